"""Rendering result dictionaries: JSON for scripts, rich tables for people.

Tables are built from the same ``to_dict()`` the JSON comes from, so what a
person sees is what a script gets. Colour only when stdout is a terminal and
``NO_COLOR`` is unset (rich honours both). A table never hides a value: the console
prints one too wide for it as stacked panels (:func:`fit_table`).
"""

from __future__ import annotations

import json
import math
import os
import sys


def emit_json(doc: dict) -> None:
    """Write one JSON document (and a newline) to stdout."""
    sys.stdout.write(json_line(doc))


def json_line(doc: dict) -> str:
    """``doc`` as one line of strict JSON (no NaN; numpy numbers and arrays as plain ones),
    ending in a newline."""
    return json.dumps(doc, allow_nan=False, default=_json_default) + "\n"


def _json_default(obj):
    import numpy as np
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def console():
    """A rich console on stdout; plain text when not a terminal or NO_COLOR is set.

    Its ``print`` never crops a table: one wider than the console is printed as stacked
    panels (:func:`fit_table`). When stdout is not a terminal the width is COLUMNS
    (default 120) and no line ends in a space. The width is :data:`MIN_WIDTH` at least
    (COLUMNS=0 on a terminal printed nothing, a few columns split the numbers)."""
    out = None
    width = None
    if not sys.stdout.isatty():
        try:
            width = max(int(os.environ.get("COLUMNS", "")), MIN_WIDTH)
        except ValueError:
            width = 120
        out = _NoTrailingSpaces(sys.stdout)
    else:
        import shutil
        # COLUMNS, else the terminal's size (rich reads COLUMNS=0 as a width of 0)
        width = max(shutil.get_terminal_size((120, 24)).columns, MIN_WIDTH)
    return _console_class()(file=out, highlight=False, markup=False,
                            no_color=bool(os.environ.get("NO_COLOR")) or None,
                            width=width, soft_wrap=False)


#: tables and text are laid out for at least this many columns (a narrower terminal wraps
#: the lines, a number stays whole)
MIN_WIDTH = 40


class _NoTrailingSpaces:
    """A text stream that writes every complete line without its trailing spaces (rich
    pads table lines to the table's width; a file or a pipe should not get them)."""

    def __init__(self, stream):
        self._stream = stream
        self._pending = ""

    def write(self, text: str) -> int:
        head, newline, self._pending = (self._pending + text).rpartition("\n")
        if newline:
            self._stream.write("\n".join(line.rstrip(" ") for line in head.split("\n")) + "\n")
        return len(text)

    def flush(self) -> None:
        if self._pending:   # a line printed without its end: keep it whole
            self._stream.write(self._pending)
            self._pending = ""
        self._stream.flush()

    def __getattr__(self, name):   # isatty, encoding, fileno, ... of the real stream
        return getattr(self._stream, name)


_CONSOLE_CLASS = None


def _console_class():
    """rich's Console, whose print passes every table through :func:`fit_table` (made on
    first use: rich is imported only when a table is drawn)."""
    global _CONSOLE_CLASS
    if _CONSOLE_CLASS is None:
        from rich.console import Console
        from rich.table import Table

        class KincalcConsole(Console):
            def print(self, *objects, **kwargs):
                if any(isinstance(o, Table) for o in objects):
                    objects = [p for o in objects
                               for p in (fit_table(self, o) if isinstance(o, Table) else (o,))]
                super().print(*objects, **kwargs)

        _CONSOLE_CLASS = KincalcConsole
    return _CONSOLE_CLASS


#: wide enough for any table's natural layout
_UNBOUNDED = 100_000
_BOX_CHARS = set("\u2500\u2501\u2550\u2504\u2505\u254c\u254d-=+|")


def key_columns(table, n: int):
    """Mark the first ``n`` columns of ``table`` as the key of its rows, repeated in every
    panel when the table is split (:func:`fit_table`); the default is 1, a matrix has 0."""
    table.kincalc_key_columns = n
    return table


