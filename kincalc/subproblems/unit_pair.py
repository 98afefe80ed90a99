"""Shared core of subproblems 5 and 6: two unit vectors under two linear equations.

Find angles ``(t1, t2)`` with ::

    M @ [cos t1, sin t1, cos t2, sin t2] = b,        M (..., 2, 4), b (..., 2)

i.e. a point ``x = (u1, u2)`` of the torus ``|u1| = |u2| = 1`` on a 2-plane of R^4:
the two-ellipse intersection of Elias & Wen (IK-Geo, arXiv:2211.05737, 2022,
subproblem 6), to which subproblem 5 reduces as well.

Method. With ``x0 = pinv(M) b`` and ``N`` (4, 2) an orthonormal basis of the null
space of ``M``, the solutions of the linear equations are ``x = x0 + N xi``; since
``x0`` is orthogonal to ``N``, ``|u1|^2 + |u2|^2 = 2`` is the circle ``|xi| = rho``,
``rho^2 = 2 - |x0|^2``. With ``xi = rho (cos phi, sin phi)`` the remaining condition
``|u1| = 1`` is a trigonometric polynomial of degree 2 in ``phi``, and with ``z =
exp(i phi)`` a quartic in ``z`` whose roots on the unit circle are the solutions (at
most four; no angle at which it degenerates, unlike ``tan(phi / 2)``). The roots come
from the eigenvalues of companion matrices, one per problem, then Newton's method on
``phi`` and Gauss-Newton on ``(t1, t2)``; a root is kept when it satisfies the
row-normalised equations to ``RESIDUAL_TOL``.

Ill-posed (``free``): an equation whose coefficients vanish (it holds for all angles
or for none), two equations with parallel coefficient rows (a curve of solutions, or
none), and ``|u1| = 1`` on the whole circle (a curve). Where the solutions form a
curve, one point of it is returned.
"""

from __future__ import annotations

import numpy as np

from ..spatial import wrap
from ..tolerances import GEOMETRY_TOL
from .roots import polynomial_roots
from .solutions import Solutions, principal
from .sp4 import ROUNDING

#: a returned solution satisfies the row-normalised equations to this
RESIDUAL_TOL = 1e-8
#: roots of the quartic in z kept for polishing: | |z| - 1 | below this (the residual
#: test decides; this only discards roots far from the unit circle)
_ROOT_BAND = 0.1
#: rho below which the circle of candidates is one point
_TINY_RHO = 1e-7
#: two solutions closer than this (rad, both angles) are one (:func:`solve`'s ``merge``)
SAME_ANGLE = 1e-6
#: slots per problem
SLOTS = 4


