"""Batched IK (``robot.ik_batch``, vectorised over poses): every solution reproduces
its pose, the generating configuration is among them, and a pose asked alone
(``robot.ik``, a batch of one) gets the same solutions with the same labels and flags."""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.errors import UnsupportedRobot
from kincalc.ik.engine import solve_batch
from kincalc.ik.families import plan
from kincalc.spatial import wrap
from kincalc.ik.selftest import sample_configurations
from kincalc.conventions.library import bundled_names

ROBOTS = ["puma560", "ur5", "ur10e", "kuka_kr16", "fanuc_lrmate200id", "abb_irb120",
          "stanford_arm", "bk_6r", "bk_scara_euler", "kocaeli_kr16_lengths"]


def same_set(A, B, robot):
    if len(A) != len(B):
        return False
    for a in A:
        d = np.abs(np.where(robot.is_revolute, wrap(np.asarray(B) - a), np.asarray(B) - a)).max(-1)
        if d.min() > 1e-7:
            return False
    return True


@pytest.mark.parametrize("name", ROBOTS)
def test_batch_matches_per_pose_solver(name):
    r = load_robot(name)
    Q = sample_configurations(r, 400, np.random.default_rng(11))
    T = r.fk(Q)
    B = solve_batch(r, T)
    assert B.q.shape[0] == 400 and B.valid.shape == B.q.shape[:2]
    for i in range(400):
        sols = B.q[i][B.valid[i]]
        # the generating configuration is among them
        d = np.abs(np.where(r.is_revolute, wrap(sols - Q[i]), sols - Q[i])).max(-1)
        assert d.min() < 1e-6
        # every batched solution reproduces the pose
        assert np.allclose(r.fk(sols), T[i], atol=1e-9 * max(1.0, r.characteristic_length))
    for i in range(0, 400, 40):                      # same solution set as robot.ik
        ref = [s.q for s in r.ik(T[i]).solutions]
        assert same_set(B.q[i][B.valid[i]], ref, r)


def test_batch_unreachable_poses_have_no_solutions():
    r = load_robot("puma560")
    T = np.tile(np.eye(4), (5, 1, 1))
    T[:, 0, 3] = np.linspace(2, 3, 5)
    assert solve_batch(r, T).counts.tolist() == [0] * 5


@pytest.mark.parametrize("name", ["iiwa14", "panda"])
def test_batch_refuses_robots_no_closed_form_covers(name):
    """Seven joints: no closed form (the numerical solver's business, pose by pose)."""
    with pytest.raises(UnsupportedRobot):
        solve_batch(load_robot(name), np.eye(4)[None])


@pytest.mark.parametrize("name", ["bk_offset_wrist", "adept_cobra600", "bk_rrp"])
def test_every_closed_form_family_is_batched(name):
    """The families the per-pose engine alone had (offset wrist, SCARA, position-only)
    now come batched: round trips over a batch."""
    r = load_robot(name)
    Q = sample_configurations(r, 50, np.random.default_rng(4))
    T = r.fk(Q)
    B = solve_batch(r, T)
    L = max(1.0, r.characteristic_length)
    for i in range(len(Q)):
        sols = B.q[i][B.valid[i]]
        assert np.abs(r.fk(sols)[:, :3, 3] - T[i, :3, 3]).max() <= 1e-9 * L
        d = np.abs(np.where(r.is_revolute, wrap(sols - Q[i]), sols - Q[i])).max(-1)
        assert d.min() < 1e-6


def test_general_6r_batch_equals_robot_ik_with_its_labels():
    """A general 6R (no closed form) through ik_batch: the same solutions as robot.ik
    and the same 'q3:root k' labels, on the textbook robot and
    random 6R robots (the generating configuration is always among them)."""
    from randrobots import random_robot

    rng = np.random.default_rng(21)
    robots = [load_robot("manocha_canny_6r")] + [
        random_robot(rng, types=["revolute"] * 6) for _ in range(2)]
    for r in robots:
        Q = rng.uniform(-np.pi, np.pi, (60, 6))
        T = r.fk(Q)
        B = solve_batch(r, T, chunk=25)
        assert B.family == "general-6r" and B.q.shape == (60, 16, 6)
        rows, slots = np.nonzero(B.valid)
        labels = B.labels[B.valid]
        for i in range(60):
            sols = B.q[i][B.valid[i]]
            assert np.abs(wrap(sols - Q[i])).max(-1).min() < 1e-6
            assert np.allclose(r.fk(sols), T[i], atol=1e-9 * r.characteristic_length)
            if i % 6:
                continue
            ref = {s.branch: np.asarray(s.q) for s in r.ik(T[i]).solutions}
            mine = dict(zip((labels[k] for k in np.flatnonzero(rows == i)), sols))
            assert mine.keys() == ref.keys(), (r.name, i)
            for key, q in mine.items():
                assert np.abs(wrap(ref[key] - q)).max() < 1e-7, (r.name, i, key)


def _dh_robot(rng, alphas, a, d):
    from kincalc.model import Joint, Robot
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=alphas[i], a=a[i], d=d[i],
                         theta=rng.uniform(-np.pi, np.pi), limits=(-np.pi, np.pi))
                   for i in range(6))
    return Robot(name="random", convention="dh", joints=joints)


