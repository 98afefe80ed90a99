"""Subproblem 5: three rotations closing a loop of two circles ("three cones").

Find ``(theta1, theta2, theta3)`` with ::

    p0 + R(k1, theta1) p1 = R(k2, theta2) (p2 + R(k3, theta3) p3)

for unit axes through the origin (Elias & Wen, IK-Geo, arXiv:2211.05737, 2022,
subproblem 5). The left side runs over a circle C1 (axis ``k1``), the bracket on the
right over a circle C3 (axis ``k3``). A point ``v1`` of C1 and a point ``v3`` of C3
are related by a rotation about ``k2`` exactly when they have the same height along
``k2`` and the same distance from the origin; with ``v = c + A (cos t, sin t)`` both
conditions are linear in ``(cos theta1, sin theta1, cos theta3, sin theta3)``:
``k2 . v1 = k2 . v3`` and ``|v1|^2 = |v3|^2``, the two-ellipse problem of subproblem 6
(up to four solutions). ``theta2`` then turns ``v3`` onto ``v1`` (subproblem 1). Unlike
IK-Geo's formulation (a quartic in the height), this needs no assumption on the axes.

No least-squares answer is defined: with no exact solution no slot is ``ok``.

Ill-posed (``free``): ``p1`` on ``k1`` (C1 a point: ``theta1`` free), likewise ``p3``
on ``k3``; a circle coaxial with ``k2``; both circles at constant height along ``k2``
or at constant distance from the origin (a curve of solutions, or none); the meeting
point on the axis ``k2`` (``theta2`` free; a double root of the quartic, found only to
about 1e-6 rad, so a point within ``AXIS_TOL`` of the axis is reported free).
"""

from __future__ import annotations

import numpy as np

from ..spatial import matrix_from_axis_angle
from ..tolerances import GEOMETRY_TOL
from . import unit_pair
from .solutions import Solutions, as_vectors, cross, dot, norm
from .sp1 import sp1

#: relative distance from the axis k2 below which theta2 counts as free; the same
#: bound caps the loop's closing error (a double root is found to ~sqrt(eps))
AXIS_TOL = 1e-6


