"""Shared core of subproblems 5 and 6: two unit vectors under two linear equations.

Find angles ``(t1, t2)`` with ::

    M @ [cos t1, sin t1, cos t2, sin t2] = b,        M (2, 4), b (2,)

i.e. a point ``x = (u1, u2)`` of the torus ``|u1| = |u2| = 1`` on a 2-plane of
R^4. This is the two-ellipse intersection of Elias & Wen (IK-Geo,
arXiv:2211.05737, 2022, subproblem 6); subproblem 5 reduces to it as well.

Method. With ``x0 = pinv(M) b`` and ``N`` (4, 2) an orthonormal basis of the
null space of ``M``, every solution of the linear equations is
``x = x0 + N xi``. Since ``x0`` is orthogonal to ``N``, ``|u1|^2 + |u2|^2 = 2``
is the circle ``|xi| = rho``, ``rho^2 = 2 - |x0|^2``, centred at the origin.
Writing ``xi = rho (cos phi, sin phi)``, the remaining condition ``|u1| = 1``
is a trigonometric polynomial of degree 2 in ``phi``; with ``z = exp(i phi)``
it becomes a quartic in ``z`` whose roots on the unit circle are the
solutions (at most four). Working with ``z`` rather than ``tan(phi / 2)``
leaves no angle at which the polynomial degenerates. The roots are polished
by Newton's method on ``phi`` and by Gauss-Newton on ``(t1, t2)``, and each is
kept only if it satisfies the equations.

Ill-posed (``free=True``): an equation whose coefficients vanish (it holds
for all angles or for none), two equations with parallel coefficient rows
(a curve of solutions, or none), and the case where ``|u1| = 1`` holds on the
whole circle (a curve of solutions). Where the solutions form a curve, one
point of it is returned.
"""

from __future__ import annotations

import math

import numpy as np

from ..tolerances import GEOMETRY_TOL

#: a returned solution satisfies the row-normalised equations to this.
RESIDUAL_TOL = 1e-8

#: roots of the quartic in z kept for polishing: | |z| - 1 | below this. The
#: residual test decides; this only discards roots far from the unit circle.
_ROOT_BAND = 0.1

#: rho below which the circle of candidates is treated as one point.
_TINY_RHO = 1e-7

#: two solutions closer than this (rad, both angles) are one solution.
_SAME_ANGLE = 1e-6


def _wrap(t: float) -> float:
    """Angle in (-pi, pi]."""
    t = math.remainder(t, 2 * math.pi)
    return math.pi if t == -math.pi else t


def _closest_unit(a, e):
    """Unit 2-vector ``u`` minimising ``|a . u - e|`` (``a . u = e`` if possible)."""
    n = math.hypot(a[0], a[1])
    if n == 0.0:
        return np.array([1.0, 0.0])
    c = min(1.0, max(-1.0, e / n))
    s = math.sqrt(1.0 - c * c)
    return (c * np.asarray(a) + s * np.array([-a[1], a[0]])) / n


def _residual(M, b, t1, t2):
    x = np.array([math.cos(t1), math.sin(t1), math.cos(t2), math.sin(t2)])
    return M @ x - b


def _gauss_newton(M, b, t1, t2, iters: int = 3):
    """Polish ``(t1, t2)`` on ``M x(t) = b`` (square system, 2x2 Jacobian)."""
    F = _residual(M, b, t1, t2)
    nF = float(np.max(np.abs(F))) if F.size else 0.0
    for _ in range(iters):
        if nF < 1e-15:
            break
        j1 = M[:, 0:2] @ np.array([-math.sin(t1), math.cos(t1)])
        j2 = M[:, 2:4] @ np.array([-math.sin(t2), math.cos(t2)])
        det = j1[0] * j2[1] - j2[0] * j1[1]
        # near a tangency the Jacobian is singular: keep the root as found
        if abs(det) <= 1e-12 * max(1.0, float(j1 @ j1 + j2 @ j2)):
            break
        d1 = (-F[0] * j2[1] + F[1] * j2[0]) / det
        d2 = (-F[1] * j1[0] + F[0] * j1[1]) / det
        G = _residual(M, b, t1 + d1, t2 + d2)
        nG = float(np.max(np.abs(G)))
        if nG >= nF:
            break
        t1, t2, F, nF = t1 + d1, t2 + d2, G, nG
    return t1, t2, nF


def _angles(x):
    return math.atan2(x[1], x[0]), math.atan2(x[3], x[2])


