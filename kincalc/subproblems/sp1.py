"""Subproblem 1: rotate a point about an axis onto another point.

Find ``theta`` with ``R(k, theta) p1 = p2``. One solution when both points
have the same height along ``k`` and the same distance from it; otherwise
the least-squares angle (the one minimising ``|R p1 - p2|``) with
``exact=False``. Ill-posed when ``p1`` (or ``p2``) lies on the axis: every
angle is a solution; then ``theta = 0`` and ``free=True``.
"""

from __future__ import annotations

import numpy as np

from ._small import cross3, norm3


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
