"""Batch output formats: JSON lines (one strict encoder; the ik answers of a chunk written
together, their joint values by :mod:`~kincalc.cli.batch.numtext`) and CSV."""

from __future__ import annotations


#: the per-pose fields of a reach record, in CSV column order
REACH_FIELDS = ["index", "id", "reachable", "verdict", "distance", "solutions",
                "solutions_within_limits", "reason", "error"]


def csv_header(kind, robot) -> str:
    names = [j.name for j in robot.joints]
    if kind == "fk":
        cols = ["index", "id", "x", "y", "z", "roll", "pitch", "yaw", "within_limits", "error"]
    elif kind == "jacobian":
        cols = ["index", "id"] + [f"J{r}_{c}" for r in ("vx", "vy", "vz", "wx", "wy", "wz")
                                  for c in names] + ["rank", "manipulability", "singular", "error"]
    elif kind == "reach":
        cols = REACH_FIELDS
    else:
        head, tail = ["index", "id", "solution", "branch"], ["within_limits", "singular", "error"]
        cols = head + joint_columns(names, head + tail) + tail
    # a joint's name is a cell like any other: quoted where it holds a comma or a quote, and
    # made safe for spreadsheets (a name "=cmd" is no formula)
    return _csv_line([csv_cell(c) for c in cols])


def joint_columns(names, taken) -> list:
    """The CSV columns of the joints ``names`` beside the columns ``taken``: each joint's
    name, ``joint NAME`` for one named as a column of the record (a joint ``index`` made
    two columns ``index``, and a reader took the joint's value for the record's index),
    ``q1 .. qn`` if that still leaves two columns of one name."""
    cols = [f"joint {n}" if n in taken else n for n in names]
    if len(set(cols) | set(taken)) < len(cols) + len(set(taken)):
        cols = [f"q{k + 1}" for k in range(len(names))]
    return cols


def _csv_line(cells) -> str:
    import csv
    import io
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(cells)
    return buf.getvalue()


def strict_json():
    """The one JSON encoder of output records: NaN or Infinity in a record is an error
    (a bug: the chunk functions make non-finite results error records), never written.
    json.dumps(..., allow_nan=False) built an encoder a call: 2 us a record."""
    global _ENCODER
    if _ENCODER is None:
        import json
        _ENCODER = json.JSONEncoder(allow_nan=False)
    return _ENCODER


_ENCODER = None


def ik_lines(heads, q, labels, within, singular, owner) -> list:
    """The JSON line (without its newline) of each of ``len(heads)`` ik answers.

    Parameters
    ----------
    heads : list of dict
        The fields before ``reachable`` of each answer: ``{"index": i}`` or ``{"index": i,
        "id": id}``.
    q : ndarray (s, n)
        The joint values of all their solutions, display units, already rounded.
    labels : list (s,) of str
        The branch words of the solutions.
    within : ndarray (s,) of bool
        Whether each solution is within the joint limits.
    singular : ndarray (s,) of bool
        Whether each solution is at a singular configuration.
    owner : ndarray (s,) of int
        The answer (position in ``heads``) of each solution, ascending.

    Every joint value is written as ``"%.12g" % x`` (12 significant digits, as ik output
    lines have always written them), the rest as the strict JSON encoder writes it; an
    answer with no solution is ``"reachable": false, "solutions": []``, one whose solutions
    all violate the limits ``"reachable": false`` with them (the text of the solutions by
    :func:`ik_solutions`).
    """
    sols = ik_solutions(q, labels, within, singular, owner, len(heads))
    reach = reachable(within, owner, len(heads)).tolist()
    return [answer_line(h["index"], h, t, r).decode("ascii")
            for h, t, r in zip(heads, sols, reach)]


def reachable(within, owner, count: int):
    """``(count,)`` bool: each answer's ``reachable``, a solution within the joint limits
    reaches its pose (as ``ik``'s; the arguments as :func:`ik_lines`')."""
    import numpy as np
    out = np.zeros(count, bool)
    out[owner[within]] = True
    return out


