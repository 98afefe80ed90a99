"""The elimination for a batch of poses (steps 3 to 5 of :mod:`kincalc.ik.general6r`):
the 12x12 matrix polynomial, its eigenproblem, and the candidate angles read from
the eigenvectors, with near-double roots split into clusters."""

from __future__ import annotations

import functools

import numpy as np

from .common import (CLUSTER_TOL, COND_BAD, COND_GOOD, DELTAS, IMAG_TOL, INV_PAD, LIMITS,
                     PAIR_IMAG, SIGMA_MAPS, nnz, reduce_all, reduce_max, reduce_min, reduce_sum)


# --- the elimination, for a batch of poses -----------------------------------

def _inv_cond(A):
    """``(A^-1, |A|_F |A^-1|_F)`` of ``A (..., n, n)``; a matrix that LU finds exactly
    singular gets its pseudo-inverse (and an infinite estimate if the SVD finds it singular
    too).

    numpy's inv raises for the whole batch when one matrix is singular; the batch is then
    halved until the singular matrices are alone, so that every matrix gets the same inverse
    (the same bits) as in any other batch, or alone."""
    try:
        Ai = np.linalg.inv(A)
    except np.linalg.LinAlgError:
        flat = A.reshape((-1,) + A.shape[-2:])
        Ai, singular = np.empty_like(flat), np.zeros(len(flat), bool)
        _invert_into(flat, Ai, singular)
        Ai = Ai.reshape(A.shape)
        return Ai, np.where(singular.reshape(A.shape[:-2]), np.inf, _frobenius_cond(A, Ai))
    return Ai, _frobenius_cond(A, Ai)


def _invert_into(A, Ai, singular):
    """``Ai[:] = A^-1`` for ``A (m, n, n)``, the pseudo-inverse for a matrix LU finds
    singular (``singular`` set where the SVD does too), each as if alone (:func:`_inv_cond`)."""
    try:
        Ai[:] = np.linalg.inv(A)
    except np.linalg.LinAlgError:
        if len(A) > 1:
            half = len(A) // 2
            _invert_into(A[:half], Ai[:half], singular[:half])
            _invert_into(A[half:], Ai[half:], singular[half:])
            return
        Uu, s, Vt = np.linalg.svd(A)
        si = np.where(s > 0.0, 1.0 / np.where(s > 0.0, s, 1.0), 0.0)
        Ai[:] = np.swapaxes(Vt, -1, -2) @ (np.swapaxes(Uu, -1, -2) * si[..., None])
        singular[:] = not s[0, -1] > 0.0


def _frobenius_cond(A, Ai):
    return np.sqrt(reduce_sum(A * A, axis=(-2, -1)) * reduce_sum(Ai * Ai, axis=(-2, -1)))


def _sigma(S, k):
    """``[C | B | A] (M, 12, 36)`` of ``Sigma(y)`` for shift delta number ``k`` from the
    scaled rows ``S (M, 6, 27)`` of the eliminated system."""
    return (S @ SIGMA_MAPS[k]).reshape(-1, 6, 2, 36).transpose(0, 2, 1, 3).reshape(-1, 12, 36)


