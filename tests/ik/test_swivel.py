"""The swivel angle of SRS arms (kincalc.ik.swivel, kincalc.analysis.swivel), against
independent values: the SEW angle computed here from the definition of Elias & Wen,
the generating configuration at its own swivel angle among the 8 branches, every
solution reproducing the pose and the angle, each solution also found by the
locked-joint solver (a different chain and family), and the feasible intervals against
dense sampling."""

import json

import numpy as np
import pytest

import kincalc
from kincalc.analysis.redundancy import solve_locked
from kincalc.analysis.swivel import swivel_ranges
from kincalc.errors import InputError
from kincalc.ik import Target, solve
from kincalc.ik.engine import solve_targets
from kincalc.ik.swivel import srs, swivel_angles
from kincalc.ik.target import Targets
from kincalc.model import Joint, Robot


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _normal_to(k, rng):
    v = np.cross(k, rng.normal(size=3))
    return _unit(v)


def random_srs(rng, limits=np.pi, orthogonal=True):
    """An SRS arm in product-of-exponentials form: three axes through a shoulder point,
    an elbow axis through a point off the shoulder and wrist, three axes through a wrist
    point, a random tool pose at q = 0. ``orthogonal``: consecutive axes of the shoulder
    and of the wrist at right angles (as on real arms: each then reaches every rotation),
    else random directions."""
    S = np.array([0.0, 0.0, rng.uniform(0.2, 0.4)])
    E = S + _unit(rng.normal(size=3)) * rng.uniform(0.3, 0.5)
    W = E + _unit(rng.normal(size=3)) * rng.uniform(0.3, 0.5)
    axes = [np.array([0.0, 0, 1])]
    for i in range(6):
        if orthogonal and i in (0, 1, 4, 5):          # axes 2, 3 and 6, 7
            axes.append(_normal_to(axes[-1], rng))
        else:
            axes.append(_unit(rng.normal(size=3)))
    points = [S, S, S, E + 0.05 * _unit(rng.normal(size=3)), W, W, W]
    joints = tuple(Joint(f"j{i + 1}", "revolute", axis=tuple(_unit(a)), point=tuple(p),
                         limits=(-limits, limits)) for i, (a, p) in enumerate(zip(axes, points)))
    from kincalc.spatial import matrix_from_rotvec
    M = np.eye(4)
    M[:3, :3] = matrix_from_rotvec(rng.normal(size=3))
    M[:3, 3] = W + _unit(rng.normal(size=3)) * 0.1
    return Robot(name="random_srs", convention="poe", joints=joints, M=M)


def sew_angle_here(S, E, W, R, V):
    """The stereographic SEW angle, written from the paper's definition."""
    w = _unit(W - S)
    n_sew = _unit(np.cross(W - S, E - S))
    n_ref = _unit(np.cross(w - R, V))
    return np.arctan2(n_sew @ np.cross(w, n_ref), n_sew @ n_ref)


def test_srs_structure_is_found_from_the_axes():
    assert srs(kincalc.load_robot("iiwa14")) is not None
    assert srs(kincalc.load_robot("iiwa7")) is not None
    assert srs(kincalc.load_robot("panda")) is None            # offsets at shoulder and wrist
    assert srs(kincalc.load_robot("puma560")) is None          # six joints
    rng = np.random.default_rng(1)
    assert srs(random_srs(rng)) is not None


def test_swivel_angle_is_the_sew_angle_of_the_arm():
    """The angle of a configuration against the definition, from the joint frames of FK:
    S and W where the axes meet, E the point of axis 4 nearest S."""
    r = kincalc.load_robot("iiwa14")
    g = srs(r)
    rng = np.random.default_rng(2)
    Q = rng.uniform(-2.5, 2.5, (50, 7))
    psi = swivel_angles(r, Q)
    from kincalc.fk import chain_frames
    for q, p in zip(Q, psi):
        F = chain_frames(r.chain, q)               # frame j: axis j+1 after joints 1..j
        z4, o4 = F[3, :3, 2], F[3, :3, 3]
        # the wrist centre: where axes 5-7 meet (least squares of the three lines)
        A, b = np.zeros((3, 3)), np.zeros(3)
        for j in (4, 5, 6):
            P = np.eye(3) - np.outer(F[j, :3, 2], F[j, :3, 2])
            A += P
            b += P @ F[j, :3, 3]
        W = np.linalg.solve(A, b)
        E = o4 + ((g.shoulder - o4) @ z4) * z4
        assert np.isclose(np.angle(np.exp(1j * (p - sew_angle_here(g.shoulder, E, W, g.R, g.V)))),
                          0, atol=1e-9)


