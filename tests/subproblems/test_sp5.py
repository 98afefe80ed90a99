"""Subproblem 5, ``p0 + R(k1, t1) p1 = R(k2, t2) (p2 + R(k3, t3) p3)``: known answers,
completeness, no solution out of reach, ill-posed cases, golden values, batch shapes
(see tests/subproblem_checks.py)."""

import numpy as np
import pytest

from kincalc.subproblems import sp5
from subproblem_checks import (LEAD, ORIGIN, PI, X, Y, Z, check_batching, check_sane, lengths,
                               nearest_error, ok_count, turn, unit, wrap)

N_DRAWS = 3000
ANGLE_TOL = 1e-7   # rad


def loop(p0, p1, p2, p3, k1, k2, k3, t1, t2, t3):
    """``p0 + R1 p1 - R2 (p2 + R3 p3)``, broadcasting."""
    return p0 + turn(k1, t1, p1) - turn(k2, t2, p2 + turn(k3, t3, p3))


def closing(args, S):
    """``|loop|`` of every slot ``(..., 4)``."""
    v = [np.asarray(a)[..., None, :] for a in args]
    return np.linalg.norm(loop(*v, *S.theta), axis=-1)


def known_answers(rng, n, k2=None):
    """``(p0, p1, p2, p3, k1, k2, k3), theta (n, 3)`` of n solvable problems (one shared
    middle axis if given)."""
    k1, k3 = unit(rng, n), unit(rng, n)
    k2 = unit(rng, n) if k2 is None else np.broadcast_to(k2, (n, 3))
    P = lengths(rng, n, 3)
    p1, p2, p3 = P[:, 0], P[:, 1], P[:, 2]
    t = rng.uniform(-PI, PI, (n, 3))
    p0 = turn(k2, t[:, 1], p2 + turn(k3, t[:, 2], p3)) - turn(k1, t[:, 0], p1)
    return (p0, p1, p2, p3, k1, k2, k3), t


def size(args):
    return np.max([np.linalg.norm(v, axis=-1) for v in args[:4]], 0)


# --- 1. known answers --------------------------------------------------------

def test_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(105)
    args, t = known_answers(rng, N_DRAWS)
    S = sp5(*args)
    check_sane(S, (N_DRAWS,), 3, 4)
    assert (S.exact == S.ok).all() and not S.free.any()
    err = nearest_error(S, t)
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())
    res = closing(args, S) / size(args)[:, None]
    assert res[S.ok].max() < 1e-9, res[S.ok].max()
    # the quartic's real roots come in pairs: 2 or 4 solutions, and both occur
    counts = np.bincount(ok_count(S), minlength=5)
    assert counts[0] == counts[1] == counts[3] == 0 and counts[2] > 0 and counts[4] > 0, counts


def test_cos_sin_are_those_of_theta():
    rng = np.random.default_rng(106)
    S = sp5(*known_answers(rng, N_DRAWS)[0])
    for t, c, s in zip(S.theta, S.c, S.s):
        assert np.abs(c[S.ok] - np.cos(t[S.ok])).max() <= 1e-12
        assert np.abs(s[S.ok] - np.sin(t[S.ok])).max() <= 1e-12


def test_axes_along_the_coordinate_axes():
    """Robot-like geometry: axes +-x, +-y, +-z and points of small multiples of 0.1, so
    that exact zeros abound (a point on its axis, a circle of constant height, ...).
    Every problem that is not free gives its true angles; a free one a true
    representative. (Exact zero coefficients once made the quartic's companion matrix
    NaN, and eigvals raised for the whole batch.)"""
    rng = np.random.default_rng(107)
    n = 2000
    signed = np.concatenate([np.eye(3), -np.eye(3)])
    k1, k2, k3 = signed[rng.integers(0, 6, (3, n))]
    p1, p2, p3 = rng.integers(-2, 3, (3, n, 3)) * rng.choice([1, 0.5, 0.1], (3, n, 1))
    t = rng.uniform(-PI, PI, (n, 3))
    p0 = turn(k2, t[:, 1], p2 + turn(k3, t[:, 2], p3)) - turn(k1, t[:, 0], p1)
    args = (p0, p1, p2, p3, k1, k2, k3)
    S = sp5(*args)
    check_sane(S, (n,), 3, 4)
    free = S.free.any(-1)
    assert 0 < free.sum() < n / 2 and S.ok.any(-1).all()
    assert nearest_error(S, t)[~free].max() < 1e-6
    res = closing(args, S) / np.maximum(size(args), 1e-300)[:, None]
    assert res[S.ok].max() < 1e-7


# --- completeness: an independent search finds no solution the solver missed --

