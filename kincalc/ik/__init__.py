"""Analytic inverse kinematics derived from the robot's geometry.

``solve(robot, Target(T))`` returns an :class:`~kincalc.ik.solve.IKResult` with
every solution; see :mod:`kincalc.ik.families` for the structures recognised.
"""

from .solve import IKResult, IKSolution, Target, solve

__all__ = ["solve", "Target", "IKResult", "IKSolution"]
