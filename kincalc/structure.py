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

    The z axis and origin of each frame of :func:`kincalc.fk.chain_frames`, i.e. of
    ``F_0 J_1 F_1 ... F_{i-1} J_i(q_i)``; for a prismatic joint the axis is its direction
    of motion.

    Parameters
    ----------
    robot : Robot
        The robot; only ``robot.dof`` and ``robot.chain`` are used.
    q : array_like (n,), optional
        One configuration (rad / m), not a batch. Default: zeros.

    Returns
    -------
    directions : ndarray (n, 3)
        Unit axis of each joint, in the world frame.
    points : ndarray (n, 3)
        A point on each axis (m), in the world frame.

    Raises
    ------
    ValueError
        If the last dimension of ``q`` is not ``n`` (from :func:`kincalc.fk.chain_frames`).
    """
    from .fk import chain_frames
    q = np.zeros(robot.dof) if q is None else np.asarray(q, dtype=float)
    frames = chain_frames(robot.chain, q)
    return frames[:, :3, 2].copy(), frames[:, :3, 3].copy()


def parallel(d1, d2, tol: float = GEOMETRY_TOL) -> bool:
    """True if unit directions ``d1``, ``d2`` are parallel or anti-parallel.

    Parameters
    ----------
    d1, d2 : array_like (3,)
        Unit vectors (not normalised here), in one frame.
    tol : float, optional
        Bound on ``|d1 x d2|``, the sine of their angle (default ``GEOMETRY_TOL``, 1e-9).

    Returns
    -------
    bool
        ``|d1 x d2| < tol``.
    """
    return float(np.linalg.norm(cross(d1, d2))) < tol


def point_line_distance(x, p, d) -> float:
    """Distance from point ``x`` to the line ``p + t d`` (``d`` unit).

    Parameters
    ----------
    x, p : array_like (3,)
        The point and a point of the line (m), in one frame.
    d : ndarray (3,)
        Unit direction of the line (not normalised here); an ndarray, not a list.

    Returns
    -------
    float
        The distance (m): the norm of ``x - p`` less its component along ``d``.
    """
    w = np.asarray(x, float) - np.asarray(p, float)
    d = np.asarray(d, float)
    return float(np.linalg.norm(w - d * (w @ d)))


def common_point(points, dirs, tol: float) -> np.ndarray | None:
    """The point where all lines ``points[k] + t dirs[k]`` meet, or ``None``.

    Least-squares intersection: the point minimising the sum of squared distances to the
    lines, accepted when every line passes within ``tol`` of it.

    Parameters
    ----------
    points : array_like (k, 3)
        A point on each line (m), in one frame.
    dirs : array_like (k, 3)
        Unit direction of each line (not normalised here).
    tol : float
        Largest accepted distance (m) from the point to any line; ``np.inf`` accepts the
        least-squares point whatever it is.

    Returns
    -------
    ndarray (3,) or None
        The common point (m), in the lines' frame. ``None`` when a line misses it by ``tol``
        or more, and when there is no unique point: no lines, a single line, parallel-only
        sets, and nearly parallel ones (the smallest singular value of ``sum(I - d d^T)``
        below 1e-6; for two lines, closer than about 1.4e-3 rad to parallel).
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

    The centre at a configuration comes from :func:`wrist_centre`.

    Attributes
    ----------
    first : int
        The 0-based index of the wrist's first joint.
    """

    first: int


def spherical_wrist(robot) -> Wrist | None:
    """The robot's spherical wrist (last three revolute axes concurrent), if any.

    Parameters
    ----------
    robot : Robot
        The robot. Its axes are tested at ``robot.home`` (not at q = 0), to within
        ``GEOMETRY_TOL * 1e3 * robot.characteristic_length`` (m) of one point.

    Returns
    -------
    Wrist or None
        ``Wrist(first=n - 3)``; ``None`` if the robot has fewer than four joints, if one of
        its last three joints is prismatic, or if their axes do not meet at one point.
    """
    n = robot.dof
    if n < 4 or not all(j.revolute for j in robot.joints[n - 3:]):
        return None
    dirs, pts = joint_axes(robot, robot.home)
    tol = GEOMETRY_TOL * 1e3 * robot.characteristic_length
    if common_point(pts[n - 3:], dirs[n - 3:], tol) is None:
        return None
    return Wrist(first=n - 3)


def wrist_centre(robot, wrist: Wrist, dirs, pts) -> np.ndarray | None:
    """The wrist centre (world frame, m) given the axes at a configuration.

    Parameters
    ----------
    robot : Robot
        Not used.
    wrist : Wrist
        From :func:`spherical_wrist`.
    dirs, pts : ndarray (n, 3)
        The joint axes at the configuration, as :func:`joint_axes` gives them (world frame;
        ``pts`` in m).

    Returns
    -------
    ndarray (3,) or None
        The least-squares common point of the wrist's three axes (:func:`common_point` with
        ``tol = inf``: not checked to lie on them), or ``None`` if those axes are (nearly)
        all parallel.
    """
    f = wrist.first
    return common_point(pts[f:f + 3], dirs[f:f + 3], np.inf)