def _random_family_robot(rng, kind):
    """Random dimensions (m) of an arm of one family; twists random where the family
    allows, so the solver cannot lean on 90-degree angles."""
    u = lambda: rng.uniform(-0.6, 0.6)  # noqa: E731
    tw = lambda: rng.uniform(-np.pi, np.pi)  # noqa: E731
    if kind == "wrist, axes 1-2 meet":        # PUMA-like: a1 = 0; wrist a4 = a5 = d5 = 0
        return _dh_robot(rng, [tw(), tw(), tw(), tw(), tw(), tw()],
                         [0, u(), u(), 0, 0, u()], [u(), u(), u(), u(), 0, u()])
    if kind == "wrist, axes 1-2 parallel":    # alpha1 = 0
        return _dh_robot(rng, [0, tw(), tw(), tw(), tw(), tw()],
                         [u(), u(), u(), 0, 0, u()], [u(), u(), u(), u(), 0, u()])
    if kind == "wrist, generic offsets":      # KUKA-like offsets, generic twists
        return _dh_robot(rng, [tw(), tw(), tw(), tw(), tw(), tw()],
                         [u(), u(), u(), 0, 0, u()], [u(), u(), u(), u(), 0, u()])
    # UR-like: axes 2, 3, 4 parallel, axes 5 and 6 meet (a5 = 0)
    return _dh_robot(rng, [tw(), 0, 0, tw(), tw(), tw()],
                     [u(), u(), u(), u(), 0, u()], [u(), u(), u(), u(), u(), u()])


@pytest.mark.parametrize("kind", ["wrist, axes 1-2 meet", "wrist, axes 1-2 parallel",
                                  "wrist, generic offsets", "three parallel"])
def test_batch_on_random_robots_of_each_family(kind):
    """Robots of random dimensions and twists: the generating configuration is always
    found, every returned solution reproduces its pose, and the set equals robot.ik's."""
    rng = np.random.default_rng(sum(map(ord, kind)))
    for _ in range(6):
        r = _random_family_robot(rng, kind)
        Q = sample_configurations(r, 300, rng)
        T = r.fk(Q)
        B = solve_batch(r, T)
        L = max(1.0, r.characteristic_length)
        found = 0
        for i in range(len(Q)):
            sols = B.q[i][B.valid[i]]
            assert np.allclose(r.fk(sols), T[i], atol=1e-9 * L)
            if len(sols):
                d = np.abs(np.where(r.is_revolute, wrap(sols - Q[i]), sols - Q[i])).max(-1)
                found += d.min() < 1e-6
        assert found >= 0.995 * len(Q), (kind, found)
        for i in range(0, len(Q), 60):
            ref = [s.q for s in r.ik(T[i]).solutions]
            assert same_set(B.q[i][B.valid[i]], ref, r), (kind, i)


@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford_arm"])
def test_batch_at_singular_configurations_returns_only_true_solutions(name):
    """Wrist aligned (q5 = 0 or pi), arm folded, the zero configuration: a continuum of
    solutions; every representative returned must reproduce the pose, and the
    generating configuration's pose is reached."""
    r = load_robot(name)
    rng = np.random.default_rng(5)
    Q = sample_configurations(r, 200, rng)
    Q[:100, 4] = rng.choice([0.0, np.pi], 100)
    Q[100:150, 2] = 0.0
    Q[150:] = 0.0
    T = r.fk(Q)
    B = solve_batch(r, T)
    L = max(1.0, r.characteristic_length)
    for i in range(len(Q)):
        sols = B.q[i][B.valid[i]]
        assert len(sols) >= 1
        assert np.allclose(r.fk(sols), T[i], atol=1e-9 * L)


def test_batch_chunks_do_not_change_the_answer():
    r = load_robot("ur5")
    T = r.fk(sample_configurations(r, 1000, np.random.default_rng(2)))
    a, b = solve_batch(r, T), solve_batch(r, T, chunk=97)
    assert np.array_equal(a.valid, b.valid)
    assert np.allclose(np.where(a.valid[..., None], a.q, 0), np.where(b.valid[..., None], b.q, 0))


def test_batch_chunks_keep_a_continuum_that_only_a_later_chunk_has():
    """Wrist-singular poses (q5 = 0: only q4 + q6 is fixed) in the last chunk only: the
    chunked batch carries the same continuum relations as one chunk of everything."""
    r = load_robot("puma560")
    Q = sample_configurations(r, 60, np.random.default_rng(4))
    Q[50:, 4] = 0.0
    T = r.fk(Q)
    a, b = solve_batch(r, T), solve_batch(r, T, chunk=25)
    assert a.continuum is not None and b.continuum is not None
    flag = a.continuum[..., 0] != 0                     # column 0: the slot has one
    assert not flag[:50].any() and flag[50:].any()
    assert np.array_equal(a.valid, b.valid) and np.array_equal(flag, b.continuum[..., 0] != 0)
    assert np.allclose(a.continuum[flag], b.continuum[flag])


