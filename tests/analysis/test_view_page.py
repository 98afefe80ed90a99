"""The page of ``kincalc view`` as text: what it embeds, that it needs nothing from
outside, that no name from a robot file can break out of its data, and that every robot
kincalc loads gets one. (The page running in a browser: tests/analysis/test_view_browser.py.)
"""

from __future__ import annotations

import dataclasses
import json
import re
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from kincalc.analysis.results import Units
from kincalc.analysis.view import ASSETS, dh_table, embedded_json, page_data, page_html
from kincalc.conventions import convert
from kincalc.conventions.library import bundled_names, load
from kincalc.ik import Target, solve

URDF = Path(__file__).parents[1] / "conventions" / "urdf"
#: the URDF test robots, and the link their chain ends at where the tree branches
URDFS = {"ur5.urdf": None, "iiwa14.urdf": None, "panda.urdf": "panda_hand_tcp",
         "gen3_7dof.urdf": None}
DATA = re.compile(r'<script type="application/json" id="kincalc-data">(.*?)</script>', re.S)


def embedded(page: str) -> dict:
    (text,) = DATA.findall(page)
    return json.loads(text)


def urdf_robot(name):
    return load(str(URDF / name), tip_link=URDFS[name])


@pytest.mark.parametrize("name", bundled_names())
def test_every_bundled_robot_gets_its_own_chain(name):
    robot = load(name)
    data = embedded(page_html(robot, Units(length=robot.length_unit)))
    assert np.array_equal(data["chain"]["fixed"], robot.chain.fixed)
    assert data["chain"]["revolute"] == robot.chain.revolute.tolist()
    assert np.array_equal(data["chain"]["offset"], robot.chain.offset)
    assert [j["name"] for j in data["joints"]] == [j.name for j in robot.joints]
    assert len(data["dh"]["rows"]) == robot.dof
    assert data["q"] == robot.home.tolist()


@pytest.mark.parametrize("name", sorted(URDFS))
def test_urdf_robots_get_a_page_with_the_dh_table_of_their_axes(name):
    robot = urdf_robot(name)
    data = page_data(robot, Units())
    assert np.array_equal(data["chain"]["fixed"], robot.chain.fixed)
    dh = convert(robot, "dh")
    assert data["dh"]["title"].startswith("Standard DH table of the same axes")
    assert [row[0][2] or row[1][2] for row in data["dh"]["rows"]] == [j.name for j in dh.joints]
    assert [row[2][0] for row in data["dh"]["rows"]] == pytest.approx([j.a for j in dh.joints])


def test_dh_table_is_the_robots_own_in_its_convention():
    puma = load("puma560")
    t = dh_table(puma)
    assert t["columns"] == ["θ_i", "d_i", "a_i", "α_i"]
    j = puma.joints[1]
    assert t["rows"][1] == [[j.theta, "angle", j.name], [j.d, "length", None],
                            [j.a, "length", None], [j.alpha, "angle", None]]
    mdh = dh_table(load("puma560_mdh"))
    assert mdh["title"] == "Modified DH table (Craig)" and mdh["columns"][0] == "α_{i-1}"
    stanford = dh_table(load("stanford_arm"))           # the prismatic joint's variable is d
    assert stanford["rows"][2][1][2] == "d3" and stanford["rows"][2][0][2] is None


def test_units_and_limits_are_carried_for_the_edges():
    robot = load("stanford_arm")
    data = page_data(robot, Units(angle="rad", length="mm"))
    assert data["units"] == {"angle": "rad", "length": "mm", "per_rad": 1.0, "per_m": 1000.0}
    assert data["joints"][2]["limits"] == pytest.approx(list(robot.joints[2].limits))
    assert page_data(load("bk_rr"), Units(length="unitless"))["joints"][0]["limits"] is None


def test_ik_solutions_are_kincalc_iks_document():
    from kincalc.analysis.results import ik_document
    robot, units = load("puma560"), Units()
    q = np.radians([10, -30, 150, 20, 40, 30])
    result = solve(robot, Target(robot.fk(q), orientation=True), units=units)
    data = page_data(robot, units, q, result)
    assert data["ik"] == json.loads(json.dumps(ik_document(result)))
    assert len(data["ik"]["solutions"]) == 8
    assert data["q"] == q.tolist()


def test_the_page_needs_nothing_from_outside():
    page = page_html(load("puma560"), Units())
    code = DATA.sub("", page)              # the robot's own words (a source URL) aside
    for needle in ("http:", "https:", "//cdn", " src=", "href=", "url(", "@import",
                   "<link", "<iframe", "fetch(", "XMLHttpRequest", "import("):
        assert needle not in code, needle
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    assert "{{" not in page                # every placeholder filled


def test_assets_are_package_data_that_cannot_end_their_element():
    folder = resources.files("kincalc.analysis.view")
    for name in list(ASSETS.values()) + ["page.html"]:
        text = folder.joinpath(name).read_text(encoding="utf-8")
        if name != "page.html":
            assert "</script" not in text.lower() and "</style" not in text.lower(), name
    for name in ("kin.js", "scene.js", "page.js"):
        code = folder.joinpath(name).read_text(encoding="utf-8")
        # names from robot files reach the DOM as text only
        for sink in ("innerHTML", "outerHTML", "insertAdjacentHTML", "document.write",
                     "eval(", "new Function"):
            assert sink not in code, f"{name} uses {sink}"


HOSTILE = "</script><script>alert(1)</script><!-- & \u2028 {{DATA}}"


def test_names_from_the_robot_file_cannot_leave_the_data():
    robot = load("bk_rr")
    joints = tuple(dataclasses.replace(j, name=HOSTILE + str(k))
                   for k, j in enumerate(robot.joints))
    robot = dataclasses.replace(robot, name=HOSTILE, title=HOSTILE, source=HOSTILE,
                                joints=joints)
    page = page_html(robot, Units(length="unitless"))
    assert page.count("</script>") == 5     # the guard, the data and the three scripts
    assert "<script>alert" not in page and "<!--" not in page.split("<body>")[1]
    data = embedded(page)
    assert data["robot"]["name"] == HOSTILE and data["joints"][1]["name"] == HOSTILE + "1"
    assert "<title>&lt;/script&gt;" in page


def test_embedded_json_escapes_what_html_would_read():
    text = embedded_json({"a": "</script>&<!--\u2028"})
    assert not set("<>&\u2028") & set(text)
    assert json.loads(text) == {"a": "</script>&<!--\u2028"}
    with pytest.raises(ValueError):
        embedded_json({"x": float("nan")})
