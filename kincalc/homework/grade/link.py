"""Grading a ``link`` item: one link transform ``T_{i-1}^i`` at the joint value the
sheet gives, with the slips behind a wrong matrix."""

from __future__ import annotations

from ..sheet import HINT_FACTOR, Item, Sheet
from ..slips import FULL_TRANSPOSE, MATRIX_SLIPS, compare_T, first_slip, fmt
from .common import ItemResult


def grade_link(sheet: Sheet, item: Item) -> ItemResult:
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
