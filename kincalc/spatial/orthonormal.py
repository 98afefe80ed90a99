"""Rotation matrices a user gives (a pose, ``--matrix``, a robot file's base or tool):
checked to be rotations as typed, to 6 decimals, and replaced by the nearest rotation."""

from __future__ import annotations

import numpy as np

from ..tolerances import ORTHONORMAL, ROTATION_TOL


def orthonormality_error(R) -> np.ndarray:
    """``max |R R^T - I|`` (entrywise) of matrices ``R (..., 3, 3)``: ``(...)``, NaN for a
    matrix with a NaN."""
    R = np.asarray(R, float)
    return np.abs(R @ np.swapaxes(R, -1, -2) - np.eye(3)).max((-1, -2))


def is_rotation(R) -> np.ndarray:
    """Whether matrices are rotations as a user types them: ``R R^T`` the identity to
    :data:`~kincalc.tolerances.ROTATION_TOL` entrywise (6 decimals pass) and ``det R > 0``.

    Parameters
    ----------
    R : array_like (..., 3, 3)

    Returns
    -------
    ndarray (...) of bool (False for a matrix with a NaN)
    """
    R = np.asarray(R, float)
    with np.errstate(invalid="ignore"):
        return (orthonormality_error(R) <= ROTATION_TOL) & (np.linalg.det(R) > 0)


def nearest_rotations(R) -> np.ndarray:
    """The nearest rotations (``U V^T`` of the SVD) to matrices that are rotations to a few
    digits (:func:`is_rotation`); a matrix orthonormal to
    :data:`~kincalc.tolerances.ORTHONORMAL` already is kept as given, bit for bit (an FK
    pose solved as computed).

    Parameters
    ----------
    R : array_like (..., 3, 3)

    Returns
    -------
    ndarray (..., 3, 3), a new array
    """
    R = np.array(R, float)
    off = orthonormality_error(R) > ORTHONORMAL
    if np.count_nonzero(off):
        u, _, vt = np.linalg.svd(R[off])
        R[off] = u @ vt
    return R
