"""DH items with 'base: ignore' / 'tool: ignore' on random robots, degenerate on
purpose (special and nearly special twists, coaxial joints, prismatic joints, rotated
base and tool): ``kincalc quiz`` keys that ``kincalc check`` grades 100 %, and the
robot's own rows graded right with every frame ignored or given."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

from kincalc.cli.main import main
from kincalc.conventions.writer import dump_robot
from randrobots import degenerate_dh_robot


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("seed", range(12))
def test_dh_key_of_a_random_robot_scores_full_marks(tmp_path, capsys, seed):
    rng = np.random.default_rng([2024, seed])
    robot = degenerate_dh_robot(rng, int(rng.integers(2, 7)))
    (tmp_path / "arm.yaml").write_text(dump_robot(robot), encoding="utf-8")
    key = tmp_path / "key.yaml"
    code, _, err = run(capsys, "quiz", tmp_path / "arm.yaml", "--seed", seed, "--items",
                       "dh,dh", "--answers", "-o", key)
    assert code == 0, err
    items = yaml.safe_load(key.read_text())["items"]
    assert items[0].get("base") == "ignore" and items[0].get("tool") == "ignore"
    code, out, err = run(capsys, "check", key, "-q")
    assert code == 0 and "(100 %)" in out, out + err


@pytest.mark.parametrize("seed", range(6))
def test_own_rows_graded_right_with_every_frame_ignored_or_given(tmp_path, capsys, seed):
    rng = np.random.default_rng([77, seed])
    robot = degenerate_dh_robot(rng, int(rng.integers(3, 7)))
    (tmp_path / "arm.yaml").write_text(dump_robot(robot), encoding="utf-8")
    code, out, _ = run(capsys, "quiz", tmp_path / "arm.yaml", "--seed", 0, "--items", "dh",
                       "--answers", "-o", "-")
    sheet = yaml.safe_load(out)
    rows = sheet["items"][0]["answer"]["table"]
    items = []
    for base in ("ignore", "compare"):
        for tool in ("ignore", "compare"):
            answer = {"convention": "dh", "table": rows}
            for name, frame, how in (("base", robot.base, base), ("tool", robot.tool, tool)):
                if how == "compare":
                    answer[name] = {"matrix": np.asarray(frame).tolist()}
            items.append({"id": f"{base}-{tool}", "kind": "dh", "base": base, "tool": tool,
                          "answer": answer})
    # a wrong row: the distance between two revolute axes (a_i) is no frame's to absorb
    i = next((i for i in range(robot.dof - 1)
              if robot.is_revolute[i] and robot.is_revolute[i + 1]), None)
    if i is not None:
        wrong = [list(r) for r in rows]
        a = robot.joints[i].a
        wrong[i][2] = a + (0.1 if a >= 0 else -0.1)
        items.append({"id": "wrong", "kind": "dh", "base": "ignore", "tool": "ignore",
                      "answer": {"convention": "dh", "table": wrong}})
    sheet["items"], sheet["robot"] = items, "arm.yaml"
    (tmp_path / "hw.yaml").write_text(yaml.safe_dump(sheet), encoding="utf-8")
    code, out, err = run(capsys, "check", tmp_path / "hw.yaml", "--json")
    assert "items" in json.loads(out), out + err
    graded = {it["id"]: it["passed"] for it in json.loads(out)["items"]}
    assert graded.pop("wrong", False) is False, out
    assert all(graded.values()) and len(graded) == 4, out
    # the robot's own rows use its joint variables, even where coaxial joints leave
    # the split of an offset between them free
    assert all(it["message"].endswith("; same joint variables")
               for it in json.loads(out)["items"] if it["id"] != "wrong"), out
