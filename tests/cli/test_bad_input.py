"""Bad input -> one clear line on stderr and exit status 2 (PRODUCT.md).

A catalogue of malformed robot files and bad command lines, each checked
through the real entry point ``kincalc.cli.main.main(argv)``. For every case:

* the exit status is 2;
* stderr is exactly one non-empty line, with no traceback and no
  "internal error";
* that line names the file (and the line, where the problem has one) and the
  field, and says what is wrong (the ``expect`` fragments);
* stdout is empty.

Robot files are written into ``tmp_path`` and checked twice: with
``kincalc robots validate FILE`` (the file named relative to the working
directory) and with ``kincalc fk FILE`` (the file named by absolute path).

The expectations are what a user deserves, not a transcript of today's
messages: a case that fails here is a bug to fix in the CLI, not in the test.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from kincalc.cli.main import main
from kincalc.errors import RobotFileError
from kincalc.limits import MAX_EXPRESSION, MAX_FILE_BYTES, MAX_JOINTS, MAX_NAME
from yaml_fuzz import bomb, padded

# ---------------------------------------------------------------------------
# Valid robot files the bad ones are derived from (each bad file changes one
# thing). ``test_templates_are_valid`` keeps them honest.

JOINTS_DH = """\
joints:
  - {name: q1, type: revolute, alpha: 90, a: 0, d: 0.1, theta: 0, limits: [-170, 170]}
  - {name: q2, type: revolute, alpha: 0, a: l1, d: 0, theta: 0, limits: [-90, 90]}
  - {name: q3, type: revolute, alpha: 0, a: l2, d: 0, theta: 0}
"""

DH = f"""\
name: arm3
title: Three-link test arm
convention: dh
units: {{length: m, angle: deg}}
parameters: {{l1: 0.3, l2: 0.25}}
{JOINTS_DH}\
base: {{xyz: [0, 0, 0.5], rpy: [0, 0, 90]}}
tool: {{xyz: [0, 0, 0.05]}}
home: [0, 30, -30]
"""

POE = """\
name: arm_poe
title: RP test arm (product of exponentials)
convention: poe
units: {length: m, angle: deg}
joints:
  - {name: q1, type: revolute, axis: [0, 0, 1], point: [0, 0, 0]}
  - {name: q2, type: prismatic, axis: [1, 0, 0], point: [0, 0, 0.2], limits: [0, 0.5]}
