"""Exact numbers and joint symbols for :mod:`kincalc.analysis.symbolic`: sympy on
demand, floating-point lengths and angles made exact, and the joints' symbols."""

from __future__ import annotations

import keyword
import math
import re
from fractions import Fraction


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


def require_sympy(command: str):
    """Import and return sympy, or raise ``MissingExtra`` naming ``command``.

    ``command`` is what the user ran, as it should read in the message:
    ``"kincalc fk --symbolic"``.
    """
    from ...errors import require_extra
    return require_extra(command, "sympy", "symbolic")


# --- exact numbers ---------------------------------------------------------------

def exact(x: float, sp):
    """``x`` as an exact rational with SIGNIFICANT_DIGITS digits (0.4318 -> 2159/5000)."""
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return sp.Integer(int(x))
    return sp.Rational(format(x, f".{SIGNIFICANT_DIGITS}g"))


def exact_angle(rad: float, sp):
    """A constant angle (rad) as an exact multiple of pi when it is one."""
    f = Fraction(rad / math.pi).limit_denominator(ANGLE_DENOMINATOR)
    if abs(float(f) * math.pi - rad) <= ANGLE_TOL:
        return sp.Rational(f.numerator, f.denominator) * sp.pi
    return exact(rad, sp)


def exact_unit(x: float, sp):
    """A rotation-matrix entry: 0, ±1/2, ±√2/2, ±√3/2, ±1 exactly, else a decimal."""
    for v in (sp.Integer(0), sp.Integer(1), sp.Rational(1, 2), sp.sqrt(2) / 2, sp.sqrt(3) / 2):
        if abs(abs(x) - float(v)) <= UNIT_TOL:
            return v if x >= 0 else -v
    return exact(x, sp)


# --- joint symbols ---------------------------------------------------------------

_ABBREV_LIKE = re.compile(r"^[CS][0-9m_]+$")


def joint_symbols(robot, sp) -> list:
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
