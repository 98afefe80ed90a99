"""The edges of the command line (issue 14, item 9): opposite flags, messages said once,
bundled names where files are checked, the bare 4x4 base/tool matrix, help that points at
what users have.

The flags and messages are tested through the CLI; the robot file form through
``parse_robot_text`` and ``robots validate`` (file, line and field in the message).
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from cli_contract import assert_contract, json_documents, run_cli


def run(*argv, stdin=b"", cwd=None):
    status, out, err = run_cli(list(argv), stdin, cwd)
    assert_contract(status, out, err, argv)
    return status, out, err


# --- 9. small ones ------------------------------------------------------------------------

@pytest.mark.parametrize("argv, first, second", [
    (["fk", "puma560", "--rad", "--deg"], "--rad", "--deg"),
    (["fk", "puma560", "--deg", "0", "0", "0", "0", "0", "0", "--rad"], "--deg", "--rad"),
    (["jacobian", "puma560", "--deg", "--rad", "--json"], "--deg", "--rad"),
    (["ik", "puma560", "--from-q", "0 0 0 0 0 0", "--rad", "--deg"], "--rad", "--deg"),
    (["robots", "show", "puma560", "--rad", "--deg"], "--rad", "--deg"),
    (["quiz", "bk_rr", "--seed", "1", "--deg", "--rad"], "--deg", "--rad"),
    (["compare", "bk_rr", "bk_rr", "--rad", "--deg"], "--rad", "--deg"),
    (["plot", "bk_rr", "--rad", "--deg", "-o", "x.png"], "--rad", "--deg"),
])
def test_deg_and_rad_together_are_refused(argv, first, second, tmp_path):
    status, out, err = run(*argv, cwd=str(tmp_path))
    assert status == 2 and out == ""
    cmd = " ".join(argv[:2] if argv[0] == "robots" else argv[:1])
    assert err == (f"kincalc {cmd}: error: {first} and {second} contradict each other; "
                   f"give one of them (see 'kincalc {cmd} --help')\n")


@pytest.mark.parametrize("argv", [
    ["fk", "puma560", "--rad", "--rad", "--json"],
    ["fk", "puma560", "--deg", "--deg", "--json"],
    ["fk", "bk_rr", "--unit", "--rad", "--deg"],          # '--rad' is --unit's value here
    ["fk", "bk_rr", "--batch", "-", "--deg"],
    ["fk", "bk_rr", "--deg", "--rad", "--help"],          # help first, as click does
])
def test_a_flag_repeated_or_consumed_as_a_value_is_no_contradiction(argv):
    status, _, err = run(*argv, stdin=b'{"q": [0, 0]}\n')
    assert "contradict" not in err


def test_the_flags_check_is_generic():
    """Every on/off flag pair of every command is checked (today --deg/--rad), and every
    option that takes one value (click kept the last of two silently)."""
    import click

    from kincalc.cli.main import _given_twice
    cmd = click.Command("t", params=[click.Option(["--color/--no-color"]),
                                     click.Option(["--name"]), click.Option(["--v/--q"]),
                                     click.Option(["--xyz"], nargs=3),
                                     click.Option(["--lock"], multiple=True)])
    clash = "{} and {} contradict each other; give one of them"
    assert _given_twice(cmd, ["--no-color", "--color"]) == clash.format("--no-color", "--color")
    assert _given_twice(cmd, ["--name", "--color", "--no-color"]) is None    # a value
    assert _given_twice(cmd, ["--color", "--", "--no-color"]) is None
    assert _given_twice(cmd, ["--q", "--color", "--v"]) == clash.format("--q", "--v")
    assert _given_twice(cmd, ["--color", "--color"]) is None                 # the same way
    twice = "--name is given twice; give it once"
    assert _given_twice(cmd, ["--name", "a", "--name", "b"]) == twice
    assert _given_twice(cmd, ["--name=a", "--v", "--name", "b"]) == twice
    assert _given_twice(cmd, ["--xyz", "1", "--name", "3", "--name"]) is None  # values
    assert _given_twice(cmd, ["--lock", "1=0", "--lock", "2=0"]) is None      # multiple


@pytest.mark.parametrize("argv, words", [
    (["convert", "puma560", "--to", "dh", "--to", "mdh"], "--to is given twice"),
    (["ik", "puma560", "--xyz", "0.4", "0.1", "0.3", "--rpy", "0", "0", "0", "--rpy", "1",
      "1", "1"], "--rpy is given twice"),
    (["fk", "puma560", "--unit", "mm", "--unit=m"], "--unit is given twice"),
])
def test_an_option_given_twice_is_refused(argv, words):
    # the last one won silently
    status, out, err = run(*argv)
    assert status == 2 and out == "" and words in err and err.count("\n") == 1


@pytest.mark.parametrize("argv, option", [
    (["fk", "puma560", "0", "0", "0", "0", "0", "0", "-j", "2"], "-j"),
    (["jacobian", "puma560", "--jobs=2"], "--jobs"),
    (["ik", "puma560", "--from-q", "0 0 0 0 0 0", "--input-format", "csv"], "--input-format"),
])
def test_a_batch_option_without_batch_is_refused(argv, option):
    # `-j 2` without --batch was read by nothing, silently
    status, out, err = run(*argv)
    assert status == 2 and out == "" and err.count("\n") == 1
    assert f"{option} applies to --batch runs only" in err
    status, out, _ = run(*argv[:2], "--batch", "-", *argv[-2:] if "=" not in argv[-1]
                         else argv[-1:], stdin=b"")
    assert status == 0 and out == ""                       # with --batch: read (no records)


@pytest.mark.parametrize("argv, path, near", [
    (["robots", "shw"], "kincalc robots", "'show'"),
    (["robots", "lst"], "kincalc robots", "'list'"),
    (["fk2"], "kincalc", "'fk'"),
    (["completon"], "kincalc", "'completion'"),
])
def test_did_you_mean_is_said_once(argv, path, near):
    status, out, err = run(*argv)
    assert status == 2 and out == ""
    assert err.count("Did you mean") == 1 and near in err, err
    assert err.startswith(f"{path}: error: No such command '{argv[-1]}'.")


def test_no_suggestion_when_nothing_is_near():
    status, _, err = run("robots", "zzzzzz")
    assert status == 2 and "Did you mean" not in err


def test_robots_validate_takes_bundled_names(tmp_path):
    status, out, err = run("robots", "validate", "puma560", "ur5_poe", cwd=str(tmp_path))
    assert status == 0, err
    assert out == ("ok: puma560: puma560, 6 joints, dh\n"
                   "ok: ur5_poe: ur5_poe, 6 joints, poe\n")
    status, out, err = run("robots", "validate", "puma560", "--json", cwd=str(tmp_path))
    assert json_documents(out)[0]["files"][0]["valid"] is True
    # a near miss is still an error, with the suggestion every command gives
    status, out, err = run_cli(["robots", "validate", "pum"], b"", str(tmp_path))
    assert status == 2 and "did you mean 'puma560'" in err


@pytest.mark.parametrize("command", [["robots", "validate"], ["fk"], ["robots", "show"]])
def test_a_name_too_long_for_a_file_is_no_robot(command, tmp_path):
    # found by the fuzz: is_file() raises ENAMETOOLONG instead of answering (exit 3)
    status, out, err = run(*command, "x" * 5000, cwd=str(tmp_path))
    assert status == 2 and out == "" and "no robot named" in err


def test_help_never_points_at_product_md(capsys):
    from test_man import PAGES, help_text

    class _MP:     # help_text wants monkeypatch for COLUMNS only
        def setenv(self, k, v):
            os.environ[k] = v
    saved = os.environ.get("COLUMNS")
    try:
        for path in PAGES:
            assert "PRODUCT" not in help_text(path, capsys, _MP()), " ".join(path)
    finally:
        if saved is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = saved


# --- 9. base and tool as a bare 4x4 matrix ---------------------------------------------------

ARM = """\
name: arm
convention: dh
units: {length: mm, angle: deg}
joints:
  - {name: q1, type: revolute, alpha: 90, a: 100, d: 200, theta: 0}
  - {name: q2, type: revolute, alpha: 0, a: 300, d: 0, theta: 0}