@pytest.mark.parametrize("which", ["iiwa14", "iiwa7", "random", "skew"])
def test_the_generating_configuration_at_its_own_angle(which):
    """Eight branches for nearly every pose (a shoulder or wrist of skew axes reaches only
    some rotations: fewer there, the generating one always among them)."""
    rng = np.random.default_rng({"iiwa14": 3, "iiwa7": 4, "random": 5, "skew": 6}[which])
    r = kincalc.load_robot(which) if which.startswith("iiwa") else \
        random_srs(rng, orthogonal=which == "random")
    lo, hi = np.clip(r.limits, -np.pi, np.pi).T
    Q = rng.uniform(0.9 * lo, 0.9 * hi, (60, 7))
    T = r.fk(Q)
    psi = swivel_angles(r, Q)
    sv = solve_targets(r, Targets(T, "swivel", swivel=psi))
    counts = sv.valid.sum(1)
    assert counts.max() <= 8 and (which == "skew" or (counts == 8).mean() > 0.9)
    for i in range(len(Q)):
        sols = sv.q[i, sv.valid[i]]
        d = np.abs(np.angle(np.exp(1j * (sols - Q[i])))).max(1)
        assert d.min() < 1e-7
        assert np.allclose(r.fk(sols), T[i], atol=1e-9)
        assert np.allclose(np.angle(np.exp(1j * (swivel_angles(r, sols) - psi[i]))), 0, atol=1e-8)


def test_every_swivel_solution_is_a_solution_with_its_joint_3_held():
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([20, -35, 50, 70, -40, 60, 10])
    T = r.fk(q0)
    for psi in np.radians([-150, -60, 0, 45, 120]):
        res = solve(r, Target(T, swivel=psi))
        assert res.family == "srs-swivel" and len(res.solutions) == 8
        for s in res.solutions:
            held = solve_locked(r, Target(T), {2: s.q[2]}).solutions
            assert min(np.abs(np.angle(np.exp(1j * (h.q - s.q)))).max() for h in held) < 1e-8


@pytest.mark.parametrize("which", ["iiwa14", "random"])
def test_feasible_intervals_against_dense_sampling(which):
    rng = np.random.default_rng(7)
    r = random_srs(rng, limits=np.radians(150)) if which == "random" else \
        kincalc.load_robot("iiwa14")
    q0 = rng.uniform(-1.2, 1.2, 7)
    T = r.fk(q0)
    ranges = swivel_ranges(r, T)
    psi = np.linspace(-np.pi, np.pi, 12001)
    sv = solve_targets(r, Targets(np.broadcast_to(T, (len(psi), 4, 4)).copy(), "swivel",
                                  swivel=psi))
    ok = sv.valid & sv.within
    by_label = {x.label: x for x in ranges}
    step = 2 * np.pi / 720 / 2 ** 20
    for k in range(ok.shape[1]):
        if not sv.valid[:, k].any():
            continue
        x = by_label[next(lab for lab, v in zip(sv.labels[:, k], sv.valid[:, k]) if v)]
        inside = np.zeros(len(psi), bool)
        near_end = np.zeros(len(psi), bool)
        for a, b in x.intervals:
            inside |= (psi - a) % (2 * np.pi) <= b - a
            for e in (a, b):
                near_end |= np.abs(np.angle(np.exp(1j * (psi - e)))) < 10 * step
        assert np.all((inside == ok[:, k]) | near_end), x.label
    # the generating configuration's angle is feasible on some branch
    p0 = swivel_angles(r, q0)
    assert any(((p0 - a) % (2 * np.pi) <= b - a) for x in ranges for a, b in x.intervals) \
        or not np.all((q0 >= r.limits[:, 0]) & (q0 <= r.limits[:, 1]))


def test_not_an_srs_arm_is_told():
    with pytest.raises(InputError, match="spherical shoulder"):
        swivel_angles(kincalc.load_robot("panda"), np.zeros(7))


