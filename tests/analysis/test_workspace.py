"""Workspace analysis against closed forms: areas of planar arms, reach envelopes,
dexterous areas; determinism; the helpers (limits, Wilson interval, SO(3) test set).

Every expected number is derived by hand in the comments, from the link lengths and
limits of the arms written out below; none is kincalc's own output captured once.
"""

import json
import math

import numpy as np
import pytest

import kincalc.analysis.workspace as ws
from kincalc.ik.joint_limits import within_limits
from kincalc.cli.main import main
from kincalc.conventions.library import load

PI = math.pi
L1, L2 = 0.7, 0.4
#: area of the annulus |l1 - l2| <= r <= l1 + l2 (the planar RR arm with q2 free)
ANNULUS = PI * ((L1 + L2) ** 2 - (L1 - L2) ** 2)        # 1.12 pi


def _yaml(name, joints):
    rows = "\n".join(f"  - {j}" for j in joints)
    return (f"name: {name}\nconvention: dh\nunits: {{length: m, angle: deg}}\n"
            f"joints:\n{rows}\n")


def _planar(lengths, limits=()):
    limits = list(limits) + [None] * (len(lengths) - len(limits))
    rows = []
    for i, (a, lim) in enumerate(zip(lengths, limits), start=1):
        extra = "" if lim is None else f", limits: [{lim[0]}, {lim[1]}]"
        rows.append(f"{{name: q{i}, type: revolute, alpha: 0, a: {a}, d: 0, theta: 0{extra}}}")
    return rows


# Spherical R-R-P arm (Stanford-like), standard DH:
#   A1 = Rz(q1) Tz(H) Rx(-90), A2 = Rz(q2) Tz(S) Rx(90), A3 = Tz(d3), d3 in [D_MIN, D_MAX].
# Tool point: p = Rz(q1) (d3 sin q2, S, H + d3 cos q2), so
#   |p|^2 = d3^2 + S^2 + H^2 + 2 H d3 cos q2,   z = H + d3 cos q2.
# max |p| at q2 = 0, d3 = D_MAX: sqrt((H + D_MAX)^2 + S^2);
# min |p|: |p|^2 >= (d3 - H)^2 + S^2 (q2 = pi), and H = 0.2 < D_MIN = 0.3, so
#   min |p| = sqrt((D_MIN - H)^2 + S^2), at the lower end of the stroke;
# z in [H - D_MAX, H + D_MAX].
H, S, D_MIN, D_MAX = 0.2, 0.15, 0.3, 0.9
RRP = [f"{{name: q1, type: revolute, alpha: -90, a: 0, d: {H}, theta: 0}}",
       f"{{name: q2, type: revolute, alpha: 90, a: 0, d: {S}, theta: 0}}",
       f"{{name: d3, type: prismatic, alpha: 0, a: 0, d: 0, theta: 0, limits: [{D_MIN}, {D_MAX}]}}"]

# PUMA 560 geometry (robots/puma560.yaml, standard DH, tool point = wrist centre): the
# wrist centre is d3 along the shoulder axis z1 (through the base origin) and, in the
# plane normal to z1 (which contains the vertical z0), at the tip of a 2-link arm a2,
# sqrt(a3^2 + d4^2). So |p| = sqrt(rho^2 + d3^2) with rho between
# |sqrt(a3^2 + d4^2) - a2| and a2 + sqrt(a3^2 + d4^2), and z = the in-plane vertical
# component, in [-rho_max, rho_max] (the in-plane direction can point straight up/down).
PA2, PA3, PD3, PD4 = 0.4318, 0.0203, 0.15005, 0.4318
FOREARM = math.hypot(PA3, PD4)
RHO_MAX, RHO_MIN = PA2 + FOREARM, abs(FOREARM - PA2)
PUMA_JOINTS = [
    "{name: q1, type: revolute, alpha: 90,  a: 0,    d: 0,    theta: 0}",
    f"{{name: q2, type: revolute, alpha: 0,   a: {PA2}, d: 0,    theta: 0}}",
    f"{{name: q3, type: revolute, alpha: -90, a: {PA3}, d: {PD3}, theta: 0}}",
    f"{{name: q4, type: revolute, alpha: 90,  a: 0,    d: {PD4}, theta: 0}}",
    "{name: q5, type: revolute, alpha: -90, a: 0,    d: 0,    theta: 0}",
    "{name: q6, type: revolute, alpha: 0,   a: 0,    d: 0,    theta: 0}",
]

