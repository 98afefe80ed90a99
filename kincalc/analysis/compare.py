"""Are two robot descriptions the same robot?

Two robots with the same number and types of joints are *equivalent* when
some constant signs ``s_i = +-1`` and offsets ``c_i`` make them agree for
every configuration::

    FK_candidate(s * q + c) == B · FK_reference(q) · T      for all q (n,)

where ``FK`` is ``T_world_tool`` (4, 4, lengths in m), ``q`` is in rad / m,
and ``B`` (base) and ``T`` (tool) are the identity unless ``free_base`` /
``free_tool`` let them be any constant rigid transforms. Without
``allow_offsets`` the signs must all be +1 and the offsets 0.

Method (product of exponentials; Lynch & Park, *Modern Robotics*, 2017,
sec. 4.1 and 5.1). Both robots are written as
``FK(q) = exp([xi_1] q_1) ··· exp([xi_n] q_n) · M`` with unit screws ``xi_i``
``(v, w)`` in the world frame at q = 0. Then

    FK_c(s q + c) = prod_i exp([s_i eta_i(c)] q_i) · G_n(c) M_c,
    eta_i(c) = Ad_{G_{i-1}(c)} eta_i,   G_k(c) = exp([eta_1] c_1) ··· exp([eta_k] c_k),

and, because the columns of the spatial Jacobian at q = 0 are the screws,
equality for all q holds exactly when ``s_i eta_i(c) = xi_i`` for every i
and ``G_n(c) M_c = M_r``. The screw equations are solved one joint at a
time: screw i + 1 fixes the offsets it depends on given the earlier ones.
With one unknown offset the equation is ``r0 + sin(x) a1 + (1 - cos x) a2 = 0``
(``r0 + x a1`` for a prismatic joint), solved exactly for every root; an
offset a screw leaves undetermined (a joint whose screw commutes with the
next ones: a prismatic joint along the previous revolute axis, two parallel
prismatic joints, ...) waits for a later screw or the tool condition, which
then solve for the waiting offsets together by damped Gauss-Newton from a
grid of starts. Where a screw has several solutions (intersecting axes:
``c`` and ``c + pi`` with the sign flipped) every branch is followed, and
among the complete solutions the one with the fewest sign changes, then the
smallest offsets, is kept. The answer is always checked by forward
kinematics on ``samples`` random configurations within the reference's
limits (plus q = 0); that check alone decides ``same``.

Without ``free_base`` the robots' ``base`` transforms are part of the
comparison (world frames must agree); ``free_base`` aligns joint 1's axis
and solves for the rest of the base like an offset, and absorbs joint 1's
offset into it. ``free_tool`` drops the tool condition and absorbs the last
joint's offset. Joint limits and names are not compared.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass, field

import numpy as np

from ..spatial import cross, invert_transform, skew

#: a linearised equation whose singular value is below this (relative) does
#: not determine the offsets along that direction.
NULL_TOL = 1e-8
#: |d residual / d offset| below this: the equation does not depend on it.
INVARIANT_TOL = 1e-11
#: limits on the branch search (it stays far below them for real robots).
MAX_NODES = 2000
MAX_STARTS = 729


@dataclass(frozen=True)
class Match:
    """The answer of :func:`match`.

    Attributes
    ----------
    same : bool
        The candidate is the reference (within ``tol``) for every sampled q.
    signs : ndarray (n,)
        +1 or -1: candidate joint i = ``signs[i] * reference joint i + offsets[i]``.
    offsets : ndarray (n,)
        rad (revolute) / m (prismatic). Joint 1's offset is 0 with
        ``free_base`` and the last joint's with ``free_tool`` (the base or
        tool absorbs them).
    base, tool : ndarray (4, 4) or None
        With ``free_base`` / ``free_tool``: ``FK_candidate(signs*q + offsets)
        = base @ FK_reference(q) @ tool``; None otherwise.
    position_error : float
        Largest tool position difference over the samples (m), with the signs
        and offsets found (for robots that differ: the best ones found for the
        joints before the first bad one, 0 from there on; when joint types
        differ: at equal joint values). NaN when the joint counts differ.
    orientation_error : float
        Largest rotation angle between the tool orientations (rad); NaN likewise.
    worst_q : ndarray (n,)
        Reference configuration (rad / m) with the largest difference
        (position difference / length scale + angle); empty (shape (0,)) when
        the joint counts differ.
    first_bad_joint : int or None
        1-based: the first joint whose axis cannot be made to match the
        reference's given the earlier ones; n + 1 when every axis matches but
        the tool frame (T_0^n at the matched zero) differs. None when the
        robots are the same, or when their joint counts differ.
    reason : str
        One line, in the reference's length unit and degrees.
    kind : str
        'same'; or why not: 'dof' (joint counts differ), 'type' (a joint's
        type differs), 'axis' (``first_bad_joint``'s axis), 'tool' (the tool
        frame, ``first_bad_joint = n + 1``).
    miss_angle, miss_distance : float or None
        How far the first bad joint's axis is from the reference's at the best
        offsets found: angle between the axes (rad) and distance between the
        lines (m; None for a prismatic joint, whose axis has no position).
        For ``first_bad_joint = n + 1`` the tool frame's rotation angle and
        position difference at the matched zero.
    length_scale : float
        The length (m) position tolerances are relative to: the larger
        characteristic length of the two robots.
    tol : float
        The tolerance used (positions: ``tol * length_scale``; angles: rad).
    allow_offsets, free_base, free_tool : bool
        The options the answer was found with.
    hint_offsets : bool
        Without ``allow_offsets``: the robots differ, but would be the same
        with offsets and sign changes allowed (the reason says so).
    """

    same: bool
    signs: np.ndarray
    offsets: np.ndarray
    base: np.ndarray | None
    tool: np.ndarray | None
    position_error: float
    orientation_error: float
    worst_q: np.ndarray
    first_bad_joint: int | None
    reason: str
    kind: str = "same"
    miss_angle: float | None = None
    miss_distance: float | None = None
    length_scale: float = 1.0
    tol: float = 1e-6
    allow_offsets: bool = False
    free_base: bool = False
    free_tool: bool = False
    hint_offsets: bool = field(default=False, repr=False)


def match(reference, candidate, *, allow_offsets: bool = False, free_base: bool = False,
          free_tool: bool = False, samples: int = 200, seed: int = 0,
          tol: float = 1e-6) -> Match:
    """Is ``candidate`` the same robot as ``reference``?

    Parameters
    ----------
    reference, candidate : Robot
        Any conventions; compared in the world frame (their ``base`` included).
    allow_offsets : bool
        Allow each candidate joint a constant offset and a sign change.
    free_base, free_tool : bool
        Allow any constant base / tool transform between the two.
    samples : int
        Random reference configurations (within its limits; unlimited
        revolute joints over [-pi, pi], unlimited prismatic joints over
        +-length scale) on which the answer is checked, besides q = 0.
    seed : int
        Seed of those samples.
    tol : float
        Tolerance: positions relative to the length scale (the larger
        characteristic length of the two robots), angles in rad.

    Returns
    -------
    Match

    Raises
    ------
    ValueError
        ``samples < 1`` or ``tol <= 0``.
    """
    if samples < 1:
        raise ValueError("samples must be at least 1")
    if not tol > 0:
        raise ValueError("tol must be positive")
    n_r, n_c = reference.dof, candidate.dof
    L = max(reference.characteristic_length, candidate.characteristic_length)
    opts = dict(allow_offsets=allow_offsets, free_base=free_base, free_tool=free_tool,
                length_scale=L, tol=tol)
    nan = float("nan")
    if n_r != n_c:
        return Match(False, np.ones(n_r), np.zeros(n_r), None, None, nan, nan, np.zeros(0),
                     None, f"the reference has {n_r} joint{'s' * (n_r != 1)}, "
                           f"the candidate {n_c}", kind="dof", **opts)
    for i, (jr, jc) in enumerate(zip(reference.joints, candidate.joints)):
        if jr.type != jc.type:
            same_q = _Solution(np.ones(n_r), np.zeros(n_r), None, None)
            errors = _fk_errors(reference, candidate, same_q,
                                _samples(reference, samples, seed, L), L)
            return dataclasses.replace(
                _result(reference, same_q, errors, i + 1, None, None, opts), kind="type",
                reason=f"joint {i + 1} ({jr.name}) is {jc.type} in the candidate, "
                       f"{jr.type} in the reference")

    solutions, failure = _Solver(reference, candidate, allow_offsets, free_base, free_tool,
                                 L, tol).run()
    q = _samples(reference, samples, seed, L)
    if solutions is not None:
        for sol in solutions:   # best first; the first that FK confirms is the answer
            errors = _fk_errors(reference, candidate, sol, q, L)
            if errors[0] <= tol * L and errors[1] <= tol:
                return _result(reference, sol, errors, None, None, None, opts)
        # every axis matched within tol but FK does not (a borderline tolerance): the
        # differences are reported as the tool's
        errors = _fk_errors(reference, candidate, solutions[0], q, L)
        return _result(reference, solutions[0], errors, n_r + 1, errors[1], errors[0], opts)
    errors = _fk_errors(reference, candidate, failure.solution, q, L)
    hint = not allow_offsets and match(
        reference, candidate, allow_offsets=True, free_base=free_base, free_tool=free_tool,
        samples=samples, seed=seed, tol=tol).same
    return _result(reference, failure.solution, errors, failure.joint, failure.angle,
                   failure.distance, opts, hint)


# --- the solution and its check ------------------------------------------------

@dataclass
class _Solution:
    signs: np.ndarray
    offsets: np.ndarray
    base: np.ndarray | None       # B (4, 4)
    tool: np.ndarray | None       # T (4, 4)
    score: tuple = ()


@dataclass
class _Failure:
    joint: int                    # 1-based; n + 1 for the tool
    angle: float | None
    distance: float | None
    solution: _Solution


def _samples(robot, count, seed, L) -> np.ndarray:
    """``(count + 1, n)``: q = 0 and ``count`` uniform samples within the limits."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.limits.T.copy()
    rev = robot.is_revolute
    lo = np.where(np.isfinite(lo), lo, np.where(rev, -np.pi, -L))
    hi = np.where(np.isfinite(hi), hi, np.where(rev, np.pi, L))
    return np.vstack([np.zeros(robot.dof), rng.uniform(lo, hi, (count, robot.dof))])


