"""The closed form of each family, for a batch of targets: short compositions of the
point placement (:mod:`kincalc.ik.place`), the wrists (:mod:`kincalc.ik.wrists`) and
the subproblems, in the manner of IK-Geo's solvers (Elias & Wen 2022).

Each solver takes the family's screws ``S`` (world frame at q = 0, SI; see
:mod:`kincalc.ik.screws`), the targets (:class:`~kincalc.ik.target.Targets`) and a
:class:`~kincalc.ik.branches.Branches` with one slot per target, and returns the
branches with every joint solved: candidates, which the engine checks by FK, labels
and flags. ``R_t = R_T R_M^T`` below is the rotation of the product of exponentials
(``T = E_1 ... E_n M``), and ``E_j^-1`` undoes joint j's motion.
"""

from __future__ import annotations

from .branches import Branches
from .families import TARGET_FAMILIES, Family, plan
from .five_joints import (pitch_roll, planar_shoulder, position_approach, spherical_shoulder,
                          wrist_pair)
from .parallel_axes import parallel_four_wrist, three_parallel, three_parallel_offset
from .pieces import meeting_point, target_rotation, tool_point
from .place import place
from .screws import Screws
from .small_arms import planar_3, planar_4, point_plus_roll, position_2, position_3, tcv
from .target import Targets
from .wrists import spherical_taking


# --- six joints --------------------------------------------------------------------

def spherical_wrist(S: Screws, targets, br: Branches) -> Branches:
    """Axes 4, 5, 6 meet at the wrist centre: joints 1-3 place it, the wrist turns.

    Joints 1-3 place the wrist centre (:func:`~kincalc.ik.place.place`), then joints 4-6
    take the orientation left for them (:func:`~kincalc.ik.wrists.spherical`).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    T = targets.T
    c0 = meeting_point(S, 3, 6)
    ct = tool_point(S, T, c0)
    br = place(S, br, (0, 1, 2), c0, ct, what="the wrist centre")
    if br.explain:
        br = br.note("wrist centre (target)", br.take(ct.repeat(br.K, 1) if br.K else ct),
                     "length")
    return spherical_taking(S, br, (3, 4, 5), target_rotation(S, T), before=(0, 1, 2))


def _tcv(robot, S, targets, br):
    """A tool configuration vector (:func:`~kincalc.ik.small_arms.tcv`); where it fixes the
    whole pose, the robot's own closed form (an exact family's) solves that."""
    family = plan(robot)[1]
    solve_pose = None if family is None or not family.exact else \
        (lambda pose, br: run_solver(robot, S, family, pose, br))
    return tcv(robot, S, targets, br, solve_pose)


def _swivel(robot, S, targets, br):
    from .swivel import swivel
    return swivel(robot, S, targets, br)


#: the solvers of target kinds that bring their own (``engine.TARGET_FAMILIES``)
TARGET_SOLVERS = {"tcv": _tcv, "swivel": _swivel}

SOLVERS = {
    "spherical-wrist": spherical_wrist,
    "three-parallel": three_parallel,
    "three-parallel-offset": three_parallel_offset,
    "parallel-four-wrist": parallel_four_wrist,
    "position-3": position_3,
    "position-2": position_2,
    "planar-3": planar_3,
    "planar-4": planar_4,
    "point-plus-roll": point_plus_roll,
    "position-approach": position_approach,
    "wrist-pair": wrist_pair,
    "pitch-roll": pitch_roll,
    "planar-shoulder": planar_shoulder,
    "spherical-shoulder": spherical_shoulder,
}


def run_solver(robot, S, family: Family, targets: Targets, br: Branches) -> Branches:
    """The candidates of ``family``'s solver for ``targets`` (step 1 of
    :mod:`kincalc.ik.engine`: the engine then checks them), before the free joints are
    oriented and the open ones valued.

    Parameters
    ----------
    robot : Robot
    S : Screws, the robot's (:func:`~kincalc.ik.families.plan`)
    family : Family, the robot's, or the target kind's (``TARGET_FAMILIES``)
    targets : Targets, ``N`` targets of a kind the family takes (world frame, SI)
    br : Branches, :meth:`Branches.start` of the N targets

    Returns
    -------
    Branches, the solver's slots (a reversed chain's in the robot's joint order)
    """
    if targets.kind in TARGET_FAMILIES:
        return TARGET_SOLVERS[targets.kind](robot, S, targets, br)
    if family.name == "general-6r":
        from .general6r import general_6r
        return general_6r(robot, targets, br)
    if family.reverse:
        br = SOLVERS[family.solver](S.constant("reversed", S.reversed), targets.inverted(), br)
        return br.flushed().reversed_chain()
    return SOLVERS[family.solver](S, targets, br)
