"""Fault likelihood of a cube larger than memory: the scan of :mod:`~seismo3d.seismic.faults.likelihood.scan` run block
by block on dask, with the halo each step needs, results written block by block to Zarr, resumable.

The steps and their blocks (every block carries exactly the halo its step needs, so the result equals the in-memory
:func:`~seismo3d.seismic.faults.fault_likelihood` up to float rounding):

1. Amplitude statistics (peak, mean square) of the whole cube: one pass of sums over its chunks.
2. Amplitude balancing on square blocks of traces with :func:`~seismo3d.seismic.faults.likelihood.scan.balance_halo`
   traces of halo (every sample of a trace in the block), written to an intermediate Zarr array; then the semblance
   terms (structure tensors, structure-oriented semblance; finite Gaussian windows) on square blocks with
   :func:`~seismo3d.seismic.faults.likelihood.scan.semblance_halo` of halo, written at half the vertical resolution.
   Two steps rather than one: each block carries only its own step's halo, so blocks can be larger for the same
   memory.
3. The scan of the planes sheared along inlines on blocks that hold every inline (the exponential smoothing down the
   dip follows a fault plane laterally without bound, so that axis is never cut) and a few crosslines with
   :func:`~seismo3d.seismic.faults.likelihood.scan.strike_halo` of halo; then the planes sheared along crosslines on
   blocks that hold every crossline. The packed keys of both are combined by their maximum.
4. Likelihood, strike and dip decoded block by block into the output Zarr group.

Every finished block leaves a marker in the run's work folder, written after its data: a run that is interrupted
(Ctrl-C, a killed process, a lost worker) and started again with the same input, options and output skips the
finished blocks. The output is assembled in ``OUTPUT.partial`` and renamed to ``OUTPUT`` only when every block is
done, so an output that exists is complete.

The same code runs on dask's local threaded scheduler (default) and on a ``dask.distributed`` cluster (pass its
address): the tasks read their input from the lazy cube's graph and the intermediate Zarr arrays by path, so the
output folder must be on storage every worker can reach.
"""

from __future__ import annotations

import json
import pathlib
import time
from dataclasses import asdict, dataclass

import numpy as np

from ...._options import resolve_options
from ....errors import InputError
from ...blocks.executor import (BlockStep, SchedulerClient, block_budget, lateral_blocks, plan_steps, trace_cube,
                                write_marker)
from ...blocks.options import ChunkOptions
from ...blocks.stores import StoreRun, write_coords
from ..likelihood.scan import (
    AmplitudeStatistics, FaultScanOptions, balance_amplitudes, balance_halo, decode_scan, saturation_counts,
    scan_planes, scan_step, semblance_floor, semblance_halo, semblance_terms, strike_halo,
)
from ..result import ChunkedLikelihood
from ...blocks.memory import default_memory_limit, in_memory_bytes, resident_memory, worker_baseline

__all__ = ["ChunkedLikelihood", "chunked_fault_likelihood", "default_memory_limit",
           "in_memory_bytes", "resident_memory", "smallest_block_bytes", "worker_baseline"]

# Bytes of working memory per sample of a block (incl. halo), from the arrays each step holds at its peak: balancing
# holds the amplitudes, their squares and two smoothing passes; the semblance step the balanced amplitudes, 3
# gradients, 6 tensor components, the planarity and the outputs; the scan 2 inputs read in its layout, 2 smoothed
# copies and the keys of the block's core (a third of it or less); decoding the key brought back to every sample
# and likelihood, strike and dip.
# (tracemalloc peaks of the steps on a 96 x 96 x 512 block: balance 12 + the input 4 and the tiles it is cut from 4,
# semblance 40 + the input 4, scan 23 per grouped sample, decoding 20; the semblance and decoding rounded up)
_BALANCE_BYTES = 20
_SEMBLANCE_BYTES = 48
_SCAN_BYTES = 24
_DECODE_BYTES = 24


