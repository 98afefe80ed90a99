"""Drawings: file formats, pixel sizes, determinism, geometry, 2D for planar arms, the CLI.

The geometry tests compare the drawn points with a second formulation: the
convention's own link transforms (``Robot.link_transforms``) multiplied out
with the base and tool, not the chain the drawing walks.
"""

from __future__ import annotations

import os
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import kincalc
from kincalc.errors import InputError
from kincalc.analysis.results import Units

pytest.importorskip("matplotlib")

from kincalc.analysis import plot  # noqa: E402
from kincalc.cli.main import main  # noqa: E402

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
ROOT = Path(__file__).parents[2]


def png_size(path) -> tuple[int, int]:
    """Width and height from the IHDR chunk (the first chunk of every PNG)."""
    data = Path(path).read_bytes()
    assert data[:8] == PNG_SIGNATURE, f"{path} is not a PNG"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def random_q(robot, rng, k=None):
    lo, hi = robot.limits.T
    span = np.where(robot.is_revolute, np.pi, robot.characteristic_length)
    lo = np.where(np.isfinite(lo), lo, -span)
    hi = np.where(np.isfinite(hi), hi, span)
    return rng.uniform(lo, hi, (robot.dof,) if k is None else (k, robot.dof))


def draw(robot_name, Q, path, **kw):
    robot = kincalc.load_robot(robot_name)
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    return plot.draw_arms(robot, Q, [f"panel {i}" for i in range(len(Q))], path, **kw)


def cfk(robot, q) -> np.ndarray:
    """World poses of the convention's link frames 0..n, ``(n + 1, 4, 4)``, from the
    link transforms (not from the chain the drawing uses)."""
    A = robot.link_transforms(q)
    frames = [np.array(robot.base)]
    for Ai in A:
        frames.append(frames[-1] @ Ai)
    return np.array(frames)


def is_vertex(points, p, tol) -> bool:
    return bool(np.min(np.linalg.norm(points - p, axis=1)) < tol)


# --- files ------------------------------------------------------------------------

@pytest.mark.parametrize("k, dpi, size", [
    (1, 100, (500, 500)),
    (2, 100, (1000, 500)),
    (1, 50, (250, 250)),
    (2, 50, (500, 250)),
    (4, 100, (2000, 500)),
    (5, 100, (2000, 1000)),   # at most four columns: a second row
])
def test_png_pixel_size(tmp_path, k, dpi, size):
    robot = kincalc.load_robot("puma560")
    Q = random_q(robot, np.random.default_rng(k), k)
    d = plot.draw_arms(robot, Q, [f"solution {i + 1}" for i in range(k)],
                       tmp_path / "a.png", dpi=dpi)
    assert png_size(tmp_path / "a.png") == size
    assert (d.width, d.height, d.size_unit, d.format) == (*size, "px", "png")
    assert d.describe() == f"{size[0]} x {size[1]} px, png"


def test_planar_png_pixel_size(tmp_path):
    draw("planar_3r", np.radians([[30, 60, -90], [0, 0, 0]]), tmp_path / "p.png")
    assert png_size(tmp_path / "p.png") == (1000, 500)


def test_svg_is_xml_of_the_declared_size(tmp_path):
    d = draw("ur5", np.zeros((2, 6)), tmp_path / "a.svg")
    text = (tmp_path / "a.svg").read_text(encoding="utf-8")
    assert text.startswith(("<?xml", "<svg"))
    root = ET.fromstring(text.encode("utf-8"))
    assert root.tag.endswith("svg")
    assert (root.get("width"), root.get("height")) == ("720pt", "360pt")
    assert (d.width, d.height, d.size_unit) == (720, 360, "pt")


def test_pdf_signature(tmp_path):
    d = draw("ur5", np.zeros(6), tmp_path / "a.pdf")
    data = (tmp_path / "a.pdf").read_bytes()
    assert data.startswith(b"%PDF")
    assert data.rstrip().endswith(b"%%EOF")
    assert (d.width, d.height, d.format) == (360, 360, "pdf")


@pytest.mark.parametrize("fmt", plot.FORMATS)
def test_identical_input_gives_identical_bytes(tmp_path, fmt):
    q = [0.1, -0.7, 2.0, 0.3, 0.8, -0.2]
    draw("puma560", q, tmp_path / f"a.{fmt}")
    draw("puma560", q, tmp_path / f"b.{fmt}")
    assert (tmp_path / f"a.{fmt}").read_bytes() == (tmp_path / f"b.{fmt}").read_bytes()


