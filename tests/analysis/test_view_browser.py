"""``kincalc view``'s page in a real browser (headless Chromium, tests/browser.py).

The page loads with no console error, no uncaught exception and no request for anything
but itself; its FK (its own JavaScript, on the chain it embeds) equals kincalc's to 1e-9;
moving a slider or typing a value gives the read-out ``kincalc fk`` and ``kincalc
jacobian`` give; choosing an IK branch sets that branch's joints (at once, or through
intermediate joints with "animate"); dragging rotates the view and the wheel zooms; a
screenshot shows the arm where the page says it drew it. One browser for the module,
a tab per page; skipped, saying why, where no Chromium is installed.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from browser import BROWSER, SKIP, Browser
from kincalc.cli.main import main
from kincalc.conventions.library import load

pytestmark = pytest.mark.skipif(BROWSER is None, reason=SKIP or "")

#: one of each: standard DH, modified DH, POE, prismatic joints (and unitless), 7 joints,
#: a URDF
FK_ROBOTS = ["puma560", "puma560_mdh", "ur5_poe", "stanford_arm", "bk_rrp", "iiwa14",
             str(Path(__file__).parents[1] / "conventions" / "urdf" / "gen3_7dof.urdf")]
PUMA_Q = ["10", "-30", "150", "20", "40", "30"]


@pytest.fixture(scope="module")
def browser():
    with Browser() as b:
        yield b


@pytest.fixture
def open_page(browser, tmp_path, capsys):
    """``open_page(*kincalc view arguments)``: write the page with the command line, open
    it in a new tab, and at the end of the test check that nothing went wrong in it."""
    tabs = []

    def opener(*args):
        path = tmp_path / f"page{len(tabs)}.html"
        assert main(["view", *args, "-o", str(path)]) == 0, capsys.readouterr().err
        tab = browser.tab()
        tabs.append(tab)
        tab.open(path)
        assert tab.eval("document.body.dataset.ready") == "yes", tab.problems()
        return tab
    yield opener
    for tab in tabs:
        assert tab.problems() == []
        tab.close()


def cli_json(capsys, *args) -> dict:
    capsys.readouterr()
    assert main([*args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def shown(tab, *ids) -> list[float]:
    """The full-precision values of read-outs (their data-value)."""
    return tab.eval(f"{list(ids)}.map((id) => Number(document.getElementById(id).dataset.value))")


def readout(tab) -> dict:
    return {"position": shown(tab, "pos-x", "pos-y", "pos-z"),
            "rpy": shown(tab, "rpy-0", "rpy-1", "rpy-2"),
            "quaternion": shown(tab, "quat-0", "quat-1", "quat-2", "quat-3")}


def assert_matches_fk(tab, fk: dict) -> None:
    got = readout(tab)
    assert got["position"] == pytest.approx(fk["position"], abs=1e-9)
    assert got["rpy"] == pytest.approx(fk["orientation"]["rpy"], abs=1e-9)
    assert got["quaternion"] == pytest.approx(fk["orientation"]["quaternion"], abs=1e-9)


@pytest.mark.parametrize("name", FK_ROBOTS, ids=lambda n: Path(n).name)
def test_the_pages_fk_is_kincalcs(name, open_page):
    robot = load(name)
    tab = open_page(name)
    rng = np.random.default_rng(20)
    lo, hi = robot.limits.T
    span = np.where(robot.is_revolute, np.pi, robot.characteristic_length)
    Q = rng.uniform(np.where(np.isfinite(lo), lo, -span), np.where(np.isfinite(hi), hi, span),
                    (25, robot.dof))
    T = tab.eval(f"(() => {{ const c = kincalcView.data.chain; "
                 f"return {json.dumps(Q.tolist())}.map((q) => Kin.fk(c, q)); }})()")
    assert np.abs(np.array(T) - robot.fk(Q)).max() < 1e-9


def test_a_slider_and_a_typed_value_give_kincalcs_fk_and_jacobian(open_page, capsys):
    tab = open_page("puma560", *PUMA_Q)
    # the page opens at Q: its read-out is kincalc fk's
    assert_matches_fk(tab, cli_json(capsys, "fk", "puma560", *PUMA_Q))
    tab.eval("(() => { const s = document.querySelectorAll('#joints input[type=range]')[1];"
             " s.value = '37.5'; s.dispatchEvent(new Event('input')); })()")
    q = ["10", "37.5", "150", "20", "40", "30"]
    assert tab.eval("document.querySelectorAll('#joints input[type=number]')[1].value") == "37.5"
    assert_matches_fk(tab, cli_json(capsys, "fk", "puma560", *q))
    jac = cli_json(capsys, "jacobian", "puma560", *q)
    assert shown(tab, "manipulability")[0] == pytest.approx(jac["manipulability"], rel=1e-9)
    assert tab.eval("document.getElementById('singularity').dataset.value") == "no"
    # typing q5 = 0 lines up the wrist axes: the page says singular, as kincalc does
    tab.eval("(() => { const b = document.querySelectorAll('#joints input[type=number]')[4];"
             " b.value = '0'; b.dispatchEvent(new Event('change')); })()")
    q[4] = "0"
    assert_matches_fk(tab, cli_json(capsys, "fk", "puma560", *q))
    assert cli_json(capsys, "jacobian", "puma560", *q)["singular"]
    assert tab.eval("document.getElementById('singularity').dataset.value") == "singular"
    # a typed value beyond the limits is held at the limit (q1: +-160 deg)
    tab.eval("(() => { const b = document.querySelectorAll('#joints input[type=number]')[0];"
             " b.value = '400'; b.dispatchEvent(new Event('change')); })()")
    assert tab.eval("kincalcView.joints()[0]") == pytest.approx(np.radians(160))


def test_user_units_at_the_edges(open_page, capsys):
    q = ["30", "-60", "700", "20", "40", "0"]                 # d3 = 700 mm
    tab = open_page("stanford_arm", "--unit", "mm", *q)
    assert tab.eval("document.querySelectorAll('#joints .unit')[2].textContent") == "mm"
    assert tab.eval("kincalcView.joints()[2]") == pytest.approx(0.7)
    assert_matches_fk(tab, cli_json(capsys, "fk", "stanford_arm", "--unit", "mm", *q))
    tab = open_page("bk_rr", "--rad", "0.5", "-1")
    assert tab.eval("document.querySelectorAll('#joints .unit')[0].textContent") == "rad"
    assert_matches_fk(tab, cli_json(capsys, "fk", "bk_rr", "--rad", "0.5", "-1"))


def test_choosing_a_branch_sets_its_joints(open_page, capsys):
    tab = open_page("puma560", *PUMA_Q, "--from-q", " ".join(PUMA_Q))
    ik = cli_json(capsys, "ik", "puma560", "--from-q", " ".join(PUMA_Q), "--near",
                  " ".join(PUMA_Q))
    labels = tab.eval("[...document.querySelectorAll('#solutions li > label')]"
                      ".map((l) => l.textContent.trim())")
    assert labels == [f"{k}. {s['branch']}" for k, s in enumerate(ik["solutions"], start=1)]
    outs = tab.eval("[...document.querySelectorAll('#solutions li')]"
                    ".map((li) => !!li.querySelector('.badge.out'))")
    assert outs == [not s["within_limits"] for s in ik["solutions"]]
    tab.eval("document.getElementById('animate').checked = false")
    for k in (len(ik["solutions"]) - 1, 0):
        tab.eval(f"document.querySelectorAll('#solutions input')[{k}].click()")
        q = np.array(tab.eval("kincalcView.joints()"))
        assert np.degrees(q) == pytest.approx(ik["solutions"][k]["q"], abs=1e-9)
        assert tab.eval("[...document.querySelectorAll('#solutions li')]"
                        ".findIndex((li) => li.classList.contains('current'))") == k
        assert readout(tab)["position"] == pytest.approx(
            [row[3] for row in ik["target"]["T"][:3]], abs=1e-9)


def test_animate_moves_through_intermediate_joints(open_page):
    tab = open_page("puma560", *PUMA_Q, "--from-q", " ".join(PUMA_Q))
    frames = tab.eval("""new Promise((done) => {
        const seen = [];
        document.getElementById('animate').checked = true;
        document.querySelectorAll('#solutions input')[3].click();
        const look = () => { seen.push(kincalcView.joints());
          kincalcView.animating() ? requestAnimationFrame(look) : done(seen); };
        requestAnimationFrame(look); })""")
    goal = np.array(tab.eval("kincalcView.data.ik.solutions[3].q")) * np.pi / 180
    start = np.radians([float(v) for v in PUMA_Q])
    assert np.allclose(frames[-1], goal, atol=1e-12)
    middle = [f for f in frames[:-1] if not np.allclose(f, goal) and not np.allclose(f, start)]
    assert len(middle) >= 3
    for f in middle:         # on the straight line from start to goal, in joint space
        s = (np.array(f) - start) @ (goal - start) / ((goal - start) @ (goal - start))
        assert 0 < s < 1 and np.allclose(f, start + s * (goal - start), atol=1e-9)


def test_drag_rotates_the_view_and_the_wheel_zooms(open_page):
    tab = open_page("iiwa14", "20", "30", "0", "-60", "0", "60", "0")
    where = "kincalcView.project(kincalcView.arm().points.at(-1))"
    box = tab.eval("(() => { const r = document.getElementById('scene')"
                   ".getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()")
    x, y = box[0] + box[2] / 2, box[1] + box[3] / 2
    before = tab.eval(where)
    tab.mouse("mousePressed", x, y)
    tab.mouse("mouseMoved", x + 80, y + 30)
    tab.mouse("mouseReleased", x + 80, y + 30)
    rotated = tab.eval(where)
    assert np.hypot(rotated[0] - before[0], rotated[1] - before[1]) > 10
    centre = np.array([box[2] / 2, box[3] / 2])
    tab.mouse("mouseWheel", x, y, deltaY=-300)              # zoom in: away from the centre
    zoomed = tab.eval(where)
    assert np.linalg.norm(np.array(zoomed[:2]) - centre) > \
        1.2 * np.linalg.norm(np.array(rotated[:2]) - centre)
    tab.eval("document.getElementById('reset-view').click()")
    assert tab.eval(where) == pytest.approx(before)
    tab.eval("document.querySelector('input[value=perspective]').click()")
    assert tab.eval(where) != pytest.approx(before)


def test_the_screenshot_shows_the_arm(open_page, tmp_path):
    Image = pytest.importorskip("PIL.Image", reason="reading the screenshot needs Pillow "
                                "(with matplotlib in the test extra)")
    tab = open_page("puma560", *PUMA_Q)
    canvas = tab.eval("(() => { const r = document.getElementById('scene')"
                      ".getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()")
    # where the page drew the links and the tool's origin (page pixels)
    drawn = np.array(tab.eval("kincalcView.arm().points.map((p) => kincalcView.project(p))"))
    drawn = drawn[:, :2] + canvas[:2]
    image = np.asarray(Image.open(tab.screenshot(tmp_path / "puma.png")).convert("RGB"), int)
    assert image.shape[:2] == (860, 1280)
    link = np.array([0x3b, 0x4a, 0x5a])                        # LINK_COLOUR of the drawings
    # (the links' own colour, not a blend of antialiased neighbours)
    ys, xs = np.nonzero(np.abs(image - link).sum(axis=-1) < 12)
    assert len(xs) > 500, "hardly any pixel of the links' colour"
    # the links' pixels are where the page put the links: the same box, to a link's width
    box = [xs.min(), ys.min(), xs.max(), ys.max()]
    expected = [*drawn.min(axis=0), *drawn.max(axis=0)]
    assert np.abs(np.array(box) - expected).max() < 10, (box, expected)
    # the tool triad: red, green and blue pixels near the tool's origin
    tx, ty = np.round(drawn[-1]).astype(int)
    near = image[ty - 60:ty + 60, tx - 60:tx + 60].reshape(-1, 3)
    for colour in ((0xd6, 0x27, 0x28), (0x2c, 0xa0, 0x2c), (0x1f, 0x77, 0xb4)):
        assert (np.abs(near - colour).sum(axis=-1) < 40).sum() > 20, colour
    # and the canvas' corner is background
    corner = image[int(canvas[1]) + 3, int(canvas[0]) + 3]
    assert corner.tolist() == [255, 255, 255]


#: every text of the joints panel and the DH table: the cells, the unit and limits
#: spans, the number boxes
TEXTS = "#joints th, #joints td, #joints span, #joints input[type=number], #dh th, #dh td"


@pytest.mark.parametrize("args, box", [
    (["puma560", "1e9", "0", "0", "0", "0", "0"], "1000000000.00"),
    ([str(Path(__file__).parents[1] / "conventions" / "urdf" / "ur5.urdf"), "--rad",
      "--unit", "mm"], "0.0000")], ids=["huge-joint", "ur5-rad-mm"])
def test_no_value_is_hidden_in_the_joints_or_the_dh_table(args, box, open_page):
    # the project's rule: a table never hides a value; what does not fit wraps or stacks
    tab = open_page(*args)
    assert tab.eval("document.querySelector('#joints input[type=number]').value") == box
    hidden = tab.eval(f"""(() => {{
        const out = [];
        const pane = (e) => e.closest('#side, #view-pane').getBoundingClientRect();
        document.querySelectorAll({json.dumps(TEXTS)}).forEach((e) => {{
          const r = e.getBoundingClientRect();
          const text = e.value !== undefined && e.tagName === 'INPUT' ? e.value : e.textContent;
          if (e.scrollWidth > e.clientWidth || r.right > pane(e).right + 0.5 ||
              r.left < pane(e).left - 0.5) out.push(text);
        }});
        ['side', 'view-pane'].forEach((id) => {{ const p = document.getElementById(id);
          if (p.scrollWidth > p.clientWidth) out.push('#' + id); }});
        return out; }})()""")
    assert hidden == []
    # a unit word is a word: "3.1416 rad" (and "90.00°", which needs no space)
    dh = tab.eval("document.getElementById('dh').innerText")
    assert not re.search(r"\drad", dh), dh
