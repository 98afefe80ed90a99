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

Slots that no pose of the batch keeps (the second arc of a wrist singularity, elbow roots a
target out of reach has none of, ...) are dropped as they appear, so later steps work only
on live slots; :meth:`Branches.expanded` puts the slots back in the family's fixed layout
(``full``: each column's slot there, ``full_signs`` the layout's sign table) once the
solver is done. Every slot is kept with ``explain`` (notes and dead ends refer to them), and
in steps of at most ``_SMALL`` slots in all (one pose's: dropping, then putting back, costs more).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
import numpy as np

from .steps import DeadEnd, Note


#: the label of a step's second root that matters only where nothing else tells two
#: solutions apart (the words and the other steps' signs): shown then, with every sign
#: (:func:`kincalc.ik.labels.labels`' ``every_sign``), hidden otherwise
TIE_BREAK = "other root"


@dataclass(frozen=True)
class Branches:
    """Candidates of ``N`` poses in ``K`` slots (see the module docstring).

    ``X (3, n, N, K)``: every joint's value, cosine and sine in each slot (rad or m; a
    joint not solved yet, or prismatic, has cosine 1 and sine 0; value 0 until set), read
    as :attr:`value`, :attr:`cos`, :attr:`sin` (each ``(n, N, K)``: ``br.value[j]`` is
    joint j's ``(N, K)``); ``F (n, N, K)`` bool, read as :attr:`free`: the joint
    undetermined at this target (a representative value is shown); ``ok (N, K)``;
    ``signs``: per slot, a tuple of ``(joint, label)`` for each step with more than one
    root; ``parent (K,)``: the slot of the previous step each slot came from; ``full (K,)``
    and ``full_signs``: once slots were dropped, each column's slot in the family's full
    layout and that layout's sign table (None before; see :meth:`expanded`).

    The arrays are shared between a :class:`Branches` and the ones made from it: never
    modify them in place (every method returns new arrays where it changes them).
    """

    n: int
    X: np.ndarray
    F: np.ndarray
    ok: np.ndarray
    signs: tuple
    parent: np.ndarray
    explain: bool = False
    lineage: tuple = ()
    notes: tuple = ()
    dead_ends: tuple = ()
    extra: dict = field(default_factory=dict)
    full: np.ndarray | None = None
    full_signs: tuple | None = None
    #: joints :meth:`set` since the arrays were last written: joint -> (value, cos, sin,
    #: free), each ``(N, K)`` or None (kept from ``X``/``F``); written by :meth:`flushed`
    #: and by the next :meth:`branch`, so a step with one root copies no array
    pending: dict = field(default_factory=dict)

    def _with(self, **changes) -> "Branches":
        """A copy with ``changes`` (``dataclasses.replace`` without its per-field checks)."""
        new = object.__new__(Branches)
        new.__dict__.update(self.__dict__, **changes)
        return new

    @property
    def value(self):
        """Every joint's value in each slot, ``value[j] (N, K)`` (rad or m; 0 where not set)."""
        return _Rows(self, 0) if self.pending else self.X[0]

    @property
    def cos(self):
        """The cosine of every revolute joint, ``cos[j] (N, K)`` (1 where not set, prismatic)."""
        return _Rows(self, 1) if self.pending else self.X[1]

    @property
    def sin(self):
        """The sine of every revolute joint, ``sin[j] (N, K)`` (0 where not set, prismatic)."""
        return _Rows(self, 2) if self.pending else self.X[2]

    @property
    def free(self):
        """``free[j] (N, K)`` bool: the joints a singular target leaves undetermined."""
        return _Rows(self, 3) if self.pending else self.F

    def free_in(self, joints) -> bool:
        """Does a singular target leave any of ``joints`` (0-based) undetermined in a slot?"""
        rows = [p[3] if p is not None and p[3] is not None else self.F[j]
                for j in joints for p in (self.pending.get(j),)]
        return bool(np.count_nonzero(rows))

    def flushed(self) -> "Branches":
        """These branches with the :attr:`pending` joints written into new arrays."""
        if not self.pending:
            return self
        X, F = self.X.copy(), self.F
        if any(p[3] is not None for p in self.pending.values()):
            F = F.copy()
        for j, (v, c, s, f) in self.pending.items():
            X[0, j] = v
            if c is not None:
                X[1, j], X[2, j] = c, s
            if f is not None:
                F[j] = f
        return self._with(X=X, F=F, pending={})

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
        # (made from a blank one, every field at its default, as fast as _with)
        return _BLANK._with(n=n, X=_unset(n, N, 1), F=np.zeros((n, N, 1), bool), ok=alive,
                            signs=((),), parent=_ZERO, explain=explain, lineage=(_ZERO,),
                            extra={}, pending={})

    def with_slots(self, ok, signs, q=None, c=None, s=None) -> "Branches":
        """A slot per sign of ``signs`` (K tuples of (joint, label)), live where ``ok (N, K)``
        and this slot are, for a solver that finds every slot at once: nothing solved
        (``parent`` 0), or every joint's value, cosine, sine ``q, c, s (N, K, n)`` set."""
        K = len(signs)
        X = _unset(self.n, self.N, K) if q is None else np.moveaxis(np.stack([q, c, s]), -1, 1)
        return self._with(X=X, F=np.zeros((self.n, self.N, K), bool), ok=ok & self.ok[:, :1],
                          signs=tuple(signs), pending={},
                          parent=np.zeros(K, np.intp) if q is None else _identity(K))

    def appended(self, ok, signs) -> "Branches":
        """These expanded branches with ``G`` more slots after the last (``ok (N, G)``),
        found another way, with their ``signs`` (``G``): values set later, not free."""
        if self.pending:
            return self.flushed().appended(ok, signs)
        N, G = ok.shape
        X = np.concatenate([self.X, _unset(self.n, N, G)], axis=-1)
        F = np.concatenate([self.F, np.zeros((self.n, N, G), bool)], axis=-1)
        extra = {k: np.concatenate([v, np.zeros((N, G) + v.shape[2:])], axis=1)
                 for k, v in self.extra.items()}
        new = (np.r_[np.arange(self.K), np.full(G, -1)],) if self.explain else ()  # no step's
        return self._with(X=X, F=F, ok=np.concatenate([self.ok, ok], axis=1),
                          signs=self.signs + tuple(signs), extra=extra,
                          parent=np.arange(self.K + G), lineage=self.lineage + new)

    def without_free(self) -> "Branches":
        """These branches with no joint free and no continuum (solutions refined on another
        robot than the one whose singular structure made them free)."""
        extra = {k: v for k, v in self.extra.items() if "continuum" not in k}
        return self.flushed()._with(F=np.zeros_like(self.F), extra=extra)

    @property
    def N(self) -> int:
        """Number of poses, ``N``."""
        return self.ok.shape[0]

    @property
    def K(self) -> int:
        """Number of slots, ``K`` (the same for every pose)."""
        return self.ok.shape[1]

    def take(self, x):
        """A per-slot quantity ``x (N, K_prev, ...)`` computed before the last step, carried
        to the slots after it: ``x[:, parent]``, ``(N, K, ...)``."""
        return x[:, self.parent]

    def branch(self, joints, sols, labels=None, *, least_squares: bool = False,
               free: bool | tuple = True) -> "Branches":
        """The next step: every slot splits into the ``k`` roots of a subproblem.

        A slot lives on where its root is ``ok`` and exact (``least_squares``: or the
        subproblem's least-squares answer, for a pose out of reach); dead slots are dropped.

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
        free : bool or tuple of int
            Or the roots' ``free`` (or each joint's ``undetermined``) into their free masks
            (False: not free, for a solver leaving another joint free; a tuple: those joints).

        Returns
        -------
        Branches
            ``K k`` slots (fewer once dead ones are dropped), ``parent (K k,)``; the free masks
            or-ed with the root's ``free`` (see ``free``).
        """
        (N, K), k = self.ok.shape, sols.ok.shape[-1]
        M = K * k
        parent, root = _parents(K, k)
        X, F = self.X[..., parent], self.F[..., parent]
        for j, (v, c, s, f) in self.pending.items():
            X[0, j] = v[:, parent]
            if c is not None:
                X[1, j], X[2, j] = c[:, parent], s[:, parent]
            if f is not None:
                F[j] = f[:, parent]
        which = sols.undetermined or (sols.free,) * len(joints)
        for j, t, c, s, f in zip(joints, sols.theta, sols.c, sols.s, which):
            if j is not None:
                Xj = X[:, j].reshape(3, N, K, k)           # (a view: the roots' own layout)
                Xj[0], Xj[1], Xj[2] = t, c, s
                if (free is True or free and j in free) and np.count_nonzero(f):
                    F[j] |= f.reshape(N, M)
        ok = (self.ok[..., None] & sols.ok if least_squares else
              self.ok[..., None] & sols.ok & sols.exact).reshape(N, M)
        if k == 1:                      # one root: nothing to tell apart
            labels = (None,)
        elif labels is None:
            labels = ("+", "-") if k == 2 else tuple(f"root {i + 1}" for i in range(k))
        first = [j for j in joints if j is not None][0]
        signs = _split_signs(self.signs, k, tuple(labels), first)
        extra = {name: x[:, parent] for name, x in self.extra.items()} if self.extra else {}
        full, full_signs = self.full, self.full_signs
        if full is not None:
            full = full[parent] * k + root
            full_signs = _split_signs(full_signs, k, tuple(labels), first)
        out = self._with(X=X, F=F, ok=ok, signs=signs, parent=parent, extra=extra, full=full,
                         full_signs=full_signs, pending={},
                         lineage=self.lineage + (parent,) if self.explain else self.lineage)
        return out if self.explain or N * M <= _SMALL else out._live()

    def _live(self) -> "Branches":
        """These branches without the slots no pose keeps (at least one slot stays)."""
        live = np.logical_or.reduce(self.ok, axis=0)
        count = np.count_nonzero(live)
        if count == len(live):
            return self
        if not count:
            live[0] = True
        cols, signs = live.nonzero()[0], self.signs
        return self._with(X=self.X[..., cols], F=self.F[..., cols], ok=self.ok[:, cols],
                          signs=tuple([signs[c] for c in cols.tolist()]),
                          parent=self.parent[cols],
                          extra={j: v[:, cols] for j, v in self.extra.items()},
                          full=cols if self.full is None else self.full[cols],
                          full_signs=signs if self.full is None else self.full_signs)

    def expanded(self) -> "Branches":
        """These branches in the family's full slot layout (once the solver is done).

        Returns
        -------
        Branches
            The dropped slots put back, dead (joint values 0, cosines 1, sines 0, not free;
            extras 0), with the layout's sign table; ``self`` when no slot was dropped.
        """
        if self.full is None:
            return self.flushed()
        K, N, cols = len(self.full_signs), self.N, self.full
        X = _unset(self.n, N, K)
        X[..., cols] = self.X
        F = np.zeros((self.n, N, K), bool)
        F[..., cols] = self.F
        for j, (v, c, s, f) in self.pending.items():       # written here, not copied first
            X[0, j][:, cols] = v
            if c is not None:
                X[1, j][:, cols], X[2, j][:, cols] = c, s
            if f is not None:
                F[j][:, cols] = f
        ok = np.zeros((N, K), bool)
        ok[:, cols] = self.ok
        extra = {}
        for j, v in self.extra.items():
            extra[j] = np.zeros((N, K) + v.shape[2:], v.dtype)
            extra[j][:, cols] = v
        return self._with(X=X, F=F, ok=ok, signs=self.full_signs, parent=np.arange(K),
                          extra=extra, full=None, full_signs=None, pending={})

    def relabel(self, joint: int, label: str) -> "Branches":
        """A copy with every slot's sign for ``joint`` (0-based) set to ``label`` (e.g.
        ``"any"``: a value the target leaves open), replacing any the steps gave, in the
        signs and the full layout's signs."""
        def new(signs):
            return tuple(tuple(p for p in sg if p[0] != joint) + ((joint, label),)
                         for sg in signs)
        return self._with(signs=new(self.signs),
                          full_signs=None if self.full_signs is None else new(self.full_signs))

    def with_extra(self, name: str, value, *more) -> "Branches":
        """A copy with ``extra[name] = value``: a per-slot quantity ``(N, K, ...)`` (SI) the
        engine needs at the end (``"continuum"``, ``"parallel continuum"``, ``"psi"``),
        carried through later steps; ``more``: further name, value pairs."""
        extra = dict(self.extra)
        extra[name] = np.asarray(value)
        extra.update(zip(more[::2], map(np.asarray, more[1::2]), strict=True))
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
            Its cosine and sine (revolute joints; give both or neither; default: kept).
        ok : ndarray (N, K) of bool, optional
            Narrows the live slots (and-ed with ``self.ok``).
        free : ndarray (N, K) of bool, optional
            Replaces the joint's free mask.

        Returns
        -------
        Branches
            A copy, the same ``K`` slots (``parent`` the identity).
        """
        shape = self.ok.shape
        was = self.pending.get(joint, (None,) * 4)          # None: kept from X and F
        row = tuple([x if x is None or type(x) is np.ndarray and x.shape == shape else
                     np.broadcast_to(x, shape) for x in (      # (else a read-only view)
                         value, was[1] if c is None else c, was[2] if c is None else s,
                         was[3] if free is None else free)])
        return self._with(pending={**self.pending, joint: row},
                          ok=self.ok if ok is None else self.ok & ok, parent=_identity(shape[1]))

    def note(self, label: str, value, kind: str = "none") -> "Branches":
        """A copy with a :class:`Note` of an intermediate quantity for ``--explain``
        (``self`` without ``explain``): ``label`` what it is, ``value (N, K, ...)`` its value
        at the current slots (SI), ``kind`` ``"length"``, ``"angle"``, ``"none"`` or
        ``"joint:I"`` (for rendering)."""
        if not self.explain:
            return self
        return self._with(notes=self.notes + (Note(label, np.asarray(value, float), kind,
                                                      len(self.lineage) - 1),))

    def dead_end(self, joint: int, phase, need, where, what: str) -> "Branches":
        """A copy with a :class:`DeadEnd`: the slots ``where (N, K)`` for which ``joint``
        (0-based) had no real root of ``cos(joint - phase) = need`` (``phase`` rad, ``need``;
        both broadcast to (N, K); a ``need`` beyond [-1, 1] is the reason), ``what`` the
        quantity placed (``--all-branches``). ``self`` without ``explain`` or failures."""
        if not self.explain or not np.any(where):
            return self
        return self._with(dead_ends=self.dead_ends + (
            DeadEnd(joint, np.broadcast_to(phase, where.shape), np.broadcast_to(need, where.shape),
                    where, what, len(self.lineage) - 1),))

    def reversed_chain(self) -> "Branches":
        """The branches of a chain solved from the tool as the robot's own.

        For a chain reversed by :meth:`Screws.reversed <kincalc.ik.screws.Screws.reversed>`:
        joint k of the reversed chain is joint n - 1 - k turned the other way
        (``q = -q'[::-1]``); signs (of the slots and of the full layout), free joints and a
        continuum's relation follow.

        Returns
        -------
        Branches
            A copy with the joints renumbered and negated (cosines kept, sines negated).
        """
        if self.pending:
            return self.flushed().reversed_chain()
        n = self.n
        extra = dict(self.extra)
        if "continuum" in extra:               # (mask, i, j, sign, total)
            c = extra["continuum"].copy()
            c[..., 1], c[..., 2], c[..., 4] = n - 1 - c[..., 1], n - 1 - c[..., 2], -c[..., 4]
            extra["continuum"] = c
        if "parallel continuum" in extra:      # (mask, sigma, total, free, about, against)
            c = extra["parallel continuum"].copy()
            c[..., 2], c[..., 3] = -c[..., 2], n - 1 - c[..., 3]
            for k in (4, 5):                   # joint bits: bit i becomes bit n - 1 - i
                bits = c[..., k].astype(np.int64)
                c[..., k] = sum(((bits >> i) & 1) << (n - 1 - i) for i in range(n))
            extra["parallel continuum"] = c
        X = self.X[:, ::-1] * np.array([-1.0, 1.0, -1.0])[:, None, None, None]
        def renumbered(signs):
            return tuple(tuple((n - 1 - j, lab) for j, lab in sg) for sg in signs)
        return self._with(X=X, F=self.F[::-1].copy(), extra=extra, signs=renumbered(self.signs),
                          full_signs=None if self.full_signs is None else
                          renumbered(self.full_signs))

    def q(self) -> np.ndarray:
        """``(N, K, n)``: the joint values of every slot (rad or m; 0 where never set)."""
        return self.flushed().X[0].transpose(1, 2, 0).copy()

    def joint_major(self) -> tuple:
        """The candidates joint by joint, for the FK check (which walks the chain joint-major).

        Returns
        -------
        c, s, x : ndarray (n, N K), contiguous, read-only views of the branches' arrays
            The cosine and sine of every revolute joint (1 and 0 for prismatic joints and
            joints never set) and every joint's value (rad or m; 0 where never set); column
            ``i K + k`` is slot k of pose i.
        """
        X = np.ascontiguousarray(self.flushed().X).reshape(3, self.n, self.N * self.K).view()
        X.flags.writeable = False
        return X[1], X[2], X[0]

    def free_mask(self) -> np.ndarray:
        """``(N, K, n)`` bool: True where a singular target leaves the joint undetermined."""
        return self.flushed().F.transpose(1, 2, 0).copy()

    def final_index(self, at: int) -> np.ndarray:
        """``(K,)``: for each final slot, its slot at lineage step ``at`` (the index into
        ``lineage`` of a :class:`Note` or :class:`DeadEnd`), -1 if :meth:`appended` after."""
        idx = np.arange(self.K)
        for parent in reversed(self.lineage[at + 1:]):
            idx = np.where(idx >= 0, parent[np.maximum(idx, 0)], -1)
        return idx


_SMALL = 64     # slots of a whole step (N K) up to which dead ones are kept (module docstring)

#: every field at its default (:meth:`Branches.start` gives the rest, and new dicts)
_BLANK = Branches(n=0, X=None, F=None, ok=None, signs=(), parent=None)
_ZERO = np.zeros(1, np.intp)
_ZERO.flags.writeable = False


def _unset(n: int, N: int, K: int) -> np.ndarray:
    """``X (3, n, N, K)`` of joints not set: values 0, cosines 1, sines 0."""
    X = np.zeros((3, n, N, K))
    X[1] = 1.0
    return X


@lru_cache(maxsize=256)
def _parents(K: int, k: int) -> tuple:
    """``(K k,)`` twice: the slot each of the ``K k`` slots of a ``k``-way split came from,
    and the root (0 .. k-1) it took (read-only; shared)."""
    out = np.repeat(np.arange(K), k), np.tile(np.arange(k), K)
    out[0].flags.writeable = out[1].flags.writeable = False
    return out


@lru_cache(maxsize=256)
def _identity(K: int) -> np.ndarray:
    """``arange(K)``, read-only and shared."""
    out = np.arange(K)
    out.flags.writeable = False
    return out


@lru_cache(maxsize=4096)
def _split_signs(signs: tuple, k: int, labels: tuple, first: int) -> tuple:
    """The sign table after each slot of ``signs`` splits into ``k`` roots labelled
    ``labels`` (None: no label) for joint ``first``."""
    return tuple(sg + (((first, labels[r]),) if labels[r] else ())
                 for sg in signs for r in range(k))


class _Rows:
    """``value``, ``cos``, ``sin`` or ``free`` with :attr:`~Branches.pending` joints."""

    __slots__ = ("br", "i")

    def __init__(self, br: Branches, i: int):
        self.br, self.i = br, i

    def __getitem__(self, j: int) -> np.ndarray:
        row = self.br.pending.get(j)
        if row is not None and row[self.i] is not None:
            return row[self.i]
        return self.br.F[j] if self.i == 3 else self.br.X[self.i, j]
