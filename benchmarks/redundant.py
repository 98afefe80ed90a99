"""Redundant arms: a locked-joint call, a swivel-angle call, a sweep and a swivel range,
against one 6-joint call, in the same run.

    python benchmarks/redundant.py [--poses 100] [--robot iiwa14]

For random reachable poses of the 7-joint arm (FK of joints drawn within the limits,
seeded) prints the median time of:

* the 6-joint reference: ``robot.ik(T)`` of the chain the arm leaves with joint 3 held
  (a spherical wrist), the chain built once;
* ``solve_locked(arm, T, {2: v})`` with the value of the pose (a new chain per call: its
  family and constants found again) and with one value for every pose (the chain cached);
* ``solve(arm, Target(T, swivel=psi))``: the eight branches at a swivel angle;
* a sweep of joint 1 over 100 values (``kincalc.analysis.sweep.sweep``: one engine batch
  of 100 targets, plus the halvings that locate branch ends), and the batch alone;
* ``swivel_ranges(arm, T)``: 720 sampled angles and the bisected ends.

Each with its ratio to the 6-joint reference (target of issue 18: a locked-joint call
about one 6-joint call; a 100-value sweep of a spherical-wrist lock <= 2 ms).
"""

import argparse
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from kincalc.analysis.redundancy import locked_robot, solve_locked  # noqa: E402
from kincalc.analysis.sweep import Solver, sweep  # noqa: E402
from kincalc.analysis.swivel import swivel_ranges  # noqa: E402
from kincalc.ik import Target, solve  # noqa: E402
from kincalc.ik.selftest import sample_configurations  # noqa: E402
from kincalc.ik.swivel import swivel_angles  # noqa: E402


def median(fn, items):
    times = []
    for x in items:
        t0 = time.perf_counter()
        fn(x)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=100)
    ap.add_argument("--robot", default="iiwa14")
    args = ap.parse_args()
    arm = kincalc.load_robot(args.robot)
    rng = np.random.default_rng(0)
    Q = sample_configurations(arm, args.poses, rng)
    T = arm.fk(Q)
    psi = swivel_angles(arm, Q)
    six = locked_robot(arm, {2: float(Q[0, 2])})
    six.ik(T[0])
    items = list(zip(T, Q, psi))
    ref = median(lambda x: six.ik(x[0]), items)
    values = np.linspace(*arm.limits[0], 100)
    rows = [
        ("6-joint chain, robot.ik(T)", ref),
        ("solve_locked, the pose's value", median(
            lambda x: solve_locked(arm, Target(x[0]), {2: float(x[1][2])}), items)),
        ("solve_locked, one value", median(
            lambda x: solve_locked(arm, Target(x[0]), {2: float(Q[0, 2])}), items)),
        ("swivel angle, 8 branches", median(
            lambda x: solve(arm, Target(x[0], swivel=float(x[2]))), items)),
        ("sweep A1, 100 values (batch)", median(
            lambda x: Solver(arm, Target(x[0]).targets(), 0, {}).grid(values), items[:20])),
        ("sweep A1, 100 values (joined)", median(
            lambda x: sweep(arm, Target(x[0]).targets(), 0, values), items[:20])),
        ("swivel range", median(lambda x: swivel_ranges(arm, x[0]), items[:20])),
    ]
    print(f"{args.robot}: medians over {args.poses} poses (20 for sweeps and ranges)")
    print(f"{'call':34s} {'ms':>9s} {'x 6-joint':>10s}")
    for name, t in rows:
        print(f"{name:34s} {t * 1e3:9.3f} {t / ref:10.2f}")


if __name__ == "__main__":
    main()
