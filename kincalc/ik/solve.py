"""Inverse kinematics of one target: every solution, labelled, checked and explained.

:func:`solve` is the engine (:func:`kincalc.ik.engine.solve_targets`) run on a batch of
one, turned into an :class:`IKResult`: the solutions (valid slots) with their labels,
residuals, limit violations and singularity; why there is none when there is none
(:func:`kincalc.ik.verdict.reason`); and on request the branches that do not reach the target
(``all_branches``: the candidates FK rejected, the textbook's cross combinations of
the solutions' joint values, the steps that found no real root) and the intermediate
quantities of each solution (``explain``). Robots no closed form covers are solved
numerically (:mod:`kincalc.ik.numeric`). The reasons are data (:mod:`kincalc.ik.reasons`,
SI); :mod:`kincalc.analysis.words` words them in the user's units.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import TargetMismatch
from .engine import Solved, singular, solve_targets
from .continua import Continuum, Followers, ParallelContinuum, followers
from .families import plan
from .joint_limits import joint_scale, same_solution, violations
from .labels import solution_order
from .reasons import Answered, Missed, NoRoot, NumericFound, NumericMissed, OutOfReach
from ..spatial import turn_toward, wrap
from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION
from .target import Targets
from .verdict import out_of_reach, reason as answer_reason

@dataclass(frozen=True)
class Target:
    """What IK must reach: a pose ``T`` (4x4, world, SI).

    ``orientation`` says whether the user gave an orientation; without one only the
    position counts (for robots that do not control orientation). ``tcv``: a tool
    configuration vector target, ``(approach (3,), last joint value q_n in rad)``; T then
    holds the position only. ``approach (3,)``: a unit approach direction (the tool z
    axis, world frame) to reach when no full orientation is given (five-joint arms).
    ``swivel``: for an arm with a spherical shoulder and wrist, the swivel angle of its
    elbow (rad, :mod:`kincalc.ik.swivel`) at which to reach the whole pose ``T``.
    """

    T: np.ndarray
    orientation: bool = True
    tcv: tuple | None = None
    approach: np.ndarray | None = None
    swivel: float | None = None

    @staticmethod
    def of(targets: Targets, i: int = 0) -> "Target":
        """Target ``i`` of a batch (the inverse of :meth:`targets`).

        Parameters
        ----------
        targets : Targets
        i : int

        Returns
        -------
        Target
            A copy of that target (world frame, SI).
        """
        T = targets.T[i].copy()
        if targets.kind == "tcv":
            return Target(T, orientation=False,
                          tcv=(targets.approach[i].copy(), float(targets.roll[i])))
        if targets.kind == "approach":
            return Target(T, orientation=False, approach=targets.approach[i].copy())
        if targets.kind == "swivel":
            return Target(T, swivel=float(targets.swivel[i]))
        return Target(T, orientation=targets.kind == "pose")

    def targets(self) -> Targets:
        """This target as a batch of one for the engine.

        Returns
        -------
        Targets
            ``N = 1``, of kind ``"tcv"``, ``"approach"``, ``"swivel"``, ``"pose"`` or
            (without an orientation) ``"position"``.
        """
        T = np.asarray(self.T, float)[None]
        if self.tcv is not None:
            a, qn = self.tcv
            return Targets(T, "tcv", approach=np.asarray(a, float)[None],
                           roll=np.array([float(qn)]))
        if self.approach is not None:
            return Targets(T, "approach", approach=np.asarray(self.approach, float)[None])
        if self.swivel is not None:
            return Targets(T, "swivel", swivel=np.array([float(self.swivel)]))
        return Targets(T, "pose" if self.orientation else "position")


@dataclass(frozen=True)
class IKSolution:
    q: np.ndarray
    branch: str
    position_error: float
    orientation_error: float | None
    within_limits: bool
    violations: list          # (joint index, amount beyond the limit, 'lower'|'upper'), SI
    singular: bool
    #: joints the target leaves undetermined (indices; a representative value is shown)
    free: tuple = ()
    continuum: object = None      # the relation left free at a singularity (Continuum, ...)
    #: with ``explain``: the steps the closed form noted (a list, empty where it noted
    #: none: the general 6R elimination); None without
    trace: list | None = None
    #: change from the --near configuration (n,), rad / m, when one was given
    change: np.ndarray | None = None


@dataclass(frozen=True)
class IKResult:
    robot: object
    target: Target
    family: str
    method: str
    controls: str
    solutions: list
    reachable: bool
    #: why the answer is what it is (a reason of :mod:`kincalc.ik.reasons`, SI)
    reason: object
    #: with all_branches: dicts of q, branch, residuals and reason (a ``Missed``)
    rejected: list | None = None
    units: object = None
    note: str | None = None
    near: np.ndarray | None = None
    #: with all_branches: why each branch that found nothing found nothing (``NoRoot``)
    dead_ends: list | None = None
    #: joints held at a value, ``((index, value), ...)`` (rad / m), when the answer is of
    #: the chain they leave (:mod:`kincalc.analysis.redundancy`)
    locked: tuple = ()
    # rendered by kincalc.analysis.results.ik_document (JSON and tables) and kincalc.analysis.words


def solve(robot, target: Target, *, all_branches: bool = False, explain: bool = False,
          units=None, near=None, numeric: bool = False, reasons: bool = True) -> IKResult:
    """Every IK solution of ``robot`` for ``target`` as an :class:`IKResult`.

    Parameters
    ----------
    robot : Robot
    target : Target
        The pose ``T_world_tool`` (world frame, SI) and what of it counts.
    all_branches : bool
        Also list the branches that do not reach the target (``rejected``: FK rejects and
        the cross combinations) and the steps that found no real root (``dead_ends``).
    explain : bool
        Give each solution the intermediate quantities of its steps (``trace``).
    units : optional
        Display units, kept on the result for rendering.
    near : array_like (n,), optional
        The current joints (rad / m): analytic solutions are then ordered by their change
        from it (moved by whole turns, within the limits, towards it), and the numerical
        solver starts there.
    numeric : bool
        Find the one solution nearest ``near`` (default: the home joints) numerically
        (:mod:`kincalc.ik.numeric`); also done for a robot no analytic family covers.
    reasons : bool
        Find why the answer is what it is (``reason``: for a target out of reach, a search
        for the nearest reachable point, some 0.1 s). False: ``reason`` is None, for a
        caller that shows none (``ik --batch`` records).

    Returns
    -------
    IKResult
        Solutions within the limits first; ``reason`` says why the answer is what it is.

    Raises
    ------
    TargetMismatch
        The target's kind does not fit the robot's family (or an approach target for a
        robot solved numerically, or a TCV target the robot cannot take).
    """
    S, family, why = plan(robot)
    if near is not None:
        near = np.asarray(near, float).reshape(robot.dof)
    if target.tcv is None and target.swivel is None and (family is None or numeric):
        result = _solve_numerical(robot, target, near, units,
                                  why if family is None else "asked for", reasons)
        if all_branches:       # one solution, found numerically: there are no branches
            result = replace(result, rejected=[], dead_ends=[], note=(
                "none: the numerical solver finds one solution, not the branches"))
        return result
    # the steps record their intermediate quantities (explain) and their dead ends
    # (all_branches) only when asked: a batch of poses records nothing
    targets = target.targets()
    sv = solve_targets(robot, targets, explain=explain or all_branches)
    family = sv.spec
    T = np.asarray(target.T, float)
    sols, rejected = _solutions(robot, sv, explain, targets.kind)
    sols = [sols[k] for k in solution_order([s.branch for s in sols],
                                            [s.within_limits for s in sols]).tolist()]
    if near is not None:
        sols = [replace(s, q=q, change=q - near) for s in sols
                for q in [_toward(robot, s.q, near, targets.kind)]]
        sols.sort(key=lambda s: (not s.within_limits, _scaled_norm(robot, s.change)))
    reachable = any(s.within_limits for s in sols)
    reason = answer_reason(robot, family, T, target, sols, rejected) if reasons else None
    result_rejected = note = dead = None
    if all_branches:
        from .combinations import cross_combinations
        combos, note = cross_combinations(robot, family.name, T, target.orientation, sols)
        result_rejected = []
        for r in rejected + combos:
            if not any(same_solution(robot, r["q"], o["q"]) for o in result_rejected):
                result_rejected.append(r)
        dead = _dead_ends(robot, sv)
    return IKResult(robot=robot, target=target, family=family.name, method=sv.method,
                    controls=family.controls, solutions=sols, reachable=reachable,
                    reason=reason, rejected=result_rejected, units=units, note=note, near=near,
                    dead_ends=dead)


def _solutions(robot, sv: Solved, explain: bool, kind: str):
    """``(solutions, rejected candidates)`` of the engine's single target, of ``kind``."""
    slots = [k for k, c in enumerate(sv.candidate[0].tolist()) if c]
    if not slots:
        return [], []
    q = list(sv.q[0])
    pe = sv.position_error[0].tolist()
    oe = sv.orientation_error[0].tolist()
    if all(oe[k] != oe[k] for k in slots):          # NaN: no orientation checked
        oe = [None] * len(oe)
    valid = sv.valid[0].tolist()
    branch = sv.labels[0].tolist()
    if any(valid):
        singular = sv.singular[0].tolist()
        within, violation = sv.within[0].tolist(), sv.violation[0].tolist()
        free = sv.free[0].tolist() if np.count_nonzero(sv.free[0]) else None    # rarely any
    sols, rejected = [], []
    for k in slots:
        if not valid[k]:
            if not _is_copy(robot, sv, k):
                rejected.append({"q": q[k], "branch": branch[k], "position_error": pe[k],
                                 "orientation_error": oe[k],
                                 "reason": _why_not(robot, sv, k, pe[k], oe[k])})
            continue
        viol = [] if within[k] else _violation_list(violation[k])
        joints = () if free is None else tuple(j for j, f in enumerate(free[k]) if f)
        sol = object.__new__(IKSolution)        # every field, without a frozen __setattr__ each
        sol.__dict__.update(q=q[k], branch=branch[k], position_error=pe[k],
                            orientation_error=oe[k], within_limits=not viol, violations=viol,
                            singular=singular[k], free=joints,
                            continuum=_continuum(robot, sv, k, kind) if joints else None,
                            trace=_trace(sv, k) if explain else None, change=None)
        sols.append(sol)
    return sols, rejected


