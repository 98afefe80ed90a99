"""Four-joint arms whose first three joints place a point of the last axis and whose last
joint takes the orientation about it (the ``point-plus-roll`` closed form), found broken by
an independent random-robot campaign:

* an arm with two pairs of meeting axes among joints 1-3 raised "operands could not be
  broadcast" on every pose (the second pair's step read the slots from before the first
  pair's branching);
* a placement that left one joint free (the point on an axis: subproblem 5's meeting point
  on ``k2``) marked all three free, so the orientation turned none of them and the pose got
  no solution, or one that was not the generating configuration;
* three parallel joints before the roll place the point on a plane with a turn to spare:
  not this family (its placement missed by 0.2 m and the pose had no solution);
* a SCARA whose first twist is 1e-7 .. 1e-4 rad off (its point placed through the
  resultant in the slide): joint 2 from the two invariants together was 0.1 of the arm's
  size off (they barely differ) and three Gauss-Newton steps did not reach it, and the two
  elbows, which share the slide's double root, polished onto one: 8 of 20 FK poses had no
  solution.

Checked against independent values: FK round trips, the generating configuration, and
Gauss-Newton from random starts (tests/randrobots.py).
"""

import numpy as np
import pytest

from kincalc.ik.families import plan
from kincalc.model import Joint, Robot
from kincalc.spatial import rotation_error, wrap
from randrobots import newton_roots

P = np.pi


def _dh_two_pairs():
    """Axes 1, 2 and 2, 3 meet (a = 0, alpha = -+90 deg): two meeting pairs."""
    lim = (-P, P)
    return Robot(name="two_pairs", convention="dh", joints=(
        Joint("q1", "revolute", alpha=-P / 2, a=0.0, d=-0.1983640191282975,
              theta=-0.9767668763344619, limits=None),
        Joint("q2", "revolute", alpha=-P / 2, a=0.0, d=0.34192488613749084, theta=P / 2,
              limits=lim),
        Joint("q3", "revolute", alpha=P / 2, a=0.0, d=0.0, theta=0.0, limits=lim),
        Joint("q4", "revolute", alpha=-P / 2, a=-0.286256151340482, d=0.36236386463394066,
              theta=P, limits=None)), base=np.eye(4), tool=np.eye(4))


def _mdh_point_on_axis_2():
    """At q3 = 90 deg the point of axis 4 lies on axis 2: joint 2 alone is free."""
    lim = (-P, P)
    return Robot(name="on_axis_2", convention="mdh", joints=(
        Joint("q1", "revolute", alpha=-P / 2, a=0.0, d=0.0, theta=0.0, limits=lim),
        Joint("q2", "revolute", alpha=P / 2, a=0.3517392777978464, d=-0.11743204890888992,
              theta=-2.057587276535881, limits=lim),
        Joint("q3", "revolute", alpha=P / 2, a=0.0, d=0.0, theta=P, limits=lim),
        Joint("q4", "revolute", alpha=-P / 2, a=-0.20957059439657066, d=0.0, theta=P / 2,
              limits=lim)), base=np.eye(4), tool=np.eye(4))


def _poe(axes, points, M):
    lim = (-2 * P, 2 * P)
    return Robot(name="poe4", convention="poe", joints=tuple(
        Joint(f"q{i + 1}", "revolute", axis=a, point=p, limits=lim)
        for i, (a, p) in enumerate(zip(axes, points))), M=np.array(M, float))


def _poe_on_axis():
    """At q = (180, 90, 0, 90) deg a placement joint is free; the other joints are not."""
    c = 6.123233995736766e-17
    return _poe([(-1, 0, 0), (0, 1, 0), (0, 0, -1), (0, 0, -1)],
                [(-0.2, 0, 0.1), (0, -0.2, 0), (0.3, 0.1, 0.1), (0, -0.2, 0)],
                [[1, 0, 0, -0.1], [0, c, 1, 0.1], [0, -1, c, -0.1], [0, 0, 0, 1]])


