"""``kincalc check`` for autograders and for a class: ``--format gradescope|prairielearn``,
``--gradebook``, ``--feedback-dir``, and the progress bar.

The sheets are drawn by ``kincalc quiz --answers`` (a key: every answer right), and a
copy of the key with known answers turned wrong and known weights; the expected scores
are computed here from those edits, not from kincalc. The documents are checked against
the field names and types the platforms document (written out below from their pages,
with no schema library):

* Gradescope, https://gradescope-autograders.readthedocs.io/en/latest/specs/
  ("Output format", "Test case status", "Output String Formatting");
* PrairieLearn, https://prairielearn.readthedocs.io/en/latest/externalGrading/
  ("Grading results").
"""

from __future__ import annotations

import csv
import io
import json
import os

import pytest
import yaml

from cli_contract import run_cli

NUM = (int, float)
VISIBILITY = {"hidden", "after_due_date", "after_published", "visible"}
STRING_FORMATS = {"text", "html", "simple_format", "md", "ansi"}

#: Gradescope's results.json: key -> type (every key optional)
GS_TOP = {"score": NUM, "execution_time": NUM, "output": str, "output_format": str,
          "test_output_format": str, "test_name_format": str, "visibility": str,
          "stdout_visibility": str, "extra_data": dict, "tests": list, "leaderboard": list}
GS_TEST = {"score": NUM, "max_score": NUM, "status": str, "name": str, "name_format": str,
           "number": str, "output": str, "output_format": str, "tags": list,
           "visibility": str, "extra_data": dict}
#: PrairieLearn's results.json: the documented keys and types (others are allowed)
PL_TOP = {"gradable": bool, "score": NUM, "message": str, "output": str,
          "format_errors": (str, list), "images": list, "tests": list}
PL_TEST = {"name": str, "description": str, "points": NUM, "max_points": NUM,
           "message": str, "output": str, "images": list}


def _typed(doc: dict, schema: dict, where: str, closed: bool):
    for key, value in doc.items():
        if key not in schema:
            assert not closed, f"{where}: {key!r} is not a documented field"
            continue
        assert isinstance(value, schema[key]) and not (
            schema[key] is NUM and isinstance(value, bool)), f"{where}.{key}: {value!r}"


def validate_gradescope(doc: dict):
    _typed(doc, GS_TOP, "results", closed=True)
    assert "score" in doc or all("score" in t for t in doc.get("tests", []))
    for key in ("visibility", "stdout_visibility"):
        assert doc.get(key, "visible") in VISIBILITY
    for key in ("output_format", "test_output_format", "test_name_format"):
        assert doc.get(key, "text") in STRING_FORMATS
    for k, t in enumerate(doc.get("tests", [])):
        _typed(t, GS_TEST, f"tests[{k}]", closed=True)
        assert t.get("status", "passed") in {"passed", "failed"}
        assert t.get("visibility", "visible") in VISIBILITY
        assert t.get("output_format", "text") in STRING_FORMATS


def validate_prairielearn(doc: dict):
    _typed(doc, PL_TOP, "results", closed=False)
    if doc.get("gradable", True):
        assert 0.0 <= doc["score"] <= 1.0
    else:
        assert doc.get("format_errors"), "not gradable, and no format_errors"
    for k, t in enumerate(doc.get("tests", [])):
        _typed(t, PL_TEST, f"tests[{k}]", closed=False)
        assert 0 <= t["points"] <= t["max_points"]


def test_the_validators_can_fail():
    good = {"score": 1, "tests": [{"name": "a", "score": 1, "max_score": 1,
                                   "status": "passed"}]}
    validate_gradescope(good)
    for bad in ({**good, "scor": 1}, {**good, "visibility": "later"},
                {"tests": [{"name": "a", "status": "ok", "score": 0}]},
                {"tests": [{"name": "a", "number": 1, "score": 0}]}, {"tests": [{"name": "a"}]}):
        with pytest.raises(AssertionError):
            validate_gradescope(bad)
    validate_prairielearn({"gradable": True, "score": 0.5, "tests": []})
    for bad in ({"score": 1.5}, {"gradable": False}, {"score": "1"},
                {"score": 1, "tests": [{"name": "a", "points": 2, "max_points": 1}]}):
        with pytest.raises(AssertionError):
            validate_prairielearn(bad)


