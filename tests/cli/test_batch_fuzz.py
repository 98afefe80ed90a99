"""Fuzz tests of ``--batch`` streams (issue 14): good and bad records mixed with every
encoding fault, for fk, jacobian, ik and reach, JSON lines and CSV in, ``--format
jsonl`` and ``csv`` out; in this process with ``-j 1``, and a few with ``-j 2`` through a
real subprocess reading a pipe.

Every run must keep the CLI's contract (tests/cli_contract.py): exit status 0, 1 or 2;
at most one stderr line and no traceback; every JSON line strict (no NaN, no Infinity);
no warning; and one output record per input record, in order. The number of input
records is computed here from the bytes by the README's rule ("Batch mode"), not by
kincalc's reader: the input is cut at each newline, a UTF-8 byte order mark at its start
is dropped, a line holding only spaces, tabs and CRs is blank and skipped unless it is
longer than the 64 KiB line limit, and every other line is a record, except the first
one of CSV input (its header). Whether an input is CSV is decided by the same rule
(``--input-format``, the file name, or a first line of column names).

Seeded: ``derandomize=True`` draws the same cases on every run; about 60 s in all.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import warnings
from unittest import mock

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cli_contract import (assert_batch_csv, assert_contract, json_documents,
                          output_format, run_cli)
from kincalc.cli.batch import runner
from kincalc.limits import MAX_RECORD_BYTES

SEEDED = dict(derandomize=True, database=None, deadline=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                     HealthCheck.large_base_example])
ROBOT = "puma560"
JOINTS = ["q1", "q2", "q3", "q4", "q5", "q6"]
BOM = b"\xef\xbb\xbf"

# --- the README's rule, written out independently of kincalc's reader ---------------------

_HEADER = re.compile(r"[A-Za-z_][\w.\-]*(?:[ \t]*,[ \t]*[A-Za-z_][\w.\-]*)*", re.ASCII)
_WHITE = b" \t\r\x0b\x0c"


def lines_of(data: bytes) -> list[bytes]:
    """The non-blank lines of a batch input (over-long ones count whatever they hold)."""
    if data.startswith(BOM):
        data = data[len(BOM):]
    lines = data.split(b"\n")
    if lines[-1] == b"":
        lines.pop()
    return [ln for ln in lines if over_long(ln) or ln.strip(_WHITE)]


def over_long(line: bytes) -> bool:
    """Longer than the limit, the CR of a CRLF end not counted."""
    return len(line) - line.endswith(b"\r") > MAX_RECORD_BYTES


def is_csv(data: bytes, input_format: str, name: str = "-") -> bool:
    if input_format != "auto":
        return input_format == "csv"
    if name.endswith(".csv") or name.endswith((".jsonl", ".ndjson")):
        return name.endswith(".csv")
    lines = lines_of(data)
    if not lines or over_long(lines[0]) or b"\0" in lines[0]:
        return False
    try:
        text = lines[0].strip(_WHITE).decode("utf-8")
    except UnicodeDecodeError:
        return False
    return text not in {"null", "true", "false", "NaN", "Infinity"} and \
        bool(_HEADER.fullmatch(text))


def input_records(data: bytes, input_format: str, name: str = "-") -> int:
    n = len(lines_of(data))
    return n - 1 if n and is_csv(data, input_format, name) else n


# --- records, good and bad --------------------------------------------------------------

GOOD = st.one_of(st.floats(-180, 180, allow_nan=False).map(repr),
                 st.integers(-360, 360).map(str),
                 st.sampled_from(["0", "-0.0", "1e-300", "5e-324", "90", "1e9", "-1e9",
                                  "999999999.9"]))
#: JSON values that must each make their record an error where a number is expected
WILD = st.sampled_from(["NaN", "Infinity", "-Infinity", "1e200", "1.0000001e9", "-1e10",
                        "1e400", "true", "false", "null", '"1"', "[]", "{}", '{"a": 1}',
                        "1" * 400, "1" + "0" * 5000])
VALUE = st.one_of(GOOD, GOOD, GOOD, GOOD, WILD)


def numbers(n):
    return st.lists(VALUE, min_size=n, max_size=n).map(lambda v: "[" + ", ".join(v) + "]")


COUNTS = st.sampled_from([6, 6, 6, 6, 5, 7, 0])
IDS = st.sampled_from(['"a"', "3", "null", "true", "1.5", '"\\u00e9t\\u00e9"', "[1]",
                       '{"x": 1}', "NaN", "1e999", '"' + "x" * 300 + '"'])
POSE_KEYS = {"rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
             "matrix": 9, "approach": 3, "tcv": 6}


@st.composite
def json_record(draw) -> str:
    kind = draw(st.sampled_from(["q", "q", "q", "pose", "pose", "pose", "T", "scalar",
                                 "broken", "twice", "unknown", "deep", "empty"]))
    if kind == "q":
        fields = [f'"q": {draw(COUNTS.flatmap(numbers))}']
    elif kind == "pose":
        fields = [f'"xyz": {draw(numbers(draw(st.sampled_from([3, 3, 3, 2]))))}']
        key = draw(st.sampled_from([None] + list(POSE_KEYS)))
        if key:
            fields.append(f'"{key}": {draw(numbers(POSE_KEYS[key]))}')
    elif kind == "T":
        rows = draw(st.sampled_from([
            "[[1, 0, 0, 0.4], [0, 1, 0, 0.1], [0, 0, 1, 0.3], [0, 0, 0, 1]]",
            "[[0, -1, 0, 0.2], [1, 0, 0, 0.1], [0, 0, 1, 0.5], [0, 0, 0, 1]]",
            "[[1, 0, 0], [0, 1, 0]]", '"nope"', "[[1, [2]], 3]"]))
        fields = [f'"T": {rows}']
    elif kind == "scalar":
        return draw(st.sampled_from(["42", "[]", '"text"', "null", "true", "[1, 2]", "-1",
                                     "NaN"]))
    elif kind == "broken":
        return draw(st.sampled_from(['{"q": [1, 2', "{q: 1}", "not json", "{'q': [1]}",
                                     '{"q": [1,,2]}', "}", '{"q": [0, 0, 0, 0, 0, 0]} x']))
    elif kind == "twice":
        fields = [f'"q": {draw(numbers(6))}', f'"q": {draw(numbers(6))}']
    elif kind == "unknown":
        fields = ['"qq": [1]']
    elif kind == "deep":
        depth = draw(st.sampled_from([50, 5000, 30000]))
        return '{"q": ' + "[" * depth + "]" * depth + "}"
    else:
        fields = []
    if draw(st.booleans()):
        fields.append(f'"id": {draw(IDS)}')
    order = draw(st.permutations(fields))
    return "{" + ", ".join(order) + "}"


CSV_WILD = st.sampled_from(["nan", "NaN", "inf", "-inf", "Infinity", "1e200", "1e999",
                            "1.0000001e9", "true", "false", "True", "", " ", "1_0", "\u0661",
                            '"1"', "0x10", "1e", "--1", "1,5", "1 2", "+.5", "5.", "1E+3"])
CSV_CELL = st.one_of(GOOD, GOOD, GOOD, GOOD, GOOD, CSV_WILD)
CSV_HEADERS = {"joints": JOINTS, "rpy": ["x", "y", "z", "roll", "pitch", "yaw"],
               "quat": ["x", "y", "z", "qw", "qx", "qy", "qz"], "xyz": ["x", "y", "z"],
               "approach": ["x", "y", "z", "ax", "ay", "az"],
               "twice": ["x", "y", "z", "x"], "unknown": ["x", "y", "z", "w"]}


@st.composite
def csv_row(draw, width: int) -> str:
    n = draw(st.sampled_from([width] * 8 + [width - 1, width + 1, 1]))
    return ",".join(draw(st.lists(CSV_CELL, min_size=n, max_size=n)))


def fault(line: bytes, draw) -> bytes:
    """One encoding fault, or none, applied to a line of a record."""
    kind = draw(st.sampled_from(["none"] * 10 + ["utf8", "nul", "bom", "long", "long-blank",
                                                 "spaces", "latin1"]))
    at = draw(st.integers(0, len(line)))
    if kind == "utf8":
        bad = draw(st.sampled_from([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\xc0\xaf", b"\x80"]))
        return line[:at] + bad + line[at:]
    if kind == "nul":
        return line[:at] + b"\0" + line[at:]
    if kind == "bom":
        return BOM + line
    if kind == "long":
        return line + b" " * (MAX_RECORD_BYTES + draw(st.integers(-2, 3000)))
    if kind == "long-blank":
        return b" " * (MAX_RECORD_BYTES + draw(st.sampled_from([-1, 0, 1, 70000])))
    if kind == "spaces":
        return b" \t" + line + b"\t "
    if kind == "latin1":
        return line + "\u00e9".encode("latin-1")
    return line


@st.composite
def batch_input(draw, csv_in: bool, header_kind=None):
    """``(data, header)``: the bytes of a batch input, with its CSV header or None."""
    lines = []
    header = None
    if csv_in:
        header = CSV_HEADERS[header_kind or draw(st.sampled_from(
            ["joints", "joints", "rpy", "rpy", "quat", "xyz", "approach", "twice", "unknown"]))]
        lines.append(",".join(header).encode())
    for _ in range(draw(st.sampled_from([0, 1, 2, 3, 5, 8, 12, 20]))):
        if draw(st.integers(0, 5)) == 0:          # blank lines are not records
            lines.append(draw(st.sampled_from([b"", b" ", b"\t", b"\r", b" \t\r"])))
            continue
        text = draw(csv_row(len(header))) if csv_in else draw(json_record())
        lines.append(fault(text.encode("utf-8"), draw))
    if draw(st.integers(0, 3)) == 0:               # a header-less stream of the other kind
        lines.append(b"42")
    eol = draw(st.sampled_from([b"\n", b"\n", b"\r\n"]))
    data = eol.join(lines)
    if lines and draw(st.booleans()):
        data += eol
    if draw(st.integers(0, 4)) == 0:
        data = BOM + data
    return data, header


#: (records a chunk, bytes a read): small ones cut records across chunks and lines (and
#: byte order marks, and over-long lines) across reads
SIZES = st.sampled_from([(2048, 1 << 16), (1, 1 << 16), (3, 17), (2, 4096), (5, 3)])


def check_run(argv, data, *, name="-", input_format="auto", sizes=(2048, 1 << 16)):
    argv = [str(a) for a in argv]
    chunk, read = sizes
    with warnings.catch_warnings(record=True) as caught, \
            mock.patch.object(runner, "CHUNK_LINES", chunk), \
            mock.patch.object(runner, "REACH_CHUNK_LINES", chunk), \
            mock.patch.object(runner, "READ_BYTES", read):
        warnings.simplefilter("always")
        status, out, err = run_cli(argv, stdin=data)
    records = input_records(data, input_format, name)
    assert_contract(status, out, err, argv, records=records)
    if not records and err:         # a CSV header that cannot be used, and no record: said once
        assert status == 2 and err.count("\n") == 1 and ": line 1: " in err, err[:300]
    else:
        assert err == "", f"a batch run refused or ended early: {err[:300]}"
    if output_format(argv) == "csv":
        assert_batch_csv(status, out, argv, records=records)
    assert not caught, f"warnings: {[str(w.message) for w in caught][:3]}"
    assert status in (0, 1, 2)
    return status, out, err


COMMANDS = st.sampled_from(["fk", "jacobian", "ik", "reach"])


@settings(max_examples=700, **SEEDED)
@given(command=COMMANDS, out_fmt=st.sampled_from(["jsonl", "csv"]),
       explicit=st.booleans(), sizes=SIZES, data=st.data())
def test_json_lines_streams_keep_the_contract(command, out_fmt, explicit, sizes, data):
    data_in, _ = data.draw(batch_input(False))
    if command == "reach":                         # slow per pose: fewer records
        data_in = b"\n".join(data_in.split(b"\n")[:6])
    input_format = "jsonl" if explicit else "auto"
    check_run([command, ROBOT, "--batch", "-", "--format", out_fmt] +
              (["--input-format", input_format] if explicit else []), data_in,
              input_format=input_format, sizes=sizes)


@settings(max_examples=550, **SEEDED)
@given(command=COMMANDS, out_fmt=st.sampled_from(["jsonl", "csv"]),
       explicit=st.booleans(), sizes=SIZES, data=st.data())
def test_csv_streams_keep_the_contract(command, out_fmt, explicit, sizes, data):
    header_kind = "joints" if command in ("fk", "jacobian") and data.draw(st.booleans()) \
        else None
    data_in, _ = data.draw(batch_input(True, header_kind))
    if command == "reach" and data_in.count(b"\n") > 6:
        data_in = b"\n".join(data_in.split(b"\n")[:6])
    input_format = "csv" if explicit else "auto"
    check_run([command, ROBOT, "--batch", "-", "--format", out_fmt] +
              (["--input-format", input_format] if explicit else []), data_in,
              input_format=input_format, sizes=sizes)


@settings(max_examples=80, **SEEDED)
@given(command=st.sampled_from(["fk", "ik"]), csv_in=st.booleans(),
       suffix=st.sampled_from([".jsonl", ".csv", ".ndjson", ".txt"]), data=st.data())
def test_files_by_name_keep_the_contract(tmp_path_factory, command, csv_in, suffix, data):
    """The same from a file, whose name's ending decides the format."""
    data_in, _ = data.draw(batch_input(csv_in))
    path = tmp_path_factory.mktemp("batch") / f"in{suffix}"
    path.write_bytes(data_in)
    check_run([command, ROBOT, "--batch", path, "--format", "jsonl"], data_in,
              name=str(path))


