"""Symbolic link transforms, forward kinematics and Jacobians (sympy).

sympy is the optional extra ``symbolic`` (``pip install 'kincalc[symbolic]'``)
and is imported only inside the functions of this module that need it, never
at import time: :func:`require_sympy` imports it or raises
:class:`~kincalc.errors.MissingExtra`.

Frames and conventions (the same as the numeric core, see :mod:`kincalc.model`)
-----------------------------------------------------------------------------
* ``dh`` link transform ``T_{i-1}^i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``,
  ``mdh`` ``T_{i-1}^i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``: the pose of
  link frame i in link frame i-1. A revolute joint's variable is ``θ_i``
  (the file's ``theta`` is added to it as a constant offset), a prismatic
  joint's variable enters ``d_i`` the same way.
* ``poe`` (Lynch & Park, *Modern Robotics*, 2017, eq. 4.14):
  ``T = base · exp([S_1] θ_1) ··· exp([S_n] θ_n) · M`` with
  ``exp([S] θ) = [[R, (I - R) p], [0, 1]]``, ``R = I + sin θ [ω] + (1 - cos θ) [ω]²``
  (Rodrigues) for a revolute joint of unit axis ω through the point p, and
  ``[[I, ω d], [0, 1]]`` for a prismatic one. The link transforms printed for
  poe robots are those of :meth:`kincalc.model.Robot.link_transforms` (frame i
  on joint i's axis, z along it).
* ``T`` is ``T_world_tool = base · T_0^n · tool`` like :meth:`Robot.fk`.
* The geometric Jacobian (Siciliano et al. 2009, eq. 3.30) has rows
  ``(vx, vy, vz, wx, wy, wz)`` and one column per joint: ``[z_i × (p_e - o_i); z_i]``
  (revolute) or ``[z_i; 0]`` (prismatic), in the world frame (``frame='base'``)
  or rotated into the tool frame (``frame='tool'``).

Symbols and numbers
-------------------
Joint variables are angles (rad) and lengths; the symbols carry no unit.
Lengths the robot file wrote as expressions over its ``parameters`` (``d:
h1``) become those parameters' symbols, in the file's length unit; lengths
the file wrote as plain numbers, and the base and tool transforms, stay
numbers. With ``numeric_lengths`` every parameter is replaced by its value.
Constant angles (``alpha``, ``theta`` offsets, rotations of base and tool)
are made exact: multiples of π/3600 become rational multiples of ``pi``, so
``cos 90° = 0`` and ``sin 30° = 1/2``.

Simplification
--------------
Every product is expanded into a sum of products of sines and cosines,
which is multilinear in each joint's sine and cosine (a serial chain meets
each joint once), and sums of angles are collapsed term by term:
``c·cos a cos b - c·sin a sin b -> c·cos(a + b)`` and the three companion
identities (plus ``cos² + sin² = 1``). This is where ``C23`` and ``S234``
come from for consecutive parallel axes. Jacobian columns are built as
``R_0^{i-1} (z × p_{i-1}^e)`` from a prefix and a suffix of the chain so
that they stay multilinear too. No general ``sympy.simplify`` is run: a
6R arm takes well under a second. The result is then written with the
textbook abbreviations ``C1 = cos θ1``, ``S12 = sin(θ1 + θ2)``,
``C2m3 = cos(θ2 - θ3)`` and common factors are pulled out greedily
(``C1·(a2·C2 + a3·C23) - d3·S1``).
"""

from __future__ import annotations

import ast
import keyword
import math
import re
from dataclasses import dataclass
from fractions import Fraction

from ..errors import InputError

#: significant digits kept when a floating-point length or matrix entry is
#: turned into an exact decimal (robot files rarely carry more than 6).
SIGNIFICANT_DIGITS = 12
#: a constant angle within ANGLE_TOL rad of a multiple of pi/ANGLE_DENOMINATOR
#: is taken as that exact multiple (0.05° steps cover every robot file).
ANGLE_DENOMINATOR = 3600
ANGLE_TOL = 1e-9
#: matrix entries of base/tool rotations within this of 0, ±1/2, ±√2/2, ±√3/2, ±1
#: are taken as those exact values.
UNIT_TOL = 1e-12

ROWS = ("vx", "vy", "vz", "wx", "wy", "wz")


