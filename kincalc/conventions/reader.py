"""Robot files (YAML) -> :class:`~kincalc.model.Robot`, with file:line errors.

This is the only module that imports yaml. The format is described in the
README ("Robot files") and in kincalc(5)-style detail in ``man/kincalc.1``.
Every problem is reported as a :class:`~kincalc.errors.RobotFileError` naming
the file, the line and the field, for example::

    arm.yaml:12: joint 3 (q3): 'alpha' is missing

Values are converted to SI (m, rad) here and nowhere else.
"""

from __future__ import annotations

import ast
import difflib
import math
import re

import numpy as np

from ..errors import RobotFileError
# MAX_MAGNITUDE stays importable from here (robot_file.MAX_MAGNITUDE), as it was defined here
from ..limits import (MAX_EXPRESSION, MAX_FILE_BYTES, MAX_MAGNITUDE, TooLarge, cut, os_error_text,
                     quote, read_bounded, size_text)
from ..model import CONVENTIONS, JOINT_TYPES, Joint, Robot
from ..spatial import matrix_from_rpy, transform
from ..units import ANGLE_UNITS, LENGTH_UNITS

TOP_KEYS = {
    "name": True, "convention": True, "units": True, "joints": True,
    "title": False, "source": False, "notes": False, "parameters": False,
    "base": False, "tool": False, "home": False,
}
DH_JOINT_KEYS = {"name": True, "type": True, "alpha": True, "a": True, "d": True,
                 "theta": True, "limits": False}
POE_JOINT_KEYS = {"name": True, "type": True, "axis": True, "point": True, "limits": False}
POSE_KEYS = {"xyz", "rpy", "matrix"}
NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_.\-]*$")


def load_robot_file(path, display_name: str | None = None) -> Robot:
    """Read and validate a robot file.

    Parameters
    ----------
    path : str or os.PathLike
        The YAML file.
    display_name : str, optional
        How to name the file in messages (defaults to ``str(path)``).

    Raises
    ------
    RobotFileError
        Unreadable file, YAML syntax error, or any invalid field.
    """
    shown = display_name or str(path)
    robot = parse_robot_text(read_text(path, shown, "a robot file"), shown)
    object.__setattr__(robot, "path", str(path))
    return robot