@pytest.mark.parametrize("fmt", plot.FORMATS)
def test_different_joints_give_different_bytes(tmp_path, fmt):
    draw("puma560", [0.1, -0.7, 2.0, 0.3, 0.8, -0.2], tmp_path / f"a.{fmt}")
    draw("puma560", [0.1, -0.6, 2.0, 0.3, 0.8, -0.2], tmp_path / f"b.{fmt}")
    assert (tmp_path / f"a.{fmt}").read_bytes() != (tmp_path / f"b.{fmt}").read_bytes()


def test_the_users_matplotlib_settings_neither_matter_nor_change(tmp_path):
    import matplotlib as mpl
    draw("ur5", np.zeros(6), tmp_path / "a.svg")
    with mpl.rc_context({"lines.linewidth": 7.0, "axes.facecolor": "black",
                         "svg.hashsalt": "someone else's"}):
        draw("ur5", np.zeros(6), tmp_path / "b.svg")
        assert mpl.rcParams["svg.hashsalt"] == "someone else's"
    assert (tmp_path / "a.svg").read_bytes() == (tmp_path / "b.svg").read_bytes()


@pytest.mark.parametrize("name", ["a.jpg", "a.PNG.txt", "a", "a.eps"])
def test_unsupported_suffix_is_an_input_error(tmp_path, name):
    with pytest.raises(InputError, match=r"\.png, \.svg or \.pdf") as err:
        draw("ur5", np.zeros(6), tmp_path / name)
    assert name in str(err.value)
    assert not (tmp_path / name).exists()


def test_suffix_is_case_insensitive(tmp_path):
    draw("ur5", np.zeros(6), tmp_path / "a.PNG")
    assert png_size(tmp_path / "a.PNG") == (500, 500)


def test_missing_folder_is_an_input_error(tmp_path):
    target = tmp_path / "no" / "such" / "a.png"
    with pytest.raises(InputError, match="does not exist") as err:
        draw("ur5", np.zeros(6), target)
    assert str(target.parent) in str(err.value)


def test_unwritable_target_is_an_input_error(tmp_path):
    (tmp_path / "d.png").mkdir()    # a folder where the file should go
    with pytest.raises(InputError, match="cannot write"):
        draw("ur5", np.zeros(6), tmp_path / "d.png")


def test_require_matplotlib_without_matplotlib(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(plot.MissingExtra) as err:
        plot.require_matplotlib("kincalc plot")
    assert str(err.value) == ("kincalc plot needs matplotlib, which is not installed: "
                              "pip install 'kincalc[plot]'")
    assert err.value.exit_status == 2


def test_importing_kincalc_plot_does_not_import_matplotlib():
    code = ("import sys, kincalc.analysis.plot, kincalc.cli.plot; "
            "sys.exit('matplotlib' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr or "importing kincalc.analysis.plot imported matplotlib"


# --- 2D or 3D ----------------------------------------------------------------------

@pytest.mark.parametrize("name, planar", [
    ("planar_3r", True), ("bk_rr", True),
    ("puma560", False), ("ur5", False), ("adept_cobra600", False),   # SCARA: z moves
    ("stanford_arm", False), ("bk_rpr", False),
])
def test_planar_arms_are_drawn_in_2d(tmp_path, name, planar):
    robot = kincalc.load_robot(name)
    Q = random_q(robot, np.random.default_rng(3), 2)
    d = plot.draw_arms(robot, Q, ["a", "b"], tmp_path / "a.png")
    assert d.projections == (("2d",) * 2 if planar else ("3d",) * 2)
    assert d.planar is planar


def test_a_planar_arm_in_a_vertical_plane_keeps_world_axes():
    # planar_3r turned onto the world xz plane (joint axes along -y)
    base = kincalc.load_robot("planar_3r")
    Rx = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], float)
    robot = kincalc.Robot(name="xz", convention="dh", joints=base.joints, base=Rx,
                          length_unit="unitless")
    u, v, labels = plot.drawing_plane(robot)
    assert labels == ("x", "z")
    assert np.allclose(u, [1, 0, 0]) and np.allclose(v, [0, 0, 1])


