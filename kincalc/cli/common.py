"""Options and argument helpers shared by the commands.

Kept import-light: typer only. numpy, rich and yaml are imported inside the
functions that need them so that ``kincalc --help`` starts fast.
"""

from __future__ import annotations

import re
from typing import Annotated, List, Optional

import click
import typer

from ..errors import InputError, UsageError
from ..limits import MAX_JOBS, MAX_MAGNITUDE, parse_decimal, quote

#: Let negative numbers through as plain arguments (``kincalc fk puma560 0 -45``):
#: click would otherwise read "-45" as the short options -4 -5.
NUMERIC_ARGS = {"ignore_unknown_options": True, "help_option_names": ["-h", "--help"]}


class FileName(click.ParamType):
    """A file name, as typed (no check here: the command reports a missing file in its
    own words); the shell completes it from the files there."""

    name = "file"

    def convert(self, value, param, ctx):
        return value

    def shell_complete(self, ctx, param, incomplete):
        from click.shell_completion import CompletionItem
        return [CompletionItem(incomplete, type="file")]


class Words(click.ParamType):
    """A word of a few, as typed (the command checks it, in its own words); the shell
    completes the ``words`` (a tuple, or a function giving them: computed at TAB only) that
    start with what is typed."""

    name = "text"

    def __init__(self, words):
        self.words = words

    def convert(self, value, param, ctx):
        return value

    def shell_complete(self, ctx, param, incomplete):
        from click.shell_completion import CompletionItem
        words = self.words() if callable(self.words) else self.words
        return [CompletionItem(w) for w in words if w.startswith(incomplete)]


class Decimal(click.ParamType):
    """A number on the command line, read strictly (:func:`~kincalc.limits.parse_decimal`):
    click's float type also takes ``1_0`` (as 10) and other scripts' digits. ``bounds``
    ``(lo, hi)`` bound it, both included (as click's ``min=`` and ``max=``, which a type
    given as ``click_type`` replaces)."""

    name = "float"

    def __init__(self, bounds: tuple[float, float] | None = None):
        self.bounds = bounds

    def convert(self, value, param, ctx):
        if not isinstance(value, float):
            try:
                value = parse_decimal(str(value).strip())
            except ValueError:
                self.fail(f"{value!r} is not a number", param, ctx)
        if self.bounds is not None and not self.bounds[0] <= value <= self.bounds[1]:
            lo, hi = self.bounds
            self.fail(f"{value:g} is not in the range {lo:g} to {hi:g}", param, ctx)
        return value


#: the type of every number option (``click_type=NUMBER``)
NUMBER = Decimal()


class Integer(click.ParamType):
    """A whole number on the command line, read strictly: decimal ASCII digits with an
    optional sign (click's int type also takes ``1_0`` and other scripts' digits), within
    ``lo .. hi``, both included (as click's ``min=`` and ``max=``, which a type given as
    ``click_type`` replaces); ``hi`` is ``MAX_MAGNITUDE`` (1e9), as for every number, unless
    given (a seed's is 2^63 - 1: :data:`SEED`)."""

    name = "integer"

    def __init__(self, lo: int = 0, hi: int = int(MAX_MAGNITUDE)):
        self.lo, self.hi = lo, hi

    def convert(self, value, param, ctx):
        if isinstance(value, int) and not isinstance(value, bool):
            number = value
        else:
            text = str(value).strip(" \t")
            if not _WHOLE.fullmatch(text):
                self.fail(f"{quote(value)} is not a whole number", param, ctx)
            number = int(text) if len(text) <= 24 else self.hi + 1
        if not self.lo <= number <= self.hi:
            self.fail(f"{quote(value)} is not in the range {self.lo} to {self.hi}", param, ctx)
        return number


_WHOLE = re.compile(r"[+-]?[0-9]+", re.ASCII)

#: the type of a seed: a roster's student seeds are 48-bit (``int(sha256(...)[:12], 16)``)
SEED = Integer(0, 2 ** 63 - 1)


class RobotName(FileName):
    """A bundled robot's name or a robot file; the shell completes the bundled names that
    start with what is typed, else file names."""

    name = "robot"

    def shell_complete(self, ctx, param, incomplete):
        if "/" not in incomplete:
            from click.shell_completion import CompletionItem

            from ..conventions.library import bundled_names
            names = [n for n in bundled_names() if n.startswith(incomplete)]
            if names:
                return [CompletionItem(n) for n in names]
        return super().shell_complete(ctx, param, incomplete)


