"""The redundant-arm options of ``kincalc ik``: ``--sweep JOINT`` (every branch along a
held joint's values, as tables, JSON, CSV and a drawing), ``--swivel`` (every branch of
an arm with a spherical shoulder and wrist at a swivel angle) and ``--swivel-range``
(the swivel angles where each branch is within its limits)."""

from __future__ import annotations

import sys
from dataclasses import replace
from typing import Annotated, NamedTuple, Optional

import typer

from ..errors import InputError
from .common import NUMBER, Integer

SweepOpt = Annotated[Optional[str], typer.Option(
    "--sweep", metavar="JOINT", show_default=False,
    help="Redundant arms: hold JOINT (a name or number) at each of --steps values from "
         "--from to --to and solve the other joints with every branch, joined into "
         "continuous branches along the values; reports where each branch is within the "
         "limits and where branches meet or leave the reach. --plot draws each joint "
         "against the swept value; --format csv gives every value.")]
FromOpt = Annotated[Optional[float], typer.Option(
    "--from", metavar="VALUE", click_type=NUMBER, show_default=False,
    help="First value of --sweep, in the angle or length unit (default: the joint's lower "
         "limit).")]
ToOpt = Annotated[Optional[float], typer.Option(
    "--to", metavar="VALUE", click_type=NUMBER, show_default=False,
    help="Last value of --sweep (default: the joint's upper limit).")]
StepsOpt = Annotated[Optional[int], typer.Option(
    "--steps", metavar="N", click_type=Integer(2, 20000), show_default=False,
    help="Number of values of --sweep, evenly spaced, ends included (default 181). The first "
         "and the last joint are swept in one batch; any other joint costs a few "
         "milliseconds per value.")]
SwivelOpt = Annotated[Optional[float], typer.Option(
    "--swivel", metavar="ANGLE", click_type=NUMBER, show_default=False,
    help="Arms with a spherical shoulder and wrist (7 joints, axes 1-3 and 5-7 each through "
         "one point): every branch at this swivel angle of the elbow about the "
         "shoulder-wrist line (the stereographic SEW angle of Elias & Wen 2023), in the "
         "angle unit. Needs the whole pose.")]
SwivelRangeOpt = Annotated[Optional[bool], typer.Option(
    "--swivel-range", show_default=False,
    help="Arms with a spherical shoulder and wrist: for each branch, the intervals of the "
         "swivel angle in which every joint is within its limits, and the joint whose limit "
         "ends each interval.")]

#: the options, in --help order: (parameter name, its typer annotation)
REDUNDANCY_OPTIONS = (("sweep", SweepOpt), ("start", FromOpt), ("stop", ToOpt),
                      ("steps", StepsOpt), ("swivel", SwivelOpt),
                      ("swivel_range", SwivelRangeOpt))


