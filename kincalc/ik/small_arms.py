"""The closed forms of the arms of two to four joints, for a batch of targets (see
:mod:`kincalc.ik.solvers`, whose table :data:`~kincalc.ik.solvers.SOLVERS` names them):
the position families, the planar (three joints, and four with a tilted last joint) and
point-plus-roll arms, and the tool configuration
vector (the five-joint arms are in :mod:`kincalc.ik.five_joints`).

Each solver takes the family's screws ``S`` (world frame at q = 0, SI; see
:mod:`kincalc.ik.screws`), the targets (:class:`~kincalc.ik.target.Targets`) and a
:class:`~kincalc.ik.branches.Branches` with one slot per target, and returns the
branches with every joint solved: candidates, which the engine checks by FK, labels
and flags.
"""

from __future__ import annotations

import numpy as np

from ..spatial import matrix_from_axis_angle, wrap
from ..structure import parallel
from ..tolerances import GEOMETRY_TOL
from ..subproblems import sp2
from ..subproblems.solutions import Solutions, dot
from ..subproblems.sp2 import free_angles
from ..subproblems.turns import nearest_turn, two_turns
from .branches import TIE_BREAK, Branches
from .pieces import (angle_about, axis_normal, closing_turn, rotate, senses_along,
                     target_rotation, tool_point, turn_onto)
from .place import place
from .screws import Screws
from .wrists import undo
from .worked import note_roll, note_tcv