# --- the sheets -------------------------------------------------------------------------

ITEMS = "fk,ik,reach,singular"
#: the key's items turned wrong in the "wrong" sheet (by id), and the weights given
WRONG_IDS = {"3", "4"}
POINTS = {"1": 2, "2": 3, "3": 1, "4": 0.5}


def quiz_key(folder, name="key.yaml", seed=11):
    status, _, err = run_cli(["quiz", "bk_rr", "--seed", seed, "--items", ITEMS,
                              "--answers", "-o", folder / name])
    assert status == 0, err
    return yaml.safe_load((folder / name).read_text())


@pytest.fixture
def sheets(tmp_path):
    """key.yaml (every answer right), wrong.yaml (reach and singular answers flipped, the
    items weighted by POINTS), bad.yaml (invalid), named.yaml (a student's name)."""
    key = quiz_key(tmp_path)
    wrong = dict(key, student="Grace Hopper")
    wrong["items"] = [dict(it, points=POINTS[it["id"]],
                           answer=(not it["answer"]) if it["id"] in WRONG_IDS else it["answer"])
                      for it in key["items"]]
    assert [it["kind"] for it in wrong["items"]] == ["fk", "ik", "reach", "singular"]
    (tmp_path / "wrong.yaml").write_text(yaml.safe_dump(wrong, sort_keys=False))
    (tmp_path / "bad.yaml").write_text("robot: bk_rr\nitems:\n  - {id: x, kind: nope}\n")
    return tmp_path


def check(folder, *argv):
    return run_cli(["check", *argv], cwd=folder)


# --- Gradescope -------------------------------------------------------------------------

def test_gradescope_key_has_full_marks(sheets):
    status, out, err = check(sheets, "key.yaml", "--format", "gradescope")
    assert status == 0 and err == "" and out.count("\n") == 1
    doc = json.loads(out)
    validate_gradescope(doc)
    assert len(doc["tests"]) == 4 and all(t["status"] == "passed" for t in doc["tests"])
    assert doc["score"] == sum(t["max_score"] for t in doc["tests"]) == 4
    assert [t["number"] for t in doc["tests"]] == ["1", "2", "3", "4"]
    assert doc["output_format"] == "md" and "visibility" not in doc
    assert doc["execution_time"] >= 0


def test_gradescope_wrong_items_fail_and_the_score_is_the_sum(sheets):
    status, out, _ = check(sheets, "wrong.yaml", "--format", "gradescope")
    assert status == 1
    doc = json.loads(out)
    validate_gradescope(doc)
    tests = {t["name"].split()[1]: t for t in doc["tests"]}
    for ident, t in tests.items():
        assert t["max_score"] == POINTS[ident]
        assert t["status"] == ("failed" if ident in WRONG_IDS else "passed")
        assert t["score"] == (0 if ident in WRONG_IDS else POINTS[ident])
        assert t["output_format"] == "md"
    assert doc["score"] == sum(t["score"] for t in doc["tests"])
    assert doc["score"] == sum(p for i, p in POINTS.items() if i not in WRONG_IDS) == 5
    assert sum(t["max_score"] for t in doc["tests"]) == sum(POINTS.values())
    # the feedback says what was wrong and why; the question comes first
    assert "wrong (answer" in tests["4"]["output"] and "singular: " in tests["4"]["output"]
    assert tests["1"]["output"].startswith("*Question:* Compute the tool pose")
    assert "| set | q | result |" in tests["2"]["output"]
    assert "Grace Hopper" in doc["output"] and "5 of 6.5 points" in doc["output"]
    # kincalc's own report rides along, as --json prints it
    _, report, _ = check(sheets, "wrong.yaml", "--json")
    assert doc["extra_data"] == json.loads(report)


