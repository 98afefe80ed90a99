"""The closed forms of the five-joint arms, for a batch of targets (see
:mod:`kincalc.ik.solvers`, whose table :data:`~kincalc.ik.solvers.SOLVERS` names them): the
arms whose axes 4 and 5 meet on the tool's approach line (``position-approach``, which sets
the position and the approach; ``planar-shoulder`` and ``spherical-shoulder``, whose first
three axes are parallel or meet, for whole poses) and the ``pitch-roll`` arms.

Each solver takes the family's screws ``S`` (world frame at q = 0, SI; see
:mod:`kincalc.ik.screws`), the targets (:class:`~kincalc.ik.target.Targets`) and a
:class:`~kincalc.ik.branches.Branches` with one slot per target, and returns the
branches with every joint solved: candidates, which the engine checks by FK, labels
and flags.
"""

from __future__ import annotations

import numpy as np

from ..spatial import wrap
from ..subproblems import sp1, sp2, sp4
from ..subproblems.cone import cone_constants
from ..subproblems.solutions import Solutions, cross, dot, pair
from ..tolerances import ALONG_PARALLEL
from .branches import Branches
from .pieces import (angle_about, axis_normal, axis_sp4, closing_turn, meeting_point, one_root,
                     rotate, rotate_back, senses_along, target_rotation, tool_point,
                     turn_onto)
from .place import place, plan as placement
from .screws import Screws
from .wrists import band_arcs, free_for_the_wrist, parallel_wrist_q6, spherical_taking, undo


def position_approach(S: Screws, targets, br: Branches) -> Branches:
    """Five joints, axes 4 and 5 meeting at ``c`` on the approach line.

    ``c = p - d a`` is placed by joints 1-3, then joints 4 and 5 turn the approach
    (subproblem 2; its least-squares answer kept, for the reasons of an unreachable
    approach). The roll about the approach follows, except where the approach lies along
    axis 4, and near it: joints 4 and 5 then come from a whole pose's rotation
    (:func:`_wrist_from_the_pose`); so do they with a placing joint the placement leaves
    free (``c`` on its line; :func:`_free_placing_joint`). When axis 3 passes through ``c``
    as well, joints 3-5 are a spherical wrist (:func:`_three_joint_wrist`).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions with approaches ``(N, 3)``, or poses (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    a = targets.approach if targets.kind == "approach" else targets.T[:, :3, 2]
    return _point_then_pair(S, targets, br, S.M[:3, 2], a)


def wrist_pair(S: Screws, targets, br: Branches) -> Branches:
    """Five joints, axes 4 and 5 meeting at a point ``c`` the tool carries, off its approach
    line (a tool offset sideways) or on it with the approach along axis 5; whole poses.

    Joints 1-3 place ``c`` where the pose puts it, then joints 4 and 5 turn a direction the
    tool carries onto the pose's and the roll follows, as :func:`position_approach` does
    with the approach: here the tool's axis at q = 0 farthest from axis 5 (the approach may
    lie along axis 5, which does not turn it).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    col = _across_axis_5(S)
    return _point_then_pair(S, targets, br, S.M[:3, col], targets.T[:, :3, col])


def _across_axis_5(S: Screws) -> int:
    """The tool's axis (a column of its rotation at q = 0) farthest from axis 5: a direction
    joint 5 turns, which a whole pose fixes (the approach may lie along axis 5)."""
    return S.constant("tool axis across axis 5",
                      lambda: int(np.argmin(np.abs(S.M[:3, :3].T @ S.axis[4]))))


def _point_then_pair(S: Screws, targets, br: Branches, a0, a) -> Branches:
    """Joints 1-3 place ``c`` (:func:`_wrist_pair_point`), joints 4 and 5 turn the tool's
    direction ``a0 (3,)`` at q = 0 onto ``a (N, 3)`` (world frame): the approach, or for a
    whole pose any direction the tool carries."""
    T = targets.T
    c0, ct = _wrist_pair_point(S, targets, a)
    br = place(S, br, (0, 1, 2), c0, ct[:, None, :], what="the point where axes 4 and 5 meet")
    if placement(S, (0, 1, 2), tuple(c0)).still:        # axis 3 through the point too
        return _three_joint_wrist(S, targets, br, a)
    if targets.kind != "pose":
        br = _free_for_the_approach(S, br, a)
    v = undo(S, br, (0, 1, 2), np.full(br.ok.shape + (3,), a[:, None, :]))
    wrist = sp2(np.full(v.shape, a0), v, S.axis[3], S.axis[4])
    if targets.kind != "pose":
        return br.branch([3, 4], wrist, least_squares=True)
    br, taken = _free_placing_joint(S, T, br, wrist)
    br = _wrist_from_the_pose(S, T, br, a0, taken)
    return br if taken is None else _shared_line(S, br, taken)


