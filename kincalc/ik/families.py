"""Kinematic families recognised from the joint axes, and their solvers.

Each solver takes the robot's :class:`~kincalc.ik.screws.Screws` and a target
pose ``T`` (world frame, SI) and returns raw candidates: joint vectors with
the sign chosen at each step, the joints left free at a singular target, and
a trace of intermediate quantities. The dispatcher (:mod:`kincalc.ik.solve`)
polishes, normalises, labels and checks them.

Families (recognised from geometry, never from names):

* ``spherical-wrist``: 6 joints, the last three revolute with concurrent axes
  (Pieper 1968). Joints 1-3 (any R/P mix) place the wrist centre
  (:func:`~kincalc.ik.position.place_point`), the wrist gives the orientation
  by subproblems 2 and 1.
* ``three-parallel``: 6 revolute joints, axes 2, 3, 4 parallel and axes 5, 6
  intersecting (the UR family). Subproblem 4 for joints 1 and 5 on the
  components along the common direction, subproblem 1 for 6 and for the sum
  2 + 3 + 4, a planar two-link problem for 2 and 3.
* ``parallel-four-wrist``: 6 joints, joints 1-4 rotating about or sliding along one
  direction (3 R + 1 P, a SCARA-type arm) and axes 5, 6 intersecting: the
  textbook's offset-wrist R-P-R-R-R-R. Rotations about parallel axes add up, so
  joints 5, 6 and the angle sum come from subproblems 4 and 1, then a point of
  axis 4 is placed by joints 1-3.
* ``position-3``: 3 joints whose tool point moves in 3-D: the point alone.
* ``planar-3``: 3 revolute joints with parallel axes: a point on axis 3 by
  joints 1-2, then joint 3 from the orientation.
* ``position-2``: 2 joints: the tool point (on a plane, a cylinder, ...).
* ``point-plus-roll``: 4 joints, the last revolute: a point on axis 4 by
  joints 1-3 (SCARA, the R-R-P-R spherical arm), joint 4 from the orientation.
* ``general-6r``: 6 revolute joints with no such structure: algebraic
  elimination (:mod:`kincalc.ik.general6r`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np

from ..spatial import cross
from ..spatial import matrix_from_unit_axis_angle as _rot

from ..structure import common_point
from ..tolerances import (EXACT_ANGLE_TOL, EXACT_POINT_TOL, STRUCTURE_ANGLE_TOL,
                          STRUCTURE_POINT_TOL)
from .legacy_sp import norm3, sp1, sp2, sp4
from .position import place_point
from .screws import Screws


@dataclass(frozen=True)
class Continuum:
    """At a singular target joints ``i`` and ``j`` (0-based) turn the tool about one
    line: only ``q_i + sign q_j`` is fixed, to ``total`` (rad); ``total`` None when the
    solver does not name the combination."""

    i: int
    j: int
    sign: int
    total: float | None = None

    def reversed(self, n: int) -> "Continuum":
        """The same relation for the original chain of a reversed one (joint k of the
        reversed chain is joint n - 1 - k, turned the other way)."""
        return Continuum(n - 1 - self.i, n - 1 - self.j, self.sign,
                         None if self.total is None else -self.total)

    def text(self, names, angle_unit: str, per_rad: float) -> str:
        a, b = names[self.i], names[self.j]
        if self.total is None:
            return f"axes of {a} and {b} aligned: they turn the tool about one line"
        from .screws import wrap
        return (f"{a} {'+' if self.sign > 0 else '-'} {b} = "
                f"{float(wrap(self.total)) * per_rad:.4f} {angle_unit}")


@dataclass
class Candidate:
    q: np.ndarray
    signs: dict = field(default_factory=dict)     # joint index -> '+' / '-' / 'root k'
    free: list = field(default_factory=list)      # joint indices undetermined (singular)
    continuum: Continuum | None = None            # e.g. q4 + q6 = 37.2 deg
    trace: list = field(default_factory=list)     # (label, value, kind), SI


@dataclass(frozen=True)
class Family:
    name: str
    description: str
    controls: str          # which pose components the robot sets
    needs_orientation: bool
    #: found on the reversed chain (:meth:`Screws.reversed`); the name is then
    #: ``reversed-<family>`` and that family's solver runs on the reversed chain
    reverse: bool = False
    #: the geometric facts the closed form relies on, as ``(kind, joints)`` pairs with
    #: 0-based joints of the robot's chain: ``("parallel", js)`` axes parallel,
    #: ``("meet", js)`` axes through one point, ``("meet-approach", js)`` through one point
    #: on the tool's approach line (z at q = 0), ``("roll", (j,))`` the axis is that line
    structure: tuple = ()
    #: the structure holds to rounding (see :func:`classify`); False for a robot that is
    #: only nearly of this family: its closed form then runs on the nearest robot of the
    #: family (:func:`idealised`) and the dispatchers refine its solutions on the robot
    exact: bool = True

    @property
    def solver(self) -> str:
        """The key of :data:`SOLVERS` (and of the batched solvers) for this family."""
        return self.name.removeprefix("reversed-") if self.reverse else self.name


def _angle_about(k, R) -> float:
    """The angle of ``R`` about the unit axis ``k`` (subproblem 1 on a vector normal to
    ``k``); exact when ``R`` is a rotation about ``k``, its projection otherwise."""
    v = cross(k, [1.0, 0, 0] if abs(k[0]) < 0.9 else [0, 1.0, 0])
    return sp1(v, R @ v, k)[0]


def _parallel(a, b, tol=1e-9) -> bool:
    return norm3(cross(a, b)) < tol


@lru_cache(maxsize=64)
def plan(robot) -> tuple[Screws, Family | None, str]:
    """``(screws, family, why)`` of ``robot``: geometry facts, computed once per robot.

    The screws are those the family's solver runs on: the robot's own, or for a robot
    only nearly of its family those of the nearest robot that is (:func:`idealised`)."""
    S = Screws.of(robot)
    family, why = classify(robot, S)
    if family is not None and not family.exact:
        S = idealised(S, family.structure)
    return S, family, why


def idealised(S: Screws, structure) -> Screws:
    """The screws ``S`` moved the least way onto ``structure`` (:attr:`Family.structure`):
    parallel axes turned to their mean direction (each keeping its sense), meeting axes
    moved (parallel to themselves) through their least-squares common point, which for
    ``meet-approach`` is then taken onto the approach line; a ``roll`` axis becomes the
    approach line. Directions first, so that points meet on the final lines."""
    axis, point = S.axis.copy(), S.point.copy()
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    order = {"parallel": 0, "roll": 0, "meet": 1, "meet-approach": 1}
    for kind, js in sorted(structure, key=lambda c: order[c[0]]):
        js = list(js)
        if kind == "parallel":
            signs = np.sign(axis[js] @ axis[js[0]])
            mean = (signs[:, None] * axis[js]).sum(0)
            axis[js] = signs[:, None] * (mean / np.linalg.norm(mean))
        elif kind == "roll":
            axis[js] = np.sign(axis[js] @ a0)[:, None] * a0
            point[js] = p0
        else:
            c = common_point(point[js], axis[js], np.inf)
            if kind == "meet-approach":
                c = p0 + ((c - p0) @ a0) * a0
            point[js] = c
    ideal = Screws(axis, point, S.revolute.copy(), S.M.copy(), S.scale)
    move, turn = structure_defect(S, ideal)
    return replace(ideal, slack=1e3 * (move + turn * max(S.scale, 1.0)))


def structure_defect(S: Screws, ideal: Screws) -> tuple[float, float]:
    """How far the screws ``ideal`` are from ``S``: ``(metres, rad)``, the largest
    distance a joint's line moved and the largest angle an axis turned."""
    turn = float(np.max(norm3_rows(cross(S.axis, ideal.axis)), initial=0.0))
    d = ideal.point - S.point          # the new point's distance from the old line
    move = float(np.max(norm3_rows(d - (d * S.axis).sum(-1)[:, None] * S.axis), initial=0.0))
    return move, turn


