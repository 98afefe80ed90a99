"""Roots of many polynomials at once: the eigenvalues of a stack of companion matrices.

Shared by the subproblems and the point placement whose last step is a polynomial (a
quartic in ``e^(i phi)``, a resultant): one ``numpy.linalg.eigvals`` call for a whole
batch instead of ``numpy.roots`` per problem.
"""

from __future__ import annotations

import numpy as np

from .solutions import Solutions


def polynomial_roots(coeffs) -> np.ndarray:
    """Complex roots of a batch of polynomials of one degree ``d``.

    Every polynomial keeps its degree ``d``: a vanishing leading coefficient (below
    1e-13 of the largest) is replaced by that bound, which sends the roots of the
    missing degrees far away (callers keep roots in a band they trust), so that one
    companion shape serves the whole batch.

    Parameters
    ----------
    coeffs : array_like (..., d + 1)
        Real or complex coefficients, highest degree first (as ``numpy.roots``).

    Returns
    -------
    ndarray (..., d) of complex
        The roots of each polynomial (eigenvalues of its companion matrix), in no
        particular order; an all-zero polynomial gives ``d`` zero roots.

    Raises
    ------
    numpy.linalg.LinAlgError
        When a coefficient is not finite (for the whole batch), or the eigenvalue
        computation does not converge.
    """
    coeffs = np.asarray(coeffs)
    d = coeffs.shape[-1] - 1
    # scaled to a largest coefficient of 1 first (the roots do not change): with
    # coefficients of 0 or near 1e-300 (a curve, a point, axes along the coordinate
    # axes) the bound would be subnormal, and complex division by it gave inf and NaN,
    # on which eigvals raised for the whole batch
    coeffs = coeffs / np.maximum(np.abs(coeffs).max(-1), 1e-300)[..., None]
    lead = coeffs[..., 0]
    lead = np.where(np.abs(lead) < 1e-13, 1e-13, lead)
    comp = np.zeros(coeffs.shape[:-1] + (d, d), np.result_type(coeffs, float))
    comp[..., 0, :] = -coeffs[..., 1:] / lead[..., None]
    comp[..., np.arange(1, d), np.arange(d - 1)] = 1.0
    return np.linalg.eigvals(comp)


def quadratic(A, B, C, scale, *, tangent=0.0) -> Solutions:
    """The real roots of ``A x^2 + B x + C = 0`` for each problem.

    Parameters
    ----------
    A, B, C : array_like, broadcast together to ``(...)``
    scale : float or array_like, the size of ``B^2`` below which a slightly negative
        discriminant (rounding) counts as a double root
    tangent : float or array_like ``(...)``, in the unit of ``C``: an extreme value ``C -
        B^2 / (4 A)`` within it of 0 is 0, the tangent (the rounding of the terms): one
        double root ``-B / (2 A)`` to rounding, not two either side, ~sqrt(rounding)
        apart, as a slightly positive discriminant would give (default 0: none)

    Returns
    -------
    Solutions
        One unknown: two slots ``(..., 2)`` in ascending order, or one ``(..., 1)`` when
        the equation is linear (``A`` ~ 0) for every problem (a robot-level fact: a
        sliding joint along the invariant's direction); ``ok = exact`` where a root is
        real, never ``free``.
    """
    A, B, C = np.broadcast_arrays(*(np.asarray(v, float) for v in (A, B, C)))
    linear = np.abs(A) <= 1e-12 * np.maximum(np.abs(B), 1e-300)
    if linear.all():
        Bl = np.where(B == 0.0, 1.0, B)
        x = (-C / Bl)[..., None]
        ok = (B != 0.0)[..., None]
        zero = np.zeros_like(x)
        return Solutions((np.where(ok, x, 0.0),), (zero,), (zero,), ok, ok, np.zeros_like(ok))
    disc = B * B - 4 * A * C
    disc = np.where(np.abs(disc) <= 4 * np.abs(A) * tangent, 0.0, disc)
    real = disc >= -1e-12 * np.maximum(B * B, scale ** 2)
    sq = np.sqrt(np.maximum(disc, 0.0))
    Aq = np.where(linear, 1.0, A)
    r1, r2 = (-B - sq) / (2 * Aq), (-B + sq) / (2 * Aq)
    lo, hi = np.minimum(r1, r2), np.maximum(r1, r2)
    Bl = np.where(B == 0.0, 1.0, B)
    x = np.stack([np.where(linear, -C / Bl, lo), hi], -1)
    ok = np.stack([np.where(linear, B != 0.0, real), ~linear & real & (sq > 0)], -1)
    zero = np.zeros_like(x)
    return Solutions((np.where(ok, x, 0.0),), (zero,), (zero,), ok, ok, np.zeros_like(ok))
