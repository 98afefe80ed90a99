"""Wrists: the last joints of an arm setting the orientation, for every slot at once.

A spherical wrist is three revolute joints whose axes meet at one point (Pieper 1968):
``R(k1, t1) R(k2, t2) R(k3, t3) = R_W``, the rotation left for it. Only two vectors of
``R_W`` are needed: ``v = R_W k3`` (where the third axis must point) and ``w = R_W e``
for a fixed ``e`` normal to ``k3``. The middle joint puts ``R(k2, t2) k3`` on the cone
of ``v`` about ``k1`` (:func:`~kincalc.subproblems.cone.cone`, exact up to the
singularity), the first turns it onto ``v`` (subproblem 1), the third turns ``e`` onto
``(R1 R2)^T w`` (subproblem 1).

At the singularity (``v`` on the line of ``k1``: the outer axes on one line) the first
and third rotations are about one line and only ``t1 + sigma t3`` is fixed
(``sigma = +-1`` as the axes point the same way or not): one representative per
placement, ``t1 = 0``, the first joint marked free and the relation kept as the slot's
continuum (``Branches.extra["continuum"]``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..subproblems import sp1
from ..subproblems.sp4 import coefficients, sp4
from ..subproblems.cone import cone
from ..subproblems.solutions import Solutions, cross, dot, pair
from .branches import Branches
from .pieces import axis_cone, axis_normal, normal_sp1, one_root, rotate, rotate_back
from ..spatial import wrap
from ..tolerances import ACCEPT_POSITION, ROUNDED_POSE
from .screws import Screws

#: the sine of axis 6's angle from h (a wrist of :func:`parallel_wrist_q6`) below which, not
#: at the singularity (:data:`~kincalc.subproblems.cone.ALIGNED_TOL`), joint 6's angle read
#: from the orientation is moved into the elbow's reach (:func:`into_elbow_reach`): its
#: error, the pose's over the sine, then moves the tool by at most the pose's error
NEAR_ALIGNED = 1e-4


def undo(S: Screws, br: Branches, joints, x) -> np.ndarray:
    """``(R_j1 ... R_jm)^T x``: the rotations of the solved revolute ``joints`` undone.

    Parameters
    ----------
    S : Screws
        The chain (world frame at q = 0).
    br : Branches
        Gives the joints' cosines and sines ``(N, K)``.
    joints : sequence of int
        Solved joints (0-based), in chain order; prismatic ones are skipped.
    x : array_like (N, K, ..., 3)
        Vectors (one or more per slot).

    Returns
    -------
    ndarray (N, K, ..., 3)
    """
    cos, sin = br.cos, br.sin
    for j in joints:
        if S.revolute[j]:
            x = S.turn(j, cos[j], sin[j], x, back=True)
    return x


def spherical(S: Screws, br: Branches, joints, v, w) -> Branches:
    """``br`` with the wrist ``joints`` (three revolute, concurrent axes) solved.

    Two slots per placement (the middle joint's +/- roots); where the orientation is out
    of the wrist's reach, its least-squares angle (for the reasons of an unreachable pose).
    At the singularity the first joint is 0 and free, and ``extra["continuum"]``
    ``(N, K, 5)`` holds (mask, first joint, third joint, sigma, total in rad).

    Parameters
    ----------
    S : Screws
        The chain (world frame at q = 0, SI).
    br : Branches
        The joints before the wrist solved.
    joints : tuple of int
        The wrist's three joints (0-based), base to tip.
    v, w : ndarray (N, K, 3)
        ``v = R_W k3`` and ``w = R_W e`` (unit; world frame at q = 0), with the joints
        before the wrist undone; ``e = axis_normal(S, joints[2])``
        (:func:`~kincalc.ik.pieces.axis_normal`).

    Returns
    -------
    Branches
        ``2 K`` slots (fewer once dead ones are dropped), the three joints set.
    """
    j1, j2, j3 = joints
    k1, k2, k3 = S.axis[j1], S.axis[j2], S.axis[j3]
    middle = cone(k1, k3, k2, v, fixed=axis_cone(S, j1, j2, j3))          # (N, K, 2)
    # the outer joints at both roots of the middle one (the roots' axis after the slots',
    # as the split lays them out), then one split for the three
    c2, s2 = middle.c[0], middle.s[0]
    vw = np.empty((2,) + c2.shape + (3,))           # v and w at both roots
    vw[0], vw[1] = v[..., None, :], w[..., None, :]
    third = S.turn(j2, c2, s2, k3)                  # R2 k3
    # (subproblem 1 projects both on the plane normal to k1 first: next to the singularity
    # their normal parts are tiny, and v's component along k1 would swamp them)
    t1, c1, s1 = one_root(sp1(third, vw[0], k1, tol=0.0))
    # the free joint is the first, where the wrist is aligned (the same at both roots)
    aligned = middle.free
    singular = np.count_nonzero(aligned)
    if singular:
        c1, s1 = np.where(aligned, 1.0, c1), np.where(aligned, 0.0, s1)
        t1 = np.arctan2(s1, c1)
    z = S.turn(j2, c2, s2, S.turn(j1, c1, s1, vw[1], back=True), back=True)
    t3, c3, s3 = one_root(sp1(axis_normal(S, j3), z, k3, tol=0.0, fixed=normal_sp1(S, j3)))
    br = br.branch([j2, j1, j3], Solutions((middle.theta[0], t1, t3), (c2, c1, c3),
                                           (s2, s1, s3), middle.ok, middle.exact, aligned),
                   least_squares=True, free=(j1,))
    if singular:
        aligned = br.free[j1]
        sigma = np.where(dot(k1, S.turn(j2, br.cos[j2], br.sin[j2], k3)) > 0, 1.0, -1.0)
        br = br.with_extra("continuum", np.stack([
            aligned.astype(float), np.full(aligned.shape, j1), np.full(aligned.shape, j3),
            sigma, br.value[j1] + sigma * br.value[j3]], -1))
    return br


def spherical_taking(S: Screws, br: Branches, joints, Rt, before=(), after=()) -> Branches:
    """``br`` with the spherical wrist ``joints`` taking the rotation ``R_W = (R_before)^T R_t
    (R_after)^T`` left for it by the solved joints ``before`` and ``after`` it
    (:func:`spherical` on ``v = R_W k3``, ``w = R_W e``).

    Parameters
    ----------
    S : Screws, the chain (world frame at q = 0, SI)
    br : Branches, the joints ``before`` and ``after`` solved
    joints : tuple of int, the wrist's three joints (0-based), base to tip
    Rt : ndarray (N, 1 or K, 3, 3), the rotation the product of exponentials must give
    before, after : tuple of int, solved joints (0-based) before and after the wrist

    Returns
    -------
    Branches, ``2 K`` slots (fewer once dead ones are dropped), the wrist's joints set
    """
    k = S.axis[joints[2]]
    ke = S.constant(("axis and its normal", joints[2]),
                    lambda: np.stack([k, axis_normal(S, joints[2])], -1))          # (3, 2)
    if not after and br.free_in(before):                       # (rare: a singular target)
        for j in before:
            if S.revolute[j] and br.free_in((j,)):
                br = free_for_the_wrist(S, br, joints[0], axis_cone(S, *joints),
                                        rotate(Rt, k), before, j)
    if after and br.free_in(after):             # (rare: a wrist at the base, after it free)
        for j in after:
            if S.revolute[j] and br.free_in((j,)):
                br = free_for_the_wrist(S, br, joints[0], axis_cone(S, *joints), k, after, j,
                                        along=rotate_back(Rt, S.axis[joints[0]]))
    vw = np.empty(br.ok.shape + (2, 3))
    if after:
        vw[...] = ke.T
        vw = (Rt @ undo(S, br, after, vw).swapaxes(-1, -2)).swapaxes(-1, -2)
    else:
        vw[...] = (Rt @ ke).swapaxes(-1, -2)
    vw = undo(S, br, before, vw)
    return spherical(S, br, joints, vw[..., 0, :], vw[..., 1, :])


def free_for_the_wrist(S: Screws, br: Branches, j1: int, cone, u, before, j: int,
                       along=None) -> Branches:
    """``br`` with joint ``j`` of ``before``, where a singular target left it free (the
    wrist centre on its axis: any value places the centre), turned so that the wrist can
    point its vector where the target asks.

    A wrist whose twists are not right angles points a vector of its last link (its last
    axis ``k3``; the approach of a two-joint wrist) only within a band of directions:
    ``k1 . v`` (``v`` the vector's target direction with the joints before the wrist undone)
    within ``[C - r, C + r]``, the range of ``k1 . R(k2, t) k3``. The free joint turns
    ``v``; its representative 0 may leave it out of the wrist's reach (a Stanford arm with
    a 30 deg wrist twist at d3 = 0: no solution). There it takes the value that puts ``k1 .
    v`` in the middle of the range, ``C`` (subproblem 4, or its least-squares angle): both
    roots, one per arc of the band, the second in a slot of its own (``other arc``: a
    three-parallel arm places axis 4 from one arc only); it stays free (the values around
    it reach too). Where the representative is within the band and the band is two arcs of
    the joint (:func:`band_arcs`), it stands for its own arc and the root in the other arc
    comes as ``other arc``. Elsewhere, and for a wrist that reaches every direction,
    nothing changes.

    Parameters
    ----------
    S : Screws, the chain (world frame at q = 0, SI)
    br : Branches, the joints ``before`` solved, ``j`` free in some slots
    j1 : int, the wrist's first joint (0-based)
    cone : ConeConstants, of the pointed vector turned by the wrist's second joint,
        measured along axis ``j1`` (:func:`~kincalc.ik.pieces.axis_cone` for an axis)
    u : ndarray (N, 1 or K, 3), the direction the target asks of the vector (world frame)
    before : tuple of int, the joints before the wrist (0-based, in chain order)
    j : int, the free revolute joint of ``before``
    along : ndarray (N, 1 or K, 3), optional
        For a free joint *after* the wrist (a wrist at the base): ``R_t^T k1``, the
        direction the wrist's reach is measured along with the target's rotation undone;
        ``u`` is then the wrist's own vector at q = 0 and ``before`` the joints after the
        wrist (``k1 . R_t R_after^T u``, the same form with the roles of the two sides
        exchanged).

    Returns
    -------
    Branches, ``2 K`` slots (fewer once dead ones are dropped)
    """
    k1, kj = S.axis[j1], S.axis[j]
    at = list(before).index(j)
    w = undo(S, br, before[:at], np.broadcast_to(u, br.ok.shape + (3,)))   # before j undone
    h = np.broadcast_to(k1 if along is None else along, w.shape)
    for i in reversed(before[at + 1:]):                                # R_after k1
        if S.revolute[i]:
            h = S.turn(i, br.cos[i], br.sin[i], h)
    band = band_arcs(h, w, kj, cone)                                 # k1 . v as j turns
    A, B = band.A, band.B
    f = band.D + A * br.cos[j] - B * br.sin[j]                         # at the representative
    out = br.free[j] & (np.abs(f - cone.C) > band.r + 1e-12)           # beyond the wrist
    two = band.two & br.free[j] & ~out   # the representative holds one of two arcs
    if not np.count_nonzero(out | two):
        return br
    # k1 . R_after^T R(k_j, -q) w = C: subproblem 4 in -q; each root is the middle of an arc
    sol = sp4(h, w, kj, np.broadcast_to(cone.C, out.shape)).negated()
    # the root of the other arc: k1 . v falls there where it rises at the representative
    slope = -A[..., None] * sol.s[0] - B[..., None] * sol.c[0]          # (N, K, 2)
    here = -A * br.sin[j] - B * br.cos[j]
    other = (np.where(slope[..., 0] * here < 0, 0, 1))[..., None]
    second = [np.take_along_axis(x, other, -1)[..., 0] for x in (sol.theta[0], sol.c[0],
                                                                   sol.s[0], sol.exact)]
    # one value per arc of the wrist's reach: the joints after the wrist may place their
    # point from one arc only (a three-parallel arm's axis 4)
    q, c, s = (pair(np.where(out, x[..., 0], y), np.where(out, x[..., 1], z))
               for x, y, z in zip((sol.theta[0], sol.c[0], sol.s[0]),
                                  (br.value[j], br.cos[j], br.sin[j]), second))
    ok = pair(np.ones(out.shape, bool),
              (out & sol.ok[..., 1] & sol.exact[..., 1]) | (two & second[3]))
    return br.branch([j], Solutions((q,), (c,), (s,), ok, ok, np.zeros(ok.shape, bool)),
                     labels=(None, "other arc"), free=False)


class Band(NamedTuple):
    """How a free joint moves the quantity a wrist must keep within its band
    (:func:`band_arcs`)."""

    D: np.ndarray           # (...) h . R(k, -q) w = D + A cos q - B sin q
    A: np.ndarray
    B: np.ndarray
    r: object               # the band's half-width about the cone's C (0.0: a degenerate cone)
    two: np.ndarray         # (...) bool: the joint's values in the band are two arcs


def band_arcs(h, w, k, cone) -> Band:
    """How a free joint (axis ``k``, turning by ``q``) moves the quantity a wrist must keep
    within its band: ``h . R(k, -q) w = D + A cos q - B sin q``, against the band ``[C - r,
    C + r]`` of ``cone`` (the wrist's reach, :func:`~kincalc.subproblems.cone.cone_constants`).

    Parameters
    ----------
    h, w : ndarray (..., 3), the direction the band is measured along and the vector the
        joint turns (one frame)
    k : ndarray (3,), the joint's unit axis (same frame)
    cone : ConeConstants, the band's ``C`` and ``rr``

    Returns
    -------
    Band
        The coefficients, ``r``, and ``two``: the band strictly within the range ``D +-
        hypot(A, B)``, where the joint's values in the band are two arcs, each monotonic in
        ``q`` and holding one root of ``h . R(k, -q) w = C`` (elsewhere one arc holds both,
        or there is none).
    """
    A, B, D = coefficients(h, w, k)                                  # subproblem 4's
    R = np.hypot(A, B)
    r = 0.0 if cone.all_degenerate else cone.rr                       # (r = 0: rr holds 1)
    return Band(D, A, B, r, (cone.C - r > D - R + 1e-12) & (cone.C + r < D + R - 1e-12))


def parallel_wrist_q6(S: Screws, a, b, sigma, elbow=(1, 2, 3)):
    """Representative values of joint 6 at the wrist singularity of a three-parallel arm.

    There joints 2, 3, 4 and 6 turn about parallel axes (direction ``h``). All
    quantities here are projected on the plane normal to h, in the frame with joint 1
    undone (world frame, m). Turning joint 6 by ``q6`` swings axis 4 about axis 6 by
    ``-sigma q6``. Joints 2 and 3 (a planar two-link arm) must then reach axis 4. They
    reach distances between ``|l2 - l3|`` and ``l2 + l3`` from axis 2, where ``l2`` is
    the distance from axis 2 to axis 3 and ``l3`` the distance from axis 3 to axis 4.
    So the continuum is made of one or two arcs of ``q6``.

    Convention, per arc: ``q6 = 0`` when the arc holds it. Otherwise ``q6`` is the
    value that puts axis 4 nearest the middle of the elbow's reach,
    ``(|l2 - l3| + l2 + l3) / 2`` from axis 2. Of the two such values the one on the
    side of ``q6 = 0`` is used. This value is inside the arc, away from the stretched
    and folded elbow.

    Parameters
    ----------
    S : Screws
        The arm's screws (world frame at q = 0, m); ``h`` is axis 2.
    a : array_like (..., 3)
        From axis 2 to axis 6, normal to h (m).
    b : array_like (..., 3)
        From axis 6 to axis 4 at ``q6 = 0``, normal to h (m).
    sigma : array_like (...)
        +1 when axis 6 points along h, -1 when it points against it.
    elbow : tuple of 3 int
        The joints (0-based) whose axes are the elbow's: its first and second revolute
        joints about h and the joint whose axis it must reach, ``h`` the axis of the first
        (three-parallel: 2, 3 and 4; an offset-wrist arm of joints 1-4 about or along one
        direction: its two revolute joints before joint 4, and joint 4).

    Returns
    -------
    q6 : ndarray (..., 2)
        Rad, in (-pi, pi]. Slot 0 is the arc on the side of ``q6 = 0`` (or the only
        arc), slot 1 the other arc.
    ok : ndarray (..., 2) of bool
        Slot 0: the elbow reaches axis 4 on some arc; slot 1: only when there are two.
    phi : ndarray (..., 2)
        The angle (rad) about h from ``a`` to axis 4's offset, whose sign tells the two
        arcs apart.
    """
    r = _elbow_reach(S, a, b, elbow)
    sigma = np.asarray(sigma, float)
    c_mid = (r.mid_r * r.mid_r - r.A2 - r.B2) / r.den
    # within the acceptance of the reach's edge (the arc a single point, the elbow stretched
    # or folded, which a pose's rounding puts a hair out of reach): the engine's check
    # and polish judge the candidate at the edge
    slack = 2.0 * elbow_radii(S, elbow)[1] * ACCEPT_POSITION * S.scale / r.den
    reach = r.flat | (r.lo <= r.hi + slack + 1e-12)
    two = ~r.flat & (r.c_out < 1.0) & (r.c_in > -1.0)
    zero_in = r.flat | ((r.cos0 >= r.lo - 1e-12) & (r.cos0 <= r.hi + 1e-12))
    # (where the elbow cannot reach axis 4 at all, lo > 1: any angle stands in, unused)
    phim = np.arccos(np.minimum(np.clip(c_mid, r.lo, np.maximum(r.lo, r.hi)), 1.0))
    side = np.where(r.sin0 >= 0, 1.0, -1.0)
    phi0 = np.arctan2(r.sin0, r.cos0)
    q6 = np.stack([np.where(zero_in, 0.0, sigma * (phi0 - side * phim)),
                   sigma * (phi0 + side * phim)], axis=-1)
    phi = np.stack([np.where(zero_in, phi0, side * phim), -side * phim], axis=-1)
    return wrap(q6), np.stack([reach, reach & two], axis=-1), phi


def into_elbow_reach(S: Screws, a, b, sigma, q6, at, sine, elbow=(1, 2, 3)):
    """Joint 6's value ``q6`` a hair from the wrist singularity of :func:`parallel_wrist_q6`,
    moved onto the nearer end of its arc where the elbow does not reach axis 4 there.

    With axis 6 at a small angle ``P`` from h, joint 6's angle read from the orientation is
    good only to the pose's error over ``P`` (a pose rounded to 12 digits: 1e-12 / P rad),
    while a turn of it by ``d`` (the others following) moves the tool's orientation by only
    about ``P d``. With the elbow stretched or folded that error can put axis 4 out of
    the elbow's reach, where a value of joint 6 a little way off reaches the pose to its
    rounding: the end of the arc (found on the arcs of the singularity, whose ``a``, ``b``
    the caller gives with joint 5 at its value; the engine polishes the small miss left).
    Only a move that undoes such an error is made: one that turns the tool by more than a
    pose's rounding (the move times ``P`` beyond ``ROUNDED_POSE``) would pick a point of
    the continuum the acceptance blurs, not a solution of the pose.

    ``a``, ``b``, ``sigma`` and ``elbow`` as in :func:`parallel_wrist_q6`; ``q6 (...)`` rad;
    ``at (..., 3)`` axis 4's offset from the elbow's first axis, across h, with joint 6 at
    ``q6`` (m); ``sine (...)`` the sine of axis 6's angle from h. Returns ``q6 (...)`` rad,
    moved only where ``at`` is out of the elbow's reach by more than ``ACCEPT_POSITION`` of
    the arm's size and the end of the arc is that near.
    """
    lo_r, hi_r = elbow_radii(S, elbow)
    d = np.sqrt(dot(at, at))
    tol = ACCEPT_POSITION * S.scale
    off = (d > hi_r + tol) | (d < lo_r - tol)
    if not np.count_nonzero(off):
        return q6
    r = _elbow_reach(S, a, b, elbow)
    sigma = np.asarray(sigma, float)
    phi0 = np.arctan2(r.sin0, r.cos0)
    phi = wrap(phi0 - sigma * q6)                 # from a to axis 4's offset at q6
    c = np.cos(phi)
    # the arcs are of axis 6 along h: their distance at q6 is off the exact one by about
    # the tilt times the offsets (as large as the move itself); the edges shift by that
    r = _elbow_reach(S, a, b, elbow, shift=d - np.sqrt(np.maximum(r.A2 + r.B2 + r.den * c, 0.0)))
    end = np.where(phi >= 0, 1.0, -1.0) * np.arccos(np.clip(c, r.lo, r.hi).clip(-1.0, 1.0))
    moved = wrap(sigma * (phi0 - end))
    near = sine * np.abs(wrap(moved - q6)) <= ROUNDED_POSE
    return np.where(off & near & ~r.flat & (r.lo <= r.hi), moved, q6)


def elbow_radii(S: Screws, elbow) -> tuple:
    """The distances from the elbow's first axis at which its two joints reach the third
    axis (:func:`parallel_wrist_q6`): ``(|l2 - l3|, l2 + l3)`` (m), made once per screws."""
    def radii():
        i2, i3, i4 = elbow
        h = S.axis[i2]
        perp = lambda x: x - (x @ h) * h  # noqa: E731
        l2 = float(np.linalg.norm(perp(S.point[i3] - S.point[i2])))
        l3 = float(np.linalg.norm(perp(S.point[i4] - S.point[i3])))
        return abs(l2 - l3), l2 + l3
    return S.constant(("elbow radii", tuple(elbow)), radii)


class _Reach(NamedTuple):
    """The elbow's reach of axis 4 as the cosine of the angle about h from ``a`` to axis 4's
    offset (:func:`parallel_wrist_q6`): ``lo <= cos <= hi``."""

    A2: np.ndarray          # |a|^2, |b|^2 (m^2)
    B2: np.ndarray
    den: np.ndarray         # 2 |a| |b| (1 where flat)
    flat: np.ndarray        # joint 6 does not move axis 4 relative to axis 2
    cos0: np.ndarray        # cos and sin of the angle from a to b (q6 = 0)
    sin0: np.ndarray
    c_out: np.ndarray       # the cosine at the stretched and the folded elbow
    c_in: np.ndarray
    lo: np.ndarray          # c_in and c_out clipped to [-1, 1]
    hi: np.ndarray
    mid_r: float            # the middle of the elbow's reach (m)


def _elbow_reach(S: Screws, a, b, elbow, shift=0.0) -> _Reach:
    """:class:`_Reach` of the vectors ``a``, ``b`` (..., 3) of :func:`parallel_wrist_q6`; with
    ``shift`` (m, ``(...)``) the elbow's reach taken that much shorter at both edges."""
    h = S.axis[elbow[0]]
    lo_r, hi_r = (x - shift for x in elbow_radii(S, elbow))
    a, b = np.asarray(a, float), np.asarray(b, float)
    A2, B2 = (a * a).sum(-1), (b * b).sum(-1)
    AB = np.sqrt(A2 * B2)
    # axis 6 on axis 2 or axis 4 on axis 6: joint 6 does not move axis 4 relative to
    # axis 2, so every q6 is equally good and q6 = 0 is used
    flat = AB <= (1e-9 * max(S.scale, 1e-300)) ** 2
    den = np.where(flat, 1.0, 2.0 * AB)
    c_out, c_in = ((x * x - A2 - B2) / den for x in (hi_r, lo_r))
    return _Reach(A2, B2, den, flat, 2.0 * (a * b).sum(-1) / den,
                  2.0 * (cross(a, b) @ h) / den, c_out, c_in, np.maximum(c_in, -1.0),
                  np.minimum(c_out, 1.0), 0.5 * (lo_r + hi_r))
