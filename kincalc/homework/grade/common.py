"""What every grader of :mod:`kincalc.homework.grade` shares: the result of an item and
of a sheet, the gaps between joint vectors, and small formatting helpers."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..sheet import Sheet
from ..slips import fmt


@dataclass(frozen=True)
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


def percent(got: float, total: float) -> float:
    """``100 * got / total`` to one decimal, never rounded to 100 (or 0) unless every
    point (or none) was earned: 99.992 % is 99.9, 0.04 % is 0.1; 100 for a total of 0."""
    if not total:
        return 100.0
    p = round(100.0 * got / total, 1)
    if got < total:
        p = min(p, 99.9)
    return max(p, 0.1) if got > 0 else p


@dataclass(frozen=True)
class Report:
    sheet: Sheet
    items: list

    @property
    def score(self) -> dict:
        total = sum(r.points for r in self.items)
        got = sum(r.points for r in self.items if r.passed)
        return {"points": got, "total": total, "percent": percent(got, total),
                "correct": sum(r.passed for r in self.items), "items": len(self.items)}

    @property
    def all_correct(self) -> bool:
        return all(r.passed for r in self.items)

    def to_dict(self) -> dict:
        from ...analysis.results import json_header
        s = self.sheet
        out = json_header("check", s.robot, s.units)
        out.update({"sheet": s.path, "title": s.title, "student": s.student,
                    "tolerance": s.tolerance.to_dict(s.units),
                    "items": [r.to_dict() for r in self.items], "score": self.score})
        return out


def gaps(robot, qa, qb) -> np.ndarray:
    """Per-joint distance ``(n,)`` between joint vectors: angles modulo 2 pi (rad), m."""
    from ...spatial import wrap
    d = np.asarray(qa, float) - np.asarray(qb, float)
    return np.where(robot.is_revolute, np.abs(wrap(d)), np.abs(d))


def unit_suffix(units, what: str) -> str:
    if what == "angle":
        return " deg" if units.angle == "deg" else " rad"
    return "" if units.length == "unitless" else f" {units.length}"


# link ---------------------------------------------------------------------------


def yes(b: bool) -> str:
    return "yes" if b else "no"


def fmt_q(values) -> str:
    return "(" + ", ".join(fmt(v) for v in values) + ")"
