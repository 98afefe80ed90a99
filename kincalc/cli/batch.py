"""``--batch FILE|-``: many inputs, one output record per input, in order.

Input is JSON lines (one object per line) or CSV with a header row; the
first non-blank line decides (``{`` starts JSON lines). A record holds a
pose in any of the forms of PRODUCT.md:

* JSON: ``{"xyz": [x, y, z], "rpy": [r, p, y]}``, with ``euler_zyz``,
  ``euler_xyz``, ``quat``, ``axis_angle``, ``matrix``, ``approach`` or ``tcv``
  instead of ``rpy``; or ``{"T": [[...], ...]}`` (4x4); or ``{"q": [...]}``
  (the pose FK gives for these joints);
* CSV: columns ``x, y, z`` with ``roll, pitch, yaw`` or ``qw, qx, qy, qz`` or
  ``ax, ay, az`` (approach), or one column per joint named as in the robot file
  (plain comma-separated numbers, no quoting).

An ``id`` field of a JSON record is echoed in its output record. Records are
counted from 1 in messages ("record 3") and indexed from 0 in ``index``.

Values are in the command's units (``--deg/--rad``, ``--unit``). A record
that cannot be read becomes ``{"index": i, "error": "..."}`` and the run goes
on; the exit status then says so (2).
"""

from __future__ import annotations

import sys

#: pose keys of a JSON record and the number of values each takes
POSE_KEYS = {"xyz": 3, "rpy": 3, "euler_zyz": 3, "euler_xyz": 3, "quat": 4, "axis_angle": 4,
             "matrix": 9, "approach": 3, "tcv": 6}
#: CSV column groups and the pose key they fill
CSV_GROUPS = {("x", "y", "z"): "xyz", ("roll", "pitch", "yaw"): "rpy",
              ("qw", "qx", "qy", "qz"): "quat", ("ax", "ay", "az"): "approach"}


class RecordError(ValueError):
    """A batch record that cannot be used; the message names what is wrong."""


def _parse(header, robot, start: int, lines) -> list:
    """:func:`records` of one chunk of lines, the first being record ``start``."""
    import json
    out = []
    for i, line in enumerate(lines, start):
        if header is None:
            out.append(_json_record(i, line, json))
            continue
        try:
            out.append((i, _csv_record(header, line, robot), None))
        except RecordError as exc:
            out.append((i, None, f"record {i + 1}: {exc}"))
    return out


def _json_record(i, line, json):
    try:
        rec = json.loads(line)
    except ValueError as exc:
        return i, None, f"record {i + 1}: not JSON ({exc.msg})"
    if not isinstance(rec, dict):
        return i, None, f"record {i + 1}: expected a JSON object"
    try:
        return i, _pose_keywords(rec, i + 1), None
    except RecordError as exc:
        return i, None, str(exc)


def _numbers(value, count, where) -> tuple:
    import math
    if not isinstance(value, (list, tuple)) or (count and len(value) != count):
        raise RecordError(f"{where}: expected {count} numbers")
    try:
        out = tuple(map(float, value))
    except (TypeError, ValueError):
        raise RecordError(f"{where}: expected numbers") from None
    if not all(map(math.isfinite, out)):
        raise RecordError(f"{where}: values must be finite")
    return out


def _pose_keywords(rec: dict, line: int) -> dict:
    known = set(POSE_KEYS) | {"T", "q", "id"}
    unknown = [k for k in rec if k not in known]
    if unknown:
        raise RecordError(f"record {line}: unknown field {unknown[0]!r} (pose fields: "
                          f"{', '.join(list(POSE_KEYS) + ['T', 'q'])})")
    out = {}
    for key, count in POSE_KEYS.items():
        if key in rec:
            out[key] = _numbers(rec[key], count, f"record {line}: {key}")
    if "T" in rec:
        flat = rec["T"]
        if isinstance(flat, list) and flat and isinstance(flat[0], list):
            flat = [x for row in flat for x in (row if isinstance(row, list) else [row])]
        out["T"] = _numbers(flat, 0, f"record {line}: T")
    if "q" in rec:
        out["q"] = _numbers(rec["q"], 0, f"record {line}: q")
    if not out:
        raise RecordError(f"record {line}: no pose (give xyz and an orientation, T or q)")
    if "id" in rec:
        out["id"] = rec["id"]
    return out


