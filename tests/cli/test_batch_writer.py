"""The ik --batch writer, byte for byte against Python's own formatting.

The oracles are independent of the writer: ``"%.12g" % x`` for every joint value (the text
ik output lines have always carried) and ``json.dumps`` for the rest of a line (heads, ids,
branch words, flags, spacing). The values are seeded draws from the families where a
vectorised float formatter goes wrong: decimal ties and their neighbours, exact binary
ties, powers of ten and their neighbours, every exponent, random bit patterns (NaN,
infinities, subnormals), -0.0, integers.
"""

import json

import numpy as np
import pytest

from kincalc.cli.batch import formats, numtext
from kincalc.cli.main import main


def g12_texts(x):
    """The text of each value of ``x (N,)`` by g12_cells, zero bytes removed."""
    cells = numtext.g12_cells(np.asarray(x, float)).view(np.uint8).reshape(-1, numtext.CELL)
    return [row[row != 0].tobytes().decode("ascii") for row in cells]


def values(family: str, n: int = 20000, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    if family == "degrees, rounded to 12 decimals (the batch's values)":
        return np.round(rng.uniform(-400, 400, n), 12) + 0.0
    if family == "every exponent":
        return sign * 10.0 ** rng.uniform(-320, 308, n)
    if family == "exponents -6..14":
        return sign * 10.0 ** rng.uniform(-6, 14, n)
    if family == "random bit patterns":
        return rng.integers(0, 2**64, n, dtype=np.uint64).view(float)
    if family in ("13-digit decimal ties", "ties - 1 ulp", "ties + 1 ulp"):
        digits = rng.integers(10**11, 10**12, n) * 10 + 5
        ties = sign * np.array([float(f"{d}e{k}") for d, k in
                                zip(digits.tolist(), rng.integers(-17, 1, n).tolist())])
        step = {"13-digit decimal ties": None, "ties - 1 ulp": 0.0, "ties + 1 ulp": np.inf}
        return ties if step[family] is None else np.nextafter(ties, sign * step[family])
    if family == "binary fractions (exact ties)":
        return sign * rng.integers(10**10, 10**14, n) / 2.0 ** rng.integers(1, 40, n)
    if family == "near powers of ten":
        p = 10.0 ** np.arange(-8, 16)
        near = np.concatenate([p, np.nextafter(p, 0), np.nextafter(p, np.inf), p * (1 - 5e-13),
                               p * (1 + 5e-13), p * 0.9999999999995, p * 0.99999999999949999])
        return np.concatenate([near, -near])
    if family == "integers and small fractions":
        return np.concatenate([rng.integers(-10**13, 10**13, n // 2).astype(float),
                               np.arange(-(n // 4), n // 4) / 64.0])
    raise ValueError(family)


FAMILIES = ["degrees, rounded to 12 decimals (the batch's values)", "every exponent",
            "exponents -6..14", "random bit patterns", "13-digit decimal ties", "ties - 1 ulp",
            "ties + 1 ulp", "binary fractions (exact ties)", "near powers of ten",
            "integers and small fractions"]
SPECIAL = [0.0, -0.0, np.nan, np.inf, -np.inf, 5e-324, -5e-324, 2.2250738585072014e-308,
           1.7976931348623157e308, 0.5, 1.5, 2.5, 1e-4, 1e-5, 9.99999999999949e-5,
           9.9999999999995e-5, 999999999999.5, 999999999999.4, 123456789012.5, 1e11, 1e12,
           99999999999.95, 0.1, 0.2, 0.3, 180.0, -180.0, 1 / 3, 2 / 3, 1e22, 1e23]


@pytest.mark.parametrize("family", FAMILIES)
def test_g12_cells_write_what_percent_12g_writes(family):
    x = values(family)
    got = g12_texts(x)
    want = ["%.12g" % v for v in x.tolist()]
    wrong = [(v, g, w) for v, g, w in zip(x.tolist(), got, want) if g != w]
    assert not wrong, f"{len(wrong)} of {len(x)} differ, e.g. (value, got, %.12g): {wrong[:5]}"


def test_g12_cells_special_values():
    assert g12_texts(SPECIAL) == ["%.12g" % v for v in SPECIAL]
    assert g12_texts([-0.0, 0.0, 1e-5, 1e12, np.nan, -np.inf]) == \
        ["-0", "0", "1e-05", "1e+12", "nan", "-inf"]


@pytest.mark.parametrize("shape", [(0,), (7,), (0, 6), (5, 6), (2, 3, 4)])
def test_g12_cells_any_shape_into_a_view_leaving_the_rest(shape, monkeypatch):
    monkeypatch.setattr(numtext, "BLOCK", 5)           # several blocks, a short last one
    x = values("exponents -6..14", int(np.prod(shape)), seed=3).reshape(shape)
    c = numtext.CELL // 8
    grid = np.full(shape[:-1] + (shape[-1] * c + 2,), 0xABAB, "<u8") if len(shape) > 1 \
        else np.full((shape[0] * c + 2,), 0xABAB, "<u8")
    inner = grid[..., 1:-1].reshape(shape + (c,))
    out = numtext.g12_cells(x, out=inner)
    assert out is inner
    assert (grid[..., 0] == 0xABAB).all() and (grid[..., -1] == 0xABAB).all()
    cells = out.view(np.uint8).reshape(-1, numtext.CELL)
    assert not cells[:, -2:].any()                      # the last two bytes are free
    assert [r[r != 0].tobytes().decode() for r in cells] == \
        ["%.12g" % v for v in x.ravel().tolist()]


# --- whole lines ------------------------------------------------------------------------------

WORDS = ["shoulder left elbow up wrist no-flip", "shoulder right elbow down wrist flip (q4 free)",
         "é\u2603 \"quoted\" \\ back", "100% sure %s %d", "tab\tnew\nline\x00nul\x1f", "",
         "\U0001F600 ascii-escaped"]
IDS = ["é%s\u2603 \"q\"", "50%", 3.5, -0.0, 1e300, 12345678901234567890, -7, True, False, None,
       "\\n\t", "\U0001F600"]


def reference_line(head, sols) -> str:
    """An ik answer's line: json.dumps of the document, each q written by "%.12g"."""
    marks = [f"\x00q{k}\x00" for k in range(len(sols))]
    doc = {**head, "reachable": any(w for _, _, w, _ in sols),
           "solutions": [{"q": m, "branch": lab, "within_limits": w, "singular": g}
                         for m, (_, lab, w, g) in zip(marks, sols)]}
    text = json.dumps(doc)
    for m, (q, _, _, _) in zip(marks, sols):
        text = text.replace(json.dumps(m), "[" + ", ".join("%.12g" % v for v in q) + "]")
    return text


def random_answers(rng, count, n):
    heads, q, labels, within, singular, owner = [], [], [], [], [], []
    pool = np.concatenate([values(f, 400, seed=int(rng.integers(1000))) for f in FAMILIES]
                          + [np.array(SPECIAL)])
    for k in range(count):
        index = int(rng.integers(0, 10**9)) if k % 5 else k
        heads.append({"index": index} if rng.random() < 0.6 else
                     {"index": index, "id": IDS[int(rng.integers(len(IDS)))]})
        for _ in range(int(rng.integers(0, 10))):       # 0 to 9 solutions
            q.append(rng.choice(pool, n))
            labels.append(WORDS[int(rng.integers(len(WORDS)))])
            within.append(bool(rng.random() < 0.5))
            singular.append(bool(rng.random() < 0.3))
            owner.append(k)
    return (heads, np.array(q, float).reshape(-1, n), labels, np.array(within, bool),
            np.array(singular, bool), np.array(owner, np.intp))


@pytest.mark.parametrize("n", [1, 2, 5, 6, 7])
@pytest.mark.parametrize("rows", [1024, 3])
def test_ik_lines_are_json_dumps_with_12_digit_joint_values(n, rows, monkeypatch):
    monkeypatch.setattr(formats, "ROWS", rows)          # one block, or many and short ones
    rng = np.random.default_rng(n)
    for count in (0, 1, 2, 300):
        heads, q, labels, within, singular, owner = random_answers(rng, count, n)
        got = formats.ik_lines(heads, q, labels, within, singular, owner)
        want = [reference_line(h, [(q[j], labels[j], bool(within[j]), bool(singular[j]))
                                   for j in np.flatnonzero(owner == k)])
                for k, h in enumerate(heads)]
        assert len(got) == count
        for g, w in zip(got, want):
            assert g == w


def test_ik_lines_with_no_solution_at_all():
    heads = [{"index": 3}, {"index": 4, "id": "x"}]
    assert formats.ik_lines(heads, np.zeros((0, 6)), [], np.zeros(0, bool), np.zeros(0, bool),
                            np.zeros(0, np.intp)) == \
        ['{"index": 3, "reachable": false, "solutions": []}',
         '{"index": 4, "id": "x", "reachable": false, "solutions": []}']


# --- through the command ------------------------------------------------------------------------

def test_batch_lines_are_the_reference_lines_of_their_own_documents(tmp_path, capsys):
    """Mixed records (pose forms solved in one batch and pose by pose, held joints, ids, bad
    records) through the CLI: every line is the reference text of its own document, the
    lines are in the input's order, and each joint value is the CSV output's value written
    by "%.12g"."""
    rng = np.random.default_rng(7)
    rows = []
    for k in range(60):
        q = rng.uniform(-90, 90, 6).round(6).tolist()
        rec = [{"q": q}, {"xyz": [0.3, 0.1, 0.2], "rpy": q[:3]},
               {"xyz": [0.35, 0.05, 0.3], "approach": [0, 0, -1]},
               {"xyz": [0.3, 0.1, 0.2], "rpy": [0, 0, 0], "lock": {"q1": 10}},
               {"xyz": [5, 5, 5], "rpy": [0, 0, 0]}, {"xyz": [1, 2]}][k % 6]
        if k % 4 == 0:
            rec = {**rec, "id": IDS[k % len(IDS)]}
        rows.append(json.dumps(rec) + "\n")
    rows.insert(9, "not json\n")
    src = tmp_path / "mixed.jsonl"
    src.write_text("".join(rows))
    assert main(["ik", "puma560", "--batch", str(src)]) == 2
    out = capsys.readouterr().out.splitlines()
    assert main(["ik", "puma560", "--batch", str(src), "--format", "csv"]) == 2
    table = capsys.readouterr().out.splitlines()[1:]
    assert len(out) == len(rows)
    csv_q = {}
    for row in table:
        cells = row.split(",")
        if cells[2].isdigit():
            csv_q.setdefault(int(cells[0]), []).append(cells[4:10])
    for i, line in enumerate(out):
        doc = json.loads(line)
        assert doc["index"] == i
        if "error" in doc:
            assert line == json.dumps(doc)
            continue
        sols = [(s["q"], s["branch"], s["within_limits"], s["singular"])
                for s in doc["solutions"]]
        assert line == reference_line({k: doc[k] for k in doc if k in ("index", "id")}, sols)
        assert [["%.12g" % float(v) for v in q] for q in csv_q.get(i, [])] == \
            [line_q.split(", ") for line_q in
             (part.split("]")[0] for part in line.split('"q": [')[1:])]


NARROW = """name: narrow
convention: dh
units: {length: m, angle: rad}
joints:
  - {name: q1, type: revolute, alpha: "pi/2", a: 0.0, d: 0.4, theta: 0.0, limits: [-0.3, 0.3]}
  - {name: q2, type: revolute, alpha: 0.0, a: 0.45, d: 0.0, theta: 0.0, limits: [-0.3, 0.3]}
  - {name: q3, type: revolute, alpha: "pi/2", a: 0.05, d: 0.0, theta: 0.0, limits: [-0.3, 0.3]}
  - {name: q4, type: revolute, alpha: "-pi/2", a: 0.0, d: 0.4, theta: 0.0, limits: [-0.3, 0.3]}
  - {name: q5, type: revolute, alpha: "pi/2", a: 0.0, d: 0.0, theta: 0.0, limits: [-0.3, 0.3]}
  - {name: q6, type: revolute, alpha: 0.0, a: 0.0, d: 0.1, theta: 0.0, limits: [-0.3, 0.3]}
"""


@pytest.mark.parametrize("fmt", ["jsonl", "csv"])
def test_batch_reachable_and_status_are_ik_s_when_every_solution_breaks_a_limit(
        tmp_path, capsys, fmt):
    """A pose whose solutions all lie beyond the joint limits is not reachable, in a batch
    as for ik (a solution within the limits must reach it; exit status 1); one with a
    solution within them is."""
    robot = tmp_path / "narrow.yaml"
    robot.write_text(NARROW)
    poses = [[0.1, -0.2, 0.15, 0.05, -0.1, 0.2], [0.6, 0.7, -0.8, 0.9, 1.0, -1.1]]
    single = []
    for q in poses:
        status = main(["ik", str(robot), "--from-q", " ".join(map(str, q)), "--rad", "--json"])
        doc = json.loads(capsys.readouterr().out)
        single.append(doc["reachable"])
        assert status == (0 if doc["reachable"] else 1)
        assert doc["solutions"] and \
            doc["reachable"] == any(s["within_limits"] for s in doc["solutions"])
    assert single == [True, False]
    src = tmp_path / "poses.jsonl"
    src.write_text("".join(json.dumps({"q": q}) + "\n" for q in poses))
    jobs = ["-j", "1"]
    assert main(["ik", str(robot), "--batch", str(src), "--rad"] + jobs) == 1
    out = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [d["reachable"] for d in out] == single
    assert all(d["solutions"] for d in out)
    src.write_text(json.dumps({"q": poses[0]}) + "\n")
    assert main(["ik", str(robot), "--batch", str(src), "--rad", "--format", fmt]) == 0