FILES = {
    "rr": _planar([L1, L2]),
    # q2 in [0, 180]: r = sqrt(l1^2 + l2^2 + 2 l1 l2 cos q2) still sweeps [0.3, 1.1]
    "rr_q2_half": _planar([L1, L2], [None, (0, 180)]),
    # q1 in [0, 90] as well: with q2 in [0, pi] each radius r has exactly one q2, and
    # the polar angle is q1 + beta(r), beta = atan2(l2 sin q2, l1 + l2 cos q2): an arc
    # of width pi/2 at every r, so the area is (pi/2) / (2 pi) of the annulus.
    "rr_sector": _planar([L1, L2], [(0, 90), (0, 180)]),
    # q2 in [-90, 90]: cos q2 in [0, 1], r in [sqrt(l1^2 + l2^2), l1 + l2]
    "rr_q2_90": _planar([L1, L2], [None, (-90, 90)]),
    "p3_annulus": _planar([0.6, 0.3, 0.1]),
    "p3_disc": _planar([0.5, 0.4, 0.3]),
    "rrp": RRP,
    "rrp_unlimited": RRP[:2] + ["{name: d3, type: prismatic, alpha: 0, a: 0, d: 0, theta: 0}"],
    "puma_free": PUMA_JOINTS,
}


@pytest.fixture(scope="module")
def arms(tmp_path_factory):
    d = tmp_path_factory.mktemp("workspace_robots")
    out = {}
    for name, joints in FILES.items():
        p = d / f"{name}.yaml"
        p.write_text(_yaml(name, joints))
        out[name] = str(p)
    return out


def check_area(w, truth, rel_half_width=0.02):
    lo, hi = w.volume_ci
    assert lo <= truth <= hi, (truth, w.volume, (lo, hi))
    assert lo <= w.volume <= hi
    assert (hi - lo) / 2 < rel_half_width * truth, ((hi - lo) / 2 / truth)


# --- reachable areas of planar RR arms -------------------------------------------

def test_rr_area_converges_to_the_annulus(arms):
    r = load(arms["rr"])
    small = ws.analyse(r, 50_000, 0)
    big = ws.analyse(r, 200_000, 0)
    assert small.dim == big.dim == 2
    for w in (small, big):
        check_area(w, ANNULUS)
    # more samples, a narrower interval
    assert big.volume_ci[1] - big.volume_ci[0] < small.volume_ci[1] - small.volume_ci[0]
    e = big.envelope
    assert abs(e["max_distance"] - (L1 + L2)) < 1e-6 * (L1 + L2)
    assert abs(e["min_distance"] - (L1 - L2)) < 1e-6 * (L1 + L2)
    assert abs(e["z_min"]) < 1e-12 and abs(e["z_max"]) < 1e-12


def test_rr_area_interval_covers_the_truth_across_seeds(arms):
    """A 95 % interval: over ten seeds, at most two may miss (P(more than 2 misses) is
    about 1 % for a calibrated interval)."""
    r = load(arms["rr"])
    misses = []
    for seed in range(10):
        lo, hi = ws.analyse(r, 50_000, seed).volume_ci
        if not lo <= ANNULUS <= hi:
            misses.append((seed, lo, hi))
    assert len(misses) <= 2, (ANNULUS, misses)


@pytest.mark.parametrize("name, truth, r_min", [
    ("rr_q2_half", ANNULUS, L1 - L2),
    ("rr_sector", ANNULUS / 4, L1 - L2),
    ("rr_q2_90", PI * ((L1 + L2) ** 2 - (L1**2 + L2**2)), math.sqrt(L1**2 + L2**2)),
])
def test_rr_area_with_joint_limits(arms, name, truth, r_min):
    w = ws.analyse(load(arms[name]), 100_000, 0)
    assert w.dim == 2
    check_area(w, truth)
    assert abs(w.envelope["max_distance"] - (L1 + L2)) < 1e-6 * (L1 + L2)
    assert abs(w.envelope["min_distance"] - r_min) < 1e-6 * (L1 + L2)


