"""All real inverse-kinematics solutions of a general 6R robot.

Method
------
Raghavan & Roth's elimination (M. Raghavan, B. Roth, "Inverse kinematics of
the general 6R manipulator and related linkages", ASME J. Mech. Des. 115,
1993; conference version 1990) in the numerically robust matrix form of
D. Manocha, J. F. Canny, "Efficient inverse kinematics for general 6R
manipulators", IEEE Trans. Robotics and Automation 10(5):648-657, 1994.

1. **Standard DH of the six axes.** Whatever the robot's convention, the
   joint axes at q = 0 (:func:`kincalc.structure.joint_axes`) are turned into
   standard DH parameters ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``
   with ``theta_i = q_i + offset_i``, plus fixed transforms, so that
   ``T = B A_1 ... A_6 E``. Frame i-1 has z along joint i's axis (same sense,
   so no sign flips); x_i runs along the common normal of axes i and i+1
   (direction ``z_{i-1} x z_i``); its origin is the normal's foot on axis i+1.
   Consistent choices for the special cases: *intersecting* axes give
   ``a_i = 0`` with x_i still ``z_{i-1} x z_i``; *parallel* axes (sine of the
   angle below 1e-7) take the normal through the previous origin (``d_i = 0``),
   and *coincident* axes keep ``x_i = x_{i-1}``. Frame 0 sits at the foot of
   the 1-2 normal on axis 1 (``d_1 = 0``) with ``x_0 = x_1``; frame 6 equals
   frame 5 turned by theta_6 (``a_6 = d_6 = alpha_6 = 0``); ``B`` (base) and
   ``E`` (tool) absorb the rest. Lengths are divided by the robot's
   characteristic length so every number is O(1).
2. **The 14 Pieper / Lee-Liang equations.** From
   ``A_3 A_4 A_5 = A_2^-1 A_1^-1 T' A_6^-1`` take the third column ``l`` and
   the origin ``p`` (both free of theta_6) and form
   ``l, p, p.p, p.l, p x l, (p.p) l - 2 (p.l) p``. The left side is
   trilinear in (1, cos, sin) of theta_3, theta_4, theta_5, the right side
   bilinear in those of theta_1, theta_2 (Raghavan & Roth's observation). The
   coefficients are not typed in symbolically: they are read off exactly by
   a 3-point discrete Fourier fit per angle (grid 0, 2pi/3, 4pi/3), once per
   robot for the left side and once per pose (nine 4x4 products) for the
   right. This gives ``P(theta_3) X1 = Q X2`` with ``X1`` the nine products
   of (1, c4, s4) and (1, c5, s5), ``X2`` the eight non-constant products of
   (1, c1, s1) and (1, c2, s2), ``P`` 14x9 linear in (1, c3, s3), ``Q`` 14x8.
3. **Elimination.** ``X2`` is removed with an orthonormal basis ``N`` (6x14)
   of the left null space of ``Q`` (Householder QR, not Cramer's rule):
   ``N P(theta_3) X1 = 0``, a 6x9 system. Half-angle substitution
   ``x_i = tan(theta_i / 2)`` for i = 4, 5 and multiplication by ``x_4`` give
   the 12x12 matrix polynomial ``Sigma(x3) = A x3^2 + B x3 + C`` acting on
   the monomials ``x4^j x5^k`` (j <= 3, k <= 2).
4. **Eigenproblem.** ``det Sigma = 0`` (degree 24, with the spurious factor
   ``(1 + x3^2)^4``) is solved as the 24x24 companion eigenproblem
   ``[[0, I], [-A^-1 C, -A^-1 B]]`` with ``numpy.linalg.eig``.
   *Degenerate leading matrix / x3 = infinity (theta_3 = pi):* numpy has no
   QZ, so instead of a generalised eigensolver the unknown is shifted,
   ``theta_3 = phi + delta``: ``A`` is then ``Sigma`` at ``theta_3 = pi +
   delta``. Four shifts are tried (0 and three irrational-looking ones) and
   the one with the best-conditioned ``A`` is used, so a root at or near
   theta_3 = pi (common: the published 16-solution example has theta_3 =
   179.96 deg) never sits at infinity. Eigenvalues whose angle
   ``2 atan(y)`` has an imaginary part below 0.05 rad count as real
   candidates (near-double real roots come out as complex pairs).
5. **Back-substitution.** ``x4``, ``x5`` come from the eigenvector (least-
   squares ratios of its largest entries, inverted ratios when |x| > 1, so
   theta = pi is fine); ``(c1, s1, c2, s2)`` from ``Q X2 = P X1`` (least
   squares through the same QR); theta_6 from ``A_6 = (A_1..A_5)^-1 T'``.
   *Clusters:* eigenvalues whose angles' real parts are closer than 1e-3 rad
   (solutions sharing the pivot angle, e.g. the two wrist flips of a
   spherical wrist; near-double roots split into a conjugate pair) get a
   second set of vectors: at their mean, the monomial vectors are recovered
   from the null space of ``Sigma`` as common eigenvectors of the "multiply
   by x4" and "multiply by x5" shift operators; the vectors closest to
   monomial structure are kept (see :func:`_split_clusters`).
6. **Polishing.** Every candidate gets up to 10 damped Newton steps on the
   *given* robot (``robot.chain``, so the DH model above only has to be
   close): error ``[(p* - p) / L; log(R* R^T)]`` against the base-frame
   geometric Jacobian, steps limited to 0.5 rad. FK, joint frames and
   Jacobian of all candidates come from six stacked 4x4 products
   (:class:`_ChainTerms`), the rotation log from the skew part below 90
   degrees. Candidates whose final
   residual ``max(|dp| / L, |dw|)`` exceeds 1e-10 are dropped, the rest are
   wrapped to (-pi, pi] and merged when within 1e-6 rad.

Choice of pivot joint and special geometry
------------------------------------------
The closure ``A_1 ... A_6 = T'`` can be rotated cyclically into
``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I``: again a 6R inverse-kinematics
problem (joints k+1..6, 1..k; the pose becomes the fixed link between joints
6 and 1, the target is the identity), whose pivot is joint k + 3 (mod 6). Shift 0
(pivot joint 3) is the standard form and has its left-side coefficients
precomputed per robot; for the other shifts the DH model is rebuilt per pose
from the same axis lines (~0.5 ms more).

For robots with special structure the standard form degenerates: with three
parallel axes (UR arms) or a spherical wrist (PUMA, KUKA, ABB, FANUC) the
12x12 pencil is singular, every leading matrix ``A`` is singular
(``cond(A) > 1e10`` for all four shifts ``delta``), or ``Q`` loses rank
(relative singular value < 1e-9). Nearly special robots (a calibrated UR5
whose twists are off by 1e-8 .. 1e-4) are worse: the pencil is regular but
ill-conditioned and the eigenvalues are inaccurate. So once per robot
(cached) the six shifts are ranked on three seeded probe poses by how
accurately their raw candidates recover the generating configuration; shift
0 is kept without further probing when it is accurate to 1e-8 rad (every
generic robot). In the library, UR arms end up pivoting on joint 2 (shift
5, the parallel joints 2-3-4 on the left side) and wrist-partitioned arms
on joint 5 (shift 2) or joint 2. Per pose the ranked shifts are tried in
order until one is not degenerate. If all six degenerate (rare: e.g. a
random arm with axes 1-2-3 parallel and 3-4-5 intersecting pairwise), the
standard form is solved for two nearby *generic* robots (each scaled DH
parameter moved by a fixed pseudo-random 0.5 .. 1 times 1e-3, resp. 1e-4;
the larger size suits robots whose solutions are well separated, the
smaller one robots close to a singular configuration) and the union of
their candidates is polished on the real robot; this last resort can lose
solutions near singular configurations and is not reached by any robot of
the library. UR5 and PUMA thus give their (up to) 8 solutions, the same
as the analytic family solvers of :mod:`kincalc.ik.families`. Robots with
infinitely many solutions at a pose (coincident axes; a pose on a
self-motion) get whatever isolated points Newton lands on, or none.

Limitations
-----------
* Solutions at or very near a singular configuration converge slowly or to
  a neighbour and may be dropped by the 1e-10 residual test or merged: two
  distinct solutions closer than 1e-6 rad are reported once. For a generic
  6R the real count is even, so an odd count flags such a case. Special
  and nearly special robots (which need another pivot) lose a solution of
  a near-singular pair somewhat more often than generic ones.
* The 1e-10 acceptance is relative to ``robot.characteristic_length``; a
  pose outside the workspace gives an empty ``(0, 6)`` array.
* Robots with a prismatic joint are not handled (ValueError).
* Measured (one core, numpy/OpenBLAS, ``benchmarks/ik_single.py``): median
  ~0.6 ms per pose for a generic robot (~1 ms for ``robot.ik`` with its
  checks and labels), of which 0.1-0.15 ms is the 24x24 ``eig``; 1-2 ms for UR/PUMA/KUKA/ABB arms (per-pose model of the other
  pivot), plus a one-off 4-20 ms per robot for the model and the pivot
  ranking (cached for 64 robots).

Many poses at once
------------------
:func:`solve_general_6r_batch` runs the same steps (pivot joint 3) for
``N`` poses together: batched QR and pencils, ``numpy.linalg.eig`` over
``(N, 24, 24)``, back-substitution and Newton over all candidates of all
poses, the cluster treatment vectorised for pairs of close eigenvalues;
poses it does not finish (a degenerate standard form, a cluster of three
or more, every pose of a robot whose pivot ranking does not start at
joint 3) go through :func:`solve_general_6r` one by one. About 0.2-0.35 ms
per pose for N = 1000.
"""

