"""Rigid transforms ``(..., 4, 4)``: building and inverting them, the tool configuration
vector, the matrix logarithm (twist coordinates) and the adjoint.

Conventions in :mod:`kincalc.spatial`: ``T_a_b`` is the pose of frame b in frame a;
lengths in m (or the robot's own unit), angles in rad; every function takes any leading
batch dimensions and never writes into its arguments.
"""

from __future__ import annotations

import math

import numpy as np

from ..limits import MAX_MAGNITUDE
from .rotations import rotvec_from_matrix, skew


def transform(rotation=None, translation=None) -> np.ndarray:
    """Homogeneous transform ``T_a_b = [[R_a_b, p], [0, 1]]`` from a rotation and a translation.

    Parameters
    ----------
    rotation : array_like (..., 3, 3), optional
        ``R_a_b``, not checked to be a rotation. Omitted: the identity.
    translation : array_like (..., 3), optional
        ``p``, the origin of frame b in frame a (m). Omitted: zero.

    Returns
    -------
    ndarray (..., 4, 4)
        ``T_a_b``; the leading dimensions of the two inputs broadcast.

    Raises
    ------
    ValueError
        If the leading dimensions of ``rotation`` and ``translation`` do not broadcast.
    """
    R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    p = np.zeros(3) if translation is None else np.asarray(translation, dtype=float)
    batch = np.broadcast_shapes(R.shape[:-2], p.shape[:-1])
    out = np.zeros(batch + (4, 4))
    out[..., :3, :3] = R
    out[..., :3, 3] = p
    out[..., 3, 3] = 1.0
    return out


def invert_transform(T) -> np.ndarray:
    """Inverse of rigid transforms: ``T_b_a`` from ``T_a_b``.

    Computed as ``[[R^T, -R^T p], [0, 1]]``: ``R`` is assumed orthonormal (not checked) and
    the last row of ``T`` is not read.

    Parameters
    ----------
    T : array_like (..., 4, 4)
        ``T_a_b``, translation in m.

    Returns
    -------
    ndarray (..., 4, 4)
        ``T_b_a``, translation in m.
    """
    T = np.asarray(T, dtype=float)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    return transform(Rt, -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3]))


#: the largest |q_n| (rad) whose tool configuration vector is given: e^(q_n/pi) stays
#: within kincalc's magnitude limit (1e9, :data:`kincalc.limits.MAX_MAGNITUDE`), about
#: 65 rad or ten turns. Beyond it the exponential leaves the numbers kincalc reads back
#: and soon overflows to infinity (q_n > 2229 rad).
TCV_MAX_ROLL = math.pi * math.log(MAX_MAGNITUDE)


def tcv_from_transform(T, q_last) -> np.ndarray:
    """Tool configuration vector ``w = [p; exp(q_n / pi) r3]`` of tool poses.

    Schilling, *Fundamentals of Robotics* (1990), sec. 3.4, as used in the FER Zagreb
    homework: ``p`` is the tool position, ``r3`` the approach vector (third column of R) and
    ``q_n`` the last joint's angle in rad, so the norm of ``w[3:]`` encodes the tool roll.

    Parameters
    ----------
    T : array_like (..., 4, 4)
        Tool pose, e.g. ``T_world_tool`` (m).
    q_last : array_like (...)
        ``q_n`` (rad), the last joint's angle: a scalar, or the leading dimensions of ``T``.
        ``|q_n|`` beyond :data:`TCV_MAX_ROLL` (about 65 rad) is not checked here: the
        exponential then exceeds kincalc's magnitude limit, and overflows to inf past 2229 rad.

    Returns
    -------
    ndarray (..., 6)
        ``w``, in the frame ``T`` is expressed in: ``w[:3]`` the position (m), ``w[3:]`` the
        approach vector scaled by ``exp(q_n / pi)`` (unitless).
    """
    T = np.asarray(T, dtype=float)
    scale = np.exp(np.asarray(q_last, dtype=float) / np.pi)
    return np.concatenate([T[..., :3, 3], scale[..., None] * T[..., :3, 2]], axis=-1)


