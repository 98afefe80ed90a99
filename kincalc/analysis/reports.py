"""Single-configuration reports: forward kinematics and Jacobian analysis.

These build the result objects the CLI renders (and scripts may use
directly). Inputs are SI (rad, m); ``units`` only chooses how the result
will be shown.
"""

from __future__ import annotations

import numpy as np

from ..spatial import cross

from ..errors import InputError
from .results import FKResult, JacobianResult, Singularity, Units


def joint_vector(robot, q) -> np.ndarray:
    """``q`` as one configuration ``(n,)`` of ``robot`` (rad / m); InputError when it has
    the wrong length or a value that is not finite."""
    q = np.asarray(q, dtype=float)
    if q.shape != (robot.dof,):
        raise InputError(f"{robot.name} has {robot.dof} joints, got {q.size} joint values")
    if not np.all(np.isfinite(q)):
        raise InputError("joint values must be finite numbers")
    return q


def fk_report(robot, q, units: Units = Units(), frames: bool = False) -> FKResult:
    """Forward kinematics of ``robot`` at ``q (n,)`` (rad / m) as an :class:`FKResult`.

    With ``frames`` the result also holds every link transform ``T_{i-1}^i``
    and every ``T_0^i`` of the robot's own convention.
    """
    q = joint_vector(robot, q)
    T = robot.fk(q, column_walk=True)          # (the bits of the same q in a batch)
    links = cumulative = None
    if frames:
        links = robot.link_transforms(q)
        cumulative = np.empty_like(links)
        acc = np.eye(4)
        for i in range(robot.dof):
            acc = acc @ links[i]
            cumulative[i] = acc
    return FKResult(robot=robot, q=q, T=T, units=units, links=links, cumulative=cumulative)


def jacobian_report(robot, q, units: Units = Units(), frame: str = "base",
                    analytic: str | None = None) -> JacobianResult:
    """Jacobian of ``robot`` at ``q`` with its singular values, rank and singularity.

    Parameters
    ----------
    frame : {'base', 'tool'}
        Frame the geometric Jacobian is expressed in.
    analytic : {'rpy', 'zyz', 'xyz'} or None
        Also compute the analytic Jacobian for this angle set.
    """
    from ..jacobian import (analytic_jacobian, jacobian_base, numerical_rank, rotate_jacobian,
                            scale_free)
    from ..spatial import euler_xyz_from_matrix, euler_zyz_from_matrix, rpy_from_matrix

    q = joint_vector(robot, q)
    Jb = jacobian_base(robot.chain, q, column_walk=True)     # (the bits of q in a batch)
    T = robot.fk(q, column_walk=True)
    J = Jb if frame == "base" else rotate_jacobian(Jb, T[:3, :3].T)

    L = robot.characteristic_length
    Jn = scale_free(Jb, robot.is_revolute, L)
    U, s, Vt = np.linalg.svd(Jn)
    Up, sv, _ = np.linalg.svd(Jn[:3])
    rank, pos_rank = int(numerical_rank(s)), int(numerical_rank(sv))
    full, full_pos = robot.generic_ranks
    singularity = None
    if rank < full or pos_rank < full_pos:
        # the direction (base frame) the tool point cannot move in, when it has lost one
        stuck = stuck_direction(robot, q, Up, pos_rank) if pos_rank < full_pos else None
        singularity = _classify(robot, q, U, s, Vt, rank, stuck)

    result_analytic = err = None
    if analytic is not None:
        extract = {"rpy": rpy_from_matrix, "zyz": euler_zyz_from_matrix,
                   "xyz": euler_xyz_from_matrix}[analytic]
        angles = extract(T[:3, :3])
        try:
            result_analytic = (analytic, analytic_jacobian(Jb, angles, analytic))
        except np.linalg.LinAlgError:
            result_analytic = (analytic, None)
            err = (f"the {analytic} angles are at their representation singularity "
                   "(gimbal lock) here; the analytic Jacobian does not exist")
    return JacobianResult(robot=robot, q=q, frame=frame, J=J, units=units,
                          sigma_normalised=s, rank=rank, length_scale=L,
                          generic_rank=full, position_rank=pos_rank, generic_position_rank=full_pos,
                          singularity=singularity, analytic=result_analytic,
                          analytic_error=err)


def stuck_direction(robot, q, Up, rank: int) -> np.ndarray:
    """The direction (unit, base frame) the tool point cannot move in at the configuration
    ``q (n,)`` (``Up (3, 3)``: the left singular vectors of the scale-free linear rows there,
    of ``rank``), among those it moves in next to it, at a configuration 1e-3 (rad, or of
    the arm's size) away in a fixed random direction, off the singular set: a planar arm
    never leaves its plane, nor an arm of two joints its sphere, so their normals are no
    loss (the SVD's order among the zero singular values is arbitrary: a stretched planar
    arm's loss came out as the plane's normal)."""
    if robot.generic_ranks[1] == 3:
        return Up[:, rank]
    from ..jacobian import scale_free
    L = max(robot.characteristic_length, 1e-12)
    step = np.random.default_rng(0).standard_normal(robot.dof)
    beside = q + 1e-3 * step / np.linalg.norm(step) * np.where(robot.is_revolute, 1.0, L)
    Jv = scale_free(robot.jacobian(beside), robot.is_revolute, L)[:3]
    moves = np.linalg.svd(Jv)[0][:, :robot.generic_ranks[1]]
    here = Up[:, :rank]
    return np.linalg.svd(moves - here @ (here.T @ moves))[0][:, 0]


