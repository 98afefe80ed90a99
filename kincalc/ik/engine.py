"""The one IK engine: every closed-form family, for a batch of targets at once.

:func:`solve_targets` recognises the robot's family (:func:`~kincalc.ik.families.plan`),
runs its solver (:mod:`kincalc.ik.solvers`, on the reversed chain for a ``reversed-``
family, with the general 6R elimination for six revolute joints of no other structure)
over all targets, and checks and flags every candidate in one pass:

1. FK of every candidate (the robot as given); a candidate is a solution when it
   reaches the target: its position to ``ACCEPT_POSITION`` of the arm's size, the
   components the family controls to ``ACCEPT_ORIENTATION`` rad, other components a
   target gives to ``CHECK_ORIENTATION``;
2. revolute joints moved by whole turns to the representative nearest their limits
   (:func:`normalise`);
3. duplicates (every joint within ``DUPLICATE``, wrapped) dropped after their first;
4. limit violations, the singular test on the Jacobian, the branch labels
   (:mod:`kincalc.ik.labels`).

A single pose is a batch of one: ``robot.ik`` and ``robot.ik_batch``, the CLI's ``ik``,
``ik --batch``, ``reach``, ``check`` and the rest answer through here, so a solution has
the same label and flags wherever it is asked for.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import KincalcError, TargetMismatch
from ..tolerances import (ACCEPT_ORIENTATION, ACCEPT_POSITION, CHECK_ORIENTATION, DUPLICATE,
                          LIMIT_TOL, SINGULAR_TOL)
from .branches import Branches
from .families import Family, plan
from .labels import labels
from .screws import wrap
from .solvers import SOLVERS
from .target import Targets


class UnsupportedRobot(KincalcError):
    """A robot (or a target kind) no closed form covers (exit status 2)."""

    exit_status = 2


@dataclass(frozen=True)
class Solved:
    """Every candidate of every target, checked (see the module docstring).

    ``q (N, K, n)`` joint values (rad / m, normalised into the limits); ``candidate (N,
    K)`` the family produced one in this slot; ``valid (N, K)`` it reaches the target
    (and is not a copy of an earlier slot); ``position_error (N, K)`` (m) and
    ``orientation_error (N, K)`` (rad; NaN where no orientation is checked);
    ``violation (N, K, n)`` how far each joint is beyond its limits (negative below the
    lower, positive above the upper, 0 within); ``within (N, K)``; ``singular (N, K)``
    (valid slots); ``free (N, K, n)`` joints the target leaves undetermined; ``labels``
    an object array ``(N, K)`` of branch labels (candidate slots); ``continuum (N, K, 5)``
    (mask, first joint, second joint, sign, total) or None; ``branches``: the solver's
    :class:`~kincalc.ik.branches.Branches` (notes and dead ends, with ``explain``).
    """

    family: str
    spec: Family
    method: str
    q: np.ndarray
    candidate: np.ndarray
    valid: np.ndarray
    position_error: np.ndarray
    orientation_error: np.ndarray
    violation: np.ndarray
    within: np.ndarray
    singular: np.ndarray
    free: np.ndarray
    labels: np.ndarray
    continuum: np.ndarray | None
    branches: Branches

    @property
    def counts(self) -> np.ndarray:
        """Number of solutions of each target, ``(N,)``."""
        return self.valid.sum(axis=1)


#: targets solved together (memory: a few kB per target and slot)
CHUNK = 2048


def solve_batch(robot, T, *, chunk: int = CHUNK) -> Solved:
    """Every IK solution of ``robot`` for each pose of ``T (N, 4, 4)`` (world frame, SI),
    solved ``chunk`` poses at a time: the :class:`Solved` of all of them (``branches``
    is None when there was more than one chunk). Raises :class:`UnsupportedRobot` for a
    robot no closed form covers."""
    T = np.asarray(T, float)
    if T.ndim == 2:
        T = T[None]
    if T.shape[1:] != (4, 4):
        raise ValueError(f"expected poses of shape (N, 4, 4), got {T.shape}")
    if len(T) <= chunk:
        return solve_targets(robot, Targets(T))
    parts = [solve_targets(robot, Targets(T[i:i + chunk])) for i in range(0, len(T), chunk)]
    first = parts[0]
    join = lambda name: np.concatenate([getattr(p, name) for p in parts])  # noqa: E731
    cont = None if first.continuum is None and all(p.continuum is None for p in parts) else \
        np.concatenate([p.continuum if p.continuum is not None
                        else np.zeros(p.valid.shape + (5,)) for p in parts])
    return replace(first, q=join("q"), candidate=join("candidate"), valid=join("valid"),
                   position_error=join("position_error"),
                   orientation_error=join("orientation_error"), violation=join("violation"),
                   within=join("within"), singular=join("singular"), free=join("free"),
                   labels=join("labels"), continuum=cont, branches=None)


def solve_targets(robot, targets: Targets, *, explain: bool = False) -> Solved:
    """Every closed-form solution of ``robot`` for each target of ``targets``.

    Raises :class:`UnsupportedRobot` when no family covers the robot (the numerical
    solver's business) or the target's kind does not fit the family."""
    S, family, why = plan(robot)
    if targets.kind == "tcv":
        family = TCV
    elif family is None:
        raise UnsupportedRobot(f"{robot.name}: no closed form ({why})")
    check_kind(robot, family, targets)
    N, n = len(targets), robot.dof
    br = Branches.start(N, n, explain=explain)
    if targets.kind == "tcv":
        from .solvers import tcv
        br = tcv(robot, S, targets, br)
    elif family.name == "general-6r":
        from .general6r import general_6r
        br = general_6r(robot, targets, br)
    elif family.reverse:
        br = SOLVERS[family.solver](S.constant("reversed", S.reversed), targets.inverted(), br)
        br = br.reversed_chain()
    else:
        br = SOLVERS[family.solver](S, targets, br)
    q = br.q(robot.is_revolute)
    q = np.where(robot.is_revolute, wrap(q), q)
    candidate = br.ok.copy()
    method = family.description
    if not family.exact:
        from .nearly import on_true_robot
        q, candidate, br, method = on_true_robot(robot, family, targets, q, candidate, br)
    return _check(robot, family, method, targets, q, candidate, br)


#: the pseudo-family of tool-configuration-vector targets (Schilling 1990): the last
#: joint from the vector's length, the others placing the tool point
TCV = Family("tcv", "tool configuration vector: the last joint from |w4..w6|, the others "
             "place the tool point, the approach vector r3 is checked",
             "position, approach and roll", False)


def check_kind(robot, family: Family, targets: Targets) -> None:
    """Refuse a target kind the family does not take (words for the edge to render)."""
    from .families import APPROACH_FAMILIES
    five = family.name in APPROACH_FAMILIES
    if family is TCV:
        return
    if targets.kind == "approach" and not five:
        raise TargetMismatch(robot.name, "full orientation", family.controls)
    if family.needs_orientation and targets.kind == "position":
        raise TargetMismatch(robot.name, "orientation", family.controls, approach_ok=five)


def _check(robot, family, method, targets, q, candidate, br) -> Solved:
    """Steps 1-4 of the module docstring for ``q (N, K, n)``."""
    from ..fk import chain_frames
    N, K, n = q.shape
    L = max(robot.characteristic_length, 1e-12)
    rev = robot.is_revolute
    idx = np.nonzero(candidate)
    Q = q[idx]                                                           # (m, n)
    F = chain_frames(robot.chain, Q) if len(Q) else np.zeros((0, n, 4, 4))
    tool = F[:, -1] @ robot.chain.fixed[-1] if len(Q) else np.zeros((0, 4, 4))
    Tt = targets.T[idx[0]]
    pe = np.linalg.norm(tool[:, :3, 3] - Tt[:, :3, 3], axis=-1)
    oe = _orientation_error(targets, idx[0], tool)
    o_tol = ACCEPT_ORIENTATION if family.needs_orientation else CHECK_ORIENTATION
    reach = pe <= ACCEPT_POSITION * L
    if oe is not None:
        reach &= oe <= o_tol
    Qn = normalise(robot, Q)
    q = q.copy()
    q[idx] = Qn
    valid = np.zeros((N, K), bool)
    valid[idx] = reach
    valid &= ~duplicates(robot, q, valid)
    viol = violations(robot, q)
    within = ~(viol != 0).any(-1)
    free = br.free_mask()
    sing = np.zeros((N, K), bool)
    good = valid[idx]
    if good.any():
        sing[tuple(i[good] for i in idx)] = singular(robot, Qn[good], F[good], tool[good])
    sing |= valid & free.any(-1)
    lab = np.empty((N, K), object)
    if len(Q):
        lab[idx] = labels(robot, family.solver, F, [br.signs[k] for k in idx[1].tolist()],
                          free[idx])
    PE = np.zeros((N, K))
    PE[idx] = pe
    OE = np.full((N, K), np.nan)
    if oe is not None:
        OE[idx] = oe
    cont = br.extra.get("continuum")
    return Solved(family=family.name, spec=family, method=method, q=q, candidate=candidate,
                  valid=valid,
                  position_error=PE, orientation_error=OE, violation=viol, within=within,
                  singular=sing, free=free, labels=lab, continuum=cont, branches=br)


def _orientation_error(targets: Targets, owner, tool):
    """Angle (rad) between each candidate's orientation and its target's, for the
    components the target gives: the whole rotation, or the approach (tool z)."""
    if targets.kind == "position":
        return None
    if targets.kind in ("approach", "tcv"):
        a = targets.approach[owner]
        z = tool[:, :3, 2]
        c = (z * a).sum(-1)
        s = np.linalg.norm(np.cross(z, a), axis=-1)
        return np.arctan2(s, c)
    R = np.swapaxes(targets.T[owner, :3, :3], -1, -2) @ tool[:, :3, :3]
    c = 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1.0)
    s = 0.5 * np.linalg.norm(np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0],
                                       R[:, 1, 0] - R[:, 0, 1]], -1), axis=-1)
    return np.arctan2(s, c)


def normalise(robot, Q) -> np.ndarray:
    """``Q (..., n)`` with each revolute joint moved by whole turns to the value nearest
    its limits: in (-pi, pi] when that is within them (to ``LIMIT_TOL``), else the turn
    that lies within them (the lowest, for limits wider than a turn), else the one
    that misses them least. A new array; prismatic joints are kept."""
    Q = np.array(Q, float)
    rev = robot.is_revolute
    if not rev.any() or Q.size == 0:
        return Q
    lo, hi = robot.limits[rev, 0], robot.limits[rev, 1]
    x = wrap(Q[..., rev])
    turn = 2 * np.pi
    inside = (x >= lo - LIMIT_TOL) & (x <= hi + LIMIT_TOL)
    with np.errstate(invalid="ignore"):          # infinite limits: x is inside
        up = x + turn * np.ceil((lo - LIMIT_TOL - x) / turn)     # first turn above lo
    up = np.where(np.isfinite(up), up, x)
    below = up - turn
    pick = np.where(up <= hi + LIMIT_TOL, up,
                    np.where(_miss(below, lo, hi) <= _miss(up, lo, hi), below, up))
    Q[..., rev] = np.where(inside, x, pick)
    return Q


def within_limits(robot, Q) -> np.ndarray:
    """``(...)`` bool: is each configuration ``Q (..., n)`` within the limits, revolute
    joints allowing whole turns (-170 deg passes a [0, 360] limit)?"""
    return ~(violations(robot, normalise(robot, Q)) != 0).any(-1)


def _miss(x, lo, hi):
    return np.maximum(np.maximum(lo - x, x - hi), 0.0)


def violations(robot, q) -> np.ndarray:
    """``(..., n)``: how far each joint of ``q`` is beyond its limits, beyond
    ``LIMIT_TOL`` (rad, or times the arm's size for prismatic joints): negative below the
    lower limit, positive above the upper, 0 within."""
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    tol = np.where(robot.is_revolute, LIMIT_TOL, LIMIT_TOL * max(robot.characteristic_length,
                                                                 1e-12))
    below = np.where(q < lo - tol, q - lo, 0.0)
    above = np.where(q > hi + tol, q - hi, 0.0)
    return below + above


def duplicates(robot, q, valid) -> np.ndarray:
    """``(N, K)``: valid slots whose every joint is within ``DUPLICATE`` (wrapped for
    revolute joints) of an earlier valid slot's."""
    N, K, n = q.shape
    drop = np.zeros((N, K), bool)
    if K < 2 or not valid.any():
        return drop
    rev = robot.is_revolute
    for j in range(1, K):
        d = np.abs(q[:, :j] - q[:, j:j + 1])                                # (N, j, n)
        d[..., rev] = np.abs(wrap(d[..., rev]))
        same = (d.max(-1) < DUPLICATE) & valid[:, :j] & ~drop[:, :j]
        drop[:, j] = valid[:, j] & same.any(-1)
    return drop


def singular(robot, Q, F, tool) -> np.ndarray:
    """``(m,)``: is each configuration singular (the rank of its Jacobian, lengths in
    units of the arm's size, below the robot's generic rank, or that of its linear
    rows)? ``F (m, n, 4, 4)`` the joint frames, ``tool (m, 4, 4)`` the tool poses."""
    m, n = Q.shape
    rev = robot.is_revolute
    L = robot.characteristic_length
    z = F[:, :, :3, 2]
    lin = np.cross(z, tool[:, None, :3, 3] - F[:, :, :3, 3]) / L
    J = np.zeros((m, 6, n))
    J[:, :3] = np.where(rev[:, None], lin, z).transpose(0, 2, 1)
    J[:, 3:] = np.where(rev[:, None], z, 0.0).transpose(0, 2, 1)
    J[:, :, ~rev] *= L
    full, full_pos = robot.generic_ranks

    def rank(M):
        sv = np.linalg.svd(M, compute_uv=False)
        return np.sum(sv > SINGULAR_TOL * np.maximum(sv[:, :1], 1.0), axis=-1)
    rJ = rank(J)
    out = rJ < full
    rest = ~((rJ == 6) & (n == 6) & (full_pos == 3))
    if rest.any():
        out[rest] |= rank(J[rest, :3, :]) < full_pos
    return out