def _why_not(robot, sv: Solved, k: int, pe: float, oe):
    """Why slot ``k`` of the engine's single target is no solution: it misses the target
    (``Missed``), or it reaches it but a valid slot answers it (``Answered``, the joint that
    differs most from the nearest one; a double root's copy, a point of a continuum)."""
    valid = sv.valid[0]
    reaches = pe <= ACCEPT_POSITION * max(robot.characteristic_length, 1e-12) and \
        (oe is None or oe <= ACCEPT_ORIENTATION)
    if not reaches or not valid.any():
        return Missed(pe, oe)
    d = sv.q[0, valid] - sv.q[0, k]
    d = np.abs(np.where(robot.is_revolute, wrap(d), d)) / joint_scale(robot)
    nearest = int(np.argmin(d.max(-1)))
    joint = int(np.argmax(d[nearest]))
    return Answered(joint, float(d[nearest, joint] * joint_scale(robot)[joint]))


def _is_copy(robot, sv, k) -> bool:
    """A valid-looking duplicate of an earlier valid slot (dropped by the engine)."""
    earlier = sv.valid[0, :k]
    return bool(earlier.any() and same_solution(robot, sv.q[0, :k][earlier], sv.q[0, k]).any())


def violation_list(robot, q) -> list:
    """The limits the configuration ``q`` breaks (beyond :data:`~kincalc.tolerances.LIMIT_TOL`).

    Parameters
    ----------
    robot : Robot
    q : array_like (n,)
        Joint values (rad / m).

    Returns
    -------
    list of (int, float, str)
        ``(joint, amount, side)`` per broken limit, sorted by joint: the amount (rad / m,
        positive) beyond it, ``side`` ``"lower"`` or ``"upper"``.
    """
    return _violation_list(violations(robot, np.asarray(q, float)))


