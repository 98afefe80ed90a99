"""Result objects: the one source of both the JSON and the tables.

Results hold SI values (m, rad) and the display units chosen by the caller;
``to_dict()`` converts at the edge and returns plain JSON types. The JSON
document layout is the contract of PRODUCT.md; ``SCHEMA_VERSION`` goes up
when it changes on purpose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..units import angle_factor, length_factor

SCHEMA_VERSION = "1.0"


@dataclass(frozen=True)
class Units:
    """Display units: ``angle`` in {'deg', 'rad'}, ``length`` a key of LENGTH_UNITS."""

    angle: str = "deg"
    length: str = "m"

    @property
    def a(self) -> float:
        """Display angle units per radian."""
        return 1.0 / angle_factor(self.angle)

    @property
    def l(self) -> float:  # noqa: E743 - short on purpose, used in formulas
        """Display length units per metre."""
        return 1.0 / length_factor(self.length)

    def joints(self, robot, q) -> list[float]:
        """Joint values in display units (angle for revolute, length for prismatic)."""
        q = np.asarray(q, dtype=float)
        scale = np.where(robot.is_revolute, self.a, self.l)
        return json_numbers(q * scale)

    def pose(self, T) -> list:
        T = np.array(T, dtype=float)
        T[..., :3, 3] *= self.l
        return json_numbers(T)

    def to_dict(self) -> dict:
        return {"angle": self.angle, "length": self.length}


def json_numbers(x):
    """Nested lists of floats, rounded to 12 decimals (so 29.999999999999996 deg
    entered as 30 reads back as 30.0) and with -0.0 turned into 0.0."""
    arr = np.round(np.asarray(x, dtype=float), 12) + 0.0
    return arr.tolist()


def robot_summary(robot) -> dict:
    return {
        "name": robot.name,
        "title": robot.title,
        "dof": robot.dof,
        "joint_types": robot.joint_types,
        "convention": robot.convention,
    }


def json_header(command: str, robot, units: Units) -> dict:
    return {
        "kincalc": SCHEMA_VERSION,
        "command": command,
        "robot": robot_summary(robot),
        "units": units.to_dict(),
    }


def orientation_dict(R, units: Units) -> dict:
    """Every orientation format of PRODUCT.md for ``R (3, 3)``, angles in display units."""
    from .. import spatial as sp
    axis, angle = sp.axis_angle_from_matrix(R)
    return {
        "matrix": json_numbers(R),
        "rpy": json_numbers(sp.rpy_from_matrix(R) * units.a),
        "euler_zyz": json_numbers(sp.euler_zyz_from_matrix(R) * units.a),
        "euler_xyz": json_numbers(sp.euler_xyz_from_matrix(R) * units.a),
        "quaternion": json_numbers(sp.quaternion_from_matrix(R)),
        "axis_angle": {"axis": json_numbers(axis), "angle": json_numbers(float(angle) * units.a)},
        "rotation_vector": json_numbers(axis * angle * units.a),
    }


@dataclass(frozen=True)
class FKResult:
    """Forward kinematics at one configuration.

    ``T`` is ``T_world_tool`` (4, 4); ``links`` the convention's link
    transforms ``T_{i-1}^i`` (n, 4, 4) and ``cumulative`` the ``T_0^i``
    (n, 4, 4), or ``None`` when frames were not asked for.
    """

    robot: object
    q: np.ndarray
    T: np.ndarray
    units: Units
    links: np.ndarray | None = None
    cumulative: np.ndarray | None = None

    def tcv(self):
        """Tool configuration vector, or ``None`` when the last joint is prismatic or
        turned beyond :data:`~kincalc.spatial.TCV_MAX_ROLL` (ten turns: e^(q_n/pi) would
        be beyond kincalc's number limit, and from 2229 rad on infinite)."""
        from ..spatial import TCV_MAX_ROLL, tcv_from_transform
        if not self.robot.joints[-1].revolute or abs(self.q[-1]) > TCV_MAX_ROLL:
            return None
        w = tcv_from_transform(self.T, self.q[-1])
        w[:3] *= self.units.l
        return json_numbers(w)

    def to_dict(self) -> dict:
        u = self.units
        out = json_header("fk", self.robot, u)
        out.update({
            "q": u.joints(self.robot, self.q),
            "T": u.pose(self.T),
            "position": json_numbers(self.T[:3, 3] * u.l),
            "orientation": orientation_dict(self.T[:3, :3], u),
            "tcv": self.tcv(),
        })
        if self.links is not None:
            out["frames"] = [
                {"index": i + 1, "joint": j.name,
                 "link": u.pose(self.links[i]), "T": u.pose(self.cumulative[i])}
                for i, j in enumerate(self.robot.joints)
            ]
            out["base"] = u.pose(self.robot.base)
            out["tool"] = u.pose(self.robot.written_tool)
        return out


@dataclass(frozen=True)
class Singularity:
    """What is known about a (near-)singular configuration."""

    kinds: tuple[str, ...]          # e.g. ("wrist",), ("elbow-stretched",), ("unclassified",)
    descriptions: tuple[str, ...]   # one sentence each
    null_space: np.ndarray | None   # joint-velocity direction (n,) giving no tool motion
    lost_motion: np.ndarray | None  # tool twist direction (6,) the arm cannot produce


def display_jacobian(robot, J, units: Units) -> np.ndarray:
    """Geometric Jacobians ``J (..., 6, n)`` (SI) in display units, a new array, not rounded:
    linear rows in length per rad (revolute) or length per length (prismatic); angular rows
    of revolute columns rad/rad, of prismatic ones zero. (``jacobian`` and ``jacobian
    --batch`` take their measures from it.)"""
    J = np.array(J, dtype=float)
    J[..., :3, :] *= np.where(robot.is_revolute, units.l, 1.0)
    return J


@dataclass(frozen=True)
class JacobianResult:
    """Jacobian and its measures at one configuration.

    ``J`` is in SI (m/rad for revolute columns' linear rows). ``analytic``
    is ``(kind, J_A)`` or ``None``. ``sigma_normalised`` are the singular
    values of ``J`` with its linear rows divided by ``length_scale`` (m): the
    scale-free numbers from which rank, condition and singularity come. The
    singular values and manipulability in ``to_dict()`` are those of ``J`` in
    the display length unit.
    """

    robot: object
    q: np.ndarray
    frame: str
    J: np.ndarray
    units: Units
    sigma_normalised: np.ndarray
    rank: int
    length_scale: float
    generic_rank: int
    position_rank: int
    generic_position_rank: int
    singularity: Singularity | None
    analytic: tuple[str, np.ndarray | None] | None = None
    analytic_error: str | None = None

    @property
    def singular(self) -> bool:
        return self.singularity is not None

    def _base_J(self) -> np.ndarray:
        if self.frame == "base":
            return self.J
        from ..jacobian import rotate_jacobian
        return rotate_jacobian(self.J, self.robot.fk(self.q, column_walk=True)[:3, :3])

    def display_J(self, J) -> np.ndarray:
        """``J (6, n)`` in display units (:func:`display_jacobian`)."""
        return display_jacobian(self.robot, J, self.units)

    def to_dict(self) -> dict:
        u = self.units
        # the measures from the unrounded matrix, as `jacobian --batch` takes them (the same
        # bits for one configuration, whichever command prints it)
        Jd = self.display_J(self.J)
        s = np.linalg.svd(Jd, compute_uv=False)
        # the base-frame linear rows (the tool point's velocity) for the position measures
        Jv = self.display_J(self._base_J())[:3]
        sv = np.linalg.svd(Jv, compute_uv=False)[: self.generic_position_rank]
        # both measures over the motions the robot has at a generic configuration: a robot
        # with two joints on one line has one fewer, its last singular value always 0
        sn = self.sigma_normalised[: self.generic_rank]
        cond = float("inf") if self.singular or sn[-1] <= 0 else float(sn[0] / sn[-1])
        out = json_header("jacobian", self.robot, u)
        out.update({
            "q": u.joints(self.robot, self.q),
            "frame": self.frame,
            "rows": ["vx", "vy", "vz", "wx", "wy", "wz"],
            "J": json_numbers(Jd),
            "singular_values": json_numbers(s),
            "rank": self.rank,
            "manipulability": float(np.prod(s[: self.generic_rank])),
            # (a tool point that no joint moves has none: 0, not the empty product)
            "position_manipulability": float(np.prod(sv)) if len(sv) else 0.0,
            "condition": cond if np.isfinite(cond) else None,
            "length_scale": self.length_scale * u.l,
            "generic_rank": self.generic_rank,
            "singular": self.singular,
        })
        if self.singularity is not None:
            sg = self.singularity
            out["singularity"] = {
                "kinds": list(sg.kinds),
                "descriptions": list(sg.descriptions),
                "null_space": None if sg.null_space is None else json_numbers(sg.null_space),
                "lost_motion": None if sg.lost_motion is None else json_numbers(sg.lost_motion),
            }
        if self.analytic is not None:
            kind, JA = self.analytic
            out["analytic"] = {
                "angles": kind,
                "J": None if JA is None else json_numbers(self.display_J(JA)),
                "error": self.analytic_error,
            }
        return out


def locked_entries(robot, locked, u: Units) -> list:
    """``[{"joint": name, "value": v}]`` of held joints ``((index, value SI), ...)``, the
    values in the units ``u``: the ``locked`` field of ik and reach documents."""
    return [{"joint": robot.joints[j].name,
             "value": json_numbers(v * (u.a if robot.joints[j].revolute else u.l))}
            for j, v in locked]


def ik_document(result) -> dict:
    """The JSON document of an IK answer (:class:`~kincalc.ik.solve.IKResult`), in its
    units (the robot file's when it has none): what ``kincalc ik --json`` prints and the
    tables show."""
    from .words import dead_end_texts, reason_text
    robot = result.robot
    u = result.units or Units(length=robot.length_unit)
    out = json_header("ik", robot, u)
    out["target"] = {"T": u.pose(result.target.T),
                     "orientation_given": result.target.orientation}
    if result.target.approach is not None:
        out["target"]["approach"] = json_numbers(np.asarray(result.target.approach, float))
    if result.target.swivel is not None:
        out["target"]["swivel"] = json_numbers(result.target.swivel * u.a)
    if result.target.tcv is not None:          # the vector given: w1..w3 position, w4..w6
        a, roll = result.target.tcv           # the approach times exp(q_n / pi)
        w = np.concatenate([np.asarray(result.target.T, float)[:3, 3] * u.l,
                            np.asarray(a, float) * np.exp(roll / np.pi)])
        out["target"]["tcv"] = json_numbers(w)
        out["target"]["roll"] = json_numbers(roll * u.a)
    out.update({
        "reachable": result.reachable,
        "reason": reason_text(result.reason, robot, u),
        "method": {"family": result.family, "description": result.method,
                   "controls": result.controls},
        "count": len(result.solutions),
        "near": None if result.near is None else u.joints(robot, result.near),
        "solutions": [_ik_solution(robot, s, u, result) for s in result.solutions],
    })
    if result.locked:
        out["locked"] = locked_entries(robot, result.locked, u)
    if result.rejected is not None:
        out["rejected"] = [
            {"q": u.joints(robot, r["q"]), "branch": r["branch"],
             "reason": reason_text(r["reason"], robot, u),
             "residual": {"position": json_numbers(r["position_error"] * u.l),
                          "orientation": None if r["orientation_error"] is None
                          else json_numbers(r["orientation_error"] * u.a)}}
            for r in result.rejected]
        if result.note:
            out["rejected_note"] = result.note
    if result.dead_ends is not None:
        out["dead_ends"] = dead_end_texts(result.dead_ends, robot, u)
    return out


def _ik_solution(robot, s, u: Units, result) -> dict:
    from .words import continuum_text, singularity_text
    names = [j.name for j in robot.joints]
    d = {
        "q": u.joints(robot, s.q),
        "branch": s.branch,
        "residual": {"position": json_numbers(s.position_error * u.l),
                     "orientation": None if s.orientation_error is None
                     else json_numbers(s.orientation_error * u.a)},
        "within_limits": s.within_limits,
        "violations": [{"joint": names[i], "side": side,
                        "by": json_numbers(amount * (u.a if robot.joints[i].revolute else u.l))}
                       for i, amount, side in s.violations],
        "singular": s.singular,
        "singularity": singularity_text(robot, s),
        "continuum": None if s.continuum is None else continuum_text(s.continuum, names, u),
    }
    if s.change is not None:
        d["change_from_near"] = u.joints(robot, s.change)
    if s.trace is not None:                   # (explain: a family that noted no step says so)
        from .explain import worked_steps
        d["trace"] = worked_steps(robot, s, np.asarray(result.target.T, float), u,
                                  result.family)
    return d
