"""The nearest position a robot's tool reaches to a given one, and why a position is
out of reach: damped least squares from the sampled configurations nearest the target
(:func:`descend`, :func:`nearest_position`), the same search with the limits removed
(:func:`unlimited`), the side of the workspace the target lies on
(:func:`where_outside`), and a ball that holds every reachable position, which proves a
position beyond it out of reach without a search (:func:`reach_ball`, :func:`beyond_reach`).

Below the IK engine, so that its "out of reach" reasons and :mod:`kincalc.analysis.reach` and
:mod:`kincalc.analysis.workspace` share one search. Positions in m, world frame.
"""

from __future__ import annotations

import numpy as np

from .cache import per_robot
from .joint_limits import joint_scale
from .newton import levenberg_marquardt
from ..spatial import into_turn
from ..tolerances import ACCEPT_POSITION

#: configurations sampled for the starts of the nearest-point search
SEARCH_SAMPLES = 4096
#: starts taken from the samples nearest the target
SEARCH_STARTS = 8


def _pose_error(P, R, p_goal, R_goal, L):
    """Scaled error ``(B, 3 or 6)``: ``[(p* - p) / L, rotvec(R* R^T)]`` (world frame)."""
    from ..spatial import rotvec_from_matrix
    e = (p_goal - P) / L
    if R_goal is None:
        return e
    w = rotvec_from_matrix(R_goal @ np.swapaxes(R, -1, -2))
    return np.concatenate([e, w], axis=-1)


def descend(robot, X0, p_goal, R_goal=None, *, iterations: int = 100, tol: float = 1e-13,
            limits=None):
    """Damped least squares from each start to its goal: a local minimum when out of reach.

    Parameters
    ----------
    robot, X0, p_goal : Robot, (B, n) starts (rad / m), (B, 3) goal positions (m, world)
    R_goal, iterations, tol : (B, 3, 3) goal orientations (None: position only), int, float
    limits : (n, 2), optional, instead of the robot's (inf allowed); steps projected onto them

    Returns
    -------
    X (B, n), position error (B,) m, orientation error (B,) rad or None: the best found"""
    from ..jacobian import jacobian_and_pose
    L = max(robot.characteristic_length, 1e-12)
    lo0, hi0 = (robot.limits if limits is None else np.asarray(limits, float)).T
    # a revolute joint whose range spans a full turn reaches every angle: it turns freely
    # here and is wrapped back into its range at the end (a stop at +-180 deg must not
    # trap the search on the wrong side)
    turns = robot.is_revolute & (hi0 - lo0 >= 2 * np.pi - 1e-12)
    lo, hi = np.where(turns, -np.inf, lo0), np.where(turns, np.inf, hi0)
    col = joint_scale(robot)                        # x = q / col is scale-free
    rows = 3 if R_goal is None else 6
    X = np.array(X0, float)
    B = len(X)
    p_goal = np.broadcast_to(np.asarray(p_goal, float), (B, 3))
    if R_goal is not None:
        R_goal = np.broadcast_to(np.asarray(R_goal, float), (B, 3, 3))

    def evaluate(x, idx):
        J, T = jacobian_and_pose(robot.chain, x * col)
        e = _pose_error(T[:, :3, 3], T[:, :3, :3], p_goal[idx],
                        None if R_goal is None else R_goal[idx], L)
        J = J[:, :rows] * col
        J[:, :3] /= L
        return e, lambda keep: J[keep]

    x, E, _ = levenberg_marquardt(evaluate, X / col, lo=lo / col, hi=hi / col,
                                  iterations=iterations, tol=tol)
    X = np.clip(x * col, lo, hi)          # (x is clipped to lo / col, which times col may pass lo)
    if turns.any():
        X[:, turns] = into_turn(X[:, turns], np.where(np.isfinite(lo0), lo0, -np.pi)[turns])
    pe = np.linalg.norm(E[:, :3], axis=1) * L
    oe = None if R_goal is None else np.linalg.norm(E[:, 3:], axis=1)
    return X, pe, oe


