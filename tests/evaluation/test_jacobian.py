"""Jacobians: finite differences through the SE(3) log, twists, adjoint relations,
analytic Jacobians, and named singularities."""

import zlib

import numpy as np
import pytest
from randrobots import random_robot

from kincalc import jacobian_report, load_robot
from kincalc.jacobian import analytic_jacobian
from kincalc.conventions.library import bundled_names
from kincalc.spatial import (adjoint, euler_xyz_from_matrix, euler_zyz_from_matrix,
                             invert_transform, log_transform, rpy_from_matrix, skew)

H = 1e-6


def fd_jacobian(robot, q, h=H):
    """Central differences of FK mapped through the SE(3) log.

    For each joint, the small displacement T(q) -> T(q + h e_i) is taken as
    the world-frame twist of the tool, log(T(q+h) T(q)^-1), converted to the
    velocity of the tool point (v + w x p ... via the point-velocity formula).
    """
    T0 = robot.fk(q)
    p = T0[:3, 3]
    J = np.zeros((6, robot.dof))
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = h
        tw_plus = log_transform(robot.fk(q + dq) @ invert_transform(T0))
        tw_minus = log_transform(robot.fk(q - dq) @ invert_transform(T0))
        tw = (tw_plus - tw_minus) / (2 * h)    # spatial twist (v_origin, w)
        v, w = tw[:3], tw[3:]
        J[:3, i] = v + np.cross(w, p)          # velocity of the tool point
        J[3:, i] = w
    return J


def robots_to_check():
    return bundled_names()


@pytest.mark.parametrize("name", robots_to_check())
def test_jacobian_matches_finite_differences_for_every_bundled_robot(name):
    r = load_robot(name)
    rng = np.random.default_rng(zlib.crc32(name.encode()))   # stable across runs
    lo, hi = r.limits.T
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    scale = np.where(r.is_revolute, 1.0, r.characteristic_length)
    for _ in range(10):
        q = rng.uniform(lo, hi)
        J = r.jacobian(q)
        Jfd = fd_jacobian(r, q, h=H)
        tol = 1e-5 * max(1.0, r.characteristic_length)
        assert np.allclose(J, Jfd, atol=tol), (name, np.abs(J - Jfd).max())
        # J q-dot equals the twist of moving along q-dot
        qd = rng.normal(size=r.dof) * scale
        Tp = r.fk(q + H * qd)
        Tm = r.fk(q - H * qd)
        T0 = r.fk(q)
        tw = (log_transform(Tp @ invert_transform(T0)) - log_transform(Tm @ invert_transform(T0))) / (2 * H)
        v_point = tw[:3] + np.cross(tw[3:], T0[:3, 3])
        assert np.allclose(J @ qd, np.r_[v_point, tw[3:]], atol=tol * np.abs(qd).sum())


@pytest.mark.parametrize("name", robots_to_check())
def test_base_and_tool_jacobians_related_by_adjoint(name):
    r = load_robot(name)
    rng = np.random.default_rng(11)
    q = rng.uniform(-1, 1, (20, r.dof))
    Jb = r.jacobian(q, "base")
    Jt = r.jacobian(q, "tool")
    T = r.fk(q)
    R = T[:, :3, :3]
    # 1) same velocities, rotated: J_tool = diag(R^T, R^T) J_base
    Rt = np.swapaxes(R, 1, 2)
    assert np.allclose(Jt[:, :3], Rt @ Jb[:, :3], atol=1e-12)
    assert np.allclose(Jt[:, 3:], Rt @ Jb[:, 3:], atol=1e-12)
    # 2) body Jacobian = Ad(T^-1) space Jacobian, with J_space = [[I, [p]x], [0, I]] J_base
    S = np.tile(np.eye(6), (20, 1, 1))
    S[:, :3, 3:] = skew(T[:, :3, 3])
    J_space = S @ Jb
    assert np.allclose(adjoint(invert_transform(T)) @ J_space, Jt, atol=1e-12)


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_random_robot_jacobians(convention):
    rng = np.random.default_rng(21)
    for _ in range(10):
        r = random_robot(rng, convention, n=int(rng.integers(2, 8)))
        q = rng.uniform(-2, 2, r.dof)
        assert np.allclose(r.jacobian(q), fd_jacobian(r, q), atol=1e-6)


