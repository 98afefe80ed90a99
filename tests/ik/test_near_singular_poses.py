"""Poses made from joints a hair (1e-7 deg) from singular or special values.

Found by an independent sweep: the closed form took a near-tangent as the exact double
root and its candidate then missed the acceptance by about 1e-9 (rejected), reached the
pose with a joint 4e-9 rad beyond a limit the generating configuration sits on, or (a pose
rounded to 12 digits, as the CLI's JSON writes it) the rounding pushed a tangent past
its band and no candidate was left. Each test makes its poses from seeded joint values and
compares against the generating configuration and the FK round trip, not captured output.
"""

import numpy as np
import pytest

import kincalc
from kincalc.ik.near_miss import NEAR, NEAR_LIMIT, near_misses
from kincalc.ik.target import targets_from
from kincalc.tolerances import (ACCEPT_ORIENTATION, ACCEPT_POSITION, CHECK_ORIENTATION,
                                ROUNDED_POSE)

HAIR = np.deg2rad(1e-7)


def _special(rng, robot, values_deg, count):
    """``count`` configurations (rad / m): revolute joints at one of ``values_deg`` plus or
    minus a hair, or 0 hair, clipped into the limits; prismatic joints uniform within them."""
    lo, hi = robot.limits.T
    rev = np.asarray(robot.is_revolute)
    base = np.deg2rad(rng.choice(values_deg, size=(count, robot.dof)))
    base += rng.choice([-HAIR, 0.0, HAIR], size=base.shape)
    slide = rng.uniform(np.where(rev, 0, lo), np.where(rev, 0, hi), size=base.shape)
    return np.clip(np.where(rev, base, slide), lo, hi)


def _reaches(robot, q, T, orientation=ACCEPT_ORIENTATION):
    """Does every solution ``q (m, n)`` reach ``T`` within the IK acceptance (the
    orientation to ``orientation`` rad)?"""
    F = robot.fk(q)
    L = max(robot.characteristic_length, 1e-12)
    pos = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=-1) <= ACCEPT_POSITION * L * 1.01
    rot = np.abs(F[:, :3, :3] - T[:3, :3]).max((-2, -1)) <= 4 * orientation
    return pos & rot


def _distance(robot, a, b):
    """Largest joint difference (rad wrapped, m) between ``a (m, n)`` and ``b (n,)``."""
    d = a - b
    rev = np.asarray(robot.is_revolute)
    d = np.where(rev, np.angle(np.exp(1j * d)), d)
    return np.abs(d).max(-1)


def _solved(robot, T):
    """``(result, solutions (m, n))`` of ``robot.ik(T)``."""
    res = robot.ik(T)
    return res, np.array([s.q for s in res.solutions])


def _rounded(robot, q):
    """The pose of ``q`` written with 12 digits and read back (the CLI's JSON round trip)."""
    return targets_from("T", np.round(robot.fk(q), 12).reshape(1, 16))[0].T[0]


def test_solution_at_its_limit_next_to_a_merged_double_root():
    # theta1 exactly at its limit, theta2 a hair from 0: the two roots of theta1 merge to
    # their midpoint, 2e-7 deg beyond the limit; the polished one is the generating q
    r = kincalc.load_robot("spong_spherical_rrp")
    rng = np.random.default_rng(11)
    Q = _special(rng, r, [170.0, -170.0, 0.0, 90.0], 40)
    Q[:10, 0], Q[:10, 1] = np.deg2rad(170.0), -HAIR              # the sweep's case
    for q in Q:
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert len(sols) and _reaches(r, sols, T, CHECK_ORIENTATION).all()
        near = _distance(r, sols, q).min()
        assert near <= 1e-7, (np.rad2deg(q), sols)
        best = res.solutions[int(np.argmin(_distance(r, sols, q)))]
        assert best.within_limits
        # the pose rounded to 12 digits (fk --json | ik --pose): the double root moves by
        # ~1e-6 and the orientation the arm does not control missed CHECK_ORIENTATION
        T12 = _rounded(r, q)
        sols = [s for s in r.ik(T12).solutions if s.within_limits]
        assert sols and _distance(r, np.array([s.q for s in sols]), q).min() <= 1e-5


