"""Placing a point with two or three joints of any type (R or P): every solution, for
a batch of targets at once.

The point ``p0`` (world frame, q = 0) is moved by ``E_a(x_a) E_b(x_b) [E_c(x_c)]`` and must reach a
target ``pt``. Joint a's motion leaves two quantities of a point unchanged (Pieper 1968; the
Paden-Kahan invariants): for a revolute joint its height along the axis and its distance from a
point ``o`` of it, for a prismatic one its two components across the axis. So the point ``f = E_b
E_c p0`` before joint a must match ``pt`` in those two: two equations in ``x_b, x_c``. The structure
of the robot decides how they are solved (:func:`plan`, once per robot), each way a short sequence
of subproblems:

* ``decoupled``: one invariant does not depend on ``x_b`` (axes a and b meet, with ``o`` their
  common point, or are parallel, or slide along one direction): that invariant alone gives ``x_c``
  (subproblem 4, or a quadratic for a prismatic c), the other then ``x_b`` (subproblem 4 or a
  quadratic), and ``x_a`` follows (subproblem 1, or the travel along the axis). The elbow arms
  (PUMA, Stanford, the textbook's RRP and RPR), SCARAs and cylindrical arms.
* ``shoulder``: revolute joints with axes b and c parallel and a not (an offset shoulder: KUKA, ABB,
  Fanuc): the height along the parallel axes fixes ``x_a`` (subproblem 4), the law of cosines in
  their plane ``x_c`` (subproblem 3), and ``x_b`` turns the elbow onto the target (subproblem 1).
* ``three cones``: three revolute joints with no such structure: subproblem 5 gives all three angles
  (up to four solutions).
* ``resultant``: the remaining mixes with prismatic joints: eliminating ``x_b`` leaves one equation
  in ``x_c`` of bounded degree, sampled and solved through a companion matrix per target; then
  ``x_b`` and ``x_a`` by back-substitution, and Gauss-Newton on the point equations.
* two joints (``pair``): the invariant that depends on ``x_b`` the most gives ``x_b`` (both together
  when they fix its cosine and sine), then ``x_a``; the third equation is left to the caller's check
  (two joints reach a surface). Also three joints whose third turns about a line through ``p0``:
  the third does not move the point, and is left free at 0.

A joint a target leaves undetermined (the point on the axis) gets 0 and is marked free. Solutions
are the roots of exact equations: a target out of reach gives none (the step that failed is recorded
as a dead end for ``--all-branches``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..subproblems import sp1, sp3, sp4, sp5
from ..subproblems.solutions import angles, cross, dot
from ..subproblems.roots import quadratic
from ..subproblems.sp3 import sp3_constants
from ..subproblems.sp4 import ROUNDING, abc_constants, from_abc, shared_roots, sp4_constants
from ..tolerances import FREE_REACH
from .branches import TIE_BREAK, Branches
from .pieces import (free_on_axis, free_on_placed_axis, hold_on_target_axis, split_fold,
                     turn_free_joint)
from .point_polish import polish_points
from .resultant import common_root, eliminate, roots_in_c, samples
from .screws import Screws
from .worked import note_equation, note_quadratic, note_slide, note_turn


class Plan(NamedTuple):
    """How joints ``joints`` place ``p0`` (see the module docstring); robot-level."""

    mode: str
    joints: tuple
    p0: np.ndarray
    o: np.ndarray           # (3,) the origin of joint a's invariants
    e: np.ndarray | None    # (2, 3) across a prismatic a's axis
    k: int = 0              # decoupled: the invariant free of x_b; pair: the one to use
    abc: tuple = ()         # decoupled: the invariant k as a function of x_c (constants)
    abc_fixed: object = None  # from_abc's constants: decoupled, revolute c: abc_constants(*abc);
                              # pair, revolute b: of invariant k at p0, (beta, gamma, alpha)
    at_p0: tuple = ()       # pair: both invariants' (alpha, beta, gamma) at p0, in x_b
    both: bool = False      # pair: both invariants fix (cos x_b, sin x_b)
    still: bool = False     # pair of three joints: the third does not move p0 (free, 0)


def place(S: Screws, br: Branches, joints, p0, PT, *, what: str = "the point",
          constant: bool = True) -> Branches:
    """``br`` with ``joints`` solved so that they move ``p0`` to ``PT``, one target per slot.

    Parameters
    ----------
    S : Screws, the chain (world frame at q = 0, SI)
    br : Branches, the candidates so far
    joints : sequence of int, 2 or 3 joints (0-based), base to tip
    p0 : array_like (3,), the point at q = 0 (world frame, m)
    PT : array_like (N, K, 3), its targets (world frame, m); joints before ``joints[0]`` undone
    what : str, the point's name in the dead ends (``--all-branches``)
    constant : bool, ``p0`` is a point of the robot: its plan is kept on ``S``; False for a
        point that changes with the target (a tool configuration vector's), planned afresh

    Returns
    -------
    Branches, with ``joints`` set: a slot per root, dead where there is no real one
    """
    P = (plan(S, tuple(joints), tuple(np.asarray(p0, float).tolist())) if constant else
         _make_plan(S, tuple(joints), np.asarray(p0, float)))
    br = _MODES[P.mode](S, P, br, np.asarray(PT, float), what)
    if P.still:
        zero = np.zeros(br.ok.shape)
        br = br.set(P.joints[2], zero, zero + 1.0, zero, free=np.ones(br.ok.shape, bool))
    return br


def plan(S: Screws, joints: tuple, p0: tuple) -> Plan:
    """The :class:`Plan` by which ``joints`` place ``p0``, cached on the screws ``S``.

    ``joints``: tuple of int (0-based); ``p0``: tuple of 3 floats (world frame at q = 0, m)."""
    return S.constant(("place", joints, p0), lambda: _make_plan(S, joints, np.array(p0)))


def _make_plan(S: Screws, joints, p0) -> Plan:
    a, b = joints[0], joints[1]
    o = _reference_point(S, a, b)
    e = None if S.revolute[a] else _across(S.axis[a], S.axis[b], S.revolute[b])
    base = Plan("", tuple(joints), p0, o, e)
    scale = S.scale + float(np.linalg.norm(p0))
    # the invariants' coefficients in x_b over samples of x_c (or at p0 for two joints)
    if len(joints) == 2:
        g = p0[None]
    else:
        c = joints[2]
        g = S.move_point(c, samples(S, c), p0)
        if np.abs(g - p0).max() <= 1e-9 * scale:      # p0 on axis c: joints a, b place it
            pair = _make_plan(S, joints[:2], p0)
            return pair._replace(joints=tuple(joints), still=True)
    al, be, ga = _coefficients(S, base, g)                      # (2, m), with pt = 0
    dep = np.maximum(np.abs(be), np.abs(ga)).max(-1) > 1e-9 * scale ** 2
    if len(joints) == 2:
        k = int(np.argmax(np.maximum(np.abs(be[:, 0]), np.abs(ga[:, 0]))))
        D = be[0, 0] * ga[1, 0] - be[1, 0] * ga[0, 0]
        both = bool(S.revolute[b] and dep.all()
                    and abs(D) > 1e-9 * max(np.abs(be).max() * np.abs(ga).max(), 1e-300))
        at_p0 = tuple(_coefficients(S, base, p0, i) for i in (0, 1))   # as _pair needs them
        al, be, ga = at_p0[k]
        return Plan("pair", tuple(joints), p0, o, e, k=k, at_p0=at_p0, both=both,
                    abc_fixed=abc_constants(be, ga, al) if S.revolute[b] else None)
    c = joints[2]
    if not dep.all():
        k = int(np.flatnonzero(~dep)[0])
        abc = _fit_c(S, c, al[k])
        return Plan("decoupled", tuple(joints), p0, o, e, k=k, abc=abc,
                    abc_fixed=abc_constants(*abc) if S.revolute[c] else None)
    if S.revolute[[a, b, c]].all():
        h, kc = S.axis[b], S.axis[c]
        if np.linalg.norm(np.cross(h, kc)) <= 1e-12 and \
                np.linalg.norm(np.cross(S.axis[a], h)) > 1e-9:
            return Plan("shoulder", tuple(joints), p0, o, e)
        return Plan("three cones", tuple(joints), p0, o, e)
    return Plan("resultant", tuple(joints), p0, o, e)


def _across(w, kb, revolute_b: bool) -> np.ndarray:
    """Two unit vectors across a prismatic joint a's axis ``w`` (3,), the directions of its
    invariants, ``(2, 3)``.

    The first is, where one exists, the direction across ``w`` in which joint b (axis ``kb``)
    moves no point: ``kb`` itself when a revolute b's axis is across ``w`` (its circles lie in
    planes normal to ``kb``), ``w x kb`` for a prismatic b. That invariant is then free of
    ``x_b`` and the plan decoupled; any other pair of directions would mix both invariants
    with ``x_b`` in proportion, which no elimination of ``x_b`` can undo. Otherwise (and
    where the plan finds the invariant not free after all) the directions are only a basis.
    """
    n = kb - (kb @ w) * w if revolute_b else np.cross(w, kb)
    if np.linalg.norm(n) < 1e-9:                        # b along a: any basis
        n = np.cross(w, [1.0, 0, 0] if abs(w[0]) < 0.9 else [0, 1.0, 0])
    e1 = n / np.linalg.norm(n)
    return np.stack([e1, np.cross(w, e1)])


def _fit_c(S: Screws, c: int, values) -> tuple:
    """An invariant free of x_b as a function of x_c, from its samples: ``(A, B, C)`` of
    ``A cos + B sin + C`` (revolute c) or of ``A x^2 + B x + C`` (prismatic c)."""
    x = samples(S, c)
    if S.revolute[c]:       # the first harmonic of the samples over a whole turn
        return 2 * np.mean(values * np.cos(x)), 2 * np.mean(values * np.sin(x)), np.mean(values)
    A, B, C = np.polyfit(x, values, 2)
    return A, B, C


def _reference_point(S: Screws, a: int, b: int) -> np.ndarray:
    """The point of axis a nearest to axis b: distances measured from there do not depend on
    x_b when the axes meet. Where the axes are parallel, or that point lies beyond
    FAR_REFERENCE arm sizes (nearly parallel: a twist written as 1.5707963 put it 1e6 m
    away, and the distances squared from there kept nothing of the arm), a point of a."""
    wa, pa, wb, pb = S.axis[a], S.point[a], S.axis[b], S.point[b]
    n = np.cross(wa, wb)
    nn = n @ n
    if nn < 1e-18:
        return pa
    along = np.cross(pb - pa, wb) @ n / nn
    return pa + along * wa if abs(along) <= FAR_REFERENCE * max(S.scale, 1.0) else pa


#: the reference point of joint a's distances (:func:`_reference_point`) lies within this
#: many arm sizes of its axis's point
FAR_REFERENCE = 100.0


# --- the invariants of joint a ---------------------------------------------------------

def _invariants(S: Screws, P: Plan, f, only: int | None = None):
    """The two invariants of joint a at points ``f (..., 3)``: two arrays ``(...)`` (with
    ``only``, 0 or 1, that invariant's: ``(...)``)."""
    a = P.joints[0]
    if S.revolute[a]:
        d = f - P.o
        if only is not None:
            return dot(d, S.axis[a]) if only == 0 else dot(d, d)
        return dot(d, S.axis[a]), dot(d, d)
    if only is not None:
        return dot(f, P.e[only])
    return dot(f, P.e[0]), dot(f, P.e[1])


def _coefficients(S: Screws, P: Plan, g, only: int | None = None):
    """``(alpha, beta, gamma)``, each ``(2, ...)`` (with ``only``, 0 or 1, that invariant's:
    ``(...)``): the invariants of ``f = E_b(x_b) g`` for points ``g (..., 3)`` as ``alpha +
    beta B1 + gamma B2``, ``(B1, B2) = (cos x_b, sin x_b)`` (revolute b) or ``(x_b, x_b^2)``.

    A revolute b moves g on a circle, ``f = m + cos(x_b) e1 + sin(x_b) e2`` (``m`` its
    centre on axis b, ``e1`` g's offset from it, ``e2 = k_b x e1``, as long as ``e1`` and
    normal to it); a prismatic b along its axis, ``f = g + x_b k_b``. The invariants are
    linear in f (heights, components) or ``|f - o|^2``, which on the circle is
    ``|m - o|^2 + |e1|^2 + 2 cos(x_b) (m - o) . e1 + 2 sin(x_b) (m - o) . e2``."""
    if only is None:
        parts = [_coefficients(S, P, g, i) for i in (0, 1)]
        return tuple(np.stack([x, y]) for x, y in zip(*parts))
    a, b = P.joints[0], P.joints[1]
    k = S.axis[b]
    if S.revolute[b]:
        m, e1, e2 = _circle(S, b, g)
        zero = 0.0                  # the terms have g's batch shape already
    else:
        m, e1, e2 = g, k, None
        zero = np.zeros(np.shape(g)[:-1])
    if S.revolute[a] and only == 1:           # |f - o|^2
        m = m - P.o
        if S.revolute[b]:
            return dot(m, m) + dot(e1, e1), 2.0 * dot(m, e1), 2.0 * dot(m, e2)
        return dot(m, m), 2.0 * dot(m, k) + zero, 1.0 + zero
    n = S.axis[a] if S.revolute[a] else P.e[only]
    if S.revolute[a]:
        m = m - P.o
    return dot(m, n), dot(e1, n) + zero, zero if e2 is None else dot(e2, n)


def _circle(S: Screws, b: int, g):
    """Joint ``b``'s circle through ``g (..., 3)``: centre ``m``, ``e1 = g - m``, ``k_b x e1``."""
    k = S.axis[b]
    u = g - S.point[b]
    hk = dot(u, k)[..., None] * k
    return S.point[b] + hk, u - hk, cross(k, u)


def _targets(S: Screws, P: Plan, PT):
    return np.stack(_invariants(S, P, PT), -1)          # the targets' invariants (N, K, 2)


# --- the steps ------------------------------------------------------------------------

def _solve_c(S: Screws, P: Plan, br, t, what) -> Branches:
    """Decoupled: x_c from the invariant free of x_b (``t (N, K)``: the target's)."""
    c = P.joints[2]
    A, B, C = P.abc
    scale = (S.scale + np.sqrt(np.abs(t))) ** 2
    if S.revolute[c]:
        sol = from_abc(A, B, C, t, scale, fixed=P.abc_fixed)
        if br.explain:
            br = br.dead_end(c, np.arctan2(B, A), (t - C) / max(np.hypot(A, B), 1e-300),
                             ~sol.exact[..., 0] & br.ok, what)
            br = note_equation(br, c, _measure(S, P, P.k), P.joints[0], A, B, C, t)
        return br.branch([c], sol)
    # a target within rounding of the invariant's extreme (the slide that puts the point
    # where axes a and b meet) is the tangent, as from_abc's: the double root to rounding
    br = note_quadratic(br, c, _measure(S, P, P.k), P.joints[0], A, B, C, t)
    return br.branch([c], quadratic(A, B, C - t, scale, tangent=ROUNDING * scale),
                     labels=("root 1", "root 2"))


def _solve_b(S: Screws, P: Plan, br, g, t, m: int, what, PT, abc=None, fixed=None) -> Branches:
    """x_b from invariant ``m`` at the points ``g (N, K, 3)`` before joint b (``t (N, K)``
    or ``(N, 1)``: the target's value of it, of the targets ``PT (N, K, 3)``); ``abc``: its
    coefficients there when already known (constants: ``fixed``, their
    :func:`~kincalc.subproblems.sp4.abc_constants`); a double root that folds the point onto
    a revolute axis a split (:func:`~kincalc.ik.pieces.split_fold`)."""
    b = P.joints[1]
    al, be, ga = _coefficients(S, P, g, m) if abc is None else abc
    scale = (S.scale + np.sqrt(np.abs(t))) ** 2
    if S.revolute[b]:
        sol = from_abc(be, ga, al, t, scale, fixed=fixed, free_reach=FREE_REACH)
        if S.revolute[P.joints[0]]:
            sol = split_fold(S, P.joints[0], b, sol, g, PT)
        if br.explain:      # the triangle's sides: o to the centre of g's circle, its radius
            br = br.dead_end(b, np.arctan2(ga, be),
                             (t - al) / np.maximum(np.hypot(be, ga), 1e-300),
                             ~sol.exact[..., 0] & br.ok, what)
            centre, e1, _ = _circle(S, b, g)
            sides = (np.sqrt(dot(centre - P.o, centre - P.o)), np.sqrt(dot(e1, e1)))
            br = note_equation(br, b, _measure(S, P, m), P.joints[0], be, ga, al, t, sides)
        return br.branch([b], sol)
    br = note_quadratic(br, b, _measure(S, P, m), P.joints[0], ga, be, al, t)
    return br.branch([b], quadratic(ga, be, al - t, scale, tangent=ROUNDING * scale),
                     labels=("-", "+"))


def _solve_a(S: Screws, P: Plan, br, g, f=None) -> Branches:
    """x_a: turn (or slide) the point before joint a, ``f (N, K, 3)`` (default: ``p0`` moved
    by the joints after a), onto the targets ``g (N, K, 3)``."""
    a = P.joints[0]
    if f is None:
        f = _point_before_a(S, P, br)
    if S.revolute[a]:
        x, y = f - S.point[a], g - S.point[a]
        sol = free_on_axis(S, sp1(x, y, S.axis[a]), x, y)
        br = note_turn(S, br, a, f, g)
        # f on axis a: the free angle turns f's way off it (as b moves) onto g's offset
        return br.set(a, *turn_free_joint(S, a, P.joints[1], f, g, sol),
                      free=sol.free[..., 0])
    x = dot(g - f, S.axis[a])
    br = note_slide(S, br, a, f, g)
    return br.set(a, x, np.ones_like(x), np.zeros_like(x))


def _measure(S: Screws, P: Plan, m: int) -> str:
    """What invariant ``m`` of joint a measures (``--explain``)."""
    return ("height", "distance2")[m] if S.revolute[P.joints[0]] else "across"


def _point_before_a(S: Screws, P: Plan, br):
    """``E_b(x_b) E_c(x_c) p0`` for every slot (N, K, 3)."""
    f = P.p0                                    # (moved into every slot by the first joint)
    for j in reversed(P.joints[1:]):
        f = S.move(j, br.value[j], br.cos[j], br.sin[j], f)
    return f


def _decoupled(S: Screws, P: Plan, br, PT, what) -> Branches:
    """One invariant free of x_b: x_c from it, x_b from the other, then x_a."""
    t = _invariants(S, P, PT)
    br = _solve_c(S, P, br, t[P.k], what)
    PT, t = br.take(PT), _carry(br, t[1 - P.k])
    b, c = P.joints[1], P.joints[2]
    g = S.move(c, br.value[c], br.cos[c], br.sin[c], P.p0)
    br = _solve_b(S, P, br, g, t, 1 - P.k, what, PT)
    f = S.move(b, br.value[b], br.cos[b], br.sin[b], br.take(g))
    return _solve_a(S, P, br, br.take(PT), f)


def _carry(br: Branches, x):
    """A quantity ``x (N, K_prev, ...)`` of the slots before the last step at the slots
    after it (:meth:`Branches.take`); one per pose (``(N, 1, ...)``) it stays so, and
    broadcasts against them."""
    return x if x.shape[1] == 1 else br.take(x)


def _shoulder(S: Screws, P: Plan, br, PT, what) -> Branches:
    """Offset shoulder: joint a (subproblem 4), c (subproblem 3), b (subproblem 1)."""
    a, b, c = P.joints
    w, h, kc = S.axis[a], S.axis[b], S.axis[c]
    oa = S.point[a]
    fx = S.constant(("shoulder", P.joints, tuple(P.p0.tolist())),
                   lambda: _shoulder_constants(S, P))
    # joint a: the height along h is the elbow's own: h . R(w, -x_a) (pt - oa) = h . (p0 - oa)
    p = PT - oa
    first = sp4(h, p, w, fx.height, fixed=fx.first).negated()
    if br.explain:          # h . R(w, -x) p = cos x (h.p - (h.w)(w.p)) - sin x h.(w x p) + ...
        hw = h @ w
        A, B, C = p @ h - hw * (p @ w), -(cross(w, p) @ h), hw * (p @ w)
        br = br.dead_end(a, np.arctan2(B, A), (fx.height - C) / np.maximum(np.hypot(A, B),
                                                                           1e-300),
                         ~first.exact[..., 0] & br.ok, what)
        br = note_equation(br, a, "height", b, A, B, C, fx.height)
    # q came from the target, rounded to its size: a stretched or folded elbow within
    # that rounding is the double root itself
    reach = (S.scale + np.sqrt(dot(p, p))) ** 2
    br = br.branch([a], first)
    # the target seen before joint a, in the plane normal to h
    pt, reach = br.take(p), _carry(br, reach)
    q = S.turn(a, br.cos[a], br.sin[a], pt, back=True) + fx.b_to_a
    q = q - dot(q, h)[..., None] * h
    u, v = fx.u, fx.v
    # joint c: |u + R(h, x_c) v| = |q| (law of cosines: subproblem 3, whose vectors are the
    # robot's, only |q| varies)
    third = sp3(v, -u, kc, np.sqrt(dot(q, q)), scale=reach, fixed=fx.third)
    if br.explain:          # |u + R v|^2 = |u|^2 + |v|^2 + 2 cos x u.v + 2 sin x u.(k x v)
        A, B, C = 2 * (u @ v), 2 * (u @ np.cross(kc, v)), u @ u + v @ v
        br = br.dead_end(c, np.arctan2(B, A), (dot(q, q) - C) / max(np.hypot(A, B), 1e-300),
                         ~third.exact[..., 0] & br.ok, what)
        br = note_equation(br, c, "distance2", b, A, B, C, dot(q, q),
                           (np.sqrt(u @ u), np.sqrt(v @ v)))
    br = br.branch([c], third)
    q = br.take(q)
    elbow = u + S.turn(c, br.cos[c], br.sin[c], v)
    second = sp1(elbow, q, h)
    if br.explain:
        ob = S.point[b]
        br = note_turn(S, br, b, elbow + ob, q + ob)
    return br.set(b, second.theta[0][..., 0], second.c[0][..., 0], second.s[0][..., 0],
                  free=second.free[..., 0])


class _ShoulderConstants(NamedTuple):
    """What :func:`_shoulder` needs of the robot alone (world frame at q = 0, m)."""

    height: float       # h . (p0 - o_a): the elbow's height along the parallel axes h
    b_to_a: np.ndarray  # (3,) o_a - o_b
    u: np.ndarray       # (3,) o_b to o_c, across h
    v: np.ndarray       # (3,) o_c to p0, across h
    first: tuple        # sp4_constants(h, w): joint a's subproblem 4 (w its axis)
    third: tuple        # sp3_constants(v, -u, kc): joint c's subproblem 3


def _shoulder_constants(S: Screws, P: Plan) -> _ShoulderConstants:
    """:class:`_ShoulderConstants` of the offset shoulder ``P``."""
    a, b, c = P.joints
    h, kc = S.axis[b], S.axis[c]
    oa, ob, oc = S.point[a], S.point[b], S.point[c]
    u, v = (oc - ob) - ((oc - ob) @ h) * h, (P.p0 - oc) - ((P.p0 - oc) @ h) * h
    return _ShoulderConstants(h @ (P.p0 - oa), oa - ob, u, v, sp4_constants(h, S.axis[a]),
                              sp3_constants(v, -u, kc))


def _three_cones(S: Screws, P: Plan, br, PT, what) -> Branches:
    """Three revolute joints: subproblem 5 on ``R_a^T (pt - o_a) = (o_b - o_a) +
    R_b ((o_c - o_b) + R_c (p0 - o_c))``. (No dead end is recorded: the roots come from
    a quartic, not from one joint's ``cos(x - phase) = need``.)"""
    a, b, c = P.joints
    oa, ob, oc = S.point[a], S.point[b], S.point[c]
    sol = sp5(-(ob - oa), PT - oa, oc - ob, P.p0 - oc, S.axis[a], S.axis[b], S.axis[c])
    sol = sol.negated(0).ordered()              # root k: the k-th smallest joint a
    br = br.branch([a, b, c], sol, labels=tuple(f"root {i + 1}" for i in range(4)))
    PT = br.take(PT)
    br, held = hold_on_target_axis(S, P.joints, br, PT)
    return polish_points(S, P.joints, P.p0, br, PT, held=held)


def _resultant(S: Screws, P: Plan, br, PT, what) -> Branches:
    """Eliminate x_b: the resultant in x_c, sampled and solved per target; then x_b by
    back-substitution, x_a, and Gauss-Newton. (No dead end is recorded: the roots come
    from a polynomial, not from one joint's ``cos(x - phase) = need``.)"""
    a, b, c = P.joints
    al_s, be_s, ga_s = S.constant(                                         # (2, m)
        ("resultant samples", P.joints, tuple(P.p0)),
        lambda: _coefficients(S, P, S.move_point(c, samples(S, c), P.p0)))
    t = _targets(S, P, PT)                                                 # (N, K, 2)
    al = al_s[:, None, None, :] - np.moveaxis(t, -1, 0)[..., None]          # (2, N, K, m)
    linear = np.abs(ga_s).max(-1) <= 1e-12 * max(np.abs(be_s).max(), 1e-300)
    R = eliminate(S.revolute[b], al, be_s[:, None, None, :], ga_s[:, None, None, :], linear)

    def resample(xc, slots):
        """The resultant at joint c's values ``xc (r, m')`` of the ``slots (N, K)``."""
        al, be, ga = _coefficients(S, P, S.move_point(c, xc, P.p0))      # (2, r, m')
        return eliminate(S.revolute[b], al - np.moveaxis(t[slots], -1, 0)[..., None], be, ga,
                         linear)
    br = br.branch([c], roots_in_c(S, c, R, resample))
    PT, t = br.take(PT), br.take(t)
    g = S.move(c, br.value[c], br.cos[c], br.sin[c], P.p0)
    al, be, ga = _coefficients(S, P, g)
    al = al - np.moveaxis(t, -1, 0)
    if S.revolute[b]:
        # both roots of the invariant that depends on x_b the most, not (cos, sin) from the
        # two together: they barely differ where axes a and b are nearly parallel, and the
        # two elbows there share a double root in x_c (the second root: TIE_BREAK)
        units = (S.scale, S.scale ** 2 if S.revolute[a] else S.scale)   # height, |f - o|^2
        br = br.branch([b], shared_roots(be, ga, al, units), (None, TIE_BREAK),
                       least_squares=True)
        PT = br.take(PT)
    else:
        x, good = common_root(al, be, ga)
        br = br.set(b, x, np.ones_like(x), np.zeros_like(x), ok=good)
    br, held = hold_on_target_axis(S, P.joints, _solve_a(S, P, br, PT), PT)
    br = polish_points(S, P.joints, P.p0, br, PT, held=held)
    return free_on_placed_axis(S, P.joints, P.p0, br, PT) if S.revolute[b] else br


def _pair(S: Screws, P: Plan, br, PT, what) -> Branches:
    """Two joints: x_b from the invariants, then x_a."""
    if P.both:                             # the point is p0 itself: its coefficients are
        t = _invariants(S, P, PT)          # constants; both fix (cos x_b, sin x_b)
        (a0, b0, g0), (a1, b1, g1) = P.at_p0
        a0, a1 = a0 - t[0], a1 - t[1]
        D = b0 * g1 - b1 * g0
        theta, c, s = angles((-a0 * g1 + a1 * g0) / D, (-b0 * a1 + b1 * a0) / D)
        br = br.set(P.joints[1], theta, c, s)
    else:
        t = _invariants(S, P, PT, P.k)
        br = _solve_b(S, P, br, P.p0, t, P.k, what, PT, P.at_p0[P.k], P.abc_fixed)
    return _solve_a(S, P, br, br.take(PT))


#: the steps of each mode of :class:`Plan`
_MODES = {"decoupled": _decoupled, "shoulder": _shoulder, "three cones": _three_cones,
          "resultant": _resultant, "pair": _pair}
