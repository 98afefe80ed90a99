"""The scalar subproblems 1, 2 and 4 of the per-pose engine (one problem per call).

Kept only until the batched engine (kincalc.ik.engine) replaces the per-pose family
solvers that call them; kincalc.subproblems holds the batched subproblems.
"""

from __future__ import annotations

import math

import numpy as np

from ..spatial import matrix_from_unit_axis_angle as _rot


def cross3(a, b) -> np.ndarray:
    """``a x b`` (3,) of two 3-vectors."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def norm3(v) -> float:
    """Euclidean length of a 3-vector."""
    return math.sqrt(float(v @ v))


def sp1(p1, p2, k, tol: float = 1e-9):
    """Return ``(theta, exact, free)``.

    Parameters
    ----------
    p1, p2 : array_like (3,)
        Points (vectors from a point on the axis).
    k : array_like (3,)
        Unit rotation axis.
    tol : float
        Relative tolerance for "same height and radius" and "on the axis".
    """
    p1, p2, k = (np.asarray(v, dtype=float) for v in (p1, p2, k))
    kxp = cross3(k, p1)
    # p1 projected on the plane of rotation, in the basis (-k x (k x p1), k x p1)
    a = cross3(kxp, k)         # = p1 - (k.p1) k
    x = a @ p2
    y = kxp @ p2
    scale = max(norm3(p1), norm3(p2), 1e-300)
    r1, r2 = norm3(a), norm3(p2 - k * (k @ p2))
    if r1 < tol * scale or r2 < tol * scale:
        return 0.0, bool(abs(k @ p1 - k @ p2) < tol * scale and abs(r1 - r2) < tol * scale), True
    theta = float(np.arctan2(y, x))
    exact = abs(k @ p1 - k @ p2) < tol * scale and abs(r1 - r2) < tol * scale
    return theta, bool(exact), False


def sp4(h, p, k, d, tol: float = 1e-12):
    """Return ``(thetas, exact, free)``; ``thetas`` a list of 0, 1 or 2 angles (rad)."""
    h, p, k = (np.asarray(v, dtype=float) for v in (h, p, k))
    kxp = cross3(k, p)
    A = -(h @ cross3(k, kxp))  # h . (p - (k.p)k)
    B = h @ kxp
    C = (h @ k) * (k @ p)
    r = np.hypot(A, B)
    scale = max(norm3(h) * norm3(p), abs(d), 1e-300)
    if r < tol * scale:
        return [0.0], bool(abs(C - d) < 1e-9 * scale), True
    base = np.arctan2(B, A)
    # the slack absorbs rounding in d - C, which does not shrink with r (an
    # absolute band on c would reject solvable inputs when r is small)
    if abs(d - C) > r + tol * scale:
        return [float(base if d > C else base + np.pi)], False, False
    c = min(1.0, max(-1.0, (d - C) / r))
    delta = np.arccos(c)
    # tangent (c = +-1): one solution; at c = -1, base + pi and base - pi are
    # the same angle
    if delta < 1e-9 or delta > np.pi - 1e-9:
        return [float(base + delta)], True, False
    return [float(base + delta), float(base - delta)], True, False


def sp2(p1, p2, k1, k2, tol: float = 1e-9):
    """Return ``(solutions, exact, free)``; ``solutions`` a list of (theta1, theta2)."""
    p1, p2, k1, k2 = (np.asarray(v, dtype=float) for v in (p1, p2, k1, k2))
    t2s, exact4, free2 = sp4(k1, p1, k2, float(k1 @ p2))
    out, exact, free = [], exact4, free2
    for t2 in t2s:
        q = _rot(k2, t2) @ p1
        t1, ex1, fr1 = sp1(q, p2, k1, tol)
        out.append((t1, t2))
        exact = exact and ex1
        free = free or fr1
    return out, exact, free
