"""The bundled robot library and name/path resolution.

A ``ROBOT`` argument is either a bundled robot's name (a file
``<name>.yaml`` in the library folder) or a path to a YAML file. Resolving a
name opens exactly one file: there is no scan of the library unless the
user asks for the list.
"""

from __future__ import annotations

import difflib
import os
from pathlib import Path

from ..errors import RobotNotFoundError
from ..limits import cut


#: a robot file with one of these endings is read as URDF (:mod:`kincalc.conventions.urdf`)
URDF_SUFFIXES = (".urdf",)
#: ... and one of these is refused with how to expand it
XACRO_SUFFIXES = (".xacro",)
XACRO_HINT = ("a .xacro file is a macro program, not a URDF: expand it first ('pip install "
              "xacro', then 'xacro FILE.xacro > FILE.urdf') and give kincalc the .urdf")


def library_dir() -> Path:
    """The folder of bundled robot files.

    In an installed wheel it is ``kincalc/robots``; in a source checkout
    (editable install or running from the tree) the top-level ``robots/``.
    ``KINCALC_ROBOTS`` overrides both.

    Returns
    -------
    pathlib.Path
        The folder (in a source tree, returned whether or not it exists).

    Raises
    ------
    InputError
        ``KINCALC_ROBOTS`` is set but is not a folder.
    """
    env = os.environ.get("KINCALC_ROBOTS")
    if env:
        if not Path(env).is_dir():
            from ..errors import InputError
            raise InputError(f"KINCALC_ROBOTS={env!r} is not a folder")
        return Path(env)
    package = Path(__file__).resolve().parent.parent       # kincalc/
    packaged = package / "robots"                           # in a wheel
    if packaged.is_dir():
        return packaged
    return package.parent / "robots"                        # in a source tree


def bundled_names() -> list[str]:
    """Sorted names of every bundled robot.

    Returns
    -------
    list of str
        The stems of the ``*.yaml`` files of :func:`library_dir`; empty when that folder
        does not exist.

    Raises
    ------
    InputError
        As :func:`library_dir`.
    """
    d = library_dir()
    return sorted(p.stem for p in d.glob("*.yaml")) if d.is_dir() else []


def resolve(robot: str) -> tuple[Path, str]:
    """Return ``(path, display_name)`` for a robot name or path.

    A value containing a path separator or ending in .yaml/.yml/.urdf/.xacro is a path;
    otherwise a bundled name is tried first, then a file of that name. A name
    the system cannot hold (too long, a NUL character) is no robot: the tests
    go through ``os.path``, which answers False where ``Path.is_file`` raises
    (ENAMETOOLONG).

    Parameters
    ----------
    robot : str
        A bundled robot's name or a path, as the user gave it.

    Returns
    -------
    path : pathlib.Path
        The file to read (not checked to exist when ``robot`` looks like a path).
    display_name : str
        ``robot`` as given, for messages.

    Raises
    ------
    RobotNotFoundError
        Neither a bundled robot nor an existing file (with up to 3 close bundled names).
    InputError
        As :func:`library_dir`.
    """
    looks_like_path = os.sep in robot or "/" in robot or \
        robot.lower().endswith((".yaml", ".yml") + URDF_SUFFIXES + XACRO_SUFFIXES)
    if not looks_like_path:
        candidate = library_dir() / f"{robot}.yaml"
        if os.path.isfile(candidate):
            return candidate, robot
    # the name as given: Path("") is "." (the working folder, "is a directory")
    if looks_like_path or os.path.exists(robot):
        return Path(robot), robot  # the loader reports "no such file" or "is a directory"
    close = difflib.get_close_matches(robot, bundled_names(), n=3, cutoff=0.6)
    raise RobotNotFoundError(robot, close)


def load(robot: str, base_link: str | None = None, tip_link: str | None = None,
         display_name: str | None = None):
    """Load a bundled robot by name, or a robot file or URDF by path (``kincalc.load_robot``).

    Parameters
    ----------
    robot : str
        A bundled robot's name (``kincalc robots list``), a path to a robot YAML file, or
        a path to a ``.urdf`` file (see :func:`resolve` for which is which).
    base_link, tip_link : str, optional
        A URDF's chain: its first and last link (defaults in :mod:`kincalc.conventions.urdf`);
        refused for a robot that is not a URDF.
    display_name : str, optional
        How messages name the file (default: ``robot`` as given, or a bundled robot's
        path).

    Returns
    -------
    Robot
        The robot, SI inside: lengths in m, angles in rad, whatever the file's units.

    Raises
    ------
    RobotNotFoundError
        No bundled robot and no file of that name (the message suggests close names).
    RobotFileError
        The file is not a valid robot file or URDF (the message names the file, line and
        field), or it is a .xacro file (the message says how to expand it).
    InputError
        As :func:`library_dir`; or links given for a robot that is not a URDF.
    """
    from ..errors import InputError, RobotFileError
    from .reader import load_robot_file
    path, shown = resolve(robot)
    if display_name is None:
        display_name = str(path) if path.parent == library_dir() else shown
    shown = display_name
    suffix = path.suffix.lower()
    if suffix in XACRO_SUFFIXES:
        raise RobotFileError(shown, None, XACRO_HINT)
    if suffix in URDF_SUFFIXES:
        from .urdf import load_urdf
        return load_urdf(path, shown, base_link=base_link, tip_link=tip_link)
    given = [o for o, v in (("--base-link", base_link), ("--tip-link", tip_link)) if v]
    if given:
        raise InputError(f"{' and '.join(given)} choose{'s' if len(given) == 1 else ''} the "
                         f"chain of a URDF robot; {cut(robot)} is not a .urdf file")
    return load_robot_file(path, display_name=shown)
