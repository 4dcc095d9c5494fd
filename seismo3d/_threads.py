"""Several threads running one compiled serial kernel: the parallelism of a numba ``parallel=True`` loop over threads
without its compile time (a ``prange`` loop compiles 1-5 s longer than the same loop serial, on every fresh install).

The kernel is compiled with ``nogil=True`` and takes the thread's index first; each call works on its own share of
the data (no shared writes), so the results are those of the ``prange`` loop it replaces, whatever the timing.

And the thread counts the steps share (:func:`query_workers`, :func:`task_workers`), and a pool for independent
Python tasks whose heavy calls release the GIL (:func:`task_pool`: the throw's patches).
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from typing import Callable

import numpy as np

__all__ = ["MIN_QUERIES_PER_THREAD", "query_workers", "task_workers", "task_pool", "deferred", "run_threads",
           "map_parts"]

# Nearest-neighbour queries per thread at least (the voxel hash's shares, scipy's cKDTree ``workers``): fewer run in
# the calling thread. Starting a thread costs about 0.2-0.4 ms of CPU (a cKDTree query of 200 and 800 points: 0.13 ->
# 0.33 and 0.64 -> 1.0 ms with ``workers=-1``; 3.5 ms of wall beside six other jobs on 2 cores, 2026-11-28), the
# work of a query 1-3.5 us per point (2D, 5 neighbours; 3D, 16): below a few thousand points the threads cost more
# than they save, and above it the saving is at most half the query's wall time.
MIN_QUERIES_PER_THREAD = 4096


def query_workers(n_queries: int) -> int:
    """scipy's ``cKDTree.query`` ``workers`` for ``n_queries`` query points: a thread per
    :data:`MIN_QUERIES_PER_THREAD` queries, at most one per core (1: the calling thread only). The neighbours found are
    the same whatever the count.

    Parameters
    ----------
    n_queries : int

    Returns
    -------
    int
    """
    return max(1, min(os.cpu_count() or 1, int(n_queries) // MIN_QUERIES_PER_THREAD))


def task_workers(n_tasks: int) -> int:
    """Threads for ``n_tasks`` independent tasks of Python code whose heavy calls release the GIL (NumPy, SciPy's
    interpolation and trees, OpenCV, numba ``nogil`` kernels): numba's thread count (``NUMBA_NUM_THREADS``, or
    ``numba.set_num_threads``: the thread setting the other steps follow), at most one per task; 1 (the calling thread
    only) when called from another thread than the main one, as :func:`run_threads` (a block of a run by blocks runs
    on a thread already).

    Parameters
    ----------
    n_tasks : int

    Returns
    -------
    int
        At least 1.
    """
    if threading.current_thread() is not threading.main_thread():
        return 1
    import numba

    return max(1, min(numba.get_num_threads(), int(n_tasks)))


class Deferred:
    """A call made when its result is asked for, in the thread that asks (what :func:`deferred` returns)."""

    def __init__(self, func: Callable, args: tuple):
        self._call = (func, args)

    def result(self):
        """``func(*args)``, called now."""
        func, args = self._call
        return func(*args)


def deferred(func: Callable, *args) -> Deferred:
    """``func(*args)`` as a :class:`Deferred`, called by its ``result()``: a pool's ``submit`` without a pool
    (:func:`task_pool` with one worker).

    Parameters
    ----------
    func : callable
    *args
        Its arguments.

    Returns
    -------
    Deferred
    """
    return Deferred(func, args)


@contextmanager
def task_pool(workers: int, name: str = "seismo3d-task"):
    """Run independent calls on ``workers`` threads, or in the calling thread when ``workers`` is 1.

    Yields ``run(func, *args)``, which returns an object whose ``result()`` is ``func(*args)``: a thread pool's
    ``submit`` (the call starts as soon as a thread is free) when ``workers`` > 1; :func:`deferred` (the call is
    made in the thread that asks for its result) when ``workers`` is 1. On an exception or an interrupt (Ctrl-C) in
    the calling thread, the calls not started are cancelled and those running finish before it propagates.

    Parameters
    ----------
    workers : int
        Threads (:func:`task_workers`).
    name : str, optional
        The threads' name prefix.

    Yields
    ------
    callable
        ``run(func, *args)``.
    """
    if workers <= 1:
        yield deferred
        return
    pool = ThreadPoolExecutor(workers, thread_name_prefix=name)
    try:
        yield pool.submit
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def run_threads(kernel: Callable, n_threads: int, *args, from_any_thread: bool = False) -> None:
    """Call ``kernel(t, n_threads, *args)`` for ``t = 0 .. n_threads - 1``: share 0 in the calling thread, the others
    each on a thread of its own, and return when all are done.

    Called from another thread than the main one (a block of a run by blocks, which runs its blocks on threads
    already), every share runs in the calling thread, one after the other: threads inside those threads would not
    run faster but would hold more memory (each thread's allocations go to a malloc arena of its own).

    Parameters
    ----------
    kernel : callable
        A numba kernel compiled with ``nogil=True`` (else the threads take turns), writing its results into the
        arrays of ``args``; its first two arguments are the share's index and ``n_threads``.
    n_threads : int
        Shares (>= 1); one runs the kernel in the calling thread only.
    *args
        The kernel's other arguments.
    from_any_thread : bool, optional
        Run the shares on threads even when called from another thread than the main one (for work whose memory
        does not grow with the threads, e.g. one batch of sections split between them).

    Raises
    ------
    Exception
        Whatever the kernel raised, from the share of lowest index that raised (after all shares ended).
    """
    if not from_any_thread and threading.current_thread() is not threading.main_thread():
        for t in range(n_threads):
            kernel(t, n_threads, *args)
        return
    errors: list = [None] * n_threads

    def share(t: int) -> None:
        try:
            kernel(t, n_threads, *args)
        except BaseException as exc:  # handed to the calling thread below
            errors[t] = exc

    others = [threading.Thread(target=share, args=(t,), daemon=True) for t in range(1, n_threads)]
    for thread in others:
        thread.start()
    share(0)
    for thread in others:
        thread.join()
    for exc in errors:
        if exc is not None:
            raise exc


def map_parts(func: Callable, x, n_parts: int):
    """``func`` on ``n_parts`` consecutive parts of ``x`` along its first axis at once, each on a thread of its own
    (:func:`run_threads`, from any thread), the results joined along the first axis in order; one call of ``func`` on
    ``x`` when ``n_parts`` is 1 or ``x`` holds fewer than 2 items. For work whose items are independent and whose
    memory is that of its items (a batch of sections split between the cores).

    Parameters
    ----------
    func : callable
        ``func(part) -> ndarray`` with as many items along its first axis as ``part``; it should release the GIL.
    x : ndarray
        The items, along the first axis.
    n_parts : int
        Parts (>= 1), at most one per item.

    Returns
    -------
    ndarray
        ``func``'s results, joined in the order of the items.
    """
    if n_parts <= 1 or len(x) < 2:
        return func(x)
    bounds = np.linspace(0, len(x), min(n_parts, len(x)) + 1).astype(int)
    out = [None] * (len(bounds) - 1)

    def part(t: int, n: int) -> None:
        out[t] = func(x[bounds[t]:bounds[t + 1]])

    run_threads(part, len(out), from_any_thread=True)
    return np.concatenate(out)
