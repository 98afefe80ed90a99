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
* Batches (the only implementation; a single pose is a batch of one): FK round
  trips of every slot over thousands of seeded random configurations, the
  generating configuration among the answers, even counts, no duplicates, no
  NaN, answers independent of the batch a pose comes in; edge cases.
"""

import time

import numpy as np
import pytest
from randrobots import random_pose, random_robot

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik.general6r import BATCH_SLOTS, solve_general_6r, solve_general_6r_batch
from kincalc.ik.general6r.polish import polish_candidates
from kincalc.ik.general6r.robot import robot_data
from kincalc.model import Joint, Robot
from kincalc.spatial import rotation_error, rotvec_from_matrix

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
        model = robot_data(robot).model
        q = rng.uniform(-np.pi, np.pi, (20, 6))
        assert np.allclose(model.fk_dh(q), robot.fk(q), atol=1e-12)
    # parallel and intersecting consecutive axes
    special = Robot("special", "dh",
                    [Joint(f"q{i}", "revolute", alpha=al, a=a, d=d)
                     for i, (al, a, d) in enumerate([(0, 0.3, 0), (0, 0.2, 0.1), (np.pi / 2, 0, 0),
                                                     (0, 0, 0.2), (np.pi / 2, 0.1, 0), (0, 0, 0)])])
    for robot in (load_robot("ur5"), load_robot("puma560"), load_robot("ur5_poe"), special):
        model = robot_data(robot).model
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
        model = robot_data(robot).model
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
        data = robot_data(robot)
        q = rng.uniform(-np.pi, np.pi, 6)
        q[2] = wrap(np.pi - data.model.offset[2])
        _, _, c, degenerate, _, _ = data.raw(robot.fk(q)[None], 0)
        assert not degenerate[0]
        assert distance(c, q).min() < 1e-6


def test_raw_eigenproblem_candidates_are_accurate_before_newton():
    """The elimination itself (no Newton step): its candidates that place the tool to
    1e-6 are the polished solutions, the generating configuration among them."""
    rng = np.random.default_rng(3)
    for convention in ("dh", "mdh", "poe"):
        robot = random_robot(rng, convention, types=["revolute"] * 6)
        for _ in range(5):
            q = rng.uniform(-np.pi, np.pi, 6)
            T = robot.fk(q)
            _, _, raw, degenerate, _, _ = robot_data(robot).raw(T[None], 0)
            assert not degenerate[0]
            raw = wrap(raw[residual(robot, T, raw) < 1e-6])
            distinct = [c for i, c in enumerate(raw)
                        if i == 0 or distance(raw[:i], c).min() > 1e-6]
            polished = solve_general_6r(robot, T)
            assert distance(raw, q).min() < 1e-6
            assert len(distinct) == len(polished)
            assert all(distance(polished, c).min() < 1e-6 for c in distinct)


def test_unreachable_pose_and_bad_input():
    rng = np.random.default_rng(4)
    robot = random_robot(rng, "dh", types=["revolute"] * 6)
    T = np.eye(4)
    T[:3, 3] = [50.0, 0.0, 0.0]                       # far outside a ~3 m robot
    assert solve_general_6r(robot, T).shape == (0, 6)
    assert solve_general_6r(robot, np.full((4, 4), np.nan)).shape == (0, 6)
    with pytest.raises(ValueError):
        solve_general_6r(load_robot("stanford_arm"), np.eye(4))    # prismatic joint
    with pytest.raises(ValueError):
        solve_general_6r(load_robot("iiwa7"), np.eye(4))           # 7 joints
    with pytest.raises(ValueError):
        solve_general_6r(load_robot("planar_3r"), np.eye(4))
    with pytest.raises(ValueError):
        solve_general_6r(robot, np.eye(3))


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
    data = robot_data(robot)
    rng = np.random.default_rng(8)
    q = rng.uniform(-np.pi, np.pi, 6)
    assert data.raw(robot.fk(q)[None], 0)[3][0]           # the standard form degenerates
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


def test_clustered_eigenvalues_of_wrist_flips(monkeypatch):
    """With the pivot on joint 2 of a spherical-wrist arm, the two wrist flips share the
    pivot angle (a double eigenvalue whose eigenvectors mix; clusters of four occur too):
    the raw candidates, before any Newton step, must be within 1e-7 of the analytic
    family solver's solutions (but for some near-singular poses), and after Newton
    contain all of them but at a rare pose whose double root rounding splits by more than
    CLUSTER_TOL (the package's limitation of a close pair sharing the pivot angle: over
    9,600 seeded poses, 46 of 76,800 solutions, at one pose in 200; here at most one)."""
    from kincalc.ik import Target, solve
    from kincalc.ik.general6r import common, elimination

    sizes = []
    split = elimination.split_clusters

    def spy(v, phi, keep, Sig, *args):
        # sizes of the runs of real candidates closer than CLUSTER_TOL (sorted angles)
        key = np.sort(np.where(keep, phi.real, np.inf), axis=1)
        for row in np.diff(key, axis=1) < common.CLUSTER_TOL:
            runs = np.diff(np.flatnonzero(np.r_[True, ~row, True]))
            sizes.extend(runs[runs > 1].tolist())
        return split(v, phi, keep, Sig, *args)

    monkeypatch.setattr(elimination, "split_clusters", spy)
    robot = load_robot("puma560")
    data = robot_data(robot)
    rng = np.random.default_rng(18)
    qs = rng.uniform(-np.pi, np.pi, (80, 6))
    Ts = robot.fk(qs)
    pose, _, c, degenerate, _, _ = data.raw(Ts, 5)        # cyclic shift 5: pivot joint 2
    assert not degenerate.any()
    assert sizes.count(2) >= 40 and max(sizes) >= 3, sizes   # pairs, and larger clusters
    found = total = missed = 0
    for n, T in enumerate(Ts):
        analytic = wrap(np.array([s.q for s in solve(robot, Target(T)).solutions]).reshape(-1, 6))
        assert len(analytic) >= 2
        found += sum(distance(c[pose == n], a).min() < 1e-7 for a in analytic)
        total += len(analytic)
        Q, res, _ = polish_candidates(data.chain, np.repeat(T[None, :3] / data.scale, np.sum(pose == n), 0),
                            c[pose == n])
        S = wrap(Q[res < 1e-10])
        missed += not all(distance(S, a).min() < 1e-6 for a in analytic)
    assert found >= 0.95 * total, (found, total)     # the rest: near-singular poses
    assert missed <= 1, missed


# --- batches -------------------------------------------------------------------

def _general_robots(count, seed):
    rng = np.random.default_rng(seed)
    return [load_robot("manocha_canny_6r")] + [
        random_robot(rng, types=["revolute"] * 6) for _ in range(count)]


def _contains(A, q, tol=1e-6):
    A = np.asarray(A).reshape(-1, 6)
    return len(A) > 0 and float(np.min(np.max(np.abs(wrap(A - q)), axis=1))) < tol


@pytest.mark.parametrize("robot", _general_robots(3, 12), ids=lambda r: r.name)
def test_batch_round_trip_every_slot_is_a_solution(robot):
    """1500 seeded random configurations per robot in one batch: every valid slot
    reproduces its pose, the generating configuration is among them, counts are even
    (a generic 6R), no duplicates, no NaN, valid slots first."""
    rng = np.random.default_rng(6)
    n = 1500
    qs = rng.uniform(-np.pi, np.pi, (n, 6))
    T = robot.fk(qs)
    Q, ok = solve_general_6r_batch(robot, T)
    assert Q.shape == (n, BATCH_SLOTS, 6) and ok.shape == (n, BATCH_SLOTS)
    assert ok.dtype == bool
    assert not np.any(np.isnan(Q))
    found = np.array([_contains(Q[k][ok[k]], qs[k]) for k in range(n)])
    assert found.mean() >= 0.998, np.flatnonzero(~found)
    counts = ok.sum(axis=1)
    assert np.mean(counts % 2 == 0) >= 0.99
    assert counts.max() > 6
    if robot.name == "manocha_canny_6r":
        assert counts.max() == 16
    k_idx = np.nonzero(ok)
    Tq = robot.fk(Q[k_idx])
    L = robot.characteristic_length
    assert np.max(np.linalg.norm(Tq[:, :3, 3] - T[k_idx[0], :3, 3], axis=-1)) <= 1e-9 * L
    assert np.max(rotation_error(Tq[:, :3, :3], T[k_idx[0], :3, :3])) <= 1e-9
    assert np.all((Q > -np.pi) & (Q <= np.pi))
    assert not np.any(~ok[:, :-1] & ok[:, 1:])
    for k in range(n):
        S = Q[k][ok[k]]
        if len(S) > 1:
            D = np.max(np.abs(wrap(S[:, None] - S[None])), axis=-1)
            assert np.min(D[~np.eye(len(S), dtype=bool)]) >= 1e-6


@pytest.mark.parametrize("name", ["manocha_canny_6r", "puma560"])
def test_a_pose_gets_the_same_answers_in_any_batch(name):
    """A pose's solutions do not depend on the other poses of its batch (per-pose shift
    delta, clusters, pivots, Newton's stopping): in one batch, reversed, or alone."""
    robot = load_robot(name)
    rng = np.random.default_rng(21)
    T = robot.fk(rng.uniform(-np.pi, np.pi, (40, 6)))
    Q, ok = solve_general_6r_batch(robot, T)
    Qr, okr = solve_general_6r_batch(robot, T[::-1])
    for k in range(len(T)):
        alone = solve_general_6r(robot, T[k])
        for other in (Qr[len(T) - 1 - k][okr[len(T) - 1 - k]], alone):
            assert len(other) == ok[k].sum()
            assert all(_contains(other, q, 1e-9) for q in Q[k][ok[k]])


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_batch_of_a_special_robot_gives_the_analytic_solutions(name):
    """Robots whose pivot ranking does not start at joint 3 (per-pose models of another
    pivot, vectorised): the analytic family solver's solutions, FK round trips."""
    from kincalc.ik import Target, solve
    robot = load_robot(name)
    assert robot_data(robot).shifts[0] != 0
    rng = np.random.default_rng(8)
    qs = rng.uniform(-np.pi, np.pi, (60, 6))
    T = robot.fk(qs)
    Q, ok = solve_general_6r_batch(robot, T)
    assert np.max(residual(robot, T[0], Q[0][ok[0]])) < 1e-9
    for k in range(len(T)):
        S = Q[k][ok[k]]
        assert np.max(residual(robot, T[k], S)) < 1e-9
        assert _contains(S, qs[k])
        analytic = wrap(np.array([s.q for s in solve(robot, Target(T[k])).solutions])
                        .reshape(-1, 6))
        assert len(S) == len(analytic), k
        assert all(_contains(S, a) for a in analytic), k


