"""The families whose axes 2-4 (or the revolute ones of 1-4) are parallel, and their
wrist pair: joints 5 and 6 from the components along the common direction h, the angle sum
about h, a planar elbow placing axis 4 (three-parallel: UR; three-parallel-offset, axes 5
and 6 skew: IK-Geo's three-parallel case; parallel-four-wrist: an offset-wrist SCARA type).

Each solver has the signature of :mod:`kincalc.ik.solvers` (the family's screws ``S``, world
frame at q = 0, SI; the targets; the branches) and returns the branches with every joint
solved. ``R_t = R_T R_M^T`` is the rotation of the product of exponentials (``T = E_1 ...
E_n M``), and ``E_j^-1`` undoes joint j's motion. At the wrist singularity (axis 6 along h)
only the signed sum of the angles about h is fixed: joint 6 takes representatives, marked
free, and the sum is kept as the slot's continuum (``extra["parallel continuum"]``).
"""

from __future__ import annotations

import numpy as np

from ..subproblems import sp4, sp6
from ..subproblems.cone import ALIGNED_TOL, cone
from ..subproblems.solutions import Solutions, cross, dot, pair
from ..tolerances import SHARPEN_NEAR_PARALLEL, SNAP_PARALLEL
from .branches import Branches
from .pieces import (angle_about, axis_cone, axis_normal, axis_sp4, back, closing_turn,
                     inverse_home, meeting_point, rotate, rotate_back, senses_along,
                     target_rotation, tool_point, turn_onto)
from .place import place
from .screws import Screws
from .worked import note_direction, note_equation
from .wrists import NEAR_ALIGNED, free_for_the_wrist, into_elbow_reach, parallel_wrist_q6