def solve(M, b, scale, *, tol: float = GEOMETRY_TOL, merge: float = SAME_ANGLE) -> Solutions:
    """Every ``(t1, t2)`` with ``M @ [cos t1, sin t1, cos t2, sin t2] = b``.

    Parameters
    ----------
    M : array_like (..., 2, 4)
        Coefficients; both rows in the unit of ``b``.
    b : array_like (..., 2)
        Right-hand sides (the leading shapes of ``M``, ``b``, ``scale`` broadcast).
    scale : array_like (...)
        Size of a typical coefficient: a row whose norm is below ``tol * scale`` is
        taken as identically zero.
    tol : float
        Relative tolerance of a vanishing row (of ``scale``) and of parallel rows (of
        the larger singular value of the row-normalised ``M``); also the tolerance of
        "``|u1| = 1`` on the whole circle".
    merge : float
        Two roots closer than this (rad, in both angles) are one: a double root, found
        twice; a root within rounding of a tangency is put on it (:func:`_tangent`). Two
        distinct roots next to a tangency are as close: 0 keeps every root as found.

    Returns
    -------
    Solutions
        Four slots; ``theta = (t1 (..., 4), t2 (..., 4))`` in rad, in (-pi, pi] (0
        where not ``ok``). ``ok (..., 4)``: the slot holds a solution satisfying the
        row-normalised equations to ``RESIDUAL_TOL`` (duplicates dropped; ``ok`` slots
        need not come first). ``exact`` is ``ok`` (no least-squares answer is given).
        ``free (..., 4)``, the same in every slot: the problem is ill-posed (a vanishing
        equation, parallel rows, a curve of solutions); one point of a curve is returned,
        or no slot is ``ok``.

    Raises
    ------
    ValueError
        When ``M`` is not ``(..., 2, 4)``, ``b`` not ``(..., 2)``, or the leading shapes
        do not broadcast.
    """
    M = np.asarray(M, float)
    b = np.asarray(b, float)
    scale = np.asarray(scale, float)
    # one geometry M may serve many right sides b (and the reverse)
    shape = np.broadcast_shapes(M.shape[:-2], b.shape[:-1], scale.shape)
    M = np.broadcast_to(M, shape + (2, 4)).reshape(-1, 2, 4)
    b = np.broadcast_to(b, shape + (2,)).reshape(-1, 2)
    scale = np.maximum(np.broadcast_to(scale, shape).reshape(-1), 1e-300)
    n = len(M)
    t = np.zeros((n, SLOTS, 2))
    ok = np.zeros((n, SLOTS), bool)
    free = np.zeros(n, bool)

    norms = np.sqrt((M * M).sum(-1))                                       # (n, 2)
    void = norms <= tol * scale[:, None]
    infeasible = (void & (np.abs(b) > np.sqrt(2.0) * norms + tol * scale[:, None])).any(-1)
    free |= void.any(-1)
    safe = np.where(void, 1.0, norms)
    Mn = np.where(void[..., None], 0.0, M / safe[..., None])
    bn = np.where(void, 0.0, b / safe)
    U, s, Vt = np.linalg.svd(Mn)
    both = ~void.any(-1)
    rank2 = both & (s[:, 1] > tol * s[:, :1].max(-1, initial=0.0)) & ~infeasible
    everything = void.all(-1) & ~infeasible            # no equation left: any angles
    ok[everything, 0] = True
    one = ~rank2 & ~everything & ~infeasible
    free |= one
    if one.any():
        t[one, 0], ok[one, 0] = _on_a_line(Mn[one], bn[one], U[one], s[one], Vt[one],
                                           both[one])
    if rank2.any():
        t[rank2], ok[rank2], free[rank2] = _general(Mn[rank2], bn[rank2], U[rank2],
                                                    s[rank2], Vt[rank2], tol, merge)
    t = np.where(ok[..., None], principal(t), 0.0)
    c, sn = np.cos(t), np.sin(t)
    frees = np.broadcast_to(free[:, None], ok.shape)
    return Solutions(tuple(t[..., j].reshape(shape + (SLOTS,)) for j in (0, 1)),
                     tuple(c[..., j].reshape(shape + (SLOTS,)) for j in (0, 1)),
                     tuple(sn[..., j].reshape(shape + (SLOTS,)) for j in (0, 1)),
                     ok.reshape(shape + (SLOTS,)), ok.reshape(shape + (SLOTS,)),
                     frees.reshape(shape + (SLOTS,)))


def _residual(M, b, t):
    """``(F0, F1)``, the rows of ``M x(t) - b`` for ``t (m, k, 2)``, each ``(m, k)``
    (``M (m, 2, 4)``, ``b (m, 2)``), by components."""
    c1, s1, c2, s2 = np.cos(t[..., 0]), np.sin(t[..., 0]), np.cos(t[..., 1]), np.sin(t[..., 1])
    m = M[:, None]                                                         # (m, 1, 2, 4)
    return tuple(m[..., i, 0] * c1 + m[..., i, 1] * s1 + m[..., i, 2] * c2 + m[..., i, 3] * s2
                 - b[:, i, None] for i in (0, 1))


def _gauss_newton(M, b, t, iters: int = 3):
    """Polish ``t (m, k, 2)`` on ``M x(t) = b`` (a square 2 x 2 system per root), by
    components; returns ``(t, largest residual (m, k))``."""
    F0, F1 = _residual(M, b, t)
    nF = np.maximum(np.abs(F0), np.abs(F1))
    m = M[:, None]                                                         # (m, 1, 2, 4)
    for _ in range(iters):
        c1, s1, c2, s2 = (np.cos(t[..., 0]), np.sin(t[..., 0]), np.cos(t[..., 1]),
                          np.sin(t[..., 1]))
        # row i's derivatives in t1 and t2
        j10, j11 = (m[..., i, 1] * c1 - m[..., i, 0] * s1 for i in (0, 1))
        j20, j21 = (m[..., i, 3] * c2 - m[..., i, 2] * s2 for i in (0, 1))
        det = j10 * j21 - j20 * j11
        # near a tangency the Jacobian is singular: keep the root as found
        good = (np.abs(det) > 1e-12 * np.maximum(1.0, j10 * j10 + j11 * j11 + j20 * j20
                                                 + j21 * j21)) & (nF >= 1e-15)
        det = np.where(good, det, 1.0)
        cand = np.empty_like(t)
        cand[..., 0] = t[..., 0] + (F1 * j20 - F0 * j21) / det
        cand[..., 1] = t[..., 1] + (F0 * j11 - F1 * j10) / det
        G0, G1 = _residual(M, b, cand)
        nG = np.maximum(np.abs(G0), np.abs(G1))
        better = good & (nG < nF)
        if not np.count_nonzero(better):    # (the next step would be this one again)
            break
        t = np.where(better[..., None], cand, t)
        F0, F1 = np.where(better, G0, F0), np.where(better, G1, F1)
        nF = np.where(better, nG, nF)
    return t, nF


