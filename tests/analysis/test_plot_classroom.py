"""The pictures of issue 19 ("the classroom"): what the drawings compute, tested on the data
rather than the pixels.

* ``ik --plot``: every branch of a PUMA's eight is drawn differently in the view the
  figure chose (the wrist's joints are drawn with their axes, so a wrist flip shows),
  the view is chosen from the data, the arm stands on a pedestal on the ground, the base
  and tool labels keep clear of what is drawn, and each panel's title is its branch;
* planar arms: the blue rings are gone, a legend says what the dots and crosses are;
* ``workspace --plot``: each section's boundary holds the tool points of random
  configurations near its plane and leaves out what is beyond the reach, the planes are
  the ones named (through the base axis, through the shoulder), the planar 3R's
  dexterous disc is where the textbook puts it, and the colour bar has its unit.

Geometry is checked independently where it can be: FK of random joints, the arm's own
axes from the chain frames, point-to-segment distances written out here.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import kincalc
from kincalc.analysis.results import Units

pytest.importorskip("matplotlib")

from kincalc.analysis import plot  # noqa: E402
from kincalc.analysis.plot.scene import (AXIS_FRACTION, LABEL_OFFSET, arm_scene,  # noqa: E402
                                         project)
from kincalc.analysis.workspace import analyse, manipulability_unit  # noqa: E402
from kincalc.cli.main import main  # noqa: E402
from kincalc.ik import Target, solve  # noqa: E402


def solutions(name, q_deg):
    robot = kincalc.load_robot(name)
    result = solve(robot, Target(robot.fk(np.radians(q_deg))))
    return robot, np.array([s.q for s in result.solutions]), result.solutions


def svg_texts(path) -> list[str]:
    """The strings of an SVG matplotlib wrote (each text is preceded by a comment
    holding it)."""
    return re.findall(r"<!-- (.*?) -->", path.read_text(encoding="utf-8"))


def seg_distance(x, a, b) -> float:
    ab = b - a
    t = np.clip((x - a) @ ab / max(ab @ ab, 1e-300), 0.0, 1.0)
    return float(np.linalg.norm(a + t * ab - x))


# --- ik --plot: every branch its own picture -------------------------------------------

PUMA_POSES = [[0, 45, 180, 0, 45, 0], [10, -40, 170, 20, 30, 40], [30, -30, 150, 20, 40, 30]]


def drawn(segments) -> np.ndarray:
    """Screen segments ``(s, 2, 2)`` as drawn: each one's ends in a fixed order (a line
    from a to b looks as one from b to a)."""
    out = []
    for a, b in segments:
        out.append([a, b] if tuple(np.round(a, 12)) <= tuple(np.round(b, 12)) else [b, a])
    return np.array(out)


def wrist_glyph(scene, k) -> np.ndarray:
    """What panel ``k`` draws at the wrist, on the screen: joints 4-6's cylinders and
    axis arrows, and the tool's triad."""
    p = scene.panels[k]
    T = p.arm.tool
    parts = [scene.cylinder(k, i) for i in (3, 4, 5)] + [scene.arrow(k, i) for i in (3, 4, 5)]
    parts += [np.stack([T[:3, 3], T[:3, 3] + 0.15 * scene.length * T[:3, j]]) for j in range(3)]
    return drawn([scene.screen(s) for s in parts])


@pytest.mark.parametrize("pose", PUMA_POSES)
def test_the_pumas_eight_branches_are_eight_pictures(pose):
    robot, Q, sols = solutions("puma560", pose)
    assert len(Q) == 8
    scene = arm_scene(robot, Q)
    glyphs = [wrist_glyph(scene, k) for k in range(8)]
    whole = [scene.screen(np.concatenate([p.arm.points, p.marks])) for p in scene.panels]
    L = robot.characteristic_length
    for i in range(8):
        for j in range(i + 1, 8):
            # the wrist alone tells a flip from a no-flip: visibly (2 % of the arm's length)
            if sols[i].branch.rsplit("wrist", 1)[0] == sols[j].branch.rsplit("wrist", 1)[0]:
                assert np.max(np.abs(glyphs[i] - glyphs[j])) > 0.02 * L, (i, j)
            assert np.max(np.abs(whole[i] - whole[j])) > 0.02 * L, (i, j)


