"""Standard DH frames from joint axes: any serial chain (a poe robot, a URDF) as a DH table.

The construction is the textbook one (Spong, Hutchinson & Vidyasagar, *Robot Modeling and
Control*, sec. 3.2-3.3), on the joint axes as lines in frame 0 at q = 0: frame i's z axis
is joint i+1's axis, its x axis the common normal from axis i to axis i+1, so that each
frame differs from the previous by ``Rz(theta) Tz(d) Tx(a) Rx(alpha)``:

* skew axes: the unique common normal; x from axis i to axis i+1 (a > 0);
* intersecting axes: x along ``z_{i-1} x z_i``, the origin at the intersection (a = 0);
* parallel axes: the common normal through frame i-1's origin (d = 0), x towards axis
  i+1; coincident axes keep frame i-1's x (a = d = 0);
* a prismatic joint's axis is a direction only: its line is put through the previous
  frame's origin (any parallel line moves the same way), which makes a = 0 before it.

Frame 0 sits on joint 1's axis at the foot of the perpendicular from the robot's frame 0
origin, its x axis the robot's x axis made perpendicular to z (the DH ``base`` carries
the difference); the last frame (n) is frame n-1 turned and moved along its z so that its
x axis points along the tool's x axis where it can; the DH ``tool`` carries what
remains. Lengths in m, angles in rad.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..model import Joint, Robot
from ..spatial import invert_transform
from ..structure import dh_frames

#: axes whose directions' cross product is below this are parallel; lines closer than
#: this times the arm's size meet (both far below any real arm's geometry, far above
#: rounding of a computed axis)
LINE_TOL = 1e-9


def _perpendicular(v, z):
    """``v`` made perpendicular to the unit ``z`` and unit, or None if ``v`` is along z."""
    u = v - z * (v @ z)
    n = float(np.linalg.norm(u))
    return u / n if n > LINE_TOL else None


def _frame(origin, x, z) -> np.ndarray:
    F = np.eye(4)
    F[:3, 0], F[:3, 1], F[:3, 2], F[:3, 3] = x, np.cross(z, x), z, origin
    return F


def _dh_row(A) -> tuple[float, float, float, float]:
    """``(theta, d, a, alpha)`` of ``A = Rz(theta) Tz(d) Tx(a) Rx(alpha)``."""
    theta = float(np.arctan2(A[1, 0], A[0, 0]))
    alpha = float(np.arctan2(A[2, 1], A[2, 2]))
    a = float(A[0, 3] * np.cos(theta) + A[1, 3] * np.sin(theta))
    return theta, float(A[2, 3]), a, alpha


def axes_to_dh(robot: Robot) -> Robot:
    """``robot`` (any convention) as a standard-DH robot with the same FK.

    Parameters
    ----------
    robot : Robot
        Any serial robot (SI: m, rad); its joint axes at q = 0 are what is used.

    Returns
    -------
    Robot
        Convention ``dh``, one row per joint (revolute: ``theta`` the offset at q = 0;
        prismatic: ``d`` the offset), ``base`` = ``T_world_0`` of DH frame 0 and ``tool``
        = ``T_n_tool``, names, limits, home and units kept; ``fk(q)`` equals
        ``robot.fk(q)`` for every q (to rounding).
    """
    from ..fk import chain_frames
    n = robot.dof
    frames = chain_frames(robot.chain, np.zeros(n))        # joint frames in the world
    to0 = invert_transform(robot.base)
    axes = [(to0 @ f)[:3, 2] for f in frames]
    points = [(to0 @ f)[:3, 3] for f in frames]
    scale = max(robot.characteristic_length, 1.0)
    tool0 = to0 @ robot.fk(np.zeros(n))                    # the tool in frame 0, q = 0

    F = list(dh_frames(np.array(axes), np.array(points), scale, LINE_TOL,
                       robot.is_revolute))
    # frame 0 on joint 1's axis at the foot of the perpendicular from frame 0's origin
    # (a prismatic joint's line through that origin), x along the robot's x where it can
    z = axes[0]
    x = _perpendicular(np.array([1.0, 0.0, 0.0]), z)
    x = x if x is not None else _perpendicular(np.array([0.0, 1.0, 0.0]), z)
    o = points[0] - z * (points[0] @ z) if robot.joints[0].revolute else np.zeros(3)
    if robot.joints[0].revolute or n == 1:
        F[0] = _frame(o, x, z)
    else:       # joint 1 slides: frame 0 stays where frame 1's construction put it
        F[0] = _frame(F[0][:3, 3], x, z)
    # frame n: frame n-1 moved along its z to the tool's height, x towards the tool's x
    last = F[n - 1]
    xe = _perpendicular(tool0[:3, 0], last[:3, 2])
    xe = xe if xe is not None else last[:3, 0]
    lift = (tool0[:3, 3] - last[:3, 3]) @ last[:3, 2]
    F[n] = _frame(last[:3, 3] + lift * last[:3, 2], xe, last[:3, 2])

    joints = []
    for i, j in enumerate(robot.joints):
        theta, d, a, alpha = _dh_row(invert_transform(F[i]) @ F[i + 1])
        joints.append(Joint(name=j.name, type=j.type, alpha=alpha, a=a, d=d, theta=theta,
                            limits=j.limits))
    return dataclasses.replace(robot, convention="dh", joints=tuple(joints),
                               base=robot.base @ F[0], tool=invert_transform(F[n]) @ tool0,
                               M=None, expressions=())
