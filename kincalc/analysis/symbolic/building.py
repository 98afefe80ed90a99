"""The derivations of :mod:`kincalc.analysis.symbolic`: link transforms, forward
kinematics and Jacobian columns built from a robot, in sympy."""

from __future__ import annotations

import ast
import math

from ...errors import InputError
from .results import Notation, SymbolicFK, SymbolicJacobian
from .simplify import Abbreviations, collapse, nest
from .symbols import exact, exact_angle, exact_unit, joint_symbols, require_sympy


def symbolic_fk(robot, numeric_lengths: bool = False, length_unit: str | None = None) -> SymbolicFK:
    """Symbolic ``T_{i-1}^i``, base, tool and ``T_world_tool`` of ``robot``.

    Parameters
    ----------
    robot : Robot
    numeric_lengths : bool
        Replace the file's parameters by their values.
    length_unit : str, optional
        Unit of the lengths in the result (default: the robot file's). Only
        with ``numeric_lengths`` may it differ from the file's unit, since the
        parameters' symbols stand for values in the file's unit.

    Raises
    ------
    MissingExtra
        sympy is not installed.
    InputError
        ``length_unit`` differs from the file's unit without ``numeric_lengths``.
    """
    b = _Builder(robot, numeric_lengths, length_unit, "kincalc fk --symbolic")
    links = tuple(b.link(i) for i in range(robot.dof))
    T = b.product(b.segments())
    base = None if _is_identity(robot.base) else b.pose(robot.base)
    tool = None if _is_identity(robot.written_tool) else b.pose(robot.written_tool)
    mats = b.finish([*links, base, tool, T])
    return SymbolicFK(robot=robot, links=tuple(mats[:-3]), base=mats[-3], tool=mats[-2],
                      T=mats[-1], notation=b.notation(), length_unit=b.unit,
                      numeric_lengths=numeric_lengths)


def symbolic_jacobian(robot, frame: str = "base", numeric_lengths: bool = False,
                      length_unit: str | None = None) -> SymbolicJacobian:
    """Symbolic geometric Jacobian ``(6, n)`` of ``robot`` in the base or tool frame.

    Column i is ``[R_G (ω_i × (t_Q - p_i)); R_G ω_i]`` (revolute) or
    ``[R_G ω_i; 0]`` (prismatic), where ``T_world_tool = G_i · Q_i`` splits the
    chain just before joint i's motion, ``ω_i`` and ``p_i`` are joint i's axis
    and a point on it in frame ``G_i``, ``R_G`` is the rotation of ``G_i`` and
    ``t_Q`` the translation of ``Q_i``. In the tool frame ``R_G`` becomes
    ``R_Q^T``. Both keep every entry multilinear in the joints' sines and
    cosines. Parameters and errors as :func:`symbolic_fk`.
    """
    if frame not in ("base", "tool"):
        raise ValueError(f"frame must be 'base' or 'tool', not {frame!r}")
    b = _Builder(robot, numeric_lengths, length_unit, "kincalc jacobian --symbolic")
    sp = b.sp
    segs = b.segments()
    prefix = [sp.eye(4)]
    for S in segs:
        prefix.append(b.mul(prefix[-1], S))
    suffix = [sp.eye(4)]
    for S in reversed(segs):
        suffix.append(b.mul(S, suffix[-1]))
    suffix.reverse()                         # suffix[k] = segs[k] ··· segs[-1]
    cols = []
    for i, joint in enumerate(robot.joints):
        k, w, p = b.split[i]
        G, Q = prefix[k], suffix[k]
        R = G[:3, :3] if frame == "base" else Q[:3, :3].T
        if joint.revolute:
            v = w.cross(Q[:3, 3] - p)
            col = list(R * v) + list(R * w)
        else:
            col = list(R * w) + [0, 0, 0]
        cols.append([b.simplify(e) for e in col])
    J = sp.Matrix(6, robot.dof, lambda r, c: cols[c][r])
    (J,) = b.finish([J])
    return SymbolicJacobian(robot=robot, frame=frame, J=J, notation=b.notation(),
                            length_unit=b.unit, numeric_lengths=numeric_lengths)


def _is_identity(T) -> bool:
    import numpy as np
    return bool(np.allclose(T, np.eye(4), rtol=0, atol=1e-15))


