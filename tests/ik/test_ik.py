"""Inverse kinematics: the seed documents' worked examples, every bundled robot, and
random robots of every supported family in all three conventions (round trips)."""

import zlib

import numpy as np
import pytest
from randrobots import random_pose

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik import Target, solve
from kincalc.ik.families import classify
from kincalc.ik.reasons import OrientationOut, OutOfReach
from kincalc.analysis.results import ik_document
from kincalc.ik.screws import Screws
from kincalc.spatial import wrap
from kincalc.ik.selftest import sample_configurations
from kincalc.conventions.library import bundled_names
from kincalc.model import Joint, Robot

D = np.deg2rad


def close(q, ref, robot, tol=1e-6):
    d = np.where(robot.is_revolute, wrap(np.asarray(q) - ref), np.asarray(q) - ref)
    return np.all(np.abs(d) < tol)


# --- seed document 000 -------------------------------------------------------

def test_example_4_2_two_valid_sets_and_two_rejected():
    r = load_robot("bk_rr")
    T = np.eye(4)
    T[:3, 3] = [12.99, 2.5, 0]
    res = solve(r, Target(T, orientation=False), all_branches=True)
    got = sorted(np.rad2deg(s.q).round(1).tolist() for s in res.solutions)
    assert got == [[-8.2, 60.0], [30.0, -60.0]]
    rejected = sorted(np.rad2deg(x["q"]).round(1).tolist() for x in res.rejected)
    assert rejected == [[-8.2, -60.0], [30.0, 60.0]]     # the book's zeta4 and zeta1
    assert all(x["position_error"] > 1 for x in res.rejected)


def test_example_4_6_scara_with_euler_wrist():
    r = load_robot("bk_scara_euler")
    from kincalc.spatial import matrix_from_rpy, transform
    T = transform(matrix_from_rpy(D([42, -17, 25])), [28, 31, 6])
    res = solve(r, Target(T))
    assert len(res.solutions) == 4
    q = np.array([s.q for s in res.solutions])
    q = np.where(r.is_revolute, np.rad2deg(q), q)
    assert sorted(set(q[:, 0].round(2))) == [32.79, 63.03]
    for row in q:
        assert abs(abs(row[1]) - 37.26) < 0.01 and np.sign(row[1]) == (1 if row[0] < 40 else -1)
        assert abs(row[2] - 12) < 1e-9                      # d3 = h1 - pz - d4
        assert abs(abs(row[4]) - 135.29) < 0.01
        if row[4] > 0:
            assert abs(row[5] - (-65.44)) < 0.01
    for s in res.solutions:                                  # every set reproduces the pose
        assert np.allclose(r.fk(s.q), T, atol=1e-9)
    # the book's theta4 = -72.2 deg is wrong: with its own theta1, theta2, d3, theta5, theta6
    # the position is right but the orientation misses by about 179 deg (yaw -154 instead of 25)
    book = D([63.03, -37.25, 0, -72.2, 135.29, -65.44])
    book[2] = 12
    Tb = r.fk(book)
    assert np.linalg.norm(Tb[:3, 3] - T[:3, 3]) < 0.01
    from kincalc.spatial import rotation_error
    assert np.rad2deg(rotation_error(Tb[:3, :3], T[:3, :3])) > 170
    right = [s for s in res.solutions if abs(np.rad2deg(s.q[0]) - 63.03) < 0.01 and s.q[4] > 0][0]
    assert abs(np.rad2deg(right.q[3]) - 108.77) < 0.01


def test_example_4_5_6r_has_eight_not_sixteen_solutions():
    r = load_robot("bk_6r")
    counts = []
    rng = np.random.default_rng(45)
    for q in sample_configurations(r, 200, rng):
        counts.append(len(r.ik(r.fk(q)).solutions))
    assert max(counts) == 8 and counts.count(8) > 100


def test_offset_wrist_arm_of_the_second_example_4_6():
    r = load_robot("bk_offset_wrist")
    q = np.array([D(20), 4.0, D(-35), D(70), D(50), D(-15)])
    res = r.ik(r.fk(q))
    assert res.family == "parallel-four-wrist"
    assert any(close(s.q, q, r) for s in res.solutions)
    assert len(res.solutions) in (2, 4)   # 2 for theta5 x 2 for the planar elbow, where reachable
    counts = [len(r.ik(r.fk(x)).solutions)
              for x in sample_configurations(r, 40, np.random.default_rng(46))]
    assert max(counts) == 4
    # the book: d2 = pz - r33 d6 (with its frames), theta6 from atan2(-r32, r31) up to pi
    for s in res.solutions:
        assert np.allclose(r.fk(s.q), r.fk(q), atol=1e-9)


def test_rrp_and_rpr_have_four_position_solutions():
    for name in ("bk_rrp", "bk_rpr"):
        r = load_robot(name)
        q = np.array([0.4, -0.6, 1.5]) if name == "bk_rrp" else np.array([0.4, 1.5, -0.6])
        res = solve(r, Target(r.fk(q), orientation=False))
        assert len(res.solutions) == 4
        assert any(close(s.q, q, r) for s in res.solutions)


def test_zagreb_rrpr():
    r = load_robot("fer_rrpr")
    q = np.array([D(30), D(50), 0.25, D(40)])
    res = r.ik(r.fk(q))
    assert any(close(s.q, q, r) for s in res.solutions)
    # the homework's closed form: q1 = atan2(w2, w1), q2 = +-atan2(sqrt(w1^2+w2^2), d1 - w3)
    p = r.fk(q)[:3, 3]
    q1 = np.arctan2(p[1], p[0])
    q2 = np.arctan2(np.hypot(p[0], p[1]), 0.5 - p[2])
    assert any(abs(wrap(s.q[0] - q1)) < 1e-9 and abs(wrap(s.q[1] - q2)) < 1e-9 for s in res.solutions)


