"""Geometric subproblems sp1-sp6: known answers, least squares, ill-posed cases, golden values.

Known answers: random unit axes, points and true angles from a seeded
generator (lengths spread over six orders of magnitude), the subproblem's
inputs built from them, and the true angles must be among the outputs
(modulo 2 pi). Rotations here come from :func:`kincalc.spatial.matrix_from_axis_angle`,
not from the subproblem modules.
"""

import math

import numpy as np
import pytest

from kincalc.spatial import matrix_from_axis_angle
from kincalc.subproblems import sp1, sp2, sp3, sp4, sp5, sp6

N_DRAWS = 2000
ANGLE_TOL = 1e-7          # rad, known answers of sp1-sp4
ANGLE_TOL_QUARTIC = 1e-7  # rad, known answers of sp5-sp6

X, Y, Z = np.eye(3)
PI = math.pi


def rot(k, t):
    return matrix_from_axis_angle(k, t)


def unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def lengths(rng, n, m=3):
    """n vectors of m random points each, every draw with its own scale 1e-3..1e3."""
    return rng.normal(size=(n, m, 3)) * 10.0 ** rng.uniform(-3, 3, (n, 1, 1))


def angle_error(a, b):
    return abs(math.remainder(a - b, 2 * PI))


def error_to_nearest(true, solutions):
    """Largest component error of the solution nearest to ``true`` (inf if none)."""
    true = np.atleast_1d(true)
    return min((max(angle_error(s, t) for s, t in zip(np.atleast_1d(sol), true))
                for sol in solutions), default=math.inf)


def all_finite(solutions):
    return all(np.all(np.isfinite(np.atleast_1d(s))) for s in solutions)


def sp4_residual(h, p, k, d, t):
    return h @ rot(k, t) @ p - d


def sp5_residual(p0, p1, p2, p3, k1, k2, k3, t):
    return np.linalg.norm(p0 + rot(k1, t[0]) @ p1 - rot(k2, t[1]) @ (p2 + rot(k3, t[2]) @ p3))


def sp6_residual(h, k, p, d1, d2, t):
    e1 = h[0] @ rot(k[0], t[0]) @ p[0] + h[1] @ rot(k[1], t[1]) @ p[1] - d1
    e2 = h[2] @ rot(k[2], t[0]) @ p[2] + h[3] @ rot(k[3], t[1]) @ p[3] - d2
    return np.array([e1, e2])


def report(failures):
    return f"{len(failures)} of {N_DRAWS} draws failed; first: {failures[:3]}"


# --- 1. known answers --------------------------------------------------------

def test_sp1_known_answer():
    rng = np.random.default_rng(101)
    k, P, t = unit(rng, N_DRAWS), lengths(rng, N_DRAWS, 1)[:, 0], rng.uniform(-PI, PI, N_DRAWS)
    P2 = np.einsum("nij,nj->ni", rot(k, t), P)
    failures = []
    for i in range(N_DRAWS):
        theta, exact, free = sp1(P[i], P2[i], k[i])
        if not (exact and not free and angle_error(theta, t[i]) < ANGLE_TOL):
            failures.append((i, theta, t[i], exact, free))
    assert not failures, report(failures)


def test_sp2_known_answer():
    rng = np.random.default_rng(102)
    k1, k2 = unit(rng, N_DRAWS), unit(rng, N_DRAWS)
    P, t = lengths(rng, N_DRAWS, 1)[:, 0], rng.uniform(-PI, PI, (N_DRAWS, 2))
    P2 = np.einsum("nij,njk,nk->ni", rot(k1, t[:, 0]), rot(k2, t[:, 1]), P)
    failures = []
    for i in range(N_DRAWS):
        sols, exact, free = sp2(P[i], P2[i], k1[i], k2[i])
        err = error_to_nearest(t[i], sols)
        if not (exact and not free and err < ANGLE_TOL and all_finite(sols)
                and 1 <= len(sols) <= 2):
            failures.append((i, err, exact, free))
    assert not failures, report(failures)


def test_sp3_known_answer():
    rng = np.random.default_rng(103)
    k, (P1, P2), t = unit(rng, N_DRAWS), lengths(rng, N_DRAWS, 2).transpose(1, 0, 2), \
        rng.uniform(-PI, PI, N_DRAWS)
    d = np.linalg.norm(np.einsum("nij,nj->ni", rot(k, t), P1) - P2, axis=1)
    failures = []
    for i in range(N_DRAWS):
        thetas, exact, free = sp3(P1[i], P2[i], k[i], d[i])
        err = error_to_nearest(t[i], thetas)
        if not (exact and not free and err < ANGLE_TOL and all_finite(thetas)):
            failures.append((i, err, exact, free))
    assert not failures, report(failures)


