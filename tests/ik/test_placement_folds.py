"""A point placed by three joints of a revolute and prismatic mix with no structure (the
resultant's placement, :mod:`kincalc.ik.place`) at a fold of the arm: where two of the
placement's roots meet.

There the resultant's polynomial gives the two roots split by rounding, up to some 5e-3
apart in the joint that moves fast along the fold, and Gauss-Newton on the point (singular
there) leaves them some 1e-4 apart, each placing the point to ~1e-9. Before the placement
answered such a pair at its middle, a five-joint arm asked for a whole pose at the fold got
no solution at all (both copies missed the roll by ~5e-4 rad), and asked for the position
and approach got two copies 1.4e-3 rad from the generating joints.

The folds are found here without kincalc: the point where axes 4 and 5 meet (the wrist
centre) by a plain DH product, and the fold where the determinant of its derivative by
joints 1-3 (central differences) changes sign, by bisection.
"""

import numpy as np
import pytest
from randrobots import dh_frames

from kincalc.ik import Target, solve
from kincalc.model import Joint, Robot
from kincalc.spatial import rot_y, rot_z, transform, wrap


#: joints 1-3: a prismatic joint among them (the campaign's misses: R-R-P, P-R-P, R-P-R)
MIXES = ("RRP", "PRP", "RPR", "PRR")


def random_arm(rng, five: bool):
    """Joints 1-3 of a mix of :data:`MIXES` with twists far from 0 and pi (no structure: the
    resultant's placement); axes 4 and 5 meet (a4 = 0). Five joints: the tool looks along x5
    from a point on that line; six: joint 6's axis through the same point (a spherical
    wrist)."""
    def twist():
        return rng.uniform(0.3, 2.8) * rng.choice([-1, 1])
    kinds = [{"R": "revolute", "P": "prismatic"}[c] for c in MIXES[rng.integers(len(MIXES))]]
    rows = [(twist(), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)) for _ in range(3)]
    rows += [(twist(), 0.0, rng.uniform(-0.5, 0.5))]
    if five:
        rows += [(twist(), rng.uniform(-0.5, 0.5), 0.0)]
        tool = transform(rot_y(np.pi / 2) @ rot_z(rng.uniform(-3, 3)), [0, 0, 0]) @ \
            transform(None, [0, 0, rng.uniform(-0.5, 0.5)])
    else:
        rows += [(twist(), 0.0, 0.0), (rng.uniform(-3, 3), rng.uniform(-0.5, 0.5),
                                      rng.uniform(-0.5, 0.5))]
        tool = np.eye(4)
    kinds += ["revolute"] * (len(rows) - 3)
    joints = tuple(Joint(f"q{i + 1}", kind, alpha=al, a=a, d=d, theta=rng.uniform(-np.pi, np.pi))
                   for i, (kind, (al, a, d)) in enumerate(zip(kinds, rows)))
    return Robot("fold", "dh", joints, base=np.eye(4), tool=tool)


def wrist_point(robot, q):
    return dh_frames(robot, q)[4][:3, 3]          # frame 4's origin: on axes 4 and 5


def fold_det(robot, q, h=1e-6):
    J = np.empty((3, 3))
    for j in range(3):
        e = np.zeros(len(q))
        e[j] = h
        J[:, j] = (wrist_point(robot, q + e) - wrist_point(robot, q - e)) / (2 * h)
    return np.linalg.det(J)


def folds(robot, q, joint, grid=48):
    """Configurations like ``q`` with ``joint`` moved onto a fold (sign changes of
    :func:`fold_det` over a grid, bisected)."""
    xs = np.linspace(-np.pi, np.pi, grid + 1) if robot.is_revolute[joint] else \
        np.linspace(-1.0, 1.0, grid + 1)
    vals = []
    for x in xs:
        y = q.copy()
        y[joint] = x
        vals.append(fold_det(robot, y))
    out = []
    for k in range(grid):
        if np.sign(vals[k]) == np.sign(vals[k + 1]):
            continue
        a, b, fa = xs[k], xs[k + 1], vals[k]
        for _ in range(55):
            y = q.copy()
            y[joint] = m = 0.5 * (a + b)
            fm = fold_det(robot, y)
            a, b, fa = (m, b, fm) if np.sign(fm) == np.sign(fa) else (a, m, fa)
        y = q.copy()
        y[joint] = 0.5 * (a + b)
        out.append(y)
    return out


def fold_poses(seed, five, count):
    rng = np.random.default_rng(seed)
    cases = []
    while len(cases) < count:
        robot = random_arm(rng, five)
        q0 = rng.uniform(-np.pi, np.pi, robot.dof)
        cases += [(robot, q) for q in folds(robot, q0, 2)[:2]]
    return cases[:count]


def distance(robot, a, b):
    d = np.asarray(a) - b
    return np.abs(np.where(robot.is_revolute, wrap(d), d)).max()