def _fk_errors(reference, candidate, sol: _Solution, q, L):
    """(position error m, orientation error rad, worst q) of ``sol`` over ``q (N, n)``."""
    Tr = reference.fk(q)
    if sol.base is not None:
        Tr = sol.base @ Tr
    if sol.tool is not None:
        Tr = Tr @ sol.tool
    Tc = candidate.fk(q * sol.signs + sol.offsets)
    dp = np.linalg.norm(Tc[:, :3, 3] - Tr[:, :3, 3], axis=-1)
    # the angle from the chord: ||R_a - R_b||_F = 2 sqrt(2) sin(angle / 2), exact near 0
    chord = np.linalg.norm(Tc[:, :3, :3] - Tr[:, :3, :3], axis=(-2, -1)) / (2 * math.sqrt(2))
    da = 2 * np.arcsin(np.clip(chord, 0.0, 1.0))
    worst = int(np.argmax(dp / L + da))
    return float(dp.max()), float(da.max()), q[worst].copy()


def _result(reference, sol, errors, bad, angle, dist, opts, hint=False) -> Match:
    """The Match of solution ``sol`` with FK ``errors``; ``bad`` is the first bad
    joint (None: the same robot), ``angle``/``dist`` how far it is off."""
    kind = "same" if bad is None else ("tool" if bad == reference.dof + 1 else "axis")
    m = Match(same=bad is None, signs=sol.signs.copy(), offsets=sol.offsets.copy() + 0.0,
              base=sol.base, tool=sol.tool, position_error=errors[0],
              orientation_error=errors[1], worst_q=errors[2], first_bad_joint=bad,
              reason="", kind=kind, miss_angle=angle, miss_distance=dist,
              hint_offsets=hint, **opts)
    m = dataclasses.replace(m, reason=_reason(m, reference, None))
    for arr in (m.signs, m.offsets, m.worst_q):
        arr.setflags(write=False)
    return m


