"""Sampling the joint space within the limits, and the reach envelope refined from
the best samples (world frame, SI); see :mod:`kincalc.analysis.workspace`."""

from __future__ import annotations

import numpy as np

from ...errors import UsageError
from ...ik.nearest import descend

#: samples per chunk of the FK pass (the progress bar moves per chunk)
CHUNK = 1 << 16


def joint_ranges(robot) -> tuple[np.ndarray, np.ndarray]:
    """``(lo, hi)`` (n,) sampling ranges in SI: the limits, with unlimited revolute
    joints sampled over one turn [-pi, pi]. Unlimited prismatic joints are refused."""
    lo, hi = (np.array(x, float) for x in robot.limits.T)
    for i, j in enumerate(robot.joints):
        if np.isfinite(lo[i]) and np.isfinite(hi[i]):
            continue
        if not j.revolute:
            raise UsageError(f"{robot.name}: prismatic joint {j.name} has no limits, so its "
                             "workspace is unbounded; give it limits in the robot file")
        lo[i], hi[i] = -np.pi, np.pi
    return lo, hi


def sample_tool_points(robot, rng, count: int, progress=None):
    """``(Q (count, n), P (count, 3))``: joints drawn uniformly within
    :func:`joint_ranges` and their tool points (m, world), in chunks through the
    vectorised FK (``progress("sampling", done, count)`` after each)."""
    lo, hi = joint_ranges(robot)
    Q = np.empty((count, robot.dof))
    P = np.empty((count, 3))
    for start in range(0, count, CHUNK):
        stop = min(start + CHUNK, count)
        Q[start:stop] = rng.uniform(lo, hi, (stop - start, robot.dof))
        P[start:stop] = robot.fk(Q[start:stop])[:, :3, 3]
        if progress is not None:
            progress("sampling", stop, count)
    return Q, P


# --- the reach envelope ------------------------------------------------------

def _push(robot, X, direction, rounds: int = 40):
    """Move each configuration as far as it goes along ``direction(P) -> (B, 3)`` unit
    vectors, by damped least squares towards a goal one robot length beyond the
    tool point along that direction, repeated until the tool stops moving.
    Returns the final configurations ``(B, n)``."""
    L = max(robot.characteristic_length, 1e-12)
    for _ in range(rounds):
        P = robot.fk(X)[:, :3, 3]
        u = direction(P)
        X_new, _, _ = descend(robot, X, P + L * u, iterations=8, tol=0.0)
        moved = np.linalg.norm(robot.fk(X_new)[:, :3, 3] - P, axis=1)
        X = X_new
        if np.all(moved < 1e-12 * L):
            break
    return X


def _measure(robot, X, o, name):
    """The value ``(B,)`` of the extreme ``name`` at the configurations ``X (B, n)`` and its
    gradient ``(B, n)`` in the joints: ``|p - o|^2 / 2`` for a distance, the height ``p_z``
    (m; per rad or m of each joint)."""
    p = robot.fk(X)[:, :3, 3]
    Jv = robot.jacobian(X)[:, :3]                               # base-frame linear rows
    if name.endswith("distance"):
        v = p - o
        return 0.5 * np.einsum("bi,bi->b", v, v), np.einsum("bij,bi->bj", Jv, v)
    return p[:, 2], Jv[:, 2]


def _newton(robot, X, o, name, sign: int, steps: int = 8):
    """``X (B, n)`` moved by Newton's method onto the nearest extreme of :func:`_measure`
    (``sign`` +1 a maximum, -1 a minimum) within the limits; a step is kept only where it
    improves the value. Near a stretched arm the pushes of :func:`_push` slow down (the
    distance is flat to first order there: 4 mm short on a 2.2 m arm after 40 rounds); the
    Hessian, by central differences of the gradient, finishes in a few steps. Joints at a
    limit that the gradient pushes beyond stay there; directions the value is flat along
    (a wrist turning the tool point about itself) are not moved."""
    lo, hi = (np.asarray(x, float) for x in robot.limits.T)
    n = robot.dof
    h = 1e-5 * np.where(robot.is_revolute, 1.0, max(robot.characteristic_length, 1e-12))
    f, g = _measure(robot, X, o, name)
    for _ in range(steps):
        D = np.eye(n) * h
        _, gp = _measure(robot, (X[:, None] + D).reshape(-1, n), o, name)
        _, gm = _measure(robot, (X[:, None] - D).reshape(-1, n), o, name)
        H = ((gp - gm).reshape(len(X), n, n) / (2 * h[:, None]))
        H = -sign * 0.5 * (H + H.swapaxes(1, 2))                 # positive at the extreme
        up = sign * g                                            # the improving direction
        held = ((X <= lo) & (up < 0)) | ((X >= hi) & (up > 0))
        H = np.where(held[:, :, None] | held[:, None, :], 0.0, H) + np.eye(n) * held[:, None]
        lam, V = np.linalg.eigh(H)
        c = np.einsum("bji,bj->bi", V, np.where(held, 0.0, up))
        keep = lam > 1e-9 * np.abs(lam).max(axis=1, keepdims=True)
        step = np.einsum("bji,bi->bj", V, np.where(keep, c / np.where(keep, lam, 1.0), 0.0))
        X_new = np.clip(X + step, lo, hi)
        f_new, g_new = _measure(robot, X_new, o, name)
        better = sign * (f_new - f) > 0
        if not better.any():
            break
        X, f, g = (np.where(better[:, None], X_new, X), np.where(better, f_new, f),
                   np.where(better[:, None], g_new, g))
    return X


def envelope(robot, Q, P, keep: int = 16) -> dict:
    """Reach envelope from samples ``Q (N, n)`` with tool points ``P (N, 3)``,
    refined from the ``keep`` best samples of each extreme.

    Returns SI values ``{min_distance, max_distance, z_min, z_max}`` (m, from the
    base frame's origin, world z) and the joints where each is attained.
    """
    o = robot.base[:3, 3]
    d = np.linalg.norm(P - o, axis=1)
    z = P[:, 2]
    ez = np.array([0.0, 0.0, 1.0])

    def outward(Pc):
        v = Pc - o
        return v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)

    out = {}
    for name, values, sign, direction in (
            ("max_distance", d, 1, outward),
            ("min_distance", d, -1, None),
            ("z_max", z, 1, lambda Pc: np.broadcast_to(ez, Pc.shape)),
            ("z_min", z, -1, lambda Pc: np.broadcast_to(-ez, Pc.shape))):
        best = np.argsort(-sign * values)[:keep]
        if name == "min_distance":   # a least-squares problem itself: the goal is the origin
            X = descend(robot, Q[best], o, iterations=300)[0]
        else:
            X = _push(robot, Q[best], direction)
        X = _newton(robot, X, o, name, sign)
        Pr = robot.fk(X)[:, :3, 3]
        vr = np.linalg.norm(Pr - o, axis=1) if name.endswith("distance") else Pr[:, 2]
        k = int(np.argmax(sign * vr))
        # never worse than the samples themselves
        if sign * vr[k] >= sign * values[best[0]]:
            out[name], out[name + "_q"] = float(vr[k]), X[k]
        else:
            out[name], out[name + "_q"] = float(values[best[0]]), Q[best[0]]
    return out
