"""Grading homework sheets (``kincalc check``).

A sheet (YAML; the format is in the README, "kincalc check", and in
``man kincalc-check``) names a robot and lists items, each an exercise with
the student's answer. :func:`load_sheet` reads and validates the whole sheet
first (an invalid sheet is a :class:`SheetError` naming file and line, exit
status 2, before anything is graded); :func:`grade` then grades every item
against kincalc's own forward kinematics, IK, Jacobian and reach analysis,
and looks for the common slips behind a wrong answer (degrees read as
radians, a joint's sign, two joints swapped, a transposed or inverted matrix,
standard and modified DH mixed up).

Everything inside is SI (m, rad); sheet values are converted on reading with
the sheet's units (by default the robot file's), and reports convert back.
"""

from __future__ import annotations

import itertools
import math
import os
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError, KincalcError, RobotFileError, TargetMismatch
from .limits import MAX_IK_SETS, MAX_SHEET_ITEMS, cut, quote
from .results import json_numbers
from .spatial import TCV_MAX_ROLL
from .robot_file import Reader, compose_yaml, node_line

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
    "ik": {"pose": True, "limits": False},
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


@dataclass
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
    tool: str = "compare"                # dh: compare | ignore
    base: str = "compare"
    answer: object = None                # kind-specific, parsed; None = not answered
    answer_line: int | None = None


@dataclass
class Sheet:
    path: str
    robot: object
    units: object                        # kincalc.results.Units: the sheet's units
    tolerance: Tolerance
    items: list
    title: str = ""
    student: str = ""


@dataclass
class ItemResult:
    id: str
    kind: str
    passed: bool
    points: float
    error: float | None
    message: str
    hint: str | None = None
    details: dict = field(default_factory=dict)
    line: int | None = None

    def to_dict(self) -> dict:
        return {"id": self.id, "kind": self.kind, "passed": self.passed, "points": self.points,
                "error": self.error, "message": self.message, "hint": self.hint,
                "line": self.line, "details": self.details}


@dataclass
class Report:
    sheet: Sheet
    items: list

    @property
    def score(self) -> dict:
        total = sum(r.points for r in self.items)
        got = sum(r.points for r in self.items if r.passed)
        return {"points": got, "total": total,
                "percent": round(100.0 * got / total, 1) if total else 100.0,
                "correct": sum(r.passed for r in self.items), "items": len(self.items)}

    @property
    def all_correct(self) -> bool:
        return all(r.passed for r in self.items)

    def to_dict(self) -> dict:
        from .results import json_header
        s = self.sheet
        out = json_header("check", s.robot, s.units)
        out.update({"sheet": s.path, "title": s.title, "student": s.student,
                    "tolerance": s.tolerance.to_dict(s.units),
                    "items": [r.to_dict() for r in self.items], "score": self.score})
        return out


# --- reading a sheet -----------------------------------------------------------------

def load_sheet(path: str, robots_dirs=()) -> Sheet:
    """Read and validate the sheet at ``path`` (at most
    :data:`~kincalc.limits.MAX_FILE_BYTES`); raise :class:`SheetError` if invalid.
    ``robots_dirs``: folders besides the sheet's own that its ``robot:`` may name a file
    in (see :func:`sheet_robot_path`)."""
    from .robot_file import read_text
    text = read_text(path, path, "a sheet", SheetError)
    return parse_sheet(text, path, os.path.dirname(os.path.abspath(path)), robots_dirs)


def parse_sheet(text: str, file: str = "<sheet>", folder: str = ".", robots_dirs=()) -> Sheet:
    """Parse the YAML ``text`` of a sheet; a robot file it names must be in ``folder``
    (the sheet's) or in one of ``robots_dirs`` (see :func:`sheet_robot_path`)."""
    try:
        root = compose_yaml(text, file)
    except RobotFileError as exc:
        raise SheetError(file, exc.line, exc.detail) from None
    return _SheetReader(file, folder, robots_dirs).sheet(root)


def sheet_robot_path(name: str, folder: str, robots_dirs=()) -> str:
    """The robot file a sheet's ``robot: NAME`` means, under the one rule for sheets.

    A sheet is untrusted input (a student writes it, a grader runs it), so it may name
    only a file inside ``folder`` (the sheet's own) or inside one of ``robots_dirs``
    (folders the grader allows, ``--robots-dir``). A relative ``name`` is looked up in
    each of ``robots_dirs``, in order, then in ``folder`` (the grader's robots come
    first); an absolute one is taken as it is. A candidate counts only when its real
    path (symbolic links followed) lies inside one of those folders, and that is
    decided before anything is asked of the file system about the candidate itself,
    so an absolute path, a ``..`` or a symbolic link leading out is refused (as
    "outside", when no candidate inside is a file) without telling whether such a
    file exists. No file is opened here.

    Raises
    ------
    InputError
        The name leads out of the allowed folders, or names no regular file there.
        The message starts "robot 'NAME'" (NAME cut to :data:`~kincalc.limits.MAX_QUOTE`).
    """
    q = quote(name)
    if not name or "\0" in name:
        raise InputError(f"robot {q} is not a file name")
    bases = [*robots_dirs, folder]
    roots = [os.path.realpath(b) for b in bases]
    candidates = [name] if os.path.isabs(name) else [os.path.join(b, name) for b in bases]
    inside = [c for c in candidates if _within(os.path.realpath(c), roots)]
    for c in inside:
        if os.path.isfile(c):
            return c
    if len(inside) < len(candidates):
        allowed = "the sheet's folder or a --robots-dir folder" if robots_dirs else \
            "the sheet's folder"
        raise InputError(f"robot {q} is outside {allowed}: a sheet's robot is a bundled robot, "
                         f"an inline robot or a file in {allowed} (no absolute path, no '..', "
                         "no symbolic link leading out)"
                         + ("" if robots_dirs else
                            "; a grader can allow another folder with --robots-dir DIR"))
    import difflib

    from .library import bundled_names
    close = difflib.get_close_matches(name, bundled_names(), n=1)
    where = "in the sheet's folder" + (" or a --robots-dir folder" if robots_dirs else "")
    raise InputError(f"robot {q} is neither a bundled robot nor a file {where}"
                     + (f" (did you mean {close[0]!r}?)" if close else
                        " (see 'kincalc robots list')"))


def _within(path: str, roots) -> bool:
    """Whether the real path ``path`` is one of the real paths ``roots`` or inside one."""
    return any(path == r or path.startswith(r.rstrip(os.sep) + os.sep) for r in roots)


