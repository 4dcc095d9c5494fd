"""Resumable block-by-block runs on dask: the bookkeeping the chunked steps of a cube larger than memory share.

A run owns a work folder holding a manifest (what is computed: the cube's shape, the options, the block plan) and a
marker per finished block, written atomically after the block's data. Started again with the same manifest, a run
skips the blocks whose markers exist; with another manifest it is refused, so an unfinished run of one cube is never
completed with the blocks of another. Blocks are dask delayed tasks run on the local threaded scheduler, one thread
(``'synchronous'``), or a ``dask.distributed`` cluster given by its address, with progress per finished block.

The blocks are planned once, before the run, from the steps' declarations (:class:`BlockStep`: whether a step maps,
reduces or gathers, its halo, the bytes of a block) and the memory limit (:func:`block_budget`, :func:`plan_steps`).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import json
import math
import os
import pathlib
import sys
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..._atomic import atomic_path
from ..._progress import LOGGER, progress_steps
from ...errors import EarlierStoresError, InputError

__all__ = ["BlockRun", "BlockStep", "SchedulerClient", "MEMORY_HEADROOM", "block_budget", "kernel_threads",
           "largest_block", "lateral_blocks", "limit_for_blocks", "plan_steps", "release_memory", "run_block",
           "serial_step_blocks", "trace_cube", "write_marker"]

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


# glibc's malloc options (malloc.h): allocations above M_MMAP_THRESHOLD are mapped and unmapped on their own, so a
# freed block's memory goes back to the system at once; setting it also stops glibc raising the threshold as large
# blocks are freed (its default), which otherwise leaves the freed blocks of one step resident through the next.
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
_LARGE = 16 << 20


def _libc():
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        return libc if hasattr(libc, "malloc_trim") and hasattr(libc, "mallopt") else None
    except OSError:  # pragma: no cover - not glibc
        return None


def release_memory() -> None:
    """Return freed memory to the system between the blocks of a chunked run (glibc: blocks over 16 MiB mapped on
    their own, and ``malloc_trim``); nothing elsewhere. Without it the resident memory of a process creeps up by the
    freed arrays of earlier blocks, beyond the memory limit the blocks were sized for (the dask documentation's
    "memory not released back to the OS")."""
    libc = _libc()
    if libc is None:
        return
    libc.mallopt(_M_MMAP_THRESHOLD, _LARGE)
    libc.mallopt(_M_TRIM_THRESHOLD, _LARGE)
    libc.malloc_trim(0)


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


@dataclass(frozen=True)
class BlockStep:
    """A step of a run by blocks, declared with what the executor needs to plan it; what the step computes on a
    block is its caller's.

    Attributes
    ----------
    name : str
        The step's name (its key in the plan, its markers' prefix).
    kind : {'map', 'reduce', 'gather'}
        ``'map'``: each block writes its core of an output; ``'reduce'``: each block returns a small statistic
        combined over the blocks (sums, a histogram, a range); ``'gather'``: each block returns a sparse list
        gathered in memory (seed candidates, cells). A step may also return what a later step reduces or gathers
        (its ``kind`` names what it is planned for).
    halo : int
        Traces read on each lateral side of a block's core.
    block_bytes : callable
        ``block_bytes(side) -> int``: bytes at the step's peak for a block of ``side`` traces a side (its halo
        included), the model of the step's arrays.
    cap : int
        Largest side considered, traces.
    fixed : int, optional
        A side forced by the caller (``ChunkOptions.block`` or ``strip``): used as is, and refused by the caller
        when it does not fit.
    """

    name: str
    kind: str
    halo: int
    block_bytes: Callable[[int], int]
    cap: int
    fixed: int | None = None

    def __post_init__(self):
        if self.kind not in STEP_KINDS:
            raise InputError(f"BlockStep(kind=...) must be one of {', '.join(STEP_KINDS)}; got {self.kind!r}")


def plan_steps(steps, *, tile: int, budget: int) -> dict:
    """The side of each step's blocks: its ``fixed`` side, else the largest multiple of ``tile`` up to its ``cap``
    whose :attr:`BlockStep.block_bytes` fit ``budget`` (``tile`` at least: the caller refuses a step whose smallest
    block does not fit, with its own message).

    Parameters
    ----------
    steps : iterable of BlockStep
    tile : int
        Traces a side of a chunk; blocks are whole chunks.
    budget : int
        Bytes one worker's block may use (:func:`block_budget`).

    Returns
    -------
    dict
        ``{step name: side}``, traces, in the steps' order.
    """
    return {s.name: int(s.fixed) if s.fixed else largest_block(int(tile), int(s.cap),
                                                                lambda b, s=s: s.block_bytes(b) <= budget)
            for s in steps}


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
    cores = _usable_cores() if scheduler in (None, "threads") else 1
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


def write_marker(path, payload: dict) -> None:
    """Write a block's marker (its small JSON result) atomically: a marker that exists is complete.

    Parameters
    ----------
    path : str or os.PathLike
        The marker file (:meth:`BlockRun.marker`).
    payload : dict
        JSON-serialisable result of the block, returned again when a resumed run skips it.
    """
    with atomic_path(str(path)) as tmp, open(tmp, "w") as fh:
        json.dump(payload, fh)


def _usable_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def kernel_threads(client) -> dict:
    """Numba threads for one block task on each host of a ``dask.distributed`` cluster: the host's cores shared by
    the worker threads running there (at least 1).

    Every worker thread runs one block at a time and each block's kernels are parallel (numba): left at numba's
    default (every core), two workers on a 2-core host run 4 kernel threads on 2 cores, and their serial parts
    (reads, writes, numpy) no longer overlap the other worker's kernels.

    Parameters
    ----------
    client : distributed.Client

    Returns
    -------
    dict
        ``{host: threads}``, host as in the scheduler's worker information.
    """
    workers = client.scheduler_info(n_workers=-1)["workers"]
    cores = client.run(_usable_cores)
    threads_on, cores_on = {}, {}
    for address, info in workers.items():
        host = info["host"]
        threads_on[host] = threads_on.get(host, 0) + int(info["nthreads"])
        cores_on[host] = max(cores_on.get(host, 1), int(cores.get(address, 1)))
    return {host: max(1, cores_on[host] // threads_on[host]) for host in threads_on}


def run_block(fn, threads, *args):
    """``fn(*args)`` with numba's kernel threads of this task set from ``threads`` (:func:`kernel_threads`, on a
    ``dask.distributed`` worker; None: left as they are).

    Parameters
    ----------
    fn : callable
        A block task.
    threads : dict or None
        ``{host: threads}``; the worker's host is looked up (the smallest value when it is missing).
    *args
        Arguments of ``fn``.

    Returns
    -------
    The result of ``fn``.
    """
    if not threads:
        return fn(*args)
    import numba
    from distributed import get_worker
    from distributed.comm import get_address_host

    n = threads.get(get_address_host(get_worker().address), min(threads.values()))
    before = numba.get_num_threads()
    numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))  # numba's setting is per thread
    try:
        return fn(*args)
    finally:
        numba.set_num_threads(before)


class SchedulerClient:
    """Context manager: the ``dask.distributed`` client of a scheduler address, or None for the local schedulers
    (None, ``'threads'``, ``'synchronous'``); closed on exit.

    Raises
    ------
    InputError
        The address cannot be reached within 5 s.
    """

    def __init__(self, scheduler):
        self.scheduler = scheduler
        self.client = None

    def __enter__(self):
        if self.scheduler is None or self.scheduler in ("threads", "synchronous"):
            return None
        from distributed import Client
        try:
            self.client = Client(self.scheduler, timeout="5s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the dask scheduler at {self.scheduler} ({exc}); start it (dask scheduler) "
                             "and its workers first, or leave out the scheduler to run here") from exc
        return self.client

    def __exit__(self, *exc):
        if self.client is not None:
            self.client.close()


class BlockRun:
    """The work folder, markers and task execution of one resumable chunked run.

    Parameters
    ----------
    work : pathlib.Path
        Work folder (created).
    scheduler : str, optional
        None / ``'threads'``, ``'synchronous'``, or a ``dask.distributed`` address (used through :attr:`client`,
        set by the caller inside a :class:`SchedulerClient`).
    workers : int
        Blocks computed at once on the threaded scheduler.
    progress : bool
        Report progress per finished block.

    Attributes
    ----------
    computed, resumed : dict
        Blocks computed and skipped (finished by an earlier run) per step.
    seconds : dict
        Wall-clock seconds per step.
    client : distributed.Client or None
    """

    def __init__(self, work: pathlib.Path, *, scheduler=None, workers: int = 1, progress: bool = False):
        self.work = pathlib.Path(work)
        self.scheduler, self.workers, self.progress = scheduler, int(workers), progress
        self.computed, self.resumed, self.seconds = {}, {}, {}
        self.client = None
        self._kernel_threads = None

    def open(self, manifest: dict, what: str) -> None:
        """Create the work folder with ``manifest``, or check that an existing one holds the same manifest.

        Raises
        ------
        InputError
            The folder holds an unfinished run of another cube or other options (``what`` names the folders to
            delete to start afresh).
        """
        path = self.work / "manifest.json"
        if self.work.exists():
            try:
                earlier = json.loads(path.read_text())
            except (OSError, ValueError):
                earlier = None
            if earlier != manifest:
                raise EarlierStoresError(f"{self.work} holds an unfinished run of another cube or other options; "
                                         f"delete {what} to start afresh, or rerun with the same input and options "
                                         "to resume it", [self.work])
        else:
            (self.work / "done").mkdir(parents=True)
            path.write_text(json.dumps(manifest))

    def earlier_plan(self, manifest: dict) -> dict | None:
        """The block plan of an unfinished run of the same work (its manifest equal to ``manifest`` but for the
        ``plan`` key), or None: a resumed run keeps its blocks even when the memory left for it has changed."""
        try:
            earlier = json.loads((self.work / "manifest.json").read_text())
        except (OSError, ValueError):
            return None
        same = {k: v for k, v in earlier.items() if k != "plan"} == {k: v for k, v in manifest.items() if k != "plan"}
        return earlier.get("plan") if same else None

    def task(self, fn, *args, threads: bool = True):
        """A dask delayed task ``fn(*args)`` of one block (impure: run once per compute), named after ``fn``; on a
        ``dask.distributed`` cluster its kernels use the worker's share of the host's cores (:func:`kernel_threads`)
        unless ``threads`` is False (a step whose float sums depend on the number of threads, kept as in memory)."""
        import dask

        share = None
        if threads and self.client is not None:
            if self._kernel_threads is None:
                self._kernel_threads = kernel_threads(self.client)
            share = self._kernel_threads
        name = f"{fn.__name__.strip('_')}-{uuid.uuid4().hex}"
        return dask.delayed(run_block, pure=False)(fn, share, *args, dask_key_name=name)

    def saved(self, name: str, compute):
        """A small result of the whole run (a statistic of the cube), computed once: ``compute()`` the first time,
        kept in the work folder as ``name.json`` (written atomically, like a marker) and read from there by a
        resumed run.

        Parameters
        ----------
        name : str
            The result's name (its file's stem).
        compute : callable
            ``compute() -> value``, a JSON-serialisable value.

        Returns
        -------
        The computed value, or the value as read back from JSON (lists for tuples).
        """
        path = self.work / f"{name}.json"
        if path.exists():
            return json.loads(path.read_text())
        value = compute()
        write_marker(path, value)
        return value

    def marker(self, step: str, block) -> pathlib.Path:
        """The marker file of ``block`` (a tuple whose items 0 and 2 are its first inline and crossline) in
        ``step``."""
        return self.work / "done" / f"{step}-{block[0]}-{block[2]}.json"

    def pending(self, step: str, blocks) -> tuple[list, list]:
        """(blocks still to compute, results of the finished ones) of ``step``; counts them."""
        done = [b for b in blocks if self.marker(step, b).exists()]
        todo = [b for b in blocks if not self.marker(step, b).exists()]
        self.resumed[step] = len(done)
        self.computed[step] = len(todo)
        if done:
            LOGGER.info("%s: %d of %d blocks finished by an earlier run, skipped; %d to compute", step, len(done),
                        len(done) + len(todo), len(todo))
        return todo, [json.loads(self.marker(step, b).read_text()) for b in done]

    def each_block(self, step: str, label: str, fn, blocks, *args, workers: int | None = None) -> list:
        """``fn(block, *args, marker)`` on every block of ``step`` not finished yet (:meth:`task`, :meth:`compute`,
        ``workers`` blocks at once on the threaded scheduler, default the run's); the results of the computed
        blocks, then those of the finished ones."""
        todo, done = self.pending(step, blocks)
        tasks = [self.task(fn, b, *args, str(self.marker(step, b))) for b in todo]
        return self.compute(tasks, label, step, workers=workers) + done

    def compute(self, tasks: list, label: str, step: str, *, workers: int | None = None) -> list:
        """Run delayed block tasks on the chosen scheduler (``workers`` at once on the threaded one, default the
        run's), reporting each finished block; their results in order."""
        start = time.perf_counter()
        release_memory()
        try:
            return self._compute_tasks(tasks, label, self.workers if workers is None else int(workers))
        finally:
            self.seconds[step] = round(self.seconds.get(step, 0.0) + time.perf_counter() - start, 2)

    def _compute_tasks(self, tasks: list, label: str, workers: int) -> list:
        import dask
        if not tasks:
            return []
        with progress_steps(len(tasks), label, unit="block", enabled=self.progress) as bar:
            if self.client is not None:
                from distributed import as_completed
                futures = self.client.compute(tasks)
                index = {f.key: i for i, f in enumerate(futures)}
                results = [None] * len(tasks)
                for fut in as_completed(futures):
                    results[index[fut.key]] = fut.result()
                    bar.advance()
                return results
            from dask.callbacks import Callback

            names = {t.key for t in tasks}

            class _Count(Callback):
                def _posttask(self, key, result, dsk, state, worker_id):
                    if key in names:
                        release_memory()
                        bar.advance()

            scheduler = "synchronous" if self.scheduler == "synchronous" else "threads"
            with _Count():
                return list(dask.compute(*tasks, scheduler=scheduler, num_workers=workers))


def lateral_blocks(shape, size0: int, size1: int) -> list:
    """``(i0, i1, j0, j1)`` of the blocks of ``size0`` inlines by ``size1`` crosslines (every sample) that tile a cube
    of ``shape``, inline-major."""
    n0, n1 = shape[:2]
    return [(i, min(i + size0, n0), j, min(j + size1, n1)) for i in range(0, n0, size0) for j in range(0, n1, size1)]


def trace_cube(cube, what: str):
    """``cube`` as a dask array whose chunks hold whole traces (3D, at least 3 samples per axis).

    Raises
    ------
    InputError
        The cube is not 3D with at least 3 samples per axis (``what`` names the computation in the message).
    """
    import dask.array as da

    x = cube if isinstance(cube, da.Array) else np.asarray(cube)
    if x.ndim != 3 or min(x.shape) < 3:
        raise InputError(f"{what} needs a 3D cube (n_inlines, n_xlines, n_samples) with at least 3 samples per axis; "
                         f"got shape {x.shape}")
    if not isinstance(x, da.Array):
        x = da.from_array(x, chunks=(64, -1, -1))
    if len(x.chunks[2]) != 1:
        x = x.rechunk({2: -1})
    return x
