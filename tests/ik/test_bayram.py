"""Seed 004: Bayram's 8-DOF hybrid VGT arm (examples/bayram_vgt.py) checked against
the paper's own equations, independently of the example's FK code path, and the
numerical IK on the paper's Table 1 targets and on random round trips."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

_PATH = Path(__file__).resolve().parents[2] / "examples" / "bayram_vgt.py"
_spec = importlib.util.spec_from_file_location("bayram_vgt", _PATH)
bay = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bay)

B, D, H1, H2 = bay.B, bay.D, bay.H1, bay.H2
LIM = bay.LIMITS
LENGTH = np.where(bay.REVOLUTE, 1.0, bay.SCALE)      # scaled variables x = q / LENGTH


# --- independent helpers -------------------------------------------------------

def Rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def Rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def angle_between(Ra, Rb):
    """Rotation angle of Ra^T Rb, accurate near 0 (atan2 of the skew and symmetric parts)."""
    R = Ra.T @ Rb
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return float(np.arctan2(np.linalg.norm(w), (np.trace(R) - 1) / 2))


def random_q(rng, n):
    return rng.uniform(LIM[:, 0], LIM[:, 1], size=(n, 8))


def jacobian_scaled(q, h=1e-6):
    """Central-difference geometric Jacobian (6, 8) in the scaled variables, linear
    rows divided by the characteristic length (as the solver weighs them)."""
    J = np.zeros((6, 8))
    for j in range(8):
        dq = np.zeros(8)
        dq[j] = h * LENGTH[j]
        Tp, Tm = bay.fk(q + dq), bay.fk(q - dq)
        J[:3, j] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h) / bay.SCALE
        W = Tp[:3, :3] @ Tm[:3, :3].T
        J[3:, j] = 0.5 * np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]]) / (2 * h)
    return J


# --- the module's closed loop and the paper's equations -------------------------

def test_passive_angles_satisfy_the_loop_equations_4_to_7():
    rng = np.random.default_rng(4)
    for s, v, p in rng.uniform(LIM[1:4, 0], LIM[1:4, 1], size=(300, 3)):
        a, b, g, t = bay.passive_angles(s, v, p)
        assert 2 * B + v * np.cos(g) == pytest.approx(p * np.cos(b), abs=1e-13)          # (4)
        assert v * np.sin(g) == pytest.approx(p * np.sin(b), abs=1e-13)                  # (5)
        assert s * np.cos(a) + 2 * D * np.cos(t) == pytest.approx(p * np.cos(b), abs=1e-13)  # (6)
        assert s * np.sin(a) + 2 * D * np.sin(t) == pytest.approx(p * np.sin(b), abs=1e-13)  # (7)
        assert np.sin(g) > 0                    # sigma1 = +1
        assert np.sin(t - b) < 0                # sigma2 = -1 (the paper's sign convention)


def test_printed_eq_10_is_a_misprint():
    """theta = beta + atan2(k, sigma2 sqrt(1 - k^2)) as printed breaks eqs. (6)-(7) for
    either sign (checked through the leg length |A0 A11| = s)."""
    s, v, p = 0.30, 0.25, 0.45
    _, beta, _, _ = bay.passive_angles(s, v, p)
    k = (p * p + 4 * D * D - s * s) / (4 * D * p)
    for sigma2 in (1, -1):
        theta = beta + np.arctan2(k, sigma2 * np.sqrt(1 - k * k))
        a11 = p * np.array([np.cos(beta), np.sin(beta)]) - 2 * D * np.array([np.cos(theta), np.sin(theta)])
        assert abs(np.linalg.norm(a11) - s) > 1e-2


def test_every_configuration_inside_the_limits_assembles():
    w = 2 * B
    xi = [(p * p - v * v - w * w) / (2 * w * v) for v in LIM[2] for p in LIM[3]]
    k = [(p * p + w * w - s * s) / (2 * w * p) for s in LIM[1] for p in LIM[3]]
    assert max(np.abs(xi + k)) < 0.97                    # corners are the extremes
    for q in random_q(np.random.default_rng(1), 500):
        bay.fk(q)                                        # no ValueError
    with pytest.raises(ValueError):
        bay.passive_angles(0.3, 0.2, 0.2 + 2 * B + 0.01)   # p > v + 2b
    with pytest.raises(ValueError):
        bay.passive_angles(0.9, 0.3, 0.4)                  # s > p + 2d


def _eqs_19_to_21(q):
    """Position from the expanded equations (19)-(21), (19) corrected (C psi0, not
    C theta1 S psi0, multiplies the module-2 in-plane term)."""
    psi0, s1, v1, p1, s2, v2, p2, _ = q
    a1, _, _, t1 = bay.passive_angles(s1, v1, p1)
    a2, _, _, t2 = bay.passive_angles(s2, v2, p2)
    C, S = np.cos, np.sin
    Y1 = s1 * C(a1) + D * C(t1) - B
    X2 = -s2 * C(a2) - D * C(t2) + B
    Z2 = s2 * S(a2) + D * S(t2)
    r1 = (-S(psi0) * Y1 + C(psi0) * X2 + S(psi0) * S(t1) * Z2
          + (C(psi0) * S(t2) + S(psi0) * S(t1) * C(t2)) * H2)
    r2 = (C(psi0) * Y1 + S(psi0) * X2 - C(psi0) * S(t1) * Z2
          + (S(psi0) * S(t2) - C(psi0) * S(t1) * C(t2)) * H2)
    r3 = H1 + s1 * S(a1) + D * S(t1) + C(t1) * Z2 + C(t1) * C(t2) * H2
    return np.array([r1, r2, r3]), (t1, t2, X2)


def test_position_agrees_with_eqs_19_to_21():
    for q in random_q(np.random.default_rng(19), 200):
        r, _ = _eqs_19_to_21(q)
        assert np.allclose(bay.fk(q)[:3, 3], r, atol=1e-13, rtol=0)


def test_printed_eq_19_is_a_misprint():
    """The printed coefficient C theta1 S psi0 of the module-2 in-plane term differs
    from the FK wherever theta1, psi0 and that term are not zero."""
    q = bay.START_Q + np.array([0.7, 0.05, -0.01, 0.02, 0.06, 0.0, -0.05, 0.3])
    r, (t1, _, X2) = _eqs_19_to_21(q)
    printed_r1 = r[0] - np.cos(q[0]) * X2 + np.cos(t1) * np.sin(q[0]) * X2
    assert abs(X2) > 1e-3 and abs(t1) > 1e-2
    assert abs(printed_r1 - bay.fk(q)[0, 3]) > 1e-3


def test_orientation_is_eq_3_and_satisfies_eqs_16_to_18():
    for q in random_q(np.random.default_rng(3), 200):
        _, _, _, t1 = bay.passive_angles(*q[1:4])
        _, _, _, t2 = bay.passive_angles(*q[4:7])
        C = bay.fk(q)[:3, :3]
        assert np.allclose(C, Rz(q[0]) @ Rx(t1) @ Ry(t2) @ Rz(q[7]), atol=1e-14)
        psi0, psi23 = q[0], q[7]
        assert np.sin(t1) == pytest.approx(C[2, 0] * np.sin(psi23) + C[2, 1] * np.cos(psi23), abs=1e-14)  # (16)
        assert np.sin(t2) == pytest.approx(C[0, 2] * np.cos(psi0) + C[1, 2] * np.sin(psi0), abs=1e-14)    # (17)
        assert np.cos(t1) * np.cos(t2) == pytest.approx(C[2, 2], abs=1e-14)                              # (18)


def test_start_configuration_is_the_papers_start_pose():
    T = bay.fk(bay.START_Q)
    assert np.allclose(T[:3, 3], [0, 0, 0.644], atol=1e-15, rtol=0)
    assert np.allclose(T[:3, :3], np.eye(3), atol=1e-15)
    assert np.all(bay.START_Q >= LIM[:, 0]) and np.all(bay.START_Q <= LIM[:, 1])


def test_tables_are_transcribed():
    assert bay.TARGETS.shape == (5, 6) and bay.PAPER_ERRORS.tolist() == [1.35, 1.08, 11.8, 4.65, 6.61]
    assert bay.TARGETS[3].tolist() == [-0.188, 0.294, 0.648, -30, -30, -30]
    T = bay.target_pose(bay.TARGETS[1])                  # moving X-Y-Z: Rx(0) Ry(30) Rz(60)
    assert np.allclose(T[:3, :3], Ry(np.radians(30)) @ Rz(np.radians(60)), atol=1e-15)


# --- numerical IK -----------------------------------------------------------------

@pytest.fixture(scope="module")
def table1():
    return [bay.solve(bay.target_pose(row)) for row in bay.TARGETS]


@pytest.mark.parametrize("i", range(5))
def test_table1_target_reached_within_limits(table1, i):
    res, row = table1[i], bay.TARGETS[i]
    assert res.converged
    T = bay.fk(res.q)
    assert np.linalg.norm(T[:3, 3] - row[:3]) <= 1e-9
    R = Rx(np.radians(row[3])) @ Ry(np.radians(row[4])) @ Rz(np.radians(row[5]))
    assert angle_between(T[:3, :3], R) <= 1e-9
    assert res.position_error <= 1e-9 and res.orientation_error <= 1e-9
    assert np.all(res.q >= LIM[:, 0]) and np.all(res.q <= LIM[:, 1])


@pytest.mark.parametrize("i", range(5))
def test_table1_solution_is_the_least_change_from_the_start(table1, i):
    """First-order (KKT) condition of min |x - x_start| subject to f(x) = T and the
    limits: x - x_start = J^T lambda + sum over joints at a limit of mu_j e_j, with
    mu_j >= 0 at a lower and <= 0 at an upper limit. With no joint at a limit this says
    that x - x_start has no component in the null space of J."""
    q = table1[i].q
    dx = (q - bay.START_Q) / LENGTH
    J = jacobian_scaled(q)
    lower = np.flatnonzero(np.abs(q - LIM[:, 0]) <= 1e-9)
    upper = np.flatnonzero(np.abs(q - LIM[:, 1]) <= 1e-9)
    active = np.concatenate([lower, upper])
    E = np.zeros((8, len(active)))
    E[active, np.arange(len(active))] = 1.0
    M = np.hstack([J.T, E])
    coef = np.linalg.lstsq(M, dx, rcond=None)[0]
    assert np.linalg.norm(M @ coef - dx) <= 1e-5
    mu = coef[6:]
    assert np.all(mu[:len(lower)] >= -1e-8) and np.all(mu[len(lower):] <= 1e-8)
    if len(active) == 0:
        null = np.linalg.svd(J)[2][6:]
        assert np.abs(null @ dx).max() <= 1e-5


def test_round_trips_from_a_perturbed_start():
    rng = np.random.default_rng(2024)
    for q in random_q(rng, 50):
        T = bay.fk(q)
        q0 = np.clip(q + rng.normal(scale=1e-3, size=8) * LENGTH, LIM[:, 0], LIM[:, 1])
        res = bay.solve(T, q0)
        assert res.converged, q
        assert np.all(res.q >= LIM[:, 0]) and np.all(res.q <= LIM[:, 1])
        Tq = bay.fk(res.q)
        assert np.linalg.norm(Tq[:3, 3] - T[:3, 3]) <= 1e-9
        assert angle_between(Tq[:3, :3], T[:3, :3]) <= 1e-9
