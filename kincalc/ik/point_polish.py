"""The Gauss-Newton polish of a point placed by three joints (:mod:`kincalc.ik.place`):
the roots of a quartic or a resultant, good to ~1e-10, brought to rounding; at a fold of
the arm (two of the placement's roots meeting) the two copies rounding split are placed
once, and the copies a few steps left short are polished on down the fold's valley.

``S`` is a family's :class:`~kincalc.ik.screws.Screws` (world frame at q = 0, SI).
"""

from __future__ import annotations

import numpy as np

from ..spatial import wrap
from ..tolerances import INEXACT, ROUGH, SPLIT_PLACEMENT
from ..subproblems.solutions import cross
from .branches import Branches
from .joint_limits import halfway_is_better
from .screws import Screws


#: Gauss-Newton steps on a placed point (:func:`polish_points`)
POLISH_STEPS = 3


def polish_points(S: Screws, joints, p0, br, PT, iters: int = POLISH_STEPS,
                  held=None) -> Branches:
    """Gauss-Newton (:func:`kincalc.ik.newton.polish`) on the point equations of every
    live slot of ``br``: ``joints`` (0-based) move ``p0 (3,)`` onto ``PT (N, K, 3)`` (world
    frame at q = 0, m). Roots of a quartic or a resultant are good to ~1e-10: three steps
    reach rounding. ``held (N, K, m)`` bool or None: joints that keep their values (a joint
    whose axis holds the target, which the point's error across it would turn at random).
    Two polished slots that are one double root split by rounding are then placed at its
    middle (:func:`_split_double_roots`), and the slots three steps left short of rounding,
    at a fold, go on down its valley (:func:`_down_the_valley`). Returns the branches with
    the joints polished."""
    from .newton import polish
    live = br.ok
    X = np.stack([br.value[j] for j in joints], -1)                        # (N, K, m)
    evaluate = _point_equations(S, joints, p0, PT[live])
    fixed = None if held is None else held[live]
    # damped: at a stretched or folded elbow two roots meet and J is singular
    x, res, _ = polish(evaluate, X[live], iterations=iters, tol=1e-15, damping=1e-14,
                       stall=1e-12, fixed=fixed)
    X = np.where(live[..., None], X, 0.0)
    x, res = _split_double_roots(S, joints, live, PT, X[live], x, res, evaluate, fixed)
    X[live] = _down_the_valley(S, joints, live, PT, x, res, evaluate, fixed)
    for i, j in enumerate(joints):
        x = X[..., i]
        br = br.set(j, x, np.cos(x), np.sin(x)) if S.revolute[j] else \
            br.set(j, x, np.ones_like(x), np.zeros_like(x))
    return br


#: Gauss-Newton steps at most along the valley of a fold (:func:`_down_the_valley`)
VALLEY_STEPS = 40
#: ... taken where the point's Jacobian has a singular value below this fraction of its
#: largest: next to a fold (elsewhere Gauss-Newton converges quadratically, and a slot
#: three steps left short is not a root's copy)
VALLEY = 1e-2


