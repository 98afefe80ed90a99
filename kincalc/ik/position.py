"""Placing a point with two or three joints of any type (R or P), all solutions.

The point ``p0`` (world frame, q = 0) is moved by ``E_a(x_a) E_b(x_b) E_c(x_c)``
and must reach ``pt``. Joint a's motion leaves two quantities of a point
unchanged (Pieper 1968; Paden-Kahan invariants):

* revolute a: the height along its axis and the distance from it;
* prismatic a: the two components perpendicular to its axis.

So the point ``f = E_b(x_b) E_c(x_c) p0`` before joint a must match ``pt`` in
those two quantities: two scalar equations in ``x_b``, ``x_c``. Each is
linear in ``(cos x_b, sin x_b)`` (revolute b) or in ``(x_b, x_b^2)``
(prismatic b), with coefficients that are trigonometric polynomials of
degree <= 1 (revolute c) or polynomials of degree <= 2 (prismatic c) in
``x_c``. Eliminating ``x_b`` leaves one equation ``R(x_c) = 0`` of bounded
degree (trigonometric degree 4, or polynomial degree <= 8), whose
coefficients are recovered exactly from samples (a DFT, or a Chebyshev fit)
and whose real roots come from a companion matrix. ``x_b`` then follows by
back-substitution and ``x_a`` from subproblem 1 (or a projection). Every
candidate is polished by Gauss-Newton on the point equations and kept only
if it reaches ``pt``.

Structural special cases are recognised numerically, never by name: an
equation that does not depend on ``x_b`` (axes a and b parallel or
intersecting) is solved on its own first, which is what makes elbow arms
(two roots), SCARAs and Stanford-type arms come out with their textbook
solution counts.
"""

from __future__ import annotations

from contextvars import ContextVar
from dataclasses import dataclass, field

import numpy as np

from ..spatial import cross
from ..spatial import matrix_from_unit_axis_angle as _rot
from .legacy_sp import cross3, norm3

from .legacy_sp import sp1
from .screws import Screws, wrap

#: when set to a list (by ``solve(..., all_branches=True)``), the steps that found no
#: real value append a sentence here: the textbook's "cos q3 = 1.3, no real angle"
DEAD_ENDS: ContextVar = ContextVar("dead_ends", default=None)


def note_dead_end(text: str) -> None:
    """Record why a branch has no real solution (when someone is listening)."""
    sink = DEAD_ENDS.get()
    if sink is not None and text not in sink:
        sink.append(text)


def _cos_form(values) -> tuple[float, float] | None:
    """``(value, phase)`` when samples of a trigonometric polynomial are of degree 1,
    ``c0 + c1 cos x + s1 sin x``: then ``cos(x - phase) = value`` (= -c0 / hypot(c1, s1))."""
    F = np.fft.rfft(values) / len(values)
    amp = 2 * abs(F[1])
    if amp < 1e-12 * max(np.abs(values).max(), 1e-300) or np.abs(F[2:]).max(initial=0.0) > \
            1e-9 * max(np.abs(F[:2]).max(), 1e-300):
        return None
    return float(-F[0].real / amp), float(-np.angle(F[1]))   # F1 = (c1 - i s1) / 2


#: samples of a trigonometric resultant (degree <= 4 needs 9; more is harmless)
TRIG_SAMPLES = 16
#: polynomial degree bound for a prismatic last variable, and its sample count
POLY_DEGREE = 8


@dataclass
class PointSolution:
    x: np.ndarray                          # joint values (a, b[, c]) in rad / m
    signs: dict = field(default_factory=dict)   # step -> '+' / '-' / 'root k'
    free: list = field(default_factory=list)    # joints left undetermined (singular)
    trace: list = field(default_factory=list)   # (label, value) for --explain


def _reference_point(S: Screws, a: int, b: int) -> np.ndarray:
    """The point of axis a nearest to axis b (any point of a if they are parallel).

    Measuring distances from there makes the distance equation independent of
    x_b whenever the axes intersect, which is what keeps elbow arms exact.
    """
    wa, pa, wb, pb = S.axis[a], S.point[a], S.axis[b], S.point[b]
    n = cross(wa, wb)
    nn = n @ n
    if nn < 1e-18:
        return pa
    # pa + t wa closest to the line pb + s wb
    t = cross(pb - pa, wb) @ n / nn
    return pa + t * wa


