"""Reachability: can the robot get there, and if not, why?

:func:`reach` answers for one target (:class:`~kincalc.ik.Target`) with a
verdict and a reason:

==========================  ==================================================
verdict                     meaning
==========================  ==================================================
``reachable``               solutions within the joint limits, at least one of
                            them not singular
``reachable-singular``      reached only at singular configurations (the
                            boundary of the workspace, a wrist singularity)
``blocked-by-limits``       solutions exist, but every one violates a joint
                            limit (which joints, by how much)
``orientation-unreachable`` the position is reachable, this orientation is not
                            (fewer than six joints, or a dexterity limit)
``beyond-outer-reach``      the position is farther out than the arm reaches
``inside-inner-void``       the position is in the hole the arm cannot reach
``outside-workspace``       the position is out of reach otherwise (off the
                            plane of a planar arm, in a notch of the workspace)
``not-found``               no solution was found although the position is
                            within reach: the numerical solver's (redundant
                            arms), or a closed form's candidates missed the
                            pose by a hair next to a singularity
==========================  ==================================================

``distance`` (m) is the distance from the target position to the nearest
position the tool reaches within the limits: zero when the position is
reachable. It is found by damped least squares
(:func:`kincalc.ik.nearest.descend`) from the sampled configurations nearest
the target, so it is a local minimum: exact for the convex-ish sets of arms'
workspaces, an upper bound in general. Whether the limits are to blame is
decided by the same search with the limits removed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..ik.nearest import nearest_position, unlimited, where_outside
from ..tolerances import ACCEPT_POSITION
from ..ik.reasons import NoSolution, OrientationOut
from .words import count_text, length, length_suffix, reason_text, singularity_text


@dataclass(frozen=True)
class ReachResult:
    """Verdict of :func:`reach`; SI values (m, rad), world frame."""

    robot: object
    target: object
    verdict: str
    reason: str
    distance: float | None
    solutions: int | None
    within_limits: int | None
    method: dict
    nearest_q: np.ndarray | None = None
    nearest_position: np.ndarray | None = None
    blocked: list | None = None
    units: object = None

    @property
    def reachable(self) -> bool:
        return self.verdict in ("reachable", "reachable-singular")

    def to_dict(self) -> dict:
        from .results import json_numbers, json_header
        u = self.units
        out = json_header("reach", self.robot, u)
        out["target"] = {"T": u.pose(self.target.T),
                         "orientation_given": bool(self.target.orientation)}
        out.update({
            "reachable": self.reachable,
            "verdict": self.verdict,
            "reason": self.reason,
            "distance": None if self.distance is None else json_numbers(self.distance * u.l),
            "solutions": self.solutions,
            "solutions_within_limits": self.within_limits,
            "method": self.method,
            "nearest": None if self.nearest_q is None else {
                "q": u.joints(self.robot, self.nearest_q),
                "position": json_numbers(self.nearest_position * u.l)},
            "blocked": self.blocked,
        })
        return out


def reach(robot, target, *, units=None) -> ReachResult:
    """Can ``robot`` reach ``target`` (a :class:`~kincalc.ik.Target`)? See the module
    docstring for the verdicts."""
    from ..ik import solve
    from ..ik.families import plan
    from .results import Units
    units = units or Units(length=robot.length_unit)
    L = max(robot.characteristic_length, 1e-12)
    family = plan(robot)[1]
    if (family is not None and family.needs_orientation and not target.orientation
            and target.approach is None and target.tcv is None):
        return _position_only(robot, target, units)
    res = solve(robot, target, units=units)
    sols = res.solutions
    inside = [s for s in sols if s.within_limits]
    common = dict(robot=robot, target=target, solutions=len(sols), within_limits=len(inside),
                  method={"family": res.family, "description": res.method}, units=units)

    if inside:
        if all(s.singular for s in inside):
            why = singularity_text(robot, inside[0]) or "the Jacobian loses rank"
            every = "at" if len(inside) == 1 else "every one of them at"
            return ReachResult(verdict="reachable-singular", distance=0.0, **common,
                               reason=f"{count_text(len(sols), len(inside))}, {every} a singular "
                                      f"configuration: {why}; reachable, but not robustly")
        return ReachResult(verdict="reachable", distance=0.0,
                           reason=count_text(len(sols), len(inside)), **common)

    p = np.asarray(target.T, float)[:3, 3]
    q_near, p_near, dist = nearest_position(robot, p)
    near = dict(nearest_q=q_near, nearest_position=p_near)
    if sols:
        blocked, text = _blocked(robot, sols, units)
        return ReachResult(verdict="blocked-by-limits", distance=dist, blocked=blocked,
                           reason=text, **near, **common)

    if dist <= ACCEPT_POSITION * L:
        # the numerical solver found nothing, or a closed form's candidates, next to a
        # singularity, missed the pose by a hair (NoSolution with the best miss)
        if res.family == "numerical" or (isinstance(res.reason, NoSolution)
                                          and res.reason.best is not None):
            return ReachResult(verdict="not-found", distance=0.0, reason=reason_text(
                res.reason, robot, units) + "; the position itself is within reach",
                **near, **common)
        if isinstance(res.reason, OrientationOut):
            reason = reason_text(res.reason, robot, units)
        else:
            reason = ("the position is reachable but this orientation is not: no "
                      "configuration within the limits takes the tool there with it")
        return ReachResult(verdict="orientation-unreachable", distance=0.0, reason=reason,
                           **near, **common)
    return _out_of_reach(robot, p, dist, near, common, units)


def _position_only(robot, target, units) -> ReachResult:
    """Reachability of a position alone, for a robot that controls its orientation
    too: the nearest-point search decides (no IK branches to count)."""
    p = np.asarray(target.T, float)[:3, 3]
    q_near, p_near, dist = nearest_position(robot, p)
    near = dict(nearest_q=q_near, nearest_position=p_near)
    common = dict(robot=robot, target=target, solutions=None, within_limits=None,
                  method={"family": "position only",
                          "description": "nearest tool position by damped least squares "
                                         "from sampled configurations, within the limits"},
                  units=units)
    if dist <= ACCEPT_POSITION * max(robot.characteristic_length, 1e-12):
        reason = ("the position is reachable (with some orientation; give one to ask about "
                  "the whole pose)")
        stuck = _on_the_boundary(robot, p, q_near)
        if stuck is None:
            return ReachResult(verdict="reachable", distance=0.0, reason=reason, **near,
                               **common)
        d = np.round(stuck * np.sign(stuck[np.argmax(np.abs(stuck))]), 3) + 0.0
        return ReachResult(verdict="reachable-singular", distance=0.0, **near, **common,
                           reason=reason + ", on the workspace's boundary: only where the "
                           "tool point cannot move along ({:.3f}, {:.3f}, {:.3f}) (base "
                           "frame); reachable, but not robustly".format(*d))
    return _out_of_reach(robot, p, dist, near, common, units)


def _on_the_boundary(robot, p, q):
    """The direction (unit, base frame) the tool point at ``p``, reached at ``q``, cannot
    move along, where ``p`` lies on the boundary of the positions reached within the limits
    (a stretched arm): the tool point's Jacobian at ``q`` has lost rank, and a point a hair
    (1e-6 of the arm's size) beyond ``p`` that way, on one side or the other, is out of
    reach. None elsewhere (a configuration singular at a point others reach as well)."""
    from ..jacobian import numerical_rank, scale_free
    from .reports import stuck_direction
    L = max(robot.characteristic_length, 1e-12)
    Jv = scale_free(robot.jacobian(q), robot.is_revolute, L)[:3]
    Up, s, _ = np.linalg.svd(Jv)
    rank = int(numerical_rank(s))
    if rank >= robot.generic_ranks[1]:
        return None
    d = stuck_direction(robot, q, Up, rank)
    beyond = [nearest_position(robot, p + side * 1e-6 * L * d)[2] for side in (1, -1)]
    return d if max(beyond) > ACCEPT_POSITION * L else None


def _out_of_reach(robot, p, dist, near, common, units) -> ReachResult:
    """The position ``p`` is ``dist`` (> 0) from the nearest point reached within the
    limits: blocked by the limits, or out of reach of the geometry, and where."""
    L = max(robot.characteristic_length, 1e-12)
    q_free, p_free, dist_free = nearest_position(robot, p, limits=unlimited(robot))
    if dist_free <= ACCEPT_POSITION * L:
        from ..ik.joint_limits import normalise
        from ..ik.solve import violation_list
        viol = violation_list(robot, normalise(robot, q_free))
        blocked = [_violation_dict(robot, v, units) for v in viol]
        what = ", ".join(_violation_text(robot, v, units) for v in viol)
        return ReachResult(
            verdict="blocked-by-limits", distance=dist, blocked=[{"branch": "numerical",
                                                                 "violations": blocked}],
            reason=(f"blocked by joint limits: the position is reachable only with joints "
                    f"beyond their limits (for example {what}); within the limits the "
                    f"nearest reachable point is {length(dist, units)} away"), **near, **common)

    outside = where_outside(robot, p, p_free, dist_free)
    verdict, reason = outside.where, reason_text(outside, robot, units)
    if dist > dist_free * (1 + 1e-6) + ACCEPT_POSITION * L:
        reason += ("; within the joint limits the nearest reachable point is "
                   f"{length(dist, units)} away")
    return ReachResult(verdict=verdict, distance=dist, reason=reason, **near, **common)


def _violation_dict(robot, v, units) -> dict:
    from .results import json_numbers
    i, amount, side = v
    j = robot.joints[i]
    f = units.a if j.revolute else units.l
    limit = robot.limits[i][0 if side == "lower" else 1]
    return {"joint": j.name, "side": side, "by": json_numbers(amount * f), "limit": json_numbers(limit * f)}


def _violation_text(robot, v, units) -> str:
    d = _violation_dict(robot, v, units)
    unit = units.angle if robot.joints[v[0]].revolute else length_suffix(units).strip()
    return (f"{d['joint']} {d['by']:.4g} {unit} beyond its {d['side']} limit "
            f"{d['limit']:.4g} {unit}").replace("  ", " ")


def _blocked(robot, sols, units):
    """Per solution: its branch and violations; and a sentence naming the solution
    that misses its limits by the least (the largest violation, scaled)."""
    blocked = [{"branch": s.branch,
                "violations": [_violation_dict(robot, v, units) for v in s.violations]}
               for s in sols]
    L = max(robot.characteristic_length, 1e-12)

    def excess(s):   # (total, largest) violation, prismatic ones per robot length
        v = [a / (1.0 if robot.joints[i].revolute else L) for i, a, _ in s.violations]
        return sum(v), max(v)
    best = min(sols, key=excess)
    what = ", ".join(_violation_text(robot, v, units) for v in best.violations)
    n = len(sols)
    return blocked, (f"blocked by joint limits: {'all ' if n > 1 else ''}{n} solution"
                     f"{'s violate' if n > 1 else ' violates'} a limit; the closest, "
                     f"{best.branch}, needs {what}")