def _down_the_valley(S: Screws, joints, live, PT, x, res, evaluate, fixed) -> np.ndarray:
    """``x (M, m)`` with the slots that :data:`POLISH_STEPS` left short (``res (M,)`` above
    :data:`~kincalc.tolerances.ROUGH`: not stalled at rounding) next to a fold
    (:data:`VALLEY`) polished on while their residual keeps
    at least halving, and then each two slots of a target within
    :data:`~kincalc.tolerances.SPLIT_PLACEMENT`, one of them polished on, set to the better.

    At a fold of the arm, where the point's Jacobian is singular and the residual only
    quadratic in the distance along the fold, Gauss-Newton halves that distance a step
    (linear convergence): a resultant's double root, off by up to 0.5 rad in a joint that
    moves fast along the fold, needs some 25 steps. A slot whose residual stops halving (a
    spurious root: the bottom of a valley with no root) stops; one that ends worse keeps
    its start. A slot that came down the valley is a copy of the fold's double root, and a
    slot near it another (a flat fold reaches the point to rounding over 1e-5 rad): it
    takes the joints of the other, or of the better where both came down (the engine's
    rule for a polished solution, :func:`kincalc.ik.near_miss.double_roots`, here on the
    placement's scale). Two slots that three steps brought to rounding are distinct roots
    and keep their joints, and so do two that both reach it to rounding while the joints
    halfway between them miss it (:func:`_two_roots`)."""
    from .newton import polish
    rows = (res > ROUGH).nonzero()[0]
    if not len(rows):
        return x
    sv = np.linalg.svd(evaluate(x[rows], rows)[1](np.ones(len(rows), bool)), compute_uv=False)
    rows = rows[sv[:, -1] < VALLEY * sv[:, 0]]
    if not len(rows):
        return x
    y, r, _ = polish(lambda z, k: evaluate(z, rows[k]), x[rows], iterations=VALLEY_STEPS,
                     tol=1e-15, stall=np.inf,
                     fixed=None if fixed is None else fixed[rows])
    better = r < res[rows]
    x, res = x.copy(), res.copy()
    x[rows[better]], res[rows[better]] = y[better], r[better]
    slow = np.zeros(len(x), bool)
    slow[rows] = True
    a, b = _close_slots(S, joints, live, PT, x)
    two = _two_roots(S, joints, x, res, a, b, evaluate)
    for a, b in zip(a[~two].tolist(), b[~two].tolist()):               # (rare: at a fold)
        if slow[b] and (not slow[a] or res[a] <= res[b]):
            x[b] = x[a]
        elif slow[a]:
            x[a] = x[b]
    return x


def _two_roots(S: Screws, joints, x, res, a, b, evaluate) -> np.ndarray:
    """``(p,)`` bool: of the pairs of rows ``a, b (p,)`` of ``x (M, m)``, those that are two
    roots: both place the point to :data:`~kincalc.tolerances.ROUGH` (``res (M,)``; next to a
    fold rounding is reached at some 1e-14, the error moving a root along it 1e-6) and the
    joints halfway between them, moved onto the floor of the valley between them
    (:func:`_across_the_valley`), miss it by more than twice the worse of them and than
    :data:`~kincalc.tolerances.INEXACT`: a double root's copies, either side of it, miss by
    more than the floor between them, which passes through it (at a flat fold, whose copies
    lie 6e-5 rad apart, all of them by rounding alone)."""
    worse = np.maximum(res[a], res[b])
    two = worse <= ROUGH
    if not np.count_nonzero(two):
        return two
    revolute = np.asarray([S.revolute[j] for j in joints])
    step = x[b[two]] - x[a[two]]
    step = np.where(revolute, wrap(step), step)
    miss = _across_the_valley(x[a[two]] + 0.5 * step, step, a[two], evaluate)
    two[two] = miss > np.maximum(2.0 * worse[two], INEXACT)
    return two


def _across_the_valley(y, along, rows, evaluate) -> np.ndarray:
    """``(p,)``: how far the point equations of ``rows`` are missed at the joints ``y (p,
    m)`` moved normal to ``along (p, m)`` onto the floor of the valley that runs that way
    (:data:`POLISH_STEPS` Gauss-Newton steps, :func:`kincalc.ik.newton.polish`, in
    coordinates ``z`` of the plane normal to it: ``y + B z``): a fold's valley is curved,
    and the straight middle of two of its points lies off it."""
    from .newton import polish
    u = along / np.maximum(np.linalg.norm(along, axis=-1, keepdims=True), 1e-300)
    normal = np.eye(y.shape[-1]) - u[:, :, None] * u[:, None, :]            # (p, m, m)
    B = np.linalg.eigh(normal)[1][..., 1:]              # (p, m, m - 1): eigenvalues 0, 1, 1

    def on_the_plane(z, k):
        e, jacobian = evaluate(y[k] + (B[k] @ z[..., None])[..., 0], rows[k])
        return e, lambda keep: jacobian(keep) @ B[k][keep]
    _, miss, _ = polish(on_the_plane, np.zeros((len(y), y.shape[-1] - 1)),
                        iterations=POLISH_STEPS, tol=1e-15, damping=1e-14, stall=1e-12)
    return miss


