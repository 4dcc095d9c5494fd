"""How :func:`~seismo3d.seismic.faults.trace_faults` runs a cube: in memory or block by block, and with what
(:class:`BlockRunOptions`): the memory limit, a forced choice, the folder of the Zarr stores, the dask scheduler, and
the input's name and coordinates recorded in the stores.

The decision itself is :func:`~seismo3d.seismic.blocks.memory.fits_in_memory`'s (:meth:`BlockRunOptions.in_memory_for`
applies it); the run by blocks is :func:`~seismo3d.seismic.faults.pipeline.trace_faults_by_blocks`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass

from ..._validation import check_int
from ...errors import InputError
from .memory import default_memory_limit, fits_in_memory, parse_memory_limit
from .plan import HeldStage

__all__ = ["BlockRunOptions", "ChunkOptions"]


@dataclass(frozen=True)
class BlockRunOptions:
    """Options of a fault run by blocks, and of the choice between it and the run in memory.

    Attributes
    ----------
    memory_limit : int or str, optional
        Memory the run may use, bytes or a size such as ``'4GB'`` (at least 64 MB; default half of the RAM).
    in_memory : bool, optional
        Force the run in memory (True) or block by block (False, 3D cubes only); default (None): decided from
        ``memory_limit`` (:func:`~seismo3d.seismic.blocks.memory.fits_in_memory`).
    work_dir : str or os.PathLike, optional
        Existing folder of the Zarr stores of a run by blocks (``fault_likelihood.zarr``, ``fault_surfaces.zarr``:
        reused when finished, resumed when interrupted); default a new temporary folder, kept.
    scheduler : str, optional
        A ``dask.distributed`` scheduler address for a run by blocks; default dask's local threads.
    source : str, optional
        The input's name, recorded in the stores of a run by blocks (a likelihood of another source is not reused);
        default the cube's file name when ``trace_faults`` is given a cube opened from a file, else ``'cube'``.
    coords : dict, optional
        ``inline``, ``crossline``, ``sample`` and ``sample_unit`` coordinates of the stores of a run by blocks.
    after : tuple of HeldStage
        Stages after a run by blocks that hold its results whole (the faults job's writers,
        :class:`~seismo3d.seismic.blocks.plan.HeldStage`), planned with the run's own stages after its blocks: the
        limit is refused before the work when they would not fit.

    Raises
    ------
    InputError
        On construction: a memory limit that is not a size or is below 64 MB, ``in_memory`` not None / True / False,
        a ``work_dir`` that is not a path, a ``scheduler`` or ``source`` that is not a string, ``coords`` that is not
        a mapping. The message names the option as ``BlockRunOptions(name=...)``.

    Examples
    --------
    >>> BlockRunOptions(memory_limit="2GB", work_dir=".").limit
    2000000000
    """

    memory_limit: int | str | None = None
    in_memory: bool | None = None
    work_dir: str | os.PathLike | None = None
    scheduler: str | None = None
    source: str | None = None
    coords: Mapping | None = None
    after: tuple = ()

    def __post_init__(self):
        try:
            parse_memory_limit(self.memory_limit)
        except InputError as exc:
            raise InputError(f"BlockRunOptions(memory_limit=...): {exc}") from exc
        if self.in_memory not in (None, True, False):
            raise InputError(f"BlockRunOptions(in_memory=...) must be None (decided from the memory limit), True or "
                             f"False; got {self.in_memory!r}")
        if self.work_dir is not None and not isinstance(self.work_dir, (str, os.PathLike)):
            raise InputError(f"BlockRunOptions(work_dir=...) must be a folder's path; got "
                             f"{type(self.work_dir).__name__}")
        if self.scheduler is not None and not isinstance(self.scheduler, str):
            raise InputError(f"BlockRunOptions(scheduler=...) must be a dask.distributed scheduler address (a string) "
                             f"or None; got {type(self.scheduler).__name__}")
        if self.source is not None and not isinstance(self.source, str):
            raise InputError(f"BlockRunOptions(source=...) must be the input's name (a string); got "
                             f"{type(self.source).__name__}")
        if self.coords is not None and not isinstance(self.coords, Mapping):
            raise InputError(f"BlockRunOptions(coords=...) must be a dict of coordinates or None; got "
                             f"{type(self.coords).__name__}")
        if not isinstance(self.after, tuple) or not all(isinstance(s, HeldStage) for s in self.after):
            raise InputError("BlockRunOptions(after=...) must be a tuple of HeldStage (the stages after the run that "
                             "hold its results)")

    @property
    def limit(self) -> int:
        """The memory limit in bytes (half of the RAM when ``memory_limit`` is None)."""
        return parse_memory_limit(self.memory_limit)

    def in_memory_for(self, shape, *, has_likelihood: bool = False, held: int | None = None) -> bool:
        """Whether data of this shape is traced in memory: forced by ``in_memory``, else the memory decision
        (:func:`~seismo3d.seismic.blocks.memory.fits_in_memory`). The one decision of every caller of
        :func:`~seismo3d.seismic.faults.trace_faults`: a job that must know it before reading its input (to read a
        cube lazily) asks it here, then passes ``dataclasses.replace(options, in_memory=decided)`` so that the run
        does not decide again from a process grown by the reading.

        Parameters
        ----------
        shape : tuple of int
            The data's shape; 2D sections are always traced in memory.
        has_likelihood : bool
            The likelihood is given (computed elsewhere): the run is in memory.
        held : int, optional
            Bytes the process holds (default: its resident memory now).

        Returns
        -------
        bool
        """
        shape = tuple(shape)
        if len(shape) != 3 or has_likelihood or self.in_memory:
            return True
        if self.in_memory is False:
            return False
        return fits_in_memory(shape, self.limit, held=held)


@dataclass(frozen=True)
class ChunkOptions:
    """How a chunked run splits a cube and where it runs.

    Attributes
    ----------
    memory_limit : int, optional
        Bytes of memory the run may use on each worker, the blocks sized to fit (default
        :func:`default_memory_limit`: half of the machine's RAM).
    tile : int
        Traces per side of a Zarr chunk of the intermediate and output arrays (32); blocks are whole tiles.
    block : int, optional
        Traces per side of a block of the scan's semblance and decoding steps, and of both steps of the learned
        likelihood (a multiple of ``tile``, and of 8 for the learned likelihood); default: the largest that fits
        ``memory_limit`` with ``workers`` blocks at once, at most 256 (512 for the network's step).
    strip : int, optional
        Crosslines (inlines) per block of the scan of planes sheared along inlines (crosslines), whose blocks hold
        every inline (crossline); a multiple of ``tile``. Default: the largest that fits ``memory_limit``.
    scheduler : str, optional
        None or ``'threads'``: dask's local threaded scheduler; ``'synchronous'``: one block at a time in this
        thread (debugging); ``'tcp://host:port'``: the ``dask.distributed`` scheduler at that address.
    workers : int
        Blocks computed at once by the threaded scheduler (1 by default: each block's kernels already use every
        core through numba).
    process : int, optional
        Bytes the process holds before its blocks, for the plans
        (:func:`~seismo3d.seismic.blocks.memory.worker_baseline`): a run by blocks measures it once, so that its
        refusal and every plan use the same number; default: measured when a plan is made.
    """

    memory_limit: int | None = None
    tile: int = 32
    block: int | None = None
    strip: int | None = None
    scheduler: str | None = None
    workers: int = 1
    process: int | None = None

    def __post_init__(self):
        check_int(self.tile, "tile", minimum=4)
        check_int(self.workers, "workers", minimum=1)
        for name in ("block", "strip"):
            value = getattr(self, name)
            if value is not None:
                check_int(value, name, minimum=int(self.tile))
                if int(value) % int(self.tile):
                    raise InputError(f"{name} must be a multiple of tile ({self.tile}); got {value}")
        if self.memory_limit is not None:
            check_int(self.memory_limit, "memory_limit", minimum=1 << 20)
        if self.process is not None:
            check_int(self.process, "process", minimum=0)
        if self.scheduler not in (None, "threads", "synchronous") and not str(self.scheduler).startswith(
                ("tcp://", "tls://", "inproc://", "ucx://")):
            raise InputError(f"scheduler must be 'threads', 'synchronous' or a dask.distributed address such as "
                             f"tcp://127.0.0.1:8786; got {self.scheduler!r}")

    @property
    def limit(self) -> int:
        """The memory limit per worker in bytes: ``memory_limit``, else half of the machine's RAM."""
        return int(self.memory_limit or default_memory_limit())
