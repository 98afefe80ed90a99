"""Reachability verdicts against hand-derived geometry, and the `kincalc reach` CLI.

Every expected number here is derived by hand (in the comments) from the link
lengths and limits of small arms written out below, never captured from kincalc.

The planar RR arm used throughout has l1 = 0.7 m, l2 = 0.4 m and unlimited
joints: its tool point reaches exactly the annulus |l1 - l2| = 0.3 <= r <= l1 + l2
= 1.1 m (law of cosines: r^2 = l1^2 + l2^2 + 2 l1 l2 cos q2, q2 free).
"""

import csv
import io
import json
import math
import re

import numpy as np
import pytest

from kincalc.cli.main import main
from kincalc.ik import Target
from kincalc.conventions.library import load
from kincalc.analysis.reach import reach

L1, L2 = 0.7, 0.4
R_OUT, R_IN = L1 + L2, abs(L1 - L2)          # 1.1, 0.3 m
#: a direction in the plane that is not a coordinate axis
AZ = math.radians(35.0)
U = np.array([math.cos(AZ), math.sin(AZ), 0.0])

# PUMA 560 (robots/puma560.yaml, standard DH, no tool: the tool point is the wrist
# centre). The wrist centre sits d3 along the shoulder axis z1 (through the base
# origin) and, in the plane normal to z1, at the tip of a 2-link arm: a2, then the
# rigid forearm vector (a3, d4) of length sqrt(a3^2 + d4^2). So its distance from
# the origin is sqrt(rho^2 + d3^2), rho in [|sqrt(a3^2+d4^2) - a2|, a2 + sqrt(a3^2+d4^2)].
PUMA_A2, PUMA_A3, PUMA_D3, PUMA_D4 = 0.4318, 0.0203, 0.15005, 0.4318
PUMA_RHO_MAX = PUMA_A2 + math.hypot(PUMA_A3, PUMA_D4)
PUMA_R_MAX = math.hypot(PUMA_RHO_MAX, PUMA_D3)


def _yaml(name, joints):
    rows = "\n".join(f"  - {j}" for j in joints)
    return (f"name: {name}\nconvention: dh\nunits: {{length: m, angle: deg}}\n"
            f"joints:\n{rows}\n")


def _rr(q2_limits=None, l1=L1, l2=L2):
    lim = "" if q2_limits is None else f", limits: [{q2_limits[0]}, {q2_limits[1]}]"
    return [f"{{name: q1, type: revolute, alpha: 0, a: {l1}, d: 0, theta: 0}}",
            f"{{name: q2, type: revolute, alpha: 0, a: {l2}, d: 0, theta: 0{lim}}}"]


# spherical R-R-P arm (Stanford-like): p = Rz(q1) (q3 sin q2, S, H + q3 cos q2)
RRP_H, RRP_S = 0.2, 0.15
RRP = [f"{{name: q1, type: revolute, alpha: -90, a: 0, d: {RRP_H}, theta: 0}}",
       f"{{name: q2, type: revolute, alpha: 90, a: 0, d: {RRP_S}, theta: 0}}",
       "{name: d3, type: prismatic, alpha: 0, a: 0, d: 0, theta: 0, limits: [0.3, 0.9]}"]


@pytest.fixture(scope="module")
def arms(tmp_path_factory):
    """Paths of the hand-made robot files, by name."""
    d = tmp_path_factory.mktemp("reach_robots")
    files = {
        "rr": _rr(),
        "rr_q2_90": _rr((-90, 90)),
        "rr_equal": _rr(l1=0.5, l2=0.5),
        "rrp": RRP,
    }
    out = {}
    for name, joints in files.items():
        p = d / f"{name}.yaml"
        p.write_text(_yaml(name, joints))
        out[name] = str(p)
    return out


def at(p, R=None):
    T = np.eye(4)
    T[:3, 3] = p
    if R is not None:
        T[:3, :3] = R
    return T


