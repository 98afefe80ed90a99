"""The fast paths of IK: the batched general-6R solver and the vectorised post-processing.

The batched solver is checked against the single-pose solver and against FK round
trips; each vectorised helper of :mod:`kincalc.ik.solve` against a plain per-item
reference written here the way the code used to be (no timing assertions).
"""

import numpy as np
import pytest
from randrobots import random_robot

from kincalc import load_robot
from kincalc.fk import chain_frames
from kincalc.ik import Target, solve
from kincalc.ik.general6r import (BATCH_SLOTS, _polish, _robot_data, _rotvec,
                                  solve_general_6r, solve_general_6r_batch)
from kincalc.ik.screws import wrap
from kincalc.ik.solve import (_branch_labels, _constants, _dedupe_rows, _frames_and_pose,
                              _jacobian_from_frames, _normalise_rows, _violations,
                              _violations_rows, branch_label)
from kincalc.spatial import (cross, matrix_from_axis_angle, rotation_angle, rotation_error,
                             rotvec_from_matrix)
from kincalc.structure import common_point


def _general_robots(count, seed):
    rng = np.random.default_rng(seed)
    return [load_robot("manocha_canny_6r")] + [
        random_robot(rng, types=["revolute"] * 6) for _ in range(count)]


def _contains(A, q, tol=1e-6):
    A = np.asarray(A).reshape(-1, 6)
    return len(A) > 0 and float(np.min(np.max(np.abs(wrap(A - q)), axis=1))) < tol


def _separated(S, gap=1e-3):
    """Are the solutions pairwise farther apart than ``gap`` (rad, max over joints)?"""
    if len(S) < 2:
        return True
    D = np.max(np.abs(wrap(S[:, None] - S[None])), axis=-1)
    return float(np.min(D[~np.eye(len(S), dtype=bool)])) > gap


# --- the batched general 6R -------------------------------------------------------

@pytest.mark.parametrize("robot", _general_robots(3, 11), ids=lambda r: r.name)
def test_batch_finds_the_single_pose_solutions(robot):
    rng = np.random.default_rng(5)
    T = robot.fk(rng.uniform(-np.pi, np.pi, (120, 6)))
    Q, ok = solve_general_6r_batch(robot, T)
    compared = 0
    for n in range(len(T)):
        single = solve_general_6r(robot, T[n])
        if not _separated(single):
            continue                   # near-singular pose: a pair may merge differently
        compared += 1
        batch = Q[n][ok[n]]
        assert len(batch) == len(single), n
        assert all(_contains(batch, q) for q in single), n
        assert all(_contains(single, q) for q in batch), n
    assert compared >= 100


@pytest.mark.parametrize("robot", _general_robots(3, 12), ids=lambda r: r.name)
def test_batch_round_trip_every_slot_is_a_solution(robot):
    rng = np.random.default_rng(6)
    qs = rng.uniform(-np.pi, np.pi, (200, 6))
    T = robot.fk(qs)
    Q, ok = solve_general_6r_batch(robot, T)
    assert Q.shape == (200, BATCH_SLOTS, 6) and ok.shape == (200, BATCH_SLOTS)
    assert ok.dtype == bool
    # the generating configuration is among the solutions of its pose
    assert all(_contains(Q[n][ok[n]], qs[n]) for n in range(len(qs)))
    # every valid slot reproduces its pose; angles wrapped; valid slots first
    n_idx, k_idx = np.nonzero(ok)
    Tq = robot.fk(Q[n_idx, k_idx])
    L = robot.characteristic_length
    assert np.max(np.linalg.norm(Tq[:, :3, 3] - T[n_idx, :3, 3], axis=-1)) <= 1e-9 * L
    assert np.max(rotation_error(Tq[:, :3, :3], T[n_idx, :3, :3])) <= 1e-9
    assert np.all(np.abs(Q) <= np.pi)
    assert not np.any(~ok[:, :-1] & ok[:, 1:])
    assert not np.any(np.isnan(Q))
    # no duplicates within a pose
    for n in range(len(qs)):
        S = Q[n][ok[n]]
        if len(S) > 1:
            D = np.max(np.abs(wrap(S[:, None] - S[None])), axis=-1)
            assert np.min(D[~np.eye(len(S), dtype=bool)]) >= 1e-6