def norm3_rows(v) -> np.ndarray:
    return np.sqrt((np.asarray(v) ** 2).sum(-1))


def _moves_along(S: Screws, idx, h, tol: float) -> bool:
    """Do joints ``idx`` all rotate about, or slide along, direction ``h`` (within
    ``tol`` rad)?"""
    return all(_parallel(S.axis[i], h, tol) for i in idx)


def classify(robot, S: Screws) -> tuple[Family | None, str]:
    """The family of ``robot`` (or None) and a sentence saying why.

    A family is recognised when the axes meet and are parallel as it needs to within
    :data:`~kincalc.tolerances.STRUCTURE_POINT_TOL` (of the arm's size) and
    :data:`~kincalc.tolerances.STRUCTURE_ANGLE_TOL` (rad). It is ``exact`` when they do
    to within ``EXACT_POINT_TOL`` and ``EXACT_ANGLE_TOL`` (rounding): a calibrated
    model or a rounded datasheet gives a robot that is only nearly of its family, whose
    closed-form solutions the dispatcher refines on the true robot.
    """
    family, why = _classify(robot, S, STRUCTURE_POINT_TOL, STRUCTURE_ANGLE_TOL)
    if family is not None and family.name != "general-6r":
        strict, _ = _classify(robot, S, EXACT_POINT_TOL, EXACT_ANGLE_TOL)
        if strict is None or strict.name != family.name:
            family = replace(family, exact=False)
    return family, why


def _classify(robot, S: Screws, point_tol: float, angle_tol: float
              ) -> tuple[Family | None, str]:
    """:func:`classify` with the given structure tolerances (relative, rad)."""
    n, rev = S.n, S.revolute
    if n == 6:
        fam = _classify_6(S, point_tol, angle_tol)
        if fam is None:
            # the same structures seen from the tool: a spherical wrist at the base, ...
            fam = _classify_6(S.reversed(), point_tol, angle_tol)
            if fam is not None:
                # the facts hold of the same lines: name them by the robot's joints
                facts = tuple((kind, tuple(sorted(n - 1 - j for j in js)))
                              for kind, js in fam.structure)
                fam = Family(f"reversed-{fam.name}",
                             fam.description + ", found on the chain reversed (the base "
                             "seen from the tool: joint k of it is joint 7 - k)",
                             fam.controls, fam.needs_orientation, reverse=True,
                             structure=facts)
        if fam is not None:
            return fam, ""
    if n == 6 and rev.all():
        return (Family("general-6r", "general 6R: no decomposable structure; algebraic "
                                     "elimination (Raghavan-Roth, Manocha-Canny)",
                       "position and orientation", True), "")
    return _classify_small(robot, S, point_tol, angle_tol)


def _classify_6(S: Screws, point_tol: float, par: float) -> Family | None:
    """The six-joint families with a closed form, or None."""
    rev = S.revolute
    tol = point_tol * max(S.scale, 1.0)
    if rev[3:].all() and common_point(S.point[3:], S.axis[3:], tol) is not None:
        return Family("spherical-wrist",
                      "spherical wrist: axes 4, 5, 6 meet at one point; joints 1-3 place "
                      "the wrist centre, joints 4-6 set the orientation",
                      "position and orientation", True, structure=(("meet", (3, 4, 5)),))
    wrist_pair = rev[4:].all() and common_point(S.point[4:], S.axis[4:], tol) is not None
    if wrist_pair and rev.all() and _parallel(S.axis[1], S.axis[2], par) \
            and _parallel(S.axis[2], S.axis[3], par) and not _parallel(S.axis[0], S.axis[1]) \
            and not _parallel(S.axis[4], S.axis[1]):
        return Family("three-parallel",
                      "three parallel axes (2, 3, 4) and axes 5, 6 intersecting (UR type)",
                      "position and orientation", True,
                      structure=(("parallel", (1, 2, 3)), ("meet", (4, 5))))
    if wrist_pair and rev[3] and _moves_along(S, range(4), S.axis[3], par) \
            and not rev[:3].all() and not _parallel(S.axis[4], S.axis[3]):
        return Family("parallel-four-wrist",
                      "joints 1-4 all rotate about or slide along one direction (a SCARA-type "
                      "arm) and axes 5, 6 intersect (an offset wrist)",
                      "position and orientation", True,
                      structure=(("parallel", (0, 1, 2, 3)), ("meet", (4, 5))))
    return None


