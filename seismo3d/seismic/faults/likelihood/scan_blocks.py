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
from dataclasses import asdict, replace

import numpy as np

from ...._options import resolve_options
from ...blocks.apply import BlockOutput
from ...blocks.executor import SchedulerClient, check_finite, trace_cube
from ...blocks.memory import chunk_bytes, default_memory_limit, worker_baseline
from ...blocks.options import ChunkOptions
from ...blocks.plan import (
    CUBE, BlockStep, block_budget, lateral_blocks, plan_steps, refuse_over_budget, smallest_need,
)
from ...blocks.stores import StoreRun, read_sheared
from ..result import ChunkedLikelihood
from .scan import (
    AmplitudeStatistics, FaultScanOptions, balance_amplitudes, balance_halo, decode_scan, saturation_counts,
    scan_planes, scan_step, semblance_floor, semblance_halo, semblance_terms, strike_halo,
)

__all__ = ["block_steps", "chunked_fault_likelihood", "smallest_block_bytes"]

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


def block_steps(shape, options: FaultScanOptions, chunking: ChunkOptions | None = None) -> tuple:
    """The steps of :func:`chunked_fault_likelihood`, declared once, in their order: the balancing (square blocks
    read from the cube), the semblance terms (their denominators reduced into the semblance floor), the scan along
    inlines and along crosslines (blocks of every trace along the scanned axis and ``b`` traces across it) and the
    decoding (on the semblance's blocks), each with its block function, halo and the bytes of a block of ``b``
    traces a side, largest and forced sides (:func:`~seismo3d.seismic.blocks.plan.plan_steps` plans those with
    bytes: ``'balance'``, ``'semblance'``, ``'scan'``).

    Returns
    -------
    tuple of BlockStep
        Named ``'balance'``, ``'semblance'``, ``'scan'`` (run as ``'scan_inline'`` and ``'scan_crossline'``),
        ``'decode'``.
    """
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

    return (BlockStep("balance", "map", bhalo, balance_bytes, 512, function=balance_block,
                      label="amplitude balancing", inputs=(CUBE,), outputs=("balanced",), place=True),
            BlockStep("semblance", "reduce", halo, semblance_bytes, 256, chunking.block, function=semblance_block,
                      label="semblance", inputs=("balanced",), outputs=("numerator", "denominator"), place=True),
            BlockStep("scan", "map", shalo, scan_bytes, n_axis, chunking.strip, function=scan_block,
                      label="fault scan", inputs=("numerator", "denominator"), outputs=("key",), place=True,
                      lazy=True),
            BlockStep("decode", "reduce", 0, function=decode_block, label="decode", inputs=("key", "denominator"),
                      outputs=("likelihood", "strike_deg", "dip_deg")))


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
    return smallest_need(block_steps(tuple(int(n) for n in shape), options or FaultScanOptions()), tile)


