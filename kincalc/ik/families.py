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

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..spatial import cross
from ..spatial import matrix_from_unit_axis_angle as _rot

from ..structure import common_point
from ..subproblems import sp1, sp2, sp4
from ..subproblems._small import norm3
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
    """``(screws, family, why)`` of ``robot``: geometry facts, computed once per robot."""
    S = Screws.of(robot)
    family, why = classify(robot, S)
    return S, family, why


def _moves_along(S: Screws, idx, h) -> bool:
    """Do joints ``idx`` all rotate about, or slide along, direction ``h``?"""
    return all(_parallel(S.axis[i], h) for i in idx)


def classify(robot, S: Screws) -> tuple[Family | None, str]:
    """The family of ``robot`` (or None) and a sentence saying why."""
    n, rev = S.n, S.revolute
    if n == 6:
        fam = _classify_6(S)
        if fam is None:
            # the same structures seen from the tool: a spherical wrist at the base, ...
            fam = _classify_6(S.reversed())
            if fam is not None:
                fam = Family(f"reversed-{fam.name}",
                             fam.description + ", found on the chain reversed (the base "
                             "seen from the tool: joint k of it is joint 7 - k)",
                             fam.controls, fam.needs_orientation, reverse=True)
        if fam is not None:
            return fam, ""
    if n == 6 and rev.all():
        return (Family("general-6r", "general 6R: no decomposable structure; algebraic "
                                     "elimination (Raghavan-Roth, Manocha-Canny)",
                       "position and orientation", True), "")
    return _classify_small(robot, S)


def _classify_6(S: Screws) -> Family | None:
    """The six-joint families with a closed form, or None."""
    rev = S.revolute
    tol = 1e-7 * max(S.scale, 1.0)
    if rev[3:].all() and common_point(S.point[3:], S.axis[3:], tol) is not None:
        return Family("spherical-wrist",
                      "spherical wrist: axes 4, 5, 6 meet at one point; joints 1-3 place "
                      "the wrist centre, joints 4-6 set the orientation",
                      "position and orientation", True)
    wrist_pair = rev[4:].all() and common_point(S.point[4:], S.axis[4:], tol) is not None
    if wrist_pair and rev.all() and _parallel(S.axis[1], S.axis[2]) \
            and _parallel(S.axis[2], S.axis[3]) and not _parallel(S.axis[0], S.axis[1]) \
            and not _parallel(S.axis[4], S.axis[1]):
        return Family("three-parallel",
                      "three parallel axes (2, 3, 4) and axes 5, 6 intersecting (UR type)",
                      "position and orientation", True)
    if wrist_pair and rev[3] and _moves_along(S, range(4), S.axis[3]) \
            and not rev[:3].all() and not _parallel(S.axis[4], S.axis[3]):
        return Family("parallel-four-wrist",
                      "joints 1-4 all rotate about or slide along one direction (a SCARA-type "
                      "arm) and axes 5, 6 intersect (an offset wrist)",
                      "position and orientation", True)
    return None


def _classify_small(robot, S: Screws) -> tuple[Family | None, str]:
    """Families of fewer (or more) than six joints."""
    n, rev = S.n, S.revolute
    pos_rank = robot.generic_ranks[1]
    if n == 3 and pos_rank == 3:
        return (Family("position-3", "three joints placing the tool point in space",
                       "position", False), "")
    if n == 3 and rev.all() and _parallel(S.axis[0], S.axis[1]) and _parallel(S.axis[1], S.axis[2]):
        return (Family("planar-3", "planar 3R: three parallel axes; a point on axis 3 by "
                                   "joints 1-2, joint 3 from the orientation",
                       "position in the plane and rotation about the axes", True), "")
    if n == 2:
        return (Family("position-2", "two joints placing the tool point",
                       "position (on the surface the arm sweeps)", False), "")
    if n == 5 and rev[3:].all():
        fam = _classify_5(S)
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