def _invariants(S: Screws, a: int, pt, b: int | None = None):
    """Two equations ``phi_k(f) = 0`` on the point before joint a (see module doc)."""
    w = S.axis[a]
    o = S.point[a] if b is None else _reference_point(S, a, b)
    if S.revolute[a]:
        u = w @ (pt - o)
        rho2 = (pt - o) @ (pt - o)

        def phi(f):
            d = f - o
            return np.stack([d @ w - u, np.einsum("...i,...i->...", d, d) - rho2])
        return phi, ("height along axis", "squared distance from axis")
    e1 = cross(w, [1.0, 0, 0] if abs(w[0]) < 0.9 else [0, 1.0, 0])
    e1 /= np.linalg.norm(e1)
    e2 = cross(w, e1)

    def phi(f):
        d = f - pt
        return np.stack([d @ e1, d @ e2])
    return phi, ("offset across axis (1)", "offset across axis (2)")


def _coefficients(S: Screws, a: int, b: int, g, pt):
    """Coefficients ``(alpha, beta, gamma)``, each (2, N), of the two equations as
    ``alpha + beta * B1(x_b) + gamma * B2(x_b)`` for points ``g (N, 3)`` before joint b,
    with ``(B1, B2) = (cos, sin)`` for revolute b and ``(x, x^2)`` for prismatic b.

    The equations are affine in f (prismatic a, or the height) or quadratic (the
    distance); f = E_b(x_b) g is evaluated at x_b in {0, pi/2, pi} (revolute) or
    {0, 1, -1} (prismatic) and the coefficients solved from those three values.
    """
    phi, _ = _invariants(S, a, pt, b)
    if S.revolute[b]:
        v0 = phi(S.move_point(b, 0.0, g))
        v1 = phi(S.move_point(b, np.pi / 2, g))
        v2 = phi(S.move_point(b, np.pi, g))
        # alpha + beta cos + gamma sin: at 0: a + b; at pi/2: a + g; at pi: a - b
        alpha = 0.5 * (v0 + v2)
        beta = 0.5 * (v0 - v2)
        gamma = v1 - alpha
    else:
        v0 = phi(S.move_point(b, 0.0, g))
        v1 = phi(S.move_point(b, 1.0, g))
        vm = phi(S.move_point(b, -1.0, g))
        alpha = v0
        beta = 0.5 * (v1 - vm)
        gamma = 0.5 * (v1 + vm) - v0
    return alpha, beta, gamma


def _depends(beta, gamma, scale) -> np.ndarray:
    """(2,) bool: does equation k depend on x_b at all (over the samples)?"""
    m = np.maximum(np.abs(beta), np.abs(gamma)).max(axis=-1)
    return m > 1e-9 * scale


def _resultant(alpha, beta, gamma, revolute_b, dep, mu=0.7390851332151607):
    """R(x_c) on samples, eliminating x_b (see module doc); also the mode used."""
    if not dep[0]:
        return alpha[0], "eq1"
    if not dep[1]:
        return alpha[1], "eq2"
    if revolute_b:
        D = beta[0] * gamma[1] - beta[1] * gamma[0]
        if np.abs(D).max() <= 1e-9 * max(np.abs(beta).max() * np.abs(gamma).max(), 1e-300):
            # rows proportional: combine the equations so x_b drops out
            m = beta + mu * gamma
            return alpha[1] * m[0] - alpha[0] * m[1], "combined"
        P = alpha[0] * gamma[1] - alpha[1] * gamma[0]
        Q = beta[0] * alpha[1] - beta[1] * alpha[0]
        return P * P + Q * Q - D * D, "generic"
    # prismatic b: resultant of two polynomials of degree <= 2 in x_b
    a1, a2 = gamma
    b1, b2 = beta
    c1, c2 = alpha
    if np.abs(gamma).max() <= 1e-12 * max(np.abs(beta).max(), 1e-300):
        return b1 * c2 - b2 * c1, "linear"
    if np.abs(a1).max() <= 1e-12 * np.abs(a2).max():
        return b1 * b1 * c2 - b1 * b2 * c1 + a2 * c1 * c1, "linear-quadratic"
    if np.abs(a2).max() <= 1e-12 * np.abs(a1).max():
        return b2 * b2 * c1 - b2 * b1 * c2 + a1 * c2 * c2, "quadratic-linear"
    return (a1 * c2 - a2 * c1) ** 2 - (a1 * b2 - a2 * b1) * (b1 * c2 - b2 * c1), "quadratic"


