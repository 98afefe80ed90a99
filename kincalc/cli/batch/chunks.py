"""One chunk of batch records through the vectorised core: fk, jacobian, ik and reach,
each record its answer or its error record (:func:`process_chunk`, pure: safe in a
worker process)."""

from __future__ import annotations

from typing import NamedTuple

from .formats import (ANSWER, answer_line, csv_rows, ik_solutions, reachable, rounded,
                      strict_json)
from .poses import head, in_run_units, record_poses, words
from .records import FK_FIELDS, FK_LENGTH, parse_chunk, parse_records

def process_chunk(kind, robot, units, header, fmt, frame, item, locks=None,
                  guessed: bool = False) -> tuple:
    """Parse, solve and format one chunk ``item = (first index, lines)``; returns
    ``(text, any record bad, any pose without a solution)``, the text str, or ASCII bytes
    for ik's JSON lines. Pure: safe to run in a
    worker process. Numbers that come out NaN or infinite make their record an error
    (each chunk function checks its results), so floating-point warnings are not shown.
    ``locks`` (ik): joints held for every record, ``{index: value}`` (SI)."""
    import numpy as np
    start, lines = item
    if kind == "ik":
        parsed, together = parse_chunk(header, robot, start, lines, guessed=guessed)
        with np.errstate(all="ignore"):
            answers, errors, no = _ik_chunk(robot, units, parsed, locks or {}, together, start)
        if fmt == "jsonl":
            return _ik_text(start, len(lines), answers, errors), bool(errors), no
        return csv_rows(kind, robot, _merge(_ik_records(answers), errors)), bool(errors), no
    parsed = parse_records(header, robot, start, lines, kind, guessed)
    parsed = [(i, None, f"record {i + 1}: lock: only ik --batch holds joints")
              if err is None and "lock" in kw else (i, kw, err) for i, kw, err in parsed]
    solve = {"fk": _fk_chunk, "jacobian": _jacobian_chunk, "reach": _reach_chunk}[kind]
    with np.errstate(all="ignore"):
        records, no = solve(robot, units, parsed, frame)
    bad = any("error" in r for r in records)
    if fmt == "jsonl":
        dump = strict_json().encode
        text = "".join(dump(r) + "\n" for r in records)
    else:
        text = csv_rows(kind, robot, records)
    return text, bad, no


def _joint_rows(robot, units, parsed, what):
    """``(good [(index, kw)], q (m, n) SI, error records)`` from records that must hold
    joint values only."""
    import numpy as np
    good, qs, errors = [], [], []
    for i, kw, err in parsed:
        if err is None:
            keys = set(kw) - {"id"}
            if keys != {"q"}:
                err = (f"record {i + 1}: {what} takes joint values ('q', or one CSV column "
                       f"per joint), not {', '.join(sorted(keys - {'q'}))}")
            elif len(kw["q"]) != robot.dof:
                err = (f"record {i + 1}: {robot.name} has {robot.dof} joints, got "
                       f"{len(kw['q'])} values")
        if err is not None:
            errors.append((i, {**head(i, kw), "error": err}))
            continue
        good.append((i, kw))
        qs.append(kw["q"])
    q = np.array(qs, float).reshape(-1, robot.dof)
    return good, q / np.where(robot.is_revolute, units.a, units.l), errors


def _merge(records, errors):
    out = records + [r for _, r in errors]
    out.sort(key=lambda r: r["index"])
    return out


def _finite_rows(good, arrays, errors):
    """``(good, arrays)`` without the records whose results (row k of every array) are
    not all finite; those become error records. Inputs within MAX_MAGNITUDE give finite
    results: this is the guarantee that no output holds NaN or Infinity."""
    import numpy as np
    if not good:
        return good, arrays
    ok = np.ones(len(good), bool)
    for a in arrays:
        ok &= np.isfinite(a).reshape(len(good), -1).all(axis=1)
    if ok.all():
        return good, arrays
    for k in np.flatnonzero(~ok):
        i, kw = good[k]
        errors.append((i, {**head(i, kw), "error": f"record {i + 1}: the result is not a "
                           "finite number for these values"}))
    return [g for g, o in zip(good, ok) if o], [a[ok] for a in arrays]