def test_sp4_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(104)
    h, k = unit(rng, N_DRAWS) * rng.uniform(0.1, 10, (N_DRAWS, 1)), unit(rng, N_DRAWS)
    P, t = lengths(rng, N_DRAWS, 1)[:, 0], rng.uniform(-PI, PI, N_DRAWS)
    d = np.einsum("ni,nij,nj->n", h, rot(k, t), P)
    failures = []
    for i in range(N_DRAWS):
        thetas, exact, free = sp4(h[i], P[i], k[i], d[i])
        err = error_to_nearest(t[i], thetas)
        scale = np.linalg.norm(h[i]) * np.linalg.norm(P[i])
        worst = max(abs(sp4_residual(h[i], P[i], k[i], d[i], th)) for th in thetas)
        if not (exact and not free and err < ANGLE_TOL and worst < 1e-9 * scale):
            failures.append((i, err, worst / scale, exact, free))
    assert not failures, report(failures)


def test_sp5_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(105)
    ks = unit(rng, 3 * N_DRAWS).reshape(N_DRAWS, 3, 3)
    P = lengths(rng, N_DRAWS, 3)
    t = rng.uniform(-PI, PI, (N_DRAWS, 3))
    counts = np.zeros(5, int)
    failures = []
    for i in range(N_DRAWS):
        (k1, k2, k3), (p1, p2, p3) = ks[i], P[i]
        p0 = rot(k2, t[i, 1]) @ (p2 + rot(k3, t[i, 2]) @ p3) - rot(k1, t[i, 0]) @ p1
        sols, exact, free = sp5(p0, p1, p2, p3, k1, k2, k3)
        L = max(np.linalg.norm(v) for v in (p0, p1, p2, p3))
        err = error_to_nearest(t[i], sols)
        worst = max(sp5_residual(p0, p1, p2, p3, k1, k2, k3, s) for s in sols)
        if not (exact and not free and err < ANGLE_TOL_QUARTIC and worst < 1e-9 * L
                and len(sols) <= 4):
            failures.append((i, err, worst / L, exact, free))
        counts[min(len(sols), 4)] += 1
    assert not failures, report(failures)
    # the quartic's real roots come in pairs: 2 or 4 solutions, and both occur
    assert counts[0] == counts[1] == counts[3] == 0 and counts[2] > 0 and counts[4] > 0


def test_sp6_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(106)
    H = unit(rng, 4 * N_DRAWS).reshape(N_DRAWS, 4, 3) * rng.uniform(0.1, 10, (N_DRAWS, 4, 1))
    K = unit(rng, 4 * N_DRAWS).reshape(N_DRAWS, 4, 3)
    P = lengths(rng, N_DRAWS, 4)
    t = rng.uniform(-PI, PI, (N_DRAWS, 2))
    counts = np.zeros(5, int)
    failures = []
    for i in range(N_DRAWS):
        h, k, p = H[i], K[i], P[i]
        d1, d2 = sp6_residual(h, k, p, 0.0, 0.0, t[i])
        sols, exact, free = sp6(h, k, p, d1, d2)
        scale = max(np.linalg.norm(h[j]) * np.linalg.norm(p[j]) for j in range(4))
        err = error_to_nearest(t[i], sols)
        worst = max(np.max(np.abs(sp6_residual(h, k, p, d1, d2, s))) for s in sols)
        if not (exact and not free and err < ANGLE_TOL_QUARTIC and worst < 1e-9 * scale
                and len(sols) <= 4):
            failures.append((i, err, worst / scale, exact, free))
        counts[min(len(sols), 4)] += 1
    assert not failures, report(failures)
    assert counts[0] == counts[1] == counts[3] == 0 and counts[2] > 0 and counts[4] > 0


# --- completeness: an independent search finds no solution the solver missed --

