"""Grading a ``dh`` item: the student's DH (or modified DH) table compared with the
robot by forward kinematics on samples, with a hint per row that differs."""

from __future__ import annotations

import math

import numpy as np

from ...analysis.results import json_numbers
from ..sheet import DH_SAMPLES, Item, Sheet
from ..slips import display_q, fmt
from .common import ItemResult, unit_suffix


def grade_dh(sheet: Sheet, item: Item) -> ItemResult:
    import dataclasses

    from ...analysis.compare import match
    robot, units, tol = sheet.robot, sheet.units, item.tol
    ans = item.answer
    cand = ans["robot"]
    conv = cand.convention
    if cand.dof != robot.dof:
        return ItemResult(item.id, "dh", False, item.points, None,
                          f"the table has {cand.dof} row{'s' if cand.dof != 1 else ''}; "
                          f"{robot.name} has {robot.dof} joints")
    kw = {"allow_offsets": True, "free_base": item.base == "ignore", "samples": DH_SAMPLES,
          "free_tool": item.tool == "ignore",
          "tol": max(1e-9, tol.position / robot.characteristic_length)}
    m = match(robot, cand, **kw)
    details = {"position_error": m.position_error * units.l,
               "orientation_error": m.orientation_error * units.a,
               "worst_q": display_q(robot, m.worst_q, units).tolist() if m.worst_q is not None else None}
    if m.same:
        signs = ans["signs"] * m.signs
        offsets = ans["signs"] * m.offsets
        used = []
        for i in range(robot.dof):
            scale = units.a if robot.is_revolute[i] else units.l
            ref = robot.joints[i].name
            text = ("" if signs[i] > 0 else "-") + ref
            off = offsets[i] * scale
            if abs(off) > 1e-9 * max(1.0, scale):
                text += f" {'+' if off > 0 else '-'} {fmt(abs(off))}"
            if text != ref:
                used.append(f"your {ans['variables'][i]} = {text.replace(ref, 'robot ' + ref)}")
        details.update(signs=json_numbers(signs), offsets=json_numbers(offsets * np.where(
            robot.is_revolute, units.a, units.l)), variables=ans["variables"])
        frames = [w for w, on in (("base", kw["free_base"]), ("tool", kw["free_tool"])) if on]
        msg = (f"right: the table describes {robot.name} (same FK at {DH_SAMPLES} random "
               "configurations" + (f", {' and '.join(frames)} frame ignored" if frames else "") + ")")
        msg += ("; with other joint zeros or directions: " + ", ".join(used)) if used else \
            "; same joint variables"
        return ItemResult(item.id, "dh", True, item.points, m.position_error * units.l, msg,
                          details=details)

    hint = None
    other = "mdh" if conv == "dh" else "dh"
    if match(robot, dataclasses.replace(cand, convention=other), **kw).same:
        hint = (f"these rows are a right {_CONV_SHORT[other]} table, but the answer says "
                f"convention: {conv} (standard and modified DH mixed up)")
    k = m.first_bad_joint
    n = robot.dof
    # the row that places joint k's axis: row k in modified DH (alpha_{k-1}, a_{k-1} then
    # z_k); row k - 1 in standard DH (z_{k-1} is set by the row before); the end frame
    # (k = n + 1) is the tool in modified DH and row n in standard DH
    row = None if k is None else (k if conv == "mdh" else k - 1)
    has_tool = not np.allclose(cand.tool, np.eye(4))
    details["first_bad_joint"] = k
    details["first_bad_row"] = row if row is not None and 1 <= row <= n else None
    if k is None:
        msg = f"wrong: {m.reason}"
    elif row == 0:
        msg = (f"wrong: the axis of joint 1 is not the robot's ({m.reason}): it is z0, "
               "the base frame's z axis")
    elif k <= n:
        msg = (f"wrong: row {row} is the first that disagrees: it places the axis of joint "
               f"{k} ({m.reason})")
    else:
        where = ("the tool transform" if conv == "mdh" or has_tool else f"row {n}")
        msg = ("wrong: every joint axis is right, but the end frame is not the robot's tool "
               f"frame: check {where} (tool position differs by up to "
               f"{fmt(m.position_error * units.l)}{unit_suffix(units, 'length')})")
        if conv == "mdh" and not has_tool:
            hint = hint or ("the robot's tool frame is not the last joint's frame: add it as "
                            "'tool: {xyz: [...], rpy: [...]}' to the answer, or grade the axes "
                            "only with 'tool: ignore' on the item")
    if hint is None and k == 1:
        hint = _missing_base(robot, cand, kw)
    if hint is None and k is not None:
        hint = _row_hint(robot, cand, min(row, n) if row else None, units, tol)
    return ItemResult(item.id, "dh", False, item.points, m.position_error * units.l, msg,
                      hint, details)


_CONV_SHORT = {"dh": "standard DH", "mdh": "modified DH"}


