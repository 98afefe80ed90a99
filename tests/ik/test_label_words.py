"""Branch labels in words (issue 19): elbow up/down for planar arms, shoulder front/back and
elbow up/down for a spatial elbow arm without a shoulder offset, right/left kept for arms
with one. The expected words come from hand derivations on the arms' own joint values,
not from the labeller."""

import numpy as np
import pytest

import kincalc
from kincalc.model import Joint, Robot


def _dh_robot(rows, name):
    """A DH robot with identity base and tool: ``rows`` of (alpha deg, a, d)."""
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=np.radians(al), a=a, d=d, theta=0.0,
                         limits=(-np.pi, np.pi)) for i, (al, a, d) in enumerate(rows))
    return Robot(name=name, convention="dh", joints=joints, base=np.eye(4), tool=np.eye(4))


def _words(label):
    return set(label.split())


def test_textbook_planar_rr_example_4_2():
    """Bingul & Kucuk Example 4.2: (30, -60) has the elbow above the line from the shoulder
    to the target (12.99, 2.5), (-8.2, 60) below it."""
    r = kincalc.load_robot("bk_rr")
    T = np.eye(4)
    T[:3, 3] = (12.99, 2.5, 0.0)
    res = r.ik(T, orientation=False)
    by_q2 = {round(float(np.degrees(s.q[1]))): s.branch for s in res.solutions}
    assert by_q2 == {-60: "elbow up", 60: "elbow down"}


@pytest.mark.parametrize("n", [2, 3])
def test_planar_elbow_up_is_a_negative_elbow_angle(n):
    """A planar arm (axes along z, out of the page): the elbow lies counterclockwise of
    the shoulder-to-wrist line, (W - S) x (E - S) . z = -a1 a2 sin(q2) > 0, exactly when
    sin(q2) < 0."""
    rng = np.random.default_rng(19)
    for trial in range(40):
        r = _dh_robot([(0.0, rng.uniform(0.2, 0.6), rng.uniform(-0.2, 0.2)) for _ in range(n)],
                      f"planar_{n}r_{trial}")
        q = rng.uniform(-3.0, 3.0, n)
        res = r.ik(r.fk(q))
        assert res.solutions
        for s in res.solutions:
            if abs(np.sin(s.q[1])) < 1e-6:           # stretched or folded: one solution
                continue
            want = "up" if np.sin(s.q[1]) < 0 else "down"
            assert _words(s.branch) >= {"elbow", want}, (s.q, s.branch)
            assert ":" not in s.branch               # the elbow word replaces q2's sign


def test_spatial_elbow_arm_front_back_and_up_down():
    """An anthropomorphic arm (Siciliano 2.9.4, with a base height d1): in the arm's plane
    (r along x1, z up) the wrist is W = E + a3 (c23, s23), E = a2 (c2, s2). Front: the wrist
    lies along +x1 (r_W > 0, as at q = 0); elbow up: E above the line to W, which is
    cross(W, E) = -a2 a3 sin(q3) of the sign of r_W."""
    rng = np.random.default_rng(7)
    for trial in range(40):
        a2, a3, d1 = rng.uniform(0.2, 0.6), rng.uniform(0.2, 0.6), rng.uniform(0.0, 0.4)
        r = _dh_robot([(90.0, 0.0, d1), (0.0, a2, 0.0), (0.0, a3, 0.0)], f"elbow_arm_{trial}")
        res = r.ik(r.fk(rng.uniform(-3.0, 3.0, 3)), orientation=False)
        assert len(res.solutions) == 4
        labels = set()
        for s in res.solutions:
            q1, q2, q3 = s.q
            r_w = a2 * np.cos(q2) + a3 * np.cos(q2 + q3)
            if abs(r_w) < 1e-6 or abs(np.sin(q3)) < 1e-6:
                continue
            front = "front" if r_w > 0 else "back"
            up = "up" if np.sin(q3) * np.sign(r_w) < 0 else "down"
            assert s.branch == f"shoulder {front} elbow {up}", (s.q, s.branch)
            labels.add(s.branch)
        assert len(labels) == 4