def _grid_newton(F, n_unknowns, grid, keep, iters=25):
    """Zeros of F: R^n -> R^n reached by Newton's method from the best grid points.

    Returns the end points (m, n) and their residual norms (m,).
    """
    axes = np.linspace(-PI, PI, grid, endpoint=False)
    x = np.stack(np.meshgrid(*[axes] * n_unknowns, indexing="ij"), -1).reshape(-1, n_unknowns)
    x = x[np.argsort(np.linalg.norm(F(x), axis=-1))[:keep]]
    eye = 1e-7 * np.eye(n_unknowns)
    for _ in range(iters):
        f = F(x)
        J = np.stack([(F(x + e) - F(x - e)) / 2e-7 for e in eye], axis=-1)
        x = x - np.einsum("nij,nj->ni", np.linalg.pinv(J), f)
    return x, np.linalg.norm(F(x), axis=-1)


def test_sp6_finds_every_solution_an_independent_search_finds():
    rng = np.random.default_rng(206)
    zeros_seen = 0
    for _ in range(25):
        h, k, p = rng.normal(size=(4, 3)), unit(rng, 4), rng.normal(size=(4, 3))
        d1, d2 = rng.normal(size=2)  # random: solvable or not

        def F(T):
            R1, R2 = rot(k[[0, 2]][None], T[:, :1]), rot(k[[1, 3]][None], T[:, 1:])
            a = np.einsum("mi,nmij,mj->nm", h[[0, 2]], R1, p[[0, 2]])
            b = np.einsum("mi,nmij,mj->nm", h[[1, 3]], R2, p[[1, 3]])
            return a + b - [d1, d2]

        sols, exact, free = sp6(h, k, p, d1, d2)
        assert not free and exact == bool(sols)
        for x, res in zip(*_grid_newton(F, 2, grid=64, keep=200)):
            if res < 1e-10:
                zeros_seen += 1
                assert error_to_nearest(x, sols) < 1e-6, (x, sols)
    assert zeros_seen > 0  # the search is not vacuous


def test_sp5_finds_every_solution_an_independent_search_finds():
    rng = np.random.default_rng(205)
    zeros_seen = 0
    for _ in range(12):
        p0, p1, p2, p3 = rng.normal(size=(4, 3))
        k1, k2, k3 = unit(rng, 3)

        def F(T):
            lhs = p0 + np.einsum("nij,j->ni", rot(k1, T[:, 0]), p1)
            inner = p2 + np.einsum("nij,j->ni", rot(k3, T[:, 2]), p3)
            return lhs - np.einsum("nij,nj->ni", rot(k2, T[:, 1]), inner)

        sols, exact, free = sp5(p0, p1, p2, p3, k1, k2, k3)
        assert not free and exact == bool(sols)
        for x, res in zip(*_grid_newton(F, 3, grid=24, keep=400)):
            if res < 1e-10:
                zeros_seen += 1
                assert error_to_nearest(x, sols) < 1e-6, (x, sols)
    assert zeros_seen > 0  # the search is not vacuous


# --- 2. least squares --------------------------------------------------------

def is_local_minimum(g, theta, steps=(1e-2, 1e-4, 1e-6)):
    g0 = g(theta)
    return all(g(theta + s) >= g0 - 1e-12 * (1 + abs(g0)) and
               g(theta - s) >= g0 - 1e-12 * (1 + abs(g0)) for s in steps)


def test_sp1_least_squares_is_the_closest_angle():
    rng = np.random.default_rng(301)
    grid = np.linspace(-PI, PI, 3601)
    for _ in range(200):
        k, p1, p2 = unit(rng, 1)[0], rng.normal(size=3), rng.normal(size=3)
        theta, exact, free = sp1(p1, p2, k)
        assert not exact and not free

        def g(t):
            return np.linalg.norm(rot(k, t) @ p1 - p2)

        assert is_local_minimum(g, theta)
        assert g(theta) <= np.min(np.linalg.norm(rot(k, grid) @ p1 - p2, axis=1)) + 1e-12


@pytest.mark.parametrize("reach", ["too far", "too near"])
def test_sp3_least_squares_is_a_local_minimum(reach):
    rng = np.random.default_rng(303)
    for _ in range(200):
        k, p1, p2 = unit(rng, 1)[0], rng.normal(size=3), rng.normal(size=3)
        # |R p1 - p2| <= |p1| + |p2| always, and is > 0 off a measure-zero set
        d = 0.0
        if reach == "too far":
            d = (np.linalg.norm(p1) + np.linalg.norm(p2)) * rng.uniform(1.01, 3)
        thetas, exact, free = sp3(p1, p2, k, d)
        assert not exact and not free and len(thetas) == 1

        def g(t):
            return abs(np.linalg.norm(rot(k, t) @ p1 - p2) - d)

        assert is_local_minimum(g, thetas[0])


