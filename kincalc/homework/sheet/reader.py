"""Reading a sheet for :mod:`kincalc.homework.sheet`: the file, the robot it names (never
outside the sheet's folder or the robot library), its items and their answers, each
checked with a line number."""

from __future__ import annotations

import math
import os

import numpy as np

from ...conventions.reader import Reader, compose_yaml, node_line
from ...errors import InputError, RobotFileError
from ...limits import MAX_SHEET_ITEMS, cut, quote
from ...spatial import TCV_MAX_ROLL
from .answers import AnswerReader
from .format import (DEFAULT_ANGLE_DEG, DEFAULT_MATRIX, DEFAULT_POSITION, ITEM_KEYS, Item,
                     KINDS, KIND_KEYS, POSE_FIELDS, SHEET_KEYS, Sheet, SheetError,
                     TOLERANCE_KEYS, Tolerance, numeric_items_limit, round1)


# --- reading a sheet -----------------------------------------------------------------

def load_sheet(path: str, robots_dirs=()) -> Sheet:
    """Read and validate the sheet at ``path`` (at most
    :data:`~kincalc.limits.MAX_FILE_BYTES`); raise :class:`SheetError` if invalid.
    ``robots_dirs``: folders besides the sheet's own that its ``robot:`` may name a file
    in (see :func:`sheet_robot_path`)."""
    from ...conventions.reader import read_text
    _regular_only(path)
    text = read_text(path, path, "a sheet", SheetError)
    return parse_sheet(text, path, os.path.dirname(os.path.abspath(path)), robots_dirs)


def _regular_only(path: str) -> None:
    """Refuse, unread, a sheet that is a symbolic link, a FIFO, a device or a socket: a
    student's ``hw.yaml -> key.yaml`` (or ``-> /etc/passwd``) would be graded or quoted,
    and a FIFO would block forever. A missing file or a folder is left to the reader."""
    from ...outputs import special_kind
    if path == "-":                        # standard input
        return
    try:
        kind = special_kind(os.lstat(path).st_mode)
    except (OSError, ValueError):
        return
    if kind is not None:
        raise SheetError(path, None, f"is {kind}, not read: a sheet must be a regular file "
                                     "(no link, no FIFO, no device)")


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
    candidates = [(name, os.sep)] if os.path.isabs(name) else \
        [(os.path.join(b, name), r) for b, r in zip(bases, roots)]
    inside = [c for c, start in candidates if _real_inside(start, name, roots) is not None]
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

    from ...conventions.library import bundled_names
    close = difflib.get_close_matches(name, bundled_names(), n=1)
    where = "in the sheet's folder" + (" or a --robots-dir folder" if robots_dirs else "")
    raise InputError(f"robot {q} is neither a bundled robot nor a file {where}"
                     + (f" (did you mean {close[0]!r}?)" if close else
                        " (see 'kincalc robots list')"))


def _within(path: str, roots) -> bool:
    """Whether the real path ``path`` is one of the real paths ``roots`` or inside one."""
    return any(path == r or path.startswith(r.rstrip(os.sep) + os.sep) for r in roots)


#: symbolic links followed at most in one sheet's robot path (the kernel's own bound)
_MAX_LINKS = 40


def _real_inside(start: str, path: str, roots) -> str | None:
    """The real path of ``path`` taken from the real folder ``start``, or None where it leads
    out of the real paths ``roots``: :func:`os.path.realpath`'s walk, component by component,
    except that nothing outside ``roots`` is asked about (an ancestor of a root is a real
    folder already; a component outside every root ends the walk without a look at it)."""
    todo = [c for c in path.split(os.sep) if c not in ("", ".")][::-1]
    here, links = start, 0
    while todo:
        part = todo.pop()
        if part == "..":
            here = os.path.dirname(here)
            continue
        nxt = os.path.join(here, part)
        if any(r == nxt or r.startswith(nxt.rstrip(os.sep) + os.sep) for r in roots):
            here = nxt                                # on the way to a root: real already
            continue
        if not _within(nxt, roots):
            return None
        if not os.path.islink(nxt):
            here = nxt
            continue
        links += 1
        if links > _MAX_LINKS:
            return None
        target = os.readlink(nxt)
        todo += [c for c in target.split(os.sep) if c not in ("", ".")][::-1]
        here = os.sep if os.path.isabs(target) else here
    return here if _within(here, roots) else None


