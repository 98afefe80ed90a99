"""Grading the yes/no items: ``singular`` (the Jacobian's rank) and ``reach`` (the
reach analysis)."""

from __future__ import annotations

from ..sheet import Item, Sheet
from ..slips import fmt
from .common import ItemResult, yes


def grade_singular(sheet: Sheet, item: Item) -> ItemResult:
    from ...analysis.reports import jacobian_report
    rep = jacobian_report(sheet.robot, item.q, sheet.units)
    truth = rep.singular
    why = ("; ".join(rep.singularity.descriptions) if truth else
           f"the Jacobian has full rank {rep.rank} (smallest normalised singular value "
           f"{fmt(rep.sigma_normalised[-1])})")
    passed = item.answer == truth
    msg = f"singular: {yes(truth)} — {why}"
    details = {"expected": truth, "rank": rep.rank, "generic_rank": rep.generic_rank}
    return ItemResult(item.id, "singular", passed, item.points, None,
                      ("right; " if passed else f"wrong (answer {yes(item.answer)}); ") + msg,
                      details=details)


def grade_reach(sheet: Sheet, item: Item) -> ItemResult:
    from ...analysis.reach import reach
    r = reach(sheet.robot, item.target, units=sheet.units)
    passed = item.answer == r.reachable
    details = {"expected": r.reachable, "verdict": r.verdict,
               "distance": None if r.distance is None else r.distance * sheet.units.l}
    return ItemResult(item.id, "reach", passed, item.points, None,
                      ("right; " if passed else f"wrong (answer {yes(item.answer)}); ")
                      + f"reachable: {yes(r.reachable)} — {r.verdict}: {r.reason}",
                      details=details)


# ik -------------------------------------------------------------------------------
