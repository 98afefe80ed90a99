"""Fuzz: homework sheets are untrusted input (issue 14).

A teacher runs ``kincalc check`` on students' files, and a student controls every
byte of them. Hypothesis (seeded: ``derandomize=True``, no example database)
mutates the sheets ``kincalc quiz`` writes and the shipped examples
(:mod:`yaml_fuzz`: keys deleted, duplicated, retyped, anchors, alias bombs, tags,
junk, ...), points their ``robot:`` anywhere (the sheet's folder, a sub-folder, a
``--robots-dir`` folder, a symbolic link leading out, ``..``, an absolute path,
``/etc/passwd``, ``/dev/zero``, a FIFO, a name too long, a NUL character, an
inline robot) and gives them too many items. Around the sheet's folder sit
files holding a secret: a YAML file and a valid robot file outside the folder,
and another student's sheet inside it. The invariants, whatever the sheet:

* exit status 0, 1 or 2 (3 is a bug), at most one stderr line, no traceback,
  every JSON document strict (:mod:`cli_contract`);
* the secret never appears on stdout or stderr: no file outside the allowed
  folders is read, and no file other than the sheet is quoted;
* an error names the sheet and is short, however long the sheet's values are;
* nothing in or around the folder is written or changed, and no YAML tag is
  constructed (nothing executed).
"""

from __future__ import annotations

import json
import os
import re
import tempfile
import time
from pathlib import Path

import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from cli_contract import assert_contract, json_documents, run_cli, snapshot
from kincalc.limits import MAX_SHEET_ITEMS
from yaml_fuzz import mutate

ROOT = Path(__file__).parents[2]
SECRET = "KINCALC-SECRET-SHEET-9c41d7"
#: the stderr line of a rejected sheet is this long at most, plus the command line's
MAX_ERROR = 700
#: cases of the main fuzz test (~20 s on one free core); issue 14's fuzz budget is 60-90 s
#: for the robot-file and sheet fuzz files together (both: ~50 s on one free core)
EXAMPLES = 600
FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=EXAMPLES,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

ARM = (ROOT / "robots" / "bk_rr.yaml").read_text(encoding="utf-8").replace("name: bk_rr",
                                                                           "name: arm")


def _quiz(robot: str) -> str:
    status, out, err = run_cli(["quiz", robot, "--seed", "3", "--answers"])
    assert status == 0, err
    return out


#: valid sheets to mutate: quiz sheets (every kind of item) and the shipped examples
SEEDS = {**{f"quiz {r}": _quiz(r) for r in ("bk_rr", "planar_3r", "bk_rrp", "puma560",
                                              "fer_rrpr", "bk_scara_euler")},
         **{p.name: p.read_text(encoding="utf-8")
            for p in sorted((ROOT / "examples").glob("*.yaml"))}}
#: what a sheet's robot: may say; "{TMP}" is the folder around the sheet's folder
INSIDE = ["bk_rr", "arm.yaml", "./arm.yaml", "sub/arm.yaml", "sub/../arm.yaml", "inlink.yaml",
          "robots/course.yaml", "{TMP}/work/arm.yaml", "../work/arm.yaml"]
OUTSIDE = ["link.yaml", "linkdir/arm.yaml", "../outside/arm.yaml", "../secret.yaml",
           "sub/../../secret.yaml", "{TMP}/outside/arm.yaml", "{TMP}/secret.yaml", "pw",
           "/etc/passwd", "/dev/zero", "/proc/self/environ", "..", "../",
           "{TMP}", "/"]
ODD = ["~/.bashrc", "other.yaml", "hw.yaml", "course.yaml", "fifo.yaml", "sub", ".", "",
       "nope.yaml", "a" * 300, "a/" * 2100, "arm.yaml\0.txt", "..\\secret.yaml", "%2e%2e/secret.yaml",
       "file:///etc/passwd", "x" * 5000, "arm.yaml ", "ARM.YAML", "bk_rr.yaml", "puma560"]
REFS = INSIDE + OUTSIDE + ODD
#: the robot as an inline robot (the name left out, as a sheet may)
INLINE = "robot:\n" + "".join(
    "  " + line for line in yaml.safe_dump(
        {k: v for k, v in yaml.safe_load(ARM).items() if k not in ("name", "source", "notes")},
        sort_keys=False, allow_unicode=True, default_flow_style=None).splitlines(keepends=True))


