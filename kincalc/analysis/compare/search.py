"""The branch search of :mod:`kincalc.analysis.compare`: the signs, offsets and base
that make a candidate's screws the reference's, joint by joint (the method is in the
package docstring).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ...spatial import invert_transform
from .screws import (adjoint, align, bracket, exp_screw, hat, line_miss, perpendiculars,
                     world_screws)

#: a linearised equation whose singular value is below this (relative) does
#: not determine the offsets along that direction; nor does one below the
#: tolerance (per radian or per length scale): a whole unit along it stays
#: within the tolerance, so the value a root lands on there is arbitrary and
#: is left to the later equations (see :meth:`Solver._cut`).
NULL_TOL = 1e-8
#: |d residual / d offset| below this: the equation does not depend on it.
INVARIANT_TOL = 1e-11
#: limits on the branch search (it stays far below them for real robots).
MAX_NODES = 2000
MAX_STARTS = 729


@dataclass
class Solution:
    """Signs and offsets (rad / m, ``(n,)``) of the candidate's joints, and the base and
    tool transforms when they are free; ``score`` orders complete solutions."""

    signs: np.ndarray
    offsets: np.ndarray
    base: np.ndarray | None       # B (4, 4)
    tool: np.ndarray | None       # T (4, 4)
    score: tuple = ()


@dataclass
class Failure:
    """Where the search stopped: the first joint whose axis no branch matches (how far
    off: angle rad, distance m), with the best solution up to it."""

    joint: int                    # 1-based; n + 1 for the tool
    angle: float | None
    distance: float | None
    solution: Solution


class Solver:
    """Offsets, signs and base from the screw equations, branch by branch."""

    def __init__(self, reference, candidate, allow_offsets, free_base, free_tool, L, tol):
        self.ref, self.cand = reference, candidate
        self.allow, self.free_base, self.free_tool = allow_offsets, free_base, free_tool
        self.L, self.tol = L, tol
        self.n = reference.dof
        self.rev = reference.is_revolute
        self.xi, self.M_r = world_screws(reference)
        self.eta0, self.M_c0 = world_screws(candidate)
        self.signs_allowed = (1, -1) if allow_offsets else (1,)
        self.W6 = np.array([1 / L] * 3 + [1.0] * 3)
        W4 = np.ones((3, 4))
        W4[:, 3] = 1 / L
        self.W4 = W4.ravel()
        self.last = self.n if free_tool else self.n + 1

    # -- setting up one problem (one alignment of the base) ---------------
    def _setup(self, s1):
        """Candidate screws and params for base alignment sign ``s1`` (free_base)."""
        n = self.n
        if self.free_base:
            A0 = align(self.eta0[0], s1 * self.xi[0], self.rev[0])
        else:
            A0 = np.eye(4)
        self.A0 = A0
        self.eta = adjoint(A0, self.eta0)
        self.M_c = A0 @ self.M_c0
        params = []                      # (screw, revolute, position, joint)
        if self.free_base:
            x1 = self.xi[0]
            if self.rev[0]:
                params += [(x1.copy(), True, 0, None),
                           (np.concatenate([x1[3:], np.zeros(3)]), False, 0, None)]
            else:
                u = x1[:3]
                a, b = perpendiculars(u)
                params += [(np.concatenate([np.zeros(3), u]), True, 0, None)]
                params += [(np.concatenate([d, np.zeros(3)]), False, 0, None) for d in (a, b, u)]
        if self.allow:
            for i in range(n):
                if self.free_base and i == 0:
                    continue             # absorbed by the base
                params.append((self.eta[i], bool(self.rev[i]), i + 1, i))
        self.params = params
        self.P = len(params)
        self.pos = np.array([p[2] for p in params], dtype=int)

    def run(self):
        """([solutions best first] or None, failure or None)."""
        leaves, failures = [], []
        for s1 in (self.signs_allowed if self.free_base else (1,)):
            self._setup(s1)
            self.leaves, self.failure, self.nodes = [], None, 0
            signs = np.zeros(self.n, dtype=int)
            if self.free_base:
                signs[0] = s1
            first = 2 if self.free_base else 1
            self._visit(first, np.zeros(self.P), signs, frozenset())
            leaves += [self._finish(x, sg) for x, sg in self.leaves]
            if self.failure is not None:
                failures.append(self._failure_result(*self.failure))
        if leaves:
            leaves.sort(key=lambda s: s.score)
            return leaves[:4], None
        failures.sort(key=lambda f: (-f.joint, f.angle or 0.0, f.distance or 0.0))
        return None, failures[0]

    # -- the branch search ----------------------------------------------------
    def _visit(self, step, x, signs, U):
        self.nodes += 1
        if self.nodes > MAX_NODES:
            return
        if step > self.last:
            self.leaves.append((x, signs))
            return
        # the params that join now: those of G_{step-1} not met before
        first = 2 if self.free_base else 1
        new = [p for p in range(self.P) if self.pos[p] <= step - 1
               and (step == first or self.pos[p] == step - 1)]
        V = sorted(set(U) | set(new))
        roots, miss = self._solve(step, V, x, signs)
        if not roots:
            if self.failure is None or step > self.failure[0] or \
                    (step == self.failure[0] and miss[0] < self.failure[1][0]):
                self.failure = (step, miss, x, signs)
            return
        for x2, s, pinned in roots:
            signs2 = signs.copy()
            if step <= self.n:
                signs2[step - 1] = s
            self._visit(step + 1, x2, signs2, frozenset(set(V) - pinned))

    # -- evaluating the equations ------------------------------------------
    def _chain(self, X):
        """For param values ``X (S, P)``: G_k (S, 4, 4) for k = 0..n and each
        param's current world screw (S, P, 6)."""
        S = X.shape[0]
        G = np.broadcast_to(np.eye(4), (S, 4, 4)).copy()
        Gs = [None] * (self.n + 1)
        Z = np.zeros((S, self.P, 6))
        p = 0
        for k in range(self.n + 1):
            while p < self.P and self.pos[p] == k:
                screw, revolute, _, _ = self.params[p]
                Z[:, p] = adjoint(G, screw)
                G = G @ exp_screw(screw, revolute, X[:, p])
                p += 1
            Gs[k] = G
        return Gs, Z

    def _residuals(self, X, signs, steps, V, step_signs=None):
        """Residuals (S, m) and Jacobian (S, m, |V|) of the equations ``steps``.

        ``signs`` (n,) gives the sign of each earlier screw equation; the
        current one (the last of ``steps`` when it is a screw) takes
        ``step_signs (S,)``.
        """
        Gs, Z = self._chain(X)
        S = X.shape[0]
        rs, Js = [], []
        for j in steps:
            if j <= self.n:
                y = adjoint(Gs[j - 1], self.eta[j - 1])
                s = step_signs if (step_signs is not None and j == steps[-1]) \
                    else np.full(S, signs[j - 1])
                rs.append((y - s[:, None] * self.xi[j - 1]) * self.W6)
                cols = [(bracket(Z[:, p], y) * self.W6) if self.pos[p] <= j - 1
                        else np.zeros((S, 6)) for p in V]
            else:
                GM = Gs[self.n] @ self.M_c
                rs.append(((GM - self.M_r)[:, :3, :].reshape(S, 12)) * self.W4)
                cols = [((hat(Z[:, p]) @ GM)[:, :3, :].reshape(S, 12)) * self.W4 for p in V]
            Js.append(np.stack(cols, axis=-1) if V else np.zeros((S, rs[-1].shape[1], 0)))
        return np.concatenate(rs, axis=1), np.concatenate(Js, axis=1)

    def _solve(self, step, V, x, signs):
        """Roots [(x, sign, pinned params)] of equation ``step`` and the miss
        (residual, x, sign) of the best attempt."""
        signs_try = self.signs_allowed if step <= self.n else (0,)
        if not V:
            roots, best = [], None
            for s in signs_try:
                r, _ = self._residuals(x[None], signs, [step], V, np.array([s]))
                res = float(np.linalg.norm(r))
                if best is None or res < best[0]:
                    best = (res, x, s)
                if res < self.tol:
                    roots.append((x, s, frozenset()))
            return roots, best
        if len(V) == 1:
            return self._solve_one(step, V[0], x, signs, signs_try)
        return self._solve_many(step, V, x, signs, signs_try)

    def _split(self, p, x, upto):
        """A, B (4, 4): the products of the params before and after ``p`` with
        position <= ``upto``."""
        A, B = np.eye(4), np.eye(4)
        for k in range(self.P):
            if self.pos[k] > upto or k == p:
                continue
            E = exp_screw(self.params[k][0], self.params[k][1], np.array(x[k]))
            if k < p:
                A = A @ E
            else:
                B = B @ E
        return A, B

    def _solve_one(self, step, p, x, signs, signs_try):
        screw, revolute = self.params[p][0], self.params[p][1]
        A, B = self._split(p, x, step - 1 if step <= self.n else self.n)
        roots, best = [], None
        for s in signs_try:
            if step <= self.n:
                y = adjoint(B, self.eta[step - 1])
                t = adjoint(invert_transform(A), s * self.xi[step - 1])
                r0 = (y - t) * self.W6
                a1 = bracket(screw, y)
                a2 = bracket(screw, a1) * self.W6
                a1 = a1 * self.W6
            else:
                D = invert_transform(A) @ self.M_r @ invert_transform(B @ self.M_c)
                Z = hat(screw)
                r0 = ((np.eye(4) - D)[:3]).ravel() * self.W4
                a1 = (Z[:3]).ravel() * self.W4
                a2 = ((Z @ Z)[:3]).ravel() * self.W4
            free, xs, res = _roots_1d(r0, a1, a2, revolute, self.tol)
            # an equation that hardly depends on the param does not pin it: the
            # later equations solve for it (a root on rounding noise lands anywhere)
            weak = (np.linalg.norm(a1) + 2 * np.linalg.norm(a2) if revolute
                    else np.linalg.norm(a1) * self.L) < self.tol
            if weak and not free and np.linalg.norm(r0) < self.tol:
                free, res = True, float(np.linalg.norm(r0))
            if free:
                if res < self.tol:
                    roots.append((x, s, frozenset()))
                cand = [(res, x[p])]
            else:
                cand = xs
            for resk, xk in cand:
                xn = x.copy()
                xn[p] = xk
                if best is None or resk < best[0]:
                    best = (resk, xn, s)
                if not free and resk < self.tol:
                    roots.append((xn, s, frozenset() if weak else frozenset([p])))
        return roots, best

    def _cut(self, sv):
        """Singular values (of a Jacobian in units of rad and length scale) at or
        below this leave their direction undetermined: rounding, or a direction
        along which a whole unit stays within the tolerance."""
        return max(NULL_TOL * max(1.0, float(sv.max()) if sv.size else 0.0), self.tol)

    def _pinv(self, A):
        """Pseudo-inverse of the stack ``A (S, m, k)`` without the directions
        :meth:`_cut` leaves undetermined (np.linalg.pinv's relative cut inverts a
        column of rounding noise when every column is: the step then explodes)."""
        U, sv, Vt = np.linalg.svd(A, full_matrices=False)
        cut = np.array([[self._cut(row)] for row in sv])
        inv = np.where(sv > cut, 1.0 / np.where(sv > cut, sv, 1.0), 0.0)
        return np.einsum("sij,si,sli->sjl", Vt, inv, U)

    def _solve_many(self, step, V, x, signs, signs_try):
        """Several unknowns. Once the revolute ones are fixed the equations are
        affine in the prismatic ones, so those are projected out by linear
        least squares; the revolute ones (usually one) are gridded, and damped
        Gauss-Newton on all of them starts from the grid's local minima."""
        first = 2 if self.free_base else 1
        lo = max(min(int(self.pos[p]) for p in V) + 1, first)
        steps = list(range(lo, step + 1))
        Vr = [p for p in V if self.params[p][1]]
        Vp = [i for i, p in enumerate(V) if not self.params[p][1]]
        if len(Vr) == 0:
            grid = np.zeros((1, 0))
        elif len(Vr) == 1:
            grid = np.linspace(-np.pi, np.pi, 72, endpoint=False)[:, None]
        else:
            k = max(3, int(MAX_STARTS ** (1 / len(Vr))))
            axes = [np.linspace(-np.pi, np.pi, k, endpoint=False)] * len(Vr)
            grid = np.array(list(itertools.product(*axes)))
        starts = []
        for s in signs_try:
            X = np.repeat(x[None], len(grid), axis=0)
            if Vr:
                X[:, Vr] = grid
            sg = np.full(len(grid), s)
            r, J = self._residuals(X, signs, steps, V, sg)
            if Vp:
                Jp = J[:, :, Vp]
                d = -np.einsum("sij,sj->si", self._pinv(Jp * self.L), r) / self.L
                X[:, [V[i] for i in Vp]] += d
                r = r + np.einsum("sij,sj->si", Jp, d)
            g = np.einsum("ij,ij->i", r, r)
            if len(Vr) == 1:
                keep = np.nonzero((g <= np.roll(g, 1)) & (g <= np.roll(g, -1)))[0]
            else:
                keep = np.argsort(g)[:16]
            starts += [(X[k], s) for k in keep]
        X = np.array([xs for xs, _ in starts])
        sg = np.array([s for _, s in starts])
        X, r, J = _levenberg_marquardt(
            lambda Xv, rows=slice(None): self._residuals(Xv, signs, steps, V, sg[rows]),
            X, V, self.tol)
        res = np.linalg.norm(r, axis=1)
        k = int(np.argmin(res))
        best = (float(res[k]), X[k], int(sg[k]))
        scale = np.array([1.0 if self.params[p][1] else self.L for p in V])
        rev = np.array([self.params[p][1] for p in V])
        roots, kept = [], []
        for k in np.argsort(res):
            if res[k] >= self.tol:
                break
            sv, vt = np.linalg.svd(J[k] * scale, full_matrices=True)[1:]
            rank = int(np.sum(sv > self._cut(sv)))
            null = vt[rank:]
            fixed = np.array([null.shape[0] == 0 or np.linalg.norm(null[:, i]) < 1e-6
                              for i in range(len(V))], dtype=bool)
            pinned = frozenset(p for i, p in enumerate(V) if fixed[i])
            # two roots are one branch when they pin the same params to the same values
            # (and differ by whole turns, or along the directions the equations leave
            # free): the later equations solve the params left free afresh
            xk = X[k, V] / scale
            dup = False
            for j, xj, pj in kept:
                if sg[j] != sg[k] or pj != pinned:
                    continue
                d = np.where(rev, np.remainder(xk - xj + np.pi, 2 * np.pi) - np.pi, xk - xj)
                if null.shape[0]:
                    d = d - null.T @ (null @ d)
                if not fixed.any() or np.max(np.abs(d[fixed])) < 1e-7:
                    dup = True
                    break
            if dup:
                continue
            kept.append((k, xk, pinned))
            roots.append((X[k].copy(), int(sg[k]), pinned))
        return roots, best

    # -- results ----------------------------------------------------------------
    def _finish(self, x, signs) -> Solution:
        x = x.copy()
        for p in range(self.P):
            if self.params[p][1]:
                x[p] = math.remainder(x[p], 2 * math.pi)
        # offsets nothing determined (the tool's, or a joint commuting with all later
        # ones when the tool is free) are set to 0 when that keeps every equation
        steps = list(range(2 if self.free_base else 1, self.last + 1))
        for p in range(self.P):
            if self.params[p][3] is None or x[p] == 0:
                continue
            trial = x.copy()
            trial[p] = 0.0
            r, _ = self._residuals(trial[None], signs, steps, [])
            if np.linalg.norm(r) < self.tol:
                x = trial
        return self._solution(x, signs)

    def _solution(self, x, signs) -> Solution:
        n = self.n
        offsets = np.zeros(n)
        for p in range(self.P):
            j = self.params[p][3]
            if j is not None:
                offsets[j] = x[p]
        signs = np.where(signs == 0, 1, signs).astype(float)
        base = tool = None
        Binv = None
        if self.free_base:
            E = np.eye(4)
            for p in range(self.P):
                if self.pos[p] == 0:
                    E = E @ exp_screw(self.params[p][0], self.params[p][1], np.array(x[p]))
            Binv = E @ self.A0
            base = invert_transform(Binv)
        if self.free_tool:
            Tc = self.cand.fk(offsets)
            tool = invert_transform(self.M_r) @ (Binv if Binv is not None else np.eye(4)) @ Tc
        flips = int(np.sum(signs < 0))
        size = float(np.sum(np.abs(offsets) / np.where(self.rev, 1.0, self.L)))
        return Solution(signs, offsets, base, tool, (flips, round(size, 9)))

    def _failure_result(self, step, miss, x, signs) -> Failure:
        res, xb, s = miss
        Gs, _ = self._chain(xb[None])
        sol = self._solution(xb, signs if step > self.n else _with(signs, step - 1, s))
        if step <= self.n:
            y = adjoint(Gs[step - 1][0], self.eta[step - 1])
            angle, dist = line_miss(y, (s or 1) * self.xi[step - 1], bool(self.rev[step - 1]))
            if self.allow:   # the sign is free: the angle between undirected axes
                angle = min(angle, math.pi - angle)
        else:
            GM = Gs[self.n][0] @ self.M_c
            chord = np.linalg.norm(GM[:3, :3] - self.M_r[:3, :3]) / (2 * math.sqrt(2))
            angle = 2 * math.asin(min(1.0, chord))
            dist = float(np.linalg.norm(GM[:3, 3] - self.M_r[:3, 3]))
        return Failure(step, angle, dist, sol)


