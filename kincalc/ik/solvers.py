"""The closed form of each family, for a batch of targets: short compositions of the
point placement (:mod:`kincalc.ik.place`), the wrists (:mod:`kincalc.ik.wrists`) and
the subproblems, in the manner of IK-Geo's solvers (Elias & Wen 2022).

Each solver takes the family's screws ``S`` (world frame at q = 0, SI; see
:mod:`kincalc.ik.screws`), the targets (:class:`~kincalc.ik.target.Targets`) and a
:class:`~kincalc.ik.branches.Branches` with one slot per target, and returns the
branches with every joint solved: candidates, which the engine checks by FK, labels
and flags. ``R_t = R_T R_M^T`` below is the rotation of the product of exponentials
(``T = E_1 ... E_n M``), and ``E_j^-1`` undoes joint j's motion.
"""

from __future__ import annotations

import numpy as np

from ..subproblems import sp4
from ..subproblems.cone import cone
from ..subproblems.solutions import Solutions, cross, dot, pair
from .branches import Branches
from .families import TARGET_FAMILIES, Family
from .pieces import (angle_about as _angle_about, axis_cone, axis_normal, axis_sp4,
                     back as _back, inverse_home as _minv, meeting_point, rotate as _mv,
                     rotate_back as _mtv, target_rotation, tool_point, turn_onto)
from .place import place
from .screws import Screws
from .target import Targets
from .five_joints import pitch_roll, planar_shoulder, position_approach, spherical_shoulder
from .small_arms import planar_3, point_plus_roll, position_2, position_3, tcv
from .wrists import NEAR_ALIGNED, into_elbow_reach, parallel_wrist_q6, spherical_taking


# --- six joints --------------------------------------------------------------------

def spherical_wrist(S: Screws, targets, br: Branches) -> Branches:
    """Axes 4, 5, 6 meet at the wrist centre: joints 1-3 place it, the wrist turns.

    Joints 1-3 place the wrist centre (:func:`~kincalc.ik.place.place`), then joints 4-6
    take the orientation left for them (:func:`~kincalc.ik.wrists.spherical`).

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
    c0 = meeting_point(S, 3, 6)
    ct = tool_point(S, T, c0)
    br = place(S, br, (0, 1, 2), c0, ct, what="the wrist centre")
    if br.explain:
        br = br.note("wrist centre (target)", br.take(ct.repeat(br.K, 1) if br.K else ct),
                     "length")
    return spherical_taking(S, br, (3, 4, 5), target_rotation(S, T), before=(0, 1, 2))


def three_parallel(S: Screws, targets, br: Branches) -> Branches:
    """Axes 2, 3, 4 parallel (direction h), axes 5 and 6 meet (UR).

    Joint 1 from the height of the wrist point along h (subproblem 4), joint 5 from the
    component of axis 6 along h (the cone form of subproblem 4), joint 6 and the angle of
    joints 2-4 about h (subproblem 1), then joints 2 and 3 place axis 4 (a planar two-link
    arm).

    At the wrist singularity (axis 6 parallel to h, q5 = 0 or 180 deg) only the signed
    sum ``q2 + s3 q3 + s4 q4 + sigma q6`` is fixed: joint 6 takes the representatives of
    :func:`~kincalc.ik.wrists.parallel_wrist_q6` (one per arc of the continuum), marked
    free, with the sum kept as the slot's continuum (``extra["parallel continuum"]``,
    ``(N, K, 3)``: mask, sigma, total in rad).

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
    h, k1, o1 = S.axis[1], S.axis[0], S.point[0]
    c56 = meeting_point(S, 4, 6)
    ct = tool_point(S, T, c56)
    # joint 1: h . R(k1, -q1)(ct - o1) = h . (c56 - o1)
    height = S.constant("height of the wrist point", lambda: h @ (c56 - o1))
    br = br.branch([0], sp4(h, ct - o1, k1, height, fixed=axis_sp4(S, 1, 0)).negated())
    Rt = target_rotation(S, T)
    br, sigma = _parallel_wrist(S, T, br, Rt, 1, (1, 2, 3))
    # joints 2 + 3 + 4 about h: R234 e = R1^T R_t R6^T R5^T e; where joints 2, 3 put
    # axis 4's point: E1^-1 T M^-1 E6^-1 E5^-1 (p4)
    r, p4 = _undo_56(S, br, 1)
    x = np.empty(r.shape[:-1] + (2, 3))                 # both with joint 1 undone: one turn
    x[..., 0, :] = _mv(Rt, r)
    np.subtract(_tool_point_of(S, T, p4), o1, out=x[..., 1, :])
    x = S.turn(0, br.cos[0], -br.sin[0], x)
    psi = _angle_about(S, 1, x[..., 0, :])[0]
    p4 = o1 + x[..., 1, :]
    br = br.with_extra("psi", psi, *_carried(sigma))
    br = place(S, br, (1, 2), S.point[3], p4, what="axis 4")
    s3, s4 = S.constant("axes 3, 4 along h", lambda: tuple(
        1.0 if float(S.axis[i] @ h) > 0 else -1.0 for i in (2, 3)))
    q4 = s4 * (br.extra["psi"] - br.value[1] - s3 * br.value[2])
    br = br.set(3, q4, np.cos(q4), np.sin(q4))
    if np.count_nonzero(br.free[5]):
        sigma = br.extra["sigma"]
        total = br.value[1] + s3 * br.value[2] + s4 * q4 + sigma * br.value[5]
        br = br.with_extra("parallel continuum", np.stack(
            [br.free[5].astype(float), sigma, total], -1))
    return br


