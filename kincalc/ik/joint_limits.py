"""Joint values of the engine's solutions: each revolute joint's representative (whole turns)
nearest its limits, how far each joint is beyond them, and when two are one solution.

One tolerance, ``LIMIT_TOL`` (:mod:`kincalc.tolerances`: rad, or times the arm's size for
prismatic joints), for every path that answers IK: ``robot.ik``, ``ik --batch``, ``reach``,
``workspace``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..spatial import into_limits, wrap
from ..tolerances import DUPLICATE, INEXACT, LIMIT_TOL, SPLIT_DOUBLE_ROOT
from .cache import per_robot


def normalise(robot, Q) -> np.ndarray:
    """``Q`` with each revolute joint moved by whole turns to the value nearest its limits.

    In (-pi, pi] when that is within them (to ``LIMIT_TOL``), else the turn within them
    nearest it (:func:`~kincalc.spatial.into_limits`), else the one that misses them least;
    prismatic kept.

    Parameters
    ----------
    robot : Robot
    Q : array_like (..., n), joint values (rad / m)

    Returns
    -------
    ndarray (..., n), a new array
    """
    Q = np.asarray(Q, float)
    rev, every = _revolute(robot)
    if Q.size == 0 or rev is None:
        return Q.copy()
    x = wrap(Q if every else Q[..., rev])
    lo, hi = _limits(robot, x.shape, every)[2:4]
    x = into_limits(x, lo, hi)
    if every:
        return x
    Q = Q.copy()
    Q[..., rev] = x
    return Q


def joint_scale(robot) -> np.ndarray:
    """``(n,)``: each joint's unit in scale-free joint values, 1 for a revolute joint (rad)
    and the arm's size (m, at least 1e-12) for a prismatic one: ``q / joint_scale`` weighs
    every joint alike in a Newton step or a distance."""
    return np.where(robot.is_revolute, 1.0, max(robot.characteristic_length, 1e-12))


def same_solution(robot, a, b) -> np.ndarray:
    """Whether configurations are one solution: every joint within ``DUPLICATE``
    (:mod:`kincalc.tolerances`; rad, revolute joints compared modulo whole turns, or m).

    Parameters
    ----------
    robot : Robot
    a, b : array_like (..., n), joint values (rad / m); the leading shapes broadcast

    Returns
    -------
    ndarray (...) of bool
    """
    d = np.asarray(a, float) - np.asarray(b, float)
    return (np.abs(np.where(robot.is_revolute, wrap(d), d)) < DUPLICATE).all(-1)


def halfway_is_better(least, half) -> np.ndarray:
    """Are two copies of one root better answered halfway between them? ``least (...)``: how
    far the better copy misses its target, ``half (...)``: how far the joints halfway between
    the two miss it (one measure: over the arm's size, plus rad). Yes where the halfway
    joints miss by less than half the better copy (rounding split one root: a double root's
    two roots move apart by the square root of a change, and its middle lies nearer it than
    either), or to ``INEXACT`` (rounding cannot tell one root from two there). The rule of
    the engine's double roots (:func:`kincalc.ik.near_miss.double_roots`) and of a
    placement's (:func:`kincalc.ik.point_polish.polish_points`).

    Returns
    -------
    ndarray (...) of bool
    """
    return (half < 0.5 * least) | (half <= INEXACT)


def close_pairs(robot, q, valid, f=None) -> tuple:
    """The pairs of valid slots of a pose whose joints agree to the wider of ``DUPLICATE``
    (rad / m) and ``SPLIT_DOUBLE_ROOT`` (rad, or of the arm's size): the candidates of
    :func:`duplicates` and of :func:`~kincalc.ik.near_miss.copies`.

    Pairs are screened first by one number per slot, ``key = sum_k w_k f_k(q_k)`` with
    ``f = (cos, sin)`` of revolute joints and the value of prismatic ones: both are 1-Lipschitz,
    so two slots within ``t_k`` in every joint have keys within ``sum_k |w_k| t_k``, and only
    the pairs that pass are compared joint by joint (distinct solutions almost never do).

    Parameters
    ----------
    robot : Robot
    q : ndarray (N, K, n), joint values (rad / m)
    valid : ndarray (N, K) of bool
    f : three ndarray (n, N K), optional: the joints' cosines, sines and values, joint-major
        (of ``q`` plus any constant per joint, such as the chain's offsets)

    Returns
    -------
    pose, j, i : ndarray (m,) of int, each pair's pose and slots, ``i < j``, ascending in ``j``
    """
    N, K, n = q.shape
    none = np.empty(0, np.intp)
    if K < 2 or np.count_nonzero(valid) < 2:
        return none, none, none
    if f is None:
        x = q.reshape(-1, n).T
        f = np.cos(x), np.sin(x), x
    w, reach, tol = _pair_key(robot)
    key = (w[0] @ f[0] + w[1] @ f[1] + w[2] @ f[2]).reshape(N, K)
    # poses with two valid keys within reach: neighbours once each pose's keys are sorted
    ordered = np.where(valid, key, np.nan)
    ordered.sort(axis=1)                                             # NaN (invalid) last
    suspect = ordered[:, 1:] - ordered[:, :-1] <= reach              # NaN: False
    if not np.count_nonzero(suspect):
        return none, none, none
    poses = np.flatnonzero(suspect.any(1))
    kv, ok = key[poses], valid[poses]
    near = (np.abs(kv[:, :, None] - kv[:, None, :]) <= reach) & ok[:, :, None] \
        & ok[:, None, :] & np.tri(K, k=-1, dtype=bool)             # [j, i]: i < j
    pose, j, i = np.nonzero(near)
    pose = poses[pose]
    d = q[pose, j] - q[pose, i]
    close = (np.abs(np.where(robot.is_revolute, wrap(d), d)) <= tol).all(-1)
    return pose[close], j[close], i[close]


def duplicates(robot, q, valid, pairs) -> np.ndarray:
    """Valid slots that are the same solution as an earlier kept one (every joint within
    ``DUPLICATE``, wrapped: :func:`same_solution`).

    Parameters
    ----------
    robot : Robot
    q : ndarray (N, K, n), joint values (rad / m)
    valid : ndarray (N, K) of bool
    pairs : tuple, :func:`close_pairs` of these slots

    Returns
    -------
    ndarray (N, K) of bool, the slots to drop
    """
    drop = np.zeros(valid.shape, bool)
    pose, j, i = pairs
    if not len(pose):
        return drop
    same = same_solution(robot, q[pose, j], q[pose, i])                 # (pairs,)
    pose, j, i = pose[same], j[same], i[same]
    # ascending: a slot's verdict before later ones (not np.unique, which imports numpy.ma:
    # 15 ms of the first call that meets a duplicate)
    for slot in np.flatnonzero(np.bincount(j)).tolist():
        at = j == slot
        kept = ~drop[pose[at], i[at]]
        drop[pose[at][kept], slot] = True
    return drop


@per_robot
def _pair_key(robot) -> tuple:
    """The weights ``(3, n)`` of :func:`close_pairs`' screening key (of the cosines, the
    sines and the values), how far apart the keys of two close slots can be, and each
    joint's closeness ``(n,)`` (rad / m). Cached per robot."""
    rev = robot.is_revolute
    tol = np.maximum(DUPLICATE, SPLIT_DOUBLE_ROOT * joint_scale(robot))
    w = 1.0 + 0.37 * np.arange(robot.dof)                      # generic, fixed weights
    reach = (tol * w * np.where(rev, 1.61, 1.0)).sum() * (1 + 1e-9) + 1e-15
    return np.array([np.where(rev, w, 0.0), np.where(rev, 0.61 * w, 0.0),
                     np.where(rev, 0.0, w)]), reach, tol


def on_continua(robot, q, valid, free, relation=None) -> np.ndarray:
    """Valid slots that are members of another slot's continuum.

    A slot that leaves joints free (a singular target) stands for every value of them; a
    valid slot equal to it in all its other joints (:func:`same_solution`'s rule) and free
    in none of those reaches the same target on that continuum: a point of it that the
    solver found as a root of its own (where the free joint's roots meet). Where the free
    joint moves with another (``relation``: an aligned wrist's ``q_i + sigma q_j = total``),
    the other joint is compared by that relation instead. Of two slots with the same free
    joints the later goes.

    Parameters
    ----------
    robot : Robot
    q : ndarray (N, K, n), joint values (rad / m)
    valid : ndarray (N, K) of bool
    free : ndarray (N, K, n) of bool, the joints each slot leaves free
    relation : ndarray (N, K, 5) or None
        Each slot's continuum relation, ``(mask, i, j, sigma, total)`` (rad) where the mask is
        not 0 (``Branches.extra["continuum"]``).

    Returns
    -------
    ndarray (N, K) of bool, the slots to drop
    """
    drop = np.zeros(valid.shape, bool)
    pose, a = np.nonzero(valid & np.logical_or.reduce(free, axis=-1))
    if not len(pose):
        return drop
    fa = free[pose, a][:, None]                                             # (m, 1, n)
    d = q[pose] - q[pose, a][:, None]                                       # (m, K, n)
    close = np.abs(np.where(robot.is_revolute, wrap(d), d)) < DUPLICATE
    if relation is not None:
        close = _by_relation(q[pose], close, relation[pose, a])
    same = np.logical_and.reduce(close | fa, axis=-1)
    same &= valid[pose] & ~np.logical_or.reduce(free[pose] & ~fa, axis=-1)
    later = np.arange(q.shape[1]) > a[:, None]
    same &= later | np.logical_or.reduce(free[pose] != fa, axis=-1)         # (not a itself)
    np.logical_or.at(drop, pose, same)                  # (a pose may have several such a)
    return drop


def _by_relation(q, close, relation) -> np.ndarray:
    """``close (m, K, n)`` (each joint of the slots ``q (m, K, n)`` equal to a free slot's)
    with the related joint ``j`` of each free slot's continuum relation ``(m, 5)`` (:func:`
    on_continua`) judged by the relation: ``q_i + sigma q_j = total``, wrapped."""
    on = np.flatnonzero(relation[:, 0])
    if not len(on):
        return close
    i, j = relation[on, 1].astype(np.intp), relation[on, 2].astype(np.intp)
    at, slots = on[:, None], np.arange(q.shape[1])
    qi, qj = q[at, slots, i[:, None]], q[at, slots, j[:, None]]             # (o, K)
    off = wrap(qi + relation[on, 3:4] * qj - relation[on, 4:5])
    close = close.copy()
    close[at, slots, j[:, None]] = np.abs(off) < DUPLICATE
    return close


@per_robot
def _revolute(robot) -> tuple:
    """``(index of the revolute joints or None when there is none, all joints revolute)``.
    Cached per robot."""
    rev = robot.is_revolute
    return (np.flatnonzero(rev) if rev.any() else None), bool(rev.all())


#: values up to this many are given limits of their own shape (:func:`_limits`): numpy
#: broadcasts an ``(n,)`` array against them at twice the cost of an operand of their shape
TILED = 512


@per_robot
def _limits(robot, shape: tuple, every: bool) -> tuple:
    """The limits :func:`normalise` and :func:`violations` compare with, cached per robot and
    shape (for values of up to :data:`TILED` entries; ``(n,)`` arrays beyond).

    ``every``: of all joints (``shape (..., n)``), else of the revolute ones. Returns ``(lo, hi,
    lo - tol, hi + tol)``, read-only: ``tol`` is ``LIMIT_TOL`` (rad, or times the arm's size
    for prismatic joints)."""
    n = len(robot.is_revolute)
    if len(shape) and int(np.prod(shape)) > TILED:
        return _limits(robot, (shape[-1],), every)
    rev = robot.is_revolute if not every else np.ones(n, bool)
    lo, hi = robot.limits[rev].T
    tol = np.where(robot.is_revolute[rev], LIMIT_TOL,
                   LIMIT_TOL * max(robot.characteristic_length, 1e-12))
    out = [np.ascontiguousarray(np.broadcast_to(a, shape)) for a in (lo, hi, lo - tol, hi + tol)]
    for a in out:
        a.setflags(write=False)
    return tuple(out)


def within_limits(robot, Q) -> np.ndarray:
    """Is each configuration within the limits, revolute joints allowing whole turns?

    Parameters
    ----------
    robot : Robot
    Q : array_like (..., n), joint values (rad / m)

    Returns
    -------
    ndarray (...) of bool, :func:`normalise` puts it within them (-170 deg passes [0, 360] deg)
    """
    return ~(violations(robot, normalise(robot, Q)) != 0).any(-1)


def violations(robot, q) -> np.ndarray:
    """How far each joint of ``q`` is beyond its limits, beyond ``LIMIT_TOL``.

    Parameters
    ----------
    robot : Robot, its limits (``LIMIT_TOL``: rad, or times the arm's size for prismatic)
    q : ndarray (..., n), joint values (rad / m), not wrapped

    Returns
    -------
    ndarray (..., n), ``q - lower`` below the lower limit, ``q - upper`` above the upper, else 0
    """
    q = np.asarray(q, float)
    lo, hi, lo_band, hi_band = _limits(robot, q.shape, True)
    return np.where(q < lo_band, q - lo, np.where(q > hi_band, q - hi, 0.0))


@lru_cache(maxsize=1024)
def open_joints(signs, n: int) -> np.ndarray:
    """``(K, n)`` bool: the joints each of ``K`` slots leaves open, labelled ``any`` in its
    ``signs`` (a tuple of ``K`` tuples of ``(joint, label)``): a value the target does not
    ask for moves nothing it asks for (the roll of a five-joint arm given an approach).

    Made once per sign table (a family has a few; every call asks twice): read-only, shared."""
    out = np.zeros((len(signs), n), bool)
    for k, sg in enumerate(signs):
        for j, label in sg:
            if label == "any":
                out[k, j] = True
    out.flags.writeable = False
    return out


def open_values(robot, br):
    """``br`` with each open joint (:func:`open_joints`) at the value nearest 0 within its
    limits: 0 where that is within them (whole turns allowed), else the nearer limit (for a
    revolute joint, nearer 0 by the wrapped distance).

    Parameters
    ----------
    robot : Robot, its limits (rad / m)
    br : Branches, the solved slots (:class:`~kincalc.ik.branches.Branches`)

    Returns
    -------
    Branches, the open joints' values (rad / m), cosines and sines set; ``br`` itself when
    no joint is open or 0 is within the limits of every open one
    """
    opened = open_joints(br.signs, br.n)
    if not opened.any():
        return br
    n = br.n
    zero = np.zeros(n)
    lo, hi = robot.limits.T
    fine = violations(robot, normalise(robot, zero)) == 0.0
    lo_w, hi_w = (np.where(np.isfinite(x), np.abs(wrap(np.where(np.isfinite(x), x, 0.0))),
                           np.inf) for x in (lo, hi))
    near = np.where(lo_w <= hi_w, lo, hi)           # 0 outside: a finite limit is nearer
    near = np.where(robot.is_revolute, near, np.clip(0.0, lo, hi))
    for j in np.flatnonzero(opened.any(axis=0) & ~fine).tolist():
        v = np.where(opened[:, j], near[j], br.value[j])
        br = br.set(j, v, np.cos(v), np.sin(v))
    return br
