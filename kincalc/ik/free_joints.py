"""Free joints turned to the target's orientation.

At a position singularity of an arm that places a point (the point on the line of a
revolute joint: a cylindrical arm's tool point on its base axis), the solver marks that
joint free and gives it a representative value: every value places the point. When the
target also gives an orientation that the arm does not control, the joint is not free
for that target. Turning it by ``delta`` turns the tool about its line,
``R_tool' = R(k, delta) R_tool`` (``k`` the joint's axis at the candidate, world frame),
and leaves the point where it is. The ``delta`` nearest the target's orientation
``R_target`` maximises ``tr(R(k, delta)^T E)`` with ``E = R_target R_tool^T``:

    delta = atan2(k . e, tr E - k^T E k),  e = (E32 - E23, E13 - E31, E21 - E12)

(subproblem 1 in its least-squares form, over the three axes of the tool frame). The
candidate then reaches the orientation when any value of the joint does, and the joint
is no longer free; the engine's check judges it like any other candidate.
"""

from __future__ import annotations

import numpy as np

from ..fk import entry_frames
from ..spatial import wrap
from .branches import Branches
from .target import Targets


def orient_free(robot, targets: Targets, br: Branches) -> Branches:
    """``br`` with each slot's one free revolute joint turned to its target's orientation.

    Only a joint whose line holds the tool point (turning it moves the tool's orientation
    alone) in a slot with no other free joint and no continuum relation (a relation ties
    the joint to another, which the orientation already fixes).

    Parameters
    ----------
    robot : Robot
        The robot whose chain the branches solve (world frame, SI).
    targets : Targets
        ``N`` targets; only whole poses (``kind == "pose"``) give an orientation to turn
        to, otherwise ``br`` is returned as it is.
    br : Branches
        The solved branches, ``K`` slots per target.

    Returns
    -------
    Branches
        The same slots; a turned joint's value (rad), cosine and sine changed and its free
        mask cleared.
    """
    br = br.flushed()
    F = br.F                                                         # (n, N, K)
    if targets.kind != "pose" or not np.count_nonzero(F):
        return br
    n, (N, K) = br.n, br.ok.shape
    alone = np.add.reduce(F, axis=0) == 1
    for name in ("continuum", "parallel continuum"):
        if name in br.extra:
            alone &= br.extra[name][..., 0] == 0
    q = br.q()
    A = entry_frames(robot.chain, q.reshape(-1, n))                  # (3, 4, n + 1, N K)
    R, p = A[:, :3, n], A[:, 3, n]                                   # tool rotation, point
    Rt = np.repeat(targets.T[:, :3, :3], K, axis=0)                  # (N K, 3, 3)
    E = np.einsum("mac,bcm->mab", Rt, R)                             # R_target R_tool^T
    e = np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]])
    trace = np.einsum("mii->m", E)
    tol = 1e-9 * max(robot.characteristic_length, 1e-12)
    for j in np.flatnonzero(robot.is_revolute & F.reshape(n, -1).any(axis=1)).tolist():
        k, o = A[:, 2, j], A[:, 3, j]                                # (3, N K)
        on_line = np.linalg.norm(np.cross(k, p - o, axis=0), axis=0) <= tol
        turn = (F[j] & alone).reshape(-1) & on_line
        if not np.count_nonzero(turn):
            continue
        kEk = np.einsum("am,mab,bm->m", k, E, k)
        delta = np.where(turn, np.arctan2(np.einsum("am,am->m", k, e), trace - kEk), 0.0)
        value = wrap(q[..., j] + delta.reshape(N, K))
        br = br.set(j, value, np.cos(value), np.sin(value), free=F[j] & ~turn.reshape(N, K))
    return br.flushed()
