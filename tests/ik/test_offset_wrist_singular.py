"""Offset-wrist arms (joints 1-4 about or along one direction h, axes 5 and 6 meeting) at
their wrist singularity.

When axis 6 is parallel to h (q5 = 0 or 180 deg on the textbook's R-P-R-R-R-R arm), the
three revolute joints of 1-4 and joint 6 all turn about parallel axes:

    R_h(s1 q1 + s3 q3 + s4 q4) R5 R(k6, q6) = R_h(s1 q1 + s3 q3 + s4 q4 + sigma q6) R5,

(``s_i``, ``sigma`` = +-1 the directions of the axes along h), so the pose fixes q5, the
prismatic joint and only that signed sum; turning q6 swings axis 4 about axis 6 and the
planar elbow follows. The arm has a one-parameter continuum of solutions there, and IK
used to answer none at all. Every check is made from FK and the joint frames of the
robot as given: the solutions reproduce the pose, the generating configuration satisfies
the reported relation, and moving the free joint along the continuum (Newton on the other
joints, a brute-force follower) keeps reaching the pose.
"""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.conventions import mdh_to_dh, to_poe
from kincalc.fk import chain_frames
from kincalc.ik.families import plan
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap
from randrobots import follow_joint


def _robot(convention):
    r = load_robot("bk_offset_wrist")                     # modified DH in its file
    return {"mdh": r, "dh": mdh_to_dh(r), "poe": to_poe(r)}[convention]


def _singular_configurations(robot, m, rng):
    """``m`` configurations with q5 = 0 or 180 deg (axis 6 along axis 4 for this arm,
    checked from the frames) and the other joints random within the limits."""
    lo, hi = robot.limits.T
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    Q = rng.uniform(lo, hi, (m, robot.dof))
    Q[:, 4] = rng.choice([0.0, np.pi], m)
    F = chain_frames(robot.chain, Q)
    z4, z6 = F[:, 3, :3, 2], F[:, 5, :3, 2]
    assert np.allclose(np.abs(np.einsum("mi,mi->m", z4, z6)), 1.0, atol=1e-12)
    return Q


def _follow(robot, T, q, j, value):
    """Move joint ``j`` of the solution ``q`` to ``value`` in steps, Gauss-Newton on the
    other joints against the pose ``T`` after each (:func:`randrobots.follow_joint`): the
    end point, or None where a step misses."""
    L = robot.characteristic_length

    def err(x):
        F = robot.fk(x)
        return np.concatenate([(F[:3, 3] - T[:3, 3]) / L, (F[:3, :3] - T[:3, :3]).ravel()])
    d = wrap(value - q[j])
    return follow_joint(err, q, j, value, 1.0 if d >= 0 else -1.0,
                        [k for k in range(robot.dof) if k != j], steps=20)


@pytest.mark.parametrize("convention", ["mdh", "dh", "poe"])
def test_wrist_singular_poses_have_their_continuum(convention):
    robot = _robot(convention)
    rng = np.random.default_rng(606)
    Q = _singular_configurations(robot, 12, rng)
    T = robot.fk(Q)
    sv = robot.ik_batch(T)
    for i, q0 in enumerate(Q):
        res = robot.ik(T[i])
        assert res.solutions, f"no solution for the pose of {q0}"
        assert int(sv.valid[i].sum()) == len(res.solutions)
        on = []
        for s in res.solutions:
            assert np.allclose(robot.fk(s.q), T[i], atol=1e-9 * robot.characteristic_length)
            assert s.singular and s.free == (5,)
            c = s.continuum
            assert c.joints == (0, 2, 3, 5)
            # the relation, evaluated on the generating configuration
            total = sum(sg * q0[k] for k, sg in zip(c.joints, c.signs))
            on.append(abs(wrap(total - c.total)) < 1e-9 and abs(s.q[1] - q0[1]) < 1e-9)
        assert any(on), (q0, [s.q for s in res.solutions])
        # joint 6 is free: the others follow it (a small turn: an arc of the continuum
        # ends where the elbow stretches or folds), keeping the relation
        for s in res.solutions:
            c, ends = s.continuum, []
            for dq in (0.01, -0.01):
                q = _follow(robot, T[i], s.q, 5, s.q[5] + dq)
                total = np.inf if q is None else sum(
                    sg * q[k] for k, sg in zip(c.joints, c.signs))
                ends.append(q is not None and abs(wrap(total - c.total)) < 1e-8)
            assert any(ends), (q0, s.q)

