"""Per-robot data of the general-6R solver: the axes at q = 0, the model of each cyclic
shift and their ranking as pivots, the chain for Newton (cached for 64 robots)."""

from __future__ import annotations

import numpy as np

from ...chain import Chain
from ...spatial import invert_transform, wrap
from ...structure import dh_frames
from ..cache import per_robot
from .common import PARALLEL_TOL, PERTURB
from .elimination import eliminate
from .model import Model
from .polish import newton_curvature


# --- per robot ------------------------------------------------------------------

class _Robot6R:
    """Per-robot data: axes at q = 0, the shift-0 model, the chain for Newton, the
    ranked pivot shifts, and (built on first use) the DH frames and left sides that the
    other shifts' per-pose models share.

    Raises ValueError if the robot does not have exactly 6 revolute joints.
    """

    def __init__(self, robot):
        from ...structure import joint_axes
        if robot.dof != 6 or not all([j.revolute for j in robot.joints]):
            raise ValueError("the general 6R solver needs a robot with exactly 6 revolute "
                             "joints, got " + "".join("R" if j.revolute else "P"
                                                      for j in robot.joints))
        self.dirs, self.pts = joint_axes(robot)
        self.T0 = robot.fk(np.zeros(6))
        self.L = float(robot.characteristic_length)
        fixed = np.array(robot.chain.fixed)
        fixed[:, :3, 3] /= self.L
        #: the chain with lengths divided by L: Newton's position errors and the
        #: Jacobian's linear rows come out scaled
        self.chain = Chain(fixed, robot.chain.revolute, robot.chain.offset)
        self.curvature = newton_curvature(self.chain)
        self.scale = np.array([[1.0, 1.0, 1.0, self.L]])      # divides a pose's rows 0-2
        self.model = Model.from_lines(self.dirs, self.pts, self.T0, self.L)
        self._perturbed = None
        #: two poses that find the DH frames of the shifted chains not moving with the pose
        self._probes = robot.fk(np.random.default_rng(7).uniform(-np.pi, np.pi, (2, 6)))
        self._known = {}                  # shift -> those frames (and a shared left side)
        self.shifts = self._rank_shifts(robot)

    def _rank_shifts(self, robot):
        """Pivot choices (cyclic shifts) ordered by the raw accuracy they reach on probe poses.

        The probe poses are FK of seeded random configurations; a shift's score is
        its worst distance from the generating configuration to the nearest raw
        (unpolished) candidate. Shift 0 (pivot joint 3, the per-robot precomputed
        form) is kept first when it recovers every probe to 1e-8 rad. Otherwise
        shifts accurate to 1e-8 come first, fewest candidates first, then the
        rest by accuracy.
        """
        qs = np.random.default_rng(6).uniform(-np.pi, np.pi, (3, 6))
        Ts = robot.fk(qs)
        keys = []
        for k in range(6):
            pose, _, cand, bad, _, _ = self.raw(Ts, k)
            worst = np.inf
            if not bad.any() and np.all(np.bincount(pose, minlength=3) > 0):
                dist = np.max(np.abs(wrap(cand - qs[pose])), axis=1)
                near = np.full(3, np.inf)
                np.minimum.at(near, pose, dist)
                worst = float(near.max())
            if k == 0 and worst < 1e-8:
                return list(range(6))
            # accurate shifts first, among them the one with fewer candidates (less Newton work)
            keys.append((worst >= 1e-8, worst if worst >= 1e-8 else len(pose), k))
        return [k for *_, k in sorted(keys)]

    @property
    def perturbed(self):
        """Nearby generic models (one per PERTURB size), built on first use.

        Returns
        -------
        list of Model
        """
        if self._perturbed is None:
            self._perturbed = [self.model.perturbed(size) for size in PERTURB]
        return self._perturbed

    def shifted_model(self, T, shift):
        """The 6Rs of the cyclic shift ``shift`` for the given poses, one model per pose.

        ``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I`` is written in the frame of joints 1 .. k
        (k = ``shift``): their axes stay where they are at q = 0 and the axes of joints
        k+1 .. 6 are moved by ``H = G^-1``, ``G = T0 T^-1``, the chain's tool pose at q = 0
        (``H G H^-1 = G``). So the last DH frames of the shifted chain, and for shift 5 its
        left side (joints 3-5: the robot's joints 2-4), are the same for every pose: computed
        once (:meth:`_known_frames`) and shared by the poses' models.

        Parameters
        ----------
        T : ndarray (M, 4, 4)
            Poses ``T_world_tool`` (SI).
        shift : int
            1 .. 5.

        Returns
        -------
        model : Model
            Leading dimension M; their target is the identity.
        order : ndarray (6,) of int
            Their joints' indices in the original order.
        """
        dirs, pts, G, order = self._shifted_lines(T, shift)
        return Model.from_lines(dirs, pts, G, self.L, known=self._known_frames(shift)), order

    def _shifted_lines(self, T, shift):
        """The axes ``dirs, pts (M, 6, 3)`` of the cyclic shift's 6R at q = 0 (joints
        ``order``, joints k+1 .. 6 moved by ``G^-1``), its tool pose at q = 0 ``G (M, 4, 4)``
        and ``order (6,)`` (see :meth:`shifted_model`)."""
        G = self.T0 @ invert_transform(T)                 # (M, 4, 4)
        H = invert_transform(G)
        order = (np.arange(6) + shift) % 6                # joints shift .. 5, 0 .. shift - 1
        moved = order >= shift
        R, t = H[:, None, :3, :3], H[:, None, :3, 3]
        dirs = np.where(moved[:, None], (R @ self.dirs[order][..., None])[..., 0],
                        self.dirs[order])
        pts = np.where(moved[:, None], (R @ self.pts[order][..., None])[..., 0] + t,
                       self.pts[order])
        return dirs, pts, G, order

    def _known_frames(self, shift):
        """``(c, F, left_of)`` of :meth:`Model.from_lines` for the cyclic shift ``shift``:
        the DH frames that do not move with the pose, found on two probe poses (frame i
        depends on axes i, i+1, and on frame i-1 where they are parallel: all fixed from
        the first frame that is the same for both), and, when frames 2 .. 6 are among them,
        a model whose left side every pose's model shares. Cached per shift."""
        if shift not in self._known:
            dirs, pts, G, _ = self._shifted_lines(self._probes, shift)
            F = dh_frames(dirs, pts, self.L, PARALLEL_TOL)                # (2, 7, 4, 4)
            same = [np.array_equal(F[0, i], F[1, i]) for i in range(7)]
            c = 7 - next((i for i, x in enumerate(reversed(same)) if not x), 7)
            c = max(c, 2)              # frames 0 and 1 come from the first two axes
            left_of = Model.from_lines(dirs[0], pts[0], G[0], self.L) if c <= 2 else None
            self._known[shift] = (c, F[0, c:], left_of)
        return self._known[shift]

    def raw(self, T, shift):
        """Raw candidates with the pivot of cyclic shift ``shift``.

        The pivot is joint ``(shift + 2) % 6 + 1`` (1-based): 3 for shift 0, 2 for shift 5.
        ``A_1 ... A_6 = T'`` is rotated into ``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I``:
        a 6R chain whose joints are k+1..6, 1..k, with the pose folded into the
        link between joints 6 and 1, and the target the identity.

        Parameters
        ----------
        T : ndarray (M, 4, 4)
            Poses ``T_world_tool`` (SI).
        shift : int
            0 .. 5.

        Returns
        -------
        pose, slot : ndarray (C,) of int
            Each candidate's pose and eigenvalue slot (see :func:`eliminate`).
        q : ndarray (C, 6)
            Rad, in the robot's joint order, not wrapped.
        degenerate : ndarray (M,) of bool
            Poses where this pivot's elimination does not apply.
        width : int
            Slots per pose (16, or 32 / 48 with a cluster).
        continuum : ndarray (M,) of bool
            Poses this pivot solves whose eigenvalues show a continuum of solutions at one
            pivot angle (:func:`~.elimination.split_clusters`).
        """
        if shift == 0:
            return eliminate(self.model, T)
        model, order = self.shifted_model(T, shift)
        pose, slot, c, bad, width, cont = eliminate(model, np.broadcast_to(np.eye(4), T.shape))
        out = np.empty_like(c)
        out[:, order] = c
        return pose, slot, out, bad, width, cont

    def candidates(self, T):
        """Raw candidates for the given poses, each pose with the first ranked shift that works.

        A pose where every shift degenerates is solved with both perturbed models (the second
        one's slots after the first's): the last resort. A pose whose pivot shows a continuum
        of solutions at one pivot angle (``continuum`` of :meth:`raw`) gets the perturbed
        models' candidates too, in slots after the pivot's: the isolated solutions that share
        that angle are lost in the pivot's cluster, and a nearby generic robot has them as
        isolated roots.

        Parameters
        ----------
        T : ndarray (M, 4, 4)
            Poses ``T_world_tool`` (SI).

        Returns
        -------
        pose, slot : ndarray (C,) of int
            Sorted by pose (then slot), ``slot < width``; the perturbed models' slots come
            after every slot of a pivot.
        q : ndarray (C, 6)
            Rad, in the robot's joint order, not wrapped.
        width : int
        resort : ndarray (C,) of bool, or None
            The perturbed models' candidates, which Newton takes from both sides
            (:func:`~.polish.polish_from_both_sides`); None when there are none.
        """
        todo = np.arange(len(T))
        more = []                        # poses a pivot solves on a continuum
        pieces = []
        for shift in self.shifts:
            pose, slot, q, bad, width, cont = self.raw(T[todo] if len(pieces) else T, shift)
            pieces.append((todo[pose] if pieces else pose, slot, q, width))
            more.append(todo[cont])
            todo = todo[bad]
            if len(todo) == 0:
                break
        todo = np.concatenate([todo] + more)
        lo = None
        if len(todo):
            # after every pivot slot (a pose's order of slots does not depend on the batch)
            lo = offset = max((p[3] for p in pieces), default=0)
            for model in self.perturbed:
                pose, slot, q, _, width, _ = eliminate(model, T[todo])
                pieces.append((todo[pose], slot + offset, q, offset + width))
                offset += width
        if len(pieces) == 1:
            return pieces[0] + (None,)
        pose = np.concatenate([p[0] for p in pieces])
        slot = np.concatenate([p[1] for p in pieces])
        order = np.lexsort((slot, pose))
        return (pose[order], slot[order], np.concatenate([p[2] for p in pieces])[order],
                max(p[3] for p in pieces), None if lo is None else slot[order] >= lo)


@per_robot
def robot_data(robot):
    """The per-robot data of the general-6R solver (cached for 64 robots).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    _Robot6R

    Raises
    ------
    ValueError
        The robot does not have exactly 6 revolute joints.
    """
    return _Robot6R(robot)
