"""Inverse kinematics: every solution, labelled, checked and explained.

:func:`solve` recognises the robot's family from its joint axes
(:func:`kincalc.ik.families.classify`), runs that family's solver, and turns
the raw candidates into :class:`IKSolution` objects: joint values normalised
into the limits (or (-pi, pi]), FK residuals, limit violations, singularity,
and a branch label computed from the geometry of the solution.

Branch labels (stable: computed from the solution, not from solver order):

* ``shoulder left/right``: side of the wrist centre (or of the point where
  axes 5 and 6 meet) relative to the plane spanned by axis 1 and the
  common normal... precisely the sign of ``(P - o1) . (z1 x z2)``: right if
  positive; for arms whose axes 1 and 2 are not parallel.
* ``elbow up/down``: for parallel axes 2 and 3, whether the elbow (axis 3)
  lies on the side of the shoulder-to-wrist line that axis 1 points to.
* ``wrist flip/no-flip``: the sign of ``(z4 x z6) . z5`` at the solution.
* otherwise ``<joint>:+`` / ``<joint>:-`` for each step with two roots, and
  ``<joint>:root k`` for steps with more.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from ..spatial import cross

from ..errors import KincalcError, UsageError
from ..spatial import invert_transform, rotation_angle, rotation_error
from .cache import per_robot
from .families import SOLVERS, Candidate, plan
from .position import DEAD_ENDS
from .screws import Screws, wrap

#: a solution is accepted when its FK misses the target by at most this much
#: (relative to the robot's size) and this many radians.
ACCEPT_POSITION = 1e-9
ACCEPT_ORIENTATION = 1e-9
#: components a robot does not control (the orientation of a position-only arm) are
#: checked, not solved for: at a double root the joint values are only good to
#: ~sqrt(eps), so the check allows this much (rad)
CHECK_ORIENTATION = 1e-6
#: --all-branches lists cross combinations only up to this many
MAX_COMBINATIONS = 512


class UnsupportedRobot(KincalcError):
    exit_status = 2


@dataclass(frozen=True)
class Target:
    """What IK must reach: a pose ``T`` (4x4, world, SI).

    ``orientation`` says whether the user gave an orientation; without one
    only the position counts (for robots that do not control orientation).
    """

    T: np.ndarray
    orientation: bool = True
    #: a tool-configuration-vector target: (approach (3,), last joint value q_n in rad);
    #: T then holds the position only
    tcv: tuple | None = None
    #: an approach direction (3,), unit, world frame: the tool z axis to reach when no
    #: full orientation is given (five-joint arms); T then holds the position only
    approach: np.ndarray | None = None


@dataclass
class IKSolution:
    q: np.ndarray
    branch: str
    position_error: float
    orientation_error: float | None
    within_limits: bool
    violations: list          # (joint index, amount beyond the limit, 'lower'|'upper'), SI
    singular: bool
    singularity: str | None
    continuum: object = None      # families.Continuum: the relation left free at a singularity
    trace: list = field(default_factory=list)
    #: change from the --near configuration (n,), rad / m, when one was given
    change: np.ndarray | None = None


@dataclass
class IKResult:
    robot: object
    target: Target
    family: str
    method: str
    controls: str
    solutions: list
    reachable: bool
    reason: str
    rejected: list | None = None
    units: object = None
    note: str | None = None
    near: np.ndarray | None = None
    #: with --all-branches: why each branch that found nothing found nothing
    dead_ends: list | None = None

    def to_dict(self) -> dict:
        from ..results import _clean, _header
        u = self.units
        out = _header("ik", self.robot, u)
        out["target"] = {"T": u.pose(self.target.T), "orientation_given": self.target.orientation}
        if self.target.approach is not None:
            out["target"]["approach"] = _clean(np.asarray(self.target.approach, float))
        out.update({
            "reachable": self.reachable,
            "reason": self.reason,
            "method": {"family": self.family, "description": self.method,
                       "controls": self.controls},
            "count": len(self.solutions),
            "near": None if self.near is None else u.joints(self.robot, self.near),
            "solutions": [self._sol(s) for s in self.solutions],
        })
        if self.rejected is not None:
            out["rejected"] = [
                {"q": u.joints(self.robot, r["q"]), "branch": r["branch"], "reason": r["reason"],
                 "residual": {"position": _clean(r["position_error"] * u.l),
                              "orientation": None if r["orientation_error"] is None
                              else _clean(r["orientation_error"] * u.a)}}
                for r in self.rejected]
            if self.note:
                out["rejected_note"] = self.note
        if self.dead_ends is not None:
            out["dead_ends"] = self.dead_ends
        return out

    def _sol(self, s: IKSolution) -> dict:
        from ..results import _clean
        u = self.units
        names = [j.name for j in self.robot.joints]
        d = {
            "q": u.joints(self.robot, s.q),
            "branch": s.branch,
            "residual": {"position": _clean(s.position_error * u.l),
                         "orientation": None if s.orientation_error is None
                         else _clean(s.orientation_error * u.a)},
            "within_limits": s.within_limits,
            "violations": [{"joint": names[i], "side": side,
                            "by": _clean(amount * (u.a if self.robot.joints[i].revolute else u.l))}
                           for i, amount, side in s.violations],
            "singular": s.singular,
            "singularity": s.singularity,
            "continuum": None if s.continuum is None else s.continuum.text(
                names, u.angle, u.a),
        }
        if s.change is not None:
            d["change_from_near"] = u.joints(self.robot, s.change)
        if s.trace:
            d["trace"] = [{"step": k, "value": self._unit(v, kind)} for k, v, kind in s.trace]
        return d


    def _unit(self, v, kind):
        from ..results import _clean
        u = self.units
        if kind.startswith("joint:"):
            kind = "angle" if self.robot.joints[int(kind[6:])].revolute else "length"
        f = {"length": u.l, "length2": u.l ** 2, "angle": u.a}.get(kind)
        if isinstance(v, str):
            return v
        return _clean(np.asarray(v, float) * (1.0 if f is None else f))


def solve(robot, target: Target, *, all_branches: bool = False, explain: bool = False,
          units=None, near=None, numeric: bool = False) -> IKResult:
    """Every IK solution of ``robot`` for ``target`` as an :class:`IKResult`.

    ``near (n,)`` (rad / m): the current joints; analytic solutions are then
    ordered by their change from it, and the numerical solver starts there.
    ``numeric=True`` (or a robot no analytic family covers) finds the one
    solution nearest ``near`` numerically (:mod:`kincalc.ik.numeric`).
    """
    from ..results import Units
    units = units or Units(length=robot.length_unit)
    S, family, why = plan(robot)
    if near is not None:
        near = np.asarray(near, float).reshape(robot.dof)
    if target.tcv is not None:
        return _solve_tcv(robot, S, target, units)
    if family is None or numeric:
        return _solve_numerical(robot, target, near, units,
                                why if family is None else "asked for with --numeric")
    five = family.name in APPROACH_FAMILIES
    if target.approach is not None and family.needs_orientation and not five:
        raise UsageError(f"--approach: {robot.name} controls {family.controls}; give a full "
                         "orientation (--rpy, --quat, ...)")
    if family.needs_orientation and not target.orientation and target.approach is None:
        raise UsageError(f"{robot.name} controls {family.controls}: give an orientation too "
                         "(--rpy, --euler-zyz, --euler-xyz, --quat, --axis-angle, --matrix, "
                         "--tcv, --pose or --from-q)" +
                         (" or an approach direction (--approach)" if five else ""))
    T = np.asarray(target.T, float)
    if target.approach is not None:
        T = T.copy()
        T[:3, :3] = _frame_with_z(target.approach)
    solver = SOLVERS[family.solver]
    dead_ends: list = []
    token = DEAD_ENDS.set(dead_ends if all_branches else None)
    try:
        if family.name == "general-6r":
            cands = solver(S, T, explain, robot=robot)
        elif five:
            cands = solver(S, T, explain, approach_only=target.approach is not None)
        elif family.reverse:
            cands = [_unreverse(c, robot.dof, explain)
                     for c in solver(S.reversed(), invert_transform(T), explain)]
        else:
            cands = solver(S, T, explain)
    finally:
        DEAD_ENDS.reset(token)

    Q = np.array([np.asarray(c.q, float) for c in cands]).reshape(len(cands), robot.dof)
    method = family.description
    if not family.exact:
        cands, Q, method = _on_true_robot(robot, family, target, T, cands, Q, units)

    scale = max(robot.characteristic_length, 1e-12)
    accepted, rejected = [], []
    # FK, frames, Jacobians, labels and residuals of every candidate at once (the
    # per-candidate work is what a pose costs; the vectorised core does it in one pass)
    C = _constants(robot)
    Q = _normalise_rows(robot, Q, C)
    frames, Tq = _frames_and_pose(robot, Q, C)
    PE = np.linalg.norm(Tq[:, :3, 3] - T[:3, 3], axis=-1)
    OE = rotation_angle(np.swapaxes(T[:3, :3], -1, -2) @ Tq[:, :3, :3]) \
        if target.orientation else None
    if target.approach is not None:
        z = Tq[:, :3, 2]
        OE = np.arctan2(np.linalg.norm(cross(z, target.approach), axis=-1), z @ target.approach)
    o_tol = ACCEPT_ORIENTATION if family.needs_orientation else CHECK_ORIENTATION
    ok_all = PE <= ACCEPT_POSITION * scale
    if OE is not None:
        ok_all &= OE <= o_tol
    branches = _branch_labels(robot, family.name, cands, frames, C)
    PE_l = PE.tolist()
    OE_l = [None] * len(cands) if OE is None else OE.tolist()
    for k, c in enumerate(cands):
        q, pe, oe, branch = Q[k], PE_l[k], OE_l[k], branches[k]
        if not ok_all[k]:
            rejected.append({"q": q, "branch": branch, "position_error": pe,
                             "orientation_error": oe,
                             "reason": _miss_reason(pe, oe, units)})
            continue
        accepted.append((k, q, c, branch, pe, oe))
    keep = _dedupe_rows(robot, Q[[a[0] for a in accepted]].reshape(-1, robot.dof), C)
    accepted = [accepted[i] for i in keep]
    rows = [a[0] for a in accepted]
    singular = _singular_mask(robot, Q[rows].reshape(-1, robot.dof),
                              J=_jacobian_from_frames(frames[rows], Tq[rows], C), c=C)

    sols = []
    violations = _violations_rows(Q[rows].reshape(-1, robot.dof), C)
    for (_, q, c, branch, pe, oe), sing, viol in zip(accepted, singular.tolist(), violations):
        desc = _singularity(robot, q)[1] if sing else None
        if c.free:
            sing = True
            desc = (desc + "; " if desc else "") + "undetermined at this target: " + ", ".join(
                robot.joints[i].name for i in c.free) + " (a representative value is shown)"
        sols.append(IKSolution(q=q, branch=branch, position_error=pe, orientation_error=oe,
                               within_limits=not viol, violations=viol, singular=bool(sing),
                               singularity=desc, continuum=c.continuum, trace=c.trace))
    sols.sort(key=lambda s: (not s.within_limits, s.branch))
    if near is not None:
        for s_ in sols:
            s_.q = _toward(robot, s_.q, near)
            s_.change = s_.q - near
        sols.sort(key=lambda s_: (not s_.within_limits, _scaled_norm(robot, s_.change)))

    reachable = any(s.within_limits for s in sols)
    reason = _reason(robot, S, family, T, target, sols, rejected, units)
    result_rejected = note = None
    if all_branches:
        combos, note = _cross_combinations(robot, T, target, sols, units)
        result_rejected = []
        for r in rejected + combos:
            if not any(np.all(np.abs(np.where(robot.is_revolute, wrap(r["q"] - o["q"]),
                                              r["q"] - o["q"])) < 1e-6) for o in result_rejected):
                result_rejected.append(r)
    return IKResult(robot=robot, target=target, family=family.name, method=method,
                    controls=family.controls, solutions=sols, reachable=reachable,
                    reason=reason, rejected=result_rejected, units=units, note=note, near=near,
                    dead_ends=[_dead_end_text(robot, d, units, family.reverse)
                               for d in dead_ends] if all_branches else None)


def _on_true_robot(robot, family, target, T, cands, Q, units):
    """``(candidates, Q, method text)`` for a robot that is only nearly of ``family``
    (:func:`~kincalc.ik.families.classify`): the candidates of the nearest robot of the
    family (``plan``'s screws), refined by Newton's method on the robot itself
    (:mod:`kincalc.ik.refine`), and for six revolute joints joined by the general 6R
    elimination's solutions, which need no structure (so a solution near a singularity
    of the structured robot, where branches meet, is not lost). A continuum of the
    structured robot is not one of the true robot: the refined candidates are ordinary
    solutions, checked for singularity as any other."""
    from dataclasses import replace

    from .families import structure_defect
    from .refine import refine
    mode = "approach" if target.approach is not None else \
        "pose" if family.needs_orientation else "position"
    Q = refine(robot, Q, T, mode=mode, approach=target.approach)
    cands = [replace(c, q=q, free=[], continuum=None) for c, q in zip(cands, Q)]
    move, turn = structure_defect(Screws.of(robot), plan(robot)[0])
    method = (f"{family.description}; the axes have this structure only to within "
              f"{move * units.l:.2g}{_len(units)} and {turn:.2g} rad, so it was solved for "
              "the nearest robot that has it and every solution refined by Newton's method "
              "on the robot as given")
    if robot.dof == 6 and robot.is_revolute.all() and target.approach is None:
        from .general6r import solve_general_6r
        more = solve_general_6r(robot, T)
        cands = cands + [Candidate(q=q) for q in more]
        Q = np.vstack([Q, np.asarray(more, float).reshape(-1, 6)])
        method += ", and joined with the general 6R elimination's solutions"
    return cands, Q, method


def _dead_end_text(robot, text: str, units, reverse: bool) -> str:
    """A dead-end sentence with its ``{jI}`` joint and ``{aX}`` angle (rad) placeholders
    written in the robot's joint names and the display unit."""
    import re
    n = robot.dof

    def joint(m):
        i = int(m.group(1))
        return robot.joints[n - 1 - i if reverse else i].name

    text = re.sub(r"\{j(\d+)\}", joint, text)
    text = re.sub(r"\{a([-0-9.e+]+)\}",
                  lambda m: f"{float(m.group(1)) * units.a:.4g} {units.angle}", text)
    if reverse:
        text = ("on the reversed chain (each joint turned the other way): " + text)
    return text


