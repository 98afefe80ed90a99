"""End-to-end `kincalc ik ROBOT --batch` throughput, and where the time goes.

    python benchmarks/batch_cli.py [--poses 50000] [--robot puma560] [--jobs 1 2]

Writes N poses (JSON lines, xyz + rpy in degrees) to a temporary file, then times whole
CLI runs (median of --repeat) with each --jobs value, and, in this process, the stages of
one run on the same records: reading the JSON, building the poses, the batched IK,
the branch labels and limit flags, and writing the output. The same-run reference is
`python -c "import json; [json.loads(l) for l in open(F)]"` (reading the input alone).
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
from kincalc.cli.batch import chunks, formats, records, runner  # noqa: E402
from kincalc.ik.selftest import sample_configurations  # noqa: E402
from kincalc.spatial import rpy_from_matrix  # noqa: E402


def wall(cmd, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, check=False)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--poses", type=int, default=50_000)
    ap.add_argument("--robot", default="puma560")
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    r = kincalc.load_robot(args.robot)
    T = r.fk(sample_configurations(r, args.poses, np.random.default_rng(0)))
    rpy = np.degrees(rpy_from_matrix(T[:, :3, :3]))
    fd, path = tempfile.mkstemp(suffix=".jsonl")
    with os.fdopen(fd, "w") as f:
        for t, a in zip(T, rpy):
            f.write(json.dumps({"xyz": t[:3, 3].round(9).tolist(), "rpy": a.round(9).tolist()})
                    + "\n")
    exe = os.path.join(os.path.dirname(sys.executable), "kincalc")
    cmd = [exe] if os.path.exists(exe) else [sys.executable, "-c",
                                              "import sys; from kincalc.cli.main import main; "
                                              "sys.exit(main())"]
    ref = wall([sys.executable, "-c", f"import json; [json.loads(l) for l in open({path!r})]"],
               args.repeat)
    print(f"{args.poses} poses of {args.robot}; reading the JSON alone: {ref:.2f} s")
    print(f"{'run':28s} {'wall s':>8s} {'poses/s':>10s} {'x reading':>10s}")
    for jobs in args.jobs:
        t = wall(cmd + ["ik", args.robot, "--batch", path, "--jobs", str(jobs)], args.repeat)
        print(f"{'kincalc ik --batch -j ' + str(jobs):28s} {t:8.2f} {args.poses / t:10.0f} "
              f"{t / ref:10.2f}")
    # stages, in this process, on the same records
    with open(path, "rb") as fh:                  # records as the reader gives them: bytes
        lines = fh.read().splitlines()
    from kincalc.cli.common import display_units
    units = display_units(r, True, None)
    stages = dict.fromkeys(["read JSON records", "build poses (vectorised)", "ik_batch",
                            "limit flags + branch labels", "write JSON lines"], 0.0)

    def timed(name, f, *a):
        t = time.perf_counter()
        out = f(*a)
        stages[name] += time.perf_counter() - t
        return out

    # the stages chunk by chunk, as the CLI runs them (the sizes and caches matter)
    for k in range(0, len(lines), runner.CHUNK_LINES):
        chunk = lines[k:k + runner.CHUNK_LINES]
        parsed = timed("read JSON records", records.parse_records, None, r, k, chunk)
        full, Tq, _, _ = timed("build poses (vectorised)", chunks._poses, r, units, parsed)
        B = timed("ik_batch", r.ik_batch, Tq)
        q = B.q[B.valid]
        owner, _ = np.nonzero(B.valid)
        within = timed("limit flags + branch labels", lambda: B.within[B.valid])
        labels = timed("limit flags + branch labels", lambda: B.labels[B.valid].tolist())
        timed("write JSON lines", formats.solutions_json, np.round(q, 12), labels, within,
              owner, len(full))
    # the whole of the same work (chunks parsed, solved and written as the CLI does)
    t0 = time.perf_counter()
    for k in range(0, len(lines), runner.CHUNK_LINES):
        chunks.process_chunk("ik", r, units, None, "jsonl", "base",
                            (k, lines[k:k + runner.CHUNK_LINES]))
    whole = time.perf_counter() - t0
    stages["the rest (records, output lines)"] = whole - sum(stages.values())
    print(f"\nstages of one run, in-process ({whole:.2f} s, {args.poses / whole:.0f} poses/s):")
    for name, t in stages.items():
        print(f"  {name:28s} {t:6.2f} s  {t / args.poses * 1e6:7.1f} us/pose  "
              f"{100 * t / whole:5.1f} %")
    os.unlink(path)


if __name__ == "__main__":
    main()
