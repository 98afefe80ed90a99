"""Shell completion (issue 14, item 9): ``kincalc completion bash|zsh|fish``.

The scripts are click's; what kincalc must get right is answering them: command names
from the lazy command table (without importing every command), options, choices,
bundled robot names and file names, through the ``_KINCALC_COMPLETE`` protocol the
scripts speak, in a real process as the shell runs it. And start-up stays as it was:
nothing of completion is imported unless completing.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from cli_contract import assert_contract, run_cli

KINCALC = [sys.executable, "-m", "kincalc"]


def complete(shell: str, words: str, cword: int | None = None, cwd=None) -> list[str]:
    """What kincalc answers a ``shell`` script completing the command line ``words``."""
    parts = words.split(" ")
    # bash and zsh send the index of the word being completed, fish the word itself
    where = parts[-1] if shell == "fish" else str(len(parts) - 1 if cword is None else cword)
    env = dict(os.environ, _KINCALC_COMPLETE=f"{shell}_complete", COMP_WORDS=words,
               COMP_CWORD=where)
    r = subprocess.run(KINCALC, env=env, capture_output=True, text=True, timeout=120, cwd=cwd)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    return r.stdout.splitlines()


@pytest.mark.parametrize("shell, marker", [("bash", "_KINCALC_COMPLETE=bash_complete"),
                                           ("zsh", "_KINCALC_COMPLETE=zsh_complete"),
                                           ("fish", "_KINCALC_COMPLETE=fish_complete")])
def test_completion_prints_the_script(shell, marker):
    status, out, err = run_cli(["completion", shell], b"", None)
    assert status == 0 and err == ""
    assert marker in out and "kincalc" in out and out.endswith("\n")


def test_completion_refuses_other_shells():
    argv = ["completion", "tcsh"]
    status, out, err = run_cli(argv, b"", None)
    assert_contract(status, out, err, argv)
    assert status == 2 and "'tcsh' is not one of 'bash', 'zsh', 'fish'" in err


def test_command_names():
    assert complete("bash", "kincalc ") == [f"plain,{c}" for c in (
        "fk", "jacobian", "ik", "reach", "workspace", "plot", "view", "quiz", "check",
        "compare", "convert", "selftest", "robots", "completion")]
    assert complete("bash", "kincalc c") == ["plain,check", "plain,compare", "plain,convert",
                                             "plain,completion"]
    # zsh and fish get each command's one-line summary
    zsh = complete("zsh", "kincalc f")
    assert zsh == ["plain", "fk", "Forward kinematics: the tool pose for joint values Q."]
    assert complete("fish", "kincalc f") == [
        "plain,fk\tForward kinematics: the tool pose for joint values Q."]


def test_sub_commands_options_and_choices():
    assert complete("bash", "kincalc robots ") == ["plain,list", "plain,show", "plain,validate"]
    assert complete("bash", "kincalc fk puma560 --fr") == ["plain,--frames"]
    assert complete("bash", "kincalc jacobian puma560 --frame ") == ["plain,base", "plain,tool"]
    assert "plain,--force" in complete("bash", "kincalc plot puma560 --f")
    assert complete("bash", "kincalc completion ") == ["plain,bash", "plain,zsh", "plain,fish"]


def test_the_words_an_option_takes(tmp_path):
    """The man pages promise the choices of every option that takes a few words; convert
    --to, --unit, --format, --input-format, check --format and robots list --family offered
    none, nor did compare its two robots (hostile-input campaign)."""
    assert complete("bash", "kincalc convert puma560 --to ") == ["plain,dh", "plain,mdh",
                                                                 "plain,poe"]
    assert complete("bash", "kincalc fk puma560 --unit m") == ["plain,m", "plain,mm"]
    assert complete("bash", "kincalc ik puma560 --batch x --format ") == ["plain,jsonl",
                                                                          "plain,csv"]
    assert complete("bash", "kincalc fk puma560 --batch x --input-format a") == ["plain,auto"]
    assert complete("bash", "kincalc check hw.yaml --format g") == ["plain,gradescope"]
    assert complete("bash", "kincalc robots list --family three") == [
        "plain,three-parallel", "plain,three-parallel-offset"]
    assert complete("bash", "kincalc compare puma560 ur5_p") == ["plain,ur5_poe"]


def test_a_tab_never_prints_an_error(tmp_path):
    """A COMP_CWORD that is no number gave an internal error, exit 3, and a robot library
    that does not exist an error line at each TAB: nothing is offered, nothing printed."""
    for env in ({"COMP_CWORD": "abc"}, {"KINCALC_ROBOTS": str(tmp_path / "none")}):
        r = subprocess.run(KINCALC, capture_output=True, text=True, timeout=120, env=dict(
            os.environ, _KINCALC_COMPLETE="bash_complete", COMP_WORDS="kincalc fk p",
            **{"COMP_CWORD": "2", **env}))
        assert r.stderr == "" and r.returncode in (0, 1)


def test_robot_names_then_files(tmp_path):
    assert complete("bash", "kincalc fk puma") == ["plain,puma560", "plain,puma560_mdh"]
    assert complete("bash", "kincalc robots validate ur5_p") == ["plain,ur5_poe"]
    # nothing bundled matches, or a path is being typed: the shell lists files
    assert complete("bash", "kincalc fk ./my", cwd=tmp_path) == ["file,./my"]
    assert complete("bash", "kincalc ik puma560 --pose ") == ["file,"]
    assert complete("bash", "kincalc plot puma560 -o ") == ["file,"]
    assert complete("bash", "kincalc fk puma560 --batch ") == ["file,"]


def test_bash_script_completes_in_bash(tmp_path):
    """The script as bash runs it: source it, press TAB (call its function)."""
    bash = shutil.which("bash")
    kincalc = Path(sys.executable).with_name("kincalc")
    if bash is None or not kincalc.exists():
        pytest.skip("needs bash and the kincalc script of this environment")
    script = subprocess.run([str(kincalc), "completion", "bash"], capture_output=True,
                            text=True, check=True, timeout=120).stdout
    (tmp_path / "kincalc.bash").write_text(script)
    probe = ("source ./kincalc.bash\n"
             "COMP_WORDS=(kincalc rob); COMP_CWORD=1; _kincalc_completion kincalc\n"
             "echo \"${COMPREPLY[*]}\"\n"
             "COMPREPLY=(); COMP_WORDS=(kincalc fk pla); COMP_CWORD=2\n"
             "_kincalc_completion kincalc\n"
             "echo \"${COMPREPLY[*]}\"\n")
    env = dict(os.environ, PATH=f"{kincalc.parent}{os.pathsep}{os.environ.get('PATH', '')}")
    r = subprocess.run([bash, "--norc", "-c", probe], capture_output=True, text=True,
                       cwd=tmp_path, env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == ["robots", "planar_3r"], r.stdout + r.stderr


def test_start_up_imports_no_completion_command():
    """--help, --version and other commands never import the completion command (typer
    itself imports click's completion module whatever kincalc does), and the root does
    no more than look up _KINCALC_COMPLETE: benchmarks/startup.py measures the rest."""
    code = ("import sys, contextlib, io\nfrom kincalc.cli.main import main\n"
            "for args in (['--help'], ['--version'], ['robots', 'validate', 'puma560']):\n"
            "    with contextlib.redirect_stdout(io.StringIO()): main(args)\n"
            "print('kincalc.cli.completion' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120).stdout.strip()
    assert out == "False", out


def test_completing_command_names_builds_no_command():
    code = ("import os, sys\nos.environ.update(_KINCALC_COMPLETE='bash_complete', "
            "COMP_WORDS='kincalc ', COMP_CWORD='1')\n"
            "from kincalc.cli.main import main\n"
            "try:\n    main([])\nexcept SystemExit:\n    pass\n"
            "sys.stderr.write(repr(sorted(m for m in sys.modules if m.startswith('kincalc.cli.')"
            " and m not in ('kincalc.cli.main', 'kincalc.cli.common'))))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=120)
    assert r.stderr == "[]", r.stderr