def solve_unit_pair(M, b, scale: float, tol: float = GEOMETRY_TOL):
    """Solve ``M @ [cos t1, sin t1, cos t2, sin t2] = b`` for all ``(t1, t2)``.

    Parameters
    ----------
    M : array_like (2, 4)
        Coefficients; both rows in the same unit as ``b``.
    b : array_like (2,)
        Right-hand sides.
    scale : float
        Size of a typical coefficient of ``M``: a row whose norm is below
        ``tol * scale`` is treated as identically zero.
    tol : float
        Relative tolerance of the degeneracy tests.

    Returns
    -------
    solutions : list of tuple(float, float)
        Up to four ``(t1, t2)`` in rad, each in (-pi, pi].
    exact : bool
        True when ``solutions`` is non-empty (no least-squares answer is given).
    free : bool
        True when the problem is ill-posed (see the module docstring); then
        ``solutions`` holds at most one representative point.
    """
    M = np.asarray(M, dtype=float).reshape(2, 4)
    b = np.asarray(b, dtype=float).reshape(2)
    scale = max(float(scale), 1e-300)

    # Drop equations that do not depend on the angles; an unsatisfied one
    # makes the problem infeasible.
    rows, rhs = [], []
    for i in range(2):
        n = float(np.linalg.norm(M[i]))
        if n <= tol * scale:
            # |M_i x| <= sqrt(2) n on the torus: beyond that it cannot hold
            if abs(b[i]) > math.sqrt(2.0) * n + tol * scale:
                return [], False, True
            continue
        rows.append(M[i] / n)
        rhs.append(b[i] / n)
    if not rows:
        return [(0.0, 0.0)], True, True
    Mn, bn = np.array(rows), np.array(rhs)

    if len(rows) == 2:
        U, s, Vt = np.linalg.svd(Mn)
        rank = 2 if s[1] > tol * s[0] else 1
    else:
        U, s, Vt = np.ones((1, 1)), np.ones(1), Mn
        rank = 1

    if rank == 1:
        # One effective equation w . x = beta: a curve of solutions (or none).
        if len(rows) == 2 and abs(U[:, 1] @ bn) > RESIDUAL_TOL:
            return [], False, True
        w, beta = Vt[0], (U[:, 0] @ bn) / s[0]
        u1 = _closest_unit(w[0:2], beta)
        u2 = _closest_unit(w[2:4], beta - w[0:2] @ u1)
        t1, t2 = _angles(np.concatenate([u1, u2]))
        if np.max(np.abs(_residual(Mn, bn, t1, t2))) <= RESIDUAL_TOL:
            return [(_wrap(t1), _wrap(t2))], True, True
        return [], False, True

    x0 = Vt[:2].T @ ((U.T @ bn) / s)
    N = Vt[2:].T
    rho2 = 2.0 - float(x0 @ x0)
    if rho2 < -RESIDUAL_TOL:
        return [], False, False
    rho = math.sqrt(max(rho2, 0.0))

    # |u1|^2 - 1 on the circle xi = rho (cos phi, sin phi):
    #   rho^2 e'Pe + 2 rho q'e + r,  e = (cos phi, sin phi)
    N1 = N[0:2]
    P = N1.T @ N1
    q = N1.T @ x0[0:2]
    r = float(x0[0:2] @ x0[0:2]) - 1.0

    free = False
    if rho < _TINY_RHO:
        phis = [0.0]
    else:
        mu = 0.5 * (P[0, 0] + P[1, 1])
        if (max(abs(P[0, 0] - mu), abs(P[1, 1] - mu), abs(P[0, 1])) <= tol
                and np.max(np.abs(q)) <= tol and abs(r + mu * rho2) <= tol):
            # |u1| = 1 on the whole circle: every phi solves it
            free = True
            phis = [0.0]
        else:
            a0 = 0.5 * rho2 * (P[0, 0] + P[1, 1]) + r
            a1, b1 = 2 * rho * q[0], 2 * rho * q[1]
            a2, b2 = 0.5 * rho2 * (P[0, 0] - P[1, 1]), rho2 * P[0, 1]
            coeffs = np.array([(a2 - 1j * b2) / 2, (a1 - 1j * b1) / 2, a0,
                               (a1 + 1j * b1) / 2, (a2 + 1j * b2) / 2])
            z = np.roots(coeffs)
            z = z[np.abs(np.abs(z) - 1.0) < _ROOT_BAND]

            def f(phi):
                return (a0 + a1 * math.cos(phi) + b1 * math.sin(phi)
                        + a2 * math.cos(2 * phi) + b2 * math.sin(2 * phi))

            def df(phi):
                return (-a1 * math.sin(phi) + b1 * math.cos(phi)
                        - 2 * a2 * math.sin(2 * phi) + 2 * b2 * math.cos(2 * phi))

            phis = []
            for zi in z:
                phi = float(np.angle(zi))
                fv = f(phi)
                for _ in range(4):
                    d = df(phi)
                    if d == 0.0:
                        break
                    cand = phi - fv / d
                    fc = f(cand)
                    if abs(fc) >= abs(fv):
                        break
                    phi, fv = cand, fc
                phis.append(phi)

    solutions = []
    for phi in phis:
        x = x0 + N @ (rho * np.array([math.cos(phi), math.sin(phi)]))
        if not (np.linalg.norm(x[0:2]) > 0.5 and np.linalg.norm(x[2:4]) > 0.5):
            continue  # far from the torus: not a solution, and atan2 would be arbitrary
        t1, t2 = _angles(x)
        t1, t2, res = _gauss_newton(Mn, bn, t1, t2)
        if res > RESIDUAL_TOL:
            continue
        t1, t2 = _wrap(t1), _wrap(t2)
        if any(abs(_wrap(t1 - s1)) < _SAME_ANGLE and abs(_wrap(t2 - s2)) < _SAME_ANGLE
               for s1, s2 in solutions):
            continue
        solutions.append((t1, t2))
    return solutions, bool(solutions), free
