"""Redundant arms solved completely: a locked joint leaves a chain the engine solves.

A 7-joint arm reaches a pose along a one-parameter family of configurations. Holding one
joint at a value (``--lock JOINT=VALUE``) leaves six joints: the analytic engine then
returns every branch of that 6-joint chain, labelled and flagged as for any 6-joint arm,
and each solution is the 7-joint configuration with the locked value put back.

The locked chain is built in product-of-exponentials form (Lynch & Park, *Modern
Robotics*, sec. 4.1): with ``G = exp([S_j] v)`` the motion of joint j held at v,

    base · e^[S_1]q_1 ··· G ··· e^[S_n]q_n · M · tool
        = base · e^[S_1]q_1 ··· e^[S_{j-1}]q_{j-1} · e^[S'_{j+1}]q_{j+1} ··· e^[S'_n]q_n · G M · tool

with ``S'_k = Ad_G S_k``: every joint after j has its axis moved by G, and the flange at
q = 0 becomes ``G M``. Its family is found from its axes like any robot's (locking joint 3
of an iiwa leaves a spherical wrist; where no structure is left, the general 6R
elimination). SI inside: rad, m.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import InputError
from ..ik import IKResult, IKSolution, Target, solve
from ..ik.reasons import Blocked, Found
from ..ik.solve import violation_list
from ..ik.verdict import limits_reason
from ..model import Joint, Robot
from ..spatial import matrix_from_axis_angle, transform
from .words import continuum_text


def joint_motion(axis, point, revolute: bool, value) -> np.ndarray:
    """``exp([S] value)`` ``(..., 4, 4)``: a turn by ``value (...)`` (rad) about the line
    through ``point`` along the unit ``axis``, or a slide by ``value`` (m) along ``axis``."""
    axis, point = np.asarray(axis, float), np.asarray(point, float)
    value = np.asarray(value, float)
    if not revolute:
        return transform(None, value[..., None] * axis)
    R = matrix_from_axis_angle(axis, value)
    return transform(R, point - R @ point)


def locked_robot(robot: Robot, locks: dict[int, float]) -> Robot:
    """``robot`` with the joints ``locks`` (0-based index -> value, rad / m) held.

    Parameters
    ----------
    robot : Robot
        Any convention; read through its joint axes at q = 0.
    locks : dict of int to float
        Joint index (0-based) -> the value it is held at (rad / m).

    Returns
    -------
    Robot
        A poe robot of the remaining joints, in order, with their names, limits and home;
        ``fk(q_rest)`` equals ``robot.fk(q)`` with the locked values in place.

    Raises
    ------
    ValueError
        A joint index out of range, or every joint locked.
    """
    from ..conventions import to_poe
    n = robot.dof
    if any(not 0 <= j < n for j in locks):
        raise ValueError(f"joint indices must be 0..{n - 1}, got {sorted(locks)}")
    if len(locks) >= n:
        raise ValueError("every joint is locked: nothing is left to solve")
    poe = to_poe(robot)
    axes = [np.array(j.axis) for j in poe.joints]
    points = [np.array(j.point) for j in poe.joints]
    M = poe.M @ poe.tool
    for j in sorted(locks):
        G = joint_motion(axes[j], points[j], poe.joints[j].revolute, locks[j])
        for k in range(j + 1, n):
            axes[k] = G[:3, :3] @ axes[k]
            points[k] = G[:3, :3] @ points[k] + G[:3, 3]
        M = G @ M
    keep = [k for k in range(n) if k not in locks]
    joints = tuple(Joint(name=poe.joints[k].name, type=poe.joints[k].type,
                         axis=tuple(axes[k] / np.linalg.norm(axes[k])),
                         point=tuple(points[k]), limits=poe.joints[k].limits) for k in keep)
    held = ", ".join(robot.joints[j].name for j in sorted(locks))
    return Robot(name=robot.name, convention="poe", joints=joints, base=robot.base, M=M,
                 home=np.asarray(robot.home)[keep],
                 title=f"{robot.title or robot.name} ({held} locked)", source=robot.source,
                 length_unit=robot.length_unit, angle_unit=robot.angle_unit,
                 structure_tol=robot.structure_tol)


def check_lock(robot: Robot, reduced: Robot, locks: dict[int, float]) -> None:
    """Refuse locks that leave a chain with a self-motion of its own.

    Parameters
    ----------
    robot : Robot
        The whole arm.
    reduced : Robot
        ``locked_robot(robot, locks)``.
    locks : dict of int to float
        Joint index (0-based) -> held value (rad / m).

    Raises
    ------
    InputError
        The reduced chain's generic Jacobian rank is below both its joint count (up to 6)
        and the whole arm's rank (the elbow of an arm whose shoulder and wrist are
        spherical: the arm still turns about the shoulder-wrist line), so its solutions
        form a continuum.
    """
    rank = reduced.generic_ranks[0]
    if rank < min(reduced.dof, 6) and rank < robot.generic_ranks[0]:
        held = ", ".join(robot.joints[j].name for j in sorted(locks))
        # the joints held at other values: is it the value (a wrist joint at 0 putting two
        # axes on one line) or the joint (the elbow of a spherical shoulder and wrist)?
        other = {j: generic_value(robot, j) for j in locks}
        if other != locks and \
                locked_robot(robot, other).generic_ranks[0] >= min(reduced.dof, 6):
            advice = "hold it at another value (at this one two of its axes lie on one line)"
        else:
            advice = ("lock another joint (of an arm with a spherical shoulder and wrist, any "
                      "but the elbow)")
        raise InputError(f"locking {held} of {robot.name} leaves a chain that still moves "
                         f"without moving the tool (its Jacobian has rank {rank} for "
                         f"{reduced.dof} joints): its solutions form a continuum, not a set "
                         f"of branches; {advice}")


#: the value (rad, or arm sizes for a prismatic joint) at which a joint held at every
#: value is checked for a self-motion of the chain it leaves (any but a few special
#: values will do)
GENERIC = 0.9


def generic_value(robot: Robot, joint: int) -> float:
    """:data:`GENERIC` for ``joint`` (0-based): rad, or arm sizes (m) for a prismatic one."""
    return GENERIC * (1.0 if robot.joints[joint].revolute else robot.characteristic_length)


def generic_chain(robot: Robot, joint: int, locks: dict | None = None) -> Robot:
    """The chain ``robot`` leaves with ``joint`` held at :data:`GENERIC` (and ``locks``),
    checked by :func:`check_lock`: what holding the joint at any value gives (its family).

    Raises
    ------
    InputError
        From :func:`check_lock`.
    """
    held = {**(locks or {}), joint: generic_value(robot, joint)}
    chain = locked_robot(robot, held)
    check_lock(robot, chain, held)
    return chain


def with_held(robot: Robot, q, locks: dict) -> np.ndarray:
    """The arm's joints ``(..., n)`` from the joints ``q (..., n - len(locks))`` of the
    chain ``locks`` leave (rad / m), the held values in place; a held value may be an
    array that broadcasts against ``q``'s leading shape."""
    q = np.asarray(q, float)
    keep = [k for k in range(robot.dof) if k not in locks]
    out = np.empty(q.shape[:-1] + (robot.dof,))
    out[..., keep] = q
    for j, v in locks.items():
        out[..., j] = v
    return out