@pytest.mark.parametrize("q1", [[180.0, 0.0, 179.9999999], [90.0, -90.0]])
def test_point_plus_roll_a_hair_from_the_shoulder_singularity(q1):
    # the point on axis 4 a hair off axis 1: the candidate with q1 free missed the roll by
    # 1e-7 deg and was rejected; polished, it reaches the pose (flagged singular). With q1
    # at +-90 the miss lay across the plane q2 moves in: q1 is now turned onto it first
    r = kincalc.load_robot("fer_rrpr")
    rng = np.random.default_rng(12)
    Q = _special(rng, r, [180.0, 0.0, 90.0, -90.0, 179.9999999], 40)
    Q[:, 0] = np.deg2rad(rng.choice(q1, size=len(Q)))
    Q[:, 1] = rng.choice([-HAIR, HAIR, np.pi - HAIR], size=len(Q))
    for q in Q:
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert len(sols), np.rad2deg(q)
        assert _reaches(r, sols, T).all()
        assert any(s.singular for s in res.solutions)


@pytest.mark.parametrize("wrist2", [[90.0, -90.0], [0.0, 180.0]])
@pytest.mark.parametrize("name", ["ur16e", "ur5e", "ur10e"])
def test_twelve_digit_pose_a_hair_from_a_double_singularity(name, wrist2):
    # elbow a hair from straight: the 12-digit pose (the CLI's JSON) re-orthonormalised
    # pushed the elbow's cosine 1e-10 past 1; the generating configuration must still be
    # found. With wrist 2 a hair from 0 too, wrist 3 read from the orientation is off by
    # the pose's error over sin(wrist 2) (~1e-12 / 1.7e-9 rad) and put axis 4 out of the
    # stretched elbow's reach: no solution came back near the generating one
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(13)
    Q = _special(rng, r, [0.0, 180.0, -180.0, 90.0, -90.0], 30)
    Q[:, 2] = rng.choice([-HAIR, HAIR], size=len(Q))
    Q[:, 4] = np.deg2rad(rng.choice(wrist2, size=len(Q))) + rng.choice([-HAIR, HAIR], len(Q))
    if name == "ur16e" and wrist2[0] == 0.0:
        Q[0] = np.deg2rad([0.0, 0.0, 1e-7, -180.0, 1e-7, -360.0])     # the sweep's case
    double = wrist2[0] == 0.0
    for q in Q:
        T = _rounded(r, q)
        res, sols = _solved(r, T)
        assert len(sols), np.rad2deg(q)
        assert _reaches(r, sols, T).all()
        near = sols[np.argmin(_distance(r, sols, q))]
        if not double:
            # the pose moved by up to 1e-12: next to a double root the solution moves by
            # about its square root (the generating q reaches this pose too, to 1e-12)
            assert _distance(r, near[None], q)[0] <= 1e-4, (np.rad2deg(q), np.rad2deg(sols))
            continue
        # at both singularities the pose's 1e-12 moves wrist 3 by up to ROUNDED_POSE /
        # sin(wrist 2), and the stretched elbow by about the square root of the move of
        # axis 4 over the links (a few 1e-2 rad): the nearest solution is that near, the
        # others follow it
        assert abs(np.angle(np.exp(1j * (near[5] - q[5])))) <= ROUNDED_POSE / np.sin(HAIR)
        assert _distance(r, near[None], q)[0] <= 0.05, (np.rad2deg(q), np.rad2deg(sols))


def test_near_misses_selects_hairs_only():
    r = kincalc.load_robot("puma560")
    L = r.characteristic_length
    n = r.dof
    candidate = np.ones((1, 4), bool)
    reach = np.array([[True, False, False, True]])
    valid = reach.copy()
    pe = np.array([[0.0, 0.5 * NEAR * L, 10 * NEAR * L, 0.0]])
    oe = np.zeros((1, 4))
    viol = np.zeros((1, 4, n))
    viol[0, 3, 1] = 0.5 * NEAR_LIMIT             # a hair beyond a limit
    mask = near_misses(r, candidate, reach, pe, oe, valid, viol)
    assert mask.tolist() == [[False, True, False, True]]
    # beyond a limit by more than NEAR_LIMIT: a solution of its own (a near double root's
    # other side, 1e-4 rad away, was polished onto its neighbour within the limits and lost)
    viol[0, 3, 1] = 2 * NEAR_LIMIT
    pe[0, 1] = 10 * NEAR * L
    assert NEAR_LIMIT < NEAR and near_misses(r, candidate, reach, pe, oe, valid, viol) is None


