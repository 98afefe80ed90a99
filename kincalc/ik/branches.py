"""The candidates of a family's closed form for a batch of poses, step by step.

A closed form solves joints one step at a time, and a step with several roots (the
+/- of a subproblem 4, the roots of a quartic) splits every candidate into as many.
:class:`Branches` holds the candidates of ``N`` poses in ``K`` slots, the same slots
for every pose: the joints solved so far (value, cosine and sine, each ``(N, K)``),
which slots are alive, which joints a singular target left free, the root each step
took in each slot (the slot's signs, the words of its branch label), and, when asked
for, the intermediate quantities of each step (``--explain``) and the steps that found
no real root (``--all-branches``).

A step's subproblem runs on all slots at once and returns ``k`` solutions per slot
(:class:`~kincalc.subproblems.Solutions` of shape ``(N, K, k)``); :meth:`Branches.branch`
makes the ``K k`` slots of the next step. Quantities a solver computed per slot before
the step are carried over with :meth:`Branches.take`.

Slots that no pose of the batch keeps (the second arc of a wrist singularity, elbow roots
a target out of reach has none of, ...) are dropped as they appear, so later steps work
only on live slots; :meth:`Branches.expanded` puts the slots back in the family's fixed
layout (``full``: each column's slot there, ``full_signs`` the layout's sign table) once
the solver is done. With ``explain`` every slot is kept (notes and dead ends refer to
them).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Note:
    """One intermediate quantity of a step, for ``--explain``: ``value (N, K_at, ...)``
    at the slots of the step that made it (``at``: index into the lineage), SI, of
    ``kind`` ("length", "angle", "none", "joint:I")."""

    label: str
    value: np.ndarray
    kind: str
    at: int


@dataclass(frozen=True)
class DeadEnd:
    """A step that found no real root for some slots: ``joint`` (0-based), the equation
    ``cos(joint - phase) = need`` it had to solve (``phase``, ``need (N, K_at)``; a
    ``need`` beyond [-1, 1] is the reason), ``where (N, K_at)`` the slots it failed for,
    ``what`` the quantity placed (a sentence fragment)."""

    joint: int
    phase: np.ndarray
    need: np.ndarray
    where: np.ndarray
    what: str
    at: int


@dataclass(frozen=True)
class Branches:
    """Candidates of ``N`` poses in ``K`` slots (see the module docstring).

    ``value``, ``cos``, ``sin``: joint (0-based) -> ``(N, K)`` (rad or m; cosine and
    sine of revolute joints); ``ok (N, K)``; ``free``: joint -> ``(N, K)`` bool, the
    joint undetermined at this target (a representative value is shown); ``signs``: per
    slot, a tuple of ``(joint, label)`` for each step with more than one root;
    ``parent (K,)``: the slot of the previous step each slot came from; ``full (K,)``
    and ``full_signs``: once slots were dropped, each column's slot in the family's full
    layout and that layout's sign table (None before; see :meth:`expanded`).
    """

    n: int
    value: dict
    cos: dict
    sin: dict
    ok: np.ndarray
    free: dict
    signs: tuple
    parent: np.ndarray
    explain: bool = False
    lineage: tuple = ()
    notes: tuple = ()
    dead_ends: tuple = ()
    extra: dict = field(default_factory=dict)
    full: np.ndarray | None = None
    full_signs: tuple | None = None

    def _with(self, **changes) -> "Branches":
        """A copy with ``changes`` (``dataclasses.replace`` without its per-field checks:
        a closed form takes a few steps per pose, and a single pose pays for each)."""
        new = object.__new__(Branches)
        new.__dict__.update(self.__dict__, **changes)
        return new

    @staticmethod
    def start(N: int, n: int, *, explain: bool = False, ok=None) -> "Branches":
        """One slot per pose, nothing solved: the branches a family solver starts from.

        Parameters
        ----------
        N : int
            Number of poses.
        n : int
            Number of joints of the chain.
        explain : bool
            Keep every slot and record notes and dead ends (``--explain``, ``--all-branches``).
        ok : array_like (N,) of bool, optional
            The poses to solve (default all); the others start dead.

        Returns
        -------
        Branches
            ``K = 1``: ``ok (N, 1)``, no joint set, empty signs.
        """
        alive = np.ones((N, 1), bool) if ok is None else np.asarray(ok, bool).reshape(N, 1)
        return Branches(n=n, value={}, cos={}, sin={}, ok=alive, free={}, signs=((),),
                        parent=np.zeros(1, int), explain=explain, lineage=(np.zeros(1, int),))

    @property
    def N(self) -> int:
        """Number of poses, ``N``."""
        return self.ok.shape[0]

    @property
    def K(self) -> int:
        """Number of slots, ``K`` (the same for every pose)."""
        return self.ok.shape[1]

    def take(self, x):
        """A per-slot quantity computed before the last step, carried to the slots after it.

        Parameters
        ----------
        x : ndarray (N, K_prev, ...)
            One value per slot of the previous step.

        Returns
        -------
        ndarray (N, K, ...)
            ``x[:, parent]``: each slot gets the value of the slot it came from.
        """
        return x[:, self.parent]

    def branch(self, joints, sols, labels=None, *, least_squares: bool = False) -> "Branches":
        """The next step: every slot splits into the ``k`` roots of a subproblem.

        A slot lives on where its root is ``ok`` and exact (``least_squares``: or the
        subproblem's least-squares answer, for the reasons of a pose out of reach); without
        ``explain`` the slots no pose keeps are then dropped.

        Parameters
        ----------
        joints : sequence of int or None
            The joint (0-based) each unknown of the subproblem gives, in its order; None to
            skip an unknown.
        sols : Solutions
            The subproblem's solutions, of shape ``(N, K, k)`` (rad for revolute, m for
            prismatic joints), with their ``ok``, ``exact`` and ``free`` masks ``(N, K, k)``.
        labels : sequence of str or None, optional
            The sign label of each of the ``k`` roots, given to the first joint of the step
            (default ``+``/``-`` for two roots, ``root i`` for more, none for one).
        least_squares : bool
            Keep the least-squares roots (``sols.ok`` without ``sols.exact``).

        Returns
        -------
        Branches
            ``K k`` slots (fewer once dead ones are dropped), ``parent (K k,)``; the free mask of
            each joint of the step or-ed with the root's ``free``.
        """
        k = sols.ok.shape[-1]
        K = self.K
        parent = np.repeat(np.arange(K), k)
        flat = lambda a: np.asarray(a).reshape(self.N, K * k)  # noqa: E731
        value, cos, sin = self._gather(parent)
        free = {j: f[:, parent] for j, f in self.free.items()}
        for j, t, c, s, fr in zip(joints, sols.theta, sols.c, sols.s, _per_unknown(sols)):
            if j is None:
                continue
            value[j], cos[j], sin[j] = flat(t), flat(c), flat(s)
            free[j] = free[j] | flat(fr) if j in free else flat(fr)
        ok = self.ok[:, parent] & flat(sols.ok if least_squares else sols.ok & sols.exact)
        if k == 1:                      # one root: nothing to tell apart
            labels = (None,)
        elif labels is None:
            labels = ("+", "-") if k == 2 else tuple(f"root {i + 1}" for i in range(k))
        first = next(j for j in joints if j is not None)
        step = lambda sg, r: sg + (((first, labels[r]),) if labels[r] else ())  # noqa: E731
        signs = tuple(step(self.signs[p], i % k) for i, p in enumerate(parent.tolist()))
        extra = {name: x[:, parent] for name, x in self.extra.items()}
        full, full_signs = self.full, self.full_signs
        if full is not None:
            full = np.repeat(full * k, k) + np.tile(np.arange(k), K)
            full_signs = tuple(step(sg, r) for sg in full_signs for r in range(k))
        out = self._with(value=value, cos=cos, sin=sin, ok=ok, free=free, signs=signs,
                      parent=parent, extra=extra, full=full, full_signs=full_signs,
                      lineage=self.lineage + (parent,) if self.explain else self.lineage)
        return out if self.explain else out._live()

    def _live(self) -> "Branches":
        """These branches without the slots no pose keeps (at least one slot stays)."""
        live = self.ok.any(axis=0)
        if live.all():
            return self
        if not live.any():
            live[0] = True
        cols = np.flatnonzero(live)
        full = np.arange(self.K) if self.full is None else self.full
        pick = lambda d: {j: v[:, cols] for j, v in d.items()}  # noqa: E731
        return self._with(value=pick(self.value), cos=pick(self.cos), sin=pick(self.sin),
                       free=pick(self.free), ok=self.ok[:, cols],
                       signs=tuple(self.signs[c] for c in cols.tolist()),
                       parent=self.parent[cols], extra=pick(self.extra), full=full[cols],
                       full_signs=self.signs if self.full is None else self.full_signs)

    def expanded(self) -> "Branches":
        """These branches in the family's full slot layout (once the solver is done).

        Returns
        -------
        Branches
            The dropped slots put back, dead (joint values 0, cosines 1, sines 0, not free;
            extras 0), with the layout's sign table; ``self`` when no slot was dropped.
        """
        if self.full is None:
            return self
        K, N, cols = len(self.full_signs), self.N, self.full

        def put(d, fill):
            out = {}
            for j, v in d.items():
                a = np.full((N, K) + v.shape[2:], fill, v.dtype)
                a[:, cols] = v
                out[j] = a
            return out
        return self._with(value=put(self.value, 0.0), cos=put(self.cos, 1.0),
                       sin=put(self.sin, 0.0), free=put(self.free, False),
                       ok=put({0: self.ok}, False)[0], signs=self.full_signs,
                       parent=np.arange(K), extra=put(self.extra, 0), full=None,
                       full_signs=None)

    def relabel(self, joint: int, label: str) -> "Branches":
        """Every slot's sign for ``joint`` set to ``label`` (a value the target leaves open).

        Parameters
        ----------
        joint : int
            The joint (0-based).
        label : str
            Its sign label in every slot (e.g. ``"any"``), replacing any the steps gave.

        Returns
        -------
        Branches
            A copy with the new signs (and full-layout signs).
        """
        def new(signs):
            return tuple(tuple(p for p in sg if p[0] != joint) + ((joint, label),)
                         for sg in signs)
        return self._with(signs=new(self.signs),
                       full_signs=None if self.full_signs is None else new(self.full_signs))

    def with_extra(self, name: str, value) -> "Branches":
        """A per-slot quantity the engine needs at the end, carried through later steps.

        Parameters
        ----------
        name : str
            Its key in ``extra`` (``"continuum"``, ``"parallel continuum"``, ``"psi"``, ...).
        value : array_like (N, K, ...)
            One value per slot (SI).

        Returns
        -------
        Branches
            A copy with ``extra[name] = value``.
        """
        extra = dict(self.extra)
        extra[name] = np.asarray(value)
        return self._with(extra=extra)

    def set(self, joint: int, value, c=None, s=None, ok=None, free=None) -> "Branches":
        """A step with one root per slot: ``joint`` gets a value in every slot.

        Parameters
        ----------
        joint : int
            The joint (0-based).
        value : ndarray (N, K)
            Its value (rad or m).
        c, s : ndarray (N, K), optional
            Its cosine and sine (revolute joints; give both or neither).
        ok : ndarray (N, K) of bool, optional
            Narrows the live slots (and-ed with ``self.ok``).
        free : ndarray (N, K) of bool, optional
            Replaces the joint's free mask.

        Returns
        -------
        Branches
            A copy, the same ``K`` slots (``parent`` the identity).
        """
        v, cs, sn = self._gather(None)
        v[joint] = value
        if c is not None:
            cs[joint], sn[joint] = c, s
        fr = dict(self.free)
        if free is not None:
            fr[joint] = free
        return self._with(value=v, cos=cs, sin=sn, free=fr,
                       ok=self.ok if ok is None else self.ok & ok,
                       parent=np.arange(self.K))

    def note(self, label: str, value, kind: str = "none") -> "Branches":
        """Record an intermediate quantity for ``--explain`` (nothing without ``explain``).

        Parameters
        ----------
        label : str
            What it is.
        value : array_like (N, K, ...)
            Its value at the current slots (SI).
        kind : str
            ``"length"``, ``"angle"``, ``"none"`` or ``"joint:I"`` (for rendering).

        Returns
        -------
        Branches
            A copy with the :class:`Note` added.
        """
        if not self.explain:
            return self
        return self._with(notes=self.notes + (Note(label, np.asarray(value, float), kind,
                                                      len(self.lineage) - 1),))

    def dead_end(self, joint: int, phase, need, where, what: str) -> "Branches":
        """Record the slots for which ``joint`` had no real root (``--all-branches``).

        Nothing is recorded without ``explain`` or when ``where`` is all False.

        Parameters
        ----------
        joint : int
            The joint (0-based) of the step.
        phase, need : array_like, broadcast to (N, K)
            The equation ``cos(joint - phase) = need`` it had to solve (``phase`` rad; a
            ``need`` beyond [-1, 1] is the reason).
        where : ndarray (N, K) of bool
            The slots it failed for.
        what : str
            The quantity placed (a sentence fragment).

        Returns
        -------
        Branches
            A copy with the :class:`DeadEnd` added.
        """
        if not self.explain or not np.any(where):
            return self
        return self._with(dead_ends=self.dead_ends + (
            DeadEnd(joint, np.broadcast_to(phase, where.shape), np.broadcast_to(need, where.shape),
                    where, what, len(self.lineage) - 1),))

    def reversed_chain(self) -> "Branches":
        """The branches of a chain solved from the tool as the robot's own.

        For a chain reversed by :meth:`Screws.reversed <kincalc.ik.screws.Screws.reversed>`:
        joint k of the reversed chain is joint n - 1 - k turned the other way
        (``q = -q'[::-1]``); signs, free joints and a continuum's relation follow. Called on
        expanded branches (the full layout's sign table is not remapped).

        Returns
        -------
        Branches
            A copy with the joints renumbered and negated (cosines kept, sines negated).
        """
        n = self.n
        m = lambda j: n - 1 - j  # noqa: E731
        extra = dict(self.extra)
        if "continuum" in extra:               # (mask, i, j, sign, total)
            c = extra["continuum"].copy()
            c[..., 1], c[..., 2], c[..., 4] = n - 1 - c[..., 1], n - 1 - c[..., 2], -c[..., 4]
            extra["continuum"] = c
        if "parallel continuum" in extra:      # (mask, sigma, total)
            c = extra["parallel continuum"].copy()
            c[..., 2] = -c[..., 2]
            extra["parallel continuum"] = c
        return self._with(value={m(j): -v for j, v in self.value.items()},
                       cos=dict((m(j), c) for j, c in self.cos.items()),
                       sin={m(j): -v for j, v in self.sin.items()},
                       free={m(j): f for j, f in self.free.items()},
                       signs=tuple(tuple((m(j), lab) for j, lab in sg) for sg in self.signs),
                       extra=extra)

    def _gather(self, parent):
        if parent is None:
            return dict(self.value), dict(self.cos), dict(self.sin)
        return ({j: v[:, parent] for j, v in self.value.items()},
                {j: v[:, parent] for j, v in self.cos.items()},
                {j: v[:, parent] for j, v in self.sin.items()})

    def q(self) -> np.ndarray:
        """The joint values of every slot.

        Returns
        -------
        ndarray (N, K, n)
            Rad or m; 0 where a joint was never set.
        """
        out = np.zeros((self.N, self.K, self.n))
        for j, v in self.value.items():
            out[:, :, j] = v
        return out

    def joint_major(self) -> tuple:
        """The candidates joint by joint, for the FK check (which walks the chain joint-major).

        Returns
        -------
        c, s, x : ndarray (n, N K), contiguous
            The cosine and sine of every revolute joint (1 and 0 for prismatic joints and
            joints never set) and every joint's value (rad or m; 0 where never set); column
            ``i K + k`` is slot k of pose i.
        """
        M = self.N * self.K
        c, s, x = np.ones((self.n, M)), np.zeros((self.n, M)), np.zeros((self.n, M))
        for j, v in self.cos.items():
            c[j] = v.ravel()
        for j, v in self.sin.items():
            s[j] = v.ravel()
        for j, v in self.value.items():
            x[j] = v.ravel()
        return c, s, x

    def free_mask(self) -> np.ndarray:
        """The joints left free in each slot.

        Returns
        -------
        ndarray (N, K, n) of bool
            True where a singular target leaves the joint undetermined.
        """
        out = np.zeros((self.N, self.K, self.n), bool)
        for j, f in self.free.items():
            out[:, :, j] = f
        return out

    def final_index(self, at: int) -> np.ndarray:
        """For each final slot, its slot at lineage step ``at`` (for notes, dead ends).

        Parameters
        ----------
        at : int
            The index into ``lineage`` (a :class:`Note`'s or :class:`DeadEnd`'s ``at``).

        Returns
        -------
        ndarray (K,) of int
            The slot index at that step.
        """
        idx = np.arange(self.K)
        for parent in reversed(self.lineage[at + 1:]):
            idx = parent[idx]
        return idx


def _per_unknown(sols):
    """``sols.free`` once per unknown of the subproblem (the mask is per slot)."""
    return [sols.free] * len(sols.theta)
