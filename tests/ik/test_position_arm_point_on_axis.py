"""R-R-P position arms with a shoulder offset whose tool point lies on axis 2 when the slide
is at 0: there joint 2 does not move the point, so every value of it reaches the target
(a continuum, "j2 free").

The placement eliminates joint 2 and solves a resultant in the slide, in which that slide
value is a fourfold root (both of joint 2's roots meet there); a companion matrix splits it
into four complex roots about 1e-4 apart, which were all dropped as complex, and the
continuum came out as two isolated "solutions" with joint 2 decided by rounding (found by a
random-robot campaign; the same arm without the offset said "j2 free"). Checked from FK
alone: every configuration on the line (j1, any j2, 0) reaches the target, and every root
Gauss-Newton finds from random starts is a solution or a member of the continuum.
"""

import numpy as np

from kincalc.ik import Target, solve
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap


def _arm(rng) -> Robot:
    """A random R-R-P arm (standard DH, m, rad) with a shoulder offset ``a1`` whose tool
    point is on axis 2 (z1, through frame 2's origin since ``a2 = 0``) at ``d3 = 0``: z1 is
    ``(0, sin alpha2, cos alpha2)`` in frame 2."""
    al1, al2 = rng.uniform(0.5, 2.6, 2)
    t = rng.uniform(0.1, 0.5)
    joints = (Joint("j1", "revolute", alpha=al1, a=rng.uniform(0.1, 0.4),
                    d=rng.uniform(0.2, 0.6), theta=0.0, limits=(-np.pi, np.pi)),
              Joint("j2", "revolute", alpha=al2, a=0.0, d=rng.uniform(0.05, 0.3), theta=0.0,
                    limits=(-np.pi, np.pi)),
              Joint("j3", "prismatic", alpha=0.0, a=0.0, d=0.0, theta=0.0, limits=(-1.0, 1.0)))
    tool = np.eye(4)
    tool[:3, 3] = t * np.array([0.0, np.sin(al2), np.cos(al2)])
    return Robot(name="rrp_offset", convention="dh", joints=joints, tool=tool)


def _position_roots(robot, p, starts, rng) -> list:
    """Configurations placing the tool point at ``p`` that Gauss-Newton finds from random
    starts (kincalc's FK and Jacobian only), regular or not, distinct to 1e-6."""
    roots = []
    for q in rng.uniform(-np.pi, np.pi, (starts, 3)) * [1, 1, 0.3]:
        for _ in range(80):
            e = p - robot.fk(q)[:3, 3]
            if np.abs(e).max() < 1e-14:
                break
            q = q + np.linalg.lstsq(robot.jacobian(q)[:3], e, rcond=None)[0]
        if np.abs(robot.fk(q)[:3, 3] - p).max() < 1e-11:
            roots.append(np.where(robot.is_revolute, wrap(q), q))
    return roots


def _matches(robot, sols, q) -> bool:
    """``q`` is a solution or a member of a solution's continuum (equal in its fixed joints)."""
    for s in sols:
        d = np.where(robot.is_revolute, wrap(s.q - q), s.q - q)
        fixed = [j for j in range(3) if j not in s.free]
        if np.abs(d[fixed]).max() < 1e-6:
            return True
    return False


def test_the_point_on_axis_2_leaves_joint_2_free():
    rng = np.random.default_rng(404)
    for _ in range(6):
        r = _arm(rng)
        for _ in range(4):
            j1, j2 = rng.uniform(-np.pi, np.pi, 2)
            p = r.fk([j1, j2, 0.0])[:3, 3]
            sols = solve(r, Target(r.fk([j1, j2, 0.0]), orientation=False)).solutions
            for s in sols:
                assert np.abs(r.fk(s.q)[:3, 3] - p).max() < 1e-9
            on_line = [s for s in sols if abs(s.q[2]) < 1e-6]
            assert len(on_line) == 1 and on_line[0].free == (1,), [s.q for s in sols]
            for x in rng.uniform(-np.pi, np.pi, 5):          # the whole line reaches p
                q = on_line[0].q.copy()
                q[1] = x
                assert np.abs(r.fk(q)[:3, 3] - p).max() < 1e-12
            for root in _position_roots(r, p, 30, rng):
                assert _matches(r, sols, root), (root, [s.q for s in sols])