def test_gradescope_visibility(sheets):
    for v in ("hidden", "after_due_date", "after_published", "visible"):
        status, out, _ = check(sheets, "key.yaml", "--format", "gradescope", "--visibility", v)
        doc = json.loads(out)
        validate_gradescope(doc)
        assert status == 0 and doc["visibility"] == v


@pytest.mark.parametrize("argv,words", [
    (["key.yaml", "--format", "gradescope", "--visibility", "later"], "--visibility must be"),
    (["key.yaml", "--json", "--visibility", "hidden"], "a setting of --format gradescope"),
    (["key.yaml", "wrong.yaml", "--format", "gradescope"], "give one sheet, not 2"),
    (["key.yaml", "wrong.yaml", "--format", "prairielearn"], "give one sheet, not 2"),
    (["key.yaml", "--format", "xml"], "--format must be one of"),
    (["key.yaml", "--format", "gradescope", "--json"], "two formats"),
    (["key.yaml", "-o", "out.txt"], "tables go to standard output"),
])
def test_options_that_do_not_go_together(sheets, argv, words):
    status, out, err = check(sheets, *argv)
    assert status == 2 and out == "" and words in err and err.count("\n") == 1
    assert not (sheets / "out.txt").exists()


def test_an_invalid_sheet_still_gets_a_document(sheets):
    status, out, err = check(sheets, "bad.yaml", "--format", "gradescope")
    assert status == 2 and "bad.yaml:3:" in err and err.count("\n") == 1
    doc = json.loads(out)
    validate_gradescope(doc)
    assert doc["score"] == 0 and doc["tests"] == [] and "bad.yaml:3:" in doc["output"]
    status, out, _ = check(sheets, "bad.yaml", "--format", "prairielearn")
    doc = json.loads(out)
    validate_prairielearn(doc)
    assert status == 2 and doc["gradable"] is False and "score" not in doc
    assert "bad.yaml:3:" in doc["format_errors"][0]


# --- PrairieLearn -----------------------------------------------------------------------

def test_prairielearn_score_is_points_over_max_points(sheets):
    status, out, _ = check(sheets, "wrong.yaml", "--format", "prairielearn")
    assert status == 1
    doc = json.loads(out)
    validate_prairielearn(doc)
    assert doc["gradable"] is True
    got, total = sum(t["points"] for t in doc["tests"]), sum(t["max_points"] for t in doc["tests"])
    assert doc["score"] == pytest.approx(got / total) == pytest.approx(5 / 6.5)
    wrong = [t["name"] for t in doc["tests"] if t["points"] == 0]
    assert wrong == ["item 3 (reach)", "item 4 (singular)"]
    assert doc["tests"][0]["description"].startswith("Compute the tool pose")
    assert "**" not in doc["tests"][0]["output"]            # plain text, not Markdown
    status, out, _ = check(sheets, "key.yaml", "--format", "prairielearn")
    assert status == 0 and json.loads(out)["score"] == 1.0


# --- -o FILE ------------------------------------------------------------------------------

def test_output_file_is_never_replaced_without_force(sheets):
    target = sheets / "results.json"
    status, out, err = check(sheets, "wrong.yaml", "--format", "gradescope", "-o", target)
    assert status == 1 and out == "" and "wrote" in err
    first = target.read_text()
    assert json.loads(first)["score"] == 5
    status, _, err = check(sheets, "key.yaml", "--format", "gradescope", "-o", target)
    assert status == 2 and "--force" in err and target.read_text() == first
    status, _, _ = check(sheets, "key.yaml", "--format", "gradescope", "-o", target, "--force")
    assert status == 0 and json.loads(target.read_text())["score"] == 4
    before = (sheets / "key.yaml").read_text()
    status, _, err = check(sheets, "key.yaml", "--format", "gradescope", "-o", "key.yaml",
                           "--force")
    assert status == 2 and "which this command reads" in err
    assert (sheets / "key.yaml").read_text() == before