# --- every bundled robot -------------------------------------------------------

SUPPORTED = [n for n in bundled_names()
             if classify(load_robot(n), Screws.of(load_robot(n)))[0] is not None
             and classify(load_robot(n), Screws.of(load_robot(n)))[0].name != "general-6r"]


def test_most_of_the_library_is_supported():
    assert len(SUPPORTED) >= 25, SUPPORTED


@pytest.mark.parametrize("name", SUPPORTED)
def test_bundled_robot_round_trip(name):
    r = load_robot(name)
    fam, _ = classify(r, Screws.of(r))
    rng = np.random.default_rng(7)
    Q = sample_configurations(r, 300, rng)
    hits = 0
    scale = r.characteristic_length
    for q in Q:
        T = r.fk(q)
        res = solve(r, Target(T, orientation=fam.needs_orientation))
        for s in res.solutions:
            assert np.all(np.isfinite(s.q))
            assert np.linalg.norm(r.fk(s.q)[:3, 3] - T[:3, 3]) <= 1e-9 * scale
        hits += any(close(s.q, q, r, 1e-6 * max(1.0, scale)) for s in res.solutions)
    assert hits / len(Q) >= 0.999, hits


def test_family_counts_at_generic_poses():
    for name, n in (("puma560", 8), ("ur5", 8), ("kuka_kr16", 8), ("abb_irb120", 8)):
        r = load_robot(name)
        counts = [len(r.ik(r.fk(q)).solutions) for q in
                  sample_configurations(r, 60, np.random.default_rng(3))]
        assert max(counts) == n, (name, counts)


# --- random robots of every family, in all three conventions -----------------------

def dh(rng, types_alpha_a_d):
    joints = []
    for i, (t, alpha, a, d) in enumerate(types_alpha_a_d):
        joints.append(Joint(f"q{i + 1}", t, alpha=alpha, a=a, d=d,
                            theta=rng.uniform(-np.pi, np.pi)))
    return Robot("rand", "dh", tuple(joints), base=random_pose(rng), tool=random_pose(rng))


def u(rng, lo=-0.5, hi=0.5):
    return rng.uniform(lo, hi)


def random_family_robot(rng, family):
    ang = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731 (non-zero twist)
    if family == "spherical-wrist":
        first = [(rng.choice(["revolute", "prismatic"], p=[0.8, 0.2]), ang(), u(rng), u(rng))
                 for _ in range(3)]
        return dh(rng, first + [("revolute", ang(), 0.0, u(rng)), ("revolute", ang(), 0.0, 0.0),
                                ("revolute", u(rng, -3, 3), u(rng), u(rng))])
    if family in ("three-parallel", "three-parallel-offset"):     # axes 5, 6 meet, or skew
        skew = u(rng, 0.05, 0.5) * rng.choice([-1, 1]) if family.endswith("offset") else 0.0
        return dh(rng, [("revolute", ang(), u(rng), u(rng)), ("revolute", 0.0, u(rng), u(rng)),
                        ("revolute", 0.0, u(rng), u(rng)), ("revolute", ang(), 0.0, u(rng)),
                        ("revolute", ang(), skew, u(rng)),
                        ("revolute", u(rng, -3, 3), u(rng), u(rng))])
    if family == "parallel-four-wrist":
        types = ["revolute", "revolute", "revolute"]
        types[int(rng.integers(0, 3))] = "prismatic"
        return dh(rng, [(t, 0.0, u(rng), u(rng)) for t in types] +
                  [("revolute", ang(), u(rng), u(rng)), ("revolute", ang(), 0.0, u(rng)),
                   ("revolute", u(rng, -3, 3), u(rng), u(rng))])
    if family == "position-3":
        return dh(rng, [(rng.choice(["revolute", "prismatic"]), ang(), u(rng), u(rng))
                        for _ in range(3)])
    if family == "planar-3":
        return dh(rng, [("revolute", 0.0, u(rng), u(rng)) for _ in range(3)])
    if family == "position-2":
        return dh(rng, [(rng.choice(["revolute", "prismatic"]), ang(), u(rng), u(rng))
                        for _ in range(2)])
    if family == "point-plus-roll":
        return dh(rng, [(rng.choice(["revolute", "prismatic"]), ang(), u(rng), u(rng))
                        for _ in range(3)] + [("revolute", u(rng, -3, 3), u(rng), u(rng))])
    raise ValueError(family)


@pytest.mark.parametrize("family", ["spherical-wrist", "three-parallel", "three-parallel-offset",
                                    "parallel-four-wrist", "position-3",
                                    "planar-3", "position-2", "point-plus-roll"])
@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_random_robots_of_each_family(family, convention):
    rng = np.random.default_rng(zlib.crc32(f"{family}/{convention}".encode()))   # stable across runs
    trials = hits = 0
    for _ in range(8):
        r = random_family_robot(rng, family)
        r = {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]
        fam, _ = classify(r, Screws.of(r))
        assert fam is not None and fam.name == family, (fam, family)
        for q in sample_configurations(r, 40, rng):
            T = r.fk(q)
            res = solve(r, Target(T, orientation=fam.needs_orientation))
            for s in res.solutions:
                assert np.all(np.isfinite(s.q))
                Tq = r.fk(s.q)
                assert np.linalg.norm(Tq[:3, 3] - T[:3, 3]) <= 1e-9 * r.characteristic_length
                if fam.needs_orientation:
                    assert np.abs(Tq[:3, :3] - T[:3, :3]).max() < 1e-9
            trials += 1
            hits += any(close(s.q, q, r, 1e-6 * max(1.0, r.characteristic_length))
                        for s in res.solutions)
    assert hits / trials >= 0.995, (hits, trials)