def _assert_solves(robot, q):
    T = robot.fk(q)
    res = robot.ik(T)
    S = np.array([s.q for s in res.solutions]).reshape(-1, robot.dof)
    Tq = robot.fk(S)
    L = robot.characteristic_length
    assert np.abs(Tq[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * L
    assert rotation_error(Tq[:, :3, :3], T[:3, :3]).max() <= 1e-9
    if not any(np.any(s.free) for s in res.solutions):    # (a continuum shows one point)
        assert np.abs(wrap(S - q)).max(-1).min() < 1e-9, np.degrees(S)
    return S


def test_two_meeting_pairs_every_pose():
    """Every pose of the arm solved (each solution reproducing it, the generating one
    among them), each solution labelled apart: the second root of a pair's step is the
    ``other root`` (two solutions had shared "elbow down q2:+")."""
    robot = _dh_two_pairs()
    assert plan(robot)[1].name == "point-plus-roll"
    Q = np.random.default_rng(4).uniform(-P, P, (40, 4))
    Q[:10, 2] = np.radians([0, 90, -90, 180, 0, 90, -90, 180, 0, 90])     # special elbows
    for q in Q:
        _assert_solves(robot, q)
    solved = robot.ik_batch(robot.fk(Q))                                  # and as one batch
    assert solved.valid.any(-1).all()
    for i in range(len(Q)):                                  # every solution its own label
        labels = solved.labels[i][solved.valid[i]].tolist()
        assert len(set(labels)) == len(labels), labels


@pytest.mark.parametrize("make, q", [
    (_mdh_point_on_axis_2, [-147.8854170080044, -160.3515767652024, 90.0, -90.0]),
    (_poe_on_axis, [180.0, 90.0, 0.0, 90.0])])
def test_a_free_placement_joint_takes_the_orientation(make, q):
    robot = make()
    assert plan(robot)[1].name == "point-plus-roll"
    q = np.radians(q)
    S = _assert_solves(robot, q)
    roots = newton_roots(robot, robot.fk(q), 60, np.random.default_rng(8))
    for r in roots:                                   # every root Gauss-Newton finds
        assert np.abs(wrap(S - r)).max(-1).min() < 1e-6


def test_three_parallel_joints_before_the_roll_are_not_point_plus_roll():
    """They place a point of axis 4 only on a plane, with a turn to spare: the orientation
    decides it (planar-4, tests/ik/test_planar_4.py), and both elbows come back (this arm
    was once solved numerically, one solution)."""
    robot = _poe([(0, 1, 0), (0, -1, 0), (0, 1, 0), (-1, 0, 0)],
                 [(0.1, -0.2, 0.3), (0, 0.1, -0.2), (-0.2, -0.2, 0), (0, 0, 0.1)],
                 [[0, -1, 0, 0], [0, 0, 1, 0], [-1, 0, 0, 0], [0, 0, 0, 1]])
    assert plan(robot)[1].name == "planar-4"
    q = np.radians([-74.78, -12.16, -138.59, -348.08])
    T = robot.fk(q)
    res = robot.ik(T)
    assert len(res.solutions) == 2
    Tq = robot.fk(np.array([s.q for s in res.solutions]))
    assert np.abs(Tq - T).max() < 1e-12
    assert min(np.abs(wrap(s.q - q)).max() for s in res.solutions) < 1e-9


@pytest.mark.parametrize("twist, at", [(1e-7, 0), (-1e-6, 0), (1e-5, 1), (-3e-4, 1)])
def test_nearly_a_scara(twist, at):
    """Joints 1-2 about nearly parallel axes (one twist ``twist`` rad), a vertical slide,
    the roll: every FK pose solved, each solution reproducing it, the generating joints and
    every root Gauss-Newton finds among them."""
    alpha = [0.0, 0.0]
    alpha[at] = twist
    robot = Robot(name="nearly_scara", convention="dh", base=np.eye(4), tool=np.eye(4), joints=(
        Joint("j1", "revolute", alpha=alpha[0], a=0.3, d=0.4, theta=0.0, limits=(-P, P)),
        Joint("j2", "revolute", alpha=alpha[1], a=0.25, d=0.05, theta=0.0, limits=(-P, P)),
        Joint("j3", "prismatic", alpha=0.0, a=0.0, d=0.0, theta=0.0, limits=(-1.0, 1.0)),
        Joint("j4", "revolute", alpha=0.0, a=0.0, d=0.1, theta=0.0, limits=(-P, P))))
    assert plan(robot)[1].name == "point-plus-roll"
    rng = np.random.default_rng(9)
    for i, q in enumerate(rng.uniform([-3, -3, -0.5, -3], [3, 3, 0.5, 3], (20, 4))):
        S = _assert_solves(robot, q)
        if i < 3:                                     # every root Gauss-Newton finds
            for r in newton_roots(robot, robot.fk(q), 40, np.random.default_rng(10)):
                d = np.where(robot.is_revolute, wrap(S - r), S - r)
                assert np.abs(d).max(-1).min() < 1e-6


#: an R-R-P-R arm of an independent campaign (standard DH: alpha, a, d, theta, kind) whose
#: slide's resultant has four real roots within 0.02 m at the pose of CLUSTER_Q: fitted over
#: the slide's whole span the four came out as two complex pairs 4e-4 off in the poe form
#: of the arm (the dh form's span found them): the pose had no solution in poe
CLUSTER_ARM = [(-1.5707963267948966, -0.06515448300587022, -0.034090608231901021,
                0.79965170995514478, "revolute"),
               (1.5707963267948966, 0.0, 0.0, 0.85018275849967218, "revolute"),
               (-1.0012709491905987, 0.0, 0.34760298939275847, -3.0011723173662355,
                "prismatic"),
               (-1.3578144153375622, -0.041173832521621968, -0.010183119352870541,
                -2.4394620395296247, "revolute")]
CLUSTER_TOOL = [[-0.57697728453721786, 0.80602697717007521, 0.1319762296859906,
                 0.26179740364299192],
                [0.61006230296146713, 0.31785960223516718, 0.72580249363876692,
                 0.031628051456224493],
                [0.54306647809767195, 0.49928527450844407, -0.67512444410317274,
                 -0.15091477329357075], [0, 0, 0, 1]]
CLUSTER_Q = [1.6673583962715002, -0.6290628099311482, -0.3395842475724461, 1.0605839862390827]


def test_close_roots_of_the_slide_are_found_in_every_convention():
    from kincalc.conventions import dh_to_mdh, to_poe
    joints = tuple(Joint(f"j{i + 1}", kind, alpha=al, a=a, d=d, theta=th,
                         limits=(-1.2, 1.2) if kind == "prismatic" else (-np.pi, np.pi))
                   for i, (al, a, d, th, kind) in enumerate(CLUSTER_ARM))
    r = Robot(name="cluster", convention="dh", joints=joints, tool=np.array(CLUSTER_TOOL))
    q0 = np.array(CLUSTER_Q)
    T = r.fk(q0)
    answers = []
    for arm in (r, dh_to_mdh(r), to_poe(r)):
        assert plan(arm)[1].name == "point-plus-roll"
        Q = np.array([s.q for s in arm.ik(T).solutions]).reshape(-1, 4)
        assert len(Q) and np.abs(arm.fk(Q) - T).max() < 1e-9
        d = np.abs(np.where(arm.is_revolute, wrap(Q - q0), Q - q0)).max(-1)
        assert d.min() < 1e-9, (arm.convention, Q)
        answers.append(np.sort(np.round(Q, 7), axis=0))
    assert all(np.array_equal(a, answers[0]) for a in answers)


#: an R-R-P-R arm whose axes meet at one point (all lengths zero but the slide) with random
#: twists: at the slide's 0 the point of axis 4 lies where axes 1 and 2 meet (the random-robot
#: campaign's rrpr413)
MEETING_ARM = """name: meeting
convention: dh
units: {length: m, angle: rad}
joints:
  - {name: j1, type: revolute, alpha: -1.5707963267948966, a: 0, d: 0, theta: 1.7810902952702854}
  - {name: j2, type: revolute, alpha: 1.5707963267948966, a: 0, d: 0, theta: -1.7083483440335729}
  - {name: j3, type: prismatic, alpha: 1.2797042898941962, a: 0, d: 0, theta: -1.4433224169410506, limits: [-0.4, 0.4]}
  - {name: j4, type: revolute, alpha: 2.0391319636298473, a: 0, d: 0, theta: -0.12828174295808559}
base: [[0.45815793333931709, 0.60772877466010755, 0.64865787944676212, -0.10422208830080726], [0.41464286309215603, 0.49936626183989274, -0.76072638486041178, -0.16114988466626923], [-0.78623317419515293, 0.61749418862542815, -0.023201784604609088, 0.3846813473834455], [0, 0, 0, 1]]
tool: [[-0.4570673152733602, -0.016888886670727687, 0.88927174407816767, -0.067853927677517467], [-0.69336409826750134, 0.63298262582551401, -0.34435333980772143, 0.26441434095132949], [-0.55707781910833387, -0.77398175747885722, -0.30102581707794074, 0.051722411544946612], [0, 0, 0, 1]]
"""


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_the_slide_at_the_shoulder_centre_leaves_the_orientation_to_joints_1_2_4(convention):
    """With the slide at 0 the point lies on axes 1 and 2: both are free for the point, and
    with joint 4 they take the orientation (their axes meet there). Subproblem 1 judged joint
    1's point on its axis against the point's own length, itself rounding there, so joint 1
    was not free and a whole pose from those joints had no solution ("orientation not
    reachable"). Now the generating joints are among the solutions, every one reaching it."""
    from kincalc import parse_robot_text
    from kincalc.conventions.conversion import convert
    dh = parse_robot_text(MEETING_ARM)
    r = dh if convention == "dh" else convert(dh, convention)
    rng = np.random.default_rng(91)
    for _ in range(10):
        q = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), 0.0, rng.uniform(-3, 3)])
        T = dh.fk(q)
        Q = np.array([s.q for s in r.ik(T).solutions]).reshape(-1, 4)
        assert len(Q) and np.abs(r.fk(Q) - T).max() < 1e-9, q
        d = np.abs(np.where(r.is_revolute, wrap(Q - q), Q - q)).max(-1)
        assert d.min() < 1e-7, (q, Q)


