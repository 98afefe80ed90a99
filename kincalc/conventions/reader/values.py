"""The one YAML reader with line numbers, part two: :class:`Reader` reads the values of
the nodes (numbers, expressions over the file's parameters, vectors, poses), converting
them to SI with ``file:line`` errors. The robot-file reader
(:class:`~.robot_file.RobotReader`) and the homework sheets'
(:mod:`kincalc.homework.sheet`) subclass it.
"""

from __future__ import annotations

import ast
import math

import numpy as np

from ...limits import DECIMAL, MAX_EXPRESSION, MAX_MAGNITUDE, cut, parse_decimal, quote
from ...spatial import is_rotation, matrix_from_rpy, nearest_rotations, transform
from .nodes import NodeReader

POSE_KEYS = ("xyz", "rpy", "matrix")          # (in this order in messages)


class Reader(NodeReader):
    """:class:`~.nodes.NodeReader` with values: the one YAML reader with line numbers."""

    def number(self, node, what: str) -> float:
        """A number or an arithmetic expression over ``parameters`` and ``pi``.

        Parameters
        ----------
        node : yaml.Node
            The scalar.
        what : str
            How to name it in messages.

        Returns
        -------
        float
            In the file's units, not converted to SI (the caller multiplies by ``L`` or
            ``A``).

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Not a scalar, yes/no, empty, an invalid expression
            (:meth:`expression`), not finite, or larger than ``MAX_MAGNITUDE`` in magnitude.
        """
        import yaml
        if not isinstance(node, yaml.ScalarNode):
            self.fail(node, f"{what} must be a number, not {self.kind(node)}")
        tag = node.tag.rsplit(":", 1)[-1]
        if tag in ("int", "float"):
            try:       # decimal, as on the command line (YAML 1.1 would take 1_000 and 0x10)
                value = parse_decimal(node.value.strip())
            except ValueError:
                value = self.expression(node, what)
            except OverflowError:
                self.fail(node, f"{what} is too large a number: {self.shown(node)}")
        elif tag == "bool":
            self.fail(node, f"{what} must be a number, not {self.shown(node)}")
        elif tag == "null" or node.value.strip() == "":
            self.fail(node, f"{what} is empty; give a number")
        else:
            value = self.expression(node, what)
        if not math.isfinite(value):
            self.fail(node, f"{what} must be a finite number, not {self.shown(node)}")
        if abs(value) > MAX_MAGNITUDE:
            self.fail(node, f"{what} is too large: {self.shown(node)} (kincalc takes numbers "
                            f"up to {MAX_MAGNITUDE:g} in size)")
        return value

    def expression(self, node, what: str) -> float:
        """The value of an arithmetic expression: numbers, parameter names, ``pi`` (files
        with angles in rad only), ``+ - * /`` and parentheses.

        Parameters
        ----------
        node : yaml.ScalarNode
            The expression's text.
        what : str
            How to name it in messages.

        Returns
        -------
        float
            In the file's units (parameters are in them too); not checked to be finite.

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Longer than ``MAX_EXPRESSION`` characters, over more
            than one line, not an expression, anything else in it, an unknown name,
            ``pi`` in a file in degrees, a division by zero, an overflow, nesting too
            deep.
        """
        src = node.value
        if len(src) > MAX_EXPRESSION:
            self.fail(node, f"{what}: expression longer than {MAX_EXPRESSION} characters")
        first, last = self.lines(node)
        if last > first:        # its message would quote lines other than the one it names
            self.fail(node, f"{what} must be a number or an expression on one line, not "
                            f"{self.shown(node)}")
        src = src.strip()
        try:
            tree = ast.parse(src, mode="eval")
        except SyntaxError as exc:          # (Python's parser stops at 200 parentheses deep)
            if "nested" in str(exc.msg):
                self.fail(node, f"{what}: expression too deeply nested")
            self.fail(node, f"{what} must be a number or an expression like 'l1 + 0.1', "
                            f"not {self.shown(node)}")
        except (RecursionError, MemoryError, ValueError):
            self.fail(node, f"{what}: expression too deeply nested")
        for part in ast.walk(tree):        # Python's literals (0x10, 1_0, 0o7) are no numbers
            if isinstance(part, ast.Name) and not src.isascii():
                # Python reads a name in NFKC form: the ligature 'ﬁ' as fi, fullwidth 'ｐｉ' as pi
                text = ast.get_source_segment(src, part) or ""
                if text != part.id:
                    self.fail(node, f"{what}: unknown name {quote(text)} in "
                                    f"{self.shown(node)}")
            if not isinstance(part, ast.Constant):
                continue
            text = ast.get_source_segment(src, part) or ""
            if not DECIMAL.fullmatch(text):
                whole = "" if text == src else f", in {self.shown(node)}"
                self.fail(node, f"{what}: {quote(text)} is not a decimal number{whole}")
        try:
            return float(self._eval(tree.body))
        except _ExprError as exc:
            self.fail(node, f"{what}: {exc} in {self.shown(node)}")
        except ZeroDivisionError:
            self.fail(node, f"{what}: division by zero in {self.shown(node)}")
        except OverflowError:
            self.fail(node, f"{what}: number too large in {self.shown(node)}")
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
                f", ... ({len(names)} in all)" if len(names) > 10 else "")
            # (a parameter may use those above it: {l1: l2, l2: 1} names l2 too early)
            raise _ExprError(f"unknown name {quote(e.id)} ("
                             + (f"parameters known here: {known})" if known else
                                "no parameter is known here: a parameter may use only "
                                "those before it)"))
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
        """A list of ``length`` numbers (:meth:`number`).

        Parameters
        ----------
        node : yaml.Node
            The list.
        what : str
            How to name it in messages (an item is ``what[k]``).
        length : int
            The number of items it must have.

        Returns
        -------
        ndarray (length,)
            In the file's units, not converted to SI.

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) As :meth:`sequence` and :meth:`number`.
        """
        items = self.sequence(node, what, length)
        return np.array([self.number(v, f"{what}[{k}]") for k, v in enumerate(items)])

    # the robot -----------------------------------------------------------
    def pose(self, node, what: str) -> np.ndarray:
        """``base`` or ``tool``: ``{xyz, rpy}``, ``{matrix: [4 rows]}`` or the 4x4 matrix
        itself (a list of 4 rows, as PRODUCT.md allows).

        Uses ``self.L`` (m per file length unit, set by the subclass) and ``self.A`` (rad
        per file angle unit). A missing ``xyz`` or ``rpy`` is zero.

        Parameters
        ----------
        node : yaml.Node
            The pose entry.
        what : str
            How to name it in messages (``"'base'"``).

        Returns
        -------
        ndarray (4, 4)
            The pose as written, in SI: translation in m; ``rpy`` (fixed X-Y-Z,
            ``R = Rz(yaw) Ry(pitch) Rx(roll)``) converted to rad; a matrix's rotation
            re-orthonormalised (by SVD). For a robot file, ``base`` is
            ``T_world_0`` and ``tool`` is ``T_flange_tool`` (dh/mdh) or ``M`` (poe).

        Raises
        ------
        RobotFileError
            (By :meth:`fail`.) Both ``matrix`` and ``xyz``/``rpy``, an unknown key, a
            last row other than ``[0, 0, 0, 1]`` (to 1e-9), a 3x3 block that is not a
            rotation (orthonormal to 1e-6, determinant +1), or as :meth:`vector`.
        """
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
            if not is_rotation(M[:3, :3]):
                self.fail(matrix, f"{mwhat}: the upper-left 3x3 block is not a "
                                  "rotation (orthonormal, determinant +1)")
            M = M.copy()
            M[:3, 3] *= self.L
            M[:3, :3] = nearest_rotations(M[:3, :3])       # one given to 6 digits
            return M
        xyz = self.vector(fields["xyz"], f"{what}.xyz", 3) * self.L if "xyz" in fields else np.zeros(3)
        rpy = self.vector(fields["rpy"], f"{what}.rpy", 3) * self.A if "rpy" in fields else np.zeros(3)
        return transform(matrix_from_rpy(rpy), xyz)


class _ExprError(Exception):
    pass
