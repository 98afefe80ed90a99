"""All real IK solutions of a general 6R (kincalc.ik.general6r).

* Random general 6R robots in all three conventions, with random base, tool
  and joint offsets: FK of a random configuration, solve, and the generating
  configuration must come back; every solution must reproduce the pose.
* The published 16-real-solution example of Manocha & Canny (1994), Table I
  (robot), the hand pose printed with it, and Table III (the 16 solutions).
* Robots with special structure (UR5, PUMA 560, ABB IRB 140): documented
  behaviour is that the degenerate elimination is avoided by another pivot
  joint and the robot's (up to) 8 solutions are returned; checked against
  kincalc's analytic family solvers and many-start Newton.
"""

import time

import numpy as np
import pytest
from randrobots import random_pose, random_robot

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik.general6r import _robot_data, solve_general_6r
from kincalc.model import Joint, Robot
from kincalc.spatial import rotvec_from_matrix

D = np.deg2rad


def wrap(q):
    return np.pi - np.mod(np.pi - q, 2 * np.pi)


def residual(robot, T, Q):
    """max(|dp| / size, |rotation error|) of each row of Q (rad, relative)."""
    Tc = robot.fk(Q)
    ep = np.linalg.norm(Tc[..., :3, 3] - T[:3, 3], axis=-1) / robot.characteristic_length
    R_err = T[:3, :3] @ np.swapaxes(Tc[..., :3, :3], -1, -2)
    ew = np.linalg.norm(rotvec_from_matrix(R_err), axis=-1)
    return np.maximum(ep, ew)


def distance(Q, q):
    """Wrapped max-abs joint distance from each row of Q to q."""
    return np.max(np.abs(wrap(Q - q)), axis=-1)


def check(robot, T, q_true, S):
    """Hard invariants (always asserted) and the generic-case success flag."""
    assert S.ndim == 2 and S.shape[1] == 6
    assert np.all(np.isfinite(S))
    assert len(S) <= 16
    assert np.all((S > -np.pi) & (S <= np.pi))
    if len(S):
        assert np.max(residual(robot, T, S)) < 1e-9
        # duplicates merged
        if len(S) > 1:
            Dm = np.max(np.abs(wrap(S[:, None] - S[None])), axis=-1) + np.eye(len(S)) * 9
            assert Dm.min() > 1e-6
    found = len(S) > 0 and distance(S, q_true).min() < 1e-6
    return found and len(S) % 2 == 0


# --- random general robots -------------------------------------------------

@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_random_general_6r_returns_the_generating_configuration(convention):
    rng = np.random.default_rng({"dh": 601, "mdh": 602, "poe": 603}[convention])
    ok = total = 0
    counts, failures, times = [], [], []
    for i in range(30):
        robot = random_robot(rng, convention, types=["revolute"] * 6)
        solve_general_6r(robot, robot.fk(np.zeros(6)))          # build the cached model
        for _ in range(10):
            q = rng.uniform(-np.pi, np.pi, 6)
            T = robot.fk(q)
            t0 = time.perf_counter()
            S = solve_general_6r(robot, T)
            times.append(time.perf_counter() - t0)
            good = check(robot, T, q, S)
            ok += good
            total += 1
            counts.append(len(S))
            if not good:
                failures.append((i, q.round(4).tolist(), len(S)))
    rate = ok / total
    print(f"\n{convention}: {ok}/{total} = {100 * rate:.2f} % recovered, "
          f"solutions per pose {np.bincount(counts).tolist()}, "
          f"median {1e3 * np.median(times):.2f} ms/pose")
    assert total >= 300
    assert rate >= 0.995, failures
    assert max(counts) > 6            # the sample is not all easy poses


