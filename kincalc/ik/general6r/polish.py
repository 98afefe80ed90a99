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
    tables = walk_tables(chain)

    def evaluate(q, rows):
        F, jacobian = pose_and_jacobian(tables, q)
        Tr = T if len(rows) == len(T) else T[rows]      # the first pass: every row, in order
        R = Tr[:, :, :3] @ np.swapaxes(F[:, :3, :3], -1, -2)
        v, c2 = skew_trace(R)
        return (np.concatenate([Tr[:, :, 3] - F[:, :3, 3], rotation_log(v, c2, R)], axis=1),
                jacobian)
    return polish(evaluate, Q, iterations=iters, tol=1e-13, damping=1e-14,
                  stall=1e-2 * ACCEPT_TOL, give_up=GIVE_UP, max_step=STEP_MAX)


# --- the chain, the same bits for any number of candidates -------------------
#
# jacobian_and_pose takes stacked 4x4 products (BLAS) for up to FEW configurations and the
# column walk beyond: the two round differently, and Newton amplifies such differences
# where a pose has a continuum of solutions or two nearly coincide (a nearly singular
# Jacobian), so a pose's answers would depend on how many candidates the rest of its batch
# brings. Here up to _ELEMENTWISE rows take the walk's products and sums in the walk's
# order, elementwise over the rows (fewer, larger numpy calls: cheaper than the walk for
# few rows), and more rows the walk itself.

def walk_tables(chain):
    """``(A0 (4, 5, 1), links, offset (n,), chain)`` of a revolute chain for
    :func:`pose_and_jacobian`: the base's columns (rows x y z x y), and per joint the fixed
    link after it ``(4, 4, 1, 1)`` (row k, column j; row 3 is 0 0 0 1)."""
    F = chain.fixed
    return F[0, _XYZXY].T[:, :, None], list(F[1:, :, :, None, None]), chain.offset, chain


def pose_and_jacobian(tables, q):
    """The tool poses of ``q (N, n)`` (rad) and their Jacobians on demand, each row's bits
    independent of how many rows are evaluated together (see above).

    Returns
    -------
    F : ndarray (N, 3, 4) or (N, 4, 4)
        The tool poses' top rows (world frame).
    jacobian : callable
        ``jacobian(keep (N,) bool) -> (k, 6, n)``: the world-frame Jacobians (rows v, w) of
        the rows ``keep``, C-contiguous, zeros +0.
    """
    A0, links, offset, chain = tables
    if len(q) > _ELEMENTWISE:
        J, F = jacobian_and_pose(chain, q)
        return F, lambda keep: J[keep] + 0.0
    N, n = q.shape
    x = q + offset
    cs = np.empty((3, n, 1, N))                  # cos, sin, -sin of each joint
    np.cos(x.T, out=cs[0, :, 0])
    np.sin(x.T, out=cs[1, :, 0])
    np.negative(cs[1], out=cs[2])
    # A[i, j]: column j of the frame before joint i (the tool's for i = n), rows x y z x y
    # (the repeated rows make the cross products of the Jacobian slices)
    A = np.empty((n + 1, 4, 5, N))
    A[0] = A0
    for a, b, ci, si, F in zip(A[:-1], A[1:], cs[0], cs[1:].swapaxes(0, 1), links):
        # columns 0, 1 turned (c0 c + c1 s, c1 c - c0 s; written over the frame's, which
        # the Jacobian does not read), then times the fixed link: the walk's products, and
        # its sums in its order (a zero term adds nothing, column 3 adds the origin last)
        np.add(a[:2] * ci, a[1::-1] * si, out=a[:2])
        np.add.reduce(a[:, None] * F, axis=0, out=b)
    return A[n, :, :3].transpose(2, 1, 0), lambda keep: _jacobian(A)[keep]


def _jacobian(A):
    """``(N, 6, n)`` from the frames ``A (n + 1, 4, 5, N)`` of :func:`pose_and_jacobian`:
    columns ``(z_i x (p_tool - p_i), z_i)``, C-contiguous like the walk's, zeros +0."""
    n = len(A) - 1
    z = A[:n, 2]                                                 # (n, 5, N): x y z x y
    d = A[n, 3] - A[:n, 3]
    J = np.empty((A.shape[-1], 6, n))
    np.add((z[:, 1:4] * d[:, 2:5] - z[:, 2:5] * d[:, 1:4]).transpose(2, 1, 0), 0.0,
           out=J[:, :3])
    np.add(z[:, :3].transpose(2, 1, 0), 0.0, out=J[:, 3:])
    return J


def jacobian_and_pose_bitwise(chain, q):
    """:func:`kincalc.jacobian.jacobian_and_pose` of a revolute chain by
    :func:`pose_and_jacobian`: each row's bits independent of how many rows are evaluated.

    Parameters
    ----------
    chain : Chain
        Revolute joints only.
    q : ndarray (N, n)
        Rad.

    Returns
    -------
    J : ndarray (N, 6, n)
        The world-frame Jacobian (rows v, w), zeros +0.
    F : ndarray (N, 3, 4) or (N, 4, 4)
        The tool poses' top rows.
    """
    F, jacobian = pose_and_jacobian(walk_tables(chain), q)
    return jacobian(np.ones(len(q), bool)), F


#: rows up to which :func:`pose_and_jacobian` goes elementwise (beyond, the walk of
#: :func:`~kincalc.jacobian.jacobian_and_pose` is faster); above FEW, where that walks
_ELEMENTWISE = max(256, FEW)
_XYZXY = np.array([0, 1, 2, 0, 1])
