"""The pieces the family solvers (:mod:`kincalc.ik.solvers`, :mod:`kincalc.ik.small_arms`,
:mod:`kincalc.ik.five_joints`) and the point placement (:mod:`kincalc.ik.place`) are
composed of: the target's rotation and points in the product of exponentials' terms, a
joint's motion undone, the angle of one subproblem 1, a free joint's angle, the turn that
joints about parallel axes close (and their continuum), a double root split where it folds
a point through an axis. The Gauss-Newton polish of a placed point is
:mod:`kincalc.ik.point_polish`.

``S`` is a family's :class:`~kincalc.ik.screws.Screws` (world frame at q = 0, SI);
``R_t = R_T R_M^T`` is the rotation of the product of exponentials (``T = E_1 ... E_n M``),
and ``E_j^-1`` undoes joint j's motion.
"""

from __future__ import annotations

import numpy as np

from ..structure import common_point
from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION, FOLD_NEAR_AXIS, MOVES
from ..subproblems import sp1
from ..subproblems.cone import cone_constants
from ..subproblems.sp1 import sp1_constants
from ..subproblems.sp4 import ROUNDING, sp4_constants
from ..subproblems.solutions import Solutions, cross, dot
from .branches import Branches
from .screws import Screws
from .worked import note_sum


def inverse_home(S: Screws) -> np.ndarray:
    """``M^-1 (4, 4)``: the inverse of the tool pose at q = 0, computed once."""
    return S.constant("M^-1", S.inverse_M)


def target_rotation(S: Screws, T) -> np.ndarray:
    """``R_t (N, 1, 3, 3)``: the rotation ``E_1 ... E_n`` must give."""
    return (T[:, :3, :3] @ inverse_home(S)[:3, :3])[:, None]


def normal_to(k) -> np.ndarray:
    """A fixed unit vector normal to the unit vector ``k``.

    Parameters
    ----------
    k : array_like (3,)

    Returns
    -------
    ndarray (3,)
    """
    e = np.cross(k, [1.0, 0, 0] if abs(k[0]) < 0.9 else [0, 1.0, 0])
    return e / np.linalg.norm(e)


def axis_normal(S: Screws, j: int) -> np.ndarray:
    """``normal_to(axis j) (3,)`` (world frame at q = 0), made once per screws: the fixed
    vector whose turn about axis j a solver reads a joint's angle from."""
    return S.constant(("normal to axis", j), lambda: normal_to(S.axis[j]))


def meeting_point(S: Screws, start: int, stop: int) -> np.ndarray:
    """Where the axes of joints ``start .. stop - 1`` meet ``(3,)`` (world frame at q = 0,
    m; :func:`~kincalc.structure.common_point`), found once per screws."""
    return S.constant(("common point of axes", start, stop), lambda: common_point(
        S.point[start:stop], S.axis[start:stop], np.inf))


def axis_sp4(S: Screws, i: int, j: int):
    """:func:`~kincalc.subproblems.sp4.sp4_constants` of the component along axis ``i``
    under a turn about axis ``j``, made once per screws."""
    return S.constant(("sp4 constants", i, j), lambda: sp4_constants(S.axis[i], S.axis[j]))


def axis_cone(S: Screws, i: int, j: int, k: int):
    """:func:`~kincalc.subproblems.cone.cone_constants` of joint ``j`` turning axis ``k`` onto
    a cone about axis ``i`` (``cone(axis i, axis k, axis j, v)``), made once per screws."""
    return S.constant(("cone", i, j, k),
                      lambda: cone_constants(S.axis[i], S.axis[k], S.axis[j]))


def tool_point(S: Screws, T, p) -> np.ndarray:
    """Where the point ``p (3,)`` (world frame at q = 0, moving with the tool) is at the
    poses ``T (N, 4, 4)``: ``(N, 1, 3)`` (``M^-1 p`` kept per point)."""
    local = S.constant(("in the tool frame", tuple(p.tolist())), lambda: (
        inverse_home(S)[:3, :3] @ p + inverse_home(S)[:3, 3]))          # M^-1 p (3,)
    return (T[:, :3, :3] @ local + T[:, :3, 3])[:, None, :]


def rotate(R, v) -> np.ndarray:
    """``R v`` for ``R (..., 3, 3)``, ``v (..., 3)`` or ``(3,)``."""
    return (R @ np.asarray(v)[..., None])[..., 0]


def rotate_back(R, v) -> np.ndarray:
    """``R^T v``."""
    return (R.swapaxes(-1, -2) @ np.asarray(v)[..., None])[..., 0]