def _free_for_the_approach(S: Screws, br: Branches, a) -> Branches:
    """``br`` with a placing joint the placement left free (the point where axes 4 and 5
    meet on its line) turned so that joints 4 and 5 can point the approach ``a (N, 3)``
    (world frame): where their twist is not a right angle they reach only a band of
    directions (:func:`~kincalc.ik.wrists.free_for_the_wrist`, with the tool's approach at
    q = 0 as the pointed vector: :func:`_approach_cone`)."""
    for j in (0, 1, 2):
        if S.revolute[j] and br.free_in((j,)):
            br = free_for_the_wrist(S, br, 3, _approach_cone(S), a[:, None, :], (0, 1, 2), j)
    return br


def _approach_cone(S: Screws):
    """The directions joints 4 and 5 point the approach ``a0`` into: its cone about axis 5
    measured along axis 4 (:func:`~kincalc.subproblems.cone.cone_constants`)."""
    return S.constant("cone of the approach about axis 5",
                      lambda: cone_constants(S.axis[3], S.M[:3, 2], S.axis[4]))


def _free_placing_joint(S: Screws, T, br: Branches, wrist):
    """``(br, taken)``: joints 4 and 5 set from subproblem 2's roots ``wrist`` (the
    approach), except in the slots ``taken (N, K)`` where the placement left one revolute
    joint ``j`` of joints 1-3 free (the point ``c`` on its line: an arm or shoulder
    singularity; None where no slot has one).

    Any value of ``j`` places ``c``, but ``j`` turns the tool about a line through ``c`` as
    joints 4 and 5 do, and a whole pose fixes it with them: ``R_A R_j R_B R4 R5 = R_t``
    (``A``, ``B`` the placing joints before and after ``j``), so ``R(u, q_j) R4 k5 = W k5``
    with ``u = R_B^T k_j`` and ``W = R_B^T R_A^T R_t`` (subproblem 2: two roots, in place of
    the approach's); joint 5 follows from the rotation (:func:`_wrist_from_the_pose`). At
    ``j``'s representative, joints 4 and 5 reach the approach but the roll about it only by
    chance. ``j`` stays free where subproblem 2 leaves it so (:func:`_shared_line`).

    ``T (N, 4, 4)`` the poses, ``br`` with joints 1-3 set, ``wrist`` subproblem 2's ``(N,
    K, 2)`` roots for joints 4 and 5 (world frame at q = 0, SI)."""
    placing = tuple(j for j in (0, 1, 2) if S.revolute[j])
    if not br.free_in(placing):
        return br.branch([3, 4], wrist, least_squares=True), None
    count = sum(np.asarray(br.free[j], int) for j in placing)
    k4, k5, shape = S.axis[3], S.axis[4], wrist.ok.shape
    Rk5 = np.full(br.ok.shape + (3,), rotate(target_rotation(S, T), k5))      # R_t k5
    # one Solutions for joints 4, 5 and the placing ones: per slot, the approach's roots
    # (the placing joints as they are) or the pose's (joint 5 set afterwards)
    theta, cos, sin = ([x[0], x[1]] for x in (wrist.theta, wrist.c, wrist.s))
    ok, exact, free = wrist.ok, wrist.exact, wrist.free
    undetermined = [free, free]
    taken = np.zeros(br.ok.shape, bool)
    for j in placing:
        one = np.asarray(br.free[j]) & (count == 1)
        x = [np.broadcast_to(r[j][..., None], shape) for r in (br.value, br.cos, br.sin)]
        still = np.zeros(shape, bool)
        if np.count_nonzero(one):
            after = tuple(i for i in placing if i > j)
            u = undo(S, br, after, np.full(br.ok.shape + (3,), S.axis[j]))        # R_B^T k_j
            w = undo(S, br, after, undo(S, br, tuple(i for i in placing if i < j), Rk5))
            sol = sp2(np.full(u.shape, k5), w, u, np.full(u.shape, k4))
            pose = one[..., None]
            x = [np.where(pose, a[0], b) for a, b in zip((sol.theta, sol.c, sol.s), x)]
            theta[0], cos[0], sin[0] = (np.where(pose, a[1], b) for a, b in zip(
                (sol.theta, sol.c, sol.s), (theta[0], cos[0], sin[0])))
            ok, exact, free = (np.where(pose, a, b) for a, b in zip(
                (sol.ok, sol.exact, sol.free), (ok, exact, free)))
            still = pose & sol.free
            undetermined[:2] = np.where(pose, sol.free, undetermined[0]), \
                undetermined[1] & ~pose
            br = br.set(j, br.value[j], free=br.free[j] & ~one)
            taken |= one
        theta.append(x[0])
        cos.append(x[1])
        sin.append(x[2])
        undetermined.append(still)
    br = br.branch([3, 4, *placing], Solutions(tuple(theta), tuple(cos), tuple(sin), ok,
                                               exact, free, tuple(undetermined)),
                   least_squares=True)
    return br, br.take(taken)


