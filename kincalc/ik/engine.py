"""The one IK engine: every closed-form family, for a batch of targets at once.

:func:`solve_targets` recognises the robot's family (:func:`~kincalc.ik.families.plan`), runs its
solver (:mod:`kincalc.ik.solvers`, on the reversed chain for a ``reversed-`` family, with the
general 6R elimination for six revolute joints of no other structure) over all targets, and checks
and flags every candidate in one pass:

1. FK of every candidate (the robot as given); a candidate is a solution when it reaches the target:
   its position to ``ACCEPT_POSITION`` of the arm's size, the components the family controls to
   ``ACCEPT_ORIENTATION`` rad, other components a target gives to ``CHECK_ORIENTATION``;
2. revolute joints moved by whole turns to the representative nearest their limits
   (:func:`normalise`);
3. duplicates (every joint within ``DUPLICATE``, wrapped) dropped after their first;
4. limit violations, the singular test on the Jacobian, the branch labels
   (:mod:`kincalc.ik.labels`).

A single pose is a batch of one: ``robot.ik`` and ``robot.ik_batch``, the CLI's ``ik``,
``ik --batch``, ``reach``, ``check`` and the rest answer through here, so a solution has the
same label and flags wherever it is asked for.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np

from ..errors import TargetMismatch, UnsupportedRobot
from ..tolerances import (ACCEPT_ORIENTATION, ACCEPT_POSITION, CHECK_ORIENTATION, DUPLICATE,
                          LIMIT_TOL, SINGULAR_TOL)
from .branches import Branches
from .cache import per_robot
from .families import TARGET_FAMILIES, TCV, Family, plan  # noqa: F401 (TCV: the API)
from .labels import labels
from ..spatial import wrap
from .solvers import SOLVERS
from ..subproblems.solutions import cross
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
    does not pay for them.
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
        """Joint frames and tool poses of the slots ``mask (N, K)`` (within the candidates).

        A few candidates (a single pose) are evaluated once, all together, for both the labels and
        the singular flags; a large batch evaluates what each asks for."""
        from ..fk import FEW, frames_and_tool
        count = int(np.count_nonzero(self.candidate))
        if 0 < count <= FEW:
            if "frames" not in self.memo:
                self.memo["frames"] = frames_and_tool(self.robot.chain, self.q[self.candidate])
            F, tool = self.memo["frames"]
            pick = mask[self.candidate]
            return F[pick], tool[pick]
        Q = self.q[mask]
        if not len(Q):
            n = self.q.shape[-1]
            return np.zeros((0, n, 4, 4)), np.zeros((0, 4, 4))
        return frames_and_tool(self.robot.chain, Q)

    @property
    def labels(self) -> np.ndarray:
        """``(N, K)`` object array: the branch label of every candidate slot."""
        if "labels" not in self.memo:
            lab = np.empty(self.candidate.shape, object)
            idx = np.nonzero(self.candidate)
            if len(idx[0]):
                from ..fk import FEW, columns_of, frame_columns
                cols = (columns_of(self._frames(self.candidate)[0]) if len(idx[0]) <= FEW
                        else frame_columns(self.robot.chain, self.q[self.candidate]))
                lab[idx] = labels(self.robot, self.spec.name, cols, self.signs, idx[1],
                                  self.free[idx])
            self.memo["labels"] = lab
        return self.memo["labels"]

    @property
    def singular(self) -> np.ndarray:
        """``(N, K)`` bool: valid solutions at a singular configuration (the rank test of
        :func:`singular`, or a joint the target leaves free)."""
        if "singular" not in self.memo:
            sing = np.zeros(self.valid.shape, bool)
            if self.valid.any():
                F, tool = self._frames(self.valid)
                sing[self.valid] = singular(self.robot, self.q[self.valid], F, tool)
            self.memo["singular"] = sing | (self.valid & self.free.any(-1))
        return self.memo["singular"]


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
    Solved, all N targets (``branches`` None when there was more than one chunk)

    Raises
    ------
    ValueError
        ``T`` is not of shape (N, 4, 4) or (4, 4).
    UnsupportedRobot
        No closed form covers the robot.
    """
    T = np.asarray(T, float)
    if T.ndim == 2:
        T = T[None]
    if T.shape[1:] != (4, 4):
        raise ValueError(f"expected poses of shape (N, 4, 4), got {T.shape}")
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
    br = Branches.start(N, n, explain=explain)
    if targets.kind in TARGET_FAMILIES:
        from .solvers import TARGET_SOLVERS
        br = TARGET_SOLVERS[targets.kind](robot, S, targets, br)
    elif family.name == "general-6r":
        from .general6r import general_6r
        br = general_6r(robot, targets, br)
    elif family.reverse:
        br = SOLVERS[family.solver](S.constant("reversed", S.reversed), targets.inverted(), br)
        br = br.expanded().reversed_chain()
    else:
        br = SOLVERS[family.solver](S, targets, br)
    br = br.expanded()
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
    from .families import APPROACH_FAMILIES
    five = family.name in APPROACH_FAMILIES
    if targets.kind in TARGET_FAMILIES:
        return
    if targets.kind == "approach" and not five:
        raise TargetMismatch(robot.name, "full orientation", family.controls)
    if family.needs_orientation and targets.kind == "position":
        raise TargetMismatch(robot.name, "orientation", family.controls, approach_ok=five)


