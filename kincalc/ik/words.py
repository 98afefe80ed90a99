"""The geometric words of the branch labels (``shoulder``, ``elbow``, ``wrist``): which
an arm has, the products of its axes and points that decide them, and their codes for
many solutions at once (:func:`branch_geometry`; the rules: ``man kincalc-ik``, BRANCH
LABELS).

A word is the sign of a product of the solution's axes and of points fixed in its links.
Those products are polynomials of a few joint values, fitted once per robot
(:mod:`~kincalc.ik.joint_polynomials`), so the words of a batch need no solution's frames.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..fk import chain_frames, entry_frames
from ..spatial import LEVI_CIVITA
from ..tolerances import WORD_BOUNDARY
from .cache import per_robot
from .families import THREE_PARALLEL
from .joint_polynomials import fit


#: the geometric words of a branch label, for the codes 1, 2, ... of :func:`branch_geometry`:
#: the shoulder of an arm with a shoulder offset (right/left) or without one (front/back),
#: the elbow, the wrist
WORDS = (("shoulder right", "shoulder left", "shoulder front", "shoulder back"),
         ("elbow up", "elbow down"), ("wrist no-flip", "wrist flip"))
#: the families whose steps the words name: the shoulder's step is joint 1's, the elbow's
#: the steps of its two joints, the wrist's joint 5's (a ``reversed-`` family has its wrist
#: at the base, and the other families split their roots otherwise)
WORDED = {"spherical-wrist", "three-parallel", "three-parallel-offset", "position-2",
          "position-3", "planar-3", "point-plus-roll", "reversed-point-plus-roll", "pitch-roll"}


class Geometry(NamedTuple):
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


def branch_geometry(robot, family: str, q) -> np.ndarray:
    """The geometric words of the branch labels of ``k`` solutions, as codes.

    Each word is the sign of a few products of the solution's axes and of points fixed in
    its links (the wrist centre of a spherical wrist, where axes 5 and 6 meet on a UR arm,
    the axis or tool point a planar arm reaches): :func:`products`, evaluated once per
    robot on sampled frames and fitted there as polynomials of the joint values
    (:mod:`~kincalc.ik.joint_polynomials`; the wrist's product depends on joint 5 alone,
    the shoulder's not on joint 1). The words of many solutions are then a few array
    operations on the cosines and sines of the joints involved, with no solution's frames.

    Parameters
    ----------
    robot : Robot
    family : str
        The family's name; only those of :data:`WORDED` have words.
    q : ndarray (k, n)
        The solutions' joint values (rad / m).

    Returns
    -------
    ndarray (k, 3) of int8
        Codes for (shoulder, elbow, wrist), each 0 where the word does not apply, else 1, 2,
        ... for the first, second, ... word of :data:`WORDS` (rules: ``man kincalc-ik``,
        BRANCH LABELS).
    """
    k = len(q)
    R = rules(robot, family)
    if R is None or k == 0:
        return np.zeros((k, 3), np.int8)
    fitted = _fitted(robot, family)
    dots = fitted(q) if fitted is not None else \
        products(R, robot.dof, entry_frames(robot.chain, np.asarray(q, float)))
    if len(R.words) == 3:                            # every word: R.words is 0, 1, 2
        return _codes(R, dots).T
    codes = np.zeros((3, k), np.int8)
    codes[R.words] = _codes(R, dots)
    return codes.T


def products(R, n: int, frames) -> np.ndarray:
    """The products ``(c + lin, k)`` the words of ``R`` are read from (:class:`Rules`), from
    ``k`` solutions' frames entry by entry (``(3, 4, n(+1), k)``, :func:`kincalc.fk.entry_frames`,
    world frame, m).

    The vectors of the rules and their differences are one product with a matrix of 0 and
    +-1 (exact: each entry is a vector or the difference of two), the cross products another
    (with the Levi-Civita symbol, of the vectors' outer products), then the dot products,
    each times its sign (``R.sign``, exact: the words of :func:`_codes` are then the signs
    of the products as they are, in the world's sense)."""
    k = frames.shape[-1]
    # the vectors (m, 3, k): the frames' axes and origins, then the carried points
    V = np.empty((R.selection.shape[1], 3, k))
    V[:2 * n].reshape(2, n, 3, k)[...] = frames[:, 2:, :n].transpose(1, 2, 0, 3)
    np.add.reduce(frames[:, :, R.point_frames] * R.point_local, axis=1,
                  out=V[2 * n:].transpose(1, 0, 2))
    Y = (R.selection @ V.reshape(len(V), -1)).reshape(-1, 3, k)  # operands, differences
    c = R.crosses
    X = LEVI_CIVITA @ (Y[:c, :, None] * Y[c:2 * c, None]).reshape(c, 9, k)   # (c, 3, k)
    return np.add.reduce(Y[2 * c:3 * c + R.lin] * np.concatenate((X, Y[3 * c + R.lin:])),
                         axis=1) * R.sign


def _codes(R, dots) -> np.ndarray:
    """The codes ``(words, k)`` of :func:`branch_geometry` from the :func:`products`."""
    w = len(R.words)
    word = dots[:w]
    # on the boundary (a stretched elbow, a wrist at q5 = 0, the point on axis 1) the word
    # tells nothing: none (code 0), whatever the rounding of this batch's products, so the
    # label shows the +/- of the steps it would name
    code = np.where(np.abs(word) > R.zero, R.first + (word < 0), _NONE)    # R.first: int8
    if R.spatial_elbow:
        # the elbow against the shoulder-to-target line in the plane of the parallel axes:
        # (l' x v') . (l' x z1') / |l'|^2 with l = W - S, v = E - S and z1 projected along
        # the elbow's axis h, that is ((l x v) . h) ((l x z1) . h) / (|l|^2 - (l . h)^2);
        # the turn sense (the word above) where the elbow is on the line, and where the
        # line is not one: the target on the elbow's axis through the shoulder (|l'| below
        # on_line), where l' is rounding and its sign that of this batch's products
        lv, lz, ll, lh = dots[w], dots[w + 1], dots[w + 2], dots[w + 3]
        across = ll - lh * lh
        up = np.where(across > R.on_line ** 2, lv * lz / np.maximum(across, 1e-300), 0.0)
        e = R.elbow_row
        code[e] = np.where(np.abs(up) < R.on_line, code[e], R.first[e] + (up < 0))
    return code


#: the code of a word that tells nothing
_NONE = np.int8(0)


class Rules(NamedTuple):
    """The vectors and products :func:`branch_geometry` evaluates for one robot and family.

    The vectors ``V`` are the frames' axes (``j``) and origins (``n + j``), then the carried
    points (``point_frames``, ``point_local``: their frames, and their coordinates there
    followed by 1, ``(4, p, 1)``). ``selection @ V`` gives, in this order, the ``crosses``
    left and right operands, then the left operands of their dot products (a cross product
    is dotted with one vector), then the ``lin`` pairs of vectors dotted together, each product
    times its ``sign``. The first products are the words' (``words``: shoulder 0, elbow 1, wrist
    2): word ``i`` is its ``first[i]`` word where the product is > ``zero[i]``, the next where it
    is < ``-zero[i]``, none between; a spatial elbow's four more products follow.
    """

    point_frames: np.ndarray
    point_local: np.ndarray
    selection: np.ndarray
    crosses: int
    lin: int
    #: (c + lin, 1): +-1, each product's sign: the words' sense in the world (a word's side
    #: seen from above, :attr:`Geometry.upward`, the front), the elbow's turn sense
    sign: np.ndarray
    #: (words, 1): a product this close to 0 is 0 (WORD_BOUNDARY of its size: m, m^2, 1)
    zero: np.ndarray
    words: np.ndarray
    first: np.ndarray                # (words, 1)
    #: (c + lin,): each product's natural size (m, m^2 or 1)
    sizes: np.ndarray = None
    spatial_elbow: bool = False
    elbow_row: int = 0
    on_line: float = 0.0


@per_robot
def rules(robot, family: str) -> Rules | None:
    """The plan of :func:`branch_geometry` from :func:`geometry` (robot-level). Cached per
    robot.

    Parameters
    ----------
    robot : Robot
    family : str

    Returns
    -------
    Rules or None
        None for a family not in :data:`WORDED`.
    """
    geo = geometry(robot, family)
    if geo is None:
        return None
    n = robot.dof
    pts = [p for p in (geo.shoulder, geo.wrist_point if geo.elbow else None) if p is not None]
    pts = list({(f, tuple(local)): (f, local) for f, local in pts}.values())
    at = {(f, tuple(local)): 2 * n + i for i, (f, local) in enumerate(pts)}
    point = lambda p: (at[p[0], tuple(p[1])],)  # noqa: E731
    z, o = (lambda j: (j,)), (lambda j: (n + j,))
    minus = lambda a, b: a + (-b[0] - 1,)        # noqa: E731  (index -1 - i: minus vector i)
    crossed, lin, words, first, sign, size = [], [], [], [], [], []
    L = robot.characteristic_length
    extra = []
    if geo.shoulder is not None:       # (P - O_1) . (z_1 x z_2)
        crossed.append((z(0), z(1), minus(point(geo.shoulder), o(0))))
        words.append(0)
        first.append(1 if geo.front == 0 else 3)
        sign.append(geo.upward * (geo.front or 1))
        size.append(L)
    if geo.elbow is not None:
        j, w = geo.elbow[0], point(geo.wrist_point)
        ws, es = minus(w, o(j)), minus(o(j + 1), o(j))
        if geo.spatial:                # the turn sense, and the products of the elbow's side
            crossed.append((es, minus(w, o(j + 1)), z(j)))
            extra = [(ws, es, z(j)), (ws, z(0), z(j))]
            lin = [(ws, ws), (ws, z(j))]
        else:                          # planar: (W - S) x (E - S) . h, seen from above
            crossed.append((ws, es, z(j)))
        words.append(1)
        first.append(1)
        sign.append(geo.elbow_upward)
        size.append(L * L)
    if geo.wrist:                      # (z_4 x z_6) . z_5
        crossed.append((z(3), z(5), z(4)))
        words.append(2)
        first.append(1)
        sign.append(1.0)
        size.append(1.0)
    crossed += extra
    rows = ([a for a, _, _ in crossed] + [b for _, b, _ in crossed] + [d for _, _, d in crossed]
            + [a for a, _ in lin] + [b for _, b in lin])
    S = np.zeros((len(rows), 2 * n + len(pts)))
    for r, terms in enumerate(rows):
        for t in terms:
            S[r, t if t >= 0 else -1 - t] += 1.0 if t >= 0 else -1.0
    S.setflags(write=False)
    return Rules(point_frames=np.array([f for f, _ in pts], np.intp),
                 point_local=np.array([[*local, 1.0] for _, local in pts]).reshape(-1, 4).T[
                     :, :, None], selection=S, crosses=len(crossed), lin=len(lin),
                 sign=np.array(sign + ([geo.upward, 1.0, 1.0, 1.0] if extra else []),
                               float)[:, None],
                 zero=WORD_BOUNDARY * np.array(size, float)[:, None],
                 words=np.array(words, np.intp),
                 first=np.array(first, np.int8)[:, None], spatial_elbow=bool(extra),
                 sizes=np.array(size + ([L * L, L, L * L, L] if extra else []), float),
                 elbow_row=words.index(1) if 1 in words else 0,
                 on_line=1e-9 * robot.characteristic_length)


@per_robot
def _fitted(robot, family: str):
    """The :func:`products` of ``robot``'s rules as polynomials of its joint values
    (:func:`kincalc.ik.joint_polynomials.fit`), or None where the fit fails. Cached per
    robot."""
    R, n = rules(robot, family), robot.dof
    return fit(lambda Q: products(R, n, entry_frames(robot.chain, Q)), robot.is_revolute,
               robot.characteristic_length, R.sizes)


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
    n, rev = robot.dof, robot.is_revolute
    F = chain_frames(robot.chain, np.zeros(n))
    z, o = F[:, :3, 2], F[:, :3, 3]
    parallel = lambda a, b: float(np.sum(np.cross(z[a], z[b]) ** 2)) < 1e-12  # noqa: E731
    tool = (n - 1, robot.chain.fixed[n][:3, 3])
    sixes = family in ("spherical-wrist",) + THREE_PARALLEL
    elbow = next(((j, j + 1) for j in (0, 1)
                  if j + 1 < n and rev[j] and rev[j + 1] and parallel(j, j + 1)), None)
    if family == "spherical-wrist":
        point = wrist = _meeting_point(robot, F, 3)
    elif family == "three-parallel":
        point, wrist = _meeting_point(robot, F, 4), (3, np.zeros(3))
    elif family == "three-parallel-offset":
        point, wrist = _foot(F, 4, 5), (3, np.zeros(3))
    else:
        third = elbow is not None and elbow[1] + 1 < n and rev[elbow[1] + 1] \
            and parallel(elbow[1], elbow[1] + 1)
        point = wrist = (elbow[1] + 1, np.zeros(3)) if third else tool
    shoulder = point if rev[0] and n >= 2 and not parallel(0, 1) and point is not None \
        and _leaves_plane(robot, point) else None
    front = 0
    if shoulder is not None:
        P = F[shoulder[0], :3, :3] @ shoulder[1] + F[shoulder[0], :3, 3]
        L = max(robot.characteristic_length, 1e-12)
        if abs((P - o[0]) @ z[1]) <= 1e-6 * L:        # no shoulder offset: front or back
            front = _front(robot, shoulder, _upward(z[0]))
    placed = shoulder or wrist or tool
    name = ("wrist centre" if family == "spherical-wrist" else
            "point where axes 5 and 6 meet" if family == "three-parallel" else
            "point of axis 5 nearest axis 6" if family == "three-parallel-offset" else
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
    L = max(robot.characteristic_length, 1e-12)
    for q in (np.asarray(robot.home, float), np.zeros(robot.dof)):
        F = chain_frames(robot.chain, q)
        P = F[point[0], :3, :3] @ point[1] + F[point[0], :3, 3]
        side = upward * (P - F[0, :3, 3]) @ np.cross(F[0, :3, 2], F[1, :3, 2])
        if abs(side) > 1e-6 * L:
            return 1 if side > 0 else -1
    return 1


def _leaves_plane(robot, point) -> bool:
    """Does the shoulder word's point leave the plane of axes 1 and 2 (through axis 1)?

    Its side of that plane is the word; an arm that keeps the point in the plane whatever
    its joints (an RPR arm whose prismatic joint and last axis move in it) has no such
    word. Judged at the home joints and two fixed generic configurations: the side's
    expression is a trigonometric polynomial of the joints, which is not zero at such
    values unless it is zero everywhere."""
    L = max(robot.characteristic_length, 1e-12)
    n = robot.dof
    unit = np.where(robot.is_revolute, 1.0, L)
    for q in (np.asarray(robot.home, float), unit * (0.31 + 0.47 * np.arange(n)),
              unit * (1.13 - 0.29 * np.arange(n))):
        F = chain_frames(robot.chain, q)
        P = F[point[0], :3, :3] @ point[1] + F[point[0], :3, 3]
        if abs((P - F[0, :3, 3]) @ np.cross(F[0, :3, 2], F[1, :3, 2])) > 1e-9 * L:
            return True
    return False


def _upward(k) -> float:
    """+1 when the axis ``k`` (world frame) points up (world z), -1 when down, +1 when it
    is horizontal (a wall-mounted or planar-in-a-vertical-plane arm: its own sense)."""
    return -1.0 if k[2] < -1e-9 else 1.0


def _foot(F, i: int, j: int):
    """The point of axis ``i`` nearest axis ``j`` (skew axes, 0-based joints) as a point fixed
    in the link that carries axis ``i``: ``(i - 1, local (3,))``. ``F``: the frames at q = 0
    (the frame of joint ``i`` has axis ``i`` as its z)."""
    p, u, r, w = F[i, :3, 3], F[i, :3, 2], F[j, :3, 3], F[j, :3, 2]
    b = float(u @ w)
    t = (float(u @ (r - p)) - b * float(w @ (r - p))) / (1.0 - b * b)
    local = F[i - 1, :3, :3].T @ (p + t * u - F[i - 1, :3, 3])
    local.setflags(write=False)
    return i - 1, local


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