def test_a_wrist_flip_turns_joint_5s_arrow_round():
    robot, Q, sols = solutions("puma560", PUMA_POSES[0])
    scene = arm_scene(robot, Q)
    by_branch = {s.branch: k for k, s in enumerate(sols)}
    pairs = [(by_branch[b], by_branch[b.replace("no-flip", "flip")])
             for b in by_branch if b.endswith("no-flip")]
    assert len(pairs) == 4
    for a, b in pairs:
        # the wrist centre is the same point; joint 5's axis (from the chain frames,
        # independent of the drawing) is reversed, and so is its drawn arrow
        pa, pb = scene.panels[a], scene.panels[b]
        assert np.allclose(pa.joints[4], pb.joints[4], atol=1e-9)
        assert np.allclose(pa.axes[4], -pb.axes[4], atol=1e-9)
        da = np.diff(scene.screen(scene.arrow(a, 4)), axis=0)[0]
        db = np.diff(scene.screen(scene.arrow(b, 4)), axis=0)[0]
        assert da @ db < 0


def test_joint_axes_are_the_chains():
    from kincalc.fk import chain_frames
    robot = kincalc.load_robot("ur5")
    q = np.radians([10, -60, 80, -40, 70, 20])
    scene = arm_scene(robot, q[None])
    F = chain_frames(robot.chain, q)
    for i in range(6):
        a, b = scene.arrow(0, i)
        assert np.allclose(b, F[i, :3, 3] + AXIS_FRACTION * robot.characteristic_length
                           * F[i, :3, 2], atol=1e-12)
        assert np.allclose(np.cross(b - a, F[i, :3, 2]), 0, atol=1e-12)


@pytest.mark.parametrize("pose", PUMA_POSES)
def test_the_view_is_chosen_from_the_data(pose):
    robot, Q, _ = solutions("puma560", pose)
    scene = arm_scene(robot, Q)
    marks = np.stack([p.marks for p in scene.panels])

    def closest_pair(view):
        S = project(marks, view)
        d = S[:, None] - S[None]
        rms = np.sqrt(np.mean(np.sum(d * d, axis=-1), axis=-1))
        return np.min(rms[np.triu_indices(len(S), 1)])
    # at least as far apart as matplotlib's default view would show them, and apart
    assert closest_pair(scene.view) >= closest_pair((-60, 30)) - 1e-12
    assert closest_pair(scene.view) > 0.02 * robot.characteristic_length
    assert 0 < scene.view[1] < 90


def test_the_view_depends_on_the_poses():
    views = {arm_scene(*solutions("puma560", pose)[:2]).view for pose in PUMA_POSES}
    views |= {arm_scene(*solutions("ur5", [10, -60, 80, -40, 70, 20])[:2]).view}
    assert len(views) > 1, "one view for every figure: it is not chosen from the data"


def test_project_is_matplotlibs_view():
    """``project`` is the orthographic projection matplotlib's 3D axes use for the same
    azimuth and elevation (up to the axes' own scale and offset)."""
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import proj3d
    rng = np.random.default_rng(2)
    P = rng.uniform(-1, 1, (20, 3))
    for view in ((-60, 30), (40, 10), (150, 40)):
        ax = Figure().add_subplot(projection="3d")
        ax.set_proj_type("ortho")
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlim(-1, 1), ax.set_ylim(-1, 1), ax.set_zlim(-1, 1)
        ax.view_init(elev=view[1], azim=view[0])
        x, y, _ = proj3d.proj_transform(*P.T, ax.get_proj())
        ours = project(P, view)
        # one scale for both screen axes, no rotation
        A = np.linalg.lstsq(np.column_stack([ours, np.ones(len(P))]),
                            np.column_stack([x, y]), rcond=None)[0]
        assert np.allclose(np.column_stack([ours, np.ones(len(P))]) @ A,
                           np.column_stack([x, y]), atol=1e-9)
        assert np.allclose(A[:2], A[0, 0] * np.eye(2), atol=1e-9)


