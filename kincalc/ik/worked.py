"""The worked steps of ``--explain``: what a step of a closed form records, as data.

A solver step notes its equation with the numbers it solved (nothing without
``explain``: a batch of poses pays nothing); :mod:`kincalc.analysis.explain` writes them
the way a textbook chapter does, in the user's units. The kinds:

* ``abc:J:WHAT:A`` — joint J from ``A cos qJ + B sin qJ + C = t`` (value ``(..., 6)``:
  A, B, C, t, and for a distance the triangle's sides l1, l2 or NaN), an invariant of
  joint A's motion: ``height`` along its axis (m), ``distance2``, the squared distance
  from a point of it (m^2), or ``across`` its sliding axis (m);
* ``turn:J`` — joint J turning a point onto its target about its axis (value
  ``(..., 4)``: the target's and the point's coordinates in the plane normal to the
  axis, ``(g1, g2, f1, f2)`` in m, on the basis of :func:`plane_basis`), so
  ``qJ = atan2(g2, g1) - atan2(f2, f1)``;
* ``quad:J:WHAT:A`` — sliding joint J from ``A dJ^2 + B dJ + C = t`` (value ``(..., 4)``:
  A, B, C, t), the invariant ``WHAT`` of joint A's motion as for ``abc`` (SI: the
  invariant in m, or m^2 for ``distance2``, dJ in m);
* ``roll:J`` — joint J turning a fixed direction ``e`` normal to its axis onto the one the
  target's orientation needs, ``u`` (the joints before it undone): value ``(..., 4)``,
  ``(u1, u2, e1, e2)`` on the basis of :func:`plane_basis` (unitless), so
  ``qJ = atan2(u2, u1) - atan2(e2, e1)``;
* ``slide:J`` — sliding joint J moving a point onto its target along its axis (value
  ``(..., 2)``: the target's and the point's components along the axis, ``(g, f)`` in m),
  so ``dJ = g - f``.
"""

from __future__ import annotations

import numpy as np

from .branches import Branches


def plane_basis(k) -> np.ndarray:
    """``(2, 3)``: unit ``e1, e2`` spanning the plane normal to the unit axis ``k``,
    counterclockwise about it (``e2 = k x e1``): the world's x and y for ``k = z``.

    Parameters
    ----------
    k : array_like (3,), unit

    Returns
    -------
    ndarray (2, 3)
    """
    k = np.asarray(k, float)
    x = np.array([1.0, 0, 0]) if abs(k[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = x - (x @ k) * k
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(k, e1)])


def note_equation(br: Branches, joint: int, what: str, pivot: int, A, B, C, t,
                  sides=(np.nan, np.nan)) -> Branches:
    """``br`` with ``A cos q + B sin q + C = t`` for ``joint`` noted (``explain`` only).

    Parameters
    ----------
    br : Branches, at the slots the coefficients belong to
    joint : int, the joint solved (0-based)
    what : str, ``height``, ``distance2``, ``across`` (the module docstring) or ``direction``
        (the component along joint ``pivot``'s axis of the last axis's direction, unitless)
    pivot : int, the joint whose invariant it is (0-based)
    A, B, C, t : array_like, broadcast to (N, K) (SI: m, or m^2 for ``distance2``)
    sides : pair of array_like, broadcast to (N, K), optional
        For a distance: from the point of joint ``pivot``'s axis to the centre of the
        circle joint ``joint`` moves the point on, and that circle's radius (m); the law
        of cosines when ``C = l1^2 + l2^2`` and ``|A| = 2 l1 l2`` (a planar triangle)

    Returns
    -------
    Branches
    """
    if not br.explain:
        return br
    value = np.stack(np.broadcast_arrays(A, B, C, t, *sides), -1)
    return br.note("A cos + B sin + C = t", np.broadcast_to(value, (br.N, br.K, 6)),
                   f"abc:{joint}:{what}:{pivot}")