def grid_newton(F, n_unknowns, grid, keep, iters=25):
    """Zeros of ``F: (m, n) -> (m, n')`` reached by Newton's method (pseudo-inverse)
    from the best points of a grid: end points ``(keep, n)`` and residuals."""
    axes = np.linspace(-PI, PI, grid, endpoint=False)
    x = np.stack(np.meshgrid(*[axes] * n_unknowns, indexing="ij"), -1).reshape(-1, n_unknowns)
    x = x[np.argsort(np.linalg.norm(F(x), axis=-1))[:keep]]
    eye = 1e-7 * np.eye(n_unknowns)
    for _ in range(iters):
        J = np.stack([(F(x + e) - F(x - e)) / 2e-7 for e in eye], axis=-1)
        x = x - np.einsum("nij,nj->ni", np.linalg.pinv(J), F(x))
    return x, np.linalg.norm(F(x), axis=-1)


def test_finds_every_solution_an_independent_search_finds():
    rng = np.random.default_rng(205)
    zeros_seen = 0
    for _ in range(12):
        p0, p1, p2, p3 = rng.normal(size=(4, 3))
        k1, k2, k3 = unit(rng, 3)
        S = sp5(p0, p1, p2, p3, k1, k2, k3)
        check_sane(S, (), 3, 4)
        assert not S.free.any() and (S.exact == S.ok).all()

        def F(T):
            return loop(p0, p1, p2, p3, k1, k2, k3, T[:, 0], T[:, 1], T[:, 2])

        for x, res in zip(*grid_newton(F, 3, grid=24, keep=400)):
            if res < 1e-10:
                zeros_seen += 1
                err = nearest_error(S, x)
                assert err < 1e-6, (x, S.rows())
    assert zeros_seen > 0  # the search is not vacuous


# --- 2. no least squares: out of reach ---------------------------------------

def test_out_of_reach_gives_no_solution():
    rng = np.random.default_rng(305)
    n = 500
    p1, p2, p3 = rng.normal(size=(3, n, 3))
    k1, k2, k3 = unit(rng, 3, n)
    # |p0 + R1 p1| >= |p0| - |p1| > |p2| + |p3| >= |right side|
    reach = sum(np.linalg.norm(v, axis=-1) for v in (p1, p2, p3))
    p0 = unit(rng, n) * (reach + rng.uniform(0.1, 5, n))[:, None]
    S = sp5(p0, p1, p2, p3, k1, k2, k3)
    check_sane(S, (n,), 3, 4)
    assert not S.ok.any() and not S.exact.any() and not S.free.any()


# --- 3. ill-posed cases ------------------------------------------------------

ILL_POSED = ["p1 on k1", "p3 on k3", "all axes parallel", "circle 1 coaxial with k2",
             "circle 3 coaxial with k2", "both circles at constant distance from the origin"]


def ill_posed(rng, case, n):
    """n problems of one ill-posed kind, each with a solution."""
    k1, k2, k3 = unit(rng, 3, n)
    p1, p2, p3 = rng.normal(size=(3, n, 3))
    t = rng.uniform(-PI, PI, (n, 3))
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
    p0 = turn(k2, t[:, 1], p2 + turn(k3, t[:, 2], p3)) - turn(k1, t[:, 0], p1)
    if case == "circle 1 coaxial with k2":
        k1, p0 = k2, 0.4 * k2
    elif case == "both circles at constant distance from the origin":
        p0 = 0.6 * k1
    if case in ("circle 1 coaxial with k2", "both circles at constant distance from the origin"):
        p1 = turn(k1, -t[:, 0], turn(k2, t[:, 1], p2 + turn(k3, t[:, 2], p3)) - p0)
    return p0, p1, p2, p3, k1, k2, k3


@pytest.mark.parametrize("case", ILL_POSED)
def test_ill_posed_cases_are_free_with_a_true_representative(case):
    rng = np.random.default_rng(501)
    n = 20
    args = ill_posed(rng, case, n)
    S = sp5(*args)
    check_sane(S, (n,), 3, 4)
    assert (ok_count(S) == 1).all() and S.ok[:, 0].all(), (case, S.ok)
    assert S.free[:, 0].all() and S.exact[:, 0].all(), (case, S.free, S.exact)
    assert closing(args, S)[:, 0].max() < 1e-9


@pytest.mark.parametrize("case", ["p1 on k1", "p3 on k3"])
def test_a_circle_that_is_a_point_is_free_without_a_solution_too(case):
    # the point out of reach of the other circle: no slot ok, every slot free
    rng = np.random.default_rng(503)
    n = 20
    args = list(ill_posed(rng, case, n))
    args[0] = args[0] + 10 * unit(rng, n) * size(args)[:, None]
    S = sp5(*args)
    check_sane(S, (n,), 3, 4)
    assert not S.ok.any() and not S.exact.any() and S.free.all()