@pytest.mark.parametrize("shape", [(), (1,), (2, 3)])
def test_batched_jacobian_equals_single(shape):
    r = load_robot("puma560")
    q = np.random.default_rng(2).uniform(-3, 3, shape + (6,))
    J = r.jacobian(q)
    assert J.shape == shape + (6, 6)
    ref = np.array([r.jacobian(x) for x in q.reshape(-1, 6)])
    assert np.allclose(J.reshape(-1, 6, 6), ref, atol=0)


@pytest.mark.parametrize("kind,extract", [("rpy", rpy_from_matrix), ("zyz", euler_zyz_from_matrix),
                                          ("xyz", euler_xyz_from_matrix)])
def test_analytic_jacobian_matches_angle_finite_differences(kind, extract):
    r = load_robot("puma560")
    q = np.array([0.3, -0.5, 0.9, 0.4, 0.7, -0.2])
    T = r.fk(q)
    JA = analytic_jacobian(r.jacobian(q), extract(T[:3, :3]), kind)
    for i in range(6):
        dq = np.zeros(6)
        dq[i] = H
        d_ang = (extract(r.fk(q + dq)[:3, :3]) - extract(r.fk(q - dq)[:3, :3])) / (2 * H)
        d_pos = (r.fk(q + dq)[:3, 3] - r.fk(q - dq)[:3, 3]) / (2 * H)
        assert np.allclose(JA[:3, i], d_pos, atol=1e-7)
        assert np.allclose(JA[3:, i], d_ang, atol=1e-6)


def test_analytic_jacobian_reports_gimbal_lock():
    r = load_robot("puma560")
    # q = 0 puts the PUMA's tool frame aligned with the base: zyz has b = 0
    res = jacobian_report(r, np.zeros(6), analytic="zyz")
    assert res.analytic == ("zyz", None) and "gimbal" in res.analytic_error
    assert res.to_dict()["analytic"]["angles"] == "zyz"


@pytest.mark.parametrize("kind,angles", [("rpy", [0.3, np.pi / 2, -0.2]),
                                         ("xyz", [0.3, np.pi / 2, -0.2]),
                                         ("zyz", [0.3, 0.0, -0.2])])
def test_analytic_jacobian_refuses_gimbal_lock_in_every_set(kind, angles):
    """At pitch = 90 deg (rpy, xyz) E(phi) is singular only to rounding: solving it gave
    rates of ~1e16 with no error; now the function itself refuses, as documented."""
    J = np.arange(36.0).reshape(6, 6).tolist()           # a nested list is taken too
    with pytest.raises(np.linalg.LinAlgError, match="gimbal lock"):
        analytic_jacobian(J, angles, kind)
    ok = analytic_jacobian(J, np.array(angles) + [0, 0.1, 0], kind)
    assert np.isfinite(ok).all() and np.abs(ok).max() < 1e3


def test_planar_rr_manipulability_is_yoshikawas_l1_l2_sin_theta2():
    # Yoshikawa (1985): w = l1 l2 |sin theta2| for the planar 2R arm; 0 when stretched/folded
    r = load_robot("bk_rr")
    for t2 in (0.0, 0.3, 1.2, np.pi / 2, 2.5, np.pi):
        res = jacobian_report(r, np.array([0.4, t2]))
        d = res.to_dict()
        assert np.isclose(d["position_manipulability"], 10 * 5 * abs(np.sin(t2)), atol=1e-9)
        assert res.singular == (abs(np.sin(t2)) < 1e-9)
        if res.singular:
            assert "position" in res.singularity.kinds


# --- singularities named from the geometry ----------------------------------

def test_puma_wrist_singularity():
    res = jacobian_report(load_robot("puma560"), np.array([0.2, 0.5, 2.5, 0.3, 0.0, 0.1]))
    assert res.singular and "wrist" in res.singularity.kinds
    ns = res.singularity.null_space
    assert abs(abs(ns[3]) - abs(ns[5])) < 1e-9 and abs(ns[3]) > 0.5


