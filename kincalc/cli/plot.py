"""``kincalc plot``: draw the arm at one configuration to a PNG, SVG or PDF file."""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from .common import (BaseLinkOpt, DebugOpt, DegOpt, DpiOpt, FileName, ForceOpt, JointsArg,
                     RobotArg, TipLinkOpt, UnitOpt, display_units, load_robot, output_target,
                     parse_joints)

OutputOpt = Annotated[str, typer.Option(
    "--output", "-o", metavar="FILE", show_default=False, click_type=FileName(),
    help="The drawing to write; its suffix picks the format: .png, .svg or .pdf. An "
         "existing FILE is not replaced without --force.")]


def plot(
    robot: RobotArg,
    q: JointsArg = None,
    output: OutputOpt = ...,
    dpi: DpiOpt = 100,
    force: ForceOpt = False,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Draw ROBOT at joint values Q into FILE (PNG, SVG or PDF).

    Links are thick lines, prismatic joints squares, and the base and tool
    frames x/y/z triads (red/green/blue), at equal scale. A planar arm is drawn
    in 2D in its plane (revolute joints as circles); any other in 3D, on a
    pedestal on the ground, seen from the direction that shows it best, each
    revolute joint a cylinder with an arrow to its axis's positive end. Needs
    matplotlib: pip install 'kincalc[plot]'.

    ROBOT is a bundled robot's name (kincalc robots list) or a path to a robot
    YAML file. Q... are the joint values in order, revolute in the angle unit,
    prismatic in the length unit; negative values need no '--'. Without Q the
    robot's home configuration is used.
    """
    from ..analysis.plot import check_output, config_title, draw_arms, require_matplotlib
    target = output_target(output, "-o", force, robot)
    check_output(target)
    require_matplotlib("kincalc plot")
    rob = load_robot(robot, base_link, tip_link)
    units = display_units(rob, deg, unit)
    qv = parse_joints(q, rob, units)
    drawing = draw_arms(rob, qv[None, :], [config_title(rob, qv, units)], target,
                        units=units, dpi=dpi)
    sys.stdout.write(f"wrote {output} ({drawing.describe()})\n")
