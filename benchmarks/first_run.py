"""A command's first run on a fresh install (numba's cache empty) beside the same command run again.

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/first_run.py [--only faults horizon] [--repeats 1]
[--top 15] [--check]``

A fresh install (and every fresh clone the tests run in) compiles the numba kernels on their first call; later runs
load them from numba's on-disk cache. Each repeat runs a command twice in child processes with ``NUMBA_CACHE_DIR``
pointing at a new empty folder: first cold (everything compiled), then warm (the same folder, everything loaded).
Printed per command: the wall time and the CPU seconds (user + system, of the child and its threads) of both runs
(the warm run is the peer: the same work without compiling), their ratio, the CPU seconds spent compiling (numba's
outermost ``numba:compile`` events: seismo3d's kernels with the helpers and numba library functions they pull in) and
how many seismo3d kernels and specialisations (one per signature) were compiled; then the seismo3d kernels that took
longest to compile, in CPU seconds, with their number of specialisations: with the helpers they call that were not
compiled yet (these overlap) and without them (these add up).

Commands (``--only``; all by default): ``faults`` (``seismo3d faults --demo``: the quick start), ``horizon``
(``seismo3d horizon f3_crop.sgy --seed 122,883,212``, the interchange guide's example), and every other command on the
inputs its guide uses (:func:`_commands`): ``register-volumes`` (segyio's f3.sgy onto f3_crop.sgy), ``register`` (the
bunny scans), ``map`` (30 frames of 7-Scenes), ``match`` (two TUM frames), ``lineaments`` and ``plan`` (the HydroSHEDS
DEM), ``render`` (f3_crop.sgy) and ``convert`` (f3_crop.sgy); all but ``faults`` need ``SEISMO3D_DATA_DIR``.
Targets (issue 58): every first run <= 2.5 x its second, ``faults --demo`` <= 20 s; ``--check`` exits 1 when one is
missed.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# the child: records every compile (dispatcher, signature, CPU seconds of its whole compile) and runs the command
_CHILD = r"""
import collections, json, sys, time
from numba.core import event

cpu = collections.defaultdict(float)
own = collections.defaultdict(float)
signatures = collections.defaultdict(list)


class Compiles(event.Listener):
    def __init__(self):
        self.started = []  # [start, CPU seconds of the compiles nested in it]

    def on_start(self, ev):
        self.started.append([time.process_time(), 0.0])

    def on_end(self, ev):
        d = ev.data["dispatcher"]
        t0, nested = self.started.pop()
        seconds = time.process_time() - t0
        name = f"{d.py_func.__module__}.{d.py_func.__qualname__}"
        cpu[name] += seconds
        own[name] += seconds - nested
        signatures[name].append(str(ev.data["args"]))
        if self.started:
            self.started[-1][1] += seconds
        else:  # outermost: nested compiles are inside it
            cpu["(all compiles, outermost)"] += seconds


event.register("numba:compile", Compiles())
from seismo3d.cli import app

record = sys.argv[1]
sys.argv = ["seismo3d"] + sys.argv[2:]
try:
    app()
except SystemExit as exc:
    if exc.code:
        raise
