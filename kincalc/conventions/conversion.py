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

A robot's ``expressions`` (the DH fields its file wrote as expressions over
``parameters``, e.g. ``('a', 'l1')``) travel with their values: ``alpha`` and
``a`` move to the neighbouring row together with their expressions, and an
expression whose value moves into the base or tool (or any value of a POE
robot) is dropped, the number being kept.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import InputError
from ..model import CONVENTIONS, Joint, Robot
from ..spatial import invert_transform, rot_x, transform

#: how each convention is named in messages and in a converted file's source
CONVENTION_NAMES = {"dh": "standard DH (dh)", "mdh": "modified DH (mdh)",
                    "poe": "product of exponentials (poe)"}


def convert(robot: Robot, to: str) -> Robot:
    """``robot`` rewritten in convention ``to`` ('dh', 'mdh' or 'poe'), same FK.

    Converting to the robot's own convention returns it unchanged. Otherwise
    the name, title, units, parameters, limits and home are kept, and the
    source ends with "(converted from <convention> by kincalc convert)".

    Parameters
    ----------
    robot : Robot
        The robot, SI (m, rad).
    to : {'dh', 'mdh', 'poe'}
        The convention to write it in.

    Returns
    -------
    Robot
        A new robot (or ``robot`` itself) whose ``fk(q)`` (``T_world_tool``) is the same
        for every q (:func:`dh_to_mdh`, :func:`mdh_to_dh`, :func:`to_poe`).

    Raises
    ------
    InputError
        ``to`` is not a convention.

    Notes
    -----
    poe to dh (or mdh) is the general line-geometry construction of
    :func:`kincalc.conventions.lines.axes_to_dh`: DH frames on the joint axes at q = 0,
    common normals for skew axes, the intersection for meeting ones, a normal through the
    previous origin for parallel ones, and a ``tool`` for what remains.
    """
    if to not in CONVENTIONS:
        raise InputError(f"the convention must be one of {', '.join(CONVENTIONS)}, not {to!r}")
    if to == robot.convention:
        return robot
    if to == "poe":
        out = to_poe(robot)
    elif robot.convention == "poe":
        from .lines import axes_to_dh
        out = axes_to_dh(robot) if to == "dh" else dh_to_mdh(axes_to_dh(robot))
    elif to == "mdh":
        out = dh_to_mdh(robot)
    else:
        out = mdh_to_dh(robot)
    _check_same_fk(robot, out)
    note = f"(converted from {CONVENTION_NAMES[robot.convention]} by kincalc convert)"
    source = f"{robot.source} {note}" if robot.source else note
    return dataclasses.replace(out, source=source)


def dh_of_axes(robot: Robot) -> tuple[Robot | None, str]:
    """The standard DH table of a poe robot's axes (a URDF's), to show beside its screws.

    Parameters
    ----------
    robot : Robot
        A ``poe`` robot, SI.

    Returns
    -------
    (Robot or None, str)
        The ``dh`` robot with the same FK and "", or None and why DH cannot describe these
        axes to full accuracy (nearly parallel consecutive axes: :func:`convert` refuses).
    """
    try:
        return convert(robot, "dh"), ""
    except InputError as exc:
        return None, str(exc)


#: a robot written in another convention, or as a file, has the same FK to this (of its
#: length scale, and rad)
SAME_FK = 1e-9


def fk_difference(robot: Robot, other: Robot) -> tuple[float, float, float]:
    """How far ``other``'s tool is from ``robot``'s, on q = 0 and a few configurations
    spread within the limits: ``(largest position difference (m), largest rotation-matrix
    entry difference, largest distance of robot's tool from the world origin (m))``."""
    from ..samples import spread
    lo, hi = robot.limits.T
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    Q = np.vstack([np.zeros(robot.dof), spread(6, lo, np.maximum(hi, lo + 1e-9))])
    A, B = robot.fk(Q), other.fk(Q)
    return (float(np.abs(A[:, :3, 3] - B[:, :3, 3]).max()),
            float(np.abs(A[:, :3, :3] - B[:, :3, :3]).max()),
            float(np.linalg.norm(A[:, :3, 3], axis=1).max()))


def _check_same_fk(robot: Robot, out: Robot) -> None:
    """Refuse a conversion whose FK is not the robot's, to SAME_FK (:func:`fk_difference`).

    Standard and modified DH put a frame on the common normal of consecutive axes; for axes a
    hair from parallel it lies far away (1e-6 rad apart, 0.5 m off: 500 km), and the offsets
    that cancel there lose the robot's own lengths to rounding (mm, for a rounded pi)."""
    moved, turned, _ = fk_difference(robot, out)
    L = robot.characteristic_length
    moved /= L
    if moved <= SAME_FK and turned <= SAME_FK:
        return
    from ..units import LENGTH_UNITS
    u = LENGTH_UNITS[robot.length_unit]          # m per unit
    near = _nearly_parallel(robot)
    why = "" if near is None else (
        f" (the axes of joints {near[0] + 1} and {near[0] + 2} are {near[1]:.2g} rad from "
        "parallel, so their common normal lies far away)")
    raise InputError(f"{robot.name} cannot be written in {out.convention} to full accuracy: "
                     f"its tool would move by up to {moved * L / u:.3g} {robot.length_unit} "
                     f"and turn by {turned:.2g} rad{why}; keep it in {robot.convention}")


