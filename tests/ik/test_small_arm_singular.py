"""Four- and five-joint arms and TCV targets at singular poses where the position leaves
joints free that the orientation (or the approach) decides.

* a pitch-roll arm (axes 2-4 parallel, joint 5 rolling the tool) with its tool point on
  axis 1: joint 1 is free for the position, and the approach sets it (two values);
* a point-plus-roll arm whose axes 1 and 2 meet, axis 4's point there (an R-R-P-R
  spherical arm's slide at 0): joints 1 and 2 are free for the point, and joints 1, 2 and
  4 together take the orientation (two solutions);
* a TCV target with the tool point where the axes of two free joints meet (an elbow of
  equal links folded onto the shoulder): the approach sets them;
* an approach target on a pitch-roll arm: the roll is open (``any``), listed free, shown
  at the value nearest 0 within its limits, and not flagged singular for that.

Every check is FK of the robot as given: each solution returned reaches the target, and
the generating configuration is among them (joints left free aside). The arms are the
bundled ones and seeded random arms of each family, in dh, mdh and poe.
"""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.fk import chain_frames
from kincalc.ik import Target, solve
from kincalc.ik.families import plan
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap
from randrobots import gauss_newton

CONVENTIONS = ["dh", "mdh", "poe"]


def _dh(rows, limits, rng, tool):
    """A DH robot from ``rows`` of (type, alpha, a, d, theta), a random base."""
    joints = tuple(Joint(f"q{i + 1}", t, alpha=al, a=a, d=d, theta=th, limits=lim)
                   for i, ((t, al, a, d, th), lim) in enumerate(zip(rows, limits)))
    base = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.3, .3, 3))
    return Robot(name="random", convention="dh", joints=joints, base=base, tool=tool)


def _convert(robot, convention):
    return {"dh": robot, "mdh": dh_to_mdh(robot), "poe": to_poe(robot)}[convention]


def _pitch_roll(rng):
    s = lambda: rng.choice([-1.0, 1.0]) * np.pi / 2  # noqa: E731
    rows = [("revolute", s(), rng.uniform(-.1, .1), rng.uniform(.05, .3), rng.uniform(-3, 3)),
            ("revolute", rng.choice([0.0, np.pi]), rng.uniform(.15, .3), 0.0, rng.uniform(-3, 3)),
            ("revolute", rng.choice([0.0, np.pi]), rng.uniform(.15, .3), 0.0, rng.uniform(-3, 3)),
            ("revolute", s(), 0.0, 0.0, rng.uniform(-3, 3)),
            ("revolute", 0.0, 0.0, rng.uniform(.03, .15), rng.uniform(-3, 3))]
    roll = rng.uniform(-np.pi, np.pi)
    tool = transform(matrix_from_rpy([0.0, 0.0, roll]), [0.0, 0.0, rng.uniform(0, .05)])
    return _dh(rows, [(-np.pi, np.pi)] * 5, rng, tool)


def _rrpr(rng):
    t = lambda: rng.uniform(0.3, 2.8) * rng.choice([-1, 1])  # noqa: E731
    rows = [("revolute", t(), 0.0, rng.uniform(.1, .4), rng.uniform(-3, 3)),
            ("revolute", t(), 0.0, 0.0, rng.uniform(-3, 3)),
            ("prismatic", t(), 0.0, 0.0, rng.uniform(-3, 3)),
            ("revolute", t(), rng.uniform(-.2, .2), rng.uniform(-.2, .2), rng.uniform(-3, 3))]
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.1, .1, 3))
    lim = [(-np.pi, np.pi), (-np.pi, np.pi), (-0.5, 0.5), (-np.pi, np.pi)]
    return _dh(rows, lim, rng, tool)


