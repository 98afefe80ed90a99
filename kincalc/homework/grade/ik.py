"""Grading an ``ik`` item: every solution the student lists checked by FK, the
solutions the student missed, and why a wrong one is wrong."""

from __future__ import annotations

import numpy as np

from ...analysis.results import json_numbers
from ..sheet import HINT_FACTOR, MIX_FACTOR, Item, Sheet
from ..slips import display_q, fmt, joint_label, q_slips
from .common import ItemResult, fmt_q, gaps, unit_suffix


def _target_residual(robot, target, q) -> tuple[float, float | None]:
    """(position error (m), orientation error (rad) or None) of joints ``q`` for ``target``."""
    from ...spatial import rotation_error
    T = robot.fk(q)
    pe = float(np.linalg.norm(T[:3, 3] - target.T[:3, 3]))
    if target.tcv is not None:          # (its last joint is e^(q_n / pi): not modulo a turn)
        a, qn = target.tcv
        oe = max(float(np.arccos(np.clip(T[:3, 2] @ a, -1, 1))), abs(float(q[-1] - qn)))
    elif target.approach is not None:
        oe = float(np.arccos(np.clip(T[:3, 2] @ target.approach, -1, 1)))
    elif target.orientation:
        oe = float(rotation_error(T[:3, :3], target.T[:3, :3]))
    else:
        oe = None
    return pe, oe


def _gaps(robot, target, qa, qb) -> np.ndarray:
    """:func:`~.common.gaps` of two joint vectors for ``target``: a tool configuration
    vector's last joint is its own value, not one modulo a turn (``e^(q_n / pi)``)."""
    out = gaps(robot, qa, qb)
    if target.tcv is not None:
        out[-1] = abs(float(qa[-1]) - float(qb[-1]))
    return out


def grade_ik(sheet: Sheet, item: Item) -> ItemResult:
    """Every answered joint set checked by FK and matched to the solutions the item requires
    (within the limits unless the item says otherwise); the required ones not listed are
    missed."""
    from ...ik.solve import solve
    robot, units = sheet.robot, sheet.units
    if item.lock:
        from ...analysis.redundancy import solve_locked
        res = solve_locked(robot, item.target, dict(item.lock), all_branches=True, units=units)
    else:
        res = solve(robot, item.target, all_branches=True, units=units)
    sols = res.solutions
    required = [k for k, s in enumerate(sols) if s.within_limits or not item.limits]
    # a numerical solver finds one solution, not all: the sets are then checked by FK
    # alone, and nothing can be called missed (unless the answer says "unreachable")
    exhaustive = res.family != "numerical"
    if not exhaustive and item.answer:
        required = []
    sets, matched, worst = _judge_sets(sheet, item, res, required, exhaustive)
    missed = [_solution_entry(robot, sols[k], k, units) for k in required if k not in matched]
    passed, msg, hint = _summary(sheet, item, res, required, exhaustive, sets, missed)
    details = {"sets": sets, "missed": missed, "solutions": len(sols), "required": len(required),
               "method": res.method}
    return ItemResult(item.id, "ik", passed, item.points, worst if sets else None, msg, hint,
                      details)


def _solution_entry(robot, s, k: int, units) -> dict:
    """Solution ``k`` (0-based) of the engine's as the report shows it."""
    return {"solution": k + 1, "solution_q": json_numbers(display_q(robot, s.q, units)),
            "branch": s.branch, "within_limits": s.within_limits, "singular": s.singular}


def _judge_sets(sheet, item, res, required, exhaustive):
    """One entry per answered set (its residuals, status and note, and the solution it
    is), the solutions matched (index -> set number), and the worst position residual."""
    from ...ik.solve import violation_list
    robot, units, tol = sheet.robot, sheet.units, item.tol
    rev = robot.is_revolute
    sols = res.solutions
    jtol = np.where(rev, tol.angle, tol.position)
    sets, matched, worst = [], {}, 0.0
    for number, (line, q) in enumerate(item.answer, start=1):
        pe, oe = _target_residual(robot, item.target, q)
        worst = max(worst, pe * units.l)
        entry = {"set": number, "line": line, "q": json_numbers(display_q(robot, q, units)),
                 "residual": {"position": pe * units.l,
                              "orientation": None if oe is None else oe * units.a}}
        held = dict(item.lock)
        gap = gaps(robot, q, [held.get(j, x) for j, x in enumerate(q)])
        moved = [j for j in held if gap[j] > jtol[j]]
        if moved:
            entry.update(status="wrong", note="the item holds " + ", ".join(
                f"{joint_label(robot, j)} at {fmt(held[j] * (units.a if rev[j] else units.l))}"
                for j in moved) + "; this set moves it")
            sets.append(entry)
            continue
        hit = next((k for k in range(len(sols))
                    if np.all(_gaps(robot, item.target, q, sols[k].q) <= jtol)), None) \
            if exhaustive else None
        reaches = pe <= tol.position and (oe is None or oe <= tol.angle)
        if hit is not None and hit in matched:
            entry.update(status="duplicate", note=f"the same solution as set {matched[hit]}",
                         **_solution_entry(robot, sols[hit], hit, units))
        elif hit is not None and hit in required:
            matched[hit] = number
            entry.update(status="correct", **_solution_entry(robot, sols[hit], hit, units))
        elif hit is not None:
            viol = ", ".join(f"{joint_label(robot, j)} beyond its {side} limit by "
                             f"{fmt(amount * (units.a if rev[j] else units.l))}"
                             for j, amount, side
                             in (violation_list(robot, q) or sols[hit].violations))
            entry.update(status="wrong", note=f"reaches the target but is outside the joint "
                         f"limits ({viol}); the item counts only solutions within the limits",
                         **_solution_entry(robot, sols[hit], hit, units))
        elif reaches and not exhaustive:
            if item.limits and violation_list(robot, q):
                entry.update(status="wrong", note="reaches the target but is outside the "
                             "joint limits")
            else:
                entry.update(status="correct", note="reaches the target (checked by FK)")
        elif reaches:
            entry.update(status="correct", note="reaches the target (not one of the isolated "
                         "solutions: the target is at a singularity or your set is equivalent)")
        else:
            entry.update(status="wrong",
                         note=_ik_wrong_note(sheet, item, q, pe, oe, res, required))
        sets.append(entry)
    return sets, matched, worst


