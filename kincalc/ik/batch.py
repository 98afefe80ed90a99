"""Inverse kinematics for many poses at once, vectorised over poses.

:func:`solve_batch` takes poses ``T (N, 4, 4)`` (world frame, SI) and returns
every solution as arrays: joint values ``q (N, K, n)`` and a validity mask
``valid (N, K)``; row i holds the solutions of pose i in its valid slots. No
Python loop runs over poses: every step of the family's closed form is an
array operation over all poses and candidate branches.

Supported (the closed-form families; others raise
:class:`~kincalc.ik.solve.UnsupportedRobot`, use :func:`kincalc.ik.solve` per pose):

* ``spherical-wrist`` whose joints 1-3 place the wrist centre in closed form:
  one of the two invariants of joint 1 does not involve joint 2 (axes 1 and 2
  meet or are parallel: PUMA, KUKA, ABB, Fanuc, Stanford, the textbook arms);
* ``three-parallel`` (UR family);
* the reversed chains of both (``reversed-spherical-wrist``,
  ``reversed-three-parallel``).

The formulas are those of :mod:`kincalc.ik.families` and
:mod:`kincalc.ik.position`; a solution is valid when its FK reproduces the
pose to ``1e-9`` of the robot's size (and ``1e-9`` rad).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..spatial import cross, invert_transform, matrix_from_axis_angle, rotation_error
from .families import plan
from .position import _coefficients, _depends, _reference_point
from .screws import Screws, wrap
from .solve import ACCEPT_ORIENTATION, ACCEPT_POSITION, UnsupportedRobot


@dataclass(frozen=True)
class BatchIK:
    """``q (N, K, n)`` joint values (rad / m) and ``valid (N, K)``; ``family`` used."""

    q: np.ndarray
    valid: np.ndarray
    family: str

    @property
    def counts(self) -> np.ndarray:
        """Number of solutions of each pose, ``(N,)``."""
        return self.valid.sum(axis=1)


# --- small vectorised pieces ------------------------------------------------------

def _rot(k, t):
    """Rotation matrices ``(..., 3, 3)`` about unit ``k (3,)`` by ``t (...)``."""
    return matrix_from_axis_angle(k, np.asarray(t, float))


def _mv(R, v):
    """``R @ v`` for ``R (..., 3, 3)`` and ``v (..., 3)`` (broadcasting)."""
    return np.einsum("...ij,...j->...i", R, v)


def _sp1(p1, p2, k):
    """Subproblem 1, vectorised: angle rotating ``p1`` onto ``p2`` about ``k (3,)``."""
    a = p1 - (p1 @ k)[..., None] * k
    return np.arctan2((cross(k, a) * p2).sum(-1), (a * p2).sum(-1))


def _sp4(h, p, k, d):
    """Subproblem 4, vectorised: ``h . R(k, t) p = d``; returns ``(t (..., 2), ok (..., 2))``.

    ``h``, ``p`` are ``(..., 3)`` or ``(3,)``; ``d (...)``.
    """
    h = np.asarray(h, float)
    p = np.asarray(p, float)
    kxp = cross(k, p)
    A = -(h * cross(k, kxp)).sum(-1)
    B = (h * kxp).sum(-1)
    C = (h * k).sum(-1) * (p * k).sum(-1)
    r = np.hypot(A, B)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = (np.asarray(d) - C) / r
    ok = np.abs(c) <= 1 + 1e-9
    delta = np.arccos(np.clip(c, -1, 1))
    base = np.arctan2(B, A)
    t = np.stack([base + delta, base - delta], axis=-1)
    okk = np.stack([ok, ok], axis=-1) & (r > 1e-12)[..., None]
    return t, okk


def _flat(x, ok):
    """Merge the last two axes of ``x (N, A, B, ...)`` and ``ok (N, A, B)``."""
    N, A, B = ok.shape
    return x.reshape((N, A * B) + x.shape[3:]), ok.reshape(N, A * B)


# --- placing a point (joints a, b[, c]) ------------------------------------------

def _place_point(S: Screws, joints, p0, PT):
    """Closed-form point placement for all poses: ``(X (N, K, m), ok (N, K))``.

    Needs one invariant of joint a that does not involve joint b (raises
    UnsupportedRobot otherwise).
    """
    joints = list(joints)
    a, b = joints[0], joints[1]
    c = joints[2] if len(joints) == 3 else None
    N = PT.shape[0]
    scale = S.scale + np.linalg.norm(PT, axis=-1).max(initial=0.0)
    o = _reference_point(S, a, b)
    w = S.axis[a]
    if S.revolute[a]:
        t = np.stack([(PT - o) @ w, ((PT - o) ** 2).sum(-1)], axis=-1)     # (N, 2)
        origin = o
    else:
        e1 = cross(w, [1.0, 0, 0] if abs(w[0]) < 0.9 else [0, 1.0, 0])
        e1 /= np.linalg.norm(e1)
        e2 = cross(w, e1)
        t = np.stack([PT @ e1, PT @ e2], axis=-1)
        origin = np.zeros(3)

    def coeffs(g):
        """alpha, beta, gamma (2, ...) with the target terms subtracted later."""
        al, be, ga = _coefficients(S, a, b, g, origin if S.revolute[a] else np.zeros(3))
        return al, be, ga

    if c is None:
        gs = np.broadcast_to(p0, (N, 1, 3))
        okc = np.ones((N, 1), bool)
        xc = None
    else:
        # which invariant is free of joint b (robot-level fact)
        th = 2 * np.pi * np.arange(16) / 16 if S.revolute[c] else np.linspace(-1, 1, 5) * 4 * S.scale
        g_s = S.move_point(c, th, p0)
        al_s, be_s, ga_s = coeffs(g_s)
        dep = _depends(be_s, ga_s, scale ** 2)
        if dep.all():
            if not (S.revolute[b] and S.revolute[c]):
                raise UnsupportedRobot("batched IK: this arm's position part has no closed form "
                                       "with a prismatic joint 2 or 3; solve it pose by pose")
            xc, okc = _generic_roots(al_s, be_s, ga_s, t)
            gs = S.move_point(c, xc, p0)
            return _finish(S, joints, p0, PT, t, gs, xc, okc, coeffs, generic=True)
        k = 0 if not dep[0] else 1
        if S.revolute[c]:
            F = np.fft.fft(al_s[k]) / 16
            if np.abs(F[2:15]).max() > 1e-9 * max(np.abs(F).max(), 1e-300):
                raise UnsupportedRobot("batched IK: joint 3 enters the placing equation "
                                       "non-linearly; solve this robot pose by pose")
            C0, A1, B1 = F[0].real, 2 * F[1].real, -2 * F[1].imag      # C + A cos + B sin
            r = np.hypot(A1, B1)
            cc = (t[:, k] - C0) / max(r, 1e-300)
            okc1 = np.abs(cc) <= 1 + 1e-9
            dlt = np.arccos(np.clip(cc, -1, 1))
            base = np.arctan2(B1, A1)
            xc = np.stack([base + dlt, base - dlt], axis=-1)              # (N, 2)
            okc = np.stack([okc1, okc1], axis=-1)
        else:
            qa, qb, qc0 = np.polyfit(th, al_s[k], 2)                        # exact for degree <= 2
            qc = qc0 - t[:, k]
            if abs(qa) < 1e-12 * max(abs(qb), 1e-300):
                xc = (-qc / qb)[:, None]
                okc = np.ones_like(xc, bool)
            else:
                disc = qb * qb - 4 * qa * qc
                okc1 = disc >= -1e-12 * scale ** 2
                sq = np.sqrt(np.maximum(disc, 0))
                xc = np.stack([(-qb + sq) / (2 * qa), (-qb - sq) / (2 * qa)], axis=-1)
                okc = np.stack([okc1, okc1], axis=-1)
        gs = S.move_point(c, xc, p0)                                       # (N, Mc, 3)
    return _finish(S, joints, p0, PT, t, gs, xc, okc, coeffs, generic=False)


def _generic_roots(al_s, be_s, ga_s, t):
    """Roots in joint 3 of the generic resultant, for every pose at once.

    ``R = P^2 + Q^2 - D^2`` (see :mod:`kincalc.ik.position`) is sampled at 16 angles
    per pose, its trigonometric coefficients come from an FFT, and the roots of
    ``z^4 R`` (a degree-8 polynomial in ``z = e^(i theta)``) from the eigenvalues
    of a batch of companion matrices; roots on the unit circle are the real angles.
    """
    al = al_s[:, None, :] - t.T[:, :, None]                                # (2, N, 16)
    be, ga = be_s[:, None, :], ga_s[:, None, :]
    D = be[0] * ga[1] - be[1] * ga[0]
    P = al[0] * ga[1] - al[1] * ga[0]
    Q = be[0] * al[1] - be[1] * al[0]
    R = P * P + Q * Q - D * D                                              # (N, 16)
    F = np.fft.fft(R, axis=-1) / 16
    K = 4
    coeffs = np.stack([F[:, k % 16] for k in range(K, -K - 1, -1)], axis=-1)   # c_K ... c_-K
    big = np.abs(coeffs).max(axis=-1, keepdims=True)
    lead = coeffs[:, :1]
    lead = np.where(np.abs(lead) < 1e-13 * big, 1e-13 * big + 0j, lead)
    n = 2 * K
    comp = np.zeros((len(t), n, n), complex)
    comp[:, 0, :] = -coeffs[:, 1:] / lead
    comp[:, np.arange(1, n), np.arange(n - 1)] = 1.0
    z = np.linalg.eigvals(comp)                                            # (N, 8)
    ok = np.isfinite(z) & (np.abs(np.abs(z) - 1.0) < 1e-3)
    return np.angle(np.where(ok, z, 1.0)), ok


def _finish(S, joints, p0, PT, t, gs, xc, okc, coeffs, generic):
    """Joint b from the invariant(s) involving it, joint a by subproblem 1."""
    b = joints[1]
    scale = S.scale + np.linalg.norm(PT, axis=-1).max(initial=0.0)
    al, be, ga = coeffs(gs)                                                # (2, N, Mc)
    al = al - t.T[:, :, None]
    if generic:
        D = be[0] * ga[1] - be[1] * ga[0]
        with np.errstate(invalid="ignore", divide="ignore"):
            cb = (-al[0] * ga[1] + al[1] * ga[0]) / D
            sb = (-be[0] * al[1] + be[1] * al[0]) / D
        xb = np.arctan2(sb, cb)[..., None]
        okb = (okc & np.isfinite(cb) & np.isfinite(sb))[..., None]
        return _assemble(S, joints, PT, gs, xb, xc, okb, polish=p0)
    kb = int(np.argmax([np.abs(be[i]).max() + np.abs(ga[i]).max() for i in (0, 1)]))
    if S.revolute[b]:
        r = np.hypot(be[kb], ga[kb])
        with np.errstate(invalid="ignore", divide="ignore"):
            cc = -al[kb] / r
        okb1 = (np.abs(cc) <= 1 + 1e-9) & (r > 1e-12 * scale)
        dlt = np.arccos(np.clip(cc, -1, 1))
        base = np.arctan2(ga[kb], be[kb])
        xb = np.stack([base + dlt, base - dlt], axis=-1)                   # (N, Mc, 2)
        okb = np.stack([okb1, okb1], axis=-1)
    elif np.abs(ga[kb]).max() <= 1e-12 * max(np.abs(be[kb]).max(), 1e-300):
        with np.errstate(invalid="ignore", divide="ignore"):
            xb = (-al[kb] / be[kb])[..., None]
        okb = np.isfinite(xb)
    else:
        disc = be[kb] ** 2 - 4 * ga[kb] * al[kb]
        okb1 = disc >= 0
        sq = np.sqrt(np.maximum(disc, 0))
        xb = np.stack([(-be[kb] + sq) / (2 * ga[kb]), (-be[kb] - sq) / (2 * ga[kb])], axis=-1)
        okb = np.stack([okb1, okb1], axis=-1)
    okb = okb & okc[..., None]
    return _assemble(S, joints, PT, gs, xb, xc, okb)


def _assemble(S, joints, PT, gs, xb, xc, okb, polish=None):
    """Stack (x_a, x_b[, x_c]) for every candidate; x_a by subproblem 1 (or a projection)."""
    a, b = joints[0], joints[1]
    c = joints[2] if len(joints) == 3 else None
    w = S.axis[a]
    N = PT.shape[0]
    Mc, Mb = xb.shape[1], xb.shape[2]
    g2 = np.broadcast_to(gs[:, :, None, :], (N, Mc, Mb, 3))
    f = S.move_point(b, np.where(okb, xb, 0.0), g2)                        # (N, Mc, Mb, 3)
    if S.revolute[a]:
        xa = _sp1(f - S.point[a], (PT - S.point[a])[:, None, None, :], w)
    else:
        xa = ((PT[:, None, None, :] - f) * w).sum(-1)
    cols = [xa, xb]
    if c is not None:
        cols.append(np.broadcast_to(xc[:, :, None], xb.shape))
    X, ok = _flat(np.stack(cols, axis=-1), okb)                            # (N, K, m)
    if polish is not None:
        X = _polish(S, joints, polish, PT, X, ok)
    return X, ok


def _polish(S, joints, p0, PT, X, ok, iters: int = 3):
    """Gauss-Newton on the point equations for every candidate of every pose."""
    X = np.where(ok[..., None], X, 0.0)
    for _ in range(iters):
        Rt = np.broadcast_to(np.eye(3), X.shape[:-1] + (3, 3))
        tt = np.zeros(X.shape[:-1] + (3,))
        axes, pts = [], []
        for k, j in enumerate(joints):
            axes.append(_mv(Rt, S.axis[j]))
            pts.append(_mv(Rt, S.point[j]) + tt)
            if S.revolute[j]:
                R = _rot(S.axis[j], X[..., k])
                tt = tt + _mv(Rt, S.point[j] - _mv(R, S.point[j]))
                Rt = Rt @ R
            else:
                tt = tt + _mv(Rt, S.axis[j]) * X[..., k:k + 1]
        p = _mv(Rt, p0) + tt
        J = np.stack([cross(axes[k], p - pts[k]) if S.revolute[j] else axes[k]
                      for k, j in enumerate(joints)], axis=-1)            # (N, K, 3, m)
        err = PT[:, None, :] - p
        Jt = np.swapaxes(J, -1, -2)
        dx = np.linalg.solve(Jt @ J + 1e-18 * np.eye(J.shape[-1]), Jt @ err[..., None])[..., 0]
        X = X + np.where(ok[..., None], dx, 0.0)
    return X


# --- families -----------------------------------------------------------------------

def _spherical_wrist(S: Screws, T):
    from ..structure import common_point
    c0 = common_point(S.point[3:], S.axis[3:], np.inf)
    Minv = S.inverse_M()
    c_tool = Minv[:3, :3] @ c0 + Minv[:3, 3]
    CT = _mv(T[:, :3, :3], c_tool) + T[:, :3, 3]
    X, ok = _place_point(S, [0, 1, 2], c0, CT)                           # (N, K, 3)
    R_pre = np.broadcast_to(np.eye(3), X.shape[:2] + (3, 3))
    for i in range(3):
        if S.revolute[i]:
            R_pre = R_pre @ _rot(S.axis[i], X[..., i])
    R_t = T[:, None, :3, :3] @ Minv[:3, :3]
    RW = np.swapaxes(R_pre, -1, -2) @ R_t                                  # (N, K, 3, 3)
    k4, k5, k6 = S.axis[3], S.axis[4], S.axis[5]
    t5, ok5 = _sp4(k4, k6, k5, _mv(RW, k6) @ k4)                          # (N, K, 2)
    R5 = _rot(k5, t5)
    q5k6 = _mv(R5, k6)
    t4 = _sp1(q5k6, _mv(RW, k6)[:, :, None, :], k4)
    R45 = _rot(k4, t4) @ R5
    v = cross(k6, [1.0, 0, 0] if abs(k6[0]) < 0.9 else [0, 1.0, 0])
    t6 = _sp1(np.broadcast_to(v, t4.shape + (3,)),
              _mv(np.swapaxes(R45, -1, -2) @ RW[:, :, None], v), k6)
    Q = np.concatenate([np.broadcast_to(X[:, :, None, :], t4.shape + (3,)),
                        np.stack([t4, t5, t6], axis=-1)], axis=-1)
    return _flat(Q, ok5 & ok[..., None])


def _three_parallel(S: Screws, T):
    from ..structure import common_point
    h = S.axis[1]
    Minv = S.inverse_M()
    c56 = common_point(S.point[4:], S.axis[4:], np.inf)
    CT = _mv(T[:, :3, :3], Minv[:3, :3] @ c56 + Minv[:3, 3]) + T[:, :3, 3]
    R_t = T[:, :3, :3] @ Minv[:3, :3]
    o1 = S.point[0]
    t1, ok1 = _sp4(h, CT - o1, S.axis[0], np.full(len(T), h @ (c56 - o1)))
    q1 = -t1                                                               # (N, 2)
    R1 = _rot(S.axis[0], q1)                                               # (N, 2, 3, 3)
    R1tRt = np.swapaxes(R1, -1, -2) @ R_t[:, None]
    t5, ok5 = _sp4(h, S.axis[5], S.axis[4], _mv(R1tRt, S.axis[5]) @ h)    # (N, 2, 2)
    R5 = _rot(S.axis[4], t5)
    w = _mv(np.swapaxes(R_t, -1, -2)[:, None] @ R1, h)                    # (N, 2, 3)
    q6 = _sp1(np.broadcast_to(w[:, :, None, :], t5.shape + (3,)), _mv(np.swapaxes(R5, -1, -2), h),
              S.axis[5])
    R6 = _rot(S.axis[5], q6)
    R234 = R1tRt[:, :, None] @ np.swapaxes(R6, -1, -2) @ np.swapaxes(R5, -1, -2)
    v = cross(h, [1.0, 0, 0] if abs(h[0]) < 0.9 else [0, 1.0, 0])
    q234 = _sp1(np.broadcast_to(v, q6.shape + (3,)), _mv(R234, v), h)
    # E2 E3 E4 = E1^-1 T M^-1 E6^-1 E5^-1; the point of axis 4 lands at E2 E3 (p4)
    Trest = invert_transform(S.exp(0, q1))[:, :, None] @ (T[:, None, None] @ Minv) @ \
        invert_transform(S.exp(5, q6)) @ invert_transform(S.exp(4, t5))
    p4t = _mv(Trest[..., :3, :3], S.point[3]) + Trest[..., :3, 3]          # (N, 2, 2, 3)
    N = len(T)
    X, okx = _place_point(S, [1, 2], S.point[3], p4t.reshape(-1, 3))      # (N*4, K, 2)
    K = X.shape[1]
    X = X.reshape(N, 2, 2, K, 2)
    okx = okx.reshape(N, 2, 2, K)
    q2, q3 = X[..., 0], X[..., 1]
    q4 = q234[..., None] - q2 - q3
    bq = lambda x: np.broadcast_to(x[..., None], q2.shape)  # noqa: E731
    Q = np.stack([bq(np.broadcast_to(q1[:, :, None], t5.shape)), q2, q3, q4, bq(t5), bq(q6)],
                 axis=-1)
    ok = okx & (ok1[:, :, None] & ok5)[..., None]
    return Q.reshape(N, -1, 6), ok.reshape(N, -1)


SOLVERS = {"spherical-wrist": _spherical_wrist, "three-parallel": _three_parallel}


def solve_batch(robot, T) -> BatchIK:
    """Every IK solution of ``robot`` for each pose in ``T (N, 4, 4)``, vectorised.

    Returns a :class:`BatchIK`: ``q (N, K, n)`` (rad / m), ``valid (N, K)``.
    Invalid slots hold undefined numbers; use the mask. Raises
    :class:`~kincalc.ik.solve.UnsupportedRobot` for families without a batched
    closed form.
    """
    T = np.asarray(T, float)
    if T.ndim == 2:
        T = T[None]
    S, family, why = plan(robot)
    if family is None or family.solver not in SOLVERS:
        raise UnsupportedRobot(f"{robot.name}: batched IK supports the "
                               f"{' and '.join(SOLVERS)} families (and their reversed "
                               f"chains), not {family.name if family else why}; use robot.ik "
                               "pose by pose")
    solver = SOLVERS[family.solver]
    if family.reverse:          # solve the chain seen from the tool (Screws.reversed)
        Q, ok = solver(S.reversed(), invert_transform(T))
        Q = -Q[..., ::-1]
    else:
        Q, ok = solver(S, T)
    N, K, n = Q.shape
    Q = np.where(robot.is_revolute, wrap(Q), Q)
    # validate by FK, vectorised over every candidate of every pose
    flat = np.where(ok[..., None], Q, 0.0).reshape(-1, n)
    Tq = robot.fk(flat).reshape(N, K, 4, 4)
    pe = np.linalg.norm(Tq[..., :3, 3] - T[:, None, :3, 3], axis=-1)
    oe = rotation_error(Tq[..., :3, :3], T[:, None, :3, :3])
    ok = ok & (pe <= ACCEPT_POSITION * max(robot.characteristic_length, 1e-12)) & \
        (oe <= ACCEPT_ORIENTATION)
    # merge duplicates within each pose (double roots come twice)
    d = np.abs(np.where(robot.is_revolute, wrap(Q[:, :, None, :] - Q[:, None, :, :]),
                        Q[:, :, None, :] - Q[:, None, :, :])).max(-1)          # (N, K, K)
    same = (d < 1e-6) & ok[:, None, :] & ok[:, :, None]
    earlier = np.tril(np.ones((K, K), bool), -1)
    ok = ok & ~np.any(same & earlier, axis=-1)
    return BatchIK(q=Q, valid=ok, family=family.name)