def test_the_sweeps_twelve_digit_ur16e_pose():
    # kincalc fk ur16e 0 0 1e-07 -180 1e-07 -360 --json | kincalc ik ur16e --pose: the elbow's
    # cosine 1e-10 past 1 left no candidate ("no solution"); --from-q found the solution
    r = kincalc.load_robot("ur16e")
    q = np.deg2rad([0.0, 0.0, 1e-7, -180.0, 1e-7, -360.0])
    T = _rounded(r, q)
    _, sols = _solved(r, T)
    assert len(sols) and _reaches(r, sols, T).all()
    assert _distance(r, sols, q).min() <= 1e-6


def test_spherical_wrist_a_hair_from_the_shoulder_singularity():
    # kawasaki_rs007n -90 1e-7 0 -1e-7 ...: the wrist centre 1.3e-9 m off axis 1, across the
    # plane of JT2 at the free JT1 = 0: "reachable no"; the generating q must be found
    r = kincalc.load_robot("kawasaki_rs007n")
    rng = np.random.default_rng(14)
    Q = _special(rng, r, [0.0, 90.0, -90.0, 45.0, 180.0], 30)
    Q[:, 1] = rng.choice([-HAIR, HAIR], size=len(Q))
    Q[:, 2] = rng.choice([-HAIR, 0.0, HAIR], size=len(Q))
    Q[:, 4] = np.deg2rad(rng.choice([28.2820775, 90.0, -45.0], size=len(Q)))  # wrist regular
    Q[0] = np.deg2rad([-90.0, 1e-7, 0.0, -1e-7, 28.2820775, 307.6687621])
    for i, q in enumerate(Q):
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert len(sols) and _reaches(r, sols, T).all(), np.rad2deg(q)
        # JT1 is free with JT4 and JT6 on the axis: an equivalent solution, flagged singular
        assert all(s.singular for s in res.solutions)
        if i == 0:
            assert _distance(r, sols, q).min() <= 1e-7, (np.rad2deg(q), np.rad2deg(sols))


def test_general_6r_a_hair_from_a_degenerate_pose():
    # yaskawa_hc10 -180 -180 179.9999999 180 -180 171.47...: the pivots' elimination is
    # ill-conditioned there but not flagged, and Newton stalled 5e-6 off: "no solution"; the
    # last resort (perturbed models) now solves it. Solutions on the continuum: FK round trip
    r = kincalc.load_robot("yaskawa_hc10")
    rng = np.random.default_rng(15)
    Q = _special(rng, r, [180.0, -180.0, 179.9999999], 6)
    Q[:, 5] = rng.uniform(-np.pi, np.pi, len(Q))
    Q[0] = np.deg2rad([-180.0, -180.0, 179.9999999, 180.0, -180.0, 171.4750364])
    for i, q in enumerate(Q):
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert len(sols) and _reaches(r, sols, T).all(), np.rad2deg(q)
        assert any(s.singular for s in res.solutions)
        if i == 0:          # elsewhere a continuum: its samples need not be next to q
            assert _distance(r, sols, q).min() <= 1e-5, (np.rad2deg(q), np.rad2deg(sols))


@pytest.mark.parametrize("name", ["ur5", "ur10", "ur3e"])
def test_twelve_digit_pose_wrist_a_hair_off_and_elbow_exactly_straight(name):
    # wrist 2 1e-5 deg from 0 (axis 6 1.7e-7 rad off h) and the elbow straight: the arcs of
    # the singularity are off the exact reach by the tilt times the offsets (~1e-8 m), as
    # much as joint 6 had to move; moved on them alone, axis 4 stayed out of reach
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(14)
    Q = _special(rng, r, [0.0, 90.0, -90.0, 180.0], 30)
    Q[:, 2] = 0.0
    Q[:, 4] = np.deg2rad(rng.choice([-1e-5, 1e-5], len(Q)) + rng.choice([0.0, 180.0], len(Q)))
    Q[0] = np.deg2rad([-90.0000001, -1e-05, 0.0, -1e-05, -1e-05, -89.9999999])   # the sweep's
    for q in Q:
        T = _rounded(r, q)
        _, sols = _solved(r, T)
        assert len(sols), np.rad2deg(q)
        assert _reaches(r, sols, T).all()
        assert _distance(r, sols, q).min() <= 0.05, (np.rad2deg(q), np.rad2deg(sols))


