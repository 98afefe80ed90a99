"""``kincalc reach``: can the robot get there, and if not, why."""

from __future__ import annotations


import typer

from .common import (BatchOpt, DebugOpt, DegOpt, FormatOpt, JsonOpt, PrecisionOpt, RobotArg,
                     UnitOpt, display_units, load_robot, output)
from .ik import (ApproachOpt, AxisAngleOpt, FromQOpt, MatrixOpt, PoseOpt, QuatOpt, RpyOpt,
                 TcvOpt, XyzEOpt, XyzOpt, ZyzOpt, build_target)

#: the per-pose fields of a --batch record, in CSV column order
BATCH_FIELDS = ["index", "reachable", "verdict", "distance", "solutions",
                "solutions_within_limits", "reason", "error"]


def reach(
    robot: RobotArg,
    xyz: XyzOpt = None,
    rpy: RpyOpt = None,
    euler_zyz: ZyzOpt = None,
    euler_xyz: XyzEOpt = None,
    quat: QuatOpt = None,
    axis_angle: AxisAngleOpt = None,
    matrix: MatrixOpt = None,
    approach: ApproachOpt = None,
    tcv: TcvOpt = None,
    pose: PoseOpt = None,
    from_q: FromQOpt = None,
    batch: BatchOpt = None,
    fmt: FormatOpt = "jsonl",
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
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
    from ..reach import reach as _reach
    rob = load_robot(robot)
    units = display_units(rob, deg, unit)
    if fmt not in ("jsonl", "csv"):
        from ..errors import UsageError
        raise UsageError(f"--format must be jsonl or csv, not {fmt!r}")
    pose_given = [xyz, rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, approach, tcv,
                  pose, from_q]
    if batch is not None:
        if any(v is not None for v in pose_given):
            from ..errors import UsageError
            raise UsageError("--batch reads the poses from a file; do not give pose options too")
        raise typer.Exit(_run_batch(rob, units, batch, fmt))
    target = build_target(rob, units, xyz=xyz, rpy=rpy, euler_zyz=euler_zyz,
                          euler_xyz=euler_xyz, quat=quat, axis_angle=axis_angle,
                          matrix=matrix, approach=approach, tcv=tcv, pose=pose, from_q=from_q)
    result = _reach(rob, target, units=units)
    output(result.to_dict(), json, _tables, rob, precision)
    if not result.reachable:
        raise typer.Exit(1)


def _run_batch(robot, units, src, fmt) -> int:
    """Answer each record of ``src``; return the exit status (2 if any record was bad,
    1 if any pose was unreachable, else 0)."""
    from ..errors import KincalcError
    from ..reach import reach as _reach
    from ..results import _clean
    from .batch import Writer, records
    out = Writer(fmt, BATCH_FIELDS)
    bad = no = False
    for index, kw, error in records(src, robot):
        ident = {} if kw is None or "id" not in kw else {"id": kw.pop("id")}
        if error is None:
            try:
                result = _reach(robot, build_target(robot, units, **kw), units=units)
            except KincalcError as exc:
                error = f"record {index + 1}: {exc}"
        if error is not None:
            bad = True
            out.write({"index": index, **ident, "error": error})
            continue
        no |= not result.reachable
        out.write({"index": index, **ident, "reachable": result.reachable,
                   "verdict": result.verdict,
                   "distance": None if result.distance is None else
                   _clean(result.distance * units.l),
                   "solutions": result.solutions,
                   "solutions_within_limits": result.within_limits,
                   "reason": result.reason})
    return 2 if bad else 1 if no else 0


def _tables(doc, robot, precision):
    from rich.markup import escape

    from .render import console, heading, kv_table, matrix_table, num, vec
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
            ("why", escape(doc["reason"])),
            ("solutions", "-" if doc["solutions"] is None else
             f"{doc['solutions']} ({doc['solutions_within_limits']} within the joint limits)"),
            ("distance", "-" if doc["distance"] is None else num(doc["distance"], precision)
             + length),
            ("solver", doc["method"]["family"])]
    if doc["nearest"] is not None:
        rows.append(("nearest reachable point", vec(doc["nearest"]["position"], precision)))
        rows.append(("  at q", vec(doc["nearest"]["q"], precision)))
    c.print(kv_table(rows))
    if doc["blocked"]:
        rows = []
        for b in doc["blocked"]:
            rows.append((escape(b["branch"]), escape(", ".join(
                f"{v['joint']} {num(v['by'], 2)} beyond its {v['side']} limit "
                f"{num(v['limit'], 2)}" for v in b["violations"]))))
        c.print(kv_table(rows, title="solutions and the limits they violate"))
