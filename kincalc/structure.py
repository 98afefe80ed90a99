"""Geometric facts about a robot's joint axes: parallel, intersecting, wrists.

Everything is computed from the joint axes (directions and points in the
world frame), never from a robot's name. Used to name singularities now and
to choose inverse-kinematics solvers later.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .spatial import cross

from .tolerances import GEOMETRY_TOL


def joint_axes(robot, q=None) -> tuple[np.ndarray, np.ndarray]:
    """World-frame joint axes at ``q`` (default: zero).

    Returns
    -------
    directions : ndarray (n, 3)
        Unit axis of each joint.
    points : ndarray (n, 3)
        A point on each axis (m).
    """
    from .fk import chain_frames
    q = np.zeros(robot.dof) if q is None else np.asarray(q, dtype=float)
    frames = chain_frames(robot.chain, q)
    return frames[:, :3, 2].copy(), frames[:, :3, 3].copy()


def parallel(d1, d2, tol: float = GEOMETRY_TOL) -> bool:
    """True if unit directions ``d1``, ``d2`` are parallel or anti-parallel."""
    return float(np.linalg.norm(cross(d1, d2))) < tol


def point_line_distance(x, p, d) -> float:
    """Distance from point ``x`` to the line ``p + t d`` (``d`` unit)."""
    w = np.asarray(x, float) - np.asarray(p, float)
    return float(np.linalg.norm(w - d * (w @ d)))


def common_point(points, dirs, tol: float) -> np.ndarray | None:
    """The point where all lines ``points[k] + t dirs[k]`` meet, or ``None``.

    Least-squares intersection; accepted when every line passes within
    ``tol`` of it. Parallel-only sets (no unique point) return ``None``.
    """
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for p, d in zip(points, dirs):
        P = np.eye(3) - np.outer(d, d)
        A += P
        b += P @ p
    if np.linalg.svd(A, compute_uv=False)[-1] < 1e-6:
        return None
    x = np.linalg.solve(A, b)
    if all(point_line_distance(x, p, d) < tol for p, d in zip(points, dirs)):
        return x
    return None


@dataclass(frozen=True)
class Wrist:
    """A spherical wrist: the last three joints, revolute, with axes meeting at a point.

    ``first`` is the 0-based index of the wrist's first joint; the centre at a
    configuration comes from :func:`wrist_centre`.
    """

    first: int


def spherical_wrist(robot) -> Wrist | None:
    """The robot's spherical wrist (last three revolute axes concurrent), if any."""
    n = robot.dof
    if n < 4 or not all(j.revolute for j in robot.joints[n - 3:]):
        return None
    dirs, pts = joint_axes(robot, robot.home)
    tol = GEOMETRY_TOL * 1e3 * robot.characteristic_length
    if common_point(pts[n - 3:], dirs[n - 3:], tol) is None:
        return None
    return Wrist(first=n - 3)


def wrist_centre(robot, wrist: Wrist, dirs, pts) -> np.ndarray:
    """The wrist centre (world frame, m) given the axes at a configuration."""
    f = wrist.first
    return common_point(pts[f:f + 3], dirs[f:f + 3], np.inf)
