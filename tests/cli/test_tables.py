"""Tables never drop data (issue 14, item 8).

For every command, at COLUMNS=60 and 80, every number of the result (taken from the
``--json`` document of the same command and formatted as the table formats it) is on
the screen, as often as the result holds it; every column header (joint names,
"limits", "singular") is there; no line is longer than COLUMNS and none ends in a space
(stdout is not a terminal here). A table too wide for the terminal is printed as
stacked panels, each repeating the row key; one that fits is printed as before.
"""

from __future__ import annotations

import io
import json
import re
from collections import Counter
from pathlib import Path

import pytest

from cli_contract import run_cli
from kincalc.cli.render import num
from kincalc.limits import MAX_JOINTS

ROOT = Path(__file__).parents[2]
EXAMPLES = ROOT / "examples"
P = 4  # the default --precision

Q6 = ["10", "-20", "30", "-90", "40", "80"]
Q7 = ["10", "-20", "30", "-90", "40", "80", "10"]
QS = [str((7 * i) % 40 - 20) for i in range(MAX_JOINTS)]      # the longest robot

NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def snake(folder: Path) -> str:
    """A robot file of MAX_JOINTS joints in ``folder``; returns its name relative to it."""
    lines = ["name: snake", f"title: A {MAX_JOINTS}-joint test snake", "convention: dh",
             "units: {length: m, angle: deg}", "joints:"]
    for i in range(MAX_JOINTS):
        lines.append(f"  - {{name: q{i + 1}, type: revolute, alpha: {90 if i % 2 == 0 else -90}, "
                     "a: 0.05, d: 0.02, theta: 0, limits: [-170, 170]}")
    (folder / "snake.yaml").write_text("\n".join(lines) + "\n", encoding="utf-8")
    return "snake.yaml"


# --- the numbers each command's table must show -------------------------------

def leaves(x):
    """Every number under ``x`` (nested lists and dicts), in order."""
    if isinstance(x, dict):
        for v in x.values():
            yield from leaves(v)
    elif isinstance(x, list):
        for v in x:
            yield from leaves(v)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        yield x


def fixed(values, precision=P):
    return [num(v, precision) for v in leaves(values)]


def g(x, precision=P):
    return f"{x:.{max(precision, 1)}g}"


def fk_numbers(d):
    o = d["orientation"]
    out = fixed([d["q"], d["T"], d["position"], o["rpy"], o["euler_zyz"], o["euler_xyz"],
                 o["quaternion"], o["axis_angle"], o["rotation_vector"], d["tcv"]])
    for f in d.get("frames", []):
        out += fixed([f["link"], f["T"]])
    return out


def jacobian_numbers(d):
    out = fixed([d["q"], d["J"], d["singular_values"], d["rank"]])
    out += fixed([d["manipulability"], d["position_manipulability"]], P + 2)
    if d["condition"] is not None:
        out += fixed(d["condition"])
    if d.get("singularity"):
        out += fixed([d["singularity"]["null_space"], d["singularity"]["lost_motion"]])
    return out


def target_numbers(d):
    T = d["target"]["T"]
    return fixed(T if d["target"]["orientation_given"] else [r[3] for r in T[:3]])


def ik_numbers(d):
    out = target_numbers(d)
    out += fixed([s["q"] for s in d["solutions"]])
    out += fixed([r["q"] for r in d.get("rejected") or []])
    return out


def reach_numbers(d):
    out = target_numbers(d)
    if d["distance"] is not None:
        out += fixed(d["distance"])
    if d["nearest"] is not None:
        out += fixed([d["nearest"]["position"], d["nearest"]["q"]])
    return out


def workspace_numbers(d):
    e, m = d["envelope"], d["manipulability"]
    out = fixed([d["samples"], d["seed"], e["min_distance"], e["max_distance"], e["z_min"],
                 e["z_max"]])
    out += [g(x) for x in [d["volume"], *d["volume_ci95"]]]
    if d["dexterous"]["defined"]:
        x = d["dexterous"]
        out += [g(v) for v in [x["volume"], *x["volume_ci95"]]]
        out += fixed([x["dexterous_points"], x["reachable_test_points"]])
    out += fixed([m["median"], m["p5"], m["p95"], m["max"]], P + 2)
    out += fixed([m["condition_median"], m["condition_p95"]], 2)
    return out


