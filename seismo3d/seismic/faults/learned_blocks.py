"""The learned fault likelihood of a cube larger than memory, block by block on dask, resumable.

The steps (each block carries the halo its step needs, so the output equals the in-memory
:func:`~seismo3d.seismic.faults.learned.learned_fault_likelihood` up to float rounding):

1. The amplitude scale (median and standard deviation) from the regular subsample of traces that
   :func:`~seismo3d.seismic.faults.learned.amplitude_scale` uses in memory too.
2. The network's probability on lateral blocks with the network's receptive half of halo
   (:data:`~seismo3d.seismic.faults.unet.RECEPTIVE_HALF` traces on the network's grid:
   :func:`~seismo3d.seismic.faults.network_grid.grid_halo`), every sample of each trace, on the inline and the
   crossline sections of the block, resampled onto the whole cube's network grid (its pooling grid included); written
   to a work array.
3. Strike and dip from the structure tensor of the probability on blocks with the tensor smoothing's halo, written
   with the likelihood to the output Zarr group (``likelihood``, ``strike_deg``, ``dip_deg``: what
   :func:`~seismo3d.seismic.faults.pipeline_blocks.chunked_fault_surfaces` reads, as from the scan's chunked run).

Markers, resumption, the ``.partial`` output and the schedulers are those of
:mod:`~seismo3d.seismic.faults.likelihood_blocks`.
"""

from __future__ import annotations

import json
import pathlib
from dataclasses import asdict

import numpy as np

from ..._options import resolve_options
from ...errors import InputError
from ..blocks import SchedulerClient, block_budget, largest_block, limit_for_blocks, write_marker
from .learned import (LearnedOptions, amplitude_scale, fault_probability, orientation_from_likelihood,
                      scale_subsample)
from .likelihood_blocks import (ChunkedLikelihood, ChunkOptions, LikelihoodRun, _write_coords, lateral_blocks,
                                trace_cube)
from .memory import default_memory_limit, worker_baseline
from .network_grid import grid_halo
from .unet import POOLING_MULTIPLE, RECEPTIVE_HALF

__all__ = ["chunked_learned_likelihood", "learned_block_bytes"]

# bytes per sample of a block (halo included) at each step's peak, as benchmarks/learned_block_memory.py measures
# them (tracemalloc): the amplitudes, both directions' probabilities and one batch of sections' activations in step 2
# (measured 21.5-23.1); the probability, its gradients, the tensor components and the outputs in step 3 (measured
# 72.0); the headroom for the allocator is block_budget's
_PROBABILITY_BYTES = 24
_ORIENTATION_BYTES = 80


def _orientation_halo(opt: LearnedOptions) -> int:
    return int(np.ceil(4 * float(opt.orientation_sigma))) + 1  # Gaussian radius (truncate 4) and the gradient


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
        Memory limit, block size and the dask scheduler.
    coords : dict, optional
        ``inline``, ``crossline``, ``sample`` coordinates (and ``sample_unit``) written beside the arrays.
    progress : bool
        Report progress per block.
    **overrides
        Fields of :class:`~seismo3d.seismic.faults.learned.LearnedOptions` by name.

    Returns
    -------
    ChunkedLikelihood
        Steps ``'probability'`` and ``'orientation'``.

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
    input_chunk = 4 * max(x.chunks[0]) * max(x.chunks[1]) * shape[2]
    plan = _plan(shape, opt, chunking, worker_baseline(chunking, input_chunk))
    out = pathlib.Path(output)
    run = _Run(out, plan, opt, chunking, progress)
    manifest = {"shape": list(shape), "options": json.loads(json.dumps(asdict(opt))), "plan": plan,
                "method": "learned"}
    earlier = run.earlier_plan(manifest)
    if earlier is not None:
        run.plan = plan = dict(earlier)
        manifest["plan"] = plan
    run.start(manifest)
    with SchedulerClient(chunking.scheduler) as client:
        run.client = client
        scale = run.scale(x)
        run.probability(x, scale)
        saturated = run.orientation(coords)
    run.finish()
    return ChunkedLikelihood(out, shape, dict(run.computed), dict(run.resumed), saturated, dict(run.seconds))