def _rrr(rng):
    L = rng.uniform(.2, .5)
    rows = [("revolute", rng.choice([-1.0, 1.0]) * np.pi / 2, 0.0, rng.uniform(0, .4),
             rng.uniform(-3, 3)),
            ("revolute", 0.0, L, 0.0, rng.uniform(-3, 3)),
            ("revolute", 0.0, L, 0.0, rng.uniform(-3, 3))]
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), np.zeros(3))
    return _dh(rows, [(-np.pi, np.pi)] * 3, rng, tool)


def _axes(robot, q):
    """Each joint's axis and a point of it at ``q`` (world frame): ``(k (n, 3), o (n, 3))``."""
    F = chain_frames(robot.chain, np.asarray(q, float)[None])[0]
    return F[:, :3, 2], F[:, :3, 3]


def _on_lines(robot, q, point, lines, moving, iters=60):
    """``q`` with the joints ``moving`` changed (Gauss-Newton, finite differences) until
    ``point(q)`` (a world point) lies on the axes ``lines``; None if it does not get there."""
    def err(x):
        k, o = _axes(robot, x)
        return np.concatenate([np.cross(k[j], point(x) - o[j]) for j in lines])
    q = gauss_newton(err, q, moving, iters, stop=1e-14)
    return q if np.abs(err(q)).max() < 1e-12 else None


def _found(robot, res, q0, target_ok):
    """Every solution reaches the target (``target_ok(q)``); one of them is ``q0`` up to
    whole turns, its free joints aside and a continuum's relation holding."""
    assert res.solutions, res.reason
    hit = False
    for s in res.solutions:
        assert target_ok(s.q), (s.branch, s.q)
        d = np.where(robot.is_revolute, wrap(s.q - q0), s.q - q0)
        keep = np.ones(robot.dof, bool)
        keep[list(s.free)] = False
        c = s.continuum
        if c is not None and hasattr(c, "i") and c.total is not None:
            keep[[c.i, c.j]] = False
            if abs(wrap(q0[c.i] + c.sign * q0[c.j] - c.total)) > 1e-7:
                continue
        hit |= bool(np.all(np.abs(d[keep]) < 1e-7))
    assert hit, (q0, [(s.q, s.free, s.continuum) for s in res.solutions])


def _pose_ok(robot, T):
    return lambda q: np.allclose(robot.fk(q), T, atol=1e-8)


def _approach_ok(robot, T):
    return lambda q: (np.allclose(robot.fk(q)[:3, 3], T[:3, 3], atol=1e-8)
                      and np.allclose(robot.fk(q)[:3, 2], T[:3, 2], atol=1e-8))


def _pitch_roll_cases(robot, rng, m):
    """Configurations of a pitch-roll arm with the tool point on axis 1."""
    out = []
    while len(out) < m:
        q = _on_lines(robot, rng.uniform(-np.pi, np.pi, 5),
                      lambda x: robot.fk(x)[:3, 3], [0], [1, 2])
        if q is not None:
            out.append(q)
    return out


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("seed", range(3))
def test_pitch_roll_tool_point_on_axis_1(convention, seed):
    """The approach decides joint 1 where the position leaves it free: the generating
    configuration is found, for the whole pose and for its approach alone."""
    rng = np.random.default_rng(100 + seed)
    robot = _convert(_pitch_roll(rng), convention)
    assert plan(robot)[1].name == "pitch-roll"
    for q0 in _pitch_roll_cases(robot, rng, 4):
        T = robot.fk(q0)
        _found(robot, solve(robot, Target(T)), q0, _pose_ok(robot, T))
        res = solve(robot, Target(T, False, approach=T[:3, 2]))
        _found(robot, res, q0, _approach_ok(robot, T))
        assert all(4 in s.free for s in res.solutions)