def test_unreachable_target_says_why():
    r = load_robot("puma560")
    T = np.eye(4)
    T[:3, 3] = [2.0, 0, 0]
    res = r.ik(T)
    assert not res.reachable and res.solutions == []
    # the reason is data (SI), worded at the edge
    assert isinstance(res.reason, OutOfReach) and res.reason.outside.where == "beyond-outer-reach"
    assert res.reason.outside.target == pytest.approx(np.linalg.norm(T[:3, 3] - r.base[:3, 3]))
    assert "beyond the outer reach" in ik_document(res)["reason"]


def test_wrist_singular_target_gives_a_representative_and_the_continuum():
    r = load_robot("puma560")
    q = D([10, -30, 150, 25, 0, 35])      # q5 = 0: axes 4 and 6 aligned
    res = r.ik(r.fk(q))
    assert res.solutions and all(np.all(np.isfinite(s.q)) for s in res.solutions)
    sing = [s for s in res.solutions if s.singular]
    assert sing and any(s.continuum for s in sing)
    for s in res.solutions:
        assert np.allclose(r.fk(s.q), r.fk(q), atol=1e-9)


def test_joint_limits_flagged_and_blocked_reason():
    r = load_robot("puma560")
    q = D([10, -30, 150, 25, 40, 35])
    res = r.ik(r.fk(q))
    outs = [s for s in res.solutions if not s.within_limits]
    for s in outs:
        assert s.violations
        lo, hi = r.limits.T
        for i, amount, side in s.violations:
            assert amount > 0 and (s.q[i] < lo[i] if side == "lower" else s.q[i] > hi[i])


def tcv_target(w):
    """The IK target of a tool configuration vector ``w (6,)`` (SI; as the CLI reads one)."""
    T = np.eye(4)
    T[:3, 3] = w[:3]
    n = np.linalg.norm(w[3:])
    return Target(T, orientation=False, tcv=(w[3:] / n, np.pi * np.log(n)))


def test_zagreb_tool_configuration_vector_target():
    from kincalc.spatial import tcv_from_transform
    r = load_robot("fer_rrpr")
    q = np.array([D(30), D(50), 0.25, D(40)])
    w = tcv_from_transform(r.fk(q), q[3])
    res = solve(r, tcv_target(w))
    assert any(close(s.q, q, r) for s in res.solutions)
    # homework eq. (2-4): q4 = pi/2 ln(w4^2 + w5^2 + w6^2) for every solution
    for s in res.solutions:
        assert abs(s.q[3] - np.pi / 2 * np.log(np.sum(w[3:] ** 2))) < 1e-12
    # and the +-q2 branch the homework writes (with q1 + 180 deg) is there too
    assert any(abs(wrap(s.q[0] - q[0] - np.pi)) < 1e-9 and abs(s.q[1] + q[1]) < 1e-9
               for s in res.solutions)


@pytest.mark.parametrize("name", ["bk_rpr", "planar_3r", "fer_rrpr"])
def test_tcv_targets_leave_no_constants_behind(name):
    """The tool point a tcv's joints place turns with the target's roll (off the last axis):
    its plan was kept on the robot's screws as a constant, one more for every target a
    process solved."""
    from kincalc.ik.families import plan
    from kincalc.spatial import tcv_from_transform
    r = load_robot(name)
    S = plan(r)[0]
    rng = np.random.default_rng(5)

    def solve_some(k):
        for q in sample_configurations(r, k, rng):
            w = tcv_from_transform(r.fk(q), q[-1])
            res = solve(r, tcv_target(w))
            assert any(close(s.q, q, r) for s in res.solutions)

    solve_some(3)
    kept = len(S.cache)
    solve_some(40)
    assert len(S.cache) == kept


@pytest.mark.parametrize("q4", [600.0, -300.0, 200.0, 405.0])
def test_a_tcv_last_joint_beyond_a_half_turn_is_not_moved_by_a_turn(q4):
    """The vector holds e^(q4 / pi): q4 = 600 deg and q4 = -120 deg are different vectors.
    The limits' normaliser moved the solver's q4 by whole turns (600 came out -120, "ok")."""
    from dataclasses import replace
    from kincalc.spatial import tcv_from_transform
    r = load_robot("fer_rrpr")
    q = np.array([D(30), D(60), 0.3, D(q4)])
    w = tcv_from_transform(r.fk(q), q[3])
    target = tcv_target(w)
    res = solve(r, target)
    assert len(res.solutions) == 2 and any(close(s.q, q, r) for s in res.solutions)
    for s in res.solutions:             # homework eq. (2-4), and the vector back from FK
        assert abs(s.q[3] - np.pi / 2 * np.log(np.sum(w[3:] ** 2))) < 1e-12
        assert np.allclose(tcv_from_transform(r.fk(s.q), s.q[3]), w, atol=1e-9)
    # nor by --near, which moves the other joints by whole turns towards it
    near = np.array([q[0] + 4 * np.pi, q[1], q[2], 0.0])
    res = solve(r, target, near=near)
    assert any(close(s.q, q, r) and abs(s.q[0] - near[0]) < 1e-9 for s in res.solutions)
    assert all(abs(s.q[3] - D(q4)) < 1e-12 for s in res.solutions)
    # limits that hold q4 only a turn away: the solutions are outside them, not turned in
    joints = list(r.joints)
    joints[3] = replace(joints[3], limits=(D(q4) + D(300), D(q4) + D(420)))
    lim = replace(r, joints=tuple(joints))
    res = solve(lim, target)
    assert len(res.solutions) == 2 and not res.reachable
    for s in res.solutions:
        assert abs(s.q[3] - D(q4)) < 1e-12 and s.violations[0][0] == 3


