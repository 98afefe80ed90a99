"""Five-joint arms whose axes 4 and 5 meet on the tool's approach line (``position-approach``)
asked for a whole pose where subproblem 2 has a continuum, and the same arms with axis 3
through that point too (a three-joint spherical wrist after two placing joints).

Both were found by an independent random-robot campaign, each answering "orientation not
reachable" for poses the arm reaches:

* the approach along axis 4 (joint 5 at 0 or 180 deg between two axes at right angles):
  subproblem 2 leaves joint 4 free, but joint 4 then rolls the tool about its approach, and
  a whole pose fixes that roll; joint 4 was left at a representative 0;
* axes 3, 4 and 5 through one point: the placement leaves joint 3 free (it does not move
  the point) and joints 4 and 5 alone cannot take the orientation that joints 3-5 take;
* the point where axes 4 and 5 meet on axis 1 or 2 (a shoulder or arm singularity): the
  placement leaves that joint free, and its representative set joints 4 and 5 to the
  approach with the roll about it left to chance, but the joint turns the tool about a line
  through the point as they do, and a whole pose fixes the three.

Checked by FK on seeded random arms of each kind in dh, mdh and poe: every answer reaches
the target, and the generating configuration is among the answers.
"""

import numpy as np
import pytest

from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik import Target, solve
from kincalc.ik.families import plan
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_axis_angle, matrix_from_rpy, rot_z, transform, wrap
from randrobots import follow_joint, newton_roots

CONVENTIONS = ["dh", "mdh", "poe"]


def _arm(rng, wrist_of_three: bool, convention: str):
    """Joints 1-3 random (revolute or prismatic; revolute 3 for the wrist of three), axes 4
    and 5 at right angles meeting at a point, the tool looking along axis 5's normal from a
    point on that line; with ``wrist_of_three`` axis 3 through the point as well."""
    t = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731
    u = lambda: rng.uniform(0.1, 0.4) * rng.choice([-1, 1])  # noqa: E731
    kinds = [rng.choice(["revolute", "prismatic"], p=[0.8, 0.2]) for _ in range(2)]
    rows = [(k, t(), u(), u(), rng.uniform(-3, 3)) for k in kinds]
    if wrist_of_three:
        rows += [("revolute", t(), 0.0, u(), rng.uniform(-3, 3)),
                 ("revolute", rng.choice([-1, 1]) * np.pi / 2, 0.0, 0.0, rng.uniform(-3, 3))]
    else:
        rows += [(rng.choice(["revolute", "prismatic"], p=[0.8, 0.2]), t(), u(), u(),
                  rng.uniform(-3, 3)),
                 ("revolute", rng.choice([-1, 1]) * np.pi / 2, 0.0, u(), rng.uniform(-3, 3))]
    rows.append(("revolute", rng.choice([-1, 1]) * np.pi / 2, 0.0, 0.0, 0.0))
    joints = tuple(Joint(f"q{i + 1}", k, alpha=al, a=a, d=d, theta=th,
                         limits=(-np.pi, np.pi) if k == "revolute" else (-0.5, 0.5))
                   for i, (k, al, a, d, th) in enumerate(rows))
    base = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.3, .3, 3))
    tool = transform(rot_z(rng.uniform(-3, 3)), [0, 0, rng.uniform(0.05, 0.2)])
    r = Robot(name="five", convention="dh", joints=joints, base=base, tool=tool)
    return {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]


def _same(robot, p, q, joints=slice(None)) -> bool:
    d = np.where(robot.is_revolute, wrap(p - q), p - q)[joints]
    return bool(np.all(np.abs(d) < 1e-6))


