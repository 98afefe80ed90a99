"""A position beyond the ball that holds every tool point is out of reach without a search.

The ball (:func:`kincalc.ik.nearest.reach_ball`) is checked against the geometry: the tool
points of many random configurations (revolute joints at any angle, prismatic ones
anywhere within their limits) all lie in it. A target beyond it is answered at once as
beyond the outer reach; the numerical search is not run.
"""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.ik import numeric
from kincalc.ik.nearest import beyond_reach, reach_ball, samples
from kincalc.ik.reasons import OutOfReach

ROBOTS = ["iiwa14", "panda", "puma560", "ur5", "kuka_kr16", "stanford_arm"]


@pytest.mark.parametrize("name", ROBOTS)
def test_every_tool_point_lies_in_the_ball(name):
    r = load_robot(name)
    center, radius = reach_ball(r)
    lim = r.limits.copy()
    lim[r.is_revolute] = [-np.pi, np.pi]              # the bound ignores revolute limits
    Q = samples(r, 5000, 7, lim)
    slides = ~np.asarray(r.is_revolute)
    Q[:1000, slides] = lim[slides, np.random.default_rng(1).integers(0, 2, (1000, slides.sum()))]
    d = np.linalg.norm(r.fk(Q)[:, :3, 3] - center, axis=1)
    assert np.isfinite(radius) and d.max() <= radius * (1 + 1e-12)
    assert not beyond_reach(r, r.fk(Q[np.argmax(d)])[:3, 3])  # the farthest is not refused
    assert d.max() > 0.7 * radius                      # and the ball is not loose


def test_an_unbounded_slide_has_no_ball(tmp_path):
    path = tmp_path / "slide.yaml"
    path.write_text("name: slide\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                    "  - {name: j1, type: revolute, alpha: 90, a: 0, d: 0.3, theta: 0}\n"
                    "  - {name: j2, type: prismatic, alpha: 0, a: 0, d: 0, theta: 0}\n")
    r = load_robot(str(path))
    assert reach_ball(r)[1] == np.inf and not beyond_reach(r, [1e9, 0, 0])


@pytest.mark.parametrize("name", ["iiwa14", "panda"])
@pytest.mark.parametrize("p", [[1e9, 1e9, 1e9], [5, 5, 5], [0, 0, -3]])
def test_a_target_beyond_reach_fails_without_a_search(name, p, monkeypatch):
    r = load_robot(name)

    def refused(*a, **k):
        raise AssertionError("searched a target the bound proves out of reach")
    monkeypatch.setattr(numeric, "solve_numeric", refused)
    T = np.eye(4)
    T[:3, 3] = p
    res = r.ik(T)
    assert not res.reachable and not res.solutions and res.family == "numerical"
    assert isinstance(res.reason, OutOfReach) and res.reason.outside is not None
    center, radius = reach_ball(r)
    assert res.reason.outside.distance >= np.linalg.norm(np.array(p) - center) - radius - 1e-9


def test_reachable_targets_of_redundant_arms_are_still_solved():
    r = load_robot("iiwa14")
    rng = np.random.default_rng(11)
    for q in rng.uniform(*r.limits.T, size=(4, r.dof)):
        T = r.fk(q)
        res = r.ik(T)
        assert res.reachable and np.allclose(r.fk(res.solutions[0].q), T, atol=1e-8)
