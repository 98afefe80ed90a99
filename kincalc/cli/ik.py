"""``kincalc ik``: every inverse-kinematics solution, labelled and checked."""

from __future__ import annotations

from typing import Annotated, Optional, Tuple

import typer

from ..errors import InputError, UsageError
from .common import (BatchOpt, DebugOpt, DegOpt, FileName, FormatOpt, InputFormatOpt, JobsOpt,
                     JsonOpt, PrecisionOpt, RobotArg, UnitOpt, check_numbers, display_units,
                     load_robot, output, output_target)

F3 = Tuple[float, float, float]
F4 = Tuple[float, float, float, float]

XyzOpt = Annotated[Optional[F3], typer.Option("--xyz", metavar="X Y Z", show_default=False,
                                              help="Target position, in the length unit.")]
RpyOpt = Annotated[Optional[F3], typer.Option(
    "--rpy", metavar="R P Y", show_default=False,
    help="Orientation as fixed X-Y-Z angles: R = Rz(Y) Ry(P) Rx(R).")]
ZyzOpt = Annotated[Optional[F3], typer.Option(
    "--euler-zyz", metavar="A B C", show_default=False,
    help="Orientation as ZYZ Euler angles: R = Rz(A) Ry(B) Rz(C).")]
XyzEOpt = Annotated[Optional[F3], typer.Option(
    "--euler-xyz", metavar="A B C", show_default=False,
    help="Orientation as moving X-Y-Z Euler angles: R = Rx(A) Ry(B) Rz(C).")]
QuatOpt = Annotated[Optional[F4], typer.Option(
    "--quat", metavar="W X Y Z", show_default=False,
    help="Orientation as a quaternion (w, x, y, z); normalised.")]
AxisAngleOpt = Annotated[Optional[F4], typer.Option(
    "--axis-angle", metavar="X Y Z ANGLE", show_default=False,
    help="Orientation as a rotation of ANGLE about the axis (X, Y, Z).")]
MatrixOpt = Annotated[Optional[Tuple[float, float, float, float, float, float, float, float,
                                     float]], typer.Option(
    "--matrix", metavar="R11 ... R33", show_default=False,
    help="Orientation as a rotation matrix, 9 numbers row by row.")]
ApproachOpt = Annotated[Optional[F3], typer.Option(
    "--approach", metavar="AX AY AZ", show_default=False,
    help="Only the approach direction (the tool z axis, world frame; normalised), for "
         "five-joint arms that set it but not the roll about it.")]
TcvOpt = Annotated[Optional[Tuple[float, float, float, float, float, float]], typer.Option(
    "--tcv", metavar="W1 ... W6", show_default=False,
    help="Tool configuration vector w = [p; e^(qn/pi) r3]: position, approach vector and "
         "the last joint's angle in one (robots whose last joint rolls the tool).")]
PoseOpt = Annotated[Optional[str], typer.Option(
    "--pose", metavar="FILE", show_default=False, click_type=FileName(),
    help="The whole target pose as a 4x4 matrix in a file ('-' for stdin): 16 numbers, "
         "or JSON (a list of rows, or an object with a 'T' field).")]
FromQOpt = Annotated[Optional[str], typer.Option(
    "--from-q", metavar="'Q1 Q2 ...'", show_default=False,
    help="Target the pose FK gives for these joint values (one quoted argument, "
         "space- or comma-separated).")]
AllBranchesOpt = Annotated[bool, typer.Option(
    "--all-branches", help="Also list the branch combinations that do not reach the target, "
                           "and why.")]
NearOpt = Annotated[Optional[str], typer.Option(
    "--near", metavar="'Q1 Q2 ...'", show_default=False,
    help="The current joints (one quoted argument): solutions are ordered by their change "
         "from them, and the numerical solver starts there.")]
NumericOpt = Annotated[bool, typer.Option(
    "--numeric", help="Find the one solution nearest --near numerically (Levenberg-Marquardt, "
                      "then least change), even when a closed form exists. Robots no closed "
                      "form covers (7 or more joints, ...) are solved this way anyway.")]
PlotOpt = Annotated[Optional[str], typer.Option(
    "--plot", metavar="FILE", show_default=False, click_type=FileName(),
    help="Also draw every solution side by side, each titled with its branch, to FILE "
         "(.png, .svg or .pdf; needs the 'plot' extra). An existing FILE is not replaced "
         "without --force.")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let --plot replace an existing regular file (never a link, a device or "
                    "the robot or --pose file).")]