def require_sympy(command: str):
    """Import and return sympy, or raise ``MissingExtra`` naming ``command``.

    ``command`` is what the user ran, as it should read in the message:
    ``"kincalc fk --symbolic"``.
    """
    from ..errors import require_extra
    return require_extra(command, "sympy", "symbolic")


# --- results ------------------------------------------------------------------

@dataclass(frozen=True)
class Notation:
    """The symbols of a derivation.

    Attributes
    ----------
    joints : tuple of sympy.Symbol
        One per joint, the joint variable (angle or length).
    parameters : tuple of (sympy.Symbol, float)
        The robot file's parameters that appear as symbols, with their values
        in the file's length unit.
    legend : tuple of (sympy.Symbol, sympy.Expr)
        Abbreviations used (``C12`` -> ``cos(theta1 + theta2)``), in order.
    """

    joints: tuple
    parameters: tuple
    legend: tuple

    def expand(self, M):
        """``M`` with every abbreviation replaced by its sine or cosine."""
        return M.xreplace(dict(self.legend))

    def substitutions(self) -> dict:
        """``{parameter symbol: value}`` (file units), for evaluating the matrices."""
        return {s: v for s, v in self.parameters}


@dataclass(frozen=True)
class SymbolicFK:
    """Symbolic link transforms and tool pose of a robot.

    Attributes
    ----------
    robot : Robot
    links : tuple of sympy.Matrix (4, 4)
        ``T_{i-1}^i`` for i = 1..n, in the robot's convention (see module docstring).
    base, tool : sympy.Matrix (4, 4) or None
        The robot's base (``T_world_0``) and tool (dh/mdh: ``T_n_tool``; poe:
        ``M``) transforms, ``None`` when they are the identity.
    T : sympy.Matrix (4, 4)
        ``T_world_tool = base · T_0^n · tool`` (poe: ``base · Π exp([S_i] θ_i) · M``).
    notation : Notation
    length_unit : str
        Unit of every length in the matrices (and of prismatic joint symbols).
    numeric_lengths : bool
    """

    robot: object
    links: tuple
    base: object
    tool: object
    T: object
    notation: Notation
    length_unit: str
    numeric_lengths: bool

    def to_dict(self) -> dict:
        """The JSON document of ``kincalc fk --symbolic --json`` (plain types)."""
        out = _doc_start("fk", self)
        out["links"] = [{"index": i + 1, "joint": j.name, "T": _rows(M)}
                        for i, (j, M) in enumerate(zip(self.robot.joints, self.links))]
        out["base"] = None if self.base is None else _rows(self.base)
        out["tool"] = None if self.tool is None else _rows(self.tool)
        out["T"] = _rows(self.T)
        out["latex"] = self.latex()
        return out

    def titles(self) -> dict:
        """Plain-text titles of the matrices: ``link``(i), ``base``, ``tool``, ``T``."""
        n = self.robot.dof
        parts = (["base"] if self.base is not None else []) + [f"T_0^{n}"] \
            + (["tool"] if self.tool is not None else [])
        return {
            "base": "base: T_world^0",
            "tool": "tool: M (tool pose at q = 0)" if self.robot.convention == "poe"
            else f"tool: T_{n}^tool",
            "T": f"T_0^{n}" if len(parts) == 1 else f"T = {' · '.join(parts)}  (world <- tool)",
        }

    def latex(self) -> str:
        """The link transforms, base/tool and ``T`` as a LaTeX fragment (amsmath)."""
        n = self.robot.dof
        lat = _latex_printer(self.notation)
        blocks = [f"% kincalc fk {self.robot.name} --symbolic: link transforms and tool pose "
                  f"({self.robot.convention}); needs \\usepackage{{amsmath}}"]
        for i, M in enumerate(self.links, start=1):
            blocks.append(_latex_matrix(lat, f"{{}}^{{{i - 1}}}T_{{{i}}}", M))
        if self.base is not None:
            blocks.append(_latex_matrix(lat, "{}^{\\mathrm{world}}T_{0}", self.base))
        if self.tool is not None:
            name = "M" if self.robot.convention == "poe" else f"{{}}^{{{n}}}T_{{\\mathrm{{tool}}}}"
            blocks.append(_latex_matrix(lat, name, self.tool))
        name = ("{}^{0}" if self.base is None else "{}^{\\mathrm{world}}") + \
            (f"T_{{{n}}}" if self.tool is None else "T_{\\mathrm{tool}}")
        blocks.append(_latex_matrix(lat, name, self.T))
        blocks.append(_latex_legend(lat, self.notation, self.length_unit))
        return "\n".join(blocks) + "\n"