# --- envelopes ----------------------------------------------------------------

def test_spherical_arm_envelope_closed_form(arms):
    w = ws.analyse(load(arms["rrp"]), 50_000, 0)
    e = w.envelope
    assert w.dim == 3
    scale = H + D_MAX
    assert abs(e["max_distance"] - math.hypot(H + D_MAX, S)) < 1e-6 * scale
    assert abs(e["min_distance"] - math.hypot(D_MIN - H, S)) < 1e-6 * scale
    assert abs(e["z_max"] - (H + D_MAX)) < 1e-6 * scale
    assert abs(e["z_min"] - (H - D_MAX)) < 1e-6 * scale
    # the extremes are attained at the joints the derivation says (q2 only to about the
    # square root of the tolerance: the distance is flat, quadratic, in q2 there)
    q = e["max_distance_q"]
    assert abs(q[2] - D_MAX) < 1e-6 and abs(math.remainder(q[1], 2 * PI)) < 1e-2
    q = e["min_distance_q"]
    assert abs(q[2] - D_MIN) < 1e-6 and abs(abs(math.remainder(q[1], 2 * PI)) - PI) < 1e-2


def test_6r_envelope_matches_its_link_lengths(arms):
    w = ws.analyse(load(arms["puma_free"]), 50_000, 0)
    e = w.envelope
    assert abs(e["max_distance"] - math.hypot(RHO_MAX, PD3)) < 1e-6 * RHO_MAX
    assert abs(e["min_distance"] - math.hypot(RHO_MIN, PD3)) < 1e-6 * RHO_MAX
    assert abs(e["z_max"] - RHO_MAX) < 1e-6 * RHO_MAX
    assert abs(e["z_min"] + RHO_MAX) < 1e-6 * RHO_MAX


def test_bundled_puma_reach_where_the_limits_do_not_bind():
    # the stretched elbow q3 = -atan2(d4, a3) = -87.3 deg is inside [-225, 45]; pointing
    # the arm up needs q2 = 90 deg, inside [-45, 225]: max distance and z_max as unlimited
    w = ws.analyse(load("puma560"), 50_000, 0)
    e = w.envelope
    assert abs(e["max_distance"] - math.hypot(RHO_MAX, PD3)) < 1e-6 * RHO_MAX
    assert abs(e["z_max"] - RHO_MAX) < 1e-6 * RHO_MAX


def test_every_envelope_extreme_is_stationary_in_its_free_joints():
    """At the joints where each extreme is attained, the value's derivative (central
    differences of FK) is zero in every joint not at a limit. KUKA KR 16's stretched reach
    came out 4 mm short of 2232.2565 mm (derivatives of 6e-5 m/rad): the pushes outward
    slow down where the distance is flat to first order."""
    r = load("kuka_kr16")
    e = ws.analyse(r, 20_000, 0).envelope
    lo, hi = r.limits.T
    o = r.base[:3, 3]
    for name in ("max_distance", "min_distance", "z_max", "z_min"):
        X = e[name + "_q"]

        def value(q):
            p = r.fk(q)[:3, 3]
            return np.linalg.norm(p - o) if name.endswith("distance") else p[2]
        assert abs(value(X) - e[name]) < 1e-12
        free = (X > lo + 1e-9) & (X < hi - 1e-9)
        h = 1e-6
        g = [(value(X + h * d) - value(X - h * d)) / (2 * h) for d in np.eye(r.dof)[free]]
        assert np.abs(g).max() < 1e-8 * r.characteristic_length, name


# --- dexterous workspace ---------------------------------------------------------