def _violation_list(v) -> list:
    """``(joint, amount, side)`` for the nonzero entries of ``v (n,)`` (joint_limits.violations; an
    array or a list)."""
    return [(i, float(-x if x < 0 else x), "lower" if x < 0 else "upper")
            for i, x in enumerate(v.tolist() if isinstance(v, np.ndarray) else v) if x != 0.0]


def _continuum(robot, sv: Solved, k: int, kind: str):
    """The relation a singular target (of ``kind``) leaves free in slot ``k``, as an object
    with ``text`` (:class:`~kincalc.ik.continua.Continuum`, ``ParallelContinuum``,
    ``Followers``)."""
    if sv.continuum is not None and sv.continuum[0, k, 0]:
        _, i, j, sign, total = sv.continuum[0, k].tolist()
        return _on_the_line(robot, sv.q[0, k], sv.free[0, k],
                            Continuum(int(i), int(j), int(sign), float(total)))
    parallel = sv.slot_extra("parallel continuum")
    if parallel is not None and parallel[0, k, 0]:
        # the joints about h (the solver's closing turn) and the free one, by its sense
        _, sigma, total, free, about, against = parallel[0, k].tolist()
        joints = [i for i in range(robot.dof) if int(about) >> i & 1] + [int(free)]
        signs = [-1 if int(against) >> i & 1 else 1 for i in joints[:-1]] + [int(sigma)]
        pairs = sorted(zip(joints, signs))
        return ParallelContinuum(tuple(i for i, _ in pairs), tuple(s for _, s in pairs),
                                 int(free), float(total))
    return _followers(robot, sv.q[0, k], np.flatnonzero(sv.free[0, k]).tolist(), kind)