def _shared_line(S: Screws, br: Branches, taken) -> Branches:
    """The slots ``taken (N, K)`` of :func:`_free_placing_joint` whose placing joint ``j``
    is still free: its line (direction ``u`` at the slot) is that of joint 4 or of joint 5,
    and only ``q_j + sigma q_i`` is fixed (``i`` that joint, ``sigma = sign(u . k_i)``,
    ``k_i`` its axis at the slot), kept as the slot's continuum
    (:class:`~kincalc.ik.continua.Continuum`: mask, j, i, sigma, total in rad)."""
    placing = tuple(j for j in (0, 1, 2) if S.revolute[j])
    c = np.zeros(br.ok.shape + (5,))
    for j in placing:
        on = taken & br.free[j]
        if not np.count_nonzero(on):
            continue
        u = undo(S, br, tuple(i for i in placing if i > j),
                 np.full(br.ok.shape + (3,), S.axis[j]))
        h4 = dot(u, S.axis[3])
        h5 = dot(u, S.turn(3, br.cos[3], br.sin[3], np.full(u.shape, S.axis[4])))  # R4 k5
        four = np.abs(h4) >= np.abs(h5)
        sigma = np.where(np.where(four, h4, h5) >= 0.0, 1.0, -1.0)
        total = br.value[j] + sigma * np.where(four, br.value[3], br.value[4])
        c = np.where(on[..., None], np.stack([np.ones(on.shape), np.full(on.shape, j),
                                              np.where(four, 3, 4), sigma, total], -1), c)
    return br.with_extra("continuum", c) if np.count_nonzero(c[..., 0]) else br