def _classify(robot, q, U, s, Vt, rank, stuck=None) -> Singularity:
    """Name the singularity from the axes' geometry where the structure allows; ``stuck``:
    the unit direction (base frame) the tool point cannot move in, if it lost one."""
    from ..structure import (joint_axes, parallel, point_line_distance,
                            spherical_wrist, wrist_centre)

    n = robot.dof
    dirs, pts = joint_axes(robot, q)
    L = robot.characteristic_length
    tol_len = 1e-6 * L
    tol_dir = 1e-6
    kinds, texts = [], []
    rev = robot.is_revolute

    # wrist: the last three joints revolute and the first and third of them aligned
    if n >= 6 and rev[n - 3:].all() and parallel(dirs[n - 3], dirs[n - 1], tol_dir):
        kinds.append("wrist")
        if point_line_distance(pts[n - 1], pts[n - 3], dirs[n - 3]) < tol_len:
            texts.append(f"wrist singularity: the axes of joints {n - 2} and {n} are aligned, "
                         f"so only q{n - 2} + q{n} (or q{n - 2} - q{n}) matters")
        else:
            # parallel but apart (a UR arm at q5 = 0): every revolute joint about that
            # direction turns the tool the same way, and only their signed sum is fixed
            group = [j + 1 for j in range(n) if rev[j] and parallel(dirs[j], dirs[n - 1], tol_dir)]
            texts.append(f"wrist singularity: the axis of joint {n} is parallel to those of "
                         f"joints {', '.join(map(str, group[:-1]))}, so only the signed sum "
                         f"of q{', q'.join(map(str, group))} is fixed by the orientation")

    wrist = spherical_wrist(robot)
    point = None
    if wrist is not None:
        point = wrist_centre(wrist, dirs, pts)
        if rev[0] and point_line_distance(point, pts[0], dirs[0]) < tol_len:
            kinds.append("shoulder")
            texts.append("shoulder singularity: the wrist centre lies on the axis of joint 1")
    elif n >= 4 and rev[1:4].all() and parallel(dirs[1], dirs[3], tol_dir) \
            and parallel(dirs[2], dirs[3], tol_dir):
        point = pts[3]  # three parallel axes: the elbow moves a point of axis 4

    if point is not None and n >= 3 and rev[1] and rev[2] and parallel(dirs[1], dirs[2], tol_dir):
        z = dirs[1]
        u = pts[2] - pts[1]
        u = u - z * (u @ z)
        v = point - pts[2]
        v = v - z * (v @ z)
        nu, nv = np.linalg.norm(u), np.linalg.norm(v)
        if nu > tol_len and nv > tol_len and np.linalg.norm(cross(u, v)) < 1e-6 * nu * nv:
            stretched = float(u @ v) > 0
            kinds.append("elbow-stretched" if stretched else "elbow-folded")
            texts.append("elbow singularity: the arm is fully "
                         + ("stretched" if stretched else "folded")
                         + " (axes 2 and 3 and the "
                         + ("wrist centre" if wrist is not None else "axis of joint 4")
                         + " lie in one plane)")

    null_space = Vt[-1] if n <= 6 and rank < n else None      # (s holds all n values)
    lost = U[:, rank] if rank < 6 and n >= 6 else None
    if not kinds and stuck is not None:
        kinds.append("position")
        texts.append(_position_text(robot, q, stuck, dirs, pts, tol_len, tol_dir))
    if not kinds:
        kinds.append("unclassified")
        msg = f"singular configuration: the Jacobian has rank {rank} instead of {robot.generic_ranks[0]}"
        if null_space is not None:
            msg += "; moving the joints along the null-space direction does not move the tool"
        texts.append(msg)
    if null_space is not None:
        # back from the normalised columns (prismatic ones scaled by L) to q-dot
        null_space = null_space * np.where(rev, 1.0, L)
        null_space = null_space / np.linalg.norm(null_space)
        k = int(np.argmax(np.abs(null_space)))
        null_space = null_space * np.sign(null_space[k])
    return Singularity(tuple(kinds), tuple(texts), null_space, lost)


def _position_text(robot, q, stuck, dirs, pts, tol_len, tol_dir) -> str:
    """The sentence of a position singularity: the direction ``stuck`` (unit, base frame)
    the tool point cannot move in, and the geometry where it says why: a planar arm
    stretched or folded, the tool point on the axis of joint 1."""
    from ..structure import parallel, point_line_distance
    rev = robot.is_revolute
    d = np.round(stuck * np.sign(stuck[np.argmax(np.abs(stuck))]), 3) + 0.0
    planar = all(parallel(dirs[j], dirs[0], tol_dir) for j in range(robot.dof) if rev[j]) \
        and robot.generic_ranks[1] == 2
    tip = robot.fk(q)[:3, 3]
    on_axis = bool(rev[0]) and point_line_distance(tip, pts[0], dirs[0]) < tol_len
    return ("position singularity: the tool point cannot move along "
            f"({d[0]:.3f}, {d[1]:.3f}, {d[2]:.3f}) (base frame)"
            + (": the planar arm is stretched or folded" if planar else
               ": it lies on the axis of joint 1 (a shoulder singularity)" if on_axis else ""))