class _SheetReader(Reader):
    """The robot file reader's checked numbers, lists and errors, for sheets."""

    def fail(self, node, message: str):
        raise SheetError(self.file, node_line(node) if node is not None else None,
                         (f"item {quote(self.item)}: " if self.item is not None else "")
                         + message)

    def __init__(self, file: str, folder: str, robots_dirs=()):
        super().__init__(file)
        self.folder = folder
        self.robots_dirs = tuple(robots_dirs)
        self.item: str | None = None

    # the sheet ---------------------------------------------------------------------
    def sheet(self, root) -> Sheet:
        from .results import Units
        top = self.mapping(root, "the sheet", SHEET_KEYS)
        if "kincalc-sheet" in top:
            version = self.text(top["kincalc-sheet"], "'kincalc-sheet'")
            if version.strip() != "1":
                self.fail(top["kincalc-sheet"], f"this kincalc reads sheet format 1, not "
                                                f"{quote(version)}")
        robot = self.robot_ref(top["robot"])
        self.robot_ = robot
        units = {}
        if "units" in top:
            from .units import ANGLE_UNITS, LENGTH_UNITS
            u = self.mapping(top["units"], "'units'", {"angle": False, "length": False})
            if "angle" in u:
                units["angle"] = self.text(u["angle"], "'units.angle'")
                if units["angle"] not in ANGLE_UNITS:
                    self.fail(u["angle"], f"'units.angle' must be deg or rad, not "
                                          f"{quote(units['angle'])}")
            if "length" in u:
                units["length"] = self.text(u["length"], "'units.length'")
                if units["length"] not in LENGTH_UNITS:
                    self.fail(u["length"], f"'units.length' must be one of "
                                           f"{', '.join(LENGTH_UNITS)}, not "
                                           f"{quote(units['length'])}")
                if (units["length"] == "unitless") != (robot.length_unit == "unitless"):
                    self.fail(u["length"], f"robot {quote(robot.name)} is "
                              + ("unitless" if robot.length_unit == "unitless" else
                                 f"in {robot.length_unit}")
                              + f"; 'units.length: {units['length']}' does not apply")
        self.units = Units(angle=units.get("angle", robot.angle_unit),
                           length=units.get("length", robot.length_unit))
        self.A = 1.0 / self.units.a      # rad per sheet angle unit
        self.L = 1.0 / self.units.l      # m per sheet length unit
        # the robot's parameters are in the robot file's units; on the sheet they mean the
        # same lengths (angles) in the sheet's units
        from .units import angle_factor, length_factor
        lf = length_factor(robot.length_unit) / length_factor(self.units.length)
        af = angle_factor(robot.angle_unit) / angle_factor(self.units.angle)
        self.length_params = {k: v * lf for k, v in robot.parameters}
        self.angle_params = {k: v * af for k, v in robot.parameters}
        self.params = dict(self.length_params)
        self.sheet_params = {}
        if "parameters" in top:
            for name, vnode in self.names(top["parameters"], "'parameters'"):
                self.sheet_params[name] = self.number(vnode, f"parameter {quote(name)}")
        self.length_params.update(self.sheet_params)
        self.angle_params.update(self.sheet_params)
        self.params = dict(self.length_params)
        default = Tolerance(
            position=_round1(DEFAULT_POSITION * robot.characteristic_length * self.units.l) * self.L,
            angle=math.radians(DEFAULT_ANGLE_DEG), matrix=DEFAULT_MATRIX)
        tol = self.tolerance(top["tolerance"], default) if "tolerance" in top else default
        inodes = self.sequence(top["items"], "'items'")
        if not inodes:
            self.fail(top["items"], "'items' is empty")
        if len(inodes) > MAX_SHEET_ITEMS:
            self.fail(top["items"], f"'items' has {len(inodes)} items; a sheet holds at most "
                                    f"{MAX_SHEET_ITEMS} (kincalc's limit)")
        items, seen = [], {}
        for node in inodes:
            item = self.item_entry(node, tol)
            if item.id in seen:
                self.fail(node, f"id {quote(item.id)} is already used by the item on line "
                                f"{seen[item.id]}")
            seen[item.id] = item.line
            items.append(item)
            self.item = None
        return Sheet(path=self.file, robot=robot, units=self.units, tolerance=tol, items=items,
                     title=self.opt_text(top, "title"), student=self.opt_text(top, "student"))

    def opt_text(self, top, key) -> str:
        return self.text(top[key], f"'{key}'").strip() if key in top else ""

    def robot_ref(self, node):
        from .library import bundled_names, library_dir
        from .robot_file import load_robot_file
        if self.is_mapping(node):
            self.put_first(node, "name", "sheet-robot")
            reader = Reader(self.file)
            try:
                return reader.robot(node)
            except RobotFileError as exc:      # the sheet's own text: quoted as for a sheet
                where = self.file if exc.line is None else f"{self.file}:{exc.line}"
                raise SheetError(self.file, exc.line, "robot: " + str(exc)[len(where) + 2:]) \
                    from None
        name = self.text(node, "'robot'").strip()
        if "/" not in name and "\\" not in name and not name.endswith((".yaml", ".yml")) \
                and name in bundled_names():
            return load_robot_file(library_dir() / f"{name}.yaml", display_name=name)
        try:
            path = sheet_robot_path(name, self.folder, self.robots_dirs)
        except InputError as exc:
            self.fail(node, str(exc))
        return self.robot_file(node, name, path)

    def robot_file(self, node, name: str, path: str):
        """The robot file at ``path`` that ``robot: NAME`` named. Its content is never
        quoted: the sheet's author may not own it (another student's sheet in the same
        folder, a grader's file), so a problem in it is reported by its line only."""
        from .robot_file import parse_robot_text, read_text
        q = quote(name)
        try:
            text = read_text(path, name, "a robot file")
        except RobotFileError as exc:
            if exc.line is None:        # about the file (size, a folder, unreadable)
                self.fail(node, f"robot {q}: {exc.detail}")
            text = None
            line = exc.line
        if text is not None:
            try:
                robot = parse_robot_text(text, name)
            except RobotFileError as exc:
                line = exc.line
            else:
                object.__setattr__(robot, "path", str(path))
                return robot
        at = f" (the first problem is on its line {line})" if line is not None else ""
        self.fail(node, f"robot {q} is not a valid robot file{at}; 'kincalc robots validate' "
                        "on it says what is wrong")

    def tolerance(self, node, base: Tolerance) -> Tolerance:
        t = self.mapping(node, "'tolerance'", TOLERANCE_KEYS)
        out = {"position": base.position, "angle": base.angle, "matrix": base.matrix}
        scale = {"position": self.L, "angle": self.A, "matrix": 1.0}
        for key, vnode in t.items():
            v = self.number(vnode, f"'tolerance.{key}'")
            if v <= 0:
                self.fail(vnode, f"'tolerance.{key}' must be positive")
            out[key] = v * scale[key]
        return Tolerance(**out)

    # items -------------------------------------------------------------------------
    def item_entry(self, node, sheet_tol: Tolerance) -> Item:
        if not self.is_mapping(node):
            self.fail(node, f"each item must be a mapping with 'id' and 'kind', not {self.kind(node)}")
        raw = self.plain_keys(node)
        if "id" in raw and self.is_scalar(raw["id"]):
            self.item = str(raw["id"].value)
        kind = None
        if "kind" in raw and self.is_scalar(raw["kind"]):
            kind = raw["kind"].value
            if kind not in KINDS:
                self.fail(raw["kind"], f"'kind' must be one of {', '.join(KINDS)}, not "
                                       f"{quote(kind)}")
        keys = dict(ITEM_KEYS, **KIND_KEYS.get(kind, {}))
        f = self.mapping(node, "the item", keys)
        ident = self.text(f["id"], "'id'").strip()
        if not ident:
            self.fail(f["id"], "'id' must not be empty")
        tol = self.tolerance(f["tolerance"], sheet_tol) if "tolerance" in f else sheet_tol
        points = self.number(f["points"], "'points'") if "points" in f else 1
        points = int(points) if float(points).is_integer() else points
        if points < 0:
            self.fail(f["points"], "'points' must not be negative")
        item = Item(id=ident, kind=kind, line=node_line(node), tol=tol, points=points,
                    question=self.text(f["question"], "'question'") if "question" in f else None)
        robot = self.robot_
        if "q" in f:
            item.q = self.joints(f["q"], "'q'", allow_one=kind == "link")
        if kind == "link":
            k = self.number(f["link"], "'link'")
            if k != int(k) or not 1 <= k <= robot.dof:
                self.fail(f["link"], f"'link' must be a joint number 1..{robot.dof}, not "
                                     f"{cut(f['link'].value)}")
            item.link = int(k)
            if item.q.shape == (1,):          # just q_i: the other joints do not matter
                q = np.zeros(robot.dof)
                q[item.link - 1] = item.q[0] * (self.A if robot.is_revolute[item.link - 1]
                                                else self.L)
                item.q = q
        if kind == "jacobian" and "frame" in f:
            item.frame = self.text(f["frame"], "'frame'").strip()
            if item.frame not in ("base", "tool"):
                self.fail(f["frame"], f"'frame' must be base or tool, not {quote(item.frame)}")
        for key in ("tool", "base"):
            if key in f:
                v = self.text(f[key], f"'{key}'").strip()
                if v not in ("compare", "ignore"):
                    self.fail(f[key], f"'{key}' must be compare or ignore, not {quote(v)}")
                setattr(item, key, v)
        if kind == "ik" and "limits" in f:
            v = self.text(f["limits"], "'limits'").strip()
            if v not in ("respect", "ignore"):
                self.fail(f["limits"], f"'limits' must be respect or ignore, not {quote(v)}")
            item.limits = v == "respect"
        if "pose" in f:
            item.target = self.pose_target(f["pose"])
        if "answer" in f and not f["answer"].tag.endswith(":null"):
            item.answer_line = node_line(f["answer"])
            item.answer = self.answer(kind, f["answer"], item)
            if kind == "fk" and "tcv" in item.answer and abs(item.q[-1]) > TCV_MAX_ROLL:
                # e^(q_n / pi) leaves the numbers a sheet can hold, and soon overflows
                self.fail(f["q"], f"'answer.tcv': the tool configuration vector is given only "
                                  f"for a last joint within {TCV_MAX_ROLL:.1f} rad (ten turns)")
        return item

    def joints(self, node, what: str, allow_one: bool = False) -> np.ndarray:
        robot = self.robot_
        if allow_one and self.is_scalar(node):
            return np.array([self.number(node, what)])   # scaled by the caller's joint
        items = self.sequence(node, what)
        if len(items) != robot.dof:
            self.fail(node, f"{what} has {len(items)} values but {robot.name} has {robot.dof} "
                            f"joints ({', '.join(j.name for j in robot.joints)})")
        values = np.array([self.number(v, f"{what}[{k}]") for k, v in enumerate(items)])
        return values * np.where(robot.is_revolute, self.A, self.L)

    def matrix(self, node, what: str, shapes) -> np.ndarray:
        """A list of rows of numbers with one of ``shapes`` (rows, cols; 0 = any)."""
        rows = self.sequence(node, what)
        if not rows or not all(self.is_sequence(r) for r in rows):
            self.fail(node, f"{what} must be a list of rows (a matrix written as [[...], [...]])")
        M = np.array([[self.number(v, f"{what} row {i + 1}") for v in r.value]
                      for i, r in enumerate(rows)], dtype=object)
        widths = {len(r.value) for r in rows}
        if len(widths) != 1:
            self.fail(node, f"{what}: the rows have different lengths")
        shape = (len(rows), widths.pop())
        if not any(all(want in (0, got) for want, got in zip(s, shape)) for s in shapes):
            want = " or ".join(dict.fromkeys(f"{r}x{c}".replace("0", "n") for r, c in shapes))
            self.fail(node, f"{what} must be {want}, not {shape[0]}x{shape[1]}")
        return M.astype(float)

    def pose_target(self, node):
        """The ``pose`` mapping as a :class:`~kincalc.ik.Target` (built by
        :mod:`kincalc.ik.target`, as the command line's and the batch records' are)."""
        from .ik import Target
        from .ik.target import BadTarget, defect_text, target_form, targets_from, to_si
        f = self.mapping(node, "'pose'", {k: False for k in POSE_FIELDS})
        if not f:
            self.fail(node, "'pose' is empty: give xyz with an orientation, T, tcv or q")
        kw = {}
        for key, vnode in f.items():
            if key == "q":
                kw["q"] = self.joints(vnode, "'pose.q'")
            elif key in ("T", "matrix") and self.is_sequence(vnode) and vnode.value \
                    and self.is_sequence(vnode.value[0]):
                n = 4 if key == "T" else 3
                kw[key] = self.matrix(vnode, f"'pose.{key}'", [(n, n)]).ravel()
            else:
                kw[key] = self.vector(vnode, f"'pose.{key}'", POSE_FIELDS[key])
        try:
            form = target_form(kw)
        except BadTarget as exc:
            self.fail(node, f"'pose': {exc.words(lambda field: field)}")
        if form == "q":
            return Target(self.robot_.fk(kw["q"]), orientation=True)
        values = None if form is None else to_si(form, np.asarray(kw[form], float)[None],
                                                 self.units)
        xyz = None if "xyz" not in kw else np.asarray(kw["xyz"], float)[None] / self.units.l
        targets, defect = targets_from(form, values, xyz)
        if defect[0] is not None:
            self.fail(node, f"'pose': {defect_text(form, defect[0], form)}")
        return Target.of(targets)

    # answers -------------------------------------------------------------------
    def answer(self, kind: str, node, item: Item):
        robot = self.robot_
        if kind in ("reach", "singular"):
            if not self.is_scalar(node):
                self.fail(node, "'answer' must be yes or no")
            v = str(node.value).strip().lower()
            if v not in ("yes", "no", "true", "false", "y", "n"):
                self.fail(node, f"'answer' must be yes or no, not {quote(node.value)}")
            return v in ("yes", "true", "y")
        if kind == "link":
            return self.matrix(node, "'answer'", [(4, 4), (3, 4)])
        if kind == "jacobian":
            return self.matrix(node, "'answer'", [(6, robot.dof), (3, robot.dof),
                                                  (2, robot.dof), (robot.dof, 6)])
        if kind == "fk":
            if self.is_sequence(node):
                return {"T": self.matrix(node, "'answer'", [(4, 4), (3, 4)])}
            keys = {"position": False, "xyz": False, "rpy": False, "euler_zyz": False,
                    "euler_xyz": False, "quat": False, "axis_angle": False, "matrix": False,
                    "T": False, "tcv": False}
            f = self.mapping(node, "'answer'", keys)
            out = {}
            given = [k for k in keys if k in f]
            if "position" in f and "xyz" in f:
                self.fail(node, "'answer': give 'position' or 'xyz', not both")
            if "T" in f and len(given) > 1:
                self.fail(node, f"'answer': T is the whole pose; do not add "
                                f"{next(k for k in given if k != 'T')!r}")
            if "tcv" in f and len(given) > 1:
                self.fail(node, f"'answer': tcv holds position and approach; do not add "
                                f"{next(k for k in given if k != 'tcv')!r}")
            if "T" in f:
                out["T"] = self.matrix(f["T"], "'answer.T'", [(4, 4), (3, 4)])
            if "tcv" in f:
                if not robot.joints[-1].revolute:
                    self.fail(f["tcv"], "'answer.tcv': the tool configuration vector needs a "
                                        "revolute last joint")
                out["tcv"] = self.vector(f["tcv"], "'answer.tcv'", 6)
            for key in ("position", "xyz"):
                if key in f:
                    out["position"] = self.vector(f[key], f"'answer.{key}'", 3)
            orient = [k for k in ("rpy", "euler_zyz", "euler_xyz", "quat", "axis_angle", "matrix")
                      if k in f]
            if len(orient) > 1:
                self.fail(node, f"'answer': give one orientation, not {' and '.join(orient)}")
            if orient:
                k = orient[0]
                if k == "matrix":
                    out["matrix"] = self.matrix(f[k], "'answer.matrix'", [(3, 3)])
                else:
                    out[k] = self.vector(f[k], f"'answer.{k}'", 4 if k in ("quat", "axis_angle") else 3)
                    if k == "quat" and np.linalg.norm(out[k]) < 1e-9:
                        self.fail(f[k], "'answer.quat' must not be the zero quaternion")
                    if k == "axis_angle" and np.linalg.norm(out[k][:3]) < 1e-9:
                        self.fail(f[k], "'answer.axis_angle' needs a non-zero axis")
            if not out:
                self.fail(node, "'answer' is empty: give T, or position and an orientation")
            return out
        if kind == "ik":
            sets = self.sequence(node, "'answer' (a list of solution sets)")
            if sets and not self.is_sequence(sets[0]):
                sets = [node]                      # one set written as a flat list
            if len(sets) > MAX_IK_SETS:
                self.fail(node, f"'answer' has {len(sets)} solution sets; an ik item takes at "
                                f"most {MAX_IK_SETS} (kincalc's limit; a six-joint arm has at "
                                f"most 16 solutions)")
            return [(node_line(s), self.joints(s, f"'answer' set {k + 1}"))
                    for k, s in enumerate(sets)]
        if kind == "dh":
            return self.dh_answer(node, item)
        raise AssertionError(kind)

    def dh_answer(self, node, item: Item):
        """The student's DH table as a robot, with how each row names its variable."""
        from .model import Joint, Robot
        f = self.mapping(node, "'answer'", {"convention": True, "table": False, "columns": False,
                                            "joints": False, "base": False, "tool": False,
                                            "name": False})
        conv = self.text(f["convention"], "'answer.convention'").strip()
        if conv not in ("dh", "mdh"):
            self.fail(f["convention"], f"'answer.convention' must be dh or mdh, not "
                                       f"{quote(conv)}")
        if ("table" in f) == ("joints" in f):
            self.fail(node, "'answer' needs either 'table' (rows of cells) or 'joints' (mappings)")
        joints, signs, variables = [], [], []
        if "table" in f:
            columns = ["theta", "d", "a", "alpha"] if conv == "dh" else ["alpha", "a", "d", "theta"]
            if "columns" in f:
                cnodes = self.sequence(f["columns"], "'answer.columns'", 4)
                alias = {"θ": "theta", "α": "alpha", "th": "theta"}
                columns = [alias.get(c.value.strip(), c.value.strip()) for c in cnodes]
                if sorted(columns) != ["a", "alpha", "d", "theta"]:
                    self.fail(f["columns"], "'answer.columns' must name theta, d, a and alpha "
                                            "once each")
            rows = self.sequence(f["table"], "'answer.table'")
            for k, rnode in enumerate(rows, start=1):
                cells = self.sequence(rnode, f"'answer.table' row {k}", 4)
                j, s, var = self.dh_row(dict(zip(columns, cells)), k, rnode)
                if var in variables:
                    self.fail(rnode, f"row {k}: the joint variable {var} is already row "
                                     f"{variables.index(var) + 1}'s; each row has its own")
                joints.append(j)
                signs.append(s)
                variables.append(var)
        else:
            for k, jnode in enumerate(self.sequence(f["joints"], "'answer.joints'"), start=1):
                jf = self.mapping(jnode, f"'answer.joints' entry {k}",
                                  {"name": False, "type": True, "alpha": True, "a": True,
                                   "d": True, "theta": True})
                jtype = self.text(jf["type"], "'type'").strip()
                if jtype not in ("revolute", "prismatic"):
                    self.fail(jf["type"], f"'type' must be revolute or prismatic, not "
                                          f"{quote(jtype)}")
                name = self.text(jf["name"], "'name'").strip() if "name" in jf else f"q{k}"
                joints.append(Joint(
                    name=name, type=jtype, alpha=self.angle(jf["alpha"], "'alpha'"),
                    a=self.number(jf["a"], "'a'") * self.L, d=self.number(jf["d"], "'d'") * self.L,
                    theta=self.angle(jf["theta"], "'theta'")))
                signs.append(1.0)
                variables.append(name)
        if not joints:
            self.fail(node, "'answer' has no rows")
        base = self.pose(f["base"], "'answer.base'") if "base" in f else np.eye(4)
        tool = self.pose(f["tool"], "'answer.tool'") if "tool" in f else np.eye(4)
        robot = Robot(name="answer", convention=conv, joints=tuple(joints), base=base, tool=tool,
                      length_unit=self.robot_.length_unit, angle_unit=self.robot_.angle_unit)
        return {"robot": robot, "signs": np.array(signs), "variables": variables,
                "table_given": "table" in f}

    def angle(self, node, what: str) -> float:
        """An angle (rad) whose parameter names mean angles in the sheet's unit."""
        self.params = dict(self.angle_params)
        try:
            return self.number(node, what) * self.A
        finally:
            self.params = dict(self.length_params)

    def dh_row(self, cells: dict, k: int, rnode):
        """One compact row: (Joint, sign of the variable, the variable's name)."""
        from .model import Joint
        found = {}
        for col, cnode in cells.items():
            names = self._names(cnode)
            unknown = sorted(n for n in names if n not in self.params and n != "pi")
            if len(unknown) > 1:
                self.fail(cnode, f"row {k}, {col}: {' and '.join(unknown)} are not parameters "
                                 "(a cell holds at most one joint variable)")
            if unknown:
                found[col] = unknown[0]
        if len(found) != 1 or next(iter(found)) not in ("theta", "d"):
            where = ("no cell" if not found else
                     f"{len(found)} cells ({', '.join(found)})" if len(found) > 1 else
                     f"the {next(iter(found))} cell")
            self.fail(rnode, f"row {k}: the joint variable (a name that is not a parameter) must "
                             f"appear in exactly one cell, theta or d; found it in {where}")
        col, var = next(iter(found.items()))
        values = {}
        for c, cnode in cells.items():
            scale = self.A if c in ("theta", "alpha") else self.L
            self.params = dict(self.angle_params if c in ("theta", "alpha") else self.length_params)
            if c != col:
                values[c] = self.number(cnode, f"row {k}, {c}") * scale
                continue
            saved = dict(self.params)
            try:
                self.params[var] = 0.0
                c0 = self.number(cnode, f"row {k}, {c}")
                self.params[var] = 1.0
                c1 = self.number(cnode, f"row {k}, {c}")
            finally:
                self.params = saved
            sign = c1 - c0
            if abs(abs(sign) - 1.0) > 1e-9 or abs(self._at(cnode, var, 7.0) - (c0 + 7 * sign)) > 1e-9:
                self.fail(cnode, f"row {k}, {c}: the joint variable {var} must appear as {var} or "
                                 f"-{var} plus a constant, not {quote(cnode.value)}")
            values[c] = c0 * scale
        self.params = dict(self.length_params)
        joint = Joint(name=var, type="revolute" if col == "theta" else "prismatic",
                      alpha=values["alpha"], a=values["a"], d=values["d"], theta=values["theta"])
        return joint, float(np.sign(sign)), var

    def _at(self, cnode, var, value):
        saved = dict(self.params)
        try:
            self.params[var] = value
            return self.number(cnode, "cell")
        finally:
            self.params = saved

    @staticmethod
    def _names(cnode) -> set:
        import ast
        if not hasattr(cnode, "value") or not isinstance(cnode.value, str):
            return set()
        try:
            tree = ast.parse(cnode.value.strip(), mode="eval")
        except (SyntaxError, ValueError):
            return set()
        return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}