def test_batch_of_a_nearly_special_robot_uses_the_single_pose_path():
    # PUMA's pivot ranking does not start at joint 3: every pose goes the single way
    robot = load_robot("puma560")
    assert _robot_data(robot).shifts[0] != 0
    rng = np.random.default_rng(8)
    T = robot.fk(rng.uniform(-np.pi, np.pi, (5, 6)))
    Q, ok = solve_general_6r_batch(robot, T)
    for n in range(len(T)):
        single = solve_general_6r(robot, T[n])
        assert ok[n].sum() == len(single)
        assert np.allclose(Q[n][ok[n]], single)


def test_batch_edge_cases():
    robot = load_robot("manocha_canny_6r")
    Q, ok = solve_general_6r_batch(robot, np.zeros((0, 4, 4)))
    assert Q.shape == (0, BATCH_SLOTS, 6) and ok.shape == (0, BATCH_SLOTS)
    T = robot.fk(np.array([[0.3, -0.2, 0.5, 1.0, -1.2, 0.4]] * 3))
    T[1, 0, 0] = np.nan                                     # no solution, no crash
    T[2, :3, 3] += 10 * robot.characteristic_length         # out of reach
    Q, ok = solve_general_6r_batch(robot, T)
    assert ok[0].any() and not ok[1].any() and not ok[2].any()
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        solve_general_6r_batch(robot, T[0])
    with pytest.raises(ValueError, match="6 revolute"):
        solve_general_6r_batch(load_robot("stanford_arm"), T)


def test_polish_with_one_target_per_candidate_equals_a_shared_target():
    robot = load_robot("manocha_canny_6r")
    T = robot.fk(np.array([0.3, -0.2, 0.5, 1.0, -1.2, 0.4]))
    start = solve_general_6r(robot, T) + 1e-5
    shared, r1 = _polish(robot, T, start, robot.characteristic_length)
    each, r2 = _polish(robot, np.repeat(T[None], len(start), 0), start,
                       robot.characteristic_length)
    assert np.array_equal(shared, each) and np.array_equal(r1, r2)
    assert np.all(r1 < 1e-10)


def test_rotvec_matches_the_quaternion_route():
    rng = np.random.default_rng(9)
    axes = rng.normal(size=(400, 3))
    angles = np.concatenate([rng.uniform(0, np.pi, 396), [0.0, 1e-9, np.pi - 1e-9, np.pi]])
    R = matrix_from_axis_angle(axes, angles)
    assert np.allclose(_rotvec(R), rotvec_from_matrix(R), atol=1e-12)


# --- spatial.rotation_angle ---------------------------------------------------------

@pytest.mark.parametrize("shape", [(), (4,), (2, 3, 2)])
def test_rotation_angle_against_rotation_error(shape):
    rng = np.random.default_rng(10)
    n = int(np.prod(shape, dtype=int))
    angles = rng.uniform(0, np.pi, n)
    angles[:1] = np.pi if n > 1 else angles[:1]
    R = matrix_from_axis_angle(rng.normal(size=(n, 3)), angles).reshape(shape + (3, 3))
    got = rotation_angle(R)
    assert got.shape == shape
    assert np.allclose(got, rotation_error(R, np.eye(3)), atol=1e-12)
    assert np.allclose(got, angles.reshape(shape), atol=1e-12)
    assert rotation_angle(np.eye(3)) == 0.0


# --- the vectorised post-processing of solve() ------------------------------------------

def _normalise_reference(robot, q):
    """The per-joint loop the vectorised normalisation replaced."""
    q = np.array(q, float)
    lo, hi = robot.limits.T
    for i, j in enumerate(robot.joints):
        if not j.revolute:
            continue
        x = float(wrap(q[i]))
        if not (lo[i] - 1e-12 <= x <= hi[i] + 1e-12):
            for shift in (2 * np.pi, -2 * np.pi, 4 * np.pi, -4 * np.pi):
                if lo[i] - 1e-12 <= x + shift <= hi[i] + 1e-12:
                    x += shift
                    break
        q[i] = x
    return q


