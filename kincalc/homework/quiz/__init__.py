"""Random exercise sheets for teachers (``kincalc quiz``).

:func:`make_sheet` draws, from a seed, one exercise per requested kind for a
robot and returns the homework sheet (the format ``kincalc check`` grades,
version 1) as a plain dict; with ``answers=True`` every item carries the
correct answer. :func:`sheet_yaml` writes that dict as YAML text, the same
bytes for the same dict.

The exercises, and where their answers come from (all computed from the
values *as written on the sheet*, so a student who types them gets the key):

==========  ================================================================
kind        question and answer
==========  ================================================================
dh          the robot's DH table, compact ``table`` form (not for poe robots)
link        ``T_{i-1}^i`` of one joint at a random value (``link_transforms``)
fk          ``T_world_tool`` at random joints (``Robot.fk``)
ik          every IK solution within the limits for a reachable pose, written
            as xyz + rpy rounded to a few decimals (:func:`kincalc.ik.solve`)
jacobian    the geometric Jacobian, base frame, rows vx vy vz wx wy wz
reach       yes/no for a reachable pose or one just beyond the reach
            (:func:`kincalc.analysis.reach.reach`)
singular    yes/no for a singular or a clearly regular configuration (the rank
            test of :func:`kincalc.analysis.jacobian_report`)
==========  ================================================================

Units on the sheet: angles in the sheet's angle unit (``deg`` or ``rad``),
lengths in the robot file's length unit; Jacobian linear rows per radian (per
length unit for prismatic columns), as ``kincalc jacobian`` prints them.
Random joints are whole degrees (0.01 rad on a rad sheet) and prismatic
values have three decimals, within the joint limits (revolute ones also
within a half turn of zero). Answers carry ten significant digits.

Each kind draws from its own generator, seeded by ``(seed, kind, k)`` for the
k-th item of that kind, so leaving a kind out does not change the others.

The modules: :mod:`~.rules` (kinds, digits, margins, :class:`QuizError`),
:mod:`~.numbers` (values a student can type), :mod:`~.items` (dh, link, fk, jacobian),
:mod:`~.singular` (the singular-configuration search), :mod:`~.poses` (ik and reach),
:mod:`~.writing` (the sheet's YAML) and :mod:`~.make` (one exercise per kind). They use
the IK engine, the analysis room and spatial.
"""

from __future__ import annotations

from .items import variable_names
from .make import make_sheet, skipped
from .numbers import random_joints
from .poses import pose_forms
from .rules import DEFAULT_KINDS, KINDS, QuizError
from .singular import scaled_sigma, singular_configuration
from .writing import sheet_yaml

__all__ = ["DEFAULT_KINDS", "KINDS", "QuizError", "make_sheet", "pose_forms",
           "random_joints", "scaled_sigma", "sheet_yaml", "singular_configuration",
           "skipped", "variable_names"]