def _trig_roots(values) -> np.ndarray:
    """Real roots of a trigonometric polynomial sampled at 2 pi k / N."""
    N = len(values)
    c = np.fft.fft(values) / N
    K = N // 2 - 1
    coeffs = np.array([c[k % N] for k in range(K, -K - 1, -1)])  # c_K ... c_-K
    big = np.abs(coeffs).max()
    if big == 0:
        return np.array([])
    while len(coeffs) > 1 and abs(coeffs[0]) < 1e-11 * big and abs(coeffs[-1]) < 1e-11 * big:
        coeffs = coeffs[1:-1]
    if len(coeffs) == 1:
        return np.array([])
    z = np.roots(coeffs)
    keep = np.abs(np.abs(z) - 1.0) < 1e-3
    return np.angle(z[keep])


def _poly_roots(xs, values, span) -> np.ndarray:
    from numpy.polynomial import Chebyshev
    fit = Chebyshev.fit(xs, values, POLY_DEGREE, domain=[-span, span])
    coef = fit.coef
    big = np.abs(coef).max()
    if big == 0:
        return np.array([])
    coef = np.where(np.abs(coef) < 1e-12 * big, 0.0, coef)
    nz = np.nonzero(coef)[0]
    if len(nz) == 0 or nz[-1] == 0:
        return np.array([])
    r = Chebyshev(coef[: nz[-1] + 1], domain=[-span, span]).roots()
    tol = 1e-4 * span
    return np.real(r[np.abs(np.imag(r)) < tol])


def _explain_no_root(S: Screws, joints, R, mode) -> None:
    """Say why the equation in the last joint has no real root."""
    names = ", ".join(f"{{j{j}}}" for j in joints)
    c = joints[-1]
    if S.revolute[c]:
        form = _cos_form(R)
        if form is not None:
            value, phase = form
            note_dead_end(f"{{j{c}}}: cos({{j{c}}} - {{a{phase!r}}}) would have to be "
                          f"{value:.4g}, outside [-1, 1]: no real angle, the point is out of "
                          f"reach of {names}")
            return
        note_dead_end(f"{{j{c}}}: its equation (trigonometric, from eliminating "
                      f"{{j{joints[1]}}}) has no real root: the point is out of reach of {names}")
    else:
        note_dead_end(f"{{j{c}}}: its polynomial (from eliminating {{j{joints[1]}}}) has no "
                      f"real root: the point is out of reach of {names}")


def _solve_b(alpha, beta, gamma, revolute_b, dep, scale):
    """Candidate x_b values (with a sign label) from the coefficients at one x_c."""
    if revolute_b:
        if dep[0] and dep[1]:
            D = beta[0] * gamma[1] - beta[1] * gamma[0]
            if abs(D) > 1e-9 * max(abs(beta).max() * abs(gamma).max(), 1e-300):
                c = (-alpha[0] * gamma[1] + alpha[1] * gamma[0]) / D
                s = (-beta[0] * alpha[1] + beta[1] * alpha[0]) / D
                return [(float(np.arctan2(s, c)), None)]
        k = int(np.argmax(np.maximum(np.abs(beta), np.abs(gamma))))
        r = np.hypot(beta[k], gamma[k])
        if r < 1e-12 * scale:
            return []
        base = np.arctan2(gamma[k], beta[k])
        cc = -alpha[k] / r
        if abs(cc) > 1 + 1e-7:
            return []
        d = np.arccos(np.clip(cc, -1, 1))
        return [(float(base + d), "+"), (float(base - d), "-")]
    ks = [k for k in (0, 1) if dep[k]]
    k = min(ks, key=lambda k: abs(gamma[k]) / max(abs(beta[k]), 1e-300))  # prefer linear
    if abs(gamma[k]) <= 1e-12 * max(abs(beta[k]), 1e-300):
        return [(float(-alpha[k] / beta[k]), None)] if beta[k] != 0 else []
    roots = np.roots([gamma[k], beta[k], alpha[k]])
    roots = roots[np.abs(np.imag(roots)) < 1e-6 * max(scale, 1.0)]
    return [(float(np.real(x)), "+" if i == 0 else "-") for i, x in enumerate(sorted(np.real(roots), reverse=True))]


