"""The IK targets of a chunk's records: whole poses of the common forms built in one
vectorised step a form, the others record by record (:func:`record_poses`), with the words
of the records' errors (:func:`head`, :func:`words`)."""

from __future__ import annotations

from .records import FK_LENGTH

#: pose forms solved in one vectorised step (others go through build_target per record)
FAST_FORMS = {frozenset({"xyz", "rpy"}), frozenset({"xyz", "euler_zyz"}),
              frozenset({"xyz", "euler_xyz"}), frozenset({"xyz", "quat"}),
              frozenset({"T"}), frozenset({"q"})}


def head(i, kw) -> dict:
    """The fields an output record of record ``i`` (its keywords ``kw``, or None) begins
    with: its index, and its id when it has one."""
    return {"index": i} if kw is None or "id" not in kw else {"index": i, "id": kw["id"]}


def words(exc) -> str:
    """A core error's message for a record, its fields named as records name them."""
    from ...errors import TargetMismatch
    from ...analysis.requests import FIELD_WORDS
    return exc.words(FIELD_WORDS) if isinstance(exc, TargetMismatch) else str(exc)


def in_run_units(kw: dict, units, i: int) -> tuple:
    """``(kw, None)``: an fk --batch record's keywords with its T in this run's length unit
    (from the unit the record says), or ``(kw, error)``: no unit converts to or from
    ``unitless``."""
    from ...units import length_factor
    kw = dict(kw)
    length = kw.pop(FK_LENGTH)
    if length == units.length:
        return kw, None
    if "unitless" in (length, units.length):
        return kw, (f"record {i + 1}: its T is in {length} (an fk --batch record's units), "
                    f"this run's lengths are {units.length}")
    scale = length_factor(length) / length_factor(units.length)
    kw["T"] = tuple(v * scale if k % 4 == 3 and k < 12 else v for k, v in enumerate(kw["T"]))
    return kw, None


def record_poses(robot, units, parsed, together=None, start: int = 0):
    """Group records by how they are solved: ``(full [(index, kw)], T (m, 4, 4) SI,
    partial [(index, kw, Target)], error records)``. Full poses of the common forms are
    built in one vectorised step per form (:func:`kincalc.ik.target.targets_from`); the
    rest go through build_target one by one. ``together``: the records read together
    (:class:`~kincalc.cli.batch.uniform.Together`, its lines from record ``start``), of a
    form built in one step with the records of ``parsed`` of that form, in the input's
    order (their ``kw`` None in ``full``).

    The poses are in the order of the records read one by one: first those built one by
    one, then each form's, the forms in the order they first appear."""
    import numpy as np

    from ...errors import KincalcError
    from ..targets import build_target
    groups, partial, errors = {}, [], []
    full, Ts = [], []
    for i, kw, err in parsed:
        if err is None and FK_LENGTH in kw:
            kw, err = in_run_units(kw, units, i)
        if err is None:
            form = frozenset(kw) - {"id"}
            if form in FAST_FORMS and (form != {"q"} or len(kw["q"]) == robot.dof):
                groups.setdefault(form, []).append((i, kw))
                continue
            try:
                target = build_target(robot, units, record=True,
                                      **{k: v for k, v in kw.items() if k != "id"})
            except KincalcError as exc:
                err = f"record {i + 1}: {words(exc)}"
            else:
                if target.orientation and target.tcv is None and target.approach is None:
                    full.append((i, kw))
                    Ts.append(np.asarray(target.T, float).reshape(1, 4, 4))
                else:
                    partial.append((i, kw, target))
                continue
        errors.append((i, {**head(i, kw), "error": err}))
    rows = {}
    if together is not None and len(together.at):
        form = frozenset(key for key, _ in together.fields)
        rows[form] = together
        first = {f: items[0][0] for f, items in groups.items()}
        first[form] = min(first.get(form, np.inf), start + int(together.at[0]))
        groups = {f: groups.get(f, []) for f in sorted(first, key=first.__getitem__)}
    for form, items in groups.items():
        items, T = _form_poses(robot, units, form, items, rows.get(form), start, errors)
        full += items
        Ts.append(np.asarray(T, float).reshape(-1, 4, 4))
    T = np.concatenate(Ts) if Ts else np.zeros((0, 4, 4))
    return full, T, partial, errors


def _form_poses(robot, units, form, items, together, start, errors):
    """``(items, T (m, 4, 4))``: the good records of one form of FAST_FORMS, ``items``
    ``[(index, kw)]`` and the lines read ``together`` (None: none) in the input's order, and
    their poses; the others' error records appended to ``errors``."""
    import numpy as np

    from ...errors import KincalcError
    from ...analysis.requests import to_si
    from ...ik.target import defect_text, targets_from
    from ..common import check_numbers
    from ..targets import pose_values
    key = "q" if form == {"q"} else "T" if form == {"T"} else next(iter(form - {"xyz"}))
    items, v, xyz = _form_values(key, items, together, start)
    if key == "q":
        return items, robot.fk(v / np.where(robot.is_revolute, units.a, units.l), column_walk=True)
    if xyz is not None:
        xyz = xyz / units.l
    targets, defect = targets_from(key, to_si(key, v, units), xyz)
    bad = ~np.isfinite(v).all(-1) | (defect != None)  # noqa: E711
    for k in np.flatnonzero(bad):
        i, kw = items[k]
        try:
            if key == "T":               # a wrong count, or a number beyond the limits
                pose_values(np.array(kw["T"], float), "T")
            else:
                check_numbers(v[k], key)
            msg = defect_text(key, defect[k], key)
        except KincalcError as exc:
            msg = str(exc)
        errors.append((i, {**head(i, kw), "error": f"record {i + 1}: {msg}"}))
    if bad.any():
        return [it for it, b in zip(items, bad) if not b], targets.T[~bad]
    return items, targets.T


def _form_values(key: str, items, together, start: int):
    """``(items, values (m, k), xyz (m, 3) or None)``: the records of one form, those read
    one by one (``items``) and together (``together``, or None) merged in the input's
    order, their ``key`` values and positions (as given, C-ordered arrays)."""
    import numpy as np
    xyz = None
    if items:
        if key == "T":
            v = np.array([_pose_matrix(kw["T"]).ravel() for _, kw in items])
        else:
            v = np.array([kw[key] for _, kw in items], float)
            if key != "q":
                xyz = np.array([kw["xyz"] for _, kw in items], float).reshape(-1, 3)
    if together is None:
        return items, v, xyz
    ends = np.cumsum([count for _, count in together.fields])
    span = {k: (end - count, end) for (k, count), end in zip(together.fields, ends.tolist())}
    vt = np.ascontiguousarray(together.values[:, slice(*span[key])])
    xyzt = None if key == "q" else np.ascontiguousarray(together.values[:, slice(*span["xyz"])])
    index = (together.at + start).tolist()
    if not items:
        return [(i, None) for i in index], vt, xyzt
    order = np.argsort([i for i, _ in items] + index, kind="stable")
    merged = items + [(i, None) for i in index]
    return ([merged[k] for k in order.tolist()], np.concatenate((v, vt))[order],
            None if xyz is None else np.concatenate((xyz, xyzt))[order])


def _pose_matrix(flat):
    """A record's ``T`` (16 or 12 numbers) as a 4x4 matrix, NaN for another count."""
    import numpy as np
    a = np.array(flat, float)
    if a.size == 16:
        return a.reshape(4, 4)
    if a.size == 12:
        return np.vstack([a.reshape(3, 4), [0, 0, 0, 1]])
    return np.full((4, 4), np.nan)
