"""Random exercise sheets for teachers (``kincalc quiz``).

:func:`make_sheet` draws, from a seed, one exercise per requested kind for a
robot and returns the homework sheet (the format ``kincalc check`` grades,
version 1) as a plain dict; with ``answers=True`` every item carries the
correct answer. :func:`sheet_yaml` writes that dict as YAML text, the same
bytes for the same dict.

The exercises, and where their answers come from (all computed from the
values *as written on the sheet*, so a student who types them gets the key):

==========  ================================================================
kind        question and answer
==========  ================================================================
dh          the robot's DH table, compact ``table`` form (not for poe robots)
link        ``T_{i-1}^i`` of one joint at a random value (``link_transforms``)
fk          ``T_world_tool`` at random joints (``Robot.fk``)
ik          every IK solution within the limits for a reachable pose, written
            as xyz + rpy rounded to a few decimals (:func:`kincalc.ik.solve`)
jacobian    the geometric Jacobian, base frame, rows vx vy vz wx wy wz
reach       yes/no for a reachable pose or one just beyond the reach
            (:func:`kincalc.analysis.reach.reach`)
singular    yes/no for a singular or a clearly regular configuration (the rank
            test of :func:`kincalc.analysis.jacobian_report`)
==========  ================================================================

Units on the sheet: angles in the sheet's angle unit (``deg`` or ``rad``),
lengths in the robot file's length unit; Jacobian linear rows per radian (per
length unit for prismatic columns), as ``kincalc jacobian`` prints them.
Random joints are whole degrees (0.01 rad on a rad sheet) and prismatic
values have three decimals, within the joint limits (revolute ones also
within a half turn of zero). Answers carry ten significant digits.

Each kind draws from its own generator, seeded by ``(seed, kind, k)`` for the
k-th item of that kind, so leaving a kind out does not change the others.
"""

from __future__ import annotations

import functools
import math
import re

import numpy as np

from ..errors import InputError, KincalcError

#: every kind of exercise, in the order of the sheet format's specification
KINDS = ("dh", "link", "fk", "ik", "jacobian", "reach", "singular")
#: the kinds of a sheet when none are asked for
DEFAULT_KINDS = ("dh", "link", "fk", "ik", "jacobian", "singular", "reach")
#: significant digits of answers (round-trip far below any grading tolerance)
SIGNIFICANT = 10
#: random draws tried for one exercise before giving up
ATTEMPTS = 60
#: a regular configuration of a ``singular`` item has its smallest scaled singular
#: value above this (far from the rank threshold, so rounding cannot flip it)
REGULAR_MARGIN = 1e-2
#: a singular one has it below SINGULAR_TOL times this
SINGULAR_MARGIN = 1e-2
#: IK solutions of an ``ik`` item stay this far (rad / robot lengths) from every
#: joint limit and from each other, so the key does not hang on the last digit
IK_CLEARANCE = 1e-6
IK_SEPARATION = math.radians(1.0)


class QuizError(KincalcError):
    """No exercise of a kind could be drawn for this robot (exit 2)."""


def skipped(robot, kinds) -> list[tuple[str, str]]:
    """The requested ``kinds`` that do not apply to ``robot``: ``[(kind, why), ...]``.

    ``dh`` needs a DH (or modified DH) robot; ``ik`` needs a closed-form IK
    family (a numerical solver finds one solution, so "every solution" could
    not be graded).
    """
    out = []
    for kind in dict.fromkeys(kinds):
        if kind == "dh" and robot.convention == "poe":
            out.append(("dh", f"{robot.name} is defined by a product of exponentials, so it "
                              "has no DH table of its own"))
        if kind == "ik":
            from ..ik.families import plan
            _, family, why = plan(robot)
            if family is None:
                out.append(("ik", f"kincalc has no closed-form IK for {robot.name} ({why}), so "
                                  "'every solution' cannot be asked"))
    return out


