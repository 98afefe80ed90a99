"""Geometric and analytic Jacobians, vectorised over poses.

Rows are ordered linear then angular: ``(vx, vy, vz, wx, wy, wz)``.
Column i of the geometric Jacobian (Siciliano et al., *Robotics: Modelling,
Planning and Control*, 2009, eq. 3.30) is

* revolute:  ``[z_i x (p_e - o_i); z_i]``
* prismatic: ``[z_i; 0]``

with ``z_i``, ``o_i`` joint i's axis and a point on it, and ``p_e`` the tool
point, all in the world frame. :func:`jacobian_base` gives the velocity of
the tool point in the world frame; :func:`jacobian_tool` the same velocities
in the tool frame: ``J_tool = diag(R^T, R^T) J_base`` with ``R`` the tool
orientation. :func:`finite_difference_jacobian` differentiates any FK function (a
mechanism given only by its FK, for the numerical IK).
"""

from __future__ import annotations

import numpy as np

from .fk import entry_frames, joint_batch
from .tolerances import SINGULAR_TOL


def jacobian_and_pose(chain, q, *, column_walk: bool = False):
    """The world-frame Jacobian and the tool pose from one evaluation of the chain (for
    Newton-type searches, which need both).

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (..., n)
        Joint values, rad / m.
    column_walk : bool
        Evaluate the chain by the column walk for any number of configurations
        (:func:`kincalc.fk.entry_frames`): each one's bits then do not depend on how many are
        evaluated together (a Newton search whose answers must not depend on the rest of
        its batch). By default up to :data:`~kincalc.fk.FEW` configurations are evaluated as
        stacked 4x4 products, which round differently in the last bits.

    Returns
    -------
    J : ndarray (..., 6, n)
        :func:`jacobian_base`, C-contiguous.
    T : ndarray (..., 4, 4)
        ``T_world_tool`` (m).

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    q, flat = joint_batch(chain, q)
    N, n = flat.shape
    A = entry_frames(chain, flat, column_walk=column_walk)          # (3, 4, n + 1, N)
    J = np.ascontiguousarray(frames_jacobian(A, chain.revolute).transpose(2, 0, 1))
    T = np.zeros((N, 4, 4))
    T[:, :3] = A[:, :, n].transpose(2, 0, 1)
    T[:, 3, 3] = 1.0
    return J.reshape(q.shape[:-1] + (6, n)), T.reshape(q.shape[:-1] + (4, 4))


def frames_jacobian(frames, revolute) -> np.ndarray:
    """The geometric Jacobian (world frame) from the joint frames, joint-major.

    Column i is ``[z_i x (p_e - o_i); z_i]`` for a revolute joint and ``[z_i; 0]`` for a
    prismatic one (Siciliano et al. 2009, eq. 3.30), ``z_i`` and ``o_i`` the axis and origin
    of frame i, ``p_e`` the tool's origin.

    Parameters
    ----------
    frames : ndarray (3, 4, n + 1, M) or (3, 2, n + 1, M)
        The joint frames and the tool pose entry by entry (:func:`kincalc.fk.entry_frames`,
        world frame, m), or their last two columns (axis, origin).
    revolute : ndarray (n,) of bool
        True for revolute joints.

    Returns
    -------
    ndarray (6, n, M)
        ``J[r, i, m]``: row r (vx vy vz wx wy wz) of column i at configuration m (rad/s and
        m/s to m/s and rad/s); a zero entry is +0.0.
    """
    n = frames.shape[2] - 1
    z = frames[:, -2, :n]                                         # (3, n, M) the axes
    d = frames[:, -1, n:] - frames[:, -1, :n]                     # origin to tool point
    J = np.empty((6,) + z.shape[1:])
    for r, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):
        np.subtract(z[a] * d[b], z[b] * d[a], out=J[r])
    J[3:] = z
    if np.count_nonzero(revolute) < len(revolute):            # a prismatic joint
        rev = revolute[:, None]
        J[:3] = np.where(rev, J[:3], z)
        J[3:] = np.where(rev, z, 0.0)
    J += 0.0                                  # -0.0 (a product of signed zeros) as 0.0
    return J


def jacobian_base(chain, q, *, column_walk: bool = False) -> np.ndarray:
    """The geometric Jacobian in the world (base) frame.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (..., n)
        Joint values, rad / m.
    column_walk : bool
        As :func:`jacobian_and_pose`'s: each configuration's bits the same in any batch.

    Returns
    -------
    ndarray (..., 6, n)
        Rows ``vx vy vz wx wy wz``: joint rates (rad/s, m/s) to the linear velocity of the
        tool point (m/s) and the angular velocity of the tool (rad/s), both in the world
        frame (Siciliano et al. 2009, eq. 3.30).

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    return jacobian_and_pose(chain, q, column_walk=column_walk)[0]