def three_parallel(S: Screws, targets, br: Branches) -> Branches:
    """Axes 2, 3, 4 parallel (direction h), axes 5 and 6 meet (UR).

    Joint 1 from the height of the wrist point along h (subproblem 4), joint 5 from the
    component of axis 6 along h (the cone form of subproblem 4), joint 6 and the angle of
    joints 2-4 about h (subproblem 1), then joints 2 and 3 place axis 4 (a planar two-link
    arm).

    At the wrist singularity (axis 6 parallel to h, q5 = 0 or 180 deg) only the signed
    sum ``q2 + s3 q3 + s4 q4 + sigma q6`` is fixed: joint 6 takes the representatives of
    :func:`~kincalc.ik.wrists.parallel_wrist_q6` (one per arc of the continuum), marked
    free, with the sum kept as the slot's continuum (``extra["parallel continuum"]``:
    :func:`~kincalc.ik.pieces.closing_turn`).

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
    if br.explain:          # h . R(k, -x) p = cos x (h.p - (h.k)(k.p)) - sin x h.(k x p) + ...
        p, hk = ct - o1, h @ k1
        br = note_equation(br, 0, "height", 1, dot(p, h) - hk * dot(p, k1),
                           -dot(cross(k1, p), h), hk * dot(p, k1), height)
    br = br.branch([0], sp4(h, ct - o1, k1, height, fixed=axis_sp4(S, 1, 0)).negated())
    Rt = target_rotation(S, T)
    br, sigma = _parallel_wrist(S, T, br, Rt, 1, (1, 2, 3))
    return _elbow_about_h(S, T, br, Rt, sigma)


def three_parallel_offset(S: Screws, targets, br: Branches) -> Branches:
    """Axes 2, 3, 4 parallel (direction h), axes 5 and 6 skew (IK-Geo's ``IK_3_parallel``).

    Joints 2-4 turn about h, so neither the height along h of a point of axis 6 nor the
    component of axis 6 along h depends on them: each is a joint-1 term plus a joint-5
    term, and the two equations give joints 1 and 5 together (subproblem 6, up to four
    roots; :func:`_joints_1_5`). Joint 6, joints 2 and 3 (placing axis 4) and joint 4 then
    follow as on a UR arm (:func:`three_parallel`), with the same continuum at the wrist
    singularity (axis 6 along h).

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
    Rt = target_rotation(S, T)
    br, v, aligned = _joints_1_5(S, T, Rt, br)
    br, sigma = _sixth(S, T, br, Rt, 1, (1, 2, 3), v, aligned)
    return _elbow_about_h(S, T, br, Rt, sigma)


def _elbow_about_h(S: Screws, T, br: Branches, Rt, sigma) -> Branches:
    """The last step of a three-parallel arm, joints 1, 5 and 6 set: the angle of joints 2-4
    about h (subproblem 1), joints 2 and 3 placing axis 4, joint 4 closing the sum; the sum
    kept as the continuum where joint 6 is free (see :func:`three_parallel`)."""
    o1 = S.point[0]
    # joints 2 + 3 + 4 about h: R234 e = R1^T R_t R6^T R5^T e; where joints 2, 3 put
    # axis 4's point: E1^-1 T M^-1 E6^-1 E5^-1 (p4)
    r, p4 = _undo_56(S, br, 1)
    x = np.empty(r.shape[:-1] + (2, 3))                 # both with joint 1 undone: one turn
    x[..., 0, :] = rotate(Rt, r)
    np.subtract(_tool_point_of(S, T, p4), o1, out=x[..., 1, :])
    x = S.turn(0, br.cos[0], br.sin[0], x, back=True)
    psi = angle_about(S, 1, x[..., 0, :])[0]
    p4 = o1 + x[..., 1, :]
    br = br.with_extra("psi", psi, *_carried(sigma))
    br = place(S, br, (1, 2), S.point[3], p4, what="axis 4")
    return closing_turn(br, (1, 2, 3), senses_along(S, (1, 2, 3)), 5)



def _joints_1_5(S: Screws, T, Rt, br: Branches):
    """Joints 1 and 5 of a three-parallel-offset arm: ``(br, v, aligned)``.

    With ``o6`` on axis 6, ``W = T M^-1 o6``, and joints 2-4 about h changing no component
    along h (subproblem 6, ``theta1 = q1`` about ``-k1``, ``theta2 = q5``)::

        h . R(-k1, q1)(W - o1)    + h . R(k5, q5)(o5 - o6) = h . (o5 - o1)
        h . R(-k1, q1)(R_t k6)    + h . R(k5, q5)(-k6)     = 0

    At the wrist singularity (axis 6 along h) the second equation's roots touch and come
    out to about 1e-8 rad: a root within :data:`~kincalc.tolerances.SNAP_PARALLEL` of it is
    put on it (joint 5 where axis 6 is along +-h, joint 1 turning ``R_t k6`` onto that line,
    subproblem 1) where that aligns axis 6 to :data:`~kincalc.subproblems.cone.ALIGNED_TOL`.
    Returns the branches with joints 1 and 5 set, ``v (N, K, 3)`` axis 6's direction ``R1^T
    R_t k6`` at their slots and ``aligned (N, K)`` where it is along h (joint 6 then
    free)."""
    h, k1, k5, k6 = S.axis[1], S.axis[0], S.axis[4], S.axis[5]
    o1, o5, o6 = S.point[0], S.point[4], S.point[5]
    N = len(T)
    p = np.empty((N, 1, 4, 3))
    p[:, :, 0] = tool_point(S, T, o6) - o1
    p[:, :, 1] = o5 - o6
    p[:, :, 2] = rotate(Rt, k6)
    p[:, :, 3] = -k6
    k = S.constant("axes of the joint 1, 5 equations", lambda: np.array([-k1, k5, -k1, k5]))
    d1 = S.constant("height of axis 5's point", lambda: float(h @ (o5 - o1)))
    # every distinct root: next to the singularity two roots a hair apart are two solutions
    br = br.branch([0, 4], sp6(h, k, p, d1, 0.0, merge=0.0))
    target6 = br.take(p[:, :, 2])                                      # R_t k6
    along = _aligning_q5(S)
    if along is None:                   # axis 6 is never along h
        return br, S.turn(0, br.cos[0], br.sin[0], target6, back=True), np.zeros(br.ok.shape, bool)
    br = _sharpen_1_5(S, br, br.take(p[:, :, 0]), o5 - o6, target6, d1)
    v = S.turn(0, br.cos[0], br.sin[0], target6, back=True)                      # R1^T R_t k6
    axis6 = S.turn(4, br.cos[4], br.sin[4], k6)                      # R5 k6
    near = _across(axis6, h) <= SNAP_PARALLEL ** 2
    if not np.count_nonzero(near):
        return br, v, np.zeros(br.ok.shape, bool)
    up = dot(axis6, h) > 0
    q5 = np.where(up, along[0], along[1])            # NaN: no angle puts it on that side
    near &= ~np.isnan(q5)
    q1, c1, s1 = turn_onto(-k1, target6, np.where(up[..., None], h, -h))
    snapped = S.turn(0, c1, s1, target6, back=True)
    aligned = near & (_across(snapped, h) <= ALIGNED_TOL ** 2)
    if np.count_nonzero(aligned):
        pick = lambda x, y: np.where(aligned, x, y)  # noqa: E731
        br = br.set(0, pick(q1, br.value[0]), pick(c1, br.cos[0]), pick(s1, br.sin[0]))
        br = br.set(4, pick(q5, br.value[4]), np.cos(pick(q5, br.value[4])),
                    np.sin(pick(q5, br.value[4])))
        v = np.where(aligned[..., None], snapped, v)
    return br, v, aligned


def _sharpen_1_5(S: Screws, br: Branches, w, b, r, d1: float, steps: int = 3) -> Branches:
    """Joints 1 and 5 of :func:`_joints_1_5` where axis 6 is within
    :data:`~kincalc.tolerances.SHARPEN_NEAR_PARALLEL` (a sine) of h,
    by Newton's method on the first equation and the second written with sines,
    ``|u x h| = |R5 k6 x h|`` (``u = R(-k1, q1) R_t k6``): next to the singularity the
    cosines ``h . u`` are within ``s^2 / 2`` of +-1 and rounding hides their difference,
    which subproblem 6 then finds to rounding over ``s``; the sines keep it. A step is kept
    where it lowers the larger residual (the first over the arm's size).

    ``w (N, K, 3)``: ``W - o1``; ``b (3,)``: ``o5 - o6``; ``r (N, K, 3)``: ``R_t k6``; ``d1``:
    the first equation's right side (m)."""
    h, k1, k5, k6 = S.axis[1], S.axis[0], S.axis[4], S.axis[5]
    sine = np.sqrt(_across(S.turn(4, br.cos[4], br.sin[4], k6), h))
    near = sine < SHARPEN_NEAR_PARALLEL
    if not np.count_nonzero(near):
        return br
    L = max(S.scale, 1e-12)

    def residual(c1, s1, c5, s5):
        # R(-k1, q1) w, r
        a, u = S.turn(0, c1, s1, w, back=True), S.turn(0, c1, s1, r, back=True)
        fifth, z = S.turn(4, c5, s5, b), S.turn(4, c5, s5, k6)          # R5 b, R5 k6
        ux, zx = cross(u, h), cross(z, h)
        su, sz = np.sqrt(dot(ux, ux)), np.sqrt(dot(zx, zx))
        f = (dot(a, h) + dot(fifth, h) - d1, su - sz)
        return f, (a, u, fifth, z, ux, zx, su, sz)

    q1, q5 = br.value[0], br.value[4]
    f, parts = residual(br.cos[0], br.sin[0], br.cos[4], br.sin[4])
    size = np.maximum(np.abs(f[0]) / L, np.abs(f[1]))
    for _ in range(steps):
        a, u, fifth, z, ux, zx, su, sz = parts
        # d/dq1 R(-k1, q1) x = -k1 x (R x); d/dq5 R5 x = k5 x (R5 x)
        j11, j15 = -dot(cross(k1, a), h), dot(cross(k5, fifth), h)
        j21 = -dot(ux, cross(cross(k1, u), h)) / np.maximum(su, 1e-300)
        j25 = -dot(zx, cross(cross(k5, z), h)) / np.maximum(sz, 1e-300)
        det = j11 * j25 - j15 * j21
        det = np.where(det != 0.0, det, 1.0)
        n1 = q1 - (f[0] * j25 - j15 * f[1]) / det
        n5 = q5 - (j11 * f[1] - j21 * f[0]) / det
        g, moved = residual(np.cos(n1), np.sin(n1), np.cos(n5), np.sin(n5))
        better = near & (np.maximum(np.abs(g[0]) / L, np.abs(g[1])) < size)
        if not np.count_nonzero(better):
            break
        q1, q5 = np.where(better, n1, q1), np.where(better, n5, q5)
        size = np.where(better, np.maximum(np.abs(g[0]) / L, np.abs(g[1])), size)
        f = tuple(np.where(better, x, y) for x, y in zip(g, f))
        parts = tuple(np.where(better[..., None] if x.ndim > better.ndim else better, x, y)
                      for x, y in zip(moved, parts))
    return br.set(0, q1, np.cos(q1), np.sin(q1)).set(4, q5, np.cos(q5), np.sin(q5))


def _across(x, h) -> np.ndarray:
    """``|x x h|^2 (...)``: the squared sine of ``x (..., 3)`` (unit) from the line of h."""
    xh = cross(x, h)
    return dot(xh, xh)


def _aligning_q5(S: Screws):
    """Joint 5's angles that put axis 6 along +h and along -h (rad, a pair, NaN for a side
    no angle reaches), or None when neither is reached (the cone of axis 6 about axis 5
    misses the line of h); once per screws."""
    def make():
        h, k5, k6 = S.axis[1], S.axis[4], S.axis[5]
        sol = cone(h, k6, k5, np.array([h, -h]))
        if not sol.free[:, 0].any():
            return None
        return tuple(np.where(sol.free[:, 0], sol.theta[0][:, 0], np.nan).tolist())
    return S.constant("joint 5 aligning axis 6 with h", make)


def _parallel_wrist(S: Screws, T, br: Branches, Rt, hj: int, elbow):
    """Joints 5 and 6 of an arm whose axes ``elbow`` (the revolute joints turning about the
    direction ``h`` before joint 5, the last of them joint 4) are parallel and whose axes 5
    and 6 meet: the three-parallel and parallel-four-wrist families.

    Joint 5 puts axis 6 at its angle to h, ``h . R5 k6 = h . v`` with ``v = R_t k6`` (the
    cone form of subproblem 4); joint 6 follows (:func:`_sixth`). On a three-parallel arm
    joint 1 turns about another axis and is undone first (``R_t`` read as ``R1^T R_t``).

    ``T (N, 4, 4)`` the targets, ``br`` with the joints before joint 5 not about h solved,
    ``Rt (N, 1, 3, 3)`` R_t of each pose, ``hj`` the joint whose axis is h (world frame at
    q = 0, SI). Returns ``(br, sigma)`` of :func:`_sixth`.
    """
    h, k5, k6 = S.axis[hj], S.axis[4], S.axis[5]
    if elbow[0] == 1 and np.count_nonzero(br.free[0]):    # (rare: the wrist point on axis 1)
        # joints h, 5, 6 point axis 6 only within a band about h where twists are not right
        # angles: the free joint 1 turned into it (as a spherical wrist's free placing joint)
        br = free_for_the_wrist(S, br, hj, axis_cone(S, hj, 4, 5), rotate(Rt, k6), (0,), 0)
    v = np.full(br.ok.shape + (3,), rotate(Rt, k6))          # R_t k6 at every slot
    if elbow[0] == 1:
        v = S.turn(0, br.cos[0], br.sin[0], v, back=True)
    fifth = cone(h, k6, k5, v, fixed=axis_cone(S, hj, 4, 5))
    if br.explain:          # h . R(k5, x) k6 = cos x (h.k6 - (h.k5)(k5.k6)) + sin x h.(k5 x k6)
        hk, kk = h @ k5, k5 @ k6                                  # + (h.k5)(k5.k6)
        br = note_equation(br, 4, "direction", hj, h @ k6 - hk * kk, h @ np.cross(k5, k6),
                           hk * kk, dot(v, h))
    # at the singularity joint 6 is the free one: joint 5's roots go in as not free, and
    # where axis 6 is along h (the same in both roots) is carried to the new slots
    br = br.branch([4], fifth, free=False)
    return _sixth(S, T, br, Rt, hj, elbow, br.take(v), br.take(fifth.free[..., 0]))


def _sixth(S: Screws, T, br: Branches, Rt, hj: int, elbow, v, aligned):
    """Joint 6 of a parallel wrist (:func:`_parallel_wrist`, :func:`_joints_1_5`), the joints
    before it not about h solved: it turns ``R_t^T h`` onto ``R5^T h`` (subproblem 1 on the
    vectors projected across axis 6: both are small near the singularity). At the wrist
    singularity joint 6 takes the representatives of
    :func:`~kincalc.ik.wrists.parallel_wrist_q6`, one slot per arc of the continuum (the
    second labelled ``other arc``), marked free.

    ``v (N, K, 3)``: axis 6's direction ``R_t k6`` at the slots of ``br`` (joint 1 undone on
    a three-parallel arm); ``aligned (N, K)``: where it is along h. Returns ``(br, sigma)``:
    joint 6 set, ``sigma (N, K')`` +1 where axis 6 points along h, else -1, needed only at
    the singularity: None where no slot is there.
    """
    h, k6 = S.axis[hj], S.axis[5]
    first = elbow[0] == 1                              # joint 1 turns about another axis
    sigma = _sense(v, h) if np.count_nonzero(aligned) else None
    a = rotate_back(Rt, S.turn(0, br.cos[0], br.sin[0], h) if first else np.full(
        br.ok.shape + (3,), h))
    b = S.turn(4, br.cos[4], br.sin[4], h, back=True)
    t6 = _near_singular_q6(S, br, T, v, aligned, b, turn_onto(k6, a, b)[0], elbow)
    br = note_direction(S, br, 5, a, b)
    arcs, ok_arcs = _singular_q6(S, br, T, v, aligned, elbow)
    q6 = pair(np.where(aligned, arcs[..., 0], t6), arcs[..., 1])
    ok6 = pair(np.where(aligned, ok_arcs[..., 0], True), aligned & ok_arcs[..., 1])
    br = br.branch([5], Solutions((q6,), (np.cos(q6),), (np.sin(q6),), ok6, ok6,
                                  pair(aligned, aligned)), labels=(None, "other arc"))
    return br, None if sigma is None else br.take(sigma)


def _sense(v, h) -> np.ndarray:
    """``sigma (N, K)``: +1 where axis 6 (``v (N, K, 3)``) points along h, else -1."""
    return np.where(dot(v, h) > 0, 1.0, -1.0)


def _carried(sigma) -> tuple:
    """The extras that carry ``sigma`` of :func:`_parallel_wrist` through the placement of
    axis 4: none where no slot is at the wrist singularity (``sigma`` None)."""
    return () if sigma is None else ("sigma", sigma)


def _slide_fourth(S: Screws, br: Branches, p4) -> Branches:
    """Joints 1, 2 and 4 of an offset-wrist arm whose fourth joint slides along the
    direction h of the three revolute ones (R-R-R-P): a slide along h commutes with turns
    about axes along h, so the slide is the height of axis 4's point ``o4`` along h, and
    joints 1 and 2 place axis 3's point where the turn ``psi`` about h (``br.extra``) puts
    it, ``p4 - x4 h - R_h(psi) (o4 - o3)`` (``p4 (N, K, 3)``: where ``o4`` must go)."""
    h, o3, o4 = S.axis[3], S.point[2], S.point[3]
    x4 = dot(p4 - o4, h)
    br = br.set(3, x4, np.ones_like(x4), np.zeros_like(x4))
    psi = br.extra["psi"]
    # R_h(psi) as a turn about axis 3 (along h; its sign makes psi a turn about axis 4's)
    s3 = float(np.sign(S.axis[2] @ h))
    arm = S.turn(2, np.cos(psi), s3 * np.sin(psi), o4 - o3)
    return place(S, br, (0, 1), o3, p4 - br.value[3][..., None] * h - arm,
                 what="axis 3")


def _undo_56(S: Screws, br: Branches, j: int):
    """``(R6^T R5^T e, E6^-1 E5^-1 o4)``, each ``(N, K, 3)``: ``e = axis_normal(S, j)`` (axis
    ``j`` along h) and axis 4's point ``o4`` with joints 5 and 6 of a parallel wrist undone.
    Joint 5 turns both fixed vectors in one call (:meth:`Screws.turn_fixed`), joint 6 both
    results in another."""
    o5, o6 = S.point[4], S.point[5]
    five = S.turn_fixed(4, br.cos[4], br.sin[4], ("normal of axis, o4 - o5", j),
                        lambda: (axis_normal(S, j), S.point[3] - o5), back=True)
    x = np.empty(five.shape)
    x[..., 0, :] = five[..., 0, :]
    np.add(o5, five[..., 1, :], out=x[..., 1, :])
    x[..., 1, :] -= o6
    x = S.turn(5, br.cos[5], br.sin[5], x, back=True)
    return x[..., 0, :], o6 + x[..., 1, :]


def _tool_point_of(S: Screws, T, x) -> np.ndarray:
    """``T M^-1 x`` for points ``x (N, K, 3)`` (world frame at q = 0 -> at the poses)."""
    Minv = inverse_home(S)
    local = x @ Minv[:3, :3].T + Minv[:3, 3]
    return (T[:, None, :3, :3] @ local[..., None])[..., 0] + T[:, None, :3, 3]


def _singular_q6(S: Screws, br: Branches, T, v, aligned, elbow=(1, 2, 3)):
    """Joint 6's representatives at the wrist singularity, two arcs per slot:
    ``(q6 (N, K, 2), ok (N, K, 2))`` (:func:`~kincalc.ik.wrists.parallel_wrist_q6`, its
    ``elbow``: a three-parallel arm's joints 2-4, with joint 1 undone; an offset-wrist arm's
    two revolute joints of 1-3 and joint 4, where a prismatic joint along h moves nothing
    across h). ``v (N, K, 3)``: axis 6's direction, whose sense is taken along the elbow's
    first axis (which may point against the h of the caller's joint)."""
    N, K = aligned.shape
    if not np.count_nonzero(aligned):
        return np.zeros((N, K, 2)), np.zeros((N, K, 2), bool)
    q6, ok, _ = parallel_wrist_q6(S, *_elbow_vectors(S, br, T, elbow),
                                  _sense(v, S.axis[elbow[0]]), elbow=elbow)
    return q6, ok


_COS_NEAR = float(np.cos(NEAR_ALIGNED))


def _near_singular_q6(S: Screws, br: Branches, T, v, aligned, b, q6, elbow):
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
    a, b, at = _elbow_vectors(S, br, T, elbow, q6)
    # (sigma along the elbow's first axis, as for the arcs)
    moved = into_elbow_reach(S, a, b, _sense(v, S.axis[elbow[0]]), q6, at, sine, elbow=elbow)
    return np.where(near, moved, q6)


def _elbow_vectors(S: Screws, br: Branches, T, elbow, q6=None):
    """``(a, b)`` of :func:`~kincalc.ik.wrists.parallel_wrist_q6`, each ``(N, K, 3)``: from
    the elbow's first axis to axis 6, and from axis 6 to axis 4 at ``q6 = 0`` (joint 5 at
    its value), across h, with joint 1 undone when it is not the elbow's (about another
    axis, or sliding along h). Given ``q6 (N, K)`` (rad), also ``at``: from the elbow's first
    axis to axis 4 with joint 6 at ``q6``, across h (exactly: axis 6 need not be along h)."""
    N, K = br.ok.shape
    h, o6 = S.axis[elbow[0]], S.point[5]
    undo1 = (lambda x: back(S, br, 0, x)) if elbow[0] == 1 else (lambda x: x)
    perp = lambda x: x - dot(x, h)[..., None] * h  # noqa: E731
    W = undo1(np.full((N, K, 3), tool_point(S, T, o6)))
    # the last elbow joint's point (axis 4's; axis 3's when joint 4 slides along h, which
    # moves nothing across h)
    o4 = back(S, br, 4, np.full((N, K, 3), S.point[elbow[-1]]))   # E5^-1 o4
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
    from subproblem 1; joints 1-3 then place axis 4's point, and joint 4 closes the sum
    (a slide fourth: :func:`_slide_fourth`, and joint 3 closes it).

    At the wrist singularity (axis 6 parallel to h) only the signed sum of the revolute
    angles about h and ``sigma q6`` is fixed, as for a three-parallel arm: joint 6 takes
    the representatives of :func:`~kincalc.ik.wrists.parallel_wrist_q6` (the elbow of the
    two revolute joints among 1-3), marked free, with the sum kept as the slot's
    continuum (``extra["parallel continuum"]``: :func:`~kincalc.ik.pieces.closing_turn`).

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
    turning = tuple(i for i in range(4) if S.revolute[i])      # the three about h
    Rt = target_rotation(S, T)
    br, sigma = _parallel_wrist(S, T, br, Rt, 3, turning)
    r, p4 = _undo_56(S, br, 3)
    psi = angle_about(S, 3, rotate(Rt, r))[0]
    p4 = _tool_point_of(S, T, p4)
    br = br.with_extra("psi", psi, *_carried(sigma))
    if S.revolute[3]:
        br = place(S, br, (0, 1, 2), S.point[3], p4, what="axis 4")
    else:
        br = _slide_fourth(S, br, p4)
    sign = [float(np.sign(S.axis[i] @ h)) for i in turning]
    return closing_turn(br, turning, sign, 5)
