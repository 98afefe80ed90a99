"""Sweeping a held joint of a redundant arm: every branch at every value, joined into
continuous branches.

A 7-joint arm reaches a pose along a one-parameter family of configurations. Holding one
joint at a value leaves a chain the engine solves with every branch
(:mod:`kincalc.analysis.redundancy`); :func:`sweep` does that for each of ``m`` values of the
joint and joins the answers:

1. **Solving.** Each value ``v`` is a locked problem: the chain the lock leaves, and the
   target. Holding the *first* joint puts its motion ``G_v`` at the base end of the chain,
   so every value shares one chain (the joint held at 0) and only the target moves,
   ``T_v = B G_v^-1 B^-1 T`` (``B`` the base); holding the *last* joint puts it at the tool
   end, ``T_v = T W^-1 G_v^-1 W`` (``W`` the flange-and-tool pose at q = 0; full poses only,
   a position target has no orientation to carry it). Those sweeps are one batch of ``m``
   targets through the engine; any other joint gives one chain per value.
2. **Joining.** Solutions at neighbouring values belong to one branch when they are each
   other's nearest and no joint moves more than :data:`JUMP` between them (greedy matching
   by the largest joint change, revolute joints wrapped, prismatic ones scaled by the
   arm's size). A solution with no such partner starts a new branch.
3. **Ends.** A branch that stops inside the swept range either *meets* another branch
   that stops at the same value with a solution within :data:`JUMP` of its own (the two
   merge and leave together: the locked chain is singular there, a fold of the
   self-motion), or *leaves* the reach (no solution near it at the next value). Ends are
   located between two sampled values; a finer ``steps`` narrows them.

SI inside: rad, m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..ik.target import Targets
from ..spatial import invert_transform, wrap
from .redundancy import (generic_chain, held_within, joint_motion, least_change,
                         locked_robot, with_held)

#: the largest change of any joint (rad; prismatic joints in units of the arm's size)
#: between neighbouring values of one branch
JUMP = np.deg2rad(20.0)
#: values of a sweep when none is given
DEFAULT_STEPS = 181


@dataclass(frozen=True)
class BranchEnd:
    """How a branch starts or stops: ``kind`` "range" (at an end of the swept range),
    "meets" (branch ``other`` starts or stops with it there: they merge) or "leaves" (no
    solution near it beyond), ``value`` where (rad / m, the last value the branch was
    seen at, located between two sampled values; None for "range")."""

    kind: str
    value: float | None
    other: int | None = None


@dataclass(frozen=True)
class SweepBranch:
    """One continuous branch: present at the values ``first..last`` (indices), its
    ``labels`` (the engine's branch labels along it, in order of appearance), how it
    ``starts`` and ``ends``."""

    first: int
    last: int
    labels: tuple
    starts: BranchEnd
    ends: BranchEnd


@dataclass(frozen=True)
class Sweep:
    """Every branch of ``robot`` for one target at each value of the held ``joint``.

    ``values (m,)`` rad / m; per value and branch (``B`` branches): ``q (m, B, n)`` the
    whole arm's joints (NaN where the branch has no solution), ``label (m, B)`` object
    (None there), ``within (m, B)`` inside every joint's limits (the swept joint's
    included), ``singular (m, B)``; ``branches``: one :class:`SweepBranch` per column;
    ``locks``: the other joints held, ``((index, value), ...)``; ``families``: the
    engine's family of the locked chain at each value (``(m,)`` object).
    """

    robot: object
    joint: int
    values: np.ndarray
    q: np.ndarray
    label: np.ndarray
    within: np.ndarray
    singular: np.ndarray
    branches: tuple
    locks: tuple
    families: np.ndarray

    @property
    def present(self) -> np.ndarray:
        """``(m, B)`` bool: the branch has a solution at the value."""
        return ~np.isnan(self.q[..., 0])


def sweep_values(robot, joint: int, start=None, stop=None, steps: int = DEFAULT_STEPS):
    """``steps`` evenly spaced values of ``joint`` from ``start`` to ``stop`` (default: its
    limits), ``(steps,)`` rad / m; ``steps`` >= 2."""
    lo, hi = robot.limits[joint]
    start = lo if start is None else start
    stop = hi if stop is None else stop
    if not (np.isfinite(start) and np.isfinite(stop)):
        raise InputError(f"joint {robot.joints[joint].name} has no finite limits to sweep "
                         "between: give the first and the last value")
    if steps < 2:
        raise InputError("a sweep needs at least 2 values")
    return np.linspace(start, stop, steps)


def sweep(robot, targets: Targets, joint: int, values, locks=None) -> Sweep:
    """Every branch of ``robot`` reaching the one target of ``targets`` with ``joint`` held
    at each of ``values``, joined into continuous branches (module docstring).

    Parameters
    ----------
    robot : Robot
        The arm (typically 7 joints).
    targets : Targets
        One target (world frame, SI) of kind pose, position or approach.
    joint : int
        The swept joint (0-based).
    values : array_like (m,)
        Its values (rad / m), increasing.
    locks : dict of int to float, optional
        Other joints held throughout (0-based index -> value, rad / m).

    Returns
    -------
    Sweep

    Raises
    ------
    InputError
        The swept joint is also locked, a TCV target, or the locks leave a chain with a
        self-motion of its own at a generic value of the joint
        (:func:`~kincalc.analysis.redundancy.check_lock`).
    UnsupportedRobot
        No closed form covers the chain a lock leaves.
    """
    locks = dict(locks or {})
    if joint in locks:
        raise InputError(f"the swept joint {robot.joints[joint].name} is also locked")
    if targets.kind == "tcv":
        raise InputError("a tool configuration vector target is not swept; give the pose")
    values = np.asarray(values, float)
    generic_chain(robot, joint, locks)
    from ..errors import UnsupportedRobot
    solver = Solver(robot, targets, joint, locks)
    try:
        found = solver.grid(values)
    except UnsupportedRobot as exc:
        held = ", ".join(robot.joints[j].name for j in sorted({**locks, joint: 0}))
        raise InputError(f"holding {held} of {robot.name} leaves {robot.dof - len(locks) - 1} "
                         f"joints that no closed form covers ({exc}); a sweep needs a "
                         "closed form at every value") from None
    return _join(solver, values, found)


#: halvings of a step to follow a branch through fast motion or locate its end
_DEPTH = 8


class Solver:
    """The solutions of the locked problem at any value of the swept ``joint`` (module
    docstring, step 1), the other ``locks`` held, for the one target of ``targets``: the
    whole arm's joints, ``(q (k, n), label (k,), within (k,), singular (k,), family)`` per
    value (within: every joint, the held ones included)."""

    def __init__(self, robot, targets, joint, locks):
        self.robot, self.targets, self.joint, self.locks = robot, targets, joint, locks
        n = robot.dof
        self.shared = joint == 0 or (joint == n - 1 and targets.kind == "pose")
        self.chain = locked_robot(robot, {**locks, joint: 0.0}) if self.shared else None
        if self.shared:
            from ..conventions import to_poe
            self.poe = to_poe(robot)

    def grid(self, values) -> list:
        """The solutions at each of ``values`` (one engine batch when the chain is shared)."""
        if self.shared:
            return self._unpack(self.chain, _moved_targets(self, values), values)
        return [self.at(v) for v in np.asarray(values).tolist()]

    def at(self, v: float):
        """The solutions at the value ``v``."""
        if self.shared:
            return self._unpack(self.chain, _moved_targets(self, [v]), [v])[0]
        chain = locked_robot(self.robot, {**self.locks, self.joint: v})
        return self._unpack(chain, self.targets, [v])[0]

    def _unpack(self, chain, targets, values) -> list:
        from ..ik.engine import solve_targets
        sv = solve_targets(chain, targets)
        values = np.asarray(values, float)
        q = with_held(self.robot, sv.q, {**self.locks, self.joint: values[:, None]})
        within = sv.within & held_within(self.robot, q, [self.joint, *self.locks])
        labels, singular = sv.labels, sv.singular
        return [(q[r, ok], labels[r, ok], within[r, ok], singular[r, ok], sv.family)
                for r, ok in enumerate(sv.valid)]


def _moved_targets(solver, values) -> Targets:
    """The targets of the chain held at 0 for each value of the first or last joint of a
    shared-chain ``solver`` (module docstring, step 1): ``m`` targets of its kind."""
    robot, targets, joint, poe = solver.robot, solver.targets, solver.joint, solver.poe
    axis, point = np.array(poe.joints[joint].axis), np.array(poe.joints[joint].point)
    G_inv = joint_motion(axis, point, poe.joints[joint].revolute,
                         -np.asarray(values, float))                            # (m, 4, 4)
    T = targets.T[0]
    if joint == 0:
        B = np.asarray(robot.base, float)
        A = B @ G_inv @ invert_transform(B)                                     # (m, 4, 4)
        approach = None if targets.approach is None else \
            np.einsum("mij,j->mi", A[:, :3, :3], targets.approach[0])
        return Targets(A @ T, targets.kind, approach)
    W = poe.M @ poe.tool
    return Targets(T @ invert_transform(W) @ G_inv @ W, targets.kind)


def _distance(robot, a, b) -> np.ndarray:
    """The largest joint change between the rows of ``a (p, n)`` and ``b (r, n)``,
    ``(p, r)``: revolute joints wrapped (rad), prismatic ones over the arm's size."""
    if not len(a) or not len(b):
        return np.zeros((len(a), len(b)))
    d = a[:, None, :] - b[None, :, :]
    scale = max(robot.characteristic_length, 1e-12)
    return np.where(robot.is_revolute, np.abs(wrap(d)), np.abs(d) / scale).max(-1)


