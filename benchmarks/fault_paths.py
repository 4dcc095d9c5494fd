"""The faults job in memory and under a memory limit that forces blocks give the same faults (issue 30).

Run: ``SEISMO3D_DATA_DIR=... python benchmarks/fault_paths.py [--only generated,penobscot,target] [--keep DIR]``

For a generated 192^3 faulted cube (:func:`~seismo3d.data.synthetic.synthetic_cube`, seed 4) and the 18 Penobscot
inlines (:func:`~seismo3d.data.load_penobscot_sections`), :func:`~seismo3d.jobs.faults.run_faults_job` runs once with
a limit far above the in-memory need and once with the process's own size plus 60 % of that need (so the library
decides on blocks). A cube whose smallest blocks need more memory than its run in memory (the 18 Penobscot inlines:
the blocks' halos span them all) gets blocks under no limit; it is compared through ``trace_faults`` with the blocks
forced, fault by fault. Printed per cube: whether ``fault_points.csv`` and ``fault_summary.csv`` are byte-identical
(forced: the faults' ids, points and likelihood, and their throws and evidence, equal), the largest fault likelihood
and votes differences (target <= 1e-6), the number of faults, and both runs' seconds with the load average. The
suite keeps a smaller cube's comparison (``tests/jobs/test_faults_chunked.py``); these two take minutes each.

``target`` (issue 34, off by default: about 10 minutes): the command a user runs on a 400 x 400 x 500 SEG-Y cube (a
generated faulted 256-trace tile mirrored into it, as ``benchmarks/out_of_core.py`` writes it; 320 MB of samples),
``seismo3d faults CUBE -o OUT`` in memory and ``seismo3d faults CUBE -o OUT --memory-limit 1GB`` by blocks, each a
child process whose own peak resident memory (its ``VmHWM``, ``benchmarks/peak_memory.py``) is reported. Printed:
seconds and s/GB of each, their ratio (target <= 1.3), the peaks against the limit, and whether the two runs wrote the
same ``fault_points.csv`` and ``fault_summary.csv``. ``--baseline CODE_DIR`` (e.g. a worktree of main) runs the same
two commands with ``PYTHONPATH=CODE_DIR`` too, each path's baseline run just before this code's (memory: baseline,
ours; blocks: baseline, ours), and prints a row per code with the load average over each run (the 1-minute average
read at its end), so that the two are compared in the same window.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import re
import shutil
import subprocess
import tempfile
import time
import warnings

import numpy as np
import zarr

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.jobs.faults import run_faults_job
from seismo3d.errors import InputError
from seismo3d.seismic.blocks.memory import in_memory_bytes, parse_memory_limit, resident_memory


def _timed(*args, **kwargs):
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = run_faults_job(*args, **kwargs)
    return result, time.perf_counter() - start, sorted({str(w.message).split(":")[0][:60] for w in caught})


def compare(name: str, npy: pathlib.Path, out: pathlib.Path) -> dict:
    """Run the job both ways on ``npy`` and compare the outputs."""
    shape = np.load(npy, mmap_mode="r").shape
    memory, t_memory, w_memory = _timed(npy, out / "memory", memory_limit=64 << 30, progress=False)
    limit = resident_memory() + int(0.6 * in_memory_bytes(shape))
    try:
        blocks, t_blocks, w_blocks = _timed(npy, out / "blocks", memory_limit=limit, progress=False)
    except InputError as exc:  # the smallest blocks need more than the run in memory: no limit forces blocks
        smallest = re.search(r"memory_limit='([^']+)'", str(exc))
        if smallest is None:
            raise
        print(f"{name}: {exc}")
        return forced_blocks(name, npy, out, parse_memory_limit(smallest.group(1)))
    m, b = memory.written, blocks.written
    if b["likelihood"].name != "fault_likelihood.zarr":
        raise SystemExit(f"{name}: the limit {limit / 2**30:.2f} GiB did not force blocks")
    traced = zarr.open_group(str(b["surfaces_zarr"]), mode="r")
    return {
        "cube": name, "shape": "x".join(map(str, shape)), "faults": memory.n_faults,
        "points equal": b["points"].read_bytes() == m["points"].read_bytes(),
        "summary equal": b["summary"].read_bytes() == m["summary"].read_bytes(),
        "likelihood diff": float(np.abs(traced["likelihood"][:] - np.load(m["likelihood"])).max()),
        "votes diff": float(np.abs(traced["votes"][:] - np.load(m["votes"])).max()),
        "s in memory": t_memory, "s by blocks": t_blocks, "limit GiB": limit / 2**30,
        "warnings equal": w_memory == w_blocks,
    }


def forced_blocks(name: str, npy: pathlib.Path, out: pathlib.Path, smallest: int) -> dict:
    """A cube whose smallest blocks need more memory than its run in memory (few inlines: the blocks' halos span
    them all), so that no ``--memory-limit`` of the job picks blocks: ``trace_faults`` in memory and by blocks
    (``BlockRunOptions(in_memory=False)`` at the smallest limit that works) compared fault by fault (ids, points,
    likelihood, throws, evidence) and sample by sample (fault likelihood, votes)."""
    from seismo3d.seismic.blocks.options import BlockRunOptions
    from seismo3d.seismic.faults import trace_faults

    data = np.load(npy)
    work = out / "forced"
    work.mkdir(parents=True)
    limit = int(1.05 * smallest)
    runs = {}
    for key in ("blocks", "memory"):  # blocks first: the limit they need grows with the process
        blocks = (BlockRunOptions(in_memory=False, memory_limit=limit, work_dir=work) if key == "blocks" else
                  BlockRunOptions(in_memory=True))
        start = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = trace_faults(data, progress=False, blocks=blocks)
        runs[key] = (result, time.perf_counter() - start, sorted({str(w.message).split(":")[0][:60] for w in caught}))
    (m, t_memory, w_memory), (b, t_blocks, w_blocks) = runs["memory"], runs["blocks"]
    same = len(m.faults) == len(b.faults) and all(
        x.id == y.id and np.array_equal(x.points, y.points) and np.array_equal(x.likelihood, y.likelihood)
        for x, y in zip(m.faults, b.faults))
    return {
        "cube": name + " (trace_faults, blocks forced)", "shape": "x".join(map(str, data.shape)),
        "faults": len(m.faults), "points equal": same,
        "summary equal": repr(m.throws) == repr(b.throws) and repr(m.evidence) == repr(b.evidence),
        "likelihood diff": float(np.abs(b.likelihood[:] - m.likelihood).max()),
        "votes diff": float(np.abs(b.votes[:] - m.votes).max()),
        "s in memory": t_memory, "s by blocks": t_blocks, "limit GiB": limit / 2**30,
        "warnings equal": w_memory == w_blocks,
    }


def target(root: pathlib.Path, shape=(400, 400, 500), limit: str = "1GB", baseline=None) -> list:
    """The faults command on a SEG-Y cube of ``shape`` in memory and under ``--memory-limit limit``, each a child
    process; its seconds and peak memory. ``baseline``: a code folder run the same way (``PYTHONPATH``), each of
    its runs just before this code's. Returns one row per code (the baseline's first)."""
    import sys

    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    from out_of_core import write_mosaic_segy
    from peak_memory import PeakRSS

    sgy = root / "target.sgy"
    if not sgy.exists():
        write_mosaic_segy(sgy, shape)
    gb = float(np.prod(shape)) * 4 / 1e9
    codes = (["baseline"] if baseline else []) + ["this code"]
    runs = {}
    for key, extra in (("memory", []), ("blocks", ["--memory-limit", limit])):
        for code in codes:
            tag = f"{key}_baseline" if code == "baseline" else key
            out = root / f"target_{tag}"
            shutil.rmtree(out, ignore_errors=True)  # an earlier benchmark's: the command would reuse its stores
            cmd = [shutil.which("seismo3d"), "faults", str(sgy), "-o", str(out), *extra]
            env = dict(os.environ)
            if code == "baseline":
                env["PYTHONPATH"] = str(baseline)
            start = time.perf_counter()
            with open(root / f"target_{tag}.log", "w") as log:  # the progress the command reports
                proc = subprocess.Popen(cmd, stderr=log, env=env)
                sampler = PeakRSS(proc.pid)
                proc.wait()
            peak = sampler.stop()
            if proc.returncode != 0:
                raise SystemExit(f"{' '.join(cmd)} failed (exit {proc.returncode})")
            runs[code, key] = (time.perf_counter() - start, peak, out, os.getloadavg()[0])
            print(f"  {code} {key}: {runs[code, key][0]:.0f} s, load {runs[code, key][3]:.1f}", flush=True)
    rows = []
    for code in codes:
        (t_m, p_m, o_m, l_m), (t_b, p_b, o_b, l_b) = runs[code, "memory"], runs[code, "blocks"]
        if not (o_b / "fault_likelihood.zarr").exists():
            raise SystemExit(f"--memory-limit {limit} did not run by blocks")
        rows.append({
            "code": str(baseline) if code == "baseline" else code,
            "cube": "x".join(map(str, shape)) + " SEG-Y", "s/GB in memory": t_m / gb, "s/GB by blocks": t_b / gb,
            "ratio": t_b / t_m, "peak GiB in memory": p_m / 2**30, "peak GiB by blocks": p_b / 2**30,
            "limit": limit, "load in memory": l_m, "load by blocks": l_b,
            "points equal": (o_b / "fault_points.csv").read_bytes() == (o_m / "fault_points.csv").read_bytes(),
            "summary equal": (o_b / "fault_summary.csv").read_bytes() == (o_m / "fault_summary.csv").read_bytes(),
        })
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="generated,penobscot")
    ap.add_argument("--keep", type=pathlib.Path, default=None, help="keep the outputs in this folder")
    ap.add_argument("--baseline", type=pathlib.Path, default=None, metavar="CODE_DIR",
                    help="target: also run the commands with PYTHONPATH=CODE_DIR (e.g. a worktree of main), each "
                    "path's baseline run just before this code's")
    args = ap.parse_args(argv)
    only = set(args.only.split(","))
    root = args.keep or pathlib.Path(tempfile.mkdtemp(prefix="fault_paths_"))
    root.mkdir(parents=True, exist_ok=True)
    rows = []
    if "generated" in only:
        npy = root / "generated.npy"
        np.save(npy, synthetic_cube((192, 192, 192), seed=4).cube.astype(np.float32))
        rows.append(compare("generated 192^3", npy, root / "generated"))
    if "penobscot" in only:
        from seismo3d.data import load_penobscot_sections

        npy = root / "penobscot.npy"
        np.save(npy, load_penobscot_sections().cube)
        rows.append(compare("Penobscot 18 inlines", npy, root / "penobscot"))
    print(f"load average {os.getloadavg()[0]:.1f}")
    if "target" in only:
        found = target(root, baseline=args.baseline)
        print(" | ".join(found[0]))
        for row in found:
            print(" | ".join(f"{v:.3g}" if isinstance(v, float) else str(v) for v in row.values()))
        print(f"load average {os.getloadavg()[0]:.1f}")
    if not rows:
        return
    keys = list(rows[0])
    print(" | ".join(keys))
    for r in rows:
        print(" | ".join(f"{r[k]:.3g}" if isinstance(r[k], float) else str(r[k]) for k in keys))
    print(f"outputs in {root}")


if __name__ == "__main__":
    main()