def test_poses_of_one_batch_on_different_pivots(monkeypatch):
    """PUMA with the standard form ranked first: it degenerates for every pose, which
    then goes on to the next pivot (shift 5) together; the answers stay the analytic
    ones."""
    from kincalc.ik import Target, solve
    robot = load_robot("puma560")
    data = robot_data(robot)
    monkeypatch.setattr(data, "shifts", [0, 5] + [k for k in data.shifts if k not in (0, 5)])
    rng = np.random.default_rng(31)
    qs = rng.uniform(-np.pi, np.pi, (30, 6))
    T = robot.fk(qs)
    Q, ok = solve_general_6r_batch(robot, T)
    for k in range(len(T)):
        S = Q[k][ok[k]]
        analytic = wrap(np.array([s.q for s in solve(robot, Target(T[k])).solutions])
                        .reshape(-1, 6))
        assert len(S) == len(analytic) and _contains(S, qs[k])
        assert all(_contains(S, a) for a in analytic)


def test_last_resort_of_two_perturbed_models(monkeypatch):
    """With no pivot left (forced here on a generic robot), every pose is solved on two
    nearby generic robots and their candidates are polished on the real one: still FK
    round trips, the generating configuration, no duplicates."""
    rng = np.random.default_rng(32)
    robot = random_robot(rng, "dh", types=["revolute"] * 6)
    monkeypatch.setattr(robot_data(robot), "shifts", [])
    qs = rng.uniform(-np.pi, np.pi, (40, 6))
    T = robot.fk(qs)
    Q, ok = solve_general_6r_batch(robot, T)
    assert np.mean([_contains(Q[k][ok[k]], qs[k]) for k in range(len(T))]) >= 0.95
    for k in range(len(T)):
        S = Q[k][ok[k]]
        if len(S):
            assert np.max(residual(robot, T[k], S)) < 1e-9
        if len(S) > 1:
            D = np.max(np.abs(wrap(S[:, None] - S[None])), axis=-1)
            assert np.min(D[~np.eye(len(S), dtype=bool)]) >= 1e-6


