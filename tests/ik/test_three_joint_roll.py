"""Three-joint arms whose tool turns about the last (revolute) axis: joints 1 and 2 place a
point of axis 3 on the surface they sweep, joint 3 takes the orientation about its axis
(the ``point-plus-roll`` closed form with two placing joints).

Such an arm (R-P-R, P-R-R, R-R-R with its tool point on axis 3) was "no analytic solver for
this structure yet" and got one numerical solution of two (found by a rerun of the
random-robot campaign). Checked against Gauss-Newton from 100 random starts: every root it
finds is among kincalc's, and kincalc's reach the pose.
"""

import numpy as np
import pytest

from kincalc.ik import Target, solve
from kincalc.ik.families import plan
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, rot_z, transform, wrap
from randrobots import newton_roots


def _arm(rng, kinds):
    t = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731
    u = lambda: rng.uniform(0.1, 0.4) * rng.choice([-1, 1])  # noqa: E731
    rows = [(k, t(), u(), u(), rng.uniform(-3, 3)) for k in kinds]
    rows.append(("revolute", 0.0, 0.0, u(), rng.uniform(-3, 3)))        # the tool on axis 3
    joints = tuple(Joint(f"q{i + 1}", k, alpha=al, a=a, d=d, theta=th,
                         limits=(-np.pi, np.pi) if k == "revolute" else (-0.5, 0.5))
                   for i, (k, al, a, d, th) in enumerate(rows))
    base = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.3, .3, 3))
    return Robot(name="roll3", convention="dh", joints=joints, base=base,
                 tool=transform(rot_z(rng.uniform(-3, 3)), [0, 0, u()]))


@pytest.mark.parametrize("kinds", [("revolute", "prismatic"), ("prismatic", "revolute"),
                                   ("revolute", "revolute")])
def test_three_joint_arm_turning_its_tool_about_axis_3(kinds):
    rng = np.random.default_rng(81 + len(kinds[0]) + 3 * len(kinds[1]))
    for _ in range(4):
        r = _arm(rng, kinds)
        assert plan(r)[1].name == "point-plus-roll"
        for q in sample_configurations(r, 4, rng):
            T = r.fk(q)
            sols = solve(r, Target(T)).solutions
            assert sols and all(np.allclose(r.fk(s.q), T, atol=1e-9) for s in sols)
            for root in newton_roots(r, T, 100, rng) + [q]:
                assert any(np.all(np.abs(np.where(r.is_revolute, wrap(s.q - root), s.q - root))
                                  < 1e-6) for s in sols), root