def _fk_chunk(robot, units, parsed, frame):
    from ...spatial import rpy_from_matrix
    good, q, errors = _joint_rows(robot, units, parsed, "fk")
    T = robot.fk(q, column_walk=True)       # (a record's bits whatever its chunk)
    T[:, :3, 3] *= units.l
    rpy = rpy_from_matrix(T[:, :3, :3]) * units.a
    good, (q, T, rpy) = _finite_rows(good, (q, T, rpy), errors)
    from ...ik.joint_limits import violations
    within = ~(violations(robot, q) != 0).any(-1)   # the values as given: 300 deg is not -60
    Tl, xyz, rpyl = rounded(T), rounded(T[:, :3, 3]), rounded(rpy)
    said = {"length": units.length, "angle": units.angle}   # (ik --batch reads T in it)
    recs = [{**head(i, kw), **dict(zip(FK_FIELDS, (Tl[k], xyz[k], rpyl[k], bool(within[k]),
                                                   said)))}
            for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _jacobian_chunk(robot, units, parsed, frame):
    import numpy as np

    from ...analysis.results import display_jacobian
    from ...jacobian import rotate_jacobian, scaled_ranks
    good, q, errors = _joint_rows(robot, units, parsed, "jacobian")
    Jb = robot.jacobian(q, column_walk=True)                   # (m, 6, n) SI, base; as fk's
    good, (q, Jb) = _finite_rows(good, (q, Jb), errors)
    J = Jb
    if frame == "tool" and len(q):
        J = rotate_jacobian(Jb, np.swapaxes(robot.fk(q, column_walk=True)[:, :3, :3], -1, -2))
    # rank and singularity as 'kincalc jacobian' (analysis.jacobian_report)
    rank, position_rank = scaled_ranks(Jb, robot.is_revolute, robot.characteristic_length)
    full, full_pos = robot.generic_ranks
    singular = (rank < full) | (position_rank < full_pos)
    Jd = display_jacobian(robot, J, units)
    manip = np.prod(np.linalg.svd(Jd, compute_uv=False)[:, :full], axis=-1) if len(q) \
        else np.zeros(0)
    good, (Jd, manip, rank, singular) = _finite_rows(good, (Jd, manip, rank, singular), errors)
    Jl = rounded(Jd)
    recs = [{**head(i, kw), "J": Jl[k], "rank": int(rank[k]),
             "manipulability": float(manip[k]), "singular": bool(singular[k])}
            for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _ik_chunk(robot, units, parsed, locks=None, together=None, start: int = 0):
    """``(answers, error records, any pose without a solution)`` of the IK records of one
    chunk, grouped by the joints they hold (``locks``, SI, for every record, and each
    record's own ``lock``, which adds to them and wins for a joint both name): each group
    solved on the chain its locks leave, in one batch. ``together``: records read together
    (from record ``start``), which hold no joints of their own."""
    from ...errors import KincalcError
    groups, errors = {}, []
    common = tuple(sorted((locks or {}).items()))
    for i, kw, err in parsed:
        held = common
        if err is None and "lock" in kw:
            try:
                held = tuple(sorted({**dict(common),
                                     **_record_locks(robot, units, kw["lock"])}.items()))
            except KincalcError as exc:
                errors.append((i, {**head(i, kw), "error": f"record {i + 1}: {exc}"}))
                continue
            kw = {k: v for k, v in kw.items() if k != "lock"}
        groups.setdefault(held, []).append((i, kw, err))
    if together is not None:
        groups.setdefault(common, [])
    blocks, no = [], False
    for held, items in groups.items():
        rows = together if held == common else None
        try:
            b, e, n = _ik_group(robot, units, items, dict(held), rows, start)
        except KincalcError as exc:        # locks this arm cannot take: every record says so
            b, n = [], False
            e = [(i, {**head(i, kw), "error": err or f"record {i + 1}: {words(exc)}"})
                 for i, kw, err in items]
            e += [(i, {"index": i, "error": f"record {i + 1}: {words(exc)}"})
                  for i in ([] if rows is None else (rows.at + start).tolist())]
        blocks += b
        errors += e
        no |= n
    return Answers.joined(blocks, robot.dof), errors, no


class Answers(NamedTuple):
    """The solved IK records of a chunk: ``heads [(index, keywords)]`` the records;
    ``q (s, n)`` the joint values of all their solutions, in display units rounded to 12
    decimals (-0.0 as 0.0); ``labels (s,)`` the branch words; ``within (s,)`` bool, within
    the limits; ``singular (s,)`` bool, at a singular configuration; ``owner (s,)`` the
    record (position in ``heads``) of each solution, ascending."""

    heads: list
    q: object
    labels: list
    within: object
    singular: object
    owner: object

    @staticmethod
    def joined(blocks, n: int) -> "Answers":
        """One Answers of ``blocks`` in their order (``n`` joints)."""
        import numpy as np
        if len(blocks) == 1:
            return blocks[0]
        offsets = np.cumsum([0] + [len(b.heads) for b in blocks])
        return Answers([h for b in blocks for h in b.heads],
                       np.concatenate([b.q for b in blocks] + [np.zeros((0, n))]),
                       [lab for b in blocks for lab in b.labels],
                       np.concatenate([b.within for b in blocks] + [np.zeros(0, bool)]),
                       np.concatenate([b.singular for b in blocks] + [np.zeros(0, bool)]),
                       np.concatenate([b.owner + o for b, o in zip(blocks, offsets)]
                                      + [np.zeros(0, np.intp)]))


def _ik_text(start: int, count: int, answers: Answers, errors) -> bytes:
    """The JSON lines (ASCII) of a chunk of ``count`` records from record ``start``: the
    answers' lines and the error records, in the input's order. When every record is an
    answer with solutions and no id, in order (records read together), the lines are one
    formatting of one template."""
    from operator import itemgetter
    heads = answers.heads
    sols = ik_solutions(answers.q, answers.labels, answers.within, answers.singular,
                        answers.owner, len(heads))
    reach = reachable(answers.within, answers.owner, len(heads))
    if not errors and len(heads) == count and reach.all() and \
            list(map(itemgetter(1), heads)).count(None) == count and \
            list(map(itemgetter(0), heads)) == list(range(start, start + count)):
        args = [None] * (2 * count)
        args[::2] = range(start, start + count)
        args[1::2] = sols
        return (ANSWER + b"\n") * count % tuple(args)
    out = [None] * count
    for (i, kw), text, r in zip(heads, sols, reach.tolist()):
        out[i - start] = answer_line(i, None if kw is None else head(i, kw), text, r)
    encode = strict_json().encode
    for i, rec in errors:
        out[i - start] = encode(rec).encode("ascii")
    return b"\n".join(out) + b"\n" if out else b""


def _ik_records(answers: Answers) -> list:
    """The answers as output records (dicts, for the CSV rows)."""
    import numpy as np
    q, within, singular = answers.q.tolist(), answers.within.tolist(), answers.singular.tolist()
    ends = np.searchsorted(answers.owner, np.arange(1, len(answers.heads) + 1)).tolist()
    reach = reachable(answers.within, answers.owner, len(answers.heads)).tolist()
    recs, start = [], 0
    for (i, kw), end, r in zip(answers.heads, ends, reach):
        sols = [{"q": q[j], "branch": answers.labels[j], "within_limits": within[j],
                 "singular": singular[j]} for j in range(start, end)]
        recs.append({**head(i, kw), "reachable": r, "solutions": sols})
        start = end
    return recs


def _record_locks(robot, units, pairs) -> dict:
    """A record's ``lock`` pairs ``((joint, value in user units), ...)`` as ``{index:
    value (SI)}``."""
    from ..common import joint_index
    out = {}
    for name, value in pairs:
        k = joint_index(name, robot, "lock")
        if k in out:
            from ...errors import InputError
            raise InputError(f"lock: joint {robot.joints[k].name} is held twice")
        out[k] = value / (units.a if robot.joints[k].revolute else units.l)
    if len(out) >= robot.dof:
        from ...errors import InputError
        raise InputError(f"lock: every joint of {robot.name} is held; nothing is left to solve")
    return out


def _ik_group(robot, units, parsed, held, together=None, start: int = 0):
    """``(answer blocks, errors, any pose without a solution)`` of IK records that hold the
    joints ``held`` (SI; none: the robot itself), with the records read ``together`` (or
    None; from record ``start``): the poses ik_batch solves in one block, the others
    (partial poses, a robot without a batched solver) pose by pose in another."""
    import numpy as np

    from ...errors import KincalcError
    from ...errors import UnsupportedRobot
    from ...ik import Target
    from ...ik.labels import solution_order
    from ...ik.solve import solve
    full, T, partial, errors = record_poses(robot, units, parsed, together, start)
    chain = robot
    if held:
        from ...analysis.redundancy import (check_lock, held_within, locked_robot,
                                             solve_locked, with_held)
        chain = locked_robot(robot, held)
        check_lock(robot, chain, held)
    qdisp = np.where(robot.is_revolute, units.a, units.l)
    blocks, no = [], False
    try:
        B = chain.ik_batch(T) if len(T) else None
    except UnsupportedRobot:
        B = None
        partial += [(i, kw, Target(t, orientation=True)) for (i, kw), t in zip(full, T)]
    if B is not None:
        valid = B.valid & np.isfinite(B.q).all(axis=-1)         # (a NaN is no solution)
        q, within = B.q[valid], B.within[valid]                            # (s, n)
        if held:
            q = with_held(robot, q, held)
            within = within & held_within(robot, q, held)
        owner, _ = np.nonzero(valid)
        no = not reachable(within, owner, len(T)).all()     # as ik's: none within the limits
        labels = B.labels[valid].tolist()
        order = solution_order(labels, within, owner)                     # as ik's
        blocks.append(Answers(full, np.round(q[order] * qdisp, 12) + 0.0,
                              [labels[k] for k in order.tolist()], within[order],
                              B.singular[valid][order], owner))
    heads, q, labels, within, singular, owner = [], [], [], [], [], []
    for i, kw, target in partial:
        try:
            # (a record shows no reason: no search for the nearest reachable point)
            result = solve_locked(robot, target, held, reasons=False) if held else \
                solve(robot, target, reasons=False)
        except KincalcError as exc:        # a question this robot cannot take: its record
            errors.append((i, {**head(i, kw), "error": f"record {i + 1}: {words(exc)}"}))
            continue
        sols = [s for s in result.solutions if np.isfinite(s.q).all()]
        no |= not any(not s.violations for s in sols)
        owner += [len(heads)] * len(sols)
        heads.append((i, kw))
        q += [s.q for s in sols]
        labels += [s.branch for s in sols]
        within += [not s.violations for s in sols]
        singular += [s.singular for s in sols]
    if heads:
        q = np.array(q, float).reshape(-1, robot.dof) * qdisp
        blocks.append(Answers(heads, np.round(q, 12) + 0.0, labels, np.array(within, bool),
                              np.array(singular, bool), np.array(owner, np.intp)))
    return blocks, errors, no


def _reach_chunk(robot, units, parsed, frame):
    """Reach records of one chunk (the analysis runs pose by pose)."""
    import math

    from ...errors import KincalcError
    from ...analysis.reach import reach
    from ...analysis.results import json_numbers
    from ..targets import build_target
    out, no = [], False
    for index, kw, error in parsed:
        first = head(index, kw)
        if error is None and FK_LENGTH in kw:
            kw, error = in_run_units(kw, units, index)
        if error is None:
            try:
                pose = {k: v for k, v in kw.items() if k != "id"}
                result = reach(robot, build_target(robot, units, **pose, record=True),
                               units=units)
            except KincalcError as exc:
                error = f"record {index + 1}: {words(exc)}"
        if error is not None:
            out.append({**first, "error": error})
            continue
        if result.distance is not None and not math.isfinite(result.distance):
            out.append({**first, "error": f"record {index + 1}: the distance is not a finite "
                        "number for this pose"})
            continue
        no |= not result.reachable
        out.append({**first, "reachable": result.reachable, "verdict": result.verdict,
                    "distance": None if result.distance is None else
                    json_numbers(result.distance * units.l),
                    "solutions": result.solutions,
                    "solutions_within_limits": result.within_limits,
                    "reason": result.reason})
    return out, no
