"""``kincalc fk``: forward kinematics at one configuration."""

from __future__ import annotations

from typing import Annotated

import typer

from .common import (BaseLinkOpt, BatchOpt, DebugOpt, DegOpt, FormatOpt, InputFormatOpt, JobsOpt,
                     JointsArg, JsonOpt, PrecisionOpt, RobotArg, TipLinkOpt, UnitOpt, display_units,
                     load_robot, output, parse_joints)


def fk(
    robot: RobotArg,
    q: JointsArg = None,
    frames: Annotated[bool, typer.Option(
        "--frames", help="Also print every link transform T_{i-1}^i and every T_0^i.")] = False,
    symbolic: Annotated[bool, typer.Option(
        "--symbolic", help="Print the link transforms T_{i-1}^i and T = base T_0^n tool as "
        "formulas in the joint variables (no Q), simplified, with the abbreviations C1 = "
        "cos theta1, S12 = sin(theta1 + theta2), ...; lengths named as in the robot file's "
        "parameters, base and tool numeric (poe robots: product of exponentials, lengths "
        "numeric). Needs sympy (pip install 'kincalc[symbolic]').")]
        = False,
    latex: Annotated[bool, typer.Option(
        "--latex", help="Print the --symbolic formulas as LaTeX (amsmath bmatrix) with the "
        "legend of abbreviations; implies --symbolic.")] = False,
    numeric_lengths: Annotated[bool, typer.Option(
        "--numeric-lengths", help="With --symbolic or --latex: the robot file's parameter "
        "values in place of their names (then --unit applies).")] = False,
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
    debug: DebugOpt = False,
):
    """Forward kinematics: the tool pose for joint values Q.

    Prints the 4x4 pose T (world <- tool), the position and the orientation
    as rotation matrix, RPY (fixed X-Y-Z), ZYZ Euler, moving X-Y-Z Euler,
    quaternion (w, x, y, z), axis-angle, rotation vector and tool
    configuration vector.

    ROBOT is a bundled robot's name (kincalc robots list) or a path to a robot
    YAML file. Q... are the joint values in order, revolute in the angle unit,
    prismatic in the length unit; negative values need no '--'. Without Q the
    robot's home configuration is used.

    With --symbolic (or --latex) no Q is given: the matrices are derived for
    every q; --deg/--rad and --precision do not apply (constant angles are
    exact multiples of pi, symbols are angles).
    """
    if batch is not None:
        from .batch import run_command
        rob = load_robot(robot, base_link, tip_link)
        run_command("fk", rob, display_units(rob, deg, unit), batch, fmt, jobs, given=[q],
                    refused={"--frames": frames, "--symbolic": symbolic, "--latex": latex,
                             "--numeric-lengths": numeric_lengths},
                    input_format=input_format, json=json)
    if symbolic or latex or numeric_lengths:
        from .symbolic import require_sympy_for, symbolic_check, symbolic_output
        symbolic_check(symbolic, latex, numeric_lengths, q)
        from ..analysis.symbolic import symbolic_fk
        require_sympy_for("fk", symbolic, latex)
        rob = load_robot(robot, base_link, tip_link)
        display_units(rob, deg, unit)
        result = symbolic_fk(rob, numeric_lengths=numeric_lengths, length_unit=unit)
        symbolic_output(result, json, latex)
        return
    from ..analysis.reports import fk_report
    rob = load_robot(robot, base_link, tip_link)
    units = display_units(rob, deg, unit)
    qv = parse_joints(q, rob, units)
    result = fk_report(rob, qv, units, frames=frames)
    output(result.to_dict(), json, _tables, rob, precision)


def _tables(doc, robot, precision):
    from .render import console, heading, joint_pairs, kv_table, matrix_table, num, vec
    c = console()
    a = doc["units"]["angle"]
    c.print(heading(doc))
    c.print(f"q: {joint_pairs(doc, robot, precision)}")
    if "frames" in doc:
        for f in doc["frames"]:
            i = f["index"]
            c.print(matrix_table(f["link"], precision,
                                 title=f"T_{i - 1}^{i}  (link {i}, joint {f['joint']})"))
            c.print(matrix_table(f["T"], precision, title=f"T_0^{i}"))
        import numpy as np
        if not np.allclose(doc["base"], np.eye(4)):
            c.print(matrix_table(doc["base"], precision, title="base: T_world^0"))
        if not np.allclose(doc["tool"], np.eye(4)):
            c.print(matrix_table(doc["tool"], precision,
                                 title="tool: T_n^tool" if robot.convention != "poe"
                                 else "tool: M (tool pose at q = 0)"))
    c.print(matrix_table(doc["T"], precision, title="T (world <- tool)"))
    o = doc["orientation"]
    rows = [
        ("position", vec(doc["position"], precision)),
        (f"rpy (fixed X-Y-Z, {a})", vec(o["rpy"], precision)),
        (f"euler zyz ({a})", vec(o["euler_zyz"], precision)),
        (f"euler xyz (moving, {a})", vec(o["euler_xyz"], precision)),
        ("quaternion (w x y z)", vec(o["quaternion"], precision)),
        (f"axis-angle ({a})", vec(o["axis_angle"]["axis"], precision) + "  |  "
         + num(o["axis_angle"]["angle"], precision)),
        (f"rotation vector ({a})", vec(o["rotation_vector"], precision)),
        ("tcv [p; e^(qn/pi) r3]", vec(doc["tcv"], precision) if doc["tcv"] is not None
         else "n/a (last joint is prismatic)" if not robot.joints[-1].revolute
         else "n/a (the last joint has turned more than ten times: e^(qn/pi) is too large)"),
    ]
    c.print(kv_table(rows))
