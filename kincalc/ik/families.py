"""The kinematic families, recognised from the joint axes (never from a robot's name).

:func:`classify` names the structure a closed form needs; :func:`plan` does it once
per robot and gives the screws the family's solver (:mod:`kincalc.ik.solvers`) runs
on. Families:

* ``spherical-wrist``: 6 joints, the last three revolute with concurrent axes
  (Pieper 1968): joints 1-3 (any R/P mix) place the wrist centre
  (:mod:`kincalc.ik.place`), the wrist sets the orientation (:mod:`kincalc.ik.wrists`).
* ``three-parallel``: 6 revolute joints, axes 2, 3, 4 parallel and axes 5, 6
  intersecting (the UR family).
* ``three-parallel-offset``: the same with axes 5 and 6 skew (IK-Geo's ``IK_3_parallel``):
  joints 1 and 5 together from subproblem 6.
* ``parallel-four-wrist``: 6 joints, joints 1-4 rotating about or sliding along one
  direction (3 R + 1 P, the slide anywhere: a SCARA-type arm) and axes 5, 6 intersecting:
  the textbook's offset-wrist R-P-R-R-R-R.
* ``position-3``: 3 joints whose tool point moves in 3-D: the point alone.
* ``planar-3``: 3 revolute joints with parallel axes: a point on axis 3 by joints 1-2,
  joint 3 from the orientation.
* ``position-2``: 2 joints: the tool point (on a plane, a cylinder, ...).
* ``planar-4``: 4 revolute joints, axes 1-3 parallel and axis 4 not: whole poses.
* ``point-plus-roll``: 4 joints, the last revolute: a point on axis 4 by joints 1-3
  (SCARA, the R-R-P-R spherical arm), joint 4 from the orientation; or 3 joints whose tool
  turns about axis 3, a point of it placed by joints 1-2 on the surface they sweep.
* ``position-approach``, ``pitch-roll``: five joints setting the position and the
  approach direction (tool z).
* ``planar-shoulder``, ``spherical-shoulder``: five revolute joints, axes 4 and 5 meeting
  on the approach line and axes 1-3 parallel or through one point, which place that point
  with a turn to spare: whole poses, the orientation first.
* ``wrist-pair``: five joints, axes 4 and 5 meeting at a point the tool carries (off its
  approach line, or the approach along axis 5), placed by joints 1-3: whole poses.
* ``reversed-...``: the six-joint structures, and the wrist pair, found on the chain seen
  from the tool.
* ``general-6r``: 6 revolute joints with no such structure: algebraic elimination
  (:mod:`kincalc.ik.general6r`).

A robot whose axes have a structure only nearly (within the structure tolerances, not
to rounding) is of that family but not ``exact``: it is solved on the nearest robot
that has it (:func:`idealised`) and refined (:mod:`kincalc.ik.nearly`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..spatial import cross

from ..structure import common_point
from ..tolerances import (EXACT_ANGLE_TOL, EXACT_POINT_TOL, STRUCTURE_ANGLE_TOL,
                          STRUCTURE_POINT_TOL)
from .cache import per_robot
from .screws import Screws


class Family(NamedTuple):
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
        """The key of :data:`~kincalc.ik.solvers.SOLVERS` for this family (``str``): its
        name without ``reversed-``."""
        return self.name.removeprefix("reversed-") if self.reverse else self.name


#: the pseudo-families of target kinds that bring their own solver: a tool configuration
#: vector (Schilling 1990; the last joint from the vector's length, the others placing the
#: tool point) and a pose at a swivel angle (kincalc.ik.swivel)
TCV = Family("tcv", "tool configuration vector: the last joint from |w4..w6|, the others "
             "place the tool point (or solve the whole pose where the approach fixes the "
             "orientation), the approach vector r3 is checked",
             "position, approach and roll", False)
SWIVEL = Family("srs-swivel", "spherical shoulder and wrist at a swivel angle: joint 4 from "
                "the shoulder-wrist distance, the shoulder turns the arm into the angle's "
                "plane, the wrist sets the orientation", "position, orientation and the "
                "swivel angle", True)
TARGET_FAMILIES = {"tcv": TCV, "swivel": SWIVEL}
#: the families whose axes 2, 3, 4 are parallel: joints 2-4 and 6 share a continuum at the
#: wrist singularity (axis 6 along them)
THREE_PARALLEL = ("three-parallel", "three-parallel-offset")


def _parallel(a, b, tol=1e-9) -> bool:
    return float(np.linalg.norm(cross(a, b))) < tol


@per_robot
def plan(robot) -> tuple[Screws, Family | None, str]:
    """``(screws, family, why)`` of ``robot``: geometry facts, computed once per robot.

    The solvers keep their robot-level constants on these screws
    (:meth:`~kincalc.ik.screws.Screws.constant`), so they too are computed once per robot.

    Parameters
    ----------
    robot : Robot
        Hashable for the cache (:class:`kincalc.model.Robot` is frozen).

    Returns
    -------
    screws : Screws
        Those the family's solver runs on (world frame at q = 0, SI): the robot's own, or
        for a robot only nearly of its family those of the nearest robot that is
        (:func:`idealised`).
    family : Family or None
        See :func:`classify`; None when no closed form covers the robot.
    why : str
        Why there is no family ("" when there is one).
    """
    S = Screws.of(robot)
    family, why = classify(robot, S)
    if family is not None and not family.exact:
        S = idealised(S, family.structure)
    return S, family, why


def idealised(S: Screws, structure) -> Screws:
    """The screws ``S`` moved the least way onto ``structure`` (:attr:`Family.structure`).

    Parallel axes are turned to their mean direction (each keeping its sense), meeting axes
    moved (parallel to themselves) through their least-squares common point, which for
    ``meet-approach`` is then taken onto the approach line; a ``roll`` axis becomes the
    approach line. Directions first, so that points meet on the final lines.

    Parameters
    ----------
    S : Screws
        The robot's screws (world frame at q = 0, m).
    structure : tuple of (str, tuple of int)
        ``(kind, joints)`` facts, 0-based joints.

    Returns
    -------
    Screws
        The nearest screws with the structure (same ``M`` and ``scale``).
    """
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
    return Screws(axis, point, S.revolute.copy(), S.M.copy(), S.scale)


def structure_defect(S: Screws, ideal: Screws) -> tuple[float, float]:
    """How far the screws ``ideal`` are from ``S``.

    Parameters
    ----------
    S, ideal : Screws
        The same chain's screws (world frame at q = 0, m).

    Returns
    -------
    move : float
        The largest distance (m) a joint's line moved (of ``ideal``'s point from ``S``'s line).
    turn : float
        The largest angle (rad, as its sine) an axis turned.
    """
    turn = float(np.max(norm3_rows(cross(S.axis, ideal.axis)), initial=0.0))
    d = ideal.point - S.point          # the new point's distance from the old line
    move = float(np.max(norm3_rows(d - (d * S.axis).sum(-1)[:, None] * S.axis), initial=0.0))
    return move, turn


def norm3_rows(v) -> np.ndarray:
    """Euclidean norms of the rows of ``v``.

    Parameters
    ----------
    v : array_like (..., 3)

    Returns
    -------
    ndarray (...)
    """
    return np.sqrt((np.asarray(v) ** 2).sum(-1))


def _moves_along(S: Screws, idx, h, tol: float) -> bool:
    """Do joints ``idx`` all rotate about, or slide along, direction ``h`` (within
    ``tol`` rad)?"""
    return all(_parallel(S.axis[i], h, tol) for i in idx)


def _independent_motions(S: Screws, joints, p) -> bool:
    """Do those of ``joints`` that move the point ``p`` (world frame at q = 0, m) move it in
    independent directions, at some of a few seeded configurations? Not when three
    parallel or three concurrent axes place it (on a plane, on a sphere, with a turn to
    spare that the orientation must decide). A joint that never moves it (an axis through
    it) does not count."""
    def placed(x):
        y = np.asarray(p, float)
        for j, v in zip(reversed(joints), reversed(x)):
            y = S.move(j, v, np.cos(v), np.sin(v), y)
        return y
    h, per = 1e-6, np.where(S.revolute[list(joints)], max(S.scale, 1e-12), 1.0)[:, None]
    for x in np.random.default_rng(7).uniform(-2.0, 2.0, (3, len(joints))):
        rates = np.array([placed(x + h * e) - placed(x - h * e) for e in np.eye(len(joints))])
        rates /= 2 * h * per                                  # per radian, in units of scale
        moving = rates[np.linalg.norm(rates, axis=1) > 1e-6]
        if np.linalg.matrix_rank(moving, tol=1e-6) == len(moving):
            return True
    return False


def classify(robot, S: Screws) -> tuple[Family | None, str]:
    """The family of ``robot`` (or None) and a sentence saying why.

    A family is recognised when the axes meet and are parallel as it needs to within
    :data:`~kincalc.tolerances.STRUCTURE_POINT_TOL` (times the arm's size, or metres for
    an arm smaller than 1 m) and
    :data:`~kincalc.tolerances.STRUCTURE_ANGLE_TOL` (rad), or both within the robot's own
    ``structure_tol`` when it has one. It is ``exact`` when they do to within
    ``EXACT_POINT_TOL`` and ``EXACT_ANGLE_TOL`` (rounding): a calibrated model or a
    rounded datasheet gives a robot that is only nearly of its family, whose closed-form
    solutions the dispatcher refines on the true robot.

    Parameters
    ----------
    robot : Robot
        Gives ``generic_ranks`` and ``structure_tol`` (optional).
    S : Screws
        The robot's screws (:meth:`Screws.of <kincalc.ik.screws.Screws.of>`).

    Returns
    -------
    family : Family or None
        ``general-6r`` (always exact) for six revolute joints of no other structure.
    why : str
        Why there is no family (redundant, or no analytic solver); "" when there is one.
    """
    tol = getattr(robot, "structure_tol", None)
    family, why = _classify(robot, S, STRUCTURE_POINT_TOL if tol is None else tol,
                            STRUCTURE_ANGLE_TOL if tol is None else tol)
    if family is not None and family.name != "general-6r":
        strict, _ = _classify(robot, S, EXACT_POINT_TOL, EXACT_ANGLE_TOL)
        if strict is not None and strict.name != "general-6r" \
                and strict.controls == family.controls:
            # a structure the robot has exactly wins over one it has only nearly, where both
            # take the same targets: its closed form is of the true robot, where the other's,
            # refined by Newton, can lose the roots the nearest robot of that family does not
            # have (an iiwa held at A6 = 0.005 deg is a spherical wrist to 2e-5 m, and a
            # reversed one exactly)
            family = strict
        else:
            family = family._replace(exact=False)
    return family, why


def _classify(robot, S: Screws, point_tol: float, angle_tol: float
              ) -> tuple[Family | None, str]:
    """:func:`classify` with the given structure tolerances (relative, rad)."""
    n, rev = S.n, S.revolute
    r = robot.generic_ranks[0]
    if n > 6 or (n > 1 and r < n):              # more joints than independent motions
        # (a family's closed form would place isolated points of a continuum, or none)
        return None, (f"redundant: {n} joints for {r} independent pose component"
                      f"{'s' if r != 1 else ''}, so infinitely many solutions")
    if n == 6:
        fam = _classify_6(S, point_tol, angle_tol)
        if fam is None:
            # the same structures seen from the tool: a spherical wrist at the base, ...
            fam = _classify_6(S.reversed(), point_tol, angle_tol)
            fam = None if fam is None else _reversed(fam, n)
        if fam is not None:
            return fam, ""
    if n == 6 and rev.all():
        return (Family("general-6r", "general 6R: no decomposable structure; algebraic "
                                     "elimination (Raghavan-Roth, Manocha-Canny)",
                       "position and orientation", True), "")
    return _classify_small(robot, S, point_tol, angle_tol)


def _reversed(fam: Family, n: int) -> Family:
    """``fam``, found on the chain of ``n`` joints reversed, as the robot's family."""
    # the facts hold of the same lines: name them by the robot's joints
    facts = tuple((kind, tuple(sorted(n - 1 - j for j in js))) for kind, js in fam.structure)
    return Family(f"reversed-{fam.name}", fam.description + ", found on the chain reversed "
                  f"(the base seen from the tool: joint k of it is joint {n + 1} - k)",
                  fam.controls, fam.needs_orientation, reverse=True, structure=facts)


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
    three = rev.all() and _parallel(S.axis[1], S.axis[2], par) \
        and _parallel(S.axis[2], S.axis[3], par) and not _parallel(S.axis[0], S.axis[1]) \
        and not _parallel(S.axis[4], S.axis[1])
    if three and wrist_pair:
        return Family("three-parallel",
                      "three parallel axes (2, 3, 4) and axes 5, 6 intersecting (UR type)",
                      "position and orientation", True,
                      structure=(("parallel", (1, 2, 3)), ("meet", (4, 5))))
    if three and not _parallel(S.axis[4], S.axis[5], par):
        return Family("three-parallel-offset",
                      "three parallel axes (2, 3, 4), axes 5 and 6 skew: joints 1 and 5 from "
                      "two equations along the parallel axes (subproblem 6)",
                      "position and orientation", True, structure=(("parallel", (1, 2, 3)),))
    if wrist_pair and np.count_nonzero(~rev[:4]) == 1 \
            and _moves_along(S, range(4), S.axis[3], par) and not _parallel(S.axis[4], S.axis[3]):
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
    if n == 3 and rev[2] and _independent_motions(S, (0, 1), S.point[2]):  # tool turns about axis 3
        return (Family("point-plus-roll", "a point on axis 3 placed by joints 1-2 (on the "
                       "surface they sweep), joint 3 from the orientation about its axis",
                       "position on a surface and rotation about axis 3", True), "")
    if n == 2:
        return (Family("position-2", "two joints placing the tool point",
                       "position (on the surface the arm sweeps)", False), "")
    if n == 5 and rev[3:].all():
        fam = _classify_5(S, point_tol, par)
        if fam is not None:
            return fam, ""
    if n == 5 and rev[:2].all():                 # the wrist pair at the base
        fam = _wrist_pair(S.reversed(), point_tol)
        if fam is not None:
            return _reversed(fam, n), ""
    roll = Family("point-plus-roll", "a point on axis 4 placed by joints 1-3, joint 4 from the "
                  "orientation about its axis", "position and rotation about axis 4", True)
    if n == 4 and rev[3] and pos_rank == 3 and _independent_motions(S, (0, 1, 2), S.point[3]):
        return roll, ""
    if n == 4 and rev[0] and not rev[3]:            # a slide last (an R-R-R-P SCARA)
        R = S.reversed()
        if _independent_motions(R, (0, 1, 2), R.point[3]):
            return _reversed(roll._replace(controls="position and rotation about axis 1"), n), ""
    # (axes 2-4 parallel, the same seen from the tool, is a point of axis 4 and a roll)
    planar = _planar_4(S, par) if n == 4 and rev.all() else None
    if planar is not None:
        return planar, ""
    why = (f"no analytic solver for this structure yet ({n} joints, "
           f"{''.join('R' if r else 'P' for r in rev)})")
    return None, why