def test_non_singular_configuration():
    res = jacobian_report(load_robot("puma560"), np.array([0.2, 0.5, 2.5, 0.3, 0.8, 0.1]))
    assert not res.singular and res.rank == 6 and res.to_dict()["condition"] is not None
    d = res.to_dict()
    assert d["manipulability"] > 0
    assert np.isclose(d["manipulability"], np.sqrt(np.linalg.det(np.array(d["J"]) @ np.array(d["J"]).T)))


ELBOW_ARM = """
name: test_elbow
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 90, a: 0, d: 0.4, theta: 0}
  - {name: q2, type: revolute, alpha: 0, a: 0.5, d: 0, theta: 0}
  - {name: q3, type: revolute, alpha: 90, a: 0, d: 0, theta: 90}
  - {name: q4, type: revolute, alpha: -90, a: 0, d: 0.4, theta: 0}
  - {name: q5, type: revolute, alpha: 90, a: 0, d: 0, theta: 0}
  - {name: q6, type: revolute, alpha: 0, a: 0, d: 0.1, theta: 0}
"""


def test_elbow_and_shoulder_singularities_named():
    from kincalc import parse_robot_text
    r = parse_robot_text(ELBOW_ARM)
    D = np.deg2rad
    # q3 = 0 with theta offset 90: forearm along the upper arm -> stretched
    res = jacobian_report(r, D(np.array([10, 20, 0, 30, 40, 0])))
    assert "elbow-stretched" in res.singularity.kinds
    res = jacobian_report(r, D(np.array([10, 20, 180, 30, 40, 0])))
    assert "elbow-folded" in res.singularity.kinds
    # wrist centre on axis 1: its distance from the axis is 0.5 cos q2 + 0.4 cos(q2 + q3)
    # (the forearm makes the angle q3 with the upper arm); with q2 = 60: cos(60 + q3) = -0.625
    q3 = np.rad2deg(np.arccos(-0.625)) - 60
    q = D(np.array([10, 60, q3, 30, 40, 0]))
    A = r.link_transforms(q)
    wc = (A[0] @ A[1] @ A[2] @ A[3])[:3, 3]
    assert np.hypot(wc[0], wc[1]) < 1e-12          # the hand computation is right
    res = jacobian_report(r, q)
    assert "shoulder" in res.singularity.kinds
    res = jacobian_report(r, D(np.array([10, 35, -50, 30, 40, 0])))
    assert not res.singular


def test_ur_wrist_singularity_names_the_parallel_joints():
    """A UR5 at q5 = 0: axis 6 is parallel to axes 2-4 but not on axis 4's line, so the
    sum of all four joints is what the orientation fixes (not q4 + q6 alone)."""
    r = load_robot("ur5")
    res = jacobian_report(r, np.radians([20, -70, 80, -30, 0, 40]))
    assert res.singular and "wrist" in res.singularity.kinds
    text = " ".join(res.singularity.descriptions)
    assert "parallel to those of joints 2, 3, 4" in text and "q2, q3, q4, q6" in text
    assert "only q4 + q6" not in text


def test_position_singularities_name_the_arm_at_hand():
    """The direction the tool point cannot move in is a left null vector of the linear
    Jacobian (checked with J from robot.jacobian); a planar arm is told it is stretched or
    folded, a spatial arm with its tool point on axis 1 that it is a shoulder singularity,
    and a spatial arm is never told it is planar."""
    import re

    from kincalc import jacobian_report, load_robot
    for name, q, words in (("bk_rr", [0, 0], "the planar arm is stretched or folded"),
                           ("bk_rr", [0, np.pi], "the planar arm is stretched or folded"),
                           ("fer_rrpr", [0, 0, 0.5, 0], "on the axis of joint 1")):
        r = load_robot(name)
        rep = jacobian_report(r, np.array(q, float))
        text = "; ".join(rep.singularity.descriptions)
        assert words in text, text
        if name == "fer_rrpr":
            assert "planar" not in text
        d = np.array([float(x) for x in re.search(r"along \(([^)]*)\)", text)[1].split(",")])
        Jv = r.jacobian(np.array(q, float))[:3]
        assert np.isclose(np.linalg.norm(d), 1, atol=2e-3)
        assert np.abs(d @ Jv).max() < 2e-3 * np.abs(Jv).max()


