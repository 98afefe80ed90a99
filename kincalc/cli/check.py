"""``kincalc check``: grade homework sheets."""

from __future__ import annotations

import sys
from typing import Annotated, List, Optional

import typer

from .common import DebugOpt, JsonOpt, PrecisionOpt


def check(
    sheets: Annotated[List[str], typer.Argument(
        metavar="SHEET.yaml...", show_default=False,
        help="One or more homework sheets (YAML; format in 'man kincalc-check').")],
    quiet: Annotated[bool, typer.Option(
        "--quiet", "-q", help="Print only each sheet's score line.")] = False,
    robots_dir: Annotated[Optional[List[str]], typer.Option(
        "--robots-dir", metavar="DIR", show_default=False,
        help="Also let a sheet's 'robot:' name a robot file in DIR (repeatable; looked up "
             "before the sheet's folder). Without it a sheet may name only a bundled robot, "
             "an inline robot or a file in its own folder.")] = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    debug: DebugOpt = False,
):
    """Grade homework sheets: each answer right or wrong, with hints and a score.

    A sheet names a robot (bundled, a file in its folder, or inline) and lists
    items (dh, link, fk, ik, jacobian, reach, singular), each with the
    student's answer. Every item is graded against kincalc's own results;
    wrong answers get the error and, where one fits, the slip behind it
    (degrees read as radians, a joint's sign, two joints swapped, a
    transposed or inverted matrix, standard and modified DH mixed up). IK
    answers are graded per solution set; missed sets are listed by branch.

    Sheets are untrusted input: a sheet's robot file must lie in the sheet's
    folder (or a --robots-dir folder), and no message quotes another file.

    Exit status: 0 every answer right, 1 some wrong, 2 an invalid sheet (the
    message names file and line; other sheets are still graded; the worst
    status counts).
    """
    import os

    from ..homework import grade, load_sheet
    from ..errors import InputError, KincalcError
    dirs = list(robots_dir or [])
    for d in dirs:
        if not os.path.isdir(d):
            raise InputError(f"--robots-dir {d}: "
                             + ("no such folder" if not os.path.exists(d) else "not a folder"))
    status = 0
    for path in sheets:
        try:
            report = grade(load_sheet(path, dirs))
        except KincalcError as exc:
            if len(sheets) == 1 or debug:
                raise
            sys.stderr.write(f"kincalc: error: {' '.join(str(exc).split())}\n")
            status = 2
            continue
        if json:
            from .render import emit_json
            emit_json(report.to_dict())
        else:
            _tables(report.to_dict(), precision, quiet)
        if not report.all_correct and status == 0:
            status = 1
    raise typer.Exit(status)


def _score_line(doc) -> str:
    s = doc["score"]
    pts = f"{_n(s['points'])} of {_n(s['total'])} points ({_n(s['percent'])} %)"
    return f"score: {pts}; {s['correct']} of {s['items']} items right"


def _n(x) -> str:
    return str(int(x)) if float(x).is_integer() else f"{x:g}"


def _tables(doc, precision: int, quiet: bool):
    from rich.markup import escape
    from rich.table import Table

    from .render import console, matrix_table
    c = console()
    who = f" — {doc['student']}" if doc["student"] else ""
    if quiet:
        c.print(f"{escape(doc['sheet'])}{escape(who)}: {_score_line(doc)}", highlight=False)
        return
    r = doc["robot"]
    title = f" — {doc['title']}" if doc["title"] else ""
    c.print(f"[bold]{escape(doc['sheet'])}[/bold]{escape(title)}{escape(who)}")
    u, t = doc["units"], doc["tolerance"]
    lu = "" if u["length"] == "unitless" else f" {u['length']}"
    c.print(f"robot {escape(r['name'])} ({r['dof']} joints, {r['convention']}); "
            f"tolerances: position {t['position']:g}{lu}, angle {t['angle']:g} {u['angle']}, "
            f"matrix entries {t['matrix']:g}", highlight=False)
    for item in doc["items"]:
        mark = "[green]right[/green]" if item["passed"] else "[red]wrong[/red]"
        c.print()
        c.print(f"[bold]item {escape(item['id'])}[/bold] ({item['kind']}): {mark}",
                highlight=False)
        rows = Table(box=None, show_header=False, pad_edge=False, padding=(0, 2, 0, 2))
        rows.add_column(style="dim", no_wrap=True)
        rows.add_column(overflow="fold")
        rows.add_row("result", escape(item["message"]))
        if item["error"] is not None and item["kind"] != "ik":
            rows.add_row("error", f"{item['error']:.{max(precision, 1)}g}")
        if item["hint"] and item["kind"] != "ik":
            rows.add_row("hint", escape(item["hint"]))
        c.print(rows)
        d = item["details"]
        if item["kind"] == "ik" and (d.get("sets") or d.get("missed")):
            c.print(_ik_table(d, precision))
        elif not item["passed"] and item["kind"] in ("link", "fk", "jacobian") \
                and "expected" in d:
            c.print(matrix_table(d["expected"], precision, title="expected"))
    c.print()
    c.print(f"[bold]{_score_line(doc)}[/bold]", highlight=False)


def _ik_table(d, precision):
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from .render import num
    t = Table(box=box.SIMPLE_HEAD, pad_edge=False)
    for name in ("set", "q", "result", "residual", "branch / note"):
        t.add_column(name, overflow="fold", no_wrap=name in ("set", "result"))
    for s in d["sets"]:
        res = s["residual"]
        resid = num(res["position"], precision) + (
            "" if res["orientation"] is None else " / " + num(res["orientation"], precision))
        colour = {"correct": "green", "duplicate": "yellow"}.get(s["status"], "red")
        note = s.get("branch", "") if s["status"] == "correct" and "branch" in s else ""
        if s.get("note"):
            note = (note + "; " if note else "") + s["note"]
        t.add_row(str(s["set"]), " ".join(num(v, precision) for v in s["q"]),
                  f"[{colour}]{s['status']}[/{colour}]", resid, escape(note))
    for m in d["missed"]:
        t.add_row("-", " ".join(num(v, precision) for v in m["solution_q"]),
                  "[red]missed[/red]", "", escape(m["branch"]))
    return t