_OPTION_KEYS = {"--from-q": "q", "--pose": "T", "--matrix": "matrix"}


#: how a sheet names the parts of an IK target (its ``pose`` keys), for the core's
#: messages about them (:class:`kincalc.errors.TargetMismatch`)
SHEET_WORDS = {"approach": "approach", "tcv": "tcv", "prefix": "{field}: ",
               "orientation": "(rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, tcv, T "
                              "or q)"}


def sheet_words(message: str) -> str:
    """A message about command-line pose options, in the words of a sheet's ``pose`` keys
    (``--euler-zyz`` -> ``euler_zyz``, ``--from-q`` -> ``q``)."""
    import re
    message = re.sub(r" X Y Z", "", message)
    return re.sub(r"--[a-z][a-z-]*",
                  lambda m: _OPTION_KEYS.get(m.group(0), m.group(0)[2:].replace("-", "_")),
                  message)


def _round1(x: float) -> float:
    """``x`` rounded to one significant digit (tolerances read better that way)."""
    if x <= 0 or not math.isfinite(x):
        return x
    e = math.floor(math.log10(x))
    return round(x, -e)


# --- grading -----------------------------------------------------------------------

def grade(sheet: Sheet) -> Report:
    """Grade every item of ``sheet``; never raises for a wrong answer."""
    results = []
    for item in sheet.items:
        if item.answer is None:
            r = ItemResult(item.id, item.kind, False, item.points, None, "no answer given")
        else:
            try:
                r = _GRADERS[item.kind](sheet, item)
            except SheetError:
                raise
            except KincalcError as exc:   # e.g. a pose this robot cannot be asked for
                text = exc.words(SHEET_WORDS) if isinstance(exc, TargetMismatch) \
                    else sheet_words(str(exc))
                raise SheetError(sheet.path, item.line, f"item {quote(item.id)}: {text}") from None
        r.line = item.line
        results.append(r)
    return Report(sheet=sheet, items=results)