def _toward(robot, q, near):
    """``q`` with each revolute joint moved by a multiple of 2 pi, inside its limits, to
    the value nearest ``near`` (a joint that may turn more than once takes the short way)."""
    q = np.array(q, float)
    lo, hi = robot.limits.T
    for i in np.flatnonzero(robot.is_revolute):
        options = [q[i] + 2 * np.pi * k for k in range(-3, 4)]
        options = [x for x in options if lo[i] - 1e-12 <= x <= hi[i] + 1e-12] or [q[i]]
        q[i] = min(options, key=lambda x: abs(x - near[i]))
    return q


def _scaled_norm(robot, d) -> float:
    """|d| with prismatic joints divided by the robot's characteristic length."""
    s = np.where(robot.is_revolute, 1.0, max(robot.characteristic_length, 1e-12))
    return float(np.linalg.norm(d / s))


def default_start(robot) -> np.ndarray:
    """The numerical solver's default start: the robot's home joints, inside the limits."""
    lo, hi = robot.limits.T
    return np.clip(np.asarray(robot.home, float), lo, hi)


def _solve_numerical(robot, target, near, units, why) -> IKResult:
    """One solution by :func:`kincalc.ik.numeric.solve_numeric`, nearest ``near``."""
    if target.approach is not None:
        raise UsageError(f"--approach: {robot.name} is solved numerically ({why}), which needs "
                         "a full orientation or the position alone")
    from .numeric import RESTARTS, solve_numeric
    start = default_start(robot) if near is None else near
    full = robot.generic_ranks[0]
    orientation = target.orientation
    T = np.asarray(target.T, float)
    res = solve_numeric(robot.fk, T, start, jacobian=robot.jacobian, limits=robot.limits,
                        revolute=robot.is_revolute, scale=robot.characteristic_length,
                        orientation=orientation)
    controls = ("position and orientation" if full >= 6 else
                f"{full} of the 6 pose components" if orientation else "position")
    method = ("Levenberg-Marquardt from the start configuration, then the least "
              "change from it; one solution, not every branch (" + why + ")")
    sols = []
    if res.converged:
        q = res.q
        viol = _violations(robot, q)
        sing = bool(_singular_mask(robot, q[None])[0])
        desc = _singularity(robot, q)[1] if sing else None
        sols.append(IKSolution(q=q, branch="nearest the start" if near is not None else
                               "nearest home", position_error=res.position_error,
                               orientation_error=res.orientation_error,
                               within_limits=not viol, violations=viol, singular=sing,
                               singularity=desc,
                               change=None if near is None else q - near))
        reason = "1 solution found numerically (the one with the least change from the start)"
        if res.restarts:
            reason += (f"; the start did not converge, restart {res.restarts} did: it may not be "
                       "the nearest solution")
    else:
        far = _out_of_reach(robot, T, units)
        if far.startswith("out of reach"):
            reason = far
        else:
            L = _len(units)
            miss = f"position off by {res.position_error * units.l:.4g}{L}"
            if res.orientation_error is not None:
                miss += f", orientation off by {res.orientation_error * units.a:.4g} {units.angle}"
            reason = (f"no solution found numerically from the start and {RESTARTS} restarts; "
                      f"the closest configuration found misses the target ({miss})")
            if orientation and full < 6:
                reason += (f": the robot controls only {full} of the 6 pose components, "
                           "give the position alone")
    reachable = bool(sols) and sols[0].within_limits
    return IKResult(robot=robot, target=target, family="numerical", method=method,
                    controls=controls, solutions=sols, reachable=reachable, reason=reason,
                    units=units, near=near)


