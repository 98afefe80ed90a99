"""``kincalc convert`` and ``kincalc compare``, and the robot-file writer behind convert.

Every bundled robot is converted to every convention, written, read back and
compared with the original, in Python and through the CLI.
"""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from kincalc.cli.main import main
from kincalc.conventions import convert
from kincalc.analysis.compare import match
from kincalc.conventions.library import bundled_names, load
from kincalc.model import Joint, Robot
from kincalc.conventions.reader import parse_robot_text
from kincalc.conventions.writer import dump_robot, num

ROBOTS = bundled_names()
CONVENTIONS = ["dh", "mdh", "poe"]


def run(capsys, *argv):
    capsys.readouterr()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


# --- the writer ---------------------------------------------------------------------

@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("to", CONVENTIONS)
def test_every_robot_converts_and_reads_back_as_the_same_robot(name, to):
    robot = load(name)
    text = dump_robot(convert(robot, to))
    back = parse_robot_text(text, f"{name}->{to}")
    assert back.convention == to
    m = match(robot, back)
    assert m.same, m.reason
    assert [j.name for j in back.joints] == [j.name for j in robot.joints]
    assert (back.length_unit, back.angle_unit) == (robot.length_unit, robot.angle_unit)
    assert np.allclose(back.limits, robot.limits) and np.allclose(back.home, robot.home)
    assert back.parameters == robot.parameters
    if to != robot.convention:
        assert back.source.endswith("by kincalc convert)")
    else:   # unchanged: every value as it was (to rounding)
        assert back.source == robot.source
        for j, k in zip(robot.joints, back.joints):
            for f in ("alpha", "a", "d", "theta"):
                assert math.isclose(getattr(j, f), getattr(k, f), rel_tol=1e-12, abs_tol=1e-12)
            if to == "poe":
                assert np.allclose(j.axis, k.axis, atol=1e-12)
                assert np.allclose(j.point, k.point, atol=1e-12)
        assert np.allclose(back.base, robot.base, atol=1e-12)
        assert np.allclose(back.tool, robot.tool, atol=1e-12)
    # writing what was read gives the same text: the form is normalised
    assert dump_robot(back) == text


def test_parameter_names_move_with_their_values():
    text = dump_robot(convert(load("bk_scara_euler"), "dh"))
    rows = [line for line in text.splitlines() if line.startswith("  - {")]
    # modified DH a_{i-1} of rows 2 and 3 (l1, l2) become standard DH a_1, a_2
    assert "a: l1, d: h1," in rows[0]
    assert "alpha: 180, a: l2," in rows[1]
    assert "d: d4," in rows[3]
    back = convert(parse_robot_text(text), "mdh")
    again = dump_robot(back)
    assert "d: h1" in again and "a: l1" in again and "a: l2" in again and "d: d4" in again
    text = dump_robot(convert(load("adept_cobra600"), "mdh"))
    assert "a: l1, d: 0" in text and "a: l2" in text and "d: h1" in text


def test_an_expression_that_no_longer_gives_its_value_is_written_as_the_number():
    r = load("bk_rr")
    wrong = Robot(r.name, "mdh", (r.joints[0], Joint("theta2", "revolute", a=11.0)),
                  tool=r.tool, length_unit="unitless", parameters=r.parameters,
                  expressions=r.expressions)        # says a = l1 (10), holds 11
    text = dump_robot(wrong)
    assert "a: 11," in text and "a: l1" not in text


@pytest.mark.parametrize("value,text", [
    (90.00000000000001, "90"), (431.79999999999995, "431.8"), (6.123e-17, "0"),
    (-0.0, "0"), (0.1 + 0.2, "0.3"), (1 / 3, "0.33333333333333"), (-45.0, "-45"),
    (1e20, "1e+20"), (2.5e-7, "2.5e-07"), (1 + 3e-13, "1"),
    (0.5 + 3e-13, "0.5000000000003"), (-1e-13, "0"),
])
def test_numbers(value, text):
    assert num(value) == text
    assert abs(float(text) - value) <= 1e-12 * max(abs(value), 1)
    assert float(num(float(text))) == float(text)


