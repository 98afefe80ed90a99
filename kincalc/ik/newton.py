"""Newton's method for kinematic equations, batched: Gauss-Newton polishing of candidates
already near a solution (:func:`polish`), and Levenberg-Marquardt descent from starts that
may be far from one (:func:`levenberg_marquardt`).

Three places end near, not on, a solution: roots of a quartic or a sampled resultant
(good to ~1e-10; :mod:`kincalc.ik.place`), the eigenvalues of the general 6R elimination
(:mod:`kincalc.ik.general6r`), and the closed form of the nearest structured robot for a
robot only nearly of its family (:mod:`kincalc.ik.refine`). Each supplies its equations
as a residual and their Jacobian; this module runs the iteration on a batch of
candidates: Gauss-Newton steps ``J dx = e`` in the least-squares sense, each candidate
stopping on its own once converged. From 1e-7 off, quadratic convergence reaches
rounding in about three steps.

The step is damped least squares: with the SVD ``J = U S V^T``, ``dx = V f(S) U^T e``
with the filter factors ``f(s) = s / (s^2 + lambda)``, ``lambda = damping |J|_F^2``.
With ``damping = 0`` it is the minimum-norm least-squares step (the pseudo-inverse):
fewer joints than equations and rank-deficient Jacobians are handled alike. A small
damping keeps a step along a nearly singular direction (where two solutions are about
to merge, and the linear model does not hold) short; a robot only nearly of its family
needs the undamped step, since there the direction it must move along is the nearly
singular one.

The descent is for a start that may be far from a solution, or a target that has none
(the nearest reachable point, :mod:`kincalc.ik.nearest`; the numerical solver,
:mod:`kincalc.ik.numeric`): Levenberg-Marquardt, whose damping adapts (it falls after a
step that lowers ``|e|`` and rises after one that does not, which is rejected), with box
limits on the variables (a variable on a limit that the step pushes outwards is held and
the step solved again without it, then the step is clipped to the box).
"""

from __future__ import annotations

from typing import Callable

import numpy as np


def polish(evaluate: Callable, x, *, iterations: int, tol: float, damping: float = 0.0,
           stall: float = 0.0, give_up: dict | None = None, max_step: float = np.inf,
           settle: float | None = None, fixed=None):
    """Gauss-Newton on a batch of candidates, each stopping when it has converged.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(x (m, n), rows (m,)) -> (e (m, r), jacobian)``: the residuals
        ``target - model(x)`` of the candidates ``rows`` (indices into ``x``), in units
        that make their components comparable (lengths divided by the robot's scale),
        and ``jacobian(keep (m,) bool) -> J (k, r, n)``, the model's derivative
        ``d model / d x`` for the candidates ``keep`` only (it is needed only for those
        that take a step).
    x : array_like (M, n)
        Starting values (rad / m); not modified.
    iterations : int
        Steps at most.
    tol : float
        A candidate has converged when its largest residual ``max |e|`` is below it.
    damping : float
        ``lambda / |J|_F^2`` of the step (module docstring); 0: the pseudo-inverse.
    stall : float
        Also stop a candidate whose residual is below ``stall`` and no longer at least
        halves (rounding reached before ``tol``); 0 disables.
    give_up : dict, optional
        ``{step: bound}``: after that many steps drop candidates whose residual is still
        above ``bound`` (spurious starts); ``bound`` a float, or an ``(M,)`` array of one
        bound per candidate.
    max_step : float
        Steps are shortened to at most this in the largest component.
    settle : float, optional
        A bound ``C`` on the model's second derivatives (every component, anywhere): a step
        ``dx`` from ``e`` leaves at most ``b = max |e - J dx| + C (|dx|_1 + max |e|) |dx|_1``
        (Taylor), so one with ``b < tol / 10`` stops with ``b`` as its residual, without the
        evaluation that would only confirm it. None: every step is evaluated.
    fixed : array_like (M, n) of bool, optional
        Variables each candidate keeps at its start (their Jacobian columns taken as 0).

    Returns
    -------
    x : ndarray (M, n)
        The polished values; a candidate that did not converge holds its last iterate.
    residual : ndarray (M,)
        Each candidate's last ``max |e|`` (or the bound ``b`` of ``settle``).
    moved : ndarray (M,) bool
        The candidates that took a step.
    """
    x = np.array(x, dtype=float)
    M = len(x)
    res = np.full(M, np.inf)
    moved = np.zeros(M, bool)
    rows, give_up = np.arange(M), give_up or {}
    moving = None if fixed is None else np.where(fixed, 0.0, 1.0)[:, None, :]   # (M, 1, n)
    for it in range(iterations + 1):
        if not len(rows):
            break
        # the first pass evaluates every row: x itself (evaluate does not modify it)
        e, jacobian = evaluate(x[rows] if it else x, rows)
        r = np.maximum.reduce(np.abs(e), axis=-1) if e.shape[-1] else np.zeros(len(rows))
        go = r >= tol
        if stall and it:
            go &= ~((r < stall) & (r > 0.5 * res[rows]))
        if it in give_up:
            bound = give_up[it]
            go &= r < (bound[rows] if np.ndim(bound) else bound)
        res[rows] = r
        stepping = np.count_nonzero(go)
        if it == iterations or not stepping:
            break
        J = jacobian(go)
        if stepping < len(go):                 # (every row steps: the common case)
            rows, e, r = rows[go], e[go], r[go]
        J = J if moving is None else J * moving[rows]
        moved[rows] = True
        dx, adx = _limited(_step(J, e, damping), max_step)
        x[rows] += dx
        if settle is not None:
            rows = _unsettled(rows, res, e, r, J, dx, adx, settle, 0.1 * tol)
    return x, res, moved


