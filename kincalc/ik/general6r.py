"""All real inverse-kinematics solutions of a general 6R robot, for a batch of poses.

Method
------
Raghavan & Roth's elimination (M. Raghavan, B. Roth, "Inverse kinematics of
the general 6R manipulator and related linkages", ASME J. Mech. Des. 115,
1993; conference version 1990) in the numerically robust matrix form of
D. Manocha, J. F. Canny, "Efficient inverse kinematics for general 6R
manipulators", IEEE Trans. Robotics and Automation 10(5):648-657, 1994.
Every step runs on all poses of a batch at once (:func:`solve_general_6r_batch`;
a single pose is a batch of one).

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
   robot for the left side; on the right, ``l`` and ``p`` at each grid point
   of (theta_1, theta_2) are linear in ``u = (1, l_T, p_T)`` of the target, so
   the fit is a cubic in u whose 84 x 126 coefficients are also computed once
   per robot (:func:`_cubic_map`), leaving one product per pose. This gives
   ``P(theta_3) X1 = Q X2`` with ``X1`` the nine products
   of (1, c4, s4) and (1, c5, s5), ``X2`` the eight non-constant products of
   (1, c1, s1) and (1, c2, s2), ``P`` 14x9 linear in (1, c3, s3), ``Q`` 14x8.
3. **Elimination.** ``X2`` is removed with an orthonormal basis ``N`` (6x14)
   of the left null space of ``Q`` (Householder QR, not Cramer's rule):
   ``N P(theta_3) X1 = 0``, a 6x9 system. Half-angle substitution
   ``x_i = tan(theta_i / 2)`` for i = 4, 5 and multiplication by ``x_4`` give
   the 12x12 matrix polynomial ``Sigma(x3) = A x3^2 + B x3 + C`` acting on
   the monomials ``x4^j x5^k`` (j <= 3, k <= 2).
4. **Eigenproblem.** ``det Sigma = 0`` has degree 24 with the spurious factor
   ``(1 + x3^2)^4``: theta_3 enters ``l`` and ``p`` only as a turn about z_2,
   so ``Sigma(+-i)`` is singular, with a right null space ``V`` (12x4) that
   depends on the left side alone (per robot). The 24x24 companion matrix
   ``[[0, I], [-A^-1 C, -A^-1 B]]`` has the invariant subspace
   ``[V; +-i V]``; an orthogonal change of basis (per robot) splits it off, and
   ``numpy.linalg.eig`` solves the remaining 16x16 block, whose eigenvalues
   are the 16 roots; the eigenvectors of the companion matrix follow from the
   block triangular form (``(lambda - M)^-1`` with ``M^2 = -I``; see
   :meth:`_Model._deflation`). ``A`` and the R factor of ``Q`` are inverted
   together (one batched ``inv``); a condition estimate of R above 1e9 marks
   ``Q`` as rank deficient.
   *Degenerate leading matrix / x3 = infinity (theta_3 = pi):* numpy has no
   QZ, so instead of a generalised eigensolver the unknown is shifted,
   ``theta_3 = phi + delta``: ``A`` is then ``Sigma`` at ``theta_3 = pi +
   delta``. Four shifts are tried (0 and three irrational-looking ones): the
   first whose ``A`` has a condition estimate ``|A|_F |A^-1|_F`` below 1e4,
   else the best conditioned, so a root at or near theta_3 = pi (common: the
   published 16-solution example has theta_3 = 179.96 deg) never sits at
   infinity. Eigenvalues whose angle ``2 atan(y)`` has an imaginary part
   below 0.05 rad count as real candidates (near-double real roots come out
   as complex pairs).
5. **Back-substitution** (:func:`_candidate_angles`, for the real candidates
   only). ``x4``, ``x5`` come from the eigenvector (least-squares ratios of
   consecutive entries, inverted ratios when |x| > 1, so theta = pi is fine);
   ``(c1, s1, c2, s2)`` from ``Q X2 = P X1`` (least squares through the same
   QR); theta_6 from ``A_6 = (A_1..A_5)^-1 T'``, with ``R1 R2`` and
   ``R3 R4 R5`` as linear maps of the products of (1, cos, sin) already at
   hand.
   *Clusters:* eigenvalues whose angles' real parts are closer than 1e-3 rad
   (solutions sharing the pivot angle, e.g. the two wrist flips of a
   spherical wrist; near-double roots split into a conjugate pair) get a
   second set of vectors: at their mean, the monomial vectors are recovered
   from the null space of ``Sigma`` as common eigenvectors of the "multiply
   by x4" and "multiply by x5" shift operators; the vectors closest to
   monomial structure are kept (see :func:`_split_clusters`; all clusters of
   one size are treated together, their extra vectors take slots 16-31 of
   their pose).
6. **Polishing.** Every candidate gets up to 10 damped Newton steps on the
   *given* robot (``robot.chain``, so the DH model above only has to be
   close): error ``[(p* - p) / L; log(R* R^T)]`` against the base-frame
   geometric Jacobian (:func:`kincalc.jacobian.jacobian_and_pose` on the
   chain with lengths divided by L), steps limited to 0.5 rad
   (:func:`kincalc.ik.newton.polish`), the rotation log from the skew part
   below 90 degrees.
   Candidates whose final residual ``max(|dp| / L, |dw|)`` exceeds 1e-10 are
   dropped, the rest are wrapped to (-pi, pi] and merged (per pose) when
   within 1e-6 rad of a solution from an earlier slot (only needed when some
   candidate moved or a pose had a cluster: distinct eigenvalue slots are
   farther apart than that otherwise).

Batches of more than 512 poses are solved 512 at a time (their arrays then
stay in the processor's cache; larger blocks are slower per pose).

Choice of pivot joint and special geometry
------------------------------------------
The closure ``A_1 ... A_6 = T'`` can be rotated cyclically into
``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I``: again a 6R inverse-kinematics
problem (joints k+1..6, 1..k; the pose becomes the fixed link between joints
6 and 1, the target is the identity), whose pivot is joint k + 3 (mod 6). Shift 0
(pivot joint 3) is the standard form and has its left side and the
deflation of step 4 precomputed per robot; for the other shifts the DH model,
left side and deflation are rebuilt per pose from the same axis lines
(vectorised over the poses that need them).

For robots with special structure the standard form degenerates: with three
parallel axes (UR arms) or a spherical wrist (PUMA, KUKA, ABB, FANUC) the
12x12 pencil is singular, every leading matrix ``A`` is singular
(condition estimate above 1e10 for all four shifts ``delta``), or ``Q``
loses rank (condition estimate of its R above 1e9). Nearly special robots
(a calibrated UR5 whose twists are off by 1e-8 .. 1e-4) are worse: the
pencil is regular but ill-conditioned and the eigenvalues are inaccurate.
So once per robot (cached) the six shifts are ranked on three seeded probe
poses by how accurately their raw candidates recover the generating
configuration; shift 0 is kept without further probing when it is accurate
to 1e-8 rad (every generic robot). In the library, UR arms end up pivoting
on joint 2 (shift 5, the parallel joints 2-3-4 on the left side) and
wrist-partitioned arms on joint 5 (shift 2) or joint 2. Per pose the ranked
shifts are tried in order until one is not degenerate. If all six
degenerate (rare: e.g. a random arm with axes 1-2-3 parallel and 3-4-5
intersecting pairwise), the standard form is solved for two nearby
*generic* robots (each scaled DH parameter moved by a fixed pseudo-random
0.5 .. 1 times 1e-3, resp. 1e-4; the larger size suits robots whose
solutions are well separated, the smaller one robots close to a singular
configuration) and the union of their candidates is polished on the real
robot; this last resort can lose solutions near singular configurations and
is not reached by any robot of the library. UR5 and PUMA thus give their (up
to) 8 solutions, the same as the analytic family solvers of
:mod:`kincalc.ik.families`. Robots with infinitely many solutions at a pose
(coincident axes; a pose on a self-motion) get whatever isolated points
Newton lands on, or none.

Limitations
-----------
* Solutions at or very near a singular configuration converge slowly or to
  a neighbour and may be dropped by the 1e-10 residual test or merged: two
  distinct solutions closer than 1e-6 rad are reported once. For a generic
  6R the real count is even, so an odd count flags such a case. Special
  and nearly special robots (which need another pivot) lose a solution of
  a near-singular pair somewhat more often than generic ones.
* The 1e-10 acceptance is relative to ``robot.characteristic_length``; a
  pose outside the workspace gets no solution.
* Robots with a prismatic joint are not handled (ValueError).
* Speed (``benchmarks/ik_single.py``, one thread, numpy/OpenBLAS, as multiples of
  one ``numpy.linalg.eig`` of a 24x24 matrix, 0.14-0.25 ms on the shared machine it
  was measured on; the 16x16 ``eig`` is about half of one): a generic robot takes
  about 2.5-4.5 of them for a batch of one pose (0.5-1 ms there) and 0.5-1.1 per pose
  in batches of 1000 to 10000; robots that pivot on another joint (UR, PUMA, KUKA,
  ABB arms: a model per pose) about 10-15 for one pose and 1.1-3.7 per pose in
  batches; plus a one-off 5-30 ms per robot for the model and the pivot ranking
  (cached for 64 robots).
"""

