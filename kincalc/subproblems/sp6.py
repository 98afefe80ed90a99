"""Subproblem 6: two angles from two sums of rotated components ("four cones").

Find ``(theta1, theta2)`` with ::

    h1 . R(k1, theta1) p1 + h2 . R(k2, theta2) p2 = d1
    h3 . R(k3, theta1) p3 + h4 . R(k4, theta2) p4 = d2

(Elias & Wen, IK-Geo, arXiv:2211.05737, 2022, subproblem 6). Each term is
``h . R(k, theta) p = a . (cos theta, sin theta) + (h . k)(k . p)`` with ``a = (h .
p_perp, h . (k x p))``, so the two equations are linear in ``(cos theta1, sin theta1,
cos theta2, sin theta2)``; with the two unit-circle constraints this is the
intersection of two ellipses, a quartic: up to four solutions
(:mod:`kincalc.subproblems.unit_pair`).

No least-squares answer is defined: with no exact solution no slot is ``ok``.

Ill-posed (``free``): an equation that does not depend on the angles (in both of its
terms ``h`` along ``k`` or ``p`` on the axis): it holds everywhere or nowhere; two
equations with proportional angle coefficients (a curve of solutions, or none); the
constraints leaving a curve (``theta1 = theta2``, ...). One point of a curve is
returned.
"""

from __future__ import annotations

import numpy as np

from ..tolerances import GEOMETRY_TOL
from . import unit_pair
from .solutions import Solutions, norm
from .sp4 import coefficients


def sp6(h, k, p, d1, d2, *, tol: float = GEOMETRY_TOL,
        merge: float = unit_pair.SAME_ANGLE) -> Solutions:
    """Solve subproblem 6, two sums of rotated components, for every problem of a batch.

    Parameters
    ----------
    h, k, p : array_like (..., 4, 3)
        Rows ``h1..h4`` (directions, any length), ``k1..k4`` (unit axes; ``k1``, ``k3``
        turn by ``theta1``, ``k2``, ``k4`` by ``theta2``) and ``p1..p4`` (vectors from a
        point of the axis), all in one frame; the shapes broadcast.
    d1, d2 : array_like (...)
        Right-hand sides, in the unit of ``h . p`` (broadcast against the vectors'
        leading shape: one geometry may take many right sides).
    tol : float
        Tolerance of :func:`~kincalc.subproblems.unit_pair.solve`, relative to the
        largest ``|h_i| |p_i|`` for a vanishing equation.
    merge : float
        Two roots closer than this (rad, both angles) are one (0: every distinct root;
        :func:`~kincalc.subproblems.unit_pair.solve`).

    Returns
    -------
    Solutions
        Four slots, as :func:`~kincalc.subproblems.unit_pair.solve`:
        ``theta = (theta1 (..., 4), theta2 (..., 4))`` in rad, in (-pi, pi] (0 where not
        ``ok``); ``ok (..., 4)`` the slots holding a solution (not necessarily the first
        ones); ``exact`` is ``ok`` (no least-squares answer); ``free (..., 4)``, the same
        in every slot, the problem is ill-posed (one point of a curve, or none, is
        returned).

    Raises
    ------
    ValueError
        When ``h``, ``k``, ``p``, or ``d1``, ``d2`` and the leading shape, do not
        broadcast.
    """
    h, k, p = np.broadcast_arrays(*(np.asarray(v, float) for v in (h, k, p)))
    a_cos, a_sin, const = coefficients(h, p, k)            # each term a subproblem 4's
    M = np.stack([np.stack([a_cos[..., 0], a_sin[..., 0], a_cos[..., 1], a_sin[..., 1]], -1),
                  np.stack([a_cos[..., 2], a_sin[..., 2], a_cos[..., 3], a_sin[..., 3]], -1)],
                 -2)
    b = np.stack(np.broadcast_arrays(d1 - const[..., 0] - const[..., 1],
                                     d2 - const[..., 2] - const[..., 3]), -1)
    scale = (norm(h) * norm(p)).max(-1)
    return unit_pair.solve(M, b, scale, tol=tol, merge=merge)
