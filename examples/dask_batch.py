"""Batched inverse kinematics on a Dask cluster: the recipe of README's *Scaling out with Dask*.

Run ``python examples/dask_batch.py --robot ur5 --poses 1000000 --chunk 20000``
(a local cluster, one single-threaded worker per core) or add
``--scheduler tcp://HOST:8786`` to use a running cluster. Needs the ``dask`` extra
(``pip install 'kincalc[dask]'``) here and kincalc on every worker.

The job: ``--poses`` random configurations within the joint limits, their tool
poses by FK, and every IK solution of each pose, chunk by chunk on the workers;
then a summary on standard output (JSON): poses per second, how many poses
have 0, 1, ... K solutions, and the share of poses whose generating
configuration is among their solutions (the round trip of
:mod:`kincalc.ik.selftest`).

The recipe is :func:`solve_poses`: the poses are a dask array ``T (N, 4, 4)``
chunked along the pose axis, and ``robot.ik_batch`` runs on each chunk with
``map_blocks``. ``ik_batch`` has a fixed number ``K`` of solution slots per
robot, so one small call on the client gives every chunk's output shape. The
two outputs of a chunk (``q (m, K, n)`` and ``valid (m, K)``) travel as one
record array, so each chunk is solved once; its fields are the dask arrays
``q (N, K, n)`` and ``valid (N, K)``.

Nothing but the :class:`~kincalc.Robot` object reaches the workers, pickled
inside the task graph: a robot loaded from the user's YAML file works on
workers that do not have that file.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import time

import dask
import dask.array as da
import numpy as np
from dask.distributed import Client

import kincalc
from kincalc.ik.selftest import sample_configurations

# A generating configuration counts as found when every joint of one valid
# solution is within this of it (rad, or m times the robot's size for prismatic
# joints); the solver's own acceptance is 1e-9 on the pose.
ROUND_TRIP_TOL = 1e-6

# Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536, to hand freed memory
# back to the system; glibc would then map every large temporary afresh and ik_batch,
# which makes many of them per chunk, would run at a quarter to half speed. ik_batch sets
# glibc's thresholds itself on its first call in a process (kincalc.memory), so workers
# need no setting of their own.


# --- the recipe ----------------------------------------------------------------

def solution_dtype(robot) -> np.dtype:
    """The record of one pose's IK solutions: ``q (K, n)`` (rad / m) and ``valid (K,)``.

    ``K``, the number of solution slots, is fixed for a robot (8 for a PUMA or a
    UR arm, more for arms with more branches); a one-pose call finds it.
    Raises :class:`~kincalc.ik.solve.UnsupportedRobot` for robots ``ik_batch``
    does not solve (redundant arms, ...), before any work is sent.
    """
    K = robot.ik_batch(robot.fk(robot.home)[None]).q.shape[1]
    return np.dtype([("q", float, (K, robot.dof)), ("valid", bool, (K,))])


def _solve_block(T, robot, dtype):
    """``robot.ik_batch`` on one chunk of poses ``T (m, 4, 4)``, as records ``(m,)``."""
    out = np.empty(len(T), dtype)
    if len(T) == 0:
        return out
    sol = robot.ik_batch(T)
    if sol.valid.shape[1:] != dtype["valid"].shape:
        raise ValueError(f"ik_batch gave {sol.valid.shape[1]} solution slots on this chunk, "
                         f"{dtype['valid'].shape[0]} on the probe pose")
    out["q"] = sol.q
    out["valid"] = sol.valid
    return out


def solve_poses(robot, T):
    """Every IK solution of the poses ``T``, lazily, chunk by chunk.

    Parameters
    ----------
    robot : kincalc.Robot
        A robot that ``ik_batch`` supports; it is pickled into every task.
    T : dask.array.Array (N, 4, 4)
        Tool poses ``T_world_tool`` (m), chunked along the pose axis only.

    Returns
    -------
    q : dask.array.Array (N, K, n)
        Joint values (rad / m); slot k of pose i holds a solution where ``valid[i, k]``.
    valid : dask.array.Array (N, K) of bool
        Compute both with one ``dask.compute(q, valid)``: each chunk is solved once.
    """
    if T.ndim != 3 or T.shape[1:] != (4, 4) or T.numblocks[1:] != (1, 1):
        raise ValueError(f"T must be (N, 4, 4) chunked along the pose axis only, "
                         f"got shape {T.shape} with chunks {T.chunks}")
    dtype = solution_dtype(robot)
    sol = T.map_blocks(_solve_block, robot, dtype, drop_axis=(1, 2),
                       dtype=dtype, meta=np.empty((0,), dtype))
    return sol["q"], sol["valid"]


# --- the example job --------------------------------------------------------------

def _sample_block(index, robot, seed):
    """Configurations ``(m, n)`` for the pose numbers ``index (m,)`` of one chunk.

    The generator is seeded by ``(seed, first pose number)``, so a job draws the
    same poses whatever the cluster and the order the chunks run in.
    """
    if len(index) == 0:
        return np.empty((0, robot.dof))
    return sample_configurations(robot, len(index), np.random.default_rng([seed, int(index[0])]))


def _fk_block(Q, robot):
    return robot.fk(Q)


def random_job(robot, poses: int, chunk: int, seed: int = 0):
    """Lazy random configurations ``Q (N, n)`` within the limits and their poses ``T (N, 4, 4)``.

    Both are made on the workers, chunk by chunk (``chunk`` poses each): the
    client sends no data, only the robot.
    """
    index = da.arange(poses, chunks=chunk)
    n = robot.dof
    Q = index.map_blocks(_sample_block, robot, seed, new_axis=1, chunks=(index.chunks[0], (n,)),
                         dtype=float, meta=np.empty((0, n)))
    T = Q.map_blocks(_fk_block, robot, new_axis=2, chunks=(Q.chunks[0], (4,), (4,)),
                     dtype=float, meta=np.empty((0, 4, 4)))
    return Q, T


def round_trip_found(robot, Q, q, valid):
    """``(N,)`` bool, lazily: ``Q[i]`` is among pose i's valid solutions (revolute joints modulo 2 pi)."""
    d = q - Q[:, None, :]
    d = da.where(robot.is_revolute, (d + np.pi) % (2 * np.pi) - np.pi, d)
    tol = np.where(robot.is_revolute, 1.0, max(robot.characteristic_length, 1.0)) * ROUND_TRIP_TOL
    return (valid & (abs(d) < tol).all(axis=-1)).any(axis=-1)


