"""--batch on fk, jacobian and ik: records in, one record out per input, in order.

Expected values come from independent places: a plain-numpy standard-DH FK written
here from the PUMA's table, finite differences of it for the Jacobian, and the
single-pose commands' JSON for the IK labels and limit flags.
"""

import csv
import errno
import io
import json
import os
import select
import subprocess
import sys

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.cli.batch import records, runner
from kincalc.cli.main import main
from kincalc.ik.selftest import sample_configurations

# PUMA 560, standard DH (robots/puma560.yaml, Corke): alpha, a, d per joint
PUMA = [(np.pi / 2, 0, 0), (0, 0.4318, 0), (-np.pi / 2, 0.0203, 0.15005),
        (np.pi / 2, 0, 0.4318), (-np.pi / 2, 0, 0), (0, 0, 0)]


def dh_fk(q):
    T = np.eye(4)
    for (alpha, a, d), th in zip(PUMA, q):
        ct, st, ca, sa = np.cos(th), np.sin(th), np.cos(alpha), np.sin(alpha)
        T = T @ np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                          [0, sa, ca, d], [0, 0, 0, 1]])
    return T


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def lines(out):
    return [json.loads(line) for line in out.splitlines()]


def write(tmp_path, name, rows):
    p = tmp_path / name
    p.write_text("".join(r if isinstance(r, str) else json.dumps(r) + "\n" for r in rows))
    return str(p)


def test_the_hand_written_fk_is_the_bundled_puma():
    r = load_robot("puma560")
    q = sample_configurations(r, 20, np.random.default_rng(0))
    assert np.allclose([dh_fk(x) for x in q], r.fk(q), atol=1e-12)


def test_fk_batch_jsonl_matches_hand_fk(tmp_path, capsys):
    q = np.random.default_rng(1).uniform(-170, 170, (300, 6))
    src = write(tmp_path, "q.jsonl", [{"q": list(x)} for x in q])
    code, out, err = run(capsys, "fk", "puma560", "--batch", src)
    assert code == 0, err
    recs = lines(out)
    assert [r["index"] for r in recs] == list(range(300))
    for r, x in zip(recs, q):
        assert np.allclose(r["T"], dh_fk(np.radians(x)), atol=1e-11)
        assert np.allclose(r["xyz"], dh_fk(np.radians(x))[:3, 3], atol=1e-11)


def test_fk_batch_within_limits_judges_the_values_as_given(tmp_path, capsys):
    """A script checking commanded joints was told q1 = 300 deg is within +-160 deg (a whole
    turn from -60), and so was q1 = 1e9 deg: the flag is of the values the record gives."""
    r = load_robot("puma560")
    lo, hi = np.degrees(r.limits.T)
    rng = np.random.default_rng(3)
    q = rng.uniform(-400, 400, (200, 6))
    q[:4] = 0.0
    q[:4, 0] = [300.0, -60.0, hi[0], 1e9]
    src = write(tmp_path, "q.jsonl", [{"q": list(x)} for x in q])
    code, out, err = run(capsys, "fk", "puma560", "--batch", src)
    assert code == 0, err
    got = [rec["within_limits"] for rec in lines(out)]
    assert got[:4] == [False, True, True, False]
    assert got == [bool(((x >= lo) & (x <= hi)).all()) for x in q]


@pytest.mark.parametrize("kind, pose", [("fk", '"q": [0, 0]'), ("ik", '"xyz": [0.1, 0.1, 0]'),
                                        ("jacobian", '"q": [0, 0]'),
                                        ("reach", '"xyz": [10, 5, 0]')])
def test_csv_ids_are_json_words_and_no_formula(tmp_path, capsys, kind, pose):
    """An id true was written True (Python's word) and an id =HYPERLINK(...) as a formula a
    spreadsheet runs: now true, and the text with an apostrophe, as the gradebook's cells;
    reach's CSV had no id column at all."""
    ids = ["true", '"=HYPERLINK(\\"http://x\\")"', "-3", '"+1"', "null", '"plain"',
           '"\\r=x"', '"\\t@y"', '"  -z"', '"a\\nb"']
    src = write(tmp_path, "r.jsonl", ["{%s, \"id\": %s}\n" % (pose, i) for i in ids])
    code, out, err = run(capsys, kind, "bk_rr", "--batch", src, "--format", "csv")
    rows = list(csv.reader(io.StringIO(out)))[1:]
    first = {}
    for r in rows:
        first.setdefault(r[0], r[1])
    # a CR or tab before '=' became a space, and then no apostrophe followed (README said one
    # would): a spreadsheet that strips the space runs the formula
    assert list(first.values()) == ["true", "'=HYPERLINK(\"http://x\")", "-3", "'+1", "", "plain",
                                    "' =x", "' @y", "'  -z", "a b"]


