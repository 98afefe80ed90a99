"""Numbers a student can type and answers that round-trip, for
:mod:`kincalc.homework.quiz`: joint values on a grid of whole degrees (or 0.01 rad,
three decimals of length), poses and matrices rounded to what is written."""

from __future__ import annotations

import math

import numpy as np

from .rules import SIGNIFICANT


# --- numbers a student can type, answers that round-trip ------------------------------

def number(x) -> float:
    """``x`` to :data:`SIGNIFICANT` digits, without a negative zero."""
    return float(f"{float(x):.{SIGNIFICANT}g}") + 0.0


def number_array(M) -> list:
    """Nested lists of :func:`number`; entries below 1e-12 of the largest are 0."""
    M = np.asarray(M, float)
    tiny = 1e-12 * max(1.0, float(np.max(np.abs(M))) if M.size else 1.0)
    M = np.where(np.abs(M) < tiny, 0.0, M)
    return [number_array(r) for r in M] if M.ndim > 1 else [number(x) for x in M]


def nice_number(x: float):
    """A whole number as an int (``90`` rather than ``90.0``), for tables."""
    return int(x) if float(x).is_integer() and abs(x) < 1e15 else x


def joint_grid(units, revolute: bool) -> tuple[float, int]:
    """(step, decimals) of typed joint values: 1 deg, 0.01 rad, 0.001 length unit."""
    if revolute:
        return (1.0, 0) if units.angle == "deg" else (0.01, 2)
    return 0.001, 3


def joint_range(robot, i: int, units) -> tuple[float, float]:
    """Range ``(lo, hi)`` of joint ``i`` in sheet units for random values: its limits,
    a revolute joint also within a half turn of zero, an unlimited prismatic one within
    the robot's size of zero."""
    lo, hi = robot.limits[i]
    if robot.joints[i].revolute:
        half = math.pi
        return max(lo, -half) * units.a, min(hi, half) * units.a
    L = robot.characteristic_length
    lo = lo if np.isfinite(lo) else min(-L, hi - 2 * L)
    hi = hi if np.isfinite(hi) else max(L, lo + 2 * L)
    return lo * units.l, hi * units.l


def typed_value(value: float, decimals: int):
    return int(round(value)) if decimals == 0 else round(float(value), decimals) + 0.0


def si_values(robot, shown, units) -> np.ndarray:
    """Joint values as written (sheet units) -> rad / m."""
    return np.asarray(shown, float) / np.where(robot.is_revolute, units.a, units.l)


def random_joints(robot, rng, units) -> tuple[list, np.ndarray]:
    """Random joints on the typing grid (see :func:`joint_grid`) within :func:`joint_range`.

    Returns ``(written values (n,) in sheet units, the same in rad / m)``.
    """
    shown = []
    for i, j in enumerate(robot.joints):
        step, dec = joint_grid(units, j.revolute)
        lo, hi = joint_range(robot, i, units)
        k_lo, k_hi = math.ceil(lo / step - 1e-9), math.floor(hi / step + 1e-9)
        if k_hi < k_lo:        # a range narrower than one step: its middle
            shown.append(number((lo + hi) / 2))
            continue
        shown.append(typed_value(int(rng.integers(k_lo, k_hi + 1)) * step, dec))
    return shown, si_values(robot, shown, units)


def pose_matrix(T, units) -> list:
    """A 4x4 pose as rows, translation in the sheet's length unit."""
    T = np.array(T, float)
    T[..., :3, 3] *= units.l
    return number_array(T)


def joint_text(robot, shown, units) -> str:
    return ", ".join(f"{j.name} = {v}" for j, v in zip(robot.joints, shown)) + \
        unit_note(robot, units)


def unit_note(robot, units) -> str:
    length = length_word(units)
    if robot.is_revolute.all():
        return f" ({units.angle})"
    return f" ({units.angle}{'' if not length else ', ' + length})"


def length_word(units) -> str:
    return "" if units.length == "unitless" else units.length


def lengths_in(units) -> str:
    return "lengths unitless" if units.length == "unitless" else f"lengths in {units.length}"