def test_awkward_text_survives():
    title = 'A "robot": #1, with \\ backslash, tab\tand accents: Küçük'
    r = Robot("odd-name.v2", "dh", (Joint("no", "revolute", a=1.0),
                                    Joint("null", "prismatic", limits=(0.0, 0.5))),
              title=title, source="s " * 60, notes="line one\nline two",
              home=[0.1, 0.2])
    back = parse_robot_text(dump_robot(r))
    assert (back.name, back.title, back.notes) == (r.name, title, r.notes)
    assert back.source == r.source.strip() or back.source == r.source
    assert [j.name for j in back.joints] == ["no", "null"]
    assert match(r, back).same


def test_general_base_and_tool_are_written_exactly():
    from randrobots import random_robot
    rng = np.random.default_rng(5)
    for convention in CONVENTIONS:
        r = random_robot(rng, convention, n=4)
        back = parse_robot_text(dump_robot(r))
        assert np.allclose(back.base, r.base, atol=1e-12)
        # a poe file's tool is M · tool (the tool at q = 0): read back as M, tool = I
        assert np.allclose(back.written_tool, r.written_tool, atol=1e-12)
        if convention == "poe":
            assert np.allclose(back.M, r.M @ r.tool, atol=1e-12)
            assert np.allclose(back.tool, np.eye(4))
        else:
            assert back.M is None and np.allclose(back.tool, r.tool, atol=1e-12)
        q = rng.uniform(-3, 3, (50, r.dof))
        assert np.allclose(back.fk(q), r.fk(q), atol=1e-12)
        assert match(r, back).same


#: lengths at the magnitude limit whose sum (a poe point, the tool) is beyond it
AT_THE_LIMIT = """name: big
convention: dh
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 0, a: 1e9, d: 0, theta: 0}
  - {name: q2, type: revolute, alpha: 0, a: 1, d: 0, theta: 0}
"""


def test_a_robot_that_would_not_read_back_is_not_written():
    """A dh robot with a = 1e9 (the largest number a robot file may hold) and another
    link: its poe tool is at 1e9 + 1, which the reader refuses. The writer wrote the file
    anyway (exit 0, a file kincalc cannot read); it now says which field is too large."""
    from kincalc.errors import InputError
    r = convert(parse_robot_text(AT_THE_LIMIT), "poe")
    with pytest.raises(InputError, match=r"big in poe cannot be written as a robot file: "
                                         r"'tool'.xyz\[0\] is too large"):
        dump_robot(r)
    # the dh form itself reads back
    assert match(parse_robot_text(dump_robot(parse_robot_text(AT_THE_LIMIT))),
                 parse_robot_text(AT_THE_LIMIT)).same


