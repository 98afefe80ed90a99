"""The CLI as users and scripts see it: JSON contract, tables, units, exit codes."""

import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from kincalc.cli.main import main

ROBOTS = os.path.join(os.path.dirname(__file__), os.pardir, os.pardir, "robots")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def run_json(capsys, *argv):
    code, out, err = run(capsys, *argv, "--json")
    assert code == 0, err
    assert out.count("\n") == 1, "exactly one JSON document"
    return json.loads(out)


def test_fk_json_contract(capsys):
    doc = run_json(capsys, "fk", "puma560", "0", "-45", "180", "0", "45", "0")
    for key in ("kincalc", "command", "robot", "units", "q", "T", "position", "orientation", "tcv"):
        assert key in doc
    assert doc["command"] == "fk"
    assert doc["robot"]["dof"] == 6 and doc["robot"]["joint_types"] == ["revolute"] * 6
    assert doc["units"] == {"angle": "deg", "length": "m"}
    assert doc["q"] == [0, -45, 180, 0, 45, 0]
    for key in ("matrix", "rpy", "euler_zyz", "euler_xyz", "quaternion", "axis_angle",
                "rotation_vector"):
        assert key in doc["orientation"]
    T = np.array(doc["T"])
    assert np.allclose(T[:3, 3], doc["position"])
    q = np.array(doc["orientation"]["quaternion"])
    assert math.isclose(np.linalg.norm(q), 1.0) and q[0] >= 0


def test_negative_values_need_no_double_dash(capsys):
    doc = run_json(capsys, "fk", "bk_rr", "-8.2", "60")
    assert doc["q"] == [-8.2, 60]
    assert np.allclose(doc["position"][:2], [12.99, 2.5], atol=0.02)


def test_rad_and_unit_options(capsys):
    deg = run_json(capsys, "fk", "puma560", "10", "20", "30", "40", "50", "60")
    rad = run_json(capsys, "fk", "puma560", *[str(math.radians(v)) for v in (10, 20, 30, 40, 50, 60)],
                   "--rad", "--unit", "mm")
    assert rad["units"] == {"angle": "rad", "length": "mm"}
    assert np.allclose(np.array(rad["position"]) / 1000, deg["position"], atol=1e-12)
    assert np.allclose(np.radians(deg["orientation"]["rpy"]), rad["orientation"]["rpy"])


def test_prismatic_joint_in_display_length_unit(capsys):
    m = run_json(capsys, "fk", "fer_rrpr", "90", "90", "0.2", "0")
    mm = run_json(capsys, "fk", "fer_rrpr", "90", "90", "200", "0", "--unit", "mm")
    assert np.allclose(m["position"], [0, 0.3, 0.5], atol=1e-12)
    assert np.allclose(mm["position"], [0, 300, 500], atol=1e-9)
    assert mm["q"] == [90, 90, 200, 0]


def test_home_configuration_when_no_joints_given(capsys):
    doc = run_json(capsys, "fk", "bk_rr")
    assert doc["q"] == [30, -60]


def test_tcv_matches_the_homework_formula(capsys):
    doc = run_json(capsys, "fk", "fer_rrpr", "30", "40", "0.25", "57")
    w = np.array(doc["tcv"])
    T = np.array(doc["T"])
    assert np.allclose(w[:3], T[:3, 3])
    assert np.allclose(w[3:], math.exp(math.radians(57) / math.pi) * T[:3, 2])
    # homework eq. (2-4): q4 = pi/2 ln(w4^2 + w5^2 + w6^2)
    assert math.isclose(math.pi / 2 * math.log(np.sum(w[3:] ** 2)), math.radians(57))


def test_frames_json(capsys):
    doc = run_json(capsys, "fk", "bk_6r", "10", "20", "30", "40", "50", "60", "--frames")
    frames = doc["frames"]
    assert len(frames) == 6
    acc = np.eye(4)
    for f in frames:
        acc = acc @ np.array(f["link"])
        assert np.allclose(acc, f["T"])
    assert np.allclose(np.array(doc["base"]) @ acc @ np.array(doc["tool"]), doc["T"])


