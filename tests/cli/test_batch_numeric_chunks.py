"""ik --batch of a robot solved numerically: small chunks, so that --jobs shares even a
short input; the output keeps the input's order and count, and every solution is checked
by an FK round trip (not against captured output)."""

import json

import numpy as np

from kincalc import load_robot
from kincalc.cli.batch import runner
from kincalc.cli.main import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_numerical_robots_get_small_chunks():
    iiwa, puma = load_robot("iiwa14"), load_robot("puma560")
    assert runner.chunk_lines("ik", iiwa) == runner.NUMERIC_CHUNK_LINES < 10
    assert runner.chunk_lines("ik", puma) == runner.CHUNK_LINES
    assert runner.chunk_lines("fk", iiwa) == runner.CHUNK_LINES
    assert runner.chunk_lines("reach", iiwa) == runner.REACH_CHUNK_LINES
    assert runner.chunk_lines("ik", iiwa, {2: 0.0}) == runner.CHUNK_LINES


def test_jobs_share_a_short_numerical_batch_in_order(tmp_path, capsys, monkeypatch):
    r = load_robot("iiwa14")
    rng = np.random.default_rng(3)
    Q = rng.uniform(*r.limits.T, size=(14, r.dof))
    rows = [{"T": T.tolist()} for T in r.fk(Q)]
    rows[5] = {"xyz": [1e9, 1e9, 1e9]}                 # beyond reach: answered at once
    rows[9] = {"T": "nope"}                             # a bad record keeps its place
    src = tmp_path / "t.jsonl"
    src.write_text("".join(json.dumps(x) + "\n" for x in rows))
    chunks = []
    real = runner.process_chunk

    def counted(kind, robot, units, header, fmt, frame, item, **options):
        chunks.append(len(item[1]))
        return real(kind, robot, units, header, fmt, frame, item, **options)
    monkeypatch.setattr(runner, "process_chunk", counted)
    c1, one, _ = run(capsys, "ik", "iiwa14", "--batch", str(src), "--rad")
    assert len(chunks) >= 2 and sum(chunks) == len(rows)
    monkeypatch.undo()                  # the workers take the module's own (picklable) one
    c2, two, _ = run(capsys, "ik", "iiwa14", "--batch", str(src), "--rad", "--jobs", "2")
    assert c1 == c2 == 2 and one == two
    out = [json.loads(x) for x in two.splitlines()]
    assert [o["index"] for o in out] == list(range(len(rows)))
    for i, o in enumerate(out):
        if i == 9:
            assert "error" in o
        elif i == 5:
            assert o["reachable"] is False and o["solutions"] == []
        else:
            assert o["reachable"] is True
            q = np.array(o["solutions"][0]["q"])
            assert np.allclose(r.fk(q), np.array(rows[i]["T"]), atol=1e-8)


def test_records_out_of_reach_search_for_no_reason(tmp_path, capsys, monkeypatch):
    """A batch record shows no reason, so none is looked for: out of reach, a target's reason
    searched for the nearest reachable point (some 0.1 s a record, and 3,000 records of
    positions inside a planar arm's inner void gave no output in two minutes). The records
    still say unreachable, in order, checked by the arm's reach (inner radius 5)."""
    import sys

    import kincalc.ik.verdict as verdict
    solve_module = sys.modules["kincalc.ik.solve"]          # (kincalc.ik.solve: the function)

    def searched(*args, **kwargs):
        raise AssertionError("a batch record searched for its reason")
    monkeypatch.setattr(verdict, "out_of_reach", searched)
    monkeypatch.setattr(solve_module, "out_of_reach", searched)
    rng = np.random.default_rng(8)
    P = np.c_[rng.uniform(-3, 3, (40, 2)), np.zeros(40)]
    P[::4] = [12.0, 3.0, 0.0]                           # reachable: l1 + l2 = 15, |l1 - l2| = 5
    src = tmp_path / "p.csv"
    src.write_text("x,y,z\n" + "".join(f"{x},{y},{z}\n" for x, y, z in P))
    code, out, err = run(capsys, "ik", "bk_rr", "--batch", str(src))
    recs = [json.loads(line) for line in out.splitlines()]
    assert code == 1 and len(recs) == 40, err
    r = load_robot("bk_rr")
    for rec, p in zip(recs, P):
        inside = 5.0 <= np.hypot(*p[:2]) <= 15.0
        assert rec["reachable"] == inside
        for s in rec["solutions"]:
            assert np.allclose(r.fk(np.radians(s["q"]))[:3, 3], p, atol=1e-9)
