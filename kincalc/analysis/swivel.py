"""The swivel angles at which each branch of an SRS arm stays within its joint limits.

For a pose, each of the (up to) eight branches of an arm with a spherical shoulder and
wrist (:mod:`kincalc.ik.swivel`) is a function of the swivel angle ``psi``. A joint
limit cuts the circle of ``psi`` into intervals where the branch is feasible.
:func:`swivel_ranges` samples the circle (``SAMPLES`` angles, one engine batch), then
locates each end of each interval by bisection (all ends together, one batch per halving,
to ``2 pi / SAMPLES / 2^HALVINGS``), and names the joint whose limit ends it. A branch
is a slot of the family's sign table: the same root of joint 4, of the shoulder's middle
joint and of the wrist's middle joint at every angle.

SI inside: rad.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..ik.target import Targets
from ..spatial import wrap

#: angles sampled on the circle
SAMPLES = 720
#: halvings of a sample step locating each end of an interval
HALVINGS = 30


@dataclass(frozen=True)
class SwivelRange:
    """One branch: its ``label``, the ``intervals`` ``((lo, hi), ...)`` of the swivel
    angle (rad; ``lo`` in [-pi, pi), ``hi`` > ``lo``, beyond pi for an interval through
    +-pi; ``((-pi, pi),)`` for the whole circle) where it exists and every joint is within
    its limits, and per interval the joints whose limits end it ``((joint, side) at lo,
    (joint, side) at hi)`` (None at the end of a branch that stops existing, or for the
    whole circle)."""

    label: str
    intervals: tuple
    bounds: tuple


def _feasible(sv, slot) -> np.ndarray:
    """``(m,)``: the solution in ``slot`` of each target exists and is within the limits."""
    rows = np.arange(len(sv.valid))
    return sv.valid[rows, slot] & sv.within[rows, slot]


def _solve(robot, T, psi):
    from ..ik.engine import solve_targets
    psi = np.asarray(psi, float)
    return solve_targets(robot, Targets(np.broadcast_to(T, (len(psi), 4, 4)).copy(), "swivel",
                                        swivel=psi))


def swivel_ranges(robot, T, samples: int = SAMPLES) -> list:
    """The feasible swivel intervals of every branch of ``robot`` at the pose ``T``.

    Parameters
    ----------
    robot : Robot
        An arm with a spherical shoulder and wrist (:func:`kincalc.ik.swivel.srs`).
    T : array_like (4, 4)
        The pose ``T_world_tool`` (world frame, SI).
    samples : int
        Angles sampled on the circle before the ends are located.

    Returns
    -------
    list of SwivelRange
        One per branch that exists at some angle, in the family's slot order.

    Raises
    ------
    InputError
        ``robot`` is not an SRS arm.
    """
    from ..ik.swivel import require_srs
    require_srs(robot)
    T = np.asarray(T, float)
    grid = -np.pi + 2 * np.pi * np.arange(samples) / samples
    sv = _solve(robot, T, grid)
    K = sv.valid.shape[1]
    ok = sv.valid & sv.within                                              # (m, K)
    # ends: (slot, i) with ok[i] != ok[i + 1] (circularly), bisected together
    ends = [(k, i) for k in range(K) for i in range(samples)
            if ok[i, k] != ok[(i + 1) % samples, k]]
    lo = np.array([grid[i] for _, i in ends])
    hi = lo + 2 * np.pi / samples
    inside_lo = np.array([ok[i, k] for k, i in ends], bool)
    slots = np.array([k for k, _ in ends], int)
    for _ in range(HALVINGS if ends else 0):
        mid = 0.5 * (lo + hi)
        f = _feasible(_solve(robot, T, mid), slots)
        same = f == inside_lo                                  # mid on lo's side
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    edge = np.where(inside_lo, lo, hi)                         # the feasible side of each end
    outside = np.where(inside_lo, hi, lo)
    why = _limits_at(robot, T, outside, slots) if ends else []
    out = []
    for k in range(K):
        if not sv.valid[:, k].any():
            continue
        label = next(lab for lab, v in zip(sv.labels[:, k], sv.valid[:, k]) if v)
        mine = [e for e, (kk, _) in enumerate(ends) if kk == k]
        if not mine:
            whole = bool(ok[:, k].all())
            out.append(SwivelRange(label, ((-np.pi, np.pi),) if whole else (),
                                   ((None, None),) if whole else ()))
            continue
        starts = [e for e in mine if not inside_lo[e]]         # infeasible -> feasible
        stops = [e for e in mine if inside_lo[e]]
        intervals, bounds = [], []
        for s in starts:
            later = [e for e in stops if edge[e] > edge[s]] or stops   # the next stop, circularly
            t = min(later, key=lambda e: (edge[e] - edge[s]) % (2 * np.pi))
            a = float(wrap(edge[s]))
            intervals.append((a, a + (edge[t] - edge[s]) % (2 * np.pi)))
            bounds.append((why[s], why[t]))
        order = np.argsort([a for a, _ in intervals])
        out.append(SwivelRange(label, tuple(intervals[i] for i in order),
                               tuple(bounds[i] for i in order)))
    return out


def nearest_swivel(robot, T, near, samples: int = SAMPLES):
    """The branch and swivel angle whose solution is nearest the current joints ``near
    (7,)`` (rad): the least change (:func:`~kincalc.analysis.redundancy.least_change`),
    among solutions within the limits; the angle found on the sampled circle, then refined seven times on 33 angles
    around it (to ``2 pi / samples / 16^7``, 3e-11 rad).

    Returns
    -------
    (label, psi (rad), q (7,), change (7,)), or None when no branch is feasible at any
    sampled angle.
    """
    from .redundancy import least_change

    def best(psi, slots=None):
        sv = _solve(robot, T, psi)
        ok = sv.valid & sv.within
        if slots is not None:
            ok &= np.arange(ok.shape[1]) == slots
        found = least_change(robot, sv.q, ok, near)
        if found is None:
            return None
        (i, k), q, _ = found
        return k, float(psi[i]), q, sv.labels[i, k]
    grid = -np.pi + 2 * np.pi * np.arange(samples) / samples
    found = best(grid)
    if found is None:
        return None
    step = 2 * np.pi / samples
    for _ in range(7):
        k, psi = found[0], found[1]
        found = best(psi + np.linspace(-step, step, 33), k) or found
        step /= 16
    k, psi, q, label = found
    return label, float(wrap(psi)), q, q - np.asarray(near, float)


def _limits_at(robot, T, psi, slots) -> list:
    """Per end: ``(joint, side)`` of the limit the solution in ``slot`` breaks just
    outside the interval (the largest violation), or None where it does not exist."""
    sv = _solve(robot, T, psi)
    rows = np.arange(len(psi))
    out = []
    for r, k in zip(rows.tolist(), slots.tolist()):
        if not sv.valid[r, k]:
            out.append(None)
            continue
        v = sv.violation[r, k]
        j = int(np.argmax(np.abs(v)))
        out.append((j, "lower" if v[j] < 0 else "upper") if v[j] != 0 else None)
    return out


def swivel_document(robot, target, ranges, units, near=None) -> dict:
    """The JSON document of ``kincalc ik --swivel-range`` in the display ``units``; with
    the current joints ``near (7,)`` (rad), ``nearest`` (:func:`nearest_swivel`)."""
    from .results import json_header, json_numbers
    u = units
    names = [j.name for j in robot.joints]
    deg = lambda x: json_numbers(x * u.a)  # noqa: E731
    side = lambda b: None if b is None else {"joint": names[b[0]], "side": b[1]}  # noqa: E731
    out = json_header("ik", robot, u)
    out["target"] = {"T": u.pose(target.T), "orientation_given": True}
    out["method"] = {"family": "srs-swivel", "samples": SAMPLES,
                     "description": "the stereographic SEW angle (Elias & Wen 2023); each "
                                    "branch sampled at every 0.5 deg, the ends of its "
                                    "feasible intervals located by bisection"}
    out["reachable"] = any(r.intervals for r in ranges)
    out["branches"] = [
        {"branch": r.label,
         "intervals": [{"from": deg(a),
                        "to": deg(float(wrap(b)) if b > np.pi else b),
                        "through_180": bool(b > np.pi), "from_limit": side(x),
                        "to_limit": side(y)} for (a, b), (x, y) in zip(r.intervals, r.bounds)],
         "whole_circle": r.intervals == ((-np.pi, np.pi),)}
        for r in ranges]
    if near is not None:
        best = nearest_swivel(robot, target.T, near)
        out["nearest"] = None if best is None else {
            "branch": best[0], "swivel": deg(best[1]), "q": u.joints(robot, best[2]),
            "change": u.joints(robot, best[3])}
    return out