@pytest.mark.parametrize("name, pose", [("puma560", PUMA_POSES[1]),
                                        ("ur5", [10, -60, 80, -40, 70, 20]),
                                        ("adept_cobra600", [30, 60, 100, 20])])
def test_the_arm_stands_on_a_pedestal_on_the_ground(name, pose):
    robot, Q, _ = solutions(name, pose)
    scene = arm_scene(robot, Q)
    L = robot.characteristic_length
    base = robot.base[:3, 3]
    x, y, top, bottom, r = scene.pedestal
    assert np.allclose([x, y, top], base)
    assert bottom == scene.ground[4] <= base[2] - 0.25 * L + 1e-12
    for p in scene.panels:
        assert p.arm.points[:, 2].min() >= bottom
        assert (scene.ground[0] <= p.arm.points[:, 0].min()
                and p.arm.points[:, 0].max() <= scene.ground[1])
    assert 0 < r < 0.2 * L


@pytest.mark.parametrize("name, pose", [("puma560", PUMA_POSES[0]), ("puma560", PUMA_POSES[1]),
                                        ("ur5", [10, -60, 80, -40, 70, 20]),
                                        ("bk_offset_wrist", [10, 0.5, 30, 20, 40, 50]),
                                        ("planar_3r", [30, 60, -90])])
def test_labels_keep_clear_of_what_is_drawn(name, pose):
    robot = kincalc.load_robot(name)
    q = np.array(pose, float)
    q[robot.is_revolute] = np.radians(q[robot.is_revolute])
    Q = np.array([s.q for s in solve(robot, Target(robot.fk(q))).solutions])
    scene = arm_scene(robot, Q)
    L = robot.characteristic_length
    for k, p in enumerate(scene.panels):
        segments = [np.stack([a, b]) for a, b in zip(p.arm.points[:-1], p.arm.points[1:])]
        segments += [scene.arrow(k, i) for i in np.flatnonzero(p.revolute)]
        segments += [scene.cylinder(k, i) for i in np.flatnonzero(p.revolute)]
        for T in (p.arm.base, p.arm.tool):
            segments += [np.stack([T[:3, 3], T[:3, 3] + 0.15 * L * T[:3, j]]) for j in range(3)]
        segs2 = [scene.screen(s) for s in segments]
        joints2 = scene.screen(p.joints)
        for name_, T in (("base", p.arm.base), ("tool", p.arm.tool)):
            d = np.array(scene.labels[k][name_])
            assert np.isclose(np.linalg.norm(d), 1)
            at = scene.screen(T[:3, 3]) + LABEL_OFFSET * scene.half * d
            # the label's point is off every joint marker and clear of every segment
            assert np.min(np.linalg.norm(joints2 - at, axis=1)) > 0.05 * scene.half
            clear = min(seg_distance(at, a, b) for a, b in segs2)
            assert clear > 0.02 * scene.half, (name_, k, clear / scene.half)


def ik_svg(tmp_path, monkeypatch, *argv):
    """Run ``kincalc ik ... --plot FILE.svg --json``: the document, the Drawing and the
    SVG's texts."""
    import kincalc.analysis.plot as plot_module
    drawn = []
    original = plot_module.draw_arms

    def spy(*a, **kw):
        drawn.append(original(*a, **kw))
        return drawn[-1]
    monkeypatch.setattr(plot_module, "draw_arms", spy)
    out = tmp_path / "ik.svg"
    code = main(["ik", *argv, "--plot", str(out), "--json"])
    return code, out, drawn[0]