def make_sheet(robot, seed: int, kinds=DEFAULT_KINDS, *, answers: bool = False,
               angle_unit: str | None = None, robot_ref: str | None = None) -> dict:
    """A random exercise sheet for ``robot`` as a dict (sheet format version 1).

    Parameters
    ----------
    robot : Robot
    seed : int
        Non-negative; the same seed (and arguments) gives the same sheet.
    kinds : sequence of str
        One item per entry, in this order, ids ``"1"``, ``"2"``, ...; a kind may
        repeat. Kinds that :func:`skipped` rules out are left out.
    answers : bool
        Fill in every ``answer`` (the key); otherwise items have none.
    angle_unit : {'deg', 'rad'} or None
        Angle unit of the sheet; default the robot file's (deg for a unitless one).
    robot_ref : str or None
        What the sheet's ``robot:`` says (a bundled name or a path relative to
        the sheet); default ``robot.name``.

    Raises
    ------
    InputError
        For an unknown kind, a negative seed, or when no requested kind applies.
    QuizError
        When no exercise of a kind could be drawn in :data:`ATTEMPTS` tries.
    """
    from ..analysis.results import Units
    unknown = [k for k in kinds if k not in KINDS]
    if unknown:
        raise InputError(f"unknown exercise kind {unknown[0]!r} (choose from "
                         f"{', '.join(KINDS)})")
    if int(seed) < 0:
        raise InputError(f"the seed must be a non-negative integer, not {seed}")
    angle_unit = angle_unit or (robot.angle_unit if robot.angle_unit in ("deg", "rad")
                                else "deg")
    units = Units(angle=angle_unit, length=robot.length_unit)
    left_out = {k for k, _ in skipped(robot, kinds)}
    todo = [k for k in kinds if k not in left_out]
    if not todo:
        raise InputError(f"none of the exercises asked for ({', '.join(kinds)}) applies to "
                         f"{robot.name}")
    makers = {"dh": _item_dh, "link": _item_link, "fk": _item_fk, "ik": _item_ik,
              "jacobian": _item_jacobian, "reach": _item_reach, "singular": _item_singular}
    items, seen = [], {}
    for number, kind in enumerate(todo, start=1):
        k = seen[kind] = seen.get(kind, -1) + 1
        rng = np.random.default_rng([int(seed), KINDS.index(kind), k])
        item = {"id": str(number), "kind": kind}
        item.update(makers[kind](robot, rng, units))
        if not answers:
            item.pop("answer")
        items.append(item)
    title = robot.title or robot.name
    return {
        "kincalc-sheet": 1,
        "title": f"Exercises on {title} (seed {int(seed)})",
        "robot": robot_ref or robot.name,
        "units": units.to_dict(),
        "seed": int(seed),
        "items": items,
    }


# --- numbers a student can type, answers that round-trip ------------------------------

def _num(x) -> float:
    """``x`` to :data:`SIGNIFICANT` digits, without a negative zero."""
    return float(f"{float(x):.{SIGNIFICANT}g}") + 0.0


def _array(M) -> list:
    """Nested lists of :func:`_num`; entries below 1e-12 of the largest are 0."""
    M = np.asarray(M, float)
    tiny = 1e-12 * max(1.0, float(np.max(np.abs(M))) if M.size else 1.0)
    M = np.where(np.abs(M) < tiny, 0.0, M)
    return [_array(r) for r in M] if M.ndim > 1 else [_num(x) for x in M]


def _nice(x: float):
    """A whole number as an int (``90`` rather than ``90.0``), for tables."""
    return int(x) if float(x).is_integer() and abs(x) < 1e15 else x


def _grid(units, revolute: bool) -> tuple[float, int]:
    """(step, decimals) of typed joint values: 1 deg, 0.01 rad, 0.001 length unit."""
    if revolute:
        return (1.0, 0) if units.angle == "deg" else (0.01, 2)
    return 0.001, 3


def _joint_range(robot, i: int, units) -> tuple[float, float]:
    """Range ``(lo, hi)`` of joint ``i`` in sheet units for random values: its limits,
    a revolute joint also within a half turn of zero, an unlimited prismatic one within
    the robot's size of zero."""
    lo, hi = robot.limits[i]
    if robot.joints[i].revolute:
        half = math.pi
        return max(lo, -half) * units.a, min(hi, half) * units.a
    L = robot.characteristic_length
    lo = lo if np.isfinite(lo) else min(-L, hi - 2 * L)
    hi = hi if np.isfinite(hi) else max(L, lo + 2 * L)
    return lo * units.l, hi * units.l


def _typed(value: float, decimals: int):
    return int(round(value)) if decimals == 0 else round(float(value), decimals) + 0.0


def _si(robot, shown, units) -> np.ndarray:
    """Joint values as written (sheet units) -> rad / m."""
    return np.asarray(shown, float) / np.where(robot.is_revolute, units.a, units.l)


