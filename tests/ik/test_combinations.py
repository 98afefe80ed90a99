"""--all-branches' wrong combinations (issue 19): the solutions' values paired within the
textbook's groups (the arm that places the wrist centre, then the wrist of each arm),
never a wrist of one branch with another branch's arm. Counts and distances from hand
derivations and a truncated chain, not from the combiner."""

import numpy as np

from kincalc import load_robot
from kincalc.ik import Target
from kincalc.ik.reasons import ArmMissed, Missed
from kincalc.ik.solve import solve
from kincalc.model import Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap


def _same(a, b, tol=1e-6):
    return bool(np.all(np.abs(wrap(np.asarray(a) - np.asarray(b))) < tol))


def _puma_result():
    r = load_robot("puma560")
    q0 = np.radians([10, -30, 40, 25, 40, 35])
    return r, solve(r, Target(r.fk(q0)), all_branches=True)


def test_puma_counts_by_hand():
    """Eight solutions: q1 takes 2 values, q2 4, q3 2, so 16 arms of which the solutions
    have 4 (12 wrong); each arm has 2 solutions whose wrists differ in q4 (+pi), q5 (sign)
    and q6 (+pi): 8 wrist combinations, 2 of them solutions (6 wrong), for 4 arms."""
    r, res = _puma_result()
    assert len(res.solutions) == 8
    kinds = [type(x["reason"]) for x in res.rejected]
    assert kinds.count(ArmMissed) == 12 and kinds.count(Missed) == 24


def test_puma_never_pairs_a_wrist_with_another_arm():
    r, res = _puma_result()
    Q = np.array([s.q for s in res.solutions])
    for x in res.rejected:
        q = np.asarray(x["q"])
        if isinstance(x["reason"], Missed):          # a wrist combination: a solution's arm
            assert any(_same(q[:3], s[:3]) for s in Q)
            assert x["position_error"] < 1e-9 and x["orientation_error"] > 1e-3
        else:                                         # an arm combination: a solution's wrist
            assert not any(_same(q[:3], s[:3]) for s in Q)
            assert any(_same(q[3:], s[3:]) for s in Q)


def test_puma_arm_combination_misses_the_wrist_centre_by_its_distance():
    """The PUMA's wrist centre is the origin of DH frame 4 (a4 = a5 = d5 = 0): the first
    four rows as a robot of their own put it there, whatever q4."""
    r, res = _puma_result()
    arm = Robot(name="puma_arm", convention="dh", joints=r.joints[:4], base=r.base,
                tool=np.eye(4))

    def centre(q):
        return arm.fk(np.append(q[:3], 0.0))[:3, 3]
    needed = centre(np.asarray(res.solutions[0].q))
    for x in res.rejected:
        if isinstance(x["reason"], ArmMissed):
            d = np.linalg.norm(centre(np.asarray(x["q"])) - needed)
            assert abs(x["reason"].distance - d) < 1e-9 and d > 1e-3
            assert x["reason"].point == "wrist centre" and x["reason"].joints == (0, 1, 2)


def test_example_4_6_scara_lists_fourteen_not_sixty():
    """Two arms (theta1, theta2) of two values each: 2 wrong arms; each arm's two
    solutions have two values of theta4, theta5, theta6: 6 wrong wrists per arm."""
    r = load_robot("bk_scara_euler")
    T = transform(matrix_from_rpy(np.radians([42, -17, 25])), [28, 31, 6])
    res = solve(r, Target(T), all_branches=True)
    kinds = [type(x["reason"]) for x in res.rejected]
    assert kinds.count(ArmMissed) == 2 and kinds.count(Missed) == 12


def test_example_4_2_is_one_group():
    """A planar RR has nothing after its tool point: its joints are combined as the
    book's zeta1 and zeta4, judged by the pose."""
    r = load_robot("bk_rr")
    T = np.eye(4)
    T[:3, 3] = [12.99, 2.5, 0]
    res = solve(r, Target(T, orientation=False), all_branches=True)
    assert [type(x["reason"]) for x in res.rejected] == [Missed, Missed]


def test_a_wrist_pair_is_its_own_group():
    """The offset-wrist arm (R-P-R-R-R-R, axes 5 and 6 meeting; a family without words):
    joints 1-4 place the point where axes 5 and 6 meet, and no combination puts one
    arm's wrist on another arm (each arm here has one solution, so only arm
    combinations are wrong, judged by that point)."""
    r = load_robot("bk_offset_wrist")
    res = solve(r, Target(r.fk(np.radians([-133.72, 0, 36.54, -169.67, -126.74, 154.15])
                                + np.array([0, 1.5685, 0, 0, 0, 0]))), all_branches=True)
    assert len(res.solutions) == 4 and res.rejected
    for x in res.rejected:
        assert isinstance(x["reason"], ArmMissed) and x["reason"].joints == (0, 1, 2, 3)
        assert x["reason"].point == "point where axes 5 and 6 meet"


def test_numerical_robots_say_there_are_no_branches():
    """A robot no closed form covers (here a redundant one; craig_rpr was such a robot until
    three-joint point-plus-roll arms had their closed form) gets one numerical solution;
    --all-branches says so instead of leaving the lists out."""
    r = load_robot("panda")
    res = solve(r, Target(r.fk(np.array([0.2, 0.3, 0.4, -1.5, 0.5, 1.5, 0.7]))),
                all_branches=True)
    assert res.family == "numerical" and res.rejected == [] and res.dead_ends == []
    assert "numerical" in res.note


def test_the_count_is_the_product_less_the_solutions():
    """``combination_count`` (what decides "too many to list" before anything is built)
    against a hand count on seeded random value tables: values on a grid, so that the
    distinct values of a joint and the distinct rows are plain to count."""
    from kincalc.ik.combinations import combination_count
    rng = np.random.default_rng(20240611)
    for _ in range(300):
        m, n = rng.integers(1, 9), rng.integers(1, 7)
        Q = rng.integers(-3, 4, size=(m, n)) * 0.25
        rev = rng.random(n) < 0.7
        joints = sorted(rng.choice(n, size=rng.integers(1, n + 1), replace=False).tolist())
        sub = Q[:, joints]
        expect = int(np.prod([len(set(sub[:, k])) for k in range(len(joints))])) \
            - len({tuple(r) for r in sub})
        assert combination_count(Q, joints, rev) == expect


def test_too_many_combinations_are_counted_not_built(monkeypatch):
    """A general 6R (xArm 6) has 8 solutions with 8 values of every joint: 8**6 - 8 arm
    combinations. --all-branches says there are too many to list; it built each one
    first (a comparison with every solution each: 16 s a pose), now it counts them."""
    import kincalc.ik.combinations as combinations
    calls = []
    real = combinations._equal
    monkeypatch.setattr(combinations, "_equal", lambda *a: calls.append(1) or real(*a))
    r = load_robot("xarm6")
    res = solve(r, Target(r.fk(np.radians([10, 20, 30, 40, 50, 60]))), all_branches=True)
    assert len(res.solutions) == 8
    assert res.rejected == [] and res.note.startswith("262136 combinations")
    assert len(calls) < 1000