def test_near_the_singularity_the_pose_is_still_solved():
    """Just off the singularity (q5 within 1e-12 to 1e-6 of 0 or 180 deg) the solutions
    reproduce the pose and the generating configuration is among them, up to the
    conditioning there (``sqrt`` of the distance to the singularity)."""
    robot = load_robot("bk_offset_wrist")
    rng = np.random.default_rng(607)
    for eps in (1e-12, 1e-9, 1e-6):
        Q = _singular_configurations(robot, 6, rng)
        Q[:, 4] += eps
        for q0 in Q:
            T = robot.fk(q0)
            res = robot.ik(T)
            assert res.solutions
            for s in res.solutions:
                assert np.allclose(robot.fk(s.q), T, atol=1e-9 * robot.characteristic_length)


def _antiparallel_arm(rng, flipped: int, slide: int):
    """An R-R-P-R-R-R (``slide`` = 2) or P-R-R-R-R-R (``slide`` = 0) offset-wrist arm, joints
    1-4 about or along one direction, whose joint ``flipped`` (0-based, of 0-2) turns the
    axes after it against those before (a twist of 180 deg), in standard DH; axis 6 is
    along h at q5 = 0 and 180 deg."""
    rows = [["revolute", 0.0, rng.uniform(.1, .4), rng.uniform(-.2, .2)],
            ["revolute", 0.0, rng.uniform(.1, .4), rng.uniform(-.2, .2)],
            ["revolute", 0.0, rng.uniform(.05, .2), 0.0],
            ["revolute", np.pi / 2, 0.0, 0.0],
            ["revolute", np.pi / 2, 0.0, rng.uniform(.3, .6)],
            ["revolute", 0.0, 0.0, rng.uniform(.05, .2)]]
    rows[slide][0] = "prismatic"
    rows[flipped][1] = np.pi
    joints = tuple(Joint(f"j{i + 1}", kind, alpha=al, a=a, d=d,
                         theta=rng.uniform(-3, 3) if kind == "revolute" and i != 4 else 0.0,
                         limits=(-0.5, 0.5) if kind == "prismatic" else (-np.pi, np.pi))
                   for i, (kind, al, a, d) in enumerate(rows))
    return Robot(name="antiparallel", convention="dh", joints=joints)


@pytest.mark.parametrize("flipped, slide", [(0, 2), (1, 2), (2, 2), (0, 0), (1, 0), (2, 0)])
def test_axes_pointing_against_each_other_keep_the_continuum(flipped, slide):
    """The joints about h may point either way along it (a 180-degree twist): joint 6's
    representatives are then read with the sense of axis 6 along the elbow's own first
    axis. With the first elbow axis against axis 4 they were taken on the wrong side and
    the singular poses had no solution at all."""
    rng = np.random.default_rng(4100 + 10 * flipped + slide)
    robot = _antiparallel_arm(rng, flipped, slide)
    assert plan(robot)[1].name == "parallel-four-wrist"
    Q = sample_configurations(robot, 16, rng)
    Q[:, 4] = rng.choice([0.0, np.pi], len(Q))
    T = robot.fk(Q)
    for i, q0 in enumerate(Q):
        res = robot.ik(T[i])
        assert res.solutions, f"no solution for the pose of {q0}"
        on = []
        for s in res.solutions:
            assert np.allclose(robot.fk(s.q), T[i], atol=1e-9 * robot.characteristic_length)
            assert s.free == (5,) and s.continuum is not None
            c = s.continuum
            total = sum(sg * q0[k] for k, sg in zip(c.joints, c.signs))
            fixed = [k for k in range(6) if k not in c.joints]
            on.append(abs(wrap(total - c.total)) < 1e-9
                      and np.abs(s.q[fixed] - q0[fixed]).max() < 1e-9)
        assert any(on), (q0, [s.q for s in res.solutions])
