"""A joint free at a position singularity, turned to the orientation a whole pose gives
(:mod:`kincalc.ik.free_joints`): FK round trips at the singular poses, the turn against a
brute-force search over the joint's values, and a position target leaving it free."""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.ik.branches import Branches
from kincalc.ik.families import plan
from kincalc.ik.free_joints import orient_free
from kincalc.ik.solvers import SOLVERS
from kincalc.ik.target import Targets
from kincalc.spatial import matrix_from_rpy, wrap


def _on_axis_1(name, m, rng):
    """``m`` configurations of ``name`` with the tool point on axis 1 (joint 1 free)."""
    robot = load_robot(name)
    lo, hi = robot.limits.T
    Q = rng.uniform(lo, hi, (m, robot.dof))
    if name == "spong_cylindrical":                      # d3 = 0: the point on the base axis
        Q[:, 2] = 0.0
    else:                                                # RRR elbow: a2 c2 + a3 c23 = 0
        a2, a3 = robot.chain.fixed[2][0, 3], robot.chain.fixed[3][0, 3]
        Q[:, 1] = rng.choice([-1, 1], m) * rng.uniform(0.2, 1.2, m)
        # sin q23 of the sign of sin q2: the point off the shoulder (where joint 2 is free too)
        q23 = np.sign(Q[:, 1]) * np.arccos(-a2 * np.cos(Q[:, 1]) / a3)
        Q[:, 2] = wrap(q23 - Q[:, 1])
    return robot, Q


def _angle(Ra, Rb):
    """The angle (rad) of ``Ra^T Rb`` for stacks of rotations."""
    c = (np.einsum("...ij,...ij->...", Ra, Rb) - 1.0) / 2.0
    return np.arccos(np.clip(c, -1.0, 1.0))


@pytest.mark.parametrize("name", ["spong_cylindrical", "siciliano_arm"])
def test_singular_poses_round_trip(name):
    """FK of a configuration with the tool point on axis 1, solved as a whole pose: the
    configuration is among the solutions (joint 1 set by the orientation, not free), the
    solution is flagged singular; solved for the position only, joint 1 stays free."""
    robot, Q = _on_axis_1(name, 40, np.random.default_rng(3))
    T = robot.fk(Q)
    sv = robot.ik_batch(T)
    for i in range(len(Q)):
        v = sv.valid[i]
        assert v.any(), f"no solution for pose {i}"
        d = np.abs(np.where(robot.is_revolute, wrap(sv.q[i][v] - Q[i]), sv.q[i][v] - Q[i]))
        assert d.max(axis=1).min() < 1e-8
        assert not sv.free[i][v][:, 0].any()
        assert sv.singular[i][v].all()
        assert np.allclose(robot.fk(sv.q[i][v]), T[i], atol=1e-9)
    res = robot.ik(T[0], orientation=False)
    assert res.solutions and all(s.free == (0,) for s in res.solutions)


@pytest.mark.parametrize("name", ["spong_cylindrical", "siciliano_arm"])
def test_turn_is_the_nearest_orientation(name):
    """For orientations the point's position does not allow, the turned joint gives the
    orientation nearest the target over every value of the joint (a grid of 3600 values and
    a local refinement), and the tool point stays where it was."""
    robot, Q = _on_axis_1(name, 12, np.random.default_rng(8))
    rng = np.random.default_rng(9)
    T = robot.fk(Q)
    T[:, :3, :3] = matrix_from_rpy(rng.uniform(-np.pi, np.pi, (len(T), 3)))
    S, family, _ = plan(robot)
    targets = Targets(T)
    br = SOLVERS[family.solver](S, targets, Branches.start(len(T), robot.dof)).expanded()
    turned = orient_free(robot, targets, br)
    q0, q1 = br.q(), turned.q()
    grid = np.linspace(-np.pi, np.pi, 3601)
    for i in range(len(T)):
        for k in np.flatnonzero(br.ok[i] & br.F[0, i]):
            tool = robot.fk(q1[i, k])
            assert np.allclose(tool[:3, 3], robot.fk(q0[i, k])[:3, 3], atol=1e-9)
            trial = np.repeat(q0[i, k][None], len(grid), 0)
            trial[:, 0] = grid
            errors = _angle(robot.fk(trial)[:, :3, :3], T[i, :3, :3])
            best = grid[np.argmin(errors)]
            fine = np.repeat(q0[i, k][None], 2001, 0)
            fine[:, 0] = best + np.linspace(-2e-3, 2e-3, 2001)
            least = _angle(robot.fk(fine)[:, :3, :3], T[i, :3, :3]).min()
            assert _angle(tool[:3, :3], T[i, :3, :3]) <= least + 1e-9
            assert not turned.F[0, i, k]



def _shoulder_robot(rng):
    """A random elbow arm (standard DH, random base and tool) whose folded elbow puts the
    tool point where axes 1 and 2 meet: a1 = 0, a2 = a3, d2 + d3 = 0, alpha2 = 0; the
    tool frame's origin at frame 3's."""
    from randrobots import random_pose
    from kincalc.model import Joint, Robot
    a, d = rng.uniform(0.2, 0.5), rng.uniform(-0.3, 0.3)
    rows = [(rng.uniform(0.4, 2.7), 0.0, rng.uniform(-0.3, 0.3)), (0.0, a, d),
            (rng.uniform(-3, 3), a, -d)]
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=ln, d=off,
                         theta=rng.uniform(-np.pi, np.pi), limits=(-np.pi, np.pi))
                   for i, (al, ln, off) in enumerate(rows))
    tool = random_pose(rng)
    tool[:3, 3] = 0.0
    return Robot("shoulder", "dh", joints, base=random_pose(rng), tool=tool)


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_two_free_joints_are_turned_to_the_orientation(convention):
    """The tool point where axes 1 and 2 meet (a folded elbow of equal links) leaves both
    joints free for its position. For the whole pose FK gave, IK used to answer
    'orientation out of reach'; both joints are now set by the orientation: the generating
    configuration is the one solution (FK round trip, joint distance), not free, flagged
    singular; for the position alone both stay free."""
    from kincalc.conventions import dh_to_mdh, to_poe
    from kincalc.fk import chain_frames
    rng = np.random.default_rng(12)
    for robot in [load_robot("siciliano_arm")] + [_shoulder_robot(rng) for _ in range(4)]:
        Q = rng.uniform(-np.pi, np.pi, (10, 3))
        Q[:, 2] = wrap(np.pi - robot.joints[2].theta)                 # the elbow folded
        robot = {"dh": robot, "mdh": dh_to_mdh(robot), "poe": to_poe(robot)}[convention]
        T = robot.fk(Q)
        F = chain_frames(robot.chain, Q)
        for j in (0, 1):                       # the tool point on axes 1 and 2 (frames)
            k, o = F[:, j, :3, 2], F[:, j, :3, 3]
            assert np.linalg.norm(np.cross(k, T[:, :3, 3] - o), axis=1).max() < 1e-12
        sv = robot.ik_batch(T)
        for i in range(len(Q)):
            v = sv.valid[i]
            assert v.sum() == 1, (robot.name, i, v.sum())
            q = sv.q[i][v][0]
            assert np.abs(wrap(q - Q[i])).max() < 1e-8
            assert not sv.free[i][v].any() and sv.singular[i][v].all()
            assert np.allclose(robot.fk(q), T[i], atol=1e-9)
        res = robot.ik(T[0], orientation=False)
        assert res.solutions and all(set(s.free) == {0, 1} for s in res.solutions)