"""
ROT_Z90 = "[[0, -1, 0, 10], [1, 0, 0, 20], [0, 0, 1, 30], [0, 0, 0, 1]]"


@pytest.mark.parametrize("key", ["base", "tool"])
def test_bare_matrix_is_the_matrix_form(key):
    from kincalc.conventions.reader import parse_robot_text
    bare = parse_robot_text(ARM + f"{key}: {ROT_Z90}\n", "bare.yaml")
    keyed = parse_robot_text(ARM + f"{key}: {{matrix: {ROT_Z90}}}\n", "keyed.yaml")
    block = parse_robot_text(ARM + f"{key}:\n" + "".join(
        f"  - {row}\n" for row in json.loads(ROT_Z90)), "block.yaml")
    expected = np.array(json.loads(ROT_Z90), float)
    expected[:3, 3] /= 1000.0                             # mm -> m
    for r in (bare, keyed, block):
        np.testing.assert_allclose(getattr(r, key), expected, atol=1e-15)
    q = np.radians([20.0, -35.0])
    np.testing.assert_allclose(bare.fk(q), keyed.fk(q), atol=1e-15)


@pytest.mark.parametrize("text, expect", [
    ("base: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]",
     ("bare.yaml:7", "'base' (a 4x4 matrix)", "4 entries", "not 3")),
    ("tool: [[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
     ("'tool' (a 4x4 matrix) row 2", "4 entries", "not 3")),
    ("base: [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
     ("'base' (a 4x4 matrix)", "not a rotation")),
    ("base: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]",
     ("'base' (a 4x4 matrix)", "last row")),
    ("base: [[1, 0, 0, 1e300], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
     ("'base' (a 4x4 matrix) row 1", "too large")),
    ("base: [1, 0, 0, 0]", ("'base' (a 4x4 matrix) row 1", "must be a list")),
    ("base: 1", ("'base' must be a mapping",)),
])
def test_bare_matrix_errors_name_the_file_line_and_field(text, expect, tmp_path):
    (tmp_path / "bare.yaml").write_text(ARM + text + "\n")
    status, out, err = run("robots", "validate", "bare.yaml", cwd=str(tmp_path))
    assert status == 2 and out == ""
    for fragment in expect:
        assert fragment in err, err


@pytest.mark.parametrize("argv, words", [
    (["fk", "bk_rr", "--", "-5", "--frames"], "--frames comes after '--'"),
    (["jacobian", "bk_rr", "--", "-5", "--json"], "--json comes after '--'"),
    (["fk", "bk_rr", "--", "-5", "--framez"], "no such option: --framez (did you mean --frames?)"),
])
def test_an_option_after_double_dash_is_said_to_be_there(argv, words):
    """After '--' every word is a joint value; an option given there was refused as 'no
    such option: --frames (did you mean --frames?)' (an independent tester)."""
    status, out, err = run(*argv)
    assert status == 2 and out == "" and words in err, err