#: the families that control the tool's approach direction but not the roll about it
APPROACH_FAMILIES = ("position-approach", "pitch-roll")


def _frame_with_z(a) -> np.ndarray:
    """A rotation whose z axis is the unit vector ``a`` (x and y chosen)."""
    z = np.asarray(a, float) / np.linalg.norm(a)
    x = cross([0.0, 1.0, 0.0] if abs(z[1]) < 0.9 else [1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, cross(z, x), z])


def _unreverse(c, n: int, explain: bool):
    """A candidate of the reversed chain (see :meth:`Screws.reversed`) for the robot:
    ``q = -q'[::-1]``, joint k of the reversed chain being joint n - 1 - k (0-based)."""
    from .families import Candidate
    trace = c.trace
    if explain:
        trace = [("chain reversed: the solver works on T^-1, joint k of the reversed "
                  f"chain is joint {n + 1} - k turned the other way; values below are "
                  "the reversed chain's", "", "none")] + list(trace)
    return Candidate(q=-np.asarray(c.q, float)[::-1],
                     signs={n - 1 - i: v for i, v in c.signs.items()},
                     free=[n - 1 - i for i in c.free],
                     continuum=None if c.continuum is None else c.continuum.reversed(n),
                     trace=trace)


def _solve_tcv(robot, S, target, units) -> IKResult:
    """A TCV target w = [p; e^(qn/pi) r3] (Schilling 1990; the FER Zagreb homework):
    the last joint's value comes from |w[3:]|, the other joints place the tool point,
    and the approach vector r3 is checked."""
    from .position import place_point
    n = robot.dof
    if not robot.joints[-1].revolute or n - 1 not in (2, 3):
        raise UnsupportedRobot(
            f"{robot.name}: --tcv targets need a robot of 3 or 4 joints whose last joint is "
            "revolute (the tool roll); give the pose another way")
    approach, qn = target.tcv
    p = target.T[:3, 3]
    tool0 = S.exp(n - 1, qn) @ S.M
    scale = max(robot.characteristic_length, 1e-12)
    sols, rejected = [], []
    for ps in place_point(S, list(range(n - 1)), tool0[:3, 3], p):
        q = _normalise(robot, np.concatenate([ps.x, [qn]]))
        Tq = robot.fk(q)
        pe = float(np.linalg.norm(Tq[:3, 3] - p))
        ae = float(np.arccos(np.clip(Tq[:3, 2] @ approach, -1, 1)))
        cand = type("C", (), {"signs": ps.signs, "free": ps.free})()
        branch = branch_label(robot, S, "tcv", q, cand)
        if pe > ACCEPT_POSITION * scale or ae > CHECK_ORIENTATION:
            rejected.append((q, branch, pe, ae))
            continue
        viol = _violations(robot, q)
        sing, desc = _singularity(robot, q)
        sols.append(IKSolution(q=q, branch=branch, position_error=pe, orientation_error=ae,
                               within_limits=not viol, violations=viol, singular=sing,
                               singularity=desc))
    reachable = any(s.within_limits for s in sols)
    if sols:
        reason = _count_text(sols)
    elif rejected:
        best = min(rejected, key=lambda r: r[3])
        reason = (f"the position is reachable but the approach vector is not: the best "
                  f"solution's approach is off by {best[3] * units.a:.4g} {units.angle}")
    else:
        reason = _out_of_reach(robot, target.T, units)
    return IKResult(robot=robot, target=target, family="tcv",
                    method=f"tool configuration vector: joint {n} from |w4..w6|, joints 1-{n - 1} "
                           "place the tool point, the approach vector r3 is checked",
                    controls="position, approach and roll", solutions=sols,
                    reachable=reachable, reason=reason, units=units)