def point(arms, name, p):
    return reach(load(arms[name]), Target(at(p), orientation=False))


# --- planar RR: the verdicts at and around the annulus ---------------------------

def test_just_beyond_the_outer_reach(arms):
    res = point(arms, "rr", (R_OUT + 1e-4) * U)
    assert res.verdict == "beyond-outer-reach" and not res.reachable
    assert res.solutions == 0 and res.within_limits == 0
    # the nearest point of the annulus is on the outer circle, straight towards the base
    assert abs(res.distance - 1e-4) < 1e-9
    assert np.allclose(res.nearest_position, R_OUT * U, atol=1e-9)
    assert "1.1001 m" in res.reason and "1.1 m" in res.reason


def test_just_inside_the_outer_reach(arms):
    res = point(arms, "rr", (R_OUT - 1e-4) * U)
    assert res.verdict == "reachable" and res.reachable
    assert res.distance == 0.0
    assert res.solutions == 2 and res.within_limits == 2      # elbow up and down


def test_exactly_at_the_outer_reach_is_singular(arms):
    res = point(arms, "rr", R_OUT * U)
    assert res.verdict == "reachable-singular" and res.reachable
    assert res.distance == 0.0
    assert res.within_limits >= 1


def test_exactly_at_the_inner_reach_is_singular(arms):
    # r = l1 - l2: the arm folded back (q2 = 180 deg), again a single singular solution
    res = point(arms, "rr", R_IN * U)
    assert res.verdict == "reachable-singular" and res.reachable
    assert res.distance == 0.0


def test_inside_the_inner_void(arms):
    res = point(arms, "rr", (R_IN - 0.05) * U)
    assert res.verdict == "inside-inner-void" and not res.reachable
    assert abs(res.distance - 0.05) < 1e-9
    assert np.allclose(res.nearest_position, R_IN * U, atol=1e-9)


def test_the_reason_says_in_this_direction_only_of_a_nearest_point_on_the_line():
    """The reason names the target's and the nearest point's distances from the base. On
    a planar arm's annulus the nearest point lies on the line from the base through the
    target (by hand: 1 from the base, the inner circle at 5, by 4), and the amount is their
    difference. On spong_spherical_rrp, whose nearest point to this target lies off that
    line, the amount is no such difference, and the text said the arm reached "no closer
    than 0.516555 m in this direction" with an amount of 0.038685 m."""
    res = reach(load("bk_rr"), Target(at((1.0, 0.0, 0.0)), orientation=False))
    assert res.verdict == "inside-inner-void"
    assert res.reason.startswith("inside the inner void by 4: the target is 1 from the base, "
                                 "the arm reaches 5 from it in this direction")
    p = np.array([-0.09360715079430261, -0.06734419363616509, -0.4930650993169097])
    res = reach(load("spong_spherical_rrp"), Target(at(p), orientation=False))
    assert res.verdict == "inside-inner-void" and "in this direction" not in res.reason
    by, target, near = (float(x) for x in re.findall(
        r"by ([0-9.e-]+) m: the target is ([0-9.e-]+) m from the base, the nearest point "
        r"the arm reaches is ([0-9.e-]+) m from it", res.reason)[0])
    assert abs(target - np.linalg.norm(p)) < 1e-5
    assert abs(near - target) < by - 1e-3          # off the line: more than the difference


@pytest.mark.parametrize("name, reach_m", [("planar_3r", 3.0), ("craig_3r", 1.0)])
def test_a_position_on_the_boundary_is_reached_singular_also_without_an_orientation(
        name, reach_m):
    """A planar arm's outer circle (by hand: the sum of its links) is reached stretched
    only: reachable-singular with or without an orientation (without one it said
    reachable), losing the motion along the arm; a hair inside it, reachable."""
    robot = load(name)
    res = reach(robot, Target(at((reach_m, 0.0, 0.0)), orientation=False))
    assert res.verdict == "reachable-singular" and res.reachable
    assert "cannot move along (1.000, 0.000, 0.000)" in res.reason
    res = reach(robot, Target(at((reach_m * (1 - 1e-4), 0.0, 0.0)), orientation=False))
    assert res.verdict == "reachable"