RobotArg = Annotated[str, typer.Argument(
    metavar="ROBOT", show_default=False, click_type=RobotName(),
    help="A bundled robot's name (see 'kincalc robots list'), a path to a robot YAML file or "
         "a URDF file (.urdf).")]
JointsArg = Annotated[Optional[List[str]], typer.Argument(
    metavar="Q...", show_default=False,
    help="Joint values in order: revolute in the angle unit, prismatic in the length unit. "
         "Negative values need no '--'. Default: the robot's home configuration.")]
DegOpt = Annotated[bool, typer.Option(
    "--deg/--rad", help="Angles in and out in degrees (default) or radians.")]
UnitOpt = Annotated[Optional[str], typer.Option(
    "--unit", metavar="UNIT", show_default=False, click_type=Words(("m", "cm", "mm", "in")),
    help="Length unit for input and output: m, cm, mm or in. Default: the robot file's unit.")]
PrecisionOpt = Annotated[int, typer.Option(
    "--precision", metavar="N", click_type=Integer(0, 17), help="Decimals shown in tables.")]
JsonOpt = Annotated[bool, typer.Option(
    "--json", help="Print one JSON document instead of tables (its fields: README, "
                   "\"JSON output\", and the command's man page).")]
DebugOpt = Annotated[bool, typer.Option(
    "--debug", help="Show a Python traceback on errors.")]
BaseLinkOpt = Annotated[Optional[str], typer.Option(
    "--base-link", metavar="LINK", show_default=False,
    help="URDF robots: the link the chain starts from (default: the tree's root).")]
StructureTolOpt = Annotated[Optional[float], typer.Option(
    "--structure-tol", metavar="TOL", show_default=False, click_type=Decimal((1e-12, 0.1)),
    help="How nearly axes must meet (fraction of the arm's size) or be parallel (sine of "
         "their angle) to count as a structure the closed forms use; the nearest "
         "structured robot is solved and every answer refined on this one. Default 1e-4, at "
         "most 0.1.")]
LockOpt = Annotated[Optional[List[str]], typer.Option(
    "--lock", metavar="JOINT=VALUE", show_default=False,
    help="Hold a joint at a value (its name or number, the value in the angle or length "
         "unit; repeatable): the other joints are solved with every branch, as for an arm "
         "of that many joints. For redundant arms.")]
TipLinkOpt = Annotated[Optional[str], typer.Option(
    "--tip-link", metavar="LINK", show_default=False,
    help="URDF robots: the link the chain ends at (default: the end of the one chain of "
         "moving joints; a tree that branches asks for it).")]
BatchOpt = Annotated[Optional[str], typer.Option(
    "--batch", metavar="FILE", show_default=False, click_type=FileName(),
    help="Answer every record of FILE ('-' for stdin), one output line per record, in order: "
         "JSON lines ({\"q\": [...]}; for ik and reach any pose: {\"xyz\": [...], \"rpy\": "
         "[...]}, {\"T\": ...}, ...) or CSV with a header (joint columns by name; x,y,z with "
         "roll,pitch,yaw or qw,qx,qy,qz). Each non-blank line is a record (in CSV, after the "
         "header); a line longer than 64 KiB, not UTF-8, or with a value that is not a finite "
         "number within 1e9 gets an error record, and the run goes on (exit 2 then).")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Let the output replace an existing regular file (never a link, a device "
                    "or one of the command's own input files).")]
FormatOpt = Annotated[str, typer.Option(
    "--format", metavar="jsonl|csv", click_type=Words(("jsonl", "csv")),
    help="Output format of --batch.")]
InputFormatOpt = Annotated[str, typer.Option(
    "--input-format", metavar="auto|jsonl|csv", click_type=Words(("auto", "jsonl", "csv")),
    help="Input format of --batch. auto: a name ending in .jsonl or .ndjson is JSON lines, "
         "one ending in .csv is CSV; otherwise (and for stdin) CSV when the first non-blank "
         "line is a header of column names, else JSON lines.")]
DpiOpt = Annotated[int, typer.Option(
    "--dpi", metavar="N", click_type=Integer(10, 1200),
    help="Pixels per inch of a PNG plot, 10 to 1200 (one 5-inch panel is 5N pixels square).")]
JobsOpt = Annotated[int, typer.Option(
    "--jobs", "-j", metavar="N", click_type=Integer(1, MAX_JOBS),
    help=f"With --batch: solve chunks of records in N processes, N at most {MAX_JOBS} "
         "(output order kept).")]