def _wrist_from_the_pose(S: Screws, T, br: Branches, a0, taken=None) -> Branches:
    """Joints 4 and 5 of a whole pose from its rotation, in the slots where subproblem 2's
    answer is that one or leaves joint 4 free, and in the slots ``taken`` (N, K) of
    :func:`_free_placing_joint` (joint 4 there already the pose's).

    Subproblem 2 sets joints 4 and 5 from the approach alone. Where the approach lies along
    axis 4 (joint 5 at 0 or 180 deg between axes at right angles) joint 4 is free for it, yet
    turns the tool about its approach, a roll the pose fixes; near there subproblem 2's
    roots are good to about 1e-8 rad only, past the FK check. The rotation left for the two
    joints, ``W = (R1 R2 R3)^T R_t = R4 R5``, decomposes well: ``R4 k5 = W k5`` (subproblem
    1 about axis 4), then ``R5 a0 = R4^T W a0`` (subproblem 1 about axis 5; ``a0 (3,)`` the
    tool's direction subproblem 2 turned, at q = 0). A slot takes it
    where subproblem 2 left joint 4 free or found it within 1e-6 rad (elsewhere the slot
    reaches the approach but not the roll: the FK check drops it, and the reason quotes it).

    ``T (N, 4, 4)`` the poses, ``br`` with joints 1-5 set (world frame at q = 0, SI)."""
    k4, k5 = S.axis[3], S.axis[4]
    Rt = target_rotation(S, T)
    W = undo(S, br, (0, 1, 2), np.full(br.ok.shape + (2, 3),                # W k5, W a0
                                        (Rt @ np.stack([k5, a0], -1)).swapaxes(-1, -2)))
    t4, c4, s4 = turn_onto(k4, k5, W[..., 0, :])
    t5, c5, s5 = turn_onto(k5, a0, S.turn(3, c4, s4, W[..., 1, :], back=True))  # onto R4^T W a0
    take = br.free[3] | ((np.abs(wrap(t4 - br.value[3])) < 1e-6)
                         & (np.abs(wrap(t5 - br.value[4])) < 1e-6))
    if taken is not None:                 # a placing joint took the pose with joints 4, 5
        take = take | taken
    pick = lambda new, old: np.where(take, new, old)  # noqa: E731
    br = br.set(3, pick(t4, br.value[3]), pick(c4, br.cos[3]), pick(s4, br.sin[3]),
                free=br.free[3] & ~take)
    return br.set(4, pick(t5, br.value[4]), pick(c5, br.cos[4]), pick(s5, br.sin[4]),
                  free=br.free[4] & ~take)


def _three_joint_wrist(S: Screws, targets, br: Branches, a) -> Branches:
    """Axes 3, 4 and 5 all meet at the wrist point: joints 1 and 2 place it, joint 3 (left free
    by the placement: it does not move the point) is the first joint of a spherical wrist.

    A whole pose: the wrist takes its orientation (:func:`~kincalc.ik.wrists.spherical`). An
    approach ``a (N, 3)`` alone leaves a turn open: joint 3 stays free, at the representative
    that puts ``k4 . R3^T a`` (the approach seen from joint 4) at the middle of the values
    ``k4 . R5 a0`` joint 5 can give, ``(k4 . k5) (k5 . a0)`` (or as near as joint 3 can:
    subproblem 4), where joints 4 and 5 turn ``a0`` onto it (subproblem 2) with the most room.
    Where joint 3's values in that band are two arcs (:func:`~kincalc.ik.wrists.band_arcs`),
    the other root is the second arc's representative (``other arc``).
    """
    if targets.kind == "pose":               # the pose sets joint 3 too: not free for it
        br = br.set(2, br.value[2], br.cos[2], br.sin[2], free=np.zeros(br.ok.shape, bool))
        return spherical_taking(S, br, (2, 3, 4), target_rotation(S, targets.T), before=(0, 1))
    k3, k4, k5, a0 = S.axis[2], S.axis[3], S.axis[4], S.M[:3, 2]
    v = undo(S, br, (0, 1), np.full(br.ok.shape + (3,), a[:, None, :]))
    cone = _approach_cone(S)
    third = sp4(k4, v, k3, cone.C, fixed=axis_sp4(S, 3, 2)).negated()
    # where the band of k4 . R3^T a is two arcs of joint 3, the second root is the middle of
    # the other one (a second representative: a piece of the continuum of its own)
    two = band_arcs(k4, v, k3, cone).two & third.exact[..., 1]
    ok = third.ok & pair(np.ones(two.shape, bool), two)
    br = br.branch([2], Solutions(third.theta, third.c, third.s, ok, third.exact, ok),
                   labels=(None, "other arc"), least_squares=True)
    v = S.turn(2, br.cos[2], br.sin[2], br.take(v), back=True)
    return br.branch([3, 4], sp2(np.full(v.shape, a0), v, k4, k5), least_squares=True)


def _wrist_pair_point(S: Screws, targets, a):
    """``(c0, ct)``: the point where axes 4 and 5 meet, at q = 0 ``(3,)``, and where the
    ``targets`` need it ``(N, 3)`` (world frame, m): where a whole pose puts it (the tool
    carries it), or for an approach ``a (N, 3)`` alone a fixed distance behind the tool point
    along the approach (the point on the approach line)."""
    c0 = meeting_point(S, 3, S.n)
    if targets.kind == "pose":
        return c0, tool_point(S, targets.T, c0)[:, 0]
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    return c0, targets.T[:, :3, 3] - float((p0 - c0) @ a0) * a


