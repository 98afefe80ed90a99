"""Record the CLI's output for a fixed corpus of commands, to compare two trees.

    python tests/output_corpus.py OUTDIR [--kincalc PATH]

Runs every command of :func:`corpus` (each bundled robot through ``robots show``,
``fk``, ``jacobian``, ``ik`` as a table and as JSON, ``reach``; the example sheets
through ``check``; a few ``compare``, ``convert``, ``workspace`` and ``quiz``
commands) with a fixed terminal width and writes each one's stdout, stderr and exit
status to ``OUTDIR/NNN.txt``. A refactoring that must not change behaviour is checked
by running it on the tree before and after and comparing the two directories::

    python tests/output_corpus.py /tmp/before      # on the old tree
    python tests/output_corpus.py /tmp/after       # on the new tree
    diff -r /tmp/before /tmp/after

Not collected by pytest (its name does not start with ``test_``); the tests check
answers against independent values, this checks that a move changed nothing.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def robots() -> list[str]:
    return sorted(p.stem for p in (ROOT / "robots").glob("*.yaml"))


def corpus() -> list[list[str]]:
    """The commands, as argument lists for ``kincalc``."""
    import kincalc
    out = []
    for r in robots():
        robot = kincalc.load_robot(r)
        # degrees for revolute joints, metres for prismatic ones (the CLI's defaults)
        q = " ".join(f"{25 + 7 * i}" if j.revolute else "0.1" for i, j in enumerate(robot.joints))
        out += [["robots", "show", r],
                ["fk", r],
                ["fk", r, *q.split(), "--json"],
                ["jacobian", r, *q.split(), "--json"],
                ["ik", r, "--from-q", q, "--json"],
                ["ik", r, "--from-q", q],
                ["reach", r, "--xyz", "0.3", "0.2", "0.4"]]
    out += [["ik", "puma560", "--from-q", "10 20 30 40 50 60", "--all-branches"],
            ["ik", "puma560", "--from-q", "10 20 30 40 50 60", "--explain", "--json"],
            ["ik", "ur5", "--from-q", "10 20 30 40 0 60", "--json"],
            ["ik", "stanford_arm", "--xyz", "0.5", "0.2", "0.3", "--rpy", "10", "20", "30"],
            ["ik", "kuka_kr16", "--xyz", "9", "9", "9", "--rpy", "0", "0", "0"],
            ["compare", "puma560", "puma560_mdh"],
            ["compare", "ur5", "ur5_poe", "--json"],
            ["compare", "stanford_arm", "stanford_arm_mdh", "--allow-offsets"],
            ["convert", "puma560", "--to", "mdh"],
            ["convert", "ur5", "--to", "poe"],
            ["workspace", "planar_3r", "--samples", "2000", "--seed", "1", "--json"],
            ["quiz", "puma560", "--seed", "3"],
            ["quiz", "stanford_arm", "--seed", "5", "--answers"],
            ["quiz", "ur5_poe", "--seed", "2", "--answers"],
            ["quiz", "bk_rrp", "--seed", "7", "--answers", "--rad"],
            ["fk", "puma560", "--symbolic"],
            ["fk", "stanford_arm", "--latex"],
            ["fk", "ur5_poe", "--symbolic", "--json"],
            ["jacobian", "puma560", "--symbolic"],
            ["jacobian", "bk_rrp", "--latex"]]
    for sheet in sorted(EXAMPLES.glob("*.yaml")):
        text = sheet.read_text(errors="replace")
        if "answers" in text or "answer" in text:
            out += [["check", str(sheet.relative_to(ROOT))],
                    ["check", str(sheet.relative_to(ROOT)), "--json"]]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir", type=Path)
    ap.add_argument("--kincalc", default=shutil.which("kincalc") or "kincalc",
                    help="the kincalc executable of the tree to record")
    args = ap.parse_args()
    args.outdir.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, COLUMNS="100", NO_COLOR="1", TERM="dumb")
    for i, cmd in enumerate(corpus()):
        run = subprocess.run([args.kincalc, *cmd], capture_output=True, text=True, cwd=ROOT,
                             env=env, timeout=300)
        (args.outdir / f"{i:03d}.txt").write_text(
            f"$ kincalc {' '.join(cmd)}\n--- exit {run.returncode}\n--- stdout\n{run.stdout}"
            f"--- stderr\n{run.stderr}")
    print(f"{len(corpus())} commands recorded in {args.outdir}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
