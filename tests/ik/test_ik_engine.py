"""The engine's one of each: the limit normaliser, the duplicate rule, the violations,
the singular test and the FK check, each against a plain reference written here
(per item, from the definitions), and round trips through ``robot.ik``."""

import numpy as np
import pytest

from kincalc import jacobian_report, load_robot
from kincalc.fk import chain_frames, tool_from_cs
from kincalc.ik import Target, solve
from kincalc.ik.engine import singular
from kincalc.ik.joint_limits import close_pairs, duplicates
from kincalc.ik.joint_limits import normalise, violations, within_limits
from kincalc.spatial import wrap
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_axis_angle, rotation_angle, rotation_error
from kincalc.tolerances import LIMIT_TOL


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


def _robot(limits):
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=0.3 * i, a=0.1, d=0.05, theta=0.0,
                         limits=lim) for i, lim in enumerate(limits))
    return Robot(name="lims", convention="dh", joints=joints)


def _nearest_turn_reference(x, lo, hi):
    """Brute force over 41 turns: the principal value if it is within [lo, hi] (to
    LIMIT_TOL), else the turn within them nearest it, else the turn missing them least."""
    p = float(wrap(x))
    if lo - LIMIT_TOL <= p <= hi + LIMIT_TOL:
        return p
    turns = [p + 2 * np.pi * k for k in range(-20, 21)]
    inside = [t for t in turns if lo - LIMIT_TOL <= t <= hi + LIMIT_TOL]
    if inside:
        return min(inside, key=lambda t: abs(t - p))
    return min(turns, key=lambda t: max(lo - t, t - hi))


LIMITS = [(-np.pi, np.pi), (0.0, 2 * np.pi), (-0.5, 0.7), (3 * np.pi, 3.5 * np.pi),
          (-4 * np.pi, 4 * np.pi), (2.0, 2.1)]
#: more than two turns below or above the principal values: the turn nearest it is taken
WIDE = [(-5 * np.pi, 0.5), (-0.5, 5 * np.pi)]


def test_normalise_is_the_turn_nearest_the_limits():
    limits = LIMITS + WIDE
    robot = _robot(limits)
    rng = np.random.default_rng(3)
    Q = rng.uniform(-15, 15, (400, len(limits)))
    Q[:20] = np.array([lo for lo, _ in limits]) + rng.choice([-1, 1], (20, len(limits))) * 5e-10
    got = normalise(robot, Q)
    for q, g in zip(Q, got):
        want = [_nearest_turn_reference(x, lo, hi) for x, (lo, hi) in zip(q, limits)]
        assert np.allclose(g, want, atol=1e-12), (q, g, want)
        assert np.allclose(np.cos(g), np.cos(q)) and np.allclose(np.sin(g), np.sin(q))
    assert np.array_equal(within_limits(robot, Q), ~(violations(robot, got) != 0).any(-1))


def test_a_solution_at_its_limit_to_rounding_is_within_it():
    """The issue's case: PUMA's q2 5e-10 rad past its 225 deg limit is within it (not
    'lower limit violated by 90 deg' after a wrap to -135 deg)."""
    r = load_robot("puma560")
    q = np.array([0.1, np.radians(225) + 5e-10, -0.3, 0.2, 0.4, 0.1])
    n = normalise(r, q[None])[0]
    assert abs(n[1] - np.radians(225)) < 1e-9 and not violations(r, n[None]).any()


def test_violations_per_joint():
    robot = _robot(LIMITS)
    q = np.array([0.0, -0.1, 0.8, 0.0, 0.0, 2.05])
    v = violations(robot, q[None])[0]
    assert v[0] == 0 and v[5] == 0
    assert np.isclose(v[1], -0.1) and np.isclose(v[2], 0.8 - 0.7)
    assert np.isclose(v[3], 0.0 - 3 * np.pi)


def test_duplicates_are_the_greedy_first_kept():
    robot = load_robot("stanford_arm")                       # revolute and prismatic
    rng = np.random.default_rng(4)
    base = rng.uniform(-3, 3, (50, 1, 6))
    q = np.repeat(base, 6, axis=1)
    q[:, 1:] += rng.choice([0.0, 1e-8, 1e-3, 2 * np.pi], (50, 5, 6)) * robot.is_revolute
    q[:, :, 2] += rng.choice([0.0, 1e-9, 0.1], (50, 6))      # the prismatic joint
    valid = rng.random((50, 6)) < 0.8
    got = duplicates(robot, q, valid, close_pairs(robot, q, valid))
    for n in range(50):
        kept, want = [], np.zeros(6, bool)
        for k in range(6):
            if not valid[n, k]:
                continue
            d = np.abs(q[n, k] - q[n, kept]) if kept else np.zeros((0, 6))
            if len(kept):
                d[:, robot.is_revolute] = np.abs(wrap(d[:, robot.is_revolute]))
            if len(kept) and (d.max(-1) < 1e-6).any():
                want[k] = True
            else:
                kept.append(k)
        assert np.array_equal(got[n], want), n