class RedundancyOptions(NamedTuple):
    """The redundant-arm options of one command line, as given (user units; None when
    absent)."""

    sweep: str | None = None
    start: float | None = None
    stop: float | None = None
    steps: int | None = None
    swivel: float | None = None
    swivel_range: bool | None = None

    def given(self) -> dict:
        """``{option: given}`` of the options that answer on their own (refused by
        --batch)."""
        return {"--sweep": self.sweep, "--swivel": self.swivel,
                "--swivel-range": self.swivel_range}

    @property
    def answers(self) -> bool:
        """A sweep or a swivel range replaces the ik answer."""
        return self.sweep is not None or bool(self.swivel_range)

    def check(self, fmt: str, refused: dict, json: bool = False) -> None:
        """Refuse what does not go together, before any work: --from/--to/--steps without
        --sweep, values that are not finite numbers, a --format that is not jsonl or csv,
        and the options of ``refused`` (name -> given) next to --sweep, --swivel or
        --swivel-range (--lock only with --sweep)."""
        from .common import check_number
        if self.sweep is None:
            for name, given in (("--from", self.start is not None),
                                ("--to", self.stop is not None),
                                ("--steps", self.steps is not None)):
                if given:
                    raise InputError(f"{name} needs --sweep JOINT")
        mine = [(name, v) for name, v in self.given().items() if v]
        if len(mine) > 1:
            raise InputError(f"{mine[0][0]} and {mine[1][0]} do not go together")
        for name, given in refused.items():
            if mine and given and not (name == "--lock" and self.sweep is not None):
                raise InputError(f"{name} does not go with {mine[0][0]}")
        for name, v in (("--from", self.start), ("--to", self.stop), ("--swivel", self.swivel)):
            if v is not None:
                check_number(v, name)
        if self.start is not None and self.start == self.stop:
            raise InputError("--from and --to are the same value: nothing to sweep")
        if fmt not in ("jsonl", "csv"):
            raise InputError(f"--format: {fmt!r} is not jsonl or csv")
        if fmt == "csv" and json and self.sweep is not None:
            raise InputError("--json and --format csv do not go together")

    def target(self, target, units):
        """``target`` at the --swivel angle (SI), or as it is."""
        if self.swivel is None:
            return target
        if not target.orientation:
            raise InputError("--swivel needs the whole pose: give an orientation (--rpy, "
                             "--quat, ...), --pose or --from-q")
        return replace(target, swivel=self.swivel / units.a)

    @staticmethod
    def check_swivel(robot, target, option: str) -> None:
        """Refuse a pose at which the swivel angle is undefined."""
        from ..ik.swivel import undefined_at
        why = undefined_at(robot, target.T)
        if why is not None:
            raise InputError(f"{option}: the swivel angle is undefined at this pose: {why}; "
                             "hold a joint instead (--lock, --sweep)")

    def run(self, robot, target, units, locks, **how) -> None:
        """Answer --sweep or --swivel-range (``how``: near, plot_to, dpi, fmt, json,
        precision); exit status 1 when nothing is within the limits."""
        if self.sweep is not None:
            return run_sweep(robot, target, units, self.sweep, self.start, self.stop,
                             self.steps, locks, **how)
        return run_swivel_range(robot, target, units, **how)


def with_redundancy_options(command):
    """A typer command whose ``redundancy: RedundancyOptions`` parameter stands for
    :data:`REDUNDANCY_OPTIONS` (see :func:`kincalc.cli.targets.option_group`)."""
    from .targets import option_group
    return option_group(command, "redundancy", REDUNDANCY_OPTIONS, RedundancyOptions)


def run_sweep(robot, target, units, joint: str, start, stop, steps, locks, *, near=None,
              plot_to=None, dpi=100, fmt="jsonl", json=False, precision=4) -> None:
    """Sweep ``joint`` (a name or number) over ``[start, stop]`` (user units, default its
    limits) in ``steps`` values (None: the default), the joints ``locks`` (SI) held; print
    the answer as ``json``, CSV (``fmt``) or tables, draw it to ``plot_to``. Exit status 1
    when no branch is within the limits at any value."""
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

    from .batch.formats import csv_cell       # (names from the robot file: no formula)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([csv_cell(doc["sweep"]["joint"] + "_swept"), "branch", "label"]
               + [csv_cell(j.name) for j in robot.joints] + ["within_limits", "singular"])
    for p in doc["points"]:
        for s in p["solutions"]:
            w.writerow([repr(p["value"]), csv_cell(s["branch"]), csv_cell(s["label"])]
                       + [repr(x) for x in s["q"]]
                       + [str(s["within_limits"]).lower(), str(s["singular"]).lower()])
    return buf.getvalue()


def _end_text(e, num) -> str:
    if e["kind"] == "range":
        return "range end"
    where = f"at {num(e['at'])}"
    return f"meets {e['with']} {where}" if e["kind"] == "meets" else f"leaves reach {where}"