def _csv_record(header, line, robot) -> dict:
    cells = [c.strip() for c in line.strip().split(",")]
    if len(cells) != len(header):
        raise RecordError(f"{len(cells)} values for {len(header)} columns")
    try:
        row = {h: float(c) for h, c in zip(header, cells)}
    except ValueError:
        bad = next(c for c in cells if not _is_float(c))
        raise RecordError(f"{bad!r} is not a number") from None
    out = {}
    used = set()
    for cols, key in CSV_GROUPS.items():
        if all(c in row for c in cols):
            out[key] = tuple(row[c] for c in cols)
            used |= set(cols)
    names = [j.name for j in robot.joints]
    if all(n in row for n in names):
        out["q"] = tuple(row[n] for n in names)
        used |= set(names)
    extra = [h for h in header if h not in used]
    if extra:
        raise RecordError(f"unknown column {extra[0]!r} (columns: x,y,z with roll,pitch,yaw or "
                          f"qw,qx,qy,qz or ax,ay,az; or the joints {','.join(names)})")
    return out


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _csv_cell(value):
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return value


# --- chunked, vectorised batch runs of fk, jacobian and ik -------------------------------
#
# The input is read in chunks of CHUNK_LINES lines; each chunk is parsed, solved
# through the vectorised core and formatted by the pure function process_chunk, in this
# process or, with --jobs N, in N worker processes (at most 2 N chunks in flight, so
# memory stays constant whatever the input's size; the output keeps the input's order).

CHUNK_LINES = 2048
#: reach analyses pose by pose (milliseconds each): smaller chunks, so that answers and
#: the progress bar come at once and --jobs has work to share
REACH_CHUNK_LINES = 64
#: the per-pose fields of a reach record, in CSV column order
REACH_FIELDS = ["index", "reachable", "verdict", "distance", "solutions",
                "solutions_within_limits", "reason", "error"]
#: pose forms solved in one vectorised step (others go through build_target per record)
_FAST_FORMS = {frozenset({"xyz", "rpy"}), frozenset({"xyz", "euler_zyz"}),
               frozenset({"xyz", "euler_xyz"}), frozenset({"xyz", "quat"}),
               frozenset({"T"}), frozenset({"q"})}


def run_command(kind: str, robot, units, src: str, fmt: str, jobs: int, *, given=(),
                frame: str = "base", refused: dict | None = None):
    """The --batch branch of a command: refuse the command's own inputs (``given``, the
    values of its joint or pose arguments) and the options in ``refused``, run, and leave
    with the batch's exit status."""
    import typer

    from ..errors import UsageError
    if any(v is not None and len(v) for v in given):
        raise UsageError("--batch reads its input from a file; do not give "
                         f"{'pose options' if kind in ('ik', 'reach') else 'joint values'} too")
    for option, value in (refused or {}).items():
        if value:
            raise UsageError(f"{option} does not combine with --batch")
    raise typer.Exit(run(kind, robot, units, src, fmt, jobs, frame))


def run(kind: str, robot, units, src: str, fmt: str, jobs: int = 1, frame: str = "base") -> int:
    """Answer every record of ``src`` with ``kind`` ('fk', 'jacobian' or 'ik'); write the
    output records to stdout; return the exit status (2 if any record was bad, 1 if all
    were good but some pose had no solution, else 0)."""
    from functools import partial
    if fmt not in ("jsonl", "csv"):
        from ..errors import UsageError
        raise UsageError(f"--format must be jsonl or csv, not {fmt!r}")
    if jobs < 1:
        from ..errors import UsageError
        raise UsageError(f"--jobs must be at least 1, not {jobs}")
    source = _Source(src)
    header, chunks = _chunked(source, REACH_CHUNK_LINES if kind == "reach" else CHUNK_LINES)
    work = partial(process_chunk, kind, robot, units, header, fmt, frame)
    if fmt == "csv":
        sys.stdout.write(_csv_header(kind, robot))
    bad = no = False
    with _progress(source) as advance:
        for text, b, n in _ordered_map(work, chunks, jobs):
            sys.stdout.write(text)
            sys.stdout.flush()
            bad |= b
            no |= n
            advance(source.position)
    return 2 if bad else 1 if no else 0