def back(S: Screws, br: Branches, j: int, x) -> np.ndarray:
    """``E_j^-1 x`` for points ``x (N, K, 3)`` (or one point ``(3,)``): joint j's motion
    undone, ``(N, K, 3)``."""
    if S.revolute[j]:
        return S.point[j] + S.turn(j, br.cos[j], br.sin[j], x - S.point[j], back=True)
    return x - br.value[j][..., None] * S.axis[j]


def one_root(sol: Solutions, i: int = 0):
    """``(theta, c, s)`` of a one-slot subproblem's unknown ``i``, each ``(N, K)``."""
    return sol.theta[i][..., 0], sol.c[i][..., 0], sol.s[i][..., 0]


def turn_onto(k, x, y):
    """The angle about the unit axis ``k (3,)`` turning ``x`` onto ``y`` (``(..., 3)``):
    subproblem 1 with no threshold, which projects both across ``k`` first (near the axis
    their normal parts are small, and a component along ``k`` would swamp them).
    ``(theta, c, s)``, each ``(...)``."""
    return one_root(sp1(x, y, k, tol=0.0))


def angle_about(S: Screws, j: int, Rv, tol=0.0):
    """The angle about axis ``j`` of ``S`` (unit ``h``) turning ``e = axis_normal(S, j)``
    onto the vectors ``Rv (..., 3)`` (subproblem 1, no threshold): ``(theta, c, s)``, each
    ``(...)``. Subproblem 1's constants of ``e`` about ``h`` are made once per screws
    (:func:`normal_sp1`)."""
    return one_root(sp1(axis_normal(S, j), Rv, S.axis[j], tol=tol, fixed=normal_sp1(S, j)))


def normal_sp1(S: Screws, j: int):
    """:func:`~kincalc.subproblems.sp1.sp1_constants` of ``axis_normal(S, j)`` about axis
    ``j``, made once per screws."""
    return S.constant(("sp1 constants of the normal", j),
                      lambda: sp1_constants(axis_normal(S, j), S.axis[j]))


def senses_along(S: Screws, about) -> tuple:
    """The sense (+1.0 or -1.0) along the first one's axis ``h`` of each revolute joint
    ``about`` (0-based, parallel axes; the first 1.0): the ``signs`` of
    :func:`closing_turn`. Computed once per chain."""
    h = S.axis[about[0]]
    return S.constant(("senses along h", tuple(about)), lambda: tuple(
        1.0 if float(S.axis[i] @ h) > 0 else -1.0 for i in about))


def closing_turn(br: Branches, about, signs, free: int) -> Branches:
    """``br`` with the last of the revolute joints ``about`` (turning about one direction h,
    ``signs`` their senses along it, +1 or -1) closing the turn ``psi = sum s_i q_i`` that
    the solver found (``br.extra["psi"]``, rad) and the others leave; where joint ``free``
    (a wrist axis along h) is free, the signed sum ``psi + sigma q_free`` is kept as the
    slot's continuum (``extra["parallel continuum"]``, ``(N, K, 6)``: mask, sigma, total in
    rad, the free joint, the joints ``about`` as bits (bit i: joint i) and those of them
    turning against h (``signs`` -1) as bits; ``sigma`` from ``br.extra["sigma"]``).

    The last step of the arms whose joints about parallel axes add up: three-parallel,
    parallel-four-wrist and planar-shoulder."""
    q = br.extra["psi"]
    for i, s in zip(about[:-1], signs[:-1]):          # (in order: the same bits as by hand)
        q = q - s * br.value[i]
    q = signs[-1] * q
    br = note_sum(br, about, signs).set(about[-1], q, np.cos(q), np.sin(q))
    if np.count_nonzero(br.free[free]):
        sigma = br.extra["sigma"]
        total = signs[0] * br.value[about[0]]
        for i, s in zip(about[1:], signs[1:]):
            total = total + s * br.value[i]
        mask = br.free[free].astype(float)
        joints = (free, sum(1 << i for i in about),
                  sum(1 << i for i, s in zip(about, signs) if s < 0))
        br = br.with_extra("parallel continuum", np.stack(
            [mask, sigma, total + sigma * br.value[free]]
            + [np.full(mask.shape, float(x)) for x in joints], -1))
    return br


