"""Simplification for :mod:`kincalc.analysis.symbolic`: sums of angles collapsed term
by term, and the textbook abbreviations (``C1``, ``S23``) with common factors pulled
out (the rules are in the package docstring)."""

from __future__ import annotations

import re


def collapse(expr, sp):
    """Collapse sums of angles in an expanded sum of products (package docstring).

    Terms are keyed by their sine/cosine factors (with multiplicity) and the
    rest of their non-numeric factors; two terms whose keys differ by the
    pattern of an angle-sum identity and whose numeric coefficients match
    are replaced by one term. Repeats until nothing changes.
    """
    if not expr.is_Add:
        return expr
    terms: dict = {}
    for t in sp.Add.make_args(expr):
        _add_term(terms, t, sp)
    while _merge_pass(terms, sp):
        pass
    return sp.Add(*[c * sp.Mul(*trig) * rest for (trig, rest), c in terms.items()])


def _add_term(terms: dict, term, sp) -> None:
    """Add ``term`` to ``terms``: (sorted sine/cosine factors, the other factors) ->
    numeric coefficient; a coefficient that cancels to 0 removes its key."""
    c, m = term.as_coeff_Mul()
    trig, rest = [], []
    for f in sp.Mul.make_args(m):
        base, e = f.as_base_exp()
        if isinstance(base, (sp.cos, sp.sin)) and e.is_Integer and e > 0:
            trig.extend([base] * int(e))
        else:
            rest.append(f)
    key = (tuple(sorted(trig, key=sp.default_sort_key)), sp.Mul(*rest))
    value = terms.get(key, 0) + c
    if value == 0:
        terms.pop(key, None)
    else:
        terms[key] = value


def _merge_pass(terms: dict, sp) -> bool:
    """One pass over the terms: each term still there is joined with the first term an
    angle-sum identity pairs it with; whether any was."""
    changed = False
    for key in list(terms):
        if key in terms and _merge_at(terms, key, sp):
            changed = True
    return changed


def _merge_at(terms: dict, key, sp) -> bool:
    """Join the term ``key`` with the first partner term found; whether there was one."""
    trig, rest = key
    for i in range(len(trig)):
        for j in range(i + 1, len(trig)):
            if trig[i] == trig[j] and not isinstance(trig[i], sp.cos):
                continue   # sin² is reached from cos²
            others = [f for k, f in enumerate(trig) if k not in (i, j)]
            pkey = (tuple(sorted(others + _partners(trig[i], trig[j], sp),
                                 key=sp.default_sort_key)), rest)
            if pkey == key or pkey not in terms:
                continue
            new = _merged(trig[i], trig[j], terms[key], terms[pkey], sp)
            if new is None:
                continue
            del terms[key]
            del terms[pkey]
            _add_term(terms, sp.Mul(new, *others, rest), sp)
            return True
    return False


def _partners(f, g, sp) -> list:
    """The factors that pair with ``f·g`` in an angle-sum identity (cos <-> sin)."""
    swap = {sp.cos: sp.sin, sp.sin: sp.cos}
    return [swap[type(f)](f.args[0]), swap[type(g)](g.args[0])]


def _merged(f, g, c1, c2, sp):
    """``c1·f·g + c2·F·G`` (F, G the partners of f, g) as one term, or None."""
    cos, sin = sp.cos, sp.sin
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


class Abbreviations:
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


def nest(expr, abbrev: Abbreviations, sp):
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
    inside = nest(sp.Add(*inner), abbrev, sp)
    sign = 1
    if all(t.could_extract_minus_sign() for t in sp.Add.make_args(inside)):
        inside, sign = nest(sp.Add(*[-t for t in inner]), abbrev, sp), -1
    head = sp.Mul(sign, s, inside)
    return sp.Add(head, nest(sp.Add(*rest), abbrev, sp)) if rest else head