class _Source:
    """Lines of a file or stdin, counting the bytes read (for the progress bar)."""

    def __init__(self, src: str):
        from ..errors import InputError
        self.src, self.position, self.size = src, 0, None
        if src == "-":
            self.fh = sys.stdin
            return
        try:
            self.fh = open(src, encoding="utf-8")
            import os
            self.size = os.fstat(self.fh.fileno()).st_size
        except OSError as exc:
            raise InputError(f"--batch {src}: cannot read ({exc.strerror})") from None

    def __iter__(self):
        try:
            for line in self.fh:
                self.position += len(line)
                if line.strip():
                    yield line
        finally:
            if self.fh is not sys.stdin:
                self.fh.close()


def _chunked(source, size: int = 0):
    """``(header or None, iterator of (first index, [lines]))``, at most ``size`` lines
    a chunk (default CHUNK_LINES); a CSV header is the first non-blank line when that
    does not start with '{'."""
    size = size or CHUNK_LINES
    lines = iter(source)
    first = next(lines, None)
    header = None
    if first is not None and not first.lstrip().startswith("{"):
        header = [h.strip() for h in first.strip().split(",")]
        first = None

    def chunks():
        import itertools
        index = 0
        pending = [] if first is None else [first]
        while True:
            block = pending + list(itertools.islice(lines, size - len(pending)))
            pending = []
            if not block:
                return
            yield index, block
            index += len(block)

    def chunks_as_they_come():
        """From a pipe: a chunk is what has arrived (up to ``size`` lines), so that a
        producer writing one pose at a time gets each answer at once."""
        import queue
        import threading
        q: queue.Queue = queue.Queue(maxsize=4 * size)
        end = object()

        def read():
            for line in lines:
                q.put(line)
            q.put(end)
        threading.Thread(target=read, daemon=True).start()
        index = 0
        block = [] if first is None else [first]
        while True:
            if not block:
                item = q.get()
                if item is end:
                    return
                block.append(item)
            while len(block) < size:
                try:
                    item = q.get_nowait()
                except queue.Empty:
                    break
                if item is end:
                    yield index, block
                    return
                block.append(item)
            yield index, block
            index += len(block)
            block = []
    return header, (chunks_as_they_come() if source.size is None else chunks())


def _ordered_map(fn, items, jobs: int):
    """``map(fn, items)`` in order, over ``jobs`` processes, at most 2 jobs chunks ahead."""
    if jobs == 1:
        for item in items:
            yield fn(item)
        return
    from collections import deque
    from concurrent.futures import ProcessPoolExecutor
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        window = deque()
        for item in items:
            window.append(pool.submit(fn, item))
            if len(window) >= 2 * jobs:
                yield window.popleft().result()
        while window:
            yield window.popleft().result()


class _progress:
    """A rich progress bar on stderr when stderr is a terminal and the input a file."""

    def __init__(self, source):
        self.source, self.bar = source, None

    def __enter__(self):
        if self.source.size and sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import (BarColumn, DownloadColumn, Progress, TextColumn,
                                       TimeRemainingColumn)
            self.bar = Progress(TextColumn("{task.description}"), BarColumn(), DownloadColumn(),
                                TimeRemainingColumn(), console=Console(stderr=True),
                                transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.source.src, total=self.source.size)
            return lambda pos: self.bar.update(self.task, completed=pos)
        return lambda pos: None

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.stop()
        return False


def _csv_header(kind, robot) -> str:
    names = [j.name for j in robot.joints]
    if kind == "fk":
        cols = ["index", "id", "x", "y", "z", "roll", "pitch", "yaw", "within_limits", "error"]
    elif kind == "jacobian":
        cols = ["index", "id"] + [f"J{r}_{c}" for r in ("vx", "vy", "vz", "wx", "wy", "wz")
                                  for c in names] + ["rank", "manipulability", "singular", "error"]
    elif kind == "reach":
        cols = REACH_FIELDS
    else:
        cols = ["index", "id", "solution", "branch"] + names + ["within_limits", "error"]
    return ",".join(cols) + "\n"


