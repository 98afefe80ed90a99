"""Subproblem 3, ``|R(k, theta) p1 - p2| = d``: known answers, least squares, ill-posed
cases, golden values, batch shapes (see tests/subproblem_checks.py)."""

import math

import numpy as np
import pytest

from kincalc.subproblems import sp3
from subproblem_checks import (LEAD, PI, X, Z, check_batching, check_sane, is_local_minimum,
                               lengths, nearest_error, ok_count, rot, turn, unit, wrap)

N_DRAWS = 5000
ANGLE_TOL = 1e-7   # rad


def known_answers(rng, n, k=None):
    """``(p1, p2, k, d, theta)`` of n solvable problems (one shared axis if given)."""
    k = unit(rng, n) if k is None else np.broadcast_to(k, (n, 3))
    P = lengths(rng, n, 2)
    p1, p2, t = P[:, 0], P[:, 1], rng.uniform(-PI, PI, n)
    return p1, p2, k, np.linalg.norm(turn(k, t, p1) - p2, axis=-1), t


def distances(p1, p2, k, theta):
    """``|R(k, theta) p1 - p2| (..., m)`` for angles ``theta (..., m)``."""
    return np.linalg.norm(turn(k[..., None, :], theta, p1[..., None, :]) - p2[..., None, :],
                          axis=-1)


# --- 1. known answers --------------------------------------------------------

def test_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(103)
    p1, p2, k, d, t = known_answers(rng, N_DRAWS)
    S = sp3(p1, p2, k, d)
    check_sane(S, (N_DRAWS,), 1, 2)
    assert S.ok[:, 0].all() and S.exact.all() and not S.free.any()
    err = nearest_error(S, t[:, None])
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())
    size = (p1 * p1).sum(-1) + (p2 * p2).sum(-1)
    res = np.abs(distances(p1, p2, k, S.theta[0]) ** 2 - d[:, None] ** 2) / size[:, None]
    assert res[S.ok].max() < 1e-12


def test_cos_sin_are_those_of_theta():
    rng = np.random.default_rng(106)
    S = sp3(*known_answers(rng, N_DRAWS)[:4])
    ok = S.ok
    assert np.abs(S.c[0][ok] - np.cos(S.theta[0][ok])).max() <= 1e-12
    assert np.abs(S.s[0][ok] - np.sin(S.theta[0][ok])).max() <= 1e-12


# --- 2. least squares --------------------------------------------------------

@pytest.mark.parametrize("reach", ["too far", "too near", "zero"])
def test_least_squares_is_the_nearest_or_farthest_point(reach):
    """No point of the circle at distance ``d``: one slot, not exact, the angle of the
    circle's farthest (too far) or nearest (too near) point: the minimum of
    ``| |R p1 - p2| - d |`` over a dense scan, and a local minimum."""
    rng = np.random.default_rng(303)
    n = 200
    k, p1, p2 = unit(rng, n), rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    grid = np.linspace(-PI, PI, 3601)
    scan = distances(p1, p2, k, np.broadcast_to(grid, (n, len(grid))))
    near, far = scan.min(-1), scan.max(-1)
    d = {"too far": far * rng.uniform(1.01, 3, n), "too near": near * rng.uniform(0.0, 0.99, n),
         "zero": np.zeros(n)}[reach]
    S = sp3(p1, p2, k, d)
    check_sane(S, (n,), 1, 2)
    assert (ok_count(S) == 1).all() and S.ok[:, 0].all()
    assert not S.exact.any() and not S.free.any()
    best = distances(p1, p2, k, S.theta[0][:, :1])[:, 0]
    if reach == "too far":      # at least as far as the scan's farthest point
        assert (best >= far * (1 - 1e-12)).all() and (best <= far * (1 + 1e-4)).all()
    else:
        assert (best <= near * (1 + 1e-12)).all() and (best >= near * (1 - 1e-4)).all()
    for i in range(n):
        def g(t):
            return abs(np.linalg.norm(rot(k[i], t[0]) @ p1[i] - p2[i]) - d[i])

        assert is_local_minimum(g, [S.theta[0][i, 0]])
        assert g([S.theta[0][i, 0]]) <= np.abs(scan[i] - d[i]).min() + 1e-12


# --- 3. ill-posed cases ------------------------------------------------------

@pytest.mark.parametrize("p1, p2, d, exact", [
    # the distance from p2 = (1, 0, 0) to a point on the axis does not change
    ([0, 0, 2], X, math.sqrt(5), True),
    ([0, 0, 2], X, math.sqrt(5) + 1, False),
    # nor the distance of a circle about the axis from a point p2 on it
    (X, [0, 0, 2], math.sqrt(5), True),
    (X, [0, 0, 2], 1.0, False),
    ([0, 0, 0], [0, 0, 0], 0.0, True),
])
def test_a_point_on_the_axis_is_free_with_theta_0(p1, p2, d, exact):
    S = sp3(p1, p2, Z, d)
    check_sane(S, (), 1, 2)
    assert S.ok.tolist() == [True, False] and S.free.all() and S.exact[0] == exact
    assert S.theta[0][0] == 0.0


