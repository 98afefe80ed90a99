"""``ik --explain``: each solution's steps in a textbook chapter's own equations, with
the numbers put in (Bingul & Kucuk ch. 4, Craig ch. 4, Spong ch. 5).

The steps are the ones the engine took and noted (:mod:`kincalc.ik.worked`); this module
only writes them, in the user's units:

* the wrist centre: ``p_w = p - d·a`` (the target's position less the wrist's offset
  along the approach ``a``);
* a joint from an invariant of an earlier joint's motion, ``A cos q + B sin q + C = t``
  (a height along that joint's axis, or the squared distance from a point of it): the
  law of cosines ``cos q = (|p - o|² - (l1² + l2²)) / (2 l1 l2)`` where it is one (no
  sine term), else ``q = atan2(B, A) ± acos((t - C) / sqrt(A² + B²))``;
* a joint turning a point onto its target: ``q = atan2(p2, p1) - atan2(f2, f1)`` in the
  plane normal to its axis (the base's x and y for a vertical axis 1);
* the last joint's roll about its axis: ``q = atan2(u2, u1) - atan2(e2, e1)``, a direction
  across its axis turned where the orientation needs it;
* a sliding joint from such an invariant, ``A d² + B d + C = t`` (the quadratic formula),
  or moving a point onto its target along its axis, ``d = p - f``;
* a spherical wrist: ``R_3^6 = (R_0^3)^T R`` and, where the wrist's axes are those of ZYZ
  angles in frame 3 (the PUMA's), ``q5 = atan2(±sqrt(r13² + r23²), r33)``,
  ``q4 = atan2(±r23, ±r13)``, ``q6 = atan2(±r32, ∓r31)``.

Symbols are the joints' own names and A, B, C, t, p, o, f: none is a DH parameter's
(a, d, alpha, theta).
"""

from __future__ import annotations

import numpy as np

from ..spatial import wrap

#: significant digits of the numbers a step works with (enough that the printed numbers
#: give the printed result, also near acos(+-1)) and of the angles it ends with
DIGITS, RESULT_DIGITS = 9, 6


def worked_steps(robot, solution, T, units, family: str) -> list:
    """The worked steps of one solution.

    Parameters
    ----------
    robot : Robot
    solution : IKSolution, with the ``trace`` the engine noted (``explain``)
    T : ndarray (4, 4), the target ``T_world_tool`` (world frame, SI)
    units : Units, the display units
    family : str, the family's name (``spherical-wrist`` adds the wrist's steps)

    Returns
    -------
    list of dict
        ``{"step": what the line solves, "text": the equation with its numbers}``, in
        the order a textbook takes them.
    """
    trace = list(solution.trace)
    names = [j.name for j in robot.joints]
    centre = [v for label, v, kind in trace if label == "wrist centre (target)"]
    out = [_wrist_centre(np.asarray(centre[0]), T, units)] if centre else []
    for _, value, kind in trace:
        step, *extra = kind.split(":")
        if step in _STEPS:
            j = int(extra[0])
            out.append({"step": names[j], "text": _STEPS[step](
                names[j], [names[int(x)] if x.isdigit() else x for x in extra[1:]],
                np.asarray(value), solution.q[j], units)})
    if family == "spherical-wrist" and robot.dof == 6 and robot.is_revolute[3:].all():
        out += _wrist_steps(robot, solution.q, names, T, units)
    shown = {part.strip() for step in out for part in step["step"].split(",")}
    rest = [j for j, name in enumerate(names) if name not in shown]
    if rest:                    # joints whose steps the closed form does not write out
        how = _UNWORKED.get(family.removeprefix("reversed-"), _UNWORKED[""])
        values = [_result(names[j], solution.q[j], units) if robot.is_revolute[j] else
                  f"{names[j]} = {_n(solution.q[j] * units.l)}{_unit(units)}" for j in rest]
        out.append({"step": ", ".join(names[j] for j in rest),
                    "text": f"{how} (not written out here): {', '.join(values)}"})
    return out


#: how a family finds the joints whose steps it does not note, in words
_UNWORKED = {
    "general-6r": "the elimination of Raghavan and Roth as Manocha and Canny solve it: one "
                  "joint's values are the real eigenvalues of the companion form of a 12x12 "
                  "matrix polynomial, two more come from its null vector and the rest by "
                  "back-substitution, each solution then polished by Newton's method",
    "": "the family's closed form, subproblems on the robot's axes (man kincalc-ik, FAMILIES)",
}


