"""Resumable block-by-block runs on dask: the bookkeeping the chunked steps of a cube larger than memory share.

A run owns a work folder holding a manifest (what is computed: the cube's shape, the options, the block plan) and a
marker per finished block, written atomically after the block's data. Started again with the same manifest, a run
skips the blocks whose markers exist; with another manifest it is refused
(:func:`~seismo3d.seismic.blocks.stores.earlier_run`), so an unfinished run of one cube is never completed with the
blocks of another. Blocks are dask delayed tasks run on the local threaded scheduler, one thread
(``'synchronous'``), or a ``dask.distributed`` cluster given by its address, with progress per finished block.

The blocks are planned once, before the run, from the steps' declarations and the memory limit
(:mod:`~seismo3d.seismic.blocks.plan`); :meth:`BlockRun.run_step` runs a declared step
(:class:`~seismo3d.seismic.blocks.plan.BlockStep`) over its blocks: the blocks finished by an earlier run skipped,
each other block read with the step's halo from the input cube (or from the run's stores by the step's function),
its function called on it as a dask task, its marker written by the function after its data.

:class:`MemoryRun` runs the same declared steps in memory, each on one block, the whole cube: a computation written
once against ``run_step`` (the fault likelihoods' ``run_scan``, ``run_learned``) runs in memory and by blocks.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import json
import pathlib
import sys
import time
import uuid

import numpy as np

from ..._atomic import atomic_path
from ..._progress import LOGGER, progress_steps, reporting_within
from ...errors import InputError
from .apply import BlockPlace, apply_block, apply_in_memory, gather, load_lists, write_marker
from .plan import CUBE, BlockStep, around, usable_cores

__all__ = ["BlockRun", "MemoryRun", "kernel_threads", "release_memory", "run_block", "trace_cube"]

# glibc's malloc options (malloc.h): allocations above M_MMAP_THRESHOLD are mapped and unmapped on their own, so a
# freed block's memory goes back to the system at once; setting it also stops glibc raising the threshold as large
# blocks are freed (its default), which otherwise leaves the freed blocks of one step resident through the next.
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
_LARGE = 16 << 20


@functools.cache
def _libc():
    """glibc, loaded once by its soname (``malloc_trim`` and ``mallopt`` are glibc's); None elsewhere. Not
    ``ctypes.util.find_library``: it runs ``/sbin/ldconfig -p`` in a child process at every call, a fork of a process
    of the blocks' size after every block, which a sampler of the process and its children counts twice (the
    400 x 400 x 500 run of ``benchmarks/fault_paths.py --only target`` under 1 GB: 0.90 GiB resident, 1.39 GiB with
    the child)."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:  # pragma: no cover - not glibc (musl)
        return None
    return libc if hasattr(libc, "malloc_trim") and hasattr(libc, "mallopt") else None


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
    cores = client.run(usable_cores)
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


class _StepRun:
    """What both executors share: a step's sparse lists read through the executor's ``lists_reader``."""

    def step_lists(self, step: str, block, names, *, mmap_mode=None) -> dict:
        """The sparse lists ``names`` of ``block`` saved by the step named ``step`` (``mmap_mode='r'``: memory-mapped
        by a run by blocks, :func:`~seismo3d.seismic.blocks.apply.load_lists`)."""
        return self.lists_reader(step, mmap_mode=mmap_mode)(block, names)

    def gathered_lists(self, step: str, blocks, names) -> dict:
        """The sparse lists ``names`` of the step named ``step`` concatenated in the blocks' order
        (:func:`~seismo3d.seismic.blocks.apply.gather`)."""
        return gather(self.lists_reader(step), blocks, names)


