"""Round-trip self-test of the IK solver: random joints -> FK -> IK.

The metrics follow IKFast's ``--iktests``: the share of poses whose
generating configuration is among the solutions (success; for robots solved
numerically, one solution of many, the share reached), poses where
some other solutions came back but not that one (missing), poses with no
solution at all (none), returned solutions whose FK misses the pose
(wrong), and the time per pose.
"""

from __future__ import annotations

import time

import numpy as np

from .screws import wrap


def sample_configurations(robot, n: int, rng) -> np.ndarray:
    """``(n, dof)`` joint values uniformly within the limits (unlimited revolute:
    (-pi, pi]; unlimited prismatic: [0, characteristic length])."""
    lo, hi = robot.limits.T
    L = robot.characteristic_length
    lo = np.where(np.isfinite(lo), lo, np.where(robot.is_revolute, -np.pi, 0.0))
    hi = np.where(np.isfinite(hi), hi, np.where(robot.is_revolute, np.pi, L))
    return rng.uniform(lo, hi, (n, robot.dof))


def run(robot, trials: int = 1000, seed: int = 0) -> dict:
    """Run ``trials`` round trips; return the metrics as a plain dict."""
    from .families import plan
    from .solve import Target, solve
    _, family, _ = plan(robot)
    # give the orientation only where the robot controls it (otherwise a position
    # target has the family's full solution set, as in the textbooks)
    orientation = family is None or family.needs_orientation
    numerical = family is None
    rng = np.random.default_rng(seed)
    Q = sample_configurations(robot, trials, rng)
    Ts = robot.fk(Q)
    found = missing = none = wrong = total = 0
    times = []
    counts: dict[int, int] = {}
    scale = robot.characteristic_length
    for q, T in zip(Q, Ts):
        t0 = time.perf_counter()
        res = solve(robot, Target(T, orientation=orientation))
        times.append(time.perf_counter() - t0)
        sols = res.solutions
        counts[len(sols)] = counts.get(len(sols), 0) + 1
        total += len(sols)
        hit = False
        for s in sols:
            Tq = robot.fk(s.q)
            if np.linalg.norm(Tq[:3, 3] - T[:3, 3]) > 1e-9 * scale:
                wrong += 1
            d = np.where(robot.is_revolute, wrap(s.q - q), s.q - q)
            if np.all(np.abs(d) < 1e-6 * np.where(robot.is_revolute, 1.0, max(scale, 1.0))):
                hit = True
        if numerical and sols and np.linalg.norm(robot.fk(sols[0].q)[:3, 3] - T[:3, 3]) <= \
                1e-9 * scale:
            hit = True          # one solution of infinitely many: reaching the pose is success
        if hit:
            found += 1
        elif sols:
            missing += 1
        else:
            none += 1
    n = max(trials, 1)
    return {
        "trials": trials, "seed": seed,
        "success_rate": found / n, "missing_rate": missing / n, "no_solution_rate": none / n,
        "wrong_solution_rate": wrong / max(total, 1),
        "solutions_per_pose": {str(k): v for k, v in sorted(counts.items())},
        "time_per_pose_ms": {"median": round(float(np.median(times) * 1e3), 4),
                             "mean": round(float(np.mean(times) * 1e3), 4)},
    }
