"""``kincalc ik``: every inverse-kinematics solution, labelled and checked."""

from __future__ import annotations

from typing import Annotated, Optional

import typer

from .common import (BaseLinkOpt, BatchOpt, DebugOpt, DegOpt, DpiOpt, FileName, InputFormatOpt,
                     JobsOpt, JsonOpt, LockOpt, PrecisionOpt, RobotArg, StructureTolOpt,
                     TipLinkOpt, UnitOpt, Words, display_units, load_robot, output,
                     output_target, parse_locks)
from .redundant import RedundancyOptions, with_redundancy_options
from .targets import PoseOptions, with_pose_options

AllBranchesOpt = Annotated[bool, typer.Option(
    "--all-branches", help="Also list the branch combinations that do not reach the target, "
                           "and why.")]
NearOpt = Annotated[Optional[str], typer.Option(
    "--near", metavar="'Q1 Q2 ...'", show_default=False,
    help="The current joints (one quoted argument, or the numbers as words after it): "
         "solutions are ordered by their change "
         "from them, and the numerical solver starts there; with --sweep, the value and "
         "branch nearest them.")]
NumericOpt = Annotated[bool, typer.Option(
    "--numeric", help="Find the one solution nearest --near numerically (Levenberg-Marquardt, "
                      "then least change), even when a closed form exists. Robots no closed "
                      "form covers (7 or more joints, ...) are solved this way anyway.")]
PlotOpt = Annotated[Optional[str], typer.Option(
    "--plot", metavar="FILE", show_default=False, click_type=FileName(),
    help="Also draw every solution side by side, each titled with its branch, to FILE "
         "(.png, .svg or .pdf; needs the 'plot' extra); with --sweep, each joint against "
         "the swept value. An existing FILE is not replaced without --force.")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let --plot replace an existing regular file (never a link, a device or "
                    "the robot or --pose file).")]
SweepFormatOpt = Annotated[str, typer.Option(
    "--format", metavar="jsonl|csv", click_type=Words(("jsonl", "csv")),
    help="Output format of --batch; with --sweep, csv prints one row per value and branch "
         "instead of the tables.")]
ExplainOpt = Annotated[bool, typer.Option(
    "--explain", help="Print each solution's steps in the textbook's equations, with the "
                       "numbers put in.")]


@with_pose_options
@with_redundancy_options
def ik(
    robot: RobotArg,
    pose_options: PoseOptions,
    all_branches: AllBranchesOpt = False,
    explain: ExplainOpt = False,
    near: NearOpt = None,
    numeric: NumericOpt = False,
    plot: PlotOpt = None,
    dpi: DpiOpt = 100,
    force: ForceOpt = False,
    batch: BatchOpt = None,
    fmt: SweepFormatOpt = "jsonl",
    input_format: InputFormatOpt = "auto",
    jobs: JobsOpt = 1,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    structure_tol: StructureTolOpt = None,
    lock: LockOpt = None,
    redundancy: RedundancyOptions = None,
    debug: DebugOpt = False,
):
    """Inverse kinematics: every joint solution that reaches a pose.

    Give the position with --xyz and at most one orientation, or the whole
    pose with --pose or --from-q. Each solution is labelled by its branch
    (shoulder left/right or front/back, elbow up/down, wrist flip/no-flip where the
    structure has them; otherwise the +/- choice of each step), checked by FK,
    and flagged for joint limits and singularity. Exit status 1 when no
    solution within the joint limits reaches the target.

    ROBOT is a bundled robot's name or a path to a robot YAML file.
    """
    from ..ik import solve
    redundancy.check(fmt, {"--all-branches": all_branches, "--explain": explain,
                           "--numeric": numeric, "--batch": batch is not None,
                           "--lock": bool(lock), "--tcv": pose_options.tcv is not None,
                           "--approach": pose_options.approach is not None}, json)
    plot_to = None if plot is None or batch is not None else \
        _plot_target(plot, force, robot, pose_options.pose)
    rob = load_robot(robot, base_link, tip_link, structure_tol)
    units = display_units(rob, deg, unit)
    if batch is not None:
        from .batch import run_command
        run_command("ik", rob, units, batch, fmt, jobs,
                    given=pose_options.given(),
                    refused={"--all-branches": all_branches, "--explain": explain,
                             "--near": near, "--numeric": numeric, "--plot": plot,
                             **redundancy.given()},
                    input_format=input_format, locks=parse_locks(lock, rob, units), json=json)
    target = redundancy.target(pose_options.target(rob, units), units)
    if target.swivel is not None:
        redundancy.check_swivel(rob, target, "--swivel")
    q_near = None
    if near is not None:
        from .common import parse_joints, value_tokens
        q_near = parse_joints(value_tokens(near, "--near"), rob, units, option="--near")
    options = dict(all_branches=all_branches, explain=explain, units=units, near=q_near,
                   numeric=numeric)
    locks = parse_locks(lock, rob, units)
    if redundancy.answers:
        return redundancy.run(rob, target, units, locks, near=q_near, plot_to=plot_to,
                              dpi=dpi, fmt=fmt, json=json, precision=precision)
    if locks:
        from ..analysis.redundancy import solve_locked
        result = solve_locked(rob, target, locks, **options)
    else:
        result = solve(rob, target, **options)
    from ..analysis.results import ik_document
    doc = ik_document(result)
    if plot_to is not None:
        doc["plot"] = _plot_solutions(rob, result, plot_to, units, dpi)
    output(doc, json, _tables, rob, precision, explain)
    if not result.reachable:
        raise typer.Exit(1)