def test_sp4_least_squares_is_the_closest_angle():
    rng = np.random.default_rng(304)
    grid = np.linspace(-PI, PI, 3601)
    for _ in range(200):
        h, k, p = rng.normal(size=3), unit(rng, 1)[0], rng.normal(size=3)
        # |h . R p| <= |h| |p|, so this d is out of reach
        d = np.linalg.norm(h) * np.linalg.norm(p) * rng.uniform(1.01, 3) * rng.choice([-1, 1])
        thetas, exact, free = sp4(h, p, k, d)
        assert not exact and not free and len(thetas) == 1

        def g(t):
            return abs(sp4_residual(h, p, k, d, t))

        assert is_local_minimum(g, thetas[0])
        assert g(thetas[0]) <= np.min(np.abs(h @ rot(k, grid) @ p - d)) + 1e-12


def test_sp2_flags_unequal_norms_as_not_exact():
    rng = np.random.default_rng(302)
    for _ in range(200):
        k1, k2 = unit(rng, 2)
        p1 = rng.normal(size=3)
        p2 = rng.normal(size=3)
        p2 *= np.linalg.norm(p1) * rng.choice([0.5, 2.0]) / np.linalg.norm(p2)
        sols, exact, free = sp2(p1, p2, k1, k2)
        assert not exact and sols and all_finite(sols)


def test_sp5_out_of_reach_gives_no_solution():
    rng = np.random.default_rng(305)
    for _ in range(200):
        p1, p2, p3 = rng.normal(size=(3, 3))
        k1, k2, k3 = unit(rng, 3)
        # |p0 + R1 p1| >= |p0| - |p1| > |p2| + |p3| >= |right side|
        p0 = unit(rng, 1)[0] * (sum(np.linalg.norm(v) for v in (p1, p2, p3)) + rng.uniform(0.1, 5))
        assert sp5(p0, p1, p2, p3, k1, k2, k3) == ([], False, False)


def test_sp6_out_of_reach_gives_no_solution():
    rng = np.random.default_rng(306)
    for _ in range(200):
        h, k, p = rng.normal(size=(4, 3)), unit(rng, 4), rng.normal(size=(4, 3))
        bound = np.linalg.norm(h, axis=1) * np.linalg.norm(p, axis=1)
        d1 = (bound[0] + bound[1]) * rng.uniform(1.01, 3) * rng.choice([-1, 1])
        assert sp6(h, k, p, d1, rng.normal()) == ([], False, False)


# --- 3. ill-posed cases ------------------------------------------------------

def test_sp1_point_on_the_axis_is_free():
    assert sp1([0, 0, 2], [0, 0, 2], Z) == (0.0, True, True)      # every angle works
    assert sp1([0, 0, 2], [0, 0, 3], Z) == (0.0, False, True)     # no angle works
    assert sp1([1, 0, 0], [0, 0, 1], Z) == (0.0, False, True)     # p2 on the axis


def test_sp4_h_parallel_to_k_or_p_on_the_axis_is_free():
    # h . R p = (h . k)(k . p) for every angle
    assert sp4(2 * Z, [1, 1, 3], Z, 6.0) == ([0.0], True, True)
    assert sp4(2 * Z, [1, 1, 3], Z, 5.0) == ([0.0], False, True)
    assert sp4([1, 1, 1], [0, 0, 3], Z, 3.0) == ([0.0], True, True)


def test_sp3_point_on_the_axis_is_free():
    # the distance from p2 = (1, 0, 0) to a point on the axis does not change
    d = math.sqrt(1 + 4)
    assert sp3([0, 0, 2], X, Z, d) == ([0.0], True, True)
    assert sp3([0, 0, 2], X, Z, d + 1) == ([0.0], False, True)


def test_sp2_parallel_axes_and_point_on_an_axis_are_free():
    # k1 = k2: only theta1 + theta2 is determined
    sols, exact, free = sp2(X, Y, Z, Z)
    assert free and exact and len(sols) == 1
    t1, t2 = sols[0]
    assert angle_error(t1 + t2, PI / 2) < 1e-12
    # p1 on the axis k2: theta2 is free
    sols, exact, free = sp2([0, 0, 1], [1, 0, 0], Y, Z)
    assert free and exact and angle_error(sols[0][0], PI / 2) < 1e-12


