"""Three-parallel (UR-type) arms at their wrist singularity.

When axis 6 is parallel to axes 2-4 (q5 = 0 or 180 deg on a UR arm), joints 2, 3, 4
and 6 all turn about parallel axes. With R5 k6 = sigma h (h the direction of axis 2,
sigma = +-1), the orientation is

    R1 R_h(q2 + s3 q3 + s4 q4) R5 R(k6, q6) = R1 R_h(q2 + s3 q3 + s4 q4 + sigma q6) R5,

where s3, s4 = +-1 give the directions of axes 3 and 4 along h. So the pose fixes q1,
q5 and the sum q2 + s3 q3 + s4 q4 + sigma q6 (mod 2 pi). Turning q6 swings axis 4
about axis 6, and the planar elbow (joints 2, 3) follows as long as it can reach axis 4.
The result is a one-parameter continuum. robot.ik must return representatives of it:
flagged singular, with joint 6 named free and the fixed sum reported. ik_batch must
return the same set. Every returned configuration must reproduce the pose.

Every check is made from the forward kinematics and the joint frames
(kincalc.fk.chain_frames), never from the solvers' own screws. This covers: the
continuum invariant above, and which connected piece of the continuum a configuration
lies on. If the whole circle of q6 is reachable, the two elbows are separate loops and
the elbow's bend sign is fixed along each. If two arcs are reachable, the elbows join at
each arc's end and the side of axis 4 relative to the line from axis 2 to axis 6 is fixed
along each arc.
"""

import zlib

import numpy as np
import pytest
from randrobots import random_pose

from kincalc import load_robot
from kincalc.conventions import dh_to_mdh, to_poe
from kincalc.fk import chain_frames
from kincalc.ik.families import classify
from kincalc.ik.screws import Screws
from kincalc.spatial import wrap
from kincalc.model import Joint, Robot
from kincalc.analysis.results import Units
from kincalc.analysis.words import continuum_text, singularity_text

UR = ["ur5", "ur10", "ur10e", "ur3", "ur5e", "ur16e", "ur20", "ur5_mdh", "ur5_poe"]


# --- independent geometry (joint frames) ------------------------------------------

def geometry(r, Q):
    """Facts about configurations ``Q (k, 6)`` of a three-parallel arm, taken from its
    joint frames (z is a joint's axis, the origin a point on it; world frame, m).

    Returns arrays ``(k,)``: ``parallel`` (the sine of the angle between axes 6 and 2),
    ``total`` (q2 + s3 q3 + s4 q4 + sigma q6, rad), and, in the plane normal to h,
    ``l2`` and ``l3`` (distances from axis 2 to axis 3 and from axis 3 to axis 4), ``A``
    (from axis 2 to axis 6), ``B`` (from axis 6 to axis 4), ``bend`` (the elbow's turn)
    and ``side`` (which side of the line from axis 2 to axis 6 axis 4 lies on).
    """
    Q = np.atleast_2d(np.asarray(Q, float))
    F = chain_frames(r.chain, Q)
    z, o = F[:, :, :3, 2], F[:, :, :3, 3]
    h = z[:, 1]

    def dot(a, b):
        return (a * b).sum(-1)

    def sign(x):
        return np.where(x > 0, 1.0, -1.0)

    def flat(x):
        return x - h * dot(x, h)[:, None]

    def turn(a, b):
        return dot(np.cross(a, b), h)

    s3, s4, sigma = sign(dot(z[:, 2], h)), sign(dot(z[:, 3], h)), sign(dot(z[:, 5], h))
    O, A3, A4, W = (flat(o[:, i]) for i in (1, 2, 3, 5))
    n = lambda v: np.linalg.norm(v, axis=-1)  # noqa: E731
    return dict(parallel=n(np.cross(z[:, 5], h)),
                total=Q[:, 1] + s3 * Q[:, 2] + s4 * Q[:, 3] + sigma * Q[:, 5],
                l2=n(A3 - O), l3=n(A4 - A3), A=n(W - O), B=n(A4 - W),
                bend=turn(A3 - O, A4 - A3), side=turn(W - O, A4 - W))