@pytest.mark.parametrize("kind, pose", [("ik", '"xyz": [0.5, 0.1, 0]'), ("jacobian", '"q": [10, 10]')])
def test_csv_header_quotes_a_joint_name_with_a_comma(tmp_path, capsys, kind, pose):
    """A joint named 'a,b' (YAML and URDF allow it) split the header into one column more
    than the rows had, so every value stood under the wrong column; one named '=c' would
    reach a spreadsheet as a formula (an independent tester). The header is a CSV row
    like the others: as many cells as every row, the names as written (safe cells)."""
    robot = tmp_path / "comma.yaml"
    robot.write_text("name: r\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                     "  - {name: 'a,b', type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n"
                     "  - {name: '=c', type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n")
    src = write(tmp_path, "r.jsonl", ["{%s}\n" % pose])
    code, out, err = run(capsys, kind, str(robot), "--batch", src, "--format", "csv")
    assert code == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    assert len(rows) >= 2 and all(len(r) == len(rows[0]) for r in rows)
    header = rows[0]
    if kind == "ik":
        assert header[4:6] == ["a,b", "'=c"]
    else:
        assert header[2:4] == ["Jvx_a,b", "Jvx_=c"]


@pytest.mark.parametrize("kind", ["fk", "jacobian", "ik", "reach"])
def test_a_csv_id_column_is_echoed_as_a_json_records_id(tmp_path, capsys, kind):
    """A CSV input with an id column was refused ('unknown column id') though a JSON record's
    id is echoed back: a script writing CSV could not tell its records apart. The cell is the
    id's text as written (quoted, with a comma; empty), in any column; the answers are the
    JSON input's. A header of an id alone has no pose."""
    head, pose = (("theta1,theta2", "30,-60") if kind in ("fk", "jacobian") else
                  ("x,y,z", "12.99,2.5,0"))
    ids = ["A7", '"b, c"', "", "=1+1"]
    src = write(tmp_path, "r.csv", [f"{head},id\n"] + [f"{pose},{i}\n" for i in ids])
    code, out, err = run(capsys, kind, "bk_rr", "--batch", src)
    docs = lines(out)
    assert code == 0 and [d.get("id") for d in docs] == ["A7", "b, c", "", "=1+1"], (err, docs)
    key = "q" if kind in ("fk", "jacobian") else "xyz"
    values = [float(v) for v in pose.split(",")]
    code, out, err = run(capsys, kind, "bk_rr", "--batch",
                         write(tmp_path, "r.jsonl", [{key: values, "id": i} for i in ids]))
    assert [{k: v for k, v in d.items() if k != "id"} for d in docs] == \
        [{k: v for k, v in d.items() if k != "id"} for d in lines(out)]
    # the id column first, in CSV output too (a formula-like id gets its apostrophe)
    src = write(tmp_path, "s.csv", [f"id,{head}\n", f"=1+1,{pose}\n"])
    code, out, err = run(capsys, kind, "bk_rr", "--batch", src, "--format", "csv")
    rows = list(csv.reader(io.StringIO(out)))
    assert code == 0 and rows[0][:2] == ["index", "id"] and rows[1][:2] == ["0", "'=1+1"]
    code, out, err = run(capsys, kind, "bk_rr", "--batch", write(tmp_path, "t.csv",
                                                                  ["id\n", "A\n"]))
    assert code == 2 and "no " in lines(out)[0]["error"] and "columns (give" in \
        lines(out)[0]["error"]


def test_csv_branch_cells_from_joint_names_are_no_formula(tmp_path, capsys):
    """A branch label names joints ('=1+2:root 1'): from an untrusted robot file's joint
    names, the CSV header's cells were neutralised but the branch cells were not (a cell
    starting with '=': an independent tester). They get the apostrophe too."""
    robot = tmp_path / "f.yaml"
    names = ["=1+2", "@x", "+y", "q4", "q5", "q6"]
    robot.write_text("name: f\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n" +
                     "".join(f"  - {{name: '{n}', type: revolute, alpha: {90 * (k % 2)}, "
                             f"a: 0.3, d: 0.1, theta: 0}}\n" for k, n in enumerate(names)))
    src = write(tmp_path, "q.jsonl", [{"q": [10, 20, 30, 40, 50, 60]}])
    code, out, err = run(capsys, "fk", str(robot), "--batch", src)
    poses = write(tmp_path, "p.jsonl", [out])
    code, out, err = run(capsys, "ik", str(robot), "--batch", poses, "--format", "csv")
    rows = list(csv.reader(io.StringIO(out)))
    labels = [r[3] for r in rows[1:]]
    assert code in (0, 1) and any(n in x for x in labels for n in names[:3]), out
    assert not any(x[:1] and x[:1] in "=+-@" for r in rows for x in r[3:4]), labels


def test_fk_batch_csv_in_and_out_with_units(tmp_path, capsys):
    q = np.random.default_rng(2).uniform(-3, 3, (40, 6))
    rows = ["q1,q2,q3,q4,q5,q6\n"] + [",".join(repr(float(v)) for v in x) + "\n" for x in q]
    src = write(tmp_path, "q.csv", rows)
    code, out, err = run(capsys, "fk", "puma560", "--batch", src, "--rad", "--unit", "mm",
                         "--format", "csv")
    assert code == 0, err
    body = out.splitlines()
    assert body[0].startswith("index,id,x,y,z,roll,pitch,yaw")
    for line, x in zip(body[1:], q):
        cells = line.split(",")
        assert np.allclose([float(c) for c in cells[2:5]], dh_fk(x)[:3, 3] * 1000, atol=1e-8)


def test_jacobian_batch_matches_finite_differences(tmp_path, capsys):
    q = np.random.default_rng(3).uniform(-2, 2, (25, 6))
    src = write(tmp_path, "q.jsonl", [{"q": list(x)} for x in q])
    code, out, err = run(capsys, "jacobian", "puma560", "--batch", src, "--rad")
    assert code == 0, err
    h = 1e-6
    for r, x in zip(lines(out), q):
        J = np.array(r["J"])
        T0 = dh_fk(x)
        for i in range(6):
            dx = np.zeros(6)
            dx[i] = h
            Tp, Tm = dh_fk(x + dx), dh_fk(x - dx)
            v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
            dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T0[:3, :3].T
            w = [dR[2, 1], dR[0, 2], dR[1, 0]]
            assert np.allclose(J[:3, i], v, atol=1e-7) and np.allclose(J[3:, i], w, atol=1e-7)


def test_jacobian_batch_flags_the_same_singularities_as_the_single_command(tmp_path, capsys):
    qs = [[0, -45, 180, 0, 45, 0], [0, 30, -30, 20, 0, 10], [10, 20, 30, 40, 50, 60]]
    qs += np.round(np.random.default_rng(11).uniform(-170, 170, (5, 6)), 3).tolist()
    src = write(tmp_path, "q.jsonl", [{"q": q} for q in qs])
    code, out, err = run(capsys, "jacobian", "puma560", "--batch", src)
    for r, q in zip(lines(out), qs):
        c, single, _ = run(capsys, "jacobian", "puma560", *map(str, q), "--json")
        doc = json.loads(single)
        assert r["rank"] == doc["rank"] and r["singular"] == doc["singular"]
        # the same numbers, to the bit: both from the unrounded matrix (the single command
        # once took them from the J it prints, rounded to 12 decimals: 0.08872415615427336
        # against the batch's 0.08872415615438091)
        assert r["manipulability"] == doc["manipulability"]
        assert r["J"] == doc["J"]


def test_ik_batch_solutions_reach_the_pose_and_match_the_single_command(tmp_path, capsys):
    r = load_robot("puma560")
    Q = sample_configurations(r, 60, np.random.default_rng(4))
    T = r.fk(Q)
    src = write(tmp_path, "t.jsonl", [{"q": list(np.degrees(q))} for q in Q])
    code, out, err = run(capsys, "ik", "puma560", "--batch", src)
    assert code == 0, err
    recs = lines(out)
    for rec, t, q in zip(recs, T, Q):
        sols = np.radians([s["q"] for s in rec["solutions"]])
        assert len(sols) == 8
        assert all(np.allclose(dh_fk(s), t, atol=1e-9) for s in sols)
        d = np.abs((sols - q + np.pi) % (2 * np.pi) - np.pi).max(-1)
        assert d.min() < 1e-6
    # the same solutions in the same order: within the limits first, each group by label
    # (the batch listed them in its slots' order: 114 of 300 records began with a
    # solution beyond the limits, which the single command lists after those within)
    some_beyond = 0
    for rec, q in list(zip(recs, Q))[:24]:
        c, single, _ = run(capsys, "ik", "puma560", "--from-q",
                           " ".join(repr(float(v)) for v in np.degrees(q)), "--json")
        doc = json.loads(single)
        mine = [(s["branch"], s["within_limits"], s["singular"]) for s in rec["solutions"]]
        theirs = [(s["branch"], s["within_limits"], s["singular"]) for s in doc["solutions"]]
        assert mine == theirs
        within = [s["within_limits"] for s in rec["solutions"]]
        assert within == sorted(within, reverse=True)
        some_beyond += not within[-1]
        for s in rec["solutions"]:              # same joint values, branch by branch
            other = next(o for o in doc["solutions"] if o["branch"] == s["branch"])
            assert np.allclose(s["q"], other["q"], atol=1e-7)
    assert some_beyond >= 5          # (poses with solutions beyond the limits, to order)


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_ik_batch_flags_the_singular_solutions_the_single_command_flags(name, tmp_path, capsys):
    """Wrist-singular (q5 = 0, 180 deg), stretched-elbow and random poses: each record's
    solutions carry the branch, limit flag and singular flag of the single command's."""
    r = load_robot(name)
    rng = np.random.default_rng(31)
    Q = np.degrees(sample_configurations(r, 12, rng))
    Q[:4, 4] = [0, 180, 0, -180]
    Q[4:7, 2] = 0.0 if name == "ur5" else 90.0    # UR5: the elbow stretched
    src = write(tmp_path, "q.jsonl", [{"q": [float(v) for v in q]} for q in Q])
    code, out, err = run(capsys, "ik", name, "--batch", src)
    assert code in (0, 1), err
    flagged = 0
    for rec, q in zip(lines(out), Q):
        c, single, _ = run(capsys, "ik", name, "--from-q",
                           " ".join(repr(float(v)) for v in q), "--json")
        doc = json.loads(single)
        mine = sorted((s["branch"], s["within_limits"], s["singular"]) for s in rec["solutions"])
        theirs = sorted((s["branch"], s["within_limits"], s["singular"])
                        for s in doc["solutions"])
        assert mine == theirs, q
        flagged += sum(s["singular"] for s in rec["solutions"])
    assert flagged >= 4                     # the singular poses' solutions are flagged


def test_ik_batch_pose_forms_csv_and_general_robots(tmp_path, capsys):
    r = load_robot("ur5")
    q = np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2])
    T = r.fk(q)
    from kincalc.spatial import quaternion_from_matrix, rpy_from_matrix
    rpy = np.degrees(rpy_from_matrix(T[:3, :3]))
    quat = quaternion_from_matrix(T[:3, :3])
    rows = ["x,y,z,roll,pitch,yaw\n", ",".join(repr(float(v)) for v in [*T[:3, 3], *rpy]) + "\n"]
    code, out, err = run(capsys, "ik", "ur5", "--batch", write(tmp_path, "p.csv", rows),
                         "--format", "csv")
    assert code == 0, err
    body = out.splitlines()
    assert body[0].split(",")[:4] == ["index", "id", "solution", "branch"]
    assert len(body) == 1 + 8
    src = write(tmp_path, "p.jsonl", [{"xyz": list(T[:3, 3]), "quat": list(quat), "id": "a"},
                                      {"q": list(np.degrees(q))},
                                      {"xyz": list(T[:3, 3]), "matrix": list(T[:3, :3].ravel())}])
    code, out, err = run(capsys, "ik", "ur5", "--batch", src)
    recs = lines(out)
    assert code == 0 and recs[0]["id"] == "a"
    assert len({len(x["solutions"]) for x in recs}) == 1
    # a robot without a batched closed form goes pose by pose, same output
    src = write(tmp_path, "g.jsonl", [{"q": [10, 20, 30, 40, 50, 60]}])
    code, out, err = run(capsys, "ik", "manocha_canny_6r", "--batch", src)
    rec = lines(out)[0]
    g = load_robot("manocha_canny_6r")
    Tg = g.fk(np.radians([10, 20, 30, 40, 50, 60]))
    assert rec["reachable"] and all(np.allclose(g.fk(np.radians(s["q"])), Tg, atol=1e-8)
                                    for s in rec["solutions"])


def test_bad_records_become_error_records_and_exit_2(tmp_path, capsys):
    rows = ['{"q": [0, 0, 0, 0, 0, 0]}\n', "not json\n", '{"q": [1, 2]}\n', '{"qq": [1]}\n',
            '{"q": [0, 0, 0, 0, 0, 0]}\n']
    code, out, err = run(capsys, "fk", "puma560", "--batch", write(tmp_path, "b.jsonl", rows))
    recs = lines(out)
    assert code == 2 and len(recs) == 5
    assert "T" in recs[0] and "T" in recs[4]
    assert recs[1]["error"].startswith("record 2: not JSON")
    assert "6 joints" in recs[2]["error"] and "unknown field 'qq'" in recs[3]["error"]
    rows = ['{"xyz": [0.3, 0.1, 0.2], "quat": [0, 0, 0, 0]}\n',
            '{"T": [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}\n',
            '{"xyz": [0.3, 0.1, 0.2], "rpy": [0, 90]}\n']
    code, out, err = run(capsys, "ik", "puma560", "--batch", write(tmp_path, "p.jsonl", rows))
    recs = lines(out)
    assert code == 2 and [r["index"] for r in recs] == [0, 1, 2]
    assert all("error" in r for r in recs)
    assert "zero quaternion" in recs[0]["error"] and "record 3: rpy" in recs[2]["error"]


@pytest.mark.parametrize("header, fault", [
    ("q1,q2,q3,q4,q5,q6,null\n", "unknown column 'null'"),
    ("x,x\n", "column 'x' appears twice"),
])
def test_a_bad_csv_header_without_records_is_said_once(header, fault, tmp_path, capsys):
    """A CSV header that cannot be used makes every record an error record; with no record
    after it, it was silence and exit status 0 (the same header with one record: exit 2)."""
    path = write(tmp_path, "h.csv", [header])
    for fmt in ("jsonl", "csv"):                    # nothing on stdout, not even a CSV header
        code, out, err = run(capsys, "fk", "puma560", "--batch", path, "--format", fmt)
        assert code == 2 and out == ""
        assert err.count("\n") == 1 and f"{path}: line 1: {fault}" in err
    code, out, err = run(capsys, "fk", "puma560", "--batch", write(tmp_path, "ok.csv",
                                                                  ["q1,q2,q3,q4,q5,q6\n"]))
    assert (code, out, err) == (0, "", "")


