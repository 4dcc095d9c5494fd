"""The learned fault likelihood of a cube larger than memory, block by block on dask, resumable.

The network is 2D: an inline section's probability depends on that section alone, so a block of inline sections
needs the network's receptive half of halo along the crosslines only, and a block of crossline sections along the
inlines only. The steps (the output equals the in-memory
:func:`~seismo3d.seismic.faults.likelihood.learned.learned_fault_likelihood` up to float rounding):

1. The amplitude scale (median and standard deviation) from the regular subsample of traces that
   :func:`~seismo3d.seismic.faults.likelihood.learned.amplitude_scale` uses in memory too.
2. Per network grid (``LearnedOptions.grids``, numbered 0, 1, ... in its order) and per direction the network
   runs on (``network_inline_0``, ``network_crossline_0``, ...): blocks of the whole cube's network
   grid (:mod:`~seismo3d.seismic.faults.likelihood.network`), ``k`` sections of ``w`` network traces each, read with the
   receptive half of halo (:data:`~seismo3d.seismic.faults.likelihood.network.RECEPTIVE_HALF` network traces, the
   block's grid on the whole cube's pooling grid) along the sections and only the resampling's few traces across them;
   every sample of each trace. The blocks are as long along the sections as the memory limit allows (the whole cube's
   width when it fits: no halo at all), so the halo adds little. Each direction's probability is written on the network
   grid to a work array.
3. Strike and dip: on blocks with the tensor smoothing's halo, the larger of the two directions' probabilities on
   each network grid is interpolated onto the block's samples (as in memory: the maximum before the interpolation)
   and the grids' are averaged in their order; its
   structure tensor gives strike and dip, written with the likelihood to the output Zarr group (``likelihood``,
   ``strike_deg``, ``dip_deg``: what :func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`
   reads, as from the scan's chunked run).

The steps are declared once beside the network (:func:`~seismo3d.seismic.faults.likelihood.learned.block_steps`)
and run in their order by :func:`~seismo3d.seismic.faults.likelihood.learned.run_learned`, the same steps the run
in memory makes on one block; here their blocks are planned under the memory limit (:func:`_plan`) and the run is
:func:`~seismo3d.seismic.faults.likelihood.runs.likelihood_by_blocks` (markers, resumption, schedulers, the stores
of :class:`~seismo3d.seismic.blocks.stores.StoreRun`, the ``.partial`` output renamed when complete).
"""

from __future__ import annotations

import math

from ...._options import resolve_options
from ....errors import InputError
from ...blocks.executor import trace_cube
from ...blocks.memory import worker_baseline
from ...blocks.options import ChunkOptions
from ...blocks.plan import block_budget, largest_block, limit_for_blocks, serial_step_blocks
from ...blocks.stores import StoreRun
from ..result import ChunkedLikelihood
from .learned import (
    DIRECTION_NAMES, LearnedOptions, cube_directions, network_region, network_shape, orientation_block_bytes,
    orientation_halo, orientation_step, run_learned,
)
from .network import POOLING_MULTIPLE
from .network_grid import grid_size
from .runs import likelihood_by_blocks

__all__ = ["chunked_learned_likelihood", "learned_block_bytes"]

# Network-grid traces a side of the chunks of the network work arrays; the network blocks are multiples of it (or the
# whole width), so no two blocks write one chunk
_NETWORK_CHUNK = 16
# bytes at the peak of a network block: per input sample of the block (8: the amplitudes as read, the anti-alias
# filter, the resampling, as benchmarks/learned_block_memory.py measures them with tracemalloc from the block as read;
# 8 more: the tiles dask reads and joins into the block, held while it joins them, and the next block's tiles read
# while this block runs; without them the 400 x 400 x 500 run of benchmarks/fault_paths.py --only target held 0.97 GiB
# of anonymous memory under a 0.93 GiB limit) and per network-grid sample of the sections run at once (one batch's
# activations, the network's output)
_NETWORK_INPUT_BYTES = 16
_NETWORK_BATCH_BYTES = 420


