"""A 6R robot as scaled standard DH and the robot-level half of the elimination
(steps 1 and 2 of :mod:`kincalc.ik.general6r`): the DH frames of its axes
(:func:`kincalc.structure.dh_frames`), the
Pieper / Lee-Liang equations' left side, the deflation of the spurious roots."""

from __future__ import annotations

import numpy as np

from ...spatial import invert_transform
from ...structure import dh_frames
from .common import CUBIC_W, FAR, GRID, H2, PARALLEL_TOL, VINV2, VINV3, cubic_map, dh, f14

# built once (a model per pose is built for every call that pivots on another joint):
# the Fourier grid of two and of three angles, flattened (the first angle slowest) ...
_GRID2 = tuple(m.ravel() for m in np.meshgrid(GRID, GRID, indexing="ij"))
_GRID3 = tuple(m.ravel() for m in np.meshgrid(GRID, GRID, GRID, indexing="ij"))
# ... the turns Rz about them (the grid of joints 1 and 2 for links that are not DH) ...
_RZ1, _RZ2 = (dh(g, 0.0, 0.0, 0.0) for g in _GRID2)
# ... and J = [[0, I], [-I, 0]] (8x8) of the deflation's real form
_J8 = np.kron(np.array([[0.0, 1.0], [-1.0, 0.0]]), np.eye(4))