def free_on_axis(S: Screws, sol, x, y):
    """Subproblem 1's ``sol`` for the vectors ``x``, ``y`` (``(N, K, 3)``, m: from a point of
    the joint's axis) with the joint also free (representative 0) where either is itself
    within rounding of the arm's size: subproblem 1 judges a vector on the axis against its
    own length, which is then rounding (a spherical arm's slide at 0 puts the point where
    axes 1 and 2 meet, and both then are free: :func:`~kincalc.ik.small_arms.point_plus_roll`
    turns them to the orientation)."""
    tol = (ROUNDING * S.scale) ** 2
    on = ((dot(x, x) <= tol) | (dot(y, y) <= tol)) & ~sol.free[..., 0]
    if not np.count_nonzero(on):
        return sol
    at = on[..., None]
    return Solutions((np.where(at, 0.0, sol.theta[0]),), (np.where(at, 1.0, sol.c[0]),),
                     (np.where(at, 0.0, sol.s[0]),), sol.ok, sol.exact, sol.free | at)


def across(k, v) -> np.ndarray:
    """``v (..., 3)``'s part across the unit axis ``k (3,)``."""
    return v - dot(v, k)[..., None] * k


#: a point within this of a revolute joint's axis (of the arm's size) is on it: every value of
#: the joint then moves it by at most half the check's tolerance (``ACCEPT_POSITION``)
ON_AXIS = 0.25 * ACCEPT_POSITION


def free_at_zero(br: Branches, j: int, on) -> Branches:
    """``br`` with joint ``j`` free, at 0, in the slots ``on (N, K)``."""
    return br.set(j, np.where(on, 0.0, br.value[j]), np.where(on, 1.0, br.cos[j]),
                  np.where(on, 0.0, br.sin[j]), free=br.free[j] | on)


def on_axis(S: Screws, j: int, p):
    """``(N, K)`` bool: the points ``p (N, K, 3)`` (world frame at q = 0, m) within
    :data:`ON_AXIS` of the arm's size of joint ``j``'s axis."""
    d = across(S.axis[j], p - S.point[j])
    return dot(d, d) <= (ON_AXIS * S.scale) ** 2


def hold_on_target_axis(S: Screws, joints, br: Branches, PT) -> tuple:
    """``(br, held)``: the first of the placing ``joints`` (a revolute one) free at 0 where
    the target ``PT (N, K, 3)`` lies on its axis (:func:`on_axis`: every value then places
    the point alike), and held there while the others are polished (``held (N, K, m)`` bool
    for :func:`~kincalc.ik.point_polish.polish_points`, or None): a double root leaves the
    point before it off the axis by the square root of rounding, and the polish would turn
    it at random to take up that error (the engine's polish of a near miss holds a free
    joint too)."""
    a = joints[0]
    if not S.revolute[a]:
        return br, None
    on = on_axis(S, a, PT) & br.ok
    if not np.count_nonzero(on):
        return br, None
    held = np.zeros(on.shape + (len(joints),), bool)
    held[..., 0] = on
    return free_at_zero(br, a, on), held


def free_on_placed_axis(S: Screws, joints, p0, br: Branches, PT) -> Branches:
    """``br`` with the second of the placing ``joints`` ``(a, b, c)`` (revolute) free at 0
    in the slots whose polished point, ``p0 (3,)`` moved by joint c, lies on its axis (a
    double root in x_c can put it there, where the roots of x_b, decided by rounding, are
    any value) and reaches its target ``PT (N, K, 3)``, each within :data:`ON_AXIS` (a
    double root is polished only to about the square root of rounding, and 0 is not
    polished)."""
    a, b, c = joints
    g = S.move(c, br.value[c], br.cos[c], br.sin[c], p0)
    on = on_axis(S, b, g) & br.ok
    if not np.count_nonzero(on):
        return br
    miss = S.move(a, br.value[a], br.cos[a], br.sin[a],
                  S.move(b, br.value[b], br.cos[b], br.sin[b], g)) - PT
    return free_at_zero(br, b, on & (dot(miss, miss) <= (ON_AXIS * S.scale) ** 2))


