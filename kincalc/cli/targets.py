"""Targets from the command line's pose options and the batch records' fields.

The core (:mod:`kincalc.ik.target`) names a request's format and builds its target in
SI; this module reads the user's numbers (in the display units, bounded), words what
the core finds wrong in the command line's names (``--rpy``, ``--pose FILE``) or a
batch record's (``rpy``), and reads ``--pose`` files.
"""

from __future__ import annotations

import functools
import inspect
import typing
from typing import Annotated, NamedTuple, Optional, Tuple

import typer

from ..errors import InputError, UsageError
from .common import NUMBER, FileName, check_numbers

# --- the pose options, declared once for every command that takes a target -----------

F3 = Tuple[float, float, float]
F4 = Tuple[float, float, float, float]

XyzOpt = Annotated[Optional[F3], typer.Option(
    "--xyz", metavar="X Y Z", show_default=False, click_type=NUMBER,
    help="Target position, in the length unit.")]
RpyOpt = Annotated[Optional[F3], typer.Option(
    "--rpy", metavar="R P Y", click_type=NUMBER, show_default=False,
    help="Orientation as fixed X-Y-Z angles: R = Rz(Y) Ry(P) Rx(R).")]
ZyzOpt = Annotated[Optional[F3], typer.Option(
    "--euler-zyz", metavar="A B C", click_type=NUMBER, show_default=False,
    help="Orientation as ZYZ Euler angles: R = Rz(A) Ry(B) Rz(C).")]
XyzEOpt = Annotated[Optional[F3], typer.Option(
    "--euler-xyz", metavar="A B C", click_type=NUMBER, show_default=False,
    help="Orientation as moving X-Y-Z Euler angles: R = Rx(A) Ry(B) Rz(C).")]
QuatOpt = Annotated[Optional[F4], typer.Option(
    "--quat", metavar="W X Y Z", click_type=NUMBER, show_default=False,
    help="Orientation as a quaternion (w, x, y, z); normalised.")]
AxisAngleOpt = Annotated[Optional[F4], typer.Option(
    "--axis-angle", metavar="X Y Z ANGLE", click_type=NUMBER, show_default=False,
    help="Orientation as a rotation of ANGLE about the axis (X, Y, Z).")]
MatrixOpt = Annotated[Optional[Tuple[float, float, float, float, float, float, float, float,
                                     float]], typer.Option(
    "--matrix", metavar="R11 ... R33", click_type=NUMBER, show_default=False,
    help="Orientation as a rotation matrix, 9 numbers row by row.")]
ApproachOpt = Annotated[Optional[F3], typer.Option(
    "--approach", metavar="AX AY AZ", click_type=NUMBER, show_default=False,
    help="Only the approach direction (the tool z axis, world frame; normalised), for "
         "five-joint arms that set it but not the roll about it.")]
TcvOpt = Annotated[Optional[Tuple[float, float, float, float, float, float]], typer.Option(
    "--tcv", metavar="W1 ... W6", click_type=NUMBER, show_default=False,
    help="Tool configuration vector w = [p; e^(qn/pi) r3]: position, approach vector and "
         "the last joint's angle in one (robots whose last joint rolls the tool).")]
PoseOpt = Annotated[Optional[str], typer.Option(
    "--pose", metavar="FILE", show_default=False, click_type=FileName(),
    help="The whole target pose as a 4x4 matrix in a file ('-' for stdin): 16 numbers, "
         "or JSON (a list of rows, or an object with a 'T' field).")]
FromQOpt = Annotated[Optional[str], typer.Option(
    "--from-q", metavar="'Q1 Q2 ...'", show_default=False,
    help="Target the pose FK gives for these joint values (one quoted argument, "
         "space- or comma-separated; for ik and reach also the numbers as words after "
         "it).")]

#: the pose options in --help order: (parameter name, its typer annotation)
POSE_OPTIONS = (("xyz", XyzOpt), ("rpy", RpyOpt), ("euler_zyz", ZyzOpt),
                ("euler_xyz", XyzEOpt), ("quat", QuatOpt), ("axis_angle", AxisAngleOpt),
                ("matrix", MatrixOpt), ("approach", ApproachOpt), ("tcv", TcvOpt),
                ("pose", PoseOpt), ("from_q", FromQOpt))