def _n(x, scale=0.0) -> str:
    """A number of a step; rounding noise (below 1e-12 of the step's ``scale``) is 0."""
    x = float(x)
    return "0" if abs(x) <= 1e-12 * scale else f"{x:.{DIGITS}g}"


def _vec(v, scale) -> str:
    return "(" + ", ".join(_n(x * scale) for x in v) + ")"


def _unit(units) -> str:
    return "" if units.length == "unitless" else f" {units.length}"


def _wrist_centre(pw, T, units) -> dict:
    """``p_w = p - d·a``: the wrist centre from the target's position and approach."""
    p, R = T[:3, 3], T[:3, :3]
    c = R.T @ (pw - p)                               # the wrist centre in the tool's frame
    L = max(np.linalg.norm(c), np.linalg.norm(p), 1e-12)
    if np.linalg.norm(c) <= 1e-12 * L:
        text = f"p_w = p = {_vec(p, units.l)}{_unit(units)} (the tool point is the wrist centre)"
    elif np.linalg.norm(c[:2]) <= 1e-9 * L:
        d = -c[2]
        text = (f"p_w = p - d·a = {_vec(p, units.l)} - {_n(d * units.l)}·{_vec(R[:, 2], 1)} "
                f"= {_vec(pw, units.l)}{_unit(units)} (a: the approach, the tool's z axis)")
    else:
        text = (f"p_w = p + R·c = {_vec(pw, units.l)}{_unit(units)} (c = {_vec(c, units.l)}: "
                "the wrist centre in the tool's frame)")
    return {"step": "wrist centre", "text": text}


def _terms(A, B, C, q) -> str:
    """``A cos q + B sin q + C`` with its signs written once."""
    out = f"{_n(A)} cos {q}"
    for x, w in ((B, f" sin {q}"), (C, "")):
        out += f" {'-' if x < 0 else '+'} {_n(abs(x))}{w}"
    return out


def _cosine_step(q, what, pivot, value, q_value, units) -> str:
    """``A cos q + B sin q + C = t`` in the textbook's words."""
    A, B, C, t, l1, l2 = value
    f = {"distance2": units.l ** 2, "direction": 1.0}.get(what, units.l)
    A, B, C, t = A * f, B * f, C * f, t * f
    big = max(abs(A), abs(B), abs(C), abs(t))
    A, B, C, t = (0.0 if abs(x) <= 1e-12 * big else x for x in (A, B, C, t))
    l1, l2 = l1 * units.l, l2 * units.l
    triangle = what == "distance2" and np.isfinite(l1) and \
        abs(abs(A) - 2 * l1 * l2) <= 1e-9 * max(C, 1e-300) and \
        abs(C - l1 * l1 - l2 * l2) <= 1e-9 * max(C, 1e-300)
    got = _result(q, q_value, units)
    lhs = _lhs(what, pivot)
    if abs(B) <= 1e-12 * max(abs(A), 1e-300) and A != 0:
        c = (t - C) / A
        head = f"cos {q} = (t - C) / A = ({_n(t)} - {_n(C)}) / {_n(A)} = {_n(c)} (t: {lhs})"
        if triangle:
            sign = "" if A > 0 else "-"
            head = (f"cos {q} = {sign}(|p - o|² - l1² - l2²) / (2 l1 l2) = {sign}({_n(t)} - "
                    f"{_n(l1 * l1)} - {_n(l2 * l2)}) / (2·{_n(l1)}·{_n(l2)}) = {_n(c)} (the law "
                    f"of cosines: p the point placed, o on the axis of {pivot}, l1 and l2 the "
                    f"triangle's sides)")
        root = _angle(np.arccos(np.clip(c, -1, 1)), units)
        if A > 0:
            return f"{head} -> {q} = ±{root}: {got}"
        # A < 0: atan2(B, A) + acos((t - C) / |A|), the + branch of the labels, is -acos(c)
        return f"{head} -> {q} = ∓{root} (the + branch is -{root}): {got}"
    if A == 0 and B == 0:              # the joint's axis holds the point: it moves nothing
        every = abs(t - C) <= 1e-9 * max(big, 1e-300)
        return (f"{_terms(A, B, C, q)} = t = {_n(t)} (t: {lhs}) -> A = B = 0: {q} leaves t "
                + (f"as it is, and t = C: every {q} solves it ({q} free): {got}" if every
                   else f"as it is, and t is not C: no {q} solves it: {got}"))
    r = np.hypot(A, B)
    c = (t - C) / r
    return (f"{_terms(A, B, C, q)} = t = {_n(t)} (t: {lhs}) -> "
            f"{q} = atan2(B, A) ± acos((t - C) / sqrt(A² + B²)) = {_angle(np.arctan2(B, A), units)}"
            f" ± {_angle(np.arccos(np.clip(c, -1, 1)), units)}: {got}")