class BlockRun(_StepRun):
    """The work folder, markers and task execution of one resumable chunked run.

    Parameters
    ----------
    work : pathlib.Path
        Work folder (created).
    scheduler : str, optional
        None / ``'threads'``, ``'synchronous'``, or a ``dask.distributed`` address (connected to by
        :meth:`scheduled`).
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
        The client of a ``dask.distributed`` scheduler, inside :meth:`scheduled`.
    arrays : dict
        ``{name: Zarr array path}``: the stores that declared steps read and write (set by
        :class:`~seismo3d.seismic.blocks.stores.StoreRun` and its callers).
    shape : tuple or None
        ``(n_inlines, n_xlines, n_samples)`` of the cube: the bounds of the regions read by declared steps that
        read no cube.
    """

    def __init__(self, work: pathlib.Path, *, scheduler=None, workers: int = 1, progress: bool = False):
        self.work = pathlib.Path(work)
        self.arrays, self.shape = {}, None
        self.scheduler, self.workers, self.progress = scheduler, int(workers), progress
        self.computed, self.resumed, self.seconds = {}, {}, {}
        self.client = None
        self._kernel_threads = None

    def open(self, manifest: dict) -> None:
        """Create the work folder with ``manifest`` (what is computed), or keep an existing one: whether it may be
        resumed is decided before, with the run's output (:func:`~seismo3d.seismic.blocks.stores.earlier_run`)."""
        if not self.work.exists():
            (self.work / "done").mkdir(parents=True)
            (self.work / "manifest.json").write_text(json.dumps(manifest))

    @contextlib.contextmanager
    def scheduled(self):
        """Context manager: the run's blocks computed on its scheduler; for a ``dask.distributed`` address its client
        is :attr:`client` inside, closed on exit (the local schedulers need none).

        Raises
        ------
        InputError
            The address cannot be reached within 5 s.
        """
        if self.scheduler is None or self.scheduler in ("threads", "synchronous"):
            yield self
            return
        from distributed import Client
        try:
            client = Client(self.scheduler, timeout="5s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the dask scheduler at {self.scheduler} ({exc}); start it (dask scheduler) "
                             "and its workers first, or leave out the scheduler to run here") from exc
        self.client = client
        try:
            yield self
        finally:
            self.client = None
            client.close()

    def release(self, *names) -> None:
        """Nothing: the arrays of a run by blocks stay in its work folder until it finishes
        (:meth:`MemoryRun.release`'s counterpart)."""

    def task(self, fn, *args, threads: bool = True, name: str | None = None):
        """A dask delayed task ``fn(*args)`` of one block (impure: run once per compute), named after ``fn``; on a
        ``dask.distributed`` cluster its kernels use the worker's share of the host's cores (:func:`kernel_threads`)
        unless ``threads`` is False (a step whose float sums depend on the number of threads, kept as in memory);
        ``name`` names the task instead of ``fn``. ``fn`` may be a :func:`functools.partial` holding what every block
        of a step shares (its options, arrays, paths): dask looks for collections in the task's arguments, rebuilding
        every dataclass and container it walks, but not inside a partial."""
        import dask

        share = None
        if threads and self.client is not None:
            if self._kernel_threads is None:
                self._kernel_threads = kernel_threads(self.client)
            share = self._kernel_threads
        label = name or getattr(fn, "__name__", None) or fn.func.__name__
        key = f"{label.strip('_')}-{uuid.uuid4().hex}"
        return dask.delayed(run_block, pure=False)(fn, share, *args, dask_key_name=key)

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

    def saved_arrays(self, name: str, compute) -> dict:
        """Arrays of the whole run (e.g. the voting's seeds), computed once: ``compute()`` the first time, kept in
        the work folder as ``name.npz`` (written atomically) and read from there by a resumed run.

        Parameters
        ----------
        name : str
            The file's stem.
        compute : callable
            ``compute() -> {name: ndarray}``.

        Returns
        -------
        dict
            ``{name: ndarray}``.
        """
        path = self.work / f"{name}.npz"
        if not path.exists():
            arrays = compute()
            with atomic_path(str(path)) as tmp, open(tmp, "wb") as fh:
                np.savez(fh, **arrays)
        with np.load(path) as saved:
            return {key: saved[key] for key in saved.files}

    def lists_reader(self, step: str, *, mmap_mode=None):
        """``reader(block, names)``: the sparse lists of a block saved by the step named ``step``
        (:func:`~seismo3d.seismic.blocks.apply.load_lists` of ``WORK/<step>/``), a function that a block task takes
        along (it holds the work folder only, never the run and its scheduler client, so that it pickles for a
        ``dask.distributed`` worker)."""
        return functools.partial(load_lists, self.work / step, mmap_mode=mmap_mode)

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

    def run_step(self, step: BlockStep, blocks, *args, source=None, workers: int | None = None) -> list:
        """Run a declared step on every block of ``blocks`` not finished by an earlier run: a dask task per block
        (:meth:`task`), ``workers`` blocks at once on the threaded scheduler (default the run's).

        Each block is :func:`~seismo3d.seismic.blocks.apply.apply_block`: its inputs read around it (the cube by
        dask from ``source``, the others from :attr:`arrays`), the step's algorithm called on arrays, the core of its
        outputs written to :attr:`arrays`, its lists saved in ``WORK/<step name>/``, its marker written last.

        Parameters
        ----------
        step : BlockStep
            Its name (markers, seconds), function, label, halo or region, declared inputs and outputs, and whether
            its kernels take the worker's share of the cores.
        blocks : list of tuple
            ``(i0, i1, j0, j1)`` of the step's blocks (a step on another grid: items 0 and 2 its first rows).
        *args
            Passed to the algorithm after the block's arrays.
        source : (n_inlines, n_xlines, n_samples) dask.array.Array, optional
            The input cube, when :data:`~seismo3d.seismic.blocks.plan.CUBE` is among the step's inputs: each block's
            region (``step.region``, default the block grown by ``step.halo``) is read from it by dask.
        workers : int, optional

        Returns
        -------
        list
            The blocks' summaries for the blocks computed now, then the markers' payloads of the finished ones.
        """
        todo, done = self.pending(step.name, blocks)
        shape = source.shape if source is not None else self.shape
        lists = self.work / step.name
        lists.mkdir(exist_ok=True)
        block_task = functools.partial(apply_block, step=step, paths=self.arrays, lists=str(lists), args=args)
        tasks = []
        for b in todo:
            region = step.region(b) if step.region is not None else around(b, step.halo, shape)
            window = source[region[0]:region[1], region[2]:region[3]] if CUBE in step.inputs else None
            tasks.append(self.task(block_task, window, BlockPlace(tuple(b), tuple(region)),
                                   str(self.marker(step.name, b)), threads=step.threads, name=step.function.__name__))
        return self.compute(tasks, step.label or step.name, step.name, workers=workers) + done

    def reduce_cube(self, parts) -> list:
        """Whole-cube reductions (dask arrays of a few values, e.g. ``da.max(x)``) computed together on the run's
        scheduler (the cluster's client, else dask's threads with the run's workers)."""
        import dask

        if self.client is not None:
            return list(self.client.compute(list(parts), sync=True))
        return list(dask.compute(*parts, scheduler="threads", num_workers=self.workers))

    def compute(self, tasks: list, label: str, step: str, *, workers: int | None = None) -> list:
        """Run delayed block tasks on the chosen scheduler (``workers`` at once on the threaded one, default the
        run's), reporting each finished block; their results in order."""
        import dask

        start = time.perf_counter()
        release_memory()
        workers = self.workers if workers is None else int(workers)
        try:
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
        finally:
            self.seconds[step] = round(self.seconds.get(step, 0.0) + time.perf_counter() - start, 2)