def eliminate(model, T, pair_imag=PAIR_IMAG):
    """Raw candidates of the model's standard form (pivot: its joint 3) for the poses ``T``.

    Parameters
    ----------
    model : Model
        One model for all poses, or one per pose (leading dimension M).
    T : ndarray (M, 4, 4)
        Poses ``T_world_tool`` (SI).
    pair_imag : float
        The largest |Im| (rad) of a conjugate pair that is a cluster (:func:`split_clusters`).

    Returns
    -------
    pose : ndarray (C,) of int
        Each candidate's pose; the candidates are sorted by pose.
    slot : ndarray (C,) of int
        Its eigenvalue slot (``< width``).
    q : ndarray (C, 6)
        Candidate joint values (the model's joints, rad, not wrapped), finite.
    degenerate : ndarray (M,) of bool
        The poses where the elimination does not apply (``Q`` loses rank, an equation
        vanishes, or ``A`` is singular for every shift delta).
    width : int
        16, or 32 when a pose has a cluster (whose extra vectors take slots 16-31), or 48
        when a cluster is a chain with a tight sub-cluster (its vectors: slots 32-47).
    continuum : ndarray (M,) of bool
        Poses (not degenerate) with a cluster that isolated solutions do not explain, the
        mark of a continuum of solutions at one pivot angle (see :func:`split_clusters`):
        their candidates may miss isolated solutions at that angle.
    """
    with np.errstate(all="ignore"):
        W, G, Sig, Ai, Ri, ok, delta = _matrix_polynomial(model, T)
        lam, v, ok, all_ok = _eigenvectors(model, Sig, Ai, ok)
        phi = 2.0 * np.arctan(lam)
        keep = np.abs(phi.imag) < IMAG_TOL
        if not all_ok:
            keep &= ok[:, None]
        keep, extra, continuum = split_clusters(v, phi, keep, Sig, pair_imag)
        pose, slot = np.nonzero(keep)
        vs, th3 = v[pose, :, slot], phi.real[pose, slot]
        width = 16
        if extra is not None:                             # clusters: extra slots 16-31 (47)
            rows, v2, phi2, keep2 = extra
            p2, s2 = np.nonzero(keep2)
            pose, slot = np.concatenate([pose, rows[p2]]), np.concatenate([slot, s2 + 16])
            order = np.lexsort((slot, pose))
            pose, slot = pose[order], slot[order]
            vs = np.concatenate([vs, v2[p2, :, s2]])[order]
            th3 = np.concatenate([th3, phi2.real[p2, s2]])[order]
            width = 16 + v2.shape[2]
        if isinstance(delta, np.ndarray):
            th3 = th3 + delta[pose, 0]
        q = _candidate_angles(model, pose, vs, th3, Ri, G[:, :8], W)
        fin = np.isfinite(reduce_sum(q, axis=1))
    if nnz(fin) < len(fin):
        pose, slot, q = pose[fin], slot[fin], q[fin]
    if continuum is None:
        continuum = np.zeros(len(ok), bool)
    return pose, slot, q, ~ok, width, continuum & ok


def _matrix_polynomial(model, T):
    """Steps 2 and 3 for the poses ``T (M, 4, 4)``: the scaled target ``W``, ``G`` (the
    right side's equations turned by Q's orthonormal basis, (M, 14, 27)), the 12x12 matrix
    polynomial ``Sig`` at each pose's shift delta, the inverse of its leading coefficient
    ``Ai`` and of Q's R factor ``Ri``, the poses where the elimination applies ``ok``, and
    the shifts ``delta`` (0.0, or ``(M, 1)`` when a pose needed one)."""
    M = len(T)
    W = model.left @ T @ model.right                 # A_1 .. A_5 Rz(theta_6), scaled
    Rc = model.right_side(W)                          # (M, 9, 14)
    Qf, Rq = np.linalg.qr(Rc[:, 1:, :].transpose(0, 2, 1), mode="complete")
    # Qf^T (P - constant): rows 0-7 give X2 (through Q's R), rows 8-13 (N) eliminate it
    QT = Qf.transpose(0, 2, 1)
    G = QT @ model.P27                                # (M, 14, 27)
    G[:, :, 0] -= (QT @ Rc[:, 0, :, None])[:, :, 0]
    S = G[:, 8:, :]
    scale = np.sqrt(reduce_sum(S * S, axis=2))
    ok = reduce_min(scale, axis=1) > 1e-12 * reduce_max(scale, axis=1)
    S = S / np.maximum(scale, 1e-300)[:, :, None]
    Sig = _sigma(S, 0)
    # one inversion for A (shift delta 0) and Q's R
    mats = INV_PAD[None].repeat(M, axis=0)
    mats[:, 0] = Sig[:, :, 24:]
    mats[:, 1, :8, :8] = Rq[:, :8, :8]
    inv, cond = _inv_cond(mats)
    lim = cond < LIMITS                              # A taken at once; R of full rank
    ok &= lim[:, 1]
    Ai, best = inv[:, 0], cond[:, 0]
    # the shift delta per pose: the first with cond(A) < COND_GOOD, else the best
    delta = 0.0
    redo = ok & ~lim[:, 0]
    if nnz(redo):
        delta = np.zeros(M)
        redo = np.flatnonzero(redo)
        for k in range(1, len(DELTAS)):
            Sk = _sigma(S[redo], k)
            Aik, ck = _inv_cond(Sk[:, :, 24:])
            take = ck < best[redo]
            rows = redo[take]
            Sig[rows], Ai[rows], best[rows], delta[rows] = (Sk[take], Aik[take], ck[take],
                                                            DELTAS[k])
            redo = redo[~(ck < COND_GOOD)]
            if len(redo) == 0:
                break
        ok &= best <= COND_BAD
        delta = delta[:, None]
    return W, G, Sig, Ai, inv[:, 1, :8, :8], ok, delta


