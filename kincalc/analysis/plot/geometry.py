"""What a drawing of an arm shows, in SI: the polyline of joints and link corners, the
plane of a planar arm, and the titles of configurations."""

from __future__ import annotations

import numpy as np

from ..reports import joint_vector
from .style import ArmPoints, PLANAR_TOL


# --- geometry -------------------------------------------------------------------

def joint_points(robot, q) -> np.ndarray:
    """Where each joint is drawn: ``(n, 3)`` world points (m) on the joint axes.

    A revolute joint's point is the origin of its chain frame (the frame
    whose z axis is the joint axis, see :func:`kincalc.fk.chain_frames`); a
    prismatic joint's point is that origin before the joint's travel, where
    the sliding link leaves the previous one.
    """
    q = joint_vector(robot, q)
    frames = _frames(robot, q)
    travel = np.where(robot.is_revolute, 0.0, q + robot.chain.offset)
    return frames[:, :3, 3] - frames[:, :3, 2] * travel[:, None]


def arm_points(robot, q) -> ArmPoints:
    """The arm at joint values ``q (n,)`` (rad / m) as a polyline, world frame, metres.

    The polyline runs from the base origin (``robot.base``) through every
    joint (:func:`joint_points`; a prismatic joint adds its travel along its
    axis) to the tool point. A link whose offset has a component along the
    axis of the joint before it is drawn as an L: first along that axis,
    then across (for DH links ``d_i`` along ``z_{i-1}``, then ``a_i`` along
    ``x_i``), the corner being ``o + z ((p - o) . z)`` for the link from
    ``o`` to ``p`` with ``z`` the joint axis at ``o``.

    Returns
    -------
    ArmPoints
        ``points (m, 3)`` with ``n + 2 <= m``, the last one the tool
        position ``robot.fk(q)[:3, 3]``; ``tool (4, 4)`` ``T_world_tool``;
        ``base (4, 4)`` ``T_world_0``.
    """
    q = joint_vector(robot, q)
    frames = _frames(robot, q)
    starts = joint_points(robot, q)
    tool = robot.fk(q)
    base = np.array(robot.base, dtype=float)
    L = robot.characteristic_length
    pts = [base[:3, 3]]
    here, axis = base[:3, 3], base[:3, 2]
    for i in range(robot.dof):
        _leg(pts, here, axis, starts[i], L)
        here, axis = frames[i, :3, 3], frames[i, :3, 2]
        if not robot.joints[i].revolute:
            _append(pts, here, L)
    _leg(pts, here, axis, tool[:3, 3], L)
    return ArmPoints(np.array(pts), tool, base)


def _leg(pts, origin, axis, target, L):
    """Append the corner (when there is one) and ``target`` to the polyline.

    ``target`` is appended even when it repeats the last point, so that
    every joint and the tool are vertices of the polyline.
    """
    corner = origin + axis * float((target - origin) @ axis)
    tiny = 1e-6 * L
    if np.linalg.norm(corner - origin) > tiny and np.linalg.norm(target - corner) > tiny:
        _append(pts, corner, L)
    _append(pts, target, L, force=True)


def _append(pts, p, L, force=False):
    if force or np.linalg.norm(p - pts[-1]) > 1e-9 * L:
        pts.append(np.array(p, dtype=float))


def _frames(robot, q) -> np.ndarray:
    from ...fk import chain_frames
    return chain_frames(robot.chain, q)


def drawing_plane(robot, Q=None):
    """The plane a planar arm moves in, or ``None`` for an arm that needs 3D.

    An arm is planar when every revolute axis is parallel to one normal
    ``w``, every prismatic axis is perpendicular to it and every drawn point
    (over seeded random configurations within the limits, and ``Q (k, n)``
    when given) lies in one plane normal to ``w``.

    Returns
    -------
    (u, v, labels) or None
        ``u, v (3,)``: orthonormal in-plane directions with ``u x v = w``
        pointing at the viewer; world axes when the plane is a world
        coordinate plane. ``labels``: the names of ``u`` and ``v``.
    """
    rng = np.random.default_rng(20240607)
    L = robot.characteristic_length
    lo, hi = robot.limits.T
    span = np.where(robot.is_revolute, np.pi, L)
    lo = np.where(np.isfinite(lo), lo, -span)
    hi = np.where(np.isfinite(hi), hi, span)
    samples = rng.uniform(lo, hi, (6, robot.dof))
    if Q is not None:
        samples = np.concatenate([samples, np.asarray(Q, dtype=float).reshape(-1, robot.dof)])
    points, axes = [], []
    for q in samples:
        frames = _frames(robot, q)
        axes.append(frames[:, :3, 2])
        points.append(arm_points(robot, q).points)
    axes = np.concatenate(axes).reshape(len(samples), robot.dof, 3)
    points = np.concatenate(points)
    revolute = robot.is_revolute
    if np.any(revolute):
        w = axes[0, np.argmax(revolute)]
    else:  # only prismatic joints: the normal of their common plane, if any
        s, vt = np.linalg.svd(axes.reshape(-1, 3))[1:]
        if s[-1] > PLANAR_TOL * s[0]:
            return None
        w = vt[-1]
    if np.any(np.abs(np.abs(axes[:, revolute] @ w) - 1.0) > PLANAR_TOL):
        return None
    if np.any(np.abs(axes[:, ~revolute] @ w) > PLANAR_TOL):
        return None
    heights = points @ w
    if np.ptp(heights) > 10 * PLANAR_TOL * L:
        return None
    return _plane_basis(w)


def _plane_basis(w):
    """In-plane directions ``u, v`` for the normal ``w`` and their labels."""
    w = w / np.linalg.norm(w)
    e = np.eye(3)
    k = int(np.argmax(np.abs(w)))
    if abs(w[k]) > 1.0 - PLANAR_TOL:
        # a world coordinate plane: keep world axes, vertical axis up when there is one
        u, v = {2: (0, 1), 0: (1, 2), 1: (0, 2)}[k]
        return e[u], e[v], ("xyz"[u], "xyz"[v])
    ref = e[0] if abs(w[0]) < 0.9 else e[1]
    u = ref - w * (ref @ w)
    u /= np.linalg.norm(u)
    v = np.cross(w, u)
    return u, v, (f"u = ({_fmt_vec(u)})", f"v = ({_fmt_vec(v)})")


def _fmt_vec(x) -> str:
    return ", ".join(f"{c:.3g}" for c in np.round(x, 3) + 0.0)


def config_title(robot, q, units) -> str:
    """A panel title for joint values ``q (n,)`` (rad / m) in ``units``.

    ``"q = (0, -45, 180, 0, 45, 0) deg"``; prismatic joints are written as
    ``name=value unit``: ``"q = (0, 0, d3=0.5 m, 0, 0, 0) deg"``.
    """
    values = units.joints(robot, q)
    length = "" if units.length == "unitless" else f" {units.length}"
    parts = [_fmt_num(v) if j.revolute else f"{j.name}={_fmt_num(v)}{length}"
             for j, v in zip(robot.joints, values)]
    angle = f" {units.angle}" if any(j.revolute for j in robot.joints) else ""
    return f"q = ({', '.join(parts)}){angle}"


def _fmt_num(x: float) -> str:
    # 9 decimals: an IK solution's 1e-12 is a zero, and six digits are shown anyway
    s = f"{round(x, 9) + 0.0:.6g}"
    return "0" if s == "-0" else s
