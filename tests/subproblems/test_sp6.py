"""Subproblem 6, two equations ``h1 . R(k1, t1) p1 + h2 . R(k2, t2) p2 = d1`` and
``h3 . R(k3, t1) p3 + h4 . R(k4, t2) p4 = d2``: known answers, completeness, no
solution out of reach, ill-posed cases, golden values, batch shapes (see
tests/subproblem_checks.py)."""

import numpy as np
import pytest

from kincalc.subproblems import sp6
from subproblem_checks import (LEAD, PI, X, Y, Z, check_batching, check_sane, lengths,
                               nearest_error, ok_count, turn, unit)

N_DRAWS = 3000
ANGLE_TOL = 1e-7   # rad


def sides(h, k, p, t1, t2):
    """The two left sides ``(..., m, 2)`` for angles ``t1, t2 (..., m)``; ``h, k, p
    (..., 4, 3)``."""
    h, k, p = (np.asarray(a, float)[..., None, :, :] for a in (h, k, p))
    t = np.stack([t1, t2, t1, t2], -1)
    terms = (h * turn(k, t, p)).sum(-1)                                   # (..., m, 4)
    return np.stack([terms[..., 0] + terms[..., 1], terms[..., 2] + terms[..., 3]], -1)


def residual(h, k, p, d1, d2, S):
    """``max |left - right|`` of every slot ``(..., 4)``."""
    d = np.stack(np.broadcast_arrays(d1, d2), -1)[..., None, :]
    return np.abs(sides(h, k, p, *S.theta) - d).max(-1)


def known_answers(rng, n, k=None):
    """``(h, k, p, d1, d2), theta (n, 2)`` of n solvable problems (axes ``k (4, 3)``
    shared if given)."""
    h = unit(rng, n, 4) * rng.uniform(0.1, 10, (n, 4, 1))
    k = unit(rng, n, 4) if k is None else np.broadcast_to(k, (n, 4, 3))
    p = lengths(rng, n, 4)
    t = rng.uniform(-PI, PI, (n, 2))
    d = sides(h, k, p, t[:, :1], t[:, 1:])[:, 0]
    return (h, k, p, d[:, 0], d[:, 1]), t


def size(h, p):
    return (np.linalg.norm(h, axis=-1) * np.linalg.norm(p, axis=-1)).max(-1)


# --- 1. known answers --------------------------------------------------------

def test_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(106)
    args, t = known_answers(rng, N_DRAWS)
    S = sp6(*args)
    check_sane(S, (N_DRAWS,), 2, 4)
    assert (S.exact == S.ok).all() and not S.free.any()
    err = nearest_error(S, t)
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())
    res = residual(*args, S) / size(args[0], args[2])[:, None]
    assert res[S.ok].max() < 1e-9, res[S.ok].max()
    counts = np.bincount(ok_count(S), minlength=5)
    assert counts[0] == counts[1] == counts[3] == 0 and counts[2] > 0 and counts[4] > 0, counts


def test_cos_sin_are_those_of_theta():
    rng = np.random.default_rng(107)
    S = sp6(*known_answers(rng, N_DRAWS)[0])
    for t, c, s in zip(S.theta, S.c, S.s):
        assert np.abs(c[S.ok] - np.cos(t[S.ok])).max() <= 1e-12
        assert np.abs(s[S.ok] - np.sin(t[S.ok])).max() <= 1e-12


def test_axes_along_the_coordinate_axes():
    """Robot-like geometry: ``h`` and ``k`` along +-x, +-y, +-z and integer points,
    so that exact zeros abound (a term without its angle, an angle in no equation,
    ...). Every problem that is not free gives its true angles; a free one a true
    representative. (Exact zero coefficients once made the quartic's companion matrix
    NaN, and eigvals raised for the whole batch.)"""
    rng = np.random.default_rng(108)
    n = 2000
    signed = np.concatenate([np.eye(3), -np.eye(3)])
    h = signed[rng.integers(0, 6, (n, 4))] * rng.choice([1, 2], (n, 4, 1))
    k = signed[rng.integers(0, 6, (n, 4))]
    p = rng.integers(-2, 3, (n, 4, 3)).astype(float)
    t = rng.uniform(-PI, PI, (n, 2))
    d = sides(h, k, p, t[:, :1], t[:, 1:])[:, 0]
    S = sp6(h, k, p, d[:, 0], d[:, 1])
    check_sane(S, (n,), 2, 4)
    free = S.free.any(-1)
    assert 0 < free.sum() < n / 2 and S.ok.any(-1).all()
    assert nearest_error(S, t)[~free].max() < 1e-6
    assert residual(h, k, p, d[:, 0], d[:, 1], S)[S.ok].max() < 1e-12


# --- completeness: an independent search finds no solution the solver missed --