def test_each_panel_is_titled_with_its_branch(tmp_path, monkeypatch, capsys):
    code, out, drawing = ik_svg(tmp_path, monkeypatch, "puma560", "--from-q", "0 45 180 0 45 0")
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and doc["count"] == 8
    assert drawing.projections == ("3d",) * 8
    for k, (title, s) in enumerate(zip(drawing.titles, doc["solutions"]), start=1):
        first = title.split("\n")[0]
        assert first == f"{k}. {s['branch']}" + ("" if s["within_limits"] else " (out of limits)")
    assert len({t.split("\n")[0] for t in drawing.titles}) == 8
    texts = svg_texts(out)
    assert "revolute joint, + axis arrow" in texts and "base" in texts and "tool" in texts
    assert any(re.fullmatch(r"0\.\d+ m", t) for t in texts), "no scale bar in m"


# --- planar arms: the rings ---------------------------------------------------------------

def test_planar_arms_explain_their_dots_and_draw_no_rings(tmp_path, capsys):
    out = tmp_path / "p.svg"
    assert main(["plot", "planar_3r", "30", "60", "-90", "-o", str(out)]) == 0
    capsys.readouterr()
    texts = svg_texts(out)
    assert "z out of the page" in texts
    # no ring: no hollow white circle stroked in the z colour around base or tool
    svg = out.read_text(encoding="utf-8")
    assert not re.search(r"fill: ?#ffffff[^\"]*stroke: ?#1f77b4", svg)
    # a frame turned over (z into the page) says so
    robot = kincalc.load_robot("planar_3r")
    flipped = kincalc.Robot(name="flipped", convention="dh", joints=robot.joints,
                            tool=np.diag([1.0, -1.0, -1.0, 1.0]), length_unit="unitless")
    out2 = tmp_path / "f.svg"
    plot.draw_arms(flipped, np.radians([[30, 60, -90]]), ["q"], out2)
    assert "z into the page" in svg_texts(out2)


# --- workspace --plot ------------------------------------------------------------------------

@pytest.fixture(scope="module")
def puma_workspace():
    return analyse(kincalc.load_robot("puma560"), 200_000, 0, sections=True)


def pixel(sec) -> float:
    u0, u1, _, _ = sec.extent
    return (u1 - u0) / sec.reach.shape[1]


def near_plane_points(robot, sec, count, seed, slab):
    """FK tool points of random joints within the limits that lie within ``slab`` of
    the section's plane, in plane coordinates."""
    from kincalc.analysis.workspace import joint_ranges
    lo, hi = joint_ranges(robot)
    rng = np.random.default_rng(seed)
    P = robot.fk(rng.uniform(lo, hi, (count, robot.dof)))[:, :3, 3]
    keep = np.abs(P @ sec.normal - sec.level) <= slab
    return sec.coords(P[keep])


def test_the_sections_are_the_planes_named(puma_workspace):
    axial, across = puma_workspace.sections
    assert axial.name == "through the base axis" and across.name == "through the shoulder"
    # the PUMA's axis 1 is the world z axis through the origin; its shoulder (axis 2 meets
    # axis 1) at z = 0 in this model
    assert abs(axial.normal @ [0, 0, 1]) < 1e-12 and abs(axial.level) < 1e-12
    assert np.allclose(across.normal, [0, 0, 1]) and abs(across.level) < 1e-12
    assert "joint 1" in axial.reason and "joint 2" in across.reason
    assert min(axial.reach.shape) >= 120 and min(across.reach.shape) >= 120


def check_boundary(ws, which, slab=0.5):
    """Section ``which`` of the analysis ``ws`` holds the FK points of random joints
    near its plane, and nothing beyond the reach."""
    robot = ws.robot
    sec = ws.sections[which]
    h = pixel(sec)
    ab = near_plane_points(robot, sec, 400_000, 99, slab * h)
    assert len(ab) > 500
    inside = sec.inside(ab) >= 0.5
    # Monte-Carlo boundaries run a little inside the true one: allow 1 % within 3 pixels
    assert inside.mean() > 0.99
    offsets = np.array([[dx, dy] for dx in (-3, 0, 3) for dy in (-3, 0, 3)]) * h
    near = np.max([sec.inside(ab + o) for o in offsets], axis=0) >= 0.5
    assert near.all()
    # beyond the reach (the envelope's greatest distance from the base, 3 pixels on)
    R = ws.envelope["max_distance"] + 3 * h
    t = np.linspace(0, 2 * np.pi, 720)
    ring = sec.coords(robot.base[:3, 3]) + R * np.stack([np.cos(t), np.sin(t)], axis=1)
    assert np.all(sec.inside(ring) < 0.5)