def list_numbers(d):
    return fixed([r["dof"] for r in d["robots"]])


def list_words(d):
    words = []
    for r in d["robots"]:
        words += [r["name"], r["structure"], r["convention"], r["units"], *r["title"].split()]
    return words


def show_numbers(d):
    r = d["robot"]
    out = []
    for j in r["joints"]:
        if j["limits"] is not None:
            out += fixed(j["limits"])
        if "axis" in j:
            out += fixed([j["axis"], j["point"]])
            continue
        rev = j["type"] == "revolute"
        for key in ("alpha", "a", "d", "theta"):
            v = j[key]
            variable = (key == "theta") == rev
            if not variable:
                out += fixed(v)
            elif abs(v) >= 10.0 ** -(P + 1):   # "q1 - 90.0000": the offset's size
                out += fixed(abs(v))
    out += fixed(r["home"])
    return out


def check_numbers(d):
    out = []
    for item in d["items"]:
        x = item["details"]
        if item["error"] is not None and item["kind"] != "ik":
            out.append(g(item["error"]))
        if item["kind"] == "ik":
            for s in x.get("sets", []):
                out += fixed([s["q"], s["residual"]])
            for m in x.get("missed", []):
                out += fixed(m["solution_q"])
        elif not item["passed"] and item["kind"] in ("link", "fk", "jacobian") \
                and "expected" in x:
            out += fixed(x["expected"])
    return out


def compare_numbers(d):
    out = []
    if d["position_error"] is not None:
        out += fixed([d["position_error"], d["orientation_error"], d["worst_q"],
                      d["samples"], d["seed"], d["length_scale"]])
    if d["allow_offsets"] or d["free_base"] or d["free_tool"]:
        out += fixed(d["offsets"])
    for key in ("base", "tool"):
        if d[key] is not None:
            out += fixed(d[key])
    return out


def selftest_numbers(d):
    out = [f"{d[k] * 100:.2f}" for k in ("success_rate", "missing_rate", "no_solution_rate",
                                         "wrong_solution_rate")]
    out += [str(d["trials"])]
    for k, v in d["solutions_per_pose"].items():
        out += [k, str(v)]
    return out


def joint_names(d):
    return [j["name"] for j in d["robot"]["joints"]] if "joints" in d["robot"] else []


# name: (argv, numbers(doc), headers(doc) the table must show as words)
CASES = {
    "fk-6": (["fk", "puma560", *Q6], fk_numbers, None),
    "fk-7-frames": (["fk", "panda", *Q7, "--frames"], fk_numbers, None),
    "fk-long": (["fk", "SNAKE", *QS], fk_numbers, None),
    "jacobian-6": (["jacobian", "puma560", "0", "45", "180", "0", "0", "0"],
                   jacobian_numbers, None),
    "jacobian-7": (["jacobian", "panda", *Q7], jacobian_numbers, None),
    "jacobian-long": (["jacobian", "SNAKE", *QS], jacobian_numbers, None),
    "ik-6": (["ik", "puma560", "--from-q", " ".join(Q6)], ik_numbers,
             lambda d: ["#", *[f"q{i}" for i in range(1, 7)], "limits", "singular"]),
    "ik-7": (["ik", "panda", "--from-q", " ".join(Q7)], ik_numbers,
             lambda d: ["#", *[f"joint{i}" for i in range(1, 8)], "limits", "singular"]),
    "ik-long": (["ik", "SNAKE", "--from-q", " ".join(QS)], ik_numbers,
                lambda d: [*[f"q{i}" for i in range(1, MAX_JOINTS + 1)], "limits", "singular"]),
    "ik-all-branches": (["ik", "bk_rr", "--xyz", "12.99", "2.5", "0", "--all-branches"],
                        ik_numbers, lambda d: ["theta1", "theta2", "why", "limits", "singular"]),
    "ik-6-all-branches": (["ik", "ur5", "--from-q", " ".join(Q6), "--all-branches"], ik_numbers,
                          lambda d: ["limits", "singular"]),
    "reach-6": (["reach", "puma560", "--xyz", "3", "0", "0"], reach_numbers, None),
    "reach-7": (["reach", "panda", "--from-q", " ".join(Q7)], reach_numbers, None),
    "workspace": (["workspace", "puma560", "--samples", "1000"], workspace_numbers, None),
    "workspace-planar": (["workspace", "planar_3r", "--samples", "1000"], workspace_numbers,
                         None),
    "robots-list": (["robots", "list"], list_numbers,
                    lambda d: ["name", "dof", "structure", "convention", "units", "title",
                               *list_words(d)]),
    "robots-show-dh": (["robots", "show", "puma560"], show_numbers,
                       lambda d: ["i", "θ_i", "d_i", "a_i", "α_i", "limits"]),
    "robots-show-mdh": (["robots", "show", "panda"], show_numbers,
                        lambda d: ["α_{i-1}", "a_{i-1}", "limits"]),
    "robots-show-poe": (["robots", "show", "ur5_poe"], show_numbers,
                        lambda d: ["type", "axis", "point", "limits"]),
    "robots-show-long": (["robots", "show", "SNAKE"], show_numbers, None),
    "check-fer": (["check", str(EXAMPLES / "homework_fer_rrpr.yaml")], check_numbers, None),
    "check-bk": (["check", str(EXAMPLES / "bk_example_4_6_book_answer.yaml")], check_numbers,
                 None),
    "compare": (["compare", "puma560", "puma560_mdh", "--allow-offsets"], compare_numbers, None),
    "compare-7": (["compare", "panda", "panda", "--free-base", "--free-tool"], compare_numbers,
                  None),
    "selftest": (["selftest", "ur5", "--trials", "20"], selftest_numbers, None),
}


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("tables")
    snake(d)
    return d


