"""Single-pose IK latency (``robot.ik(T)``) and the batched general-6R solver, same run.

    python benchmarks/ik_single.py [--poses 200] [--batch 1000 10000]
                                   [--robots puma560 ur5 kuka_kr16 manocha_canny_6r bk_offset_wrist]

For each robot (plus one seeded random general 6R built here) prints the median
time of one ``robot.ik(T)`` call over random reachable poses (FK of joints drawn
within the limits by :func:`kincalc.ik.selftest.sample_configurations`), and its
ratio to a reference measured in the same run: the median time of one
``numpy.linalg.eig`` of a random 24x24 matrix (the eigenproblem at the heart of
the general-6R solver; it makes figures from different machines comparable).
For the general 6R robots, and a seeded random arm of the three-parallel-offset family
(solved in closed form; the elimination solved it before), it also prints the median time
of one call of ``solve_general_6r_batch`` on a batch of one pose (``g6r 1``, over the same
poses), and its time per pose on each ``--batch`` size (median of 3 runs), each with its
ratio to the reference.

Times are wall-clock (``time.perf_counter``) unless ``--cpu`` asks for the
thread's CPU time (``time.thread_time``), steadier on a shared machine.
"""

import argparse
import os
import statistics
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from kincalc.ik.families import plan  # noqa: E402
try:
    from kincalc.ik.general6r import solve_general_6r_batch  # noqa: E402
except ImportError:              # an older tree (to time it against this one): no batch column
    solve_general_6r_batch = None
from kincalc.ik.selftest import sample_configurations  # noqa: E402
from kincalc.model import Joint, Robot  # noqa: E402

DEFAULT_ROBOTS = ["puma560", "ur5", "kuka_kr16", "manocha_canny_6r", "bk_offset_wrist"]


def random_general_6r(seed: int = 7) -> Robot:
    """A seeded random 6R robot in standard DH (lengths in [-0.5, 0.5] m, any twists)."""
    rng = np.random.default_rng(seed)
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=rng.uniform(-np.pi, np.pi),
                         a=rng.uniform(-0.5, 0.5), d=rng.uniform(-0.5, 0.5),
                         theta=rng.uniform(-np.pi, np.pi), limits=(-np.pi, np.pi))
                   for i in range(6))
    return Robot(name="random_6r", convention="dh", joints=joints)


def random_three_parallel_offset(seed: int = 7) -> Robot:
    """A seeded random arm of the three-parallel-offset family: DH twists 0 between axes 2-4,
    axes 5 and 6 a link apart (lengths in [-0.5, 0.5] m, the other twists any)."""
    rng = np.random.default_rng(seed)
    twist = [rng.uniform(0.3, 2.8), 0.0, 0.0, rng.uniform(0.3, 2.8), rng.uniform(0.3, 2.8),
             rng.uniform(-np.pi, np.pi)]
    joints = tuple(Joint(f"q{i + 1}", "revolute", alpha=twist[i],
                         a=0.3 if i == 4 else rng.uniform(-0.5, 0.5), d=rng.uniform(-0.5, 0.5),
                         theta=rng.uniform(-np.pi, np.pi), limits=(-np.pi, np.pi))
                   for i in range(6))
    return Robot(name="random_3par_offset", convention="dh", joints=joints)


def median_time(fn, args_list, clock) -> float:
    times = []
    for a in args_list:
        t0 = clock()
        fn(a)
        times.append(clock() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=200)
    ap.add_argument("--batch", type=int, nargs="+", default=[1000, 10000])
    ap.add_argument("--robots", nargs="+", default=DEFAULT_ROBOTS)
    ap.add_argument("--cpu", action="store_true", help="thread CPU time instead of wall time")
    args = ap.parse_args()
    clock = time.thread_time if args.cpu else time.perf_counter

    rng = np.random.default_rng(0)
    mats = list(rng.standard_normal((200, 24, 24)))
    np.linalg.eig(mats[0])
    ref = median_time(np.linalg.eig, mats, clock)
    print(f"reference: numpy.linalg.eig of a 24x24 matrix, median {ref * 1e3:.3f} ms "
          f"({'cpu' if args.cpu else 'wall'} time)")
    print(f"{'robot':18s} {'family':20s} {'ik ms':>8s} {'x eig':>6s} {'sols':>5s} "
          f"{'g6r 1 ms':>9s} {'x eig':>6s}"
          + "".join(f" {'N=' + str(n) + ' ms/pose':>16s} {'x eig':>6s}" for n in args.batch))

    robots = [kincalc.load_robot(n) for n in args.robots] + [random_general_6r(),
                                                             random_three_parallel_offset()]
    for r in robots:
        family = plan(r)[1]
        fam = family.name if family else "numerical"
        T = r.fk(sample_configurations(r, args.poses, np.random.default_rng(1)))
        r.ik(T[0])                                  # per-robot caches
        t_ik = median_time(r.ik, T, clock)
        sols = np.mean([len(r.ik(t).solutions) for t in T[:50]])
        line = f"{r.name:18s} {fam:20s} {t_ik * 1e3:8.3f} {t_ik / ref:6.1f} {sols:5.1f}"
        # (the elimination on a three-parallel-offset arm: what solved it before its family)
        if fam in ("general-6r", "three-parallel-offset") and solve_general_6r_batch is not None:
            t1 = median_time(lambda t: solve_general_6r_batch(r, t[None]), T, clock)
            line += f" {t1 * 1e3:9.3f} {t1 / ref:6.1f}"
            for n in args.batch:
                Tb = r.fk(sample_configurations(r, n, np.random.default_rng(2)))
                solve_general_6r_batch(r, Tb[:10])
                tb = []
                for _ in range(3):
                    t0 = clock()
                    solve_general_6r_batch(r, Tb)
                    tb.append((clock() - t0) / len(Tb))
                b = statistics.median(tb)
                line += f" {b * 1e3:16.3f} {b / ref:6.2f}"
        print(line)
        sys.stdout.flush()


if __name__ == "__main__":
    main()