def jacobian_tool(chain, q, *, column_walk: bool = False) -> np.ndarray:
    """The geometric Jacobian expressed in the tool frame.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (..., n)
        Joint values, rad / m.
    column_walk : bool
        As :func:`jacobian_and_pose`'s: each configuration's bits the same in any batch.

    Returns
    -------
    ndarray (..., 6, n)
        The velocities of :func:`jacobian_base` with both parts rotated into the tool
        frame: ``J_tool = diag(R^T, R^T) J_base``, ``R`` the tool's rotation.

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    J, T = jacobian_and_pose(chain, q, column_walk=column_walk)
    return rotate_jacobian(J, np.swapaxes(T[..., :3, :3], -1, -2))


def rotate_jacobian(J, R) -> np.ndarray:
    """Both halves of a Jacobian rotated: ``diag(R, R) @ J``.

    Parameters
    ----------
    J : ndarray (..., 6, n)
        A Jacobian, rows linear then angular.
    R : ndarray (..., 3, 3)
        The rotation applied to each half, broadcast against ``J``'s leading dimensions
        (:func:`jacobian_tool` passes the tool's ``R^T``: world-frame rows to tool-frame).

    Returns
    -------
    ndarray (..., 6, n)
        A new array; ``J`` is not modified.
    """
    out = np.empty_like(J)
    out[..., :3, :] = R @ J[..., :3, :]
    out[..., 3:, :] = R @ J[..., 3:, :]
    return out


# --- analytic Jacobian -------------------------------------------------------

#: angle sets for the analytic Jacobian: each maps angles (a, b, c) to the
#: sequence of elementary axes of R = R_1(a) R_2(b) R_3(c). For RPY the
#: angles are (roll, pitch, yaw) and R = Rz(yaw) Ry(pitch) Rx(roll).
ANGLE_SETS = {
    "rpy": ("zyx", (2, 1, 0)),  # composition order, and which angle each factor uses
    "zyz": ("zyz", (0, 1, 2)),
    "xyz": ("xyz", (0, 1, 2)),
}

_UNIT = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}


def angular_rate_matrix(angles, kind: str) -> np.ndarray:
    """``E (..., 3, 3)`` with ``w = E(phi) phi_dot`` for the angle set ``kind``.

    For ``R = R_a(t1) R_b(t2) R_c(t3)`` the world-frame angular velocity is
    ``w = e_a t1' + R_a(t1) e_b t2' + R_a(t1) R_b(t2) e_c t3'``
    (Siciliano et al. 2009, sec. 3.6); columns are reordered to the set's
    own angle order. Singular at the set's gimbal lock.

    Parameters
    ----------
    angles : array_like (..., 3)
        The angles in the set's own order (rpy: roll, pitch, yaw), rad.
    kind : {'rpy', 'zyz', 'xyz'}
        The angle set (:data:`ANGLE_SETS`).

    Returns
    -------
    ndarray (..., 3, 3)
        ``E``: angle rates (rad/s) to the angular velocity in the world frame (rad/s).

    Raises
    ------
    KeyError
        An unknown ``kind``.
    """
    from .spatial import rot_x, rot_y, rot_z
    rot = {"x": rot_x, "y": rot_y, "z": rot_z}
    axes, which = ANGLE_SETS[kind]
    angles = np.asarray(angles, dtype=float)
    E = np.zeros(angles.shape[:-1] + (3, 3))
    R = np.broadcast_to(np.eye(3), angles.shape[:-1] + (3, 3))
    for axis, k in zip(axes, which):
        E[..., :, k] = R @ _UNIT[axis]
        R = R @ rot[axis](angles[..., k])
    return E


#: below this smallest singular value of E(phi) the angle set is at its gimbal lock: its
#: rates would be ~1e16 times the angular velocity, so no analytic Jacobian is given
GIMBAL_LOCK_CONDITION = 1e-9


def analytic_jacobian(J, angles, kind: str) -> np.ndarray:
    """The analytic Jacobian: the rates of an angle set instead of the angular velocity.

    Parameters
    ----------
    J : array_like (..., 6, n)
        The base-frame geometric Jacobian (:func:`jacobian_base`).
    angles : array_like (..., 3)
        The tool orientation's angles of the set ``kind`` (rad).
    kind : {'rpy', 'zyz', 'xyz'}
        The angle set (:data:`ANGLE_SETS`).

    Returns
    -------
    ndarray (..., 6, n)
        ``J_A = diag(I, E(phi)^-1) J``: rows ``vx vy vz`` and the time derivatives of the
        three angles.

    Raises
    ------
    numpy.linalg.LinAlgError
        At (within :data:`GIMBAL_LOCK_CONDITION` of) the set's representation singularity
        (gimbal lock), for any of the configurations.
    KeyError
        An unknown ``kind``.
    """
    if np.any(rate_matrix_condition(angles, kind) < GIMBAL_LOCK_CONDITION):
        raise np.linalg.LinAlgError(f"the {kind} angles are at their representation "
                                    "singularity (gimbal lock): no analytic Jacobian")
    E = angular_rate_matrix(angles, kind)
    out = np.array(J, dtype=float, copy=True)
    out[..., 3:, :] = np.linalg.solve(E, out[..., 3:, :])
    return out


def rate_matrix_condition(angles, kind: str) -> np.ndarray:
    """Smallest singular value of ``E(phi)`` (:func:`angular_rate_matrix`): 0 at the set's
    gimbal lock.

    Parameters
    ----------
    angles : array_like (..., 3)
        The angles of the set ``kind``, rad.
    kind : {'rpy', 'zyz', 'xyz'}
        The angle set (:data:`ANGLE_SETS`).

    Returns
    -------
    ndarray (...,)
        The smallest singular value (dimensionless).

    Raises
    ------
    KeyError
        An unknown ``kind``.
    """
    return np.linalg.svd(angular_rate_matrix(angles, kind), compute_uv=False)[..., -1]


def scaled_ranks(J, revolute, length: float):
    """``(rank of J, rank of its linear rows)`` of a Jacobian made scale-free first.

    A singular value counts when above ``SINGULAR_TOL`` times the largest (or times 1 when
    the largest is below 1).

    Parameters
    ----------
    J : array_like (..., 6, n)
        A geometric Jacobian, SI (copied, not modified).
    revolute : array_like of bool (n,)
        True for revolute joints (``robot.is_revolute``).
    length : float
        The length scale (m, e.g. ``robot.characteristic_length``): linear rows are divided
        by it and prismatic columns multiplied by it.

    Returns
    -------
    rank, position_rank : ndarray of int (...,)
        The rank of ``J`` and of its rows ``vx vy vz``; zeros when ``J`` is empty.
    """
    J = scale_free(J, revolute, length)
    if J.size == 0:
        z = np.zeros(J.shape[:-2], int)
        return z, z
    return _rank(J), _rank(J[..., :3, :])


def scale_free(J, revolute, length: float) -> np.ndarray:
    """A copy of the geometric Jacobian ``J (..., 6, n)`` (SI) without units: its linear
    rows divided by ``length`` (m) and its prismatic columns (``revolute (n,)`` False)
    multiplied by it, as :func:`scaled_ranks` takes it."""
    J = np.array(J, dtype=float)
    J[..., :3, :] /= length
    J[..., :, ~np.asarray(revolute, bool)] *= length
    return J


def numerical_rank(s) -> np.ndarray:
    """The number of singular values ``s (..., k)`` (descending) that count: above
    ``SINGULAR_TOL`` times the largest, or times 1 when the largest is below 1 (int
    ``(...)``; one rule for every rank test of a scale-free Jacobian)."""
    s = np.asarray(s, float)
    return np.sum(s > SINGULAR_TOL * np.maximum(s[..., :1], 1.0), axis=-1)


def _rank(M) -> np.ndarray:
    """The numerical rank of each matrix of ``M (..., r, c)`` (:func:`numerical_rank`)."""
    return numerical_rank(np.linalg.svd(M, compute_uv=False))


def rank_deficient(frames, revolute, length: float, ranks: tuple, columns=None) -> np.ndarray:
    """Is the Jacobian's rank below the generic rank (a singular configuration) at each of
    ``m`` configurations given by their frames?

    The rank test of :func:`scaled_ranks` (same tolerance), with the SVD taken only where the
    determinant does not prove the full rank of a 6-joint arm: ``s_min = |det| / prod`` of
    the other five, whose squares sum to at most ``|J|_F^2``, so that their product is at
    most ``(|J|_F^2 / 5)^(5/2)`` (the arithmetic-geometric mean inequality).

    Parameters
    ----------
    frames : ndarray (3, 4, n + 1, m) or (3, 2, n + 1, m)
        The joint frames and the tool pose entry by entry (:func:`kincalc.fk.entry_frames`,
        world frame, m), or their last two columns (axis, origin).
    revolute : ndarray (n,) of bool
        True for revolute joints.
    length : float
        The length scale (m, ``robot.characteristic_length``).
    ranks : tuple of int
        ``(rank, position rank)`` of the Jacobian at a generic configuration
        (``robot.generic_ranks``).
    columns : ndarray (k,) of int, optional
        Test these configurations of ``frames`` only (default all: ``k = m``).

    Returns
    -------
    ndarray (k,) of bool
        Either rank below the generic one (the linear rows against the position rank).
    """
    n = frames.shape[2] - 1
    # the transposed Jacobian (6, n, m) joint by joint, made scale-free as scaled_ranks makes
    # it: linear rows divided by L, prismatic columns times L (their linear rows then as they
    # are, their angular rows 0); it has the same singular values
    J = frames_jacobian(frames, revolute)
    if columns is not None:
        J = np.take(J, columns, axis=-1)                    # (C order, as J)
    m = J.shape[-1]
    J[:3] *= np.where(revolute, 1.0 / length, 1.0)[:, None]
    by_entry, J = J, J.transpose(2, 1, 0)                     # (6, n, m), (m, n, 6)
    full, full_pos = ranks
    out = np.zeros(m, bool)
    todo = slice(None)
    if n == 6 == full and full_pos == 3:
        fro = np.sqrt(np.add.reduce(J * J, axis=(1, 2)))
        todo = abs_det6(by_entry) <= SINGULAR_TOL * np.maximum(fro, 1.0) \
            * (fro * fro / 5.0) ** 2.5
        if not np.count_nonzero(todo):
            return out
    M = J[todo]
    rJ = _rank(M)
    sub = rJ < full
    rest = ~((rJ == 6) & (n == 6) & (full_pos == 3))
    if np.count_nonzero(rest):
        sub[rest] |= _rank(M[rest, :, :3]) < full_pos
    out[todo] = sub
    return out


#: from this many matrices on, :func:`abs_det6` takes the closed forms (numpy calls on rows
#: of the batch), below it LAPACK's (a call per matrix, fewer numpy calls)
SCHUR_FROM = 64


def abs_det6(J) -> np.ndarray:
    """``|det|`` of each 6x6 matrix of a batch.

    For :data:`SCHUR_FROM` matrices or more, by the Schur complement of the top-left 3x3
    block ``A``: ``det J = det(S) / det(A)^2`` with ``S = det(A) D - C adj(A) B``, all in
    closed form along the batch (some 8 times faster than LAPACK's LU a matrix at a time),
    where ``A`` is well-conditioned: ``|det A|`` at least 1e-2 of ``(|A|_F^2 / 3)^(3/2)``,
    its largest possible value, so that the division loses no more than two digits; by
    LAPACK for the others.

    Parameters
    ----------
    J : ndarray (6, 6, m)
        The matrices entry by entry (``J[r, c]`` is the batch of entries r, c).

    Returns
    -------
    ndarray (m,)
    """
    m = J.shape[-1]
    if m < SCHUR_FROM:
        return np.abs(np.linalg.det(J.transpose(2, 0, 1)))
    A, B, C, D = J[:3, :3], J[:3, 3:], J[3:, :3], J[3:, 3:]
    adj = _adjugate3(A)
    dA = np.add.reduce(A[0] * adj[:, 0], 0)
    S = D * dA - np.einsum("ikm,kjm->ijm", C, np.einsum("ikm,kjm->ijm", adj, B))
    dS = np.add.reduce(S[0] * _adjugate3(S)[:, 0], 0)
    poor = np.abs(dA) < 1e-2 * (np.add.reduce(A * A, axis=(0, 1)) / 3.0) ** 1.5
    out = np.abs(dS) / np.where(poor, 1.0, dA * dA)
    if np.count_nonzero(poor):
        out[poor] = np.abs(np.linalg.det(J[..., poor].transpose(2, 0, 1)))
    return out


def _adjugate3(a) -> np.ndarray:
    """The adjugate (transposed cofactors) of each 3x3 matrix of ``a (3, 3, m)``, ``(3, 3,
    m)``: ``a adj(a) = det(a) I``."""
    return np.array([
        [a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1], a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2],
         a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]],
        [a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2], a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0],
         a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]],
        [a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0], a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1],
         a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]]])


def finite_difference_jacobian(fk, q, revolute, scale: float, h: float = 1e-6):
    """Geometric Jacobian of any FK function by central differences.

    A column whose central difference ``fk`` refuses (ValueError, ArithmeticError: the edge
    of a mechanism's assembly region) is taken forward or backward, towards whichever side
    ``fk`` accepts; it stays 0 when ``fk`` refuses both sides.

    Parameters
    ----------
    fk : callable
        ``fk(q (n,)) -> T (4, 4)``, ``T_world_tool`` (SI).
    q : array_like (n,)
        Joint values (rad / m).
    revolute : array_like (n,) of bool
    scale : float
        The prismatic joints' step is ``h * scale`` (m).
    h : float
        The revolute joints' step (rad).

    Returns
    -------
    ndarray (6, n)
        World frame, linear rows (m per rad or per m) then angular.
    """
    from .spatial import rotvec_from_matrix
    q = np.asarray(q, float)
    n = len(q)
    J = np.zeros((6, n))

    def pose(x):
        try:
            return np.asarray(fk(x), float)
        except (ValueError, ArithmeticError):
            return None

    T0 = None
    for j in range(n):
        dq = np.zeros(n)
        dq[j] = h if revolute[j] else h * scale
        Tp, Tm = pose(q + dq), pose(q - dq)
        if Tp is None or Tm is None:                 # one-sided, from q itself
            T0 = pose(q) if T0 is None else T0
            Tp, Tm = (Tp, T0) if Tp is not None else (T0, Tm)
        if Tp is None or Tm is None:
            continue
        width = np.linalg.norm(dq) * (2 if Tp is not T0 and Tm is not T0 else 1)
        J[:3, j] = (Tp[:3, 3] - Tm[:3, 3]) / width
        J[3:, j] = rotvec_from_matrix(Tp[:3, :3] @ Tm[:3, :3].T) / width
    return J