def _lhs(what, pivot) -> str:
    """What the invariant ``t`` of a step is, in words."""
    if what == "distance2":
        return f"|p - o|², p the point placed, o on the axis of {pivot}"
    if what == "height":
        return f"the height along the axis of {pivot} of p, the point placed"
    if what == "direction":
        return (f"the component along the axis of {pivot} of the last axis's direction, where "
                "the target's orientation puts it")
    return f"p, the point placed, across the axis of {pivot}"


def _quadratic_step(d, what, pivot, value, d_value, units) -> str:
    """``A d² + B d + C = t`` and its roots, in the user's length unit: the equation times
    ``l^p`` (``l`` the unit's factor, ``p`` the invariant's power of length) has the
    coefficients ``A l^(p-2)``, ``B l^(p-1)``, ``C l^p`` in the slide ``l d``."""
    l, p = units.l, 2 if what == "distance2" else 1
    A, B, C, t = (float(x) for x in value)
    A, B, C, t = A * l ** (p - 2), B * l ** (p - 1), C * l ** p, t * l ** p
    big = max(abs(A), abs(B), abs(C), abs(t))
    A, B, C, t = (0.0 if abs(x) <= 1e-12 * big else x for x in (A, B, C, t))
    got = f"{d} = {_n(d_value * l)}{_unit(units)}"
    # the leading term's coefficient without a 1, later terms only when not 0
    lead = lambda x, w: {"1": "", "-1": "-"}.get(_n(x), _n(x) + " ") + w  # noqa: E731
    more = lambda x, w: (f" {'-' if x < 0 else '+'} {_n(abs(x))}{w}"  # noqa: E731
                         if x != 0.0 else "")
    if A == 0.0 and B == 0.0:          # the slide moves the point along the axis
        every = abs(t - C) <= 1e-9 * max(big, 1e-300)
        return (f"{_n(C)} = t = {_n(t)} (t: {_lhs(what, pivot)}) -> {d} leaves t as it is, "
                + (f"and t = C: every {d} solves it ({d} free): {got}" if every
                   else f"and t is not C: no {d} solves it: {got}"))
    if A == 0.0:
        return (f"{lead(B, d)}{more(C, '')} = t = {_n(t)} (t: {_lhs(what, pivot)}) -> "
                f"{d} = (t - C) / B: {got}")
    root = np.sqrt(max(B * B - 4 * A * (C - t), 0.0))
    head = f"{lead(A, d + '²')}{more(B, ' ' + d)}{more(C, '')}"
    return (f"{head} = t = {_n(t)} (t: {_lhs(what, pivot)}) -> {d} = (-B ± sqrt(B² - "
            f"4 A (C - t))) / (2 A) = {_n((-B - root) / (2 * A))} or "
            f"{_n((-B + root) / (2 * A))}: {got}")


def _turn_step(q, value, q_value, units) -> str:
    """``q = atan2(p2, p1) - atan2(f2, f1)``: a point turned onto its target (m)."""
    return _angle_between(q, "p", "f", [float(x) * units.l for x in value], q_value, units,
                          f"p: where the point placed must go, f: where {q} = 0 leaves it, in "
                          f"the plane normal to the axis of {q}")


def _roll_step(q, value, q_value, units) -> str:
    """``q = atan2(u2, u1) - atan2(e2, e1)``: a direction turned (the last joint's roll)."""
    return _angle_between(q, "u", "e", [float(x) for x in value], q_value, units,
                          f"u: a direction across the axis of {q} where the target's "
                          f"orientation needs it, the joints before {q} undone; e: where "
                          f"{q} = 0 leaves it; both in the plane normal to the axis of {q}")