def test_meeting_point_on_the_k2_axis_is_free():
    # a double root: its angles come out to ~1e-6 rad, and it is flagged free
    rng = np.random.default_rng(502)
    n = 20
    k1, k3 = unit(rng, 2, n)
    p1, p2, p3 = rng.normal(size=(3, n, 3))
    t1, t3 = rng.uniform(-PI, PI, (2, n))
    w = p2 + turn(k3, t3, p3)
    p2 = p2 - (w - w[:, 2:] * Z)                 # p2 + R3 p3 on the z axis
    p0 = p2 + turn(k3, t3, p3) - turn(k1, t1, p1)
    args = (p0, p1, p2, p3, k1, Z, k3)
    S = sp5(*args)
    check_sane(S, (n,), 3, 4)
    assert (S.exact == S.ok).all()
    # theta2 is free: compare theta1 and theta3 only; the slot that matches is free
    err = np.max([np.abs(wrap(S.theta[j] - t[:, None])) for j, t in ((0, t1), (2, t3))], 0)
    err = np.where(S.ok, err, np.inf)
    assert err.min(-1).max() < 1e-5
    assert S.free[np.arange(n), err.argmin(-1)].all()
    assert closing(args, S)[S.ok].max() < 1e-6
    # theta2 alone is the undetermined angle (theta1 and theta3 are the true ones)
    u1, u2, u3 = S.undetermined
    assert (u2 == S.free).all() and not (u1 & S.ok).any() and not (u3 & S.ok).any()


@pytest.mark.parametrize("case, angle", [("p1 on k1", 0), ("p3 on k3", 2)])
def test_the_undetermined_angle_of_a_circle_that_is_a_point(case, angle):
    """A circle that is a point leaves its own angle undetermined, not the other two (a
    placement that marked all three free lost the orientation's solutions: a point-plus-roll
    arm turned the wrong joints)."""
    rng = np.random.default_rng(501)
    S = sp5(*ill_posed(rng, case, 20))
    slot = S.ok & S.free
    assert slot.any(-1).all()
    for j, u in enumerate(S.undetermined):
        assert (u[slot] == (j == angle)).all(), (case, j)
    assert ((S.undetermined[0] | S.undetermined[1] | S.undetermined[2]) == S.free).all()


def test_both_circles_at_constant_height_without_a_common_height_has_no_solution():
    # k1 = k2 = k3 = z: heights are p0_z + p1_z and p2_z + p3_z, never equal here
    S = sp5([0, 0, 1], X, ORIGIN, Y, Z, Z, Z)
    check_sane(S, (), 3, 4)
    assert not S.ok.any() and not S.exact.any() and S.free.all()


def test_zero_vectors_are_free_and_finite():
    S = sp5(ORIGIN, ORIGIN, ORIGIN, ORIGIN, Z, Z, Z)
    check_sane(S, (), 3, 4)
    assert S.ok[0] and S.free[0] and S.exact[0]


# --- 4. golden cases ---------------------------------------------------------

def test_golden_four_solutions():
    # e_x + R_z(t1) e_y = (1 - sin t1, cos t1, 0) must have norm 1: sin t1 = 1/2;
    # R_x(t2) R_z(t3) e_x = (cos t3, sin t3 cos t2, sin t3 sin t2)
    S = sp5(X, Y, ORIGIN, X, Z, X, Z)
    check_sane(S, (), 3, 4)
    assert S.ok.all() and S.exact.all() and not S.free.any()
    expected = [(PI / 6, 0, PI / 3), (PI / 6, PI, -PI / 3),
                (5 * PI / 6, PI, PI / 3), (5 * PI / 6, 0, -PI / 3)]
    for e in expected:
        assert nearest_error(S, e) < 1e-12, (e, S.rows())


# --- 5. shapes ---------------------------------------------------------------

def mixed_batch(rng, k2=None):
    """``LEAD`` problems: solvable, out of reach and ill-posed ones."""
    n = int(np.prod(LEAD))
    args, _ = known_answers(rng, n, k2)
    p0, p1, p2, p3, k1, k2, k3 = (np.array(np.broadcast_to(a, (n, 3))) for a in args)
    p0[1::6] *= 1e3                                    # out of reach
    p1[2::6] = 0.7 * k1[2::6]                          # p1 on k1 (then out of reach or not)
    bad = ill_posed(rng, "p3 on k3", n)
    for a, b in zip((p0, p1, p2, p3, k1, k2, k3), bad):
        if a is not k2:
            a[3::6] = b[3::6]
    p0[3::6] = turn(k2[3::6], 0.3, p2[3::6] + turn(k3[3::6], 0.2, p3[3::6])) \
        - turn(k1[3::6], 0.1, p1[3::6])
    return [a.reshape(LEAD + (3,)) for a in (p0, p1, p2, p3, k1, k2, k3)]


def test_batch_shapes_agree_with_each_problem_alone():
    rng = np.random.default_rng(501)
    S = check_batching(sp5, mixed_batch(rng), 3, 4)
    assert S.free.any() and S.ok.any() and not S.ok.any(-1).all()


def test_a_shared_axis_broadcasts_against_per_problem_points():
    rng = np.random.default_rng(502)
    k2 = unit(rng)
    check_batching(sp5, mixed_batch(rng, k2), 3, 4, shared={5: k2})