def test_jacobian_json_contract(capsys):
    doc = run_json(capsys, "jacobian", "puma560", "0", "45", "180", "0", "0", "0")
    for key in ("q", "frame", "J", "singular_values", "rank", "manipulability", "condition",
                "singular", "rows"):
        assert key in doc
    assert doc["rows"] == ["vx", "vy", "vz", "wx", "wy", "wz"]
    assert doc["singular"] is True and doc["rank"] == 5
    assert "wrist" in doc["singularity"]["kinds"]
    assert doc["condition"] is None
    doc = run_json(capsys, "jacobian", "puma560", "0", "45", "180", "0", "30", "0",
                   "--frame", "tool", "--analytic", "rpy")
    assert doc["frame"] == "tool" and doc["singular"] is False
    assert doc["analytic"]["angles"] == "rpy" and len(doc["analytic"]["J"]) == 6


def test_jacobian_units_scale_linear_rows(capsys):
    m = run_json(capsys, "jacobian", "puma560", "10", "20", "30", "40", "50", "60")
    mm = run_json(capsys, "jacobian", "puma560", "10", "20", "30", "40", "50", "60", "--unit", "mm")
    Jm, Jmm = np.array(m["J"]), np.array(mm["J"])
    assert np.allclose(Jmm[:3], 1000 * Jm[:3]) and np.allclose(Jmm[3:], Jm[3:])


def leaves(doc):
    if isinstance(doc, dict):
        for v in doc.values():
            yield from leaves(v)
    elif isinstance(doc, list):
        for v in doc:
            yield from leaves(v)
    else:
        yield doc


@pytest.mark.parametrize("argv", [
    ["fk", "puma560", "10", "-20", "30", "40", "50", "60"],
    ["fk", "ur5", "10", "-20", "30", "40", "50", "60", "--frames"],
    ["jacobian", "puma560", "10", "-20", "30", "40", "50", "60"],
])
def test_every_json_number_appears_in_the_table(capsys, argv):
    doc = run_json(capsys, *argv, "--precision", "4")
    code, table, err = run(capsys, *argv, "--precision", "4")
    assert code == 0 and err == ""
    assert "\x1b[" not in table, "no colour when stdout is not a terminal"
    shown = {float(x) for x in re.findall(r"-?\d+\.\d+", table)}
    for leaf in leaves({k: v for k, v in doc.items() if k not in ("kincalc", "robot", "units",
                                                               "length_scale")}):
        if isinstance(leaf, float) and not isinstance(leaf, bool):
            assert any(abs(round(leaf, 4) - x) < 1.5e-4 for x in shown), leaf


def test_robots_list_of_a_family_that_does_not_exist_says_so(capsys):
    """A mistyped family is an error naming the families (it printed an empty table, exit 0);
    one no bundled robot has is an empty list."""
    code, out, err = run(capsys, "robots", "list", "--family", "spherical-wirst")
    assert code == 2 and "spherical-wirst" in err and "spherical-wrist" in err
    assert len(err.strip().splitlines()) == 1
    doc = run_json(capsys, "robots", "list", "--family", "three-parallel-offset")
    assert doc["robots"] == []


def test_robots_list_and_show(capsys):
    doc = run_json(capsys, "robots", "list")
    names = [r["name"] for r in doc["robots"]]
    assert "puma560" in names and "bk_rr" in names
    assert not [r for r in doc["robots"] if "error" in r]
    show = run_json(capsys, "robots", "show", "puma560_mdh" if "puma560_mdh" in names else "bk_6r")
    assert show["robot"]["convention"] == "mdh"
    assert {"alpha", "a", "d", "theta"} <= set(show["robot"]["joints"][0])
    code, table, _ = run(capsys, "robots", "show", "bk_6r")
    assert code == 0 and "α_{i-1}" in table and "a_{i-1}" in table
    code, table, _ = run(capsys, "robots", "show", "fer_rrpr")
    assert "θ_i" in table and "q3" in table


