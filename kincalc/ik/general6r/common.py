"""The general-6R solver's tolerances, its robot-independent tables (the 3-point
Fourier grid, the maps of the 12x12 matrix polynomial's coefficients, the cubic map
of the target's terms) and small vectorised helpers (see :mod:`kincalc.ik.general6r`
for the method)."""

from __future__ import annotations

import numpy as np

from ...spatial import cross
from ...tolerances import DUPLICATE

#: solution slots per pose of :func:`~kincalc.ik.general6r.solve_general_6r_batch` (a
#: general 6R has at most 16)
BATCH_SLOTS = 16
#: sine of the angle below which two consecutive axes are treated as parallel.
PARALLEL_TOL = 1e-7
#: a shifted 6R whose DH lengths reach this many L (the common normal of two nearly
#: parallel axes, its foot far along them) does not apply at that pose: its elimination
#: would lose the digits of the lengths' squares (see Model.from_lines)
FAR = 1e3
#: residual (relative position, rad) a polished solution must reach.
ACCEPT_TOL = 1e-10
#: where no candidate of a pose reaches ACCEPT_TOL: the residual Newton must reach instead,
#: half the engine's acceptance (kincalc.tolerances.ACCEPT_POSITION and _ORIENTATION; the
#: largest of the three components at most this, their norm is within the engine's 1e-9).
#: At a singular pose whose exact root sits in a valley of near-solutions Newton converges
#: sublinearly (fanuc_crx10ia at q2 = 179.9, q5 = 0 deg: 9e-10 after 8 steps, 4.5e-10
#: after 40), and the pose had no solution.
SETTLED = 5e-10
#: the candidates of such a pose within this residual are in the valley: they get
#: RESCUE_ITERS more Newton steps
VALLEY = 1e-6
RESCUE_ITERS = 200
#: the rescued solutions of a pose are at least this far apart (rad, every joint wrapped),
#: those within the joint limits first, then the best: samples of the valley (or of a
#: continuum) Newton landed on, not every point of it.
THIN = 0.1
#: seeded Newton starts for a pose where every pivot and the last resort degenerate (a
#: continuum of solutions, a pose on a fold of the workspace).
STARTS = 32
#: wrapped joint distance (rad) below which two solutions are the same: the engine's
#: (kincalc.tolerances.DUPLICATE)
MERGE_TOL = DUPLICATE
#: |Im(theta_3)| (rad) below which an eigenvalue is a real candidate.
IMAG_TOL = 0.05
#: eigenvalues (as angles, rad) closer than this are treated as one cluster.
CLUSTER_TOL = 1e-3
#: |Im(theta_3)| (rad) below which a conjugate pair of the robot's own pencil (not a
#: perturbed one) is treated as a cluster: a real double root split by rounding (some
#: sqrt(eps * condition), at most ~1e-3), not a complex root near the real axis.
PAIR_IMAG = 1e-2
#: sizes of the generic perturbations of the last resort (scaled units, rad).
PERTURB = (1e-3, 1e-4)

# 3-point DFT grid: exact for (1, cos, sin) expansions.
GRID = np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0])
_VINV = np.linalg.inv(np.stack([np.ones(3), np.cos(GRID), np.sin(GRID)], axis=1))
# the same fit for two angles at once: (9, 9), rows i1 * 3 + i2, columns grid a * 3 + b
VINV2 = np.kron(_VINV, _VINV)
VINV3 = np.kron(VINV2, _VINV)       # three angles: rows i3 * 9 + i4 * 3 + i5
# (1, c, s) * (1 + x^2) in powers (1, x, x^2) of x = tan(theta / 2)
_H = np.array([[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]])
H2 = np.kron(_H, _H)     # trig (i4, i5) -> powers (j4, j5), both flattened i*3 + j
DELTAS = (0.0, 1.1071487177940904, -0.6435011087932844, 2.4980915447965089)
COND_GOOD = 1e4          # a shift delta whose A is conditioned below this is taken at once
COND_BAD = 1e10          # above this for every delta: the standard form degenerates
_RANK_BAD = 1e9           # condition estimate of Q's R above which Q has lost rank
LIMITS = np.array([COND_GOOD, _RANK_BAD])
STEP_MAX = 0.5
NEWTON_ITERS = 20
GIVE_UP = {3: 1e-2, 6: 1e-6}      # after this many steps, drop candidates still above
#: the same for the last resort's candidates, which start 1e-3 .. 1e-2 rad away, where a
#: close pair of solutions (a nearly singular Jacobian) makes Newton converge linearly
GIVE_UP_LAST = {3: 1e-2, 10: 1e-4}
# the two matrices inverted together per pose: A (12x12) and Q's R (8x8, padded with I)
INV_PAD = np.zeros((2, 12, 12))
INV_PAD[1, 8:, 8:] = np.eye(4)