def _limited(dx, max_step):
    """``(dx, |dx|)``: the steps ``dx (m, n)`` shortened to at most ``max_step`` in their
    largest component, and their absolute values."""
    adx = np.abs(dx)
    if max_step < np.inf:
        big = np.maximum.reduce(adx, axis=-1)
        if np.count_nonzero(big > max_step):          # else every factor below is 1
            dx = dx * np.minimum(1.0, max_step / np.maximum(big, 1e-300))[:, None]
            adx = np.abs(dx)
    return dx, adx


def _unsettled(rows, res, e, emax, J, dx, adx, C, bound):
    """The ``rows`` whose step ``dx (m, n)`` (``adx`` its absolute values) from residual
    ``e (m, r)`` (``emax (m,)`` its largest absolute value per row; Jacobian ``J``) may leave
    a residual of ``bound`` or more (the ``settle`` bound of :func:`polish`, with ``C``); the
    others get that bound in ``res``."""
    l1 = np.add.reduce(adx, axis=-1)
    b = np.maximum.reduce(np.abs(e - (J @ dx[..., None])[..., 0]), axis=-1) + C * (l1 + emax) * l1
    done = b < bound
    if not np.count_nonzero(done):
        return rows
    res[rows[done]] = b[done]
    return rows[~done]


def _step(J, e, damping: float) -> np.ndarray:
    """``dx (m, n)``: the damped least-squares step of ``J (m, r, n)``, ``e (m, r)``.

    Damped, through the normal equations ``(J^T J + lambda I) dx = J^T e``: the damping
    bounds their condition number by ``1 / damping``, and the directions it does not
    damp keep their accuracy (several times faster than an SVD per candidate). Undamped,
    through the SVD, without squaring the condition number."""
    if damping:
        mu = damping * np.einsum("...rn,...rn->...", J, J) + 1e-300     # tr(J^T J) = |J|_F^2
        return _solved(J, e, mu, False)
    return _svd_step(J, e, 0.0)


def _svd_step(J, e, mu) -> np.ndarray:
    """``dx (m, n) = V f(S) U^T e`` of ``J (m, r, n) = U S V^T``, ``e (m, r)``, with the
    filter factors ``f(s) = s / (s^2 + mu)`` (``mu (m,)`` or 0: the pseudo-inverse), and 0
    for singular values below rounding (``eps max(r, n)`` times the largest)."""
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    keep = s > np.finfo(float).eps * max(J.shape[-2:]) * s[..., :1]
    safe = np.where(keep, s, 1.0)
    f = np.where(keep, 1.0 / (safe + np.asarray(mu, float)[..., None] / safe), 0.0)
    ue = (e[..., None, :] @ U)[..., 0, :]                     # U^T e, (m, k)
    return ((f * ue)[..., None, :] @ Vt)[..., 0, :]