@pytest.mark.parametrize("command", ["ik", "reach"])
def test_a_pose_record_with_no_joint_values_is_an_error_not_home(command, tmp_path, capsys):
    """``{"q": []}`` is a record with too few joint values, as in fk: it was answered for the
    home configuration, as if the record had asked for it."""
    path = write(tmp_path, "q.jsonl", ['{"q": []}\n', '{"q": [0, 90, -90, 0, 0, 0]}\n'])
    code, out, err = run(capsys, command, "puma560", "--batch", path)
    recs = lines(out)
    assert code == 2 and [r["index"] for r in recs] == [0, 1]
    assert recs[0]["error"].startswith("record 1: q: puma560 has 6 joints")
    assert "got 0 joint values" in recs[0]["error"] and "error" not in recs[1]


def test_unreachable_poses_exit_1(tmp_path, capsys):
    rows = [{"xyz": [5, 0, 0], "rpy": [0, 0, 0]}, {"q": [0, -45, 180, 0, 45, 0]}]
    code, out, err = run(capsys, "ik", "puma560", "--batch", write(tmp_path, "u.jsonl", rows))
    recs = lines(out)
    assert code == 1 and recs[0]["reachable"] is False and recs[0]["solutions"] == []
    assert recs[1]["reachable"]


def test_batch_refuses_other_inputs(tmp_path, capsys):
    src = write(tmp_path, "q.jsonl", [{"q": [0] * 6}])
    code, out, err = run(capsys, "fk", "puma560", "1", "2", "3", "4", "5", "6", "--batch", src)
    assert code == 2 and "--batch" in err
    code, out, err = run(capsys, "ik", "puma560", "--xyz", "1", "0", "0", "--batch", src)
    assert code == 2 and "--batch" in err
    code, out, err = run(capsys, "fk", "puma560", "--batch", str(tmp_path / "missing.jsonl"))
    assert code == 2 and "cannot read" in err
    code, out, err = run(capsys, "fk", "puma560", "--batch", src, "--format", "xml")
    assert code == 2 and "--format" in err


