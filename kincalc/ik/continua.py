"""The relations a singular target leaves between joints, as data: the continua the solvers
mark (``Branches.extra["continuum"]``, ``["parallel continuum"]``), and where no sum is
fixed the joints that follow a free one (read from the Jacobian), which
:mod:`kincalc.ik.solve` hands to the results. Angles in rad, joints 0-based; worded at the
edge (:func:`kincalc.analysis.words.continuum_text`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..jacobian import scale_free



class Continuum(NamedTuple):
    """At a singular target joints ``i`` and ``j`` (0-based) turn the tool about one
    line: only ``q_i + sign q_j`` is fixed, to ``total`` (rad); ``total`` None when the
    solver does not name the combination."""

    i: int
    j: int
    sign: int
    total: float | None = None


class ParallelContinuum(NamedTuple):
    """A three-parallel arm at its wrist singularity: joints ``joints`` (0-based) turn
    about parallel axes, so only ``sum(sign_k q_k)`` is fixed, to ``total`` (rad).
    Joint ``free`` can take any value the elbow can follow. The others follow it: the
    sum, and the planar elbow placing axis 4."""

    joints: tuple
    signs: tuple
    free: int
    total: float


class Followers(NamedTuple):
    """At a singular target joint ``free`` (0-based) can take any value, and joints
    ``joints`` change with it to keep the target, by no relation of sums: the wrist of an
    arm whose wrist centre lies on axis 1, which turns the wrist's orientation with joint
    1. Found from the Jacobian at the solution, on the robot's own chain (:func:`followers`;
    never reversed)."""

    free: int
    joints: tuple


def followers(J, free, length: float, revolute) -> tuple:
    """The joints that must move with joint ``free`` to keep a target, to first order.

    Parameters
    ----------
    J : ndarray (r, n)
        The target's rows of the geometric Jacobian at the solution (linear rows, m per
        rad or m per m, first; angular rows after them), world frame.
    free : sequence of int
        The joints the target leaves free (0-based); the first is turned.
    length : float
        The arm's size (m): linear rows are divided by it, prismatic columns multiplied.
    revolute : ndarray (n,) of bool

    Returns
    -------
    tuple of int
        The joints other than ``free`` whose least-squares change, for a unit turn of the
        first free joint, is above 1e-6 (rad per rad, or of the arm's size): those that
        follow it. Empty where it moves alone (the target does not see it).
    """
    J = scale_free(J, revolute, max(length, 1e-12))
    rest = [j for j in range(J.shape[1]) if j not in free]
    x = np.linalg.lstsq(J[:, rest], -J[:, free[0]], rcond=1e-10)[0]
    return tuple(j for j, v in zip(rest, x.tolist()) if abs(v) > 1e-6)
