"""The classroom: homework sheets, their grading, and quizzes (``kincalc check``,
``kincalc quiz``).

* :mod:`~kincalc.homework.sheet`: the sheet format, read and validated
  (:func:`load_sheet`; an invalid sheet is a :class:`SheetError` naming file and line);
* :mod:`~kincalc.homework.grade`: :func:`grade`, one grader per item kind, each against
  kincalc's own FK, IK, Jacobian and reach analysis;
* :mod:`~kincalc.homework.slips`: the common mistakes a wrong answer is tried against,
  for the hint;
* :mod:`~kincalc.homework.quiz`: random exercise sheets and their answer keys;
* :mod:`~kincalc.homework.roster`: a sheet and a key per student of a roster, each from a
  seed of the course's salt and the student's id;
* :mod:`~kincalc.homework.export`: a graded sheet as Gradescope's and PrairieLearn's
  results documents and as a Markdown feedback page;
* :mod:`~kincalc.homework.gradebook`: a class's sheets as a CSV gradebook, and the names
  of their feedback files.
"""

from .grade import ItemResult, Report, grade
from .sheet import Item, Sheet, SheetError, Tolerance, load_sheet, parse_sheet, sheet_robot_path

__all__ = ["Item", "ItemResult", "Report", "Sheet", "SheetError", "Tolerance", "grade",
           "load_sheet", "parse_sheet", "sheet_robot_path"]
