"""The swivel angle of an arm with a spherical shoulder and wrist, and every branch at a
given swivel angle in closed form.

An SRS arm has seven revolute joints: axes 1-3 through one point S (the shoulder), axes
5-7 through one point W (the wrist centre), joint 4 (the elbow) changing the distance
SW. For a pose, W is fixed by the tool (it moves with the flange) and S by the base;
joint 4 is fixed by ``|SW|`` (two roots), and the arm between S and W can still turn
about the line SW: the arm's self-motion. Its angle is the swivel angle ``psi``.

kincalc measures it as the stereographic SEW angle of Elias & Wen ("Redundancy
parameterization and inverse kinematics of 7-DOF revolute manipulators", arXiv
2307.13122, 2023): with ``w = unit(W - S)``, the elbow point E (the point of axis 4
nearest S) and two reference directions R and V (V normal to R),

    n_sew = unit(w x (E - S)),   n_ref = unit((w - R) x V),
    psi = atan2(n_sew . (w x n_ref), n_sew . n_ref),

continuous for every direction ``w`` but ``w = R``. kincalc takes ``R = -k1`` (the wrist
straight along the first axis, into the base: where an arm does not reach) and V the
base frame's x axis made normal to R (or its y axis when x is along R): with the wrist
above the shoulder, ``psi = 0`` puts the elbow towards V, and psi turns it about SW by
the right-hand rule.

The inverse, for poses and angles in one batch (:func:`swivel`):

1. joint 4: ``|R(k4, q4)(W0 - o4) + o4 - S| = |W_t - S|`` (subproblem 3, two roots), with
   ``W_t`` the target's wrist centre;
2. the shoulder's rotation ``R_s``: the arm's triangle S, E, W (at q = 0 with q4 turned)
   carried onto S, E_t, W_t, where E_t lies in the half-plane of ``psi``:
   ``E_t - S = a w + b k(psi)``, ``k(psi) = x_c cos psi + y_c sin psi``,
   ``x_c = unit(n_ref x w)``, ``y_c = w x x_c``;
3. joints 1-3: ``R_1 R_2 R_3 = R_s``, a spherical wrist problem (two roots);
4. joints 5-7: ``R_5 R_6 R_7 = (R_1 ... R_4)^T R_t``, the spherical wrist (two roots).

Up to eight solutions. Where ``w = R`` the angle is undefined (no solution is given), and
where the elbow lies on the line SW (stretched or folded) the arm has no plane: the angle
then turns the straight arm about SW from an arbitrary zero. :func:`undefined_at` says
which, for the callers to refuse such a pose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..structure import common_point
from ..subproblems import sp3
from ..subproblems.solutions import Solutions, cross, dot
from .branches import Branches
from .cache import per_robot
from .screws import Screws
from .pieces import axis_normal, target_rotation, tool_point
from .wrists import spherical, undo


@dataclass(frozen=True)
class SRS:
    """The geometry of an SRS arm at q = 0 (world frame, m): the ``shoulder`` S, the
    ``wrist`` centre W0, the ``elbow`` point E0 (on axis 4, nearest S), the references
    ``R`` and ``V`` of the SEW angle (unit), and the arm's screws."""

    shoulder: np.ndarray
    wrist: np.ndarray
    elbow: np.ndarray
    R: np.ndarray
    V: np.ndarray
    screws: Screws


@per_robot
def srs(robot) -> SRS | None:
    """The SRS geometry of ``robot`` (module docstring), found from its axes, or None.

    Seven revolute joints with axes 1-3 through one point and 5-7 through another (to
    1e-9 of the arm's size), neither point on axis 4. Cached per robot.
    """
    if robot.dof != 7 or not robot.is_revolute.all():
        return None
    S = Screws.of(robot)
    tol = 1e-9 * max(robot.characteristic_length, 1e-300)
    s = common_point(S.point[:3], S.axis[:3], tol)
    w = common_point(S.point[4:], S.axis[4:], tol)
    if s is None or w is None:
        return None
    k4, o4 = S.axis[3], S.point[3]
    off = lambda p: np.linalg.norm(np.cross(p - o4, k4))  # noqa: E731
    if off(s) <= tol or off(w) <= tol:
        return None
    e = o4 + ((s - o4) @ k4) * k4
    R = -S.axis[0]
    B = np.asarray(robot.base, float)[:3, :3]
    V = B[:, 0] - (B[:, 0] @ R) * R
    if np.linalg.norm(V) < 1e-6:
        V = B[:, 1] - (B[:, 1] @ R) * R
    return SRS(s, w, e, R, V / np.linalg.norm(V), S)


