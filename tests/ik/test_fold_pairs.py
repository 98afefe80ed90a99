"""Two roots either side of a fold of the placement are two solutions.

Next to a fold (a configuration where the joints placing the wrist centre lose a direction)
two solutions of a pose lie some 2 delta apart along the Jacobian's null vector, each
reaching the pose to rounding while the joints halfway between them miss it. The
placement's polynomial resolves them no better than its fit (they can come out as one
complex pair, one start for both), and the polish took both copies to one root: at 1e-4
rad from a fold about 3 % of such pairs lost one solution, at 1e-5 about 13 %, and which
one depended on the robot file's convention (an independent oracle's fold study).

The pairs here are made without kincalc's IK: a fold found by bisection of det J along
joint 3, ``qa = q_s + delta n`` the pose's generating joints, ``qb`` Gauss-Newton (kincalc's
FK and Jacobian) from ``q_s - delta n``; a pair counts where ``qb`` reaches the pose to
1e-13, apart from ``qa``, with the halfway joints missing it by more than 1e-10. (Flatter
pairs, 1e-6 rad apart next to a flat fold, are not told apart by the wrist centre alone in
double precision: between them it is placed to rounding.)
"""

import numpy as np
import pytest

from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap

from randrobots import random_pose


def wrist_arm(rng, third: str) -> Robot:
    """A random standard-DH arm, joints 1-3 R, R and ``third``, then a spherical wrist."""
    joints = []
    for i, kind in enumerate(["revolute", "revolute", third]):
        lim = (-np.pi, np.pi) if kind == "revolute" else (-3.0, 3.0)
        joints.append(Joint(f"j{i + 1}", kind, alpha=rng.uniform(-np.pi, np.pi),
                            a=rng.uniform(-0.5, 0.5), d=rng.uniform(-0.5, 0.5),
                            theta=rng.uniform(-np.pi, np.pi), limits=lim))
    for i, (a, d) in enumerate([(0.0, rng.uniform(-0.4, 0.4)), (0.0, 0.0),
                                (rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2))]):
        joints.append(Joint(f"j{i + 4}", "revolute", alpha=rng.uniform(0.3, 2.8), a=a, d=d,
                            theta=rng.uniform(-np.pi, np.pi), limits=(-np.pi, np.pi)))
    return Robot(name="fold_arm", convention="dh", joints=tuple(joints),
                 base=random_pose(rng), tool=random_pose(rng))


def error(robot, q, T):
    """The pose error of ``q`` (position, then half the rotation's skew part)."""
    F = robot.fk(q)
    E = T[:3, :3] @ F[:3, :3].T
    return np.r_[T[:3, 3] - F[:3, 3], 0.5 * np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0],
                                                      E[1, 0] - E[0, 1]])]


def newton(robot, q, T, steps=80):
    for _ in range(steps):
        e = error(robot, q, T)
        if np.abs(e).max() < 1e-15:
            break
        q = q + np.linalg.lstsq(robot.jacobian(q), e, rcond=None)[0]
    return q, np.abs(error(robot, q, T)).max()


def fold(robot, rng):
    """A configuration where det J changes sign along joint 3 (the wrist kept regular), or
    None."""
    q = rng.uniform(-np.pi, np.pi, 6)
    q[4] = rng.choice([-1, 1]) * rng.uniform(0.5, 2.5)
    span = np.linspace(-np.pi, np.pi, 61) if robot.is_revolute[2] else np.linspace(-2, 2, 61)
    det = []
    for x in span:
        q[2] = x
        det.append(np.linalg.det(robot.jacobian(q)))
    flips = np.flatnonzero(np.sign(det[:-1]) != np.sign(det[1:]))
    if not len(flips):
        return None
    lo, hi = span[flips[0]], span[flips[0] + 1]
    q[2] = lo
    s_lo = np.sign(np.linalg.det(robot.jacobian(q)))
    for _ in range(60):
        q[2] = 0.5 * (lo + hi)
        if np.sign(np.linalg.det(robot.jacobian(q))) == s_lo:
            lo = q[2]
        else:
            hi = q[2]
    return q