def place_point(S: Screws, joints, p0, pt, explain: bool = False) -> list[PointSolution]:
    """All joint values ``x`` for ``joints`` (2 or 3 indices, base to tip) moving ``p0`` to ``pt``.

    Returns solutions polished to machine precision; an empty list when the
    point cannot be reached. A joint whose value the point does not fix
    (a singular target, e.g. the point on joint a's axis) is set to 0 and
    listed in ``free``.
    """
    p0, pt = np.asarray(p0, float), np.asarray(pt, float)
    joints = list(joints)
    scale = S.scale + np.linalg.norm(pt)
    a, b = joints[0], joints[1]
    c = joints[2] if len(joints) == 3 else None

    mode, roots = None, []
    if c is None:
        xs_c = [(None, None)]
    else:
        if S.revolute[c]:
            th = 2 * np.pi * np.arange(TRIG_SAMPLES) / TRIG_SAMPLES
            g = S.move_point(c, th, p0)
        else:
            span = 4.0 * scale
            th = span * np.cos(np.pi * (np.arange(2 * POLY_DEGREE + 1) + 0.5) / (2 * POLY_DEGREE + 1))
            g = S.move_point(c, th, p0)
        alpha, beta, gamma = _coefficients(S, a, b, g, pt)
        dep = _depends(beta, gamma, scale ** 2)
        R, mode = _resultant(alpha, beta, gamma, S.revolute[b], dep)
        roots = _trig_roots(R) if S.revolute[c] else _poly_roots(th, R, span)
        roots = np.sort(roots)
        if len(roots) == 0:
            _explain_no_root(S, joints, R, mode)
        xs_c = [(x, f"root {i + 1}" if len(roots) > 1 else None) for i, x in enumerate(roots)]
        if mode in ("eq1", "eq2", "combined", "linear") and len(roots) == 2 and S.revolute[c]:
            # a cos-type equation: label the pair by the sign of the angle from its middle
            mid = np.angle(np.exp(1j * roots).sum())
            xs_c = [(x, "+" if wrap(x - mid) > 0 else "-") for x in roots]

    out: list[PointSolution] = []
    for xc, sign_c in xs_c:
        gc = p0 if xc is None else S.move_point(c, xc, p0)
        al, be, ga = (v[:, 0] for v in _coefficients(S, a, b, gc[None, :], pt))
        dep = _depends(be[:, None], ga[:, None], scale ** 2)
        if not dep.any():
            # neither equation involves x_b: the point is fixed by x_c alone
            phi, _ = _invariants(S, a, pt)
            if np.abs(al).max() > 1e-6 * scale ** 2:
                continue
            cands = [(0.0, None)]
            free_b = True
        else:
            cands = _solve_b(al, be, ga, S.revolute[b], dep, scale ** 2)
            free_b = False
            if not cands and S.revolute[b]:
                k = int(np.argmax(np.maximum(np.abs(be), np.abs(ga))))
                r = np.hypot(be[k], ga[k])
                if r > 0:
                    at = "" if xc is None else f" with {{j{c}}} = {{a{float(xc)!r}}}"
                    note_dead_end(f"{{j{b}}}: cos({{j{b}}} - {{a{float(np.arctan2(ga[k], be[k]))!r}}})"
                                  f" would have to be {-al[k] / r:.4g}{at}: no real angle, "
                                  "the point is out of reach on that branch")
        for xb, sign_b in cands:
            f = S.move_point(b, xb, gc)
            if S.revolute[a]:
                xa, _, free_a = sp1(f - S.point[a], pt - S.point[a], S.axis[a])
            else:
                xa, free_a = float(S.axis[a] @ (pt - f)), False
            x = np.array([xa, xb] + ([] if xc is None else [xc]), float)
            x = _polish(S, joints, p0, pt, x, frozen=[i for i, fr in ((0, free_a), (1, free_b)) if fr])
            if x is None:
                continue
            sol = PointSolution(x=x)
            if sign_c is not None:
                sol.signs[c] = sign_c
            if sign_b is not None:
                sol.signs[b] = sign_b
            if free_a:
                sol.free.append(a)
            if free_b:
                sol.free.append(b)
            if explain:
                sol.trace = _trace(S, joints, p0, pt, x, mode, roots, (al, be, ga), f)
            out.append(sol)
    return _unique(S, joints, out, scale)


def point_of(S: Screws, joints, x, p0):
    p = np.asarray(p0, float)
    for i, xi in zip(reversed(joints), reversed(list(x))):
        p = S.move_point(i, xi, p)
    return p


