"""One chunk of batch records through the vectorised core: fk, jacobian, ik and reach,
each record its answer or its error record (:func:`process_chunk`, pure: safe in a
worker process)."""

from __future__ import annotations

from typing import NamedTuple

from .formats import csv_rows, ik_lines, rounded, strict_json
from .records import parse_records

#: pose forms solved in one vectorised step (others go through build_target per record)
FAST_FORMS = {frozenset({"xyz", "rpy"}), frozenset({"xyz", "euler_zyz"}),
               frozenset({"xyz", "euler_xyz"}), frozenset({"xyz", "quat"}),
               frozenset({"T"}), frozenset({"q"})}


def process_chunk(kind, robot, units, header, fmt, frame, item, locks=None) -> tuple[str, bool, bool]:
    """Parse, solve and format one chunk ``item = (first index, lines)``; returns
    ``(text, any record bad, any pose without a solution)``. Pure: safe to run in a
    worker process. Numbers that come out NaN or infinite make their record an error
    (each chunk function checks its results), so floating-point warnings are not shown.
    ``locks`` (ik): joints held for every record, ``{index: value}`` (SI)."""
    import numpy as np
    start, lines = item
    parsed = parse_records(header, robot, start, lines)
    if kind == "ik":
        with np.errstate(all="ignore"):
            answers, errors, no = _ik_chunk(robot, units, parsed, locks or {})
        if fmt == "jsonl":
            return _ik_text(start, len(parsed), answers, errors), bool(errors), no
        return csv_rows(kind, robot, _merge(_ik_records(answers), errors)), bool(errors), no
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


def _head(i, kw):
    return {"index": i} if kw is None or "id" not in kw else {"index": i, "id": kw["id"]}


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
            errors.append((i, {**_head(i, kw), "error": err}))
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
        errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: the result is not a "
                           "finite number for these values"}))
    return [g for g, o in zip(good, ok) if o], [a[ok] for a in arrays]


