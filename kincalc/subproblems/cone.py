"""Subproblem 4 on unit vectors, exact next to its double root ("two cones").

Find ``t`` with ``h . R(k, t) p = h . v`` for unit ``h``, ``p``, ``v``: the vector
``R(k, t) p`` sweeps a cone about ``k``, and must lie on the cone about ``h`` through
``v`` (the middle joint of a wrist: ``k`` its axis, ``p`` the third axis, ``v`` where the
rotation asks the third axis to be, ``h`` the first axis). As subproblem 4,
``C + r cos(t - b) = f`` with ``f = h . v``; the roots ``b +- delta``.

Next to ``v = +-h`` (the wrist singularity) ``1 -+ f`` is the square of a small
number, and ``arccos`` of a value near 1 is good only to sqrt(rounding), 1.5e-8 rad.
Here ``1 - f`` and ``1 + f`` come from ``P = |h x v|`` (``P^2 / (1 +- f)`` on their own
side), and the cone's reach of the lines ``+-h`` from the angles ``beta`` (from ``k``
to ``h``) and ``gamma`` (from ``k`` to ``p``): ``top = 1 - cos(beta - gamma)`` and
``bottom = 1 + cos(beta + gamma)`` as ``2 sin^2`` and ``2 cos^2`` of half angles. So
``delta`` is exact to the rounding of ``P``, up to the singularity.

Solutions: two; the least-squares angle when the cones do not meet (``exact`` False).

Ill-posed (``free``): ``v`` within ``aligned_tol`` (sine) of the line of ``h`` while
the cone of ``R(k, t) p`` holds that line (``top`` or ``bottom`` at most
``aligned_tol^2 / 2``): the aligned value (``b`` for ``v`` along ``h``, ``b + pi``
against it) in both slots, where the outer rotations about the one line are left free
(a continuum: the caller names it). ``r = 0`` (``p`` or ``h`` along ``k``): as
subproblem 4.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .solutions import (Solutions, as_vectors, cross, crossing, dot, norm, rows_times,
                        two_roots, two_slots)
from .sp4 import from_abc

#: the sine of the angle between ``v`` and the line of ``h`` below which a wrist counts
#: as singular (its outer axes on one line): a representative of the continuum then
#: misses the pose by at most about this (rad, and times the arm's size)
ALIGNED_TOL = 1e-10


class ConeConstants(NamedTuple):
    """What :func:`cone` needs of ``h, p, k`` alone (see :func:`cone_constants`)."""

    A: np.ndarray           # (...) the coefficients A cos t + B sin t + C of h . R(k, t) p
    B: np.ndarray
    C: np.ndarray
    rr: np.ndarray          # r = |(A, B)|, 1 where r is 0
    top: np.ndarray         # the cone's reach of the lines +-h (module docstring)
    bottom: np.ndarray
    degenerate: np.ndarray  # (...) bool: r <= 1e-12 ("r = 0")
    cb: np.ndarray          # cos and sin of the phase atan2(B, A): A / rr, B / rr
    sb: np.ndarray
    some_degenerate: bool   # degenerate somewhere; everywhere
    all_degenerate: bool
    h_cross: np.ndarray | None  # (3, 3): rows b @ h_cross = h x b, for a single h (else None)


def cone_constants(h, p, k) -> ConeConstants:
    """What :func:`cone` needs of ``h, p, k`` alone.

    A solver whose ``h, p, k`` are a robot's fixed axes computes these once and passes
    them to :func:`cone` as ``fixed``.

    Parameters
    ----------
    h, p, k : ndarray (..., 3)
        Unit vectors in one frame, as in :func:`cone` (numpy arrays: they are indexed,
        not converted); the leading shapes broadcast.

    Returns
    -------
    ConeConstants
        The coefficients ``A cos t + B sin t + C`` of ``h . R(k, t) p`` (each ``(...)``);
        ``rr`` (``r = |(A, B)|``, 1 where ``r`` is 0); the cone's reach ``top`` and
        ``bottom`` of the lines ``+-h`` (module docstring); ``degenerate`` (bool),
        ``r <= 1e-12`` ("``r = 0``"), and whether it is so somewhere, everywhere; the
        cosine and sine ``A / rr``, ``B / rr`` of the phase; and for a single ``h (3,)``
        the matrix crossing rows with it (:func:`~kincalc.subproblems.solutions.crossing`).
    """
    beta = np.arctan2(norm(cross(k, h)), dot(k, h))
    gamma = np.arctan2(norm(cross(k, p)), dot(k, p))
    kxp = cross(k, p)
    A = -dot(h, cross(k, kxp))
    B = dot(h, kxp)
    r = np.sqrt(A * A + B * B)
    degenerate = r <= 1e-12
    top = 2.0 * np.sin(0.5 * (beta - gamma)) ** 2
    bottom = 2.0 * np.cos(0.5 * (beta + gamma)) ** 2
    rr = np.where(degenerate, 1.0, r)
    some = int(np.count_nonzero(degenerate))
    return ConeConstants(A, B, dot(h, k) * dot(k, p), rr, top, bottom, degenerate, A / rr,
                         B / rr, some > 0, some == np.size(degenerate),
                         crossing(h) if h.ndim == 1 else None)


def cone(h, p, k, v, *, aligned_tol: float = ALIGNED_TOL, fixed=None) -> Solutions:
    """Solve ``h . R(k, t) p = h . v`` for unit vectors (see the module docstring).

    Parameters
    ----------
    h, p, k : array_like (..., 3)
        Unit vectors: the fixed axis, the vector turned, the rotation axis, in one
        frame; the leading shapes of all inputs broadcast.
    v : array_like (..., 3)
        Unit vector: where ``R(k, t) p`` must be, up to a rotation about ``h``.
    aligned_tol : float
        The sine of the angle between ``v`` and the line of ``h`` at most which the
        wrist counts as singular (``free``), when the cone holds that line.
    fixed : ConeConstants, optional
        :func:`cone_constants` of ``h, p, k``, when the caller has them.

    Returns
    -------
    Solutions
        Two slots, ``theta[0] (..., 2)`` in rad: ``b + delta`` and ``b - delta`` (the
        same value where ``free``), in (-pi, pi];
        where ``r = 0``, the answer of :func:`~kincalc.subproblems.sp4.from_abc`, in
        (-pi, pi]. ``ok (..., 2)``: slot 0 always, slot 1 when there are two distinct
        exact roots (not where the cones only touch, nor where ``free``).
        ``exact (..., 2)`` False for the least-squares angle (the cones do not meet; in
        slot 0). ``free (..., 2)``: the aligned (singular) case, with the value ``b`` or
        ``b + pi``; where ``r = 0``, as subproblem 4.

    Raises
    ------
    ValueError
        When an input is not of shape ``(..., 3)`` or the leading shapes do not
        broadcast.
    """
    h, p, k, v = as_vectors(h, p, k, v)
    fx = cone_constants(h, p, k) if fixed is None else fixed
    top, bottom, rr = fx.top, fx.bottom, fx.rr
    f = dot(h, v)
    if fx.all_degenerate:
        return from_abc(fx.A, fx.B, fx.C, f, 1.0)
    if fx.h_cross is None or v.ndim == 1:
        hv = cross(h, v)
    else:                               # h x v for a single h: cross's product, kept matrix
        hv = rows_times(v, fx.h_cross)
    P = np.sqrt(dot(hv, hv))
    up = f > 0
    far = 1.0 + np.abs(f)                 # 1 - f (f <= 0) or 1 + f (f >= 0): no cancellation
    near = P * P / far                    # the other one, exact next to +-h
    um = np.where(up, near, far) - top                  # r (1 - cos delta)
    wm = np.where(f < 0, near, far) - bottom            # r (1 + cos delta)
    exact = np.minimum(um, wm) >= -1e-9 * rr          # both (NaN in either: not exact)
    u, w = np.maximum(um, 0.0), np.maximum(wm, 0.0)
    n = np.maximum(u + w, 1e-300)
    cd, sd = (w - u) / n, 2.0 * np.sqrt(u * w) / n
    gap = 0.5 * aligned_tol ** 2
    aligned = P <= aligned_tol
    # one root where the cones only touch (delta 0 or pi: both roots are one
    # configuration), or a single aligned value; next to the singularity, where the cone
    # of R(k, t) p holds the line of h, delta is tiny but the two roots are two
    two = exact
    if np.count_nonzero(aligned):
        aligned &= np.where(up, top <= gap, bottom <= gap)
        cd = np.where(aligned, np.where(up, 1.0, -1.0), cd)
        sd = np.where(aligned, 0.0, sd)
        two = exact & ~aligned
        exact = exact | aligned
    theta, c, s = two_roots(fx.cb, fx.sb, cd, sd)
    touch = sd <= 1e-9
    if np.count_nonzero(touch):
        two = two & ~(touch & np.where(cd > 0, top > gap, bottom > gap))
    sol = Solutions((theta,), (c,), (s,), *two_slots(two, exact, aligned))
    if fx.some_degenerate:
        plain = from_abc(fx.A, fx.B, fx.C, f, 1.0)
        pick = lambda x, y: np.where(fx.degenerate[..., None], y, x)  # noqa: E731
        sol = Solutions((pick(sol.theta[0], plain.theta[0]),), (pick(sol.c[0], plain.c[0]),),
                        (pick(sol.s[0], plain.s[0]),), pick(sol.ok, plain.ok),
                        pick(sol.exact, plain.exact), pick(sol.free, plain.free))
    return sol