# --- screws ----------------------------------------------------------------------

def _world_screws(robot):
    """Unit screws ``(n, 6)`` ordered ``(v, w)`` in the world frame at q = 0, and
    the tool pose ``M = FK(0)`` (4, 4). Revolute: ``w`` the axis, ``v = p x w``;
    prismatic: ``w = 0``, ``v`` the direction."""
    from ..fk import chain_frames
    q0 = np.zeros(robot.dof)
    frames = chain_frames(robot.chain, q0)
    z, p = frames[:, :3, 2], frames[:, :3, 3]
    screws = np.where(robot.is_revolute[:, None],
                      np.concatenate([cross(p, z), z], axis=-1),
                      np.concatenate([z, np.zeros_like(z)], axis=-1))
    return screws, robot.fk(q0)


def _exp(screw, revolute: bool, x) -> np.ndarray:
    """``exp([screw] x)`` (S, 4, 4) for a unit screw ``(6,)`` and ``x (S,)``."""
    x = np.asarray(x, dtype=float)
    out = np.zeros(x.shape + (4, 4))
    out[..., 3, 3] = 1.0
    v, w = screw[:3], screw[3:]
    if revolute:
        K = skew(w)
        s, c = np.sin(x)[..., None, None], np.cos(x)[..., None, None]
        R = np.eye(3) + s * K + (1.0 - c) * (K @ K)
        point = cross(w, v)                       # the foot of the axis from the origin
        out[..., :3, :3] = R
        out[..., :3, 3] = point - R @ point
    else:
        out[..., :3, :3] = np.eye(3)
        out[..., :3, 3] = x[..., None] * v
    return out


def _ad(T, y) -> np.ndarray:
    """``Ad_T y``: the screw ``y (..., 6)`` moved by the rigid motion ``T (..., 4, 4)``."""
    R, t = T[..., :3, :3], T[..., :3, 3]
    w = np.einsum("...ij,...j->...i", R, y[..., 3:])
    v = np.einsum("...ij,...j->...i", R, y[..., :3]) + cross(t, w)
    return np.concatenate([v, w], axis=-1)


def _bracket(z, y) -> np.ndarray:
    """Lie bracket ``[z, y] = ad_z y`` of screws ``(..., 6)`` (the derivative of
    ``Ad_{exp(z x)} y`` at x = 0)."""
    return np.concatenate([cross(z[..., 3:], y[..., :3]) + cross(z[..., :3], y[..., 3:]),
                           cross(z[..., 3:], y[..., 3:])], axis=-1)


def _hat(z) -> np.ndarray:
    """``[z]`` (..., 4, 4) of a screw ``(..., 6)``."""
    out = np.zeros(z.shape[:-1] + (4, 4))
    out[..., :3, :3] = skew(z[..., 3:])
    out[..., :3, 3] = z[..., :3]
    return out


def _align(src, dst, revolute: bool) -> np.ndarray:
    """A rigid motion (4, 4) taking the axis of screw ``src`` onto that of ``dst``."""
    a = src[3:] if revolute else src[:3]
    b = dst[3:] if revolute else dst[:3]
    axis = np.cross(a, b)
    s, c = np.linalg.norm(axis), float(a @ b)
    if s < 1e-12:
        if c > 0:
            R = np.eye(3)
        else:                                      # half turn about any perpendicular axis
            helper = np.array([1.0, 0, 0]) if abs(a[0]) < 0.9 else np.array([0, 1.0, 0])
            k = np.cross(a, helper)
            k /= np.linalg.norm(k)
            R = 2 * np.outer(k, k) - np.eye(3)
    else:
        K = skew(axis / s)
        R = np.eye(3) + s * K + (1 - c) * (K @ K)
    T = np.eye(4)
    T[:3, :3] = R
    if revolute:
        T[:3, 3] = cross(dst[3:], dst[:3]) - R @ cross(src[3:], src[:3])
    return T


def _perpendiculars(u):
    helper = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    a = np.cross(u, helper)
    a /= np.linalg.norm(a)
    return a, np.cross(u, a)


