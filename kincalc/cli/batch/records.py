"""Batch records: one line of bytes to pose keywords, or the reason it cannot be used
(JSON lines and CSV; see :mod:`kincalc.cli.batch` for what a record is)."""

from __future__ import annotations

import heapq
import itertools
import math

from ...limits import quote
from .csv_input import csv_records
from .values import NUMBER_TYPES, RecordError, json_kind, line_text, numbers, within_range

#: pose keys of a JSON record and the number of values each takes
POSE_KEYS = {"xyz": 3, "rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
             "matrix": 9, "approach": 3, "tcv": 6}
#: the input formats of --input-format
INPUT_FORMATS = ("auto", "jsonl", "csv")
#: file name endings that decide the input format when --input-format is auto
FORMAT_OF_SUFFIX = {".jsonl": "jsonl", ".ndjson": "jsonl", ".csv": "csv"}
BOM = b"\xef\xbb\xbf"
#: the bytes of a blank line, which is skipped (any other line is a record)
BLANK = b" \t\r"


# --- records: one line of bytes -> pose keywords, or the reason it cannot be used ---------

def parse_records(header, robot, start: int, lines, kind: str = "ik",
                  guessed: bool = False) -> list:
    """``[(index, keywords or None, error or None)]`` of one chunk of lines (bytes, or
    None for a line over the length limit), the first being record ``start``. ``header``
    is None for JSON lines, the column names for CSV, or the reason the CSV header cannot
    be used. ``kind`` is the command ('ik', 'reach', 'fk' or 'jacobian'), whose fields an
    unknown field's message lists. ``guessed``: JSON lines because the first line is no
    CSV header (not by the input's name or --input-format): a first record that looks like
    one says what a header is."""
    parsed, together = parse_chunk(header, robot, start, lines, kind, guessed)
    if together is None:
        return parsed
    keys = [key for key, _ in together.fields]
    ends = list(itertools.accumulate(count for _, count in together.fields))
    spans = list(zip(keys, [0] + ends[:-1], ends))
    read = [(start + k, {key: tuple(row[a:b]) for key, a, b in spans}, None)
            for k, row in zip(together.at.tolist(), together.values.tolist())]
    return list(heapq.merge(parsed, read, key=lambda r: r[0]))


def parse_chunk(header, robot, start: int, lines, kind: str = "ik",
                guessed: bool = False) -> tuple:
    """:func:`parse_records` with the JSON lines read together
    (:mod:`~kincalc.cli.batch.uniform`) kept as arrays: ``(parsed, together)``, the
    records of the other lines and a :class:`~kincalc.cli.batch.uniform.Together` (its
    ``at`` the positions of its lines in ``lines``) or None."""
    if header is not None:
        return csv_records(header, robot, start, lines, kind), None
    from .uniform import read_together
    together = read_together(lines, lambda line: _together_fields(line, robot))
    if together is None:
        return _json_records(range(start, start + len(lines)), lines, kind, guessed), None
    if len(together.at) == len(lines):
        return [], together
    taken = set(together.at.tolist())
    rest = [k for k in range(len(lines)) if k not in taken]
    return _json_records([start + k for k in rest], [lines[k] for k in rest], kind,
                         guessed), together


#: the pose forms whose records may be read together: those ik solves in one vectorised
#: step (kincalc.cli.batch.chunks.FAST_FORMS) but T (its rows may be nested)
TOGETHER_FORMS = {frozenset({"xyz", "rpy"}), frozenset({"xyz", "euler_zyz"}),
                  frozenset({"xyz", "euler_xyz"}), frozenset({"xyz", "quat"}),
                  frozenset({"q"})}


def _together_fields(line, robot):
    """The fields ``((key, count), ...)`` of a line to read together with the lines of its
    shape (:func:`~kincalc.cli.batch.uniform.read_together`): a good record of a form of
    TOGETHER_FORMS (``q`` of one value a joint), else None."""
    try:
        kw = _pose_keywords(_json_object(line_text(line)))
    except RecordError:
        return None
    if frozenset(kw) not in TOGETHER_FORMS or ("q" in kw and len(kw["q"]) != robot.dof):
        return None
    return tuple((key, len(value)) for key, value in kw.items())


def _json_records(indices, lines, kind: str = "ik", guessed: bool = False) -> list:
    """:func:`parse_records` of JSON lines, record ``indices[k]`` being ``lines[k]``. The
    objects are read one by one; their fields are checked together for the records that
    have the same fields, when those are pose fields of a fixed count and ``id``
    (:func:`_fields_together`), else record by record (:func:`_pose_keywords`, which also
    says what is wrong)."""
    out, same = [], {}
    for i, line in zip(indices, lines):
        try:
            rec = _json_object(line_text(line))
        except RecordError as exc:
            hint = _header_hint(i, line) if guessed else ""
            out.append((i, None, f"record {i + 1}: {exc}{hint}"))
            continue
        same.setdefault(tuple(rec), []).append((len(out), i, rec))
        out.append(None)
    for keys, items in same.items():
        together = _fields_together(keys, [rec for _, _, rec in items])
        for k, (at, i, rec) in enumerate(items):
            if together is not None:
                out[at] = (i, together[k], None)
                continue
            try:
                out[at] = (i, _pose_keywords(rec, kind), None)
            except RecordError as exc:
                out[at] = (i, None, f"record {i + 1}: {exc}")
    return out


