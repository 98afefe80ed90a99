"""The ``kincalc`` command: the typer app and the one place errors become exit codes.

Exit statuses (PRODUCT.md): 0 done; 1 a well-formed question answered "no";
2 bad input or usage (one line on stderr); 3 an internal error (a bug); 130 Ctrl-C;
141 (128 + SIGPIPE, as a shell reports it) stdout closed before the output was written
(``kincalc ... | head -1``), quietly.
"""

from __future__ import annotations

import contextlib
import errno
import re
import signal
import sys

import click
import typer
from typer.core import TyperGroup

from ..limits import one_line
from ..version import __version__

from .common import NUMERIC_ARGS

_HELP = {"help_option_names": ["-h", "--help"]}

#: The commands, in the order of ``kincalc --help``: name -> (module of kincalc.cli,
#: its function or ``app`` for a group, context settings, the short help). A command's
#: module is imported only when that command runs (or shows its own help), so start-up
#: pays for one command, not fourteen. The short help is the first sentence of the
#: command's docstring; tests/cli/test_cli.py checks that the two agree.
COMMANDS = {
    "fk": ("fk", "fk", NUMERIC_ARGS,
           "Forward kinematics: the tool pose for joint values Q."),
    "jacobian": ("jacobian", "jacobian", NUMERIC_ARGS,
                 "Geometric Jacobian (6 x n, rows vx vy vz wx wy wz) at joint values Q."),
    "ik": ("ik", "ik", _HELP,
           "Inverse kinematics: every joint solution that reaches a pose."),
    "reach": ("reach", "reach", _HELP,
              "Reachability: can the robot reach a pose, and if not, why."),
    "workspace": ("workspace", "workspace", None,
                  "Workspace: Monte-Carlo sampling of the joint space within the limits."),
    "plot": ("plot", "plot", NUMERIC_ARGS,
             "Draw ROBOT at joint values Q into FILE (PNG, SVG or PDF)."),
    "view": ("view", "view", NUMERIC_ARGS,
             "Write an interactive 3D page of ROBOT: joint sliders, the live tool pose, IK "
             "branches."),
    "quiz": ("quiz", "quiz", None,
             "Write a random exercise sheet for ROBOT (the format 'kincalc check' grades)."),
    "check": ("check", "check", None,
              "Grade homework sheets: each answer right or wrong, with hints and a score."),
    "compare": ("compare", "compare", None,
                "Are ROBOT_A and ROBOT_B the same robot (same tool pose for every joint value)?"),
    "convert": ("convert", "convert", None,
                "Rewrite ROBOT in another convention: standard DH, modified DH or product of "
                "exponentials (poe; a URDF file reads as poe)."),
    "selftest": ("selftest", "selftest", None,
                 "Check IK on random configurations within the limits (IKFast's --iktests "
                 "metrics)."),
    "robots": ("robots", "app", None, "The robot library: list, show and validate robot files."),
    "completion": ("completion", "completion", None,
                   "Print the shell completion script for bash, zsh or fish."),
}


class _Group(TyperGroup):
    """A kincalc command group: one "No such command" message, and opposite flags
    (``--deg`` and ``--rad``) refused when both are given."""

    def resolve_command(self, ctx, args):
        if ctx.resilient_parsing:            # shell completion: never fail
            return super().resolve_command(ctx, args)
        if args and not args[0].startswith("-") and self.get_command(ctx, args[0]) is None:
            # one message with the suggestions (click >= 8.4 adds its own "Did you mean"
            # and typer another: they said it twice)
            import difflib
            near = difflib.get_close_matches(args[0], self.list_commands(ctx))
            hint = f" Did you mean {', '.join(repr(m) for m in near)}?" if near else ""
            raise click.UsageError(f"No such command '{args[0]}'.{hint}", ctx)
        name, cmd, rest = super().resolve_command(ctx, args)
        if cmd is not None and not isinstance(cmd, click.Group) and \
                not {"-h", "--help"} & set(rest):               # help first, as click does
            problem = _given_twice(cmd, rest) or _without_batch(cmd, rest)
            if problem:
                raise click.UsageError(problem, click.Context(cmd, info_name=name, parent=ctx))
        return name, cmd, rest


