"""Conversion benchmark: ``seismo3d convert`` (SEG-Y -> Zarr) beside a plain segyio read of the same file.

Run:  python benchmarks/convert.py [--shape 400 400 500] [--chunk-mb 16 64 256] [--repeats 3]

A generated inline-sorted IEEE SEG-Y cube (default 400 x 400 x 500, 358 MB, with inline / crossline / CDP X / Y
headers) is written once into the temporary folder (``--work``; not removed, so reruns reuse it). Each run is a fresh
Python process, so its peak resident memory (``ru_maxrss``) is its own (the convert process imports zarr and
seismo3d before its clock starts); the runs are interleaved (segyio read, then a
convert per ``--chunk-mb``, repeated) so that load changes hit all alike. The peer is ``segyio.tools.cube`` (the
whole cube into memory through segyio's memory map), the I/O floor of reading that file from Python. Targets
(issue 34): convert within 2x the segyio read in s/GB, and peak memory within ``--chunk-mb`` + 300 MB.
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

import numpy as np

_SEGYIO_READ = """
import json, resource, sys, time, segyio
t0 = time.perf_counter()
with segyio.open(sys.argv[1], "r") as f:
    f.mmap()
    cube = segyio.tools.cube(f)
seconds = time.perf_counter() - t0
print(json.dumps({"seconds": seconds, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""

_CONVERT = """
import json, pathlib, resource, shutil, sys, time
import zarr  # imported by the job on first use; imported here so that the time is the conversion's
from seismo3d.jobs.convert import run_convert_job
out = sys.argv[2]
shutil.rmtree(out, ignore_errors=True)
pathlib.Path(out + ".run.json").unlink(missing_ok=True)  # the run record of the previous run, beside the store
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
t0 = time.perf_counter()
run_convert_job(sys.argv[1], out, chunk_mb=float(sys.argv[3]))
seconds = time.perf_counter() - t0
print(json.dumps({"seconds": seconds, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "after_imports_mb": base}))
"""


def write_segy(path: Path, shape) -> None:
    """An inline-sorted IEEE (format 5) SEG-Y of smooth random amplitudes with inline / crossline / CDP headers."""
    import segyio

    n_il, n_xl, ns = shape
    rng = np.random.default_rng(0)
    spec = segyio.spec()
    spec.sorting, spec.format = segyio.TraceSortingFormat.INLINE_SORTING, 5
    spec.samples, spec.ilines, spec.xlines = np.arange(ns) * 4.0, np.arange(1, n_il + 1), np.arange(1, n_xl + 1)
    wavelet = np.sin(np.linspace(0, np.pi, 9))
    with segyio.create(str(path), spec) as f:
        f.bin.update(hns=ns, hdt=4000, format=5)
        k = 0
        for i in range(n_il):
            line = rng.normal(size=(n_xl, ns)).astype(np.float32)
            line = np.apply_along_axis(np.convolve, 1, line, wavelet, mode="same").astype(np.float32)
            for j in range(n_xl):
                f.header[k] = {segyio.su.iline: i + 1, segyio.su.xline: j + 1, segyio.su.cdpx: 25 * i,
                               segyio.su.cdpy: 25 * j, segyio.su.scalco: 1}
                k += 1
            f.iline[i + 1] = line


def _run(code: str, *args) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(Path(__file__).resolve().parents[1]) + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True, env=env,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", type=int, nargs=3, default=(400, 400, 500))
    parser.add_argument("--chunk-mb", type=float, nargs="+", default=(16.0, 64.0, 256.0))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--work", default=tempfile.gettempdir(), help="folder of the generated SEG-Y and the stores")
    args = parser.parse_args()
    work = Path(args.work)
    segy = work / ("seismo3d_bench_%dx%dx%d.sgy" % tuple(args.shape))
    if not segy.exists():
        print(f"writing {segy} ...", flush=True)
        write_segy(segy, args.shape)
    gb = segy.stat().st_size / 1e9
    print(f"{segy.name}: {segy.stat().st_size / 2**20:.0f} MiB; load average before: "
          f"{' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    runs = {"segyio.tools.cube read": []}
    runs.update({f"seismo3d convert --chunk-mb {c:g}": [] for c in args.chunk_mb})
    for _ in range(args.repeats):
        runs["segyio.tools.cube read"].append(_run(_SEGYIO_READ, segy))
        for c in args.chunk_mb:
            runs[f"seismo3d convert --chunk-mb {c:g}"].append(_run(_CONVERT, segy, work / "seismo3d_bench.zarr", c))
    peer = float(np.median([r["seconds"] for r in runs["segyio.tools.cube read"]]))
    print(f"{'method':32s} {'s (median)':>10s} {'s/GB':>7s} {'x segyio':>9s} {'peak MB':>8s} {'limit MB':>9s}")
    for name, rs in runs.items():
        s = float(np.median([r["seconds"] for r in rs]))
        peak = max(r["peak_mb"] for r in rs)
        limit = f"{float(name.split()[-1]) + 300:9.0f}" if "convert" in name else f"{'':9s}"
        base = f"  (after imports {max(r['after_imports_mb'] for r in rs):.0f} MB)" if "convert" in name else ""
        print(f"{name:32s} {s:10.3f} {s / gb:7.2f} {s / peer:9.2f} {peak:8.0f} {limit}{base}")
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print("targets: convert <= 2.0 x the segyio read (s/GB); peak <= chunk-mb + 300 MB")


if __name__ == "__main__":
    main()
