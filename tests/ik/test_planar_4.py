"""Four revolute joints, axes 1-3 parallel and axis 4 of another direction (a planar arm
carrying a tilted wrist joint), asked for a whole pose: the turn about the parallel axes
and joint 4 come from the orientation, joints 1 and 2 place axis 3, joint 3 completes the
turn (two elbows). The same seen from the tool (axes 2-4 parallel) is a point of axis 4
placed by joints 1-3 and a roll.

Every answer reaches the pose by a plain standard-DH product, the generating joints are
among them, and every root that Gauss-Newton finds from many random starts (the robot's FK
and Jacobian only) is among them.
"""

import numpy as np
import pytest
from randrobots import dh_frames, newton_roots, three_conventions

from kincalc.ik import Target, solve
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap


def random_arm(rng, parallel: str):
    """Standard DH: ``parallel`` "123": alpha1 = alpha2 = 0 (axes 1-3 parallel), alpha3
    generic; "234": alpha2 = alpha3 = 0, alpha1 generic. Random lengths, offsets and tool."""
    flat = (0, 1) if parallel == "123" else (1, 2)
    joints = []
    for i in range(4):
        al = (0.0 if i in flat else rng.uniform(0.4, 2.7) * rng.choice([-1, 1]))
        joints.append(Joint(f"q{i + 1}", "revolute", alpha=al, a=rng.uniform(0.1, 0.5),
                            d=rng.uniform(-0.4, 0.4), theta=rng.uniform(-np.pi, np.pi)))
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-0.3, 0.3, 3))
    return Robot("planar_4", "dh", tuple(joints), base=np.eye(4), tool=tool)


def dh_pose(robot, q):
    return dh_frames(robot, q)[-1]


def distance(a, b):
    return np.abs(wrap(np.asarray(a) - b)).max()


@pytest.mark.parametrize("parallel, family", [("123", "planar-4"), ("234", "point-plus-roll")])
def test_a_planar_arm_with_a_tilted_fourth_joint_gets_both_elbows(parallel, family):
    rng = np.random.default_rng(21)
    for _ in range(4):
        robot = random_arm(rng, parallel)
        for _ in range(4):
            q = rng.uniform(-np.pi, np.pi, 4)
            T = dh_pose(robot, q)
            res = solve(robot, Target(T))
            assert res.family == family
            sols = res.solutions
            for s in sols:
                assert np.abs(dh_pose(robot, s.q) - T).max() < 1e-10
            assert min(distance(s.q, q) for s in sols) < 1e-8
            roots = newton_roots(robot, T, 30, rng)
            assert len(roots) >= 1
            for root in roots:
                assert min(distance(s.q, root) for s in sols) < 1e-7
            assert len(sols) <= 2
            for i, a in enumerate(sols):
                assert all(distance(a.q, b.q) > 1e-6 for b in sols[:i])


def test_the_three_conventions_give_the_same_solutions():
    rng = np.random.default_rng(4)
    robot = random_arm(rng, "123")
    q = rng.uniform(-np.pi, np.pi, 4)
    T = dh_pose(robot, q)
    sets = three_conventions(robot, T)
    assert len(sets[0]) == 2 and sets[0] == sets[1] == sets[2]
