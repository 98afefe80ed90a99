"""Subproblem 4, ``h . R(k, theta) p = d``: known answers, least squares, ill-posed
cases, the tangent, golden values, batch shapes (see tests/subproblem_checks.py)."""

import numpy as np
import pytest

from kincalc.subproblems import sp4
from kincalc.subproblems.sp4 import from_abc
from subproblem_checks import (LEAD, PI, X, Y, Z, check_batching, check_sane, is_local_minimum,
                               lengths, nearest_error, ok_count, rot, turn, unit, wrap)

N_DRAWS = 5000
ANGLE_TOL = 1e-7   # rad


def residual(h, p, k, d, theta):
    """``h . R(k, theta) p - d`` for angles ``theta (..., m)``."""
    return (h[..., None, :] * turn(k[..., None, :], theta, p[..., None, :])).sum(-1) - d[..., None]


def known_answers(rng, n, k=None):
    """``(h, p, k, d, theta)`` of n solvable problems (one shared axis if given)."""
    h = unit(rng, n) * rng.uniform(0.1, 10, (n, 1))
    k = unit(rng, n) if k is None else np.broadcast_to(k, (n, 3))
    p, t = lengths(rng, n)[:, 0], rng.uniform(-PI, PI, n)
    d = (h * turn(k, t, p)).sum(-1)
    return h, p, k, d, t


def extremes(h, p, k):
    """The range ``C -+ r`` of ``h . R p`` and its maximiser, from the projections on
    the plane across ``k`` (independently of the module's ``A``, ``B``)."""
    hk, pk = (h * k).sum(-1), (p * k).sum(-1)
    hp, pp = h - hk[..., None] * k, p - pk[..., None] * k
    r = np.linalg.norm(hp, axis=-1) * np.linalg.norm(pp, axis=-1)
    top = np.arctan2((np.cross(pp, hp) * k).sum(-1), (pp * hp).sum(-1))
    return hk * pk - r, hk * pk + r, top


# --- 1. known answers --------------------------------------------------------

def test_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(104)
    h, p, k, d, t = known_answers(rng, N_DRAWS)
    S = sp4(h, p, k, d)
    check_sane(S, (N_DRAWS,), 1, 2)
    assert S.ok[:, 0].all() and S.exact.all() and not S.free.any()
    err = nearest_error(S, t[:, None])
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())
    scale = np.linalg.norm(h, axis=-1) * np.linalg.norm(p, axis=-1)
    res = np.abs(residual(h, p, k, d, S.theta[0])) / scale[:, None]
    assert res[S.ok].max() < 1e-9
    assert (ok_count(S) == 2).mean() > 0.99          # a tangent is rare


def test_cos_sin_are_those_of_theta():
    rng = np.random.default_rng(106)
    h, p, k, d, _ = known_answers(rng, N_DRAWS)
    S = sp4(h, p, k, d)
    ok = S.ok
    assert np.abs(S.c[0][ok] - np.cos(S.theta[0][ok])).max() <= 1e-12
    assert np.abs(S.s[0][ok] - np.sin(S.theta[0][ok])).max() <= 1e-12


# --- 2. least squares --------------------------------------------------------

@pytest.mark.parametrize("side", [1, -1])
def test_least_squares_is_the_closest_angle(side):
    """``d`` beyond ``|h| |p|`` (out of reach): one slot, not exact, the extreme of
    ``h . R p`` on ``d``'s side: minimum of the residual over a dense scan."""
    rng = np.random.default_rng(304)
    n = 200
    h, k, p = rng.normal(size=(n, 3)), unit(rng, n), rng.normal(size=(n, 3))
    d = side * np.linalg.norm(h, axis=-1) * np.linalg.norm(p, axis=-1) * rng.uniform(1.01, 3, n)
    S = sp4(h, p, k, d)
    check_sane(S, (n,), 1, 2)
    assert (ok_count(S) == 1).all() and S.ok[:, 0].all()
    assert not S.exact.any() and not S.free.any()
    lo, hi, top = extremes(h, p, k)
    assert np.abs(wrap(S.theta[0][:, 0] - (top if side > 0 else top + PI))).max() < 1e-12
    grid = np.linspace(-PI, PI, 3601)
    for i in range(n):
        def g(t):
            return abs(h[i] @ rot(k[i], t[0]) @ p[i] - d[i])

        theta = S.theta[0][i, 0]
        assert is_local_minimum(g, [theta])
        assert g([theta]) <= np.abs(h[i] @ turn(k[i], grid, p[i]).T - d[i]).min() + 1e-12