def chunked_learned_likelihood(cube, output, *, options: LearnedOptions | None = None,
                               chunking: ChunkOptions | None = None, coords: dict | None = None,
                               progress: bool = False, attrs: dict | None = None,
                               **overrides) -> ChunkedLikelihood:
    """Learned fault likelihood, strike and dip of a 3D cube computed block by block and written to a Zarr group.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
        Amplitudes, e.g. ``open_lazy(path).data``; finite.
    output : str or os.PathLike
        Output Zarr group (a folder), created; must not exist unless it is the unfinished output of the same run.
    options : LearnedOptions, optional
    chunking : ChunkOptions, optional
        Memory limit, block size and the dask scheduler. ``chunking.block`` (traces, a multiple of the tile) fixes
        the strike-and-dip blocks and makes the network blocks as many network traces a side as it spans
        (``block * resample``, rounded up to a multiple of 16).
    coords : dict, optional
        ``inline``, ``crossline``, ``sample`` coordinates (and ``sample_unit``) written beside the arrays.
    progress : bool
        Report progress per block.
    attrs : dict, optional
        More attributes of the output group (JSON-serialisable), written before it is renamed into place.
    **overrides
        Fields of :class:`~seismo3d.seismic.faults.likelihood.learned.LearnedOptions` by name.

    Returns
    -------
    ChunkedLikelihood
        Steps ``'network_inline_K'`` and / or ``'network_crossline_K'`` (as ``options.directions`` says) for each
        network grid K = 0, 1, ... of ``options.grids(n_samples, 3)``, and ``'orientation'``.

    Raises
    ------
    InputError
        The cube is not 3D, holds NaN / inf, ``output`` exists and is not an unfinished run of the same cube and
        options, or the memory limit is too small for the smallest blocks.
    """
    opt = resolve_options(LearnedOptions, options, overrides, "chunked_learned_likelihood")
    chunking = chunking or ChunkOptions()
    x = trace_cube(cube, "a chunked learned fault likelihood")
    plan = _plan(tuple(int(n) for n in x.shape), opt, chunking, worker_baseline(chunking, x))
    return likelihood_by_blocks(x, output, opt=opt, plan=plan, steps=run_learned, start=_start, chunking=chunking,
                                coords=coords, progress=progress,
                                method="learned fault likelihood (seismo3d fault network), chunked run",
                                manifest={"method": "learned, network blocks per direction"}, attrs=attrs)


def _network_block_bytes(block, axis: int, shape, factor: float, batch: int, step: int = 1) -> int:
    """Bytes at the peak of one network block (the model of ``_NETWORK_INPUT_BYTES`` and ``_NETWORK_BATCH_BYTES``)."""
    a0, a1, b0, b1 = network_region(block, axis, shape, factor, step)
    nt = int(shape[2])
    along = grid_size(b1 - b0, factor) if axis == 0 else grid_size(a1 - a0, factor)  # network traces per section
    sections = block[1] - block[0] if axis == 0 else block[3] - block[2]
    per_section = (along + POOLING_MULTIPLE) * (grid_size(nt, factor) + POOLING_MULTIPLE)
    return ((a1 - a0) * (b1 - b0) * nt * _NETWORK_INPUT_BYTES
            + min(batch, sections) * per_section * _NETWORK_BATCH_BYTES)