def _reaches(robot, s, T) -> bool:
    return bool(np.allclose(robot.fk(s.q), T, atol=1e-9))


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("off", [0.0, 1e-7, 1e-5, 3e-4])
def test_whole_pose_with_the_approach_along_axis_4(convention, off):
    """At the singularity and near it: subproblem 2's roots there are good to ~1e-8 rad
    only (a pose 3e-4 rad from it was 'orientation not reachable', 2e-9 rad off)."""
    rng = np.random.default_rng(31 + CONVENTIONS.index(convention))
    found = trials = 0
    for _ in range(10):
        r = _arm(rng, False, convention)
        assert plan(r)[1].name == "position-approach"
        for q in sample_configurations(r, 10, rng):
            q[4] = rng.choice([0.0, np.pi]) + rng.choice([-1, 1]) * off
            T = r.fk(q)
            res = solve(r, Target(T))
            assert all(_reaches(r, s, T) for s in res.solutions)
            trials += 1
            found += any(_same(r, s.q, q) and 3 not in s.free for s in res.solutions)
    assert found == trials, (found, trials)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_three_joint_wrist_after_two_placing_joints(convention):
    rng = np.random.default_rng(41 + CONVENTIONS.index(convention))
    found = trials = found_approach = 0
    for _ in range(10):
        r = _arm(rng, True, convention)
        assert plan(r)[1].name == "position-approach"
        for q in sample_configurations(r, 10, rng):
            T = r.fk(q)
            res = solve(r, Target(T))
            assert all(_reaches(r, s, T) for s in res.solutions)
            # the whole pose sets joint 3 too (it was listed free, with the others following)
            assert not any(s.free for s in res.solutions)
            trials += 1
            found += any(_same(r, s.q, q) for s in res.solutions)
            # the approach alone: the roll is open, joint 3 a representative of it
            P = T.copy()
            P[:3, :3] = np.eye(3)
            res = solve(r, Target(P, orientation=False, approach=T[:3, 2]))
            for s in res.solutions:
                Tq = r.fk(s.q)
                assert np.linalg.norm(Tq[:3, 3] - T[:3, 3]) < 1e-9
                assert np.linalg.norm(Tq[:3, 2] - T[:3, 2]) < 1e-9
                assert 2 in s.free
            found_approach += any(_same(r, s.q, q, slice(0, 2)) for s in res.solutions)
    assert found == trials and found_approach == trials, (found, found_approach, trials)


def _unit(rng):
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def _turned(k, o, angle, x):
    """The point ``x`` turned by ``angle`` about the line of ``k`` through ``o``."""
    return o + matrix_from_axis_angle(k, angle) @ (x - o)


def _placing_joint_on_the_point(rng, free: int):
    """``(robot, q)``: a poe arm whose axes 4 and 5 meet at ``c0`` on the tool's approach
    line, and joints ``q`` at which ``c`` lies on axis ``free + 1`` (0: a shoulder, 1: an
    arm singularity): that axis is drawn through where joints ``free + 2 ..`` 3 put ``c0``."""
    q = rng.uniform(-np.pi, np.pi, 5)
    c0 = rng.uniform(-.3, .3, 3)
    k = [_unit(rng) for _ in range(5)]
    o = [rng.uniform(-.4, .4, 3) for _ in range(3)] + [c0, c0]
    c = c0
    for i in (2, 1)[:2 - free]:
        c = _turned(k[i], o[i], q[i], c)
    o[free] = c + rng.uniform(-.3, .3) * k[free]
    a0 = _unit(rng)
    R = matrix_from_axis_angle(_unit(rng), rng.uniform(0, np.pi))
    R = matrix_from_axis_angle(np.cross(R[:, 2], a0), np.arccos(R[:, 2] @ a0)) @ R  # z = a0
    M = transform(R, c0 + rng.uniform(.05, .2) * a0)
    joints = tuple(Joint(f"q{i + 1}", "revolute", axis=tuple(k[i]), point=tuple(o[i]),
                         limits=(-np.pi, np.pi)) for i in range(5))
    return Robot(name="five", convention="poe", joints=joints, M=M), q