from __future__ import annotations

import numpy as np

from ..spatial import cross, invert_transform, rotvec_from_matrix
from .cache import per_robot

__all__ = ["solve_general_6r", "solve_general_6r_batch"]

#: sine of the angle below which two consecutive axes are treated as parallel.
PARALLEL_TOL = 1e-7
#: residual (relative position, rad) a polished solution must reach.
ACCEPT_TOL = 1e-10
#: wrapped joint distance (rad) below which two solutions are the same.
MERGE_TOL = 1e-6
#: residual below which an unpolished candidate is returned (polish=False).
RAW_TOL = 1e-6
#: |Im(theta_3)| (rad) below which an eigenvalue is a real candidate.
IMAG_TOL = 0.05
#: eigenvalues (as angles, rad) closer than this are treated as one cluster.
CLUSTER_TOL = 1e-3
#: sizes of the generic perturbations of the last resort (scaled units, rad).
PERTURB = (1e-3, 1e-4)

# 3-point DFT grid: exact for (1, cos, sin) expansions.
_GRID = np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0])
_VINV = np.linalg.inv(np.stack([np.ones(3), np.cos(_GRID), np.sin(_GRID)], axis=1))
# the same fit for two angles at once: (9, 9), rows i1 * 3 + i2, columns grid a * 3 + b
_VINV2 = np.kron(_VINV, _VINV)
# (1, c, s) * (1 + x^2) in powers (1, x, x^2) of x = tan(theta / 2)
_H = np.array([[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]])
_H2 = np.kron(_H, _H)     # trig (i4, i5) -> powers (j4, j5), both flattened i*3 + j
_DELTAS = (0.0, 1.1071487177940904, -0.6435011087932844, 2.4980915447965089)
_COS_SIN_DELTAS = tuple((float(np.cos(d)), float(np.sin(d))) for d in _DELTAS)
_STEP_MAX = 0.5
_NEWTON_ITERS = 10
_GIVE_UP = {3: 1e-2, 6: 1e-6}      # after this many steps, drop candidates still above


# --- small vectorised helpers ---------------------------------------------

def _dh(theta, d, a, alpha):
    """Standard DH link transforms ``(..., 4, 4)``; all arguments broadcast."""
    theta, d, a, alpha = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                               for x in (theta, d, a, alpha)))
    c, s = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(alpha), np.sin(alpha)
    T = np.zeros(theta.shape + (4, 4))
    T[..., 0, 0] = c
    T[..., 0, 1] = -s * ca
    T[..., 0, 2] = s * sa
    T[..., 0, 3] = a * c
    T[..., 1, 0] = s
    T[..., 1, 1] = c * ca
    T[..., 1, 2] = -c * sa
    T[..., 1, 3] = a * s
    T[..., 2, 1] = sa
    T[..., 2, 2] = ca
    T[..., 2, 3] = d
    T[..., 3, 3] = 1.0
    return T


def _f14(l, p):
    """The 14 Raghavan-Roth quantities ``(..., 14)`` of ``l, p (..., 3)``."""
    pp = np.einsum("...i,...i->...", p, p)[..., None]
    pl = np.einsum("...i,...i->...", p, l)[..., None]
    return np.concatenate([l, p, pp, pl, cross(p, l), pp * l - 2.0 * pl * p], axis=-1)


def _wrap(q):
    """Angles wrapped to (-pi, pi]."""
    return np.pi - np.mod(np.pi - q, 2.0 * np.pi)


# --- the robot as standard DH ----------------------------------------------

def _dh_frames(dirs, pts, L):
    """World poses ``(7, 4, 4)`` of DH frames 0..6 at q = 0 (see module docstring)."""
    z = [dirs[i] for i in range(6)] + [dirs[5]]      # z_i = axis i+1; z_6 = axis 6
    x = [None] * 7
    o = [None] * 7
    for i in range(1, 6):                            # frame i: axes i (0-based i-1) and i+1
        u, v = dirs[i - 1], dirs[i]
        p, r = pts[i - 1], pts[i]
        n = cross(u, v)
        sn = np.linalg.norm(n)
        if sn > PARALLEL_TOL:
            # closest points p + t u (axis i) and r + s v (axis i+1)
            w = r - p
            uv = u @ v
            den = 1.0 - uv * uv
            t = (w @ u - (w @ v) * uv) / den
            s = ((w @ u) * uv - w @ v) / den
            foot_i, foot_j = p + t * u, r + s * v
            xi = n / sn
            if i == 1:
                o[0] = foot_i
        else:
            if i == 1:
                o[0] = p
            ref = o[i - 1]
            w = r - ref
            w = w - u * (w @ u)
            nw = np.linalg.norm(w)
            if nw > 1e-9 * L:
                xi = w / nw
            elif x[i - 1] is not None:
                xi = x[i - 1]
            else:                                    # axes 1 and 2 coincide
                xi = cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
            foot_j = ref + w
        xi = xi - v * (xi @ v)
        x[i] = xi / np.linalg.norm(xi)
        o[i] = foot_j
        if i == 1:
            x0 = x[1] - z[0] * (x[1] @ z[0])
            x[0] = x0 / np.linalg.norm(x0)
    x[6], o[6] = x[5] - z[6] * (x[5] @ z[6]), o[5]
    x[6] /= np.linalg.norm(x[6])
    F = np.zeros((7, 4, 4))
    for i in range(7):
        F[i, :3, 0] = x[i]
        F[i, :3, 1] = cross(z[i], x[i])
        F[i, :3, 2] = z[i]
        F[i, :3, 3] = o[i]
        F[i, 3, 3] = 1.0
    return F