def _line_miss(y, target, revolute):
    """(angle rad, distance m or None) between the axes of screws ``y`` and ``target``."""
    if revolute:
        u1, u2 = y[3:], target[3:]
    else:
        u1, u2 = y[:3], target[:3]
    angle = math.atan2(np.linalg.norm(np.cross(u1, u2)), float(u1 @ u2))
    if not revolute:
        return angle, None
    p1, p2 = cross(u1, y[:3]), cross(u2, target[:3])
    n = np.cross(u1, u2)
    if np.linalg.norm(n) < 1e-9:
        dist = np.linalg.norm(np.cross(p2 - p1, u1))
    else:
        dist = abs(float((p2 - p1) @ n)) / np.linalg.norm(n)
    return angle, float(dist)


# --- the solver ----------------------------------------------------------------

class _Solver:
    """Offsets, signs and base from the screw equations, branch by branch."""

    def __init__(self, reference, candidate, allow_offsets, free_base, free_tool, L, tol):
        self.ref, self.cand = reference, candidate
        self.allow, self.free_base, self.free_tool = allow_offsets, free_base, free_tool
        self.L, self.tol = L, tol
        self.n = reference.dof
        self.rev = reference.is_revolute
        self.xi, self.M_r = _world_screws(reference)
        self.eta0, self.M_c0 = _world_screws(candidate)
        self.signs_allowed = (1, -1) if allow_offsets else (1,)
        self.W6 = np.array([1 / L] * 3 + [1.0] * 3)
        W4 = np.ones((3, 4))
        W4[:, 3] = 1 / L
        self.W4 = W4.ravel()
        self.last = self.n if free_tool else self.n + 1

    # -- setting up one problem (one alignment of the base) ---------------
    def _setup(self, s1):
        """Candidate screws and params for base alignment sign ``s1`` (free_base)."""
        n = self.n
        if self.free_base:
            A0 = _align(self.eta0[0], s1 * self.xi[0], self.rev[0])
        else:
            A0 = np.eye(4)
        self.A0 = A0
        self.eta = _ad(A0, self.eta0)
        self.M_c = A0 @ self.M_c0
        params = []                      # (screw, revolute, position, joint)
        if self.free_base:
            x1 = self.xi[0]
            if self.rev[0]:
                params += [(x1.copy(), True, 0, None),
                           (np.concatenate([x1[3:], np.zeros(3)]), False, 0, None)]
            else:
                u = x1[:3]
                a, b = _perpendiculars(u)
                params += [(np.concatenate([np.zeros(3), u]), True, 0, None)]
                params += [(np.concatenate([d, np.zeros(3)]), False, 0, None) for d in (a, b, u)]
        if self.allow:
            for i in range(n):
                if self.free_base and i == 0:
                    continue             # absorbed by the base
                params.append((self.eta[i], bool(self.rev[i]), i + 1, i))
        self.params = params
        self.P = len(params)
        self.pos = np.array([p[2] for p in params], dtype=int)

    def run(self):
        """([solutions best first] or None, failure or None)."""
        leaves, failures = [], []
        for s1 in (self.signs_allowed if self.free_base else (1,)):
            self._setup(s1)
            self.leaves, self.failure, self.nodes = [], None, 0
            signs = np.zeros(self.n, dtype=int)
            if self.free_base:
                signs[0] = s1
            first = 2 if self.free_base else 1
            self._visit(first, np.zeros(self.P), signs, frozenset())
            leaves += [self._finish(x, sg) for x, sg in self.leaves]
            if self.failure is not None:
                failures.append(self._failure_result(*self.failure))
        if leaves:
            leaves.sort(key=lambda s: s.score)
            return leaves[:4], None
        failures.sort(key=lambda f: (-f.joint, f.angle or 0.0, f.distance or 0.0))
        return None, failures[0]

    # -- the branch search ----------------------------------------------------
    def _visit(self, step, x, signs, U):
        self.nodes += 1
        if self.nodes > MAX_NODES:
            return
        if step > self.last:
            self.leaves.append((x, signs))
            return
        # the params that join now: those of G_{step-1} not met before
        first = 2 if self.free_base else 1
        new = [p for p in range(self.P) if self.pos[p] <= step - 1
               and (step == first or self.pos[p] == step - 1)]
        V = sorted(set(U) | set(new))
        roots, miss = self._solve(step, V, x, signs)
        if not roots:
            if self.failure is None or step > self.failure[0] or \
                    (step == self.failure[0] and miss[0] < self.failure[1][0]):
                self.failure = (step, miss, x, signs)
            return
        for x2, s, pinned in roots:
            signs2 = signs.copy()
            if step <= self.n:
                signs2[step - 1] = s
            self._visit(step + 1, x2, signs2, frozenset(set(V) - pinned))

    # -- evaluating the equations ------------------------------------------
    def _chain(self, X):
        """For param values ``X (S, P)``: G_k (S, 4, 4) for k = 0..n and each
        param's current world screw (S, P, 6)."""
        S = X.shape[0]
        G = np.broadcast_to(np.eye(4), (S, 4, 4)).copy()
        Gs = [None] * (self.n + 1)
        Z = np.zeros((S, self.P, 6))
        p = 0
        for k in range(self.n + 1):
            while p < self.P and self.pos[p] == k:
                screw, revolute, _, _ = self.params[p]
                Z[:, p] = _ad(G, screw)
                G = G @ _exp(screw, revolute, X[:, p])
                p += 1
            Gs[k] = G
        return Gs, Z

    def _residuals(self, X, signs, steps, V, step_signs=None):
        """Residuals (S, m) and Jacobian (S, m, |V|) of the equations ``steps``.

        ``signs`` (n,) gives the sign of each earlier screw equation; the
        current one (the last of ``steps`` when it is a screw) takes
        ``step_signs (S,)``.
        """
        Gs, Z = self._chain(X)
        S = X.shape[0]
        rs, Js = [], []
        for j in steps:
            if j <= self.n:
                y = _ad(Gs[j - 1], self.eta[j - 1])
                s = step_signs if (step_signs is not None and j == steps[-1]) \
                    else np.full(S, signs[j - 1])
                rs.append((y - s[:, None] * self.xi[j - 1]) * self.W6)
                cols = [(_bracket(Z[:, p], y) * self.W6) if self.pos[p] <= j - 1
                        else np.zeros((S, 6)) for p in V]
            else:
                GM = Gs[self.n] @ self.M_c
                rs.append(((GM - self.M_r)[:, :3, :].reshape(S, 12)) * self.W4)
                cols = [((_hat(Z[:, p]) @ GM)[:, :3, :].reshape(S, 12)) * self.W4 for p in V]
            Js.append(np.stack(cols, axis=-1) if V else np.zeros((S, rs[-1].shape[1], 0)))
        return np.concatenate(rs, axis=1), np.concatenate(Js, axis=1)

    def _solve(self, step, V, x, signs):
        """Roots [(x, sign, pinned params)] of equation ``step`` and the miss
        (residual, x, sign) of the best attempt."""
        signs_try = self.signs_allowed if step <= self.n else (0,)
        if not V:
            roots, best = [], None
            for s in signs_try:
                r, _ = self._residuals(x[None], signs, [step], V, np.array([s]))
                res = float(np.linalg.norm(r))
                if best is None or res < best[0]:
                    best = (res, x, s)
                if res < self.tol:
                    roots.append((x, s, frozenset()))
            return roots, best
        if len(V) == 1:
            return self._solve_one(step, V[0], x, signs, signs_try)
        return self._solve_many(step, V, x, signs, signs_try)

    def _split(self, p, x, upto):
        """A, B (4, 4): the products of the params before and after ``p`` with
        position <= ``upto``."""
        A, B = np.eye(4), np.eye(4)
        for k in range(self.P):
            if self.pos[k] > upto or k == p:
                continue
            E = _exp(self.params[k][0], self.params[k][1], np.array(x[k]))
            if k < p:
                A = A @ E
            else:
                B = B @ E
        return A, B

    def _solve_one(self, step, p, x, signs, signs_try):
        screw, revolute = self.params[p][0], self.params[p][1]
        A, B = self._split(p, x, step - 1 if step <= self.n else self.n)
        roots, best = [], None
        for s in signs_try:
            if step <= self.n:
                y = _ad(B, self.eta[step - 1])
                t = _ad(invert_transform(A), s * self.xi[step - 1])
                r0 = (y - t) * self.W6
                a1 = _bracket(screw, y)
                a2 = _bracket(screw, a1) * self.W6
                a1 = a1 * self.W6
            else:
                D = invert_transform(A) @ self.M_r @ invert_transform(B @ self.M_c)
                Z = _hat(screw)
                r0 = ((np.eye(4) - D)[:3]).ravel() * self.W4
                a1 = (Z[:3]).ravel() * self.W4
                a2 = ((Z @ Z)[:3]).ravel() * self.W4
            free, xs, res = _roots_1d(r0, a1, a2, revolute, self.tol)
            if free:
                if res < self.tol:
                    roots.append((x, s, frozenset()))
                cand = [(res, x[p])]
            else:
                cand = xs
            for resk, xk in cand:
                xn = x.copy()
                xn[p] = xk
                if best is None or resk < best[0]:
                    best = (resk, xn, s)
                if not free and resk < self.tol:
                    roots.append((xn, s, frozenset([p])))
        return roots, best

    def _solve_many(self, step, V, x, signs, signs_try):
        """Several unknowns. Once the revolute ones are fixed the equations are
        affine in the prismatic ones, so those are projected out by linear
        least squares; the revolute ones (usually one) are gridded, and damped
        Gauss-Newton on all of them starts from the grid's local minima."""
        first = 2 if self.free_base else 1
        lo = max(min(int(self.pos[p]) for p in V) + 1, first)
        steps = list(range(lo, step + 1))
        Vr = [p for p in V if self.params[p][1]]
        Vp = [i for i, p in enumerate(V) if not self.params[p][1]]
        if len(Vr) == 0:
            grid = np.zeros((1, 0))
        elif len(Vr) == 1:
            grid = np.linspace(-np.pi, np.pi, 72, endpoint=False)[:, None]
        else:
            k = max(3, int(MAX_STARTS ** (1 / len(Vr))))
            axes = [np.linspace(-np.pi, np.pi, k, endpoint=False)] * len(Vr)
            grid = np.array(list(itertools.product(*axes)))
        starts = []
        for s in signs_try:
            X = np.repeat(x[None], len(grid), axis=0)
            if Vr:
                X[:, Vr] = grid
            sg = np.full(len(grid), s)
            r, J = self._residuals(X, signs, steps, V, sg)
            if Vp:
                Jp = J[:, :, Vp]
                d = -np.einsum("sij,sj->si", np.linalg.pinv(Jp), r)
                X[:, [V[i] for i in Vp]] += d
                r = r + np.einsum("sij,sj->si", Jp, d)
            g = np.einsum("ij,ij->i", r, r)
            if len(Vr) == 1:
                keep = np.nonzero((g <= np.roll(g, 1)) & (g <= np.roll(g, -1)))[0]
            else:
                keep = np.argsort(g)[:16]
            starts += [(X[k], s) for k in keep]
        X = np.array([xs for xs, _ in starts])
        sg = np.array([s for _, s in starts])
        X, r, J = _levenberg_marquardt(
            lambda Xv, rows=slice(None): self._residuals(Xv, signs, steps, V, sg[rows]),
            X, V, self.tol)
        res = np.linalg.norm(r, axis=1)
        k = int(np.argmin(res))
        best = (float(res[k]), X[k], int(sg[k]))
        scale = np.array([1.0 if self.params[p][1] else self.L for p in V])
        rev = np.array([self.params[p][1] for p in V])
        roots, kept = [], []
        for k in np.argsort(res):
            if res[k] >= self.tol:
                break
            sv, vt = np.linalg.svd(J[k] * scale, full_matrices=True)[1:]
            rank = int(np.sum(sv > NULL_TOL * max(1.0, sv.max() if sv.size else 0)))
            null = vt[rank:]
            # two roots are one branch when they differ only along the directions the
            # equations leave free (and by whole turns)
            xk = X[k, V] / scale
            dup = False
            for j, xj in kept:
                if sg[j] != sg[k]:
                    continue
                d = np.where(rev, np.remainder(xk - xj + np.pi, 2 * np.pi) - np.pi, xk - xj)
                if null.shape[0]:
                    d = d - null.T @ (null @ d)
                if np.max(np.abs(d)) < 1e-7:
                    dup = True
                    break
            if dup:
                continue
            kept.append((k, xk))
            pinned = frozenset(p for i, p in enumerate(V)
                               if null.shape[0] == 0 or np.linalg.norm(null[:, i]) < 1e-6)
            roots.append((X[k].copy(), int(sg[k]), pinned))
        return roots, best

    # -- results ----------------------------------------------------------------
    def _finish(self, x, signs) -> _Solution:
        x = x.copy()
        for p in range(self.P):
            if self.params[p][1]:
                x[p] = math.remainder(x[p], 2 * math.pi)
        # offsets nothing determined (the tool's, or a joint commuting with all later
        # ones when the tool is free) are set to 0 when that keeps every equation
        steps = list(range(2 if self.free_base else 1, self.last + 1))
        for p in range(self.P):
            if self.params[p][3] is None or x[p] == 0:
                continue
            trial = x.copy()
            trial[p] = 0.0
            r, _ = self._residuals(trial[None], signs, steps, [])
            if np.linalg.norm(r) < self.tol:
                x = trial
        return self._solution(x, signs)

    def _solution(self, x, signs) -> _Solution:
        n = self.n
        offsets = np.zeros(n)
        for p in range(self.P):
            j = self.params[p][3]
            if j is not None:
                offsets[j] = x[p]
        signs = np.where(signs == 0, 1, signs).astype(float)
        base = tool = None
        Binv = None
        if self.free_base:
            E = np.eye(4)
            for p in range(self.P):
                if self.pos[p] == 0:
                    E = E @ _exp(self.params[p][0], self.params[p][1], np.array(x[p]))
            Binv = E @ self.A0
            base = invert_transform(Binv)
        if self.free_tool:
            Tc = self.cand.fk(offsets)
            tool = invert_transform(self.M_r) @ (Binv if Binv is not None else np.eye(4)) @ Tc
        flips = int(np.sum(signs < 0))
        size = float(np.sum(np.abs(offsets) / np.where(self.rev, 1.0, self.L)))
        return _Solution(signs, offsets, base, tool, (flips, round(size, 9)))

    def _failure_result(self, step, miss, x, signs) -> _Failure:
        res, xb, s = miss
        Gs, _ = self._chain(xb[None])
        sol = self._solution(xb, signs if step > self.n else _with(signs, step - 1, s))
        if step <= self.n:
            y = _ad(Gs[step - 1][0], self.eta[step - 1])
            angle, dist = _line_miss(y, (s or 1) * self.xi[step - 1], bool(self.rev[step - 1]))
            if self.allow:   # the sign is free: the angle between undirected axes
                angle = min(angle, math.pi - angle)
        else:
            GM = Gs[self.n][0] @ self.M_c
            chord = np.linalg.norm(GM[:3, :3] - self.M_r[:3, :3]) / (2 * math.sqrt(2))
            angle = 2 * math.asin(min(1.0, chord))
            dist = float(np.linalg.norm(GM[:3, 3] - self.M_r[:3, 3]))
        return _Failure(step, angle, dist, sol)


