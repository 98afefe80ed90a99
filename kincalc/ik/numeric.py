"""Numerical inverse kinematics: the solution nearest a start configuration.

For what no closed form covers: redundant arms (seven or more joints, the
8-DOF hybrid arm of Bayram's paper, seed 004), structures outside
:mod:`kincalc.ik.families`, and mechanisms known only through their own FK
function. Unlike the analytic solvers this finds one solution, not every
branch: the one a motion from the start configuration ``q0`` would take, with
the *least change* from ``q0``.

Method
------
Variables are scaled so that revolute and prismatic joints compare:
``x_j = q_j`` (rad) for revolute joints and ``x_j = q_j / L`` for prismatic
ones, with ``L`` the robot's characteristic length; the pose error is
``e = [(p* - p) / L, log(R* R^T)]`` (world frame; the rotation vector that
carries the current orientation onto the target).

1. Levenberg-Marquardt on ``e`` with the geometric Jacobian (or central
   differences of the user's FK), steps projected onto the joint limits
   (joints at a limit that the step pushes outward are held for that step).
2. On the solution manifold, least change: repeat a step ``(I - J^+ J)(x0 - x)``
   in the null space of the task followed by Gauss-Newton back onto the
   manifold, until the null-space step vanishes. The result satisfies the
   first-order condition of ``min |x - x0|`` subject to ``f(x) = T*``: ``x - x0``
   lies in the row space of ``J`` (Whitney's resolved-rate pseudo-inverse,
   1969, applied at the position level). A step that would carry a joint past
   its limit stops exactly on it; the joint stays there while the condition
   (with a multiplier of the right sign) asks it to.
3. If the start does not converge within the limits, the same search with the
   revolute joints turning freely (their limits lifted, the result wrapped back
   into the ranges by whole turns, then polished within the limits): a range of
   nearly a full turn leaves a gap that a projected step cannot cross. Then
   restarts, searched the same way (within the limits for a few iterations
   first), from seeded random configurations inside the limits, until one
   converges (then the least-change step runs from there towards ``q0``).

A user's ``fk`` may raise ValueError (or an ArithmeticError) for joints where the
mechanism cannot be assembled: such steps are rejected and such restarts skipped.

Convergence: ``|e| <= 1e-10``; iterations continue to the rounding floor.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..jacobian import finite_difference_jacobian
from .newton import levenberg_marquardt, pushed_out
from ..spatial import TURN, into_limits, into_turn, rotation_error, rotvec_from_matrix
from ..tolerances import ACCEPT_ORIENTATION, ACCEPT_POSITION

#: converged when the scaled pose error is at most this (the analytic solvers accept
#: 1e-9 relative); iterations go on down to STOP or until they make no progress
TOL = 1e-10
STOP = 1e-14
#: largest step (scaled joint space, rad) one iteration may take
MAX_STEP = 0.5
#: random restarts tried when the start configuration does not converge
RESTARTS = 30
#: iterations of a restart's first search within the limits, before it turns freely: next to
#: a narrow range (a Panda's joint 4) most random starts converge only there (FR3 poses a
#: joint 0.03 rad from a limit: 22-30 % of them, against 2-3 % turning freely at once),
#: and one that will not has stalled on a limit within a few iterations
RESTART_WITHIN = 20
#: steps in a row that each lower the error by less than a part in 1e9 after which a descent
#: stops (a minimum that is no solution; 300 iterations crept on there)
CREEP = 5
#: iterations of the search within the limits from a solution found turning freely and
#: wrapped into the ranges: a polish, or a short repair when a joint ended in a range's gap
#: (on random robots those that succeed take at most 6; those that fail would go on to
#: the full ``max_iter``)
REPAIR_ITER = 20


@dataclass(frozen=True)
class NumericIK:
    """One numerical IK solution.

    ``q (n,)`` joints (rad / m); ``converged`` whether the target was reached to
    :data:`TOL`; residuals in m and rad (``orientation_error`` None when only the
    position was asked for); ``iterations`` those of the start kept; ``at_limits`` the
    joints held at a limit; ``distance`` the scaled distance ``|x - x0|`` from the start;
    ``start`` the start configuration that converged (``q0`` or a restart);
    ``restarts`` the restarts tried (0 when ``q0`` converged).
    """

    q: np.ndarray
    converged: bool
    position_error: float
    orientation_error: float | None
    iterations: int
    at_limits: list
    distance: float
    start: np.ndarray
    restarts: int


class _Problem:
    """One problem of :func:`solve_numeric`: the target, the joints' scaling (``q = s x``,
    x in rad or in units of ``scale``) and limits, and the steps that solve it
    (Levenberg-Marquardt onto the target, then least change in the task's null space)."""

    def __init__(self, fk, T, q0, jacobian, limits, revolute, scale, orientation,
                 least_change, max_iter):
        self.fk, self.scale = fk, scale
        self.least_change, self.max_iter = least_change, max_iter
        self.T = np.asarray(T, float)
        self.q0 = np.asarray(q0, float).ravel()
        self.n = n = len(self.q0)
        self.revolute = np.ones(n, bool) if revolute is None else np.asarray(revolute, bool)
        lim = np.tile([-np.inf, np.inf], (n, 1)) if limits is None else np.asarray(limits, float)
        self.lo, self.hi = lim[:, 0], lim[:, 1]
        self.s = np.where(self.revolute, 1.0, scale)               # q = s * x
        self.rows = slice(0, 6) if orientation else slice(0, 3)
        self.jac = jacobian or (lambda q: finite_difference_jacobian(fk, q, self.revolute, scale))

    def error(self, q):
        """The scaled pose error ``[(p* - p) / scale, rotvec(R* R^T)]`` at ``q (n,)``.

        Returns
        -------
        ndarray (6,) or (3,)
            The rows asked for (position only without orientation); inf where ``self.fk``
            refuses ``q`` (a mechanism that cannot be assembled there raises ValueError or an
            ArithmeticError): such a step is rejected.
        """
        try:
            Tq = np.asarray(self.fk(q), float)
        except (ValueError, ArithmeticError):
            return np.full(6, np.inf)[self.rows]
        e = np.empty(6)
        e[:3] = (self.T[:3, 3] - Tq[:3, 3]) / self.scale
        e[3:] = rotvec_from_matrix(self.T[:3, :3] @ Tq[:3, :3].T)
        return e[self.rows]

    def scaled_jacobian(self, q):
        """The Jacobian at ``q`` in the scaled variables.

        Linear rows divided by ``scale``, columns times the joints' scaling ``s``; central
        differences when the user's Jacobian refuses ``q``.

        Parameters
        ----------
        q : ndarray (n,)
            Joint values (rad / m).

        Returns
        -------
        ndarray (6, n) or (3, n)
            The rows of the error (position only without orientation).
        """
        try:
            J = np.asarray(self.jac(q), float).copy()
        except (ValueError, ArithmeticError):   # a difference left the mechanism
            J = finite_difference_jacobian(self.fk, q, self.revolute, self.scale)
        J[:3] /= self.scale
        return J[self.rows] * self.s

    def held(self, q, dx):
        """Joints at a limit that the step ``dx`` would push further out.

        Parameters
        ----------
        q, dx : ndarray (n,)
            Joint values (rad / m) and a step (any scale; its sign is read).

        Returns
        -------
        ndarray (n,) of bool
        """
        return pushed_out(q, self.lo, self.hi, dx, 1e-12)

    def into_range(self, q):
        """``q (n,)``, each revolute joint beyond its limits turned by whole turns to the value
        nearest it within them (:func:`~kincalc.spatial.into_limits`): the same pose, where
        :meth:`project` would clip it onto a limit, another pose (a start of 180 deg for a
        joint limited to [-225, 45] deg is -180 deg, not 45)."""
        return np.where(self.revolute, into_limits(q, self.lo, self.hi), q)

    def project(self, q):
        """``q`` clipped to the limits.

        Parameters
        ----------
        q : ndarray (n,)
            Joint values (rad / m).

        Returns
        -------
        ndarray (n,)
        """
        return np.clip(q, self.lo, self.hi)

    def lm(self, q, iters, fixed=None):
        """Levenberg-Marquardt onto the target from ``q (n,)``, ``fixed (n,)`` joints kept.

        Returns
        -------
        q : ndarray (n,)
        E : float
            ``|e|``, the scaled error reached.
        k : int
            Iterations used (at most ``iters``).
        """
        def evaluate(x, rows):
            q = x[0] * self.s
            return self.error(q)[None], lambda keep: self.scaled_jacobian(q)[None]

        x, e, k = levenberg_marquardt(
            evaluate, (np.asarray(q, float) / self.s)[None], lo=self.lo / self.s,
            hi=self.hi / self.s, iterations=iters, tol=STOP, fixed=fixed,
            damping=1e-6, max_step=MAX_STEP, floor=TOL, creep=CREEP, give_up=1e8)
        # (within the limits exactly: x is clipped to lo / s, which times s may pass lo)
        return self.project(x[0] * self.s), float(np.linalg.norm(e[0])), int(k[0])

    def null_step(self, q, x0, free):
        """The step towards ``x0`` in the null space of the task, moving ``free (n,)`` joints only.

        Joints at a limit that it would push outward are taken out and it is redone.

        Returns
        -------
        step : ndarray (n,)
            Scaled joint space.
        free : ndarray (n,) of bool
            The joints it moves.
        """
        J = self.scaled_jacobian(q)
        dz = x0 - q / self.s
        free = free.copy()
        for _ in range(self.n):
            Jf = J[:, free]
            step = np.zeros(self.n)
            step[free] = dz[free] - np.linalg.pinv(Jf, rcond=1e-10) @ (Jf @ dz[free])
            block = self.held(q, step) & free
            if not block.any():
                break
            free &= ~block
        return step, free

    def nearest(self, q, x0):
        """Least change: null-space steps from ``q`` towards ``x0`` (scaled), each followed by LM.

        A joint a step would carry past its limit stops exactly on it and stays there (pinned)
        while the first-order condition asks it to; then it is released.

        Returns
        -------
        q : ndarray (n,)
        used : int
            LM iterations used.
        """
        used = 0
        gain = 1.0
        pinned = np.zeros(self.n, bool)
        for _ in range(200):
            step, free = self.null_step(q, x0, ~pinned)
            pinned |= ~free
            if np.linalg.norm(step) < 1e-10:
                # converged for this pinned set: release a joint the step would move inward
                release = False
                for j in np.flatnonzero(pinned):
                    trial, _ = self.null_step(q, x0, ~pinned | (np.arange(self.n) == j))
                    if not self.held(q, trial)[j] and abs(trial[j]) > 1e-10:
                        pinned[j] = False
                        release = True
                if not release:
                    break
                continue
            dx = gain * step
            with np.errstate(divide="ignore", invalid="ignore"):
                room = np.where(dx > 0, (self.hi - q) / self.s / dx,
                                np.where(dx < 0, (self.lo - q) / self.s / dx, np.inf))
            t = float(np.min(room, initial=np.inf))
            q_new = q + self.s * min(t, 1.0) * dx
            hit = None
            if t < 1.0:
                hit = int(np.argmin(room))
                q_new[hit] = self.lo[hit] if dx[hit] < 0 else self.hi[hit]
            mask = pinned.copy()
            if hit is not None:
                mask[hit] = True
            q_try, E_try, k = self.lm(self.project(q_new), 50, mask)
            used += k
            closer = np.linalg.norm(q_try / self.s - x0) < np.linalg.norm(q / self.s - x0) - 1e-15
            if E_try <= TOL and closer:
                q = q_try
                pinned = mask
                gain = min(1.0, gain * 2)
            else:
                gain /= 2
                if gain < 1e-3:
                    break
        return q, used

    def turning_freely(self) -> "_Problem":
        """This problem with the revolute joints' limits lifted (prismatic ones kept).

        A revolute range of nearly a full turn (+-170 deg, say) leaves a narrow gap that
        a projected step cannot cross: a search started on the wrong side of the gap
        sticks on the limit. Turning freely it crosses; :meth:`wrap` then brings the
        joints back into their ranges by whole turns (the same pose).
        """
        P = copy.copy(self)
        P.lo = np.where(self.revolute, -np.inf, self.lo)
        P.hi = np.where(self.revolute, np.inf, self.hi)
        return P

    def wrap(self, q):
        """``q (n,)``, the same pose, each revolute joint turned by whole turns into
        ``[lo, lo + 2 pi)`` (``[hi - 2 pi, hi)`` when only ``hi`` is finite; unchanged when
        neither is): within the limits unless it lies in the gap of a range under a turn."""
        base = np.where(np.isfinite(self.lo), self.lo, self.hi - TURN)
        turn = self.revolute & np.isfinite(base)
        return np.where(turn, into_turn(q, np.where(turn, base, 0.0)), q)

    def descend(self, start, within: int):
        """Levenberg-Marquardt from ``start (n,)`` (within the limits) onto the target.

        It first runs within the limits for ``within`` iterations (so that a start that
        converges there gives what it always gave); when that does not converge (or with
        ``within`` 0) it runs with the revolute joints turning freely
        (:meth:`turning_freely`) and, once converged, within the limits again from the
        result wrapped into the ranges, for at most :data:`REPAIR_ITER` iterations (a
        polish there, or a repair when a joint ended in a range's gap).

        Returns ``(q (n,) within the limits, E = |e| there (scaled), iterations used)``.
        """
        q, E, k = self.lm(start, within) if within else (start, np.inf, 0)
        if E <= TOL:
            return q, E, k
        qf, Ef, kf = self.turning_freely().lm(start, self.max_iter)
        k += kf
        qf = self.project(self.wrap(qf))
        if Ef <= TOL:
            qf, Ef, kf = self.lm(qf, min(REPAIR_ITER, self.max_iter))
            k += kf
        else:
            Ef = float(np.linalg.norm(self.error(qf)))
        return (qf, Ef, k) if Ef < E else (q, E, k)

    def attempt(self, start, within: int):
        """:meth:`descend` from ``start (n,)`` (``within``: its iterations within the limits
        first), then the least-change steps towards ``q0`` when converged.

        Returns
        -------
        q : ndarray (n,)
        E : float
            The scaled error reached (inf when ``self.fk`` refuses the start).
        k : int
            Iterations used.
        """
        start = self.project(self.into_range(start))
        if not np.isfinite(self.error(start)).all():
            return start, np.inf, 0          # self.fk refuses the start: skip it
        q, E, k = self.descend(start, within)
        if E <= TOL and self.least_change:
            q, extra = self.nearest(q, self.q0 / self.s)
            k += extra
        return q, float(np.linalg.norm(self.error(q))), k


def solve_numeric(fk: Callable, T, q0, *, jacobian: Callable | None = None, limits=None,
                  revolute=None, scale: float = 1.0, orientation: bool = True,
                  least_change: bool = True, restarts: int = RESTARTS,
                  seed: int = 0, max_iter: int = 300) -> NumericIK:
    """The IK solution of ``fk`` for target ``T`` nearest ``q0``.

    Parameters
    ----------
    fk : callable
        ``fk(q (n,)) -> (4, 4)``, ``T_world_tool`` (SI); it may raise ValueError or an
        ArithmeticError where the mechanism cannot be assembled.
    T : array_like (4, 4)
        The target pose (world frame, SI).
    q0 : array_like (n,)
        The start configuration (rad / m).
    jacobian : callable, optional
        ``jacobian(q) -> (6, n)``, the geometric Jacobian of ``fk`` (rows vx vy vz wx wy wz,
        world frame); None for central differences.
    limits : array_like (n, 2), optional
        Rad / m, +-inf for none.
    revolute : array_like (n,) of bool, optional
        Default all revolute.
    scale : float
        A characteristic length (m) to weigh positions against angles.
    orientation : bool
        False reaches the position only.
    least_change : bool
        Move to the solution with the least scaled change from ``q0`` once converged.
    restarts : int
        Seeded random starts tried when ``q0`` does not converge.
    seed : int
        Seeds the restarts.
    max_iter : int
        Levenberg-Marquardt iterations per start.

    Returns
    -------
    NumericIK
        When the target cannot be reached, the least-squares best found, with
        ``converged`` False.
    """
    P = _Problem(fk, T, q0, jacobian, limits, revolute, scale, orientation, least_change,
                 max_iter)
    T, q0, lo, hi, s, n = P.T, P.q0, P.lo, P.hi, P.s, P.n
    rng = np.random.default_rng(seed)
    box_lo = np.where(np.isfinite(lo), lo, np.where(P.revolute, -np.pi, -scale))
    box_hi = np.where(np.isfinite(hi), hi, np.where(P.revolute, np.pi, scale))
    best = None
    tried = 0
    for r in range(restarts + 1):
        start = P.project(P.into_range(q0)) if r == 0 else rng.uniform(box_lo, box_hi)
        q, E, k = P.attempt(start, P.max_iter if r == 0 else min(RESTART_WITHIN, P.max_iter))
        tried = r
        cand = (E > TOL, float(np.linalg.norm((q - q0) / s)) if E <= TOL else E, q, k, start, E)
        if best is None or cand[:2] < best[:2]:
            best = cand
        if E <= TOL:
            break
    _, _, q, k, start, E = best
    try:
        Tq = np.asarray(fk(q), float)
        pe = float(np.linalg.norm(Tq[:3, 3] - T[:3, 3]))
        oe = float(rotation_error(Tq[:3, :3], T[:3, :3])) if orientation else None
    except (ValueError, ArithmeticError):      # no start the mechanism accepts
        pe, oe = np.inf, (np.inf if orientation else None)
    at = [i for i in range(n) if q[i] <= lo[i] + 1e-12 or q[i] >= hi[i] - 1e-12]
    # a descent that stalls short of TOL (a joint held at a limit) but reaches the pose to the
    # analytic solvers' acceptance has found a solution, as theirs would be
    accepted = pe <= ACCEPT_POSITION * scale and (oe is None or oe <= ACCEPT_ORIENTATION)
    return NumericIK(q=q, converged=bool(E <= TOL or accepted), position_error=pe,
                     orientation_error=oe, iterations=k, at_limits=at,
                     distance=float(np.linalg.norm((q - q0) / s)), start=start, restarts=tried)