@pytest.mark.parametrize("free", [0, 1])
def test_whole_pose_with_a_placing_joint_free(free):
    """Every such pose was "orientation not reachable": the roll at the free joint's
    representative missed, by up to 2 rad."""
    rng = np.random.default_rng(61 + free)
    for _ in range(40):
        r, q = _placing_joint_on_the_point(rng, free)
        assert plan(r)[1].name == "position-approach"
        T = r.fk(q)
        sols = solve(r, Target(T)).solutions
        assert all(_reaches(r, s, T) for s in sols)
        assert any(_same(r, s.q, q) and not s.free for s in sols), np.degrees(q)


def _follow_the_free_joint(r, q, j, value, target, way) -> bool:
    """Joint ``j`` of ``q`` turned to ``value`` (``way`` round), joints 4 and 5 kept on the
    position and approach of ``target`` (:func:`randrobots.follow_joint`)."""
    def miss(x):
        F = r.fk(x)
        return np.concatenate([F[:3, 3] - target[:3, 3], F[:3, 2] - target[:3, 2]])
    return follow_joint(miss, q, j, value, way, (3, 4)) is not None


@pytest.mark.parametrize("free", [0, 1])
def test_approach_with_a_placing_joint_free(free):
    """Position and approach, the point on the free joint's axis: where the twist of axes 4
    and 5 is not a right angle they point the approach only within a band, and the free
    joint's representative 0 left it outside (no solution, "approach not reachable"). The
    free joint is now turned into the band; the generating joints lie on the continuum of a
    representative (the free joint moved there, joints 4 and 5 following)."""
    rng = np.random.default_rng(71 + free)
    for _ in range(30):
        r, q = _placing_joint_on_the_point(rng, free)
        T = r.fk(q)
        P = T.copy()
        P[:3, :3] = np.eye(3)
        sols = solve(r, Target(P, orientation=False, approach=T[:3, 2])).solutions
        assert sols, np.degrees(q)
        for s in sols:
            F = r.fk(s.q)
            assert np.allclose(F[:3, 3], T[:3, 3], atol=1e-9)
            assert np.allclose(F[:3, 2], T[:3, 2], atol=1e-9)
        placed = [s for s in sols if s.free == (free,) and _same(r, s.q, q, slice(free + 1, 3))]
        assert any(_follow_the_free_joint(r, s.q, free, q[free], T, way)
                   for s in placed for way in (1, -1)), np.degrees(q)


def _three_joint_wrist_arm(rng):
    """A poe arm of two placing joints and axes 3, 4 and 5 through one point ``c0`` at random
    angles (their twists not right angles), the tool's approach ``a0`` random."""
    c0 = rng.uniform(-.3, .3, 3)
    k = [_unit(rng) for _ in range(5)]
    o = [rng.uniform(-.4, .4, 3) for _ in range(2)] + [c0, c0, c0]
    a0 = _unit(rng)
    R = matrix_from_axis_angle(_unit(rng), rng.uniform(0, np.pi))
    R = matrix_from_axis_angle(np.cross(R[:, 2], a0), np.arccos(R[:, 2] @ a0)) @ R  # z = a0
    joints = tuple(Joint(f"q{i + 1}", "revolute", axis=tuple(k[i]), point=tuple(o[i]),
                         limits=(-np.pi, np.pi)) for i in range(5))
    return Robot(name="five", convention="poe", joints=joints,
                 M=transform(R, c0 + rng.uniform(.05, .2) * a0))


def test_approach_of_a_three_joint_wrist_on_two_arcs():
    """Joint 3 is free for an approach, within the values where joints 4 and 5 can point
    it. Where those are two arcs, one representative stood for one of them: the generating
    joints on the other were not on any answer's continuum."""
    rng = np.random.default_rng(81)
    pieces = 0
    for _ in range(12):
        r = _three_joint_wrist_arm(rng)
        assert plan(r)[1].name == "position-approach"
        for q in sample_configurations(r, 5, rng):
            T = r.fk(q)
            P = T.copy()
            P[:3, :3] = np.eye(3)
            sols = solve(r, Target(P, orientation=False, approach=T[:3, 2])).solutions
            for s in sols:
                F = r.fk(s.q)
                assert np.allclose(F[:3, 3], T[:3, 3], atol=1e-9)
                assert np.allclose(F[:3, 2], T[:3, 2], atol=1e-9)
            placed = [s for s in sols if s.free == (2,) and _same(r, s.q, q, slice(0, 2))]
            assert any(_follow_the_free_joint(r, s.q, 2, q[2], T, way)
                       for s in placed for way in (1, -1)), np.degrees(q)
            pieces += sum("other arc" in s.branch for s in placed) > 0
    assert pieces > 0                    # the case of two arcs was met