def _with(signs, i, s):
    out = signs.copy()
    out[i] = s if s else 1
    return out


def _roots_1d(r0, a1, a2, revolute, tol):
    """Roots of ``r(x) = r0 + sin(x) a1 + (1 - cos x) a2`` (revolute) or
    ``r0 + x a1`` (prismatic), vectors of any length.

    Returns ``(free, [(|r|, x), ...], |r0|)``: ``free`` when r does not depend on
    x; otherwise every local minimum of |r| (the roots are those with |r| ~ 0).
    ``|r|^2`` is a trigonometric polynomial of degree 2 in x, so it has at most
    two minima; a 72-point grid separates them and Gauss-Newton polishes each.
    """
    scale = max(1.0, float(np.linalg.norm(r0)))
    if np.linalg.norm(a1) < INVARIANT_TOL * scale and np.linalg.norm(a2) < INVARIANT_TOL * scale:
        return True, [], float(np.linalg.norm(r0))
    if not revolute:
        x = -float(a1 @ r0) / float(a1 @ a1)
        return False, [(float(np.linalg.norm(r0 + x * a1)), x)], 0.0
    grid = np.linspace(-np.pi, np.pi, 72, endpoint=False)
    R = r0 + np.sin(grid)[:, None] * a1 + (1 - np.cos(grid))[:, None] * a2
    g = np.einsum("ij,ij->i", R, R)
    mins = np.nonzero((g <= np.roll(g, 1)) & (g <= np.roll(g, -1)))[0]
    x = grid[mins]
    for _ in range(30):
        s, c = np.sin(x)[:, None], np.cos(x)[:, None]
        r = r0 + s * a1 + (1 - c) * a2
        dr = c * a1 + s * a2
        num = np.einsum("ij,ij->i", r, dr)
        den = np.einsum("ij,ij->i", dr, dr)
        step = -num / np.where(den > 0, den, 1.0)
        x = x + np.clip(step, -0.3, 0.3)
        if np.all(np.abs(step) < 1e-15):
            break
    r = r0 + np.sin(x)[:, None] * a1 + (1 - np.cos(x))[:, None] * a2
    res = np.linalg.norm(r, axis=1)
    out = []
    for rk, xk in sorted(zip(res.tolist(), x.tolist())):
        xk = math.remainder(xk, 2 * math.pi)
        if all(abs(math.remainder(xk - xo, 2 * math.pi)) > 1e-9 for _, xo in out):
            out.append((rk, xk))
    return False, out, 0.0