def _fmt(x, digits: int = 4) -> str:
    if x is None:
        return "-"
    x = float(x)
    if x == 0 or 1e-3 <= abs(x) < 1e6:
        text = f"{x:.{digits}f}".rstrip("0").rstrip(".")
        return "0" if text in ("-0", "") else text
    return f"{x:.{digits - 1}e}"


def _qdisp(robot, q, units) -> np.ndarray:
    return np.asarray(q, float) * np.where(robot.is_revolute, units.a, units.l)


def _gaps(robot, qa, qb) -> np.ndarray:
    """Per-joint distance ``(n,)`` between joint vectors: angles modulo 2 pi (rad), m."""
    from .spatial import wrap
    d = np.asarray(qa, float) - np.asarray(qb, float)
    return np.where(robot.is_revolute, np.abs(wrap(d)), np.abs(d))


def _joint(robot, i: int) -> str:
    return f"joint {i + 1} ({robot.joints[i].name})"


def _unit_suffix(units, what: str) -> str:
    if what == "angle":
        return " deg" if units.angle == "deg" else " rad"
    return "" if units.length == "unitless" else f" {units.length}"


# slips: the answer a student gets after a common mistake --------------------------

def _q_slips(sheet: Sheet, q: np.ndarray, joints=None):
    """``(hint, robot, q)`` for the joint-value slips: degrees and radians, one sign,
    two joints swapped, standard and modified DH mixed up. ``joints`` restricts the
    per-joint slips (a link transform depends on one joint only)."""
    robot, units = sheet.robot, sheet.units
    rev = robot.is_revolute
    joints = range(robot.dof) if joints is None else joints
    disp = _qdisp(robot, q, units)
    if rev.any():
        if units.angle == "deg":
            alt = np.where(rev, disp, q)
            yield ("fits the joint angles read as radians: the sheet's angles are in degrees "
                   "(is the calculator in radian mode?)", robot, alt)
        else:
            alt = np.where(rev, np.radians(disp), q)
            yield ("fits the joint angles read as degrees: the sheet's angles are in radians",
                   robot, alt)
    for i in joints:
        if q[i] != 0:
            alt = q.copy()
            alt[i] = -q[i]
            yield (f"fits {_joint(robot, i)} with the opposite sign "
                   f"({_fmt(-disp[i])} instead of {_fmt(disp[i])}): check its direction",
                   robot, alt)
    for i, j in itertools.combinations(joints, 2):
        if rev[i] == rev[j] and q[i] != q[j]:
            alt = q.copy()
            alt[[i, j]] = q[[j, i]]
            yield (f"fits the values of {_joint(robot, i)} and {_joint(robot, j)} swapped",
                   robot, alt)
    if robot.convention in ("dh", "mdh"):
        import dataclasses
        other = "mdh" if robot.convention == "dh" else "dh"
        yield (f"fits the same table evaluated as {_CONV[other]} instead of {_CONV[robot.convention]}"
               " (standard and modified DH mixed up)",
               dataclasses.replace(robot, convention=other), q)