def test_jobs_keep_the_order_and_the_answers(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(runner, "CHUNK_LINES", 64)
    r = load_robot("ur5")
    T = r.fk(sample_configurations(r, 500, np.random.default_rng(6)))
    rows = [{"T": t.tolist()} for t in T]
    rows[77] = {"T": "nope"}
    src = write(tmp_path, "t.jsonl", rows)
    c1, one, _ = run(capsys, "ik", "ur5", "--batch", src)
    c2, two, _ = run(capsys, "ik", "ur5", "--batch", src, "--jobs", "2")
    assert c1 == c2 == 2
    assert one == two
    assert [json.loads(x)["index"] for x in two.splitlines()] == list(range(500))


def test_first_answers_come_before_the_input_ends():
    """A producer writing one pose at a time gets each answer at once (stdin pipe)."""
    code = "import sys; from kincalc.cli.main import main; sys.exit(main())"
    p = subprocess.Popen([sys.executable, "-c", code, "fk", "puma560", "--batch", "-"],
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        p.stdin.write('{"q": [0, 0, 0, 0, 0, 0]}\n')
        p.stdin.flush()
        ready, _, _ = select.select([p.stdout], [], [], 60)
        assert ready, "no answer while the input is still open"
        assert json.loads(p.stdout.readline())["index"] == 0
        p.stdin.write('{"q": [0, 10, 0, 0, 0, 0]}\n')
        p.stdin.close()
        assert json.loads(p.stdout.readline())["index"] == 1
    finally:
        p.kill()
        p.wait()


@pytest.mark.parametrize("kind", ["fk", "jacobian"])
def test_memory_stays_flat_on_a_large_input(tmp_path, kind):
    """200,000 records through a subprocess: peak memory close to that of 2,000."""
    def peak(n):
        src = tmp_path / f"{n}.jsonl"
        src.write_text('{"q": [10, 20, 30, 40, 50, 60]}\n' * n)
        code = ("import resource, sys\nfrom kincalc.cli.main import main\n"
                "main(['%s', 'puma560', '--batch', %r])\n"
                "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)"
                % (kind, str(src)))
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             env={**os.environ, "COLUMNS": "100"})
        assert out.stdout.count("\n") == n
        return int(out.stderr.strip().splitlines()[-1])
    small, large = peak(2000), peak(200_000)
    assert large < small + 40_000, (small, large)   # kB: no growth with the input's size


def test_ik_batch_a_question_the_robot_cannot_take_is_an_error_record(tmp_path, capsys):
    """An approach-only pose for a 6-DOF arm, after a full chunk of good poses, is that
    record's error: the run goes on (it used to end the whole run with a one-line error
    after printing the first chunk)."""
    r = load_robot("puma560")
    T = r.fk(sample_configurations(r, 2100, np.random.default_rng(4)))
    rows = [{"T": t.tolist()} for t in T]
    rows.insert(2050, {"xyz": [0.4, 0.1, 0.2], "approach": [0, 0, -1]})
    code, out, err = run(capsys, "ik", "puma560", "--batch", write(tmp_path, "a.jsonl", rows))
    recs = lines(out)
    assert code == 2 and err == "" and len(recs) == 2101
    assert "approach" in recs[2050]["error"] and recs[2050]["error"].startswith("record 2051:")
    assert all(rec["reachable"] for k, rec in enumerate(recs) if k != 2050)


def test_ik_batch_jsonl_solutions_are_the_csv_solutions(tmp_path, capsys):
    """The JSON lines of a chunk are written in bulk (one format over all solutions),
    the CSV row by row: both must carry the same numbers, labels and limit flags."""
    r = load_robot("ur5")
    T = r.fk(sample_configurations(r, 300, np.random.default_rng(8)))
    src = write(tmp_path, "u.jsonl", [{"T": t.tolist(), "id": f"p{k}"} for k, t in enumerate(T)])
    _, out, _ = run(capsys, "ik", "ur5", "--batch", src)
    _, csv_out, _ = run(capsys, "ik", "ur5", "--batch", src, "--format", "csv")
    rows = list(csv.reader(io.StringIO(csv_out)))[1:]
    flat = [(rec["index"], rec["id"], k, s["branch"], s["q"], s["within_limits"])
            for rec in lines(out) for k, s in enumerate(rec["solutions"])]
    assert len(flat) == len(rows) > 300
    for (i, ident, k, branch, q, within), row in zip(flat, rows):
        assert row[:4] == [str(i), ident, str(k), branch]
        assert np.allclose([float(x) for x in row[4:10]], q, rtol=1e-11, atol=1e-9)
        assert row[10] == ("true" if within else "false")


@pytest.mark.parametrize("argv, option", [
    (["fk", "puma560", "--frames"], "--frames"),
    (["fk", "puma560", "--symbolic"], "--symbolic"),
    (["fk", "puma560", "--latex"], "--latex"),
    (["jacobian", "puma560", "--symbolic"], "--symbolic"),
    (["jacobian", "puma560", "--numeric-lengths"], "--numeric-lengths"),
    (["ik", "puma560", "--plot", "out.png"], "--plot"),
])
def test_batch_refuses_options_it_would_ignore(tmp_path, capsys, argv, option):
    src = write(tmp_path, "q.jsonl", [{"q": [0, 0, 0, 0, 0, 0]}])
    code, out, err = run(capsys, *argv, "--batch", src)
    assert code == 2 and out == ""
    assert err == f"kincalc: error: {option} does not combine with --batch\n"


def test_reach_batch_jobs_gives_the_same_output_in_order(tmp_path, capsys):
    """reach --batch goes through the chunked runner: with -j 2 the records come out
    byte-identical and in input order (more records than one reach chunk)."""
    rng = np.random.default_rng(3)
    rows = [{"xyz": list(rng.uniform(-1.2, 1.2, 3)), "id": k} for k in range(150)]
    rows.insert(70, "not json\n")
    src = write(tmp_path, "targets.jsonl", rows)
    code1, out1, _ = run(capsys, "reach", "bk_rr", "--batch", src)
    code2, out2, _ = run(capsys, "reach", "bk_rr", "--batch", src, "-j", "2")
    assert code1 == code2 == 2 and out1 == out2
    recs = lines(out1)
    assert [r["index"] for r in recs] == list(range(151))
    assert "error" in recs[70] and all("verdict" in r for k, r in enumerate(recs) if k != 70)


# --- issue 14: reading never loses a record, pipes, signals ------------------------------
#
# Each bug has a test where it lived (the reader _blocks/_chunked, the record parser
# _parse, the runner) and one through the command line.

from kincalc.limits import MAX_BATCH_SKIP_BYTES, MAX_RECORD_BYTES  # noqa: E402
from cli_contract import json_documents, run_cli  # noqa: E402

KINCALC = [sys.executable, "-c", "import sys; from kincalc.cli.main import main; "
           "sys.exit(main())"]


class _Bytes:
    """A batch source over ``pieces`` (each read returns the next one), as _Source is."""

    def __init__(self, *pieces, src="-", ready=True):
        self.pieces, self.src, self.position, self.stopped = list(pieces), src, 0, None
        self.reads, self._ready = 0, ready

    def read(self):
        self.reads += 1
        return self.pieces.pop(0) if self.pieces else b""

    def ready(self):
        return self._ready

    def close(self):
        pass


class _Zeros(_Bytes):
    """/dev/zero: reads that never end, with no newline."""

    def read(self):
        self.reads += 1
        return bytes(runner.READ_BYTES)


def _records(source, size=2048, input_format="auto"):
    header, chunks, _ = runner._chunked(source, size, input_format)
    return header, [line for (start, lines), _ in chunks for line in lines]


@pytest.mark.parametrize("first", [b"42", b"[]", b'"text"', b"null", b"true", b"NaN",
                                   b"{broken", b"not json", b"\xff\xfe", b"1,2,3"])
def test_a_bad_first_record_does_not_make_json_lines_csv(first):
    """The first line decided the format: a JSON lines input whose first record was not
    an object was read as CSV with it as the header (3 records in, 2 out)."""
    rest = [b'{"q": [0, 0, 0, 0, 0, 0]}', b'{"q": [1, 2, 3, 4, 5, 6]}']
    header, lines = _records(_Bytes(b"\n".join([first] + rest) + b"\n"))
    assert header is None and lines == [first] + rest


@pytest.mark.parametrize("data, src, input_format, header", [
    (b"q1,q2,q3,q4,q5,q6\n1,2,3,4,5,6\n", "-", "auto", ("q1", "q2", "q3", "q4", "q5", "q6")),
    (b"\xef\xbb\xbf x, y ,z\r\n1,2,3\n", "-", "auto", ("x", "y", "z")),
    (b"\n  \nx,y,z\n1,2,3\n", "-", "auto", ("x", "y", "z")),
    (b"x,y,z\n1,2,3\n", "-", "jsonl", None),
    (b"x,y,z\n1,2,3\n", "in.jsonl", "auto", None),
    (b"x,y,z\n1,2,3\n", "in.NDJSON", "auto", None),
    (b'{"q": []}\n1,2,3\n', "in.csv", "auto", ('{"q": []}',)),
    (b'null\n1,2,3\n', "-", "csv", ("null",)),
])
def test_the_input_format_rule(data, src, input_format, header):
    """--input-format, then the name's ending, then a first line of column names."""
    got, lines = _records(_Bytes(data, src=src), input_format=input_format)
    assert got == header
    assert len(lines) == data.count(b"\n") - (header is not None) - data.count(b"\n\n") - \
        data.startswith(b"\n") - (b"  \n" in data)


def test_an_unreadable_csv_header_is_every_records_error():
    header, lines = _records(_Bytes(b"x,\xff,z\n1,2,3\n4,5,6\n"), input_format="csv")
    assert "not UTF-8" in header and len(lines) == 2
    parsed = records.parse_records(header, load_robot("puma560"), 0, lines)
    assert [e for _, _, e in parsed] == [f"record {i}: {header}" for i in (1, 2)]


def test_blank_lines_crlf_and_the_byte_order_mark():
    """A record is every line that is not blank; a CR before the newline and a byte order
    mark at the start of the input are not part of a line (the mark may come byte by byte
    from a pipe)."""
    header, lines = _records(_Bytes(b"\xef", b"\xbb", b"\xbf{\"q\": [1]}\r\n", b"\r\n \t\n",
                                    b'{"q": [2]}\n\xef\xbb\xbf{"q": [3]}'))
    assert header is None
    assert lines == [b'{"q": [1]}\r', b'{"q": [2]}', b'\xef\xbb\xbf{"q": [3]}']
    parsed = records.parse_records(None, load_robot("bk_rr"), 0, lines)
    assert parsed[0][1] == {"q": (1.0,)} and parsed[1][1] == {"q": (2.0,)}
    assert "byte order mark" in parsed[2][2]


def test_a_line_of_form_feeds_or_vertical_tabs_is_a_record():
    """Blank is spaces, tabs and a CR only (as the man pages say): a line holding a form feed
    or a vertical tab is a record, its error in the output, so that the output has a line for
    every input line that is not blank (it was dropped, as blank)."""
    header, lines = _records(_Bytes(b'{"q": [1, 2]}\n\x0c\n \x0b \n{"q": [3, 4]}\n\x0c'))
    assert lines == [b'{"q": [1, 2]}', b"\x0c", b" \x0b ", b'{"q": [3, 4]}', b"\x0c"]
    parsed = records.parse_records(None, load_robot("bk_rr"), 0, lines)
    assert [e is None for _, _, e in parsed] == [True, False, False, True, False]


def test_an_over_long_line_is_its_records_error_and_reading_goes_on():
    """A line beyond MAX_RECORD_BYTES is one record (None, its error), read in bounded
    pieces and skipped to its newline; the next line is the next record, even when the
    long line is blank."""
    long = b"{" + b" " * (3 * runner.READ_BYTES) + b"}"
    source = _Bytes(b'{"q": [1]}\n' + long[:1000], long[1000:70000], long[70000:] + b"\n{}\n",
                    b" " * (MAX_RECORD_BYTES + 1) + b"\n", b" " * MAX_RECORD_BYTES + b"\n[]")
    header, lines = _records(source)
    assert lines == [b'{"q": [1]}', None, b"{}", None, b"[]"]
    parsed = records.parse_records(None, load_robot("bk_rr"), 0, lines)
    assert parsed[1][2] == "record 2: longer than 64 KiB, kincalc's limit for a --batch line"


@pytest.mark.parametrize("kind, listed, not_listed", [
    ("fk", "(q, the joint values; also id)", "rpy"),
    ("jacobian", "(q, the joint values; also id)", "rpy"),
    ("reach", "(pose fields: xyz, rpy", "lock"), ("ik", "(pose fields: xyz, rpy", None)])
def test_an_unknown_field_is_named_with_the_fields_of_the_command(kind, listed, not_listed):
    """fk and jacobian named ik's pose fields (and lock) as the ones they take."""
    line = b'{"q": [1, 2], "pad": 1}'
    (_, kw, err), = records.parse_records(None, load_robot("bk_rr"), 0, [line], kind)
    assert kw is None and err.startswith("record 1: unknown field 'pad' ") and listed in err
    assert not_listed is None or not_listed not in err


def test_the_cr_of_a_crlf_line_end_is_not_part_of_the_line():
    """A line of exactly MAX_RECORD_BYTES was a record ending in LF but "longer than 64 KiB"
    ending in CRLF (the README: the CR is not part of the line); a byte more is over-long
    with either end, also as the last line of the input."""
    full = b"{" + b" " * (MAX_RECORD_BYTES - 2) + b"}"
    over = full + b" "
    for end in (b"\n", b"\r\n"):
        header, lines = _records(_Bytes(full + end, over + end, full + end.rstrip(b"\n")))
        assert lines == [full + end[:-1], None, full + end[:-1]], end
        header, lines = _records(_Bytes(over + end.rstrip(b"\n")))
        assert lines == [None], end


def test_an_endless_line_ends_the_input_after_a_bounded_read():
    """/dev/zero was read until memory ran out: now its one line is record 1's error, and
    reading stops after MAX_BATCH_SKIP_BYTES."""
    source = _Zeros()
    header, lines = _records(source)
    assert header is None and lines == [None] and source.stopped == 1
    assert source.reads * runner.READ_BYTES <= MAX_BATCH_SKIP_BYTES + 3 * runner.READ_BYTES


def test_a_chunk_is_what_has_arrived_from_a_pipe():
    """With nothing more ready, the lines so far are a chunk of their own, flagged so that
    their answers are written before the reader waits (with --jobs N too)."""
    header, chunks, _ = runner._chunked(_Bytes(b"{}\n{}\n", b"{}\n", ready=False), 2048)
    assert list(chunks) == [((0, [b"{}", b"{}"]), True), ((2, [b"{}"]), True)]
    header, chunks, _ = runner._chunked(_Bytes(b"{}\n" * 5, ready=True), 2)
    assert [(c[0], len(c[1]), f) for c, f in chunks] == [(0, 2, False), (2, 2, False),
                                                          (4, 1, True)]


@pytest.mark.parametrize("line, error", [
    (b'{"q": [0, 0, 0, 0, 0, \xff]}', "not UTF-8 text (byte 0xff at position 23)"),
    (b'{"q": [0, 0, 0, 0, 0, 0]}\0', "holds a NUL byte"),
    (b'{"q": [1, 2, 3, 4, 5, 6], "q": [1, 2, 3, 4, 5, 6]}', "field 'q' is given twice"),
    (b'{"q": [true, 0, 0, 0, 0, 0]}', "q: true is not a number"),
    (b'{"q": ["1", 0, 0, 0, 0, 0]}', "q: a string is not a number"),
    (b'{"q": [NaN, 0, 0, 0, 0, 0]}', "NaN is not a finite number (JSON has no NaN"),
    (b'{"q": [0, -Infinity, 0, 0, 0, 0]}', "-Infinity is not a finite number"),
    (b'{"q": [0, 0, 1e400, 0, 0, 0]}', "q: value 3 is not a finite number"),
    (b'{"q": [0, 0, 0, 1e200, 0, 0]}', "q: value 4 (1e+200) is beyond 1e9"),
    (b'{"q": [0, 0, 0, 0, 1000000001, 0]}', "q: value 5 (1e+09) is beyond 1e9"),
    (b'{"q": [0, 0, 0, 0, 0, 1' + b"0" * 400 + b']}', "q: value 6 is beyond 1e9"),
    (b'{"q": [0, 0, 0, 0, 0, 1' + b"0" * 5000 + b']}', "not JSON (a number too long"),
    (b'{"q": ' + b"[" * 30000 + b"]" * 30000 + b"}", "not JSON (nested too deeply)"),
    (b'{"xyz": [1e200, 0, 0]}', "xyz: value 1 (1e+200) is beyond 1e9"),
    (b'{"q": [0, 0, 0, 0, 0, 0], "id": NaN}', "NaN is not a finite number"),
    (b'{"q": [0, 0, 0, 0, 0, 0], "id": 1e999}', "id must be a string"),
    (b'{"q": [0, 0, 0, 0, 0, 0], "id": [1]}', "id must be a string"),
    (b"42", "expected a JSON object ({...}), not a number"),
    (b"null", "expected a JSON object ({...}), not null"),
    (b'{"' + b"k" * 1000 + b'": 1}', "unknown field 'kkkkkkkk"),
])
def test_json_records_that_are_their_own_error(line, error):
    (i, kw, err), = records.parse_records(None, load_robot("puma560"), 4, [line])
    assert kw is None and err.startswith(f"record 5: {error}"), err
    assert len(err) < 300


def test_json_records_at_the_limits_are_read():
    rows = [b'{"q": [1e9, -1e9, 999999999.5, 0, -0.0, 5e-324], "id": "a:b"}',
            b'{"q": [1, 2, 3, 4, 5, 6], "id": 1e300}', b'{"q": [0, 0, 0, 0, 0, 0], "id": null}']
    parsed = records.parse_records(None, load_robot("puma560"), 0, rows)
    assert [e for _, _, e in parsed] == [None] * 3
    assert parsed[0][1] == {"q": (1e9, -1e9, 999999999.5, 0.0, -0.0, 5e-324), "id": "a:b"}


@pytest.mark.parametrize("cells, error", [
    ("nan,0,0,0,0,0", "column 'q1': 'nan' is not a number"),
    ("0,inf,0,0,0,0", "column 'q2': 'inf' is not a number"),
    ("0,0,true,0,0,0", "column 'q3': 'true' is not a number"),
    ("0,0,0,1e200,0,0", "column 'q4' (1e+200) is beyond 1e9"),
    ("0,0,0,0,1e999,0", "column 'q5' is not a finite number"),
    ("0,0,0,0,,0", "column 'q5': empty cell"),
    ("0,0,0,0,0,1_0", "column 'q6': '1_0' is not a number"),
    ("0,0,0,0,0,\u0661", "column 'q6': '\u0661' is not a number"),
    ('0,0,0,0,0,"1', "not a CSV line: unexpected end of data"),     # ("1" is 1)
    ('0,0,0,0,0,"1"x', "not a CSV line"),
    ("0,0,0,0,0", "5 values for 6 columns"),
])
def test_csv_cells_that_are_their_records_error(cells, error):
    """A NaN or inf cell lost the whole fk/jacobian run (a JSON ValueError, an SVD that
    did not converge) and gave ik an 'unreachable'; 'true' was read as 1."""
    header = tuple(f"q{k}" for k in range(1, 7))
    (i, kw, err), = records.parse_records(header, load_robot("puma560"), 0, [cells.encode()])
    assert err == f"record 1: {error}" or err.startswith(f"record 1: {error}"), err


@pytest.mark.parametrize("blank", ["\x1c", "\x1d", "\x1e", "\x1f", "\xa0", "\u3000", "\x0b"])
def test_csv_cells_with_unicode_blanks_around_a_number(blank):
    """A cell '1' followed by an information separator (0x1c-0x1f, blanks to str.strip but
    not to float) passed the cell check and then failed float(): an internal error, exit 3,
    no record written (an independent tester). Blanks around a number are ignored."""
    header = tuple(f"q{k}" for k in range(1, 7))
    cells = f"0,{blank}1{blank},0,0,0,0".encode()
    (i, kw, err), = records.parse_records(header, load_robot("puma560"), 0, [cells])
    assert err is None and kw["q"] == (0.0, 1.0, 0.0, 0.0, 0.0, 0.0)


def test_csv_headers_that_cannot_be_used():
    """The message names the column at fault: an unknown one, else the one whose group (or
    the joints) is not whole (the first column not used was named: 'theta1' of 'theta1,zzz',
    'roll' of 'x,y,z,roll,pitch,yawn')."""
    robot = load_robot("puma560")
    for header, error in [(("x", "y", "z", "x"), "column 'x' appears twice"),
                          (("x", "y", "w"), "unknown column 'w'"),
                          (("q1", "zzz"), "unknown column 'zzz'"),
                          (("x", "y", "z", "roll", "pitch", "yawn"), "unknown column 'yawn'"),
                          (("x", "y", "z", "roll", "pitch"), "column 'roll' without 'yaw'"),
                          (("q1", "q2"), "column 'q1' without 'q3', 'q4', 'q5', 'q6'")]:
        (_, _, err), = records.parse_records(header, robot, 0, [b"1,2,3"])
        assert err.startswith(f"record 1: {error}"), err
    # fk and jacobian take joints only: their hint lists no pose column
    for kind in ("fk", "jacobian"):
        (_, _, err), = records.parse_records(("Q1",), robot, 0, [b"1"], kind)
        assert err == ("record 1: unknown column 'Q1' (columns: the joints "
                       "q1,q2,q3,q4,q5,q6; and id)")
    # nor does it count pose columns as known ('x' without 'z', then x,y,z refused)
    for header in (("x", "y"), ("x", "y", "z")):
        (_, _, err), = records.parse_records(header, robot, 0, [b"1,2,3"], "fk")
        assert err == "record 1: unknown column 'x' (columns: the joints q1,q2,q3,q4,q5,q6; and id)"
    (_, _, err), = records.parse_records(("Q1",), robot, 0, [b"1"], "reach")
    assert "roll,pitch,yaw" in err and "the joints q1" in err


@pytest.mark.parametrize("first", [b"garbage", b"q", b" Theta1 "])
def test_json_lines_on_stdin_whose_first_record_is_a_stray_word(first):
    """A first line of one name that is not a column of the robot's records is a bad JSON
    record, not a CSV header: it was read as one, every record after it an error ('unknown
    column') and one record fewer out than in. Several names are a CSV header, its unknown
    column named (not every row 'not JSON')."""
    rows = [first, b'{"q": [30, -60]}', b'{"q": [10, 10]}']
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-"], b"\n".join(rows))
    docs = json_documents(out)
    assert status == 2 and [d["index"] for d in docs] == [0, 1, 2]
    assert "error" in docs[0] and "error" not in docs[1] and "error" not in docs[2]
    # a header with a joint's name is CSV, its unknown column named; so is one of several
    # names that are all wrong
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-"], b"theta1,zzz\n1,2\n")
    assert "unknown column 'zzz'" in json_documents(out)[0]["error"]
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-"], b"X,Y\n1,2\n")
    assert "unknown column 'X'" in json_documents(out)[0]["error"]
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-"], b"theta1\n30\n")
    assert "column 'theta1' without 'theta2'" in json_documents(out)[0]["error"]
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-"], b"{}\n")
    assert json_documents(out)[0]["error"] == "record 1: no joints (give q)"


@pytest.mark.parametrize("header", [b"theta1,theta2,", b"theta1;theta2", b"theta1\ttheta2"])
def test_a_first_line_like_a_csv_header_that_cannot_be_one_says_what_a_header_is(header):
    """A trailing comma, ';' or tabs: not taken as a CSV header, so the input is JSON lines;
    record 1's error says what a header is (it said only 'not JSON', as every row did)."""
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-"], header + b"\n30,60\n")
    docs = json_documents(out)
    assert status == 2 and [d["index"] for d in docs] == [0, 1]
    assert docs[0]["error"].endswith("as a CSV header it cannot be used: column names "
                                     "separated by commas, none empty")
    assert "CSV" not in docs[1]["error"]
    # JSON lines by --input-format (or a .jsonl name): a valid header is no hint's business
    status, out, err = run_cli(["fk", "bk_rr", "--batch", "-", "--input-format", "jsonl"],
                               b"theta1,theta2\n30,60\n")
    assert "CSV" not in json_documents(out)[0]["error"]


@pytest.mark.parametrize("command", ["fk", "jacobian", "ik", "reach"])
def test_a_bad_record_is_its_own_error_and_the_run_goes_on(command, tmp_path):
    """Through the command line: each fault of issue 14 costs its own record only (one
    invalid UTF-8 byte lost the whole run, even record 0; a NaN CSV cell or 1e200 in
    reach lost every record)."""
    good = b'{"q": [10, 20, 30, 40, 50, 60]}'
    rows = [b"42", good, b'{"q": [0, 0, 0, 0, 0, \xff]}', good, b'{"q": [NaN, 0, 0, 0, 0, 0]}',
            b'{"xyz": [1e200, 0, 0]}', good]
    status, out, err = run_cli([command, "puma560", "--batch", "-"], b"\n".join(rows))
    docs = json_documents(out)
    assert status == 2 and err == "" and [d["index"] for d in docs] == list(range(7))
    assert [k for k, d in enumerate(docs) if "error" not in d] == [1, 3, 6]
    csv_rows = b"q1,q2,q3,q4,q5,q6\n10,20,30,40,50,60\nnan,0,0,0,0,0\ninf,0,0,0,0,0\n" \
               b"true,0,0,0,0,0\n1e200,0,0,0,0,0\n10,20,30,40,50,60\n"
    status, out, err = run_cli([command, "puma560", "--batch", "-"], csv_rows)
    docs = json_documents(out)
    assert status == 2 and err == "" and len(docs) == 6
    assert [k for k, d in enumerate(docs) if "error" not in d] == [0, 5]
    assert all(d.get("reachable", True) for k, d in enumerate(docs) if k in (0, 5))


def test_reach_batch_a_huge_position_is_one_error_of_forty(tmp_path):
    rng = np.random.default_rng(14)
    rows = [{"xyz": list(rng.uniform(-0.5, 0.5, 3)), "rpy": [0, 90, 0]} for _ in range(40)]
    rows[17] = {"xyz": [1e200, 0, 0]}
    status, out, err = run_cli(["reach", "puma560", "--batch",
                                write(tmp_path, "r.jsonl", rows)])
    docs = json_documents(out)
    assert status == 2 and err == "" and len(docs) == 40
    assert [k for k, d in enumerate(docs) if "error" in d] == [17]
    assert "beyond 1e9" in docs[17]["error"]


def test_batch_dev_zero_ends_with_one_error_record():
    """/dev/zero as --batch was read until MemoryError (exit 3)."""
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero")
    status, out, err = run_cli(["fk", "puma560", "--batch", "/dev/zero"])
    assert status == 2
    assert json_documents(out) == [{"index": 0, "error": "record 1: longer than 64 KiB, "
                                    "kincalc's limit for a --batch line"}]
    assert err.startswith("kincalc: error: --batch /dev/zero: record 1 runs on for more "
                          "than 16 MiB without a newline") and err.count("\n") == 1


def test_no_output_holds_nan_even_if_the_core_returns_it(monkeypatch, capsys):
    """Results that come out NaN become their record's error (the core should never give
    them for inputs within the limits; this is the guard)."""
    r = load_robot("puma560")
    real = type(r).fk

    def fk(self, q, **kw):
        T = real(self, q, **kw)
        T[1] = np.nan
        return T
    monkeypatch.setattr(type(r), "fk", fk)
    status, out, err = run_cli(["fk", "puma560", "--batch", "-"],
                               '{"q": [0, 0, 0, 0, 0, 0]}\n{"q": [1, 0, 0, 0, 0, 0]}\n')
    docs = json_documents(out)
    assert status == 2 and "T" in docs[0]
    assert docs[1] == {"index": 1, "error": "record 2: the result is not a finite number for "
                       "these values"}


def test_input_format_option(tmp_path, capsys):
    src = write(tmp_path, "q.txt", ["q1,q2,q3,q4,q5,q6\n", "0,0,0,0,0,0\n"])
    assert len(lines(run(capsys, "fk", "puma560", "--batch", src)[1])) == 1
    code, out, err = run(capsys, "fk", "puma560", "--batch", src, "--input-format", "jsonl")
    assert code == 2 and len(lines(out)) == 2
    code, out, err = run(capsys, "fk", "puma560", "--batch", src, "--input-format", "xml")
    assert code == 2 and out == "" and "--input-format must be auto, jsonl or csv" in err


# --- pipes, processes and signals (real processes) --------------------------------------

def _kincalc(*argv, **kw):
    return subprocess.Popen([*KINCALC, *argv], env={**os.environ, "OMP_NUM_THREADS": "1"},
                            **kw)


@pytest.mark.parametrize("command", ["fk", "ik"])
def test_a_pipe_into_jobs_does_not_hang(command, tmp_path):
    """`cat poses.jsonl | kincalc ik puma560 --batch - -j 2` hung forever (3 of 3 runs with
    5,000 records, 4 of 5 with 3): the pool forked while the stdin reader thread held
    stdin's lock, and each worker deadlocked closing its stdin. Several runs, since the
    hang was a race."""
    rows = "".join('{"q": [%d, 20, 30, 40, 50, 60]}\n' % k for k in range(3))
    for _ in range(4):
        p = subprocess.run([*KINCALC, command, "puma560", "--batch", "-", "-j", "2"],
                           input=rows, capture_output=True, text=True, timeout=60)
        assert p.returncode == 0 and p.stderr == ""
        assert [d["index"] for d in json_documents(p.stdout)] == [0, 1, 2]
    big = "".join('{"q": [%d, 20, 30, 40, 50, 60]}\n' % (k % 300) for k in range(5000))
    p = subprocess.run([*KINCALC, command, "puma560", "--batch", "-", "-j", "2"],
                       input=big, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and len(json_documents(p.stdout)) == 5000


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_each_answer_comes_at_once_from_a_pipe_with_jobs(jobs):
    """A producer writing one pose at a time gets each answer before it writes the next,
    with --jobs N too (the answers of the chunks in flight are written before the reader
    waits)."""
    p = _kincalc("ik", "puma560", "--batch", "-", "-j", jobs, stdin=subprocess.PIPE,
                 stdout=subprocess.PIPE, text=True)
    try:
        for k in range(4):
            p.stdin.write('{"q": [0, %d, 0, 0, 30, 0]}\n' % (10 * k))
            p.stdin.flush()
            ready, _, _ = select.select([p.stdout], [], [], 60)
            assert ready, f"no answer to record {k + 1} while the input is open"
            assert json.loads(p.stdout.readline())["index"] == k
        p.stdin.close()
        assert p.wait(timeout=60) == 0
    finally:
        p.kill()
        p.wait()


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_closed_stdout_exits_141_quietly(tmp_path, jobs):
    """`kincalc fk puma560 --batch big.jsonl | head -1` exited 1, which the README defines
    as "the answer was no". Here the reader takes one line and closes the pipe."""
    src = write(tmp_path, "big.jsonl", ['{"q": [%d, 20, 30, 40, 50, 60]}\n' % (k % 300)
                                        for k in range(20000)])
    p = _kincalc("fk", "puma560", "--batch", src, "-j", jobs, stdout=subprocess.PIPE,
                 stderr=subprocess.PIPE)
    assert json.loads(p.stdout.readline())["index"] == 0
    p.stdout.close()
    assert p.wait(timeout=60) == 141
    assert p.stderr.read() == b""


def test_a_closed_stdout_in_process_is_141(monkeypatch):
    """main() maps the sys.exit(1) that typer makes of an EPIPE to 141."""
    class Closed(io.StringIO):
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")
    monkeypatch.setattr(sys, "stdout", Closed())
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b'{"q": [0,0,0,0,0,0]}\n')))
    assert main(["fk", "puma560", "--batch", "-"]) == 141      # (typer's sys.exit(1) was 1)
    assert err.getvalue() == ""


