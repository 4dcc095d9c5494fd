"""How :func:`~seismo3d.seismic.faults.trace_faults` runs a cube: in memory or block by block, and with what
(:class:`BlockRunOptions`): the memory limit, a forced choice, the folder of the Zarr stores, the dask scheduler, and
the input's name and coordinates recorded in the stores.

The decision itself is :func:`~seismo3d.seismic.blocks.memory.fits_in_memory`'s (:meth:`BlockRunOptions.in_memory_for`
applies it); the run by blocks is :func:`~seismo3d.seismic.faults.blocks.cube_run.trace_faults_by_blocks`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass

from ...errors import InputError
from .memory import fits_in_memory, parse_memory_limit

__all__ = ["BlockRunOptions"]


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
        reused when finished, resumed when interrupted); required when the cube is traced block by block.
    scheduler : str, optional
        A ``dask.distributed`` scheduler address for a run by blocks; default dask's local threads.
    source : str
        The input's name, recorded in the stores of a run by blocks (a likelihood of another source is not reused).
    coords : dict, optional
        ``inline``, ``crossline``, ``sample`` and ``sample_unit`` coordinates of the stores of a run by blocks.

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
    source: str = "cube"
    coords: Mapping | None = None

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
        if not isinstance(self.source, str):
            raise InputError(f"BlockRunOptions(source=...) must be the input's name (a string); got "
                             f"{type(self.source).__name__}")
        if self.coords is not None and not isinstance(self.coords, Mapping):
            raise InputError(f"BlockRunOptions(coords=...) must be a dict of coordinates or None; got "
                             f"{type(self.coords).__name__}")

    @property
    def limit(self) -> int:
        """The memory limit in bytes (half of the RAM when ``memory_limit`` is None)."""
        return parse_memory_limit(self.memory_limit)

    def in_memory_for(self, shape, *, has_likelihood: bool = False) -> bool:
        """Whether data of this shape is traced in memory: forced by ``in_memory``, else the memory decision.

        Parameters
        ----------
        shape : tuple of int
            The data's shape; 2D sections are always traced in memory.
        has_likelihood : bool
            The likelihood is given (computed elsewhere): the run is in memory.

        Returns
        -------
        bool
        """
        shape = tuple(shape)
        if len(shape) != 3 or has_likelihood or self.in_memory:
            return True
        if self.in_memory is False:
            return False
        return fits_in_memory(shape, self.limit)