def _plan(shape, options: FaultScanOptions, chunking: ChunkOptions, baseline: int) -> dict:
    """The sides of the steps' blocks under the memory limit (:func:`~seismo3d.seismic.blocks.plan.plan_steps`:
    ``'balance'``, ``'semblance'`` (also the decoding's), ``'scan'`` (crosslines or inlines of a strip)), refused
    when the smallest do not fit."""
    limit = int(chunking.memory_limit or default_memory_limit())
    budget = block_budget(limit, baseline, int(chunking.workers))
    steps = block_steps(shape, options, chunking)
    sizes = plan_steps(steps, tile=int(chunking.tile), budget=budget)
    refuse_over_budget(steps, sizes, budget=budget, baseline=baseline, workers=chunking.workers, limit=limit,
                       what="a chunked run of a {} x {} x {} cube".format(*shape))
    return {"shape": list(shape), "tile": int(chunking.tile), **sizes}


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
    x = trace_cube(cube, "a chunked fault likelihood", dtype=np.float32)
    shape = tuple(int(n) for n in x.shape)
    manifest = {"shape": list(shape), "options": json.loads(json.dumps(asdict(opt), default=str)),
                "plan": _plan(shape, opt, chunking, worker_baseline(chunking, chunk_bytes(x)))}
    out = pathlib.Path(output)
    run = StoreRun(out, chunking, progress)
    manifest["plan"] = plan = run.earlier_plan(manifest) or manifest["plan"]  # resuming: the interrupted run's blocks
    n0, n1, nt = shape
    m = -(-nt // scan_step(opt, nt))
    run.start_output(manifest, shape, plan["tile"], (("balanced", "float32", nt), ("numerator", "float32", m),
                                                     ("denominator", "float32", m), ("key", "int32", m)))
    steps = {step.name: step for step in block_steps(shape, opt, chunking)}
    block, strip = plan["semblance"], plan["scan"]
    with SchedulerClient(chunking.scheduler) as client:
        run.client = client
        stats = _amplitude_statistics(run, x)
        run.run_step(steps["balance"], lateral_blocks(shape, plan["balance"], plan["balance"]), opt, stats, source=x)
        results = run.run_step(steps["semblance"], lateral_blocks(shape, block, block), opt)
        tiny = semblance_floor(sum(r["sum_denominator"] for r in results), n0 * n1 * m)
        for axis, name in ((0, "inline"), (1, "crossline")):
            # the second scan keeps the better plane of both
            scan = replace(steps["scan"], name=f"scan_{name}", label=f"fault scan along {name}s",
                           combine=np.maximum if axis == 1 else None)
            run.run_step(scan, lateral_blocks(shape, n0, strip) if axis == 0 else lateral_blocks(shape, strip, n1),
                         axis, opt, tiny, nt, plan["tile"])
        results = run.run_step(steps["decode"], lateral_blocks(shape, block, block), opt, tiny, nt)
    live = sum(r["live"] for r in results)
    saturated = sum(r["high"] for r in results) / live if live else 0.0
    run.describe(coords, {"method": "fault likelihood (Hale 2013), seismo3d chunked run",
                          "saturated_fraction": saturated})
    run.finish()
    return ChunkedLikelihood(out, shape, dict(run.computed), dict(run.resumed), saturated, dict(run.seconds))


def _amplitude_statistics(run: StoreRun, x) -> AmplitudeStatistics:
    """Peak and mean square of the whole cube (one pass of sums over its chunks), kept by a resumed run."""
    import dask.array as da

    def compute() -> dict:
        start = time.perf_counter()
        peak, squares = run.reduce_cube((da.max(da.fabs(x)), da.sum(x.astype(np.float64) ** 2)))
        check_finite((float(peak), float(squares)))
        run.seconds["statistics"] = round(time.perf_counter() - start, 2)
        return asdict(AmplitudeStatistics.from_sums(float(peak), float(squares),
                                                    int(np.prod(x.shape, dtype=np.int64))))

    return AmplitudeStatistics(**run.saved("amplitudes", compute))


def balance_block(place, f, opt: FaultScanOptions, stats: AmplitudeStatistics) -> BlockOutput:
    """Balanced amplitudes of a block read with the balancing's halo (:func:`balance_amplitudes`).

    Parameters
    ----------
    place : BlockPlace
    f : (m0, m1, n_samples) array_like
        Amplitudes of ``place.region``.
    opt : FaultScanOptions
    stats : AmplitudeStatistics
        Of the whole cube.

    Returns
    -------
    BlockOutput
        ``balanced``: (m0, m1, n_samples) float32, cut to the core by the executor.

    Raises
    ------
    InputError
        The block holds NaN or inf.
    """
    f = np.ascontiguousarray(f, dtype=np.float32)
    check_finite(f, (place.block[0], place.block[1] - 1))
    return BlockOutput({"balanced": balance_amplitudes(f, opt, stats)})


def semblance_block(place, f, opt: FaultScanOptions) -> BlockOutput:
    """Semblance terms of a block of balanced amplitudes read with the semblance's halo
    (:func:`semblance_terms`), and the sum of the core's denominators (the semblance floor's).

    Parameters
    ----------
    place : BlockPlace
    f : (m0, m1, n_samples) float32 ndarray
        Balanced amplitudes of ``place.region``.
    opt : FaultScanOptions

    Returns
    -------
    BlockOutput
        ``numerator``, ``denominator`` of the core, float32 at the scan's grouped samples; summary
        ``sum_denominator``.
    """
    sn, sd = semblance_terms(f, opt)
    sn, sd = sn[place.core], sd[place.core]
    return BlockOutput({"numerator": sn, "denominator": sd}, {"sum_denominator": float(sd.sum(dtype=np.float64))})


def scan_block(place, numerator, denominator, axis: int, opt: FaultScanOptions, tiny: float, n_samples: int,
               tile: int) -> BlockOutput:
    """The planes sheared along ``axis`` (:func:`scan_planes`) on a block that holds that whole axis.

    Parameters
    ----------
    place : BlockPlace
        The block (every trace along ``axis``) and the region read (the strike smoothing's halo across it).
    numerator, denominator : (n_inlines, n_xlines, m) arrays read by slicing
        Semblance terms, read here in the sheared layout (:func:`~seismo3d.seismic.blocks.stores.read_sheared`).
    axis : {0, 1}
    opt : FaultScanOptions
    tiny : float
        The semblance floor.
    n_samples : int
        Samples per trace of the cube.
    tile : int
        Rows read at once.

    Returns
    -------
    BlockOutput
        ``key``: the core's packed scan keys, int32.
    """
    a0, a1, b0, b1 = place.region
    i0, i1, j0, j1 = place.block
    core, origin = ((j0 - b0, j1 - b0), b0) if axis == 0 else ((i0 - a0, i1 - a0), a0)
    sn = read_sheared(numerator, place.read, axis, tile)
    sd = read_sheared(denominator, place.read, axis, tile)
    key = scan_planes(sn, sd, opt, tiny, n_samples=n_samples, axes=(axis,), core=core, origin=origin,
                      sheared_layout=True)
    return BlockOutput({"key": key})


def decode_block(key, denominator, opt: FaultScanOptions, tiny: float, n_samples: int) -> BlockOutput:
    """Likelihood, strike and dip of a block from the combined key (:func:`decode_scan`), with its saturated and
    live samples.

    Parameters
    ----------
    key : (m0, m1, m) int32 ndarray
        Packed scan keys.
    denominator : (m0, m1, m) float32 ndarray
        Semblance denominators (live where above ``tiny``).
    opt : FaultScanOptions
    tiny : float
    n_samples : int

    Returns
    -------
    BlockOutput
        ``likelihood``, ``strike_deg``, ``dip_deg``: (m0, m1, n_samples) float32; summary ``high``, ``live``.
    """
    live = denominator > tiny
    high, n_live = saturation_counts(key, live, opt.saturation_level)
    del live
    fl, strike, dip = decode_scan(key, opt, n_samples=n_samples)
    return BlockOutput({"likelihood": fl, "strike_deg": strike, "dip_deg": dip}, {"high": high, "live": n_live})
