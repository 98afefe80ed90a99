"""The exercises of :mod:`kincalc.homework.quiz` that need no search: the DH table,
a link transform, forward kinematics and the Jacobian."""

from __future__ import annotations

import re

import numpy as np

from .numbers import (joint_text, length_word, lengths_in, nice_number, number,
                      number_array, pose_matrix, random_joints)
from .rules import SIGNIFICANT


# --- the kinds -------------------------------------------------------------------------

#: names the DH cell parser may treat as constants or functions, never as a joint variable
_RESERVED = {"theta", "d", "a", "alpha", "pi", "e", "sin", "cos", "tan", "sqrt", "deg", "rad"}


def variable_names(robot) -> list[str]:
    """The joint variables of the DH table: each joint's name when it is a plain
    identifier that no parameter or column uses, else ``q<i>``."""
    taken = {name for name, _ in robot.parameters} | _RESERVED
    out = []
    for i, j in enumerate(robot.joints, start=1):
        name = j.name
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name) or name in taken or name in out:
            name = f"q{i}"
            while name in taken or name in out:
                name = "_" + name
        out.append(name)
    return out


def _variable_cell(var: str, offset: float) -> str:
    off = number(offset)
    if off == 0:
        return var
    return f"{var} {'+' if off > 0 else '-'} {abs(off):.{SIGNIFICANT}g}"


def item_dh(robot, rng, units) -> dict:
    """The robot's own DH table in the compact form, angles and lengths in sheet units."""
    dh = robot.convention == "dh"
    cols = ["theta", "d", "a", "alpha"] if dh else ["alpha", "a", "d", "theta"]
    names = variable_names(robot)
    rows = []
    for j, var in zip(robot.joints, names):
        cells = {"theta": j.theta * units.a, "d": j.d * units.l, "a": j.a * units.l,
                 "alpha": j.alpha * units.a}
        row = {k: nice_number(number_array([v])[0]) for k, v in cells.items()}
        field = "theta" if j.revolute else "d"
        row[field] = _variable_cell(var, cells[field])
        rows.append([row[c] for c in cols])
    item = {"question": (
        f"Write the {'standard' if dh else 'modified (Craig)'} DH table of {robot.name}: one "
        f"row per joint with the columns {', '.join(cols)}"
        f"{'' if dh else ' (alpha and a of the previous link)'}, the joint variable "
        f"({', '.join(names)}) in its cell, e.g. '{names[0]} + 90'; angles in {units.angle}, "
        f"{lengths_in(units)}. Answer: {{convention: {robot.convention}, table: [[...], ...]}}.")}
    eye = np.eye(4)
    if not np.allclose(robot.tool, eye, atol=1e-12):
        item["tool"] = "ignore"
    if not np.allclose(robot.base, eye, atol=1e-12):
        item["base"] = "ignore"
    if "tool" in item or "base" in item:
        which = " and ".join(w for w in ("base", "tool") if w in item)
        item["question"] += f" The {which} transform{'s are' if ' and ' in which else ' is'} " \
                            "not asked."
    item["answer"] = {"convention": robot.convention, "columns": cols, "table": rows}
    return item


def item_link(robot, rng, units) -> dict:
    """``T_{i-1}^i`` of a random joint at a random value; only ``q_i`` is written."""
    i = int(rng.integers(robot.dof))
    shown, q = random_joints(robot, rng, units)
    j = robot.joints[i]
    frames = {"dh": "standard DH", "mdh": "modified DH (Craig)",
              "poe": "joint-axis (z along each joint axis)"}[robot.convention]
    unit = units.angle if j.revolute else (length_word(units) or "unitless")
    return {
        "question": (f"Compute the link transform T_{i}^{i + 1} of {robot.name} (the "
                     f"{frames} link frames of joint {i + 1}) at {j.name} = {shown[i]} {unit}. "
                     "Answer: the 4x4 matrix as a list of 4 rows; "
                     f"{lengths_in(units)}."),
        "link": i + 1,
        "q": shown[i],
        "answer": pose_matrix(robot.link_transforms(q)[i], units),
    }


def item_fk(robot, rng, units) -> dict:
    """``T_world_tool`` (base and tool included) at random joints."""
    shown, q = random_joints(robot, rng, units)
    return {
        "question": (f"Compute the tool pose T (world <- tool, base and tool transforms "
                     f"included) of {robot.name} at {joint_text(robot, shown, units)}. "
                     f"Answer: the 4x4 matrix as a list of 4 rows; {lengths_in(units)}."),
        "q": shown,
        "answer": pose_matrix(robot.fk(q), units),
    }


def item_jacobian(robot, rng, units) -> dict:
    """The geometric Jacobian in the base frame at random joints, display units."""
    shown, q = random_joints(robot, rng, units)
    J = np.array(robot.jacobian(q, frame="base"))
    J[:3, :] *= np.where(robot.is_revolute, units.l, 1.0)
    length = length_word(units) or "length units"
    per = f"{length}/rad" + ("" if robot.is_revolute.all() else
                             f", {length}/{length} for prismatic joints")
    return {
        "question": (f"Compute the geometric Jacobian of {robot.name} in the base (world) frame "
                     f"at {joint_text(robot, shown, units)}. Answer: 6 rows vx vy vz "
                     f"({per}) and wx wy wz (rad/rad), one column per joint."),
        "q": shown,
        "frame": "base",
        "answer": number_array(J),
    }
