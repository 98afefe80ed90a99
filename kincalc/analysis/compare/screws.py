"""Screws for :mod:`kincalc.analysis.compare`: a robot's unit screws in the world frame
at q = 0, their exponentials, the adjoint action and Lie bracket, and how far apart
two screws' axes are (Lynch & Park, *Modern Robotics*, 2017, ch. 3 and 4).

Screws are ``(6,)`` or ``(..., 6)`` ordered ``(v, w)``; transforms ``(..., 4, 4)``;
lengths in m, angles in rad.
"""

from __future__ import annotations

import math

import numpy as np

from ...spatial import cross, skew


def world_screws(robot):
    """Unit screws ``(n, 6)`` ordered ``(v, w)`` in the world frame at q = 0, and
    the tool pose ``M = FK(0)`` (4, 4). Revolute: ``w`` the axis, ``v = p x w``;
    prismatic: ``w = 0``, ``v`` the direction."""
    from ...fk import chain_frames
    q0 = np.zeros(robot.dof)
    frames = chain_frames(robot.chain, q0)
    z, p = frames[:, :3, 2], frames[:, :3, 3]
    screws = np.where(robot.is_revolute[:, None],
                      np.concatenate([cross(p, z), z], axis=-1),
                      np.concatenate([z, np.zeros_like(z)], axis=-1))
    return screws, robot.fk(q0)


def exp_screw(screw, revolute: bool, x) -> np.ndarray:
    """``exp([screw] x)`` (S, 4, 4) for a unit screw ``(6,)`` and ``x (S,)``."""
    x = np.asarray(x, dtype=float)
    out = np.zeros(x.shape + (4, 4))
    out[..., 3, 3] = 1.0
    v, w = screw[:3], screw[3:]
    if revolute:
        K = skew(w)
        s, c = np.sin(x)[..., None, None], np.cos(x)[..., None, None]
        R = np.eye(3) + s * K + (1.0 - c) * (K @ K)
        point = cross(w, v)                       # the foot of the axis from the origin
        out[..., :3, :3] = R
        out[..., :3, 3] = point - R @ point
    else:
        out[..., :3, :3] = np.eye(3)
        out[..., :3, 3] = x[..., None] * v
    return out


def adjoint(T, y) -> np.ndarray:
    """``Ad_T y``: the screw ``y (..., 6)`` moved by the rigid motion ``T (..., 4, 4)``."""
    R, t = T[..., :3, :3], T[..., :3, 3]
    w = np.einsum("...ij,...j->...i", R, y[..., 3:])
    v = np.einsum("...ij,...j->...i", R, y[..., :3]) + cross(t, w)
    return np.concatenate([v, w], axis=-1)


def bracket(z, y) -> np.ndarray:
    """Lie bracket ``[z, y] = ad_z y`` of screws ``(..., 6)`` (the derivative of
    ``Ad_{exp(z x)} y`` at x = 0)."""
    return np.concatenate([cross(z[..., 3:], y[..., :3]) + cross(z[..., :3], y[..., 3:]),
                           cross(z[..., 3:], y[..., 3:])], axis=-1)


def hat(z) -> np.ndarray:
    """``[z]`` (..., 4, 4) of a screw ``(..., 6)``."""
    out = np.zeros(z.shape[:-1] + (4, 4))
    out[..., :3, :3] = skew(z[..., 3:])
    out[..., :3, 3] = z[..., :3]
    return out


def align(src, dst, revolute: bool) -> np.ndarray:
    """A rigid motion (4, 4) taking the axis of screw ``src`` onto that of ``dst``."""
    a = src[3:] if revolute else src[:3]
    b = dst[3:] if revolute else dst[:3]
    axis = np.cross(a, b)
    s, c = np.linalg.norm(axis), float(a @ b)
    if s < 1e-12:
        if c > 0:
            R = np.eye(3)
        else:                                      # half turn about any perpendicular axis
            helper = np.array([1.0, 0, 0]) if abs(a[0]) < 0.9 else np.array([0, 1.0, 0])
            k = np.cross(a, helper)
            k /= np.linalg.norm(k)
            R = 2 * np.outer(k, k) - np.eye(3)
    else:
        K = skew(axis / s)
        R = np.eye(3) + s * K + (1 - c) * (K @ K)
    T = np.eye(4)
    T[:3, :3] = R
    if revolute:
        T[:3, 3] = cross(dst[3:], dst[:3]) - R @ cross(src[3:], src[:3])
    return T


def perpendiculars(u):
    helper = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    a = np.cross(u, helper)
    a /= np.linalg.norm(a)
    return a, np.cross(u, a)


def line_miss(y, target, revolute):
    """(angle rad, distance m or None) between the axes of screws ``y`` and ``target``."""
    if revolute:
        u1, u2 = y[3:], target[3:]
    else:
        u1, u2 = y[:3], target[:3]
    angle = math.atan2(np.linalg.norm(np.cross(u1, u2)), float(u1 @ u2))
    if not revolute:
        return angle, None
    p1, p2 = cross(u1, y[:3]), cross(u2, target[:3])
    n = np.cross(u1, u2)
    if np.linalg.norm(n) < 1e-9:
        dist = np.linalg.norm(np.cross(p2 - p1, u1))
    else:
        dist = abs(float((p2 - p1) @ n)) / np.linalg.norm(n)
    return angle, float(dist)