def grid_newton(F, grid, keep, iters=25):
    """Zeros of ``F: (m, 2) -> (m, 2)`` reached by Newton's method from the best points
    of a grid: end points ``(keep, 2)`` and residuals."""
    axes = np.linspace(-PI, PI, grid, endpoint=False)
    x = np.stack(np.meshgrid(axes, axes, indexing="ij"), -1).reshape(-1, 2)
    x = x[np.argsort(np.linalg.norm(F(x), axis=-1))[:keep]]
    eye = 1e-7 * np.eye(2)
    for _ in range(iters):
        J = np.stack([(F(x + e) - F(x - e)) / 2e-7 for e in eye], axis=-1)
        x = x - np.einsum("nij,nj->ni", np.linalg.pinv(J), F(x))
    return x, np.linalg.norm(F(x), axis=-1)


def test_finds_every_solution_an_independent_search_finds():
    rng = np.random.default_rng(206)
    zeros_seen = 0
    for _ in range(25):
        h, k, p = rng.normal(size=(4, 3)), unit(rng, 4), rng.normal(size=(4, 3))
        d1, d2 = rng.normal(size=2)  # random: solvable or not
        S = sp6(h, k, p, d1, d2)
        check_sane(S, (), 2, 4)
        assert not S.free.any() and (S.exact == S.ok).all()

        def F(T):
            return sides(h, k, p, T[:, 0], T[:, 1]) - [d1, d2]

        for x, res in zip(*grid_newton(F, grid=64, keep=200)):
            if res < 1e-10:
                zeros_seen += 1
                assert nearest_error(S, x) < 1e-6, (x, S.rows())
    assert zeros_seen > 0  # the search is not vacuous


# --- 2. no least squares: out of reach ---------------------------------------

def test_out_of_reach_gives_no_solution():
    rng = np.random.default_rng(306)
    n = 500
    h, k, p = rng.normal(size=(n, 4, 3)), unit(rng, n, 4), rng.normal(size=(n, 4, 3))
    bound = np.linalg.norm(h, axis=-1) * np.linalg.norm(p, axis=-1)
    d1 = (bound[:, 0] + bound[:, 1]) * rng.uniform(1.01, 3, n) * rng.choice([-1, 1], n)
    S = sp6(h, k, p, d1, rng.normal(size=n))
    check_sane(S, (n,), 2, 4)
    assert not S.ok.any() and not S.exact.any() and not S.free.any()


# --- 3. ill-posed cases ------------------------------------------------------

def test_equation_without_angles_is_free():
    # h1 || k1 and h2 || k2: the first equation reads 1 + 2 = d1
    h, k, p = np.array([Z, Z, Y, Y]), np.array([Z, Z, Z, Z]), np.array([X + Z, X + 2 * Z, X, X])
    S = sp6(h, k, p, 3.0, 0.5)
    check_sane(S, (), 2, 4)
    assert S.ok.tolist() == [True, False, False, False] and S.exact[0] and S.free[0]
    assert residual(h, k, p, 3.0, 0.5, S)[0] < 1e-12
    S = sp6(h, k, p, 2.0, 0.5)                       # 3 = 2: no solution
    assert not S.ok.any() and not S.exact.any() and S.free.all()


def test_same_equation_twice_is_free():
    rng = np.random.default_rng(601)
    n = 20
    h, k, p = rng.normal(size=(n, 2, 3)), unit(rng, n, 2), rng.normal(size=(n, 2, 3))
    H, K, P = np.concatenate([h, 2 * h], 1), np.concatenate([k, k], 1), np.concatenate([p, p], 1)
    t = rng.uniform(-PI, PI, (n, 1, 2))
    d1 = sides(H, K, P, t[..., 0], t[..., 1])[:, 0, 0]
    S = sp6(H, K, P, d1, 2 * d1)
    check_sane(S, (n,), 2, 4)
    assert (ok_count(S) == 1).all() and S.ok[:, 0].all() and S.exact[:, 0].all()
    assert S.free.all()
    assert residual(H, K, P, d1, 2 * d1, S)[:, 0].max() < 1e-9
    S = sp6(H, K, P, d1, 2 * d1 + 0.1)
    assert not S.ok.any() and S.free.all()


def test_curve_of_solutions_is_free():
    # cos t1 - cos t2 = 0 and sin t1 - sin t2 = 0: every t1 = t2
    S = sp6([X, -X, Y, -Y], [Z] * 4, [X] * 4, 0.0, 0.0)
    check_sane(S, (), 2, 4)
    assert S.ok.tolist() == [True, False, False, False] and S.exact[0] and S.free[0]
    (t1, t2), = S.rows()
    assert abs(t1 - t2) < 1e-12


