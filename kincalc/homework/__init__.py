"""The classroom: homework sheets, their grading, and quizzes (``kincalc check``,
``kincalc quiz``).

* :mod:`~kincalc.homework.sheet`: the sheet format, read and validated
  (:func:`load_sheet`; an invalid sheet is a :class:`SheetError` naming file and line);
* :mod:`~kincalc.homework.grade`: :func:`grade`, one grader per item kind, each against
  kincalc's own FK, IK, Jacobian and reach analysis;
* :mod:`~kincalc.homework.slips`: the common mistakes a wrong answer is tried against,
  for the hint;
* :mod:`~kincalc.homework.quiz`: random exercise sheets and their answer keys.
"""

from .grade import ItemResult, Report, grade
from .sheet import Item, Sheet, SheetError, Tolerance, load_sheet, parse_sheet, sheet_robot_path

__all__ = ["Item", "ItemResult", "Report", "Sheet", "SheetError", "Tolerance", "grade",
           "load_sheet", "parse_sheet", "sheet_robot_path"]
