"""Are two robot descriptions the same robot? :func:`match` answers with a
:class:`Match` (see the package docstring for the method).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ...spatial import invert_transform
from .search import Solution, Solver
from .words import reason_text


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


#: the tolerance of a second search when every solution of the first misses FK
SEARCH_TOL = 1e-6


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
        Tolerance: positions relative to the length scale (the smaller
        characteristic length of the two robots: large offsets that cancel in
        one of them would widen the larger to metres), angles in rad.

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
    L = min(reference.characteristic_length, candidate.characteristic_length)
    opts = dict(allow_offsets=allow_offsets, free_base=free_base, free_tool=free_tool,
                length_scale=L, tol=tol)
    nan = float("nan")
    if n_r != n_c:
        return Match(False, np.ones(n_r), np.zeros(n_r), None, None, nan, nan, np.zeros(0),
                     None, f"the reference has {n_r} joint{'s' * (n_r != 1)}, "
                           f"the candidate {n_c}", kind="dof", **opts)
    for i, (jr, jc) in enumerate(zip(reference.joints, candidate.joints)):
        if jr.type != jc.type:
            same_q = Solution(np.ones(n_r), np.zeros(n_r), None, None)
            errors = _fk_errors(reference, candidate, same_q,
                                _samples(reference, samples, seed, L), L)
            return dataclasses.replace(
                _result(reference, same_q, errors, i + 1, None, None, opts), kind="type",
                reason=f"joint {i + 1} ({jr.name}) is {jc.type} in the candidate, "
                       f"{jr.type} in the reference")

    q = _samples(reference, samples, seed, L)
    # the same joint variables first (no sign change, no offset: the best score), so
    # that the reference's own rows say so where the joints leave offsets undetermined
    same = _confirmed(reference, candidate, [_same_joints(reference, candidate, free_base,
                                                          free_tool)], q, L, tol)
    if same is not None:
        return _result(reference, *same, None, None, None, opts)
    search = (reference, candidate, allow_offsets, free_base, free_tool, L)
    solutions, failure = Solver(*search, tol).run()
    if solutions is not None:
        return _solved(search, solutions, q, tol, opts)
    errors = _fk_errors(reference, candidate, failure.solution, q, L)
    hint = not allow_offsets and match(
        reference, candidate, allow_offsets=True, free_base=free_base, free_tool=free_tool,
        samples=samples, seed=seed, tol=tol).same
    return _result(reference, failure.solution, errors, failure.joint, failure.angle,
                   failure.distance, opts, hint)


# --- the check by forward kinematics ------------------------------------------

def _samples(robot, count, seed, L) -> np.ndarray:
    """``(count + 1, n)``: q = 0 and ``count`` uniform samples within the limits."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.limits.T.copy()
    rev = robot.is_revolute
    lo = np.where(np.isfinite(lo), lo, np.where(rev, -np.pi, -L))
    hi = np.where(np.isfinite(hi), hi, np.where(rev, np.pi, L))
    return np.vstack([np.zeros(robot.dof), rng.uniform(lo, hi, (count, robot.dof))])


def _solved(search, solutions, q, tol, opts) -> Match:
    """The Match once the branch search found ``solutions``: the first FK confirms,
    else (a borderline tolerance) the best, its differences reported as the tool's."""
    reference, candidate, L, n_r = search[0], search[1], search[5], search[0].dof
    sol = _confirmed(reference, candidate, solutions, q, L, tol)
    if sol is None and tol > SEARCH_TOL:
        # roots within a loose tolerance may miss FK by a few times it (the equations
        # hold at q = 0, the samples lie far from it): again, strictly
        sol = _confirmed(reference, candidate, Solver(*search, SEARCH_TOL).run()[0] or [],
                         q, L, tol)
    if sol is not None:
        return _result(reference, *sol, None, None, None, opts)
    errors = _fk_errors(reference, candidate, solutions[0], q, L)
    return _result(reference, solutions[0], errors, n_r + 1, errors[1], errors[0], opts)


def _confirmed(reference, candidate, solutions, q, L, tol):
    """The first of ``solutions`` (best first) that FK confirms, with its errors; None."""
    for sol in solutions:
        errors = _fk_errors(reference, candidate, sol, q, L)
        if errors[0] <= tol * L and errors[1] <= tol:
            return sol, errors
    return None


def _same_joints(reference, candidate, free_base, free_tool) -> Solution:
    """Signs 1, offsets 0, and the base and tool that make the candidate the reference
    when their chains from frame 0 to frame n agree."""
    n = reference.dof
    base = candidate.base @ invert_transform(reference.base) if free_base else None
    tool = invert_transform(reference.tool) @ candidate.tool if free_tool else None
    return Solution(np.ones(n), np.zeros(n), base, tool)


def _fk_errors(reference, candidate, sol: Solution, q, L):
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
    m = dataclasses.replace(m, reason=reason_text(m, reference, None))
    for arr in (m.signs, m.offsets, m.worst_q):
        arr.setflags(write=False)
    return m
