"""Subproblem 4: a rotated vector's component along a direction.

Find ``theta`` with ``h . R(k, theta) p = d``. Writing
``h . R p = A cos(theta) + B sin(theta) + C`` the solutions are
``theta = atan2(B, A) +- acos((d - C) / sqrt(A^2 + B^2))``: two, one (at the
boundary) or none, in which case the least-squares angle
(``atan2(B, A)`` or its opposite) is returned with ``exact=False``. Ill-posed
when ``A = B = 0`` (``h`` parallel to ``k`` or ``p`` on the axis): every angle
or none solves it; then ``free=True``.
"""

from __future__ import annotations

import numpy as np

from ._small import cross3, norm3


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