def run_job(robot, poses: int, chunk: int, seed: int = 0) -> dict:
    """Sample, FK, solve and check ``poses`` poses on the current Dask scheduler; a summary dict.

    Only the summary comes back to the client; ``q`` and ``valid`` stay on the workers.
    """
    Q, T = random_job(robot, poses, chunk, seed)
    q, valid = solve_poses(robot, T)
    K = valid.shape[1]
    hist = da.bincount(valid.sum(axis=1), minlength=K + 1)
    found = round_trip_found(robot, Q, q, valid).sum()
    t0 = time.perf_counter()
    hist, found = dask.compute(hist, found)
    seconds = time.perf_counter() - t0
    return {
        "robot": robot.name,
        "family": robot.ik_batch(robot.fk(robot.home)[None]).family,
        "poses": poses,
        "chunk": chunk,
        "chunks": len(T.chunks[0]),
        "solution_slots": K,
        "seconds": round(seconds, 3),
        "poses_per_second": round(poses / seconds, 1),
        "solutions_per_pose": {str(k): int(c) for k, c in enumerate(hist) if c},
        "round_trip_found": round(int(found) / poses, 6),
    }


def workers_with_kincalc(client) -> dict:
    """``{worker address: kincalc version}``; raises on a worker without kincalc."""
    return client.run(lambda: importlib.import_module("kincalc.ik.engine") and kincalc.__version__)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--robot", default="ur5", help="bundled robot name or a YAML path (default ur5)")
    p.add_argument("--poses", type=int, default=1_000_000, help="number of random poses (default 1e6)")
    p.add_argument("--chunk", type=int, default=20_000, help="poses per task (default 20000)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="a running cluster's scheduler, e.g. tcp://host:8786 (default: a local cluster)")
    p.add_argument("--workers", type=int, default=os.cpu_count(),
                   help="local cluster only: single-threaded worker processes (default: one per core)")
    args = p.parse_args(argv)
    if args.poses < 1 or args.chunk < 1:
        p.error("--poses and --chunk must be positive")
    try:
        robot = kincalc.load_robot(args.robot)
        solution_dtype(robot)                   # unsupported robots fail here, before a cluster starts
    except kincalc.KincalcError as e:
        print(f"dask_batch: {e}", file=sys.stderr)
        return 2
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        # a Client made without an address starts a local cluster and closes it with itself
        client = Client(n_workers=args.workers, threads_per_worker=1, processes=True,
                        dashboard_address=None)
    with client:
        versions = workers_with_kincalc(client)
        summary = run_job(robot, args.poses, args.chunk, args.seed)
        summary["scheduler"] = client.scheduler.address
        summary["workers"] = len(versions)
        summary["threads"] = sum(client.nthreads().values())
    print(json.dumps(summary, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
