"""The core of subproblems 5 and 6, ``M @ [cos t1, sin t1, cos t2, sin t2] = b``: known
answers, every kind of problem (rank 2, one line, no equation, a curve, a point, a
quartic of lower degree) alone and mixed in one batch (see tests/subproblem_checks.py)."""

import numpy as np
import pytest

from kincalc.subproblems import unit_pair
from subproblem_checks import LEAD, PI, assert_same, check_batching, check_sane, nearest_error, \
    ok_count

N_DRAWS = 3000
ANGLE_TOL = 1e-7   # rad


def torus(t1, t2):
    """``[cos t1, sin t1, cos t2, sin t2] (..., 4)``."""
    return np.stack([np.cos(t1), np.sin(t1), np.cos(t2), np.sin(t2)], -1)


def residual(M, b, S):
    """``max |M x(t) - b|`` of every slot ``(..., 4)``."""
    x = torus(*S.theta)
    return np.abs(np.einsum("...ij,...kj->...ki", M, x) - b[..., None, :]).max(-1)


def solve(M, b, scale=1.0):
    return unit_pair.solve(M, b, scale)


# --- 1. known answers --------------------------------------------------------

def test_known_answer_and_every_answer_solves_it():
    rng = np.random.default_rng(701)
    M = rng.normal(size=(N_DRAWS, 2, 4)) * 10.0 ** rng.uniform(-3, 3, (N_DRAWS, 1, 1))
    t = rng.uniform(-PI, PI, (N_DRAWS, 2))
    b = np.einsum("nij,nj->ni", M, torus(t[:, 0], t[:, 1]))
    S = unit_pair.solve(M, b, np.abs(M).max((-1, -2)))
    check_sane(S, (N_DRAWS,), 2, 4)
    assert (S.exact == S.ok).all() and not S.free.any()
    err = nearest_error(S, t)
    assert err.max() < ANGLE_TOL, (err.argmax(), err.max())
    rows = np.linalg.norm(M, axis=-1).max(-1)
    assert (residual(M, b, S) / rows[:, None])[S.ok].max() < 1e-9
    assert set(np.unique(ok_count(S))) == {2, 4}


# --- every kind of problem ---------------------------------------------------

E = np.eye(4)
#: (name, M, b, number of solutions, free, solutions that must be among them)
KINDS = [
    # u1 + u2 = (1, 1): {t1, t2} = {0, pi/2}
    ("rank 2", [E[0] + E[2], E[1] + E[3]], [1, 1], 2, False, [(0, PI / 2), (PI / 2, 0)]),
    # u1 - u2 = (1, 0): the quartic's leading coefficients vanish (degree 2 in z)
    ("lower degree", [E[0] - E[2], E[1] - E[3]], [1, 0], 2, False,
     [(PI / 3, 2 * PI / 3), (-PI / 3, -2 * PI / 3)]),
    # cos t1 = 1 and sin t1 + cos t2 = 1/2: t1 = 0 a double root, twice
    ("double roots", [E[0], E[1] + E[2]], [1, 0.5], 2, False, [(0, PI / 3), (0, -PI / 3)]),
    # u1 + u2 = (2, 0): one point of the torus (rho = 0)
    ("point", [E[0] + E[2], E[1] + E[3]], [2, 0], 1, False, [(0, 0)]),
    # u1 = u2: a curve (|u1| = 1 on the whole circle)
    ("curve", [E[0] - E[2], E[1] - E[3]], [0, 0], 1, True, []),
    # u1 + u2 = (3, 0): out of reach
    ("out of reach", [E[0] + E[2], E[1] + E[3]], [3, 0], 0, False, []),
    # cos t1 = 1/2 twice (parallel rows): a curve in t2
    ("parallel rows", [E[0], 2 * E[0]], [0.5, 1.0], 1, True, []),
    ("parallel rows, inconsistent", [E[0], 2 * E[0]], [0.5, 2.0], 0, True, []),
    # 0 = 0 and cos t1 + cos t2 = 1
    ("one void row", [0 * E[0], E[0] + E[2]], [0, 1], 1, True, []),
    ("one void row, inconsistent", [0 * E[0], E[0] + E[2]], [1, 1], 0, True, []),
    # -sin t1 = 0 and cos t1 = 1: t1 = 0, t2 in no equation (exact zeros in the
    # quartic: this raised LinAlgError)
    ("one angle absent", [-E[1], E[0]], [0, 1], 1, True, [(0, 0)]),
    ("no equation", [0 * E[0], 0 * E[0]], [0, 0], 1, True, [(0, 0)]),
    ("no equation, inconsistent", [0 * E[0], 0 * E[0]], [0, 1], 0, True, []),
]


