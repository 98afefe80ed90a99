"""Geometric subproblems of inverse kinematics (Paden-Kahan 1-3; Elias & Wen 4-6).

One module per subproblem, each with its equation, its number of solutions and its
ill-posed cases at the top. Every subproblem solves a batch of problems at once
(inputs of any leading shape ``(..., 3)``) and returns a
:class:`~kincalc.subproblems.solutions.Solutions`: the angles of every solution slot,
their cosines and sines, and masks saying which slots hold a solution, which are exact
(the others least-squares answers) and where the problem is ill-posed. Rotations are
about unit axes through the origin (translate the inputs first); angles in rad.

This room uses numpy, :mod:`kincalc.spatial` and :mod:`kincalc.tolerances` only; the IK
families compose it.

References: B. Paden, "Kinematics and control of robot manipulators", PhD thesis, UC
Berkeley 1986; R. Murray, Z. Li, S. Sastry, *A Mathematical Introduction to Robotic
Manipulation*, 1994, sec. 3.3; A. Elias, J. Wen, "IK-Geo: Unified robot inverse
kinematics using subproblem decomposition", arXiv:2211.05737, 2022.
"""

from .solutions import Solutions
from .sp1 import sp1
from .sp2 import sp2
from .sp3 import sp3
from .sp4 import sp4
from .sp5 import sp5
from .sp6 import sp6

__all__ = ["Solutions", "sp1", "sp2", "sp3", "sp4", "sp5", "sp6"]
