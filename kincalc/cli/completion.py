"""``kincalc completion SHELL``: the shell completion script for bash, zsh or fish."""

from __future__ import annotations

from enum import Enum
from typing import Annotated

import typer

from .common import DebugOpt


class Shell(str, Enum):
    bash = "bash"
    zsh = "zsh"
    fish = "fish"


def completion(
    shell: Annotated[Shell, typer.Argument(
        metavar="SHELL", show_default=False, help="bash, zsh or fish.")],
    debug: DebugOpt = False,
):
    """Print the shell completion script for bash, zsh or fish.

    The script completes command names, options, choices and bundled robot
    names by asking kincalc itself (through the _KINCALC_COMPLETE variable),
    so it stays right as kincalc changes. Install it once:

    bash: kincalc completion bash > ~/.local/share/bash-completion/completions/kincalc

    zsh: kincalc completion zsh > ~/.zfunc/_kincalc (with fpath+=(~/.zfunc) before
    compinit in ~/.zshrc)

    fish: kincalc completion fish > ~/.config/fish/completions/kincalc.fish

    or load it in the shell's start-up file: eval "$(kincalc completion bash)".
    """
    import sys

    import click
    from click.shell_completion import get_completion_class
    root = click.get_current_context().find_root()
    script = get_completion_class(shell.value)(root.command, {}, root.info_name,
                                               "_KINCALC_COMPLETE").source()
    sys.stdout.write(script.rstrip("\n") + "\n")