def principal_directions(P) -> tuple:
    """The directions along which the points ``P (M, 3)`` (M >= 3) spread, widest first:
    ``(centre (3,), spreads (3,), directions (3, 3) as rows, m)``, the SVD of the points
    about their centre, every ``M // 20000``-th point of ``m`` taken (units of ``P``)."""
    c = P.mean(axis=0)
    sub = P[:: max(1, len(P) // 20000)] - c
    _, s, Vt = np.linalg.svd(sub, full_matrices=False)    # (the m x m U is never built)
    return c, s, Vt, len(sub)


def motion_frame(P, robot):
    """The affine span of the tool points ``P``: where the tool moves.

    Parameters
    ----------
    P : ndarray (M, 3)
        Tool points (world frame, m).
    robot : Robot
        Its ``characteristic_length`` (m) sets the rank tolerance.

    Returns
    -------
    origin : ndarray (3,)
        A point of the span (m).
    basis : ndarray (3, d)
        Orthonormal columns; d is 3 for a spatial arm (origin 0, world axes), 2 for a
        planar one (world x, y when the plane is horizontal), 1 for a line.
    """
    c, s, Vt, m = principal_directions(P)
    L = max(robot.characteristic_length, 1e-12)
    d = int(np.sum(s > 1e-9 * L * np.sqrt(m)))
    if d == 3:
        return np.zeros(3), np.eye(3)
    if d == 2 and abs(abs(Vt[2, 2]) - 1.0) < 1e-9:
        return np.array([0.0, 0.0, c[2]]), np.eye(3)[:, :2]
    return c, Vt[:max(d, 1)].T


def samples(robot, count: int, seed: int, limits=None) -> np.ndarray:
    """Seeded joint values uniform within ``limits``, for search starts and shape tests.

    A bound that is infinite is replaced from the other bound and zero, with ``s = pi``
    (revolute) or the robot's size (prismatic): ``lo = min(-s, hi - 2 s)``,
    ``hi = max(s, lo + 2 s)``.

    Parameters
    ----------
    robot : Robot
    count : int
    seed : int
    limits : array_like (n, 2), optional
        Rad / m; default the robot's.

    Returns
    -------
    ndarray (count, n)
    """
    lo, hi = (robot.limits if limits is None else np.asarray(limits, float)).T
    span = np.where(robot.is_revolute, np.pi, max(robot.characteristic_length, 1e-12))
    lo = np.where(np.isfinite(lo), lo, np.minimum(-span, hi - 2 * span))
    hi = np.where(np.isfinite(hi), hi, np.maximum(span, lo + 2 * span))
    return np.random.default_rng(seed).uniform(lo, hi, (count, robot.dof))


def unlimited(robot) -> np.ndarray:
    """Limits that hold no joint back (for :func:`nearest_position`).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    ndarray (n, 2)
        ``-inf`` and ``+inf`` for every joint.
    """
    return np.column_stack([np.full(robot.dof, -np.inf), np.full(robot.dof, np.inf)])


def nearest_position(robot, p, *, limits=None, seed: int = 0):
    """The configuration whose tool point is nearest ``p``.

    The last few answers are remembered: ``reach`` asks again for what the IK reason
    already measured.

    Parameters
    ----------
    robot : Robot
    p : array_like (3,)
        The position (world frame, m).
    limits : array_like (n, 2), optional
        Rad / m; default the robot's.
    seed : int
        Seeds the sampled starts.

    Returns
    -------
    q : ndarray (n,)
        Joint values (rad / m).
    point : ndarray (3,)
        Its tool point (world frame, m).
    distance : float
        From ``p`` (m).
    """
    key = (tuple(np.asarray(p, float).reshape(3)),
           None if limits is None else tuple(np.asarray(limits, float).ravel()), seed)
    q, point, dist = _nearest(robot, key)
    return q.copy(), point.copy(), dist


@per_robot
def _nearest(robot, key):
    p, limits, seed = key
    p = np.array(p)
    if limits is not None:
        limits = np.array(limits).reshape(robot.dof, 2)
    Q = samples(robot, SEARCH_SAMPLES, seed, limits)
    P = robot.fk(Q)[:, :3, 3]
    best = np.argsort(np.linalg.norm(P - p, axis=1))[:SEARCH_STARTS]
    X, pe, _ = descend(robot, Q[best], np.broadcast_to(p, (len(best), 3)), iterations=400,
                       limits=limits)
    k = int(np.argmin(pe))
    return X[k], robot.fk(X[k])[:3, 3], float(pe[k])


def where_outside(robot, p, p_near, dist):
    """Where a position out of reach even without joint limits lies.

    Off the plane of a planar arm (or the line of a linear one): outside the workspace.
    Otherwise the nearest point says which side the target is on: farther from the base
    than it, and roughly along the line from the base (within 60 deg), the target is beyond
    the outer reach; nearer the base than it, inside the inner void; anything else (a notch
    in the workspace) is outside the workspace.

    Parameters
    ----------
    robot : Robot
    p : ndarray (3,)
        The position (world frame, m).
    p_near : ndarray (3,)
        The nearest reachable point (world frame, m).
    dist : float
        Its distance from ``p`` (m).

    Returns
    -------
    Outside
        :class:`~kincalc.ik.reasons.Outside`, distances in m.
    """
    from .reasons import Outside
    o = robot.base[:3, 3]
    origin, basis = motion_frame(robot.fk(samples(robot, 512, 1))[:, :3, 3], robot)
    if basis.shape[1] < 3:
        rel = p - p_near
        off = float(np.linalg.norm(rel - basis @ (basis.T @ rel)))
        if off > 1e-6 * dist:
            return Outside("outside-workspace", dist,
                           motion="plane" if basis.shape[1] == 2 else "line", off=off)
    d_target = float(np.linalg.norm(p - o))
    d_near = float(np.linalg.norm(p_near - o))
    radial = p_near - o
    cos = float((p - p_near) @ radial / max(np.linalg.norm(radial) * dist, 1e-300))
    # the nearest point on the line from the base through the target: the distances add up
    # (a target at the base has no direction)
    size = max(robot.characteristic_length, 1e-12)
    on_line = d_target > 1e-12 * size and abs(dist - abs(d_target - d_near)) <= 1e-6 * size
    if d_target > d_near and cos > 0.5:
        return Outside("beyond-outer-reach", dist, target=d_target, reach=d_near,
                       radial=on_line)
    if d_target < d_near:
        return Outside("inside-inner-void", dist, target=d_target, reach=d_near,
                       radial=on_line)
    return Outside("outside-workspace", dist)


@per_robot
def reach_ball(robot):
    """A ball about a point of the first joint's axis that holds the tool point in every
    configuration: the revolute joints at any angle, the prismatic ones within their limits.

    Let ``c_i`` be a point of joint i's axis fixed in link i - 1 and ``c_{n+1}`` the tool
    point (fixed in link n). Then ``|p_tool - c_1| <= sum_i |c_{i+1} - c_i|``; a revolute
    joint i leaves ``|c_{i+1} - c_i|`` as it is (it turns ``c_{i+1}`` about an axis through
    ``c_i``) and a prismatic one changes it by at most its travel from the reference
    configuration (the middle of its limits). Each ``c_{i+1}`` is taken at the foot of
    the perpendicular from ``c_i`` onto axis i + 1, which keeps the sum small (for
    intersecting axes, their intersection).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    center : ndarray (3,)
        ``c_1`` (world frame, m).
    radius : float
        m; inf when a prismatic joint's travel is unbounded.
    """
    from ..fk import frames_and_tool
    lo, hi = robot.limits.T
    slides = ~np.asarray(robot.is_revolute, bool)
    bounded = slides & np.isfinite(lo) & np.isfinite(hi)
    q = np.zeros(robot.dof)
    q[bounded] = (lo[bounded] + hi[bounded]) / 2
    F, tool = frames_and_tool(robot.chain, q[None])          # (1, n, 4, 4), (1, 4, 4)
    c = F[0, 0, :3, 3]
    center = c
    if (slides & ~bounded).any():
        return center, np.inf
    radius = float(np.sum(hi[slides] - lo[slides]) / 2)
    for i in range(1, robot.dof):
        z, o = F[0, i, :3, 2], F[0, i, :3, 3]
        foot = o + z * ((c - o) @ z)
        radius += float(np.linalg.norm(foot - c))
        c = foot
    radius += float(np.linalg.norm(tool[0, :3, 3] - c))
    return center, radius


def beyond_reach(robot, p) -> bool:
    """Whether the position ``p (3,)`` (world frame, m) lies outside :func:`reach_ball`:
    then no configuration reaches it, with or without joint limits (a proof, not a search).
    """
    center, radius = reach_ball(robot)
    margin = 1e-9 * radius + ACCEPT_POSITION * max(robot.characteristic_length, 1e-12)
    return bool(np.linalg.norm(np.asarray(p, float) - center) > radius + margin)
