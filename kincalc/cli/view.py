"""``kincalc view``: the arm in 3D in one HTML page, a slider per joint, IK branches."""

from __future__ import annotations

import os
import sys
from typing import Annotated, Optional

import typer

from ..errors import InputError, UsageError
from .common import (BaseLinkOpt, DebugOpt, DegOpt, FileName, ForceOpt, JointsArg, RobotArg,
                     TipLinkOpt, UnitOpt, display_units, load_robot, output_target, parse_joints)
from .targets import PoseOptions, with_pose_options

OutputOpt = Annotated[Optional[str], typer.Option(
    "--output", "-o", metavar="FILE", show_default=False, click_type=FileName(),
    help="Write the page to FILE (.html or .htm; '-' for standard output). Default: a new "
         "file in the temporary folder, its path said on standard error; with no display, "
         "standard output. An existing FILE is not replaced without --force.")]
OpenOpt = Annotated[bool, typer.Option(
    "--open", help="Open the page in the web browser (needs a display).")]

#: the names an output page may have
SUFFIXES = (".html", ".htm")


@with_pose_options
def view(
    robot: RobotArg,
    q: JointsArg = None,
    pose_options: PoseOptions = None,
    output: OutputOpt = None,
    force: ForceOpt = False,
    open_page: OpenOpt = False,
    deg: DegOpt = True,
    unit: UnitOpt = None,
    base_link: BaseLinkOpt = None,
    tip_link: TipLinkOpt = None,
    debug: DebugOpt = False,
):
    """Write an interactive 3D page of ROBOT: joint sliders, the live tool pose, IK branches.

    One self-contained HTML file (no network, nothing else to install) that
    any current browser opens from disk: the arm in 3D (drag to rotate, wheel
    to zoom), a slider and a number box per joint within its limits, the tool
    pose (position, RPY, quaternion), manipulability and a singularity
    warning, updated as the joints move, and the DH table. With a pose
    (the pose options of 'kincalc ik') the page lists every IK solution by
    branch, marked out of limits or singular; a click moves the arm there.

    ROBOT is a bundled robot's name or a path to a robot YAML or URDF file.
    Q... are the joints the page opens at (default: home), revolute in the
    angle unit, prismatic in the length unit; negative values need no '--'.
    """
    destination = _destination(output, force, open_page, robot, pose_options.pose)
    rob = load_robot(robot, base_link, tip_link)
    units = display_units(rob, deg, unit)
    qv = parse_joints(q, rob, units)
    result = _solve(rob, pose_options, units, qv if q else None)
    from ..analysis.view import page_html
    page = page_html(rob, units, qv, result)
    if destination is None:
        sys.stdout.write(page)
        return
    from ..outputs import write_text
    write_text(destination, page)
    if output is None:
        sys.stderr.write(f"kincalc: wrote {destination.shown}"
                         + ("; opening it in the web browser\n" if open_page
                            else " (open it in a web browser)\n"))
    if open_page:
        _open(destination.path)


def _solve(robot, pose_options, units, near):
    """Every IK solution for the pose options, as ``kincalc ik`` finds them (ordered from
    ``near`` when given), or None when no pose was given; a note on stderr when there is
    none."""
    if all(v is None for v in pose_options.given()):
        return None
    from ..ik import solve
    result = solve(robot, pose_options.target(robot, units), units=units, near=near)
    if not result.solutions:
        from ..analysis.words import reason_text
        sys.stderr.write(f"kincalc: note: no IK solution "
                         f"({reason_text(result.reason, robot, units)}); the page lists none\n")
    return result


def _destination(output, force, open_page, robot, pose):
    """Where the page goes, checked before any work: a :class:`kincalc.outputs.Target`
    (``-o FILE``, or a new file in the temporary folder when there is a display), or None
    for standard output (``-o -``, or no display)."""
    if open_page and output == "-":
        raise UsageError("--open needs a file to open; give -o FILE.html, not -o -")
    if open_page and not has_display():
        raise InputError("--open: there is no display to open a browser on (DISPLAY and "
                         "WAYLAND_DISPLAY are unset); give -o FILE.html and copy it")
    if output == "-":
        return None
    if output is not None:
        from ..outputs import check_target
        target = output_target(output, "-o", force, robot, [("--pose", pose)])
        check_target(target)
        if not output.lower().endswith(SUFFIXES):
            target.fail("the page is HTML; give a file name ending in .html")
        return target
    if has_display():
        return _temporary(robot)
    if sys.stdout.isatty():
        raise InputError("there is no display to show the page on (DISPLAY and "
                         "WAYLAND_DISPLAY are unset): give -o FILE.html, or redirect "
                         "standard output to a file")
    return None


def has_display() -> bool:
    """True where a browser window can be opened: macOS, Windows, or an X11 or Wayland
    session (``DISPLAY`` or ``WAYLAND_DISPLAY`` set)."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def _temporary(robot: str):
    """A new file ``kincalc-view-XXXX/NAME.html`` in the temporary folder (NAME from the
    ROBOT argument, letters, digits, ``_`` and ``-`` only)."""
    import re
    import tempfile

    from ..outputs import Target
    stem = re.sub(r"[^A-Za-z0-9_-]+", "_", os.path.splitext(os.path.basename(robot))[0])
    folder = tempfile.mkdtemp(prefix="kincalc-view-")
    return Target(os.path.join(folder, (stem.strip("_")[:60] or "robot") + ".html"))


def _open(path: str) -> None:
    """Open ``path`` in the user's web browser; a note on stderr when none starts."""
    import pathlib
    import webbrowser
    if not webbrowser.open(pathlib.Path(path).resolve().as_uri()):
        sys.stderr.write(f"kincalc: note: no web browser could be started; open {path} "
                         "yourself\n")
