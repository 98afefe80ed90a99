"""The closed forms of the arms of two to five joints, for a batch of targets (see
:mod:`kincalc.ik.solvers`, whose table :data:`~kincalc.ik.solvers.SOLVERS` names them):
the position families, the planar and point-plus-roll arms, the five-joint arms that set
a position and an approach, and the tool configuration vector.

Each solver takes the family's screws ``S`` (world frame at q = 0, SI; see
:mod:`kincalc.ik.screws`), the targets (:class:`~kincalc.ik.target.Targets`) and a
:class:`~kincalc.ik.branches.Branches` with one slot per target, and returns the
branches with every joint solved: candidates, which the engine checks by FK, labels
and flags.
"""

from __future__ import annotations

import numpy as np

from ..structure import common_point
from ..subproblems import sp1, sp2, sp4
from .branches import Branches
from .pieces import (angle_about as _angle_about, one_root as _one, rotate as _mv,
                     target_rotation, tool_point)
from .place import place
from .screws import Screws
from .wrists import normal_to, undo


def position_3(S: Screws, targets, br: Branches) -> Branches:
    """Three joints place the tool point.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions ``T[:, :3, 3]`` (m) (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    return place(S, br, (0, 1, 2), S.M[:3, 3], targets.T[:, None, :3, 3], what="the tool")


def position_2(S: Screws, targets, br: Branches) -> Branches:
    """Two joints place the tool point (on the surface they sweep).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions ``T[:, :3, 3]`` (m) (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved (two joints reach a surface: the FK check decides)
    """
    return place(S, br, (0, 1), S.M[:3, 3], targets.T[:, None, :3, 3], what="the tool")


def _last_axis_roll(S: Screws, targets, br: Branches, first) -> Branches:
    """A point of the last axis placed by ``first`` joints, then the last joint's roll
    about its axis from the orientation (subproblem 1)."""
    n = S.n
    T = targets.T
    br = place(S, br, first, S.point[n - 1], tool_point(S, T, S.point[n - 1]),
               what=f"axis {n}")
    Rt = target_rotation(S, T)
    k = S.axis[n - 1]
    e = S.constant(("normal to axis", n - 1), lambda: normal_to(k))
    return br.set(n - 1, *_angle_about(k, e, undo(S, br, first, np.broadcast_to(
        _mv(Rt, e), (br.N, br.K, 3)))))


def planar_3(S: Screws, targets, br: Branches) -> Branches:
    """Three parallel revolute axes: a point of axis 3 by joints 1-2, joint 3 from the orientation.

    Joint 3 by subproblem 1.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    return _last_axis_roll(S, targets, br, (0, 1))


def point_plus_roll(S: Screws, targets, br: Branches) -> Branches:
    """A point of axis 4 by joints 1-3, joint 4 from the orientation (subproblem 1).

    SCARA, the R-R-P-R spherical arm.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` poses ``T (N, 4, 4)`` (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    return _last_axis_roll(S, targets, br, (0, 1, 2))


def position_approach(S: Screws, targets, br: Branches) -> Branches:
    """Five joints, axes 4 and 5 meeting at ``c`` on the approach line.

    ``c = p - d a`` is placed by joints 1-3, then joints 4 and 5 turn the approach
    (subproblem 2; its least-squares answer kept, for the reasons of an unreachable
    approach). The roll about the approach follows.

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions with approaches ``(N, 3)``, or poses (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    T = targets.T
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    c0 = S.constant("wrist point", lambda: common_point(S.point[3:], S.axis[3:], np.inf))
    d = float((p0 - c0) @ a0)
    a = targets.approach if targets.kind == "approach" else T[:, :3, 2]
    ct = (T[:, :3, 3] - d * a)[:, None, :]
    br = place(S, br, (0, 1, 2), c0, ct, what="the point where axes 4 and 5 meet")
    v = undo(S, br, (0, 1, 2), np.broadcast_to(a[:, None, :], (br.N, br.K, 3)))
    return br.branch([3, 4], sp2(np.broadcast_to(a0, v.shape), v, S.axis[3], S.axis[4]),
                     least_squares=True)


def pitch_roll(S: Screws, targets, br: Branches) -> Branches:
    """Five joints, axes 2-4 parallel and joint 5 rolling the tool about its approach.

    Joint 1 from the position (subproblem 4), the pitch sum from the approach (subproblem
    1), joints 2-3 planar, joint 5 from the orientation (any value, 0, for an approach
    alone: labelled ``any``).

    Parameters
    ----------
    S : Screws, the family's (world frame at q = 0, SI)
    targets : Targets, ``N`` positions with approaches ``(N, 3)``, or poses (world frame, SI)
    br : Branches, one slot per target

    Returns
    -------
    Branches, every joint solved: the candidates, which the engine checks by FK
    """
    T = targets.T
    h, k1 = S.axis[1], S.axis[0]
    o1 = S.point[0]
    a0, p0 = S.M[:3, 2], S.M[:3, 3]
    pt = T[:, None, :3, 3]
    a = (targets.approach if targets.kind == "approach" else T[:, :3, 2])[:, None, :]
    br = br.branch([0], sp4(h, pt - o1, k1, h @ (p0 - o1)).negated())
    a1 = S.turn(0, br.cos[0], -br.sin[0], br.take(a))              # joint 1 undone
    p1 = o1 + S.turn(0, br.cos[0], -br.sin[0], br.take(pt) - o1)
    psi, cps, sps = _one(sp1(np.broadcast_to(a0, a1.shape), a1, h))
    # where axis 4's point must go: p1 + R_h(psi) (p4 - p0)
    d = S.point[3] - p0
    ch, sh = cps[..., None], sps[..., None]
    p4t = p1 + ch * d + sh * np.cross(h, d) + (1 - ch) * (d @ h) * h
    br = br.with_extra("psi", psi)
    br = place(S, br, (1, 2), S.point[3], p4t, what="axis 4")
    sgn = [float(np.sign(S.axis[i] @ h)) for i in (1, 2, 3)]
    q4 = (br.extra["psi"] - sgn[0] * br.value[1] - sgn[1] * br.value[2]) * sgn[2]
    br = br.set(3, q4, np.cos(q4), np.sin(q4))
    if targets.kind == "approach":        # the roll was not asked for: 0 stands for any
        z = np.zeros_like(q4)
        br = br.set(4, z, np.ones_like(z), z)
        return br.relabel(4, "any")
    k5 = S.axis[4]
    e = S.constant("normal to axis 5", lambda: normal_to(k5))
    Rt = target_rotation(S, T)
    return br.set(4, *_angle_about(k5, e, undo(S, br, (0, 1, 2, 3), np.broadcast_to(
        _mv(Rt, e), (br.N, br.K, 3)))))


def tcv(robot, S: Screws, targets, br: Branches) -> Branches:
    """A tool configuration vector ``w = [p; e^(qn/pi) r3]`` for one target.

    Schilling 1990; the FER Zagreb homework. The last joint from ``|w4..w6|``, the other
    joints place the tool point as the last joint turns it; the approach ``r3`` is checked by
    the engine. (The point depends on the target's roll, so the engine gives this one target
    at a time.)

    Parameters
    ----------
    robot : Robot
        Its ``name`` goes into the error.
    S : Screws
        The robot's screws (world frame at q = 0, SI); 3 or 4 joints, the last revolute.
    targets : Targets
        One target of kind ``"tcv"``: the position ``T[0, :3, 3]`` (m) and ``roll (1,)``
        (rad), the last joint's value.
    br : Branches
        One slot.

    Returns
    -------
    Branches
        Every joint solved; the last joint is ``roll`` in every slot.

    Raises
    ------
    TargetMismatch
        The last joint is not revolute, or the robot has other than 3 or 4 joints.
    ValueError
        More than one target.
    """
    from ..errors import TargetMismatch
    n = S.n
    if not S.revolute[n - 1] or n - 1 not in (2, 3):
        raise TargetMismatch(robot.name, "tcv robot")
    if br.N != 1:
        raise ValueError("tcv: one target at a time")
    qn = float(targets.roll[0])
    p = S.move_point(n - 1, qn, S.M[:3, 3])
    br = place(S, br, tuple(range(n - 1)), p, targets.T[:, None, :3, 3], what="the tool")
    q = np.full((br.N, br.K), qn)
    return br.set(n - 1, q, np.cos(q), np.sin(q))