def _eigenvectors(model, Sig, Ai, ok):
    """Step 4: the 16 eigenvalues ``lam (M, 16)`` of the deflated companion matrix and
    the matching null vectors ``v (M, 12, 16)`` of the matrix polynomial; ``ok`` narrowed
    to the poses with finite matrices, and whether every pose is ok."""
    M = len(Sig)
    DE = model.K - model.UWb @ (Ai @ (Sig[:, :, :24] @ model.U))    # (M, 24, 16)
    all_ok = nnz(ok) == M
    if not all_ok:
        DE[~ok] = 0.0
    try:
        lam, yv = np.linalg.eig(DE[:, :16])
    except np.linalg.LinAlgError:                     # non-finite entries: degenerate
        ok &= reduce_all(np.isfinite(DE), axis=(1, 2))
        all_ok = False
        DE[~ok] = 0.0
        lam, yv = np.linalg.eig(DE[:, :16])
    lam = lam.astype(complex, copy=False)             # real when every eigenvalue is
    yv = yv.astype(complex, copy=False)
    # the companion matrix's eigenvectors U y + Wo (lam + Mo) E y / (1 + lam^2)
    c = 1.0 / (1.0 + lam * lam)
    Ey = (DE[:, 16:] @ yv.view(float)).view(complex)  # (M, 8, 16), real BLAS products
    x = (model.UWW @ np.concatenate([yv, Ey * (lam * c)[:, None, :], Ey * c[:, None, :]],
                                    axis=1).view(float)).view(complex)       # (M, 24, 16)
    v = np.where((np.abs(lam) > 1.0)[:, None, :], x[:, 12:], x[:, :12])   # (M, 12, 16)
    return lam, v, ok, all_ok


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
        R35 = (Y[:, None, :] @ model.C35)[:, 0]        # per candidate (bits not batch-dependent)
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
    """``(AB (102,), STARTS (6,))``: rows of a gather whose two halves' product, flattened
    with each entry's real and imaginary parts side by side, summed over the segments that
    begin at ``STARTS``, gives ``sum lo hi``, ``sum lo^2``, ``sum hi^2`` over the pairs
    (x4^j x5^k, x4^(j+1) x5^k) (9 of them) and (x4^j x5^k, x4^j x5^(k+1)) (8), in the
    order cr4, cr5, lo4, lo5, hi4, hi5 (the real forms ``Re(conj(a) b)``)."""
    lo, hi = np.r_[_LO4, _LO5], np.r_[_HI4, _HI5]
    starts = 2 * np.cumsum([0] + [len(_LO4), len(_LO5)] * 3)[:6]     # 2 floats per entry
    return np.r_[lo, lo, hi, hi, lo, hi], starts


_RATIO_AB, _RATIO_STARTS = _ratio_maps()