def turn_free_joint(S, a: int, b: int, f, g, sol):
    """The free angle of joint ``a`` (``sol``, subproblem 1's: the point ``f`` on its axis)
    chosen so that a target ``g`` a hair off the axis can be polished onto.

    Joint ``b`` a hair from its tangent (a double root taken as exact) leaves ``f (N, K, 3)``
    on axis a while ``g (N, K, 3)`` is off it by ~1e-9 (world frame, m): any angle of a
    misses by that much, and at the subproblem's 0 the miss may lie across the plane joint b
    moves ``f`` in, where no Newton step can reach (a turn of a is second order). Turning the
    direction ``f`` leaves the axis as joint b moves onto the target's offset puts the miss in
    that plane (:func:`~kincalc.ik.near_miss.polished` then reaches it). Only where 0 would
    miss the acceptance: the offset beyond ``ACCEPT_POSITION`` of the arm's size, or beyond
    ``ACCEPT_ORIENTATION`` of joint b's lever on ``f`` (where b moves ``f`` at all, by
    :data:`~kincalc.tolerances.MOVES` of the arm's size per rad); elsewhere ``sol`` is
    kept (bit for bit). ``S``: the robot's
    :class:`~kincalc.ik.screws.Screws`. Returns ``(theta, c, s)``, each ``(N, K)``."""
    theta, c, s = sol.theta[0][..., 0], sol.c[0][..., 0], sol.s[0][..., 0]
    if not np.count_nonzero(sol.free):
        return theta, c, s
    k, gq = S.axis[a], g - S.point[a]
    gk = across(k, gq)
    move = np.cross(S.axis[b], f - S.point[b]) if S.revolute[b] else S.axis[b] + 0.0 * f
    lever = np.sqrt(np.add.reduce(move * move, -1))
    bound = np.minimum(ACCEPT_POSITION * S.scale, ACCEPT_ORIENTATION * lever)
    off = sol.free[..., 0] & (np.add.reduce(gk * gk, -1) > bound * bound) & (
        lever > MOVES * S.scale)                            # (b moves f at all)
    if not np.count_nonzero(off):
        return theta, c, s
    turn = sp1(move, gq, k, tol=0.0)
    return tuple(np.where(off, t[0][..., 0], x) for t, x in
                 ((turn.theta, theta), (turn.c, c), (turn.s, s)))


def split_fold(S, a: int, b: int, sol, g, PT):
    """Subproblem 4's double root of joint ``b`` split where it folds the placed point
    through the revolute axis a while the target is off it.

    ``sol`` (:func:`~kincalc.subproblems.sp4.from_abc`'s, ``(N, K, 2)``) takes a cosine
    within rounding of +-1 as the tangent, one double root. Where that root leaves the point
    ``f = E_b(x_b) g`` within :data:`~kincalc.tolerances.FOLD_NEAR_AXIS` of the axis (a
    planar arm of equal links folded, a wrist centre straight above the shoulder) and the
    target ``PT`` lies off it
    beyond ``ACCEPT_POSITION`` of the arm's size, the two roots are distinct solutions,
    which joint a turns about half a turn apart: taken as one, joint a came out "free" and
    one of them was lost. With ``u`` the point's offset across axis a and ``m`` its velocity
    across it under joint b (per rad), the point at ``x_b + delta`` is ``|u + m delta|`` off
    the axis to first order; the roots are where that is the target's offset ``d``:
    ``|m|^2 delta^2 + 2 (u . m) delta + |u|^2 - d^2 = 0``. They are good to the second order
    in ``delta`` (the engine's check polishes what misses). Elsewhere ``sol`` is kept, bit for
    bit.

    Parameters
    ----------
    S : Screws, the chain (world frame at q = 0, SI)
    a, b : int, the revolute joints (0-based) turning the point last and just before
    sol : Solutions (N, K, 2), joint b's two roots
    g : ndarray (3,) or (N, K, 3), the point before joint b (m)
    PT : ndarray (N, K, 3), its targets (m)

    Returns
    -------
    Solutions (N, K, 2)
    """
    fold = sol.exact[..., 0] & ~sol.ok[..., 1] & ~sol.free[..., 0]
    if not np.count_nonzero(fold):
        return sol
    x = sol.theta[0][..., 0]
    f = S.move(b, x, sol.c[0][..., 0], sol.s[0][..., 0], g)
    k = S.axis[a]
    u, m, w = across(k, f - S.point[a]), across(k, cross(S.axis[b], f - S.point[b])), \
        across(k, PT - S.point[a])
    on, mm, off = dot(u, u), dot(m, m), dot(w, w)                       # squared lengths
    um = dot(u, m)
    disc = um * um + mm * (off - on)
    L = S.scale
    fold &= (on <= (FOLD_NEAR_AXIS * L) ** 2) & (off > (ACCEPT_POSITION * L) ** 2) & (
        mm > (MOVES * L) ** 2) & (disc > 0.0)
    if not np.count_nonzero(fold):
        return sol
    mm = np.where(fold, mm, 1.0)
    delta = (-um[..., None] + np.sqrt(np.where(fold, disc, 0.0))[..., None] * [1.0, -1.0]) \
        / mm[..., None]
    theta = np.where(fold[..., None], x[..., None] + delta, sol.theta[0])
    c = np.where(fold[..., None], np.cos(theta), sol.c[0])
    s = np.where(fold[..., None], np.sin(theta), sol.s[0])
    ok, exact = sol.ok.copy(), sol.exact.copy()
    ok[..., 1] |= fold
    exact[..., 1] |= fold
    return Solutions((theta,), (c,), (s,), ok, exact, sol.free, sol.undetermined)
