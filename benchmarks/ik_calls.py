"""Python-level calls per single IK call: the per-call overhead of ``robot.ik(T)``, counted.

    python benchmarks/ik_calls.py [--poses 50] [--robots puma560 ur5 kuka_kr16]

A single pose is a batch of one, so its time is mostly the overhead of the numpy calls
and Python functions the engine makes on tiny arrays. Wall time on a shared machine
varies by a factor of two between runs; the number of calls does not. For each robot
this prints the mean number of function calls (Python functions and numpy's built-in
functions, as ``cProfile`` counts them) per ``robot.ik(T)`` over random reachable poses
(FK of joints drawn within the limits, seeded), split into the engine's phases: the
family's solver, the FK check and flags (``solve_targets``), the labels and singular
flags, and the whole call with its post-processing.
"""

import argparse
import cProfile
import os
import pstats

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from kincalc.ik.branches import Branches  # noqa: E402
from kincalc.ik.engine import solve_targets  # noqa: E402
from kincalc.ik.solvers import run_solver  # noqa: E402
from kincalc.ik.families import plan  # noqa: E402
from kincalc.ik.selftest import sample_configurations  # noqa: E402
from kincalc.ik.target import Targets  # noqa: E402


def calls_per_pose(fn, poses) -> float:
    for T in poses[:5]:           # per-robot caches filled first
        fn(T)
    prof = cProfile.Profile()
    prof.enable()
    for T in poses:
        fn(T)
    prof.disable()
    return pstats.Stats(prof).total_calls / len(poses)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=50)
    ap.add_argument("--robots", nargs="+", default=["puma560", "ur5", "kuka_kr16"])
    args = ap.parse_args()
    print(f"{'robot':12s} {'solver':>8s} {'+check':>8s} {'+labels':>8s} {'robot.ik':>9s}"
          "   (calls per pose)")
    for name in args.robots:
        robot = kincalc.load_robot(name)
        Q = sample_configurations(robot, args.poses, np.random.default_rng(1))
        poses = list(robot.fk(Q))
        S, family, _ = plan(robot)

        def solver(T):
            run_solver(robot, S, family, Targets(T[None]), Branches.start(1, robot.dof))

        def flagged(T):
            solved = solve_targets(robot, Targets(T[None]))
            solved.labels, solved.singular

        row = [calls_per_pose(f, poses) for f in
               (solver, lambda T: solve_targets(robot, Targets(T[None])), flagged, robot.ik)]
        print(f"{name:12s} " + " ".join(f"{x:8.0f}" for x in row[:3]) + f" {row[3]:9.0f}")


if __name__ == "__main__":
    main()