@pytest.mark.parametrize("tool", ["approach", "sideways", "rolling"])
@pytest.mark.parametrize("shoulder", ["parallel", "concurrent"])
def test_three_placing_axes_with_a_turn_to_spare(shoulder, tool):
    """Axes 1-3 parallel (a plane) or through one point (a sphere) place the wrist point with
    a turn to spare, which the orientation decides (two of the campaign's arms answered "no
    solution" for every pose they reach, the next version solved them numerically, one
    solution of up to four). Every solution Gauss-Newton finds from 150 random starts is
    among kincalc's, and kincalc's reach the pose. The point where axes 4 and 5 meet lies on
    the tool's approach line, or off it (a tool carried sideways), or the approach lies along
    axis 5 (joint 5 rolls the tool; an independent campaign's planar arm with a pitch and a
    roll, which was solved numerically, one solution)."""
    rng = np.random.default_rng(51)
    for _ in range(3):
        if shoulder == "parallel":
            rows = [(0.0, rng.uniform(.2, .4), .1), (0.0, rng.uniform(.15, .3), 0.0),
                    (rng.uniform(.5, 2.5), .2, .1)]
        else:
            rows = [(rng.uniform(.3, 2.8), 0.0, 0.0), (np.pi / 2, 0.0, 0.0),
                    (rng.uniform(.3, 2.8), rng.uniform(.1, .3), 0.0)]
        rows += [(rng.uniform(.3, 2.8), 0.0, rng.uniform(.1, .3)),
                 (0.0 if tool == "rolling" else np.pi / 2, 0.0, 0.0)]
        joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d,
                             theta=rng.uniform(-3, 3)) for i, (al, a, d) in enumerate(rows))
        r = Robot(name="five", convention="dh", joints=joints, tool={
            "approach": transform(rot_z(0.4), [0, 0, 0.1]),
            "sideways": transform(matrix_from_rpy(rng.uniform(-3, 3, 3)),
                                  rng.uniform(-.2, .2, 3)),
            "rolling": transform(rot_z(0.4), [0, 0, 0.1])}[tool])
        assert plan(r)[1].name == {"parallel": "planar-shoulder",
                                   "concurrent": "spherical-shoulder"}[shoulder]
        for q in sample_configurations(r, 4, rng):
            T = r.fk(q)
            sols = solve(r, Target(T)).solutions
            assert sols and all(_reaches(r, s, T) for s in sols) and len(sols) <= 4
            for root in newton_roots(r, T, 150, rng) + [q]:
                assert any(_same(r, s.q, root) for s in sols), np.degrees(root)


def test_planar_shoulder_with_axis_5_along_the_parallel_axes():
    """Axis 5 turned by joint 4 onto the direction of axes 1-3 (q4 = 0 here: joint 4's twist
    undoes joint 3's): the planar arm's turn and joint 5 are one continuum, which subproblem 1
    left to rounding; the turn taken then could be one joints 1 and 2 cannot follow, and a
    pose FK gives was "no solution" (3 of 10 such poses of a random-robot campaign). Now a
    representative they can follow: solutions that reach the pose, flagged singular."""
    rng = np.random.default_rng(61)
    answered = 0
    for _ in range(6):
        twist = rng.uniform(.5, 2.5)
        rows = [(0.0, rng.uniform(.2, .4), .1), (0.0, rng.uniform(.15, .3), 0.0),
                (twist, .2, .1), (-twist, 0.0, rng.uniform(.1, .3)), (np.pi / 2, 0.0, 0.0)]
        joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0)
                       for i, (al, a, d) in enumerate(rows))
        r = Robot(name="five", convention="dh", joints=joints,
                  tool=transform(rot_z(0.4), [0, 0, 0.1]))
        assert plan(r)[1].name == "planar-shoulder"
        for q in sample_configurations(r, 5, rng):
            q[3] = 0.0
            T = r.fk(q)
            sols = solve(r, Target(T)).solutions
            assert sols, np.degrees(q)
            assert all(_reaches(r, s, T) and s.singular for s in sols)
            answered += 1
    assert answered == 30


