"""Forward kinematics on a :class:`~kincalc.chain.Chain`, vectorised over poses.

The chain ``F_0 J_1(q_1) F_1 ... J_n(q_n) F_n`` is evaluated column-wise on
structure-of-arrays data: the running pose is kept as three column vectors
and a position, each of shape ``(3, N)``. A joint rotation mixes two
columns, a joint translation shifts the position along the z column, and a
constant ``F_i`` is applied as a sparse linear combination that skips its
zero entries and does not multiply by +-1 (DH links are mostly permutations
and sign flips). Poses are processed in cache-sized chunks.

For a few configurations (up to :data:`FEW`: a single ``robot.fk(q)``, an IK call's
candidates) the same product is taken as stacked 4x4 matrices instead: all joint
motions from one product of ``[cos x, sin x, x, 1]`` with the chain's
:attr:`~kincalc.chain.Chain.motion_basis`, then one matrix product per joint
(:func:`prefixes_few`). That costs a fixed ~n + 10 numpy calls where the walk costs
~10 per joint. Units: rad and m (or the robot's own unit for unitless robots).
"""

from __future__ import annotations

import numpy as np

#: poses per chunk: large enough to amortise Python overhead, small enough
#: for the working set (~30 arrays of CHUNK doubles) to stay in cache.
CHUNK = 8192

#: up to this many configurations the chain is evaluated by multiplying stacked 4x4
#: matrices (:func:`prefixes_few`: about n + 10 numpy calls, ~15 us for one configuration
#: of a 6-joint arm); above it, by the column-wise walk (~10 numpy calls per joint, each
#: on all configurations: four times faster for thousands). Both evaluate the same
#: product F_0 J_1 F_1 ... J_n F_n; tests/evaluation/test_fk.py checks them against each other.
FEW = 32


def _combine(cols, coeffs):
    """``sum_k coeffs[k] * cols[k]`` skipping zero coefficients; ``None`` if all zero."""
    acc = None
    for c, v in zip(coeffs, cols):
        if c == 0.0:
            continue
        term = v if c == 1.0 else (-v if c == -1.0 else c * v)
        acc = term if acc is None else acc + term
    return acc


def _apply_fixed(cols, p, F):
    """Post-multiply the running pose ``[cols | p]`` by the constant transform ``F``."""
    new_cols = []
    for j in range(3):
        c = _combine(cols, F[:3, j])
        new_cols.append(c if c is not None else 0.0 * cols[0])
    shift = _combine(cols, F[:3, 3])
    return new_cols, (p if shift is None else p + shift)


def _start(F0, size):
    cols = [np.repeat(F0[:3, j, None], size, axis=1) for j in range(3)]
    p = np.repeat(F0[:3, 3, None], size, axis=1)
    return cols, p


def _move(chain, i, cols, p, x):
    """Post-multiply the running pose by joint i's motion ``J_i(x)`` (x already offset)."""
    if chain.revolute[i]:
        c, s = np.cos(x), np.sin(x)
        c0, c1 = cols[0], cols[1]
        return [c0 * c + c1 * s, c1 * c - c0 * s, cols[2]], p
    return cols, p + cols[2] * x


def walk(chain, q, on_joint=None):
    """Run the chain over ``q (N, n)``; return the final ``(cols, p)``.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : ndarray (N, n)
        Joint values, rad / m (a float array, not checked: see :func:`joint_batch`).
    on_joint : callable, optional
        ``on_joint(i, cols, p)`` is called with the frame just before joint i's
        motion (whose z column is joint i's axis in the world frame, and whose origin
        ``p (3, N)`` is on that axis).

    Returns
    -------
    cols : list of three ndarray (3, N)
        The columns of the rotation of ``T_world_tool``.
    p : ndarray (3, N)
        Its position, world frame (m).
    """
    F = chain.fixed
    cols, p = _start(F[0], q.shape[0])
    qq = q + chain.offset
    for i in range(chain.dof):
        if on_joint is not None:
            on_joint(i, cols, p)
        cols, p = _move(chain, i, cols, p, qq[:, i])
        cols, p = _apply_fixed(cols, p, F[i + 1])
    return cols, p


