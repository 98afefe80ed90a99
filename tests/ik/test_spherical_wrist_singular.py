"""Spherical-wrist arms at (and next to) their wrist singularity.

Axes 4, 5, 6 meet in a point. Write sigma = +-1 for the direction of axis 6 relative
to axis 4. When R5 k6 = sigma k4 (axis 6 on the line of axis 4, q5 = 0 or 180 deg on a
PUMA), R(k4, q4) R5 R(k6, q6) = R(k4, q4 + sigma q6) R5. The pose then fixes q1-q3 (the
wrist centre), q5 and q4 + sigma q6 (mod 2 pi): a one-parameter continuum. robot.ik
must return a representative of it for the generating placement of joints 1-3: flagged
singular, joint 4 named free, the fixed combination reported. The other placements
(axis 6 not on axis 4 there) give their two isolated wrist solutions each. ik_batch must
return the same set. Every returned configuration must reproduce the pose.

Every check is made from the forward kinematics and the joint frames
(kincalc.fk.chain_frames): whether axes 4 and 6 are aligned, sigma, and the combination
q4 + sigma q6 come from the frames at the configuration, never from the solvers' screws.
The wrist axes need not be orthogonal: the random arms have twists alpha5 = -alpha4 or
pi - alpha4 (DH), which line axis 6 up with axis 4 at one value of q5 only.
"""

import zlib

import numpy as np
import pytest
from randrobots import follow_joint, random_pose

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.fk import chain_frames
from kincalc.ik.families import classify
from kincalc.ik.screws import Screws
from kincalc.spatial import wrap
from kincalc.ik.selftest import sample_configurations
from kincalc.conventions.library import bundled_names
from kincalc.model import Joint, Robot
from kincalc.analysis.words import singularity_text

WRIST = (3, 4, 5)                # 0-based joints of the wrist (forward chains)
REVERSED_WRIST = (0, 1, 2)       # ... and of a reversed chain (the wrist is at the base)


# --- independent geometry (joint frames) ----------------------------------------------

def wrist_facts(r, Q, wrist=WRIST):
    """For configurations ``Q (k, n)``, from the joint frames (z: a joint's axis; world
    frame): ``aligned`` (k,) the sine of the angle between the outer wrist axes,
    ``sigma`` (k,) +1 when they point the same way, and ``total`` (k,) the combination
    q_i + sigma q_k (rad) that the pose fixes when they are aligned."""
    Q = np.atleast_2d(np.asarray(Q, float))
    z = chain_frames(r.chain, Q)[:, :, :3, 2]
    i, _, k = wrist
    zi, zk = z[:, i], z[:, k]
    sigma = np.where((zi * zk).sum(-1) > 0, 1.0, -1.0)
    return dict(aligned=np.linalg.norm(np.cross(zi, zk), axis=-1), sigma=sigma,
                total=Q[:, i] + sigma * Q[:, k])


def joint_diff(r, A, b):
    """``|A - b|`` per joint (k, n) for rows ``A (k, n)`` and ``b (n,)``: wrapped for
    revolute joints."""
    D = np.atleast_2d(np.asarray(A, float)) - np.asarray(b, float)
    return np.abs(np.where(r.is_revolute, wrap(D), D))


def on_generating_continuum(r, sols, q, wrist=WRIST, tol=1e-6):
    """Indices of the rows of ``sols (m, n)`` on the continuum of the generating
    configuration ``q`` (aligned wrist): the same placement joints (within ``tol``),
    outer wrist axes aligned (1e-9) the same way, and the same fixed combination."""
    sols = np.asarray(sols, float).reshape(-1, r.dof)
    if len(sols) == 0:
        return []
    arm = [j for j in range(r.dof) if j not in wrist]
    F = wrist_facts(r, np.vstack([q, sols]), wrist)
    ok = (joint_diff(r, sols, q)[:, arm].max(-1) < tol) & (F["aligned"][1:] < 1e-9) & \
        (F["sigma"][1:] == F["sigma"][0]) & (np.abs(wrap(F["total"][1:] - F["total"][0])) < tol)
    return np.flatnonzero(ok).tolist()