def test_least_squares_just_out_of_reach():
    """``d`` a little beyond the range ``[C - r, C + r]`` (not beyond ``|h| |p|``)."""
    rng = np.random.default_rng(305)
    n = 500
    h, k, p = rng.normal(size=(n, 3)), unit(rng, n), rng.normal(size=(n, 3))
    lo, hi, top = extremes(h, p, k)
    above = rng.random(n) < 0.5
    gap = (hi - lo) * rng.uniform(1e-6, 0.5, n)
    d = np.where(above, hi + gap, lo - gap)
    S = sp4(h, p, k, d)
    assert (ok_count(S) == 1).all() and not S.exact.any() and not S.free.any()
    expected = np.where(above, top, top + PI)
    assert np.abs(wrap(S.theta[0][:, 0] - expected)).max() < 1e-9


# --- 3. ill-posed cases ------------------------------------------------------

@pytest.mark.parametrize("h, p, d, exact", [
    (2 * Z, [1, 1, 3], 6.0, True),      # h along k: h . R p = (h . k)(k . p) = 6 always
    (2 * Z, [1, 1, 3], 5.0, False),
    ([1, 1, 1], [0, 0, 3], 3.0, True),  # p on the axis
    ([1, 1, 1], [0, 0, 3], -3.0, False),
    ([0, 0, 0], [1, 2, 3], 0.0, True),  # h zero
    ([1, 2, 3], [0, 0, 0], 0.0, True),  # p zero
    ([0, 0, 0], [0, 0, 0], 0.0, True),  # both zero
    ([1, 2, 3], [0, 0, 0], 1.0, False),
])
def test_h_along_k_or_p_on_the_axis_is_free_with_theta_0(h, p, d, exact):
    S = sp4(h, p, Z, d)
    check_sane(S, (), 1, 2)
    assert S.ok.tolist() == [True, False] and S.free.all()
    assert S.exact[0] == exact
    assert (S.theta[0][0], S.c[0][0], S.s[0][0]) == (0.0, 1.0, 0.0)


@pytest.mark.parametrize("miss, reach, exact", [(0.0, None, True), (3e-7, None, False),
                                               (3e-7, 1e-6, True), (1e-5, 1e-6, False)])
def test_a_free_problem_is_solved_to_its_free_reach(miss, reach, exact):
    """p on the axis (every angle gives h . p = 3) and d off by ``miss`` of the scale: solved
    to 1e-9 of it, or to a caller's ``free_reach`` (a point put on the axis by a double root
    before is off it by up to ~2e-7 of the arm's size); far beyond that no angle does."""
    from kincalc.subproblems.sp4 import coefficients, from_abc
    A, B, C = coefficients(np.array([1.0, 1, 1]), np.array([0.0, 0, 3]), Z)
    kw = {} if reach is None else {"free_reach": reach}
    S = from_abc(A, B, C, 3.0 + miss * 3 * np.sqrt(3), 3 * np.sqrt(3), **kw)
    assert S.free[0] and S.exact[0] == exact


def test_nearly_along_k_within_tol_is_free():
    assert sp4([1e-13, 0, 1], [1, 0, 1], Z, 1.0).free[0]
    assert not sp4([1e-9, 0, 1], [1, 0, 1], Z, 1.0).free[0]


# --- the tangent -------------------------------------------------------------

def test_tangent_gives_one_solution():
    S = sp4(X, X, Z, 1.0)
    assert S.rows() == [(0.0,)] and S.exact[0] and not S.free[0]
    S = sp4(X, X, Z, -1.0)                   # pi once, not pi and -pi
    assert S.rows() == [(PI,)] and S.exact[0] and not S.free[0]