def _ratio_angles(v):
    """``(theta_4, theta_5) (n, 2)`` with x = tan(theta / 2) from monomial vectors
    ``v (n, 12)`` (complex, entries x4^j x5^k at j * 3 + k, any common phase):
    least-squares ratios of consecutive entries (``x = sum lo hi / sum lo^2`` over the
    pairs (x4^j x5^k, x4^(j+1) x5^k), resp. (.., x4^j x5^(k+1)), with the real forms
    ``Re(conj(a) b)``), inverted when |x| > 1."""
    n = len(v)
    g = np.ascontiguousarray(v, dtype=complex).view(float).reshape(n, 12, 2).take(_RATIO_AB,
                                                                                   axis=1)
    # each candidate's sums on its own (a segment sum per row: no matrix product whose
    # kernel depends on the number of rows)
    f = np.add.reduceat((g[:, :51] * g[:, 51:]).reshape(n, 102), _RATIO_STARTS, axis=1)
    cr, dlo, dhi = f[:, 0:2], f[:, 2:4], f[:, 4:6]    # cr4, cr5, lo4, lo5, hi4, hi5
    return 2.0 * np.where(dlo >= dhi, np.arctan2(cr, dlo), np.arctan2(dhi, cr))


def split_clusters(v, phi, keep, Sig, pair_imag=PAIR_IMAG):
    """Better vectors for clustered eigenvalues, all clusters of all poses at once.

    Solutions that share the pivot angle (e.g. the two wrist flips of a spherical wrist when the
    pivot is an arm joint) give a multiple eigenvalue, often defective in the companion form: it
    splits by up to ~sqrt(eps) and eig's vectors are arbitrary mixtures, or nearly parallel. The
    mean of a cluster is accurate (Manocha & Canny 1994, sec. V-B), so each cluster of m eigenvalues
    (real parts of the angles within CLUSTER_TOL of the next; also a conjugate pair closer than
    ``pair_imag`` to the real axis, as rounding splits a double root, by ~sqrt(eps * condition), or
    a perturbed model, by ~sqrt(its size): a pair farther off is a complex root) gets the mean angle
    and, as its space, the m smallest right singular vectors ``N`` of ``Sigma`` there (see
    :func:`_subspace_vectors`). The cluster's own eigenvectors compete (they are right when its
    eigenvalues are distinct roots that merely lie close): of the 2m vectors, those within 1e-3 of a
    monomial vector are kept, and at least the m closest. The subspace vectors get the mean angle.

    A cluster is a chain (single linkage), so an exact multiple root may share it with distinct
    roots some 1e-4 rad away: the mean then misses the multiple root by that much, its eigenvectors
    are mixtures, and the solutions it stands for were lost. So each tight sub-cluster of a chain
    (:func:`_tight_subclusters`) also gets its own mean and subspace vectors, in a second set of
    extra slots (kept all; Newton drops what does not converge, and the merge what duplicates).

    Parameters
    ----------
    v, phi : ndarray (M, 12, n), (M, n) complex, the eigenvectors and their angles (rad)
    keep, Sig : ndarray (M, n) bool, the real candidates; (M, 12, 36) ``[C | B | A]`` per pose
    pair_imag : float, the largest |Im(phi)| (rad) of a conjugate pair that is treated

    Returns
    -------
    keep : ndarray (M, n) of bool, updated for the clusters' own vectors
    extra : None (no cluster: the common case) or ``(rows (P,), v2 (P, 12, w), phi2 (P, w),
        keep2 (P, w))`` for the P poses with a cluster, slot j of ``v2`` holding the subspace
        vector that goes with own slot j, and (``w = 2n`` when a chain has a tight sub-cluster,
        else ``w = n``) slot n + j that of its tight sub-cluster
    continuum : None (no cluster) or ndarray (M,) of bool, the poses with a cluster of which
        ``UNEXPLAINED`` eigenvalues lack a monomial vector, or a chain over 12: a continuum"""
    M, n = phi.shape
    key = np.where(keep, phi.real, _PAST[:n])     # past every angle, far apart (no inf - inf)
    sk = np.sort(key, axis=1)
    if not nnz(sk[:, 1:] - sk[:, :-1] < CLUSTER_TOL):
        return keep, None, None                          # no cluster (the common case)
    order, start, run, imag = _runs(key, sk, np.abs(phi.imag))
    # Sigma (12 x 12) has a null space at a cluster's mean only up to 12 wide: a longer chain
    # (a pencil all but singular, e.g. a perturbed robot at a degenerate pose) keeps its vectors
    treat = start & (run >= 2) & (run <= 12) & ((run > 2) | (imag < pair_imag))
    continuum = np.logical_or.reduce(start & (run > 12), axis=1)
    rows = np.flatnonzero(np.logical_or.reduce(treat, axis=1))
    if not len(rows):
        return keep, None, continuum
    at = np.zeros(M, int)
    at[rows] = np.arange(len(rows))                      # pose -> row of the extra slots
    sizes = np.flatnonzero(np.bincount(run[treat]))    # (not np.unique: it imports numpy.ma)
    tight = _tight_subclusters(phi, order, treat, run, sizes[sizes >= 3])
    w = 2 * n if tight else n
    v2 = np.zeros((len(rows), 12, w), complex)
    v2[:, 0] = 1.0
    phi2 = np.zeros((len(rows), w), complex)
    keep2 = np.zeros((len(rows), w), bool)
    for k in sizes:
        pg, j0 = np.nonzero(treat & (run == k))
        members = order[pg[:, None], j0[:, None] + np.arange(k)]       # (p, k) slots
        mean, sub = _subspace_vectors(phi, Sig, pg, members)
        sub = np.swapaxes(sub, 1, 2)                                    # (p, k, 12)
        both = np.concatenate([v[pg[:, None], :, members], sub], axis=1)   # own, sub (p, 2k, 12)
        res = _structure_residual(both.reshape(-1, 12)).reshape(-1, 2 * k)
        rank = np.argsort(np.argsort(res, axis=1, kind="stable"), axis=1, kind="stable")
        kept = (res < 1e-3) | (rank < k)
        keep[pg[:, None], members] = kept[:, :k]
        continuum[pg[k - nnz(res < 1e-3, axis=1) >= UNEXPLAINED]] = True
        pgk = at[pg][:, None]
        v2[pgk, :, members] = sub
        phi2[pgk, members] = mean[:, None]
        keep2[pgk, members] = kept[:, k:]
    for k, (pg, members) in tight.items():       # tight sub-clusters of chains: slots n + j
        mean, sub = _subspace_vectors(phi, Sig, pg, members)
        pgk, slots = at[pg][:, None], members + n
        v2[pgk, :, slots] = np.swapaxes(sub, 1, 2)
        phi2[pgk, slots] = mean[:, None]
        keep2[pgk, slots] = True
    return keep, (rows, v2, phi2, keep2), continuum