def _probability_halo(opt: LearnedOptions) -> int:
    return grid_halo(RECEPTIVE_HALF, float(opt.resample), POOLING_MULTIPLE)


def learned_block_bytes(shape, opt: LearnedOptions, tile: int) -> int:
    """Bytes of the learned likelihood's smallest block (one worker), the larger of its two steps.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : LearnedOptions
    tile : int
        Traces a side of the smallest blocks (rounded up to the network's pooling multiple).

    Returns
    -------
    int
        Bytes per worker: a ``memory_limit`` below :func:`~seismo3d.seismic.blocks.limit_for_blocks` of it is refused
        by :func:`chunked_learned_likelihood`.
    """
    nt = int(shape[2])
    step = int(np.lcm(int(tile), POOLING_MULTIPLE))
    return max((step + 2 * _probability_halo(opt)) ** 2 * nt * _PROBABILITY_BYTES,
               (step + 2 * _orientation_halo(opt)) ** 2 * nt * _ORIENTATION_BYTES)


def _plan(shape, opt: LearnedOptions, chunking: ChunkOptions, baseline: int) -> dict:
    """Block sides (traces, multiples of 8 and of the tile) of the two steps under the memory limit, planned with
    :func:`~seismo3d.seismic.blocks.block_budget` as the scan's and the surfaces' blocks are."""
    nt = shape[2]
    tile = int(chunking.tile)
    halo_p = _probability_halo(opt)
    halo_o = _orientation_halo(opt)
    cap = max(tile, (max(shape[0], shape[1]) + tile - 1) // tile * tile)
    limit = int(chunking.memory_limit or default_memory_limit())
    budget = block_budget(limit, baseline, int(chunking.workers))

    def fits(halo, per_sample):
        return lambda b: (b + 2 * halo) ** 2 * nt * per_sample <= budget

    step = int(np.lcm(tile, POOLING_MULTIPLE))
    if chunking.block and int(chunking.block) % step:
        raise InputError(f"block must be a multiple of {step} traces for the learned likelihood (the tile and the "
                         f"network's pooling multiple {POOLING_MULTIPLE}); got {chunking.block}")
    block_p = int(chunking.block or largest_block(step, min(cap, 512), fits(halo_p, _PROBABILITY_BYTES)))
    block_o = int(chunking.block or largest_block(step, min(cap, 256), fits(halo_o, _ORIENTATION_BYTES)))
    if not (fits(halo_p, _PROBABILITY_BYTES)(block_p) and fits(halo_o, _ORIENTATION_BYTES)(block_o)):
        need = limit_for_blocks(learned_block_bytes(shape, opt, tile), baseline, int(chunking.workers))
        raise InputError(f"the memory limit ({limit / 2**30:.2f} GiB) is below what the smallest blocks of the "
                         f"learned likelihood need ({need / 2**30:.2f} GiB for {nt} samples per trace and "
                         f"{int(chunking.workers)} worker(s)); raise memory_limit (--memory-limit on the command line)")
    return {"shape": list(shape), "tile": tile, "block_probability": int(block_p), "block_orientation": int(block_o),
            "halo_probability": halo_p, "halo_orientation": halo_o}


class _Run(LikelihoodRun):
    """One chunked learned-likelihood run: its steps."""

    def __init__(self, out: pathlib.Path, plan: dict, opt: LearnedOptions, chunking: ChunkOptions, progress: bool):
        super().__init__(out, chunking, progress)
        self.plan, self.opt = plan, opt

    def start(self, manifest: dict) -> None:
        self.start_output(manifest, tuple(self.plan["shape"]), self.plan["tile"],
                          (("probability", "float32", self.plan["shape"][2]),))

    def scale(self, x) -> tuple:
        path = self.work / "scale.json"
        if path.exists():
            return tuple(json.loads(path.read_text()))
        s0, s1 = scale_subsample(x.shape)
        sample = np.asarray(x[::s0, ::s1, :].compute(), dtype=np.float32)
        if not np.isfinite(sample).all():
            raise InputError("the cube holds NaN or infinite amplitudes; replace them (e.g. by 0) before tracing "
                             "faults")
        scale = amplitude_scale(sample, subsample=False)
        path.write_text(json.dumps(list(scale)))
        return scale

    def probability(self, x, scale) -> None:
        p = self.plan
        n0, n1, _ = p["shape"]
        halo = p["halo_probability"]
        todo, _ = self.pending("probability", lateral_blocks(p["shape"], p["block_probability"], p["block_probability"]))
        tasks = []
        for b in todo:
            i0, i1, j0, j1 = b
            a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, n0), max(j0 - halo, 0), min(j1 + halo, n1)
            tasks.append(self.task(_probability_block, x[a0:a1, b0:b1, :], (i0 - a0, i1 - a0, j0 - b0, j1 - b0), b,
                                   str(self.work), self.opt, scale, (a0, b0), str(self.marker("probability", b))))
        self.compute(tasks, "fault network", "probability")

    def orientation(self, coords) -> float:
        import zarr
        p = self.plan
        results = self.each_block("orientation", "fault orientation", _orientation_block,
                                  lateral_blocks(p["shape"], p["block_orientation"], p["block_orientation"]), p, str(self.work),
                                  str(self.partial), self.opt)
        high = sum(r["high"] for r in results)
        group = zarr.open_group(str(self.partial), mode="r+")
        _write_coords(group, tuple(p["shape"]), coords)
        fraction = high / float(np.prod(p["shape"]))
        group.attrs.update({"method": "learned fault likelihood (seismo3d fault network), chunked run",
                            "saturated_fraction": fraction})
        return fraction


