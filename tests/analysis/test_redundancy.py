"""Redundant arms with a locked joint: the locked chain is the arm (FK), every branch of
it is found (round trips of random configurations, and no solution an independent
multi-start numerical search finds is missing), and the command line says what was
locked."""

import json

import numpy as np
import pytest
from randrobots import random_robot

import kincalc
from kincalc.analysis.redundancy import locked_robot, solve_locked
from kincalc.errors import InputError
from kincalc.ik import Target
from kincalc.ik.families import plan

SEVEN = ["iiwa14", "iiwa7", "panda", "kinova_gen3"]


def _close(a, b, revolute, tol=1e-6):
    d = np.where(revolute, np.angle(np.exp(1j * (a - b))), a - b)
    return np.abs(d).max() < tol


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_the_locked_chain_is_the_arm_with_the_joint_held(convention):
    rng = np.random.default_rng({"dh": 1, "mdh": 2, "poe": 3}[convention])
    for _ in range(20):
        r = random_robot(rng, convention, n=int(rng.integers(2, 9)))
        held = sorted(rng.choice(r.dof, size=int(rng.integers(1, r.dof)), replace=False))
        values = rng.uniform(-2, 2, len(held))
        red = locked_robot(r, dict(zip(held, values)))
        keep = [k for k in range(r.dof) if k not in held]
        assert [j.name for j in red.joints] == [r.joints[k].name for k in keep]
        for q in rng.uniform(-2, 2, (20, r.dof)):
            q[held] = values
            assert np.allclose(red.fk(q[keep]), r.fk(q), atol=1e-12)


@pytest.mark.parametrize("name", SEVEN)
def test_every_lock_of_a_seven_joint_arm_finds_the_generating_configuration(name):
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(sum(map(ord, name)))
    lo, hi = np.clip(r.limits, -np.pi, np.pi).T
    elbow = _srs_elbow(r)
    for q0 in rng.uniform(lo, hi, (4, 7)):
        T = r.fk(q0)
        for j in range(7):
            if j == elbow:
                with pytest.raises(InputError, match="continuum"):
                    solve_locked(r, Target(T), {j: q0[j]})
                continue
            res = solve_locked(r, Target(T), {j: q0[j]})
            assert res.locked == ((j, q0[j]),)
            assert any(_close(s.q, q0, r.is_revolute) for s in res.solutions), (j, res.method)
            for s in res.solutions:
                assert s.q[j] == q0[j]
                assert np.allclose(r.fk(s.q), T, atol=1e-9)


def _srs_elbow(robot):
    """Joint 4 (index 3) when joints 1-3 and 5-7 each meet at a point (an SRS arm),
    found from the axes at q = 0 with a least-squares common point; else None."""
    from kincalc.structure import common_point, joint_axes
    dirs, pts = joint_axes(robot)
    meets = [common_point(pts[js], dirs[js], 1e-9 * robot.characteristic_length) is not None
             for js in ([0, 1, 2], [4, 5, 6])]
    return 3 if all(meets) else None


def test_locking_gives_the_analytic_family_the_geometry_has():
    """iiwa (an SRS arm): any single lock leaves a spherical wrist at one end; the Panda
    with joint 7 held: joints 1-3 meet (a wrist at the base, seen from the tool)."""
    iiwa, panda = kincalc.load_robot("iiwa14"), kincalc.load_robot("panda")
    assert plan(locked_robot(iiwa, {2: 0.4}))[1].name == "spherical-wrist"
    assert plan(locked_robot(panda, {6: 0.4}))[1].name == "reversed-spherical-wrist"
    assert plan(locked_robot(panda, {0: 0.4}))[1].name == "general-6r"


