"""The algebra of the ``resultant`` placement (:mod:`kincalc.ik.place`): joint c's values
sampled, joint b eliminated from the two invariants of joint a, the real roots in x_c.

The invariants of joint a are ``alpha + beta B1 + gamma B2`` in ``(B1, B2) = (cos x_b, sin x_b)``
(revolute b) or ``(x_b, x_b^2)`` (prismatic b), with coefficients depending on x_c. Their
resultant in x_b is a trigonometric polynomial of degree <= 4 in x_c (revolute c) or a
polynomial of degree <= :data:`POLY_DEGREE` in its travel (prismatic c): sampled at
:func:`samples`, fitted, and solved through a companion matrix per target.
"""

from __future__ import annotations

import numpy as np

from ..subproblems.solutions import Solutions, rows_times
from .screws import Screws

#: joint c's samples for the resultant: trigonometric degree <= 4 needs 9
TRIG_SAMPLES = 16
#: polynomial degree bound of the resultant in a prismatic joint c's travel
POLY_DEGREE = 8


def samples(S: Screws, c: int) -> np.ndarray:
    """Values of joint c at which the coefficients are sampled."""
    if S.revolute[c]:
        return 2 * np.pi * np.arange(TRIG_SAMPLES) / TRIG_SAMPLES
    span = 4.0 * S.scale
    n = 2 * POLY_DEGREE + 1
    return span * np.cos(np.pi * (np.arange(n) + 0.5) / n)


def eliminate(revolute_b: bool, al, be, ga, linear):
    """The resultant of the two invariants in x_b, on the samples ``(N, K, m)``;
    ``linear (2,)``: which invariants are linear in a prismatic x_b (robot-level)."""
    if revolute_b:
        D = be[0] * ga[1] - be[1] * ga[0]
        P = al[0] * ga[1] - al[1] * ga[0]
        Q = be[0] * al[1] - be[1] * al[0]
        return P * P + Q * Q - D * D
    # two polynomials a x^2 + b x + c in x_b (a = gamma, b = beta, c = alpha); the
    # Sylvester resultant vanishes identically when both are linear, so that case (and
    # one linear, one quadratic) is written out
    (a1, a2), (b1, b2), (c1, c2) = ga, be, al
    if linear.all():
        return b1 * c2 - b2 * c1
    if linear[0]:
        return b1 * b1 * c2 - b1 * b2 * c1 + a2 * c1 * c1
    if linear[1]:
        return b2 * b2 * c1 - b2 * b1 * c2 + a1 * c2 * c2
    return (a1 * c2 - a2 * c1) ** 2 - (a1 * b2 - a2 * b1) * (b1 * c2 - b2 * c1)


def common_root(al, be, ga):
    """The common root of ``gamma_i x^2 + beta_i x + alpha_i`` (i = 0, 1) at a root of
    their resultant: ``x = -(a1 c2 - a2 c1) / (a1 b2 - a2 b1)``, or of the linear one."""
    (a1, a2), (b1, b2), (c1, c2) = ga, be, al
    den = a1 * b2 - a2 * b1
    big = np.maximum(np.abs(b1) + np.abs(b2), 1e-300)
    quad = np.abs(den) > 1e-12 * big * np.maximum(np.abs(a1) + np.abs(a2), 1e-300)
    lin = np.where(np.abs(b1) >= np.abs(b2), -c1 / np.where(b1 == 0, 1.0, b1),
                   -c2 / np.where(b2 == 0, 1.0, b2))
    x = np.where(quad, -(a1 * c2 - a2 * c1) / np.where(quad, den, 1.0), lin)
    return x, np.isfinite(x)


def roots_in_c(S: Screws, c: int, R, resample=None) -> Solutions:
    """The real roots of the resultant sampled at :func:`samples`, ``R (N, K, m)``: up to
    eight slots, ascending. ``resample(x (r, m'), slots (N, K) bool) -> R (r, m')``: the
    resultant of the ``r`` slots ``slots`` at other values of joint c (rad / m). Where the
    fit over the whole span leaves roots a little off
    the real ones' locus (a cluster of real roots close together, which the fit's rounding
    splits into complex pairs), they are found again on a window about them
    (:func:`_refit`)."""
    from ..subproblems.roots import polynomial_roots
    if S.revolute[c]:
        F = np.fft.fft(R, axis=-1) / R.shape[-1]
        K = 4
        coeffs = np.stack([F[..., k % R.shape[-1]] for k in range(K, -K - 1, -1)], -1)
        z = polynomial_roots(coeffs)
        off = np.abs(np.abs(z) - 1.0)                  # (about the angle's distance)
        z = _multiple_roots(z, off, 1e-3)
        x = np.angle(np.where(np.isfinite(z), z, 1.0))
        ok = np.isfinite(z) & (np.abs(np.abs(z) - 1.0) < 1e-3)
        near = (off >= 1e-3) & (off < CLUSTER) & ~ok
    else:
        span = 4.0 * S.scale
        coeffs = rows_times(R, _poly_fit_matrix().T)                       # highest first
        y = polynomial_roots(coeffs)
        off = np.abs(y.imag)
        y = _multiple_roots(y, off, 1e-4)
        x = span * np.where(np.isfinite(y), y.real, 0.0)
        ok = np.isfinite(y) & (np.abs(y.imag) < 1e-4) & (np.abs(y.real) <= 10.0)
        near = (off >= 1e-4) & (off < CLUSTER) & (np.abs(y.real) <= 10.0) & ~ok
        off = off * span                                                    # (m)
    if resample is not None:
        # (a revolute c's resultant is a trigonometric polynomial: the window's degree 8
        # holds it to rounding over 0.05 rad either side, no wider)
        x, ok = _refit(x, ok, near & np.isfinite(x), np.where(near, off, 0.0), resample,
                       0.05 if S.revolute[c] else np.inf)
    order = np.argsort(np.where(ok, x, np.inf), axis=-1)
    x, ok = np.take_along_axis(x, order, -1), np.take_along_axis(ok, order, -1)
    x = np.where(ok, x, 0.0)
    return Solutions((x,), (np.cos(x),), (np.sin(x),), ok, ok, np.zeros_like(ok))