def _classify_small(robot, S: Screws, point_tol: float, par: float
                    ) -> tuple[Family | None, str]:
    """Families of fewer (or more) than six joints."""
    n, rev = S.n, S.revolute
    pos_rank = robot.generic_ranks[1]
    if n == 3 and pos_rank == 3:
        return (Family("position-3", "three joints placing the tool point in space",
                       "position", False), "")
    if n == 3 and rev.all() and _parallel(S.axis[0], S.axis[1], par) \
            and _parallel(S.axis[1], S.axis[2], par):
        return (Family("planar-3", "planar 3R: three parallel axes; a point on axis 3 by "
                                   "joints 1-2, joint 3 from the orientation",
                       "position in the plane and rotation about the axes", True,
                       structure=(("parallel", (0, 1, 2)),)), "")
    if n == 2:
        return (Family("position-2", "two joints placing the tool point",
                       "position (on the surface the arm sweeps)", False), "")
    if n == 5 and rev[3:].all():
        fam = _classify_5(S, point_tol, par)
        if fam is not None:
            return fam, ""
    if n == 4 and rev[3] and pos_rank == 3:
        return (Family("point-plus-roll", "a point on axis 4 placed by joints 1-3, joint 4 "
                                          "from the orientation about its axis",
                       "position and rotation about axis 4", True), "")
    if n > 6 or (n > 1 and pos_rank == 3 and robot.generic_ranks[0] < n):
        return None, (f"redundant: {n} joints for {robot.generic_ranks[0]} independent pose "
                      "components, so infinitely many solutions")
    why = (f"no analytic solver for this structure yet ({n} joints, "
           f"{''.join('R' if r else 'P' for r in rev)})")
    return None, why


def _classify_5(S: Screws, point_tol: float, par: float) -> Family | None:
    """Five joints controlling the position and the approach direction (tool z)."""
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    tol = point_tol * max(S.scale, 1.0)
    c = common_point(S.point[3:], S.axis[3:], tol)
    if c is not None and float(np.linalg.norm(cross(p0 - c, a0))) < tol \
            and not _parallel(S.axis[4], a0, 1e-6):
        return Family("position-approach",
                      "five joints, axes 4 and 5 meeting on the tool's approach line: joints 1-3 "
                      "place the point where they meet, joints 4 and 5 turn the approach "
                      "direction (subproblem 2); the roll about it follows",
                      "position and approach direction (tool z)", True,
                      structure=(("meet-approach", (3, 4)),))
    on_axis5 = float(np.linalg.norm(cross(p0 - S.point[4], S.axis[4]))) < tol
    if S.revolute.all() and on_axis5 and _parallel(S.axis[4], a0, par) \
            and _parallel(S.axis[1], S.axis[2], par) and _parallel(S.axis[2], S.axis[3], par) \
            and not _parallel(S.axis[0], S.axis[1]) and not _parallel(S.axis[4], S.axis[1]):
        return Family("pitch-roll",
                      "five joints, axes 2, 3, 4 parallel and joint 5 rolling the tool about its "
                      "approach axis: joint 1 from the position (subproblem 4), the pitch sum "
                      "q2 + q3 + q4 from the approach (subproblem 1), a planar two-link problem "
                      "for joints 2 and 3, joint 5 from the orientation",
                      "position, the approach direction within the arm's plane, and the roll "
                      "about it", True, structure=(("parallel", (1, 2, 3)), ("roll", (4,))))
    return None


# --- solvers -------------------------------------------------------------------

def _exp(S: Screws, i: int, x) -> np.ndarray:
    """``E_i(x)`` (4, 4) for one value: :meth:`Screws.exp` without its broadcasting."""
    E = np.eye(4)
    if S.revolute[i]:
        R = _rot(S.axis[i], x)
        E[:3, :3] = R
        E[:3, 3] = S.point[i] - R @ S.point[i]
    else:
        E[:3, 3] = float(x) * S.axis[i]
    return E


def _product(S: Screws, idx, xs) -> np.ndarray:
    """``E_idx[0](xs[0]) E_idx[1](xs[1]) ...`` (4, 4), as :meth:`Screws.product`."""
    T = np.eye(4)
    for i, x in zip(idx, xs):
        T = T @ _exp(S, i, x)
    return T


def _inv(T) -> np.ndarray:
    """Inverse of one rigid transform (4, 4): ``[R^T, -R^T p]``."""
    out = np.eye(4)
    Rt = T[:3, :3].T
    out[:3, :3] = Rt
    out[:3, 3] = -(Rt @ T[:3, 3])
    return out


def _point_in_tool(S: Screws, p):
    """Coordinates of world point ``p`` (at q = 0) in the tool frame M."""
    Minv = S.inverse_M()
    return Minv[:3, :3] @ p + Minv[:3, 3]


def _from_tool(T, p_tool):
    return T[:3, :3] @ p_tool + T[:3, 3]


def solve_spherical_wrist(S: Screws, T, explain=False) -> list[Candidate]:
    c0 = common_point(S.point[3:], S.axis[3:], np.inf)
    ct = _from_tool(T, _point_in_tool(S, c0))
    out = []
    consts = _cone_constants(S.axis[3], S.axis[4], S.axis[5])
    for ps in place_point(S, [0, 1, 2], c0, ct, explain):
        q123 = ps.x
        W = _inv(_product(S, [0, 1, 2], q123)) @ T @ S.inverse_M()
        out.extend(_wrist(S, W[:3, :3], q123, ps, [3, 4, 5], ct, explain, consts))
    return out


def _wrist_middle_roots(consts, f: float, P: float):
    """The middle wrist joint's roots (rad) from ``k1 . R(k2, t) k3 = f``, the equation
    of :func:`_wrist` written ``C + r cos(t - b) = f`` (``consts`` from
    :func:`_cone_constants` ``(k1, k2, k3)``; axes at q = 0, world frame).

    ``f = k1 . v`` and ``P = |k1 x v|`` for the unit vector ``v = R_W k3``: the target
    direction of the third axis, along and across the first.

    Returns ``(roots, sigma)``:

    * the wrist singularity: ``v`` within :data:`PARALLEL_WRIST_TOL` (sine) of the line
      of ``k1`` (``P <= tol``), and the wrist able to put its third axis on that line
      (``top``, resp. ``bottom``, at most ``tol^2 / 2``: the cone angles differ from
      equal, resp. supplementary, by at most ``tol`` rad). Then ``roots`` is the one
      aligned value, ``b`` when ``v`` points along ``k1`` (``sigma = +1``) and ``b + pi``
      against it (``sigma = -1``). The outer axes are then on one line: a representative
      of the continuum misses the pose by at most ~2 tol rad.
    * otherwise ``sigma`` is None and ``roots`` is ``[b + delta, b - delta]`` with
      ``delta`` from :func:`_wrist_q5`, exact to rounding up to the singularity (the plain
      ``arccos`` is only good to sqrt(eps) ~ 1.5e-8 rad there). One root only where the
      target is out of the wrist's reach (the least-squares angle, ``delta`` 0 or pi;
      the FK check rejects it) and at the tangent double root of a side where the wrist
      cannot line its outer axes up (``delta`` or ``pi - delta`` below 1e-9 rad there:
      both roots give one configuration).
    """
    cb, sb, r, top, bottom = consts
    sigma = 1.0 if f > 0 else -1.0
    gap_tol = 0.5 * PARALLEL_WRIST_TOL ** 2
    if P <= PARALLEL_WRIST_TOL and (top if f > 0 else bottom) <= gap_tol:
        return [float(np.arctan2(sigma * sb, sigma * cb))], sigma
    cd, sd, ok = _wrist_q5(consts, f, P, 1e-12)
    base = float(np.arctan2(sb, cb))
    delta = float(np.arctan2(sd, cd))
    if not ok or (delta < 1e-9 and top > gap_tol) or (np.pi - delta < 1e-9 and bottom > gap_tol):
        return [base + delta], None
    return [base + delta, base - delta], None