from __future__ import annotations

import numpy as np

from ..jacobian import jacobian_and_pose
from ..model import Chain
from ..spatial import cross, invert_transform, rotvec_from_matrix, wrap
from .cache import per_robot
from .newton import polish

__all__ = ["BATCH_SLOTS", "solve_general_6r", "solve_general_6r_batch"]

#: solution slots per pose of :func:`solve_general_6r_batch` (a general 6R has at most 16)
BATCH_SLOTS = 16
#: sine of the angle below which two consecutive axes are treated as parallel.
PARALLEL_TOL = 1e-7
#: residual (relative position, rad) a polished solution must reach.
ACCEPT_TOL = 1e-10
#: wrapped joint distance (rad) below which two solutions are the same.
MERGE_TOL = 1e-6
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
_VINV3 = np.kron(_VINV2, _VINV)       # three angles: rows i3 * 9 + i4 * 3 + i5
# (1, c, s) * (1 + x^2) in powers (1, x, x^2) of x = tan(theta / 2)
_H = np.array([[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]])
_H2 = np.kron(_H, _H)     # trig (i4, i5) -> powers (j4, j5), both flattened i*3 + j
_DELTAS = (0.0, 1.1071487177940904, -0.6435011087932844, 2.4980915447965089)
_COND_GOOD = 1e4          # a shift delta whose A is conditioned below this is taken at once
_COND_BAD = 1e10          # above this for every delta: the standard form degenerates
_RANK_BAD = 1e9           # condition estimate of Q's R above which Q has lost rank
_LIMITS = np.array([_COND_GOOD, _RANK_BAD])
_STEP_MAX = 0.5
_NEWTON_ITERS = 10
_GIVE_UP = {3: 1e-2, 6: 1e-6}      # after this many steps, drop candidates still above
# the two matrices inverted together per pose: A (12x12) and Q's R (8x8, padded with I)
_INV_PAD = np.zeros((2, 12, 12))
_INV_PAD[1, 8:, 8:] = np.eye(4)


def _sigma_maps():
    """``(4, 27, 72)``: for each shift delta, the linear map from the rows of ``S``
    (the 27 coefficients ``S_k[i4, i5]`` of ``(1, c3, s3) x (1, c4, s4) x (1, c5, s5)``,
    k-major) to a row of the 12x36 ``[C | B | A]`` of ``Sigma(y)``: columns 0-35 for
    rows 0-5 of Sigma (the equations), 36-71 for rows 6-11 (the equations times x4)."""
    out = np.zeros((len(_DELTAS), 27, 72))
    for n, dl in enumerate(_DELTAS):
        cd, sd = np.cos(dl), np.sin(dl)
        # theta3 = phi + delta; (1, c3, s3) (1 + y^2) in powers (1, y, y^2) of y = tan(phi/2)
        trig = np.array([[1.0, 0.0, 1.0], [cd, -2.0 * sd, -cd], [sd, 2.0 * cd, -sd]])
        for k in range(3):
            for o in range(3):                        # o: 0 = C (y^0), 1 = B, 2 = A
                blk = trig[k, o] * _H2
                rows = slice(9 * k, 9 * k + 9)
                out[n, rows, 12 * o:12 * o + 9] = blk              # rows 0-5: x4^0..2
                out[n, rows, 36 + 12 * o + 3:36 + 12 * o + 12] = blk   # rows 6-11: x4^1..3
    return out


_SIGMA_MAPS = _sigma_maps()


def _cubic_monomials():
    """The 84 monomials ``u_a u_b u_c`` (a <= b <= c) of ``u (7,)``: their indices in the
    flattened ``u x u x u`` and the number of index orders of each."""
    mons = [(a, b, c) for a in range(7) for b in range(a, 7) for c in range(b, 7)]
    idx = np.array([a * 49 + b * 7 + c for a, b, c in mons])
    mult = np.array([6.0 / np.prod([np.prod(np.arange(1, m.count(k) + 1)) for k in set(m)])
                     for m in mons])
    return idx, mult


_CUBIC_IDX, _CUBIC_MULT = _cubic_monomials()
# entries (1, l, p) of the scaled target W (flattened 4x4): W[3,3], W[0:3,2], W[0:3,3]
_U_IDX = np.array([15, 2, 6, 10, 3, 7, 11])
_LEVI_CIVITA = np.zeros((3, 3, 3))
_LEVI_CIVITA[[0, 1, 2], [1, 2, 0], [2, 0, 1]] = 1.0
_LEVI_CIVITA[[0, 1, 2], [2, 0, 1], [1, 2, 0]] = -1.0


def _cubic_map(N12):
    """``(84, 126)``: the right side's coefficients ``Rc (9, 14)`` (step 2) as a linear
    map of the cubic monomials of ``u = (1, l, p)``, ``l, p`` the third column and the
    origin of the scaled target: at grid point g, ``l_g = R_g l`` and ``p_g = R_g p + t_g``
    (``N12[g] = [R_g, t_g]``) are linear in u, so each of the 14 quantities is a cubic in
    u (lower degrees times powers of ``u_0 = 1``), and the Fourier fit is linear."""
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
    C = np.einsum("kg,gqabc->kqabc", _VINV2, T).reshape(126, 7, 7, 7)
    C = (C + C.transpose(0, 1, 3, 2) + C.transpose(0, 2, 1, 3) + C.transpose(0, 2, 3, 1)
         + C.transpose(0, 3, 1, 2) + C.transpose(0, 3, 2, 1)) / 6.0
    return np.ascontiguousarray((C.reshape(126, 343)[:, _CUBIC_IDX] * _CUBIC_MULT).T)


