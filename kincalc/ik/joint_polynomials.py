"""Quantities of a chain's frames as polynomials of its joint values, fitted once per robot.

A quantity made of the frames by sums and products (a dot product of two axes, a triple
product of points) is, in each revolute joint ``q_j``, a trigonometric polynomial: every
frame after joint j is turned by a rotation whose entries are linear in ``cos q_j`` and
``sin q_j``, so a product of three such vectors has degree at most 3. In a prismatic
joint ``d_j`` it is an ordinary polynomial (points are linear in ``d_j``, axes do not
depend on it). Many such quantities depend on few joints: a triple product with joint j's
axis does not change when joint j turns everything after it.

:func:`fit` finds, once per robot, which joints each quantity depends on and with what
degree, and its coefficients; :meth:`JointPolynomials.__call__` then evaluates the
quantities of many configurations from the cosines and sines of those joints alone, a few
array operations, instead of every configuration's frames.

The fit is exact, not an approximation: its degrees are found from samples of each joint
over a whole turn (a discrete Fourier transform of :data:`SCAN` points tells frequencies 0
to 4 apart), its coefficients solve the square system on a grid of the joints involved,
and it is checked against the quantities at :data:`CHECKS` configurations spread over
every joint's range (agreement to ``1e-11`` of each quantity's size). A fit that fails the
check (never seen: the degrees are bounded as above) is None, and the caller evaluates the
frames.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from ..samples import spread

#: samples per joint when finding the degrees: a DFT of 8 points separates frequencies 0-4
#: (degree 3 is the most a product of three vectors has; 4 would show a wrong model)
SCAN = 8
#: configurations the fit is checked at
CHECKS = 32
#: agreement of the fit with the quantities, relative to each one's size
AGREE = 1e-11


class Group(NamedTuple):
    """Quantities ``rows`` that depend on the same joints, with a common degree in each."""

    joints: tuple            # (0-based)
    degrees: tuple           # per joint: the trigonometric (revolute) or power degree
    rows: np.ndarray         # (r,) of int: which quantities
    coefficients: np.ndarray  # (terms, r): of the tensor product basis of :func:`_basis`


@dataclass(frozen=True)
class JointPolynomials:
    """The fitted quantities of one robot (see the module docstring).

    Their bases are written into one array ``Phi (terms, m)``: first the rows ``1, cos q,
    sin q`` of every revolute joint some group takes to degree 1 (``first``: a group of one
    such joint reads its terms there), then the terms of every other group (``made``:
    ``(group, its first row)``). Each group's quantities are its coefficients times its rows
    of ``Phi``, one product written into its block of the quantities in group order."""

    count: int
    revolute: np.ndarray     # (n,) of bool
    length: float            # m: prismatic joints are fitted in d / length
    groups: tuple
    #: the revolute joints some group takes to degree 1 (their rows are made together)
    first: tuple = ()
    #: the groups whose terms are made, each with the row of ``Phi`` they start at
    made: tuple = ()
    #: per group, ``((start, stop) of its rows of Phi, (start, stop) of its quantities in
    #: group order)``; a constant has no rows of Phi
    blocks: tuple = ()
    terms: int = 0
    #: ``(count,)``: where each quantity is in group order, None when it is already in place
    order: np.ndarray | None = None

    def __call__(self, Q) -> np.ndarray:
        """The quantities at configurations ``Q (m, n)`` (rad / m): ``(count, m)``."""
        Q = np.asarray(Q, float)
        Phi = np.empty((self.terms, len(Q)))
        bases = _first_harmonics(self, Q, Phi)
        for g, at in self.made:
            _basis(self, Q, g.joints, g.degrees, bases, out=Phi[at:at + len(g.coefficients)])
        out = np.empty((self.count, len(Q)))
        for g, ((a, b), (r, s)) in zip(self.groups, self.blocks):
            if g.joints:
                np.matmul(g.coefficients.T, Phi[a:b], out=out[r:s])
            else:        # a constant (one coefficient per row) is its coefficient times 1
                out[r:s] = g.coefficients.T
        return out if self.order is None else out[self.order]


def fit(quantities, revolute, length: float, sizes) -> JointPolynomials | None:
    """The quantities ``quantities(Q) -> (r, m)`` as polynomials of the joint values.

    Parameters
    ----------
    quantities : callable
        ``Q (m, n)`` (rad / m) -> ``(r, m)``: the quantities of each configuration.
    revolute : array_like (n,) of bool
    length : float
        The robot's characteristic length (m): prismatic joints are sampled over about
        ``+-length``.
    sizes : array_like (r,)
        Each quantity's natural size (its unit: m, m^2, 1): the scale of "negligible".

    Returns
    -------
    JointPolynomials, or None when the fit does not reproduce the quantities
    """
    revolute = np.asarray(revolute, bool)
    L = max(float(length), 1e-12)
    span = np.where(revolute, np.pi, L)
    points = spread(3 + CHECKS, -span, span)
    base = points[:3]
    degrees, scale = _degrees(quantities, revolute, L, base, np.asarray(sizes, float))
    model = JointPolynomials(len(degrees), revolute, L, ())
    groups = {}
    for r, d in enumerate(degrees):
        groups.setdefault(tuple(np.flatnonzero(d).tolist()), []).append(r)
    out = []
    for joints, rows in groups.items():
        deg = tuple(int(degrees[rows, j].max()) for j in joints)
        grid = _grid(model, joints, deg, base[0])
        Phi = _basis(model, grid, joints, deg)
        C = np.linalg.solve(Phi.T, quantities(grid)[rows].T)
        out.append(Group(joints, deg, np.array(rows, np.intp), C))
    model = _stacked(JointPolynomials(len(degrees), revolute, L, tuple(out)))
    Q = points[3:]
    miss = np.abs(model(Q) - quantities(Q)).max(-1)
    return model if np.all(miss <= AGREE * scale) else None


def _degrees(quantities, revolute, L, base, sizes):
    """Each quantity's degree in each joint ``(r, n)`` of int, found by turning (sliding)
    one joint at a time from the configurations ``base (b, n)``; and each one's size
    ``(r,)``: the larger of ``sizes`` and its largest sample."""
    b, n = base.shape
    theta = 2 * np.pi * np.arange(SCAN) / SCAN
    x = np.cos(np.pi * (np.arange(SCAN) + 0.5) / SCAN)             # Chebyshev nodes in [-1, 1]
    Q = np.repeat(base[:, None, None, :], n, 1).repeat(SCAN, 2)    # (b, n, SCAN, n)
    for j in range(n):
        Q[:, j, :, j] = theta if revolute[j] else L * x
    values = quantities(Q.reshape(-1, n)).reshape(-1, b, n, SCAN)  # (r, b, n, SCAN)
    scale = np.maximum(sizes, np.abs(values).max((1, 2, 3)))
    k = np.arange(SCAN // 2 + 1)[:, None] * theta                    # the DFT, frequencies 0..4
    F = np.hypot(values @ np.cos(k).T, values @ np.sin(k).T) / SCAN  # (r, b, n, 5)
    P = np.abs(values @ np.linalg.inv(np.vander(x, SCAN, increasing=True)).T)  # powers 0..7
    big = lambda c: c > 1e-12 * scale[:, None, None]  # noqa: E731  (r, n, k)
    rev = big(F.max(1))[..., 1:]                     # frequencies 1..4
    pri = big(P.max(1))[..., 1:]                     # powers 1..7
    deg_rev = np.where(rev.any(-1), rev.shape[-1] - np.argmax(rev[..., ::-1], -1), 0)
    deg_pri = np.where(pri.any(-1), pri.shape[-1] - np.argmax(pri[..., ::-1], -1), 0)
    return np.where(revolute, deg_rev, deg_pri), scale


def _stacked(model: JointPolynomials) -> JointPolynomials:
    """``model`` with its bases laid out in one array (:class:`JointPolynomials`): the rows of
    the first harmonics, then the terms of each group that does not read its terms there; and
    the quantities in group order."""
    first = tuple(sorted({j for g in model.groups for j, d in zip(g.joints, g.degrees)
                          if d == 1 and model.revolute[j]}))
    at, made, blocks, row = 3 * len(first), [], [], 0
    for g in model.groups:
        if len(g.joints) == 1 and g.degrees == (1,) and g.joints[0] in first:
            a = 3 * first.index(g.joints[0])
            cols = (a, a + 3)
        elif not g.joints:
            cols = (0, 0)
        else:
            made.append((g, at))
            cols = (at, at + len(g.coefficients))
            at += len(g.coefficients)
        blocks.append((cols, (row, row + len(g.rows))))
        row += len(g.rows)
    grouped = np.concatenate([g.rows for g in model.groups]) if model.groups else \
        np.arange(model.count)
    order = None if np.array_equal(grouped, np.arange(model.count)) else np.argsort(grouped)
    return replace(model, first=first, made=tuple(made), blocks=tuple(blocks), terms=at,
                   order=order)


def _grid(model: JointPolynomials, joints, degrees, base) -> np.ndarray:
    """Configurations ``(m, n)`` on which the basis of ``joints`` with ``degrees`` is a
    square, well-conditioned system: ``2 d + 1`` equally spaced angles (a revolute joint)
    or ``d + 1`` Chebyshev nodes (prismatic), the other joints at ``base``."""
    axes = []
    for j, d in zip(joints, degrees):
        if model.revolute[j]:
            axes.append(2 * np.pi * np.arange(2 * d + 1) / (2 * d + 1))
        else:
            axes.append(model.length * np.cos(np.pi * (np.arange(d + 1) + 0.5) / (d + 1)))
    mesh = np.meshgrid(*axes, indexing="ij") if axes else []
    Q = np.repeat(base[None], int(np.prod([len(a) for a in axes])), 0)
    for j, m in zip(joints, mesh):
        Q[:, j] = m.reshape(-1)
    return Q


def _basis(model: JointPolynomials, Q, joints, degrees, bases=None, out=None) -> np.ndarray:
    """The tensor product basis ``(terms, m)`` of ``joints`` at ``Q (m, n)``: per revolute
    joint ``1, cos q, sin q, ..., cos dq, sin dq``, per prismatic one ``1, x, ..., x^d``
    (``x = d_j / length``), the last joint's index running fastest. ``bases``: a dict that
    keeps each joint's rows for the next call on the same ``Q``; ``out``: the rows written
    (and returned)."""
    bases = {} if bases is None else bases
    for j, d in zip(joints, degrees):
        if (j, d) not in bases:
            bases[j, d] = _joint_basis(model, Q[:, j], j, d)
    B = [bases[j, d] for j, d in zip(joints, degrees)]
    if out is None:
        out = np.empty((int(np.prod([len(b) for b in B])), len(Q)))
    if len(B) < 2:
        out[...] = B[0] if B else 1.0
        return out
    Phi = B[0]
    for b in B[1:-1]:
        Phi = (Phi[:, None] * b).reshape(-1, len(Q))
    np.multiply(Phi[:, None], B[-1], out=out.reshape(len(Phi), len(B[-1]), len(Q)))
    return out


def _first_harmonics(model: JointPolynomials, Q, Phi) -> dict:
    """The rows ``1, cos q, sin q`` ``(3, m)`` of each joint of ``model.first`` at ``Q (m,
    n)``, written into the stacked basis ``Phi`` by one cosine and one sine of them all:
    :func:`_basis`' ``bases`` for degree 1 (the values of :func:`_joint_basis`: the cosine
    of a value does not depend on the array it is in)."""
    if not model.first:
        return {}
    B = Phi[:3 * len(model.first)].reshape(len(model.first), 3, len(Q))
    B[:, 0] = 1.0
    x = Q.T[model.first, :]                 # (joints, m), each row contiguous
    np.cos(x, out=B[:, 1])
    np.sin(x, out=B[:, 2])
    return {(j, 1): b for j, b in zip(model.first, B)}


def _joint_basis(model: JointPolynomials, x, j: int, d: int) -> np.ndarray:
    """Joint ``j``'s rows of :func:`_basis` at its values ``x (m,)``: ``(2 d + 1, m)`` or
    ``(d + 1, m)``."""
    B = np.empty(((2 * d + 1) if model.revolute[j] else d + 1, len(x)))
    B[0] = 1.0
    if model.revolute[j]:
        c, s = B[1], B[2]
        np.cos(x, out=c)
        np.sin(x, out=s)
        for k in range(2, d + 1):       # cos/sin of (k-1) q and q -> of k q
            ck, sk = B[2 * k - 3], B[2 * k - 2]
            B[2 * k - 1], B[2 * k] = ck * c - sk * s, sk * c + ck * s
    else:
        x = x / model.length
        for k in range(1, d + 1):
            B[k] = B[k - 1] * x
    return B