# Planar 3R, links l1, l2, l3: the tool point P reaches heading phi iff the wrist point
# P - l3 (cos phi, sin phi) is in the 2R annulus |l1 - l2| <= r <= l1 + l2. Every phi
# works iff the whole circle of radius l3 about P is in the annulus: its farthest
# point from the origin is |P| + l3, its nearest | |P| - l3 |. So the dexterous set is
#   |P| <= l1 + l2 - l3  and  ( |P| >= |l1 - l2| + l3  or  |P| <= l3 - |l1 - l2| ).
# p3_annulus (0.6, 0.3, 0.1): 0.4 <= |P| <= 0.8 (no inner disc: 0.1 - 0.3 < 0):
#   pi (0.8^2 - 0.4^2) = 0.48 pi; reachable: the annulus 0.2 <= r <= 1.0, 0.96 pi.
# p3_disc (0.5, 0.4, 0.3): 0.4 <= |P| <= 0.6, plus the disc |P| <= 0.2:
#   pi (0.36 - 0.16) + pi 0.04 = 0.24 pi; reachable: the disc r <= 1.2 (0.5 <= 0.4 + 0.3),
#   1.44 pi.
@pytest.mark.parametrize("name, dexterous, reachable", [
    ("p3_annulus", 0.48 * PI, 0.96 * PI),
    ("p3_disc", 0.24 * PI, 1.44 * PI),
])
def test_planar_3r_dexterous_area(arms, monkeypatch, name, dexterous, reachable):
    monkeypatch.setattr(ws.dexterity, "DEXTERITY_POINTS", 800)
    w = ws.analyse(load(arms[name]), 50_000, 0)
    check_area(w, reachable)
    d = w.dexterous
    assert d["defined"] is True and d["test_points"] == 800
    lo, hi = d["volume_ci95"]
    assert lo <= dexterous <= hi, (dexterous, d["volume"], (lo, hi))
    # a binomial interval of 800 points: half-width at most about z sqrt(1/4 / 800) = 3.5 %
    # of the region the points are drawn from (the reachable area and its boundary band)
    assert (hi - lo) / 2 < 0.05 * reachable


def test_dexterous_needs_an_orientation_to_turn(arms):
    # the RR arm's heading q1 + q2 is tied to its position; the RRP arm controls position only
    for name in ("rr", "rrp"):
        d = ws.analyse(load(arms[name]), 5_000, 0).dexterous
        assert d["defined"] is False and d["volume"] is None and d["reason"]


# --- determinism and the CLI -------------------------------------------------------

