"""Reading JSON lines records: the fields of records that share them are checked together
(one type check, conversion and range check a field for a chunk); the result must be, record
for record, what reading each record alone gives, errors and their words included.

A record alone is a chunk of one line; in a chunk, one record with a fault sends every record
with the same fields through the record-by-record reading, so the comparison below covers both
ways for good records and bad ones.
"""

import json

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.cli.batch import records

ROBOT = load_robot("puma560")

GOOD_IDS = ["a", "é\u2603", "", 0, -3, 12345678901234567890, 2.5, -0.0, 1e300, True, False,
            None]
#: a record's fields, and ways a value can be refused
FORMS = [("xyz", "rpy"), ("rpy", "xyz"), ("xyz", "quat"), ("xyz", "euler_zyz", "id"),
         ("id", "xyz", "axis_angle"), ("xyz", "matrix"), ("xyz", "approach"), ("tcv",),
         ("xyz",), ("id",), ()]
FAULTS = [True, "1", None, [1], {"a": 1}, 10**400, -10**400, 2e9, -1e10, 1e999, "NaN"]


def record_text(rng, form, fault_rate):
    rec = {}
    for key in form:
        if key == "id":
            value = GOOD_IDS[int(rng.integers(len(GOOD_IDS)))]
            if rng.random() < fault_rate:
                value = [[1], {"x": 1}, 1e999][int(rng.integers(3))]
        else:
            value = rng.uniform(-500, 500, records.POSE_KEYS[key]).round(6).tolist()
            value = [int(v) if rng.random() < 0.2 else v for v in value]
            if rng.random() < fault_rate:
                kind = int(rng.integers(3))
                if kind == 0:
                    value[int(rng.integers(len(value)))] = FAULTS[int(rng.integers(len(FAULTS)))]
                elif kind == 1:
                    value = value[:-1] if rng.random() < 0.5 else value + [1.0]
                else:
                    value = 7 if rng.random() < 0.5 else {"v": value}
        rec[key] = value
    text = json.dumps(rec)
    return text.replace('"NaN"', "NaN").replace("Infinity", "1e999")


@pytest.mark.parametrize("fault_rate", [0.0, 0.002, 0.05, 0.5])
def test_fields_read_together_are_the_fields_read_alone(fault_rate):
    rng = np.random.default_rng(int(fault_rate * 1000))
    lines = [record_text(rng, FORMS[int(rng.integers(len(FORMS)))], fault_rate).encode()
             for _ in range(3000)]
    lines[5:5] = [b'{"xyz": [1, 2, 3], "rpy": [0, 0, 0], "xyz": [1, 2, 3]}', b"[1, 2]", b"{} x",
                  b'{"xyz": [1, 2, 3], "rpy": [0, 0, 0], "lock": {"q1": 5}}',
                  b'{"q": [1, 2, 3, 4, 5, 6], "id": 3}', b'{"T": [[1, 0, 0, 0]]}']
    together = records.parse_records(None, ROBOT, 10, lines)
    alone = [records.parse_records(None, ROBOT, 10 + k, [line])[0]
             for k, line in enumerate(lines)]
    assert together == alone
    assert [i for i, _, _ in together] == list(range(10, 10 + len(lines)))
    for (_, kw, err), line in zip(together, lines):
        if kw is not None:                        # floats, in the record's order
            assert list(kw) == list(json.loads(line))
            assert all(type(x) is float for k, v in kw.items() if k not in ("id", "lock")
                       for x in v)
    if fault_rate == 0:
        assert sum(err is None for _, _, err in together) > 2000