@pytest.mark.parametrize("fold", [1e-2, 1e-3, 1e-4])
def test_position_arm_folded_next_to_its_shoulder_given_a_whole_pose(fold):
    # an arm of equal links folded (q3 a little off 180 deg) with the tool above the
    # shoulder, on axis 1: q2 from the position is a double root there, good to the square
    # root of rounding over the tool's distance from the shoulder (2e-5 .. 4e-3 rad), and
    # the orientation the arm does not control, which follows q2, missed its near miss
    r = kincalc.load_robot("siciliano_arm")
    rng = np.random.default_rng(15)
    for q1 in [90.0, *rng.uniform(-180.0, 180.0, 5)]:
        q = np.deg2rad([q1, 0.0, 180.0 - fold])
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert len(sols), (q1, fold, res.reason)
        assert _reaches(r, sols, T, CHECK_ORIENTATION).all()
        assert _distance(r, sols, q).min() <= 1e-6


def test_position_arm_at_a_fold_given_a_twelve_digit_pose():
    """A three-joint position arm at a fold of its workspace (q2 = 0 a double root of the
    position), given the whole pose rounded to 12 digits (found by an independent campaign):
    the rounding splits the double root into two roots 0.13 deg either side, each reaching
    the position exactly, the orientation the arm does not control 8e-4 rad off: "orientation
    out of reach". Polished on the whole pose, the fold's solution reaches it to the check,
    next to the generating joints (by the square root of the rounding)."""
    from kincalc.model import Joint, Robot
    P = np.pi
    rows = [(P, 0.1259666097780755, 0.0, -0.2093994807185453),
            (-P / 2, 0.22570215617389455, -0.09153007944213465, 0.0),
            (0.0, 0.4085787502869178, 0.0, P)]
    r = Robot(name="fold3", convention="dh", base=np.eye(4), tool=np.eye(4), joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=th, limits=(-2 * P, 2 * P))
        for i, (al, a, d, th) in enumerate(rows)))
    q = np.array([-1.1566437054860392, 0.0, -P / 2])
    T = np.round(r.fk(q), 12)
    res, sols = _solved(r, T)
    assert len(sols) == 1, res.reason
    assert _reaches(r, sols, T, CHECK_ORIENTATION).all()
    assert _distance(r, sols, q).min() <= 1e-5


def test_spherical_wrist_next_to_a_double_singularity_twelve_digit_pose():
    """A spherical wrist a hair (5e-8 deg) from q5 = 0 with joint 3 a hair from 0 (two
    singular values of 7e-11 and 6e-17), the pose rounded to 12 digits (found by an
    independent campaign): the closed form's candidate misses the orientation by 1.2e-9,
    and eight Newton steps, converging linearly there, left 1.2e-9 m: "orientation out of
    reach" for an FK pose. Polished to the acceptance, it reproduces the pose."""
    from kincalc.model import Joint, Robot
    P = np.pi
    rows = [(P / 2, 0.0, 0.0), (P, -0.20315762568652462, 0.0),
            (0.0, -0.2133581493033181, 0.045034214429813146), (P / 2, 0.0, -0.40003910725364267),
            (-1.5707969280036034, 0.0, 0.0), (P, 0.0, -0.06046335520284729)]
    r = Robot(name="wrist6", convention="dh", base=np.eye(4), tool=np.eye(4), joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0, limits=(-2 * P, 2 * P))
        for i, (al, a, d) in enumerate(rows)))
    q = np.radians([179.9999999539564, -90.0000000460436, 4.604359845356874e-08,
                    30.384059646281287, 4.604359845356874e-08, -137.2058386549449])
    T = np.round(r.fk(q), 12)
    res, sols = _solved(r, T)
    assert len(sols), res.reason
    assert _reaches(r, sols, T, ACCEPT_ORIENTATION).all()


def test_bk_6r_a_hair_from_its_wrist_centre_on_axis_2_and_q5_180():
    """bk_6r (Bingul & Kucuk's 6R) 8e-7 deg from q3 = 90 (the wrist centre on axis 2 and on
    the shoulder cylinder) and q5 = 180: the exact FK pose had no solution (an independent
    campaign). Joint 3's double root is taken at its tangent, which leaves the wrist centre
    2e-8 m off axis 2; joint 2, free there, was then solved only to 1e-9. Now the pose gets
    the continuum's representatives (theta2 free), each reproducing it."""
    r = kincalc.load_robot("bk_6r")
    q = np.array([2.00691074453122, -0.39806129619090913, 1.5707963407773267,
                  2.8808072874075847, 3.141592639607363, -1.5707963407773267])
    T = r.fk(q)
    res, sols = _solved(r, T)
    assert len(sols) == 2, res.reason
    assert _reaches(r, sols, T).all()
    assert all(1 in s.free for s in res.solutions)


