"""The work of each step of the fault surfaces by blocks (:mod:`~seismo3d.seismic.faults.blocks.surface_blocks`) on one
block: fill values, ridges and seeds, seed surfaces, votes, thinned votes, the thresholds' statistics and the cells;
each
reads its inputs from the run's stores, writes its outputs there and leaves a marker when done (resumable)."""

from __future__ import annotations

import pathlib

import numpy as np

from ...._atomic import atomic_path
from ...attributes import structure_tensor_slopes
from ...blocks.executor import write_marker
from ..surfaces.dead_samples import dead_samples, fill_values, near_dead_samples
from ..options import FaultTracingOptions
from ..surfaces.ridges import live_likelihood, ridges, thin_votes, without_dead_edges
from .surface_plan import RIDGE_HALO, SURFACE_BATCH_BYTES, THIN_HALO, SurfacePlan, around
from ..surfaces.thresholds import block_histogram
from ..surfaces.voting import SeedSurfaces, VoteSum, seed_surfaces

__all__ = ["cell_block", "fill_block", "gather_block", "histogram_block", "ridge_block", "save_npz", "surface_block",
           "surfaces_of", "thin_block", "vote_block"]


def save_npz(path: pathlib.Path, **arrays) -> None:
    with atomic_path(str(path)) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)


def fill_block(f, lo, hi, dead, marker) -> dict:
    result = {"fill": [float(v) for v in fill_values(np.asarray(f, np.float32), lo, hi, options=dead)]}
    write_marker(marker, result)
    return result


def ridge_block(f, origin, block, fill, lo, hi, likelihood, work, partial, plan: SurfacePlan, opt: FaultTracingOptions,
                 marker) -> dict:
    """Dead samples, live likelihood and ridges of one block; seed candidates of its core saved."""
    import zarr
    n0, n1, _ = plan.shape
    i0, i1, j0, j1 = block
    f = np.asarray(f, np.float32)
    write_slopes(f, origin, block, partial)
    dead = dead_samples(f, fill, lo, hi, options=opt.dead)
    del f
    near = near_dead_samples(dead, options=opt.dead) if dead.any() else None
    del dead
    a0, a1, b0, b1 = around(block, RIDGE_HALO, plan.shape)
    group = zarr.open_group(likelihood, mode="r")
    fl = group["likelihood"][a0:a1, b0:b1]
    st = group["strike_deg"][a0:a1, b0:b1]
    dp = group["dip_deg"][a0:a1, b0:b1]
    if near is not None:
        near = near[a0 - origin[0]:a1 - origin[0], b0 - origin[1]:b1 - origin[1]]
    core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
    high, live = live_likelihood(fl, near, core)
    zarr.open_group(partial, mode="r+")["likelihood"][i0:i1, j0:j1] = fl[core]
    if near is not None:
        zarr.open_array(f"{work}/near", mode="r+")[i0:i1, j0:j1] = near[core].view(np.uint8)
    ridge = ridges(fl, st, dp, opt.voting.seed_threshold)[core]
    cand = np.argwhere(ridge > float(opt.voting.seed_threshold))
    at = tuple(cand.T)
    local = (cand[:, 0] + i0 - a0, cand[:, 1] + j0 - b0, cand[:, 2])
    save_npz(pathlib.Path(work) / "candidates" / f"{i0}-{j0}.npz",
              points=(cand + np.array([i0, j0, 0])).astype(np.int64), values=ridge[at].astype(np.float32),
              angles=np.stack([st[local], dp[local]], axis=-1).astype(np.float32))
    result = {"high": high, "live": live}
    write_marker(marker, result)
    return result


def write_slopes(f: np.ndarray, origin, block, partial) -> None:
    """Reflector slopes (:func:`structure_tensor_slopes`, as the throws read them in memory) of a block's core,
    from its amplitudes read with at least :func:`structure_tensor_halo` traces of halo."""
    import zarr
    i0, i1, j0, j1 = block
    core = (slice(i0 - origin[0], i1 - origin[0]), slice(j0 - origin[1], j1 - origin[1]))
    slopes = structure_tensor_slopes(f)
    group = zarr.open_group(partial, mode="r+")
    group["slope_inline"][i0:i1, j0:j1] = slopes[0][core]
    group["slope_xline"][i0:i1, j0:j1] = slopes[1][core]