def test_swivel_on_the_command_line():
    from cli_contract import run_cli
    q0 = "20 -35 50 70 -40 60 10"
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, "--swivel", "45", "--json"])
    assert status == 0, err
    doc = json.loads(out)
    assert doc["target"]["swivel"] == 45.0 and doc["count"] == 8
    assert doc["method"]["family"] == "srs-swivel"
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, "--swivel-range", "--json"])
    assert status == 0, err
    doc = json.loads(out)
    assert len(doc["branches"]) == 8 and doc["reachable"]
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, "--swivel-range"])
    assert status == 0 and "swivel angles within the limits" in out
    status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, "--swivel-range", "--near", q0,
                                "--json"])
    assert status == 0 and json.loads(out)["nearest"]["change"] == pytest.approx([0] * 7,
                                                                                   abs=1e-6)
    for extra, words in ((["--swivel", "10", "--lock", "A1=0"], "--lock does not go with"),
                         (["--swivel", "10", "--sweep", "A1"], "do not go together"),
                         (["--swivel", "nan"], "--swivel"),
                         (["--swivel-range", "--format", "csv"], "--format csv does not go")):
        status, out, err = run_cli(["ik", "iiwa14", "--from-q", q0, *extra])
        assert status == 2 and words in err and err.count("\n") == 1, (extra, err)
    status, out, err = run_cli(["ik", "panda", "--from-q", q0, "--swivel", "10"])
    assert status == 2 and "spherical shoulder" in err
    status, out, err = run_cli(["ik", "iiwa14", "--xyz", "0.5", "0", "0.5", "--swivel", "10"])
    assert status == 2 and "whole pose" in err


def test_nearest_swivel_is_the_least_change_on_the_circle():
    """Against a dense scan of the circle (20 000 angles, every branch)."""
    from kincalc.analysis.swivel import nearest_swivel
    from kincalc.spatial import turn_toward
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([20, -35, 50, 70, -40, 60, 10])
    near = q0 + np.radians([3, -2, 5, 0, 4, -3, 2])
    label, psi, q, change = nearest_swivel(r, r.fk(q0), near)
    assert np.allclose(r.fk(q), r.fk(q0), atol=1e-9)
    assert np.isclose(np.angle(np.exp(1j * (swivel_angles(r, q) - psi))), 0, atol=1e-8)
    grid = np.linspace(-np.pi, np.pi, 20000)
    sv = solve_targets(r, Targets(np.broadcast_to(r.fk(q0), (len(grid), 4, 4)).copy(),
                                  "swivel", swivel=grid))
    Q = turn_toward(sv.q, near, *r.limits.T)
    cost = np.where(sv.valid & sv.within, np.linalg.norm(Q - near, axis=-1), np.inf)
    assert np.linalg.norm(change) <= cost.min() + 1e-9
    assert np.linalg.norm(change) <= np.linalg.norm(q0 - near) + 1e-12


def test_labels_name_the_sign_of_joints_2_4_6():
    """The iiwa's eight branches at a swivel angle: each label's +/- of A2, A4 and A6 is the
    sign of that joint (as the held-joint families label them)."""
    r = kincalc.load_robot("iiwa14")
    rng = np.random.default_rng(9)
    for q0 in rng.uniform(-2.0, 2.0, (10, 7)):
        res = solve(r, Target(r.fk(q0), swivel=float(swivel_angles(r, q0))))
        for s in res.solutions:
            signs = dict(part.split(":") for part in s.branch.split() if ":" in part)
            for j in (1, 3, 5):
                if abs(s.q[j]) > 1e-6:
                    assert signs[f"A{j + 1}"] == ("+" if s.q[j] > 0 else "-"), s.branch


def test_undefined_swivel_angles_are_refused():
    """The wrist straight below the shoulder (the SEW singular direction) and a stretched
    arm: the angle is undefined, and the command line says so instead of 'unreachable'."""
    from cli_contract import run_cli
    from kincalc.ik.swivel import undefined_at
    r = kincalc.load_robot("iiwa14")
    assert undefined_at(r, r.fk(np.radians([10, 40, 20, 0, 30, 50, -20]))) is not None
    assert undefined_at(r, r.fk(np.radians([10, 40, 20, 0.01, 30, 50, -20]))) is None
    g = srs(r)
    T = np.eye(4)
    T[:3, :3] = np.diag([1.0, -1.0, -1.0])
    from kincalc.ik.pieces import tool_point
    W = tool_point(g.screws, T[None], g.wrist)[0, 0]      # the wrist centre of this pose
    T[:3, 3] += (g.shoulder + 0.5 * g.R) - W              # moved onto S + t R
    assert "singular direction" in undefined_at(r, T)
    for extra in (["--swivel", "10"], ["--swivel-range"]):
        status, out, err = run_cli(["ik", "iiwa14", "--from-q", "10 40 20 0 30 50 -20", *extra])
        assert status == 2 and "undefined at this pose" in err, err