def _header_hint(i: int, line) -> str:
    """What to add to the error of record ``i``: for a first line that looks like a CSV header
    the auto-detection did not take (a name first, then separators), what a header is."""
    if i or not line or not line[:1].isalpha() or not any(c in line for c in b",;\t"):
        return ""
    return ("; as a CSV header it cannot be used: column names separated by commas, none "
            "empty")


def _json_object(text: str) -> dict:
    """The JSON object of one JSON lines record (a field given twice is an error)."""
    global _DECODER
    if _DECODER is None:
        import json
        _DECODER = (json.JSONDecoder(parse_constant=_not_finite),
                    json.JSONDecoder(parse_constant=_not_finite, object_pairs_hook=_unique_fields))
    if text.startswith("\ufeff"):
        raise RecordError("starts with a byte order mark (only the input's first line may)")
    try:
        # (the text has no white space around it: what follows the value is "Extra data")
        rec, end = _DECODER[0].raw_decode(text)
        if end != len(text):
            raise RecordError("not JSON (Extra data)")
        # a field given twice: the decoder keeps the last; every key is followed by a
        # colon, so a record with no more colons than keys has none twice
        if type(rec) is dict and text.count(":") > len(rec):
            _DECODER[1].decode(text)
    except RecursionError:
        raise RecordError("not JSON (nested too deeply)") from None
    except RecordError:
        raise
    except ValueError as exc:
        # a JSONDecodeError has .msg; int() refusing a number of thousands of digits not
        raise RecordError(f"not JSON ({getattr(exc, 'msg', 'a number too long to read')})") \
            from None
    if type(rec) is not dict:
        raise RecordError(f"expected a JSON object ({{...}}), not {json_kind(rec)}")
    return rec


_DECODER = None


def _not_finite(word):
    """The JSON decoders' hook for NaN, Infinity and -Infinity (not JSON, but Python's
    json module reads them)."""
    raise RecordError(f"{word} is not a finite number (JSON has no NaN or Infinity)")


def _unique_fields(pairs) -> dict:
    out = dict(pairs)
    if len(out) != len(pairs):
        seen = set()
        twice = next(k for k, _ in pairs if k in seen or seen.add(k))
        raise RecordError(f"field {quote(twice)} is given twice")
    return out


def _matrix_numbers(value, key: str) -> tuple:
    """:func:`~kincalc.cli.batch.values.numbers` of a matrix field (``T``, ``matrix``): 16 or 12 / 9 numbers, or
    their rows."""
    if type(value) is list and value and type(value[0]) is list:
        value = [x for row in value for x in (row if type(row) is list else [row])]
    return numbers(value, _FIELDS[key], key)


#: the fields of a JSON record, with the count of numbers of each (0: any)
_FIELDS = {**POSE_KEYS, "T": 0, "q": 0}
_KNOWN = frozenset(_FIELDS) | {"id", "lock"}
#: the fields of each command's records, as an unknown field's message lists them
TAKEN = {"ik": f"pose fields: {', '.join(_FIELDS)}; also id, lock",
         "reach": f"pose fields: {', '.join(_FIELDS)}; also id",
         "fk": "q, the joint values; also id", "jacobian": "q, the joint values; also id"}


def _pose_keywords(rec: dict, kind: str = "ik") -> dict:
    """The keywords of the JSON record ``rec`` (field -> value; numbers as tuples of
    floats), or :class:`RecordError` saying what is wrong (an unknown field named with the
    fields of ``kind``'s records)."""
    length = None                       # an fk --batch record's length unit, if it says
    if kind in ("ik", "reach") and _fk_record(rec):
        rec = _fk_pose(rec)
        length = rec.pop(FK_LENGTH, None)
    if not _KNOWN.issuperset(rec):
        unknown = next(k for k in rec if k not in _KNOWN)
        raise RecordError(f"unknown field {quote(unknown)} ({TAKEN[kind]})")
    out = {}
    for key, value in rec.items():
        if key == "id":
            if isinstance(value, (list, dict)) or (type(value) is float and
                                                    not math.isfinite(value)):
                raise RecordError("id must be a string, a finite number, true, false or null")
        elif key == "lock":
            value = _lock(value)
        elif key in ("T", "matrix"):
            value = _matrix_numbers(value, key)
        else:
            value = numbers(value, _FIELDS[key], key)
        out[key] = value
    if len(out) == ("id" in out) + ("lock" in out):
        raise RecordError("no joints (give q)" if kind in ("fk", "jacobian") else
                          "no pose (give xyz and an orientation, T or q)")
    if length is not None:
        out[FK_LENGTH] = length
    return out