# --- geometry: the drawing is the arm -------------------------------------------------

GEOMETRY_ROBOTS = ["puma560", "puma560_mdh", "ur5", "ur5_mdh", "stanford_arm",
                   "stanford_arm_mdh", "adept_cobra600", "kuka_kr16", "bk_rr", "bk_rrp",
                   "bk_offset_wrist", "panda"]


@pytest.mark.parametrize("name", GEOMETRY_ROBOTS)
def test_last_point_is_the_tool_position(name):
    robot = kincalc.load_robot(name)
    rng = np.random.default_rng(7)
    L = robot.characteristic_length
    for q in random_q(robot, rng, 20):
        arm = plot.arm_points(robot, q)
        T = cfk(robot, q)[-1] @ robot.tool          # base . A_1 ... A_n . tool
        assert np.allclose(arm.points[-1], T[:3, 3], atol=1e-9 * L)
        assert np.allclose(arm.tool, T, atol=1e-9 * L)
        assert np.allclose(arm.base, robot.base)
        assert np.allclose(arm.points[0], robot.base[:3, 3])


@pytest.mark.parametrize("name", GEOMETRY_ROBOTS + ["ur5_poe"])
def test_joint_points_lie_on_the_joint_axes(name):
    robot = kincalc.load_robot(name)
    rng = np.random.default_rng(11)
    L = robot.characteristic_length
    for q in random_q(robot, rng, 20):
        frames = cfk(robot, q)
        arm = plot.arm_points(robot, q)
        for i, p in enumerate(plot.joint_points(robot, q)):
            # dh: joint i turns about z of frame i-1; mdh and poe: about z of frame i
            F = frames[i] if robot.convention == "dh" else frames[i + 1]
            o, z = F[:3, 3], F[:3, 2]
            off = (p - o) - z * ((p - o) @ z)
            assert np.linalg.norm(off) < 1e-9 * L, f"joint {i + 1} is off its axis"
            assert is_vertex(arm.points, p, 1e-9 * L), f"joint {i + 1} is not a vertex"


@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford_arm", "adept_cobra600",
                                  "kuka_kr16", "planar_3r"])
def test_dh_links_are_drawn_as_an_l(name):
    # a DH link goes d_i along z_{i-1}, then a_i along x_i: frame origins and those
    # corners are all vertices of the polyline, and no segment cuts the corner
    robot = kincalc.load_robot(name)
    assert robot.convention == "dh"
    rng = np.random.default_rng(5)
    L = robot.characteristic_length
    for q in random_q(robot, rng, 10):
        frames = cfk(robot, q)
        pts = plot.arm_points(robot, q).points
        for i, j in enumerate(robot.joints):
            o, z = frames[i][:3, 3], frames[i][:3, 2]
            d = j.d + (0.0 if j.revolute else q[i])
            assert is_vertex(pts, o + z * d, 1e-9 * L), f"corner of link {i + 1} missing"
            if np.allclose(robot.tool, np.eye(4)) or i + 1 < robot.dof:
                assert is_vertex(pts, frames[i + 1][:3, 3], 1e-9 * L)


def test_prismatic_travel_is_drawn_along_its_axis():
    robot = kincalc.load_robot("stanford_arm")
    q = np.array([0.3, -0.4, 0.9, 0.2, 0.5, 0.1])
    frames = cfk(robot, q)
    pts = plot.arm_points(robot, q).points
    start = plot.joint_points(robot, q)[2]
    assert np.allclose(start, frames[2][:3, 3])                 # the boom leaves o_2 ...
    tip = frames[2][:3, 3] + frames[2][:3, 2] * q[2]
    assert is_vertex(pts, tip, 1e-12)                           # ... and runs d3 along z_2
    i = int(np.argmin(np.linalg.norm(pts - tip, axis=1)))
    assert np.allclose(pts[i - 1], start)


def test_arm_points_does_not_write_into_q():
    robot = kincalc.load_robot("stanford_arm")
    q = np.array([0.3, -0.4, 0.9, 0.2, 0.5, 0.1])
    before = q.copy()
    plot.arm_points(robot, q)
    plot.joint_points(robot, q)
    assert np.array_equal(q, before)


