""":class:`~kincalc.model.Robot` -> robot file text (the YAML that
:mod:`kincalc.conventions.reader` reads).

The file is written in the robot's own units (``length_unit``, ``angle_unit``)
with the keys in the order of the bundled files: name, title, source,
convention, units, parameters, joints, base, tool, home, notes. Numbers are
written with ``repr`` precision, then cleaned: within 1e-12 relative of an
integer they are written as the integer (``90.00000000000001 -> 90``), below
1e-12 in magnitude as 0, and otherwise as the shortest decimal within 1e-14
relative (``431.79999999999995 -> 431.8``: the noise of a unit conversion).
DH fields the robot carries as expressions over its ``parameters``
(``robot.expressions``) are written as those expressions, and checked by
reading the text back: a field whose expression does not give its value is
written as the number. ``base`` and ``tool`` are written as ``xyz`` (and
``rpy`` when the rotation is reproduced by its rpy angles to 1e-12), else as
a 4x4 ``matrix``; an identity base or tool is left out (a poe robot always
has its ``tool``). ``home`` is written unless it is all zeros. Comments of
the original file are not kept (the Robot does not hold them).

This module writes YAML by hand: only :mod:`kincalc.conventions.reader` imports yaml.
"""

from __future__ import annotations

import json
import re

import numpy as np

from ..spatial import matrix_from_rpy, rpy_from_matrix
from ..units import ANGLE_UNITS, LENGTH_UNITS

#: a number this close (relative) to an integer is written as the integer
CLEAN_TOL = 1e-12
#: relative change allowed when a number is shortened to fewer decimals
SHORT_TOL = 1e-14
_PLAIN = re.compile(r"^[A-Za-z][A-Za-z0-9_.\-]*$")
_YAML_WORDS = {"null", "true", "false", "yes", "no", "on", "off", "y", "n"}
_DH_FIELDS = ("alpha", "a", "d", "theta")


def dump_robot(robot) -> str:
    """The robot file (YAML text, ending in a newline) that reads back as ``robot``.

    Parameters
    ----------
    robot : Robot
        Any convention. Its ``name``, ``title``, ``source`` and ``notes`` are
        written as they are; lengths are converted from m to
        ``robot.length_unit`` and angles from rad to ``robot.angle_unit``.

    Returns
    -------
    str
        ``reader.parse_robot_text`` of it gives a robot with the same
        joints, base, tool, limits and home (to 1e-12 relative). ``base`` is written
        as ``T_world_0``, ``tool`` as :attr:`~kincalc.model.Robot.written_tool`
        (``T_flange_tool`` for dh/mdh, ``M @ tool`` for poe).

    Raises
    ------
    InputError
        The text would not read back: a number of it is beyond what a robot file may
        hold (:data:`~kincalc.limits.MAX_MAGNITUDE`; a point of a poe joint, summed
        from lengths at the limit, can be), or the text is longer than a robot file may be
        (:data:`~kincalc.limits.MAX_FILE_BYTES`).
    ValueError
        A number that is not finite (:func:`num`).
    KeyError
        A ``length_unit`` or ``angle_unit`` not in :data:`~kincalc.units.LENGTH_UNITS` /
        :data:`~kincalc.units.ANGLE_UNITS`.
    """
    from ..errors import InputError
    from ..limits import MAX_FILE_BYTES
    from .conversion import SAME_FK, fk_difference
    text, back = _written(robot, num)
    moved, turned, reach = fk_difference(robot, back)
    if moved > SAME_FK * max(reach, 1e-12) or turned > SAME_FK:
        # shortened numbers that cancel (two DH offsets of 5e5 m for axes 1e-6 rad from
        # parallel, each within 1e-12 of its size) moved the tool: every number exactly
        # (the tool's reach is the scale: such a robot's own size is the offsets')
        text, back = _written(robot, _exact)
    size = len(text.encode("utf-8"))
    if size > MAX_FILE_BYTES:           # (its title's quotes, escaped, can double a file)
        raise InputError(f"{robot.name} written as a robot file would be {size} bytes, more "
                         f"than kincalc reads ({MAX_FILE_BYTES}, MAX_FILE_BYTES)")
    return text


