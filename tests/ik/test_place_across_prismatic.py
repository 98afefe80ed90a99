"""Placing a point when the first of the placing joints slides (``kincalc.ik.place``).

A prismatic joint a keeps the point's two components across its axis. When joint b moves
points only in one direction across that axis (a revolute b whose axis is across a's: its
circles lie in planes normal to its axis; a prismatic b), one combination of the two is
free of ``x_b`` and the placement is decoupled. The plan used to measure the components
along fixed directions built from the world x or y axis, which mix both with ``x_b`` unless
b's axis happens to lie along one of them; no elimination of ``x_b`` can then separate
them, and a prismatic-revolute-revolute arm with its second axis at 30 deg to the world x
axis had no solution at all for poses it reaches (4 solutions; found by an independent
random-robot campaign). Checked here by FK of random arms of each such mix, in every
direction: every answer reaches the point and the generating configuration is among them.
"""

import numpy as np
import pytest

from kincalc.ik import Target, solve
from kincalc.ik.families import plan
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import wrap


def _unit(rng):
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def _arm(rng, third: str, second: str = "revolute"):
    """Joint 1 slides along a random direction ``w``; joint 2 turns about an axis across ``w``
    (or slides in a random direction); joint 3 is ``third``; random points and tool point."""
    w = _unit(rng)
    k2 = _unit(rng)
    if second == "revolute":
        k2 -= (k2 @ w) * w
        k2 /= np.linalg.norm(k2)
    kinds = ("prismatic", second, third)
    axes = (w, k2, _unit(rng))
    joints = tuple(Joint(f"q{i + 1}", t, axis=tuple(k), point=tuple(rng.uniform(-.3, .3, 3)),
                         limits=(-np.pi, np.pi) if t == "revolute" else (-.4, .4))
                   for i, (t, k) in enumerate(zip(kinds, axes)))
    M = np.eye(4)
    M[:3, 3] = rng.uniform(-.4, .4, 3)
    return Robot(name="slide-first", convention="poe", joints=joints, M=M)


def _same(robot, p, q) -> bool:
    d = np.where(robot.is_revolute, wrap(p - q), p - q)
    return bool(np.all(np.abs(d) < 1e-6))


@pytest.mark.parametrize("second, third", [("revolute", "revolute"), ("revolute", "prismatic"),
                                           ("prismatic", "revolute")])
def test_slide_then_joints_that_move_across_it_in_one_direction(second, third):
    seed = {"revolute": 11, "prismatic": 12}[third] + 10 * (second == "prismatic")
    rng = np.random.default_rng(seed)
    found = trials = 0
    for _ in range(12):
        r = _arm(rng, third, second)
        S, family, _ = plan(r)
        assert family is not None and family.name == "position-3"
        for q in sample_configurations(r, 20, rng):
            T = r.fk(q)
            sols = solve(r, Target(T, orientation=False)).solutions
            for s in sols:
                assert np.linalg.norm(r.fk(s.q)[:3, 3] - T[:3, 3]) < 1e-9
            trials += 1
            found += any(_same(r, s.q, q) for s in sols)
    assert found == trials, (found, trials)


def test_the_reported_arm_has_its_four_solutions():
    """The campaign's arm: a slide along z, then axes at 30 deg to x and along z through the
    origin, the tool 0.3 m out: the tool point is on a sphere about a point sliding on z."""
    joints = (Joint("d1", "prismatic", axis=(0, 0, 1), point=(0, 0, 0)),
              Joint("q2", "revolute", axis=(np.cos(np.pi / 6), 0.5, 0), point=(0, 0, 0)),
              Joint("q3", "revolute", axis=(0, 0, 1), point=(0, 0, 0)))
    M = np.eye(4)
    M[:3, 3] = [0.3, 0, 0]
    r = Robot(name="prr", convention="poe", joints=joints, M=M)
    q = np.array([0.1, np.pi / 6, np.radians(40)])
    sols = solve(r, Target(r.fk(q), orientation=False)).solutions
    # the four (q2, q3), deg, from an independent campaign's least-squares restarts (each
    # reaching the point to 1e-16); the slide differs between the pairs
    for s in sols:
        assert np.linalg.norm(r.fk(s.q)[:3, 3] - r.fk(q)[:3, 3]) < 1e-12
    assert len(sols) == 4
    got = sorted(np.round(np.degrees(wrap(s.q[1:])), 6).tolist() for s in sols)
    assert got == sorted([[30.0, 40.0], [-150.0, 20.0], [-30.0, 40.0], [150.0, 20.0]])