def held_within(robot: Robot, q, joints) -> np.ndarray:
    """``(...)`` bool: the ``joints`` of the arm's configurations ``q (..., n)`` are within
    their limits (the engine's test, :func:`kincalc.ik.joint_limits.violations`)."""
    from ..ik.joint_limits import violations
    return (violations(robot, np.asarray(q, float))[..., list(joints)] == 0).all(-1)


def least_change(robot: Robot, Q, ok, near):
    """The candidate of ``Q (..., n)`` (where ``ok (...)``) nearest the current joints
    ``near (n,)`` (rad / m): each revolute joint moved by whole turns within its limits
    towards ``near`` (:func:`kincalc.spatial.turn_toward`), prismatic changes over the
    arm's size.

    Returns
    -------
    (index tuple, q (n,), change (n,)), or None when no candidate is ``ok``.
    """
    from ..spatial import turn_toward
    near = np.asarray(near, float)
    ok = np.asarray(ok, bool)
    if not ok.any():
        return None
    lo, hi = robot.limits.T
    Q = np.where(ok[..., None], Q, 0.0)
    Q = np.where(robot.is_revolute, turn_toward(Q, near, lo, hi), Q)
    scale = np.where(robot.is_revolute, 1.0, max(robot.characteristic_length, 1e-12))
    cost = np.where(ok, np.linalg.norm((Q - near) / scale, axis=-1), np.inf)
    idx = np.unravel_index(int(np.argmin(cost)), cost.shape)
    return tuple(int(i) for i in idx), Q[idx], Q[idx] - near


