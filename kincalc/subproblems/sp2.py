"""Subproblem 2: two rotations about intersecting axes taking one point to another.

Find ``(theta1, theta2)`` with ``R(k1, theta1) R(k2, theta2) p1 = p2`` for unit axes
through the origin (Paden 1986; Elias & Wen, IK-Geo, 2022). Equivalent to
``R(k2, theta2) p1 = R(k1, -theta1) p2``: the component along ``k1`` gives
``theta2`` by subproblem 4 (``k1 . R(k2, theta2) p1 = k1 . p2``), then ``theta1``
turns ``R(k2, theta2) p1`` onto ``p2`` by subproblem 1.

Both points are first scaled to unit length (as IK-Geo does), so that the answer
depends only on their directions.

Solutions: two, one (tangent), or, when ``|p1| != |p2|`` or the cone of ``k2`` does
not reach the height of ``p2``, the least-squares pair with ``exact`` False: the one
minimising ``|R1 R2 p1 - p2|``, i.e. turning the direction of ``p1`` as close to that
of ``p2`` as the axes allow (both slots when the directions can be matched, else the
nearest height along ``k1`` by subproblem 4's least squares, then subproblem 1's).

Ill-posed (``free``): ``theta2`` undetermined (``p1`` on ``k2``, or ``k1`` along
``k2``) or ``theta1`` undetermined (the rotated point on ``k1``); :func:`free_angles`
tells which.
"""

from __future__ import annotations

import numpy as np

from .solutions import Solutions, as_vectors, cross, dot, norm
from .sp1 import sp1
from .sp4 import sp4


def sp2(p1, p2, k1, k2, *, tol: float = 1e-9) -> Solutions:
    """Solve subproblem 2, ``R(k1, theta1) R(k2, theta2) p1 = p2``, for every problem of a batch.

    Parameters
    ----------
    p1, p2 : array_like (..., 3)
        The point and its target, as vectors from the axes' common point, in one frame
        and one length unit (only their directions enter the angles); the leading shapes
        of all inputs broadcast.
    k1, k2 : array_like (..., 3)
        Unit rotation axes in the same frame (``k1`` applied last).
    tol : float
        Relative tolerance (of ``max(|p1|, |p2|)``) of ``|p1| = |p2|``, and subproblem
        1's tolerance for ``theta1``; subproblem 4 (``theta2``) uses its own default.

    Returns
    -------
    Solutions
        Two slots; ``theta = (theta1 (..., 2), theta2 (..., 2))`` in rad, in (-pi, pi].
        ``ok (..., 2)``: slot 0 always, slot 1 when there are two distinct solutions.
        ``exact (..., 2)``: the pair solves the equation, else it is the least-squares
        pair (``|p1| != |p2|``, or the cone of ``k2`` does not reach the height of
        ``p2``). ``free (..., 2)``: ``theta2`` or ``theta1`` undetermined (the
        undetermined angle shows 0); ``undetermined``: which (:func:`free_angles`), or
        None where no slot is free.

    Raises
    ------
    ValueError
        When an input is not of shape ``(..., 3)`` or the leading shapes do not
        broadcast.
    """
    p1, p2, k1, k2 = as_vectors(p1, p2, k1, k2)
    n1, n2 = norm(p1), norm(p2)
    same = np.abs(n1 - n2) <= tol * np.maximum(np.maximum(n1, n2), 1e-300)
    # unit directions (a zero vector stays zero: free): without this scaling the
    # answer for |p1| != |p2| matched heights, not directions, and was no minimum
    p1 = p1 / np.where(n1 > 0.0, n1, 1.0)[..., None]
    p2 = p2 / np.where(n2 > 0.0, n2, 1.0)[..., None]
    second = sp4(k1, p1, k2, dot(k1, p2))
    c2, s2 = second.c[0][..., None], second.s[0][..., None]              # (..., 2, 1)
    v, kv = p1[..., None, :], cross(k2, p1)[..., None, :]
    q = c2 * v + s2 * kv + (1.0 - c2) * dot(k2, p1)[..., None, None] * k2[..., None, :]
    first = sp1(q, p2[..., None, :], k1[..., None, :], tol=tol)
    t1, c1, s1 = (x[0][..., 0] for x in (first.theta, first.c, first.s))
    free = second.free | first.free[..., 0]
    # which angle is undetermined (rare: the others are then the problem's own)
    which = free_angles(free, *(x[..., None, :] for x in (p1, p2, k1, k2)), tol=tol) \
        if np.count_nonzero(free) else None
    return Solutions((t1, second.theta[0]), (c1, second.c[0]), (s1, second.s[0]), second.ok,
                     second.exact & first.exact[..., 0] & same[..., None], free, which)


def free_angles(free, p1, p2, k1, k2, *, tol: float = 1e-9) -> tuple:
    """Which angle of subproblem 2 is undetermined where it is ill-posed.

    Parameters
    ----------
    free : ndarray (...) of bool
        The problems that are ill-posed (``sp2(...).free`` of a slot).
    p1, p2, k1, k2 : ndarray (..., 3)
        Unit vectors of ``R(k1, theta1) R(k2, theta2) p1 = p2``.
    tol : float
        The ``tol`` :func:`sp2` was given: a unit vector is along an axis within this sine.

    Returns
    -------
    free1, free2 : ndarray (...) of bool
        ``theta2`` where ``p1`` is along ``k2``, ``theta1`` where ``p2`` is along ``k1``,
        both otherwise (``k1`` along ``k2``).
    """
    on2 = np.linalg.norm(np.cross(p1, k2), axis=-1) < tol
    on1 = np.linalg.norm(np.cross(p2, k1), axis=-1) < tol
    return free & (on1 | ~on2), free & (on2 | ~on1)
