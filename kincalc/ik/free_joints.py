"""Free joints turned to the target's orientation.

At a position singularity of an arm that places a point (the point on the line of a
revolute joint: a cylindrical arm's tool point on its base axis), the solver marks that
joint free and gives it a representative value: every value places the point. When the
target also gives an orientation that the arm does not control, the joint is not free
for that target. Turning it by ``delta`` turns the tool about its line,
``R_tool' = R(k, delta) R_tool`` (``k`` the joint's axis at the candidate, world frame),
and leaves the point where it is: the turn nearest the target's orientation
(:func:`~kincalc.subproblems.turns.nearest_turn` of ``E = R_target R_tool^T``) is the
joint's value for that target. Two free joints whose lines both hold the point (the
point where axes 1 and 2 meet: a spherical arm's slide at 0, an elbow of equal links
folded) take :func:`~kincalc.subproblems.turns.two_turns`. The candidate then reaches
the orientation when any value of the joints does, and they are no longer free; the
engine's check judges it like any other candidate.
"""

from __future__ import annotations

import numpy as np

from ..fk import entry_frames
from ..spatial import wrap
from ..subproblems import sp1, sp2
from ..subproblems.sp2 import free_angles
from ..subproblems.turns import nearest_turn, two_turns
from ..subproblems.solutions import Solutions
from .branches import Branches
from .target import Targets


def orient_free(robot, targets: Targets, br: Branches) -> Branches:
    """``br`` with each slot's free revolute joints (one or two) turned to its target's
    orientation.

    Only joints whose lines hold the tool point (turning them moves the tool's orientation
    alone) in a slot with no other free joint and no continuum relation (a relation ties
    the joint to another, which the orientation already fixes).

    Parameters
    ----------
    robot : Robot
        The robot whose chain the branches solve (world frame, SI).
    targets : Targets
        ``N`` targets; whole poses (``kind == "pose"``) give an orientation to turn to,
        tool configuration vectors (``"tcv"``) an approach (:func:`_to_approach`),
        otherwise ``br`` is returned as it is.
    br : Branches
        The solved branches, ``K`` slots per target.

    Returns
    -------
    Branches
        The same slots (for a TCV, two free joints split a slot in two: the second root of
        subproblem 2); a turned joint's value (rad), cosine and sine changed and its free
        mask cleared (world frame, SI throughout).
    """
    br = br.flushed()
    F = br.F                                                         # (n, N, K)
    if targets.kind not in ("pose", "tcv") or not np.count_nonzero(F):
        return br
    n, (N, K) = br.n, br.ok.shape
    count = np.add.reduce(F, axis=0)
    related = np.zeros((N, K), bool)
    for name in ("continuum", "parallel continuum"):
        if name in br.extra:
            related |= br.extra[name][..., 0] != 0
    q = br.q()
    A = entry_frames(robot.chain, q.reshape(-1, n))                  # (3, 4, n + 1, N K)
    R, p = A[:, :3, n], A[:, 3, n]                                   # tool rotation, point
    Rt = np.repeat(targets.T[:, :3, :3], K, axis=0)                  # (N K, 3, 3)
    E = np.einsum("mac,bcm->mab", Rt, R)                             # R_target R_tool^T
    tol = 1e-9 * max(robot.characteristic_length, 1e-12)
    turn = {}                         # joint -> its slots holding the tool point (N K,)
    for j in np.flatnonzero(robot.is_revolute & F.reshape(n, -1).any(axis=1)).tolist():
        k, o = A[:, 2, j], A[:, 3, j]                                # (3, N K)
        on_line = np.linalg.norm(np.cross(k, p - o, axis=0), axis=0) <= tol
        turn[j] = (F[j] & ~related).reshape(-1) & on_line
    if targets.kind == "tcv":
        return _to_approach(targets, br, A, turn, count)
    delta = {j: np.zeros(N * K) for j in turn}
    done = {j: turn[j] & (count == 1).reshape(-1) for j in turn}     # one free joint
    for j in turn:
        if np.count_nonzero(done[j]):
            delta[j] = np.where(done[j], nearest_turn(A[:, 2, j].T, E), 0.0)
    for a, b in ((a, b) for a in turn for b in turn if a < b):       # two: a before b
        t = turn[a] & turn[b] & (count == 2).reshape(-1)
        if np.count_nonzero(t):
            da, db = two_turns(A[:, 2, a].T, A[:, 2, b].T, E)
            delta[a], delta[b] = np.where(t, da, delta[a]), np.where(t, db, delta[b])
            done[a], done[b] = done[a] | t, done[b] | t
    for j in turn:
        if np.count_nonzero(done[j]):
            value = wrap(q[..., j] + delta[j].reshape(N, K))
            br = br.set(j, value, np.cos(value), np.sin(value),
                        free=F[j] & ~done[j].reshape(N, K))
    return br.flushed()


def _to_approach(targets: Targets, br: Branches, A, turn: dict, count) -> Branches:
    """The free joints of ``turn`` (joint -> its slots holding the tool point, ``(N K,)``)
    turned so that the tool's z axis (``A[:, 2, n]``, world frame, of the frames ``A (3, 4,
    n + 1, N K)``) reaches the target's approach (a TCV: the last joint, the roll, is
    given). One joint ``j``: ``R(k_j, x) z = a`` (subproblem 1, least squares); two, ``a``
    before ``b``: ``R(k_a, x) R(k_b, y) z = a`` (subproblem 2: two roots, each slot split
    in two, the second empty where it has none). A joint stays free where its turn leaves
    the approach where it is (``z`` along its axis)."""
    n, (N, K) = br.n, br.ok.shape
    z = A[:, 2, n].T                                                 # (N K, 3)
    a = np.repeat(targets.approach, K, axis=0)
    q = br.q()
    for j in turn:
        one = (turn[j] & (count == 1).reshape(-1)).reshape(N, K)
        if np.count_nonzero(one):
            sol = sp1(z, a, A[:, 2, j].T, tol=0.0)
            v = wrap(q[..., j] + np.where(one, sol.theta[0][:, 0].reshape(N, K), 0.0))
            still = sol.free[:, 0].reshape(N, K)
            br = br.set(j, v, np.cos(v), np.sin(v), free=br.F[j] & ~(one & ~still))
    br = br.flushed()
    for ja, jb in ((ja, jb) for ja in turn for jb in turn if ja < jb):
        t = (turn[ja] & turn[jb] & (count == 2).reshape(-1)).reshape(N, K)
        if not np.count_nonzero(t):
            continue
        sol = sp2(z, a, A[:, 2, ja].T, A[:, 2, jb].T)
        t2 = t[..., None]
        x, y = (wrap(q[..., j][..., None] + np.where(t2, d.reshape(N, K, 2), 0.0))
                for j, d in ((ja, sol.theta[0]), (jb, sol.theta[1])))
        ok = np.where(t2, sol.ok.reshape(N, K, 2), np.array([True, False]))
        still = free_angles(t & sol.free.reshape(N, K, 2).any(-1), z.reshape(N, K, 3),
                          a.reshape(N, K, 3), A[:, 2, ja].T.reshape(N, K, 3),
                          A[:, 2, jb].T.reshape(N, K, 3))
        for j, f in zip((ja, jb), still):
            br = br.set(j, q[..., j], free=(br.F[j] & ~t) | f)
        br = br.branch([ja, jb], Solutions((x, y), (np.cos(x), np.cos(y)), (np.sin(x), np.sin(y)),
                                           ok, np.ones_like(ok), np.zeros_like(ok)),
                       labels=(None, None))
    return br.flushed()
