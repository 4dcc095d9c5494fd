"""Fault throw on a lazy cube (one patch window at a time) against the in-memory run (issue 19).

Run: ``python benchmarks/fault_throw_lazy.py [--size 256] [--seed 5] [--keep DIR]``

A generated ``size^3`` faulted cube (:func:`seismo3d.data.synthetic.synthetic_cube`, noise 0.1) is written as an
inline-sorted IEEE SEG-Y file and its faults traced in memory (:func:`~seismo3d.seismic.trace_faults`). Then, each in
a child process (numba kernels warmed up on a small cube first), :func:`~seismo3d.seismic.fault_throws` of those
faults on

- memory: the cube read whole (:func:`~seismo3d.seismic.io.read_segy`), the orientation computed over it;
- lazy: the dask array of ``seismo3d.open`` (chunks of 64 x 64 traces), each patch
  reading only a window of tiles of 64 x 64 traces around it, the slopes of a tile computed with the structure
  tensor's halo, the tiles last used kept up to 256 MiB (the default of
  :class:`~seismo3d.seismic.faults.windows.LazyWindows`);
- lazy-32: the same with tiles of 32 traces and a 128 MiB tile cache (a window of about 5 x 5 tiles: smaller cache
  thrashes).

Printed: seconds of the call, its peak of traced allocations (``tracemalloc``: numpy arrays made by the call; the
cube read before the call is not counted), its peak resident memory above the resident memory before the call
(the process's ``VmHWM`` from the call's start, ``benchmarks/peak_memory.py``), and the largest throw difference
between the two paths (target: <= 1e-4 samples, NaN at the same points, the same registered points).
"""

from __future__ import annotations

import argparse
import json
import pickle
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from peak_memory import PeakRSS  # noqa: E402


def write_segy(path: Path, cube: np.ndarray) -> None:
    """``cube`` (n_il, n_xl, ns) as an inline-sorted IEEE float SEG-Y file, 4 ms sampling."""
    import segyio

    n_il, n_xl, ns = cube.shape
    spec = segyio.spec()
    spec.sorting, spec.format = segyio.TraceSortingFormat.INLINE_SORTING, 5
    spec.samples, spec.ilines, spec.xlines = np.arange(ns) * 4.0, np.arange(1, n_il + 1), np.arange(1, n_xl + 1)
    with segyio.create(str(path), spec) as f:
        f.bin.update(hns=ns, hdt=4000, format=5)
        k = 0
        for i in range(n_il):
            for j in range(n_xl):
                f.header[k] = {segyio.su.iline: i + 1, segyio.su.xline: j + 1, segyio.su.cdpx: 25 * i,
                               segyio.su.cdpy: 25 * j, segyio.su.offset: 1}
                k += 1
            f.iline[i + 1] = cube[i]


def _warm_up() -> None:
    """Compile / load the numba kernels of both paths on a small cube."""
    import dask.array as da

    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic import fault_throws

    syn = synthetic_cube((48, 48, 64), n_faults=1, seed=0)
    pts = np.argwhere(syn.fault_labels == 1)
    fault_throws(syn.cube, [pts])
    fault_throws(da.from_array(syn.cube, chunks=(16, 48, 64)), [pts])


def case(path: str, sgy: str, faults_pkl: str, out: str) -> dict:
    import psutil

    from seismo3d.seismic import fault_throws
    from seismo3d.seismic.io import read_segy
    import seismo3d

    _warm_up()
    faults = pickle.loads(Path(faults_pkl).read_bytes())
    from seismo3d.seismic.faults.windows import LazyWindows

    if path == "memory":
        data = read_segy(sgy)[0]
    elif path == "lazy":
        data = seismo3d.open(sgy, tile=64).data
    else:
        data = LazyWindows(seismo3d.open(sgy, tile=32).data, tile=32, cache_mb=128)
    rss0 = psutil.Process().memory_info().rss
    sampler = PeakRSS()
    tracemalloc.start()
    t0 = time.perf_counter()
    throws = fault_throws(data, faults)
    seconds = time.perf_counter() - t0
    traced = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    peak = sampler.stop()
    np.savez(out, throw=np.concatenate([r.throw for r in throws]),
             registered=np.concatenate([r.registered for r in throws]))
    return {"seconds": seconds, "traced_mb": traced / 2**20, "rss_extra_mb": (peak - rss0) / 2**20,
            "rss_before_mb": rss0 / 2**20}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--keep", type=Path, help="folder for the SEG-Y file and faults (reused when present)")
    ap.add_argument("--case", nargs=4, metavar=("PATH", "SGY", "FAULTS", "OUT"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.case:
        print(json.dumps(case(*args.case)))
        return

    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic import trace_faults

    folder = args.keep or Path(tempfile.mkdtemp(prefix="throw_lazy_"))
    folder.mkdir(parents=True, exist_ok=True)
    sgy, faults_pkl = folder / f"cube{args.size}_seed{args.seed}.sgy", folder / f"faults{args.size}_seed{args.seed}.pkl"
    if not faults_pkl.exists():
        n = args.size
        cube = synthetic_cube((n, n, n), seed=args.seed, noise=0.1).cube
        write_segy(sgy, cube)
        t0 = time.perf_counter()
        faults = trace_faults(cube, progress=False).faults
        print(f"traced {len(faults)} faults in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        faults_pkl.write_bytes(pickle.dumps(faults))
        del cube
    faults = pickle.loads(faults_pkl.read_bytes())
    rows = {}
    for path in ("memory", "lazy", "lazy-32"):
        out = folder / f"throws_{path}.npz"
        res = subprocess.run([sys.executable, __file__, "--case", path, str(sgy), str(faults_pkl), str(out)],
                             check=True, stdout=subprocess.PIPE, text=True)
        rows[path] = json.loads(res.stdout.strip().splitlines()[-1])
    a = np.load(folder / "throws_memory.npz")
    checks = []
    for path in ("lazy", "lazy-32"):
        b = np.load(folder / f"throws_{path}.npz")
        ok = np.isfinite(a["throw"]) & np.isfinite(b["throw"])
        checks.append((path, float(np.max(np.abs(a["throw"][ok] - b["throw"][ok]), initial=0.0)),
                       bool(np.array_equal(np.isnan(a["throw"]), np.isnan(b["throw"]))),
                       bool(np.array_equal(a["registered"], b["registered"]))))

    n = args.size
    print(f"\nfault_throws on a {n}^3 float32 cube ({n ** 3 * 4 / 2**20:.0f} MiB), {len(faults)} faults, "
          f"{sum(len(f.points) for f in faults)} fault points, {int(np.isfinite(a['throw']).sum())} throws measured")
    print(f"{'path':<8} {'seconds':>8} {'traced peak MiB':>16} {'RSS above start MiB':>20} {'RSS at start MiB':>17}")
    for path, r in rows.items():
        print(f"{path:<8} {r['seconds']:8.2f} {r['traced_mb']:16.1f} {r['rss_extra_mb']:20.1f} "
              f"{r['rss_before_mb']:17.1f}")
    for path, diff, same_nan, same_reg in checks:
        print(f"{path} vs memory: largest throw difference {diff:.2e} samples (target <= 1e-4); NaN at the same "
              f"points: {same_nan}; same registered points: {same_reg}")


if __name__ == "__main__":
    main()