def assert_reproduces(r, Q, T):
    """FK of every row of ``Q`` is ``T``: position within 1e-9 of the robot's size (at
    least 1 m), rotation entries within 1e-9."""
    Q = np.asarray(Q, float).reshape(-1, r.dof)
    assert np.all(np.isfinite(Q))
    if len(Q) == 0:
        return
    Tq = r.fk(Q)
    L = max(1.0, r.characteristic_length)
    assert np.abs(Tq[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * L
    assert np.abs(Tq[:, :3, :3] - T[:3, :3]).max() <= 1e-9


def same_set(r, A, B, tol=1e-7) -> bool:
    A, B = np.asarray(A).reshape(-1, r.dof), np.asarray(B).reshape(-1, r.dof)
    return len(A) == len(B) and all(joint_diff(r, B, a).max(-1).min() < tol for a in A)


def away_from_arm_singularities(r, q, q5, wrist=WRIST) -> bool:
    """Is the placement of ``q`` well conditioned? The Jacobian, with the wrist turned a
    quarter turn away from the aligned value (that is as far from the wrist's own
    singularities as it gets), must have a smallest singular value above 1e-3 (lengths
    scaled by the robot's size). A stretched elbow or the wrist centre on the shoulder's
    axis would be a double root of the placement, good only to sqrt(eps)."""
    p = np.array(q, float)
    p[wrist[1]] = q5 + np.pi / 2
    J = r.jacobian(p[None])[0]
    J[:3] /= max(1.0, r.characteristic_length)
    return np.linalg.svd(J, compute_uv=False)[-1] > 1e-3


# --- robots ---------------------------------------------------------------------------

def random_wrist_arm(rng, arm: str, orthogonal: bool, convention: str):
    """A random spherical-wrist arm (DH rows alpha, a, d, theta; random lengths, offsets,
    base and tool) whose axis 6 lines up with axis 4 at q5 = -theta5. ``arm``: axes 1-2
    meeting (a1 = 0), parallel (alpha1 = 0), or a generic offset shoulder. The wrist:
    a4 = a5 = d5 = 0 (axes 4-6 concurrent), alpha5 = -alpha4 (axis 6 along axis 4 at
    q5 = -theta5) or pi - alpha4 (against it). With ``orthogonal`` the twists are
    +-90 deg and the wrist lines up at q5 = pi - theta5 as well.

    Returns ``(robot, aligned q5 values)``."""
    u = lambda lo=-0.5, hi=0.5: rng.uniform(lo, hi)  # noqa: E731
    # twists well off 0 and 180 deg (nearly parallel neighbouring axes: a nearly singular arm)
    ang = lambda: rng.uniform(0.6, 2.5) * rng.choice([-1, 1])  # noqa: E731
    length = lambda: rng.uniform(0.15, 0.5) * rng.choice([-1, 1])  # noqa: E731
    if orthogonal:
        a4, a5 = (rng.choice([-1, 1]) * np.pi / 2 for _ in range(2))
    else:
        a4 = ang()
        a5 = rng.choice([-a4, np.pi - a4])
    th = rng.uniform(-np.pi, np.pi, 6)
    a1, al1 = {"meet": (0.0, ang()), "parallel": (length(), 0.0), "offset": (length(), ang())}[arm]
    rows = [(al1, a1, u(), th[0]), (ang(), length(), u(), th[1]), (ang(), length(), u(), th[2]),
            (a4, 0.0, length(), th[3]), (a5, 0.0, 0.0, th[4]), (u(-3, 3), u(), u(), th[5])]
    joints = tuple(Joint(f"j{i + 1}", "revolute", alpha=al, a=a, d=d, theta=t,
                         limits=(-np.pi, np.pi)) for i, (al, a, d, t) in enumerate(rows))
    r = Robot("random_wrist", "dh", joints, base=random_pose(rng), tool=random_pose(rng))
    r = {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]
    q5s = [-th[4], wrap(np.pi - th[4])] if orthogonal else [-th[4]]
    return r, q5s


def robot_cases():
    cases = []
    for name in bundled_names():
        r = load_robot(name)
        fam, _ = classify(r, Screws.of(r))
        if fam is not None and fam.name == "spherical-wrist":
            cases.append((name, r, [0.0, np.pi]))
    rng = np.random.default_rng(20261122)
    for conv in ("dh", "mdh", "poe"):
        for arm in ("meet", "parallel", "offset"):
            for orthogonal in (True, False):
                r, q5s = random_wrist_arm(rng, arm, orthogonal, conv)
                cases.append((f"random-{conv}-{arm}-{'ortho' if orthogonal else 'twist'}",
                              r, q5s))
    return cases


CASES = robot_cases()
IDS = [c[0] for c in CASES]
BUNDLED = ["puma560", "kuka_kr16", "fanuc_lrmate200id", "abb_irb120", "abb_irb6640",
           "stanford_arm", "kuka_kr6_r700_sixx"]


def test_the_cases_cover_the_bundled_arms_and_are_aligned_where_claimed():
    names = {c[0] for c in CASES}
    assert set(BUNDLED) <= names
    rng = np.random.default_rng(0)
    for name, r, q5s in CASES:
        assert classify(r, Screws.of(r))[0].name == "spherical-wrist", name
        Q = sample_configurations(r, 5, rng)
        for q5 in q5s:
            Q[:, 4] = q5
            assert wrist_facts(r, Q)["aligned"].max() < 1e-12, (name, q5)
        Q[:, 4] = q5s[0] + 0.3
        assert wrist_facts(r, Q)["aligned"].min() > 1e-3


def configurations(r, q5s, n, seed, wrist=WRIST):
    """``n`` random configurations per aligned value of the wrist's middle joint, each
    with a well-conditioned placement: a list of (q, aligned q5)."""
    rng = np.random.default_rng(seed)
    out = []
    for q5 in q5s:
        k = 0
        for _ in range(20 * n):
            q = sample_configurations(r, 1, rng)[0]
            q[wrist[1]] = q5
            if away_from_arm_singularities(r, q, q5, wrist):
                out.append((q, q5))
                k += 1
                if k == n:
                    break
        assert k == n
    return out


# --- at the singularity ---------------------------------------------------------------

def check_singular_pose(r, q, T, sols, wrist=WRIST):
    """robot.ik's solutions ``sols`` (IKSolution list) of the pose ``T`` of ``q``
    (aligned wrist): every one reproduces T, every aligned one is a flagged
    representative, and one of them is on the generating continuum. Returns the array
    of joint values."""
    Qs = np.array([s.q for s in sols]).reshape(-1, r.dof)
    assert_reproduces(r, Qs, T)
    # the free joint is an outer wrist joint: joint 4 of a forward chain; on a reversed
    # chain the solver's joint 4 is the robot's joint 3 (the wrist joint next to the arm)
    outer = [r.joints[wrist[0]].name, r.joints[wrist[2]].name]
    F = wrist_facts(r, Qs, wrist)
    for s, aligned in zip(sols, F["aligned"]):
        if aligned > 1e-9:
            assert s.continuum is None and "free" not in s.branch
            continue
        free = [x for x in outer if f"({x} free)" in s.branch]
        assert s.singular and len(free) == 1, s.branch
        assert [r.joints[i].name for i in s.free] == free and free[0] in singularity_text(r, s)
        c = s.continuum
        assert c is not None and {c.i, c.j} == {wrist[0], wrist[2]}
        assert abs(wrap(s.q[c.i] + c.sign * s.q[c.j] - c.total)) < 1e-9
    hits = on_generating_continuum(r, Qs, q, wrist)
    assert hits, (r.name, q, Qs)
    for k in hits:
        c = sols[k].continuum
        assert c is not None
        # the generating configuration satisfies the reported relation as well
        assert abs(wrap(q[c.i] + c.sign * q[c.j] - c.total)) < 1e-6
    return Qs


@pytest.mark.parametrize("name,r,q5s", CASES, ids=IDS)
def test_wrist_singular_poses_give_the_generating_continuum(name, r, q5s):
    """q5 at an aligned value: robot.ik returns a flagged representative of the
    generating continuum (same q1-q3, axes 4 and 6 aligned the same way, the same
    q4 + sigma q6); ik_batch returns the same set, also containing it."""
    cases = configurations(r, q5s, 10, zlib.crc32(name.encode()))
    Q = np.array([c[0] for c in cases])
    T = r.fk(Q)
    B = r.ik_batch(T)
    for q, Tk, bq, bv in zip(Q, T, B.q, B.valid):
        sols = check_singular_pose(r, q, Tk, r.ik(Tk).solutions)
        bs = bq[bv]
        assert_reproduces(r, bs, Tk)
        assert same_set(r, bs, sols), (name, q, bs, sols)
        assert on_generating_continuum(r, bs, q)


@pytest.mark.parametrize("name,r,q5s", CASES, ids=IDS)
def test_wrist_singular_pose_count(name, r, q5s):
    """The count at an aligned wrist. The placements of joints 1-3 depend only on the wrist
    centre. So turning q5 away from the aligned value (q5 + 0.7: the wrist centre stays)
    gives the placements, from its 2 m isolated solutions. An orthogonal wrist turns
    axis 6 onto any direction, so at the aligned pose every placement is reachable too. A
    placement whose axis 4 (from the frames: it depends on joints 1-3 only) lies on the
    target's axis 6 gives one representative, the generating one among them, the others
    two solutions each. (On a PUMA only the generating placement is aligned: 7 solutions.
    A SCARA's axis 4 is vertical whatever the placement: 2.) A twisted wrist reaches only
    a cone of directions of axis 6: there the count is compared with robot.ik only.
    ik_batch gives the same count."""
    orthogonal = len(q5s) == 2
    for q, q5 in configurations(r, q5s, 8, zlib.crc32(name.encode()) + 1):
        T = r.fk(q)
        n_ik = len(r.ik(T).solutions)
        n_batch = int(r.ik_batch(T[None]).counts[0])
        assert n_batch == n_ik, (name, q)
        if orthogonal:
            p = q.copy()
            p[4] = q5 + 0.7
            generic = np.array([s.q for s in r.ik(r.fk(p)).solutions])
            places = []
            for g in generic:
                if not places or joint_diff(r, np.array(places), g)[:, :3].max(-1).min() > 1e-6:
                    places.append(g)
            assert len(generic) == 2 * len(places)
            z6 = chain_frames(r.chain, q[None])[0, 5, :3, 2]              # the target's axis 6
            z4 = chain_frames(r.chain, np.array(places))[:, 3, :3, 2]      # each placement's axis 4
            aligned = np.linalg.norm(np.cross(z4, z6), axis=-1) < 1e-9
            assert aligned.sum() >= 1
            assert n_ik == int(np.where(aligned, 1, 2).sum()), (name, q, n_ik, aligned)


def test_puma_issue_poses():
    """The report: PUMA 560, 20 random configurations with q5 = 0. Each gives 7 solutions
    (4 placements, the generating one a continuum's representative) from both solvers,
    and the generating configuration's continuum is among them."""
    r = load_robot("puma560")
    Q = sample_configurations(r, 20, np.random.default_rng(1))
    Q[:, 4] = 0
    T = r.fk(Q)
    B = r.ik_batch(T)
    assert B.counts.tolist() == [7] * 20
    for q, Tk, bq, bv in zip(Q, T, B.q, B.valid):
        sols = r.ik(Tk).solutions
        assert len(sols) == 7
        Qs = check_singular_pose(r, q, Tk, sols)
        assert sum(s.continuum is not None for s in sols) == 1
        assert same_set(r, bq[bv], Qs)


def test_representative_convention():
    """The representative has joint 4 at 0 and joint 6 carrying the whole combination;
    joint 5 is exactly the aligned value (0 or pi for a PUMA)."""
    r = load_robot("puma560")
    for q5 in (0.0, np.pi):
        q = np.array([0.4, -0.7, 0.3, 1.1, q5, -0.6])
        res = r.ik(r.fk(q))
        reps = [s for s in res.solutions if s.continuum is not None]
        assert len(reps) == 1
        s = reps[0]
        assert s.q[3] == 0.0 and abs(wrap(s.q[4] - q5)) < 1e-15
        sigma = 1.0 if q5 == 0.0 else -1.0
        assert abs(wrap(s.q[5] - sigma * (q[3] + sigma * q[5]))) < 1e-9
        assert s.continuum.sign == sigma


@pytest.mark.parametrize("q5", [3e-11, -3e-11, np.pi - 3e-11])
def test_within_the_tolerance_the_pose_counts_as_singular(q5):
    """The solvers treat axis 6 as on the line of axis 4 when the sine of the angle
    between them is at most 1e-10 (PARALLEL_WRIST_TOL). On a PUMA that sine is
    |sin q5|. So q5 = 3e-11 gives the representative (q5 snapped to 0 or pi), which
    misses the pose by about 3e-11 rad, inside the 1e-9 acceptance. At 3e-10 the
    solutions are isolated."""
    r = load_robot("puma560")
    q = np.array([0.4, -0.7, 0.3, 1.1, q5, -0.6])
    T = r.fk(q)
    sols = r.ik(T).solutions
    reps = [s for s in sols if s.continuum is not None]
    assert len(reps) == 1 and len(sols) == 7
    assert joint_diff(r, reps[0].q, q)[0, :3].max() < 1e-9
    assert abs(wrap(reps[0].q[4] - np.round(q5 / np.pi) * np.pi)) < 1e-15
    assert reps[0].orientation_error < 1e-10
    B = r.ik_batch(T[None])
    assert same_set(r, B.q[0][B.valid[0]], [s.q for s in sols])
    q[4] = 10 * q5 - 9 * np.round(q5 / np.pi) * np.pi             # 3e-10 from the aligned value
    T = r.fk(q)
    sols = r.ik(T).solutions
    assert len(sols) == 8 and all(s.continuum is None for s in sols)
    assert generating_found(r, [s.q for s in sols], q)
    B = r.ik_batch(T[None])
    assert generating_found(r, B.q[0][B.valid[0]], q)


# --- reversed chains ----------------------------------------------------------------------

def reversed_robot(r):
    """``r`` mounted tool-first: the PoE robot of :meth:`Screws.reversed` (joint k is
    joint n - 1 - k of ``r`` turned the other way). Its wrist is joints 1-3."""
    R = Screws.of(r).reversed()
    joints = tuple(Joint(f"j{i + 1}", "revolute" if R.revolute[i] else "prismatic",
                         axis=tuple(R.axis[i]), point=tuple(R.point[i]),
                         limits=(-2 * np.pi, 2 * np.pi) if R.revolute[i] else (-2.0, 2.0))
                   for i in range(6))
    return Robot(f"{r.name}_reversed", "poe", joints, M=R.M)


@pytest.mark.parametrize("name", ["puma560", "kuka_kr16", "stanford_arm"])
def test_reversed_chain_at_its_wrist_singularity(name):
    """reversed-spherical-wrist shares the solvers: the continuum at q2 = 0 or pi (its
    wrist is joints 1-3; joint 3, next to the arm, is the free one), found by both
    solvers; and q2 = 1e-9 or 1e-6 away the generating configuration with exact FK."""
    r = reversed_robot(load_robot(name))
    assert classify(r, Screws.of(r))[0].name == "reversed-spherical-wrist"
    n = 0
    for q, q2 in configurations(r, [0.0, np.pi], 6, 3, REVERSED_WRIST):
        T = r.fk(q)
        sols = check_singular_pose(r, q, T, r.ik(T).solutions, REVERSED_WRIST)
        B = r.ik_batch(T[None])
        assert_reproduces(r, B.q[0][B.valid[0]], T)
        assert same_set(r, B.q[0][B.valid[0]], sols)
        for eps in (1e-9, -1e-6):
            p = q.copy()
            p[1] = q2 + eps
            Tp = r.fk(p)
            res = r.ik(Tp)
            Qs = np.array([s.q for s in res.solutions]).reshape(-1, 6)
            assert_reproduces(r, Qs, Tp)
            assert all(s.continuum is None for s in res.solutions)
            assert generating_found(r, Qs, p, REVERSED_WRIST)
            B = r.ik_batch(Tp[None])
            assert_reproduces(r, B.q[0][B.valid[0]], Tp)
            assert generating_found(r, B.q[0][B.valid[0]], p, REVERSED_WRIST)
        n += 1
    assert n == 12


# --- next to the singularity ----------------------------------------------------------------

def wrist_tolerance(r, q, wrist=WRIST) -> float:
    """How well the outer wrist joints (4 and 6) are determined at ``q``, a configuration
    next to the wrist singularity (rad).

    Joint 4 is the angle between two vectors normal to axis 4 whose length is
    P = |z4 x z6| (from the frames: the sine of the angle between axes 4 and 6, about
    sin(beta) |eps| with beta the angle from axis 5 to axis 4). The rounding of the wrist's
    target rotation R_W turns that angle by about (error of R_W) / P, and joint 6 follows
    it (the combination q4 + sigma q6, joint 5 and the placement stay good to rounding).
    R_W's error is that of the placement joints: ~1e-16 rad for the closed-form arms, up to
    ~1e-13 for the generic offset shoulders (a resultant). With a margin of 100:
    1e-11 / P, and 1e-9 at least; at |eps| = 1e-9 that is about 1e-2, at 1e-6 1e-5."""
    return 1e-9 + 1e-11 / wrist_facts(r, q, wrist)["aligned"][0]


def generating_found(r, sols, q, wrist=WRIST) -> bool:
    """Is the generating configuration ``q`` (next to the aligned wrist) among ``sols``?
    The middle wrist joint within 1e-9, the placement within 1e-6, q4 + sigma q6 within
    1e-9 and joints 4 and 6 each within :func:`wrist_tolerance`."""
    sols = np.asarray(sols, float).reshape(-1, r.dof)
    if len(sols) == 0:
        return False
    arm = [j for j in range(r.dof) if j not in wrist]
    i, j, k = wrist
    d = joint_diff(r, sols, q)
    F = wrist_facts(r, np.vstack([q, sols]), wrist)
    ok = (d[:, arm].max(-1) < 1e-6) & (d[:, j] < 1e-9) & \
        (np.abs(wrap(F["total"][1:] - F["total"][0])) < 1e-9) & \
        (np.maximum(d[:, i], d[:, k]) < wrist_tolerance(r, q, wrist))
    return bool(ok.any())


@pytest.mark.parametrize("eps", [1e-9, -1e-9, 1e-6, -1e-6, 1e-3])
@pytest.mark.parametrize("name,r,q5s", CASES, ids=IDS)
def test_near_the_singularity_solutions_are_isolated_and_exact(name, r, q5s, eps):
    """q5 = aligned + eps: no continuum and no free joint, every solution FK-exact, the
    generating configuration found by robot.ik and by ik_batch, and the same set from
    both (up to the looser determination of joints 4 and 6, see
    :func:`wrist_tolerance`)."""
    cases = configurations(r, q5s, 6, zlib.crc32(name.encode()) + 2)
    Q = np.array([c[0] for c in cases])
    Q[:, 4] += eps
    T = r.fk(Q)
    B = r.ik_batch(T)
    for q, Tk, bq, bv in zip(Q, T, B.q, B.valid):
        res = r.ik(Tk)
        sols = np.array([s.q for s in res.solutions]).reshape(-1, r.dof)
        assert_reproduces(r, sols, Tk)
        assert all(s.continuum is None and "free" not in s.branch for s in res.solutions)
        assert generating_found(r, sols, q), (name, q, sols)
        bs = bq[bv]
        assert_reproduces(r, bs, Tk)
        assert generating_found(r, bs, q), (name, q, bs)
        assert same_set(r, bs, sols, wrist_tolerance(r, q))


def test_wrist_line_on_axis_1_relates_three_joints():
    """kawasaki_rs007n standing straight up with q5 = 0 (the hunt's pose q = [135.2 deg, 0,
    180 deg, 180 deg, 0, -77.4 deg]): axes 1, 4 and 6 are one line, so only JT1 + JT4 + JT6
    is fixed. The reported relation holds for the solution and for the configuration the
    pose came from, whatever its JT1 and JT6 (it said JT1 free and JT4 + JT6 = total)."""
    robot = load_robot("kawasaki_rs007n")
    rng = np.random.default_rng(17)
    for a, b in rng.uniform(-np.pi, np.pi, (6, 2)):
        q0 = np.array([a, 0.0, np.pi, np.pi, 0.0, b])
        res = robot.ik(robot.fk(q0))
        assert res.solutions
        for s in res.solutions:
            c = s.continuum
            assert c is not None and set(c.joints) == {0, 3, 5}, c
            total = lambda q: sum(sg * q[j] for j, sg in zip(c.joints, c.signs))  # noqa: E731
            assert abs(wrap(total(s.q) - c.total)) < 1e-9
            assert abs(wrap(total(q0) - c.total)) < 1e-9


@pytest.mark.parametrize("alpha4", [-30.0, -60.0, -120.0])
def test_a_free_placement_joint_turns_a_wrist_that_reaches_few_directions(alpha4):
    """A Stanford arm whose wrist twist alpha4 is not a right angle, at d3 = 0: the wrist
    centre lies on axis 2, so q2 is free for the position, but a wrist with twists of
    alpha4 and 90 deg points its last axis only within a band of directions, and the
    representative q2 = 0 left 12 of 30 FK poses with no solution (an independent campaign).
    Every pose is reached (FK round trip), q2 flagged free; single and batch agree."""
    P = np.pi
    rows = [(-P / 2, 0.412, 0.0, "revolute"), (P / 2, 0.154, 0.0, "revolute"),
            (0.0, 0.0, -P / 2, "prismatic"), (np.radians(alpha4), 0.0, 0.0, "revolute"),
            (P / 2, 0.0, 0.0, "revolute"), (0.0, 0.263, 0.0, "revolute")]
    r = Robot(name="stanford_twisted", convention="dh", base=np.eye(4), tool=np.eye(4),
              joints=tuple(Joint(f"j{i + 1}", kind, alpha=al, a=0.0, d=d, theta=th,
                                 limits=(-1.0, 1.0) if kind == "prismatic" else (-P, P))
                           for i, (al, d, th, kind) in enumerate(rows)))
    Q = np.random.default_rng(21).uniform(-3, 3, (30, 6))
    Q[:, 2] = 0.0
    T = r.fk(Q)
    solved = r.ik_batch(T)
    for i in range(len(Q)):
        res = r.ik(T[i])
        S = np.array([s.q for s in res.solutions])
        assert len(S), (np.degrees(Q[i]), res.reason)
        assert np.abs(r.fk(S) - T[i]).max() < 1e-9
        assert all(1 in s.free for s in res.solutions)
        got = np.sort(np.round(solved.q[i][solved.valid[i]], 9), axis=0)
        assert np.array_equal(got, np.sort(np.round(S, 9), axis=0))
        # the generating joints are on the continuum of an answer: q2 turned there (either
        # way round: the wrist's band may hold two arcs of q2, one per representative)
        assert any(_follow_joint(r, T[i], s.q, 1, Q[i][1], way, (3, 4, 5))
                   for s in res.solutions for way in (1, -1)), np.degrees(Q[i])


def _follow_joint(r, T, q, j, value, way, others) -> bool:
    """Joint ``j`` of ``q`` turned to ``value`` (``way`` round), the joints ``others`` kept
    on the pose ``T`` (:func:`randrobots.follow_joint`)."""
    def miss(x):
        F = r.fk(x)
        return np.concatenate([F[:3, 3] - T[:3, 3], (F[:3, :3] - T[:3, :3]).ravel()])
    return follow_joint(miss, q, j, value, way, others) is not None


def test_wrist_singular_at_an_arm_singularity_gives_the_continuum():
    """A spherical-wrist arm whose joints 1-3 place the wrist centre by subproblem 5, at
    q5 = 0 with the placement at a double root (an arm singularity; an independent
    campaign's pose): the double root was found to sqrt(eps) only, axis 6 then read 3.6e-8
    rad off axis 4 and two isolated wrist solutions came out, not the continuum. Now the
    generating placement's representative: joint 4 free, q4 - q6 the generating total."""
    P = np.pi
    rows = [(0.48233694057320614, 0.4365878773445606, 0.0),
            (-P / 2, -0.4125464212891483, 0.13797640616951484), (-P / 2, 0.0, 0.0),
            (-P / 2, 0.0, -0.18339697300707336), (-P / 2, 0.0, 0.0),
            (1.7016113894523996, -0.47358845888522355, 0.39486790181357395)]
    r = Robot(name="sw_arm_singular", convention="dh", base=np.eye(4), tool=np.eye(4),
              joints=tuple(Joint(f"j{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0,
                                 limits=(-2 * P, 2 * P))
                           for i, (al, a, d) in enumerate(rows)))
    q = np.array([0.310383731632498, 1.5793338880041254, 0.48624519954598006,
                  -1.9574960440877442, 0.0, -0.2572058303415634])
    T = r.fk(q)
    res = r.ik(T)
    assert_reproduces(r, [s.q for s in res.solutions], T)
    reps = [s for s in res.solutions if s.continuum is not None]
    assert len(reps) == 1 and 3 in reps[0].free
    c = reps[0].continuum
    assert abs(wrap(q[c.i] + c.sign * q[c.j] - c.total)) < 1e-9
    assert joint_diff(r, reps[0].q, q)[0, :3].max() < 1e-9
    B = r.ik_batch(T[None])
    assert same_set(r, B.q[0][B.valid[0]], [s.q for s in res.solutions])


#: an R-R-P arm with a twisted spherical wrist (the random-robot campaign's sw6p9), whose
#: axes 4 and 6 line up at q5 = -3.1321 rad, and joints there at which the slide's placement
#: is a double root: from its one copy the wrist came out aligned (joint 4 free), from the
#: other it did not, two more representatives of the one continuum, no free joint named
DOUBLE_PLACEMENT_ARM = """name: sw6p9
convention: dh
units: {length: m, angle: rad}
joints:
  - {name: j1, type: revolute, alpha: 2.195243305361338, a: -0.065019655279264954, d: 0.77513463222267232, theta: -1.3024508712180509}
  - {name: j2, type: revolute, alpha: -1.3938500337545705, a: 0, d: -0.3720398255573279, theta: 1.4747797685843143}
  - {name: j3, type: prismatic, alpha: 1.5707963267948966, a: 0.02729486238179726, d: 0.54261659036220733, theta: -2.3585201363837065}
  - {name: j4, type: revolute, alpha: 1.5707963267948966, a: 0, d: -0.082607005865384969, theta: 1.3469431321770085}
  - {name: j5, type: revolute, alpha: 1.5707963267948966, a: 0, d: 0, theta: 3.1321220184893042}
  - {name: j6, type: revolute, alpha: -0.75466489103736745, a: 0, d: 0, theta: -1.3486985576508823}
base: [[-0.59243738639974985, -0.80460523762468927, 0.040352878246175228, 0.18144413873207543], [-0.50745261778987949, 0.41160758505029915, 0.75701455509604254, -0.058129758417302169], [-0.62570742675313662, 0.42800655078629096, -0.6521507560296087, 0.20147082094170943], [0, 0, 0, 1]]
tool: [[-0.33848975698645822, -0.021073125808461435, 0.9407340792083112, 0.13381218952081531], [-0.93694992764628626, -0.084767419676043732, -0.33902701609913705, -0.16643355378789887], [0.086887959458531838, -0.99617789973986381, 0.0089484395849941389, 0.27659825895935414], [0, 0, 0, 1]]
"""
DOUBLE_PLACEMENT_Q = [-0.0025410553114313394, 2.3681858491005414, -1.0613474861013623,
                      2.685922449125057, -3.132122018489304, -0.22066813790976259]


def test_a_wrist_continuum_is_reported_once_where_its_placement_is_a_double_root():
    """Where two copies of one placement give the aligned wrist, the continuum (joint 4
    free, q4 - q6 fixed) comes once: a solution with the same placement whose q4 - q6 is the
    continuum's is a point of it, though its q6 differs from the representative's (two were
    returned besides the representative, neither naming a free joint)."""
    from kincalc import parse_robot_text
    r = parse_robot_text(DOUBLE_PLACEMENT_ARM)
    q0 = np.array(DOUBLE_PLACEMENT_Q)
    T = r.fk(q0)
    sols = r.ik(T).solutions
    Q = np.array([s.q for s in sols])
    assert_reproduces(r, Q, T)
    assert wrist_facts(r, q0)["aligned"][0] < 1e-9
    on = on_generating_continuum(r, Q, q0)
    assert len(on) == 1 and sols[on[0]].free == (3,), [(s.q, s.branch) for s in sols]
    same_arm = joint_diff(r, Q, q0)[:, :3].max(-1) < 1e-6
    assert np.count_nonzero(same_arm) == 1