def test_batch_edge_cases():
    robot = load_robot("manocha_canny_6r")
    Q, ok = solve_general_6r_batch(robot, np.zeros((0, 4, 4)))
    assert Q.shape == (0, BATCH_SLOTS, 6) and ok.shape == (0, BATCH_SLOTS)
    T = robot.fk(np.array([[0.3, -0.2, 0.5, 1.0, -1.2, 0.4]] * 3))
    T[1, 0, 0] = np.nan                                     # no solution, no crash
    T[2, :3, 3] += 10 * robot.characteristic_length         # out of reach
    Q, ok = solve_general_6r_batch(robot, T)
    assert ok[0].any() and not ok[1].any() and not ok[2].any()
    assert not np.any(np.isnan(Q))
    Q, ok = solve_general_6r_batch(robot, T[1:2])           # nothing finite at all
    assert not ok.any()
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        solve_general_6r_batch(robot, T[0])
    with pytest.raises(ValueError, match="6 revolute"):
        solve_general_6r_batch(load_robot("stanford_arm"), T)


def test_polish_returns_to_the_solutions_and_gives_up_far_away():
    robot = load_robot("manocha_canny_6r")
    data = robot_data(robot)
    T = robot.fk(np.array([0.3, -0.2, 0.5, 1.0, -1.2, 0.4]))
    S = solve_general_6r(robot, T)
    rng = np.random.default_rng(2)
    start = S + rng.uniform(-1e-4, 1e-4, S.shape)
    target = T[None, :3] / data.scale                     # rows 0-2, scaled translation
    Q, res, moved = polish_candidates(data.chain, np.repeat(target, len(S), 0), start)
    assert moved.all()
    assert np.all(res < 1e-12)
    assert np.max(np.abs(wrap(Q - S))) < 1e-10
    far = rng.uniform(-np.pi, np.pi, (200, 6))
    Q, res, _ = polish_candidates(data.chain, np.repeat(target, len(far), 0), far)
    good = res < 1e-10
    assert not good.all()                                   # most give up
    assert all(_contains(S, q) for q in wrap(Q[good]))      # the rest found real ones


