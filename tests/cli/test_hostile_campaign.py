"""Command-line cases of what an outside hostile-input campaign found (one per fix; the
tests at the depth of each fix are next to the code's other tests)."""

from __future__ import annotations

import json
import time
from pathlib import Path

from cli_contract import assert_contract, run_cli

ROOT = Path(__file__).resolve().parents[2]


def test_all_branches_of_a_general_6r_answers_at_once():
    """ik --all-branches on the xArm 6 (8 solutions, 8 values a joint) built its 262,136
    arm combinations one by one before saying they were too many to list: 16 s of CPU a
    pose, a hang to a grader's timeout."""
    argv = ["ik", "xarm6", "--from-q", "-156 -5.496 -71.87 173.2 170.9 70.64",
            "--all-branches", "--json"]
    t0 = time.perf_counter()
    status, out, err = run_cli(argv)
    took = time.perf_counter() - t0
    assert_contract(status, out, err, argv)
    doc = json.loads(out)
    assert doc["rejected"] == [] and "too many to list" in doc["rejected_note"]
    assert took < 8, f"{took:.1f} s"


def test_explain_on_a_robot_only_nearly_of_its_family(tmp_path):
    """ik --explain on a PUMA 560 whose wrist axes miss each other by 0.1 mm (a datasheet
    rounded, a calibrated model): exit status 3 (IndexError) for every pose."""
    text = (ROOT / "robots" / "puma560.yaml").read_text()
    old = "- {name: q5, type: revolute, alpha: -90, a: 0,    d: 0,"
    assert old in text
    (tmp_path / "arm.yaml").write_text(text.replace(old, old.replace("d: 0,", "d: 0.0001,")))
    argv = ["ik", str(tmp_path / "arm.yaml"), "--from-q", "-8.98 43.17 83.11 -25.04 48.54 58.39",
            "--explain", "--json"]
    status, out, err = run_cli(argv)
    assert_contract(status, out, err, argv)
    doc = json.loads(out)
    assert status in (0, 1) and len(doc["solutions"]) == 8
    assert all(s["trace"] for s in doc["solutions"])


MARK = "KCNOTTHELINE_m4w9"        # written on a line no message may show


def _shows_only_its_line(err: str, text: str, name: str) -> None:
    """``err`` names a line of ``name`` and shows nothing of the file's other lines (the
    marker sits on a line that is not the one named)."""
    assert err.count("\n") == 1 and MARK not in err, err
    line = int(err.split(f"{name}:", 1)[1].split(":", 1)[0])
    assert MARK not in text.splitlines()[line - 1], (line, err)


def test_a_name_over_two_lines_is_not_quoted_in_a_robot_file(tmp_path):
    """A joint name written over two lines (a plain YAML scalar continued) was quoted in the
    error of a later line of the joint, showing the other lines."""
    text = ("name: arm\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
            f"  - name: q1\n      {MARK}\n    type: revolute\n    alpha: bad\n    a: 0.3\n"
            "    d: 0\n    theta: 0\n")
    (tmp_path / "arm.yaml").write_text(text)
    argv = ["robots", "validate", str(tmp_path / "arm.yaml")]
    status, out, err = run_cli(argv)
    assert_contract(status, out, err, argv)
    assert status == 2 and ":8: joint 1:" in err
    _shows_only_its_line(err, text, "arm.yaml")


def test_an_item_id_over_two_lines_in_a_sheet(tmp_path):
    """The same for a homework sheet's item id, quoted in the errors of its item (now named
    there by the line alone; such an id is still an id, sanitised where it is written)."""
    text = (f"title: t\nrobot: planar_3r\nitems:\n  - id: one\n      {MARK}\n    kind: fk\n"
            "    q: [1, 2, bad]\n    answer: {position: [1, 2, 0]}\n")
    (tmp_path / "sheet.yaml").write_text(text)
    argv = ["check", str(tmp_path / "sheet.yaml")]
    status, out, err = run_cli(argv)
    assert status == 2 and "sheet.yaml:7: 'q'" in err
    _shows_only_its_line(err, text, "sheet.yaml")


URDF = """<?xml version="1.0"?>
<robot name="two_link">
  <link name="base_link"/>
  <link name="upper_arm"/>
  <link name="forearm"/>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="upper_arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-2.5" upper="2.5" effort="10" velocity="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper_arm"/><child link="forearm"/>
    <origin xyz="0.4 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2.5" upper="2.5" effort="10" velocity="1"/>
  </joint>
</robot>
"""


def test_urdf_names_and_values_over_lines(tmp_path):
    """URDF names over two lines were quoted whole (a joint's name, the link it names), and
    a lone CR, a line break to XML and to expat's line numbers, was not one to kincalc's
    attribute lines: the value was quoted with the next line, an attribute after it named
    on the tag's line."""
    cases = [("elbow", f'elbow\n{MARK}', "<joint name> runs on over lines 11-12"),
             ('child link="forearm"', f'child link="fore\n{MARK}"', "<child link> runs on"),
             ('xyz="0.4 0 0"', f'xyz="abc\r{MARK} 0"', "a value over lines 13-14"),
             ('<origin xyz="0.4 0 0"/>', '<origin\rxyz="abc"/>', "urdf:14: <origin xyz>")]
    for old, new, want in cases:
        text = URDF.replace(old, new, 1)
        f = tmp_path / "a.urdf"
        f.write_bytes(text.encode())
        argv = ["robots", "validate", str(f)]
        status, out, err = run_cli(argv)
        assert status == 2 and want in err, (new, err)
        assert err.count("\n") == 1 and MARK not in err, err


def test_a_pose_file_with_nan_beside_its_matrix(tmp_path):
    """A --pose JSON object was read by its T only: a NaN elsewhere in it was accepted,
    where every number of a pose file must be finite (an ik --batch record refuses it)."""
    (tmp_path / "pose.json").write_text(
        '{"T": [[1,0,0,0.3],[0,1,0,0],[0,0,1,0.2],[0,0,0,1]], "position": [NaN]}\n')
    argv = ["ik", "puma560", "--pose", str(tmp_path / "pose.json"), "--json"]
    status, out, err = run_cli(argv)
    assert_contract(status, out, err, argv)
    assert status == 2 and "NaN is not a finite number" in err


def test_a_file_name_with_an_escape_sequence_reaches_no_terminal_raw(tmp_path):
    """A student who named a sheet ``bad<ESC>[31m.yaml`` recoloured the grader's terminal:
    the error lines (``check``, a missing robot file) and ``robots validate``'s "ok" line
    echoed file names raw. Their control characters are shown as U+FFFD now."""
    esc = "\x1b[2J"
    robot = tmp_path / f"ok{esc}name.yaml"
    robot.write_text((ROOT / "robots" / "puma560.yaml").read_text())
    sheet = tmp_path / f"bad{esc}.yaml"
    sheet.write_text("robot: puma560\nitems: [\n")
    for argv, status in ((["robots", "validate", robot], 0), (["check", sheet], 2),
                         (["fk", tmp_path / f"none{esc}.yaml", "0"], 2)):
        got, out, err = run_cli(argv)
        assert got == status, (argv, err)
        text = out + err
        assert "\x1b" not in text and "\ufffd[2J" in text, text


def test_a_very_long_robot_file_name_is_cut_in_the_error_line():
    """A 5,000-character path that names no file was echoed whole: a 5,077-character error
    line. Cut to 300 characters now, with the name's length."""
    path = "/nonexist/" + "a" * 5000 + ".yaml"
    status, out, err = run_cli(["fk", path, "0"])
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and len(err) < 500 and "(5015 characters)" in err
