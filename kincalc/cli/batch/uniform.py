"""JSON lines written alike, read together: the lines of a chunk that differ only in their
numbers are read with a few array operations on their bytes, not ``json.loads`` a line.

A line's *shape* is its bytes with each number (a run of number characters: digits, ``.``,
``+``, ``-``, and ``e`` or ``E`` after a digit or point) replaced by one ``#``. The lines of
the chunk's most common shape are read together when one of them, read alone by
:mod:`~kincalc.cli.batch.records`, is a good record whose fields are all arrays of numbers
(``accept`` says which fields): the other lines of that shape are the same JSON text but
for their numbers, so each is the same object with its own numbers, once every number is
a JSON number (RFC 8259: ``-`` only first or after the exponent's ``e``, ``+`` only there,
digits on both sides of a point, no leading zero) that ``float()`` reads as ``json`` does.
``json`` reads a number with a point or an exponent by ``float()`` of its text, and an
integer by ``int()``, whose float is ``float()`` of the same text (both round the exact
value once) except for ``-0`` (``0``, not ``-0.0``): such a line, like any line of another
shape, with a number out of the grammar or beyond MAX_MAGNITUDE, is left to the record by
record reading, which says what is wrong. Nothing here writes an error.
"""

from __future__ import annotations

from collections import Counter
from typing import NamedTuple

import numpy as np

from ...limits import MAX_MAGNITUDE

#: byte classes: 0 other, 1 a digit 1-9, 2 "0", 3 ".", 4 "-", 5 "+", 6 "e" or "E" (a
#: number's only after a digit or a point, else 0: :func:`_scan`)
_CLASSES = bytes(1 if c in b"123456789" else 2 if c == ord("0") else 3 if c == ord(".") else
                 4 if c == ord("-") else 5 if c == ord("+") else 6 if c in b"eE" else 0
                 for c in range(256))
_NUMBER_CHARACTERS = b"0123456789.-+eE"
#: the number characters as "#", the others kept
_MARKED = bytes(ord("#") if c in _NUMBER_CHARACTERS else c for c in range(256))
#: the number characters kept, the others made spaces
_NUMBERS_ONLY = bytes(c if c in _NUMBER_CHARACTERS else ord(" ") for c in range(256))
_DIGIT_OR_POINT = np.array([0, 1, 1, 1, 0, 0, 0], bool)
#: by pair code ``8 a + b`` of the classes of two characters in a row, a number holding them
#: is no JSON number: after "+", "-" or ".", no digit; after "e", no digit or sign; "+" after
#: no "e"; "-" after a number character but "e"; "." after no digit. (A leading zero and -0
#: are found apart.) Each such pair holds a character of class 3 or more.
_BAD_PAIR = np.zeros((8, 8), bool)
_BAD_PAIR[3:6, :] = True
_BAD_PAIR[3:6, 1:3] = False
_BAD_PAIR[6, :] = True
_BAD_PAIR[6, (1, 2, 4, 5)] = False
_BAD_PAIR[:6, 5] = True
_BAD_PAIR[1:6, 4] = True
_BAD_PAIR[(0, 3, 4, 5, 6), 3] = True
_BAD_PAIR = _BAD_PAIR.ravel()


class Together(NamedTuple):
    """The lines read together: ``at (m,)`` their positions in the chunk, ascending;
    ``fields`` ``((key, count), ...)`` in the lines' order; ``values (m, total)`` the
    numbers of each line, field after field (floats, as json and the record reader give
    them)."""

    at: np.ndarray
    fields: tuple
    values: np.ndarray


