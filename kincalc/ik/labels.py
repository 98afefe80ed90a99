"""Branch labels: the words that name each solution's branch, the same in ``ik`` and
``ik --batch``.

A label is made of

* the geometric words where the arm has them (:func:`branch_geometry`, from the
  solution's joint frames): ``shoulder right/left`` for an arm with a shoulder offset,
  ``shoulder front/back`` for one without (the side of the wrist point relative to the
  plane of axes 1 and 2), ``elbow up/down`` (for the first two parallel revolute axes
  among joints 1-3, the elbow's side of the shoulder-to-wrist line), ``wrist
  no-flip/flip`` (the sign of ``(z4 x z6) . z5``);
* the +/- (or ``root k``) of every other step with more than one root, from the slot the
  solution came from (:class:`~kincalc.ik.branches.Branches` gives each slot its
  signs: one table per family, not a string per solution);
* ``(<joint> free)`` for a joint a singular target leaves undetermined;
* ``unique`` when there is nothing to tell.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .cache import per_robot


#: the geometric words of a branch label, for the codes 1, 2, ... of :func:`branch_geometry`:
#: the shoulder of an arm with a shoulder offset (right/left) or without one (front/back),
#: the elbow, the wrist
WORDS = (("shoulder right", "shoulder left", "shoulder front", "shoulder back"),
         ("elbow up", "elbow down"), ("wrist no-flip", "wrist flip"))
#: the families whose steps the words name: the shoulder's step is joint 1's, the elbow's
#: the steps of its two joints, the wrist's joint 5's (a ``reversed-`` family has its wrist
#: at the base, and the other families split their roots otherwise)
WORDED = {"spherical-wrist", "three-parallel", "position-2", "position-3", "planar-3",
          "point-plus-roll", "pitch-roll"}


@dataclass(frozen=True)
class Geometry:
    """Which words of :data:`WORDS` an arm has and where their points are (robot-level).

    A point fixed in a link is ``(frame, local)``: its coordinates ``local (3,)`` (m) in
    the frame of :func:`kincalc.fk.chain_frames` that moves with that link.
    """

    #: P, the point the shoulder word judges; None: no shoulder word
    shoulder: tuple | None
    #: +1 or -1: the side of P at q = 0 (front); 0: the arm has a shoulder offset (right/left)
    front: int
    #: the elbow's joints (j, j + 1), revolute with parallel axes; None: no elbow word
    elbow: tuple | None
    #: W, the point the elbow reaches towards (the wrist)
    wrist_point: tuple | None
    #: the elbow's plane holds axis 1 (a spatial arm), else it is normal to it (a planar arm)
    spatial: bool
    #: +1 or -1: axis 1 as written points up, or down, in the world (a KUKA's A1 points
    #: down): the words are the world's, not the file's sign
    upward: float
    #: the same for the elbow's axes
    elbow_upward: float
    #: the wrist word (z4 x z6) . z5 applies
    wrist: bool
    #: the point the arm's first joints place, ``(frame, local)`` (the shoulder's P, else
    #: W, else the tool point), its name, and the joints that move it (0-based)
    placed: tuple = None
    placed_name: str = "tool point"
    arm: tuple = ()

    def named(self) -> tuple:
        """The joints (0-based) whose +/- choice each word already names."""
        return ({0}, set(self.elbow or ()), {4})


def branch_geometry(robot, family: str, frames) -> np.ndarray:
    """The geometric words of the branch labels of ``k`` solutions, as codes.

    The points of the rules (the wrist centre of a spherical wrist, where axes 5 and 6
    meet on a UR arm, the axis or tool point a planar arm reaches) are fixed in a link, so
    they are carried from their coordinates there (:func:`geometry`) instead of being
    found anew for every solution.

    Parameters
    ----------
    robot : Robot
    family : str
        The family's name; only those of :data:`WORDED` have words.
    frames : list of (tuple of 3 ndarray (3, k), ndarray (3, k))
        Per joint, its rotation's columns and origin (world frame, m), as
        :func:`kincalc.fk.frame_columns` gives them.

    Returns
    -------
    ndarray (k, 3) of int8
        Codes for (shoulder, elbow, wrist), each 0 where the word does not apply, else 1, 2,
        ... for the first, second, ... word of :data:`WORDS` (rules: ``man kincalc-ik``,
        BRANCH LABELS).
    """
    k = frames[0][1].shape[1] if frames else 0
    codes = np.zeros((k, 3), np.int8)
    geo = geometry(robot, family)
    if geo is None or k == 0:
        return codes
    z = [cols[2] for cols, _ in frames]
    o = [p for _, p in frames]
    if geo.shoulder is not None:
        side = geo.upward * _dot(_carried(frames, geo.shoulder) - o[0], _cross(z[0], z[1]))
        codes[:, 0] = (np.where(side >= 0, 1, 2) if geo.front == 0 else
                       np.where(geo.front * side >= 0, 3, 4))
    if geo.elbow is not None:
        codes[:, 1] = np.where(_elbow_up(robot, geo, z, o, _carried(frames, geo.wrist_point)),
                               1, 2)
    if geo.wrist:
        codes[:, 2] = np.where(_dot(_cross(z[3], z[5]), z[4]) >= 0, 1, 2)
    return codes


def _carried(frames, point):
    """A point fixed in a link, ``(frame, local)``, in the world: ``(3, k)``."""
    f, local = point
    cols, o = frames[f]
    return cols[0] * local[0] + cols[1] * local[1] + cols[2] * local[2] + o


def _elbow_up(robot, geo: Geometry, z, o, tgt):
    """``(k,)`` bool: the elbow is up (``man kincalc-ik``, BRANCH LABELS)."""
    j = geo.elbow[0]
    sh, el, h = o[j], o[j + 1], z[j] * geo.elbow_upward
    if not geo.spatial:
        # a planar elbow: on the counterclockwise side of the shoulder-to-wrist line, seen
        # from above (the tip of the axes turned up; (W - S) x (E - S) . h: components
        # along h drop out)
        return _dot(_cross(tgt - sh, el - sh), h) >= 0
    # the elbow against the shoulder-to-target line, in the plane of the parallel axes:
    # up on the side axis 1 points to, axis 1 turned to point up in the world
    line = tgt - sh
    line = line - h * _dot(h, line)
    v = el - sh
    v = v - h * _dot(h, v)
    ll = np.maximum(_dot(line, line), 1e-300)
    perp = v - line * (_dot(v, line) / ll)
    up = _dot(perp, z[0]) * geo.upward
    # the elbow on the line (stretched or folded): the turn sense decides
    alt = _dot(_cross(el - sh, tgt - el), h)
    return np.where(np.abs(up) < 1e-9 * robot.characteristic_length, alt, up) >= 0


def _dot(a, b):
    """``a . b`` of vectors stored as ``(3, k)`` columns."""
    return (a * b).sum(0)


def _cross(a, b):
    """``a x b`` of vectors stored as ``(3, k)`` columns."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