def _wrist(S: Screws, RW, prefix_q, ps, idx, centre, explain, consts=None):
    """Angles of three concurrent revolute axes ``idx`` with ``R(k1, t1) R(k2, t2)
    R(k3, t3) = RW`` (rotation (3, 3) in the world frame at q = 0; axes from ``S`` at
    q = 0), appended to ``prefix_q``: candidates (rad).

    ``t2`` from ``k1 . R(k2, t2) k3 = k1 . (RW k3)`` (subproblem 4, in the form of
    :func:`_wrist_middle_roots`), ``t1`` turning ``R(k2, t2) k3`` onto ``RW k3`` about
    ``k1`` (subproblem 1 on the parts normal to ``k1``, no threshold: next to the
    singularity both are small and their rounding, ~1e-16 / sin(distance), is absorbed
    by ``t3``), ``t3`` from the rest (subproblem 1).

    At the wrist singularity (``RW k3`` on the line of ``k1``, see
    :func:`_wrist_middle_roots`) ``R(k1, t1) R2 R(k3, t3) = R(k1, t1 + sigma t3) R2`` and
    only ``t1 + sigma t3`` is fixed. One representative is returned: ``t2`` at its aligned
    value, ``t1 = 0`` and ``t3`` carrying the combination; joint ``idx[0]`` is marked
    free and a :class:`Continuum` gives ``t1 + sigma t3``. ``consts``: the
    :func:`_cone_constants` of the three axes (computed when not given).
    """
    k1, k2, k3 = (S.axis[i] for i in idx)
    if consts is None:
        consts = _cone_constants(k1, k2, k3)
    if consts is None:       # axis 2 along axis 1 or 3: not a working wrist
        return _wrist_sp2(S, RW, prefix_q, ps, idx, centre, explain)
    v = RW @ k3
    roots, sigma = _wrist_middle_roots(consts, float(k1 @ v), norm3(cross(k1, v)))
    out = []
    for n_sol, t2 in enumerate(roots):
        R2 = _rot(k2, t2)
        t1 = 0.0 if sigma is not None else _angle_onto(R2 @ k3, v, k1)
        R12 = _rot(k1, t1) @ R2
        t3 = _angle_about(k3, R12.T @ RW)
        q = np.concatenate([prefix_q, [t1, t2, t3]])
        cand = Candidate(q=q, signs=dict(ps.signs), free=list(ps.free))
        if len(roots) == 2:
            cand.signs[idx[1]] = "+" if n_sol == 0 else "-"
        if sigma is not None:
            # axes idx[0] and idx[2] on one line: rotations add (or subtract, when the
            # axes point opposite ways) and only that combination is fixed
            cand.free.append(idx[0])
            cand.continuum = Continuum(idx[0], idx[2], int(sigma), t1 + sigma * t3)
        if explain:
            a, b, c = (i + 1 for i in idx)
            if sigma is None:
                steps = [(f"joint {b} by subproblem 4: axis {c}'s component along axis {a}",
                          float(t2), "angle"),
                         (f"joint {a} by subproblem 1: turn axis {c} onto R_W times it",
                          float(t1), "angle")]
            else:
                steps = [(f"axes {a} and {c} aligned (wrist singularity): joint {b} at its "
                          "aligned value", float(t2), "angle"),
                         (f"joint {a} free: 0 (joint {c} takes joint {a} "
                          f"{'+' if sigma > 0 else '-'} joint {c})", float(t1), "angle")]
            cand.trace = [("wrist centre (target)", centre.tolist(), "length")] + list(ps.trace) + [
                ("wrist: rotation left for joints 4-6, R_W", RW.tolist(), "none")] + steps + [
                (f"joint {c} by subproblem 1", float(t3), "angle")]
        out.append(cand)
    return out


def _wrist_sp2(S: Screws, RW, prefix_q, ps, idx, centre, explain):
    """:func:`_wrist` by plain subproblem 2 (then 1), for a degenerate wrist whose middle
    axis lies along one of the others (no cone constants)."""
    k1, k2, k3 = (S.axis[i] for i in idx)
    sols, exact, free = sp2(k3, RW @ k3, k1, k2)
    out = []
    for n_sol, (t1, t2) in enumerate(sols):
        R12 = _rot(k1, t1) @ _rot(k2, t2)
        t3 = _angle_about(k3, R12.T @ RW)
        q = np.concatenate([prefix_q, [t1, t2, t3]])
        cand = Candidate(q=q, signs=dict(ps.signs), free=list(ps.free))
        if len(sols) == 2:
            cand.signs[idx[1]] = "+" if n_sol == 0 else "-"
        if free:
            # axes idx[0] and idx[2] on one line: rotations add (or subtract, when the
            # axes point opposite ways) and only that combination is fixed
            cand.free.append(idx[0])
            same = float(k1 @ (R12 @ k3)) > 0
            cand.continuum = Continuum(idx[0], idx[2], 1 if same else -1,
                                       t1 + t3 if same else t1 - t3)
        if explain:
            cand.trace = [("wrist centre (target)", centre.tolist(), "length")] + list(ps.trace) + [
                ("wrist: rotation left for joints 4-6, R_W", RW.tolist(), "none"),
                (f"joints {idx[0] + 1}, {idx[1] + 1} by subproblem 2: carry axis "
                 f"{idx[2] + 1} onto R_W times it", [float(t1), float(t2)], "angle"),
                (f"joint {idx[2] + 1} by subproblem 1", float(t3), "angle")]
        out.append(cand)
    return out


#: A three-parallel arm's axis 6 counts as parallel to axes 2-4 when the sine of the
#: angle between them is at most this. That is the wrist singularity: joints 2, 3, 4
#: and 6 then all turn about parallel axes, and a one-parameter continuum of
#: configurations reaches the pose. A representative of the continuum misses the pose
#: by at most about this much (in rad, and times the arm's size), well inside the 1e-9
#: acceptance. The tolerance also absorbs the rounding of joint 1 near the shoulder's
#: double root, which is 1e-12 and more. Above this value the pose has isolated
#: solutions. They are computed exactly, with joint 5 from the well-conditioned form of
#: :func:`_wrist_q5`.
PARALLEL_WRIST_TOL = 1e-10


