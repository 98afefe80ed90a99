"""Three parallel axes (2, 3, 4) with axes 5 and 6 skew: the three-parallel-offset family.

Joints 1 and 5 come from subproblem 6 (kincalc.ik.solvers.three_parallel_offset). The
independent reference is a second formulation of the same problem: the general 6R
elimination (kincalc.ik.general6r, Raghavan-Roth / Manocha-Canny), which needs no
structure and solved these robots before the family existed. Over random robots in dh,
mdh and poe, and their chains read backwards, both must give the same set of solutions,
every one reproducing its pose by FK, the generating joints among them; robot.ik and
robot.ik_batch must agree on every joint value, label and flag. The wrist singularity
(axis 6 along axes 2-4) and its neighbourhood are in test_ur_wrist_singular.py.
"""

import zlib

import numpy as np
import pytest
from randrobots import random_pose

from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik.families import classify
from kincalc.ik.general6r.solve import solve_general_6r_batch
from kincalc.ik.screws import Screws
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap


def random_arm(rng, convention: str, backwards: bool = False) -> Robot:
    """A random 6R arm in DH rows: axes 2-4 parallel (twists 0), axes 5 and 6 a link apart
    (a of joint 5 not 0), the other twists and every length random; with ``backwards`` the
    structure seen from the tool: axes 3-5 parallel, axes 1 and 2 a link apart."""
    u = lambda lo=-0.5, hi=0.5: rng.uniform(lo, hi)  # noqa: E731
    ang = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731
    skew = lambda: u(0.05, 0.5) * rng.choice([-1, 1])  # noqa: E731
    # row i (alpha_i, a_i, d_i): axes i and i + 1 are parallel where alpha_i = 0, a_i apart
    rows = [(ang(), u(), u()), (0.0, u(), u()), (0.0, u(), u()), (ang(), u(), u()),
            (ang(), skew(), u()), (u(-3, 3), u(), u())]
    if backwards:
        rows = [(ang(), skew(), u()), (ang(), u(), u()), (0.0, u(), u()), (0.0, u(), u()),
                (ang(), u(), u()), (u(-3, 3), u(), u())]
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d,
                         theta=rng.uniform(-np.pi, np.pi)) for i, (al, a, d) in enumerate(rows))
    r = Robot("random_offset", "dh", joints, base=random_pose(rng), tool=random_pose(rng))
    return {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]


def same_set(A, B, tol=1e-6) -> bool:
    A, B = np.asarray(A).reshape(-1, 6), np.asarray(B).reshape(-1, 6)
    if len(A) != len(B):
        return False
    return all(np.abs(wrap(B - a)).max(-1).min() < tol for a in A) and \
        all(np.abs(wrap(A - b)).max(-1).min() < tol for b in B)


@pytest.mark.parametrize("backwards", [False, True])
@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_solutions_are_those_of_the_general_elimination(convention, backwards):
    rng = np.random.default_rng(zlib.crc32(f"offset/{convention}/{backwards}".encode()))
    for _ in range(5):
        r = random_arm(rng, convention, backwards)
        family = classify(r, Screws.of(r))[0]
        assert family.name == ("reversed-" if backwards else "") + "three-parallel-offset"
        assert family.exact
        Q = rng.uniform(-np.pi, np.pi, (30, 6))
        T = r.fk(Q)
        G, ok = solve_general_6r_batch(r, T)
        for q, Tk, g, k in zip(Q, T, G, ok):
            res = r.ik(Tk)
            sols = np.array([s.q for s in res.solutions]).reshape(-1, 6)
            assert same_set(sols, g[k]), (convention, backwards, q)
            assert np.abs(wrap(sols - q)).max(-1).min() < 1e-6
            F = r.fk(sols)
            assert np.abs(F[:, :3, 3] - Tk[:3, 3]).max() <= 1e-9 * r.characteristic_length
            assert np.abs(F[:, :3, :3] - Tk[:3, :3]).max() <= 1e-9
            assert len({s.branch for s in res.solutions}) == len(res.solutions)


def test_single_poses_and_the_batch_agree_on_every_label_and_flag():
    """robot.ik pose by pose against robot.ik_batch over the same poses (random, and with
    joints at 0, +-90, 180 deg and a hair off them): the same joint values, bit for bit in
    batches of 1, 2 and 9, the same labels, limit and singular flags."""
    rng = np.random.default_rng(11)
    for convention in ("dh", "poe"):
        r = random_arm(rng, convention)
        Q = rng.uniform(-np.pi, np.pi, (24, 6))
        special = np.radians(rng.choice([0.0, 90.0, -90.0, 180.0], (12, 6)))
        Q[12:] = special + rng.choice([0.0, 0.0, 1e-9, -1e-7], special.shape)
        T = r.fk(Q)
        whole = r.ik_batch(T)
        for m in (1, 2, 9):
            for i in range(0, len(T) - m + 1, 5):
                part = r.ik_batch(T[i:i + m])
                np.testing.assert_array_equal(part.valid, whole.valid[i:i + m])
                np.testing.assert_array_equal(np.where(part.valid[..., None], part.q, 0.0),
                                              np.where(whole.valid[i:i + m, ..., None],
                                                       whole.q[i:i + m], 0.0))
        for i, Tk in enumerate(T):
            res = r.ik(Tk)
            valid = whole.valid[i]
            assert same_set([s.q for s in res.solutions], whole.q[i][valid], 1e-12)
            by_q = {tuple(np.round(q, 9)): (lab, w, sg) for q, lab, w, sg in zip(
                whole.q[i][valid], whole.labels[i][valid], whole.within[i][valid],
                whole.singular[i][valid])}
            for s in res.solutions:
                assert by_q[tuple(np.round(s.q, 9))] == (s.branch, s.within_limits, s.singular)