@pytest.mark.parametrize("end", ["top", "bottom"])
def test_random_tangents_give_one_double_root(end):
    """``d`` at an end of the range, within rounding: one solution, exact, the
    extreme angle to about sqrt(rounding)."""
    rng = np.random.default_rng(307)
    n = 2000
    h, p, k, _, _ = known_answers(rng, n)
    lo, hi, top = extremes(h, p, k)
    S = sp4(h, p, k, hi if end == "top" else lo)
    check_sane(S, (n,), 1, 2)
    assert (ok_count(S) == 1).all() and S.exact[:, 0].all() and not S.free.any()
    expected = top if end == "top" else top + PI
    assert np.abs(wrap(S.theta[0][:, 0] - expected)).max() < 1e-7


def test_inside_the_tangent_by_more_than_rounding_gives_two_solutions():
    rng = np.random.default_rng(308)
    n = 2000
    h, p, k, _, _ = known_answers(rng, n)
    lo, hi, _ = extremes(h, p, k)
    d = hi - (hi - lo) * 1e-8
    S = sp4(h, p, k, d)
    assert (ok_count(S) == 2).all() and S.exact.all()
    scale = np.linalg.norm(h, axis=-1) * np.linalg.norm(p, axis=-1)
    assert (np.abs(residual(h, p, k, d, S.theta[0])) / scale[:, None]).max() < 1e-12


def test_scale_sets_the_tolerances():
    # h = 0: h . R p = 0 for every angle; a d of 1e-17 is rounding of terms of size 1
    # (a law of cosines) only if the caller says so
    assert not sp4(np.zeros(3), X, Z, 1e-17).exact[0]
    assert sp4(np.zeros(3), X, Z, 1e-17, scale=1.0).exact[0]
    # cos t = 1 + 1e-8: beyond the tangent by more than REACH of 1, within REACH of 1e3
    assert not sp4(X, X, Z, 1 + 1e-8).exact[0]
    S = sp4(X, X, Z, 1 + 1e-8, scale=1e3)
    assert S.exact[0] and S.rows() == [(0.0,)]
    # within REACH of the tangent: its double root (the IK's FK check decides)
    S = sp4(X, X, Z, 1 + 1e-10)
    assert S.exact[0] and S.rows() == [(0.0,)]


# --- 4. golden cases ---------------------------------------------------------

def test_golden_thirty_degrees():
    # e_y . R_z(t) e_x = sin t = 1/2
    S = sp4(Y, X, Z, 0.5)
    assert S.exact.all() and not S.free.any()
    assert sorted(t for (t,) in S.rows()) == pytest.approx([PI / 6, 5 * PI / 6], abs=1e-15)


def test_golden_from_coefficients():
    # cos t = 1/2; 3 sin t + 1 = 4 (tangent); cos t + 5 = 7 (out of reach); 0 = 1
    S = from_abc([1.0, 0.0, 1.0, 0.0], [0.0, 3.0, 0.0, 0.0], [0.0, 1.0, 5.0, 0.0],
                 [0.5, 4.0, 7.0, 1.0], 1.0)
    check_sane(S, (4,), 1, 2)
    assert sorted(t for (t,) in S.rows(0)) == pytest.approx([-PI / 3, PI / 3], abs=1e-15)
    assert S.rows(1) == [(pytest.approx(PI / 2, abs=1e-15),)] and S.exact[1, 0]
    assert S.rows(2) == [(0.0,)] and not S.exact[2].any() and not S.free[2].any()
    assert S.rows(3) == [(0.0,)] and S.free[3].all() and not S.exact[3].any()


@pytest.mark.parametrize("d", [0.0, -0.0])
@pytest.mark.parametrize("h, p, k", [(-Y, -X, -Z), (Y, X, Z), (-Y, X, Z), (Y, -X, -Z)])
def test_golden_half_turn_is_pi_not_minus_pi(h, p, k, d):
    # h . R p = 0 with h across p: 0 and pi (arctan2 of a sine of -0 gave -pi)
    S = sp4(h, p, k, d)
    assert sorted(abs(t) for (t,) in S.rows()) == [0.0, PI]
    assert max(t for (t,) in S.rows()) == PI


# --- 5. shapes ---------------------------------------------------------------