@pytest.mark.parametrize("which", [0, 1])
def test_the_boundary_holds_the_reach_and_nothing_beyond(puma_workspace, which):
    check_boundary(puma_workspace, which)


def test_a_prismatic_joint_1_slides_its_sections():
    from kincalc.model import Joint
    joints = [Joint("d1", "prismatic", limits=(0.2, 0.6)),
              Joint("q2", "revolute", a=0.5, limits=(-2.5, 2.5)),
              Joint("q3", "revolute", a=0.4, limits=(-2.5, 2.5))]
    robot = kincalc.Robot(name="prr", convention="dh", joints=joints, length_unit="m")
    ws = analyse(robot, 100_000, 0, sections=True)
    axial, across = ws.sections
    assert axial.reason == "joint 1 slides the arm along it"
    assert min(axial.reach.shape) >= 30 and min(across.reach.shape) >= 120
    for which in (0, 1):
        check_boundary(ws, which)


def test_the_pumas_axis_is_out_of_reach_in_the_axial_section(puma_workspace):
    # the shoulder offset keeps the wrist 0.15 m (d3) from axis 1 at least
    sec = puma_workspace.sections[0]
    z = np.linspace(-0.7, 0.8, 300)
    on_axis = np.stack([np.zeros_like(z), z], axis=1)
    assert np.all(sec.inside(on_axis) < 0.5)


def test_sections_of_a_scara_and_a_planar_arm():
    cobra = analyse(kincalc.load_robot("adept_cobra600"), 100_000, 1, sections=True)
    axial, across = cobra.sections
    assert axial.name == "through the base axis"
    # the shoulder (joint 2's point, 387 mm up) is above the tool's range: the level
    # nearest to it that the tool fills instead
    assert across.name == "across the base axis"
    z_lo, z_hi = cobra.envelope["z_min"], cobra.envelope["z_max"]
    assert z_lo < across.level < z_hi
    planar = analyse(kincalc.load_robot("planar_3r"), 200_000, 0, sections=True)
    (sec,) = planar.sections
    assert sec.name == "the plane of motion"
    # the textbook's dexterous workspace of l1 = l2 = l3 = 1: the disc r <= l1 + l2 - l3
    t = np.linspace(0, 2 * np.pi, 36, endpoint=False)
    circle = np.stack([np.cos(t), np.sin(t)], axis=1)
    assert np.all(sec.inside(0.6 * circle, sec.dexterous) >= 0.5)
    assert np.all(sec.inside(1.5 * circle, sec.dexterous) < 0.5)
    assert np.all(sec.inside(2.8 * circle) >= 0.5) and np.all(sec.inside(3.2 * circle) < 0.5)


@pytest.mark.parametrize("name, unit, expected", [
    ("puma560", None, "m^3"), ("adept_cobra600", None, "mm^2"), ("stanford_arm", None, "m^2"),
    ("planar_3r", None, ""), ("puma560", "mm", "mm^3")])
def test_the_manipulabilitys_unit(name, unit, expected):
    robot = kincalc.load_robot(name)
    units = Units(length=unit or robot.length_unit)
    assert manipulability_unit(robot, units) == expected


def test_the_workspace_picture_says_its_unit_and_planes(tmp_path, capsys):
    out = tmp_path / "w.svg"
    assert main(["workspace", "puma560", "--samples", "20000", "--plot", str(out)]) == 0
    capsys.readouterr()
    texts = svg_texts(out)
    assert "manipulability (Yoshikawa, as kincalc jacobian), m\u00b3" in texts
    assert any(t.startswith("Through the base axis (y-z plane, x = 0 m)") for t in texts)
    assert any(t.startswith("Through the shoulder (x-y plane, z = 0 m)") for t in texts)
    assert "boundary of the reach" in texts and "dexterous (every test orientation)" in texts
