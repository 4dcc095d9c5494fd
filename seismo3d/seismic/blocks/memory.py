"""Memory of a fault run: the limit, what the process holds, and the decision to trace a cube in memory or block by
block.

:func:`fits_in_memory` is the one decision every caller of :func:`~seismo3d.seismic.faults.trace_faults` shares (the
``faults`` and ``horizon --faults`` commands, the Python API): a cube whose in-memory run would need more than the
memory limit leaves beside the process is traced block by block
(:mod:`~seismo3d.seismic.faults.surfaces.blocks`).
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError

__all__ = ["PROCESS_STEP", "default_memory_limit", "fits_in_memory", "in_memory_bytes", "parse_memory_limit",
           "process_bytes", "resident_memory", "size_text", "worker_baseline"]

# The in-memory `seismo3d faults` beyond the process that decides (its imports, about 150-160 MiB): a fixed part (the
# fault network's ONNX session, about 60 MiB; the numba kernels loaded from their cache; the writers' pyvista and
# matplotlib, about 70 MiB) and a part per float32 sample. Peaks measured with /usr/bin/time -f %M on 2026-11-26
# (2 cores, other runs beside): the 128^3 demo 469 MiB (319 beyond the 150 held), the generated 192^3 cube 777 MiB
# (627 beyond), the 18 x 512 x 1536 Penobscot inlines 1591 MiB (1441 beyond: the network's sections of 1536 samples
# make it the most per sample), and 1408 MB on a 256^3 cube earlier; trace_faults alone 133, 241 and 626 MiB beyond
# the process at 64^3, 128^3 and 192^3. 160 MiB + 24 bytes a sample covers every one of them.
_IN_MEMORY_FIXED = 160 << 20
_IN_MEMORY_FACTOR = 24
# The smallest memory limit accepted.
_SMALLEST_LIMIT = 64 << 20
# The process's own size in a plan is rounded up to a multiple of this (process_bytes): runs of the same command
# measure it a few MiB apart (the allocator's state, threads; up to ~10 MB), and a plan made from the bytes left
# would change its blocks with them. Several times that spread: the plan moves only for a process within it of a
# multiple.
PROCESS_STEP = 64 << 20


def default_memory_limit() -> int:
    """Half of the machine's physical memory, bytes (the default ``--memory-limit``; psutil, a dependency)."""
    import psutil

    return int(psutil.virtual_memory().total // 2)


def in_memory_bytes(shape) -> int:
    """Peak memory of the in-memory ``seismo3d faults`` on a float32 cube of this shape beyond the process that
    decides, bytes: 160 MiB fixed (the fault network's session, the numba kernels, the writers) and 24 times the
    cube's float32 size, calibrated against measured peaks (the module's notes; a run of
    :func:`~seismo3d.seismic.faults.trace_faults` without the command's writers needs less).

    Parameters
    ----------
    shape : tuple of int

    Returns
    -------
    int
        Bytes.
    """
    return _IN_MEMORY_FIXED + int(np.prod(shape, dtype=np.int64)) * 4 * _IN_MEMORY_FACTOR


def resident_memory() -> int:
    """Resident memory of this process, bytes (psutil, a dependency)."""
    import psutil

    return int(psutil.Process().memory_info().rss)


def process_bytes(scheduler=None) -> int:
    """The bytes a worker's process holds before its blocks, as the plans of a run by blocks count them: this
    process's resident memory on the local schedulers, rounded up to a multiple of :data:`PROCESS_STEP` (64 MiB) so
    that reruns of the same command plan the same blocks; 256 MiB assumed for a ``dask.distributed`` worker.

    Parameters
    ----------
    scheduler : str, optional
        The run's scheduler (:attr:`~seismo3d.seismic.blocks.options.ChunkOptions.scheduler`): None, ``'threads'``
        or ``'synchronous'`` run the blocks in this process.

    Returns
    -------
    int
        Bytes, a multiple of :data:`PROCESS_STEP` for this process.
    """
    if scheduler not in (None, "threads", "synchronous"):
        return 256 << 20
    return -(-resident_memory() // PROCESS_STEP) * PROCESS_STEP


def worker_baseline(chunking, x) -> int:
    """Memory of a worker before its blocks: the process itself (``chunking.process`` when the run measured it, else
    :func:`process_bytes` now) and two of the input's largest chunks being read.

    Parameters
    ----------
    chunking : ChunkOptions
        Its ``process``, or its scheduler (whether the blocks run in this process).
    x : (n_inlines, n_xlines, n_samples) dask.array.Array
        The lazy input, chunks of whole traces, counted as float32.

    Returns
    -------
    int
        Bytes.
    """
    process = process_bytes(chunking.scheduler) if chunking.process is None else int(chunking.process)
    return process + 2 * 4 * max(x.chunks[0]) * max(x.chunks[1]) * int(x.shape[2])


def parse_memory_limit(value) -> int:
    """A memory limit in bytes: an int, a size string ('4GB', '500MiB'), or None for half of the RAM.

    Parameters
    ----------
    value : int or str or None

    Returns
    -------
    int
        Bytes, at least 64 MB.

    Raises
    ------
    InputError
        Not a size, or below 64 MB.
    """
    if value is None:
        return default_memory_limit()
    if isinstance(value, str):
        from dask.utils import parse_bytes

        try:
            value = parse_bytes(value)
        except (ValueError, TypeError) as exc:
            raise InputError(f"memory_limit {value!r} is not a size; pass bytes or e.g. '4GB', '500MB'") from exc
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < _SMALLEST_LIMIT:
        raise InputError(f"memory_limit must be at least 64 MB; got {value!r}")
    return int(value)


def fits_in_memory(shape, memory_limit=None, *, held: int | None = None) -> bool:
    """Whether the in-memory fault run of data of ``shape`` fits in ``memory_limit`` beside the process: the decision
    between the in-memory run and the run block by block.

    Sections (2D) always fit: only 3D cubes are traced block by block.

    Parameters
    ----------
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)`` or ``(n_traces, n_samples)``.
    memory_limit : int or str, optional
        Bytes or a size such as ``'4GB'`` (:func:`parse_memory_limit`; default half of the RAM).
    held : int, optional
        Bytes the process already holds (default: its resident memory now).

    Returns
    -------
    bool

    Raises
    ------
    InputError
        An invalid ``memory_limit``.
    """
    limit = parse_memory_limit(memory_limit)
    if len(tuple(shape)) != 3:
        return True
    held = resident_memory() if held is None else int(held)
    return in_memory_bytes(shape) <= limit - held


def size_text(n: int) -> str:
    """Bytes as a ``--memory-limit`` value, rounded up: '1.3GB', '460MB'."""
    if n >= 10 ** 9:
        return f"{np.ceil(n / 10 ** 8) / 10:g}GB"
    return f"{int(np.ceil(n / 10 ** 7)) * 10}MB"