def random_joints(robot, rng, units) -> tuple[list, np.ndarray]:
    """Random joints on the typing grid (see :func:`_grid`) within :func:`_joint_range`.

    Returns ``(written values (n,) in sheet units, the same in rad / m)``.
    """
    shown = []
    for i, j in enumerate(robot.joints):
        step, dec = _grid(units, j.revolute)
        lo, hi = _joint_range(robot, i, units)
        k_lo, k_hi = math.ceil(lo / step - 1e-9), math.floor(hi / step + 1e-9)
        if k_hi < k_lo:        # a range narrower than one step: its middle
            shown.append(_num((lo + hi) / 2))
            continue
        shown.append(_typed(int(rng.integers(k_lo, k_hi + 1)) * step, dec))
    return shown, _si(robot, shown, units)


def _pose_matrix(T, units) -> list:
    """A 4x4 pose as rows, translation in the sheet's length unit."""
    T = np.array(T, float)
    T[..., :3, 3] *= units.l
    return _array(T)


def _joint_text(robot, shown, units) -> str:
    return ", ".join(f"{j.name} = {v}" for j, v in zip(robot.joints, shown)) + \
        _unit_note(robot, units)


def _unit_note(robot, units) -> str:
    length = _length_word(units)
    if robot.is_revolute.all():
        return f" ({units.angle})"
    return f" ({units.angle}{'' if not length else ', ' + length})"


def _length_word(units) -> str:
    return "" if units.length == "unitless" else units.length


def _lengths_in(units) -> str:
    return "lengths unitless" if units.length == "unitless" else f"lengths in {units.length}"


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
    off = _num(offset)
    if off == 0:
        return var
    return f"{var} {'+' if off > 0 else '-'} {abs(off):.{SIGNIFICANT}g}"


def _item_dh(robot, rng, units) -> dict:
    """The robot's own DH table in the compact form, angles and lengths in sheet units."""
    dh = robot.convention == "dh"
    cols = ["theta", "d", "a", "alpha"] if dh else ["alpha", "a", "d", "theta"]
    names = variable_names(robot)
    rows = []
    for j, var in zip(robot.joints, names):
        cells = {"theta": j.theta * units.a, "d": j.d * units.l, "a": j.a * units.l,
                 "alpha": j.alpha * units.a}
        row = {k: _nice(_array([v])[0]) for k, v in cells.items()}
        field = "theta" if j.revolute else "d"
        row[field] = _variable_cell(var, cells[field])
        rows.append([row[c] for c in cols])
    item = {"question": (
        f"Write the {'standard' if dh else 'modified (Craig)'} DH table of {robot.name}: one "
        f"row per joint with the columns {', '.join(cols)}"
        f"{'' if dh else ' (alpha and a of the previous link)'}, the joint variable "
        f"({', '.join(names)}) in its cell, e.g. '{names[0]} + 90'; angles in {units.angle}, "
        f"{_lengths_in(units)}. Answer: {{convention: {robot.convention}, table: [[...], ...]}}.")}
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


def _item_link(robot, rng, units) -> dict:
    """``T_{i-1}^i`` of a random joint at a random value; only ``q_i`` is written."""
    i = int(rng.integers(robot.dof))
    shown, q = random_joints(robot, rng, units)
    j = robot.joints[i]
    frames = {"dh": "standard DH", "mdh": "modified DH (Craig)",
              "poe": "joint-axis (z along each joint axis)"}[robot.convention]
    unit = units.angle if j.revolute else (_length_word(units) or "unitless")
    return {
        "question": (f"Compute the link transform T_{i}^{i + 1} of {robot.name} (the "
                     f"{frames} link frames of joint {i + 1}) at {j.name} = {shown[i]} {unit}. "
                     "Answer: the 4x4 matrix as a list of 4 rows; "
                     f"{_lengths_in(units)}."),
        "link": i + 1,
        "q": shown[i],
        "answer": _pose_matrix(robot.link_transforms(q)[i], units),
    }


def _item_fk(robot, rng, units) -> dict:
    """``T_world_tool`` (base and tool included) at random joints."""
    shown, q = random_joints(robot, rng, units)
    return {
        "question": (f"Compute the tool pose T (world <- tool, base and tool transforms "
                     f"included) of {robot.name} at {_joint_text(robot, shown, units)}. "
                     f"Answer: the 4x4 matrix as a list of 4 rows; {_lengths_in(units)}."),
        "q": shown,
        "answer": _pose_matrix(robot.fk(q), units),
    }


