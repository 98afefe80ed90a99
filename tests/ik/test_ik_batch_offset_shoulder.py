"""Batched IK of arms with an offset shoulder: axes 1 and 2 skew (a shoulder offset
a1 != 0), axes 2 and 3 parallel, a spherical wrist (KUKA, Fanuc, ABB IRB 6640).

Their wrist centre is placed by the offset-shoulder form of :mod:`kincalc.ik.place`
(subproblem 4 on joint 1, subproblem 3 on joint 3, subproblem 1 on joint 2). It is
checked against values that do not come from it: the configuration that generated each
pose and the robot's FK, including poses at the placement's double roots (stretched and
folded elbow, the wrist centre on the shoulder-singularity cylinder or on axis 1) and at
the wrist singularity; and ``robot.ik`` (a batch of one) must agree with the batch.
"""

import numpy as np
import pytest

from kincalc import load_robot
from kincalc.fk import chain_frames
from kincalc.ik.engine import solve_batch
from kincalc.ik.families import plan
from kincalc.spatial import wrap
from kincalc.ik.selftest import sample_configurations
from kincalc.model import Joint, Robot
from randrobots import random_pose

BUNDLED = ["kuka_kr16", "fanuc_lrmate200id", "abb_irb6640", "abb_irb140", "kuka_kr6_r700_sixx",
           "kocaeli_kr16_lengths"]
KINDS = ["alpha1 = +-90 deg", "alpha1 = +-90 deg, no offsets along axis 2",
         "random alpha1"]


# --- robots and independent geometry -------------------------------------------------

def offset_shoulder_robot(rng, kind, orthogonal_wrist=False):
    """A random arm of the family (standard DH, m / rad): a1 != 0, alpha2 = 0 (axes 2, 3
    parallel), a4 = a5 = d5 = 0 (spherical wrist); other twists random (alpha4, alpha5
    = +-90 deg with ``orthogonal_wrist``), offsets d2, d3 along the parallel axes (so
    the wrist centre can lie off the plane of axis 1), random base and tool transforms."""
    u = lambda: rng.uniform(-0.6, 0.6)  # noqa: E731
    tw = lambda: rng.uniform(-np.pi, np.pi)  # noqa: E731
    right = lambda: rng.choice([-np.pi / 2, np.pi / 2])  # noqa: E731
    alpha1 = tw() if kind == "random alpha1" else right()
    a1 = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 0.5)
    along = kind != "alpha1 = +-90 deg, no offsets along axis 2"
    alphas = [alpha1, 0.0, tw(), right() if orthogonal_wrist else tw(),
              right() if orthogonal_wrist else tw(), tw()]
    a = [a1, u(), u(), 0.0, 0.0, u()]
    d = [u(), u() if along else 0.0, u() if along else 0.0, u(), 0.0, u()]
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=alphas[i], a=a[i], d=d[i],
                         theta=tw(), limits=(-np.pi, np.pi)) for i in range(6))
    return Robot(name="random_offset_shoulder", convention="dh", joints=joints,
                 base=random_pose(rng), tool=random_pose(rng))


def robots():
    """(label, robot): the bundled arms and three random arms of each kind."""
    out = [(name, load_robot(name)) for name in BUNDLED]
    for kind in KINDS:
        rng = np.random.default_rng(sum(map(ord, kind)))
        out += [(f"{kind} #{k}", offset_shoulder_robot(rng, kind)) for k in range(3)]
    return out


ROBOTS = robots()
IDS = [label for label, _ in ROBOTS]


def wrist_centre(robot, Q):
    """World position ``(N, 3)`` of the point where axes 4, 5, 6 meet, from the robot's
    frames (least squares over the three lines)."""
    F = chain_frames(robot.chain, np.atleast_2d(Q))
    z, o = F[:, 3:, :3, 2], F[:, 3:, :3, 3]
    P = np.eye(3) - z[..., :, None] * z[..., None, :]                      # (N, 3, 3, 3)
    return np.linalg.solve(P.sum(1), (P @ o[..., None]).sum(1))[..., 0]


def line_distance2(x, point, axis):
    """Squared distance of points ``x (N, 3)`` from lines ``point + t axis`` (N, 3)."""
    r = x - point
    r = r - axis * (r * axis).sum(-1)[:, None]
    return (r * r).sum(-1)


def sinusoid(f):
    """``(alpha, beta, gamma)`` of ``f(x) = alpha + beta cos x + gamma sin x`` (exact for such
    f) from its values at 0, pi / 2 and pi."""
    f0, f1, f2 = f(0.0), f(np.pi / 2), f(np.pi)
    al = 0.5 * (f0 + f2)
    return al, 0.5 * (f0 - f2), f1 - al