_CONV = {"dh": "standard DH (Rz(θ) Tz(d) Tx(a) Rx(α))",
         "mdh": "modified DH (Rx(α) Tx(a) Rz(θ) Tz(d))"}


def _transpose_rotation(M: np.ndarray) -> np.ndarray:
    Mt = np.array(M, float)
    Mt[:3, :3] = Mt[:3, :3].T
    return Mt


def _invert(M: np.ndarray) -> np.ndarray:
    from .spatial import invert_transform
    return invert_transform(M)


#: ``(hint, f)``: a right 4x4 ``M`` becomes ``f(M)`` after the slip
MATRIX_SLIPS = (
    ("fits the right matrix with its rotation part transposed", _transpose_rotation),
    ("fits the inverse of the right matrix (the transform in the other direction)", _invert),
)


def _compare_T(answer: np.ndarray, T: np.ndarray, tol: Tolerance, units, factor: float = 1.0):
    """(ok, rotation entry error, translation entry error in sheet units) for a 4x4 or
    3x4 ``answer`` (sheet units) against ``T`` (SI)."""
    Td = np.array(T, float)
    Td[:3, 3] *= units.l
    rot = float(np.max(np.abs(answer[:3, :3] - Td[:3, :3])))
    pos = float(np.max(np.abs(answer[:3, 3] - Td[:3, 3])))
    ok = rot <= tol.matrix * factor and pos <= tol.position * units.l * factor
    return ok, rot, pos


FULL_TRANSPOSE = "fits the right matrix transposed (rows written as columns)"


def _first_slip(sheet, item, check_variant, joints=None, forms=()):
    """The first slip whose result fits the answer (``check_variant(robot, q, form)``)."""
    for hint, robot, q in _q_slips(sheet, item.q, joints):
        if check_variant(robot, q, None):
            return hint
    for hint, form in forms:
        if check_variant(sheet.robot, item.q, form):
            return hint
    return None


# link ---------------------------------------------------------------------------

