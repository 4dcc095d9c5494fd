"""Fault likelihood of a cube larger than memory: the declared steps of the scan
(:func:`~seismo3d.seismic.faults.likelihood.scan.block_steps`, run in their order by
:func:`~seismo3d.seismic.faults.likelihood.scan.run_scan`, the same steps the run in memory makes on one block) run
block by block on dask, with the halo each step needs, results written block by block to Zarr, resumable; the
blocks planned here under the memory limit, the run by
:func:`~seismo3d.seismic.faults.likelihood.runs.likelihood_by_blocks`.

The steps and their blocks (every block carries exactly the halo its step needs, so the result equals the in-memory
:func:`~seismo3d.seismic.faults.fault_likelihood` up to float rounding):

1. Amplitude statistics (peak, mean square) of the whole cube: sums block by block.
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

Resumption (a marker per finished block), the output renamed into place when complete and the schedulers (local
threads or a ``dask.distributed`` cluster, whose workers must reach the output folder) are the executor's
(:func:`~seismo3d.seismic.faults.likelihood.runs.likelihood_by_blocks`).
"""

from __future__ import annotations

import numpy as np

from ...._options import resolve_options
from ...blocks.executor import trace_cube
from ...blocks.memory import worker_baseline
from ...blocks.options import ChunkOptions
from ...blocks.plan import plan_steps, smallest_need
from ..result import ChunkedLikelihood
from .runs import likelihood_by_blocks
from .scan import FaultScanOptions, block_steps, run_scan, scan_step

__all__ = ["block_steps", "chunked_fault_likelihood", "smallest_block_bytes"]


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
    ``'balance'`` (also the statistics'), ``'semblance'`` (also the decoding's), ``'scan'`` (crosslines or inlines
    of a strip)), refused when the smallest do not fit."""
    steps = block_steps(shape, options, block=chunking.block, strip=chunking.strip)
    sizes = plan_steps(steps, chunking, baseline=baseline, what="a chunked run of a {} x {} x {} cube".format(*shape))
    return {"shape": list(shape), "tile": int(chunking.tile), **sizes}


def chunked_fault_likelihood(cube, output, *, options: FaultScanOptions | None = None,
                             chunking: ChunkOptions | None = None, coords: dict | None = None,
                             progress: bool = False, attrs: dict | None = None,
                             **overrides) -> ChunkedLikelihood:
    """Fault likelihood, strike and dip of a 3D cube computed block by block and written to a Zarr group.

    The method is :func:`~seismo3d.seismic.faults.fault_likelihood` (Hale 2013): the same declared steps, each run
    on blocks with the halo it needs (see the module notes), so the output equals the in-memory result up to float
    rounding (max abs difference of the likelihood <= 1e-5, checked by the tests on generated cubes).

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
        Amplitudes, e.g. ``seismo3d.open(path).data`` (a SEG-Y or Zarr cube read chunk by chunk); samples along the
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
    attrs : dict, optional
        More attributes of the output group (JSON-serialisable), written before it is renamed into place.
    **overrides
        Fields of :class:`FaultScanOptions` by name.

    Returns
    -------
    ChunkedLikelihood

    Raises
    ------
    InputError
        If the cube is not 3D with at least 3 samples per axis, holds NaN or inf, ``output`` exists and is not an
        unfinished run of the same cube and options, the memory limit is too small for the smallest blocks, or the
        scheduler address cannot be reached.

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
    plan = _plan(shape, opt, chunking, worker_baseline(chunking, x))
    m = -(-shape[2] // scan_step(opt, shape[2]))
    work = (("balanced", "float32", shape[2]), ("numerator", "float32", m), ("denominator", "float32", m),
            ("key", "int32", m))
    return likelihood_by_blocks(
        x, output, opt=opt, plan=plan, steps=run_scan, chunking=chunking, coords=coords, progress=progress,
        start=lambda run, manifest, plan: run.start_output(manifest, shape, plan["tile"], work),
        method="fault likelihood (Hale 2013), seismo3d chunked run", attrs=attrs)