def planar_shoulder(S: Screws, targets, br: Branches) -> Branches:
    """Five revolute joints, axes 1-3 parallel (direction ``h``), axes 4 and 5 meeting at a
    point ``c`` the tool carries (on its approach line, or off it, or with the approach along
    axis 5); a whole pose.

    The three parallel joints turn the arm by ``psi = q1 + s2 q2 + s3 q3`` about h (``s_i``
    the sign of axis i along h), so ``R_h(psi) R4 R5 = R_t``. Joint 4 from the height of
    axis 5 along h, ``h . R4 k5 = h . R_t k5`` (subproblem 4); psi turns ``R4 k5`` onto ``R_t
    k5``, joint 5 turns ``a0`` (the tool's axis farthest from axis 5) onto ``R4^T R_h(-psi)
    R_t a0`` (subproblem 1 each). Joints 1 and 2 then place axis 3's point ``o3`` where
    ``c_t - R_h(psi) (c0 - o3)`` needs it, and joint 3 completes psi. Up to 4 solutions.

    Where joint 4 turns axis 5 along h (a singular pose), joints 1, 2, 3 and 5 turn about
    parallel axes and only ``psi + sigma q5`` is fixed: joint 5 takes the representatives of
    :func:`~kincalc.ik.wrists.parallel_wrist_q6` (one per arc of the continuum, the second
    ``other arc``), marked free, with the sum kept as the slot's continuum (``extra["parallel
    continuum"]``: mask, sigma, total in rad), as on a three-parallel arm.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    T = targets.T
    h, k4, k5, o3 = S.axis[0], S.axis[3], S.axis[4], S.point[2]
    a0 = S.M[:3, _across_axis_5(S)]
    c0, ct = _wrist_pair_point(S, targets, T[:, :3, 2])
    Rt = target_rotation(S, T)
    u, at = rotate(Rt, k5), rotate(Rt, a0)                                      # (N, 1, 3)
    br = br.branch([3], sp4(h, k5, k4, dot(u, h), fixed=axis_sp4(S, 0, 3)))
    u, at, ct = br.take(u), br.take(at), br.take(ct[:, None, :])
    k5t = S.turn(3, br.cos[3], br.sin[3], k5)
    psi, cp, sp = turn_onto(h, k5t, u)
    # R4^T R_h(-psi) R_t a0
    z = S.turn(3, br.cos[3], br.sin[3], S.turn(0, cp, sp, at, back=True), back=True)
    br, psi, sigma = _fifth(S, br, Rt, k5t, ct, c0, psi, turn_onto(k5, a0, z))
    br = br.with_extra("psi", psi, *(() if sigma is None else ("sigma", sigma)))
    cp, sp = np.cos(br.extra["psi"]), np.sin(br.extra["psi"])
    br = place(S, br, (0, 1), o3, br.take(ct) - S.turn(0, cp, sp, c0 - o3), what="axis 3")
    return closing_turn(br, (0, 1, 2), senses_along(S, (0, 1, 2)), 4)


def _fifth(S: Screws, br: Branches, Rt, k5t, ct, c0, psi, q5):
    """Joint 5 of a planar-shoulder arm, ``q5 = (theta, c, s)`` each ``(N, K)``, and where axis
    5 lies along h (``k5t (N, K, 3)``, turned by joint 4) the representatives of the
    continuum instead: ``(br, psi, sigma)``, ``2 K`` slots (the second ``other arc``, live
    only there), ``psi (N, 2K)`` the parallel joints' turn (``total - sigma q5`` on the
    continuum), ``sigma (N, 2K)`` +1 where axis 5 points along h (None where no slot is on a
    continuum). ``ct (N, K, 3)``: where the target needs the point ``c`` (``c0`` at q = 0)."""
    h, o1, o3 = S.axis[0], S.point[0], S.point[2]
    off = cross(k5t, h)
    aligned = dot(off, off) < ALONG_PARALLEL ** 2
    N, K = aligned.shape
    arcs, ok_arcs = np.zeros((N, K, 2)), np.zeros((N, K, 2), bool)
    sigma = total = None
    if np.count_nonzero(aligned):
        sigma = np.where(dot(k5t, h) > 0, 1.0, -1.0)
        # R_t = R_h(total) R4 there: the turn about h of R4 e onto R_t e (e normal to k5)
        e = axis_normal(S, 4)
        total = turn_onto(h, S.turn(3, br.cos[3], br.sin[3], e),
                          np.broadcast_to(rotate(Rt, e), k5t.shape))[0]
        perp = lambda x: x - dot(x, h)[..., None] * h  # noqa: E731
        b = perp(S.turn(0, np.cos(total), np.sin(total), np.broadcast_to(o3 - c0, ct.shape)))
        arcs, ok_arcs, _ = parallel_wrist_q6(S, perp(ct - o1), b, sigma, elbow=(0, 1, 2))
    t5 = pair(np.where(aligned, arcs[..., 0], q5[0]), arcs[..., 1])
    ok5 = pair(np.where(aligned, ok_arcs[..., 0], True), aligned & ok_arcs[..., 1])
    br = br.branch([4], Solutions((t5,), (np.cos(t5),), (np.sin(t5),), ok5, ok5,
                                  pair(aligned, aligned)), labels=(None, "other arc"))
    psi = br.take(psi)
    if sigma is None:
        return br, psi, None
    sigma = br.take(sigma)
    psi = np.where(br.free[4], br.take(total) - sigma * br.value[4], psi)
    return br, psi, sigma


def spherical_shoulder(S: Screws, targets, br: Branches) -> Branches:
    """Five revolute joints, axes 1-3 meeting at a point ``O`` (a spherical shoulder), axes 4
    and 5 meeting at a point ``c`` the tool carries; a whole pose.

    The shoulder's rotation ``R123 = R_t (R4 R5)^T`` takes ``c0 - O`` to ``c_t - O``, so
    ``R4 R5 u = c0 - O`` with ``u = R_t^T (c_t - O)`` (subproblem 2), and the shoulder takes
    the rotation left, ``R_t R5^T R4^T`` (a spherical wrist at the base,
    :func:`~kincalc.ik.wrists.spherical`). Up to 4 solutions.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    T = targets.T
    O = meeting_point(S, 0, 3)
    c0, ct = _wrist_pair_point(S, targets, T[:, :3, 2])
    Rt = target_rotation(S, T)
    u = rotate_back(Rt, (ct - O)[:, None, :])                                    # (N, 1, 3)
    p2 = np.full(u.shape, c0 - O)
    # (axis 5 through O: joint 5 free, 4 not, as the subproblem's undetermined masks say)
    br = br.branch([3, 4], sp2(u, p2, S.axis[3], S.axis[4]))
    return spherical_taking(S, br, (0, 1, 2), Rt, after=(3, 4))


