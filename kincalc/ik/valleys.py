"""The broken continua of a robot only nearly of its family: their roots, traced.

At a pose where the nearest structured robot is singular (a spherical wrist at q5 = 0, a
three-parallel arm with axis 6 along its parallel axes), that robot reaches the pose along
a continuum, a closed curve of configurations. A robot a defect ``d`` away from it reaches
the pose only at isolated points of a curve next to it; elsewhere on that curve it misses by
about ``d`` times the arm's size. Newton's method stalls along such a curve (the Jacobian is
nearly singular along it) and the general 6R elimination places its roots there poorly, so
the candidates on it reach the pose only to the defect, and the configuration the pose came
from can be missing among them. This module follows the curve from such a candidate and
returns its roots.

* **The curve.** With the Jacobian ``A = U S V^T`` (scaled as :mod:`kincalc.ik.refine`'s
  equations: lengths divided by the arm's size), it is the set of configurations where the
  residual ``e`` has no component along the five largest singular directions,
  ``U5^T e = 0``: five equations in six unknowns. It is followed by steps of :data:`STEP`
  rad along its tangent (the right singular vector of the smallest singular value), each
  corrected back onto it by Gauss-Newton on the five equations (the truncated
  pseudo-inverse), until it closes on its start, ends, or :data:`MAX_STEPS`; an open trace
  is followed the other way from its start too.
* **The roots.** On the curve the residual is ``g u``, ``u`` the left singular vector of the
  smallest singular value (its sign kept continuous along the curve). A solution is a zero
  of ``g``: a change of sign between two steps brackets one; where ``|g|`` dips between
  two steps without changing sign, the bottom of the dip (a golden-section search) either
  lies beyond zero, and brackets two roots, or touches it, a double root. The Illinois
  regula falsi on the chord of a bracket places a root, and Newton's method on the whole
  pose (:func:`~kincalc.ik.refine.refine`) polishes it to rounding where it can. Beside a
  root at a step (a start is a candidate, often a root) g is read just off it, and a small
  closed curve is traced again in :data:`MIN_POINTS` steps; each candidate the answer
  replaces has the zero of g next to it found along the curve (the general 6R elimination
  places every root roughly, where the steps may pass two at once).
* **The answer.** On a broken continuum (a closed curve along which ``|g|`` stays small)
  the candidates are replaced by the curve's roots, one per root: two roots between which
  the curve reaches the pose to rounding are one (the defect leaves them no better placed).
  Elsewhere (an ordinary singular configuration) the roots found are added and nothing is
  dropped.

Every array holds one configuration per row, and each row's values do not depend on the
other rows (per-matrix SVDs and products): a pose's roots are the same alone and in a batch.
Inside, a slide's value is divided by the arm's size, so that steps and distances in the
joints' space (rad) weigh every joint alike; the caller, :mod:`kincalc.ik.nearly`, traces
six-joint robots given a whole pose.
"""

from __future__ import annotations

import numpy as np

from ..spatial import wrap
from ..tolerances import NEAR_MISS, SAME_DOUBLE_ROOT
from .joint_limits import joint_scale
from .refine import linearised, refine

