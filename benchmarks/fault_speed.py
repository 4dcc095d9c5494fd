"""The whole ``seismo3d faults`` command step by step beside FaultNet's fault probability on the same generated cube,
in CPU seconds and wall seconds, and per GB (issue 76).

Run: ``SEISMO3D_DATA_DIR=../shared/data python benchmarks/fault_speed.py [--shapes 256 512x512x256] [--by-blocks]
[--repeats N] [--check]``

For each shape (``256``: 256^3; ``512x512x256``: 512 x 512 x 256) a generated faulted cube
(:func:`~seismo3d.data.synthetic.synthetic_cube`, seed 0, noise 0.1) is saved as ``.npy`` and, back to back, each in
a process of its own on 2 threads (numba, ONNX Runtime and torch: ``NUMBA_NUM_THREADS``, ``OMP_NUM_THREADS``,
``torch.set_num_threads``):

- ``seismo3d faults``: the job of the command (:func:`~seismo3d.jobs.faults.run_faults_job`, its defaults: read the
  ``.npy``, trace, write every output), in memory, and with ``--by-blocks`` by blocks under a memory limit of half of
  what its run in memory needs, or the least limit the job names when it refuses that one (on 256^3: its smallest
  blocks and the writers beside the process need more; the refusal comes before any pass over the cube, and the
  column's title gives the limit used; the executor of :mod:`seismo3d.seismic.blocks`); numba's kernels compiled on
  a small cube first, outside the measurement. Its steps: the job's own wall seconds per step
  (``stage_seconds``: read input, fault likelihood, ridges, voting, thinning, fault skins, throw, evidence, write
  outputs) and, in memory, the CPU seconds of the process over each step of the tracing and each file written (a
  row each under the writing, largest first; ``time.process_time`` read at each step's start and end by a wrapper of
  the job's step timer that this script installs in the worker; the rest: reading and the checks before the
  tracing). Under the fault likelihood, its own steps' CPU seconds in memory (each declared step of
  :func:`~seismo3d.seismic.faults.likelihood.learned.block_steps`: the network per grid and direction, then strike
  and dip), and of the network steps' the CPU seconds inside ONNX Runtime (the rest: resampling onto the network
  grid, scaling, the interpolation between sections). By blocks the steps run on dask's threads: only the whole
  job's CPU seconds are shown;
- FaultNet (Dou et al. 2022, its released TorchScript weights, ``benchmarks/faultnet.py``): its fault probability of
  the same cube, the network alone (the cube in memory; torch loaded and one small cube run first).

The machine may be shared: the CPU seconds of a process (all its threads) move little when other jobs load the
cores, its wall seconds a lot, so the comparison and ``--check`` use CPU seconds. On a virtual machine whose speed
changes from minute to minute (the same run's CPU seconds 21.5 and 31.1 half an hour apart), ``--repeats N`` runs
ours and the peer back to back N times per shape: the tables show the runs of median CPU seconds, each round's ratio
is printed, and the checks compare the medians. s/GB: seconds per 10^9 bytes of
the cube in float32 (256^3: 0.067 GB).

``--check`` asserts the targets of issue 76 in CPU seconds, on each shape run: the whole command in no more than
FaultNet's probability, the fault likelihood in no more than half of it; and, when both shapes run, the command's
CPU s/GB at 512 x 512 x 256 within 15 % of 256^3's, in memory and (with ``--by-blocks``) by blocks. Exit 1 when one
is missed. With both shapes, the runs in memory are also split (printed, not checked): the steps that follow the
cube's volume per GB, those that follow the faults' area (skins, throw, evidence) per million fault points, and the
writing; a generated cube's faults span its height, so 512 x 512 x 256 holds about twice 256^3's fault points for
four times its samples.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

THREADS = 2
TARGETS = {"command": 1.0, "likelihood": 0.5, "growth": 0.15}  # issue 76, in CPU seconds
# the job's steps in its order (FaultsJobResult.stage_seconds); by blocks the executor's steps replace the middle
STEPS = ("read input", "fault likelihood", "ridges", "voting", "thinning", "fault skins", "throw", "evidence",
         "write outputs")


def _shape(text: str) -> tuple:
    parts = [int(p) for p in text.lower().split("x")]
    return tuple(parts * 3) if len(parts) == 1 else tuple(parts)


def _gb(shape) -> float:
    return 4.0 * float(np.prod(shape)) / 1e9


_TRACING = {"bar": None}  # the bar of the fault tracing's steps in the run measured (None before they start)


def _cpu_per_step():
    """Wrap the job's step timer (:mod:`seismo3d._progress`) so that each named step's CPU seconds of the process are
    recorded beside its wall seconds, and each file's the job writes after them; the stages a step reports within
    it (:func:`~seismo3d._progress.progress_within`) stay in their step's. Returns the dict they are added to."""
    from seismo3d import _progress

    cpu: dict = {}
    start, stop = _progress._Steps.start, _progress._Steps.stop

    def timed_stop(self):
        running = getattr(self, "_cpu_running", None)
        if running is not None:
            cpu[running[0]] = cpu.get(running[0], 0.0) + time.process_time() - running[1]
            self._cpu_running = None
        stop(self)

    def timed_start(self, label):
        start(self, label)  # calls stop (timed) first
        if label in STEPS:
            _TRACING["bar"] = self
        # the tracing's steps, and the files written after them; not the stages a step reports within it (timed in
        # the step's), nor those of the sample judged before it (in the rest)
        tracing = _TRACING["bar"]
        if label in STEPS or (tracing is not None and tracing._running is None):
            self._cpu_running = (label, time.process_time())

    _progress._Steps.start, _progress._Steps.stop = timed_start, timed_stop
    return cpu