def _close_slots(S: Screws, joints, live, PT, x) -> tuple:
    """``(a, b)``, each ``(p,)``: the rows of ``x (M, m)`` (the joints of the ``live (N, K)``
    slots) of two slots of one target (``PT (N, K, 3)``) whose joints agree to
    :data:`~kincalc.tolerances.SPLIT_PLACEMENT` (rad, or of the arm's size)."""
    N, K = live.shape
    X = np.zeros((N, K, len(joints)))
    X[live] = x
    revolute = np.asarray([S.revolute[j] for j in joints])
    d = X[:, None] - X[:, :, None]                                         # (N, K, K, m)
    d = np.abs(np.where(revolute, wrap(d), d / max(S.scale, 1e-300))).max(-1)
    close = (d <= SPLIT_PLACEMENT) & live[:, None] & live[:, :, None] \
        & np.tri(K, k=-1, dtype=bool).T & (PT[:, None] == PT[:, :, None]).all(-1)
    row = np.full((N, K), -1)
    row[live] = np.arange(len(x))
    pose, i, j = close.nonzero()
    return row[pose, i], row[pose, j]


def _point_equations(S: Screws, joints, p0, targets):
    """``evaluate(x (M, m), rows (M,)) -> (e (M, 3), jacobian)`` of
    :func:`kincalc.ik.newton.polish`: how far ``joints`` at ``x`` leave ``p0`` from
    ``targets[rows]`` (``targets (R, 3)``, m), over the arm's size."""
    from ..spatial import matrix_from_axis_angle
    scale = max(S.scale, 1e-300)

    def evaluate(x, rows):
        R = np.broadcast_to(np.eye(3), x.shape[:-1] + (3, 3))
        t = np.zeros(x.shape[:-1] + (3,))
        axes, pts = [], []
        for i, j in enumerate(joints):
            axes.append(np.einsum("...ij,j->...i", R, S.axis[j]))
            pts.append(np.einsum("...ij,j->...i", R, S.point[j]) + t)
            if S.revolute[j]:
                Rj = matrix_from_axis_angle(S.axis[j], x[..., i])
                t = t + np.einsum("...ij,...j->...i", R, S.point[j] - np.einsum(
                    "...ij,j->...i", Rj, S.point[j]))
                R = R @ Rj
            else:
                t = t + axes[-1] * x[..., i:i + 1]
        p = np.einsum("...ij,j->...i", R, p0) + t

        def jacobian(keep):
            return np.stack([cross(axes[i][keep], p[keep] - pts[i][keep]) if S.revolute[j]
                             else axes[i][keep] for i, j in enumerate(joints)], -1) / scale
        return (targets[rows] - p) / scale, jacobian
    return evaluate


def _split_double_roots(S: Screws, joints, live, PT, start, x, res, evaluate, fixed) -> tuple:
    """``(x, res)``: ``x (M, m)``, the polished joints of the ``live (N, K)`` slots, with
    each two slots of a target that are one double root split by rounding both set to the
    joints halfway between them, and ``res (M,)`` their residuals.

    Where two of the placement's roots meet (the point at a fold of the arm: a stretched
    or folded elbow) a polynomial gives them split by rounding, up to some 5e-3 apart in a
    joint that moves fast along the fold, and Gauss-Newton, whose Jacobian is singular
    there, stops short of the root, leaving them some 1e-6 to 1e-3 apart, each placing the
    point to 1e-14 .. 1e-9: the joints a later step derives from them (a wrist's) are then up
    to 1e-3 off, and a pose that the point alone does not fix is missed by both. Two live
    slots with the same target (``PT (N, K, 3)``) whose joints agree to
    :data:`~kincalc.tolerances.SPLIT_PLACEMENT` (rad, or of the arm's size) are one double
    root when neither places the point to :data:`~kincalc.tolerances.INEXACT` (``res
    (M,)``, the polish's residuals over the arm's size) and the joints halfway between
    them, polished (:data:`POLISH_STEPS`; the valley of a fold is curved, and the straight
    middle lies off it), place it better than half the better of the two, or to ``INEXACT``
    (:func:`~kincalc.ik.joint_limits.halfway_is_better`): the rule by which the engine takes
    two solutions of a pose as one (:func:`kincalc.ik.near_miss.double_roots`), here on the
    placement's own split, before the joints that follow multiply it.

    Unless they are two roots next to the fold (the point 1e-6 .. 1e-4 of the arm's size
    from it, two roots 1e-4 rad apart): both are polished on down the fold's valley
    (:data:`VALLEY_STEPS`, where Gauss-Newton converges linearly), the second from across
    the fold (:func:`_across_the_fold`) where they started from the same joints ``start
    (M, m)`` (two real roots closer than the polynomial's fit resolves come out as one
    complex pair, both slots at its real part, and Gauss-Newton takes both to one root),
    and where both then reach the point to rounding while the joints halfway between them
    miss it (:func:`_two_roots`), each keeps its root.
    ``fixed (M, m)`` bool or None: the joints the polish holds."""
    from .newton import polish
    if live.shape[1] < 2 or len(x) < 2:
        return x, res
    a, b = _close_slots(S, joints, live, PT, x)
    if not len(a):
        return x, res
    revolute = np.asarray([S.revolute[j] for j in joints])
    step = x[b] - x[a]
    half = x[a] + 0.5 * np.where(revolute, wrap(step), step)
    half, miss, _ = polish(lambda y, rows: evaluate(y, a[rows]), half, iterations=POLISH_STEPS,
                           tol=1e-15, damping=1e-14, stall=1e-12,
                           fixed=None if fixed is None else fixed[a])
    least = np.minimum(res[a], res[b])
    one = (least > INEXACT) & halfway_is_better(least, miss)
    x, res = x.copy(), res.copy()
    if np.count_nonzero(one):                                   # (rare: next to a fold)
        two = _deeper(S, joints, start, x, res, a[one], b[one], evaluate, fixed)
        one[one] = ~two
    for a, b, h, r in zip(a[one].tolist(), b[one].tolist(), half[one], miss[one]):  # (rare)
        x[a] = x[b] = h
        res[a] = res[b] = r
    return x, res