#: a candidate is traced when the smallest singular value of its scaled Jacobian is at most
#: this times the largest (at a broken continuum it is about the defect) ...
VALLEY = 1e-5
#: ... and it reaches its pose to NEAR_MISS of the arm's size (rad): it lies on the curve.
#: A traced candidate that reaches it only to more than this is a point of the curve where
#: Newton's method stalled, not a solution, and gives way to the curve's roots
STALLED = 1e-14
#: two roots of a curve closer than this (rad, every joint) may be one (:func:`_one_per_root`)
SAME_ROOT = 1e-2
#: a traced curve is a broken continuum when it closes and ``|g|`` stays within this
#: (scaled) all along it; elsewhere (an ordinary singular configuration, a double root where two
#: branches meet) its roots are added and no candidate is dropped
BROKEN = 1e-4
#: a zero of g is kept as a root when it reaches the pose to this (scaled): a root is a
#: solution to rounding (a double root's to some 1e-15); a change of sign that is no root
#: (the curve's singular directions swapping, where two of them come close) ends above it
ROOT = 1e-13
#: the predictor's step along the tangent (rad, the joints' space)
STEP = 0.2
#: steps at most in each direction (a curve of 80 rad), and at least around a closed curve (a
#: small one is traced again with a step that makes them: its roots lie closer together)
MAX_STEPS = 400
MIN_POINTS = 32
#: corrector iterations per step, its convergence (the five components, scaled) and the
#: residual beyond which the curve is lost (it ends, or turns more sharply than a step)
CORRECTIONS = 5
#: ... and along the trace, where only the sign of g is read (off the curve by ``r``, g is
#: off by about ``r`` times its slope, some defects smaller)
TRACE_CORRECTIONS = 3
ON_CURVE = 1e-16
LOST = 1e-8
#: Illinois iterations per root at most
ILLINOIS = 20
#: 1 / the golden ratio, and the golden-section steps of a dip of g (its interval of two steps
#: shrinks to 1e-4 of itself)
INV_PHI = 0.5 * (5 ** 0.5 - 1)
GOLDEN = 20


def broken_continua(robot, T, q, candidate, q_more, more) -> tuple:
    """The roots of the curves through the candidates ``q[candidate]`` and ``q_more[more]``,
    and which of the candidates they replace.

    Parameters
    ----------
    robot : Robot
        The robot as given, six joints.
    T : ndarray (N, 4, 4)
        The target poses ``T_world_tool`` (world frame, m).
    q : ndarray (N, K, n)
        Candidates (rad / m), refined on ``robot``.
    candidate : ndarray (N, K) of bool
        The slots that hold one.
    q_more, more : ndarray (N, K', n), (N, K') of bool
        More starting points (rad / m), not candidates themselves.

    Returns
    -------
    replaced : ndarray (N, K) of bool
        Candidates on a broken continuum, to be dropped: those that reach their pose only to
        more than :data:`STALLED` are points of the curve where Newton's method stalled, and
        the others are among the roots.
    roots : ndarray (N, R, n)
        Each pose's roots of the curves traced (rad, wrapped / m): the zeros of g found along
        them (the module docstring) and the candidates on a broken continuum that reach the
        pose to STALLED, one per root (:func:`_one_per_root`).
    ok : ndarray (N, R) of bool
        The roots that hold one.
    """
    N, K, n = q.shape
    L = max(robot.characteristic_length, 1e-12)
    Q = np.concatenate([q, q_more], axis=1) / joint_scale(robot)          # scaled: slides over L
    seed = np.concatenate([candidate, more], axis=1)
    replaced = np.zeros(seed.shape, bool)
    found = [[] for _ in range(N)]
    at = np.nonzero(seed)
    if len(at[0]):
        A, e = _linearised(robot, Q[at], T[at[0]], L)
        s = np.linalg.svd(A, compute_uv=False)
        reach = np.maximum.reduce(np.abs(e), axis=-1)
        on = (s[:, -1] <= VALLEY * s[:, 0]) & (reach <= NEAR_MISS)
        valley = np.zeros(seed.shape, bool)
        valley[at[0][on], at[1][on]] = True
        residual = np.zeros(seed.shape)
        residual[at] = reach
        todo = valley.copy()
        while np.count_nonzero(todo):
            rows = np.nonzero(todo.any(1))[0]
            first = todo[rows].argmax(1)                         # each pose's next start
            paths, roots, broken = _loops(robot, T[rows], Q[rows, first], L)
            for i, t in enumerate(rows.tolist()):
                found[t] += roots[i]
                on_it = _covered(robot, paths[i], Q[t]) & valley[t]
                on_it[first[i]] = True
                if broken[i]:
                    mine = on_it.copy()
                    mine[K:] = False
                    replaced[t] |= mine
                    found[t] += list(Q[t, mine & (residual[t] <= STALLED)])
                todo[t] &= ~on_it
        # a replaced candidate lies next to a root of its curve (the general 6R elimination
        # places every root roughly), which the trace's steps may have passed between two
        # others: the zero of g next to each, found along the curve
        t, k = np.nonzero(replaced & (residual > STALLED))
        if len(t):
            y, reach = _zero_nearby(robot, T[t], Q[t, k], L)
            for i in np.nonzero(reach <= ROOT)[0].tolist():
                found[t[i]].append(y[i])
    found = [_one_per_root(robot, T[t], f, L) if len(f) > 1 else f
             for t, f in enumerate(found)]
    R = max([len(f) for f in found] + [0])
    roots = np.zeros((N, R, n))
    ok = np.zeros((N, R), bool)
    for t, f in enumerate(found):
        if f:
            roots[t, :len(f)] = f
            ok[t, :len(f)] = True
    return replaced[:, :K], _unscaled(robot, roots), ok