# --- -j 2 through a real process and a pipe ----------------------------------------------

@settings(max_examples=8, **SEEDED)
@given(command=COMMANDS, csv_in=st.booleans(), data=st.data())
def test_jobs_through_a_pipe_keep_the_contract(command, csv_in, data):
    """A real ``kincalc ... --batch - -j 2`` reading a pipe: same contract, and the same
    output as in this process with -j 1."""
    data_in = b"".join(data.draw(batch_input(csv_in))[0] + b"\n" for _ in range(3))
    argv = [command, ROBOT, "--batch", "-", "-j", "2"]
    p = subprocess.run([sys.executable, "-c", "import sys; from kincalc.cli.main import main; "
                        "sys.exit(main())", *argv], input=data_in, capture_output=True,
                       timeout=120, env={**os.environ, "OMP_NUM_THREADS": "1"})
    out, err = p.stdout.decode(), p.stderr.decode()
    records = input_records(data_in, "auto")
    assert_contract(p.returncode, out, err, argv, records=records)
    assert json_documents(out) == json_documents(run_cli(argv[:-2], stdin=data_in)[1])


def test_the_oracle_counts_as_the_readme_says():
    """The rule above, on hand-made inputs (so that the fuzz tests' count can fail)."""
    assert input_records(b"", "auto") == 0
    assert input_records(b'{"q": []}', "auto") == 1
    assert input_records(b'\n\n  \t\r\n{"q": []}\r\n\n', "auto") == 1
    assert input_records(b"q1,q2\n1,2\n\n3,4", "auto") == 2
    assert input_records(BOM + b"x,y,z\n1,2,3\n", "auto") == 1
    assert input_records(b"null\n{}\n", "auto") == 2
    assert input_records(b" " * (MAX_RECORD_BYTES + 1) + b"\n{}", "auto") == 2
    assert input_records(b" " * MAX_RECORD_BYTES + b"\n{}", "auto") == 1
    assert input_records(b"x,y\n1,2\n", "jsonl") == 2
    assert input_records(b"x,y\n1,2\n", "auto", "in.jsonl") == 2