class _Model:
    """A 6R robot as scaled standard DH plus the per-robot half of the elimination."""

    def __init__(self, B, E, L, theta0, d, a, alpha):
        self.B, self.E, self.L = B, E, L
        self.Binv, self.Einv = invert_transform(B), invert_transform(E)
        self.offset = np.asarray(theta0, float)
        self.d, self.a, self.alpha = (np.asarray(v, float) for v in (d, a, alpha))
        d, a, al = self.d, self.a, self.alpha
        # right side: inverses of A1(g1) A2(g2) on the 3x3 grid, and T' -> W
        g1, g2 = np.meshgrid(_GRID, _GRID, indexing="ij")
        A12 = _dh(g1.ravel(), d[0], a[0], al[0]) @ _dh(g2.ravel(), d[1], a[1], al[1])
        self.N12 = invert_transform(A12)                  # (9, 4, 4)
        self.N12R, self.N12t = self.N12[:, :3, :3].copy(), self.N12[:, :3, 3].copy()
        self.post = invert_transform(_dh(0.0, d[5], a[5], al[5]))
        # left side: l, p of A3 A4 A5 on the 3x3x3 grid -> coefficients
        g3, g4, g5 = (m.ravel() for m in np.meshgrid(_GRID, _GRID, _GRID, indexing="ij"))
        M = _dh(g3, d[2], a[2], al[2]) @ _dh(g4, d[3], a[3], al[3]) @ _dh(g5, d[4], a[4], al[4])
        F = _f14(M[:, :3, 2], M[:, :3, 3]).reshape(3, 3, 3, 14)
        C = np.einsum("ia,jb,kc,abce->iejk", _VINV, _VINV, _VINV, F)
        self.P = C.reshape(3, 14, 9)                      # P(theta3) = P0 + c3 P1 + s3 P2

    @classmethod
    def from_lines(cls, dirs, pts, T0, L):
        """Model of the 6R whose axes at q = 0 are ``pts[i] + t dirs[i]`` and tool pose ``T0``."""
        F = _dh_frames(dirs, pts, L)
        G = invert_transform(F[:-1]) @ F[1:]             # (6, 4, 4) = A_i(offset_i)
        theta0 = np.arctan2(G[:, 1, 0], G[:, 0, 0])
        d = G[:, 2, 3]
        a = G[:, 0, 3] * np.cos(theta0) + G[:, 1, 3] * np.sin(theta0)
        alpha = np.arctan2(G[:, 2, 1], G[:, 2, 2])
        E = invert_transform(F[6]) @ T0
        return cls(F[0], E, L, theta0, d / L, a / L, alpha)

    def perturbed(self, size):
        """The same robot with every scaled DH parameter moved by 0.5 .. 1 ``size`` (seeded)."""
        rng = np.random.default_rng(20240611)
        dd, da, dal = rng.uniform(0.5, 1.0, (3, 6)) * rng.choice([-1.0, 1.0], (3, 6)) * size
        m = _Model(self.B, self.E, self.L, self.offset, self.d + dd, self.a + da,
                   self.alpha + dal)
        return m

    def fk_dh(self, q):
        """FK of the DH model (SI), for checks."""
        th = np.asarray(q, float) + self.offset
        T = np.broadcast_to(np.eye(4), th.shape[:-1] + (4, 4)).copy()
        for i in range(6):
            T = T @ _dh(th[..., i], self.d[i], self.a[i], self.alpha[i])
        T[..., :3, 3] *= self.L
        return self.B @ T @ self.E

    # --- per pose -------------------------------------------------------

    def _coefficients(self, T):
        """``(P (..., 3, 14, 9), Q (..., 14, 8), W (..., 4, 4))`` of poses ``T (..., 4, 4)``:
        the system ``P(theta_3) X1 = Q X2`` and the scaled target with A_6^-1 folded in."""
        W = self.Binv @ T @ self.Einv
        W[..., :3, 3] /= self.L
        W = W @ self.post
        lT, pT = W[..., None, :3, 2], W[..., None, :3, 3]
        # right side at the 3x3 grid of (theta_1, theta_2): R @ l, R @ p + t
        lR = np.einsum("kij,...kj->...ki", self.N12R, lT)
        pR = np.einsum("kij,...kj->...ki", self.N12R, pT) + self.N12t
        Rc = np.swapaxes(_VINV2 @ _f14(lR, pR), -1, -2)           # (..., 14, 9)
        P = np.broadcast_to(self.P, T.shape[:-2] + self.P.shape).copy()
        P[..., 0, :, 0] -= Rc[..., :, 0]
        return P, Rc[..., :, 1:], W

    def candidates(self, T):
        """Joint-value candidates ``(m, 6)`` from the eigenproblem, or None if degenerate."""
        P, Q, W = self._coefficients(T)
        Qf, Rq = np.linalg.qr(Q, mode="complete")
        rd = np.abs(np.diag(Rq[:8]))
        if rd.min() <= 1e-9 * max(rd.max(), 1e-300):
            return None
        N = Qf[:, 8:].T                                   # (6, 14), N Q = 0
        S = N @ P                                          # (3, 6, 9)
        scale = np.sqrt(np.einsum("kij,kij->i", S, S))
        if scale.min() <= 1e-12 * scale.max():
            return None
        S = S / scale[None, :, None]

        best = None
        for delta, (cd, sd) in zip(_DELTAS, _COS_SIN_DELTAS):
            Sc = S[1] * cd + S[2] * sd
            Ss = S[2] * cd - S[1] * sd
            coeffs = np.stack([S[0] + Sc, 2.0 * Ss, S[0] - Sc]) @ _H2    # 1, y, y^2
            mats = np.zeros((3, 12, 12))
            mats[:, :6, :9] = coeffs
            mats[:, 6:, 3:] = coeffs
            cond = np.linalg.cond(mats[2])
            if best is None or cond < best[0]:
                best = (cond, delta, mats)
            if cond < 1e4:
                break
        cond, delta, (Cm, Bm, Am) = best
        if not np.isfinite(cond) or cond > 1e10:
            return None
        AiB = np.linalg.solve(Am, np.concatenate([Cm, Bm], axis=1))
        Comp = np.zeros((24, 24))
        Comp[:12, 12:] = np.eye(12)
        Comp[12:] = -AiB
        y, vecs = np.linalg.eig(Comp)
        with np.errstate(all="ignore"):
            phi = 2.0 * np.arctan(y)
        keep = np.isfinite(phi) & (np.abs(phi.imag) < IMAG_TOL)
        if not np.any(keep):
            return np.zeros((0, 6))
        y, vecs, phi = y[keep], vecs[:, keep], phi[keep]
        big = np.abs(y) > 1.0
        v = np.where(big[None, :], vecs[12:], vecs[:12])  # (12, m)
        v = v / np.linalg.norm(v, axis=0)
        v, phi = _split_clusters(v, phi, (Cm, Bm, Am))
        th3 = phi.real + delta
        idx = np.argmax(np.abs(v), axis=0)
        v = (v / v[idx, np.arange(v.shape[1])]).real.T.reshape(-1, 4, 3)   # (m, j4, j5)
        return self._back_substitute(P, Qf, Rq, W, th3, _ratio_angle(v, axis=1),
                                     _ratio_angle(v, axis=2))

    def _back_substitute(self, P, Qf, Rq, W, th3, th4, th5):
        """Joint values ``(..., m, 6)`` (original offsets, wrapped) from theta_3..5 ``(..., m)``:
        theta_1, theta_2 from ``Q X2 = P X1`` through the QR of Q, theta_6 from
        ``A_6 = (A_1 .. A_5)^-1 T'``. ``P (..., 3, 14, 9)``, ``Qf (..., 14, 14)``,
        ``Rq (..., 14, 8)``, ``W (..., 4, 4)`` for the pose of each leading index."""
        c3, s3, c4, s4, c5, s5 = (f(t) for t in (th3, th4, th5) for f in (np.cos, np.sin))
        one = np.ones_like(c4)
        b4 = np.stack([one, c4, s4], -1)
        b5 = np.stack([one, c5, s5], -1)
        X1 = (b4[..., :, None] * b5[..., None, :]).reshape(b4.shape[:-1] + (9,))
        b3 = np.stack([one, c3, s3], -1)                                    # (..., m, 3)
        # Q X2 = P(theta3) X1 = sum_k b3_k P_k X1, solved through Q = Qf Rq: X2 = Y Z with
        # Y the 27 products b3_k X1_j and Z = (Rq8^-1 Qf8^T P_flat^T)^T, one per pose
        Y = (b3[..., :, None] * X1[..., None, :]).reshape(b3.shape[:-1] + (27,))
        Pflat = np.swapaxes(P, -1, -2).reshape(P.shape[:-3] + (27, 14))
        Z = np.swapaxes(np.linalg.solve(Rq[..., :8, :],
                                        np.swapaxes(Pflat @ Qf[..., :, :8], -1, -2)), -1, -2)
        X2 = Y @ Z                                                          # (..., m, 8)
        # X2 = products (i1, i2) != (0, 0), flattened i1 * 3 + i2 minus one
        th1 = np.arctan2(X2[..., 5], X2[..., 2])
        th2 = np.arctan2(X2[..., 1], X2[..., 0])
        th15 = np.stack([th1, th2, th3, th4, th5], axis=-1)
        A = _dh(th15, self.d[:5], self.a[:5], self.alpha[:5])[..., :3, :3]   # (..., m, 5, 3, 3)
        R15 = A[..., 0, :, :] @ A[..., 1, :, :] @ A[..., 2, :, :] @ A[..., 3, :, :] \
            @ A[..., 4, :, :]
        w0 = W[..., None, :3, 0]                                              # (..., 1, 3)
        # R6 = R15^T W = Rz(theta6): theta6 from its first column
        r6 = np.einsum("...ki,...k->...i", R15, w0)
        th6 = np.arctan2(r6[..., 1], r6[..., 0])
        th = np.stack([th1, th2, th3, th4, th5, th6], axis=-1)
        return _wrap(th - self.offset)


