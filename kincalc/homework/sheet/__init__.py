"""Homework sheets: the format, read and validated (``kincalc check``).

A sheet (YAML; the format is in the README, "kincalc check", and in ``man kincalc-check``)
names a robot and lists items, each an exercise with the student's answer.
:func:`load_sheet` reads and validates the whole sheet first: an invalid sheet is a
:class:`SheetError` naming file and line (exit status 2) before anything is graded.
Sheet values are converted to SI (m, rad) on reading, with the sheet's units (by default
the robot file's). The YAML is read by :class:`kincalc.conventions.reader.Reader`, the one YAML
reader with line numbers.

The modules: :mod:`~.format` (keys, tolerances, :class:`Sheet`, :class:`Item`, the
sheet's words), :mod:`~.reader` (the file, its robot, its items) and :mod:`~.answers`
(each kind's answer). They use the one YAML reader (:mod:`kincalc.conventions.reader`),
the IK targets and spatial.
"""

from __future__ import annotations

from .format import (DEFAULT_ANGLE_DEG, DEFAULT_MATRIX, DEFAULT_POSITION, DH_SAMPLES,
                     HINT_FACTOR, ITEM_KEYS, Item, KINDS, KIND_KEYS, MIX_FACTOR,
                     POSE_FIELDS, SHEET_KEYS, Sheet, SheetError,
                     TOLERANCE_KEYS, Tolerance, sheet_words)
from .reader import load_sheet, parse_sheet, sheet_robot_path

__all__ = ["DEFAULT_ANGLE_DEG", "DEFAULT_MATRIX", "DEFAULT_POSITION", "DH_SAMPLES",
           "HINT_FACTOR", "ITEM_KEYS", "Item", "KINDS", "KIND_KEYS", "MIX_FACTOR",
           "POSE_FIELDS", "SHEET_KEYS", "Sheet", "SheetError",
           "TOLERANCE_KEYS", "Tolerance", "load_sheet", "parse_sheet", "sheet_robot_path",
           "sheet_words"]