def test_at_the_base_origin(arms):
    # every point of the inner circle is 0.3 m from the origin
    res = point(arms, "rr", np.zeros(3))
    assert res.verdict == "inside-inner-void"
    assert abs(res.distance - R_IN) < 1e-9
    assert abs(np.linalg.norm(res.nearest_position) - R_IN) < 1e-9
    # with equal links the inner void shrinks to the origin itself, reached folded
    # (q2 = 180 deg, q1 arbitrary): singular
    res = point(arms, "rr_equal", np.zeros(3))
    assert res.verdict == "reachable-singular" and res.distance == 0.0


# --- joint limits ---------------------------------------------------------------

# q2 in [-90, 90] deg. A target at r^2 = l1^2 + l2^2 + 2 l1 l2 cos(120 deg) = 0.37 needs
# q2 = +-120 deg: the elbow-up solution is 30 deg beyond the upper limit 90, the
# elbow-down one 30 deg beyond the lower limit -90.
BLOCKED_R = math.sqrt(L1**2 + L2**2 + 2 * L1 * L2 * math.cos(math.radians(120)))


def test_every_solution_blocked_names_the_joint_and_the_amount(arms):
    assert math.isclose(BLOCKED_R**2, 0.37)
    res = point(arms, "rr_q2_90", BLOCKED_R * U)
    assert res.verdict == "blocked-by-limits" and not res.reachable
    assert res.solutions == 2 and res.within_limits == 0
    assert len(res.blocked) == 2
    sides = set()
    for b in res.blocked:
        (v,) = b["violations"]
        assert v["joint"] == "q2"
        assert math.isclose(v["by"], 30.0, abs_tol=1e-6)               # deg
        assert v["limit"] == (90.0 if v["side"] == "upper" else -90.0)
        sides.add(v["side"])
    assert sides == {"upper", "lower"}
    assert re.search(r"\bq2 30(\.0+)? deg beyond its (upper|lower) limit -?90", res.reason), \
        res.reason


def test_blocked_distance_is_to_the_limited_annulus(arms):
    # Within q2 in [-90, 90] the reachable radii are sqrt(l1^2 + l2^2 + 2 l1 l2 cos q2)
    # for cos q2 in [0, 1]: the annulus sqrt(0.65) <= r <= 1.1 (q1 free). The target
    # at r = sqrt(0.37) is inside its hole, sqrt(0.65) - sqrt(0.37) from it.
    res = point(arms, "rr_q2_90", BLOCKED_R * U)
    expected = math.sqrt(0.65) - math.sqrt(0.37)
    assert abs(res.distance - expected) < 1e-9 * R_OUT, (res.distance, expected)


def test_one_solution_inside_the_limits_is_enough(arms):
    # |q2| = 60 deg: both elbow solutions are inside [-90, 90]
    r60 = math.sqrt(L1**2 + L2**2 + 2 * L1 * L2 * 0.5)
    res = point(arms, "rr_q2_90", r60 * U)
    assert res.verdict == "reachable" and res.within_limits == 2 and res.distance == 0.0


# --- a 6R arm ------------------------------------------------------------------

def test_puma_pose_from_fk_is_reachable():
    r = load("puma560")
    q = np.radians([10, 30, -60, 20, 40, 15])            # inside every limit, not singular
    res = reach(r, Target(r.fk(q)))
    assert res.verdict == "reachable" and res.reachable and res.distance == 0.0
    assert res.within_limits >= 1 and res.solutions >= res.within_limits