def _violations(robot, q, c=None) -> list:
    """``(joint index, amount beyond the limit, 'lower'|'upper')`` for each violated limit.
    ``c``: the robot's :func:`_constants` when already at hand."""
    c = c or _constants(robot)
    q = np.asarray(q, float).tolist()
    return sorted([(i, lo - x, "lower") for i, (x, lo) in enumerate(zip(q, c.lo_list))
                   if x < lo - 1e-12] +
                  [(i, x - hi, "upper") for i, (x, hi) in enumerate(zip(q, c.hi_list))
                   if x > hi + 1e-12])


def _violations_rows(Q, c) -> list:
    """:func:`_violations` of each row of ``Q (k, n)``: the limits compared for all rows
    at once, the lists built only for rows that violate one."""
    low = Q < c.lo - 1e-12
    high = Q > c.hi + 1e-12
    bad = (low | high).any(axis=1)
    return [_violations(None, q, c) if b else [] for q, b in zip(Q, bad.tolist())]


def _count_text(sols) -> str:
    n_in = sum(s.within_limits for s in sols)
    return f"{len(sols)} solution{'s' if len(sols) != 1 else ''}, {n_in} within the joint limits"


@dataclass(frozen=True)
class _Constants:
    """Per-robot facts the post-processing of every pose needs (built once per robot)."""

    revolute: np.ndarray      # (n,) bool
    lo: np.ndarray            # (n,) lower limits, rad / m (-inf when unlimited)
    hi: np.ndarray
    lo_list: list             # the same as Python floats
    hi_list: list
    fixed: np.ndarray         # (n + 1, 4, 4) the chain's fixed transforms
    offset: np.ndarray        # (n,) the chain's joint offsets