def _probability_block(f, core, block, work, opt, scale, origin, marker) -> dict:
    """The network's probability on one block read with halo; its core written to the work array."""
    import zarr
    f = np.ascontiguousarray(f, dtype=np.float32)
    if not np.isfinite(f).all():
        raise InputError(f"the cube holds NaN or infinite amplitudes in inlines {block[0]}-{block[1] - 1} (indices); "
                         "replace them (e.g. by 0) before tracing faults")
    prob = fault_probability(f, options=opt, scale=scale, origin=origin)
    c0, c1, d0, d1 = core
    i0, i1, j0, j1 = block
    zarr.open_array(f"{work}/probability", mode="r+")[i0:i1, j0:j1, :] = prob[c0:c1, d0:d1]
    write_marker(marker, {})
    return {}


def _orientation_block(block, plan: dict, work, partial, opt, marker) -> dict:
    """Strike and dip of one block from the probability around it, written with the likelihood to the output."""
    import zarr
    n0, n1, _ = plan["shape"]
    halo = plan["halo_orientation"]
    i0, i1, j0, j1 = block
    a0, a1, b0, b1 = max(i0 - halo, 0), min(i1 + halo, n0), max(j0 - halo, 0), min(j1 + halo, n1)
    prob = zarr.open_array(f"{work}/probability", mode="r")[a0:a1, b0:b1]
    strike, dip = orientation_from_likelihood(prob, sigma=float(opt.orientation_sigma))
    core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
    group = zarr.open_group(partial, mode="r+")
    likelihood = np.where(dip[core] < float(opt.min_dip), np.float32(0.0), prob[core])
    group["likelihood"][i0:i1, j0:j1] = likelihood
    group["strike_deg"][i0:i1, j0:j1] = strike[core]
    group["dip_deg"][i0:i1, j0:j1] = dip[core]
    result = {"high": int(np.count_nonzero(likelihood > 0.9))}
    write_marker(marker, result)
    return result
