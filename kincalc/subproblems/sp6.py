"""Subproblem 6: two angles from two sums of rotated components ("four cones").

Find ``(theta1, theta2)`` with ::

    h1 . R(k1, theta1) p1 + h2 . R(k2, theta2) p2 = d1
    h3 . R(k3, theta1) p3 + h4 . R(k4, theta2) p4 = d2

(Elias & Wen, "IK-Geo", arXiv:2211.05737, 2022, subproblem 6). Each term is
``h . R(k, theta) p = a . (cos theta, sin theta) + (h . k)(k . p)`` with
``a = (h . p_perp, h . (k x p))``, so the two equations are linear in
``(cos theta1, sin theta1, cos theta2, sin theta2)``; with the two unit-circle
constraints this is the intersection of two ellipses, a quartic: up to four
solutions (see :mod:`kincalc.subproblems._unit_pair`).

No least-squares answer is defined: when there is no exact solution the
list is empty and ``exact=False``.

Ill-posed (``free=True``):

* an equation does not depend on the angles (in both of its terms ``h`` is
  parallel to ``k`` or ``p`` lies on the axis): it holds everywhere or nowhere;
* the two equations have proportional angle coefficients (for instance the
  same equation twice): a curve of solutions or none;
* the constraints leave a curve of solutions, for instance ``cos theta1 =
  cos theta2`` and ``sin theta1 = sin theta2`` (``theta1 = theta2``).

When the solutions form a curve, one point of it is returned.
"""

from __future__ import annotations

import numpy as np

from ..spatial import cross

from ..tolerances import GEOMETRY_TOL
from ._unit_pair import solve_unit_pair


def sp6(h, k, p, d1: float, d2: float, tol: float = GEOMETRY_TOL):
    """Solve subproblem 6 for all ``(theta1, theta2)``.

    Parameters
    ----------
    h : array_like (4, 3)
        Directions ``h1, h2, h3, h4``, one per row (any length).
    k : array_like (4, 3)
        Unit rotation axes ``k1, k2, k3, k4`` through the origin, one per row;
        ``k1`` and ``k3`` turn by ``theta1``, ``k2`` and ``k4`` by ``theta2``.
    p : array_like (4, 3)
        Vectors ``p1, p2, p3, p4``, one per row (from a point on the axis).
    d1, d2 : float
        Right-hand sides, in the unit of ``h . p``.
    tol : float
        Relative tolerance of the degeneracy tests (an equation counted as
        constant, rows counted as parallel).

    Returns
    -------
    solutions : list of tuple(float, float)
        Up to four ``(theta1, theta2)`` in rad, each in (-pi, pi].
    exact : bool
        True when ``solutions`` is non-empty; False (with an empty list) when
        there is no solution.
    free : bool
        True when the problem is ill-posed (see the module docstring).

    References
    ----------
    A. Elias, J. Wen, "IK-Geo: Unified robot inverse kinematics using
    subproblem decomposition", arXiv:2211.05737, 2022, sec. on subproblem 6.
    """
    h = np.asarray(h, dtype=float).reshape(4, 3)
    k = np.asarray(k, dtype=float).reshape(4, 3)
    p = np.asarray(p, dtype=float).reshape(4, 3)
    kp = np.einsum("ij,ij->i", k, p)
    p_perp = p - kp[:, None] * k
    kxp = cross(k, p)
    a_cos = np.einsum("ij,ij->i", h, p_perp)
    a_sin = np.einsum("ij,ij->i", h, kxp)
    const = np.einsum("ij,ij->i", h, k) * kp
    M = np.array([[a_cos[0], a_sin[0], a_cos[1], a_sin[1]],
                  [a_cos[2], a_sin[2], a_cos[3], a_sin[3]]])
    b = np.array([d1 - const[0] - const[1], d2 - const[2] - const[3]])
    scale = float(np.max(np.linalg.norm(h, axis=1) * np.linalg.norm(p, axis=1)))
    return solve_unit_pair(M, b, scale, tol)
