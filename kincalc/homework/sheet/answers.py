"""Reading the answers of a sheet's items, by kind, for :mod:`kincalc.homework.sheet`:
yes/no verdicts, joint vectors and sets of them, matrices, poses and DH tables, each
converted to SI and checked with a line number."""

from __future__ import annotations

import numpy as np

from ...conventions.reader import node_line
from ...limits import MAX_EXPRESSION, MAX_IK_SETS


class AnswerReader:
    """The answers of a sheet's items (a mixin of the sheet reader, whose checked numbers,
    lists, ``fail``, ``robot_`` and ``units`` it uses)."""

    def answer(self, kind: str, node):
        robot = self.robot_
        if kind in ("reach", "singular"):
            if not self.is_scalar(node):
                self.fail(node, "'answer' must be yes or no")
            v = str(node.value).strip().lower()
            if v not in ("yes", "no", "true", "false", "y", "n"):
                self.fail(node, f"'answer' must be yes or no, not {self.shown(node)}")
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
            return self.dh_answer(node)
        raise AssertionError(kind)

    def dh_answer(self, node):
        """The student's DH table as a robot, with how each row names its variable."""
        from ...model import Joint, Robot
        f = self.mapping(node, "'answer'", {"convention": True, "table": False, "columns": False,
                                            "joints": False, "base": False, "tool": False,
                                            "name": False})
        conv = self.text(f["convention"], "'answer.convention'").strip()
        if conv not in ("dh", "mdh"):
            self.fail(f["convention"], f"'answer.convention' must be dh or mdh, not "
                                       f"{self.shown(f['convention'])}")
        if ("table" in f) == ("joints" in f):
            self.fail(node, "'answer' needs either 'table' (rows of cells) or 'joints' (mappings)")
        joints, signs, variables = [], [], []
        if "table" in f:
            columns = ["theta", "d", "a", "alpha"] if conv == "dh" else ["alpha", "a", "d", "theta"]
            if "columns" in f:
                cnodes = self.sequence(f["columns"], "'answer.columns'", 4)
                alias = {"θ": "theta", "α": "alpha", "th": "theta"}
                columns = [self.text(c, "'answer.columns' entry").strip() for c in cnodes]
                columns = [alias.get(c, c) for c in columns]
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
                                          f"{self.shown(jf['type'])}")
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
        from ...model import Joint
        found = {}
        for col, cnode in cells.items():
            names = self._names(cnode, f"row {k}, {col}")
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
                                 f"-{var} plus a constant, not {self.shown(cnode)}")
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

    def _names(self, cnode, where: str) -> set:
        """The names in a cell's expression (none for a number; a cell that is no
        expression is said so when it is read as a number)."""
        import ast
        if not hasattr(cnode, "value") or not isinstance(cnode.value, str):
            return set()
        if len(cnode.value) > MAX_EXPRESSION:       # (parsed first, it exhausted the stack)
            self.fail(cnode, f"{where}: expression longer than {MAX_EXPRESSION} characters")
        try:
            tree = ast.parse(cnode.value.strip(), mode="eval")
        except (SyntaxError, ValueError):
            return set()
        except (RecursionError, MemoryError):
            self.fail(cnode, f"{where}: expression nested too deeply")
        return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
