"""The blocks of a fault-surface run by blocks (:mod:`~seismo3d.seismic.faults.blocks.surface_blocks`): the halo each
step reads, the memory a block of each step needs, and the largest blocks a memory limit allows."""

from __future__ import annotations

from dataclasses import dataclass

import numba

from ....errors import InputError
from ...attributes import structure_tensor_halo
from ...blocks.executor import block_budget, largest_block
from ..options import FaultTracingOptions
from ...blocks.options import ChunkOptions
from ...blocks.memory import default_memory_limit

__all__ = ["CANDIDATE_BYTES", "CELL_BYTES", "RIDGE_HALO", "SURFACE_BATCH_BYTES", "SurfacePlan", "THIN_HALO",
           "amplitude_halo", "around", "plan_blocks", "smallest_block_bytes", "square_blocks"]

# Lateral halo of the ridges (thin_faults with its defaults): the Gaussian of sigma 1.5 (5 traces), the average along
# the dip over +-4 samples on planes steeper than 45 degrees (4 traces, +1 for the bilinear reads), and the
# comparison one sample across the fault (+1, +1 for the trilinear reads).
RIDGE_HALO = 12
# Lateral halo of the thinning of the votes (no smoothing): one sample across the fault, trilinear reads.
THIN_HALO = 2
# Bytes of working memory per sample of a block (incl. halo): amplitudes, their reflector slopes and the dead-sample
# masks; likelihood, strike, dip, the ranking image and its smoothing passes, ridges (and, until stop 49, the
# hysteresis labels: the ridges now peak at 21, the slopes at 36 per amplitude sample; the constants were kept); the
# voting's core (votes, strongest surface and its seed per numba thread; the summed votes, strike, dip) and its
# input; the thinning of the votes.
# (tracemalloc peaks on 96-trace blocks of 512 samples: ridges 44 per sample of the likelihood's halo block, amplitudes
# included; voting 32 per core sample with 2 threads besides the input, 8 + 12 per thread; thinning 41)
_DEAD_BYTES = 12
_RIDGE_BYTES = 48
_VOTE_CORE_BYTES = 12
_VOTE_THREAD_BYTES = 12  # per numba thread: its votes, strongest surface and seed (each thread its own arrays)
_VOTE_HALO_BYTES = 4
# Surfaces of seeds read back at once by a block of the voting (the rest of the seeds reaching it come in later
# batches, in id order).
SURFACE_BATCH_BYTES = 16 << 20
_THIN_BYTES = 44
# Bytes per seed candidate and per cell while they are gathered, sorted and linked (keys, values, strike, dip,
# frames, links, labels, the merging's KD-tree; measured 219-234 bytes a cell on 1.4 M cells of a 512^3 cube, 250 on
# the 11 M cells of a 1448 x 1448 x 512 one).
CANDIDATE_BYTES = 80  # points, values, angles (36), the sort keys, order and sorted copy
CELL_BYTES = 240



@dataclass(frozen=True)
class SurfacePlan:
    """Block sizes (traces a side) of the steps of a run by blocks, and the voting's reach."""

    shape: tuple
    tile: int
    dead: int     # block sizes (traces a side) of the steps
    ridge: int
    vote: int
    thin: int
    reach: int    # a voting box's reach from its seed


def amplitude_halo(opt: FaultTracingOptions) -> int:
    """Traces of amplitudes read around a block of the ridge step: the dead samples' reach around the likelihood's
    halo, and the structure tensor's halo for the reflector slopes."""
    return max(RIDGE_HALO + opt.dead.reach[0], structure_tensor_halo()[0])


