"""Workspace sampling throughput (FK samples per second), same-run references.

    python benchmarks/workspace.py [--n 1000000] [--robot puma560] [--repeat 5]

Measures :func:`kincalc.analysis.workspace.sample_tool_points` (uniform joints within
the limits, then the tool point of each through the vectorised FK: the
sampling stage of ``kincalc workspace``) against two references in the same
run: the same sampling with a batched numpy DH product written directly
(``@`` over 4x4 link matrices: what a numpy user writes), and a
per-configuration loop (what a user writes without vectorising). Then one
whole ``analyse`` with its stage timings. Target: >= 1,000,000 samples/s on
one core for a 6-DOF arm. Medians of --repeat runs.
"""

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from fk_batch import best_of as median_time  # noqa: E402  (the same median timer)
from fk_batch import naive_fk  # noqa: E402
from kincalc.analysis import workspace  # noqa: E402


def numpy_points(robot, rng, n):
    """Reference: uniform joints, link matrices as batched 4x4 products (matmul)."""
    lo, hi = workspace.joint_ranges(robot)
    q = rng.uniform(lo, hi, (n, robot.dof))
    A = robot.link_transforms(q)            # (n, dof, 4, 4)
    T = np.broadcast_to(robot.base, (n, 4, 4))
    for i in range(robot.dof):
        T = T @ A[:, i]
    return q, (T @ robot.tool)[:, :3, 3]


def loop_points(robot, rng, n):
    """Reference: uniform joints, then fk_batch's per-configuration numpy loop."""
    lo, hi = workspace.joint_ranges(robot)
    q = rng.uniform(lo, hi, (n, robot.dof))
    return q, naive_fk(robot, q)[:, :3, 3]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--robot", default="puma560")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    r = kincalc.load_robot(args.robot)
    q, P = workspace.sample_tool_points(r, np.random.default_rng(1), 1000)
    _, P_ref = numpy_points(r, np.random.default_rng(1), 1000)
    assert np.allclose(P, P_ref, atol=1e-12), "the references disagree with kincalc"
    n_np, n_loop = min(args.n, 200_000), 2000
    t_k = median_time(lambda: workspace.sample_tool_points(r, np.random.default_rng(0), args.n),
                      args.repeat)
    t_np = median_time(lambda: numpy_points(r, np.random.default_rng(0), n_np), args.repeat)
    t_loop = median_time(lambda: loop_points(r, np.random.default_rng(0), n_loop), 3)
    rates = {"kincalc sample_tool_points": args.n / t_k,
             "numpy batched DH (matmul)": n_np / t_np,
             "per-configuration loop": n_loop / t_loop}
    print(f"robot {r.name} ({r.dof} DOF), medians of {args.repeat} runs, one thread")
    print(f"{'sampling stage':32s} {'samples/s':>14s} {'ratio':>8s}")
    for name, rate in rates.items():
        print(f"{name:32s} {rate:14,.0f} {rate / rates['kincalc sample_tool_points']:8.3f}")
    print(f"target >= 1,000,000 samples/s: "
          f"{'ok' if rates['kincalc sample_tool_points'] >= 1e6 else 'MISSED'}")
    t0 = time.perf_counter()
    ws = workspace.analyse(r, 200_000, 0)
    total = time.perf_counter() - t0
    print(f"\nkincalc workspace {r.name} (200000 samples): {total:.2f} s in all; stages: "
          + ", ".join(f"{k} {v:.2f} s" for k, v in ws.timings.items()))


if __name__ == "__main__":
    main()