def _parallel_wrist(S: Screws, T, br: Branches, Rt, hj: int, elbow):
    """Joints 5 and 6 of an arm whose axes ``elbow`` (the revolute joints turning about the
    direction ``h`` before joint 5, the last of them joint 4) are parallel and whose axes 5
    and 6 meet: the three-parallel and parallel-four-wrist families.

    Joint 5 puts axis 6 at its angle to h, ``h . R5 k6 = h . v`` with ``v = R_t k6`` (the
    cone form of subproblem 4); joint 6 turns ``R_t^T h`` onto ``R5^T h`` (subproblem 1 on
    the vectors projected across axis 6: both are small near the singularity). On a
    three-parallel arm joint 1 turns about another axis and is undone first (``R_t`` read
    as ``R1^T R_t``). At the wrist singularity (axis 6 along h) joint 6 takes the
    representatives of :func:`~kincalc.ik.wrists.parallel_wrist_q6`, one slot per arc of
    the continuum (the second labelled ``other arc``), marked free.

    ``T (N, 4, 4)`` the targets, ``br`` with the joints before joint 5 not about h solved,
    ``Rt (N, 1, 3, 3)`` R_t of each pose, ``hj`` the joint whose axis is h (world frame at
    q = 0, SI).
    Returns ``(br, sigma)``: joints 5 and 6 set, ``sigma (N, K')`` +1 where axis 6 points
    along h, else -1, needed only at the singularity: None where no slot is there.
    """
    h, k5, k6 = S.axis[hj], S.axis[4], S.axis[5]
    first = elbow[0] == 1                              # joint 1 turns about another axis
    v = np.full(br.ok.shape + (3,), _mv(Rt, k6))          # R_t k6 at every slot
    if first:
        v = S.turn(0, br.cos[0], -br.sin[0], v)
    fifth = cone(h, k6, k5, v, fixed=axis_cone(S, hj, 4, 5))
    # at the singularity joint 6 is the free one: joint 5's roots go in as not free, and
    # where axis 6 is along h (the same in both roots) is carried to the new slots
    br = br.branch([4], fifth, free=False)
    aligned = br.take(fifth.free[..., 0])
    sigma = _sense(br, v, h) if np.count_nonzero(aligned) else None
    a = _mtv(Rt, S.turn(0, br.cos[0], br.sin[0], h) if first else np.full(
        br.ok.shape + (3,), h))
    b = S.turn(4, br.cos[4], -br.sin[4], h)
    t6 = _near_singular_q6(S, br, T, hj, v, aligned, b, turn_onto(k6, a, b)[0], elbow)
    arcs, ok_arcs = _singular_q6(S, br, T, sigma, aligned, elbow)
    q6 = pair(np.where(aligned, arcs[..., 0], t6), arcs[..., 1])
    ok6 = pair(np.where(aligned, ok_arcs[..., 0], True), aligned & ok_arcs[..., 1])
    br = br.branch([5], Solutions((q6,), (np.cos(q6),), (np.sin(q6),), ok6, ok6,
                                  pair(aligned, aligned)), labels=(None, "other arc"))
    return br, None if sigma is None else br.take(sigma)


def _sense(br: Branches, v, h) -> np.ndarray:
    """``sigma (N, K')``: +1 where axis 6 points along h, else -1, at the slots of ``br``
    (``v (N, K, 3)``: axis 6's direction in the slots before joint 5 branched them)."""
    return np.where(dot(br.take(v), h) > 0, 1.0, -1.0)


