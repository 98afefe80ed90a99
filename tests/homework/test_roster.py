"""``kincalc quiz ROBOT --roster FILE --salt TEXT -o DIR``: a sheet and a key per student.

The roster is untrusted input (ids name files: no path leaves DIR), the seed derivation
is the documented one (checked here with hashlib from its description), the same roster
draws the same bytes, two students draw different exercises, and ``kincalc check``
grades each sheet against its own values: full marks for the student's own key, not for
another student's.
"""

from __future__ import annotations

import hashlib
import os

import pytest
import yaml

from cli_contract import run_cli
from kincalc.homework.roster import RosterError, parse_roster, variant_seed

ITEMS = "fk,ik,reach,singular"


def quiz(folder, roster_text, *extra, out="class", salt="hw4-2026"):
    (folder / "roster.csv").write_text(roster_text)
    argv = ["quiz", "bk_rr", "--roster", "roster.csv", "--items", ITEMS, "-o", out, *extra]
    if salt is not None:
        argv += ["--salt", salt]
    return run_cli(argv, cwd=folder)


def files(folder) -> dict:
    """{relative path: bytes} of every file below ``folder``."""
    out = {}
    for root, _, names in os.walk(folder):
        for n in names:
            p = os.path.join(root, n)
            out[os.path.relpath(p, folder)] = open(p, "rb").read()
    return out


def test_seed_is_the_documented_derivation():
    # README and man kincalc-quiz: int(sha256(SALT:ID).hexdigest()[:12], 16)
    for salt, sid in (("hw4-2026", "s123"), ("", "a"), ("ünï", "Z.9_-")):
        text = (salt + ":" + sid).encode("utf-8")
        assert variant_seed(salt, sid) == int(hashlib.sha256(text).hexdigest()[:12], 16)
    assert variant_seed("hw4", "s1") != variant_seed("hw5", "s1") != variant_seed("hw4", "s2")
    assert 0 <= variant_seed("x", "y") < 2 ** 48


def test_roster_reading():
    text = "\ufeffName,ID,email\n\nAda Lovelace,s1,ada@x\n  Bob , s2 ,\n\n"
    assert [(s.id, s.line) for s in parse_roster(text, "r.csv")] == [("s1", 3), ("s2", 4)]
    quoted = 'id,note\n"s3","a ""quoted"", multi\nline note"\ns4,x\n'
    # a record's line is its first (s3's quoted note spans lines 2 and 3)
    assert [(s.id, s.line) for s in parse_roster(quoted)] == [("s3", 2), ("s4", 4)]


@pytest.mark.parametrize("text,line,words", [
    ("id\n../../etc/x\n", 2, "not a safe file name"),
    ("id\ns1\na/b\n", 3, "not a safe file name"),
    ("id\n.hidden\n", 2, "not a safe file name"),
    ("id\n..\n", 2, "not a safe file name"),
    ("id\nC:x\n", 2, "not a safe file name"),
    ("id,name\n,Ada\n", 2, "the id is empty"),
    ("id,name\ns1\ns2,Bob\n", None, None),
    ("id\ncon.txt\n", 2, "device name"),
    ("id\ns1\ns2\ns1\n", 4, "already on line 2"),
    ("id\nAb\naB\n", 3, "differing only in case"),
    ("id\n" + "x" * 65 + "\n", 2, "at most 64"),
    ("name\nAda\n", 1, "'id'"),
    ("id,ID\ns1,s2\n", 1, "two columns"),
    ("id\n", None, "no students"),
    ("id\ns1\x00\n", 2, "not a safe file name"),
    ('id\ns1\n"s2"x\n', 3, "not a CSV file"),
    # an id cell over two lines names them and quotes neither (the next line may be anything)
    ('id\n"s1\nSECRET"\n', 2, "runs on over lines 2-3"),
])
def test_bad_rosters_name_their_line(text, line, words):
    if words is None:                                  # a short row is fine: its id is there
        assert [s.id for s in parse_roster(text)] == ["s1", "s2"]
        return
    with pytest.raises(RosterError) as info:
        parse_roster(text, "roster.csv")
    assert info.value.line == line and words in str(info.value)
    assert "SECRET" not in str(info.value)
    assert str(info.value).startswith("roster.csv" + ("" if line is None else f":{line}") + ": ")