def _nearly_parallel(robot: Robot):
    """``(i, angle)``: the consecutive joint axes i, i + 1 (0-based) nearest to parallel without
    being parallel (to 1e-12 rad), when that angle is under 1e-3 rad; None otherwise."""
    axes = np.asarray([j.axis for j in to_poe(robot).joints], float)
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    s = np.linalg.norm(np.cross(axes[:-1], axes[1:]), axis=1)
    near = [(float(x), i) for i, x in enumerate(s) if 1e-12 < x < 1e-3]
    return (min(near)[1], min(near)[0]) if near else None


def _xa(alpha, a):
    return transform(rot_x(alpha), [a, 0.0, 0.0])


def dh_to_mdh(robot: Robot) -> Robot:
    """The standard-DH ``robot`` as a modified-DH robot with identical FK.

    Modified row i takes ``alpha``/``a`` (and their expressions) of standard row i - 1
    (zero for row 1); ``Tx(a_n) Rx(alpha_n)`` of the last standard row moves into the tool.

    Parameters
    ----------
    robot : Robot
        A ``dh`` robot, SI (m, rad).

    Returns
    -------
    Robot
        The ``mdh`` robot, with ``tool = Tx(a_n) Rx(alpha_n) @ robot.tool``
        (``T_flange_tool``: its flange is standard frame n without ``Tx(a_n) Rx(alpha_n)``)
        and the same base, joint variables, limits and home.

    Raises
    ------
    ValueError
        ``robot`` is not a ``dh`` robot.
    """
    if robot.convention != "dh":
        raise ValueError("dh_to_mdh needs a dh robot")
    joints, prev = [], (0.0, 0.0)
    for j in robot.joints:
        joints.append(dataclasses.replace(j, alpha=prev[0], a=prev[1]))
        prev = (j.alpha, j.a)
    tool = _xa(*prev) @ robot.tool
    exprs = _expressions(robot)
    moved = [_fields(e, ("d", "theta")) + _fields(exprs[k - 1], ("alpha", "a")) if k else
             _fields(e, ("d", "theta")) for k, e in enumerate(exprs)]
    return dataclasses.replace(robot, convention="mdh", joints=tuple(joints), tool=tool,
                               expressions=_ordered(moved))


def mdh_to_dh(robot: Robot) -> Robot:
    """The modified-DH ``robot`` as a standard-DH robot with identical FK.

    Standard row i takes ``alpha``/``a`` (and their expressions) of modified row i + 1
    (zero for the last row); ``Rx(alpha_0) Tx(a_0)`` of the first modified row moves into
    the base (its expressions are dropped).

    Parameters
    ----------
    robot : Robot
        An ``mdh`` robot, SI (m, rad).

    Returns
    -------
    Robot
        The ``dh`` robot, with ``base = robot.base @ Rx(alpha_0) Tx(a_0)`` (``T_world_0``)
        and the same tool, joint variables, limits and home.

    Raises
    ------
    ValueError
        ``robot`` is not an ``mdh`` robot.
    """
    if robot.convention != "mdh":
        raise ValueError("mdh_to_dh needs an mdh robot")
    js = robot.joints
    base = robot.base @ _xa(js[0].alpha, js[0].a)
    joints = []
    for k, j in enumerate(js):
        nxt = (js[k + 1].alpha, js[k + 1].a) if k + 1 < len(js) else (0.0, 0.0)
        joints.append(dataclasses.replace(j, alpha=nxt[0], a=nxt[1]))
    exprs = _expressions(robot)
    moved = [_fields(e, ("d", "theta")) + (_fields(exprs[k + 1], ("alpha", "a"))
                                           if k + 1 < len(exprs) else ())
             for k, e in enumerate(exprs)]
    return dataclasses.replace(robot, convention="dh", joints=tuple(joints), base=base,
                               expressions=_ordered(moved))


def _expressions(robot: Robot) -> list[tuple]:
    """``robot.expressions`` with one (possibly empty) entry per joint."""
    exprs = list(robot.expressions)
    return exprs + [()] * (robot.dof - len(exprs))


def _fields(entry: tuple, keys: tuple) -> tuple:
    return tuple((k, src) for k, src in entry if k in keys)


def _ordered(entries) -> tuple:
    """Each joint's (field, source) pairs in the file's field order."""
    order = {"alpha": 0, "a": 1, "d": 2, "theta": 3}
    return tuple(tuple(sorted(e, key=lambda kv: order[kv[0]])) for e in entries)


def to_poe(robot: Robot) -> Robot:
    """Any ``robot`` as a product-of-exponentials robot with identical FK.

    Parameters
    ----------
    robot : Robot
        Any convention, SI (m, rad).

    Returns
    -------
    Robot
        The ``poe`` robot: each joint's unit ``axis`` and ``point`` (m) are those of its
        chain frame at q = 0, in frame 0; ``M = T_0_tool(q = 0)`` (the old tool folded
        in), ``tool`` the identity, the same base, limits and home; expressions dropped.
    """
    from ..fk import chain_frames
    q0 = np.zeros(robot.dof)
    inv_base = invert_transform(robot.base)
    frames = inv_base @ chain_frames(robot.chain, q0)   # joint frames in frame 0
    joints = tuple(
        Joint(name=j.name, type=j.type, axis=tuple(frames[i, :3, 2]),
              point=tuple(frames[i, :3, 3]), limits=j.limits)
        for i, j in enumerate(robot.joints))
    M = inv_base @ robot.fk(q0)
    return dataclasses.replace(robot, convention="poe", joints=joints, tool=np.eye(4), M=M,
                               expressions=())
