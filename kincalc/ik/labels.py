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

from .cache import per_robot


#: the geometric words of a branch label, for the codes 1 and 2 of :func:`branch_geometry`
WORDS = (("shoulder right", "shoulder left"), ("elbow up", "elbow down"),
         ("wrist no-flip", "wrist flip"))
#: the joints whose +/- choice each word already names (shoulder 1, elbow 2 and 3, wrist 5)
_NAMED = ({0}, {1, 2}, {4})


def branch_geometry(robot, family: str, frames) -> np.ndarray:
    """The geometric words of the branch labels of ``k`` solutions, as codes.

    The point P of the rules (the wrist centre of a spherical wrist, where axes 5 and 6
    meet on a UR arm) is fixed in the frame of the joint before those axes, so it is
    carried from its coordinates there (:func:`_meeting_point_local`) instead of being
    intersected anew for every solution.

    Parameters
    ----------
    robot : Robot
    family : str
        The family's solver name; only ``spherical-wrist`` and ``three-parallel`` have words.
    frames : list of (tuple of 3 ndarray (3, k), ndarray (3, k))
        Per joint, its rotation's columns and origin (world frame, m), as
        :func:`kincalc.fk.frame_columns` gives them.

    Returns
    -------
    ndarray (k, 3) of int8
        Codes for (shoulder, elbow, wrist), each 0 where the word does not apply, else 1 or
        2 for the first or second word of :data:`WORDS` (rules: the module docstring).
    """
    k = frames[0][1].shape[1] if frames else 0
    codes = np.zeros((k, 3), np.int8)
    first = {"spherical-wrist": 3, "three-parallel": 4}.get(family)
    if first is None or k == 0:
        return codes
    z = [cols[2] for cols, _ in frames]
    o = [p for _, p in frames]
    rev = robot.is_revolute
    local = _meeting_point_local(robot, first)
    skew_01, parallel_12 = _axis_pairs(robot)
    if local is not None:
        cols = frames[first - 1][0]
        P = cols[0] * local[0] + cols[1] * local[1] + cols[2] * local[2] + o[first - 1]
        if rev[0] and skew_01:
            side = _dot(P - o[0], _cross(z[0], z[1]))
            codes[:, 0] = np.where(side >= 0, 1, 2)
        if robot.dof >= 3 and rev[1] and rev[2] and parallel_12:
            # the elbow (axis 3) against the shoulder-to-target line, in the plane of the
            # parallel axes 2 and 3; the target is P, or axis 4 for a UR arm
            sh, el, h = o[1], o[2], z[1]
            tgt = P if family == "spherical-wrist" else o[3]
            line = tgt - sh
            line = line - h * _dot(h, line)
            v = el - sh
            v = v - h * _dot(h, v)
            ll = np.maximum(_dot(line, line), 1e-300)
            perp = v - line * (_dot(v, line) / ll)
            up = _dot(perp, z[0])
            # the elbow on the line (stretched or folded): the turn sense decides
            alt = _dot(_cross(el - sh, tgt - el), h)
            up = np.where(np.abs(up) < 1e-9 * robot.characteristic_length, alt, up)
            codes[:, 1] = np.where(up >= 0, 1, 2)
    w = _dot(_cross(z[3], z[5]), z[4])
    codes[:, 2] = np.where(w >= 0, 1, 2)
    return codes


def _dot(a, b):
    """``a . b`` of vectors stored as ``(3, k)`` columns."""
    return (a * b).sum(0)


def _cross(a, b):
    """``a x b`` of vectors stored as ``(3, k)`` columns."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


@per_robot
def _axis_pairs(robot) -> tuple:
    """``(axes 1 and 2 not parallel, axes 2 and 3 parallel)``: facts of the robot (a joint
    turns the axes after it together, so the angle between two consecutive axes is the
    same in every configuration), from q = 0. Cached per robot."""
    from ..fk import chain_frames
    z = chain_frames(robot.chain, np.zeros(robot.dof))[:, :3, 2]
    sin2 = lambda a, b: float(np.sum(np.cross(a, b) ** 2))  # noqa: E731
    return (sin2(z[0], z[1]) > 1e-12,
            robot.dof >= 3 and sin2(z[1], z[2]) < 1e-12)


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


def labels(robot, family: str, frames, signs, slot, free) -> np.ndarray:
    """The branch label of each of ``s`` solutions.

    A string is made once per robot and distinct combination of words, signs and free
    joints, not per solution.

    Parameters
    ----------
    robot : Robot
    family : str
        The family's name (a ``reversed-`` family has no geometric words: its wrist is at
        the base, and the words' rules read joints 4-6 as the wrist).
    frames : list of (tuple of 3 ndarray (3, s), ndarray (3, s))
        Their joint frames (:func:`kincalc.fk.frame_columns`, world frame, m).
    signs : tuple
        The family's sign table: per slot, a tuple of ``(joint, label)`` for each step with
        more than one root.
    slot : ndarray (s,) of int
        The slot each solution came from (index into ``signs``).
    free : array_like (s, n) of bool
        The joints each leaves free.

    Returns
    -------
    ndarray (s,) of object
        The labels (str); ``"unique"`` when there is nothing to tell.
    """
    out = np.empty(len(slot), object)
    if len(slot) == 0:
        return out
    codes = branch_geometry(robot, family, frames).astype(np.int64)
    bits = np.asarray(free, bool) @ (1 << np.arange(robot.dof, dtype=np.int64))
    code = ((codes @ np.array([9, 3, 1])) * len(signs) + slot) << robot.dof | bits
    distinct, inverse = np.unique(code, return_inverse=True)
    texts = _texts(robot)
    made = []
    for c in distinct.tolist():
        b, rest = c & ((1 << robot.dof) - 1), c >> robot.dof
        k, sg = rest // len(signs), signs[rest % len(signs)]
        key = (k, sg, b)
        if key not in texts:
            texts[key] = _text(robot, (k // 9, k // 3 % 3, k % 3), sg, b)
        made.append(texts[key])
    out[:] = np.array(made, object)[inverse.ravel()]
    return out


@per_robot
def _texts(robot) -> dict:
    """The labels made so far for ``robot``: (geometric code, signs, free bits) -> text."""
    return {}


def _text(robot, words, signs, free_bits) -> str:
    """One label: the geometric ``words`` (codes of :data:`WORDS`), the ``signs`` of the
    steps they do not name, the free joints (bit j: joint j)."""
    names = [j.name for j in robot.joints]
    parts = [WORDS[w][x - 1] for w, x in enumerate(words) if x]
    named = set().union(*(_NAMED[w] for w, x in enumerate(words) if x))
    parts += [f"{names[j]}:{lab}" for j, lab in sorted(signs) if j not in named]
    if free_bits:
        parts.append("(" + ", ".join(names[j] for j in range(robot.dof) if free_bits >> j & 1)
                     + " free)")
    return " ".join(parts) if parts else "unique"
