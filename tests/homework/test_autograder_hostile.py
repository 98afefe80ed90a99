"""``kincalc check`` and ``quiz --roster`` against hostile input (a review's findings):
empty and clashing output names, sheets that are links or FIFOs, a line per sheet in
JSON, Markdown and control characters from a sheet, numbers that hide a value, and the
progress bar sharing a line with the results.

Each test names the contract it holds: bad input gets one line and exit 2, nothing given
is lost or overwritten, a batch gives a record per input, nothing is hidden.
"""

from __future__ import annotations

import csv
import io
import json
import os
import subprocess
import sys

import pytest
import yaml

from cli_contract import run_cli

ITEMS = "fk,reach"


@pytest.fixture
def work(tmp_path):
    """a.yaml and b.yaml (keys: every answer right), bad.yaml (invalid)."""
    status, _, err = run_cli(["quiz", "bk_rr", "--seed", 5, "--items", ITEMS, "--answers",
                              "-o", tmp_path / "a.yaml"])
    assert status == 0, err
    (tmp_path / "b.yaml").write_bytes((tmp_path / "a.yaml").read_bytes())
    (tmp_path / "bad.yaml").write_text("robot: bk_rr\n")
    return tmp_path


def check(folder, *argv):
    return run_cli(["check", *argv], cwd=folder)


def one_error(status, out, err, *words):
    assert status == 2 and out == "" and err.count("\n") == 1, (status, out, err)
    assert "Traceback" not in err and all(w in err for w in words), err


def tree(folder) -> dict:
    out = {}
    for root, _, names in os.walk(folder):
        for n in names:
            p = os.path.join(root, n)
            out[os.path.relpath(p, folder)] = None if os.path.islink(p) else \
                open(p, "rb").read()
    return out


# 1, 9: names that are no file -------------------------------------------------------------

@pytest.mark.parametrize("argv,words", [
    (["--feedback-dir", ""], "--feedback-dir: give a folder name"),
    (["--gradebook", ""], "--gradebook: give a file name"),
    (["--json", "-o", ""], "--output: give a file name"),
    (["--gradebook", "-"], "--gradebook -: standard output is for the sheets' results"),
])
def test_empty_names_and_gradebook_dash_are_refused(work, argv, words):
    before = tree(work)
    one_error(*check(work, "a.yaml", *argv), words)
    assert tree(work) == before


# 2: a sheet that is no regular file --------------------------------------------------------

def test_a_linked_or_fifo_sheet_is_refused_unread(work):
    os.symlink("a.yaml", work / "link.yaml")
    os.symlink("/etc/passwd", work / "passwd.yaml")
    os.mkfifo(work / "fifo.yaml")
    # a child process with a timeout: reading the FIFO would block for ever
    run = subprocess.run([sys.executable, "-m", "kincalc", "check", "fifo.yaml", "link.yaml",
                          "passwd.yaml", "b.yaml", "-q"], cwd=work, capture_output=True,
                         text=True, timeout=60, stdin=subprocess.DEVNULL)
    status, out, err = run.returncode, run.stdout, run.stderr
    assert status == 2 and out.startswith("b.yaml") and out.count("\n") == 1
    lines = err.splitlines()
    assert lines == [
        "kincalc: error: fifo.yaml: is a named pipe (FIFO), not read: a sheet must be a "
        "regular file (no link, no FIFO, no device)",
        "kincalc: error: link.yaml: is a symbolic link, not read: a sheet must be a regular "
        "file (no link, no FIFO, no device)",
        "kincalc: error: passwd.yaml: is a symbolic link, not read: a sheet must be a "
        "regular file (no link, no FIFO, no device)"]
    assert "root" not in out + err


# 3: outputs that are one file ----------------------------------------------------------------

def test_output_and_a_feedback_file_clash(work):
    (work / "fb").mkdir()
    for force in ([], ["--force"]):
        one_error(*check(work, "a.yaml", "--json", "-o", "fb/a.md", "--feedback-dir", "fb",
                         *force), "are the same file")
        assert os.listdir(work / "fb") == []