def _match(D) -> np.ndarray:
    """``(p,)``: the column paired with each row of ``D (p, r)`` (-1 for none), greedy by
    increasing distance, each column used once, distances up to :data:`JUMP`."""
    link = np.full(D.shape[0], -1)
    used = np.zeros(D.shape[1], bool)
    for flat in np.argsort(D, axis=None).tolist():
        i, j = divmod(flat, D.shape[1])
        if D[i, j] > JUMP:
            break
        if link[i] < 0 and not used[j]:
            link[i], used[j] = j, True
    return link


def _track(solver, va, A, vb, B, depth=0):
    """Follow the solutions ``A (p, n)`` at ``va`` to those ``B (r, n)`` at ``vb``.

    Where the direct match leaves a solution of either side without a partner, the step
    is halved (up to :data:`_DEPTH` times): a branch moving fast is followed through the
    values between, and a branch that stops is located to ``|vb - va| / 2^_DEPTH``.

    Returns ``(link (p,), ends, starts)``: the solution of B each of A continues to (-1:
    it stops), ``ends`` {i: (value, q)} the last value and solution seen of each A that
    stops, ``starts`` {j: (value, q)} the first of each B that begins after ``va``.
    """
    link = _match(_distance(solver.robot, A, B))
    unpaired_b = np.setdiff1d(np.arange(len(B)), link[link >= 0])
    if (link >= 0).all() and not len(unpaired_b):
        return link, {}, {}
    if depth >= _DEPTH:
        return (link, {i: (va, A[i]) for i in np.flatnonzero(link < 0).tolist()},
                {j: (vb, B[j]) for j in unpaired_b.tolist()})
    mid = 0.5 * (va + vb)
    M = solver.at(mid)[0]
    l1, e1, s1 = _track(solver, va, A, mid, M, depth + 1)
    l2, e2, s2 = _track(solver, mid, M, vb, B, depth + 1)
    link = np.where(l1 >= 0, l2[np.maximum(l1, 0)] if len(M) else -1, -1)
    ends = {i: e1[i] if l1[i] < 0 else e2[int(l1[i])] for i in np.flatnonzero(link < 0).tolist()}
    starts = {}
    for j in range(len(B)):
        if j not in link:        # it begins in the second half, or in the first (via M)
            via = np.flatnonzero(l2 == j)
            starts[j] = s1[int(via[0])] if len(via) else s2[j]
    return link, ends, starts


