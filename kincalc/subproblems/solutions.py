"""The one return type of the subproblems: a solution set per problem of a batch.

IK-Geo's subproblems return their solutions with a least-squares flag; here every
subproblem solves a whole batch of problems (inputs with any leading shape ``...``)
and returns a :class:`Solutions` with a fixed number ``k`` of slots per problem:

* ``theta``: a tuple with one array ``(..., k)`` per unknown angle (rad, in
  (-pi, pi]); ``c`` and ``s`` their cosines and sines, obtained from the algebra
  (a family solver composes rotations from them without calling trigonometry);
* ``ok (..., k)``: the slot holds an answer (a problem with one solution fills one
  slot; a double root fills one);
* ``exact (..., k)``: the answer solves the equations (else it is the least-squares
  answer the module describes);
* ``free (..., k)``: the problem is ill-posed there: an angle is undetermined (a
  point on the axis, ...) and the answer shows one representative, 0;
* ``undetermined``: for a subproblem that knows it, which angle that is: one mask
  ``(..., k)`` per unknown (within ``free``); None: every angle of a free slot.

Slots that are not ``ok`` hold finite numbers (0) that mean nothing. The arrays are
not to be modified: a mask that is True everywhere is one shared read-only array.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..spatial import LEVI_CIVITA

@dataclass(frozen=True, init=False)
class Solutions:
    """The solutions of one subproblem for a batch of problems (see the module).

    Attributes
    ----------
    theta : tuple of ndarray (..., k)
        One array per unknown angle, rad, in (-pi, pi].
    c, s : tuple of ndarray (..., k)
        Cosines and sines of ``theta``, in the same order.
    ok : ndarray (..., k) of bool
        The slot holds an answer; slots that are not ``ok`` hold meaningless finite numbers.
    exact : ndarray (..., k) of bool
        The answer solves the equations; else it is the solver's least-squares answer.
    free : ndarray (..., k) of bool
        The problem is ill-posed there (an angle undetermined, a continuum of answers):
        the slot shows one representative.
    undetermined : tuple of ndarray (..., k) of bool, or None
        Per unknown, the free slots where its angle is undetermined; None when the
        subproblem does not tell (every angle of a free slot).
    """

    theta: tuple
    c: tuple
    s: tuple
    ok: np.ndarray
    exact: np.ndarray
    free: np.ndarray
    undetermined: tuple | None

    def __init__(self, theta, c, s, ok, exact, free, undetermined=None):
        # the fields set directly (a frozen dataclass's __init__ sets each through
        # object.__setattr__, twice as slow; every subproblem call makes one)
        d = self.__dict__
        d["theta"], d["c"], d["s"], d["ok"], d["exact"], d["free"] = theta, c, s, ok, exact, free
        d["undetermined"] = undetermined

    @property
    def slots(self) -> int:
        """The number ``k`` of solution slots per problem.

        Returns
        -------
        int
            The length of the last axis of ``ok``.
        """
        return self.ok.shape[-1]

    def negated(self, i: int = 0) -> "Solutions":
        """These solutions with unknown ``i``'s angle negated: the answer for ``R(k, -x)``
        of a subproblem solved for ``R(k, x)`` (cosines kept, sines negated).

        Parameters
        ----------
        i : int
            The unknown (0-based).

        Returns
        -------
        Solutions
            The same masks; ``theta[i]`` and ``s[i]`` negated.
        """
        flip = lambda t: tuple(-x if j == i else x for j, x in enumerate(t))  # noqa: E731
        return Solutions(flip(self.theta), self.c, flip(self.s), self.ok, self.exact,
                         self.free, self.undetermined)

    def ordered(self) -> "Solutions":
        """These solutions with each problem's slots in ascending order of their angles
        (the first unknown's, ties to 1e-9 rad broken by the next; -pi counts as pi), the
        slots that are not ``ok`` last: an order that depends on the answers alone, not on how the solver found
        them (a "root k" label is then the same for the same robot in any convention).

        Returns
        -------
        Solutions
            The same answers and masks, the slots permuted along the last axis.
        """
        # an angle within 1e-9 of -pi is pi (the same root, rounded across the wrap)
        near = [np.where(t < -np.pi + 1e-9, t + 2 * np.pi, t) for t in self.theta]
        keys = [np.round(t / 1e-9) for t in reversed(near)] + [~self.ok]
        order = np.lexsort(keys, axis=-1)
        take = lambda t: tuple(np.take_along_axis(x, order, -1) for x in t)  # noqa: E731
        ok, exact, free = take((self.ok, self.exact, self.free))
        which = None if self.undetermined is None else take(self.undetermined)
        return Solutions(take(self.theta), take(self.c), take(self.s), ok, exact, free, which)

    def rows(self, index=()) -> list:
        """The answers of one problem as a list of tuples of angles, for reading and testing.

        Parameters
        ----------
        index : int or tuple
            A full index into the leading shape ``...``, selecting one problem; the default
            ``()`` only for an unbatched result (empty leading shape).

        Returns
        -------
        list of tuple of float
            ``[(theta1, theta2, ...), ...]`` (rad), one tuple per ``ok`` slot, in slot
            order; exact, least-squares and free answers alike.
        """
        ok = self.ok[index]
        return [tuple(float(t[index][j]) for t in self.theta) for j in np.flatnonzero(ok)]


def principal(theta) -> np.ndarray:
    """Angles from ``arctan2`` in (-pi, pi]: ``-pi`` becomes ``pi``.

    ``arctan2`` gives ``-pi`` for a sine of -0 or of -1e-17 with a cosine of -1.

    Parameters
    ----------
    theta : array_like (...)
        Angles in [-pi, pi] (rad).

    Returns
    -------
    ndarray (...)
        The same angles in (-pi, pi]; only values equal to ``-pi`` change.
    """
    at = theta == -np.pi
    return np.where(at, np.pi, theta) if np.count_nonzero(at) else theta


def angles(c, s) -> tuple:
    """The angle of one unknown with its cosine and sine, from an unnormalised direction.

    Parameters
    ----------
    c, s : ndarray (..., k)
        Unnormalised cosine and sine parts: a direction in the plane, of any length
        (the shapes broadcast).

    Returns
    -------
    theta : ndarray (..., k)
        ``atan2(s, c)`` in rad, in (-pi, pi]; 0 where ``(c, s)`` is the zero vector.
    c, s : ndarray (..., k)
        The normalised cosine and sine of ``theta`` (1 and 0 for the zero vector).
    """
    return direction(c, s)[:3]


def direction(c, s) -> tuple:
    """:func:`angles` and where the direction was the zero vector.

    Parameters
    ----------
    c, s : ndarray (..., k)
        As :func:`angles`.

    Returns
    -------
    theta, c, s : ndarray (..., k)
        As :func:`angles`.
    zero : ndarray (..., k) of bool
        ``(c, s)`` was exactly ``(0, 0)`` (its length ``hypot(c, s)`` is 0 there only):
        ``theta = 0``, cosine 1, sine 0.
    """
    n = np.hypot(c, s)
    zero = n == 0.0
    if np.count_nonzero(zero):
        n = np.where(zero, 1.0, n)
        cn, sn = np.where(zero, 1.0, c / n), np.where(zero, 0.0, s / n)
    else:
        cn, sn = c / n, s / n
    return principal(np.arctan2(sn, cn)), cn, sn, zero


@lru_cache(maxsize=64)
def true_mask(shape: tuple) -> np.ndarray:
    """A read-only array of ``shape`` that is True everywhere, shared: the mask of a
    subproblem's slots that always hold an (exact) answer.

    Parameters
    ----------
    shape : tuple of int

    Returns
    -------
    ndarray of bool, read-only
    """
    out = np.ones(shape, bool)
    out.flags.writeable = False
    return out


#: ``(+1, -1)``: the signs of the two roots ``base +- delta`` (a product with it is exact)
_PLUS_MINUS = np.array([1.0, -1.0])


def two_roots(cb, sb, cd, sd) -> tuple:
    """The roots ``base + delta`` and ``base - delta`` from the cosines and sines of ``base``
    and ``delta``, without trigonometry but the angles' ``arctan2``.

    The cosines and sines of ``base +- delta`` by the addition theorems; ``+-sd`` is one
    product with ``(1, -1)`` (exact), so both slots are computed at once.

    Parameters
    ----------
    cb, sb : ndarray (...)
        Cosine and sine of ``base``.
    cd, sd : ndarray (...)
        Cosine and sine (>= 0) of ``delta``; all four shapes broadcast.

    Returns
    -------
    theta : ndarray (..., 2)
        ``base + delta`` and ``base - delta`` (rad), in (-pi, pi].
    c, s : ndarray (..., 2)
        Their cosines and sines.
    """
    cb, sb, cd = cb[..., None], sb[..., None], cd[..., None]
    sd = sd[..., None] * _PLUS_MINUS
    c = cb * cd - sb * sd
    s = sb * cd + cb * sd
    return principal(np.arctan2(s, c)), c, s


def two_slots(two, exact, free) -> tuple:
    """The masks ``(ok, exact, free)``, each ``(..., 2)`` bool, of a subproblem with the roots
    ``base +- delta``: slot 0 always holds an answer, slot 1 where ``two``; ``exact`` and
    ``free (...)`` the same for both. Views of one new array (written once, four copies).

    Parameters
    ----------
    two, exact, free : ndarray (...) of bool
        The shapes broadcast against that of ``two``, the largest.

    Returns
    -------
    tuple of three ndarray (..., 2) of bool
    """
    out = np.empty((3,) + two.shape + (2,), bool)
    out[0, ..., 0] = True
    out[0, ..., 1] = two
    out[1] = exact[..., None]
    out[2] = free[..., None]
    return out[0], out[1], out[2]


def pair(a, b) -> np.ndarray:
    """``np.stack([a, b], -1)`` for two arrays that broadcast together.

    The two slots of a subproblem's roots, written into one new array (``np.stack`` costs
    several times as much on the small batches of a single pose).

    Parameters
    ----------
    a, b : array_like (...)
        The values of slot 0 and slot 1; their shapes broadcast together.

    Returns
    -------
    ndarray (..., 2)
        ``a`` in ``[..., 0]``, ``b`` in ``[..., 1]``, of the dtype ``result_type(a, b)``.

    Raises
    ------
    ValueError
        When the shapes of ``a`` and ``b`` do not broadcast.
    """
    if type(b) is np.ndarray and b.ndim:
        if a is True or a is False:
            a = np.full(b.shape, a)
        if type(a) is np.ndarray and a.shape == b.shape and a.dtype == b.dtype:
            return np.concatenate((a[..., None], b[..., None]), -1)
    out = np.empty(np.broadcast(a, b).shape + (2,), np.result_type(a, b))
    out[..., 0] = a
    out[..., 1] = b
    return out


#: ``(3, 3, 3)``: ``_SKEW @ a`` is the cross-product matrix of ``a`` (``[a]_x b = a x b``),
#: the Levi-Civita symbol ``eps_ijm`` with ``[a]_x[i, m] = eps_ijm a_j``
_SKEW = LEVI_CIVITA.reshape(3, 3, 3).transpose(0, 2, 1)


def dot(a, b) -> np.ndarray:
    """The dot product ``a . b`` over the last axis.

    Summed along the components, ``(a0 b0 + a1 b1) + a2 b2``, each sum a numpy call on
    whole components, never by a BLAS product or a reduction over the batch: BLAS rounds a
    row by a kernel that depends on how many rows it is given (a lone row, the tail of a
    block), and a pose's decisions at a singular configuration would then depend on its
    batch. Both ways of forming the products give the same bits.

    Parameters
    ----------
    a, b : ndarray (..., 3)
        Vectors in one frame (numpy arrays: they are not converted); the leading shapes
        broadcast.

    Returns
    -------
    ndarray (...)
        ``a . b``, in the product of their units.

    Raises
    ------
    ValueError
        When the leading shapes do not broadcast.
    """
    if (a.ndim == 1 or b.ndim == 1) and a.size + b.size > _FEW:
        # a fixed vector against many: its components as Python floats (numpy broadcasts
        # a (3,) row slowly)
        (b0, b1, b2), a = (b.tolist(), a) if b.ndim == 1 else (a.tolist(), b)
        out = a[..., 0] * b0
        out += a[..., 1] * b1
        out += a[..., 2] * b2
        return out
    p = a * b                   # the same products and sums, in the same order: same bits
    out = p[..., 0] + p[..., 1]
    out += p[..., 2]
    return out


#: up to this many components in all, :func:`dot` multiplies a fixed vector as an array
#: (fewer numpy calls)
_FEW = 192


def rows_times(X, B) -> np.ndarray:
    """``X @ B`` for the rows ``X (..., k)`` of a batch and a fixed ``B (k, m)``, each row's
    bits the same for any number of rows (:func:`dot`'s rule; numpy's own sum of products,
    not BLAS).

    Returns
    -------
    ndarray (..., m)
    """
    return np.einsum("...k,km->...m", X, B)


def cross(a, b) -> np.ndarray:
    """The cross product ``a x b``.

    A fixed vector against a batch is its cross-product matrix applied to the rows
    (:func:`rows_times`, two numpy calls on any batch); two batches are crossed by
    components, written into one new array (stacking them costs four times as much); two
    single vectors on their components as Python floats (the same products and differences,
    a tenth of the calls).

    Parameters
    ----------
    a, b : array_like (..., 3)
        Vectors in one frame; the leading shapes broadcast.

    Returns
    -------
    ndarray (..., 3)
        ``a x b`` (float), in the same frame.

    Raises
    ------
    ValueError
        When the shapes do not broadcast.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    if a.ndim == 1 and b.ndim > 1:                  # [a]_x b, as rows: b [a]_x^T
        return rows_times(b, crossing(a))
    if b.ndim == 1 and a.ndim > 1:                  # a x b = -[b]_x a, as rows: a [b]_x
        return rows_times(a, _SKEW @ b)
    if a.ndim == 1 and b.ndim == 1:                 # two vectors: on floats, the same roundings
        (a0, a1, a2), (b0, b1, b2) = a.tolist(), b.tolist()
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast(a, b).shape)
    np.multiply(a1, b2, out=out[..., 0])
    out[..., 0] -= a2 * b1
    np.multiply(a2, b0, out=out[..., 1])
    out[..., 1] -= a0 * b2
    np.multiply(a0, b1, out=out[..., 2])
    out[..., 2] -= a1 * b0
    return out


