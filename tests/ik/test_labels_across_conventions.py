"""A solution is named alike in dh, mdh and poe where a pose sits on the boundary of a branch
word (an independent random-robot campaign's cases).

* An R-R-R-P arm (a point-plus-roll arm, solved reversed) at q = 0, its elbow stretched: two
  candidates, each polished onto the double root from its side, stopped 1.4e-6 rad either
  side of it, and which was kept depended on the convention (``q2:root 1`` in dh, ``q2:root
  2`` in poe). Met only in the check after the polish, they were not answered at their
  middle, as two copies met in the first check are.
* A spherical-wrist arm of general twists at q5 = 0, where the wrist's flip word changes
  sign: found at q5 = 0 in dh and at -4.7e-8 in poe (a double root, to the square root of
  rounding), it was ``shoulder left q5:+`` in dh and ``shoulder left wrist no-flip q1:root 3
  q5:+`` in poe.
"""

import numpy as np
import pytest

from kincalc.conventions.conversion import convert
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap

#: (alpha, a, d, theta, type), standard DH, rad and m; the tool; the generating joints
RRRP = ([(0.0, 0.33307779788817937, 0.0, -2.9193101109138735, "revolute"),
         (0.0, -0.33173059666801324, 0.0, 0.0, "revolute"),
         (0.0, 0.0, -0.27758222191994186, 0.0, "revolute"),
         (0.0, 0.0, 0.0, 0.0, "prismatic")],
        [[-0.6325634384772064, -0.757828095810917, -0.15987518100534884, -0.3669238958732738],
         [-0.44489693916683976, 0.18656672227046567, 0.8759335429478837, -0.3095709159228104],
         [-0.6339796604165395, 0.6252115124826594, -0.45517068758573936, 0.0],
         [0.0, 0.0, 0.0, 1.0]],
        [0.0, 0.0, 0.0, 0.0])
WRIST = ([(np.pi / 2, -0.5698181889874234, 0.0, -1.489089287031482, "revolute"),
          (np.pi / 2, 0.42288867744827613, 0.0, -0.7698424452309824, "revolute"),
          (-np.pi / 2, 0.40329390855553204, -0.30154715282743677, 1.7943378857812666,
           "revolute"),
          (np.pi / 2, 0.0, -0.3707006728453941, 0.0, "revolute"),
          (0.8425053293858786, 0.0, 0.0, 0.0, "revolute"),
          (2.4918294555165863, 0.0, 0.08096956414416415, -2.560555842887037, "revolute")],
         [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.5899438705219205],
          [0.0, 0.0, 0.0, 1.0]],
         [1.8483606450172338, -0.3713819237588143, 2.9251806228696537, -2.694705379399845,
          0.0, -0.23662862119727812])


#: the same wrist arm in poe as the campaign wrote it (axis, point at q = 0; the tool M)
WRIST_POE = ([([0.0, 0.0, 1.0], [0.0, 0.0, 0.0]),
              ([-0.9966638364764513, -0.08161615685660281, 6.123233995736766e-17],
               [-0.0465063706921429, 0.567917182330269, 0.0]),
              ([-0.056806650500188884, 0.6937000761303881, -0.7180203401266869],
               [-0.02172422274443434, 0.2652875119197094, -0.2943398736906811]),
              ([0.16380091903569333, 0.7159120879601419, 0.6787040159271287],
               [-0.4017809535383664, 0.08798763309764782, -0.015595732219972736]),
              ([-0.056806650500188884, 0.6937000761303881, -0.7180203401266869],
               [-0.46250206443759184, -0.17740145960732775, -0.2671917675870304]),
              ([-0.16005698599908266, -0.07257108395915303, -0.9844364880508458],
               [-0.46250206443759184, -0.17740145960732775, -0.2671917675870304])],
             [[0.786663258958465, 0.3779353696264636, 0.4881862077016874, -0.18745934792521446],
              [-0.611804732334036, 0.5832610498729965, 0.534323420032033, 0.13194331787923755],
              [-0.08280028078772032, -0.719007235072331, 0.690052685970511, 0.0601911914733716],
              [0.0, 0.0, 0.0, 1.0]])


def poe_arm(joints, tool) -> Robot:
    return Robot(name="boundary", convention="poe", M=np.array(tool), joints=tuple(
        Joint(f"q{i + 1}", "revolute", axis=np.array(k), point=np.array(p))
        for i, (k, p) in enumerate(joints)))


def arm(rows, tool) -> Robot:
    return Robot(name="boundary", convention="dh", tool=np.array(tool), joints=tuple(
        Joint(f"q{i + 1}", kind, alpha=al, a=a, d=d, theta=th)
        for i, (al, a, d, th, kind) in enumerate(rows)))


@pytest.mark.parametrize("rows, tool, q", [RRRP, WRIST], ids=["RRRP stretched", "wrist q5=0"])
def test_the_generating_solution_is_named_alike_in_every_convention(rows, tool, q):
    r0 = arm(rows, tool)
    q = np.array(q)
    T = r0.fk(q)
    named = {}
    robots = {c: convert(r0, c) for c in ("dh", "mdh", "poe")}
    if rows is WRIST[0]:
        robots["campaign's poe"] = poe_arm(*WRIST_POE)
    for convention, r in robots.items():
        sols = r.ik(T).solutions
        assert all(np.abs(r.fk(s.q) - T).max() < 1e-12 for s in sols)
        d = [np.abs(np.where(r.is_revolute, wrap(s.q - q), s.q - q)).max() for s in sols]
        # at the stretched elbow's double root the pose is reached to rounding 1e-6 rad
        # from the generating joints (the two copies once stopped 1.4e-6 either side)
        assert min(d) < 1e-5, convention
        named[convention] = sorted(s.branch for s in sols)
    assert all(v == named["dh"] for v in named.values()), named