def _join(solver, values, found) -> Sweep:
    """Step 2 and 3 of the module docstring on the per-value solutions ``found``."""
    robot = solver.robot
    m, n = len(values), robot.dof
    column = [np.arange(len(found[0][0]))]         # per value: the branch of each solution
    count = len(column[0])
    ends, starts = {}, {}                          # branch -> (value, q) where it stops/begins
    for i in range(1, m):
        link, e, s = _track(solver, values[i - 1], found[i - 1][0], values[i], found[i][0])
        cols = np.full(len(found[i][0]), -1)
        cols[link[link >= 0]] = column[i - 1][link >= 0]
        for b in np.flatnonzero(cols < 0).tolist():
            cols[b] = count
            starts[count] = s[b]
            count += 1
        column.append(cols)
        ends.update({int(column[i - 1][a]): e[a] for a in e})
    Q = np.full((m, count, n), np.nan)
    label = np.full((m, count), None, object)
    within = np.zeros((m, count), bool)
    singular = np.zeros((m, count), bool)
    for i, (q, lab, inside, sing, _) in enumerate(found):
        c = column[i]
        Q[i, c], label[i, c], within[i, c], singular[i, c] = q, lab, inside, sing
    present = ~np.isnan(Q[..., 0])
    branches = []
    for b in range(count):
        rows = np.flatnonzero(present[:, b])
        branches.append(SweepBranch(
            int(rows[0]), int(rows[-1]), tuple(dict.fromkeys(label[rows, b].tolist())),
            _end(robot, b, starts, int(rows[0]) == 0),
            _end(robot, b, ends, int(rows[-1]) == m - 1)))
    return Sweep(robot=robot, joint=solver.joint, values=values, q=Q, label=label,
                 within=within, singular=singular, branches=tuple(branches),
                 locks=tuple(sorted(solver.locks.items())),
                 families=np.array([f[4] for f in found], object))