def position_3(S: Screws, targets, br: Branches) -> Branches:
    """Three joints place the tool point.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions ``T[:, :3, 3]`` (m) (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    return place(S, br, (0, 1, 2), S.M[:3, 3], targets.T[:, None, :3, 3], what="the tool")


def position_2(S: Screws, targets, br: Branches) -> Branches:
    """Two joints place the tool point (on the surface they sweep).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions ``T[:, :3, 3]`` (m) (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved (two joints reach a surface: the FK check decides)
    """
    return place(S, br, (0, 1), S.M[:3, 3], targets.T[:, None, :3, 3], what="the tool")


def _last_axis_roll(S: Screws, targets, br: Branches, first) -> Branches:
    """A point of the last axis placed by ``first`` joints, then the last joint's roll
    about its axis from the orientation (subproblem 1)."""
    n = S.n
    T = targets.T
    p0 = S.constant(("last axis point", first[-1]), lambda: _last_axis_point(S, first[-1]))
    br = place(S, br, first, p0, tool_point(S, T, p0), what=f"axis {n}")
    Rt = target_rotation(S, T)
    e = axis_normal(S, n - 1)
    u = undo(S, br, first, np.full(br.ok.shape + (3,), rotate(Rt, e)))
    br = note_roll(S, br, n - 1, e, u)
    return br.set(n - 1, *angle_about(S, n - 1, u))


def _last_axis_point(S: Screws, c: int) -> np.ndarray:
    """The point of the last axis that the joints before it place (world frame at q = 0, m):
    the axis's own point, unless that lies a hair off the axis of the last placing joint ``c``
    (revolute; more than rounding, less than ``NEAR_AXIS`` of the arm's size: a twist or
    offset written to 9 digits). There joint c moves the point on a tiny circle and the
    placement is ill-conditioned (an offset of 1e-9 m found no solution on any pose); a point
    an arm's size along the last axis is placed well, and any point of it will do."""
    n = S.n
    p, k = S.point[n - 1], S.axis[n - 1]
    if not S.revolute[c]:
        return p
    kc = S.axis[c]
    off = p - S.point[c]
    off = off - (off @ kc) * kc                                  # p across axis c
    away = float(np.linalg.norm(off))
    size = max(S.scale, 1e-12)
    if not ROUNDING_AXIS * size < away < NEAR_AXIS * size or \
            np.linalg.norm(np.cross(k, kc)) < NEAR_AXIS:         # (along axis c: no better)
        return p
    return p + size * k


#: a point within this of an axis (of the arm's size) is on it to rounding
ROUNDING_AXIS = 1e-12
#: a point of the last axis within this of the last placing joint's axis (of the arm's size,
#: and not on it) is moved along the last axis (:func:`_last_axis_point`)
NEAR_AXIS = 1e-3


def planar_3(S: Screws, targets, br: Branches) -> Branches:
    """Three parallel revolute axes: a point of axis 3 by joints 1-2, joint 3 from the orientation.

    Joint 3 by subproblem 1.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    return _last_axis_roll(S, targets, br, (0, 1))


def planar_4(S: Screws, targets, br: Branches) -> Branches:
    """Four revolute joints, axes 1-3 parallel (direction ``h``) and axis 4 not: a planar arm
    carrying a tilted joint; whole poses.

    The parallel joints turn the arm by ``psi = q1 + s2 q2 + s3 q3`` about h (``s_i`` the
    sign of axis i along h), so ``R_h(psi) R4 = R_t``: ``psi`` turns axis 4 onto ``R_t k4``
    (subproblem 1 about h), joint 4 turns a normal of its axis onto ``R_h(-psi) R_t e``
    (subproblem 1). A point ``o4`` of axis 4 moves with the tool and only joints 1-3 move
    it, so joints 1 and 2 place axis 3's point ``o3`` at ``T M^-1 o4 - R_h(psi) (o4 - o3)``
    (two elbows), and joint 3 completes the turn.

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
    h, k4, o3, o4 = S.axis[0], S.axis[3], S.point[2], S.point[3]
    Rt = target_rotation(S, T)                                               # (N, 1, 3, 3)
    u = rotate(Rt, k4)                                                       # R_h(psi) k4
    psi, cp, sp = turn_onto(h, np.broadcast_to(k4, u.shape), u)
    t4, c4, s4 = angle_about(S, 3, S.turn(0, cp, sp, rotate(Rt, axis_normal(S, 3)), back=True))
    br = br.set(3, t4, c4, s4).with_extra("psi", psi)
    pt = tool_point(S, T, o4) - S.turn(0, cp, sp, o4 - o3)                   # (N, 1, 3)
    br = place(S, br, (0, 1), o3, pt, what="axis 3")
    return closing_turn(br, (0, 1, 2), senses_along(S, (0, 1, 2)), 3)


def point_plus_roll(S: Screws, targets, br: Branches) -> Branches:
    """A point of the last axis by the joints before it, the last joint from the orientation
    (subproblem 1).

    Four joints: a SCARA, the R-R-P-R spherical arm. Three: an arm whose tool turns about
    its last axis, joints 1-2 placing a point of it on the surface they sweep.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    br = _last_axis_roll(S, targets, br, tuple(range(S.n - 1)))
    return _roll_with_free(S, targets, br)


def _meeting_pairs(S: Screws) -> tuple:
    """The pairs ``(a, b)``, ``a < b``, of revolute joints before the last whose axes meet
    (not parallel): both lines can hold the last axis's point, both joints then free.
    Cached."""
    def meet(a, b) -> bool:
        # the lines' distance |(p_b - p_a) . n| / |n|, n = k_a x k_b: exact however close to
        # parallel the axes are (two wrist axes a hair apart still meet, and subproblem 2
        # solves them)
        n = np.cross(S.axis[a], S.axis[b])
        sine = float(np.linalg.norm(n))
        return sine > GEOMETRY_TOL and abs(float(np.dot(S.point[b] - S.point[a], n))) \
            < GEOMETRY_TOL * max(S.scale, 1.0) * sine

    def make():
        rev = [j for j in range(S.n - 1) if S.revolute[j]]
        return tuple((a, b) for a in rev for b in rev if a < b and meet(a, b))
    return S.constant("meeting pairs before the last joint", make)


def _frame(S: Screws, br: Branches, upto: int):
    """``(R^T (N, K, 3, 3), u (n, N, K, 3))``: the rotation ``R = E_1 ... E_upto`` of
    each slot (its rows are ``R``'s columns) and every joint's axis there, ``u_j = R_1 ...
    R_{j-1} k_j`` (world frame at q = 0)."""
    shape = br.ok.shape
    X = np.broadcast_to(np.eye(3), shape + (3, 3))
    u = []
    for j in range(S.n):
        v = np.broadcast_to(S.axis[j], shape + (3,))
        for i in range(j - 1, -1, -1):
            v = S.turn(i, br.cos[i], br.sin[i], v) if S.revolute[i] else v
        u.append(v)
    for i in range(upto - 1, -1, -1):
        X = S.turn(i, br.cos[i], br.sin[i], X) if S.revolute[i] else X
    return X, np.stack(u)


def _roll_with_free(S: Screws, targets, br: Branches) -> Branches:
    """Joints before the last (``m = n - 1`` of them) left free by the placement (the last
    axis's point on their lines) turned, with the last joint, to the target's orientation;
    turning them keeps that point, so the tool reaches the pose when its rotation does.

    With ``E = R_t R^T`` the rotation still missing (``R`` the slot's ``E_1 ... E_n``), and
    ``u`` the slot's axes: one free joint ``a`` gives ``R(u_a, x) R(u_n, z) = E``
    (:func:`~kincalc.subproblems.turns.two_turns`, no longer free unless ``u_a`` is along
    ``u_n``); two, ``a`` and ``b`` on meeting axes, ``R(u_a, x) R(u_b, y) R(u_n, z) = E``:
    ``(x, y)`` turn ``u_n`` onto ``E u_n`` (subproblem 2, two roots, the second a slot of
    its own) and ``z`` the turn about ``u_n`` left
    (:func:`~kincalc.subproblems.turns.nearest_turn`). Slots with no free joint keep their
    values (the second root of the pair's step is then empty).
    """
    m = S.n - 1
    F = np.stack([br.free[j] for j in range(m)]) & S.revolute[:m, None, None]
    count = F.sum(0)
    pairs = _meeting_pairs(S)
    if not np.count_nonzero(count) and not pairs:
        return br
    N, K = br.ok.shape
    Rt = np.broadcast_to(target_rotation(S, targets.T), (N, K, 3, 3))
    X, u = _frame(S, br, S.n)
    E = Rt @ X                                                      # R_t R^T
    for a in range(m):
        one = F[a] & (count == 1)
        if np.count_nonzero(one):
            x, z = two_turns(u[a], u[m], E)
            keep = np.linalg.norm(np.cross(u[a], u[m]), axis=-1) < 1e-9
            # joint a on the last axis's line: only q_a + sign q_m counts (R(u_a, x) R(u_m, z)
            # = R(u_m, z + sign x)); joint a keeps its representative (the split two_turns
            # made there is rounding noise) and the relation is the slot's continuum
            sign = np.where(dot(u[a], u[m]) > 0, 1.0, -1.0)
            z = np.where(keep, z + sign * x, z)
            x = np.where(keep, 0.0, x)
            v = wrap(br.value[a] + np.where(one, x, 0.0))
            w = wrap(br.value[m] + np.where(one, z, 0.0))
            br = br.set(a, v, np.cos(v), np.sin(v), free=F[a] & ~(one & ~keep))
            br = br.set(m, w, np.cos(w), np.sin(w))
            if np.count_nonzero(one & keep):
                c = np.stack([(one & keep).astype(float), np.full(one.shape, a),
                              np.full(one.shape, m), sign, v + sign * w], -1)
                if "continuum" in br.extra:
                    c = np.where(br.extra["continuum"][..., :1] > 0, br.extra["continuum"], c)
                br = br.with_extra("continuum", c)
    for a, b in pairs:                  # (every pair branches: one layout for any batch)
        br = _free_pair(S, targets, br, a, b)
    return br


def _free_pair(S: Screws, targets, br: Branches, a: int, b: int) -> Branches:
    """The slots whose free joints are exactly ``a`` and ``b`` (meeting axes) and the last
    joint turned to the target's orientation (see :func:`_roll_with_free`): each such slot
    becomes two, one per root of subproblem 2 (the second labelled
    :data:`~kincalc.ik.branches.TIE_BREAK`); the others keep their values (their second slot
    empty). Everything is read from ``br`` as it is now: an earlier pair's branching doubled
    its slots."""
    m = S.n - 1
    F = np.stack([br.free[j] for j in range(m)]) & S.revolute[:m, None, None]
    two = F[a] & F[b] & (F.sum(0) == 2)                              # (N, K)
    X, u = _frame(S, br, S.n)
    E = np.broadcast_to(target_rotation(S, targets.T), X.shape) @ X  # R_t R^T
    sol = sp2(u[m], (E @ u[m][..., None])[..., 0], u[a], u[b])
    x, y = sol.theta[0], sol.theta[1]                                # (N, K, 2)
    Ra = matrix_from_axis_angle(u[a][..., None, :], x)
    Rb = matrix_from_axis_angle(u[b][..., None, :], y)
    rest = (Ra @ Rb).swapaxes(-1, -2) @ E[..., None, :, :]         # (N, K, 2, 3, 3)
    z = nearest_turn(u[m][..., None, :], rest)
    t2 = two[..., None]
    q = tuple(wrap(br.value[j][..., None] + np.where(t2, d, 0.0))
              for j, d in ((a, x), (b, y), (m, z)))
    ok = np.where(t2, sol.ok, np.array([True, False]))
    still = free_angles(two & sol.free.any(-1), u[m], (E @ u[m][..., None])[..., 0], u[a],
                        u[b])                                          # degenerate: free
    for j, f in zip((a, b), still):
        br = br.set(j, br.value[j], free=(br.free[j] & ~two) | f)
    return br.branch([a, b, m], Solutions(q, tuple(np.cos(t) for t in q),
                                          tuple(np.sin(t) for t in q), ok,
                                          np.ones_like(ok), np.zeros_like(ok)),
                     labels=(None, TIE_BREAK))


def takes_tcv(revolute) -> bool:
    """Whether a chain of joints of these types (``revolute (n,)`` bool) takes a tool
    configuration vector target: 3 or 4 joints, the last revolute (the tool roll)."""
    return len(revolute) in (3, 4) and bool(revolute[-1])


def tcv(robot, S: Screws, targets, br: Branches, solve_pose=None) -> Branches:
    """A tool configuration vector ``w = [p; e^(qn/pi) r3]`` for one target.

    Schilling 1990; the FER Zagreb homework. The last joint from ``|w4..w6|``. Where the
    approach and that joint fix the whole orientation (:func:`tcv_pose`), the robot's own
    closed form solves that pose (``solve_pose``); elsewhere the other joints place the tool
    point as the last joint turns it. The approach ``r3`` is checked by the engine. (The
    point depends on the target's roll, so the engine gives this one target at a time.)

    Parameters
    ----------
    robot : Robot
        Its ``name`` goes into the error.
    S : Screws
        The robot's screws (world frame at q = 0, SI); 3 or 4 joints, the last revolute.
    targets : Targets
        One target of kind ``"tcv"``: the position ``T[0, :3, 3]`` (m), the unit
        ``approach (1, 3)`` and ``roll (1,)`` (rad), the last joint's value.
    br : Branches
        One slot.
    solve_pose : callable, optional
        ``solve_pose(targets, br) -> Branches``, the robot's closed form for whole poses;
        None: the tool point is placed.

    Returns
    -------
    Branches
        Every joint solved; the last joint is ``roll`` in every slot.

    Raises
    ------
    TargetMismatch
        The last joint is not revolute, or the robot has other than 3 or 4 joints.
    ValueError
        More than one target.
    """
    from ..errors import TargetMismatch
    n = S.n
    if not takes_tcv(S.revolute):
        raise TargetMismatch(robot.name, "tcv robot")
    if br.N != 1:
        raise ValueError("tcv: one target at a time")
    qn = float(targets.roll[0])
    br = note_tcv(br, n - 1, np.exp(qn / np.pi))
    pose = None if solve_pose is None else tcv_pose(S, targets)
    if pose is not None:
        br = solve_pose(pose, br)
    else:
        p = S.move_point(n - 1, qn, S.M[:3, 3])
        br = place(S, br, tuple(range(n - 1)), p, targets.T[:, None, :3, 3],
                   what="the tool", constant=False)     # (the point turns with the roll)
    q = np.full((br.N, br.K), qn)
    return br.set(n - 1, q, np.cos(q), np.sin(q))


def tcv_pose(S: Screws, targets):
    """The whole pose a tool configuration vector asks for, where the approach and the last
    joint's value fix it, as :class:`~kincalc.ik.target.Targets` of kind ``"pose"``; None
    elsewhere.

    The joints before the last turn the arm about one direction ``h`` at most (their
    revolute axes parallel; slides turn nothing): ``R_t = R_h(psi) R_n(q_n) R_M``, and
    ``psi`` turns ``v = R_n(q_n) z_M`` (the approach the last joint leaves) onto the target's
    approach (subproblem 1 about h; its least-squares angle where the approach is off the
    cone, which the engine's check then refuses). Three parallel axes and a tilted fourth
    (``planar-4``) place the tool point on a curve, not at points: there the approach must
    choose. None where the joints turn about two directions, or ``v`` lies along ``h``
    (every ``psi`` points it alike).
    """
    from .target import Targets
    n = S.n
    turning = [j for j in range(n - 1) if S.revolute[j]]
    h = S.axis[turning[0]] if turning else None
    if not all(parallel(S.axis[j], h) for j in turning[1:]):
        return None
    R = matrix_from_axis_angle(S.axis[n - 1], float(targets.roll[0])) @ S.M[:3, :3]
    if h is not None:
        v = R[:, 2]
        if parallel(v, h):
            return None
        psi = turn_onto(h, v, np.asarray(targets.approach[0], float))[0]
        R = matrix_from_axis_angle(h, float(psi)) @ R
    T = np.array(targets.T[:1], float)
    T[0, :3, :3] = R
    return Targets(T)