def test_no_output_replaces_the_robot_file_a_sheet_names(sheets):
    """A sheet's robot file is read while grading, not named on the command line: --force
    replaced it with the gradebook or the report (it now exits 2 and the file stays)."""
    robot = sheets / "arm.yaml"
    status, _, err = run_cli(["convert", "bk_rr", "--to", "dh", "-o", robot])
    assert status == 0, err
    key = yaml.safe_load((sheets / "key.yaml").read_text())
    (sheets / "mine.yaml").write_text(yaml.safe_dump(dict(key, robot="arm.yaml"),
                                                     sort_keys=False))
    before = robot.read_bytes()
    for option in (["--gradebook"], ["--format", "json", "-o"]):
        status, _, err = check(sheets, "mine.yaml", "-q", *option, "arm.yaml", "--force")
        assert status == 2 and "that is a file this command read" in err, err
        assert robot.read_bytes() == before
    status, _, err = check(sheets, "mine.yaml", "-q", "--gradebook", "grades.csv")
    assert status == 0, err


# --- a class: gradebook and feedback -------------------------------------------------------

def class_folder(sheets):
    for sub in ("a", "b"):
        (sheets / sub).mkdir()
    (sheets / "a" / "hw.yaml").write_text((sheets / "key.yaml").read_text())
    (sheets / "b" / "hw.yaml").write_text((sheets / "wrong.yaml").read_text())
    evil = yaml.safe_load((sheets / "key.yaml").read_text())
    evil["student"] = "=HYPERLINK(\"http://x\")"
    (sheets / "evil.yaml").write_text(yaml.safe_dump(evil, sort_keys=False))
    return ["key.yaml", "wrong.yaml", "bad.yaml", "a/hw.yaml", "b/hw.yaml", "evil.yaml"]


def test_gradebook_has_a_row_per_sheet(sheets):
    names = class_folder(sheets)
    status, out, err = check(sheets, *names, "-q", "--gradebook", "grades.csv")
    assert status == 2                                   # the worst: an invalid sheet
    assert out.count("score:") == 5 and "bad.yaml:3:" in err and "wrote grades.csv" in err
    rows = list(csv.DictReader(io.StringIO((sheets / "grades.csv").read_text())))
    assert [r["file"] for r in rows] == names
    assert list(rows[0]) == ["student", "file", "item 1", "item 2", "item 3", "item 4",
                             "points", "total", "percent", "error"]
    by = {r["file"]: r for r in rows}
    assert by["key.yaml"]["student"] == "key"            # no student: the file's stem
    assert by["wrong.yaml"]["student"] == "Grace Hopper"
    assert [by["wrong.yaml"][f"item {i}"] for i in "1234"] == ["2", "3", "0", "0"]
    assert (by["wrong.yaml"]["points"], by["wrong.yaml"]["total"],
            by["wrong.yaml"]["percent"]) == ("5", "6.5", "76.9")
    assert (by["key.yaml"]["points"], by["key.yaml"]["total"],
            by["key.yaml"]["percent"]) == ("4", "4", "100")
    assert by["key.yaml"]["error"] == "" and by["a/hw.yaml"]["points"] == "4"
    bad = by["bad.yaml"]
    assert bad["error"].startswith("bad.yaml:3:") and "'kind' must be one of" in bad["error"]
    assert bad["student"] == "bad" and bad["points"] == bad["item 1"] == ""
    assert by["evil.yaml"]["student"] == "'=HYPERLINK(\"http://x\")"   # not a formula


def test_gradebook_exit_status_is_the_worst(sheets):
    assert check(sheets, "key.yaml", "--gradebook", "g0.csv", "-q")[0] == 0
    assert check(sheets, "key.yaml", "wrong.yaml", "--gradebook", "g1.csv", "-q")[0] == 1
    status, _, err = check(sheets, "key.yaml", "--gradebook", "g1.csv", "-q")
    assert status == 2 and "the file exists; use --force" in err


