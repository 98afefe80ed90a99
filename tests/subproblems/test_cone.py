"""The cone form of subproblem 4 (``kincalc.subproblems.cone``): ``h . R(k, t) p = h . v``
for unit vectors, exact next to its double root: known answers, the aligned
(singular) case, the touching cones, least squares, batch shapes."""

import numpy as np
import pytest

from kincalc.subproblems.cone import ALIGNED_TOL, cone
from subproblem_checks import LEAD, PI, X, Y, Z, rot, turn, unit, wrap


def draws(rng, n):
    h, p, k = unit(rng, n), unit(rng, n), unit(rng, n)
    t = rng.uniform(-PI, PI, n)
    w = rng.uniform(-PI, PI, n)
    v = turn(h, w, turn(k, t, p))                   # R(k, t) p turned about h: same cone
    return h, p, k, v, t


def test_known_answers():
    rng = np.random.default_rng(41)
    h, p, k, v, t = draws(rng, 5000)
    S = cone(h, p, k, v)
    th = S.theta[0]
    err = np.where(S.ok, np.abs(wrap(th - t[:, None])), np.inf).min(-1)
    assert (err < 1e-7).mean() > 0.999, np.sort(err)[-5:]
    assert np.allclose(np.where(S.ok, S.c[0] - np.cos(th), 0), 0, atol=1e-12)
    assert np.allclose(np.where(S.ok, S.s[0] - np.sin(th), 0), 0, atol=1e-12)
    # every ok root is a root
    res = ((h[:, None] * turn(k[:, None], th, p[:, None])).sum(-1) - (h * v).sum(-1)[:, None])
    assert np.abs(np.where(S.ok & S.exact, res, 0)).max() < 1e-9


@pytest.mark.parametrize("offset", [0.0, 1e-12, 1e-9, 1e-7, 1e-5])
def test_next_to_the_singularity_the_roots_are_exact(offset):
    """A wrist whose third axis can line up with the first (k ⟂ h, k ⟂ p): v within
    ``offset`` of h. The middle angle must come back to rounding (arccos of a value
    near 1 would be 1e-8 off), two roots while v is off the line, one aligned value on
    it."""
    h, k, p = Z, X, Z                      # R(X, t) Z: the cone is the whole y-z circle
    t = np.array([offset, -offset])
    v = turn(k, t, p)                      # exactly on the cone
    S = cone(h, p, k, v)
    got = S.theta[0]
    if offset <= ALIGNED_TOL:
        assert S.free.all() and np.allclose(got, 0.0, atol=1e-15)
    else:
        assert not S.free.any() and S.ok.all()
        for row, want in zip(got, t):
            assert np.abs(wrap(row - want)).min() < 1e-15 * max(1.0, abs(want) * 1e6)


def test_touching_cones_give_one_root():
    h, k, p = Z, X, unit(np.random.default_rng(1), 1)[0]
    # v on the line of h is reached only at the tangent when the cone of p does not hold h
    top_angle = np.arccos(np.clip(np.dot(turn(k, 0.3, p), h), -1, 1))
    S = cone(h, p, k, turn(k, 0.3, p))
    assert S.ok[0] and S.exact.all()
    assert np.isfinite(top_angle)


def test_least_squares_when_the_cones_do_not_meet():
    h, k, p = Z, Z, X                      # R(Z, t) X stays in the x-y plane: h . R p = 0
    S = cone(h, p, k, Z)                   # asks for 1
    assert not S.exact.any() and S.free.all()     # r = 0: subproblem 4's degenerate case


@pytest.mark.parametrize("shape", [(), (5,), LEAD])
def test_shapes_and_fixed_axes(shape):
    rng = np.random.default_rng(7)
    n = int(np.prod(shape, dtype=int))
    h, p, k, v, t = draws(rng, n)
    S = cone(h.reshape(shape + (3,)), p.reshape(shape + (3,)), k.reshape(shape + (3,)),
             v.reshape(shape + (3,)))
    assert S.ok.shape == shape + (2,)
    # a fixed geometry (3,) with a batch of targets answers as each alone
    hv = turn(Z, rng.uniform(-PI, PI, n), turn(X, rng.uniform(-PI, PI, n), Y))
    together = cone(Z, Y, X, hv.reshape(shape + (3,)))
    for i in range(n):
        alone = cone(Z, Y, X, hv[i])
        idx = np.unravel_index(i, shape) if shape else ()
        assert np.allclose(together.theta[0][idx], alone.theta[0], atol=1e-15)


def test_angles_are_in_the_half_open_turn():
    """A root at a half turn comes out as +pi, never -pi (the Solutions contract), at 0,
    1 and 3 leading dimensions."""
    x, z = np.array([1.0, 0, 0]), np.array([0, 0, 1.0])
    for shape in ((), (4,), (2, 3, 2)):
        h = np.broadcast_to(x, shape + (3,))
        sol = cone(h, h, np.broadcast_to(z, shape + (3,)), -h)
        theta = sol.theta[0]
        assert np.all(theta <= np.pi) and np.all(theta > -np.pi)
        assert np.all(np.isclose(np.abs(theta[sol.ok]), np.pi))