# --- small vectorised helpers ---------------------------------------------

def _dh(theta, d, a, alpha):
    """Standard DH link transforms ``(..., 4, 4)``; all arguments broadcast."""
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


def _f14(l, p):
    """The 14 Raghavan-Roth quantities ``(..., 14)`` of ``l, p (..., 3)``."""
    pp = np.einsum("...i,...i->...", p, p)[..., None]
    pl = np.einsum("...i,...i->...", p, l)[..., None]
    return np.concatenate([l, p, pp, pl, cross(p, l), pp * l - 2.0 * pl * p], axis=-1)


# the reductions without the Python layer of the ndarray methods (per-call overhead
# matters at a batch of one)
_sum, _max, _min, _all = np.add.reduce, np.maximum.reduce, np.minimum.reduce, np.logical_and.reduce
_nnz = np.count_nonzero


def _dot(u, v):
    return np.einsum("...i,...i->...", u, v)


def _unit(u):
    return u / np.sqrt(_dot(u, u))[..., None]


# --- the robot as standard DH ----------------------------------------------

def _dh_frames(dirs, pts, L):
    """World poses ``(..., 7, 4, 4)`` of DH frames 0..6 at q = 0 (see module docstring)
    of the axes ``pts + t dirs`` (``(..., 6, 3)`` each; the leading dimensions are
    independent robots, e.g. one per pose of a cyclically shifted problem)."""
    z = [dirs[..., i, :] for i in range(6)] + [dirs[..., 5, :]]  # z_i = axis i+1; z_6 = axis 6
    x = [None] * 7
    o = [None] * 7
    with np.errstate(divide="ignore", invalid="ignore"):
        for i in range(1, 6):                        # frame i: axes i (0-based i-1) and i+1
            u, v = dirs[..., i - 1, :], dirs[..., i, :]
            p, r = pts[..., i - 1, :], pts[..., i, :]
            n = cross(u, v)
            sn = np.sqrt(_dot(n, n))
            par = ~(sn > PARALLEL_TOL)[..., None]    # (..., 1): axes i, i+1 parallel
            # skew axes: closest points p + t u (axis i) and r + s v (axis i+1)
            w = r - p
            uv, wu, wv = _dot(u, v), _dot(w, u), _dot(w, v)
            den = 1.0 - uv * uv
            t = ((wu - wv * uv) / den)[..., None]
            s = ((wu * uv - wv) / den)[..., None]
            foot_j = r + s * v
            xi = n / sn[..., None]
            if i == 1:
                o[0] = np.where(par, p, p + t * u)
            # parallel axes: the normal through the previous origin
            ref = o[i - 1]
            wp = r - ref
            wp = wp - u * _dot(wp, u)[..., None]
            nw = np.sqrt(_dot(wp, wp))[..., None]
            if i == 1:                               # axes 1 and 2 coincide: any normal
                prev = cross(u, np.where(np.abs(u[..., :1]) < 0.9, [1.0, 0.0, 0.0],
                                         [0.0, 1.0, 0.0]))
            else:
                prev = x[i - 1]
            xp = np.where(nw > 1e-9 * L, wp / nw, prev)
            xi = np.where(par, xp, xi)
            foot_j = np.where(par, ref + wp, foot_j)
            xi = xi - v * _dot(xi, v)[..., None]
            x[i] = _unit(xi)
            o[i] = foot_j
            if i == 1:
                x[0] = _unit(x[1] - z[0] * _dot(x[1], z[0])[..., None])
    x[6], o[6] = _unit(x[5] - z[6] * _dot(x[5], z[6])[..., None]), o[5]
    X, Z, O = (np.stack(f, axis=-2) for f in (x, z, o))
    F = np.zeros(dirs.shape[:-2] + (7, 4, 4))
    F[..., :3, 0] = X
    F[..., :3, 1] = cross(Z, X)
    F[..., :3, 2] = Z
    F[..., :3, 3] = O
    F[..., 3, 3] = 1.0
    return F