def test_output_and_gradebook_clash_through_a_linked_folder(work):
    (work / "real").mkdir()
    os.symlink("real", work / "ld")
    one_error(*check(work, "a.yaml", "--json", "-o", "ld/x.json", "--gradebook",
                     "real/x.json"), "--output ld/x.json and --gradebook real/x.json are the "
                                     "same file")
    assert os.listdir(work / "real") == []


def test_a_hard_link_clash_is_found(work):
    (work / "g.csv").write_text("old\n")
    os.link(work / "g.csv", work / "h.json")
    one_error(*check(work, "a.yaml", "--json", "-o", "h.json", "--gradebook", "g.csv",
                     "--force"), "are the same file")
    assert (work / "g.csv").read_text() == "old\n"


# 5: a JSON line per sheet -------------------------------------------------------------------

def test_json_has_a_line_per_sheet(work):
    status, out, err = check(work, "a.yaml", "bad.yaml", "b.yaml", "--json")
    docs = [json.loads(line) for line in out.splitlines()]
    assert status == 2 and len(docs) == 3
    assert [d["sheet"] for d in docs] == ["a.yaml", "bad.yaml", "b.yaml"]
    assert docs[1] == {"sheet": "bad.yaml", "error": "bad.yaml:1: 'items' is missing in the sheet"}
    assert err == f"kincalc: error: {docs[1]['error']}\n"
    status, out, err = check(work, "bad.yaml", "--json", "-o", "out.json")
    assert status == 2 and json.loads((work / "out.json").read_text())["error"]


# 6, 7: a sheet's words ----------------------------------------------------------------------

def test_markdown_escapes_line_breaks_fences_and_line_starts():
    from kincalc.homework.export import md
    assert md("line1\n~~~\nfenced") == r"line1 \~\~\~ fenced"
    assert md("- a") == r"\- a" and md("12. b") == r"12\. b" and md("> q") == r"\> q"
    assert md("+ x") == r"\+ x" and md("&lt;") == r"\&lt;" and md("a\x1bb") == "a\ufffdb"


def test_printable_folds_breaks_and_replaces_controls():
    from kincalc.limits import printable
    assert printable("a\r\nb\tc") == "a b c"
    assert printable("\x1b[31mR\x00\x7f\x9b\u202e") == "\ufffd[31mR\ufffd\ufffd\ufffd\ufffd"
    assert printable("Zoë Ñ") == "Zoë Ñ"
    # invisible characters that make a name look like another (a message named the joint
    # 'a\u200bb' as 'ab'); the joiners of scripts and emoji stay
    assert printable("a\u200bb\u2060c\ufeffd\u200ee") == "a\ufffdb\ufffdc\ufffdd\ufffde"
    assert printable("\U0001f468\u200d\U0001f469") == "\U0001f468\u200d\U0001f469"


def hostile(work, name="evil.yaml"):
    doc = yaml.safe_load((work / "a.yaml").read_text())
    doc.update(student="\x1b[31mRED\x1b[0m \x1b]0;TITLE\x07\nNUL\x00",
               title="line1\n~~~\nfenced")
    doc["items"][0]["id"] = "1\n# x"
    (work / name).write_text(yaml.safe_dump(doc, sort_keys=False))


def test_no_control_character_from_a_sheet_reaches_a_terminal_csv_or_markdown(work):
    hostile(work)
    status, out, err = check(work, "evil.yaml", "-q", "--gradebook", "g.csv",
                             "--feedback-dir", "fb")
    assert status == 0, err
    assert out.count("\n") == 1 and "\x1b" not in out and "\x07" not in out
    status, table, _ = check(work, "evil.yaml")
    assert status == 0 and "\x1b" not in table and "\x00" not in table
    text = (work / "g.csv").read_bytes().decode()
    rows = list(csv.reader(io.StringIO(text)))
    assert text.count("\n") == 2 and not any(c in text for c in "\x1b\x07\x00")
    assert rows[1][0] == "\ufffd[31mRED\ufffd[0m \ufffd]0;TITLE\ufffd NUL\ufffd"
    page = (work / "fb" / "evil.md").read_text()
    assert "\x1b" not in page and "~~~" not in page and "\n# x" not in page
    status, out, _ = check(work, "evil.yaml", "--format", "gradescope")
    doc = json.loads(out)
    assert "~~~" not in doc["output"] and doc["output"].count("\n") == 3