@dataclass(frozen=True)
class SymbolicJacobian:
    """The symbolic geometric Jacobian of a robot.

    Attributes
    ----------
    robot : Robot
    frame : {'base', 'tool'}
    J : sympy.Matrix (6, n)
        Rows ``(vx, vy, vz, wx, wy, wz)``; linear rows in ``length_unit`` per
        rad (per length unit for prismatic columns), angular rows in rad/rad.
    notation : Notation
    length_unit : str
    numeric_lengths : bool
    """

    robot: object
    frame: str
    J: object
    notation: Notation
    length_unit: str
    numeric_lengths: bool

    def to_dict(self) -> dict:
        """The JSON document of ``kincalc jacobian --symbolic --json``."""
        out = _doc_start("jacobian", self)
        out["frame"] = self.frame
        out["rows"] = list(ROWS)
        out["J"] = _rows(self.J)
        out["latex"] = self.latex()
        return out

    def latex(self) -> str:
        lat = _latex_printer(self.notation)
        name = "J" if self.frame == "base" else "{}^{\\mathrm{tool}}J"
        head = (f"% kincalc jacobian {self.robot.name} --symbolic: geometric Jacobian, "
                f"{self.frame} frame, rows vx vy vz wx wy wz; needs \\usepackage{{amsmath}}")
        return "\n".join([head, _latex_matrix(lat, name, self.J),
                          _latex_legend(lat, self.notation, self.length_unit)]) + "\n"


def _doc_start(command: str, res) -> dict:
    from .results import Units, json_header
    n = res.notation
    out = json_header(command, res.robot, Units(angle="rad", length=res.length_unit))
    out["symbolic"] = True
    out["numeric_lengths"] = res.numeric_lengths
    out["joints"] = [{"name": j.name, "type": j.type, "symbol": str(s)}
                     for j, s in zip(res.robot.joints, n.joints)]
    out["parameters"] = {str(s): v for s, v in n.parameters}
    out["legend"] = {str(s): expr_str(e) for s, e in n.legend}
    return out


def _rows(M) -> list:
    return [[expr_str(M[r, c]) for c in range(M.shape[1])] for r in range(M.shape[0])]


# --- the derivations ------------------------------------------------------------

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
    tool = None if _is_identity(robot.tool) else b.pose(robot.tool)
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
        from ..units import LENGTH_UNITS
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
        self.k = _exact(LENGTH_UNITS[file_unit], sp) / _exact(LENGTH_UNITS[self.unit], sp)
        # rad per file angle unit, exact (expressions are in the file's unit)
        self.A = sp.pi / 180 if robot.angle_unit == "deg" else sp.Integer(1)
        self.q = _joint_symbols(robot, sp)
        self.index = {s: i + 1 for i, s in enumerate(self.q)}
        self.param_symbols = {name: sp.Symbol(name, real=True) for name, _ in robot.parameters}
        self.param_values = {name: _exact(v, sp) for name, v in robot.parameters}
        self.used: dict[str, object] = {}
        self.split: list = []
        exprs = tuple(robot.expressions)
        self.exprs = [dict(e) for e in exprs] if len(exprs) == robot.dof else \
            [{} for _ in robot.joints]

    # numbers -----------------------------------------------------------------
    def length(self, si: float):
        return _exact(si / self.L_file, self.sp) * self.k

    def angle(self, rad: float):
        return _exact_angle(rad, self.sp)

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
                return _exact(e.value, sp)
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
                M[r, c] = _exact_unit(float(T[r, c]), sp)
            M[r, 3] = self.length(float(T[r, 3]))
        return M

    # elementary transforms ---------------------------------------------------
    def rot(self, axis: str, t):
        sp = self.sp
        c, s = sp.cos(t), sp.sin(t)
        if not t.free_symbols and (c.has(sp.cos, sp.sin) or s.has(sp.cos, sp.sin)):
            # a constant angle without a closed form (1°): its sine and cosine as decimals
            c, s = _exact(float(c), sp), _exact(float(s), sp)
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
        fixed = self.trans(x=a) * self.rot("x", alpha)
        if self.robot.convention == "dh":
            return self.sp.eye(4), motion, fixed
        return fixed, motion, self.sp.eye(4)

    def poe_axis(self, i: int):
        sp = self.sp
        joint = self.robot.joints[i]
        w = sp.Matrix([_exact_unit(float(x), sp) for x in joint.axis])
        p = sp.Matrix([self.length(float(x)) for x in joint.point])
        return w, p

    def poe_exp(self, i: int):
        """``exp([S_i] q_i)`` (Rodrigues; module docstring)."""
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
        segs.append(self.pose(robot.tool))
        return segs

    def link(self, i: int):
        """``T_{i-1}^i`` of joint i (0-based), exact, simplified."""
        sp = self.sp
        if self.robot.convention != "poe":
            before, motion, after = self.dh_parts(i)
            return (before * motion * after).applyfunc(self.simplify)
        from ..model import axis_frame
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
        return _collapse(self.sp.expand(e), self.sp)

    # presentation ----------------------------------------------------------------
    def finish(self, mats):
        """Abbreviate and factor the final matrices (``None`` passes through)."""
        sp = self.sp
        abbrev = _Abbreviations(self.index, {str(s) for s in self.q} | set(self.param_symbols), sp)
        out = []
        for M in mats:
            if M is None:
                out.append(None)
                continue
            M = M.applyfunc(abbrev.apply)
            out.append(M.applyfunc(lambda e: _nest(e, abbrev, sp)))
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