def _angle_between(q, to, fro, xy, q_value, units, words) -> str:
    """``q = atan2(to2, to1) - atan2(fro2, fro1)`` with the coordinates ``xy = (to1, to2,
    fro1, fro2)`` put in (rounding noise, 1e-12 of the largest, as 0)."""
    big = max(abs(x) for x in xy)
    g1, g2, f1, f2 = (0.0 if abs(x) <= 1e-12 * big else x for x in xy)
    back = np.arctan2(f2, f1)
    return (f"{q} = atan2({to}2, {to}1) - atan2({fro}2, {fro}1) = atan2({_n(g2)}, {_n(g1)}) - "
            f"atan2({_n(f2)}, {_n(f1)}) = {_angle(np.arctan2(g2, g1), units)} "
            f"{'-' if back >= 0 else '+'} {_angle(abs(back), units)}: "
            f"{_result(q, q_value, units)} ({words})")


def _slide_step(d, value, d_value, units) -> str:
    """``d = p - f``: a point slid onto its target along the axis (m)."""
    g, f = (float(x) * units.l for x in value)
    return (f"{d} = p - f = {_n(g)} - {_n(f)} = {_n(g - f)}{_unit(units)} (p: where the point "
            f"placed must go, f: where {d} = 0 leaves it, along the axis of {d})")


def _tcv_step(q, value, q_value, units) -> str:
    """``q = pi ln |w4..w6|``: the last joint of a tool configuration vector."""
    length = float(np.ravel(value)[0])
    return (f"{q} = pi ln|w4..w6| = pi ln({_n(length)}) (w4..w6: the vector's approach part, "
            f"e^({q}/pi) times the tool's z axis): {_result(q, q_value, units)}")


#: the writer of each kind of noted step (:mod:`kincalc.ik.worked`): ``(joint name, the
#: kind's other fields (what, the pivot joint's name), value, the joint's value, units)``
_STEPS = {
    "abc": lambda q, extra, v, x, units: _cosine_step(q, *extra, v, x, units),
    "quad": lambda q, extra, v, x, units: _quadratic_step(q, *extra, v, x, units),
    "turn": lambda q, extra, v, x, units: _turn_step(q, v, x, units),
    "roll": lambda q, extra, v, x, units: _roll_step(q, v, x, units),
    "slide": lambda q, extra, v, x, units: _slide_step(q, v, x, units),
    "tcv": lambda q, extra, v, x, units: _tcv_step(q, v, x, units),
    "sum": lambda q, extra, v, x, units: _sum_step(q, extra, v, x, units),
    "dir": lambda q, extra, v, x, units: _direction_step(q, v, x, units),
}


def _direction_step(q, value, q_value, units) -> str:
    """``q = atan2(b2, b1) - atan2(a2, a1)``: the parallel axes' direction seen from the tool
    turned onto it with the joints before ``q`` undone (a UR-type arm's joint 6); both
    within rounding of ``q``'s axis at the wrist singularity, where ``q`` is free."""
    if max(abs(float(x)) for x in value) <= 1e-9:
        return (f"the parallel axes lie along the axis of {q}: {q} is free (the wrist "
                f"singularity), shown at {_result(q, q_value, units)}")
    return _angle_between(q, "b", "a", [float(x) for x in value], q_value, units,
                          f"a: the direction of the parallel axes with the target's "
                          f"orientation undone, b: that direction with the joints before {q} "
                          f"undone; both in the plane normal to the axis of {q}")


def _sum_step(q, extra, value, q_value, units) -> str:
    """The last joint about parallel axes closing their turn ``psi``: ``q = s (psi - sum
    s_i q_i)`` (``extra``: its sense, then each other joint's name and sense)."""
    psi, *others = (float(x) for x in value)
    names, senses = extra[1::2], extra[2::2]

    def signed(pairs):                      # "a + b - c" from (sign, word) pairs
        text = " ".join(f"{s} {w}" for s, w in pairs)
        return text[2:] if text.startswith("+ ") else "-" + text[2:]
    words = signed(zip(senses, names))
    numbers = signed((("+" if (s == "+") == (x >= 0) else "-"), _angle(abs(x), units))
                     for s, x in zip(senses, others))
    lead, close = ("", "") if extra[0] == "+" else ("-(", ")")
    return (f"{q} = {lead}ψ - ({words}){close} = {lead}{_angle(psi, units)} - ({numbers})"
            f"{close}: {_result(q, q_value, units)} (ψ: the turn about the parallel axes the "
            "orientation asks for, the sum of their joints' turns, each with its sense)")


