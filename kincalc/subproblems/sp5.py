"""Subproblem 5: three rotations closing a loop of two circles ("three cones").

Find ``(theta1, theta2, theta3)`` with ::

    p0 + R(k1, theta1) p1 = R(k2, theta2) (p2 + R(k3, theta3) p3)

for unit axes through the origin (Elias & Wen, "IK-Geo", arXiv:2211.05737,
2022, subproblem 5). The left side runs over a circle C1 (axis ``k1``), the
bracket on the right over a circle C3 (axis ``k3``). A point ``v1`` of C1
and a point ``v3`` of C3 are related by a rotation about ``k2`` exactly when
they have the same height along ``k2`` and the same distance from the
origin. With ``v = c + A (cos theta, sin theta)`` both conditions are linear
in ``(cos theta1, sin theta1, cos theta3, sin theta3)``:

    k2 . v1 = k2 . v3,        |v1|^2 = |v3|^2,

which is the two-ellipse problem of subproblem 6: a quartic, up to four
solutions. ``theta2`` then follows from subproblem 1 (``R(k2, theta2) v3 =
v1``). Unlike IK-Geo's own formulation (a quartic in the height), this one
needs no assumption on the axes (``k1`` or ``k3`` may be parallel to ``k2``).

No least-squares answer is defined: when there is no exact solution the
list is empty and ``exact=False``.

Ill-posed (``free=True``):

* ``p1`` on the axis ``k1`` (C1 is a point: ``theta1`` is free), likewise
  ``p3`` on ``k3``;
* a circle coaxial with ``k2`` (``theta2`` and that circle's angle are
  redundant);
* both circles at constant height along ``k2`` (``k1 || k2`` and
  ``k3 || k2``), or both at constant distance from the origin (``p0 || k1``
  and ``p2 || k3``): one condition is void, a curve of solutions or none;
* the meeting point on the axis ``k2`` (``theta2`` is free). This one is a
  double root of the quartic: its angles come out to only about 1e-6 rad, and
  a point within ``AXIS_TOL`` of the axis is reported free.

Where the solutions form a curve, one point of it is returned.
"""

from __future__ import annotations

import numpy as np

from ..spatial import cross

from ..tolerances import GEOMETRY_TOL
from ._unit_pair import _wrap, solve_unit_pair
from .sp1 import sp1

#: relative distance from the axis k2 below which theta2 counts as free. A
#: meeting point on that axis is a double root of the quartic, found only to
#: about sqrt(machine eps); the same bound caps the loop's closing error.
AXIS_TOL = 1e-6


def _circle(offset, k, p):
    """Centre ``c`` (3,) and basis ``A`` (3, 2) with ``offset + R(k, t) p = c + A (cos t, sin t)``.

    The columns of ``A`` are orthogonal, both of length ``|k x p|``.
    """
    kp = k @ p
    return offset + kp * k, np.column_stack([p - kp * k, cross(k, p)])


def _rot(k, t):
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * (K @ K)


def sp5(p0, p1, p2, p3, k1, k2, k3, tol: float = GEOMETRY_TOL):
    """Solve subproblem 5 for all ``(theta1, theta2, theta3)``.

    Parameters
    ----------
    p0, p1, p2, p3 : array_like (3,)
        Vectors of the loop ``p0 + R1 p1 = R2 (p2 + R3 p3)``, in one length unit.
    k1, k2, k3 : array_like (3,)
        Unit rotation axes through the origin.
    tol : float
        Relative tolerance of the degeneracy tests (point on an axis, parallel
        conditions), relative to the largest of ``|p0|, ..., |p3|``.

    Returns
    -------
    solutions : list of tuple(float, float, float)
        Up to four ``(theta1, theta2, theta3)`` in rad, each in (-pi, pi].
    exact : bool
        True when ``solutions`` is non-empty; False (with an empty list) when
        there is no solution.
    free : bool
        True when the problem is ill-posed (see the module docstring).

    References
    ----------
    A. Elias, J. Wen, "IK-Geo: Unified robot inverse kinematics using
    subproblem decomposition", arXiv:2211.05737, 2022, sec. on subproblem 5.
    """
    p0, p1, p2, p3, k1, k2, k3 = (np.asarray(v, dtype=float).reshape(3)
                                  for v in (p0, p1, p2, p3, k1, k2, k3))
    L = max(float(np.linalg.norm(v)) for v in (p0, p1, p2, p3))
    if L == 0.0:
        return [(0.0, 0.0, 0.0)], True, True
    c1, A1 = _circle(p0, k1, p1)
    c3, A3 = _circle(p2, k3, p3)
    r1sq, r3sq = float(A1[:, 0] @ A1[:, 0]), float(A3[:, 0] @ A3[:, 0])
    # heights along k2 agree; squared norms agree (divided by 2L to keep the
    # two rows in one unit)
    M = np.array([np.concatenate([A1.T @ k2, -(A3.T @ k2)]),
                  np.concatenate([A1.T @ c1, -(A3.T @ c3)]) / L])
    b = np.array([k2 @ (c3 - c1),
                  (c3 @ c3 + r3sq - c1 @ c1 - r1sq) / (2 * L)])
    pairs, _, free = solve_unit_pair(M, b, L, tol)
    # a circle shrunk to a point: its angle does nothing
    free = free or min(r1sq, r3sq) <= (tol * L) ** 2

    solutions = []
    for t1, t3 in pairs:
        v1 = c1 + A1 @ np.array([np.cos(t1), np.sin(t1)])
        v3 = c3 + A3 @ np.array([np.cos(t3), np.sin(t3)])
        t2, _, free2 = sp1(v3, v1, k2, tol)
        residual = np.linalg.norm(p0 + _rot(k1, t1) @ p1
                                  - _rot(k2, t2) @ (p2 + _rot(k3, t3) @ p3))
        if residual > AXIS_TOL * L:
            continue
        near_axis = np.linalg.norm(v1 - (k2 @ v1) * k2) <= AXIS_TOL * L
        free = bool(free or free2 or near_axis)
        solutions.append((_wrap(t1), _wrap(t2), _wrap(t3)))
    return solutions, bool(solutions), free