#: the fields of an answer of fk --batch after its head (``index``, ``id``), in the order
#: written (kincalc.cli.batch.chunks), and of its error record; ``units`` (the lengths' and
#: angles' unit) may be missing from a record written before it was
FK_FIELDS = ("T", "xyz", "rpy", "within_limits", "units")
FK_ERROR = ("error",)
#: the keyword of an fk --batch record's length unit, for its T (kincalc.cli.batch.poses)
FK_LENGTH = "T's length unit"


def _fk_record(rec: dict) -> bool:
    """Whether the JSON record ``rec`` is an output record of ``fk --batch`` (an ``index``,
    and then a ``T`` or an ``error``)."""
    return "index" in rec and ("T" in rec or "error" in rec)


def _fk_pose(rec: dict) -> dict:
    """An ``fk --batch`` output record read as a pose: ``{"T": ..., "id": ...}``, once its
    fields are checked to be the answer's own (``index`` a whole number, ``xyz`` T's
    position, ``rpy`` three numbers, ``within_limits`` true or false); ``rpy``,
    ``within_limits`` and ``index`` are not read further (the answers are numbered afresh).
    Its error record, and any other field, are errors."""
    fields = FK_ERROR if "error" in rec else FK_FIELDS
    other = next((k for k in rec if k not in ("index", "id") + fields), None)
    if other is not None:
        raise RecordError(f"unknown field {quote(other)} (an fk --batch record has index, "
                          f"{', '.join(fields)} and perhaps id)")
    if "error" in rec:
        raise RecordError("an error record of fk --batch, not a pose")
    missing = next((k for k in fields if k not in rec and k != "units"), None)
    if missing is not None:
        raise RecordError(f"an fk --batch record without {missing}")
    if type(rec["index"]) is not int or rec["index"] < 0:
        raise RecordError("index: expected a whole number from 0 (an fk --batch record)")
    if type(rec["within_limits"]) is not bool:
        raise RecordError("within_limits: expected true or false (an fk --batch record)")
    numbers(rec["rpy"], 3, "rpy")
    T = _matrix_numbers(rec["T"], "T")
    if len(T) >= 12 and numbers(rec["xyz"], 3, "xyz") != (T[3], T[7], T[11]):
        raise RecordError("xyz is not T's position (an fk --batch record is read by its T)")
    out = {key: rec[key] for key in ("id", "T") if key in rec}
    return {**out, FK_LENGTH: _fk_units(rec["units"])} if "units" in rec else out


def _fk_units(units) -> str:
    """The length unit of an fk --batch record's ``units`` ``{"length", "angle"}``, checked."""
    from ...units import ANGLE_UNITS, LENGTH_UNITS
    if not (isinstance(units, dict) and set(units) == {"length", "angle"}
            and units["length"] in LENGTH_UNITS and units["angle"] in ANGLE_UNITS):
        raise RecordError("units: expected {\"length\": one of "
                          f"{', '.join(LENGTH_UNITS)}, \"angle\": deg or rad}} "
                          "(an fk --batch record)")
    return units["length"]


def _fields_together(keys: tuple, recs: list):
    """The keywords of records that all have the fields ``keys`` (in this order), pose
    fields of a fixed count and ``id``, checked together: the dicts :func:`_pose_keywords`
    gives, or None when any record has another field or a value to refuse (then each record
    goes through :func:`_pose_keywords`, which says what). One type check, one conversion
    and one range check a field for all the records (record by record it was half the
    reading time)."""
    import itertools
    columns = []
    for key in keys:
        values = [rec[key] for rec in recs]
        if key == "id":
            if not _ID_TYPES.issuperset(map(type, values)) or \
                    not all(map(math.isfinite, (v for v in values if type(v) is float))):
                return None
            columns.append(values)
            continue
        count = POSE_KEYS.get(key)
        if count is None or not all(type(v) is list and len(v) == count for v in values):
            return None
        flat = list(itertools.chain.from_iterable(values))
        if not NUMBER_TYPES.issuperset(map(type, flat)):
            return None
        try:
            flat = list(map(float, flat))
        except OverflowError:
            return None
        if not within_range(flat):
            return None
        rows = iter(flat)
        columns.append(list(zip(*[rows] * count)))
    if len(columns) == ("id" in keys):
        return None                                       # no pose: _pose_keywords says so
    return [dict(zip(keys, values)) for values in zip(*columns)]


#: the types an ``id`` may have (a float only when finite)
_ID_TYPES = frozenset({str, int, float, bool, type(None)})


def _lock(value) -> tuple:
    """A record's ``lock``: an object of joint names (or numbers from 1, as strings) and
    their held values in the user's units, as ``((joint, value), ...)``; the joints are
    found on the robot when the record is solved."""
    if type(value) is not dict or not value:
        raise RecordError("lock: expected an object of joints and their values, like "
                          '{"A3": 30}')
    names = list(value)
    held = numbers([value[k] for k in names], len(names), "lock")
    return tuple(zip(names, held))