class _Model:
    """A 6R robot as scaled standard DH plus the robot-level half of the elimination.

    Every array may have leading dimensions (one model per pose: the cyclically
    shifted problems, whose fixed link holds the pose); :func:`_eliminate` broadcasts
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
        The right side as a map of the target (:func:`_cubic_map`); None for
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
    """

    def __init__(self, B, E, L, theta0, d, a, alpha):
        self.B, self.E, self.L = B, E, L
        self.Binv, self.Einv = invert_transform(B), invert_transform(E)
        self.offset = np.asarray(theta0, float)
        self.d, self.a, self.alpha = (np.asarray(v, float) for v in (d, a, alpha))
        d, a, al = (v[..., :, None] for v in (self.d, self.a, self.alpha))   # (..., 6, 1)
        # right side: inverses of A1(g1) A2(g2) on the 3x3 grid
        g1, g2 = (m.ravel() for m in np.meshgrid(_GRID, _GRID, indexing="ij"))
        A12 = _dh(g1, d[..., 0, :], a[..., 0, :], al[..., 0, :]) \
            @ _dh(g2, d[..., 1, :], a[..., 1, :], al[..., 1, :])
        self.N12 = invert_transform(A12)                  # (..., 9, 4, 4)
        post = invert_transform(_dh(0.0, self.d[..., 5], self.a[..., 5], self.alpha[..., 5]))
        scale = np.array([1.0 / L, 1.0 / L, 1.0 / L, 1.0])
        self.left = scale[:, None] * self.Binv
        self.right = (self.Einv / scale) @ post
        # left side: l, p of A3 A4 A5 on the 3x3x3 grid -> coefficients
        g3, g4, g5 = (m.ravel() for m in np.meshgrid(_GRID, _GRID, _GRID, indexing="ij"))
        M = _dh(g3, d[..., 2, :], a[..., 2, :], al[..., 2, :]) \
            @ _dh(g4, d[..., 3, :], a[..., 3, :], al[..., 3, :]) \
            @ _dh(g5, d[..., 4, :], a[..., 4, :], al[..., 4, :])
        lead = self.d.shape[:-1]
        Pc = _VINV3 @ _f14(M[..., :3, 2], M[..., :3, 3])  # (..., 27, 14): row k3 * 9 + k4 * 3 + k5
        self.P27 = np.ascontiguousarray(np.swapaxes(Pc, -1, -2))
        P = np.swapaxes(Pc.reshape(lead + (3, 9, 14)), -1, -2)   # P(theta3) = P0 + c3 P1 + s3 P2
        self.cubic = None if lead else _cubic_map(self.N12)
        C12 = (_VINV2 @ A12[..., :3, :3].reshape(lead + (9, 9))).reshape(lead + (9, 3, 3))
        self.C12w = np.ascontiguousarray(np.moveaxis(C12, -2, -3).reshape(lead + (3, 27)))
        self.C35 = _VINV3 @ M[..., :3, :3].reshape(lead + (27, 9))
        self.U, self.K, self.UWb, self.UWW = self._deflation(P)

    def right_side(self, W):
        """Coefficients ``Rc (M, 9, 14)`` of the right side for scaled targets ``W (M, 4, 4)``
        (``W = left @ T @ right``): row ``i1 * 3 + i2`` holds the 14 equations' coefficients
        of ``(1, c1, s1)[i1] (1, c2, s2)[i2]``."""
        M = len(W)
        if self.cubic is not None:
            u = np.take(W.reshape(M, 16), _U_IDX, axis=1)
            m = ((u[:, :, None] * u[:, None, :]).reshape(M, 49, 1) * u[:, None, :])
            return (np.take(m.reshape(M, 343), _CUBIC_IDX, axis=1) @ self.cubic).reshape(M, 9, 14)
        lp = self.N12 @ W[:, None, :, 2:]                 # (M, 9, 4, 2): [l 0; p 1] per grid point
        return _VINV2 @ _f14(lp[..., :3, 0], lp[..., :3, 1])

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
        Sp = (P[..., 1, :, :] + 1j * P[..., 2, :, :]) @ _H2             # (..., 14, 9)
        R = np.linalg.svd(Sp)[2][..., :4, :]                             # its row space
        C8 = np.zeros(lead + (8, 12), complex)
        C8[..., :4, :9] = R
        C8[..., 4:, 3:] = R
        V = np.swapaxes(np.linalg.svd(C8)[2][..., 8:, :].conj(), -1, -2)   # (..., 12, 4)
        Vr, Vi = V.real, V.imag
        W = np.concatenate([np.concatenate([Vr, Vi], -1), np.concatenate([-Vi, Vr], -1)], -2)
        Qw, Rw = np.linalg.qr(W, mode="complete")
        Wo, U = Qw[..., :8], Qw[..., 8:]
        Rw = Rw[..., :8, :]
        J = np.kron(np.array([[0.0, 1.0], [-1.0, 0.0]]), np.eye(4))
        Mo = Rw @ J @ np.linalg.inv(Rw)
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
    def from_lines(cls, dirs, pts, T0, L):
        """Model of the 6R whose axes at q = 0 are ``pts[..., i, :] + t dirs[..., i, :]``
        (``(..., 6, 3)``, m) and whose tool pose at q = 0 is ``T0 (..., 4, 4)``."""
        F = _dh_frames(dirs, pts, L)
        G = invert_transform(F[..., :-1, :, :]) @ F[..., 1:, :, :]   # A_i(offset_i) (.., 6, 4, 4)
        theta0 = np.arctan2(G[..., 1, 0], G[..., 0, 0])
        d = G[..., 2, 3]
        a = G[..., 0, 3] * np.cos(theta0) + G[..., 1, 3] * np.sin(theta0)
        alpha = np.arctan2(G[..., 2, 1], G[..., 2, 2])
        E = invert_transform(F[..., 6, :, :]) @ T0
        return cls(F[..., 0, :, :], E, L, theta0, d / L, a / L, alpha)

    def perturbed(self, size):
        """The same robot with every scaled DH parameter moved by 0.5 .. 1 ``size`` (seeded)."""
        rng = np.random.default_rng(20240611)
        dd, da, dal = rng.uniform(0.5, 1.0, (3, 6)) * rng.choice([-1.0, 1.0], (3, 6)) * size
        return _Model(self.B, self.E, self.L, self.offset, self.d + dd, self.a + da,
                      self.alpha + dal)

    def fk_dh(self, q):
        """FK ``(..., 4, 4)`` (SI) of the DH model at ``q (..., 6)``, for checks."""
        th = np.asarray(q, float) + self.offset
        T = np.broadcast_to(np.eye(4), th.shape[:-1] + (4, 4)).copy()
        for i in range(6):
            T = T @ _dh(th[..., i], self.d[..., i], self.a[..., i], self.alpha[..., i])
        T[..., :3, 3] *= self.L
        return self.B @ T @ self.E


# --- the elimination, for a batch of poses -----------------------------------

def _inv_cond(A):
    """``(A^-1, |A|_F |A^-1|_F)`` of ``A (..., n, n)``; an exactly singular ``A`` gets a
    zero inverse and an infinite estimate (numpy's inv raises for the whole batch)."""
    try:
        Ai = np.linalg.inv(A)
    except np.linalg.LinAlgError:
        Uu, s, Vt = np.linalg.svd(A)
        si = np.where(s > 0.0, 1.0 / np.where(s > 0.0, s, 1.0), 0.0)
        Ai = np.swapaxes(Vt, -1, -2) @ (np.swapaxes(Uu, -1, -2) * si[..., None])
        return Ai, np.where(s[..., -1] > 0.0, _frobenius_cond(A, Ai), np.inf)
    return Ai, _frobenius_cond(A, Ai)


def _frobenius_cond(A, Ai):
    return np.sqrt(_sum(A * A, axis=(-2, -1)) * _sum(Ai * Ai, axis=(-2, -1)))


def _sigma(S, k):
    """``[C | B | A] (M, 12, 36)`` of ``Sigma(y)`` for shift delta number ``k`` from the
    scaled rows ``S (M, 6, 27)`` of the eliminated system."""
    return (S @ _SIGMA_MAPS[k]).reshape(-1, 6, 2, 36).transpose(0, 2, 1, 3).reshape(-1, 12, 36)


