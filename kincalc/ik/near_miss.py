"""Candidates that miss by a hair, polished onto the solution next to them.

Near a singularity a closed form takes a double root (subproblem 4 within rounding of its
tangent, a point within its band of an axis) as exact, and the joint it gives is then good to
about sqrt(rounding) only: a pose made from joints 1e-7 deg away from such a configuration gets
candidates that miss the acceptance (``ACCEPT_POSITION``, ``ACCEPT_ORIENTATION``) by 1e-9 to
1e-7 (by ~1e-6 when the pose is rounded to 12 digits, as the CLI's JSON writes it), or that
reach the target with a joint a hair beyond its limit where the solution on the other side of
the merged double root is within it. Such a candidate lies next to a solution:
a few Gauss-Newton steps (:func:`kincalc.ik.refine.refine`, from the candidate with its joints
clipped into their limits) reach it. The polished value replaces the candidate only when it
reaches the target to the acceptance (and, for one beyond its limits, is within them); the
engine's check then judges it like any other.
"""

from __future__ import annotations

import numpy as np

from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION
from .joint_limits import normalise, violations

#: a candidate is polished when it misses by at most this: position error / the arm's size,
#: orientation error (rad), or a joint beyond its limit (rad; / the arm's size for prismatic)
NEAR = 1e-5


def near_misses(robot, candidate, reach, pe, oe, valid, violation):
    """``(N, K)`` bool, or None when there is none: candidates that miss the target by at most
    :data:`NEAR` (``reach`` False), and solutions beyond their limits by at most that.

    ``pe (N, K)`` position errors (m), ``oe (N, K)`` orientation errors (rad) or None,
    ``violation (N, K, n)`` (rad / m, :func:`~kincalc.ik.joint_limits.violations`)."""
    miss = candidate & ~reach
    some_miss, some_beyond = np.count_nonzero(miss), np.count_nonzero(violation)
    if not (some_miss or some_beyond):              # every candidate a solution within limits
        return None
    L = max(robot.characteristic_length, 1e-12)
    mask = np.zeros(miss.shape, bool)
    if some_miss:
        mask = miss & (pe <= NEAR * L)
        if oe is not None:
            mask &= oe <= NEAR
    if some_beyond:
        v = (np.abs(violation) / np.where(robot.is_revolute, 1.0, L)).max(-1)
        mask |= valid & (v > 0.0) & (v <= NEAR)
    return mask if np.count_nonzero(mask) else None


def polished(robot, targets, q, mask, valid, reaches):
    """``q (N, K, n)`` (rad / m) with the slots ``mask (N, K)`` polished where that reaches
    the target (a copy; the other slots unchanged, bit for bit); a slot already ``valid (N,
    K)`` (one beyond its limits) only where the polished value is within them.

    The equations are those the target gives: the whole pose, the position and approach (an
    ``approach`` target), or the position alone (a position arm given a whole pose, whose
    double root moves by ~1e-6 when the pose is rounded to 12 digits, is polished on the pose
    so that its orientation follows too). ``reaches(targets, T) -> (M,) bool`` is the engine's
    test of ``M`` tool poses ``T (M, 4, 4)`` against ``M`` targets, which the polished value
    must pass."""
    from .refine import refine             # (the Newton polish: imported when a pose needs it)
    mode = targets.kind
    if mode not in ("pose", "position", "approach"):
        return q
    rows, slots = mask.nonzero()
    lo, hi = robot.limits.T
    start = np.clip(q[rows, slots], lo, hi)
    aimed = targets.take(rows)
    y = normalise(robot, refine(robot, start, aimed.T, mode=mode, approach=aimed.approach))
    good = reaches(aimed, robot.fk(y))
    good &= ~valid[rows, slots] | (violations(robot, y) == 0.0).all(-1)
    out = q.copy()
    out[rows[good], slots[good]] = y[good]
    return out


def turn_free_joint(S, a: int, b: int, f, g, sol):
    """The free angle of joint ``a`` (``sol``, subproblem 1's: the point ``f`` on its axis)
    chosen so that a target ``g`` a hair off the axis can be polished onto.

    Joint ``b`` a hair from its tangent (a double root taken as exact) leaves ``f (N, K, 3)``
    on axis a while ``g (N, K, 3)`` is off it by ~1e-9 (world frame, m): any angle of a
    misses by that much, and at the subproblem's 0 the miss may lie across the plane joint b
    moves ``f`` in, where no Newton step can reach (a turn of a is second order). Turning the
    direction ``f`` leaves the axis as joint b moves onto the target's offset puts the miss in
    that plane (:func:`polished` then reaches it). Only where 0 would miss the acceptance:
    the offset beyond ``ACCEPT_POSITION`` of the arm's size, or beyond ``ACCEPT_ORIENTATION``
    of joint b's lever on ``f`` (where b moves ``f`` at all, by :data:`NEAR` of the arm's
    size per rad); elsewhere ``sol`` is kept (bit for bit). ``S``: the robot's
    :class:`~kincalc.ik.screws.Screws`. Returns ``(theta, c, s)``, each ``(N, K)``."""
    theta, c, s = sol.theta[0][..., 0], sol.c[0][..., 0], sol.s[0][..., 0]
    if not np.count_nonzero(sol.free):
        return theta, c, s
    k, gq = S.axis[a], g - S.point[a]
    across = gq - (gq @ k)[..., None] * k
    move = np.cross(S.axis[b], f - S.point[b]) if S.revolute[b] else S.axis[b] + 0.0 * f
    lever = np.sqrt(np.add.reduce(move * move, -1))
    bound = np.minimum(ACCEPT_POSITION * S.scale, ACCEPT_ORIENTATION * lever)
    off = sol.free[..., 0] & (np.add.reduce(across * across, -1) > bound * bound) & (
        lever > NEAR * S.scale)                             # (b moves f at all)
    if not np.count_nonzero(off):
        return theta, c, s
    from ..subproblems import sp1
    turn = sp1(move, gq, k, tol=0.0)
    return tuple(np.where(off, t[0][..., 0], x) for t, x in
                 ((turn.theta, theta), (turn.c, c), (turn.s, s)))
