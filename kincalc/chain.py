"""The robot's uniform chain, as data: what forward kinematics, Jacobians and the IK
engine evaluate, whatever convention the robot was written in.

    T_world_tool(q) = F_0 · J_1(q_1 + c_1) · F_1 · J_2(q_2 + c_2) · ... · J_n(q_n + c_n) · F_n

``F_i`` constant transforms ``(4, 4)`` (lengths in m), ``J_i`` a rotation about (revolute)
or a translation along (prismatic) the local z axis. :class:`kincalc.model.Robot` builds
its chain from its joints (``Robot.chain``); this module knows no convention.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np


@dataclass(frozen=True)
class Chain:
    """``T(q) = F_0 J_1(q_1 + c_1) F_1 ... J_n(q_n + c_n) F_n``.

    ``T(q)`` is ``T_world_tool`` for joint values ``q (n,)`` (rad for revolute, m for
    prismatic joints).

    Attributes
    ----------
    fixed : ndarray (n + 1, 4, 4)
        The constant transforms ``F_i`` (lengths in m), base folded into ``F_0``, tool into
        ``F_n``.
    revolute : ndarray (n,) of bool
        ``J_i`` is ``Rz`` (True) or ``Tz`` (False).
    offset : ndarray (n,)
        ``c_i``, added to the joint variable (rad or m).
    """

    fixed: np.ndarray
    revolute: np.ndarray
    offset: np.ndarray

    @property
    def dof(self) -> int:
        """Number of joints ``n`` (int), the length of :attr:`revolute`."""
        return len(self.revolute)

    @cached_property
    def offset_cos_sin(self) -> tuple:
        """``(cos c_i, sin c_i)``, each ``(n,)`` (unitless): the offsets' turn, for revolute joint
        angles given by their cosines and sines (unused for prismatic joints). Computed once per
        chain and cached.
        """
        return np.cos(self.offset), np.sin(self.offset)

    @cached_property
    def fixed_terms(self) -> tuple:
        """The nonzero entries of each ``F_i``, for the column walk of :mod:`kincalc.fk`:
        ``fixed_terms[i][j]`` lists ``(k, F_i[k, j])`` (a float) for the rows k < 3 of column
        j (3: the translation) where the entry is not 0. Computed once per chain and cached.
        """
        return tuple(tuple(tuple((k, float(F[k, j])) for k in range(3) if F[k, j] != 0.0)
                           for j in range(4)) for F in self.fixed)

    @cached_property
    def motion_basis(self) -> np.ndarray:
        """``(n, 4, 16)``, read-only: joint i's motion ``J_i(x)`` (4x4, flattened) is
        ``[cos x, sin x, x, 1] @ motion_basis[i]``: ``Rz(x)`` for a revolute joint, ``Tz(x)``
        for a prismatic one (x = q_i + c_i, rad or m). Computed once per chain and cached.
        """
        rz = np.zeros((4, 4, 4))
        rz[0, 0, 0] = rz[0, 1, 1] = 1.0                     # cos x
        rz[1, 1, 0], rz[1, 0, 1] = 1.0, -1.0                # sin x
        rz[3, 2, 2] = rz[3, 3, 3] = 1.0                     # 1
        tz = np.zeros((4, 4, 4))
        tz[2, 2, 3] = 1.0                                   # x
        tz[3] = np.eye(4)                                   # 1
        basis = np.where(self.revolute[:, None, None, None], rz, tz).reshape(-1, 4, 16)
        basis.setflags(write=False)
        return basis