def _step_bytes(shape, opt: FaultTracingOptions) -> dict:
    """Bytes a block of ``b`` traces a side needs in each step (dead samples, ridges, voting, thinning): functions of
    ``b`` by step name."""
    nt = shape[2]
    reach = opt.voting.reach(shape)
    threads = numba.get_num_threads()

    def dead_bytes(b):
        return b * b * nt * _DEAD_BYTES

    def ridge_bytes(b):
        h = amplitude_halo(opt)
        return (b + 2 * h) ** 2 * nt * _DEAD_BYTES + (b + 2 * RIDGE_HALO) ** 2 * nt * _RIDGE_BYTES

    # the surfaces of a block's seeds: at most one seed per (spacing + 1)^3 samples (greedy_seeds keeps them more
    # than spacing apart), each (2 rw + 1) x (2 rv + 1) offsets of 3 int8, its vote (float64) and normal (3 float32)
    _, rv, rw = opt.voting.box(shape)
    per_seed = (2 * rw + 1) * (2 * rv + 1) * 3 * (1 if reach < 127 else 2) + 20
    surface_density = per_seed / (opt.voting.spacing(3) + 1) ** 3  # bytes per sample of a block's core

    def vote_bytes(b):
        surfaces = (b + 2 * reach) ** 2 * nt * _VOTE_HALO_BYTES + b * b * nt * surface_density
        votes = b * b * nt * (_VOTE_CORE_BYTES + _VOTE_THREAD_BYTES * threads) + SURFACE_BATCH_BYTES
        return int(max(surfaces, votes))

    def thin_bytes(b):
        return (b + 2 * THIN_HALO) ** 2 * nt * _THIN_BYTES

    return {"dead": dead_bytes, "ridge": ridge_bytes, "vote": vote_bytes, "thin": thin_bytes}


def smallest_block_bytes(shape, options: FaultTracingOptions | None = None, tile: int = 32) -> int:
    """Bytes the largest step of :func:`chunked_fault_surfaces` needs with its smallest blocks (one ``tile`` a side),
    on top of the process itself: what ``memory_limit`` must leave for it (before the headroom).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    options : FaultTracingOptions, optional
    tile : int
        Traces a side of the smallest block (:attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile`).

    Returns
    -------
    int
    """
    steps = _step_bytes(tuple(int(n) for n in shape), options or FaultTracingOptions())
    return int(max(need(int(tile)) for need in steps.values()))


def plan_blocks(shape, opt: FaultTracingOptions, chunking: ChunkOptions, baseline: int) -> SurfacePlan:
    n0, n1, nt = shape
    tile = int(chunking.tile)
    limit = int(chunking.memory_limit or default_memory_limit())
    budget = block_budget(limit, baseline, int(chunking.workers))
    reach = opt.voting.reach(shape)
    cap = max(n0, n1)
    sizes = {}
    for name, need in _step_bytes(shape, opt).items():
        top = int(chunking.block) if chunking.block else min(cap, 512)
        sizes[name] = largest_block(tile, top, lambda b, need=need: need(b) <= budget)
        if need(sizes[name]) > budget:
            raise InputError(
                f"the fault surfaces of a {n0} x {n1} x {nt} cube need about "
                f"{(need(sizes[name]) * int(chunking.workers) + baseline) / 2**30:.2f} GiB per block but the memory "
                f"limit is {limit / 2**30:.2f} GiB: raise memory_limit (or use fewer workers)")
    return SurfacePlan((n0, n1, nt), tile, sizes["dead"], sizes["ridge"], sizes["vote"], sizes["thin"], reach)


def square_blocks(shape, size):
    """``(i0, i1, j0, j1)`` of the square blocks of ``size`` traces a side tiling a cube of ``shape``."""
    n0, n1 = shape[:2]
    return [(i, min(i + size, n0), j, min(j + size, n1)) for i in range(0, n0, size) for j in range(0, n1, size)]


def around(block, halo, shape):
    """(a0, a1, b0, b1): ``block`` grown by ``halo`` traces, clipped to the cube."""
    i0, i1, j0, j1 = block
    return max(i0 - halo, 0), min(i1 + halo, shape[0]), max(j0 - halo, 0), min(j1 + halo, shape[1])