@pytest.mark.parametrize("out_fmt", ["jsonl", "csv"])
def test_every_fault_in_one_stream(out_fmt):
    """One hand-written stream with each fault of the issue, for each command."""
    good = b'{"q": [10, 20, 30, 40, 50, 60], "id": "g"}'
    data = b"\n".join([
        BOM + good, b"42", b"[]", b'"text"', b"null", good + b"\r", b"", b"   ",
        b'{"q": [1, 2, 3, 4, 5, \xff]}', b'{"q": [0, 0, 0, 0, 0, 0]}\0', b"\t" + good,
        b'{"q": [1, 2, 3, 4, 5, 6], "q": [1, 2, 3, 4, 5, 6]}', b'{"q": [NaN, 0, 0, 0, 0, 0]}',
        b'{"q": [1e200, 0, 0, 0, 0, 0]}', b'{"q": [true, 0, 0, 0, 0, 0]}',
        b'{"xyz": [1e200, 0, 0]}', b'{"xyz": [0.4, 0.1, 0.3], "rpy": [0, 90, Infinity]}',
        b"{" + b" " * MAX_RECORD_BYTES + b"}", b" " * (MAX_RECORD_BYTES + 1), good])
    for command in ("fk", "jacobian", "ik", "reach"):
        argv = [command, ROBOT, "--batch", "-", "--format", out_fmt]
        status, out, err = check_run(argv, data)
        assert status == 2 and err == ""
        if out_fmt == "jsonl":
            docs = json_documents(out)
            assert len(docs) == 18
            assert [d["index"] for d in docs if "error" not in d] == [0, 5, 8, 17]