#: the least damping of :func:`levenberg_marquardt` (relative to ``1 + tr(J^T J) / n``):
#: far below the square of a nearly singular Jacobian's smallest singular value (1e-6
#: next to a singularity), so that convergence along it stays quadratic
LAMBDA_MIN = 1e-18


def levenberg_marquardt(evaluate: Callable, x, *, lo, hi, iterations: int, tol: float,
                        fixed=None, damping: float = 1e-3, max_step: float = 0.5,
                        floor: float = 0.0, creep: int = 0, give_up: float = 1e6):
    """Levenberg-Marquardt from a batch of starts, each stopping on its own.

    The step solves ``(J^T J + mu I) dx = J^T e``, ``mu = lambda (1 + tr(J^T J) / n)``
    (or its dual ``dx = J^T (J J^T + mu I)^-1 e``, the same step, when there are fewer
    residuals than free variables), shortened to at most ``max_step`` in norm. ``lambda`` starts
    at ``damping``; it is divided by 3 (down to :data:`LAMBDA_MIN`) after a step that
    lowers ``|e|`` and multiplied by 4 after one that does not (which is rejected).

    Parameters
    ----------
    evaluate : callable
        ``evaluate(x (m, n), rows (m,)) -> (e (m, r), jacobian)``: the residuals ``target -
        model(x)`` of the candidates ``rows`` (indices into ``x``), in comparable units
        (inf where the model refuses ``x``), and ``jacobian(keep (m,) bool) -> J (k, r,
        n)``, ``d model / d x`` of the candidates ``keep`` (asked for accepted points only).
    x : array_like (M, n)
        Starts, within the limits (not modified).
    lo, hi : array_like (n,) or (M, n)
        The box (``-inf`` / ``inf`` for none).
    iterations, tol : int, float
        Steps at most (accepted or not); a candidate has converged when ``|e| <= tol``.
    fixed : array_like (n,) or (M, n) of bool, optional
        Variables held at their start.
    damping, max_step : float
        The first ``lambda`` (small for starts next to a solution: quadratic convergence
        from the first step), and the longest step (norm).
    floor, creep, give_up : float, int, float
        A descent also ends at a rejected step once ``|e| <= floor`` (rounding reached;
        0: off), after ``creep`` accepted steps in a row that each lower ``|e|`` by less
        than a part in 1e9 (a minimum that is no solution; 0: off), and when ``lambda``
        reaches ``give_up`` (no step lowers ``|e|``).

    Returns
    -------
    x, e, steps : ndarray (M, n), (M, r), (M,) of int
        The best point each candidate reached, its residuals and the iterations taken.
    """
    x = np.array(x, dtype=float)
    M, n = x.shape
    lo, hi = np.broadcast_to(lo, (M, n)), np.broadcast_to(hi, (M, n))
    movable = np.ones((M, n), bool) if fixed is None else ~np.broadcast_to(fixed, (M, n))
    e, jacobian = evaluate(x, np.arange(M))
    e = np.array(e, dtype=float)                            # (written in: the caller's copy)
    err = np.einsum("mr,mr->m", e, e)
    active = (err > tol ** 2) & np.isfinite(err)          # (a start the model refuses stays)
    if not np.count_nonzero(active):
        return x, e, np.zeros(M, int)
    J = np.zeros(e.shape + (n,))
    J[active] = jacobian(active)
    lam, steps, crept = np.full(M, float(damping)), np.zeros(M, int), np.zeros(M, int)
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if not idx.size:
            break
        xa, lo_a, hi_a = x[idx], lo[idx], hi[idx]
        step = _held_step(J[idx], e[idx], lam[idx], xa, lo_a, hi_a, movable[idx])
        moved = np.sqrt(np.einsum("mn,mn->m", step, step))
        step *= np.minimum(1.0, max_step / np.maximum(moved, 1e-300))[:, None]
        xn = np.clip(xa + step, lo_a, hi_a)
        en, jac_n = evaluate(xn, idx)
        errn, before = np.einsum("mr,mr->m", en, en), err[idx]
        steps[idx] += 1
        # |en|^2 < |e|^2 as (en - e).(en + e) < 0: a gain far below |e|^2 still counts
        better = np.einsum("mr,mr->m", en - e[idx], en + e[idx]) < 0
        ok = idx[better]
        stop = (better & (moved < 1e-15)) | (moved == 0)       # (every free variable held)
        if floor:                 # a rejected step below it: rounding is reached
            stop |= ~better & (before <= floor ** 2)
        if creep:
            crept[ok] = np.where(errn[better] > (1 - 1e-9) ** 2 * before[better], crept[ok] + 1, 0)
            stop |= better & (crept[idx] >= creep)
        x[ok], e[ok], err[ok] = xn[better], en[better], errn[better]
        if ok.size:
            J[ok] = jac_n(better)
        lam[idx] = np.where(better, np.maximum(lam[idx] / 3.0, LAMBDA_MIN), lam[idx] * 4.0)
        active[idx] = (err[idx] > tol ** 2) & (lam[idx] < give_up) & ~stop
    return x, e, steps


