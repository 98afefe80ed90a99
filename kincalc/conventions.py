"""Rewriting a robot in another convention without changing its kinematics.

* standard DH -> modified DH: the modified row i takes ``alpha``/``a`` of the
  standard row i - 1 (zero for row 1), and ``Tx(a_n) Rx(alpha_n)`` of the last
  standard row moves into the tool (Craig 2005, sec. 3.4 vs. Spong et al.
  2006, sec. 3.2: both factor the same product
  ``Rz Tz (Tx Rx Rz Tz) ... (Tx Rx Rz Tz) Tx Rx`` differently).
* modified DH -> standard DH: the reverse; ``Rx(alpha_0) Tx(a_0)`` moves into
  the base.
* any -> POE: joint axes and points at q = 0 in frame 0, ``M = T_0_tool(0)``.

The joint variables keep their meaning (same zero, same direction), so FK
agrees for every q; intermediate link frames differ between conventions.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .model import Joint, Robot
from .spatial import invert_transform, rot_x, transform


def _xa(alpha, a):
    return transform(rot_x(alpha), [a, 0.0, 0.0])


def dh_to_mdh(robot: Robot) -> Robot:
    """The standard-DH ``robot`` as a modified-DH robot with identical FK."""
    if robot.convention != "dh":
        raise ValueError("dh_to_mdh needs a dh robot")
    joints, prev = [], (0.0, 0.0)
    for j in robot.joints:
        joints.append(dataclasses.replace(j, alpha=prev[0], a=prev[1]))
        prev = (j.alpha, j.a)
    tool = _xa(*prev) @ robot.tool
    return dataclasses.replace(robot, convention="mdh", joints=tuple(joints), tool=tool)


def mdh_to_dh(robot: Robot) -> Robot:
    """The modified-DH ``robot`` as a standard-DH robot with identical FK."""
    if robot.convention != "mdh":
        raise ValueError("mdh_to_dh needs an mdh robot")
    js = robot.joints
    base = robot.base @ _xa(js[0].alpha, js[0].a)
    joints = []
    for k, j in enumerate(js):
        nxt = (js[k + 1].alpha, js[k + 1].a) if k + 1 < len(js) else (0.0, 0.0)
        joints.append(dataclasses.replace(j, alpha=nxt[0], a=nxt[1]))
    return dataclasses.replace(robot, convention="dh", joints=tuple(joints), base=base)


def to_poe(robot: Robot) -> Robot:
    """Any ``robot`` as a product-of-exponentials robot with identical FK."""
    from .fk import chain_frames
    q0 = np.zeros(robot.dof)
    inv_base = invert_transform(robot.base)
    frames = inv_base @ chain_frames(robot.chain, q0)   # joint frames in frame 0
    joints = tuple(
        Joint(name=j.name, type=j.type, axis=tuple(frames[i, :3, 2]),
              point=tuple(frames[i, :3, 3]), limits=j.limits)
        for i, j in enumerate(robot.joints))
    M = inv_base @ robot.fk(q0)
    return dataclasses.replace(robot, convention="poe", joints=joints, tool=M)