def _check(robot, family, method, targets, joints, candidate, br) -> Solved:
    """Steps 1-3 of the module docstring for the candidates ``joints``: ``(c, s, x)``,
    each ``(n, N K)`` joint-major (:meth:`Branches.joint_major`)."""
    from ..fk import tool_from_cs
    c, s, x = joints
    N, K = candidate.shape
    n = robot.dof
    L = max(robot.characteristic_length, 1e-12)
    cols, p = tool_from_cs(robot.chain, c, s, x)
    T = targets.T
    pe = _distance(p, np.repeat(T[:, :3, 3], K, axis=0).T)
    oe = _orientation_error(targets, cols, K)
    o_tol = ACCEPT_ORIENTATION if family.needs_orientation else CHECK_ORIENTATION
    reach = pe <= ACCEPT_POSITION * L
    if oe is not None:
        reach &= oe <= o_tol
    with np.errstate(invalid="ignore"):            # dead slots may hold anything
        valid = candidate & reach.reshape(N, K)
    q = normalise(robot, np.where(candidate[..., None], x.T.reshape(N, K, n), 0.0))
    valid &= ~duplicates(robot, q, valid, (c, s))
    viol = violations(robot, q)
    return Solved(family=family.name, spec=family, method=method, robot=robot, q=q,
                  candidate=candidate, valid=valid,
                  position_error=np.where(candidate, pe.reshape(N, K), 0.0),
                  orientation_error=np.full((N, K), np.nan) if oe is None else
                  np.where(candidate, oe.reshape(N, K), np.nan),
                  violation=viol, within=~(viol != 0).any(-1), free=br.free_mask(),
                  signs=br.signs, continuum=br.extra.get("continuum"), branches=br)


def _distance(a, b):
    """``|a - b|`` of structure-of-arrays points ``(3, M)``."""
    d0, d1, d2 = a[0] - b[0], a[1] - b[1], a[2] - b[2]
    return np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


def _orientation_error(targets: Targets, cols, K):
    """Angle (rad) between each slot's orientation (rotation columns ``cols``, three ``(3, M)``)
    and its target's, for the components the target gives: the whole rotation (from
    ``|R_a - R_b|_F = 2 sqrt(2) sin(angle / 2)``, accurate for small angles), or the approach
    (tool z)."""
    if targets.kind == "position":
        return None
    if targets.kind in ("approach", "tcv"):
        a = np.repeat(targets.approach, K, axis=0).T
        z = cols[2]
        c = z[0] * a[0] + z[1] * a[1] + z[2] * a[2]
        x = z[1] * a[2] - z[2] * a[1]
        y = z[2] * a[0] - z[0] * a[2]
        w = z[0] * a[1] - z[1] * a[0]
        return np.arctan2(np.sqrt(x * x + y * y + w * w), c)
    R = targets.T[:, :3, :3]
    f2 = 0.0
    for j in range(3):
        d = cols[j] - np.repeat(R[:, :, j], K, axis=0).T
        f2 = f2 + d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    return 2.0 * np.arcsin(np.minimum(np.sqrt(f2) / (2.0 * np.sqrt(2.0)), 1.0))


