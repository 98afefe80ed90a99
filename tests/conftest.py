"""Shared by every test: the helper modules beside this file (``randrobots``,
``subproblem_checks``, ``yaml_fuzz``, ``cli_contract``) are importable by name, since pytest
puts this conftest's folder on the import path; and hypothesis draws the same examples on
every run."""

from hypothesis import settings

# Every hypothesis test draws the same examples on every run and machine (issue 14: a
# seeded test must draw the same cases every time); no example database on disk.
settings.register_profile("kincalc", derandomize=True, database=None, deadline=None)
settings.load_profile("kincalc")