def joint_batch(chain, q):
    """Joint values as a float array and flattened to one batch dimension.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (..., n)
        Joint values, rad / m.

    Returns
    -------
    q : ndarray (..., n)
        ``q`` as floats.
    flat : ndarray (N, n)
        The same values, ``N`` the product of the leading dimensions.

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    q = np.asarray(q, dtype=float)
    if q.ndim == 0 or q.shape[-1] != chain.dof:
        raise ValueError(f"expected joint values of shape (..., {chain.dof}), got {q.shape}")
    return q, q.reshape(-1, chain.dof)


def forward_kinematics(chain, q) -> np.ndarray:
    """Tool pose ``T_world_tool`` of shape ``(..., 4, 4)`` for ``q (..., n)``.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``; includes the robot's base and tool transforms.
    q : array_like (..., n)
        Joint values: rad for revolute, m for prismatic joints.

    Returns
    -------
    ndarray (..., 4, 4)
        Pose of the tool frame in the world frame (m).

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    q, flat = joint_batch(chain, q)
    N = flat.shape[0]
    if N <= FEW:
        P = _prefixes(chain, _motions(chain, _coefficients(chain, flat)))
        return P[-1].reshape(q.shape[:-1] + (4, 4))
    out = np.zeros((N, 4, 4))
    out[:, 3, 3] = 1.0
    for start in range(0, N, CHUNK):
        sl = slice(start, min(start + CHUNK, N))
        cols, p = walk(chain, flat[sl])
        for j in range(3):
            out[sl, :3, j] = cols[j].T
        out[sl, :3, 3] = p.T
    return out.reshape(q.shape[:-1] + (4, 4))


def _coefficients(chain, flat) -> np.ndarray:
    """``(4, N, n)``: each joint's ``[cos x, sin x, x, 1]`` for ``flat (N, n)``, with
    ``x = q_i + c_i`` (the coefficients of :attr:`~kincalc.chain.Chain.motion_basis`)."""
    N, n = flat.shape
    coef = np.empty((4, N, n))
    x = np.add(flat, chain.offset, out=coef[2])
    np.cos(x, out=coef[0])
    np.sin(x, out=coef[1])
    coef[3] = 1.0
    return coef


def _motions(chain, coef) -> np.ndarray:
    """The joint motions ``J_i`` of ``coef (4, N, n)`` (:func:`_coefficients`), joint-major:
    ``(n, N, 4, 4)``, one product with :attr:`~kincalc.chain.Chain.motion_basis`."""
    _, N, n = coef.shape
    return (coef.T[:, :, None, :] @ chain.motion_basis[:, None]).reshape(n, N, 4, 4)


def prefixes_few(chain, flat):
    """The chain's prefix products, by stacked 4x4 products.

    For a few configurations (any number gives the right answer).

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    flat : ndarray (N, n)
        Joint values, rad / m (not checked: see :func:`joint_batch`).

    Returns
    -------
    ndarray (n + 1, N, 4, 4)
        ``P``, joint-major, world frame (m): ``P_0 = F_0`` and ``P_i = P_{i-1} J_i F_i``, so
        that ``P_{i-1}`` is the frame just before joint i's motion (its z column joint i's
        axis, its origin on that axis) and ``P_n`` the tool pose ``T_world_tool``.
    """
    return _prefixes(chain, _motions(chain, _coefficients(chain, flat)))


def _prefixes(chain, motions):
    """The prefixes of :func:`prefixes_few`, joint-major ``(n + 1, N, 4, 4)``, from the joint
    motions ``(n, N, 4, 4)`` of :func:`_motions` (each product on contiguous stacks)."""
    n, N = motions.shape[:2]
    links = motions @ chain.fixed[1:, None]
    P = np.empty((n + 1, N, 4, 4))
    P[0] = chain.fixed[0]
    for i in range(n):
        np.matmul(P[i], links[i], out=P[i + 1])
    return P