def _planar_4(S: Screws, par: float) -> Family | None:
    """Four revolute joints, axes 1-3 parallel and axis 4 not."""
    h = S.axis[0]
    if not (_parallel(h, S.axis[1], par) and _parallel(h, S.axis[2], par)) \
            or _parallel(h, S.axis[3], par):
        return None
    return Family("planar-4", "four joints, axes 1-3 parallel and axis 4 not: the turn about "
                  "the parallel axes and joint 4 from the orientation (subproblem 1), joints 1 "
                  "and 2 place axis 3, joint 3 completes the turn",
                  "position and orientation (the poses four joints reach)", True,
                  structure=(("parallel", (0, 1, 2)),))


def _classify_5(S: Screws, point_tol: float, par: float) -> Family | None:
    """Five joints controlling the position and the approach direction (tool z)."""
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    tol = point_tol * max(S.scale, 1.0)
    c = common_point(S.point[3:], S.axis[3:], tol)
    pair = c is not None and float(np.linalg.norm(cross(p0 - c, a0))) < tol \
        and not _parallel(S.axis[4], a0, 1e-6)
    if pair and _independent_motions(S, (0, 1, 2), c):
        return Family("position-approach",
                      "five joints, axes 4 and 5 meeting on the tool's approach line: joints 1-3 "
                      "place the point where they meet, joints 4 and 5 turn the approach "
                      "direction (subproblem 2); the roll about it follows",
                      "position and approach direction (tool z)", True,
                      structure=(("meet-approach", (3, 4)),))
    if pair and S.revolute.all():        # joints 1-3 place that point with a turn to spare
        return _shoulder_5(S, c, tol, par)
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
    if pair:
        return None
    fam = _wrist_pair(S, point_tol)
    if fam is None and c is not None and S.revolute.all():
        # axes 1-3 cannot place c alone (parallel, or through one point): a turn to spare
        fam = _shoulder_5(S, c, tol, par, on_approach=False)
    return fam


