"""Quantities of the joint values fitted as polynomials (kincalc.ik.joint_polynomials),
against functions written out by hand and, for the branch labels, the words read from
each solution's frames."""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.fk import entry_frames
from kincalc.ik import words as L
from kincalc.ik.families import plan
from kincalc.ik.joint_polynomials import fit
from kincalc.ik.selftest import sample_configurations


def _by_hand(Q):
    """Three quantities of a R-P-R-R chain's values, written out: degrees (1, 0, 1, 0),
    (0, 2, 2, 0) and none."""
    q1, d2, q3, _ = Q.T
    return np.array([0.3 + 2.0 * np.cos(q1 + 0.4) * np.sin(q3) - np.sin(q1),
                     d2 * d2 * np.cos(2 * q3) - 0.5 * d2 + np.sin(q3) ** 2,
                     np.full(len(Q), -1.25)])


def test_degrees_and_values_of_quantities_written_by_hand():
    revolute = np.array([True, False, True, True])
    P = fit(_by_hand, revolute, 0.7, np.ones(3))
    assert P is not None
    found = {int(r): (g.joints, g.degrees) for g in P.groups for r in g.rows}
    assert found == {0: ((0, 2), (1, 1)), 1: ((1, 2), (2, 2)), 2: ((), ())}
    Q = np.random.default_rng(11).uniform(-4, 4, (1000, 4))
    assert np.allclose(P(Q), _by_hand(Q), rtol=0, atol=1e-12)


def test_a_quantity_that_is_not_a_polynomial_is_refused():
    def bad(Q):
        return np.sqrt(2.0 + np.cos(Q[:, 0]))[None]
    assert fit(bad, np.array([True, True]), 1.0, np.ones(1)) is None


@pytest.mark.parametrize("name", ["puma560", "ur5", "kuka_kr16", "stanford_arm", "bk_rrp",
                                  "spong_scara", "fer_rrpr", "planar_3r", "lynxmotion_al5d",
                                  "spong_spherical_rrp", "mycobot_280"])
def test_label_products_fitted_equal_those_of_the_frames(name):
    """The products the words are read from, at 2,000 seeded configurations: fitted against
    evaluated from each configuration's frames."""
    r = load_robot(name)
    family = plan(r)[1].name
    R = L.rules(r, family)
    Q = sample_configurations(r, 2000, np.random.default_rng(4))
    want = L.products(R, r.dof, entry_frames(r.chain, Q))
    got = L._fitted(r, family)(Q)
    size = R.sizes[:, None]
    assert np.all(np.abs(got - want) <= 1e-12 * size + 1e-12 * np.abs(want))


def test_words_from_the_frames_where_no_fit(monkeypatch):
    """The frames' products stand in where a fit fails: the same codes."""
    r = load_robot("puma560")
    family = plan(r)[1].name
    Q = sample_configurations(r, 300, np.random.default_rng(8))
    fitted = L.branch_geometry(r, family, Q)
    monkeypatch.setattr(L, "_fitted", lambda robot, fam: None)
    assert np.array_equal(L.branch_geometry(r, family, Q), fitted)


def test_spread_points_fill_the_box_evenly_and_repeat():
    """Every coordinate within its box, no two points alike, each joint's values spread
    over its range (a quarter of the points in each quarter, to one point), the same twice."""
    from kincalc.samples import spread
    lo = np.array([-np.pi, 0.0, -2.0, 5.0, -1, -1, -1])
    hi = np.array([np.pi, 0.3, 2.0, 6.0, 1, 1, 1])
    P = spread(400, lo, hi)
    assert P.shape == (400, 7) and np.all((P >= lo) & (P < hi))
    assert np.array_equal(P, spread(400, lo, hi))
    u = (P - lo) / (hi - lo)
    for j in range(7):
        counts = np.histogram(u[:, j], bins=4, range=(0, 1))[0]
        assert np.all(np.abs(counts - 100) <= 2), (j, counts)
    assert len(np.unique(np.round(u, 12), axis=0)) == 400