def test_shoulder_offset_keeps_right_and_left():
    """The PUMA's shoulder offset (d2 - d3 along axis 2) makes its arms right and left;
    the KUKA KR 16 has none: front and back."""
    for name, words in [("puma560", {"right", "left"}), ("kuka_kr16", {"front", "back"})]:
        r = kincalc.load_robot(name)
        T = r.fk(np.radians([20, -30, 40, 10, 30, 20]))
        labels = [s.branch for s in r.ik(T).solutions]
        assert labels and all(lab.split()[1] in words for lab in labels), labels


def _closed_form_robots():
    from kincalc.conventions.library import bundled_names
    from kincalc.ik.families import plan
    return [n for n in bundled_names() if plan(kincalc.load_robot(n))[1] is not None]


@pytest.mark.parametrize("name", _closed_form_robots())
def test_labels_tell_every_solution_apart(name):
    """Words replace the signs they name, never a sign that tells two solutions apart
    (every bundled robot with a closed form; the others get one numerical solution)."""
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(3)
    lo, hi = np.clip(r.limits.T, -3.0, 3.0)
    for _ in range(5):
        res = r.ik(r.fk(rng.uniform(lo, hi)))
        labels = [s.branch for s in res.solutions]
        assert len(set(labels)) == len(labels), labels


@pytest.mark.parametrize("name", ["kuka_kr16", "kawasaki_rs007n", "kinova_gen3_6dof",
                                  "abb_irb120", "puma560", "fanuc_m20ia"])
def test_elbow_up_is_the_worlds_up(name):
    """The elbow is up when it lies above the line from the shoulder (axis 2) to the wrist
    centre, above in the world (z up), in the plane normal to the elbow's axes: also for
    the files whose axis 1 points down (KUKA, Kawasaki, Kinova), where the labeller's
    'side axis 1 points to' read upside down. Computed here from the solution's frames."""
    from kincalc.fk import chain_frames
    from kincalc.structure import common_point
    r = kincalc.load_robot(name)
    rng = np.random.default_rng(11)
    lo, hi = np.clip(r.limits.T, -3.0, 3.0)
    checked = 0
    for _ in range(20):
        for s in r.ik(r.fk(rng.uniform(lo, hi))).solutions:
            F = chain_frames(r.chain, s.q)
            h = F[1, :3, 2]
            W = common_point(F[3:, :3, 3], F[3:, :3, 2], np.inf)

            def flat(x):
                return x - (x @ h) * h
            line, v = flat(W - F[1, :3, 3]), flat(F[2, :3, 3] - F[1, :3, 3])
            perp = v - line * (v @ line) / (line @ line)
            up = perp[2]
            if abs(up) < 1e-6 or abs(flat(np.array([0, 0, 1.0])) @ perp) < 1e-6:
                continue                  # stretched, folded, or the plane is horizontal
            assert ("elbow up" in s.branch) == (up > 0), (s.q, s.branch)
            checked += 1
    assert checked > 20


@pytest.mark.parametrize("others", [0, 1, 39])
def test_no_elbow_side_with_the_wrist_on_the_shoulder(others):
    """siciliano_arm folded with equal links (a2 = a3) puts the tool point on the shoulder:
    there is no shoulder-to-target line, so no elbow word, whatever the rounding of the
    products. The label was "elbow down" with other poses in the batch and the signs alone
    without them (a 5e-33 product over a negative 2e-16 |l'|^2)."""
    r = kincalc.load_robot("siciliano_arm")
    T = r.fk(np.radians([[-90.0, 0.0, 180.0]] + [[10.0, 20.0, 30.0]] * others))
    solved = r.ik_batch(T)
    first = solved.labels[0][solved.valid[0]].tolist()
    assert first == [r.ik(T[0]).solutions[0].branch]
    assert not {"up", "down"} & _words(first[0])