def surface_block(block, seeds, ids, frames, work, partial, plan: SurfacePlan, opt: FaultTracingOptions,
                   marker) -> dict:
    """The optimal surfaces of the seeds of one block, on the live likelihood read with the voting's reach around
    it, saved in ``work/surfaces`` (offsets as a .npy, read back row by row; ids, votes and normals)."""
    import zarr
    a0, a1, b0, b1 = around(block, plan.reach, plan.shape)
    att = zarr.open_group(partial, mode="r")["likelihood"][a0:a1, b0:b1]
    found = seed_surfaces(att, seeds, frames, image_shape=plan.shape, options=opt.voting, origin=(a0, b0))
    del att
    stem = pathlib.Path(work) / "surfaces" / f"{block[0]}-{block[2]}"
    with atomic_path(str(stem) + ".offsets.npy") as tmp, open(tmp, "wb") as fh:
        np.save(fh, found.offsets)
    save_npz(stem.with_suffix(".npz"), ids=np.asarray(ids, np.int64), mean_likelihood=found.mean_likelihood,
              normals=found.normals)
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


def thin_block(block, work, partial, plan: SurfacePlan, marker) -> dict:
    """Thinned votes of one block; the count, smallest and largest of the positive ones."""
    import zarr
    i0, i1, j0, j1 = block
    a0, a1, b0, b1 = around(block, THIN_HALO, plan.shape)
    group = zarr.open_group(partial, mode="r")
    votes = group["votes"][a0:a1, b0:b1]
    thin = thin_votes(votes, group["vote_strike_deg"][a0:a1, b0:b1],
                      group["vote_dip_deg"][a0:a1, b0:b1])[i0 - a0:i1 - a0, j0 - b0:j1 - b0]
    del votes
    zarr.open_array(f"{work}/thin_raw", mode="r+")[i0:i1, j0:j1] = thin
    positive = thin[thin > 0]
    result = {"count": int(positive.size), "min": float(positive.min()) if positive.size else 0.0,
              "max": float(positive.max()) if positive.size else 0.0}
    write_marker(marker, result)
    return result


def positive_thin(block, work) -> np.ndarray:
    import zarr
    i0, i1, j0, j1 = block
    thin = zarr.open_array(f"{work}/thin_raw", mode="r")[i0:i1, j0:j1]
    return thin[thin > 0]


def histogram_block(block, work, vmin, vmax, bins, marker) -> dict:
    result = {"counts": block_histogram(positive_thin(block, work), vmin, vmax, bins).tolist()}
    write_marker(marker, result)
    return result


def gather_block(block, work, lo_edge, hi_edge, marker) -> dict:
    values = positive_thin(block, work)
    result = {"below": int(np.count_nonzero(values < lo_edge)),
              "values": values[(values >= lo_edge) & (values <= hi_edge)].tolist()}
    write_marker(marker, result)
    return result


def cell_block(block, work, partial, lower, marker) -> dict:
    """The thinned votes at or above ``lower`` of one block, written to the output and saved as cells."""
    import zarr
    i0, i1, j0, j1 = block
    thin = zarr.open_array(f"{work}/thin_raw", mode="r")[i0:i1, j0:j1]
    thin[thin < lower] = 0.0
    group = zarr.open_group(partial, mode="r+")
    group["thin"][i0:i1, j0:j1] = thin
    cells = np.argwhere(thin >= lower)
    at = tuple(cells.T)
    save_npz(pathlib.Path(work) / "cells" / f"{i0}-{j0}.npz",
              points=(cells + np.array([i0, j0, 0])).astype(np.int64), values=thin[at],
              strike=group["vote_strike_deg"][i0:i1, j0:j1][at], dip=group["vote_dip_deg"][i0:i1, j0:j1][at])
    result = {"count": int(len(cells))}
    write_marker(marker, result)
    return result