@pytest.mark.parametrize("name, M, b, count, free, expected", KINDS, ids=[k[0] for k in KINDS])
def test_every_kind_alone(name, M, b, count, free, expected):
    M, b = np.array(M, float), np.array(b, float)
    S = solve(M, b)
    check_sane(S, (), 2, 4)
    assert ok_count(S) == count, S.rows()
    assert (S.exact == S.ok).all() and S.free.all() == free and S.free.any() == free
    if count:
        assert residual(M, b, S)[S.ok].max() < 1e-12
    for e in expected:
        assert nearest_error(S, e) < 1e-7, (e, S.rows())


def test_every_kind_mixed_in_one_batch_agrees_with_each_alone():
    rng = np.random.default_rng(702)
    n = int(np.prod(LEAD))
    kinds = [KINDS[i % len(KINDS)] for i in rng.permutation(n)]
    M = np.array([k[1] for k in kinds], float).reshape(LEAD + (2, 4))
    b = np.array([k[2] for k in kinds], float).reshape(LEAD + (2,))
    # each problem in its own units: scale each row
    s = 10.0 ** rng.uniform(-3, 3, LEAD + (2, 1))
    M, b = M * s, b * s[..., 0]
    S = check_batching(lambda M, b, scale: unit_pair.solve(M, b, scale),
                       [M, b, np.abs(M).max((-1, -2))], 2, 4)
    for index, kind in zip(np.ndindex(*LEAD), kinds):
        assert ok_count(S)[index] == kind[3], kind[0]


def test_one_geometry_against_many_right_sides():
    M = np.array([E[0] + E[2], E[1] + E[3]])
    b = np.array([[1, 1], [2, 0], [3, 0]], float)
    S = solve(M, b)
    check_sane(S, (3,), 2, 4)
    assert ok_count(S).tolist() == [2, 1, 0]
    for i in range(3):
        assert_same(S, solve(M, b[i]), i)


@pytest.mark.parametrize("gap", [3e-7, 8e-7])
def test_two_roots_a_hair_apart_are_one_unless_merge_is_0(gap):
    """Two solutions ``gap`` apart in both angles (the equations' rows across their
    difference), below the default ``merge``: that takes them for one double root found
    twice; with ``merge=0`` both come back, in two slots, each near its own angles (a
    near-double root of the quartic comes to ~1e-8)."""
    rng = np.random.default_rng(int(gap * 1e9))
    for _ in range(50):
        ta = rng.uniform(-PI, PI, 2)
        tb = ta + gap * rng.choice([-1, 1], 2)
        xa, xb = torus(*ta), torus(*tb)
        d = (xa - xb) / np.linalg.norm(xa - xb)
        M = rng.normal(size=(2, 4))
        M -= np.outer(M @ d, d)                       # both rows across the difference
        b = M @ xa
        merged = unit_pair.solve(M, b, 1.0)
        kept = unit_pair.solve(M, b, 1.0, merge=0.0)
        slots = np.flatnonzero(kept.ok)
        theta = np.array(kept.theta)[:, slots]                              # (2, k)
        off = lambda t: np.abs(np.angle(np.exp(1j * (theta - t[:, None])))).max(0)  # noqa: E731
        a, b_ = off(ta), off(tb)
        assert a.min() < gap / 3 and b_.min() < gap / 3
        assert a.argmin() != b_.argmin()
        assert ok_count(kept) == ok_count(merged) + 1


def test_a_tangency_gives_its_double_root_to_rounding():
    """Equations whose Jacobian in (t1, t2) is singular at the known answer (the two
    ellipses touch: an arm at a singularity, placed by subproblem 5): the double root is
    found to rounding, once. Newton's method on the quartic stopped at ~sqrt(eps) (1.4e-8
    rad, a spherical wrist's aligned axes then read as 3.6e-8 apart: no continuum)."""
    rng = np.random.default_rng(733)
    n = 500
    t = rng.uniform(-PI, PI, (n, 2))
    M = rng.normal(size=(n, 2, 4))
    d1 = np.zeros((n, 4))
    d2 = np.zeros((n, 4))
    d1[:, 0], d1[:, 1] = -np.sin(t[:, 0]), np.cos(t[:, 0])       # d x / d t1, d t2
    d2[:, 2], d2[:, 3] = -np.sin(t[:, 1]), np.cos(t[:, 1])
    # row 1's derivatives made those of row 2 times lam: the Jacobian of rank 1
    lam = rng.uniform(-2, 2, n)
    for d in (d1, d2):
        M[:, 0] += ((lam * (M[:, 1] * d).sum(-1) - (M[:, 0] * d).sum(-1)))[:, None] * d
    b = np.einsum("nij,nj->ni", M, torus(t[:, 0], t[:, 1]))
    S = unit_pair.solve(M, b, np.abs(M).max((-1, -2)))
    err = nearest_error(S, t)
    # (a tangency flat to fourth order is ill-conditioned in its coefficients: 1 draw of 500
    # is found to 2e-8 only)
    assert np.count_nonzero(err > 1e-12) <= n // 100, np.sort(err)[-10:]
    assert err.max() < 1e-7
    assert residual(M, b, S)[S.ok].max() < 1e-12
