"""Three-angle forms of a rotation ``(..., 3, 3)``: fixed X-Y-Z roll-pitch-yaw, ZYZ Euler
and moving X-Y-Z Euler angles, both ways, with the gimbal-lock branches stated.

Conventions in :mod:`kincalc.spatial`. Angles in rad; every function takes any leading
batch dimensions and never writes into its arguments.
"""

from __future__ import annotations

import numpy as np

from ..tolerances import GIMBAL_TOL
from .rotations import rot_x, rot_y, rot_z

#: the spacing of doubles at 1
EPS = float(np.finfo(float).eps)


def matrix_from_rpy(rpy) -> np.ndarray:
    """Rotation matrix of fixed X-Y-Z angles: ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

    Craig, *Introduction to Robotics*, 3rd ed., sec. 2.8 ("X-Y-Z fixed angles").

    Parameters
    ----------
    rpy : array_like (..., 3)
        ``(roll, pitch, yaw)`` (rad), any range.

    Returns
    -------
    ndarray (..., 3, 3)
        ``R_a_b`` of frame b got from frame a by turning roll about x_a, then pitch about
        y_a, then yaw about z_a.
    """
    rpy = np.asarray(rpy, dtype=float)
    return rot_z(rpy[..., 2]) @ rot_y(rpy[..., 1]) @ rot_x(rpy[..., 0])


def _turn_angle(y, x):
    """``atan2(y, x)`` in (-pi, pi]: a ``y`` of rounding size against a negative ``x``
    counts as +0, so a half turn is +pi whichever sign the rounding gave it (the angle a
    table prints must not flip between 180 and -180 with the last bit of a matrix entry:
    ``rot_z(-pi)`` holds a sine of -1.2e-16)."""
    y = np.asarray(y, float) + 0.0
    x = np.asarray(x, float)
    return np.arctan2(np.where((x < 0) & (np.abs(y) <= 4 * EPS * -x), 0.0, y), x)


def rpy_from_matrix(R) -> np.ndarray:
    """Fixed X-Y-Z angles ``(roll, pitch, yaw)`` of rotation matrices.

    The inverse of :func:`matrix_from_rpy` (Craig, 3rd ed., sec. 2.8), on the branch
    ``cos(pitch) >= 0``.

    Parameters
    ----------
    R : array_like (..., 3, 3)
        Rotation matrices (not checked to be orthonormal).

    Returns
    -------
    ndarray (..., 3)
        ``(roll, pitch, yaw)`` (rad) with ``R = Rz(yaw) Ry(pitch) Rx(roll)``. Pitch lies in
        [-pi/2, pi/2]; roll and yaw in (-pi, pi]: a half turn gives +pi, whether its sine
        entry is zero (of either sign) or of rounding size (``rot_z(-pi)`` holds -1.2e-16;
        see :func:`_turn_angle`).

    Notes
    -----
    At gimbal lock (|pitch| = pi/2, where only ``yaw - roll`` or ``yaw + roll`` is
    defined), detected as ``hypot(R[0, 0], R[1, 0]) < GIMBAL_TOL`` (1e-9,
    :mod:`kincalc.tolerances`), pitch is set to exactly +-pi/2, roll is set to 0 and the
    whole rotation about the vertical goes into yaw: ``yaw - roll`` at pitch = +pi/2,
    ``yaw + roll`` at pitch = -pi/2. (Craig's degenerate solution instead sets the z angle,
    yaw, to 0.)
    """
    R = np.asarray(R, dtype=float)
    cp = np.hypot(R[..., 0, 0], R[..., 1, 0])
    pitch = np.arctan2(-R[..., 2, 0], cp)
    locked = cp < GIMBAL_TOL
    # at lock the pitch is exactly +-pi/2: the tilt left in cp (< GIMBAL_TOL) has no
    # direction once roll is 0, and keeping it would double the round-trip error
    pitch = np.where(locked, np.copysign(np.pi / 2, pitch), pitch)
    roll = np.where(locked, 0.0, _turn_angle(R[..., 2, 1], R[..., 2, 2]))
    yaw = np.where(locked, _turn_angle(-R[..., 0, 1], R[..., 1, 1]),
                   _turn_angle(R[..., 1, 0], R[..., 0, 0]))
    return np.stack([roll, pitch, yaw], axis=-1)


def matrix_from_euler_zyz(zyz) -> np.ndarray:
    """Rotation matrix of ZYZ Euler angles: ``R = Rz(a) Ry(b) Rz(c)``.

    Craig, 3rd ed., sec. 2.8 ("Z-Y-Z Euler angles").

    Parameters
    ----------
    zyz : array_like (..., 3)
        ``(a, b, c)`` (rad), any range.

    Returns
    -------
    ndarray (..., 3, 3)
        ``R_a_b`` of frame b got from frame a by turning a about z, then b about the new y,
        then c about the new z.
    """
    zyz = np.asarray(zyz, dtype=float)
    return rot_z(zyz[..., 0]) @ rot_y(zyz[..., 1]) @ rot_z(zyz[..., 2])


