"""``kincalc ik --sweep``: tables, JSON and CSV say the same, the options are checked, a
drawing is written."""

import csv
import io
import json

import pytest
from cli_contract import run_cli

Q0 = "10 40 20 -60 30 50 -20"


def test_json_csv_and_tables_agree():
    base = ["ik", "iiwa14", "--from-q", Q0, "--sweep", "A3", "--from", "-90", "--to", "90",
            "--steps", "7"]
    status, out, err = run_cli(base + ["--json"])
    assert status == 0, err
    doc = json.loads(out)
    assert doc["sweep"]["values"] == [-90.0, -60.0, -30.0, 0.0, 30.0, 60.0, 90.0]
    assert len(doc["branches"]) == 8 and doc["reachable"]
    status, out, err = run_cli(base + ["--format", "csv"])
    assert status == 0, err
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == sum(len(p["solutions"]) for p in doc["points"])
    first = doc["points"][0]["solutions"][0]
    assert float(rows[0]["A5"]) == pytest.approx(first["q"][4], abs=1e-9)
    assert rows[0]["A3_swept"] == "-90.0" and rows[0]["label"] == first["label"]
    status, out, err = run_cli(base)
    assert status == 0, err
    assert "8 branches along A3" in out and "range end" in out


def test_near_picks_a_branch_and_value():
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", Q0, "--sweep", "3", "--steps", "19",
                                "--near", "0 30 0 -60 0 60 0", "--json"])
    assert status == 0, err
    best = json.loads(out)["nearest"]
    assert best["branch"] >= 1 and best["q"][2] == best["value"]


def test_bad_sweep_options():
    for extra, words in ((["--from", "10"], "--from needs --sweep"),
                         (["--steps", "5"], "--steps needs --sweep"),
                         (["--sweep", "A9"], "no joint 'A9'"),
                         (["--sweep", "A4"], "continuum"),
                         (["--sweep", "A3", "--lock", "A3=10"], "also locked"),
                         (["--sweep", "A3", "--all-branches"], "--all-branches does not go"),
                         (["--sweep", "A3", "--numeric"], "--numeric does not go"),
                         (["--sweep", "A3", "--from", "nan"], "--from"),
                         (["--sweep", "A3", "--format", "xml"], "--format")):
        status, out, err = run_cli(["ik", "iiwa14", "--from-q", Q0, *extra])
        assert status == 2 and words in err and err.count("\n") == 1, (extra, err)
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", Q0, "--sweep", "A3", "--steps", "1"])
    assert status == 2 and "--steps" in err


def test_unreachable_everywhere_exits_1():
    status, out, err = run_cli(["ik", "iiwa14", "--xyz", "5", "0", "0", "--rpy", "0", "0", "0",
                                "--sweep", "A1", "--steps", "5", "--json"])
    assert status == 1, err
    doc = json.loads(out)
    assert not doc["reachable"] and doc["branches"] == []


def test_plot(tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "sweep.png"
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", Q0, "--sweep", "A1", "--steps", "31",
                                "--plot", str(path)])
    assert status == 0, err
    assert path.stat().st_size > 10_000 and "drawing:" in out


def test_more_bad_sweeps():
    for argv, words in ((["iiwa14", "--from-q", Q0, "--sweep", "3", "--from", "10", "--to", "10"],
                         "the same value"),
                        (["iiwa14", "--from-q", Q0, "--sweep", "3", "--format", "csv", "--json"],
                         "--json and --format csv"),
                        # (a general 6R arm's joints 1-4 and 6: no structure)
                        (["manocha_canny_6r", "--from-q", "10 20 30 40 50 60", "--sweep", "5",
                          "--from", "0", "--to", "20"], "no closed form covers")):
        status, out, err = run_cli(["ik", *argv])
        assert status == 2 and words in err and err.count("\n") == 1, (argv, err)
    status, out, err = run_cli(["selftest", "puma560", "--lock-joint", "1"])
    assert status == 2 and "redundant arms" in err


def test_a_ur_arm_held_at_its_first_joint_is_solved_in_closed_form():
    """A UR arm's joints 2-6 (three parallel axes placing the point where axes 5 and 6 meet,
    with a turn to spare: the planar shoulder, that point off the tool's approach line) were
    refused as having no closed form. Held at q1 = 10 deg a pose FK gave from q1 = 10 deg has
    the UR5's solutions with that q1: four, each reaching the pose; at 0 and 20 deg none
    (five joints reach a pose only where the held joint lets them)."""
    import numpy as np

    from kincalc import load_robot
    r = load_robot("ur5")
    q0 = np.radians([10, 20, 30, 40, 50, 60])
    status, out, err = run_cli(["ik", "ur5", "--from-q", "10 20 30 40 50 60", "--sweep", "1",
                                "--from", "0", "--to", "20", "--steps", "3", "--json"])
    assert status == 0, err
    points = {p["value"]: p["solutions"] for p in json.loads(out)["points"]}
    assert points[0.0] == [] and points[20.0] == []
    sols = points[10.0]
    assert len(sols) == 4 and len({s["label"] for s in sols}) == 4
    for s in sols:
        assert np.abs(r.fk(np.radians(s["q"])) - r.fk(q0)).max() < 1e-9
    assert any(np.allclose(s["q"], np.degrees(q0), atol=1e-9) for s in sols)


def test_csv_names_and_labels_from_the_robot_file_are_no_formula(tmp_path):
    """The sweep's CSV wrote the robot file's joint names (header, swept column) and the
    branch labels that name them as they were: a joint '=A1' reached a spreadsheet as a
    formula (the batch CSV's cells had their apostrophe already)."""
    import yaml
    from pathlib import Path
    doc = yaml.safe_load((Path(__file__).parents[2] / "robots" / "iiwa14.yaml").read_text())
    for j, name in zip(doc["joints"], ["=A1", "@A2", "+A3", "-A4", "A5", "A6", "A7"]):
        j["name"] = name
    robot = tmp_path / "iiwa.yaml"
    robot.write_text(yaml.safe_dump(doc, allow_unicode=True))
    status, out, err = run_cli(["ik", str(robot), "--from-q", Q0, "--sweep", "+A3",
                                "--steps", "5", "--format", "csv"])
    assert status == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0][:1] == ["'+A3_swept"] and rows[0][3:7] == ["'=A1", "'@A2", "'+A3", "'-A4"]
    assert all(not c[:1] or c[:1] not in "=+-@" for r in rows[1:] for c in r[2:3]), rows[:3]
