"""``kincalc convert``: rewrite a robot file in another convention."""

from __future__ import annotations

from typing import Annotated, Optional

import typer

from .common import DebugOpt, RobotArg

ToOpt = Annotated[str, typer.Option(
    "--to", metavar="dh|mdh|poe", show_default=False,
    help="The convention to write: dh (standard DH), mdh (modified DH, Craig) or poe "
         "(product of exponentials). poe robots cannot be converted to dh or mdh.")]
OutputOpt = Annotated[Optional[str], typer.Option(
    "-o", "--output", metavar="FILE", show_default=False,
    help="Write the robot file to FILE instead of standard output. An existing FILE is "
         "not overwritten without --force.")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let -o overwrite an existing file.")]


def convert(
    robot: RobotArg,
    to: ToOpt = ...,
    output_file: OutputOpt = None,
    force: ForceOpt = False,
    debug: DebugOpt = False,
):
    """Rewrite ROBOT in another convention: standard DH <-> modified DH, or
    either to product of exponentials (poe).

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
    from ..robot_writer import dump_robot
    if to not in CONVENTIONS:
        raise UsageError(f"--to must be one of {', '.join(CONVENTIONS)}, not {to!r}")
    rob = load_robot_checked(robot, output_file, force)
    text = dump_robot(_convert(rob, to))
    if output_file is None or output_file == "-":
        import sys
        sys.stdout.write(text)
        return
    _write(output_file, text, force)


def load_robot_checked(robot, output_file, force):
    """The robot, after checking -o before any work (a refused file costs nothing)."""
    from .common import load_robot
    if output_file not in (None, "-"):
        _check_target(output_file, force)
    return load_robot(robot)


def _check_target(path: str, force: bool) -> None:
    import os

    from ..errors import InputError
    if os.path.isdir(path):
        raise InputError(f"-o {path}: is a folder; give a file name")
    if os.path.lexists(path) and not force:
        raise InputError(f"-o {path}: the file exists; use --force to overwrite it")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InputError(f"-o {path}: no such folder {folder}")


def _write(path: str, text: str, force: bool) -> None:
    """Write ``text`` to ``path`` atomically: a new file next to it, then renamed
    over it, so an interrupted write never leaves a half file behind."""
    import os
    import tempfile

    from ..errors import InputError
    _check_target(path, force)
    folder = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(prefix=".kincalc-", suffix=".yaml", dir=folder)
    except OSError as exc:
        raise InputError(f"-o {path}: cannot write in {folder}: {exc.strerror}") from None
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        if os.path.lexists(path) and not force:   # appeared meanwhile
            raise InputError(f"-o {path}: the file exists; use --force to overwrite it")
        os.replace(tmp, path)
    except OSError as exc:
        raise InputError(f"-o {path}: cannot write: {exc.strerror}") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
