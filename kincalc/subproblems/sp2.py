"""Subproblem 2: two rotations about intersecting axes taking one point to another.

Find ``(theta1, theta2)`` with ``R(k1, theta1) R(k2, theta2) p1 = p2`` for unit
axes through the origin. Equivalent to ``R(k2, theta2) p1 = R(k1, -theta1) p2``:
``theta2`` from subproblem 4 on the component along ``k1``
(``k1 . R(k2, theta2) p1 = k1 . p2``), then ``theta1`` from subproblem 1.
Up to two solutions; ``free`` when an angle is undetermined (a point on an axis).
"""

from __future__ import annotations

import numpy as np

from ..spatial import matrix_from_unit_axis_angle as _rot
from .sp1 import sp1
from .sp4 import sp4


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
