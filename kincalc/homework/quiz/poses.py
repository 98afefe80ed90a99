"""The exercises of :mod:`kincalc.homework.quiz` on a pose: ``ik`` (every solution
within the limits of a reachable pose as written) and ``reach`` (a reachable pose or
one just beyond the reach)."""

from __future__ import annotations

import math

import numpy as np

from ...errors import KincalcError
from .numbers import joint_range, length_word, number_array, random_joints, unit_note
from .rules import ATTEMPTS, IK_CLEARANCE, IK_SEPARATION, NUMERIC_ATTEMPTS, QuizError


# --- poses -------------------------------------------------------------------------------

def _uses_orientation(robot) -> bool:
    from ...ik.families import plan
    family = plan(robot)[1]
    if family is None:
        return robot.generic_ranks[0] >= 6
    return family.needs_orientation


def _written_pose(xyz, rpy, units):
    """``(pose mapping, T (4, 4) in SI)`` for written ``xyz`` and ``rpy`` (or None)."""
    from ...spatial import matrix_from_rpy
    T = np.eye(4)
    T[:3, 3] = np.asarray(xyz, float) / units.l
    pose = {"xyz": list(xyz)}
    if rpy is not None:
        T[:3, :3] = matrix_from_rpy(np.asarray(rpy, float) / units.a)
        pose["rpy"] = list(rpy)
    return pose, T


def pose_forms(robot, T, units):
    """Ways to write the pose ``T`` (SI), from the most rounded to the exact.

    Yields ``(pose mapping, T as written (SI), Target)``: xyz and rpy rounded (a
    few decimals: 1e-4 of the robot's size, 0.01 deg / 1e-4 rad), then xyz rounded
    with the exact rpy, then both exact (for arms with fewer than six joints, whose
    orientation a rounded rpy would take out of reach). Robots that do not control
    the orientation get the position only.
    """
    from ...ik import Target
    from ...spatial import rpy_from_matrix
    orient = _uses_orientation(robot)
    L = robot.characteristic_length * units.l
    dec = min(6, max(0, 4 - round(math.log10(L)))) if L > 0 else 4
    adec = 2 if units.angle == "deg" else 4
    xyz = T[:3, 3] * units.l
    rpy = rpy_from_matrix(T[:3, :3]) * units.a
    exact_xyz = [_exact(x) for x in xyz]
    exact_rpy = [_exact(a) for a in rpy]
    rounded_xyz = [round(float(x), dec) + 0.0 for x in xyz]
    rounded_rpy = [round(float(a), adec) + 0.0 for a in rpy]
    if orient:
        forms = [(rounded_xyz, rounded_rpy), (rounded_xyz, exact_rpy), (exact_xyz, exact_rpy)]
    else:
        forms = [(rounded_xyz, None), (exact_xyz, None)]
    for x, r in forms:
        pose, Tw = _written_pose(x, r, units)
        yield pose, Tw, Target(Tw, orientation=r is not None)


def _exact(x) -> float:
    return float(x) + 0.0


def _pose_text(robot, pose, units) -> str:
    length = length_word(units)
    text = f"position xyz = ({', '.join(map(str, pose['xyz']))}){' ' + length if length else ''}"
    if "rpy" in pose:
        text += (f", orientation rpy = ({', '.join(map(str, pose['rpy']))}) {units.angle} "
                 "(fixed X-Y-Z angles: R = Rz(Y) Ry(P) Rx(R))")
    return text


def _ik_ok(robot, result) -> bool:
    """Is this IK result a fair exercise: solutions within the limits, none singular,
    none within :data:`IK_CLEARANCE` of a limit, the ones within limits apart?"""
    inside = [s for s in result.solutions if s.within_limits]
    if not inside or any(s.singular for s in result.solutions):
        return False
    lo, hi = robot.limits.T
    scale = np.where(robot.is_revolute, 1.0, robot.characteristic_length)
    for s in result.solutions:
        gap = np.minimum(np.abs(s.q - lo), np.abs(s.q - hi)) / scale
        if np.any(gap < IK_CLEARANCE):
            return False
    from ...spatial import wrap
    for a in range(len(inside)):
        for b in range(a):
            d = inside[a].q - inside[b].q
            d = np.where(robot.is_revolute, wrap(d), d / robot.characteristic_length)
            if np.max(np.abs(d)) < IK_SEPARATION:
                return False
    return True


