"""Subproblem 4: a rotated vector's component along a direction.

Find ``theta`` with ``h . R(k, theta) p = d`` (Elias & Wen, IK-Geo, 2022, subproblem
4; Paden-Kahan's subproblem 3 reduces to it). By Rodrigues,
``h . R p = A cos(theta) + B sin(theta) + C`` with ``A = h . (p - (k . p) k)``,
``B = h . (k x p)``, ``C = (h . k)(k . p)``; with ``r = hypot(A, B)`` and
``cos(delta) = (d - C) / r`` the solutions are ``theta = atan2(B, A) +- delta``.

Solutions: two; one at the tangent, where both coincide (the pose is then singular:
the value is only good to about sqrt(rounding) of the inputs, and values within
rounding of the tangent are taken as the tangent itself, so that an exactly singular
problem gets its double root to rounding and not two copies either side, and so does
one beyond the tangent by at most ``REACH``); none when ``|d - C| > r``: then the
least-squares angle (``atan2(B, A)``, or the opposite direction when ``d < C``) with
``exact`` False.

Ill-posed: ``r = 0`` (``h`` along ``k``, or ``p`` on the axis): every angle solves it
when ``C = d`` (to 1e-9 of the scale, or a caller's ``free_reach``: ``theta = 0``, ``free``
True, ``exact`` True) and none otherwise (``free`` True, ``exact`` False).

The cosines and sines of the roots come from the algebra: ``cos(base +- delta)`` from
``cos base = A / r``, ``sin base = B / r``, ``cos delta`` and ``sin delta = sqrt(1 -
cos^2)``, no trigonometric call.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..tolerances import ACCEPT_POSITION
from .solutions import (Solutions, as_vectors, cross, crossing, dot, norm, rows_times,
                        two_roots, two_slots)

#: rounding of a cosine computed from lengths of size ``scale``, per unit of
#: ``scale / r`` (a few dozen float64 epsilons): the band of the tangent
ROUNDING = 64 * np.finfo(float).eps

#: a right-hand side beyond the tangent by at most this (of ``scale``) still has its double
#: root: the IK acceptance (``kincalc.tolerances.ACCEPT_POSITION``), so that a target made from
#: joints a hair from a singular configuration, whose tangent the rounding of a near-singular
#: step before it pushed past, gets its candidate and the FK check decides (else none)
REACH = ACCEPT_POSITION


class Sp4Constants(NamedTuple):
    """What :func:`sp4` needs of ``h`` and ``k`` alone (see :func:`sp4_constants`)."""

    h: np.ndarray           # (..., 3) the direction, as a float array
    k: np.ndarray           # (..., 3) the unit axis, as a float array
    hk: np.ndarray          # (...) h . k
    h_norm: np.ndarray      # (...) |h|
    kx: np.ndarray | None   # (3, 3) the matrix crossing rows with a single k, else None


def sp4_constants(h, k) -> Sp4Constants:
    """What :func:`sp4` needs of ``h`` and ``k`` alone.

    A solver whose ``h`` and ``k`` are fixed vectors (a robot's axes) computes these once
    and passes them to :func:`sp4` as ``fixed``.

    Parameters
    ----------
    h, k : array_like (..., 3)
        As in :func:`sp4`.

    Returns
    -------
    Sp4Constants
        ``h``, ``k``, ``h . k``, ``|h|`` and, for a single ``k (3,)``, the matrix crossing
        rows with it (:func:`~kincalc.subproblems.solutions.crossing`), computed as
        :func:`sp4` computes them (the same bits).
    """
    h, k = as_vectors(h, k)
    return Sp4Constants(h, k, dot(h, k), norm(h), crossing(k) if k.ndim == 1 else None)


def sp4(h, p, k, d, *, tol: float = 1e-12, scale=None, fixed=None) -> Solutions:
    """Solve subproblem 4, ``h . R(k, theta) p = d``, for every problem of a batch.

    Parameters
    ----------
    h : array_like (..., 3)
        The direction of the component (any length).
    p : array_like (..., 3)
        The vector rotated (from a point of the axis).
    k : array_like (..., 3)
        Unit rotation axis. ``h``, ``p``, ``k`` in one frame; their leading shapes
        broadcast.
    d : array_like (...)
        The component to reach, in the unit of ``h . p`` (broadcast against the
        vectors' leading shape: one geometry may take many ``d``).
    tol : float
        Relative tolerance (of ``scale``) of "``r`` is zero" and of how far beyond the
        tangent a problem still counts as solved (at least :data:`REACH`).
    scale : array_like (...), optional
        The size of the terms ``d`` was computed from, the unit of the tolerances;
        default ``max(|h| |p|, |d|)``. A ``d`` obtained by cancellation (subproblem
        3's law of cosines) carries the rounding of its terms, not of its value.
    fixed : Sp4Constants, optional
        ``sp4_constants(h, k)``, for a caller whose ``h`` and ``k`` are fixed vectors:
        what depends on them alone is then read from it, not computed again (``h`` and
        ``k`` are not read; the same result).

    Returns
    -------
    Solutions
        Two slots, as :func:`from_abc`: ``theta[0] (..., 2)`` in rad, in (-pi, pi],
        ``base + delta`` and ``base - delta``. ``ok (..., 2)``: slot 0 always, slot 1
        when there are two distinct exact roots. ``exact (..., 2)`` False for the
        least-squares angle (in slot 0). ``free (..., 2)``: ``r = 0``, ``theta = 0``
        (``exact`` where every angle solves it, else no angle does).

    Raises
    ------
    ValueError
        When a vector is not of shape ``(..., 3)`` or the shapes do not broadcast.
    """
    if fixed is None:
        h, p, k = as_vectors(h, p, k)
    else:
        (p,), h = as_vectors(p), fixed.h
    A, B, C = coefficients(h, p, k, fixed=fixed)
    d = np.asarray(d, float)      # broadcast with the vectors' leading shape by from_abc
    if scale is None:
        scale = np.maximum((norm(h) if fixed is None else fixed.h_norm) * norm(p), np.abs(d))
    return from_abc(A, B, C, d, scale, tol=tol)


def coefficients(h, p, k, *, fixed=None) -> tuple:
    """The coefficients of ``h . R(k, theta) p = A cos(theta) + B sin(theta) + C``.

    ``A = h . (p - (k . p) k)``, ``B = h . (k x p)``, ``C = (h . k)(k . p)`` (Rodrigues'
    formula dotted with ``h``).

    Parameters
    ----------
    h, p, k : ndarray (..., 3)
        As in :func:`sp4` (float arrays; ``h`` and ``k`` not read with ``fixed``).
    fixed : Sp4Constants, optional
        ``sp4_constants(h, k)``.

    Returns
    -------
    A, B, C : ndarray (...)
        In the unit of ``h . p``.
    """
    if fixed is None:
        hk, kxp = dot(h, k), cross(k, p)
    else:
        h, k, hk, _, kx = fixed
        # k x p as cross() makes it for a single k: rows times the crossing matrix
        kxp = cross(k, p) if kx is None or p.ndim == 1 else rows_times(p, kx)
    kp = dot(k, p)
    return dot(h, p - kp[..., None] * k), dot(h, kxp), hk * kp


class AbcConstants(NamedTuple):
    """Fixed coefficients of :func:`from_abc` and what it needs of them alone
    (see :func:`abc_constants`)."""

    A: np.ndarray           # (...) the coefficients, as float arrays
    B: np.ndarray
    C: np.ndarray
    r: np.ndarray           # (...) hypot(A, B), as sqrt(A A + B B)
    cb: np.ndarray          # (...) A / r and B / r: the phase's cosine and sine where r > 0
    sb: np.ndarray


def abc_constants(A, B, C) -> AbcConstants:
    """What :func:`from_abc` needs of fixed coefficients ``A, B, C`` alone.

    A solver whose coefficients are a robot's constants (a law of cosines, a height)
    computes these once and passes them to :func:`from_abc` as ``fixed``.

    Parameters
    ----------
    A, B, C : array_like (...)
        As in :func:`from_abc`.

    Returns
    -------
    AbcConstants
        The coefficients, ``r`` and the phase's cosine and sine, computed as
        :func:`from_abc` computes them (the same bits).
    """
    A, B, C = [np.asarray(v, float) for v in (A, B, C)]
    r = np.sqrt(A * A + B * B)
    with np.errstate(divide="ignore", invalid="ignore"):     # r = 0: not read
        return AbcConstants(A, B, C, r, A / r, B / r)


def from_abc(A, B, C, d, scale, *, tol: float = 1e-12, fixed=None,
             free_reach: float = 1e-9) -> Solutions:
    """Subproblem 4 in its coefficients: ``A cos(theta) + B sin(theta) + C = d``.

    For solvers that have the coefficients from constants of the robot (a height along
    an axis, a law of cosines) rather than the vectors ``h``, ``p``, ``k``.

    Parameters
    ----------
    A, B, C, d : array_like (...)
        Coefficients and right-hand side, in one unit (the shapes broadcast).
    scale : array_like (...)
        The size of the terms, the unit of the tolerances (floored at 1e-300).
    tol : float
        Relative tolerance (of ``scale``) of "``r = hypot(A, B)`` is zero" and of how
        far beyond the tangent (``|d - C| <= r + max(tol, REACH) * scale``) a problem
        still counts as solved (its double root).
    fixed : AbcConstants, optional
        ``abc_constants(A, B, C)``, for fixed coefficients: what depends on them alone
        is then read from it, not computed again (``A, B, C`` are not read; the same
        result).
    free_reach : float
        Relative tolerance (of ``scale``) of ``C = d`` where ``r`` is zero: a caller whose
        ``d`` carries the rounding of a double root taken before widens it.

    Returns
    -------
    Solutions
        Two slots, ``theta[0] (..., 2)`` in rad, in (-pi, pi]: ``base + delta`` and
        ``base - delta``, ``base = atan2(B, A)``. ``ok (..., 2)``: slot 0 always, slot 1
        when there are two distinct exact roots (not at the tangent, within rounding).
        ``exact (..., 2)``: ``|d - C| <= r`` within the tolerance, else slot 0 holds the
        least-squares angle (``base``, or ``base + pi`` when ``d < C``). ``free (..., 2)``:
        ``r`` is zero; ``theta = 0``, ``exact`` where ``|d - C| <= free_reach * scale``
        (every angle solves it), else no angle does.

    Raises
    ------
    ValueError
        When the shapes do not broadcast.
    """
    if fixed is None:
        A, B, C, d = [np.asarray(v, float) for v in (A, B, C, d)]
        r = np.sqrt(A * A + B * B)
    else:
        (A, B, C, r, cb, sb), d = fixed, np.asarray(d, float)
    scale = np.maximum(scale, 1e-300)
    band = tol * scale
    reach = max(tol, REACH) * scale            # how far beyond the tangent is still exact
    free = r < band
    dC = d - C
    some_free = np.count_nonzero(free)
    if some_free:                       # r = 0: the angle is anyone's; 1 and 0 stand in
        rr = np.where(free, 1.0, r)
        cb, sb = np.where(free, 1.0, A / rr), np.where(free, 0.0, B / rr)
        cd = dC / rr
        far = np.abs(cd)
        # exactness from the cosine as computed, before the tangent band moves it to +-1
        exact = np.where(free, np.abs(dC) <= free_reach * scale, far <= 1.0 + reach / rr)
    else:
        rr = r
        if fixed is None:
            cb, sb = A / r, B / r
        cd = dC / r
        far = np.abs(cd)
        exact = far <= 1.0 + reach / r
    # a cosine within rounding of +-1 is the tangent: one (double) root (and beyond +-1
    # the least-squares end, also +-1); every other cosine is inside (-1, 1) already
    tangent = far >= 1.0 - ROUNDING * scale / rr
    if np.count_nonzero(tangent):
        cd = np.where(tangent, np.sign(cd), cd)
    if some_free:
        cd = np.where(free, 1.0, cd)
    sd = np.sqrt(1.0 - cd * cd)
    theta, c, s = two_roots(cb, sb, cd, sd)
    two = exact & (sd > 0.0)
    if some_free:
        two &= ~free
    return Solutions((theta,), (c,), (s,), *two_slots(two, exact, free))


def shared_roots(A, B, C, unit) -> Solutions:
    """The angle two equations ``A_i cos(theta) + B_i sin(theta) + C_i = 0`` (``i = 0, 1``)
    share: both roots of the one that depends on ``theta`` the most (:func:`from_abc`), the
    one the other equation leaves the smaller residual first.

    Two equations of one angle hold together at one root, or at both where they are nearly
    proportional (two invariants of a point turned about axes that are nearly parallel):
    solving them together, ``(cos, sin)`` from their 2 x 2 system, divides by how much they
    differ, and keeps one root only.

    Parameters
    ----------
    A, B, C : array_like (2, ...)
        The equations' coefficients (the first axis: the equation); the shapes broadcast.
    unit : sequence of 2 floats
        Each equation's unit (a length, a squared length), by which its dependence on
        ``theta``, ``hypot(A_i, B_i)``, is compared and its tolerances scaled.

    Returns
    -------
    Solutions
        Two slots ``(..., 2)`` as :func:`from_abc`'s (slot 1 where there are two distinct
        exact roots, least-squares where there is none), ordered by the other equation's
        residual.
    """
    A, B, C = (np.asarray(v, float) for v in (A, B, C))
    one = np.hypot(A[1], B[1]) * unit[0] >= np.hypot(A[0], B[0]) * unit[1]

    def pick(v, w=one):
        return np.where(w, v[1], v[0])
    sol = from_abc(pick(A), pick(B), pick(C), 0.0, np.where(one, unit[1], unit[0]))
    c, s = sol.c[0], sol.s[0]
    other = np.abs(pick(C, ~one)[..., None] + pick(A, ~one)[..., None] * c
                   + pick(B, ~one)[..., None] * s)
    swap = ((other[..., 1] < other[..., 0]) & sol.ok[..., 1])[..., None]
    return Solutions(tuple(np.where(swap, x[..., ::-1], x) for x in (sol.theta[0],)),
                     (np.where(swap, c[..., ::-1], c),), (np.where(swap, s[..., ::-1], s),),
                     sol.ok, sol.exact, sol.free)
