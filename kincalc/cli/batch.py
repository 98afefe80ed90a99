"""``--batch FILE|-``: many inputs, one output record per input, in order.

Input is JSON lines (one object per line) or CSV with a header row; the
first non-blank line decides (``{`` starts JSON lines). A record holds a
pose in any of the forms of PRODUCT.md:

* JSON: ``{"xyz": [x, y, z], "rpy": [r, p, y]}``, with ``euler_zyz``,
  ``euler_xyz``, ``quat``, ``axis_angle``, ``matrix``, ``approach`` or ``tcv``
  instead of ``rpy``; or ``{"T": [[...], ...]}`` (4x4); or ``{"q": [...]}``
  (the pose FK gives for these joints);
* CSV: columns ``x, y, z`` with ``roll, pitch, yaw`` or ``qw, qx, qy, qz`` or
  ``ax, ay, az`` (approach), or one column per joint named as in the robot file
  (plain comma-separated numbers, no quoting).

An ``id`` field of a JSON record is echoed in its output record. Records are
counted from 1 in messages ("record 3") and indexed from 0 in ``index``.

Values are in the command's units (``--deg/--rad``, ``--unit``). A record
that cannot be read becomes ``{"index": i, "error": "..."}`` and the run goes
on; the exit status then says so (2).
"""

from __future__ import annotations

import sys
from typing import Iterator

#: pose keys of a JSON record and the number of values each takes
POSE_KEYS = {"xyz": 3, "rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
             "matrix": 9, "approach": 3, "tcv": 6}
#: CSV column groups and the pose key they fill
CSV_GROUPS = {("x", "y", "z"): "xyz", ("roll", "pitch", "yaw"): "rpy",
              ("qw", "qx", "qy", "qz"): "quat", ("ax", "ay", "az"): "approach"}


class RecordError(ValueError):
    """A batch record that cannot be used; the message names what is wrong."""


def _lines(src: str):
    if src == "-":
        yield from sys.stdin
        return
    from ..errors import InputError
    try:
        fh = open(src, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"--batch {src}: cannot read ({exc.strerror})") from None
    with fh:
        yield from fh


def records(src: str, robot) -> Iterator[tuple[int, dict | None, str | None]]:
    """``(index, pose keywords for build_target, None)`` or ``(index, None, error)`` for
    each input record of ``src`` (a path or ``-``), streaming."""
    import json

    lines = (line for line in _lines(src) if line.strip())
    first = next(lines, None)
    if first is None:
        return
    if first.lstrip().startswith("{"):
        yield _json_record(0, first, json)
        for i, line in enumerate(lines, start=1):
            yield _json_record(i, line, json)
        return
    header = [h.strip() for h in first.strip().split(",")]
    for i, line in enumerate(lines):
        try:
            yield i, _csv_record(header, line, robot), None
        except RecordError as exc:
            yield i, None, f"record {i + 1}: {exc}"


def _json_record(i, line, json):
    try:
        rec = json.loads(line)
    except ValueError as exc:
        return i, None, f"record {i + 1}: not JSON ({exc.msg})"
    if not isinstance(rec, dict):
        return i, None, f"record {i + 1}: expected a JSON object"
    try:
        return i, _pose_keywords(rec, i + 1), None
    except RecordError as exc:
        return i, None, str(exc)


def _numbers(value, count, where) -> tuple:
    import math
    if not isinstance(value, (list, tuple)) or (count and len(value) != count):
        raise RecordError(f"{where}: expected {count} numbers")
    try:
        out = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        raise RecordError(f"{where}: expected numbers") from None
    if not all(math.isfinite(x) for x in out):
        raise RecordError(f"{where}: values must be finite")
    return out


def _pose_keywords(rec: dict, line: int) -> dict:
    known = set(POSE_KEYS) | {"T", "q", "id"}
    unknown = [k for k in rec if k not in known]
    if unknown:
        raise RecordError(f"record {line}: unknown field {unknown[0]!r} (pose fields: "
                          f"{', '.join(list(POSE_KEYS) + ['T', 'q'])})")
    out = {}
    for key, count in POSE_KEYS.items():
        if key in rec:
            out[key] = _numbers(rec[key], count, f"record {line}: {key}")
    if "T" in rec:
        flat = rec["T"]
        if isinstance(flat, list) and flat and isinstance(flat[0], list):
            flat = [x for row in flat for x in (row if isinstance(row, list) else [row])]
        out["T"] = _numbers(flat, 0, f"record {line}: T")
    if "q" in rec:
        out["q"] = _numbers(rec["q"], 0, f"record {line}: q")
    if not out:
        raise RecordError(f"record {line}: no pose (give xyz and an orientation, T or q)")
    if "id" in rec:
        out["id"] = rec["id"]
    return out


def _csv_record(header, line, robot) -> dict:
    cells = [c.strip() for c in line.strip().split(",")]
    if len(cells) != len(header):
        raise RecordError(f"{len(cells)} values for {len(header)} columns")
    try:
        row = {h: float(c) for h, c in zip(header, cells)}
    except ValueError:
        bad = next(c for c in cells if not _is_float(c))
        raise RecordError(f"{bad!r} is not a number") from None
    out = {}
    used = set()
    for cols, key in CSV_GROUPS.items():
        if all(c in row for c in cols):
            out[key] = tuple(row[c] for c in cols)
            used |= set(cols)
    names = [j.name for j in robot.joints]
    if all(n in row for n in names):
        out["q"] = tuple(row[n] for n in names)
        used |= set(names)
    extra = [h for h in header if h not in used]
    if extra:
        raise RecordError(f"unknown column {extra[0]!r} (columns: x,y,z with roll,pitch,yaw or "
                          f"qw,qx,qy,qz or ax,ay,az; or the joints {','.join(names)})")
    return out


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


class Writer:
    """Output records, one per input, as JSON lines or CSV (with a header), flushed
    as they come so that a pipeline sees results before the input ends."""

    def __init__(self, fmt: str, columns: list[str]):
        import csv
        import json
        self.fmt, self.columns, self._json = fmt, columns, json
        self._csv = csv.writer(sys.stdout, lineterminator="\n") if fmt == "csv" else None
        if self._csv is not None:
            self._csv.writerow(columns)

    def write(self, record: dict) -> None:
        if self._csv is not None:
            self._csv.writerow([_csv_cell(record.get(c)) for c in self.columns])
        else:
            sys.stdout.write(self._json.dumps(record, allow_nan=False) + "\n")
        sys.stdout.flush()


def _csv_cell(value):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return value