def test_arm_points_rejects_a_wrong_shape():
    robot = kincalc.load_robot("ur5")
    from kincalc.errors import InputError
    with pytest.raises(InputError, match=r"ur5 has 6 joints, got 5"):
        plot.arm_points(robot, np.zeros(5))


# --- titles --------------------------------------------------------------------------

def test_config_title():
    puma = kincalc.load_robot("puma560")
    q = np.radians([0, -45, 180, 0, 45, 0])
    assert plot.config_title(puma, q, Units()) == "q = (0, -45, 180, 0, 45, 0) deg"
    stanford = kincalc.load_robot("stanford_arm")
    q = np.array([0, np.pi / 2, 0.5, 0, 0, 0])
    assert plot.config_title(stanford, q, Units(length="mm")) == \
        "q = (0, 90, d3=500 mm, 0, 0, 0) deg"
    # an IK solution's round-off is a zero in the title
    noise = np.array([-1e-14, 0, 0, 0, 0, 1e-12])
    assert plot.config_title(puma, noise, Units()) \
        == "q = (0, 0, 0, 0, 0, 0) deg"
    rrp = kincalc.load_robot("bk_rrp")
    assert plot.config_title(rrp, [0, 1, 2.5], Units(angle="rad", length="unitless")) == \
        "q = (0, 1, d3=2.5) rad"


# --- workspace sections -----------------------------------------------------------------

def sections(k=2, seed=0):
    """``k`` made-up sections: a disc of reach with random manipulability in it."""
    from kincalc.analysis.workspace import Section
    rng = np.random.default_rng(seed)
    out = []
    y, x = np.mgrid[-1:1:40j, -1.5:1.5:60j]
    for i in range(k):
        g = rng.uniform(0, 1, (40, 60))
        g[:5] = np.nan
        e = np.eye(3)
        out.append(Section(f"section {i}", "made up", e[0], e[1], e[2], float(i),
                           (np.zeros(2), None), None, (-1.5, 1.5, -1.0, 1.0),
                           (np.hypot(x, y) < 0.9).astype(float), g, None, 100))
    return out


@pytest.mark.parametrize("k, dpi, size", [(1, 100, (500, 500)), (2, 100, (1000, 500)),
                                          (3, 50, (750, 250))])
def test_sections_png_size(tmp_path, k, dpi, size):
    d = plot.draw_sections(sections(k), tmp_path / "w.png", suptitle="workspace",
                           colour_label="manipulability", dpi=dpi)
    assert png_size(tmp_path / "w.png") == size
    assert d.projections == ("2d",) * k


@pytest.mark.parametrize("fmt", plot.FORMATS)
def test_sections_are_deterministic(tmp_path, fmt):
    for name in ("a", "b"):
        plot.draw_sections(sections(), tmp_path / f"{name}.{fmt}", suptitle="w",
                           colour_label="c")
    assert (tmp_path / f"a.{fmt}").read_bytes() == (tmp_path / f"b.{fmt}").read_bytes()
    other = sections(seed=1)
    plot.draw_sections(other, tmp_path / f"c.{fmt}", suptitle="w", colour_label="c")
    assert (tmp_path / f"a.{fmt}").read_bytes() != (tmp_path / f"c.{fmt}").read_bytes()


def test_sections_all_empty_and_bad_suffix(tmp_path):
    import dataclasses
    empty = [dataclasses.replace(sections(1)[0], reach=np.zeros((10, 10)),
                                 manipulability=np.full((10, 10), np.nan))]
    plot.draw_sections(empty, tmp_path / "e.png", suptitle="w", colour_label="c")
    assert png_size(tmp_path / "e.png") == (500, 500)
    with pytest.raises(InputError):
        plot.draw_sections(empty, tmp_path / "e.gif", suptitle="w", colour_label="c")


# --- the command ---------------------------------------------------------------------------

def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_writes_png(tmp_path, capsys):
    target = tmp_path / "p.png"
    code, out, err = run(capsys, "plot", "puma560", "0", "-45", "180", "0", "45", "0",
                         "-o", str(target))
    assert code == 0, err
    assert out == f"wrote {target} (500 x 500 px, png)\n"
    assert png_size(target) == (500, 500)