@dataclass(frozen=True)
class _Plan:
    shape: tuple
    tile: int
    block: int          # square blocks of the semblance and decoding steps
    balance: int        # square blocks of the balancing step
    strip: int          # crosslines (inlines) per block of the scan along inlines (crosslines)
    bhalo: int          # lateral halo of the balancing step
    halo: int           # lateral halo of the semblance step
    shalo: int          # halo of the smoothing along strike
    m: int              # grouped samples

    def blocks(self, size0, size1):
        return lateral_blocks(self.shape, size0, size1)


def _block_steps(shape, options: FaultScanOptions, chunking: ChunkOptions | None = None) -> tuple:
    """The semblance (its denominators reduced into the semblance floor; the decoding uses its square blocks),
    balancing and scan steps declared for the executor's plan (:func:`~seismo3d.seismic.blocks.executor.plan_steps`):
    halo, bytes of a block of ``b`` traces a side (the scan: ``b`` crosslines or inlines of blocks that hold every
    trace along the other axis), largest and forced sides."""
    n0, n1, nt = shape
    m = -(-nt // scan_step(options, nt))
    bhalo, halo, shalo = balance_halo(options), semblance_halo(options), strike_halo(options)
    n_axis = max(n0, n1)
    chunking = chunking or ChunkOptions()

    def semblance_bytes(b):
        return max((b + 2 * halo) ** 2 * nt * _SEMBLANCE_BYTES, b ** 2 * nt * _DECODE_BYTES)

    def balance_bytes(b):
        return (b + 2 * bhalo) ** 2 * nt * _BALANCE_BYTES

    def scan_bytes(w):
        return n_axis * (w + 2 * shalo) * m * _SCAN_BYTES

    return (BlockStep("semblance", "reduce", halo, semblance_bytes, 256, chunking.block),
            BlockStep("balance", "map", bhalo, balance_bytes, 512),
            BlockStep("scan", "map", shalo, scan_bytes, n_axis, chunking.strip))


def smallest_block_bytes(shape, options: FaultScanOptions | None, tile: int) -> int:
    """Bytes the largest step of :func:`chunked_fault_likelihood` needs with its smallest blocks (one ``tile`` a
    side), on top of the process itself: what ``memory_limit`` must leave for it (before the headroom).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    options : FaultScanOptions or None
        The scan's options (None: the defaults).
    tile : int
        Traces a side of the smallest block (:attr:`ChunkOptions.tile`).

    Returns
    -------
    int
    """
    steps = _block_steps(tuple(int(n) for n in shape), options or FaultScanOptions())
    return int(max(step.block_bytes(int(tile)) for step in steps))


def _plan(shape, options: FaultScanOptions, chunking: ChunkOptions, baseline: int) -> _Plan:
    n0, n1, nt = shape
    tile = int(chunking.tile)
    m = -(-nt // scan_step(options, nt))
    bhalo, halo, shalo = balance_halo(options), semblance_halo(options), strike_halo(options)
    limit = int(chunking.memory_limit or default_memory_limit())
    # what the blocks may use: the limit less the process itself, less a fifth for the allocator's fragmentation
    # (freed blocks that threads' arenas keep) and the reads in flight; measured 1.54 GB peak for 1.4 GB without it
    budget = block_budget(limit, baseline, int(chunking.workers))
    steps = _block_steps(shape, options, chunking)
    sizes = plan_steps(steps, tile=tile, budget=budget)
    block, balance, strip = sizes["semblance"], sizes["balance"], sizes["scan"]
    need = max(step.block_bytes(sizes[step.name]) for step in steps)
    if need > budget:
        raise InputError(
            f"a chunked run of a {n0} x {n1} x {nt} cube needs about "
            f"{(need * int(chunking.workers) + baseline) / 2**30:.2f} GiB but the memory limit is "
            f"{limit / 2**30:.2f} GiB: raise memory_limit (or use fewer workers)")
    return _Plan((n0, n1, nt), tile, block, balance, strip, bhalo, halo, shalo, m)


def chunked_fault_likelihood(cube, output, *, options: FaultScanOptions | None = None,
                             chunking: ChunkOptions | None = None, coords: dict | None = None,
                             progress: bool = False, **overrides) -> ChunkedLikelihood:
    """Fault likelihood, strike and dip of a 3D cube computed block by block and written to a Zarr group.

    The method is :func:`~seismo3d.seismic.faults.fault_likelihood` (Hale 2013): every step runs on blocks with the
    halo it needs (see the module notes), so the output equals the in-memory result up to float rounding (max abs
    difference of the likelihood <= 1e-5, checked by the tests on generated cubes).

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
        Amplitudes, e.g. ``open_lazy(path).data`` (a SEG-Y or Zarr cube read chunk by chunk); samples along the
        last axis, every chunk holding whole traces. Must be finite.
    output : str or os.PathLike
        Output Zarr group (a folder), created; must not exist unless it is the unfinished output of the same run
        (then ``output + '.partial'`` and ``output + '.work'`` exist and the run resumes).
    options : FaultScanOptions, optional
        The scan (defaults as in :func:`~seismo3d.seismic.faults.fault_likelihood`).
    chunking : ChunkOptions, optional
        Memory limit, block sizes and the dask scheduler.
    coords : dict, optional
        1-D coordinates written beside the arrays: ``inline``, ``crossline`` (numbers) and ``sample`` (times or
        depths) with an optional ``sample_unit`` string; default: indices.
    progress : bool
        Report progress per block (a bar on a terminal, log lines otherwise).
    **overrides
        Fields of :class:`FaultScanOptions` by name.

    Returns
    -------
    ChunkedLikelihood

    Raises
    ------
    InputError
        If the cube is not 3D with at least 3 samples per axis, ``output`` exists and is not an unfinished run of
        the same cube and options, the memory limit is too small for the smallest blocks, or the scheduler address
        cannot be reached.

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013.
    .. [2] Dask documentation, "Overlapping computations" (``dask.array.map_overlap``): the halo idea used here
       with per-step halos and per-block resumability.
    """
    opt = resolve_options(FaultScanOptions, options, overrides, "chunked_fault_likelihood")
    chunking = chunking or ChunkOptions()
    x = trace_cube(cube, "a chunked fault likelihood")
    if x.dtype != np.float32:
        x = x.astype(np.float32)
    input_chunk = 4 * max(x.chunks[0]) * max(x.chunks[1]) * x.shape[2]
    plan = _plan(x.shape, opt, chunking, worker_baseline(chunking, input_chunk))
    out = pathlib.Path(output)
    run = _Run(out, plan, opt, chunking, progress)
    earlier = run.earlier_plan(_manifest(x.shape, opt, plan))
    if earlier is not None:  # resuming: the blocks of the interrupted run
        run.plan = plan = _Plan(**dict(earlier, shape=tuple(earlier["shape"])))
    run.start(_manifest(x.shape, opt, plan))
    with SchedulerClient(chunking.scheduler) as client:
        run.client = client
        run.balance(x, run.amplitude_statistics(x))
        tiny = run.semblance()
        run.scan(tiny, axis=0)
        run.scan(tiny, axis=1)
        saturated = run.decode(tiny, coords)
    run.finish()
    return ChunkedLikelihood(out, tuple(x.shape), dict(run.computed), dict(run.resumed), saturated,
                             dict(run.seconds))


def _manifest(shape, opt, plan) -> dict:
    return {"shape": list(shape), "options": json.loads(json.dumps(asdict(opt), default=str)),
            "plan": json.loads(json.dumps(asdict(plan)))}


class _Run(StoreRun):
    """One chunked likelihood run: its block lists and steps."""

    def __init__(self, out: pathlib.Path, plan: _Plan, opt: FaultScanOptions, chunking: ChunkOptions,
                 progress: bool):
        super().__init__(out, chunking, progress)
        self.plan, self.opt = plan, opt

    def start(self, manifest: dict) -> None:
        m, nt = self.plan.m, self.plan.shape[2]
        self.start_output(manifest, self.plan.shape, self.plan.tile,
                          (("balanced", "float32", nt), ("numerator", "float32", m), ("denominator", "float32", m),
                           ("key", "int32", m)))

    def amplitude_statistics(self, x) -> AmplitudeStatistics:
        import dask
        import dask.array as da

        def compute() -> dict:
            start = time.perf_counter()
            peak = da.max(da.fabs(x))
            squares = da.sum(x.astype(np.float64) ** 2)
            if self.client is not None:
                peak, squares = self.client.compute([peak, squares], sync=True)
            else:
                peak, squares = dask.compute(peak, squares, scheduler="threads",
                                             num_workers=int(self.chunking.workers))
            if not np.isfinite(float(peak)) or not np.isfinite(float(squares)):
                raise InputError("the cube holds NaN or infinite amplitudes; replace them (e.g. by 0) before tracing "
                                 "faults")
            self.seconds["statistics"] = round(time.perf_counter() - start, 2)
            return asdict(AmplitudeStatistics.from_sums(float(peak), float(squares),
                                                        int(np.prod(x.shape, dtype=np.int64))))

        return AmplitudeStatistics(**self.saved("amplitudes", compute))

    def balance(self, x, stats: AmplitudeStatistics) -> None:
        p = self.plan
        n0, n1, _ = p.shape
        todo, _ = self.pending("balance", p.blocks(p.balance, p.balance))
        tasks = []
        for b in todo:
            i0, i1, j0, j1 = b
            a0, a1, b0, b1 = max(i0 - p.bhalo, 0), min(i1 + p.bhalo, n0), max(j0 - p.bhalo, 0), min(j1 + p.bhalo, n1)
            tasks.append(self.task(_balance_block, x[a0:a1, b0:b1, :], (i0 - a0, i1 - a0, j0 - b0, j1 - b0), b,
                                   str(self.work), self.opt, stats, str(self.marker("balance", b))))
        self.compute(tasks, "amplitude balancing", "balance")

    def semblance(self) -> float:
        p = self.plan
        n0, n1, _ = p.shape
        results = self.each_block("semblance", "semblance", _semblance_block, p.blocks(p.block, p.block), p,
                                  str(self.work), self.opt)
        total = sum(r["sum_denominator"] for r in results)
        return semblance_floor(total, n0 * n1 * p.m)

    def scan(self, tiny: float, axis: int) -> None:
        p = self.plan
        n0, n1, _ = p.shape
        step = f"scan_{'inline' if axis == 0 else 'crossline'}"
        blocks = p.blocks(n0, p.strip) if axis == 0 else p.blocks(p.strip, n1)
        self.each_block(step, f"fault scan along {'inlines' if axis == 0 else 'crosslines'}", _scan_block, blocks,
                        axis, p, str(self.work), self.opt, tiny)

    def decode(self, tiny: float, coords: dict | None) -> float:
        import zarr
        p = self.plan
        results = self.each_block("decode", "decode", _decode_block, p.blocks(p.block, p.block), p, str(self.work),
                                  str(self.partial), self.opt, tiny)
        high = sum(r["high"] for r in results)
        live = sum(r["live"] for r in results)
        group = zarr.open_group(str(self.partial), mode="r+")
        write_coords(group, p.shape, coords)
        fraction = high / live if live else 0.0
        group.attrs.update({"method": "fault likelihood (Hale 2013), seismo3d chunked run",
                            "saturated_fraction": fraction})
        return fraction


def _balance_block(f, core, block, work, opt, stats, marker) -> dict:
    """Balanced amplitudes of one block (read with halo), its core written to the work array."""
    import zarr
    f = np.ascontiguousarray(f, dtype=np.float32)
    if not np.all(np.isfinite(f)):
        raise InputError(f"the cube holds NaN or infinite amplitudes in inlines {block[0]}-{block[1] - 1} (indices); "
                         "replace them (e.g. by 0) before tracing faults")
    g = balance_amplitudes(f, opt, stats)
    del f
    c0, c1, d0, d1 = core
    i0, i1, j0, j1 = block
    zarr.open_array(f"{work}/balanced", mode="r+")[i0:i1, j0:j1, :] = g[c0:c1, d0:d1]
    write_marker(marker, {})
    return {}


def _semblance_block(block, plan: _Plan, work, opt, marker) -> dict:
    """Semblance terms of one block from the balanced amplitudes around it, its core written to the work arrays."""
    import zarr
    n0, n1, _ = plan.shape
    i0, i1, j0, j1 = block
    a0, a1, b0, b1 = max(i0 - plan.halo, 0), min(i1 + plan.halo, n0), max(j0 - plan.halo, 0), min(j1 + plan.halo, n1)
    f = zarr.open_array(f"{work}/balanced", mode="r")[a0:a1, b0:b1]
    sn, sd = semblance_terms(f, opt)
    del f
    sn, sd = sn[i0 - a0:i1 - a0, j0 - b0:j1 - b0], sd[i0 - a0:i1 - a0, j0 - b0:j1 - b0]
    zarr.open_array(f"{work}/numerator", mode="r+")[i0:i1, j0:j1, :] = sn
    zarr.open_array(f"{work}/denominator", mode="r+")[i0:i1, j0:j1, :] = sd
    result = {"sum_denominator": float(sd.sum(dtype=np.float64))}
    write_marker(marker, result)
    return result


def _read_sheared(array, region, axis: int, tile: int) -> np.ndarray:
    """A region of a (n0, n1, m) work array in the scan's layout (sheared axis, sample, other axis), read tile row
    by tile row so that only one row is held twice."""
    rows, cols = region
    n_a = (rows.stop - rows.start) if axis == 0 else (cols.stop - cols.start)
    n_b = (cols.stop - cols.start) if axis == 0 else (rows.stop - rows.start)
    out = np.empty((n_a, array.shape[2], n_b), dtype=np.float32)
    start = rows.start if axis == 0 else cols.start
    for a in range(0, n_a, tile):
        b = min(a + tile, n_a)
        if axis == 0:
            out[a:b] = array[start + a:start + b, cols].transpose(0, 2, 1)
        else:
            out[a:b] = array[rows, start + a:start + b].transpose(1, 2, 0)
    return out


def _scan_block(block, axis, plan: _Plan, work, opt, tiny, marker) -> dict:
    """The planes sheared along ``axis`` on a block that holds that whole axis; the key maximised into the work
    array (idempotent: a block scanned twice leaves the same key)."""
    import zarr
    n0, n1, nt = plan.shape
    i0, i1, j0, j1 = block
    if axis == 0:
        a, b = max(j0 - plan.shalo, 0), min(j1 + plan.shalo, n1)
        region = (slice(0, n0), slice(a, b))
        core, origin = (j0 - a, j1 - a), a
    else:
        a, b = max(i0 - plan.shalo, 0), min(i1 + plan.shalo, n0)
        region = (slice(a, b), slice(0, n1))
        core, origin = (i0 - a, i1 - a), a
    sn = _read_sheared(zarr.open_array(f"{work}/numerator", mode="r"), region, axis, plan.tile)
    sd = _read_sheared(zarr.open_array(f"{work}/denominator", mode="r"), region, axis, plan.tile)
    key = scan_planes(sn, sd, opt, tiny, n_samples=nt, axes=(axis,), core=core, origin=origin, sheared_layout=True)
    del sn, sd
    store = zarr.open_array(f"{work}/key", mode="r+")
    target = (slice(i0, i1), slice(j0, j1))
    if axis == 1:  # the second scan: keep the better plane of both
        np.maximum(key, store[target], out=key)
    store[target] = key
    write_marker(marker, {})
    return {}


def _decode_block(block, plan: _Plan, work, partial, opt, tiny, marker) -> dict:
    """Likelihood, strike and dip of one block from the combined key, written to the output."""
    import zarr
    i0, i1, j0, j1 = block
    key = zarr.open_array(f"{work}/key", mode="r")[i0:i1, j0:j1]
    live = zarr.open_array(f"{work}/denominator", mode="r")[i0:i1, j0:j1] > tiny
    high, n_live = saturation_counts(key, live, opt.saturation_level)
    del live
    fl, strike, dip = decode_scan(key, opt, n_samples=plan.shape[2])
    group = zarr.open_group(partial, mode="r+")
    group["likelihood"][i0:i1, j0:j1] = fl
    group["strike_deg"][i0:i1, j0:j1] = strike
    group["dip_deg"][i0:i1, j0:j1] = dip
    result = {"high": high, "live": n_live}
    write_marker(marker, result)
    return result
