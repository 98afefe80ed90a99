"""Grading a sheet (:func:`grade`): every item against kincalc's own forward
kinematics, IK, Jacobian and reach analysis, with a hint from the slips behind a wrong
answer (:mod:`kincalc.homework.slips`). Values are SI inside; reports convert back to the
sheet's units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import KincalcError, TargetMismatch
from ..limits import quote
from ..analysis.results import json_numbers
from .sheet import (DH_SAMPLES, HINT_FACTOR, MIX_FACTOR, SHEET_WORDS, Item, Sheet, SheetError,
                    Tolerance, sheet_words)
from .slips import (FULL_TRANSPOSE, MATRIX_SLIPS, compare_T, display_q, first_slip, fmt,
                    joint_label, q_slips)

@dataclass
class ItemResult:
    id: str
    kind: str
    passed: bool
    points: float
    error: float | None
    message: str
    hint: str | None = None
    details: dict = field(default_factory=dict)
    line: int | None = None

    def to_dict(self) -> dict:
        return {"id": self.id, "kind": self.kind, "passed": self.passed, "points": self.points,
                "error": self.error, "message": self.message, "hint": self.hint,
                "line": self.line, "details": self.details}


@dataclass
class Report:
    sheet: Sheet
    items: list

    @property
    def score(self) -> dict:
        total = sum(r.points for r in self.items)
        got = sum(r.points for r in self.items if r.passed)
        return {"points": got, "total": total,
                "percent": round(100.0 * got / total, 1) if total else 100.0,
                "correct": sum(r.passed for r in self.items), "items": len(self.items)}

    @property
    def all_correct(self) -> bool:
        return all(r.passed for r in self.items)

    def to_dict(self) -> dict:
        from ..analysis.results import json_header
        s = self.sheet
        out = json_header("check", s.robot, s.units)
        out.update({"sheet": s.path, "title": s.title, "student": s.student,
                    "tolerance": s.tolerance.to_dict(s.units),
                    "items": [r.to_dict() for r in self.items], "score": self.score})
        return out


# --- grading -----------------------------------------------------------------------

def grade(sheet: Sheet) -> Report:
    """Grade every item of ``sheet``; never raises for a wrong answer."""
    results = []
    for item in sheet.items:
        if item.answer is None:
            r = ItemResult(item.id, item.kind, False, item.points, None, "no answer given")
        else:
            try:
                r = _GRADERS[item.kind](sheet, item)
            except SheetError:
                raise
            except KincalcError as exc:   # e.g. a pose this robot cannot be asked for
                text = exc.words(SHEET_WORDS) if isinstance(exc, TargetMismatch) \
                    else sheet_words(str(exc))
                raise SheetError(sheet.path, item.line, f"item {quote(item.id)}: {text}") from None
        r.line = item.line
        results.append(r)
    return Report(sheet=sheet, items=results)






def _gaps(robot, qa, qb) -> np.ndarray:
    """Per-joint distance ``(n,)`` between joint vectors: angles modulo 2 pi (rad), m."""
    from ..spatial import wrap
    d = np.asarray(qa, float) - np.asarray(qb, float)
    return np.where(robot.is_revolute, np.abs(wrap(d)), np.abs(d))




def _unit_suffix(units, what: str) -> str:
    if what == "angle":
        return " deg" if units.angle == "deg" else " rad"
    return "" if units.length == "unitless" else f" {units.length}"


# link ---------------------------------------------------------------------------

def _grade_link(sheet: Sheet, item: Item) -> ItemResult:
    robot, units, tol = sheet.robot, sheet.units, item.tol
    i = item.link - 1
    T = robot.link_transforms(item.q)[i]
    A = item.answer
    ok, rot, pos = compare_T(A, T, tol, units)
    details = {"expected": units.pose(T), "rotation_error": rot, "translation_error": pos,
               "link": item.link}
    name = f"T_{item.link - 1}^{item.link}"
    if ok:
        return ItemResult(item.id, "link", True, item.points, max(rot, pos),
                          f"{name} is right", details=details)

    def fits(rob, q, form):
        M = rob.link_transforms(q)[i]
        if form == FULL_TRANSPOSE:
            return A.shape == (4, 4) and compare_T(A.T, M, tol, units, HINT_FACTOR)[0]
        if form is not None:
            M = form(M)
        return compare_T(A, M, tol, units, HINT_FACTOR)[0]
    forms = MATRIX_SLIPS + ((FULL_TRANSPOSE, FULL_TRANSPOSE),)
    hint = first_slip(sheet, item, fits, joints=[i], forms=forms)
    return ItemResult(item.id, "link", False, item.points, max(rot, pos),
                      f"{name} is wrong: largest difference {fmt(rot)} in the rotation, "
                      f"{fmt(pos)} in the translation", hint, details)


# fk ---------------------------------------------------------------------------------

_ANGLE_SETS = ("rpy", "euler_zyz", "euler_xyz")
_ANGLE_NAMES = {"rpy": "fixed X-Y-Z (roll, pitch, yaw)", "euler_zyz": "Z-Y-Z Euler",
                "euler_xyz": "moving X-Y-Z Euler"}


def _rotation_from(kind: str, values, units) -> np.ndarray:
    """The rotation ``(3, 3)`` of an orientation answer of ``kind`` in the sheet's units,
    built by :mod:`kincalc.ik.target` as a pose's is; NaN for a degenerate answer (a zero
    quaternion or axis)."""
    from ..ik.target import targets_from, to_si
    v = np.asarray(values, float)
    if kind == "matrix":
        return v
    targets, defect = targets_from(kind, to_si(kind, v.reshape(1, -1), units))
    return np.full((3, 3), np.nan) if defect[0] is not None else targets.T[0, :3, :3]


def _fk_errors(answer: dict, T: np.ndarray, units, q_last: float = 0.0) -> dict:
    """Per given part of an fk ``answer``: the error in sheet units (``q_last``: the
    last joint's value, rad, for a tool configuration vector)."""
    from ..spatial import rotation_error, tcv_from_transform
    out = {}
    if "tcv" in answer:
        w = tcv_from_transform(T, q_last)
        out["position"] = float(np.linalg.norm(answer["tcv"][:3] - w[:3] * units.l))
        out["tcv"] = float(np.max(np.abs(answer["tcv"][3:] - w[3:])))
    if "T" in answer:
        _, rot, pos = compare_T(answer["T"], T, Tolerance(1, 1, 1), units)
        out["matrix"], out["position"] = rot, pos
    if "position" in answer:
        out["position"] = float(np.linalg.norm(answer["position"] - T[:3, 3] * units.l))
    for k in ("rpy", "euler_zyz", "euler_xyz", "quat", "axis_angle", "matrix"):
        if k in answer and not ("T" in answer and k == "matrix"):
            if k == "matrix":
                out["matrix"] = float(np.max(np.abs(answer[k] - T[:3, :3])))
            else:
                R = _rotation_from(k, answer[k], units)
                out["orientation"] = float(rotation_error(R, T[:3, :3])) * units.a
    return out


def _fk_ok(err: dict, tol: Tolerance, units, factor=1.0) -> bool:
    limits = {"position": tol.position * units.l, "matrix": tol.matrix, "tcv": tol.matrix,
              "orientation": tol.angle * units.a}
    return all(v <= limits[k] * factor for k, v in err.items())


def _grade_fk(sheet: Sheet, item: Item) -> ItemResult:
    robot, units, tol = sheet.robot, sheet.units, item.tol
    T = robot.fk(item.q)
    err = _fk_errors(item.answer, T, units, item.q[-1])
    details = {"expected": units.pose(T), "errors": err}
    parts = ", ".join(f"{k} {fmt(v)}" for k, v in err.items())
    error = max(err.values()) if err else None
    if _fk_ok(err, tol, units):
        return ItemResult(item.id, "fk", True, item.points, error,
                          f"T_0^{robot.dof} is right (differences: {parts})", details=details)

    def fits(rob, q, form):
        M = rob.fk(q)
        answer = item.answer
        if form == FULL_TRANSPOSE:
            if "T" not in answer or answer["T"].shape != (4, 4):
                return False
            answer = dict(answer, T=answer["T"].T)
        elif form is not None:
            M = form(M)
        return _fk_ok(_fk_errors(answer, M, units, q[-1]), tol, units, HINT_FACTOR)
    forms = MATRIX_SLIPS + ((FULL_TRANSPOSE, FULL_TRANSPOSE),)
    hint = first_slip(sheet, item, fits, forms=forms) or _angle_set_slip(item.answer, T, tol, units)
    wrong = [k for k, v in err.items() if not _fk_ok({k: v}, tol, units)]
    return ItemResult(item.id, "fk", False, item.points, error,
                      f"T_0^{robot.dof} is wrong: {' and '.join(wrong)} off "
                      f"(differences: {parts})", hint, details)


def _angle_set_slip(answer: dict, T, tol, units) -> str | None:
    """The student's three angles read in another convention, order or unit."""
    from ..spatial import rotation_error
    given = [k for k in _ANGLE_SETS if k in answer]
    if not given:
        return None
    k = given[0]
    v = np.asarray(answer[k], float)
    tries = []
    for other in _ANGLE_SETS:
        for order, label in ((v, ""), (v[::-1], " in reverse order")):
            if other == k and not label:
                continue
            tries.append((other, order, f"your {_ANGLE_NAMES[k]} angles are the "
                          f"{_ANGLE_NAMES[other]} angles{label} of the right orientation"))
    if units.angle == "deg":
        tries.append((k, np.degrees(v), "your angles fit in radians: the sheet's unit is degrees"))
    for kind, values, hint in tries:
        R = _rotation_from(kind, values, units)
        if rotation_error(R, T[:3, :3]) * units.a <= tol.angle * units.a * HINT_FACTOR:
            return hint
    return None


# jacobian ----------------------------------------------------------------------------

def _grade_jacobian(sheet: Sheet, item: Item) -> ItemResult:
    from ..analysis.reports import jacobian_report
    robot, units, tol = sheet.robot, sheet.units, item.tol
    n = robot.dof
    A = item.answer

    def expected(rob, q, frame):
        rep = jacobian_report(rob, q, units, frame=frame)
        return np.array(rep._display_J(rep.J))

    J = expected(robot, item.q, item.frame)
    lin_tol, ang_tol = tol.position * units.l, tol.matrix

    def score(Jx, factor=1.0, A=A):
        """(ok, error, row order) of the answer ``A`` against the 6 x n ``Jx``."""
        if A.shape == (6, n):
            best = None
            for order, lin_rows, ang_rows in (("vx vy vz wx wy wz", A[:3], A[3:]),
                                              ("wx wy wz vx vy vz", A[3:], A[:3])):
                lin = float(np.max(np.abs(lin_rows - Jx[:3])))
                ang = float(np.max(np.abs(ang_rows - Jx[3:])))
                cand = (lin <= lin_tol * factor and ang <= ang_tol * factor, max(lin, ang), order)
                if best is None or (cand[0], -cand[1]) > (best[0], -best[1]):
                    best = cand
            return best
        if A.shape == (3, n):
            e = float(np.max(np.abs(A - Jx[:3])))
            if e <= lin_tol * factor:
                return True, e, "vx vy vz"
            el = float(np.max(np.abs(A[:2] - Jx[:2])))     # a planar arm's [vx; vy; wz]
            ea = float(np.max(np.abs(A[2] - Jx[5])))
            if el <= lin_tol * factor and ea <= ang_tol * factor:
                return True, max(el, ea), "vx vy wz"
            return False, e, "vx vy vz"
        if A.shape == (2, n):
            e = float(np.max(np.abs(A - Jx[:2])))
            return e <= lin_tol * factor, e, "vx vy"
        return False, float("inf"), "transposed"

    ok, error, order = score(J)
    details = {"expected": J.tolist(), "frame": item.frame, "rows": order}
    if ok:
        return ItemResult(item.id, "jacobian", True, item.points, error,
                          f"J ({item.frame} frame) is right; rows read as {order}", details=details)
    if order == "transposed":
        ok_t = score(J, 1.0, A.T)[0]
        hint = "this is the transpose of J (n x 6): J has one column per joint" + \
            (" — transposed back it is right" if ok_t else "")
        return ItemResult(item.id, "jacobian", False, item.points, None,
                          f"J must be 6 x {n} (rows vx vy vz wx wy wz),"
                          f" not {n} x 6", hint, details)

    def fits(rob, q, form):
        Jx = expected(rob, q, form or item.frame)
        return score(Jx, HINT_FACTOR)[0]
    if n == 6 and score(J, 1.0, A.T)[0]:
        return ItemResult(item.id, "jacobian", False, item.points, error,
                          f"J ({item.frame} frame) is wrong: largest difference {fmt(error)}",
                          "this is the transpose of J: J has one column per joint", details)
    other = "tool" if item.frame == "base" else "base"
    hint = first_slip(sheet, item, fits,
                       forms=[(f"fits J in the {other} frame; the item asks for the "
                               f"{item.frame} frame", other)])
    if hint is None and units.angle == "deg" and score(J * math.pi / 180, HINT_FACTOR)[0]:
        hint = "fits J per degree: the Jacobian maps joint rates in rad/s"
    return ItemResult(item.id, "jacobian", False, item.points, error,
                      f"J ({item.frame} frame) is wrong: largest difference {fmt(error)}",
                      hint, details)


# singular and reach --------------------------------------------------------------

def _yes(b: bool) -> str:
    return "yes" if b else "no"


def _grade_singular(sheet: Sheet, item: Item) -> ItemResult:
    from ..analysis.reports import jacobian_report
    rep = jacobian_report(sheet.robot, item.q, sheet.units)
    truth = rep.singular
    why = ("; ".join(rep.singularity.descriptions) if truth else
           f"the Jacobian has full rank {rep.rank} (smallest normalised singular value "
           f"{fmt(rep.sigma_normalised[-1])})")
    passed = item.answer == truth
    msg = f"singular: {_yes(truth)} — {why}"
    details = {"expected": truth, "rank": rep.rank, "generic_rank": rep.generic_rank}
    return ItemResult(item.id, "singular", passed, item.points, None,
                      ("right; " if passed else f"wrong (answer {_yes(item.answer)}); ") + msg,
                      details=details)


def _grade_reach(sheet: Sheet, item: Item) -> ItemResult:
    from ..analysis.reach import reach
    r = reach(sheet.robot, item.target, units=sheet.units)
    passed = item.answer == r.reachable
    details = {"expected": r.reachable, "verdict": r.verdict,
               "distance": None if r.distance is None else r.distance * sheet.units.l}
    return ItemResult(item.id, "reach", passed, item.points, None,
                      ("right; " if passed else f"wrong (answer {_yes(item.answer)}); ")
                      + f"reachable: {_yes(r.reachable)} — {r.verdict}: {r.reason}",
                      details=details)


# ik -------------------------------------------------------------------------------

def _target_residual(robot, target, q) -> tuple[float, float | None]:
    """(position error (m), orientation error (rad) or None) of joints ``q`` for ``target``."""
    from ..spatial import wrap
    from ..spatial import rotation_error
    T = robot.fk(q)
    pe = float(np.linalg.norm(T[:3, 3] - target.T[:3, 3]))
    if target.tcv is not None:
        a, qn = target.tcv
        oe = max(float(np.arccos(np.clip(T[:3, 2] @ a, -1, 1))), abs(float(wrap(q[-1] - qn))))
    elif target.approach is not None:
        oe = float(np.arccos(np.clip(T[:3, 2] @ target.approach, -1, 1)))
    elif target.orientation:
        oe = float(rotation_error(T[:3, :3], target.T[:3, :3]))
    else:
        oe = None
    return pe, oe


def _grade_ik(sheet: Sheet, item: Item) -> ItemResult:
    from ..ik.solve import solve, violation_list
    from ..analysis.words import reason_text
    robot, units, tol = sheet.robot, sheet.units, item.tol
    rev = robot.is_revolute
    res = solve(robot, item.target, all_branches=True, units=units)
    sols = res.solutions
    required = [k for k, s in enumerate(sols) if s.within_limits or not item.limits]
    # a numerical solver finds one solution, not all: the sets are then checked by FK
    # alone, and nothing can be called missed (unless the answer says "unreachable")
    exhaustive = res.family != "numerical"
    if not exhaustive and item.answer:
        required = []
    jtol = np.where(rev, tol.angle, tol.position)

    def close(qa, qb):
        return bool(np.all(_gaps(robot, qa, qb) <= jtol))

    def sol_dict(k):
        s = sols[k]
        return {"solution": k + 1, "solution_q": json_numbers(display_q(robot, s.q, units)),
                "branch": s.branch,
                "within_limits": s.within_limits, "singular": s.singular}

    sets, matched, worst = [], {}, 0.0
    for number, (line, q) in enumerate(item.answer, start=1):
        pe, oe = _target_residual(robot, item.target, q)
        worst = max(worst, pe * units.l)
        entry = {"set": number, "line": line, "q": json_numbers(display_q(robot, q, units)),
                 "residual": {"position": pe * units.l,
                              "orientation": None if oe is None else oe * units.a}}
        hit = next((k for k in range(len(sols)) if close(q, sols[k].q)), None) \
            if exhaustive else None
        reaches = pe <= tol.position and (oe is None or oe <= tol.angle)
        if hit is not None and hit in matched:
            entry.update(status="duplicate", note=f"the same solution as set {matched[hit]}",
                         **sol_dict(hit))
        elif hit is not None and hit in required:
            matched[hit] = number
            entry.update(status="correct", **sol_dict(hit))
        elif hit is not None:
            viol = ", ".join(f"{joint_label(robot, j)} beyond its {side} limit by "
                             f"{fmt(amount * (units.a if rev[j] else units.l))}"
                             for j, amount, side in (violation_list(robot, q) or sols[hit].violations))
            entry.update(status="wrong", note=f"reaches the target but is outside the joint "
                         f"limits ({viol}); the item counts only solutions within the limits",
                         **sol_dict(hit))
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
            entry.update(status="wrong", note=_ik_wrong_note(sheet, item, q, pe, oe, res, required))
        sets.append(entry)
    missed = [sol_dict(k) for k in required if k not in matched]
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
        notes.append("missed: " + "; ".join(f"{_fmt_q(m['solution_q'])} ({m['branch']})"
                                          for m in missed))
    hint = "; ".join(notes) or None
    details = {"sets": sets, "missed": missed, "solutions": len(sols), "required": len(required),
               "method": res.method}
    return ItemResult(item.id, "ik", passed, item.points, worst if sets else None, msg, hint,
                      details)


def _fmt_q(values) -> str:
    return "(" + ", ".join(fmt(v) for v in values) + ")"


def _ik_wrong_note(sheet, item, q, pe, oe, res, required) -> str:
    """Why a student's set misses: a textbook +/- combination, one joint off, a slip."""
    robot, units, tol = sheet.robot, sheet.units, item.tol
    rev = robot.is_revolute
    jtol = np.where(rev, tol.angle, tol.position)
    sols = res.solutions
    miss = f"FK misses the target by {fmt(pe * units.l)}{_unit_suffix(units, 'length')}"
    if oe is not None:
        miss += f" and {fmt(oe * units.a)}{_unit_suffix(units, 'angle')} in orientation"

    def diff(qa, qb):
        return _gaps(robot, qa, qb)

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
                if near is not s and diff(q, near.q)[j] <= MIX_FACTOR * jtol[j]:
                    borrowed.append(f"{robot.joints[j].name} is near the "
                                    f"{fmt(display_q(robot, near.q, units)[j])} of the {near.branch} "
                                    "solution")
            if borrowed and len(borrowed) == len(bad):
                note += f" ({'; '.join(borrowed)}: the set mixes branches)"
    for hint, rob, alt in q_slips(sheet, np.asarray(q, float)):
        if rob is not robot:
            continue
        if any(np.all(diff(alt, c.q) <= jtol * HINT_FACTOR) for c in cands):
            return f"{note}; your set {hint}"
    return note


# dh ---------------------------------------------------------------------------------

def _grade_dh(sheet: Sheet, item: Item) -> ItemResult:
    import dataclasses

    from ..analysis.compare import match
    robot, units, tol = sheet.robot, sheet.units, item.tol
    ans = item.answer
    cand = ans["robot"]
    conv = cand.convention
    if cand.dof != robot.dof:
        return ItemResult(item.id, "dh", False, item.points, None,
                          f"the table has {cand.dof} row{'s' if cand.dof != 1 else ''}; "
                          f"{robot.name} has {robot.dof} joints")
    kw = {"allow_offsets": True, "free_base": item.base == "ignore", "samples": DH_SAMPLES,
          "free_tool": item.tool == "ignore",
          "tol": max(1e-9, tol.position / robot.characteristic_length)}
    m = match(robot, cand, **kw)
    details = {"position_error": m.position_error * units.l,
               "orientation_error": m.orientation_error * units.a,
               "worst_q": display_q(robot, m.worst_q, units).tolist() if m.worst_q is not None else None}
    if m.same:
        signs = ans["signs"] * m.signs
        offsets = ans["signs"] * m.offsets
        used = []
        for i in range(robot.dof):
            scale = units.a if robot.is_revolute[i] else units.l
            ref = robot.joints[i].name
            text = ("" if signs[i] > 0 else "-") + ref
            off = offsets[i] * scale
            if abs(off) > 1e-9 * max(1.0, scale):
                text += f" {'+' if off > 0 else '-'} {fmt(abs(off))}"
            if text != ref:
                used.append(f"your {ans['variables'][i]} = {text.replace(ref, 'robot ' + ref)}")
        details.update(signs=json_numbers(signs), offsets=json_numbers(offsets * np.where(
            robot.is_revolute, units.a, units.l)), variables=ans["variables"])
        frames = [w for w, on in (("base", kw["free_base"]), ("tool", kw["free_tool"])) if on]
        msg = (f"right: the table describes {robot.name} (same FK at {DH_SAMPLES} random "
               "configurations" + (f", {' and '.join(frames)} frame ignored" if frames else "") + ")")
        msg += ("; with other joint zeros or directions: " + ", ".join(used)) if used else \
            "; same joint variables"
        return ItemResult(item.id, "dh", True, item.points, m.position_error * units.l, msg,
                          details=details)

    hint = None
    other = "mdh" if conv == "dh" else "dh"
    if match(robot, dataclasses.replace(cand, convention=other), **kw).same:
        hint = (f"these rows are a right {_CONV_SHORT[other]} table, but the answer says "
                f"convention: {conv} (standard and modified DH mixed up)")
    k = m.first_bad_joint
    n = robot.dof
    # the row that places joint k's axis: row k in modified DH (alpha_{k-1}, a_{k-1} then
    # z_k); row k - 1 in standard DH (z_{k-1} is set by the row before); the end frame
    # (k = n + 1) is the tool in modified DH and row n in standard DH
    row = None if k is None else (k if conv == "mdh" else k - 1)
    has_tool = not np.allclose(cand.tool, np.eye(4))
    details["first_bad_joint"] = k
    details["first_bad_row"] = row if row is not None and 1 <= row <= n else None
    if k is None:
        msg = f"wrong: {m.reason}"
    elif row == 0:
        msg = (f"wrong: the axis of joint 1 is not the robot's ({m.reason}): it is z0, "
               "the base frame's z axis")
    elif k <= n:
        msg = (f"wrong: row {row} is the first that disagrees: it places the axis of joint "
               f"{k} ({m.reason})")
    else:
        where = ("the tool transform" if conv == "mdh" or has_tool else f"row {n}")
        msg = ("wrong: every joint axis is right, but the end frame is not the robot's tool "
               f"frame: check {where} (tool position differs by up to "
               f"{fmt(m.position_error * units.l)}{_unit_suffix(units, 'length')})")
        if conv == "mdh" and not has_tool:
            hint = hint or ("the robot's tool frame is not the last joint's frame: add it as "
                            "'tool: {xyz: [...], rpy: [...]}' to the answer, or grade the axes "
                            "only with 'tool: ignore' on the item")
    if hint is None and k is not None:
        hint = _row_hint(robot, cand, min(row, n) if row else None, units, tol)
    return ItemResult(item.id, "dh", False, item.points, m.position_error * units.l, msg,
                      hint, details)


_CONV_SHORT = {"dh": "standard DH", "mdh": "modified DH"}


def _reference_table(robot, conv: str, fold_tool: bool):
    """The robot's own table in convention ``conv`` (None for poe robots); with
    ``fold_tool`` a standard-DH tool is folded into the last row where it fits."""
    from ..conventions import dh_to_mdh, mdh_to_dh
    if robot.convention == "poe":
        return None
    ref = robot if robot.convention == conv else \
        (dh_to_mdh(robot) if conv == "mdh" else mdh_to_dh(robot))
    if conv == "dh" and fold_tool and not np.allclose(ref.tool, np.eye(4)):
        ref = _fold_tool(ref) or ref
    return ref


def _row_hint(robot, cand, row, units, tol) -> str | None:
    """Where the answer's table first differs from the robot's own table, if at or
    before ``row`` (DH tables are not unique, so this is a hint, not the verdict)."""
    from ..spatial import wrap
    ref = _reference_table(robot, cand.convention, np.allclose(cand.tool, np.eye(4)))
    if ref is None:
        return None
    for k, (r, c) in enumerate(zip(ref.joints, cand.joints), start=1):
        if row is not None and k > row:
            break
        diffs = []
        if r.type != c.type:
            diffs.append(f"the joint is {r.type} there, {c.type} here")
        else:
            for f in ("alpha", "a", "d", "theta"):
                if (f == "theta" and r.revolute) or (f == "d" and not r.revolute):
                    continue              # the joint variable's own offset may differ
                rv, cv = getattr(r, f), getattr(c, f)
                angle = f in ("alpha", "theta")
                gap = abs(float(wrap(rv - cv))) if angle else abs(rv - cv)
                if gap > (tol.angle if angle else tol.position):
                    s = units.a if angle else units.l
                    diffs.append(f"{f} = {fmt(rv * s)} there, {fmt(cv * s)} here")
        if diffs:
            return (f"compare row {k} with the robot's own {_CONV_SHORT[cand.convention]} "
                    f"table ({'; '.join(diffs)}); that table has row {k}: "
                    f"{_reference_row(ref, k, units)}")
    return None


def _reference_row(ref, k: int, units) -> str:
    """Row ``k`` (1-based) of the dh/mdh robot ``ref``'s table, as text."""
    j = ref.joints[k - 1]
    var = j.name
    th = fmt(j.theta * units.a)
    d = fmt(j.d * units.l)
    theta = (var + (f" + {th}" if j.theta else "")) if j.revolute else th
    dd = (var + (f" + {d}" if j.d else "")) if not j.revolute else d
    return (f"theta = {theta}, d = {dd}, a = {fmt(j.a * units.l)}, "
            f"alpha = {fmt(j.alpha * units.a)}")


def _fold_tool(robot):
    """The standard-DH ``robot`` with a tool of the form Tz(d) Rz(th) Tx(a) Rx(alpha)
    folded into its last row, so that frame n is the tool frame; None if it is not."""
    import dataclasses

    from ..spatial import rot_x, rot_z, transform
    T = robot.tool
    R = T[:3, :3]
    alpha = math.atan2(R[2, 1], R[2, 2])
    theta = math.atan2(R[1, 0], R[0, 0])
    if abs(R[2, 0]) > 1e-9:
        return None
    d = T[2, 3]
    a = math.hypot(T[0, 3], T[1, 3])
    if a > 1e-12:
        theta = math.atan2(T[1, 3], T[0, 3])
        alpha = math.atan2(R[2, 1], R[2, 2])
    rebuilt = transform(rot_z(theta), [0, 0, d]) @ transform(rot_x(alpha), [a, 0, 0])
    if not np.allclose(rebuilt, T, atol=1e-9):
        return None
    last = robot.joints[-1]
    # Rz(th0 + q) Tz(d0) Tx(a0) Rx(al0) with a0 = al0 = 0 (frame n of mdh_to_dh) then the tool
    if abs(last.a) > 1e-12 or abs(last.alpha) > 1e-12:
        return None
    joint = dataclasses.replace(last, theta=last.theta + theta, d=last.d + d, a=a, alpha=alpha)
    return dataclasses.replace(robot, joints=robot.joints[:-1] + (joint,), tool=np.eye(4))


_GRADERS = {"dh": _grade_dh, "link": _grade_link, "fk": _grade_fk, "ik": _grade_ik,
            "jacobian": _grade_jacobian, "reach": _grade_reach, "singular": _grade_singular}
