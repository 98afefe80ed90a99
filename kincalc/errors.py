"""Exceptions raised by kincalc.

The core never prints and never exits: it raises a :class:`KincalcError`
subclass whose ``str()`` is the one-line message a user sees. The CLI maps
``exit_status`` to the process exit code (2 for bad input, see PRODUCT.md).
"""

from __future__ import annotations


class KincalcError(Exception):
    """Base class of every error kincalc reports to a user.

    ``exit_status`` is the documented process exit status for this error.
    """

    exit_status = 2

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message

    def __str__(self) -> str:
        return self.message


class UsageError(KincalcError):
    """A command line or API call that does not make sense (exit 2)."""


class BadValue(UsageError):
    """A request's value outside what kincalc takes (exit 2), as data: ``field`` the
    parameter as the Python API names it (``samples``, ``seed``), ``need`` what it must
    be (``"from 1000 to 5000000 (kincalc's limit)"``), ``value`` what was given.
    :meth:`words` names the field as the caller names it (``--samples`` on the command
    line)."""

    def __init__(self, field: str, need: str, value):
        self.field, self.need, self.value = field, need, value
        super().__init__(self.words(lambda f: f))

    def words(self, name) -> str:
        """The message with the field named as the caller names it.

        Parameters
        ----------
        name : callable
            Maps the field's API name (``'samples'``) to the caller's (``'--samples'``).

        Returns
        -------
        str
            ``"<name(field)> must be <need>, not <value!r>"``.
        """
        return f"{name(self.field)} must be {self.need}, not {self.value!r}"


class RobotNotFoundError(KincalcError):
    """Neither a bundled robot name nor a readable file."""

    def __init__(self, name: str, suggestions: list[str] | None = None):
        self.name = name
        self.suggestions = suggestions or []
        hint = ""
        if self.suggestions:
            hint = f"; did you mean {', '.join(repr(s) for s in self.suggestions)}?"
        from .limits import quote
        super().__init__(
            f"no robot named {quote(name)} and no such file{hint} "
            "(see 'kincalc robots list')"
        )


class RobotFileError(KincalcError):
    """A robot file that cannot be read or is not valid.

    Parameters
    ----------
    file : str
        The path as the user gave it.
    line : int or None
        1-based line number of the offending node, when known.
    message : str
        What is wrong, naming the field.
    joint : int or None
        1-based joint number the field belongs to, if any.
    joint_name : str or None
        That joint's ``name``, if known.
    """

    def __init__(
        self,
        file: str,
        line: int | None,
        message: str,
        joint: int | None = None,
        joint_name: str | None = None,
    ):
        self.file = file
        self.line = line
        self.detail = message
        self.joint = joint
        self.joint_name = joint_name
        from .limits import quote
        shown = file if len(str(file)) <= SHOWN_FILE else quote(file, SHOWN_FILE)
        where = shown if line is None else f"{shown}:{line}"
        who = ""
        if joint is not None:
            who = f"joint {joint}" + (f" ({joint_name})" if joint_name else "") + ": "
        #: what is wrong and with which joint, without the file's name and line
        self.what = who + message
        super().__init__(f"{where}: {self.what}")


#: a file name longer than this (characters) is cut in a message
SHOWN_FILE = 300


class InputError(KincalcError):
    """A value given on the command line or to the API is invalid (exit 2)."""


class MissingExtra(KincalcError):
    """An optional dependency (an extra of the kincalc package) is not installed."""

    exit_status = 2

    def __init__(self, command: str, module: str, extra: str):
        self.command = command
        self.module = module
        self.extra = extra
        super().__init__(f"{command} needs {module}, which is not installed: "
                         f"pip install 'kincalc[{extra}]'")


def require_extra(command: str, module: str, extra: str):
    """Import and return ``module``, or raise :class:`MissingExtra` naming ``command`` and
    the extra that installs it.

    Parameters
    ----------
    command : str
        What the user ran, as it should read in the message: ``"kincalc ik --plot"``.
    module : str
        The module to import (``"matplotlib"``).
    extra : str
        The kincalc extra that installs it (``pip install 'kincalc[<extra>]'``).

    Returns
    -------
    module
        The imported module.

    Raises
    ------
    MissingExtra
        ``module`` cannot be imported (any ImportError).
    """
    import importlib
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtra(command, module, extra) from None


class TargetMismatch(UsageError):
    """An IK target of a kind the robot cannot take (exit 2), as data; each edge words it
    in its own vocabulary (:meth:`words`: command-line options, sheet keys, record
    fields).

    ``need``: ``"full orientation"`` (an approach alone for a robot that sets the whole
    orientation), ``"orientation"`` (a position alone for a robot that controls its
    orientation; ``approach_ok``: an approach direction would do), ``"not approach"`` (a
    robot solved numerically, ``why``, given an approach direction), ``"tcv robot"`` (a
    tool configuration vector for a robot without 3 or 4 joints and a revolute last one).
    """

    #: the core's own words: what a target gives, by field
    VOCABULARY = {"approach": "an approach direction", "tcv": "a tool configuration vector",
                  "orientation": "(an orientation in any form)", "prefix": ""}

    def __init__(self, robot: str, need: str, controls: str = "", approach_ok: bool = False,
                 why: str = "", tcv_ok: bool = False):
        self.robot, self.need, self.controls = robot, need, controls
        self.approach_ok, self.tcv_ok, self.why = approach_ok, tcv_ok, why
        super().__init__(self.words(self.VOCABULARY))

    def words(self, w: dict) -> str:
        """The message with the fields named as ``w`` names them.

        Parameters
        ----------
        w : dict of str
            Keys ``approach``, ``tcv``, ``orientation`` (the ways to give one, in
            parentheses) and ``prefix`` (a format string with ``{field}``, e.g.
            ``"{field}: "`` on the command line; ``""`` in :data:`VOCABULARY`).

        Returns
        -------
        str
            The one-line message for this mismatch's ``need``.
        """
        a = w["approach"]
        if self.need == "full orientation":
            return (f"{w['prefix'].format(field=a)}{self.robot} controls {self.controls}; "
                    f"give a full orientation {w['orientation']}")
        if self.need == "orientation":
            return (f"{self.robot} controls {self.controls}: give an orientation too "
                    f"{w['orientation']}"
                    + (f" or {_named('an approach direction', a)}" if self.approach_ok else "")
                    + (f" or {_named('a tool configuration vector', w['tcv'])}"
                       if self.tcv_ok else ""))
        if self.need == "not approach":
            return (f"{w['prefix'].format(field=a)}{self.robot} is solved numerically "
                    f"({self.why}), which needs a full orientation or the position alone")
        return (f"{self.robot}: {w['tcv']} targets need a robot of 3 or 4 joints whose last "
                "joint is revolute (the tool roll); give the pose another way")


def _named(thing: str, field: str) -> str:
    """``thing`` followed by the ``field`` that gives it, unless that is the thing's name."""
    return thing if field == thing else f"{thing} ({field})"


class UnsupportedRobot(KincalcError):
    """A robot (or a target kind) no closed form covers (exit status 2)."""

    exit_status = 2
