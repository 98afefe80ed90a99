"""Grading an ``fk`` item: the tool pose as a matrix, a position, or a position with an
orientation in any of the sheet's forms, with the slips behind a wrong one."""

from __future__ import annotations

import numpy as np

from ..sheet import HINT_FACTOR, Item, Sheet, Tolerance
from ..slips import FULL_TRANSPOSE, MATRIX_SLIPS, compare_T, first_slip, fmt
from .common import ItemResult


_ANGLE_SETS = ("rpy", "euler_zyz", "euler_xyz")
_ANGLE_NAMES = {"rpy": "fixed X-Y-Z (roll, pitch, yaw)", "euler_zyz": "Z-Y-Z Euler",
                "euler_xyz": "moving X-Y-Z Euler"}


def _rotation_from(kind: str, values, units) -> np.ndarray:
    """The rotation ``(3, 3)`` of an orientation answer of ``kind`` in the sheet's units,
    built by :mod:`kincalc.ik.target` as a pose's is; NaN for a degenerate answer (a zero
    quaternion or axis)."""
    from ...analysis.requests import to_si
    from ...ik.target import targets_from
    v = np.asarray(values, float)
    if kind == "matrix":
        return v
    targets, defect = targets_from(kind, to_si(kind, v.reshape(1, -1), units))
    return np.full((3, 3), np.nan) if defect[0] is not None else targets.T[0, :3, :3]


def _fk_errors(answer: dict, T: np.ndarray, units, q_last: float = 0.0) -> dict:
    """Per given part of an fk ``answer``: the error in sheet units (``q_last``: the
    last joint's value, rad, for a tool configuration vector)."""
    from ...spatial import rotation_error, tcv_from_transform
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


def grade_fk(sheet: Sheet, item: Item) -> ItemResult:
    robot, units, tol = sheet.robot, sheet.units, item.tol
    T = robot.fk(item.q)
    err = _fk_errors(item.answer, T, units, item.q[-1])
    details = {"expected": units.pose(T), "errors": err}
    if "tcv" in item.answer:                  # (the vector the answer is compared with)
        from ...spatial import tcv_from_transform
        w = tcv_from_transform(T, item.q[-1])
        details["expected_tcv"] = [*(w[:3] * units.l).tolist(), *w[3:].tolist()]
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
    hint = first_slip(sheet, item, fits, forms=forms)
    if hint is None and not fits(robot, item.q, None):      # (as first_slip: nearly right)
        hint = _angle_set_slip(item.answer, T, tol, units)
    wrong = [k for k, v in err.items() if not _fk_ok({k: v}, tol, units)]
    return ItemResult(item.id, "fk", False, item.points, error,
                      f"T_0^{robot.dof} is wrong: {' and '.join(wrong)} off "
                      f"(differences: {parts})", hint, details)


def _angle_set_slip(answer: dict, T, tol, units) -> str | None:
    """The student's three angles read in another convention, order or unit."""
    from ...spatial import rotation_error
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
