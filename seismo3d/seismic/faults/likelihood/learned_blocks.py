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

The steps are declared once (:func:`block_steps`) and run by the executor of :mod:`seismo3d.seismic.blocks`
(:meth:`~seismo3d.seismic.blocks.executor.BlockRun.run_step`: markers, resumption, schedulers), into the stores of
:class:`~seismo3d.seismic.blocks.stores.StoreRun` (the ``.partial`` output renamed when complete).
"""

from __future__ import annotations

import functools
import json
import math
import pathlib
from dataclasses import asdict

import numpy as np

from ...._options import resolve_options
from ....errors import InputError
from ...blocks.apply import BlockOutput
from ...blocks.executor import SchedulerClient, check_finite, trace_cube
from ...blocks.memory import chunk_bytes, default_memory_limit, worker_baseline
from ...blocks.options import ChunkOptions
from ...blocks.plan import (
    CUBE, BlockStep, block_budget, largest_block, lateral_blocks, limit_for_blocks, serial_step_blocks,
)
from ...blocks.stores import StoreRun
from ..result import ChunkedLikelihood
from .learned import (
    LearnedOptions, amplitude_scale, cube_directions, direction_probability, grids_mean, orientation_from_likelihood,
    scale_subsample, section_span,
)
from .network import POOLING_MULTIPLE, RECEPTIVE_HALF
from .network_grid import anti_alias_sigma, from_network_grid, grid_size, to_network_grid

__all__ = ["block_steps", "chunked_learned_likelihood", "learned_block_bytes"]

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
# bytes per sample of an orientation block (halo included) at its peak: the probability, its gradients, the tensor
# components, the normals (measured 48.0 with tracemalloc on an 82 x 82 x 500 block of the fault_paths target; 72.0
# while the tensor was still held as the angles were computed); the headroom for the allocator is block_budget's
_ORIENTATION_BYTES = 54
_DIRECTION_NAMES = {0: "inline", 1: "crossline"}


def _orientation_halo(opt: LearnedOptions) -> int:
    return int(np.ceil(4 * float(opt.orientation_sigma))) + 1  # Gaussian radius (truncate 4) and the gradient


def _orientation_block_bytes(side: int, n_samples: int, opt: LearnedOptions) -> int:
    """Bytes of a strike-and-dip block of ``side`` traces a side, its halo included."""
    return (int(side) + 2 * _orientation_halo(opt)) ** 2 * int(n_samples) * _ORIENTATION_BYTES


def chunked_learned_likelihood(cube, output, *, options: LearnedOptions | None = None,
                               chunking: ChunkOptions | None = None, coords: dict | None = None,
                               progress: bool = False, **overrides) -> ChunkedLikelihood:
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
    shape = tuple(int(n) for n in x.shape)
    plan = _plan(shape, opt, chunking, worker_baseline(chunking, chunk_bytes(x)))
    out = pathlib.Path(output)
    run = StoreRun(out, chunking, progress)
    manifest = {"shape": list(shape), "options": json.loads(json.dumps(asdict(opt))), "plan": plan,
                "method": "learned, network blocks per direction"}
    earlier = run.earlier_plan(manifest)
    if earlier is not None:
        plan = dict(earlier)
        manifest["plan"] = plan
    _start(run, manifest, plan)
    *networks, orientation = block_steps(plan, opt)
    with SchedulerClient(chunking.scheduler) as client:
        run.client = client
        scale = _scale(run, x)
        networks = iter(networks)
        for g in plan["grids"]:
            for axis in cube_directions(opt):
                step = next(networks)
                blocks = _network_blocks(g["network_shape"], *g["network_blocks"][_DIRECTION_NAMES[axis]], axis)
                run.run_step(step, blocks, axis, opt, float(g["factor"]), scale, int(g["network_shape"][axis]),
                             source=x)
        results = run.run_step(orientation, lateral_blocks(plan["shape"], plan["block_orientation"],
                                                           plan["block_orientation"]),
                               plan, opt, workers=plan["workers_orientation"])
    saturated = sum(r["high"] for r in results) / float(np.prod(plan["shape"]))
    run.describe(coords, {"method": "learned fault likelihood (seismo3d fault network), chunked run",
                          "saturated_fraction": saturated})
    run.finish()
    return ChunkedLikelihood(out, shape, dict(run.computed), dict(run.resumed), saturated, dict(run.seconds))


def block_steps(plan: dict, opt: LearnedOptions) -> tuple:
    """The steps of :func:`chunked_learned_likelihood`, declared once, in their order: per network grid K and per
    direction the network runs on, ``'network_inline_K'`` / ``'network_crossline_K'`` (blocks of the network grid
    read from the cube with the receptive half of halo along the sections), then ``'orientation'`` (strike and dip on
    square blocks with the tensor smoothing's halo, its likelihood reduced into the saturated fraction), each with its
    block function; the network's block sizes and the orientation's are planned by :func:`_plan`.

    Parameters
    ----------
    plan : dict
        The run's plan (:func:`_plan`).
    opt : LearnedOptions

    Returns
    -------
    tuple of BlockStep
    """
    shape = tuple(plan["shape"])
    steps = []
    for k, g in enumerate(plan["grids"]):
        factor = float(g["factor"])
        for axis in cube_directions(opt):
            name = _DIRECTION_NAMES[axis]
            label = f"fault network on {name}s" + (f" (grid {factor:g})" if len(plan["grids"]) > 1 else "")
            # the network's blocks are on the network grid: their outputs are their cores already (trim=False)
            steps.append(BlockStep(f"network_{name}_{k}", "map", RECEPTIVE_HALF, function=network_block, label=label,
                                   region=functools.partial(_network_region, axis=axis, shape=shape, factor=factor,
                                                            step=int(opt.section_step)),
                                   inputs=(CUBE,), outputs=(("probability", f"network_{name}_{k}"),), place=True,
                                   trim=False))
    networks = tuple(f"network_{name}_{k}" for k, g in enumerate(plan["grids"]) for name in g["network_blocks"])
    return (*steps, _orientation_step(shape, opt, plan["block_orientation"], plan["block_orientation"], networks))


def _orientation_step(shape, opt: LearnedOptions, cap: int, fixed=None, networks: tuple = ()) -> BlockStep:
    """Strike and dip on square blocks from the network arrays ``networks`` (the probability reduced into the
    saturated fraction)."""
    nt = int(shape[2])
    return BlockStep("orientation", "reduce", _orientation_halo(opt), lambda b: _orientation_block_bytes(b, nt, opt),
                     cap, fixed, function=orientation_block, label="fault orientation", inputs=networks,
                     outputs=("likelihood", "strike_deg", "dip_deg"), place=True, lazy=True)


def _network_shape(shape, factor: float) -> tuple:
    """The whole cube's network grid: samples per axis."""
    return tuple(grid_size(int(n), factor) for n in shape)


def _input_span(u0: int, u1: int, need: int, factor: float, n: int) -> tuple:
    """Input samples ``[a0, a1)`` along one lateral axis whose resampling gives the whole cube's network samples
    ``[u0 - need, u1 + need)`` (within the cube) exactly: the anti-alias filter's radius and the linear
    interpolation's neighbour on both sides. ``u0 - need`` is a multiple of the pooling multiple, so at factor 1
    ``a0`` is too (the block's pooling grid is the cube's)."""
    if factor == 1.0:
        return max(u0 - need, 0), min(u1 + need, n)
    margin = int(4.0 * anti_alias_sigma(factor) + 0.5) + 2  # scipy's Gaussian radius at truncate 4, and one more
    return (max(math.floor((u0 - need) / factor) - margin, 0),
            min(math.floor((u1 - 1 + need) / factor) + 1 + margin, n))


def _network_region(block, axis: int, shape, factor: float, step: int = 1) -> tuple:
    """``(a0, a1, b0, b1)``: the input traces a network block of direction ``axis`` reads (the receptive half along
    its sections, the resampling's margin across them, and the computed sections its others are interpolated from
    when ``step`` > 1: :func:`~seismo3d.seismic.faults.likelihood.learned.section_span`)."""
    u0, u1, v0, v1 = block
    if axis == 0:
        u0, u1 = section_span(u0, u1, step, grid_size(int(shape[0]), factor))[0]
    else:
        v0, v1 = section_span(v0, v1, step, grid_size(int(shape[1]), factor))[0]
    need = (0, RECEPTIVE_HALF) if axis == 0 else (RECEPTIVE_HALF, 0)
    return _input_span(u0, u1, need[0], factor, shape[0]) + _input_span(v0, v1, need[1], factor, shape[1])


def _network_block_bytes(block, axis: int, shape, factor: float, batch: int, step: int = 1) -> int:
    """Bytes at the peak of one network block (the model of ``_NETWORK_INPUT_BYTES`` and ``_NETWORK_BATCH_BYTES``)."""
    a0, a1, b0, b1 = _network_region(block, axis, shape, factor, step)
    nt = int(shape[2])
    along = grid_size(b1 - b0, factor) if axis == 0 else grid_size(a1 - a0, factor)  # network traces per section
    sections = block[1] - block[0] if axis == 0 else block[3] - block[2]
    per_section = (along + POOLING_MULTIPLE) * (grid_size(nt, factor) + POOLING_MULTIPLE)
    return ((a1 - a0) * (b1 - b0) * nt * _NETWORK_INPUT_BYTES
            + min(batch, sections) * per_section * _NETWORK_BATCH_BYTES)


def _network_blocks(grid, across: int, along: int, axis: int) -> list:
    """``(u0, u1, v0, v1)`` network-grid blocks of ``across`` sections by ``along`` traces for direction ``axis``."""
    size = (across, along) if axis == 0 else (along, across)
    return lateral_blocks(grid, *size)


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
    network = max(_largest_network_bytes(_network_shape(shape, factor), c, c, axis, shape, factor,
                                         int(opt.sections_per_batch), int(opt.section_step))
                  for factor in opt.grids(shape[2], 3) for axis in cube_directions(opt))
    return max(network, _orientation_block_bytes(tile, shape[2], opt))


def _plan(shape, opt: LearnedOptions, chunking: ChunkOptions, baseline: int) -> dict:
    """The network blocks of each grid and direction (network traces, multiples of 16 or the whole width) and the
    strike-and-dip blocks (traces, multiples of the tile) under the memory limit, planned with
    :func:`~seismo3d.seismic.blocks.plan.block_budget` as the scan's and the surfaces' blocks are."""
    nt = shape[2]
    tile = int(chunking.tile)
    halo_o = _orientation_halo(opt)
    cap = max(tile, (max(shape[0], shape[1]) + tile - 1) // tile * tile)
    limit = int(chunking.memory_limit or default_memory_limit())
    budget = block_budget(limit, baseline, int(chunking.workers))
    batch = int(opt.sections_per_batch)
    if chunking.block and int(chunking.block) % tile:
        raise InputError(f"block must be a multiple of the tile ({tile} traces); got {chunking.block}")
    grids, biggest = [], 0
    for factor in opt.grids(nt, 3):
        grid = _network_shape(shape, factor)
        fixed = None
        if chunking.block:
            fixed = max(_NETWORK_CHUNK,
                        -(-math.ceil(int(chunking.block) * factor) // _NETWORK_CHUNK) * _NETWORK_CHUNK)
        network = {}
        for axis in cube_directions(opt):
            size = _largest_network_block(grid, axis, shape, factor, batch, budget, fixed, int(opt.section_step))
            network[_DIRECTION_NAMES[axis]] = list(size)
            biggest = max(biggest, _largest_network_bytes(grid, *size, axis, shape, factor, batch,
                                                          int(opt.section_step)))
        grids.append({"factor": factor, "network_shape": list(grid), "network_blocks": network})

    orientation = _orientation_step(shape, opt, min(cap, 256), chunking.block)
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


def _scale(run: StoreRun, x) -> tuple:
    """The amplitude scale from the cube's subsample of traces, kept by a resumed run."""
    def compute() -> list:
        s0, s1 = scale_subsample(x.shape)
        sample = np.asarray(x[::s0, ::s1, :].compute(), dtype=np.float32)
        check_finite(sample)
        return list(amplitude_scale(sample, subsample=False))

    return tuple(run.saved("scale", compute))


def network_block(place, f, axis: int, opt: LearnedOptions, factor: float, scale, n_sections: int) -> BlockOutput:
    """The network's probability (:func:`direction_probability`) on the sections of one block of the network grid
    (``place.block``, direction ``axis``), from the amplitudes of its input region (``place.region``, read with the
    receptive half of halo along the sections).

    Parameters
    ----------
    place : BlockPlace
        The block on the network grid and its input region (:func:`_network_region`).
    f : (m0, m1, n_samples) array_like
        Amplitudes of ``place.region``.
    axis : {0, 1}
        The sections' direction (inlines, crosslines).
    opt : LearnedOptions
    factor : float
        The network grid's resampling factor.
    scale : (float, float)
        The cube's amplitude scale (:func:`amplitude_scale`).
    n_sections : int
        Sections of the whole cube's network grid along ``axis`` (``LearnedOptions.section_step``'s last one).

    Returns
    -------
    BlockOutput
        ``probability``: (u1 - u0, v1 - v0, network samples) float32, the block's core on the network grid.

    Raises
    ------
    InputError
        The region holds NaN or inf.
    """
    f = np.ascontiguousarray(f, dtype=np.float32)
    u0, u1, v0, v1 = place.block
    check_finite(f, (place.origin[0], place.origin[0] + f.shape[0] - 1))
    aligns = (1, POOLING_MULTIPLE) if axis == 0 else (POOLING_MULTIPLE, 1)
    small, first = to_network_grid(f, factor, origin=place.origin, align=aligns)
    n_samples = f.shape[2]
    del f
    step = int(opt.section_step)
    (s0, s1) = section_span(*((u0, u1) if axis == 0 else (v0, v1)), step, n_sections)[0]  # with the computed ones
    r0, r1, c0, c1 = u0 - first[0], u1 - first[0], v0 - first[1], v1 - first[1]
    k0, k1 = s0 - first[axis], s1 - first[axis]
    assert min(r0, c0, k0) >= 0 and max(r1, k1 if axis == 0 else 0) <= small.shape[0] \
        and max(c1, k1 if axis == 1 else 0) <= small.shape[1], "network block outside its region"
    sections = small[k0:k1] if axis == 0 else small[:, k0:k1]
    prob = direction_probability(sections, axis, scale=scale, batch=int(opt.sections_per_batch),
                                 stretch_to=opt.stretch(n_samples, factor, 3), network=opt.model(3), step=step,
                                 origin=s0, n_sections=n_sections)
    if axis == 0:
        return BlockOutput({"probability": prob[u0 - s0:u1 - s0, c0:c1]})
    return BlockOutput({"probability": prob[r0:r1, v0 - s0:v1 - s0]})


def _probability(plan: dict, networks, region) -> np.ndarray:
    """The network's probability on the input samples of ``region`` ``(a0, a1, b0, b1)`` from the network arrays
    ``networks`` (read by slicing; per grid, its directions): on each network grid the larger of the two directions',
    interpolated, then the grids' mean in their order (as
    :func:`~seismo3d.seismic.faults.likelihood.learned.fault_probability` does on the whole cube)."""
    a0, a1, b0, b1 = region
    total = None
    arrays = iter(networks)
    for g in plan["grids"]:
        factor, grid = float(g["factor"]), g["network_shape"]
        if factor == 1.0:
            u, v = (a0, a1), (b0, b1)
        else:  # the network samples either side of every input sample of the region
            u = (math.floor(a0 * factor), min(math.floor((a1 - 1) * factor) + 2, grid[0]))
            v = (math.floor(b0 * factor), min(math.floor((b1 - 1) * factor) + 2, grid[1]))
        small = None
        for _ in g["network_blocks"]:
            one = next(arrays)[u[0]:u[1], v[0]:v[1]]
            small = one if small is None else np.maximum(small, one)
        prob = from_network_grid(small, (a1 - a0, b1 - b0, plan["shape"][2]), factor, origin=(a0, b0),
                                 first=(u[0], v[0], 0))
        del small
        total = prob if total is None else np.add(total, prob, out=total)
    return grids_mean(total, len(plan["grids"]))


def orientation_block(place, *networks_plan_opt) -> BlockOutput:
    """Strike and dip of one block (:func:`orientation_from_likelihood`) from the probability around it
    (``place.region``, the tensor smoothing's halo), read from the network arrays; with the likelihood (0 below the
    smallest dip) and its saturated samples.

    Parameters
    ----------
    place : BlockPlace
    *networks_plan_opt
        The network arrays (read by slicing: per grid, its directions), then the run's plan (dict) and the
        :class:`LearnedOptions`.

    Returns
    -------
    BlockOutput
        ``likelihood``, ``strike_deg``, ``dip_deg`` of the core; summary ``high``.
    """
    *networks, plan, opt = networks_plan_opt
    prob = _probability(plan, networks, place.region)
    core = place.core  # the tensor smoothed over the region, eigen-decomposed at the core only (the same bits)
    strike, dip = orientation_from_likelihood(prob, sigma=float(opt.orientation_sigma), core=core)
    likelihood = np.where(dip < float(opt.min_dip), np.float32(0.0), prob[core])
    return BlockOutput({"likelihood": likelihood, "strike_deg": strike, "dip_deg": dip},
                       {"high": int(np.count_nonzero(likelihood > float(opt.saturation_level)))})
