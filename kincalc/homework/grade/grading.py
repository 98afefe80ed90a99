"""Grading a sheet: every item by the grader of its kind."""

from __future__ import annotations

from dataclasses import replace

from ...errors import KincalcError, TargetMismatch
from ...limits import quote
from ...analysis.requests import FIELD_WORDS
from ..sheet import Sheet, SheetError, sheet_words
from .common import ItemResult, Report
from .dh import grade_dh
from .fk import grade_fk
from .ik import grade_ik
from .jacobian import grade_jacobian
from .link import grade_link
from .verdicts import grade_reach, grade_singular


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
                text = exc.words(FIELD_WORDS) if isinstance(exc, TargetMismatch) \
                    else sheet_words(str(exc))
                raise SheetError(sheet.path, item.line, f"item {quote(item.id)}: {text}") from None
        results.append(replace(r, line=item.line))
    return Report(sheet=sheet, items=results)


_GRADERS = {"dh": grade_dh, "link": grade_link, "fk": grade_fk, "ik": grade_ik,
            "jacobian": grade_jacobian, "reach": grade_reach, "singular": grade_singular}
