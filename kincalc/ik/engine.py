"""The one IK engine: every closed-form family, for a batch of targets at once.

:func:`solve_targets` recognises the robot's family (:func:`~kincalc.ik.families.plan`), runs its
solver (:mod:`kincalc.ik.solvers`, on the reversed chain for a ``reversed-`` family, with the
general 6R elimination for six revolute joints of no other structure) over all targets, and checks
and flags every candidate in one pass:

1. FK of every candidate (the robot as given); a candidate is a solution when it reaches the target:
   its position to ``ACCEPT_POSITION`` of the arm's size, the components the family controls to
   ``ACCEPT_ORIENTATION`` rad, other components a target gives to ``CHECK_ORIENTATION``; a
   candidate that misses by a hair, or reaches with a joint a hair beyond its limits (a double
   root next to a singularity), is polished by Newton and checked again (:mod:`~.near_miss`);
2. revolute joints moved by whole turns to the representative nearest their limits
   (:func:`~kincalc.ik.joint_limits.normalise`);
3. duplicates (every joint within ``DUPLICATE``, wrapped) dropped after their first
   (:func:`~kincalc.ik.joint_limits.duplicates`), and so are a point of another slot's continuum
   (:func:`~kincalc.ik.joint_limits.on_continua`) and a copy of another's double root
   (:func:`~kincalc.ik.near_miss.double_roots`: within ``SAME_DOUBLE_ROOT``, polished, or the
   joints halfway between the two reaching the target too, unless both reach it to rounding and
   the halfway joints miss it, two roots; the two sides of a flat double root within
   ``SPLIT_DOUBLE_ROOT``): answered once at the halfway joints, checked again, where those reach
   the target better than both;
4. limit violations, the singular test on the Jacobian, the branch labels
   (:mod:`kincalc.ik.labels`).

A single pose is a batch of one: for every closed-form family ``robot.ik`` and ``robot.ik_batch``,
the CLI's ``ik``, ``ik --batch``, ``reach``, ``check`` and the rest answer through here, so a
solution has the same label and flags wherever it is asked for (a robot with no closed form is
solved numerically, pose by pose: :mod:`kincalc.ik.numeric`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np

from ..errors import TargetMismatch, UnsupportedRobot
from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION, CHECK_ORIENTATION
from .branches import Branches
from .cache import per_robot
from ..fk import FEW, entry_frames, forward_kinematics, tool_from_cs
from .families import APPROACH_FAMILIES, TARGET_FAMILIES, Family, plan
from ..jacobian import rank_deficient
from ..memory import keep_freed_memory
from .joint_limits import (close_pairs, duplicates, normalise, on_continua, open_joints,
                           open_values, violations)
from .labels import labels
from .near_miss import at_halfway, double_roots, near_misses, polished
from .small_arms import takes_tcv
from .solvers import run_solver
from .target import Targets


@dataclass(frozen=True)
class Solved:
    """Every candidate of every target, checked (see the module docstring).

    ``q (N, K, n)`` joint values (rad / m, normalised into the limits); ``candidate (N, K)`` the
    family produced one in this slot; ``valid (N, K)`` it reaches the target (and is not a copy of
    an earlier slot); ``position_error (N, K)`` (m) and ``orientation_error (N, K)`` (rad; NaN where
    no orientation is checked); ``violation (N, K, n)`` how far each joint is beyond its limits
    (negative below the lower, positive above the upper, 0 within); ``within (N, K)``;
    ``free (N, K, n)`` joints the target leaves undetermined; ``signs``: each slot's +/- per step;
    ``continuum (N, K, 5)`` (mask, first joint, second joint, sign, total) or None; ``branches``:
    the solver's :class:`~kincalc.ik.branches.Branches` (its notes and dead ends, with
    ``explain``; None for a batch solved in chunks).

    :attr:`labels` (branch labels of the candidates) and :attr:`singular` (the singular flag of the
    valid solutions) are computed when first asked for: a batch that only needs the joint values
    does not pay for them; a single pose's come from the frames its check evaluated (``memo``).
    """

    family: str
    spec: Family
    method: str
    robot: object
    q: np.ndarray
    candidate: np.ndarray
    valid: np.ndarray
    position_error: np.ndarray
    orientation_error: np.ndarray
    violation: np.ndarray
    within: np.ndarray
    free: np.ndarray
    signs: tuple
    continuum: np.ndarray | None
    branches: Branches | None
    memo: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def counts(self) -> np.ndarray:
        """Number of solutions of each target, ``(N,)``."""
        return self.valid.sum(axis=1)

    def _frames(self, mask):
        """The slots ``mask (N, K)`` (candidates), :data:`FLAGS` at a time: ``(rows, frames,
        columns)``, their flat indices into the ``N K`` slots, frames entry by entry ``(3, 4,
        n + 1, m')`` (:func:`kincalc.fk.entry_frames`, world frame, m; or their axis and
        origin columns alone, ``(3, 2, n + 1, m')``, as the column walk keeps them for many
        slots: what :func:`kincalc.jacobian.rank_deficient` reads) and which of them are
        theirs (``(m,)``, or None: all, ``m' = m``): those the check evaluated (a view of the
        span of its columns that holds them), or where it kept none, evaluated now."""
        A, rows = self.memo.get("frames"), mask.reshape(-1).nonzero()[0]
        for start in range(0, len(rows), FLAGS):
            r = rows[start:start + FLAGS]
            if A is None:
                yield r, entry_frames(self.robot.chain, self.q.reshape(mask.size, -1)[r]), None
                continue
            at, K = self.memo.get("at"), mask.shape[1]      # A: the slots the check kept
            c = r if at is None else r // K * (A.shape[-1] // mask.shape[0]) + at[r % K]
            span = A[..., c[0]:c[-1] + 1]                   # (a view; c ascends)
            yield r, span, None if len(c) == span.shape[-1] else c - c[0]

    def slot_extra(self, name: str):
        """The solver's per-slot quantity ``name`` (``Branches.extra``: ``"parallel
        continuum"``, ...) in these slots, ``(N, K, ...)`` (0 in a slot no target kept), or
        None."""
        x = None if self.branches is None else self.branches.extra.get(name)
        at = self.memo.get("at")
        if x is None or at is None:
            return x
        out = np.zeros(x.shape[:1] + at.shape + x.shape[2:], x.dtype)
        out[:, at >= 0] = x
        return out

    @property
    def labels(self) -> np.ndarray:
        """``(N, K)`` object array: the branch label of every candidate slot.

        Two solutions of a pose that the words and the signs they leave do not tell apart
        (the words can coincide at a singular pose) show the +/- of every step."""
        if "labels" not in self.memo:
            N, K = self.candidate.shape
            lab, free = np.empty(N * K, object), self.free.reshape(N * K, -1)
            q = self.q.reshape(N * K, -1)
            ids = np.arange(-1, -1 - N * K, -1)          # distinct where no solution
            rows = self.candidate.reshape(-1).nonzero()[0]
            # a target kind's solutions (a tool configuration vector's) take the words of the
            # robot's own family, as the same solutions of a whole pose do
            own = plan(self.robot)[1] if self.spec.name in TARGET_FAMILIES else None
            words = self.spec.name if own is None else own.name
            lab[rows], i = labels(self.robot, words, q[rows], self.signs, rows % K,
                                  free[rows])
            ids[rows] = np.where(self.valid.reshape(-1)[rows], i, ids[rows])
            ids = ids.reshape(N, K)
            order = np.sort(ids, axis=1)
            if np.count_nonzero(order[:, 1:] == order[:, :-1]):          # rare
                same = (ids[:, :, None] == ids[:, None, :]).sum(-1) > 1    # (N, K)
                rows = same.reshape(-1).nonzero()[0]
                lab[rows] = labels(self.robot, words, q[rows], self.signs, rows % K,
                                   free[rows], every_sign=True)[0]
            self.memo["labels"] = lab.reshape(N, K)
        return self.memo["labels"]

    @property
    def singular(self) -> np.ndarray:
        """``(N, K)`` bool: valid solutions at a singular configuration (the rank test of
        :func:`singular`, or a joint the target leaves free, other than one it leaves open:
        labelled ``any``, a value it does not ask for)."""
        if "singular" not in self.memo:
            r, n = self.robot, self.free.shape[-1]
            sing = np.zeros(self.valid.shape, bool)
            if np.count_nonzero(self.free):                  # a target leaves joints free
                sing = self.valid & np.logical_or.reduce(
                    self.free & ~open_joints(self.signs, n), axis=-1)
            flat = sing.reshape(-1)
            for rows, A, columns in self._frames(self.valid):
                flat[rows] |= rank_deficient(A, r.is_revolute, r.characteristic_length,
                                             r.generic_ranks, columns)
            self.memo["singular"] = sing
        return self.memo["singular"]


#: slots whose labels and singular flags are evaluated together (their frames stay in cache)
FLAGS = 2048

#: targets solved together (memory: a few kB per target and slot)
CHUNK = 2048


def solve_batch(robot, T, *, chunk: int = CHUNK) -> Solved:
    """Every IK solution of ``robot`` for each pose of ``T``, solved ``chunk`` poses at a time.

    Parameters
    ----------
    robot : Robot
    T : array_like (N, 4, 4) or (4, 4), the target poses ``T_world_tool`` (world frame, SI)
    chunk : int, poses solved together (memory: a few kB per target and slot)

    Returns
    -------
    Solved, all N targets (``branches`` None when there was more than one chunk); glibc's malloc
    keeps freed memory from then on (:mod:`kincalc.memory`)

    Raises
    ------
    ValueError, UnsupportedRobot
        ``T`` is not of shape (N, 4, 4) or (4, 4); no closed form covers the robot.
    """
    T = np.asarray(T, float)
    if T.ndim == 2:
        T = T[None]
    if T.shape[1:] != (4, 4):
        raise ValueError(f"expected poses of shape (N, 4, 4), got {T.shape}")
    keep_freed_memory()                 # each chunk's temporaries: the last one's pages
    if len(T) <= chunk:
        return solve_targets(robot, Targets(T))
    first = solve_targets(robot, Targets(T[:chunk]))
    names = [f.name for f in fields(Solved) if f.name != "continuum"
             and isinstance(getattr(first, f.name), np.ndarray)]
    out = {name: np.empty((len(T),) + getattr(first, name).shape[1:],
                          getattr(first, name).dtype) for name in names}
    continuum = None           # (N, K, 5), made when a chunk has a singular continuum
    for start in range(0, len(T), chunk):
        part = first if start == 0 else solve_targets(robot, Targets(T[start:start + chunk]))
        for name, a in out.items():
            a[start:start + chunk] = getattr(part, name)
        if part.continuum is not None:
            if continuum is None:
                continuum = np.zeros((len(T),) + part.continuum.shape[1:])
            continuum[start:start + chunk] = part.continuum
    return replace(first, **out, continuum=continuum, branches=None, memo={})


def solve_targets(robot, targets: Targets, *, explain: bool = False) -> Solved:
    """Every closed-form solution of ``robot`` for each target of ``targets``.

    Parameters
    ----------
    robot : Robot
    targets : Targets, ``N`` targets of one kind (world frame, SI)
    explain : bool, record notes and dead ends in ``branches`` (every slot is then kept)

    Returns
    -------
    Solved, the candidates ``q (N, K, n)`` and their checks (see the module docstring)

    Raises
    ------
    UnsupportedRobot
        No family covers the robot (the numerical solver's business).
    TargetMismatch
        The kind does not fit the family (:func:`check_kind`) or the robot cannot take a TCV.
    ValueError
        A ``"tcv"`` batch of more than one target.
    """
    S, family, why = plan(robot)
    if targets.kind in TARGET_FAMILIES:
        family = TARGET_FAMILIES[targets.kind]
    elif family is None:
        raise UnsupportedRobot(f"{robot.name}: no closed form ({why})")
    check_kind(robot, family, targets)
    N, n = len(targets), robot.dof
    br = run_solver(robot, S, family, targets, Branches.start(N, n, explain=explain))
    if not family.needs_orientation and family.exact:
        from .free_joints import orient_free
        br = orient_free(robot, targets, br)
    br = open_values(robot, br)
    # an exact family's candidates are checked in the slots some target keeps (the others,
    # half of a three-parallel arm's, are put back empty at the end)
    br = br.flushed() if family.exact else br.expanded()
    candidate = br.ok.copy()
    method = family.description
    if family.exact:
        c, s, x = br.joint_major()
    else:
        from .nearly import on_true_robot
        q, candidate, br, method = on_true_robot(robot, family, targets, br.q(), candidate,
                                                 br)
        x = np.ascontiguousarray(q.reshape(-1, n).T)
        c, s = np.cos(x), np.sin(x)
    return _check(robot, family, method, targets, (c, s, x), candidate, br)


def check_kind(robot, family: Family, targets: Targets) -> None:
    """Refuse a target kind the family does not take (words for the edge to render).

    Parameters
    ----------
    robot : Robot
    family : Family, the robot's (:data:`TCV` takes every kind)
    targets : Targets, of which only the ``kind`` is read

    Raises
    ------
    TargetMismatch
        An approach target for a family not in ``APPROACH_FAMILIES``, or a position target
        for one that needs the orientation.
    """
    five = family.name in APPROACH_FAMILIES
    if targets.kind in TARGET_FAMILIES:
        return
    if targets.kind == "approach" and not five:
        raise TargetMismatch(robot.name, "full orientation", family.controls)
    if family.needs_orientation and targets.kind == "position":
        raise TargetMismatch(robot.name, "orientation", family.controls, approach_ok=five,
                             tcv_ok=takes_tcv(robot.is_revolute))


def _check(robot, family, method, targets, joints, candidate, br, polish=True,
           polished_slots=None, middle=True) -> Solved:
    """Steps 1-3 of the module docstring for the candidates ``joints``: ``(c, s, x)``,
    each ``(n, N K)`` joint-major (:meth:`Branches.joint_major`), in the slots of ``br``; the
    answer laid out in the family's slots (:func:`_in_layout`) where the solver kept fewer.
    Candidates that miss by a hair (``polish``: :mod:`kincalc.ik.near_miss`) are polished and
    all checked again (``polished_slots``: those, of which one that reached another's double
    root goes). A double root is answered at its middle (``middle``: bool, or ``(N,)`` per
    pose) once: in the first
    check, or in the second where two polished copies of it are met only there (Newton's
    method approaches a double root linearly, and leaves its copies either side of it).

    A few candidates (a single pose: ``N K <= FEW``) are evaluated as stacked frames from their
    normalised joint values, many by the column walk from the solver's cosines and sines; the
    frames are kept for the singular test."""
    c, s, x = joints
    N, K = candidate.shape
    n = robot.dof
    raw = np.where(candidate[..., None], x.T.reshape(N, K, n), 0.0)
    q = normalise(robot, raw)
    if targets.kind == "tcv":       # the vector holds e^(q_n / pi): q_n itself, no turn from it
        q[..., -1] = raw[..., -1]
    memo = {}
    if N * K <= FEW:
        A, f = entry_frames(robot.chain, q.reshape(-1, n), coefficients=True)
        tool, f, memo["frames"] = A[:, :, n], f.transpose(0, 2, 1), A
    else:
        memo["frames"] = np.empty((3, 2, n + 1, N * K))   # axes, origins: for the flags
        cols, p = tool_from_cs(robot.chain, c, s, x, memo["frames"])
        tool, f = np.stack(cols + [p], 1), (c, s, x)
    pe, oe, reach = _reach(robot, family, targets, tool.reshape(3, 4, N, K))
    valid = candidate & reach
    pairs = close_pairs(robot, q, valid, f)
    halfway = None
    if len(pairs[0]):                                                      # (rare)
        valid &= ~duplicates(robot, q, valid, pairs)
        drop, halfway = double_roots(robot, q, valid, pairs, polished_slots,
                                     _judge(robot, family, targets), again=middle)
        valid &= ~drop
    free = br.free_mask()
    if np.count_nonzero(free):
        held = _moves_freely(robot, family, targets, q, valid & free.any(-1), free, br)
        valid &= ~on_continua(robot, q, valid, free & held[..., None],
                              br.extra.get("continuum"))
    viol = violations(robot, q)
    near = near_misses(robot, candidate, reach, pe, oe, valid, viol,
                       family.needs_orientation, free) if polish else None
    moved = near                        # slots whose joints change for a second check
    if near is not None:
        q = polished(robot, targets, q, near, valid, _judge(robot, family, targets), free)
    if halfway is not None:
        q, moved = at_halfway(q, moved, *halfway)
    if moved is not None:
        at = moved.reshape(-1).nonzero()[0]
        x = x.copy()
        x[:, at] = q.reshape(-1, n)[at].T
        c, s = c.copy(), s.copy()
        c[:, at], s[:, at] = np.cos(x[:, at]), np.sin(x[:, at])
        if halfway is not None:             # (per pose: each pose's bits whatever its batch)
            middle = np.broadcast_to(middle, (N,)).copy()
            middle[halfway[0]] = False
        return _check(robot, family, method, targets, (c, s, x), candidate, br, polish=False,
                      polished_slots=polished_slots if near is None else near, middle=middle)
    checked = dict(q=q, candidate=candidate, valid=valid,
                   position_error=np.where(candidate, pe, 0.0),
                   orientation_error=np.full((N, K), np.nan) if oe is None else
                   np.where(candidate, oe, np.nan),
                   violation=viol, within=np.logical_and.reduce(viol == 0.0, axis=-1),
                   free=free, continuum=br.extra.get("continuum"))
    signs = br.signs
    if br.full is not None:
        checked, memo["at"] = _in_layout(robot, checked, br.full, len(br.full_signs))
        signs = br.full_signs
    return Solved(family=family.name, spec=family, method=method, robot=robot, signs=signs,
                  branches=br, memo=memo, **checked)


def _judge(robot, family, targets):
    """``judge(rows, T) -> (error (M,), reach (M,))`` of :func:`~kincalc.ik.near_miss.double_roots`:
    how far the tool poses ``T (M, 4, 4)`` miss the targets ``rows (M,)`` (position over the
    arm's size plus the orientation's angle) and whether they reach them (:func:`_reach`)."""
    def judge(rows, T):
        pe, oe, reach = _reach(robot, family, targets.take(rows),
                               T[:, :3].transpose(1, 2, 0)[..., None])
        error = pe[:, 0] / max(robot.characteristic_length, 1e-12)
        return (error if oe is None else error + np.nan_to_num(oe[:, 0])), reach[:, 0]
    return judge


def _in_layout(robot, checked: dict, cols, K: int) -> tuple:
    """The arrays ``checked`` of :class:`Solved`'s fields (``(N, K', ...)``, None for none)
    of the slots ``cols (K',)`` some target keeps, in the family's layout of ``K`` slots, so
    that every batch lays its slots out alike: the other slots hold no candidate and the
    joints of an unset slot (all 0, normalised). Returns ``(arrays, at)``, ``at (K,)`` each
    slot's index among ``cols`` (-1 for none)."""
    q0, v0, within0 = _unset_slot(robot)
    fill = dict(q=q0, candidate=False, valid=False, position_error=0.0,
                orientation_error=np.nan, violation=v0, within=within0, free=False,
                continuum=0.0)
    out = {}
    for name, a in checked.items():
        if a is not None:
            out[name] = np.empty((len(a), K) + a.shape[2:], a.dtype)
            out[name][...] = fill[name]
            out[name][:, cols] = a
        else:
            out[name] = None
    at = np.full(K, -1)
    at[cols] = np.arange(len(cols))
    return out, at


@per_robot
def _unset_slot(robot) -> tuple:
    """The joints of a slot no target kept, all 0 normalised ``(n,)`` (rad / m), their limit
    violations ``(n,)`` and whether they are within the limits (:func:`_in_layout`). Cached
    per robot (read-only)."""
    q0 = normalise(robot, np.zeros(robot.dof))
    v0 = violations(robot, q0)
    q0.flags.writeable = v0.flags.writeable = False
    return q0, v0, not v0.any()


def _moves_freely(robot, family, targets, q, slots, free, br) -> np.ndarray:
    """``(N, K)`` bool: of the ``slots (N, K)``, those whose ``free (N, K, n)`` joints are
    free indeed: a slot with a continuum relation (its free joints move with others), or one
    that still reaches its target with every free joint moved (by 1 rad, or a tenth of the
    arm's size). A band of a double root can call a joint free that moves the point by a
    hair more than the check allows; such a slot stands for itself alone, and no other
    solution is taken for a point of it (:func:`~kincalc.ik.joint_limits.on_continua`)."""
    out = np.zeros(slots.shape, bool)
    for name in ("continuum", "parallel continuum"):
        if name in br.extra:
            out |= slots & (br.extra[name][..., 0] != 0)
    pose, slot = np.nonzero(slots & ~out)
    if len(pose):                       # (the slots to test only: FK of each moved once)
        step = np.where(robot.is_revolute, 1.0, 0.1 * robot.characteristic_length)
        f = free[pose, slot]
        moved = forward_kinematics(robot.chain, np.where(f, q[pose, slot] + step,
                                                         q[pose, slot]))         # (m, 4, 4)
        out[pose, slot] = _reach(robot, family, targets.take(pose),
                                 moved[:, :3].transpose(1, 2, 0)[..., None])[2][:, 0]
    return out


def _reach(robot, family: Family, targets: Targets, tool) -> tuple:
    """``(position error, orientation error, reach)`` of each slot's tool pose ``tool (3, 4, N,
    K)`` (:func:`_errors`), and whether it reaches its target: the position to
    ``ACCEPT_POSITION`` of the arm's size, the orientation to ``ACCEPT_ORIENTATION`` where the
    family controls it and to ``CHECK_ORIENTATION`` where it does not; each ``(N, K)``."""
    pe, oe = _errors(targets, tool)
    reach = pe <= ACCEPT_POSITION * max(robot.characteristic_length, 1e-12)
    if oe is not None:
        reach &= oe <= (ACCEPT_ORIENTATION if family.needs_orientation else CHECK_ORIENTATION)
    return pe, oe, reach


def _errors(targets: Targets, tool) -> tuple:
    """Position error (m) and orientation error (rad) of each slot's tool pose ``tool (3, 4, N,
    K)`` (its top rows entry by entry, world frame) against its target, each ``(N, K)``; the
    orientation error None for a position target. The angle is that between the orientations
    for the components the target gives: the whole rotation (from ``|R_a - R_b|_F = 2 sqrt(2)
    sin(angle / 2)``, accurate for small angles), or the approach (tool z)."""
    T = targets.T[:, :3].transpose(1, 2, 0)[..., None]      # (3, 4, N, 1)
    if targets.kind in ("approach", "tcv", "position"):
        d = tool[:, 3] - T[:, 3]
        pe = np.sqrt(np.add.reduce(d * d, 0))
        if targets.kind == "position":
            return pe, None
        z, a = tool[:, 2], targets.approach.T[..., None]
        w = np.array([z[1] * a[2] - z[2] * a[1], z[2] * a[0] - z[0] * a[2],
                      z[0] * a[1] - z[1] * a[0]])
        return pe, np.arctan2(np.sqrt(np.add.reduce(w * w, 0)), np.add.reduce(z * a, 0))
    d = tool - T
    d = d * d
    chord = np.sqrt(np.add.reduce(d[:, :3], axis=(0, 1))) / (2.0 * 2.0 ** 0.5)
    return np.sqrt(np.add.reduce(d[:, 3], 0)), 2.0 * np.arcsin(np.minimum(chord, 1.0))


def singular(robot, Q, F, tool) -> np.ndarray:
    """Is each configuration singular (its Jacobian's rank below the robot's generic rank)?

    Parameters
    ----------
    robot : Robot
    Q : ndarray (m, n), joint values (rad / m)
    F : ndarray (m, n, 4, 4), the joint frames (world frame, m)
    tool : ndarray (m, 4, 4), the tool poses ``T_world_tool`` (m)

    Returns
    -------
    ndarray (m,) of bool
        :func:`rank_deficient` of these frames.
    """
    m, n = np.shape(Q)
    A = np.empty((3, 4, n + 1, m))
    A[:, :, :n] = np.asarray(F)[..., :3, :].transpose(2, 3, 1, 0)
    A[:, :, n] = np.asarray(tool)[:, :3].transpose(1, 2, 0)
    return rank_deficient(A, robot.is_revolute, robot.characteristic_length,
                          robot.generic_ranks)
