"""Batch output formats: JSON lines (one strict encoder; the solutions of a chunk
written by one format) and CSV."""

from __future__ import annotations

from .records import csv_cell

#: the per-pose fields of a reach record, in CSV column order
REACH_FIELDS = ["index", "reachable", "verdict", "distance", "solutions",
                "solutions_within_limits", "reason", "error"]


def csv_header(kind, robot) -> str:
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


def ik_json(r) -> str:
    """One ik output record as JSON; the solutions' joint values are written with 12
    significant digits by one format per solution (json.dumps spends ~0.5 us on the
    shortest repr of each float, most of a batch run's time)."""
    import json
    strict = strict_json()
    if "solutions" not in r:
        return strict.encode(r)
    head = strict.encode({k: v for k, v in r.items() if k != "solutions"})[:-1]
    if isinstance(r["solutions"], SolutionsJSON):
        return f'{head}, "solutions": [{r["solutions"]}]}}'
    sols = ", ".join('{"q": [%s], "branch": %s, "within_limits": %s}'
                     % (", ".join(["%.12g"] * len(s["q"])) % tuple(s["q"]),
                        json.dumps(s["branch"]), "true" if s["within_limits"] else "false")
                     for s in r["solutions"])
    return f'{head}, "solutions": [{sols}]}}'


def strict_json():
    """The one JSON encoder of output records: NaN or Infinity in a record is an error
    (a bug: the chunk functions make non-finite results error records), never written.
    json.dumps(..., allow_nan=False) built an encoder a call: 2 us a record."""
    global _ENCODER
    if _ENCODER is None:
        import json
        _ENCODER = json.JSONEncoder(allow_nan=False)
    return _ENCODER


_ENCODER = None


class SolutionsJSON(str):
    """A pose's solutions already written as JSON (the items of the array), by
    :func:`solutions_json` for a whole chunk at once."""


def solutions_json(ql, labels, within, owner, count) -> list:
    """The JSON text of each pose's solutions, for ``count`` poses: ``ql (s, n)`` the
    display values (rounded), ``labels``/``within (s,)`` and ``owner (s,)`` the pose of
    each solution, ascending. One %-format runs over all solutions of the chunk (per
    solution formatting in Python was the largest cost of a batch run); the numbers are
    written with 12 significant digits, as :func:`ik_json` writes them."""
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
        out.append(SolutionsJSON(", ".join(items[start:end])))
        start = end
    return out


def rounded(a):
    """Arrays as nested lists rounded to 12 decimals, -0.0 as 0.0 (as results.json_numbers)."""
    import numpy as np
    return (np.round(a, 12) + 0.0).tolist()


def csv_rows(kind, robot, records) -> str:
    import csv
    import io
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    n = robot.dof
    if kind == "reach":
        for r in records:
            w.writerow([csv_cell(r.get(c)) for c in REACH_FIELDS])
        return buf.getvalue()
    for r in records:
        head = [r["index"], r.get("id", "")]
        if "error" in r:
            width = {"fk": 7, "jacobian": 6 * n + 3, "ik": n + 3}[kind]
            w.writerow(head + [""] * width + [r["error"]])
        elif kind == "fk":
            w.writerow(head + r["xyz"] + r["rpy"] + [csv_cell(r["within_limits"]), ""])
        elif kind == "jacobian":
            w.writerow(head + [x for row in r["J"] for x in row] +
                       [r["rank"], r["manipulability"], csv_cell(r["singular"]), ""])
        elif not r["solutions"]:
            w.writerow(head + ["", "no solution"] + [""] * n + ["", ""])
        else:
            for k, s in enumerate(r["solutions"]):
                w.writerow(head + [k, s["branch"]] + s["q"] + [csv_cell(s["within_limits"]), ""])
    return buf.getvalue()