def _closest_unit(a, e):
    """Unit 2-vectors ``u (m, 2)`` minimising ``|a . u - e|`` for ``a (m, 2)``, ``e (m,)``."""
    n = np.sqrt((a * a).sum(-1))
    zero = n == 0.0
    n = np.where(zero, 1.0, n)
    c = np.clip(e / n, -1.0, 1.0)
    s = np.sqrt(1.0 - c * c)
    u = (c[:, None] * a + s[:, None] * np.stack([-a[:, 1], a[:, 0]], -1)) / n[:, None]
    return np.where(zero[:, None], [1.0, 0.0], u)


def _on_a_line(Mn, bn, U, s, Vt, both):
    """One effective equation ``w . x = beta`` (a curve of solutions, or none): one
    representative ``(t (m, 2), ok (m,))``."""
    s0 = np.where(s[:, 0] > 0, s[:, 0], 1.0)
    # two parallel rows must agree; with one row dropped the other is the equation
    consistent = ~both | (np.abs((U[:, :, 1] * bn).sum(-1)) <= RESIDUAL_TOL)
    w = Vt[:, 0]
    beta = (U[:, :, 0] * bn).sum(-1) / s0
    u1 = _closest_unit(w[:, 0:2], beta)
    u2 = _closest_unit(w[:, 2:4], beta - (w[:, 0:2] * u1).sum(-1))
    t = np.stack([np.arctan2(u1[:, 1], u1[:, 0]), np.arctan2(u2[:, 1], u2[:, 0])], -1)
    F0, F1 = _residual(Mn, bn, t[:, None])
    res = np.maximum(np.abs(F0[:, 0]), np.abs(F1[:, 0]))
    return t, consistent & (res <= RESIDUAL_TOL)


def _general(Mn, bn, U, s, Vt, tol, merge):
    """Rank-2 problems: ``(t (m, 4, 2), ok (m, 4), free (m,))``."""
    x0 = np.einsum("mji,mj->mi", Vt[:, :2], np.einsum("mji,mj->mi", U, bn) / s)
    N = np.swapaxes(Vt[:, 2:], 1, 2)                                       # (m, 4, 2)
    rho2 = 2.0 - (x0 * x0).sum(-1)
    reach = rho2 >= -RESIDUAL_TOL
    rho = np.sqrt(np.maximum(rho2, 0.0))
    N1 = N[:, 0:2]
    P = np.einsum("mji,mjk->mik", N1, N1)
    q = np.einsum("mji,mj->mi", N1, x0[:, 0:2])
    r = (x0[:, 0:2] ** 2).sum(-1) - 1.0
    mu = 0.5 * (P[:, 0, 0] + P[:, 1, 1])
    circle = (np.maximum(np.maximum(np.abs(P[:, 0, 0] - mu), np.abs(P[:, 1, 1] - mu)),
                         np.abs(P[:, 0, 1])) <= tol) & (np.abs(q).max(-1) <= tol) & \
        (np.abs(r + mu * rho2) <= tol)
    point = rho < _TINY_RHO
    a0 = 0.5 * rho2 * (P[:, 0, 0] + P[:, 1, 1]) + r
    a1, b1 = 2 * rho * q[:, 0], 2 * rho * q[:, 1]
    a2, b2 = 0.5 * rho2 * (P[:, 0, 0] - P[:, 1, 1]), rho2 * P[:, 0, 1]
    phi, have = _quartic_phi(a0, a1, b1, a2, b2, tangent=merge > 0)           # (m, 4)
    single = point | circle
    phi = np.where(single[:, None], 0.0, phi)
    have = np.where(single[:, None], np.arange(4) == 0, have) & reach[:, None]
    x = x0[:, None, :] + rho[:, None, None] * np.einsum(
        "mij,mkj->mki", N, np.stack([np.cos(phi), np.sin(phi)], -1))      # (m, 4, 4)
    on_torus = (np.sqrt((x[..., 0:2] ** 2).sum(-1)) > 0.5) & \
        (np.sqrt((x[..., 2:4] ** 2).sum(-1)) > 0.5)
    t = np.stack([np.arctan2(x[..., 1], x[..., 0]), np.arctan2(x[..., 3], x[..., 2])], -1)
    t, res = _gauss_newton(Mn, bn, t)
    ok = have & on_torus & (res <= RESIDUAL_TOL)
    t = wrap(t)
    # one solution found twice (a double root) is one
    for j in range(1, SLOTS if merge > 0 else 1):
        for i in range(j):
            same = (np.abs(wrap(t[:, j] - t[:, i])) < merge).all(-1)
            ok[:, j] &= ~(same & ok[:, i])
    return t, ok, circle