@pytest.mark.parametrize("name", ["puma560", "ur5", "kuka_kr16", "stanford_arm"])
def test_the_determinant_screen_decides_as_the_svd_rank(name):
    """``rank_deficient`` takes the SVD only where the determinant does not prove full rank;
    its verdict is the SVD rank test's (``scaled_ranks``) at random configurations and at
    configurations 1e-9 to 1e-3 rad from the wrist singularity, on both sides of the
    tolerance (SINGULAR_TOL of the largest singular value)."""
    from kincalc.fk import entry_frames
    from kincalc.ik.selftest import sample_configurations
    from kincalc.jacobian import rank_deficient, scaled_ranks
    r = load_robot(name)
    rng = np.random.default_rng(17)
    Q = sample_configurations(r, 400, rng)
    Q[200:, 4] = rng.choice([-1.0, 1.0], 200) * 10.0 ** rng.uniform(-9, -3, 200)
    got = rank_deficient(entry_frames(r.chain, Q), r.is_revolute, r.characteristic_length,
                         r.generic_ranks)
    rank, prank = scaled_ranks(r.jacobian(Q), r.is_revolute, r.characteristic_length)
    want = (rank < r.generic_ranks[0]) | (prank < r.generic_ranks[1])
    assert (got == want).all()
    assert 0 < want.sum() < 200                 # both verdicts near the singularity
    some = rng.choice(400, 50, replace=False)   # and a subset of the frames' columns
    assert (rank_deficient(entry_frames(r.chain, Q), r.is_revolute, r.characteristic_length,
                           r.generic_ranks, some) == want[some]).all()


def test_abs_det6_is_the_lu_determinant_in_every_case():
    """The closed-form Schur determinant against LAPACK's (numpy.linalg.det): random
    matrices, nearly singular ones, ones whose top-left block is singular or nearly so, and
    scales from 1e-3 to 1e3; absolute error against |J|_F^6 (the singular test's unit)."""
    from kincalc.jacobian import SCHUR_FROM, abs_det6
    rng = np.random.default_rng(23)
    m = 4 * SCHUR_FROM
    J = rng.normal(size=(m, 6, 6)) * 10.0 ** rng.uniform(-3, 3, (m, 1, 1))
    J[0::4, :, 5] = 0.5 * J[0::4, :, 4] + 1e-9 * J[0::4, :, 3]       # nearly singular
    J[1::4, :3, :3] *= 1e-4                                          # a poor block A
    J[2::4, :3, 2] = J[2::4, :3, 1]                                  # a singular block A
    fro = np.sqrt((J * J).sum((1, 2)))
    for batch in (J, J[:3]):                                         # closed forms, LAPACK
        got = abs_det6(np.ascontiguousarray(batch.transpose(1, 2, 0)))
        want = np.abs(np.linalg.det(batch))
        assert (np.abs(got - want) <= 1e-14 * fro[:len(batch)] ** 6).all()


@pytest.mark.parametrize("offset, wrist", [(0.0, True), (1e-7, True), (2e-5, True),
                                           (1e-2, False)])
def test_a_spherical_wrist_is_one_thing_for_ik_and_the_singularity_report(offset, wrist):
    """The singularity report's wrist (``structure.spherical_wrist``) and the IK's family
    agree on a wrist whose axes miss one point by ``offset`` (m, a5 of the arm above): a
    rounded datasheet's wrist is (nearly) spherical for both, a 1 cm offset for neither.
    (The report once took 1e-6 of the arm's size and the families 1e-4.)"""
    from kincalc import parse_robot_text
    from kincalc.ik.families import plan
    from kincalc.structure import spherical_wrist
    text = ELBOW_ARM.replace("{name: q5, type: revolute, alpha: 90, a: 0,",
                             f"{{name: q5, type: revolute, alpha: 90, a: {offset!r},")
    r = parse_robot_text(text)
    assert r.joints[4].a == offset
    assert (plan(r)[1].name == "spherical-wrist") is wrist
    assert (spherical_wrist(r) is not None) is wrist