# --- exact numbers ---------------------------------------------------------------

def _exact(x: float, sp):
    """``x`` as an exact rational with SIGNIFICANT_DIGITS digits (0.4318 -> 2159/5000)."""
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return sp.Integer(int(x))
    return sp.Rational(format(x, f".{SIGNIFICANT_DIGITS}g"))


def _exact_angle(rad: float, sp):
    """A constant angle (rad) as an exact multiple of pi when it is one."""
    f = Fraction(rad / math.pi).limit_denominator(ANGLE_DENOMINATOR)
    if abs(float(f) * math.pi - rad) <= ANGLE_TOL:
        return sp.Rational(f.numerator, f.denominator) * sp.pi
    return _exact(rad, sp)


def _exact_unit(x: float, sp):
    """A rotation-matrix entry: 0, ±1/2, ±√2/2, ±√3/2, ±1 exactly, else a decimal."""
    for v in (sp.Integer(0), sp.Integer(1), sp.Rational(1, 2), sp.sqrt(2) / 2, sp.sqrt(3) / 2):
        if abs(abs(x) - float(v)) <= UNIT_TOL:
            return v if x >= 0 else -v
    return _exact(x, sp)


# --- joint symbols ---------------------------------------------------------------

_ABBREV_LIKE = re.compile(r"^[CS][0-9m_]+$")


def _joint_symbols(robot, sp) -> list:
    """Joint variables: the joints' own names when every one is a usable
    identifier (``theta1``, ``q1``, ``d3``), else ``theta<i>`` / ``d<i>``."""
    from sympy.abc import _clash
    taken = {name for name, _ in robot.parameters}
    names = [j.name for j in robot.joints]

    def usable(n):
        return (n.isidentifier() and not keyword.iskeyword(n) and n not in _clash
                and n not in taken and not _ABBREV_LIKE.match(n) and not n.startswith("_"))

    if not all(usable(n) for n in names) or len(set(names)) != len(names):
        names = [("theta" if j.revolute else "d") + str(i + 1) for i, j in enumerate(robot.joints)]
        names = [n if n not in taken else n + "_q" for n in names]
    return [sp.Symbol(n, real=True) for n in names]


def unicode_name(name: str) -> str:
    """``theta1`` -> ``θ1`` (for tables); other names unchanged."""
    return re.sub(r"^theta(?=[0-9_]|$)", "θ", name)


# --- simplification ------------------------------------------------------------