def _summary(sheet, item, res, required, exhaustive, sets, missed):
    """``(passed, message, hint)`` of an ik item from its judged sets."""
    from ...analysis.words import reason_text
    robot, units, sols = sheet.robot, sheet.units, res.solutions
    wrong = [s for s in sets if s["status"] == "wrong"]
    right = [s for s in sets if s["status"] == "correct"]
    passed = not wrong and not missed
    if not exhaustive and item.answer:
        truth = (f"{robot.name} has no closed-form IK in kincalc: each set is checked by FK, "
                 "and sets you did not list cannot be named")
    elif not sols:
        truth = f"the target is not reachable ({reason_text(res.reason, robot, units)})"
    else:
        truth = (f"the target has {len(required)} solution{'s' if len(required) != 1 else ''}"
                 + (" within the limits" if item.limits and len(required) != len(sols) else ""))
    if passed:
        msg = (f"right: {'all ' if len(right) > 1 else ''}{len(right)} solution "
               f"set{'s' if len(right) != 1 else ''} ({truth})" if sets else f"right: {truth}")
    else:
        parts = []
        if right:
            parts.append(f"{len(right)} right")
        if wrong:
            parts.append(f"{len(wrong)} wrong (set{'s' if len(wrong) > 1 else ''} "
                         f"{', '.join(str(s['set']) for s in wrong)})")
        if missed:
            parts.append(f"{len(missed)} missed")
        msg = f"{'; '.join(parts)}; {truth}"
    notes = [f"set {s['set']}: {s['note']}" for s in wrong]
    if missed:
        notes.append("missed: " + "; ".join(f"{fmt_q(m['solution_q'])} ({m['branch']})"
                                            for m in missed))
    return passed, msg, "; ".join(notes) or None


def _ik_wrong_note(sheet, item, q, pe, oe, res, required) -> str:
    """Why a student's set misses: a textbook +/- combination, one joint off, a slip."""
    robot, units, tol = sheet.robot, sheet.units, item.tol
    rev = robot.is_revolute
    jtol = np.where(rev, tol.angle, tol.position)
    sols = res.solutions
    miss = f"FK misses the target by {fmt(pe * units.l)}{unit_suffix(units, 'length')}"
    if oe is not None:
        miss += f" and {fmt(oe * units.a)}{unit_suffix(units, 'angle')} in orientation"

    def diff(qa, qb):
        return _gaps(robot, item.target, qa, qb)

    for rej in res.rejected or []:
        if np.all(diff(q, rej["q"]) <= jtol):
            return (f"{miss}: every value is one of the solutions' values, but this "
                    "combination of them is not a solution (a wrong pairing of the +/- roots, "
                    "as in Bingül & Küçük's Example 4.2)")
    note = miss
    cands = [sols[k] for k in required] or sols
    if cands:
        d = [diff(q, s.q) for s in cands]
        off = [np.flatnonzero(x > jtol) for x in d]
        best = min(range(len(cands)), key=lambda k: (len(off[k]), float(np.sum(d[k] / jtol))))
        s, bad = cands[best], off[best]
        if len(bad) < robot.dof:
            vals = ", ".join(f"{robot.joints[j].name} = {fmt(display_q(robot, s.q, units)[j])}"
                             for j in bad)
            note += (f"; closest solution ({s.branch}) differs only in "
                     f"{', '.join(robot.joints[j].name for j in bad)}: it has {vals}")
            borrowed = []
            for j in bad:
                near = min(cands, key=lambda c: diff(q, c.q)[j])
                gap = diff(q, near.q)[j]
                # (a value the closest solution shares, as its wrist twin does, is its own)
                if gap < d[best][j] and gap <= MIX_FACTOR * jtol[j]:
                    borrowed.append(f"{robot.joints[j].name} is near the "
                                    f"{fmt(display_q(robot, near.q, units)[j])} of the {near.branch} "
                                    "solution")
            if borrowed and len(borrowed) == len(bad):
                note += f" ({'; '.join(borrowed)}: the set mixes branches)"
    for hint, rob, alt in q_slips(sheet, np.asarray(q, float)):
        if rob is not robot:
            continue
        if any(np.all(diff(alt, c.q) <= jtol * HINT_FACTOR)
               and not np.all(diff(q, c.q) <= jtol * HINT_FACTOR) for c in cands):
            return f"{note}; your set {hint}"
    return note


# dh ---------------------------------------------------------------------------------