def _plot_target(plot: str, force: bool, robot: str, pose: str | None):
    """The checked output target of ``--plot`` (before any work: a file that may not be
    written, or a missing matplotlib, is said at once)."""
    from ..analysis.plot import check_output, require_matplotlib
    target = output_target(plot, "--plot", force, robot, [("--pose", pose)])
    check_output(target)
    require_matplotlib("kincalc ik --plot")
    return target


def _plot_solutions(robot, result, target, units, dpi):
    """Draw every solution of ``result`` to ``target`` (a :class:`kincalc.outputs.Target`),
    titled by number and branch; returns its path, or None (with a note on stderr) when
    there is nothing to draw."""
    import sys

    import numpy as np

    from ..analysis.plot import config_title, draw_arms
    sols = result.solutions
    if not sols:
        sys.stderr.write(f"kincalc: no solution to draw; {target.shown} not written\n")
        return None
    titles = [f"{k}. {s.branch}" + ("" if s.within_limits else " (out of limits)")
              + "\n" + config_title(robot, s.q, units) for k, s in enumerate(sols, start=1)]
    p = result.target.T[:3, 3] * units.l
    length = "" if units.length == "unitless" else f" {units.length}"
    draw_arms(robot, np.array([s.q for s in sols]), titles, target, units=units, dpi=dpi,
              suptitle=f"{robot.name}: {len(sols)} IK solution{'s' if len(sols) != 1 else ''} "
                       f"for p = ({', '.join(f'{x:.4g}' for x in p)}){length}")
    return str(target.path)


def _target_position(t: dict, u: dict, precision: int) -> str:
    """The line of a target without a whole pose: its position and what else it gives (an
    approach, a tool configuration vector, or nothing)."""
    from .render import num, vec
    length = "" if u["length"] == "unitless" else f" {u['length']}"
    what = ("approach " + vec(t["approach"], precision) if "approach" in t else
            f"tool configuration vector: w4..w6 {vec(t['tcv'][3:], precision)}, the last "
            f"joint {num(t['roll'], precision)} {u['angle']}" if "tcv" in t else
            "no orientation given")
    return f"target position: {vec([r[3] for r in t['T'][:3]], precision)}{length}  ({what})"


def _tables(doc, robot, precision, explain):
    from rich import box
    from rich.table import Table

    from .render import console, heading, joint_amount, kv_table, matrix_table, num
    c = console()
    c.print(heading(doc))
    u = doc["units"]
    if doc["target"]["orientation_given"]:
        c.print(matrix_table(doc["target"]["T"], precision, title="target T (world <- tool)"))
    else:
        c.print(_target_position(doc["target"], u, precision))
    m = doc["method"]
    rows = [("method", f"{m['family']}: {m['description']}"), ("controls", m["controls"])]
    if doc.get("locked"):
        rows.append(("locked", ", ".join(f"{e['joint']} = {num(e['value'], precision)}"
                                         for e in doc["locked"])
                     + " (the other joints solved with every branch)"))
    c.print(kv_table(rows + [("reachable", "yes" if doc["reachable"] else "no"),
                             ("", doc["reason"])]))
    n = doc["count"]
    if n:
        t = Table(box=box.SIMPLE_HEAD, title=f"{n} solution{'s' if n != 1 else ''} ({u['angle']}"
                  + ("" if u["length"] == "unitless" else f", {u['length']}") + ")",
                  title_justify="left")
        t.add_column("#", justify="right")
        for j in robot.joints:
            t.add_column(j.name, justify="right", min_width=precision + 5, overflow="fold")
        t.add_column("limits")
        t.add_column("singular")
        for k, s in enumerate(doc["solutions"], start=1):
            t.add_row(str(k), *(num(v, precision) for v in s["q"]),
                      "ok" if s["within_limits"] else "out", "yes" if s["singular"] else "no")
        c.print(t)
        rows = []
        for k, s in enumerate(doc["solutions"], start=1):
            res = s["residual"]
            text = s["branch"] + f"; residual {res['position']:.1e}" + (
                "" if res["orientation"] is None else f" / {res['orientation']:.1e}")
            if s["violations"]:
                text += "; out of limits: " + ", ".join(
                    f"{v['joint']} by {joint_amount(robot, v['joint'], v['by'], u)} ({v['side']})"
                    for v in s["violations"])
            if s.get("change_from_near") is not None:
                text += "; change from --near: " + " ".join(
                    num(v, 2) for v in s["change_from_near"])
            if s["singular"] and s["singularity"]:
                text += f"; {s['singularity']}" + (f"; {s['continuum']}" if s.get("continuum") else "")
            rows.append((str(k), text))
        c.print(kv_table(rows, title="branches"))
    if doc.get("rejected_note"):
        c.print(f"rejected combinations: {doc['rejected_note']}")
    if "rejected" in doc and doc["rejected"]:
        rt = Table(box=box.SIMPLE_HEAD, title=f"{len(doc['rejected'])} rejected branch "
                   "combinations", title_justify="left")
        rt.add_column("#", justify="right")
        for j in robot.joints:
            rt.add_column(j.name, justify="right")
        rt.add_column("why")
        for k, r in enumerate(doc["rejected"], start=1):
            rt.add_row(str(k), *(num(v, precision) for v in r["q"]), r["reason"])
        c.print(rt)
    if doc.get("dead_ends"):
        c.print(kv_table([(str(k), t) for k, t in enumerate(doc["dead_ends"], start=1)],
                         title="branches with no real solution"))
    if doc.get("plot"):
        c.print(f"drawing: {doc['plot']}")
    if explain:
        for k, s in enumerate(doc["solutions"], start=1):
            if s.get("trace"):
                c.print(kv_table([(e["step"], e["text"]) for e in s["trace"]],
                                 title=f"solution {k}: {s['branch']}"))
