"""Grading a ``jacobian`` item: the geometric Jacobian in the base or tool frame, column
by column, with the slips behind a wrong one."""

from __future__ import annotations

import math

import numpy as np

from ..sheet import HINT_FACTOR, Item, Sheet
from ..slips import first_slip, fmt
from .common import ItemResult


def grade_jacobian(sheet: Sheet, item: Item) -> ItemResult:
    from ...analysis.reports import jacobian_report
    robot, units, tol = sheet.robot, sheet.units, item.tol
    n = robot.dof
    A = item.answer

    def expected(rob, q, frame):
        rep = jacobian_report(rob, q, units, frame=frame)
        return rep.display_J(rep.J)

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
    if hint is None and units.angle == "deg" and score(J * math.pi / 180, HINT_FACTOR)[0] \
            and not fits(sheet.robot, item.q, None):
        hint = "fits J per degree: the Jacobian maps joint rates in rad/s"
    return ItemResult(item.id, "jacobian", False, item.points, error,
                      f"J ({item.frame} frame) is wrong: largest difference {fmt(error)}",
                      hint, details)


# singular and reach --------------------------------------------------------------
