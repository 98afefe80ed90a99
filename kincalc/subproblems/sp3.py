"""Subproblem 3: rotate a point about an axis to a given distance from another point.

Find ``theta`` with ``|R(k, theta) p1 - p2| = d``. Reduces to subproblem 4:
``|R p1 - p2|^2 = |p1|^2 + |p2|^2 - 2 p2 . R p1``, so
``p2 . R p1 = (|p1|^2 + |p2|^2 - d^2) / 2``.
"""

from __future__ import annotations

import numpy as np

from .sp4 import sp4


def sp3(p1, p2, k, d, tol: float = 1e-12):
    """Return ``(thetas, exact, free)`` as :func:`~kincalc.subproblems.sp4.sp4`."""
    p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
    target = 0.5 * (p1 @ p1 + p2 @ p2 - d * d)
    return sp4(p2, p1, k, target, tol)