def joints_text(count: int) -> str:
    """``"1 joint"``, ``"6 joints"``: a robot's joint count in words."""
    return f"{count} joint{'' if count == 1 else 's'}"


def display_units(robot, deg: bool, unit: str | None):
    """The :class:`~kincalc.analysis.results.Units` chosen by ``--deg/--rad`` and ``--unit``."""
    from ..analysis.results import Units
    from ..units import LENGTH_UNITS
    if unit is not None:
        if unit not in LENGTH_UNITS or unit == "unitless":
            allowed = ", ".join(u for u in LENGTH_UNITS if u != "unitless")
            raise InputError(f"--unit must be one of {allowed}, not {unit!r}")
        if robot.length_unit == "unitless":
            raise InputError(f"robot {robot.name!r} is unitless (a textbook robot); "
                             "--unit does not apply")
    return Units(angle="deg" if deg else "rad", length=unit or robot.length_unit)


def value_tokens(text: str, option: str) -> list[str]:
    """The values of an option that takes them in one string (``--from-q "0 -45 180"``),
    apart by spaces or commas; an empty value between two commas or at an end is refused
    (not dropped: ``"10,,20"`` would otherwise be two values)."""
    parts = text.split(",")
    tokens = [part.split() for part in parts]
    if any(tokens) and not all(tokens):          # (none at all: too few values, said later)
        k = next(i for i, t in enumerate(tokens) if not t)
        raise InputError(f"{option}: value {k + 1} is empty (values go apart by spaces or "
                         "single commas)")
    return [t for part in tokens for t in part]


def refuse_unknown_option(token) -> None:
    """Refuse, as click would, a token of a command's free values (its joint values, which
    may be negative) that is no number but looks like an option (``--frobnicate``)."""
    if isinstance(token, str) and token.startswith("-"):
        try:
            parse_decimal(token.strip())
        except ValueError:
            hint = _suggest_option(token)
            if hint == f" (did you mean {token}?)":      # an option, given after '--'
                raise UsageError(f"{token} comes after '--', where every word is a joint "
                                 f"value: give options before '--'") from None
            raise UsageError(f"no such option: {token}{hint}"
                             f" (see '{_command_path()} --help')") from None


def parse_joints(tokens: list[str] | None, robot, units, option: str | None = None):
    """Joint values from the command line, converted to SI; home when none are given as
    Q arguments.

    ``option`` names the option (``--near``, ``--from-q``) or record field (``q``) the
    values came with, for error messages; given one, no values at all (``--from-q ''``,
    ``{"q": []}``) are too few values, not the home configuration."""
    import numpy as np
    where = f"{option}: " if option else ""
    if not tokens and option is None:
        return np.array(robot.home, dtype=float)
    values = []
    for tok in tokens:
        try:
            values.append(parse_decimal(tok.strip()))
        except ValueError:
            refuse_unknown_option(tok)
            raise InputError(f"{where}joint value {tok!r} is not a number") from None
    if len(values) != robot.dof:
        raise InputError(f"{where}{robot.name} has {robot.dof} joints "
                         f"({', '.join(j.name for j in robot.joints)}), "
                         f"got {len(values)} joint value{'s' if len(values) != 1 else ''}")
    for joint, value in zip(robot.joints, values):
        check_number(value, f"{where}joint {joint.name}")
    q = np.array(values)
    return q / np.where(robot.is_revolute, units.a, units.l)


def parse_locks(items: list[str] | None, robot, units) -> dict:
    """``--lock JOINT=VALUE`` options as ``{joint index (0-based): value (SI)}``; JOINT
    is a joint's name or its number (1-based), VALUE in the user's units."""
    from ..limits import quote
    locks = {}
    names = [j.name for j in robot.joints]
    for item in items or []:
        joint, sep, value = item.partition("=")
        joint = joint.strip()
        if not sep or not joint or not value.strip():
            raise InputError(f"--lock: {quote(item)} is not JOINT=VALUE (a joint name or "
                             "number, then its value)")
        k = joint_index(joint, robot, "--lock")
        if k in locks:
            raise InputError(f"--lock: joint {names[k]} is locked twice")
        try:
            v = parse_decimal(value.strip())
        except ValueError:
            raise InputError(f"--lock: value {quote(value.strip())} of joint {names[k]} is "
                             "not a number") from None
        check_number(v, f"--lock: joint {names[k]}")
        locks[k] = v / (units.a if robot.joints[k].revolute else units.l)
    if locks and len(locks) >= robot.dof:
        raise InputError(f"--lock: every joint of {robot.name} is locked; nothing is left "
                         "to solve")
    return locks


