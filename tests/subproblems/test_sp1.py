"""Subproblem 1, ``R(k, theta) p1 = p2``: known answers, least squares, ill-posed cases,
golden values, batch shapes (see tests/subproblem_checks.py)."""

import numpy as np
import pytest

import kincalc.subproblems as subproblems
from kincalc.subproblems import sp1
from subproblem_checks import (LEAD, PI, X, Y, Z, check_batching, check_sane, is_local_minimum,
                               lengths, nearest_error, rot, turn, unit, wrap)

N_DRAWS = 5000
ANGLE_TOL = 1e-7   # rad


def known_answers(rng, n, k=None):
    """``(p1, p2, k, theta)`` of n solvable problems (one shared axis ``k`` if given)."""
    k = unit(rng, n) if k is None else np.broadcast_to(k, (n, 3))
    p1, t = lengths(rng, n)[:, 0], rng.uniform(-PI, PI, n)
    return p1, turn(k, t, p1), k, t


# --- 1. known answers --------------------------------------------------------

def test_known_answer():
    rng = np.random.default_rng(101)
    p1, p2, k, t = known_answers(rng, N_DRAWS)
    S = sp1(p1, p2, k)
    check_sane(S, (N_DRAWS,), 1, 1)
    assert S.ok.all() and S.exact.all() and not S.free.any()
    err = nearest_error(S, t[:, None])
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())


def test_cos_sin_are_those_of_theta():
    rng = np.random.default_rng(106)
    p1, p2, k, _ = known_answers(rng, N_DRAWS)
    S = sp1(p1, p2, k)
    assert np.abs(S.c[0] - np.cos(S.theta[0])).max() <= 1e-12
    assert np.abs(S.s[0] - np.sin(S.theta[0])).max() <= 1e-12


# --- 2. least squares --------------------------------------------------------

def test_least_squares_is_the_closest_angle():
    """Random points (different heights and distances): not exact, and the angle is
    the minimum of ``|R p1 - p2|`` over a dense scan and a local minimum."""
    rng = np.random.default_rng(301)
    n = 200
    k, p1, p2 = unit(rng, n), rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    S = sp1(p1, p2, k)
    check_sane(S, (n,), 1, 1)
    assert S.ok.all() and not S.exact.any() and not S.free.any()
    grid = np.linspace(-PI, PI, 3601)
    for i in range(n):
        def g(t):
            return np.linalg.norm(rot(k[i], t[0]) @ p1[i] - p2[i])

        theta = S.theta[0][i, 0]
        assert is_local_minimum(g, [theta])
        scan = np.linalg.norm(turn(k[i], grid, p1[i]) - p2[i], axis=-1).min()
        assert g([theta]) <= scan + 1e-12


@pytest.mark.parametrize("miss", ["height", "distance"])
def test_least_squares_when_only_one_condition_fails(miss):
    """Same distance from the axis but another height, or the reverse: the angle
    still turns ``p1`` to ``p2``'s side of the axis."""
    rng = np.random.default_rng(302)
    n = 200
    p1, p2, k, t = known_answers(rng, n)
    if miss == "height":
        p2 = p2 + k * np.linalg.norm(p1, axis=-1, keepdims=True) * rng.uniform(0.1, 2, (n, 1))
    else:
        h = (p2 * k).sum(-1, keepdims=True) * k
        p2 = h + (p2 - h) * rng.uniform(1.1, 3, (n, 1))
    S = sp1(p1, p2, k)
    check_sane(S, (n,), 1, 1)
    assert S.ok.all() and not S.exact.any() and not S.free.any()
    assert np.abs(wrap(S.theta[0][:, 0] - t)).max() < ANGLE_TOL


# --- 3. ill-posed cases ------------------------------------------------------

