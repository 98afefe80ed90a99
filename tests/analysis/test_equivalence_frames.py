"""``match`` with free base and tool frames (what 'base: ignore' / 'tool: ignore' grade)
on degenerate robots: parallel and coaxial axes, special and nearly special twists,
prismatic joints, base and tool rotations.

The robots are drawn from a seeded generator; the candidate is the robot's own rows
(with joint offsets added, so that the branch search runs rather than the
same-joints check) and another base and tool where those are free. The truth is
independent of the search: the candidate's FK is, by construction, the reference's
up to the offsets and the frames."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from kincalc.analysis.compare import match
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform
from randrobots import degenerate_dh_robot as degenerate_robot
from randrobots import random_pose

#: the tolerance 'kincalc check' passes (position tolerance / arm size), and a strict one
TOLS = [1e-3, 1e-6]


def shifted(robot, rng):
    """The robot's rows with a random offset on some joint variables."""
    joints = []
    for j in robot.joints:
        c = rng.uniform(-1, 1) if rng.random() < 0.5 else 0.0
        joints.append(dataclasses.replace(j, theta=j.theta + c) if j.revolute
                      else dataclasses.replace(j, d=j.d + 0.2 * c))
    return dataclasses.replace(robot, joints=tuple(joints))


def robots(count, seed):
    rng = np.random.default_rng(seed)
    return [(degenerate_robot(rng, int(rng.integers(2, 7))), rng) for _ in range(count)]


def the_tester_robots():
    """The tester's two: all axes parallel under a rotated base (a); a prismatic first
    joint with alpha just off 90 deg, joints 2 and 3 coaxial, base moved along x (b)."""
    a = Robot(name="m3", convention="dh", joints=(
        Joint("q1", "revolute", alpha=math.pi, a=0.3, d=0.0, theta=0.0),
        Joint("q2", "revolute", alpha=math.pi, a=0.2, d=0.1, theta=0.0),
        Joint("d3", "prismatic", alpha=math.pi, a=0.0, d=0.0, theta=0.0, limits=(0, 0.2))),
        base=transform(matrix_from_rpy(np.radians([30, 40, 50])), [0.1, 0.2, 0.3]),
        tool=transform(np.eye(3), [0.05, 0, 0]))
    b = Robot(name="m1", convention="dh", joints=(
        Joint("d1", "prismatic", alpha=math.radians(89.99998), a=0.0, d=0.0,
              theta=-math.pi / 2, limits=(0, 0.4)),
        Joint("q2", "revolute", alpha=0.0, a=0.0, d=-0.2317, theta=0.0),
        Joint("q3", "revolute", alpha=-math.pi / 2, a=0.0, d=0.1012, theta=0.0)),
        base=np.array([[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]))
    return [a, b]


FREE = list(itertools.product([False, True], repeat=2))


@pytest.mark.parametrize("tol", TOLS)
@pytest.mark.parametrize("free_base,free_tool", FREE)
def test_the_tester_robots_own_rows_match_with_frames_free(free_base, free_tool, tol):
    for r in the_tester_robots():
        for cand in (r, shifted(r, np.random.default_rng(5))):
            if free_base:
                cand = dataclasses.replace(cand, base=np.eye(4))
            if free_tool:
                cand = dataclasses.replace(cand, tool=np.eye(4))
            m = match(r, cand, allow_offsets=True, free_base=free_base,
                      free_tool=free_tool, tol=tol)
            assert m.same, (r.name, m.reason)


@pytest.mark.parametrize("tol", TOLS)
def test_degenerate_robots_with_offsets_match_with_frames_free(tol):
    fails = []
    for k, (r, rng) in enumerate(robots(40, 2024)):
        for free_base, free_tool in FREE:
            cand = shifted(r, rng)
            if free_base:
                cand = dataclasses.replace(cand, base=random_pose(rng))
            if free_tool:
                cand = dataclasses.replace(cand, tool=random_pose(rng))
            m = match(r, cand, allow_offsets=True, free_base=free_base,
                      free_tool=free_tool, tol=tol, samples=50)
            if not m.same:
                fails.append((k, free_base, free_tool, m.reason))
    assert not fails


def test_a_wrong_distance_between_axes_stays_wrong_with_frames_free():
    # a_i is the distance between the revolute axes i and i + 1: no offset, base or
    # tool changes it
    checked = 0
    for r, rng in robots(30, 7):
        rows = [i for i in range(r.dof - 1) if r.is_revolute[i] and r.is_revolute[i + 1]]
        if not rows:
            continue
        i = rows[0]
        j = r.joints[i]
        bad = list(r.joints)
        bad[i] = dataclasses.replace(j, a=j.a + (0.1 if j.a >= 0 else -0.1))
        cand = dataclasses.replace(r, joints=tuple(bad), base=np.eye(4), tool=np.eye(4))
        m = match(r, cand, allow_offsets=True, free_base=True, free_tool=True, tol=1e-3,
                  samples=50)
        assert not m.same and m.first_bad_joint is not None
        checked += 1
    assert checked >= 10


def test_own_rows_give_the_same_joint_variables():
    # coaxial joints fix only the sum of their offsets; the robot's own rows still
    # match with signs 1 and offsets 0
    for r, _ in robots(20, 11):
        for free_base, free_tool in FREE:
            cand = r
            if free_base:
                cand = dataclasses.replace(cand, base=np.eye(4))
            if free_tool:
                cand = dataclasses.replace(cand, tool=np.eye(4))
            m = match(r, cand, allow_offsets=True, free_base=free_base,
                      free_tool=free_tool, tol=1e-3, samples=50)
            assert m.same and np.all(m.signs == 1) and np.all(m.offsets == 0)