def _grade_link(sheet: Sheet, item: Item) -> ItemResult:
    robot, units, tol = sheet.robot, sheet.units, item.tol
    i = item.link - 1
    T = robot.link_transforms(item.q)[i]
    A = item.answer
    ok, rot, pos = _compare_T(A, T, tol, units)
    details = {"expected": units.pose(T), "rotation_error": rot, "translation_error": pos,
               "link": item.link}
    name = f"T_{item.link - 1}^{item.link}"
    if ok:
        return ItemResult(item.id, "link", True, item.points, max(rot, pos),
                          f"{name} is right", details=details)

    def fits(rob, q, form):
        M = rob.link_transforms(q)[i]
        if form == FULL_TRANSPOSE:
            return A.shape == (4, 4) and _compare_T(A.T, M, tol, units, HINT_FACTOR)[0]
        if form is not None:
            M = form(M)
        return _compare_T(A, M, tol, units, HINT_FACTOR)[0]
    forms = MATRIX_SLIPS + ((FULL_TRANSPOSE, FULL_TRANSPOSE),)
    hint = _first_slip(sheet, item, fits, joints=[i], forms=forms)
    return ItemResult(item.id, "link", False, item.points, max(rot, pos),
                      f"{name} is wrong: largest difference {_fmt(rot)} in the rotation, "
                      f"{_fmt(pos)} in the translation", hint, details)


# fk ---------------------------------------------------------------------------------

_ANGLE_SETS = ("rpy", "euler_zyz", "euler_xyz")
_ANGLE_NAMES = {"rpy": "fixed X-Y-Z (roll, pitch, yaw)", "euler_zyz": "Z-Y-Z Euler",
                "euler_xyz": "moving X-Y-Z Euler"}


def _rotation_from(kind: str, values, units) -> np.ndarray:
    """The rotation ``(3, 3)`` of an orientation answer of ``kind`` in the sheet's units,
    built by :mod:`kincalc.ik.target` as a pose's is; NaN for a degenerate answer (a zero
    quaternion or axis)."""
    from .ik.target import targets_from, to_si
    v = np.asarray(values, float)
    if kind == "matrix":
        return v
    targets, defect = targets_from(kind, to_si(kind, v.reshape(1, -1), units))
    return np.full((3, 3), np.nan) if defect[0] is not None else targets.T[0, :3, :3]


def _fk_errors(answer: dict, T: np.ndarray, units, q_last: float = 0.0) -> dict:
    """Per given part of an fk ``answer``: the error in sheet units (``q_last``: the
    last joint's value, rad, for a tool configuration vector)."""
    from .spatial import rotation_error, tcv_from_transform
    out = {}
    if "tcv" in answer:
        w = tcv_from_transform(T, q_last)
        out["position"] = float(np.linalg.norm(answer["tcv"][:3] - w[:3] * units.l))
        out["tcv"] = float(np.max(np.abs(answer["tcv"][3:] - w[3:])))
    if "T" in answer:
        _, rot, pos = _compare_T(answer["T"], T, Tolerance(1, 1, 1), units)
        out["matrix"], out["position"] = rot, pos
    if "position" in answer:
        out["position"] = float(np.linalg.norm(answer["position"] - T[:3, 3] * units.l))
    for k in ("rpy", "euler_zyz", "euler_xyz", "quat", "axis_angle", "matrix"):
        if k in answer and not ("T" in answer and k == "matrix"):
            if k == "matrix":
                out["matrix"] = float(np.max(np.abs(answer[k] - T[:3, :3])))
            else:
                R = _rotation_from(k, answer[k], units)
                out["orientation"] = float(rotation_error(R, T[:3, :3])) * units.a
    return out


def _fk_ok(err: dict, tol: Tolerance, units, factor=1.0) -> bool:
    limits = {"position": tol.position * units.l, "matrix": tol.matrix, "tcv": tol.matrix,
              "orientation": tol.angle * units.a}
    return all(v <= limits[k] * factor for k, v in err.items())


def _grade_fk(sheet: Sheet, item: Item) -> ItemResult:
    robot, units, tol = sheet.robot, sheet.units, item.tol
    T = robot.fk(item.q)
    err = _fk_errors(item.answer, T, units, item.q[-1])
    details = {"expected": units.pose(T), "errors": err}
    parts = ", ".join(f"{k} {_fmt(v)}" for k, v in err.items())
    error = max(err.values()) if err else None
    if _fk_ok(err, tol, units):
        return ItemResult(item.id, "fk", True, item.points, error,
                          f"T_0^{robot.dof} is right (differences: {parts})", details=details)

    def fits(rob, q, form):
        M = rob.fk(q)
        answer = item.answer
        if form == FULL_TRANSPOSE:
            if "T" not in answer or answer["T"].shape != (4, 4):
                return False
            answer = dict(answer, T=answer["T"].T)
        elif form is not None:
            M = form(M)
        return _fk_ok(_fk_errors(answer, M, units, q[-1]), tol, units, HINT_FACTOR)
    forms = MATRIX_SLIPS + ((FULL_TRANSPOSE, FULL_TRANSPOSE),)
    hint = _first_slip(sheet, item, fits, forms=forms) or _angle_set_slip(item.answer, T, tol, units)
    wrong = [k for k, v in err.items() if not _fk_ok({k: v}, tol, units)]
    return ItemResult(item.id, "fk", False, item.points, error,
                      f"T_0^{robot.dof} is wrong: {' and '.join(wrong)} off "
                      f"(differences: {parts})", hint, details)


def _angle_set_slip(answer: dict, T, tol, units) -> str | None:
    """The student's three angles read in another convention, order or unit."""
    from .spatial import rotation_error
    given = [k for k in _ANGLE_SETS if k in answer]
    if not given:
        return None
    k = given[0]
    v = np.asarray(answer[k], float)
    tries = []
    for other in _ANGLE_SETS:
        for order, label in ((v, ""), (v[::-1], " in reverse order")):
            if other == k and not label:
                continue
            tries.append((other, order, f"your {_ANGLE_NAMES[k]} angles are the "
                          f"{_ANGLE_NAMES[other]} angles{label} of the right orientation"))
    if units.angle == "deg":
        tries.append((k, np.degrees(v), "your angles fit in radians: the sheet's unit is degrees"))
    for kind, values, hint in tries:
        R = _rotation_from(kind, values, units)
        if rotation_error(R, T[:3, :3]) * units.a <= tol.angle * units.a * HINT_FACTOR:
            return hint
    return None


# jacobian ----------------------------------------------------------------------------