def test_centre_at_the_origin_is_free_and_exact():
    """``p2 = 0``: every angle is at distance ``|p1|``; ``d`` computed with rounding
    (``|R p1|``) is still exact (it was not: the tolerance was relative to the
    target, itself a rounding error)."""
    rng = np.random.default_rng(304)
    n = 500
    p1, _, k, _, t = known_answers(rng, n)
    S = sp3(p1, np.zeros(3), k, np.linalg.norm(turn(k, t, p1), axis=-1))
    check_sane(S, (n,), 1, 2)
    assert S.ok[:, 0].all() and S.free.all() and S.exact[:, 0].all()


@pytest.mark.parametrize("sizes", [(1e3, 1e-3), (1e-3, 1e3), (1.0, 1.0)])
@pytest.mark.parametrize("end", ["far", "near"])
def test_tangent_between_lengths_of_different_sizes(sizes, end):
    """``d`` the circle's largest or smallest distance from ``p2``: one exact root, the
    extreme point, to about sqrt(rounding of |p1|^2 + |p2|^2) over ``|p1| |p2|`` (it
    was flagged not exact, or split in two, for lengths of different sizes: the
    tolerances were relative to ``|p1| |p2|``)."""
    rng = np.random.default_rng(305)
    n = 2000
    k = unit(rng, n)
    p1, p2 = rng.normal(size=(n, 3)) * sizes[0], rng.normal(size=(n, 3)) * sizes[1]
    h1, h2 = (p1 * k).sum(-1), (p2 * k).sum(-1)
    a1, a2 = p1 - h1[:, None] * k, p2 - h2[:, None] * k
    r1, r2 = np.linalg.norm(a1, axis=-1), np.linalg.norm(a2, axis=-1)
    d = np.hypot(h1 - h2, r1 + r2 if end == "far" else r1 - r2)
    # the angle turning a1 against (far) or along (near) a2
    target = -a2 if end == "far" else a2
    extreme = np.arctan2((np.cross(a1, target) * k).sum(-1), (a1 * target).sum(-1))
    S = sp3(p1, p2, k, d)
    check_sane(S, (n,), 1, 2)
    assert (ok_count(S) == 1).all() and S.exact[:, 0].all() and not S.free.any()
    ratio = max(sizes) / min(sizes)
    err = np.abs(wrap(S.theta[0][:, 0] - extreme))
    assert err.max() < 1e-7 * ratio ** 0.5, err.max()


# --- 4. golden cases ---------------------------------------------------------

def test_golden_distance_sqrt2():
    # |R_z(t) e_x - e_x|^2 = 2 - 2 cos t = 2
    S = sp3(X, X, Z, math.sqrt(2))
    assert S.exact.all() and not S.free.any()
    assert sorted(t for (t,) in S.rows()) == pytest.approx([-PI / 2, PI / 2], abs=1e-15)


@pytest.mark.parametrize("d, theta", [(2.0, PI), (0.0, 0.0)])
def test_golden_tangent_gives_one_solution(d, theta):
    # the farthest and the nearest point of the unit circle from e_x
    S = sp3(X, X, Z, d)
    assert S.rows() == [(theta,)] and S.exact[0] and not S.free[0]


def test_golden_above_the_plane():
    # |R_z(t) (1, 0, 1) - (0, 2, 0)|^2 = 1 + 1 + 4 - 4 sin t = 4: sin t = 1/2
    S = sp3([1, 0, 1], [0, 2, 0], Z, 2.0)
    assert S.exact.all()
    assert sorted(t for (t,) in S.rows()) == pytest.approx([PI / 6, 5 * PI / 6], abs=1e-15)


# --- 5. shapes ---------------------------------------------------------------

def mixed_batch(rng, k=None):
    """``LEAD`` problems: solvable ones, out of reach ones and a point on the axis."""
    n = int(np.prod(LEAD))
    p1, p2, k, d, _ = known_answers(rng, n, k)
    p1, d = p1.copy(), d.copy()
    d[1::5] = 3 * (np.linalg.norm(p1[1::5], axis=-1) + np.linalg.norm(p2[1::5], axis=-1))
    p1[2::5] = 0.5 * k[2::5]
    return [a.reshape(LEAD + a.shape[1:]) for a in (p1, p2, np.broadcast_to(k, (n, 3)), d)]


def test_batch_shapes_agree_with_each_problem_alone():
    rng = np.random.default_rng(501)
    S = check_batching(sp3, mixed_batch(rng), 1, 2)
    assert S.free.any() and not S.exact.all()


def test_a_shared_axis_broadcasts_against_per_problem_points():
    rng = np.random.default_rng(502)
    k = unit(rng)
    check_batching(sp3, mixed_batch(rng, k), 1, 2, shared={2: k})


def test_one_geometry_against_many_distances():
    S = sp3(X, X, Z, [math.sqrt(2), 2.0, 3.0])
    check_sane(S, (3,), 1, 2)
    assert sorted(t for (t,) in S.rows(0)) == pytest.approx([-PI / 2, PI / 2], abs=1e-15)
    assert S.rows(1) == [(PI,)] and S.exact[1, 0]
    assert S.rows(2) == [(PI,)] and not S.exact[2, 0]
