"""The slips behind a wrong answer: what a student gets after a common mistake
(degrees read as radians, a joint's sign, two joints swapped, a transposed or inverted
matrix, standard and modified DH mixed up), tried against a wrong answer to name it in a
hint; and the number formats hints quote.
"""

from __future__ import annotations

import itertools

import numpy as np

from .sheet import Sheet, Tolerance


def fmt(x, digits: int = 4) -> str:
    if x is None:
        return "-"
    x = float(x)
    if x == 0 or 1e-3 <= abs(x) < 1e6:
        text = f"{x:.{digits}f}".rstrip("0").rstrip(".")
        return "0" if text in ("-0", "") else text
    return f"{x:.{digits - 1}e}"


def display_q(robot, q, units) -> np.ndarray:
    return np.asarray(q, float) * np.where(robot.is_revolute, units.a, units.l)


def joint_label(robot, i: int) -> str:
    return f"joint {i + 1} ({robot.joints[i].name})"


# slips: the answer a student gets after a common mistake --------------------------

def q_slips(sheet: Sheet, q: np.ndarray, joints=None):
    """``(hint, robot, q)`` for the joint-value slips: degrees and radians, one sign,
    two joints swapped, standard and modified DH mixed up. ``joints`` restricts the
    per-joint slips (a link transform depends on one joint only)."""
    robot, units = sheet.robot, sheet.units
    rev = robot.is_revolute
    joints = range(robot.dof) if joints is None else joints
    disp = display_q(robot, q, units)
    if rev.any():
        if units.angle == "deg":
            alt = np.where(rev, disp, q)
            yield ("fits the joint angles read as radians: the sheet's angles are in degrees "
                   "(is the calculator in radian mode?)", robot, alt)
        else:
            alt = np.where(rev, np.radians(disp), q)
            yield ("fits the joint angles read as degrees: the sheet's angles are in radians",
                   robot, alt)
    for i in joints:
        if q[i] != 0:
            alt = q.copy()
            alt[i] = -q[i]
            yield (f"fits {joint_label(robot, i)} with the opposite sign "
                   f"({fmt(-disp[i])} instead of {fmt(disp[i])}): check its direction",
                   robot, alt)
    for i, j in itertools.combinations(joints, 2):
        if rev[i] == rev[j] and q[i] != q[j]:
            alt = q.copy()
            alt[[i, j]] = q[[j, i]]
            yield (f"fits the values of {joint_label(robot, i)} and {joint_label(robot, j)} swapped",
                   robot, alt)
    if robot.convention in ("dh", "mdh"):
        import dataclasses
        other = "mdh" if robot.convention == "dh" else "dh"
        yield (f"fits the same table evaluated as {_CONV[other]} instead of {_CONV[robot.convention]}"
               " (standard and modified DH mixed up)",
               dataclasses.replace(robot, convention=other), q)


_CONV = {"dh": "standard DH (Rz(θ) Tz(d) Tx(a) Rx(α))",
         "mdh": "modified DH (Rx(α) Tx(a) Rz(θ) Tz(d))"}


def _transpose_rotation(M: np.ndarray) -> np.ndarray:
    Mt = np.array(M, float)
    Mt[:3, :3] = Mt[:3, :3].T
    return Mt


def _invert(M: np.ndarray) -> np.ndarray:
    from ..spatial import invert_transform
    return invert_transform(M)


#: ``(hint, f)``: a right 4x4 ``M`` becomes ``f(M)`` after the slip
MATRIX_SLIPS = (
    ("fits the right matrix with its rotation part transposed", _transpose_rotation),
    ("fits the inverse of the right matrix (the transform in the other direction)", _invert),
)


def compare_T(answer: np.ndarray, T: np.ndarray, tol: Tolerance, units, factor: float = 1.0):
    """(ok, rotation entry error, translation entry error in sheet units) for a 4x4 or
    3x4 ``answer`` (sheet units) against ``T`` (SI)."""
    Td = np.array(T, float)
    Td[:3, 3] *= units.l
    rot = float(np.max(np.abs(answer[:3, :3] - Td[:3, :3])))
    pos = float(np.max(np.abs(answer[:3, 3] - Td[:3, 3])))
    ok = rot <= tol.matrix * factor and pos <= tol.position * units.l * factor
    return ok, rot, pos


FULL_TRANSPOSE = "fits the right matrix transposed (rows written as columns)"


def first_slip(sheet, item, check_variant, joints=None, forms=()):
    """The first slip whose result fits the answer (``check_variant(robot, q, form)``), or
    None, as where the right result fits it as well: a slip that leaves the result as it is
    (the sign of a joint the quantity does not depend on, a row both conventions write
    alike) or nearly explains nothing of an answer that is only a little off."""
    if check_variant(sheet.robot, item.q, None):
        return None
    for hint, robot, q in q_slips(sheet, item.q, joints):
        if check_variant(robot, q, None):
            return hint
    for hint, form in forms:
        if check_variant(sheet.robot, item.q, form):
            return hint
    return None