# index sets of the monomials x4^j x5^k (flattened j * 3 + k) for the shift operators
_J4, _J5 = np.divmod(np.arange(12), 3)
_LO4, _HI4 = np.flatnonzero(_J4 < 3), np.flatnonzero(_J4 > 0)
_LO5, _HI5 = np.flatnonzero(_J5 < 2), np.flatnonzero(_J5 > 0)
_TAU = np.tan(0.3)


def _split_clusters(v, phi, mats):
    """Better vectors for clustered eigenvalues: returns new ``(v, phi)``.

    Solutions that share the pivot angle (e.g. the two wrist flips of a
    spherical wrist when the pivot is an arm joint) give a multiple
    eigenvalue, often defective in the companion form: it splits by up to
    ~sqrt(eps) and eig's vectors are arbitrary mixtures, or nearly parallel.
    The mean of a cluster is accurate (Manocha & Canny 1994, sec. V-B), so
    each cluster of m eigenvalues (real parts of the angles within
    CLUSTER_TOL; this includes a conjugate pair with a small imaginary part,
    which is how a near-double real root often comes out) gets the mean
    angle and, as its space, the m smallest right singular vectors ``N`` of
    ``Sigma`` there. In that space the true vectors ``v = N c`` are those of
    monomials, so ``c`` is a common eigenvector of the shift operators
    "multiply by x4" (``v[j+1, k] = x4 v[j, k]``) and "multiply by x5"; these
    m x m operators come from least squares on the Moebius-shifted form
    ``(Hi - t Lo) c = z (Lo + t Hi) c`` (finite even at x = infinity), and a
    fixed combination of the two is diagonalised. The cluster's own
    eigenvectors compete (they are right when its eigenvalues are distinct
    roots that merely lie close): of the 2m vectors, those within 1e-3 of a
    monomial vector are kept, and at least the m closest.
    """
    m = len(phi)
    if m < 2:
        return v, phi
    order = np.argsort(phi.real)
    if np.min(np.diff(phi.real[order])) >= CLUSTER_TOL:
        return v, phi                                    # no cluster (the common case)
    groups, cur = [], [order[0]]
    for a, b in zip(order[:-1], order[1:]):
        if abs(phi[b].real - phi[a].real) < CLUSTER_TOL:
            cur.append(b)
        else:
            groups.append(cur)
            cur = [b]
    groups.append(cur)
    Cm, Bm, Am = mats
    new_v, new_phi, drop = [], [], []
    for grp in groups:
        k = len(grp)
        if k < 2:
            continue
        mean = float(np.mean(phi[grp].real))
        y = np.tan(mean / 2.0)
        if abs(y) <= 1.0:
            S = (Am * y + Bm) * y + Cm
        else:
            w = 1.0 / y
            S = Am + (Bm + Cm * w) * w
        N = np.linalg.svd(S)[2][-k:].T                    # (12, k)
        M = np.zeros((k, k))
        for lo, hi, wgt in ((_LO4, _HI4, 1.0), (_LO5, _HI5, 0.6180339887)):
            lhs = N[lo] + _TAU * N[hi]
            rhs = N[hi] - _TAU * N[lo]
            M += wgt * np.linalg.lstsq(lhs, rhs, rcond=None)[0]
        _, C = np.linalg.eig(M)
        # of the 2k vectors (own, subspace) keep those close to monomial vectors (at least k)
        both = np.concatenate([v[:, grp], N @ C], axis=1)
        both_phi = np.concatenate([phi[grp], np.full(k, mean)])
        res = _structure_residual(both)
        keep = (res < 1e-3) | (np.argsort(np.argsort(res, kind="stable")) < k)
        new_v.append(both[:, keep])
        new_phi.append(both_phi[keep])
        drop.extend(grp)
    rest = np.setdiff1d(np.arange(m), drop)
    return (np.concatenate([v[:, rest]] + new_v, axis=1),
            np.concatenate([phi[rest]] + new_phi))