def _planar_tilted_arm(rng):
    """Three parallel revolute axes (a random direction) and a tilted fourth, random points
    and tool: ``planar-4``, as POE."""
    from kincalc import parse_robot_text
    from kincalc.spatial import matrix_from_axis_angle, rpy_from_matrix

    def unit(v):
        return v / np.linalg.norm(v)
    h, k4 = unit(rng.normal(size=3)), unit(rng.normal(size=3))
    axes = [h, h, h, k4]
    points = rng.uniform(-0.5, 0.5, (4, 3))
    R = matrix_from_axis_angle(unit(rng.normal(size=3)), rng.uniform(0, np.pi))
    joints = "".join(f"  - {{name: j{i + 1}, type: revolute, axis: {list(map(float, a))}, "
                     f"point: {list(map(float, p))}}}\n"
                     for i, (a, p) in enumerate(zip(axes, points)))
    tool = (f"tool: {{xyz: {list(map(float, rng.uniform(-0.5, 0.5, 3)))}, "
            f"rpy: {list(map(float, np.degrees(rpy_from_matrix(R))))}}}\n")
    return parse_robot_text("name: tilted\nconvention: poe\nunits: {length: m, angle: deg}\n"
                            "joints:\n" + joints + tool)


@pytest.mark.parametrize("seed", range(5))
def test_tcv_of_a_planar_arm_with_a_tilted_last_joint(seed):
    """Three parallel axes place the tool point on a curve, not at points: the approach
    chooses where on it (every such TCV was "the approach vector is not reachable"). The
    approach and the last joint fix the whole orientation, so the TCV's solutions are the
    whole pose's with that last joint: checked by FK, the generating joints among them."""
    from kincalc.ik.families import plan
    from kincalc.spatial import tcv_from_transform
    rng = np.random.default_rng(seed)
    r = _planar_tilted_arm(rng)
    assert plan(r)[1].name == "planar-4"
    for q in rng.uniform(-np.pi, np.pi, (8, 4)):
        w = tcv_from_transform(r.fk(q), q[3])
        res = solve(r, tcv_target(w))
        assert any(close(s.q, q, r) for s in res.solutions)
        for s in res.solutions:
            assert abs(s.q[3] - q[3]) < 1e-9
            assert np.allclose(tcv_from_transform(r.fk(s.q), s.q[3]), w, atol=1e-9)
        whole = [s for s in r.ik(r.fk(q)).solutions if abs(wrap(s.q[3] - q[3])) < 1e-9]
        assert len(res.solutions) == len(whole)


def test_tcv_typed_to_six_decimals_is_still_reachable():
    # bug: the approach check allowed 1e-7 rad, so a TCV printed by 'kincalc fk' and
    # typed back with 6 decimals (approach off by 2.3e-7 rad) was called unreachable
    from kincalc.spatial import tcv_from_transform
    r = load_robot("fer_rrpr")
    q = np.array([D(30), D(60), 0.3, D(45)])
    w = np.round(tcv_from_transform(r.fk(q), q[3]), 6)
    res = solve(r, tcv_target(w))
    assert res.reachable and any(np.allclose(s.q, q, atol=1e-5) for s in res.solutions)


def test_general_6r_through_the_dispatcher():
    r = load_robot("manocha_canny_6r")
    res = r.ik(r.fk(r.home))
    assert res.family == "general-6r" and len(res.solutions) == 16
    assert len({s.branch for s in res.solutions}) == 16
    assert any(close(s.q, r.home, r) for s in res.solutions)


# --- the same families with the chain reversed (a spherical wrist at the base, ...) -----

def test_reversed_screws_give_the_inverse_pose():
    """Screws.reversed: T'(-q[::-1]) must be T(q)^-1 (a second formulation of FK)."""
    rng = np.random.default_rng(11)
    for _ in range(5):
        r = random_family_robot(rng, "spherical-wrist")
        S, R = Screws.of(r), Screws.of(r).reversed()
        for q in sample_configurations(r, 20, rng):
            qr = -q[::-1]
            Tr = R.product(range(6), qr) @ R.M
            assert np.allclose(Tr @ r.fk(q), np.eye(4), atol=1e-12)


def wrist_first_robot(rng):
    """Axes 1, 2, 3 concurrent (a1 = a2 = d2 = 0), joints 4-6 any type and geometry."""
    ang = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731
    rest = [(rng.choice(["revolute", "prismatic"], p=[0.7, 0.3]), ang(), u(rng), u(rng))
            for _ in range(3)]
    return dh(rng, [("revolute", ang(), 0.0, u(rng)), ("revolute", ang(), 0.0, 0.0),
                    ("revolute", ang(), u(rng), u(rng))] + rest)


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_spherical_wrist_at_the_base(convention):
    rng = np.random.default_rng({"dh": 1, "mdh": 2, "poe": 3}[convention])
    trials = hits = 0
    for _ in range(8):
        r = wrist_first_robot(rng)
        r = {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]
        fam, _ = classify(r, Screws.of(r))
        assert fam is not None and fam.name == "reversed-spherical-wrist", fam
        for q in sample_configurations(r, 40, rng):
            T = r.fk(q)
            res = solve(r, Target(T))
            for s in res.solutions:
                assert np.allclose(r.fk(s.q), T, atol=1e-9 * max(1.0, r.characteristic_length))
            trials += 1
            hits += any(close(s.q, q, r, 1e-6 * max(1.0, r.characteristic_length))
                        for s in res.solutions)
    assert hits / trials >= 0.995, (hits, trials)


