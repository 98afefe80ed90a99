"""The CLI's contract with its users, as assertions shared by the fuzz tests.

``run_cli`` runs ``kincalc`` in-process (fast enough for thousands of cases) with
its own stdin, stdout and stderr; ``assert_contract`` checks what every run must
satisfy whatever the input (PRODUCT.md, "Exit status" and "JSON output"):

* the exit status is 0, 1 or 2 (3 is an internal error: a bug);
* stderr holds at most one line and never a traceback (unless ``--debug``);
* every JSON document on stdout parses strictly (no NaN or Infinity);
* with ``--batch``, one output record per input record, in order (``assert_batch_csv``
  checks the same of ``--format csv`` output, rows grouped by ``index``);
* (with :func:`snapshot`) nothing in the working folder is written or changed.

What an input record is (README, "Batch mode"): every line that is not blank (only
spaces, tabs, a CR), except the header line of CSV input; a line over the length limit
counts whatever it holds.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys

from kincalc.cli.main import main

#: the statuses a well-behaved run may end with
STATUSES = {0, 1, 2}


class _Stdin(io.TextIOWrapper):
    """A text stdin over bytes, with a ``buffer`` as the real one has."""


def run_cli(argv, stdin: bytes | str = b"", cwd: str | None = None):
    """``(status, stdout, stderr)`` of ``kincalc *argv`` run in this process, with
    ``stdin`` as standard input and, if given, ``cwd`` as the working folder."""
    data = stdin.encode() if isinstance(stdin, str) else stdin
    fake_in = _Stdin(io.BytesIO(data), encoding="utf-8")
    out, err = io.StringIO(), io.StringIO()
    old = os.getcwd()
    saved = sys.stdin
    try:
        if cwd is not None:
            os.chdir(cwd)
        sys.stdin = fake_in
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main([str(a) for a in argv])
    finally:
        sys.stdin = saved
        os.chdir(old)
    return status, out.getvalue(), err.getvalue()


def _strict(token):
    raise ValueError(f"non-finite number {token} in JSON output")


def json_documents(text: str) -> list:
    """Every line of ``text`` parsed as strict JSON (NaN/Infinity are errors)."""
    return [json.loads(line, parse_constant=_strict) for line in text.splitlines() if line]


def assert_contract(status, out, err, argv=(), *, records: int | None = None):
    """Assert the invariants above for one run; ``records`` is the number of batch input
    records when the run was ``--batch`` (then stdout must hold that many JSON lines)."""
    where = f"kincalc {' '.join(map(str, argv))}"[:300]
    assert status in STATUSES, f"{where}: exit {status}: {err[:500]}"
    if "--debug" not in argv:
        assert "Traceback" not in err, f"{where}: traceback on stderr: {err[:500]}"
        assert err.count("\n") <= 1 and "\n" not in err.rstrip("\n"), \
            f"{where}: more than one stderr line: {err[:500]}"
    if "--json" in argv or ("--batch" in argv and output_format(argv) != "csv"):
        docs = json_documents(out)
        # a run refused as a whole (an unknown robot, a bad option) writes nothing
        if records is not None and (status != 2 or out):
            assert len(docs) == records, f"{where}: {records} records in, {len(docs)} out"
            assert [d.get("index") for d in docs] == list(range(records)), \
                f"{where}: records out of order"


def snapshot(root) -> dict:
    """Every file under ``root`` with a hash of its content (a symbolic link: its
    target, not followed), to assert that a run wrote, changed or removed nothing:
    ``assert snapshot(folder) == before``."""
    import hashlib
    out = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in filenames + [d for d in dirnames if os.path.islink(os.path.join(dirpath, d))]:
            path = os.path.join(dirpath, name)
            if os.path.islink(path):
                out[path] = ("link", os.readlink(path))
            elif os.path.isfile(path):
                with open(path, "rb") as fh:
                    out[path] = hashlib.sha256(fh.read()).hexdigest()
            else:                                   # a FIFO, a socket: its kind only
                out[path] = ("special", os.stat(path).st_mode)
    return out


def output_format(argv) -> str:
    """The value of ``--format`` in ``argv`` (``jsonl`` when not given)."""
    argv = [str(a) for a in argv]
    for k, a in enumerate(argv):
        if a == "--format" and k + 1 < len(argv):
            return argv[k + 1]
        if a.startswith("--format="):
            return a.split("=", 1)[1]
    return "jsonl"


#: how NaN and infinities would look in a CSV cell (Python's and JSON's spellings)
NON_FINITE = {"nan", "inf", "-inf", "NaN", "Infinity", "-Infinity"}


def assert_batch_csv(status, out, argv=(), *, records: int):
    """The ``--format csv`` output of a batch run: a header row, then rows whose
    ``index`` column runs through 0 .. records-1 in order (ik writes one row per
    solution, so an index may repeat on consecutive rows), every row as wide as the
    header, and no NaN or infinite cell."""
    import csv
    where = f"kincalc {' '.join(map(str, argv))}"[:300]
    if status == 2 and not out:             # refused as a whole
        return
    rows = list(csv.reader(io.StringIO(out)))
    assert rows and rows[0][0] == "index", f"{where}: no CSV header: {out[:200]!r}"
    indexes = []
    for row in rows[1:]:
        assert len(row) == len(rows[0]), f"{where}: a row of {len(row)} cells: {row}"
        assert not NON_FINITE & set(row), f"{where}: a non-finite cell: {row}"
        if not indexes or indexes[-1] != row[0]:
            indexes.append(row[0])
    assert indexes == [str(i) for i in range(records)], \
        f"{where}: {records} records in, indexes out {indexes[:20]}..."