DpiOpt = Annotated[int, typer.Option("--dpi", metavar="N", min=10, max=1200,
                                     help="Pixels per inch of a PNG --plot.")]
ExplainOpt = Annotated[bool, typer.Option(
    "--explain", help="Print a worked trace per solution: the intermediate quantities.")]


def ik(
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
    all_branches: AllBranchesOpt = False,
    explain: ExplainOpt = False,
    near: NearOpt = None,
    numeric: NumericOpt = False,
    plot: PlotOpt = None,
    dpi: DpiOpt = 100,
    force: ForceOpt = False,
    batch: BatchOpt = None,
    fmt: FormatOpt = "jsonl",
    input_format: InputFormatOpt = "auto",
    jobs: JobsOpt = 1,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    json: JsonOpt = False,
    debug: DebugOpt = False,
):
    """Inverse kinematics: every joint solution that reaches a pose.

    Give the position with --xyz and at most one orientation, or the whole
    pose with --pose or --from-q. Each solution is labelled by its branch
    (shoulder left/right, elbow up/down, wrist flip/no-flip where the
    structure has them; otherwise the +/- choice of each step), checked by FK,
    and flagged for joint limits and singularity. Exit status 1 when no
    solution within the joint limits reaches the target.

    ROBOT is a bundled robot's name or a path to a robot YAML file.
    """
    from ..ik import solve
    plot_to = None
    if plot is not None and batch is None:
        from ..plot import check_output, require_matplotlib
        plot_to = output_target(plot, "--plot", force, robot, [("--pose", pose)])
        check_output(plot_to)
        require_matplotlib("kincalc ik --plot")
    rob = load_robot(robot)
    units = display_units(rob, deg, unit)
    if batch is not None:
        from .batch import run_command
        run_command("ik", rob, units, batch, fmt, jobs,
                    given=[xyz, rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, approach,
                           tcv, pose, from_q],
                    refused={"--all-branches": all_branches, "--explain": explain,
                             "--near": near, "--numeric": numeric, "--plot": plot},
                    input_format=input_format)
    target = build_target(rob, units, xyz=xyz, rpy=rpy, euler_zyz=euler_zyz,
                          euler_xyz=euler_xyz, quat=quat, axis_angle=axis_angle,
                          matrix=matrix, approach=approach, tcv=tcv, pose=pose,
                          from_q=from_q)
    q_near = None
    if near is not None:
        from .common import parse_joints
        q_near = parse_joints(near.replace(",", " ").split(), rob, units, option="--near")
    result = solve(rob, target, all_branches=all_branches, explain=explain, units=units,
                   near=q_near, numeric=numeric)
    doc = result.to_dict()
    if plot_to is not None:
        doc["plot"] = _plot_solutions(rob, result, plot_to, units, dpi)
    output(doc, json, _tables, rob, precision, explain)
    if not result.reachable:
        raise typer.Exit(1)


def _plot_solutions(robot, result, target, units, dpi):
    """Draw every solution of ``result`` to ``target`` (a :class:`kincalc.outputs.Target`),
    titled by number and branch; returns its path, or None (with a note on stderr) when
    there is nothing to draw."""
    import sys

    import numpy as np

    from ..plot import config_title, draw_arms
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