def run(argv, folder, monkeypatch, columns):
    argv = [snake(folder) if a == "SNAKE" else a for a in argv]
    monkeypatch.setenv("COLUMNS", str(columns))
    monkeypatch.delenv("NO_COLOR", raising=False)
    status, out, err = run_cli(argv, cwd=str(folder))
    assert status in (0, 1), f"kincalc {' '.join(argv)}: exit {status}: {err}"
    return out


@pytest.fixture(scope="module")
def documents(folder):
    """The --json document of each case, computed once."""
    cache = {}

    def get(name):
        if name not in cache:
            argv = [snake(folder) if a == "SNAKE" else a for a in CASES[name][0]]
            status, out, err = run_cli([*argv, "--json"], cwd=str(folder))
            assert status in (0, 1), err
            cache[name] = json.loads(out)
        return cache[name]
    return get


def missing(expected, text):
    """The entries of ``expected`` (with multiplicity) that ``text`` does not show."""
    have = Counter(NUMBER.findall(text))
    need = Counter(expected)
    return {k: n - have[k] for k, n in need.items() if have[k] < n}


@pytest.mark.parametrize("columns", [60, 80])
@pytest.mark.parametrize("name", list(CASES))
def test_every_number_of_the_result_is_on_the_screen(name, columns, folder, documents,
                                                     monkeypatch):
    argv, numbers, headers = CASES[name]
    doc = documents(name)
    out = run(argv, folder, monkeypatch, columns)
    lines = out.splitlines()
    long = [line for line in lines if len(line) > columns]
    assert not long, f"{len(long)} lines longer than {columns} columns: {long[:3]}"
    trailing = [line for line in lines if line != line.rstrip()]
    assert not trailing, f"{len(trailing)} lines end in a space: {trailing[:3]}"
    lost = missing(numbers(doc), out)
    assert not lost, f"numbers of the result not shown at {columns} columns: " \
                     f"{dict(list(lost.items())[:12])}\n{out}"
    if headers is not None:
        words = Counter(out.split())
        gone = [h for h in headers(doc) if not words[h]]
        assert not gone, f"not shown at {columns} columns: {gone[:12]}\n{out}"
    # whatever a wide terminal shows (every number), a narrow one shows too
    # (selftest's times differ from run to run)
    wide = run(argv, folder, monkeypatch, 1000)
    wide = "\n".join(line for line in wide.splitlines() if "time per pose" not in line)
    lost = missing(NUMBER.findall(wide), out)
    assert not lost, f"shown at 1000 columns but not at {columns}: " \
                     f"{dict(list(lost.items())[:12])}\n{out}"