def euler_zyz_from_matrix(R) -> np.ndarray:
    """ZYZ Euler angles ``(a, b, c)`` of rotation matrices, with ``b`` in [0, pi].

    The inverse of :func:`matrix_from_euler_zyz`: Craig's solution (3rd ed., sec. 2.8) on
    the branch ``sin b >= 0``, with his choice ``a = 0`` at the singularities.

    Parameters
    ----------
    R : array_like (..., 3, 3)
        Rotation matrices (not checked to be orthonormal).

    Returns
    -------
    ndarray (..., 3)
        ``(a, b, c)`` (rad) with ``R = Rz(a) Ry(b) Rz(c)``: ``b`` in [0, pi], ``a`` and ``c``
        in (-pi, pi] (a half turn as in :func:`rpy_from_matrix`).

    Notes
    -----
    When ``b`` is 0 or pi only ``a + c`` (or ``a - c``) is defined; then ``a = 0``. The test
    is ``hypot(R[0, 2], R[1, 2]) < GIMBAL_TOL`` (1e-9); ``b`` is then set to exactly 0 (if
    ``R[2, 2] > 0``) or pi, and ``c`` carries ``a + c`` (b = 0) or ``c - a`` (b = pi).
    """
    R = np.asarray(R, dtype=float)
    sb = np.hypot(R[..., 0, 2], R[..., 1, 2])
    b = np.arctan2(sb, R[..., 2, 2])
    locked = sb < GIMBAL_TOL
    # at lock b is exactly 0 or pi (see rpy_from_matrix)
    b = np.where(locked, np.where(R[..., 2, 2] > 0, 0.0, np.pi), b)
    a = np.where(locked, 0.0, _turn_angle(R[..., 1, 2], R[..., 0, 2]))
    c_free = _turn_angle(R[..., 2, 1], -R[..., 2, 0])
    # b = 0: R = Rz(c); b = pi: R = Ry(pi) Rz(c) = [[-cc, sc, 0], [sc, cc, 0], ...]
    c_locked = np.where(R[..., 2, 2] > 0, _turn_angle(R[..., 1, 0], R[..., 0, 0]),
                        _turn_angle(R[..., 1, 0], R[..., 1, 1]))
    c = np.where(locked, c_locked, c_free)
    return np.stack([a, b, c], axis=-1)


def matrix_from_euler_xyz(xyz) -> np.ndarray:
    """Rotation matrix of moving-axis X-Y-Z ("1-2-3") Euler angles: ``R = Rx(a) Ry(b) Rz(c)``.

    Parameters
    ----------
    xyz : array_like (..., 3)
        ``(a, b, c)`` (rad), any range.

    Returns
    -------
    ndarray (..., 3, 3)
        ``R_a_b`` of frame b got from frame a by turning a about x, then b about the new y,
        then c about the new z.
    """
    xyz = np.asarray(xyz, dtype=float)
    return rot_x(xyz[..., 0]) @ rot_y(xyz[..., 1]) @ rot_z(xyz[..., 2])


def euler_xyz_from_matrix(R) -> np.ndarray:
    """Moving X-Y-Z Euler angles ``(a, b, c)`` of rotation matrices, ``b`` in [-pi/2, pi/2].

    The inverse of :func:`matrix_from_euler_xyz`, on the branch ``cos b >= 0``.

    Parameters
    ----------
    R : array_like (..., 3, 3)
        Rotation matrices (not checked to be orthonormal).

    Returns
    -------
    ndarray (..., 3)
        ``(a, b, c)`` (rad) with ``R = Rx(a) Ry(b) Rz(c)``: ``b`` in [-pi/2, pi/2], ``a`` and
        ``c`` in (-pi, pi] (a half turn as in :func:`rpy_from_matrix`).

    Notes
    -----
    At gimbal lock (|b| = pi/2) ``a = 0``. The test is ``hypot(R[0, 0], R[0, 1]) <
    GIMBAL_TOL`` (1e-9); ``b`` is then set to exactly +-pi/2 and ``c`` carries ``a + c``
    (b = +pi/2) or ``c - a`` (b = -pi/2).
    """
    R = np.asarray(R, dtype=float)
    cb = np.hypot(R[..., 0, 0], R[..., 0, 1])
    b = np.arctan2(R[..., 0, 2], cb)
    locked = cb < GIMBAL_TOL
    b = np.where(locked, np.copysign(np.pi / 2, b), b)       # see rpy_from_matrix
    a = np.where(locked, 0.0, _turn_angle(-R[..., 1, 2], R[..., 2, 2]))
    c = np.where(locked, _turn_angle(R[..., 1, 0], R[..., 1, 1]),
                 _turn_angle(-R[..., 0, 1], R[..., 0, 0]))
    return np.stack([a, b, c], axis=-1)
