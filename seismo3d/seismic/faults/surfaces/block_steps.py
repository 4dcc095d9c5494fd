"""The block steps of the fault surfaces by blocks (:mod:`~seismo3d.seismic.faults.surfaces.blocks`), each
declared once (:func:`block_steps`) with what the executor needs to plan and run it: the halo it reads (``RIDGE_HALO``, ``THIN_HALO``, the voting's reach,
:func:`amplitude_halo`), the bytes a block needs (:func:`plan_blocks`: the largest blocks a memory limit allows), and
its work on one block: fill values, ridges and seeds, seed surfaces, votes, thinned votes, the thresholds' statistics
and the cells. Each block function reads its inputs from the run's stores, writes its outputs there and leaves a
marker when done (resumable); the algorithms are those of :mod:`~seismo3d.seismic.faults.surfaces`."""

from __future__ import annotations

import pathlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from ...._atomic import atomic_path
from ....errors import InputError
from ...attributes import structure_tensor_halo, structure_tensor_slopes
from ...blocks.executor import write_marker
from ...blocks.memory import default_memory_limit
from ...blocks.options import ChunkOptions
from ...blocks.apply import BlockOutput, save_lists
from ...blocks.plan import CUBE, BlockStep, around, block_budget, plan_steps
from .dead_samples import dead_samples, fill_values, near_dead_samples
from .ridges import live_likelihood, ridges, thin_votes, without_dead_edges
from .thresholds import block_histogram
from .voting import SeedSurfaces, VoteSum, seed_surfaces

if TYPE_CHECKING:  # annotations only: the options are passed in
    from ..options import FaultTracingOptions

__all__ = ["CANDIDATE_BYTES", "CELL_BYTES", "RIDGE_HALO", "SURFACE_BATCH_BYTES", "SurfacePlan", "THIN_HALO",
           "amplitude_halo", "block_steps", "cell_block", "fill_block", "gather_block", "histogram_block", "plan_blocks",
           "ridge_block", "smallest_block_bytes", "surface_block", "surfaces_of",
           "thin_block", "vote_block"]

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


# The fault likelihood's arrays the ridges read (the run's stores' names of the likelihood group's arrays)
LIKELIHOOD_INPUTS = ("fault_likelihood", "fault_strike_deg", "fault_dip_deg")


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


def block_steps(shape, opt: FaultTracingOptions, cap: int) -> tuple:
    """The block steps of the fault surfaces, declared once in their order, each with its block function, its halo
    and (those planned by :func:`~seismo3d.seismic.blocks.plan.plan_steps`) the bytes of a block of ``b`` traces a
    side: the fill values of the dead-sample rules (reduced over the blocks), the ridges (their seed candidates
    gathered), the voting (seed surfaces, then votes on the surfaces' blocks) and the thinning (its statistics
    reduced into the thresholds; the histograms, the quantile and the cells run on its blocks).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : FaultTracingOptions
    cap : int
        Largest side of a block, traces.

    Returns
    -------
    tuple of BlockStep
        Named ``'fill'``, ``'ridges'``, ``'surfaces'``, ``'thin'`` (planned: the fields ``dead``, ``ridge``,
        ``vote``, ``thin`` of :class:`SurfacePlan`), ``'votes'``, ``'histogram'``, ``'quantile_histogram'``,
        ``'quantile'``, ``'cells'``.
    """
    nt = shape[2]
    reach = opt.voting.reach(shape)
    threads = numba.get_num_threads()
    halo = amplitude_halo(opt)

    def dead_bytes(b):
        return b * b * nt * _DEAD_BYTES

    def ridge_bytes(b):
        return (b + 2 * halo) ** 2 * nt * _DEAD_BYTES + (b + 2 * RIDGE_HALO) ** 2 * nt * _RIDGE_BYTES

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

    return (BlockStep("fill", "reduce", 0, dead_bytes, cap, function=fill_block, label="fill values", inputs=(CUBE,)),
            # the amplitudes read with their halo, the likelihood (read by slicing) with the ridges'
            BlockStep("ridges", "gather", halo, ridge_bytes, cap, function=ridge_block, label="fault ridges",
                      inputs=(CUBE, *LIKELIHOOD_INPUTS), place=True, lazy=True,
                      outputs=("slope_inline", "slope_xline", "likelihood", "near")),
            BlockStep("surfaces", "map", reach, vote_bytes, cap, function=surface_block, label="fault surfaces"),
            # threads=False: the votes are summed per numba thread (voting.VoteSum), so a block's kernel keeps the
            # process's threads, as the in-memory run
            BlockStep("votes", "map", reach, function=vote_block, label="fault voting", threads=False),
            BlockStep("thin", "reduce", THIN_HALO, thin_bytes, cap, function=thin_block, label="thinning",
                      inputs=("votes", "vote_strike_deg", "vote_dip_deg"), outputs=("thin_raw",), place=True),
            BlockStep("histogram", "reduce", function=histogram_block, label="histogram of the thinned votes",
                      inputs=("thin_raw",)),
            BlockStep("quantile_histogram", "reduce", function=histogram_block,
                      label="histogram of the thinned votes", inputs=("thin_raw",)),
            BlockStep("quantile", "gather", function=gather_block, label="quantile of the thinned votes",
                      inputs=("thin_raw",)),
            BlockStep("cells", "gather", function=cell_block, label="fault cells",
                      inputs=("thin_raw", "vote_strike_deg", "vote_dip_deg"), outputs=("thin",), place=True))


