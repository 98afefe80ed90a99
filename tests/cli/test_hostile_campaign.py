"""Command-line cases of what an outside hostile-input campaign found (one per fix; the
tests at the depth of each fix are next to the code's other tests)."""

from __future__ import annotations

import json
import time

from cli_contract import assert_contract, run_cli


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