def _runs(key, sk, imag):
    """The runs of close neighbours (within CLUSTER_TOL) of the sorted ``key (M, n)`` (``sk``,
    sorted along its rows): the sort ``order (M, n)``, whether a run begins at a sorted
    position ``start (M, n)``, the size of the run at each ``run (M, n)`` and the largest
    ``imag (M, n)`` (any per-slot value) of its members."""
    M, n = key.shape
    order = np.argsort(key, axis=1)
    close = np.diff(sk, axis=1) < CLUSTER_TOL
    gid = np.concatenate([np.zeros((M, 1), int), np.cumsum(~close, axis=1)], axis=1)
    flat = (np.arange(M)[:, None] * n + gid).ravel()          # group id per sorted position
    size = np.bincount(flat, minlength=M * n)
    start = np.concatenate([np.ones((M, 1), bool), ~close], axis=1)
    top = np.zeros(M * n)
    np.maximum.at(top, flat, np.take_along_axis(imag, order, axis=1).ravel())
    return order, start, size[flat].reshape(M, n), top[flat].reshape(M, n)


#: a sub-cluster of a chain is tight when its diameter times this is below its distance to the
#: chain's other angles (complex plane) ...
TIGHT_RATIO = 10.0
#: ... and its distance to the rest exceeds this (rad): below, the pattern is rounding's
TIGHT_GAP = 1e-5
#: eigenvalues of one cluster without a monomial vector (own or subspace, within 1e-3) that
#: mark a continuum of solutions at its angle (a self-motion with the pivot fixed, e.g. two
#: joint axes lined up): Sigma's null space there holds a curve of monomial vectors, not one
#: per eigenvalue, the shift operators do not commute and the subspace vectors are mixtures,
#: so isolated solutions at that angle are lost. On special poses of yaskawa_hc10 and
#: fanuc_crx10ia such clusters have 8 to 12 eigenvalues, 4 to 11 of them unexplained; a
#: cluster of isolated roots leaves at most 2 (a complex pair in the chain).
UNEXPLAINED = 4