def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def ws_json(capsys, *argv):
    code, out, err = run(capsys, "workspace", *argv, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert "timings_s" not in doc   # a seeded run prints the same JSON every time
    return doc


def test_same_seed_same_numbers_other_seed_overlapping_intervals(capsys, arms):
    a = ws_json(capsys, arms["rr"], "--samples", 50_000, "--seed", 7)
    b = ws_json(capsys, arms["rr"], "--samples", 50_000, "--seed", 7)
    assert a == b
    c = ws_json(capsys, arms["rr"], "--samples", 50_000, "--seed", 8)
    assert c["volume"] != a["volume"]
    (alo, ahi), (clo, chi) = a["volume_ci95"], c["volume_ci95"]
    assert alo <= a["volume"] <= ahi and clo <= c["volume"] <= chi
    assert max(alo, clo) <= min(ahi, chi), "the two intervals must overlap"
    assert a["dimension"] == 2 and a["measure"] == "area" and a["samples"] == 50_000
    assert a["envelope"]["max_distance"] == pytest.approx(L1 + L2, rel=1e-6)


def test_cli_units_scale_the_area(capsys, arms):
    m = ws_json(capsys, arms["rr"], "--samples", 20_000, "--seed", 1)
    mm = ws_json(capsys, arms["rr"], "--samples", 20_000, "--seed", 1, "--unit", "mm")
    assert mm["volume"] == pytest.approx(1e6 * m["volume"], rel=1e-9)
    assert mm["envelope"]["max_distance"] == pytest.approx(1e3 * (L1 + L2), rel=1e-6)


@pytest.mark.parametrize("argv", [
    ["rr", "--samples", "10"],
    ["no_such_robot_xyz", "--samples", "5000"],
    ["rrp_unlimited", "--samples", "5000"],      # an unlimited prismatic joint: unbounded
])
def test_cli_bad_input_exit_2_one_line(capsys, arms, argv):
    argv = [arms.get(argv[0], argv[0])] + argv[1:]
    code, out, err = run(capsys, "workspace", *argv, "--json")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("kincalc"), err


@pytest.mark.parametrize("rows", [
    ["{name: a, type: revolute, alpha: 0, a: 0, d: 0, theta: 0}"],
    ["{name: a, type: revolute, alpha: 0, a: 0, d: 0.5, theta: 0}",
     "{name: b, type: revolute, alpha: 0, a: 0, d: 0.2, theta: 0}"],
])
def test_a_tool_point_no_joint_moves_has_no_volume(capsys, tmp_path, rows):
    """Every axis through the tool point: the samples' points differ by rounding only, and
    a grid sized to their spread asked for 539 GiB (a MemoryError, exit 3; an independent
    hostile-input campaign). Now one line, exit 2."""
    f = tmp_path / "still.yaml"
    f.write_text(_yaml("still", rows))
    code, out, err = run(capsys, "workspace", str(f), "--json")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "single point" in err, err
    assert "every axis passes through it" in err


def test_joints_held_by_their_limits_are_named_as_the_reason(capsys, tmp_path):
    """Limits of one value each were said to be "every axis passes through it" (hostile-input
    campaign)."""
    f = tmp_path / "held.yaml"
    f.write_text(_yaml("held", ["{name: a, type: revolute, alpha: 0, a: 1, d: 0, theta: 0, "
                                "limits: [10, 10]}",
                                "{name: b, type: revolute, alpha: 0, a: 1, d: 0, theta: 0, "
                                "limits: [20, 20]}"]))
    code, out, err = run(capsys, "workspace", str(f), "--json")
    assert code == 2 and err.count("\n") == 1 and "every joint's limits are one value" in err


def test_analyse_refuses_too_few_samples(arms):
    with pytest.raises(Exception, match="1000"):
        ws.analyse(load(arms["rr"]), 10, 0)


# --- helpers --------------------------------------------------------------------

def test_within_limits_hand_cases(tmp_path):
    f = tmp_path / "mixed.yaml"
    f.write_text(_yaml("mixed", [
        "{name: a, type: revolute, alpha: 0, a: 0.5, d: 0, theta: 0, limits: [-90, 90]}",
        "{name: b, type: revolute, alpha: 0, a: 0.5, d: 0, theta: 0, limits: [0, 360]}",
        "{name: c, type: prismatic, alpha: 0, a: 0, d: 0, theta: 0, limits: [0.3, 0.9]}",
    ]))
    r = load(str(f))
    D = math.radians
    T = 2 * PI
    cases = [
        ([0.0, D(10), 0.5], True),
        ([D(90), D(360), 0.9], True),            # both ends inclusive
        ([D(-90), 0.0, 0.3], True),
        ([D(100), D(10), 0.5], False),           # 10 deg beyond +90, and 100 - 360 < -90
        ([D(45) + T, D(10), 0.5], True),         # a whole turn more: the same joint angle
        ([D(45) - 2 * T, D(10), 0.5], True),
        ([D(180), D(10), 0.5], False),           # 180 and -180: outside [-90, 90]
        ([0.0, D(-170), 0.5], True),             # -170 = 190 within [0, 360]
        ([0.0, D(-170) - 3 * T, 0.5], True),
        ([0.0, D(10), 0.3 + T], False),          # prismatic: no wrap
        ([0.0, D(10), 0.9 - T], False),
        ([0.0, D(10), 0.29], False),
        ([0.0, D(10), 0.91], False),
    ]
    Q = np.array([q for q, _ in cases])
    want = np.array([ok for _, ok in cases])
    got = within_limits(r, Q)
    assert got.shape == (len(cases),)
    assert (got == want).all(), [c for c, g in zip(cases, got) if g != c[1]]
    # batched over more leading axes, and one configuration alone
    assert (within_limits(r, Q.reshape(1, -1, 3)) == want).all()
    assert bool(within_limits(r, Q[3])) is False and bool(within_limits(r, Q[4]))


def test_wilson_against_hand_computed_intervals():
    # z = 1.959964; 5 of 20: p = 0.25, den = 1 + z^2/20 = 1.192073,
    # mid = (0.25 + z^2/40) / den = 0.290281, half = z sqrt(p(1-p)/20 + z^2/1600) / den
    # = 0.178420 -> (0.111862, 0.468701), the textbook (0.1119, 0.4687)
    lo, hi = ws.wilson(5, 20)
    assert lo == pytest.approx(0.111862, abs=2e-6) and hi == pytest.approx(0.468701, abs=2e-6)
    # 0 of 10: (0, z^2 / (10 + z^2)) = (0, 0.277533)
    lo, hi = ws.wilson(0, 10)
    assert lo == pytest.approx(0.0, abs=1e-12) and hi == pytest.approx(0.277533, abs=2e-6)
    # 10 of 10: the mirror image
    lo, hi = ws.wilson(10, 10)
    assert lo == pytest.approx(1 - 0.277533, abs=2e-6) and hi == pytest.approx(1.0, abs=1e-12)
    # 50 of 100: symmetric about 1/2, half-width z sqrt(0.25/100 + z^2/40000) / (1 + z^2/100)
    lo, hi = ws.wilson(50, 100)
    z = 1.959963984540054
    half = z * math.sqrt(0.0025 + z * z / 40000) / (1 + z * z / 100)
    assert lo == pytest.approx(0.5 - half, abs=1e-12) and hi == pytest.approx(0.5 + half, abs=1e-12)
    assert ws.wilson(0, 0) == (0.0, 1.0)


def _angle(A, B):
    c = (np.einsum("...ij,...ij->...", A, B) - 1) / 2       # trace(A^T B) = 1 + 2 cos
    return np.arccos(np.clip(c, -1, 1))


def _random_rotations(rng, n):
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


@pytest.mark.parametrize("count, min_gap, cover", [(24, 30, 95), (48, 25, 72), (200, 15, 45)])
def test_super_fibonacci_rotations_are_proper_and_spread(count, min_gap, cover):
    """Proper rotations; no two nearly equal (iid random sets of this size have pairs a few
    degrees apart); every random rotation near one of them. A ball of radius t in SO(3)
    has measure (t - sin t) / pi, so ``count`` balls cover it only if
    t - sin t >= pi / count: t >= 42 deg for 48, so ``cover`` is within 2x of optimal."""
    R = ws.super_fibonacci(count)
    assert R.shape == (count, 3, 3)
    assert np.allclose(R @ np.swapaxes(R, 1, 2), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(R), 1.0, atol=1e-12)
    A = _angle(R[:, None], R[None])
    np.fill_diagonal(A, np.inf)
    assert np.degrees(A.min()) > min_gap
    X = _random_rotations(np.random.default_rng(0), 20_000)
    worst = np.degrees(_angle(X[:, None], R[None]).min(axis=1).max())
    assert worst < cover, worst
    # uniform on SO(3): the mean rotation matrix is zero
    assert np.abs(R.mean(axis=0)).max() < 3.0 / math.sqrt(count)


def test_plane_of_a_planar_arm_in_bounded_memory():
    """The plane of motion of a planar arm, from 40,000 tool points: its normal is the
    joint axes' direction, found from the points' 3x3 scatter (the SVD of the points
    themselves built a 20,000 x 20,000 matrix, 3 GiB, for `workspace --plot`)."""
    import tracemalloc

    from kincalc.analysis.workspace.sections import _planes
    robot = load("planar_3r")
    rng = np.random.default_rng(2)
    lo, hi = np.clip(robot.limits, -np.pi, np.pi).T
    P = robot.fk(rng.uniform(lo, hi, (40_000, robot.dof)))[:, :3, 3]
    tracemalloc.start()
    try:
        (plane,) = _planes(robot, P, 2, 0.01)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6
    axis = robot.fk(np.zeros(robot.dof))[:3, 2]          # the joint axes' common direction
    assert abs(abs(plane["normal"] @ axis) - 1) < 1e-9