def test_pose_no_candidate_reaches_after_polishing():
    """A pose where every candidate is polished (some move) and none reaches it: no
    solution, not a crash (the duplicate check ran on an empty set). The Kinova Gen3 with
    its joint 6 held at -3 deg is a general 6R; the pose, made with joint 6 at 50 deg, is
    outside its reach: many-start Newton on the same chain finds nothing either."""
    from kincalc.analysis.redundancy import locked_robot
    gen3 = load_robot("kinova_gen3")
    T = gen3.fk(D([10, 40, 20, -60, 30, 50, -20]))
    chain = locked_robot(gen3, {5: D(-3.0)})
    assert solve_general_6r(chain, T).shape == (0, 6)
    rng = np.random.default_rng(11)
    for _ in range(40):
        q = rng.uniform(-np.pi, np.pi, 6)
        for _ in range(40):
            Tq = chain.fk(q)
            e = np.concatenate([Tq[:3, 3] - T[:3, 3],
                                0.5 * sum(np.cross(T[:3, i], Tq[:3, i]) for i in range(3))])
            q = q - np.linalg.lstsq(chain.jacobian(q), e, rcond=None)[0]
        assert residual(chain, T, q[None])[0] > 1e-6


def test_merge_screen_finds_every_duplicate_pair():
    """The merge of _solve_block screens a pose's pairs by their first joint before comparing
    all six: the same verdicts as comparing every pair in full (its own loop here), with
    duplicates planted across the +-pi seam and near misses in one joint."""
    from kincalc.ik.general6r.common import MERGE_TOL
    from kincalc.ik.general6r.solve import _duplicates
    rng = np.random.default_rng(31)
    M, S = 40, 12
    Qd = rng.uniform(-np.pi, np.pi, (M, S, 6))
    for m in range(M):
        i, j = sorted(rng.choice(S, 2, replace=False))
        Qd[m, j] = Qd[m, i] + rng.uniform(-0.5, 0.5, 6) * MERGE_TOL     # a duplicate of i
        if m % 3 == 0:                                                     # across the seam
            Qd[m, i, 0], Qd[m, j, 0] = np.pi - 1e-8, -np.pi + 1e-8
        if m % 4 == 0:                                 # same first joint, another differs
            k = (j + 1) % S
            Qd[m, k] = Qd[m, i]
            Qd[m, k, rng.integers(1, 6)] += 3 * MERGE_TOL
    good = rng.random((M, S)) < 0.85
    expected = np.zeros((M, S), bool)
    for m in range(M):
        for i in range(S):
            for j in range(i):
                d = np.abs(wrap(Qd[m, i] - Qd[m, j]))
                expected[m, i] |= good[m, j] and bool(np.all(d < MERGE_TOL))
    assert expected.sum() >= 20
    assert np.array_equal(_duplicates(wrap(Qd), good), expected)
    assert _duplicates(wrap(Qd), np.zeros_like(good)) is None          # none: no array


@pytest.mark.parametrize("name", ["manocha_canny_6r", "kinova_gen3_lite"])
def test_root_labels_alone_and_in_a_batch(name):
    """A general 6R solution's label is its rank (``root k`` of joint 3): the same whether
    its pose is solved alone (``robot.ik``) or in a batch, also at poses with joints at 0,
    +-90 and 180 deg, where several solutions share a joint-3 value or sit at +-pi and the
    last bits of the values differ between the two."""
    from kincalc.ik.selftest import sample_configurations
    from kincalc.spatial import wrap
    robot = load_robot(name)
    rng = np.random.default_rng(11)
    Q = sample_configurations(robot, 40, rng)
    special = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi])
    Q = np.where(rng.random(Q.shape) < 0.5, special[rng.integers(0, 4, Q.shape)], Q)
    T = robot.fk(Q)
    batch = robot.ik_batch(T)
    compared = 0
    for i in range(len(T)):
        for s in robot.ik(T[i]).solutions:
            d = np.where(batch.valid[i], np.abs(wrap(batch.q[i] - s.q)).max(-1), np.inf)
            k = int(np.argmin(d))
            assert d[k] < 1e-7
            assert batch.labels[i][k] == s.branch
            compared += 1
    assert compared > 100