tool: {xyz: [0.3, 0, 0.2]}
home: [0, 0.1]
"""

IDENTITY_ROWS = "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"
BASE_LINE = "base: {xyz: [0, 0, 0.5], rpy: [0, 0, 90]}"


def sub(text: str, old: str, new: str) -> str:
    """``text`` with the one occurrence of ``old`` replaced by ``new``."""
    assert text.count(old) == 1, f"{old!r} must occur exactly once in the template"
    return text.replace(old, new)


def drop_line(text: str, start: str) -> str:
    """``text`` without the one line that starts with ``start``."""
    lines = text.splitlines(keepends=True)
    hits = [k for k, ln in enumerate(lines) if ln.startswith(start)]
    assert len(hits) == 1, f"exactly one line must start with {start!r}"
    del lines[hits[0]]
    return "".join(lines)


DIRECTORY = object()  # the "file" is a directory
MISSING = object()    # the file does not exist
ENDLESS = object()    # the "file" is a symbolic link to /dev/zero
PIPE = object()       # the "file" is a named pipe no process writes to


@dataclass(frozen=True)
class BadFile:
    id: str
    content: object            # str, bytes, DIRECTORY or MISSING
    expect: tuple[str, ...]    # fragments the stderr line must contain
    at: str | None = None      # the error's line is the one containing this text
    forbid: tuple[str, ...] = ()  # fragments that must NOT appear (unclear wording)
    exact: str | None = None   # the message after "FILE:LINE: ", exactly

    def line(self, text: str) -> int | None:
        if self.at is None:
            return None
        hits = [k for k, ln in enumerate(text.splitlines(), start=1) if self.at in ln]
        assert len(hits) == 1, f"{self.id}: {self.at!r} must be on exactly one line"
        return hits[0]


BAD_FILES = [
    # --- the file itself ----------------------------------------------------
    BadFile("empty-file", "", ("empty",)),
    BadFile("only-comments", "# a robot, some day\n\n# nothing here yet\n", ("empty",)),
    BadFile("non-utf8-latin1-title",
            sub(DH, "Three-link test arm", "K\u00fc\u00e7\u00fck test arm").encode("latin-1"),
            ("UTF-8",), at="title:"),
    BadFile("directory-not-file", DIRECTORY, ("directory",)),
    BadFile("missing-file", MISSING, ("no such file",)),
    BadFile("file-beyond-the-size-limit", padded(DH, MAX_FILE_BYTES + 1),
            ("the file is larger than 1 MiB, kincalc's limit for a robot file",)),
    BadFile("endless-file", ENDLESS, ("larger than 1 MiB",)),
    BadFile("pipe-without-writer", PIPE, ("a named pipe that no process writes to",)),

    # --- YAML syntax --------------------------------------------------------
    BadFile("yaml-syntax-error", sub(DH, "convention: dh", "convention: dh: mdh"),
            ("not valid YAML",), at="convention:"),
    BadFile("yaml-unclosed-bracket", sub(DH, "home: [0, 30, -30]", "home: [0, 30, -30"),
            ("not valid YAML",), at="home:"),
    BadFile("yaml-tab-indentation", sub(DH, "title:", "\ttitle:"),
            ("not valid YAML", "tab"), at="title:"),
    BadFile("yaml-control-character", sub(DH, "Three-link test arm", "Three-link\x07 arm"),
            ("not valid YAML", "control character"), at="title:",
            forbid=("<unicode string>", "position")),
    BadFile("yaml-two-documents", DH + "---\nname: arm4\n",
            ("not valid YAML", "document"), at="---", forbid=("YAML: but",)),
    BadFile("yaml-billion-laughs", sub(DH, "home: [0, 30, -30]", "home: " + bomb(9, "list")),
            ("'home' has 9 values",), at="home:"),
    BadFile("yaml-recursive-alias", sub(DH, JOINTS_DH, "joints: &j [*j]\n"),
            ("joint 1", "must be a mapping", "list"), at="joints:"),
    BadFile("yaml-python-tag-not-constructed",
            sub(DH, "d: 0.1,", "d: !!python/object/apply:os.system [touch pwned],"),
            ("the tag '!!python/object/apply:os.system' is not allowed",), at="name: q1"),
    BadFile("yaml-python-name-tag", sub(DH, "title: Three-link test arm",
                                        "title: !!python/name:os.system"),
            ("the tag '!!python/name:os.system' is not allowed", "plain YAML"), at="title:"),
    # a merge key: the user wrote no tag, so the message names the '<<'
    BadFile("yaml-merge-key", sub(DH, "tool: {xyz: [0, 0, 0.05]}",
                                  "tool: {<<: {xyz: [0, 0, 0.05]}}"),
            ("a merge key '<<' is not allowed; write its keys out", "plain YAML"), at="tool:"),
    BadFile("yaml-custom-tag", sub(DH, "d: 0.1,", "d: !metres 0.1,"),
            ("the tag '!metres' is not allowed",), at="name: q1"),

    # --- top level ----------------------------------------------------------
    BadFile("top-level-list", "- name: arm3\n- convention: dh\n", ("must be a mapping", "list")),
    BadFile("top-level-scalar", "arm3\n", ("must be a mapping", "a text of 4 characters")),
    # a one-line .env or token given as a robot file: its line is not shown (the tester saw
    # 38 of the 40 characters of a secret key quoted back)
    BadFile("top-level-one-line-secret",
            "AWS_SECRET_ACCESS_KEY=wJalrXUtnFEMI/K7MDENG/bPxRfiCYEXAMPLEKEY\n",
            ("must be a mapping", "a text of 62 characters", "is it a robot file?"),
            forbid=("AWS", "wJalr")),
    # a file that is no robot file (a key, a .env) is one text over its lines: the message
    # names line 1 and echoes nothing of the lines after it
    BadFile("top-level-text-over-lines", "-----BEGIN KEY-----\nS3CRET-LINE-2\nS3CRET-LINE-3\n",
            ("must be a mapping", "a text over lines 1-3"), forbid=("S3CRET", "BEGIN")),
    BadFile("number-over-two-lines", sub(DH, "alpha: 90,", 'alpha: "90 +\n      S3CRET",'),
            ("joint 1", "'alpha'", "a text over lines"), at="- {name: q1", forbid=("S3CRET",)),
    BadFile("block-text-as-convention", sub(DH, "convention: dh", "convention: |\n  S3CRET"),
            ("'convention'", "a text over lines"), at="convention:", forbid=("S3CRET",)),
    BadFile("missing-name", drop_line(DH, "name:"), ("'name' is missing",)),
    BadFile("missing-convention", drop_line(DH, "convention:"), ("'convention' is missing",)),
    BadFile("missing-units", drop_line(DH, "units:"), ("'units' is missing",)),
    BadFile("missing-joints", sub(DH, JOINTS_DH, ""), ("'joints' is missing",)),
    BadFile("unknown-top-level-key", sub(DH, "convention: dh", "convnetion: dh"),
            ("unknown key 'convnetion'", "did you mean 'convention'?"), at="convnetion"),
    BadFile("duplicate-top-level-key", sub(DH, "title:", "name: arm4\ntitle:"),
            ("'name'", "twice"), at="name: arm4"),
    BadFile("bad-name", sub(DH, "name: arm3", "name: 6-axis arm"),
            ("'name'", "'6-axis arm'", "must start with a letter (A-Z, a-z)"), at="name: 6-axis"),
    BadFile("unknown-convention", sub(DH, "convention: dh", "convention: craig"),
            ("'convention'", "'craig'", "dh, mdh, poe"), at="convention:"),
    BadFile("long-value-quoted-cut", sub(DH, "convention: dh", "convention: " + "c" * 5000),
            ("'convention'", "'" + "c" * 60 + "'... (5000 characters)"), at="convention:",
            forbid=("c" * 61,)),
    BadFile("long-key-quoted-cut",
            sub(DH, "convention: dh", "convention: dh\n? " + "k" * 5000 + "\n: 1"),
            ("unknown key", "(5000 characters)"), at="kkkk", forbid=("k" * 61,)),
    BadFile("units-not-a-mapping", sub(DH, "units: {length: m, angle: deg}", "units: m"),
            ("'units'", "mapping"), at="units:"),
    BadFile("unknown-length-unit", sub(DH, "length: m,", "length: furlong,"),
            ("'units.length'", "'furlong'", "m, cm, mm, in"), at="units:"),
    BadFile("unknown-angle-unit", sub(DH, "angle: deg}", "angle: grad}"),
            ("'units.angle'", "'grad'", "deg, rad"), at="units:"),

    # --- parameters ---------------------------------------------------------
    BadFile("parameters-not-a-mapping",
            sub(DH, "parameters: {l1: 0.3, l2: 0.25}", "parameters: [0.3, 0.25]"),
            ("'parameters'", "mapping"), at="parameters:"),
    BadFile("parameter-named-pi", sub(DH, "l2: 0.25}", "l2: 0.25, pi: 3.14}"),
            ("'pi'",), at="parameters:"),
    BadFile("parameter-key-not-a-name",
            sub(DH, "parameters: {l1: 0.3, l2: 0.25}", "parameters: {[l1]: 0.3, l2: 0.25}"),
            ("'parameters'", "plain names"), at="parameters:"),
    BadFile("parameter-division-by-zero", sub(DH, "l2: 0.25}", "l2: l1 / 0}"),
            ("parameter 'l2'", "division by zero"), at="parameters:"),

    # --- joints -------------------------------------------------------------
    BadFile("joints-not-a-list",
            sub(DH, JOINTS_DH, "joints: {name: q1, type: revolute, alpha: 0, a: 0, d: 0, theta: 0}\n"),
            ("'joints' must be a list", "mapping"), at="joints:"),
    BadFile("joints-empty", sub(DH, JOINTS_DH, "joints: []\n"), ("'joints' is empty",),
            at="joints:"),
    # 200 joints made quiz, workspace and fk --symbolic run for minutes
    BadFile("joints-too-many", sub(DH, JOINTS_DH, "joints:\n" + "".join(
        f"  - {{name: q{i}, type: revolute, alpha: 90, a: 0.01, d: 0, theta: 0}}\n"
        for i in range(MAX_JOINTS + 1))),
        (f"'joints' lists {MAX_JOINTS + 1} joints; kincalc takes robots of up to {MAX_JOINTS}",),
        at="  - {name: q0"),
    BadFile("joint-not-a-mapping",
            sub(DH, "  - {name: q2, type: revolute, alpha: 0, a: l1, d: 0, theta: 0, "
                    "limits: [-90, 90]}", "  - q2"),
            ("joint 2", "must be a mapping", "'q2'"), at="- q2"),
    BadFile("joint-missing-alpha", sub(DH, "alpha: 0, a: l2", "a: l2"),
            ("joint 3 (q3)", "'alpha' is missing"), at="name: q3",
            exact="joint 3 (q3): 'alpha' is missing"),
    BadFile("joint-missing-name", sub(DH, "name: q2, ", ""),
            ("joint 2", "'name' is missing"), at="a: l1"),
    BadFile("joint-empty-name", sub(DH, "name: q2,", 'name: "",'),
            ("joint 2", "'name'"), at="a: l1"),
    BadFile("joint-unknown-key", sub(DH, "alpha: 0, a: l1", "alpah: 0, a: l1"),
            ("joint 2 (q2)", "unknown key 'alpah'", "did you mean 'alpha'?"), at="name: q2"),
    BadFile("joint-duplicate-key", sub(DH, "d: 0.1,", "d: 0.1, d: 0.2,"),
            ("joint 1 (q1)", "'d'", "twice"), at="name: q1"),
    BadFile("joint-bad-type", sub(DH, "name: q2, type: revolute", "name: q2, type: rotary"),
            ("joint 2 (q2)", "'type'", "'rotary'", "revolute or prismatic"), at="name: q2"),
    BadFile("duplicate-joint-names", sub(DH, "name: q3", "name: q2"),
            ("joint 3 (q2)", "'q2'", "already used by joint 2"), at="a: l2"),
    BadFile("value-not-numeric", sub(DH, "d: 0.1,", "d: 0.1m,"),
            ("joint 1 (q1)", "'d'", "'0.1m'", "number"), at="name: q1"),
    BadFile("value-is-a-list", sub(DH, "a: l1,", "a: [l1],"),
            ("joint 2 (q2)", "'a'", "number", "list"), at="name: q2"),
    BadFile("value-empty", sub(DH, "a: l2, d: 0, theta: 0}", "a: l2, d: 0, theta: null}"),
            ("joint 3 (q3)", "'theta'", "empty"), at="name: q3"),
    BadFile("value-boolean-yes", sub(DH, "d: 0.1,", "d: yes,"),
            ("joint 1 (q1)", "'d'", "'yes'", "number"), at="name: q1"),
    BadFile("value-boolean-true", sub(DH, "alpha: 90,", "alpha: true,"),
            ("joint 1 (q1)", "'alpha'", "'true'", "number"), at="name: q1"),
    BadFile("value-nan", sub(DH, "d: 0.1,", "d: .nan,"),
            ("joint 1 (q1)", "'d'", ".nan", "number"), at="name: q1"),
    BadFile("value-minus-inf", sub(DH, "alpha: 90,", "alpha: -.inf,"),
            ("joint 1 (q1)", "'alpha'", "-.inf", "number"), at="name: q1"),
    BadFile("value-overflows-to-inf", sub(DH, "d: 0.1,", "d: 1e999,"),
            ("joint 1 (q1)", "'d'", "finite"), at="name: q1"),
    BadFile("value-5000-digits-quoted-cut", sub(DH, "d: 0.1,", "d: " + "1" * 5000 + ","),
            ("joint 1 (q1)", "'d'", "finite", "(5000 characters)"), at="name: q1",
            forbid=("1" * 61,)),
    BadFile("joint-name-cut", sub(DH, "name: q2, type: revolute", "name: " + "q" * 5000
                                  + ", type: rotary"),
            ("joint 2 (" + "q" * 60 + "...)", "'name' is 5000 characters long",
             f"up to {MAX_NAME}"), at="type: rotary", forbid=("q" * 61,)),
    # a joint's name heads a table's column: a newline in it split the table's lines
    BadFile("joint-name-newline", sub(DH, "name: q2,", 'name: "el\\nbow",'),
            ("joint 2", "'name' must not hold a control character"), at="el\\nbow"),
    # an escape sequence in the name reached the terminal through the error's "joint 2 (...)"
    BadFile("joint-name-escape", sub(DH, "name: q2,", 'name: "q\\e[31m2",'),
            ("joint 2 (q\ufffd[31m2)", "'name' must not hold a control character"),
            at='name: "q', forbid=("\x1b",)),
    # a no-break space was called a control character
    BadFile("joint-name-no-break-space", sub(DH, "name: q2,", 'name: "q\\u00a02",'),
            ("joint 2", "'name' must not hold a space other than ' ' (it holds U+00A0)"),
            at='name: "q'),
    BadFile("joint-name-65", sub(DH, "name: q2,", "name: " + "j" * (MAX_NAME + 1) + ","),
            ("joint 2", f"'name' is {MAX_NAME + 1} characters long"), at="j" * 60),
    BadFile("robot-name-65", sub(DH, "name: arm3", "name: a" + "r" * MAX_NAME),
            (f"'name' is {MAX_NAME + 1} characters long",), at="name: arr"),
    BadFile("expression-too-long", sub(DH, "a: l1,", "a: \"" + "+".join(["l1"] * 200) + "\","),
            ("joint 2 (q2)", f"expression longer than {MAX_EXPRESSION} characters"), at="name: q2"),
    # 201 parentheses deep, 403 characters: Python's parser refuses it (a SyntaxError)
    BadFile("expression-too-deep", sub(DH, "a: l1,", "a: \"" + "(" * 201 + "1" + ")" * 201 + "\","),
            ("joint 2 (q2)", "expression too deeply nested"), at="name: q2"),
    BadFile("expression-name-quoted-cut", sub(DH, "a: l1,", "a: " + "z" * 400 + ","),
            ("joint 2 (q2)", "unknown name", "(400 characters)"), at="name: q2"),
    BadFile("expression-unknown-name", sub(DH, "a: l2,", "a: l3 + 0.1,"),
            ("joint 3 (q3)", "'a'", "unknown name 'l3'", "l1, l2"), at="name: q3"),
    # a parameter uses those before it only: the message said "(parameters: none defined)"
    BadFile("parameter-names-a-later-one", sub(DH, "{l1: 0.3, l2: 0.25}",
                                               "{l1: l2, l2: 0.25}"),
            ("parameter 'l1'", "unknown name 'l2'", "a parameter may use only those before it"),
            at="parameters:"),
    BadFile("expression-division-by-zero", sub(DH, "a: l1,", "a: l1 / (l2 - 0.25),"),
            ("joint 2 (q2)", "'a'", "division by zero"), at="name: q2"),
    BadFile("expression-pi-in-degree-file", sub(DH, "alpha: 90,", "alpha: pi/2,"),
            ("joint 1 (q1)", "'alpha'", "'pi' is only allowed", "angle: rad"), at="name: q1"),
    BadFile("expression-power-not-allowed", sub(DH, "a: l1,", "a: l1 ** 2,"),
            ("joint 2 (q2)", "'a'", "only numbers"), at="name: q2"),
    # a joint named by an alias: its text is written on another line (an anchor's, here
    # line 1) than the one the message names, and is not shown (an independent tester)
    BadFile("joint-name-alias", "notes: &s 'API_KEY=sk-live-12345'\n" + sub(
        DH, "{name: q2, type: revolute, alpha: 0,", "{name: *s, type: revolute,"),
            ("joint 2", "'alpha' is missing"), at="name: *s", forbid=("API_KEY", "sk-live")),
    # Python reads names in NFKC form: the ligature 'ﬁ' was the parameter fi... (l1 here),
    # fullwidth letters a known name (an independent tester)
    BadFile("expression-nfkc-name", sub(DH, "a: l1,", "a: \"2*\uff4c1\","),
            ("joint 2 (q2)", "'a'", "unknown name '\uff4c1'"), at="name: q2"),
    BadFile("expression-ligature-name", sub(sub(DH, "l2: 0.25", "l2: 0.25, fi: 1"),
                                             "a: l1,", "a: \"\ufb01 + l1\","),
            ("joint 2 (q2)", "'a'", "unknown name '\ufb01'"), at="name: q2"),
    # Python's literal syntax inside an expression was read (0x10 + 1 = 17)
    BadFile("expression-hex-literal", sub(DH, "a: l1,", "a: 0x10 + l1,"),
            ("joint 2 (q2)", "'a'", "'0x10' is not a decimal number"), at="name: q2"),
    # a plain number in YAML 1.1's syntax was read (1_000 as 1000): decimal, as everywhere
    BadFile("number-underscores", sub(DH, "d: 0.1,", "d: 1_000,"),
            ("joint 1 (q1)", "'d'", "'1_000' is not a decimal number"), at="name: q1",
            forbid=(", in",)),
    BadFile("expression-underscore-literal", sub(DH, "a: l1,", "a: l1 * 1_0,"),
            ("joint 2 (q2)", "'a'", "'1_0' is not a decimal number"), at="name: q2"),
    BadFile("expression-int-too-large", sub(DH, "a: l1,", "a: l1 * 1" + "0" * 400 + ","),
            ("joint 2 (q2)", "'a'"), at="name: q2"),
    BadFile("expression-too-deeply-nested", sub(DH, "d: 0.1,", "d: " + "-" * 100_000 + "1,"),
            ("joint 1 (q1)", "'d'"), at="name: q1"),
    BadFile("limits-wrong-length", sub(DH, "limits: [-90, 90]", "limits: [-90]"),
            ("joint 2 (q2)", "'limits'", "2 entries", "not 1"), at="name: q2"),
    BadFile("limits-lower-above-upper", sub(DH, "limits: [-90, 90]", "limits: [90, -90]"),
            ("joint 2 (q2)", "'limits'", "lower <= upper"), at="name: q2"),
    BadFile("limits-not-a-list", sub(DH, "limits: [-90, 90]", "limits: 90"),
            ("joint 2 (q2)", "'limits'", "list"), at="name: q2"),

    # --- poe ----------------------------------------------------------------
    BadFile("poe-axis-zero", sub(POE, "axis: [0, 0, 1]", "axis: [0, 0, 0]"),
            ("joint 1 (q1)", "'axis'", "zero vector"), at="name: q1"),
    BadFile("poe-axis-not-unit", sub(POE, "axis: [1, 0, 0]", "axis: [2, 0, 0]"),
            ("joint 2 (q2)", "'axis'", "unit vector", "norm is 2"), at="name: q2"),
    BadFile("poe-point-wrong-length", sub(POE, "point: [0, 0, 0.2]", "point: [0, 0.2]"),
            ("joint 2 (q2)", "'point'", "3 entries", "not 2"), at="name: q2"),
    BadFile("poe-without-tool", drop_line(POE, "tool:"),
            ("'tool' is missing", "poe")),
    BadFile("poe-joint-with-dh-keys",
            sub(POE, "axis: [0, 0, 1], point: [0, 0, 0]", "alpha: 0, a: 0, d: 0, theta: 0"),
            ("joint 1 (q1)", "unknown key 'alpha'"), at="name: q1"),

    # --- base, tool, home ---------------------------------------------------
    BadFile("base-matrix-not-4x4",
            sub(DH, BASE_LINE, "base: {matrix: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]}"),
            ("'base'", "matrix", "4 entries", "not 3"), at="base:"),
    BadFile("base-matrix-short-row",
            sub(DH, BASE_LINE, "base: {matrix: [[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], "
                               "[0, 0, 0, 1]]}"),
            ("'base'", "matrix row 2", "4 entries", "not 3"), at="base:"),
    BadFile("base-matrix-not-rotation",
            sub(DH, BASE_LINE, "base: {matrix: [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], "
                               "[0, 0, 0, 1]]}"),
            ("'base'", "matrix", "not a rotation"), at="base:"),
    BadFile("base-matrix-reflection",
            sub(DH, BASE_LINE, "base: {matrix: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 0], "
                               "[0, 0, 0, 1]]}"),
            ("'base'", "matrix", "not a rotation"), at="base:"),
    BadFile("base-matrix-bad-last-row",
            sub(DH, BASE_LINE, "base: {matrix: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], "
                               "[0, 0, 0, 2]]}"),
            ("'base'", "matrix", "last row", "[0, 0, 0, 1]"), at="base:"),
    BadFile("base-matrix-and-xyz",
            sub(DH, BASE_LINE, f"base: {{matrix: {IDENTITY_ROWS}, xyz: [0, 0, 0.5]}}"),
            ("'base'", "either 'matrix' or 'xyz'/'rpy'"), at="base:"),
    BadFile("base-unknown-key", sub(DH, "rpy: [0, 0, 90]", "rpz: [0, 0, 90]"),
            ("'base'", "unknown key 'rpz'", "did you mean 'rpy'?"), at="base:"),
    BadFile("tool-xyz-wrong-length", sub(DH, "tool: {xyz: [0, 0, 0.05]}", "tool: {xyz: [0, 0.05]}"),
            ("'tool'", "xyz", "3 entries", "not 2"), at="tool:"),
    BadFile("home-wrong-length", sub(DH, "home: [0, 30, -30]", "home: [0, 30]"),
            ("'home'", "2 values", "3 joints"), at="home:"),
    BadFile("home-outside-limits", sub(DH, "home: [0, 30, -30]", "home: [0, 120, -30]"),
            ("'home'", "joint 2 (q2)", "outside its limits"), at="home:"),
    BadFile("home-not-numeric", sub(DH, "home: [0, 30, -30]", "home: [0, 30, abc]"),
            ("'home'", "'abc'"), at="home:"),
]


def _write(tmp_path: Path, case: BadFile) -> tuple[Path, str]:
    """Create the case's file as tmp_path/arm.yaml; return it and its text."""
    path = tmp_path / "arm.yaml"
    if case.content is DIRECTORY:
        path.mkdir()
        return path, ""
    if case.content is MISSING:
        return path, ""
    if case.content is ENDLESS:
        path.symlink_to("/dev/zero")
        return path, ""
    if case.content is PIPE:
        os.mkfifo(path)
        return path, ""
    data = case.content
    if isinstance(data, str):
        path.write_text(data, encoding="utf-8")
        return path, data
    path.write_bytes(data)
    return path, data.decode("latin-1")


