"""JSON lines read together (kincalc.cli.batch.uniform): the lines of a chunk's most common
shape are read by array operations on their bytes. Checked against the json module: a line
is read together exactly when json reads it as that object with every number a JSON number
that float() reads as json does and within the limit, and then every value is, bit for bit,
float() of what json.loads gives; every other line is left to the record-by-record reader,
whose answers (errors included) the chunk's must be."""

import json
import re
import struct

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.cli.batch import records, uniform
from kincalc.limits import MAX_MAGNITUDE

ROBOT = load_robot("puma560")
JSON_NUMBER = re.compile(r"-?(?:0|[1-9][0-9]*)(?:\.[0-9]+)?(?:[eE][-+]?[0-9]+)?")
#: numbers as text: good ones, and ones json refuses or reads otherwise than float()
GOOD = ["0", "1", "-1", "0.5", "-0.5", "-0.0", "0.0", "12345678901234567890", "1e5", "1E5",
        "1e-05", "1E+2", "-2.5e-3", "1e05", "0e0", "-0e0", "999999999.9999999999",
        "1000000000", "-1000000000", "4.9e-324", "1e-400", "123.456789012345678901234"]
ODD = ["-0", "01", "-01", "00", "+1", ".5", "-.5", "1.", "1.e5", "--1", "1-2", "1e", "1e+",
       "1.2.3", "1e5e5", "1e5.5", "-", "1e10", "-1000000001", "1e999", "1" + "0" * 5000, "0x10",
       "1_0", "NaN", "Infinity", "-Infinity", "true", "null", '"1"', "[1]", "#", "", "1 2",
       "1e-", "e5", "2e+-1", "0.", "00.5", "-00"]
#: line shapes: the fields and how they are written (%s a number)
SHAPES = ['{"xyz": [%s, %s, %s], "rpy": [%s, %s, %s]}', '{"rpy":[%s,%s,%s],"xyz":[%s,%s,%s]}',
          '  {"xyz": [ %s , %s , %s ], "quat": [%s, %s, %s, %s]}\r',
          '{"xyz": [%s, %s, %s], "euler_zyz": [%s, %s, %s]}',
          '{"euler_xyz": [%s, %s, %s], "xyz": [%s, %s, %s]}', '{"q": [%s, %s, %s, %s, %s, %s]}']


def bits(x):
    return struct.pack("<d", x)


def number(rng, odd_rate):
    if rng.random() < odd_rate:
        return ODD[int(rng.integers(len(ODD)))]
    if rng.random() < 0.5:
        return GOOD[int(rng.integers(len(GOOD)))]
    return repr(float(rng.uniform(-400, 400)))


def expected_values(line: bytes, keys):
    """The numbers of a line as the module must read it, or None when it must not (not an
    object of the fields ``keys`` in this order)."""
    try:
        rec = json.loads(line, parse_constant=lambda w: float("nan"))
    except ValueError:
        return None
    if type(rec) is not dict or list(rec) != keys:
        return None
    values = []
    for value in rec.values():
        for x in value:
            if type(x) not in (int, float) or not abs(float(x)) <= MAX_MAGNITUDE:
                return None
            values.append(float(x))
    tokens = re.findall(rb"[-+.0-9eE]+", re.sub(rb'"[a-z_]+"', b"", line))
    if not all(JSON_NUMBER.fullmatch(t.decode()) and t != b"-0" for t in tokens):
        return None
    return values


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("odd_rate", [0.0, 0.01, 0.2])
def test_lines_read_together_are_what_json_reads(shape, odd_rate):
    rng = np.random.default_rng(SHAPES.index(shape) * 10 + int(odd_rate * 100))
    lines = [(shape % tuple(number(rng, odd_rate) for _ in range(shape.count("%s")))).encode()
             for _ in range(1500)]
    lines[7:7] = [b"not json", b"{}", b"", None]
    lines.insert(11, (shape.replace("[", "[  ", 1) % tuple(["1"] * shape.count("%s"))).encode())
    got = uniform.read_together(lines, records_fields)
    keys = list(json.loads(shape % tuple(["1"] * shape.count("%s"))))
    want = {k: expected_values(v, keys) for k, v in enumerate(lines)
            if k != 11 and v is not None}
    want = {k: v for k, v in want.items() if v is not None}
    assert got is not None
    assert got.at.tolist() == sorted(want)
    for k, row in zip(got.at.tolist(), got.values.tolist()):
        assert list(map(bits, row)) == list(map(bits, want[k]))
    assert [key for key, _ in got.fields] == keys


def records_fields(line):
    """The fields of a line the record reader reads without error (any form)."""
    (_, kw, err), = records.parse_records(None, ROBOT, 0, [line])
    return None if err else tuple((k, len(v)) for k, v in kw.items())


@pytest.mark.parametrize("odd_rate", [0.0, 0.05, 0.5])
def test_a_chunk_read_together_is_each_line_read_by_json(odd_rate):
    """parse_records of a chunk (lines read together and the rest) against json.loads
    line by line: the same records, the same floats bit for bit, errors for the others."""
    rng = np.random.default_rng(int(odd_rate * 100) + 1)
    shape = SHAPES[0]
    lines = [(shape % tuple(number(rng, odd_rate) for _ in range(6))).encode()
             for _ in range(2000)]
    got = records.parse_records(None, ROBOT, 100, lines)
    assert [i for i, _, _ in got] == list(range(100, 2100))
    for (i, kw, err), line in zip(got, lines):
        want = expected_values(line, ["xyz", "rpy"])
        if kw is None:
            assert want is None and err.startswith(f"record {i + 1}: ")
            continue
        assert list(kw) == ["xyz", "rpy"]
        assert list(map(bits, kw["xyz"] + kw["rpy"])) == \
            list(map(bits, [float(x) for v in json.loads(line).values() for x in v]))


def test_nothing_is_read_together_without_a_good_line_of_the_common_shape():
    assert uniform.read_together([None, None], records_fields) is None
    assert uniform.read_together([b'{"xyz": [1, 2, 3]}'] * 3, records_fields) is not None
    assert uniform.read_together([b'{"xyz": [1, 2, 3], "id": 1}'] * 3,
                                 lambda line: None) is None
    assert uniform.read_together([b'{"x#": [1, 2, 3]}'] * 3, records_fields) is None
    assert uniform.read_together([b'{"\\u0078yz": [1, 2, 3]}'] * 3, records_fields) is None
