"""Rotations and rigid transforms, batched over leading axes.

Conventions (see also the package docstring):

* A rotation matrix ``R_a_b`` has shape ``(..., 3, 3)`` and maps vectors in
  frame b to frame a; a transform ``T_a_b`` has shape ``(..., 4, 4)`` and is
  the pose of frame b in frame a.
* Angles are in radians, lengths in metres (or in the robot's own unit for
  unitless robots); nothing here converts units.
* RPY means fixed-axis X-Y-Z angles ``(roll, pitch, yaw)`` with
  ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)`` (Craig, *Introduction to Robotics*,
  3rd ed., sec. 2.8, "X-Y-Z fixed angles").
* ZYZ Euler angles ``(a, b, c)`` mean ``R = Rz(a) @ Ry(b) @ Rz(c)``; moving
  X-Y-Z Euler angles ("1-2-3") mean ``R = Rx(a) @ Ry(b) @ Rz(c)``.
* Quaternions are ``(w, x, y, z)``, scalar first, returned with ``w >= 0``.
* Twists and Jacobian rows are ordered linear then angular ``(v, w)``.

Every function accepts any number of leading batch dimensions, returns new
arrays and never writes into its arguments.
"""

from __future__ import annotations

import math

import numpy as np

from .limits import MAX_MAGNITUDE
from .tolerances import GIMBAL_TOL, SMALL_ANGLE

__all__ = [
    "rot_x", "rot_y", "rot_z", "transform", "invert_transform", "cross", "skew",
    "matrix_from_rpy", "rpy_from_matrix",
    "matrix_from_euler_zyz", "euler_zyz_from_matrix",
    "matrix_from_euler_xyz", "euler_xyz_from_matrix",
    "quaternion_from_matrix", "matrix_from_quaternion",
    "axis_angle_from_matrix", "matrix_from_axis_angle",
    "rotvec_from_matrix", "matrix_from_rotvec",
    "tcv_from_transform", "transform_from_tcv",
    "log_transform", "adjoint", "rotation_error", "rotation_angle",
    "matrix_from_unit_axis_angle",
]


#: one turn (rad)
TURN = 2 * math.pi


def wrap(x) -> np.ndarray:
    """Wrap angles into (-pi, pi].

    Rounds the number of turns (a floating remainder is several times slower on large
    batches). The one angle wrap of kincalc: subproblems, the IK engine and its
    post-processing all use it.

    Parameters
    ----------
    x : array_like (...)
        Angles (rad), any range.

    Returns
    -------
    ndarray (...)
        ``x`` minus a whole number of turns (rad), in (-pi, pi]; a half turn gives +pi. A
        float near an odd multiple of pi, far from 0, can come back above pi by the rounding
        of ``x`` (~|x| 1e-16): the upper end is not clamped. Non-finite ``x`` gives nan.
    """
    x = np.asarray(x, float)
    y = x - TURN * np.rint(x / TURN)
    return np.where(y <= -math.pi, y + TURN, y)