def test_puma_max_reach_closed_form_by_brute_force():
    """Guard the derivation of PUMA_R_MAX: a 1-D sweep of the elbow (the only joint that
    changes the wrist centre's distance from the origin) finds the same maximum."""
    r = load("puma560")
    Q = np.zeros((400001, 6))
    Q[:, 2] = np.linspace(-np.pi, np.pi, len(Q))
    d = np.linalg.norm(r.fk(Q)[:, :3, 3], axis=1)
    assert abs(d.max() - PUMA_R_MAX) < 1e-10


@pytest.mark.parametrize("az, el", [(30, 20), (-100, -35), (0, 0)])
def test_puma_pose_beyond_the_outer_reach(az, el):
    # Along any direction u at least d3 away from the vertical axis the outer boundary is
    # the sphere of radius PUMA_R_MAX, reachable within the limits there (q1 within
    # +-160, upper arm at elevation el within [-45, 225], elbow stretched at
    # q3 = -atan2(d4, a3) = -87.3 deg within [-225, 45]); so the target (R_MAX + 0.05) u
    # is 0.05 m from the workspace.
    r = load("puma560")
    a, e = math.radians(az), math.radians(el)
    u = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    T = r.fk(np.radians([10, 30, -60, 20, 40, 15]))
    T[:3, 3] = (PUMA_R_MAX + 0.05) * u
    res = reach(r, Target(T))
    assert res.verdict == "beyond-outer-reach" and not res.reachable
    assert abs(res.distance - 0.05) < 1e-9
    assert abs(np.linalg.norm(res.nearest_position) - PUMA_R_MAX) < 1e-9
    assert f"{PUMA_R_MAX:.6g} m" in res.reason


# --- orientation --------------------------------------------------------------

def test_planar_rr_cannot_tilt_its_tool(arms):
    # The RR tool frame is always Rz(phi), phi = q1 + q2. At (0.9, 0, 0):
    # cos q2 = (0.81 - l1^2 - l2^2) / (2 l1 l2), q1 = -atan2(l2 sin q2, l1 + l2 cos q2),
    # and both elbows give |phi| = q2 - atan2(...). Against Rx(90 deg) the error rotation
    # Rz(-phi) Rx(90) has trace cos(phi), so the angle is acos((cos(phi) - 1) / 2).
    q2 = math.acos((0.81 - L1**2 - L2**2) / (2 * L1 * L2))
    phi = q2 - math.atan2(L2 * math.sin(q2), L1 + L2 * math.cos(q2))
    off = math.degrees(math.acos((math.cos(phi) - 1) / 2))          # 99.59 deg
    Rx90 = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])
    res = reach(load(arms["rr"]), Target(at([0.9, 0, 0], Rx90)))
    assert res.verdict == "orientation-unreachable" and not res.reachable
    assert res.distance == 0.0
    m = re.search(r"off by ([0-9.]+) deg", res.reason)
    assert m and abs(float(m.group(1)) - off) < 0.01, (res.reason, off)
    # the same position with the elbow-up solution's own orientation is reachable
    Rz = np.array([[math.cos(phi), -math.sin(phi), 0], [math.sin(phi), math.cos(phi), 0],
                   [0, 0, 1]])
    assert reach(load(arms["rr"]), Target(at([0.9, 0, 0], Rz))).verdict == "reachable"


def test_three_joint_arm_given_an_orientation_it_cannot_take(arms):
    # R-R-P: R = Rz(q1) Rx(-90) Rz(q2) Rx(90) = Rz(q1) Ry(q2) is the identity only for
    # q1 = q2 = 0 (mod 2 pi), i.e. only on the line x = 0, y = S; the target below is not
    # on it, but its position is reached (it is FK of joints within the limits).
    r = load(arms["rrp"])
    q = np.array([0.3, 0.5, 0.6])
    p = r.fk(q)[:3, 3]
    assert abs(p[0]) > 0.1
    res = reach(r, Target(at(p, np.eye(3))))
    assert res.verdict == "orientation-unreachable" and not res.reachable
    assert res.distance == 0.0
    assert reach(r, Target(at(p), orientation=False)).verdict == "reachable"
    assert reach(r, Target(r.fk(q))).verdict == "reachable"