def _angle(x, units, digits: int = RESULT_DIGITS) -> str:
    """An angle wrapped into (-180, 180] deg (or (-pi, pi] rad), as a formula gives it."""
    sign = "°" if units.angle == "deg" else " rad"
    return f"{float(wrap(x)) * units.a:.{digits}g}{sign}"


def _result(q, value, units) -> str:
    """``q = value``, with the turn the solution keeps within the joint's limits when that
    is not the formula's (-180, 180] (the table's value)."""
    out = f"{q} = {_angle(value, units)}"
    if abs(float(wrap(value)) - float(value)) > 1e-12:
        sign = "°" if units.angle == "deg" else " rad"
        out += f" (= {float(value) * units.a:.{RESULT_DIGITS}g}{sign} within its limits)"
    return out


def _wrist_steps(robot, q, names, T, units) -> list:
    """``R_3^6 = (R_0^3)^T R_0^6`` (R_0^6 from the target without the base and the tool) and
    the ZYZ angles, where the wrist's axes are theirs."""
    A = robot.link_transforms(q)
    R03 = A[0][:3, :3] @ A[1][:3, :3] @ A[2][:3, :3]
    R06 = (np.linalg.inv(robot.base) @ T @ np.linalg.inv(robot.tool))[:3, :3]
    R36 = R03.T @ R06
    out = [{"step": "R_3^6", "text": (
        f"R_3^6 = (R_0^3)^T R_0^6 = {_matrix(R36)} (R_0^3 from "
        f"{', '.join(names[:3])}; R_0^6 the target's rotation without the base and the tool)")}]
    zyz = _zyz_form(robot, R36, q)
    q4, q5, q6 = names[3:6]
    if zyz is None:
        out.append({"step": f"{q4}, {q5}, {q6}", "text": (
            f"R_3^6 = R({q4}) R({q5}) R({q6}) about this wrist's own axes (not those of ZYZ "
            f"angles in frame 3): {q5} from the cone its axis must lie on, {q4} and {q6} by "
            f"turning onto R_3^6's columns: {', '.join(_angle(x, units) for x in q[3:6])}")})
        return out
    r, sigma, what = zyz
    if what != "R_3^6":
        out.append({"step": what, "text": f"{what} = {_matrix(r)} (link 4's fixed rotation, "
                                          "its twist and angle offset, taken off)"})
    b = sigma * q[4]
    s = 1.0 if np.sin(b) >= 0 else -1.0
    pm, mp = ("+", "-") if s > 0 else ("-", "+")
    five = q5 if sigma > 0 else f"-{q5}"
    out.append({"step": q5, "text": (
        f"{five} = atan2({pm}sqrt(r13² + r23²), r33) = atan2({_n(s * np.hypot(r[0, 2], r[1, 2]))}"
        f", {_n(r[2, 2])}) = {_angle(b, units)} ({what} = Rz({q4}) Ry({five}) Rz({q6}): ZYZ "
        f"angles, r its entries)")})
    out.append({"step": q4, "text": f"{q4} = atan2({pm}r23, {pm}r13) = atan2({_n(s * r[1, 2])}, "
                                    f"{_n(s * r[0, 2])}): {_result(q4, q[3], units)}"})
    out.append({"step": q6, "text": f"{q6} = atan2({pm}r32, {mp}r31) = atan2({_n(s * r[2, 1])}, "
                                    f"{_n(-s * r[2, 0])}): {_result(q6, q[5], units)}"})
    return out


def _matrix(R) -> str:
    return "[" + "; ".join(" ".join(_n(x, 1.0) for x in row) for row in R) + "]"


def _zyz_form(robot, R36, q):
    """``(R, sigma, name)`` when ``R = Rz(q4) Ry(sigma q5) Rz(q6)`` for ``R = R_3^6`` or, for
    modified DH, ``R_3^6`` without link 4's fixed rotation in front (``F4`` = Rx(alpha3)
    and its angle offset); None when the wrist's axes are not those of ZYZ angles."""
    from ..spatial import matrix_from_euler_zyz
    first = robot.link_transforms(np.zeros(robot.dof))[3][:3, :3]
    forms = [(R36, "R_3^6")]
    if robot.convention == "mdh":
        forms.append((first.T @ R36, "F4^T R_3^6"))
    for R, what in forms:
        for sigma in (1.0, -1.0):
            if np.abs(matrix_from_euler_zyz([q[3], sigma * q[4], q[5]]) - R).max() < 1e-9:
                return R, sigma, what
    return None
