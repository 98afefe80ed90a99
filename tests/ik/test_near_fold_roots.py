"""Two distinct roots next to a fold of the arm are two solutions, however close.

A PUMA 560 a few 1e-6 rad from its stretched elbow has two elbow roots on each shoulder and
wrist branch, some 4e-6 rad apart, each reaching the pose to rounding; halfway between them
the pose is missed only to second order (1e-12 m), which once made the two one "double
root" and dropped the generating joints (4 answers where EAIK and ik-geo give 8).

The singular elbow angle is found here without kincalc: a plain standard-DH product for the
wrist centre (frame 4's origin, where the PUMA's axes 4, 5 and 6 meet) and bisection on the
sign of the determinant of its derivative by joints 1-3 (central differences).
"""

import numpy as np
import pytest
from randrobots import dh_frames

from kincalc import load_robot
from kincalc.conventions import to_poe
from kincalc.ik import Target, solve
from kincalc.spatial import wrap


def centre_det(robot, q, h=1e-6):
    J = np.empty((3, 3))
    for k in range(3):
        e = np.zeros(6)
        e[k] = h
        J[:, k] = (dh_frames(robot, q + e)[4][:3, 3] - dh_frames(robot, q - e)[4][:3, 3]) / (2 * h)
    return np.linalg.det(J)


def stretched_elbow(robot, q):
    """``q`` with joint 3 moved onto the elbow singularity nearest -90 deg (bisection)."""
    a, b = np.radians(-120.0), np.radians(-60.0)
    fa = centre_det(robot, np.r_[q[:2], a, q[3:]])
    assert np.sign(fa) != np.sign(centre_det(robot, np.r_[q[:2], b, q[3:]]))
    for _ in range(60):
        m = 0.5 * (a + b)
        fm = centre_det(robot, np.r_[q[:2], m, q[3:]])
        a, b, fa = (m, b, fm) if np.sign(fm) == np.sign(fa) else (a, m, fa)
    return np.r_[q[:2], 0.5 * (a + b), q[3:]]


def distance(a, b):
    return np.abs(wrap(np.asarray(a) - b)).max()


def near_fold_poses(seed, count):
    rng = np.random.default_rng(seed)
    r = load_robot("puma560")
    out = []
    for _ in range(count):
        q = stretched_elbow(r, np.r_[rng.uniform(-1, 1, 2), 0.0, rng.uniform(-1, 1, 3)])
        q[2] += rng.choice([-1, 1]) * rng.choice([1e-6, 2e-6, 5e-6])
        out.append(q)
    return r, out


def test_the_singular_elbow_is_found_without_kincalc():
    r, (q,) = near_fold_poses(1, 1)
    assert np.allclose(dh_frames(r, q)[-1], r.fk(q), atol=1e-12)


@pytest.mark.parametrize("form", ["dh", "mdh", "poe"])
def test_both_elbow_roots_next_to_a_stretched_elbow_are_answered(form):
    r, qs = near_fold_poses(3, 6)
    robot = {"dh": r, "mdh": load_robot("puma560_mdh"), "poe": to_poe(r)}[form]
    for q in qs:
        T = dh_frames(r, q)[-1]
        sols = solve(robot, Target(T)).solutions
        for s in sols:                          # each an exact solution, by the DH product
            F = dh_frames(r, s.q)[-1]
            assert np.abs(F - T).max() < 1e-12
        assert min(distance(s.q, q) for s in sols) < 1e-9
        assert len(sols) == 8, [s.branch for s in sols]
        assert len({s.branch for s in sols}) == 8
