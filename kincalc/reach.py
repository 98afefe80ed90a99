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
``not-found``               the numerical solver found no solution although
                            the position is within reach (redundant arms)
==========================  ==================================================

``distance`` (m) is the distance from the target position to the nearest
position the tool reaches within the limits: zero when the position is
reachable. It is found by damped least squares
(:func:`kincalc.workspace.descend`) from the sampled configurations nearest
the target, so it is a local minimum: exact for the convex-ish sets of arms'
workspaces, an upper bound in general. Whether the limits are to blame is
decided by the same search with the limits removed.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .ik.solve import count_text, length_suffix

#: configurations sampled for the starts of the nearest-point search
SEARCH_SAMPLES = 4096
#: starts taken from the samples nearest the target
SEARCH_STARTS = 8
#: a position counts as reached when it is within this of the target (relative
#: to the robot's characteristic length)
POSITION_TOL = 1e-9


@dataclass
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
        from .results import _clean, _header
        u = self.units
        out = _header("reach", self.robot, u)
        out["target"] = {"T": u.pose(self.target.T),
                         "orientation_given": bool(self.target.orientation)}
        out.update({
            "reachable": self.reachable,
            "verdict": self.verdict,
            "reason": self.reason,
            "distance": None if self.distance is None else _clean(self.distance * u.l),
            "solutions": self.solutions,
            "solutions_within_limits": self.within_limits,
            "method": self.method,
            "nearest": None if self.nearest_q is None else {
                "q": u.joints(self.robot, self.nearest_q),
                "position": _clean(self.nearest_position * u.l)},
            "blocked": self.blocked,
        })
        return out


def _samples(robot, count: int, seed: int, limits=None) -> np.ndarray:
    """``(count, n)`` seeded joints uniform within ``limits`` (default the robot's);
    a bound that is infinite is replaced by a turn (revolute) or the robot's size
    (prismatic) beyond the other bound or zero. For search starts and shape tests."""
    lo, hi = (robot.limits if limits is None else np.asarray(limits, float)).T
    span = np.where(robot.is_revolute, np.pi, max(robot.characteristic_length, 1e-12))
    lo = np.where(np.isfinite(lo), lo, np.minimum(-span, hi - 2 * span))
    hi = np.where(np.isfinite(hi), hi, np.maximum(span, lo + 2 * span))
    return np.random.default_rng(seed).uniform(lo, hi, (count, robot.dof))


def unlimited(robot) -> np.ndarray:
    """``(n, 2)`` limits that hold no joint back (for :func:`nearest_position`)."""
    return np.column_stack([np.full(robot.dof, -np.inf), np.full(robot.dof, np.inf)])


def nearest_position(robot, p, *, limits=None, seed: int = 0):
    """The configuration whose tool point is nearest ``p (3,)`` (m, world), within
    ``limits (n, 2)`` (default the robot's). Returns ``(q (n,), tool point (3,),
    distance)``.

    The last few answers are remembered: ``reach`` asks again for what the IK
    reason already measured."""
    key = (tuple(np.asarray(p, float).reshape(3)),
           None if limits is None else tuple(np.asarray(limits, float).ravel()), seed)
    q, point, dist = _nearest(robot, key)
    return q.copy(), point.copy(), dist


@functools.lru_cache(maxsize=32)
def _nearest(robot, key):
    from .workspace import descend
    p, limits, seed = key
    p = np.array(p)
    if limits is not None:
        limits = np.array(limits).reshape(robot.dof, 2)
    Q = _samples(robot, SEARCH_SAMPLES, seed, limits)
    P = robot.fk(Q)[:, :3, 3]
    best = np.argsort(np.linalg.norm(P - p, axis=1))[:SEARCH_STARTS]
    X, pe, _ = descend(robot, Q[best], np.broadcast_to(p, (len(best), 3)), iterations=400,
                       limits=limits)
    k = int(np.argmin(pe))
    return X[k], robot.fk(X[k])[:3, 3], float(pe[k])


def reach(robot, target, *, units=None) -> ReachResult:
    """Can ``robot`` reach ``target`` (a :class:`~kincalc.ik.Target`)? See the module
    docstring for the verdicts."""
    from .ik import solve
    from .ik.families import plan
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
            why = inside[0].singularity or "the Jacobian loses rank"
            every = "at" if len(inside) == 1 else "every one of them at"
            return ReachResult(verdict="reachable-singular", distance=0.0, **common,
                               reason=f"{count_text(sols)}, {every} a singular "
                                      f"configuration: {why}; reachable, but not robustly")
        return ReachResult(verdict="reachable", distance=0.0, reason=count_text(sols),
                           **common)

    p = np.asarray(target.T, float)[:3, 3]
    q_near, p_near, dist = nearest_position(robot, p)
    near = dict(nearest_q=q_near, nearest_position=p_near)
    if sols:
        blocked, text = _blocked(robot, sols, units)
        return ReachResult(verdict="blocked-by-limits", distance=dist, blocked=blocked,
                           reason=text, **near, **common)

    if dist <= POSITION_TOL * L:
        if res.family == "numerical":
            return ReachResult(verdict="not-found", distance=0.0, reason=res.reason + (
                "; the position itself is within reach"), **near, **common)
        reason = res.reason
        if not reason.startswith("the position is reachable"):
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
    if dist <= POSITION_TOL * max(robot.characteristic_length, 1e-12):
        return ReachResult(verdict="reachable", distance=0.0, **near, **common,
                           reason="the position is reachable (with some orientation; give "
                                  "one to ask about the whole pose)")
    return _out_of_reach(robot, p, dist, near, common, units)