def require_srs(robot) -> SRS:
    """:func:`srs` of ``robot``, or an :class:`~kincalc.errors.InputError` saying why the
    swivel angle does not apply."""
    g = srs(robot)
    if g is None:
        raise InputError(f"{robot.name} is not an arm with a spherical shoulder and wrist (7 "
                         "revolute joints, axes 1-3 through one point, 5-7 through another): "
                         "its self-motion has no swivel angle; hold a joint instead")
    return g


def undefined_at(robot, T) -> str | None:
    """Why the swivel angle is undefined at the pose ``T (4, 4)`` (world frame, SI), or
    None: the wrist centre on the singular direction R from the shoulder, or the elbow on
    the shoulder-wrist line (the arm stretched or folded: the elbow within 1e-7 of the
    arm's size of it)."""
    g = require_srs(robot)
    S = g.screws
    W = tool_point(S, np.asarray(T, float)[None], g.wrist)[0, 0]
    d = float(np.linalg.norm(W - g.shoulder))
    tol = 1e-9 * S.scale
    if d <= tol or not reference_axes(g, (W - g.shoulder) / d)[2]:
        return ("the wrist centre is on the swivel angle's singular direction from the "
                "shoulder (along axis 1, towards the base)")
    r1 = float(np.linalg.norm(g.elbow - g.shoulder))
    r2 = float(np.linalg.norm(g.wrist - g.elbow))
    c = np.clip((r1 * r1 + d * d - r2 * r2) / (2 * r1 * d), -1.0, 1.0)
    if r1 * np.sqrt(1.0 - c * c) <= 1e-7 * S.scale:     # the elbow's distance from SW
        return "the arm is stretched or folded: its elbow is on the shoulder-wrist line"
    return None


def reference_axes(g: SRS, w):
    """``(x_c, y_c, ok)`` of the SEW angle for unit shoulder-to-wrist directions
    ``w (..., 3)``: ``k(psi) = x_c cos psi + y_c sin psi``; ``ok`` False where ``w`` is
    (nearly) the singular direction R."""
    n = cross(w - g.R, np.broadcast_to(g.V, w.shape))
    nn = np.sqrt(dot(n, n))
    ok = nn > 1e-9
    n = n / np.where(ok, nn, 1.0)[..., None]
    x = cross(n, w)
    xn = np.sqrt(dot(x, x))
    ok &= xn > 1e-9
    x = x / np.where(ok, xn, 1.0)[..., None]
    return x, cross(w, x), ok


def swivel_angles(robot, q) -> np.ndarray:
    """The swivel angle of configurations ``q (..., 7)`` (rad) of an SRS arm, ``(...)`` rad;
    NaN where it is undefined (the wrist along R, or the elbow on the line SW).

    Raises
    ------
    InputError
        ``robot`` is not an SRS arm.
    """
    g = require_srs(robot)
    S = g.screws
    q = np.asarray(q, float)
    E = g.elbow
    for j in (2, 1, 0):
        E = S.move_point(j, q[..., j], E)
    W = g.wrist
    for j in (3, 2, 1, 0):
        W = S.move_point(j, q[..., j], W)
    w = W - g.shoulder
    w = w / np.linalg.norm(w, axis=-1, keepdims=True)
    x, y, ok = reference_axes(g, w)
    e = E - g.shoulder
    e = e - dot(e, w)[..., None] * w
    ok &= np.sqrt(dot(e, e)) > 1e-9 * robot.characteristic_length
    return np.where(ok, np.arctan2(dot(e, y), dot(e, x)), np.nan)