def _written(robot, number) -> tuple:
    """``(text, robot read back)``: the file with numbers written by ``number`` (:func:`num`
    or :func:`_exact`), and the expressions that do not give their field's value written as
    numbers."""
    numeric: set[tuple[int, str]] = set()
    for _ in range(2):
        text = _text(robot, numeric, number)
        back = _read_back(text, robot)
        if robot.convention == "poe" or not robot.expressions:
            return text, back
        wrong = {(i, f) for i, (j, k) in enumerate(zip(robot.joints, back.joints))
                 for f in _DH_FIELDS
                 if not _close(getattr(j, f), getattr(k, f))}
        if not wrong:
            return text, back
        numeric |= wrong
    return text, back


def _read_back(text: str, robot):
    """``text`` read as a robot file; a text that does not read is an :class:`InputError`
    naming the field (a file kincalc writes is one it reads)."""
    from ..errors import InputError, RobotFileError
    from .reader import parse_robot_text
    try:
        return parse_robot_text(text, "<written>")
    except RobotFileError as exc:
        raise InputError(f"{robot.name} in {robot.convention} cannot be written as a robot "
                         f"file: {exc.what}") from None


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-11 * max(1.0, abs(a))


def _text(robot, numeric, number) -> str:
    """The file's text, its numbers written by ``number`` (:func:`num` or :func:`_exact`), the
    DH fields ``numeric`` as numbers rather than their expressions."""
    L = LENGTH_UNITS[robot.length_unit]
    A = ANGLE_UNITS[robot.angle_unit]
    out = [f"name: {yaml_string(robot.name, plain_ok=True)}"]
    if robot.title:
        out.append(f"title: {yaml_string(robot.title)}")
    if robot.source:
        out.append(f"source: {_text_block(robot.source)}")
    out.append(f"convention: {robot.convention}")
    out.append(f"units: {{length: {robot.length_unit}, angle: {robot.angle_unit}}}")
    if robot.parameters:
        # the file's own values, never converted: written exactly (num would shorten
        # 0.5773502691896257, a parameter given to full precision)
        items = ", ".join(f"{yaml_string(k, plain_ok=True)}: {_exact(v)}"
                          for k, v in robot.parameters)
        out.append(f"parameters: {{{items}}}")
    out.append("joints:")
    exprs = list(robot.expressions) + [()] * (robot.dof - len(robot.expressions))
    for i, j in enumerate(robot.joints):
        scale = A if j.revolute else L
        fields = [f"name: {yaml_string(j.name, plain_ok=True)}", f"type: {j.type}"]
        if robot.convention == "poe":
            fields.append(f"axis: {_unit_vector(j.axis, number)}")
            fields.append(f"point: {_vector(np.asarray(j.point) / L, number)}")
        else:
            given = dict(exprs[i]) if robot.convention != "poe" else {}
            for f in _DH_FIELDS:
                unit = A if f in ("alpha", "theta") else L
                if f in given and (i, f) not in numeric:
                    fields.append(f"{f}: {yaml_string(given[f], expression=True)}")
                else:
                    fields.append(f"{f}: {number(getattr(j, f) / unit)}")
        if j.limits is not None:
            fields.append(f"limits: {_vector(np.asarray(j.limits) / scale, number)}")
        out.append("  - {" + ", ".join(fields) + "}")
    base, tool = _pose(robot.base, L, A, number), _pose(robot.written_tool, L, A, number)
    if base is not None:
        out.append(f"base: {base}")
    if tool is not None or robot.convention == "poe":
        out.append(f"tool: {tool or '{xyz: [0, 0, 0]}'}")
    if np.any(robot.home != 0):
        home = np.asarray(robot.home) / np.where(robot.is_revolute, A, L)
        out.append(f"home: {_vector(home, number)}")
    if robot.notes:
        out.append(f"notes: {_text_block(robot.notes)}")
    return "\n".join(out) + "\n"


def num(x: float) -> str:
    """``x`` as a number of a robot file.

    Parameters
    ----------
    x : float
        The value, in the file's units.

    Returns
    -------
    str
        An integer when within ``CLEAN_TOL`` (relative) of one (and below 1e15), 0 below
        ``CLEAN_TOL`` in magnitude, else the shortest decimal within ``SHORT_TOL``
        (relative; a few units in the last place, what a unit conversion leaves:
        431.79999999999995 -> 431.8), else ``repr``.

    Raises
    ------
    ValueError
        ``x`` is infinite or NaN.
    """
    x = float(x)
    if not np.isfinite(x):
        raise ValueError(f"cannot write {x!r} in a robot file")
    text = _short(x)
    # the text read back must write as itself (a file rewritten is unchanged): shortening
    # the shortened value can drop one more digit, so go on to the fixed point (a few
    # SHORT_TOL at most)
    while (again := _short(float(text))) != text:
        text = again
    return text


