"""``kincalc jacobian``: Jacobian, singular values, manipulability, singularity."""

from __future__ import annotations

from enum import Enum
from typing import Annotated, Optional

import typer

from .common import (BaseLinkOpt, BatchOpt, DebugOpt, DegOpt, FormatOpt, InputFormatOpt, JobsOpt,
                     JointsArg, JsonOpt, PrecisionOpt, RobotArg, TipLinkOpt, UnitOpt, display_units,
                     load_robot, output, parse_joints)


class Frame(str, Enum):
    base = "base"
    tool = "tool"


class AngleSet(str, Enum):
    rpy = "rpy"
    zyz = "zyz"
    xyz = "xyz"


def jacobian(
    robot: RobotArg,
    q: JointsArg = None,
    frame: Annotated[Frame, typer.Option(
        "--frame", help="Express the geometric Jacobian in the base (world) or tool frame.")]
        = Frame.base,
    analytic: Annotated[Optional[AngleSet], typer.Option(
        "--analytic", show_default=False,
        help="Also give the analytic Jacobian for this angle set: rpy (fixed X-Y-Z), "
             "zyz or xyz (moving X-Y-Z Euler).")] = None,
    symbolic: Annotated[bool, typer.Option(
        "--symbolic", help="Print the geometric Jacobian as formulas in the joint variables "
        "(no Q), simplified, with the abbreviations C1 = cos theta1, S23 = sin(theta2 + "
        "theta3), ...; lengths named as in the robot file's parameters. Honours --frame. "
        "Needs sympy (pip install 'kincalc[symbolic]').")] = False,
    latex: Annotated[bool, typer.Option(
        "--latex", help="Print the --symbolic Jacobian as LaTeX (amsmath bmatrix) with the "
        "legend of abbreviations; implies --symbolic.")] = False,
    numeric_lengths: Annotated[bool, typer.Option(
        "--numeric-lengths", help="With --symbolic or --latex: the robot file's parameter "
        "values in place of their names (then --unit applies).")] = False,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    precision: PrecisionOpt = 4,
    batch: BatchOpt = None,
    fmt: FormatOpt = "jsonl",
    input_format: InputFormatOpt = "auto",
    jobs: JobsOpt = 1,
    json: JsonOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Geometric Jacobian (6 x n, rows vx vy vz wx wy wz) at joint values Q.

    Also prints the singular values, rank, Yoshikawa manipulability,
    condition number and, at a singular configuration, which singularity
    it is (wrist, elbow, shoulder) or the null-space direction.

    ROBOT is a bundled robot's name or a path to a robot YAML file; Q... are
    the joint values (default: home). Linear rows are in the length unit per
    radian (per length unit for prismatic columns), angular rows in rad/rad.

    With --symbolic (or --latex) no Q is given: J is derived for every q;
    --deg/--rad and --precision do not apply.
    """
    if batch is not None:
        from .batch import run_command
        rob = load_robot(robot, base_link, tip_link)
        run_command("jacobian", rob, display_units(rob, deg, unit), batch, fmt, jobs, given=[q],
                    frame=frame.value,
                    refused={"--analytic": analytic, "--symbolic": symbolic, "--latex": latex,
                             "--numeric-lengths": numeric_lengths},
                    input_format=input_format, json=json)
    if symbolic or latex or numeric_lengths:
        from ..errors import UsageError
        from .symbolic import require_sympy_for, symbolic_check, symbolic_output
        symbolic_check(symbolic, latex, numeric_lengths, q)
        if analytic is not None:
            raise UsageError("--analytic is not available with --symbolic")
        from ..analysis.symbolic import symbolic_jacobian
        require_sympy_for("jacobian", symbolic, latex)
        rob = load_robot(robot, base_link, tip_link)
        display_units(rob, deg, unit)
        result = symbolic_jacobian(rob, frame=frame.value, numeric_lengths=numeric_lengths,
                                   length_unit=unit)
        symbolic_output(result, json, latex)
        return
    from ..analysis.reports import jacobian_report
    rob = load_robot(robot, base_link, tip_link)
    units = display_units(rob, deg, unit)
    qv = parse_joints(q, rob, units)
    result = jacobian_report(rob, qv, units, frame=frame.value,
                             analytic=analytic.value if analytic else None)
    output(result.to_dict(), json, _tables, rob, precision)


def _tables(doc, robot, precision):
    from .render import console, heading, joint_pairs, kv_table, matrix_table, num, vec
    c = console()
    c.print(heading(doc))
    c.print(f"q: {joint_pairs(doc, robot, precision)}")
    headers = [j.name for j in robot.joints]
    L = doc["units"]["length"]
    c.print(matrix_table(
        doc["J"], precision, headers=headers, row_labels=["vx", "vy", "vz", "wx", "wy", "wz"],
        title=f"J ({doc['frame']} frame; rows vx vy vz [{L}/rad] wx wy wz [rad/rad])"))
    if "analytic" in doc:
        an = doc["analytic"]
        if an["J"] is not None:
            rates = {"rpy": ("roll", "pitch", "yaw"), "zyz": ("z1", "y", "z2"),
                     "xyz": ("x", "y", "z")}.get(an["angles"], ("a1", "a2", "a3"))
            c.print(matrix_table(an["J"], precision, headers=headers,
                                 row_labels=["vx", "vy", "vz"] + [f"d{a}" for a in rates],
                                 title=f"analytic Jacobian ({an['angles']} angle rates)"))
        else:
            c.print(f"analytic Jacobian: {an['error']}")
    rows = [
        ("singular values", vec(doc["singular_values"], precision)),
        ("rank", str(doc["rank"])),
        ("manipulability", num(doc["manipulability"], precision + 2)),
        ("position manipulability", num(doc["position_manipulability"], precision + 2)),
        ("condition", "unbounded (singular)" if doc["condition"] is None
         else num(doc["condition"], precision)),
        ("singular", "yes" if doc["singular"] else "no"),
    ]
    sg = doc.get("singularity")
    if sg:
        for text in sg["descriptions"]:
            rows.append(("", text))
        if sg["null_space"] is not None:
            rows.append(("null space (q-dot)", vec(sg["null_space"], precision)))
        if sg["lost_motion"] is not None:
            rows.append(("lost tool motion", vec(sg["lost_motion"], precision)
                         + "  (vx vy vz wx wy wz)"))
    c.print(kv_table(rows))