def on_continuum(r, sols, q, tol=1e-7) -> bool:
    """Does one of ``sols (m, 6)`` lie on the same connected piece of the continuum as the
    generating configuration ``q``? That requires the same q1 and q5, the same sum, and the
    same bend sign (whole circle reachable) or the same side (two arcs)."""
    sols = np.asarray(sols, float).reshape(-1, 6)
    if len(sols) == 0:
        return False
    G = geometry(r, np.vstack([q, sols]))
    ok = (np.abs(wrap(sols[:, 0] - q[0])) < tol) & (np.abs(wrap(sols[:, 4] - q[4])) < tol) & \
        (np.abs(wrap(G["total"][1:] - G["total"][0])) < tol)
    lo, hi = abs(G["l2"][0] - G["l3"][0]), G["l2"][0] + G["l3"][0]
    A, B = G["A"][0], G["B"][0]
    m = 1e-6 * max(1.0, r.characteristic_length)
    if abs(A - B) >= lo + m and A + B <= hi - m and abs(G["bend"][0]) > m * m:
        ok &= np.sign(G["bend"][1:]) == np.sign(G["bend"][0])
    if abs(A - B) <= lo - m and A + B >= hi + m and abs(G["side"][0]) > m * m:
        ok &= np.sign(G["side"][1:]) == np.sign(G["side"][0])
    return bool(ok.any())


def assert_reproduces(r, Q, T):
    Q = np.asarray(Q, float).reshape(-1, r.dof)
    assert np.all(np.isfinite(Q))
    if len(Q) == 0:
        return
    Tq = r.fk(Q)
    L = max(1.0, r.characteristic_length)
    assert np.abs(Tq[:, :3, 3] - T[:3, 3]).max() <= 1e-9 * L
    assert np.abs(Tq[:, :3, :3] - T[:3, :3]).max() <= 1e-9


def same_set(A, B, tol=1e-7) -> bool:
    A, B = np.asarray(A).reshape(-1, 6), np.asarray(B).reshape(-1, 6)
    return len(A) == len(B) and all(np.abs(wrap(B - a)).max(-1).min() < tol for a in A)


def singular_q5(r) -> list:
    """The values among q5 = 0 and pi at which axis 6 is parallel to axis 2, found from
    the joint frames at random configurations (the angle depends on q5 alone)."""
    Q = np.random.default_rng(0).uniform(-np.pi, np.pi, (5, 6))
    out = []
    for q5 in (0.0, np.pi):
        Q[:, 4] = q5
        if geometry(r, Q)["parallel"].max() < 1e-12:
            out.append(q5)
    return out


def away_from_other_singularities(r, q, q5s) -> bool:
    """Is ``q`` clear of the arm's other singularities? Two checks: the elbow must be
    clearly bent, since a stretched or folded elbow is a double root good only to
    sqrt(eps). And the Jacobian must be well conditioned once the wrist is turned a
    quarter turn away (q5 = q5s + pi/2), which keeps the wrist point off the shoulder's
    double root of joint 1."""
    G = geometry(r, q)
    if abs(G["bend"][0]) <= 0.05 * G["l2"][0] * G["l3"][0]:
        return False
    p = np.array(q, float)
    p[4] = q5s + np.pi / 2
    J = r.jacobian(p[None])[0]
    J[:3] /= max(1.0, r.characteristic_length)
    return np.linalg.svd(J, compute_uv=False)[-1] > 1e-3


# --- robots -------------------------------------------------------------------------