def _item_jacobian(robot, rng, units) -> dict:
    """The geometric Jacobian in the base frame at random joints, display units."""
    shown, q = random_joints(robot, rng, units)
    J = np.array(robot.jacobian(q, frame="base"))
    J[:3, :] *= np.where(robot.is_revolute, units.l, 1.0)
    length = _length_word(units) or "length units"
    per = f"{length}/rad" + ("" if robot.is_revolute.all() else
                             f", {length}/{length} for prismatic joints")
    return {
        "question": (f"Compute the geometric Jacobian of {robot.name} in the base (world) frame "
                     f"at {_joint_text(robot, shown, units)}. Answer: 6 rows vx vy vz "
                     f"({per}) and wx wy wz (rad/rad), one column per joint."),
        "q": shown,
        "frame": "base",
        "answer": _array(J),
    }


def scaled_sigma(robot, q) -> np.ndarray:
    """Smallest scale-free singular value ``(...,)`` deciding singularity at ``q (..., n)``.

    The Jacobian's linear rows are divided by the robot's characteristic length
    (prismatic columns multiplied by it), as in
    :func:`kincalc.analysis.jacobian_report`; the result is the smaller of
    ``sigma_r / max(sigma_1, 1)`` for the whole Jacobian and for its linear rows,
    ``r`` their generic ranks. A configuration is singular when it is below
    :data:`kincalc.tolerances.SINGULAR_TOL`.
    """
    J = np.array(robot.jacobian(q))
    L = robot.characteristic_length
    J[..., :3, :] /= L
    J[..., :, ~robot.is_revolute] *= L
    full, full_pos = robot.generic_ranks
    s = np.linalg.svd(J, compute_uv=False)
    sv = np.linalg.svd(J[..., :3, :], compute_uv=False)
    return np.minimum(s[..., full - 1] / np.maximum(s[..., 0], 1.0),
                      sv[..., full_pos - 1] / np.maximum(sv[..., 0], 1.0))


def _zoom(f, a: float, b: float, rounds: int = 9, points: int = 41) -> float:
    """The minimiser of ``f`` (vectorised over an array of abscissae) on ``[a, b]``:
    ``points`` samples, then the same between the best one's neighbours, ``rounds``
    times (the bracket shrinks twentyfold a round)."""
    for _ in range(rounds):
        x = np.linspace(a, b, points)
        k = int(np.argmin(f(x)))
        a, b = x[max(k - 1, 0)], x[min(k + 1, points - 1)]
    return (a + b) / 2


def singular_configuration(robot, shown, rng, units):
    """A singular configuration near the written joints ``shown``, or None.

    One joint at a time (in random order) is swept over its range; at the
    deepest minima of :func:`scaled_sigma` a zooming grid search finds where
    the Jacobian loses rank (a wrist that aligns, an arm that stretches), and
    the joint is written with the fewest decimals that keep the configuration
    singular (a whole degree when the singularity sits on one). When no single
    joint gets there, :func:`_newton_singular` moves them all. Returns
    ``(written values, q in rad / m)``.
    """
    from ..tolerances import SINGULAR_TOL
    base = _si(robot, shown, units)
    for i in rng.permutation(robot.dof):
        i = int(i)
        lo, hi = _joint_range(robot, i, units)
        scale = units.a if robot.joints[i].revolute else units.l
        grid = np.linspace(lo, hi, 721) / scale
        f = _sigma_along(robot, base, i, grid)
        minima = [k for k in range(len(grid)) if f[k] <= f[max(k - 1, 0)]
                  and f[k] <= f[min(k + 1, len(grid) - 1)]]
        sweep = functools.partial(_sigma_along, robot, base, i)
        for k in sorted(minima, key=lambda k: f[k])[:3]:
            x = _zoom(sweep, grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)])
            if float(sweep(np.array([x]))[0]) > SINGULAR_TOL * 1e-3:
                continue
            first = _grid(units, robot.joints[i].revolute)[1]
            for dec in range(first, first + 12):
                v = _typed(x * scale, dec)
                if not lo - 1e-9 <= v <= hi + 1e-9:
                    continue
                written = list(shown)
                written[i] = v
                q = _si(robot, written, units)
                if float(scaled_sigma(robot, q)) < SINGULAR_TOL * SINGULAR_MARGIN:
                    return written, q
    # no joint alone reaches a singularity (redundant arms: their singular set has
    # codimension 2): Newton's method on sigma(q) = 0 moves every joint
    x = _newton_singular(robot, base)
    if x is None:
        return None
    from ..spatial import wrap
    x = np.where(robot.is_revolute, wrap(x), x)
    lo, hi = np.array([_joint_range(robot, i, units) for i in range(robot.dof)]).T
    scale = np.where(robot.is_revolute, units.a, units.l)
    first = _grid(units, True)[1]
    for dec in range(first, first + 12):
        written = [_typed(v, dec) for v in x * scale]
        if np.all((lo - 1e-9 <= written) & (written <= hi + 1e-9)):
            q = _si(robot, written, units)
            if float(scaled_sigma(robot, q)) < SINGULAR_TOL * SINGULAR_MARGIN:
                return written, q
    return None