def _tables(doc, robot, precision):
    from rich import box
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
                 "no: no branch is within the joint limits at any value" if doc["branches"]
                 else "no: the pose is out of reach at every value"))
    c.print(kv_table(rows))
    t = Table(box=box.SIMPLE_HEAD, title_justify="left",
              title=f"{len(doc['branches'])} branches along {sw['joint']} ({unit})")
    for name, justify in (("#", "right"), ("labels", "left"), ("from", "right"),
                          ("to", "right"), ("within limits", "left"), ("starts", "left"),
                          ("ends", "left")):
        t.add_column(name, justify=justify, overflow="fold")
    for b in doc["branches"]:
        t.add_row(str(b["branch"]), "; ".join(b["labels"]), n(b["from"]), n(b["to"]),
                  ", ".join(n(a) if a == z else f"{n(a)}..{n(z)}"
                            for a, z in b["within_limits"]) or "nowhere",
                  _end_text(b["starts"], n), _end_text(b["ends"], n))
    c.print(t)
    best = doc.get("nearest")
    if best is not None:
        c.print(kv_table([("branch", f"{best['branch']} at {sw['joint']} = {n(best['value'])} "
                                     f"({best['label']})"),
                          ("q", " ".join(n(x) for x in best["q"])),
                          ("change", " ".join(n(x) for x in best["change"]))],
                         title="nearest --near (least change, within the limits)"))
    elif "nearest" in doc:
        c.print("nearest --near: no solution of the sweep is within the joint limits")
    if doc.get("plot"):
        c.print(f"drawing: {doc['plot']}")
    c.print("every value and joint: --json, or --format csv")


def run_swivel_range(robot, target, units, *, near=None, plot_to=None, dpi=100, fmt="jsonl",
                     json=False, precision=4) -> None:
    """Print the feasible swivel intervals of every branch (``kincalc ik --swivel-range``);
    exit status 1 when no branch is feasible at any angle."""
    from ..analysis.swivel import swivel_document, swivel_ranges
    from .common import output
    for name, given in (("--plot", plot_to is not None), ("--format csv", fmt == "csv")):
        if given:
            raise InputError(f"{name} does not go with --swivel-range")
    if not target.orientation:
        raise InputError("--swivel-range needs the whole pose: give an orientation (--rpy, "
                         "--quat, ...), --pose or --from-q")
    RedundancyOptions.check_swivel(robot, target, "--swivel-range")
    doc = swivel_document(robot, target, swivel_ranges(robot, target.T), units, near=near)
    output(doc, json, _swivel_tables, robot, precision)
    if not doc["reachable"]:
        raise typer.Exit(1)


def _swivel_tables(doc, robot, precision):
    from .render import console, heading, kv_table, num
    c = console()
    c.print(heading(doc))
    u = doc["units"]["angle"]
    c.print(kv_table([("method", doc["method"]["description"]),
                      ("reachable", "yes" if doc["reachable"] else
                       "no: no branch is within the joint limits at any swivel angle")]))
    limit = lambda b: "" if b is None else f"{b['joint']} {b['side']}"  # noqa: E731
    rows = []
    for b in doc["branches"]:
        if b["whole_circle"]:
            text = "every angle"
        elif not b["intervals"]:
            text = "none"
        else:
            text = ", ".join(f"{num(i['from'], precision)} .. {num(i['to'], precision)}"
                             + (" through 180" if i["through_180"] else "")
                             + (f" ({limit(i['from_limit'])} / {limit(i['to_limit'])})"
                                if i["from_limit"] or i["to_limit"] else "")
                             for i in b["intervals"])
        rows.append((b["branch"], text))
    c.print(kv_table(rows, title=f"swivel angles within the limits ({u}; the joint limits "
                                 "that end each interval)"))
    best = doc.get("nearest")
    if best is not None:
        c.print(kv_table([("branch", f"{best['branch']} at {num(best['swivel'], precision)}"),
                          ("q", " ".join(num(x, precision) for x in best["q"])),
                          ("change", " ".join(num(x, precision) for x in best["change"]))],
                         title="nearest --near (least change, within the limits)"))
    elif "nearest" in doc:
        c.print("nearest --near: no branch is within the joint limits at any swivel angle")