@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford_arm", "bk_rrp", "fer_rrpr"])
def test_singular_test_is_jacobian_reports(name):
    """The engine's rank test against kincalc.jacobian_report, configuration by
    configuration, at random and at singular configurations."""
    r = load_robot(name)
    rng = np.random.default_rng(8)
    Q = rng.uniform(-2, 2, (40, r.dof))
    if r.dof >= 5:
        Q[:15, 4] = 0.0
    Q[15:20, :] = 0.0
    F = chain_frames(r.chain, Q)
    tool = F[:, -1] @ r.chain.fixed[-1]
    got = singular(r, Q, F, tool)
    want = [jacobian_report(r, q).singular for q in Q]
    assert got.tolist() == want


@pytest.mark.parametrize("name", ["puma560", "stanford_arm", "ur5_poe", "bk_rrp", "planar_3r"])
def test_fk_from_cosines_and_sines_is_fk(name):
    r = load_robot(name)
    q = np.random.default_rng(2).uniform(-2, 2, (30, r.dof))
    cols, p = tool_from_cs(r.chain, np.cos(q).T.copy(), np.sin(q).T.copy(), q.T.copy())
    T = r.fk(q)
    assert np.allclose(np.stack(cols, -1).transpose(1, 0, 2), T[:, :3, :3], atol=1e-14)
    assert np.allclose(p.T, T[:, :3, 3], atol=1e-14)


@pytest.mark.parametrize("name", ["puma560", "ur5", "manocha_canny_6r", "stanford_arm"])
def test_round_trips_through_robot_ik(name):
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
        for s in res.solutions:
            assert s.position_error <= 1e-9 * robot.characteristic_length
            assert s.orientation_error <= 1e-9


def test_labels_of_a_wrist_at_the_base_tell_every_branch_apart():
    """A reversed family (the wrist at the base) had the words of a wrist at the tool put
    on the robot's own joints 4-6: two branches of one pose read "shoulder right wrist
    no-flip joint2:+ joint4:+". Every solution of a pose has its own label."""
    from test_ik import wrist_first_robot
    from kincalc.analysis.redundancy import locked_robot
    from kincalc.ik.selftest import sample_configurations
    import kincalc
    rng = np.random.default_rng(31)
    robots = [wrist_first_robot(rng) for _ in range(4)]
    robots.append(locked_robot(kincalc.load_robot("panda"), {6: 0.4}))
    for r in robots:
        for q in sample_configurations(r, 10, rng):
            labels = [s.branch for s in r.ik(r.fk(q)).solutions]
            assert len(labels) == len(set(labels)), labels


@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford_arm", "abb_irb140"])
def test_singular_flags_equal_the_svd_rank_test(name):
    """The engine skips the SVD where the determinant proves full rank; its flags must be
    those of the rank test itself (every singular value, written here) on random
    configurations and on singular ones (wrist straight, elbow at special values)."""
    import kincalc
    from kincalc.fk import frames_and_tool
    from kincalc.ik.engine import singular
    from kincalc.tolerances import SINGULAR_TOL
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(12)
    Q = rng.uniform(-3, 3, (6000, r.dof))
    Q[:1500, 4] = 0.0
    Q[1500:2500, 2] = rng.choice([0.0, np.pi / 2, -np.pi / 2], 1000)
    F, tool = frames_and_tool(r.chain, Q)
    rev, L = r.is_revolute[:, None], r.characteristic_length
    z = F[:, :, :3, 2]
    # scale-free: linear rows over L, prismatic columns times L (m/s per m/s stays as is)
    J = np.concatenate([np.where(rev, np.cross(z, tool[:, None, :3, 3] - F[:, :, :3, 3]) / L,
                                 z), np.where(rev, z, 0.0)], axis=-1)
    sv = np.linalg.svd(J, compute_uv=False)
    full, full_pos = r.generic_ranks
    rank = (sv > SINGULAR_TOL * np.maximum(sv[:, :1], 1.0)).sum(-1)
    want = rank < full
    sv3 = np.linalg.svd(J[..., :3], compute_uv=False)
    rank3 = (sv3 > SINGULAR_TOL * np.maximum(sv3[:, :1], 1.0)).sum(-1)
    want |= ~((rank == 6) & (full_pos == 3)) & (rank3 < full_pos)
    got = singular(r, Q, F, tool)
    assert np.array_equal(got, want) and got[:1500].mean() > 0.5