def _with(signs, i, s):
    out = signs.copy()
    out[i] = s if s else 1
    return out


def _roots_1d(r0, a1, a2, revolute, tol):
    """Roots of ``r(x) = r0 + sin(x) a1 + (1 - cos x) a2`` (revolute) or
    ``r0 + x a1`` (prismatic), vectors of any length.

    Returns ``(free, [(|r|, x), ...], |r0|)``: ``free`` when r does not depend on
    x; otherwise every local minimum of |r| (the roots are those with |r| ~ 0).
    ``|r|^2`` is a trigonometric polynomial of degree 2 in x, so it has at most
    two minima; a 72-point grid separates them and Gauss-Newton polishes each.
    """
    scale = max(1.0, float(np.linalg.norm(r0)))
    if np.linalg.norm(a1) < INVARIANT_TOL * scale and np.linalg.norm(a2) < INVARIANT_TOL * scale:
        return True, [], float(np.linalg.norm(r0))
    if not revolute:
        x = -float(a1 @ r0) / float(a1 @ a1)
        return False, [(float(np.linalg.norm(r0 + x * a1)), x)], 0.0
    grid = np.linspace(-np.pi, np.pi, 72, endpoint=False)
    R = r0 + np.sin(grid)[:, None] * a1 + (1 - np.cos(grid))[:, None] * a2
    g = np.einsum("ij,ij->i", R, R)
    mins = np.nonzero((g <= np.roll(g, 1)) & (g <= np.roll(g, -1)))[0]
    x = grid[mins]
    for _ in range(30):
        s, c = np.sin(x)[:, None], np.cos(x)[:, None]
        r = r0 + s * a1 + (1 - c) * a2
        dr = c * a1 + s * a2
        num = np.einsum("ij,ij->i", r, dr)
        den = np.einsum("ij,ij->i", dr, dr)
        step = -num / np.where(den > 0, den, 1.0)
        x = x + np.clip(step, -0.3, 0.3)
        if np.all(np.abs(step) < 1e-15):
            break
    r = r0 + np.sin(x)[:, None] * a1 + (1 - np.cos(x))[:, None] * a2
    res = np.linalg.norm(r, axis=1)
    out = []
    for rk, xk in sorted(zip(res.tolist(), x.tolist())):
        xk = math.remainder(xk, 2 * math.pi)
        if all(abs(math.remainder(xk - xo, 2 * math.pi)) > 1e-9 for _, xo in out):
            out.append((rk, xk))
    return False, out, 0.0