@per_robot
def _constants(robot) -> _Constants:
    lo, hi = robot.limits.T
    ch = robot.chain
    arrays = [robot.is_revolute, lo.copy(), hi.copy(), np.array(ch.fixed, float),
              np.array(ch.offset, float)]
    for a in arrays:
        a.setflags(write=False)            # shared by every call for this robot
    rev, lo, hi, fixed, offset = arrays
    return _Constants(rev, lo, hi, lo.tolist(), hi.tolist(), fixed, offset)


def _normalise(robot, q):
    """Revolute joints into (-pi, pi], or shifted by 2 pi into their limits."""
    return _normalise_rows(robot, np.asarray(q, float)[None])[0]


def _normalise_rows(robot, Q, c=None):
    """:func:`_normalise` of each row of ``Q (k, n)`` (a new array)."""
    c = c or _constants(robot)
    Q = np.array(Q, float)
    rev = c.revolute
    if not rev.any() or len(Q) == 0:
        return Q
    x = wrap(Q[:, rev])
    lo, hi = c.lo[rev] - 1e-12, c.hi[rev] + 1e-12
    done = (lo <= x) & (x <= hi)
    if not done.all():
        for shift in (2 * np.pi, -2 * np.pi, 4 * np.pi, -4 * np.pi):
            y = x + shift
            fit = ~done & (lo <= y) & (y <= hi)
            x = np.where(fit, y, x)
            done |= fit
    Q[:, rev] = x
    return Q