def _missing_base(robot, cand, kw) -> str | None:
    """The hint for a table whose rows are right but that leaves out the robot's base
    frame (and its tool), where the item compares them; else None."""
    def left_out(frame):
        return not kw[f"free_{frame}"] and np.allclose(getattr(cand, frame), np.eye(4)) \
            and not np.allclose(getattr(robot, frame), np.eye(4))
    if not left_out("base"):
        return None
    frames = ["base"] + (["tool"] if left_out("tool") else [])
    from ...analysis.compare import match
    if not match(robot, cand, **dict(kw, **{f"free_{f}": True for f in frames})).same:
        return None
    what = " and ".join(f"'{f}: {{xyz: [...], rpy: [...]}}'" for f in frames)
    return (f"every row is right, but the robot's {' and '.join(frames)} frame"
            f"{'s are' if len(frames) > 1 else ' is'} left out: add {what} to the answer, or "
            f"grade the rows only with {', '.join(f'{f}: ignore' for f in frames)} on the "
            "item")


def _reference_table(robot, conv: str, fold_tool: bool):
    """The robot's own table in convention ``conv`` (None for poe robots); with
    ``fold_tool`` a standard-DH tool is folded into the last row where it fits."""
    from ...conventions import dh_to_mdh, mdh_to_dh
    if robot.convention == "poe":
        return None
    ref = robot if robot.convention == conv else \
        (dh_to_mdh(robot) if conv == "mdh" else mdh_to_dh(robot))
    if conv == "dh" and fold_tool and not np.allclose(ref.tool, np.eye(4)):
        ref = _fold_tool(ref) or ref
    return ref


def _row_hint(robot, cand, row, units, tol) -> str | None:
    """Where the answer's table first differs from the robot's own table, if at or
    before ``row`` (DH tables are not unique, so this is a hint, not the verdict)."""
    from ...spatial import wrap
    ref = _reference_table(robot, cand.convention, np.allclose(cand.tool, np.eye(4)))
    if ref is None:
        return None
    for k, (r, c) in enumerate(zip(ref.joints, cand.joints), start=1):
        if row is not None and k > row:
            break
        diffs = []
        if r.type != c.type:
            diffs.append(f"the joint is {r.type} there, {c.type} here")
        else:
            for f in ("alpha", "a", "d", "theta"):
                if (f == "theta" and r.revolute) or (f == "d" and not r.revolute):
                    continue              # the joint variable's own offset may differ
                rv, cv = getattr(r, f), getattr(c, f)
                angle = f in ("alpha", "theta")
                gap = abs(float(wrap(rv - cv))) if angle else abs(rv - cv)
                if gap > (tol.angle if angle else tol.position):
                    s = units.a if angle else units.l
                    diffs.append(f"{f} = {fmt(rv * s)} there, {fmt(cv * s)} here")
        if diffs:
            return (f"compare row {k} with the robot's own {_CONV_SHORT[cand.convention]} "
                    f"table ({'; '.join(diffs)}); that table has row {k}: "
                    f"{_reference_row(ref, k, units)}")
    return None


def _reference_row(ref, k: int, units) -> str:
    """Row ``k`` (1-based) of the dh/mdh robot ``ref``'s table, as text."""
    j = ref.joints[k - 1]
    var = j.name
    th = fmt(j.theta * units.a)
    d = fmt(j.d * units.l)
    theta = (var + (f" + {th}" if j.theta else "")) if j.revolute else th
    dd = (var + (f" + {d}" if j.d else "")) if not j.revolute else d
    return (f"theta = {theta}, d = {dd}, a = {fmt(j.a * units.l)}, "
            f"alpha = {fmt(j.alpha * units.a)}")


def _fold_tool(robot):
    """The standard-DH ``robot`` with a tool of the form Tz(d) Rz(th) Tx(a) Rx(alpha)
    folded into its last row, so that frame n is the tool frame; None if it is not."""
    import dataclasses

    from ...spatial import rot_x, rot_z, transform
    T = robot.tool
    R = T[:3, :3]
    alpha = math.atan2(R[2, 1], R[2, 2])
    theta = math.atan2(R[1, 0], R[0, 0])
    if abs(R[2, 0]) > 1e-9:
        return None
    d = T[2, 3]
    a = math.hypot(T[0, 3], T[1, 3])
    if a > 1e-12:
        theta = math.atan2(T[1, 3], T[0, 3])
        alpha = math.atan2(R[2, 1], R[2, 2])
    rebuilt = transform(rot_z(theta), [0, 0, d]) @ transform(rot_x(alpha), [a, 0, 0])
    if not np.allclose(rebuilt, T, atol=1e-9):
        return None
    last = robot.joints[-1]
    # Rz(th0 + q) Tz(d0) Tx(a0) Rx(al0) with a0 = al0 = 0 (frame n of mdh_to_dh) then the tool
    if abs(last.a) > 1e-12 or abs(last.alpha) > 1e-12:
        return None
    joint = dataclasses.replace(last, theta=last.theta + theta, d=last.d + d, a=a, alpha=alpha)
    return dataclasses.replace(robot, joints=robot.joints[:-1] + (joint,), tool=np.eye(4))
