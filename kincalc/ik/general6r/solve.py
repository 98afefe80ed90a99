"""The general-6R solver's public API: every real solution of a batch of poses, and
the engine's step."""

from __future__ import annotations

import numpy as np

from ...spatial import wrap
from ..joint_limits import within_limits
from .common import (ACCEPT_TOL, BATCH_SLOTS, MERGE_TOL, RESCUE_ITERS, SETTLED, STARTS, THIN,
                     VALLEY, nnz, reduce_all, reduce_max)
from .polish import polish_candidates, polish_from_both_sides, regular
from .robot import robot_data


# --- public API -------------------------------------------------------------

def solve_general_6r_batch(robot, T) -> tuple[np.ndarray, np.ndarray]:
    """All real IK solutions of a 6R robot (any geometry) for a batch of poses.

    Parameters
    ----------
    robot : Robot
        Six revolute joints; no structure needed (see the package docstring for robots
        with special structure).
    T : array_like (N, 4, 4)
        Tool poses ``T_world_tool`` (SI, world frame). A single pose is ``T[None]``.

    Returns
    -------
    Q : ndarray (N, BATCH_SLOTS, 6)
        Joint values (rad, wrapped to (-pi, pi]); 0 in unused slots.
    ok : ndarray (N, BATCH_SLOTS) bool
        The valid slots, first in each row: each reproduces its pose by FK to 1e-10
        relative to ``robot.characteristic_length`` (position) and 1e-10 rad, after
        Newton polishing on ``robot.chain`` (the last resort's candidates also from a
        second start each, past their solution: a close pair's other one); duplicates
        within MERGE_TOL are merged. A pose that no candidate reaches so is rescued (to
        SETTLED, thinned: see the package docstring). A pose outside the workspace or a
        non-finite pose gets none.

    Raises
    ------
    ValueError
        If ``robot`` does not have exactly 6 revolute joints, or ``T`` is not (N, 4, 4).

    Notes
    -----
    Every step (model, elimination, eigenproblems, clusters, other pivots, Newton)
    runs on all poses together; see the package docstring for the method.
    """
    if robot.dof != 6 or not all([j.revolute for j in robot.joints]):
        raise ValueError("solve_general_6r_batch needs a robot with exactly 6 revolute "
                         "joints, got " + "".join("R" if j.revolute else "P"
                                                  for j in robot.joints))
    T = np.asarray(T, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise ValueError(f"T must be an (N, 4, 4) array of transforms, got shape {T.shape}")
    N = len(T)
    Q = np.zeros((N, BATCH_SLOTS, 6))
    ok = np.zeros((N, BATCH_SLOTS), bool)
    data = robot_data(robot)
    for lo in range(0, N, _BLOCK):       # blocks of poses: their arrays stay in cache
        _solve_block(data, T[lo:lo + _BLOCK], Q[lo:lo + _BLOCK], ok[lo:lo + _BLOCK])
    return Q, ok


#: poses solved together (larger batches go in blocks of this many)
_BLOCK = 512


#: a pose none of whose candidates reaches it, though one came this close (Newton's scaled
#: residual), gets the last resort too: a pose a hair from a degenerate one, where the pivots'
#: elimination is ill-conditioned and not flagged (yaskawa_hc10 -180 -180 179.9999999 ...)
RETRY_TOL = 1e-3


def _solve_block(data, T, Q_out, ok, last_resort: bool = False):
    """:func:`solve_general_6r_batch` for poses ``T (N, 4, 4)``, into ``Q_out (N, K, 6)``
    and ``ok (N, K)`` (zero on entry); ``last_resort``: with the perturbed models alone."""
    N, K = len(T), Q_out.shape[1]
    finite = reduce_all(np.isfinite(T), axis=(1, 2))
    rows = None if nnz(finite) == N else np.flatnonzero(finite)
    Tr = T if rows is None else T[rows]
    M = len(Tr)
    if M == 0:
        return
    pose, slot, cand, width, resort, degenerate = data.candidates(Tr, last_resort=last_resort)
    Tt = Tr[:, :3] / data.scale                      # rows 0-2, translation scaled
    if resort is None:
        Qp, res, moved = polish_candidates(data.chain, Tt.take(pose, axis=0), cand,
                                           curvature=data.curvature)
    else:                       # the perturbed models' candidates: patient, from both sides
        Qp, res, moved, src = polish_from_both_sides(data.chain, Tt.take(pose, axis=0),
                                                     cand, resort, data.curvature)
        # a pose's candidates in slot order, then its restarts in the order of their sources
        pose = np.concatenate([pose, pose[src]])
        order = np.argsort(pose, kind="stable")
        pose, Qp, res, moved = pose[order], Qp[order], res[order], moved[order]
    acc = res < ACCEPT_TOL
    if not last_resort:
        _retry(data, Tr, rows, pose, res, acc, Q_out, ok)
        lost = np.ones(M, bool)
        lost[pose[acc]] = False
        lost &= ~(ok if rows is None else ok[rows]).any(1)
        if nnz(lost):
            pose, Qp, res, moved, acc = _rescued(data, Tt, lost, degenerate, pose, Qp, res,
                                                 moved, acc | (lost[pose] & (res < SETTLED)))
    pose, Qp = pose[acc], wrap(Qp[acc])
    if not len(pose):                   # no candidate reaches its pose: no solution
        return
    rank = np.arange(len(pose)) - np.searchsorted(pose, pose)     # in slot order
    if width > 16 or nnz(moved):
        # duplicates: a solution within MERGE_TOL of one in an earlier slot of its pose
        # (raw candidates from distinct eigenvalue slots that did not move are farther
        # apart than CLUSTER_TOL unless they are a cluster's)
        S = int(reduce_max(rank)) + 1
        Qd = np.zeros((M, S, 6))
        good = np.zeros((M, S), bool)
        Qd[pose, rank] = Qp
        good[pose, rank] = True
        dup = _duplicates(Qd, good)
        if dup is not None:
            new = ~dup[pose, rank]
            pose, Qp = pose[new], Qp[new]
            rank = np.arange(len(pose)) - np.searchsorted(pose, pose)
    # valid slots first, in slot order, at most K (regular solutions first)
    if len(rank) and reduce_max(rank) >= K:
        first = _first_regular(data.chain, pose, rank, Qp, K)
        pose, rank, Qp = pose[first], rank[first], Qp[first]
        rank = np.arange(len(pose)) - np.searchsorted(pose, pose)
    if rows is not None:
        pose = rows[pose]
    Q_out[pose, rank] = Qp
    ok[pose, rank] = True


def _retry(data, T, rows, pose, res, acc, Q_out, ok):
    """The last resort (:meth:`~.robot._Robot6R.candidates`) for the poses of ``T`` whose
    candidates ``pose (C,)`` all missed (``acc`` False) though one came within
    :data:`RETRY_TOL` (``res``), into their rows of ``Q_out`` and ``ok`` (``rows``: the
    poses' rows there, None for all)."""
    close = np.zeros(len(T), bool)
    close[pose[res < RETRY_TOL]] = True
    if nnz(acc):
        close[pose[acc]] = False
    again = np.flatnonzero(close)
    if not len(again):
        return
    Q2, ok2 = np.zeros((len(again),) + Q_out.shape[1:]), np.zeros((len(again),) + ok.shape[1:],
                                                                 bool)
    _solve_block(data, T[again], Q2, ok2, last_resort=True)
    at = again if rows is None else rows[again]
    Q_out[at], ok[at] = Q2, ok2


def _rescued(data, Tt, lost, degenerate, pose, Qp, res, moved, acc):
    """The candidates of :func:`_solve_block` with those of the ``lost`` poses (``(M,)
    bool``: no candidate reached them to ACCEPT_TOL) rescued. Their candidates in a valley
    (residual below VALLEY) get RESCUE_ITERS more Newton steps and are kept where they reach
    SETTLED. A lost pose with none where every pivot and the last resort ``degenerate``
    gets Newton from STARTS seeded starts instead (a continuum of solutions, or the double
    root of a pose on a fold of the workspace). The lost poses' solutions are thinned to one
    per THIN, those within the joint limits first, then the best. Returns ``(pose, Qp, res,
    moved, acc)``, sorted by pose."""
    valley = lost[pose] & (res < VALLEY)
    if nnz(valley):
        Qp, res = Qp.copy(), res.copy()
        Qp[valley], res[valley], _ = polish_candidates(
            data.chain, Tt.take(pose[valley], axis=0), Qp[valley], iters=RESCUE_ITERS,
            give_up={}, curvature=data.curvature)
        acc = acc | (valley & (res < SETTLED))
    stuck = lost & degenerate
    stuck[pose[acc]] = False
    if nnz(stuck):
        at = np.repeat(np.flatnonzero(stuck), STARTS)
        Q2, res2, moved2 = polish_candidates(
            data.chain, Tt.take(at, axis=0), np.tile(_STARTS, (nnz(stuck), 1)),
            iters=RESCUE_ITERS, give_up={}, curvature=data.curvature)
        keep = ~stuck[pose]
        pose = np.concatenate([pose[keep], at])
        Qp, res = np.concatenate([Qp[keep], Q2]), np.concatenate([res[keep], res2])
        moved = np.concatenate([moved[keep], moved2])
        acc = np.concatenate([acc[keep], res2 < SETTLED])
        order = np.argsort(pose, kind="stable")
        pose, Qp, res, moved, acc = pose[order], Qp[order], res[order], moved[order], acc[order]
    thin = np.flatnonzero(acc & lost[pose])
    if len(thin):
        outside = ~within_limits(data.robot, Qp[thin])
        thin = thin[np.lexsort((res[thin], outside, pose[thin]))]
        acc[thin] = False
        for group in np.split(thin, np.flatnonzero(np.diff(pose[thin])) + 1):
            kept = group[:1]
            for i in group[1:]:
                if np.abs(wrap(Qp[kept] - Qp[i])).max(-1).min() >= THIN:
                    kept = np.append(kept, i)
            acc[kept] = True
    return pose, Qp, res, moved, acc


#: the rescue's starts (rad): the same for every pose, so that a pose's answer does not
#: depend on its batch
_STARTS = np.random.default_rng(6).uniform(-np.pi, np.pi, (STARTS, 6))


def _first_regular(chain, pose, rank, Qp, K):
    """The solutions kept where a pose has more than K: ``(C,) bool`` over the solutions
    ``Qp (C, 6)`` of poses ``pose (C,)`` (sorted, ``rank`` their order within the pose).

    A 6R has at most 16 isolated solutions; more come from a continuum (a self-motion), whose
    points are arbitrary samples with a rank-deficient Jacobian. So the regular solutions
    (:func:`~.polish.regular`, the engine's singular test) come first, then the rest, each
    in slot order; a pose's first K are kept."""
    rows = np.flatnonzero(np.bincount(pose)[pose] > K)
    singular = np.zeros(len(pose), bool)
    singular[rows] = ~regular(chain, Qp[rows])
    order = np.lexsort((rank, singular, pose))
    keep = np.zeros(len(pose), bool)
    keep[order[(np.arange(len(pose)) - np.searchsorted(pose[order], pose[order])) < K]] = True
    return keep


def _duplicates(Qd, good):
    """``(M, S)``: slot i of a pose is within MERGE_TOL (wrapped, every joint) of a good slot
    j < i of it; ``Qd (M, S, 6)`` wrapped to (-pi, pi], ``good (M, S)``; None when there is
    none. The pairs are screened by their first joint (a pose's slots rarely share it)."""
    M, S = good.shape
    d = np.abs(Qd[:, :, None, 0] - Qd[:, None, :, 0])
    pose, i, j = np.nonzero(((d < MERGE_TOL) | (d > 2.0 * np.pi - MERGE_TOL))
                            & _EARLIER[:S, :S] & good[:, None, :])
    if not len(pose):
        return None
    d = np.abs(Qd[pose, i] - Qd[pose, j])
    same = reduce_all((d < MERGE_TOL) | (d > 2.0 * np.pi - MERGE_TOL), axis=1)
    if not nnz(same):
        return None
    dup = np.zeros((M, S), bool)
    dup[pose[same], i[same]] = True
    return dup


# [i, j]: slot j comes before slot i (a pose has at most 240 candidates: 48 of a pivot, 2 x 48
# of the perturbed models, and as many restarts)
_EARLIER = np.tri(16 * BATCH_SLOTS, k=-1, dtype=bool)


def solve_general_6r(robot, T) -> np.ndarray:
    """All real solutions of ``robot.fk(q) == T`` for one pose.

    The valid rows of :func:`solve_general_6r_batch` for the batch ``T[None]`` (same
    accuracy and merging).

    Parameters
    ----------
    robot : Robot
        Six revolute joints.
    T : array_like (4, 4)
        The pose ``T_world_tool`` (SI, world frame).

    Returns
    -------
    ndarray (k, 6)
        Rad, wrapped to (-pi, pi], k <= 16; ``(0, 6)`` for a non-finite or unreachable pose.

    Raises
    ------
    ValueError
        If ``robot`` does not have exactly 6 revolute joints, or ``T`` is not (4, 4).
    """
    Q, ok = solve_general_6r_batch(robot, np.asarray(T, dtype=float)[None])
    return Q[0][ok[0]]


def general_6r(robot, targets, br):
    """The branches of a general 6R robot: the elimination's solutions of every pose.

    The solutions of :func:`solve_general_6r_batch`, ordered by joint 3 then joint 1, one
    slot each, labelled by their rank (``root k`` of joint 3).

    Parameters
    ----------
    robot : Robot
        Six revolute joints.
    targets : Targets
        ``N`` whole poses (world frame, SI).
    br : Branches
        One slot per target (:meth:`Branches.start <kincalc.ik.branches.Branches.start>`).

    Returns
    -------
    Branches
        ``K = BATCH_SLOTS`` slots, every joint set (rad), valid slots first.

    Raises
    ------
    UnsupportedRobot
        ``targets`` are not whole poses.
    ValueError
        If ``robot`` does not have exactly 6 revolute joints.
    """
    if targets.kind != "pose":
        from ...errors import UnsupportedRobot
        raise UnsupportedRobot(f"{robot.name}: a general 6R robot needs a whole pose")
    Q, ok = ranked_solutions(robot, targets.T)
    return br.with_slots(ok, ROOTS, Q, np.cos(Q), np.sin(Q))


def ranked_solutions(robot, T) -> tuple[np.ndarray, np.ndarray]:
    """:func:`solve_general_6r_batch`'s solutions ``(Q (N, BATCH_SLOTS, 6), ok)`` (rad),
    each pose's in the order of their labels (slot k is :data:`ROOTS` [k]).

    Ranked by joint 3, then joints 1, 2, 4, 5, 6, each on a grid of RANK_STEP rad in
    (-pi, pi] (a value within a step of -pi counts as pi): a rank (the label) then does not
    depend on the last bits of the values, which differ between a pose solved alone and in
    a batch (equal joint-3 values at a singular pose, a joint at +-pi)."""
    Q, ok = solve_general_6r_batch(robot, T)
    W = np.where(Q <= RANK_STEP - np.pi, np.pi, Q)          # (Q is wrapped)
    key = np.where(ok[..., None], np.round(W / RANK_STEP), np.inf)
    order = np.lexsort(tuple(key[..., j] for j in (5, 4, 3, 1, 0, 2)), axis=-1)
    at = np.arange(len(Q))[:, None]
    return Q[at, order], ok[at, order]


#: the grid (rad) on which :func:`ranked_solutions` compares joint values to rank them
RANK_STEP = 1e-9

#: the signs of the slots of :func:`general_6r`: slot k is ``root k + 1`` of joint 3
ROOTS = tuple(((2, f"root {k + 1}"),) for k in range(BATCH_SLOTS))