def random_singular_arm(rng, ur_like: bool, convention: str, skew: bool = False):
    """A random three-parallel arm (DH rows as in test_ik.random_family_robot: axes 2-4
    parallel, axes 5 and 6 meeting, or with ``skew`` a link between them) whose axis 6
    turns parallel to axes 2-4 at q5 = 0. Twist alpha5 = -alpha4 (mod pi) makes that
    happen. With ``ur_like`` both twists are +-90 deg and it happens at q5 = pi as well.
    Random lengths, offsets, base and tool."""
    u = lambda lo=-0.5, hi=0.5: rng.uniform(lo, hi)  # noqa: E731
    # twists well off 0 and 180 deg: near-parallel neighbouring axes make a near-singular arm
    ang = lambda: rng.uniform(0.6, 2.5) * rng.choice([-1, 1])  # noqa: E731
    if ur_like:
        a4, a5 = rng.choice([-1, 1]) * np.pi / 2, rng.choice([-1, 1]) * np.pi / 2
    else:
        a4 = ang()
        a5 = rng.choice([-a4, np.pi - a4])
    link = lambda: rng.uniform(0.1, 0.5) * rng.choice([-1, 1])  # noqa: E731 (the elbow's links)
    rows = [(ang(), u(), u(), u(-np.pi, np.pi)), (0.0, link(), u(), u(-np.pi, np.pi)),
            (0.0, link(), u(), u(-np.pi, np.pi)), (a4, u(), u(), u(-np.pi, np.pi)),
            (a5, link() if skew else 0.0, u(), 0.0), (u(-3, 3), u(), u(), u(-np.pi, np.pi))]
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=th)
                   for i, (al, a, d, th) in enumerate(rows))
    r = Robot("random_ur", "dh", joints, base=random_pose(rng), tool=random_pose(rng))
    return {"dh": r, "mdh": dh_to_mdh(r), "poe": to_poe(r)}[convention]


def robot_cases():
    cases = [(name, load_robot(name)) for name in UR]
    rng = np.random.default_rng(2024)
    for conv in ("dh", "mdh", "poe"):
        for ur_like in (True, False):
            for k in range(2):
                cases.append((f"random-{conv}-{'ur' if ur_like else 'twist'}-{k}",
                              random_singular_arm(rng, ur_like, conv)))
    rng = np.random.default_rng(2026)      # axes 5 and 6 skew (three-parallel-offset)
    for conv in ("dh", "mdh", "poe"):
        for ur_like in (True, False):
            for k in range(2):
                cases.append((f"random-{conv}-{'ur' if ur_like else 'twist'}-skew-{k}",
                              random_singular_arm(rng, ur_like, conv, skew=True)))
    return cases


CASES = robot_cases()
IDS = [c[0] for c in CASES]


# --- at the singularity -------------------------------------------------------------

@pytest.mark.parametrize("name,r", CASES, ids=IDS)
def test_wrist_singular_poses_give_the_continuum(name, r):
    fam, _ = classify(r, Screws.of(r))
    assert fam.name == ("three-parallel-offset" if "-skew-" in name else "three-parallel")
    q5s = singular_q5(r)
    assert q5s == ([0.0, np.pi] if name in UR or "-ur-" in name else [0.0]), q5s
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    free_name = r.joints[5].name
    Q = []
    for q5 in q5s:
        for _ in range(20):
            q = rng.uniform(-np.pi, np.pi, 6)
            q[4] = q5
            Q.append(q)
    Q = np.array(Q)
    T = r.fk(Q)
    B = r.ik_batch(T)                      # all poses at once, singular or not per branch
    for q, Tk, bq, bv in zip(Q, T, B.q, B.valid):
        res = r.ik(Tk)
        sols = np.array([s.q for s in res.solutions]).reshape(-1, 6)
        assert len(sols) >= 1 and res.reachable, (name, q)
        assert_reproduces(r, sols, Tk)
        G = geometry(r, sols)
        on_branch = 0
        for s, par in zip(res.solutions, G["parallel"]):
            if par > 1e-12:
                # isolated solutions (another branch of joint 1 near the aligned wrist)
                assert s.continuum is None and (par > 1e-9 or s.singular)
                continue
            # a configuration with axis 6 parallel to axis 2: a representative
            on_branch += 1
            assert s.singular and f"({free_name} free)" in s.branch, s.branch
            assert free_name in [r.joints[i].name for i in s.free]
            assert free_name in singularity_text(r, s)
            c = s.continuum
            assert c is not None and c.free == 5 and set(c.joints) == {1, 2, 3, 5}
            rel = lambda x: wrap(sum(sg * x[j] for j, sg in zip(c.joints, c.signs)) - c.total)  # noqa: E731
            assert abs(rel(s.q)) < 1e-9
            if abs(wrap(s.q[0] - q[0])) < 1e-9:          # the generating branch: it too
                assert abs(rel(q)) < 1e-9
            assert " = " in continuum_text(c, [j.name for j in r.joints], Units("deg"))
        assert on_branch >= 1, (name, q)
        assert on_continuum(r, sols, q), (name, q, sols)
        # the batch: the same representatives, reproducing the pose
        bs = bq[bv]
        assert_reproduces(r, bs, Tk)
        assert same_set(bs, sols), (name, q, bs, sols)
        assert on_continuum(r, bs, q)


