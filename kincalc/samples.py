"""Configurations spread evenly over a box, the same in every run: for the robot-level
checks of a generic property (a Jacobian's generic rank, the degrees of a fitted
polynomial), which need configurations that are not special, not random ones.

Kronecker's sequence: point k is ``k alpha mod 1`` with ``alpha_j`` the fractional part of
the square root of the j-th prime. These are rationally independent, so no coordinate
repeats another and none sits on a grid (Weyl's equidistribution theorem; Kuipers &
Niederreiter, Uniform Distribution of Sequences, 1974). Not ``numpy.random``: importing it
is about 10 ms of every command's start.
"""

from __future__ import annotations

import numpy as np


def spread(m: int, lo, hi) -> np.ndarray:
    """``m`` points of the box ``[lo, hi)`` spread evenly (see the module docstring).

    Parameters
    ----------
    m : int
        How many.
    lo, hi : array_like (n,)
        The box's corners (finite), in any unit.

    Returns
    -------
    ndarray (m, n)
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    n = lo.size
    primes = []
    k = 2
    while len(primes) < n:
        if all(k % p for p in primes):
            primes.append(k)
        k += 1
    alpha = np.sqrt(np.array(primes, float)) % 1.0
    u = (np.arange(1, m + 1)[:, None] * alpha + 0.5) % 1.0
    return lo + u * (hi - lo)