def test_cli_a_conversion_beyond_the_limit_is_one_line_and_no_file(capsys, tmp_path):
    (tmp_path / "big.yaml").write_text(AT_THE_LIMIT)
    out = tmp_path / "out.yaml"
    assert main(["convert", str(tmp_path / "big.yaml"), "--to", "poe", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot be written as a robot file" in err
    assert not out.exists()


# --- kincalc convert ------------------------------------------------------------------

@pytest.mark.parametrize("name", ROBOTS)
def test_cli_round_trip(name, capsys, tmp_path):
    for to in CONVENTIONS:
        code, out, err = run(capsys, "convert", name, "--to", to)
        assert code == 0, err
        f = tmp_path / f"{to}.yaml"
        f.write_text(out, encoding="utf-8")
        code, out, err = run(capsys, "compare", name, str(f))
        assert code == 0, out + err
        assert "same robot" in out


def test_output_file_is_not_overwritten_without_force(capsys, tmp_path):
    f = tmp_path / "out.yaml"
    assert run(capsys, "convert", "puma560", "--to", "mdh", "-o", str(f))[0] == 0
    first = f.read_text()
    assert "convention: mdh" in first
    code, out, err = run(capsys, "convert", "puma560", "--to", "poe", "-o", str(f))
    assert code == 2 and "exists; use --force" in err and f.read_text() == first
    code, out, err = run(capsys, "convert", "puma560", "--to", "poe", "-o", str(f), "--force")
    assert code == 0 and out == "" and "convention: poe" in f.read_text()
    assert os.listdir(tmp_path) == ["out.yaml"]          # no temporary file left behind
    code, _, err = run(capsys, "convert", "puma560", "--to", "poe", "-o", str(tmp_path))
    assert code == 2 and "is a folder" in err
    code, _, err = run(capsys, "convert", "puma560", "--to", "poe",
                       "-o", str(tmp_path / "no" / "such.yaml"))
    assert code == 2 and "does not exist" in err


def test_a_refused_conversion_writes_nothing(capsys, tmp_path):
    f = tmp_path / "out.yaml"
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\nconvention: poe\nunits: {length: m, angle: deg}\njoints: []\n")
    code, out, err = run(capsys, "convert", str(bad), "--to", "dh", "-o", str(f))
    assert code == 2 and not f.exists() and err.count("\n") == 1 and str(bad) in err


@pytest.mark.parametrize("argv,message", [
    (["convert", "puma560"], "Missing option '--to'"),
    (["convert", "puma560", "--to", "urdf"], "--to must be one of dh, mdh, poe"),
    (["convert", "no_such_robot", "--to", "dh"], "no robot named"),
])
def test_convert_bad_input(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


def test_same_convention_prints_the_robot_normalised(capsys):
    code, out, _ = run(capsys, "convert", "puma560", "--to", "dh")
    assert code == 0
    back = parse_robot_text(out)
    assert back.joints == load("puma560").joints
    assert "converted" not in back.source


# --- kincalc compare --------------------------------------------------------------

STUDENT = """name: rr_student
convention: dh
units: {length: unitless, angle: deg}
joints:
  - {name: t1, type: revolute, alpha: 180, a: 10, d: 0, theta: 90}
  - {name: t2, type: revolute, alpha: 180, a: 5, d: 0, theta: 0}
"""


@pytest.fixture
def student(tmp_path):
    f = tmp_path / "rr_student.yaml"
    f.write_text(STUDENT)
    return str(f)


def test_compare_json_contract(capsys, student):
    code, out, _ = run(capsys, "compare", "bk_rr", student, "--allow-offsets", "--json")
    assert code == 0 and out.count("\n") == 1
    doc = json.loads(out)
    for key in ("kincalc", "command", "robots", "units", "same", "position_error",
                "orientation_error", "worst_q", "offsets", "signs", "first_bad_joint",
                "reason", "samples", "seed", "allow_offsets"):
        assert key in doc
    assert doc["command"] == "compare" and doc["same"] is True
    assert [r["name"] for r in doc["robots"]] == ["bk_rr", "rr_student"]
    assert doc["robots"][1]["argument"] == student
    assert doc["offsets"] == [-90.0, 0.0] and doc["signs"] == [1, -1]
    assert doc["first_bad_joint"] is None
    assert doc["reason"] == "same robot up to joint offsets and signs (joints 1 and 2)"
    assert doc["explanation"][1] == ("joint 1 (theta1): candidate zero is at reference "
                                     "theta1 = 90 deg")
    assert doc["position_tolerance"] == 1.5e-05 and doc["length_scale"] == 15
    assert doc["base"] is None and doc["tool"] is None


def test_compare_units(capsys, student):
    _, out, _ = run(capsys, "compare", "bk_rr", student, "--allow-offsets", "--json", "--rad")
    doc = json.loads(out)
    assert doc["units"]["angle"] == "rad"
    assert math.isclose(doc["offsets"][0], -math.pi / 2, rel_tol=1e-12)
    m_doc = json.loads(run(capsys, "compare", "puma560", "ur5", "--json", "--unit", "mm")[1])
    m_doc_m = json.loads(run(capsys, "compare", "puma560", "ur5", "--json")[1])
    assert math.isclose(m_doc["position_error"], 1000 * m_doc_m["position_error"], rel_tol=1e-9)


def test_compare_different_robots_exit_1(capsys, student):
    code, out, err = run(capsys, "compare", "bk_rr", student, "--json")
    doc = json.loads(out)
    assert code == 1 and doc["same"] is False and doc["first_bad_joint"] == 2
    assert doc["reason"].startswith("joint 2 (theta2): its axis differs")
    assert doc["reason"].endswith("with joint offsets and sign changes allowed they are the "
                                  "same robot")
    code, out, _ = run(capsys, "compare", "puma560", "stanford_arm")
    assert code == 1 and "prismatic in the candidate" in out
    code, out, _ = run(capsys, "compare", "puma560", "adept_cobra600", "--json")
    doc = json.loads(out)
    assert code == 1 and doc["position_error"] is None and doc["worst_q"] is None


def test_compare_table_shows_the_json(capsys, student, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    code, out, _ = run(capsys, "compare", "bk_rr", student, "--allow-offsets")
    assert code == 0
    doc = json.loads(run(capsys, "compare", "bk_rr", student, "--allow-offsets", "--json")[1])
    assert "same robot   " in out and doc["reason"] in out
    assert "-90.0000  0.0000" in out and "+1  -1" in out
    for line in doc["explanation"][1:]:
        assert line.partition(": ")[2] in out
    assert "201 configurations" in out


def test_compare_free_frames(capsys, tmp_path):
    f = tmp_path / "moved.yaml"
    f.write_text(dump_robot(convert(load("puma560"), "poe")).replace(
        "tool: {xyz: [0.4521, -0.15005, 0.4318]}",
        "base: {xyz: [1, 2, 3], rpy: [0, 0, 30]}\ntool: {xyz: [0.4521, -0.15005, 0.5318]}"))
    assert run(capsys, "compare", "puma560", str(f))[0] == 1
    code, out, _ = run(capsys, "compare", "puma560", str(f), "--free-base", "--free-tool",
                       "--json")
    doc = json.loads(out)
    assert code == 0 and doc["same"]
    base, tool = np.array(doc["base"]), np.array(doc["tool"])
    assert np.allclose(base[:3, 3], [1, 2, 3]) and math.isclose(base[1, 0], 0.5)
    assert np.allclose(tool[:3, 3], [0, 0, 0.1])


@pytest.mark.parametrize("argv,message", [
    (["compare", "puma560"], "Missing argument"),
    (["compare", "puma560", "nope"], "no robot named 'nope'"),
    (["compare", "puma560", "ur5", "--samples", "0"], "--samples"),
    (["compare", "bk_rr", "bk_rr", "--unit", "mm"], "unitless"),
])
def test_compare_bad_input(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and message in err and err.count("\n") == 1


def test_absurd_lengths_are_refused_not_compared(tmp_path, capsys):
    # found in review: a planar 3R with a = 1e160 compared "the same" as one with a = 1
    # (the products of lengths overflowed); such files are now invalid
    f = tmp_path / "huge.yaml"
    f.write_text("name: huge\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                 "  - {name: q1, type: revolute, alpha: 0, a: 1e160, d: 0, theta: 0}\n")
    status = main(["compare", "planar_3r", str(f)])
    err = capsys.readouterr().err
    assert status == 2 and "huge.yaml:5" in err and "too large" in err


def test_a_number_written_reads_back_and_writes_as_itself():
    """xarm6's tool z, 112.000000459881 mm, wrote as 112.00000045988 the second time: a
    file rewritten must be unchanged."""
    rng = np.random.default_rng(8)
    values = np.concatenate([rng.uniform(-1, 1, 3000) * 10.0 ** rng.integers(-6, 6, 3000),
                             112.0 + rng.uniform(0, 1e-6, 2000), [112.000000459881]])
    for x in values:
        text = num(x)
        assert num(float(text)) == text, (x, text)
        assert abs(float(text) - x) <= 1e-13 * max(abs(x), 1e-300) + 1e-300 or \
            abs(x) < 1e-12
    assert num(112.00000045988099) == num(112.000000459881)


# --- axes a hair from parallel (found by an independent tester) ----------------------------

NEARLY_PARALLEL = """name: np3
convention: poe
units: {{length: m, angle: deg}}
joints:
  - {{name: q1, type: revolute, axis: [0, 0, 1], point: [0, 0, 0]}}
  - {{name: q2, type: revolute, axis: [{hair}, 0, 1], point: [0.5, 0, 0]}}
  - {{name: q3, type: revolute, axis: [0, 1, 0], point: [0.5, 0, 0.3]}}
tool: {{xyz: [0.9, 0, 0.3], rpy: [0, 0, 0]}}
"""


def test_axes_a_hair_from_parallel_are_not_converted_to_dh(tmp_path, capsys):
    """Axes 1 and 2 are 3e-9 rad apart and 0.5 m off: their common normal is 170,000 km away
    (they meet at z = -0.5 / 3e-9), and the DH offsets d that cancel there lose the tool's
    position to ~1e-8 m (by hand: the tool is at (0.9, 0, 0.3) at q = 0). Refused, naming
    the axes; the POE description and the robot's own DH tables are untouched."""
    from kincalc.errors import InputError
    text = NEARLY_PARALLEL.format(hair=3e-9)
    robot = parse_robot_text(text)
    assert np.allclose(robot.fk(np.zeros(3))[:3, 3], [0.9, 0, 0.3], atol=1e-15)
    for to in ("dh", "mdh"):
        with pytest.raises(InputError, match=r"np3 cannot be written in " + to + r" to full "
                           r"accuracy: .* \(the axes of joints 1 and 2 are 3e-09 rad from parallel"):
            convert(robot, to)
    (tmp_path / "np3.yaml").write_text(text)
    out = tmp_path / "np3_dh.yaml"
    assert main(["convert", str(tmp_path / "np3.yaml"), "--to", "dh", "-o", str(out)]) == 2
    assert capsys.readouterr().err.count("\n") == 1 and not out.exists()
    # robots show keeps the screws and says why there is no DH table
    assert main(["robots", "show", str(tmp_path / "np3.yaml"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)["robot"]
    assert doc["dh"] is None and "3e-09 rad from parallel" in doc["dh_note"]
    assert main(["robots", "show", str(tmp_path / "np3.yaml")]) == 0
    assert "no standard DH table of these axes" in capsys.readouterr().out


def test_the_refusal_states_the_tool_motion_in_the_robot_file_unit():
    """The same robot in metres, centimetres and millimetres moves its tool by the same
    length: the message's figure times the unit is one length (it was divided by the unit's
    square: 2.96e-12 mm for 2.96e-9 m)."""
    import re
    from kincalc.errors import InputError
    moved = {}
    for unit, k in (("m", 1.0), ("cm", 100.0), ("mm", 1000.0)):
        text = NEARLY_PARALLEL.format(hair=3e-9).replace("length: m", f"length: {unit}")
        text = re.sub(r"[0-9]+\.[0-9]+", lambda m: repr(float(m.group()) * k), text)
        with pytest.raises(InputError) as err:
            convert(parse_robot_text(text), "dh")
        figure = re.search(r"move by up to (\S+) (\w+)", str(err.value))
        assert figure.group(2) == unit
        moved[unit] = float(figure.group(1)) / k
    assert 1e-10 < moved["m"] < 1e-6
    assert np.isclose(moved["cm"], moved["m"], rtol=0.02)
    assert np.isclose(moved["mm"], moved["m"], rtol=0.02)


@pytest.mark.parametrize("to", ["dh", "mdh"])
def test_axes_1e6_from_parallel_convert_to_full_accuracy(to):
    """The same axes 1e-6 rad apart: their common normal is 500 km away, at z = -0.5 / 1e-6
    on axis 1, and the table's offsets are -500000 and +500000.3 m (by hand: the normal's
    foot on axis 2 is 0.3 m above axis 3's). Taking the axes' directions for unit vectors
    (the DH frames' 1 - (u.v)^2) had put them 66 m off, the tool 6.7e-5 m off, and refused
    this robot. The converted robot's FK is the POE robot's at random configurations."""
    robot = parse_robot_text(NEARLY_PARALLEL.format(hair=1e-6))
    out = convert(robot, to)
    d = sorted(j.d for j in out.joints)
    assert d[0] == pytest.approx(-500000.0, abs=1e-3) and d[-1] == pytest.approx(500000.3, abs=1e-3)
    Q = np.random.default_rng(3).uniform(-np.pi, np.pi, (200, 3))
    A, B = robot.fk(Q), out.fk(Q)
    assert np.abs(A[:, :3, 3] - B[:, :3, 3]).max() < 1e-9
    assert np.abs(A[:, :3, :3] - B[:, :3, :3]).max() < 1e-9


@pytest.mark.parametrize("to", ["dh", "mdh"])
@pytest.mark.parametrize("hair", [1e-6, 1e-7])
def test_axes_a_hair_from_parallel_are_written_to_full_accuracy(to, hair):
    """The converted robot was right, the file written of it was not: its numbers were
    shortened to 1e-12 of their size, and the two offsets of 5e5 m that cancel then moved the
    tool by 1.7e-7 m (hostile-input campaign). The written text read back has the POE
    robot's FK to 1e-9 m."""
    robot = parse_robot_text(NEARLY_PARALLEL.format(hair=hair))
    back = parse_robot_text(dump_robot(convert(robot, to)))
    Q = np.random.default_rng(4).uniform(-np.pi, np.pi, (200, 3))
    A, B = robot.fk(Q), back.fk(Q)
    assert np.abs(A[:, :3, 3] - B[:, :3, 3]).max() < 1e-9
    assert np.abs(A[:, :3, :3] - B[:, :3, :3]).max() < 1e-9
    # an ordinary robot's file keeps its short numbers (no 13 digits after a point)
    import re
    assert re.search(r"\d\.\d{13}", dump_robot(convert(load("puma560"), "poe"))) is None


def test_compare_tolerance_is_not_widened_by_offsets_that_cancel(tmp_path, capsys):
    """A planar 2R (a = 0.4, 0.3) against the same with d = 400000 and -399999.5 on its
    parallel axes: by hand the tool is 0.5 m higher. The tolerance was 1e-6 of the larger
    characteristic length, 0.8 m, and the two were 'the same robot'."""
    two = "name: {n}\nconvention: dh\nunits: {{length: m, angle: deg}}\njoints:\n" \
          "  - {{name: q1, type: revolute, alpha: 0, a: 0.4, d: {d1}, theta: 0}}\n" \
          "  - {{name: q2, type: revolute, alpha: 0, a: 0.3, d: {d2}, theta: 0}}\n"
    (tmp_path / "a.yaml").write_text(two.format(n="a", d1=0, d2=0))
    (tmp_path / "b.yaml").write_text(two.format(n="b", d1=400000, d2=-399999.5))
    b = parse_robot_text(two.format(n="b", d1=400000, d2=-399999.5))
    assert np.allclose(b.fk(np.zeros(2))[:3, 3], [0.7, 0, 0.5])
    assert main(["compare", str(tmp_path / "a.yaml"), str(tmp_path / "b.yaml"), "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["same"] is False


def test_a_converted_file_kincalc_would_not_read_is_not_written(tmp_path, capsys):
    """A 700 KB title of quotes, each escaped when written, made a 1.4 MB file that kincalc
    then refused to read (hostile-input campaign): the conversion is refused instead."""
    src = tmp_path / "q.yaml"
    src.write_text("name: h\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                   "  - {name: q1, type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n"
                   "title: '" + '"' * 700000 + "'\n")
    out = tmp_path / "out.yaml"
    assert main(["convert", str(src), "--to", "poe", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "would be 1400" in err and "MAX_FILE_BYTES" in err
    assert not out.exists()