def _collapse(expr, sp):
    """Collapse sums of angles in an expanded sum of products (module docstring).

    Terms are keyed by their sine/cosine factors (with multiplicity) and the
    rest of their non-numeric factors; two terms whose keys differ by the
    pattern of an angle-sum identity and whose numeric coefficients match
    are replaced by one term. Repeats until nothing changes.
    """
    if not expr.is_Add:
        return expr
    cos, sin = sp.cos, sp.sin
    key_of = sp.default_sort_key
    terms: dict = {}

    def add(term):
        c, m = term.as_coeff_Mul()
        trig, rest = [], []
        for f in sp.Mul.make_args(m):
            base, e = f.as_base_exp()
            if isinstance(base, (cos, sin)) and e.is_Integer and e > 0:
                trig.extend([base] * int(e))
            else:
                rest.append(f)
        key = (tuple(sorted(trig, key=key_of)), sp.Mul(*rest))
        value = terms.get(key, 0) + c
        if value == 0:
            terms.pop(key, None)
        else:
            terms[key] = value

    for t in sp.Add.make_args(expr):
        add(t)

    def without(trig, i, j):
        return [f for k, f in enumerate(trig) if k not in (i, j)]

    swap = {cos: sin, sin: cos}

    def partner(trig, i, j):
        """The factors that pair with ``trig[i]·trig[j]`` in an angle-sum identity."""
        f, g = trig[i], trig[j]
        return [swap[type(f)](f.args[0]), swap[type(g)](g.args[0])]

    def merged(f, g, c1, c2):
        """``c1·f·g + c2·F·G`` (F, G the partners of f, g) as one term, or None."""
        a, b = f.args[0], g.args[0]
        kinds = (type(f), type(g))
        if a == b:
            if kinds == (cos, cos) and c1 == c2:         # c (cos² a + sin² a) = c
                return c1
            return None
        if kinds[0] is kinds[1]:                         # cc·Ca·Cb + ss·Sa·Sb
            cc, ss = (c1, c2) if kinds[0] is cos else (c2, c1)
            if ss == -cc:
                return cc * cos(a + b)
            if ss == cc:
                return cc * cos(a - b)
            return None
        sc, cs = (c1, c2) if kinds[0] is sin else (c2, c1)   # sc·Sa·Cb + cs·Ca·Sb
        if cs == sc:
            return sc * sin(a + b)
        if cs == -sc:
            return sc * sin(a - b)
        return None

    changed = True
    while changed:
        changed = False
        for key in list(terms):
            if key not in terms:
                continue
            trig, rest = key
            c1 = terms[key]
            done = False
            for i in range(len(trig)):
                for j in range(i + 1, len(trig)):
                    if trig[i] == trig[j] and not isinstance(trig[i], cos):
                        continue   # sin² is reached from cos²
                    F, G = partner(trig, i, j)
                    others = without(trig, i, j)
                    pkey = (tuple(sorted(others + [F, G], key=key_of)), rest)
                    if pkey == key or pkey not in terms:
                        continue
                    new = merged(trig[i], trig[j], c1, terms[pkey])
                    if new is None:
                        continue
                    del terms[key]
                    del terms[pkey]
                    add(sp.Mul(new, *others, rest))
                    done = changed = True
                    break
                if done:
                    break
    return sp.Add(*[c * sp.Mul(*trig) * rest for (trig, rest), c in terms.items()])


class _Abbreviations:
    """``cos(theta1 + theta2)`` <-> ``C12``: naming, replacing, legend."""

    def __init__(self, index: dict, taken: set, sp):
        self.sp = sp
        self.index = index
        clash = any(re.match(r"^[CS][0-9]", n) for n in taken)
        self.prefix = ("cos", "sin") if clash else ("C", "S")
        self.made: dict = {}     # trig expr -> (legend order, symbol, LaTeX subscript)
        self.ranks: dict = {}    # symbol -> (joint indices, negated indices, cos/sin)

    def label(self, arg):
        """``('12', '1+2')`` for theta1 + theta2, ``('2m3', '2-3')`` for theta2 - theta3."""
        pos, neg = [], []
        for s, c in arg.as_coefficients_dict().items():
            if s not in self.index or c not in (1, -1):
                return None
            (pos if c == 1 else neg).append(self.index[s])
        if not pos:
            return None
        pos.sort()
        neg.sort()
        sep = "_" if max(pos + neg) > 9 else ""
        text = sep.join(map(str, pos)) + ("m" + sep.join(map(str, neg)) if neg else "")
        tex = ("," if sep else "").join(map(str, pos)) + \
            ("-" + ("," if sep else "").join(map(str, neg)) if neg else "")
        return text, tex, (len(pos) + len(neg), pos, neg)

    def apply(self, e):
        sp = self.sp
        repl = {}
        for f in e.atoms(sp.cos, sp.sin):
            if f not in self.made:
                lab = self.label(f.args[0])
                if lab is None:
                    continue
                text, tex, order = lab
                kind = 0 if isinstance(f, sp.cos) else 1
                sym = sp.Symbol(self.prefix[kind] + text, real=True)
                self.made[f] = ((*order, kind), sym, tex)
                self.ranks[sym] = (order[1], order[2], kind)
            repl[f] = self.made[f][1]
        return e.xreplace(repl)

    def rank(self, sym):
        """Order for factoring: by joint indices (C23 before C6), cosine first."""
        return self.ranks[sym]

    def symbols(self) -> set:
        return {s for _, s, _ in self.made.values()}

    def legend(self) -> tuple:
        items = sorted(self.made.items(), key=lambda kv: kv[1][0])
        return tuple((s, f) for f, (_, s, _) in items)

    def latex_names(self) -> dict:
        out = {}
        for f, (_, s, tex) in self.made.items():
            out[s] = f"{self.prefix[0 if isinstance(f, self.sp.cos) else 1]}_{{{tex}}}"
        return out


