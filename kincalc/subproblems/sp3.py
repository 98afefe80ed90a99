"""Subproblem 3: rotate a point about an axis to a given distance from another point.

Find ``theta`` with ``|R(k, theta) p1 - p2| = d`` (Paden 1986; Murray, Li & Sastry
1994, sec. 3.3.2). Since ``|R p1 - p2|^2 = |p1|^2 + |p2|^2 - 2 p2 . R p1``, it is
subproblem 4 with ``h = p2`` and ``p2 . R p1 = (|p1|^2 + |p2|^2 - d^2) / 2``: two
solutions, one at the tangent (the circle touches the sphere), the least-squares
angle (nearest or farthest point of the circle) when there is none, ill-posed when the
circle's distance from ``p2`` does not change (``p1`` on the axis, or ``p2`` on it).
"""

from __future__ import annotations

import numpy as np

from typing import NamedTuple

from .solutions import Solutions, as_vectors, dot
from .sp4 import AbcConstants, abc_constants, coefficients, from_abc


class Sp3Constants(NamedTuple):
    """What :func:`sp3` needs of fixed ``p1``, ``p2``, ``k`` (see :func:`sp3_constants`)."""

    squares: np.ndarray     # (...) |p1|^2 + |p2|^2
    abc: AbcConstants       # subproblem 4's coefficients of p2 . R(k, theta) p1


def sp3_constants(p1, p2, k) -> Sp3Constants:
    """What :func:`sp3` needs of ``p1``, ``p2``, ``k`` alone, for a solver whose vectors are
    fixed (a robot's link lengths in a law of cosines): only ``d`` then varies.

    Parameters
    ----------
    p1, p2, k : array_like (..., 3)
        As in :func:`sp3`.

    Returns
    -------
    Sp3Constants
        Computed as :func:`sp3` computes them (the same bits).
    """
    p1, p2, k = as_vectors(p1, p2, k)
    return Sp3Constants(dot(p1, p1) + dot(p2, p2), abc_constants(*coefficients(p2, p1, k)))


def sp3(p1, p2, k, d, *, tol: float = 1e-12, scale=None, fixed=None) -> Solutions:
    """Solve subproblem 3, ``|R(k, theta) p1 - p2| = d``, for every problem of a batch.

    Parameters
    ----------
    p1, p2 : array_like (..., 3)
        The point to rotate and the centre of the sphere, from a point of the axis, in
        one frame and one length unit; the leading shapes of all inputs broadcast.
    k : array_like (..., 3)
        Unit rotation axis, in the same frame.
    d : array_like (...)
        The distance to reach (same length unit; broadcast against the vectors'
        leading shape).
    tol : float
        Subproblem 4's relative tolerance (of the scale below): of "the circle's
        distance from ``p2`` is constant" and of how far beyond the tangent a problem
        still counts as solved.
    scale : array_like (...), optional
        The size of the squared lengths the inputs were computed from (default: their
        own, ``(|p1|^2 + |p2|^2 + d^2) / 2``): a caller whose ``d`` comes from larger
        quantities (a target far from the origin) passes their size, so that a tangent
        within their rounding counts as one. The unit of the tolerances is the larger
        of the two.
    fixed : Sp3Constants, optional
        ``sp3_constants(p1, p2, k)``, for fixed vectors (``p1``, ``p2``, ``k`` are then
        not read; the same result).

    Returns
    -------
    Solutions
        Two slots, as :func:`~kincalc.subproblems.sp4.sp4`: ``theta[0] (..., 2)`` in
        rad, in (-pi, pi]; ``ok (..., 2)``: slot 0 always, slot 1 when there are two
        distinct solutions; ``exact (..., 2)`` False for the least-squares angle (the
        nearest or farthest point of the circle, in slot 0 only); ``free (..., 2)``:
        ``p1`` or ``p2`` on the axis (``theta = 0``; ``exact`` when the constant
        distance is ``d``).

    Raises
    ------
    ValueError
        When a vector is not of shape ``(..., 3)`` or the shapes do not broadcast.
    """
    if fixed is None:
        p1, p2, k = as_vectors(p1, p2, k)
        squares, (A, B, C), abc = dot(p1, p1) + dot(p2, p2), coefficients(p2, p1, k), None
    else:
        squares, abc = fixed
        A, B, C = abc.A, abc.B, abc.C
    d = np.asarray(d, float)
    # the target is a difference of squares: its rounding is that of its terms, which
    # sets the tolerances (with the default, |p2| |p1|, a tangent between lengths of
    # different sizes came out not exact or as two roots, and an exactly solvable
    # problem with p2 = 0 not exact): subproblem 4 with h = p2, p = p1
    own = 0.5 * (squares + d * d)
    return from_abc(A, B, C, 0.5 * (squares - d * d),
                    own if scale is None else np.maximum(own, scale), tol=tol, fixed=abc)
