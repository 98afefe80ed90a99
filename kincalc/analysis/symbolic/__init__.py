"""Symbolic link transforms, forward kinematics and Jacobians (sympy).

sympy is the optional extra ``symbolic`` (``pip install 'kincalc[symbolic]'``)
and is imported only inside the functions of this package that need it, never
at import time: :func:`require_sympy` imports it or raises
:class:`~kincalc.errors.MissingExtra`.

Frames and conventions (the same as the numeric core, see :mod:`kincalc.model`)
-----------------------------------------------------------------------------
* ``dh`` link transform ``T_{i-1}^i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``,
  ``mdh`` ``T_{i-1}^i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``: the pose of
  link frame i in link frame i-1. A revolute joint's variable is ``θ_i``
  (the file's ``theta`` is added to it as a constant offset), a prismatic
  joint's variable enters ``d_i`` the same way.
* ``poe`` (Lynch & Park, *Modern Robotics*, 2017, eq. 4.14):
  ``T = base · exp([S_1] θ_1) ··· exp([S_n] θ_n) · M`` with
  ``exp([S] θ) = [[R, (I - R) p], [0, 1]]``, ``R = I + sin θ [ω] + (1 - cos θ) [ω]²``
  (Rodrigues) for a revolute joint of unit axis ω through the point p, and
  ``[[I, ω d], [0, 1]]`` for a prismatic one. The link transforms printed for
  poe robots are those of :meth:`kincalc.model.Robot.link_transforms` (frame i
  on joint i's axis, z along it).
* ``T`` is ``T_world_tool = base · T_0^n · tool`` like :meth:`Robot.fk`.
* The geometric Jacobian (Siciliano et al. 2009, eq. 3.30) has rows
  ``(vx, vy, vz, wx, wy, wz)`` and one column per joint: ``[z_i × (p_e - o_i); z_i]``
  (revolute) or ``[z_i; 0]`` (prismatic), in the world frame (``frame='base'``)
  or rotated into the tool frame (``frame='tool'``).

Symbols and numbers
-------------------
Joint variables are angles (rad) and lengths; the symbols carry no unit.
Lengths the robot file wrote as expressions over its ``parameters`` (``d:
h1``) become those parameters' symbols, in the file's length unit; lengths
the file wrote as plain numbers, and the base and tool transforms, stay
numbers. With ``numeric_lengths`` every parameter is replaced by its value.
Constant angles (``alpha``, ``theta`` offsets, rotations of base and tool)
are made exact: multiples of π/3600 become rational multiples of ``pi``, so
``cos 90° = 0`` and ``sin 30° = 1/2``.

Simplification
--------------
Every product is expanded into a sum of products of sines and cosines,
which is multilinear in each joint's sine and cosine (a serial chain meets
each joint once), and sums of angles are collapsed term by term:
``c·cos a cos b - c·sin a sin b -> c·cos(a + b)`` and the three companion
identities (plus ``cos² + sin² = 1``). This is where ``C23`` and ``S234``
come from for consecutive parallel axes. Jacobian columns are built as
``R_0^{i-1} (z × p_{i-1}^e)`` from a prefix and a suffix of the chain so
that they stay multilinear too. No general ``sympy.simplify`` is run: a
6R arm takes well under a second. The result is then written with the
textbook abbreviations ``C1 = cos θ1``, ``S12 = sin(θ1 + θ2)``,
``C2m3 = cos(θ2 - θ3)`` and common factors are pulled out greedily
(``C1·(a2·C2 + a3·C23) - d3·S1``).

The modules: :mod:`~.building` (the derivations), :mod:`~.simplify` (angle sums,
abbreviations), :mod:`~.printing` (text, Unicode, LaTeX), :mod:`~.results` (the notation,
the symbolic FK and Jacobian and their documents) and :mod:`~.symbols` (sympy on demand,
exact numbers, joint symbols). They use the model, units, errors and
:mod:`kincalc.analysis.results`; sympy only inside functions.
"""

from .building import symbolic_fk, symbolic_jacobian
from .printing import expr_str, expr_text
from .results import ROWS, Notation, SymbolicFK, SymbolicJacobian
from .symbols import require_sympy, unicode_name

__all__ = ["Notation", "ROWS", "SymbolicFK", "SymbolicJacobian", "expr_str", "expr_text",
           "require_sympy", "symbolic_fk", "symbolic_jacobian", "unicode_name"]