def test_semi_special_random_robots():
    """Random DH with many zero lengths and 0 / +-90 deg twists (parallel, perpendicular,
    intersecting consecutive axes) but finitely many solutions."""
    rng = np.random.default_rng(77)
    ok = total = 0
    while total < 150:
        joints = []
        for i in range(6):
            a = 0.0 if rng.random() < 0.35 else rng.uniform(-0.5, 0.5)
            d = 0.0 if rng.random() < 0.35 else rng.uniform(-0.5, 0.5)
            u = rng.random()
            alpha = 0.0 if u < 0.2 else (rng.choice([np.pi / 2, -np.pi / 2]) if u < 0.5
                                         else rng.uniform(-np.pi, np.pi))
            joints.append(Joint(f"q{i + 1}", "revolute", alpha=alpha, a=a, d=d,
                                theta=rng.uniform(-np.pi, np.pi)))
        robot = Robot("semi", "dh", joints, base=random_pose(rng), tool=random_pose(rng))
        robot = [robot, dh_to_mdh(robot), to_poe(robot)][total % 3]
        if robot.generic_ranks[0] < 6:          # e.g. coincident axes: a self-motion
            continue
        for _ in range(5):
            q = rng.uniform(-np.pi, np.pi, 6)
            J = robot.jacobian(q)
            J[:3] /= robot.characteristic_length
            if np.linalg.svd(J, compute_uv=False)[-1] < 1e-6:   # generating q singular
                continue
            T = robot.fk(q)
            S = solve_general_6r(robot, T)
            found = len(S) > 0 and distance(S, q).min() < 1e-6
            assert np.all(np.isfinite(S)) and len(S) <= 16
            if len(S):
                assert np.max(residual(robot, T, S)) < 1e-9
            ok += found
            total += 1
    assert ok / total >= 0.99, (ok, total)


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_dh_model_of_the_axes_reproduces_fk(convention):
    rng = np.random.default_rng(11)
    for _ in range(10):
        robot = random_robot(rng, convention, types=["revolute"] * 6)
        model = _robot_data(robot).model
        q = rng.uniform(-np.pi, np.pi, (20, 6))
        assert np.allclose(model.fk_dh(q), robot.fk(q), atol=1e-12)
    # parallel and intersecting consecutive axes
    special = Robot("special", "dh",
                    [Joint(f"q{i}", "revolute", alpha=al, a=a, d=d)
                     for i, (al, a, d) in enumerate([(0, 0.3, 0), (0, 0.2, 0.1), (np.pi / 2, 0, 0),
                                                     (0, 0, 0.2), (np.pi / 2, 0.1, 0), (0, 0, 0)])])
    for robot in (load_robot("ur5"), load_robot("puma560"), load_robot("ur5_poe"), special):
        model = _robot_data(robot).model
        q = rng.uniform(-np.pi, np.pi, (20, 6))
        assert np.allclose(model.fk_dh(q), robot.fk(q), atol=1e-12)


def test_same_solutions_in_every_convention():
    rng = np.random.default_rng(5)
    dh = random_robot(rng, "dh", types=["revolute"] * 6)
    q = rng.uniform(-np.pi, np.pi, 6)
    T = dh.fk(q)
    sets = [solve_general_6r(r, T) for r in (dh, dh_to_mdh(dh), to_poe(dh))]
    assert len(sets[0]) >= 2
    for S in sets[1:]:
        assert len(S) == len(sets[0])
        assert all(distance(S, s).min() < 1e-9 for s in sets[0])


def test_pivot_and_eigenvector_angles_at_pi():
    """theta = pi makes x = tan(theta / 2) infinite: the pivot (x3) through the shift of
    the unknown, x4 and x5 through the inverted ratios."""
    rng = np.random.default_rng(9)
    for _ in range(10):
        robot = random_robot(rng, "dh", types=["revolute"] * 6)
        model = _robot_data(robot).model
        for joints in ([2], [3], [4], [2, 3, 4]):
            q = rng.uniform(-np.pi, np.pi, 6)
            q[joints] = wrap(np.pi - model.offset[joints])       # DH theta = pi exactly
            T = robot.fk(q)
            S = solve_general_6r(robot, T)
            assert distance(S, q).min() < 1e-6


def test_standard_form_with_the_pivot_at_pi():
    """The standard form itself (pivot joint 3) must cope with theta_3 = pi, where the
    leading matrix A of Sigma(x3) is singular: the unknown is shifted, not the pivot."""
    rng = np.random.default_rng(10)
    for _ in range(10):
        robot = random_robot(rng, "dh", types=["revolute"] * 6)
        data = _robot_data(robot)
        q = rng.uniform(-np.pi, np.pi, 6)
        q[2] = wrap(np.pi - data.model.offset[2])
        c = data.candidates(robot.fk(q), 0)
        assert c is not None
        assert distance(c, q).min() < 1e-6


def test_polish_false_returns_the_raw_eigenproblem_candidates():
    rng = np.random.default_rng(3)
    robot = random_robot(rng, "poe", types=["revolute"] * 6)
    q = rng.uniform(-np.pi, np.pi, 6)
    T = robot.fk(q)
    raw = solve_general_6r(robot, T, polish=False)
    polished = solve_general_6r(robot, T)
    assert distance(raw, q).min() < 1e-6
    assert np.max(residual(robot, T, raw)) < 1e-6
    assert len(raw) == len(polished)