def _structure_residual(V):
    """Sine of the angle between each column of ``V (12, n)`` and the nearest monomial vector."""
    idx = np.argmax(np.abs(V), axis=0)
    R = (V / V[idx, np.arange(V.shape[1])]).real
    Rm = R.T.reshape(-1, 4, 3)
    h4 = _ratio_angle(Rm, axis=1) / 2.0
    h5 = _ratio_angle(Rm, axis=2) / 2.0
    # x4^j x5^k times cos^3(h4) cos^2(h5): bounded also at x = infinity
    m4 = np.stack([np.cos(h4) ** (3 - j) * np.sin(h4) ** j for j in range(4)], axis=-1)
    m5 = np.stack([np.cos(h5) ** (2 - j) * np.sin(h5) ** j for j in range(3)], axis=-1)
    W = (m4[:, :, None] * m5[:, None, :]).reshape(-1, 12)
    R = R.T
    cos = np.abs(np.sum(R * W, axis=1)) / (np.linalg.norm(R, axis=1) * np.linalg.norm(W, axis=1))
    return np.sqrt(np.maximum(0.0, 1.0 - cos * cos))


def _ratio_angle(v, axis):
    """Angle theta with x = tan(theta/2) from monomial vectors ``v (m, 4, 3)`` along ``axis``."""
    if axis == 1:
        lo, hi = v[:, :-1, :], v[:, 1:, :]
    else:
        lo, hi = v[:, :, :-1], v[:, :, 1:]
    sum_axes = (1, 2)
    cross = np.sum(lo * hi, axis=sum_axes)
    dlo = np.sum(lo * lo, axis=sum_axes)
    dhi = np.sum(hi * hi, axis=sum_axes)
    with np.errstate(all="ignore"):
        fwd = 2.0 * np.arctan2(cross, dlo)      # x = cross / dlo
        bwd = 2.0 * np.arctan2(dhi, cross)      # 1/x = cross / dhi
    return np.where(dlo >= dhi, fwd, bwd)


class _Robot6R:
    """Per-robot data: axes at q = 0, the shift-0 model, and the formulation order."""

    def __init__(self, robot):
        from ..structure import joint_axes
        self.dirs, self.pts = joint_axes(robot)
        self.T0 = robot.fk(np.zeros(6))
        self.L = float(robot.characteristic_length)
        self.model = _Model.from_lines(self.dirs, self.pts, self.T0, self.L)
        self._perturbed = None
        self.shifts = self._rank_shifts(robot)

    def _rank_shifts(self, robot):
        """Pivot choices (cyclic shifts) ordered by the raw accuracy they reach on probe poses.

        The probe poses are FK of seeded random configurations; a shift's score is
        its worst distance from the generating configuration to the nearest raw
        (unpolished) candidate. Shift 0 (pivot joint 3, the per-robot precomputed
        form) is kept first when it recovers every probe to 1e-8 rad. Otherwise
        shifts accurate to 1e-8 come first, fewest candidates first, then the
        rest by accuracy.
        """
        qs = np.random.default_rng(6).uniform(-np.pi, np.pi, (3, 6))
        Ts = robot.fk(qs)
        keys = []
        for k in range(6):
            worst, count = 0.0, 0
            for q, T in zip(qs, Ts):
                c = self.candidates(T, k)
                if c is None or len(c) == 0:
                    worst = np.inf
                    break
                worst = max(worst, float(np.min(np.max(np.abs(_wrap(c - q)), axis=1))))
                count += len(c)
            if k == 0 and worst < 1e-8:
                return list(range(6))
            # accurate shifts first, among them the one with fewer candidates (less Newton work)
            keys.append((worst >= 1e-8, worst if worst >= 1e-8 else count, k))
        return [k for *_, k in sorted(keys)]

    @property
    def perturbed(self):
        """Nearby generic models (one per PERTURB size), built on first use."""
        if self._perturbed is None:
            self._perturbed = [self.model.perturbed(size) for size in PERTURB]
        return self._perturbed

    def shifted_model(self, T, shift):
        """``(model, order)``: the 6R of the cyclic shift ``shift`` for pose ``T`` (its
        target is the identity) and its joints' indices in the original order."""
        G = self.T0 @ invert_transform(T)
        order = np.r_[shift:6, 0:shift]
        dirs, pts = self.dirs[order].copy(), self.pts[order].copy()
        moved = order < shift
        dirs[moved] = dirs[moved] @ G[:3, :3].T
        pts[moved] = pts[moved] @ G[:3, :3].T + G[:3, 3]
        return _Model.from_lines(dirs, pts, G, self.L), order

    def candidates(self, T, shift):
        """Candidates ``(m, 6)`` (original joint order), or None if degenerate.

        The pivot is joint ``(shift + 2) % 6 + 1`` (1-based): 3 for shift 0, 2 for shift 5.

        ``A_1 ... A_6 = T'`` is rotated into ``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I``:
        a 6R chain whose joints are k+1..6, 1..k, with the pose folded into the
        link between joints 6 and 1, and the target the identity.
        """
        if shift == 0:
            return self.model.candidates(T)
        model, order = self.shifted_model(T, shift)
        c = model.candidates(np.eye(4))
        if c is None:
            return None
        out = np.empty_like(c)
        out[:, order] = c
        return out


@per_robot
def _robot_data(robot):
    return _Robot6R(robot)


# --- Newton polishing on the real robot -----------------------------------

class _ChainTerms:
    """``robot.chain`` of a 6R as constant arrays for :meth:`link_transforms`.

    The chain is ``F_0 Rz(q_1 + o_1) F_1 ... Rz(q_6 + o_6) F_6``; each
    ``Rz(t) F_i = cos(t) Kc_i + sin(t) Ks_i + K0_i`` (the first two rows of
    ``F_i`` mixed, the last two kept), so all six links of all candidates come
    from three products, and FK, the joint frames and the Jacobian from six
    stacked matrix products (not a Python loop of small operations per joint).
    """

    def __init__(self, chain):
        F = np.asarray(chain.fixed, float)
        self.F0 = F[0, :3, :].copy()                      # (3, 4)
        Fi = F[1:]
        self.Kc = np.zeros((6, 4, 4))
        self.Ks = np.zeros((6, 4, 4))
        self.K0 = np.zeros((6, 4, 4))
        self.Kc[:, :2] = Fi[:, :2]
        self.Ks[:, 0], self.Ks[:, 1] = -Fi[:, 1], Fi[:, 0]
        self.K0[:, 2:] = Fi[:, 2:]
        self.offset = np.asarray(chain.offset, float)

    def frames(self, Q):
        """``(m, 7, 3, 4)``: rows 0-2 of ``F_0 A_1 ... A_i`` for i = 0..6 at ``Q (m, 6)``;
        the z column of entry i is joint i+1's axis, its last column a point on it, and
        entry 6 is the tool pose."""
        th = Q + self.offset
        c = np.cos(th)[..., None, None]
        s = np.sin(th)[..., None, None]
        A = c * self.Kc + s * self.Ks + self.K0           # (m, 6, 4, 4)
        out = np.empty((len(Q), 7, 3, 4))
        out[:, 0] = self.F0
        for i in range(6):
            np.matmul(out[:, i], A[:, i], out=out[:, i + 1])
        return out


