"""The ``singular`` exercise of :mod:`kincalc.homework.quiz`: a configuration that
is singular (found by a search along one joint and Newton on the smallest scaled
singular value) or clearly regular."""

from __future__ import annotations

import functools

import numpy as np

from .numbers import joint_grid, joint_range, joint_text, random_joints, si_values, typed_value
from .rules import ATTEMPTS, QuizError, REGULAR_MARGIN, SINGULAR_MARGIN


def scaled_sigma(robot, q) -> np.ndarray:
    """Smallest scale-free singular value ``(...,)`` deciding singularity at ``q (..., n)``.

    The Jacobian's linear rows are divided by the robot's characteristic length
    (prismatic columns multiplied by it), as in
    :func:`kincalc.analysis.jacobian_report`; the result is the smaller of
    ``sigma_r / max(sigma_1, 1)`` for the whole Jacobian and for its linear rows,
    ``r`` their generic ranks. A configuration is singular when it is below
    :data:`kincalc.tolerances.SINGULAR_TOL`.
    """
    from ...jacobian import scale_free
    J = scale_free(robot.jacobian(q), robot.is_revolute, robot.characteristic_length)
    full, full_pos = robot.generic_ranks
    s = np.linalg.svd(J, compute_uv=False)
    sv = np.linalg.svd(J[..., :3, :], compute_uv=False)
    return np.minimum(s[..., full - 1] / np.maximum(s[..., 0], 1.0),
                      sv[..., full_pos - 1] / np.maximum(sv[..., 0], 1.0))


def _zoom(f, a: float, b: float, rounds: int = 9, points: int = 41) -> float:
    """The minimiser of ``f`` (vectorised over an array of abscissae) on ``[a, b]``:
    ``points`` samples, then the same between the best one's neighbours, ``rounds``
    times (the bracket shrinks twentyfold a round)."""
    for _ in range(rounds):
        x = np.linspace(a, b, points)
        k = int(np.argmin(f(x)))
        a, b = x[max(k - 1, 0)], x[min(k + 1, points - 1)]
    return (a + b) / 2


def singular_configuration(robot, shown, rng, units):
    """A singular configuration near the written joints ``shown``, or None.

    One joint at a time (in random order) is swept over its range; at the
    deepest minima of :func:`scaled_sigma` a zooming grid search finds where
    the Jacobian loses rank (a wrist that aligns, an arm that stretches), and
    the joint is written with the fewest decimals that keep the configuration
    singular (a whole degree when the singularity sits on one). When no single
    joint gets there, :func:`_newton_singular` moves them all. Returns
    ``(written values, q in rad / m)``.
    """
    from ...tolerances import SINGULAR_TOL
    base = si_values(robot, shown, units)
    for i in rng.permutation(robot.dof):
        i = int(i)
        lo, hi = joint_range(robot, i, units)
        scale = units.a if robot.joints[i].revolute else units.l
        grid = np.linspace(lo, hi, 721) / scale
        f = _sigma_along(robot, base, i, grid)
        minima = [k for k in range(len(grid)) if f[k] <= f[max(k - 1, 0)]
                  and f[k] <= f[min(k + 1, len(grid) - 1)] and _may_vanish(f, k)]
        sweep = functools.partial(_sigma_along, robot, base, i)
        for k in sorted(minima, key=lambda k: f[k])[:3]:
            x = _zoom(sweep, grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)])
            if float(sweep(np.array([x]))[0]) > SINGULAR_TOL * 1e-3:
                continue
            first = joint_grid(units, robot.joints[i].revolute)[1]
            for dec in range(first, first + 12):
                v = typed_value(x * scale, dec)
                if not lo - 1e-9 <= v <= hi + 1e-9:
                    continue
                written = list(shown)
                written[i] = v
                q = si_values(robot, written, units)
                if float(scaled_sigma(robot, q)) < SINGULAR_TOL * SINGULAR_MARGIN:
                    return written, q
    # no joint alone reaches a singularity (redundant arms: their singular set has
    # codimension 2): Newton's method on sigma(q) = 0 moves every joint
    x = _newton_singular(robot, base)
    if x is None:
        return None
    from ...spatial import wrap
    x = np.where(robot.is_revolute, wrap(x), x)
    lo, hi = np.array([joint_range(robot, i, units) for i in range(robot.dof)]).T
    scale = np.where(robot.is_revolute, units.a, units.l)
    first = joint_grid(units, True)[1]
    for dec in range(first, first + 12):
        written = [typed_value(v, dec) for v in x * scale]
        if np.all((lo - 1e-9 <= written) & (written <= hi + 1e-9)):
            q = si_values(robot, written, units)
            if float(scaled_sigma(robot, q)) < SINGULAR_TOL * SINGULAR_MARGIN:
                return written, q
    return None