def transform_from_tcv(w) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, approach and roll ``q_n`` from a tool configuration vector.

    The inverse of :func:`tcv_from_transform` as far as it goes: a TCV fixes the position,
    the approach vector and the last joint's angle ``q_n = pi ln |w[3:]|``, not the whole
    rotation, so no transform is returned.

    Parameters
    ----------
    w : array_like (..., 6)
        Tool configuration vector: position (m), then scaled approach vector.

    Returns
    -------
    p : ndarray (..., 3)
        Tool position ``w[:3]`` (m).
    approach : ndarray (..., 3)
        Unit approach vector ``w[3:] / |w[3:]|``, in the frame of ``w``.
    q_n : ndarray (...)
        The last joint's angle (rad), any real (not wrapped).

    Raises
    ------
    ValueError
        If any ``w[3:]`` is zero.
    """
    w = np.asarray(w, dtype=float)
    n = np.linalg.norm(w[..., 3:], axis=-1)
    if np.any(n == 0):
        raise ValueError("tool configuration vector has a zero approach part")
    return w[..., :3], w[..., 3:] / n[..., None], np.pi * np.log(n)


def log_transform(T) -> np.ndarray:
    """Twist coordinates ``(v, w)`` with ``exp([v; w]^) = T``: the matrix logarithm of SE(3).

    Lynch & Park, *Modern Robotics*, 2017, sec. 3.3.3.2 (their twist is ordered ``(w, v)``
    and split into a unit screw times theta; here the product is returned). Used to compare
    poses and to differentiate FK numerically.

    Parameters
    ----------
    T : array_like (..., 4, 4)
        ``T_a_b`` (m), assumed rigid; the last row is not read.

    Returns
    -------
    ndarray (..., 6)
        ``(v, w)``: ``w`` (rad) is the rotation vector of ``R`` (:func:`rotvec_from_matrix`,
        norm theta in [0, pi]); ``v = G(w)^-1 p`` (m) with
        ``G(w) = I + (1 - cos theta) / theta^2 [w]x + (theta - sin theta) / theta^3 [w]x^2``
        (a series below theta = 1e-6). The twist has the same coordinates in frames a and b.
    """
    T = np.asarray(T, dtype=float)
    R = T[..., :3, :3]
    p = T[..., :3, 3]
    w = rotvec_from_matrix(R)
    theta = np.linalg.norm(w, axis=-1)
    W = skew(w)
    # G^-1 = I - W/2 + (1/theta^2 - (1 + cos)/(2 theta sin)) W^2 ; series near 0
    with np.errstate(invalid="ignore", divide="ignore"):
        coef = np.where(
            theta > 1e-6,
            1.0 / theta**2 - (1.0 + np.cos(theta)) / (2.0 * theta * np.sin(theta)),
            1.0 / 12.0 + theta**2 / 720.0,
        )
    Ginv = np.eye(3) - 0.5 * W + coef[..., None, None] * (W @ W)
    v = np.einsum("...ij,...j->...i", Ginv, p)
    return np.concatenate([v, w], axis=-1)


def adjoint(T) -> np.ndarray:
    """Adjoint ``Ad_T = [[R, [p]x R], [0, R]]`` of rigid transforms, for twists ordered ``(v, w)``.

    Maps a twist expressed in frame b to the same twist expressed in frame a, for
    ``T = T_a_b``. Murray, Li & Sastry, *A Mathematical Introduction to Robotic
    Manipulation*, 1994, ch. 2 (same ordering); Lynch & Park, *Modern Robotics*, sec. 3.3.2,
    order it ``(w, v)``.

    Parameters
    ----------
    T : array_like (..., 4, 4)
        ``T_a_b``, translation ``p`` in m; the last row is not read.

    Returns
    -------
    ndarray (..., 6, 6)
        ``Ad_T``: ``V_a = Ad_T @ V_b``.
    """
    T = np.asarray(T, dtype=float)
    R = T[..., :3, :3]
    p = T[..., :3, 3]
    out = np.zeros(T.shape[:-2] + (6, 6))
    out[..., :3, :3] = R
    out[..., 3:, 3:] = R
    out[..., :3, 3:] = skew(p) @ R
    return out