def _carried(sigma) -> tuple:
    """The extras that carry ``sigma`` of :func:`_parallel_wrist` through the placement of
    axis 4: none where no slot is at the wrist singularity (``sigma`` None)."""
    return () if sigma is None else ("sigma", sigma)


def _undo_56(S: Screws, br: Branches, j: int):
    """``(R6^T R5^T e, E6^-1 E5^-1 o4)``, each ``(N, K, 3)``: ``e = axis_normal(S, j)`` (axis
    ``j`` along h) and axis 4's point ``o4`` with joints 5 and 6 of a parallel wrist undone.
    Joint 5 turns both fixed vectors in one call (:meth:`Screws.turn_fixed`), joint 6 both
    results in another."""
    o5, o6 = S.point[4], S.point[5]
    five = S.turn_fixed(4, br.cos[4], -br.sin[4], ("normal of axis, o4 - o5", j),
                        lambda: (axis_normal(S, j), S.point[3] - o5))
    x = np.empty(five.shape)
    x[..., 0, :] = five[..., 0, :]
    np.add(o5, five[..., 1, :], out=x[..., 1, :])
    x[..., 1, :] -= o6
    x = S.turn(5, br.cos[5], -br.sin[5], x)
    return x[..., 0, :], o6 + x[..., 1, :]


def _tool_point_of(S: Screws, T, x) -> np.ndarray:
    """``T M^-1 x`` for points ``x (N, K, 3)`` (world frame at q = 0 -> at the poses)."""
    Minv = _minv(S)
    local = x @ Minv[:3, :3].T + Minv[:3, 3]
    return (T[:, None, :3, :3] @ local[..., None])[..., 0] + T[:, None, :3, 3]


def _singular_q6(S: Screws, br: Branches, T, sigma, aligned, elbow=(1, 2, 3)):
    """Joint 6's representatives at the wrist singularity, two arcs per slot:
    ``(q6 (N, K, 2), ok (N, K, 2))`` (:func:`~kincalc.ik.wrists.parallel_wrist_q6`, its
    ``elbow``: a three-parallel arm's joints 2-4, with joint 1 undone; an offset-wrist arm's
    two revolute joints of 1-3 and joint 4, where a prismatic joint along h moves nothing
    across h)."""
    N, K = aligned.shape
    if not np.count_nonzero(aligned):
        return np.zeros((N, K, 2)), np.zeros((N, K, 2), bool)
    q6, ok, _ = parallel_wrist_q6(S, *_elbow_vectors(S, br, T, elbow), sigma, elbow=elbow)
    return q6, ok


_COS_NEAR = float(np.cos(NEAR_ALIGNED))


def _near_singular_q6(S: Screws, br: Branches, T, hj: int, v, aligned, b, q6, elbow):
    """Joint 6's angle ``q6 (N, K)`` read from the orientation, moved into the elbow's reach
    where axis 6 is within :data:`NEAR_ALIGNED` of h but not aligned
    (:func:`~kincalc.ik.wrists.into_elbow_reach`; the candidate's small miss is polished
    by the engine). ``v``, ``aligned`` and ``b = R5^T h`` (``(N, K, 3)``) of
    :func:`_parallel_wrist`."""
    near = np.abs(dot(b, S.axis[5])) >= _COS_NEAR
    if not np.count_nonzero(near):
        return q6
    across = cross(b, S.axis[5])
    sine = np.sqrt(dot(across, across))     # (1 - cos^2 loses a sine below ~1e-8)
    near &= ~aligned
    sigma = _sense(br, v, S.axis[hj])
    a, b, at = _elbow_vectors(S, br, T, elbow, q6)
    moved = into_elbow_reach(S, a, b, sigma, q6, at, sine, elbow=elbow)
    return np.where(near, moved, q6)


def _elbow_vectors(S: Screws, br: Branches, T, elbow, q6=None):
    """``(a, b)`` of :func:`~kincalc.ik.wrists.parallel_wrist_q6`, each ``(N, K, 3)``: from
    the elbow's first axis to axis 6, and from axis 6 to axis 4 at ``q6 = 0`` (joint 5 at
    its value), across h, with joint 1 undone when it is not the elbow's (about another
    axis, or sliding along h). Given ``q6 (N, K)`` (rad), also ``at``: from the elbow's first
    axis to axis 4 with joint 6 at ``q6``, across h (exactly: axis 6 need not be along h)."""
    N, K = br.ok.shape
    h, o6 = S.axis[elbow[0]], S.point[5]
    undo1 = (lambda x: _back(S, br, 0, x)) if elbow[0] == 1 else (lambda x: x)
    perp = lambda x: x - dot(x, h)[..., None] * h  # noqa: E731
    W = undo1(np.full((N, K, 3), tool_point(S, T, o6)))
    o4 = _back(S, br, 4, np.full((N, K, 3), S.point[3]))           # E5^-1 o4
    ab = perp(W - S.point[elbow[0]]), perp(undo1(_tool_point_of(S, T, o4)) - W)
    if q6 is None:
        return ab
    o4 = o6 + S.turn(5, np.cos(q6), -np.sin(q6), o4 - o6)           # E6^-1 E5^-1 o4
    return ab + (perp(undo1(_tool_point_of(S, T, o4)) - S.point[elbow[0]]),)


