"""3-vector helpers for the subproblems' single-vector hot paths.

Each is the arithmetic of its numpy counterpart (``numpy.cross``,
``numpy.linalg.norm``) for one 3-vector, without the per-call overhead of
broadcasting and axis handling, which dominated the subproblems' time.
"""

from __future__ import annotations

import math

import numpy as np


def cross3(a, b) -> np.ndarray:
    """``a x b`` (3,) of two 3-vectors."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def norm3(v) -> float:
    """Euclidean length of a 3-vector: ``sqrt(v . v)``, as numpy.linalg.norm computes it."""
    return math.sqrt(float(v @ v))
