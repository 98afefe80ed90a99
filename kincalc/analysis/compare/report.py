"""The ``compare`` command's result: a :class:`~.match.Match` with its display units
and the inputs to echo, and its JSON document.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .match import Match, match
from .words import describe, reason_text


@dataclass(frozen=True)
class CompareResult:
    """``kincalc compare``: the match of ``candidate`` against ``reference``,
    with the display units and the inputs to echo.

    ``arguments`` are the two robots as the user named them.
    """

    reference: object
    candidate: object
    match: Match
    units: object
    samples: int
    seed: int
    tol: float
    arguments: tuple = ("", "")

    def to_dict(self) -> dict:
        from ..results import SCHEMA_VERSION, json_numbers, robot_summary
        m, u, ref = self.match, self.units, self.reference

        def value(x, scale):
            return None if x is None or not math.isfinite(x) else json_numbers(x * scale)

        evaluated = m.worst_q.size == ref.dof
        return {
            "kincalc": SCHEMA_VERSION,
            "command": "compare",
            "robots": [dict(robot_summary(r), argument=a)
                       for r, a in zip((ref, self.candidate), self.arguments)],
            "units": u.to_dict(),
            "allow_offsets": m.allow_offsets,
            "free_base": m.free_base,
            "free_tool": m.free_tool,
            "samples": self.samples,
            "seed": self.seed,
            "tolerance": self.tol,
            "length_scale": json_numbers(m.length_scale * u.l),
            "position_tolerance": json_numbers(self.tol * m.length_scale * u.l),
            "orientation_tolerance": json_numbers(self.tol * u.a),
            "same": m.same,
            "position_error": value(m.position_error, u.l),
            "orientation_error": value(m.orientation_error, u.a),
            "worst_q": u.joints(ref, m.worst_q) if evaluated else None,
            "offsets": u.joints(ref, m.offsets),
            "signs": [int(s) for s in m.signs],
            "first_bad_joint": m.first_bad_joint,
            "reason": reason_text(m, ref, u),
            "base": None if m.base is None else u.pose(m.base),
            "tool": None if m.tool is None else u.pose(m.tool),
            "explanation": describe(m, ref, u),
        }


def compare(reference, candidate, units, *, arguments=("", ""), samples: int = 200,
            seed: int = 0, tol: float = 1e-6, **options) -> CompareResult:
    """:func:`match` wrapped with its display ``units`` for the ``compare`` command.

    ``options`` are those of :func:`match` (allow_offsets, free_base, free_tool).
    """
    m = match(reference, candidate, samples=samples, seed=seed, tol=tol, **options)
    return CompareResult(reference, candidate, m, units, samples, seed, tol, tuple(arguments))