def world(tmp: Path) -> Path:
    """The files around a sheet; returns the sheet's folder (``tmp/work``)."""
    (tmp / "secret.yaml").write_text(f"name: {SECRET}\nsecret: {SECRET}\n")
    (tmp / "passwd").write_text(f"root:x:0:0:{SECRET}:/root:/bin/bash\n")
    (tmp / "outside").mkdir()
    (tmp / "outside" / "arm.yaml").write_text(ARM.replace("title: Planar", f"title: {SECRET}"))
    work = tmp / "work"
    (work / "sub").mkdir(parents=True)
    (work / "robots").mkdir()
    for path in ("arm.yaml", "sub/arm.yaml", "robots/course.yaml"):
        (work / path).write_text(ARM)
    # another student's sheet, in the same folder
    (work / "other.yaml").write_text(f"student: {SECRET}\nrobot: bk_rr\nitems:\n"
                                     f"  - {{id: '{SECRET}', kind: singular, q: [0, 0], "
                                     "answer: yes}\n")
    os.symlink("../outside/arm.yaml", work / "link.yaml")
    os.symlink("../outside", work / "linkdir")
    os.symlink("../passwd", work / "pw")
    os.symlink("arm.yaml", work / "inlink.yaml")
    os.mkfifo(work / "fifo.yaml")
    return work


def with_robot(text: str, ref: str | None) -> str:
    """``text`` with its top-level ``robot:`` line saying ``ref`` (None: the inline robot)."""
    line = INLINE if ref is None else f"robot: {json.dumps(ref)}\n"
    return re.sub(r"(?m)^robot:.*\n", lambda _: line, text, count=1)


def many_items(text: str, n: int) -> str:
    """``text`` with ``n`` items, copies of its first one with their own ids."""
    doc = yaml.safe_load(text)
    first = doc["items"][0]
    doc["items"] = [dict(first, id=f"c{k}") for k in range(n)]
    return yaml.safe_dump(doc, sort_keys=False, allow_unicode=True, width=10 ** 6)


@st.composite
def cases(draw):
    """(sheet bytes, extra options) of one run."""
    text = SEEDS[draw(st.sampled_from(sorted(SEEDS)))]
    how = draw(st.sampled_from(["ref", "ref", "ref", "inline", "keep", "items"]))
    if how == "ref":
        text = with_robot(text, draw(st.sampled_from(REFS)))
    elif how == "inline":
        text = with_robot(text, None)
    elif how == "items":
        text = many_items(text, draw(st.sampled_from([MAX_SHEET_ITEMS + 1, 2 * MAX_SHEET_ITEMS,
                                                      3000])))
    data = text.encode("utf-8")
    if how != "items" and draw(st.integers(0, 3)):
        data = draw(mutate(text, values=[json.dumps(r) for r in REFS] + ["*undefined"],
                           keys=["robot", "items", "tolerance"]))
    options = draw(st.sampled_from([["--json"], ["--json"], [], ["--quiet"]]))
    if draw(st.booleans()):
        options.append("--robots-dir=robots")
    return data, options


def exercise(data: bytes, options) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        work = world(Path(tmp))
        (work / "hw.yaml").write_bytes(data.replace(b"{TMP}", tmp.encode()))
        before = snapshot(tmp)
        argv = ["check", "hw.yaml", *options]
        t0 = time.perf_counter()
        status, out, err = run_cli(argv, cwd=work)
        took = time.perf_counter() - t0
        assert_contract(status, out, err, argv)
        assert took < 30, f"grading took {took:.1f} s"
        assert "internal error" not in err, err[:500]
        assert SECRET not in out and SECRET not in err, \
            f"a file other than the sheet was read or quoted: {(err or out)[:300]}"
        if status == 2:
            assert err.startswith("kincalc"), err[:300]
            assert "hw.yaml" in err or "--robots-dir" in err, err[:300]
            assert len(err) <= MAX_ERROR, f"a {len(err)}-character error line: {err[:300]}"
        elif "--json" in argv:
            assert len(json_documents(out)) == 1
        assert snapshot(tmp) == before, "a file was written or changed"
        assert not (work / "pwned").exists()
        return status


@FUZZ
@given(cases())
def test_mutated_sheets_keep_the_contract(case):
    event(f"check: exit {exercise(*case)}")


def test_the_seeds_are_valid_and_every_inside_robot_loads():
    for name, text in SEEDS.items():
        assert exercise(text.encode(), ["--json"]) in (0, 1), name
    text = SEEDS["quiz bk_rr"]
    for ref in INSIDE + [None]:
        assert exercise(with_robot(text, ref).encode(), ["--json", "--robots-dir", "robots"]) \
            == 0, ref


def test_every_outside_robot_is_refused_as_outside():
    text = SEEDS["quiz bk_rr"]
    for ref in OUTSIDE:
        with tempfile.TemporaryDirectory() as tmp:
            work = world(Path(tmp))
            (work / "hw.yaml").write_text(with_robot(text, ref).replace("{TMP}", tmp))
            for extra in ([], ["--robots-dir", "robots"]):
                status, out, err = run_cli(["check", "hw.yaml", *extra], cwd=work)
                assert status == 2 and out == "", (ref, err)
                assert "is outside the sheet's folder" in err, (ref, err)
                assert SECRET not in err
