"""The textbook's wrong combinations (``--all-branches``): the solutions' joint values
paired the way a student pairs the +/- roots of each step, each with why it fails.

A textbook solves an arm in groups: the first joints place a point (the wrist centre,
the tool point, ...; :func:`~kincalc.ik.words.placed_point` finds it from the axes), the
others (the wrist) then set the orientation from them. A student who pairs a root of one
step with a root of another from the wrong branch gets a combination that does not reach
the target (Bingul & Kucuk, Example 4.2: zeta1 and zeta4). Within each group the values
of the solutions are combined freely:

* the arm: every combination of the placing joints' values that no solution has; it is
  judged by the point alone (``ArmMissed``: how far it puts the point from where the
  target needs it), the other joints taken from the solution sharing most of its values
  (they do not move the point);
* the wrist, for each arm of the solutions: every combination of the other joints'
  values among the solutions with that arm, judged by the whole pose (``Missed``).

A wrist from one branch paired with another branch's arm is no textbook slip (the wrist
is solved from the arm) and is not listed. An arm with nothing after the point (a planar
RR) is one group: all its joints are combined, as Example 4.2 does.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..spatial import rotation_error, wrap
from ..tolerances import DUPLICATE
from .words import placed_point
from .reasons import ArmMissed, Missed

#: --all-branches lists combinations only up to this many
MAX_COMBINATIONS = 512


def cross_combinations(robot, family: str, T, orientation: bool, sols) -> tuple:
    """The wrong combinations of the solutions' joint values (see the module docstring).

    Parameters
    ----------
    robot : Robot
    family : str
        The family the solutions came from (its placed point and arm, :func:`placed_point`).
    T : ndarray (4, 4)
        The target pose ``T_world_tool`` (world frame, SI).
    orientation : bool
        Whether the target's orientation counts.
    sols : list of IKSolution
        The solutions (``q (n,)`` rad / m).

    Returns
    -------
    rejected : list of dict
        ``q (n,)``, ``branch`` (what was combined), ``position_error`` (m),
        ``orientation_error`` (rad or None) and ``reason`` (``ArmMissed`` or ``Missed``).
    note : str or None
        Why nothing was listed: more than :data:`MAX_COMBINATIONS` combinations.
    """
    if len(sols) < 2:
        return [], None
    Q = np.array([s.q for s in sols])
    rev = robot.is_revolute
    placed = placed_point(robot, family)
    arm = list(placed[2]) if placed is not None and placed[2] else list(range(robot.dof))
    rest = [j for j in range(robot.dof) if j not in arm]
    groups = [(arm, None)] if not rest else \
        [(arm, None)] + [(rest, members) for members in _same(Q, arm, rev)]
    # counted before any is built: 8 solutions of a general 6R give 8**6 combinations,
    # and building each one (a Python-level comparison with every solution) took 16 s
    count = sum(combination_count(Q if m is None else Q[m], g, rev) for g, m in groups)
    if count > MAX_COMBINATIONS:
        return [], (f"{count} combinations of the solutions' joint values: too many to "
                    f"list (at most {MAX_COMBINATIONS})")
    combos = [(g, m, c) for g, m in groups
              for c in _combinations(Q if m is None else Q[m], g, rev)]
    out = []
    for joints, members, values in combos:
        if members is None and rest:
            out.append(_arm_combination(robot, placed, Q, joints, values))
        else:
            q = Q[0 if members is None else members[0]].copy()
            q[joints] = values
            out.append(_pose_combination(robot, T, orientation, q, "combination of the "
                                         "solutions' values" if members is None else
                                         "combination of the wrist values of one arm"))
    return out, None


def _gap(a, b, rev):
    """``|a - b|`` per joint, wrapped for revolute ones (``rev``, bool mask)."""
    d = np.asarray(a, float) - np.asarray(b, float)
    return np.abs(np.where(rev, wrap(d), d))


def _equal(a, b, rev) -> bool:
    return bool(np.all(_gap(a, b, rev) < DUPLICATE))


def _distinct(values, rev) -> list:
    """The values of one joint, each once (within :data:`DUPLICATE`)."""
    out = []
    for v in values.tolist():
        if not any(_gap(v, u, rev) < DUPLICATE for u in out):
            out.append(v)
    return out


def _same(Q, joints, rev) -> list:
    """The solutions (indices) grouped by their values of ``joints``."""
    groups = []
    for i, q in enumerate(Q):
        for g in groups:
            if _equal(Q[g[0]][joints], q[joints], rev[joints]):
                g.append(i)
                break
        else:
            groups.append([i])
    return groups


def combination_count(Q, joints, rev) -> int:
    """How many combinations :func:`_combinations` gives for the same arguments, without
    building them."""
    values, taken = _table(Q, joints, rev)
    total = 1
    for v in values:
        total *= len(v)
    return total - len(taken)


def _combinations(Q, joints, rev) -> list:
    """The combinations of the distinct values of ``joints`` in ``Q (m, n)`` that no row
    of ``Q`` has, each an array ``(len(joints),)``."""
    values, taken = _table(Q, joints, rev)
    return [np.array([v[k] for v, k in zip(values, idx)])
            for idx in itertools.product(*(range(len(v)) for v in values)) if idx not in taken]


def _table(Q, joints, rev) -> tuple:
    """``(values, taken)``: the distinct values of each of ``joints`` in ``Q (m, n)``
    (:func:`_distinct`), and the index tuples of the combinations a row of ``Q`` has (within
    :data:`DUPLICATE` of the row's value, joint by joint)."""
    values = [_distinct(Q[:, j], rev[j]) for j in joints]
    taken = set()
    for q in Q:
        near = [[k for k, u in enumerate(v) if _gap(q[j], u, rev[j]) < DUPLICATE]
                for j, v in zip(joints, values)]
        taken.update(itertools.product(*near))
    return values, taken


def _arm_combination(robot, placed, Q, arm, values) -> dict:
    """An arm combination, judged by the point it places: the other joints from the
    solution that shares most of its values."""
    shared = [(_gap(q[arm], values, robot.is_revolute[arm]) < DUPLICATE).sum() for q in Q]
    q = Q[int(np.argmax(shared))].copy()
    q[arm] = values
    from ..fk import chain_frames
    (frame, local), name, _ = placed
    F = chain_frames(robot.chain, np.array([q, Q[0]]))[:, frame]
    P = F[:, :3, :3] @ local + F[:, :3, 3]          # the combination's point, a solution's
    d = float(np.linalg.norm(P[0] - P[1]))
    return {"q": q, "branch": "combination of the arm's values", "position_error": d,
            "orientation_error": None,
            "reason": ArmMissed(name, d, tuple(arm))}


def _pose_combination(robot, T, orientation, q, branch) -> dict:
    """A combination judged by the whole pose (FK)."""
    Tq = robot.fk(q)
    pe = float(np.linalg.norm(Tq[:3, 3] - T[:3, 3]))
    oe = float(rotation_error(Tq[:3, :3], T[:3, :3])) if orientation else None
    return {"q": q, "branch": branch, "position_error": pe, "orientation_error": oe,
            "reason": Missed(pe, oe)}
