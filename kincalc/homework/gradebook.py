"""A class's sheets at once (``kincalc check SHEET... --gradebook FILE --feedback-dir
DIR``): the gradebook, one CSV row per sheet, and the names of the feedback files.

Pure functions from :class:`~kincalc.homework.export.Outcome` objects (and sheet paths) to
rows, CSV text and file names; the command line writes them.
"""

from __future__ import annotations

import csv
import io
import os

from .export import number
from ..limits import printable

#: the columns before the items' and after them
LEAD_COLUMNS = ("student", "file")
TAIL_COLUMNS = ("points", "total", "percent", "error")

#: a text cell starting with one of these is read as a formula by spreadsheet programs
#: (CSV injection): such a cell gets a leading apostrophe
_FORMULA_START = ("=", "+", "-", "@")


def item_columns(outcomes) -> list[str]:
    """The item ids of the gradebook's columns: every id of every graded sheet, in the
    order of first appearance (sheets in the order given, items in sheet order).

    Parameters
    ----------
    outcomes : iterable of Outcome

    Returns
    -------
    list of str
    """
    seen: dict[str, None] = {}
    for o in outcomes:
        if o.report is not None:
            for r in o.report.items:
                seen.setdefault(r.id, None)
    return list(seen)


def safe_cell(text: str) -> str:
    """A text cell that a spreadsheet program shows as text, on one line: control
    characters and line breaks as :func:`~kincalc.limits.printable` shows them (spaces), and
    one starting, after any spaces (which a spreadsheet may strip: a tab or a carriage
    return before ``=`` is one), with ``=``, ``+``, ``-`` or ``@`` gets a leading apostrophe.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    text = printable(text)
    return "'" + text if text.lstrip(" ").startswith(_FORMULA_START) else text


def gradebook_rows(outcomes) -> list[list[str]]:
    """The gradebook as rows of text cells, the header first.

    Parameters
    ----------
    outcomes : sequence of Outcome
        One per sheet, in the order given; every one gets its row (an invalid sheet too).

    Returns
    -------
    list of list of str
        Header ``student, file, item ID..., points, total, percent, error`` (the item
        columns by :func:`item_columns`, named ``item ID``), then per sheet: the student
        (:attr:`Outcome.student`), the sheet's path, the points each item earned (its
        points when right, 0 when wrong, empty when the sheet has no such item), the
        points earned, the points there were, the percent (one decimal, never 100 unless
        every point was earned, never 0 unless none was) and an empty
        error; an invalid sheet has empty numbers and its error message. Text cells are
        made safe by :func:`safe_cell`.
    """
    ids = item_columns(outcomes)
    rows = [[*LEAD_COLUMNS, *(safe_cell(f"item {i}") for i in ids), *TAIL_COLUMNS]]
    for o in outcomes:
        lead = [safe_cell(o.student), safe_cell(o.path)]
        if o.report is None:
            rows.append([*lead, *([""] * len(ids)), "", "", "", safe_cell(o.error or "")])
            continue
        earned = {r.id: number(r.points if r.passed else 0) for r in o.report.items}
        s = o.report.score
        rows.append([*lead, *(earned.get(i, "") for i in ids), number(s["points"]),
                     number(s["total"]), number(s["percent"]), ""])
    return rows


def gradebook_csv(outcomes) -> str:
    """:func:`gradebook_rows` as CSV text (comma-separated, quoted where needed, lines
    ending in ``\\r\\n`` as RFC 4180 has them).

    Parameters
    ----------
    outcomes : sequence of Outcome

    Returns
    -------
    str
    """
    buf = io.StringIO()
    csv.writer(buf).writerows(gradebook_rows(outcomes))
    return buf.getvalue()


def feedback_names(paths) -> list[str]:
    """The feedback file's name for each sheet: the sheet's file name with ``.md`` for its
    extension; when two sheets would get one name (``a/hw.yaml`` and ``b/hw.yaml``, or
    names that differ only in case), the later sheet in the order given gets ``-2``,
    ``-3``, ... (``hw-2.md``), the first number that names no other sheet's file.

    Parameters
    ----------
    paths : sequence of str
        The sheets, in the order given.

    Returns
    -------
    list of str
        File names (no folder), one per path, all different even ignoring case.
    """
    stems = [os.path.splitext(os.path.basename(os.path.normpath(p)))[0] or "sheet"
             for p in paths]
    own = {s.casefold() for s in stems}
    taken: set[str] = set()
    out = []
    for stem in stems:
        name, k = stem, 1
        while name.casefold() in taken or (k > 1 and name.casefold() in own):
            k += 1
            name = f"{stem}-{k}"
        taken.add(name.casefold())
        out.append(name + ".md")
    return out