def _deeper(S: Screws, joints, start, x, res, a, b, evaluate, fixed) -> np.ndarray:
    """``(p,)`` bool: which of the pairs of rows ``a, b (p,)`` of ``x (M, m)`` are two roots
    once polished on down the fold's valley, the second from across the fold
    (:func:`_across_the_fold`) where both started at ``start`` (and no joint is held);
    those pairs' joints and residuals are set in ``x`` and ``res (M,)`` (modified)."""
    from .newton import polish

    def deep(y, rows):
        return polish(lambda z, k: evaluate(z, rows[k]), y, iterations=VALLEY_STEPS,
                      tol=1e-15, damping=1e-14, stall=1e-12,
                      fixed=None if fixed is None else fixed[rows])[:2]
    first, r_first = deep(x[a], a)
    other = x[b].copy()
    same = (start[a] == start[b]).all(-1)
    if np.count_nonzero(same) and fixed is None:
        other[same] = _across_the_fold(first[same], a[same], evaluate)
    second, r_second = deep(other, b)
    rows, y, r = (np.concatenate(v) for v in ((a, b), (first, second), (r_first, r_second)))
    X, R = x.copy(), res.copy()
    X[rows], R[rows] = y, r
    two = _two_roots(S, joints, X, R, a, b, evaluate)
    keep = np.concatenate([a[two], b[two]])
    x[keep], res[keep] = X[keep], R[keep]
    return two


#: the step along a fold's null direction by which :func:`_across_the_fold` measures the
#: point equations' slope and curvature (joint units: rad, or over the arm's size)
FOLD_PROBE = 1e-4


def _across_the_fold(x, rows, evaluate) -> np.ndarray:
    """``(p, m)``: for roots ``x (p, m)`` of the point equations of ``rows`` next to a fold,
    where the other root lies: along the Jacobian's null direction ``n``, the equations'
    component along the lost direction ``u`` is ``sigma t + c t^2 / 2`` to second order,
    zero at ``t = 0`` and ``t = -2 sigma / c`` (central differences at ``+-``
    :data:`FOLD_PROBE`); ``x`` itself where that is no small step."""
    U, _, Vt = np.linalg.svd(evaluate(x, rows)[1](np.ones(len(x), bool)))
    n, u = Vt[:, -1], U[:, :, -1]
    ahead = np.add.reduce(evaluate(x + FOLD_PROBE * n, rows)[0] * u, -1)
    behind = np.add.reduce(evaluate(x - FOLD_PROBE * n, rows)[0] * u, -1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -(ahead - behind) * FOLD_PROBE / (ahead + behind)
    t = np.where(np.isfinite(t) & (np.abs(t) < 100 * FOLD_PROBE), t, 0.0)
    return x + t[:, None] * n
