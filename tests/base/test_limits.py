"""kincalc.limits: the README lists every limit, and the request limits hold in the core.

The constants are the one source of the numbers (issue 14); README's "Limits" section
is the user's copy, checked here row by row. The request limits (workspace samples
and orientations, selftest trials, seeds) are checked at the core functions, under the
CLI's own range checks (tests/cli/test_bad_input.py has the command lines), and the chunks
that keep memory bounded are checked to change no number.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from kincalc import limits
from kincalc.errors import UsageError

README = Path(__file__).parents[2] / "README.md"


def constants() -> dict:
    """Every number ``kincalc.limits`` defines (upper-case module-level int or float)."""
    return {k: v for k, v in vars(limits).items()
            if k.isupper() and isinstance(v, (int, float)) and not isinstance(v, bool)}


def limits_rows() -> dict:
    """``{NAME: value cell}`` of the table in README's "## Limits" section."""
    text = README.read_text(encoding="utf-8")
    m = re.search(r"^## Limits\n(.*?)^## ", text, re.S | re.M)
    assert m, "README has no '## Limits' section"
    rows = {}
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 2 and re.fullmatch(r"`[A-Z_][A-Z0-9_]*`", cells[0]):
            rows[cells[0].strip("`")] = cells[1]
    return rows


def test_readme_lists_every_limit_with_its_value():
    rows = limits_rows()
    for name, value in constants().items():
        assert name in rows, f"README's Limits section has no row for {name}"
        first = rows[name].split()[0].replace(",", "").replace("_", "")
        assert float(first) == value, f"README says {name} = {rows[name]}, limits.py {value}"
    stale = set(rows) - set(constants())
    assert not stale, f"README lists limits kincalc.limits does not define: {sorted(stale)}"


def test_the_limits_section_comes_just_before_exit_status():
    heads = re.findall(r"^## (.+)$", README.read_text(encoding="utf-8"), re.M)
    assert heads[heads.index("Limits") + 1] == "Exit status"


def test_cut_and_quote():
    assert limits.cut("q" * 60) == "q" * 60
    assert limits.cut("q" * 61) == "q" * 60 + "..."
    assert limits.quote("x" * 5000) == repr("x" * 60) + "... (5000 characters)"
    assert limits.quote("ab") == "'ab'"


# --- request limits in the core --------------------------------------------------------

@pytest.fixture(scope="module")
def planar():
    from kincalc.conventions.library import load
    return load("planar_3r")


@pytest.mark.parametrize("kw,words", [
    ({"samples": limits.MAX_SAMPLES + 1}, f"from 1000 to {limits.MAX_SAMPLES}"),
    ({"samples": 999}, "from 1000"),
    ({"seed": -1}, "seed must be a non-negative integer"),
    ({"seed": 1.5}, "seed must be a non-negative integer"),
    ({"orientations": limits.MAX_ORIENTATIONS + 1}, f"from 2 to {limits.MAX_ORIENTATIONS}"),
])
def test_workspace_refuses_requests_beyond_the_limits(planar, kw, words):
    from kincalc.analysis.workspace import analyse
    with pytest.raises(UsageError, match=re.escape(words)):
        analyse(planar, **{"samples": 2000, **kw})


def test_workspace_dexterity_chunks_change_no_number(planar, monkeypatch):
    from kincalc.analysis import workspace
    whole = workspace.analyse(planar, 3000, 4).to_dict()
    monkeypatch.setattr(workspace.dexterity, "PAIR_CHUNK", 900)   # 37 points a chunk: ~10, one ragged
    chunked = workspace.analyse(planar, 3000, 4).to_dict()
    for d in (whole, chunked):
        d.pop("timings", None)
    assert chunked == whole


@pytest.mark.parametrize("kw,words", [
    ({"trials": limits.MAX_TRIALS + 1}, f"from 1 to {limits.MAX_TRIALS}"),
    ({"trials": 0}, "from 1 to"),
    ({"seed": -1}, "seed must be a non-negative integer"),
])
def test_selftest_refuses_requests_beyond_the_limits(planar, kw, words):
    from kincalc.ik.selftest import run
    with pytest.raises(UsageError, match=re.escape(words)):
        run(planar, **{"trials": 10, **kw})


def test_selftest_chunks_draw_the_same_configurations(planar, monkeypatch):
    from kincalc.ik import selftest
    rng = np.random.default_rng(9)
    whole = selftest.sample_configurations(planar, 50, rng)
    monkeypatch.setattr(selftest, "CHUNK", 7)
    pairs = list(selftest._round_trip_inputs(planar, 50, np.random.default_rng(9)))
    assert len(pairs) == 50
    assert np.array_equal(np.array([q for q, _ in pairs]), whole)
    assert np.allclose(np.array([T for _, T in pairs]), planar.fk(whole))
    a = selftest.run(planar, 50, 9)
    monkeypatch.setattr(selftest, "CHUNK", 4096)
    b = selftest.run(planar, 50, 9)
    for m in (a, b):
        m.pop("time_per_pose_ms")
    assert a == b


# --- named pipes: read when a process writes, never waited for --------------------------

needs_fifo = pytest.mark.skipif(not hasattr(__import__("os"), "mkfifo"),
                                reason="no named pipes on this platform")


@needs_fifo
def test_a_named_pipe_without_a_writer_is_refused_at_once(tmp_path):
    import os
    import threading
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    done = []
    worker = threading.Thread(target=lambda: done.append(_outcome(fifo)), daemon=True)
    worker.start()
    worker.join(10)                       # open() of a FIFO used to block here for ever
    assert done and isinstance(done[0], limits.NoWriter)
    assert "named pipe that no process writes to" in limits.os_error_text(done[0])


def _outcome(path):
    try:
        return limits.read_bounded(path)
    except Exception as exc:              # the test looks at which
        return exc


@needs_fifo
def test_a_named_pipe_with_a_writer_is_read_whole(tmp_path):
    """More than a pipe's buffer (64 KiB), written slowly: every byte, once."""
    import os
    import threading
    import time
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    data = bytes(range(256)) * 1000
    fd = os.open(fifo, os.O_RDWR)          # a writer that has the pipe open already

    def write():
        for k in range(0, len(data), 50_000):
            os.write(fd, data[k:k + 50_000])
            time.sleep(0.05)
        os.close(fd)
    threading.Thread(target=write, daemon=True).start()
    got = []
    reader = threading.Thread(target=lambda: got.append(_outcome(fifo)), daemon=True)
    reader.start()
    reader.join(20)
    assert got and got[0] == data