def test_a_point_of_a_continuum_goes_with_it_and_nothing_else_does():
    """The rule by which the engine drops such points (``on_continua``), slot by slot."""
    from kincalc.ik.joint_limits import on_continua
    r = _arm(np.random.default_rng(1))
    base = np.array([0.3, 0.0, 0.0])
    q = np.array([base,                                # 0: j2 free
                  base + [0, 2.0, 0],                  # 1: j2 elsewhere: on 0's continuum
                  base + [1e-3, 2.0, 0],               # 2: j1 differs: its own
                  base + [2 * np.pi, 0.0, 1e-9],       # 3: 0 again, a turn and 1e-9 away
                  base + [0, 1.0, 0],                  # 4: free in j3 alone: no one's
                  base + [0, 1.5, 0]])[None]           # 5: like 1, but not valid
    free = np.zeros((1, 6, 3), bool)
    free[0, [0, 3], 1] = True
    free[0, 4, 2] = True
    valid = np.array([[True, True, True, True, True, False]])
    assert on_continua(r, q, valid, free).tolist() == [[False, True, False, True, False, False]]


def test_points_near_axis_2_are_not_free_and_not_twice():
    """The same arms with the point 1e-9 .. 1e-3 m off axis 2 (a campaign's repros of a first
    version of the fix): joint 2 is free only where every value of it reaches the target,
    and no two solutions are one double root (within 1e-5). (Next to the fourfold root every
    Gauss-Newton root is not always found: the resultant's fitted coefficients place such
    roots to about the fourth root of rounding; man kincalc-ik says so.)"""
    rng = np.random.default_rng(405)
    for _ in range(6):
        r = _arm(rng)
        for off in (1e-9, 1e-7, 1e-5, 1e-3):
            j1, j2 = rng.uniform(-np.pi, np.pi, 2)
            q = np.array([j1, j2, 0.0])
            q[2] = off * rng.choice([-1.0, 1.0])         # the slide moves the point off axis 2
            p = r.fk(q)[:3, 3]
            sols = solve(r, Target(r.fk(q), orientation=False)).solutions
            for s in sols:
                assert np.abs(r.fk(s.q)[:3, 3] - p).max() < 1e-9
                if s.free:                                # every value of the free joint
                    moved = s.q.copy()
                    moved[1] += 1.0
                    L = max(1.0, r.characteristic_length)        # the check's unit
                    assert np.linalg.norm(r.fk(moved)[:3, 3] - p) <= 1e-9 * L
            for a in range(len(sols)):
                for b in range(a):
                    d = np.abs(np.where(r.is_revolute, wrap(sols[a].q - sols[b].q),
                                        sols[a].q - sols[b].q))
                    assert d.max() > 1e-5, [s.q for s in sols]


def test_a_joint_free_by_a_hair_takes_no_other_solution_with_it():
    """A P-R-R arm (a campaign's robot, cm) whose tool point passes 2e-6 cm from axis 2: a
    slot the double root's band calls "(j2 free)" moves the point by 1.6e-9 m when j2 turns,
    more than the check allows, so the generating joints (j2 = 90 deg), equal to it but in
    j2, are a solution of their own, not a point of its continuum (they had been dropped)."""
    deg, cm = np.pi / 180, 0.01
    rows = [("prismatic", 125.4382266673655, -25.781580435915384, -13.742879808957245, 0.0,
             (-27.360036083159915 * cm, 41.443984382142155 * cm)),
            ("revolute", 36.837867846941634, 2e-4, 0.0, -90.0, (-108.36716756434885 * deg,
                                                               108.36716756434885 * deg)),
            ("revolute", -35.652178916209174, 16.183683508911795, 21.60339423501872, -90.0,
             (-314.51661414553354 * deg, 345.10702783584986 * deg))]
    r = Robot(name="g025", convention="dh", joints=tuple(
        Joint(f"j{i + 1}", kind, alpha=al * deg, a=a * cm, d=d * cm, theta=th * deg,
              limits=lim) for i, (kind, al, a, d, th, lim) in enumerate(rows)))
    q = np.array([0.09006536692266043, np.pi / 2, -3.141580285195012])
    sols = solve(r, Target(r.fk(q), orientation=False)).solutions
    assert any(np.abs(np.where(r.is_revolute, wrap(s.q - q), s.q - q)).max() < 1e-6
               for s in sols), [s.q for s in sols]