def _cpu_in_likelihood():
    """Wrap the run in memory's step runner and the fault network's call so that the CPU seconds of the process in
    each declared step of the likelihood (by its label) and inside ONNX Runtime are recorded; returns the dict they
    are added to (``'ONNX Runtime'``: the network's calls)."""
    from seismo3d.seismic.blocks.executor import MemoryRun
    from seismo3d.seismic.faults.likelihood.network import FaultNetwork

    cpu: dict = {}
    run_step, call = MemoryRun.run_step, FaultNetwork.__call__

    def timed(key, function, *args, **kwargs):
        t0 = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            cpu[key] = cpu.get(key, 0.0) + time.process_time() - t0

    MemoryRun.run_step = lambda self, step, *a, **k: timed(step.label or step.name, run_step, self, step, *a, **k)
    FaultNetwork.__call__ = lambda self, x: timed("ONNX Runtime", call, self, x)
    return cpu


def _ours(path: str, limit: str | None) -> dict:
    from seismo3d.errors import InputError
    from seismo3d.jobs.faults import run_faults_job

    cpu = _cpu_per_step()
    inner = _cpu_in_likelihood()
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as tmp:
        small = Path(tmp) / "warmup.npy"
        np.save(small, np.ascontiguousarray(np.load(path, mmap_mode="r")[:48, :48, :64]))
        run_faults_job(small, Path(tmp) / "warmup", progress=False)  # numba's kernels compiled outside the measurement
        cpu.clear()
        _TRACING["bar"] = None
        inner.clear()
        while True:
            t_wall, t_cpu = time.perf_counter(), time.process_time()
            try:
                res = run_faults_job(path, Path(tmp) / "out", progress=False, memory_limit=limit)
                break
            except InputError as exc:  # by blocks: refused below the least limit its run needs, which it names
                limit = _named_limit(exc, limit)
        wall, total = time.perf_counter() - t_wall, time.process_time() - t_cpu
        if limit is not None and "surfaces_zarr" not in res.written:  # its Zarr stores: a run by blocks
            raise SystemExit(f"the run under memory_limit={limit} ran in memory, not by blocks")
    likelihood = {k: v for k, v in inner.items()  # the likelihood's steps (the later steps run on MemoryRun too)
                  if k.startswith("fault network") or k in ("fault orientation", "ONNX Runtime")}
    return {"wall": wall, "cpu": total, "steps": dict(res.stage_seconds), "cpu_steps": cpu if limit is None else {},
            "cpu_likelihood": likelihood if limit is None else {}, "limit": limit,
            "fault_points": sum(int(row["n_points"]) for row in res.faults)}