def process_chunk(kind, robot, units, header, fmt, frame, item) -> tuple[str, bool, bool]:
    """Parse, solve and format one chunk ``item = (first index, lines)``; returns
    ``(text, any record bad, any pose without a solution)``. Pure: safe to run in a
    worker process."""
    import json
    from functools import partial
    start, lines = item
    parsed = _parse(header, robot, start, lines)
    solve = {"fk": _fk_chunk, "jacobian": _jacobian_chunk, "reach": _reach_chunk,
             "ik": partial(_ik_chunk, fmt=fmt)}[kind]
    records, no = solve(robot, units, parsed, frame)
    bad = any("error" in r for r in records)
    if fmt == "jsonl":
        dump = _ik_json if kind == "ik" else partial(json.dumps, allow_nan=False)
        text = "".join(dump(r) + "\n" for r in records)
    else:
        text = _csv_rows(kind, robot, records)
    return text, bad, no


def _ik_json(r) -> str:
    """One ik output record as JSON; the solutions' joint values are written with 12
    significant digits by one format per solution (json.dumps spends ~0.5 us on the
    shortest repr of each float, most of a batch run's time)."""
    import json
    if "solutions" not in r:
        return json.dumps(r)
    head = json.dumps({k: v for k, v in r.items() if k != "solutions"})[:-1]
    if isinstance(r["solutions"], _SolutionsJSON):
        return f'{head}, "solutions": [{r["solutions"]}]}}'
    sols = ", ".join('{"q": [%s], "branch": %s, "within_limits": %s}'
                     % (", ".join(["%.12g"] * len(s["q"])) % tuple(s["q"]),
                        json.dumps(s["branch"]), "true" if s["within_limits"] else "false")
                     for s in r["solutions"])
    return f'{head}, "solutions": [{sols}]}}'


class _SolutionsJSON(str):
    """A pose's solutions already written as JSON (the items of the array), by
    :func:`_solutions_json` for a whole chunk at once."""


def _solutions_json(ql, labels, within, owner, count) -> list:
    """The JSON text of each pose's solutions, for ``count`` poses: ``ql (s, n)`` the
    display values (rounded), ``labels``/``within (s,)`` and ``owner (s,)`` the pose of
    each solution, ascending. One %-format runs over all solutions of the chunk (per
    solution formatting in Python was the largest cost of a batch run); the numbers are
    written with 12 significant digits, as :func:`_ik_json` writes them."""
    import json

    import numpy as np
    s, n = ql.shape
    one = ('{"q": [' + ", ".join(["%.12g"] * n) + '], "branch": %s, "within_limits": %s}\x1e')
    quoted = {lab: json.dumps(lab) for lab in set(labels)}
    cells = np.empty((s, n + 2), object)
    cells[:, :n] = ql
    cells[:, n] = [quoted[lab] for lab in labels]
    cells[:, n + 1] = np.where(within, "true", "false")
    items = ((one * s) % tuple(cells.ravel().tolist())).split("\x1e")
    ends = np.searchsorted(owner, np.arange(1, count + 1)).tolist()
    out, start = [], 0
    for end in ends:
        out.append(_SolutionsJSON(", ".join(items[start:end])))
        start = end
    return out


def _round(a):
    """Arrays as nested lists rounded to 12 decimals, -0.0 as 0.0 (as results._clean)."""
    import numpy as np
    return (np.round(a, 12) + 0.0).tolist()


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