def pushed_out(x, lo, hi, step, slack: float = 0.0) -> np.ndarray:
    """Which variables lie on a limit (within ``slack``) that ``step`` pushes them beyond.

    Parameters
    ----------
    x, step : ndarray (..., n)
        The variables and a step (any scale: its sign is read).
    lo, hi : array_like, broadcasting with ``x``
        The limits.
    slack : float
        How near a limit counts as on it (units of ``x``).

    Returns
    -------
    ndarray (..., n) of bool
    """
    return ((x <= lo + slack) & (step < 0)) | ((x >= hi - slack) & (step > 0))


def _held_step(J, e, lam, x, lo, hi, free) -> np.ndarray:
    """The step ``(m, n)`` of :func:`_damped` from ``x (m, n)`` in the box ``lo, hi``,
    moving the variables ``free (m, n)`` only: a variable on a limit that the step pushes
    outwards is held, and the step solved again without it (clipping alone would shorten
    the other variables' steps too)."""
    step = _damped(J, e, lam) if free.all() else _damped(J, e, lam, free)
    for _ in range(x.shape[1]):
        held = pushed_out(x, lo, hi, step)
        if not held.any():
            break
        free = free & ~held
        r = np.flatnonzero(held.any(axis=1))
        step[r] = _damped(J[r], e[r], lam[r], free[r])
    return step


def _damped(J, e, lam, free=None) -> np.ndarray:
    """``dx (m, n)``: the Levenberg-Marquardt step of ``J (m, r, n)``, ``e (m, r)`` with
    damping ``lam (m,)`` (:func:`levenberg_marquardt`) moving the variables ``free (m, n)``
    only (None: all), through the normal equations of the free variables, or their dual
    where there are more of them than residuals (a redundant arm: there the normal
    equations are singular but for the damping). Should either be singular to rounding,
    the step is the same one through the SVD."""
    m, r, n = J.shape
    if free is not None:
        J = J * free[:, None, :]
    mu = lam * (1.0 + np.einsum("mrn,mrn->m", J, J) / n)         # tr(J^T J) = |J|_F^2
    dual = (n if free is None else np.count_nonzero(free, axis=1)) > r
    try:
        if np.all(dual):
            return _solved(J, e, mu, True)
        if not np.any(dual):
            return _solved(J, e, mu, False)
        out = np.empty((m, n))
        out[dual] = _solved(J[dual], e[dual], mu[dual], True)
        out[~dual] = _solved(J[~dual], e[~dual], mu[~dual], False)
        return out
    except np.linalg.LinAlgError:
        step = _svd_step(J, e, mu)
        return step if free is None else step * free


def _solved(J, e, mu, dual: bool) -> np.ndarray:
    """:func:`_damped`'s step through the dual ``J^T (J J^T + mu I)^-1 e`` or the normal
    equations ``(J^T J + mu I)^-1 J^T e``."""
    m = len(J)
    Jt = J.swapaxes(-1, -2)
    A = J @ Jt if dual else Jt @ J                                 # (m, k, k)
    k = A.shape[-1]
    A.reshape(m, k * k)[:, ::k + 1] += mu[:, None]                 # (the diagonal, a view)
    if dual:
        return (Jt @ np.linalg.solve(A, e[..., None]))[..., 0]
    return np.linalg.solve(A, Jt @ e[..., None])[..., 0]