def _quartic_phi(a0, a1, b1, a2, b2, tangent: bool = True):
    """Roots ``phi (m, 4)`` of ``a0 + a1 cos + b1 sin + a2 cos 2phi + b2 sin 2phi`` near the
    unit circle in ``z = e^(i phi)``, polished by Newton's method (and, with ``tangent``,
    put on a tangency within rounding: :func:`_tangent`); ``ok (m, 4)``."""
    coeffs = np.stack([(a2 - 1j * b2) / 2, (a1 - 1j * b1) / 2, a0 + 0j,
                       (a1 + 1j * b1) / 2, (a2 + 1j * b2) / 2], -1)        # z^4 .. z^0
    # a vanishing leading term: the quartic is of lower degree; its extra roots go far
    # from the unit circle and the band discards them
    z = polynomial_roots(coeffs)
    ok = np.isfinite(z) & (np.abs(np.abs(z) - 1.0) < _ROOT_BAND)
    phi = np.angle(np.where(ok, z, 1.0))
    A = (a0, a1, b1, a2, b2)
    A = tuple(v[:, None] for v in A)
    fv, d = _f_df(A, phi)
    for _ in range(4):
        good = d != 0.0
        cand = phi - fv / np.where(good, d, 1.0)
        fc, dc = _f_df(A, cand)
        better = good & (np.abs(fc) < np.abs(fv))
        if not np.count_nonzero(better):    # (the next step would be this one again)
            break
        phi = np.where(better, cand, phi)
        fv, d = np.where(better, fc, fv), np.where(better, dc, d)
    return (_tangent(A, phi) if tangent else phi), ok


def _tangent(A, phi):
    """The roots ``phi (m, 4)`` moved onto the double root next to them where ``f`` touches
    zero there to rounding (a tangency: the arm at a singularity).

    Newton's method on ``f`` converges there only to ~sqrt(rounding) (1.4e-8 rad; two copies
    either side, or one). The double root is the simple root ``d`` of ``f'``, found by
    Newton's method on it to rounding; a root is moved there where ``|f(d)|`` is within the
    rounding of ``f`` (its terms are parts of ``|x|^2 = 2``; subproblem 4's
    :data:`~kincalc.subproblems.sp4.ROUNDING`) and ``phi`` no farther from ``d`` than the
    roots such a rounding splits a double root into, ``sqrt(2 band / |f''|)`` (twice that,
    for the roots' own error). Simple roots keep their values.
    """
    d = phi
    for _ in range(3):
        dd = _ddf(A, d)
        good = dd != 0.0
        d = d - np.where(good, _df(A, d) / np.where(good, dd, 1.0), 0.0)
    band = 2.0 * ROUNDING
    split = 2.0 * np.sqrt(2.0 * band / np.maximum(np.abs(_ddf(A, d)), 1e-300))
    touch = (np.abs(_f(A, d)) <= band) & (np.abs(wrap(d - phi)) <= split)
    return np.where(touch, d, phi)


def _f_df(A, phi):
    """``(f, f')`` at ``phi`` from one cosine and sine of it."""
    _, a1, b1, a2, b2 = A
    c, s = np.cos(phi), np.sin(phi)
    c2, s2 = c * c - s * s, 2.0 * s * c
    return (A[0] + a1 * c + b1 * s + a2 * c2 + b2 * s2,
            b1 * c - a1 * s + 2.0 * (b2 * c2 - a2 * s2))


def _f(A, phi):
    a0, a1, b1, a2, b2 = A
    return a0 + a1 * np.cos(phi) + b1 * np.sin(phi) + a2 * np.cos(2 * phi) + b2 * np.sin(2 * phi)


def _df(A, phi):
    _, a1, b1, a2, b2 = A
    return (-a1 * np.sin(phi) + b1 * np.cos(phi) - 2 * a2 * np.sin(2 * phi)
            + 2 * b2 * np.cos(2 * phi))


def _ddf(A, phi):
    _, a1, b1, a2, b2 = A
    return (-a1 * np.cos(phi) - b1 * np.sin(phi) - 4 * a2 * np.cos(2 * phi)
            - 4 * b2 * np.sin(2 * phi))
