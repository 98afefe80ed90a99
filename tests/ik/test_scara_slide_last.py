"""An R-R-R-P SCARA (three parallel revolute axes, then the slide along them) has a closed
form: on the chain reversed it is a point-plus-roll arm (the slide and two turns place a
point of axis 1, which then turns the tool about it). It used to be solved numerically:
one solution of two (found by an independent random-robot campaign).

Checked by FK on seeded random arms in dh, mdh and poe: exactly two solutions, elbow up and
elbow down, both reaching the pose, the generating configuration among them.
"""

import numpy as np
import pytest

from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik import Target, solve
from kincalc.ik.families import plan
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap

CONVENTIONS = ["dh", "mdh", "poe"]


def _scara(rng, convention):
    rows = [("revolute", rng.uniform(-.1, .1), rng.uniform(.2, .4)),
            ("revolute", rng.uniform(.15, .35), rng.uniform(-.1, .1)),
            ("revolute", rng.uniform(.1, .3), rng.uniform(-.1, .1)),
            ("prismatic", rng.uniform(-.1, .1), rng.uniform(-.1, .1))]
    joints = tuple(Joint(f"q{i + 1}", kind, alpha=0.0, a=a, d=d, theta=rng.uniform(-3, 3),
                         limits=(-np.pi, np.pi) if kind == "revolute" else (-0.3, 0.3))
                   for i, (kind, a, d) in enumerate(rows))
    base = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.3, .3, 3))
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.1, .1, 3))
    r = Robot(name="rrrp", convention="dh", joints=joints, base=base, tool=tool)
    return {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_rrrp_scara_has_both_elbows(convention):
    rng = np.random.default_rng(61 + CONVENTIONS.index(convention))
    for _ in range(6):
        r = _scara(rng, convention)
        assert plan(r)[1].name == "reversed-point-plus-roll"
        for q in sample_configurations(r, 15, rng):
            T = r.fk(q)
            sols = solve(r, Target(T)).solutions
            assert len(sols) == 2
            assert sorted(s.branch for s in sols) == ["elbow down", "elbow up"]
            for s in sols:
                assert np.allclose(r.fk(s.q), T, atol=1e-9)
            assert any(np.all(np.abs(np.where(r.is_revolute, wrap(s.q - q), s.q - q)) < 1e-6)
                       for s in sols)