def build_target(robot, units, *, xyz=None, rpy=None, euler_zyz=None, euler_xyz=None,
                 quat=None, axis_angle=None, matrix=None, approach=None, tcv=None, pose=None,
                 from_q=None, T=None, q=None):
    """A :class:`~kincalc.ik.Target` from the pose options (user units -> SI).

    ``T`` (a 4x4 matrix, or 16 or 12 numbers) and ``q`` (joint values) are the
    batch-record forms of ``--pose`` and ``--from-q``."""
    import numpy as np

    from .. import spatial as sp
    from ..ik import Target
    orient = {"--rpy": rpy, "--euler-zyz": euler_zyz, "--euler-xyz": euler_xyz,
              "--quat": quat, "--axis-angle": axis_angle, "--matrix": matrix,
              "--approach": approach, "--tcv": tcv}
    given = [k for k, v in orient.items() if v is not None]
    whole = [k for k, v in (("--pose", pose), ("--from-q", from_q), ("T", T), ("q", q))
             if v is not None]
    for name, v in [("--xyz", xyz), *orient.items(), ("T", T)]:
        if v is not None:
            check_numbers(np.asarray(v, float).ravel(), name)
    if len(given) > 1:
        raise UsageError(f"give at most one orientation, not {' and '.join(given)}")
    if whole and (given or xyz is not None):
        raise UsageError(f"{whole[0]} gives the whole pose; do not combine it with "
                         f"{(given + (['--xyz'] if xyz is not None else []))[0]}")
    if len(whole) > 1:
        raise UsageError(f"give either {whole[0]} or {whole[1]}, not both")
    A = 1.0 / units.a   # rad per display angle unit
    Lf = 1.0 / units.l  # m per display length unit
    if from_q is not None or q is not None:
        from .common import parse_joints
        tokens = from_q.replace(",", " ").split() if from_q is not None else [str(x) for x in q]
        qv = parse_joints(tokens, robot, units, option="--from-q" if q is None else "q")
        return Target(robot.fk(qv), orientation=True)
    if pose is not None or T is not None:
        M = _read_pose(pose) if pose is not None else _check_pose(np.array(T, float), "T")
        M = M.copy()
        M[:3, 3] *= Lf
        return Target(M, orientation=True)
    if tcv is not None:
        if xyz is not None:
            raise UsageError("--tcv holds the position; do not give --xyz as well")
        from ..spatial import transform_from_tcv
        w = np.array(tcv, float)
        if np.linalg.norm(w[3:]) < 1e-300:
            raise InputError("--tcv: the approach part w4..w6 must not be zero")
        p, approach, qn = transform_from_tcv(w)
        T = np.eye(4)
        T[:3, 3] = p * Lf
        return Target(T, orientation=False, tcv=(approach, float(qn)))
    if xyz is None:
        raise UsageError("give the target position with --xyz X Y Z (or the whole pose with "
                         "--pose or --from-q)")
    T = np.eye(4)
    T[:3, 3] = np.array(xyz, float) * Lf
    if not given:
        return Target(T, orientation=False)
    if approach is not None:
        a = np.array(approach, float)
        if np.linalg.norm(a) < 1e-12:
            raise InputError("--approach must not be the zero vector")
        return Target(T, orientation=False, approach=a / np.linalg.norm(a))
    if rpy is not None:
        R = sp.matrix_from_rpy(np.array(rpy) * A)
    elif euler_zyz is not None:
        R = sp.matrix_from_euler_zyz(np.array(euler_zyz) * A)
    elif euler_xyz is not None:
        R = sp.matrix_from_euler_xyz(np.array(euler_xyz) * A)
    elif quat is not None:
        if np.linalg.norm(quat) < 1e-12:
            raise InputError("--quat must not be the zero quaternion")
        R = sp.matrix_from_quaternion(np.array(quat))
    elif axis_angle is not None:
        if np.linalg.norm(axis_angle[:3]) < 1e-12:
            raise InputError("--axis-angle needs a non-zero axis")
        R = sp.matrix_from_axis_angle(np.array(axis_angle[:3]), axis_angle[3] * A)
    else:
        R = np.array(matrix, float).reshape(3, 3)
        _check_rotation(R, "--matrix")
    T[:3, :3] = R
    return Target(T, orientation=True)


def _check_rotation(R, what):
    import numpy as np
    if not np.allclose(R @ R.T, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0:
        raise InputError(f"{what} is not a rotation matrix (rows must be orthonormal with "
                         "determinant +1, to 6 digits)")


def _read_pose(src: str):
    import json as _json

    import numpy as np

    from ..limits import TooLarge, os_error_text, read_bounded, size_text
    what = f"--pose {src}"
    try:
        raw = read_bounded(src)
    except TooLarge as exc:
        raise InputError(f"{what}: larger than {size_text(exc.limit)}, kincalc's limit for "
                         "a pose file (a 4x4 matrix is a few hundred bytes)") from None
    except OSError as exc:
        raise InputError(f"{what}: cannot read ({os_error_text(exc)})") from None
    except ValueError:
        raise InputError(f"{what}: cannot read (not a valid file name)") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{what}: not UTF-8 text; expected 16 numbers or JSON rows of a "
                         "4x4 matrix") from None
    try:
        data = _json.loads(text)
        if isinstance(data, dict):
            data = data.get("T", data.get("target", {}).get("T") if isinstance(
                data.get("target"), dict) else None)
        M = np.array(data, dtype=float)
    except (ValueError, TypeError, RecursionError):
        try:
            M = np.array(text.replace(",", " ").replace("[", " ").replace("]", " ").split(),
                         dtype=float)
        except ValueError:
            raise InputError(f"{what}: expected 16 numbers or JSON rows of a 4x4 matrix")\
                from None
    return _check_pose(M, what)