def _fk_chunk(robot, units, parsed, frame):

    from ..spatial import rpy_from_matrix
    good, q, errors = _joint_rows(robot, units, parsed, "fk")
    T = robot.fk(q)
    T[:, :3, 3] *= units.l
    rpy = rpy_from_matrix(T[:, :3, :3]) * units.a
    from ..ik.engine import within_limits
    within = within_limits(robot, q)
    Tl, xyz, rpyl = _round(T), _round(T[:, :3, 3]), _round(rpy)
    recs = [{**_head(i, kw), "T": Tl[k], "xyz": xyz[k], "rpy": rpyl[k],
             "within_limits": bool(within[k])} for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _jacobian_chunk(robot, units, parsed, frame):
    import numpy as np

    from ..jacobian import rotate_jacobian, scaled_ranks
    good, q, errors = _joint_rows(robot, units, parsed, "jacobian")
    Jb = robot.jacobian(q)                                                 # (m, 6, n) SI, base
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
    Jl = _round(Jd)
    recs = [{**_head(i, kw), "J": Jl[k], "rank": int(rank[k]),
             "manipulability": float(manip[k]), "singular": bool(singular[k])}
            for k, (i, kw) in enumerate(good)]
    return _merge(recs, errors), False


def _poses(robot, units, parsed):
    """Group records by how they are solved: ``(full [(index, kw)], T (m, 4, 4) SI,
    partial [(index, kw, Target)], error records)``. Full poses of the common forms are
    converted in one vectorised step; the rest go through build_target one by one."""
    import numpy as np

    from .. import spatial as sp
    from ..errors import KincalcError
    from .ik import build_target
    groups, partial, errors = {}, [], []
    full, Ts = [], []
    for i, kw, err in parsed:
        if err is None:
            form = frozenset(kw) - {"id"}
            if form in _FAST_FORMS and (form != {"q"} or len(kw["q"]) == robot.dof):
                groups.setdefault(form, []).append((i, kw))
                continue
            try:
                target = build_target(robot, units, **{k: v for k, v in kw.items() if k != "id"})
            except KincalcError as exc:
                err = f"record {i + 1}: {exc}"
            else:
                if target.orientation and target.tcv is None and target.approach is None:
                    full.append((i, kw))
                    Ts.append(target.T)
                else:
                    partial.append((i, kw, target))
                continue
        errors.append((i, {**_head(i, kw), "error": err}))
    A, Lf = 1.0 / units.a, 1.0 / units.l
    for form, items in groups.items():
        if form == {"q"}:
            q = np.array([kw["q"] for _, kw in items]) / np.where(robot.is_revolute, units.a,
                                                                  units.l)
            T = robot.fk(q)
        elif form == {"T"}:
            T = np.array([_pose_matrix(kw["T"]) for _, kw in items])
            bad = _not_poses(T)
            if bad.any():
                from .ik import _check_pose
                for k in np.flatnonzero(bad)[::-1]:
                    i, kw = items[k]
                    try:
                        _check_pose(T[k], "T")
                        msg = "T is not a rigid transform"
                    except KincalcError as exc:
                        msg = str(exc)
                    errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {msg}"}))
                keep = ~bad
                items = [it for it, g in zip(items, keep) if g]
                T = T[keep]
            T[:, :3, 3] *= Lf
        else:
            key = next(iter(form - {"xyz"}))
            v = np.array([kw[key] for _, kw in items], float)
            if key == "quat":
                n = np.linalg.norm(v, axis=-1)
                zero = n < 1e-12
                for k in np.flatnonzero(zero):
                    i, kw = items[k]
                    errors.append((i, {**_head(i, kw), "error":
                                       f"record {i + 1}: quat must not be the zero quaternion"}))
                items = [it for it, z in zip(items, zero) if not z]
                R = sp.matrix_from_quaternion(v[~zero] / n[~zero, None])
            else:
                make = {"rpy": sp.matrix_from_rpy, "euler_zyz": sp.matrix_from_euler_zyz,
                        "euler_xyz": sp.matrix_from_euler_xyz}[key]
                R = make(v * A)
            T = np.zeros((len(items), 4, 4))
            T[:, :3, :3] = R
            T[:, :3, 3] = np.array([kw["xyz"] for _, kw in items], float).reshape(-1, 3) * Lf
            T[:, 3, 3] = 1.0
        full += items
        Ts.extend(T)
    T = np.array(Ts, float).reshape(-1, 4, 4)
    return full, T, partial, errors


def _pose_matrix(flat):
    import numpy as np
    a = np.array(flat, float)
    if a.size == 16:
        return a.reshape(4, 4)
    if a.size == 12:
        return np.vstack([a.reshape(3, 4), [0, 0, 0, 1]])
    return np.full((4, 4), np.nan)


def _not_poses(T):
    """Which of ``T (m, 4, 4)`` are not rigid transforms (to 1e-6)."""
    import numpy as np
    R = T[:, :3, :3]
    orth = np.abs(R @ np.swapaxes(R, -1, -2) - np.eye(3)).max(axis=(-1, -2)) <= 1e-6
    return ~(orth & (np.linalg.det(R) > 0) & np.all(np.abs(T[:, 3] - [0, 0, 0, 1]) <= 1e-9,
                                                    axis=-1) & np.isfinite(T).all(axis=(-1, -2)))


def _ik_chunk(robot, units, parsed, frame, fmt="jsonl"):
    import numpy as np

    from ..ik import Target
    from ..errors import KincalcError
    from ..ik.engine import UnsupportedRobot
    from ..ik.solve import solve
    full, T, partial, errors = _poses(robot, units, parsed)
    qdisp = np.where(robot.is_revolute, units.a, units.l)
    recs, no = [], False
    try:
        B = robot.ik_batch(T) if len(T) else None
    except UnsupportedRobot:
        B = None
        for (i, kw), t in zip(full, T):
            partial.append((i, kw, Target(t, orientation=True)))
    if B is not None:
        valid = B.valid
        q = B.q[valid]                                                     # (s, n)
        within = B.within[valid]
        owner, _ = np.nonzero(valid)
        labels = B.labels[valid].tolist()
        counts = valid.sum(axis=1)
        # each pose's solutions: written as JSON in bulk, or as dicts for the CSV rows
        if fmt == "jsonl":
            sols_of = _solutions_json(np.round(q * qdisp, 12) + 0.0, labels, within, owner,
                                      len(full))
        else:
            sols_of = [[] for _ in full]
            for o, ql, lab, w in zip(owner.tolist(), _round(q * qdisp), labels, within.tolist()):
                sols_of[o].append({"q": ql, "branch": lab, "within_limits": w})
        for ((i, kw), c, sols) in zip(full, counts.tolist(), sols_of):
            no |= not c
            recs.append({**_head(i, kw), "reachable": bool(c), "solutions": sols})
    for i, kw, target in partial:
        try:
            result = solve(robot, target)
        except KincalcError as exc:        # a question this robot cannot take: its record
            errors.append((i, {**_head(i, kw), "error": f"record {i + 1}: {exc}"}))
            continue
        sols = [{"q": _round(np.asarray(s.q) * qdisp), "branch": s.branch,
                 "within_limits": not s.violations} for s in result.solutions]
        no |= not sols
        recs.append({**_head(i, kw), "reachable": bool(sols), "solutions": sols})
    return _merge(recs, errors), no


def _reach_chunk(robot, units, parsed, frame):
    """Reach records of one chunk (the analysis runs pose by pose)."""
    from ..errors import KincalcError
    from ..reach import reach
    from ..results import _clean
    from .ik import build_target
    out, no = [], False
    for index, kw, error in parsed:
        head = _head(index, kw)
        if error is None:
            try:
                pose = {k: v for k, v in kw.items() if k != "id"}
                result = reach(robot, build_target(robot, units, **pose), units=units)
            except KincalcError as exc:
                error = f"record {index + 1}: {exc}"
        if error is not None:
            out.append({**head, "error": error})
            continue
        no |= not result.reachable
        out.append({**head, "reachable": result.reachable, "verdict": result.verdict,
                    "distance": None if result.distance is None else
                    _clean(result.distance * units.l),
                    "solutions": result.solutions,
                    "solutions_within_limits": result.within_limits,
                    "reason": result.reason})
    return out, no


def _csv_rows(kind, robot, records) -> str:
    import csv
    import io
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    n = robot.dof
    if kind == "reach":
        for r in records:
            w.writerow([_csv_cell(r.get(c)) for c in REACH_FIELDS])
        return buf.getvalue()
    for r in records:
        head = [r["index"], r.get("id", "")]
        if "error" in r:
            width = {"fk": 7, "jacobian": 6 * n + 3, "ik": n + 3}[kind]
            w.writerow(head + [""] * width + [r["error"]])
        elif kind == "fk":
            w.writerow(head + r["xyz"] + r["rpy"] + [_csv_cell(r["within_limits"]), ""])
        elif kind == "jacobian":
            w.writerow(head + [x for row in r["J"] for x in row] +
                       [r["rank"], r["manipulability"], _csv_cell(r["singular"]), ""])
        elif not r["solutions"]:
            w.writerow(head + ["", "no solution"] + [""] * n + ["", ""])
        else:
            for k, s in enumerate(r["solutions"]):
                w.writerow(head + [k, s["branch"]] + s["q"] + [_csv_cell(s["within_limits"]), ""])
    return buf.getvalue()
