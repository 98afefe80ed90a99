"""The sheet format of :mod:`kincalc.homework.sheet`: its keys, default tolerances and
hint factors, the parsed sheet (:class:`Sheet`, :class:`Item`, :class:`Tolerance`), its
error, and the words a sheet uses for the core's pose messages."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import RobotFileError


KINDS = ("dh", "link", "fk", "ik", "jacobian", "reach", "singular")
SHEET_KEYS = {"kincalc-sheet": False, "title": False, "student": False, "robot": True,
              "units": False, "tolerance": False, "parameters": False, "seed": False,
              "items": True}
ITEM_KEYS = {"id": True, "kind": True, "answer": False, "tolerance": False, "points": False,
             "question": False}
KIND_KEYS = {
    "dh": {"tool": False, "base": False},
    "link": {"link": True, "q": True},
    "fk": {"q": True},
    "ik": {"pose": True, "limits": False, "lock": False},
    "jacobian": {"q": True, "frame": False},
    "reach": {"pose": True},
    "singular": {"q": True},
}
TOLERANCE_KEYS = {"position": False, "angle": False, "matrix": False}
POSE_FIELDS = {"xyz": 3, "rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
               "matrix": 9, "approach": 3, "tcv": 6, "T": 16, "q": 0}
#: default tolerances: angles (deg) and rotation-matrix entries; positions are
#: DEFAULT_POSITION x the arm's size
DEFAULT_ANGLE_DEG = 0.1
DEFAULT_MATRIX = 2e-3
DEFAULT_POSITION = 1e-3
#: answers within HINT_FACTOR x the tolerance of a slip's result are said to fit it
HINT_FACTOR = 3.0
#: an ik set whose every value is within MIX_FACTOR x the tolerance of some solution's
#: value, but not all of one solution's, is said to mix branches
MIX_FACTOR = 20.0
#: random configurations on which a dh answer's FK must agree with the robot's
DH_SAMPLES = 200


def numeric_items_limit(robot, kinds) -> str | None:
    """What is wrong with a sheet of items ``kinds`` (their kinds, those of ik items that
    hold no joint) for ``robot``: more than MAX_NUMERIC_ITEMS ik and reach items for a robot
    kincalc solves numerically (they bound the time a sheet takes to grade, as the item
    count does), or None."""
    from ...limits import MAX_NUMERIC_ITEMS, quote
    count = sum(kind in ("ik", "reach") for kind in kinds)
    if count <= MAX_NUMERIC_ITEMS:
        return None
    from ...ik.families import plan
    if plan(robot)[1] is not None:
        return None
    return (f"{count} ik and reach items; for {quote(robot.name)}, which kincalc solves "
            f"numerically (a second or so an item), a sheet holds at most {MAX_NUMERIC_ITEMS} "
            "(kincalc's limit)")


class SheetError(RobotFileError):
    """An invalid sheet: ``file:line: message`` (exit status 2)."""


@dataclass(frozen=True)
class Tolerance:
    """Grading tolerances in SI: ``position`` (m), ``angle`` (rad), ``matrix`` (unitless)."""

    position: float
    angle: float
    matrix: float

    def to_dict(self, units) -> dict:
        return {"position": self.position * units.l, "angle": self.angle * units.a,
                "matrix": self.matrix}


@dataclass(frozen=True)
class Item:
    """One exercise of a sheet, parsed; values SI."""

    id: str
    kind: str
    line: int
    tol: Tolerance
    points: float
    question: str | None = None
    q: np.ndarray | None = None          # (n,) joints for link/fk/jacobian/singular
    link: int | None = None              # 1-based, for link
    frame: str = "base"                  # for jacobian
    target: object = None                # kincalc.ik.Target for ik/reach
    limits: bool = True                  # ik: only solutions within the limits are required
    lock: tuple = ()                     # ik: joints held, ((index, value SI), ...)
    tool: str = "compare"                # dh: compare | ignore
    base: str = "compare"
    answer: object = None                # kind-specific, parsed; None = not answered
    answer_line: int | None = None


@dataclass(frozen=True)
class Sheet:
    path: str
    robot: object
    units: object                        # kincalc.analysis.results.Units: the sheet's units
    tolerance: Tolerance
    items: list
    title: str = ""
    student: str = ""


_OPTION_KEYS = {"--from-q": "q", "--pose": "T", "--matrix": "matrix"}


def sheet_words(message: str) -> str:
    """A message about command-line pose options, in the words of a sheet's ``pose`` keys
    (``--euler-zyz`` -> ``euler_zyz``, ``--from-q`` -> ``q``)."""
    import re
    message = re.sub(r" X Y Z", "", message)
    return re.sub(r"--[a-z][a-z-]*",
                  lambda m: _OPTION_KEYS.get(m.group(0), m.group(0)[2:].replace("-", "_")),
                  message)


def round1(x: float) -> float:
    """``x`` rounded to one significant digit (tolerances read better that way)."""
    if x <= 0 or not math.isfinite(x):
        return x
    e = math.floor(math.log10(x))
    return round(x, -e)
