"""Branch labels: the words that name each solution's branch, the same in ``ik`` and
``ik --batch``.

A label is made of

* the geometric words where the arm has them (:func:`branch_geometry`, from the
  solution's joint frames): ``shoulder right/left`` (the side of the wrist point
  relative to the plane of axes 1 and 2), ``elbow up/down`` (for parallel axes 2 and 3,
  the elbow's side of the shoulder-to-wrist line), ``wrist no-flip/flip`` (the sign of
  ``(z4 x z6) . z5``);
* the +/- (or ``root k``) of every other step with more than one root, from the slot the
  solution came from (:class:`~kincalc.ik.branches.Branches` gives each slot its
  signs: one table per family, not a string per solution);
* ``(<joint> free)`` for a joint a singular target leaves undetermined;
* ``unique`` when there is nothing to tell.
"""

from __future__ import annotations

import numpy as np

from ..spatial import cross
from .cache import per_robot


#: the geometric words of a branch label, for the codes 1 and 2 of :func:`branch_geometry`
WORDS = (("shoulder right", "shoulder left"), ("elbow up", "elbow down"),
         ("wrist no-flip", "wrist flip"))
#: the joints whose +/- choice each word already names (shoulder 1, elbow 2 and 3, wrist 5)
_NAMED = ({0}, {1, 2}, {4})


def branch_geometry(robot, family: str, F) -> np.ndarray:
    """The geometric words of the branch labels of solutions with joint frames
    ``F (k, n, 4, 4)`` (:func:`kincalc.fk.chain_frames`, world frame): codes ``(k, 3)``
    for (shoulder, elbow, wrist), each 0 where the word does not apply, else 1 or 2 for
    the first or second word of :data:`WORDS` (see the module docstring for the rules).

    The point P of the rules (the wrist centre of a spherical wrist, where axes 5 and 6
    meet on a UR arm) is fixed in the frame of the joint before those axes, so it is
    carried from its coordinates there (:func:`_meeting_point_local`) instead of being
    intersected anew for every solution.
    """
    F = np.asarray(F, float)
    k = len(F)
    codes = np.zeros((k, 3), np.int8)
    first = {"spherical-wrist": 3, "three-parallel": 4}.get(family)
    if first is None or k == 0:
        return codes
    z, o = F[:, :, :3, 2], F[:, :, :3, 3]
    rev = robot.is_revolute
    local = _meeting_point_local(robot, first)
    if local is not None:
        P = (F[:, first - 1, :3, :3] @ local[:, None])[..., 0] + o[:, first - 1]
        if rev[0]:
            n01 = cross(z[:, 0], z[:, 1])
            side = np.einsum("ij,ij->i", P - o[:, 0], n01)
            codes[:, 0] = np.where(np.linalg.norm(n01, axis=-1) > 1e-6,
                                   np.where(side >= 0, 1, 2), 0)
        if robot.dof >= 3 and rev[1] and rev[2]:
            # the elbow (axis 3) against the shoulder-to-target line, in the plane of the
            # parallel axes 2 and 3; the target is P, or axis 4 for a UR arm
            sh, el, h = o[:, 1], o[:, 2], z[:, 1]
            tgt = P if family == "spherical-wrist" else o[:, 3]
            line = tgt - sh
            line = line - h * np.einsum("ij,ij->i", h, line)[:, None]
            v = el - sh
            v = v - h * np.einsum("ij,ij->i", h, v)[:, None]
            ll = np.maximum(np.einsum("ij,ij->i", line, line), 1e-300)
            perp = v - line * (np.einsum("ij,ij->i", v, line) / ll)[:, None]
            up = np.einsum("ij,ij->i", perp, z[:, 0])
            # the elbow on the line (stretched or folded): the turn sense decides
            alt = np.einsum("ij,ij->i", cross(el - sh, tgt - el), h)
            up = np.where(np.abs(up) < 1e-9 * robot.characteristic_length, alt, up)
            parallel = np.linalg.norm(cross(z[:, 1], z[:, 2]), axis=-1) < 1e-6
            codes[:, 1] = np.where(parallel, np.where(up >= 0, 1, 2), 0)
    w = np.einsum("ij,ij->i", cross(z[:, 3], z[:, 5]), z[:, 4])
    codes[:, 2] = np.where(w >= 0, 1, 2)
    return codes


@per_robot
def _meeting_point_local(robot, first: int):
    """Where axes ``first+1 .. n`` meet (least squares over their lines), ``(3,)`` in the
    coordinates of joint ``first``'s frame of :func:`kincalc.fk.chain_frames` (it moves
    only with the joints before them: the axes after it turn about lines through it), from
    the robot at q = 0; None if those axes are all parallel. Cached per robot."""
    from ..fk import chain_frames
    F = chain_frames(robot.chain, np.zeros(robot.dof))
    A, b = np.zeros((3, 3)), np.zeros(3)
    for j in range(first, robot.dof):
        Pj = np.eye(3) - np.outer(F[j, :3, 2], F[j, :3, 2])
        A += Pj
        b += Pj @ F[j, :3, 3]
    if np.linalg.svd(A, compute_uv=False)[-1] < 1e-6:
        return None
    P = np.linalg.solve(A, b)
    local = F[first - 1, :3, :3].T @ (P - F[first - 1, :3, 3])
    local.setflags(write=False)
    return local


def labels(robot, family: str, frames, signs, free) -> list:
    """The label of each solution: ``frames (s, n, 4, 4)`` its joint frames
    (:func:`kincalc.fk.chain_frames`), ``signs`` its slot's signs (a tuple of ``(joint,
    label)`` per solution), ``free (s, n)`` bool. Strings are made once per distinct
    combination of words, signs and free joints."""
    if len(frames) == 0:
        return []
    codes = branch_geometry(robot, family, frames)
    key = codes.astype(np.int64) @ np.array([9, 3, 1])
    bits = np.asarray(free, bool) @ (1 << np.arange(robot.dof, dtype=np.int64))
    names = [j.name for j in robot.joints]
    made: dict = {}
    out = []
    for k, sg, b in zip(key.tolist(), signs, bits.tolist()):
        label = made.get((k, sg, b))
        if label is None:
            words = (k // 9, k // 3 % 3, k % 3)
            parts = [WORDS[w][x - 1] for w, x in enumerate(words) if x]
            named = set().union(*(_NAMED[w] for w, x in enumerate(words) if x))
            parts += [f"{names[j]}:{lab}" for j, lab in sorted(sg) if j not in named]
            if b:
                parts.append("(" + ", ".join(names[j] for j in range(robot.dof) if b >> j & 1)
                             + " free)")
            label = made[(k, sg, b)] = " ".join(parts) if parts else "unique"
        out.append(label)
    return out
