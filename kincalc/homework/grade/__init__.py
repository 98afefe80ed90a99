"""Grading a sheet (:func:`grade`): every item against kincalc's own forward
kinematics, IK, Jacobian and reach analysis, with a hint from the slips behind a wrong
answer (:mod:`kincalc.homework.slips`). Values are SI inside; reports convert back to the
sheet's units.

The modules: one grader per item kind (:mod:`~.link`, :mod:`~.fk`, :mod:`~.jacobian`,
:mod:`~.verdicts` for ``singular`` and ``reach``, :mod:`~.ik`, :mod:`~.dh`), what they
share (:mod:`~.common`) and the dispatch over a sheet (:mod:`~.grading`). They use the
sheet, the slips, the IK engine and the analysis room.
"""

from __future__ import annotations

from .common import ItemResult, Report
from .grading import grade

__all__ = ["ItemResult", "Report", "grade"]