class Model:
    """A 6R robot as scaled standard DH plus the robot-level half of the elimination.

    Every array may have leading dimensions (one model per pose: the cyclically
    shifted problems, whose fixed link holds the pose); :func:`eliminate` broadcasts
    them against its poses.

    Attributes (``...`` the leading dimensions)
    ----------
    B, E, Binv, Einv : (..., 4, 4)
        Base and tool transforms (SI) around the DH chain, and their inverses.
    L : float
        Length scale (m); ``d`` and ``a`` are in units of ``L``.
    offset, d, a, alpha : (..., 6)
        DH parameters; ``theta_i = q_i + offset_i`` (rad).
    left, right : (..., 4, 4)
        ``W = left @ T @ right`` is the scaled target times ``A_6(0)^-1``:
        ``A_1 ... A_5 Rz(theta_6)`` with lengths in units of ``L``.
    N12 : (..., 9, 4, 4)
        ``(A_1 A_2)^-1`` on the 3x3 grid of (theta_1, theta_2).
    cubic : (84, 126) or None
        The right side as a map of the target (:func:`cubic_map`); None for
        per-pose models, which use ``N12``.
    P27 : (..., 14, 27)
        Left side ``P(theta_3)``: column ``k * 9 + j`` is the coefficient of
        ``(1, c3, s3)[k] X1[j]``.
    C12w, C35 : (..., 3, 27), (..., 27, 9)
        The rotations ``R1 R2`` and ``R3 R4 R5`` as coefficients of the products of
        (1, cos, sin) of their angles (for theta_6): ``w @ C12w`` is ``R12_k^T w``
        (column ``k * 3 + j``), ``Y @ C35`` the flattened ``R3 R4 R5``.
    U, K, UWb, UWW : (..., 24, 16), (..., 24, 16), (..., 24, 12), (..., 24, 32)
        The deflation of step 4 (see :meth:`_deflation`).
    far : (...) of bool
        Models that do not apply: DH lengths of ``FAR`` L or more (:meth:`from_lines`).

    ``left_of``, a Model with the same joints 3-5 (d, a, alpha), lends its left side
    (``P27, C35, U, K, UWb, UWW``, then without the leading dimensions) instead of
    computing it. ``links``, ``(M_1, M_2)`` each ``(..., 4, 4)``, gives joints 1 and 2
    as ``A_i = Rz(theta_i) M_i`` with any fixed links (frames 0 and 1 need not be DH:
    only the product ``A_1 A_2`` on the grid is used), their ``d, a, alpha`` unused.
    """

    def __init__(self, B, E, L, theta0, d, a, alpha, left_of=None, links=None, far=None):
        self.B, self.E, self.L = B, E, L
        self.far = np.zeros(np.shape(B)[:-2], bool) if far is None else far
        self.Binv, self.Einv = invert_transform(B), invert_transform(E)
        self.offset = np.asarray(theta0, float)
        self.d, self.a, self.alpha = (np.asarray(v, float) for v in (d, a, alpha))
        self.links = links
        d, a, al = (v[..., :, None] for v in (self.d, self.a, self.alpha))   # (..., 6, 1)
        # right side: inverses of A1(g1) A2(g2) on the 3x3 grid
        g1, g2 = _GRID2
        if links is None:
            A12 = dh(g1, d[..., 0, :], a[..., 0, :], al[..., 0, :]) \
                @ dh(g2, d[..., 1, :], a[..., 1, :], al[..., 1, :])
        else:                           # A_i = Rz(theta_i) M_i
            A12 = (_RZ1 @ links[0][..., None, :, :]) @ (_RZ2 @ links[1][..., None, :, :])
        self.N12 = invert_transform(A12)                  # (..., 9, 4, 4)
        post = invert_transform(dh(0.0, self.d[..., 5], self.a[..., 5], self.alpha[..., 5]))
        scale = np.array([1.0 / L, 1.0 / L, 1.0 / L, 1.0])
        self.left = scale[:, None] * self.Binv
        self.right = (self.Einv / scale) @ post
        lead = np.shape(B)[:-2]
        self.cubic = None if lead else cubic_map(self.N12)
        C12 = (VINV2 @ A12[..., :3, :3].reshape(lead + (9, 9))).reshape(lead + (9, 3, 3))
        self.C12w = np.ascontiguousarray(np.moveaxis(C12, -2, -3).reshape(lead + (3, 27)))
        if left_of is not None:         # joints 3-5 the same as another model's: its left side
            self.P27, self.C35 = left_of.P27, left_of.C35
            self.U, self.K, self.UWb, self.UWW = left_of.U, left_of.K, left_of.UWb, left_of.UWW
            return
        # left side: l, p of A3 A4 A5 on the 3x3x3 grid -> coefficients
        g3, g4, g5 = _GRID3
        M = dh(g3, d[..., 2, :], a[..., 2, :], al[..., 2, :]) \
            @ dh(g4, d[..., 3, :], a[..., 3, :], al[..., 3, :]) \
            @ dh(g5, d[..., 4, :], a[..., 4, :], al[..., 4, :])
        Pc = VINV3 @ f14(M[..., :3, 2], M[..., :3, 3])  # (..., 27, 14): row k3 * 9 + k4 * 3 + k5
        self.P27 = np.ascontiguousarray(np.swapaxes(Pc, -1, -2))
        P = np.swapaxes(Pc.reshape(lead + (3, 9, 14)), -1, -2)   # P(theta3) = P0 + c3 P1 + s3 P2
        self.C35 = VINV3 @ M[..., :3, :3].reshape(lead + (27, 9))
        self.U, self.K, self.UWb, self.UWW = self._deflation(P)

    def right_side(self, W):
        """Coefficients of the right side for scaled targets.

        Parameters
        ----------
        W : ndarray (M, 4, 4)
            ``W = left @ T @ right`` (lengths in units of ``L``).

        Returns
        -------
        ndarray (M, 9, 14)
            Row ``i1 * 3 + i2`` holds the 14 equations' coefficients of
            ``(1, c1, s1)[i1] (1, c2, s2)[i2]``.
        """
        M = len(W)
        if self.cubic is not None:
            w = W.reshape(M, 1, 16)
            a, b, c = CUBIC_W                 # the monomials u_a u_b u_c, (u_a u_b) u_c
            m = w.take(a, axis=2) * w.take(b, axis=2) * w.take(c, axis=2)      # (M, 1, 84)
            # one product per pose (not one (M, 84) matrix product: a pose's bits then do not
            # depend on how many poses are solved with it)
            return (m @ self.cubic).reshape(M, 9, 14)
        lp = self.N12 @ W[:, None, :, 2:]                 # (M, 9, 4, 2): [l 0; p 1] per grid point
        return VINV2 @ f14(lp[..., :3, 0], lp[..., :3, 1])

    @staticmethod
    def _deflation(P):
        """Orthogonal basis change that splits off the 8 spurious eigenvalues x3 = +-i.

        ``Sigma(i)`` is ``2 (S1 + i S2) H2`` placed in rows 0-5 / columns 0-8 and rows
        6-11 / columns 3-11, with ``S_k = N P_k / scale``; the rows of ``(P1 + i P2) H2``
        span a space ``R`` of dimension (at most) 4 that depends on the left side alone
        (theta_3 turns l and p about z: the x and y rows are ``x' - i y'`` and
        ``i (x' - i y')``), so ``V = {v : R v[0:9] = 0, R v[3:12] = 0}`` (12x4) is a right
        null space of ``Sigma(i)`` for every pose, pivot shift delta and row scaling, and
        ``[V; i V]`` an eigenspace of the companion matrix ``Comp``. Its real form
        ``W = [[Vr, Vi], [-Vi, Vr]]`` (24x8) satisfies ``Comp W = W J``,
        ``J = [[0, I], [-I, 0]]``. With ``[Wo, U]`` orthogonal (QR of W) and
        ``Mo = Rw J Rw^-1`` (so ``Mo^2 = -I``), ``[Wo U]^T Comp [Wo U]`` is
        ``[[Mo, E], [0, D]]``: ``D`` (16x16) has the 16 true roots, and an eigenvector
        ``y`` of ``D`` gives ``Comp``'s as ``U y + Wo (lambda + Mo) E y / (1 + lambda^2)``.

        Returns ``(U, K, UWb, UWW)``: ``U (..., 24, 16)``; ``K = [U_top^T U_bot;
        Wo_top^T U_bot] (..., 24, 16)`` and ``UWb = [U_bot^T; Wo_bot^T] (..., 24, 12)``,
        so that ``[D; E] = K - UWb A^-1 [C B] U``; ``UWW = [U, Wo, Wo Mo] (..., 24, 32)``.
        """
        lead = P.shape[:-3]
        Sp = (P[..., 1, :, :] + 1j * P[..., 2, :, :]) @ H2             # (..., 14, 9)
        R = np.linalg.svd(Sp, full_matrices=False)[2][..., :4, :]        # its row space
        C8 = np.zeros(lead + (8, 12), complex)
        C8[..., :4, :9] = R
        C8[..., 4:, 3:] = R
        V = np.swapaxes(np.linalg.svd(C8)[2][..., 8:, :].conj(), -1, -2)   # (..., 12, 4)
        Vr, Vi = V.real, V.imag
        W = np.concatenate([np.concatenate([Vr, Vi], -1), np.concatenate([-Vi, Vr], -1)], -2)
        Qw, Rw = np.linalg.qr(W, mode="complete")
        Wo, U = Qw[..., :8], Qw[..., 8:]
        Rw = Rw[..., :8, :]
        Mo = Rw @ _J8 @ np.linalg.inv(Rw)
        top, bot = slice(0, 12), slice(12, 24)
        UT = np.swapaxes(U, -1, -2)
        WT = np.swapaxes(Wo, -1, -2)
        K = np.concatenate([UT[..., :, top] @ U[..., bot, :], WT[..., :, top] @ U[..., bot, :]],
                           axis=-2)
        UWb = np.concatenate([UT[..., :, bot], WT[..., :, bot]], axis=-2)
        UWW = np.concatenate([U, Wo, Wo @ Mo], axis=-1)
        return (np.ascontiguousarray(U), np.ascontiguousarray(K), np.ascontiguousarray(UWb),
                np.ascontiguousarray(UWW))

    @classmethod
    def from_lines(cls, dirs, pts, T0, L, known=None):
        """Model of the 6R whose axes at q = 0 are ``pts[..., i, :] + t dirs[..., i, :]``.

        Parameters
        ----------
        dirs, pts : ndarray (..., 6, 3)
            Unit axis directions and a point of each axis (world frame, m).
        T0 : ndarray (..., 4, 4)
            The tool pose at q = 0 (SI).
        L : float
            Length scale (m).
        known : tuple, optional
            ``(c, F)`` for models that share their last axes (the cyclic shifts of
            :meth:`~.robot._Robot6R.shifted_model`): the DH frames c .. 6 ``F (7 - c, 4, 4)``
            (:func:`kincalc.structure.dh_frames` of these axes; frame i depends on axes i
            and i + 1 only, or on frame i - 1 too where those are parallel), so only frames
            0 .. c - 1 are computed (c >= 2).

        Returns
        -------
        Model
            With the leading dimensions of the arguments.
        """
        if known is None:
            F = dh_frames(dirs, pts, L, PARALLEL_TOL)
        else:
            c, Fc = known
            # frames 0 .. c - 1 from the axes 1 .. c alone (its frame c is not the chain's)
            first = dh_frames(dirs[..., :c, :], pts[..., :c, :], L, PARALLEL_TOL)[..., :c, :, :]
            F = np.concatenate([first, np.broadcast_to(Fc, first.shape[:-3] + Fc.shape)], axis=-3)
        G = invert_transform(F[..., :-1, :, :]) @ F[..., 1:, :, :]   # A_i(offset_i) (.., 6, 4, 4)
        theta0 = np.arctan2(G[..., 1, 0], G[..., 0, 0])
        d = G[..., 2, 3]
        a = G[..., 0, 3] * np.cos(theta0) + G[..., 1, 3] * np.sin(theta0)
        alpha = np.arctan2(G[..., 2, 1], G[..., 2, 2])
        E = invert_transform(F[..., 6, :, :]) @ T0
        # the common normal of nearly parallel axes can be FAR along them: such a model is
        # not used (``far``), and its numbers are replaced by finite ones
        far = ~np.all((np.abs(d) < FAR * L) & (np.abs(a) < FAR * L) & np.isfinite(theta0)
                      & np.isfinite(alpha), axis=-1)
        if np.count_nonzero(far):
            theta0, d, a, alpha = (np.where(far[..., None], 0.0, v) for v in (theta0, d, a, alpha))
            F0, E = (np.where(far[..., None, None], np.eye(4), v) for v in (F[..., 0, :, :], E))
        else:
            F0 = F[..., 0, :, :]
        return cls(F0, E, L, theta0, d / L, a / L, alpha, far=far)

    def perturbed(self, size):
        """The same robot with every scaled DH parameter moved by 0.5 .. 1 ``size`` (seeded).

        Parameters
        ----------
        size : float
            Scaled units (lengths over ``L``) and rad.

        Returns
        -------
        Model
            Random signs; the same ``B``, ``E``, ``L`` and offsets.

        Raises
        ------
        ValueError
            For a model with general ``links`` (their joints have no DH parameters to move).
        """
        if self.links is not None:
            raise ValueError("a model with general links of joints 1 and 2 is not perturbed")
        rng = np.random.default_rng(20240611)
        dd, da, dal = rng.uniform(0.5, 1.0, (3, 6)) * rng.choice([-1.0, 1.0], (3, 6)) * size
        return Model(self.B, self.E, self.L, self.offset, self.d + dd, self.a + da,
                     self.alpha + dal)

    def fk_dh(self, q):
        """FK of the DH model, for checks.

        Parameters
        ----------
        q : array_like (..., 6)
            Joint values (rad).

        Returns
        -------
        ndarray (..., 4, 4)
            ``T_world_tool`` (SI).
        """
        th = np.asarray(q, float) + self.offset
        T = np.broadcast_to(np.eye(4), th.shape[:-1] + (4, 4)).copy()
        for i in range(6):
            if self.links is not None and i < 2:
                T = T @ dh(th[..., i], 0.0, 0.0, 0.0) @ self.links[i]
            else:
                T = T @ dh(th[..., i], self.d[..., i], self.a[..., i], self.alpha[..., i])
        T[..., :3, 3] *= self.L
        return self.B @ T @ self.E
