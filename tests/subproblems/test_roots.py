"""The real roots of a quadratic (kincalc.subproblems.roots.quadratic), against roots
written out: two, one double, none, the linear case, and a tangent met to rounding."""

import numpy as np

from kincalc.subproblems.roots import quadratic


def _roots(sol):
    return [sorted(np.asarray(x)[ok].tolist()) for x, ok in zip(sol.theta[0], sol.ok)]


def test_two_one_and_no_roots():
    # (x - 1)(x - 3); (x - 2)^2; x^2 + 1; the linear 2 x - 1
    A, B, C = np.array([1.0, 1, 1, 0]), np.array([-4.0, -4, 0, 2]), np.array([3.0, 4, 1, -1])
    got = _roots(quadratic(A, B, C, 1.0))
    assert np.allclose(got[0], [1, 3]) and np.allclose(got[1], [2]) and got[2] == []
    assert np.allclose(got[3], [0.5])


def test_a_tangent_within_rounding_is_one_double_root():
    """(x - c)^2 with C off by a few eps of its size: without a band the discriminant's
    sign decides between two roots ~sqrt(eps) apart and none; with it, one root at c."""
    rng = np.random.default_rng(5)
    c = rng.uniform(-2, 2, 200)
    noise = rng.uniform(-8, 8, 200) * np.finfo(float).eps * (1 + c * c)
    A, B, C = np.ones(200), -2 * c, c * c + noise
    plain = quadratic(A, B, C, 1.0)
    split = (plain.ok.sum(-1) == 2) & (np.abs(np.diff(plain.theta[0], axis=-1))[..., 0] > 1e-9)
    assert np.count_nonzero(split) > 50
    band = quadratic(A, B, C, 1.0, tangent=64 * np.finfo(float).eps * (1 + c * c))
    for roots, ci in zip(_roots(band), c):
        assert len(roots) >= 1 and np.allclose(roots, ci, atol=1e-12)
    # a true pair of roots just outside the band stays a pair
    far = quadratic(np.ones(1), np.zeros(1), -np.full(1, 1e-12), 1.0, tangent=1e-14)
    assert np.allclose(_roots(far)[0], [-1e-6, 1e-6])