def _dedupe_rows(robot, Q, c=None) -> list:
    """Indices of the rows of ``Q (k, n)`` to keep, in order: each row unless it is
    within 1e-6 (wrapped for revolute joints) of an earlier kept one."""
    if len(Q) < 2:
        return list(range(len(Q)))
    rev = (c or _constants(robot)).revolute
    D = np.abs(Q[:, None, :] - Q[None, :, :])
    # wrapped distance of revolute joints: the difference taken the short way round
    Dr = np.mod(D[..., rev], 2 * np.pi)
    D[..., rev] = np.minimum(Dr, 2 * np.pi - Dr)
    close = np.all(D < 1e-6, axis=-1)
    if not np.triu(close, 1).any():                 # no two rows alike: the common case
        return list(range(len(Q)))
    close = close.tolist()
    kept = []
    for i, row in enumerate(close):
        if not any(row[j] for j in kept):
            kept.append(i)
    return kept


def _frames_and_pose(robot, Q, c=None):
    """``(frames (k, n, 4, 4), tool poses (k, 4, 4))`` of ``Q (k, n)``: the frames of
    :func:`kincalc.fk.chain_frames` (just after each joint's motion) and the tool pose,
    the last frame times the chain's last fixed transform."""
    from ..fk import chain_frames
    c = c or _constants(robot)
    frames = chain_frames(robot.chain, Q)
    return frames, frames[:, -1] @ c.fixed[-1]


def _jacobian_from_frames(frames, Tq, c) -> np.ndarray:
    """The base-frame geometric Jacobian ``(k, 6, n)`` from joint frames and tool poses
    (the columns of :func:`kincalc.jacobian.jacobian_base`)."""
    rev = c.revolute
    k, n = frames.shape[:2]
    J = np.zeros((k, 6, n))
    z = frames[:, :, :3, 2]
    lin = cross(z, Tq[:, None, :3, 3] - frames[:, :, :3, 3])
    J[:, :3, :] = np.where(rev[:, None], lin, z).transpose(0, 2, 1)
    J[:, 3:, :] = np.where(rev[:, None], z, 0.0).transpose(0, 2, 1)
    return J


def _singular_mask(robot, Q, J=None, c=None) -> np.ndarray:
    """``(k,)`` bool: is each configuration singular (rank below the generic rank of J
    or of its linear rows, on the length-normalised Jacobian, as jacobian_report)?
    ``J`` (k, 6, n): the base-frame Jacobians at ``Q`` when already known."""
    from ..tolerances import SINGULAR_TOL
    if len(Q) == 0:
        return np.zeros(0, bool)
    J = robot.jacobian(Q) if J is None else J.copy()
    L = robot.characteristic_length
    J[:, :3, :] /= L
    J[:, :, ~(c or _constants(robot)).revolute] *= L
    full, full_pos = robot.generic_ranks

    def rank(M):
        sv = np.linalg.svd(M, compute_uv=False)
        return np.sum(sv > SINGULAR_TOL * np.maximum(sv[:, :1], 1.0), axis=-1)
    rJ = rank(J)
    out = rJ < full
    # rank 6 of J (6 x 6) gives rank 3 of its first three rows: their smallest singular
    # value is at least J's (interlacing) and their threshold at most J's
    rest = ~((rJ == 6) & (J.shape[1:] == (6, 6)) & (full_pos == 3))
    if rest.any():
        out[rest] |= rank(J[rest, :3, :]) < full_pos
    return out


def _singularity(robot, q):
    from ..analysis import jacobian_report
    rep = jacobian_report(robot, q)
    if rep.singularity is None:
        return False, None
    return True, "; ".join(rep.singularity.descriptions)


def _len(units) -> str:
    return "" if units.length == "unitless" else f" {units.length}"


def _miss_reason(pe, oe, units):
    parts = []
    if pe > 0:
        parts.append(f"position off by {pe * units.l:.4g}{_len(units)}")
    if oe:
        parts.append(f"orientation off by {oe * units.a:.4g} {units.angle}")
    return "does not reach the target: " + ", ".join(parts)