def _one_per_root(robot, T, roots, L) -> list:
    """``roots`` (``(n,)`` each) with those that are one root dropped: two within
    :data:`SAME_ROOT` of each other (rad) are one where the curve halfway between them
    reaches the pose to :data:`STALLED`, or about as closely as the worse of the two (a
    double root, a stretch of the curve flat to rounding, or a root placed only to 1e-14: no
    value between them is better than another), and two within ``SAME_DOUBLE_ROOT`` always
    (:mod:`kincalc.tolerances`: where Newton's copies of a double root stop); the one that
    reaches closer stays."""
    R = np.array(roots)
    reach = np.maximum.reduce(np.abs(_linearised(robot, R, np.broadcast_to(T, (len(R), 4, 4)),
                                                L)[1]), axis=-1)
    kept = []
    for i in np.argsort(reach, kind="stable").tolist():
        d = [np.abs(_diff(robot, R[i], R[k])).max() for k in kept]
        if any(x <= SAME_DOUBLE_ROOT for x in d):       # Newton's copies of one double root
            continue
        near = [k for k, x in zip(kept, d) if x <= SAME_ROOT]
        if near:
            mid = R[near] + 0.5 * _diff(robot, R[i], R[near])
            _, e, _, _, _ = _corrected(robot, np.broadcast_to(T, (len(mid), 4, 4)), mid, L)
            if np.count_nonzero(np.maximum.reduce(np.abs(e), axis=-1)
                                <= max(STALLED, 2.0 * reach[i])):
                continue
        kept.append(i)
    return [R[i] for i in sorted(kept)]


def _zero_nearby(robot, T, y, L, reach: float = 0.1, iterations: int = 16):
    """The zero of ``g`` next to each point ``y (m, n)`` of a curve, by the secant method on
    the distance along the curve's tangent at ``y`` (each point of that line corrected onto
    the curve), within ``reach`` rad. Returns the points ``(m, n)`` and how closely each
    reaches its pose ``(m,)`` (scaled)."""
    y0, e0, u0, v0, _ = _corrected(robot, T, y, L)
    s0, g0 = np.zeros(len(y)), _dot(u0, e0)
    s1 = np.full(len(y), 1e-3)
    y1, e1, u1, _, _ = _corrected(robot, T, y0 + s1[:, None] * v0, L)
    g1 = _dot(u1, e1) * np.where(_dot(u1, u0) < 0, -1.0, 1.0)
    best, gbest = np.where((np.abs(g1) < np.abs(g0))[:, None], y1, y0), np.minimum(
        np.abs(g0), np.abs(g1))
    for _ in range(iterations):
        live = (g1 != g0) & (gbest > 0)
        if not np.count_nonzero(live):
            break
        s2 = np.where(live, s1 - g1 * (s1 - s0) / np.where(live, g1 - g0, 1.0), s1)
        s2 = np.clip(s2, -reach, reach)
        y2, e2, u2, _, _ = _corrected(robot, T, y0 + s2[:, None] * v0, L)
        g2 = _dot(u2, e2) * np.where(_dot(u2, u0) < 0, -1.0, 1.0)
        better = live & (np.abs(g2) < gbest)
        best[better], gbest[better] = y2[better], np.abs(g2[better])
        s0, g0, s1, g1 = s1, g1, s2, g2
    return best, np.maximum.reduce(np.abs(_linearised(robot, best, T, L)[1]), axis=-1)