def _levenberg_marquardt(fun, X, V, tol, iterations=50):
    """Damped Gauss-Newton on every start at once; ``fun(X, rows) -> (r (S, m), J (S, m, v))``
    for the starts ``rows`` (all by default), J the derivative by the params ``V``.
    Returns (X, r, J) at the end.

    A start stops when its residual is at rounding level or its step is."""
    r, J = fun(X)
    cost = np.einsum("ij,ij->i", r, r)
    lam = np.full(X.shape[0], 1e-4)
    eye = np.eye(len(V))
    active = np.ones(X.shape[0], dtype=bool)
    for _ in range(iterations):
        a = np.nonzero(active)[0]
        if a.size == 0:
            break
        Ja, ra = J[a], r[a]
        JTJ = np.einsum("smi,smj->sij", Ja, Ja)
        g = np.einsum("smi,sm->si", Ja, ra)
        diag = np.diagonal(JTJ, axis1=1, axis2=2)
        Amat = JTJ + lam[a, None, None] * (eye * diag[:, None, :] + 1e-9 * eye)
        d = np.linalg.solve(Amat, -g[..., None])[..., 0]
        Xt = X[a].copy()
        Xt[:, V] += d
        rt, Jt = fun(Xt, a)
        ct = np.einsum("ij,ij->i", rt, rt)
        ok = ct < cost[a]
        # near a root Gauss-Newton converges quadratically; a start whose accepted
        # step gains less than 1% while far from zero sits in a local minimum
        stalled = ok & (ct > 0.99 * cost[a]) & (ct > (0.01 * tol) ** 2)
        idx = a[ok]
        X[idx], r[idx], J[idx], cost[idx] = Xt[ok], rt[ok], Jt[ok], ct[ok]
        lam[a] = np.clip(np.where(ok, lam[a] * 0.1, lam[a] * 10.0), 1e-12, 1e12)
        small = np.abs(d).max(axis=1) < 1e-14
        active[a] = ~((cost[a] < 1e-30) | small | stalled | (lam[a] >= 1e8))
    return X, r, J
