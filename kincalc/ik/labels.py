"""Branch labels: the words that name each solution's branch, the same in ``ik`` and
``ik --batch``.

A label is made of

* the geometric words where the arm has them (:mod:`~kincalc.ik.words`, read from the
  solution's joint values): ``shoulder right/left`` for an arm with a shoulder offset,
  ``shoulder front/back`` for one without (the side of the wrist point relative to the
  plane of axes 1 and 2), ``elbow up/down`` (for the first two parallel revolute axes
  among joints 1-3, the elbow's side of the shoulder-to-wrist line), ``wrist
  no-flip/flip`` (the sign of ``(z4 x z6) . z5``);
* the +/- (or ``root k``) of every other step with more than one root, from the slot the
  solution came from (:class:`~kincalc.ik.branches.Branches` gives each slot its
  signs: one table per family, not a string per solution); a second root labelled
  :data:`~kincalc.ik.branches.TIE_BREAK` only where nothing else tells the pose's
  solutions apart;
* ``(<joint> free)`` for a joint a singular target leaves undetermined;
* ``unique`` when there is nothing to tell.
"""

from __future__ import annotations

import re
from functools import lru_cache

import numpy as np

from .branches import TIE_BREAK
from .cache import per_robot
from .words import WORDS, branch_geometry, geometry


def labels(robot, family: str, q, signs, slot, free, every_sign: bool = False) -> tuple:
    """The branch label of each of ``s`` solutions.

    A label is a function of the slot (its signs, :class:`~kincalc.ik.branches.Branches`' sign
    table) and the solution's geometric words: each string is made once per robot, sign table
    and combination, then looked up in a table of ``45 len(signs)`` entries (the free joints,
    rarely any, are put in afterwards).

    Parameters
    ----------
    robot : Robot
    family : str
        The family's name (words only for :data:`WORDED`: a ``reversed-`` family has its
        wrist at the base, and the words' rules read joints 4-6 as the wrist; the
        reversed point-plus-roll, which has no wrist, is the one reversed family worded).
    q : ndarray (s, n)
        Their joint values (rad / m).
    signs : tuple
        The family's sign table: per slot, a tuple of ``(joint, label)`` for each step with
        more than one root.
    slot : ndarray (s,) of int
        The slot each solution came from (index into ``signs``).
    free : array_like (s, n) of bool
        The joints each leaves free.

    every_sign : bool
        Show the +/- of every step, also of those the words name: for solutions of one pose
        that the words and the other signs do not tell apart (rare: see
        :meth:`Solved.labels <kincalc.ik.engine.Solved.labels>`).

    Returns
    -------
    texts : ndarray (s,) of object
        The labels (str); ``"unique"`` when there is nothing to tell.
    ids : ndarray (s,) of int
        A number per distinct text (per robot and family): equal labels, equal numbers.
    """
    if len(slot) == 0:
        return np.empty(0, object), np.empty(0, np.int64)
    table, ids, weights = _table(robot, family, signs, every_sign)
    S = len(signs)
    code = weights @ branch_geometry(robot, family, q).T + slot
    out_ids = ids[code]
    if np.count_nonzero(out_ids >= 0) < len(code):
        # (the codes met, ascending; not np.unique, which imports numpy.ma, 8 ms of every
        # CLI run's start)
        for c in np.flatnonzero(np.bincount(code)).tolist():
            k, g = divmod(c, S)
            table[c], ids[c] = _label(robot, family, (k // 9, k // 3 % 3, k % 3), signs[g], 0,
                                      every_sign)
        out_ids = ids[code]
    out = table[code]
    free = np.asarray(free, bool)
    if np.count_nonzero(free):                       # a joint left free: rare
        bits = free @ (1 << np.arange(robot.dof, dtype=np.int64))
        for i in bits.nonzero()[0].tolist():
            k, g = divmod(int(code[i]), S)
            out[i], out_ids[i] = _label(robot, family, (k // 9, k // 3 % 3, k % 3), signs[g],
                                        int(bits[i]), every_sign)
    return out, out_ids


@per_robot
def _table(robot, family: str, signs: tuple, every_sign: bool) -> tuple:
    """The labels of ``robot`` solved as ``family`` with the sign table ``signs`` and no free
    joint, by code ``(9 shoulder + 3 elbow + wrist) len(signs) + slot``: ``(texts (45
    len(signs),) of object, their ids (45 len(signs),), -1 where not made yet, the code's
    weights (3,))``, filled as they are met."""
    S = len(signs)
    return np.empty(45 * S, object), np.full(45 * S, -1, np.int64), np.array([9 * S, 3 * S, S])


def _label(robot, family, words, signs, free_bits, every_sign) -> tuple:
    """``(text, id)``: :func:`_text`, made once per robot and combination, and the number of
    the text among those of the robot and family (:func:`_texts`)."""
    texts, numbers = _texts(robot, family)
    key = (words, signs, free_bits, every_sign)
    if key not in texts:
        text = texts[key] = _text(robot, family, words, signs, free_bits, every_sign)
        numbers.setdefault(text, len(numbers))
    return texts[key], numbers[texts[key]]


@per_robot
def _texts(robot, family: str) -> tuple:
    """The labels made so far for ``robot`` solved as ``family``: ``((geometric code, signs,
    free bits, every sign) -> text, text -> id)``."""
    return {}, {}


def _text(robot, family, words, signs, free_bits, every_sign=False) -> str:
    """One label: the geometric ``words`` (codes of :data:`WORDS`), the ``signs`` of the
    steps they do not name and of joints not free (``every_sign``: of every step), the free
    joints (bit j: joint j)."""
    names = [j.name for j in robot.joints]
    parts = [WORDS[w][x - 1] for w, x in enumerate(words) if x]
    geo = geometry(robot, family)
    named = set() if every_sign else \
        set().union(*(geo.named()[w] for w, x in enumerate(words) if x))
    # (a free joint's step has one root, its representative: no sign tells it apart; an
    # open joint's "any" says it is free)
    parts += [f"{names[j]}:{lab}" for j, lab in sorted(signs)
              if j not in named and (every_sign or lab != TIE_BREAK and (
                  lab == "any" or not free_bits >> j & 1))]
    said = {j for j, lab in signs if lab == "any"}          # open: "any" says it already
    free = [names[j] for j in range(robot.dof) if free_bits >> j & 1 and j not in said]
    if free:
        parts.append("(" + ", ".join(free) + " free)")
    return " ".join(parts) if parts else "unique"


@lru_cache(maxsize=4096)
def label_order(text: str) -> tuple:
    """A label as a sort key that orders the numbers in it by value (``root 2`` before
    ``root 10``)."""
    return tuple((0, int(w), "") if w.isdigit() else (1, 0, w)
                 for w in re.split(r"(\d+)", text))


def solution_order(labels, within, owner=None) -> np.ndarray:
    """The order in which ``ik`` and ``ik --batch`` list solutions: each pose's solutions
    within the limits first, each group by branch label (:func:`label_order`), solutions
    that tie in both in the order given.

    Parameters
    ----------
    labels : list of str (s,), the solutions' branch labels
    within : array_like (s,) of bool, within the joint limits
    owner : array_like (s,) of int, optional, the pose of each (ascending; default one pose)

    Returns
    -------
    ndarray (s,) of int, the solutions' indices in that order (poses kept in theirs)
    """
    rank = {t: k for k, t in enumerate(sorted(set(labels), key=label_order))}
    key = np.array([rank[t] for t in labels], np.intp) + np.where(within, 0, len(rank))
    return np.lexsort((key,) if owner is None else (key, owner))