# --- measures of a robot with fewer motions than joints ------------------------------------

ONE_JOINT = """
name: one_joint
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 0, a: 0, d: 0.3, theta: 0}
"""

WRIST_ONLY = """
name: wrist_only
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q4, type: revolute, alpha: -90, a: 0, d: 0, theta: 0}
  - {name: q5, type: revolute, alpha: 90, a: 0, d: 0, theta: 0}
  - {name: q6, type: revolute, alpha: 0, a: 0, d: 0, theta: 0}
"""

COAXIAL = """
name: coaxial
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 90, a: 1, d: 0, theta: 0}
  - {name: q2, type: revolute, alpha: 0, a: 0, d: 0, theta: 0}
  - {name: q3, type: revolute, alpha: 0, a: 1, d: 0, theta: 0}
"""


@pytest.mark.parametrize("text, q", [(ONE_JOINT, [0.5]), (WRIST_ONLY, [0.2, 0.9, 0.3])])
def test_a_tool_point_no_joint_moves_has_position_manipulability_zero(text, q):
    """The tool on the only axis, or at a wrist's centre: the linear rows are zero, and so is
    the measure (it was 1.0, the product of no singular values)."""
    from kincalc import parse_robot_text
    res = jacobian_report(parse_robot_text(text), np.array(q))
    assert np.abs(res.J[:3]).max() < 1e-15
    assert res.to_dict()["position_manipulability"] == 0.0


def test_the_condition_of_a_robot_with_two_joints_on_one_line_is_over_its_generic_rank():
    """Joints 2 and 3 on one line: two motions at every configuration, the third singular
    value a rounding zero. The condition number is the largest over the second of the
    length-normalised Jacobian (it was that over the rounding zero, 1e15..1e17, changing
    with q and the unit), and the same in metres and millimetres."""
    from kincalc import parse_robot_text
    from kincalc.analysis.results import Units
    r = parse_robot_text(COAXIAL)
    rng = np.random.default_rng(4)
    for q in rng.uniform(-np.pi, np.pi, (20, 3)):
        res = jacobian_report(r, q)
        J = r.jacobian(q)
        J[:3] /= r.characteristic_length
        s = np.linalg.svd(J, compute_uv=False)
        d = res.to_dict()
        assert res.generic_rank == 2 and not res.singular
        assert np.isclose(d["condition"], s[0] / s[1], rtol=1e-9)
        res_mm = jacobian_report(r, q, units=Units(length="mm"))
        assert np.isclose(res_mm.to_dict()["condition"], d["condition"], rtol=1e-9)


@pytest.mark.parametrize("name", ["planar_3r", "craig_3r", "bk_rr"])
def test_a_stretched_planar_arm_loses_the_motion_along_itself_not_off_its_plane(name):
    """Stretched or folded, a planar arm's joints all move the tool point across its links:
    the lost direction is in the plane and normal to every joint's motion of the tool point
    (central differences of FK), never the plane's normal, which no configuration moves
    along. At q1 = 0 it was said to be z."""
    import re
    r = load_robot(name)
    for q1 in (0.0, 0.5, -2.0):
        for bend in (0.0, np.pi):
            q = np.zeros(r.dof)
            q[0], q[1] = q1, bend
            res = jacobian_report(r, q)
            text = [t for t in res.singularity.descriptions if "cannot move along" in t][0]
            d = np.array([float(x) for x in re.search(r"along \(([^)]*)\)", text)[1].split(",")])
            h = 1e-6
            moves = [(r.fk(q + h * e)[:3, 3] - r.fk(q - h * e)[:3, 3]) / (2 * h)
                     for e in np.eye(r.dof)]
            assert abs(d[2]) < 1e-3 and np.linalg.norm(d) > 0.99            # in the plane
            assert all(abs(d @ m) < 2e-3 * r.characteristic_length for m in moves), (q, text)