class _LazyGroup(_Group):
    """The root group: commands built from :data:`COMMANDS` on first use."""

    def list_commands(self, ctx) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx, name):
        if name not in COMMANDS:
            return None
        if name not in self.commands:
            self.commands[name] = _build(name)
        return self.commands[name]

    def format_commands(self, ctx, formatter) -> None:
        # click's layout, from the table (building every command would import them all)
        width = formatter.width - 6 - max(len(n) for n in COMMANDS)
        rows = [(name, click.Command(name, help=text).get_short_help_str(width))
                for name, (_, _, _, text) in COMMANDS.items()]
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def shell_complete(self, ctx, incomplete):
        # command names from the table, as format_commands does (click would build and
        # import every command on each TAB), then the root's own options
        from click.shell_completion import CompletionItem
        items = [CompletionItem(name, help=text) for name, (_, _, _, text) in COMMANDS.items()
                 if name.startswith(incomplete)]
        return items + click.Command.shell_complete(self, ctx, incomplete)

    def _main_shell_completion(self, ctx_args, prog_name, complete_var=None):
        # click's protocol (_KINCALC_COMPLETE=bash_complete, zsh_complete, fish_complete),
        # which the scripts of 'kincalc completion SHELL' speak; typer's override expects
        # its own scripts. Costs one environment lookup when not completing. A TAB never
        # prints an error (the words typed so far are half a command line, the shell's
        # variables may be anything, KINCALC_ROBOTS a folder not made yet): nothing offered.
        try:
            click.Command._main_shell_completion(self, ctx_args, prog_name, complete_var)
        except SystemExit:
            raise
        except Exception:                           # (no completions, status 1)
            sys.exit(1)


#: the options that only a --batch run reads
BATCH_ONLY = ("--jobs", "--input-format")


def _without_batch(command, args) -> str | None:
    """Why ``args`` give an option of :data:`BATCH_ONLY` without ``--batch`` (which then
    went unread), or None."""
    given, param = _options_given(command, args)
    batch = param.get("--batch")
    if batch is None or any(param[g] is batch for g in given):
        return None
    for g in given:
        if set(param[g].opts) & set(BATCH_ONLY):
            return f"{g} applies to --batch runs only; give --batch FILE, or leave {g} out"
    return None


def _options_given(command, args) -> tuple[list, dict]:
    """The options of ``command`` that ``args`` give, in order (as written: ``--opt`` of
    ``--opt=value``), and each option string's click parameter. Values of options are
    skipped as click consumes them (``--unit --rad`` gives --unit the value '--rad'), and
    ``--`` ends options."""
    takes, param = {}, {}
    for p in command.params:
        if isinstance(p, click.Option):
            for o in p.opts + p.secondary_opts:
                takes[o] = 0 if p.is_flag or p.count else p.nargs
                param[o] = p
    given, i = [], 0
    while i < len(args) and args[i] != "--":
        word = args[i].split("=", 1)[0] if args[i].startswith("--") else args[i]
        if word in takes:
            given.append(word)
            i += takes[word] if word == args[i] else 0
        i += 1
    return given, param


def _given_twice(command, args) -> str | None:
    """Why ``args`` give an option of ``command`` twice, or None: an on/off flag pair both
    ways (``--deg`` and ``--rad``), or an option that takes one value given two (``--rpy 0
    0 0 --rpy 1 1 1``; the ``multiple`` ones, ``--lock``, excepted).

    click keeps the last silently (the options as :func:`_options_given` reads them)."""
    given, param = _options_given(command, args)
    seen = {}
    for o in given:
        p = param[o]
        if id(p) not in seen:
            seen[id(p)] = o
            continue
        first = seen[id(p)]
        if p.multiple or p.count:
            continue
        if p.is_flag and p.secondary_opts and (first in p.opts) != (o in p.opts):
            return f"{first} and {o} contradict each other; give one of them"
        if not p.is_flag:
            return f"{o} is given twice; give it once"
    return None


def _build(name: str):
    """The click command of ``name`` (imports its module)."""
    import importlib
    module, attr, settings, _ = COMMANDS[name]
    target = getattr(importlib.import_module(f"{__package__}.{module}"), attr)
    if isinstance(target, typer.Typer):                      # a command group (robots)
        target.info.cls = _Group
        cmd = typer.main.get_command(target)
        cmd.name = name
        return cmd
    one = typer.Typer(add_completion=False, rich_markup_mode=None)
    one.command(name, **({"context_settings": settings} if settings else {}))(target)
    return typer.main.get_command(one)


app = typer.Typer(
    name="kincalc",
    cls=_LazyGroup,
    help="Robot kinematics calculator: forward and inverse kinematics, Jacobians and robot files. "
         "ROBOT is a bundled robot's name or a path to a YAML robot file.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain click help: rich.markdown costs ~60 ms of start-up
    context_settings=_HELP,
)