def _followers(robot, q, free, kind: str):
    """The joints that follow the first of the ``free`` joints of solution ``q`` to keep a
    target of ``kind`` (``"pose"`` or ``"position"``), as a
    :class:`~kincalc.ik.continua.Followers`; None where it moves alone, or for another
    kind of target (an approach's free roll is open)."""
    if kind not in ("pose", "position"):
        return None
    J = robot.jacobian(q)
    J = J if kind == "pose" else J[:3]
    joints = followers(J, free, robot.characteristic_length, robot.is_revolute)
    return Followers(free[0], joints) if joints else None


def _on_the_line(robot, q, free, c: Continuum):
    """``c``, or where another free revolute joint turns about the same line as joints
    ``c.i`` and ``c.j`` at ``q`` (a wrist at q5 = 0 whose line is axis 1: the wrist centre
    on it too), the relation of all three, ``q_f s_f + q_i + sign q_j`` (a
    :class:`~kincalc.ik.continua.ParallelContinuum`, joint f free)."""
    others = [f for f in np.flatnonzero(free).tolist()
              if f not in (c.i, c.j) and robot.is_revolute[f]]
    if not others:
        return c
    from ..fk import chain_frames
    F = chain_frames(robot.chain, q)
    z, o = F[:, :3, 2], F[:, :3, 3]
    tol = 1e-9 * max(robot.characteristic_length, 1e-12)
    for f in others:
        if np.linalg.norm(np.cross(z[f], z[c.i])) <= 1e-9 \
                and np.linalg.norm(np.cross(o[f] - o[c.i], z[c.i])) <= tol:
            s_f = 1 if float(z[f] @ z[c.i]) > 0 else -1
            terms = sorted([(f, s_f), (c.i, 1), (c.j, c.sign)])
            return ParallelContinuum(tuple(j for j, _ in terms), tuple(x for _, x in terms), f,
                                     c.total + s_f * float(q[f]))
    return c


def _trace(sv: Solved, k: int) -> list:
    """The intermediate quantities of slot ``k`` (``explain``), in the order noted."""
    br = sv.branches
    out = []
    for note in br.notes:
        slot = br.final_index(note.at)[k] if note.at < len(br.lineage) else k
        if slot < 0:                # a slot appended after this step (nearly.py)
            continue
        value = note.value[0, slot] if note.value.ndim >= 2 else note.value
        out.append((note.label, value.tolist() if isinstance(value, np.ndarray) else float(value),
                    note.kind))
    return out