@per_robot
def _chain_terms(robot):
    return _ChainTerms(robot.chain)


def _rotvec(R):
    """Rotation vector ``(m, 3)`` of ``R (m, 3, 3)``: from the skew part, which is
    accurate to rounding up to 90 degrees; larger angles go through the quaternion
    (:func:`~kincalc.spatial.rotvec_from_matrix`)."""
    v = 0.5 * np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0],
                        R[:, 1, 0] - R[:, 0, 1]], axis=-1)          # sin(angle) axis
    c = 0.5 * (R[:, 0, 0] + R[:, 1, 1] + R[:, 2, 2] - 1.0)        # cos(angle)
    sn = np.sqrt(np.einsum("ij,ij->i", v, v))
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(sn > 1e-300, np.arctan2(sn, c) / sn, 1.0)
    w = v * f[:, None]
    far = c < 0.0
    if np.any(far):
        w[far] = rotvec_from_matrix(R[far])
    return w


def _jacobian_error(terms, T, Q, L):
    """``(J (m, 6, 6), e (m, 6))`` at ``Q (m, 6)`` for targets ``T (m or 1, 4, 4)``:
    the base-frame geometric Jacobian with its linear rows divided by ``L`` and the
    error ``[(p* - p) / L; log(R* R^T)]``."""
    F = terms.frames(Q)
    z = F[:, :6, :, 2]                                    # (m, 6, 3) axes
    pe = F[:, 6, :, 3]
    lin = cross(z, pe[:, None, :] - F[:, :6, :, 3]) / L
    J = np.concatenate([lin, z], axis=-1).transpose(0, 2, 1)
    ep = (T[:, :3, 3] - pe) / L
    ew = _rotvec(T[:, :3, :3] @ np.swapaxes(F[:, 6, :, :3], -1, -2))
    return J, np.concatenate([ep, ew], axis=-1)


def _pose_error(T, Tc, L):
    ep = (T[:3, 3] - Tc[:, :3, 3]) / L
    ew = rotvec_from_matrix(T[:3, :3] @ np.swapaxes(Tc[:, :3, :3], -1, -2))
    return np.concatenate([ep, ew], axis=-1)


def _polish(robot, T, Q, L, iters=_NEWTON_ITERS):
    """Damped Newton on ``fk(q) = T``; returns ``(q, residual)``.

    ``T`` is one pose ``(4, 4)`` or one per candidate ``(m, 4, 4)`` (the batched
    solver). A candidate stops when its residual is at rounding level (below 1e-13,
    or below ACCEPT_TOL / 100 and no longer halving), after ``iters`` steps, or
    when it is still far after a few (``_GIVE_UP``: spurious candidates from
    complex eigenvalues; the few that would wander into a solution after many
    steps only find one that a good candidate already gave).
    """
    terms = _chain_terms(robot)
    Q = np.array(Q, dtype=float).reshape(-1, 6)
    T = np.asarray(T, dtype=float).reshape(-1, 4, 4)
    per_row = len(T) > 1 or len(Q) == 1
    res = np.full(len(Q), np.inf)
    idx = np.arange(len(Q))
    eye = np.eye(6)
    for it in range(iters + 1):
        J, e = _jacobian_error(terms, T[idx] if per_row else T, Q[idx], L)
        r = np.max(np.abs(e), axis=-1)
        prev = res[idx]
        res[idx] = r
        go = (r >= 1e-13) & ~((r < 1e-2 * ACCEPT_TOL) & (r > 0.5 * prev))
        go &= r < _GIVE_UP.get(it, np.inf)
        if it == iters or not np.any(go):
            break
        idx, J, e = idx[go], J[go], e[go]
        JT = np.swapaxes(J, -1, -2)
        H = JT @ J
        lam = 1e-14 * np.trace(H, axis1=-2, axis2=-1)[:, None, None] + 1e-300
        dq = np.linalg.solve(H + lam * eye, (JT @ e[..., None]))[..., 0]
        n = np.max(np.abs(dq), axis=-1, keepdims=True)
        dq = np.where(n > _STEP_MAX, dq * (_STEP_MAX / np.maximum(n, 1e-300)), dq)
        Q[idx] += dq
    return Q, res


def _merge(Q):
    """Drop rows within MERGE_TOL (wrapped, max-abs) of an earlier row."""
    if len(Q) < 2:
        return Q.reshape(-1, 6)
    D = np.max(np.abs(_wrap(Q[:, None, :] - Q[None, :, :])), axis=-1)
    dup = np.any(np.tril(D < MERGE_TOL, k=-1), axis=1)
    return Q[~dup]


# --- public API -------------------------------------------------------------

def solve_general_6r(robot, T, *, polish: bool = True) -> np.ndarray:
    """All real joint solutions (k, 6) in rad, k <= 16, of robot.fk(q) == T (4x4, SI, world frame).

    Raises ValueError if robot is not 6 revolute joints. Each returned row reproduces T by FK to ~1e-10
    relative to the robot size after Newton polishing; duplicates merged; angles wrapped to (-pi, pi].

    With ``polish=False`` no Newton step is taken: the eigenproblem's candidates are returned if
    their residual is below 1e-6 (merged, wrapped), which shows the accuracy of the elimination
    itself.
    """
    if robot.dof != 6 or not all([j.revolute for j in robot.joints]):
        raise ValueError("solve_general_6r needs a robot with exactly 6 revolute joints, got "
                         + "".join("R" if j.revolute else "P" for j in robot.joints))
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise ValueError(f"T must be a finite 4x4 transform, got shape {T.shape}")
    data = _robot_data(robot)
    cand = None
    for shift in data.shifts:
        cand = data.candidates(T, shift)
        if cand is not None:
            break
    if cand is None:
        found = [c for c in (m.candidates(T) for m in data.perturbed) if c is not None]
        cand = np.concatenate(found) if found else None
        if cand is None:
            raise ValueError("the elimination degenerates for this robot and pose, "
                             "even after a generic perturbation")
    cand = cand[np.all(np.isfinite(cand), axis=1)]
    if len(cand) == 0:
        return np.zeros((0, 6))
    if not polish:
        res = np.max(np.abs(_pose_error(T, robot.fk(cand), data.L)), axis=-1)
        return _merge(_wrap(cand[res < RAW_TOL]))
    Q, res = _polish(robot, T, cand, data.L)
    Q = _wrap(Q[res < ACCEPT_TOL])
    return _merge(Q)