def _largest_network_bytes(grid, across: int, along: int, axis: int, shape, factor: float, batch: int,
                           step: int = 1) -> int:
    """Bytes of the largest block of a network block plan: the first, second and last blocks along each axis hold
    every size of region there is (clipped at the cube's two edges or not)."""
    size = (across, along) if axis == 0 else (along, across)
    starts = [sorted({0, min(s, (n - 1) // s * s), (n - 1) // s * s}) for n, s in zip(grid[:2], size)]
    return max(_network_block_bytes((u, min(u + size[0], grid[0]), v, min(v + size[1], grid[1])), axis, shape,
                                    factor, batch, step) for u in starts[0] for v in starts[1])


def _largest_network_block(grid, axis: int, shape, factor: float, batch: int, budget: int, fixed=None,
                           step: int = 1) -> tuple:
    """``(across, along)`` network traces of the blocks of direction ``axis``: as long along the sections as the
    budget allows (the whole width when it fits), then as many sections as it allows; ``fixed`` forces both."""
    if fixed is not None:
        return fixed, fixed
    c = _NETWORK_CHUNK
    width = grid[1 - axis]

    def fits(across, along):
        return _largest_network_bytes(grid, across, along, axis, shape, factor, batch, step) <= budget

    along = max((w for w in [*range(c, width, c), width] if fits(c, w)), default=c)
    across = largest_block(c, max(c, -(-grid[axis] // c) * c), lambda k: fits(k, along))
    return across, along


def learned_block_bytes(shape, opt: LearnedOptions, tile: int) -> int:
    """Bytes of the learned likelihood's smallest block (one worker), the largest of its steps.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : LearnedOptions
    tile : int
        Traces a side of the smallest strike-and-dip blocks.

    Returns
    -------
    int
        Bytes per worker: a ``memory_limit`` below :func:`~seismo3d.seismic.blocks.plan.limit_for_blocks` of it is
        refused by :func:`chunked_learned_likelihood`.
    """
    shape = tuple(int(n) for n in shape)
    c = _NETWORK_CHUNK
    network = max(_largest_network_bytes(network_shape(shape, factor), c, c, axis, shape, factor,
                                         int(opt.sections_per_batch), int(opt.section_step))
                  for factor in opt.grids(shape[2], 3) for axis in cube_directions(opt))
    return max(network, orientation_block_bytes(tile, shape[2], opt))


def _plan(shape, opt: LearnedOptions, chunking: ChunkOptions, baseline: int) -> dict:
    """The network blocks of each grid and direction (network traces, multiples of 16 or the whole width) and the
    strike-and-dip blocks (traces, multiples of the tile) under the memory limit, planned with
    :func:`~seismo3d.seismic.blocks.plan.block_budget` as the scan's and the surfaces' blocks are."""
    nt = shape[2]
    tile = int(chunking.tile)
    halo_o = orientation_halo(opt)
    cap = max(tile, (max(shape[0], shape[1]) + tile - 1) // tile * tile)
    limit = chunking.limit
    budget = block_budget(limit, baseline, int(chunking.workers))
    batch = int(opt.sections_per_batch)
    if chunking.block and int(chunking.block) % tile:
        raise InputError(f"block must be a multiple of the tile ({tile} traces); got {chunking.block}")
    grids, biggest = [], 0
    for factor in opt.grids(nt, 3):
        grid = network_shape(shape, factor)
        fixed = None
        if chunking.block:
            fixed = max(_NETWORK_CHUNK,
                        -(-math.ceil(int(chunking.block) * factor) // _NETWORK_CHUNK) * _NETWORK_CHUNK)
        network = {}
        for axis in cube_directions(opt):
            size = _largest_network_block(grid, axis, shape, factor, batch, budget, fixed, int(opt.section_step))
            network[DIRECTION_NAMES[axis]] = list(size)
            biggest = max(biggest, _largest_network_bytes(grid, *size, axis, shape, factor, batch,
                                                          int(opt.section_step)))
        grids.append({"factor": factor, "network_shape": list(grid), "network_blocks": network})

    orientation = orientation_step(shape, opt, min(cap, 256), chunking.block)
    if chunking.block:
        workers_o, block_o = int(chunking.workers), int(chunking.block)
    else:  # its kernels are mostly serial (scipy's Gaussian filters): blocks at once on the idle cores
        workers_o, block_o = serial_step_blocks(orientation, limit=limit, baseline=baseline,
                                                workers=int(chunking.workers), scheduler=chunking.scheduler, tile=tile)
    if not (biggest <= budget and orientation.block_bytes(block_o) <= block_budget(limit, baseline, workers_o)):
        need = limit_for_blocks(learned_block_bytes(shape, opt, tile), baseline, int(chunking.workers))
        raise InputError(f"the memory limit ({limit / 2**30:.2f} GiB) is below what the smallest blocks of the "
                         f"learned likelihood need ({need / 2**30:.2f} GiB for {nt} samples per trace and "
                         f"{int(chunking.workers)} worker(s)); raise memory_limit (--memory-limit on the command line)")
    return {"shape": list(shape), "tile": tile, "grids": grids, "network_chunk": _NETWORK_CHUNK,
            "block_orientation": int(block_o), "workers_orientation": int(workers_o), "halo_orientation": halo_o}


def _start(run: StoreRun, manifest: dict, plan: dict) -> None:
    """The run's folders and output, and a work array on each grid's network grid per direction."""
    import zarr
    run.start_output(manifest, tuple(plan["shape"]), plan["tile"], ())
    c = plan["network_chunk"]
    for k, g in enumerate(plan["grids"]):
        grid = g["network_shape"]
        for name in g["network_blocks"]:
            path = run.work / f"network_{name}_{k}"
            run.arrays[path.name] = str(path)
            if not path.exists():
                zarr.create_array(str(path), shape=tuple(grid), chunks=(c, c, grid[2]), dtype="float32",
                                  compressors=None, fill_value=0)