class PoseOptions(NamedTuple):
    """The pose options of one command line, as given (user units; None when absent)."""

    xyz: tuple | None = None
    rpy: tuple | None = None
    euler_zyz: tuple | None = None
    euler_xyz: tuple | None = None
    quat: tuple | None = None
    axis_angle: tuple | None = None
    matrix: tuple | None = None
    approach: tuple | None = None
    tcv: tuple | None = None
    pose: str | None = None
    from_q: str | None = None

    def given(self) -> list:
        """Every option's value, in --help order (for refusing them next to --batch)."""
        return [getattr(self, name) for name, _ in POSE_OPTIONS]

    def target(self, robot, units):
        """The :class:`~kincalc.ik.Target` they ask for (SI), by :func:`build_target`."""
        return build_target(robot, units, **self._asdict())


def with_pose_options(command):
    """A typer command whose ``pose_options: PoseOptions`` parameter stands for the eleven
    pose options (``--xyz`` .. ``--from-q``, in that place of its signature, so --help
    lists them as before); the command receives them as one :class:`PoseOptions`."""
    return option_group(command, "pose_options", POSE_OPTIONS, PoseOptions)


def option_group(command, param: str, options, make):
    """``command`` with its parameter ``param`` standing for the typer ``options``
    (``(name, annotation)`` pairs, listed by --help in that place of its signature); the
    command receives them as one ``make(**values)``."""
    hints = typing.get_type_hints(command, include_extras=True)
    params = []
    for p in inspect.signature(command).parameters.values():
        if p.name == param:
            params += [inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD,
                                         default=None, annotation=annotation)
                       for name, annotation in options]
        else:
            params.append(p.replace(annotation=hints.get(p.name, p.annotation)))

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        values = {name: kwargs.pop(name, None) for name, _ in options}
        return command(*args, **{param: make(**values)}, **kwargs)
    wrapper.__signature__ = inspect.Signature(params)
    wrapper.__annotations__ = {p.name: p.annotation for p in params}
    return wrapper


# --- targets from them -----------------------------------------------------------------

#: how the command line names the fields of a target request
OPTION_NAMES = {"q": "--from-q", "T": "--pose"}


def option_name(field: str) -> str:
    """The command-line option of a request field (``euler_zyz`` -> ``--euler-zyz``,
    ``q`` -> ``--from-q``)."""
    return OPTION_NAMES.get(field) or "--" + field.replace("_", "-")


def build_target(robot, units, *, xyz=None, rpy=None, euler_zyz=None, euler_xyz=None,
                 quat=None, axis_angle=None, matrix=None, approach=None, tcv=None, pose=None,
                 from_q=None, T=None, q=None, record: bool = False):
    """A :class:`~kincalc.ik.Target` from the pose options (user units -> SI).

    ``T`` (a 4x4 matrix, or 16 or 12 numbers) and ``q`` (joint values) are the
    batch-record forms of ``--pose`` and ``--from-q``. ``record``: the fields come from a
    batch record, and the messages name them as records do (``quat``, not ``--quat``)."""
    import numpy as np

    from ..ik import Target
    from ..analysis.requests import to_si
    from ..ik.target import BadTarget, defect_text, target_form, targets_from
    given = {"xyz": xyz, "rpy": rpy, "euler_zyz": euler_zyz, "euler_xyz": euler_xyz,
             "quat": quat, "axis_angle": axis_angle, "matrix": matrix, "approach": approach,
             "tcv": tcv, "T": T if pose is None else pose, "q": q if from_q is None else from_q}
    name = (lambda f: f) if record else option_name
    for f in ("xyz", "rpy", "euler_zyz", "euler_xyz", "quat", "axis_angle", "matrix",
              "approach", "tcv"):
        if given[f] is not None:
            check_numbers(np.asarray(given[f], float).ravel(), name(f))
    try:
        form = target_form(f for f, v in given.items() if v is not None)
    except BadTarget as exc:
        raise UsageError(exc.words(name)) from None
    if form == "q":
        from .common import parse_joints, value_tokens
        tokens = value_tokens(from_q, name("q")) if from_q is not None else [str(x) for x in q]
        qv = parse_joints(tokens, robot, units, option=name("q"))
        return Target(robot.fk(qv, column_walk=True), orientation=True)
    if form == "T":
        values = _read_pose(pose, units) if pose is not None else \
            pose_values(np.array(T, float), "T")
        what = f"--pose {pose}" if pose is not None else "T"
    else:
        values = None if form is None else np.asarray(given[form], float).ravel()
        what = name(form) if form else None
    v = None if form is None else to_si(form, values[None], units)
    p = None if xyz is None else np.asarray(xyz, float)[None] / units.l
    targets, defect = targets_from(form, v, p)
    if defect[0] is not None:
        raise InputError(defect_text(form, defect[0], what))
    return Target.of(targets)