def _numeric_solutions(robot, T, starts, rng):
    """Damped least squares from many random starts, written here (no kincalc IK): the
    distinct configurations that reach ``T``."""
    found = []
    for q in rng.uniform(-np.pi, np.pi, (starts, robot.dof)):
        for _ in range(60):
            E = robot.fk(q)
            dp = T[:3, 3] - E[:3, 3]
            Rerr = T[:3, :3] @ E[:3, :3].T
            dw = 0.5 * np.array([Rerr[2, 1] - Rerr[1, 2], Rerr[0, 2] - Rerr[2, 0],
                                 Rerr[1, 0] - Rerr[0, 1]])
            e = np.concatenate([dp, dw])
            if np.linalg.norm(e) < 1e-12:
                break
            J = robot.jacobian(q)
            q = q + J.T @ np.linalg.solve(J @ J.T + 1e-6 * np.eye(6), e)
        if np.linalg.norm(e) < 1e-10 and not any(_close(q, f, robot.is_revolute, 1e-5)
                                                  for f in found):
            found.append(q)
    return found


def test_no_solution_of_an_independent_search_is_missing():
    r = kincalc.load_robot("panda")
    rng = np.random.default_rng(5)
    q0 = rng.uniform(*np.clip(r.limits, -np.pi, np.pi).T)
    locks = {0: q0[0]}                                     # general 6R left: the hard case
    red = locked_robot(r, locks)
    T = r.fk(q0)
    ours = solve_locked(r, Target(T), locks).solutions
    theirs = _numeric_solutions(red, T, 300, rng)
    assert theirs and len(ours) <= 16
    for q in theirs:
        assert any(_close(s.q[1:], q, red.is_revolute, 1e-5) for s in ours)


@pytest.mark.parametrize("a2,a6", [(-0.5, 0.005), (-0.005, 0.005), (-0.05, -0.005)])
def test_a_structure_held_exactly_wins_over_one_held_nearly(a2, a6):
    """iiwa14 held at A6 = 0.005 deg is a spherical wrist (axes A4, A5, A7) to 2e-5 m and a
    reversed one (A1, A2, A3 meet) exactly: the near family's solutions, refined by Newton,
    lost the four roots with the other elbow, the generating configuration among them
    (redundant-arm oracle, whose own search polished eight exact roots in 40 digits: four
    with each sign of A4)."""
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([83, a2, 4, -41, -121, a6, -26])
    locks = {5: q0[5]}
    red = locked_robot(r, locks)
    family = plan(red)[1]
    assert family.name == "reversed-spherical-wrist" and family.exact
    T = r.fk(q0)
    ours = solve_locked(r, Target(T), locks).solutions
    assert any(_close(s.q, q0, r.is_revolute) for s in ours)
    assert len(ours) == 8
    assert sorted(np.sign(s.q[3]) for s in ours) == [-1] * 4 + [1] * 4
    for k, s in enumerate(ours):
        assert s.q[5] == q0[5] and np.allclose(r.fk(s.q), T, atol=1e-9)
        assert not any(_close(s.q, o.q, r.is_revolute, 1e-6) for o in ours[:k])


def test_a_held_value_outside_its_limits_flags_every_solution():
    r = kincalc.load_robot("iiwa14")
    q0 = np.zeros(7) + 0.3
    res = solve_locked(r, Target(r.fk(q0)), {2: 3.5})       # beyond +-170 deg
    assert all(not s.within_limits and any(v[0] == 2 for v in s.violations)
               for s in res.solutions)
    assert not res.reachable and 2 in dict(res.reason.worst)


def test_the_reason_names_the_arms_joints():
    """A pose every branch of the held chain reaches only outside the limits: the reason
    names the joints the solutions break (the arm's, not the chain's numbering)."""
    r = kincalc.load_robot("iiwa14")
    T = np.eye(4)
    T[:3, :3] = np.diag([1.0, -1.0, -1.0])
    T[2, 3] = 0.034
    res = solve_locked(r, Target(T), {2: 0.0})
    assert res.solutions and not res.reachable
    broken = {v[0] for s in res.solutions for v in s.violations}
    assert set(dict(res.reason.worst)) == broken and 2 not in broken


