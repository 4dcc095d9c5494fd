"""Several threads running one compiled serial kernel: the parallelism of a numba ``parallel=True`` loop over threads
without its compile time (a ``prange`` loop compiles 1-5 s longer than the same loop serial, on every fresh install).

The kernel is compiled with ``nogil=True`` and takes the thread's index first; each call works on its own share of
the data (no shared writes), so the results are those of the ``prange`` loop it replaces, whatever the timing.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Callable

__all__ = ["run_threads"]


def run_threads(kernel: Callable, n_threads: int, *args) -> None:
    """Call ``kernel(t, n_threads, *args)`` for ``t = 0 .. n_threads - 1``, each on its own thread.

    Parameters
    ----------
    kernel : callable
        A numba kernel compiled with ``nogil=True`` (else the threads take turns), writing its results into the
        arrays of ``args``; its first two arguments are the thread's index and ``n_threads``.
    n_threads : int
        Threads (>= 1); one runs the kernel in the calling thread.
    *args
        The kernel's other arguments.

    Raises
    ------
    Exception
        Whatever the kernel raised, from the first thread that raised.
    """
    if n_threads <= 1:
        kernel(0, 1, *args)
        return
    with ThreadPoolExecutor(max_workers=n_threads) as pool:
        for future in [pool.submit(kernel, t, n_threads, *args) for t in range(n_threads)]:
            future.result()
