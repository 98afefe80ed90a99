"""Gauss-Newton polishing: the one iteration every solver uses to finish a candidate
that is already near a solution.

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
"""

from __future__ import annotations

from typing import Callable

import numpy as np


def polish(evaluate: Callable, x, *, iterations: int, tol: float, damping: float = 0.0,
           stall: float = 0.0, give_up: dict | None = None, max_step: float = np.inf,
           settle: float | None = None):
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
    rows = np.arange(M)
    give_up = give_up or {}
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
        Jt = J.swapaxes(-1, -2)
        H = Jt @ J
        n = H.shape[-1]
        diag = H.reshape(H.shape[:-2] + (n * n,))[..., ::n + 1]          # a view of H
        diag += (damping * np.add.reduce(diag, axis=-1) + 1e-300)[..., None]
        return np.linalg.solve(H, Jt @ e[..., None])[..., 0]
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    keep = s > np.finfo(float).eps * max(J.shape[-2:]) * s[..., :1]
    f = np.where(keep, 1.0 / np.where(keep, s, 1.0), 0.0)
    ue = (e[..., None, :] @ U)[..., 0, :]                     # U^T e, (m, k)
    return ((f * ue)[..., None, :] @ Vt)[..., 0, :]
