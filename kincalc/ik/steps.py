"""What the steps of a closed form record when asked (``--explain``, ``--all-branches``):
the intermediate quantities of a step and the steps that found no real root, per slot of
:class:`~kincalc.ik.branches.Branches`."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Note(NamedTuple):
    """One intermediate quantity of a step, for ``--explain``: ``value (N, K_at, ...)``
    at the slots of the step that made it (``at``: index into the lineage), SI, of
    ``kind`` ("length", "angle", "none", "joint:I")."""

    label: str
    value: np.ndarray
    kind: str
    at: int


class DeadEnd(NamedTuple):
    """A step that found no real root for some slots: ``joint`` (0-based), the equation
    ``cos(joint - phase) = need`` it had to solve (``phase``, ``need (N, K_at)``; a
    ``need`` beyond [-1, 1] is the reason), ``where (N, K_at)`` the slots it failed for,
    ``what`` the quantity placed (a sentence fragment)."""

    joint: int
    phase: np.ndarray
    need: np.ndarray
    where: np.ndarray
    what: str
    at: int