def _refit(x, ok, near, off, resample, widest):
    """The roots ``x (N, K, d)`` (``ok`` the real ones) with those ``near`` the real locus
    (``off (N, K, d)`` from it, in joint units) replaced, per slot, by the real roots of
    the resultant fitted again on a window about them: ``resample`` at ``2 d + 1``
    Chebyshev points of ``[lo - w, hi + w]``, ``lo``, ``hi`` the near roots' extremes and
    ``w`` four times their largest offset. The window holds the cluster's roots well apart
    (a fit over the whole span rounds them into complex pairs 4e-4 off, on an R-R-P-R arm
    whose four roots lie within 0.02 m; the same arm in dh found them). A window wider than
    ``widest`` either side, or one holding a real root already, is left as it is."""
    from ..subproblems.roots import polynomial_roots
    rows = np.flatnonzero(np.logical_or.reduce(near, axis=-1).reshape(-1))
    if not len(rows):
        return x, ok
    shape = x.shape
    x, ok, near, off = (a.reshape(-1, shape[-1]).copy() for a in (x, ok, near, off))
    lo = np.where(near[rows], x[rows], np.inf).min(-1)
    hi = np.where(near[rows], x[rows], -np.inf).max(-1)
    w = 4.0 * np.where(near[rows], off[rows], 0.0).max(-1)
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo) + w
    # a window that holds a real root already is a multiple root's cluster
    # (:func:`_multiple_roots` stood its mean or a real root for it): left as it is
    single = ~np.logical_or.reduce(ok[rows] & (np.abs(x[rows] - centre[:, None])
                                             <= half[:, None]), axis=-1) & (half <= widest)
    rows, centre, half = rows[single], centre[single], half[single]
    if not len(rows):
        return x.reshape(shape), ok.reshape(shape)
    n = 2 * POLY_DEGREE + 1
    u = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    where = np.zeros(len(x), bool)
    where[rows] = True
    local = resample((centre[:, None] + half[:, None] * u), where.reshape(shape[:-1]))
    v = polynomial_roots(rows_times(local, _poly_fit_matrix().T))       # (r, d) in u
    good = np.isfinite(v) & (np.abs(v.imag) < 1e-6) & (np.abs(v.real) <= 1.0)
    new = centre[:, None] + half[:, None] * np.where(good, v.real, 0.0)
    # the slot's real roots and the window's, ascending; at most d in all
    merged = np.concatenate([np.where(ok[rows], x[rows], np.inf), np.where(good, new, np.inf)],
                            -1)
    merged.sort(axis=-1)
    merged = merged[:, :shape[-1]]
    x[rows], ok[rows] = np.where(np.isfinite(merged), merged, 0.0), np.isfinite(merged)
    return x.reshape(shape), ok.reshape(shape)


def _multiple_roots(z, off, real):
    """The roots ``z (..., d)`` of a polynomial, each root that lies ``off (..., d)`` from
    the real ones' locus (the real axis, the unit circle) beyond ``real`` but within
    :data:`CLUSTER` replaced by the mean of the roots within ``3 off`` of it, where those
    are three or more and none of them is real.

    A real root of multiplicity ``m`` comes out of a companion matrix as ``m`` roots about
    ``eps^(1/m)`` around it (a point placed on axis b by a slide where both of joint b's
    roots meet: a fourfold root, 4e-4 off); the mean of such a cluster is good to rounding,
    and is real. Where the cluster holds a real root, that root stands for it (a mean
    beside it would be the same solution twice, a little apart after Newton's method) and
    its other real roots are roots of their own; a pair alone is a double root split by
    far less than ``real`` (``eps^(1/2)``) or a complex pair. A cluster's mean that is not
    a split real root is rejected by the FK check."""
    split = (off >= real) & (off < CLUSTER)
    if not np.count_nonzero(split):
        return z
    with np.errstate(invalid="ignore"):
        near = np.abs(z[..., :, None] - z[..., None, :]) <= 3.0 * off[..., :, None]
        mean = (near * z[..., None, :]).sum(-1) / np.maximum(near.sum(-1), 1)
    alone = ~np.logical_or.reduce(near & (off < real)[..., None, :], axis=-1)
    return np.where(split & alone & (near.sum(-1) >= 3), mean, z)


#: how far from the real roots' locus a root may lie and still be one of a real multiple
#: root split by rounding (:func:`_multiple_roots`; a fourfold root splits by ~1e-4)
CLUSTER = 1e-2


def _poly_fit_matrix() -> np.ndarray:
    """``(POLY_DEGREE + 1, samples)``: samples of a polynomial of that degree in ``y = x / span``
    at the Chebyshev points of :func:`samples` -> its coefficients, highest degree first."""
    n = 2 * POLY_DEGREE + 1
    y = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    V = np.vander(y, POLY_DEGREE + 1)                                      # highest first
    return np.linalg.pinv(V)