def crossing(a) -> np.ndarray:
    """The matrix that crosses rows with the fixed vector ``a``: ``b @ crossing(a) = a x b``.

    ``[a]_x^T`` (``[a]_x`` the cross-product matrix of ``a``); a caller crossing many batches
    with one ``a`` keeps it (:func:`cross` makes it on every call).

    Parameters
    ----------
    a : ndarray (3,)

    Returns
    -------
    ndarray (3, 3)
        A transposed view (the layout :func:`cross` multiplies with).
    """
    return (_SKEW @ a).T


def norm(a) -> np.ndarray:
    """The Euclidean length ``|a|`` over the last axis.

    Parameters
    ----------
    a : ndarray (..., 3)
        Vectors (a numpy array: it is indexed, not converted).

    Returns
    -------
    ndarray (...)
        ``sqrt(a . a)``, in the unit of ``a``.
    """
    return np.sqrt(dot(a, a))


def as_vectors(*vs):
    """The inputs as float arrays ``(..., 3)`` whose leading shapes broadcast together.

    They are not broadcast here: a fixed axis ``(3,)`` given with a batch of points
    stays one vector, so that what depends on it alone is computed once.

    Parameters
    ----------
    *vs : array_like (..., 3)
        Vectors of one subproblem call.

    Returns
    -------
    list of ndarray (..., 3)
        The inputs as float arrays, each with its own leading shape, in input order.

    Raises
    ------
    ValueError
        When an input's last axis is not of length 3, or the leading shapes do not
        broadcast together.
    """
    arrays = [v if type(v) is np.ndarray and v.dtype == np.float64 else np.asarray(v, float)
              for v in vs]
    shapes = set()                                      # of the batches: a single vector
    for a in arrays:                                    # broadcasts
        shape = a.shape
        if shape[-1:] != (3,):
            raise ValueError(f"expected vectors of shape (..., 3), got {shape}")
        if len(shape) > 1:
            shapes.add(shape)
    if len(shapes) > 1:
        np.broadcast_shapes(*shapes)    # raises when the leading shapes do not broadcast
    return arrays