def _grade_jacobian(sheet: Sheet, item: Item) -> ItemResult:
    from .analysis import jacobian_report
    robot, units, tol = sheet.robot, sheet.units, item.tol
    n = robot.dof
    A = item.answer

    def expected(rob, q, frame):
        rep = jacobian_report(rob, q, units, frame=frame)
        return np.array(rep._display_J(rep.J))

    J = expected(robot, item.q, item.frame)
    lin_tol, ang_tol = tol.position * units.l, tol.matrix

    def score(Jx, factor=1.0, A=A):
        """(ok, error, row order) of the answer ``A`` against the 6 x n ``Jx``."""
        if A.shape == (6, n):
            best = None
            for order, lin_rows, ang_rows in (("vx vy vz wx wy wz", A[:3], A[3:]),
                                              ("wx wy wz vx vy vz", A[3:], A[:3])):
                lin = float(np.max(np.abs(lin_rows - Jx[:3])))
                ang = float(np.max(np.abs(ang_rows - Jx[3:])))
                cand = (lin <= lin_tol * factor and ang <= ang_tol * factor, max(lin, ang), order)
                if best is None or (cand[0], -cand[1]) > (best[0], -best[1]):
                    best = cand
            return best
        if A.shape == (3, n):
            e = float(np.max(np.abs(A - Jx[:3])))
            if e <= lin_tol * factor:
                return True, e, "vx vy vz"
            el = float(np.max(np.abs(A[:2] - Jx[:2])))     # a planar arm's [vx; vy; wz]
            ea = float(np.max(np.abs(A[2] - Jx[5])))
            if el <= lin_tol * factor and ea <= ang_tol * factor:
                return True, max(el, ea), "vx vy wz"
            return False, e, "vx vy vz"
        if A.shape == (2, n):
            e = float(np.max(np.abs(A - Jx[:2])))
            return e <= lin_tol * factor, e, "vx vy"
        return False, float("inf"), "transposed"

    ok, error, order = score(J)
    details = {"expected": J.tolist(), "frame": item.frame, "rows": order}
    if ok:
        return ItemResult(item.id, "jacobian", True, item.points, error,
                          f"J ({item.frame} frame) is right; rows read as {order}", details=details)
    if order == "transposed":
        ok_t = score(J, 1.0, A.T)[0]
        hint = "this is the transpose of J (n x 6): J has one column per joint" + \
            (" — transposed back it is right" if ok_t else "")
        return ItemResult(item.id, "jacobian", False, item.points, None,
                          f"J must be 6 x {n} (rows vx vy vz wx wy wz),"
                          f" not {n} x 6", hint, details)

    def fits(rob, q, form):
        Jx = expected(rob, q, form or item.frame)
        return score(Jx, HINT_FACTOR)[0]
    if n == 6 and score(J, 1.0, A.T)[0]:
        return ItemResult(item.id, "jacobian", False, item.points, error,
                          f"J ({item.frame} frame) is wrong: largest difference {_fmt(error)}",
                          "this is the transpose of J: J has one column per joint", details)
    other = "tool" if item.frame == "base" else "base"
    hint = _first_slip(sheet, item, fits,
                       forms=[(f"fits J in the {other} frame; the item asks for the "
                               f"{item.frame} frame", other)])
    if hint is None and units.angle == "deg" and score(J * math.pi / 180, HINT_FACTOR)[0]:
        hint = "fits J per degree: the Jacobian maps joint rates in rad/s"
    return ItemResult(item.id, "jacobian", False, item.points, error,
                      f"J ({item.frame} frame) is wrong: largest difference {_fmt(error)}",
                      hint, details)


# singular and reach --------------------------------------------------------------

def _yes(b: bool) -> str:
    return "yes" if b else "no"


def _grade_singular(sheet: Sheet, item: Item) -> ItemResult:
    from .analysis import jacobian_report
    rep = jacobian_report(sheet.robot, item.q, sheet.units)
    truth = rep.singular
    why = ("; ".join(rep.singularity.descriptions) if truth else
           f"the Jacobian has full rank {rep.rank} (smallest normalised singular value "
           f"{_fmt(rep.sigma_normalised[-1])})")
    passed = item.answer == truth
    msg = f"singular: {_yes(truth)} — {why}"
    details = {"expected": truth, "rank": rep.rank, "generic_rank": rep.generic_rank}
    return ItemResult(item.id, "singular", passed, item.points, None,
                      ("right; " if passed else f"wrong (answer {_yes(item.answer)}); ") + msg,
                      details=details)


def _grade_reach(sheet: Sheet, item: Item) -> ItemResult:
    from .reach import reach
    r = reach(sheet.robot, item.target, units=sheet.units)
    passed = item.answer == r.reachable
    details = {"expected": r.reachable, "verdict": r.verdict,
               "distance": None if r.distance is None else r.distance * sheet.units.l}
    return ItemResult(item.id, "reach", passed, item.points, None,
                      ("right; " if passed else f"wrong (answer {_yes(item.answer)}); ")
                      + f"reachable: {_yes(r.reachable)} — {r.verdict}: {r.reason}",
                      details=details)


# ik -------------------------------------------------------------------------------

def _target_residual(robot, target, q) -> tuple[float, float | None]:
    """(position error (m), orientation error (rad) or None) of joints ``q`` for ``target``."""
    from .spatial import wrap
    from .spatial import rotation_error
    T = robot.fk(q)
    pe = float(np.linalg.norm(T[:3, 3] - target.T[:3, 3]))
    if target.tcv is not None:
        a, qn = target.tcv
        oe = max(float(np.arccos(np.clip(T[:3, 2] @ a, -1, 1))), abs(float(wrap(q[-1] - qn))))
    elif target.approach is not None:
        oe = float(np.arccos(np.clip(T[:3, 2] @ target.approach, -1, 1)))
    elif target.orientation:
        oe = float(rotation_error(T[:3, :3], target.T[:3, :3]))
    else:
        oe = None
    return pe, oe


def _grade_ik(sheet: Sheet, item: Item) -> ItemResult:
    from .ik.solve import solve, violation_list
    from .words import reason_text
    robot, units, tol = sheet.robot, sheet.units, item.tol
    rev = robot.is_revolute
    res = solve(robot, item.target, all_branches=True, units=units)
    sols = res.solutions
    required = [k for k, s in enumerate(sols) if s.within_limits or not item.limits]
    # a numerical solver finds one solution, not all: the sets are then checked by FK
    # alone, and nothing can be called missed (unless the answer says "unreachable")
    exhaustive = res.family != "numerical"
    if not exhaustive and item.answer:
        required = []
    jtol = np.where(rev, tol.angle, tol.position)

    def close(qa, qb):
        return bool(np.all(_gaps(robot, qa, qb) <= jtol))

    def sol_dict(k):
        s = sols[k]
        return {"solution": k + 1, "solution_q": json_numbers(_qdisp(robot, s.q, units)),
                "branch": s.branch,
                "within_limits": s.within_limits, "singular": s.singular}

    sets, matched, worst = [], {}, 0.0
    for number, (line, q) in enumerate(item.answer, start=1):
        pe, oe = _target_residual(robot, item.target, q)
        worst = max(worst, pe * units.l)
        entry = {"set": number, "line": line, "q": json_numbers(_qdisp(robot, q, units)),
                 "residual": {"position": pe * units.l,
                              "orientation": None if oe is None else oe * units.a}}
        hit = next((k for k in range(len(sols)) if close(q, sols[k].q)), None) \
            if exhaustive else None
        reaches = pe <= tol.position and (oe is None or oe <= tol.angle)
        if hit is not None and hit in matched:
            entry.update(status="duplicate", note=f"the same solution as set {matched[hit]}",
                         **sol_dict(hit))
        elif hit is not None and hit in required:
            matched[hit] = number
            entry.update(status="correct", **sol_dict(hit))
        elif hit is not None:
            viol = ", ".join(f"{_joint(robot, j)} beyond its {side} limit by "
                             f"{_fmt(amount * (units.a if rev[j] else units.l))}"
                             for j, amount, side in (violation_list(robot, q) or sols[hit].violations))
            entry.update(status="wrong", note=f"reaches the target but is outside the joint "
                         f"limits ({viol}); the item counts only solutions within the limits",
                         **sol_dict(hit))
        elif reaches and not exhaustive:
            if item.limits and violation_list(robot, q):
                entry.update(status="wrong", note="reaches the target but is outside the "
                             "joint limits")
            else:
                entry.update(status="correct", note="reaches the target (checked by FK)")
        elif reaches:
            entry.update(status="correct", note="reaches the target (not one of the isolated "
                         "solutions: the target is at a singularity or your set is equivalent)")
        else:
            entry.update(status="wrong", note=_ik_wrong_note(sheet, item, q, pe, oe, res, required))
        sets.append(entry)
    missed = [sol_dict(k) for k in required if k not in matched]
    wrong = [s for s in sets if s["status"] == "wrong"]
    right = [s for s in sets if s["status"] == "correct"]
    passed = not wrong and not missed
    if not exhaustive and item.answer:
        truth = (f"{robot.name} has no closed-form IK in kincalc: each set is checked by FK, "
                 "and sets you did not list cannot be named")
    elif not sols:
        truth = f"the target is not reachable ({reason_text(res.reason, robot, units)})"
    else:
        truth = (f"the target has {len(required)} solution{'s' if len(required) != 1 else ''}"
                 + (" within the limits" if item.limits and len(required) != len(sols) else ""))
    if passed:
        msg = (f"right: {'all ' if len(right) > 1 else ''}{len(right)} solution "
               f"set{'s' if len(right) != 1 else ''} ({truth})" if sets else f"right: {truth}")
    else:
        parts = []
        if right:
            parts.append(f"{len(right)} right")
        if wrong:
            parts.append(f"{len(wrong)} wrong (set{'s' if len(wrong) > 1 else ''} "
                         f"{', '.join(str(s['set']) for s in wrong)})")
        if missed:
            parts.append(f"{len(missed)} missed")
        msg = f"{'; '.join(parts)}; {truth}"
    notes = [f"set {s['set']}: {s['note']}" for s in wrong]
    if missed:
        notes.append("missed: " + "; ".join(f"{_fmt_q(m['solution_q'])} ({m['branch']})"
                                          for m in missed))
    hint = "; ".join(notes) or None
    details = {"sets": sets, "missed": missed, "solutions": len(sols), "required": len(required),
               "method": res.method}
    return ItemResult(item.id, "ik", passed, item.points, worst if sets else None, msg, hint,
                      details)


