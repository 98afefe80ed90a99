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