def test_cli_dpi_svg_pdf_and_units(tmp_path, capsys):
    code, out, err = run(capsys, "plot", "ur5", "--dpi", "50", "-o", str(tmp_path / "u.png"))
    assert code == 0, err
    assert png_size(tmp_path / "u.png") == (250, 250)
    assert "(250 x 250 px, png)" in out
    code, out, err = run(capsys, "plot", "stanford_arm", "0", "90", "500", "0", "0", "0",
                         "--unit", "mm", "--output", str(tmp_path / "s.svg"))
    assert code == 0, err
    assert out.endswith("(360 x 360 pt, svg)\n")
    svg = (tmp_path / "s.svg").read_text(encoding="utf-8")
    ET.fromstring(svg.encode("utf-8"))
    code, out, err = run(capsys, "plot", "bk_rr", "--rad", "0.5", "-1", "-o",
                         str(tmp_path / "r.pdf"))
    assert code == 0, err
    assert (tmp_path / "r.pdf").read_bytes().startswith(b"%PDF")


def test_cli_same_picture_as_the_api(tmp_path, capsys):
    code, _, err = run(capsys, "plot", "puma560", "0", "-45", "180", "0", "45", "0",
                       "-o", str(tmp_path / "cli.png"))
    assert code == 0, err
    robot = kincalc.load_robot("puma560")
    q = np.radians([0, -45, 180, 0, 45, 0])
    plot.draw_arms(robot, q[None], [plot.config_title(robot, q, Units())], tmp_path / "api.png",
                   units=Units())
    assert (tmp_path / "cli.png").read_bytes() == (tmp_path / "api.png").read_bytes()


@pytest.mark.parametrize("argv, needle", [
    (["ur5", "-o", "{tmp}/a.jpg"], "unsupported format '.jpg'"),
    (["ur5", "-o", "{tmp}/nope/a.png"], "does not exist"),
    (["ur5", "1", "2", "-o", "{tmp}/a.png"], "has 6 joints"),
    (["ur5", "--dpi", "5", "-o", "{tmp}/a.png"], "--dpi"),
    (["ur5"], "--output"),
    (["bk_rr", "--unit", "mm", "-o", "{tmp}/a.png"], "unitless"),
])
def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, capsys, argv, needle):
    code, out, err = run(capsys, "plot", *[a.replace("{tmp}", str(tmp_path)) for a in argv])
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1 and needle in err, err
    assert not any(tmp_path.iterdir()), "nothing may be written on bad input"


