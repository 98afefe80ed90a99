"""Random robots for property tests (seeded; no robot names, only geometry)."""

import math

import numpy as np

from kincalc.model import Joint, Robot
from kincalc.spatial import matrix_from_rpy, transform, wrap


def random_pose(rng, scale=0.5):
    return transform(matrix_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-scale, scale, 3))


def random_robot(rng, convention="dh", n=6, types=None, base_tool=True):
    """A random serial robot: lengths in [-0.5, 0.5] m, twists and offsets anywhere."""
    types = types or ["revolute" if rng.random() < 0.8 else "prismatic" for _ in range(n)]
    joints = []
    for i, t in enumerate(types):
        lim = (-np.pi, np.pi) if t == "revolute" else (0.0, 0.5)
        if convention == "poe":
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
            joints.append(Joint(f"q{i + 1}", t, axis=tuple(axis),
                                point=tuple(rng.uniform(-0.5, 0.5, 3)), limits=lim))
        else:
            joints.append(Joint(f"q{i + 1}", t, alpha=rng.uniform(-np.pi, np.pi),
                                a=rng.uniform(-0.5, 0.5), d=rng.uniform(-0.5, 0.5),
                                theta=rng.uniform(-np.pi, np.pi), limits=lim))
    base = random_pose(rng) if base_tool else np.eye(4)
    M = random_pose(rng) if convention == "poe" else None
    tool = random_pose(rng) if base_tool else np.eye(4)
    return Robot(name=f"random_{convention}", convention=convention, joints=tuple(joints),
                 base=base, tool=tool, M=M)


def dh_frames(robot, q) -> list:
    """The frames of a standard-DH chain by a plain product, without kincalc's FK:
    ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)`` with ``q_i`` added to ``theta_i``, or to
    ``d_i`` for a prismatic joint; ``[base, frame 1, ..., frame n, tool pose]`` (4, 4) each."""
    T = [np.array(robot.base, float)]
    for j, x in zip(robot.joints, q):
        slide = j.type == "prismatic"
        theta, d = (j.theta, j.d + x) if slide else (j.theta + x, j.d)
        ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(j.alpha), np.sin(j.alpha)
        T.append(T[-1] @ np.array([[ct, -st * ca, st * sa, j.a * ct],
                                   [st, ct * ca, -ct * sa, j.a * st], [0, sa, ca, d], [0, 0, 0, 1]]))
    T.append(T[-1] @ np.array(robot.tool, float))
    return T


def three_conventions(robot, T) -> list:
    """The IK solutions of a standard-DH ``robot`` for the pose ``T``, and of its modified-DH
    and product-of-exponentials forms, each a sorted list of joint vectors (wrapped, 7
    decimals): equal lists, one solution set."""
    from kincalc.conventions import dh_to_mdh, to_poe
    from kincalc.ik import Target, solve
    return [sorted(np.round(wrap(np.array(s.q)), 7).tolist() for s in solve(r, Target(T)).solutions)
            for r in (robot, dh_to_mdh(robot), to_poe(robot))]


def newton_roots(robot, T, starts, rng) -> list:
    """Every configuration reaching the pose ``T (4, 4)`` that Gauss-Newton finds from
    ``starts`` random starts drawn from ``rng`` (kincalc's FK and Jacobian only, no IK:
    revolute joints in [-pi, pi), prismatic in [-pi, pi) m; distinct to 1e-6, regular
    Jacobian), wrapped to (-pi, pi] for revolute joints: the oracle of a solution set."""
    roots = []
    for q in rng.uniform(-np.pi, np.pi, (starts, robot.dof)):
        for _ in range(60):
            F = robot.fk(q)
            E = T[:3, :3] @ F[:3, :3].T
            e = np.r_[T[:3, 3] - F[:3, 3], 0.5 * np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0],
                                                           E[1, 0] - E[0, 1]])]
            if np.abs(e).max() < 1e-13:
                break
            q = q + np.linalg.lstsq(robot.jacobian(q), e, rcond=None)[0]
        # the whole pose, not e: a rotation by pi has a zero skew part
        reached = np.abs(robot.fk(q) - T).max() < 1e-10
        regular = np.linalg.svd(robot.jacobian(q), compute_uv=False)[-1] > 1e-6
        if reached and regular \
                and not any(np.abs(np.where(robot.is_revolute, wrap(q - p), q - p)).max() < 1e-6
                        for p in roots):
            roots.append(np.where(robot.is_revolute, wrap(q), q))
    return roots


#: twists that make axes parallel, perpendicular, antiparallel, or nearly so
SPECIAL_TWISTS = [0.0, math.pi / 2, -math.pi / 2, math.pi, math.pi / 2 + 3.5e-7, math.pi - 1e-7]


def degenerate_dh_robot(rng, n):
    """A random standard-DH robot of ``n`` joints, degenerate on purpose: special and
    nearly special twists, coaxial axes, prismatic joints, rotated base and tool."""
    joints = []
    for i in range(n):
        kind = "revolute" if rng.random() < 0.7 else "prismatic"
        alpha = float(rng.choice(SPECIAL_TWISTS)) if rng.random() < 0.6 \
            else rng.uniform(-np.pi, np.pi)
        a = 0.0 if rng.random() < 0.4 else rng.uniform(-0.5, 0.5)
        d = 0.0 if rng.random() < 0.3 else rng.uniform(-0.5, 0.5)
        if rng.random() < 0.25:
            alpha, a = 0.0, 0.0                      # the next axis is coaxial with this one
        theta = float(rng.choice([0.0, np.pi / 2, -np.pi / 2])) if rng.random() < 0.5 \
            else rng.uniform(-np.pi, np.pi)
        lim = (-np.pi, np.pi) if kind == "revolute" else (0.0, 0.5)
        joints.append(Joint(f"q{i + 1}", kind, alpha=alpha, a=a, d=d, theta=theta, limits=lim))

    def frame():
        T = random_pose(rng)
        if rng.random() < 0.25:
            T[:3, :3] = np.eye(3)                    # translated only
        return T
    return Robot(name="degenerate", convention="dh", joints=tuple(joints), base=frame(),
                 tool=frame())


def gauss_newton(err, q, moving, iters=30, stop=1e-13):
    """``q`` with the joints ``moving`` changed by Gauss-Newton steps (finite differences of
    ``err(q) -> residual vector``) until the residual is below ``stop`` or ``iters`` steps
    are taken (a copy)."""
    q, moving = np.array(q, float), list(moving)
    for _ in range(iters):
        e = err(q)
        if np.abs(e).max() < stop:
            break
        J = np.empty((len(e), len(moving)))
        for c, k in enumerate(moving):
            x = q.copy()
            x[k] += 1e-7
            J[:, c] = (err(x) - e) / 1e-7
        q[moving] -= np.linalg.lstsq(J, e, rcond=None)[0]
    return q


def follow_joint(miss, q, j, value, way, others, steps=60):
    """The end of a continuum of solutions from ``q`` to joint ``j`` at ``value``, or None
    where there is none: joint ``j`` moved there in ``steps``, turning ``way`` (+1 or -1)
    round, the joints ``others`` kept on the target by :func:`gauss_newton` on ``miss(q) ->
    residual vector`` after each, every step reaching it to 1e-12."""
    q = np.array(q, float)
    start, turn = q[j], wrap(value - q[j])
    if turn * way < 0:
        turn += way * 2 * np.pi
    for t in np.linspace(0.0, 1.0, steps + 1)[1:]:
        q[j] = start + t * turn
        q = gauss_newton(miss, q, others)
        if np.abs(miss(q)).max() > 1e-12:
            return None
    return q