json.dump({"cpu": dict(cpu), "own": dict(own), "signatures": dict(signatures)}, open(record, "w"))
"""

FAULTS_LIMIT = 20.0  # s, the first run of faults --demo
RATIO_LIMIT = 2.5  # first run / second run


def _commands(out: Path) -> dict[str, list[str]]:
    """Each command with the inputs of the data folder its guide uses (docs/), its outputs in ``out``."""
    data = Path(os.environ.get("SEISMO3D_DATA_DIR", ""))
    seismic, terrain = data / "seismic", data / "terrain"
    dem = str(terrain / "dem_hydrosheds_dfw.tif")
    return {
        "faults": ["faults", "--demo", "-o", str(out / "faults")],
        "horizon": ["horizon", str(seismic / "f3_crop.sgy"), "--seed", "122,883,212", "-o", str(out / "h.txt")],
        # docs/guide/volumes.md: two SEG-Y sub-volumes (segyio's f3.sgy onto the F3 crop)
        "register-volumes": ["register", str(seismic / "segyio_test_data" / "f3.sgy"), str(seismic / "f3_crop.sgy"),
                             "-o", str(out / "volumes.json")],
        # docs/guide/registration.md: the Stanford bunny scans
        "register": ["register", str(data / "scans" / "bunny" / "bun045_clean.ply"),
                     str(data / "scans" / "bunny" / "bun000_clean.ply"), "-o", str(out / "bunny.json")],
        "map": ["map", str(data / "rgbd" / "7scenes_redkitchen_0000_0495"), "-o", str(out / "kitchen"),
                "--max-frames", "30"],
        "match": ["match", str(data / "rgbd" / "tum_fr1xyz_pair" / "img_prev.png"),
                  str(data / "rgbd" / "tum_fr1xyz_pair" / "img_curr.png"), "-o", str(out / "matches.csv")],
        "lineaments": ["lineaments", dem, "-o", str(out / "lineaments")],
        "plan": ["plan", dem, "--start", "40,40", "--goal", "300,320", "--max-slope", "3", "-o",
                 str(out / "path.csv")],
        "render": ["render", str(seismic / "f3_crop.sgy"), "-o", str(out / "f3_crop.png")],
        "convert": ["convert", str(seismic / "f3_crop.sgy"), str(out / "f3_crop.zarr")],
    }


COMMANDS = list(_commands(Path()))


def _run(cache: Path, work: Path, name: str, argv: list[str]) -> tuple[float, float, dict]:
    """Run once in a child; return its wall seconds, CPU seconds (user + system) and compile record."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    record = work / f"{name}.json"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", _CHILD, str(record)] + argv, env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, json.loads(record.read_text())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", default=COMMANDS, choices=COMMANDS,
                        help="commands measured (default: all)")
    parser.add_argument("--repeats", type=int, default=1, help="cold / warm pairs, each with a new empty cache")
    parser.add_argument("--top", type=int, default=15, help="kernels listed per command")
    parser.add_argument("--check", action="store_true", help="exit 1 when a target is missed")
    args = parser.parse_args()
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"{'command':>16} {'repeat':>6} {'cold s':>7} {'warm s':>7} {'ratio':>6} {'cold CPU':>9} {'warm CPU':>9} "
          f"{'CPU ratio':>9} {'compile CPU':>11} {'kernels':>7} {'specialisations':>15}")
    missed = []
    for command in args.only:
        kernels: dict[str, list[tuple[float, float, int]]] = {}
        for r in range(args.repeats):
            with tempfile.TemporaryDirectory() as tmp:
                tmp = Path(tmp)
                argv = _commands(tmp)[command]
                cold, cold_cpu, compiled = _run(tmp / "numba-cache", tmp, "cold", argv)
                argv = _commands(tmp / "again")[command]
                (tmp / "again").mkdir()
                warm, warm_cpu, again = _run(tmp / "numba-cache", tmp, "warm", argv)
            total = compiled["cpu"].pop("(all compiles, outermost)", 0.0)
            ours = {k: v for k, v in compiled["cpu"].items() if k.startswith("seismo3d")}
            n_specialisations = sum(len(compiled["signatures"][k]) for k in ours)
            print(f"{command:>16} {r + 1:>6} {cold:7.1f} {warm:7.1f} {cold / warm:6.2f} {cold_cpu:9.1f} "
                  f"{warm_cpu:9.1f} {cold_cpu / warm_cpu:9.2f} {total:11.1f} {len(ours):7d} {n_specialisations:15d}"
                  + (f"  (warm run compiled {again['cpu'].get('(all compiles, outermost)', 0.0):.1f} s)"
                     if again["cpu"] else ""))
            for k, v in ours.items():
                kernels.setdefault(k, []).append((v, compiled["own"][k], len(compiled["signatures"][k])))
            if cold / warm > RATIO_LIMIT:
                missed.append(f"{command}: first run {cold / warm:.2f} x the second (limit {RATIO_LIMIT})")
            if command == "faults" and cold > FAULTS_LIMIT:
                missed.append(f"faults --demo: first run {cold:.1f} s (limit {FAULTS_LIMIT:.0f} s)")
        print(f"  {command}: kernels that took longest to compile (CPU s with the kernels compiled inside it and "
              f"without them, median of {args.repeats}; specialisations)")
        ranked = sorted(kernels.items(), key=lambda kv: -sorted(kv[1])[len(kv[1]) // 2][0])
        for name, values in ranked[:args.top]:
            seconds, alone, n = sorted(values)[len(values) // 2]
            print(f"  {seconds:6.2f} {alone:6.2f}  {n:2d}  {name}")
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    if args.check and missed:
        print("missed: " + "; ".join(missed))
        sys.exit(1)


if __name__ == "__main__":
    main()