# --- many poses at once -------------------------------------------------------

#: solution slots per pose of :func:`solve_general_6r_batch` (a general 6R has at most 16)
BATCH_SLOTS = 16


def _candidates_batch(model, T):
    """Raw candidates of the standard form (pivot joint 3) for poses ``T (M, 4, 4)``.

    The steps of :meth:`_Model.candidates`, vectorised over poses: returns ``(Q (M, 48, 6),
    valid (M, 48), fallback (M,))``. Slots 0-23 hold the eigenvalues, slots 24-47 the second
    vectors of two-eigenvalue clusters (:func:`_split_clusters_batch`). ``fallback`` marks
    the poses the batch does not finish: a degenerate elimination (the single-pose solver
    then tries other pivots) or a cluster of three or more eigenvalues.
    """
    M = len(T)
    P, Qm, W = model._coefficients(T)
    Qf, Rq = np.linalg.qr(Qm, mode="complete")
    rd = np.abs(np.diagonal(Rq[:, :8, :8], axis1=-2, axis2=-1))
    bad = rd.min(axis=-1) <= 1e-9 * np.maximum(rd.max(axis=-1), 1e-300)
    Nt = np.swapaxes(Qf[:, :, 8:], -1, -2)                              # (M, 6, 14)
    S = np.einsum("mij,mkjl->mkil", Nt, P)                              # (M, 3, 6, 9)
    scale = np.sqrt(np.einsum("mkij,mkij->mi", S, S))
    bad |= scale.min(axis=-1) <= 1e-12 * scale.max(axis=-1)
    S = S / np.where(bad[:, None], 1.0, scale)[:, None, :, None]
    # the shift delta per pose: the first with cond(A) < 1e4, else the best conditioned
    mats = np.zeros((M, 3, 12, 12))
    delta = np.zeros(M)
    best = np.full(M, np.inf)
    todo = np.flatnonzero(~bad)
    for k, (dl, (cd, sd)) in enumerate(zip(_DELTAS, _COS_SIN_DELTAS)):
        if len(todo) == 0:
            break
        Sx = S[todo]
        Sc = Sx[:, 1] * cd + Sx[:, 2] * sd
        Ss = Sx[:, 2] * cd - Sx[:, 1] * sd
        coeffs = np.stack([Sx[:, 0] + Sc, 2.0 * Ss, Sx[:, 0] - Sc], axis=1) @ _H2
        mk = np.zeros((len(todo), 3, 12, 12))
        mk[:, :, :6, :9] = coeffs
        mk[:, :, 6:, 3:] = coeffs
        cond = np.linalg.cond(mk[:, 2])
        take = (cond < best[todo]) | (k == 0)
        rows = todo[take]
        mats[rows], delta[rows], best[rows] = mk[take], dl, cond[take]
        todo = todo[~(cond < 1e4)]
    bad |= ~np.isfinite(best) | (best > 1e10)
    Q = np.zeros((M, 48, 6))
    valid = np.zeros((M, 48), bool)
    g = np.flatnonzero(~bad)
    if len(g) == 0:
        return Q, valid, bad
    Cm, Bm, Am = mats[g, 0], mats[g, 1], mats[g, 2]
    AiB = np.linalg.solve(Am, np.concatenate([Cm, Bm], axis=2))
    Comp = np.zeros((len(g), 24, 24))
    Comp[:, :12, 12:] = np.eye(12)
    Comp[:, 12:] = -AiB
    y, vecs = np.linalg.eig(Comp)
    with np.errstate(all="ignore"):
        phi = 2.0 * np.arctan(y.astype(complex))
    keep = np.isfinite(phi) & (np.abs(phi.imag) < IMAG_TOL)
    big = np.abs(y) > 1.0
    v = np.where(big[:, None, :], vecs[:, 12:], vecs[:, :12]).astype(complex)   # (G, 12, 24)
    v[:, 0, :][~keep] = 1.0                       # harmless stand-ins for dropped slots
    v = v / np.linalg.norm(v, axis=1, keepdims=True)
    v, phi, keep, more = _split_clusters_batch(v, phi, keep, (Cm, Bm, Am))
    th3 = phi.real + delta[g, None]
    idx = np.argmax(np.abs(v), axis=1)                                          # (G, 48)
    piv = np.take_along_axis(v, idx[:, None, :], axis=1)
    with np.errstate(all="ignore"):
        vr = (v / piv).real
    vr = np.swapaxes(vr, 1, 2).reshape(-1, 4, 3)
    with np.errstate(all="ignore"):
        th4 = _ratio_angle(vr, axis=1).reshape(len(g), 48)
        th5 = _ratio_angle(vr, axis=2).reshape(len(g), 48)
    th3, th4, th5 = (np.where(keep, t, 0.0) for t in (th3, th4, th5))
    Q[g] = model._back_substitute(P[g], Qf[g], Rq[g], W[g], th3, th4, th5)
    valid[g] = keep & np.all(np.isfinite(Q[g]), axis=-1)
    bad[g] |= more
    return Q, valid, bad


def _split_clusters_batch(v, phi, keep, mats):
    """:func:`_split_clusters` for clusters of two eigenvalues, vectorised over poses.

    ``v (G, 12, 24)``, ``phi``, ``keep (G, 24)``; returns ``(v (G, 12, 48), phi (G, 48),
    keep (G, 48), more (G,))``: a pair's own vectors stay in their slots (kept or not by
    the same rule), its two subspace vectors go to slots 24 + (the pair's slots), and
    ``more`` flags poses with a cluster of three or more (left to the single-pose path).
    """
    G = len(phi)
    key = np.where(keep, phi.real, np.inf)
    order = np.argsort(key, axis=1)
    sk = np.take_along_axis(key, order, axis=1)
    with np.errstate(invalid="ignore"):
        close = np.diff(sk, axis=1) < CLUSTER_TOL                              # (G, 23)
    run3 = np.any(close[:, :-1] & close[:, 1:], axis=1)
    v2 = np.zeros((G, 12, 48), complex)
    v2[:, :, :24] = v
    v2[:, 0, 24:] = 1.0
    phi2 = np.concatenate([phi, np.zeros((G, 24), complex)], axis=1)
    keep2 = np.concatenate([keep, np.zeros((G, 24), bool)], axis=1)
    pg, pj = np.nonzero(close & ~run3[:, None])
    if len(pg) == 0:
        return v2, phi2, keep2, run3
    a, b = order[pg, pj], order[pg, pj + 1]
    Cm, Bm, Am = (m[pg] for m in mats)
    mean = (phi[pg, a].real + phi[pg, b].real) / 2.0
    y = np.tan(mean / 2.0)
    small = np.abs(y) <= 1.0
    with np.errstate(all="ignore"):
        w = np.where(small, 0.0, 1.0 / y)
    yy, ww = np.where(small, y, 0.0)[:, None, None], w[:, None, None]
    Sig = np.where(small[:, None, None], (Am * yy + Bm) * yy + Cm, Am + (Bm + Cm * ww) * ww)
    Nsub = np.swapaxes(np.linalg.svd(Sig)[2][:, -2:, :], -1, -2)             # (p, 12, 2)
    Mop = np.zeros((len(pg), 2, 2))
    for lo, hi, wgt in ((_LO4, _HI4, 1.0), (_LO5, _HI5, 0.6180339887)):
        lhs = Nsub[:, lo] + _TAU * Nsub[:, hi]
        rhs = Nsub[:, hi] - _TAU * Nsub[:, lo]
        Mop += wgt * (np.linalg.pinv(lhs, rcond=np.finfo(float).eps * len(lo)) @ rhs)
    _, Cv = np.linalg.eig(Mop)
    sub = Nsub @ Cv                                                            # (p, 12, 2)
    both = np.stack([v[pg, :, a], v[pg, :, b], sub[:, :, 0], sub[:, :, 1]], axis=1)  # (p,4,12)
    res = _structure_residual(both.reshape(-1, 12).T).reshape(-1, 4)
    rank = np.argsort(np.argsort(res, axis=1, kind="stable"), axis=1, kind="stable")
    kept = (res < 1e-3) | (rank < 2)
    for col, slot in ((0, a), (1, b), (2, 24 + a), (3, 24 + b)):
        v2[pg, :, slot] = both[:, col]
        keep2[pg, slot] = kept[:, col]
    phi2[pg, 24 + a] = mean
    phi2[pg, 24 + b] = mean
    return v2, phi2, keep2, run3