def _covered(robot, path, q) -> np.ndarray:
    """``(K,)`` bool: the configurations ``q (K, n)`` within three quarters of a step of a
    point of ``path (S, n)`` (rad, wrapped differences): on the curve, between two of its
    points."""
    if not len(path):
        return np.zeros(len(q), bool)
    d = np.abs(_diff(robot, q[:, None, :], path[None, :, :])).max(-1)
    return d.min(1) < 0.75 * STEP


def _loops(robot, T, y0, L) -> tuple[list, list, np.ndarray]:
    """The curves through ``y0 (m, n)`` (targets ``T (m, 4, 4)``): per start, the points
    visited ``(S, n)``, the list of roots found (``(n,)`` each, rad), and whether the curve
    is a broken continuum ``(m,)``: it closed on its start, and ``g`` stays within
    :data:`BROKEN` all along it."""
    paths = [[] for _ in range(len(y0))]
    roots = [[] for _ in range(len(y0))]
    go = np.ones(len(y0), bool)
    broken = np.zeros(len(y0), bool)
    for direction in (1.0, -1.0):
        rows = np.nonzero(go)[0]
        if not len(rows):
            break
        Y, G, U, count, closed, far = _trace(robot, T[rows], y0[rows], L, direction)
        short = closed & (count < MIN_POINTS)
        if np.count_nonzero(short):             # a small loop: again, in MIN_POINTS steps
            i = np.nonzero(short)[0]
            again = _trace(robot, T[rows[i]], y0[rows[i]], L, direction,
                           STEP * count[i] / MIN_POINTS)
            for x, y in zip((Y, G, U, count, closed, far), again):
                x[i] = y
        if direction > 0:
            broken = closed & ~far
        b, k = _brackets(G, count, closed)
        last = count[b] - 1
        k1 = np.where(k == last, 0, k + 1)                      # the closing chord: to the start
        ya = Y[b, k]
        yb = ya + _diff(robot, Y[b, k1], ya)
        b2, ya2, yb2, ga2, gb2, ua2 = _near_doubles(robot, T[rows], Y, G, U, count, closed, L)
        b = np.concatenate([b, b2])
        if len(b):
            y, reach = _root(robot, T[rows[b]], np.concatenate([ya, ya2]),
                             np.concatenate([yb, yb2]), np.concatenate([G[b[:len(k)], k], ga2]),
                             np.concatenate([G[b[:len(k)], k1], gb2]),
                             np.concatenate([U[b[:len(k)], k], ua2]), L)
            for i, r in zip(b[reach <= ROOT].tolist(), y[reach <= ROOT]):
                roots[rows[i]].append(r)
        for i, r in enumerate(rows.tolist()):
            paths[r].append(Y[i, :count[i]])
        go[rows[closed | far]] = False
    return ([np.concatenate(p) if p else np.zeros((0, y0.shape[1])) for p in paths], roots,
            broken)


def _brackets(G, count, closed) -> tuple[np.ndarray, np.ndarray]:
    """``(trace, step)`` of every change of sign of ``g`` between step ``k`` and the next
    (the start, after the last step of a closed trace); a zero at a step counts once."""
    k, last, _, nxt = _neighbours(count, G.shape[1])
    valid = (k < last) | ((k == last) & closed[:, None])
    change = valid & (G != 0) & (G * np.take_along_axis(G, nxt, 1) <= 0)
    change[:, 0] |= (G[:, 0] == 0) & (count > 0)                  # the start itself a root
    return np.nonzero(change)


def _neighbours(count, S: int) -> tuple:
    """Of traces of ``count (m,)`` steps stored in ``S`` columns: each step's index ``(1,
    S)``, each trace's last step ``(m, 1)``, and the steps before and after each step ``(m,
    S)`` around a closed trace (the start follows the last; beyond the last, the start)."""
    k = np.arange(S)[None, :]
    last = (count - 1)[:, None]
    return k, last, np.where(k == 0, last, k - 1), np.where(k >= last, 0, k + 1)


