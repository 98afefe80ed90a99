"""kincalc.analysis.compare.match against constructed truths.

Candidates with known offsets and sign changes are built here, without the
engine's screw code: from the reference's joint axes and points at q = 0
(``to_poe``), by moving every later axis with the motion that the offsets
(and the sign change of the joint) make (a rotation about / translation along
the joint's own axis), and checking by forward kinematics that
``FK_candidate(signs * q + offsets) == FK_reference(q)`` before the engine
sees them. Offsets are drawn uniformly (never multiples of 90 degrees).
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import pytest

from randrobots import random_pose, random_robot

from kincalc.conventions import dh_to_mdh, mdh_to_dh, to_poe
from kincalc.analysis.compare import describe, match
from kincalc.conventions.library import load
from kincalc.model import Joint, Robot
from kincalc.analysis.results import Units
from kincalc.conventions.reader import parse_robot_text
from kincalc.spatial import matrix_from_axis_angle, transform


def moved(robot, signs, offsets, name="candidate"):
    """A poe robot C with ``FK_C(signs * q + offsets) == FK_robot(q)`` for all q.

    FK_C(q') = FK_robot(s (q' - c)) = base * prod_i exp(s_i S_i (q'_i - c_i)) * M,
    whose zero configuration is that of the reference at q = -s*c: joint i's axis
    there is axis i moved by H_{i-1} = prod_{j<i} exp(-s_j S_j c_j), and its
    direction is multiplied by s_i; the tool is H_n * M.
    """
    poe = to_poe(robot)
    H = np.eye(4)
    joints = []
    for j, s, c in zip(poe.joints, signs, offsets):
        axis, point = np.array(j.axis), np.array(j.point)
        R, p = H[:3, :3], H[:3, 3]
        joints.append(Joint(j.name, j.type, axis=tuple(s * (R @ axis)),
                            point=tuple(R @ point + p), limits=None))
        if j.revolute:   # rotate about the reference's axis i by -s*c ...
            E = transform(matrix_from_axis_angle(axis, -s * c))
            E[:3, 3] = point - E[:3, :3] @ point
        else:            # ... or translate along it by -s*c
            E = transform(None, -s * c * axis)
        H = H @ E
    cand = Robot(name=name, convention="poe", joints=tuple(joints), base=robot.base,
                 M=H @ poe.M)
    q = _random_q(robot, np.random.default_rng(99), 20)
    assert np.allclose(cand.fk(q * signs + offsets), robot.fk(q), atol=1e-9), \
        "the test's own construction is wrong"
    return cand


def _random_q(robot, rng, count):
    return np.where(robot.is_revolute, rng.uniform(-np.pi, np.pi, (count, robot.dof)),
                    rng.uniform(-0.5, 0.5, (count, robot.dof)))


def _random_change(robot, rng):
    n = robot.dof
    signs = rng.choice([-1, 1], n)
    offsets = np.where(robot.is_revolute, rng.uniform(-np.pi, np.pi, n),
                       rng.uniform(-0.3, 0.3, n) * robot.characteristic_length)
    return signs, offsets


def _with_joint(robot, k, **changes):
    js = list(robot.joints)
    js[k] = dataclasses.replace(js[k], **changes)
    return dataclasses.replace(robot, joints=tuple(js))


# --- conversions: the same robot, no offsets needed -------------------------------

@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_converted_random_robots_are_the_same(convention):
    rng = np.random.default_rng(11)
    for _ in range(25):
        r = random_robot(rng, convention, n=int(rng.integers(1, 8)))
        others = [to_poe(r)]
        if convention == "dh":
            others += [dh_to_mdh(r), mdh_to_dh(dh_to_mdh(r))]
        elif convention == "mdh":
            others += [mdh_to_dh(r), dh_to_mdh(mdh_to_dh(r))]
        for other in others:
            m = match(r, other)
            assert m.same, m.reason
            assert m.kind == "same" and m.first_bad_joint is None
            assert np.array_equal(m.signs, np.ones(r.dof))
            assert np.array_equal(m.offsets, np.zeros(r.dof))
            assert m.position_error < 1e-12 and m.orientation_error < 1e-12


# --- offsets and signs ----------------------------------------------------------

def test_recovers_random_offsets_and_signs():
    # generic random robots (1-7 joints, revolute and prismatic): the offsets and
    # signs that make them agree are unique, so they must be the ones applied
    rng = np.random.default_rng(1)
    for trial in range(120):
        r = random_robot(rng, ["dh", "mdh", "poe"][trial % 3], n=int(rng.integers(1, 8)))
        signs, offsets = _random_change(r, rng)
        cand = moved(r, signs, offsets)
        m = match(r, cand, allow_offsets=True)
        assert m.same, (trial, m.reason)
        assert np.array_equal(m.signs, signs), trial
        assert np.allclose(m.offsets, offsets, atol=1e-8), (trial, m.offsets, offsets)
        assert m.position_error <= 1e-6 * m.length_scale and m.orientation_error <= 1e-6
        # the same candidate is a different robot when offsets are not allowed
        strict = match(r, cand)
        assert not strict.same and strict.hint_offsets
        assert "with joint offsets and sign changes allowed they are the same robot" \
            in strict.reason


@pytest.mark.parametrize("name", ["adept_cobra600", "bk_scara_euler", "planar_3r", "bk_rr",
                                  "bk_rrp", "bk_rpr", "ur5", "fer_rrpr"])
def test_recovers_offsets_on_degenerate_robots(name):
    # parallel axes (planar arms), a prismatic joint along a revolute axis (SCARA),
    # intersecting axes. With all signs +1 the answer is unique even for the
    # SCARA's Euler wrist (its other solution flips joint 5's sign).
    r = load(name)
    rng = np.random.default_rng(sum(map(ord, name)))
    for _ in range(4):
        _, offsets = _random_change(r, rng)
        m = match(r, moved(r, np.ones(r.dof, int), offsets), allow_offsets=True)
        assert m.same, m.reason
        assert np.array_equal(m.signs, np.ones(r.dof))
        assert np.allclose(m.offsets, offsets, atol=1e-8), (m.offsets, offsets)


def test_wrist_flip_prefers_fewer_sign_changes():
    # PUMA wrist: offsets (c4, c5, c6) with signs (-1, -1, -1) on joints 4-6 is the
    # same robot as (c4 + 180, -c5, c6 + 180) with only joints 4 and 6 flipped...
    # whichever is found, it must be a valid one with no more sign changes
    r = load("puma560")
    signs = np.array([1, 1, 1, -1, -1, -1])
    offsets = np.radians([10, 20, 30, 40, 50, 60])
    m = match(r, moved(r, signs, offsets), allow_offsets=True)
    assert m.same
    assert np.sum(m.signs < 0) <= 3
    q = _random_q(r, np.random.default_rng(5), 50)
    assert np.allclose(moved(r, signs, offsets).fk(q * m.signs + m.offsets), r.fk(q), atol=1e-9)


def test_coaxial_joints_only_fix_the_sum():
    # joints 1 and 2 share an axis: any split of the total offset is right
    r = Robot("coax", "dh", (Joint("q1", "revolute", d=0.1),
                             Joint("q2", "revolute", d=0.2, a=0.3, alpha=1.0),
                             Joint("q3", "revolute", a=0.2)))
    offsets = np.array([0.4, 0.7, -0.3])
    m = match(r, moved(r, np.ones(3, int), offsets), allow_offsets=True)
    assert m.same
    # the split, and the sum up to whole turns
    assert math.isclose(math.remainder(m.offsets[0] + m.offsets[1] - 1.1, 2 * math.pi), 0.0,
                        abs_tol=1e-8)
    assert math.isclose(m.offsets[2], -0.3, abs_tol=1e-8)


# --- hand-written cases ---------------------------------------------------------------

def test_planar_rr_in_standard_dh_is_bk_rr():
    # bk_rr is modified DH with the second link in the tool (Tx(l2)); the same arm
    # in standard DH is the two rows (theta_i, d = 0, a = l_i, alpha = 0)
    dh = parse_robot_text("""
name: rr
convention: dh
units: {length: unitless, angle: deg}
joints:
  - {name: t1, type: revolute, alpha: 0, a: 10, d: 0, theta: 0}
  - {name: t2, type: revolute, alpha: 0, a: 5, d: 0, theta: 0}
""")
    assert match(load("bk_rr"), dh).same
    wrong = _with_joint(dh, 1, a=6.0)
    m = match(load("bk_rr"), wrong, allow_offsets=True)
    assert not m.same and m.first_bad_joint == 3 and m.kind == "tool"
    assert math.isclose(m.miss_distance, 1.0, rel_tol=1e-9)


def test_hand_written_scara_in_poe_is_the_cobra():
    # The Adept Cobra s600 (standard DH, mm) read off its DH table by hand:
    # joints 1 and 2 turn about +z through (0, 0, 0) and (325, 0, 387) (row 1:
    # d1 = 387, a1 = 325); row 2 (a2 = 275, alpha2 = 180) puts frame 2 at
    # (600, 0, 387) with z pointing down, so joint 3 slides along -z and joint 4
    # turns about -z there; the tool (frame 4 at q = 0) sits at (600, 0, 387),
    # turned 180 deg about x.
    poe = parse_robot_text("""
name: cobra_by_hand
convention: poe
units: {length: mm, angle: deg}
joints:
  - {name: J1, type: revolute, axis: [0, 0, 1], point: [0, 0, 0]}
  - {name: J2, type: revolute, axis: [0, 0, 1], point: [325, 0, 387]}
  - {name: J3, type: prismatic, axis: [0, 0, -1], point: [600, 0, 387]}
  - {name: J4, type: revolute, axis: [0, 0, -1], point: [600, 0, 387]}
tool: {xyz: [600, 0, 387], rpy: [180, 0, 0]}
""")
    cobra = load("adept_cobra600")
    assert match(cobra, poe).same
    # a quill turning the other way, and its zero 30 deg off: found
    flipped = _with_joint(poe, 3, axis=(0.0, 0.0, 1.0))
    assert not match(cobra, flipped).same
    m = match(cobra, flipped, allow_offsets=True)
    assert m.same and list(m.signs) == [1, 1, 1, -1]


@pytest.mark.parametrize("convention", ["dh", "mdh"])
@pytest.mark.parametrize("field", ["a", "d"])
def test_perturbed_row_names_the_first_joint_whose_axis_moves(convention, field):
    # Standard DH: row k is A_k = Rz(theta_k) Tz(d_k) Tx(a_k) Rx(alpha_k); it places
    # frame k, whose z axis is joint k+1's axis. A wrong a_k or d_k moves joint k+1's
    # axis (d_k slides frame k along joint k's own axis, which moves the next axis
    # unless it is parallel; the random twists make it generic) and leaves joints
    # 1..k alone: the first bad joint is k+1 (the tool, n+1, for the last row).
    # Modified DH: row k is Rx(alpha_{k-1}) Tx(a_{k-1}) Rz(theta_k) Tz(d_k) and frame k
    # is on joint k's axis: a wrong a_{k-1} moves joint k's axis itself (first bad
    # joint k), a wrong d_k slides frame k along that axis and moves joint k+1's.
    # Joint offsets cannot undo either (an offset turns about an axis; it does not
    # change the distance between axes), so allow_offsets gives the same answer.
    rng = np.random.default_rng(21 + len(convention) + len(field))
    for _ in range(15):
        r = random_robot(rng, convention, n=6, types=["revolute"] * 6)
        k = int(rng.integers(0, 6))
        bad = _with_joint(r, k, **{field: getattr(r.joints[k], field) + 0.05})
        expected = k + 1 if (convention == "mdh" and field == "a") else k + 2
        for allow in (False, True):
            m = match(r, bad, allow_offsets=allow)
            assert not m.same
            assert m.first_bad_joint == expected, (k, allow, m.reason)
            assert m.kind == ("tool" if expected == 7 else "axis")
            assert m.miss_distance > 1e-4 or m.miss_angle > 1e-4


def test_changed_tool_is_joint_n_plus_1_and_free_tool_accepts_it():
    r = load("puma560")
    change = transform(matrix_from_axis_angle([0, 1, 0], 0.3), [0.01, 0.02, 0.05])
    cand = dataclasses.replace(to_poe(r), tool=to_poe(r).tool @ change)
    m = match(r, cand)
    assert not m.same and m.first_bad_joint == 7 and m.kind == "tool"
    assert "the tool frames at the matched zero" in m.reason
    m = match(r, cand, free_tool=True)
    assert m.same and m.base is None
    assert np.allclose(m.tool, change, atol=1e-9)


def test_free_base_and_tool_find_the_frames():
    rng = np.random.default_rng(3)
    for trial in range(30):
        r = random_robot(rng, ["dh", "mdh", "poe"][trial % 3], n=int(rng.integers(1, 7)))
        signs, offsets = _random_change(r, rng)
        cand = moved(r, signs, offsets)
        B, T = random_pose(rng), random_pose(rng)
        cand = dataclasses.replace(cand, base=B @ cand.base, tool=cand.tool @ T)
        assert not match(r, cand, allow_offsets=True).same
        m = match(r, cand, allow_offsets=True, free_base=True, free_tool=True)
        assert m.same, (trial, m.reason)
        q = _random_q(r, rng, 30)
        assert np.allclose(cand.fk(q * m.signs + m.offsets), m.base @ r.fk(q) @ m.tool,
                           atol=1e-8)
        assert m.offsets[0] == 0 and m.offsets[-1] == 0   # absorbed by base and tool


def test_free_base_alone():
    r = load("ur5")
    B = random_pose(np.random.default_rng(8))
    cand = dataclasses.replace(r, base=B @ r.base)
    assert not match(r, cand).same
    m = match(r, cand, free_base=True)
    assert m.same and m.tool is None
    assert np.allclose(m.base, B, atol=1e-9)


def test_joint_types_and_counts_differ():
    m = match(load("puma560"), load("stanford_arm"))
    assert not m.same and m.kind == "type" and m.first_bad_joint == 3
    assert m.reason == "joint 3 (q3) is prismatic in the candidate, revolute in the reference"
    # the differences at equal joint values (finite: they go into JSON)
    assert math.isfinite(m.position_error) and m.worst_q.shape == (6,)
    m = match(load("puma560"), load("adept_cobra600"), allow_offsets=True)
    assert not m.same and m.kind == "dof" and m.first_bad_joint is None
    assert m.reason == "the reference has 6 joints, the candidate 4"
    assert math.isnan(m.position_error) and m.worst_q.shape == (0,)


def test_tiny_differences_are_found():
    # 1e-4 of the arm's size is far above the tolerance (1e-6): different
    r = load("puma560")
    bad = _with_joint(r, 2, a=r.joints[2].a + 1e-4)
    m = match(r, bad)
    assert not m.same and m.first_bad_joint == 4
    assert 0.5e-4 < m.position_error < 1e-3
    # and at 1e-9 they count as the same
    assert match(r, _with_joint(r, 2, a=r.joints[2].a + 1e-9)).same


def test_reported_errors_come_from_fk_at_worst_q():
    r = load("puma560")
    bad = _with_joint(r, 4, alpha=r.joints[4].alpha + 0.01)
    m = match(r, bad, samples=50, seed=4)
    assert not m.same
    dp = np.linalg.norm(bad.fk(m.worst_q)[:3, 3] - r.fk(m.worst_q)[:3, 3])
    assert math.isclose(dp, m.position_error, rel_tol=1e-9)
    # the same seed gives the same answer
    again = match(r, bad, samples=50, seed=4)
    assert np.array_equal(again.worst_q, m.worst_q)


def test_describe_words_offsets_in_user_units():
    r = load("bk_rr")
    cand = moved(r, np.array([1, -1]), np.radians([-90.0, 12.5]))
    m = match(r, cand, allow_offsets=True)
    lines = describe(m, r, Units("deg", "unitless"))
    assert lines[0] == "same robot up to joint offsets and signs (joints 1 and 2)"
    assert lines[1] == "joint 1 (theta1): candidate zero is at reference theta1 = 90 deg"
    assert lines[2] == ("joint 2 (theta2): opposite sign, candidate zero is at "
                        "reference theta2 = 12.5 deg")
    rad = describe(m, r, Units("rad", "unitless"))
    assert rad[1].endswith(f"theta1 = {math.pi / 2:.4g} rad")


def test_bad_arguments():
    r = load("bk_rr")
    with pytest.raises(ValueError):
        match(r, r, samples=0)
    with pytest.raises(ValueError):
        match(r, r, tol=0)


def test_six_joint_comparison_is_fast():
    # a regression guard, generous against slow machines (typically 5-25 ms)
    r = load("puma560")
    cand = moved(r, np.array([1, -1, 1, 1, -1, 1]), np.radians([13, -71, 100, 5, 33, -140]))
    times = []
    for _ in range(3):
        t = time.perf_counter()
        assert match(r, cand, allow_offsets=True).same
        times.append(time.perf_counter() - t)
    assert sorted(times)[1] < 0.5