def _tight_subclusters(phi, order, start, run, sizes):
    """The tight sub-clusters of the clusters (runs) of ``sizes`` (each at least 3), by size.

    A proper sub-run (in sorted order, at least two) of a run is tight when ``TIGHT_RATIO``
    times its diameter is below its distance to the run's other angles, and that distance is
    above ``TIGHT_GAP``, both in the complex plane: the pattern of a multiple root split by
    rounding (equal angles to ~1e-13; a regular polygon of a defective one, e.g. a real angle
    and a conjugate pair) is not torn apart. Tight sub-runs are nested or disjoint; the largest
    ones are taken. Vectorised over the runs of a size (a Python loop only over the runs that
    have a tight sub-run: rare); a pose's sub-clusters depend on its angles alone.

    Parameters
    ----------
    phi : ndarray (M, n) complex, the angles (rad)
    order : ndarray (M, n) of int, the slots sorted by the real part of the angle
    start, run : ndarray (M, n), the first positions of the runs (sorted order) and their sizes
    sizes : the run sizes to look at

    Returns
    -------
    dict
        size m -> ``(pg (p,), members (p, m))``: poses and the slots of each sub-cluster.
    """
    found = {}
    for k in sizes:
        pg, j0 = np.nonzero(start & (run == k))
        x = phi[pg[:, None], order[pg[:, None], j0[:, None] + np.arange(k)]]      # (p, k)
        D = np.abs(x[:, :, None] - x[:, None, :]).reshape(len(pg), 1, k * k)
        lo, size, pair, cross = _subruns(k)
        diam = reduce_max(np.where(pair, D, 0.0), axis=2)                     # (p, subruns)
        gap = reduce_min(np.where(cross, D, np.inf), axis=2)
        for r in np.flatnonzero(np.logical_or.reduce((gap > TIGHT_GAP)
                                                     & (TIGHT_RATIO * diam < gap), axis=1)):
            taken = np.zeros(k, bool)
            for t in np.flatnonzero((gap[r] > TIGHT_GAP) & (TIGHT_RATIO * diam[r] < gap[r])):
                i, m = lo[t], size[t]                     # the largest first (sorted so)
                if not taken[i:i + m].any():
                    taken[i:i + m] = True
                    found.setdefault(m, []).append((pg[r], order[pg[r], j0[r] + i:j0[r] + i + m]))
    return {m: (np.array([sub[0] for sub in subs]), np.array([sub[1] for sub in subs]))
            for m, subs in sorted(found.items())}


@functools.lru_cache(maxsize=None)
def _subruns(k):
    """The proper sub-runs (at least two) of a run of k, the largest first: their first
    positions and sizes, and masks ``(subruns, k * k)`` of the pairs inside one and of the
    pairs (inside, outside)."""
    lo, size = zip(*[(i, m) for m in range(k - 1, 1, -1) for i in range(k - m + 1)])
    lo, size = np.array(lo), np.array(size)
    inner = (np.arange(k) >= lo[:, None]) & (np.arange(k) < (lo + size)[:, None])
    pair = (inner[:, :, None] & inner[:, None, :]).reshape(len(lo), k * k)
    cross = (inner[:, :, None] & ~inner[:, None, :]).reshape(len(lo), k * k)
    return lo, size, pair, cross


