"""The plan of a run by blocks: its steps declared once (:class:`BlockStep`: what a block computes, whether the step
maps, reduces or gathers, the halo it reads, the bytes of a block), and the largest blocks a memory limit allows them
(:func:`block_budget`, :func:`plan_steps`, :func:`serial_step_blocks`), decided once before the run; and the stages
after the blocks that hold their data whole (:class:`HeldStage`: a gather's lists linked, the results written),
whose memory grows with the items gathered, not with a block (:func:`held_need`). The run itself is
:class:`~seismo3d.seismic.blocks.executor.BlockRun`'s (:meth:`~seismo3d.seismic.blocks.executor.BlockRun.run_step`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass

from ...errors import InputError

__all__ = ["BlockStep", "CUBE", "HeldStage", "MEMORY_HEADROOM", "STEP_KINDS", "around", "block_budget", "held_need",
           "largest_block", "lateral_blocks", "limit_for_blocks", "plan_steps", "serial_step_blocks", "smallest_need",
           "usable_cores"]

# Fraction of the memory left under a limit (less the process itself) that a run's blocks may plan for: the rest is
# for the allocator's fragmentation and the reads in flight (a chunked likelihood run peaked at 1.54 GB under a
# 1.4 GB limit without it).
MEMORY_HEADROOM = 0.8


def block_budget(limit: int, baseline: int, workers: int) -> int:
    """Bytes one worker's block may plan for under a memory limit: the limit less the process itself, times
    :data:`MEMORY_HEADROOM`, shared by the workers. Both likelihoods (scan and learned) and the fault surfaces plan
    with it; :func:`limit_for_blocks` is its inverse.

    Parameters
    ----------
    limit : int
        Memory limit, bytes.
    baseline : int
        Bytes the process holds before its blocks (:func:`~seismo3d.seismic.blocks.memory.worker_baseline`).
    workers : int
        Blocks computed at once (>= 1).

    Returns
    -------
    int
        Bytes; negative when the baseline is above the limit (no block fits).
    """
    return int((int(limit) - int(baseline)) * MEMORY_HEADROOM) // int(workers)


def limit_for_blocks(block_bytes: int, baseline: int, workers: int) -> int:
    """The smallest memory limit whose :func:`block_budget` holds a block of ``block_bytes`` per worker.

    Parameters
    ----------
    block_bytes : int
        Bytes of one block at its step's peak.
    baseline : int
        Bytes the process holds before its blocks.
    workers : int
        Blocks computed at once (>= 1).

    Returns
    -------
    int
        Bytes: ``baseline + ceil(block_bytes * workers / MEMORY_HEADROOM)``.
    """
    return int(baseline) + math.ceil(int(block_bytes) * int(workers) / MEMORY_HEADROOM)


def largest_block(tile: int, cap: int, fits) -> int:
    """The largest multiple of ``tile`` up to ``cap`` for which ``fits(size)`` holds (``tile`` at least).

    Parameters
    ----------
    tile : int
        Traces per side of a chunk; blocks are whole chunks.
    cap : int
        Largest size considered, traces.
    fits : callable
        ``fits(size) -> bool``: whether a block of ``size`` traces a side fits the memory budget.

    Returns
    -------
    int
    """
    size = tile
    while size + tile <= cap and fits(size + tile):
        size += tile
    return size


STEP_KINDS = ("map", "reduce", "gather")
# The name of the input cube among a step's declared inputs
CUBE = "cube"


@dataclass(frozen=True)
class BlockStep:
    """A step of a run by blocks, declared once with what the executor needs to plan and run it.

    Attributes
    ----------
    name : str
        The step's name (its key in the plan, its markers' prefix, its seconds' key).
    kind : {'map', 'reduce', 'gather'}
        ``'map'``: each block writes its core of an output; ``'reduce'``: each block returns a small statistic
        combined over the blocks (sums, a histogram, a range); ``'gather'``: each block returns a sparse list
        gathered in memory (seed candidates, cells). A step may also return what a later step reduces or gathers
        (its ``kind`` names what it is planned for).
    halo : int
        Traces read on each lateral side of a block's core.
    block_bytes : callable, optional
        ``block_bytes(side) -> int``: bytes at the step's peak for a block of ``side`` traces a side (its halo
        included), the model of the step's arrays; None for a step run on the blocks another step was planned for
        (left out of :func:`plan_steps`).
    cap : int
        Largest side considered, traces.
    fixed : int, optional
        A side forced by the caller (``ChunkOptions.block`` or ``strip``): used as is, and refused by the caller
        when it does not fit.
    function : callable, optional
        The step's algorithm on the arrays of one block, run by
        :meth:`~seismo3d.seismic.blocks.executor.BlockRun.run_step` (through
        :func:`~seismo3d.seismic.blocks.apply.apply_block`, which reads, writes and leaves the marker):
        ``function(*arrays, *args)`` (``function(place, *arrays, *args)`` with ``place``), the arrays its ``inputs``
        read around the block, returning a :class:`~seismo3d.seismic.blocks.apply.BlockOutput`.
    label : str
        What the progress reports name the step.
    region : callable, optional
        ``region(block) -> (a0, a1, b0, b1)``: the input traces a block reads; default the block grown by ``halo``
        (:func:`around`).
    threads : bool
        On a ``dask.distributed`` cluster, a block's kernels use the worker's share of the host's cores; False keeps
        the process's threads (a step whose float sums depend on the number of threads, kept as in memory).
    inputs : tuple of str
        The names of the arrays a block reads, :data:`CUBE` for the input cube (read with the step's ``region``
        or ``halo``, like the other inputs).
    outputs : tuple of str or of (str, str)
        Names of the ``(n_inlines, n_xlines, ...)`` arrays whose block core the step writes (the run's stores,
        :attr:`~seismo3d.seismic.blocks.executor.BlockRun.arrays`), each the name of an array the algorithm returns
        or ``(returned name, store name)``.
    place : bool
        Pass the block's :class:`~seismo3d.seismic.blocks.apply.BlockPlace` (its core and the region read) first.
    lazy : bool
        Pass the stored inputs as arrays read by slicing (Zarr arrays), not read around the block: for a step that
        reads them with other halos or layouts than its own (the algorithm slices them).
    trim : bool
        An output array over the region read is cut to the block's core (default); False: the outputs are the
        core already, on another grid than the region (the fault network's).
    combine : callable, optional
        ``combine(new, stored) -> array``: how an output's core combines with what is stored there (e.g.
        ``numpy.maximum``; default: replaced).
    """

    name: str
    kind: str
    halo: int = 0
    block_bytes: Callable[[int], int] | None = None
    cap: int = 0
    fixed: int | None = None
    function: Callable | None = None
    label: str = ""
    region: Callable | None = None
    threads: bool = True
    inputs: tuple = ()
    outputs: tuple = ()
    place: bool = False
    lazy: bool = False
    trim: bool = True
    combine: Callable | None = None

    def __post_init__(self):
        if self.kind not in STEP_KINDS:
            raise InputError(f"BlockStep(kind=...) must be one of {', '.join(STEP_KINDS)}; got {self.kind!r}")


@dataclass(frozen=True)
class HeldStage:
    """A stage of a run after its blocks that holds its data whole in the process (a gather's lists linked, its
    results written), declared once with its memory model.

    Its memory does not depend on the blocks' size (the blocks' arrays are freed before it starts), so it decides
    not the blocks but whether the run fits at all: :func:`held_need` beside the blocks' need.

    Attributes
    ----------
    name : str
        The stage's name (for messages).
    held_bytes : callable
        ``held_bytes(items) -> int``: the stage's peak bytes beyond the process as the run's plan counts it, with
        ``items`` gathered (e.g. fault cells); the model of the stage (fixed, per item and per sample parts measured
        on the run's data: the declaring module says where).
    """

    name: str
    held_bytes: Callable[[int], int]


def held_need(stages, items: int) -> tuple[int, str]:
    """The bytes of the largest of ``stages`` with ``items`` gathered, beyond the process, and its name.

    Parameters
    ----------
    stages : iterable of HeldStage
    items : int
        Items gathered (>= 0).

    Returns
    -------
    (int, str)
        Bytes (0 and ``''`` without stages).
    """
    found = [(int(stage.held_bytes(int(items))), stage.name) for stage in stages]
    return max(found) if found else (0, "")


def plan_steps(steps, chunking, *, baseline: int, what: str) -> dict:
    """The side of each step's blocks under a run's memory limit: its ``fixed`` side, else the largest multiple of
    the tile up to its ``cap`` whose :attr:`BlockStep.block_bytes` fit the :func:`block_budget`; refused when the
    largest block still needs more (a step whose smallest block does not fit gets the tile, then the refusal).

    Parameters
    ----------
    steps : iterable of BlockStep
        Those without ``block_bytes`` are left out.
    chunking : ChunkOptions
        Its memory limit (:attr:`~seismo3d.seismic.blocks.options.ChunkOptions.limit`), tile (blocks are whole
        chunks) and workers (blocks at once).
    baseline : int
        Bytes the process holds before its blocks (:func:`~seismo3d.seismic.blocks.memory.worker_baseline`).
    what : str
        What is computed, for the message, e.g. ``'a chunked run of a 400 x 400 x 500 cube'``.

    Returns
    -------
    dict
        ``{step name: side}``, traces, in the steps' order.

    Raises
    ------
    InputError
        A block needs more than the budget: the message names the memory it needs and the limit.
    """
    limit, workers, tile = chunking.limit, int(chunking.workers), int(chunking.tile)
    budget = block_budget(limit, baseline, workers)
    planned = [s for s in steps if s.block_bytes is not None]
    sizes = {s.name: int(s.fixed) if s.fixed else largest_block(tile, int(s.cap),
                                                                 lambda b, s=s: s.block_bytes(b) <= budget)
             for s in planned}
    need = max(s.block_bytes(sizes[s.name]) for s in planned)
    if need > budget:
        raise InputError(f"{what} needs about {(need * workers + baseline) / 2**30:.2f} GiB but the memory limit "
                         f"is {limit / 2**30:.2f} GiB: raise memory_limit (or use fewer workers)")
    return sizes


def smallest_need(steps, tile: int) -> int:
    """Bytes of the largest of ``steps`` with their smallest blocks (``tile`` traces a side): what a memory limit must
    leave beside the process (before :data:`MEMORY_HEADROOM`).

    Parameters
    ----------
    steps : iterable of BlockStep
        Those without ``block_bytes`` are left out.
    tile : int

    Returns
    -------
    int
    """
    return int(max(step.block_bytes(int(tile)) for step in steps if step.block_bytes is not None))


def serial_step_blocks(step: BlockStep, *, limit: int, baseline: int, workers: int, scheduler,
                       tile: int) -> tuple[int, int]:
    """Blocks at once and their side for a step whose kernels are mostly serial (numpy, ``scipy.ndimage``): on the
    local threaded scheduler, up to one block per core, each planned for its share of the memory.

    Used by the learned likelihood's strike-and-dip step (Gaussian filters: 1.18 CPU s per wall-clock s on 2 cores;
    on the 400 x 400 x 500 cube of ``benchmarks/fault_paths.py --only target`` under a 1 GB limit, 2 blocks of 64
    traces at once took 25 s against 35 s for 1 block of 96). The ridges' kernels (structure tensor, ridges) are
    parallel already (1.8 CPU s per s): 2 blocks of 64 at once took 48 s there against 46 s for one of 96.

    More blocks at once use the cores the serial kernels leave idle, but each is smaller, so its halo costs more.
    The count chosen minimises the step's time per core, ``((b + 2 halo) / b)**2 / n`` for ``n`` blocks of side
    ``b`` at once (``b`` the largest that fits the budget of ``n`` workers), never below ``workers``.

    Parameters
    ----------
    step : BlockStep
        The step: its halo (traces on each side of a block), the bytes of a block of ``side`` traces a side (its
        halo included) and the largest side (``cap``); its ``fixed`` side is not used (the caller's).
    limit, baseline : int
        Memory limit and the process's own bytes (:func:`block_budget`).
    workers : int
        Blocks at once asked for (the run's ``ChunkOptions.workers``).
    scheduler : str or None
        The run's scheduler: only the local threaded one (None, ``'threads'``) runs more blocks at once.
    tile : int
        Blocks are multiples of ``tile`` traces a side.

    Returns
    -------
    (int, int)
        Blocks at once and their side (``tile`` at least; the caller refuses a limit below what it needs).
    """
    cores = usable_cores() if scheduler in (None, "threads") else 1
    cap, halo, block_bytes = int(step.cap), int(step.halo), step.block_bytes
    best = None
    for n in range(int(workers), max(int(workers), cores) + 1):
        budget = block_budget(limit, baseline, n)
        side = largest_block(tile, cap, lambda b: block_bytes(b) <= budget)
        if block_bytes(side) > budget:
            break
        cost = ((side + 2 * halo) / side) ** 2 / min(n, cores)
        if best is None or cost < best[0] - 1e-9:
            best = (cost, n, side)
    if best is None:
        return int(workers), largest_block(tile, cap, lambda b: block_bytes(b) <= block_budget(limit, baseline,
                                                                                                  int(workers)))
    return best[1], best[2]


def usable_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def lateral_blocks(shape, size0: int, size1: int) -> list:
    """``(i0, i1, j0, j1)`` of the blocks of ``size0`` inlines by ``size1`` crosslines (every sample) that tile a cube
    of ``shape``, inline-major."""
    n0, n1 = shape[:2]
    return [(i, min(i + size0, n0), j, min(j + size1, n1)) for i in range(0, n0, size0) for j in range(0, n1, size1)]




def around(block, halo: int, shape) -> tuple:
    """``(a0, a1, b0, b1)``: ``block`` ``(i0, i1, j0, j1)`` grown by ``halo`` traces on each lateral side, clipped to
    a cube of ``shape``."""
    i0, i1, j0, j1 = block
    return max(i0 - halo, 0), min(i1 + halo, shape[0]), max(j0 - halo, 0), min(j1 + halo, shape[1])
