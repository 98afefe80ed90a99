"""Shared draws and checks of the subproblem tests (tests/test_sp1.py ... test_sp6.py).

Rotations come from :func:`kincalc.spatial.matrix_from_axis_angle`, never from the
subproblem modules. Every generator is seeded by its test.
"""

import math

import numpy as np

from kincalc.spatial import matrix_from_axis_angle

PI = math.pi
X, Y, Z = np.eye(3)
ORIGIN = np.zeros(3)
#: c, s against cos(theta), sin(theta) in every ok slot
COS_SIN_TOL = 1e-12
#: leading shape of the three-dimensional batches
LEAD = (2, 3, 4)


def rot(k, t):
    """``R(k, t) (..., 3, 3)``."""
    return matrix_from_axis_angle(k, t)


def turn(k, t, p):
    """``R(k, t) p (..., 3)``, broadcasting."""
    return np.einsum("...ij,...j->...i", rot(k, t), p)


def unit(rng, *shape):
    """Random unit vectors ``shape + (3,)``."""
    v = rng.normal(size=shape + (3,))
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def lengths(rng, n, m=1):
    """``(n, m, 3)``: m random vectors per draw, each draw with its own scale in
    1e-3 .. 1e3 (six orders of magnitude)."""
    return rng.normal(size=(n, m, 3)) * 10.0 ** rng.uniform(-3, 3, (n, 1, 1))


def wrap(a):
    """Angles (or angle differences) to [-pi, pi)."""
    return np.remainder(np.asarray(a) + PI, 2 * PI) - PI


def nearest_error(S, true):
    """Per problem, the largest angle error of the ``ok`` slot nearest to ``true``
    (``(..., u)``, one column per unknown); inf where no slot is ok."""
    true = np.asarray(true, float)
    err = np.max([np.abs(wrap(t - true[..., j, None])) for j, t in enumerate(S.theta)], 0)
    return np.where(S.ok, err, np.inf).min(-1)


def ok_count(S):
    return S.ok.sum(-1)


def check_sane(S, lead, unknowns, slots):
    """The contract of :class:`Solutions` every answer must keep: shapes, boolean
    masks, no NaN or inf in any slot, angles in (-pi, pi] and ``c``, ``s`` the
    cosines and sines of ``theta`` (to 1e-12) in every ok slot."""
    shape = tuple(lead) + (slots,)
    assert len(S.theta) == len(S.c) == len(S.s) == unknowns
    for name in ("ok", "exact", "free"):
        mask = getattr(S, name)
        assert mask.shape == shape and mask.dtype == bool, (name, mask.shape, mask.dtype)
    assert S.slots == slots
    for t, c, s in zip(S.theta, S.c, S.s):
        for a in (t, c, s):
            assert a.shape == shape
            assert np.isfinite(a).all(), "NaN or inf in a slot"
        theta = t[S.ok]
        assert ((theta > -PI) & (theta <= PI)).all(), theta[(theta <= -PI) | (theta > PI)]
        assert np.abs(c[S.ok] - np.cos(theta)).max(initial=0.0) <= COS_SIN_TOL
        assert np.abs(s[S.ok] - np.sin(theta)).max(initial=0.0) <= COS_SIN_TOL


def frozen(a):
    """A read-only copy: a subproblem writing into its input raises (``ValueError:
    assignment destination is read-only``)."""
    a = np.array(a, float)
    a.setflags(write=False)
    return a


def assert_same(S, T, index=(), *, atol=1e-12):
    """``S[index]`` and ``T`` hold the same answers: the same masks everywhere, the
    same angles (and cosines, sines) in the ok slots."""
    ok = S.ok[index]
    for name in ("ok", "exact", "free"):
        np.testing.assert_array_equal(getattr(S, name)[index], getattr(T, name), err_msg=name)
    for field in ("theta", "c", "s"):
        for a, b in zip(getattr(S, field), getattr(T, field)):
            diff = a[index] - b
            if field == "theta":
                diff = wrap(diff)
            assert np.abs(diff[ok]).max(initial=0.0) <= atol, (field, a[index], b)


def check_batching(solve, args, unknowns, slots, shared=()):
    """Run ``solve`` on a batch ``LEAD`` of problems at 3, 1 and 0 leading dimensions.

    ``args`` are arrays ``LEAD + core``. The answers must agree with those of each
    problem solved alone, and no input may be written into. ``shared`` maps an
    argument's index to one value of its core shape (an axis all problems share:
    ``args[i]`` must be that value broadcast), which is then also passed as it is and
    must give the same answers. Returns the batch's Solutions."""
    args = [np.asarray(a, float) for a in args]
    S = solve(*(frozen(a) for a in args))
    check_sane(S, LEAD, unknowns, slots)
    n = math.prod(LEAD)
    flat = solve(*(frozen(a.reshape((n,) + a.shape[len(LEAD):])) for a in args))
    check_sane(flat, (n,), unknowns, slots)
    for i, index in enumerate(np.ndindex(*LEAD)):
        alone = solve(*(frozen(a[index]) for a in args))
        check_sane(alone, (), unknowns, slots)
        assert_same(S, alone, index)
        assert_same(flat, alone, i)
    for i, value in dict(shared).items():
        value = np.asarray(value, float)
        np.testing.assert_array_equal(args[i], np.broadcast_to(value, args[i].shape))
        mixed = [frozen(a) for a in args]
        mixed[i] = frozen(value)
        T = solve(*mixed)
        check_sane(T, LEAD, unknowns, slots)
        assert_same(T, S)
    return S


def is_local_minimum(g, x, steps=(1e-2, 1e-4, 1e-6), rtol=1e-12):
    """``g`` at ``x`` (a point of R^u) is no larger than at its neighbours ``x +- h
    e_j`` and ``x +- h (e_i +- e_j)`` for each step ``h``."""
    x = np.atleast_1d(np.asarray(x, float))
    g0 = g(x)
    eye = np.eye(len(x))
    dirs = list(eye) + [eye[i] + s * eye[j] for i in range(len(x)) for j in range(i + 1, len(x))
                        for s in (1, -1)]
    slack = rtol * (1 + abs(g0))
    return all(g(x + s * h * e) >= g0 - slack for h in steps for e in dirs for s in (1, -1))
