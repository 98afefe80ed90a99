"""The ``fixed=`` constants of the subproblems: a solver whose vectors are a robot's fixed
axes and lengths computes what depends on them alone once (``sp1_constants``,
``sp3_constants``, ``sp4_constants``, ``abc_constants``, ``cone_constants``) and passes it
on every call. The answers must be the same, bit for bit, as without them: the same
roots, masks and least-squares angles, for batches of 0, 1 and 3 leading dimensions,
including the ill-posed and out-of-reach problems."""

import numpy as np
import pytest

from kincalc.subproblems import sp1, sp3, sp4
from kincalc.subproblems.cone import cone, cone_constants
from kincalc.subproblems.sp1 import sp1_constants
from kincalc.subproblems.sp3 import sp3_constants
from kincalc.subproblems.sp4 import abc_constants, from_abc, sp4_constants

SHAPES = [(), (5,), (2, 3, 4)]


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def same(a, b):
    """Every field of two Solutions equal, bit for bit (NaN where NaN)."""
    for x, y in zip(a.theta + a.c + a.s, b.theta + b.c + b.s):
        np.testing.assert_array_equal(x, y)
    for x, y in ((a.ok, b.ok), (a.exact, b.exact), (a.free, b.free)):
        np.testing.assert_array_equal(x, y)


@pytest.fixture(params=range(6))
def rng(request):
    return np.random.default_rng(1000 + request.param)


@pytest.mark.parametrize("shape", SHAPES)
def test_sp1_fixed_is_sp1(rng, shape):
    p1, k = rng.normal(size=3), unit(rng.normal(size=3))
    p2 = rng.normal(size=shape + (3,))
    p2.reshape(-1, 3)[:1] = np.cos(0.7) * p1 + np.sin(0.7) * np.cross(k, p1)   # reachable
    for tol in (0.0, 1e-9):
        same(sp1(p1, p2, k, tol=tol, fixed=sp1_constants(p1, k)), sp1(p1, p2, k, tol=tol))


@pytest.mark.parametrize("shape", SHAPES)
def test_sp4_and_from_abc_fixed_are_the_same(rng, shape):
    h, k = rng.normal(size=3), unit(rng.normal(size=3))
    p = rng.normal(size=shape + (3,))
    d = rng.normal(size=shape) * 2.0              # in reach and out of it
    same(sp4(h, p, k, d, fixed=sp4_constants(h, k)), sp4(h, p, k, d))
    A, B, C = rng.normal(size=3)
    scale = np.abs(rng.normal(size=shape)) + 1.0
    same(from_abc(A, B, C, d, scale, fixed=abc_constants(A, B, C)),
         from_abc(A, B, C, d, scale))


@pytest.mark.parametrize("shape", SHAPES)
def test_sp3_fixed_is_sp3(rng, shape):
    p1, p2, k = rng.normal(size=3), rng.normal(size=3), unit(rng.normal(size=3))
    d = np.abs(rng.normal(size=shape)) * 2.0
    fixed = sp3_constants(p1, p2, k)
    same(sp3(p1, p2, k, d, fixed=fixed), sp3(p1, p2, k, d))
    scale = np.abs(rng.normal(size=shape)) * 10.0
    same(sp3(p1, p2, k, d, scale=scale, fixed=fixed), sp3(p1, p2, k, d, scale=scale))


def test_sp3_fixed_on_the_axis_is_free():
    """p1 on the axis: every angle or none (ill-posed), the same with the constants."""
    k = np.array([0.0, 0.0, 1.0])
    p1, p2 = 2.0 * k, np.array([1.0, 0.0, 0.0])
    d = np.array([np.sqrt(5.0), 1.0])
    sol = sp3(p1, p2, k, d, fixed=sp3_constants(p1, p2, k))
    same(sol, sp3(p1, p2, k, d))
    assert sol.free[:, 0].all() and sol.exact[:, 0].tolist() == [True, False]


@pytest.mark.parametrize("shape", SHAPES)
def test_cone_fixed_is_cone(rng, shape):
    h, p, k = (unit(rng.normal(size=3)) for _ in range(3))
    v = unit(rng.normal(size=shape + (3,)))
    same(cone(h, p, k, v, fixed=cone_constants(h, p, k)), cone(h, p, k, v))
