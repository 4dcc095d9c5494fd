"""A 3D SEG-Y cube read by blocks of inlines (and crosslines), only those traces: the task functions of the lazy
cube's dask graph (:func:`~seismo3d.seismic.io.lazy.open_lazy`) and of the Zarr conversion
(:class:`~seismo3d.seismic.io.zarr_store.SeismicZarrWriter`).

A :class:`SegyGrid` holds the file's path, byte order, trace order and shape (plain picklable values), so a block is
read without scanning the file's geometry again: the file is opened read-only and memory-mapped by each task itself.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import segyio

from ...errors import InputError, SegyFormatError, SegyGeometryError

__all__ = ["SegyGrid", "read_segy_block", "read_segy_block_headers", "segyio_handle"]

_RUN_TRACES = 1024  # traces read per segyio call into a block (a few MB of temporaries, not a block's worth)


@dataclass(frozen=True)
class SegyGrid:
    """How to find the traces of a 3D SEG-Y cube without reading its headers again: picklable plain values.

    Attributes
    ----------
    path : str
        The file (absolute path; workers of a cluster must see it there).
    endian : {'big', 'little'}
        Byte order (see :mod:`~seismo3d.seismic.io.layout`).
    sorting : {'inline', 'crossline'}
        Trace order of the file.
    n_inlines, n_xlines, n_samples : int
        Grid shape.
    """

    path: str
    endian: str
    sorting: str
    n_inlines: int
    n_xlines: int
    n_samples: int

    @classmethod
    def from_cube(cls, cube) -> "SegyGrid":
        """The grid of an open 3D :class:`~seismo3d.seismic.io.SeismicCube`.

        Raises
        ------
        SegyGeometryError
            ``cube`` is a 2D line or a trace list: chunked processing needs a 3D cube.
        """
        if not cube.is_3d:
            raise SegyGeometryError(f"{cube.path.name} is {cube.description}; chunked processing needs a 3D cube "
                                    "(more than one inline and crossline): read it with open_segy / read_segy instead")
        return cls(path=str(Path(cube.path).resolve()), endian=cube.endian, sorting=cube.sorting,
                   n_inlines=int(cube.inlines.size), n_xlines=int(cube.xlines.size), n_samples=int(cube.samples.size))

    @property
    def n_traces(self) -> int:
        """``n_inlines * n_xlines``."""
        return self.n_inlines * self.n_xlines

    def trace_runs(self, inline_start: int, inline_stop: int, xline_start: int, xline_stop: int):
        """The block's traces as runs of consecutive traces in the file.

        Yields
        ------
        (first, last, where) : (int, int, tuple)
            Traces ``first:last`` of the file fill ``block[where]`` of a block shaped
            ``(inline_stop - inline_start, xline_stop - xline_start, ...)``.
        """
        n_il, n_xl = self.n_inlines, self.n_xlines
        if self.sorting == "inline":
            if xline_start == 0 and xline_stop == n_xl:  # whole inlines: one run
                yield inline_start * n_xl, inline_stop * n_xl, (slice(None),)
                return
            for i in range(inline_start, inline_stop):
                yield i * n_xl + xline_start, i * n_xl + xline_stop, (i - inline_start,)
        else:
            for j in range(xline_start, xline_stop):
                yield j * n_il + inline_start, j * n_il + inline_stop, (slice(None), j - xline_start)


def segyio_handle(grid: SegyGrid):
    """Open the file of ``grid`` read-only without scanning its geometry, memory-mapped.

    Parameters
    ----------
    grid : SegyGrid

    Returns
    -------
    segyio.SegyFile
        Opened with ``ignore_geometry=True`` (traces addressed by index); close it, or use it in a ``with``.

    Raises
    ------
    SegyFormatError
        The file cannot be opened, or no longer holds ``grid.n_traces`` traces of ``grid.n_samples`` samples (it
        changed since its geometry was read).
    """
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # segyio's warnings were reported when the geometry was read
            f = segyio.open(grid.path, "r", ignore_geometry=True, endian=grid.endian)
    except (RuntimeError, ValueError, OSError) as exc:
        raise SegyFormatError(f"cannot open {grid.path} to read a chunk ({exc}); it was readable when the cube was "
                              "opened: check that it still exists and is not being written") from exc
    if f.tracecount != grid.n_traces or len(f.samples) != grid.n_samples:
        f.close()
        raise SegyFormatError(f"{grid.path} now holds {f.tracecount} traces of {len(f.samples)} samples, not the "
                              f"{grid.n_traces} of {grid.n_samples} read when it was opened; open it again")
    f.mmap()
    return f


def _block_bounds(grid: SegyGrid, inline_start, inline_stop, xline_start, xline_stop) -> tuple:
    xline_stop = grid.n_xlines if xline_stop is None else xline_stop
    if not (0 <= inline_start < inline_stop <= grid.n_inlines and 0 <= xline_start < xline_stop <= grid.n_xlines):
        raise InputError(f"block inlines {inline_start}:{inline_stop}, crosslines {xline_start}:{xline_stop} is not "
                         f"inside the grid of {grid.n_inlines} x {grid.n_xlines}; pass array indices in range")
    return xline_stop


def read_segy_block(grid: SegyGrid, inline_start: int, inline_stop: int, xline_start: int = 0,
                    xline_stop: int | None = None, *, segyfile=None) -> np.ndarray:
    """Read the amplitudes of a block of inlines (and crosslines) of a 3D SEG-Y cube, only those traces.

    The task function of :func:`open_lazy`'s graph: module-level and picklable; it opens the file itself unless an
    open ``segyfile`` is given, and reads through segyio's memory map one run of consecutive traces at a time (one
    run for whole inlines of an inline-sorted file, one per crossline of a crossline-sorted file).

    Parameters
    ----------
    grid : SegyGrid
    inline_start, inline_stop : int
        Array indices (not inline numbers) of the block's first and one-past-last inline.
    xline_start, xline_stop : int, optional
        Array indices of the crosslines; by default every crossline.
    segyfile : segyio.SegyFile, optional
        An open handle of ``grid.path`` (e.g. from :func:`segyio_handle`) to read through instead of opening it.

    Returns
    -------
    block : (inline_stop - inline_start, xline_stop - xline_start, n_samples) float32 ndarray
        Integer sample formats converted to float32 without scaling, as :meth:`SeismicCube.read`.

    Raises
    ------
    InputError
        The block is not inside the grid.
    SegyFormatError
        The file cannot be opened or changed since it was opened (see :func:`segyio_handle`).
    """
    xline_stop = _block_bounds(grid, inline_start, inline_stop, xline_start, xline_stop)
    out = np.empty((inline_stop - inline_start, xline_stop - xline_start, grid.n_samples), np.float32)
    f = segyfile if segyfile is not None else segyio_handle(grid)
    try:
        for first, last, where in grid.trace_runs(inline_start, inline_stop, xline_start, xline_stop):
            flat = out[where].reshape(last - first, grid.n_samples)
            if np.shares_memory(flat, out):  # a view: filled in pieces, so the temporaries stay small
                for a in range(first, last, _RUN_TRACES):
                    b = min(a + _RUN_TRACES, last)
                    flat[a - first:b - first] = f.trace.raw[a:b]
            else:
                out[where] = np.asarray(f.trace.raw[first:last], dtype=np.float32).reshape(out[where].shape)
    finally:
        if segyfile is None:
            f.close()
    return out


def read_segy_block_headers(grid: SegyGrid, fields, inline_start: int, inline_stop: int, xline_start: int = 0,
                            xline_stop: int | None = None, *, segyfile=None) -> dict:
    """Read trace header fields of a block of a 3D SEG-Y cube, laid out on the grid.

    Parameters
    ----------
    grid : SegyGrid
    fields : iterable of int
        ``segyio.TraceField`` values (first byte of the field in the 240-byte trace header, SEG-Y rev 1 Table 3).
    inline_start, inline_stop, xline_start, xline_stop, segyfile
        As in :func:`read_segy_block`.

    Returns
    -------
    headers : dict of int to (n_block_inlines, n_block_xlines) int32 ndarray
        The field's value per trace, as segyio decodes it (2- and 4-byte signed integers).

    Raises
    ------
    InputError, SegyFormatError
        As :func:`read_segy_block`.
    """
    xline_stop = _block_bounds(grid, inline_start, inline_stop, xline_start, xline_stop)
    shape = (inline_stop - inline_start, xline_stop - xline_start)
    fields = [int(k) for k in fields]
    out = {k: np.empty(shape, np.int32) for k in fields}
    f = segyfile if segyfile is not None else segyio_handle(grid)
    try:
        for first, last, where in grid.trace_runs(inline_start, inline_stop, xline_start, xline_stop):
            for k in fields:
                target = out[k][where]
                out[k][where] = np.asarray(f.attributes(k)[first:last], dtype=np.int64).reshape(target.shape)
    finally:
        if segyfile is None:
            f.close()
    return out