def test_reversed_ur_arm_and_batch():
    """A UR arm mounted tool-first (axes 1, 2 meet, 3, 4, 5 parallel) gets its 8 solutions,
    by robot.ik and by robot.ik_batch alike."""
    from kincalc.model import Joint, Robot
    ur = load_robot("ur5")
    R = Screws.of(ur).reversed()
    joints = tuple(Joint(f"j{i + 1}", "revolute", axis=tuple(R.axis[i]), point=tuple(R.point[i]),
                         limits=(-2 * np.pi, 2 * np.pi)) for i in range(6))
    r = Robot("ur5_reversed", "poe", joints, M=R.M)
    fam, _ = classify(r, Screws.of(r))
    assert fam.name == "reversed-three-parallel"
    Q = sample_configurations(r, 50, np.random.default_rng(4))
    counts = []
    for q in Q:
        res = r.ik(r.fk(q))
        counts.append(len(res.solutions))
        assert any(close(s.q, q, r) for s in res.solutions)
    assert max(counts) == 8
    batch = r.ik_batch(r.fk(Q))
    assert list(batch.valid.sum(1)) == counts


def test_wrist_continuum_value_is_the_solutions_own():
    """At q5 = 0 the PUMA's axes 4 and 6 line up: the reported relation must hold for the
    returned solutions (q4 + q6 or q4 - q6, whichever the axes' directions give)."""
    r = load_robot("puma560")
    for q5 in (0.0, np.pi):
        q = D([10, -30, 150, 25, 0, 35])
        q[4] = q5
        res = r.ik(r.fk(q))
        for s in res.solutions:
            if s.continuum is None:
                continue
            c = s.continuum
            assert abs(wrap(s.q[c.i] + c.sign * s.q[c.j] - c.total)) < 1e-9


# --- five joints: position and approach direction ------------------------------------

def five_joint_robot(rng, kind):
    from kincalc.spatial import rot_y, rot_z, transform
    ang = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731
    if kind == "position-approach":
        # axes 4 and 5 meet (a4 = 0); the tool looks along x5 from a point on that line
        joints = [(rng.choice(["revolute", "prismatic"], p=[0.8, 0.2]), ang(), u(rng), u(rng))
                  for _ in range(3)] + [("revolute", ang(), 0.0, u(rng)),
                                        ("revolute", ang(), u(rng), 0.0)]
        tool = transform(rot_y(np.pi / 2) @ rot_z(u(rng, -3, 3)), [0, 0, 0]) @ \
            transform(None, [0, 0, u(rng)])
    else:
        # axes 2, 3, 4 parallel; joint 5 rolls the tool about its own axis
        joints = [("revolute", ang(), u(rng), u(rng)), ("revolute", 0.0, u(rng), u(rng)),
                  ("revolute", 0.0, u(rng), u(rng)), ("revolute", ang(), u(rng), u(rng)),
                  ("revolute", 0.0, 0.0, u(rng))]
        tool = transform(rot_z(u(rng, -3, 3)), [0, 0, u(rng)])
    r = dh(rng, joints)
    return Robot("five", "dh", r.joints, base=r.base, tool=tool)


@pytest.mark.parametrize("kind", ["position-approach", "pitch-roll"])
def test_five_joint_arms_position_and_approach(kind):
    rng = np.random.default_rng({"position-approach": 5, "pitch-roll": 6}[kind])
    trials = hits_full = hits_approach = 0
    for _ in range(8):
        r = five_joint_robot(rng, kind)
        fam, _ = classify(r, Screws.of(r))
        assert fam is not None and fam.name == kind, fam
        L = max(1.0, r.characteristic_length)
        for q in sample_configurations(r, 30, rng):
            T = r.fk(q)
            trials += 1
            # the whole pose: the generating configuration must come back
            res = solve(r, Target(T))
            for s in res.solutions:
                assert np.allclose(r.fk(s.q), T, atol=1e-9 * L)
            hits_full += any(close(s.q, q, r, 1e-6 * L) for s in res.solutions)
            # position and approach only: every answer has them; q (but the free roll) is one
            a = T[:3, 2]
            P = T.copy()
            P[:3, :3] = np.eye(3)
            res = solve(r, Target(P, orientation=False, approach=a))
            for s in res.solutions:
                Tq = r.fk(s.q)
                assert np.linalg.norm(Tq[:3, 3] - T[:3, 3]) <= 1e-9 * L
                assert np.linalg.norm(Tq[:3, 2] - a) <= 1e-9
            n_fixed = 5 if kind == "position-approach" else 4
            hits_approach += any(np.all(np.abs(wrap(s.q[:n_fixed] - q[:n_fixed])) < 1e-6 * L)
                                 for s in res.solutions)
    assert hits_full / trials >= 0.99 and hits_approach / trials >= 0.99, \
        (hits_full, hits_approach, trials)


def test_five_joint_arm_with_an_unreachable_roll_says_so():
    rng = np.random.default_rng(9)
    r = five_joint_robot(rng, "position-approach")
    T = r.fk(sample_configurations(r, 1, rng)[0])
    from kincalc.spatial import rot_z
    T[:3, :3] = T[:3, :3] @ rot_z(0.5)           # same approach, rolled by 0.5 rad
    res = solve(r, Target(T))
    assert not res.reachable and res.solutions == []
    assert isinstance(res.reason, OrientationOut) and len(res.reason.rolls) == 2
    text = ik_document(res)["reason"]
    assert "orientation is not" in text and "controls position and approach" in text
    # The reason quotes facts of the family's own solutions: every solution that reaches the
    # position and the approach, with the roll it leaves (measured here from FK's x axes).
    # The generating branch leaves the 0.5 rad itself; the other branch another roll. (The
    # old text named one "best" solution chosen by position errors equal to rounding, so
    # the number depended on the platform: 28.65 on one machine, 13.06 on another.)
    placed = solve(r, Target(T, orientation=False, approach=T[:3, 2])).solutions
    assert len(placed) == 2
    for s in placed:
        x = r.fk(s.q)[:3, 0]
        roll = abs(np.arctan2(np.cross(x, T[:3, 0]) @ T[:3, 2], x @ T[:3, 0]))
        assert (roll, s.branch) in [(pytest.approx(a, abs=1e-9), b) for a, b in res.reason.rolls]
        assert f"{np.rad2deg(roll):.4g} deg ({s.branch})" in text
    assert "off by 13.06 deg" in text and "28.65 deg" in text