def test_batch_keeps_both_wrist_solutions_near_the_singularity():
    """q5 = 2.3e-5 rad: the wrist's two solutions differ clearly (by pi in q4); a
    degenerate-angle threshold above the rounding floor once set q4 = 0 for them and
    lost both (found by benchmarks/peers.py against EAIK)."""
    r = load_robot("puma560")
    q = np.array([1.1978067658, 0.8500925701, -3.1831982129, 1.4759860354, 0.000023113,
                  3.765408426])
    B = solve_batch(r, r.fk(q)[None])
    sols = B.q[0][B.valid[0]]
    assert len(sols) == 8
    assert np.abs(wrap(sols - q)).max(-1).min() < 1e-6


def test_batch_of_no_poses_has_the_robots_slots():
    for name in ("puma560", "ur5"):
        r = load_robot(name)
        K = solve_batch(r, r.fk(r.home)[None]).q.shape[1]
        B = solve_batch(r, np.zeros((0, 4, 4)))
        assert B.q.shape == (0, K, 6) and B.valid.shape == (0, K) and K >= 8


def agree(r, T):
    """``robot.ik`` of each pose against the batch: the same solutions, each with the same
    label, limit flag and singular flag."""
    B = solve_batch(r, T)
    free = 0
    for i in range(len(T)):
        sols = r.ik(T[i]).solutions
        assert len(sols) == B.counts[i], i
        for s in sols:
            d = np.abs(np.where(r.is_revolute, wrap(B.q[i] - s.q), B.q[i] - s.q)).max(-1)
            k = int(np.argmin(np.where(B.valid[i], d, np.inf)))
            assert d[k] < 1e-9, (i, s.branch)           # the same solution (to rounding)
            assert B.labels[i, k] == s.branch, (i, B.labels[i, k], s.branch)
            assert bool(B.within[i, k]) == s.within_limits, (i, s.branch)
            assert bool(B.singular[i, k]) == s.singular, (i, s.branch)
            free += "free)" in s.branch
    return free


@pytest.mark.parametrize("name", [n for n in bundled_names() if plan(load_robot(n))[1]])
def test_ik_and_ik_batch_agree_on_every_label_and_flag(name):
    """Every bundled robot with a closed form, at random poses and at the wrist
    singularity (q5 = 0 or 180 deg) where it has one."""
    r = load_robot(name)
    rng = np.random.default_rng(9)
    Q = sample_configurations(r, 25, rng)
    if r.dof == 6:
        Q[15:, 4] = rng.choice([0.0, np.pi], 10)
    if not plan(r)[1].needs_orientation:
        return agree_position(r, r.fk(Q))
    agree(r, r.fk(Q))


def agree_position(r, T):
    from kincalc.ik.engine import solve_targets
    from kincalc.ik.target import Targets
    B = solve_targets(r, Targets(T, "position"))
    for i in range(len(T)):
        sols = r.ik(T[i], orientation=False).solutions
        assert len(sols) == B.counts[i]
        for s in sols:
            d = np.abs(np.where(r.is_revolute, wrap(B.q[i] - s.q), B.q[i] - s.q)).max(-1)
            k = int(np.argmin(np.where(B.valid[i], d, np.inf)))
            assert d[k] < 1e-9 and B.labels[i, k] == s.branch


@pytest.mark.parametrize("name", ["puma560", "kuka_kr16", "ur5", "stanford_arm"])
def test_labels_name_the_free_joint_at_the_wrist_singularity(name):
    """At q5 = 0 or 180 deg the continuum's representatives say which joint is free,
    in the batch as alone."""
    r = load_robot(name)
    rng = np.random.default_rng(12)
    Q = sample_configurations(r, 30, rng)
    Q[:, 4] = rng.choice([0.0, np.pi], 30)
    assert agree(r, r.fk(Q)) >= 30          # the generating continuum at least, every pose


def test_three_cones_placement_at_the_stretched_elbow(monkeypatch):
    """The general placement of joints 1-3 (subproblem 5) at the stretched and folded
    elbow, where the polish's J^T J is singular (numpy once raised LinAlgError for the
    whole batch there). The offset-shoulder form is switched off so that KUKA and ABB
    arms take that path; every pose must be answered exactly."""
    from test_ik_batch_offset_shoulder import stretched_and_folded

    import kincalc.ik.place as place
    real = place._make_plan

    def no_shoulder(S, joints, p0):
        P = real(S, joints, p0)
        return P._replace(mode="three cones") if P.mode == "shoulder" else P
    monkeypatch.setattr(place, "_make_plan", no_shoulder)
    for name in ("kuka_kr16", "abb_irb6640"):
        r = load_robot(name)
        plan.cache_clear()
        for Qe in stretched_and_folded(r, sample_configurations(r, 30, np.random.default_rng(5))):
            T = r.fk(Qe)
            B = solve_batch(r, T)
            for i in range(len(T)):
                sols = B.q[i][B.valid[i]]
                assert len(sols) and np.allclose(r.fk(sols), T[i], atol=1e-9 * r.characteristic_length)
    plan.cache_clear()