@pytest.mark.parametrize("args", [["fk", "puma560"], ["fk", "puma560", "--json"],
                                  ["fk", "puma560", "--batch", "-"], ["robots", "list"]])
@pytest.mark.parametrize("error", [OSError(errno.ENOSPC, "No space left on device"),
                                   OSError(errno.EIO, "Input/output error"),
                                   UnicodeEncodeError("ascii", "\u03b8", 0, 1, "no")])
def test_an_output_the_system_refuses_is_one_line_and_2(monkeypatch, args, error):
    """A full disk (``> /dev/full``) or a terminal whose encoding cannot hold the text was
    called "internal error ... a bug in kincalc", exit 3: the write failed, not kincalc."""
    class Refusing(io.StringIO):
        def write(self, text):
            raise error
    monkeypatch.setattr(sys, "stdout", Refusing())
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b'{"q": [0,0,0,0,0,0]}\n')))
    assert main(args) == 2
    lines = err.getvalue().splitlines()
    assert len(lines) == 1 and lines[0].startswith("kincalc: error: cannot write the output: ")
    assert "bug" not in lines[0]


@pytest.mark.parametrize("argv,closed,words", [
    (["fk", "puma560", "0", "0", "0", "0", "0", "0"], 1, "standard output is closed"),
    (["--help"], 1, "standard output is closed"),
    (["--version"], 1, "standard output is closed"),
    (["fk", "puma560", "--batch", "-"], 1, "standard output is closed"),
    (["ik", "bk_rr", "--pose", "-"], 0, "--pose -: cannot read (standard input is closed)"),
    (["ik", "bk_rr", "--batch", "-"], 0, "--batch -: there is no standard input"),
    (["fk", "nosuch"], 2, None)])
