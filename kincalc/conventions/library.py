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

    A value containing a path separator or ending in .yaml/.yml is a path;
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
    looks_like_path = os.sep in robot or "/" in robot or robot.endswith((".yaml", ".yml"))
    if not looks_like_path:
        candidate = library_dir() / f"{robot}.yaml"
        if os.path.isfile(candidate):
            return candidate, robot
    p = Path(robot)
    if looks_like_path or os.path.exists(p):
        return p, robot  # the loader reports "no such file" or "is a directory"
    close = difflib.get_close_matches(robot, bundled_names(), n=3, cutoff=0.6)
    raise RobotNotFoundError(robot, close)


def load(robot: str):
    """Load a bundled robot by name, or a robot file by path (``kincalc.load_robot``).

    Parameters
    ----------
    robot : str
        A bundled robot's name (``kincalc robots list``) or a path to a robot YAML file
        (see :func:`resolve` for which is which).

    Returns
    -------
    Robot
        The robot, SI inside: lengths in m, angles in rad, whatever the file's units.

    Raises
    ------
    RobotNotFoundError
        No bundled robot and no file of that name (the message suggests close names).
    RobotFileError
        The file is not a valid robot file (the message names the file, line and field).
    InputError
        As :func:`library_dir`.
    """
    from .reader import load_robot_file
    path, shown = resolve(robot)
    return load_robot_file(path, display_name=str(path) if path.parent == library_dir() else shown)