def _eliminate(model, T):
    """Raw candidates of the model's standard form (pivot: its joint 3) for ``T (M, 4, 4)``.

    Returns ``(pose (C,), slot (C,), q (C, 6), degenerate (M,), width)``: candidate
    joint values (the model's joints, rad, not wrapped), sorted by pose, with the index
    of their pose and their eigenvalue slot (``< width``: 16, or 32 when a pose has a
    cluster, whose extra vectors take slots 16-31); ``degenerate`` marks the poses where
    the elimination does not apply (``Q`` loses rank, an equation vanishes, or ``A`` is
    singular for every shift delta). ``model`` is one model for all poses or one per
    pose (leading dimension M).
    """
    M = len(T)
    with np.errstate(all="ignore"):
        W = model.left @ T @ model.right                 # A_1 .. A_5 Rz(theta_6), scaled
        Rc = model.right_side(W)                          # (M, 9, 14)
        Qf, Rq = np.linalg.qr(Rc[:, 1:, :].transpose(0, 2, 1), mode="complete")
        # Qf^T (P - constant): rows 0-7 give X2 (through Q's R), rows 8-13 (N) eliminate it
        QT = Qf.transpose(0, 2, 1)
        G = QT @ model.P27                                # (M, 14, 27)
        G[:, :, 0] -= (QT @ Rc[:, 0, :, None])[:, :, 0]
        S = G[:, 8:, :]
        scale = np.sqrt(_sum(S * S, axis=2))
        ok = _min(scale, axis=1) > 1e-12 * _max(scale, axis=1)
        S = S / np.maximum(scale, 1e-300)[:, :, None]
        Sig = _sigma(S, 0)
        # one inversion for A (shift delta 0) and Q's R
        mats = _INV_PAD[None].repeat(M, axis=0)
        mats[:, 0] = Sig[:, :, 24:]
        mats[:, 1, :8, :8] = Rq[:, :8, :8]
        inv, cond = _inv_cond(mats)
        lim = cond < _LIMITS                              # A taken at once; R of full rank
        ok &= lim[:, 1]
        Ai, best = inv[:, 0], cond[:, 0]
        # the shift delta per pose: the first with cond(A) < _COND_GOOD, else the best
        delta = 0.0
        redo = ok & ~lim[:, 0]
        if _nnz(redo):
            delta = np.zeros(M)
            redo = np.flatnonzero(redo)
            for k in range(1, len(_DELTAS)):
                Sk = _sigma(S[redo], k)
                Aik, ck = _inv_cond(Sk[:, :, 24:])
                take = ck < best[redo]
                rows = redo[take]
                Sig[rows], Ai[rows], best[rows], delta[rows] = (Sk[take], Aik[take], ck[take],
                                                                _DELTAS[k])
                redo = redo[~(ck < _COND_GOOD)]
                if len(redo) == 0:
                    break
            ok &= best <= _COND_BAD
            delta = delta[:, None]
        # the deflated companion matrix D and the block E (step 4)
        DE = model.K - model.UWb @ (Ai @ (Sig[:, :, :24] @ model.U))    # (M, 24, 16)
        all_ok = _nnz(ok) == M
        if not all_ok:
            DE[~ok] = 0.0
        try:
            lam, yv = np.linalg.eig(DE[:, :16])
        except np.linalg.LinAlgError:                     # non-finite entries: degenerate
            ok &= _all(np.isfinite(DE), axis=(1, 2))
            all_ok = False
            DE[~ok] = 0.0
            lam, yv = np.linalg.eig(DE[:, :16])
        lam = lam.astype(complex)
        yv = yv.astype(complex)
        # the companion matrix's eigenvectors U y + Wo (lam + Mo) E y / (1 + lam^2)
        c = 1.0 / (1.0 + lam * lam)
        Ey = (DE[:, 16:] @ yv.view(float)).view(complex)  # (M, 8, 16), real BLAS products
        x = (model.UWW @ np.concatenate([yv, Ey * (lam * c)[:, None, :], Ey * c[:, None, :]],
                                        axis=1).view(float)).view(complex)       # (M, 24, 16)
        v = np.where((np.abs(lam) > 1.0)[:, None, :], x[:, 12:], x[:, :12])   # (M, 12, 16)
        phi = 2.0 * np.arctan(lam)
        keep = np.abs(phi.imag) < IMAG_TOL
        if not all_ok:
            keep &= ok[:, None]
        keep, extra = _split_clusters(v, phi, keep, Sig)
        pose, slot = np.nonzero(keep)
        vs, th3 = v[pose, :, slot], phi.real[pose, slot]
        width = 16
        if extra is not None:                             # clusters: extra slots 16-31
            rows, v2, phi2, keep2 = extra
            p2, s2 = np.nonzero(keep2)
            order = np.lexsort((np.r_[slot, s2 + 16], np.r_[pose, rows[p2]]))
            pose, slot = np.r_[pose, rows[p2]][order], np.r_[slot, s2 + 16][order]
            vs = np.concatenate([vs, v2[p2, :, s2]])[order]
            th3 = np.r_[th3, phi2.real[p2, s2]][order]
            width = 32
        if isinstance(delta, np.ndarray):
            th3 = th3 + delta[pose, 0]
        q = _candidate_angles(model, pose, vs, th3, inv[:, 1, :8, :8], G[:, :8], W)
        fin = np.isfinite(_sum(q, axis=1))
    if _nnz(fin) < len(fin):
        pose, slot, q = pose[fin], slot[fin], q[fin]
    return pose, slot, q, ~ok, width


def _candidate_angles(model, pose, v, th3, Ri, G8, W):
    """Joint values ``(C, 6)`` (the model's joints, rad) of candidates of poses
    ``pose (C,)``.

    ``v (C, 12)`` are the monomial vectors (any complex phase), ``th3 (C,)`` the pivot
    angles. theta_4, theta_5 from the vectors (:func:`_ratio_angles`); theta_1, theta_2
    from ``Q X2 = P X1``: ``X2 = Ri G8 Y`` with ``Ri (M, 8, 8)`` the inverse of Q's R,
    ``G8 (M, 8, 27)`` the first rows of ``Qf^T P`` and ``Y`` the 27 products of
    (1, cos, sin) of theta_3..5; theta_6 from ``Rz(theta_6) = (R1 .. R5)^T W``
    (``W (M, 4, 4)``, its first column), with ``R1 R2`` linear in ``(1, X2)`` and
    ``R3 R4 R5`` in ``Y``.
    """
    C, M = len(pose), len(W)
    th345 = np.concatenate([th3[:, None], _ratio_angles(v)], axis=1)       # (C, 3)
    b = np.cos(th345[..., None] * _TRIG_MUL - _TRIG_SUB)  # (1, cos, sin): (C, 3, 3)
    Y = ((b[:, 0, :, None] * b[:, 1, None, :]).reshape(C, 9, 1) * b[:, 2, None, :]).reshape(C, 27)
    Gw = (W[:, None, :3, 0] @ model.C12w).reshape(M, 9, 3)   # R12_k^T w0, k = i1 * 3 + i2
    # per pose, 27 -> (s1, s2, c1, c2) of X2 (the products (i1, i2) != (0, 0), flattened
    # i1 * 3 + i2 - 1) and sum_k X2_k R12_k^T w0
    L7 = np.concatenate([np.take(Ri, _X2_SEL, axis=1), Gw[:, 1:].transpose(0, 2, 1) @ Ri], axis=1)
    X = (Y[:, None, :] @ np.take((L7 @ G8).transpose(0, 2, 1), pose, axis=0))[:, 0]   # (C, 7)
    if model.C35.ndim == 2:
        R35 = Y @ model.C35
    else:                                                 # one model per pose
        R35 = (Y[:, None, :] @ np.take(model.C35, pose, axis=0))[:, 0]
    u = ((X[:, None, 4:] + np.take(Gw[:, None, 0], pose, axis=0)) @ R35.reshape(C, 3, 3))[:, 0]
    # u = (R35^T R12^T w0)^T
    offset = model.offset if model.offset.ndim == 1 else np.take(model.offset, pose, axis=0)
    return np.concatenate([np.arctan2(X[:, :2], X[:, 2:4]), th345,
                           np.arctan2(u[:, 1:2], u[:, 0:1])], axis=1) - offset


_X2_SEL = np.array([5, 1, 2, 0])
_TRIG_MUL = np.array([0.0, 1.0, 1.0])
_TRIG_SUB = np.array([0.0, 0.0, np.pi / 2.0])


# index sets of the monomials x4^j x5^k (flattened j * 3 + k) for the shift operators
_J4, _J5 = np.divmod(np.arange(12), 3)
_LO4, _HI4 = np.flatnonzero(_J4 < 3), np.flatnonzero(_J4 > 0)
_LO5, _HI5 = np.flatnonzero(_J5 < 2), np.flatnonzero(_J5 > 0)
_TAU = np.tan(0.3)