def smallest_block_bytes(shape, options: FaultTracingOptions, tile: int) -> int:
    """Bytes the largest step of :func:`chunked_fault_surfaces` needs with its smallest blocks (one ``tile`` a side),
    on top of the process itself: what ``memory_limit`` must leave for it (before the headroom).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    options : FaultTracingOptions
    tile : int
        Traces a side of the smallest block (:attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile`).

    Returns
    -------
    int
    """
    steps = block_steps(tuple(int(n) for n in shape), options, int(tile))
    return int(max(step.block_bytes(int(tile)) for step in steps if step.block_bytes is not None))


def plan_blocks(shape, opt: FaultTracingOptions, chunking: ChunkOptions, baseline: int) -> SurfacePlan:
    """The largest blocks of each of :func:`block_steps` (multiples of ``chunking.tile``, at most ``chunking.block`` or
    512 traces a side) whose bytes fit the budget a memory limit leaves
    (:func:`~seismo3d.seismic.blocks.plan.block_budget`), by the executor's planner
    (:func:`~seismo3d.seismic.blocks.plan.plan_steps`).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : FaultTracingOptions
    chunking : ChunkOptions
        Memory limit (default half of the RAM), tile, largest block and workers.
    baseline : int
        Bytes the process holds before its blocks (:func:`~seismo3d.seismic.blocks.memory.worker_baseline`).

    Returns
    -------
    SurfacePlan

    Raises
    ------
    InputError
        The smallest blocks of a step need more than the budget (the message says by how much).
    """
    n0, n1, nt = shape
    tile = int(chunking.tile)
    limit = int(chunking.memory_limit or default_memory_limit())
    budget = block_budget(limit, baseline, int(chunking.workers))
    steps = block_steps(shape, opt, int(chunking.block) if chunking.block else min(max(n0, n1), 512))
    sizes = plan_steps(steps, tile=tile, budget=budget)
    for step in (step for step in steps if step.block_bytes is not None):
        need = step.block_bytes(sizes[step.name])
        if need > budget:
            raise InputError(
                f"the fault surfaces of a {n0} x {n1} x {nt} cube need about "
                f"{(need * int(chunking.workers) + baseline) / 2**30:.2f} GiB per block but the memory "
                f"limit is {limit / 2**30:.2f} GiB: raise memory_limit (or use fewer workers)")
    return SurfacePlan((n0, n1, nt), tile, sizes["fill"], sizes["ridges"], sizes["surfaces"], sizes["thin"],
                       opt.voting.reach(shape))


# -- the work of each step on one block ---------------------------------------------------------------------

def fill_block(f, lo: float, hi: float, dead) -> BlockOutput:
    """The fill values of one block of amplitudes under the dead-sample rules (:func:`fill_values`)."""
    return BlockOutput(summary={"fill": [float(v) for v in fill_values(np.asarray(f, np.float32), lo, hi,
                                                                        options=dead)]})


