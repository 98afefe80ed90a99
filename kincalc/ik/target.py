"""What inverse kinematics must reach, for a batch of targets.

A :class:`Targets` holds ``N`` targets of one kind, world frame, SI:

* ``"pose"``: the whole pose ``T (N, 4, 4)``;
* ``"position"``: the tool position only (``T[:, :3, 3]``; the rotation part is the
  identity and means nothing) for robots that do not control the orientation;
* ``"approach"``: the position and the approach direction, the tool z axis
  (``approach (N, 3)``, unit), for five-joint arms that do not set the roll about it;
* ``"tcv"``: a tool configuration vector (Schilling 1990): the position, the approach
  and the last joint's value ``roll (N,)`` (rad).

:func:`targets_from` builds them from the orientation formats a user gives (RPY,
Euler angles, quaternions, axis-angle, matrices, ...), vectorised: the CLI, the batch
runner and the homework grader all use it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..spatial import invert_transform

KINDS = ("pose", "position", "approach", "tcv")


@dataclass(frozen=True)
class Targets:
    """``N`` IK targets of one ``kind`` (see the module docstring)."""

    T: np.ndarray
    kind: str = "pose"
    approach: np.ndarray | None = None
    roll: np.ndarray | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, not {self.kind!r}")

    def __len__(self) -> int:
        return len(self.T)

    @staticmethod
    def poses(T) -> "Targets":
        """Whole poses ``T (N, 4, 4)`` or one ``(4, 4)``."""
        T = np.asarray(T, float)
        return Targets(T.reshape(-1, 4, 4))

    def inverted(self) -> "Targets":
        """The inverse poses (for a chain solved from the tool: ``T^-1``)."""
        return Targets(invert_transform(self.T), self.kind, self.approach, self.roll)

    def take(self, index) -> "Targets":
        """The targets at ``index`` (an index array or mask into the N)."""
        pick = lambda x: None if x is None else x[index]  # noqa: E731
        return Targets(self.T[index], self.kind, pick(self.approach), pick(self.roll))
