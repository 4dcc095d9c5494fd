"""Cubes larger than memory: the chunked fault likelihood against the in-memory one (issue 19).

Run: ``python benchmarks/out_of_core.py [--shape 1024,1024,1000]
[--only equal,threads,surfaces,distributed,distributed-inprocess,memory,memory_surfaces] [--keep DIR]``

1. equal: a 256^3 generated faulted cube, in memory (:func:`~seismo3d.seismic.trace_faults`) and chunked
   (:func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood` then
   :func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`, 64-trace blocks): the largest
   likelihood difference, strike / dip differences, votes difference, and the faults (count, sizes, the same samples,
   throws).
2. threads / distributed: a generated cube of ``--shape`` (default 1448 x 1448 x 512 float32 = 4.29 GB) written as
   SEG-Y (a 256-trace faulted tile mirrored into a mosaic, so reflectors and faults continue across the seams),
   read lazily (``seismo3d.open``, tiles of 32 traces) and its fault likelihood, strike
   and dip computed chunk by chunk into Zarr with ``--memory-limit`` (default 1.4 GB): on dask's threaded
   scheduler, and on a local ``dask.distributed`` cluster of 2 workers (1 thread each, blocks planned for half the
   limit each, each block's kernels on the worker's share of the cores, :func:`~seismo3d.seismic.blocks.executor.
   kernel_threads`; tiles of 16 traces, so that a scan strip fits half the limit): as 2 worker processes with their
   nannies (``distributed``) and as 2 workers in
   the client's process (``distributed-inprocess``, off by default). Each run is a child process; its peak memory
   (``benchmarks/peak_memory.py``): the process's own peak resident memory (its ``VmHWM``, exact; a child it forks
   is not counted) and the summed proportional set size of it and all its children (PSS, every 1 s: the cluster's
   scheduler, nannies and workers included, shared pages split between the processes that share them: the memory
   the machine gives the run). Seconds per GB of input samples (1e9 bytes).
   surfaces: then the fault surfaces of that cube
   (:func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces` on the threaded run's likelihood, same
   memory limit), same sampling. Its fault cells (the thinned faults linked into skins in memory, ~1 % of the samples
   here) may need more than the limit: the run then refuses after its block steps, and the benchmark runs it again with
   ``--link-memory-limit`` (the blocks resumed, the linking done); the peaks of both parts are printed.
3. memory: the in-memory path (:func:`~seismo3d.seismic.faults.fault_likelihood`) on the largest cube it holds in this
   machine's 24 GB (768 x 768 x 512 = 1.21 GB; about 14 copies of the cube at its peak), same sampling;
   memory_surfaces: the whole in-memory :func:`~seismo3d.seismic.trace_faults` on the largest cube it holds
   (``--surfaces-memory-shape``, 512 x 512 x 512 = 0.54 GB).

The targets of issue 19: chunked peak <= 1.5 GB, <= 250 s/GB (the fault likelihood); equal: likelihood difference
<= 1e-5 and the same faults.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from peak_memory import PeakRSS  # noqa: E402

_TILE = 256


def _tile(n_samples: int) -> np.ndarray:
    from seismo3d.data.synthetic import synthetic_cube

    return synthetic_cube((_TILE, _TILE, n_samples), seed=7).cube.astype(np.float32)


def write_mosaic_segy(path: Path, shape) -> None:
    """A (n_il, n_xl, ns) cube as an inline-sorted IEEE SEG-Y: the tile mirrored along both lateral axes."""
    import segyio

    n_il, n_xl, ns = shape
    tile = _tile(ns)
    spec = segyio.spec()
    spec.sorting, spec.format = segyio.TraceSortingFormat.INLINE_SORTING, 5
    spec.samples, spec.ilines, spec.xlines = np.arange(ns) * 4.0, np.arange(1, n_il + 1), np.arange(1, n_xl + 1)
    idx_xl = np.arange(n_xl) % (2 * _TILE)
    idx_xl = np.where(idx_xl < _TILE, idx_xl, 2 * _TILE - 1 - idx_xl)
    with segyio.create(str(path), spec) as f:
        f.bin.update(hns=ns, hdt=4000, format=5)
        k = 0
        for i in range(n_il):
            r = i % (2 * _TILE)
            r = r if r < _TILE else 2 * _TILE - 1 - r
            line = tile[r][idx_xl]
            for j in range(n_xl):
                f.header[k] = {segyio.su.iline: i + 1, segyio.su.xline: j + 1, segyio.su.cdpx: 25 * i,
                               segyio.su.cdpy: 25 * j, segyio.su.offset: 1}
                k += 1
            f.iline[i + 1] = line
            if i % 128 == 0:
                print(f"  writing SEG-Y: inline {i + 1}/{n_il}", file=sys.stderr, flush=True)


def _child(case: str, args: list) -> dict:
    """Run one case in a child process; its JSON result and peak memory."""
    cmd = [sys.executable, __file__, "--case", case, *args]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
    sampler = PeakRSS(proc.pid)
    out, _ = proc.communicate()
    peak = sampler.stop()
    if proc.returncode != 0:
        raise RuntimeError(f"case {case} failed (exit {proc.returncode})")
    result = json.loads(out.strip().splitlines()[-1])
    result["peak_gb"] = peak / 1e9
    result["peak_pss_gb"] = sampler.peak_pss / 1e9
    return result


# ---------------------------------------------------------------------------------------------- cases (children)

def case_chunked(sgy: str, out: str, limit: int, scheduler: str) -> dict:
    from seismo3d.seismic.blocks.options import ChunkOptions
    from seismo3d.seismic.faults.likelihood.scan_blocks import chunked_fault_likelihood
    import seismo3d

    # tiles of 16 traces on the cluster: each worker plans for half the limit, and a scan strip holds a whole
    # lateral axis (1448 traces x 32 x 256 grouped samples x 24 B = 0.65 GiB for a 32-trace strip: too much)
    tile = 32 if scheduler == "threads" else 16
    cube = seismo3d.open(sgy, tile=tile)
    t0 = time.perf_counter()
    if scheduler == "threads":
        r = chunked_fault_likelihood(cube.data, out, chunking=ChunkOptions(memory_limit=limit), progress=True)
    else:
        from distributed import LocalCluster

        # the cluster's own memory manager is left off (it would pause a worker whose numpy blocks it cannot
        # spill); the run plans its blocks for half the limit per worker. "distributed": 2 worker processes (each
        # with its nanny); "distributed-inprocess": 2 workers as threads of this process (numba's omp layer lets
        # both run parallel kernels at once)
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=scheduler == "distributed",
                          dashboard_address=None, memory_limit=0) as lc:
            r = chunked_fault_likelihood(cube.data, out, progress=True, chunking=ChunkOptions(
                memory_limit=limit // 2, tile=tile, scheduler=lc.scheduler_address))
    sec = time.perf_counter() - t0
    fl = r.open()["likelihood"]
    return {"seconds": sec, "gb": float(np.prod(cube.shape)) * 4 / 1e9, "shape": list(cube.shape),
            "blocks": r.blocks_computed, "steps": r.seconds, "max_likelihood": float(np.max(fl[::64, ::64, :]))}


def case_surfaces(sgy: str, likelihood: str, out: str, limit: int, link_limit: int) -> dict:
    """The surfaces under ``limit``; when their cells need more to be linked (the run refuses, its blocks done),
    the same run again under ``link_limit`` (every block resumed: only the cells, skins and throws computed). The
    peak resident memory of each part is sampled in this process."""
    from seismo3d.errors import InputError
    from seismo3d.seismic.faults.surfaces.blocks import chunked_fault_surfaces
    from seismo3d.seismic.blocks.options import ChunkOptions
    import seismo3d

    cube = seismo3d.open(sgy, tile=32)
    sampler = PeakRSS(os.getpid())
    t0 = time.perf_counter()
    try:
        r = chunked_fault_surfaces(cube.data, likelihood, out, chunking=ChunkOptions(memory_limit=limit))
        refused = None
    except InputError as exc:
        if "thinned fault samples" not in str(exc):
            raise
        refused = str(exc)
    blocks_peak, blocks_sec = sampler.stop(), time.perf_counter() - t0
    result = {"gb": float(np.prod(cube.shape)) * 4 / 1e9, "shape": list(cube.shape),
              "blocks_peak_gb": blocks_peak / 1e9, "blocks_seconds": blocks_sec, "refused": refused}
    if refused is not None:
        sampler = PeakRSS(os.getpid())
        r = chunked_fault_surfaces(cube.data, likelihood, out, chunking=ChunkOptions(memory_limit=link_limit))
        result.update(link_peak_gb=sampler.stop() / 1e9, link_limit_gb=link_limit / 1e9)
    result.update(seconds=time.perf_counter() - t0, blocks=r.blocks_computed, steps=r.seconds,
                  faults=len(r.faults), cells=r.n_cells, seeds=r.n_seeds)
    return result


def _mosaic(shape: str) -> np.ndarray:
    n_il, n_xl, ns = (int(v) for v in shape.split(","))
    tile = _tile(ns)
    reps = (-(-n_il // _TILE), -(-n_xl // _TILE), 1)
    return np.tile(tile, reps)[:n_il, :n_xl]


def case_memory(shape: str) -> dict:
    from seismo3d.seismic import fault_likelihood

    cube = _mosaic(shape)
    t0 = time.perf_counter()
    fl = fault_likelihood(cube)
    sec = time.perf_counter() - t0
    return {"seconds": sec, "gb": cube.nbytes / 1e9, "shape": list(cube.shape),
            "max_likelihood": float(fl.likelihood.max())}


def case_memory_surfaces(shape: str) -> dict:
    from seismo3d.seismic import trace_faults

    cube = _mosaic(shape)
    t0 = time.perf_counter()
    result = trace_faults(cube, progress=False)
    sec = time.perf_counter() - t0
    return {"seconds": sec, "gb": cube.nbytes / 1e9, "shape": list(cube.shape), "faults": len(result.faults)}


def equal(work: Path) -> None:
    from seismo3d.data.synthetic import synthetic_cube
    from seismo3d.seismic import fault_likelihood, trace_faults
    import zarr

    from seismo3d.seismic.faults.surfaces.blocks import chunked_fault_surfaces
    from seismo3d.seismic.blocks.options import ChunkOptions
    from seismo3d.seismic.faults.likelihood.scan_blocks import chunked_fault_likelihood
    from seismo3d.seismic.faults.result import FaultLikelihood

    cube = synthetic_cube((256, 256, 256), seed=0).cube.astype(np.float32)
    t0 = time.perf_counter()
    ref = fault_likelihood(cube)
    t_mem = time.perf_counter() - t0
    t0 = time.perf_counter()
    r = chunked_fault_likelihood(cube, work / "equal.zarr", chunking=ChunkOptions(block=64, strip=64))
    t_chunk = time.perf_counter() - t0
    a = r.open()
    fl = FaultLikelihood(a["likelihood"][:], a["strike_deg"][:], a["dip_deg"][:])
    diff = float(np.abs(fl.likelihood - ref.likelihood).max())
    strike = float(np.mean(fl.strike_deg != ref.strike_deg))
    dip = float(np.mean(fl.dip_deg != ref.dip_deg))
    mem = trace_faults(cube, progress=False)
    t0 = time.perf_counter()
    chk = chunked_fault_surfaces(cube, work / "equal.zarr", work / "equal_surfaces.zarr",
                                 chunking=ChunkOptions(block=64))
    t_surf = time.perf_counter() - t0
    votes = float(np.abs(zarr.open_group(str(chk.path), mode="r")["votes"][:] - mem.votes).max())
    same = (len(mem.faults) == len(chk.faults)
            and all(np.array_equal(f.points, g.points) for f, g in zip(mem.faults, chk.faults)))
    throw = max((float(np.nanmax(np.abs(f.throw - g.throw), initial=0.0)) for f, g in zip(mem.throws, chk.throws)),
                default=0.0)
    print("\n### equal: 256^3 generated cube, in memory vs chunked (64-trace blocks and strips)\n")
    print("| likelihood in memory s | chunked s | blocks | max abs likelihood diff | strike differs | dip differs | "
          "surfaces chunked s | max abs votes diff | faults in memory | faults chunked | same fault samples | "
          "max abs throw diff |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    print(f"| {t_mem:.1f} | {t_chunk:.1f} | {sum(r.blocks_computed.values())} | {diff:.2e} | {strike:.2%} | "
          f"{dip:.2%} | {t_surf:.1f} | {votes:.2e} | {len(mem.faults)} ({sum(f.size for f in mem.faults)} samples) | "
          f"{len(chk.faults)} ({sum(f.size for f in chk.faults)} samples) | {'yes' if same else 'no'} | "
          f"{throw:.2e} |", flush=True)


def _surface_notes(rows: list) -> None:
    """The two parts of a chunked surfaces run that needed a larger limit for its linking."""
    for label, r in rows:
        if r.get("refused"):
            print(f"\n{label}: block steps {r['blocks_seconds']:.0f} s, peak {r['blocks_peak_gb']:.2f} GB (the run's "
                  f"process's own); then refused: {r['refused']}; linking under {r['link_limit_gb']:.1f} GB: peak "
                  f"{r['link_peak_gb']:.2f} GB; {r['cells']} cells, {r['seeds']} seeds", flush=True)


def _table(title: str, rows: list, faults: bool = False) -> None:
    """One markdown table of (label, result) rows: cube, GB, seconds, s/GB, peak, (faults,) seconds per step."""
    if not rows:
        return
    print(f"\n### {title}\n")
    print(f"| path | cube | GB | s | s/GB | peak resident GB (the process's own) | peak PSS GB |"
          f"{' faults |' if faults else ''} seconds per step |")
    print("|---" * (9 if faults else 8) + "|")
    for label, r in rows:
        steps = ", ".join(f"{k} {v:.0f}" for k, v in r.get("steps", {}).items())
        extra = f" {r['faults']} |" if faults else ""
        print(f"| {label} | {' x '.join(map(str, r['shape']))} | {r['gb']:.2f} | {r['seconds']:.0f} | "
              f"{r['seconds'] / r['gb']:.0f} | {r['peak_gb']:.2f} | {r['peak_pss_gb']:.2f} |{extra} {steps} |",
              flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shape", default="1448,1448,512")
    ap.add_argument("--memory-shape", default="768,768,512")
    ap.add_argument("--surfaces-memory-shape", default="512,512,512")
    ap.add_argument("--memory-limit", default="1.4e9")
    ap.add_argument("--link-memory-limit", default="4e9",
                    help="memory limit of the fault surfaces' linking when their cells need more than --memory-limit")
    ap.add_argument("--only", default="equal,threads,surfaces,distributed,memory,memory_surfaces")
    ap.add_argument("--keep", default=None, help="folder for the SEG-Y cube (kept between runs) and the outputs")
    ap.add_argument("--case", default=None, help=argparse.SUPPRESS)
    ap.add_argument("case_args", nargs="*", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.case == "chunked":
        print(json.dumps(case_chunked(args.case_args[0], args.case_args[1], int(float(args.case_args[2])),
                                      args.case_args[3])))
        return
    if args.case == "surfaces":
        print(json.dumps(case_surfaces(args.case_args[0], args.case_args[1], args.case_args[2],
                                       int(float(args.case_args[3])), int(float(args.case_args[4])))))
        return
    if args.case == "memory":
        print(json.dumps(case_memory(args.case_args[0])))
        return
    if args.case == "memory_surfaces":
        print(json.dumps(case_memory_surfaces(args.case_args[0])))
        return
    only = set(args.only.split(","))
    work = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="seismo3d_ooc_"))
    work.mkdir(parents=True, exist_ok=True)
    try:
        if "equal" in only:
            equal(work)
        rows = []
        shape = tuple(int(v) for v in args.shape.split(","))
        surface_rows = []
        if only & {"threads", "distributed", "distributed-inprocess", "surfaces"}:
            sgy = work / f"cube_{'x'.join(map(str, shape))}.sgy"
            if not sgy.exists():
                t0 = time.perf_counter()
                write_mosaic_segy(sgy.with_suffix(".tmp"), shape)
                os.replace(sgy.with_suffix(".tmp"), sgy)
                print(f"wrote {sgy} ({sgy.stat().st_size / 1e9:.2f} GB) in {time.perf_counter() - t0:.0f} s",
                      flush=True)
            for scheduler in ("threads", "distributed", "distributed-inprocess"):
                if scheduler not in only:
                    continue
                out = work / f"fl_{scheduler}.zarr"
                for p in (out, out.with_name(out.name + ".partial"), out.with_name(out.name + ".work")):
                    shutil.rmtree(p, ignore_errors=True)
                r = _child("chunked", [str(sgy), str(out), args.memory_limit, scheduler])
                label = {"threads": "threaded scheduler", "distributed": "dask.distributed, 2 worker processes",
                         "distributed-inprocess": "dask.distributed, 2 workers in one process"}[scheduler]
                rows.append((f"chunked, {label}", r))
                if scheduler == "threads" and "surfaces" in only:
                    traced = work / "surfaces.zarr"
                    for p in (traced, traced.with_name(traced.name + ".partial"),
                              traced.with_name(traced.name + ".work")):
                        shutil.rmtree(p, ignore_errors=True)
                    surface_rows.append(("chunked fault surfaces, threaded scheduler",
                                         _child("surfaces", [str(sgy), str(out), str(traced), args.memory_limit,
                                                             args.link_memory_limit])))
                    shutil.rmtree(traced, ignore_errors=True)
                shutil.rmtree(out, ignore_errors=True)
        if "memory" in only:
            rows.append(("in memory (fault_likelihood)", _child("memory", [args.memory_shape])))
        if "memory_surfaces" in only:
            surface_rows.append(("in memory (trace_faults, likelihood included)",
                                 _child("memory_surfaces", [args.surfaces_memory_shape])))
        limit_gb = float(args.memory_limit) / 1e9
        _table(f"fault likelihood of large cubes (memory limit of the chunked runs {limit_gb:.2f} GB)", rows)
        _table(f"fault surfaces of large cubes (voting, skins, throw; memory limit {limit_gb:.2f} GB)", surface_rows,
               faults=True)
        _surface_notes(surface_rows)
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