def test_feedback_files(sheets):
    names = class_folder(sheets)
    status, _, err = check(sheets, *names, "-q", "--feedback-dir", "feedback")
    assert status == 2 and "wrote 6 feedback files in feedback" in err
    folder = sheets / "feedback"
    assert sorted(os.listdir(folder)) == ["bad.md", "evil.md", "hw-2.md", "hw.md", "key.md",
                                          "wrong.md"]
    wrong = (folder / "wrong.md").read_text()
    assert "## item 3 (reach): wrong" in wrong and "## item 4 (singular): wrong" in wrong
    assert "## item 1 (fk): right" in wrong and "score: 5 of 6.5 points" in wrong
    assert "item 3 (reach): wrong" not in (folder / "key.md").read_text()
    assert "Grace Hopper" in (folder / "hw-2.md").read_text()      # b/hw.yaml, the later one
    assert "Grace Hopper" not in (folder / "hw.md").read_text()
    assert "bad.yaml:3:" in (folder / "bad.md").read_text()
    # again: refused without --force (nothing written), replaced with it
    (folder / "key.md").write_text((folder / "key.md").read_text() + "teacher's note\n")
    status, _, err = check(sheets, "key.yaml", "--feedback-dir", "feedback", "-q")
    assert status == 2 and "--force" in err and "teacher's note" in (folder / "key.md").read_text()
    status, _, _ = check(sheets, "key.yaml", "--feedback-dir", "feedback", "-q", "--force")
    assert status == 0 and "teacher's note" not in (folder / "key.md").read_text()
    # a file kincalc did not write is never replaced
    (folder / "mine.md").write_text("my own notes\n")
    (sheets / "mine.yaml").write_text((sheets / "key.yaml").read_text())
    status, _, err = check(sheets, "mine.yaml", "--feedback-dir", "feedback", "--force")
    assert status == 2 and "not a feedback file kincalc wrote" in err
    assert (folder / "mine.md").read_text() == "my own notes\n"


def test_feedback_dir_must_be_a_folder(sheets):
    (sheets / "file").write_text("x")
    status, _, err = check(sheets, "key.yaml", "--feedback-dir", "file")
    assert status == 2 and "not a folder" in err
    status, _, err = check(sheets, "key.yaml", "--feedback-dir", "no/such/dir")
    assert status == 2 and "does not exist" in err and not (sheets / "no").exists()


def test_feedback_names_are_deterministic():
    from kincalc.homework.gradebook import feedback_names
    assert feedback_names(["a/hw.yaml", "b/hw.yaml", "hw-2.yaml", "c/HW.yaml"]) == \
        ["hw.md", "hw-3.md", "hw-2.md", "HW-4.md"]
    assert feedback_names(["x.yaml", "y.yml"]) == ["x.md", "y.md"]


def test_markdown_escapes_the_sheets_words():
    from kincalc.homework.export import md
    assert md("T_0^3 <b>*x*</b> [a](b) | # `c` \\") == \
        r"T\_0^3 \<b\>\*x\*\</b\> \[a\](b) \| \# \`c\` \\"


# --- the progress bar ---------------------------------------------------------------------

class FakeTerminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_only_on_a_terminal(sheets, monkeypatch, capsys):
    from kincalc.cli.main import main
    monkeypatch.chdir(sheets)
    argv = ["check", "key.yaml", "wrong.yaml", "-q"]
    assert main(argv) == 1
    plain = capsys.readouterr()
    assert plain.err == ""                                 # not a terminal: no bar
    term = FakeTerminal()
    monkeypatch.setattr("sys.stderr", term)
    assert main(argv) == 1
    assert capsys.readouterr().out == plain.out            # stdout (a pipe) untouched
    assert "grading" in term.getvalue()                    # the bar was drawn on stderr
