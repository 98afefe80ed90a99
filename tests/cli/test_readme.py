"""README examples are executed: every `$ kincalc ...` block must print what it shows.

A block's output is compared line by line (trailing spaces ignored) up to a
line reading "..." (the README cut the rest); "(exit status N)" checks the
exit status. Tables are rendered at COLUMNS=100.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).parents[2] / "README.md"
TEXT = README.read_text(encoding="utf-8")


def examples():
    for block in re.findall(r"```\n(\$ kincalc.*?)\n```", TEXT, flags=re.S):
        lines = block.split("\n")
        i = 0
        while i < len(lines):
            if lines[i].startswith("$ kincalc"):
                j = i + 1
                while j < len(lines) and not lines[j].startswith("$ "):
                    j += 1
                yield lines[i][2:], lines[i + 1:j]
                i = j
            else:
                i += 1


CASES = list(examples())


def test_readme_has_an_example_for_every_command():
    commands = {shlex.split(c)[1] for c, _ in CASES}
    subs = {" ".join(shlex.split(c)[1:3]) for c, _ in CASES if shlex.split(c)[1] == "robots"}
    assert {"fk", "jacobian", "ik", "reach", "workspace", "plot", "view", "check", "quiz",
            "compare", "convert", "selftest", "robots"} <= commands
    assert any("--symbolic" in c for c, _ in CASES)
    assert {"robots list", "robots show", "robots validate"} <= subs


@pytest.mark.parametrize("command,shown", CASES, ids=[c for c, _ in CASES])
def test_readme_example_output(command, shown, tmp_path):
    # the files the README shows ("Given this `NAME`:" and a fenced block) are written
    # where the examples run
    for name, body in re.findall(r"Given this `([\w.]+)`:\n\n```\w*\n(.*?)```", TEXT, re.S):
        (tmp_path / name).write_text(body)
    env = dict(os.environ, COLUMNS="100")
    env.pop("NO_COLOR", None)
    argv = [sys.executable, "-m", "kincalc", *shlex.split(command)[1:]]
    p = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True)
    text = (p.stdout + p.stderr).rstrip("\n")
    actual = [line.rstrip() for line in text.split("\n")] if text else []   # quiet: no line
    expected_status = 0
    if shown and shown[-1].startswith("(exit status"):
        expected_status = int(shown[-1].strip("()").split()[-1])
        shown = shown[:-1]
    assert p.returncode == expected_status, p.stderr
    if "..." in shown:
        shown = shown[:shown.index("...")]
        actual = actual[:len(shown)]
    assert actual == [line.rstrip() for line in shown]