def _one_line(err: str) -> str:
    assert err.endswith("\n") and err.count("\n") == 1, \
        f"stderr must be exactly one line, got {err!r}"
    line = err.rstrip("\n")
    assert line.strip(), "stderr line is empty"
    assert "Traceback" not in line
    assert "internal error" not in line, f"bad input reported as a bug: {line}"
    return line


def _check(case_id, status, out, err, expect, forbid=()):
    """Every problem with one run, reported together (actual status, stdout, stderr)."""
    problems = []
    if status != 2:
        problems.append(f"exit status {status}, not 2")
    if out != "":
        problems.append("stdout is not empty")
    if not (err.endswith("\n") and err.count("\n") == 1 and err.strip()):
        problems.append(f"stderr is {err.count(chr(10))} lines, not exactly one non-empty line")
    line = err.rstrip("\n")
    if "Traceback" in err:
        problems.append("stderr has a traceback")
    if "internal error" in err:
        problems.append("bad input reported as an internal error")
    if err and not line.startswith("kincalc"):
        problems.append("stderr does not start with 'kincalc'")
    missing = [f for f in expect if f not in line]
    if missing:
        problems.append(f"missing {missing}")
    present = [f for f in forbid if f in line]
    if present:
        problems.append(f"unclear wording {present}")
    assert not problems, (f"{case_id}: {'; '.join(problems)}\n"
                          f"  stderr: {err!r}\n  stdout: {out[:300]!r}")
    return line