def test_ur5_at_q5_zero_and_pi_gives_both_shoulders_and_elbows():
    """The pose of the issue: the generating shoulder gives two representatives, one for
    each elbow (q6 = 0 reachable there), and the other shoulder gives its four isolated
    solutions."""
    r = load_robot("ur5")
    for q5, sigma in ((0.0, 1), (np.pi, -1)):
        q = np.array([0.3, -1.0, 1.2, -0.5, q5, 0.7])
        T = r.fk(q)
        res = r.ik(T)
        assert len(res.solutions) == 6
        reps = [s for s in res.solutions if s.continuum is not None]
        assert len(reps) == 2
        assert {s.branch.split(" wrist")[0] for s in reps} == \
            {"shoulder left elbow up", "shoulder left elbow down"}
        for s in reps:
            assert s.q[5] == 0.0 and abs(wrap(s.q[0] - 0.3)) < 1e-12
            assert abs(wrap(s.q[4] - q5)) < 1e-12
            # q2 + q3 + q4 + sigma q6 is the generating configuration's
            assert abs(wrap(s.q[1] + s.q[2] + s.q[3] + sigma * s.q[5] - (-0.3 + sigma * 0.7))) < 1e-12
        assert_reproduces(r, [s.q for s in res.solutions], T)
        B = r.ik_batch(T[None])
        assert B.counts[0] == 6 and same_set(B.q[0][B.valid[0]], [s.q for s in res.solutions])


@pytest.mark.parametrize("name,r", CASES[:1] + CASES[len(UR):], ids=IDS[:1] + IDS[len(UR):])
def test_generated_with_q6_zero_comes_back_exactly(name, r):
    """The convention: q6 = 0 wherever the elbow reaches it. So a configuration generated
    with q6 = 0 at the singularity is returned itself, by robot.ik and by the batch."""
    rng = np.random.default_rng(7)
    n = 0
    for q5 in singular_q5(r):
        for _ in range(30):
            q = rng.uniform(-np.pi, np.pi, 6)
            q[4], q[5] = q5, 0.0
            if not away_from_other_singularities(r, q, q5):
                continue
            T = r.fk(q)
            sols = [s.q for s in r.ik(T).solutions]
            assert np.abs(wrap(np.array(sols) - q)).max(-1).min() < 1e-9, (name, q)
            B = r.ik_batch(T[None])
            assert np.abs(wrap(B.q[0][B.valid[0]] - q)).max(-1).min() < 1e-9
            n += 1
    assert n >= 10


@pytest.mark.parametrize("name", UR)
def test_home_pose_returns_home(name):
    r = load_robot(name)
    T = r.fk(r.home)
    B = r.ik_batch(T[None])
    for sols in ([s.q for s in r.ik(T).solutions], B.q[0][B.valid[0]]):
        # the home pose is also a stretched elbow: a double root, good to sqrt(eps)
        assert np.abs(wrap(np.array(sols) - r.home)).max(-1).min() < 1e-7