def distance(robot, a, b):
    d = np.asarray(a) - np.asarray(b)
    return np.abs(np.where(robot.is_revolute, wrap(d), d)).max()


def pairs(seed, third):
    """``(robot, T, qa, qb, delta)`` of the genuine pairs of a seeded set of arms."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(20):
        robot = wrist_arm(rng, third)
        qs = fold(robot, rng)
        if qs is None:
            continue
        n = np.linalg.svd(robot.jacobian(qs))[2][-1]
        for delta in (1e-4, 1e-5):
            qa = qs + delta * n
            T = robot.fk(qa)
            qb, miss = newton(robot, qs - delta * n, T)
            halfway = np.abs(error(robot, 0.5 * (qa + qb), T)).max()
            if miss < 1e-13 and distance(robot, qa, qb) > 1e-9 and halfway > 1e-10:
                out.append((robot, T, qa, qb, delta))
    return out


@pytest.mark.parametrize("third", ["revolute", "prismatic"])
def test_both_roots_next_to_a_fold_are_solutions_in_every_convention(third):
    cases = pairs(20261208, third)
    assert len(cases) >= 10
    for robot, T, qa, qb, delta in cases:
        for r in (robot, dh_to_mdh(robot), to_poe(robot)):
            found = [s.q for s in r.ik(T).solutions]
            # one solution on each side (next to a flat fold a solution that reaches the pose
            # to 4e-14 can lie 7e-6 rad from the root in a wrist joint)
            near = [distance(robot, qa, s) < distance(robot, qb, s) for s in found
                    if min(distance(robot, qa, s), distance(robot, qb, s)) < delta]
            assert set(near) == {True, False}, (r.convention, delta, qa, qb, found)


#: an independent oracle's worst case: RR-slide arm with a spherical wrist, 1.3e-4 rad
#: between the two roots, at a configuration whose Jacobian has full rank (condition 5e5);
#: its dh and poe files gave one of them, its mdh file both
R8 = [("revolute", 2.837749227759878, 0.4732837423113194, 0.1396402246615131, -0.5701928232515563),
      ("revolute", -2.664086228735687, -0.48206852493925495, 0.14070593977215676,
       0.13825410589978704),
      ("prismatic", 1.6976597183505753, 0.3646499297946373, -0.4475819607563168,
       0.27205185919645647),
      ("revolute", -0.37795967461590596, 0.0, -0.3350336048745723, -0.07173123746902643),
      ("revolute", 2.376382084019032, 0.0, 0.0, 1.7277609423144842),
      ("revolute", -2.067367284029989, 0.08757036358958004, -0.11955650303509946,
       -2.9705314947258974)]
R8_Q = [0.1823079246216595, 2.9941316226734447, 1.7036557887387966, -1.1904677502641818,
        -0.28762531803950275, 1.4730409706253078]


def test_the_oracles_pair_at_a_regular_configuration():
    joints = tuple(Joint(f"j{i + 1}", t, alpha=al, a=a, d=d, theta=th,
                         limits=(-np.pi, np.pi) if t == "revolute" else (-3.0, 3.0))
                   for i, (t, al, a, d, th) in enumerate(R8))
    robot = Robot(name="r8", convention="dh", joints=joints)
    T = robot.fk(np.array(R8_Q))
    other, miss = newton(robot, np.array([0.182256, 2.994000, 1.703668] + R8_Q[3:]), T)
    assert miss < 1e-13 and distance(robot, other, R8_Q) > 1e-4
    for r in (robot, dh_to_mdh(robot), to_poe(robot)):
        found = [s.q for s in r.ik(T).solutions]
        for q in (R8_Q, other):
            assert any(distance(robot, q, s) < 1e-8 for s in found), (r.convention, found)