def _out_of_reach(robot, p, dist, near, common, units) -> ReachResult:
    """The position ``p`` is ``dist`` (> 0) from the nearest point reached within the
    limits: blocked by the limits, or out of reach of the geometry, and where."""
    L = max(robot.characteristic_length, 1e-12)
    q_free, p_free, dist_free = nearest_position(robot, p, limits=unlimited(robot))
    Lu = length_suffix(units)
    fmt = lambda x: f"{x * units.l:.6g}{Lu}"  # noqa: E731 - a local formatter
    if dist_free <= POSITION_TOL * L:
        from .ik.engine import normalise
        from .ik.solve import violation_list
        viol = violation_list(robot, normalise(robot, q_free))
        blocked = [_violation_dict(robot, v, units) for v in viol]
        what = ", ".join(_violation_text(robot, v, units) for v in viol)
        return ReachResult(
            verdict="blocked-by-limits", distance=dist, blocked=[{"branch": "numerical",
                                                                 "violations": blocked}],
            reason=(f"blocked by joint limits: the position is reachable only with joints "
                    f"beyond their limits (for example {what}); within the limits the "
                    f"nearest reachable point is {fmt(dist)} away"), **near, **common)

    verdict, reason = _where_outside(robot, p, p_free, dist_free, fmt)
    if dist > dist_free * (1 + 1e-6) + POSITION_TOL * L:
        reason += (f"; within the joint limits the nearest reachable point is {fmt(dist)} "
                   "away")
    return ReachResult(verdict=verdict, distance=dist, reason=reason, **near, **common)


def _where_outside(robot, p, p_near, dist, fmt):
    """Verdict and reason for a position out of reach even without joint limits,
    ``p_near`` being the nearest reachable point, ``dist`` away.

    Off the plane of a planar arm: outside the workspace. Otherwise the nearest
    point says which side the target is on: farther from the base than it, and
    roughly along the line from the base (within 60 deg), the target is beyond
    the outer reach; nearer the base than it, inside the inner void; anything
    else (a notch in the workspace) is outside the workspace."""
    from .workspace import _frame_of
    o = robot.base[:3, 3]
    origin, basis = _frame_of(robot.fk(_samples(robot, 512, 1))[:, :3, 3], robot)
    if basis.shape[1] < 3:
        rel = p - p_near
        off = float(np.linalg.norm(rel - basis @ (basis.T @ rel)))
        if off > 1e-6 * dist:
            kind = "plane" if basis.shape[1] == 2 else "line"
            return "outside-workspace", (
                f"outside the workspace: the tool moves in a {kind} and the target is "
                f"{fmt(off)} off it; the nearest reachable point is {fmt(dist)} away")
    d_target = float(np.linalg.norm(p - o))
    d_near = float(np.linalg.norm(p_near - o))
    radial = p_near - o
    cos = float((p - p_near) @ radial / max(np.linalg.norm(radial) * dist, 1e-300))
    if d_target > d_near and cos > 0.5:
        return "beyond-outer-reach", (
            f"beyond the outer reach by {fmt(dist)}: the target is {fmt(d_target)} from the "
            f"base, the arm reaches {fmt(d_near)} from it in this direction")
    if d_target < d_near:
        where = ("" if d_target <= 1e-12 * max(robot.characteristic_length, 1e-12)
                 else " in this direction")
        return "inside-inner-void", (
            f"inside the inner void by {fmt(dist)}: the target is {fmt(d_target)} from the "
            f"base, the arm reaches no closer than {fmt(d_near)}{where}")
    return "outside-workspace", (f"outside the workspace: the nearest reachable point is "
                                 f"{fmt(dist)} away")


def _violation_dict(robot, v, units) -> dict:
    from .results import _clean
    i, amount, side = v
    j = robot.joints[i]
    f = units.a if j.revolute else units.l
    limit = robot.limits[i][0 if side == "lower" else 1]
    return {"joint": j.name, "side": side, "by": _clean(amount * f), "limit": _clean(limit * f)}


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
