"""The sentences of IK and reach answers, from the reasons the core returns as data
(:mod:`kincalc.ik.reasons`, SI), in the user's units (:class:`kincalc.analysis.results.Units`).
The one place where an answer's "why" is worded."""

from __future__ import annotations

from functools import singledispatch

from ..ik.continua import Continuum, Followers, ParallelContinuum
from ..spatial import wrap
from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION
from ..ik.reasons import (Answered, ArmMissed, Blocked, Found, Missed, NoRoot, NoSolution, NumericFound,
                         NumericMissed, OrientationOut, Outside, OutOfReach)


def length_suffix(units) -> str:
    """`` m`` (with its space), or nothing for a unitless robot."""
    return "" if units.length == "unitless" else f" {units.length}"


#: a target this many times beyond the reach suggests numbers meant in a smaller unit
UNIT_SLIP = 20.0


def _unit_slip(r: Outside, units) -> str:
    """A hint for a target far beyond the reach (:data:`UNIT_SLIP` times) that a smaller
    length unit would bring within it: the numbers were likely meant in that unit."""
    from ..units import LENGTH_UNITS
    if units.length == "unitless" or r.reach <= 0 or r.target < UNIT_SLIP * r.reach:
        return ""
    shown = LENGTH_UNITS[units.length]
    smaller = sorted((f, u) for u, f in LENGTH_UNITS.items() if u != "unitless" and f < shown)
    for f, u in reversed(smaller):                 # the least change of unit that fits
        if r.target * f / shown <= r.reach:
            return (f"; were the numbers meant in {u}? Read as {u}, the target is "
                    f"{length(r.target * f / shown, units)} from the base, within the reach")
    return ""


def length(x: float, units, digits: int = 6) -> str:
    return f"{x * units.l:.{digits}g}{length_suffix(units)}"


def angle(x: float | None, units) -> str:
    return f"{(x or 0.0) * units.a:.4g} {units.angle}"


def joint_amount(robot, i: int, amount: float, units) -> str:
    """``amount`` (rad or m) of joint ``i`` in its unit, four significant digits."""
    if robot.joints[i].revolute:
        return f"{amount * units.a:.4g} {units.angle}"
    return f"{amount * units.l:.4g}{length_suffix(units)}"


def count_text(count: int, within: int) -> str:
    return f"{count} solution{'s' if count != 1 else ''}, {within} within the joint limits"


@singledispatch
def reason_text(reason, robot, units) -> str:
    """The sentence for ``reason`` (any reason of :mod:`kincalc.ik.reasons`)."""
    raise TypeError(f"no words for {type(reason).__name__}")


@reason_text.register
def _(r: Found, robot, units) -> str:
    return count_text(r.count, r.within)


@reason_text.register
def _(r: Blocked, robot, units) -> str:
    what = ", ".join(f"{robot.joints[i].name} by {joint_amount(robot, i, amount, units)}"
                     for i, amount in r.worst)
    return f"blocked by joint limits: all {r.count} solutions violate a limit ({what})"


@reason_text.register
def _(r: Missed, robot, units) -> str:
    # (an error within what a solution is allowed is no miss, and is not said as one)
    parts = []
    turned = r.orientation_error is not None and r.orientation_error > ACCEPT_ORIENTATION
    if r.position_error > ACCEPT_POSITION * max(robot.characteristic_length, 1e-12):
        parts.append(f"position off by {r.position_error * units.l:.4g}{length_suffix(units)}")
    elif turned:
        parts.append("position reached")
    if turned:
        parts.append(f"orientation off by {r.orientation_error * units.a:.4g} {units.angle}")
    return "does not reach the target" + (": " + ", ".join(parts) if parts else " to rounding")


@reason_text.register
def _(r: Answered, robot, units) -> str:
    return (f"reaches the target, but is one root with a listed solution "
            f"({robot.joints[r.joint].name} differs by "
            f"{joint_amount(robot, r.joint, r.amount, units)}): answered once")


@reason_text.register
def _(r: ArmMissed, robot, units) -> str:
    names = ", ".join(robot.joints[j].name for j in r.joints)
    return (f"does not reach the target: {names} put the {r.point} "
            f"{r.distance * units.l:.4g}{length_suffix(units)} from where the target needs it")


@reason_text.register
def _(r: NoSolution, robot, units) -> str:
    if r.best is None:
        return "no solution: the arm cannot place its tool at this pose"
    return "no solution: " + reason_text(r.best, robot, units)


@reason_text.register
def _(r: OrientationOut, robot, units) -> str:
    if r.what == "approach vector" and r.closest is not None:
        return (f"the position is reachable but the approach vector is not: the best "
                f"solution's approach is off by {angle(r.closest[1], units)}")
    head = (f"the position is reachable but this {r.what} is not" + (
        f" for a robot that controls {r.controls}" if r.controls else "") + ": ")
    if r.closest is None and not r.rolls:
        return head + f"no configuration reaches the position with this {r.what}"
    if r.rolls:
        rolls = ", ".join(f"{angle(a, units)} ({branch})" for a, branch in r.rolls)
        count = "solution" if len(r.rolls) == 1 else f"{len(r.rolls)} solutions"
        return (head + f"the {count} that reach the position and the approach leave the "
                f"roll about it off by {rolls}")
    branch, error = r.closest
    return head + f"the closest solution ({branch}) is off by {angle(error, units)}"