def pose_values(M, what):
    """``M`` (16 or 12 numbers, or a 4x4 matrix) as 16 or 12 bounded numbers, the field
    named ``what``; an InputError otherwise."""
    M = M.ravel()
    if M.size not in (12, 16):
        raise InputError(f"{what}: expected a 4x4 matrix (16 finite numbers), got {M.size}")
    check_numbers(M, what)
    return M


def _read_pose(src: str, units):
    """The 16 or 12 numbers of the pose file ``src``, its translation in the length unit of
    ``units`` (a JSON document's own ``units.length``, as fk and ik write it, converted)."""
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
        text = raw.decode("utf-8-sig")           # (a byte-order mark, as the other readers)
    except UnicodeDecodeError:
        raise InputError(f"{what}: not UTF-8 text; expected 16 numbers or JSON rows of a "
                         "4x4 matrix") from None
    def not_finite(word):                    # (json reads NaN and Infinity; JSON has none)
        raise InputError(f"{what}: {word} is not a finite number (JSON has no NaN or "
                         "Infinity)")
    factor = 1.0
    try:
        data = _json.loads(text, parse_constant=not_finite)
        if isinstance(data, dict):
            factor = _document_length(data, units, what)
            data = data.get("T", data.get("target", {}).get("T") if isinstance(
                data.get("target"), dict) else None)
        M = np.array(data, dtype=float)
    except (ValueError, TypeError, RecursionError):
        M = np.array(_pose_words(text, what))
    M = pose_values(M, what)
    if factor != 1.0:
        M = M.astype(float)                              # (a copy)
        M[[3, 7, 11]] *= factor
    return M


def _document_length(data: dict, units, what: str) -> float:
    """The factor from a JSON pose document's length unit (its ``units.length``, as ``fk``
    and ``ik --json`` write it) to the command's: 1 where it names none."""
    from ..limits import quote
    from ..units import LENGTH_UNITS
    stated = data.get("units")
    unit = stated.get("length") if isinstance(stated, dict) else None
    if unit is None:
        return 1.0
    if not isinstance(unit, str) or unit not in LENGTH_UNITS:
        raise InputError(f"{what}: units.length {quote(str(unit), 40)} is not a length unit "
                         f"(use one of {', '.join(LENGTH_UNITS)})")
    return LENGTH_UNITS[unit] * units.l


def _pose_words(text: str, what: str) -> list:
    """The numbers of a pose file written as words (commas and brackets between them), or
    an error naming the line and the word that is not a number."""
    from ..limits import parse_decimal, quote
    numbers = []
    for n, line in enumerate(text.splitlines(), 1):
        for word in line.replace(",", " ").replace("[", " ").replace("]", " ").split():
            try:
                numbers.append(parse_decimal(word))
            except ValueError:
                raise InputError(f"{what}: line {n}: {quote(word, 40)} is not a number; "
                                 "expected 16 numbers or JSON rows of a 4x4 matrix") from None
    return numbers