def test_second_angle_in_no_equation_is_free():
    # -sin t1 = 0 and cos t1 = 1 (the h2, h4 terms are constants 0): t1 = 0, t2 free
    # (this raised LinAlgError: the quartic's coefficients were exactly 0)
    S = sp6([-Y, Z, X, Z], [Z] * 4, [X] * 4, 0.0, 1.0)
    check_sane(S, (), 2, 4)
    assert S.ok.tolist() == [True, False, False, False] and S.exact[0] and S.free.all()
    assert S.rows() == [(0.0, 0.0)]


@pytest.mark.parametrize("d1", [0.0, 1.0])
def test_zero_coefficients_are_free_and_finite(d1):
    S = sp6(np.zeros((4, 3)), [Z] * 4, np.zeros((4, 3)), d1, 0.0)
    check_sane(S, (), 2, 4)
    assert S.free.all() and S.ok.any() == (d1 == 0.0)


# --- 4. golden cases ---------------------------------------------------------

def test_golden_two_unit_vectors_summing_to_1_1():
    # (cos t1 + cos t2, sin t1 + sin t2) = (1, 1): {t1, t2} = {0, pi/2}
    S = sp6([X, X, Y, Y], [Z] * 4, [X] * 4, 1.0, 1.0)
    check_sane(S, (), 2, 4)
    assert ok_count(S) == 2 and S.exact[S.ok].all() and not S.free.any()
    for e in [(0.0, PI / 2), (PI / 2, 0.0)]:
        assert nearest_error(S, e) < 1e-12, S.rows()


def test_golden_tangent_circles_give_one_solution():
    # (cos t1 + cos t2, sin t1 + sin t2) = (2, 0): t1 = t2 = 0, a double root
    S = sp6([X, X, Y, Y], [Z] * 4, [X] * 4, 2.0, 0.0)
    check_sane(S, (), 2, 4)
    assert ok_count(S) == 1 and not S.free.any()
    assert nearest_error(S, (0.0, 0.0)) < 1e-7, S.rows()


@pytest.mark.parametrize("k, d", [(Z, (-1.0, 1.0)), (-Z, (-1.0, -1.0)), (Z, (-2.0, 0.0))])
def test_golden_half_turns_are_pi_not_minus_pi(k, d):
    # (cos t1 + cos t2, sin t1 + sin t2) = d with a solution at t = pi
    S = sp6([X, X, Y, Y], [k] * 4, [X] * 4, *d)
    check_sane(S, (), 2, 4)
    assert any(PI in sol for sol in S.rows()), S.rows()


# --- 5. shapes ---------------------------------------------------------------

def mixed_batch(rng, k=None):
    """``LEAD`` problems: solvable, out of reach and ill-posed ones."""
    n = int(np.prod(LEAD))
    (h, k, p, d1, d2), _ = known_answers(rng, n, k)
    h, p, d1, d2 = h.copy(), p.copy(), d1.copy(), d2.copy()
    d1[1::6] = 3 * size(h[1::6], p[1::6])                  # out of reach
    h[2::6, 0], h[2::6, 1] = 2 * k[2::6, 0], -k[2::6, 1]   # an equation without angles
    h[3::6, 2:], p[3::6, 2:], d2[3::6] = 2 * h[3::6, :2], p[3::6, :2], 2 * d1[3::6]
    shared = np.broadcast_to(k, (n, 4, 3))
    if not (shared == shared[:1]).all():                   # twice the same equation
        shared = np.array(shared)
        shared[3::6, 2:] = shared[3::6, :2]
    return [a.reshape(LEAD + a.shape[1:]) for a in (h, shared, p, d1, d2)]


def test_batch_shapes_agree_with_each_problem_alone():
    rng = np.random.default_rng(501)
    S = check_batching(sp6, mixed_batch(rng), 2, 4)
    assert S.free.any() and S.ok.any() and not S.ok.any(-1).all()


def test_shared_axes_broadcast_against_per_problem_points():
    rng = np.random.default_rng(502)
    k = unit(rng, 4)
    check_batching(sp6, mixed_batch(rng, k), 2, 4, shared={1: k})


def test_one_geometry_against_many_right_sides():
    # (cos t1 + cos t2, sin t1 + sin t2) = (1, 1), (2, 0), (3, 0)
    S = sp6([X, X, Y, Y], [Z] * 4, [X] * 4, [1.0, 2.0, 3.0], [1.0, 0.0, 0.0])
    check_sane(S, (3,), 2, 4)
    assert ok_count(S).tolist() == [2, 1, 0]
    # d2 one number for all: (1, 0), (2, 0), (3, 0)
    S = sp6([X, X, Y, Y], [Z] * 4, [X] * 4, [1.0, 2.0, 3.0], 0.0)
    check_sane(S, (3,), 2, 4)
    assert ok_count(S).tolist() == [2, 1, 0]
    assert sorted(S.rows(0)) == [pytest.approx((-PI / 3, PI / 3)), pytest.approx((PI / 3, -PI / 3))]