def _dead_ends(robot, sv: Solved) -> list:
    """The steps that found no real root (``all_branches``), one :class:`NoRoot` per
    slot and step, joints numbered on the robot."""
    out = []
    n = robot.dof
    for d in sv.branches.dead_ends:
        for slot in np.flatnonzero(d.where[0]).tolist():
            out.append(NoRoot(n - 1 - d.joint if sv.spec.reverse else d.joint,
                              float(d.phase[0, slot]), float(d.need[0, slot]), d.what,
                              reversed_chain=bool(sv.spec.reverse)))
    return out


def _toward(robot, q, near, kind: str):
    """``q``'s revolute joints moved by whole turns towards ``near`` (``turn_toward``), but
    the last joint of a ``kind`` ``"tcv"`` target (the vector holds ``e^(q_n / pi)``)."""
    lo, hi = robot.limits.T
    turns = robot.is_revolute.copy()
    if kind == "tcv":
        turns[-1] = False
    return np.where(turns, turn_toward(q, near, lo, hi), q)


def _scaled_norm(robot, d) -> float:
    """|d| with revolute joints wrapped into (-pi, pi] (a change of a whole turn, made to
    keep a joint within its limits when ``near`` is beyond them, is the same
    configuration) and prismatic joints divided by the robot's characteristic length."""
    return float(np.linalg.norm(np.where(robot.is_revolute, wrap(d), d) / joint_scale(robot)))


def default_start(robot) -> np.ndarray:
    """The numerical solver's default start: the robot's home joints, inside the limits.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    ndarray (n,)
        ``robot.home`` clipped to the limits (rad / m).
    """
    lo, hi = robot.limits.T
    return np.clip(np.asarray(robot.home, float), lo, hi)


def _solve_numerical(robot, target, near, units, why, reasons=True) -> IKResult:
    """One solution by :func:`kincalc.ik.numeric.solve_numeric`, nearest ``near``
    (``reasons``: of :func:`solve`)."""
    if target.approach is not None:
        raise TargetMismatch(robot.name, "not approach", why=why)
    from .nearest import beyond_reach
    from .numeric import RESTARTS, solve_numeric
    start = default_start(robot) if near is None else near
    full, orientation = robot.generic_ranks[0], target.orientation
    T = np.asarray(target.T, float)
    res = None if beyond_reach(robot, T[:3, 3]) else solve_numeric(  # proven out of reach
        robot.fk, T, start, jacobian=robot.jacobian, limits=robot.limits,
        revolute=robot.is_revolute, scale=robot.characteristic_length, orientation=orientation)
    controls = ("position and orientation" if full >= 6 else
                f"{full} of the 6 pose components" if orientation else "position")
    method = ("Levenberg-Marquardt from the start configuration, then the least "
              "change from it; one solution, not every branch (" + why + ")")
    sols = []
    if res is not None and res.converged:
        from ..fk import frames_and_tool
        q = res.q
        viol = _violation_list(violations(robot, q))
        sing = bool(singular(robot, q[None], *frames_and_tool(robot.chain, q[None]))[0])
        sols.append(IKSolution(q=q, branch="nearest the start" if near is not None else
                               "nearest home", position_error=res.position_error,
                               orientation_error=res.orientation_error,
                               within_limits=not viol, violations=viol, singular=sing,
                               change=None if near is None else q - near))
        reason = NumericFound(res.restarts)
    elif not reasons:
        reason = None
    else:
        reason = out_of_reach(robot, T)
        if not isinstance(reason, OutOfReach):
            reason = NumericMissed(Missed(res.position_error, res.orientation_error), RESTARTS,
                                   full if orientation and full < 6 else None)
    reachable = bool(sols) and sols[0].within_limits
    return IKResult(robot=robot, target=target, family="numerical", method=method,
                    controls=controls, solutions=sols, reachable=reachable, reason=reason,
                    units=units, near=near)