def _sigma_maps():
    """``(4, 27, 72)``: for each shift delta, the linear map from the rows of ``S``
    (the 27 coefficients ``S_k[i4, i5]`` of ``(1, c3, s3) x (1, c4, s4) x (1, c5, s5)``,
    k-major) to a row of the 12x36 ``[C | B | A]`` of ``Sigma(y)``: columns 0-35 for
    rows 0-5 of Sigma (the equations), 36-71 for rows 6-11 (the equations times x4)."""
    out = np.zeros((len(DELTAS), 27, 72))
    for n, dl in enumerate(DELTAS):
        cd, sd = np.cos(dl), np.sin(dl)
        # theta3 = phi + delta; (1, c3, s3) (1 + y^2) in powers (1, y, y^2) of y = tan(phi/2)
        trig = np.array([[1.0, 0.0, 1.0], [cd, -2.0 * sd, -cd], [sd, 2.0 * cd, -sd]])
        for k in range(3):
            for o in range(3):                        # o: 0 = C (y^0), 1 = B, 2 = A
                blk = trig[k, o] * H2
                rows = slice(9 * k, 9 * k + 9)
                out[n, rows, 12 * o:12 * o + 9] = blk              # rows 0-5: x4^0..2
                out[n, rows, 36 + 12 * o + 3:36 + 12 * o + 12] = blk   # rows 6-11: x4^1..3
    return out


SIGMA_MAPS = _sigma_maps()


def _cubic_monomials():
    """The 84 monomials ``u_a u_b u_c`` (a <= b <= c) of ``u (7,)``: their indices in the
    flattened ``u x u x u`` and the number of index orders of each."""
    mons = [(a, b, c) for a in range(7) for b in range(a, 7) for c in range(b, 7)]
    idx = np.array([a * 49 + b * 7 + c for a, b, c in mons])
    mult = np.array([6.0 / np.prod([np.prod(np.arange(1, m.count(k) + 1)) for k in set(m)])
                     for m in mons])
    return idx, mult