def normalise(robot, Q) -> np.ndarray:
    """``Q`` with each revolute joint moved by whole turns to the value nearest its limits.

    In (-pi, pi] when that is within them (to ``LIMIT_TOL``), else the turn within them (the
    lowest, for limits wider than a turn), else the one that misses them least; prismatic kept.

    Parameters
    ----------
    robot : Robot
    Q : array_like (..., n), joint values (rad / m)

    Returns
    -------
    ndarray (..., n), a new array
    """
    Q = np.array(Q, float)
    rev = robot.is_revolute
    if Q.size == 0 or not rev.any():
        return Q
    turn, tol = 2 * np.pi, LIMIT_TOL
    lo, hi = robot.limits[rev].T
    x = wrap(Q[..., rev])
    inside = ((lo - tol <= -np.pi) & (hi + tol >= np.pi)) | ((x >= lo - tol) & (x <= hi + tol))
    if not inside.all():
        with np.errstate(invalid="ignore"):          # an infinite limit: x is inside
            up = x + turn * np.ceil((lo - tol - x) / turn)     # the first turn above lo
        up = np.where(np.isfinite(up), up, x)
        below = up - turn
        pick = np.where(up <= hi + tol, up,
                        np.where(_miss(below, lo, hi) <= _miss(up, lo, hi), below, up))
        x = np.where(inside, x, pick)
    Q[..., rev] = x
    return Q


def within_limits(robot, Q) -> np.ndarray:
    """Is each configuration within the limits, revolute joints allowing whole turns?

    Parameters
    ----------
    robot : Robot
    Q : array_like (..., n), joint values (rad / m)

    Returns
    -------
    ndarray (...) of bool, :func:`normalise` puts it within them (-170 deg passes [0, 360] deg)
    """
    return ~(violations(robot, normalise(robot, Q)) != 0).any(-1)


def _miss(x, lo, hi):
    return np.maximum(np.maximum(lo - x, x - hi), 0.0)


def violations(robot, q) -> np.ndarray:
    """How far each joint of ``q`` is beyond its limits, beyond ``LIMIT_TOL``.

    Parameters
    ----------
    robot : Robot, its limits (``LIMIT_TOL``: rad, or times the arm's size for prismatic)
    q : ndarray (..., n), joint values (rad / m), not wrapped

    Returns
    -------
    ndarray (..., n), ``q - lower`` below the lower limit, ``q - upper`` above the upper, else 0
    """
    lo, hi, lo_band, hi_band = _limit_bands(robot)
    below = np.where(q < lo_band, q - lo, 0.0)
    above = np.where(q > hi_band, q - hi, 0.0)
    return below + above


@per_robot
def _limit_bands(robot) -> tuple:
    """``(lo, hi, lo - tol, hi + tol)``, each ``(n,)``: the limits and the limits widened by
    ``LIMIT_TOL`` (rad, or times the arm's size for prismatic joints). Cached per robot."""
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    tol = np.where(robot.is_revolute, LIMIT_TOL, LIMIT_TOL * max(robot.characteristic_length,
                                                                 1e-12))
    return lo, hi, lo - tol, hi + tol


