"""The robot as screws in the world frame, for the geometric IK solvers.

At q = 0 each joint i is a line through ``point[i]`` along the unit
``axis[i]`` (world frame, m), and the tool pose is ``M = fk(0)``. Then
``T(q) = E_1(q_1) ... E_n(q_n) M`` with ``E_i`` a rotation about, or a
translation along, joint i's line (Brockett's product of exponentials; the
robot's base transform is already inside the axes and M).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..spatial import invert_transform, matrix_from_axis_angle


@dataclass(frozen=True)
class Screws:
    axis: np.ndarray        # (n, 3) unit
    point: np.ndarray       # (n, 3)
    revolute: np.ndarray    # (n,) bool
    M: np.ndarray           # (4, 4) tool pose at q = 0
    scale: float            # characteristic length (m)
    #: robot-level constants of the solvers, computed once (see :meth:`constant`)
    cache: dict = field(default_factory=dict, compare=False, repr=False, init=False)

    def constant(self, key, make):
        """``make()``, computed once for these screws and ``key``.

        The robot-level constants of a solver (a subproblem's fixed vectors, a placement's
        structure), which every batch of poses would otherwise compute again.

        Parameters
        ----------
        key : hashable
            Names the constant (unique across the solvers).
        make : callable
            ``make() -> value``, called on the first request only.

        Returns
        -------
        object
            The cached value (shared: do not modify it).
        """
        try:
            return self.cache[key]
        except KeyError:
            value = self.cache[key] = make()
            return value

    def turn(self, i: int, c, s, v, back: bool = False) -> np.ndarray:
        """Vectors turned by joint ``i``'s rotation, given as its cosine and sine.

        ``R v = (I + K^2) v - c K^2 v + s K v`` (Rodrigues, ``K`` the cross-product matrix of
        the axis), all three terms in one matrix product. Computed on components (``(3, ...)``:
        each operation runs along the batch, where ``(M, 3)`` arrays broadcast against
        ``(M, 1)`` factors cost several times more).

        Parameters
        ----------
        i : int
            The joint (0-based; revolute).
        c, s : array_like (...)
            Cosine and sine of the angle (rad): of the same shape as ``v``'s leading part,
            or of a leading part of it (one angle for the vectors behind it), or anything
            that broadcasts.
        v : array_like (..., 3)
            Vectors (world frame at q = 0), free vectors: the axis passes through the origin
            here (use :meth:`move` for points).
        back : bool
            Turn by minus the angle (``R^T v``, the joint's motion undone): the sine term
            subtracted, the same bits as ``turn(i, c, -s, v)`` without negating ``s``.

        Returns
        -------
        ndarray (..., 3)
            The turned vectors, a transposed view of the ``(3, ...)`` layout; the shape
            broadcast from ``v`` and ``c, s``.
        """
        v, c, s = np.asarray(v, float), np.asarray(c, float), np.asarray(s, float)
        if v.ndim == 1 and c.shape == s.shape:          # one vector, turned by every angle
            R = self.cache.get("rodrigues")             # (no method call: as dear as the rest)
            B = (self.rodrigues(i) if R is None else R[i]) @ v              # (9,)
            out = B[3:6, None] * c.reshape(-1)
            out += B[0:3, None]
            if back:
                out -= B[6:9, None] * s.reshape(-1)
            else:
                out += B[6:9, None] * s.reshape(-1)
            return out.T.reshape(c.shape + (3,))
        shape = v.shape[:-1]
        if c.shape != s.shape or shape[:c.ndim] != c.shape:    # the angles broadcast
            shape = np.broadcast_shapes(shape, c.shape, s.shape)
            v = np.broadcast_to(v, shape + (3,))
            c, s = np.broadcast_to(c, shape), np.broadcast_to(s, shape)
        # (else several vectors per angle: the angles' shape is v's leading part)
        if c.ndim < len(shape):                         # one angle for the vectors behind
            grow = (...,) + (None,) * (len(shape) - c.ndim)
            c, s = c[grow], s[grow]
        # R v per vector as products and sums along the batch, not BLAS: each vector's bits
        # depend neither on how many are turned nor on v's layout (numpy's sum of products,
        # which this replaced, took a transposed view's vectors by another kernel, two or
        # more otherwise than one). x, z, then y is the order it summed the terms in.
        R = self.cache.get("rodrigues columns")         # per joint: three (9, 1) columns
        x, y, z = self._columns()[i] if R is None else R[i]
        v = v.transpose(_FIRST[len(shape)]).reshape(3, -1)
        B = x * v[0]
        B += z * v[2]
        B += y * v[1]
        B = B.reshape((9,) + shape)
        out = B[3:6]
        out *= c
        out += B[0:3]
        sk = B[6:9]
        sk *= s
        if back:
            out -= sk
        else:
            out += sk
        return out.transpose(_LAST[len(shape)])

    def _columns(self) -> list:
        """Per joint, the three columns of its :meth:`rodrigues`, each ``(9, 1)`` (contiguous;
        :meth:`turn` multiplies the components of its vectors by them): computed once
        (:meth:`constant`), read without indexing an array."""
        return self.constant("rodrigues columns", lambda: [
            tuple(np.ascontiguousarray(col[:, None]) for col in self.rodrigues(i).T)
            for i in range(self.n)])

    def turn_fixed(self, i: int, c, s, name, V, back: bool = False) -> np.ndarray:
        """Fixed vectors turned by joint ``i``'s rotation: :meth:`turn` of ``V`` at every angle.

        The three Rodrigues terms of the vectors, ``rodrigues(i) @ V.T`` ``(9, m)``, are
        robot constants: computed once per ``(name, i)`` (:meth:`constant`), so a call costs
        only ``B0 + c B1 + s B2``, whatever the number of vectors (the same products and
        sums as :meth:`turn`: the same bits).

        Parameters
        ----------
        i : int
            The joint (0-based; revolute).
        c, s : ndarray (...)
            Cosine and sine of the angle (rad), of one shape.
        name : hashable
            Names the vectors (unique across the solvers: the key of the cached terms).
        V : array_like (m, 3) or callable
            The vectors (world frame at q = 0; free vectors, as for :meth:`turn`), or
            ``V() -> (m, 3)``; read on the first call for ``(name, i)`` only.
        back : bool
            Turn by minus the angle (:meth:`turn`'s ``back``).

        Returns
        -------
        ndarray (..., m, 3)
            ``R(c, s) V[j]`` for every angle and vector ``j`` (a view of a ``(3, m, M)``
            layout).
        """
        B = self.cache.get(("turned", name, i))
        if B is None:
            B = self.constant(("turned", name, i), lambda: (self.rodrigues(i) @ np.asarray(
                V() if callable(V) else V, float).T).reshape(3, 3, -1, 1))  # (term, xyz, m, 1)
        out = B[1] * c.reshape(-1)                                          # (3, m, M)
        out += B[0]
        if back:
            out -= B[2] * s.reshape(-1)
        else:
            out += B[2] * s.reshape(-1)
        return out.transpose(2, 1, 0).reshape(c.shape + out.shape[1::-1])

    def rodrigues(self, i: int) -> np.ndarray:
        """``[I + K^2; -K^2; K]`` of joint ``i``'s axis ``k`` (``K`` its cross-product matrix).

        ``rodrigues @ v`` stacks the three terms of :meth:`turn`; computed once for all the
        joints (:meth:`constant`).

        Parameters
        ----------
        i : int
            The joint (0-based).

        Returns
        -------
        ndarray (9, 3), contiguous
        """
        every = self.cache.get("rodrigues")     # (without a closure per call: as dear)
        if every is None:
            every = self.constant("rodrigues",
                                  lambda: np.array([_rodrigues(k) for k in self.axis]))
        return every[i]

    def move(self, i: int, x, c, s, p) -> np.ndarray:
        """Points moved by joint ``i``: turned about its line, or slid along it.

        Parameters
        ----------
        i : int
            The joint (0-based).
        x : array_like (...)
            A prismatic joint's travel (m); unused for a revolute joint.
        c, s : array_like (...)
            A revolute joint's cosine and sine of the angle; unused for a prismatic joint.
        p : array_like (..., 3)
            Points (world frame at q = 0, m).

        Returns
        -------
        ndarray (..., 3)
            The moved points (m).
        """
        if self.revolute[i]:
            return self.point[i] + self.turn(i, c, s, p - self.point[i])
        return p + np.asarray(x)[..., None] * self.axis[i]

    @staticmethod
    def of(robot) -> "Screws":
        """The screws of ``robot`` from its FK at q = 0.

        Parameters
        ----------
        robot : Robot
            Gives ``chain``, ``dof``, ``is_revolute`` and ``characteristic_length``.

        Returns
        -------
        Screws
            Joint axes and points of the joint frames at q = 0 (world frame, m), ``M`` the
            tool pose ``T_world_tool`` at q = 0, ``scale`` the characteristic length (m).
        """
        from ..fk import frames_and_tool
        F, M = frames_and_tool(robot.chain, np.zeros(robot.dof))
        return Screws(F[:, :3, 2].copy(), F[:, :3, 3].copy(), robot.is_revolute.copy(), M,
                      robot.characteristic_length)

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.revolute)

    def exp(self, i: int, x) -> np.ndarray:
        """``E_i(x)``: joint ``i``'s motion as transforms.

        Parameters
        ----------
        i : int
            The joint (0-based).
        x : array_like (...)
            Joint values (rad for revolute, m for prismatic joints).

        Returns
        -------
        ndarray (..., 4, 4)
            Rotations about joint i's line (through ``point[i]``) or translations along its
            axis (world frame at q = 0, m).
        """
        x = np.asarray(x, float)
        T = np.zeros(x.shape + (4, 4))
        T[..., 3, 3] = 1.0
        if self.revolute[i]:
            R = matrix_from_axis_angle(self.axis[i], x)
            T[..., :3, :3] = R
            T[..., :3, 3] = self.point[i] - R @ self.point[i]
        else:
            T[..., :3, :3] = np.eye(3)
            T[..., :3, 3] = x[..., None] * self.axis[i]
        return T

    def product(self, idx, xs) -> np.ndarray:
        """``E_idx[0](xs[0]) E_idx[1](xs[1]) ...``.

        Parameters
        ----------
        idx : sequence of int
            The joints (0-based), in the order of the product.
        xs : sequence of array_like (...)
            Their values (rad / m), broadcasting against each other.

        Returns
        -------
        ndarray (..., 4, 4)
            The product (the identity for no joint).
        """
        T = np.eye(4)
        for i, x in zip(idx, xs):
            T = T @ self.exp(i, x)
        return T

    def move_point(self, i: int, x, p) -> np.ndarray:
        """``E_i(x)`` applied to points ``p``.

        Parameters
        ----------
        i : int
            The joint (0-based).
        x : array_like (...)
            Joint values (rad / m); broadcast against ``p``'s leading part.
        p : array_like (..., 3)
            Points (world frame at q = 0, m).

        Returns
        -------
        ndarray (..., 3)
            The moved points (m).
        """
        p = np.asarray(p, float)
        x = np.asarray(x, float)[..., None]
        k = self.axis[i]
        if not self.revolute[i]:
            return p + x * k
        # Rodrigues on the offset from the axis: d -> (k.d) k + cos x (d - (k.d) k) + sin x (k x d)
        d = p - self.point[i]
        along = (d @ k)[..., None] * k
        kxd = np.stack([k[1] * d[..., 2] - k[2] * d[..., 1], k[2] * d[..., 0] - k[0] * d[..., 2],
                        k[0] * d[..., 1] - k[1] * d[..., 0]], axis=-1)
        return self.point[i] + along + np.cos(x) * (d - along) + np.sin(x) * kxd

    def inverse_M(self) -> np.ndarray:
        """The inverse of the tool pose at q = 0.

        Returns
        -------
        ndarray (4, 4)
            ``M^-1`` (SI).
        """
        return invert_transform(self.M)

    def reversed(self) -> "Screws":
        """The chain seen from the tool: ``T(q)^-1 = E'_1(-q_n) ... E'_n(-q_1) M^-1``.

        With ``T = E_1(q_1) ... E_n(q_n) M``, inverting and moving ``M^-1`` to the right
        gives ``E'_k(x) = M^-1 E_{n+1-k}(x) M``: joint k of the reversed chain is joint
        n + 1 - k, its line carried by ``M^-1``, turned by minus the angle (or slid by minus
        the length). Solve the reversed chain for ``T^-1`` and map back with
        ``q = -q'[::-1]``.

        Returns
        -------
        Screws
            Axes and points in the tool frame at q = 0, ``M`` replaced by ``M^-1``; the same
            ``scale``.
        """
        Mi = self.inverse_M()
        return Screws((self.axis @ Mi[:3, :3].T)[::-1].copy(),
                      (self.point @ Mi[:3, :3].T + Mi[:3, 3])[::-1].copy(),
                      self.revolute[::-1].copy(), Mi, self.scale)


#: the axes that move a leading axis of n + 1 last: ``(1, ..., n, 0)``
_LAST = [tuple(range(1, n + 1)) + (0,) for n in range(33)]

#: the axes that move a last axis after n others first: ``(n, 0, ..., n - 1)``
_FIRST = [(n,) + tuple(range(n)) for n in range(33)]


def _rodrigues(k) -> np.ndarray:
    """``[I + K^2; -K^2; K] (9, 3)`` of the unit axis ``k (3,)``, ``K`` its cross-product
    matrix (:meth:`Screws.rodrigues`)."""
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    K2 = K @ K
    return np.concatenate([np.eye(3) + K2, -K2, K])