def _sigma_along(robot, base, i: int, x) -> np.ndarray:
    """:func:`scaled_sigma` at ``base (n,)`` with joint ``i`` set to each of ``x (k,)``."""
    Q = np.repeat(np.asarray(base, float)[None], len(x), axis=0)
    Q[:, i] = x
    return scaled_sigma(robot, Q)


def _newton_singular(robot, q, iterations: int = 60):
    """Joints near ``q (n,)`` (rad / m) where :func:`scaled_sigma` vanishes, or None.

    Newton's method for the scalar equation sigma(q) = 0 with the minimum-norm step
    ``-sigma g / |g|^2``, ``g`` the gradient by central differences over a step
    below sigma (sigma is cone-shaped near a singularity, so its gradient is only
    meaningful farther from the tip than the step). Converges from about one start
    in four on a redundant arm; None when it stalls.
    """
    n = robot.dof
    unit = np.where(robot.is_revolute, 1.0, robot.characteristic_length)
    q = np.array(q, float)
    for _ in range(iterations):
        sigma = float(scaled_sigma(robot, q))
        if sigma < 1e-13:
            return q
        h = min(1e-6, 0.01 * sigma) * unit
        f = scaled_sigma(robot, np.concatenate([q + np.diag(h), q - np.diag(h)]))
        g = (f[:n] - f[n:]) / (2 * h)
        if not np.all(np.isfinite(g)) or g @ g < 1e-24:
            return None
        q = q - sigma * g / (g @ g)
    return None


