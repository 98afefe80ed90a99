"""The rules of :mod:`kincalc.homework.quiz`: the kinds of exercise, how many
digits an answer carries, how far an exercise stays from limits and singularities,
and the error when none can be drawn."""

from __future__ import annotations

import math

from ...errors import KincalcError


#: every kind of exercise, in the order of the sheet format's specification
KINDS = ("dh", "link", "fk", "ik", "jacobian", "reach", "singular")
#: the kinds of a sheet when none are asked for
DEFAULT_KINDS = ("dh", "link", "fk", "ik", "jacobian", "singular", "reach")
#: significant digits of answers (round-trip far below any grading tolerance)
SIGNIFICANT = 10
#: random draws tried for one exercise before giving up
ATTEMPTS = 60
#: ... for a ``reach`` exercise of a robot with no closed-form IK, each of whose draws a
#: numerical search decides (up to a second on a long chain: 60 draws took a minute)
NUMERIC_ATTEMPTS = 4
#: a regular configuration of a ``singular`` item has its smallest scaled singular
#: value above this (far from the rank threshold, so rounding cannot flip it)
REGULAR_MARGIN = 1e-2
#: a singular one has it below SINGULAR_TOL times this
SINGULAR_MARGIN = 1e-2
#: IK solutions of an ``ik`` item stay this far (rad / robot lengths) from every
#: joint limit and from each other, so the key does not hang on the last digit
IK_CLEARANCE = 1e-6
IK_SEPARATION = math.radians(1.0)


class QuizError(KincalcError):
    """No exercise of a kind could be drawn for this robot (exit 2). ``why`` is the
    reason without the advice to leave the kind out (the note when it is)."""

    def __init__(self, why: str, advice: str = " (leave it out with --items)"):
        super().__init__(why + advice)
        self.why = why