def _elementary(angle, i: int, j: int) -> np.ndarray:
    """Rotation by ``angle`` mixing axes i and j (the plane of rotation)."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros(angle.shape + (3, 3))
    k = 3 - i - j
    out[..., k, k] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(angle) -> np.ndarray:
    """Rotation matrix ``Rx(angle)`` about the x axis.

    Parameters
    ----------
    angle : array_like (...)
        Rotation angle (rad), right-handed about +x.

    Returns
    -------
    ndarray (..., 3, 3)
        ``[[1, 0, 0], [0, c, -s], [0, s, c]]``: ``R_a_b`` of a frame b turned by ``angle``
        about the x axis of frame a.
    """
    return _elementary(angle, 1, 2)


def rot_y(angle) -> np.ndarray:
    """Rotation matrix ``Ry(angle)`` about the y axis.

    Parameters
    ----------
    angle : array_like (...)
        Rotation angle (rad), right-handed about +y.

    Returns
    -------
    ndarray (..., 3, 3)
        ``[[c, 0, s], [0, 1, 0], [-s, 0, c]]``: ``R_a_b`` of a frame b turned by ``angle``
        about the y axis of frame a.
    """
    return _elementary(angle, 2, 0)


def rot_z(angle) -> np.ndarray:
    """Rotation matrix ``Rz(angle)`` about the z axis.

    Parameters
    ----------
    angle : array_like (...)
        Rotation angle (rad), right-handed about +z.

    Returns
    -------
    ndarray (..., 3, 3)
        ``[[c, -s, 0], [s, c, 0], [0, 0, 1]]``: ``R_a_b`` of a frame b turned by ``angle``
        about the z axis of frame a.
    """
    return _elementary(angle, 0, 1)


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


def cross(a, b) -> np.ndarray:
    """Cross product ``a x b`` of 3-vectors.

    numpy.cross without its per-call overhead (it dominated the IK solvers' time on single
    3-vectors).

    Parameters
    ----------
    a, b : array_like (..., 3)
        Vectors in one frame; leading dimensions broadcast.

    Returns
    -------
    ndarray (..., 3)
        ``a x b``, in the same frame (unit: the product of the inputs' units).
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def skew(v) -> np.ndarray:
    """Skew-symmetric matrix ``[v]x`` of ``v``, so that ``[v]x @ u = v x u``.

    Parameters
    ----------
    v : array_like (..., 3)
        Vector (any unit).

    Returns
    -------
    ndarray (..., 3, 3)
        ``[[0, -vz, vy], [vz, 0, -vx], [-vy, vx, 0]]``, in the unit of ``v``.
    """
    v = np.asarray(v, dtype=float)
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1] = -v[..., 2]
    out[..., 0, 2] = v[..., 1]
    out[..., 1, 0] = v[..., 2]
    out[..., 1, 2] = -v[..., 0]
    out[..., 2, 0] = -v[..., 1]
    out[..., 2, 1] = v[..., 0]
    return out


# --- Euler-type angle sets -------------------------------------------------

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
    """``atan2(y, x)`` in (-pi, pi]: a zero ``y`` counts as +0, so a half turn is +pi
    whichever sign the rounding gave the zero (the angle a table prints must not
    flip between 180 and -180 with the last bit of a matrix entry)."""
    return np.arctan2(y + 0.0, x)


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
        [-pi/2, pi/2]; roll and yaw in (-pi, pi]: a half turn whose sine entry is zero (of
        either sign) gives +pi, but one whose sine entry is a rounding-level negative number
        (as in ``rot_z(-pi)``) gives -pi.

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


# --- quaternions, axis-angle, rotation vectors ----------------------------

def quaternion_from_matrix(R) -> np.ndarray:
    """Unit quaternions ``(w, x, y, z)`` of rotation matrices, with ``w >= 0``.

    Shepperd's method (S. W. Shepperd, J. Guidance and Control 1(3), 1978): the largest of
    the four squared components is taken from the diagonal, the others from off-diagonal
    sums, so no component is computed from a difference of nearly equal numbers. Euler
    parameters in Craig, 3rd ed., sec. 2.8.

    Parameters
    ----------
    R : array_like (..., 3, 3)
        ``R_a_b``, not checked to be orthonormal (the result is normalised whatever ``R``).

    Returns
    -------
    ndarray (..., 4)
        ``(w, x, y, z)``, scalar first, unit norm, ``w = cos(angle / 2) >= 0`` and ``(x, y,
        z) = sin(angle / 2) axis``. At a half turn (``w = 0``) ``q`` and ``-q`` are both
        canonical; the sign returned is the one Shepperd's pivot gives.
    """
    R = np.asarray(R, dtype=float)
    m00, m11, m22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    trace = m00 + m11 + m22
    candidates = np.stack([trace, m00, m11, m22], axis=-1)
    pick = np.argmax(candidates, axis=-1)
    q = np.empty(R.shape[:-2] + (4,))

    d21 = R[..., 2, 1] - R[..., 1, 2]
    d02 = R[..., 0, 2] - R[..., 2, 0]
    d10 = R[..., 1, 0] - R[..., 0, 1]
    s01 = R[..., 0, 1] + R[..., 1, 0]
    s02 = R[..., 0, 2] + R[..., 2, 0]
    s12 = R[..., 1, 2] + R[..., 2, 1]

    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.sqrt(np.maximum(1.0 + trace, 0.0)) * 2.0  # 4w
        qw = np.stack([t / 4, d21 / t, d02 / t, d10 / t], axis=-1)
        t = np.sqrt(np.maximum(1.0 + m00 - m11 - m22, 0.0)) * 2.0  # 4x
        qx = np.stack([d21 / t, t / 4, s01 / t, s02 / t], axis=-1)
        t = np.sqrt(np.maximum(1.0 - m00 + m11 - m22, 0.0)) * 2.0  # 4y
        qy = np.stack([d02 / t, s01 / t, t / 4, s12 / t], axis=-1)
        t = np.sqrt(np.maximum(1.0 - m00 - m11 + m22, 0.0)) * 2.0  # 4z
        qz = np.stack([d10 / t, s02 / t, s12 / t, t / 4], axis=-1)
    for k, cand in enumerate((qw, qx, qy, qz)):
        sel = pick == k
        q[sel] = cand[sel]
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