def ik_solutions(q, labels, within, singular, owner, count: int) -> list:
    """The text (ASCII bytes) of the solutions of each of ``count`` ik answers, between the
    brackets of ``"solutions": [...]``, or None for an answer without a solution (the
    arguments as :func:`ik_lines`').

    The solutions of all answers are written at once, as rows of one byte grid: ``{"q": [``
    and the cells of :func:`~kincalc.cli.batch.numtext.g12_cells`, then the rest of the
    solution by a table of its branch word, limit flag and singular flag, then ", " or, after an answer's
    last solution, a newline; the zero bytes of the grid removed, the text cut at the
    newlines. (Formatting per solution in Python was the largest cost of a batch run;
    ``%.12g`` a number at a time, 150 ns, more than half of that.)
    """
    import numpy as np

    from .numtext import CELL
    s, n = q.shape
    strict = strict_json()
    words = {lab: k for k, lab in enumerate(dict.fromkeys(labels))}
    tails = [f'], "branch": {strict.encode(lab)}, "within_limits": {flag}, '
             f'"singular": {sing}}}'.encode()
             for lab in words for flag in ("false", "true") for sing in ("false", "true")]
    width = -(-max(map(len, tails), default=0) // 8)            # words of the longest
    table = np.zeros((len(tails) or 1, width * 8), np.uint8)
    for k, tail in enumerate(tails):
        table[k, :len(tail)] = np.frombuffer(tail, np.uint8)
    tails = table.view("<u8")[np.fromiter(map(words.__getitem__, labels), np.intp, s) * 4
                              + within * 2 + singular]
    last = np.ones(s, bool)                                     # an answer's last solution
    last[:-1] = owner[1:] != owner[:-1]
    grid = np.empty((min(s, ROWS), 2 + CELL // 8 * n + width), "<u8")   # one, kept cached
    body = b"".join([_rows(grid[:min(ROWS, s - k)], q[k:k + ROWS], tails[k:k + ROWS],
                           last[k:k + ROWS]) for k in range(0, s, ROWS)]).split(b"\n")
    body.pop()
    if len(body) == count:                                      # every answer has some
        return body
    sols = [None] * count
    for k, text in zip(owner[last].tolist(), body):
        sols[k] = text
    return sols


#: a reachable ik answer's line, from its index and the text of its solutions
ANSWER = b'{"index": %d, "reachable": true, "solutions": [%b]}'


def answer_line(index: int, head, sols, reachable: bool) -> bytes:
    """An ik answer's line (ASCII bytes) from its index, its head fields (``{"index":
    index[, "id": id]}``; None: the index alone), the text of its solutions (None: no
    solution) and whether one within the limits reaches the pose."""
    if reachable and (head is None or len(head) == 1):
        return ANSWER % (index, sols)
    head = strict_json().encode(head or {"index": index})[:-1].encode("ascii")
    if sols is None:
        return head + b', "reachable": false, "solutions": []}'
    return head + b', "reachable": %b, "solutions": [%b]}' % (
        b"true" if reachable else b"false", sols)


#: solutions written a block at a time (the block's grid stays in the cache)
ROWS = 1024


def _rows(grid, q, tails, last) -> bytes:
    """The text of the solutions ``q (r, n)`` (their rest ``tails (r, w)``, uint64 words of
    text and zero bytes), each followed by ", " or, where ``last (r,)``, a newline; written
    in ``grid (r, 2 + CELL // 8 * n + w)``, uint64."""
    import numpy as np

    from .numtext import CELL, g12_cells
    r, n = q.shape
    c = CELL // 8
    grid[:, 0] = _word(b'{"q": [')
    cells = g12_cells(q, out=grid[:, 1:1 + c * n].reshape(r, n, c))
    cells[:, :-1, c - 1] |= _word(b", ", 6)                     # into the cell's last bytes
    grid[:, 1 + c * n:-1] = tails
    grid[:, -1] = np.where(last, _word(b"\n"), _word(b", "))
    return grid.tobytes().translate(None, b"\0")      # (faster than a mask, 20 %)


def _word(text: bytes, at: int = 0):
    """``text`` (at most 8 - ``at`` bytes) at byte ``at`` of a little-endian uint64."""
    import numpy as np
    return np.frombuffer(bytes(at) + text.ljust(8 - at, b"\0"), "<u8")[0]


def rounded(a):
    """Arrays as nested lists rounded to 12 decimals, -0.0 as 0.0 (as results.json_numbers)."""
    import numpy as np
    return (np.round(a, 12) + 0.0).tolist()


def csv_rows(kind, robot, records) -> str:
    import csv
    import io
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    n = robot.dof
    if kind == "reach":
        for r in records:
            w.writerow([csv_cell(r.get(c)) for c in REACH_FIELDS])
        return buf.getvalue()
    for r in records:
        head = [r["index"], csv_cell(r.get("id"))]
        if "error" in r:
            width = {"fk": 7, "jacobian": 6 * n + 3, "ik": n + 4}[kind]
            w.writerow(head + [""] * width + [r["error"]])
        elif kind == "fk":
            w.writerow(head + r["xyz"] + r["rpy"] + [csv_cell(r["within_limits"]), ""])
        elif kind == "jacobian":
            w.writerow(head + [x for row in r["J"] for x in row] +
                       [r["rank"], r["manipulability"], csv_cell(r["singular"]), ""])
        elif not r["solutions"]:
            w.writerow(head + ["", "no solution"] + [""] * n + ["", "", ""])
        else:
            for k, s in enumerate(r["solutions"]):
                w.writerow(head + [k, csv_cell(s["branch"])] + s["q"]
                           + [csv_cell(s["within_limits"]), csv_cell(s["singular"]), ""])
    return buf.getvalue()


def csv_cell(value):
    """A value as a CSV cell: None empty, a bool ``true``/``false`` (as in JSON), a text made
    safe for spreadsheets (:func:`~kincalc.homework.gradebook.safe_cell`: an id ``=HYPERLINK(...)``
    is not a formula), a number as it is."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        from ...homework.gradebook import safe_cell
        return safe_cell(value)
    return value