# --- the CLI ---------------------------------------------------------------------

def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_exit_status_and_json_fields(capsys, arms):
    code, out, err = run(capsys, "reach", arms["rr"], "--xyz", 0.9, 0, 0, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["reachable"] is True and doc["verdict"] == "reachable"
    assert doc["distance"] == 0 and doc["solutions_within_limits"] == 2
    assert isinstance(doc["reason"], str) and doc["reason"]

    code, out, err = run(capsys, "reach", arms["rr"], "--xyz", 1.2, 0, 0, "--json")
    assert code == 1, err
    doc = json.loads(out)
    assert doc["reachable"] is False and doc["verdict"] == "beyond-outer-reach"
    assert abs(doc["distance"] - 0.1) < 1e-9
    assert doc["solutions_within_limits"] == 0 and "reason" in doc

    # the same in millimetres: the distance follows --unit
    code, out, err = run(capsys, "reach", arms["rr"], "--xyz", 1200, 0, 0, "--unit", "mm",
                         "--json")
    assert code == 1, err
    assert abs(json.loads(out)["distance"] - 100.0) < 1e-6

    # blocked: exit 1 too, the violation in degrees
    x = BLOCKED_R
    code, out, err = run(capsys, "reach", arms["rr_q2_90"], "--xyz", x, 0, 0, "--json")
    assert code == 1, err
    doc = json.loads(out)
    assert doc["verdict"] == "blocked-by-limits" and doc["solutions_within_limits"] == 0
    assert all(abs(b["violations"][0]["by"] - 30.0) < 1e-6 for b in doc["blocked"])


def test_cli_table_output_exit_status(capsys, arms):
    code, out, _ = run(capsys, "reach", arms["rr"], "--xyz", 0.9, 0, 0)
    assert code == 0 and "reachable" in out
    code, out, _ = run(capsys, "reach", arms["rr"], "--xyz", 0.1, 0, 0)
    assert code == 1 and "inside-inner-void" in out


def test_cli_batch_json_lines_from_stdin(capsys, monkeypatch, arms):
    lines = ['{"xyz": [0.9, 0, 0]}',
             '{"xyz": [1.2, 0, 0]}',
             'this is not json',
             '{"xyz": [0, 0.25, 0]}',
             '{"xyz": [0.5, 0.5]}']
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join(lines) + "\n"))
    code, out, err = run(capsys, "reach", arms["rr"], "--batch", "-")
    assert code == 2, "a malformed record makes the exit status 2"
    recs = [json.loads(line) for line in out.splitlines()]
    assert [r["index"] for r in recs] == [0, 1, 2, 3, 4]
    assert recs[0]["reachable"] is True and recs[0]["verdict"] == "reachable"
    assert recs[0]["distance"] == 0 and recs[0]["solutions_within_limits"] == 2
    assert recs[1]["reachable"] is False and recs[1]["verdict"] == "beyond-outer-reach"
    assert abs(recs[1]["distance"] - 0.1) < 1e-9                      # 1.2 - 1.1
    assert "error" in recs[2] and "verdict" not in recs[2]
    assert "3" in recs[2]["error"]                                    # names its record
    assert recs[3]["verdict"] == "inside-inner-void"
    assert abs(recs[3]["distance"] - 0.05) < 1e-9                     # 0.3 - 0.25
    assert "error" in recs[4] and "verdict" not in recs[4]            # xyz needs 3 numbers


