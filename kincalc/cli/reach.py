"""``kincalc reach``: can the robot get there, and if not, why."""

from __future__ import annotations


import typer

from .common import (BaseLinkOpt, BatchOpt, DebugOpt, DegOpt, FormatOpt, InputFormatOpt, JobsOpt,
                     JsonOpt, LockOpt, PrecisionOpt, RobotArg, StructureTolOpt, TipLinkOpt, UnitOpt,
                     display_units, load_robot, output, parse_locks)
from .targets import PoseOptions, with_pose_options


@with_pose_options
def reach(
    robot: RobotArg,
    pose_options: PoseOptions,
    batch: BatchOpt = None,
    fmt: FormatOpt = "jsonl",
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
    debug: DebugOpt = False,
):
    """Reachability: can the robot reach a pose, and if not, why.

    The verdict is one of: reachable; reachable only at a singular
    configuration; blocked by joint limits (which joints, by how much); the
    position is reachable but not the orientation; beyond the outer reach or
    inside the inner void (by how much); outside the workspace otherwise.
    The distance is from the target to the nearest position the tool
    reaches within the limits. Exit status 0 reachable, 1 not.

    ROBOT is a bundled robot's name or a path to a robot YAML file. The pose
    options are those of 'kincalc ik'.
    """
    from ..analysis.reach import reach as _reach
    rob = load_robot(robot, base_link, tip_link, structure_tol)
    units = display_units(rob, deg, unit)
    locks = parse_locks(lock, rob, units)
    if fmt not in ("jsonl", "csv"):
        from ..errors import UsageError
        raise UsageError(f"--format must be jsonl or csv, not {fmt!r}")
    if batch is not None:
        from .batch import run_command
        run_command("reach", rob, units, batch, fmt, jobs,
                    given=pose_options.given(), refused={"--lock": lock},
                    input_format=input_format, json=json)
    target = pose_options.target(rob, units)
    from ..analysis.results import locked_entries
    held = locked_entries(rob, sorted(locks.items()), units)
    if locks:       # the question is asked of the chain the held joints leave
        from ..analysis.redundancy import locked_robot
        rob = locked_robot(rob, locks)
    result = _reach(rob, target, units=units)
    doc = result.to_dict()
    if held:
        doc["locked"] = held
    output(doc, json, _tables, rob, precision)
    if not result.reachable:
        raise typer.Exit(1)


def _tables(doc, robot, precision):
    from .render import console, heading, joint_amount, kv_table, matrix_table, num, vec
    c = console()
    c.print(heading(doc))
    u = doc["units"]
    length = "" if u["length"] == "unitless" else f" {u['length']}"
    rows = []
    if doc["target"]["orientation_given"]:
        c.print(matrix_table(doc["target"]["T"], precision, title="target T (world <- tool)"))
    else:
        rows.append(("target position", vec([r[3] for r in doc["target"]["T"][:3]], precision)
                     + length + "  (no orientation given)"))
    rows += [("reachable", "yes" if doc["reachable"] else "no"),
            ("verdict", doc["verdict"]),
            ("why", doc["reason"]),
            ("solutions", "-" if doc["solutions"] is None else
             f"{doc['solutions']} ({doc['solutions_within_limits']} within the joint limits)"),
            ("distance", "-" if doc["distance"] is None else num(doc["distance"], precision)
             + length),
            ("solver", doc["method"]["family"])]
    if doc.get("locked"):
        rows.append(("locked", ", ".join(f"{e['joint']} = {num(e['value'], precision)}"
                                         for e in doc["locked"])))
    if doc["nearest"] is not None:
        rows.append(("nearest reachable point", vec(doc["nearest"]["position"], precision)))
        rows.append(("  at q", vec(doc["nearest"]["q"], precision)))
    c.print(kv_table(rows))
    if doc["blocked"]:
        rows = []
        for b in doc["blocked"]:
            rows.append((b["branch"], ", ".join(
                f"{v['joint']} {joint_amount(robot, v['joint'], v['by'], doc['units'])} beyond "
                f"its {v['side']} limit {joint_amount(robot, v['joint'], v['limit'], doc['units'])}"
                for v in b["violations"])))
        c.print(kv_table(rows, title="solutions and the limits they violate"))