def _wrist_pair(S: Screws, point_tol: float) -> Family | None:
    """Five joints, axes 4 and 5 (revolute) meeting at a point the tool carries, placed by
    joints 1-3, not a ``position-approach`` arm (the point off the approach line, or the
    approach along axis 5): whole poses only (a position and an approach leave the roll,
    which moves the point or does not turn joint 5)."""
    tol = point_tol * max(S.scale, 1.0)
    c = common_point(S.point[3:5], S.axis[3:5], tol)
    if c is None or not S.revolute[3:5].all() or not _independent_motions(S, (0, 1, 2), c):
        return None
    return Family("wrist-pair",
                  "five joints, axes 4 and 5 meeting at a point the tool carries (off its "
                  "approach line, or the approach along axis 5): joints 1-3 place that point "
                  "where the pose puts it, joints 4 and 5 take the orientation left "
                  "(subproblem 2, then the roll)",
                  "position and orientation (the poses five joints reach)", True,
                  structure=(("meet", (3, 4)),))


def _shoulder_5(S: Screws, c, tol: float, par: float, on_approach: bool = True
                ) -> Family | None:
    """Five revolute joints, axes 4 and 5 meeting at ``c`` (on the approach line, or
    ``on_approach`` False: elsewhere in the tool, or with the approach along axis 5), axes 1-3
    parallel (a plane) or through one point (a sphere): the shoulder places ``c`` with a turn
    to spare, which a whole pose's orientation decides."""
    h = S.axis[0]
    where, meet = ("on the tool's approach line", "meet-approach") if on_approach else \
        ("at a point the tool carries", "meet")
    if _parallel(h, S.axis[1], par) and _parallel(h, S.axis[2], par) \
            and not _parallel(h, S.axis[3], par):
        return Family("planar-shoulder",
                      f"five joints, axes 1-3 parallel and axes 4 and 5 meeting {where}: "
                      "joint 4 from the height of axis 5 (subproblem 4), the "
                      "planar arm's turn and joint 5 from the orientation (subproblem 1), "
                      "joints 1 and 2 place axis 3, joint 3 completes the turn",
                      "position and orientation (the poses five joints reach)", True,
                      structure=(("parallel", (0, 1, 2)), (meet, (3, 4))))
    o = common_point(S.point[:3], S.axis[:3], tol)
    if o is not None and float(np.linalg.norm(c - o)) > tol:
        return Family("spherical-shoulder",
                      f"five joints, axes 1-3 meeting at one point and axes 4 and 5 meeting "
                      f"{where}: joints 4 and 5 turn the wrist point into the "
                      "pose's frame (subproblem 2), the shoulder takes the orientation left",
                      "position and orientation (the poses five joints reach)", True,
                      structure=(("meet", (0, 1, 2)), (meet, (3, 4))))
    return None


#: the families that control the tool's approach direction but not the roll about it
APPROACH_FAMILIES = ("position-approach", "pitch-roll")
