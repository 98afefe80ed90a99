"""CLI start-up: kincalc wall time against importing its dependencies, same run.

    python benchmarks/startup.py [--repeat 21]

Run it with the interpreter of a normal (non-editable) install: ``pip install .``
writes kincalc's bytecode, an editable install may not (a warning is printed).
Prints the median wall time of each command over interleaved repetitions and
the ratios kincalc/reference (targets: fk --json <= 1.3 x the dependency
import; --help and --version <= 1.5 x `import typer`).
"""

import argparse
import shutil
import statistics
import subprocess
import sys
import time

PY = sys.executable
KINCALC = shutil.which("kincalc") or f"{PY} -m kincalc"

CASES = {
    "deps": [PY, "-c", "import numpy, typer, rich, yaml"],
    "typer": [PY, "-c", "import typer"],
    "fk": [*KINCALC.split(), "fk", "puma560", "0", "-45", "180", "0", "45", "0", "--json"],
    "jacobian": [*KINCALC.split(), "jacobian", "puma560", "0", "-45", "180", "0", "45", "0", "--json"],
    "ik": [*KINCALC.split(), "ik", "puma560", "--from-q", "0 -45 180 0 45 0", "--json"],
    "help": [*KINCALC.split(), "--help"],
    "version": [*KINCALC.split(), "--version"],
}
RATIOS = [("ik", "deps", 1.3), ("fk", "deps", 1.3), ("jacobian", "deps", 1.3), ("help", "typer", 1.5),
          ("version", "typer", 1.5)]


def _bytecode_warning() -> str | None:
    """Start-up is only meaningful with kincalc's bytecode cached (a normal ``pip install``
    writes it; an editable install under PYTHONDONTWRITEBYTECODE compiles every module on
    every run, about 40 ms here)."""
    import importlib.util
    from pathlib import Path
    spec = importlib.util.find_spec("kincalc")
    cache = Path(spec.origin).parent / "__pycache__" if spec and spec.origin else None
    if cache is None or not any(cache.glob("*.pyc")):
        return (f"warning: no bytecode cache in {cache}: every run recompiles kincalc "
                "(editable install with PYTHONDONTWRITEBYTECODE?); measure a `pip install .`")
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=21)
    args = ap.parse_args()
    warning = _bytecode_warning()
    if warning:
        print(warning, file=sys.stderr)
    times = {k: [] for k in CASES}
    for _ in range(args.repeat):          # interleaved, so drift hits every case alike
        for name, cmd in CASES.items():
            t0 = time.perf_counter()
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
            times[name].append(time.perf_counter() - t0)
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"{'command':10s} {'median ms':>10s}")
    for k, v in med.items():
        print(f"{k:10s} {v * 1000:10.1f}")
    print()
    print(f"{'ratio':22s} {'value':>6s} {'target':>7s}")
    for a, b, target in RATIOS:
        r = med[a] / med[b]
        print(f"{a + ' / ' + b:22s} {r:6.2f} {target:7.2f} {'ok' if r <= target else 'OVER'}")


if __name__ == "__main__":
    main()
