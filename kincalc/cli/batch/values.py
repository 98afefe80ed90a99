"""The values of batch records: the one error a record's fault raises, and its numbers
read and checked (finite, within :data:`~kincalc.limits.MAX_MAGNITUDE`) with messages that
name the field and value at fault."""

from __future__ import annotations

import math

from ...limits import MAX_MAGNITUDE, MAX_RECORD_BYTES, size_text


class RecordError(ValueError):
    """A batch record that cannot be used; the message names what is wrong."""


#: the types of a JSON number
NUMBER_TYPES = frozenset({int, float})
#: MAX_MAGNITUDE as the messages write it (1e9), and why it is there
LIMIT = f"{MAX_MAGNITUDE:.0e}".replace("e+0", "e").replace("e+", "e")
WHY = "kincalc's limit for the magnitude of a number"


def json_kind(value) -> str:
    """How a JSON value reads in a message: null, true, an array, a string, ..."""
    if value is None or isinstance(value, bool):
        return "null" if value is None else str(value).lower()
    return {list: "an array", dict: "an object", str: "a string"}.get(type(value), "a number")


def numbers(value, count: int, key: str) -> tuple:
    """The floats of the JSON array of field ``key``: ``count`` numbers (any number for
    0), each finite and within MAX_MAGNITUDE."""
    if type(value) is not list or (count and len(value) != count):
        raise RecordError(f"{key}: expected {count or 'a list of'} numbers")
    if not NUMBER_TYPES.issuperset(map(type, value)):     # true, "1", [...], null
        bad = next(v for v in value if type(v) not in NUMBER_TYPES)
        raise RecordError(f"{key}: {json_kind(bad)} is not a number")
    try:
        out = tuple(map(float, value))
    except OverflowError:                               # an integer beyond any float
        k = next(k for k, v in enumerate(value) if abs(v) > MAX_MAGNITUDE)
        raise RecordError(f"{key}: value {k + 1} is beyond {LIMIT}, {WHY}") from None
    if not within_range(out):
        range_error(out, lambda k: f"{key}: value {k + 1}")
    return out


def within_range(values) -> bool:
    """Whether every value is within MAX_MAGNITUDE (so finite: an overflow to infinity
    is caught, and no value is NaN, which neither a JSON number nor a decimal CSV cell can
    be; the JSON words NaN and Infinity are refused by the parser). Two C calls: this runs
    for every array of every record."""
    return not values or (min(values) >= -MAX_MAGNITUDE and max(values) <= MAX_MAGNITUDE)


def range_error(values, name):
    """Raise the RecordError for the first value that is not finite or too large;
    ``name(k)`` names value k in the message."""
    for k, x in enumerate(values):
        if not math.isfinite(x):
            raise RecordError(f"{name(k)} is not a finite number")
        if abs(x) > MAX_MAGNITUDE:
            raise RecordError(f"{name(k)} ({x:.6g}) is beyond {LIMIT}, {WHY}")


def line_text(line) -> str:
    """A record's line as text, without the whitespace around it."""
    if line is None:
        raise RecordError(f"longer than {size_text(MAX_RECORD_BYTES)}, kincalc's limit for a "
                          "--batch line")
    if b"\0" in line:
        raise RecordError("holds a NUL byte, so it is not a line of text")
    line = line.strip()
    try:
        return line.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise RecordError(f"not UTF-8 text (byte {line[exc.start]:#04x} at position "
                          f"{exc.start + 1})") from None
