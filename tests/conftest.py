"""Shared by every test: the helper modules beside this file (``randrobots``,
``subproblem_checks``, ``yaml_fuzz``, ``cli_contract``) are importable by name, since pytest
puts this conftest's folder on the import path; and hypothesis draws the same examples on
every run; and a test of Ctrl-C gets the handler of a program at a terminal
(``python_ctrl_c``)."""

import pytest
from hypothesis import settings

# Every hypothesis test draws the same examples on every run and machine (issue 14: a
# seeded test must draw the same cases every time); no example database on disk.
settings.register_profile("kincalc", derandomize=True, database=None, deadline=None)
settings.load_profile("kincalc")


@pytest.fixture
def python_ctrl_c():
    """Ctrl-C handled as Python starts a program: ``default_int_handler`` for the test, the
    handler it found after. A shell starts a background job (``pytest &``) with Ctrl-C
    ignored, which Python then keeps: the tests of what kincalc does with a Ctrl-C need the
    handler a program at a terminal has."""
    import signal
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