def _a_hair_from_folded(rng, eps):
    """Joints ``(3,)`` of a planar 3R arm: q1 and q3 at random, q2 = +-(180 deg - eps)."""
    return np.array([rng.uniform(-np.pi, np.pi), rng.choice([-1.0, 1.0]) * (np.pi - eps),
                     rng.uniform(-np.pi, np.pi)])


@pytest.mark.parametrize("eps", [1e-6, 1e-7, 1e-8])
def test_planar_arm_of_equal_links_a_hair_from_folded_onto_its_first_axis(eps):
    """craig_3r (L1 = L2) with q2 = +-(180 deg - eps): the point on axis 3 lies eps L1 off
    axis 1, beyond the acceptance. Joint 2's cosine is within rounding of -1 and was taken as
    the tangent, one double root that left the point on axis 1: one solution, "theta1 free",
    the other lost. Both are solutions: the generating joints and, by the isosceles triangle
    of the two links, ``(q1 + q2, -q2, q2 + q3)``; neither joint is free. (Joint 1's angle is
    good to rounding over the point's distance from its axis: compared to 1e-6.)"""
    r = kincalc.load_robot("craig_3r")
    rng = np.random.default_rng(16)
    for _ in range(6):
        q = _a_hair_from_folded(rng, eps)
        T = r.fk(q)
        res, sols = _solved(r, T)
        mirror = np.array([q[0] + q[1], -q[1], q[1] + q[2]])
        assert len(sols) == 2, (np.rad2deg(q), res.reason)
        assert _reaches(r, sols, T).all()
        assert _distance(r, sols, q).min() <= 1e-6 and _distance(r, sols, mirror).min() <= 1e-6
        assert not any(s.free for s in res.solutions)


@pytest.mark.parametrize("eps", [1e-6, 1e-7])
def test_planar_arm_of_nearly_equal_links_a_hair_from_folded(eps):
    """Links 1 and 1 - 1e-4 (a planar 3R arm, a whole planar pose), q2 = +-(180 deg - eps):
    the point on axis 3 lies about 1e-4 off axis 1, so the elbow's two roots, 2 eps apart,
    take joint 1 some 2 eps / 1e-4 apart. Joint 2's cosine within rounding of -1 was taken
    as one double root, and the split that answers a double root folding the point onto
    axis 1 held only within 1e-6 of the arm's size of it: one solution, the other elbow
    (4e-3 rad away at 1e-6) lost (an independent campaign's planar-shoulder arm with a1 ~
    a2). Both are found, each reaching the pose: the generating joints and the other elbow
    by the plane's triangle (q2' = -q2, q1' = atan2(p) - atan2(l2 sin q2', l1 + l2 cos q2'),
    q3' completing the turn)."""
    from kincalc.model import Joint, Robot
    l1, l2 = 1.0, 1.0 - 1e-4
    r = Robot(name="nearly equal", convention="dh", joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=0.0, a=a, d=0.0, theta=0.0)
        for i, a in enumerate((l1, l2, 0.3))))
    rng = np.random.default_rng(29)
    for _ in range(4):
        q = _a_hair_from_folded(rng, eps)
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert len(sols) == 2, (np.rad2deg(q), res.reason)
        assert _reaches(r, sols, T).all()
        p = np.array([l1 * np.cos(q[0]) + l2 * np.cos(q[0] + q[1]),
                      l1 * np.sin(q[0]) + l2 * np.sin(q[0] + q[1])])
        q2 = -q[1]
        q1 = np.arctan2(p[1], p[0]) - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
        other = np.array([q1, q2, q.sum() - q1 - q2])
        assert _distance(r, other, q) > 1e-3          # the elbows, far apart in joint 1
        for root in (q, other):
            assert _distance(r, sols, root).min() <= 1e-6, np.rad2deg(root)


def test_planar_arm_of_equal_links_folded_within_the_acceptance_leaves_joint_1_free():
    # 1e-10 rad from folded: the point 5e-11 m from axis 1, within the acceptance: one
    # representative of the continuum, joint 1 free
    r = kincalc.load_robot("craig_3r")
    q = np.array([0.3, np.pi - 1e-10, -0.7])
    res, sols = _solved(r, r.fk(q))
    assert len(sols) == 1 and res.solutions[0].free == (0,)
    assert _reaches(r, sols, r.fk(q)).all()


