"""Forward kinematics on a :class:`~kincalc.chain.Chain`, vectorised over poses.

There is one chain product, ``F_0 J_1(q_1) F_1 ... J_n(q_n) F_n``, evaluated in one of two
layouts chosen by the number of configurations:

* **the column walk** (:func:`_walk`, many configurations): the running pose is kept as
  three column vectors and a position, each of shape ``(3, N)``. A joint rotation mixes two
  columns, a joint translation shifts the position along the z column, and a constant
  ``F_i`` is applied as a sparse linear combination that skips its zero entries and does
  not multiply by +-1 (DH links are mostly permutations and sign flips). Every operation is
  elementwise along the configurations, so a configuration's bits do not depend on how many
  are walked together (the general 6R solver's Newton steps rely on that:
  ``column_walk=True`` of :func:`entry_frames` walks any number). Poses are processed in
  cache-sized chunks.
* **stacked 4x4 products** (up to :data:`FEW` configurations: a single ``robot.fk(q)``, an
  IK call's candidates): all joint motions from one product of ``[cos x, sin x, x, 1]``
  with the chain's :attr:`~kincalc.chain.Chain.motion_basis`, then one matrix product per
  joint (:func:`_prefixes`). That costs a fixed ~n + 10 numpy calls where the walk costs
  ~10 per joint; the two agree to rounding (tests/evaluation/test_fk.py).

Units: rad and m (or the robot's own unit for unitless robots).
"""

from __future__ import annotations

import numpy as np

#: poses per chunk: large enough to amortise Python overhead, small enough
#: for the working set (~30 arrays of CHUNK doubles) to stay in cache.
CHUNK = 8192

#: up to this many configurations the chain is evaluated by multiplying stacked 4x4
#: matrices (about n + 10 numpy calls, ~15 us for one configuration of a 6-joint arm);
#: above it, by the column walk (~10 numpy calls per joint, each on all configurations:
#: four times faster for thousands).
FEW = 32


def _combine(cols, terms):
    """``sum_k c_k cols[k]`` over the ``terms (k, c_k)`` (nonzero), in their order, without
    multiplying by +-1 (``a + (-v)`` is ``a - v`` exactly); ``None`` when there is none."""
    acc = None
    for k, c in terms:
        v = cols[k]
        if acc is None:
            acc = v if c == 1.0 else (-v if c == -1.0 else c * v)
        elif c == 1.0:
            acc = acc + v
        elif c == -1.0:
            acc = acc - v
        else:
            acc = acc + c * v
    return acc


def _apply_fixed(cols, p, terms):
    """Post-multiply the running pose ``[cols | p]`` by a constant transform, given by its
    nonzero entries ``terms`` (:attr:`~kincalc.chain.Chain.fixed_terms`)."""
    new_cols = []
    for j in range(3):
        c = _combine(cols, terms[j])
        new_cols.append(c if c is not None else 0.0 * cols[0])
    shift = _combine(cols, terms[3])
    return new_cols, (p if shift is None else p + shift)


def _start(F0, size):
    cols = [np.repeat(F0[:3, j, None], size, axis=1) for j in range(3)]
    p = np.repeat(F0[:3, 3, None], size, axis=1)
    return cols, p


def _walk(chain, c, s, x, frames=None):
    """The column walk over ``M`` configurations; returns the tool pose ``(cols, p)``.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``.
    c, s : ndarray (n, M), or sequences of n rows (M,)
        Joint-major cosines and sines of the revolute joints' angles, offsets included
        (``x = q_i + c_i``). Rows of prismatic joints: any finite values.
    x : ndarray (n, M), or a sequence of n rows (M,)
        The prismatic joints' travel, offsets included (m). Rows of revolute joints: any
        finite values.
    frames : ndarray (3, 4, n + 1, M) or (3, 2, n + 1, M), optional
        Receives each joint's frame just after its motion and the tool pose, entry by entry
        (the layout of :func:`entry_frames`), or their last two columns (axis, origin).

    Returns
    -------
    cols : list of three ndarray (3, M)
        The columns of the rotation of ``T_world_tool``.
    p : ndarray (3, M)
        Its position, world frame (m).
    """
    cols, p = _start(chain.fixed[0], len(x[0]))
    terms = chain.fixed_terms
    for i in range(chain.dof):
        if chain.revolute[i]:
            c0, c1 = cols[0], cols[1]
            cols = [c0 * c[i] + c1 * s[i], c1 * c[i] - c0 * s[i], cols[2]]
        else:
            p = p + cols[2] * x[i]
        if frames is not None:
            _put(frames, i, cols, p)
        cols, p = _apply_fixed(cols, p, terms[i + 1])
    if frames is not None:
        _put(frames, chain.dof, cols, p)
    return cols, p


