"""The one return type of the subproblems: a solution set per problem of a batch.

IK-Geo's subproblems return their solutions with a least-squares flag; here every
subproblem solves a whole batch of problems (inputs with any leading shape ``...``)
and returns a :class:`Solutions` with a fixed number ``k`` of slots per problem:

* ``theta``: a tuple with one array ``(..., k)`` per unknown angle (rad, in
  (-pi, pi]); ``c`` and ``s`` their cosines and sines, obtained from the algebra
  (a family solver composes rotations from them without calling trigonometry);
* ``ok (..., k)``: the slot holds an answer (a problem with one solution fills one
  slot; a double root fills one);
* ``exact (..., k)``: the answer solves the equations (else it is the least-squares
  answer the module describes);
* ``free (..., k)``: the problem is ill-posed there: an angle is undetermined (a
  point on the axis, ...) and the answer shows one representative, 0.

Slots that are not ``ok`` hold finite numbers (0) that mean nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Solutions:
    """The solutions of one subproblem for a batch of problems (see the module)."""

    theta: tuple
    c: tuple
    s: tuple
    ok: np.ndarray
    exact: np.ndarray
    free: np.ndarray

    @property
    def slots(self) -> int:
        """The number ``k`` of solution slots per problem."""
        return self.ok.shape[-1]

    def rows(self, index=()) -> list:
        """The answers of one problem (``index`` into the leading shape) as a list of
        tuples of angles, for reading and testing: ``[(theta1, theta2, ...), ...]``."""
        ok = self.ok[index]
        return [tuple(float(t[index][j]) for t in self.theta) for j in np.flatnonzero(ok)]


def principal(theta) -> np.ndarray:
    """Angles from ``arctan2`` in (-pi, pi]: ``-pi`` (a sine of -0 or of -1e-17 with a
    cosine of -1) becomes ``pi``."""
    return np.where(theta == -np.pi, np.pi, theta)


def angles(c, s) -> tuple:
    """``(theta, c, s)`` tuples of one unknown from unnormalised cosine and sine parts
    ``c, s (..., k)`` (a direction in the plane; the zero vector gives angle 0)."""
    n = np.sqrt(c * c + s * s)
    zero = n == 0.0
    n = np.where(zero, 1.0, n)
    cn = np.where(zero, 1.0, c / n)
    sn = np.where(zero, 0.0, s / n)
    return principal(np.arctan2(sn, cn)), cn, sn


def pair(a, b) -> np.ndarray:
    """``np.stack([a, b], -1)`` for two arrays that broadcast together: the two slots of a
    subproblem's roots (written into one new array; ``np.stack`` costs several times as
    much on the small batches of a single pose)."""
    out = np.empty(np.broadcast(a, b).shape + (2,), np.result_type(a, b))
    out[..., 0] = a
    out[..., 1] = b
    return out


def dot(a, b) -> np.ndarray:
    """``a . b`` over the last axis of ``(..., 3)`` arrays (broadcasting), by components
    (``(a * b).sum(-1)`` is six times slower on large batches)."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def cross(a, b) -> np.ndarray:
    """``a x b`` for ``(..., 3)`` arrays (broadcasting), written into one new array
    (stacking the components costs four times as much)."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast(a, b).shape)
    np.multiply(a1, b2, out=out[..., 0])
    out[..., 0] -= a2 * b1
    np.multiply(a2, b0, out=out[..., 1])
    out[..., 1] -= a0 * b2
    np.multiply(a0, b1, out=out[..., 2])
    out[..., 2] -= a1 * b0
    return out


def norm(a) -> np.ndarray:
    return np.sqrt(dot(a, a))


def as_vectors(*vs):
    """The inputs as float arrays ``(..., 3)`` whose leading shapes broadcast together.
    They are not broadcast here: a fixed axis ``(3,)`` given with a batch of points
    stays one vector, so that what depends on it alone is computed once."""
    arrays = [np.asarray(v, dtype=float) for v in vs]
    for a in arrays:
        if a.shape[-1:] != (3,):
            raise ValueError(f"expected vectors of shape (..., 3), got {a.shape}")
    np.broadcast(*arrays)               # raises when the leading shapes do not broadcast
    return arrays