@per_robot
def geometry(robot, family: str) -> Geometry | None:
    """The words ``robot`` has when solved as ``family``, and their points (robot-level:
    a joint turns the axes after it together, so the angle between consecutive axes and
    the points fixed in a link are facts of the robot, read at q = 0). Cached per robot.

    Parameters
    ----------
    robot : Robot
    family : str
        The family's name.

    Returns
    -------
    Geometry or None
        None for a family not in :data:`WORDED`.
    """
    if family not in WORDED:
        return None
    from ..fk import chain_frames
    n, rev = robot.dof, robot.is_revolute
    F = chain_frames(robot.chain, np.zeros(n))
    z, o = F[:, :3, 2], F[:, :3, 3]
    parallel = lambda a, b: float(np.sum(np.cross(z[a], z[b]) ** 2)) < 1e-12  # noqa: E731
    tool = (n - 1, robot.chain.fixed[n][:3, 3])
    sixes = family in ("spherical-wrist", "three-parallel")
    elbow = next(((j, j + 1) for j in (0, 1) if j + 1 < n and rev[j] and rev[j + 1] and parallel(j, j + 1)), None)
    if family == "spherical-wrist":
        point = wrist = _meeting_point(robot, F, 3)
    elif family == "three-parallel":
        point, wrist = _meeting_point(robot, F, 4), (3, np.zeros(3))
    else:
        third = elbow is not None and elbow[1] + 1 < n and rev[elbow[1] + 1] \
            and parallel(elbow[1], elbow[1] + 1)
        point = wrist = (elbow[1] + 1, np.zeros(3)) if third else tool
    shoulder = point if rev[0] and n >= 2 and not parallel(0, 1) and point is not None else None
    front = 0
    if shoulder is not None:
        P = F[shoulder[0], :3, :3] @ shoulder[1] + F[shoulder[0], :3, 3]
        L = max(robot.characteristic_length, 1e-12)
        if abs((P - o[0]) @ z[1]) <= 1e-6 * L:        # no shoulder offset: front or back
            front = _front(robot, shoulder, _upward(z[0]))
    placed = shoulder or wrist or tool
    name = ("wrist centre" if family == "spherical-wrist" else
            "point where axes 5 and 6 meet" if family == "three-parallel" else
            "tool point" if placed is tool else f"point of axis {placed[0] + 1}")
    P = F[placed[0], :3, :3] @ placed[1] + F[placed[0], :3, 3]
    arm = list(range(placed[0] + 1))
    while arm and rev[arm[-1]] and np.linalg.norm(np.cross(z[arm[-1]], P - o[arm[-1]])) \
            <= 1e-9 * max(robot.characteristic_length, 1e-12):   # turning about the point
        arm.pop()
    return Geometry(shoulder=shoulder, front=front, elbow=elbow if wrist is not None else None,
                    wrist_point=wrist, spatial=elbow is not None and not parallel(0, elbow[0]),
                    upward=_upward(z[0]),
                    elbow_upward=_upward(z[elbow[0]]) if elbow is not None else 1.0,
                    wrist=sixes and n >= 6, placed=placed, placed_name=name, arm=tuple(arm))


