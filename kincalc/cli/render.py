"""Rendering result dictionaries: JSON for scripts, rich tables for people.

Tables are built from the same ``to_dict()`` the JSON comes from, so what a
person sees is what a script gets. Colour only when stdout is a terminal and
``NO_COLOR`` is unset (rich honours both).
"""

from __future__ import annotations

import json
import math
import os
import sys


def emit_json(doc: dict) -> None:
    """Write one JSON document (and a newline) to stdout."""
    sys.stdout.write(json.dumps(doc, allow_nan=False, default=_json_default) + "\n")


def _json_default(obj):
    import numpy as np
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def console():
    """A rich console on stdout; plain text when not a terminal or NO_COLOR is set."""
    from rich.console import Console
    width = None
    if not sys.stdout.isatty():
        try:
            width = max(int(os.environ.get("COLUMNS", "")), 40)
        except ValueError:
            width = 120
    return Console(highlight=False, no_color=bool(os.environ.get("NO_COLOR")) or None,
                   width=width, soft_wrap=False)


def num(x, precision: int) -> str:
    """A number for a table: fixed decimals, no negative zero, inf/nan spelled out."""
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if math.isinf(x) or math.isnan(x):
        return str(x)
    s = f"{x:.{precision}f}"
    if s.lstrip("-").strip("0.") == "":
        s = s.lstrip("-")
    return s


def vec(values, precision: int) -> str:
    return "  ".join(num(v, precision) for v in values)


def matrix_table(rows, precision: int, title: str | None = None, headers=None):
    """A borderless right-aligned table of a matrix (list of rows)."""
    from rich import box
    from rich.table import Table
    from rich.markup import escape
    t = Table(title=escape(title) if title else None, box=box.SIMPLE, show_header=headers is not None,
              title_justify="left", pad_edge=False)
    ncols = len(rows[0]) if rows else 0
    for k in range(ncols):
        t.add_column(headers[k] if headers else "", justify="right")
    for r in rows:
        t.add_row(*(num(v, precision) for v in r))
    return t


def kv_table(pairs, title: str | None = None):
    """Two-column table of (label, text) pairs."""
    from rich import box
    from rich.table import Table
    from rich.markup import escape
    t = Table(title=escape(title) if title else None, box=box.SIMPLE, show_header=False, title_justify="left",
              pad_edge=False)
    t.add_column(style="bold")
    t.add_column()
    for k, v in pairs:
        t.add_row(escape(k), escape(v))
    return t


def heading(doc: dict) -> str:
    r = doc["robot"]
    title = f" - {r['title']}" if r.get("title") else ""
    return f"[bold]{r['name']}[/bold]{title}  ({r['dof']} joints, {doc['units']['angle']}, {doc['units']['length']})"


def joint_pairs(doc: dict, robot, precision: int) -> str:
    u = doc["units"]
    parts = []
    for j, v in zip(robot.joints, doc["q"]):
        unit = u["angle"] if j.revolute else u["length"]
        if unit == "unitless":
            unit = ""
        parts.append(f"{j.name}={num(v, precision)}{'' if not unit else ' ' + unit}")
    return ", ".join(parts)
