"""Turns about given axes that make up a given rotation: subproblem 1 on a whole frame.

:func:`nearest_turn`: find ``delta`` with ``R(k, delta)`` nearest the rotation ``E``, the
one maximising ``tr(R(k, delta)^T E)`` (the least-squares form of subproblem 1 over the
three axes of a frame):

    delta = atan2(k . e, tr E - k^T E k),  e = (E32 - E23, E13 - E31, E21 - E12).

One solution; exact where ``E`` is a rotation about ``k``. Ill-posed where both
arguments are 0 (``E`` a half turn about an axis normal to ``k``): every ``delta`` is as
near, and ``delta = 0``.

:func:`two_turns`: find ``(delta_a, delta_b)`` with ``R(k_a, delta_a) R(k_b, delta_b) =
E``. Axis ``k_b`` is left where it is by its own turn, so ``R(k_a, delta_a) k_b = E k_b``
(subproblem 1, its least-squares angle where ``E`` is not of that form), then
``delta_b`` is the turn about ``k_b`` nearest ``R(k_a, delta_a)^T E``. One solution;
ill-posed where ``k_a`` is along ``k_b`` (only the sum of the turns is fixed: ``delta_a =
0`` carries nothing).

Used to turn joints that a position leaves free to what the rest of a target asks for.
"""

from __future__ import annotations

import numpy as np

from ..spatial import matrix_from_axis_angle
from .sp1 import sp1


def nearest_turn(k, E) -> np.ndarray:
    """The turn about ``k`` nearest the rotation ``E`` (module docstring).

    Parameters
    ----------
    k : ndarray (..., 3)
        Unit axes, in one frame.
    E : ndarray (..., 3, 3)
        Rotations in that frame; the leading shapes broadcast.

    Returns
    -------
    ndarray (...)
        ``delta`` (rad), in (-pi, pi].
    """
    e = np.stack([E[..., 2, 1] - E[..., 1, 2], E[..., 0, 2] - E[..., 2, 0],
                  E[..., 1, 0] - E[..., 0, 1]], axis=-1)
    kEk = np.einsum("...a,...ab,...b->...", k, E, k)
    return np.arctan2(np.einsum("...a,...a->...", k, e), np.einsum("...ii->...", E) - kEk)


def two_turns(ka, kb, E) -> tuple:
    """The turns about ``ka`` then ``kb`` that make up the rotation ``E`` (module docstring).

    Parameters
    ----------
    ka, kb : ndarray (..., 3)
        Unit axes, in one frame.
    E : ndarray (..., 3, 3)
        Rotations in that frame; the leading shapes broadcast.

    Returns
    -------
    delta_a, delta_b : ndarray (...)
        Rad, in (-pi, pi].
    """
    Ekb = np.einsum("...ab,...b->...a", E, kb)
    da = sp1(kb, Ekb, ka, tol=0.0).theta[0][..., 0]
    Ra = matrix_from_axis_angle(ka, da)
    return da, nearest_turn(kb, np.swapaxes(Ra, -1, -2) @ E)
