"""``kincalc ik --sweep JOINT``: every branch of a redundant arm along a held joint's
values, as tables, JSON, CSV and a drawing."""

from __future__ import annotations

import sys

from ..errors import InputError


def run_sweep(robot, target, units, joint: str, start, stop, steps, locks, *, near=None,
              plot_to=None, dpi=100, fmt="jsonl", json=False, precision=4) -> None:
    """Sweep ``joint`` (a name or number) over ``[start, stop]`` (user units, default its
    limits) in ``steps`` values (None: the default), the joints ``locks`` (SI) held; print
    the answer as ``json``, CSV (``fmt``) or tables, draw it to ``plot_to``. Exit status 1
    when no branch is within the limits at any value."""
    import typer

    from ..analysis.sweep import DEFAULT_STEPS, sweep, sweep_document, sweep_values
    from .common import joint_index, output
    j = joint_index(joint, robot, "--sweep")
    scale = units.a if robot.joints[j].revolute else units.l
    values = sweep_values(robot, j, None if start is None else start / scale,
                          None if stop is None else stop / scale, steps or DEFAULT_STEPS)
    sw = sweep(robot, target.targets(), j, values, locks)
    doc = sweep_document(sw, target, units, near=near)
    if plot_to is not None:
        from ..analysis.plot.sweeps import draw_sweep
        doc["plot"] = draw_sweep(sw, plot_to, units=units, dpi=dpi).path
    if fmt == "csv":
        sys.stdout.write(csv_text(doc, robot))
    else:
        output(doc, json, _tables, robot, precision)
    if not doc["reachable"]:
        raise typer.Exit(1)


def csv_text(doc, robot) -> str:
    """One row per value and branch: value, branch, label, the joints, within_limits,
    singular (display units)."""
    import csv
    import io
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([doc["sweep"]["joint"] + "_swept", "branch", "label"]
               + [j.name for j in robot.joints] + ["within_limits", "singular"])
    for p in doc["points"]:
        for s in p["solutions"]:
            w.writerow([repr(p["value"]), s["branch"], s["label"]] + [repr(x) for x in s["q"]]
                       + [str(s["within_limits"]).lower(), str(s["singular"]).lower()])
    return buf.getvalue()


def _end_text(e, num) -> str:
    if e["kind"] == "range":
        return "range end"
    where = f"at {num(e['at'])}"
    return f"meets {e['with']} {where}" if e["kind"] == "meets" else f"leaves reach {where}"


def _tables(doc, robot, precision):
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from .render import console, heading, kv_table, num, vec
    c = console()
    n = lambda x: num(x, precision)  # noqa: E731
    u, sw = doc["units"], doc["sweep"]
    angle = robot.joints[[j.name for j in robot.joints].index(sw["joint"])].revolute
    unit = u["angle"] if angle else ("" if u["length"] == "unitless" else u["length"])
    c.print(heading(doc))
    T = doc["target"]["T"]
    length = "" if u["length"] == "unitless" else f" {u['length']}"
    rows = [("target", f"position {vec([r[3] for r in T[:3]], precision)}{length}"
             + ("" if doc["target"]["orientation_given"] else " (no orientation given)")),
            ("sweep", f"{sw['joint']} from {n(sw['values'][0])} to {n(sw['values'][-1])} "
                      f"{unit}, {sw['steps']} values"),
            ("method", "; ".join(f"{f['family']} ({f['values']} values)"
                                 for f in doc["method"]["families"])),
            ("", doc["method"]["description"])]
    if doc.get("locked"):
        rows.append(("locked", ", ".join(f"{e['joint']} = {n(e['value'])}"
                                         for e in doc["locked"])))
    rows.append(("reachable", "yes" if doc["reachable"] else
                 "no: no branch is within the joint limits at any value"))
    c.print(kv_table(rows))
    t = Table(box=box.SIMPLE_HEAD, title_justify="left",
              title=f"{len(doc['branches'])} branches along {sw['joint']} ({unit})")
    for name, justify in (("#", "right"), ("labels", "left"), ("from", "right"),
                          ("to", "right"), ("within limits", "left"), ("starts", "left"),
                          ("ends", "left")):
        t.add_column(name, justify=justify, overflow="fold")
    for b in doc["branches"]:
        t.add_row(str(b["branch"]), escape("; ".join(b["labels"])), n(b["from"]), n(b["to"]),
                  ", ".join(n(a) if a == z else f"{n(a)}..{n(z)}"
                            for a, z in b["within_limits"]) or "nowhere",
                  _end_text(b["starts"], n), _end_text(b["ends"], n))
    c.print(t)
    best = doc.get("nearest")
    if best is not None:
        c.print(kv_table([("branch", f"{best['branch']} at {sw['joint']} = {n(best['value'])} "
                                     f"({escape(best['label'])})"),
                          ("q", " ".join(n(x) for x in best["q"])),
                          ("change", " ".join(n(x) for x in best["change"]))],
                         title="nearest --near (least change, within the limits)"))
    elif "nearest" in doc:
        c.print("nearest --near: no solution of the sweep is within the joint limits")
    if doc.get("plot"):
        c.print(f"drawing: {escape(doc['plot'])}")
    c.print("every value and joint: --json, or --format csv")


def check_sweep_options(sweep, start, stop, steps, fmt: str, refused: dict) -> None:
    """Refuse --from/--to/--steps without --sweep, values that are not finite numbers, a
    --format that is not jsonl or csv, and the options of ``refused`` (name -> given) that
    --sweep does not take."""
    from .common import check_number
    if sweep is None:
        for name, given in (("--from", start is not None), ("--to", stop is not None),
                            ("--steps", steps is not None)):
            if given:
                raise InputError(f"{name} needs --sweep JOINT")
        return
    for name, given in refused.items():
        if given:
            raise InputError(f"{name} does not go with --sweep")
    for name, v in (("--from", start), ("--to", stop)):
        if v is not None:
            check_number(v, name)
    if fmt not in ("jsonl", "csv"):
        raise InputError(f"--format: {fmt!r} is not jsonl or csv")