def _exact(x: float) -> str:
    """``x`` as the shortest text that reads back as exactly ``x`` (an integer as one)."""
    x = float(x)
    if not np.isfinite(x):
        raise ValueError(f"cannot write {x!r} in a robot file")
    return str(int(x)) if x.is_integer() and abs(x) < 1e15 else repr(x)


def _short(x: float) -> str:
    """One step of :func:`num`: the integer, 0, or the shortest decimal near ``x``."""
    if abs(x) < CLEAN_TOL:
        return "0"
    nearest = round(x)
    if abs(nearest - x) <= CLEAN_TOL * abs(x) and abs(nearest) < 1e15:
        return str(int(nearest))
    for digits in range(1, 17):
        r = round(x, digits)
        if abs(r - x) <= SHORT_TOL * abs(x):
            return repr(r)
    return repr(x)


def _vector(values, number=num) -> str:
    return "[" + ", ".join(number(v) for v in values) + "]"


def _unit_vector(values, number=num) -> str:
    """A unit vector written so that normalising what is read (as the reader
    does) gives back the same text: a file read and written again is unchanged."""
    v = np.asarray(values, dtype=float)
    for _ in range(5):
        text = [number(x) for x in v]
        back = np.array([float(x) for x in text])
        back = back / np.linalg.norm(back)
        if [number(x) for x in back] == text:
            break
        v = back
    return "[" + ", ".join(text) + "]"


def _pose(T, L, A, number=num) -> str | None:
    """``{xyz: [...], rpy: [...]}`` or ``{matrix: [...]}`` for the transform ``T``;
    None for the identity (as written: rounding noise below 1e-12 is no pose)."""
    T = np.asarray(T, dtype=float)
    xyz = [number(v) for v in T[:3, 3] / L]
    R = T[:3, :3]
    rpy = rpy_from_matrix(R)
    # the extraction gives (-pi, pi]; an angle at -pi (to rounding) is written as +pi
    # (180 deg), so that a file read and written again keeps its text
    rpy = [number(v) for v in np.where(rpy < -np.pi + 1e-9, rpy + 2 * np.pi, rpy) / A]
    written = np.array([float(v) for v in rpy]) * A
    if np.max(np.abs(matrix_from_rpy(written) - R)) <= CLEAN_TOL:
        parts = []
        if any(v != "0" for v in xyz):
            parts.append(f"xyz: [{', '.join(xyz)}]")
        if any(v != "0" for v in rpy):
            parts.append(f"rpy: [{', '.join(rpy)}]")
        return "{" + ", ".join(parts) + "}" if parts else None
    M = T.copy()
    M[:3, 3] /= L
    return "{matrix: [" + ", ".join(_vector(row, number) for row in M) + "]}"


def _text_block(s: str) -> str:
    """Long prose as a folded block (``>-``, lines of at most 96 characters) when
    folding gives back exactly ``s``; otherwise a quoted string."""
    import textwrap
    simple = (s.isprintable() and "  " not in s and s == s.strip() and len(s) > 80)
    if not simple:
        return yaml_string(s)
    lines = textwrap.wrap(s, width=96, break_long_words=False, break_on_hyphens=False)
    if " ".join(lines) != s:
        return yaml_string(s)
    return ">-\n" + "\n".join(f"  {line}" for line in lines)


def yaml_string(s: str, plain_ok: bool = False, expression: bool = False) -> str:
    """A YAML scalar for ``s``: plain when that reads back as the same text,
    else double-quoted (JSON escapes are valid YAML ones).

    Parameters
    ----------
    s : str
        The text (``str(s)`` is written).
    plain_ok : bool
        Allow a plain name (a letter, then letters, digits, ``_ . -``) that is no YAML
        word such as ``yes`` or ``null``.
    expression : bool
        Allow a plain identifier (a parameter name standing for a DH field).

    Returns
    -------
    str
        The scalar as it goes in the file.
    """
    s = str(s)
    if plain_ok and _PLAIN.match(s) and s.lower() not in _YAML_WORDS:
        return s
    if expression and re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", s) and s.lower() not in _YAML_WORDS:
        return s
    quoted = json.dumps(s, ensure_ascii=False)
    # YAML rejects DEL and the C1 controls unescaped, JSON leaves them
    return re.sub(r"[\x7f-\x9f\u2028\u2029]", lambda m: f"\\u{ord(m.group()):04x}", quoted)