def _nest(expr, abbrev: _Abbreviations, sp):
    """Pull out, recursively, the abbreviation shared by the most terms
    (ties: the lowest joint index): ``C1·C2·a2 + C1·C23·a3 -> C1·(a2·C2 + a3·C23)``."""
    if not expr.is_Add:
        return expr
    terms = sp.Add.make_args(expr)
    syms = abbrev.symbols()
    count: dict = {}
    for t in terms:
        for f in set(sp.Mul.make_args(t)):
            if f in syms:
                count[f] = count.get(f, 0) + 1
    best = [s for s, n in count.items() if n >= 2]
    if not best:
        return expr
    s = min(best, key=lambda s: (-count[s], abbrev.rank(s)))
    inner = [t / s for t in terms if s in sp.Mul.make_args(t)]
    rest = [t for t in terms if s not in sp.Mul.make_args(t)]
    inside = _nest(sp.Add(*inner), abbrev, sp)
    sign = 1
    if all(t.could_extract_minus_sign() for t in sp.Add.make_args(inside)):
        inside, sign = _nest(sp.Add(*[-t for t in inner]), abbrev, sp), -1
    head = sp.Mul(sign, s, inside)
    return sp.Add(head, _nest(sp.Add(*rest), abbrev, sp)) if rest else head


# --- printing -------------------------------------------------------------------

def _display(expr, sp):
    """An unevaluated copy of ``expr`` ordered for reading: numbers first, then
    other symbols, then abbreviations by joint index, then parenthesised sums;
    exact decimals (2159/5000) shown as decimals (0.4318)."""
    def is_abbrev(f):
        return f.is_Symbol and re.match(r"^(C|S|cos|sin)[0-9]", f.name) is not None

    def abbrev_key(f):
        m = re.match(r"^(C|S|cos|sin)([0-9_]+)(?:m([0-9_]+))?$", f.name)
        if not m:
            return ((), 0, f.name)
        digits = m.group(2)
        idx = tuple(int(x) for x in (digits.split("_") if "_" in digits else digits))
        return (idx, 0 if m.group(1) in ("C", "cos") else 1, f.name)

    def number(c, has_root):
        if c.is_Rational and not c.is_Integer and not has_root:
            q = int(c.q)
            while q % 2 == 0:
                q //= 2
            while q % 5 == 0:
                q //= 5
            if q == 1:
                return sp.Float(str(c.p / c.q) if abs(c.p) < 2 ** 52 else float(c), 15)
        return c

    def walk(e):
        if e.is_Rational:
            return number(e, False)
        if e.is_Add:
            terms = [walk(t) for t in e.args]
            terms.sort(key=term_key)
            return sp.Add(*terms, evaluate=False)
        if e.is_Mul:
            c, rest = e.as_coeff_Mul()
            factors = []
            for f in sp.Mul.make_args(rest):
                fc, fr = f.as_coeff_Mul() if f.is_Mul else (1, f)
                c *= fc
                factors.extend(sp.Mul.make_args(fr))
            has_root = any(f.is_Pow and f.exp.is_Rational and not f.exp.is_Integer
                           for f in factors)
            plain = sorted((f for f in factors if not is_abbrev(f) and not f.is_Add),
                           key=sp.default_sort_key)
            ab = sorted((f for f in factors if is_abbrev(f)), key=abbrev_key)
            sums = []
            for f in factors:
                if f.is_Add:
                    inner = walk(f)
                    if inner.args[0].could_extract_minus_sign():   # -S1·(a + b), not S1·(-a - b)
                        c = -c
                        inner = sp.Add(*[walk(-t) for t in f.args], evaluate=False)
                        inner = sp.Add(*sorted(inner.args, key=term_key), evaluate=False)
                    sums.append(inner)
            args = [walk(f) for f in plain + ab] + sums
            c = number(c, has_root)
            if c == 1 and len(args) == 1:
                return args[0]
            return sp.Mul(*([c] if c != 1 else []), *args, evaluate=False)
        if e.is_Pow:
            return sp.Pow(walk(e.base), e.exp, evaluate=False)
        if e.args and not e.is_Atom:
            return e.func(*[walk(a) for a in e.args], evaluate=False)
        return e

    def term_key(t):
        factors = [f for f in sp.Mul.make_args(t) if f.is_Symbol or f.is_Add]
        ab = [abbrev_key(f) for f in factors if f.is_Symbol and is_abbrev(f)]
        nested = any(f.is_Add for f in factors)
        if ab:
            return (0 if nested else 1, min(ab), 0, sp.default_sort_key(t))
        # sums of lengths after the trigonometric terms: h1 - d3 - d4, 18 - d3
        return (0 if nested else 1, ((99,), 2, ""), int(t.could_extract_minus_sign()),
                int(t.is_Number), sp.default_sort_key(t))

    return walk(expr)


