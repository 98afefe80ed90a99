"""Rotation matrices ``(..., 3, 3)``: elementary rotations, cross products, quaternions,
axis-angle and rotation vectors, and the distance between two rotations; the angle wrap.

Conventions in :mod:`kincalc.spatial`. Angles in rad; every function takes any leading
batch dimensions and never writes into its arguments.
"""

from __future__ import annotations

import math

import numpy as np

from ..tolerances import SMALL_ANGLE


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
    if not np.count_nonzero(np.abs(x) >= math.pi):     # already within: no turn (-0 is 0)
        y = x + 0.0
        return y if y.ndim else np.asarray(y)
    y = x - TURN * np.rint(x / TURN)
    # far from zero the rounded remainder can land a few ulps outside (-pi, pi], and a half
    # turn must come out as +pi: both have |y| >= pi (rare: tested before fixed)
    if np.count_nonzero(np.abs(y) >= math.pi):
        return np.where(y <= -math.pi, y + TURN, np.where(y > math.pi, y - TURN, y))
    return y if y.ndim else np.asarray(y)


def into_turn(x, base) -> np.ndarray:
    """Angles moved by whole turns into ``[base, base + 2 pi)``.

    Parameters
    ----------
    x : array_like (...)
        Angles (rad).
    base : array_like, broadcasting with ``x``
        The start of each turn (rad), finite.

    Returns
    -------
    ndarray (...)
    """
    r = np.mod(np.asarray(x, float) - base, TURN)
    return base + np.where(r < TURN, r, 0.0)        # (mod of a tiny negative rounds to TURN)


def into_limits(x, lo, hi) -> np.ndarray:
    """Angles beyond their limits moved by whole turns to the value within them nearest the
    angle, or where no turn of it is within them, to the turn that misses them least.

    Parameters
    ----------
    x : array_like (...)
        Angles (rad).
    lo, hi : array_like, broadcasting with ``x``
        Limits (rad; infinite allowed), ``lo <= hi``.

    Returns
    -------
    ndarray (...)
        A new array: ``x`` where it is within ``[lo, hi]`` (or not finite), else ``x + 2 pi
        k``. Of two turns missing the limits alike, the lower.
    """
    x = np.asarray(x, float)
    low, high = x < lo, x > hi
    if not (np.count_nonzero(low) or np.count_nonzero(high)):
        return x.copy()
    with np.errstate(invalid="ignore"):         # (infinite limits: in entries not taken)
        up = x + TURN * np.ceil((lo - x) / TURN)        # the first turn at or above lo
        down = x - TURN * np.ceil((x - hi) / TURN)      # the last at or below hi
        up = np.where((up <= hi) | (up - hi < lo - (up - TURN)), up, up - TURN)
        down = np.where((down >= lo) | (lo - down <= down + TURN - hi), down, down + TURN)
    return np.where(low, up, np.where(high, down, x))


def turn_toward(x, near, lo, hi) -> np.ndarray:
    """Angles moved by whole turns (up to 3) to the value nearest ``near`` within limits.

    Parameters
    ----------
    x : array_like (..., n)
        Angles (rad).
    near : array_like (n,)
        The angles to move towards (rad).
    lo, hi : array_like (n,)
        Limits (rad; 1e-12 of slack).

    Returns
    -------
    ndarray (..., n)
        ``x + 2 pi k`` with ``k`` in -3..3 the nearest ``near`` within ``[lo, hi]`` (a range of
        more than a turn takes the short way); ``x`` itself where no such value is within.
    """
    x = np.asarray(x, float)
    lo, hi = np.asarray(lo, float)[:, None], np.asarray(hi, float)[:, None]
    options = x[..., None] + TURN * np.arange(-3, 4)                    # (..., n, 7)
    inside = (options >= lo - 1e-12) & (options <= hi + 1e-12)
    cost = np.where(inside, np.abs(options - np.asarray(near, float)[:, None]), np.inf)
    best = np.take_along_axis(options, cost.argmin(-1)[..., None], -1)[..., 0]
    return np.where(inside.any(-1), best, x)


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


#: ``(3, 9)``: the cross product from the outer product, ``(a x b)_i = eps_ijm (a_j b_m)`` with
#: ``a_j b_m`` at ``3 j + m`` (unitless). A product with it adds two of the outer product's
#: entries, with their signs, and nothing else: the same numbers as the formula
#: ``a_1 b_2 - a_2 b_1, ...`` for a batch of vectors in one matrix product.
LEVI_CIVITA = np.zeros((3, 9))
for _i, _j, _m in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    LEVI_CIVITA[_i, 3 * _j + _m], LEVI_CIVITA[_i, 3 * _m + _j] = 1.0, -1.0
LEVI_CIVITA.setflags(write=False)


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

    Up to a quarter turn (``tr R >= 1``) from the skew part ``v = 2 sin(angle) axis`` and
    ``2 cos(angle) = tr R - 1``: ``v atan2(|v|, tr R - 1) / |v|``, accurate to rounding in
    direction and size down to the smallest angles (a Newton polish's orientation residual
    near rounding keeps its direction); beyond, where the skew part loses the angle, through
    the quaternion (:func:`axis_angle_from_matrix`).

    Parameters
    ----------
    R : array_like (..., 3, 3)
        ``R_a_b`` (not checked to be orthonormal).

    Returns
    -------
    ndarray (..., 3)
        Rotation vector (rad), norm in [0, pi].
    """
    R = np.asarray(R, dtype=float)
    v = np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0],
                  R[..., 1, 0] - R[..., 0, 1]], axis=-1)
    c2 = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0
    sn = np.sqrt(v[..., 0] * v[..., 0] + v[..., 1] * v[..., 1] + v[..., 2] * v[..., 2])
    out = v * (np.arctan2(sn, c2) / np.maximum(sn, 1e-300))[..., None]
    far = c2 < 0.0
    if np.count_nonzero(far):
        axis, angle = axis_angle_from_matrix(R[far])
        out[far] = axis * angle[..., None]
    return out


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