def check_answers(robot, T, sols, approach_only=False):
    """Every answer reaches the target by the plain DH product; no two are copies."""
    for s in sols:
        F = dh_frames(robot, s.q)[-1]
        assert np.linalg.norm(F[:3, 3] - T[:3, 3]) < 1e-9
        if approach_only:
            assert np.linalg.norm(F[:3, 2] - T[:3, 2]) < 1e-9
        else:
            assert np.abs(F[:3, :3] - T[:3, :3]).max() < 1e-9
    for i, a in enumerate(sols):
        for b in sols[:i]:
            assert distance(robot, a.q, b.q) > 1e-2, (a.branch, b.branch)


def test_the_fold_search_is_independent_of_kincalc():
    robot, q = fold_poses(4, True, 1)[0]
    assert np.allclose(dh_frames(robot, q)[-1], robot.fk(q), atol=1e-12)
    assert abs(fold_det(robot, q)) < 1e-8


@pytest.mark.parametrize("seed", [1, 2, 3, 27])
def test_a_five_joint_arm_at_a_fold_gets_its_whole_pose_back(seed):
    """(Seed 27: copies some 5e-3 rad apart, beyond the 1e-3 that once bounded a
    split double root.)"""
    for robot, q in fold_poses(seed, True, 4):
        T = dh_frames(robot, q)[-1]
        sols = solve(robot, Target(T)).solutions
        check_answers(robot, T, sols)
        assert min((distance(robot, s.q, q) for s in sols), default=np.inf) < 1e-6


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_five_joint_arm_at_a_fold_places_the_approach_once(seed):
    """Position and approach: five equations for five joints, singular at the fold, where
    the generating joints are one double root, found to about the square root of rounding
    (and answered once)."""
    for robot, q in fold_poses(seed, True, 4):
        T = dh_frames(robot, q)[-1]
        P = np.eye(4)
        P[:3, 3] = T[:3, 3]
        sols = solve(robot, Target(P, orientation=False, approach=T[:3, 2])).solutions
        check_answers(robot, T, sols, approach_only=True)
        assert min((distance(robot, s.q, q) for s in sols), default=np.inf) < 1e-4


@pytest.mark.parametrize("seed", [1, 2])
def test_a_spherical_wrist_arm_at_a_fold_answers_its_double_root_once(seed):
    for robot, q in fold_poses(seed, False, 4):
        T = dh_frames(robot, q)[-1]
        sols = solve(robot, Target(T)).solutions
        check_answers(robot, T, sols)
        assert min((distance(robot, s.q, q) for s in sols), default=np.inf) < 1e-4


#: an independent campaign's case: a wrist-pair arm (axes 4 and 5 meet off the approach
#: line), its slide third, at a fold of the placement where joint 2 moves some 60 times
#: faster along the fold than joint 3; rows (type, alpha, a, d, theta), m and rad
FAST_FOLD = [("revolute", -1.6346979636540389, 0.43029596609420806, 0.27057904721188153,
              -1.0779222354483329),
             ("revolute", -1.0144736430376966, -0.48896665493104885, -0.2988575842569984,
              -2.44551856921809),
             ("prismatic", 0.8177392751483583, 0.3818380453017233, -0.35465597246830893,
              -0.29273505475491923),
             ("revolute", -0.5929405507122975, 0.0, -0.48244091841043313, 1.828030145695271),
             ("revolute", 0.4109527151216189, -0.04363689868080112, -0.03786272151700942,
              -0.4123224729715096)]
FAST_FOLD_TOOL = [[0.09601738795413807, 0.9532226853884878, 0.28661328174253287,
                   0.11626901675670531],
                  [-0.05359097812093699, -0.2825754372101949, 0.9577469025528134,
                   0.2585025009624106],
                  [0.9939359477725442, -0.10732024201532159, 0.02395198069611379,
                   0.07229849883873246],
                  [0.0, 0.0, 0.0, 1.0]]
FAST_FOLD_Q = [2.5812540459440374, -3.052229459914597, 0.5345624130665565, -1.496439228262098,
               0.25650677031710734]


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_a_fold_along_which_one_joint_moves_fast_is_placed_once(convention):
    """The resultant's two copies of the fold's double root come 0.1 .. 0.9 rad off in
    joint 2 (the point then 1e-4 off), and Gauss-Newton, halving the distance a step there,
    left them 6e-3 rad off after three steps: the whole pose, regular, was missed by 3e-4 m
    and got no solution. The copies are now polished down the fold's valley."""
    from kincalc.conventions.conversion import convert
    robot = Robot("fast fold", "dh", tuple(
        Joint(f"q{i + 1}", kind, alpha=al, a=a, d=d, theta=th)
        for i, (kind, al, a, d, th) in enumerate(FAST_FOLD)),
        base=np.eye(4), tool=np.array(FAST_FOLD_TOOL))
    q = np.array(FAST_FOLD_Q)
    assert abs(fold_det(robot, q)) < 1e-9 < abs(fold_det(robot, q + [0, 0.05, 0, 0, 0]))
    T = dh_frames(robot, q)[-1]
    sols = solve(convert(robot, convention), Target(T)).solutions
    check_answers(robot, T, sols)
    assert min((distance(robot, s.q, q) for s in sols), default=np.inf) < 1e-6