@dataclass(frozen=True)
class ParallelContinuum:
    """A three-parallel arm at its wrist singularity: joints ``joints`` (0-based) turn
    about parallel axes, so only ``sum(sign_k q_k)`` is fixed, to ``total`` (rad).
    Joint ``free`` can take any value the elbow can follow. The others follow it: the
    sum, and the planar elbow placing axis 4. It has the same interface as
    :class:`Continuum` (``reversed``, ``text``) for the dispatcher."""

    joints: tuple
    signs: tuple
    free: int
    total: float

    def reversed(self, n: int) -> "ParallelContinuum":
        """The same relation for the original chain of a reversed one (joint k of the
        reversed chain is joint n - 1 - k, turned the other way)."""
        pairs = sorted((n - 1 - i, s) for i, s in zip(self.joints, self.signs))
        return ParallelContinuum(tuple(i for i, _ in pairs), tuple(s for _, s in pairs),
                                 n - 1 - self.free, -self.total)

    def text(self, names, angle_unit: str, per_rad: float) -> str:
        from .screws import wrap
        terms = [("-" if s < 0 else "") + names[j] if k == 0 else
                 ("- " if s < 0 else "+ ") + names[j]
                 for k, (j, s) in enumerate(zip(self.joints, self.signs))]
        rest = ", ".join(names[j] for j in self.joints if j != self.free)
        return (f"{' '.join(terms)} = {float(wrap(self.total)) * per_rad:.4f} {angle_unit} "
                f"(axis of {names[self.free]} parallel to theirs: {names[self.free]} free, "
                f"{rest} follow it)")


def _wrist_q5_constants(S: Screws):
    """Joint 5's equation ``h . R(k5, t) k6 = f`` for a three-parallel arm, written as
    ``C + r cos(t - b) = f``. ``h`` is the direction of axes 2-4 and the screws are
    taken at q = 0 (world frame).

    Returns ``(cos b, sin b, r, top, bottom)`` with ``top = 1 - (C + r)`` and
    ``bottom = 1 + (C - r)``, both >= 0. They are 0 when axis 6 can be turned parallel
    (``top``) or antiparallel (``bottom``) to h. With beta the angle from k5 to h and
    gamma the angle from k5 to k6, ``C + r = cos(beta - gamma)`` and
    ``C - r = cos(beta + gamma)``. Computing them from the angles makes them exact to
    the rounding of the angles, not to the rounding of 1. Returns ``None`` when
    ``r`` is 0 (axis 6 or h along axis 5).
    """
    return _cone_constants(S.axis[1], S.axis[4], S.axis[5])


def _cone_constants(h, k5, k6):
    """:func:`_wrist_q5_constants` for any unit vectors (3,): the equation
    ``h . R(k5, t) k6 = f`` as ``C + r cos(t - b) = f``, returned as
    ``(cos b, sin b, r, top, bottom)``, or ``None`` when ``r`` is 0. ``R(k5, t) k6``
    sweeps a cone about ``k5``; ``top`` (``bottom``) is 0 when the cone holds ``h``
    (``-h``). The three-parallel arm uses it with ``h`` the direction of axes 2-4, the
    spherical wrist with ``h = k4`` (:func:`_wrist`)."""
    beta = np.arctan2(norm3(cross(k5, h)), float(k5 @ h))
    gamma = np.arctan2(norm3(cross(k5, k6)), float(k5 @ k6))
    kxp = cross(k5, k6)
    A = -float(h @ cross(k5, kxp))
    B = float(h @ kxp)
    r = float(np.hypot(A, B))
    if r <= 1e-12:
        return None
    return (A / r, B / r, r, 2.0 * np.sin(0.5 * (beta - gamma)) ** 2,
            2.0 * np.cos(0.5 * (beta + gamma)) ** 2)


def _wrist_q5(consts, f, P, tol: float):
    """Both roots ``t = b +- delta`` of joint 5's equation ``C + r cos(t - b) = f`` (see
    :func:`_wrist_q5_constants`). Returns ``(cos delta, sin delta, ok)`` with ``delta``
    in [0, pi]; ``ok`` says that the roots are real within ``tol`` (in units of f).

    ``f = h . v`` and ``P = |v - f h|`` for the unit vector ``v = R1^T R(q) k6``
    (arrays that broadcast). Near the singularity ``1 - f`` and ``1 + f`` are small, so
    they are computed as ``P^2 / (1 + f)`` and ``P^2 / (1 - f)`` on their own side. This
    keeps ``delta`` exact to the rounding of ``P``. The plain ``arccos((f - C) / r)`` is
    only good to sqrt(eps) there, which is 1.5e-8 rad at an exactly aligned wrist.
    """
    cb, sb, r, top, bottom = consts
    f = np.asarray(f, float)
    P2 = np.asarray(P, float) ** 2
    one_minus = np.where(f > 0, P2 / (1.0 + np.abs(f)), 1.0 - f)
    one_plus = np.where(f < 0, P2 / (1.0 + np.abs(f)), 1.0 + f)
    um = one_minus - top           # r (1 - cos delta)
    wm = one_plus - bottom         # r (1 + cos delta)
    ok = (um >= -tol) & (wm >= -tol)
    u, w = np.maximum(um, 0.0), np.maximum(wm, 0.0)
    n = np.maximum(u + w, 1e-300)  # 2 r
    return (w - u) / n, 2.0 * np.sqrt(u * w) / n, ok


