"""The relations a singular target leaves between joints, as data with their words: the
continua the solvers mark (``Branches.extra["continuum"]``, ``["parallel continuum"]``) and
:mod:`kincalc.ik.solve` hands to the results. Angles in rad, joints 0-based.
"""

from __future__ import annotations

from typing import NamedTuple

from ..spatial import wrap


class Continuum(NamedTuple):
    """At a singular target joints ``i`` and ``j`` (0-based) turn the tool about one
    line: only ``q_i + sign q_j`` is fixed, to ``total`` (rad); ``total`` None when the
    solver does not name the combination."""

    i: int
    j: int
    sign: int
    total: float | None = None

    def reversed(self, n: int) -> "Continuum":
        """The same relation for the original chain of a reversed one.

        Joint k of the reversed chain is joint n - 1 - k, turned the other way.

        Parameters
        ----------
        n : int
            Number of joints.

        Returns
        -------
        Continuum
            Joints renumbered, ``total`` negated (None stays None).
        """
        return Continuum(n - 1 - self.i, n - 1 - self.j, self.sign,
                         None if self.total is None else -self.total)

    def text(self, names, angle_unit: str, per_rad: float) -> str:
        """The relation in words: ``a + b = total`` (or ``a - b``), in the display angle unit.

        Parameters
        ----------
        names : sequence of str
            The joints' names, by 0-based index.
        angle_unit : str
            The display angle unit's name.
        per_rad : float
            Display angle units per rad.

        Returns
        -------
        str
            ``total`` wrapped to (-pi, pi] and shown in the display unit; without a ``total``,
            the sentence that the two axes are aligned.
        """
        a, b = names[self.i], names[self.j]
        if self.total is None:
            return f"axes of {a} and {b} aligned: they turn the tool about one line"
        return (f"{a} {'+' if self.sign > 0 else '-'} {b} = "
                f"{_shown(self.total, per_rad)} {angle_unit}")


class ParallelContinuum(NamedTuple):
    """A three-parallel arm at its wrist singularity: joints ``joints`` (0-based) turn
    about parallel axes, so only ``sum(sign_k q_k)`` is fixed, to ``total`` (rad).
    Joint ``free`` can take any value the elbow can follow. The others follow it: the
    sum, and the planar elbow placing axis 4. It has the same interface as
    :class:`Continuum` (``reversed``, ``text``) for the dispatcher."""

    joints: tuple
    signs: tuple
    free: int
    total: float

    def reversed(self, n: int) -> "ParallelContinuum":
        """The same relation for the original chain of a reversed one.

        Joint k of the reversed chain is joint n - 1 - k, turned the other way.

        Parameters
        ----------
        n : int
            Number of joints.

        Returns
        -------
        ParallelContinuum
            Joints renumbered (in ascending order, their signs with them), ``total`` negated.
        """
        pairs = sorted((n - 1 - i, s) for i, s in zip(self.joints, self.signs))
        return ParallelContinuum(tuple(i for i, _ in pairs), tuple(s for _, s in pairs),
                                 n - 1 - self.free, -self.total)

    def text(self, names, angle_unit: str, per_rad: float) -> str:
        """The relation in words: the signed sum, its total, and which joint is free.

        Parameters
        ----------
        names : sequence of str
            The joints' names, by 0-based index.
        angle_unit : str
            The display angle unit's name.
        per_rad : float
            Display angle units per rad.

        Returns
        -------
        str
            ``total`` wrapped to (-pi, pi] and shown in the display unit.
        """
        terms = [("-" if s < 0 else "") + names[j] if k == 0 else
                 ("- " if s < 0 else "+ ") + names[j]
                 for k, (j, s) in enumerate(zip(self.joints, self.signs))]
        rest = ", ".join(names[j] for j in self.joints if j != self.free)
        return (f"{' '.join(terms)} = {_shown(self.total, per_rad)} {angle_unit} "
                f"(axis of {names[self.free]} parallel to theirs: {names[self.free]} free, "
                f"{rest} follow it)")


def _shown(total: float, per_rad: float) -> str:
    """A relation's total (rad) in the display unit, to 4 decimals (a total rounding to zero
    is 0.0000, not -0.0000)."""
    return f"{round(float(wrap(total)) * per_rad, 4) + 0.0:.4f}"