def test_cli_without_matplotlib(tmp_path):
    target = tmp_path / "p.png"
    code = ("import sys; sys.modules['matplotlib'] = None\n"
            "from kincalc.cli.main import main\n"
            f"sys.exit(main(['plot', 'ur5', '-o', {str(target)!r}]))\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=120, env=env)
    assert r.returncode == 2, r.stderr
    assert r.stdout == ""
    assert r.stderr == ("kincalc: error: kincalc plot needs matplotlib, which is not installed: "
                        "pip install 'kincalc[plot]'\n")
    assert not target.exists()


# --- ik --plot and workspace --plot, through the CLI -----------------------------------

def test_ik_plot_draws_one_panel_per_solution(tmp_path, capsys):
    # bk_rr reaches (12.99, 2.5) two ways (Example 4.2): two 5-inch panels side by side
    out = tmp_path / "rr.png"
    assert main(["ik", "bk_rr", "--xyz", "12.99", "2.5", "0", "--plot", str(out)]) == 0
    assert png_size(out) == (1000, 500)
    doc_out = tmp_path / "rr.svg"
    capsys.readouterr()
    assert main(["ik", "puma560", "--from-q", "10 -40 170 20 30 40", "--plot", str(doc_out),
                 "--json"]) == 0
    import json
    doc = json.loads(capsys.readouterr().out)
    assert doc["plot"] == str(doc_out) and doc["count"] == 8
    # eight panels, four a row: 20 x 10 inches, 72 points each
    root = ET.parse(doc_out).getroot()
    assert root.get("width").startswith("1440") and root.get("height").startswith("720")


def test_ik_plot_with_no_solution_writes_nothing(tmp_path, capsys):
    out = tmp_path / "none.png"
    assert main(["ik", "bk_rr", "--xyz", "20", "0", "0", "--plot", str(out)]) == 1
    assert not out.exists()
    assert "no solution to draw" in capsys.readouterr().err


def test_workspace_plot_is_deterministic_for_a_seed(tmp_path, capsys):
    paths = [tmp_path / f"w{k}.png" for k in range(3)]
    for path, seed in zip(paths, (0, 0, 1)):
        assert main(["workspace", "puma560", "--samples", "20000", "--seed", str(seed),
                     "--plot", str(path)]) == 0
    capsys.readouterr()
    data = [p.read_bytes() for p in paths]
    assert data[0][:8] == b"\x89PNG\r\n\x1a\n"
    assert data[0] == data[1] and data[0] != data[2]
    # two sections (through the base axis and the shoulder) for a spatial arm: two panels wide
    w, h = png_size(paths[0])
    assert w >= 2 * h


def test_a_title_the_font_lacks_glyphs_for_puts_nothing_on_stderr(tmp_path):
    """A robot titled in CJK with an emoji: matplotlib's "Glyph ... missing from font(s)"
    warnings, with kincalc's source line in them, went to stderr (16 lines for a PDF of
    workspace --plot; an independent tester). The drawing is written, and no warning."""
    robot = tmp_path / "cjk.yaml"
    robot.write_text('name: cjk\ntitle: "Arm \u673a\u5668\u4eba \U0001f916"\nconvention: dh\n'
                     "units: {length: m, angle: deg}\njoints:\n"
                     "  - {name: a, type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n"
                     "  - {name: b, type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n",
                     encoding="utf-8")
    out = tmp_path / "cjk.png"
    p = subprocess.run([sys.executable, "-m", "kincalc", "plot", str(robot), "10", "20",
                        "-o", str(out)], capture_output=True, text=True, encoding="utf-8")
    assert p.returncode == 0, p.stderr
    assert out.exists() and "wrote" in p.stdout + p.stderr
    assert "Glyph" not in p.stderr and "warn" not in p.stderr.lower(), p.stderr


@pytest.mark.parametrize("title", [r"Arm $\frac{$ v2", "$x^$", "cost $5 and $6"])
def test_a_title_or_joint_name_with_dollars_is_text_not_mathtext(tmp_path, capsys, title):
    """A title 'Arm $\\frac{$ v2', valid to `robots validate`, made plot and workspace
    --plot fail with matplotlib's mathtext parse error (exit 3; an independent tester). The
    title and joint names are drawn as written."""
    robot = tmp_path / "dollar.yaml"
    robot.write_text(f"name: arm\ntitle: '{title}'\nconvention: dh\n"
                     "units: {length: m, angle: deg}\njoints:\n"
                     "  - {name: '$q_1$', type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n"
                     "  - {name: 'q$2', type: revolute, alpha: 0, a: 0.2, d: 0, theta: 0}\n")
    out = tmp_path / "d.png"
    assert main(["plot", str(robot), "10", "20", "-o", str(out)]) == 0
    assert png_size(out) == (500, 500)
    assert main(["workspace", str(robot), "--samples", "1000", "--plot",
                 str(tmp_path / "w.png")]) == 0
    capsys.readouterr()


def test_a_matplotlibrc_in_the_working_directory_is_not_read(tmp_path):
    """matplotlib reads ./matplotlibrc when it is imported: a file the user did not name. A
    grader running kincalc in a student's folder had its lines echoed on stderr ('Bad key
    API_KEY ... sk-live-...'), waited forever on a FIFO of that name, and read a link to
    /dev/zero until memory ran out (an independent tester). The import runs elsewhere."""
    folder = tmp_path / "student"
    folder.mkdir()
    (folder / "matplotlibrc").write_text("API_KEY: sk-live-SECRET123\nfigure.dpi: 7\n")
    out = tmp_path / "arm.png"
    env = {k: v for k, v in os.environ.items() if k != "MATPLOTLIBRC"}
    run = [sys.executable, "-m", "kincalc", "plot", "bk_rr", "30", "-60", "-o", str(out)]
    p = subprocess.run(run, capture_output=True, text=True, cwd=folder, env=env, timeout=120)
    assert p.returncode == 0 and "SECRET" not in p.stdout + p.stderr, p.stderr
    assert png_size(out) == (500, 500)                  # not the file's 7 dpi
    if hasattr(os, "mkfifo"):
        (folder / "matplotlibrc").unlink()
        os.mkfifo(folder / "matplotlibrc")
        p = subprocess.run(run + ["--force"], capture_output=True, text=True, cwd=folder,
                           env=env, timeout=120)
        assert p.returncode == 0, p.stderr
