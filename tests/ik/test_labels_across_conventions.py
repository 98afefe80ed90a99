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


#: a UR-type arm of general twists (the campaign's, in rad) and the poe file that ``kincalc
#: convert`` writes of it (14 significant digits: a robot 1e-14 away)
UR_DH = """name: ur
convention: dh
units: {length: m, angle: rad}
joints:
  - {name: j1, type: revolute, alpha: -0.5144357970253287, a: 0.0, d: -0.2762,
     theta: 3.0075513670366285}
  - {name: j2, type: revolute, alpha: 0.0, a: -0.3209, d: 0.1935, theta: -2.489712177969911}
  - {name: j3, type: revolute, alpha: 0.0, a: 0.2497, d: 0.0, theta: 0.0}
  - {name: j4, type: revolute, alpha: 1.8037105154735398, a: 0.0, d: 0.0311, theta: 0.0}
  - {name: j5, type: revolute, alpha: -2.436235289688805, a: 0.0, d: 0.0, theta: 0.0}
  - {name: j6, type: revolute, alpha: -1.8101333271208788, a: -0.0533, d: -0.0329, theta: 0.0}
base: {xyz: [0.2822, 0.1755, -0.1666],
       rpy: [-0.8620355708525193, -1.5839910159399737, 0.7472801725338922]}
tool: {xyz: [-0.0451, 0.1521, -0.0267],
       rpy: [0.8022754972642334, -0.4517261170011724, 0.8029910822575512]}
"""
UR_POE = """name: ur
convention: poe
units: {length: m, angle: rad}
joints:
  - {name: j1, type: revolute, axis: [0, 0, 1], point: [0, 0, 0]}
  - {name: j2, type: revolute, axis: [-0.065756853981424, -0.48763007189051, 0.87057047339232],
     point: [0, 0, -0.2762]}
  - {name: j3, type: revolute, axis: [-0.065756853981424, -0.48763007189051, 0.87057047339232],
     point: [-0.28818355979258, -0.22823125599286, -0.20353783891737]}
  - {name: j4, type: revolute, axis: [-0.065756853981424, -0.48763007189051, 0.87057047339232],
     point: [-0.073841820140884, -0.12406002875887, -0.128998828596272]}
  - {name: j5, type: revolute, axis: [0.51019410873139, -0.63366404729848, -0.58152544791874],
     point: [-0.075886858299706, -0.139225323994665, -0.10192408687377]}
  - {name: j6, type: revolute, axis: [-0.35380202687712, 0.060100755222141, 0.93338739277932],
     point: [-0.075886858299706, -0.139225323994665, -0.10192408687377]}
base: {xyz: [0.2822, 0.1755, -0.1666],
       rpy: [2.27955708273727, -1.55760163764982, -2.3943124810559]}
tool: {xyz: [-0.075644519012213, -0.2469735749355, -0.28167098496014],
       rpy: [-1.0027983655312, 0.58343351323581, 0.58679876678898]}
"""


def test_a_wrist_at_q5_180_is_named_alike_in_the_poe_file_convert_writes(tmp_path):
    """The UR-type arm at q5 = 180 deg, the wrist's flip boundary: in its dh file the double
    root is found at q5 = -180, in the poe file ``convert`` writes (a robot 1e-14 away) at
    179.9999836 deg, 2.9e-7 rad off, which the wrist word took as ``no-flip`` (campaign
    case). Both solutions reach the pose in both files, and are named alike."""
    from kincalc import load_robot
    q = np.radians([41.79595799306966, -24.893254768947955, -31.370637322935107,
                    45.98822826334494, 180.0, 6.024518181892522])
    named = {}
    for name, text in (("dh", UR_DH), ("poe", UR_POE)):
        (tmp_path / f"{name}.yaml").write_text(text)
        r = load_robot(str(tmp_path / f"{name}.yaml"))
        T = load_robot(str(tmp_path / "dh.yaml")).fk(q) if name == "poe" else r.fk(q)
        sols = [s for s in r.ik(T).solutions if abs(abs(s.q[4]) - np.pi) < 1e-3]
        assert len(sols) == 2 and all(np.abs(r.fk(s.q) - T).max() < 1e-9 for s in sols)
        named[name] = sorted(s.branch for s in sols)
    assert named["dh"] == named["poe"] == ["shoulder right elbow down j5:+",
                                            "shoulder right elbow up j5:+"], named