# --- joint values after --from-q and --near as words of their own -------------------------

@pytest.mark.parametrize("command", ["ik", "reach"])
def test_from_q_values_as_words_are_the_quoted_values(command):
    """``--from-q 0 -45 180 0 45 0`` (what a user types first) said "No such option '-4'":
    the numbers after the option are its values, as if quoted, up to the first other word."""
    words = ["--from-q", "0", "-45.5", "180", "0", "45", "0", "--json"]
    _, quoted, _ = run(command, "puma560", "--from-q", "0 -45.5 180 0 45 0", "--json")
    status, out, _ = run(command, "puma560", *words)
    assert status == 0 and json.loads(out) == json.loads(quoted)
    status, out, _ = run(command, *words[:-1], "puma560", "--json")       # robot after them
    assert status == 0 and json.loads(out) == json.loads(quoted)


def test_near_values_as_words_and_words_after_double_dash_untouched():
    _, quoted, _ = run("ik", "puma560", "--from-q", "0 -45 180 0 45 0", "--near",
                       "1 -44 179 0 44 0", "--numeric", "--json")
    status, out, _ = run("ik", "puma560", "--from-q", "0", "-45", "180", "0", "45", "0",
                         "--near", "1", "-44", "179", "0", "44", "0", "--numeric", "--json")
    assert status == 0 and json.loads(out) == json.loads(quoted)
    # too few words stay too few values, said by the option
    status, _, err = run("ik", "puma560", "--from-q", "0", "-45", "180", "--json")
    assert status == 2 and "--from-q" in err and "got 3 joint values" in err


def test_gathering_touches_only_ik_and_reach_and_nothing_after_double_dash():
    from kincalc.cli.main import gathered
    view = ["view", "puma560", "--from-q", "1", "2", "3", "4", "5", "6"]
    assert gathered(view) == view                          # view's joint values are its own
    assert gathered(["ik", "r", "--", "--from-q", "1", "2"]) == \
        ["ik", "r", "--", "--from-q", "1", "2"]
    assert gathered(["ik", "--from-q", "1", "-2e-3", "x", "3"]) == \
        ["ik", "--from-q", "1 -2e-3", "x", "3"]
    assert gathered(["ik", "r", "--from-q"]) == ["ik", "r", "--from-q"]
    assert gathered(["reach", "r", "--from-q=1", "-2", "--near=3"]) == \
        ["reach", "r", "--from-q", "1 -2", "--near", "3"]
    assert gathered(["ik", "r", "--from-q", "1 2", "3"]) == ["ik", "r", "--from-q", "1 2 3"]


def test_an_option_or_double_dash_after_from_q_is_its_missing_values():
    # was "no such option: -- (did you mean --to?)", and --near took "--from-q 1 2 ..." as
    # its values
    for words in (["--from-q", "--", "1", "2"], ["--near", "--from-q", "0", "0", "0", "0",
                                                  "0", "0"]):
        status, out, err = run("ik", "puma560", *words)
        option = words[0]
        assert status == 2 and out == "" and len(err.splitlines()) == 1
        assert f"Option '{option}' requires an argument" in err and "did you mean" not in err
    status, _, err = run("ik", "puma560", "--from-q", "-1 -2 -3 0 0 0", "--json")
    assert status == 0, err                         # a value that starts with '-' is a value