def _levenberg_marquardt(fun, X, V, tol, iterations=50):
    """Damped Gauss-Newton on every start at once; ``fun(X, rows) -> (r (S, m), J (S, m, v))``
    for the starts ``rows`` (all by default), J the derivative by the params ``V``.
    Returns (X, r, J) at the end.

    A start stops when its residual is at rounding level or its step is."""
    r, J = fun(X)
    cost = np.einsum("ij,ij->i", r, r)
    lam = np.full(X.shape[0], 1e-4)
    eye = np.eye(len(V))
    active = np.ones(X.shape[0], dtype=bool)
    for _ in range(iterations):
        a = np.nonzero(active)[0]
        if a.size == 0:
            break
        Ja, ra = J[a], r[a]
        JTJ = np.einsum("smi,smj->sij", Ja, Ja)
        g = np.einsum("smi,sm->si", Ja, ra)
        diag = np.diagonal(JTJ, axis1=1, axis2=2)
        Amat = JTJ + lam[a, None, None] * (eye * diag[:, None, :] + 1e-9 * eye)
        d = np.linalg.solve(Amat, -g[..., None])[..., 0]
        Xt = X[a].copy()
        Xt[:, V] += d
        rt, Jt = fun(Xt, a)
        ct = np.einsum("ij,ij->i", rt, rt)
        ok = ct < cost[a]
        # near a root Gauss-Newton converges quadratically; a start whose accepted
        # step gains less than 1% while far from zero sits in a local minimum
        stalled = ok & (ct > 0.99 * cost[a]) & (ct > (0.01 * tol) ** 2)
        idx = a[ok]
        X[idx], r[idx], J[idx], cost[idx] = Xt[ok], rt[ok], Jt[ok], ct[ok]
        lam[a] = np.clip(np.where(ok, lam[a] * 0.1, lam[a] * 10.0), 1e-12, 1e12)
        small = np.abs(d).max(axis=1) < 1e-14
        active[a] = ~((cost[a] < 1e-30) | small | stalled | (lam[a] >= 1e8))
    return X, r, J


