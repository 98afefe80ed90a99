"""Robots only nearly of their family: the family's closed form runs on the nearest
robot that has its structure exactly (:func:`~kincalc.ik.families.idealised`), and its
candidates are refined by Newton's method on the robot as given
(:mod:`kincalc.ik.refine`); for six revolute joints the general 6R elimination's
solutions, which need no structure, are joined in, so that none is lost where branches
of the structured robot meet (a singular pose), and where the nearest robot has a
continuum the candidates on the curve it breaks into give way to that curve's roots
(:mod:`kincalc.ik.valleys`). A robot within
:data:`~kincalc.tolerances.KEEP_CONTINUA` of the structure keeps the nearest robot's
continua instead, as the exact family's."""

from __future__ import annotations


import numpy as np

from .refine import refine
from ..spatial import wrap
from .screws import Screws
from ..tolerances import KEEP_CONTINUA


def on_true_robot(robot, family, targets, q, candidate, br):
    """The candidates of the nearest robot of ``family`` moved onto the robot as given.

    Each candidate is refined by Newton's method (:func:`~kincalc.ik.refine.refine`, on the
    pose, the position or the position and approach, as the targets and the family ask);
    the free masks are cleared and the continua dropped (they belong to the idealised
    robot). For six revolute joints and whole poses the general 6R elimination's solutions
    are appended as ``G`` more slots (their signs ``root k`` of joint 3, as the general 6R
    family's: two solutions the words do not tell apart still differ). Within
    :data:`~kincalc.tolerances.KEEP_CONTINUA` of the structure the free slots are kept as
    they are, continua and free masks with them, the others refined, nothing appended.

    Parameters
    ----------
    robot : Robot
        The robot as given.
    family : Family
        Its (not exact) family.
    targets : Targets
        ``N`` targets (world frame, SI).
    q : ndarray (N, K, n)
        The candidates (rad / m) of the nearest robot of the family.
    candidate : ndarray (N, K) of bool
        The slots that hold one.
    br : Branches
        The solver's branches (expanded).

    Returns
    -------
    q : ndarray (N, K', n)
        Refined joint values, revolute joints wrapped to (-pi, pi]; ``K' = K`` or ``K + G``.
    candidate : ndarray (N, K') of bool
    br : Branches
        With the same ``K'`` slots.
    method : str
        The method text, saying how far the axes are from the structure (m, rad).
    """
    from .families import plan, structure_defect
    N, K, n = q.shape
    mode = {"pose": "pose", "approach": "approach", "position": "position",
            "tcv": "position"}[targets.kind]
    if mode == "pose" and not family.needs_orientation:
        mode = "position"
    move, turn = structure_defect(Screws.of(robot), plan(robot)[0])
    # within KEEP_CONTINUA the robot reaches the pose along a continuum of the nearest one
    # to what the check sees: its continua are kept, their representatives as they are
    # (Newton's method there runs along the continuum)
    keep = move <= KEEP_CONTINUA * max(robot.characteristic_length, 1e-12) \
        and turn <= KEEP_CONTINUA
    idx = np.nonzero(candidate & ~br.free_mask().any(-1) if keep else candidate)
    nearest = q, candidate
    if len(idx[0]):
        q = q.copy()
        q[idx] = refine(robot, q[idx], targets.T[idx[0]], mode=mode,
                        approach=None if targets.approach is None else targets.approach[idx[0]])
    method = (f"{family.description}; the axes have this structure only to within "
              f"{move:.2g} m and {turn:.2g} rad, so it was solved for the nearest robot "
              "that has it and every solution refined by Newton's method on the robot as "
              "given")
    if not keep:
        br = br.without_free()
    if not keep and robot.dof == 6 and targets.kind == "pose":
        if robot.is_revolute.all():
            from .general6r.solve import ROOTS, ranked_solutions
            Qg, okg = ranked_solutions(robot, targets.T)
            q = np.concatenate([q, Qg], axis=1)
            candidate = np.concatenate([candidate, okg], axis=1)
            br = br.appended(okg, ROOTS)
            method += ", and joined with the general 6R elimination's solutions"
        q, candidate, br = _with_valley_roots(robot, targets.T, q, candidate, br, K, nearest)
    q = np.where(robot.is_revolute, wrap(q), q)
    return q, candidate, br, method


def _with_valley_roots(robot, T, q, candidate, br, first: int, nearest):
    """The candidates with the roots of the broken continua through them or through the
    nearest robot's candidates ``nearest`` (``(q, candidate)`` before refinement: Newton's
    method may have taken them off their curve) (:mod:`kincalc.ik.valleys`): the candidates
    on each broken continuum replaced by its roots, put in the general 6R elimination's
    empty slots (from ``first``; labelled ``root k`` of joint 3, as that elimination's),
    more slots appended where they do not suffice; a robot with a slide has no such slots,
    and its roots are labelled ``continuum root k`` of its last joint (joint 3's ``root k``
    is its own family's slide)."""
    from .valleys import broken_continua
    replaced, roots, rok = broken_continua(robot, T, q, candidate, *nearest)
    candidate = candidate & ~replaced
    if not np.count_nonzero(rok):
        return q, candidate, br
    N, K, n = q.shape
    counts = rok.sum(1)
    room = (~candidate[:, first:]).sum(1)
    more = int(max(0, (counts - room).max()))
    if more:                   # after the elimination's roots, or a robot's own continuum roots
        G = K - first
        joint, word = (2, "root {}") if G else (robot.dof - 1, "continuum root {}")
        signs = tuple(((joint, word.format(G + k + 1)),) for k in range(more))
        br = br.appended(np.zeros((N, more), bool), signs)
        q = np.concatenate([q, np.zeros((N, more, n))], axis=1)
        candidate = np.concatenate([candidate, np.zeros((N, more), bool)], axis=1)
    q, candidate = q.copy(), candidate.copy()
    for t in np.nonzero(counts)[0].tolist():
        slots = first + np.nonzero(~candidate[t, first:])[0][:counts[t]]
        q[t, slots], candidate[t, slots] = roots[t, rok[t]], True
    return q, candidate, br
