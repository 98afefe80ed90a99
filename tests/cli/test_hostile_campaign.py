"""Command-line cases of what an outside hostile-input campaign found (one per fix; the
tests at the depth of each fix are next to the code's other tests)."""

from __future__ import annotations

import json
import time
from pathlib import Path

from cli_contract import assert_contract, run_cli

ROOT = Path(__file__).resolve().parents[2]


def test_all_branches_of_a_general_6r_answers_at_once():
    """ik --all-branches on the xArm 6 (8 solutions, 8 values a joint) built its 262,136
    arm combinations one by one before saying they were too many to list: 16 s of CPU a
    pose, a hang to a grader's timeout."""
    argv = ["ik", "xarm6", "--from-q", "-156 -5.496 -71.87 173.2 170.9 70.64",
            "--all-branches", "--json"]
    t0 = time.perf_counter()
    status, out, err = run_cli(argv)
    took = time.perf_counter() - t0
    assert_contract(status, out, err, argv)
    doc = json.loads(out)
    assert doc["rejected"] == [] and "too many to list" in doc["rejected_note"]
    assert took < 8, f"{took:.1f} s"


def test_explain_on_a_robot_only_nearly_of_its_family(tmp_path):
    """ik --explain on a PUMA 560 whose wrist axes miss each other by 0.1 mm (a datasheet
    rounded, a calibrated model): exit status 3 (IndexError) for every pose."""
    text = (ROOT / "robots" / "puma560.yaml").read_text()
    old = "- {name: q5, type: revolute, alpha: -90, a: 0,    d: 0,"
    assert old in text
    (tmp_path / "arm.yaml").write_text(text.replace(old, old.replace("d: 0,", "d: 0.0001,")))
    argv = ["ik", str(tmp_path / "arm.yaml"), "--from-q", "-8.98 43.17 83.11 -25.04 48.54 58.39",
            "--explain", "--json"]
    status, out, err = run_cli(argv)
    assert_contract(status, out, err, argv)
    doc = json.loads(out)
    assert status in (0, 1) and len(doc["solutions"]) == 8
    assert all(s["trace"] for s in doc["solutions"])