def sp5(p0, p1, p2, p3, k1, k2, k3, *, tol: float = GEOMETRY_TOL) -> Solutions:
    """Solve subproblem 5, ``p0 + R1 p1 = R2 (p2 + R3 p3)``, for every problem of a batch.

    Parameters
    ----------
    p0, p1, p2, p3 : array_like (..., 3)
        Vectors of the loop ``p0 + R1 p1 = R2 (p2 + R3 p3)``, in one frame and one length
        unit; the leading shapes of all inputs broadcast.
    k1, k2, k3 : array_like (..., 3)
        Unit rotation axes through the origin, in the same frame.
    tol : float
        Tolerance of the two-ellipse solver (relative to ``L``, the largest of
        ``|p0|..|p3|``), of subproblem 1 for ``theta2``, and of "a circle is a point"
        (radius at most ``tol * L``).

    Returns
    -------
    Solutions
        Four slots; ``theta = (theta1, theta2, theta3)``, each ``(..., 4)``, in rad, in
        (-pi, pi] (0 where not ``ok``). ``ok (..., 4)``: the slot holds a solution whose
        loop closes to ``AXIS_TOL * L`` (``ok`` slots need not come first; all zero
        vectors give one free slot, 0). ``exact`` is ``ok`` (no least-squares answer).
        ``free (..., 4)``: an ``ok`` slot where the problem is ill-posed (module
        docstring), its undetermined angles showing one representative; every slot when
        an ill-posed problem has no ``ok`` slot. ``undetermined``: which angles those are,
        per unknown.

    Raises
    ------
    ValueError
        When an input is not of shape ``(..., 3)`` or the leading shapes do not
        broadcast.
    """
    p0, p1, p2, p3, k1, k2, k3 = np.broadcast_arrays(*as_vectors(p0, p1, p2, p3, k1, k2, k3))
    L = np.maximum(np.maximum(norm(p0), norm(p1)), np.maximum(norm(p2), norm(p3)))
    Ls = np.maximum(L, 1e-300)
    c1, A1 = _circle(p0, k1, p1)
    c3, A3 = _circle(p2, k3, p3)
    r1sq, r3sq = dot(A1[..., 0], A1[..., 0]), dot(A3[..., 0], A3[..., 0])
    # heights along k2 agree; squared norms agree (over 2L: both rows in one unit)
    row1 = np.concatenate([np.einsum("...ij,...i->...j", A1, k2),
                           -np.einsum("...ij,...i->...j", A3, k2)], -1)
    row2 = np.concatenate([np.einsum("...ij,...i->...j", A1, c1),
                           -np.einsum("...ij,...i->...j", A3, c3)], -1) / Ls[..., None]
    M = np.stack([row1, row2], -2)
    b = np.stack([dot(k2, c3 - c1), (dot(c3, c3) + r3sq - dot(c1, c1) - r1sq) / (2 * Ls)], -1)
    pairs = unit_pair.solve(M, b, Ls, tol=tol)
    t1, t3 = pairs.theta
    e1 = np.stack([pairs.c[0], pairs.s[0]], -1)[..., None, :]              # (..., 4, 1, 2)
    e3 = np.stack([pairs.c[1], pairs.s[1]], -1)[..., None, :]
    v1 = c1[..., None, :] + (A1[..., None, :, :] * e1).sum(-1)             # (..., 4, 3)
    v3 = c3[..., None, :] + (A3[..., None, :, :] * e3).sum(-1)
    second = sp1(v3, v1, k2[..., None, :], tol=tol)
    t2 = second.theta[0][..., 0]
    loop = p0[..., None, :] + _turn(k1, t1, p1) - _turn(k2, t2, p2[..., None, :] + _turn(k3, t3, p3))
    ok = pairs.ok & (norm(loop) <= AXIS_TOL * Ls[..., None])
    near_axis = norm(v1 - dot(k2[..., None, :], v1)[..., None] * k2[..., None, :]) \
        <= AXIS_TOL * Ls[..., None]
    zero = L == 0.0
    # which angle: theta1 on a circle C1 that is a point (the pair's free angle then), theta3
    # likewise, theta2 with the meeting point on k2; all three on a curve of solutions
    point1, point3 = ((r <= (tol * Ls) ** 2) | zero for r in (r1sq, r3sq))
    curve = pairs.free & ~(point1 | point3)[..., None] | zero[..., None]
    which = (curve | point1[..., None], curve | second.free[..., 0] | near_axis,
             curve | point3[..., None])
    ok = np.where(zero[..., None], np.arange(4) == 0, ok)
    none = ~ok.any(-1)[..., None]
    which = tuple(f & (ok | none) for f in which)
    thetas = tuple(np.where(ok, t, 0.0) for t in (t1, t2, t3))
    return Solutions(thetas, tuple(np.cos(t) for t in thetas), tuple(np.sin(t) for t in thetas),
                     ok, ok, which[0] | which[1] | which[2], which)


def _circle(offset, k, p):
    """Centre ``(..., 3)`` and basis ``(..., 3, 2)`` with ``offset + R(k, t) p = c + A
    (cos t, sin t)``; the columns are orthogonal, of length ``|k x p|``."""
    kp = dot(k, p)
    return offset + kp[..., None] * k, np.stack([p - kp[..., None] * k, cross(k, p)], -1)


def _turn(k, t, p):
    """``R(k, t) p`` for axes ``k (..., 3)``, angles ``t (..., 4)``, ``p (..., [4,] 3)``."""
    R = matrix_from_axis_angle(k[..., None, :], t)
    p = np.broadcast_to(p if p.ndim == R.ndim - 1 else p[..., None, :], R.shape[:-1])
    return np.einsum("...ij,...j->...i", R, p)