def _reason(robot, S, family, T, target, sols, rejected, units) -> str:
    if any(s.within_limits for s in sols):
        return _count_text(sols)
    if sols:
        worst = {}
        for s in sols:
            for i, amount, side in s.violations:
                worst[i] = min(worst.get(i, np.inf), amount)
        what = ", ".join(
            f"{robot.joints[i].name} by {amount * (units.a if robot.joints[i].revolute else units.l):.4g}"
            f"{' ' + units.angle if robot.joints[i].revolute else _len(units)}"
            for i, amount in sorted(worst.items()))
        return f"blocked by joint limits: all {len(sols)} solutions violate a limit ({what})"
    if rejected:
        placed = _placing(robot, rejected)
        if not placed:
            best = min(rejected, key=lambda r: (r["position_error"], r["branch"]))
            return "no solution: " + best["reason"]
        what = "approach direction" if target.approach is not None else "orientation"
        head = (f"the position is reachable but this {what} is not for a robot that controls "
                f"{family.controls}: ")
        if family.name in APPROACH_FAMILIES and target.approach is None \
                and _reach_approach(robot, placed, T[:3, 2]):
            # the five-joint solvers place the tool and its approach: what is left is the
            # roll about the approach, one value per solution of the family
            rolls = ", ".join(f"{_angle_text(r['orientation_error'], units)} ({r['branch']})"
                              for r in placed)
            return (head + f"the {_count_words(len(placed))} that reach the position and "
                    f"the approach leave the roll about it off by {rolls}")
        best = placed[0]
        return (head + f"the closest solution ({best['branch']}) is off by "
                f"{_angle_text(best['orientation_error'], units)}")
    return _out_of_reach(robot, T, units)


def _placing(robot, rejected) -> list:
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
    return bool(np.all(np.linalg.norm(cross(z, a), axis=-1) <= ACCEPT_ORIENTATION)
                and np.all(z @ a > 0))


def _angle_text(angle, units) -> str:
    return f"{(angle or 0.0) * units.a:.4g} {units.angle}"


def _count_words(n: int) -> str:
    return "solution" if n == 1 else f"{n} solutions"


def _out_of_reach(robot, T, units) -> str:
    """Why nothing was found, from the nearest reachable position (see
    :mod:`kincalc.reach`): out of reach of the geometry and where, out of reach
    within the limits, or within reach (then the pose as a whole is not)."""
    from ..reach import POSITION_TOL, _where_outside, nearest_position, unlimited
    p = np.asarray(T, float)[:3, 3]
    tol = POSITION_TOL * max(robot.characteristic_length, 1e-12)
    L = _len(units)
    _, _, dist = nearest_position(robot, p)
    if dist <= tol:
        return "no solution: the arm cannot place its tool at this pose"
    _, p_free, dist_free = nearest_position(robot, p, limits=unlimited(robot))
    if dist_free <= tol:
        return (f"out of reach within the joint limits: the nearest position reachable "
                f"within them is {dist * units.l:.6g}{L} away")
    _, reason = _where_outside(robot, p, p_free, dist_free,
                               lambda x: f"{x * units.l:.6g}{L}")
    return "out of reach: " + reason


def _cross_combinations(robot, T, target, sols, units):
    """Combinations of joint values taken independently, as a textbook's +/- choices
    are, that do not reach the target (Bingul & Kucuk, Example 4.2: zeta1, zeta4).

    Returns ``(rejected, note)``; ``note`` says why nothing was listed when there
    are more than :data:`MAX_COMBINATIONS` combinations.
    """
    if len(sols) < 2:
        return [], None
    values = []
    for i in range(robot.dof):
        vals = []
        for s in sols:
            if not any(abs(wrap(s.q[i] - v)) < 1e-6 for v in vals):
                vals.append(s.q[i])
        values.append(vals)
    total = int(np.prod([len(v) for v in values]))
    if total > MAX_COMBINATIONS:
        return [], (f"{total} combinations of the solutions' joint values: too many to list "
                    f"(at most {MAX_COMBINATIONS})")
    out = []
    for combo in itertools.product(*values):
        q = np.array(combo)
        if any(np.all(np.abs(wrap(q - s.q)) < 1e-6) for s in sols):
            continue
        Tq = robot.fk(q)
        pe = float(np.linalg.norm(Tq[:3, 3] - T[:3, 3]))
        oe = float(rotation_error(Tq[:3, :3], T[:3, :3])) if target.orientation else None
        out.append({"q": q, "branch": "combination of the solutions' values",
                    "position_error": pe, "orientation_error": oe,
                    "reason": _miss_reason(pe, oe, units)})
    return out, None


def branch_label(robot, S: Screws, family: str, q, cand, F=None) -> str:
    """Geometric branch label of solution ``q`` (see module docstring); ``F`` are its
    joint frames (``chain_frames``) when already computed."""
    from ..fk import chain_frames
    if F is None:
        F = chain_frames(robot.chain, np.asarray(q, float))
    return _branch_labels(robot, family, [cand], np.asarray(F)[None])[0]


