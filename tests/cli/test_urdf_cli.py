"""URDF robots through the command line: every command takes one, errors are one line
with exit 2, and malformed URDFs (seeded mutations of real ones) never break the CLI's
contract."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from cli_contract import assert_contract, run_cli, snapshot

DATA = Path(__file__).resolve().parent.parent / "conventions" / "urdf"


@pytest.fixture
def arms(tmp_path):
    for f in DATA.glob("*.urdf"):
        shutil.copy(f, tmp_path / f.name)
    return tmp_path


def test_every_command_takes_a_urdf(arms):
    ur5 = str(arms / "ur5.urdf")
    links = ["--base-link", "base", "--tip-link", "tool0"]
    status, out, err = run_cli(["fk", ur5, "10", "-20", "30", "-40", "50", "-60", "--json",
                                *links])
    assert status == 0, err
    T = np.array(json.loads(out)["T"])
    import kincalc
    from kincalc.conventions.urdf import load_urdf
    robot = load_urdf(ur5, base_link="base", tip_link="tool0")
    assert np.allclose(T, robot.fk(np.radians([10, -20, 30, -40, 50, -60])), atol=1e-9)
    # the same pose as the bundled ur5 (UR's DH table) puts it, to the position
    ref = kincalc.load_robot("ur5").fk(np.radians([10, -20, 30, -40, 50, -60]))
    assert np.allclose(T[:3, 3], ref[:3, 3], atol=1e-9)
    status, out, err = run_cli(["ik", ur5, "--from-q", "10 -20 30 -40 50 -60", "--json",
                                *links])
    assert status == 0, err
    doc = json.loads(out)
    count = len(kincalc.load_robot("ur5").ik(ref).solutions)   # the DH model's own count
    assert len(doc["solutions"]) == count
    for s in doc["solutions"]:
        assert np.allclose(robot.fk(np.radians(s["q"])), T, atol=1e-9)
    assert any(np.allclose(s["q"], [10, -20, 30, -40, 50, -60], atol=1e-6)
               for s in doc["solutions"])
    for argv in (["jacobian", ur5, "0", "-90", "90", "0", "90", "0", "--json"],
                 ["reach", ur5, "--xyz", "0.4", "0.1", "0.3", "--json"],
                 ["robots", "show", ur5, "--json"], ["robots", "validate", ur5],
                 ["selftest", ur5, "--trials", "20", "--json"]):
        status, out, err = run_cli(argv)
        assert status == 0, (argv, err)
    status, out, err = run_cli(["convert", ur5, "--to", "dh", "-o", str(arms / "ur5_dh.yaml")])
    assert status == 0, err
    status, out, err = run_cli(["compare", ur5, str(arms / "ur5_dh.yaml"), "--json"])
    assert status == 0 and json.loads(out)["same"], err


def test_batch_ik_of_a_urdf_robot_in_two_processes(arms):
    from kincalc.conventions.urdf import load_urdf
    robot = load_urdf(arms / "iiwa14.urdf", tip_link="iiwa_link_ee_kuka")
    rng = np.random.default_rng(3)
    q = rng.uniform(-1, 1, (40, 7))
    lines = "".join(json.dumps({"q": list(np.degrees(qq))}) + "\n" for qq in q)
    argv = ["fk", str(arms / "iiwa14.urdf"), "--batch", "-", "-j", "2",
            "--tip-link", "iiwa_link_ee_kuka"]
    status, out, err = run_cli(argv, stdin=lines)
    assert_contract(status, out, err, argv, records=40)
    got = [json.loads(line)["xyz"] for line in out.splitlines()]
    assert np.allclose(got, robot.fk(q)[:, :3, 3], atol=1e-9)


@pytest.mark.parametrize("argv,words", [
    (["fk", "{d}/panda.urdf"], "the tree branches below link 'panda_link7'"),
    (["fk", "{d}/panda.urdf", "--tip-link", "panda_rightfinger"], "is a <mimic> joint"),
    (["fk", "{d}/panda.urdf", "--tip-link", "nowhere"], "--tip-link 'nowhere' is not a link"),
    (["fk", "puma560", "--tip-link", "x"], "--tip-link chooses the chain of a URDF robot; "
                                           "puma560 is not a .urdf file"),
    (["fk", "{d}/arm.urdf.xacro"], "a .xacro file is a macro program, not a URDF"),
    (["fk", "{d}/missing.urdf"], "missing.urdf: no such file"),
])
def test_urdf_mistakes_are_one_line_with_exit_2(arms, argv, words):
    (arms / "arm.urdf.xacro").write_text('<robot xmlns:xacro="x"><xacro:macro/></robot>')
    argv = [a.format(d=arms) for a in argv]
    status, out, err = run_cli(argv)
    assert status == 2 and out == ""
    assert words in err and err.count("\n") == 1 and "Traceback" not in err


def _mutations(text: str, rng, count: int):
    """Seeded damage to a URDF: cut it short, drop or double a character run, swap in a
    hostile token, or change a number."""
    hostile = ['<!DOCTYPE r [<!ENTITY a "aaaa">]>', "&a;", "<joint/>", "nan", "1e400",
               '"', "<", "]]>", "\x00", "type=\"floating\"", "<mimic joint=\"j\"/>",
               '<link name="base_link"/>', "${pi}", "\ufffd", "-0", " " * 50]
    for _ in range(count):
        k = int(rng.integers(0, 4))
        i = int(rng.integers(0, len(text)))
        j = min(len(text), i + int(rng.integers(1, 40)))
        if k == 0:
            yield text[:i]
        elif k == 1:
            yield text[:i] + text[j:]
        elif k == 2:
            yield text[:i] + hostile[int(rng.integers(0, len(hostile)))] + text[i:]
        else:
            yield text[:i] + text[i:j] + text[i:]


def test_malformed_urdfs_never_break_the_contract(tmp_path):
    rng = np.random.default_rng(2026)
    texts = [(DATA / f).read_text() for f in ("ur5.urdf", "panda.urdf", "gen3_7dof.urdf")]
    f = tmp_path / "fuzz.urdf"
    before = None
    for n, text in enumerate(t for base in texts for t in _mutations(base, rng, 400)):
        f.write_text(text, encoding="utf-8", errors="surrogateescape")
        if before is None:
            before = snapshot(tmp_path)
        argv = ["fk", str(f), "--json"] if n % 2 else ["robots", "validate", str(f)]
        status, out, err = run_cli(argv)
        assert_contract(status, out, err, argv)
        assert status in (0, 2), (argv, err)
        if status == 2:
            assert err.startswith(f"kincalc: error: {f}"), err
    assert snapshot(tmp_path).keys() == before.keys()


def test_robots_list_filters_by_family_and_dof():
    """The ik column is the family each robot's axes give (checked against plan, the
    engine's own choice), and the filters keep exactly the matching robots."""
    import kincalc
    from kincalc.ik.families import plan
    status, out, err = run_cli(["robots", "list", "--json"])
    everyone = json.loads(out)["robots"]
    for e in everyone:
        family = plan(kincalc.load_robot(e["name"]))[1]
        assert e["ik"] == (family.name if family else "numerical")
    status, out, err = run_cli(["robots", "list", "--family", "three-parallel", "--dof", "6",
                                "--json"])
    kept = json.loads(out)["robots"]
    assert status == 0 and kept and all(e["ik"] == "three-parallel" for e in kept)
    assert {e["name"] for e in kept} == {e["name"] for e in everyone
                                         if e["ik"] == "three-parallel" and e["dof"] == 6}
    status, out, err = run_cli(["robots", "list", "--dof", "7"])
    assert status == 0 and "with 7 joints" in out and "panda" in out and "puma560" not in out


def test_compare_applies_the_links_to_the_urdf_side(arms):
    """A YAML robot against a URDF's chosen chain: the links were refused for the YAML."""
    status, out, err = run_cli(["compare", "ur5", str(arms / "ur5.urdf"), "--base-link", "base",
                                "--tip-link", "tool0", "--free-tool", "--json"])
    assert status == 0, err
    assert json.loads(out)["same"]
    status, out, err = run_cli(["compare", "ur5", "puma560", "--tip-link", "tool0"])
    assert status == 2 and "not a .urdf file" in err