def test_three_slides_in_one_plane_are_called_redundant():
    """Three slides whose directions lie in one plane move the tool point in that plane with a
    direction to spare: infinitely many solutions, said so (it read "no analytic solver for
    this structure yet")."""
    dirs = [(1, 0, 0), (0, 1, 0), (np.sqrt(.5), np.sqrt(.5), 0)]
    joints = tuple(Joint(f"d{i + 1}", "prismatic", axis=k, point=(0, 0, 0), limits=(-1, 1))
                   for i, k in enumerate(dirs))
    r = Robot(name="ppp-flat", convention="poe", joints=joints, M=np.eye(4))
    _, family, why = plan(r)
    assert family is None
    assert why == "redundant: 3 joints for 2 independent pose components, so infinitely many " \
                  "solutions"


def _dh_robot(name, rows):
    """A standard-DH robot of ``rows`` (type, alpha, a, d, theta; rad, m)."""
    joints = tuple(Joint(f"q{i + 1}", t, alpha=al, a=a, d=d, theta=th,
                         limits=(0.0, 0.5) if t == "prismatic" else (-np.pi, np.pi))
                   for i, (t, al, a, d, th) in enumerate(rows))
    return Robot(name=name, convention="dh", joints=joints)


@pytest.mark.parametrize("name, rows", [
    ("two slides along one line", [("prismatic", 0, 0, 0, 0), ("prismatic", 0, 0, 0, 1.57)]),
    ("six coaxial turns", [("revolute", 0, 0, 0.1 * i, 0) for i in range(6)]),
    ("a SCARA with joints 2 and 4 on one line",
     [("revolute", 0, 0.25, 0, 0), ("revolute", 0, 0, 0, 0.3),
      ("prismatic", np.pi, 0, -0.4, 2.2), ("revolute", 0, 0, 0.37, -0.3)]),
    ("a spherical wrist on a shoulder of coaxial turns",
     [("revolute", 0, 0, 0.3, 0), ("revolute", 0, 0, 0.2, 0), ("revolute", 0, 0, 0.1, 0),
      ("revolute", np.pi / 2, 0, 0.4, 0), ("revolute", -np.pi / 2, 0, 0, 0),
      ("revolute", 0, 0, 0.1, 0)])])
def test_fewer_independent_motions_than_joints_is_redundant(name, rows):
    """A robot whose Jacobian has fewer independent columns than joints everywhere (joints on
    one line, slides along one direction) has a continuum of solutions at every reachable
    pose. A family's closed form (position-2, general-6r, point-plus-roll,
    spherical-wrist) placed none of it: ``ik`` of the robot's own FK pose said "no
    solution". It is called redundant and solved numerically: one solution, reaching the
    pose."""
    r = _dh_robot(name, rows)
    _, family, why = plan(r)
    assert family is None and why.startswith(f"redundant: {r.dof} joints for "), why
    rng = np.random.default_rng(3)
    lo, hi = r.limits.T
    for _ in range(5):
        T = r.fk(rng.uniform(lo, hi))
        res = solve(r, Target(T))
        assert res.reachable and res.family == "numerical", res.reason
        assert np.allclose(r.fk(res.solutions[0].q), T, atol=1e-9)
