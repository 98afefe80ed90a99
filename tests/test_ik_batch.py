"""Batched IK (vectorised over poses) agrees with the per-pose solver."""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.ik.batch import solve_batch
from kincalc.ik.screws import wrap
from kincalc.ik.selftest import sample_configurations
from kincalc.ik.solve import UnsupportedRobot

ROBOTS = ["puma560", "ur5", "ur10e", "kuka_kr16", "fanuc_lrmate200id", "abb_irb120",
          "stanford_arm", "bk_6r", "bk_scara_euler", "kocaeli_kr16_lengths"]


def same_set(A, B, robot):
    if len(A) != len(B):
        return False
    for a in A:
        d = np.abs(np.where(robot.is_revolute, wrap(np.asarray(B) - a), np.asarray(B) - a)).max(-1)
        if d.min() > 1e-7:
            return False
    return True


@pytest.mark.parametrize("name", ROBOTS)
def test_batch_matches_per_pose_solver(name):
    r = load_robot(name)
    Q = sample_configurations(r, 400, np.random.default_rng(11))
    T = r.fk(Q)
    B = solve_batch(r, T)
    assert B.q.shape[0] == 400 and B.valid.shape == B.q.shape[:2]
    for i in range(400):
        sols = B.q[i][B.valid[i]]
        # the generating configuration is among them
        d = np.abs(np.where(r.is_revolute, wrap(sols - Q[i]), sols - Q[i])).max(-1)
        assert d.min() < 1e-6
        # every batched solution reproduces the pose
        assert np.allclose(r.fk(sols), T[i], atol=1e-9 * max(1.0, r.characteristic_length))
    for i in range(0, 400, 40):                      # same solution set as robot.ik
        ref = [s.q for s in r.ik(T[i]).solutions]
        assert same_set(B.q[i][B.valid[i]], ref, r)


def test_batch_unreachable_poses_have_no_solutions():
    r = load_robot("puma560")
    T = np.tile(np.eye(4), (5, 1, 1))
    T[:, 0, 3] = np.linspace(2, 3, 5)
    assert solve_batch(r, T).counts.tolist() == [0] * 5


def test_batch_refuses_families_without_a_closed_form():
    with pytest.raises(UnsupportedRobot):
        solve_batch(load_robot("manocha_canny_6r"), np.eye(4)[None])