def _parallel_wrist_q6(S: Screws, a, b, sigma):
    """Representative values of joint 6 at the wrist singularity of a three-parallel arm.

    There joints 2, 3, 4 and 6 turn about parallel axes (direction ``h``). All
    quantities here are projected on the plane normal to h, in the frame with joint 1
    undone (world frame, m). Turning joint 6 by ``q6`` swings axis 4 about axis 6 by
    ``-sigma q6``. Joints 2 and 3 (a planar two-link arm) must then reach axis 4. They
    reach distances between ``|l2 - l3|`` and ``l2 + l3`` from axis 2, where ``l2`` is
    the distance from axis 2 to axis 3 and ``l3`` the distance from axis 3 to axis 4.
    So the continuum is made of one or two arcs of ``q6``.

    Convention, per arc: ``q6 = 0`` when the arc holds it. Otherwise ``q6`` is the
    value that puts axis 4 nearest the middle of the elbow's reach,
    ``(|l2 - l3| + l2 + l3) / 2`` from axis 2. Of the two such values the one on the
    side of ``q6 = 0`` is used. This value is inside the arc, away from the stretched
    and folded elbow.

    ``a (..., 3)``: from axis 2 to axis 6, normal to h. ``b (..., 3)``: from axis 6 to
    axis 4 at ``q6 = 0``, normal to h. ``sigma (...)``: +1 when axis 6 points along h,
    -1 when it points against it.

    Returns ``q6 (..., 2)`` (rad, in (-pi, pi]), ``ok (..., 2)`` and ``phi (..., 2)``.
    Slot 0 is the arc on the side of ``q6 = 0`` (or the only arc). Slot 1 is the other
    arc, valid only when there are two. ``phi`` is the angle about h from ``a`` to axis
    4's offset, whose sign tells the two arcs apart.
    """
    from .screws import wrap
    h = S.axis[1]
    perp = lambda x: x - (x @ h) * h  # noqa: E731
    l2 = norm3(perp(S.point[2] - S.point[1]))
    l3 = norm3(perp(S.point[3] - S.point[2]))
    lo_r, hi_r = abs(l2 - l3), l2 + l3
    mid_r = 0.5 * (lo_r + hi_r)
    a, b = np.asarray(a, float), np.asarray(b, float)
    sigma = np.asarray(sigma, float)
    A2, B2 = (a * a).sum(-1), (b * b).sum(-1)
    AB = np.sqrt(A2 * B2)
    # axis 6 on axis 2 or axis 4 on axis 6: joint 6 does not move axis 4 relative to
    # axis 2, so every q6 is equally good and q6 = 0 is used
    flat = AB <= (1e-9 * max(S.scale, 1e-300)) ** 2
    den = np.where(flat, 1.0, 2.0 * AB)
    cos0 = 2.0 * (a * b).sum(-1) / den
    sin0 = 2.0 * (cross(a, b) @ h) / den
    c_out, c_in, c_mid = ((x * x - A2 - B2) / den for x in (hi_r, lo_r, mid_r))
    hi, lo = np.minimum(c_out, 1.0), np.maximum(c_in, -1.0)
    reach = flat | (lo <= hi + 1e-12)
    two = ~flat & (c_out < 1.0) & (c_in > -1.0)
    zero_in = flat | ((cos0 >= lo - 1e-12) & (cos0 <= hi + 1e-12))
    phim = np.arccos(np.clip(c_mid, lo, np.maximum(lo, hi)))
    side = np.where(sin0 >= 0, 1.0, -1.0)
    phi0 = np.arctan2(sin0, cos0)
    q6 = np.stack([np.where(zero_in, 0.0, sigma * (phi0 - side * phim)),
                   sigma * (phi0 + side * phim)], axis=-1)
    phi = np.stack([np.where(zero_in, phi0, side * phim), -side * phim], axis=-1)
    return wrap(q6), np.stack([reach, reach & two], axis=-1), phi


def _angle_onto(p1, p2, k) -> float:
    """The angle about unit ``k`` turning ``p1`` toward ``p2`` (subproblem 1 without a
    threshold). Near-zero projections keep their direction, since the solution's other
    joints absorb the rounding of a nearly free angle. 0 when a projection is exactly 0.

    Both vectors are projected on the plane normal to ``k``. Otherwise the rounding of
    ``p1``'s projection along ``k`` (~1e-16) times ``p2``'s component along ``k`` (~1)
    would swamp the products of two small normal parts next to the singularity."""
    a = p1 - (k @ p1) * k
    b = p2 - (k @ p2) * k
    return float(np.arctan2(float(cross(k, a) @ b), float(a @ b)))


