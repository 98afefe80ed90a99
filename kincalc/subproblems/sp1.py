"""Subproblem 1: rotate a point about an axis onto another point.

Find ``theta`` with ``R(k, theta) p1 = p2`` (Paden 1986; Murray, Li & Sastry 1994,
sec. 3.3.2). With ``a = p1 - (k . p1) k`` the part of ``p1`` across the axis,
``theta = atan2((k x p1) . p2, a . p2)``.

Solutions: one when both points have the same height along ``k`` and the same
distance from it; otherwise the least-squares angle (the one minimising
``|R p1 - p2|``, given by the same formula) with ``exact`` False.

Ill-posed: ``p1`` or ``p2`` on the axis (within ``tol`` of their size): every angle
solves it (or none does); ``theta = 0`` and ``free`` True.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .solutions import Solutions, angles, as_vectors, cross, direction, dot, true_mask


class Sp1Constants(NamedTuple):
    """What :func:`sp1` needs of ``p1`` and ``k`` alone (see :func:`sp1_constants`)."""

    k: np.ndarray           # (..., 3) the unit axis, as a float array
    h1: np.ndarray          # (...) p1 . k, the height of p1 along the axis
    a: np.ndarray           # (..., 3) p1 across the axis, p1 - h1 k
    kxa: np.ndarray         # (..., 3) k x a
    p1p1: np.ndarray        # (...) p1 . p1


def sp1_constants(p1, k) -> Sp1Constants:
    """What :func:`sp1` needs of ``p1`` and ``k`` alone.

    A solver that turns a fixed vector ``p1`` about a fixed axis ``k`` (a robot's axis
    and a vector of its geometry) computes these once and passes them to :func:`sp1` as
    ``fixed``.

    Parameters
    ----------
    p1, k : array_like (..., 3)
        As in :func:`sp1`.

    Returns
    -------
    Sp1Constants
        ``k``, the height ``h1 = p1 . k``, the part ``a = p1 - h1 k`` across the axis,
        ``k x a`` and ``p1 . p1``, computed as :func:`sp1` computes them (the same bits).
    """
    p1, k = as_vectors(p1, k)
    h1 = dot(p1, k)
    a = p1 - h1[..., None] * k
    return Sp1Constants(k, h1, a, cross(k, a), dot(p1, p1))


def sp1(p1, p2, k, *, tol: float = 1e-9, fixed: Sp1Constants | None = None) -> Solutions:
    """Solve subproblem 1, ``R(k, theta) p1 = p2``, for every problem of a batch.

    Parameters
    ----------
    p1, p2 : array_like (..., 3)
        The point to rotate and its target, as vectors from a point of the axis, in one
        frame and one length unit; the leading shapes of all inputs broadcast.
    k : array_like (..., 3)
        Unit rotation axis, in the same frame.
    tol : float
        Relative tolerance (of ``max(|p1|, |p2|)``) of "same height and distance" and
        "on the axis". With ``tol <= 0`` there is no threshold: ``free`` only where a
        part across the axis is exactly 0, and ``exact`` is True everywhere.
    fixed : Sp1Constants, optional
        ``sp1_constants(p1, k)``, for a caller whose ``p1`` and ``k`` are fixed vectors:
        what depends on them alone is then read from it, not computed again (``p1`` and
        ``k`` are not read; the same result).

    Returns
    -------
    Solutions
        One slot: ``theta[0] (..., 1)`` in rad, in (-pi, pi]; ``ok (..., 1)`` always
        True; ``exact (..., 1)``: the heights along ``k`` and the distances from it
        agree, else ``theta`` is the least-squares angle minimising ``|R p1 - p2|``;
        ``free (..., 1)``: ``p1`` or ``p2`` on the axis, ``theta = 0``.

    Raises
    ------
    ValueError
        When an input is not of shape ``(..., 3)`` or the leading shapes do not
        broadcast.
    """
    if fixed is None:
        p1, p2, k = as_vectors(p1, p2, k)
        h1 = dot(p1, k)
        a = p1 - h1[..., None] * k                              # p1 across the axis
        kxa = cross(k, a)
    else:
        (p2,), (k, h1, a, kxa, p1p1) = as_vectors(p2), fixed
    h2 = dot(p2, k)
    b = p2 - h2[..., None] * k                                  # p2 across the axis
    x = dot(a, b)[..., None]
    y = dot(kxa, b)[..., None]
    if tol <= 0.0:          # no threshold: free only where a part across the axis is 0
        theta, c, s, free = direction(x, y)     # (x, y) = 0 exactly there
        one = true_mask(theta.shape)
        return Solutions((theta,), (c,), (s,), one, one, free)
    band = tol * np.maximum(np.sqrt(np.maximum(dot(p1, p1) if fixed is None else p1p1,
                                               dot(p2, p2))), 1e-300)
    r1, r2 = np.sqrt(dot(a, a)), np.sqrt(dot(b, b))
    free = (np.fmin(r1, r2) < band)[..., None]                  # r1 or r2 below the band
    # both differences below it (a NaN in either is not: maximum keeps NaN)
    exact = (np.maximum(np.abs(h1 - h2), np.abs(r1 - r2)) < band)[..., None]
    if np.count_nonzero(free):
        x, y = np.where(free, 1.0, x), np.where(free, 0.0, y)
    theta, c, s = angles(x, y)
    return Solutions((theta,), (c,), (s,), true_mask(theta.shape), exact, free)
