"""Why an IK answer is what it is: the reason of one target's answer, as data
(:mod:`kincalc.ik.reasons`, SI; :mod:`kincalc.analysis.words` words it).

Solutions: how many, how many within the limits, or which limits block them all. None: the
closest candidates that reach the position and miss the orientation, or, where none
reaches it, the nearest reachable position (:mod:`kincalc.ik.nearest`): out of reach of the
geometry and where, out of reach within the limits, or within reach, then the orientation
is what no solution takes.
"""

from __future__ import annotations

import numpy as np

from ..spatial import wrap
from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION, NEAR_MISS
from .families import APPROACH_FAMILIES, TCV
from .reasons import Blocked, Found, NoSolution, OrientationOut, OutOfReach


def limits_reason(sols) -> Found | Blocked:
    """``Found`` (how many of ``sols``, one or more, are within the limits), else ``Blocked``
    (each broken joint and the least amount any solution is beyond it)."""
    if any(s.within_limits for s in sols):
        return Found(len(sols), sum(s.within_limits for s in sols))
    worst = {}
    for s in sols:
        for i, amount, side in s.violations:
            worst[i] = min(worst.get(i, np.inf), amount)
    return Blocked(len(sols), tuple(sorted(worst.items())))


def reason(robot, family, T, target, sols, rejected):
    """Why the answer of one target is what it is (:mod:`kincalc.ik.reasons`, SI).

    Parameters
    ----------
    robot : Robot
    family : Family, the robot's (or the target kind's)
    T : ndarray (4, 4), the target ``T_world_tool`` (world frame, SI)
    target : Target
    sols : list of IKSolution, the solutions found
    rejected : list of dict, the candidates that missed (``q``, ``branch``, errors, ``reason``)

    Returns
    -------
    a reason of :mod:`kincalc.ik.reasons`
    """
    if sols:
        return limits_reason(sols)
    if rejected:
        placed = placing(robot, rejected)
        what = "approach vector" if family is TCV else \
            "approach direction" if target.approach is not None else "orientation"
        if not placed:
            best = min(rejected, key=lambda r: (r["position_error"], r["branch"]))
            if best["position_error"] <= NEAR_MISS * max(robot.characteristic_length, 1e-12):
                return NoSolution(best["reason"])              # a hair: say by how much
            # no candidate reaches the position: out of reach, or (reachable alone) not
            # with this orientation, which moved the point the family places
            why = out_of_reach(robot, T)
            return why if isinstance(why, OutOfReach) else OrientationOut(what, family.controls)
        if placed[0]["orientation_error"] is not None \
                and placed[0]["orientation_error"] <= ACCEPT_ORIENTATION:
            # the closest has the orientation: it missed the position, by a hair (next to a
            # singularity, where a closed form's joints are good to sqrt(rounding) only)
            return NoSolution(min(placed, key=lambda r: r["position_error"])["reason"])
        if family is TCV:
            return OrientationOut(what, closest=(placed[0]["branch"],
                                                 placed[0]["orientation_error"]))
        if family.name in APPROACH_FAMILIES and target.approach is None \
                and _reach_approach(robot, placed, T[:3, 2]):
            # the five-joint solvers place the tool and its approach: what is left is the
            # roll about the approach, one value per solution of the family
            return OrientationOut(what, family.controls, rolls=tuple(
                (r["orientation_error"], r["branch"]) for r in placed))
        return OrientationOut(what, family.controls,
                              closest=(placed[0]["branch"], placed[0]["orientation_error"]))
    return out_of_reach(robot, T)


def placing(robot, rejected) -> list:
    """The rejected candidates that reach the target position, each once, in order of
    their orientation error (then branch): the facts a reason may quote. Candidates
    within rounding of each other in position are equal here; which of them is "best"
    must not depend on the last bits of their position errors."""
    tol = ACCEPT_POSITION * max(robot.characteristic_length, 1e-12) * 1e3
    placed = sorted((r for r in rejected if r["position_error"] <= tol),
                    key=lambda r: (r["orientation_error"] or 0.0, r["branch"]))
    out = []
    for r in placed:
        if not any(r["branch"] == o["branch"] and np.allclose(
                np.where(robot.is_revolute, wrap(r["q"] - o["q"]), r["q"] - o["q"]), 0,
                atol=1e-9) for o in out):
            out.append(r)
    return out


def _reach_approach(robot, candidates, a) -> bool:
    """Whether every candidate's tool z axis is the approach ``a`` (unit, world)."""
    z = robot.fk(np.array([c["q"] for c in candidates]))[:, :3, 2]
    return bool(np.all(np.linalg.norm(np.cross(z, a), axis=-1) <= ACCEPT_ORIENTATION)
                and np.all(z @ a > 0))


def out_of_reach(robot, T):
    """Why nothing was found, from the nearest reachable position (see
    :mod:`kincalc.analysis.reach`): out of reach of the geometry and where, out of reach
    within the limits, or within reach (then the pose as a whole is not)."""
    from .nearest import nearest_position, unlimited, where_outside
    p = np.asarray(T, float)[:3, 3]
    tol = ACCEPT_POSITION * max(robot.characteristic_length, 1e-12)
    _, _, dist = nearest_position(robot, p)
    if dist <= tol:
        return NoSolution()
    _, p_free, dist_free = nearest_position(robot, p, limits=unlimited(robot))
    if dist_free <= tol:
        return OutOfReach(distance=dist)
    return OutOfReach(where_outside(robot, p, p_free, dist_free))
