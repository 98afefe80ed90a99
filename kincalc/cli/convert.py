"""``kincalc convert``: rewrite a robot file in another convention."""

from __future__ import annotations

from typing import Annotated, Optional

import typer

from .common import (BaseLinkOpt, DebugOpt, FileName, RobotArg, TipLinkOpt, Words, load_robot,
                     output_target)

ToOpt = Annotated[str, typer.Option(
    "--to", metavar="dh|mdh|poe", show_default=False, click_type=Words(("dh", "mdh", "poe")),
    help="The convention to write: dh (standard DH), mdh (modified DH, Craig) or poe "
         "(product of exponentials).")]
OutputOpt = Annotated[Optional[str], typer.Option(
    "-o", "--output", metavar="FILE", show_default=False, click_type=FileName(),
    help="Write the robot file to FILE instead of standard output ('-'). An existing FILE "
         "is not replaced without --force.")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let -o replace an existing regular file (never a link, a device or "
                    "the robot file itself).")]


def convert(
    robot: RobotArg,
    to: ToOpt = ...,
    output_file: OutputOpt = None,
    force: ForceOpt = False,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Rewrite ROBOT in another convention: standard DH, modified DH or product
    of exponentials (poe; a URDF file reads as poe).

    Prints a robot file (YAML) with the same forward kinematics for every
    joint value: same joint names, zeros, directions, limits, home, units and
    parameter names (a value given as a parameter, like 'a: l1', keeps its
    name when it moves to another row). Converting to the robot's own
    convention prints it unchanged (normalised). Check the result with
    'kincalc compare ROBOT FILE'.
    """
    from ..conventions import convert as _convert
    from ..errors import UsageError
    from ..model import CONVENTIONS
    from ..conventions.writer import dump_robot
    if to not in CONVENTIONS:
        raise UsageError(f"--to must be one of {', '.join(CONVENTIONS)}, not {to!r}")
    target = _check_target(output_file, force, robot)
    rob = load_robot(robot, base_link, tip_link)
    text = dump_robot(_convert(rob, to))
    if target is None:
        import sys
        sys.stdout.write(text)
        return
    _write(target, text)


def _check_target(path: str | None, force: bool, robot: str):
    """The :class:`kincalc.outputs.Target` of ``-o`` (None for standard output), checked
    before any work: a refused file costs nothing."""
    if path in (None, "-"):
        return None
    from ..outputs import check_target
    target = output_target(path, "-o", force, robot)
    check_target(target)
    return target


def _write(target, text: str) -> None:
    """Write ``text`` to ``target`` through a temporary file renamed over it when
    complete (:mod:`kincalc.outputs`): an interrupted write never leaves a half file,
    and a new file's mode follows the umask."""
    from ..outputs import write_text
    write_text(target, text)