# --- words ------------------------------------------------------------------------

def _fmt(x, precision=4) -> str:
    s = f"{x:.{precision}g}" if abs(x) >= 1e-4 or x == 0 else f"{x:.2e}"
    return "0" if s in ("-0", "0") else s


def _reason(m: Match, reference, units, precision: int = 4) -> str:
    """The one-line reason of ``m`` in ``units`` (default: reference's length, degrees)."""
    if units is None:
        from .results import Units
        units = Units(angle="deg", length=reference.length_unit)
    n = len(m.signs)
    a_unit = f" {units.angle}"
    l_unit = "" if units.length == "unitless" else f" {units.length}"

    def ang(x):
        return f"{_fmt(x * units.a, precision)}{a_unit}"

    def length(x):
        return f"{_fmt(x * units.l, precision)}{l_unit}"

    if m.same:
        changed = [i for i in range(n) if m.signs[i] < 0 or m.offsets[i] != 0]
        frames = [w for w, v in (("base", m.base), ("tool", m.tool)) if v is not None
                  and not np.allclose(v, np.eye(4), atol=1e-12)]
        text = "same robot"
        if changed:
            text += (" up to joint offsets and signs (joint"
                     f"{'s' * (len(changed) > 1)} {_join([str(i + 1) for i in changed])})")
        if frames:
            text += (" and " if changed else " up to ") + " and ".join(
                f"a different {w} frame" for w in frames)
        return text
    if m.kind in ("dof", "type"):
        return m.reason
    j = m.first_bad_joint
    tol_l, tol_a = m.tol * m.length_scale, m.tol
    hint = ("; with joint offsets and sign changes allowed they are the same robot"
            if m.hint_offsets else "")
    if j == n + 1:
        what = "every joint axis matches"
        if m.allow_offsets:
            what += " (with the offsets found)"
        if m.miss_angle is None:
            return f"{what}, but the tool frame differs{hint}"
        parts = []
        if m.miss_distance is not None and m.miss_distance > tol_l:
            parts.append(f"{length(m.miss_distance)} apart")
        if m.miss_angle > tol_a:
            parts.append(f"turned {ang(m.miss_angle)} from each other")
        detail = " and ".join(parts) or "by a tiny amount"
        return f"{what}, but the tool frames at the matched zero are {detail}{hint}"
    name = reference.joints[j - 1].name
    given = "" if j == 1 else (
        " given joint 1" if j == 2 else f" given joints 1-{j - 1}")
    if m.allow_offsets:
        head = f"joint {j} ({name}): its axis cannot be made to match the reference's{given}"
    else:
        head = (f"joint {j} ({name}): its axis differs from the reference's at the zero "
                "configuration")
    bits = []
    skew_lines = m.miss_angle is not None and tol_a < m.miss_angle < math.pi - tol_a
    if m.miss_angle is not None:
        if not m.allow_offsets and abs(m.miss_angle - math.pi) <= tol_a:
            bits.append("it points the opposite way")
        elif m.miss_angle > tol_a:
            bits.append(f"its direction is off by {ang(m.miss_angle)}")
    if m.miss_distance is not None and m.miss_distance > tol_l:
        bits.append(f"it passes {length(m.miss_distance)} from the reference axis"
                    if skew_lines else f"it is {length(m.miss_distance)} away")
    best = " at best" if m.allow_offsets and j > 1 else ""
    detail = f":{best} {' and '.join(bits)}" if bits else ""
    return head + detail + hint