@pytest.mark.parametrize("name", ["lynxmotion_al5d", "dobot_magician", "kuka_youbot_arm"])
def test_pitch_roll_bundled_tool_point_on_axis_1(name):
    """The tester's pose (lynxmotion, q = [0.618392, pi/2, 0, 0.672294, pi]) and seeded
    ones of each bundled pitch-roll arm; limits are not the point here."""
    robot = load_robot(name)
    rng = np.random.default_rng(7)
    cases = _pitch_roll_cases(robot, rng, 5)
    if name == "lynxmotion_al5d":
        cases.append(np.array([0.618392, np.pi / 2, 0.0, 0.672294, np.pi]))
    for q0 in cases:
        T = robot.fk(q0)
        res = solve(robot, Target(T))
        _found(robot, res, q0, _pose_ok(robot, T))
        # the shoulder word is on its boundary (the point on axis 1): the two solutions,
        # q1 and q1 + 180 deg, are told apart by joint 1's sign instead
        labels = [s.branch for s in res.solutions]
        assert len(set(labels)) == len(labels), labels
        _found(robot, solve(robot, Target(T, False, approach=T[:3, 2])), q0,
               _approach_ok(robot, T))


def test_pitch_roll_tool_and_approach_on_axis_1_is_a_continuum():
    """Tool point and approach both on axis 1 (joint 5's line then): only q1 + sigma q5 is
    fixed; the representative reaches the pose and the generating configuration satisfies
    the relation."""
    robot = load_robot("lynxmotion_al5d")
    q0 = np.array([0.618392, np.pi / 2, 0.0, -np.pi / 2, 0.7])
    T = robot.fk(q0)
    res = solve(robot, Target(T))
    _found(robot, res, q0, _pose_ok(robot, T))
    assert any(s.continuum is not None and (s.continuum.i, s.continuum.j) == (0, 4)
               for s in res.solutions)


ARM5 = """name: arm5
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 90, a: 0.033, d: 0.147, theta: 0}
  - {name: q2, type: revolute, alpha: 0, a: 0.155, d: 0, theta: 0}
  - {name: q3, type: revolute, alpha: 0, a: 0.135, d: 0, theta: 0}
  - {name: q4, type: revolute, alpha: 90, a: 0, d: 0, theta: 0}
  - {name: q5, type: revolute, alpha: 0, a: 0, d: 0.2175, theta: 0, limits: [LO, HI]}
"""


@pytest.mark.parametrize("lo, hi, expect", [(30, 200, 30), (-200, -40, -40), (-90, 90, 0),
                                            (100, 350, 350)])
def test_open_roll_is_free_within_its_limits(tmp_path, lo, hi, expect):
    """An approach target leaves the roll open: listed free, labelled q5:any (not also
    "(q5 free)"), at the value nearest 0 within its limits, within limits and not flagged
    singular at a regular pose."""
    path = tmp_path / "arm5.yaml"
    path.write_text(ARM5.replace("LO", str(lo)).replace("HI", str(hi)))
    robot = load_robot(str(path))
    T = robot.fk(np.radians([20, 30, 40, 50, 60]))
    res = solve(robot, Target(T, False, approach=T[:3, 2]))
    assert len(res.solutions) >= 2
    for s in res.solutions:
        assert s.free == (4,) and "q5:any" in s.branch and "free" not in s.branch
        assert abs(wrap(s.q[4] - np.radians(expect))) < 1e-12
        assert not s.singular and not np.any(s.violations)
        assert _approach_ok(robot, T)(s.q)


def _rrpr_cases(robot, rng, m):
    """Configurations of an R-R-P-R arm with axis 4's point where axes 1 and 2 meet."""
    out = []
    while len(out) < m:
        q = rng.uniform(-np.pi, np.pi, 4)
        q[2] = rng.uniform(-.3, .3)
        q = _on_lines(robot, q, lambda x: _axes(robot, x)[1][3], [0, 1], [2])
        if q is not None:
            out.append(q)
    return out


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("seed", range(3))
def test_point_plus_roll_slide_at_the_meeting_point(convention, seed):
    """Joints 1, 2 and 4 take the orientation where the point leaves 1 and 2 free: the
    generating configuration is found, and a second solution."""
    rng = np.random.default_rng(200 + seed)
    robot = _convert(_rrpr(rng), convention)
    assert plan(robot)[1].name == "point-plus-roll"
    for q0 in _rrpr_cases(robot, rng, 4):
        T = robot.fk(q0)
        res = solve(robot, Target(T))
        _found(robot, res, q0, _pose_ok(robot, T))
        assert len(res.solutions) == 2 and not any(s.free for s in res.solutions)