def test_the_closest_solution_of_a_reason_does_not_hang_on_rounding():
    """Two candidates that both place the tool: the reason names the one with the smaller
    orientation error, whatever the last bits of their position errors say."""
    from kincalc.ik.verdict import placing
    r = load_robot("puma560")
    q = np.zeros(6)
    a = {"q": q, "branch": "a", "position_error": 2.0e-15, "orientation_error": 0.5}
    b = {"q": q + 0.1, "branch": "b", "position_error": 2.1e-15, "orientation_error": 0.2}
    far = {"q": q + 0.2, "branch": "c", "position_error": 0.05, "orientation_error": 0.0}
    assert [p["branch"] for p in placing(r, [a, b, far])] == ["b", "a"]
    assert [p["branch"] for p in placing(r, [b, a, far])] == ["b", "a"]


def test_all_branches_says_why_a_branch_has_no_real_angle():
    """Beyond the PUMA's reach the elbow equation has no real root. Hand derivation
    (standard DH, shoulder point at the base origin, wrist centre w = target position):
    |w|^2 = a2^2 + a3^2 + d3^2 + d4^2 + 2 a2 (a3 cos q3 - d4 sin q3), i.e.
    cos(q3 + atan2(d4, a3)) = (|w|^2 - a2^2 - a3^2 - d3^2 - d4^2) / (2 a2 hypot(a3, d4))."""
    import re
    r = load_robot("puma560")
    a2, a3, d3, d4 = r.joints[1].a, r.joints[2].a, r.joints[2].d, r.joints[3].d
    w = np.array([0.85, 0.2, 0.3])
    T = np.eye(4)
    T[:3, 3] = w
    res = solve(r, Target(T), all_branches=True)
    assert not res.reachable and res.dead_ends
    d = res.dead_ends[0]                          # data, SI: the step and its equation
    value = (w @ w - a2 ** 2 - a3 ** 2 - d3 ** 2 - d4 ** 2) / (2 * a2 * np.hypot(a3, d4))
    assert d.joint == 2 and d.need == pytest.approx(value, rel=1e-9) and abs(d.need) > 1
    assert abs(wrap(d.phase + np.arctan2(d4, a3))) < 1e-9
    text = ik_document(res)["dead_ends"][0]          # worded at the edge, in degrees
    # cos(q3 - phase), the phase's sign written once: "q3 + 87.31", never "q3 - -87.31"
    m = re.search(r"cos\(q3 ([-+]) ([0-9.]+) deg\) would have to be (-?[0-9.]+)", text)
    assert m, text
    assert float(m.group(3)) == pytest.approx(value, rel=1e-3)
    phase = float(m.group(2)) * (1 if m.group(1) == "-" else -1)
    assert abs(wrap(np.radians(phase) - d.phase)) < 1e-3
    # without --all-branches nothing is collected
    assert solve(r, Target(T)).dead_ends is None


def _kuka_wrist_point(p):
    """The KR 6 R900's wrist point for a flange at ``p`` (m) pointing straight down: its
    tool is Ry(180) on DH frame 6, so z6 points up, and the flange is d6 = -0.08 along z6
    from the wrist point."""
    return np.asarray(p) + [0.0, 0.0, 0.08]


def test_all_branches_says_why_an_offset_shoulder_has_no_elbow_angle():
    """An offset shoulder (axis 1 skew to the parallel axes 2 and 3: the KUKA) records the
    elbow equation it could not meet, as the PUMA does, not 'cos(A3 - 0) would have to be
    0'. Hand derivation (the robot file's numbers, m): axis 1 is the world z axis, axis 2
    is 0.4 above the floor and 0.025 from axis 1, on the wrist point's side or on the other
    (the two shoulder slots); the elbow's triangle has sides l2 = 0.455 and hypot(0.42,
    0.035), so |q|^2 = l2^2 + l4^2 + o3^2 + 2 l2 hypot(l4, o3) cos(A3 - phase), q the wrist
    point from axis 2 in the arm's plane."""
    r = load_robot("kuka_kr6_r900")
    T = np.diag([-1.0, 1.0, -1.0, 1.0])                     # the flange pointing down
    T[:3, 3] = [0.5, 0.0, 3.0]
    res = solve(r, Target(T), all_branches=True)
    assert not res.reachable
    w = _kuka_wrist_point(T[:3, 3])
    rho, z = np.hypot(w[0], w[1]), w[2] - 0.4
    side = np.hypot(0.42, 0.035)
    expected = sorted(((rho + s * 0.025) ** 2 + z ** 2 - 0.455 ** 2 - side ** 2)
                      / (2 * 0.455 * side) for s in (-1, 1))
    needs = sorted(d.need for d in res.dead_ends if d.joint == 2)
    assert needs == pytest.approx(expected, rel=1e-9)
    assert all(abs(d.need) > 1 for d in res.dead_ends)
    texts = ik_document(res)["dead_ends"]
    assert len(texts) == 2 and not any("would have to be 0," in t for t in texts), texts