def _classify_5(S: Screws) -> Family | None:
    """Five joints controlling the position and the approach direction (tool z)."""
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    tol = 1e-7 * max(S.scale, 1.0)
    c = common_point(S.point[3:], S.axis[3:], tol)
    if c is not None and float(np.linalg.norm(cross(p0 - c, a0))) < tol \
            and not _parallel(S.axis[4], a0, 1e-6):
        return Family("position-approach",
                      "five joints, axes 4 and 5 meeting on the tool's approach line: joints 1-3 "
                      "place the point where they meet, joints 4 and 5 turn the approach "
                      "direction (subproblem 2); the roll about it follows",
                      "position and approach direction (tool z)", True)
    on_axis5 = float(np.linalg.norm(cross(p0 - S.point[4], S.axis[4]))) < tol
    if S.revolute.all() and on_axis5 and _parallel(S.axis[4], a0, 1e-9) \
            and _parallel(S.axis[1], S.axis[2]) and _parallel(S.axis[2], S.axis[3]) \
            and not _parallel(S.axis[0], S.axis[1]) and not _parallel(S.axis[4], S.axis[1]):
        return Family("pitch-roll",
                      "five joints, axes 2, 3, 4 parallel and joint 5 rolling the tool about its "
                      "approach axis: joint 1 from the position (subproblem 4), the pitch sum "
                      "q2 + q3 + q4 from the approach (subproblem 1), a planar two-link problem "
                      "for joints 2 and 3, joint 5 from the orientation",
                      "position, the approach direction within the arm's plane, and the roll "
                      "about it", True)
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
    for ps in place_point(S, [0, 1, 2], c0, ct, explain):
        q123 = ps.x
        W = _inv(_product(S, [0, 1, 2], q123)) @ T @ S.inverse_M()
        out.extend(_wrist(S, W[:3, :3], q123, ps, [3, 4, 5], ct, explain))
    return out


def _wrist(S: Screws, RW, prefix_q, ps, idx, centre, explain):
    """Angles of three concurrent revolute axes idx with R(a1) R(a2) R(a3) = RW."""
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


def solve_three_parallel(S: Screws, T, explain=False) -> list[Candidate]:
    h = S.axis[1]
    c56 = common_point(S.point[4:], S.axis[4:], np.inf)
    ct = _from_tool(T, _point_in_tool(S, c56))
    R_t = T[:3, :3] @ S.inverse_M()[:3, :3]        # R(q) for the product of exponentials
    o1 = S.point[0]
    out = []
    # joint 1: the component along h of (c56 - o1) is unchanged by joints 2-4 (and 5, 6 fix c56)
    d = float(h @ (c56 - o1))
    t1s, ex1, free1 = sp4(h, ct - o1, S.axis[0], d)
    t1s = [-t for t in t1s]   # sp4 solved h . R(k1, t)(ct - o1) = d; we need R(k1, -q1)
    if not ex1:
        return []
    for i1, q1 in enumerate(t1s):
        R1 = _rot(S.axis[0], q1)
        # joint 5: h . R(k5, q5) k6 = h . R1^T R_t k6 (rotations about h drop out)
        t5s, ex5, free5 = sp4(h, S.axis[5], S.axis[4], float(h @ (R1.T @ R_t @ S.axis[5])))
        if not ex5:
            continue
        for i5, q5 in enumerate(t5s):
            R5 = _rot(S.axis[4], q5)
            # joint 6: R6^T R5^T h = R_t^T R1 h, i.e. R(k6, q6) (R_t^T R1 h) = R5^T h
            q6, _, free6 = sp1(R_t.T @ R1 @ h, R5.T @ h, S.axis[5])
            R6 = _rot(S.axis[5], q6)
            # sum of joints 2-4 about h
            R234 = R1.T @ R_t @ R6.T @ R5.T
            q234 = _angle_about(h, R234)
            # the point on axis 5 nearest axis 4 -> where axis 4 must be, then a planar 2R
            # Screws.exp and numpy's inverse on purpose (not _exp, _inv): at the stretched
            # elbow of a UR arm's home pose the elbow is a double root whose value and
            # up/down label follow the rounding of exactly these products
            T_rest = np.linalg.inv(S.exp(0, q1)) @ T @ S.inverse_M() @ np.linalg.inv(
                S.exp(5, q6)) @ np.linalg.inv(S.exp(4, q5))
            # T_rest = E2 E3 E4; the point of axis 4 at q = 0 maps to E2 E3 (p4) (E4 fixes it)
            p4 = S.point[3]
            p4t = T_rest[:3, :3] @ p4 + T_rest[:3, 3]
            for ps in place_point(S, [1, 2], p4, p4t, explain):
                q2, q3 = ps.x
                q4 = q234 - q2 - q3
                q = np.array([q1, q2, q3, q4, q5, q6])
                cand = Candidate(q=q, signs={0: "+" if i1 == 0 else "-",
                                             4: "+" if i5 == 0 else "-", **ps.signs})
                if free6:
                    cand.free.append(5)
                    cand.continuum = Continuum(3, 5, 1)
                if explain:
                    cand.trace = [("point where axes 5 and 6 meet (target)", ct.tolist(), "length"),
                                  ("joint 1 by subproblem 4 (component along the parallel "
                                   "axes)", float(q1), "angle"),
                                  ("joint 5 by subproblem 4", float(q5), "angle"),
                                  ("joint 6 by subproblem 1", float(q6), "angle"),
                                  ("q2 + q3 + q4 by subproblem 1", float(q234), "angle")] + ps.trace
                out.append(cand)
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