class _SheetReader(AnswerReader, Reader):
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
        from ...analysis.results import Units
        top = self.document(root, "the sheet", SHEET_KEYS)
        if "kincalc-sheet" in top:
            version = self.text(top["kincalc-sheet"], "'kincalc-sheet'")
            if version.strip() != "1":
                self.fail(top["kincalc-sheet"], f"this kincalc reads sheet format 1, not "
                                                f"{self.shown(top['kincalc-sheet'])}")
        robot = self.robot_ref(top["robot"])
        self.robot_ = robot
        units = {}
        if "units" in top:
            from ...units import ANGLE_UNITS, LENGTH_UNITS
            u = self.mapping(top["units"], "'units'", {"angle": False, "length": False})
            if "angle" in u:
                units["angle"] = self.text(u["angle"], "'units.angle'")
                if units["angle"] not in ANGLE_UNITS:
                    self.fail(u["angle"], f"'units.angle' must be deg or rad, not "
                                          f"{self.shown(u['angle'])}")
            if "length" in u:
                units["length"] = self.text(u["length"], "'units.length'")
                if units["length"] not in LENGTH_UNITS:
                    self.fail(u["length"], f"'units.length' must be one of "
                                           f"{', '.join(LENGTH_UNITS)}, not "
                                           f"{self.shown(u['length'])}")
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
        from ...units import angle_factor, length_factor
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
            position=round1(DEFAULT_POSITION * robot.characteristic_length * self.units.l) * self.L,
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
                self.fail(node, f"id {self.shown(self.plain_keys(node)['id'])} is already "
                                f"used by the item on line {seen[item.id]}")
            seen[item.id] = item.line
            items.append(item)
            self.item = None
        too_many = numeric_items_limit(robot, [item.kind for item in items if not item.lock])
        if too_many:
            self.fail(top["items"], f"'items' has {too_many}")
        return Sheet(path=self.file, robot=robot, units=self.units, tolerance=tol, items=items,
                     title=self.opt_text(top, "title"), student=self.opt_text(top, "student"))

    def opt_text(self, top, key) -> str:
        return self.text(top[key], f"'{key}'").strip() if key in top else ""

    def robot_ref(self, node):
        from ...conventions.library import bundled_names, library_dir
        from ...conventions.reader import RobotReader, load_robot_file
        if self.is_mapping(node):
            self.put_first(node, "name", "sheet-robot")
            reader = RobotReader(self.file)
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
        """The robot file (YAML, or a URDF for a name ending in .urdf) at ``path`` that
        ``robot: NAME`` named. Its content is never
        quoted: the sheet's author may not own it (another student's sheet in the same
        folder, a grader's file), so a problem in it is reported by its line only."""
        from ...conventions.reader import parse_robot_text, read_text
        q = quote(name)
        try:
            text = read_text(path, name, "a robot file")
        except RobotFileError as exc:
            if exc.line is None:        # about the file (size, a folder, unreadable)
                self.fail(node, f"robot {q}: {exc.detail}")
            text = None
            line = exc.line
        if text is not None:
            parse = parse_robot_text
            if name.lower().endswith(".urdf"):        # the URDF's default chain
                from ...conventions.urdf import parse_urdf_text as parse
            try:
                robot = parse(text, name)
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
        # (the id names the item in messages, unless it runs over lines: a message shows
        # nothing of the file but the line it names)
        if "id" in raw and self.is_scalar(raw["id"]) and self.on_one_line(raw["id"]):
            self.item = str(raw["id"].value)
        kind = None
        if "kind" in raw:           # a list or a mapping is no kind either
            kind = raw["kind"].value if self.is_scalar(raw["kind"]) else None
            if kind not in KINDS:
                self.fail(raw["kind"], f"'kind' must be one of {', '.join(KINDS)}, not "
                                       f"{self.kind(raw['kind'])}")
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
        item = dict(id=ident, kind=kind, line=node_line(node), tol=tol, points=points,
                    question=self.text(f["question"], "'question'") if "question" in f else None)
        robot = self.robot_
        if "q" in f:
            item["q"] = self.joints(f["q"], "'q'", allow_one=kind == "link")
        if kind == "link":
            k = self.number(f["link"], "'link'")
            if k != int(k) or not 1 <= k <= robot.dof:
                self.fail(f["link"], f"'link' must be a joint number 1..{robot.dof}, not "
                                     f"{cut(f['link'].value)}")
            item["link"] = link = int(k)
            if item["q"].shape == (1,):          # just q_i: the other joints do not matter
                q = np.zeros(robot.dof)
                q[link - 1] = item["q"][0] * (self.A if robot.is_revolute[link - 1] else self.L)
                item["q"] = q
        if kind == "jacobian" and "frame" in f:
            item["frame"] = self.text(f["frame"], "'frame'").strip()
            if item["frame"] not in ("base", "tool"):
                self.fail(f["frame"], f"'frame' must be base or tool, not {self.shown(f['frame'])}")
        for key in ("tool", "base"):
            if key in f:
                v = self.text(f[key], f"'{key}'").strip()
                if v not in ("compare", "ignore"):
                    self.fail(f[key], f"'{key}' must be compare or ignore, not "
                                      f"{self.shown(f[key])}")
                item[key] = v
        if kind == "ik" and "limits" in f:
            v = self.text(f["limits"], "'limits'").strip()
            if v not in ("respect", "ignore"):
                self.fail(f["limits"], f"'limits' must be respect or ignore, not "
                                       f"{self.shown(f['limits'])}")
            item["limits"] = v == "respect"
        if "lock" in f:
            item["lock"] = self.locks(f["lock"])
        if "pose" in f:
            item["target"] = self.pose_target(f["pose"])
        if "answer" in f and not f["answer"].tag.endswith(":null"):
            item["answer_line"] = node_line(f["answer"])
            item["answer"] = answer = self.answer(kind, f["answer"])
            if kind == "fk" and "tcv" in answer and abs(item["q"][-1]) > TCV_MAX_ROLL:
                # e^(q_n / pi) leaves the numbers a sheet can hold, and soon overflows
                self.fail(f["q"], f"'answer.tcv': the tool configuration vector is given only "
                                  f"for a last joint within {TCV_MAX_ROLL:.1f} rad (ten turns)")
        return Item(**item)

    def locks(self, node) -> tuple:
        """An ik item's ``lock``: joint names (or numbers from 1) and the values they are
        held at, in the sheet's units, as ``((index, value SI), ...)``."""
        robot = self.robot_
        names = [j.name for j in robot.joints]
        entries = self.mapping(node, "'lock'", {**{n: False for n in names},
                                                 **{str(k + 1): False for k in range(robot.dof)}})
        out = {}
        for key, vnode in entries.items():
            k = names.index(key) if key in names else int(key) - 1
            if k in out:
                self.fail(vnode, f"'lock': joint {names[k]} is held twice")
            v = self.number(vnode, f"'lock.{key}'")
            out[k] = v * (self.A if robot.is_revolute[k] else self.L)
        if not out or len(out) >= robot.dof:
            self.fail(node, f"'lock' must hold from 1 to {robot.dof - 1} of the joints of "
                            f"{robot.name}")
        return tuple(sorted(out.items()))

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
        from ...ik import Target
        from ...analysis.requests import to_si
        from ...ik.target import BadTarget, defect_text, target_form, targets_from
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