def pitch_roll(S: Screws, targets, br: Branches) -> Branches:
    """Five joints, axes 2-4 parallel and joint 5 rolling the tool about its approach.

    Joint 1 from the position (subproblem 4), or from the approach where the tool point is
    on axis 1 (:func:`base_angle`), the pitch sum from the approach (subproblem 1), joints
    2-3 planar, joint 5 from the orientation. For an approach alone joint 5 is open: free,
    labelled ``any``, shown as 0 (the engine moves it to the value nearest 0 within its
    limits). Where joint 1 is still free for a whole pose (the tool point and its approach
    both on axis 1, which is then joint 5's line) only ``q1 + sigma q5`` is fixed: joint 1
    shows 0 and the relation is the slot's continuum (``extra["continuum"]``: mask, 0, 4,
    sigma, total in rad).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions with approaches ``(N, 3)``, or poses (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    T = targets.T
    h = S.axis[1]
    o1 = S.point[0]
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    pt = T[:, None, :3, 3]
    a = (targets.approach if targets.kind == "approach" else T[:, :3, 2])[:, None, :]
    br = br.branch([0], base_angle(S, pt, a))
    a1 = S.turn(0, br.cos[0], br.sin[0], br.take(a), back=True)              # joint 1 undone
    p1 = o1 + S.turn(0, br.cos[0], br.sin[0], br.take(pt) - o1, back=True)
    psi, cps, sps = one_root(sp1(np.full(a1.shape, a0), a1, h))
    # where axis 4's point must go: p1 + R_h(psi) (p4 - p0)
    d = S.point[3] - p0
    ch, sh = cps[..., None], sps[..., None]
    p4t = p1 + ch * d + sh * np.cross(h, d) + (1 - ch) * (d @ h) * h
    br = br.with_extra("psi", psi)
    br = place(S, br, (1, 2), S.point[3], p4t, what="axis 4")
    sgn = [float(np.sign(S.axis[i] @ h)) for i in (1, 2, 3)]
    q4 = (br.extra["psi"] - sgn[0] * br.value[1] - sgn[1] * br.value[2]) * sgn[2]
    br = br.set(3, q4, np.cos(q4), np.sin(q4))
    if targets.kind == "approach":        # the roll was not asked for: open, 0 stands for any
        z = np.zeros_like(q4)
        br = br.set(4, z, np.ones_like(z), z, free=np.ones(z.shape, bool))
        return br.relabel(4, "any")
    Rt = target_rotation(S, T)
    br = br.set(4, *angle_about(S, 4, undo(S, br, (0, 1, 2, 3), np.full(
        br.ok.shape + (3,), rotate(Rt, axis_normal(S, 4))))))
    return _base_and_roll(S, br)


def base_angle(S: Screws, pt, a) -> Solutions:
    """Joint 1 of a pitch-roll arm: ``(N, 1, 2)`` roots (rad).

    Undone, joint 1 must bring the tool point ``pt (N, 1, 3)`` into the plane of the
    pitch joints, ``h . R(k1, -q1)(pt - o1) = h . (p0 - o1)`` (subproblem 4; ``h`` the
    pitch axes, ``k1``, ``o1`` axis 1, ``p0`` the tool point at q = 0, world frame at q =
    0, m). Where ``pt`` is on axis 1 every angle does (a free root), and the approach
    ``a (N, 1, 3)`` (unit) decides instead: the pitch joints turn the approach about
    ``h``, so ``h . R(k1, -q1) a = h . a0`` (two roots, or free again when ``a`` is along
    axis 1). The slot lives where the position's equation holds; an approach out of the
    arm's plane leaves its least-squares angle, for the FK check to judge.
    """
    h, k1, o1 = S.axis[1], S.axis[0], S.point[0]
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    at = sp4(h, pt - o1, k1, h @ (p0 - o1), fixed=axis_sp4(S, 1, 0)).negated()
    on = at.free[..., :1]                                          # pt on axis 1
    if not np.count_nonzero(on):
        return at
    by = sp4(h, a, k1, h @ a0, fixed=axis_sp4(S, 1, 0)).negated()
    pick = lambda x, y: np.where(on, x, y)  # noqa: E731
    return Solutions((pick(by.theta[0], at.theta[0]),), (pick(by.c[0], at.c[0]),),
                     (pick(by.s[0], at.s[0]),), pick(by.ok, at.ok), at.exact,
                     pick(by.free, at.free))


def _base_and_roll(S: Screws, br: Branches) -> Branches:
    """A pitch-roll arm's slots whose joint 1 is still free for a whole pose (the tool
    point and its approach on axis 1, joint 5's line then): the relation ``q1 + sigma q5
    = total`` kept as their continuum (:class:`~kincalc.ik.continua.Continuum`),
    ``sigma = sign(k1 . k5)`` with joint 5's axis ``k5`` at the slot (world frame)."""
    free = br.free[0]
    if not np.count_nonzero(free):
        return br
    k5 = np.full(br.ok.shape + (3,), S.axis[4])
    for j in (3, 2, 1, 0):                                        # R1 R2 R3 R4 k5
        k5 = S.turn(j, br.cos[j], br.sin[j], k5)
    sigma = np.where(k5 @ S.axis[0] >= 0.0, 1.0, -1.0)
    total = br.value[0] + sigma * br.value[4]
    c = np.stack([free.astype(float), np.zeros_like(total), np.full_like(total, 4.0),
                  sigma, total], -1)
    return br.with_extra("continuum", c)