def _dip_bottom(robot, T, y0, chord, ua, side, L, iterations: int = GOLDEN):
    """Where ``side g`` is least on the curve between ``y0`` and ``y0 + chord (b, n)`` (the
    chord's points corrected onto the curve; ``g`` measured along ``ua (b, 6)``): a
    golden-section search on the chord. Returns the point ``(b, n)`` and ``g`` there
    ``(b,)``."""
    def h(f):
        y, e, u, _, _ = _corrected(robot, T, y0 + f[:, None] * chord, L, TRACE_CORRECTIONS)
        return y, _dot(u, e) * np.where(_dot(u, ua) < 0, -1.0, 1.0)
    a, b = np.zeros(len(y0)), np.ones(len(y0))
    c, d = b - INV_PHI * (b - a), a + INV_PHI * (b - a)
    hc, hd = side * h(c)[1], side * h(d)[1]
    for _ in range(iterations):
        left = hc < hd                                   # the least lies in [a, d]
        a, b = np.where(left, a, c), np.where(left, d, b)
        x = np.where(left, b - INV_PHI * (b - a), a + INV_PHI * (b - a))
        hx = side * h(x)[1]
        c, d = np.where(left, x, d), np.where(left, c, x)
        hc, hd = np.where(left, hx, hd), np.where(left, hc, hx)
    return h(0.5 * (a + b))



def _near_doubles(robot, T, Y, G, U, count, closed, L):
    """Roots that no change of sign between two steps shows: two roots within one step, or
    a double root where ``g`` touches zero. At each step where ``|g|`` has a local minimum
    (along a closed trace, around its start too) with no change of sign beside it: a minimum
    within :data:`STALLED` is a root there; one below a quarter of the largest ``|g|`` of
    the trace has the bottom of its dip found between the steps beside it
    (:func:`_dip_bottom`): beyond zero, it brackets two roots; within STALLED, it is a
    double root. Returns ``(trace, ya, yb, ga, gb, ua)``: brackets (points ``(b, n)``,
    ``g`` at them ``(b,)`` measured along ``ua (b, 6)``), ``ga = 0`` for a root at ``ya``."""
    k, last, prev, nxt = _neighbours(count, G.shape[1])     # (an open trace's ends masked)
    gp, g, gn = np.take_along_axis(G, prev, 1), G, np.take_along_axis(G, nxt, 1)
    inside = (k <= last) & (closed[:, None] | ((k > 0) & (k < last)))
    low = inside & (np.abs(g) <= np.abs(gp)) & (np.abs(g) <= np.abs(gn)) & (gp * g > 0) & \
        (g * gn > 0)
    at_root = low & (np.abs(g) <= STALLED)
    dip = low & ~at_root & (np.abs(g) <= 0.25 * np.maximum.reduce(np.abs(G), axis=-1,
                                                                     keepdims=True))
    b0, k0 = np.nonzero(at_root)
    out = [(b0, Y[b0, k0], Y[b0, k0], np.zeros(len(b0)), np.ones(len(b0)), U[b0, k0])]
    # a root at a step (a start is a candidate, often one) hides g's sign there: the step
    # beside it may hold another root; g is read a hundredth of the way along each side
    b0, k0 = np.nonzero(inside & (np.abs(g) <= STALLED))
    for other, g_other in ((nxt, gn), (prev, gp)):
        yk = Y[b0, k0]
        far_end = yk + _diff(robot, Y[b0, other[b0, k0]], yk)
        y, e, u, _, _ = _corrected(robot, T[b0], yk + 0.01 * (far_end - yk), L, TRACE_CORRECTIONS)
        gs = _dot(u, e) * np.where(_dot(u, U[b0, k0]) < 0, -1.0, 1.0)
        i = np.nonzero(gs * g_other[b0, k0] < 0)[0]
        out.append((b0[i], y[i], far_end[i], gs[i], g_other[b0[i], k0[i]], U[b0[i], k0[i]]))
    b, j = np.nonzero(dip)
    if len(b):
        y0 = Y[b, j] + _diff(robot, Y[b, prev[b, j]], Y[b, j])
        chord = _diff(robot, Y[b, nxt[b, j]], Y[b, j]) + (Y[b, j] - y0)
        side = np.sign(g[b, j])
        ys, gs = _dip_bottom(robot, T[b], y0, chord, U[b, j], side, L)
        cross = gs * side < 0                            # two roots, one on each side
        i = np.nonzero(cross)[0]
        out.append((np.r_[b[i], b[i]], np.r_[y0[i], ys[i]], np.r_[ys[i], y0[i] + chord[i]],
                    np.r_[gp[b[i], j[i]], gs[i]], np.r_[gs[i], gn[b[i], j[i]]],
                    np.r_[U[b[i], j[i]], U[b[i], j[i]]]))
        i = np.nonzero(~cross & (np.abs(gs) <= STALLED))[0]        # touches zero: a double root
        out.append((b[i], ys[i], ys[i], np.zeros(len(i)), np.ones(len(i)), U[b[i], j[i]]))
    return tuple(np.concatenate([o[x] for o in out]) for x in range(6))


