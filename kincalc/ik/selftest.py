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

from ..errors import BadValue
from ..limits import MAX_TRIALS
from ..spatial import wrap

#: configurations drawn (and FK'd) at a time: memory stays a few MB whatever ``trials``
#: is, and the numbers are those of one draw of ``trials`` (a Generator fills arrays
#: in order)
CHUNK = 4096


def sample_configurations(robot, n: int, rng) -> np.ndarray:
    """Joint values drawn uniformly within the limits.

    An infinite bound is replaced: revolute joints by -pi or pi, prismatic ones by 0 or the
    characteristic length (m).

    Parameters
    ----------
    robot : Robot
    n : int
        Number of configurations.
    rng : numpy.random.Generator

    Returns
    -------
    ndarray (n, dof)
        Rad / m, in ``[lo, hi)`` per joint.
    """
    lo, hi = robot.limits.T
    L = robot.characteristic_length
    lo = np.where(np.isfinite(lo), lo, np.where(robot.is_revolute, -np.pi, 0.0))
    hi = np.where(np.isfinite(hi), hi, np.where(robot.is_revolute, np.pi, L))
    return rng.uniform(lo, hi, (n, robot.dof))


def run(robot, trials: int = 1000, seed: int = 0, solver=None) -> dict:
    """Run ``trials`` round trips (random joints -> FK -> IK); return the metrics.

    A returned solution is counted wrong when its FK position misses the pose's by more
    than 1e-9 of the characteristic length; the generating configuration is found when a
    solution is within 1e-6 of it (rad, or times max(length, 1) m; wrapped for revolute
    joints).

    Parameters
    ----------
    robot : Robot
    trials : int
        From 1 to :data:`~kincalc.limits.MAX_TRIALS`.
    seed : int
        Non-negative; seeds the configurations.
    solver : callable, optional
        ``solver(q, T) -> IKResult``: every solution of the pose ``T`` made by the joints
        ``q`` (rad / m), for a question that depends on them (a joint held at its own value,
        the swivel angle of the configuration); default ``solve`` of the pose (its
        orientation where the robot controls it).

    Returns
    -------
    dict
        ``trials``, ``seed``, ``success_rate``, ``missing_rate``, ``no_solution_rate`` (of
        the poses), ``wrong_solution_rate`` (of the solutions returned),
        ``solutions_per_pose`` (count -> poses, keys str) and ``time_per_pose_ms``
        (``median``, ``mean``).

    Raises
    ------
    BadValue
        ``trials`` outside 1 ... :data:`~kincalc.limits.MAX_TRIALS`, or a ``seed``
        that is not a non-negative integer.
    """
    from .families import plan
    from .solve import Target, solve
    if isinstance(trials, bool) or not isinstance(trials, (int, np.integer)) \
            or not 1 <= trials <= MAX_TRIALS:
        raise BadValue("trials", f"from 1 to {MAX_TRIALS} (kincalc's limit)", trials)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise BadValue("seed", "a non-negative integer", seed)
    _, family, _ = plan(robot)
    # give the orientation only where the robot controls it (otherwise a position
    # target has the family's full solution set, as in the textbooks)
    orientation = family is None or family.needs_orientation
    numerical = family is None and solver is None
    if solver is None:
        def solver(q, T):
            return solve(robot, Target(T, orientation=orientation))
    rng = np.random.default_rng(seed)
    found = missing = none = wrong = total = 0
    times = np.empty(trials)
    counts: dict[int, int] = {}
    for k, (q, T) in enumerate(_round_trip_inputs(robot, trials, rng)):
        t0 = time.perf_counter()
        res = solver(q, T)
        times[k] = time.perf_counter() - t0
        sols = res.solutions
        counts[len(sols)] = counts.get(len(sols), 0) + 1
        total += len(sols)
        hit, misses = _score(robot, q, T, [s.q for s in sols], numerical)
        wrong += misses
        if hit:
            found += 1
        elif sols:
            missing += 1
        else:
            none += 1
    n = trials
    return {
        "trials": trials, "seed": seed,
        "success_rate": found / n, "missing_rate": missing / n, "no_solution_rate": none / n,
        "wrong_solution_rate": wrong / max(total, 1),
        "solutions_per_pose": {str(k): v for k, v in sorted(counts.items())},
        "time_per_pose_ms": {"median": round(float(np.median(times) * 1e3), 4),
                             "mean": round(float(np.mean(times) * 1e3), 4)},
    }


def _score(robot, q, T, sols, numerical: bool) -> tuple[bool, int]:
    """``(found, wrong)`` of the solutions ``sols`` (joint vectors) of the pose ``T`` made
    by ``q``: the generating joints among them (for a robot solved numerically, one
    solution of infinitely many: reaching the pose), and how many miss the pose."""
    scale = robot.characteristic_length
    if not sols:
        return False, 0
    Q = np.array(sols)
    miss = np.linalg.norm(robot.fk(Q)[:, :3, 3] - T[:3, 3], axis=-1) > 1e-9 * scale
    d = np.where(robot.is_revolute, wrap(Q - q), Q - q)
    tol = 1e-6 * np.where(robot.is_revolute, 1.0, max(scale, 1.0))
    hit = bool(np.all(np.abs(d) < tol, axis=-1).any()) or (numerical and not miss[0])
    return hit, int(miss.sum())


def _round_trip_inputs(robot, trials: int, rng):
    """``(q, T)`` pairs: :func:`sample_configurations` and their FK, drawn :data:`CHUNK`
    at a time."""
    for start in range(0, trials, CHUNK):
        Q = sample_configurations(robot, min(CHUNK, trials - start), rng)
        yield from zip(Q, robot.fk(Q))
