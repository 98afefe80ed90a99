"""CSV batch input: the header's columns, and one line of cells to pose keywords (see
:mod:`kincalc.cli.batch` for what a record is)."""

from __future__ import annotations

from ...limits import DECIMAL, quote
from .values import RecordError, line_text, range_error, within_range

#: CSV column groups and the pose key they fill
CSV_GROUPS = {("x", "y", "z"): "xyz", ("roll", "pitch", "yaw"): "rpy",
              ("qw", "qx", "qy", "qz"): "quat", ("ax", "ay", "az"): "approach"}
#: the first line of a JSON lines input that would otherwise pass for a CSV header
_JSON_WORDS = {"null", "true", "false", "NaN", "Infinity"}


def header_problem(header, robot, kind: str = "ik") -> str | None:
    """Why the CSV header ``header`` (from :func:`read_header`: the column names, or the
    reason it cannot be read) cannot be used for ``robot``'s records of command ``kind``,
    or None."""
    return header if isinstance(header, str) else _csv_layout(header, robot, kind)[1]


def csv_records(header, robot, start: int, lines, kind: str) -> list:
    """``[(index, keywords or None, error or None)]`` of CSV ``lines`` (bytes, or None for a
    line over the length limit) from record ``start``, under the column names ``header`` (or
    the reason the header cannot be used: every record's error), for command ``kind``."""
    out = []
    if isinstance(header, str):
        reason, layout = header, None
    else:
        layout, reason = _csv_layout(header, robot, kind)
    for i, line in enumerate(lines, start):
        try:
            if layout is None:
                raise RecordError(reason)
            out.append((i, _csv_record(header, layout, line_text(line)), None))
        except RecordError as exc:
            out.append((i, None, f"record {i + 1}: {exc}"))
    return out


def _csv_layout(header, robot, kind: str = "ik"):
    """``(layout, None)``: the pose keys a CSV record fills and the column of each of their
    values, ``[(key, [column, ...])]``; or ``(None, reason)`` when the header cannot be
    used (a column twice, or one that is not a pose or joint column; the columns named are
    those of command ``kind``: fk and jacobian take joints only)."""
    seen = set()
    for h in header:
        if h in seen:
            return None, f"column {quote(h)} appears twice in the CSV header"
        seen.add(h)
    where = {h: k for k, h in enumerate(header)}
    layout, used = [], set()
    groups = {} if kind in ("fk", "jacobian") else CSV_GROUPS       # (these take joints only)
    for cols, key in groups.items():
        if all(c in where for c in cols):
            layout.append((key, [where[c] for c in cols]))
            used |= set(cols)
    names = [j.name for j in robot.joints]
    if all(n in where for n in names):
        layout.append(("q", [where[n] for n in names]))
        used |= set(names)
    if "id" in where and "id" not in names:     # a text echoed back, as a JSON record's id
        layout.append(("id", [where["id"]]))
        used.add("id")
    extra = [h for h in header if h not in used]
    if not extra:
        if layout[-1][0] == "id" and len(layout) == 1:
            return None, ("no joint columns (give " + ",".join(names) + ")" if not groups
                          else "no pose columns (give x,y,z with an orientation, or the joints)")
        return layout, None
    unknown = [h for h in extra if h not in names and not any(h in g for g in groups)]
    if unknown:
        joints = f"the joints {','.join(names)}"
        return None, f"unknown column {quote(unknown[0])} (columns: " + (
            f"x,y,z with roll,pitch,yaw or qw,qx,qy,qz or ax,ay,az; or {joints}" if groups
            else joints) + "; and id)"
    # every column known, but a group or the joints not whole
    group = next((g for g in (*groups, tuple(names)) if extra[0] in g), ())
    missing = [c for c in group if c not in where]
    return None, (f"column {quote(extra[0])} without {', '.join(map(quote, missing))}: "
                  f"give {','.join(group)} together")


def _csv_patterns():
    import re
    # a line of plain numbers (digits, signs, points, exponents) needs no cell-by-cell look
    plain = re.compile(r"[0-9eE+\-.,\s]*", re.ASCII)
    number = DECIMAL
    header = re.compile(r"[A-Za-z_][\w.\-]*(?:[ \t]*,[ \t]*[A-Za-z_][\w.\-]*)*", re.ASCII)
    return plain, number, header


_PLAIN = _NUMBER = _HEADER = None


def _csv_record(header, layout, text: str) -> dict:
    """The pose keywords of one CSV line: decimal numbers, one per column, and the text of
    an ``id`` column (the layout's last entry, :func:`_csv_layout`), as the cell holds it."""
    global _PLAIN, _NUMBER
    if _PLAIN is None:
        _PLAIN, _NUMBER, _ = _csv_patterns()
    if '"' in text:                     # cells quoted as a CSV writer may quote them
        cells = _unquoted(text)
        text = ",".join(cells)
    else:
        cells = text.split(",")
    if len(cells) != len(header):
        raise RecordError(f"{len(cells)} values for {len(header)} columns")
    ident = None
    if layout[-1][0] == "id":
        (k,), layout = layout[-1][1], layout[:-1]
        ident, cells[k] = cells[k], "0"             # (not a number: read as 0, not used)
        text = ",".join(cells)
    values = None
    if _PLAIN.fullmatch(text):
        try:
            values = list(map(float, cells))
        except ValueError:
            pass
    if values is None:                  # find the cell that is not a number, and say so
        # (without the blanks around it: float() keeps some, a separator 0x1c-0x1f)
        cells = [c.strip() for c in cells]
        for h, c in zip(header, cells):
            if not _NUMBER.fullmatch(c):
                raise RecordError(f"column {quote(h)}: " + (
                    "empty cell" if not c else f"{quote(c)} is not a number"))
        values = list(map(float, cells))
    if not within_range(values):
        range_error(values, lambda k: f"column {quote(header[k])}")
    out = {key: tuple(values[k] for k in cols) for key, cols in layout}
    if ident is not None:
        out["id"] = ident
    return out


def read_header(line, forced: bool, robot=None):
    """The column names of a CSV header line. With ``forced`` (--input-format csv, or a
    name ending in .csv), the reason when the line cannot be read; otherwise None when it
    is not a header (then the input is JSON lines), nor is a single name that is not a column
    of ``robot``'s records (a pose or joint column): a JSON lines input whose first record is
    a stray word stays JSON lines, while ``X,Y,Z`` is a CSV header whose columns are wrong."""
    global _HEADER
    if _HEADER is None:
        _, _, _HEADER = _csv_patterns()
    try:
        text = line_text(line)
    except RecordError as exc:
        return f"the CSV header (the first line) cannot be used: {exc}" if forced else None
    if '"' in text and "," in text and text[0] not in "{[":     # names a CSV writer quoted
        text = ",".join(_unquoted(text))
    if not forced and (text in _JSON_WORDS or not _HEADER.fullmatch(text)):
        return None
    names = tuple(c.strip() for c in text.split(","))
    if not forced and robot is not None and len(names) == 1 and names[0] not in _columns(robot):
        return None
    return names


def _unquoted(text: str) -> list:
    """The cells of a CSV line, quoted or not (``"q1","0.5"``), as the csv module reads them."""
    import csv
    try:
        return next(csv.reader([text], strict=True))
    except csv.Error as exc:
        raise RecordError(f"not a CSV line: {exc}") from None


def _columns(robot) -> set:
    """The names a CSV header may hold for ``robot``: the pose groups' and the joints'."""
    return {c for group in CSV_GROUPS for c in group} | {j.name for j in robot.joints}