@pytest.mark.parametrize("name", ["puma560", "stanford_arm", "fer_rrpr", "ur5", "bk_rrp"])
def test_normalise_and_violations_per_row_as_per_joint(name):
    robot = load_robot(name)
    rng = np.random.default_rng(13)
    Q = rng.uniform(-4 * np.pi, 4 * np.pi, (300, robot.dof))
    Q[:5] = np.pi                                    # on the wrap boundary
    got = _normalise_rows(robot, Q)
    want = np.array([_normalise_reference(robot, q) for q in Q])
    assert np.array_equal(got, want)
    lo, hi = robot.limits.T
    for q in got:
        ref = sorted([(i, float(lo[i] - q[i]), "lower") for i in range(robot.dof)
                      if q[i] < lo[i] - 1e-12] +
                     [(i, float(q[i] - hi[i]), "upper") for i in range(robot.dof)
                      if q[i] > hi[i] + 1e-12])
        assert _violations(robot, q) == ref
    assert _violations_rows(got, _constants(robot)) == [_violations(robot, q) for q in got]


def test_dedupe_rows_is_the_greedy_first_kept():
    robot = load_robot("stanford_arm")          # revolute and prismatic joints
    rng = np.random.default_rng(14)
    base = rng.uniform(-np.pi, np.pi, (6, robot.dof))
    Q = np.concatenate([base, base[[0, 2, 2]] + 3e-7, base[[1]] + 2 * np.pi * robot.is_revolute,
                        base[[3]] + 2e-6])
    Q = Q[rng.permutation(len(Q))]
    kept = []
    for i, q in enumerate(Q):
        d = [np.where(robot.is_revolute, wrap(q - Q[j]), q - Q[j]) for j in kept]
        if not any(np.all(np.abs(x) < 1e-6) for x in d):
            kept.append(i)
    assert _dedupe_rows(robot, Q) == kept
    assert len(kept) == 7
    # two turns apart (a value shifted into wide limits) is the same; distinct rows all stay
    far = np.concatenate([base, base[[4]] - 4 * np.pi * robot.is_revolute])
    assert _dedupe_rows(robot, far) == list(range(6))
    assert _dedupe_rows(robot, base) == list(range(6))


@pytest.mark.parametrize("name", ["puma560", "stanford_arm", "fer_rrpr", "bk_rrp"])
def test_frames_pose_and_jacobian_in_one_pass(name):
    robot = load_robot(name)
    rng = np.random.default_rng(15)
    Q = rng.uniform(-np.pi, np.pi, (7, robot.dof))
    frames, Tq = _frames_and_pose(robot, Q)
    assert np.allclose(frames, chain_frames(robot.chain, Q), atol=1e-14)
    assert np.allclose(Tq, robot.fk(Q), atol=1e-14)
    J = _jacobian_from_frames(frames, Tq, _constants(robot))
    assert np.allclose(J, robot.jacobian(Q), atol=1e-13)