@pytest.mark.parametrize("name,r", CASES, ids=IDS)
def test_representatives_off_zero_sit_mid_reach(name, r):
    """Where q6 = 0 is out of the elbow's reach, the representative puts axis 4 at the
    middle of the elbow's reach, (|l2 - l3| + l2 + l3) / 2 from axis 2. When the circle
    that axis 4 sweeps about axis 6 does not get there, axis 4 goes to the circle's
    nearest point, distance |A - B| or A + B."""
    rng = np.random.default_rng(3)
    seen = 0
    for q5 in singular_q5(r):
        for _ in range(30):
            q = rng.uniform(-np.pi, np.pi, 6)
            q[4] = q5
            for s in r.ik(r.fk(q)).solutions:
                if s.continuum is None or s.q[5] == 0.0:
                    continue
                G = {k: v[0] for k, v in geometry(r, s.q).items()}
                rho = np.linalg.norm(_axis4_from_axis2(r, s.q))
                mid = 0.5 * (abs(G["l2"] - G["l3"]) + G["l2"] + G["l3"])
                tol = 1e-9 * max(1.0, r.characteristic_length)
                assert min(abs(rho - mid), abs(rho - abs(G["A"] - G["B"])),
                           abs(rho - G["A"] - G["B"])) < tol, (name, s.q)
                seen += 1
    assert seen >= 1, name


def _axis4_from_axis2(r, q):
    F = chain_frames(r.chain, np.asarray(q, float)[None])[0]
    h = F[1, :3, 2]
    d = F[3, :3, 3] - F[1, :3, 3]
    return d - h * (d @ h)


# --- structure variants ---------------------------------------------------------------

def flipped_ur5(flip):
    """UR5 as screws with the axes of joints ``flip`` reversed (their angles then count the
    other way): axes 2-4 no longer all point the same way."""
    S = Screws.of(load_robot("ur5"))
    sg = np.ones(6)
    sg[list(flip)] = -1
    joints = tuple(Joint(f"j{i + 1}", "revolute", axis=tuple(sg[i] * S.axis[i]),
                         point=tuple(S.point[i]), limits=(-2 * np.pi, 2 * np.pi)) for i in range(6))
    return Robot("ur5_flipped", "poe", joints, M=S.M)


