"""Inverse kinematics for many poses at once, vectorised over poses.

:func:`solve_batch` takes poses ``T (N, 4, 4)`` (world frame, SI) and returns
every solution as arrays: joint values ``q (N, K, n)`` and a validity mask
``valid (N, K)``; row i holds the solutions of pose i in its valid slots. No
Python loop runs over poses: every step of the family's closed form is an
array operation over all poses and candidate branches.

Supported (the closed-form families; others raise
:class:`~kincalc.ik.solve.UnsupportedRobot`, use :func:`kincalc.ik.solve` per pose):

* ``spherical-wrist`` whose joints 1-3 place the wrist centre in closed form:
  axes 2 and 3 parallel and axis 1 not (PUMA, ABB, KUKA and Fanuc with their
  shoulder offsets: subproblem 4 on joint 1, then a planar 2R;
  :func:`_offset_shoulder_cs`), or one of the two invariants of joint 1 free of
  joint 2 (axes 1 and 2 meet or are parallel: Stanford, the textbook arms);
  other revolute arms through a degree-8 resultant per pose;
* ``three-parallel`` (UR family);
* the reversed chains of both (``reversed-spherical-wrist``,
  ``reversed-three-parallel``);
* ``general-6r`` (any six revolute joints): the algebraic elimination of
  :func:`kincalc.ik.general6r.solve_general_6r_batch`, vectorised over poses
  (``K = 16`` slots, each pose's solutions ordered by joint 3 then joint 1).

The formulas are those of :mod:`kincalc.ik.families` and
:mod:`kincalc.ik.position`; a solution is valid when its FK reproduces the
pose to ``1e-9`` of the robot's size (and ``1e-9`` rad).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..spatial import cross, invert_transform, matrix_from_axis_angle
from .families import plan
from .position import _coefficients, _depends, _reference_point
from .screws import Screws
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


def _flat(x, ok):
    """Merge the last two axes of ``x (N, A, B, ...)`` and ``ok (N, A, B)``."""
    N, A, B = ok.shape
    return x.reshape((N, A * B) + x.shape[3:]), ok.reshape(N, A * B)


# --- placing a point (joints a, b[, c]) ------------------------------------------

_MEMO: dict = {}


def _memo(S: Screws, key, make):
    """``make()``, computed once per screws object ``S`` and ``key`` (robot-level facts
    that every chunk of poses would otherwise recompute)."""
    k = (id(S), key)
    hit = _MEMO.get(k)
    if hit is None or hit[0] is not S:
        if len(_MEMO) > 512:
            _MEMO.clear()
        hit = _MEMO[k] = (S, make())
    return hit[1]


def _place_point(S: Screws, joints, p0, PT, cs: bool = False):
    """Closed-form point placement for all poses: ``(X (N, K, m), ok (N, K))``.

    Joints ``(a, b[, c])``, point ``p0 (3,)`` at q = 0 and targets ``PT (N, 3)`` (world
    frame, m). Axes b and c parallel (and a not) give the offset-shoulder closed form
    (:func:`_offset_shoulder_cs`); else one invariant of joint a free of joint b gives
    joint c first; else three revolute joints go through the resultant (:func:`_generic_roots`), and
    anything else raises UnsupportedRobot. With ``cs``, returns ``(c, s, x, ok)`` instead, the
    joints' cosines, sines and travels each ``(m, N, K)`` (see :func:`_finish_cs`).
    """
    joints = list(joints)
    a, b = joints[0], joints[1]
    c = joints[2] if len(joints) == 3 else None
    N = PT.shape[0]
    # tolerances per pose: one far target in a chunk must not loosen its neighbours'
    scale = S.scale + np.linalg.norm(PT, axis=-1)                         # (N,)
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
        shoulder = _offset_shoulder(S, joints, p0)
        if shoulder is not None:              # axes b, c parallel: closed form
            cq, sq, xq, okq = _offset_shoulder_cs(shoulder, PT, scale)
            return (cq, sq, xq, okq) if cs else (np.moveaxis(np.arctan2(sq, cq), 0, -1), okq)
        # which invariant is free of joint b (robot-level fact)
        th = 2 * np.pi * np.arange(16) / 16 if S.revolute[c] else np.linspace(-1, 1, 5) * 4 * S.scale
        al_s, be_s, ga_s = _memo(S, ("samples", tuple(joints), tuple(p0)),
                                 lambda: coeffs(S.move_point(c, th, p0)))
        dep = _depends(be_s, ga_s, (S.scale + np.linalg.norm(p0)) ** 2)   # robot-level
        if dep.all():
            if not (S.revolute[b] and S.revolute[c]):
                raise UnsupportedRobot("batched IK: this arm's position part has no closed form "
                                       "with a prismatic joint 2 or 3; solve it pose by pose")
            xc, okc = _generic_roots(al_s, be_s, ga_s, t)
            gs = S.move_point(c, xc, p0)
            X, ok = _finish(S, joints, p0, PT, t, gs, xc, okc, coeffs, generic=True)
            return _as_cs(S, joints, X, ok) if cs else (X, ok)
        k = 0 if not dep[0] else 1
        if S.revolute[c]:
            F = _memo(S, ("fft", tuple(joints), tuple(p0), k), lambda: np.fft.fft(al_s[k]) / 16)
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
    if cs and S.revolute[a] and S.revolute[b]:
        return _finish_cs(S, joints, PT, t, o, gs, xc, okc)
    X, ok = _finish(S, joints, p0, PT, t, gs, xc, okc, coeffs, generic=False)
    return _as_cs(S, joints, X, ok) if cs else (X, ok)


def _as_cs(S: Screws, joints, X, ok):
    """``X (N, K, m)`` joint values -> ``(c, s, x (m, N, K), ok)``."""
    X = np.moveaxis(np.where(ok[..., None], X, 0.0), -1, 0)
    rev = S.revolute[list(joints)][:, None, None]
    return np.where(rev, np.cos(X), 1.0), np.where(rev, np.sin(X), 0.0), X, ok


@dataclass(frozen=True)
class _Shoulder:
    """Robot-level constants of the offset-shoulder placement (:func:`_offset_shoulder`),
    world frame at q = 0, metres."""

    o1: np.ndarray          # (3,) a point of axis a
    rows: np.ndarray        # (12, 3): p -> (A, B, w.p, then A_h A_w p, A_h K_w p, A_h B_w p)
    q_off: np.ndarray       # (3,) A_h (o_a - o_b)
    hw: float               # h . w
    d: float                # h . (p0 - o_a), the height joint a must give the point
    wxh: float              # |w x h| (> 0: axis a not parallel to h)
    uv2: float              # |u|^2 + |v|^2
    cb3: float              # cos and sine of the phase of u . R_c v, and its amplitude |u| |v|
    sb3: float
    r3: float
    G: np.ndarray           # (6, 3): u, v, k_c x v, h x u, h x v, h x (k_c x v)


def _offset_shoulder(S: Screws, joints, p0):
    """Constants of the closed form for joints ``(a, b, c)``, all revolute, with axes b
    and c parallel (common unit direction ``h = axis[b]``) and axis a not parallel to
    them, placing ``p0`` (3,) (world frame, q = 0); ``None`` for any other structure
    (or a degenerate one: ``p0`` on axis c, or axis c through axis b). Once per robot.

    Axes b and c leave a point's height along h above their own points unchanged, so
    ``h . (E_a^-1 pt - o_b) = h . (p0 - o_b)``: with ``p = pt - o_a`` and ``t = x_a``,
    ``h . R(w, -t) p = d``, ``d = h . (p0 - o_a)``. Rodrigues on ``R(w, -t) p`` makes
    it ``A cos t + B sin t + C = d`` with ``A = (A_w h) . p``, ``B = (w x h) . p``,
    ``C = (h . w)(w . p)``. The point then lies in a plane normal to h, where joints
    c, b are a planar 2R arm: with ``u = A_h (o_c - o_b)``, ``v = A_h (p0 - o_c)``
    (``A_h = I - h h^T``), ``|A_h (E_c p0 - o_b)|^2 = |u|^2 + |v|^2 + 2 u . R_c v``.
    """
    def make():
        a, b, c = joints
        if not (S.revolute[a] and S.revolute[b] and S.revolute[c]):
            return None
        w, h, kc = S.axis[a], S.axis[b], S.axis[c]
        o1, o2, o3 = S.point[a], S.point[b], S.point[c]
        if np.linalg.norm(np.cross(h, kc)) > 1e-12:
            return None
        wxh = float(np.linalg.norm(np.cross(w, h)))
        if wxh < 1e-9:
            return None
        ax_w, ax_h = _Axis(w), _Axis(h)
        u = ax_h.A @ (o3 - o2)
        v = ax_h.A @ (np.asarray(p0, float) - o3)
        r3 = float(np.linalg.norm(u) * np.linalg.norm(v))
        if r3 <= 1e-12 * S.scale ** 2:
            return None
        kv = np.cross(kc, v)
        al3, be3 = float(u @ v), float(u @ kv)
        rows = np.vstack([ax_w.A @ h, np.cross(w, h), w,
                          ax_h.A @ ax_w.A, ax_h.A @ ax_w.K, ax_h.A @ ax_w.B])
        G = np.vstack([u, v, kv, np.cross(h, u), np.cross(h, v), np.cross(h, kv)])
        return _Shoulder(o1=o1, rows=rows, q_off=ax_h.A @ (o1 - o2), hw=float(h @ w),
                         d=float(h @ (np.asarray(p0, float) - o1)), wxh=wxh,
                         uv2=float(u @ u + v @ v), cb3=al3 / r3, sb3=be3 / r3, r3=r3, G=G)
    return _memo(S, ("offset shoulder", tuple(joints), tuple(np.asarray(p0, float))), make)


#: rounding of a cosine computed from lengths of size ``scale``, per unit of
#: ``scale / amplitude`` (a few dozen float64 epsilons)
_ROUNDING = 64 * np.finfo(float).eps


def _snap_double_root(cc, band):
    """``cc`` with values within ``band`` of +-1 set to +-1.

    A cosine that close to +-1 is a double root to rounding: the pose fixes the angle
    only to ~sqrt(band) (a singular configuration: the stretched elbow, the shoulder
    cylinder). Taking the double root itself returns an exactly singular pose's
    configuration to rounding instead of two copies ~sqrt(band) either side, and moves
    a merely nearby pair by no more than that noise."""
    return np.where(np.abs(cc) >= 1.0 - band, np.sign(cc), cc)


def _offset_shoulder_cs(sh: _Shoulder, PT, scale: float):
    """All placements of the point by joints ``(a, b, c)`` (see :func:`_offset_shoulder`)
    for targets ``PT (N, 3)`` (world frame, m): ``(c, s, x, ok)``, the joints' cosines,
    sines and (zero) travels ``(3, N, 4)`` and ``ok (N, 4)``; the four slots are
    (joint a root) x (joint c root). ``scale`` (m) sets the tolerances.

    1. joint a, Paden-Kahan subproblem 4 (Paden 1985; ``h . R(k, t) p = d``):
       ``A cos t + B sin t = d - C`` gives ``t = atan2(B, A) +- arccos((d - C) / r)``,
       ``r = hypot(A, B) = |w x h| |A_w p|`` (two roots, one on the shoulder-singularity
       cylinder ``r = |d - C|``, none inside it). With ``p`` on axis a (``r`` ~ 0) the
       height does not depend on ``t``: ``t = 0`` when ``d = C`` (as robot.ik's free joint).
    2. joint c, subproblem 3 (Murray, Li & Sastry 1994, sec. 3.3.2) by the law of cosines
       in the plane normal to h: ``u . R_c v = (|q|^2 - |u|^2 - |v|^2) / 2`` with
       ``q = A_h (E_a^-1 pt - o_b)`` and ``u . R_c v = cos x_c (u . v) + sin x_c
       (u . k_c x v)``: ``x_c = phase +- arccos(...)`` (a double root at the stretched
       or folded elbow).
    3. joint b, subproblem 1 (ibid.): the angle about h turning ``u + R_c v`` onto ``q``;
       cos and sine from ``(u + R_c v) . q`` and ``(h x (u + R_c v)) . q``, each linear in
       ``(cos x_c, sin x_c)``.
    """
    N = len(PT)
    P = sh.rows @ (PT.T - sh.o1[:, None])                                    # (12, N)
    A, B, wp = P[0], P[1], P[2]
    # joint a (subproblem 4)
    C = sh.hw * wp
    r = np.sqrt(A * A + B * B)
    good = r > 1e-12 * scale * sh.wxh
    rr = np.where(good, r, 1.0)
    cc = np.where(good, (sh.d - C) / rr, 0.0)
    ok1 = np.where(good, np.abs(cc) <= 1 + 1e-9, np.abs(sh.d - C) <= 1e-9 * scale)
    cc = _snap_double_root(cc, _ROUNDING * scale / rr)
    ca, sa, ok1 = _both_roots(np.where(good, A / rr, 1.0), np.where(good, B / rr, 0.0),
                              np.where(good, cc, 1.0), ok1)                # (N, 2)
    # the target seen before joint a, projected on the plane normal to h:
    # q = A_h (R(w, -t) p + o_a - o_b), R^T p = cos A_w p - sin K_w p + B_w p
    q = P[3:6, :, None] * ca - P[6:9, :, None] * sa + \
        (P[9:12] + sh.q_off[:, None])[:, :, None]                           # (3, N, 2)
    # joint c (subproblem 3, law of cosines)
    cc3 = (0.5 * ((q * q).sum(0) - sh.uv2)) / sh.r3
    ok3 = (np.abs(cc3) <= 1 + 1e-9) & ok1
    cc3 = _snap_double_root(cc3, _ROUNDING * scale[:, None] ** 2 / sh.r3)
    cc_, sc_, ok3 = _both_roots(sh.cb3, sh.sb3, cc3, ok3)                  # (N, 2, 2)
    # joint b (subproblem 1)
    g = (sh.G @ q.reshape(3, -1)).reshape(6, N, 2, 1)
    x = g[0] + g[1] * cc_ + g[2] * sc_
    y = g[3] + g[4] * cc_ + g[5] * sc_
    cb, sb = _unit_cs(x, y, 1e-28 * scale[:, None, None] ** 2)
    shape = (N, 2, 2)
    c = np.stack([np.broadcast_to(ca[..., None], shape), cb, cc_]).reshape(3, N, 4)
    s = np.stack([np.broadcast_to(sa[..., None], shape), sb, sc_]).reshape(3, N, 4)
    return c, s, np.zeros_like(c), ok3.reshape(N, 4)


def _finish_cs(S: Screws, joints, PT, t, o, gs, xc, okc):
    """Joints b and a (both revolute) for every candidate point ``gs (N, Mc, 3)`` of
    joint c, as cosines and sines: ``(c, s, x, ok)`` with ``c, s, x (m, N, K)``.

    With ``d = g - o_b``, joint b moves g to ``f = o_b + B d + cos x A d + sin x K d``
    (:class:`_Axis`), so the two invariants of joint a about ``o`` are
    ``alpha + beta cos x_b + gamma sin x_b``: the height ``(f - o) . w`` and the squared
    distance ``|f - o|^2 = |u|^2 + |A d|^2 + 2 cos (u . A d) + 2 sin (u . K d)`` with
    ``u = o_b - o + B d`` (``|A d| = |K d|``, ``A d . K d = 0``). The one that depends
    more on x_b gives x_b = atan2(gamma, beta) +- arccos(-alpha / r); joint a is then
    subproblem 1 on ``f``.
    """
    a, b = joints[0], joints[1]
    c = joints[2] if len(joints) == 3 else None
    N, Mc = gs.shape[:2]
    ab, aa = _Axis(S.axis[b]), _Axis(S.axis[a])
    w = aa.k
    d = np.moveaxis(gs, -1, 0) - S.point[b][:, None, None]                # (3, N, Mc)
    Ad, Kd, Bd = _cmv(ab.A, d), _cmv(ab.K, d), _cmv(ab.B, d)
    u = Bd + (S.point[b] - o)[:, None, None]
    coef = [(_dot(w, u) - t[:, 0, None], _dot(w, Ad), _dot(w, Kd)),
            ((u * u).sum(0) + (Ad * Ad).sum(0) - t[:, 1, None], 2 * (u * Ad).sum(0),
             2 * (u * Kd).sum(0))]
    kb = int(np.argmax([np.abs(be).max(initial=0) + np.abs(ga).max(initial=0)
                        for _, be, ga in coef]))
    al, be, ga = coef[kb]
    scale = (S.scale + np.sqrt((PT * PT).sum(-1)))[:, None]                # (N, 1) per pose
    r = np.sqrt(be * be + ga * ga)
    good = r > 1e-12 * scale
    r = np.where(good, r, 1.0)
    cc = -al / r
    cb, sb, okb = _both_roots(be / r, ga / r, cc, (np.abs(cc) <= 1 + 1e-9) & good & okc)
    f = (S.point[b] - S.point[a])[:, None, None, None] + Bd[..., None] + \
        Ad[..., None] * cb + Kd[..., None] * sb                           # f - o_a (3, N, Mc, 2)
    ca, sa = _sp1_cs((_cmv(aa.A, f), _cmv(aa.K, f)),
                     (PT.T - S.point[a][:, None])[:, :, None, None], w,
                     1e-28 * scale[..., None] ** 2)
    K = Mc * 2
    C = [ca.reshape(N, K), cb.reshape(N, K)]
    Sn = [sa.reshape(N, K), sb.reshape(N, K)]
    X = [np.zeros((N, K))] * 2
    if c is not None:
        xcb = np.broadcast_to(xc[:, :, None], (N, Mc, 2)).reshape(N, K)
        X.append(xcb)
        C.append(np.cos(xcb) if S.revolute[c] else np.ones((N, K)))
        Sn.append(np.sin(xcb) if S.revolute[c] else np.zeros((N, K)))
    return np.stack(C), np.stack(Sn), np.stack(X), okb.reshape(N, K)


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
    scale = (S.scale + np.linalg.norm(PT, axis=-1))[:, None]              # (N, 1) per pose
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
        H = Jt @ J
        # damping relative to H's size: at a singular configuration (a stretched elbow) H
        # is singular, and an absolute 1e-18 is below its rounding (numpy raised
        # LinAlgError for the whole batch); 1e-14 of the trace keeps the step exact elsewhere
        lam = 1e-14 * np.trace(H, axis1=-2, axis2=-1)[..., None, None] + 1e-300
        dx = np.linalg.solve(H + lam * np.eye(J.shape[-1]), Jt @ err[..., None])[..., 0]
        X = X + np.where(ok[..., None], dx, 0.0)
    return X


# --- structure-of-arrays pieces for the hot paths ----------------------------------
#
# Rotations of many candidates are kept component-first, ``R (3, 3, ...)``, so that
# every entry is one contiguous array and a product of two rotations is 27 array
# multiplications (numpy's matmul over stacks of 3x3 matrices costs ~100 ns per
# product, ten times more). Joint angles travel as their cosine and sine, obtained
# algebraically from the subproblems (cos/sin cost ~11 ns per value, arctan2 ~1.5 ns).

class _Axis:
    """A constant unit axis ``k``: ``R(k, t) = cos t A + sin t K + B`` with
    ``A = I - k k^T``, ``K = [k]x``, ``B = k k^T``."""

    def __init__(self, k):
        k = np.asarray(k, float)
        self.k = k
        self.B = np.outer(k, k)
        self.A = np.eye(3) - self.B
        self.K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])

    def turn_back(self, v, c, s):
        """``R(k, t)^T v = cos t A v - sin t K v + B v`` for vectors ``v (3, ...)``
        (broadcasting with ``c``, ``s``)."""
        return _cmv(self.A, v) * c - _cmv(self.K, v) * s + _cmv(self.B, v)

    def matrix(self, c, s):
        """``R(k, t) (3, 3, *c.shape)`` from ``c = cos t``, ``s = sin t``."""
        e = (slice(None), slice(None)) + (None,) * np.ndim(c)
        return self.A[e] * c + self.K[e] * s + self.B[e]


def _cmv(M, v):
    """Constant ``M (3, 3)`` times vectors ``v (3, ...)`` (one BLAS call)."""
    return (M @ v.reshape(3, -1)).reshape(v.shape)


def _dot(k, v):
    """Constant ``k (3,)`` dotted with vectors ``v (3, ...)``."""
    return k[0] * v[0] + k[1] * v[1] + k[2] * v[2]


def _mv_soa(R, v):
    """``R @ v`` for ``R (3, 3, ...)``, ``v (3, ...)``."""
    return (R * v[None]).sum(1)


def _both_roots(cb, sb, cc, ok):
    """``t = b +- arccos(cc)`` as ``(cos t, sin t, ok)``, each with a last axis of 2,
    from ``cos b``, ``sin b`` and ``cc`` (clipped into [-1, 1]); ``ok`` is repeated."""
    cd = np.clip(cc, -1.0, 1.0)
    sd = np.sqrt(1.0 - cd * cd)
    c = np.stack([cb * cd - sb * sd, cb * cd + sb * sd], axis=-1)
    s = np.stack([sb * cd + cb * sd, sb * cd - cb * sd], axis=-1)
    return c, s, np.stack([ok, ok], axis=-1)


def _unit_cs(x, y, tiny=1e-300):
    """``(cos, sin)`` of ``arctan2(y, x)`` without trigonometric calls; (1, 0) at the origin."""
    r = np.sqrt(x * x + y * y)
    zero = r <= tiny
    r = np.where(zero, 1.0, r)
    return np.where(zero, 1.0, x / r), np.where(zero, 0.0, y / r)


def _sp1_cs(p1k, p2, k, tiny: float = 1e-28):
    """Subproblem 1 as ``(cos, sin)``: the angle about unit ``k`` turning ``p1`` onto ``p2``.

    ``p1k = (a, k x a)`` with ``a`` the part of ``p1`` normal to ``k``, as arrays
    ``(3, ...)`` or constants; ``p2 (3, ...)``. Where ``|a| |p2_normal|`` is below
    ``tiny`` (``p1`` or ``p2`` on the axis to rounding: a singular configuration, any
    angle does) the angle is 0, so that the continuum's representative is the same for
    every branch. Near a singularity both factors shrink together (each ~ sin of the
    distance to it), so the threshold must sit at the rounding floor, not above it.
    """
    a, kxa = p1k
    x = (a * p2).sum(0) if np.ndim(a) > 1 else _dot(a, p2)
    y = (kxa * p2).sum(0) if np.ndim(kxa) > 1 else _dot(kxa, p2)
    return _unit_cs(x, y, tiny)


def _sp4_consts(h, p, k):
    """The robot-level part of subproblem 4 ``h . R(k, t) p = d``: ``(C, r, cos b, sin b)``
    such that ``t = b +- arccos((d - C) / r)``."""
    kxp = np.cross(k, p)
    A = -float(h @ np.cross(k, kxp))
    B = float(h @ kxp)
    C = float(h @ k) * float(p @ k)
    r = float(np.hypot(A, B))
    if r <= 1e-12:
        return C, 0.0, 1.0, 0.0
    return C, r, A / r, B / r


def _sp4_cs(consts, d):
    """Both roots of subproblem 4 as ``(cos, sin, ok)``, each ``(*d.shape, 2)``."""
    C, r, cb, sb = consts
    if r == 0.0:
        z = np.zeros(np.shape(d) + (2,))
        return z + 1.0, z, z.astype(bool)
    cc = (d - C) / r
    return _both_roots(cb, sb, cc, np.abs(cc) <= 1 + 1e-9)


def _sp4_points(h, p, k, d):
    """Subproblem 4 ``h . R(k, t) p = d`` for constant ``h``, ``k``, ``d`` and points
    ``p (3, N)``: ``(cos t, sin t, ok)``, each ``(N, 2)``."""
    kxp = np.cross(k[:, None], p, axis=0)
    A = -_dot(h, np.cross(k[:, None], kxp, axis=0))
    B = _dot(h, kxp)
    C = float(h @ k) * _dot(k, p)
    r = np.sqrt(A * A + B * B)
    good = r > 1e-12
    r = np.where(good, r, 1.0)
    cc = (d - C) / r
    return _both_roots(A / r, B / r, cc, (np.abs(cc) <= 1 + 1e-9) & good)


def _soa_rot(T):
    """``T (N, 4, 4)`` -> rotation ``(3, 3, N)`` and position ``(3, N)``."""
    return np.moveaxis(T[:, :3, :3], 0, -1), np.moveaxis(T[:, :3, 3], 0, -1)


# --- families -----------------------------------------------------------------------
#
# Each family solver returns ``(c, s, x, ok)``: for every joint i and candidate, the
# cosine and sine of a revolute joint's angle (``c[i], s[i]``) or a prismatic joint's
# travel (``x[i]``), each ``(n, N, K)``, and the candidates' mask ``ok (N, K)``.

def _spherical_wrist(S: Screws, T):
    """Every candidate of the spherical-wrist family for poses ``T (N, 4, 4)`` (world
    frame, m), as ``(c, s, x, ok)``: cosines, sines and travels of the joints
    ``(6, N, 2 K4)`` and the mask ``(N, 2 K4)``. The slots are (placement of joints 1-3,
    ``K4`` of them) x (root of joint 5); the formulas are those of
    :func:`kincalc.ik.families.solve_spherical_wrist`. Joint 5 comes from
    :func:`_spherical_wrist_q5_cs`, exact to rounding up to the wrist singularity. There
    (axis 6 on the line of axis 4) both joint-5 slots hold the aligned value with q4 = 0
    and q6 carrying q4 + sigma q6: one representative of the continuum, as robot.ik
    returns it (the second copy is dropped as a duplicate).
    """
    from ..structure import common_point
    c0 = _memo(S, "wrist centre", lambda: common_point(S.point[3:], S.axis[3:], np.inf))
    Minv = _memo(S, "M^-1", S.inverse_M)
    c_tool = Minv[:3, :3] @ c0 + Minv[:3, 3]
    CT = _mv(T[:, :3, :3], c_tool) + T[:, :3, 3]
    c3, s3, x3, ok = _place_point(S, [0, 1, 2], c0, CT, cs=True)          # (3, N, K4)
    N, K4 = ok.shape
    a4, a5, a6 = (_Axis(S.axis[i]) for i in (3, 4, 5))
    k6 = a6.k
    e = np.cross(k6, [1.0, 0, 0] if abs(k6[0]) < 0.9 else [0, 1.0, 0])
    e /= np.linalg.norm(e)
    # RW = R_pre^T Rt is needed only through RW k6 and RW e: turn those two vectors
    # back through joints 1-3 (R^T v = c A v - s K v + B v)
    Rt, _ = _soa_rot(T @ Minv)                                           # (3, 3, N)
    V = np.broadcast_to(np.stack([_mv_soa(Rt, k6[:, None]), _mv_soa(Rt, e[:, None])],
                                 axis=1)[..., None], (3, 2, N, K4))     # (3, 2, N, K4)
    for i in range(3):
        if S.revolute[i]:
            V = _Axis(S.axis[i]).turn_back(V, c3[i], s3[i])
    p2, w1 = V[:, 0], V[:, 1]                                             # RW k6, RW e
    # joint 5: k4 . R5 k6 = k4 . RW k6, exact to rounding up to the wrist singularity
    c5, s5, ok5, sing = _spherical_wrist_q5_cs(S, a4, p2)              # (N, K4, 2), (N, K4)
    # joint 4: turn R5 k6 onto RW k6 about k4. R5 k6 = c5 u + s5 v + w; its part
    # normal to k4 and that part turned by 90 degrees about k4 are linear in (c5, s5).
    # RW k6 is projected on the plane normal to k4 first: next to the singularity both
    # normal parts are ~P, x4 and y4 ~P^2, and the rounding of the constant vectors'
    # component along k4 (~1e-17) times RW k6's (~1) would swamp them (as in
    # families._angle_onto)
    p2n = _cmv(a4.A, p2)                                                   # (3, N, K4)
    u, v, w = a5.A @ k6, a5.K @ k6, a5.B @ k6
    x4 = sum(cf * _dot(a4.A @ g, p2n)[..., None] for cf, g in ((c5, u), (s5, v), (1.0, w)))
    y4 = sum(cf * _dot(a4.K @ g, p2n)[..., None] for cf, g in ((c5, u), (s5, v), (1.0, w)))
    c4, s4 = _unit_cs(x4, y4, 1e-28)
    if sing.any():      # axes 4 and 6 on one line: the representative has q4 = 0
        c4 = np.where(sing[..., None], 1.0, c4)
        s4 = np.where(sing[..., None], 0.0, s4)
    # joint 6: turn a vector e normal to k6 onto R5^T R4^T RW e about k6
    z = a4.turn_back(w1[..., None], c4, s4)                              # R4^T RW e
    z = a5.turn_back(z, c5, s5)                                           # (3, N, K4, 2)
    c6, s6 = _sp1_cs((e, np.cross(k6, e)), z, k6)
    shape = (N, K4, 2)
    bc = lambda x: np.broadcast_to(x[..., None], shape)  # noqa: E731
    c = np.stack([bc(c3[0]), bc(c3[1]), bc(c3[2]), c4, c5, c6])
    s = np.stack([bc(s3[0]), bc(s3[1]), bc(s3[2]), s4, s5, s6])
    x = np.stack([bc(x3[0]), bc(x3[1]), bc(x3[2])] + [np.zeros(shape)] * 3)
    okk = ok5 & ok[..., None]
    return (c.reshape(6, N, -1), s.reshape(6, N, -1), x.reshape(6, N, -1),
            okk.reshape(N, -1))


def _spherical_wrist_q5_cs(S: Screws, a4: _Axis, v):
    """Joint 5 of a spherical wrist from ``v = R_W k6 (3, N, K)``: the unit axis 6 that
    joints 4-6 must produce, with joints 1-3 undone (world frame at q = 0), for each pose
    and placement of joints 1-3. ``a4``: axis 4.

    Solves ``k4 . R(k5, q5) k6 = k4 . v`` in the form of
    :func:`kincalc.ik.families._wrist_middle_roots` (as robot.ik does): ``(cos, sin, ok)``
    of both roots, each ``(N, K, 2)`` (last axis: ``b + delta``, ``b - delta``), and the
    wrist-singular mask ``sing (N, K)``. Where ``v`` lies within ``PARALLEL_WRIST_TOL``
    (sine) of the line of axis 4 and the wrist can put axis 6 on it, both slots hold the
    aligned value (``b`` along axis 4, ``b + pi`` against it); the caller sets q4 = 0
    there, so that the two slots are one representative of the continuum.
    """
    from .families import PARALLEL_WRIST_TOL, _cone_constants
    consts = _memo(S, "spherical wrist q5",
                   lambda: _cone_constants(S.axis[3], S.axis[4], S.axis[5]))
    f = _dot(a4.k, v)                                                       # (N, K)
    if consts is None:          # axis 5 along axis 4 or 6: plain subproblem 4
        c5, s5, ok5 = _sp4_cs(_sp4_consts(a4.k, S.axis[5], S.axis[4]), f)
        return c5, s5, ok5, np.zeros(f.shape, bool)
    top, bottom = consts[3], consts[4]
    kv = _cmv(a4.K, v)                                                      # k4 x v
    P = np.sqrt((kv * kv).sum(0))                                           # |v across k4|
    gap = 0.5 * PARALLEL_WRIST_TOL ** 2
    sing = (P <= PARALLEL_WRIST_TOL) & np.where(f > 0, top <= gap, bottom <= gap)
    return _cone_roots_cs(consts, f, P, sing) + (sing,)


def _cone_roots_cs(consts, f, P, sing):
    """Both roots ``t = b +- delta`` of ``C + r cos(t - b) = f`` (``consts`` of
    :func:`kincalc.ik.families._cone_constants`; ``f`` and ``P`` the target vector's
    parts along and across the reference axis, arrays of one shape), by
    :func:`kincalc.ik.families._wrist_q5`: ``(cos, sin, ok)``, each of that shape plus
    a last axis of 2 (``b + delta``, ``b - delta``). Where ``sing`` both slots hold the
    aligned value, ``b`` for ``f > 0``, ``b + pi`` otherwise."""
    from .families import _wrist_q5
    cb, sb, r = consts[0], consts[1], consts[2]
    cd, sd, ok = _wrist_q5(consts, f, P, 1e-9 * r)
    if sing.any():
        cd = np.where(sing, np.where(f > 0, 1.0, -1.0), cd)
        sd = np.where(sing, 0.0, sd)
        ok = ok | sing
    c = np.stack([cb * cd - sb * sd, cb * cd + sb * sd], axis=-1)
    s = np.stack([sb * cd + cb * sd, sb * cd - cb * sd], axis=-1)
    return c, s, np.stack([ok, ok], axis=-1)


def _wrist_q5_cs(S: Screws, v):
    """Joint 5 of a three-parallel arm from ``v = R1^T R(q) k6 (3, N, 2)``, the unit axis 6
    with joint 1 undone (world frame at q = 0), for each pose and root of joint 1.

    Returns ``(cos, sin, ok)`` of both roots, each ``(N, 2, 2)`` (last axis: ``b + delta``,
    ``b - delta``), and the wrist-singular mask ``sing (N, 2)``. The roots come from
    :func:`kincalc.ik.families._wrist_q5`, exact to rounding next to the singularity.
    Where axis 6 is parallel to h within ``PARALLEL_WRIST_TOL``, both slots hold the
    aligned value: ``b`` along h, ``b + pi`` against it.
    """
    from .families import PARALLEL_WRIST_TOL, _wrist_q5_constants
    h = S.axis[1]
    consts = _memo(S, "wrist q5", lambda: _wrist_q5_constants(S))
    f = _dot(h, v)                                                         # (N, 2)
    if consts is None:          # axis 6 or h along axis 5: plain subproblem 4
        c5, s5, ok5 = _sp4_cs(_sp4_consts(h, S.axis[5], S.axis[4]), f)
        return c5, s5, ok5, np.zeros(f.shape, bool)
    vp = v - h[:, None, None] * f
    P = np.sqrt((vp * vp).sum(0))                                          # |v normal to h|
    sing = P <= PARALLEL_WRIST_TOL
    return _cone_roots_cs(consts, f, P, sing) + (sing,)


def _wrist_singular_q6(S: Screws, Rt, pt, c1, s1, c5, s5, v, sing, c6, s6, ok5):
    """Joint 6 on the wrist-singular branches ``sing (N, 2)`` of a three-parallel arm, by
    the convention of :func:`kincalc.ik.families._parallel_wrist_q6`.

    The two joint-5 slots of such a branch hold one double root. Here they carry one
    representative per arc of the continuum. ``Rt (3, 3, N)``, ``pt (3, N)``: rotation
    and translation of ``T M^-1``. ``c1, s1 (N, 2)``: joint 1. ``c5, s5 (N, 2, 2)``:
    joint 5, aligned where ``sing``. ``v (3, N, 2)``: axis 6 with joint 1 undone. Returns
    ``c6, s6, ok5`` (N, 2, 2), new arrays changed only where ``sing``. The singular
    branches are gathered and solved as arrays, with no loop over poses.
    """
    from .families import _parallel_wrist_q6
    h = S.axis[1]
    n, j = np.nonzero(sing)
    a1, a5 = _Axis(S.axis[0]), _Axis(S.axis[4])
    o1, p4, p5, p6 = (S.point[i][:, None] for i in (0, 3, 4, 5))
    R, t = Rt[:, :, n], pt[:, n]                                           # (3, 3, M), (3, M)
    C1, S1, C5, S5 = c1[n, j], s1[n, j], c5[n, j, 0], s5[n, j, 0]         # (M,)
    # with joint 1 undone: axis 6, W = E1^-1 T M^-1 p6, and axis 4 at q6 = 0,
    # P0 = E1^-1 T M^-1 E5^-1 p4 (E5^-1 x = R5^T (x - p5) + p5)
    W = a1.turn_back(_mv_soa(R, p6) + t - o1, C1, S1) + o1                # (3, M)
    q = a5.turn_back(p4 - p5, C5, S5) + p5
    P0 = a1.turn_back(_mv_soa(R, q) + t - o1, C1, S1) + o1
    Ah = _Axis(h).A
    a = _cmv(Ah, W - S.point[1][:, None]).T                                # (M, 3)
    b = _cmv(Ah, P0 - W).T
    sigma = np.where(_dot(h, v[:, n, j]) > 0, 1.0, -1.0)
    q6, okq, _ = _parallel_wrist_q6(S, a, b, sigma)                        # (M, 2)
    c6, s6, ok5 = np.array(c6), np.array(s6), np.array(ok5)
    c6[n, j], s6[n, j] = np.cos(q6), np.sin(q6)
    ok5[n, j] &= okq
    return c6, s6, ok5


def _three_parallel(S: Screws, T):
    """Every candidate of the three-parallel (UR-type) family for poses ``T (N, 4, 4)``
    (world frame, m), as ``(c, s, x, ok)``: cosines, sines and (zero) travels of the
    joints ``(6, N, 8)`` and the mask ``(N, 8)``. The slots are (joint 1 root) x (joint 5
    root) x (elbow), the formulas those of :func:`kincalc.ik.families.solve_three_parallel`.
    At the wrist singularity (axis 6 parallel to axes 2-4) the joint-5 slots of the
    branch carry the continuum's representatives instead (:func:`_wrist_singular_q6`).
    """
    from ..structure import common_point
    h = S.axis[1]
    Minv = _memo(S, "M^-1", S.inverse_M)
    c56 = _memo(S, "wrist point", lambda: common_point(S.point[4:], S.axis[4:], np.inf))
    TM = T @ Minv
    CT = _mv(TM[:, :3, :3], c56) + TM[:, :3, 3]
    Rt, pt = _soa_rot(TM)                                                  # (3, 3, N), (3, N)
    N = len(T)
    a1, a5, a6 = _Axis(S.axis[0]), _Axis(S.axis[4]), _Axis(S.axis[5])
    o1 = S.point[0]
    # joint 1: the wrist point's height along h is fixed: h . R1^T (CT - o1) = h . (c56 - o1)
    t1c, t1s, ok1 = _sp4_points(h, np.moveaxis(CT - o1, 0, -1), a1.k, h @ (c56 - o1))
    c1, s1 = t1c, -t1s                                                     # q1 = -t1, (N, 2)
    C1, S1 = c1[None], s1[None]                                            # (1, N, 2)
    Rt_T = Rt.transpose(1, 0, 2)[..., None]                                # Rt^T (3, 3, N, 1)
    # joint 5: h . R5 k6 = h . R1^T Rt k6
    v = _mv_soa(Rt, a6.k[:, None])[..., None]                              # Rt k6 (3, N, 1)
    v = a1.turn_back(v, C1, S1)                                            # (3, N, 2)
    c5, s5, ok5, sing = _wrist_q5_cs(S, v)                                 # (N, 2, 2), (N, 2)
    # joint 6: turn Rt^T R1 h onto R5^T h about k6
    wv = (a1.A @ h)[:, None, None] * C1 + (a1.K @ h)[:, None, None] * S1 + \
        (a1.B @ h)[:, None, None]                                          # R1 h (3, N, 2)
    wv = _mv_soa(Rt_T, wv)[..., None]                                      # (3, N, 2, 1)
    p2 = a5.turn_back(h[:, None, None, None], c5, s5)                      # R5^T h (3, N, 2, 2)
    wa = _cmv(a6.A, wv)
    # p2 projected on the plane normal to k6 as well: next to the singularity both normal
    # parts are small and p2's component along k6 times wa's rounding would swamp them
    c6, s6 = _sp1_cs((wa, _cmv(a6.K, wv)), _cmv(a6.A, p2), a6.k)
    if sing.any():      # axis 6 parallel to h: joint 6 by the convention, one per arc
        c6, s6, ok5 = _wrist_singular_q6(S, Rt, pt, c1, s1, c5, s5, v, sing, c6, s6, ok5)
    # joints 2 + 3 + 4 about h: R234 e = R1^T Rt R6^T R5^T e
    e = np.cross(h, [1.0, 0, 0] if abs(h[0]) < 0.9 else [0, 1.0, 0])
    e /= np.linalg.norm(e)
    v = a5.turn_back(e[:, None, None, None], c5, s5)
    v = a6.turn_back(v, c6, s6)
    v = _mv_soa(Rt[..., None, None], v)
    C1, S1 = c1[:, :, None], s1[:, :, None]                                # (N, 2, 1)
    v = a1.turn_back(v, C1, S1)
    c234, s234 = _sp1_cs((e, np.cross(h, e)), v, h)                       # (N, 2, 2)
    # where joints 2, 3 must put axis 4's point: E2 E3 (p4) = E1^-1 T M^-1 E6^-1 E5^-1 (p4)
    p = S.point[3][:, None, None, None] - S.point[4][:, None, None, None]
    p = a5.turn_back(p, c5, s5) + (S.point[4] - S.point[5])[:, None, None, None]
    p = a6.turn_back(p, c6, s6) + S.point[5][:, None, None, None]
    p = _mv_soa(Rt[..., None, None], p) + pt[:, :, None, None] - o1[:, None, None, None]
    p = a1.turn_back(p, C1, S1) + o1[:, None, None, None]
    cx, sx, _, okx = _place_point(S, [1, 2], S.point[3], np.moveaxis(p, 0, -1).reshape(-1, 3),
                                  cs=True)                               # (2, N*4, K2)
    K2 = okx.shape[1]
    c2, s2, c3, s3 = (v.reshape(N, 2, 2, K2) for v in (cx[0], sx[0], cx[1], sx[1]))
    okx = okx.reshape(N, 2, 2, K2)
    # joint 4 = g4 ((2 + g3 3 + g4 4) - 2 - g3 3), by the angle-difference formulas;
    # g3, g4 = +-1 as axes 3, 4 point along h or against it
    g3, g4 = (1.0 if float(S.axis[i] @ h) > 0 else -1.0 for i in (2, 3))
    s3g = g3 * s3
    c23, s23 = c2 * c3 - s2 * s3g, s2 * c3 + c2 * s3g
    C234, S234 = c234[..., None], s234[..., None]
    c4, s4 = C234 * c23 + S234 * s23, g4 * (S234 * c23 - C234 * s23)
    shape = (N, 2, 2, K2)
    b1 = lambda x: np.broadcast_to(x[:, :, None, None], shape)  # noqa: E731
    b2 = lambda x: np.broadcast_to(x[..., None], shape)  # noqa: E731
    c = np.stack([b1(c1), c2, c3, c4, b2(c5), b2(c6)]).reshape(6, N, -1)
    s = np.stack([b1(s1), s2, s3, s4, b2(s5), b2(s6)]).reshape(6, N, -1)
    ok = okx & (ok1[:, :, None] & ok5)[..., None]
    return c, s, np.zeros_like(c), ok.reshape(N, -1)


SOLVERS = {"spherical-wrist": _spherical_wrist, "three-parallel": _three_parallel}

#: poses per chunk: the working set of a chunk (a few hundred arrays of
#: CHUNK x 8 doubles) stays in the processor's cache
CHUNK = 2048


def _fk_matches(robot, c, s, x, T, tol_p: float, tol_o: float) -> np.ndarray:
    """Does FK of every candidate reproduce its pose? ``c, s, x (n, N, K)`` as the
    family solvers give them (cosine and sine of each revolute joint's angle, travel
    of each prismatic joint), ``T (N, 4, 4)``; returns ``(N, K)`` bool.

    The chain ``F_0 J_1 F_1 ... J_n F_n`` (:class:`~kincalc.model.Chain`) is walked
    column-wise as in :mod:`kincalc.fk`, with each joint's cosine and sine turned by
    its offset instead of recomputed. Position within ``tol_p`` (m); orientation
    within ``tol_o`` rad, through ``|R_a - R_b|_F = 2 sqrt(2) sin(angle / 2)``.
    """
    from ..fk import _apply_fixed, _start
    chain = robot.chain
    n, N, K = c.shape
    M = N * K
    cols, p = _start(chain.fixed[0], M)
    for i in range(n):
        off = chain.offset[i]
        if chain.revolute[i]:
            ci, si = c[i].reshape(M), s[i].reshape(M)
            if off != 0.0:
                co, so = np.cos(off), np.sin(off)
                ci, si = ci * co - si * so, si * co + ci * so
            c0, c1 = cols[0], cols[1]
            cols = [c0 * ci + c1 * si, c1 * ci - c0 * si, cols[2]]
        else:
            p = p + cols[2] * (x[i].reshape(M) + off)
        cols, p = _apply_fixed(cols, p, chain.fixed[i + 1])
    e_p = ((p.reshape(3, N, K) - T[:, :3, 3].T[:, :, None]) ** 2).sum(0)
    e_o = sum(((cols[j].reshape(3, N, K) - T[:, :3, j].T[:, :, None]) ** 2).sum(0)
              for j in range(3))
    return (e_p <= tol_p ** 2) & (e_o <= 8 * np.sin(tol_o / 2) ** 2)


def _first_of_duplicates(q, ok, revolute) -> np.ndarray:
    """``ok`` with later copies of a solution (every joint within 1e-6) cleared.

    ``q (n, N, K)`` with revolute angles in (-pi, pi]; double roots come twice."""
    n, N, K = q.shape
    qk = np.ascontiguousarray(q.transpose(2, 0, 1))                       # (K, n, N)
    rev = np.asarray(revolute)
    drop = np.zeros((K, N), bool)
    for j in range(1, K):
        for i in range(j):
            d = np.abs(qk[j] - qk[i])
            d[rev] = np.minimum(d[rev], 2 * np.pi - d[rev])
            drop[j] |= (d.max(0) < 1e-6) & ok[:, i]
    return ok & ~drop.T


def _solve_chunk(robot, S, family, solver, T):
    """``(q (N, K, n), valid (N, K))`` for one chunk of poses."""
    if family.reverse:          # solve the chain seen from the tool (Screws.reversed)
        c, s, x, ok = solver(_memo(S, "reversed", S.reversed), invert_transform(T))
        c, s, x = c[::-1], -s[::-1], -x[::-1]
    else:
        c, s, x, ok = solver(S, T)
    rev = robot.is_revolute
    if not family.exact:
        return _on_true_robot(robot, c, s, x, ok, T)
    with np.errstate(invalid="ignore"):
        ok = ok & _fk_matches(robot, c, s, x, T,
                              ACCEPT_POSITION * max(robot.characteristic_length, 1e-12),
                              ACCEPT_ORIENTATION)
    q = np.where(rev[:, None, None], np.arctan2(s, c), x)                   # (n, N, K)
    ok = _first_of_duplicates(q, ok, rev)
    return np.moveaxis(q, 0, -1), ok


def _on_true_robot(robot, c, s, x, ok, T):
    """:func:`_solve_chunk` for a robot only nearly of its family (as
    :func:`kincalc.ik.solve._on_true_robot`): the closed form's candidates ``c, s, x
    (n, N, K)`` refined by Newton's method on the robot itself, and for six revolute
    joints the general 6R elimination's solutions added as further slots."""
    from .refine import refine
    from .screws import wrap
    rev = robot.is_revolute
    n, N, K = c.shape
    with np.errstate(invalid="ignore"):
        q = np.moveaxis(np.where(rev[:, None, None], np.arctan2(s, c), x), 0, -1).copy()
    ok = ok & np.isfinite(q).all(-1)
    q[ok] = refine(robot, q[ok], np.repeat(T[:, None], K, axis=1)[ok])
    if robot.dof == 6 and rev.all():
        from .general6r import solve_general_6r_batch
        qg, okg = solve_general_6r_batch(robot, T)
        q, ok = np.concatenate([q, qg], axis=1), np.concatenate([ok, okg], axis=1)
    q = np.where(rev, wrap(q), q)
    Tq = robot.fk(q[ok])
    L = max(robot.characteristic_length, 1e-12)
    Tt = np.repeat(T[:, None], q.shape[1], axis=1)[ok]
    good = (np.linalg.norm(Tq[:, :3, 3] - Tt[:, :3, 3], axis=-1) <= ACCEPT_POSITION * L) & \
        (np.linalg.norm(Tq[:, :3, :3] - Tt[:, :3, :3], axis=(-2, -1))
         <= 2 * np.sqrt(2) * np.sin(ACCEPT_ORIENTATION / 2))
    ok[ok] = good
    ok = _first_of_duplicates(np.moveaxis(q, -1, 0), ok, rev)
    return q, ok


def solve_batch(robot, T, *, chunk: int = CHUNK) -> BatchIK:
    """Every IK solution of ``robot`` for each pose in ``T (N, 4, 4)``, vectorised.

    Returns a :class:`BatchIK`: ``q (N, K, n)`` (rad in (-pi, pi] / m),
    ``valid (N, K)``. Invalid slots hold undefined numbers; use the mask. Poses
    are solved ``chunk`` at a time (the arithmetic is vectorised within a
    chunk). Raises :class:`~kincalc.ik.solve.UnsupportedRobot` for families
    without a batched closed form.
    """
    T = np.asarray(T, float)
    if T.ndim == 2:
        T = T[None]
    if T.shape[1:] != (4, 4):
        raise ValueError(f"expected poses of shape (N, 4, 4), got {T.shape}")
    S, family, why = plan(robot)
    if family is not None and family.name == "general-6r":
        return _general_6r(robot, T, chunk)
    if family is None or family.solver not in SOLVERS:
        raise UnsupportedRobot(f"{robot.name}: batched IK supports the "
                               f"{' and '.join(SOLVERS)} families (and their reversed "
                               f"chains), not {family.name if family else why}; use robot.ik "
                               "pose by pose")
    solver = SOLVERS[family.solver]
    N = len(T)
    if N == 0:              # the number of slots K comes from solving one pose
        qc, okc = _solve_chunk(robot, S, family, solver, robot.fk(robot.home)[None])
        return BatchIK(q=qc[:0], valid=okc[:0], family=family.name)
    q = valid = None
    for start in range(0, N, chunk):
        qc, okc = _solve_chunk(robot, S, family, solver, T[start:start + chunk])
        if q is None:
            q = np.empty((N,) + qc.shape[1:])
            valid = np.empty((N, qc.shape[1]), bool)
        q[start:start + len(qc)] = qc
        valid[start:start + len(qc)] = okc
    return BatchIK(q=q, valid=valid, family=family.name)


def _general_6r(robot, T, chunk: int) -> BatchIK:
    """:func:`~kincalc.ik.general6r.solve_general_6r_batch` in chunks, each pose's
    solutions ordered as :func:`kincalc.ik.solve` orders them (by joint 3, then joint 1:
    the order of its ``root k`` labels)."""
    from .general6r import BATCH_SLOTS, solve_general_6r_batch
    N = len(T)
    q = np.zeros((N, BATCH_SLOTS, 6))
    valid = np.zeros((N, BATCH_SLOTS), bool)
    for start in range(0, N, chunk):
        qc, okc = solve_general_6r_batch(robot, T[start:start + chunk])
        # invalid slots last, valid ones by (q3, q1)
        key = np.where(okc, qc[..., 2], np.inf), np.where(okc, qc[..., 0], np.inf)
        order = np.lexsort((key[1], key[0]), axis=-1)
        q[start:start + len(qc)] = np.take_along_axis(qc, order[..., None], axis=1)
        valid[start:start + len(qc)] = np.take_along_axis(okc, order, axis=1)
    return BatchIK(q=q, valid=valid, family="general-6r")


def branch_labels(robot, family: str, q, slots, poses=None) -> list:
    """Branch labels of solutions ``q (s, n)`` (SI) of a batched family, all at once.

    The words are those of :func:`kincalc.ik.solve.branch_label`, from
    :func:`kincalc.ik.solve.branch_geometry` on the joint frames of all solutions:
    shoulder right/left, elbow up/down, wrist flip/no-flip. Where none applies (the
    reversed chains) the label is ``branch K``, ``K`` the solution's slot ``slots (s,)``
    of the closed form; where two solutions of one pose (``poses (s,)``, the pose index
    of each solution) get the same words, ``branch K`` is appended to theirs. A general
    6R's solutions are ``<joint 3>:root k`` in the order of :func:`_general_6r`, as
    robot.ik labels them.
    """
    from ..fk import chain_frames
    from .solve import WORDS, branch_geometry
    q = np.asarray(q, float)
    s = len(q)
    if s == 0:
        return []
    slots = np.asarray(slots)
    if family == "general-6r":
        more = np.ones(s, bool) if poses is None else \
            np.bincount(np.asarray(poses))[np.asarray(poses)] > 1
        name = robot.joints[2].name
        return [f"{name}:root {int(k) + 1}" if m else "unique"
                for k, m in zip(slots.tolist(), more.tolist())]
    F = chain_frames(robot.chain, q)
    codes = branch_geometry(robot, family, F)
    key = codes.astype(int) @ [9, 3, 1]                   # one of 27 word combinations
    table = [" ".join(WORDS[w][x - 1] for w, x in enumerate((c // 9, c // 3 % 3, c % 3)) if x)
             for c in range(27)]
    out = [table[c] or f"branch {k}" for c, k in zip(key.tolist(), slots.tolist())]
    # the words may not tell every branch apart (robot.ik adds the +/- choice of the
    # other steps, e.g. Stanford's d3 root): name the closed form's slot as well there
    pose = np.zeros(s, int) if poses is None else np.asarray(poses)
    _, inverse, counts = np.unique(key + 27 * pose, return_inverse=True, return_counts=True)
    for k in np.flatnonzero((counts[inverse] > 1) & (key > 0)).tolist():
        out[k] = f"{out[k]} branch {int(slots[k])}"
    # a continuum's representative (the wrist singularity) names its free joint, as
    # robot.ik does: axis 6 along axis 4 (spherical wrist) or along axis 2 (UR arm),
    # within the solvers' PARALLEL_WRIST_TOL (the representatives are aligned exactly)
    from .families import PARALLEL_WRIST_TOL
    ref, free = {"spherical-wrist": (3, 3), "three-parallel": (1, 5)}.get(family, (None, None))
    if ref is not None:
        z = F[:, :, :3, 2]
        aligned = np.linalg.norm(cross(z[:, ref], z[:, 5]), axis=-1) <= PARALLEL_WRIST_TOL
        for k in np.flatnonzero(aligned).tolist():
            out[k] = f"{out[k]} ({robot.joints[free].name} free)"
    return out