def _end(robot, b, where, at_range_end) -> BranchEnd:
    """How branch ``b`` starts or stops: at the range's end, or where ``where[b]``
    ``(value, q)`` says, meeting the branch that starts or stops nearest it there."""
    if at_range_end and b not in where:
        return BranchEnd("range", None)
    v, q = where[b]
    others = [c for c, (w, _) in where.items() if c != b and abs(w - v) <= 1e-12 + 1e-9 * abs(v)]
    if others:
        D = _distance(robot, q[None], np.array([where[c][1] for c in others]))[0]
        k = int(np.argmin(D))
        if D[k] <= JUMP:
            return BranchEnd("meets", v, others[k])
    return BranchEnd("leaves", v)


def nearest(sw: Sweep, near) -> tuple | None:
    """The value and branch of ``sw`` nearest the current joints ``near (n,)`` (rad / m):
    the least change, each revolute joint moved by whole turns within its limits towards
    ``near``, prismatic joints scaled by the arm's size
    (:func:`~kincalc.analysis.redundancy.least_change`).

    Returns
    -------
    (value index, branch index, q (n,), change (n,)) of the nearest solution within the
    limits, or None when no solution of the sweep is within them.
    """
    best = least_change(sw.robot, sw.q, sw.present & sw.within, near)
    return None if best is None else (*best[0], best[1], best[2])


# --- the document ---------------------------------------------------------------------

def sweep_document(sw: Sweep, target, units, near=None) -> dict:
    """The JSON document of a sweep (what ``kincalc ik --sweep --json`` prints and the
    tables show), in the display ``units``.

    Parameters
    ----------
    sw : Sweep
    target : Target
        The pose swept over (:class:`kincalc.ik.Target`, world frame, SI).
    units : Units
    near : array_like (n,), optional
        The current joints (rad / m): adds ``nearest`` (:func:`nearest`).
    """
    from .results import json_header, json_numbers, locked_entries
    robot, u = sw.robot, units
    scale = u.a if robot.joints[sw.joint].revolute else u.l
    shown = lambda v: None if v is None else json_numbers(v * scale)  # noqa: E731
    families = dict(zip(*np.unique(sw.families.astype(str), return_counts=True)))
    out = json_header("ik", robot, u)
    out["target"] = {"T": u.pose(target.T), "orientation_given": target.orientation}
    out["sweep"] = {"joint": robot.joints[sw.joint].name, "values": shown(sw.values),
                    "steps": len(sw.values)}
    if sw.locks:
        out["locked"] = locked_entries(robot, sw.locks, u)
    out["method"] = {
        "families": [{"family": f, "values": int(c)} for f, c in families.items()],
        "description": "every branch of the chain the lock leaves at each value (the IK "
                       "engine), joined into continuous branches by the smallest joint "
                       f"change (at most {np.rad2deg(JUMP):g} deg between neighbouring "
                       "values, steps halved where a branch moves faster or stops)"}
    out["reachable"] = bool((sw.present & sw.within).any())
    out["branches"] = [_branch_entry(sw, b, br, shown) for b, br in enumerate(sw.branches)]
    out["points"] = [
        {"value": shown(v), "solutions": [
            {"branch": b + 1, "label": sw.label[i, b], "q": u.joints(robot, sw.q[i, b]),
             "within_limits": bool(sw.within[i, b]), "singular": bool(sw.singular[i, b])}
            for b in np.flatnonzero(sw.present[i]).tolist()]}
        for i, v in enumerate(sw.values.tolist())]
    if near is not None:
        best = nearest(sw, near)
        out["nearest"] = None if best is None else {
            "branch": best[1] + 1, "value": shown(sw.values[best[0]]),
            "label": sw.label[best[0], best[1]], "q": u.joints(robot, best[2]),
            "change": u.joints(robot, best[3])}
    return out


def _branch_entry(sw: Sweep, b: int, br: SweepBranch, shown) -> dict:
    rows = np.flatnonzero(sw.present[:, b])
    inside = sw.within[rows, b]
    runs, start = [], None
    for k, ok in enumerate(inside.tolist() + [False]):
        if ok and start is None:
            start = k
        elif not ok and start is not None:
            runs.append([shown(sw.values[rows[start]]), shown(sw.values[rows[k - 1]])])
            start = None
    end = lambda e: {"kind": e.kind, "at": shown(e.value),  # noqa: E731
                     "with": None if e.other is None else e.other + 1}
    return {"branch": b + 1, "labels": list(br.labels), "from": shown(sw.values[br.first]),
            "to": shown(sw.values[br.last]), "within_limits": runs,
            "singular_at": [shown(sw.values[i]) for i in rows[sw.singular[rows, b]].tolist()],
            "starts": end(br.starts), "ends": end(br.ends)}