def matrix_from_quaternion(q) -> np.ndarray:
    """Rotation matrices of quaternions ``(w, x, y, z)``.

    Craig, 3rd ed., sec. 2.8 ("Euler parameters").

    Parameters
    ----------
    q : array_like (..., 4)
        ``(w, x, y, z)``, scalar first; any nonzero norm: ``q`` is normalised first, and ``q``
        and ``-q`` give the same matrix. A zero ``q`` is not an error: it gives nan.

    Returns
    -------
    ndarray (..., 3, 3)
        ``R_a_b`` of the rotation by ``2 atan2(|(x, y, z)|, w)`` about ``(x, y, z)``.
    """
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = np.empty(q.shape[:-1] + (3, 3))
    out[..., 0, 0] = 1 - 2 * (y * y + z * z)
    out[..., 0, 1] = 2 * (x * y - z * w)
    out[..., 0, 2] = 2 * (x * z + y * w)
    out[..., 1, 0] = 2 * (x * y + z * w)
    out[..., 1, 1] = 1 - 2 * (x * x + z * z)
    out[..., 1, 2] = 2 * (y * z - x * w)
    out[..., 2, 0] = 2 * (x * z - y * w)
    out[..., 2, 1] = 2 * (y * z + x * w)
    out[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return out


def axis_angle_from_matrix(R) -> tuple[np.ndarray, np.ndarray]:
    """Unit axis and angle in [0, pi] (rad) of rotation matrices.

    Computed through the quaternion (``angle = 2 atan2(|v|, w)``), which stays accurate near
    0 and near pi where ``arccos((tr R - 1) / 2)`` does not.

    Parameters
    ----------
    R : array_like (..., 3, 3)
        ``R_a_b`` (not checked to be orthonormal).

    Returns
    -------
    axis : ndarray (..., 3)
        Unit axis, in frame a (equally in frame b). For the identity, and below an angle of
        about 2e-12 rad (``|v| <= SMALL_ANGLE``), it is reported as ``(0, 0, 1)``. At a half
        turn ``axis`` and ``-axis`` are the same rotation; the sign is the quaternion's.
    angle : ndarray (...)
        Rotation angle (rad) in [0, pi].
    """
    q = quaternion_from_matrix(R)
    v = q[..., 1:]
    n = np.linalg.norm(v, axis=-1)
    angle = 2.0 * np.arctan2(n, q[..., 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        axis = np.where((n > SMALL_ANGLE)[..., None], v / n[..., None], [0.0, 0.0, 1.0])
    return axis, angle


def matrix_from_axis_angle(axis, angle) -> np.ndarray:
    """Rodrigues' formula: ``R = I + sin(angle) [k]x + (1 - cos(angle)) [k]x^2``.

    Rotation by ``angle`` about the unit vector ``k = axis / |axis|`` (Lynch & Park,
    *Modern Robotics*, 2017, sec. 3.2.3).

    Parameters
    ----------
    axis : array_like (..., 3)
        Rotation axis, any nonzero length: it is normalised.
    angle : array_like (...)
        Rotation angle (rad); leading dimensions broadcast with ``axis``.

    Returns
    -------
    ndarray (..., 3, 3)
        The rotation matrix.

    Raises
    ------
    ValueError
        If any ``axis`` is the zero vector.
    """
    axis = np.asarray(axis, dtype=float)
    angle = np.asarray(angle, dtype=float)
    n = np.linalg.norm(axis, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise ValueError("rotation axis must not be the zero vector")
    k = axis / n
    K = skew(k)
    s = np.sin(angle)[..., None, None]
    c = np.cos(angle)[..., None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def rotvec_from_matrix(R) -> np.ndarray:
    """Rotation vectors ``axis * angle`` of rotation matrices.

    Parameters
    ----------
    R : array_like (..., 3, 3)
        ``R_a_b`` (not checked to be orthonormal).

    Returns
    -------
    ndarray (..., 3)
        Rotation vector (rad), norm in [0, pi]: axis and angle of
        :func:`axis_angle_from_matrix`.
    """
    axis, angle = axis_angle_from_matrix(R)
    return axis * angle[..., None]


def matrix_from_rotvec(r) -> np.ndarray:
    """Rotation matrices of rotation vectors (the exponential map of SO(3)).

    Parameters
    ----------
    r : array_like (..., 3)
        Rotation vectors ``axis * angle`` (rad), any norm; a zero vector gives the identity.

    Returns
    -------
    ndarray (..., 3, 3)
        The rotation by ``|r|`` about ``r / |r|`` (:func:`matrix_from_axis_angle`).
    """
    r = np.asarray(r, dtype=float)
    angle = np.linalg.norm(r, axis=-1)
    safe = np.where(angle[..., None] > 0, r, [0.0, 0.0, 1.0])
    return matrix_from_axis_angle(safe, angle)


# --- tool configuration vector ---------------------------------------------

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


def transform_from_tcv(w) -> tuple[np.ndarray, np.ndarray]:
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


# --- twists and errors -------------------------------------------------------

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


def rotation_error(R_a, R_b) -> np.ndarray:
    """Angle of the rotation taking ``R_b`` to ``R_a``.

    The angle of ``R_b^T R_a`` (:func:`axis_angle_from_matrix`); it is symmetric in the two
    arguments.

    Parameters
    ----------
    R_a, R_b : array_like (..., 3, 3)
        Rotation matrices in one frame; leading dimensions broadcast.

    Returns
    -------
    ndarray (...)
        Angle (rad) in [0, pi].
    """
    R = np.swapaxes(np.asarray(R_b, dtype=float), -1, -2) @ np.asarray(R_a, dtype=float)
    return axis_angle_from_matrix(R)[1]


def rotation_angle(R) -> np.ndarray:
    """Angle of rotations ``R`` in [0, pi] (rad).

    ``atan2(sin, cos)`` with ``2 sin = |vee(R - R^T)|`` and ``2 cos = tr R - 1``: both parts
    are accurate to rounding at every angle, so the angle is too (to ~1e-16 rad absolute),
    near 0 and near pi alike, without the quaternion of :func:`axis_angle_from_matrix`
    (cheaper when only the angle is needed).

    Parameters
    ----------
    R : array_like (..., 3, 3)
        Rotation matrices (not checked to be orthonormal).

    Returns
    -------
    ndarray (...)
        Rotation angle (rad) in [0, pi].
    """
    R = np.asarray(R, dtype=float)
    x = R[..., 2, 1] - R[..., 1, 2]
    y = R[..., 0, 2] - R[..., 2, 0]
    z = R[..., 1, 0] - R[..., 0, 1]
    return np.arctan2(np.sqrt(x * x + y * y + z * z),
                      R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0)


def matrix_from_unit_axis_angle(axis, angle) -> np.ndarray:
    """Rodrigues' formula for one rotation: ``R = c I + s [k]x + (1 - c) k k^T``.

    Written out in Python floats: the one-rotation case of :func:`matrix_from_axis_angle`
    without its normalisation, checks and broadcasting (the geometric IK solvers build many
    single rotations per pose).

    Parameters
    ----------
    axis : array_like (3,)
        The unit vector ``k``. It must already be unit; it is not checked.
    angle : float
        Rotation angle (rad), a scalar.

    Returns
    -------
    ndarray (3, 3)
        The rotation by ``angle`` about ``axis``.
    """
    x, y, z = np.asarray(axis, dtype=float).tolist()
    angle = float(angle)
    c, s = math.cos(angle), math.sin(angle)
    C = 1.0 - c
    xC, yC, zC = x * C, y * C, z * C
    return np.array([[c + x * xC, x * yC - z * s, x * zC + y * s],
                     [y * xC + z * s, c + y * yC, y * zC - x * s],
                     [z * xC - y * s, z * yC + x * s, c + z * zC]])