def read_text(path, shown: str, what: str, error=RobotFileError,
              limit: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of ``path``, at most ``limit`` bytes of it (read through
    :func:`kincalc.limits.read_bounded`, so an endless device is refused, not read);
    any failure is an ``error(shown, line, message)`` (``what`` names the kind of file,
    e.g. "a robot file"). Only a failure to decode has a line: every other message is
    about the file, never its content."""
    try:
        data = read_bounded(path, limit)
    except TooLarge:
        raise error(shown, None, f"the file is larger than {size_text(limit)}, kincalc's "
                                 f"limit for {what}") from None
    except IsADirectoryError:
        raise error(shown, None, f"is a directory, not {what}") from None
    except OSError as exc:
        reason = os_error_text(exc)
        raise error(shown, None, reason if reason == "no such file" else
                    f"cannot read: {reason}") from None
    except ValueError:                       # a NUL character in the name
        raise error(shown, None, "cannot read: not a valid file name") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise error(shown, line, f"not UTF-8 text (byte 0x{data[exc.start]:02x} "
                                 "cannot be decoded; save the file as UTF-8)") from None


def parse_robot_text(text: str, file: str = "<robot>") -> Robot:
    """Parse the YAML ``text`` of a robot file; ``file`` names it in errors."""
    root = compose_yaml(text, file)
    return Reader(file).robot(root)


# --- YAML with line numbers ----------------------------------------------

def compose_yaml(text: str, file: str):
    """The node tree of the YAML ``text`` (plain tags only, see :func:`_plain_tags`), for
    :class:`Reader`; a RobotFileError naming ``file`` and the line for invalid YAML."""
    import yaml
    loader_cls = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    try:
        node = yaml.compose(text, Loader=loader_cls)
    except yaml.MarkedYAMLError as exc:
        raise RobotFileError(file, *_yaml_error(exc)) from None
    except yaml.reader.ReaderError as exc:
        line = text[:exc.position].count("\n") + 1 if isinstance(exc.position, int) else None
        what = f"#x{exc.character:04x}" if isinstance(exc.character, int) else repr(exc.character)
        raise RobotFileError(file, line, f"not valid YAML: character {what} is not allowed "
                                         "(control characters cannot appear in YAML)") from None
    except yaml.YAMLError as exc:
        raise RobotFileError(file, None, f"not valid YAML: {_one_line(str(exc))[:200]}") from None
    except RecursionError:               # the pure-Python composer on deep nesting
        raise RobotFileError(file, None, "not valid YAML: nested too deeply") from None
    if node is None:
        raise RobotFileError(file, 1, "the file is empty")
    _plain_tags(node, file)
    return node


#: the tags of plain YAML: text, numbers, yes/no, null, lists and mappings
PLAIN_TAGS = {f"tag:yaml.org,2002:{t}" for t in ("str", "int", "float", "bool", "null", "seq",
                                                  "map")}


def _plain_tags(root, file: str):
    """Refuse any other tag (``!!python/object``, ``!!binary``, ``!custom``): nothing is
    ever constructed from one, but a file that has one is not what it looks like. Each
    node is visited once, so an alias bomb costs its text's length, not its size."""
    import yaml
    seen, todo = set(), [root]
    while todo:
        node = todo.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if node.tag not in PLAIN_TAGS:
            tag = node.tag.replace("tag:yaml.org,2002:", "!!")
            raise RobotFileError(file, node_line(node), f"the tag {quote(tag)} is not allowed "
                                 "(kincalc reads plain YAML: text, numbers, lists, mappings)")
        if isinstance(node, yaml.SequenceNode):
            todo.extend(node.value)
        elif isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                todo.extend((k, v))


def _yaml_error(exc) -> tuple[int | None, str]:
    """(line, message) for a PyYAML error, pointing where the user's mistake starts.

    For an unclosed bracket or quote PyYAML reports the place it gave up; the
    construct it was parsing ("while parsing a flow sequence") starts earlier,
    and that line is the one to fix.
    """
    problem = exc.problem or "syntax error"
    pm, cm = exc.problem_mark, exc.context_mark
    context = exc.context or ""
    if context.startswith("while") and ("flow" in context or "quoted" in context) \
            and cm is not None:
        where = f"; found at line {pm.line + 1}" if pm is not None and pm.line != cm.line else ""
        what = context[len("while "):]
        return cm.line + 1, f"not valid YAML: {problem} ({what} that starts here{where})"
    line = (pm or cm).line + 1 if (pm or cm) is not None else None
    text = f"{context}, {problem}" if context else problem
    return line, f"not valid YAML: {text}"


def _one_line(text: str) -> str:
    return " ".join(text.split())


def node_line(node) -> int:
    """The 1-based line where ``node`` starts."""
    return node.start_mark.line + 1


class Reader:
    """Walks the node tree, converting and validating as it goes: the one YAML reader
    with line numbers. Robot files use it as it is; homework sheets
    (:mod:`kincalc.homework.sheet`) subclass it. Callers see nodes only through its methods (no
    other module imports yaml)."""

    def __init__(self, file: str):
        self.file = file
        self.params: dict[str, float] = {}
        self.A = 1.0
        self.joint: int | None = None
        self.joint_name: str | None = None
        self.exprs: list[tuple] = []

    # errors --------------------------------------------------------------
    def fail(self, node, message: str):
        line = node_line(node) if node is not None else None
        raise RobotFileError(self.file, line, message, self.joint, self.joint_name)

    # node kinds ----------------------------------------------------------
    def mapping(self, node, what: str, keys: dict[str, bool]) -> dict:
        import yaml
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, f"{what} must be a mapping (key: value), not {self.kind(node)}")
        out: dict = {}
        for knode, vnode in node.value:
            key = knode.value if isinstance(knode, yaml.ScalarNode) else None
            if key is None:
                self.fail(knode, f"{what}: keys must be plain names")
            if key in out:
                self.fail(knode, f"{what}: {quote(key)} is given twice")
            if key not in keys:
                close = difflib.get_close_matches(key, list(keys), n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else \
                    f" (allowed: {', '.join(keys)})"
                self.fail(knode, f"unknown key {quote(key)} in {what}{hint}")
            out[key] = vnode
        for key, required in keys.items():
            if required and key not in out:
                self.fail(node, f"{key!r} is missing"
                          + ("" if what in ("the robot file", "the joint") else f" in {what}"))
        return out

    @staticmethod
    def is_mapping(node) -> bool:
        import yaml
        return isinstance(node, yaml.MappingNode)

    @staticmethod
    def is_scalar(node) -> bool:
        import yaml
        return isinstance(node, yaml.ScalarNode)

    @staticmethod
    def is_sequence(node) -> bool:
        import yaml
        return isinstance(node, yaml.SequenceNode)

    @staticmethod
    def plain_keys(node) -> dict:
        """``{key: value node}`` of a mapping node's plain-text keys (others skipped, the
        last of repeated keys kept), without validation: for a first look at a mapping
        whose checks depend on one of its entries."""
        return {k.value: v for k, v in node.value if Reader.is_scalar(k)}

    def names(self, node, what: str):
        """``(name, value node)`` of each entry of a mapping of plain names, in order (an
        entry whose key is not a plain name fails when it is reached)."""
        if not self.is_mapping(node):
            self.fail(node, f"{what} must be a mapping of names to numbers")
        for knode, vnode in node.value:
            if not self.is_scalar(knode):
                self.fail(knode, f"{what}: keys must be plain names")
            yield knode.value, vnode

    @staticmethod
    def put_first(node, key: str, value: str) -> None:
        """Give the mapping ``node`` the text entry ``key: value`` first, unless it has
        ``key`` (for a default the reader should treat as written)."""
        import yaml
        if any(k.value == key for k, _ in node.value):
            return
        mark = node.start_mark
        node.value.insert(0, (yaml.ScalarNode("tag:yaml.org,2002:str", key, mark, mark),
                              yaml.ScalarNode("tag:yaml.org,2002:str", value, mark, mark)))

    @staticmethod
    def kind(node) -> str:
        import yaml
        if isinstance(node, yaml.MappingNode):
            return "a mapping"
        if isinstance(node, yaml.SequenceNode):
            return "a list"
        return quote(node.value) if node.value != "" else "empty"

    def sequence(self, node, what: str, length: int | None = None) -> list:
        import yaml
        if not isinstance(node, yaml.SequenceNode):
            self.fail(node, f"{what} must be a list, not {self.kind(node)}")
        if length is not None and len(node.value) != length:
            self.fail(node, f"{what} must have {length} entries, not {len(node.value)}")
        return node.value

    def text(self, node, what: str) -> str:
        import yaml
        if not isinstance(node, yaml.ScalarNode) or node.tag.endswith(":null"):
            self.fail(node, f"{what} must be text, not {self.kind(node) if not isinstance(node, yaml.ScalarNode) else 'empty'}")
        return str(node.value)

    def number(self, node, what: str) -> float:
        """A number or an arithmetic expression over ``parameters`` and ``pi``."""
        import yaml
        if not isinstance(node, yaml.ScalarNode):
            self.fail(node, f"{what} must be a number, not {self.kind(node)}")
        tag = node.tag.rsplit(":", 1)[-1]
        if tag in ("int", "float"):
            try:
                value = float(node.value.replace("_", ""))
            except ValueError:
                value = self.expression(node, what)
            except OverflowError:
                self.fail(node, f"{what} is too large a number: {quote(node.value)}")
        elif tag == "bool":
            self.fail(node, f"{what} must be a number, not {quote(node.value)}")
        elif tag == "null" or node.value.strip() == "":
            self.fail(node, f"{what} is empty; give a number")
        else:
            value = self.expression(node, what)
        if not math.isfinite(value):
            self.fail(node, f"{what} must be a finite number, not {quote(node.value)}")
        if abs(value) > MAX_MAGNITUDE:
            self.fail(node, f"{what} is too large: {quote(node.value)} (kincalc takes numbers "
                            f"up to {MAX_MAGNITUDE:g} in size)")
        return value

    def expression(self, node, what: str) -> float:
        src = node.value
        if len(src) > MAX_EXPRESSION:
            self.fail(node, f"{what}: expression longer than {MAX_EXPRESSION} characters")
        try:
            tree = ast.parse(src.strip(), mode="eval")
        except SyntaxError:
            self.fail(node, f"{what} must be a number or an expression like 'l1 + 0.1', "
                            f"not {quote(src)}")
        except (RecursionError, MemoryError, ValueError):
            self.fail(node, f"{what}: expression too deeply nested")
        try:
            return float(self._eval(tree.body))
        except _ExprError as exc:
            self.fail(node, f"{what}: {exc} in {quote(src)}")
        except ZeroDivisionError:
            self.fail(node, f"{what}: division by zero in {quote(src)}")
        except OverflowError:
            self.fail(node, f"{what}: number too large in {quote(src)}")
        except RecursionError:
            self.fail(node, f"{what}: expression too deeply nested")

    def _eval(self, e):
        if isinstance(e, ast.Constant) and isinstance(e.value, (int, float)) \
                and not isinstance(e.value, bool):
            return e.value
        if isinstance(e, ast.Name):
            if e.id == "pi":
                if self.A != 1.0:
                    raise _ExprError("'pi' is only allowed in files with angle: rad "
                                     "(this file's angles are in degrees: write 180 for pi)")
                return math.pi
            if e.id in self.params:
                return self.params[e.id]
            names = sorted(self.params)
            known = ", ".join(cut(n) for n in names[:10]) + (
                f", ... ({len(names)} in all)" if len(names) > 10 else "") or "none defined"
            raise _ExprError(f"unknown name {quote(e.id)} (parameters: {known})")
        if isinstance(e, ast.UnaryOp) and isinstance(e.op, (ast.USub, ast.UAdd)):
            v = self._eval(e.operand)
            return -v if isinstance(e.op, ast.USub) else v
        if isinstance(e, ast.BinOp) and isinstance(e.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
            a, b = self._eval(e.left), self._eval(e.right)
            if isinstance(e.op, ast.Add):
                return a + b
            if isinstance(e.op, ast.Sub):
                return a - b
            if isinstance(e.op, ast.Mult):
                return a * b
            return a / b
        raise _ExprError("only numbers, parameter names, pi, + - * / and parentheses are allowed")

    def vector(self, node, what: str, length: int) -> np.ndarray:
        items = self.sequence(node, what, length)
        return np.array([self.number(v, f"{what}[{k}]") for k, v in enumerate(items)])

    # the robot -----------------------------------------------------------
    def robot(self, root) -> Robot:
        top = self.mapping(root, "the robot file", TOP_KEYS)
        name = self.text(top["name"], "'name'")
        if not name.strip():
            self.fail(top["name"], "'name' must not be empty")
        if not NAME_RE.match(name):
            self.fail(top["name"], f"'name' {quote(name)} must start with a letter (A-Z, a-z) and "
                                   "contain only such letters, digits, '_', '-' and '.'")
        convention = self.text(top["convention"], "'convention'")
        if convention not in CONVENTIONS:
            self.fail(top["convention"], f"'convention' must be one of {', '.join(CONVENTIONS)} "
                                         "(dh = standard, mdh = modified/Craig), not "
                                         f"{quote(convention)}")
        units = self.mapping(top["units"], "'units'", {"length": True, "angle": True})
        length_unit = self.text(units["length"], "'units.length'")
        if length_unit not in LENGTH_UNITS:
            self.fail(units["length"], f"'units.length' must be one of {', '.join(LENGTH_UNITS)}, "
                                       f"not {quote(length_unit)}")
        angle_unit = self.text(units["angle"], "'units.angle'")
        if angle_unit not in ANGLE_UNITS:
            self.fail(units["angle"], f"'units.angle' must be one of {', '.join(ANGLE_UNITS)}, "
                                      f"not {quote(angle_unit)}")
        self.L = LENGTH_UNITS[length_unit]
        self.A = ANGLE_UNITS[angle_unit]

        if "parameters" in top:
            self.read_parameters(top["parameters"])

        joints = self.joint_list(top["joints"], convention)

        base = self.pose(top["base"], "'base'") if "base" in top else np.eye(4)
        if convention == "poe" and "tool" not in top:
            self.fail(root, "'tool' is missing: a poe robot needs the tool pose at q = 0 (M)")
        tool = self.pose(top["tool"], "'tool'") if "tool" in top else np.eye(4)

        home = self.home_values(top["home"], joints) if "home" in top else None

        def opt_text(key):
            return self.text(top[key], f"'{key}'").strip() if key in top else ""

        return Robot(
            name=name, convention=convention, joints=tuple(joints), base=base, tool=tool,
            home=home, title=opt_text("title"), source=opt_text("source"),
            notes=opt_text("notes"), length_unit=length_unit, angle_unit=angle_unit,
            parameters=tuple(self.params.items()),
            expressions=tuple(self.exprs) if convention != "poe" else (),
        )

    def read_parameters(self, pnode) -> None:
        """The file's ``parameters`` (name -> number, in the file's units) into
        ``self.params``, for the expressions of the joints' entries."""
        import yaml
        if not isinstance(pnode, yaml.MappingNode):
            self.fail(pnode, "'parameters' must be a mapping of names to numbers")
        for knode, vnode in pnode.value:
            if not isinstance(knode, yaml.ScalarNode):
                self.fail(knode, "'parameters': keys must be plain names")
            pname = knode.value
            if not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", pname) or pname == "pi":
                self.fail(knode, f"parameter name {quote(pname)} must be an identifier "
                                 "other than 'pi'")
            if pname in self.params:
                self.fail(knode, f"parameter {quote(pname)} is given twice")
            self.params[pname] = self.number(vnode, f"parameter {quote(pname)}")

    def joint_list(self, node, convention: str) -> list:
        """The ``joints`` entries, in order, each with a name no other joint has."""
        jnodes = self.sequence(node, "'joints'")
        if not jnodes:
            self.fail(node, "'joints' is empty; a robot needs at least one joint")
        joints = []
        seen: dict[str, int] = {}
        for k, jnode in enumerate(jnodes, start=1):
            self.joint, self.joint_name = k, None
            joint = self.joint_entry(jnode, convention)
            if joint.name in seen:
                self.fail(jnode, f"name {quote(joint.name)} is already used by joint "
                                 f"{seen[joint.name]}")
            seen[joint.name] = k
            joints.append(joint)
        self.joint, self.joint_name = None, None
        return joints

    def home_values(self, hnode, joints) -> np.ndarray:
        """The ``home`` joint values (SI), one per joint, each within its limits."""
        items = self.sequence(hnode, "'home'")
        if len(items) != len(joints):
            self.fail(hnode, f"'home' has {len(items)} values but the robot has {len(joints)} joints")
        home = np.empty(len(joints))
        for k, (v, j) in enumerate(zip(items, joints)):
            home[k] = self.number(v, f"'home'[{k}]") * (self.A if j.revolute else self.L)
            if j.limits is not None and not (j.limits[0] - 1e-12 <= home[k] <= j.limits[1] + 1e-12):
                self.fail(v, f"'home' value for joint {k + 1} ({j.name}) is outside its limits")
        return home

    def joint_entry(self, node, convention: str) -> Joint:
        import yaml
        keys = POE_JOINT_KEYS if convention == "poe" else DH_JOINT_KEYS
        if isinstance(node, yaml.MappingNode):
            for knode, vnode in node.value:
                if knode.value == "name" and isinstance(vnode, yaml.ScalarNode):
                    self.joint_name = cut(vnode.value)
        fields = self.mapping(node, "the joint", keys)
        name = self.text(fields["name"], "'name'")
        if not name.strip():
            self.fail(fields["name"], "'name' must not be empty")
        jtype = self.text(fields["type"], "'type'")
        if jtype not in JOINT_TYPES:
            self.fail(fields["type"], f"'type' must be revolute or prismatic, not {quote(jtype)}")
        revolute = jtype == "revolute"
        limits = None
        if "limits" in fields:
            lo, hi = self.vector(fields["limits"], "'limits'", 2) * (self.A if revolute else self.L)
            if lo > hi:
                self.fail(fields["limits"], "'limits' must be [lower, upper] with lower <= upper")
            limits = (float(lo), float(hi))
        if convention == "poe":
            axis = self.vector(fields["axis"], "'axis'", 3)
            norm = float(np.linalg.norm(axis))
            if norm < 1e-9:
                self.fail(fields["axis"], "'axis' must not be the zero vector")
            if abs(norm - 1.0) > 1e-6:
                self.fail(fields["axis"], f"'axis' must be a unit vector (its norm is {norm:.6g})")
            point = self.vector(fields["point"], "'point'", 3) * self.L
            return Joint(name=name, type=jtype, axis=tuple(axis / norm), point=tuple(point),
                         limits=limits)
        self.exprs.append(tuple(
            (key, fields[key].value.strip()) for key in ("alpha", "a", "d", "theta")
            if isinstance(fields[key], yaml.ScalarNode)
            and fields[key].tag.rsplit(":", 1)[-1] not in ("int", "float")))
        return Joint(
            name=name, type=jtype,
            alpha=self.number(fields["alpha"], "'alpha'") * self.A,
            a=self.number(fields["a"], "'a'") * self.L,
            d=self.number(fields["d"], "'d'") * self.L,
            theta=self.number(fields["theta"], "'theta'") * self.A,
            limits=limits,
        )

    def pose(self, node, what: str) -> np.ndarray:
        """``base`` or ``tool``: ``{xyz, rpy}``, ``{matrix: [4 rows]}`` or the 4x4 matrix
        itself (a list of 4 rows, as PRODUCT.md allows)."""
        import yaml
        if isinstance(node, yaml.SequenceNode):     # the bare matrix
            matrix, mwhat = node, f"{what} (a 4x4 matrix)"
        else:
            fields = self.mapping(node, what, {k: False for k in POSE_KEYS})
            matrix, mwhat = fields.get("matrix"), f"{what}.matrix"
            if matrix is not None and ("xyz" in fields or "rpy" in fields):
                self.fail(node, f"{what}: give either 'matrix' or 'xyz'/'rpy', not both")
        if matrix is not None:
            rows = self.sequence(matrix, mwhat, 4)
            M = np.array([self.vector(r, f"{mwhat} row {k + 1}", 4)
                          for k, r in enumerate(rows)])
            if not np.allclose(M[3], [0, 0, 0, 1], atol=1e-9):
                self.fail(matrix, f"{mwhat}: the last row must be [0, 0, 0, 1]")
            R = M[:3, :3]
            if not np.allclose(R @ R.T, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0:
                self.fail(matrix, f"{mwhat}: the upper-left 3x3 block is not a "
                                  "rotation (orthonormal, determinant +1)")
            M = M.copy()
            M[:3, 3] *= self.L
            # re-orthonormalise the rotation given to 6 digits
            u, _, vt = np.linalg.svd(R)
            M[:3, :3] = u @ vt
            return M
        xyz = self.vector(fields["xyz"], f"{what}.xyz", 3) * self.L if "xyz" in fields else np.zeros(3)
        rpy = self.vector(fields["rpy"], f"{what}.rpy", 3) * self.A if "rpy" in fields else np.zeros(3)
        return transform(matrix_from_rpy(rpy), xyz)


class _ExprError(Exception):
    pass
