"""Batched FK and Jacobian throughput through the Python API, same-run reference.

    python benchmarks/fk_batch.py [--n 1000000] [--robot puma560] [--repeat 5]

Reference: a plain per-configuration loop multiplying the convention's link
matrices with numpy (what a user writes without kincalc), timed on a subset
and reported per configuration. Target: >= 1,000,000 FK configurations/s
on one core for a 6-DOF arm.
"""

import argparse
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402


def naive_fk(robot, q):
    out = np.empty((len(q), 4, 4))
    for k, qq in enumerate(q):
        T = robot.base.copy()
        for A in robot.link_transforms(qq):
            T = T @ A
        out[k] = T @ robot.tool
    return out


def best_of(f, repeat):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--robot", default="puma560")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    r = kincalc.load_robot(args.robot)
    rng = np.random.default_rng(0)
    q = rng.uniform(-np.pi, np.pi, (args.n, r.dof))
    t_fk = best_of(lambda: r.fk(q), args.repeat)
    nj = max(args.n // 4, 1)
    t_j = best_of(lambda: r.jacobian(q[:nj]), args.repeat)
    ns = 2000
    t_naive = best_of(lambda: naive_fk(r, q[:ns]), 3)
    assert np.allclose(naive_fk(r, q[:100]), r.fk(q[:100]), atol=1e-12)
    fk_rate, j_rate, naive_rate = args.n / t_fk, nj / t_j, ns / t_naive
    print(f"robot {r.name} ({r.dof} DOF), medians of {args.repeat} runs")
    print(f"{'what':34s} {'configs/s':>14s} {'us/config':>10s}")
    print(f"{'kincalc fk (batched, ' + str(args.n) + ')':34s} {fk_rate:14,.0f} {1e6 / fk_rate:10.3f}")
    print(f"{'kincalc jacobian (batched, ' + str(nj) + ')':34s} {j_rate:14,.0f} {1e6 / j_rate:10.3f}")
    print(f"{'per-config numpy loop (' + str(ns) + ')':34s} {naive_rate:14,.0f} {1e6 / naive_rate:10.3f}")
    print(f"speed-up of batched FK over the loop: {fk_rate / naive_rate:.0f}x "
          f"(target >= 1,000,000 FK/s: {'ok' if fk_rate >= 1e6 else 'MISSED'})")


if __name__ == "__main__":
    main()