#: the KR 6 R900 (robots/kuka_kr6_r900.yaml) with a lateral offset d2 = 150 mm
KUKA_LATERAL = """name: kuka_lateral
convention: dh
units: {length: mm, angle: deg}
base: {xyz: [0, 0, 0], rpy: [180, 0, 0]}
joints:
  - {name: A1, type: revolute, alpha: 90,  a: 25,  d: -400, theta: 0}
  - {name: A2, type: revolute, alpha: 0,   a: 455, d: 150,  theta: 0}
  - {name: A3, type: revolute, alpha: 90,  a: 35,  d: 0,    theta: -90}
  - {name: A4, type: revolute, alpha: -90, a: 0,   d: -420, theta: 0}
  - {name: A5, type: revolute, alpha: 90,  a: 0,   d: 0,    theta: 0}
  - {name: A6, type: revolute, alpha: 0,   a: 0,   d: -80,  theta: 0}
tool: {xyz: [0, 0, 0], rpy: [0, 180, 0]}
"""


def test_all_branches_says_why_an_offset_shoulder_cannot_face_the_target():
    """The shoulder's first step: with a lateral offset d2 along the parallel axes, joint 1
    must turn them so that the wrist point lies d2 off its own plane, impossible within d2
    of axis 1: cos(A1 - phase) = d2 / rho, rho the wrist point's distance from axis 1."""
    from kincalc import parse_robot_text
    r = parse_robot_text(KUKA_LATERAL)
    T = np.diag([-1.0, 1.0, -1.0, 1.0])
    T[:3, 3] = [0.05, 0.0, 0.6]
    res = solve(r, Target(T), all_branches=True)
    assert not res.reachable
    w = _kuka_wrist_point(T[:3, 3])
    first = [d for d in res.dead_ends if d.joint == 0]
    assert len(first) == 1 and abs(first[0].need) == pytest.approx(0.15 / np.hypot(w[0], w[1]),
                                                                    rel=1e-9)

ARM5 = """name: arm5
title: five-joint arm with a pitch-roll wrist
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 90, a: 0.033, d: 0.147, theta: 0}
  - {name: q2, type: revolute, alpha: 0, a: 0.155, d: 0, theta: 0}
  - {name: q3, type: revolute, alpha: 0, a: 0.135, d: 0, theta: 0}
  - {name: q4, type: revolute, alpha: 90, a: 0, d: 0, theta: 0}
  - {name: q5, type: revolute, alpha: 0, a: 0, d: 0.2175, theta: 0}
"""