def test_point_plus_roll_bundled_spherical_arm():
    robot = load_robot("fer_rrpr")
    rng = np.random.default_rng(9)
    cases = _rrpr_cases(robot, rng, 6) + [np.array([-np.pi / 2, -np.pi / 2, 0.0, np.pi / 2])]
    for q0 in cases:
        T = robot.fk(q0)
        _found(robot, solve(robot, Target(T)), q0, _pose_ok(robot, T))


def _tcv_ok(robot, T, roll):
    return lambda q: _approach_ok(robot, T)(q) and abs(wrap(q[-1] - roll)) < 1e-9


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("seed", range(3))
def test_tcv_folded_elbow(convention, seed):
    """A 3R arm of equal links folded onto its shoulder (joints 1 and 2 free for the
    point), asked with a TCV: the approach sets them (two solutions, or joint 2 free when
    the approach is along its axis)."""
    rng = np.random.default_rng(300 + seed)
    robot = _convert(_rrr(rng), convention)
    for _ in range(4):
        q0 = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), np.pi])
        T = robot.fk(q0)
        res = solve(robot, Target(T, False, tcv=(T[:3, 2], float(q0[2]))))
        _found(robot, res, q0, _tcv_ok(robot, T, q0[2]))


def test_tcv_bundled_folded_elbow():
    """siciliano_arm at q = [2.626927, 0, pi]: the tool's z is along axis 2, so joint 1 is
    set by the approach and joint 2 stays free."""
    robot = load_robot("siciliano_arm")
    for q0 in ([2.626927, 0.0, np.pi], [-1.1, 0.7, np.pi]):
        q0 = np.array(q0)
        T = robot.fk(q0)
        res = solve(robot, Target(T, False, tcv=(T[:3, 2], float(q0[2]))))
        _found(robot, res, q0, _tcv_ok(robot, T, q0[2]))
        assert all(s.free == (1,) for s in res.solutions)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_point_plus_roll_joint_on_the_last_axis(convention):
    """A SCARA of equal links folded (q2 = 180 deg: axis 4 on the line of axis 1): joints 1
    and 4 turn about one line and only q1 - q4 counts. Joint 1 is free at its
    representative 0 (the split between the two was rounding noise, which changed with the
    batch), the relation is the solution's continuum, and the generating configuration
    satisfies it; the same alone and among other poses."""
    rng = np.random.default_rng(41)
    rows = [("revolute", 0.0, 0.3, 0.4, 0.0), ("revolute", np.pi, 0.3, 0.0, 0.0),
            ("prismatic", 0.0, 0.0, 0.0, 0.0), ("revolute", 0.0, 0.0, 0.1, 0.0)]
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.1, .1, 3))
    robot = _convert(_dh(rows, [(-np.pi, np.pi)] * 2 + [(0.0, 0.3), (-np.pi, np.pi)], rng,
                         tool), convention)
    Q = np.column_stack([rng.uniform(-3, 3, 30), np.full(30, np.pi), rng.uniform(0, 0.3, 30),
                         rng.uniform(-3, 3, 30)])
    T = robot.fk(Q)
    together = robot.ik_batch(T)
    for k in range(len(Q)):
        res = solve(robot, Target(T[k]))
        _found(robot, res, Q[k], _pose_ok(robot, T[k]))
        assert res.solutions and all(s.free == (0,) and s.q[0] == 0.0 and s.continuum
                                     is not None for s in res.solutions)
        alone = sorted(tuple(np.round(s.q, 9)) for s in res.solutions)
        assert alone == sorted(tuple(np.round(q, 9))
                               for q in together.q[k][together.valid[k]]), k