class _Builder:
    """Turns a Robot into exact sympy matrices and simplifies their products."""

    def __init__(self, robot, numeric_lengths: bool, length_unit: str | None, command: str):
        from ...limits import MAX_SYMBOLIC_JOINTS
        from ...units import LENGTH_UNITS
        if robot.dof > MAX_SYMBOLIC_JOINTS:
            raise InputError(f"{command}: {robot.name} has {robot.dof} joints; symbolic "
                             f"expressions are expanded for up to {MAX_SYMBOLIC_JOINTS} "
                             "joints (they grow about 1.7 times a joint)")
        sp = self.sp = require_sympy(command)
        self.robot = robot
        self.numeric = numeric_lengths
        file_unit = robot.length_unit
        self.unit = length_unit or file_unit
        if self.unit not in LENGTH_UNITS:
            raise InputError(f"unknown length unit {self.unit!r}")
        if self.unit != file_unit and not numeric_lengths:
            raise InputError(f"symbolic lengths are in the robot file's unit ({file_unit}); "
                             f"add --numeric-lengths to show lengths in {self.unit}")
        self.L_file = LENGTH_UNITS[file_unit]                       # m per file unit
        self.k = exact(LENGTH_UNITS[file_unit], sp) / exact(LENGTH_UNITS[self.unit], sp)
        # rad per file angle unit, exact (expressions are in the file's unit)
        self.A = sp.pi / 180 if robot.angle_unit == "deg" else sp.Integer(1)
        self.q = joint_symbols(robot, sp)
        self.index = {s: i + 1 for i, s in enumerate(self.q)}
        self.param_symbols = {name: sp.Symbol(name, real=True) for name, _ in robot.parameters}
        self.param_values = {name: exact(v, sp) for name, v in robot.parameters}
        self.used: dict[str, object] = {}
        self.split: list = []
        exprs = tuple(robot.expressions)
        self.exprs = [dict(e) for e in exprs] if len(exprs) == robot.dof else \
            [{} for _ in robot.joints]

    # numbers -----------------------------------------------------------------
    def length(self, si: float):
        return exact(si / self.L_file, self.sp) * self.k

    def angle(self, rad: float):
        return exact_angle(rad, self.sp)

    def field(self, i: int, key: str):
        """Joint i's DH field ``key`` as an exact expression (rad / display length)."""
        joint = self.robot.joints[i]
        si = getattr(joint, key)
        is_angle = key in ("alpha", "theta")
        src = self.exprs[i].get(key)
        if src is not None:
            value = self._parse(src)
            if value is not None:
                value = value * (self.A if is_angle else self.k)
                # Trust the source text only if it evaluates to what the robot holds.
                check = value.xreplace({self.param_symbols[n]: self.param_values[n]
                                        for n in self.param_symbols})
                target = si if is_angle else si / self.L_file * float(self.k)
                if abs(float(check) - target) <= 1e-9 * max(1.0, abs(target)):
                    if self.numeric:
                        return check
                    for s in value.free_symbols:
                        self.used[str(s)] = s
                    return value
        return self.angle(si) if is_angle else self.length(si)

    def _parse(self, src: str):
        sp = self.sp
        try:
            tree = ast.parse(src, mode="eval").body
        except SyntaxError:
            return None

        def walk(e):
            if isinstance(e, ast.Constant) and isinstance(e.value, (int, float)) \
                    and not isinstance(e.value, bool):
                return exact(e.value, sp)
            if isinstance(e, ast.Name):
                if e.id == "pi":
                    return sp.pi
                if e.id in self.param_symbols:
                    return self.param_symbols[e.id]
                raise ValueError(e.id)
            if isinstance(e, ast.UnaryOp) and isinstance(e.op, (ast.USub, ast.UAdd)):
                v = walk(e.operand)
                return -v if isinstance(e.op, ast.USub) else v
            if isinstance(e, ast.BinOp) and isinstance(e.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
                a, b = walk(e.left), walk(e.right)
                if isinstance(e.op, ast.Add):
                    return a + b
                if isinstance(e.op, ast.Sub):
                    return a - b
                return a * b if isinstance(e.op, ast.Mult) else a / b
            raise ValueError(type(e).__name__)

        try:
            return sp.sympify(walk(tree))
        except (ValueError, ZeroDivisionError, RecursionError):
            return None

    def pose(self, T):
        """An exact sympy matrix for a numeric pose ``T (4, 4)`` (SI)."""
        sp = self.sp
        M = sp.eye(4)
        for r in range(3):
            for c in range(3):
                M[r, c] = exact_unit(float(T[r, c]), sp)
            M[r, 3] = self.length(float(T[r, 3]))
        return M

    # elementary transforms ---------------------------------------------------
    def rot(self, axis: str, t, held: float | None = None):
        """The rotation about ``axis`` by ``t``; ``held``: the angle (rad) the robot holds,
        when ``t`` is a constant that stands for it."""
        sp = self.sp
        c, s = sp.cos(t), sp.sin(t)
        if not t.free_symbols and (c.has(sp.cos, sp.sin) or s.has(sp.cos, sp.sin)):
            # a constant angle without a closed form (1°): its sine and cosine as decimals,
            # of the angle held (t may be its 12 digits: a cosine of 1.7e-9 then had 3)
            if held is not None:
                c, s = math.cos(held), math.sin(held)
            c, s = exact(float(c), sp), exact(float(s), sp)
        R = {"x": [[1, 0, 0], [0, c, -s], [0, s, c]],
             "z": [[c, -s, 0], [s, c, 0], [0, 0, 1]]}[axis]
        M = sp.eye(4)
        M[:3, :3] = sp.Matrix(R)
        return M

    def trans(self, x=0, y=0, z=0):
        M = self.sp.eye(4)
        M[0, 3], M[1, 3], M[2, 3] = x, y, z
        return M

    def dh_parts(self, i: int):
        """``(before, motion, after)`` of joint i's link transform (dh/mdh)."""
        joint = self.robot.joints[i]
        alpha, a = self.field(i, "alpha"), self.field(i, "a")
        theta, d = self.field(i, "theta"), self.field(i, "d")
        if joint.revolute:
            theta = theta + self.q[i]
        else:
            d = d + self.q[i]
        motion = self.rot("z", theta) * self.trans(z=d)
        fixed = self.trans(x=a) * self.rot("x", alpha, held=joint.alpha)
        if self.robot.convention == "dh":
            return self.sp.eye(4), motion, fixed
        return fixed, motion, self.sp.eye(4)

    def poe_axis(self, i: int):
        sp = self.sp
        joint = self.robot.joints[i]
        w = sp.Matrix([exact_unit(float(x), sp) for x in joint.axis])
        p = sp.Matrix([self.length(float(x)) for x in joint.point])
        return w, p

    def poe_exp(self, i: int):
        """``exp([S_i] q_i)`` (Rodrigues; package docstring)."""
        sp = self.sp
        w, p = self.poe_axis(i)
        q = self.q[i]
        M = sp.eye(4)
        if self.robot.joints[i].revolute:
            W = sp.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
            R = sp.eye(3) + sp.sin(q) * W + (1 - sp.cos(q)) * W * W
            M[:3, :3] = R
            M[:3, 3] = (sp.eye(3) - R) * p
        else:
            M[:3, 3] = w * q
        return M.applyfunc(sp.expand)

    def segments(self) -> list:
        """The chain as a list of matrices whose product is ``T_world_tool``.

        Also fills ``self.split``: for joint i, ``(k, ω, p)`` with the chain
        split before joint i's motion at segment k.
        """
        robot = self.robot
        segs = [self.pose(robot.base)]
        self.split = []
        ez, o = self.sp.Matrix([0, 0, 1]), self.sp.Matrix([0, 0, 0])
        for i in range(robot.dof):
            if robot.convention == "poe":
                w, p = self.poe_axis(i)
                self.split.append((len(segs), w, p))
                segs.append(self.poe_exp(i))
                continue
            before, motion, after = self.dh_parts(i)
            segs.append(before)
            self.split.append((len(segs), ez, o))
            segs.append(motion * after)
        segs.append(self.pose(robot.written_tool))
        return segs

    def link(self, i: int):
        """``T_{i-1}^i`` of joint i (0-based), exact, simplified."""
        sp = self.sp
        if self.robot.convention != "poe":
            before, motion, after = self.dh_parts(i)
            return (before * motion * after).applyfunc(self.simplify)
        from ...model import axis_frame
        robot = self.robot

        def frame(k):
            j = robot.joints[k]
            return self.pose(axis_frame(j.axis, j.point))

        C = frame(i)
        prev = sp.eye(4) if i == 0 else _invert(frame(i - 1), sp)
        J = self.rot("z", self.q[i]) if robot.joints[i].revolute else self.trans(z=self.q[i])
        return (prev * C * J).applyfunc(self.simplify)

    # products ------------------------------------------------------------------
    def mul(self, A, B):
        return (A * B).applyfunc(self.simplify)

    def product(self, mats):
        M = self.sp.eye(4)
        for S in mats:
            M = self.mul(M, S)
        return M

    def simplify(self, e):
        return collapse(self.sp.expand(e), self.sp)

    # presentation ----------------------------------------------------------------
    def finish(self, mats):
        """Abbreviate and factor the final matrices (``None`` passes through)."""
        sp = self.sp
        abbrev = Abbreviations(self.index, {str(s) for s in self.q} | set(self.param_symbols), sp)
        out = []
        for M in mats:
            if M is None:
                out.append(None)
                continue
            M = M.applyfunc(abbrev.apply)
            out.append(M.applyfunc(lambda e: nest(e, abbrev, sp)))
        self.legend = abbrev.legend()
        return out

    def notation(self) -> Notation:
        params = tuple((self.used[n], float(self.param_values[n]))
                       for n, _ in self.robot.parameters if n in self.used)
        return Notation(joints=tuple(self.q), parameters=params, legend=self.legend)


def _invert(T, sp):
    R, p = T[:3, :3], T[:3, 3]
    M = sp.eye(4)
    M[:3, :3] = R.T
    M[:3, 3] = -R.T * p
    return M