def test_roster_size_is_bounded(monkeypatch):
    import kincalc.homework.roster as roster
    monkeypatch.setattr(roster, "MAX_ROSTER_STUDENTS", 3)
    with pytest.raises(RosterError, match=r"^r.csv:5: more than 3 students"):
        parse_roster("id\na\nb\nc\nd\n", "r.csv")


def test_a_path_traversal_id_is_refused_and_nothing_is_written(tmp_path):
    before = files(tmp_path.parent / tmp_path.name)
    status, out, err = quiz(tmp_path, "id\ns1\n../../etc/x\n")
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("kincalc: error: roster.csv:3: the id '../../etc/x' is not a safe")
    after = files(tmp_path)
    assert set(after) - set(before) == {"roster.csv"}
    assert not (tmp_path / "class").exists()


def test_a_roster_too_large_to_read(tmp_path):
    from kincalc.limits import MAX_FILE_BYTES
    status, _, err = quiz(tmp_path, "id\n" + "s1,x\n" * (MAX_FILE_BYTES // 5 + 1))
    assert status == 2 and "larger than" in err and "roster.csv" in err


@pytest.mark.parametrize("extra,salt,words", [
    ([], None, "needs --salt"),
    ([], "", "needs --salt"),
    (["--seed", "3"], "x", "--seed does not go with --roster"),
    (["--answers"], "x", "--answers does not go with --roster"),
])
def test_roster_options(tmp_path, extra, salt, words):
    status, out, err = quiz(tmp_path, "id\ns1\n", *extra, salt=salt)
    assert status == 2 and out == "" and words in err and not (tmp_path / "class").exists()


def test_salt_needs_a_roster_and_a_roster_needs_a_folder(tmp_path):
    status, _, err = run_cli(["quiz", "bk_rr", "--salt", "x"], cwd=tmp_path)
    assert status == 2 and "--salt goes with --roster" in err
    status, _, err = quiz(tmp_path, "id\ns1\n", out="-")
    assert status == 2 and "needs -o DIR" in err
    (tmp_path / "afile").write_text("x")
    status, _, err = quiz(tmp_path, "id\ns1\n", out="afile")
    assert status == 2 and "not a folder" in err and (tmp_path / "afile").read_text() == "x"


ROSTER = "id,name\ns1,Ada\ns2,Bob\n"


@pytest.fixture
def drawn(tmp_path):
    status, out, err = quiz(tmp_path, ROSTER)
    assert status == 0 and out == "", err
    assert err == "kincalc: wrote 2 sheets in class and their keys in class/keys\n"
    return tmp_path


def test_one_sheet_and_one_key_per_student(drawn):
    assert sorted(files(drawn / "class")) == ["keys/s1.yaml", "keys/s2.yaml", "s1.yaml",
                                              "s2.yaml"]
    for sid in ("s1", "s2"):
        sheet = yaml.safe_load((drawn / "class" / f"{sid}.yaml").read_text())
        key = yaml.safe_load((drawn / "class" / "keys" / f"{sid}.yaml").read_text())
        assert sheet["student"] == key["student"] == sid
        assert sheet["seed"] == key["seed"] == variant_seed("hw4-2026", sid)
        assert all("answer" not in it for it in sheet["items"])
        assert all("answer" in it for it in key["items"])
        assert [{k: v for k, v in it.items() if k != "answer"} for it in key["items"]] \
            == sheet["items"]
    one, two = (yaml.safe_load((drawn / "class" / f"{s}.yaml").read_text()) for s in ("s1", "s2"))
    assert one["items"][0]["q"] != two["items"][0]["q"]              # fk joints
    assert one["items"][1]["pose"] != two["items"][1]["pose"]        # ik pose


def test_the_same_roster_draws_the_same_bytes(drawn):
    status, _, err = quiz(drawn, ROSTER, out="again")
    assert status == 0, err
    assert files(drawn / "again") == files(drawn / "class")
    status, _, _ = quiz(drawn, ROSTER, out="other", salt="hw5-2026")
    assert files(drawn / "other") != files(drawn / "class")
    # one student's sheet is the plain quiz of their seed, with their id
    seed = variant_seed("hw4-2026", "s1")
    status, plain, _ = run_cli(["quiz", "bk_rr", "--seed", seed, "--items", ITEMS])
    body = [line for line in plain.splitlines() if not line.startswith("#")]
    mine = [line for line in (drawn / "class" / "s1.yaml").read_text().splitlines()
            if not line.startswith("#") and line != "student: s1"]
    assert status == 0 and mine == body


def answered(sheet_path, key_path, out_path):
    sheet = yaml.safe_load(sheet_path.read_text())
    key = {it["id"]: it["answer"] for it in yaml.safe_load(key_path.read_text())["items"]}
    for it in sheet["items"]:
        it["answer"] = key[it["id"]]
    out_path.write_text(yaml.safe_dump(sheet, sort_keys=False))


def grade(folder, *paths):
    import json
    status, out, err = run_cli(["check", "--json", *paths], cwd=folder)
    return status, [json.loads(line)["score"] for line in out.splitlines()], err


def test_check_grades_each_sheet_against_its_own_variant(drawn):
    c = drawn / "class"
    status, scores, err = grade(c, "keys/s1.yaml", "keys/s2.yaml")
    assert status == 0 and [s["percent"] for s in scores] == [100, 100], err
    answered(c / "s1.yaml", c / "keys" / "s1.yaml", c / "s1-own.yaml")
    answered(c / "s1.yaml", c / "keys" / "s2.yaml", c / "s1-copied.yaml")
    status, scores, _ = grade(c, "s1-own.yaml")
    assert status == 0 and scores[0]["percent"] == 100
    status, scores, _ = grade(c, "s1-copied.yaml")
    assert status == 1 and scores[0]["points"] < scores[0]["total"]
    status, scores, _ = grade(c, "s1.yaml")                        # the blank sheet
    assert status == 1 and scores[0]["points"] == 0


def test_existing_files_are_refused_before_any_is_written(drawn):
    before = files(drawn / "class")
    (drawn / "class" / "s2.yaml").write_text("mine\n")
    status, _, err = quiz(drawn, ROSTER + "s3,Cy\n")
    assert status == 2 and "class/s1.yaml: the file exists; use --force" in err
    now = files(drawn / "class")
    assert now["s2.yaml"] == b"mine\n" and "s3.yaml" not in now
    status, _, err = quiz(drawn, ROSTER, "--force")
    assert status == 0, err
    assert files(drawn / "class") == before


def test_a_robot_file_is_named_from_each_folder(tmp_path):
    from kincalc.conventions.library import load
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "arm.yaml").write_text(open(load("bk_rr").path).read())
    (tmp_path / "roster.csv").write_text("id\ns1\n")
    status, _, err = run_cli(["quiz", "robots/arm.yaml", "--roster", "roster.csv", "--salt",
                              "x", "--items", "fk", "-o", "class"], cwd=tmp_path)
    assert status == 0, err
    assert yaml.safe_load((tmp_path / "class/s1.yaml").read_text())["robot"] == "../robots/arm.yaml"
    key = tmp_path / "class/keys/s1.yaml"
    assert yaml.safe_load(key.read_text())["robot"] == "../../robots/arm.yaml"
    status, _, err = run_cli(["check", "class/keys/s1.yaml", "--robots-dir", "robots"],
                             cwd=tmp_path)
    assert status == 0, err