def _join(items):
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def describe(m: Match, reference, units, precision: int = 4) -> list[str]:
    """Readable lines about ``m`` in display ``units`` (a :class:`~kincalc.analysis.results.Units`).

    The first line is the reason; then, for each joint with an offset or a
    sign change, where the candidate's zero lies in the reference's joint
    values (candidate q_i = 0 is reference q_i = -signs[i] * offsets[i]) and
    whether it turns the other way; then the base and tool frames when free.
    """
    lines = [_reason(m, reference, units, precision)]
    a_unit = f" {units.angle}"
    l_unit = "" if units.length == "unitless" else f" {units.length}"
    for i, j in enumerate(reference.joints):
        s, c = m.signs[i], m.offsets[i]
        if s > 0 and c == 0:
            continue
        zero = -s * c
        value = (f"{_fmt(zero * units.a, precision)}{a_unit}" if j.revolute
                 else f"{_fmt(zero * units.l, precision)}{l_unit}")
        bits = []
        if s < 0:
            bits.append("opposite sign")
        if c != 0:
            bits.append(f"candidate zero is at reference {j.name} = {value}")
        lines.append(f"joint {i + 1} ({j.name}): " + ", ".join(bits))
    from ..spatial import rpy_from_matrix
    for word, T in (("base", m.base), ("tool", m.tool)):
        if T is None:
            continue
        xyz = ", ".join(_fmt(v * units.l, precision) for v in T[:3, 3])
        rpy = ", ".join(_fmt(v * units.a, precision) for v in rpy_from_matrix(T[:3, :3]))
        rule = ("candidate = base * reference" if word == "base"
                else "candidate = reference * tool")
        lines.append(f"{word} ({rule}): xyz ({xyz}){l_unit}, rpy ({rpy}){a_unit}")
    return lines


# --- the compare command's result ----------------------------------------------

@dataclass(frozen=True)
class CompareResult:
    """``kincalc compare``: the match of ``candidate`` against ``reference``,
    with the display units and the inputs to echo.

    ``arguments`` are the two robots as the user named them.
    """

    reference: object
    candidate: object
    match: Match
    units: object
    samples: int
    seed: int
    tol: float
    arguments: tuple = ("", "")

    def to_dict(self) -> dict:
        from .results import SCHEMA_VERSION, json_numbers, robot_summary
        m, u, ref = self.match, self.units, self.reference

        def value(x, scale):
            return None if x is None or not math.isfinite(x) else json_numbers(x * scale)

        evaluated = m.worst_q.size == ref.dof
        return {
            "kincalc": SCHEMA_VERSION,
            "command": "compare",
            "robots": [dict(robot_summary(r), argument=a)
                       for r, a in zip((ref, self.candidate), self.arguments)],
            "units": u.to_dict(),
            "allow_offsets": m.allow_offsets,
            "free_base": m.free_base,
            "free_tool": m.free_tool,
            "samples": self.samples,
            "seed": self.seed,
            "tolerance": self.tol,
            "length_scale": json_numbers(m.length_scale * u.l),
            "position_tolerance": json_numbers(self.tol * m.length_scale * u.l),
            "orientation_tolerance": json_numbers(self.tol * u.a),
            "same": m.same,
            "position_error": value(m.position_error, u.l),
            "orientation_error": value(m.orientation_error, u.a),
            "worst_q": u.joints(ref, m.worst_q) if evaluated else None,
            "offsets": u.joints(ref, m.offsets),
            "signs": [int(s) for s in m.signs],
            "first_bad_joint": m.first_bad_joint,
            "reason": _reason(m, ref, u),
            "base": None if m.base is None else u.pose(m.base),
            "tool": None if m.tool is None else u.pose(m.tool),
            "explanation": describe(m, ref, u),
        }


def compare(reference, candidate, units, *, arguments=("", ""), samples: int = 200,
            seed: int = 0, tol: float = 1e-6, **options) -> CompareResult:
    """:func:`match` wrapped with its display ``units`` for the ``compare`` command.

    ``options`` are those of :func:`match` (allow_offsets, free_base, free_tool).
    """
    m = match(reference, candidate, samples=samples, seed=seed, tol=tol, **options)
    return CompareResult(reference, candidate, m, units, samples, seed, tol, tuple(arguments))
