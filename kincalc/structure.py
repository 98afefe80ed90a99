"""Geometric facts about a robot's joint axes: parallel, intersecting, wrists.

Everything is computed from the joint axes (directions and points in the
world frame), never from a robot's name. Used to name singularities and to
recognise the inverse-kinematics families (:mod:`kincalc.ik.families`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .spatial import cross

from .tolerances import GEOMETRY_TOL, STRUCTURE_POINT_TOL


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


class Wrist(NamedTuple):
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
        The robot. Its axes are tested at ``robot.home`` (not at q = 0), to within the
        tolerance by which the IK families recognise a wrist
        (:func:`kincalc.ik.families.classify`): the robot's ``structure_tol``, else
        ``STRUCTURE_POINT_TOL``, times its characteristic length or 1 m, whichever is larger.

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
    tol = getattr(robot, "structure_tol", None)
    tol = (STRUCTURE_POINT_TOL if tol is None else tol) * max(robot.characteristic_length, 1.0)
    if common_point(pts[n - 3:], dirs[n - 3:], tol) is None:
        return None
    return Wrist(first=n - 3)


def wrist_centre(wrist: Wrist, dirs, pts) -> np.ndarray | None:
    """The wrist centre (world frame, m) given the axes at a configuration.

    Parameters
    ----------
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


def _feet(u, v, w, sn):
    """``(t, s)``, each ``(..., 1)``: the closest points ``p + t u`` and ``r + s v`` of two
    skew lines (``w = r - p``, ``sn = |u x v|``; nothing for parallel ones, where ``sn`` is
    0). The directions are unit only to rounding: near parallel that rounding is all of
    ``1 - (u.v)^2``, so their lengths are kept and the denominator is ``|u x v|^2``."""
    uv, wu, wv, den = _dot(u, v), _dot(w, u), _dot(w, v), sn * sn
    t = (wu * _dot(v, v) - wv * uv) / den
    s = (wu * uv - wv * _dot(u, u)) / den
    return t[..., None], s[..., None]


def dh_frames(dirs, pts, L: float = 1.0, parallel_tol: float = 1e-7,
              revolute=None) -> np.ndarray:
    """Standard DH frames on joint axes (Spong, Hutchinson & Vidyasagar, *Robot Modeling
    and Control*, sec. 3.2): frame i's z axis along axis i+1 and its x axis along the
    common normal of axes i and i+1, batched over independent sets of axes.

    Skew or meeting axes: x along ``z_{i-1} x z_i``, the origin the foot of the common
    normal on axis i+1 (the intersection; a may be negative); parallel axes (sine below
    ``parallel_tol``): the normal through frame i-1's origin (d = 0); coincident axes keep
    frame i-1's x; a prismatic axis (a direction only) is put through frame i-1's origin.
    Frame 0 sits on axis 1 at the foot of its normal with axis 2, frame n at frame n-1's
    origin; any frame 0 on axis 1 and frame n along axis n may replace them.

    Parameters
    ----------
    dirs, pts : ndarray (..., n, 3)
        Directions of the axes, unit to rounding (the common normal's feet keep their
        lengths), and a point on each, one frame for all (m).
    L, parallel_tol : float
        The arm's size (m; coincident axes are within ``1e-9 L``), and the sine of the
        angle below which consecutive axes are parallel.
    revolute : array_like (n,) of bool, optional
        False for prismatic joints (default: all revolute).

    Returns
    -------
    ndarray (..., n + 1, 4, 4)
        The poses of DH frames 0..n in the axes' frame (m); between frames i-1 and i the
        transform is ``Rz(theta) Tz(d) Tx(a) Rx(alpha)``.
    """
    n = dirs.shape[-2]
    moving_line = np.ones(n, bool) if revolute is None else np.asarray(revolute, bool)
    z = [dirs[..., i, :] for i in range(n)] + [dirs[..., n - 1, :]]
    x, o = [None] * (n + 1), [None] * (n + 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for i in range(1, n):                        # frame i: axes i (0-based i-1) and i+1
            u, v = dirs[..., i - 1, :], dirs[..., i, :]
            p, r = pts[..., i - 1, :], pts[..., i, :]
            if i == 1 and not moving_line[0]:
                p = np.zeros_like(p)
            if i > 1 and not moving_line[i - 1]:
                p = o[i - 1]
            if not moving_line[i]:
                r = o[i - 1] if i > 1 else p
            nn = cross(u, v)
            sn = np.sqrt(_dot(nn, nn))
            par = ~(sn > parallel_tol)[..., None]    # (..., 1): axes i, i+1 parallel
            t, s = _feet(u, v, r - p, sn)
            foot_j = r + s * v
            xi = nn / sn[..., None]
            if i == 1:
                o[0] = np.where(par, p, p + t * u)
            # parallel axes: the normal through the previous origin
            ref = o[i - 1]
            wp = r - ref
            wp = wp - u * _dot(wp, u)[..., None]
            nw = np.sqrt(_dot(wp, wp))[..., None]
            if i == 1:                               # axes 1 and 2 coincide: any normal
                prev = cross(u, np.where(np.abs(u[..., :1]) < 0.9, [1.0, 0.0, 0.0],
                                         [0.0, 1.0, 0.0]))
            else:
                prev = x[i - 1]
            xp = np.where(nw > 1e-9 * L, wp / nw, prev)
            xi = np.where(par, xp, xi)
            foot_j = np.where(par, ref + wp, foot_j)
            xi = xi - v * _dot(xi, v)[..., None]
            x[i] = _unit(xi)
            o[i] = foot_j
            if i == 1:
                x[0] = _unit(x[1] - z[0] * _dot(x[1], z[0])[..., None])
    if n == 1:                                       # one axis: any normal to it
        x[0] = _unit(cross(z[0], np.where(np.abs(z[0][..., :1]) < 0.9, [1.0, 0.0, 0.0],
                                          [0.0, 1.0, 0.0])))
        o[0] = pts[..., 0, :] if moving_line[0] else np.zeros_like(pts[..., 0, :])
    x[n], o[n] = _unit(x[n - 1] - z[n] * _dot(x[n - 1], z[n])[..., None]), o[n - 1]
    return _poses(*(np.stack(f, axis=-2) for f in (x, z, o)))


def _poses(X, Z, O) -> np.ndarray:
    """Frames ``(..., 4, 4)`` from their x and z axes and origins ``(..., 3)``."""
    F = np.zeros(X.shape[:-1] + (4, 4))
    F[..., :3, 0] = X
    F[..., :3, 1] = cross(Z, X)
    F[..., :3, 2] = Z
    F[..., :3, 3] = O
    F[..., 3, 3] = 1.0
    return F


def _dot(u, v):
    return np.einsum("...i,...i->...", u, v)


def _unit(u):
    return u / np.sqrt(_dot(u, u))[..., None]
