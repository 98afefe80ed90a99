"""Five joints whose axes 4 and 5 meet at a point off the tool's approach line (a tool offset
sideways), asked for a whole pose: the point is fixed in the tool, joints 1-3 place it, and
joints 4 and 5 take the orientation left. Also the same seen from the tool (axes 1 and 2
meeting), and a slide among joints 1-3.

Every answer reaches the pose by a plain standard-DH product; the generating joints are
among the answers; and every root that Gauss-Newton finds from many random starts (the
robot's FK and Jacobian only) is among them.
"""

import numpy as np
import pytest
from randrobots import dh_frames, newton_roots, three_conventions

from kincalc.ik import Target, solve
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap


def random_arm(rng, meeting: str, kinds="RRRRR", roll_tool=None):
    """Standard DH, twists far from 0 and pi. ``meeting`` "45": a4 = 0 (axes 4 and 5
    meet at frame 4's origin); "12": a1 = 0 (axes 1 and 2 meet). The tool is a random pose,
    so the approach line misses the meeting point; or, ``roll_tool`` an offset ``(3,)``,
    joint 5 rolls the tool (alpha5 = 0: the approach along axis 5) carried sideways."""
    rows = []
    for i in range(5):
        al = rng.uniform(0.4, 2.7) * rng.choice([-1, 1])
        if roll_tool is not None and i == 4:
            al = 0.0
        a = 0.0 if (meeting == "45" and i == 3) or (meeting == "12" and i == 0) \
            else rng.uniform(-0.5, 0.5)
        rows.append((al, a, rng.uniform(-0.5, 0.5), rng.uniform(-np.pi, np.pi)))
    kind = {"R": "revolute", "P": "prismatic"}
    joints = tuple(Joint(f"q{i + 1}", kind[k], alpha=al, a=a, d=d, theta=th)
                   for i, (k, (al, a, d, th)) in enumerate(zip(kinds, rows)))
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-0.3, 0.3, 3)) \
        if roll_tool is None else transform(None, roll_tool)
    return Robot("wrist_pair", "dh", joints, base=np.eye(4), tool=tool)


def dh_pose(robot, q):
    return dh_frames(robot, q)[-1]


def distance(robot, a, b):
    d = np.asarray(a) - b
    return np.abs(np.where(robot.is_revolute, wrap(d), d)).max()


CASES = [("45", "RRRRR"), ("45", "RRPRR"), ("45", "PRRRR"), ("12", "RRRRR")]


@pytest.mark.parametrize("meeting, kinds", CASES)
def test_a_five_joint_arm_with_an_offset_tool_gets_every_solution(meeting, kinds):
    rng = np.random.default_rng(11)
    for _ in range(4):
        robot = random_arm(rng, meeting, kinds)
        for _ in range(3):
            q = rng.uniform(-np.pi, np.pi, 5)
            T = dh_pose(robot, q)
            res = solve(robot, Target(T))
            assert res.family == ("wrist-pair" if meeting == "45" else "reversed-wrist-pair")
            sols = res.solutions
            for s in sols:
                assert np.abs(dh_pose(robot, s.q) - T).max() < 1e-10
            assert min(distance(robot, s.q, q) for s in sols) < 1e-8
            for i, a in enumerate(sols):
                assert all(distance(robot, a.q, b.q) > 1e-6 for b in sols[:i])
            if kinds == "RRRRR":
                for root in newton_roots(robot, T, 40, rng):
                    assert min(distance(robot, s.q, root) for s in sols) < 1e-7


def test_a_roll_joint_carrying_a_sideways_tool():
    """The usual tool of a five-joint arm: joint 5 rolls it, its approach along axis 5, but
    the tool point is offset sideways, so the approach line misses where axes 4 and 5
    meet (and the approach does not turn joint 5: the solver turns another of the tool's
    directions)."""
    rng = np.random.default_rng(8)
    for _ in range(4):
        robot = random_arm(rng, "45", roll_tool=[0.12, 0.0, 0.05])
        for _ in range(3):
            q = rng.uniform(-np.pi, np.pi, 5)
            T = dh_pose(robot, q)
            res = solve(robot, Target(T))
            assert res.family == "wrist-pair"
            for s in res.solutions:
                assert np.abs(dh_pose(robot, s.q) - T).max() < 1e-10
            assert min(distance(robot, s.q, q) for s in res.solutions) < 1e-8
            for root in newton_roots(robot, T, 40, rng):
                assert min(distance(robot, s.q, root) for s in res.solutions) < 1e-7


def test_the_three_conventions_give_the_same_solutions():
    rng = np.random.default_rng(5)
    robot = random_arm(rng, "45")
    q = rng.uniform(-np.pi, np.pi, 5)
    T = dh_pose(robot, q)
    sets = three_conventions(robot, T)
    assert sets[0] and sets[0] == sets[1] == sets[2]


def test_an_approach_alone_is_refused_with_the_reason():
    """Position and approach leave the roll, which moves the meeting point: five joints then
    have no finite set of solutions to give, and the family says what it takes."""
    from kincalc.errors import TargetMismatch
    rng = np.random.default_rng(2)
    robot = random_arm(rng, "45")
    T = dh_pose(robot, rng.uniform(-np.pi, np.pi, 5))
    P = np.eye(4)
    P[:3, 3] = T[:3, 3]
    with pytest.raises(TargetMismatch):
        solve(robot, Target(P, orientation=False, approach=T[:3, 2]))