def item_ik(robot, rng, units) -> dict:
    """A reachable pose (FK of random joints, written rounded); the answer is every IK
    solution within the limits of the pose as written."""
    from ...ik import solve
    for _ in range(ATTEMPTS):
        _, q = random_joints(robot, rng, units)
        for pose, _, target in pose_forms(robot, robot.fk(q), units):
            result = solve(robot, target, units=units)
            if not _ik_ok(robot, result):
                continue
            sols = [units.joints(robot, s.q) for s in result.solutions if s.within_limits]
            return {
                "question": (f"Find every joint solution of {robot.name} within its joint "
                             f"limits that reaches the pose: {_pose_text(robot, pose, units)}. "
                             f"Answer: a list of joint vectors{unit_note(robot, units)}, "
                             "[] if there is none."),
                "pose": pose,
                "answer": [number_array(s) for s in sols],
            }
    raise QuizError(f"could not draw an 'ik' exercise for {robot.name} in {ATTEMPTS} tries")


def _beyond(robot, p, rng, samples) -> np.ndarray | None:
    """A position on the ray from the base through ``p`` (m), 2-10 % beyond the
    farthest sampled tool position along that ray's direction."""
    o = robot.base[:3, 3]
    r = np.linalg.norm(p - o)
    if r < 1e-9 * robot.characteristic_length:
        return None
    u = (p - o) / r
    reach_along = float(np.max((samples - o) @ u))
    return o + u * max(reach_along, r) * (1.02 + 0.08 * float(rng.random()))


def item_reach(robot, rng, units) -> dict:
    """Half of the time a reachable pose, otherwise one just beyond the reach along
    the ray from the base; the answer is :func:`kincalc.analysis.reach.reach`'s verdict
    (:data:`NUMERIC_ATTEMPTS` draws of each where no closed form solves the robot)."""
    from ...analysis.reach import reach
    from ...ik.families import plan
    want = bool(rng.integers(2))
    samples = None
    L = robot.characteristic_length
    tries = ATTEMPTS if plan(robot)[1] is not None else NUMERIC_ATTEMPTS
    for attempt in range(2 * tries):
        if attempt == tries:
            want = not want      # e.g. an unlimited prismatic joint: no "no" to give
        _, q = random_joints(robot, rng, units)
        T = np.array(robot.fk(q))
        if not want:
            if samples is None:
                lo, hi = np.array([joint_range(robot, i, units) for i in range(robot.dof)]).T
                scale = np.where(robot.is_revolute, units.a, units.l)
                Q = rng.uniform(lo / scale, hi / scale, (4096, robot.dof))
                samples = robot.fk(Q)[:, :3, 3]
            p = _beyond(robot, T[:3, 3], rng, samples)
            if p is None:
                continue
            T[:3, 3] = p
        for pose, _, target in pose_forms(robot, T, units):
            try:
                res = reach(robot, target, units=units)
            except KincalcError:
                break
            fair = (res.verdict == "reachable") if want else \
                (not res.reachable and (res.distance is None or res.distance > 1e-3 * L))
            if fair:
                return {
                    "question": (f"Can {robot.name} reach this pose within its joint limits: "
                                 f"{_pose_text(robot, pose, units)}? Answer: yes or no."),
                    "pose": pose,
                    "answer": bool(res.reachable),
                }
            if not want:
                break    # only the rounded form of a pose beyond reach is of interest
    raise QuizError(f"could not draw a 'reach' exercise for {robot.name} in {2 * tries} tries")