def _ratio_maps():
    """``(AB (102,), SUM (6, 51))``: rows of a gather whose two halves' product, summed by
    ``SUM``, gives ``sum lo hi``, ``sum lo^2``, ``sum hi^2`` over the pairs
    (x4^j x5^k, x4^(j+1) x5^k) (9 of them) and (x4^j x5^k, x4^j x5^(k+1)) (8), in the
    order cr4, cr5, lo4, lo5, hi4, hi5."""
    lo, hi = np.r_[_LO4, _LO5], np.r_[_HI4, _HI5]
    SUM = np.zeros((6, 51))
    for q, (a, b) in enumerate(((0, 9), (9, 17))):
        for k in range(3):
            SUM[2 * k + q, 17 * k + a:17 * k + b] = 1.0
    return np.r_[lo, lo, hi, hi, lo, hi], SUM


_RATIO_AB, _RATIO_SUM = _ratio_maps()


def _ratio_angles(v):
    """``(theta_4, theta_5) (n, 2)`` with x = tan(theta / 2) from monomial vectors
    ``v (n, 12)`` (complex, entries x4^j x5^k at j * 3 + k, any common phase):
    least-squares ratios of consecutive entries (``x = sum lo hi / sum lo^2`` over the
    pairs (x4^j x5^k, x4^(j+1) x5^k), resp. (.., x4^j x5^(k+1)), with the real forms
    ``Re(conj(a) b)``), inverted when |x| > 1."""
    g = np.take(np.ascontiguousarray(v, dtype=complex).view(float).reshape(-1, 12, 2), _RATIO_AB,
                axis=1)
    f = _sum(_RATIO_SUM @ (g[:, :51] * g[:, 51:]), axis=2)   # cr4, cr5, lo4, lo5, hi4, hi5
    cr, dlo, dhi = f[:, 0:2], f[:, 2:4], f[:, 4:6]
    return 2.0 * np.where(dlo >= dhi, np.arctan2(cr, dlo), np.arctan2(dhi, cr))


def _split_clusters(v, phi, keep, Sig):
    """Better vectors for clustered eigenvalues, all clusters of all poses at once.

    ``v (M, 12, n)`` (vectors), ``phi (M, n)`` (angles), ``keep (M, n)`` (real
    candidates), ``Sig (M, 12, 36)`` (``[C | B | A]`` of each pose). Returns
    ``(keep, extra)``: ``keep`` updated for the clusters' own vectors, and ``extra`` None
    (no cluster: the common case) or ``(rows (P,), v2 (P, 12, n), phi2 (P, n), keep2
    (P, n))`` for the P poses with a cluster, slot j of ``v2`` holding the subspace
    vector that goes with own slot j.

    Solutions that share the pivot angle (e.g. the two wrist flips of a
    spherical wrist when the pivot is an arm joint) give a multiple
    eigenvalue, often defective in the companion form: it splits by up to
    ~sqrt(eps) and eig's vectors are arbitrary mixtures, or nearly parallel.
    The mean of a cluster is accurate (Manocha & Canny 1994, sec. V-B), so
    each cluster of m eigenvalues (real parts of the angles within
    CLUSTER_TOL of the next; this includes a conjugate pair with a small
    imaginary part, which is how a near-double real root often comes out)
    gets the mean angle and, as its space, the m smallest right singular
    vectors ``N`` of ``Sigma`` there. In that space the true vectors ``v = N c``
    are those of monomials, so ``c`` is a common eigenvector of the shift
    operators "multiply by x4" (``v[j+1, k] = x4 v[j, k]``) and "multiply by
    x5"; these m x m operators come from least squares on the Moebius-shifted
    form ``(Hi - t Lo) c = z (Lo + t Hi) c`` (finite even at x = infinity), and a
    fixed combination of the two is diagonalised. The cluster's own
    eigenvectors compete (they are right when its eigenvalues are distinct
    roots that merely lie close): of the 2m vectors, those within 1e-3 of a
    monomial vector are kept, and at least the m closest. The subspace vectors
    get the mean angle.
    """
    M, n = phi.shape
    key = np.where(keep, phi.real, np.inf)
    sk = np.sort(key, axis=1)
    if not _nnz(sk[:, 1:] - sk[:, :-1] < CLUSTER_TOL):
        return keep, None                                # no cluster (the common case)
    order = np.argsort(key, axis=1)
    close = np.diff(np.take_along_axis(key, order, axis=1), axis=1) < CLUSTER_TOL
    # runs of close neighbours in sorted order: group id per sorted position
    gid = np.concatenate([np.zeros((M, 1), int), np.cumsum(~close, axis=1)], axis=1)
    flat = (np.arange(M)[:, None] * n + gid).ravel()
    size = np.bincount(flat, minlength=M * n)
    start = np.concatenate([np.ones((M, 1), bool), ~close], axis=1)     # a run begins here
    run = size[flat].reshape(M, n)
    rows = np.flatnonzero(np.logical_or.reduce(start & (run >= 2), axis=1))
    at = np.zeros(M, int)
    at[rows] = np.arange(len(rows))                      # pose -> row of the extra slots
    v2 = np.zeros((len(rows), 12, n), complex)
    v2[:, 0] = 1.0
    phi2 = np.zeros((len(rows), n), complex)
    keep2 = np.zeros((len(rows), n), bool)
    for k in np.unique(run[start & (run >= 2)]):
        pg, j0 = np.nonzero(start & (run == k))
        members = order[pg[:, None], j0[:, None] + np.arange(k)]       # (p, k) slots
        mean = np.mean(phi.real[pg[:, None], members], axis=1)
        y = np.tan(mean / 2.0)
        small = (np.abs(y) <= 1.0)[:, None, None]
        with np.errstate(all="ignore"):
            w = np.where(small[:, 0, 0], 0.0, 1.0 / y)[:, None, None]
        yy = np.where(small[:, 0, 0], y, 0.0)[:, None, None]
        Sp = Sig[pg]
        Cm, Bm, Am = Sp[:, :, :12], Sp[:, :, 12:24], Sp[:, :, 24:]
        S = np.where(small, (Am * yy + Bm) * yy + Cm, Am + (Bm + Cm * w) * w)
        Nsub = np.swapaxes(np.linalg.svd(S)[2][:, -k:, :], -1, -2)     # (p, 12, k)
        Mop = np.zeros((len(pg), k, k))
        for lo, hi, wgt in ((_LO4, _HI4, 1.0), (_LO5, _HI5, 0.6180339887)):
            lhs = Nsub[:, lo] + _TAU * Nsub[:, hi]
            rhs = Nsub[:, hi] - _TAU * Nsub[:, lo]
            Mop = Mop + wgt * (np.linalg.pinv(lhs, rcond=np.finfo(float).eps * len(lo)) @ rhs)
        sub = Nsub @ np.linalg.eig(Mop)[1]                              # (p, 12, k)
        own = np.take_along_axis(v[pg], members[:, None, :], axis=2)    # (p, 12, k)
        both = np.concatenate([own, sub], axis=2)                       # (p, 12, 2k)
        res = _structure_residual(np.swapaxes(both, 1, 2).reshape(-1, 12)).reshape(-1, 2 * k)
        rank = np.argsort(np.argsort(res, axis=1, kind="stable"), axis=1, kind="stable")
        kept = (res < 1e-3) | (rank < k)
        keep[pg[:, None], members] = kept[:, :k]
        pgk = at[pg][:, None]
        v2[pgk, :, members] = np.swapaxes(sub, 1, 2)
        phi2[pgk, members] = mean[:, None]
        keep2[pgk, members] = kept[:, k:]
    return keep, (rows, v2, phi2, keep2)


