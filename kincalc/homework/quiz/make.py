"""Drawing a sheet for :mod:`kincalc.homework.quiz`: one exercise per requested kind,
each from its own generator."""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from .items import item_dh, item_fk, item_jacobian, item_link
from .poses import item_ik, item_reach
from .rules import DEFAULT_KINDS, KINDS, QuizError
from .singular import item_singular


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
            from ...ik.families import plan
            _, family, why = plan(robot)
            if family is None:
                out.append(("ik", f"kincalc has no closed-form IK for {robot.name} ({why}), so "
                                  "'every solution' cannot be asked"))
    return out


def make_sheet(robot, seed: int, kinds=DEFAULT_KINDS, *, answers: bool = False,
               angle_unit: str | None = None, robot_ref: str | None = None,
               notes: list | None = None) -> dict:
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
    notes : list or None
        None: a kind no exercise of which can be drawn raises :class:`QuizError`
        (the kinds were asked for). A list (the default kinds): such a kind is
        left out and ``(kind, why)`` appended to it, as :func:`skipped` gives; the
        other items keep their draws (each kind has its own random stream).

    Raises
    ------
    InputError
        For an unknown kind, a negative seed, or when no requested kind applies.
    QuizError
        When no exercise of a kind could be drawn in :data:`ATTEMPTS` tries (and
        ``notes`` is None), or none of any kind.
    """
    from ...analysis.results import Units
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
    makers = {"dh": item_dh, "link": item_link, "fk": item_fk, "ik": item_ik,
              "jacobian": item_jacobian, "reach": item_reach, "singular": item_singular}
    items, seen = [], {}
    for kind in todo:
        k = seen[kind] = seen.get(kind, -1) + 1
        rng = np.random.default_rng([int(seed), KINDS.index(kind), k])
        item = {"id": str(len(items) + 1), "kind": kind}
        try:
            item.update(makers[kind](robot, rng, units))
        except QuizError as err:
            if notes is None:
                raise
            if kind not in [n[0] for n in notes]:
                notes.append((kind, err.why))
            continue
        if not answers:
            item.pop("answer")
        items.append(item)
    if not items:
        raise QuizError(f"no exercise of the kinds asked for ({', '.join(kinds)}) could be "
                        f"drawn for {robot.name}")
    title = robot.title or robot.name
    return {
        "kincalc-sheet": 1,
        "title": f"Exercises on {title} (seed {int(seed)})",
        "robot": robot_ref or robot.name,
        "units": units.to_dict(),
        "seed": int(seed),
        "items": items,
    }