def solve_three_parallel(S: Screws, T, explain=False) -> list[Candidate]:
    """Three-parallel (UR-type) arm, pose ``T`` (4, 4; world frame, m): all candidates.

    Joint 1 comes from the height of the wrist point along h, the direction of axes 2-4
    (subproblem 4). Joint 5 comes from the component of axis 6 along h (subproblem 4,
    in the form of :func:`_wrist_q5`). Joint 6 and the angle about h of joints 2-4
    come from subproblem 1. Joints 2 and 3 then place a point of axis 4, a planar
    two-link problem. Axes 3 and 4 may point along h or against it (signs s3, s4): the
    rotation about h is ``q2 + s3 q3 + s4 q4``.

    Wrist singularity: axis 6 parallel to h within :data:`PARALLEL_WRIST_TOL`, which for
    a UR arm is q5 = 0 or 180 deg. The rotation is then
    ``R1 R_h(q2 + s3 q3 + s4 q4 + sigma q6) R5``, with ``sigma = +-1`` the direction of
    axis 6 along h. Joint 6 can take any value the elbow can follow. For such a branch
    of joint 1, joint 5 is the aligned value (a double root). The candidates are the
    representatives of :func:`_parallel_wrist_q6`: ``q6 = 0`` where the elbow reaches
    it, else a value in mid-reach, one per arc of the continuum. Each is followed by
    both elbow solutions. They are marked with joint 6 free and a
    :class:`ParallelContinuum` giving the fixed sum.
    """
    h = S.axis[1]
    c56 = common_point(S.point[4:], S.axis[4:], np.inf)
    ct = _from_tool(T, _point_in_tool(S, c56))
    Minv = S.inverse_M()
    R_t = T[:3, :3] @ Minv[:3, :3]        # R(q) for the product of exponentials
    o1 = S.point[0]
    out = []
    # joint 1: the component along h of (c56 - o1) is unchanged by joints 2-4 (and 5, 6 fix c56)
    d = float(h @ (c56 - o1))
    t1s, ex1, free1 = sp4(h, ct - o1, S.axis[0], d)
    t1s = [-t for t in t1s]   # sp4 solved h . R(k1, t)(ct - o1) = d; we need R(k1, -q1)
    if not ex1:
        return []
    s3, s4 = (1.0 if float(S.axis[i] @ h) > 0 else -1.0 for i in (2, 3))
    consts = _wrist_q5_constants(S)

    def finish(q1, q5, q6, signs, sigma):
        """Joints 2-4 for the given q1, q5, q6 -> candidates. ``sigma`` (+-1, axis 6
        along or against h) at the wrist singularity, else None."""
        R1 = _rot(S.axis[0], q1)
        R5 = _rot(S.axis[4], q5)
        R6 = _rot(S.axis[5], q6)
        # angle about h of joints 2-4: R2 R3 R4 = R_h(q2 + s3 q3 + s4 q4)
        q234 = _angle_about(h, R1.T @ R_t @ R6.T @ R5.T)
        # the point of axis 4 at q = 0 maps to E2 E3 (p4) (E4 fixes it), with
        # E2 E3 E4 = E1^-1 T M^-1 E6^-1 E5^-1. This uses Screws.exp and numpy's inverse
        # on purpose (not _exp, _inv): at the stretched elbow of a UR arm's home pose
        # the elbow is a double root whose value and up/down label follow the rounding
        # of exactly these products.
        T_rest = np.linalg.inv(S.exp(0, q1)) @ T @ Minv @ np.linalg.inv(
            S.exp(5, q6)) @ np.linalg.inv(S.exp(4, q5))
        p4 = S.point[3]
        p4t = T_rest[:3, :3] @ p4 + T_rest[:3, 3]
        res = []
        for ps in place_point(S, [1, 2], p4, p4t, explain):
            q2, q3 = ps.x
            q4 = s4 * (q234 - q2 - s3 * q3)
            cand = Candidate(q=np.array([q1, q2, q3, q4, q5, q6]), signs={**signs, **ps.signs})
            if sigma is not None:
                cand.free.append(5)
                cand.continuum = ParallelContinuum(
                    (1, 2, 3, 5), (1, int(s3), int(s4), int(sigma)), 5,
                    float(q2 + s3 * q3 + s4 * q4 + sigma * q6))
            if explain:
                if sigma is None:
                    steps = [("joint 5 by subproblem 4", float(q5), "angle"),
                             ("joint 6 by subproblem 1", float(q6), "angle")]
                else:
                    steps = [("axis 6 parallel to axes 2-4 (wrist singularity): joint 5 "
                              "at its aligned value", float(q5), "angle"),
                             ("joint 6 free: 0 where the elbow reaches, else mid-reach "
                              "(one value per arc of the continuum)", float(q6), "angle")]
                cand.trace = [("point where axes 5 and 6 meet (target)", ct.tolist(), "length"),
                              ("joint 1 by subproblem 4 (component along the parallel "
                               "axes)", float(q1), "angle")] + steps + [
                              ("q2 + s3 q3 + s4 q4 by subproblem 1", float(q234), "angle")] + \
                    ps.trace
            res.append(cand)
        return res

    for i1, q1 in enumerate(t1s):
        R1 = _rot(S.axis[0], q1)
        sign1 = {0: "+" if i1 == 0 else "-"}
        v = R1.T @ R_t @ S.axis[5]          # axis 6 with joint 1 undone
        f = float(h @ v)
        P = norm3(v - f * h)
        if consts is None:                  # degenerate wrist: plain subproblem 4
            t5s, ex5, _ = sp4(h, S.axis[5], S.axis[4], f)
            roots = t5s if ex5 else []
        elif P <= PARALLEL_WRIST_TOL:
            # wrist singularity: axis 6 along +-h; joint 5 at the aligned value
            sigma = 1.0 if f > 0 else -1.0
            cb, sb = consts[0], consts[1]
            q5 = float(np.arctan2(sigma * sb, sigma * cb))
            W = _from_tool(T, S.point[5] @ Minv[:3, :3].T + Minv[:3, 3])    # axis 6
            G0 = _inv(_exp(S, 0, q1)) @ T @ Minv @ _inv(_exp(S, 4, q5))
            P0 = G0[:3, :3] @ S.point[3] + G0[:3, 3]                      # axis 4, q6 = 0
            W = R1.T @ (W - o1) + o1
            perp = lambda x: x - (x @ h) * h  # noqa: E731
            q6s, oks, phis = _parallel_wrist_q6(S, perp(W - S.point[1]), perp(P0 - W), sigma)
            two = bool(oks[1])
            for q6, ok, phi in zip(q6s.tolist(), oks.tolist(), phis.tolist()):
                if ok:
                    signs = {**sign1, **({3: "+" if phi >= 0 else "-"} if two else {})}
                    out.extend(finish(q1, q5, q6, signs, sigma))
            continue
        else:
            cd, sd, ok5 = _wrist_q5(consts, f, P, 1e-12)
            if not ok5:
                continue
            base = np.arctan2(consts[1], consts[0])
            dl = float(np.arctan2(sd, cd))
            roots = [base + dl, base - dl]
        for i5, q5 in enumerate(roots):
            R5 = _rot(S.axis[4], q5)
            # joint 6: R(k6, q6) (R_t^T R1 h) = R5^T h
            q6 = _angle_onto(R_t.T @ R1 @ h, R5.T @ h, S.axis[5])
            out.extend(finish(q1, q5, q6, {**sign1, 4: "+" if i5 == 0 else "-"}, None))
    return out


def solve_parallel_four_wrist(S: Screws, T, explain=False) -> list[Candidate]:
    """Joints 1-4 about/along h (3 revolute, 1 prismatic), axes 5 and 6 intersecting.

    Rotations about parallel axes add up, so R(q) = R_h(psi) R5(q5) R6(q6) with psi
    the sum of the revolute angles among joints 1-4: subproblem 4 gives q5 from the
    component along h, subproblem 1 gives q6 and psi; a point of axis 4 is then placed
    by joints 1-3 and q4 closes the sum. (Bingul & Kucuk's offset-wrist R-P-R-R-R-R.)
    """
    h = S.axis[3]
    R_t = T[:3, :3] @ S.inverse_M()[:3, :3]
    out = []
    t5s, ex5, free5 = sp4(h, S.axis[5], S.axis[4], float(h @ (R_t @ S.axis[5])))
    if not ex5:
        return []
    revs = [i for i in range(4) if S.revolute[i]]
    sign = {i: float(np.sign(S.axis[i] @ h)) for i in revs}
    for i5, q5 in enumerate(t5s):
        R5 = _rot(S.axis[4], q5)
        q6, _, free6 = sp1(R_t.T @ h, R5.T @ h, S.axis[5])
        R6 = _rot(S.axis[5], q6)
        psi = _angle_about(h, R_t @ R6.T @ R5.T)
        T_rest = T @ S.inverse_M() @ _inv(_exp(S, 5, q6)) @ _inv(_exp(S, 4, q5))
        p4 = S.point[3]
        p4t = T_rest[:3, :3] @ p4 + T_rest[:3, 3]
        for ps in place_point(S, [0, 1, 2], p4, p4t, explain):
            x = list(ps.x)
            # psi = sum over revolute joints 1-4 of sign_i q_i  -> q4
            partial = sum(sign[i] * x[i] for i in revs if i < 3)
            q4 = (psi - partial) * sign[3]
            q = np.array(x + [q4, q5, q6])
            cand = Candidate(q=q, signs={4: "+" if i5 == 0 else "-", **ps.signs})
            if free6:
                cand.free.append(5)
            if explain:
                cand.trace = [("joint 5 by subproblem 4 (component along the parallel axes)",
                               float(q5), "angle"), ("joint 6 by subproblem 1", float(q6), "angle"),
                              ("sum of the parallel joints' angles", float(psi), "angle"),
                              ("point of axis 4 to place (target)", p4t.tolist(), "length")] + ps.trace
            out.append(cand)
    return out


