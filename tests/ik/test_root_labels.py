""""root k" labels name the same solution for the same robot however it is described.

A general three-revolute arm places the wrist centre by subproblem 5 (up to four roots
found at once). Its slots used to be in the order the two-ellipse solver found the roots,
which depends on the frames the description puts the axes in: the same solution of the
same robot was "q1:root 4" in dh and "q1:root 2" in mdh, and a pose given in degrees on the
command line against the same pose in radians could swap two roots sharing q1 (found by an
independent random-robot campaign). Roots are now ordered by their joint values (root 1
the smallest q1, ties to 1e-9 rad by the next joint): the labels depend on the answers only.
"""

import numpy as np

from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.ik.families import plan
from kincalc.ik.place import plan as placement
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap
from kincalc.structure import common_point
from kincalc.subproblems.solutions import Solutions


def _pieper(rng):
    """Joints 1-3 at right angles with offsets (no parallel or meeting axes), then a
    spherical wrist, a random base and tool (the campaign's arms were of this kind)."""
    r = lambda: rng.choice([-1, 1]) * np.pi / 2  # noqa: E731
    u = lambda: rng.uniform(0.05, 0.45) * rng.choice([-1, 1])  # noqa: E731
    rows = [(r(), u(), u()), (r(), u(), 0.0), (r(), u(), 0.0), (r(), 0.0, 0.0),
            (rng.uniform(0.2, 2.8), 0.0, 0.0), (r(), 0.0, u())]
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=rng.uniform(-3, 3))
                   for i, (al, a, d) in enumerate(rows))
    base = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.3, .3, 3))
    tool = transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-.2, .2, 3))
    return Robot(name="pieper", convention="dh", joints=joints, base=base, tool=tool)


def _labelled(robot, T) -> dict:
    return {tuple(np.round(wrap(s.q), 6)): s.branch for s in robot.ik(T).solutions}


def test_root_labels_agree_across_conventions_and_paths():
    rng = np.random.default_rng(71)
    checked = rooted = 0
    for _ in range(8):
        r = _pieper(rng)
        S, family, _ = plan(r)
        centre = common_point(S.point[3:], S.axis[3:], np.inf)
        assert placement(S, (0, 1, 2), tuple(centre)).mode == "three cones"
        others = (dh_to_mdh(r), to_poe(r))
        Q = sample_configurations(r, 10, rng)
        for q in Q:
            T = r.fk(q)
            want = _labelled(r, T)
            rooted += any("root" in b for b in want.values())
            for other in others:
                assert _labelled(other, T) == want
            # the batch of all poses, and the pose rounded as a degree value read back
            T2 = r.fk(np.radians(np.round(np.degrees(q), 9)))
            got = _labelled(r, T2)
            assert sorted(got.values()) == sorted(want.values())
            checked += 1
        B = r.ik_batch(r.fk(Q))
        for k, q in enumerate(Q):
            want = _labelled(r, r.fk(q))
            got = {tuple(np.round(wrap(B.q[k, j]), 6)): B.labels[k, j]
                   for j in np.flatnonzero(B.valid[k])}
            assert got == want
    assert checked == 80 and rooted >= 20, (checked, rooted)


def test_ordered_sorts_each_problem_by_its_angles():
    """By hand: two problems of three slots; unknown 0 ties in the first (broken by unknown
    1), the second has a slot that is not ok (last)."""
    t0 = np.array([[0.5, 0.5, -1.0], [2.0, -3.0, 1.0]])
    t1 = np.array([[0.2, -0.2, 0.0], [0.0, 0.0, 0.0]])
    ok = np.array([[True, True, True], [True, False, True]])
    sol = Solutions((t0, t1), (np.cos(t0), np.cos(t1)), (np.sin(t0), np.sin(t1)), ok, ok,
                    np.zeros_like(ok)).ordered()
    assert sol.theta[0].tolist() == [[-1.0, 0.5, 0.5], [1.0, 2.0, -3.0]]
    assert sol.theta[1].tolist() == [[0.0, -0.2, 0.2], [0.0, 0.0, 0.0]]
    assert sol.ok.tolist() == [[True, True, True], [True, True, False]]
    assert np.allclose(sol.c[0], np.cos(sol.theta[0]))
    assert np.allclose(sol.s[1], np.sin(sol.theta[1]))


def test_ordered_counts_minus_pi_as_pi():
    """A root at the wrap, -pi + 1e-13 in one description and pi in another, is one root: it
    sorts last in both (a reversed chain's 'root k' shifted with it on poses at 180 deg)."""
    for first in (-np.pi + 1e-13, np.pi):
        t = np.array([first, 0.5, -1.0])
        ok = np.ones(3, bool)
        sol = Solutions((t,), (np.cos(t),), (np.sin(t),), ok, ok, np.zeros(3, bool)).ordered()
        assert sol.theta[0].tolist() == [-1.0, 0.5, first]


def test_every_sign_label_is_the_branch_its_explained_formula_names():
    """Over every bundled robot: where --explain writes a step as ``q = b ± d``, ``q = ±d`` or
    ``q = ∓d (the + branch is v)``, the solution whose label says ``q:+`` is the + branch of
    that formula and ``q:-`` the other (60 of 126 such labels contradicted the written
    formula where A < 0: cos q = (t - C) / A, shown as q = ±acos(...))."""
    import re

    from kincalc import load_robot
    from kincalc.analysis.results import ik_document
    from kincalc.conventions.library import bundled_names
    checked = 0
    for name in bundled_names():
        r = load_robot(name)
        for q in sample_configurations(r, 4, np.random.default_rng(3)):
            res = r.ik(r.fk(q), explain=True)
            for s, d in zip(res.solutions, ik_document(res)["solutions"]):
                for step in d.get("trace") or []:
                    joint, line = step["step"], step["text"]
                    lab = re.search(re.escape(joint) + r":([+-])(?:\s|$)", s.branch)
                    g = re.search(r"= (-?[0-9.]+)° ± (-?[0-9.]+)°: \S+ = (-?[0-9.]+)", line)
                    h = re.search(r"= ±(-?[0-9.]+)°: \S+ = (-?[0-9.]+)", line)
                    k = re.search(r"the \+ branch is (-?[0-9.]+)°\): \S+ = (-?[0-9.]+)", line)
                    if not lab or not (g or h or k):
                        continue
                    if g:
                        b, dd, got = map(float, g.groups())
                        plus = b + dd
                    else:
                        plus, got = map(float, (h or k).groups())
                    checked += 1
                    on_plus = abs((got - plus + 180) % 360 - 180) < 1e-2
                    assert on_plus == (lab.group(1) == "+"), (name, s.branch, line)
    assert checked >= 50
