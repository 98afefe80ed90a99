"""The ``kincalc`` command: the typer app and the one place errors become exit codes.

Exit statuses (PRODUCT.md): 0 done; 1 a well-formed question answered "no";
2 bad input or usage (one line on stderr); 3 an internal error (a bug).
"""

from __future__ import annotations

import sys

import typer

from .. import __version__
from . import check as _check
from . import compare as _compare
from . import convert as _convert
from . import fk as _fk
from . import ik as _ik
from . import jacobian as _jacobian
from . import plot as _plot
from . import quiz as _quiz
from . import reach as _reach
from . import robots as _robots
from . import selftest as _selftest
from . import workspace as _workspace
from .common import NUMERIC_ARGS

app = typer.Typer(
    name="kincalc",
    help="Robot kinematics calculator: forward and inverse kinematics, Jacobians and robot files. "
         "ROBOT is a bundled robot's name or a path to a YAML robot file.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain click help: rich.markdown costs ~60 ms of start-up
    context_settings={"help_option_names": ["-h", "--help"]},
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


app.command("fk", context_settings=NUMERIC_ARGS)(_fk.fk)
app.command("jacobian", context_settings=NUMERIC_ARGS)(_jacobian.jacobian)
app.command("ik", context_settings={"help_option_names": ["-h", "--help"]})(_ik.ik)
app.command("reach", context_settings={"help_option_names": ["-h", "--help"]})(_reach.reach)
app.command("workspace")(_workspace.workspace)
app.command("plot", context_settings=NUMERIC_ARGS)(_plot.plot)
app.command("quiz")(_quiz.quiz)
app.command("check")(_check.check)
app.command("compare")(_compare.compare)
app.command("convert")(_convert.convert)
app.command("selftest")(_selftest.selftest)
app.add_typer(_robots.app, name="robots")


def main(argv: list[str] | None = None) -> int:
    """Run kincalc with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    import click

    from ..errors import KincalcError

    args = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in args
    try:
        # in non-standalone mode click returns the code of a typer.Exit instead of raising
        status = app(args=args, prog_name="kincalc", standalone_mode=False)
        return status if isinstance(status, int) else 0
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except click.exceptions.Abort:
        sys.stderr.write("kincalc: aborted\n")
        return 130
    except click.exceptions.UsageError as exc:
        if debug:
            raise
        cmd = exc.ctx.command_path if exc.ctx is not None else "kincalc"
        if cmd == "kincalc" and args and not args[0].startswith("-"):
            cmd = f"kincalc {args[0]}"   # an option error inside a command names the command
        if type(exc).__name__ == "NoArgsIsHelpError":  # bare `kincalc` or `kincalc robots`
            sys.stderr.write(f"{cmd}: error: missing command (see '{cmd} --help')\n")
            return 2
        sys.stderr.write(f"{cmd}: error: {_one_line(exc.format_message())} "
                         f"(see '{cmd} --help')\n")
        return 2
    except click.exceptions.ClickException as exc:
        if debug:
            raise
        sys.stderr.write(f"kincalc: error: {_one_line(exc.format_message())}\n")
        return 2
    except KincalcError as exc:
        if debug:
            raise
        sys.stderr.write(f"kincalc: error: {_one_line(str(exc))}\n")
        return exc.exit_status
    except BrokenPipeError:
        return 0
    except KeyboardInterrupt:
        return 130
    except Exception as exc:  # a bug: say so, and how to see it
        if debug:
            raise
        sys.stderr.write(f"kincalc: internal error: {type(exc).__name__}: {_one_line(str(exc))}. "
                         "This is a bug in kincalc; rerun with --debug for a traceback and "
                         "report it.\n")
        return 3


def _one_line(text: str) -> str:
    return " ".join(text.split())


def run() -> None:  # pragma: no cover - console-script shim
    sys.exit(main())