def _put(frames, i, cols, p) -> None:
    """Frame ``i`` of ``frames (3, 4, n + 1, M)`` from its columns and origin ``(3, M)``; of
    ``frames (3, 2, n + 1, M)`` its last two, the axis (column 2) and the origin."""
    first = 4 - frames.shape[1]
    for j in range(first, 3):
        frames[:, j - first, i] = cols[j]
    frames[:, -1, i] = p


def _angles(chain, flat) -> tuple:
    """``(cos x, sin x, x)`` of ``x = q_i + c_i`` (offsets added) for ``flat (M, n)``, each
    joint-major ``(n, M)`` (the arguments of :func:`_walk`)."""
    x = np.ascontiguousarray((flat + chain.offset).T)
    return np.cos(x), np.sin(x), x


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


def forward_kinematics(chain, q, *, column_walk: bool = False) -> np.ndarray:
    """Tool pose ``T_world_tool`` of shape ``(..., 4, 4)`` for ``q (..., n)``.

    Parameters
    ----------
    chain : Chain
        From ``robot.chain``; includes the robot's base and tool transforms.
    q : array_like (..., n)
        Joint values: rad for revolute, m for prismatic joints.
    column_walk : bool
        The column walk for any number of configurations: each one's bits then do not
        depend on how many are evaluated together.

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
    if N <= FEW and not column_walk:
        P = _prefixes(chain, _motions(chain, _coefficients(chain, flat)))
        return P[-1].reshape(q.shape[:-1] + (4, 4))
    out = np.zeros((N, 4, 4))
    out[:, 3, 3] = 1.0
    for start in range(0, N, CHUNK):
        sl = slice(start, min(start + CHUNK, N))
        cols, p = _walk(chain, *_angles(chain, flat[sl]))
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


def _prefixes(chain, motions):
    """The chain's prefix products by stacked 4x4 products, joint-major ``(n + 1, N, 4, 4)``,
    from the joint motions ``(n, N, 4, 4)`` of :func:`_motions` (each product on contiguous
    stacks): ``P_0 = F_0`` and ``P_i = P_{i-1} J_i F_i``, so that ``P_n`` is the tool pose
    ``T_world_tool`` (world frame, m). The links ``J_i F_i`` of all configurations are one
    product per joint (their motions stacked as the rows of one matrix)."""
    n, N = motions.shape[:2]
    links = (motions.reshape(n, 4 * N, 4) @ chain.fixed[1:]).reshape(n, N, 4, 4)
    P = np.empty((n + 1, N, 4, 4))
    P[0] = chain.fixed[0]
    for i in range(n):
        np.matmul(P[i], links[i], out=P[i + 1])
    return P


def tool_from_cs(chain, c, s, x, frames=None):
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
    frames : ndarray (3, 4, n + 1, M) or (3, 2, n + 1, M), optional
        For more than :data:`FEW` configurations: receives every joint's frame and the tool
        pose, entry by entry (the layout of :func:`entry_frames`), or their last two columns
        (axis, origin: what a Jacobian needs).

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
    c, s = list(c), list(s)              # the offsets turned in, without trigonometry
    for i in np.flatnonzero(chain.revolute & (chain.offset != 0.0)).tolist():
        c[i], s[i] = c[i] * co[i] - s[i] * so[i], s[i] * co[i] + c[i] * so[i]
    x = x + chain.offset[:, None]
    if M > FEW:
        return _walk(chain, c, s, x, frames)
    coef = np.empty((4, M, chain.dof))
    coef[0], coef[1], coef[2], coef[3] = np.transpose(c), np.transpose(s), x.T, 1.0
    T = _prefixes(chain, _motions(chain, coef))[-1]
    return [T[:, :3, j].T for j in range(3)], T[:, :3, 3].T


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


def entry_frames(chain, q, *, coefficients: bool = False, column_walk: bool = False):
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
    column_walk : bool
        The column walk for any number of configurations: each one's bits then do not
        depend on how many are evaluated together.

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
    if N <= FEW and not column_walk:
        coef = _coefficients(chain, flat)
        motions = _motions(chain, coef)
        P = _prefixes(chain, motions)
        out[:, :, :n] = (P[:-1] @ motions)[:, :, :3].transpose(2, 3, 0, 1)
        out[:, :, n] = P[-1, :, :3].transpose(1, 2, 0)
        return (out, coef[:3]) if coefficients else out
    coef = np.empty((3, n, N))                    # joint-major cos x, sin x, x
    for start in range(0, N, CHUNK):
        sl = slice(start, min(start + CHUNK, N))
        coef[:, :, sl] = _angles(chain, flat[sl])
        _walk(chain, *coef[:, :, sl], frames=out[..., sl])
    return (out, coef.transpose(0, 2, 1)) if coefficients else out