def _polish(S: Screws, joints, p0, pt, x, frozen=(), iters: int = 30):
    """Gauss-Newton on the point equations; None if it does not converge onto pt."""
    scale = S.scale + norm3(pt)
    x = x.copy()
    active = [k for k in range(len(joints)) if k not in frozen]
    for _ in range(iters):
        p, J = _point_jacobian(S, joints, x, p0)
        err = pt - p
        if norm3(err) < 1e-14 * scale:
            break
        Ja = J[:, active]
        step, *_ = np.linalg.lstsq(Ja, err, rcond=None)
        x[active] += step
        if norm3(step) < 1e-16 * max(scale, 1):
            break
    p = point_of(S, joints, x, p0)
    if not np.all(np.isfinite(x)) or norm3(p - pt) > max(1e-9 * scale, S.slack):
        return None
    for k, j in enumerate(joints):
        if S.revolute[j]:
            x[k] = float(wrap(x[k]))
    return x


def _point_jacobian(S: Screws, joints, x, p0):
    """Point position and its 3 x m Jacobian w.r.t. the joints' values."""
    # world poses of each joint's line after the preceding joints' motion, as a
    # rotation R and translation t (T = [R t]) built up joint by joint
    R = np.eye(3)
    t = np.zeros(3)
    axes, pts = [], []
    for j, xj in zip(joints, x):
        w, o = S.axis[j], S.point[j]
        axes.append(R @ w)
        pts.append(R @ o + t)
        if S.revolute[j]:
            Rj = _rot(w, xj)
            t = t + R @ (o - Rj @ o)
            R = R @ Rj
        else:
            t = t + R @ (w * xj)
    p = R @ p0 + t
    J = np.empty((3, len(joints)))
    for k, j in enumerate(joints):
        J[:, k] = cross3(axes[k], p - pts[k]) if S.revolute[j] else axes[k]
    return p, J


def _unique(S, joints, sols, scale):
    out = []
    for s in sols:
        dup = False
        for t in out:
            d = s.x - t.x
            for k, j in enumerate(joints):
                if S.revolute[j]:
                    d[k] = wrap(d[k])
            if np.all(np.abs(d) < 1e-7 * np.where([S.revolute[j] for j in joints], 1.0, scale)):
                dup = True
                break
        if not dup:
            out.append(s)
    return out


def _trace(S, joints, p0, pt, x, mode, roots, coeffs, f):
    """The quantities a student computes, as (label, value, kind) with kind one of
    'length', 'length2', 'angle', 'joint:<index>' (angle or length by joint type), 'text'."""
    a, b = joints[0], joints[1]
    c = joints[2] if len(joints) == 3 else None
    name = lambda j: f"joint {j + 1}"  # noqa: E731
    t = [("point to place, at q = 0", p0.tolist(), "length"),
         ("target point", pt.tolist(), "length")]
    if S.revolute[a]:
        o = _reference_point(S, a, b)
        t += [(f"{name(a)} leaves unchanged: height of the point along its axis",
               float(S.axis[a] @ (pt - o)), "length"),
              (f"{name(a)} leaves unchanged: squared distance from the axis point",
               float((pt - o) @ (pt - o)), "length2")]
    else:
        t += [(f"{name(a)} (prismatic) leaves unchanged: the offsets across its axis", "", "text")]
    if c is not None:
        t += [(f"eliminate {name(b)}: resultant in {name(c)} ({mode})", "", "text"),
              (f"real roots for {name(c)}", [float(r) for r in roots], f"joint:{c}"),
              (f"{name(c)}", float(x[2]), f"joint:{c}")]
    al, be, ga = coeffs
    k = int(np.argmax(np.maximum(np.abs(be), np.abs(ga))))
    kind = "length2" if (S.revolute[a] and k == 1) else "length"
    if S.revolute[b]:
        t += [(f"{name(b)}: alpha + beta cos + gamma sin = 0 with (alpha, beta, gamma)",
               [float(al[k]), float(be[k]), float(ga[k])], kind),
              (f"{name(b)} = atan2(gamma, beta) +- acos(-alpha / sqrt(beta^2 + gamma^2))",
               float(x[1]), f"joint:{b}")]
    else:
        t += [(f"{name(b)}: alpha + beta d + gamma d^2 = 0 with (alpha, beta, gamma)",
               [float(al[k]), float(be[k]), float(ga[k])], kind),
              (f"{name(b)}", float(x[1]), f"joint:{b}")]
    if S.revolute[a]:
        t += [(f"{name(a)} by subproblem 1: rotate the point before it", f.tolist(), "length"),
              (f"{name(a)}", float(x[0]), f"joint:{a}")]
    else:
        t += [(f"{name(a)} = offset along its axis", float(x[0]), f"joint:{a}")]
    return t