def test_planar_shoulder_singular_continuum_holds_the_generating_joints():
    """At that singularity joints 1, 2, 3 and 5 turn about parallel axes and only their
    signed sum is fixed: joint 5 is named free with the relation (q1 + s2 q2 + s3 q3 + sigma
    q5 = total, mod 2 pi), which the generating joints satisfy, and they lie on the continuum
    of a representative (joint 5 turned from them to its value, joints 1-3 kept on the pose
    by Gauss-Newton, ends at one). Before, the answers named no free joint, and at 10 of 36
    planar-shoulder arms of a random-robot campaign the generating joints lay on a closed
    curve of solutions more than 2 rad from every answer (the other arc of joint 5)."""
    from kincalc.ik.continua import ParallelContinuum
    rng = np.random.default_rng(62)
    followed = other = 0
    for _ in range(8):
        twist = rng.uniform(.5, 2.5)
        rows = [(0.0, rng.uniform(.2, .4), .1), (0.0, rng.uniform(.15, .3), 0.0),
                (twist, rng.choice([.2, .6]), .1), (-twist, 0.0, rng.uniform(.1, .3)),
                (np.pi / 2, 0.0, 0.0)]
        joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0)
                       for i, (al, a, d) in enumerate(rows))
        r = Robot(name="five", convention="dh", joints=joints,
                  tool=transform(rot_z(0.4), [0, 0, 0.1]))
        for q in sample_configurations(r, 4, rng):
            q[3] = 0.0
            T = r.fk(q)
            sols = solve(r, Target(T)).solutions
            reps = [s for s in sols if s.free == (4,)]
            assert reps and all(_reaches(r, s, T) for s in sols), np.degrees(q)
            for s in reps:
                c = s.continuum
                assert isinstance(c, ParallelContinuum) and c.free == 4
                assert c.joints == (0, 1, 2, 4)
            c = reps[0].continuum
            assert abs(wrap(sum(g * q[j] for j, g in zip(c.joints, c.signs)) - c.total)) < 1e-9

            def miss(x):
                return (r.fk(x) - T)[:3].ravel()
            ends = [(s, follow_joint(miss, q, 4, s.q[4], way, (0, 1, 2)))
                    for s in reps for way in (1, -1)]
            reached = [s for s, e in ends if e is not None and _same(r, e, s.q)]
            assert reached, np.degrees(q)
            followed += 1
            other += all("other arc" in s.branch for s in reached)
    assert followed == 32 and other > 0              # the second arc was met


def _normed(v):
    return np.asarray(v, float) / np.linalg.norm(v)