def duplicates(robot, q, valid, cs=None) -> np.ndarray:
    """Valid slots whose every joint is within ``DUPLICATE`` (wrapped) of an earlier kept one.

    Pairs are screened first by one number per slot, ``key = sum_k w_k f_k(q_k)`` with
    ``f = (cos, sin)`` of revolute joints and the value of prismatic ones: both are 1-Lipschitz,
    so two slots within ``DUPLICATE`` in every joint have keys within ``sum_k |w_k| DUPLICATE``,
    and only the pairs that pass are compared joint by joint (distinct solutions almost never do).

    Parameters
    ----------
    robot : Robot
    q : ndarray (N, K, n), joint values (rad / m)
    valid : ndarray (N, K) of bool
    cs : tuple of ndarray (n, N K), optional: the joints' cosines and sines, joint-major

    Returns
    -------
    ndarray (N, K) of bool, the slots to drop
    """
    N, K, n = q.shape
    drop = np.zeros((N, K), bool)
    if K < 2 or not valid.any():
        return drop
    rev = robot.is_revolute
    x = q.reshape(-1, n).T
    c, s = (np.cos(x), np.sin(x)) if cs is None else cs
    w_cos, w_sin, w_x, reach = _duplicate_key(robot)
    key = (w_cos @ c + w_sin @ s + w_x @ x).reshape(N, K)
    # poses with two valid keys within reach: neighbours once each pose's keys are sorted
    with np.errstate(invalid="ignore"):
        ordered = np.sort(np.where(valid, key, np.nan), axis=1)      # NaN (invalid) last
        suspect = (np.diff(ordered, axis=1) <= reach).any(1)
    if not suspect.any():
        return drop
    poses = np.flatnonzero(suspect)
    kv, ok = key[poses], valid[poses]
    near = (np.abs(kv[:, :, None] - kv[:, None, :]) <= reach) & ok[:, :, None] \
        & ok[:, None, :] & np.tri(K, k=-1, dtype=bool)             # [j, i]: i < j
    pose, j, i = np.nonzero(near)
    pose = poses[pose]
    d = q[pose, j] - q[pose, i]                                    # (pairs, n)
    d[:, rev] = wrap(d[:, rev])
    same = (np.abs(d) < DUPLICATE).all(-1)
    pose, j, i = pose[same], j[same], i[same]
    for slot in np.unique(j).tolist():          # ascending: a slot's verdict before later ones
        at = j == slot
        kept = ~drop[pose[at], i[at]]
        drop[pose[at][kept], slot] = True
    return drop


@per_robot
def _duplicate_key(robot) -> tuple:
    """The weights of :func:`duplicates`' screening key (of the cosines, sines and values)
    and how far apart the keys of two duplicates can be. Cached per robot."""
    rev = robot.is_revolute
    w = 1.0 + 0.37 * np.arange(robot.dof)                      # generic, fixed weights
    reach = DUPLICATE * (w * np.where(rev, 1.61, 1.0)).sum() * (1 + 1e-9) + 1e-15
    return np.where(rev, w, 0.0), np.where(rev, 0.61 * w, 0.0), np.where(rev, 0.0, w), reach


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
        Lengths in units of the arm's size; the linear rows tested against the position rank.
    """
    m, n = Q.shape
    rev = robot.is_revolute[:, None]
    L = robot.characteristic_length
    z = F[:, :, :3, 2]
    lin = cross(z, tool[:, None, :3, 3] - F[:, :, :3, 3]) / L
    # the transposed Jacobian (m, n, 6), joint by joint: it has the same singular values
    J = np.empty((m, n, 6))
    J[..., :3] = np.where(rev, lin, z * L)
    J[..., 3:] = np.where(rev, z, 0.0)
    full, full_pos = robot.generic_ranks

    def rank(M):
        sv = np.linalg.svd(M, compute_uv=False)
        return np.sum(sv > SINGULAR_TOL * np.maximum(sv[:, :1], 1.0), axis=-1)
    out, todo = np.zeros(m, bool), np.ones(m, bool)
    if n == 6 == full and full_pos == 3:   # s_min >= |det| / |J|_F^5: full rank, no SVD
        fro = np.sqrt((J * J).sum(axis=(1, 2)))
        todo = np.abs(np.linalg.det(J)) <= SINGULAR_TOL * np.maximum(fro, 1.0) * fro ** 5
    if todo.any():
        M = J[todo]
        rJ = rank(M)
        sub = rJ < full
        rest = ~((rJ == 6) & (n == 6) & (full_pos == 3))
        if rest.any():
            sub[rest] |= rank(M[rest, :, :3]) < full_pos
        out[todo] = sub
    return out