@pytest.mark.parametrize("p1, p2, exact", [
    ([0, 0, 2], [0, 0, 2], True),      # p1 = p2 on the axis: every angle works
    ([0, 0, 2], [0, 0, 3], False),     # both on the axis, apart: no angle works
    ([1, 0, 0], [0, 0, 1], False),     # p2 on the axis
    ([0, 0, 1], [1, 0, 0], False),     # p1 on the axis
    ([0, 0, 0], [0, 0, 0], True),      # both zero
    ([1e-12, 0, 2], [0, 1e-12, 2], True),  # within tol (1e-9 of the size) of the axis
])
def test_point_on_the_axis_is_free_with_theta_0(p1, p2, exact):
    S = sp1(p1, p2, Z)
    check_sane(S, (), 1, 1)
    assert S.ok[0] and S.free[0] and S.exact[0] == exact
    assert (S.theta[0][0], S.c[0][0], S.s[0][0]) == (0.0, 1.0, 0.0)


def test_off_the_axis_by_more_than_tol_is_not_free():
    S = sp1([1e-6, 0, 2], [0, 1e-6, 2], Z)
    assert not S.free[0] and S.exact[0] and S.theta[0][0] == pytest.approx(PI / 2, abs=1e-12)


# --- 4. golden cases ---------------------------------------------------------

@pytest.mark.parametrize("p1, p2, k, theta", [
    (X, Y, Z, PI / 2),                    # quarter turn
    (Y, X, Z, -PI / 2),
    (X, -X, Z, PI),                       # half turn: pi, not -pi
    (3 * X + Z, 3 * Y + Z, Z, PI / 2),    # above the origin, radius 3
    (Y, Z, X, PI / 2),
    (X, [0.5, 0.5 * 3 ** 0.5, 0], Z, PI / 3),
])
def test_golden(p1, p2, k, theta):
    S = sp1(p1, p2, k)
    assert (S.ok[0], S.exact[0], S.free[0]) == (True, True, False)
    assert S.theta[0][0] == pytest.approx(theta, abs=1e-15)


@pytest.mark.parametrize("p1, p2, k", [(X, -X, Z), (-X, X, -Z), (X, -X, -Z), (-Y, Y, -X)])
def test_golden_half_turn_is_pi_not_minus_pi(p1, p2, k):
    assert sp1(p1, p2, k).rows() == [(PI,)]


# --- 5. shapes ---------------------------------------------------------------

def mixed_batch(rng, k=None):
    """``LEAD`` problems: solvable ones, least-squares ones and points on the axis."""
    n = int(np.prod(LEAD))
    p1, p2, k, _ = known_answers(rng, n, k)
    p2 = p2.copy()
    p2[1::4] += rng.normal(size=(len(p2[1::4]), 3))      # least squares
    p1 = p1.copy()
    p1[2::6] = 2.5 * k[2::6]                               # on the axis
    k = np.broadcast_to(k, (n, 3))
    return [a.reshape(LEAD + (3,)) for a in (p1, p2, k)]


def test_batch_shapes_agree_with_each_problem_alone():
    rng = np.random.default_rng(501)
    S = check_batching(sp1, mixed_batch(rng), 1, 1)
    assert S.exact.any() and not S.exact.all() and S.free.any()


def test_a_shared_axis_broadcasts_against_per_problem_points():
    rng = np.random.default_rng(502)
    k = unit(rng)
    check_batching(sp1, mixed_batch(rng, k), 1, 1, shared={2: k})


@pytest.mark.parametrize("solve", [
    lambda v: subproblems.sp1(v, v, Z), lambda v: subproblems.sp2(X, Y, v, Z),
    lambda v: subproblems.sp3(v, X, Z, 1.0), lambda v: subproblems.sp4(X, v, Z, 1.0),
    lambda v: subproblems.sp5(X, v, X, X, Z, Z, Z)], ids=["sp1", "sp2", "sp3", "sp4", "sp5"])
def test_vectors_not_of_three_components_raise(solve):
    # against 3-vectors: numpy's broadcasting error (a ValueError as well)
    with pytest.raises(ValueError, match="shape"):
        solve(np.ones(2))


def test_vectors_of_two_components_raise_with_the_shape():
    with pytest.raises(ValueError, match=r"expected vectors of shape \(\.\.\., 3\), got \(4, 2\)"):
        sp1(np.ones((4, 2)), np.ones(2), np.ones(2))


def test_package_exports_every_subproblem():
    assert subproblems.__all__ == ["Solutions", "sp1", "sp2", "sp3", "sp4", "sp5", "sp6"]