def _branch_labels(robot, family: str, cands, F, c=None) -> list:
    """:func:`branch_label` of every candidate at once; ``F (k, n, 4, 4)`` their joint
    frames. The geometric words come from :func:`branch_geometry` for all candidates in
    one pass; the +/- choices of the other steps are added per candidate."""
    codes = branch_geometry(robot, family, F, c).tolist()
    names = [j.name for j in robot.joints]
    out = []
    for row, cand in zip(codes, cands):
        parts = [WORDS[w][x - 1] for w, x in enumerate(row) if x]
        named = set().union(*(_NAMED[w] for w, x in enumerate(row) if x))
        parts += [f"{names[j]}:{cand.signs[j]}" for j in sorted(cand.signs) if j not in named]
        if cand.free:
            parts.append("(" + ", ".join(names[j] for j in cand.free) + " free)")
        out.append(" ".join(parts) if parts else "unique")
    return out


#: the geometric words of a branch label, for the codes 1 and 2 of :func:`branch_geometry`
WORDS = (("shoulder right", "shoulder left"), ("elbow up", "elbow down"),
         ("wrist no-flip", "wrist flip"))
#: the joints whose +/- choice each word already names (shoulder 1, elbow 2 and 3, wrist 5)
_NAMED = ({0}, {1, 2}, {4})


def branch_geometry(robot, family: str, F, c=None) -> np.ndarray:
    """The geometric words of the branch labels of solutions with joint frames
    ``F (k, n, 4, 4)`` (:func:`kincalc.fk.chain_frames`, world frame): codes ``(k, 3)``
    for (shoulder, elbow, wrist), each 0 where the word does not apply, else 1 or 2 for
    the first or second word of :data:`WORDS` (see the module docstring for the rules).

    The point P of the rules (the wrist centre of a spherical wrist, where axes 5 and 6
    meet on a UR arm) is fixed in the frame of the joint before those axes, so it is
    carried from its coordinates there (:func:`_meeting_point_local`) instead of being
    intersected anew for every solution. ``c``: the robot's :func:`_constants`.
    """
    F = np.asarray(F, float)
    k = len(F)
    codes = np.zeros((k, 3), np.int8)
    first = {"spherical-wrist": 3, "three-parallel": 4}.get(family)
    if first is None or k == 0:
        return codes
    z, o = F[:, :, :3, 2], F[:, :, :3, 3]
    rev = (c or _constants(robot)).revolute
    local = _meeting_point_local(robot, first)
    if local is not None:
        P = (F[:, first - 1, :3, :3] @ local[:, None])[..., 0] + o[:, first - 1]
        if rev[0]:
            n01 = cross(z[:, 0], z[:, 1])
            side = np.einsum("ij,ij->i", P - o[:, 0], n01)
            codes[:, 0] = np.where(np.linalg.norm(n01, axis=-1) > 1e-6,
                                   np.where(side >= 0, 1, 2), 0)
        if robot.dof >= 3 and rev[1] and rev[2]:
            # the elbow (axis 3) against the shoulder-to-target line, in the plane of the
            # parallel axes 2 and 3; the target is P, or axis 4 for a UR arm
            sh, el, h = o[:, 1], o[:, 2], z[:, 1]
            tgt = P if family == "spherical-wrist" else o[:, 3]
            line = tgt - sh
            line = line - h * np.einsum("ij,ij->i", h, line)[:, None]
            v = el - sh
            v = v - h * np.einsum("ij,ij->i", h, v)[:, None]
            ll = np.maximum(np.einsum("ij,ij->i", line, line), 1e-300)
            perp = v - line * (np.einsum("ij,ij->i", v, line) / ll)[:, None]
            up = np.einsum("ij,ij->i", perp, z[:, 0])
            # the elbow on the line (stretched or folded): the turn sense decides
            alt = np.einsum("ij,ij->i", cross(el - sh, tgt - el), h)
            up = np.where(np.abs(up) < 1e-9 * robot.characteristic_length, alt, up)
            parallel = np.linalg.norm(cross(z[:, 1], z[:, 2]), axis=-1) < 1e-6
            codes[:, 1] = np.where(parallel, np.where(up >= 0, 1, 2), 0)
    w = np.einsum("ij,ij->i", cross(z[:, 3], z[:, 5]), z[:, 4])
    codes[:, 2] = np.where(w >= 0, 1, 2)
    return codes


@per_robot
def _meeting_point_local(robot, first: int):
    """Where axes ``first+1 .. n`` meet (least squares over their lines), ``(3,)`` in the
    coordinates of joint ``first``'s frame of :func:`kincalc.fk.chain_frames` (it moves
    only with the joints before them: the axes after it turn about lines through it), from
    the robot at q = 0; None if those axes are all parallel. Cached per robot."""
    from ..fk import chain_frames
    F = chain_frames(robot.chain, np.zeros(robot.dof))
    A, b = np.zeros((3, 3)), np.zeros(3)
    for j in range(first, robot.dof):
        Pj = np.eye(3) - np.outer(F[j, :3, 2], F[j, :3, 2])
        A += Pj
        b += Pj @ F[j, :3, 3]
    if np.linalg.svd(A, compute_uv=False)[-1] < 1e-6:
        return None
    P = np.linalg.solve(A, b)
    local = F[first - 1, :3, :3].T @ (P - F[first - 1, :3, 3])
    local.setflags(write=False)
    return local
