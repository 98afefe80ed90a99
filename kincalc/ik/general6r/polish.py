"""Newton polishing of the general-6R candidates on the real robot (step 6 of
:mod:`kincalc.ik.general6r`), with the pose residual as a rotation vector."""

from __future__ import annotations

import numpy as np

from ...fk import FEW
from ...jacobian import jacobian_and_pose
from ...spatial import rotvec_from_matrix
from ..newton import polish
from .common import ACCEPT_TOL, GIVE_UP, NEWTON_ITERS, STEP_MAX, nnz, reduce_sum


# --- Newton polishing on the real robot -----------------------------------

_ROT_IDX = np.array([7, 2, 3, 5, 6, 1, 0, 4, 8])   # R21 R02 R10, R12 R20 R01, R00 R11 R22


def skew_trace(R):
    """The skew part and the trace of rotations.

    Parameters
    ----------
    R : ndarray (m, 3, 3)

    Returns
    -------
    v : ndarray (m, 3)
        ``2 sin(angle) axis`` (the skew part, doubled).
    c2 : ndarray (m,)
        ``2 cos(angle)``.
    """
    g = np.take(R.reshape(-1, 9), _ROT_IDX, axis=1)
    return g[:, :3] - g[:, 3:6], reduce_sum(g[:, 6:], axis=1) - 1.0


def rotation_log(v, c2, R):
    """Rotation vectors from :func:`skew_trace`.

    Parameters
    ----------
    v, c2 : ndarray (m, 3), (m,)
        :func:`skew_trace` of ``R``.
    R : ndarray (m, 3, 3)
        The rotations (read only beyond 90 degrees, where the skew part is inaccurate).

    Returns
    -------
    ndarray (m, 3)
        ``angle axis`` (rad).
    """
    sn = np.sqrt(reduce_sum(v * v, axis=1))
    w = v * (np.arctan2(sn, c2) / np.maximum(sn, 1e-300))[:, None]
    far = c2 < 0.0
    if nnz(far):
        w[far] = rotvec_from_matrix(R[far])
    return w


def polish_candidates(chain, T, Q, iters=NEWTON_ITERS):
    """Newton (:func:`kincalc.ik.newton.polish`) on ``fk(q) = T`` for the candidates ``Q``.

    A candidate stops when its residual ``max(|dp| / L, |dw|)`` is at rounding level (below
    1e-13, or below ACCEPT_TOL / 100 and no longer halving), after ``iters`` steps, or when
    it is still far after a few (``GIVE_UP``: spurious candidates from complex eigenvalues;
    the few that would wander into a solution after many steps only find one that a good
    candidate already gave).

    Parameters
    ----------
    chain : Chain
        The robot's, with lengths divided by its length scale L.
    T : ndarray (m, 3, 4)
        Each candidate's target (rows 0-2 of ``T_world_tool``, translation scaled alike).
    Q : ndarray (m, 6)
        The starts (rad).
    iters : int
        Newton steps at most (steps of at most ``STEP_MAX`` rad).

    Returns
    -------
    q : ndarray (m, 6)
        Rad, not wrapped.
    residual : ndarray (m,)
        Each one's last residual: the largest component of ``(dp / L, dw)`` (rad).
    moved : ndarray (m,) of bool
        The candidates that took a step.
    """
    def evaluate(q, rows):
        J, F = jacobian_and_pose_bitwise(chain, q)
        Tr = T if len(rows) == len(T) else T[rows]      # the first pass: every row, in order
        R = Tr[:, :, :3] @ np.swapaxes(F[:, :3, :3], -1, -2)
        v, c2 = skew_trace(R)
        return (np.concatenate([Tr[:, :, 3] - F[:, :3, 3], rotation_log(v, c2, R)], axis=1),
                lambda keep: J[keep])
    return polish(evaluate, Q, iterations=iters, tol=1e-13, damping=1e-14,
                  stall=1e-2 * ACCEPT_TOL, give_up=GIVE_UP, max_step=STEP_MAX)


# --- the chain, the same bits for any number of candidates -------------------

def jacobian_and_pose_bitwise(chain, q):
    """:func:`kincalc.jacobian.jacobian_and_pose` of a revolute chain, each row's bits
    independent of how many rows are evaluated together.

    :func:`~kincalc.jacobian.jacobian_and_pose` takes stacked 4x4 products (BLAS) for up to
    ``FEW`` configurations and the column walk beyond: the two round differently, and
    Newton amplifies such differences where a pose has a continuum of solutions or two
    nearly coincide (a nearly singular Jacobian), so a pose's answers would depend on
    how many candidates the rest of its batch brings. Here up to ``_ELEMENTWISE`` rows
    take the walk's products and sums in the walk's order, elementwise over the rows
    (fewer, larger numpy calls: a few times cheaper than the walk for few rows), and
    more rows the walk itself; zeros of ``J`` are made +0.

    Parameters
    ----------
    chain : Chain
        Revolute joints only.
    q : ndarray (N, n)
        Rad.

    Returns
    -------
    J : ndarray (N, 6, n)
        The world-frame Jacobian (rows v, w).
    F : ndarray (N, 3, 4) or (N, 4, 4)
        The tool poses' top rows.
    """
    if len(q) > _ELEMENTWISE:
        J, F = jacobian_and_pose(chain, q)
        return J + 0.0, F
    N, n = q.shape
    Fx = chain.fixed
    x = (q + chain.offset).T                                     # (n, N)
    c = np.cos(x)[:, None, :]
    s = np.sin(x)
    ss = np.stack([s, -s], axis=1)[:, :, None, :]                # (n, 2, 1, N)
    A = np.empty((n + 1, 4, 3, N))       # A[i, j]: column j of the frame before joint i
    A[0] = Fx[0, :3].T[:, :, None]
    F01, F2 = Fx[1:, :2, :, None, None], Fx[1:, 2, :, None, None]
    for i in range(n):
        a = A[i]
        r01 = a[:2] * c[i] + a[1::-1] * ss[i]       # columns 0, 1 turned: c0 c + c1 s, c1 c - c0 s
        p = r01[:, None] * F01[i]                    # times the fixed link's rows 0, 1
        b = A[i + 1]
        np.add(p[0], p[1], out=b)
        b += a[2] * F2[i]
        b[3] += a[3]
    z = A[:n, 2]                                                 # (n, 3, N)
    d = A[n, 3] - A[:n, 3]
    J = np.empty((N, 6, n))
    J[:, :3] = (z[:, _CY1] * d[:, _CY2] - z[:, _CY2] * d[:, _CY1]).transpose(2, 1, 0)
    J[:, 3:] = z.transpose(2, 1, 0)
    return J + 0.0, A[n].transpose(2, 1, 0)


#: rows up to which :func:`jacobian_and_pose_bitwise` goes elementwise (beyond, the walk
#: of :func:`~kincalc.jacobian.jacobian_and_pose` is faster); above FEW, where that walks
_ELEMENTWISE = max(256, FEW)
_CY1, _CY2 = np.array([1, 2, 0]), np.array([2, 0, 1])
