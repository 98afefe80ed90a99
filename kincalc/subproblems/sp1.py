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

import numpy as np

from .solutions import Solutions, angles, as_vectors, norm


def sp1(p1, p2, k, *, tol: float = 1e-9) -> Solutions:
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
    p1, p2, k = as_vectors(p1, p2, k)
    # by components: no (..., 3) temporaries broadcast against (..., 1) factors
    (u0, u1, u2), (v0, v1, v2), (k0, k1, k2) = ((w[..., 0], w[..., 1], w[..., 2])
                                                for w in (p1, p2, k))
    h1 = k0 * u0 + k1 * u1 + k2 * u2
    h2 = k0 * v0 + k1 * v1 + k2 * v2
    a0, a1, a2 = u0 - h1 * k0, u1 - h1 * k1, u2 - h1 * k2      # p1 across the axis
    b0, b1, b2 = v0 - h2 * k0, v1 - h2 * k1, v2 - h2 * k2      # p2 across the axis
    x = a0 * b0 + a1 * b1 + a2 * b2                            # a . b
    y = ((k1 * a2 - k2 * a1) * b0 + (k2 * a0 - k0 * a2) * b1   # (k x a) . b
         + (k0 * a1 - k1 * a0) * b2)
    if tol > 0.0:
        scale = np.maximum(np.maximum(norm(p1), norm(p2)), 1e-300)
        r1 = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        r2 = np.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
        free = (r1 < tol * scale) | (r2 < tol * scale)
        exact = (np.abs(h1 - h2) < tol * scale) & (np.abs(r1 - r2) < tol * scale)
    else:                   # no threshold: free only where a part across the axis is 0
        free = (x == 0.0) & (y == 0.0)
        exact = np.ones(free.shape, bool)
    theta, c, s = angles(np.where(free, 1.0, x)[..., None], np.where(free, 0.0, y)[..., None])
    one = np.ones(theta.shape, bool)
    return Solutions((theta,), (c,), (s,), one, exact[..., None], free[..., None])