def fit_table(console, table, width: int | None = None) -> list:
    """``table`` as one or more tables that show all of it within ``width`` columns
    (default: the console's).

    A table is kept as it is when it fits, or when rich can fit it by wrapping cells at
    spaces without cutting a word. Otherwise its columns are dealt out into stacked
    panels, as many columns to a panel as fit at their natural width, each panel
    repeating the key columns (:func:`key_columns`; the first column by default) and
    titled "(continued)" after the first (a headerless matrix's panels name their
    columns). A column too wide even alone with the key is wrapped, long words folded:
    every character stays on the screen."""
    width = width or console.width
    skeleton = _skeleton(console, table)
    size = console.measure(skeleton, options=console.options.update_width(_UNBOUNDED))
    if size.maximum <= width or (size.minimum <= width
                                 and _keeps_every_word(console, table, width)):
        return [table]
    n = len(table.columns)
    k = min(getattr(table, "kincalc_key_columns", 1), n - 1)

    def natural(group):
        return _natural_width(console, _subtable(skeleton, [*range(k), *group]))

    groups = _deal(natural, list(range(k, n)), width)
    if len(groups) == 1:   # nothing to split: each row's key above its values, or fold
        stacked = _stacked(table, k) if k else None
        if stacked is not None and _keeps_every_word(console, stacked, width):
            return [stacked]
        return [_subtable(table, list(range(n)), fold=True)]
    panels = []
    for p, group in enumerate(groups):
        wide = natural(group)
        sub = _subtable(table, [*range(k), *group], fold=wide > width)
        sub.title = _panel_title(table, p, group[0] + 1, group[-1] + 1, n, min(wide, width))
        sub.caption = table.caption if p == len(groups) - 1 else None
        panels.append(sub)
    return panels


def _stacked(table, k: int):
    """``table`` in one column: each row's ``k`` key cells on a line (in the key column's
    style), then its other cells below them, indented (for a table whose values cannot
    stand beside their keys without cutting a word)."""
    import copy

    from rich.padding import Padding
    from rich.text import Text
    out = copy.copy(table)
    out.columns, out.rows, out.show_header = [], [], False
    out.add_column(overflow="fold")
    keys, rest = table.columns[:k], table.columns[k:]
    for r in range(table.row_count):
        key = [c._cells[r] for c in keys]
        out.add_row(" ".join(str(x) for x in key) if all(isinstance(x, str) for x in key)
                    else Text(" ").join(Text(x) if isinstance(x, str) else x for x in key),
                    style=keys[0].style or None)
        for c in rest:
            out.add_row(Padding(c._cells[r], (0, 0, 0, 2)))
    return out


def _deal(natural, rest: list, width: int) -> list:
    """``rest`` (column indices) in as few groups as fit ``width`` (``natural(group)`` is
    a group's width beside the key columns), in order, as even in count as they can be
    (not a full panel and a panel of one column)."""
    greedy, group = [], []
    for col in rest:
        if group and natural(group + [col]) > width:
            greedy.append(group)
            group = []
        group.append(col)
    greedy.append(group)
    size, more = divmod(len(rest), len(greedy))
    even, start = [], 0
    for i in range(len(greedy)):
        stop = start + size + (i < more)
        even.append(rest[start:stop])
        start = stop
    return even if all(len(g) == 1 or natural(g) <= width for g in even) else greedy


def _skeleton(console, table):
    """``table`` cut down to two rows: the widest cell of each column and the cell with
    its longest word. It measures as the table does (the natural width, and the width
    below which a word must be cut), quickly, again and again."""
    import copy
    from dataclasses import replace

    from rich.measure import Measurement
    options = console.options.update_width(_UNBOUNDED)
    columns = []
    for col in table.columns:
        cells = list(col.cells)
        if cells:
            sizes = [Measurement.get(console, options, c) for c in cells]
            widest = max(range(len(cells)), key=lambda i: sizes[i].maximum)
            longest_word = max(range(len(cells)), key=lambda i: sizes[i].minimum)
            cells = [cells[widest], cells[longest_word]]
        columns.append(replace(col, _cells=cells))
    sk = copy.copy(table)
    sk.columns = columns
    sk.rows = table.rows[:1] * 2 if table.rows else []
    sk.title = sk.caption = None
    return sk


def _natural_width(console, table) -> int:
    return console.measure(table, options=console.options.update_width(_UNBOUNDED)).maximum


def _words(console, table, width: int):
    from collections import Counter
    lines = console.render_lines(table, console.options.update_width(width), pad=False)
    words = " ".join("".join(s.text for s in line if not s.control) for line in lines).split()
    # box lines ("────") get shorter with the table: they are not data
    return Counter(w for w in words if len(w) == 1 or not set(w) <= _BOX_CHARS)


def _keeps_every_word(console, table, width: int) -> bool:
    """Whether rich renders ``table`` in ``width`` columns with every word it shows at full
    width: rich shrinks wrapping columns widest first, past their longest word (which
    it then cuts with "…"), and crops a row of unwrappable columns at the edge."""
    shown = _words(console, table, width)
    return all(shown[w] >= n for w, n in _words(console, table, _UNBOUNDED).items())


def _subtable(table, columns: list, fold: bool = False):
    """A copy of ``table`` with only the columns at indices ``columns`` (their cells
    shared); ``fold``: let them wrap and fold long words, with no minimum width."""
    import copy
    from dataclasses import replace
    sub = copy.copy(table)
    extra = {"overflow": "fold", "no_wrap": False, "min_width": None} if fold else {}
    sub.columns = [replace(table.columns[c], _index=i, **extra) for i, c in enumerate(columns)]
    return sub