class MemoryRun(_StepRun):
    """The run in memory of the declared steps that :class:`BlockRun` runs by blocks: each step on one block, the
    whole cube (:func:`~seismo3d.seismic.blocks.apply.apply_in_memory`), its arrays held in :attr:`arrays`; no work
    folder, no marker, no scheduler. A computation written once against :meth:`run_step` runs by blocks with a
    :class:`~seismo3d.seismic.blocks.stores.StoreRun` and in memory with this, the blocks of its plan then the whole
    cube.

    Parameters
    ----------
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)`` of the cube (a section: ``(n_traces, 1, n_samples)``).
    arrays : dict, optional
        ``{name: ndarray}``: arrays the steps read by their declared names, given before the first step (the
        steps' outputs are set in it; an input no step wrote is None to the algorithm, as a store holding only its
        fill value).
    progress : bool
        Report progress per step, and the loop within its one block where the step reports one (the network's
        sections, the voting's seeds: :func:`~seismo3d._progress.progress_within`).

    Attributes
    ----------
    arrays : dict
        ``{name: ndarray}``: the steps' inputs and outputs by their declared names.
    computed, resumed, seconds : dict
        As :class:`BlockRun`'s: one block computed per step, none resumed; wall-clock seconds per step.
    lists : dict
        ``{step name: {block: {list name: ndarray}}}``: the sparse lists of each step's one block.
    """

    client = None

    def __init__(self, shape, *, arrays: dict | None = None, progress: bool = False):
        self.shape = tuple(int(n) for n in shape)
        self.arrays, self.progress = ({} if arrays is None else arrays), progress
        self.computed, self.resumed, self.seconds = {}, {}, {}
        self.lists = {}

    def saved(self, name: str, compute):
        """``compute()``: a run in memory is never resumed (:meth:`BlockRun.saved`'s counterpart)."""
        return compute()

    def saved_arrays(self, name: str, compute) -> dict:
        """``compute()``: arrays of the run, nothing kept (:meth:`BlockRun.saved_arrays`' counterpart)."""
        return compute()

    def lists_reader(self, step: str, *, mmap_mode=None):
        """``reader(block, names)``: the lists of the one block of the step named ``step``, held
        (:meth:`BlockRun.lists_reader`'s counterpart; ``mmap_mode`` not used)."""
        held = self.lists[step]
        return lambda block, names: {name: held[tuple(int(v) for v in block)][name] for name in names}

    def release(self, *names) -> None:
        """Drop the arrays ``names`` that no later step reads (a run by blocks keeps them in its work folder)."""
        for name in names:
            self.arrays.pop(name, None)

    def run_step(self, step: BlockStep, blocks, *args, source=None, workers: int | None = None) -> list:
        """Run a declared step on its one block, in memory: :meth:`BlockRun.run_step`'s counterpart.

        Parameters
        ----------
        step : BlockStep
        blocks : list of tuple
            The step's blocks: one, the whole cube (or the whole grid of a step on another grid), with its region
            (``step.region``, default the block grown by ``step.halo``) the whole cube.
        *args
            Passed to the algorithm after the arrays.
        source : (n_inlines, n_xlines, n_samples) ndarray, optional
            The input cube, when :data:`~seismo3d.seismic.blocks.plan.CUBE` is among the step's inputs.
        workers : int, optional
            Not used (one block).

        Returns
        -------
        list
            The block's summary, in a list as :meth:`BlockRun.run_step` returns them.

        Raises
        ------
        ValueError
            More than one block, or a region that is not the whole cube: a plan made for a run by blocks.
        """
        if len(blocks) != 1:
            raise ValueError(f"a run in memory computes one block per step; {step.name!r} has {len(blocks)}")
        block = tuple(int(v) for v in blocks[0])
        region = step.region(block) if step.region is not None else around(block, step.halo, self.shape)
        if tuple(region) != (0, self.shape[0], 0, self.shape[1]):
            raise ValueError(f"step {step.name!r} reads traces {region} in memory, not the whole cube {self.shape}")
        start = time.perf_counter()
        arrays = dict(self.arrays, **({CUBE: source} if source is not None else {}))
        label = step.label or step.name
        with (progress_steps(1, label, unit="step", enabled=self.progress) as bar,
              reporting_within(label if self.progress else None)):  # the loops within the one block report too
            out = apply_in_memory(step, arrays, *args, place=BlockPlace(block, tuple(region)))
            bar.advance()
        arrays.pop(CUBE, None)
        self.arrays.clear()
        self.arrays.update(arrays)  # the caller's dict too
        self.lists[step.name] = {block: out.lists}
        self.computed[step.name], self.resumed[step.name] = 1, 0
        self.seconds[step.name] = round(self.seconds.get(step.name, 0.0) + time.perf_counter() - start, 2)
        return [out.summary]


def trace_cube(cube, what: str, *, chunks: tuple = (64, -1, -1), dtype=None):
    """``cube`` as a dask array whose chunks hold whole traces (3D, at least 3 samples per axis).

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
    what : str
        The computation, named in the message.
    chunks : tuple
        Chunks of an array given in memory (whole traces: -1 samples).
    dtype : numpy dtype, optional
        Cast to it (e.g. float32) unless it is the cube's.

    Returns
    -------
    (n_inlines, n_xlines, n_samples) dask.array.Array

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
        x = da.from_array(x, chunks=chunks)
    if len(x.chunks[2]) != 1:
        x = x.rechunk({2: -1})
    if dtype is not None and x.dtype != dtype:
        x = x.astype(dtype)
    return x