def test_dead_ends_name_the_arms_joints():
    """--all-branches of a held chain out of reach: each step that found no real root
    names the arm's joint (iiwa7, A3 held: the chain's joint 3 is the arm's A4)."""
    r = kincalc.load_robot("iiwa7")
    T = r.fk(np.zeros(7))
    T[:3, 3] = [1.5, 0.1, 0.3]
    res = solve_locked(r, Target(T), {2: 0.0}, all_branches=True)
    assert res.dead_ends and not res.solutions
    assert {d.joint for d in res.dead_ends} <= {0, 1, 3, 4, 5, 6}
    assert 3 in {d.joint for d in res.dead_ends}


def test_lock_on_the_command_line():
    from cli_contract import run_cli
    q0 = "20 -30 40 -50 60 30 -20"
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, "--lock", "A3=40", "--json"])
    assert status == 0, err
    doc = json.loads(out)
    assert doc["locked"] == [{"joint": kincalc.load_robot("iiwa14").joints[2].name,
                              "value": 40.0}]
    assert doc["method"]["family"] == "spherical-wrist"
    q = [20, -30, 40, -50, 60, 30, -20]
    assert any(np.allclose(s["q"], q, atol=1e-6) for s in doc["solutions"])
    assert all(s["q"][2] == 40.0 for s in doc["solutions"])
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, "--lock", "3=40"])
    assert status == 0 and "locked" in out
    for bad, words in ((["--lock", "9=1"], "no joint '9'"), (["--lock", "3"], "JOINT=VALUE"),
                       (["--lock", "3=x"], "not a number"),
                       (["--lock", "3=1", "--lock", "3=2"], "locked twice"),
                       (["--lock", "A3=1e400"], "not a finite number"),
                       (["--lock", "=5"], "JOINT=VALUE"), (["--lock", "0=1"], "no joint '0'"),
                       ([x for k in range(1, 8) for x in ("--lock", f"{k}=0")], "nothing is left")):
        status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, *bad])
        assert status == 2 and words in err and err.count("\n") == 1, err


def test_reach_with_a_lock_asks_of_the_chain_left():
    from cli_contract import run_cli
    q0 = "10 20 30 -40 50 60 70"
    status, out, err = run_cli(["reach", "iiwa14", "--from-q", q0, "--lock", "A3=30", "--json"])
    assert status == 0, err
    doc = json.loads(out)
    assert doc["locked"] == [{"joint": "A3", "value": 30.0}] and doc["solutions"] == 8
    # held where the pose cannot be reached with it: A3 = 30 and a pose of A3 = -120
    q1 = "10 20 -120 -40 50 60 70"
    status, out, err = run_cli(["reach", "iiwa14", "--from-q", q1, "--lock", "A3=30"])
    assert status in (0, 1) and "locked" in out
    status, out, err = run_cli(["reach", "iiwa14", "--batch", "-", "--lock", "A3=30"],
                               stdin='{"xyz": [0.5, 0, 0.5]}\n')
    assert status == 2 and "--lock" in err


def test_selftest_of_locked_and_swivel_ik():
    """Round trips through the closed forms of a redundant arm: the generating joints come
    back every time, no solution misses its pose."""
    from cli_contract import run_cli
    for extra, family, count in ((["--lock-joint", "A3"], "spherical-wrist", "8"),
                                 (["--lock-joint", "7"], "reversed-spherical-wrist", "8"),
                                 (["--swivel"], "srs-swivel", "8")):
        status, out, err = run_cli(["selftest", "iiwa14", "--trials", "40", "--seed", "3",
                                    "--json", *extra])
        assert status == 0, (extra, err)
        doc = json.loads(out)
        assert doc["method"]["family"] == family
        assert doc["success_rate"] == 1.0 and doc["wrong_solution_rate"] == 0.0
        assert set(doc["solutions_per_pose"]) == {count}
    for extra, words in ((["--lock-joint", "A4"], "continuum"),
                         (["--lock-joint", "A3", "--swivel"], "do not go together"),
                         (["--lock-joint", "A9"], "no joint")):
        status, out, err = run_cli(["selftest", "iiwa14", "--trials", "5", *extra])
        assert status == 2 and words in err, (extra, err)
    status, out, err = run_cli(["selftest", "panda", "--trials", "5", "--swivel"])
    assert status == 2 and "spherical shoulder" in err