def test_cli_approach_target(tmp_path):
    """kincalc ik FILE --xyz ... --approach ...: every solution puts the tool point there
    with its z axis along the (normalised) approach; the roll is labelled q5:any."""
    import json
    import subprocess
    import sys
    path = tmp_path / "arm5.yaml"
    path.write_text(ARM5)
    a = np.array([0.3, 0.05, -0.2])
    out = subprocess.run([sys.executable, "-m", "kincalc", "ik", str(path), "--xyz", "0.3", "0.05",
                          "0.2", "--approach", *map(str, a), "--rad", "--json"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["method"]["family"] == "pitch-roll" and doc["count"] == 4
    assert np.allclose(doc["target"]["approach"], a / np.linalg.norm(a))
    r = load_robot(str(path))
    for s in doc["solutions"]:
        T = r.fk(np.array(s["q"]))
        assert np.allclose(T[:3, 3], [0.3, 0.05, 0.2], atol=1e-9)
        assert np.allclose(T[:3, 2], a / np.linalg.norm(a), atol=1e-9)
        assert "q5:any" in s["branch"] and not s["singular"]


def test_near_beyond_a_limit_orders_by_the_configuration():
    """near = the PUMA at q3 = 150 deg, beyond q3's limits [-225, 45]: the same
    configuration within them is q3 = -210, a change of a whole turn, and must come first
    (it came fifth, ranked as a 360-degree change)."""
    r = load_robot("puma560")
    near = np.radians([10, -30, 150, 20, 40, 30])
    res = solve(r, Target(r.fk(near)), near=near)
    assert close(res.solutions[0].q, near, r)


def test_a_continuum_total_that_rounds_to_zero_is_written_without_a_sign():
    """PUMA 560 at q5 = 0 with q4 + q6 = 0: the relation reads 'q4 + q6 = 0.0000 deg' (it
    read '-0.0000', the total a rounding below zero)."""
    r = load_robot("puma560")
    res = r.ik(r.fk(np.radians([0, 45, 180, 0, 0, 0])))
    from kincalc.analysis.results import Units
    from kincalc.analysis.words import continuum_text
    texts = [continuum_text(s.continuum, [j.name for j in r.joints], Units("deg"))
             for s in res.solutions if s.continuum is not None]
    assert texts and all(t.startswith("q4 + q6 = ") for t in texts)
    assert not any("-0.0000" in t for t in texts)


def test_a_label_s_sign_is_the_branch_the_explained_formula_calls_so():
    """The FER homework's arm (a TCV target): joint 2 from cos q2 = (t - C) / A with A < 0.
    The root labelled q2:+ is atan2(B, A) + acos(...) = -60 deg; the trace wrote "q2 =
    ±60°" beside it, as if + were +60. It now names the + branch's value."""
    import re

    from kincalc.analysis.results import ik_document
    r = load_robot("fer_rrpr")
    w = np.array([0.963019, 0.555999, -0.642013])          # --tcv 0.3 0.173205 0.3 w4 w5 w6
    T = np.eye(4)
    T[:3, 3] = [0.3, 0.173205, 0.3]
    n = np.linalg.norm(w)
    res = solve(r, Target(T, orientation=False, tcv=(w / n, np.pi * np.log(n))), explain=True)
    doc = ik_document(res)
    assert len(res.solutions) == 2
    for s, d in zip(res.solutions, doc["solutions"]):
        q2 = np.degrees(s.q[1])
        line = next(t for t in (str(x) for x in d["trace"]) if "cos q2" in t)
        plus = re.search(r"the \+ branch is (-?[0-9.]+)", line)
        assert plus, line
        assert ("q2:+" in s.branch) == (abs(q2 - float(plus.group(1))) < 1e-3), (s.branch, q2)


def test_a_tcv_target_is_shown_and_its_last_joint_explained():
    """The FER homework's --tcv: the JSON target keeps the vector and the last joint it sets
    (q4 = pi ln |w4..w6|, here ln 1.28402538 = pi/4: 45 deg), and --explain shows that step
    (the target read "no orientation given"; the trace began at q3)."""
    from kincalc.cli.main import main
    import contextlib
    import io
    import json
    argv = ["ik", "fer_rrpr", "--tcv", "0.3", "0.173205", "0.3", "0.963019", "0.555999",
            "-0.642013", "--explain", "--json"]
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(argv) == 0
    doc = json.loads(buf.getvalue())
    w = [0.3, 0.173205, 0.3, 0.963019, 0.555999, -0.642013]
    assert doc["target"]["tcv"] == pytest.approx(w, abs=1e-12)
    assert doc["target"]["roll"] == pytest.approx(180 * np.log(np.linalg.norm(w[3:])), abs=1e-9)
    for s in doc["solutions"]:
        first = s["trace"][0]
        assert first["step"] == "q4" and "pi ln|w4..w6|" in first["text"]
        assert s["q"][3] == pytest.approx(doc["target"]["roll"], abs=1e-6)


@pytest.mark.parametrize("name,xyz,rpy,kind,distance", [
    ("spong_scara", [0.3755, 0.4209, -0.3], [0, 0, 20], "orientation", 0.0),
    ("planar_3r", [1.0, 1.0, 0.5], [0, 0, 30], "out of reach", 0.5),
])
def test_no_candidate_at_the_position_says_whether_the_position_is_within_reach(
        name, xyz, rpy, kind, distance):
    """A target no candidate reaches in position: a SCARA given its tool z upside down
    (the position is reachable; the orientation moved the point on axis 4 that the family
    places), a planar arm given a point 0.5 off its plane. The answer said 'position off by
    0.2 m, orientation off by 180 deg' and 'position off by 0.5393'; now what reach says."""
    from kincalc.ik.reasons import OrientationOut, OutOfReach
    from kincalc.spatial import matrix_from_rpy, transform
    r = load_robot(name)
    T = transform(matrix_from_rpy(np.radians(rpy)), np.array(xyz, float))
    res = r.ik(T)
    assert not res.solutions and not res.reachable
    if kind == "orientation":
        assert isinstance(res.reason, OrientationOut) and res.reason.closest is None
        from kincalc.analysis.reach import reach
        assert reach(r, Target(T)).verdict == "orientation-unreachable"
    else:
        assert isinstance(res.reason, OutOfReach)
        assert res.reason.outside.distance == pytest.approx(distance, rel=1e-6)


def test_a_tcv_target_labels_a_solution_as_its_whole_pose_does():
    """The FER homework's arm: the same two solutions from --tcv and from their whole pose
    carry the same labels (the TCV's lacked the shoulder word: 'q2:- q3:root 2' against
    'shoulder front q2:- q3:root 2')."""
    r = load_robot("fer_rrpr")
    q = np.array([np.radians(30), np.radians(60), 0.3, np.radians(45)])
    T = r.fk(q)
    w = T[:3, 2] * np.exp(q[3] / np.pi)
    by_tcv = solve(r, Target(T, orientation=False, tcv=(T[:3, 2], q[3])))
    by_pose = r.ik(T)
    # (the pose's other solution turns q4 by 180 deg where the TCV's keeps q4: joints 1-3,
    # which the labels name, are the same)
    labels = lambda res: sorted((tuple(np.round(s.q[:3], 6)), s.branch)  # noqa: E731
                                for s in res.solutions)
    assert len(by_tcv.solutions) == 2 and labels(by_tcv) == labels(by_pose)
    assert all("shoulder" in s.branch for s in by_tcv.solutions)
    assert np.allclose(np.linalg.norm(w), np.exp(q[3] / np.pi))


@pytest.mark.parametrize("tilt", [0.3, 1e-3, 3.4e-6, -2e-5])
def test_a_wrist_of_three_joints_with_axes_1_and_2_nearly_one_line(tilt, tmp_path):
    """Three revolute axes through one point (an orientation-only arm), axes 1 and 2 a hair
    apart (a URDF's rpy rounded to 1.570796): the pair's meeting point was sought by a
    least-squares intersection that calls lines within 1.4e-3 rad of parallel "no unique
    point", so the pair was not solved (subproblem 2) and no pose by FK had a solution."""
    path = tmp_path / "wrist3.urdf"
    path.write_text(
        '<robot name="w3"><link name="b"/><link name="l1"/><link name="l2"/><link name="l3"/>'
        '<joint name="j1" type="revolute"><parent link="b"/><child link="l1"/>'
        '<origin xyz="0.1 -0.2 0.5"/><axis xyz="0 0 1"/><limit lower="-3" upper="3"/></joint>'
        '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>'
        f'<axis xyz="0 {float(np.sin(tilt))!r} {float(np.cos(tilt))!r}"/>'
        '<limit lower="-3" upper="3"/></joint>'
        '<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>'
        '<axis xyz="1 0 0"/><limit lower="-3" upper="3"/></joint></robot>')
    r = load_robot(str(path))
    for q in sample_configurations(r, 40, np.random.default_rng(8)):
        T = r.fk(q)
        res = solve(r, Target(T))
        assert any(close(s.q, q, r, tol=1e-5) for s in res.solutions), q
        for s in res.solutions:                 # every one reaches the pose, by FK
            assert np.allclose(r.fk(s.q), T, atol=1e-9)