@per_robot
def placed_point(robot, family: str):
    """The point the arm's first joints place and the joints that move it, for any family.

    A worded family's (:func:`geometry`); otherwise where the last three axes meet (a
    spherical wrist), else where the last two meet (a wrist pair), the joints before them
    being the arm. Cached per robot.

    Parameters
    ----------
    robot : Robot
    family : str

    Returns
    -------
    tuple or None
        ``((frame, local (3,)), name, arm joints)``: the point fixed in the link of
        :func:`kincalc.fk.chain_frames` frame ``frame`` (local coordinates, m); None when
        no axes meet (a general 6R: the arm is the whole chain).
    """
    geo = geometry(robot, family)
    if geo is not None:
        return geo.placed, geo.placed_name, geo.arm
    from ..fk import chain_frames
    from ..structure import common_point
    n = robot.dof
    F = chain_frames(robot.chain, np.zeros(n))
    tol = 1e-9 * max(robot.characteristic_length, 1e-12)
    for first, name in ((n - 3, "wrist centre"), (n - 2, f"point where axes {n - 1} and {n} meet")):
        if first >= 2 and robot.is_revolute[first:].all() and common_point(
                F[first:, :3, 3], F[first:, :3, 2], tol) is not None:
            frame, local = _meeting_point(robot, F, first)
            return (frame, local), name, tuple(range(first))
    return None


def _front(robot, point, upward: float) -> int:
    """The side (+1 or -1) of the shoulder word's point that is the front: its side at the
    robot's home joints (the arm reaching out), else at q = 0 when the point is on axis 1
    there (an arm standing straight up), else +1."""
    from ..fk import chain_frames
    L = max(robot.characteristic_length, 1e-12)
    for q in (np.asarray(robot.home, float), np.zeros(robot.dof)):
        F = chain_frames(robot.chain, q)
        P = F[point[0], :3, :3] @ point[1] + F[point[0], :3, 3]
        side = upward * (P - F[0, :3, 3]) @ np.cross(F[0, :3, 2], F[1, :3, 2])
        if abs(side) > 1e-6 * L:
            return 1 if side > 0 else -1
    return 1


def _upward(k) -> float:
    """+1 when the axis ``k`` (world frame) points up (world z), -1 when down, +1 when it
    is horizontal (a wall-mounted or planar-in-a-vertical-plane arm: its own sense)."""
    return -1.0 if k[2] < -1e-9 else 1.0


def _meeting_point(robot, F, first: int):
    """Where axes ``first+1 .. n`` meet (least squares over their lines) as a point fixed
    in the link of joint ``first`` (its frame moves only with the joints before those axes,
    which turn about lines through it): ``(first - 1, local (3,))``; None if the axes are
    all parallel. ``F``: the frames at q = 0."""
    from ..structure import common_point
    P = common_point(F[first:, :3, 3], F[first:, :3, 2], np.inf)
    if P is None:
        return None
    local = F[first - 1, :3, :3].T @ (P - F[first - 1, :3, 3])
    local.setflags(write=False)
    return first - 1, local


def labels(robot, family: str, frames, signs, slot, free) -> np.ndarray:
    """The branch label of each of ``s`` solutions.

    A string is made once per robot and distinct combination of words, signs and free
    joints, not per solution.

    Parameters
    ----------
    robot : Robot
    family : str
        The family's name (words only for :data:`WORDED`: a ``reversed-`` family has its
        wrist at the base, and the words' rules read joints 4-6 as the wrist).
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
    texts = _texts(robot, family)
    made = []
    for c in distinct.tolist():
        b, rest = c & ((1 << robot.dof) - 1), c >> robot.dof
        k, sg = rest // len(signs), signs[rest % len(signs)]
        key = (k, sg, b)
        if key not in texts:
            texts[key] = _text(robot, family, (k // 9, k // 3 % 3, k % 3), sg, b)
        made.append(texts[key])
    out[:] = np.array(made, object)[inverse.ravel()]
    return out


@per_robot
def _texts(robot, family: str) -> dict:
    """The labels made so far for ``robot`` solved as ``family``: (geometric code, signs,
    free bits) -> text."""
    return {}


def _text(robot, family, words, signs, free_bits) -> str:
    """One label: the geometric ``words`` (codes of :data:`WORDS`), the ``signs`` of the
    steps they do not name, the free joints (bit j: joint j)."""
    names = [j.name for j in robot.joints]
    parts = [WORDS[w][x - 1] for w, x in enumerate(words) if x]
    geo = geometry(robot, family)
    named = set().union(*(geo.named()[w] for w, x in enumerate(words) if x))
    parts += [f"{names[j]}:{lab}" for j, lab in sorted(signs) if j not in named]
    if free_bits:
        parts.append("(" + ", ".join(names[j] for j in range(robot.dof) if free_bits >> j & 1)
                     + " free)")
    return " ".join(parts) if parts else "unique"