def test_sp4_tangent_gives_one_solution():
    assert sp4(X, X, Z, 1.0) == ([0.0], True, False)
    thetas, exact, free = sp4(X, X, Z, -1.0)     # used to return pi twice
    assert len(thetas) == 1 and angle_error(thetas[0], PI) < 1e-12 and exact and not free


@pytest.mark.parametrize("case", ["p1 on k1", "p3 on k3", "all axes parallel",
                                  "circle 1 coaxial with k2", "circle 3 coaxial with k2",
                                  "both circles at constant distance from the origin"])
def test_sp5_ill_posed_cases_are_free_with_a_true_representative(case):
    rng = np.random.default_rng(501)
    for _ in range(20):
        k1, k2, k3 = unit(rng, 3)
        p1, p2, p3 = rng.normal(size=(3, 3))
        t = rng.uniform(-PI, PI, 3)
        if case == "p1 on k1":
            p1 = 0.7 * k1
        elif case == "p3 on k3":
            p3 = -1.3 * k3
        elif case == "all axes parallel":
            k1 = k3 = k2
        elif case == "circle 3 coaxial with k2":
            k3, p2 = k2, 0.4 * k2
        elif case == "both circles at constant distance from the origin":
            p2 = 0.6 * k3
        p0 = rot(k2, t[1]) @ (p2 + rot(k3, t[2]) @ p3) - rot(k1, t[0]) @ p1
        if case == "circle 1 coaxial with k2":
            k1, p0 = k2, 0.4 * k2
            p1 = rot(k1, -t[0]) @ (rot(k2, t[1]) @ (p2 + rot(k3, t[2]) @ p3) - p0)
        elif case == "both circles at constant distance from the origin":
            p0 = 0.6 * k1
            p1 = rot(k1, -t[0]) @ (rot(k2, t[1]) @ (p2 + rot(k3, t[2]) @ p3) - p0)
        sols, exact, free = sp5(p0, p1, p2, p3, k1, k2, k3)
        assert free and exact and len(sols) == 1, (case, sols, exact, free)
        assert sp5_residual(p0, p1, p2, p3, k1, k2, k3, sols[0]) < 1e-9


def test_sp5_meeting_point_on_the_k2_axis_is_free():
    # a double root: its angles come out to ~1e-6 rad, and it is flagged free
    rng = np.random.default_rng(502)
    for _ in range(20):
        k1, k3 = unit(rng, 2)
        p1, p2, p3 = rng.normal(size=(3, 3))
        t1, t3 = rng.uniform(-PI, PI, 2)
        w = p2 + rot(k3, t3) @ p3
        p2 = p2 - (w - (w @ Z) * Z)           # p2 + R3 p3 on the z axis
        p0 = p2 + rot(k3, t3) @ p3 - rot(k1, t1) @ p1
        sols, exact, free = sp5(p0, p1, p2, p3, k1, Z, k3)
        assert exact and free
        assert min(max(angle_error(s[0], t1), angle_error(s[2], t3)) for s in sols) < 1e-5
        assert max(sp5_residual(p0, p1, p2, p3, k1, Z, k3, s) for s in sols) < 1e-6


def test_sp5_both_circles_at_constant_height_without_a_common_height_has_no_solution():
    # k1 = k2 = k3 = z: heights are p0_z + p1_z and p2_z + p3_z, never equal here
    assert sp5([0, 0, 1], X, [0, 0, 0], Y, Z, Z, Z) == ([], False, True)


def test_sp6_equation_without_angles_is_free():
    # h1 || k1 and h2 || k2: the first equation reads 1 + 2 = d1
    h, k, p = [Z, Z, Y, Y], [Z, Z, Z, Z], [X + Z, X + 2 * Z, X, X]
    sols, exact, free = sp6(h, k, p, 3.0, 0.5)
    assert exact and free and len(sols) == 1
    assert np.max(np.abs(sp6_residual(np.array(h), np.array(k), np.array(p), 3.0, 0.5,
                                      sols[0]))) < 1e-12
    assert sp6(h, k, p, 2.0, 0.5) == ([], False, True)