@pytest.mark.parametrize("q2", [1e-6, -1e-7, 1e-8])
def test_spherical_wrist_arm_upright_a_hair_off_axis_1(q2):
    """kawasaki_rs007n upright (JT2 a hair from 0, JT3 = 0): the wrist centre ~q2 x 0.7 m off
    axis 1, beyond the acceptance. JT2's double root (the wrist centre at its highest) was
    taken as one root on axis 1: JT1 "free" and the shoulder's other side lost. Both sides
    reach the pose, JT1 half a turn apart, none free, the generating joints among them (to
    1e-6: JT1's angle is good to rounding over the wrist centre's distance from axis 1)."""
    r = kincalc.load_robot("kawasaki_rs007n")
    rng = np.random.default_rng(17)
    for _ in range(4):
        q = np.array([rng.uniform(-2.5, 2.5), q2, 0.0, *rng.uniform(-1.5, 1.5, 3)])
        q[4] = rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 1.5)              # wrist regular
        T = r.fk(q)
        res, sols = _solved(r, T)
        assert _reaches(r, sols, T).all()
        assert _distance(r, sols, q).min() <= 1e-6, (np.rad2deg(q), res.reason)
        sides = np.angle(np.exp(1j * (sols[:, 0] - q[0])))
        assert (np.abs(sides) < 1e-6).any() and (np.abs(np.abs(sides) - np.pi) < 1e-6).any()
        assert not any(s.free for s in res.solutions)


def test_five_joint_approach_arm_twelve_digit_pose_at_q5_0():
    """A five-joint arm (axes 4 and 5 meeting on the approach line) at q5 = 0, the pose
    rounded to 12 digits (an independent campaign): subproblem 2's double root split into
    q5 = +-1.9e-5, each missing the approach by 1.8e-5 rad, beyond the near miss of 1e-5:
    "orientation out of reach". The generating joints reach the rounded pose to 1.5e-12."""
    from kincalc.model import Joint, Robot
    P = np.pi
    rows = [(0.0962933399642707, 0.17861062103966374, -0.22251599635348324),
            (-0.5750798109183086, -0.07037383725610033, -0.49962925177928214),
            (0.9573633631976515, -0.15552959075142078, -0.4883837869666649),
            (2.498682104261955, 0.0, -0.42990396692393346),
            (-0.0438376661931823, 0.0, 0.0)]
    r = Robot(name="approach5", convention="dh", base=np.eye(4), tool=np.eye(4), joints=tuple(
        Joint(f"j{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0, limits=(-1.5 * P, 1.5 * P))
        for i, (al, a, d) in enumerate(rows)))
    q = np.array([-3.1358134481626974, -0.501495358901825, 0.8258374108833015,
                  2.7329411561883177, 0.0])
    T = _rounded(r, q)
    res, sols = _solved(r, T)
    assert res.family == "position-approach" and len(sols), res.reason
    assert _distance(r, sols, q).min() <= 1e-6


def test_planar_arm_of_nearly_equal_links_a_hair_from_folded_near_its_first_axis():
    """Links 0.5 and 0.500000005 m: folded, the point passes 5e-9 m from axis 1, not through
    it, and q2 = 180 deg - 1e-7 leaves the target 5e-8 m off the axis. The double root
    left joint 1 'free' (a representative) and the generating joints were lost (an
    independent review). Both solutions, each Gauss-Newton's from random starts."""
    from kincalc.model import Joint, Robot
    from randrobots import newton_roots
    r = Robot(name="p3", convention="dh", base=np.eye(4), tool=np.eye(4), joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=0.0, a=a, d=0.0, theta=0.0, limits=(-np.pi, np.pi))
        for i, a in enumerate((0.5, 0.500000005, 0.2))))
    q = np.array([0.4, np.pi - 1e-7, -1.1])
    T = r.fk(q)
    res, sols = _solved(r, T)
    assert len(sols) == 2 and _reaches(r, sols, T).all(), res.reason
    assert not any(s.free for s in res.solutions)
    for root in [q] + newton_roots(r, T, 40, np.random.default_rng(18)):
        assert _distance(r, sols, root).min() <= 1e-6
