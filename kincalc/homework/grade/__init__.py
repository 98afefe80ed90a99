"""Grading a sheet (:func:`grade`): every item against kincalc's own forward
kinematics, IK, Jacobian and reach analysis, with a hint from the slips behind a wrong
answer (:mod:`kincalc.homework.slips`). Values are SI inside; reports convert back to the
sheet's units.
"""

from __future__ import annotations

from .common import ItemResult, Report
from .grading import grade

__all__ = ["ItemResult", "Report", "grade"]