def _check_pose(M, what):
    """``M`` (16 or 12 numbers, or a 4x4 matrix) as a 4x4 pose, re-orthonormalised."""
    import numpy as np
    if M.size == 12:
        M = np.vstack([M.reshape(3, 4), [0, 0, 0, 1]])
    if M.size != 16:
        raise InputError(f"{what}: expected a 4x4 matrix (16 finite numbers), got {M.size}")
    check_numbers(M.ravel(), what)
    M = M.reshape(4, 4)
    if not np.allclose(M[3], [0, 0, 0, 1]):
        raise InputError(f"{what}: the last row must be 0 0 0 1")
    _check_rotation(M[:3, :3], what)
    u, _, vt = np.linalg.svd(M[:3, :3])
    M[:3, :3] = u @ vt
    return M


def _tables(doc, robot, precision, explain):
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from .render import console, heading, kv_table, matrix_table, num
    c = console()
    c.print(heading(doc))
    u = doc["units"]
    if doc["target"]["orientation_given"]:
        c.print(matrix_table(doc["target"]["T"], precision, title="target T (world <- tool)"))
    else:
        from .render import vec
        length = "" if u["length"] == "unitless" else f" {u['length']}"
        what = ("approach " + vec(doc["target"]["approach"], precision)
                if "approach" in doc["target"] else "no orientation given")
        c.print(f"target position: {vec([r[3] for r in doc['target']['T'][:3]], precision)}"
                f"{length}  ({what})")
    m = doc["method"]
    c.print(kv_table([("method", f"{m['family']}: {m['description']}"),
                      ("controls", m["controls"]),
                      ("reachable", "yes" if doc["reachable"] else "no"),
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
                    f"{v['joint']} by {num(v['by'], 2)} ({v['side']})" for v in s["violations"])
            if s.get("change_from_near") is not None:
                text += "; change from --near: " + " ".join(
                    num(v, 2) for v in s["change_from_near"])
            if s["singular"] and s["singularity"]:
                text += f"; {s['singularity']}" + (f"; {s['continuum']}" if s.get("continuum") else "")
            rows.append((str(k), text))
        c.print(kv_table(rows, title="branches"))
    if doc.get("rejected_note"):
        c.print(escape(f"rejected combinations: {doc['rejected_note']}"))
    if "rejected" in doc and doc["rejected"]:
        rt = Table(box=box.SIMPLE_HEAD, title=f"{len(doc['rejected'])} rejected branch "
                   "combinations", title_justify="left")
        rt.add_column("#", justify="right")
        for j in robot.joints:
            rt.add_column(j.name, justify="right")
        rt.add_column("why")
        for k, r in enumerate(doc["rejected"], start=1):
            rt.add_row(str(k), *(num(v, precision) for v in r["q"]), escape(r["reason"]))
        c.print(rt)
    if doc.get("dead_ends"):
        c.print(kv_table([(str(k), escape(t)) for k, t in enumerate(doc["dead_ends"], start=1)],
                         title="branches with no real solution"))
    if doc.get("plot"):
        c.print(f"drawing: {escape(doc['plot'])}")
    if explain:
        for k, s in enumerate(doc["solutions"], start=1):
            if s.get("trace"):
                c.print(kv_table([(escape(str(e["step"])), escape(_fmt(e["value"], precision)))
                                  for e in s["trace"]], title=f"solution {k}: {s['branch']}"))


def _fmt(v, precision):
    from .render import num
    if isinstance(v, list):
        if v and isinstance(v[0], list):
            return "; ".join(" ".join(num(x, precision) for x in row) for row in v)
        return " ".join(num(x, precision) for x in v)
    if isinstance(v, float):
        return num(v, precision)
    return str(v)