#: an R-R-P-R arm of a fuzz campaign, as URDF: joint 2's axis turned a right angle written
#: with a few digits (TWIST), its slide turned by (0, -0.4, 0.7)
NEARLY_RIGHT_URDF = """<?xml version="1.0"?>
<robot name="r">
  <link name="l0"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <joint name="j0" type="revolute"><parent link="l0"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j1" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.3 0.05 0" rpy="TWIST 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.2 0 0.02" rpy="0 -0.4 0.7"/><axis xyz="1 0 0"/>
    <limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="continuous"><parent link="l3"/><child link="l4"/>
    <origin xyz="0 0.1 0.25" rpy="0 0 0"/><axis xyz="0 0 1"/></joint>
</robot>
"""


@pytest.mark.parametrize("twist", ["1.5708", "1.57079633", "1.5707963"])
def test_a_right_angle_written_with_few_digits_places_the_point(tmp_path, twist):
    """Axes 1 and 2 some 1e-8 .. 4e-6 rad from parallel: the point of axis 1 nearest to
    axis 2, from which the placement measured its distances, lay up to 1e6 m away, and the
    distances squared from there (1e12 m^2) kept nothing of the arm: 28 .. 78 % of FK
    poses had no solution ("orientation unreachable"). Every pose solved now, each solution
    reproducing it, the generating joints and every root Gauss-Newton finds among them."""
    from kincalc import load_robot
    path = tmp_path / "arm.urdf"
    path.write_text(NEARLY_RIGHT_URDF.replace("TWIST", twist))
    robot = load_robot(str(path))
    assert plan(robot)[1].name == "point-plus-roll"
    rng = np.random.default_rng(4)
    for i, q in enumerate(rng.uniform([-2.4, -2.4, -0.5, -3], [2.4, 2.4, 0.5, 3], (30, 4))):
        S = _assert_solves(robot, q)
        if i < 3:
            for r in newton_roots(robot, robot.fk(q), 40, np.random.default_rng(10)):
                d = np.where(robot.is_revolute, wrap(S - r), S - r)
                assert np.abs(d).max(-1).min() < 1e-6