def parallel_four_wrist(S: Screws, targets, br: Branches) -> Branches:
    """Joints 1-4 about or along one direction h, axes 5 and 6 meet (offset wrist).

    Three revolute joints and one prismatic (the textbook's offset-wrist arm): rotations
    about parallel axes add up, so joint 5 comes from the component of axis 6 along h
    (the cone form of subproblem 4), joint 6 and the sum of the revolute angles about h
    from subproblem 1; joints 1-3 then place axis 4's point, and joint 4 closes the sum.

    At the wrist singularity (axis 6 parallel to h) only the signed sum of the revolute
    angles about h and ``sigma q6`` is fixed, as for a three-parallel arm: joint 6 takes
    the representatives of :func:`~kincalc.ik.wrists.parallel_wrist_q6` (the elbow of the
    two revolute joints among 1-3), marked free, with the sum kept as the slot's
    continuum (``extra["parallel continuum"]``: mask, sigma, total in rad).

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
    h = S.axis[3]
    elbow = tuple(i for i in range(3) if S.revolute[i]) + (3,)
    Rt = target_rotation(S, T)
    br, sigma = _parallel_wrist(S, T, br, Rt, 3, elbow)
    r, p4 = _undo_56(S, br, 3)
    psi = _angle_about(S, 3, _mv(Rt, r))[0]
    p4 = _tool_point_of(S, T, p4)
    br = br.with_extra("psi", psi, *_carried(sigma))
    br = place(S, br, (0, 1, 2), S.point[3], p4, what="axis 4")
    sign = [float(np.sign(S.axis[i] @ h)) for i in range(4)]
    partial = sum(sign[i] * br.value[i] for i in range(3) if S.revolute[i])
    q4 = (br.extra["psi"] - partial) * sign[3]
    br = br.set(3, q4, np.cos(q4), np.sin(q4))
    if np.count_nonzero(br.free[5]):
        total = br.extra["psi"] + br.extra["sigma"] * br.value[5]
        br = br.with_extra("parallel continuum", np.stack(
            [br.free[5].astype(float), br.extra["sigma"], total], -1))
    return br


def _swivel(robot, S, targets, br):
    from .swivel import swivel
    return swivel(robot, S, targets, br)


#: the solvers of target kinds that bring their own (``engine.TARGET_FAMILIES``)
TARGET_SOLVERS = {"tcv": tcv, "swivel": _swivel}

SOLVERS = {
    "spherical-wrist": spherical_wrist,
    "three-parallel": three_parallel,
    "parallel-four-wrist": parallel_four_wrist,
    "position-3": position_3,
    "position-2": position_2,
    "planar-3": planar_3,
    "point-plus-roll": point_plus_roll,
    "position-approach": position_approach,
    "pitch-roll": pitch_roll,
    "planar-shoulder": planar_shoulder,
    "spherical-shoulder": spherical_shoulder,
}


def run_solver(robot, S, family: Family, targets: Targets, br: Branches) -> Branches:
    """The candidates of ``family``'s solver for ``targets``: step 1 of the module docstring,
    before the free joints are oriented and the open ones valued.

    Parameters
    ----------
    robot : Robot
    S : Screws, the robot's (:func:`~kincalc.ik.families.plan`)
    family : Family, the robot's, or the target kind's (``TARGET_FAMILIES``)
    targets : Targets, ``N`` targets of a kind the family takes (world frame, SI)
    br : Branches, :meth:`Branches.start` of the N targets

    Returns
    -------
    Branches, the solver's slots (a reversed chain's in the robot's joint order)
    """
    if targets.kind in TARGET_FAMILIES:
        return TARGET_SOLVERS[targets.kind](robot, S, targets, br)
    if family.name == "general-6r":
        from .general6r import general_6r
        return general_6r(robot, targets, br)
    if family.reverse:
        br = SOLVERS[family.solver](S.constant("reversed", S.reversed), targets.inverted(), br)
        return br.flushed().reversed_chain()
    return SOLVERS[family.solver](S, targets, br)