# 8: numbers that hide nothing -----------------------------------------------------------------

def test_numbers_are_written_exactly_enough():
    from kincalc.homework.export import number
    assert [number(x) for x in (1234.5678, 1235.0011, 2, 2.0, 2.5, 0.1 + 0.2)] == \
        ["1234.5678", "1235.0011", "2", "2", "2.5", "0.3"]


def test_percent_is_never_rounded_to_100_or_0():
    from kincalc.homework.grade.common import percent
    assert percent(99.992, 100) == 99.9 and percent(1235.0011 - 0.1, 1235.0011) == 99.9
    assert percent(0.0004, 1) == 0.1 and percent(0, 5) == 0 and percent(5, 5) == 100
    assert percent(5, 6.5) == 76.9 and percent(0, 0) == 100


def test_gradebook_shows_points_as_written(work):
    doc = yaml.safe_load((work / "a.yaml").read_text())
    doc["items"][0]["points"] = 1234.5678
    doc["items"][1]["points"] = 0.0011
    doc["items"][1]["answer"] = not doc["items"][1]["answer"]
    (work / "p.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    status, out, _ = check(work, "p.yaml", "-q", "--gradebook", "g.csv")
    assert status == 1
    assert "1234.5678 of 1234.5689 points (99.9 %)" in out
    row = list(csv.reader(io.StringIO((work / "g.csv").read_text())))[1]
    assert row[2:7] == ["1234.5678", "0", "1234.5678", "1234.5689", "99.9"]


# 10: the progress bar never shares a line with the results -------------------------------------

@pytest.mark.skipif(sys.platform == "win32", reason="a pseudo-terminal")
def test_progress_bar_and_score_lines_on_one_terminal(work):
    import pty
    import re
    import select
    main, child = pty.openpty()
    env = dict(os.environ, COLUMNS="100", TERM="xterm")
    proc = subprocess.Popen([sys.executable, "-m", "kincalc", "check", "a.yaml", "bad.yaml",
                             "b.yaml", "-q"], cwd=work, stdin=child, stdout=child,
                            stderr=child, env=env, close_fds=True)
    os.close(child)
    data = b""
    while True:
        ready, _, _ = select.select([main], [], [], 60)
        if not ready:
            break
        try:
            chunk = os.read(main, 65536)
        except OSError:
            break
        if not chunk:
            break
        data += chunk
    proc.wait(timeout=60)
    os.close(main)
    assert proc.returncode == 2
    text = data.decode("utf-8", "replace")
    assert "grading" in text                               # the bar was drawn
    # what a line shows after the terminal's carriage returns and erasures
    for line in text.split("\n"):
        shown = re.split(r"\r|\x1b\[2K", line)[-1] if "score:" not in line else \
            line[line.rfind("\r", 0, line.index("score:")) + 1:]
        if "score:" in shown:
            assert "grading" not in shown, repr(line)
    assert text.count("score:") == 2


# 4, 11: quiz --roster --------------------------------------------------------------------------

def roster_quiz(folder, *extra):
    (folder / "r.csv").write_text("id\ns1\ns2\n")
    return run_cli(["quiz", "planar_3r", "--roster", "r.csv", "--salt", "hw", "--items",
                    "fk", "-o", "E", *extra], cwd=folder)


@pytest.mark.parametrize("force", [[], ["--force"]])
def test_keys_linked_to_the_sheets_folder_are_refused(tmp_path, force):
    (tmp_path / "E").mkdir()
    os.symlink(".", tmp_path / "E" / "keys")
    one_error(*roster_quiz(tmp_path, *force), "keys folder", "the sheets would hold "
                                                 "the answers")
    assert sorted(os.listdir(tmp_path / "E")) == ["keys"]


def test_an_existing_key_is_refused_before_any_sheet_is_written(tmp_path):
    (tmp_path / "E" / "keys").mkdir(parents=True)
    (tmp_path / "E" / "keys" / "s2.yaml").write_text("mine\n")
    one_error(*roster_quiz(tmp_path), "E/keys/s2.yaml: the file exists")
    assert tree(tmp_path / "E") == {os.path.join("keys", "s2.yaml"): b"mine\n"}


def test_a_multi_line_id_is_reported_on_its_first_line():
    from kincalc.homework.roster import RosterError, parse_roster
    with pytest.raises(RosterError, match=r"^r.csv:2: "):
        parse_roster('id,name\n"s1\ns2",A\n', "r.csv")
    with pytest.raises(RosterError, match=r"^r.csv:5: "):
        parse_roster('id\n\ns1\n\n"x\r\ny"\n', "r.csv")


# independent hostile-input campaign, twenty-sixth session ---------------------------------

DH_ITEM = ("robot: planar_3r\nitems:\n  - id: '1'\n    kind: dh\n    answer:\n"
           "      convention: dh\n{columns}      table: [[{cell}, 0, 1, 0], [q2, 0, 1, 0], "
           "[q3, 0, 1, 0]]\n")


@pytest.mark.parametrize("columns", ["[theta, d, a, [alpha]]", "[theta, d, a, {x: 1}]",
                                     "[theta, d, a, ~]"])
def test_a_dh_answers_column_that_is_no_name(tmp_path, columns):
    """A list or a mapping among 'answer.columns' was an internal error (exit 3:
    'list' object has no attribute 'strip'); it is the sheet's one error."""
    (tmp_path / "hw.yaml").write_text(DH_ITEM.format(columns=f"      columns: {columns}\n",
                                                     cell="q1"))
    one_error(*check(tmp_path, "hw.yaml"), "hw.yaml:7", "'answer.columns' entry")


@pytest.mark.parametrize("cell, words", [
    ("'" + "-" * 200000 + "q1'", "expression longer than 500 characters"),
    ("'" + "-" * 600 + "q1'", "expression longer than 500 characters"),
    ("'" + "-" * 5000 + "1'", "expression longer than 500 characters"),
])
def test_a_dh_cell_too_long_to_parse_is_said_so(tmp_path, cell, words):
    """A DH cell of 200000 '-' was parsed before its length was checked: a RecursionError
    or MemoryError, exit 3. The length is checked first (any cell: the first one read)."""
    (tmp_path / "hw.yaml").write_text(DH_ITEM.format(columns="", cell=cell))
    one_error(*check(tmp_path, "hw.yaml"), "hw.yaml:7", "row 1, theta", words)


def test_a_file_name_with_a_line_break_stays_in_the_sheets_comment(tmp_path):
    """quiz wrote its command line, with the robot file's name, as the sheet's first comment:
    a name 'arm<newline>tolerance: {...} #.yaml' put a live 'tolerance' key into the sheet
    (every answer right at check), a plain line break made it unreadable. Each comment is one
    line; the name is quoted as a shell would take it."""
    name = "arm\ntolerance: {position: 1000000, angle: 1000000} #.yaml"
    robot = tmp_path / name
    robot.write_text(open(os.path.join(os.path.dirname(__file__), "..", "..", "robots",
                                       "planar_3r.yaml")).read())
    status, _, err = run_cli(["quiz", name, "--seed", 1, "--items", "fk", "-o", "s.yaml"],
                             cwd=tmp_path)
    assert status == 0, err
    text = (tmp_path / "s.yaml").read_text()
    assert text.startswith("# Generated by") and "\ntolerance" not in text
    assert "kincalc quiz 'arm tolerance:" in text.splitlines()[0]
    doc = yaml.safe_load(text)
    assert "tolerance" not in doc and doc["robot"] == name
    status, out, err = check(tmp_path, "s.yaml", "--json")
    assert status == 1 and json.loads(out)["tolerance"]["position"] < 1, (out, err)
