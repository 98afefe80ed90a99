"""Sweeping a held joint of a redundant arm (kincalc.analysis.sweep), against independent
values: the generating configuration at its own value on a branch, every solution
reproducing the pose by FK, the first/last-joint sweeps (one chain, moved targets) equal
to the conjugated chain held at each value, branches continuous (a solve at the midpoint
of every step lies between its ends), a fold where two branches meet is a singular
configuration of the chain the lock leaves, and the least-change pick is the brute-force
minimum."""

import json

import numpy as np
import pytest

import kincalc
from kincalc.analysis.redundancy import locked_robot, solve_locked
from kincalc.analysis.sweep import JUMP, nearest, sweep, sweep_document
from kincalc.analysis.results import Units
from kincalc.errors import InputError
from kincalc.ik import Target

SEVEN = ["iiwa14", "iiwa7", "panda", "kinova_gen3"]


def _wrapped(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


def _elbow(robot):
    from kincalc.structure import common_point, joint_axes
    dirs, pts = joint_axes(robot)
    meets = [common_point(pts[js], dirs[js], 1e-9 * robot.characteristic_length) is not None
             for js in ([0, 1, 2], [4, 5, 6])]
    return 3 if all(meets) else None


def _values_through(x, steps=25, half=0.6):
    """``steps`` values around ``x`` (rad) with ``x`` one of them."""
    return x + np.linspace(-half, half, steps)


@pytest.mark.parametrize("name", SEVEN)
def test_the_generating_configuration_is_on_a_branch_at_its_value(name):
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(sum(map(ord, name)) + 1)
    lo, hi = np.clip(r.limits, -np.pi, np.pi).T
    q0 = rng.uniform(0.8 * lo, 0.8 * hi)
    T = r.fk(q0)
    joints = [0, 2, 6] if name != "kinova_gen3" else [0, 6]   # first, middle, last
    for j in joints:
        if j == _elbow(r):
            continue
        values = _values_through(q0[j])
        sw = sweep(r, Target(T).targets(), j, values)
        i = len(values) // 2
        assert any(np.all(_wrapped(sw.q[i, b], q0) < 1e-6)
                   for b in np.flatnonzero(sw.present[i])), (name, j)
        Q = sw.q[sw.present]
        assert np.allclose(r.fk(Q), T, atol=1e-9)
        assert np.allclose(Q[:, j], np.repeat(values, sw.present.sum(1)))


@pytest.mark.parametrize("joint", [0, 6])
def test_end_joint_sweeps_equal_the_conjugated_chain_at_each_value(joint):
    """Moved targets on one chain (the first or last joint) against the chain with the
    joint held at each value (redundancy.locked_robot: every later axis moved)."""
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([15, 35, -25, -70, 40, 55, -30])
    T = r.fk(q0)
    values = _values_through(q0[joint], steps=9, half=1.0)
    sw = sweep(r, Target(T).targets(), joint, values)
    for i, v in enumerate(values):
        ours = sw.q[i][sw.present[i]]
        theirs = np.array([s.q for s in solve_locked(r, Target(T), {joint: v}).solutions])
        assert len(ours) == len(theirs)
        for q in theirs:
            assert np.min(np.max(_wrapped(ours, q), axis=1)) < 1e-8


@pytest.mark.parametrize("name,joint", [("iiwa14", 2), ("panda", 6), ("iiwa14", 0)])
def test_branches_are_continuous(name, joint):
    """Each step of a branch, followed independently of the sweep: the chain held at 32
    values between its ends (solve_locked), always taking the solution nearest the last,
    moves by small changes from one end to the other. The steps checked are each branch's
    largest (the fast motions the sweep followed by halving) and a random one."""
    r = kincalc.load_robot(name)
    q0 = np.radians([10, 40, 20, -60, 30, 50, -20])
    T = r.fk(q0)
    values = np.linspace(*r.limits[joint], 41)
    sw = sweep(r, Target(T).targets(), joint, values)
    rng = np.random.default_rng(3)
    steps = []
    for b in range(len(sw.branches)):
        both = np.flatnonzero(sw.present[:-1, b] & sw.present[1:, b])
        if len(both):
            size = [np.max(_wrapped(sw.q[i, b], sw.q[i + 1, b])) for i in both]
            steps += [(b, int(both[np.argmax(size)])), (b, int(rng.choice(both)))]
    assert len(steps) >= 8
    for b, i in steps[:12]:
        q = sw.q[i, b]
        for v in np.linspace(values[i], values[i + 1], 33)[1:]:
            sols = np.array([s.q for s in solve_locked(r, Target(T), {joint: v}).solutions])
            d = np.max(_wrapped(sols, q), axis=1)
            assert d.min() < JUMP / 2, (b, i, v)
            q = sols[np.argmin(d)]
        assert np.max(_wrapped(q, sw.q[i + 1, b])) < 1e-8


def test_branches_meet_where_the_held_chain_is_singular():
    """Two branches that meet stop together at a fold: there the chain the lock leaves
    loses rank (its smallest singular value, relative to the largest, is tiny)."""
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([10, 40, 20, -60, 30, 50, -20])
    T = r.fk(q0)
    values = np.linspace(*r.limits[0], 61)
    sw = sweep(r, Target(T).targets(), 0, values)
    folds = [(b, br) for b, br in enumerate(sw.branches) if br.ends.kind == "meets"]
    assert len(folds) >= 8
    keep = list(range(1, 7))
    for b, br in folds:
        v = br.ends.value
        assert values[br.last] <= v < values[br.last + 1]
        other = sw.branches[br.ends.other]
        assert other.ends.kind == "meets" and other.ends.other == b
        sols = solve_locked(r, Target(T), {0: v}).solutions
        # the two merging solutions: the nearest pair of the held chain's answers
        Q = np.array([s.q for s in sols])
        chain = locked_robot(r, {0: v})
        sv = np.linalg.svd(chain.jacobian(Q[:, keep]), compute_uv=False)
        assert (sv[:, -1] / sv[:, 0]).min() < 2e-2


def test_nearest_is_the_least_change_over_the_sweep():
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([10, 40, 20, -60, 30, 50, -20])
    near = np.radians([0, 30, 0, -60, 0, 60, 0])
    sw = sweep(r, Target(r.fk(q0)).targets(), 2, np.linspace(-2.5, 2.5, 37))
    i, b, q, change = nearest(sw, near)
    best = min(np.linalg.norm(sw.q[k, c] - near) for k in range(37) for c in range(len(sw.branches))
               if sw.present[k, c] and sw.within[k, c])
    assert np.isclose(np.linalg.norm(change), best) and np.allclose(q, sw.q[i, b])


def test_sweep_document_counts_and_units():
    r = kincalc.load_robot("iiwa14")
    q0 = np.radians([10, 40, 20, -60, 30, 50, -20])
    target = Target(r.fk(q0))
    sw = sweep(r, target.targets(), 2, np.radians(np.linspace(-90, 90, 7)))
    doc = json.loads(json.dumps(sweep_document(sw, target, Units("deg", "mm"))))
    assert doc["sweep"] == {"joint": "A3", "values": [-90.0, -60.0, -30.0, 0.0, 30.0, 60.0,
                                                      90.0], "steps": 7}
    assert sum(len(p["solutions"]) for p in doc["points"]) == int(sw.present.sum())
    assert all(s["q"][2] == p["value"] for p in doc["points"] for s in p["solutions"])
    assert doc["target"]["T"][0][3] == pytest.approx(r.fk(q0)[0, 3] * 1000)


def test_refusals():
    r = kincalc.load_robot("iiwa14")
    T = Target(r.fk(np.zeros(7) + 0.3)).targets()
    with pytest.raises(InputError, match="continuum"):
        sweep(r, T, 3, np.linspace(-1, 1, 5))                   # the SRS elbow
    with pytest.raises(InputError, match="also locked"):
        sweep(r, T, 2, np.linspace(-1, 1, 5), {2: 0.1})


@pytest.mark.parametrize("convention", ["dh", "mdh", "poe"])
def test_random_seven_joint_arms(convention):
    """Random 7R arms (general 6R once a joint is held): the generating configuration on a
    branch at its value, every solution reproducing the pose."""
    from randrobots import random_robot
    rng = np.random.default_rng({"dh": 21, "mdh": 22, "poe": 23}[convention])
    r = random_robot(rng, convention, n=7, types=["revolute"] * 7)
    q0 = rng.uniform(-2, 2, 7)
    T = r.fk(q0)
    j = int(rng.integers(1, 6))
    values = _values_through(q0[j], steps=7, half=0.3)
    sw = sweep(r, Target(T).targets(), j, values)
    assert any(np.all(_wrapped(sw.q[3, b], q0) < 1e-6) for b in np.flatnonzero(sw.present[3]))
    Q = sw.q[sw.present]
    assert np.allclose(r.fk(Q), T, atol=1e-8)