def tool_from_cs(chain, c, s, x):
    """Tool poses from each joint's cosine and sine (revolute) or travel (prismatic).

    For checking IK candidates whose angles are known by their cosines and sines.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    c, s : ndarray (n, M)
        Joint-major cosines and sines of the revolute joints' values, joint offsets not
        applied (IK's solvers give joint values without them; the chain's offsets are
        turned in here, without trigonometry). Rows of prismatic joints: any finite values.
    x : ndarray (n, M)
        The prismatic joints' travel (m), offsets not applied. Rows of revolute joints:
        any finite values.

    Returns
    -------
    cols : list of three ndarray (3, M)
        The columns of the rotation of ``T_world_tool`` (structure of arrays, as
        :func:`forward_kinematics` walks it).
    p : ndarray (3, M)
        Its position, world frame (m).
    """
    M = c.shape[1]
    co, so = chain.offset_cos_sin
    if M <= FEW:
        coef = np.empty((4, M, chain.dof))
        coef[0] = (c * co[:, None] - s * so[:, None]).T
        coef[1] = (s * co[:, None] + c * so[:, None]).T
        coef[2] = x.T + chain.offset
        coef[3] = 1.0
        T = _prefixes(chain, _motions(chain, coef))[-1]
        return [T[:, :3, j].T for j in range(3)], T[:, :3, 3].T
    F = chain.fixed
    cols, p = _start(F[0], M)
    for i in range(chain.dof):
        if chain.revolute[i]:
            ci, si = c[i], s[i]
            if chain.offset[i] != 0.0:
                ci, si = ci * co[i] - si * so[i], si * co[i] + ci * so[i]
            c0, c1 = cols[0], cols[1]
            cols = [c0 * ci + c1 * si, c1 * ci - c0 * si, cols[2]]
        else:
            p = p + cols[2] * (x[i] + chain.offset[i])
        cols, p = _apply_fixed(cols, p, F[i + 1])
    return cols, p


def frame_columns(chain, q) -> list:
    """The frames of :func:`chain_frames` as a structure of arrays.

    For many configurations this is several times faster than the ``(M, n, 4, 4)``
    stack, which it never builds.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (M, n)
        Joint values, rad / m (any leading shape, flattened to ``(M, n)``).

    Returns
    -------
    list of n tuples ``(cols, p)``
        Per joint, its frame's rotation columns ``cols`` (three arrays ``(3, M)``; the
        z column is the joint's axis) and origin ``p (3, M)``, world frame, m.
    """
    q = np.asarray(q, dtype=float)
    if q.shape[-1:] != (chain.dof,):
        raise ValueError(f"expected joint values of shape (..., {chain.dof}), got {q.shape}")
    q = q.reshape(-1, chain.dof)
    if len(q) <= FEW:
        return columns_of(chain_frames(chain, q))
    F = chain.fixed
    qq = q + chain.offset
    cols, p = _start(F[0], q.shape[0])
    out = []
    for i in range(chain.dof):
        cols, p = _move(chain, i, cols, p, qq[:, i])
        out.append((cols, p))
        cols, p = _apply_fixed(cols, p, F[i + 1])
    return out


def columns_of(frames) -> list:
    """Stacked frames as the structure of arrays of :func:`frame_columns`.

    Parameters
    ----------
    frames : ndarray (M, n, 4, 4)
        Poses, e.g. those of :func:`chain_frames`.

    Returns
    -------
    list of n tuples ``(cols, p)``
        Per frame, its rotation columns (three ``(3, M)``) and origin ``(3, M)``, all
        views into ``frames``.
    """
    return [([frames[:, i, :3, j].T for j in range(3)], frames[:, i, :3, 3].T)
            for i in range(frames.shape[1])]