def ridge_block(place, f, likelihood, strike, dip, fill, lo: float, hi: float, shape,
                opt: FaultTracingOptions) -> BlockOutput:
    """Reflector slopes, dead samples, live likelihood and ridges of one block (Hale 2013).

    Parameters
    ----------
    place : BlockPlace
        The block's core and the region of ``f``.
    f : (m0, m1, n_samples) ndarray
        Amplitudes of ``place.region`` (the block grown by :func:`amplitude_halo`).
    likelihood, strike, dip : (n_inlines, n_xlines, n_samples) arrays read by slicing
        The fault likelihood, strike and dip of the cube, read around the block with ``RIDGE_HALO``.
    fill : (k,) float32 ndarray
        Fill values of the dead-sample rules; ``lo``, ``hi`` the cube's smallest and largest amplitudes.
    shape : (int, int, int)
        Of the cube.
    opt : FaultTracingOptions

    Returns
    -------
    BlockOutput
        The core's ``slope_inline``, ``slope_xline`` (:func:`structure_tensor_slopes`, as the throws read them in
        memory), ``likelihood`` (0 near dead samples) and ``near`` (uint8; None without dead samples); lists
        ``points`` (k, 3) int64, ``values`` (k,) float32 and ``angles`` (k, 2) float32 of the ridge samples above
        the seed threshold (the seed candidates); summary ``high``, ``live`` (:func:`live_likelihood`).
    """
    i0, i1, j0, j1 = place.block
    origin = place.origin
    f = np.asarray(f, np.float32)
    slopes = [p[place.core] for p in structure_tensor_slopes(f)]
    dead = dead_samples(f, fill, lo, hi, options=opt.dead)
    del f
    near = near_dead_samples(dead, options=opt.dead) if dead.any() else None
    del dead
    a0, a1, b0, b1 = around(place.block, RIDGE_HALO, shape)
    fl, st, dp = (a[a0:a1, b0:b1] for a in (likelihood, strike, dip))
    if near is not None:
        near = near[a0 - origin[0]:a1 - origin[0], b0 - origin[1]:b1 - origin[1]]
    core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
    high, live = live_likelihood(fl, near, core, level=opt.saturation_level)
    ridge = ridges(fl, st, dp, opt.voting.seed_threshold)[core]
    cand = np.argwhere(ridge > float(opt.voting.seed_threshold))
    at = tuple(cand.T)
    local = (cand[:, 0] + i0 - a0, cand[:, 1] + j0 - b0, cand[:, 2])
    candidates = {"points": (cand + np.array([i0, j0, 0])).astype(np.int64), "values": ridge[at].astype(np.float32),
                  "angles": np.stack([st[local], dp[local]], axis=-1).astype(np.float32)}
    arrays = {"slope_inline": slopes[0], "slope_xline": slopes[1], "likelihood": fl[core],
              "near": None if near is None else near[core].view(np.uint8)}
    return BlockOutput(arrays, {"high": high, "live": live}, candidates)


def surface_block(block, seeds, frames, work, partial, plan: SurfacePlan, opt: FaultTracingOptions,
                  marker) -> dict:
    """The optimal surfaces of the seeds in one block, on the live likelihood read with the voting's reach around
    it, saved in ``work/surfaces`` (offsets as a .npy, read back row by row; ids, votes and normals)."""
    import zarr
    i0, i1, j0, j1 = block
    ids = np.nonzero((seeds[:, 0] >= i0) & (seeds[:, 0] < i1) & (seeds[:, 1] >= j0) & (seeds[:, 1] < j1))[0]
    seeds, frames = seeds[ids], frames[ids]
    a0, a1, b0, b1 = around(block, plan.reach, plan.shape)
    att = zarr.open_group(partial, mode="r")["likelihood"][a0:a1, b0:b1]
    found = seed_surfaces(att, seeds, frames, image_shape=plan.shape, options=opt.voting, origin=(a0, b0))
    del att
    stem = pathlib.Path(work) / "surfaces" / f"{block[0]}-{block[2]}"
    with atomic_path(str(stem) + ".offsets.npy") as tmp, open(tmp, "wb") as fh:
        np.save(fh, found.offsets)
    save_lists(stem.with_suffix(".npz"), {"ids": np.asarray(ids, np.int64), "mean_likelihood": found.mean_likelihood,
                                          "normals": found.normals})
    write_marker(marker, {})
    return {}


