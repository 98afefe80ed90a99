"""The subproblems' shared helpers: the solution set's negation and the vector products
the subproblems are written with, against numpy's own and against a second formulation."""

import numpy as np
import pytest

from kincalc.subproblems import sp1, sp4
from kincalc.subproblems.solutions import cross, dot, pair


def test_negated_is_the_answer_about_the_reversed_axis():
    """R(-k, t) = R(k, -t): solving about -k gives the negated angles of solving about k."""
    rng = np.random.default_rng(7)
    k = rng.normal(size=3)
    k /= np.linalg.norm(k)
    p1, p2 = rng.normal(size=(2, 5, 3))
    h, p = rng.normal(size=(2, 5, 3))
    d = rng.uniform(-0.5, 0.5, 5)
    for mine, other in ((sp1(p1, p2, k).negated(), sp1(p1, p2, -k)),
                        (sp4(h, p, k, d).negated(), sp4(h, p, -k, d))):
        assert np.array_equal(mine.ok.sum(-1), other.ok.sum(-1))
        for i in range(len(mine.ok)):          # the same roots (the slots may be swapped)
            for x, y in ((mine.theta[0], other.theta[0]), (mine.c[0], other.c[0]),
                         (mine.s[0], other.s[0])):
                np.testing.assert_allclose(np.sort(x[i][mine.ok[i]]),
                                           np.sort(y[i][other.ok[i]]), atol=1e-12)


@pytest.mark.parametrize("shapes", [((3,), (4, 2, 3)), ((4, 2, 3), (3,)), ((4, 2, 3),) * 2,
                                    ((4, 1, 3), (4, 2, 3)), ((3,), (3,)), ((0, 3), (3,)),
                                    ((3,), (0, 2, 3))])
def test_dot_and_cross_match_numpy_for_every_layout(shapes):
    rng = np.random.default_rng(11)
    a, b = (rng.normal(size=s) for s in shapes)
    np.testing.assert_allclose(cross(a, b), np.cross(a, b), atol=1e-14)
    np.testing.assert_allclose(dot(a, b), (a * b).sum(-1), atol=1e-14)
    assert np.shape(dot(a, b)) == np.broadcast_shapes(a.shape, b.shape)[:-1]
    assert cross(a, b).shape == np.broadcast_shapes(a.shape, b.shape)


def test_pair_stacks_two_slots_of_any_broadcastable_pair():
    m = np.array([[True, False]])
    assert pair(True, m).tolist() == [[[True, True], [True, False]]]
    assert pair(m, m).shape == (1, 2, 2)
    x = np.arange(3.0)
    assert pair(x, 0.0).tolist() == [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]
    assert pair(x, -x)[..., 1].tolist() == [0.0, -1.0, -2.0]