@reason_text.register
def _(r: Outside, robot, units) -> str:
    d = length(r.distance, units)
    if r.motion is not None:
        return (f"outside the workspace: the tool moves in a {r.motion} and the target is "
                f"{length(r.off, units)} off it; the nearest reachable point is {d} away")
    # (in this direction: the nearest point on the line from the base through the target;
    # elsewhere its own distance from the base, which is no reach in the target's direction)
    reach = (f"the arm reaches {length(r.reach, units)} from it in this direction" if r.radial
             else f"the nearest point the arm reaches is {length(r.reach, units)} from it")
    if r.where == "beyond-outer-reach":
        return (f"beyond the outer reach by {d}: the target is {length(r.target, units)} "
                f"from the base, {reach}" + _unit_slip(r, units))
    if r.where == "inside-inner-void":
        return (f"inside the inner void by {d}: the target is {length(r.target, units)} "
                f"from the base, {reach}")
    return f"outside the workspace: the nearest reachable point is {d} away"


@reason_text.register
def _(r: OutOfReach, robot, units) -> str:
    if r.outside is None:
        return (f"out of reach within the joint limits: the nearest position reachable "
                f"within them is {length(r.distance, units)} away")
    return "out of reach: " + reason_text(r.outside, robot, units)


@reason_text.register
def _(r: NumericFound, robot, units) -> str:
    text = "1 solution found numerically (the one with the least change from the start)"
    if r.restart:
        text += (f"; the start did not converge, restart {r.restart} did: it may not be the "
                 "nearest solution")
    return text


@reason_text.register
def _(r: NumericMissed, robot, units) -> str:
    miss = f"position off by {r.miss.position_error * units.l:.4g}{length_suffix(units)}"
    if r.miss.orientation_error is not None:
        miss += f", orientation off by {r.miss.orientation_error * units.a:.4g} {units.angle}"
    text = (f"no solution found numerically from the start and {r.restarts} restarts; the "
            f"closest configuration found misses the target ({miss})")
    if r.controls is not None:
        text += (f": the robot controls only {r.controls} of the 6 pose components, give the "
                 "position alone")
    return text


@reason_text.register
def _(r: NoRoot, robot, units) -> str:
    name = robot.joints[r.joint].name
    phase = float(r.phase * units.a) + 0.0             # (-0.0 as 0)
    sign = "+" if phase < 0 else "-"
    text = (f"{name}: cos({name} {sign} {abs(phase):.4g} {units.angle}) would have to be "
            f"{r.need:.4g}, outside [-1, 1]: no real angle, {r.what} is out of reach on that "
            "branch")
    if r.reversed_chain:
        text = "on the reversed chain (each joint turned the other way): " + text
    return text


@singledispatch
def continuum_text(c, names, units) -> str:
    """A relation a singular target leaves between joints (:mod:`kincalc.ik.continua`), in
    words and the display angle unit: ``names`` the joints' names by 0-based index, the
    total wrapped to (-180, 180] deg or (-pi, pi] rad, to 4 decimals."""
    raise TypeError(f"no words for {type(c).__name__}")


@continuum_text.register
def _(c: Continuum, names, units) -> str:
    a, b = names[c.i], names[c.j]
    if c.total is None:
        return f"axes of {a} and {b} aligned: they turn the tool about one line"
    return f"{a} {'+' if c.sign > 0 else '-'} {b} = {_total(c.total, units)}"


@continuum_text.register
def _(c: ParallelContinuum, names, units) -> str:
    terms = [("-" if s < 0 else "") + names[j] if k == 0 else ("- " if s < 0 else "+ ") + names[j]
             for k, (j, s) in enumerate(zip(c.joints, c.signs))]
    rest = ", ".join(names[j] for j in c.joints if j != c.free)
    return (f"{' '.join(terms)} = {_total(c.total, units)} (axis of {names[c.free]} parallel "
            f"to theirs: {names[c.free]} free, {rest} follow it)")


@continuum_text.register
def _(c: Followers, names, units) -> str:
    rest = ", ".join(names[j] for j in c.joints)
    return (f"{names[c.free]} free, {rest} {'follows' if len(c.joints) == 1 else 'follow'} it "
            "to keep the target")


def _total(total: float, units) -> str:
    """A relation's total (rad) in the display unit, to 4 decimals (a total rounding to zero
    is 0.0000, not -0.0000)."""
    return f"{round(float(wrap(total)) * units.a, 4) + 0.0:.4f} {units.angle}"


def dead_end_texts(dead_ends, robot, units) -> list:
    """The sentences of ``dead_ends``, each once, in order."""
    out = []
    for d in dead_ends:
        text = reason_text(d, robot, units)
        if text not in out:
            out.append(text)
    return out


def singularity_text(robot, solution) -> str | None:
    """What makes an IK solution singular (:class:`~kincalc.ik.solve.IKSolution`): the
    Jacobian's singularity at its joints (:func:`kincalc.analysis.jacobian_report`) and the
    joints the target leaves undetermined; None when it is not singular."""
    parts = []
    if solution.singular:
        from .reports import jacobian_report
        rep = jacobian_report(robot, solution.q)
        if rep.singularity is not None:
            parts.append("; ".join(rep.singularity.descriptions))
    if solution.free:
        parts.append("undetermined at this target: "
                     + ", ".join(robot.joints[i].name for i in solution.free)
                     + " (a representative value is shown)")
    return "; ".join(parts) or None