def vote_block(block, seeds, blocks, work, partial, plan: SurfacePlan, opt: FaultTracingOptions, marker) -> dict:
    """Votes over one block's core of the surfaces of the seeds reaching it, added in id order (as in memory), a
    batch of at most ``SURFACE_BATCH_BYTES`` of surfaces at a time."""
    import zarr
    i0, i1, j0, j1 = block
    r = plan.reach
    total = VoteSum(plan.shape, (i0, j0, i1 - i0, j1 - j0), options=opt.voting)
    parts = []  # (ids, file, rows, stored votes and normals) of the seeds reaching the block, per seed block
    for b in blocks:  # seed blocks within reach
        if b[1] <= i0 - r or b[0] >= i1 + r or b[3] <= j0 - r or b[2] >= j1 + r:
            continue
        stem = pathlib.Path(work) / "surfaces" / f"{b[0]}-{b[2]}"
        with np.load(stem.with_suffix(".npz")) as saved:
            stored = dict(saved)
        at = seeds[stored["ids"]]
        rows = np.nonzero((at[:, 0] >= i0 - r) & (at[:, 0] < i1 + r) & (at[:, 1] >= j0 - r) &
                          (at[:, 1] < j1 + r))[0]
        if rows.size:
            parts.append((stored["ids"][rows], stem, rows, stored))
    if parts:
        ids = np.concatenate([q[0] for q in parts])
        which = np.concatenate([np.full(q[0].size, n) for n, q in enumerate(parts)])
        rows = np.concatenate([q[2] for q in parts])
        order = np.argsort(ids)
        ids, which, rows = ids[order], which[order], rows[order]
        per_seed = np.load(str(parts[0][1]) + ".offsets.npy", mmap_mode="r")[:1].nbytes + 32
        batch = max(1, SURFACE_BATCH_BYTES // per_seed)
        for lo in range(0, ids.size, batch):
            hi = min(lo + batch, ids.size)
            surfaces = surfaces_of(parts, which[lo:hi], rows[lo:hi])
            total.add(seeds[ids[lo:hi]], ids[lo:hi], surfaces)
            del surfaces
    votes = total.votes()
    del total
    without_dead_edges(votes.votes, zarr.open_array(f"{work}/near", mode="r")[i0:i1, j0:j1].view(bool))
    group = zarr.open_group(partial, mode="r+")
    group["votes"][i0:i1, j0:j1] = votes.votes
    group["vote_strike_deg"][i0:i1, j0:j1] = votes.strike_deg
    group["vote_dip_deg"][i0:i1, j0:j1] = votes.dip_deg
    write_marker(marker, {})
    return {}


def surfaces_of(parts, which, rows) -> SeedSurfaces:
    """The stored surfaces of a batch of seeds, in the batch's order: seed k is row ``rows[k]`` of seed block
    ``which[k]`` (an item of ``parts``)."""
    out = None
    for n, (_, stem, _, stored) in enumerate(parts):
        mine = np.nonzero(which == n)[0]
        if not mine.size:
            continue
        offsets = np.load(str(stem) + ".offsets.npy", mmap_mode="r")
        if out is None:
            out = SeedSurfaces(np.empty((which.size,) + offsets.shape[1:], offsets.dtype), np.empty(which.size),
                               np.empty((which.size, 3), np.float32))
        out.offsets[mine] = offsets[rows[mine]]
        del offsets
        out.mean_likelihood[mine] = stored["mean_likelihood"][rows[mine]]
        out.normals[mine] = stored["normals"][rows[mine]]
    return out


def thin_block(place, votes, strike, dip) -> BlockOutput:
    """Thinned votes of one block (:func:`thin_votes`, its votes read with ``THIN_HALO``); the count, smallest and
    largest of the positive ones of its core."""
    thin = thin_votes(votes, strike, dip)[place.core]
    positive = thin[thin > 0]
    return BlockOutput({"thin_raw": thin}, {"count": int(positive.size),
                                            "min": float(positive.min()) if positive.size else 0.0,
                                            "max": float(positive.max()) if positive.size else 0.0})


def histogram_block(thin, vmin: float, vmax: float, bins: int) -> BlockOutput:
    """The histogram of one block's positive thinned votes (:func:`block_histogram`)."""
    return BlockOutput(summary={"counts": block_histogram(thin[thin > 0], vmin, vmax, bins).tolist()})


def gather_block(thin, lo_edge: float, hi_edge: float) -> BlockOutput:
    """One block's positive thinned votes below ``lo_edge`` counted, and those in ``[lo_edge, hi_edge]``."""
    values = thin[thin > 0]
    return BlockOutput(summary={"below": int(np.count_nonzero(values < lo_edge)),
                                "values": values[(values >= lo_edge) & (values <= hi_edge)].tolist()})


def cell_block(place, thin, strike, dip, lower: float) -> BlockOutput:
    """The thinned votes at or above ``lower`` of one block (the others set to 0), and its cells (points, values,
    strike, dip) as lists."""
    thin[thin < lower] = 0.0
    cells = np.argwhere(thin >= lower)
    at = tuple(cells.T)
    i0, j0 = place.block[0], place.block[2]
    lists = {"points": (cells + np.array([i0, j0, 0])).astype(np.int64), "values": thin[at], "strike": strike[at],
             "dip": dip[at]}
    return BlockOutput({"thin": thin}, {"count": int(len(cells))}, lists)