def _item_singular(robot, rng, units) -> dict:
    """Singular (half of the time, when one is found) or clearly regular joints; the
    answer is ``jacobian_report``'s verdict at the written values."""
    from ..analysis.reports import jacobian_report
    from ..tolerances import SINGULAR_TOL
    want = bool(rng.integers(2))
    for _ in range(2):
        for _ in range(ATTEMPTS // 3 if want else ATTEMPTS):
            shown, q = random_joints(robot, rng, units)
            if want:
                found = singular_configuration(robot, shown, rng, units)
                if found is None:
                    continue
                shown, q = found
            sigma = float(scaled_sigma(robot, q))
            singular = jacobian_report(robot, q).singular
            if (want and singular and sigma < SINGULAR_TOL * SINGULAR_MARGIN) or \
                    (not want and not singular and sigma > REGULAR_MARGIN):
                return {
                    "question": (f"Is {robot.name} at a singular configuration (its Jacobian "
                                 f"below full rank) at {_joint_text(robot, shown, units)}? "
                                 "Answer: yes or no."),
                    "q": shown,
                    "answer": bool(singular),
                }
        want = not want   # no singularity to be found (or no regular place): the other
    raise QuizError(f"could not draw a 'singular' exercise for {robot.name}")


# --- poses -------------------------------------------------------------------------------

def _uses_orientation(robot) -> bool:
    from ..ik.families import plan
    family = plan(robot)[1]
    if family is None:
        return robot.generic_ranks[0] >= 6
    return family.needs_orientation


def _written_pose(xyz, rpy, units):
    """``(pose mapping, T (4, 4) in SI)`` for written ``xyz`` and ``rpy`` (or None)."""
    from ..spatial import matrix_from_rpy
    T = np.eye(4)
    T[:3, 3] = np.asarray(xyz, float) / units.l
    pose = {"xyz": list(xyz)}
    if rpy is not None:
        T[:3, :3] = matrix_from_rpy(np.asarray(rpy, float) / units.a)
        pose["rpy"] = list(rpy)
    return pose, T


def pose_forms(robot, T, units):
    """Ways to write the pose ``T`` (SI), from the most rounded to the exact.

    Yields ``(pose mapping, T as written (SI), Target)``: xyz and rpy rounded (a
    few decimals: 1e-4 of the robot's size, 0.01 deg / 1e-4 rad), then xyz rounded
    with the exact rpy, then both exact (for arms with fewer than six joints, whose
    orientation a rounded rpy would take out of reach). Robots that do not control
    the orientation get the position only.
    """
    from ..ik import Target
    from ..spatial import rpy_from_matrix
    orient = _uses_orientation(robot)
    L = robot.characteristic_length * units.l
    dec = min(6, max(0, 4 - round(math.log10(L)))) if L > 0 else 4
    adec = 2 if units.angle == "deg" else 4
    xyz = T[:3, 3] * units.l
    rpy = rpy_from_matrix(T[:3, :3]) * units.a
    exact_xyz = [_exact(x) for x in xyz]
    exact_rpy = [_exact(a) for a in rpy]
    rounded_xyz = [round(float(x), dec) + 0.0 for x in xyz]
    rounded_rpy = [round(float(a), adec) + 0.0 for a in rpy]
    if orient:
        forms = [(rounded_xyz, rounded_rpy), (rounded_xyz, exact_rpy), (exact_xyz, exact_rpy)]
    else:
        forms = [(rounded_xyz, None), (exact_xyz, None)]
    for x, r in forms:
        pose, Tw = _written_pose(x, r, units)
        yield pose, Tw, Target(Tw, orientation=r is not None)


def _exact(x) -> float:
    return float(x) + 0.0


def _pose_text(robot, pose, units) -> str:
    length = _length_word(units)
    text = f"position xyz = ({', '.join(map(str, pose['xyz']))}){' ' + length if length else ''}"
    if "rpy" in pose:
        text += (f", orientation rpy = ({', '.join(map(str, pose['rpy']))}) {units.angle} "
                 "(fixed X-Y-Z angles: R = Rz(Y) Ry(P) Rx(R))")
    return text


def _ik_ok(robot, result) -> bool:
    """Is this IK result a fair exercise: solutions within the limits, none singular,
    none within :data:`IK_CLEARANCE` of a limit, the ones within limits apart?"""
    inside = [s for s in result.solutions if s.within_limits]
    if not inside or any(s.singular for s in result.solutions):
        return False
    lo, hi = robot.limits.T
    scale = np.where(robot.is_revolute, 1.0, robot.characteristic_length)
    for s in result.solutions:
        gap = np.minimum(np.abs(s.q - lo), np.abs(s.q - hi)) / scale
        if np.any(gap < IK_CLEARANCE):
            return False
    from ..spatial import wrap
    for a in range(len(inside)):
        for b in range(a):
            d = inside[a].q - inside[b].q
            d = np.where(robot.is_revolute, wrap(d), d / robot.characteristic_length)
            if np.max(np.abs(d)) < IK_SEPARATION:
                return False
    return True


def _item_ik(robot, rng, units) -> dict:
    """A reachable pose (FK of random joints, written rounded); the answer is every IK
    solution within the limits of the pose as written."""
    from ..ik import solve
    for _ in range(ATTEMPTS):
        _, q = random_joints(robot, rng, units)
        for pose, _, target in pose_forms(robot, robot.fk(q), units):
            result = solve(robot, target, units=units)
            if not _ik_ok(robot, result):
                continue
            sols = [units.joints(robot, s.q) for s in result.solutions if s.within_limits]
            return {
                "question": (f"Find every joint solution of {robot.name} within its joint "
                             f"limits that reaches the pose: {_pose_text(robot, pose, units)}. "
                             f"Answer: a list of joint vectors{_unit_note(robot, units)}, "
                             "[] if there is none."),
                "pose": pose,
                "answer": [_array(s) for s in sols],
            }
    raise QuizError(f"could not draw an 'ik' exercise for {robot.name} in {ATTEMPTS} tries "
                    "(leave it out with --items)")


def _beyond(robot, p, rng, samples) -> np.ndarray | None:
    """A position on the ray from the base through ``p`` (m), 2-10 % beyond the
    farthest sampled tool position along that ray's direction."""
    o = robot.base[:3, 3]
    r = np.linalg.norm(p - o)
    if r < 1e-9 * robot.characteristic_length:
        return None
    u = (p - o) / r
    reach_along = float(np.max((samples - o) @ u))
    return o + u * max(reach_along, r) * (1.02 + 0.08 * float(rng.random()))


def _item_reach(robot, rng, units) -> dict:
    """Half of the time a reachable pose, otherwise one just beyond the reach along
    the ray from the base; the answer is :func:`kincalc.analysis.reach.reach`'s verdict."""
    from ..analysis.reach import reach
    want = bool(rng.integers(2))
    samples = None
    L = robot.characteristic_length
    for attempt in range(2 * ATTEMPTS):
        if attempt == ATTEMPTS:
            want = not want      # e.g. an unlimited prismatic joint: no "no" to give
        _, q = random_joints(robot, rng, units)
        T = np.array(robot.fk(q))
        if not want:
            if samples is None:
                lo, hi = np.array([_joint_range(robot, i, units) for i in range(robot.dof)]).T
                scale = np.where(robot.is_revolute, units.a, units.l)
                Q = rng.uniform(lo / scale, hi / scale, (4096, robot.dof))
                samples = robot.fk(Q)[:, :3, 3]
            p = _beyond(robot, T[:3, 3], rng, samples)
            if p is None:
                continue
            T[:3, 3] = p
        for pose, _, target in pose_forms(robot, T, units):
            try:
                res = reach(robot, target, units=units)
            except KincalcError:
                break
            fair = (res.verdict == "reachable") if want else \
                (not res.reachable and (res.distance is None or res.distance > 1e-3 * L))
            if fair:
                return {
                    "question": (f"Can {robot.name} reach this pose within its joint limits: "
                                 f"{_pose_text(robot, pose, units)}? Answer: yes or no."),
                    "pose": pose,
                    "answer": bool(res.reachable),
                }
            if not want:
                break    # only the rounded form of a pose beyond reach is of interest
    raise QuizError(f"could not draw a 'reach' exercise for {robot.name} "
                    "(leave it out with --items)")


# --- YAML ------------------------------------------------------------------------------

def _scalar(v) -> str:
    if v is None:
        return "null"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        text = repr(float(v) + 0.0)
        mantissa, _, exponent = text.partition("e")
        if exponent:        # YAML 1.1 floats need a dot and a signed exponent: 1.0e-05
            if "." not in mantissa:
                mantissa += ".0"
            exponent = exponent if exponent[0] in "+-" else "+" + exponent
            text = f"{mantissa}e{exponent}"
        return text
    from ..conventions.writer import yaml_string
    return yaml_string(str(v), plain_ok=True)


def _flat(v) -> bool:
    if isinstance(v, dict):
        return all(not isinstance(x, (dict, list)) for x in v.values())
    if isinstance(v, list):
        return all(not isinstance(x, (dict, list)) for x in v)
    return True


def _flow(v) -> str:
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_scalar(k)}: {_scalar(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(_scalar(x) for x in v) + "]"
    return _scalar(v)


def _block(v, indent: int) -> list[str]:
    pad = " " * indent
    out = []
    if isinstance(v, dict):
        for k, x in v.items():
            if _flat(x):
                out.append(f"{pad}{_scalar(k)}: {_flow(x)}")
            else:
                out.append(f"{pad}{_scalar(k)}:")
                out.extend(_block(x, indent + 2))
        return out
    for x in v:
        if _flat(x):
            out.append(f"{pad}- {_flow(x)}")
        else:
            inner = _block(x, indent + 2)
            out.append(f"{pad}- {inner[0].lstrip()}")
            out.extend(inner[1:])
    return out


def sheet_yaml(sheet: dict, comments=()) -> str:
    """``sheet`` (a :func:`make_sheet` dict) as YAML text, ``comments`` as ``#`` lines
    on top. Lists of numbers are written in flow style (a matrix one row a line),
    floats so that they read back as the same float, yes/no for booleans."""
    lines = [f"# {c}" if c else "#" for c in comments]
    lines += _block(sheet, 0)
    return "\n".join(lines) + "\n"