def _subspace_vectors(phi, Sig, pg, members):
    """The mean angle ``(p,)`` and monomial vectors ``(p, 12, k)`` of the clusters ``members
    (p, k)`` (eigenvalue slots) of poses ``pg (p,)``.

    At the mean, the k smallest right singular vectors ``N`` of ``Sigma`` span the space of the
    cluster's vectors; the true vectors ``v = N c`` are those of monomials, so ``c`` is a common
    eigenvector of the shift operators "multiply by x4" (``v[j+1, k] = x4 v[j, k]``) and "multiply
    by x5"; these k x k operators come from least squares on the Moebius-shifted form
    ``(Hi - t Lo) c = z (Lo + t Hi) c`` (finite even at x = infinity), and a fixed combination of
    the two is diagonalised."""
    k = members.shape[1]
    mean = reduce_sum(phi.real[pg[:, None], members], axis=1) / k
    y = np.tan(mean / 2.0)
    small = (np.abs(y) <= 1.0)[:, None, None]
    with np.errstate(all="ignore"):
        w = np.where(small[:, 0, 0], 0.0, 1.0 / y)[:, None, None]
    yy = np.where(small[:, 0, 0], y, 0.0)[:, None, None]
    Sp = Sig[pg]
    Cm, Bm, Am = Sp[:, :, :12], Sp[:, :, 12:24], Sp[:, :, 24:]
    S = np.where(small, (Am * yy + Bm) * yy + Cm, Am + (Bm + Cm * w) * w)
    Nsub = np.swapaxes(np.linalg.svd(S)[2][:, -k:, :], -1, -2)     # (p, 12, k)
    # both operators' least squares in one pseudo-inverse: (p, 2, 9, k), x5's padded with
    # a zero row (row 12 of the extended Nsub)
    Next = np.concatenate([Nsub, np.zeros((len(pg), 1, k))], axis=1)
    lo, hi = Next[:, _SHIFT_LO], Next[:, _SHIFT_HI]
    ops = np.linalg.pinv(lo + _TAU * hi, rcond=_SHIFT_RCOND) @ (hi - _TAU * lo)    # (p, 2, k, k)
    Mop = ops[:, 0] + 0.6180339887 * ops[:, 1]
    return mean, Nsub @ np.linalg.eig(Mop)[1]                       # (p, 12, k)


# the pairs (lo, hi) of the shift operators "multiply by x4" (9) and "by x5" (8, padded with
# the zero row 12), and their pseudo-inverses' cut-offs
_SHIFT_LO = np.array([_LO4, np.r_[_LO5, 12]])
_SHIFT_HI = np.array([_HI4, np.r_[_HI5, 12]])
_SHIFT_RCOND = np.finfo(float).eps * np.array([len(_LO4), len(_LO5)])


#: the sort key of a slot that is not a candidate: beyond pi, 10 apart
_PAST = 10.0 * np.arange(1, 33)


def _structure_residual(V):
    """Sine of the angle between each row of ``V (n, 12)`` and the nearest monomial vector."""
    R = (V / V[np.arange(len(V)), np.argmax(np.abs(V), axis=1)][:, None]).real
    h = _ratio_angles(R) / 2.0                                          # (n, 2)
    c, s = np.cos(h), np.sin(h)
    # x4^j x5^k times cos^3(h4) cos^2(h5) (entry j * 3 + k): bounded also at x = infinity
    W = (c[:, :1] ** (3 - _J4) * s[:, :1] ** _J4) * (c[:, 1:] ** (2 - _J5) * s[:, 1:] ** _J5)
    cos = np.abs(reduce_sum(R * W, axis=1)) / np.sqrt(reduce_sum(R * R, axis=1)
                                                      * reduce_sum(W * W, axis=1))
    return np.sqrt(np.maximum(0.0, 1.0 - cos * cos))