def _fk_chunk(robot, units, parsed, frame):
    from ...spatial import rpy_from_matrix
    good, q, errors = _joint_rows(robot, units, parsed, "fk")
    T = robot.fk(q)
    T[:, :3, 3] *= units.l
    rpy = rpy_from_matrix(T[:, :3, :3]) * units.a
    good, (q, T, rpy) = _finite_rows(good, (q, T, rpy), errors)
    from ...ik.engine import within_limits
    within = within_limits(robot, q)
    Tl, xyz, rpyl = rounded(T), rounded(T[:, :3, 3]), rounded(rpy)
    recs = [{**_head(i, kw), "T": Tl[k], "xyz": xyz[k], "rpy": rpyl[k],
             "within_limits": bool(within[k])} for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _jacobian_chunk(robot, units, parsed, frame):
    import numpy as np

    from ...jacobian import rotate_jacobian, scaled_ranks
    good, q, errors = _joint_rows(robot, units, parsed, "jacobian")
    Jb = robot.jacobian(q)                                                 # (m, 6, n) SI, base
    good, (q, Jb) = _finite_rows(good, (q, Jb), errors)
    J = Jb
    if frame == "tool" and len(q):
        J = rotate_jacobian(Jb, np.swapaxes(robot.fk(q)[:, :3, :3], -1, -2))
    # rank and singularity as 'kincalc jacobian' (analysis.jacobian_report)
    rank, position_rank = scaled_ranks(Jb, robot.is_revolute, robot.characteristic_length)
    full, full_pos = robot.generic_ranks
    singular = (rank < full) | (position_rank < full_pos)
    Jd = J.copy()
    Jd[:, :3] *= np.where(robot.is_revolute, units.l, 1.0)
    manip = np.prod(np.linalg.svd(Jd, compute_uv=False)[:, :full], axis=-1) if len(q) \
        else np.zeros(0)
    good, (Jd, manip, rank, singular) = _finite_rows(good, (Jd, manip, rank, singular), errors)
    Jl = rounded(Jd)
    recs = [{**_head(i, kw), "J": Jl[k], "rank": int(rank[k]),
             "manipulability": float(manip[k]), "singular": bool(singular[k])}
            for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _poses(robot, units, parsed):
    """Group records by how they are solved: ``(full [(index, kw)], T (m, 4, 4) SI,
    partial [(index, kw, Target)], error records)``. Full poses of the common forms are
    built in one vectorised step per form (:func:`kincalc.ik.target.targets_from`); the
    rest go through build_target one by one."""
    import numpy as np

    from ...errors import KincalcError
    from ...ik.target import defect_text, targets_from, to_si
    from ..common import check_numbers
    from ..targets import pose_values, build_target
    groups, partial, errors = {}, [], []
    full, Ts = [], []
    for i, kw, err in parsed:
        if err is None:
            form = frozenset(kw) - {"id"}
            if form in FAST_FORMS and (form != {"q"} or len(kw["q"]) == robot.dof):
                groups.setdefault(form, []).append((i, kw))
                continue
            try:
                target = build_target(robot, units, **{k: v for k, v in kw.items() if k != "id"})
            except KincalcError as exc:
                err = f"record {i + 1}: {_words(exc)}"
            else:
                if target.orientation and target.tcv is None and target.approach is None:
                    full.append((i, kw))
                    Ts.append(np.asarray(target.T, float).reshape(1, 4, 4))
                else:
                    partial.append((i, kw, target))
                continue
        errors.append((i, {**_head(i, kw), "error": err}))
    for form, items in groups.items():
        if form == {"q"}:
            q = np.array([kw["q"] for _, kw in items]) / np.where(robot.is_revolute, units.a,
                                                                  units.l)
            T = robot.fk(q)
        else:
            key = "T" if form == {"T"} else next(iter(form - {"xyz"}))
            xyz = None
            if key == "T":
                v = np.array([_pose_matrix(kw["T"]).ravel() for _, kw in items])
            else:
                v = np.array([kw[key] for _, kw in items], float)
                xyz = np.array([kw["xyz"] for _, kw in items], float).reshape(-1, 3) / units.l
            targets, defect = targets_from(key, to_si(key, v, units), xyz)
            bad = ~np.isfinite(v).all(-1) | (defect != None)  # noqa: E711
            for k in np.flatnonzero(bad):
                i, kw = items[k]
                try:
                    if key == "T":           # a wrong count, or a number beyond the limits
                        pose_values(np.array(kw["T"], float), "T")
                    else:
                        check_numbers(v[k], key)
                    msg = defect_text(key, defect[k], key)
                except KincalcError as exc:
                    msg = str(exc)
                errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {msg}"}))
            if bad.any():
                items = [it for it, b in zip(items, bad) if not b]
                T = targets.T[~bad]
            else:
                T = targets.T
        full += items
        Ts.append(np.asarray(T, float).reshape(-1, 4, 4))
    T = np.concatenate(Ts) if Ts else np.zeros((0, 4, 4))
    return full, T, partial, errors


#: how a batch record names the parts of an IK target, for the core's messages about
#: them (:class:`kincalc.errors.TargetMismatch`)
RECORD_WORDS = {"approach": "approach", "tcv": "tcv", "prefix": "{field}: ",
                "orientation": "(rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, tcv, T "
                               "or q)"}


def _words(exc) -> str:
    """A core error's message for a record, its fields named as records name them."""
    from ...errors import TargetMismatch
    return exc.words(RECORD_WORDS) if isinstance(exc, TargetMismatch) else str(exc)


def _pose_matrix(flat):
    """A record's ``T`` (16 or 12 numbers) as a 4x4 matrix, NaN for another count."""
    import numpy as np
    a = np.array(flat, float)
    if a.size == 16:
        return a.reshape(4, 4)
    if a.size == 12:
        return np.vstack([a.reshape(3, 4), [0, 0, 0, 1]])
    return np.full((4, 4), np.nan)


def _ik_chunk(robot, units, parsed, locks=None):
    """``(answers, error records, any pose without a solution)`` of the IK records of one
    chunk, grouped by the joints they hold (``locks``, SI, for every record, and each
    record's own ``lock``, which adds to them and wins for a joint both name): each group
    solved on the chain its locks leave, in one batch."""
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
                errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {exc}"}))
                continue
            kw = {k: v for k, v in kw.items() if k != "lock"}
        groups.setdefault(held, []).append((i, kw, err))
    blocks, no = [], False
    for held, items in groups.items():
        try:
            b, e, n = _ik_group(robot, units, items, dict(held))
        except KincalcError as exc:        # locks this arm cannot take: every record says so
            b, n = [], False
            e = [(i, {**_head(i, kw), "error": err or f"record {i + 1}: {_words(exc)}"})
                 for i, kw, err in items]
        blocks += b
        errors += e
        no |= n
    return Answers.joined(blocks, robot.dof), errors, no


class Answers(NamedTuple):
    """The solved IK records of a chunk: ``heads [(index, keywords)]`` the records;
    ``q (s, n)`` the joint values of all their solutions, in display units rounded to 12
    decimals (-0.0 as 0.0); ``labels (s,)`` the branch words; ``within (s,)`` bool, within
    the limits; ``owner (s,)`` the record (position in ``heads``) of each solution,
    ascending."""

    heads: list
    q: object
    labels: list
    within: object
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
                       np.concatenate([b.owner + o for b, o in zip(blocks, offsets)]
                                      + [np.zeros(0, np.intp)]))


def _ik_text(start: int, count: int, answers: Answers, errors) -> str:
    """The JSON lines of a chunk of ``count`` records from record ``start``: the answers'
    lines and the error records, in the input's order."""
    out = [None] * count
    lines = ik_lines([_head(i, kw) for i, kw in answers.heads], answers.q, answers.labels,
                     answers.within, answers.owner)
    for (i, _), line in zip(answers.heads, lines):
        out[i - start] = line
    encode = strict_json().encode
    for i, rec in errors:
        out[i - start] = encode(rec)
    return "\n".join(out) + "\n" if out else ""


def _ik_records(answers: Answers) -> list:
    """The answers as output records (dicts, for the CSV rows)."""
    import numpy as np
    q, within = answers.q.tolist(), answers.within.tolist()
    ends = np.searchsorted(answers.owner, np.arange(1, len(answers.heads) + 1)).tolist()
    recs, start = [], 0
    for (i, kw), end in zip(answers.heads, ends):
        sols = [{"q": q[j], "branch": answers.labels[j], "within_limits": within[j]}
                for j in range(start, end)]
        recs.append({**_head(i, kw), "reachable": bool(sols), "solutions": sols})
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


def _ik_group(robot, units, parsed, held):
    """``(answer blocks, errors, any pose without a solution)`` of IK records that hold the
    joints ``held`` (SI; none: the robot itself): the poses ik_batch solves in one block,
    the others (partial poses, a robot without a batched solver) pose by pose in another."""
    import numpy as np

    from ...errors import KincalcError
    from ...errors import UnsupportedRobot
    from ...ik import Target
    from ...ik.solve import solve
    full, T, partial, errors = _poses(robot, units, parsed)
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
        no = not valid.any(axis=1).all()
        blocks.append(Answers(full, np.round(q * qdisp, 12) + 0.0, B.labels[valid].tolist(),
                              within, owner))
    heads, q, labels, within, owner = [], [], [], [], []
    for i, kw, target in partial:
        try:
            result = solve_locked(robot, target, held) if held else solve(robot, target)
        except KincalcError as exc:        # a question this robot cannot take: its record
            errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {_words(exc)}"}))
            continue
        sols = [s for s in result.solutions if np.isfinite(s.q).all()]
        no |= not sols
        owner += [len(heads)] * len(sols)
        heads.append((i, kw))
        q += [s.q for s in sols]
        labels += [s.branch for s in sols]
        within += [not s.violations for s in sols]
    if heads:
        q = np.array(q, float).reshape(-1, robot.dof) * qdisp
        blocks.append(Answers(heads, np.round(q, 12) + 0.0, labels, np.array(within, bool),
                              np.array(owner, np.intp)))
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
        head = _head(index, kw)
        if error is None:
            try:
                pose = {k: v for k, v in kw.items() if k != "id"}
                result = reach(robot, build_target(robot, units, **pose), units=units)
            except KincalcError as exc:
                error = f"record {index + 1}: {_words(exc)}"
        if error is not None:
            out.append({**head, "error": error})
            continue
        if result.distance is not None and not math.isfinite(result.distance):
            out.append({**head, "error": f"record {index + 1}: the distance is not a finite "
                        "number for this pose"})
            continue
        no |= not result.reachable
        out.append({**head, "reachable": result.reachable, "verdict": result.verdict,
                    "distance": None if result.distance is None else
                    json_numbers(result.distance * units.l),
                    "solutions": result.solutions,
                    "solutions_within_limits": result.within_limits,
                    "reason": result.reason})
    return out, no