@pytest.mark.parametrize("offset", [1e-13, 1e-11, 1e-10, 1e-9, 3e-8, 1e-7, 1e-5, 1e-4])
def test_the_last_axis_a_hair_off_the_placing_joints_axis(offset):
    """An independent tester's 4R arm (modified DH) whose last axis passes ``offset`` m from
    axis 3 (a3 written 1e-9 where it is 0): its point of axis 4 lay that far from axis 3,
    which then moved it on a tiny circle, and the placement (subproblem 5, or the plan for a
    point on the axis) found no solution on any pose for offsets of 1e-11 to 1e-5 m (0 %
    in selftest; the same arm with 0 had every pose). Every FK pose is solved, with the
    generating configuration and every root Gauss-Newton finds."""
    D = np.radians
    robot = Robot(name="hair", convention="mdh", base=np.eye(4), tool=np.eye(4), joints=(
        Joint("j1", "revolute", alpha=D(90), a=0.0, d=0.0, theta=D(-114.66),
              limits=(-D(170), D(170))),
        Joint("j2", "revolute", alpha=D(90), a=0.5, d=0.0, theta=D(57.3), limits=(-P, P)),
        Joint("j3", "revolute", alpha=D(90), a=0.0, d=0.0, theta=D(109.52), limits=(-P, P)),
        Joint("j4", "revolute", alpha=D(90), a=offset, d=0.076, theta=0.0, limits=(-P, P))))
    assert plan(robot)[1].name == "point-plus-roll"
    rng = np.random.default_rng(21)
    Q = rng.uniform(-2.9, 2.9, (25, 4))
    Q[0] = D([90, 90, 90, 90])
    for i, q in enumerate(Q):
        S = _assert_solves(robot, q)
        if i < 3:
            for r in newton_roots(robot, robot.fk(q), 40, np.random.default_rng(22)):
                assert np.abs(wrap(S - r)).max(-1).min() < 1e-6