def test_unreachable_pose_and_bad_input():
    rng = np.random.default_rng(4)
    robot = random_robot(rng, "dh", types=["revolute"] * 6)
    T = np.eye(4)
    T[:3, 3] = [50.0, 0.0, 0.0]                       # far outside a ~3 m robot
    assert solve_general_6r(robot, T).shape == (0, 6)
    with pytest.raises(ValueError):
        solve_general_6r(load_robot("stanford_arm"), np.eye(4))    # prismatic joint
    with pytest.raises(ValueError):
        solve_general_6r(load_robot("iiwa7"), np.eye(4))           # 7 joints
    with pytest.raises(ValueError):
        solve_general_6r(load_robot("planar_3r"), np.eye(4))
    with pytest.raises(ValueError):
        solve_general_6r(robot, np.full((4, 4), np.nan))


# --- the published 16-solution example --------------------------------------

# D. Manocha, J. F. Canny, "Efficient inverse kinematics for general 6R
# manipulators", IEEE Trans. Robotics and Automation 10(5), 1994: Table I (standard
# DH; Wampler & Morgan's problem 6, a variant of Manseur & Doty's 16-solution robot),
# the hand pose A_hand printed in sec. V-F, and Table III (joint angles, deg).
MC_A = [0.3, 1.0, 0.0, 1.5, 0.0, 0.0]
MC_D = [0.0, 0.0, 0.2, 0.0, 0.0, 0.0]
MC_ALPHA = [90.0, 1.0, 90.0, 1.0, 90.0, 1.0]
MC_HAND = [[-0.7601, -0.6416, 0.1022, -1.1401],
           [0.1333, 0.0, 0.9910, 0.0],
           [-0.6359, 0.7669, 0.0855, 0.0],
           [0.0, 0.0, 0.0, 1.0]]
MC_TABLE_III = [
    [-96.28, -6.27, 179.96, 38.48, 52.55, -39.40],
    [-120.78, 172.33, -179.07, 31.33, -146.71, 142.82],
    [88.67, -176.72, -176.72, -63.24, 157.19, 140.43],
    [113.84, 5.30, -177.74, -55.92, -62.98, -43.37],
    [-178.12, 108.19, -147.73, -5.69, -164.67, 179.58],
    [168.32, -103.89, 146.60, -17.24, -171.87, 98.16],
    [-12.94, -105.09, -114.97, 3.02, 7.41, -79.42],
    [2.51, 108.07, 112.04, -10.52, 0.00, -0.10],
    [2.51, 108.07, -67.95, -169.47, 179.99, 179.89],
    [-12.94, -105.09, 65.02, 176.97, 172.58, 100.57],
    [168.32, -103.89, -33.39, -162.75, -8.12, -81.83],
    [-178.12, 108.19, 32.26, -174.30, -15.32, -0.41],
    [88.67, -176.72, 3.27, -116.75, 22.80, -39.56],
    [-96.28, -6.27, -0.03, 141.51, 127.44, 140.59],
    [-120.78, 172.33, 0.92, 148.66, -33.28, -37.17],
    [113.84, 5.30, 2.25, -124.07, -117.01, 136.62],
]


def manocha_canny_robot():
    return Robot("manocha_canny_1994", "dh",
                 [Joint(f"q{i + 1}", "revolute", alpha=D(MC_ALPHA[i]), a=MC_A[i], d=MC_D[i])
                  for i in range(6)])


def test_manocha_canny_example_has_16_real_solutions():
    robot = manocha_canny_robot()
    T = np.array(MC_HAND)
    U, _, Vt = np.linalg.svd(T[:3, :3])               # the printed 4 digits, made a rotation
    T[:3, :3] = U @ Vt
    ref = D(np.array(MC_TABLE_III))
    # the transcription is consistent: every row of Table III gives the printed pose
    assert np.allclose(robot.fk(ref), T, atol=2e-3)
    S = solve_general_6r(robot, T)
    assert len(S) == 16
    dist = np.max(np.abs(wrap(S[:, None, :] - ref[None, :, :])), axis=-1)   # (16, 16)
    assert np.all(dist.min(axis=1) < D(0.05))        # each solution is a row of Table III
    assert np.all(dist.min(axis=0) < D(0.05))        # each row of Table III is found
    assert len(set(dist.argmin(axis=1))) == 16       # one to one
    assert np.max(residual(robot, T, S)) < 1e-9
    # theta_3 = 179.96 deg and -0.03 deg: roots near x3 = infinity and 0 are both there
    assert np.abs(S[:, 2]).max() > D(179.9) and np.abs(S[:, 2]).min() < D(0.1)