def _panel_title(table, n: int, a: int, b: int, total: int, width: int):
    """The title of panel ``n`` (from 0) holding columns ``a``..``b`` of ``total``, the
    note alone when the whole would not fit the panel's ``width``."""
    from rich.text import Text
    title = table.title
    if table.show_header:
        if n == 0:
            return title
        note = "(continued)"
    else:
        note = f"(columns {a}-{b} of {total})" if a != b else f"(column {a} of {total})"
    if title is None or title == "":
        return note
    if isinstance(title, Text):
        whole = Text.assemble(title, " " + note)
        return whole if whole.cell_len <= width else note
    whole = f"{title} {note}"
    return whole if Text(whole).cell_len <= width else note


def joint_amount(robot, joint: str, x: float, units: dict) -> str:
    """An amount of joint ``joint`` (its name; an angle for a revolute joint, a length for a
    prismatic one) with 4 significant digits and its unit, from the document's ``units``:
    a limit violation reads the same in every table whatever --precision is."""
    revolute = next(j.revolute for j in robot.joints if j.name == joint)
    unit = units["angle"] if revolute else ("" if units["length"] == "unitless"
                                            else units["length"])
    return f"{x:.4g}" + (f" {unit}" if unit else "")


#: significant digits a table shows at most: a double holds about 16
SIGNIFICANT = 16


def num(x, precision: int) -> str:
    """A number for a table: fixed decimals (no more than leave :data:`SIGNIFICANT`
    significant digits: 11184349.22705329 at --precision 12, not 11184349.227053290233),
    no negative zero, inf/nan spelled out."""
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if math.isinf(x) or math.isnan(x):
        return str(x)
    whole = len(str(int(abs(x)))) if abs(x) >= 1 else 0
    s = f"{x:.{min(precision, max(SIGNIFICANT - whole, 0))}f}"
    if s.lstrip("-").strip("0.") == "":
        s = s.lstrip("-")
    return s


def vec(values, precision: int) -> str:
    return "  ".join(num(v, precision) for v in values)


def matrix_table(rows, precision: int, title: str | None = None, headers=None,
                 row_labels=None):
    """A borderless right-aligned table of a matrix (list of rows); ``row_labels``: a first
    column naming each row (repeated in every panel of a split table)."""
    from rich import box
    from rich.table import Table
    t = Table(title=title or None, box=box.SIMPLE, show_header=headers is not None,
              title_justify="left", pad_edge=False)
    key_columns(t, 0 if row_labels is None else 1)
    if row_labels is not None:
        t.add_column("", justify="left")
    ncols = len(rows[0]) if rows else 0
    for k in range(ncols):
        t.add_column(headers[k] if headers else "", justify="right")
    for i, r in enumerate(rows):
        t.add_row(*([] if row_labels is None else [row_labels[i]]),
                  *(num(v, precision) for v in r))
    return t


def kv_table(pairs, title: str | None = None):
    """Two-column table of (label, text) pairs."""
    from rich import box
    from rich.table import Table
    t = Table(title=title or None, box=box.SIMPLE, show_header=False, title_justify="left",
              pad_edge=False)
    t.add_column(style="bold")
    t.add_column()
    for k, v in pairs:
        t.add_row(k, v)
    return t


def file_words(text) -> str:
    """Words a robot file wrote (its title, source, notes, names) as a table shows them: on
    one line with no control character (:func:`~kincalc.limits.printable`: no escape sequence
    reaches the terminal). Markup is off in :func:`console`: a name such as ``[/]`` or
    ``[link=...]`` is text."""
    from ..limits import printable
    return printable(text)


def bold_line(bold: str, rest: str = ""):
    """A line of text whose first part is bold (a rich ``Text``: no markup is read)."""
    from rich.text import Text
    return Text.assemble((bold, "bold"), rest)


def heading(doc: dict):
    """The robot's line above a command's tables (a rich ``Text``; the name and title as
    :func:`file_words`)."""
    from .common import joints_text
    r = doc["robot"]
    title = f" - {r['title']}" if r.get("title") else ""
    return bold_line(file_words(r["name"]), f"{file_words(title)}  ({joints_text(r['dof'])}, "
                                            f"{doc['units']['angle']}, {doc['units']['length']})")


def joint_pairs(doc: dict, robot, precision: int) -> str:
    u = doc["units"]
    parts = []
    for j, v in zip(robot.joints, doc["q"]):
        unit = u["angle"] if j.revolute else u["length"]
        if unit == "unitless":
            unit = ""
        parts.append(f"{j.name}={num(v, precision)}{'' if not unit else ' ' + unit}")
    return ", ".join(parts)