def solve_locked(robot: Robot, target: Target, locks: dict[int, float], *,
                 near=None, **options) -> IKResult:
    """Every IK solution of ``robot`` for ``target`` with the joints ``locks`` held.

    Parameters
    ----------
    robot : Robot
        The arm (any number of joints; typically 7).
    target : Target
        As for :func:`kincalc.ik.solve` (``T_world_tool``, m).
    locks : dict of int to float
        Joint index (0-based) -> held value (rad / m).
    near : array_like (n,), optional
        The current joints of the whole arm (rad / m).
    **options
        Those of :func:`kincalc.ik.solve` (``all_branches``, ``explain``, ``units``,
        ``numeric``, ``reasons``).

    Raises
    ------
    InputError
        The locks leave a chain with a self-motion of its own (the elbow of an arm whose
        shoulder and wrist are spherical: the arm still turns about the shoulder-wrist
        line), whose solutions are a continuum.

    Returns
    -------
    IKResult
        Of ``robot``: each solution's ``q (n,)`` holds the locked values, its branch label,
        flags and free joints are those of the locked chain (indices of ``robot``), a
        held value outside its joint's limits is a violation of every solution, and
        ``locked`` lists ``(index, value)``.
    """
    reduced = locked_robot(robot, locks)
    check_lock(robot, reduced, locks)
    keep = [k for k in range(robot.dof) if k not in locks]
    near_full = None if near is None else np.asarray(near, float)
    res = solve(reduced, target, near=None if near_full is None else near_full[keep],
                **options)
    held = [(j, v) for j, v in sorted(locks.items())]
    outside = [v for v in violation_list(robot, with_held(robot, np.zeros(reduced.dof), locks))
               if v[0] in locks]

    def solution(s: IKSolution) -> IKSolution:
        violations = [(keep[i], amount, side) for i, amount, side in s.violations] + outside
        q = with_held(robot, s.q, locks)
        return dataclasses.replace(
            s, q=q, violations=violations, within_limits=s.within_limits and not outside,
            free=tuple(keep[i] for i in s.free),
            continuum=None if s.continuum is None else _Renamed(s.continuum, keep),
            change=None if near_full is None else q - near_full)

    rejected = None if res.rejected is None else \
        [{**r, "q": with_held(robot, r["q"], locks)} for r in res.rejected]
    sols = [solution(s) for s in res.solutions]
    reason = res.reason
    if isinstance(reason, (Found, Blocked)):    # of the arm's joints and its held values
        reason = limits_reason(sols)
    dead = None if res.dead_ends is None else \
        [d._replace(joint=keep[d.joint]) for d in res.dead_ends]  # NoRoot, a NamedTuple
    chain = ", ".join(f"{k + 1} = {robot.joints[i].name}" for k, i in enumerate(keep))
    return dataclasses.replace(res, robot=robot, solutions=sols,
                               reachable=any(s.within_limits for s in sols),
                               rejected=rejected, near=near_full, locked=tuple(held),
                               reason=reason, dead_ends=dead,
                               method=f"{res.method} (joints of the chain the lock leaves: "
                                      f"{chain})")


@dataclasses.dataclass(frozen=True)
class _Renamed:
    """A continuum of the locked chain, read with the whole arm's joint names."""

    inner: object
    keep: list


@continuum_text.register
def _(c: _Renamed, names, units) -> str:
    return continuum_text(c.inner, [names[i] for i in c.keep], units)
