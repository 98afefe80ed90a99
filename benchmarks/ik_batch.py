"""Batched IK throughput (vectorised over poses) against per-pose calls, same run.

    python benchmarks/ik_batch.py [--poses 100000] [--robots puma560 ur5 kuka_kr16]

Reports the median time per pose of ``robot.ik_batch(T)`` over all poses and of
``robot.ik(T)`` called per pose (on a subset), and their ratio.
"""

import argparse
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from kincalc.ik.selftest import sample_configurations  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--poses", type=int, default=100_000)
    ap.add_argument("--robots", nargs="+", default=["puma560", "ur5", "kuka_kr16"])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"{'robot':14s} {'batch us/pose':>14s} {'per-pose us':>12s} {'speed-up':>9s} {'sols/pose':>9s}")
    for name in args.robots:
        r = kincalc.load_robot(name)
        Q = sample_configurations(r, args.poses, np.random.default_rng(0))
        T = r.fk(Q)
        tb = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            B = r.ik_batch(T)
            tb.append((time.perf_counter() - t0) / args.poses)
        n1 = min(300, args.poses)
        tp = []
        for i in range(n1):
            t0 = time.perf_counter()
            r.ik(T[i])
            tp.append(time.perf_counter() - t0)
        b, p = statistics.median(tb), statistics.median(tp)
        print(f"{name:14s} {b * 1e6:14.2f} {p * 1e6:12.1f} {p / b:9.0f} {B.counts.mean():9.2f}")


if __name__ == "__main__":
    main()