def read_together(lines, accept) -> Together | None:
    """The lines of ``lines`` (bytes; None for an over-long line) that are read together
    (the module's docstring), or None. ``accept(line)``: the fields ``((key, count), ...)``
    of a line read alone that may be read together, or None."""
    live = list(range(len(lines))) if None not in lines else \
        [k for k, line in enumerate(lines) if line is not None]
    if not live:
        return None
    texts = lines if len(live) == len(lines) else [lines[k] for k in live]
    text, cls, start, shape = _scan(texts)
    first = shape[:shape.find(b"\n")] if len(texts) > 1 else shape
    if b"#" in text or (len(texts) > 1 and shape != b"\n".join([first] * len(texts))):
        # the lines of the most common shape, but those with a "#" of their own
        shapes = shape.split(b"\n")
        first = Counter(shapes).most_common(1)[0][0]
        keep = [k for k, s in enumerate(shapes) if s == first and b"#" not in texts[k]]
        if not keep:
            return None
        live, texts = [live[k] for k in keep], [texts[k] for k in keep]
        text, cls, start, _ = _scan(texts)
    # the fields, from one of the first lines that the record reader reads without error
    fields = None if b"\\" in first else next(filter(None, map(accept, texts[:16])), None)
    total = sum(count for _, count in fields or ())
    if not fields or first.count(b"#") != total:
        return None
    if b"e" in first or b"E" in first:        # "e" outside numbers: numbers as classed
        tokens = np.where(cls != 0, np.frombuffer(text, np.uint8), 32).tobytes().split()
    else:
        tokens = text.translate(_NUMBERS_ONLY).split()
    if len(tokens) != total * len(texts):       # (cannot be: every "#" is a number's)
        return None
    good = _grammar_ok(text, cls, start, len(texts))
    values = _floats(tokens, total, good)
    good &= (np.abs(values) <= MAX_MAGNITUDE).all(axis=1)   # (NaN from a bad line: False)
    if not good.any():
        return None
    at = np.array(live, np.intp)
    return Together(at[good], tuple(fields), values[good])


def _scan(texts):
    """``(text, class (L,), first of its number (L,), shape)`` of the lines ``texts``:
    ``text`` the lines each after a newline, then one; the class of each of its
    characters (:data:`_CLASSES`, 0 for no number character); the shapes of the lines,
    joined by newlines."""
    text = b"\n" + b"\n".join(texts) + b"\n"
    cls = np.frombuffer(text.translate(_CLASSES), np.uint8)
    marked = np.frombuffer(text.translate(_MARKED), np.uint8)
    if b"e" in text or b"E" in text:            # an "e" after no digit or point: no number's
        e = np.flatnonzero(cls == 6)
        e = e[~_DIGIT_OR_POINT[cls[e - 1]]]
        if len(e):
            cls, marked = cls.copy(), marked.copy()
            cls[e], marked[e] = 0, np.frombuffer(text, np.uint8)[e]
    num = cls != 0
    keep = num.copy()
    keep[1:] &= ~num[:-1]                           # the first character of each number
    start = keep.copy()
    keep |= ~num
    return text, cls, start, marked[keep][1:-1].tobytes()


def _grammar_ok(text, cls, start, lines: int) -> np.ndarray:
    """``(lines,)`` bool: the numbers of each line are JSON numbers that float() reads as
    json does (``text``: the ``lines`` lines, with a newline before and after)."""
    special = np.flatnonzero(cls >= 3)
    c = cls[special] << 3
    bad = _BAD_PAIR[(cls[special - 1] << 3) | cls[special]] | _BAD_PAIR[c | cls[special + 1]]
    # the first digit of a number (after its "-"): "0" then a digit is a leading zero;
    # "-0" then nothing an integer -0 (json: 0, not -0.0)
    begin = np.flatnonzero(start)
    minus = cls[begin] == 4
    first = begin + minus
    after = cls[first + 1]
    wrong = (cls[first] == 2) & ((after == 1) | (after == 2) | ((after == 0) & minus))
    good = np.ones(lines, bool)
    if bad.any() or wrong.any():
        at = np.concatenate((special[bad], first[wrong]))
        newlines = np.flatnonzero(np.frombuffer(text, np.uint8) == 10)
        good[np.searchsorted(newlines, at) - 1] = False
    return good


def _floats(tokens, total: int, good) -> np.ndarray:
    """The numbers ``(lines, total)`` of the tokens, line after line; a line that float()
    cannot read (then not ``good``) holds NaN."""
    try:
        return np.fromiter(map(float, tokens), float, len(tokens)).reshape(-1, total)
    except ValueError:
        pass
    out = np.full((len(tokens) // total, total), np.nan)
    for k in range(len(out)):
        try:
            out[k] = list(map(float, tokens[k * total:(k + 1) * total]))
        except ValueError:
            good[k] = False
    return out
