"""The words of :mod:`kincalc.analysis.compare`: a :class:`~.match.Match` as one line of
reason and as the readable lines of the ``compare`` command, in display units.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .match import Match


def _fmt(x, precision=4) -> str:
    s = f"{x:.{precision}g}" if abs(x) >= 1e-4 or x == 0 else f"{x:.2e}"
    return "0" if s in ("-0", "0") else s


def reason_text(m: Match, reference, units, precision: int = 4) -> str:
    """The one-line reason of ``m`` in ``units`` (default: reference's length, degrees)."""
    if units is None:
        from ..results import Units
        units = Units(angle="deg", length=reference.length_unit)
    n = len(m.signs)
    a_unit = f" {units.angle}"
    l_unit = "" if units.length == "unitless" else f" {units.length}"

    def ang(x):
        return f"{_fmt(x * units.a, precision)}{a_unit}"

    def length(x):
        return f"{_fmt(x * units.l, precision)}{l_unit}"

    if m.same:
        changed = [i for i in range(n) if m.signs[i] < 0 or m.offsets[i] != 0]
        frames = [w for w, v in (("base", m.base), ("tool", m.tool)) if v is not None
                  and not np.allclose(v, np.eye(4), atol=1e-12)]
        text = "same robot"
        if changed:
            text += (" up to joint offsets and signs (joint"
                     f"{'s' * (len(changed) > 1)} {_join([str(i + 1) for i in changed])})")
        if frames:
            text += (" and " if changed else " up to ") + " and ".join(
                f"a different {w} frame" for w in frames)
        return text
    if m.kind in ("dof", "type"):
        return m.reason
    j = m.first_bad_joint
    tol_l, tol_a = m.tol * m.length_scale, m.tol
    hint = ("; with joint offsets and sign changes allowed they are the same robot"
            if m.hint_offsets else "")
    if j == n + 1:
        what = "every joint axis matches"
        if m.allow_offsets:
            what += " (with the offsets found)"
        if m.miss_angle is None:
            return f"{what}, but the tool frame differs{hint}"
        parts = []
        if m.miss_distance is not None and m.miss_distance > tol_l:
            parts.append(f"{length(m.miss_distance)} apart")
        if m.miss_angle > tol_a:
            parts.append(f"turned {ang(m.miss_angle)} from each other")
        detail = " and ".join(parts) or "by a tiny amount"
        return f"{what}, but the tool frames at the matched zero are {detail}{hint}"
    name = reference.joints[j - 1].name
    given = "" if j == 1 else (
        " given joint 1" if j == 2 else f" given joints 1-{j - 1}")
    if m.allow_offsets:
        head = f"joint {j} ({name}): its axis cannot be made to match the reference's{given}"
    else:
        head = (f"joint {j} ({name}): its axis differs from the reference's at the zero "
                "configuration")
    bits = []
    skew_lines = m.miss_angle is not None and tol_a < m.miss_angle < math.pi - tol_a
    if m.miss_angle is not None:
        if not m.allow_offsets and abs(m.miss_angle - math.pi) <= tol_a:
            bits.append("it points the opposite way")
        elif m.miss_angle > tol_a:
            bits.append(f"its direction is off by {ang(m.miss_angle)}")
    if m.miss_distance is not None and m.miss_distance > tol_l:
        bits.append(f"it passes {length(m.miss_distance)} from the reference axis"
                    if skew_lines else f"it is {length(m.miss_distance)} away")
    best = " at best" if m.allow_offsets and j > 1 else ""
    detail = f":{best} {' and '.join(bits)}" if bits else ""
    return head + detail + hint


def _join(items):
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def describe(m: Match, reference, units, precision: int = 4) -> list[str]:
    """Readable lines about ``m`` in display ``units`` (a :class:`~kincalc.analysis.results.Units`).

    The first line is the reason; then, for each joint with an offset or a
    sign change, where the candidate's zero lies in the reference's joint
    values (candidate q_i = 0 is reference q_i = -signs[i] * offsets[i]) and
    whether it turns the other way; then the base and tool frames when free.
    """
    lines = [reason_text(m, reference, units, precision)]
    a_unit = f" {units.angle}"
    l_unit = "" if units.length == "unitless" else f" {units.length}"
    for i, j in enumerate(reference.joints):
        s, c = m.signs[i], m.offsets[i]
        if s > 0 and c == 0:
            continue
        zero = -s * c
        value = (f"{_fmt(zero * units.a, precision)}{a_unit}" if j.revolute
                 else f"{_fmt(zero * units.l, precision)}{l_unit}")
        bits = []
        if s < 0:
            bits.append("opposite sign")
        if c != 0:
            bits.append(f"candidate zero is at reference {j.name} = {value}")
        lines.append(f"joint {i + 1} ({j.name}): " + ", ".join(bits))
    from ...spatial import rpy_from_matrix
    for word, T in (("base", m.base), ("tool", m.tool)):
        if T is None:
            continue
        xyz = ", ".join(_fmt(v * units.l, precision) for v in T[:3, 3])
        rpy = ", ".join(_fmt(v * units.a, precision) for v in rpy_from_matrix(T[:3, :3]))
        rule = ("candidate = base * reference" if word == "base"
                else "candidate = reference * tool")
        lines.append(f"{word} ({rule}): xyz ({xyz}){l_unit}, rpy ({rpy}){a_unit}")
    return lines