def test_manocha_canny_exact_pose_of_each_table_row():
    """FK of a Table III row is a pose with 16 solutions, the row among them exactly."""
    robot = manocha_canny_robot()
    for row in (0, 7, 13):
        q = D(np.array(MC_TABLE_III[row]))
        S = solve_general_6r(robot, robot.fk(q))
        assert len(S) == 16
        assert distance(S, q).min() < 1e-9


# --- special structure --------------------------------------------------------

def newton_multistart(robot, T, n=400, seed=0):
    """Independent reference: damped Newton from n random starts (its own loop)."""
    rng = np.random.default_rng(seed)
    Q = rng.uniform(-np.pi, np.pi, (n, 6))
    L = robot.characteristic_length
    for _ in range(60):
        Tc = robot.fk(Q)
        e = np.concatenate([(T[:3, 3] - Tc[:, :3, 3]) / L,
                            rotvec_from_matrix(T[:3, :3] @ np.swapaxes(Tc[:, :3, :3], -1, -2))], -1)
        J = robot.jacobian(Q)
        J[:, :3] /= L
        JT = np.swapaxes(J, -1, -2)
        dq = np.linalg.solve(JT @ J + 1e-6 * np.eye(6), (JT @ e[..., None]))[..., 0]
        scale = np.minimum(1.0, 0.3 / np.maximum(np.abs(dq).max(-1, keepdims=True), 1e-300))
        Q = Q + dq * scale
    Q = wrap(Q[residual(robot, T, Q) < 1e-9])
    keep = []
    for q in Q:
        if all(distance(k[None], q)[0] > 1e-5 for k in keep):
            keep.append(q)
    return np.array(keep).reshape(-1, 6)


@pytest.mark.parametrize("name", ["ur5", "puma560", "abb_irb140"])
def test_special_robots_return_their_solutions(name):
    """Documented behaviour: the standard pivot (joint 3) degenerates for these robots
    (singular matrix pencil); another pivot joint is used and the robot's up to 8
    solutions come back: the same set as kincalc's analytic family solver (UR-type
    three-parallel, resp. spherical wrist) and as many-start Newton."""
    from kincalc.ik import Target, solve

    robot = load_robot(name)
    data = _robot_data(robot)
    rng = np.random.default_rng(8)
    q = rng.uniform(-np.pi, np.pi, 6)
    assert data.candidates(robot.fk(q), 0) is None        # the standard form degenerates
    assert data.shifts[0] != 0
    counts = []
    for k in range(15):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = robot.fk(q)
        S = solve_general_6r(robot, T)
        assert 1 <= len(S) <= 8
        assert distance(S, q).min() < 1e-6
        assert np.max(residual(robot, T, S)) < 1e-9
        analytic = wrap(np.array([s.q for s in solve(robot, Target(T)).solutions]).reshape(-1, 6))
        assert len(analytic) == len(S)
        assert all(distance(S, a).min() < 1e-6 for a in analytic)
        if k < 3:
            R = newton_multistart(robot, T, seed=k)
            assert len(R) <= len(S)
            assert all(distance(S, r).min() < 1e-6 for r in R)
        counts.append(len(S))
    assert counts.count(8) >= 3, counts


def test_clustered_eigenvalues_of_wrist_flips():
    """With the pivot on joint 2 of a spherical-wrist arm, the two wrist flips share the
    pivot angle (a double eigenvalue whose eigenvectors mix): both must come out."""
    from kincalc.ik import Target, solve
    from kincalc.ik.general6r import _polish

    robot = load_robot("puma560")
    data = _robot_data(robot)
    rng = np.random.default_rng(12)
    for _ in range(8):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = robot.fk(q)
        c = data.candidates(T, 5)                        # cyclic shift 5: pivot joint 2
        Q, res = _polish(robot, T, c, robot.characteristic_length)
        S = wrap(Q[res < 1e-10])
        analytic = wrap(np.array([s.q for s in solve(robot, Target(T)).solutions]).reshape(-1, 6))
        assert len(analytic) >= 2
        assert all(distance(S, a).min() < 1e-6 for a in analytic)
