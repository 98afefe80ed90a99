"""Rendering for :mod:`kincalc.analysis.symbolic`: expressions as plain text, Unicode
and LaTeX."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from .symbols import exact, unicode_name

if TYPE_CHECKING:
    from .results import Notation


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


def latex_printer(notation: Notation):
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


def latex_matrix(lat, name: str, M) -> str:
    rows = [" & ".join(lat(M[r, c]) for c in range(M.shape[1])) for r in range(M.shape[0])]
    body = " \\\\\n".join(rows)
    return f"\\[\n{name} = \\begin{{bmatrix}}\n{body}\n\\end{{bmatrix}}\n\\]"


def latex_legend(lat, notation: Notation, unit: str) -> str:
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
    return exact(v, sp)