def _trace(robot, T, y0, L, direction, step=STEP):
    """Follow the curves from ``y0 (m, n)``: points ``Y (m, S, n)``, ``g`` there ``G (m, S)``,
    the left singular vectors ``U (m, S, 6)`` it was measured along, the points per trace
    ``count (m,)``, whether each closed on its start ``(m,)``, and whether it was left where
    ``|g|`` exceeded :data:`BROKEN` ``(m,)`` (no broken continuum). A step the corrector does
    not bring back onto the curve is halved, down to a sixteenth of ``step`` (rad; one per
    start, or one for all), before the trace ends there."""
    m, n = y0.shape
    S = MAX_STEPS + 1
    Y, G, U = np.zeros((m, S, n)), np.zeros((m, S)), np.zeros((m, S, 6))
    closed, far = np.zeros(m, bool), np.zeros(m, bool)
    y, e, u, v, lost = _corrected(robot, T, y0, L)
    big = np.abs(v).argmax(-1)                     # a deterministic first direction
    v *= direction * np.sign(v[np.arange(m), big])[:, None]
    live = ~lost
    count = live.astype(int)
    Y[:, 0], G[:, 0], U[:, 0] = y, _dot(u, e), u
    full = np.broadcast_to(np.asarray(step, float), (m,))
    h = full.copy()
    bend = np.zeros((m, n))                        # the tangent's turn per rad: the predictor's
    for _ in range(4 * MAX_STEPS):
        rows = np.nonzero(live)[0]
        if not len(rows):
            break
        hr = h[rows, None]
        yk, ek, uk, vk, lostk = _corrected(robot, T[rows], y[rows] + hr * v[rows]
                                           + 0.5 * hr * hr * bend[rows], L, TRACE_CORRECTIONS)
        h[rows[lostk]] *= 0.5
        live[rows[lostk & (h[rows] < full[rows] / 16)]] = False
        rows, yk, ek, uk, vk = rows[~lostk], yk[~lostk], ek[~lostk], uk[~lostk], vk[~lostk]
        uk *= np.where(_dot(uk, u[rows]) < 0, -1.0, 1.0)[:, None]
        vk *= np.where(_dot(vk, v[rows]) < 0, -1.0, 1.0)[:, None]
        bend[rows] = (vk - v[rows]) / h[rows, None]
        y[rows], u[rows], v[rows], h[rows] = yk, uk, vk, full[rows]
        k = count[rows]
        Y[rows, k], G[rows, k], U[rows, k] = yk, _dot(uk, ek), uk
        count[rows] += 1
        home = (k >= 4) & (np.abs(_diff(robot, yk, Y[rows, 0])).max(-1) < 0.75 * full[rows])
        closed[rows[home]] = True
        far[rows[np.abs(G[rows, k]) > BROKEN]] = True
        live[rows[home | (count[rows] == S)]] = False
        live &= ~far
    return Y, G, U, count, closed, far


