"""Offset-wrist arms whose fourth joint is the slide: R-R-R-P about and along one direction
h, then axes 5 and 6 meeting (a SCARA-type arm with a two-axis wrist).

A slide along h commutes with turns about axes along h, so the slide is the height of axis
4's point along h, and joints 1 and 2 place axis 3's point where the total turn puts it;
joint 3 closes the turn. Such an arm went to the numerical solver (one solution) while an
R-P-R-R arm of the same family got every one (found by a random-robot campaign). Checked
from FK alone: every solution reaches the pose, the generating configuration is among them,
and so is every root Gauss-Newton finds from random starts.
"""

import numpy as np
import pytest

from kincalc.conventions import to_poe
from kincalc.ik import Target, solve
from kincalc.ik.families import plan
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import rot_z, transform, wrap
from randrobots import newton_roots


def _arm(rng, convention):
    rows = [("revolute", 0.0, rng.uniform(.1, .4), rng.uniform(0, .3)),
            ("revolute", 0.0, rng.uniform(.1, .4), 0.0),
            ("revolute", 0.0, rng.uniform(.05, .2), 0.0),
            ("prismatic", rng.uniform(.5, 2.5), 0.0, 0.0),
            ("revolute", rng.uniform(.5, 2.5), 0.0, rng.uniform(.05, .2)),
            ("revolute", 0.0, 0.0, rng.uniform(.05, .2))]
    joints = tuple(Joint(f"q{i + 1}", kind, alpha=al, a=a, d=d,
                         theta=rng.uniform(-3, 3) if kind == "revolute" else 0.0,
                         limits=(-0.5, 0.5) if kind == "prismatic" else (-np.pi, np.pi))
                   for i, (kind, al, a, d) in enumerate(rows))
    r = Robot(name="rrrp", convention="dh", joints=joints,
              tool=transform(rot_z(0.3), [0.0, 0.02, 0.05]))
    return to_poe(r) if convention == "poe" else r


def _same(robot, p, q) -> bool:
    d = np.where(robot.is_revolute, wrap(np.asarray(p) - q), np.asarray(p) - q)
    return bool(np.abs(d).max() < 1e-6)


@pytest.mark.parametrize("convention", ["dh", "poe"])
def test_every_solution_of_an_arm_whose_fourth_joint_slides(convention):
    rng = np.random.default_rng(73)
    for _ in range(3):
        r = _arm(rng, convention)
        assert plan(r)[1].name == "parallel-four-wrist"
        for q in sample_configurations(r, 4, rng):
            T = r.fk(q)
            sols = solve(r, Target(T)).solutions
            for s in sols:
                assert np.abs(r.fk(s.q) - T).max() < 1e-9
            assert any(_same(r, s.q, q) for s in sols), np.degrees(q)
            for root in newton_roots(r, T, 60, rng):
                assert any(_same(r, s.q, root) for s in sols), root