def joint_index(joint: str, robot, option: str) -> int:
    """The 0-based index of the joint a user named (its name, or its number from 1)."""
    from ..limits import quote
    names = [j.name for j in robot.joints]
    joint = joint.strip()
    if joint in names:
        return names.index(joint)
    if joint.isdigit() and 1 <= int(joint) <= robot.dof:
        return int(joint) - 1
    raise InputError(f"{option}: {robot.name} has no joint {quote(joint)} (joints "
                     f"{', '.join(names)}, or 1..{robot.dof})")


def check_number(value: float, what: str) -> float:
    """``value`` if it is finite and within :data:`~kincalc.limits.MAX_MAGNITUDE` (the
    limit robot files have), else an :class:`InputError` naming ``what``.

    Every number from the command line passes here, in the user's units, before any
    arithmetic: beyond the limit, products overflow to inf and NaN (numpy warnings on
    stderr, ``q3=inf`` in tables, JSON that cannot be written)."""
    import math

    if not math.isfinite(value):       # (1e400 reads as inf: not the text, which is gone)
        raise InputError(f"{what}: not a finite number (nan, inf, or beyond 1.8e308)")
    if abs(value) > MAX_MAGNITUDE:      # (all of the value: 1.000000001e9 is not 1e+09)
        raise InputError(f"{what}: {value!r} is too large (kincalc takes numbers up to "
                         f"{MAX_MAGNITUDE:g} in size)")
    return value


def check_numbers(values, what: str) -> None:
    """:func:`check_number` for each of ``values`` (an option's numbers)."""
    for v in values:
        check_number(float(v), what)


def _suggest_option(token: str) -> str:
    """" (did you mean --frames?)" for a mistyped option of the running command."""
    import difflib

    import click
    ctx = click.get_current_context(silent=True)
    if ctx is None:
        return ""
    names = [o for p in ctx.command.params for o in getattr(p, "opts", []) + getattr(p, "secondary_opts", [])
             if o.startswith("--")]
    close = difflib.get_close_matches(token, names, n=1)
    return f" (did you mean {close[0]}?)" if close else ""


def _command_path() -> str:
    import click
    ctx = click.get_current_context(silent=True)
    return ctx.command_path if ctx is not None else "kincalc"


def output_target(path: str, option: str, force: bool, robot: str | None = None,
                  files=()):
    """The :class:`kincalc.outputs.Target` of an output option, knowing the command's
    input files: the robot file of ``robot`` (a name or a path) and each ``(option,
    path)`` of ``files`` (``-`` and None skipped), none of which it may write."""
    from ..outputs import Target
    inputs = []
    if robot is not None:
        inputs.append(("the robot file", robot_file(robot)))
    inputs += [(f"the {opt} file", p) for opt, p in files if p not in (None, "-")]
    return Target(path, option, force, tuple(inputs))


def robot_file(robot: str) -> str | None:
    """The file a ROBOT argument names (a bundled robot's too), or None if none."""
    from ..errors import KincalcError
    from ..conventions.library import resolve
    try:
        return str(resolve(robot)[0])
    except KincalcError:
        return None


def load_robot(name: str, base_link: str | None = None, tip_link: str | None = None,
               structure_tol: float | None = None):
    """The robot ``name`` (bundled name, robot file or URDF); the links choose a URDF's
    chain and are refused for a robot that is not a URDF; ``structure_tol`` (when given)
    becomes the robot's :attr:`~kincalc.model.Robot.structure_tol`."""
    import dataclasses

    from ..conventions.library import load
    import math
    if structure_tol is not None and not math.isfinite(structure_tol):
        raise InputError(f"--structure-tol: {structure_tol} is not a finite number")
    robot = load(name, base_link=base_link, tip_link=tip_link)
    return robot if structure_tol is None else \
        dataclasses.replace(robot, structure_tol=structure_tol)


def output(doc: dict, json: bool, tables, *args) -> None:
    """Print ``doc`` as one JSON document, or call ``tables(doc, *args)`` for people."""
    if json:
        from .render import emit_json
        emit_json(doc)
    else:
        tables(doc, *args)