def with_joint(Q, i, value):
    Q = np.array(Q, float)
    Q[:, i] = value
    return Q


def stretched_and_folded(robot, Q):
    """``Q`` with joint 3 at the value that puts the wrist centre farthest from axis 2
    (stretched elbow) and, as a second array, nearest to it (folded elbow); from FK."""
    def dist2(q3):
        Qx = with_joint(Q, 2, q3)
        F = chain_frames(robot.chain, Qx)
        return line_distance2(wrist_centre(robot, Qx), F[:, 1, :3, 3], F[:, 1, :3, 2])
    _, be, ga = sinusoid(dist2)
    far = np.arctan2(ga, be)
    return with_joint(Q, 2, wrap(far)), with_joint(Q, 2, wrap(far + np.pi))


def on_shoulder_cylinder(robot, Q):
    """``Q`` with joint 3 (or else joint 2) moved so that the wrist centre lies on the
    cylinder about axis 1 where joint 1's two roots meet: seen with joint 1 at 0, the
    wrist centre lies in the plane through axis 1 that contains the direction h of
    axes 2 and 3 (``(w x h) . (c - o_1) = 0``, the height along h stationary in joint 1).
    Rows where neither joint can do this are dropped."""
    Q0 = with_joint(Q, 0, 0.0)
    F = chain_frames(robot.chain, Q0)
    w, o1, h = F[:, 0, :3, 2], F[:, 0, :3, 3], F[:, 1, :3, 2]
    n = np.cross(w, h)
    out, done = np.array(Q, float), np.zeros(len(Q), bool)
    sign = np.where(np.arange(len(Q)) % 2 == 0, 1.0, -1.0)
    for j in (2, 1):
        def g(x):
            return ((wrist_centre(robot, with_joint(Q0, j, x)) - o1) * n).sum(-1)
        al, be, ga = sinusoid(g)
        r = np.hypot(be, ga)
        can = ~done & (np.abs(al) < 0.99 * r)
        x = np.arctan2(ga, be) + np.arccos(np.clip(-al / np.maximum(r, 1e-300), -1, 1)) * sign
        out[can, j] = wrap(x[can])
        done |= can
    return out[done]


def on_axis_1(robot, Q, iters=60):
    """``Q`` with joints 2 and 3 moved (Gauss-Newton from the given values, numerical
    Jacobian of the FK) so that the wrist centre lies on axis 1; rows that do not get
    there (to 1e-13 m per m of reach) are dropped."""
    F = chain_frames(robot.chain, Q)
    w, o1 = F[:, 0, :3, 2], F[:, 0, :3, 3]
    L = robot.characteristic_length

    def resid(Qx):
        r = wrist_centre(robot, Qx) - o1
        return r - w * (r * w).sum(-1)[:, None]
    Q = np.array(Q, float)
    eps = 1e-7
    for _ in range(iters):
        e = resid(Q)
        J = np.stack([(resid(Q + eps * np.eye(6)[k]) - resid(Q - eps * np.eye(6)[k])) / (2 * eps)
                      for k in (1, 2)], axis=-1)                          # (N, 3, 2)
        JtJ = np.swapaxes(J, 1, 2) @ J + 1e-14 * np.eye(2)
        dx = np.linalg.solve(JtJ, (np.swapaxes(J, 1, 2) @ -e[..., None]))[..., 0]
        Q[:, 1:3] += dx
    ok = np.sqrt((resid(Q) ** 2).sum(-1)) < 1e-13 * L
    return Q[ok]


# --- comparisons -------------------------------------------------------------------

def joint_distance(A, q, robot):
    return np.abs(np.where(robot.is_revolute, wrap(np.asarray(A) - q), np.asarray(A) - q)).max(-1)


def same_set(A, B, robot, tol=1e-7):
    if len(A) != len(B):
        return False
    return same_branches(A, B, robot, tol)


def same_branches(A, B, robot, tol):
    """Every solution of A is within ``tol`` of one of B and vice versa (copies ignored)."""
    if len(A) == 0 or len(B) == 0:
        return len(A) == len(B)
    return all(joint_distance(B, a, robot).min() <= tol for a in A) and \
        all(joint_distance(A, b, robot).min() <= tol for b in B)


#: robot.ik finds a double root of its resultant in joint 3 as two nearby roots, each a
#: few 1e-6 rad (up to ~1e-4) from the exact value; at such poses its solutions are
#: compared branch by branch at this tolerance (the batch's are checked exactly above)
DOUBLE_ROOT_TOL = 1e-3