def expr_str(expr) -> str:
    """sympy ``str`` syntax of one entry, in reading order (parses back with sympify)."""
    import sympy as sp
    return sp.sstr(_display(sp.sympify(expr), sp), order="none", full_prec=False)


def expr_text(expr) -> str:
    """One entry for a table: like :func:`expr_str`, with θ for theta and · for *."""
    import sympy as sp
    from sympy.printing.str import StrPrinter

    class _Text(StrPrinter):
        def _print_Symbol(self, s):
            return unicode_name(s.name)

    text = _Text({"order": "none", "full_prec": False}).doprint(_display(sp.sympify(expr), sp))
    return text.replace("**", "^").replace("*", "·")


def _latex_printer(notation: Notation):
    import sympy as sp
    names = {}
    for s in notation.joints:
        m = re.match(r"^theta_?([0-9]+)$", s.name)
        if m:
            names[s] = f"\\theta_{{{m.group(1)}}}"
    for s, f in notation.legend:
        m = re.match(r"^(C|S|cos|sin)([0-9_]+)(?:m([0-9_]+))?$", s.name)
        if m:
            pos = m.group(2).replace("_", ",")
            neg = ("-" + m.group(3).replace("_", ",")) if m.group(3) else ""
            names[s] = f"{m.group(1)}_{{{pos}{neg}}}"

    def lat(e):
        return sp.latex(_display(sp.sympify(e), sp), order="none", full_prec=False,
                        symbol_names=names, mul_symbol=None)
    return lat


def _latex_matrix(lat, name: str, M) -> str:
    rows = [" & ".join(lat(M[r, c]) for c in range(M.shape[1])) for r in range(M.shape[0])]
    body = " \\\\\n".join(rows)
    return f"\\[\n{name} = \\begin{{bmatrix}}\n{body}\n\\end{{bmatrix}}\n\\]"


def _latex_legend(lat, notation: Notation, unit: str) -> str:
    items = []
    for s, f in notation.legend:
        arg = f.args[0]
        arg_tex = lat(arg) if arg.is_Symbol else f"({lat(arg)})"
        items.append(f"${lat(s)} = \\{type(f).__name__}{' ' if arg.is_Symbol else ''}{arg_tex}$")
    unit_text = "" if unit == "unitless" else f"\\,\\mathrm{{{unit}}}"
    items += [f"${lat(s)} = {lat(_num(v))}{unit_text}$" for s, v in notation.parameters]
    if not items:
        return "% no abbreviations"
    return "where\n" + ",\n".join(items) + "."


def _num(v: float):
    import sympy as sp
    return _exact(v, sp)