def test_robots_list_is_readable_at_80_columns(monkeypatch, folder, documents):
    robots = documents("robots-list")["robots"]
    out = run(["robots", "list"], folder, monkeypatch, 80)
    lines = out.splitlines()
    # a row per panel (three panels at 80 columns since the ik column: the facts, the
    # units, the title) and a title wrapped to a few lines, not one word of a title per line
    assert len(lines) <= 5 * len(robots) + 10, f"{len(lines)} lines for {len(robots)} robots"
    flat = [" ".join(line.split()) for line in lines]
    cut = [r["name"] for r in robots
           if not any(" ".join(r["title"].split()[:3]) in line for line in flat)]
    assert not cut, f"titles cut into narrow pieces: {cut}"


# --- the mechanism: kincalc.cli.render.fit_table and the console -------------------

def wide_table(n=9, rows=3):
    from rich import box
    from rich.table import Table
    t = Table(box=box.SIMPLE_HEAD, title="3 solutions (deg, m)", title_justify="left")
    t.add_column("#", justify="right")
    for j in range(1, n + 1):
        t.add_column(f"joint{j}", justify="right", min_width=9)
    t.add_column("limits")
    for r in range(rows):
        t.add_row(str(r + 1), *(f"{-100 - 10 * r - j:.4f}" for j in range(n)), "ok")
    return t


def printed(monkeypatch, capsys, columns, *renderables):
    from kincalc.cli.render import console
    monkeypatch.setenv("COLUMNS", str(columns))
    capsys.readouterr()
    c = console()
    for r in renderables:
        c.print(r)
    return capsys.readouterr().out


def test_a_table_that_fits_is_printed_as_it_is(monkeypatch, capsys):
    from rich.console import Console

    from kincalc.cli.render import console, fit_table
    t = wide_table(n=3)
    monkeypatch.setenv("COLUMNS", "80")
    assert fit_table(console(), t) == [t]
    out = printed(monkeypatch, capsys, 80, t)
    plain = Console(width=80, file=io.StringIO(), color_system=None)
    with plain.capture() as cap:
        plain.print(t)
    assert out.splitlines() == [line.rstrip() for line in cap.get().splitlines()]


def test_a_wide_table_is_stacked_in_panels_that_repeat_the_key(monkeypatch, capsys):
    out = printed(monkeypatch, capsys, 60, wide_table())
    lines = out.splitlines()
    assert max(map(len, lines)) <= 60
    assert not [line for line in lines if line != line.rstrip()]
    words = out.split()
    for j in range(1, 10):
        assert words.count(f"joint{j}") == 1
    assert words.count("#") == 3 and words.count("limits") == 1   # three panels
    assert "3 solutions (deg, m)" in lines[0]
    assert sum("(continued)" in line for line in lines) == 2
    for r in range(3):
        for j in range(9):
            assert f"{-100 - 10 * r - j:.4f}" in words
        assert words.count(str(r + 1)) >= 3   # the row number in every panel


def test_panels_are_even(monkeypatch):
    from kincalc.cli.render import console, fit_table
    monkeypatch.setenv("COLUMNS", "80")
    panels = fit_table(console(), wide_table(n=7))
    # '#' and four columns twice, not six joints and then only joint7 and "limits"
    assert [len(p.columns) for p in panels] == [5, 5]


def test_a_headerless_matrix_names_the_columns_of_each_panel(monkeypatch, capsys):
    from kincalc.cli.render import matrix_table
    rows = [[1.0 + i + j / 10 for j in range(4)] for i in range(4)]
    out = printed(monkeypatch, capsys, 60, matrix_table(rows, 14, title="T"))
    assert "T (columns 1-2 of 4)" in out and "T (columns 3-4 of 4)" in out
    for v in (x for r in rows for x in r):
        assert f"{v:.14f}" in out.split()


def test_a_squeezed_text_column_gets_a_panel_of_its_own(monkeypatch, capsys):
    from rich import box
    from rich.table import Table
    t = Table(box=box.SIMPLE)
    for col in ("name", "dof", "structure", "convention", "units"):
        t.add_column(col, no_wrap=True)
    t.add_column("title")
    t.add_row("abb_irb6640", "6", "RRRRRR", "dh", "mm",
              "ABB IRB 6640-185/2.8, standard DH with ABB joint zero and directions")
    out = printed(monkeypatch, capsys, 60, t)
    assert "…" not in out
    assert "6640-185/2.8," in out.split()
    assert out.split().count("abb_irb6640") == 2