def solve_position_3(S: Screws, T, explain=False) -> list[Candidate]:
    return [Candidate(q=ps.x, signs=ps.signs, free=ps.free, trace=ps.trace)
            for ps in place_point(S, [0, 1, 2], S.M[:3, 3], T[:3, 3], explain)]


def solve_position_2(S: Screws, T, explain=False) -> list[Candidate]:
    return [Candidate(q=ps.x, signs=ps.signs, free=ps.free, trace=ps.trace)
            for ps in place_point(S, [0, 1], S.M[:3, 3], T[:3, 3], explain)]


def _last_axis_roll(S: Screws, T, first: list[int], explain):
    """A point of the last axis placed by ``first`` joints, then the last joint's roll."""
    n = S.n
    c0 = S.point[n - 1]
    ct = _from_tool(T, _point_in_tool(S, c0))
    out = []
    for ps in place_point(S, first, c0, ct, explain):
        W = _inv(_product(S, first, ps.x)) @ T @ S.inverse_M()
        qn = _angle_about(S.axis[n - 1], W[:3, :3])
        cand = Candidate(q=np.concatenate([ps.x, [qn]]), signs=ps.signs, free=ps.free,
                         trace=ps.trace)
        out.append(cand)
    return out


def solve_planar_3(S, T, explain=False):
    return _last_axis_roll(S, T, [0, 1], explain)


def solve_point_plus_roll(S, T, explain=False):
    return _last_axis_roll(S, T, [0, 1, 2], explain)


def solve_position_approach(S: Screws, T, explain=False, approach_only=False):
    """Axes 4 and 5 meet at c on the approach line: c = p - d a, then subproblem 2."""
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    c0 = common_point(S.point[3:], S.axis[3:], np.inf)
    d = float((p0 - c0) @ a0)
    a = T[:3, 2]
    ct = T[:3, 3] - d * a
    out = []
    for ps in place_point(S, [0, 1, 2], c0, ct, explain):
        R123 = _product(S, [0, 1, 2], ps.x)[:3, :3]
        sols, exact, free = sp2(a0, R123.T @ a, S.axis[3], S.axis[4])
        for k, (t4, t5) in enumerate(sols):
            cand = Candidate(q=np.concatenate([ps.x, [t4, t5]]), signs=dict(ps.signs),
                             free=list(ps.free))
            if len(sols) == 2:
                cand.signs[4] = "+" if k == 0 else "-"
            if free:
                cand.free.append(3)
            if explain:
                cand.trace = [("wrist point where axes 4 and 5 meet (target)", ct.tolist(),
                               "length")] + list(ps.trace) + [
                    ("approach to reach, in the frame after joints 1-3", (R123.T @ a).tolist(),
                     "none"),
                    ("joints 4, 5 by subproblem 2", [float(t4), float(t5)], "angle")]
            out.append(cand)
    return out


def solve_pitch_roll(S: Screws, T, explain=False, approach_only=False):
    """Joint 1 from the position, q2 + q3 + q4 from the approach, joints 2-3 planar,
    joint 5 (the roll about the approach) from the orientation (free without one)."""
    h = S.axis[1]
    o1 = S.point[0]
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    pt, a = T[:3, 3], T[:3, 2]
    sgn = [float(np.sign(S.axis[i] @ h)) for i in (1, 2, 3)]
    t1s, ex1, _ = sp4(h, pt - o1, S.axis[0], float(h @ (p0 - o1)))
    out = []
    for i1, t in enumerate(t1s):
        q1 = -t
        E1i = _inv(_exp(S, 0, q1))
        a1 = E1i[:3, :3] @ a                     # approach with joint 1 undone
        p1 = E1i[:3, :3] @ pt + E1i[:3, 3]       # tool point with joint 1 undone
        psi, _, _ = sp1(a0, a1, h)               # the pitch sum (projected onto the plane)
        Rpsi = _rot(h, psi)
        p4t = p1 + Rpsi @ (S.point[3] - p0)      # where the point of axis 4 must go
        for ps in place_point(S, [1, 2], S.point[3], p4t, explain):
            q2, q3 = ps.x
            q4 = (psi - sgn[0] * q2 - sgn[1] * q3) * sgn[2]
            q = np.array([q1, q2, q3, q4, 0.0])
            cand = Candidate(q=q, signs={0: "+" if i1 == 0 else "-", **ps.signs},
                             free=list(ps.free))
            if approach_only:
                cand.signs[4] = "any"    # the roll was not asked for: 0 stands for any value
            else:
                R = _product(S, range(4), q[:4])[:3, :3]
                q[4] = _angle_about(S.axis[4], R.T @ T[:3, :3] @ S.M[:3, :3].T)
            if explain:
                cand.trace = [("joint 1 by subproblem 4 (component along the parallel axes)",
                               float(q1), "angle"),
                              ("q2 + q3 + q4 from the approach by subproblem 1", float(psi),
                               "angle"),
                              ("point of axis 4 to place (target)", p4t.tolist(), "length")] + \
                    list(ps.trace) + [("joint 5 (roll about the approach)", float(q[4]), "angle")]
            out.append(cand)
    return out


def solve_general_6r(S, T, explain=False, robot=None):
    from .general6r import solve_general_6r as solver
    qs = sorted(solver(robot, T), key=lambda q: (q[2], q[0]))
    # no +/- structure to name: label the roots of the eliminated joint (3) in order
    return [Candidate(q=q, signs={2: f"root {k + 1}"} if len(qs) > 1 else {})
            for k, q in enumerate(qs)]


SOLVERS = {
    "spherical-wrist": solve_spherical_wrist,
    "three-parallel": solve_three_parallel,
    "parallel-four-wrist": solve_parallel_four_wrist,
    "position-3": solve_position_3,
    "position-2": solve_position_2,
    "planar-3": solve_planar_3,
    "point-plus-roll": solve_point_plus_roll,
    "general-6r": solve_general_6r,
    "position-approach": solve_position_approach,
    "pitch-roll": solve_pitch_roll,
}