CUBIC_IDX, _CUBIC_MULT = _cubic_monomials()
# entries (1, l, p) of the scaled target W (flattened 4x4): W[3,3], W[0:3,2], W[0:3,3]
U_IDX = np.array([15, 2, 6, 10, 3, 7, 11])
#: ``(3, 84)``: the three factors ``u_a, u_b, u_c`` of each cubic monomial (:data:`CUBIC_IDX`
#: order) as entries of the flattened scaled target W, to gather them without the 343 products
CUBIC_W = U_IDX[np.stack([CUBIC_IDX // 49, CUBIC_IDX // 7 % 7, CUBIC_IDX % 7])]
_LEVI_CIVITA = np.zeros((3, 3, 3))
_LEVI_CIVITA[[0, 1, 2], [1, 2, 0], [2, 0, 1]] = 1.0
_LEVI_CIVITA[[0, 1, 2], [2, 0, 1], [1, 2, 0]] = -1.0


def cubic_map(N12):
    """The right side's coefficients as a linear map of the cubic monomials of the target.

    ``Rc (9, 14)`` (step 2) as a map of the cubic monomials of ``u = (1, l, p)``, ``l, p``
    the third column and the origin of the scaled target: at grid point g, ``l_g = R_g l``
    and ``p_g = R_g p + t_g`` (``N12[g] = [R_g, t_g]``) are linear in u, so each of the 14
    quantities is a cubic in u (lower degrees times powers of ``u_0 = 1``), and the Fourier
    fit is linear.

    Parameters
    ----------
    N12 : ndarray (9, 4, 4)
        ``(A_1 A_2)^-1`` on the 3x3 grid of (theta_1, theta_2), lengths scaled.

    Returns
    -------
    ndarray (84, 126), contiguous
        Rows: the 84 monomials ``u_a u_b u_c`` (:data:`CUBIC_IDX`); columns: ``Rc`` flattened.
    """
    R, t = N12[:, :3, :3], N12[:, :3, 3]
    Lg = np.zeros((9, 3, 7))
    Lg[:, :, 1:4] = R
    Pg = np.zeros((9, 3, 7))
    Pg[:, :, 0], Pg[:, :, 4:] = t, R
    e0 = np.eye(7)[0]
    T = np.zeros((9, 14, 7, 7, 7))
    T[:, 0:3] = np.einsum("gqa,b,c->gqabc", Lg, e0, e0)
    T[:, 3:6] = np.einsum("gqa,b,c->gqabc", Pg, e0, e0)
    T[:, 6] = np.einsum("gia,gib,c->gabc", Pg, Pg, e0)
    T[:, 7] = np.einsum("gia,gib,c->gabc", Pg, Lg, e0)
    T[:, 8:11] = np.einsum("qjk,gja,gkb,c->gqabc", _LEVI_CIVITA, Pg, Lg, e0)
    T[:, 11:14] = (np.einsum("gia,gib,gqc->gqabc", Pg, Pg, Lg)
                   - 2.0 * np.einsum("gia,gib,gqc->gqabc", Pg, Lg, Pg))
    C = np.einsum("kg,gqabc->kqabc", VINV2, T).reshape(126, 7, 7, 7)
    C = (C + C.transpose(0, 1, 3, 2) + C.transpose(0, 2, 1, 3) + C.transpose(0, 2, 3, 1)
         + C.transpose(0, 3, 1, 2) + C.transpose(0, 3, 2, 1)) / 6.0
    return np.ascontiguousarray((C.reshape(126, 343)[:, CUBIC_IDX] * _CUBIC_MULT).T)


# --- small vectorised helpers ---------------------------------------------

def dh(theta, d, a, alpha):
    """Standard DH link transforms ``Rz(theta) Tz(d) Tx(a) Rx(alpha)``.

    Parameters
    ----------
    theta, d, a, alpha : array_like
        Angles (rad) and lengths (any unit, kept); all arguments broadcast.

    Returns
    -------
    ndarray (..., 4, 4)
    """
    c, s = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(alpha), np.sin(alpha)
    T = np.zeros(np.shape(c * ca + d * a) + (4, 4))
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


def f14(l, p):
    """The 14 Raghavan-Roth quantities ``l, p, p.p, p.l, p x l, (p.p) l - 2 (p.l) p``.

    Parameters
    ----------
    l, p : ndarray (..., 3)
        A third column and an origin (scaled lengths).

    Returns
    -------
    ndarray (..., 14)
    """
    pp = np.einsum("...i,...i->...", p, p)[..., None]
    pl = np.einsum("...i,...i->...", p, l)[..., None]
    return np.concatenate([l, p, pp, pl, cross(p, l), pp * l - 2.0 * pl * p], axis=-1)


# the reductions without the Python layer of the ndarray methods (per-call overhead
# matters at a batch of one)
reduce_sum, reduce_max = np.add.reduce, np.maximum.reduce
reduce_min, reduce_all = np.minimum.reduce, np.logical_and.reduce
nnz = np.count_nonzero


def dot(u, v):
    """Row-wise dot products.

    Parameters
    ----------
    u, v : ndarray (..., k)

    Returns
    -------
    ndarray (...)
    """
    return np.einsum("...i,...i->...", u, v)


def unit(u):
    """The vectors divided by their norms.

    Parameters
    ----------
    u : ndarray (..., k)
        Non-zero vectors.

    Returns
    -------
    ndarray (..., k)
    """
    return u / np.sqrt(dot(u, u))[..., None]
