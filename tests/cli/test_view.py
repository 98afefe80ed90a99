"""``kincalc view``: where the page goes (-o FILE, -o -, a temporary file when there is a
display, standard output when there is none), --open, the pose options, bad input.

(The page itself: tests/analysis/test_view_page.py as text, test_view_browser.py running.)
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from cli_contract import assert_contract, run_cli

URDF = Path(__file__).parents[1] / "conventions" / "urdf"
PUMA_Q = ["10", "-30", "150", "20", "40", "30"]


def run(*argv, cwd=None):
    status, out, err = run_cli(list(argv), b"", cwd)
    assert_contract(status, out, err, list(argv))
    return status, out, err


def data_of(page: str) -> dict:
    (text,) = re.findall(r'id="kincalc-data">(.*?)</script>', page, re.S)
    return json.loads(text)


@pytest.fixture
def no_display(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")


@pytest.fixture
def display(monkeypatch, tmp_path):
    """A display, and the temporary folder in tmp_path."""
    import tempfile
    monkeypatch.setenv("DISPLAY", ":0")
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    return tmp_path


def test_output_file_is_written_quietly(tmp_path, no_display):
    page = tmp_path / "puma.html"
    status, out, err = run("view", "puma560", *PUMA_Q, "-o", str(page))
    assert (status, out, err) == (0, "", "")
    data = data_of(page.read_text(encoding="utf-8"))
    assert data["robot"]["name"] == "puma560" and data["ik"] is None
    assert data["q"] == pytest.approx([float(v) * 3.141592653589793 / 180 for v in PUMA_Q])
    # an existing page is replaced only with --force
    status, _, err = run("view", "puma560", "-o", str(page))
    assert status == 2 and "the file exists; use --force" in err
    assert run("view", "bk_rr", "-o", str(page), "--force")[0] == 0
    assert data_of(page.read_text(encoding="utf-8"))["robot"]["name"] == "bk_rr"


def test_the_page_is_html_by_name(tmp_path):
    status, _, err = run("view", "puma560", "-o", str(tmp_path / "arm.png"))
    assert status == 2
    assert err.endswith("arm.png: the page is HTML; give a file name ending in .html\n")
    assert run("view", "puma560", "-o", str(tmp_path / "arm.HTM"))[0] == 0


def test_dash_and_no_display_mean_standard_output(no_display):
    status, out, err = run("view", "bk_rr", "-o", "-")
    assert status == 0 and err == "" and out.startswith("<!DOCTYPE html>")
    status, out2, err = run("view", "bk_rr")           # stdout is not a terminal here
    assert status == 0 and err == "" and out2 == out


def test_no_display_and_a_terminal_asks_for_a_file(no_display, monkeypatch):
    monkeypatch.setattr("sys.stdout.isatty", lambda: True, raising=False)
    from kincalc.cli.main import main
    status = main(["view", "bk_rr"])
    assert status == 2


def test_with_a_display_a_new_file_and_where_it_is(display):
    status, out, err = run("view", "puma560")
    assert status == 0 and out == ""
    (path,) = re.findall(r"^kincalc: wrote (\S+) \(open it in a web browser\)\n$", err)
    assert Path(path).parent.parent == display and Path(path).name == "puma560.html"
    assert data_of(Path(path).read_text(encoding="utf-8"))["robot"]["name"] == "puma560"
    # a robot file's name becomes the page's, tamed
    robot = display / "my arm!.yaml"
    robot.write_text((Path(__file__).parents[2] / "robots" / "bk_rr.yaml").read_text())
    status, _, err = run("view", str(robot))
    assert status == 0 and err.rstrip().endswith("/my_arm.html (open it in a web browser)")


def test_open_opens_the_page(display, monkeypatch):
    import webbrowser
    opened = []
    monkeypatch.setattr(webbrowser, "open", lambda url: opened.append(url) or True)
    status, _, err = run("view", "bk_rr", "--open")
    assert status == 0 and "; opening it in the web browser" in err
    assert opened and opened[0].startswith("file:///") and opened[0].endswith("/bk_rr.html")
    page = display / "given.html"
    assert run("view", "bk_rr", "--open", "-o", str(page)) == (0, "", "")
    assert opened[1] == page.resolve().as_uri()
    monkeypatch.setattr(webbrowser, "open", lambda url: False)
    status, _, err = run("view", "bk_rr", "--open", "-o", str(display / "again.html"))
    assert status == 0 and "no web browser could be started" in err


def test_open_needs_a_display_and_a_file(no_display, tmp_path):
    status, _, err = run("view", "bk_rr", "--open", "-o", str(tmp_path / "a.html"))
    assert status == 2 and "--open: there is no display" in err
    status, _, err = run("view", "bk_rr", "--open", "-o", "-")
    assert status == 2 and "--open needs a file to open" in err


def test_a_pose_embeds_every_ik_solution(tmp_path):
    page = tmp_path / "puma.html"
    status, _, err = run("view", "puma560", *PUMA_Q, "--from-q", " ".join(PUMA_Q),
                         "-o", str(page))
    assert status == 0, err
    ik = data_of(page.read_text(encoding="utf-8"))["ik"]
    assert ik["command"] == "ik" and ik["count"] == 8 and len(ik["solutions"]) == 8
    # the same answer as kincalc ik, ordered from the joints the page opens at
    _, out, _ = run("ik", "puma560", "--from-q", " ".join(PUMA_Q), "--near", " ".join(PUMA_Q),
                    "--json")
    assert [s["q"] for s in ik["solutions"]] == [s["q"] for s in json.loads(out)["solutions"]]
    # a textbook example, position only: Example 4.2's two branches
    status, _, _ = run("view", "bk_rr", "--xyz", "12.99", "2.5", "0", "-o",
                       str(tmp_path / "rr.html"))
    ik = data_of((tmp_path / "rr.html").read_text(encoding="utf-8"))["ik"]
    assert status == 0 and [s["branch"] for s in ik["solutions"]] == ["elbow down", "elbow up"]


def test_the_configuration_the_page_opens_at_is_the_first_solution(tmp_path):
    # PUMA_Q's q3 = 150 is outside [-225, 45]: within the limits it is -210, the same
    # configuration, a change of 0 modulo a turn: the first solution listed
    page = tmp_path / "puma.html"
    status, _, err = run("view", "puma560", *PUMA_Q, "--from-q", " ".join(PUMA_Q),
                         "-o", str(page))
    assert status == 0, err
    first = data_of(page.read_text(encoding="utf-8"))["ik"]["solutions"][0]
    assert first["q"] == pytest.approx([10, -30, -210, 20, 40, 30], abs=1e-6)


def test_an_unreachable_pose_still_writes_the_page(tmp_path):
    page = tmp_path / "far.html"
    status, _, err = run("view", "bk_rr", "--xyz", "100", "0", "0", "-o", str(page))
    assert status == 0 and err.startswith("kincalc: note: no IK solution (")
    assert data_of(page.read_text(encoding="utf-8"))["ik"]["solutions"] == []


@pytest.mark.parametrize("argv, words", [
    (["nope"], "no robot named 'nope'"),
    (["puma560", "1", "2"], "puma560 has 6 joints"),
    (["bk_rr", "1", "x"], "joint value 'x' is not a number"),
    (["bk_rr", "1", "1e10"], "joint theta2: 10000000000.0 is too large"),
    (["bk_rr", "--bogus"], "no such option: --bogus"),
    (["puma560", "--xyz", "0.3", "0", "0.2"], "give an orientation too"),
    (["bk_rr", "--unit", "ft"], "--unit"),
    (["bk_rr", "--deg", "--rad"], "contradict each other"),
])
def test_bad_input_is_one_line_and_status_2(argv, words, tmp_path):
    status, out, err = run("view", *argv, "-o", str(tmp_path / "x.html"))
    assert status == 2 and out == "" and words in err and err.count("\n") == 1, err
    assert not (tmp_path / "x.html").exists()


@pytest.mark.parametrize("name, links", [("ur5.urdf", []), ("iiwa14.urdf", []),
                                         ("panda.urdf", ["--tip-link", "panda_hand_tcp"])])
def test_urdf_robots(name, links, tmp_path):
    page = tmp_path / "arm.html"
    status, _, err = run("view", str(URDF / name), *links, "-o", str(page))
    assert status == 0, err
    data = data_of(page.read_text(encoding="utf-8"))
    assert data["convention_name"] == "product of exponentials (poe)"
    assert data["dh"]["title"].startswith("Standard DH table of the same axes")