def solve_general_6r_batch(robot, T) -> tuple[np.ndarray, np.ndarray]:
    """All real IK solutions of a 6R robot for many poses at once, vectorised over poses.

    Parameters
    ----------
    robot : Robot
        Six revolute joints (any geometry; see :func:`solve_general_6r`).
    T : array_like (N, 4, 4)
        Tool poses ``T_world_tool`` (SI, world frame).

    Returns
    -------
    Q : ndarray (N, BATCH_SLOTS, 6)
        Joint values (rad, wrapped to (-pi, pi]); 0 in unused slots.
    ok : ndarray (N, BATCH_SLOTS) bool
        The valid slots: each reproduces its pose by FK to 1e-10 relative to
        ``robot.characteristic_length`` (position) and 1e-10 rad, after Newton
        polishing on ``robot.chain``; duplicates within MERGE_TOL are merged.
        Valid slots come first. A non-finite pose gets no solution.

    Method: the elimination of :func:`solve_general_6r` with pivot joint 3 (the
    per-robot precomputed form) on all poses at once: batched QR, 12x12 pencils,
    24x24 companion eigenproblems (``numpy.linalg.eig`` over ``(N, 24, 24)``),
    back-substitution, the cluster treatment for pairs of close eigenvalues, and
    damped Newton on all candidates of all poses together. The single-pose solver
    is called (a loop over those poses only) where the batch does not finish: a
    pose whose standard form degenerates, a cluster of three or more eigenvalues
    (both rare for a generic robot), and every pose of a robot whose pivot
    ranking does not put joint 3 first (nearly special robots: UR-, PUMA-like).

    Raises ValueError if ``robot`` is not 6 revolute joints or ``T`` is not (N, 4, 4).
    """
    if robot.dof != 6 or not all([j.revolute for j in robot.joints]):
        raise ValueError("solve_general_6r_batch needs a robot with exactly 6 revolute "
                         "joints, got " + "".join("R" if j.revolute else "P"
                                                  for j in robot.joints))
    T = np.asarray(T, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise ValueError(f"T must be an (N, 4, 4) array of transforms, got shape {T.shape}")
    N, K = len(T), BATCH_SLOTS
    Q_out = np.zeros((N, K, 6))
    ok = np.zeros((N, K), bool)
    finite = np.all(np.isfinite(T), axis=(1, 2))
    data = _robot_data(robot)
    rows = np.flatnonzero(finite)
    fallback = np.zeros(N, bool)
    if data.shifts[0] != 0:
        fallback[rows] = True
        rows = rows[:0]
    if len(rows):
        cand, valid, bad = _candidates_batch(data.model, T[rows])
        fallback[rows[bad]] = True
        valid &= ~bad[:, None]
        pose, slot = np.nonzero(valid)
        Qp, res = _polish(robot, T[rows][pose], cand[pose, slot], data.L)
        acc = res < ACCEPT_TOL
        Qa = np.zeros_like(cand)
        Qa[pose[acc], slot[acc]] = _wrap(Qp[acc])
        good = np.zeros(valid.shape, bool)
        good[pose[acc], slot[acc]] = True
        Qa, good = _compact(Qa, good, None)
        if good.shape[1] > 1:
            D = np.max(np.abs(_wrap(Qa[:, :, None, :] - Qa[:, None, :, :])), axis=-1)
            dup = np.any(np.tril((D < MERGE_TOL) & good[:, None, :], k=-1), axis=2)
            good &= ~dup
        Qa, good = _compact(Qa, good, K)
        Q_out[rows, :good.shape[1]] = Qa
        ok[rows, :good.shape[1]] = good
    for n in np.flatnonzero(fallback):
        try:
            sols = solve_general_6r(robot, T[n])[:K]
        except ValueError:
            continue
        Q_out[n, :len(sols)] = sols
        ok[n, :len(sols)] = True
    return Q_out, ok


def _compact(Q, ok, width):
    """Valid slots first (stable), cut to the most any row uses (or ``width`` columns)."""
    order = np.argsort(~ok, axis=1, kind="stable")
    ok = np.take_along_axis(ok, order, axis=1)
    Q = np.take_along_axis(Q, order[..., None], axis=1)
    w = int(ok.sum(axis=1).max(initial=0)) if width is None else width
    if Q.shape[1] < w:
        pad = w - Q.shape[1]
        Q = np.concatenate([Q, np.zeros((len(Q), pad, 6))], axis=1)
        ok = np.concatenate([ok, np.zeros((len(ok), pad), bool)], axis=1)
    return Q[:, :w], ok[:, :w]


def general_6r(robot, targets, br):
    """The branches of a general 6R robot: the elimination's solutions of every pose
    (:func:`solve_general_6r_batch`), ordered by joint 3 then joint 1, one slot each,
    labelled by their rank (``root k`` of joint 3). ``targets`` must be whole poses."""
    from dataclasses import replace as _replace
    from .engine import UnsupportedRobot
    if targets.kind != "pose":
        raise UnsupportedRobot(f"{robot.name}: a general 6R robot needs a whole pose")
    Q, ok = solve_general_6r_batch(robot, targets.T)
    key3 = np.where(ok, Q[..., 2], np.inf)
    key1 = np.where(ok, Q[..., 0], np.inf)
    order = np.lexsort((key1, key3), axis=-1)
    Q = np.take_along_axis(Q, order[..., None], axis=1)
    ok = np.take_along_axis(ok, order, axis=1)
    K = Q.shape[1]
    out = _replace(br, ok=ok & br.ok[:, :1], parent=np.zeros(K, int),
                   signs=tuple(((2, f"root {k + 1}"),) for k in range(K)))
    for j in range(6):
        out = out.set(j, Q[..., j], np.cos(Q[..., j]), np.sin(Q[..., j]))
    return out