def test_the_families_the_readme_states_for_each_lock():
    """The README's table of the family each single lock of a bundled 7-joint arm leaves."""
    import re
    from pathlib import Path
    text = Path(__file__).parents[2].joinpath("README.md").read_text()
    words = {"spherical wrist": "spherical-wrist", "general 6R": "general-6r",
             "reversed spherical wrist": "reversed-spherical-wrist"}
    rows = re.findall(r"^\| `(\w+)`(?:, `(\w+)`)? \| (.+) \|$", text, flags=re.M)
    checked = 0
    for first, second, cells in rows:
        cells = [c.strip() for c in cells.split("|")]
        if len(cells) != 7:
            continue
        for name in filter(None, (first, second)):
            r = kincalc.load_robot(name)
            for j, cell in enumerate(cells):
                chain = locked_robot(r, {j: 0.9})
                if cell.startswith("refused"):
                    with pytest.raises(InputError):
                        solve_locked(r, Target(r.fk(np.zeros(7) + 0.3)), {j: 0.9})
                    continue
                assert plan(chain)[1].name == words[cell], (name, j)
            checked += 1
    assert checked == 4


def test_a_position_missed_by_a_hair_is_not_called_an_orientation_out_of_reach():
    """iiwa14 held at A1 with the elbow 1.7e-7 rad from straight (redundant-arm oracle):
    the closed form's candidates reach the orientation (3e-14 deg) and miss the position by
    4e-8 m, and the answer said "the position is reachable but this orientation is not",
    reach "orientation-unreachable". A miss by a hair is said as one."""
    from kincalc.analysis.reach import reach
    from kincalc.analysis.words import reason_text
    from kincalc.ik.reasons import NoSolution, OrientationOut
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([10, -30, -35, 0.00001, 130, 25, 50])
    locks = {0: q0[0]}
    T = r.fk(q0)
    res = solve_locked(r, Target(T), locks)
    if res.solutions:                   # (the closed form may one day reach it: then fine)
        assert any(np.allclose(r.fk(s.q), T, atol=1e-9) for s in res.solutions)
        return
    assert isinstance(res.reason, NoSolution) and not isinstance(res.reason, OrientationOut)
    assert res.reason.best.position_error > 1e-9 and res.reason.best.orientation_error < 1e-9
    from kincalc.analysis.results import Units
    assert "position off by" in reason_text(res.reason, r, Units(length="m"))
    assert reach(locked_robot(r, locks), Target(T)).verdict == "not-found"


def test_a_lock_at_a_value_that_lines_up_two_axes_says_to_hold_it_elsewhere():
    """iiwa7 with A6 held at 0 (axes 5 and 7 on one line) is refused, rightly, but the
    message said to lock another joint, 'any but the elbow', which A6 is (an independent
    tester): it now says the value is the trouble. The elbow keeps its own advice."""
    from cli_contract import run_cli
    q = ["--from-q", "49 4 91 14 138 0 15"]
    status, out, err = run_cli(["ik", "iiwa7", *q, "--lock", "A6=0"])
    assert status == 2 and "hold it at another value" in err and "elbow" not in err, err
    status, out, err = run_cli(["ik", "iiwa7", *q, "--lock", "A4=14"])
    assert status == 2 and "any but the elbow" in err, err
    status, out, err = run_cli(["ik", "iiwa7", "--from-q", "49 4 91 14 138 30 15",
                                "--lock", "A6=30", "--json"])
    assert status == 0 and json.loads(out)["solutions"], err