@pytest.mark.parametrize("flip", [(2,), (3,), (1,), (1, 5)])
def test_axes_pointing_against_each_other(flip):
    """Axes 2-4 parallel but not all the same way: angles about h add with signs (round
    trip at generic poses, and the continuum at the singularity)."""
    r = flipped_ur5(flip)
    assert classify(r, Screws.of(r))[0].name == "three-parallel"
    rng = np.random.default_rng(1)
    for k in range(30):
        q = rng.uniform(-3, 3, 6)
        if k % 2:
            q[4] = [0.0, np.pi][k % 4 // 2]
        T = r.fk(q)
        sols = [s.q for s in r.ik(T).solutions]
        assert_reproduces(r, sols, T)
        bs = r.ik_batch(T[None])
        bs = bs.q[0][bs.valid[0]]
        assert_reproduces(r, bs, T)
        assert same_set(bs, sols)
        if k % 2:
            assert on_continuum(r, sols, q)
        else:
            assert np.abs(wrap(np.array(sols) - q)).max(-1).min() < 1e-6


def test_reversed_ur_arm_at_its_wrist_singularity():
    """A UR arm mounted tool-first (reversed-three-parallel): its joint 2 plays q5, and
    the continuum's relation maps back with the joints' order and angle signs reversed."""
    R = Screws.of(load_robot("ur5")).reversed()
    joints = tuple(Joint(f"j{i + 1}", "revolute", axis=tuple(R.axis[i]), point=tuple(R.point[i]),
                         limits=(-2 * np.pi, 2 * np.pi)) for i in range(6))
    r = Robot("ur5_reversed", "poe", joints, M=R.M)
    assert classify(r, Screws.of(r))[0].name == "reversed-three-parallel"
    rng = np.random.default_rng(8)
    for k in range(20):
        q = rng.uniform(-3, 3, 6)
        q[1] = [0.0, np.pi][k % 2]
        T = r.fk(q)
        res = r.ik(T)
        assert_reproduces(r, [s.q for s in res.solutions], T)
        reps = [s for s in res.solutions if s.continuum is not None]
        assert reps and all(s.singular and "(j1 free)" in s.branch for s in reps)
        hit = False
        for s in reps:
            c = s.continuum
            assert c.free == 0 and set(c.joints) == {0, 2, 3, 4}
            rel = lambda x: wrap(sum(sg * x[j] for j, sg in zip(c.joints, c.signs)) - c.total)  # noqa: E731
            assert abs(rel(s.q)) < 1e-9
            hit |= abs(wrap(s.q[5] - q[5])) < 1e-9 and abs(wrap(s.q[1] - q[1])) < 1e-9 and \
                abs(rel(q)) < 1e-9
        assert hit
        B = r.ik_batch(T[None])
        assert_reproduces(r, B.q[0][B.valid[0]], T)
        assert same_set(B.q[0][B.valid[0]], [s.q for s in res.solutions])


# --- next to the singularity: isolated solutions, found as by any round trip ----------

@pytest.mark.parametrize("eps", [1e-6, -1e-6, 1e-3])
@pytest.mark.parametrize("name,r", CASES, ids=IDS)
def test_near_the_singularity_solutions_are_isolated_and_exact(name, r, eps):
    """q5 a little off the aligned value: no continuum, no free joint, every solution
    FK-exact, the generating configuration found by robot.ik and by the batch alike, and
    the same set from both (configurations near another singularity are left out: a
    stretched elbow has its own double root)."""
    rng = np.random.default_rng(5)
    n = 0
    for q5 in singular_q5(r):
        for _ in range(15):
            q = rng.uniform(-np.pi, np.pi, 6)
            if not away_from_other_singularities(r, q, q5):
                continue
            q[4] = q5 + eps
            T = r.fk(q)
            res = r.ik(T)
            sols = np.array([s.q for s in res.solutions]).reshape(-1, 6)
            assert_reproduces(r, sols, T)
            assert all(s.continuum is None and "free" not in s.branch for s in res.solutions)
            tol = 1e-6
            assert np.abs(wrap(sols - q)).max(-1).min() < tol, (name, q)
            B = r.ik_batch(T[None])
            bs = B.q[0][B.valid[0]]
            assert_reproduces(r, bs, T)
            assert np.abs(wrap(bs - q)).max(-1).min() < tol
            assert same_set(bs, sols, 1e-6)
            n += 1
    assert n >= 8


@pytest.mark.parametrize("name", UR)
def test_ur_at_q5_1e9_solutions_are_exact(name):
    """1e-9 rad off: still isolated solutions, FK-exact (they once came back as
    representatives that missed the pose by ~1e-9, or were dropped); joints 2-6 are only
    determined to ~1e-16 / q5 there, so the generating configuration is matched loosely."""
    r = load_robot(name)
    rng = np.random.default_rng(6)
    for k in range(15):
        q = rng.uniform(-np.pi, np.pi, 6)
        q[4] = [1e-9, np.pi - 1e-9][k % 2]
        T = r.fk(q)
        res = r.ik(T)
        sols = np.array([s.q for s in res.solutions]).reshape(-1, 6)
        assert_reproduces(r, sols, T)
        assert all(s.continuum is None for s in res.solutions)
        assert np.abs(wrap(sols - q)).max(-1).min() < 1e-4
        B = r.ik_batch(T[None])
        assert_reproduces(r, B.q[0][B.valid[0]], T)
        assert B.counts[0] == len(sols)


@pytest.mark.parametrize("digits", [None, 12])
def test_wrist_singular_with_the_elbow_at_its_edge_twelve_digit_pose(digits):
    """A UR-type arm at q5 = 180 deg with the elbow folded, so that joint 6's arc of the
    continuum is a single point (axis 4 at the edge of the elbow's reach), the pose rounded
    to 12 digits (found by an independent campaign): the rounding put that point a hair
    out of reach and the pose had no solution. Within the acceptance of the edge, the
    candidate is judged by the engine: one solution, q6 free, reproducing the pose."""
    from kincalc.model import Joint, Robot
    P = np.pi
    rows = [(P / 2, 0.0, 0.4017790308070126), (P, 0.31827688929785036, 0.08354163989106156),
            (0.0, -0.2422972628959903, 0.0), (P / 2, 0.0, 0.34958525607934365),
            (-P / 2, 0.0, 0.08555733239184804), (0.0, 0.0, -0.14947535859548233)]
    robot = Robot(name="ur_like", convention="dh", base=np.eye(4), tool=np.eye(4), joints=tuple(
        Joint(f"q{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0, limits=(-2 * P, 2 * P))
        for i, (al, a, d) in enumerate(rows)))
    assert classify(robot, Screws.of(robot))[0].name == "three-parallel"
    T = robot.fk(np.radians([0.0, 180.0, 180.0, -90.0, 180.0, 180.0]))
    T = T if digits is None else np.round(T, digits)
    res = robot.ik(T)
    assert res.solutions, res.reason
    L = robot.characteristic_length
    for s in res.solutions:
        Tq = robot.fk(s.q)
        assert np.linalg.norm(Tq[:3, 3] - T[:3, 3]) <= 1e-9 * L
        assert np.abs(Tq[:3, :3] - T[:3, :3]).max() <= 4e-9
    assert all(5 in s.free for s in res.solutions)                 # q6 free


def test_reversed_arm_with_the_wrist_point_on_axis_1_turns_it_into_the_wrists_reach():
    """A reversed three-parallel arm (joint 6 of the robot is the chain's joint 1) whose
    twists at the wrist are not right angles, at a pose whose wrist point lies on the
    chain's axis 1 (an independent campaign's): joint 1 is free for the position, but the
    wrist points axis 6 only within a band about h, and the representative 0 left it out
    of that band (no solution). The value that puts it in the middle of the band is taken
    on each of the band's arcs (joints 2-4 place axis 4 from one of them only): the pose
    is reached, the robot's joint 6 flagged free; single and batch agree."""
    P = np.pi
    rows = [(-2.7638082654398133, 0.0, 0.38277191286692996),
            (P / 2, -0.3159272366151201, 0.1737458785652708),
            (0.0, -0.15952280234596386, 0.0), (0.0, 0.21648184451545976, 0.0),
            (P / 2, 0.0, 0.0), (-2.595585210332154, 0.24480889830786934, 0.4602248988966617)]
    robot = Robot(name="rev_ur", convention="dh", base=np.eye(4), tool=np.eye(4), joints=tuple(
        Joint(f"j{i + 1}", "revolute", alpha=al, a=a, d=d, theta=0.0, limits=(-2 * P, 2 * P))
        for i, (al, a, d) in enumerate(rows)))
    fam = classify(robot, Screws.of(robot))[0]
    assert fam.name == "reversed-three-parallel"
    q = np.array([-2.0817692676781583, -2.3956210983562753, 1.2430587001631992,
                  -2.3380182489754517, 0.08850614210672259, -2.2248081510160294])
    T = robot.fk(q)
    res = robot.ik(T)
    assert res.solutions, res.reason
    S = np.array([s.q for s in res.solutions])
    assert_reproduces(robot, S, T)
    assert all(5 in s.free for s in res.solutions)
    # a free joint's step has one root: its label names it free, with no sign ("j6:+")
    assert all("(j6 free)" in s.branch and "j6:" not in s.branch for s in res.solutions)
    B = robot.ik_batch(T[None])
    assert B.counts[0] == len(S)
    assert_reproduces(robot, B.q[0][B.valid[0]], T)
