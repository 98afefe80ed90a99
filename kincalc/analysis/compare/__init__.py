"""Are two robot descriptions the same robot?

Two robots with the same number and types of joints are *equivalent* when
some constant signs ``s_i = +-1`` and offsets ``c_i`` make them agree for
every configuration::

    FK_candidate(s * q + c) == B · FK_reference(q) · T      for all q (n,)

where ``FK`` is ``T_world_tool`` (4, 4, lengths in m), ``q`` is in rad / m,
and ``B`` (base) and ``T`` (tool) are the identity unless ``free_base`` /
``free_tool`` let them be any constant rigid transforms. Without
``allow_offsets`` the signs must all be +1 and the offsets 0.

Method (product of exponentials; Lynch & Park, *Modern Robotics*, 2017,
sec. 4.1 and 5.1). Both robots are written as
``FK(q) = exp([xi_1] q_1) ··· exp([xi_n] q_n) · M`` with unit screws ``xi_i``
``(v, w)`` in the world frame at q = 0. Then

    FK_c(s q + c) = prod_i exp([s_i eta_i(c)] q_i) · G_n(c) M_c,
    eta_i(c) = Ad_{G_{i-1}(c)} eta_i,   G_k(c) = exp([eta_1] c_1) ··· exp([eta_k] c_k),

and, because the columns of the spatial Jacobian at q = 0 are the screws,
equality for all q holds exactly when ``s_i eta_i(c) = xi_i`` for every i
and ``G_n(c) M_c = M_r``. The screw equations are solved one joint at a
time: screw i + 1 fixes the offsets it depends on given the earlier ones.
With one unknown offset the equation is ``r0 + sin(x) a1 + (1 - cos x) a2 = 0``
(``r0 + x a1`` for a prismatic joint), solved exactly for every root; an
offset a screw leaves undetermined (a joint whose screw commutes with the
next ones: a prismatic joint along the previous revolute axis, two parallel
prismatic joints, ...) waits for a later screw or the tool condition, which
then solve for the waiting offsets together by damped Gauss-Newton from a
grid of starts. Where a screw has several solutions (intersecting axes:
``c`` and ``c + pi`` with the sign flipped) every branch is followed, and
among the complete solutions the one with the fewest sign changes, then the
smallest offsets, is kept. The answer is always checked by forward
kinematics on ``samples`` random configurations within the reference's
limits (plus q = 0); that check alone decides ``same``.

Without ``free_base`` the robots' ``base`` transforms are part of the
comparison (world frames must agree); ``free_base`` aligns joint 1's axis
and solves for the rest of the base like an offset, and absorbs joint 1's
offset into it. ``free_tool`` drops the tool condition and absorbs the last
joint's offset. Joint limits and names are not compared.

The modules: :mod:`~.screws` (screws, exponentials, adjoint, bracket, axis distances),
:mod:`~.search` (the branch search), :mod:`~.match` (:class:`Match` and the FK check),
:mod:`~.words` (the reason line and the readable lines), :mod:`~.report` (the command's
result and JSON). They use fk, spatial and :mod:`kincalc.analysis.results`.
"""

from .match import Match, match
from .report import CompareResult, compare
from .words import describe

__all__ = ["CompareResult", "Match", "compare", "describe", "match"]
