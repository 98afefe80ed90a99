"""The results of :mod:`kincalc.analysis.symbolic`: the notation, the symbolic forward
kinematics and Jacobian, and their documents (JSON, text, LaTeX)."""

from __future__ import annotations

from dataclasses import dataclass

from .printing import expr_str, latex_legend, latex_matrix, latex_printer

ROWS = ("vx", "vy", "vz", "wx", "wy", "wz")


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
        ``T_{i-1}^i`` for i = 1..n, in the robot's convention (see the package docstring).
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
        lat = latex_printer(self.notation)
        blocks = [f"% kincalc fk {self.robot.name} --symbolic: link transforms and tool pose "
                  f"({self.robot.convention}); needs \\usepackage{{amsmath}}"]
        for i, M in enumerate(self.links, start=1):
            blocks.append(latex_matrix(lat, f"{{}}^{{{i - 1}}}T_{{{i}}}", M))
        if self.base is not None:
            blocks.append(latex_matrix(lat, "{}^{\\mathrm{world}}T_{0}", self.base))
        if self.tool is not None:
            name = "M" if self.robot.convention == "poe" else f"{{}}^{{{n}}}T_{{\\mathrm{{tool}}}}"
            blocks.append(latex_matrix(lat, name, self.tool))
        name = ("{}^{0}" if self.base is None else "{}^{\\mathrm{world}}") + \
            (f"T_{{{n}}}" if self.tool is None else "T_{\\mathrm{tool}}")
        blocks.append(latex_matrix(lat, name, self.T))
        blocks.append(latex_legend(lat, self.notation, self.length_unit))
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
        lat = latex_printer(self.notation)
        name = "J" if self.frame == "base" else "{}^{\\mathrm{tool}}J"
        head = (f"% kincalc jacobian {self.robot.name} --symbolic: geometric Jacobian, "
                f"{self.frame} frame, rows vx vy vz wx wy wz; needs \\usepackage{{amsmath}}")
        return "\n".join([head, latex_matrix(lat, name, self.J),
                          latex_legend(lat, self.notation, self.length_unit)]) + "\n"


def _doc_start(command: str, res) -> dict:
    from ..results import Units, json_header
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
