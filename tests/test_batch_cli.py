"""--batch on fk, jacobian and ik: records in, one record out per input, in order.

Expected values come from independent places: a plain-numpy standard-DH FK written
here from the PUMA's table, finite differences of it for the Jacobian, and the
single-pose commands' JSON for the IK labels and limit flags.
"""

import csv
import io
import json
import os
import select
import subprocess
import sys

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.cli import batch as batch_mod
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
    src = write(tmp_path, "q.jsonl", [{"q": q} for q in qs])
    code, out, err = run(capsys, "jacobian", "puma560", "--batch", src)
    for r, q in zip(lines(out), qs):
        c, single, _ = run(capsys, "jacobian", "puma560", *map(str, q), "--json")
        doc = json.loads(single)
        assert r["rank"] == doc["rank"] and r["singular"] == doc["singular"]
        assert np.isclose(r["manipulability"], doc["manipulability"], rtol=1e-9, atol=1e-15)
        assert np.allclose(r["J"], doc["J"], atol=1e-11)


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
    for rec, q in list(zip(recs, Q))[:6]:
        c, single, _ = run(capsys, "ik", "puma560", "--from-q",
                           " ".join(repr(float(v)) for v in np.degrees(q)), "--json")
        doc = json.loads(single)
        mine = {(s["branch"], s["within_limits"]) for s in rec["solutions"]}
        theirs = {(s["branch"], s["within_limits"]) for s in doc["solutions"]}
        assert mine == theirs
        for s in rec["solutions"]:              # same joint values, branch by branch
            other = next(o for o in doc["solutions"] if o["branch"] == s["branch"])
            assert np.allclose(s["q"], other["q"], atol=1e-7)


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
    monkeypatch.setattr(batch_mod, "CHUNK_LINES", 64)
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
