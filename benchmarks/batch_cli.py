"""End-to-end `kincalc ik ROBOT --batch` throughput, against the standard json module.

    python benchmarks/batch_cli.py [--poses 50000] [--robot puma560] [--jobs 1 2] [--repeat 3]

Writes N poses (JSON lines, xyz + rpy in degrees) to a temporary file, then times whole
CLI runs (median of --repeat) with each --jobs value and, in the same run, the floor of
the issue: the standard json module alone parsing the same input (json.loads a line) and
writing the same output documents kincalc writes (json.dumps a document, the documents
being kincalc's own output lines read back; their text is checked to be kincalc's). The
floor is timed in this process, without an interpreter's start, alternating with the CLI
runs; kincalc's ratio to it is the issue's measure (target: at most 0.6).

The CLI runs with a warm bytecode cache (in a temporary PYTHONPYCACHEPREFIX), as an
installed kincalc does: without one (PYTHONDONTWRITEBYTECODE=1) every run compiles its
modules again, ~0.1 s. --no-bytecode-cache measures that case.

Then, in this process, the stages of one run on the same records: reading the JSON,
building the poses, the batched IK, the branch labels and limit flags, and writing the
output.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import kincalc  # noqa: E402
from kincalc.cli.batch import chunks, records, runner  # noqa: E402
from kincalc.cli.batch.poses import record_poses  # noqa: E402
from kincalc.ik.selftest import sample_configurations  # noqa: E402
from kincalc.spatial import rpy_from_matrix  # noqa: E402


def run_once(cmd, env):
    t0 = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, check=False, env=env)
    return time.perf_counter() - t0


def json_floor(path, docs):
    """Seconds the json module takes to read every input line and write every document."""
    t0 = time.perf_counter()
    with open(path, "rb") as f:
        for line in f:
            json.loads(line)
    with open(os.devnull, "w") as out:
        out.write("".join([json.dumps(d) + "\n" for d in docs]))
    return time.perf_counter() - t0


def cli_env(bytecode_cache: bool, prefix: str) -> dict:
    env = dict(os.environ)
    if bytecode_cache:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = prefix
    else:
        env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--poses", type=int, default=50_000)
    ap.add_argument("--robot", default="puma560")
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-bytecode-cache", action="store_true")
    args = ap.parse_args()
    r = kincalc.load_robot(args.robot)
    T = r.fk(sample_configurations(r, args.poses, np.random.default_rng(0)))
    rpy = np.degrees(rpy_from_matrix(T[:, :3, :3]))
    tmp = tempfile.mkdtemp()
    path = os.path.join(tmp, "poses.jsonl")
    with open(path, "w") as f:
        for t, a in zip(T, rpy):
            f.write(json.dumps({"xyz": t[:3, 3].round(9).tolist(), "rpy": a.round(9).tolist()})
                    + "\n")
    exe = os.path.join(os.path.dirname(sys.executable), "kincalc")
    cmd = [exe] if os.path.exists(exe) else [sys.executable, "-c",
                                              "import sys; from kincalc.cli.main import main; "
                                              "sys.exit(main())"]
    env = cli_env(not args.no_bytecode_cache, os.path.join(tmp, "pycache"))
    # kincalc's output, read back: the documents the floor writes
    out = subprocess.run(cmd + ["ik", args.robot, "--batch", path], capture_output=True,
                         env=env, check=False).stdout.decode()
    docs = [json.loads(line) for line in out.splitlines()]
    same = "".join(json.dumps(d) + "\n" for d in docs) == out
    floors, walls = [], {jobs: [] for jobs in args.jobs}
    for _ in range(args.repeat):                  # alternating, for a noisy machine
        floors.append(json_floor(path, docs))
        for jobs in args.jobs:
            walls[jobs].append(run_once(cmd + ["ik", args.robot, "--batch", path, "--jobs",
                                               str(jobs)], env))
    floor = statistics.median(floors)
    print(f"{args.poses} poses of {args.robot} ({len(out) / args.poses:.0f} bytes of output a "
          f"pose); bytecode cache: {'no' if args.no_bytecode_cache else 'yes'}")
    print(f"json floor (json.loads each input line + json.dumps each output document): "
          f"{floor:.3f} s{'' if same else ' (json.dumps text differs from kincalc output!)'}")
    print(f"{'run':28s} {'wall s':>8s} {'poses/s':>10s} {'x floor':>8s}")
    for jobs in args.jobs:
        t = statistics.median(walls[jobs])
        print(f"{'kincalc ik --batch -j ' + str(jobs):28s} {t:8.3f} {args.poses / t:10.0f} "
              f"{t / floor:8.2f}")
    del docs, out                                 # (a million objects: the collector's work)
    stages_in_process(r, path, args.poses)
    for name in os.listdir(tmp):
        if name != "pycache":
            os.unlink(os.path.join(tmp, name))


def stages_in_process(r, path, poses):
    """The stages of one run, in this process, on the same records, chunk by chunk as the
    CLI runs them (the sizes and caches matter)."""
    with open(path, "rb") as fh:                  # records as the reader gives them: bytes
        lines = fh.read().splitlines()
    from kincalc.cli.common import display_units
    units = display_units(r, True, None)
    qdisp = np.where(r.is_revolute, units.a, units.l)
    stages = dict.fromkeys(["read JSON records", "build poses (vectorised)", "ik_batch",
                            "limit flags + branch labels", "singular flags",
                            "write JSON lines"], 0.0)

    def timed(name, f, *a):
        t = time.perf_counter()
        out = f(*a)
        stages[name] += time.perf_counter() - t
        return out

    for k in range(0, len(lines), runner.CHUNK_LINES):
        chunk = lines[k:k + runner.CHUNK_LINES]
        parsed, together = timed("read JSON records", records.parse_chunk, None, r, k, chunk)
        full, Tq, _, _ = timed("build poses (vectorised)", record_poses, r, units, parsed,
                               together, k)
        B = timed("ik_batch", r.ik_batch, Tq)
        q = np.round(B.q[B.valid] * qdisp, 12) + 0.0
        owner, _ = np.nonzero(B.valid)
        within = timed("limit flags + branch labels", lambda: B.within[B.valid])
        labels = timed("limit flags + branch labels", lambda: B.labels[B.valid].tolist())
        singular = timed("singular flags", lambda: B.singular[B.valid])
        answers = chunks.Answers(full, q, labels, within, singular, owner)
        timed("write JSON lines", chunks._ik_text, k, len(chunk), answers, [])
    # the whole of the same work (chunks parsed, solved and written as the CLI does)
    t0 = time.perf_counter()
    for k in range(0, len(lines), runner.CHUNK_LINES):
        chunks.process_chunk("ik", r, units, None, "jsonl", "base",
                             (k, lines[k:k + runner.CHUNK_LINES]))
    whole = time.perf_counter() - t0
    stages["the rest (records, output lines)"] = whole - sum(stages.values())
    print(f"\nstages of one run, in-process ({whole:.2f} s, {poses / whole:.0f} poses/s):")
    for name, t in stages.items():
        print(f"  {name:34s} {t:6.3f} s  {t / poses * 1e6:7.1f} us/pose  "
              f"{100 * t / whole:5.1f} %")


if __name__ == "__main__":
    main()
