"""Every bundled robot is a test input: it loads, cites a source, converts between
conventions, and matches golden FK facts taken from independent sources."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, mdh_to_dh, to_poe
from kincalc.conventions.library import bundled_names, library_dir

REPO_ROBOTS = Path(__file__).parents[2] / "robots"
#: the facts files: robot_facts.yaml and one robot_facts_<group>.yaml per group of the zoo
FACTS = sorted((Path(__file__).parents[1] / "golden").glob("robot_facts*.yaml"))
NAMES = sorted(p.stem for p in REPO_ROBOTS.glob("*.yaml"))


def test_library_has_at_least_75_robots():
    assert len(NAMES) >= 75, NAMES


def test_installed_library_is_complete():
    # Whether kincalc runs from the tree or from a wheel, it sees every robot.
    assert bundled_names() == NAMES, library_dir()


@pytest.mark.parametrize("name", NAMES)
def test_robot_loads_and_cites_a_source(name):
    r = load_robot(name)
    assert r.name == name
    assert r.title and len(r.source) > 20, "every robot file cites its source"
    assert r.home.shape == (r.dof,)
    lo, hi = r.limits.T
    assert np.all((r.home >= lo - 1e-9) & (r.home <= hi + 1e-9))


@pytest.mark.parametrize("name", NAMES)
def test_robot_converts_between_conventions(name):
    r = load_robot(name)
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (1000, r.dof))
    ref = r.fk(q)
    others = [to_poe(r)]
    if r.convention == "dh":
        others.append(dh_to_mdh(r))
    elif r.convention == "mdh":
        others.append(mdh_to_dh(r))
    scale = max(1.0, r.characteristic_length)
    for o in others:
        assert np.abs(o.fk(q) - ref).max() < 1e-12 * scale


PAIRS = [("puma560", "puma560_mdh")]


@pytest.mark.parametrize("a,b", [p for p in PAIRS if all(n in NAMES for n in p)])
def test_robots_shipped_in_two_conventions_agree(a, b):
    ra, rb = load_robot(a), load_robot(b)
    assert ra.convention != rb.convention
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (1000, ra.dof))
    assert np.abs(ra.fk(q) - rb.fk(q)).max() < 1e-12


def facts():
    return [f for path in FACTS for f in yaml.safe_load(path.read_text(encoding="utf-8")) or []]


def test_golden_facts_cover_the_library():
    """Every bundled robot has at least one FK fact from its source."""
    covered = {f["robot"] for f in facts()}
    assert not set(NAMES) - covered, sorted(set(NAMES) - covered)
    assert not covered - set(NAMES), sorted(covered - set(NAMES))


@pytest.mark.parametrize("fact", facts(), ids=lambda f: f"{f['robot']}:{f.get('source', '')[:30]}")
def test_golden_fk_facts(fact):
    r = load_robot(fact["robot"])
    from kincalc.units import ANGLE_UNITS, LENGTH_UNITS
    A, L = ANGLE_UNITS[r.angle_unit], LENGTH_UNITS[r.length_unit]
    q = np.array(fact["q"], float) * np.where(r.is_revolute, A, L)
    T = r.fk(q)
    tol = fact.get("tolerance", 1e-4)
    assert np.allclose(T[:3, 3] / L, fact["position"], atol=tol), (T[:3, 3] / L, fact["source"])
    if "rotation" in fact:
        assert np.allclose(T[:3, :3], fact["rotation"], atol=fact.get("rotation_tolerance", 1e-4))


# --- names and files the system cannot hold or kincalc will not read (issue 14) -------

from kincalc import limits  # noqa: E402
from kincalc.conventions import reader as robot_file  # noqa: E402
from kincalc.errors import RobotFileError, RobotNotFoundError  # noqa: E402
from kincalc.conventions.library import load, resolve  # noqa: E402


@pytest.mark.parametrize("name", ["a" * 300, "a" * 5000, "a\0b", "pum\0a560"])
def test_resolve_a_name_no_file_can_have(name):
    # ENAMETOOLONG or a NUL character: no robot of that name, not an OSError
    with pytest.raises(RobotNotFoundError) as info:
        resolve(name)
    message = str(info.value)
    assert len(message) < 300
    if len(name) > limits.MAX_QUOTE:
        assert f"({len(name)} characters)" in message


@pytest.mark.parametrize("name,words", [
    ("a" * 300 + ".yaml", "the name is too long for a file"),
    ("a/" * 2100 + "x.yaml", "the name is too long for a file"),
    ("arm\0.yaml", "not a valid file name"),
])
def test_load_a_path_no_file_can_have(name, words):
    with pytest.raises(RobotFileError, match=words):
        load(name)


def test_read_text_is_bounded(tmp_path):
    big = tmp_path / "big.yaml"
    big.write_bytes(b"#" * (limits.MAX_FILE_BYTES + 1))
    for path in (big, "/dev/zero"):
        with pytest.raises(RobotFileError, match="larger than 1 MiB, kincalc's limit for a "
                                                 "robot file") as info:
            robot_file.load_robot_file(path)
        assert info.value.line is None
    big.write_bytes(b"#" * limits.MAX_FILE_BYTES)        # at the limit: read (and empty)
    with pytest.raises(RobotFileError, match="the file is empty"):
        robot_file.load_robot_file(big)
    assert robot_file.read_text(big, "big", "a file", limit=10 ** 7) == "#" * limits.MAX_FILE_BYTES


def test_read_text_reports_the_line_of_a_bad_byte(tmp_path):
    path = tmp_path / "bin.yaml"
    path.write_bytes(b"name: x\ntitle: \xff\n")
    with pytest.raises(RobotFileError) as info:
        robot_file.read_text(path, "bin.yaml", "a robot file")
    assert info.value.line == 2 and "0xff" in str(info.value)


def test_max_magnitude_is_the_shared_limit():
    # robot_file.MAX_MAGNITUDE was a copy; it stays importable and is the same number
    assert robot_file.MAX_MAGNITUDE is limits.MAX_MAGNITUDE


def test_a_base_rotation_typed_to_six_decimals_is_read(tmp_path):
    """A base matrix whose rotation is a rotation rounded to six decimals, the worst kind
    (R R^T off the identity by 1.45e-6 at an off-diagonal entry: 2.4 % of random rotations
    so rounded were refused as "not a rotation" at 1e-6), is read and re-orthonormalised."""
    R = [[-0.32236, 0.721141, -0.613221], [0.571451, 0.664695, 0.481274],
         [0.754671, -0.195282, -0.626368]]
    base = [row + [x] for row, x in zip(R, (0.1, 0.2, 0.3))] + [[0, 0, 0, 1]]
    doc = {"name": "typed", "convention": "dh", "units": {"length": "m", "angle": "rad"},
           "base": base,
           "joints": [{"name": "q1", "type": "revolute", "alpha": 0, "a": 0.5, "d": 0,
                       "theta": 0}]}
    path = tmp_path / "typed.yaml"
    path.write_text(yaml.safe_dump(doc))
    r = load_robot(str(path))
    B = r.base[:3, :3]
    assert np.abs(B @ B.T - np.eye(3)).max() < 1e-14
    assert np.abs(B - np.array(R)).max() < 1e-6


def test_an_unknown_key_message_is_the_same_in_every_run(tmp_path):
    """The keys a base or tool allows were a set: the message listed them in another order
    from one run to the next (hostile-input campaign). Three hash seeds, one message."""
    import os
    import subprocess
    import sys
    f = tmp_path / "tool_extra.yaml"
    f.write_text("name: h\nconvention: dh\nunits: {length: m, angle: deg}\njoints:\n"
                 "  - {name: q1, type: revolute, alpha: 0, a: 0.3, d: 0, theta: 0}\n"
                 "tool: {xyz: [0, 0, 0], foo: 1}\n")
    errs = set()
    for seed in ("1", "2", "3"):
        p = subprocess.run([sys.executable, "-m", "kincalc", "robots", "validate", str(f)],
                           capture_output=True, text=True, env={**os.environ,
                                                                "PYTHONHASHSEED": seed})
        assert p.returncode == 2
        errs.add(p.stderr)
    assert len(errs) == 1 and "(allowed: xyz, rpy, matrix)" in errs.pop()