def chain_frames(chain, q) -> np.ndarray:
    """World poses of the frames just after each joint's motion.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (..., n)
        Joint values, rad / m.

    Returns
    -------
    ndarray (..., n, 4, 4)
        Frame i is ``F_0 J_1 F_1 ... F_{i-1} J_i(q_i)`` in the world frame (m): its z axis
        is joint i's axis and it moves with link i.

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    return frames_and_tool(chain, q)[0]


def frames_and_tool(chain, q):
    """The joint frames and the tool pose from one evaluation of the chain.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (..., n)
        Joint values, rad / m.

    Returns
    -------
    frames : ndarray (..., n, 4, 4)
        The frames of :func:`chain_frames` (world frame, m).
    tool : ndarray (..., 4, 4)
        ``T_world_tool``, as :func:`forward_kinematics` gives it.

    Raises
    ------
    ValueError
        ``q`` is a scalar or its last axis is not ``n`` long.
    """
    q, flat = joint_batch(chain, q)
    N, n = flat.shape
    lead = q.shape[:-1]
    A = entry_frames(chain, flat)                                  # (3, 4, n + 1, N)
    out = np.zeros((N, n + 1, 4, 4))
    out[..., :3, :] = A.transpose(3, 2, 0, 1)
    out[..., 3, 3] = 1.0
    return out[:, :n].reshape(lead + (n, 4, 4)), out[:, n].reshape(lead + (4, 4))


def entry_frames(chain, q, *, coefficients: bool = False):
    """The joint frames and the tool pose, entry by entry: each entry of every frame of every
    configuration in one array, so that a vector of the frames (an axis, an origin) is a
    ``(3, M)`` block and the same vector of all frames a ``(3, n + 1, M)`` one.

    The frames of :func:`frames_and_tool` (the same numbers): stacked 4x4 products for up to
    :data:`FEW` configurations, the column walk beyond.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    q : array_like (M, n)
        Joint values, rad / m.
    coefficients : bool
        Also return each joint's ``cos x, sin x, x`` with ``x = q_i + c_i`` (its offset
        added), ``(3, M, n)``.

    Returns
    -------
    ndarray (3, 4, n + 1, M)
        ``A[r, c, i, m]``: row r, column c of frame i of configuration m (world frame, m): the
        frames of :func:`chain_frames` for ``i < n`` (column 2 joint i's axis, column 3 a
        point on it), the tool pose ``T_world_tool`` for ``i = n``. The bottom rows (0 0 0 1)
        are left out. With ``coefficients``, ``(A, coefficients)``.

    Raises
    ------
    ValueError
        ``q`` is not of shape ``(M, n)``.
    """
    q, flat = joint_batch(chain, q)
    if q.ndim != 2:
        raise ValueError(f"expected joint values of shape (M, {chain.dof}), got {q.shape}")
    N, n = flat.shape
    out = np.empty((3, 4, n + 1, N))
    if N <= FEW:
        coef = _coefficients(chain, flat)
        motions = _motions(chain, coef)
        P = _prefixes(chain, motions)
        out[:, :, :n] = (P[:-1] @ motions)[:, :, :3].transpose(2, 3, 0, 1)
        out[:, :, n] = P[-1, :, :3].transpose(1, 2, 0)
        return (out, coef[:3]) if coefficients else out
    if coefficients:
        qq = flat + chain.offset
        return entry_frames(chain, flat), np.stack((np.cos(qq), np.sin(qq), qq))
    F = chain.fixed
    for start in range(0, N, CHUNK):
        sl = slice(start, min(start + CHUNK, N))
        qq = flat[sl] + chain.offset
        cols, p = _start(F[0], len(qq))
        for i in range(n + 1):
            if i < n:
                cols, p = _move(chain, i, cols, p, qq[:, i])
            for j in range(3):
                out[:, j, i, sl] = cols[j]
            out[:, 3, i, sl] = p
            if i < n:
                cols, p = _apply_fixed(cols, p, F[i + 1])
    return out