def swivel(robot, S: Screws, targets, br: Branches) -> Branches:
    """Every branch of an SRS arm at each target's pose and swivel angle (module
    docstring).

    Parameters
    ----------
    robot : Robot
        An SRS arm (:func:`srs`).
    S : Screws
        The engine's (the signature of its target-kind solvers); replaced by the screws of
        the arm's SRS geometry (:func:`srs`), which it is solved on.
    targets : Targets
        Of kind ``"swivel"``: poses ``T (N, 4, 4)`` (world frame, SI) and ``swivel (N,)``
        (rad).
    br : Branches
        One slot per target.

    Returns
    -------
    Branches
        Every joint solved, up to 8 slots: the candidates, which the engine checks by FK.

    Raises
    ------
    InputError
        ``robot`` is not an SRS arm.
    """
    g = require_srs(robot)
    S = g.screws
    T, psi = targets.T, np.asarray(targets.swivel, float)
    Wt = tool_point(S, T, g.wrist)                                         # (N, 1, 3)
    d = np.sqrt(dot(Wt - g.shoulder, Wt - g.shoulder))
    o4, k4 = S.point[3], S.axis[3]
    elbow = _larger_first(sp3(g.wrist - o4, g.shoulder - o4, k4, d, scale=(S.scale + d) ** 2))
    br = br.branch([3], elbow)
    Wt, psi_k = br.take(Wt), br.take(np.broadcast_to(psi[:, None], (br.N, 1)))
    # the arm's triangle at q = 0 with q4 turned (body) and where psi puts it (world)
    u1 = o4 + S.turn(3, br.cos[3], br.sin[3], g.wrist - o4) - g.shoulder
    u1 = u1 / np.sqrt(dot(u1, u1))[..., None]
    u2 = np.broadcast_to(g.elbow - g.shoulder, u1.shape)
    a = dot(u2, u1)
    e2 = u2 - a[..., None] * u1
    b = np.sqrt(dot(e2, e2))
    flat = b <= 1e-9 * S.scale                      # the elbow on SW: any plane will do
    e2 = np.where(flat[..., None], normal_to_each(u1), e2 / np.where(flat, 1.0, b)[..., None])
    w = (Wt - g.shoulder) / np.sqrt(dot(Wt - g.shoulder, Wt - g.shoulder))[..., None]
    x, y, ok = reference_axes(g, w)
    k = x * np.cos(psi_k)[..., None] + y * np.sin(psi_k)[..., None]
    body = np.stack([u1, e2, cross(u1, e2)], -1)                           # columns
    world = np.stack([w, k, cross(w, k)], -1)
    Rs = world @ np.swapaxes(body, -1, -2)                                 # (N, K, 3, 3)
    br = br.set(3, br.value[3], br.cos[3], br.sin[3], ok=ok)
    e3 = axis_normal(S, 2)
    br = spherical(S, br, (0, 1, 2), (Rs @ S.axis[2][:, None])[..., 0],
                   (Rs @ e3[:, None])[..., 0])
    Rt = np.broadcast_to(target_rotation(S, T), (br.N, br.K, 3, 3))
    ke = np.stack([S.axis[6], axis_normal(S, 6)], -1)                      # (3, 2)
    vw = undo(S, br, (0, 1, 2, 3), np.swapaxes(Rt @ ke, -1, -2))
    return spherical(S, br, (4, 5, 6), vw[..., 0, :], vw[..., 1, :])


def _larger_first(sol: Solutions) -> Solutions:
    """Subproblem 3's two roots with the larger angle first, so that joint 4's label ``+``
    is its larger value (for an elbow whose zero is the stretched arm: the positive one,
    as the held-joint families label it)."""
    swap = (sol.ok[..., 1] & (sol.theta[0][..., 1] > sol.theta[0][..., 0]))[..., None]
    pick = lambda a: np.where(swap, a[..., ::-1], a)  # noqa: E731
    return Solutions((pick(sol.theta[0]),), (pick(sol.c[0]),), (pick(sol.s[0]),),
                     pick(sol.ok), pick(sol.exact), pick(sol.free))


def normal_to_each(u) -> np.ndarray:
    """A unit vector normal to each unit ``u (..., 3)``."""
    pick = np.where((np.abs(u[..., 0]) < 0.9)[..., None], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    n = cross(u, pick)
    return n / np.sqrt(dot(n, n))[..., None]