def _structure_residual(V):
    """Sine of the angle between each row of ``V (n, 12)`` and the nearest monomial vector."""
    R = (V / V[np.arange(len(V)), np.argmax(np.abs(V), axis=1)][:, None]).real
    h = _ratio_angles(R) / 2.0                                          # (n, 2)
    c, s = np.cos(h), np.sin(h)
    # x4^j x5^k times cos^3(h4) cos^2(h5): bounded also at x = infinity
    m4 = np.stack([c[:, 0] ** (3 - j) * s[:, 0] ** j for j in range(4)], axis=-1)
    m5 = np.stack([c[:, 1] ** (2 - j) * s[:, 1] ** j for j in range(3)], axis=-1)
    W = (m4[:, :, None] * m5[:, None, :]).reshape(-1, 12)
    cos = np.abs(np.sum(R * W, axis=1)) / (np.linalg.norm(R, axis=1) * np.linalg.norm(W, axis=1))
    return np.sqrt(np.maximum(0.0, 1.0 - cos * cos))


# --- per robot ------------------------------------------------------------------

class _Robot6R:
    """Per-robot data: axes at q = 0, the shift-0 model, the chain for Newton, and the
    ranked pivot shifts.

    Raises ValueError if the robot does not have exactly 6 revolute joints.
    """

    def __init__(self, robot):
        from ..structure import joint_axes
        if robot.dof != 6 or not all([j.revolute for j in robot.joints]):
            raise ValueError("the general 6R solver needs a robot with exactly 6 revolute "
                             "joints, got " + "".join("R" if j.revolute else "P"
                                                      for j in robot.joints))
        self.dirs, self.pts = joint_axes(robot)
        self.T0 = robot.fk(np.zeros(6))
        self.L = float(robot.characteristic_length)
        fixed = np.array(robot.chain.fixed)
        fixed[:, :3, 3] /= self.L
        #: the chain with lengths divided by L: Newton's position errors and the
        #: Jacobian's linear rows come out scaled
        self.chain = Chain(fixed, robot.chain.revolute, robot.chain.offset)
        self.scale = np.array([[1.0, 1.0, 1.0, self.L]])      # divides a pose's rows 0-2
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
            pose, _, cand, bad, _ = self.raw(Ts, k)
            worst = np.inf
            if not bad.any() and np.all(np.bincount(pose, minlength=3) > 0):
                dist = np.max(np.abs(wrap(cand - qs[pose])), axis=1)
                near = np.full(3, np.inf)
                np.minimum.at(near, pose, dist)
                worst = float(near.max())
            if k == 0 and worst < 1e-8:
                return list(range(6))
            # accurate shifts first, among them the one with fewer candidates (less Newton work)
            keys.append((worst >= 1e-8, worst if worst >= 1e-8 else len(pose), k))
        return [k for *_, k in sorted(keys)]

    @property
    def perturbed(self):
        """Nearby generic models (one per PERTURB size), built on first use."""
        if self._perturbed is None:
            self._perturbed = [self.model.perturbed(size) for size in PERTURB]
        return self._perturbed

    def shifted_model(self, T, shift):
        """``(model, order)``: the 6Rs of the cyclic shift ``shift`` for poses ``T (M, 4, 4)``
        (one model per pose; their target is the identity) and their joints' indices in
        the original order."""
        G = self.T0 @ invert_transform(T)                 # (M, 4, 4)
        order = np.r_[shift:6, 0:shift]
        moved = order < shift
        R, t = G[:, None, :3, :3], G[:, None, :3, 3]
        dirs = np.where(moved[:, None], (R @ self.dirs[order][..., None])[..., 0],
                        self.dirs[order])
        pts = np.where(moved[:, None], (R @ self.pts[order][..., None])[..., 0] + t,
                       self.pts[order])
        return _Model.from_lines(dirs, pts, G, self.L), order

    def raw(self, T, shift):
        """Raw candidates with the pivot of cyclic shift ``shift`` for ``T (M, 4, 4)``:
        ``(pose (C,), slot (C,), q (C, 6) in the robot's joint order, degenerate (M,),
        width)`` (see :func:`_eliminate`).

        The pivot is joint ``(shift + 2) % 6 + 1`` (1-based): 3 for shift 0, 2 for shift 5.
        ``A_1 ... A_6 = T'`` is rotated into ``A_{k+1} ... A_6 T'^-1 A_1 ... A_k = I``:
        a 6R chain whose joints are k+1..6, 1..k, with the pose folded into the
        link between joints 6 and 1, and the target the identity.
        """
        if shift == 0:
            return _eliminate(self.model, T)
        model, order = self.shifted_model(T, shift)
        pose, slot, c, bad, width = _eliminate(model, np.broadcast_to(np.eye(4), T.shape))
        out = np.empty_like(c)
        out[:, order] = c
        return pose, slot, out, bad, width

    def candidates(self, T):
        """Raw candidates for ``T (M, 4, 4)``: each pose with the first ranked shift that
        does not degenerate, else with both perturbed models (the second one's slots after
        the first's). Returns ``(pose (C,), slot (C,), q (C, 6), width)`` sorted by pose
        (then slot), ``slot < width``."""
        todo = np.arange(len(T))
        pieces = []
        for shift in self.shifts:
            pose, slot, q, bad, width = self.raw(T[todo] if len(pieces) else T, shift)
            pieces.append((todo[pose] if pieces else pose, slot, q, width))
            todo = todo[bad]
            if len(todo) == 0:
                break
        else:
            offset = 0
            for model in self.perturbed:
                pose, slot, q, _, width = _eliminate(model, T[todo])
                pieces.append((todo[pose], slot + offset, q, offset + width))
                offset += width
        if len(pieces) == 1:
            return pieces[0]
        pose = np.concatenate([p[0] for p in pieces])
        order = np.lexsort((np.concatenate([p[1] for p in pieces]), pose))
        return (pose[order], np.concatenate([p[1] for p in pieces])[order],
                np.concatenate([p[2] for p in pieces])[order], max(p[3] for p in pieces))


@per_robot
def _robot_data(robot):
    return _Robot6R(robot)


# --- Newton polishing on the real robot -----------------------------------

_ROT_IDX = np.array([7, 2, 3, 5, 6, 1, 0, 4, 8])   # R21 R02 R10, R12 R20 R01, R00 R11 R22


def _skew_trace(R):
    """``(v, c2)`` of rotations ``R (m, 3, 3)``: ``v = 2 sin(angle) axis`` (the skew part,
    doubled) and ``c2 = 2 cos(angle)``."""
    g = np.take(R.reshape(-1, 9), _ROT_IDX, axis=1)
    return g[:, :3] - g[:, 3:6], _sum(g[:, 6:], axis=1) - 1.0


def _log(v, c2, R):
    """Rotation vectors ``(m, 3)`` from :func:`_skew_trace` ``(v, c2)`` of ``R (m, 3, 3)``."""
    sn = np.sqrt(_sum(v * v, axis=1))
    w = v * (np.arctan2(sn, c2) / np.maximum(sn, 1e-300))[:, None]
    far = c2 < 0.0
    if _nnz(far):
        w[far] = rotvec_from_matrix(R[far])
    return w