def _fmt_q(values) -> str:
    return "(" + ", ".join(_fmt(v) for v in values) + ")"


def _ik_wrong_note(sheet, item, q, pe, oe, res, required) -> str:
    """Why a student's set misses: a textbook +/- combination, one joint off, a slip."""
    robot, units, tol = sheet.robot, sheet.units, item.tol
    rev = robot.is_revolute
    jtol = np.where(rev, tol.angle, tol.position)
    sols = res.solutions
    miss = f"FK misses the target by {_fmt(pe * units.l)}{_unit_suffix(units, 'length')}"
    if oe is not None:
        miss += f" and {_fmt(oe * units.a)}{_unit_suffix(units, 'angle')} in orientation"

    def diff(qa, qb):
        return _gaps(robot, qa, qb)

    for rej in res.rejected or []:
        if np.all(diff(q, rej["q"]) <= jtol):
            return (f"{miss}: every value is one of the solutions' values, but this "
                    "combination of them is not a solution (a wrong pairing of the +/- roots, "
                    "as in Bingül & Küçük's Example 4.2)")
    note = miss
    cands = [sols[k] for k in required] or sols
    if cands:
        d = [diff(q, s.q) for s in cands]
        off = [np.flatnonzero(x > jtol) for x in d]
        best = min(range(len(cands)), key=lambda k: (len(off[k]), float(np.sum(d[k] / jtol))))
        s, bad = cands[best], off[best]
        if len(bad) < robot.dof:
            vals = ", ".join(f"{robot.joints[j].name} = {_fmt(_qdisp(robot, s.q, units)[j])}"
                             for j in bad)
            note += (f"; closest solution ({s.branch}) differs only in "
                     f"{', '.join(robot.joints[j].name for j in bad)}: it has {vals}")
            borrowed = []
            for j in bad:
                near = min(cands, key=lambda c: diff(q, c.q)[j])
                if near is not s and diff(q, near.q)[j] <= MIX_FACTOR * jtol[j]:
                    borrowed.append(f"{robot.joints[j].name} is near the "
                                    f"{_fmt(_qdisp(robot, near.q, units)[j])} of the {near.branch} "
                                    "solution")
            if borrowed and len(borrowed) == len(bad):
                note += f" ({'; '.join(borrowed)}: the set mixes branches)"
    for hint, rob, alt in _q_slips(sheet, np.asarray(q, float)):
        if rob is not robot:
            continue
        if any(np.all(diff(alt, c.q) <= jtol * HINT_FACTOR) for c in cands):
            return f"{note}; your set {hint}"
    return note


# dh ---------------------------------------------------------------------------------

def _grade_dh(sheet: Sheet, item: Item) -> ItemResult:
    import dataclasses

    from .equivalence import match
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
               "worst_q": _qdisp(robot, m.worst_q, units).tolist() if m.worst_q is not None else None}
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
                text += f" {'+' if off > 0 else '-'} {_fmt(abs(off))}"
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
               f"{_fmt(m.position_error * units.l)}{_unit_suffix(units, 'length')})")
        if conv == "mdh" and not has_tool:
            hint = hint or ("the robot's tool frame is not the last joint's frame: add it as "
                            "'tool: {xyz: [...], rpy: [...]}' to the answer, or grade the axes "
                            "only with 'tool: ignore' on the item")
    if hint is None and k is not None:
        hint = _row_hint(robot, cand, min(row, n) if row else None, units, tol)
    return ItemResult(item.id, "dh", False, item.points, m.position_error * units.l, msg,
                      hint, details)


_CONV_SHORT = {"dh": "standard DH", "mdh": "modified DH"}


def _reference_table(robot, conv: str, fold_tool: bool):
    """The robot's own table in convention ``conv`` (None for poe robots); with
    ``fold_tool`` a standard-DH tool is folded into the last row where it fits."""
    from .conventions import dh_to_mdh, mdh_to_dh
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
    from .spatial import wrap
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
                    diffs.append(f"{f} = {_fmt(rv * s)} there, {_fmt(cv * s)} here")
        if diffs:
            return (f"compare row {k} with the robot's own {_CONV_SHORT[cand.convention]} "
                    f"table ({'; '.join(diffs)}); that table has row {k}: "
                    f"{_reference_row(ref, k, units)}")
    return None


def _reference_row(ref, k: int, units) -> str:
    """Row ``k`` (1-based) of the dh/mdh robot ``ref``'s table, as text."""
    j = ref.joints[k - 1]
    var = j.name
    th = _fmt(j.theta * units.a)
    d = _fmt(j.d * units.l)
    theta = (var + (f" + {th}" if j.theta else "")) if j.revolute else th
    dd = (var + (f" + {d}" if j.d else "")) if not j.revolute else d
    return (f"theta = {theta}, d = {dd}, a = {_fmt(j.a * units.l)}, "
            f"alpha = {_fmt(j.alpha * units.a)}")


def _fold_tool(robot):
    """The standard-DH ``robot`` with a tool of the form Tz(d) Rz(th) Tx(a) Rx(alpha)
    folded into its last row, so that frame n is the tool frame; None if it is not."""
    import dataclasses

    from .spatial import rot_x, rot_z, transform
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


_GRADERS = {"dh": _grade_dh, "link": _grade_link, "fk": _grade_fk, "ik": _grade_ik,
            "jacobian": _grade_jacobian, "reach": _grade_reach, "singular": _grade_singular}
