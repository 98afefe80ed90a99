"""Analytic inverse kinematics derived from the robot's geometry.

``solve(robot, Target(T))`` returns an :class:`~kincalc.ik.solve.IKResult` with
every solution; see :mod:`kincalc.ik.families` for the structures recognised.

The room (layer ``ik`` of the house plan, ``tests/test_architecture.py``): the one IK
engine. :mod:`~kincalc.ik.families` recognises a robot's structure; the closed form of
each family (:mod:`~kincalc.ik.solvers`, composing :mod:`~kincalc.ik.place`,
:mod:`~kincalc.ik.wrists` and the subproblems on the robot's :mod:`~kincalc.ik.screws`)
fills :class:`~kincalc.ik.branches.Branches`; :mod:`~kincalc.ik.engine` checks, flags
and labels (:mod:`~kincalc.ik.labels`) every candidate for a batch of targets
(:mod:`~kincalc.ik.target`); :mod:`~kincalc.ik.solve` turns a batch of one into an
answer with its reasons (:mod:`~kincalc.ik.reasons`). General 6R
(:mod:`~kincalc.ik.general6r`), nearly structured robots (:mod:`~kincalc.ik.nearly`,
:mod:`~kincalc.ik.refine`), the Newton polish (:mod:`~kincalc.ik.newton`), the numerical
solver (:mod:`~kincalc.ik.numeric`) and the nearest reachable point
(:mod:`~kincalc.ik.nearest`) live here too. It may use the subproblems, fk and jacobian,
the chain, spatial and the base layer; nothing above it, and no CLI words. A robot
reaches it as an object with a ``chain``, ``joints`` (names, types, limits), ``limits``,
``is_revolute``, ``characteristic_length`` and ``fk``: :class:`kincalc.model.Robot`,
which sits above the engine so that ``robot.ik(T)`` is a downward call.
"""

from .solve import IKResult, IKSolution, Target, solve

__all__ = ["solve", "Target", "IKResult", "IKSolution"]