def note_turn(S, br: Branches, joint: int, f, g) -> Branches:
    """``br`` with joint ``joint``'s turn of the points ``f`` onto ``g`` noted (``explain``
    only).

    Parameters
    ----------
    S : Screws, the chain (world frame at q = 0, m)
    br : Branches
    joint : int, revolute (0-based)
    f, g : ndarray (N, K, 3), the point with the joint at 0 and its target (m)

    Returns
    -------
    Branches
    """
    if not br.explain:
        return br
    o = S.point[joint]
    return _turn_in_plane(S, br, "turn", joint, f - o, g - o)


def note_quadratic(br: Branches, joint: int, what: str, pivot: int, A, B, C, t) -> Branches:
    """``br`` with ``A d^2 + B d + C = t`` for the sliding ``joint`` noted (``explain``
    only; ``what`` and ``pivot`` as for :func:`note_equation`; ``A, B, C, t`` broadcast to
    (N, K), SI)."""
    if not br.explain:
        return br
    value = np.stack(np.broadcast_arrays(A, B, C, t), -1)
    return br.note("A d^2 + B d + C = t", np.broadcast_to(value, (br.N, br.K, 4)),
                   f"quad:{joint}:{what}:{pivot}")


def note_direction(S, br: Branches, joint: int, f, g) -> Branches:
    """``br`` with joint ``joint``'s turn of the directions ``f`` onto ``g`` (``(N, K, 3)``,
    unit vectors) noted (``explain`` only): as :func:`note_turn`, of directions."""
    if not br.explain:
        return br
    return _turn_in_plane(S, br, "dir", joint, f, g)


def _turn_in_plane(S, br: Branches, kind: str, joint: int, f, g) -> Branches:
    """``br`` with the turn of ``f`` onto ``g`` (``(N, K, 3)``, vectors from joint ``joint``'s
    axis) noted as ``kind``, both in the plane normal to the axis: ``(g1, g2, f1, f2)``."""
    e = S.constant(("plane of", joint), lambda: plane_basis(S.axis[joint]))
    return br.note(kind, np.concatenate([g @ e.T, f @ e.T], -1), f"{kind}:{joint}")


def note_slide(S, br: Branches, joint: int, f, g) -> Branches:
    """``br`` with the sliding ``joint``'s move of the points ``f`` onto ``g`` (``(N, K,
    3)``, m) noted (``explain`` only)."""
    if not br.explain:
        return br
    k = S.axis[joint]
    return br.note("slide", np.stack([g @ k, f @ k], -1), f"slide:{joint}")


def note_roll(S, br: Branches, joint: int, e, u) -> Branches:
    """``br`` with joint ``joint``'s turn of the fixed unit ``e (3,)`` (normal to its axis)
    onto the directions ``u (N, K, 3)`` noted (``explain`` only)."""
    if not br.explain:
        return br
    E = S.constant(("plane of", joint), lambda: plane_basis(S.axis[joint]))
    return br.note("roll", np.concatenate(np.broadcast_arrays(u @ E.T, E @ e), -1),
                   f"roll:{joint}")


def note_sum(br: Branches, about, signs) -> Branches:
    """``br`` with the last of the joints ``about`` (turning about one direction, ``signs``
    their senses along it) noted as closing the turn ``psi = sum s_i q_i``
    (``br.extra["psi"]``, rad) the others leave (``explain`` only)."""
    if not br.explain:
        return br
    value = np.stack([br.extra["psi"], *(br.value[i] for i in about[:-1])], -1)
    sense = lambda s: "+" if s > 0 else "-"                             # noqa: E731
    return br.note("psi", value, ":".join(
        ["sum", str(about[-1]), sense(signs[-1])]
        + [f"{i}:{sense(s)}" for i, s in zip(about[:-1], signs[:-1])]))


def note_tcv(br: Branches, joint: int, length: float) -> Branches:
    """``br`` with the last joint of a tool configuration vector noted, ``q = pi ln |w4..w6|``
    (``length`` the approach part's, unitless; ``explain`` only)."""
    if not br.explain:
        return br
    return br.note("|w4..w6|", np.full((br.N, br.K, 1), float(length)), f"tcv:{joint}")
