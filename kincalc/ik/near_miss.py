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

Two solutions that are one double root (two polished copies, two roots a pose's rounding
split, the two sides of a flat one) are answered once (:func:`double_roots`): at the joints
halfway between them where those reach the target better than both (:func:`at_halfway`),
else the one that misses less (:func:`copies`).
"""

from __future__ import annotations

import numpy as np

from ..fk import forward_kinematics
from ..spatial import wrap
from ..tolerances import (INEXACT, NEAR_LIMIT, NEAR_MISS as NEAR, NEAR_MISS_UNCONTROLLED,
                          ROUGH, SAME_DOUBLE_ROOT, SPLIT_DOUBLE_ROOT)
from .joint_limits import halfway_is_better, joint_scale, normalise, violations



def near_misses(robot, candidate, reach, pe, oe, valid, violation, controlled: bool = True,
                free=None):
    """``(N, K)`` bool, or None when there is none: candidates that miss the target by at most
    :data:`~kincalc.tolerances.NEAR_MISS` (``reach`` False), solutions beyond their limits
    by at most :data:`~kincalc.tolerances.NEAR_LIMIT`, and solutions that reach the target
    less well than :data:`~kincalc.tolerances.ROUGH` (of the arm's size, or rad in the
    components the robot controls: a root a few Gauss-Newton steps left 1e-10 short, which
    the polish takes to rounding), other than a continuum's representatives (``free (N, K, n)``
    bool, or None: the joints each leaves free), which may miss by the width of the band that
    made the target singular.

    ``pe (N, K)`` position errors (m), ``oe (N, K)`` orientation errors (rad) or None,
    ``violation (N, K, n)`` (rad / m, :func:`~kincalc.ik.joint_limits.violations`);
    ``controlled`` False for an orientation the robot does not control: its near miss is
    :data:`~kincalc.tolerances.NEAR_MISS_UNCONTROLLED` (next to a double root of the position,
    the joints and the orientation are good to the square root of rounding only)."""
    miss = candidate & ~reach
    L = max(robot.characteristic_length, 1e-12)
    rough = pe > ROUGH * L
    if oe is not None and controlled:
        rough |= oe > ROUGH
    rough &= valid
    if free is not None:
        rough &= ~np.logical_or.reduce(free, axis=-1)
    some_miss, some_beyond = np.count_nonzero(miss), np.count_nonzero(violation)
    some_rough = np.count_nonzero(rough)
    if not (some_miss or some_beyond or some_rough):  # every candidate exact, within limits
        return None
    mask = rough
    if some_miss:
        near = miss & (pe <= NEAR * L)
        if oe is not None:
            near &= oe <= (NEAR if controlled else max(NEAR, NEAR_MISS_UNCONTROLLED))
        mask = mask | near
    if some_beyond:
        v = (np.abs(violation) / np.where(robot.is_revolute, 1.0, L)).max(-1)
        mask |= valid & (v > 0.0) & (v <= NEAR_LIMIT)
    return mask if np.count_nonzero(mask) else None


def polished(robot, targets, q, mask, valid, judge, free=None):
    """``q (N, K, n)`` (rad / m) with the slots ``mask (N, K)`` polished where that reaches
    the target (a copy; the other slots unchanged, bit for bit), each from its own joints (from
    the limit for a joint a hair beyond it: :data:`~kincalc.tolerances.NEAR_LIMIT`); a slot
    already ``valid (N, K)`` only where the polished value moves it into the limits, or reaches
    the target better without leaving them. The joints a
    slot leaves free (``free (N, K, n)`` bool, or None) keep their values where that
    reaches the target (every value does, and the polish would move them at random), else
    move too (a band of a double root can call free a joint that is not quite).

    The equations are those the target gives: the whole pose, the position and approach (an
    ``approach`` target), or the position alone (a position arm given a whole pose, whose
    double root moves by ~1e-6 when the pose is rounded to 12 digits, is polished on the pose
    so that its orientation follows too). ``judge(rows, T) -> (error (M,), reach (M,))`` is the
    engine's measure and test of ``M`` tool poses ``T (M, 4, 4)`` against the targets of
    poses ``rows (M,)`` (as :func:`double_roots` takes it), which the polished value must
    pass."""
    from .refine import refine             # (the Newton polish: imported when a pose needs it)
    mode = targets.kind
    if mode not in ("pose", "position", "approach"):
        return q
    rows, slots = mask.nonzero()
    lo, hi = robot.limits.T
    start = q[rows, slots]
    inside = np.clip(start, lo, hi)                  # a hair beyond a limit: from the limit
    start = np.where(np.abs(inside - start) / joint_scale(robot) <= NEAR_LIMIT, inside, start)
    was_within = (violations(robot, q[rows, slots]) == 0.0).all(-1)
    before = judge(rows, forward_kinematics(robot.chain, q[rows, slots], column_walk=True))[0]
    held = None if free is None else free[rows, slots]
    out = q.copy()
    for holding in ((True, False) if held is not None and held.any() else (False,)):
        aimed = targets.take(rows)
        y = normalise(robot, refine(robot, start, aimed.T, mode=mode, approach=aimed.approach,
                                    held=held if holding else None))
        error, good = judge(rows, forward_kinematics(robot.chain, y, column_walk=True))
        within = (violations(robot, y) == 0.0).all(-1)
        # a solution moves into its limits, or nearer its target without leaving them
        good &= ~valid[rows, slots] | (within & ~was_within) | (
            (error < before) & (within | ~was_within))
        out[rows[good], slots[good]] = y[good]
        rows, slots, start = rows[~good], slots[~good], start[~good]
        was_within, before = was_within[~good], before[~good]
        held = None if held is None else held[~good]
        if not len(rows):
            break
    return out


def copies(robot, q, valid, pairs, one, miss, flat=None) -> tuple:
    """Of two valid slots of a pose that are one double root, the one that misses its target
    by more (a tie, or both within ``INEXACT``: the later): slots whose joints agree to
    :data:`~kincalc.tolerances.SAME_DOUBLE_ROOT` (rad, or of the arm's size) with the
    evidence ``one``, or to :data:`~kincalc.tolerances.SPLIT_DOUBLE_ROOT` with ``flat``.

    ``q (N, K, n)`` (rad / m), ``valid (N, K)``; ``pairs``: ``(pose, j, i)`` of
    :func:`~kincalc.ik.joint_limits.close_pairs`, ``one (m,)`` bool: the pair is one double
    root (the caller's evidence: Gauss-Newton reached it from two candidates, or the joints
    halfway between the two reach the target too); ``flat (m,)`` bool or None: the pair is
    the two sides of a flat double root (the joints halfway miss the target by less than
    either); ``miss (m, 2)``: how far slots ``j`` and ``i`` miss the target (the caller's
    measure).

    Returns ``(drop, same)``: ``drop (N, K)`` bool, the slots that go; ``same (m,)`` bool, the
    pairs that are one double root."""
    pose, j, i = pairs
    drop = np.zeros(valid.shape, bool)
    d = q[pose, j] - q[pose, i]
    d = (np.abs(np.where(robot.is_revolute, wrap(d), d)) / joint_scale(robot)).max(-1)
    same = one & (d <= SAME_DOUBLE_ROOT)
    if flat is not None:
        same |= flat & (d <= SPLIT_DOUBLE_ROOT)
    same &= valid[pose, j] & valid[pose, i]
    # (two copies that both reach the target to rounding tie: which misses less is noise,
    # and would differ between a batch's FK and a single pose's)
    miss = np.where(miss <= INEXACT, 0.0, miss)
    worse_j = miss[:, 0] >= miss[:, 1]
    drop[pose[same], np.where(worse_j, j, i)[same]] = True
    return drop, same


def double_roots(robot, q, valid, pairs, polished_slots, judge, again=False) -> tuple:
    """:func:`copies` of the close ``pairs`` of ``q (N, K, n)``
    (:func:`~kincalc.ik.joint_limits.close_pairs`) that are one double root, and of those the
    ones better answered halfway between their two solutions.

    Two solutions within ``SAME_DOUBLE_ROOT`` are one double root where one of them was
    polished (``polished_slots (N, K)`` or None: Gauss-Newton approaches a double root only
    linearly, from two candidates) or the joints halfway between them reach the target too
    (between two distinct roots the target is missed by the slope times half their
    distance), except where both reach the target to ``INEXACT`` and the halfway joints
    miss it by more: two roots, however close (next to a fold the slope is small). With
    ``again`` (bool, or ``(N,)`` per pose: the halfway joints can be checked again), two
    within ``SPLIT_DOUBLE_ROOT`` are one where neither reaches the target to ``INEXACT`` and
    the halfway joints miss it by less than half the better: the two sides of a flat double
    root (:mod:`kincalc.tolerances`). A pair is answered halfway (``again`` only) where
    :func:`~kincalc.ik.joint_limits.halfway_is_better`. The two, and the joints halfway, are
    evaluated by the column walk, whose bits do not depend on the batch.

    ``judge(rows, T) -> (error, reach)``, each ``(M,)``: how far the tool poses ``T (M, 4,
    4)`` miss the targets of poses ``rows (M,)``, and whether they reach them (the engine's
    measure and test).

    Returns ``(drop, halfway)``: ``drop (N, K)`` the copies that go; ``halfway``, the pairs
    to answer halfway, ``(pose, j, i, half)`` with ``half (m, n)`` (rad / m), or None."""
    pose, j, i = pairs
    live = np.flatnonzero(valid[pose, j] & valid[pose, i])
    if not len(live):
        return np.zeros(valid.shape, bool), None
    one, miss = np.zeros(len(pose), bool), np.zeros((len(pose), 2))
    a, b = q[pose[live], i[live]], q[pose[live], j[live]]
    d = b - a
    half = np.zeros((len(pose), robot.dof))
    half[live] = a + 0.5 * np.where(robot.is_revolute, wrap(d), d)
    T = forward_kinematics(robot.chain, np.concatenate([b, a, half[live]]), column_walk=True)
    error, reach = judge(np.tile(pose[live], 3), T)
    m = len(live)
    miss[live] = error[:2 * m].reshape(2, m).T
    one[live] = reach[2 * m:]
    better, sides = np.zeros(len(pose), bool), np.zeros(len(pose), bool)
    least = miss[live].min(-1)
    better[live] = halfway_is_better(least, error[2 * m:])
    sides[live] = better[live] & (least > INEXACT)
    if polished_slots is not None:
        one |= polished_slots[pose, j] | polished_slots[pose, i]
    # two solutions that each reach the target to rounding, with the target missed between
    # them, are two roots however close: next to a fold the target changes to second order
    # only, and the joints halfway still reach it (two elbows 4e-6 rad apart, 2e-6 from the
    # stretched elbow: each to 1e-16, halfway to 1e-12)
    distinct = np.zeros(len(pose), bool)
    distinct[live] = (miss[live].max(-1) <= INEXACT) & (error[2 * m:] > INEXACT)
    one &= ~distinct
    again = np.broadcast_to(again, valid.shape[:1])[pose]       # (per pair)
    drop, same = copies(robot, q, valid, pairs, one, miss, sides & again)
    met = same & better & again
    if not met.any():
        return drop, None
    return drop, (pose[met], j[met], i[met], half[met])


def at_halfway(q, moved, pose, j, i, half) -> tuple:
    """``q (N, K, n)`` with both slots ``j`` and ``i`` of each pose in ``pose`` (one double
    root: :func:`double_roots`) at the joints ``half`` halfway between them, and the slots
    ``moved (N, K)`` (or None) with those added: the double root checked again at its middle,
    which is nearer it than either copy rounding split off (a double root's roots move by the
    square root of a change of the pose), and the two, now one solution, left to
    :func:`~kincalc.ik.joint_limits.duplicates`, which keeps the earlier slot in every
    convention and batch."""
    q = q.copy()
    q[pose, j] = q[pose, i] = half
    moved = np.zeros(q.shape[:2], bool) if moved is None else moved.copy()
    moved[pose, j] = moved[pose, i] = True
    return q, moved