def _named_limit(exc, limit: str | None) -> str:
    """The least memory limit the job names when it refuses ``limit`` as below what a run by blocks of the cube needs
    (its smallest blocks, the fault cells a sample of its blocks predicts, the writers: refused after the sample, in
    seconds, before any pass over the cube; on 256^3 half of the run in memory is below it); else ``exc`` raised."""
    named = re.search(r"pass memory_limit='([^']+)' or more", str(exc))
    if limit is None or named is None or named.group(1) == limit:
        raise exc
    return named.group(1)


def _faultnet(path: str) -> dict:
    from faultnet import faultnet_probability, load_faultnet  # benchmarks/faultnet.py: the peer

    net = load_faultnet(THREADS)
    if net is None:
        return {}
    cube = np.load(path)
    faultnet_probability(net, cube[:32, :32, :32])  # torch's first call outside the measurement
    t_wall, t_cpu = time.perf_counter(), time.process_time()
    faultnet_probability(net, cube)
    return {"wall": time.perf_counter() - t_wall, "cpu": time.process_time() - t_cpu}


def _run(what: str, path: Path, limit: str | None = None) -> dict:
    env = dict(os.environ, NUMBA_NUM_THREADS=str(THREADS), OMP_NUM_THREADS=str(THREADS))
    proc = subprocess.run([sys.executable, __file__, "--worker", what, str(path), limit or ""], capture_output=True,
                          text=True, check=False, env=env, cwd=Path(__file__).parent)
    if proc.returncode != 0:
        raise SystemExit(f"{what} on {path.name} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _blocks_limit(shape) -> str:
    """A memory limit half of what the cube's run in memory needs: a run by blocks (the job names a larger one when its
    smallest blocks need more, :func:`_named_limit`)."""
    from seismo3d.seismic.blocks.memory import in_memory_bytes

    return f"{in_memory_bytes(shape) // 2 >> 20}MB"


def _step_cpu(run: dict, step: str) -> float | None:
    """CPU seconds of one of the job's steps (None when not timed): the writing's are those of the files it writes,
    each a step of its own."""
    cpu = run["cpu_steps"]
    if step == "write outputs" and cpu:
        return sum(v for k, v in cpu.items() if k not in run["steps"])
    return cpu.get(step)


def _print_files(runs: dict, gb: float) -> None:
    """The writing's rows, a file (or store) each, named "write KEY" (apart from the steps by blocks named as the
    files they compute, e.g. "surfaces", "votes"): CPU seconds of the runs in memory, largest first."""
    files = {}
    for label, r in runs.items():
        for key, cpu in r["cpu_steps"].items():
            if key not in r["steps"]:
                files.setdefault(key, {})[label] = cpu
    for key in sorted(files, key=lambda k: -max(files[k].values())):
        row = f"{'  write ' + key:40s}"
        for label in runs:
            cpu = files[key].get(label)
            row += f" | {'':8s} " + (f"{cpu:8.1f} {cpu / gb:9.0f}" if cpu is not None else f"{'':8s} {'':9s}")
        print(row)


def _print_likelihood(runs: dict, gb: float) -> None:
    """The fault likelihood's rows, a declared step each, then the network's CPU seconds inside ONNX Runtime and
    outside it (resampling, scaling, interpolation between sections): CPU seconds of the runs in memory."""
    rows: dict = {}
    for label, r in runs.items():
        inner = r.get("cpu_likelihood", {})
        for key, cpu in inner.items():
            if key != "ONNX Runtime":
                rows.setdefault("  " + key, {})[label] = cpu
        if inner:
            network = sum(v for k, v in inner.items() if k.startswith("fault network"))
            rows.setdefault("  network: inside ONNX Runtime", {})[label] = inner.get("ONNX Runtime", 0.0)
            rows.setdefault("  network: outside it", {})[label] = network - inner.get("ONNX Runtime", 0.0)
    for key, cpus in rows.items():
        row = f"{key:40s}"
        for label in runs:
            cpu = cpus.get(label)
            row += f" | {'':8s} " + (f"{cpu:8.1f} {cpu / gb:9.0f}" if cpu is not None else f"{'':8s} {'':9s}")
        print(row)


def _median_run(runs: list) -> dict:
    """The run of median CPU seconds (the lower of the middle two of an even count)."""
    return sorted(runs, key=lambda r: r["cpu"])[(len(runs) - 1) // 2]


def profile(shape, by_blocks: bool, repeats: int = 1) -> dict:
    """Ours (in memory, and by blocks when asked) and FaultNet on one generated cube, back to back, ``repeats``
    rounds; the table of the runs of median CPU seconds printed, each round's ratios, the CPU seconds returned."""
    from seismo3d.data.synthetic import synthetic_cube

    rounds = []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cube.npy"
        np.save(path, synthetic_cube(shape, seed=0, noise=0.1).cube)
        for _ in range(repeats):  # each round ours then the peer: a change of the machine's speed hits both
            one = {"in memory": _run("ours", path)}
            if by_blocks:
                one["by blocks"] = _run("ours", path, _blocks_limit(shape))
            one["peer"] = _run("faultnet", path)
            rounds.append(one)
    runs = {"in memory": _median_run([r["in memory"] for r in rounds])}
    if by_blocks:
        blocks = _median_run([r["by blocks"] for r in rounds])
        runs[f"by blocks ({blocks['limit']})"] = blocks
    peer = _median_run([r["peer"] for r in rounds]) if rounds[0]["peer"] else {}
    gb = _gb(shape)
    name = " x ".join(map(str, shape))
    median = f", the runs of median CPU seconds of {repeats} rounds" if repeats > 1 else ""
    print(f"\n`seismo3d faults` on a generated {name} faulted cube ({gb:.3f} GB float32), {THREADS} threads, load "
          f"average {os.getloadavg()[0]:.1f}{median}: wall and CPU seconds (the process's, all threads), and CPU "
          f"s/GB; {runs['in memory']['fault_points']:,} fault points\n")
    labels = list(runs)
    head = f"{'step':40s}" + "".join(f" | {label:>27s}" for label in labels)
    sub = f"{'':40s}" + "".join(f" | {'wall s':>8s} {'CPU s':>8s} {'CPU s/GB':>9s}" for _ in labels)
    print(head + "\n" + sub + "\n" + "-" * len(sub))
    names = []
    for r in runs.values():
        names += [k for k in r["steps"] if k not in names]
    for step in names:
        row = f"{step:40s}"
        for r in runs.values():
            wall, cpu = r["steps"].get(step), _step_cpu(r, step)
            row += (f" | {wall:8.1f} " if wall is not None else f" | {'':8s} ")
            row += f"{cpu:8.1f} {cpu / gb:9.0f}" if cpu is not None else f"{'':8s} {'':9s}"
        print(row)
        if step == "fault likelihood":
            _print_likelihood(runs, gb)
        if step == "write outputs":
            _print_files(runs, gb)
    rest = ""  # the CPU seconds outside the timed steps: reading, the job's checks
    for r in runs.values():
        cpu = r["cpu"] - sum(r["cpu_steps"].values()) if r["cpu_steps"] else None
        rest += f" | {'':8s} {cpu:8.1f} {cpu / gb:9.0f}" if cpu is not None else f" | {'':8s} {'':8s} {'':9s}"
    print(f"{'read input and the rest (CPU)':40s}{rest}")
    print(f"{'whole command':40s}" + "".join(f" | {r['wall']:8.1f} {r['cpu']:8.1f} {r['cpu'] / gb:9.0f}"
                                             for r in runs.values()))
    if not peer:
        from faultnet import NOT_RUN

        print(NOT_RUN)
        return {"ours": runs["in memory"], "peer": None}
    print(f"{'FaultNet probability (peer)':40s} | {peer['wall']:8.1f} {peer['cpu']:8.1f} {peer['cpu'] / gb:9.0f}")
    ours = runs["in memory"]
    if repeats > 1:  # each round's whole command over its own peer's
        print("each round, the whole command over FaultNet: CPU " + " ".join(
            f"{r['in memory']['cpu'] / r['peer']['cpu']:.2f}" for r in rounds) + "; wall " + " ".join(
            f"{r['in memory']['wall'] / r['peer']['wall']:.2f}" for r in rounds))
    likelihood = ours["cpu_steps"].get("fault likelihood", float("nan"))
    print(f"ratios to FaultNet in CPU seconds: whole command {ours['cpu'] / peer['cpu']:.2f} (target <= "
          f"{TARGETS['command']:.2f}), fault likelihood {likelihood / peer['cpu']:.2f} (target <= "
          f"{TARGETS['likelihood']:.2f}); in wall seconds {ours['wall'] / peer['wall']:.2f} and "
          f"{ours['steps'].get('fault likelihood', float('nan')) / peer['wall']:.2f}")
    return {"ours": ours, "peer": peer, "gb": gb, "blocks": [r for k, r in runs.items() if k != "in memory"]}


# the steps whose work follows the faults' area (their points) rather than the cube's volume (a generated cube's
# faults span its height: x2 points for a cube x4 larger laterally)
FAULT_STEPS = ("fault skins", "throw", "evidence")


def _print_growth_parts(results: dict) -> None:
    """Beside the growth per GB, the runs in memory split: the CPU seconds of the steps that follow the cube's volume
    (reading, the likelihood, ridges, voting, thinning, the rest) per GB, of those that follow the faults' area
    (:data:`FAULT_STEPS`) per million fault points, and the writing (volumes, fault files and the picture) apart."""
    parts = {"volume steps, CPU s/GB": [], "fault steps, CPU s per million fault points": [],
             "writing, CPU s/GB": []}
    points = []
    for r in results.values():
        run = r["ours"]
        fault = sum(_step_cpu(run, s) or 0.0 for s in FAULT_STEPS)
        writing = _step_cpu(run, "write outputs") or 0.0
        parts["volume steps, CPU s/GB"].append((run["cpu"] - fault - writing) / r["gb"])
        parts["fault steps, CPU s per million fault points"].append(fault / run["fault_points"] * 1e6)
        parts["writing, CPU s/GB"].append(writing / r["gb"])
        points.append(run["fault_points"])
    print(f"  fault points: {', '.join(f'{n:,}' for n in points)}")
    for name, values in parts.items():
        print(f"  {name}: {', '.join(f'{v:.0f}' for v in values)} ({max(values) / min(values) - 1.0:.0%} apart)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shapes", nargs="+", default=["256"], help="cube shapes: N (N^3) or NIxNXxNS (default: 256)")
    ap.add_argument("--by-blocks", action="store_true", help="also the run by blocks under half of its memory")
    ap.add_argument("--check", action="store_true", help="exit 1 when a target of issue 76 is missed (CPU seconds)")
    ap.add_argument("--repeats", type=int, default=1,
                    help="rounds of ours then FaultNet per shape; the runs of median CPU seconds are compared")
    ap.add_argument("--worker", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        what, path, limit = args.worker
        print(json.dumps(_ours(path, limit or None) if what == "ours" else _faultnet(path)))
        return 0
    if args.repeats < 1:
        ap.error(f"--repeats must be 1 or more; got {args.repeats}")
    results = {tuple(_shape(s)): profile(_shape(s), args.by_blocks, args.repeats) for s in args.shapes}
    ok = True
    for shape, r in results.items():
        if r["peer"] is None:
            ok = False
            continue
        ratio = r["ours"]["cpu"] / r["peer"]["cpu"]
        lk = r["ours"]["cpu_steps"].get("fault likelihood", float("inf")) / r["peer"]["cpu"]
        ok &= ratio <= TARGETS["command"] and lk <= TARGETS["likelihood"]
    if len(results) > 1:
        ways = {"in memory": [r["ours"] for r in results.values()]}
        if args.by_blocks:
            ways["by blocks"] = [r["blocks"][0] for r in results.values()]
        for way, runs in ways.items():
            per_gb = [run["cpu"] / r["gb"] for run, r in zip(runs, results.values())]
            growth = max(per_gb) / min(per_gb) - 1.0
            shown = ", ".join(f"{v:.0f}" for v in per_gb)
            print(f"{'' if way == 'by blocks' else chr(10)}CPU s/GB of the whole command {way}: {shown} "
                  f"({growth:.0%} apart; target <= {TARGETS['growth']:.0%})")
            ok &= growth <= TARGETS["growth"]
            if way == "in memory":
                _print_growth_parts(results)
    if args.check:
        print(f"check (CPU seconds): {'passed' if ok else 'FAILED'}")
    return 1 if args.check and not ok else 0


if __name__ == "__main__":
    raise SystemExit(main())
