"""Per-robot data of the general-6R solver: the axes at q = 0, the model of each cyclic
shift and their ranking as pivots, the chain for Newton (cached for 64 robots)."""

from __future__ import annotations

import numpy as np

from ...chain import Chain
from ...spatial import invert_transform, wrap
from ...structure import dh_frames
from ..cache import per_robot
from .common import IMAG_TOL, PARALLEL_TOL, PERTURB
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
        self.robot = robot                # (its joint limits: the rescue prefers solutions in)
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
        (``H G H^-1 = G``). So the last DH frames of the shifted chain are the same for every
        pose: computed once (:meth:`_known_frames`) and shared by the poses' models. For
        shift 5 (pivot joint 2) frames 2 .. 6 are, hence the left side (joints 3-5: the
        robot's joints 2-4) and its deflation; its joints 1 and 2 are then given as general
        links (``links`` of :class:`Model`) from frame 0, which moves with the pose, to a
        fixed frame 1: no DH frame is built per pose.

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
        G = self.T0 @ invert_transform(T)        # the shifted chain's tool pose at q = 0
        H = invert_transform(G)
        order = (np.arange(6) + shift) % 6       # joints shift .. 5, 0 .. shift - 1
        c, F, left_of, fixed = self._known_frames(shift)
        if fixed is None:
            dirs, pts = self._shifted_lines(H, order, shift)
            return Model.from_lines(dirs, pts, G, self.L, known=(c, F)), order
        F0, F1, M2, F6inv, offset = fixed
        F0 = H @ F0                               # frame 0, on the moved axis 1
        M1 = invert_transform(F0) @ F1
        M1[:, :3, 3] /= self.L                    # lengths in units of L, as the DH model's
        return Model(F0, F6inv @ G, self.L, offset, left_of.d, left_of.a, left_of.alpha,
                     left_of=left_of, links=(M1, M2)), order

    def _shifted_lines(self, H, order, shift):
        """The axes ``dirs, pts (M, 6, 3)`` of the cyclic shift's 6R at q = 0: joints
        ``order``, those after the fold (joints shift+1 .. 6) moved by ``H (M, 4, 4)`` (see
        :meth:`shifted_model`)."""
        moved = order >= shift
        R, t = H[:, None, :3, :3], H[:, None, :3, 3]
        dirs = np.where(moved[:, None], (R @ self.dirs[order][..., None])[..., 0],
                        self.dirs[order])
        pts = np.where(moved[:, None], (R @ self.pts[order][..., None])[..., 0] + t,
                       self.pts[order])
        return dirs, pts

    def _known_frames(self, shift):
        """``(c, F, left_of, fixed)`` for the cyclic shift ``shift``, cached per shift.

        ``(c, F)`` is ``known`` of :meth:`Model.from_lines`: the DH frames c .. 6 ``F`` that
        do not move with the pose, found on two probe poses (frame i depends on axes i, i+1,
        and on frame i-1 where they are parallel: all fixed from the first frame that is the
        same for both). When frames 2 .. 6 are among them (c = 2), ``left_of`` is the model of
        the first probe pose, whose left side every pose's model shares (and whose DH
        parameters and offsets of joints 3-6), and ``fixed`` is ``(F0, F1, M2,
        F6^-1, offset)`` for :meth:`shifted_model`: frame 0 of that probe pose in the
        coordinates of the unmoved axes (it moves with the pose), its frame 1 (fixed, on axis
        2), the link from frame 1 to frame 2 (lengths over L), frame 6's inverse and the
        joint offsets (0 for joints 1 and 2); else both are None."""
        if shift not in self._known:
            order = (np.arange(6) + shift) % 6
            G = self.T0 @ invert_transform(self._probes)
            dirs, pts = self._shifted_lines(invert_transform(G), order, shift)
            F = dh_frames(dirs, pts, self.L, PARALLEL_TOL)                # (2, 7, 4, 4)
            same = [np.array_equal(F[0, i], F[1, i]) for i in range(7)]
            c = max(7 - next((i for i, x in enumerate(reversed(same)) if not x), 7), 2)
            left_of = fixed = None
            if c == 2:                 # frames 0 and 1 come from the first two axes
                left_of = Model.from_lines(dirs[0], pts[0], G[0], self.L)
                M2 = invert_transform(F[0, 1]) @ F[0, 2]
                M2[:3, 3] /= self.L
                # A_i = Rz(q_i) M_i for joints 1 and 2 (links between frames at q = 0)
                offset = np.concatenate([[0.0, 0.0], left_of.offset[2:]])
                fixed = (G[0] @ F[0, 0], F[0, 1], M2, invert_transform(F[0, 6]), offset)
            self._known[shift] = (c, F[0, c:], left_of, fixed)
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
            Poses whose candidates may miss isolated solutions: this pivot solves them and its
            eigenvalues show a continuum of solutions at one pivot angle
            (:func:`~.elimination.split_clusters`), or its model does not apply there (DH
            lengths of ``FAR`` L, :meth:`Model.from_lines`).
        """
        if shift == 0:
            model, order, target = self.model, np.arange(6), T
        else:
            model, order = self.shifted_model(T, shift)
            target = np.broadcast_to(np.eye(4), T.shape)
        pose, slot, c, bad, width, cont = eliminate(model, target)
        if np.count_nonzero(model.far):
            # a model that does not apply: nearly parallel axes at this pose, whose special
            # configuration can hide solutions from the other pivots too
            far = np.broadcast_to(model.far, bad.shape)
            keep = ~far[pose]
            pose, slot, c = pose[keep], slot[keep], c[keep]
            bad, cont = bad | far, cont | far
        out = np.empty_like(c)
        out[:, order] = c
        return pose, slot, out, bad, width, cont

    def candidates(self, T, *, last_resort: bool = False):
        """Raw candidates for the given poses, each pose with the first ranked shift that works
        (``last_resort``: the perturbed models' alone, for poses the pivots did not solve).

        A pose where every shift degenerates is solved with both perturbed models (the second
        one's slots after the first's): the last resort. A pose whose pivot shows a continuum
        of solutions at one pivot angle (``continuum`` of :meth:`raw`) gets the perturbed
        models' candidates too, in slots after the pivot's: the isolated solutions that share
        that angle are lost in the pivot's cluster, and a nearby generic robot has them as
        isolated roots. So does a pose where a pivot's model does not apply (nearly parallel
        axes at that pose, a special configuration the other pivots may not see).

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
        degenerate : ndarray (M,) of bool
            The poses where every pivot degenerates (all of them for ``last_resort``).
        """
        todo = np.arange(len(T))
        more = []                        # poses a pivot solves on a continuum
        pieces = []
        for shift in () if last_resort else self.shifts:
            pose, slot, q, bad, width, cont = self.raw(T[todo] if len(pieces) else T, shift)
            pieces.append((todo[pose] if pieces else pose, slot, q, width))
            more.append(todo[cont])
            todo = todo[bad]
            if len(todo) == 0:
                break
        degenerate = np.isin(np.arange(len(T)), todo)
        todo = np.flatnonzero(np.isin(np.arange(len(T)), np.concatenate([todo] + more)))
        lo = None
        if len(todo):
            # after every pivot slot (a pose's order of slots does not depend on the batch)
            lo = offset = max((p[3] for p in pieces), default=0)
            for model in self.perturbed:
                # (a perturbed model splits a double root into a pair ~sqrt(size) apart)
                pose, slot, q, _, width, _ = eliminate(model, T[todo], pair_imag=IMAG_TOL)
                pieces.append((todo[pose], slot + offset, q, offset + width))
                offset += width
        if len(pieces) == 1:
            return pieces[0] + (None, degenerate)
        pose = np.concatenate([p[0] for p in pieces])
        slot = np.concatenate([p[1] for p in pieces])
        order = np.lexsort((slot, pose))
        return (pose[order], slot[order], np.concatenate([p[2] for p in pieces])[order],
                max(p[3] for p in pieces), None if lo is None else slot[order] >= lo,
                degenerate)


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