def test_path_works_where_a_name_does(capsys, tmp_path):
    src = open(os.path.join(ROBOTS, "bk_rr.yaml"), encoding="utf-8").read()
    f = tmp_path / "my_arm.yaml"
    f.write_text(src)
    doc = run_json(capsys, "fk", str(f), "30", "-60")
    assert np.allclose(doc["position"][:2], [12.99, 2.5], atol=0.02)
    code, out, err = run(capsys, "robots", "validate", str(f))
    assert code == 0 and "ok" in out


def test_version_and_help_are_quick_to_reach(capsys):
    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.startswith("kincalc ")
    code, out, _ = run(capsys, "--help")
    assert code == 0 and "fk" in out and "jacobian" in out and "robots" in out


def test_cli_import_is_light():
    """`kincalc --help` must not import numpy, yaml or rich (start-up time)."""
    code = ("import sys; from kincalc.cli.main import main; "
            "import contextlib, io\n"
            "with contextlib.redirect_stdout(io.StringIO()): main(['--help'])\n"
            "print(sorted(m for m in ('numpy', 'yaml', 'rich', 'pydantic') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout


def test_help_and_version_import_no_command_module():
    """The commands are built on first use: --help and --version import none of them,
    and a command imports its own module only."""
    code = ("import sys; from kincalc.cli.main import main; "
            "import contextlib, io\n"
            "for args in (['--help'], ['--version'], ['compare', '--help']):\n"
            "    with contextlib.redirect_stdout(io.StringIO()): main(args)\n"
            "    print(sorted(m.split('.')[-1] for m in sys.modules\n"
            "                 if m.startswith('kincalc.cli.') and m not in\n"
            "                 ('kincalc.cli.main', 'kincalc.cli.common')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split("\n")
    assert out[:3] == ["[]", "[]", "['compare']"], out


def test_closed_form_ik_imports_only_its_path():
    """`kincalc ik` on a closed-form robot, solutions found, imports none of the modules
    of other answers (start-up: benchmarks/startup.py): the numerical solver, the nearest
    reachable point, the cross combinations (--all-branches), the free joints of a
    position target, the Newton polish, general 6R, the swivel, batches and plots."""
    code = ("import sys, contextlib, io\nfrom kincalc.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    main(['ik', 'puma560', '--from-q', '0 -45 180 0 45 0', '--json'])\n"
            "print(sorted(m for m in sys.modules if m.startswith('kincalc.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120).stdout
    lazy = ["kincalc.ik.numeric", "kincalc.ik.nearest", "kincalc.ik.combinations",
            "kincalc.ik.free_joints", "kincalc.ik.newton", "kincalc.ik.general6r",
            "kincalc.ik.swivel", "kincalc.cli.batch", "kincalc.analysis.plot",
            "kincalc.analysis.explain", "kincalc.analysis.redundancy"]
    loaded = eval(out)
    assert "kincalc.ik.solve" in loaded, out
    assert [m for m in lazy if m in loaded] == [], out


def test_command_table_short_help_is_each_commands_own():
    """kincalc --help lists COMMANDS' short help without importing the commands; each
    must be the first paragraph of the command's docstring (what click would show)."""
    import importlib
    import inspect

    import typer

    from kincalc.cli.main import COMMANDS
    for name, (module, attr, _, text) in COMMANDS.items():
        target = getattr(importlib.import_module(f"kincalc.cli.{module}"), attr)
        doc = target.info.help if isinstance(target, typer.Typer) else inspect.getdoc(target)
        assert " ".join(text.split()) == " ".join(doc.split("\n\n")[0].split()), name


def test_unknown_command_points_to_the_main_help(capsys):
    code, _, err = run(capsys, "ik2", "puma560")
    assert code == 2 and err.strip() == ("kincalc: error: No such command 'ik2'. "
                                         "Did you mean 'ik'? (see 'kincalc --help')")


def test_no_color_env(capsys, monkeypatch):
    monkeypatch.setenv("NO_COLOR", "1")
    code, out, _ = run(capsys, "fk", "bk_rr", "30", "-60")
    assert code == 0 and "\x1b[" not in out


def test_internal_errors_exit_3(capsys, monkeypatch):
    import kincalc.analysis.reports as an

    def boom(*a, **k):
        raise RuntimeError("synthetic failure")
    monkeypatch.setattr(an, "fk_report", boom)
    code, out, err = run(capsys, "fk", "bk_rr", "1", "2")
    assert code == 3 and "bug" in err and "--debug" in err and err.count("\n") == 1


def test_ik_json_contract_and_exit_status(capsys):
    doc = run_json(capsys, "ik", "puma560", "--from-q", "10 -30 150 25 40 35")
    for key in ("target", "reachable", "method", "solutions", "reason", "count"):
        assert key in doc
    assert doc["reachable"] is True and doc["count"] == len(doc["solutions"]) >= 1
    s = doc["solutions"][0]
    for key in ("q", "branch", "residual", "within_limits", "violations", "singular"):
        assert key in s
    # q3 = 150 deg is outside the PUMA's limits [-225, 45]; the same joint value is -210
    assert any(np.allclose((np.array(x["q"]) - [10, -30, 150, 25, 40, 35] + 180) % 360 - 180, 0,
                           atol=1e-6) for x in doc["solutions"])
    assert any(np.allclose(x["q"], [10, -30, -210, 25, 40, 35], atol=1e-6) for x in doc["solutions"])
    code, out, err = run(capsys, "ik", "puma560", "--xyz", "3", "0", "0", "--rpy", "0", "0", "0",
                         "--json")
    assert code == 1 and json.loads(out)["reachable"] is False


def test_ik_pose_options_agree(capsys, tmp_path):
    from kincalc import spatial as sp
    T = np.array(run_json(capsys, "fk", "puma560", "10", "-30", "150", "25", "40", "35")["T"])
    R = T[:3, :3]
    xyz = [str(v) for v in T[:3, 3]]
    ways = {
        "rpy": ["--rpy", *map(str, np.degrees(sp.rpy_from_matrix(R)))],
        "zyz": ["--euler-zyz", *map(str, np.degrees(sp.euler_zyz_from_matrix(R)))],
        "xyz": ["--euler-xyz", *map(str, np.degrees(sp.euler_xyz_from_matrix(R)))],
        "quat": ["--quat", *map(str, sp.quaternion_from_matrix(R))],
        "matrix": ["--matrix", *map(str, R.ravel())],
    }
    axis, ang = sp.axis_angle_from_matrix(R)
    ways["axis"] = ["--axis-angle", *map(str, axis), str(np.degrees(ang))]
    counts = set()
    for name, opt in ways.items():
        doc = run_json(capsys, "ik", "puma560", "--xyz", *xyz, *opt)
        counts.add(doc["count"])
        assert np.allclose(doc["target"]["T"], T, atol=1e-9), name
    pose = tmp_path / "pose.txt"
    pose.write_text("\n".join(" ".join(map(str, row)) for row in T))
    doc = run_json(capsys, "ik", "puma560", "--pose", str(pose))
    counts.add(doc["count"])
    assert len(counts) == 1


def test_a_pose_file_with_a_byte_order_mark_and_a_bad_word(capsys, tmp_path):
    # a file that starts with a UTF-8 byte-order mark was refused (robot files, sheets and
    # batches take one); an error never named the line or the word at fault
    T = np.array(run_json(capsys, "fk", "puma560", "10", "-30", "150", "25", "40", "35")["T"])
    text = "\n".join(" ".join(map(repr, row)) for row in T.tolist())
    pose = tmp_path / "pose.txt"
    pose.write_bytes(b"\xef\xbb\xbf" + text.encode())
    doc = run_json(capsys, "ik", "puma560", "--pose", str(pose))
    assert np.allclose(doc["target"]["T"], T, atol=1e-12)
    for bad in ("0.4m", "0x1", "\u22121", "1_0"):
        pose.write_text(text.replace(repr(T[1, 3].item()), bad, 1))
        code, out, err = run(capsys, "ik", "puma560", "--pose", str(pose))
        assert code == 2 and out == "" and err.count("\n") == 1
        assert f"--pose {pose}: line 2: {bad!r} is not a number" in err, err


def test_a_json_pose_document_is_read_in_its_own_length_unit(capsys, tmp_path):
    # `fk --json --unit m | ik --pose -` in a robot's mm read the metres as mm: a target
    # 0.8 mm from the base, "reachable", none of its solutions the joints fk was given
    q = [10, -40, 30, 20, 30, 40]
    T_m = np.array(run_json(capsys, "fk", "puma560", *map(str, q), "--unit", "m")["T"])
    for unit, scale in (("m", 1.0), ("cm", 100.0), ("mm", 1000.0), ("in", 1 / 0.0254)):
        doc = run_json(capsys, "fk", "puma560", *map(str, q), "--unit", unit)
        pose = tmp_path / f"fk_{unit}.json"
        pose.write_text(json.dumps(doc))
        for given in ("mm", "m"):
            got = run_json(capsys, "ik", "puma560", "--pose", str(pose), "--unit", given)
            # the target, in the ik command's unit, is the pose fk printed, in its own
            k = {"mm": 1000.0, "m": 1.0}[given]
            assert np.allclose(np.array(got["target"]["T"])[:3, 3], T_m[:3, 3] * k,
                               rtol=1e-9), (unit, given)
            assert any(np.allclose(s["q"], q, atol=1e-6) for s in got["solutions"]), (unit, given)
        assert np.allclose(np.array(doc["T"])[:3, 3], T_m[:3, 3] * scale, rtol=1e-9)
    # an ik document's target is read alike; a unit kincalc does not know is refused
    doc = run_json(capsys, "ik", "puma560", "--from-q", " ".join(map(str, q)), "--unit", "cm")
    pose = tmp_path / "ik_cm.json"
    pose.write_text(json.dumps(doc))
    got = run_json(capsys, "ik", "puma560", "--pose", str(pose), "--unit", "m")
    assert np.allclose(np.array(got["target"]["T"])[:3, 3], T_m[:3, 3], rtol=1e-9)
    pose.write_text(json.dumps({"units": {"length": "furlong"}, "T": np.eye(4).tolist()}))
    code, out, err = run(capsys, "ik", "puma560", "--pose", str(pose))
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "units.length 'furlong' is not a length unit" in err, err


def test_ik_tcv_option(capsys):
    w = run_json(capsys, "fk", "fer_rrpr", "30", "50", "0.25", "40")["tcv"]
    doc = run_json(capsys, "ik", "fer_rrpr", "--tcv", *map(str, w))
    assert any(np.allclose(s["q"], [30, 50, 0.25, 40], atol=1e-6) for s in doc["solutions"])


def test_precision_never_prints_more_digits_than_a_double_holds(capsys):
    """--precision 12 on a manipulability of 1.1e7 mm^3: 16 significant digits at most, the
    value the JSON holds (it printed 11184349.22705329023302)."""
    argv = ("jacobian", "puma560", "10", "20", "30", "40", "50", "60", "--unit", "mm")
    code, table, _ = run(capsys, *argv, "--precision", "12")
    doc = run_json(capsys, *argv)
    value = doc["manipulability"]
    line = next(x for x in table.splitlines() if x.strip().startswith("manipulability"))
    shown = line.split()[-1]
    assert code == 0 and len(shown.replace(".", "").lstrip("-0")) <= 16, shown
    assert float(shown) == pytest.approx(value, rel=1e-15)


def test_robots_list_names_what_to_type(tmp_path, monkeypatch, capsys):
    """A library file file_name.yaml holding 'name: other_name' was listed as other_name,
    which kincalc fk then did not know ("did you mean 'file_name'?"; hostile-input
    campaign): the list names what ROBOT takes, the file's name."""
    (tmp_path / "file_name.yaml").write_text(
        "name: other_name\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
        "  - {name: q1, type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n")
    monkeypatch.setenv("KINCALC_ROBOTS", str(tmp_path))
    doc = run_json(capsys, "robots", "list")
    assert [r["name"] for r in doc["robots"]] == ["file_name"]
    assert run_json(capsys, "fk", "file_name", "10")["q"] == [10.0]