def assert_solutions_reproduce(robot, B, T):
    L = max(1.0, robot.characteristic_length)
    for i in range(len(T)):
        sols = B.q[i][B.valid[i]]
        assert len(sols) >= 1, i
        assert np.allclose(robot.fk(sols), T[i], rtol=0, atol=1e-9 * L), i


def assert_generators_found(robot, B, Q, joints=slice(None), tol=1e-6):
    """The configuration ``Q[i]`` (its ``joints``) is among pose i's solutions."""
    for i in range(len(Q)):
        sols = B.q[i][B.valid[i]]
        d = np.abs(wrap(sols[:, joints] - Q[i, joints])).max(-1)
        assert d.min() < tol, (i, d.min())


# --- tests --------------------------------------------------------------------------

@pytest.mark.parametrize("label,robot", ROBOTS, ids=IDS)
def test_offset_shoulder_structure_is_recognised(label, robot):
    """The robot-level plan of the placement finds these arms (from their screws)."""
    from kincalc.ik.place import plan as placement
    from kincalc.structure import common_point
    S, family, _ = plan(robot)
    assert family.name == "spherical-wrist"
    c0 = common_point(S.point[3:], S.axis[3:], np.inf)
    assert placement(S, (0, 1, 2), tuple(c0)).mode == "shoulder"


def test_arms_whose_first_axes_meet_take_the_decoupled_form():
    """PUMA and IRB 120 (axes 1 and 2 meet) place the wrist centre by the invariant free
    of joint 2 (the distance from the meeting point); Stanford's prismatic joint 3 the
    same way, with a quadratic."""
    from kincalc.ik.place import plan as placement
    from kincalc.structure import common_point
    for name in ("puma560", "abb_irb120", "stanford_arm"):
        S, _, _ = plan(load_robot(name))
        c0 = common_point(S.point[3:], S.axis[3:], np.inf)
        assert placement(S, (0, 1, 2), tuple(c0)).mode == "decoupled", name


@pytest.mark.parametrize("label,robot", ROBOTS, ids=IDS)
def test_every_generating_configuration_is_found_and_every_solution_is_exact(label, robot):
    rng = np.random.default_rng(3)
    Q = sample_configurations(robot, 300, rng)
    T = robot.fk(Q)
    B = solve_batch(robot, T)
    assert_solutions_reproduce(robot, B, T)
    assert_generators_found(robot, B, Q)
    for i in range(0, 300, 25):
        ref = [s.q for s in robot.ik(T[i]).solutions]
        assert same_set(B.q[i][B.valid[i]], ref, robot), (label, i)


@pytest.mark.parametrize("label,robot", ROBOTS, ids=IDS)
def test_stretched_and_folded_elbow(label, robot):
    """Joint 3's double root: the elbow straight (and folded back)."""
    Q = sample_configurations(robot, 60, np.random.default_rng(4))
    for Qe in stretched_and_folded(robot, Q):
        T = robot.fk(Qe)
        B = solve_batch(robot, T)
        assert_solutions_reproduce(robot, B, T)
        # a double root fixes the angle only to ~sqrt(rounding) (~1e-8 rad, amplified
        # in the other joints); the batch takes the double root itself, so the
        # generating configuration comes back to the usual tolerance
        assert_generators_found(robot, B, Qe)
        for i in range(0, len(Qe), 10):
            ref = [s.q for s in robot.ik(T[i]).solutions]
            assert same_branches(B.q[i][B.valid[i]], ref, robot, DOUBLE_ROOT_TOL), (label, i)


def test_wrist_centre_on_the_shoulder_singularity_cylinder():
    """Joint 1's double root (subproblem 4 at |cos| = 1), on the random arms whose wrist
    centre stays off the plane of axis 1 and can reach the cylinder (the bundled arms'
    cylinder is axis 1 itself: see test_wrist_centre_on_axis_1); the double root is
    taken exactly, so the generating configuration comes back to the usual tolerance."""
    tested = 0
    for label, robot in ROBOTS[len(BUNDLED):]:
        Q = on_shoulder_cylinder(robot, sample_configurations(robot, 80, np.random.default_rng(6)))
        if len(Q) < 10:          # the wrist centre cannot reach the cylinder (short arm)
            continue
        tested += 1
        F = chain_frames(robot.chain, Q)
        radius = np.sqrt(line_distance2(wrist_centre(robot, Q), F[:, 0, :3, 3], F[:, 0, :3, 2]))
        assert radius.min() > 1e-3
        T = robot.fk(Q)
        B = solve_batch(robot, T)
        assert_solutions_reproduce(robot, B, T)
        assert_generators_found(robot, B, Q)
        for i in range(0, len(Q), 10):
            ref = [s.q for s in robot.ik(T[i]).solutions]
            assert same_branches(B.q[i][B.valid[i]], ref, robot, DOUBLE_ROOT_TOL), (label, i)
    assert tested >= 7


