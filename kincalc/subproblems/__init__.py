"""Geometric subproblems of inverse kinematics (Paden-Kahan 1-3; Elias & Wen 4-6).

Each module holds one subproblem, solved for all its exact solutions, with a
flag when it fell back to a least-squares answer. Rotations are about unit
axes ``k`` through the origin (translate the inputs first); angles in rad.
References: B. Paden, "Kinematics and control of robot manipulators", PhD
thesis, UC Berkeley 1986; R. Murray, Z. Li, S. Sastry, *A Mathematical
Introduction to Robotic Manipulation*, 1994, sec. 3.3; A. Elias, J. Wen,
"IK-Geo: Unified robot inverse kinematics using subproblem decomposition",
arXiv:2211.05737, 2022.
"""

from .sp1 import sp1
from .sp2 import sp2
from .sp3 import sp3
from .sp4 import sp4
from .sp5 import sp5
from .sp6 import sp6

__all__ = ["sp1", "sp2", "sp3", "sp4", "sp5", "sp6"]