def test_cli_batch_all_good_lines_exit_status(capsys, monkeypatch, arms):
    monkeypatch.setattr("sys.stdin", io.StringIO('{"xyz": [0.9, 0, 0]}\n{"xyz": [0, 1, 0]}\n'))
    code, out, _ = run(capsys, "reach", arms["rr"], "--batch", "-")
    assert code == 0 and len(out.splitlines()) == 2
    monkeypatch.setattr("sys.stdin", io.StringIO('{"xyz": [0.9, 0, 0]}\n{"xyz": [0, 2, 0]}\n'))
    code, out, _ = run(capsys, "reach", arms["rr"], "--batch", "-")
    assert code == 1 and len(out.splitlines()) == 2


def test_cli_batch_csv_in_csv_out(capsys, tmp_path, arms):
    src = tmp_path / "targets.csv"
    src.write_text("x,y,z\n0.9,0,0\n1.2,0,0\n0,0.25,0\n0.5,0.5,0\n")
    code, out, err = run(capsys, "reach", arms["rr"], "--batch", src, "--format", "csv")
    assert code == 1, err
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 4
    assert [int(r["index"]) for r in rows] == [0, 1, 2, 3]
    for key in ("reachable", "verdict", "distance", "solutions_within_limits", "reason"):
        assert key in rows[0]
    assert [r["verdict"] for r in rows] == ["reachable", "beyond-outer-reach",
                                            "inside-inner-void", "reachable"]
    assert abs(float(rows[1]["distance"]) - 0.1) < 1e-9
    assert abs(float(rows[2]["distance"]) - 0.05) < 1e-9
    assert float(rows[0]["distance"]) == 0 and int(rows[0]["solutions_within_limits"]) == 2
    # reasons contain commas: the csv module must still see one row per input
    assert all(r["reason"] for r in rows)


def test_cli_bad_input_exit_2_and_one_line(capsys, tmp_path, arms):
    code, out, err = run(capsys, "reach", "no_such_robot_xyz", "--xyz", 1, 0, 0)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("kincalc") and "no_such_robot_xyz" in err

    code, out, err = run(capsys, "reach", arms["rr"], "--batch", tmp_path / "missing.jsonl")
    assert code == 2
    assert err.count("\n") == 1 and "missing.jsonl" in err

    code, out, err = run(capsys, "reach", arms["rr"], "--xyz", 0.9, 0, 0, "--batch", "-")
    assert code == 2 and err.count("\n") == 1

    code, out, err = run(capsys, "reach", arms["rr"], "--batch", "-", "--format", "xml")
    assert code == 2 and err.count("\n") == 1


def test_a_target_far_beyond_the_reach_suggests_a_smaller_unit():
    """PUMA numbers written in mm or cm but read as m: the reason says which unit brings
    the target within the reach (the target's distance divided by that unit's factor),
    and says nothing for a target merely out of reach."""
    from cli_contract import run_cli
    for xyz, unit in ((["500", "100", "300"], "mm"), (["50", "10", "30"], "cm")):
        status, out, err = run_cli(["ik", "puma560", "--xyz", *xyz, "--rpy", "0", "90", "0",
                                    "--json"])
        reason = json.loads(out)["reason"]
        assert status == 1 and f"were the numbers meant in {unit}?" in reason, reason
        shown = float(reason.split(f"Read as {unit}, the target is ")[1].split(" m")[0])
        r = np.linalg.norm(np.array(xyz, float)) * {"mm": 1e-3, "cm": 1e-2}[unit]
        assert abs(shown - r) < 0.2       # from the base (the base point is near the origin)
    status, out, err = run_cli(["ik", "puma560", "--xyz", "5", "1", "3", "--rpy", "0", "90", "0",
                                "--json"])
    assert "meant" not in json.loads(out)["reason"]
    status, out, err = run_cli(["ik", "puma560", "--xyz", "500000", "0", "0", "--rpy", "0", "0",
                                "0", "--unit", "mm", "--json"])
    assert "meant" not in json.loads(out)["reason"]      # no unit smaller than mm