def _polish(chain, T, Q, iters=_NEWTON_ITERS):
    """Newton (:func:`kincalc.ik.newton.polish`) on ``fk(q) = T``; returns ``(q (m, 6),
    residual (m,), moved (m,))``.

    ``chain`` is the robot's with lengths divided by its length scale, ``T (m, 3, 4)``
    each candidate's target (rows 0-2, translation scaled alike), ``Q (m, 6)`` the
    starts; ``moved`` marks the candidates that took a step. A candidate stops when its
    residual ``max(|dp| / L, |dw|)`` is at rounding level (below 1e-13, or below
    ACCEPT_TOL / 100 and no longer halving), after ``iters`` steps, or when it is still
    far after a few (``_GIVE_UP``: spurious candidates from complex eigenvalues; the few
    that would wander into a solution after many steps only find one that a good
    candidate already gave).
    """
    tp, tR = T[:, :, 3], T[:, :, :3]

    def evaluate(q, rows):
        J, F = jacobian_and_pose(chain, q)
        ep = tp[rows] - F[:, :3, 3]
        R = tR[rows] @ F[:, :3, :3].transpose(0, 2, 1)
        v, c2 = _skew_trace(R)
        return np.concatenate([ep, _log(v, c2, R)], axis=1), lambda keep: J[keep]
    return polish(evaluate, Q, iterations=iters, tol=1e-13, damping=1e-14,
                  stall=1e-2 * ACCEPT_TOL, give_up=_GIVE_UP, max_step=_STEP_MAX)


# --- public API -------------------------------------------------------------

def solve_general_6r_batch(robot, T) -> tuple[np.ndarray, np.ndarray]:
    """All real IK solutions of a 6R robot (any geometry) for a batch of poses.

    Parameters
    ----------
    robot : Robot
        Six revolute joints; no structure needed (see the module docstring for robots
        with special structure).
    T : array_like (N, 4, 4)
        Tool poses ``T_world_tool`` (SI, world frame). A single pose is ``T[None]``.

    Returns
    -------
    Q : ndarray (N, BATCH_SLOTS, 6)
        Joint values (rad, wrapped to (-pi, pi]); 0 in unused slots.
    ok : ndarray (N, BATCH_SLOTS) bool
        The valid slots, first in each row: each reproduces its pose by FK to 1e-10
        relative to ``robot.characteristic_length`` (position) and 1e-10 rad, after
        Newton polishing on ``robot.chain``; duplicates within MERGE_TOL are merged. A
        pose outside the workspace, a non-finite pose, or (not reached by any robot of
        the library) a pose where every pivot and the last resort degenerate, gets none.

    Raises
    ------
    ValueError
        If ``robot`` does not have exactly 6 revolute joints, or ``T`` is not (N, 4, 4).

    Notes
    -----
    Every step (model, elimination, eigenproblems, clusters, other pivots, Newton)
    runs on all poses together; see the module docstring for the method.
    """
    if robot.dof != 6 or not all([j.revolute for j in robot.joints]):
        raise ValueError("solve_general_6r_batch needs a robot with exactly 6 revolute "
                         "joints, got " + "".join("R" if j.revolute else "P"
                                                  for j in robot.joints))
    T = np.asarray(T, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise ValueError(f"T must be an (N, 4, 4) array of transforms, got shape {T.shape}")
    N = len(T)
    Q = np.zeros((N, BATCH_SLOTS, 6))
    ok = np.zeros((N, BATCH_SLOTS), bool)
    data = _robot_data(robot)
    for lo in range(0, N, _BLOCK):       # blocks of poses: their arrays stay in cache
        _solve_block(data, T[lo:lo + _BLOCK], Q[lo:lo + _BLOCK], ok[lo:lo + _BLOCK])
    return Q, ok


#: poses solved together (larger batches go in blocks of this many)
_BLOCK = 512


def _solve_block(data, T, Q_out, ok):
    """:func:`solve_general_6r_batch` for poses ``T (N, 4, 4)``, into ``Q_out (N, K, 6)``
    and ``ok (N, K)`` (zero on entry)."""
    N, K = len(T), Q_out.shape[1]
    finite = _all(np.isfinite(T), axis=(1, 2))
    rows = None if _nnz(finite) == N else np.flatnonzero(finite)
    Tr = T if rows is None else T[rows]
    M = len(Tr)
    if M == 0:
        return
    pose, slot, cand, width = data.candidates(Tr)
    Tt = Tr[:, :3] / data.scale                      # rows 0-2, translation scaled
    Qp, res, moved = _polish(data.chain, np.take(Tt, pose, axis=0), cand)
    acc = res < ACCEPT_TOL
    pose, Qp = pose[acc], wrap(Qp[acc])
    rank = np.arange(len(pose)) - np.searchsorted(pose, pose)     # in slot order
    if width > 16 or _nnz(moved):
        # duplicates: a solution within MERGE_TOL of one in an earlier slot of its pose
        # (raw candidates from distinct eigenvalue slots that did not move are farther
        # apart than CLUSTER_TOL unless they are a cluster's)
        S = int(_max(rank)) + 1
        Qd = np.zeros((M, S, 6))
        good = np.zeros((M, S), bool)
        Qd[pose, rank] = Qp
        good[pose, rank] = True
        d = np.abs(Qd[:, :, None] - Qd[:, None])
        near = _all((d < MERGE_TOL) | (d > 2.0 * np.pi - MERGE_TOL), axis=3)
        dup = np.logical_or.reduce(near & _EARLIER[:S, :S] & good[:, None, :], axis=2)
        if _nnz(dup):
            new = ~dup[pose, rank]
            pose, Qp = pose[new], Qp[new]
            rank = np.arange(len(pose)) - np.searchsorted(pose, pose)
    # valid slots first, in slot order, at most K
    if len(rank) and _max(rank) >= K:
        first = rank < K
        pose, rank, Qp = pose[first], rank[first], Qp[first]
    if rows is not None:
        pose = rows[pose]
    Q_out[pose, rank] = Qp
    ok[pose, rank] = True


# [i, j]: slot j comes before slot i (a pose has at most 64 candidates: 2 x 32 in the last resort)
_EARLIER = np.tri(4 * BATCH_SLOTS, k=-1, dtype=bool)


def solve_general_6r(robot, T) -> np.ndarray:
    """All real solutions ``(k, 6)`` (rad, wrapped to (-pi, pi], k <= 16) of
    ``robot.fk(q) == T`` for one pose ``T (4, 4)`` (SI, world frame): the valid rows of
    :func:`solve_general_6r_batch` for the batch ``T[None]`` (same accuracy, merging
    and ValueErrors; a non-finite or unreachable pose gives ``(0, 6)``)."""
    Q, ok = solve_general_6r_batch(robot, np.asarray(T, dtype=float)[None])
    return Q[0][ok[0]]


def general_6r(robot, targets, br):
    """The branches of a general 6R robot: the elimination's solutions of every pose
    (:func:`solve_general_6r_batch`), ordered by joint 3 then joint 1, one slot each,
    labelled by their rank (``root k`` of joint 3). ``targets`` must be whole poses."""
    from dataclasses import replace as _replace
    from ..errors import UnsupportedRobot
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