def _version(value: bool):
    if value:
        sys.stdout.write(f"kincalc {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """Robot kinematics calculator."""


def main(argv: list[str] | None = None) -> int:
    """Run kincalc with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    import click

    from ..errors import KincalcError
    from ..limits import inputs_recorded

    args = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args
    _quiet_numeric_warnings(debug)
    _closed_streams()
    handler = signal.getsignal(signal.SIGINT)
    try:
        with inputs_recorded():         # no output of this run replaces a file it read
            status = _run(args, debug, click, KincalcError)
            if status == 130:           # interrupted: the next Ctrl-Cs are ignored until
                with contextlib.suppress(ValueError):       # the program ends (one in its
                    signal.signal(signal.SIGINT, signal.SIG_IGN)  # teardown: a traceback)
            return status
    finally:
        # (a caller in this process gets its handler back)
        if argv is not None and handler is not None and \
                signal.getsignal(signal.SIGINT) is not handler:
            with contextlib.suppress(ValueError):
                signal.signal(signal.SIGINT, handler)


def _run(args: list, debug: bool, click, KincalcError) -> int:
    """:func:`main`'s run of the command line ``args``: the exit status, every error worded."""
    try:
        # in non-standalone mode click returns the code of a typer.Exit instead of raising
        # (and typer turns a KeyboardInterrupt into Exit(130), quietly)
        status = app(args=gathered(args), prog_name="kincalc", standalone_mode=False)
        sys.stdout.flush()          # (a write that fails fails here, not at the exit)
        return status if isinstance(status, int) else 0
    except SystemExit as exc:
        # typer and click meet a closed stdout (EPIPE) with sys.exit(1), which the README
        # defines as "the answer was no": a closed pipe is not an answer
        if isinstance(exc.__context__, BrokenPipeError):
            return _stdout_closed()
        raise
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except click.exceptions.Abort:
        sys.stderr.write("kincalc: aborted\n")
        return 130
    except click.exceptions.UsageError as exc:       # (no traceback: the line says it all)
        cmd = exc.ctx.command_path if exc.ctx is not None else "kincalc"
        if cmd == "kincalc" and args and args[0] in COMMANDS:
            cmd = f"kincalc {args[0]}"   # an option error inside a command names the command
        if type(exc).__name__ == "NoArgsIsHelpError":  # bare `kincalc` or `kincalc robots`
            sys.stderr.write(f"{cmd}: error: missing command (see '{cmd} --help')\n")
            return 2
        sys.stderr.write(f"{cmd}: error: {one_line(exc.format_message())} "
                         f"(see '{cmd} --help')\n")
        return 2
    except click.exceptions.ClickException as exc:
        _traceback(debug)
        sys.stderr.write(f"kincalc: error: {one_line(exc.format_message())}\n")
        return 2
    except KincalcError as exc:
        _traceback(debug)
        sys.stderr.write(f"kincalc: error: {one_line(_words(exc))}\n")
        return exc.exit_status
    except BrokenPipeError:
        return _stdout_closed()
    except KeyboardInterrupt:
        return 130
    except Exception as exc:  # a bug: say so, and how to see it
        _traceback(debug)
        if _unwritable(exc):        # (not a bug: the system refused the output)
            sys.stderr.write(f"kincalc: error: cannot write the output: {_write_error(exc)}\n")
            return 2
        sys.stderr.write(f"kincalc: internal error: {type(exc).__name__}: {one_line(str(exc))}. "
                         "This is a bug in kincalc; rerun with --debug for a traceback and "
                         "report it.\n")
        return 3


#: options that take joint values in one argument (``--from-q '0 -45 180 0 45 0'``), and the
#: commands with no joint values of their own, where the values may also follow as words
ONE_ARGUMENT_VALUES = ("--from-q", "--near")
VALUES_AS_WORDS = ("ik", "reach")


#: a word that is a long option's name, not a value (``--near``; ``--`` itself)
_OPTION = re.compile(r"--([A-Za-z]|$)")


def gathered(args: list) -> list:
    """``args`` with the numbers that follow ``--from-q`` or ``--near`` (or their
    ``--from-q=0`` form) as words of their own (``kincalc ik puma560 --from-q 0 -45 180 0
    45 0``) joined into the option's one argument, for the commands of
    :data:`VALUES_AS_WORDS`: the parser would read ``-45`` as an option. A word that is no
    decimal number ends the values; nothing after ``--`` is touched (and another command's
    words never are: ``view`` takes joint values of its own)."""
    if not args or args[0] not in VALUES_AS_WORDS:
        return args
    from ..limits import DECIMAL
    out, k = [], 0
    while k < len(args):
        word = args[k]
        k += 1
        if word == "--":
            return out + [word] + args[k:]
        name, equals, value = word.partition("=")
        if name not in ONE_ARGUMENT_VALUES or not equals and k == len(args):
            out.append(word)
            continue
        if not equals:                          # the value is the next word
            value, k = args[k], k + 1
            if value == "--" or _OPTION.match(value):
                raise click.UsageError(f"Option '{name}' requires an argument: its joint "
                                       "values, before the next option")
        values = [value]
        while k < len(args) and DECIMAL.fullmatch(args[k]):
            values.append(args[k])
            k += 1
        out += [name, " ".join(values)]
    return out


def _traceback(debug: bool) -> None:
    """With ``--debug``, the traceback of the error being handled on stderr (the exit
    status stays the error's: 2 for bad input, 3 for a bug)."""
    if debug:
        import traceback
        traceback.print_exc()


class _Closed:
    """A standard output that was closed before kincalc started (``>&-``: Python then has
    None for it): writing it fails as a closed descriptor does (EBADF), which the run words
    as one line and exit status 2; it is no terminal."""

    encoding = "utf-8"

    def __init__(self, name: str):
        self.name = name

    def _closed(self, *_args):
        raise OSError(errno.EBADF, f"{self.name} is closed")

    write = fileno = _closed

    def isatty(self) -> bool:
        return False

    def flush(self) -> None:
        pass


def _closed_streams() -> None:
    """Put :class:`_Closed` in place of a stdout that was closed when the program started; a
    closed stderr takes /dev/null (there is nowhere to say anything, and the exit status
    still tells). (A closed stdin stays None: its readers say that there is none.)"""
    import os
    if sys.stdout is None:
        sys.stdout = _Closed("standard output")
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")


#: how the command line names the parts of an IK target, for the core's messages about
#: them (:class:`kincalc.errors.TargetMismatch`)
TARGET_WORDS = {"approach": "--approach", "tcv": "--tcv", "prefix": "{field}: ",
                "orientation": "(--rpy, --euler-zyz, --euler-xyz, --quat, --axis-angle, "
                               "--matrix, --pose or --from-q)"}


def _words(exc) -> str:
    """The message of a core error, in the command line's words where it has fields."""
    from ..errors import BadValue, TargetMismatch
    if isinstance(exc, TargetMismatch):
        return exc.words(TARGET_WORDS)
    if isinstance(exc, BadValue):
        from .targets import option_name
        return exc.words(option_name)
    return str(exc)


def _quiet_numeric_warnings(debug: bool) -> None:
    """Keep numpy's RuntimeWarnings (overflow, invalid value) off the user's stderr,
    except with --debug.

    A backstop: command-line numbers are bounded (:func:`kincalc.cli.common.check_number`)
    so that no computation overflows, and the core silences the divisions it expects to
    degenerate with ``np.errstate``. numpy's warnings are the built-in RuntimeWarning, so
    this needs no numpy import at start-up. The filter is process-wide: ``main`` is the
    program (tests that call it run under pytest, which restores the filters per test)."""
    if not debug:
        import warnings
        warnings.filterwarnings("ignore", category=RuntimeWarning)


#: the exit status when stdout is closed early: 128 + SIGPIPE, what a shell reports for a
#: program a closed pipe stops (``cat big | head -1``)
EXIT_STDOUT_CLOSED = 141


def _stdout_closed() -> int:
    """Leave quietly after stdout was closed by its reader: point the stdout descriptor
    at /dev/null, so that the interpreter's last flush of what is still buffered does not
    fail (and print) again, and return :data:`EXIT_STDOUT_CLOSED`."""
    import os
    try:
        fd = sys.stdout.fileno()            # (through typer's wrapper, if it put one on)
        null = os.open(os.devnull, os.O_WRONLY)
    except (AttributeError, OSError, ValueError):    # not a real stdout (a test's)
        return EXIT_STDOUT_CLOSED
    os.dup2(null, fd)
    os.close(null)
    return EXIT_STDOUT_CLOSED


#: the errors of a write the system refused: the output's device or file system, not kincalc
#: (no space, quota, file too large, an I/O error, a read-only file system, a closed
#: descriptor)
WRITE_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EIO, errno.EROFS, errno.EBADF}


def _unwritable(exc: BaseException) -> bool:
    """Is ``exc`` an output the system would not take (:data:`WRITE_ERRNOS`, or text the
    output's encoding cannot hold), rather than a bug?"""
    if isinstance(exc, UnicodeEncodeError):
        return True
    return isinstance(exc, OSError) and exc.errno in WRITE_ERRNOS


def _write_error(exc: BaseException) -> str:
    """The reason of :func:`_unwritable` ``exc`` in words."""
    if isinstance(exc, UnicodeEncodeError):
        return (f"the output's encoding ({exc.encoding}) cannot hold its text; "
                "set PYTHONIOENCODING=utf-8")
    return exc.strerror or str(exc)


def run() -> None:  # pragma: no cover - console-script shim
    sys.exit(main())