def test_a_stream_closed_before_the_start_is_one_line_and_2(argv, closed, words):
    """`kincalc fk puma560 >&-` (Python's sys.stdout is then None) was "internal error:
    AttributeError: 'NoneType' object has no attribute 'isatty'", exit 3, for every command;
    `<&-` with --pose - the same; `2>&-` exited 1."""
    p = subprocess.run([*KINCALC, *argv], input=None if closed == 0 else
                       b'{"q": [0, 0, 0, 0, 0, 0]}\n', capture_output=True, timeout=120,
                       preexec_fn=lambda: os.close(closed),
                       env={**os.environ, "OMP_NUM_THREADS": "1"})
    assert p.returncode == 2
    if words is not None:
        lines = p.stderr.decode().splitlines()
        assert lines == [f"kincalc: error: {words}" if words.startswith("--") else
                         f"kincalc: error: cannot write the output: {words}"]


def test_an_os_error_that_is_not_a_write_is_still_a_bug(monkeypatch):
    """Only the write errors of the system (:data:`WRITE_ERRNOS`) are the user's: any other
    OSError escaping a command stays an internal error (exit 3)."""
    from kincalc.model import Robot

    def boom(*a, **k):
        raise OSError(errno.EACCES, "Permission denied")
    monkeypatch.setattr(Robot, "fk", boom)
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    assert main(["fk", "puma560", "--json"]) == 3
    assert "internal error" in err.getvalue()


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_ctrl_c_exits_130_with_whole_lines_and_no_traceback(tmp_path, jobs):
    """Ctrl-C with -j 2 printed the workers' KeyboardInterrupt tracebacks. SIGINT goes to
    the whole process group, as from a terminal, while the parent is blocked writing to
    a full pipe (the reader pauses): exit 130, nothing on stderr, and the output ends with
    a whole line (CPython's buffered stdout lost the rest of an interrupted write)."""
    import signal
    import time
    src = write(tmp_path, "big.jsonl", ['{"q": [%d, 20, 30, 40, 50, 60]}\n' % (k % 300)
                                        for k in range(60000)])
    # SIGINT as a terminal leaves it: a run started in the background of a script (as
    # `pytest &`) inherits it ignored, and then Ctrl-C is rightly ignored too
    p = _kincalc("ik", "puma560", "--batch", src, "-j", jobs, stdout=subprocess.PIPE,
                 stderr=subprocess.PIPE, start_new_session=True,
                 preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        # (unbuffered: communicate() reads the descriptor, past a buffered reader's bytes)
        first = os.read(p.stdout.fileno(), 1 << 16)
        time.sleep(1.0)                 # let the pipe fill: the parent blocks in a write
        os.killpg(p.pid, signal.SIGINT)
        rest, err = p.communicate(timeout=60)
    finally:
        p.kill()
        p.wait()
    assert p.returncode == 130 and err == b""
    out = first + rest
    assert out.endswith(b"\n") and len(json_documents(out.decode())) < 60000
    leftover = subprocess.run(["pgrep", "-g", str(p.pid)], capture_output=True, text=True)
    assert leftover.stdout.split() == []


@pytest.mark.parametrize("gap", [0.01, 0.1, 0.3])
def test_ctrl_c_twice_with_two_workers_ends_the_run(tmp_path, gap):
    """A second Ctrl-C while the pool shut down after the first broke the shutdown half-way,
    and the run hung for good (the workers waiting on a pipe; a third Ctrl-C exited with a
    multiprocessing traceback): fuzz campaign, 8 runs of 8. The run ends now, with nothing on
    stderr, no worker left, the output whole lines; 130, or killed by the second SIGINT where
    it came as Python was exiting (its handler then the default: a shell shows 130)."""
    import signal
    import time
    # a redundant arm's records (solved numerically, slowly): the workers are busy
    src = write(tmp_path, "q7.jsonl", ['{"q": [%d, 20, 30, 40, 50, 60, 70]}\n' % (k % 170)
                                       for k in range(600)])
    p = _kincalc("ik", "iiwa14", "--batch", src, "-j", "2", stdout=subprocess.PIPE,
                 stderr=subprocess.PIPE, start_new_session=True,
                 preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        first = os.read(p.stdout.fileno(), 1 << 16)
        os.killpg(p.pid, signal.SIGINT)
        time.sleep(gap)
        try:
            os.killpg(p.pid, signal.SIGINT)
        except ProcessLookupError:
            pass
        rest, err = p.communicate(timeout=60)
    finally:
        group = subprocess.run(["pgrep", "-g", str(p.pid)], capture_output=True,
                               text=True).stdout.split()
        for pid in group:                      # do not leave them behind either way
            os.kill(int(pid), 9)
        p.wait()
    assert p.returncode in (130, -signal.SIGINT) and err == b""
    assert (first + rest).endswith(b"\n")
    assert group == []


def test_a_ctrl_c_leaves_the_next_ones_ignored_until_the_program_ends(tmp_path, monkeypatch,
                                                                   python_ctrl_c):
    """Under load, a second Ctrl-C that came after the run had stopped, while kincalc
    returned (3 runs of 60), came out as a KeyboardInterrupt traceback. The first one now
    leaves Ctrl-C ignored while the run stops; main() gives an in-process caller its
    handler back."""
    import signal
    calls = []
    real = runner.process_chunk

    def interrupted(*a, **k):                 # Ctrl-C while the first chunk is solved
        if not calls:
            calls.append(1)
            os.kill(os.getpid(), signal.SIGINT)
            calls.append(signal.getsignal(signal.SIGINT))
        return real(*a, **k)
    monkeypatch.setattr(runner, "process_chunk", interrupted)
    src = write(tmp_path, "q.jsonl", ['{"q": [0, 0, 0, 0, 0, 0]}\n'] * 3)
    status, out, err = run_cli(["fk", "puma560", "--batch", src])
    assert status == 130 and err == ""
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    # as the program (argv from sys.argv): Ctrl-C stays ignored after the run stopped
    calls.clear()
    monkeypatch.setattr(sys, "argv", ["kincalc", "fk", "puma560", "--batch", str(src)])
    monkeypatch.setattr(sys, "stdout", io.StringIO())
    try:
        assert main() == 130
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def test_workers_exit_when_the_parent_is_killed():
    """A killed parent never shuts its pool down: the workers, blocked reading their task
    queue (whose write end they hold too), stayed forever."""
    import time
    p = _kincalc("fk", "puma560", "--batch", "-", "-j", "2", stdin=subprocess.PIPE,
                 stdout=subprocess.PIPE, start_new_session=True)
    p.stdin.write(b'{"q": [0, 0, 0, 0, 0, 0]}\n')
    p.stdin.flush()
    if not select.select([p.stdout], [], [], 60)[0]:
        os.killpg(p.pid, 9)
        pytest.fail("no answer from a pipe with -j 2")
    p.stdout.readline()
    group = lambda: subprocess.run(["pgrep", "-g", str(p.pid)], capture_output=True,  # noqa
                                   text=True).stdout.split()
    assert len(group()) == 3                       # the parent and two workers
    p.kill()
    p.wait()
    for _ in range(300):
        if not group():
            break
        time.sleep(0.1)
    left = group()
    for pid in left:                               # do not leave them behind either way
        os.kill(int(pid), 9)
    assert left == []



def test_a_far_pose_does_not_change_its_neighbours_answers(capsys):
    """A pose 1e9 from the base (within the limits) in the same chunk made ik --batch
    answer 'unreachable' for an ordinary pose."""
    alone = run_cli(["ik", "puma560", "--batch", "-"],
                    '{"xyz": [0.3, 0.1, 0.2], "quat": [1, 0, 0, 0]}\n')[1]
    both = run_cli(["ik", "puma560", "--batch", "-"],
                   '{"xyz": [1e9, -1e9, 1e9], "rpy": [0, 0, 0]}\n'
                   '{"xyz": [0.3, 0.1, 0.2], "quat": [1, 0, 0, 0]}\n')[1]
    assert json_documents(both)[1]["solutions"] == json_documents(alone)[0]["solutions"]


def test_ik_batch_records_hold_joints(tmp_path, capsys):
    """A record's ``lock`` (and ``--lock`` for every record): the generating joints among
    the solutions, each reproducing the pose with the held values in place, the same
    branches and flags as ``ik --lock``; bad locks are error records, and only ik takes
    them."""
    r = load_robot("iiwa14")
    Q = sample_configurations(r, 12, np.random.default_rng(8))
    T = r.fk(Q)
    held = [2 if k % 2 else 6 for k in range(len(Q))]          # A3 or A7
    src = write(tmp_path, "l.jsonl", [
        {"q": list(np.degrees(q)), "lock": {r.joints[j].name: float(np.degrees(q[j]))}}
        for q, j in zip(Q, held)])
    for jobs in ("1", "2"):
        code, out, err = run(capsys, "ik", "iiwa14", "--batch", src, "-j", jobs)
        assert code == 0, err
        recs = lines(out)
        for rec, t, q, j in zip(recs, T, Q, held):
            sols = np.radians([s["q"] for s in rec["solutions"]])
            assert len(sols) == 8 and np.allclose(sols[:, j], q[j])
            assert np.allclose(r.fk(sols), t, atol=1e-9)
            assert (np.abs((sols - q + np.pi) % (2 * np.pi) - np.pi).max(-1) < 1e-6).any()
    rec, q, j = recs[1], Q[1], held[1]
    c, single, _ = run(capsys, "ik", "iiwa14", "--from-q",
                       " ".join(repr(float(v)) for v in np.degrees(q)), "--lock",
                       f"{r.joints[j].name}={float(np.degrees(q[j]))!r}", "--json")
    doc = json.loads(single)
    assert {(s["branch"], s["within_limits"]) for s in rec["solutions"]} == \
        {(s["branch"], s["within_limits"]) for s in doc["solutions"]}
    # --lock for every record, a record's own lock added to it
    src = write(tmp_path, "g.jsonl", [{"q": list(np.degrees(Q[0]))},
                                      {"q": list(np.degrees(Q[0])), "lock": {"A9": 1}},
                                      {"q": list(np.degrees(Q[0])), "lock": {"A4": 1}},
                                      {"q": list(np.degrees(Q[0])), "lock": [1]},
                                      {"q": list(np.degrees(Q[0])), "lock": {"A1": True}},
                                      {"q": list(np.degrees(Q[0])), "lock": {"A1": 1, "1": 2}}])
    code, out, err = run(capsys, "ik", "iiwa14", "--batch", src, "--lock",
                         f"A3={float(np.degrees(Q[0][2]))!r}")
    recs = lines(out)
    assert code == 2 and len(recs) == 6
    assert "A1 is held twice" in recs[5]["error"]
    assert len(recs[0]["solutions"]) == 8
    assert "no joint 'A9'" in recs[1]["error"]
    assert "reachable" in recs[2]                     # A3 and A4 held: five joints left
    assert "lock: expected an object" in recs[3]["error"] and "not a number" in recs[4]["error"]
    code, out, err = run(capsys, "ik", "iiwa14", "--batch", src)
    assert "continuum" in lines(out)[2]["error"]
    code, out, err = run(capsys, "reach", "iiwa14", "--batch", src)
    assert code == 2 and "only ik --batch" in lines(out)[1]["error"]


@pytest.mark.parametrize("command", ["ik", "reach"])
def test_record_errors_name_record_fields_and_matrix_takes_rows(command, tmp_path, capsys):
    """Found by an independent tester: reach --batch worded a record's zero quaternion as
    '--quat must not be ...', and both commands a T given with xyz as '... with --xyz'
    (command-line option names for a record's fields); a 'matrix' given as three rows was
    'expected 9 numbers' although T takes its rows and sheets take the matrix's."""
    recs = [{"xyz": [0.3, 0, 0.3], "quat": [0, 0, 0, 0]},
            {"xyz": [0.3, 0, 0.3], "T": np.eye(4).tolist()},
            {"xyz": [0.3, 0.1, 0.3], "matrix": [[0, -1, 0], [1, 0, 0], [0, 0, 1]]},
            {"xyz": [0.3, 0.1, 0.3], "matrix": [0, -1, 0, 1, 0, 0, 0, 0, 1]}]
    f = tmp_path / "recs.jsonl"
    f.write_text("".join(json.dumps(r) + "\n" for r in recs))
    assert main([command, "puma560", "--batch", str(f)]) == 2
    out = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert out[0]["error"] == "record 1: quat must not be the zero quaternion"
    assert out[1]["error"] == "record 2: T gives the whole pose; do not combine it with xyz"
    assert "error" not in out[2] and {**out[2], "index": 3} == out[3]


def test_fk_batch_output_is_ik_and_reach_batch_input():
    """`kincalc fk R --batch | kincalc ik R --batch -`: fk's records (index, T, xyz, rpy,
    within_limits) are read by their T, so every configuration comes back among the
    solutions of its pose; fk's error records stay error records, one answer each."""
    robot = load_robot("puma560")
    Q = np.degrees(sample_configurations(robot, 40, np.random.default_rng(8)))
    lines = [json.dumps({"q": q.tolist()}).encode() for q in Q]
    lines.insert(7, b'{"q": [1, 2, 3]}')                         # an fk error record
    status, out, _ = run_cli(["fk", "puma560", "--batch", "-"], b"\n".join(lines))
    assert status == 2
    status, ik_out, err = run_cli(["ik", "puma560", "--batch", "-"], out.encode())
    docs = json_documents(ik_out)
    assert status == 2 and err == "" and [d["index"] for d in docs] == list(range(41))
    assert docs[7]["error"] == "record 8: an error record of fk --batch, not a pose"
    for q, doc in zip(Q, docs[:7] + docs[8:]):
        sols = np.array([s["q"] for s in doc["solutions"]])
        gap = np.abs((sols - q + 180) % 360 - 180).max(axis=1)
        assert gap.min() < 1e-6
    status, reach_out, _ = run_cli(["reach", "puma560", "--batch", "-"], out.encode())
    assert [d.get("verdict") for d in json_documents(reach_out)] == \
        ["reachable"] * 7 + [None] + ["reachable"] * 33
    # an fk record is read only as fk wrote it: every field its own, of its own form
    rec = json.loads(out.splitlines()[0])
    for change, error in [({"xyz": [rec["xyz"][0] + 0.01] + rec["xyz"][1:]},
                           "xyz is not T's position"),
                          ({"index": "x"}, "index: expected a whole number from 0"),
                          ({"rpy": "junk"}, "rpy: expected 3 numbers"),
                          ({"within_limits": {"a": 1}}, "within_limits: expected true or false"),
                          ({"units": {"length": "furlong", "angle": "deg"}},
                           "units: expected {\"length\": one of m, cm, mm, in, unitless"),
                          ({"foo": 1}, "unknown field 'foo' (an fk --batch record has index, "
                                       "T, xyz, rpy, within_limits, units and perhaps id)")]:
        status, ik_out, _ = run_cli(["ik", "puma560", "--batch", "-"],
                                    json.dumps({**rec, **change}).encode())
        assert error in json_documents(ik_out)[0]["error"], change
    del rec["rpy"]
    status, ik_out, _ = run_cli(["ik", "puma560", "--batch", "-"], json.dumps(rec).encode())
    assert json_documents(ik_out)[0]["error"] == "record 1: an fk --batch record without rpy"


@pytest.mark.parametrize("kind", ["ik", "reach"])
def test_fk_batch_records_say_their_units_and_ik_batch_reads_them(kind):
    """`kincalc fk R --batch --unit m | kincalc ik R --batch -` on a robot in mm read the
    metres as millimetres: 'reachable' with 8 solutions of a point 0.4 mm from the base.
    Now an fk record says its units, and its T is read in them; a record without them (as
    fk wrote them before) is read in the run's units."""
    robot = load_robot("abb_irb120")                              # a robot file in mm
    Q = np.degrees(sample_configurations(robot, 12, np.random.default_rng(9)))
    lines = b"\n".join(json.dumps({"q": q.tolist()}).encode() for q in Q)
    status, out, _ = run_cli(["fk", "abb_irb120", "--batch", "-", "--unit", "m"], lines)
    assert status == 0
    assert all(json.loads(x)["units"] == {"length": "m", "angle": "deg"}
               for x in out.splitlines())
    for unit in ([], ["--unit", "cm"], ["--unit", "m"]):
        status, got, err = run_cli([kind, "abb_irb120", "--batch", "-"] + unit, out.encode())
        docs = json_documents(got)
        assert status == 0 and err == "" and len(docs) == 12, (unit, err)
        if kind == "reach":
            assert {d["verdict"] for d in docs} == {"reachable"}
            continue
        for q, doc in zip(Q, docs):
            sols = np.array([s["q"] for s in doc["solutions"]])
            assert np.abs((sols - q + 180) % 360 - 180).max(axis=1).min() < 1e-6
    old = "\n".join(json.dumps({k: v for k, v in json.loads(x).items() if k != "units"})
                    for x in out.splitlines())
    status, got, _ = run_cli([kind, "abb_irb120", "--batch", "-", "--unit", "m"], old.encode())
    assert status == 0 and len(json_documents(got)) == 12
    # no unit converts to a unitless robot's lengths
    status, out, _ = run_cli(["fk", "bk_rr", "--batch", "-"], b'{"q": [10, 20]}')
    rec = {**json.loads(out), "units": {"length": "m", "angle": "deg"}}
    status, got, _ = run_cli([kind, "bk_rr", "--batch", "-"], json.dumps(rec).encode())
    assert status == 2 and json_documents(got)[0]["error"] == (
        "record 1: its T is in m (an fk --batch record's units), this run's lengths are "
        "unitless")


def test_a_record_without_orientation_lists_tcv_only_for_a_robot_that_takes_one():
    """The orientation hint of a batch record: a 6R arm's offered tcv, then refused it; a
    SCARA's named it twice."""
    status, out, _ = run_cli(["ik", "ur5", "--batch", "-"], b'{"xyz": [0.3, 0.1, 0.4]}\n')
    error = json_documents(out)[0]["error"]
    assert error.endswith("(rpy, euler_zyz, euler_xyz, quat, axis_angle, matrix, T or q)")
    status, out, _ = run_cli(["ik", "adept_cobra600", "--batch", "-"],
                             b'{"xyz": [300, 100, 40]}\n')
    error = json_documents(out)[0]["error"]
    assert error.endswith("T or q) or a tool configuration vector (tcv)")


#: a PUMA configuration (deg) whose roll's 12th decimal the two ways of evaluating the chain
#: round differently (found by a fuzz campaign)
SPLIT_DIGIT = [14.787, -88.995, 65.328, 80.383, -18.056, -72.553]


@pytest.mark.parametrize("command", ["fk", "jacobian", "ik"])
def test_a_records_digits_do_not_depend_on_the_records_read_with_it(command, tmp_path, capsys):
    """Up to 32 configurations were evaluated as stacked 4x4 products and more by the column
    walk, which round differently: a record's last printed digit depended on how many records
    its chunk held (from a pipe, on timing, so that -j 1 and -j 2 differed), and the single
    command agreed with the small chunks only. Each record alone, all 40 together and the
    single command now print the same numbers (ik: its target from the joints, --from-q)."""
    rng = np.random.default_rng(11)
    Q = np.vstack([SPLIT_DIGIT, rng.uniform(-170, 170, (39, 6))]).round(3).tolist()
    together = lines(run(capsys, command, "puma560", "--batch",
                         write(tmp_path, "all.jsonl", [{"q": q} for q in Q]))[1])
    for k, q in enumerate(Q):
        alone = lines(run(capsys, command, "puma560", "--batch",
                          write(tmp_path, "one.jsonl", [{"q": q}]))[1])[0]
        assert {**alone, "index": k} == together[k], k
    argv = [command, "puma560", *map(str, SPLIT_DIGIT), "--json"] if command != "ik" else [
        "ik", "puma560", "--from-q", " ".join(map(str, SPLIT_DIGIT)), "--json"]
    single = json.loads(run(capsys, *argv)[1])
    if command == "fk":
        assert single["T"] == together[0]["T"]
        assert single["orientation"]["rpy"] == together[0]["rpy"]
    elif command == "jacobian":
        assert single["J"] == together[0]["J"]
    else:                       # (the single command's 12 decimals, the batch's 12 digits)
        assert np.allclose(sorted(s["q"] for s in single["solutions"]),
                           sorted(s["q"] for s in together[0]["solutions"]), atol=1e-9)


@pytest.mark.parametrize("kind", ["fk", "jacobian"])
@pytest.mark.parametrize("extra", [["--frobnicate"], ["--lock", "A3=30"]])
def test_an_unknown_option_with_batch_is_named(tmp_path, capsys, kind, extra):
    """An unknown option after ``--batch`` is refused as one, not as joint values given
    with the batch (fk and jacobian take their joint values, which may be negative, as
    free tokens; a fuzz campaign's finding); joint values themselves still get the batch's
    refusal."""
    src = tmp_path / "q.jsonl"
    src.write_text('{"q": [0, 0, 0, 0, 0, 0]}\n')
    status, out, err = run(capsys, kind, "puma560", "--batch", str(src), *extra)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and f"no such option: {extra[0]}" in err, err
    status, out, err = run(capsys, kind, "puma560", "--batch", str(src), "0", "-45")
    assert status == 2 and "do not give joint values" in err, err


@pytest.mark.parametrize("command", [["fk", "bk_rr"], ["jacobian", "bk_rr"], ["ik", "bk_rr"],
                                     ["reach", "bk_rr"]])
def test_batch_json_with_format_csv_is_refused(command):
    """--json with --batch --format csv printed CSV, exit 0 (hostile-input campaign)."""
    status, out, err = run_cli([*command, "--batch", "-", "--json", "--format", "csv"],
                               stdin='{"q": [0, 0]}\n')
    assert status == 2 and out == "" and err.count("\n") == 1
    assert "--json and --format csv" in err


def test_a_joint_named_as_a_csv_column_gets_its_own_column(tmp_path):
    """Joints named index and error made a header with two columns index and two error, and
    csv.DictReader took a joint's value for the record's index (hostile-input campaign)."""
    import csv
    robot = tmp_path / "idx.yaml"
    robot.write_text("name: idx\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                     "  - {name: index, type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n"
                     "  - {name: error, type: revolute, alpha: 0, a: 0.2, d: 0, theta: 0}\n")
    status, out, err = run_cli(["ik", str(robot), "--batch", "-", "--format", "csv"],
                               stdin="x,y,z\n0.4,0.1,0\n")
    assert status == 0 and err == ""
    rows = list(csv.DictReader(io.StringIO(out)))
    header = out.splitlines()[0].split(",")
    assert len(header) == len(set(header)) and "joint index" in header and "joint error" in header
    assert [r["index"] for r in rows] == ["0", "0"] and all(r["error"] == "" for r in rows)
    assert sorted(round(float(r["joint error"]), 6) for r in rows) == [-70.528779, 70.528779]


def test_csv_written_with_every_cell_quoted_is_read(tmp_path, capsys):
    """A file from Python's csv.QUOTE_ALL ('"q1","q2",... then "1","2",...') gave every
    record "unknown column '\"q1\"'": the header and the cells were split at commas only."""
    q = np.random.default_rng(6).uniform(-100, 100, (5, 6))
    names = [j.name for j in load_robot("puma560").joints]
    buf = io.StringIO()
    w = csv.writer(buf, quoting=csv.QUOTE_ALL, lineterminator="\n")
    w.writerow(names)
    w.writerows(x.tolist() for x in q)
    quoted = tmp_path / "quoted.csv"
    quoted.write_text(buf.getvalue() + '"1,2",3,4,5,6,7\n')
    plain = write(tmp_path, "plain.jsonl", [{"q": x.tolist()} for x in q])
    code, out, err = run(capsys, "fk", "puma560", "--batch", str(quoted))
    assert code == 2, err
    recs = lines(out)
    _, ref, _ = run(capsys, "fk", "puma560", "--batch", plain)
    assert recs[:5] == lines(ref)
    assert recs[5] == {"index": 5, "error": "record 6: column 'q1': '1,2' is not a number"}