def test_sp6_same_equation_twice_is_free():
    rng = np.random.default_rng(601)
    for _ in range(20):
        h, k, p = rng.normal(size=(2, 3)), unit(rng, 2), rng.normal(size=(2, 3))
        H, K, P = np.vstack([h, 2 * h]), np.vstack([k, k]), np.vstack([p, p])
        d1 = sp6_residual(H, K, P, 0, 0, rng.uniform(-PI, PI, 2))[0]
        sols, exact, free = sp6(H, K, P, d1, 2 * d1)
        assert exact and free and len(sols) == 1
        assert np.max(np.abs(sp6_residual(H, K, P, d1, 2 * d1, sols[0]))) < 1e-9
        assert sp6(H, K, P, d1, 2 * d1 + 0.1) == ([], False, True)


def test_sp6_curve_of_solutions_is_free():
    # cos t1 - cos t2 = 0 and sin t1 - sin t2 = 0: every t1 = t2
    sols, exact, free = sp6([X, -X, Y, -Y], [Z] * 4, [X] * 4, 0.0, 0.0)
    assert exact and free and len(sols) == 1 and angle_error(*sols[0]) < 1e-12


def test_no_nan_on_degenerate_inputs():
    zero = np.zeros(3)
    theta, _, free = sp1(zero, zero, Z)
    assert free and math.isfinite(theta)
    cases = [sp2(zero, zero, Z, Z), sp3(zero, zero, Z, 0.0),
             sp4(zero, zero, Z, 0.0), sp5(zero, zero, zero, zero, Z, Z, Z),
             sp6(np.zeros((4, 3)), [Z] * 4, np.zeros((4, 3)), 0.0, 0.0),
             sp6(np.zeros((4, 3)), [Z] * 4, np.zeros((4, 3)), 1.0, 0.0)]
    for sols, exact, free in cases:
        assert free and all_finite(sols)


# --- 4. golden cases ---------------------------------------------------------

def test_golden_sp1_quarter_turn():
    theta, exact, free = sp1(X, Y, Z)
    assert (exact, free) == (True, False) and theta == pytest.approx(PI / 2, abs=1e-15)


def test_golden_sp2_two_quarter_turns():
    # R_z(t1) R_x(t2) e_z = e_x: t2 = +-pi/2 takes e_z to -+e_y, then t1 = +-pi/2
    sols, exact, free = sp2(Z, X, Z, X)
    assert exact and not free
    assert len(sols) == 2
    for e in [(PI / 2, PI / 2), (-PI / 2, -PI / 2)]:
        assert error_to_nearest(e, sols) < 1e-12


def test_golden_sp3_distance_sqrt2():
    # |R_z(t) e_x - e_x|^2 = 2 - 2 cos t = 2
    thetas, exact, free = sp3(X, X, Z, math.sqrt(2))
    assert exact and not free
    assert sorted(thetas) == pytest.approx([-PI / 2, PI / 2], abs=1e-12)


def test_golden_sp4_thirty_degrees():
    # e_y . R_z(t) e_x = sin t = 1/2
    thetas, exact, free = sp4(Y, X, Z, 0.5)
    assert exact and not free
    assert sorted(math.remainder(t, 2 * PI) for t in thetas) == pytest.approx(
        [PI / 6, 5 * PI / 6], abs=1e-12)


def test_golden_sp5_four_solutions():
    # e_x + R_z(t1) e_y = (1 - sin t1, cos t1, 0) must have norm 1: sin t1 = 1/2;
    # R_x(t2) R_z(t3) e_x = (cos t3, sin t3 cos t2, sin t3 sin t2)
    sols, exact, free = sp5(X, Y, np.zeros(3), X, Z, X, Z)
    assert exact and not free and len(sols) == 4
    expected = [(PI / 6, 0, PI / 3), (PI / 6, PI, -PI / 3),
                (5 * PI / 6, PI, PI / 3), (5 * PI / 6, 0, -PI / 3)]
    for e in expected:
        assert error_to_nearest(e, sols) < 1e-12


def test_golden_sp6_two_unit_vectors_summing_to_1_1():
    # (cos t1 + cos t2, sin t1 + sin t2) = (1, 1): {t1, t2} = {0, pi/2}
    sols, exact, free = sp6([X, X, Y, Y], [Z] * 4, [X] * 4, 1.0, 1.0)
    assert exact and not free and len(sols) == 2
    for e in [(0.0, PI / 2), (PI / 2, 0.0)]:
        assert error_to_nearest(e, sols) < 1e-12


def test_every_subproblem_is_exported():
    import kincalc.subproblems as sub
    assert sub.__all__ == ["sp1", "sp2", "sp3", "sp4", "sp5", "sp6"]