def test_wrist_centre_on_axis_1():
    """Joint 1 is free (a continuum): its representative is joint 1 = 0 (as robot.ik's),
    every solution reproduces the pose, the generating elbow (joints 2, 3) is among
    them and the set equals robot.ik's; for the bundled arms (whose wrist centre
    reaches axis 1 in the plane of the arm) and random arms with a random twist alpha1
    (axis 1 crosses the plane the wrist centre moves in at one point) and an orthogonal
    wrist (which turns the hand into any orientation whatever joint 1's representative)."""
    rng = np.random.default_rng(12)
    arms = [load_robot(name) for name in BUNDLED] + \
        [offset_shoulder_robot(rng, "random alpha1", orthogonal_wrist=True) for _ in range(6)]
    reached = 0
    for robot in arms:
        Q = on_axis_1(robot, sample_configurations(robot, 40, np.random.default_rng(7)))
        if len(Q) == 0:
            continue
        reached += 1
        T = robot.fk(Q)
        B = solve_batch(robot, T)
        assert_solutions_reproduce(robot, B, T)
        assert_generators_found(robot, B, Q, joints=slice(1, 3))
        for i in range(0, len(Q), 5):
            sols = B.q[i][B.valid[i]]
            assert np.all(sols[:, 0] == 0.0)
            ref = [s.q for s in robot.ik(T[i]).solutions]
            assert same_set(sols, ref, robot, tol=1e-6), i
    assert reached >= len(BUNDLED) + 3


def placements(robot, T):
    """Joints 1-3 of every candidate placement of the wrist centre for poses ``T``, as
    the batched solver computes them before the wrist: ``(q (N, K, 3), ok (N, K))``."""
    from kincalc.structure import common_point
    S, _, _ = plan(robot)
    c0 = common_point(S.point[3:], S.axis[3:], np.inf)
    Minv = S.inverse_M()
    CT = T[:, :3, :3] @ (Minv[:3, :3] @ c0 + Minv[:3, 3]) + T[:, :3, 3]
    from kincalc.ik.branches import Branches
    from kincalc.ik.place import place
    br = place(S, Branches.start(len(T), robot.dof), (0, 1, 2), c0, CT[:, None, :])
    return br.q()[..., :3], br.ok


@pytest.mark.parametrize("name", BUNDLED)
def test_wrist_singularity_q5_zero(name):
    """q5 = 0 (axes 4 and 6 aligned, a continuum of q4, q6): every representative
    reproduces the pose, and the generating joints 1-3 are among the placements (the
    wrist centre does not see the wrist's singularity). (The wrist's own subproblem 4
    is at its double root there: a representative whose q5 comes out ~1e-8 instead of 0
    misses the 1e-9 rad orientation check; that part is not the placement's.)"""
    r = load_robot(name)
    Q = with_joint(sample_configurations(r, 100, np.random.default_rng(8)), 4, 0.0)
    T = r.fk(Q)
    B = solve_batch(r, T)
    assert_solutions_reproduce(r, B, T)
    q, ok = placements(r, T)
    for i in range(len(Q)):
        d = np.abs(wrap(q[i][ok[i]] - Q[i, :3])).max(-1)
        assert d.min() < 1e-9, (i, d.min())


@pytest.mark.parametrize("label,robot", ROBOTS, ids=IDS)
def test_placements_are_the_generating_ones_and_exact(label, robot):
    """The placement on its own: joints 1-3 of every generating configuration are among
    the candidates to 1e-9 rad, and every candidate puts the wrist centre on its target
    (FK of joints 1-3, to 1e-12 m per m of reach)."""
    Q = sample_configurations(robot, 200, np.random.default_rng(13))
    T = robot.fk(Q)
    q, ok = placements(robot, T)
    for i in range(len(Q)):
        d = np.abs(wrap(q[i][ok[i]] - Q[i, :3])).max(-1)
        assert d.min() < 1e-9, (i, d.min())
    full = np.concatenate([q[ok], np.zeros((ok.sum(), 3))], axis=1)
    target = np.repeat(wrist_centre(robot, Q), ok.sum(1), axis=0)
    assert np.abs(wrist_centre(robot, full) - target).max() < 1e-12 * robot.characteristic_length


def test_unreachable_poses_have_no_solutions():
    r = load_robot("kuka_kr16")
    T = r.fk(sample_configurations(r, 20, np.random.default_rng(9)))
    T[:, :3, 3] *= 10.0
    assert not solve_batch(r, T).valid.any()