def _may_vanish(f, k: int) -> bool:
    """May the sampled minimum ``f[k]`` of :func:`scaled_sigma` along a joint be a zero
    between its neighbours? Where the Jacobian loses rank as a joint passes, sigma is a cone
    ``c |x - x*|``: with ``x*`` within half a step of sample k, ``f[k]`` is at most a quarter
    of its neighbours' sum. A smooth minimum above 0 is flat over a step (a half of that sum):
    no zoom. Values below 1e-3 are zoomed into in any case (a zero that touches)."""
    lo, hi = f[max(k - 1, 0)], f[min(k + 1, len(f) - 1)]
    return bool(f[k] < 1e-3 or f[k] <= 0.3 * (lo + hi))


def _sigma_along(robot, base, i: int, x) -> np.ndarray:
    """:func:`scaled_sigma` at ``base (n,)`` with joint ``i`` set to each of ``x (k,)``."""
    Q = np.repeat(np.asarray(base, float)[None], len(x), axis=0)
    Q[:, i] = x
    return scaled_sigma(robot, Q)


def _newton_singular(robot, q, iterations: int = 60):
    """Joints near ``q (n,)`` (rad / m) where :func:`scaled_sigma` vanishes, or None.

    Newton's method for the scalar equation sigma(q) = 0 with the minimum-norm step
    ``-sigma g / |g|^2``, ``g`` the gradient by central differences over a step
    below sigma (sigma is cone-shaped near a singularity, so its gradient is only
    meaningful farther from the tip than the step). Converges from about one start
    in four on a redundant arm; None when it stalls.
    """
    n = robot.dof
    unit = np.where(robot.is_revolute, 1.0, robot.characteristic_length)
    q = np.array(q, float)
    for _ in range(iterations):
        sigma = float(scaled_sigma(robot, q))
        if sigma < 1e-13:
            return q
        h = min(1e-6, 0.01 * sigma) * unit
        f = scaled_sigma(robot, np.concatenate([q + np.diag(h), q - np.diag(h)]))
        g = (f[:n] - f[n:]) / (2 * h)
        if not np.all(np.isfinite(g)) or g @ g < 1e-24:
            return None
        q = q - sigma * g / (g @ g)
    return None


def item_singular(robot, rng, units) -> dict:
    """Singular (half of the time, when one is found) or clearly regular joints; the
    answer is ``jacobian_report``'s verdict at the written values."""
    from ...analysis.reports import jacobian_report
    from ...tolerances import SINGULAR_TOL
    want = bool(rng.integers(2))
    for _ in range(2):
        for _ in range(ATTEMPTS // 3 if want else ATTEMPTS):
            shown, q = random_joints(robot, rng, units)
            if want:
                found = singular_configuration(robot, shown, rng, units)
                if found is None:
                    continue
                shown, q = found
            sigma = float(scaled_sigma(robot, q))
            singular = jacobian_report(robot, q).singular
            if (want and singular and sigma < SINGULAR_TOL * SINGULAR_MARGIN) or \
                    (not want and not singular and sigma > REGULAR_MARGIN):
                return {
                    "question": (f"Is {robot.name} at a singular configuration (its Jacobian "
                                 f"below full rank) at {joint_text(robot, shown, units)}? "
                                 "Answer: yes or no."),
                    "q": shown,
                    "answer": bool(singular),
                }
        want = not want   # no singularity to be found (or no regular place): the other
    raise QuizError(f"could not draw a 'singular' exercise for {robot.name}")