@pytest.mark.parametrize("tool", ["approach", "sideways", "rolling"])
def test_spherical_shoulder_with_axis_5_through_the_shoulder_point(tool):
    """Axes 1-3 through O, axes 4 and 5 through c, and joint 4 at the value that turns axis 5
    through O (built in poe: axis 5 at q = 0 is the line c-O turned back about axis 4 by
    that value). Joint 5 then turns nothing the shoulder cannot undo: a curve of solutions,
    joint 5 free and joints 1-3 following, joint 4 fixed. An independent campaign found no
    solution for such poses of arms whose tool is off the approach line or rolled by joint 5
    (joint 5's representative 0 asked the shoulder for a turn out of its reach), and joint 4
    named free (with joint 5) for the others. Now joint 5 alone is free, turned into the
    shoulder's reach, and the generating joints lie on the curve of a representative (joint
    5 moved to its value, joints 1-3 kept on the pose by Gauss-Newton)."""
    rng = np.random.default_rng(97)
    checked = 0
    while checked < 8:
        O = np.zeros(3)
        c = rng.uniform(-.4, .4, 3)
        k4 = _normed(rng.normal(size=3))
        t4 = rng.uniform(-3, 3)
        k5 = matrix_from_axis_angle(k4, -t4) @ _normed(O - c)
        axes = [_normed(rng.normal(size=3)) for _ in range(3)] + [k4, k5]
        points = [O, O, O, c, c]
        if tool == "rolling":
            z = k5
            x = _normed(np.cross(z, rng.normal(size=3)))
            M = transform(np.column_stack([x, np.cross(z, x), z]), c + 0.15 * k5)
        elif tool == "approach":
            z = _normed(rng.normal(size=3))
            x = _normed(np.cross(z, rng.normal(size=3)))
            M = transform(np.column_stack([x, np.cross(z, x), z]), c + 0.1 * z)
        else:
            M = transform(matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.uniform(-.4, .4, 3))
        r = Robot(name="five", convention="poe", M=M, joints=tuple(
            Joint(f"q{i + 1}", "revolute", axis=k, point=p)
            for i, (k, p) in enumerate(zip(axes, points))))
        if plan(r)[1].name != "spherical-shoulder":
            continue
        q = rng.uniform(-np.pi, np.pi, 5)
        q[3] = t4
        T = r.fk(q)
        sols = solve(r, Target(T)).solutions
        assert sols, np.degrees(q)
        for s in sols:
            assert _reaches(r, s, T) and s.singular and s.free == (4,)
            assert abs(wrap(s.q[3] - t4)) < 1e-9

        def miss(x):
            return (r.fk(x) - T)[:3].ravel()
        assert any(follow_joint(miss, s.q, 4, q[4], way, (0, 1, 2)) is not None and
                   _same(r, follow_joint(miss, s.q, 4, q[4], way, (0, 1, 2)), q)
                   for s in sols for way in (1, -1)), np.degrees(q)
        checked += 1


PA_ON_AXIS_1 = """
name: pa
convention: dh
units: {length: mm, angle: deg}
joints:
  - {name: j1, type: revolute, alpha: -90.0, a: 0.0, d: 351.7670583793126, theta: 0.0}
  - {name: j2, type: revolute, alpha: 90.0, a: 0.0, d: 86.07847483531593, theta: 0.0}
  - {name: j3, type: prismatic, alpha: 0.0, a: 0.0, d: 0.0, theta: -90.0}
  - {name: j4, type: revolute, alpha: -90.0, a: 0.0, d: 386.0359064138038, theta: 0.0}
  - {name: j5, type: revolute, alpha: 90.0, a: 0.0, d: 0.0, theta: 0.0}
tool: {xyz: [0.0, 0.0, 117.98045448620455], rpy: [0.0, -0.0, 0.0]}
"""


def test_an_approach_along_axis_4_leaves_joint_4_free_not_joint_5():
    """The approach and the point both on axis 1 (the independent IK oracle's case): joint
    4 turns the tool about the approach, joint 5 tilts it. Both were labelled free (the
    subproblem's free mask given to both its angles); a joint is free exactly when moving
    it alone keeps the point and the approach (checked by FK)."""
    from kincalc import parse_robot_text
    r = parse_robot_text(PA_ON_AXIS_1)
    T = np.eye(4)
    T[:3, 3] = np.array([0.0, -86.07847483531599, -152.24930252069578]) * 1e-3
    res = solve(r, Target(T, orientation=False, approach=np.array([0.0, 0.0, -1.0])))
    assert res.solutions
    for s in res.solutions:
        for j in range(r.dof):
            q = np.array(s.q, float)
            q[j] += 0.3
            F = r.fk(q)
            keeps = np.allclose(F[:3, 3], T[:3, 3], atol=1e-9) and \
                np.allclose(F[:3, 2], [0, 0, -1], atol=1e-9)
            assert (j in s.free) == keeps, (s.branch, j)
        assert "(j4 free)" in s.branch