def test_a_word_longer_than_the_line_is_folded_not_cut(monkeypatch, capsys):
    from kincalc.cli.render import kv_table
    word = "R" * 70
    out = printed(monkeypatch, capsys, 60, kv_table([("structure", word)]))
    assert "".join(out.split()).count("R") == 70
    assert max(map(len, out.splitlines())) <= 60


def test_values_that_cannot_stand_beside_their_labels_go_below_them(monkeypatch, capsys):
    # at 40 columns fk's table of 17-digit numbers folded them: "50.588713227471998" with
    # "83" on the next line, read as two numbers; each label now goes above its values
    from kincalc.cli.render import kv_table
    values = ["50.58871322747199883 -41.39298764051999768 1216.85772721868897861",
              "32.92374895308900307 21.95818667743800034 157.51396159747099546"]
    out = printed(monkeypatch, capsys, 40, kv_table([("position", values[0]),
                                                     ("rpy (fixed X-Y-Z, deg)", values[1])]))
    assert NUMBER.findall(out) == " ".join(values).split()
    assert max(map(len, out.splitlines())) <= 40
    lines = [line.strip() for line in out.splitlines() if line.strip()]
    assert lines[0] == "position" and lines[4] == "rpy (fixed X-Y-Z, deg)"


def test_no_trailing_spaces_when_not_a_terminal():
    from kincalc.cli.render import _NoTrailingSpaces
    buf = io.StringIO()
    out = _NoTrailingSpaces(buf)
    out.write("a  \nb ")
    out.write(" c   \n\n   \nend ")
    assert buf.getvalue() == "a\nb  c\n\n\n"
    out.flush()   # a line without its newline is written whole
    assert buf.getvalue() == "a\nb  c\n\n\nend "
    assert out.isatty() is False


@pytest.mark.parametrize("columns", ["0", "1", "20", "-5", "abc", None])
def test_a_terminal_of_few_or_zero_columns_gets_tables_40_wide(monkeypatch, columns):
    """On a terminal, COLUMNS=0 printed nothing (exit 0) and COLUMNS=20 split numbers over
    lines: rich took COLUMNS as it was. The width is 40 at least, as when piped."""
    import sys

    from kincalc.cli.render import MIN_WIDTH, console
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True, raising=False)
    if columns is None:
        monkeypatch.delenv("COLUMNS", raising=False)
    else:
        monkeypatch.setenv("COLUMNS", columns)
    assert console().width >= MIN_WIDTH == 40


def test_jacobian_rows_are_labelled(monkeypatch):
    """Every row of the geometric and the analytic Jacobian carries its name (vx..wz, and
    the angle rates), also in every panel of a table split to fit the width."""
    from cli_contract import run_cli
    monkeypatch.setenv("COLUMNS", "50")
    status, out, err = run_cli(["jacobian", "puma560", "0", "45", "-90", "0", "30", "0",
                                "--analytic", "rpy"])
    assert status == 0, err
    first = [line.split()[0] for line in out.splitlines() if line.strip()]
    vx, wx, dyaw = first.count("vx"), first.count("wx"), first.count("dyaw")
    assert wx >= 2 and dyaw >= 2 and vx == wx + dyaw            # split, every panel labelled
    for k in ("vy", "vz", "wy", "wz"):
        assert first.count(k) == (vx if k[0] == "v" else wx)


def test_limit_violations_carry_their_unit_and_digits():
    """A prismatic joint 4.8 mm beyond its limit says so in metres with its digits, not
    "by 0.00" (whatever --precision is); an angle in degrees."""
    from cli_contract import run_cli
    status, out, err = run_cli(["ik", "stanford_arm", "--from-q", "10 20 1.2748 30 40 50",
                                "--precision", "2"])
    assert "d3 by 0.0048 m (upper)" in out, out
    status, out, err = run_cli(["reach", "stanford_arm", "--from-q", "10 20 1.2748 30 40 50"])
    assert "d3 0.0048 m beyond its upper limit 1.27 m" in out, out
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", "10 40 20 -60 30 50 -20", "--lock",
                                "A3=175"])
    assert "A3 by 5 deg (upper)" in out