def _corrected(robot, T, y, L, iterations: int = CORRECTIONS):
    """Points ``y (m, n)`` moved onto the curve: ``(y, e, u, v, lost)``, the residual
    ``e (m, 6)`` there, the left and right singular vectors of the smallest singular value
    ``u (m, 6)``, ``v (m, n)``, and where the corrector did not converge ``(m,)``. A point
    stops once its five components are below :data:`ON_CURVE` or no longer halve (rounding)."""
    y = np.array(y, float)
    best = np.full(len(y), np.inf)
    go = np.ones(len(y), bool)
    for it in range(iterations + 1):
        A, e = _linearised(robot, y, T, L)
        Uf, s, Vt = np.linalg.svd(A)
        f = (e[:, None, :] @ Uf[:, :, :-1])[:, 0]                 # U5^T e, (m, 5)
        r = np.maximum.reduce(np.abs(f), axis=-1)
        go &= (r > ON_CURVE) & (r < 0.5 * best)
        best = np.minimum(best, r)
        if it == iterations or not np.count_nonzero(go):
            break
        step = ((f / s[:, :-1])[:, None, :] @ Vt[:, :-1])[:, 0]
        y = y + np.where(go[:, None], step, 0.0)
    return y, e, Uf[:, :, -1], Vt[:, -1], r > LOST


def _root(robot, T, ya, yb, ga, gb, ua, L) -> np.ndarray:
    """The zeros of ``g`` between the curve's points ``ya`` and ``yb (b, n)`` (``g`` of
    opposite signs there, measured along ``ua (b, 6)``; ``ga = 0``: at ``ya``), polished on
    the whole pose: ``(b, n)`` (rad), and how closely each reaches it ``(b,)`` (scaled)."""
    sa, sb = np.zeros(len(ya)), np.ones(len(ya))
    fa, fb = np.array(ga, float), np.array(gb, float)
    side = np.zeros(len(ya))
    y = np.where((fa == 0)[:, None], ya, yb)
    live = (fa != 0) & (fb != 0)
    for _ in range(ILLINOIS):
        rows = np.nonzero(live)[0]
        if not len(rows):
            break
        sc = (sa[rows] * fb[rows] - sb[rows] * fa[rows]) / (fb[rows] - fa[rows])
        yc, ec, uc, _, _ = _corrected(robot, T[rows],
                                      ya[rows] + sc[:, None] * (yb[rows] - ya[rows]), L)
        fc = _dot(uc, ec) * np.where(_dot(uc, ua[rows]) < 0, -1.0, 1.0)
        y[rows] = yc
        right = fc * fb[rows] > 0                    # the root lies between a and c
        ra, rb = rows[~right], rows[right]
        fa[rb[side[rb] == -1]] *= 0.5                # (Illinois: halve the end kept twice)
        sb[rb], fb[rb], side[rb] = sc[right], fc[right], -1
        fb[ra[side[ra] == 1]] *= 0.5
        sa[ra], fa[ra], side[ra] = sc[~right], fc[~right], 1
        live[rows[(fc == 0) | ((sb[rows] - sa[rows]) * STEP < 1e-13)]] = False
    # Newton's method on the whole pose takes a root to rounding where it is well placed;
    # along a flat stretch of g its step (g over the smallest singular value) may wander
    # off: the better of the two is kept
    polished = refine(robot, y * joint_scale(robot), T, mode="pose") / joint_scale(robot)
    before, after = (np.maximum.reduce(np.abs(_linearised(robot, x, T, L)[1]), axis=-1)
                     for x in (y, polished))
    better = after < before
    return np.where(better[:, None], polished, y), np.where(better, after, before)


def _linearised(robot, y, T, L):
    """:func:`~kincalc.ik.refine.linearised` on the pose at the scaled joints ``y (m, n)``:
    ``(A (m, 6, n), e (m, 6))``, the columns of slides scaled as their variables."""
    A, e = linearised(robot, y * joint_scale(robot), T, L)
    return A * joint_scale(robot), e


def _diff(robot, a, b) -> np.ndarray:
    """``a - b`` of scaled joints, revolute ones wrapped to (-pi, pi]."""
    return np.where(robot.is_revolute, wrap(a - b), a - b)


def _unscaled(robot, y) -> np.ndarray:
    """Scaled joints ``y (..., n)`` in rad / m, revolute ones wrapped."""
    q = y * joint_scale(robot)
    return np.where(robot.is_revolute, wrap(q), q)


def _dot(a, b) -> np.ndarray:
    """Row-wise dot products of ``a, b (m, k)``, summed along the components in order."""
    out = a[:, 0] * b[:, 0]
    for i in range(1, a.shape[1]):
        out += a[:, i] * b[:, i]
    return out
