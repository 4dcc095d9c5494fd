"""The quick start's first run: `seismo3d faults --demo` with numba's cache empty, beside the same command run again.

Run: ``python benchmarks/first_run.py [--repeats 2] [--top 15]``

A fresh install (and every fresh clone the tests run in) compiles the numba kernels on their first call; later runs
load them from numba's on-disk cache. Each repeat runs the command twice in child processes with ``NUMBA_CACHE_DIR``
pointing at a new empty folder: first cold (everything compiled), then warm (the same folder, everything loaded).
Printed: the wall time of both runs (the warm run is the peer: the same work without compiling), the CPU seconds
spent compiling (numba's outermost ``numba:compile`` events: seismo3d's kernels with the helpers and numba library
functions they pull in), and the seismo3d kernels that took longest to compile, in CPU seconds (a kernel's time
includes the helpers it calls that were not compiled yet, so these overlap).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# the child: records every compile (dispatcher, CPU seconds of its whole compile) and runs the command
_CHILD = r"""
import collections, json, sys, time
from numba.core import event

cpu = collections.defaultdict(float)


class Compiles(event.Listener):
    def __init__(self):
        self.started = {}
        self.depth = 0

    def on_start(self, ev):
        self.started[id(ev.data["dispatcher"])] = time.process_time()
        self.depth += 1

    def on_end(self, ev):
        d = ev.data["dispatcher"]
        t0 = self.started.pop(id(d), None)
        self.depth -= 1
        if t0 is not None:
            seconds = time.process_time() - t0
            cpu[f"{d.py_func.__module__}.{d.py_func.__qualname__}"] += seconds
            if self.depth == 0:  # outermost: nested compiles are inside it
                cpu["(all compiles, outermost)"] += seconds


event.register("numba:compile", Compiles())
from seismo3d.cli import app

out, record = sys.argv[1], sys.argv[2]
sys.argv = ["seismo3d", "faults", "--demo", "-o", out]
try:
    app()
except SystemExit as exc:
    if exc.code:
        raise
json.dump(dict(cpu), open(record, "w"))
"""


def _run(cache: Path, work: Path, name: str) -> tuple[float, dict]:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    record = work / f"{name}.json"
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", _CHILD, str(work / name), str(record)], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start, json.loads(record.read_text())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2, help="cold / warm pairs, each with a new empty cache")
    parser.add_argument("--top", type=int, default=15, help="kernels listed")
    args = parser.parse_args()
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"{'repeat':>6} {'cold s':>7} {'warm s':>7} {'compiling s':>14}")
    kernels: dict[str, list[float]] = {}
    for r in range(args.repeats):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = Path(tmp)
            cold, compiled = _run(tmp / "numba-cache", tmp, "cold")
            warm, again = _run(tmp / "numba-cache", tmp, "warm")
        total = compiled.pop("(all compiles, outermost)", 0.0)
        print(f"{r + 1:>6} {cold:7.1f} {warm:7.1f} {total:14.1f}"
              + (f"  (warm run compiled {again.get('(all compiles, outermost)', 0.0):.1f} s)" if again else ""))
        for k, v in compiled.items():
            if k.startswith("seismo3d"):
                kernels.setdefault(k, []).append(v)
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"\nkernels that took longest to compile (CPU s, median of {args.repeats}):")
    ranked = sorted(kernels.items(), key=lambda kv: -sorted(kv[1])[len(kv[1]) // 2])
    for name, values in ranked[:args.top]:
        print(f"  {sorted(values)[len(values) // 2]:6.2f}  {name}")


if __name__ == "__main__":
    main()