def mixed_batch(rng, k=None):
    """``LEAD`` problems: solvable, out of reach, free and tangent ones."""
    n = int(np.prod(LEAD))
    h, p, k, d, _ = known_answers(rng, n, k)
    h, p, d = h.copy(), p.copy(), d.copy()
    d[1::5] = 2 * np.linalg.norm(h[1::5], axis=-1) * np.linalg.norm(p[1::5], axis=-1)
    h[2::5] = -3 * k[2::5]
    d[3::5] = extremes(h[3::5], p[3::5], k[3::5])[1]
    return [a.reshape(LEAD + a.shape[1:]) for a in (h, p, np.broadcast_to(k, (n, 3)), d)]


def test_batch_shapes_agree_with_each_problem_alone():
    rng = np.random.default_rng(501)
    S = check_batching(sp4, mixed_batch(rng), 1, 2)
    assert S.free.any() and not S.exact.all() and (ok_count(S) == 1).any()


def test_a_shared_axis_broadcasts_against_per_problem_points():
    rng = np.random.default_rng(502)
    k = unit(rng)
    check_batching(sp4, mixed_batch(rng, k), 1, 2, shared={2: k})


def test_one_geometry_against_many_components():
    # d (3,) against vectors (3,): sin t = 1/2, 0, 1
    S = sp4(Y, X, Z, [0.5, 0.0, 1.0])
    check_sane(S, (3,), 1, 2)
    assert sorted(t for (t,) in S.rows(1)) == pytest.approx([0.0, PI], abs=1e-15)
    assert S.rows(2) == [(pytest.approx(PI / 2),)]


# --- two equations of one angle ------------------------------------------------

def test_shared_roots_the_common_root_first():
    """Two equations that share a root (and one other each): the shared one in slot 0,
    whichever equation is solved; every root solves the equation it came from."""
    from kincalc.subproblems.sp4 import shared_roots
    rng = np.random.default_rng(41)
    n = 2000
    t = rng.uniform(-PI, PI, n)
    A, B = rng.normal(size=(2, 2, n))
    C = -(A * np.cos(t) + B * np.sin(t))                       # both vanish at t
    sol = shared_roots(A, B, C, (1.0, 1.0))
    assert (np.abs(wrap(sol.theta[0][:, 0] - t)) < ANGLE_TOL).all()
    assert sol.exact.all()


def test_shared_roots_of_nearly_proportional_equations_keep_both():
    """Nearly proportional equations (the invariants of a point turned about two nearly
    parallel axes) hold at both roots: both are kept (a 2 x 2 solve kept one, 0.1 off)."""
    from kincalc.subproblems.sp4 import shared_roots
    rng = np.random.default_rng(42)
    n = 500
    t1, t2 = rng.uniform(-PI, PI, (2, n))
    # an equation with roots t1 and t2, and 0.3 times it perturbed by 1e-7
    A, B = np.cos((t1 + t2) / 2), np.sin((t1 + t2) / 2)
    C = -np.cos((t1 - t2) / 2)
    eps = 1e-7 * rng.normal(size=(3, n))
    sol = shared_roots([A, 0.3 * A + eps[0]], [B, 0.3 * B + eps[1]], [C, 0.3 * C + eps[2]],
                       (1.0, 1.0))
    assert sol.ok.all()
    got = np.sort(wrap(sol.theta[0] - t1[:, None]), -1)
    want = np.sort(np.stack([np.zeros(n), wrap(t2 - t1)], -1), -1)
    assert np.abs(got - want).max() < 1e-6


def test_shared_roots_compares_dependence_in_each_equations_unit():
    """An equation in m^2 against one in m: the one that depends on the angle the most,
    measured in its unit, is solved (a height of 0.01 m against a distance^2 of 0.5 m^2 at
    an arm's size of 0.1 m: the distance)."""
    from kincalc.subproblems.sp4 import shared_roots
    t = 0.7
    A = np.array([0.01, 0.5])
    B = np.array([0.0, 0.2])
    C = -(A * np.cos(t) + B * np.sin(t))
    sol = shared_roots(A, B, C, (0.1, 0.01))
    base = np.arctan2(0.2, 0.5)
    assert abs(wrap(sol.theta[0][0] - t)) < 1e-12
    assert abs(wrap(sol.theta[0][1] - (2 * base - t))) < 1e-12   # the distance's other root