def _label_reference(robot, family, q, cand):
    """The per-candidate branch label the vectorised one replaced."""
    F = chain_frames(robot.chain, q)
    z, o = F[:, :3, 2], F[:, :3, 3]
    rev = robot.is_revolute
    parts, named, P = [], set(), None
    if family == "spherical-wrist":
        P = common_point(o[3:], z[3:], np.inf)
    elif family == "three-parallel":
        P = common_point(o[4:], z[4:], np.inf)
    if P is not None and rev[0] and np.linalg.norm(cross(z[0], z[1])) > 1e-6:
        parts.append("shoulder right" if (P - o[0]) @ cross(z[0], z[1]) >= 0
                     else "shoulder left")
        named.add(0)
    if P is not None and robot.dof >= 3 and rev[1] and rev[2] and \
            np.linalg.norm(cross(z[1], z[2])) < 1e-6:
        s, e = o[1], o[2]
        target = P if family == "spherical-wrist" else o[3]
        h = z[1]
        line = target - s
        line -= h * (h @ line)
        v = e - s
        v -= h * (h @ v)
        perp = v - line * (v @ line) / max(line @ line, 1e-300)
        up = float(perp @ z[0])
        if abs(up) < 1e-9 * robot.characteristic_length:
            up = float(cross(e - s, target - e) @ h)
        parts.append("elbow up" if up >= 0 else "elbow down")
        named.add(2 if family == "spherical-wrist" else 1)
        named.add(1 if family == "spherical-wrist" else 2)
    if family in ("spherical-wrist", "three-parallel"):
        parts.append("wrist no-flip" if cross(z[3], z[5]) @ z[4] >= 0 else "wrist flip")
        named.add(4)
    for i in sorted(cand.signs):
        if i not in named:
            parts.append(f"{robot.joints[i].name}:{cand.signs[i]}")
    if cand.free:
        parts.append("(" + ", ".join(robot.joints[i].name for i in cand.free) + " free)")
    return " ".join(parts) if parts else "unique"


@pytest.mark.parametrize("name", ["puma560", "kuka_kr16", "ur5", "stanford_arm",
                                  "bk_offset_wrist", "fer_rrpr", "manocha_canny_6r"])
def test_branch_labels_at_once_as_one_by_one(name):
    from kincalc.ik.families import Candidate, plan
    robot = load_robot(name)
    family = plan(robot)[1].name
    rng = np.random.default_rng(16)
    Q = rng.uniform(-np.pi, np.pi, (40, robot.dof))
    cands = [Candidate(q=q, signs={1: "+", robot.dof - 1: "root 2"},
                       free=[0] if k % 7 == 0 else []) for k, q in enumerate(Q)]
    got = _branch_labels(robot, family, cands, chain_frames(robot.chain, Q))
    want = [_label_reference(robot, family, q, c) for q, c in zip(Q, cands)]
    assert got == want
    assert [branch_label(robot, None, family, q, c) for q, c in zip(Q, cands)] == want


@pytest.mark.parametrize("name", ["puma560", "ur5", "manocha_canny_6r", "stanford_arm"])
def test_solve_round_trip_after_the_refactor(name):
    robot = load_robot(name)
    rng = np.random.default_rng(17)
    lo, hi = robot.limits.T
    for q in rng.uniform(np.maximum(lo, -np.pi), np.minimum(hi, np.pi), (20, robot.dof)):
        res = solve(robot, Target(robot.fk(q)))
        qs = np.array([s.q for s in res.solutions])
        d = np.where(robot.is_revolute, wrap(qs - q), qs - q)
        assert np.min(np.max(np.abs(d), axis=1)) < 1e-6
        assert len({tuple(np.round(s.q, 9)) for s in res.solutions}) == len(res.solutions)
        assert not np.any(np.isnan(qs))


def test_batch_clusters_give_the_single_pose_candidates():
    """PUMA with the pivot on joint 2: the two wrist flips share the pivot angle (a
    double eigenvalue whose eigenvectors mix), which the cluster treatment resolves;
    the batched core must give the raw candidates of the single-pose core (clusters of
    three or more are flagged for the single-pose path instead)."""
    from kincalc.ik.general6r import _candidates_batch
    robot = load_robot("puma560")
    data = _robot_data(robot)
    rng = np.random.default_rng(18)
    clusters = 0
    for q in rng.uniform(-np.pi, np.pi, (12, 6)):
        model, _ = data.shifted_model(robot.fk(q), 5)
        single = model.candidates(np.eye(4))
        Q, valid, fallback = _candidates_batch(model, np.eye(4)[None])
        if fallback[0] or len(single) != 8:
            # a cluster of 3 or more (left to the single-pose path), or a pose near the
            # wrist singularity (extra raw candidates that depend on rounding)
            continue
        batch = Q[0][valid[0]]
        clusters += int(valid[0, 24:].any())
        assert all(_contains(batch, c, 1e-7) for c in single)
        assert all(_contains(single, c, 1e-7) for c in batch)
    assert clusters >= 4