def _robot_file_case(case: BadFile, command: str, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    path, text = _write(tmp_path, case)
    shown = "arm.yaml" if command == "validate" else str(path)
    argv = ["robots", "validate", shown] if command == "validate" else ["fk", shown]
    status = main(argv)
    out, err = capsys.readouterr()
    lineno = case.line(text)
    where = f"{shown}:{lineno}:" if lineno is not None else f"{shown}"
    msg = _check(f"{command} {case.id}", status, out, err, (where,) + case.expect, case.forbid)
    if case.exact is not None:
        assert msg.endswith(f"{shown}:{lineno}: {case.exact}"), msg


@pytest.mark.parametrize("case", BAD_FILES, ids=[c.id for c in BAD_FILES])
def test_robots_validate_rejects(case, tmp_path, monkeypatch, capsys):
    _robot_file_case(case, "validate", tmp_path, monkeypatch, capsys)


@pytest.mark.parametrize("case", BAD_FILES, ids=[c.id for c in BAD_FILES])
def test_fk_rejects_robot_file(case, tmp_path, monkeypatch, capsys):
    _robot_file_case(case, "fk", tmp_path, monkeypatch, capsys)


def test_a_robot_files_words_reach_no_terminal_as_escapes(tmp_path, monkeypatch, capsys):
    # a title, source or notes holding escape sequences (clear the screen, retitle the
    # terminal) was printed raw in the headings of fk, robots show and others, and in
    # compare's lines naming the two robots
    text = DH.replace("title: Three-link test arm",
                      'title: "x\\e[2J\\e]0;pwned\\a"\nsource: "s\\e[31m"\nnotes: "n\\x9b1m"')
    path = tmp_path / "esc.yaml"
    path.write_text(text)
    monkeypatch.setenv("COLUMNS", "200")
    for argv in (["fk", str(path), "10", "20", "30"], ["robots", "show", str(path)],
                 ["compare", str(path), str(path)]):
        assert main(argv) == 0
        out = capsys.readouterr().out
        assert "\x1b" not in out and "\x07" not in out and "\x9b" not in out
    assert main(["robots", "show", str(path)]) == 0
    assert "x\ufffd[2J\ufffd]0;pwned\ufffd" in capsys.readouterr().out


def test_catalogue_ids_are_unique():
    ids = [c.id for c in BAD_FILES] + [c.id for c in BAD_COMMANDS]
    assert len(ids) == len(set(ids))
    assert len(BAD_FILES) >= 30 and len(BAD_COMMANDS) >= 10


# ---------------------------------------------------------------------------
# Bad command lines (bundled robots: bk_rr is a unitless 2R arm, puma560 6R).

@dataclass(frozen=True)
class BadCommand:
    id: str
    argv: tuple[str, ...]
    expect: tuple[str, ...]
    forbid: tuple[str, ...] = field(default=())


BAD_COMMANDS = [
    BadCommand("no-command-args", (), ("command", "kincalc --help"),
               forbid=("Usage:", "Options:")),  # one line, not the whole help
    BadCommand("unknown-command", ("frobnicate",), ("'frobnicate'",)),
    BadCommand("fk-missing-robot", ("fk",), ("Missing argument 'ROBOT'",)),
    BadCommand("validate-no-files", ("robots", "validate"), ("Missing argument 'FILE...'",)),
    BadCommand("unknown-robot-name", ("fk", "pum560", "0", "0", "0", "0", "0", "0"),
               ("'pum560'", "did you mean 'puma560'")),
    BadCommand("unknown-robot-name-jacobian", ("jacobian", "ur5ee"),
               ("'ur5ee'", "did you mean 'ur5e'")),
    # an empty name is no robot; it was the working folder ('.: is a directory')
    BadCommand("empty-robot-name", ("fk", ""), ("no robot named ''",), forbid=("directory",)),
    BadCommand("empty-robot-name-show", ("robots", "show", ""), ("no robot named ''",),
               forbid=("directory", "'.'")),
    # a negative seed reached numpy (ValueError: an internal error, exit 3)
    BadCommand("compare-negative-seed", ("compare", "bk_rr", "bk_rr", "--seed", "-1"),
               ("--seed", "-1", "range 0 to")),
    BadCommand("robots-show-missing-file", ("robots", "show", "nope.yaml"),
               ("nope.yaml", "no such file")),
    BadCommand("robots-show-unknown-name", ("robots", "show", "stanfrod_arm"),
               ("'stanfrod_arm'", "did you mean 'stanford_arm'")),
    BadCommand("too-few-joint-values", ("fk", "bk_rr", "30"),
               ("bk_rr has 2 joints", "theta1, theta2", "got 1 joint value")),
    BadCommand("too-many-joint-values", ("fk", "bk_rr", "30", "-60", "10"),
               ("bk_rr has 2 joints", "got 3 joint values")),
    BadCommand("too-few-joint-values-jacobian", ("jacobian", "puma560", "0", "-45"),
               ("puma560 has 6 joints", "got 2 joint values")),
    # an option given no joint values is too few values, not the home configuration
    # (--from-q "$Q" with Q unset must not answer for the home pose)
    BadCommand("from-q-empty", ("ik", "puma560", "--from-q", ""),
               ("--from-q", "puma560 has 6 joints", "got 0 joint values")),
    BadCommand("from-q-blank-reach", ("reach", "puma560", "--from-q", " , "),
               ("--from-q", "got 0 joint values")),
    BadCommand("near-empty", ("ik", "bk_rr", "--xyz", "12", "2", "0", "--near", ""),
               ("--near", "bk_rr has 2 joints", "got 0 joint values")),
    BadCommand("non-numeric-joint-value", ("fk", "bk_rr", "30", "abc"),
               ("joint value 'abc'", "not a number")),
    BadCommand("joint-value-nan", ("fk", "bk_rr", "30", "nan"), ("finite",)),
    BadCommand("unknown-option-fk", ("fk", "bk_rr", "30", "-60", "--frmaes"),
               ("--frmaes", "--frames")),  # a did-you-mean, as click gives elsewhere
    BadCommand("unknown-option-robots-show", ("robots", "show", "bk_rr", "--jsno"),
               ("--jsno", "--json")),
    BadCommand("bad-unit", ("fk", "puma560", "--unit", "furlong"),
               ("--unit", "'furlong'", "m, cm, mm, in")),
    BadCommand("unit-missing-value", ("fk", "bk_rr", "--unit"),
               ("--unit", "requires an argument")),
    BadCommand("unit-on-unitless-robot", ("fk", "bk_rr", "--unit", "mm"),
               ("'bk_rr'", "unitless", "--unit")),
    BadCommand("bad-frame", ("jacobian", "puma560", "--frame", "world"),
               ("--frame", "'world'", "'base'", "'tool'")),
    BadCommand("bad-analytic", ("jacobian", "puma560", "--analytic", "quat"),
               ("--analytic", "'quat'", "'rpy'", "'zyz'", "'xyz'")),
    BadCommand("negative-precision", ("fk", "bk_rr", "--precision", "-1"),
               ("--precision", "-1")),
    BadCommand("precision-too-large", ("fk", "bk_rr", "--precision", "99"),
               ("--precision", "99")),

    # --- issue 14: bounded reads and bounded requests -------------------------
    BadCommand("robot-file-endless", ("fk", "/dev/zero"),
               ("/dev/zero", "larger than 1 MiB, kincalc's limit for a robot file")),
    BadCommand("robot-path-too-long", ("fk", "a" * 300 + ".yaml"),
               ("cannot read: the name is too long for a file",)),
    BadCommand("pose-file-endless", ("ik", "puma560", "--pose", "/dev/zero"),
               ("--pose /dev/zero", "larger than 1 MiB")),
    BadCommand("pose-file-missing", ("ik", "puma560", "--pose", "nope.txt"),
               ("--pose nope.txt", "no such file")),
    BadCommand("pose-file-name-too-long", ("ik", "puma560", "--pose", "p" * 300),
               ("--pose", "the name is too long for a file")),
    BadCommand("sheet-endless", ("check", "/dev/zero"),
               ("/dev/zero", "a sheet must be a regular file")),
    BadCommand("check-robots-dir-missing", ("check", "hw.yaml", "--robots-dir", "nope"),
               ("--robots-dir nope", "no such folder")),
    BadCommand("workspace-samples-beyond-the-limit",
               ("workspace", "bk_rr", "--samples", "1000000000"), ("--samples", "5000000")),
    BadCommand("workspace-seed-negative", ("workspace", "bk_rr", "--seed", "-1"),
               ("--seed", "-1", "range 0 to")),
    # integer options took what click's int takes: 1_0 as 10, other scripts' digits, any size
    BadCommand("selftest-seed-underscore", ("selftest", "bk_rr", "--seed", "1_0"),
               ("--seed", "1_0", "not a whole number")),
    BadCommand("selftest-trials-arabic-indic", ("selftest", "bk_rr", "--trials", "\u0663"),
               ("--trials", "not a whole number")),
    BadCommand("compare-seed-beyond-2-63", ("compare", "bk_rr", "bk_rr", "--seed", "9" * 20),
               ("--seed", "range 0 to 9223372036854775807")),
    BadCommand("workspace-orientations-beyond-the-limit",
               ("workspace", "puma560", "--orientations", "100000000"),
               ("--orientations", "1000")),
    BadCommand("selftest-trials-beyond-the-limit",
               ("selftest", "bk_rr", "--trials", "100000000"), ("--trials", "1000000")),
]

#: every command that takes a ROBOT, with the other arguments it needs
ROBOT_COMMANDS = [("fk", "{}"), ("jacobian", "{}"), ("plot", "{} 0 0 -o x.png"),
                  ("view", "{} -o x.html"),
                  ("quiz", "{}"), ("compare", "bk_rr {}"), ("compare", "{} bk_rr"),
                  ("robots show", "{}"), ("ik", "{} --xyz 1 0 0"), ("reach", "{} --xyz 1 0 0"),
                  ("workspace", "{}"), ("selftest", "{}"), ("convert", "{} --to dh")]
BAD_COMMANDS += [
    BadCommand(f"robot-name-too-long-{cmd.replace(' ', '-')}-{k}",
               tuple(cmd.split()) + tuple(args.format("a" * 300).split()),
               ("no robot named '" + "a" * 60 + "'... (300 characters)",), forbid=("a" * 61,))
    for k, (cmd, args) in enumerate(ROBOT_COMMANDS)]


@pytest.mark.parametrize("case", BAD_COMMANDS, ids=[c.id for c in BAD_COMMANDS])
def test_bad_command_line(case, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # so "nope.yaml" really is missing
    status = main(list(case.argv))
    out, err = capsys.readouterr()
    _check(case.id, status, out, err, case.expect, case.forbid)


# ---------------------------------------------------------------------------
# --debug, valid files, several files at once.

def _bad_alpha_file(tmp_path: Path) -> Path:
    path = tmp_path / "arm.yaml"
    path.write_text(sub(DH, "alpha: 0, a: l2", "a: l2"), encoding="utf-8")
    return path


@pytest.mark.parametrize("command", [["fk"], ["robots", "validate"]])
def test_debug_shows_the_traceback_and_keeps_the_status(command, tmp_path, capsys):
    # --debug re-raised the error: Python then exited 1, not the error's 2
    path = _bad_alpha_file(tmp_path)
    assert main([*command, str(path), "--debug"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("Traceback (most recent call last):")
    assert "RobotFileError" in err and err.rstrip().splitlines()[-1].startswith("kincalc: error:")
    assert "joint 3 (q3): 'alpha' is missing" in err.rstrip().splitlines()[-1]


def test_debug_before_the_command_is_a_usage_error_without_a_traceback(capsys):
    # `kincalc --debug fk puma560` printed click's traceback for "No such option" (exit 1)
    assert main(["--debug", "fk", "puma560"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "No such option '--debug'" in err


@pytest.mark.parametrize("text, summary", [(DH, "arm3, 3 joints, dh"),
                                           (POE, "arm_poe, 2 joints, poe")],
                         ids=["dh", "poe"])
def test_templates_are_valid(text, summary, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm.yaml").write_text(text, encoding="utf-8")
    assert main(["robots", "validate", "arm.yaml"]) == 0
    out, err = capsys.readouterr()
    assert out == f"ok: arm.yaml: {summary}\n"
    assert err == ""
    assert main(["fk", "arm.yaml", "--json"]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("{") and err == ""


def test_validate_good_and_bad_files(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "good.yaml").write_text(DH, encoding="utf-8")
    (tmp_path / "bad.yaml").write_text(sub(DH, "angle: deg}", "angle: grad}"), encoding="utf-8")
    status = main(["robots", "validate", "good.yaml", "bad.yaml"])
    out, err = capsys.readouterr()
    assert out == "ok: good.yaml: arm3, 3 joints, dh\n"
    line = _one_line(err)
    assert "bad.yaml:4:" in line and "'units.angle'" in line and "'grad'" in line
    assert status == 2


def test_pose_from_stdin_is_bounded():
    from cli_contract import assert_contract, run_cli
    argv = ["ik", "puma560", "--pose", "-"]
    status, out, err = run_cli(argv, stdin=b"0 " * MAX_FILE_BYTES)
    assert_contract(status, out, err, argv)
    assert status == 2 and out == "" and "--pose -: larger than 1 MiB" in err
    status, out, err = run_cli(argv, stdin=b"[" * 100_000)          # nested too deeply
    assert status == 2 and "--pose -" in err and "internal error" not in err
    status, out, err = run_cli(argv, stdin=b"\xff\xfe")
    assert status == 2 and "not UTF-8" in err
