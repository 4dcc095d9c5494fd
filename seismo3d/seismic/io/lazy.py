"""A seismic cube read lazily as a dask array: SEG-Y through segyio's memory map, or a Zarr v3 store of
``seismo3d convert``.

:func:`open_lazy` reads the geometry once and returns a :class:`LazyCube` whose ``data`` is a dask array chunked by
blocks of whole inlines (every crossline and every sample in a chunk), so an operator with a halo along the inline
axis (``dask.array.map_overlap``) sees complete traces and complete crossline ranges. Nothing is read until a chunk is
computed, and each chunk reads only its own traces.

The dask graph of a SEG-Y cube holds no open file: each task is a call of :func:`read_segy_block` with a
:class:`SegyGrid` (the file's path, byte order, trace order and shape; plain picklable values), which opens the file
read-only itself. The same graph therefore runs on the local threaded scheduler and on a ``dask.distributed`` cluster
whose workers see the file at the same path.

Trace order: in an inline-sorted file the traces of inline ``i`` (array index) are the ``n_xlines`` consecutive traces
from ``i * n_xlines``; in a crossline-sorted file the trace of (inline ``i``, crossline ``j``) is ``j * n_inlines + i``.
This is segyio's grid, the one :meth:`~seismo3d.seismic.io.SeismicCube.read` returns, so a lazy cube equals
:func:`~seismo3d.seismic.io.read_segy` value for value.

References
----------
SEG Technical Standards Committee, *SEG-Y rev 1 Data Exchange format* (2002) and *SEG-Y_r2.0* (2017): trace order
and the trace headers. Zarr v3 storage specification, https://zarr-specs.readthedocs.io/en/latest/v3/core/index.html.
Dask array, https://docs.dask.org/en/stable/array.html (custom graphs: ``dask.array.Array`` from a task dict).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..._validation import check_choice, check_int, check_positive
from ...errors import TraceListWarning
from .blocks import SegyGrid, read_segy_block, read_segy_block_headers, segyio_handle
from .segy import open_segy
from .zarr_store import open_seismic_zarr

__all__ = ["LazyCube", "SegyGrid", "inline_block_size", "lazy_segy_cube", "open_lazy", "read_segy_block",
           "read_segy_block_headers", "segy_dask_array", "segyio_handle"]

_BYTES_PER_SAMPLE = 4  # float32


@dataclass(frozen=True)
class LazyCube:
    """A 3D cube whose amplitudes are read on demand, chunk by chunk.

    Attributes
    ----------
    data : (n_inlines, n_xlines, n_samples) float32 dask.array.Array
        Axis 0 inline, axis 1 crossline, axis 2 sample (downward), as :func:`~seismo3d.seismic.io.read_segy`.
        Chunked by blocks of whole inlines: ``data.chunks[1] == (n_xlines,)`` and ``data.chunks[2] == (n_samples,)``.
    inlines : (n_inlines,) int32 ndarray
        Inline numbers in array order.
    xlines : (n_xlines,) int32 ndarray
        Crossline numbers in array order.
    samples : (n_samples,) float64 ndarray
        Sample positions (time or depth) in ``sample_unit``.
    sample_unit : {'ms', 'm', 'ft'}
    source : pathlib.Path
        The SEG-Y file or the Zarr store read.
    format : {'segy', 'zarr'}
    """

    data: object
    inlines: np.ndarray
    xlines: np.ndarray
    samples: np.ndarray
    sample_unit: str
    source: Path
    format: str

    @property
    def shape(self) -> tuple:
        """``(n_inlines, n_xlines, n_samples)``."""
        return tuple(int(n) for n in self.data.shape)

    @property
    def sample_interval(self) -> float:
        """Sample interval in ``sample_unit`` (0.0 for a single sample)."""
        return float(self.samples[1] - self.samples[0]) if self.samples.size > 1 else 0.0


def inline_block_size(n_xlines: int, n_samples: int, chunk_mb: float) -> int:
    """Inlines per chunk: as many whole inlines of float32 as fit in ``chunk_mb`` MiB, at least one.

    Parameters
    ----------
    n_xlines, n_samples : int
    chunk_mb : float
        Target chunk size in MiB (2**20 bytes); > 0.

    Returns
    -------
    int

    Raises
    ------
    InputError
        ``chunk_mb`` is not a positive number.
    """
    chunk_mb = check_positive(chunk_mb, "chunk_mb")
    return max(1, int(chunk_mb * 2**20 // (n_xlines * n_samples * _BYTES_PER_SAMPLE)))


def _block_edges(n: int, size: int) -> list:
    return [(a, min(a + size, n)) for a in range(0, n, size)]


def segy_dask_array(grid: SegyGrid, *, tile: int | None = None, block: int | None = None):
    """The amplitudes of a SEG-Y grid as a float32 dask array: one :func:`read_segy_block` task per tile of ``tile``
    x ``tile`` traces (every sample), or per block of ``block`` whole inlines.

    Parameters
    ----------
    grid : SegyGrid
        The file and its grid (a 2D line is a grid of one inline or crossline; a trace list one of ``n_traces``
        inlines and one crossline, inline-sorted).
    tile, block : int, optional
        One of them: traces a side of a tile, or inlines of a block.

    Returns
    -------
    (n_inlines, n_xlines, n_samples) float32 dask.array.Array
        Its graph holds no open file (each task opens it read-only), and its name the file's size and time.
    """
    import dask.array as da
    from dask.base import tokenize

    stat = Path(grid.path).stat()
    name = f"segy-{tokenize(grid, stat.st_mtime_ns, stat.st_size, tile, block)}"
    edges = _block_edges(grid.n_inlines, block if tile is None else tile)
    xedges = [(0, grid.n_xlines)] if tile is None else _block_edges(grid.n_xlines, tile)
    graph = {(name, k, q, 0): (read_segy_block, grid, a, b, c, d) for k, (a, b) in enumerate(edges)
             for q, (c, d) in enumerate(xedges)}
    chunks = (tuple(b - a for a, b in edges), tuple(d - c for c, d in xedges), (grid.n_samples,))
    return da.Array(graph, name, chunks, dtype=np.float32)


def lazy_segy_cube(cube, *, chunk_mb: float = 64, tile: int | None = None) -> LazyCube:
    """The amplitudes of an open 3D SEG-Y cube as a lazy dask array, without opening the file again.

    Parameters
    ----------
    cube : SeismicCube
        An open 3D cube of :func:`~seismo3d.seismic.io.open_segy` (its geometry is read here; the graph's tasks open
        the file themselves, read-only).
    chunk_mb, tile
        As :func:`open_lazy`.

    Returns
    -------
    LazyCube

    Raises
    ------
    SegyGeometryError
        The file is a 2D line or a trace list (see :func:`open_lazy`).
    """
    path = Path(cube.path)
    grid = SegyGrid.from_cube(cube)
    data = segy_dask_array(grid, tile=tile, block=None if tile is not None else
                           inline_block_size(grid.n_xlines, grid.n_samples, chunk_mb))
    return LazyCube(data=data, inlines=np.array(cube.inlines), xlines=np.array(cube.xlines),
                    samples=np.array(cube.samples), sample_unit=cube.sample_unit, source=path, format="segy")


def _open_segy_lazy(path: Path, *, iline, xline, sample_unit, endian, chunk_mb, tile) -> LazyCube:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TraceListWarning)  # a trace list is refused below, saying what it is
        cube = open_segy(path, iline=iline, xline=xline, sample_unit=sample_unit, endian=endian)
    with cube:
        return lazy_segy_cube(cube, chunk_mb=chunk_mb, tile=tile)


def _open_zarr_lazy(path: Path, *, sample_unit, chunk_mb, tile) -> LazyCube:
    import dask.array as da

    store = open_seismic_zarr(path)
    seismic = store.seismic
    n_il, n_xl, ns = seismic.shape
    # the store's (64, 64, n_samples) tiles regrouped into blocks of whole inlines (a no-op when they already are)
    chunks = (inline_block_size(n_xl, ns, chunk_mb), n_xl, ns) if tile is None else (tile, tile, ns)
    data = da.from_zarr(seismic).rechunk(chunks)
    return LazyCube(data=data, inlines=store.inlines, xlines=store.xlines, samples=store.samples,
                    sample_unit=sample_unit or store.sample_unit, source=path, format="zarr")


def open_lazy(path, *, iline: int = 189, xline: int = 193, sample_unit=None, endian=None,
              chunk_mb: float = 64, tile: int | None = None) -> LazyCube:
    """Open a 3D cube (SEG-Y file or Zarr store of ``seismo3d convert``) as a lazy dask array.

    Only the geometry is read here. The returned array is chunked by blocks of whole inlines of about ``chunk_mb``
    MiB; computing a chunk reads only its traces.

    Parameters
    ----------
    path : str or os.PathLike
        A SEG-Y file (opened through :func:`~seismo3d.seismic.io.open_segy`, with its checks and errors), or a
        directory holding a Zarr v3 store written by ``seismo3d convert`` (see
        :mod:`~seismo3d.seismic.io.zarr_store`).
    iline, xline : int
        SEG-Y only: trace header bytes of the inline and crossline numbers (189 / 193 by default, SEG-Y rev 1).
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of the sample axis; by default from the headers (SEG-Y, see :class:`SeismicCube`) or the store.
    endian : {'big', 'little'}, optional
        SEG-Y only: byte order; by default detected from the binary header.
    chunk_mb : float
        Target chunk size in MiB (2**20 bytes of float32); a chunk holds at least one inline.
    tile : int, optional
        Chunk by tiles of ``tile`` x ``tile`` traces (every sample) instead of blocks of whole inlines: for work on
        square blocks of traces (the chunked fault likelihood), which then reads only the tiles around a block.

    Returns
    -------
    LazyCube

    Raises
    ------
    SegyGeometryError
        The SEG-Y file is a 2D line or a trace list (chunked processing needs a 3D cube), or holds no grid at the given
        header bytes (see :func:`open_segy`).
    SegyFormatError, DataNotFoundError
        The SEG-Y file cannot be read (see :func:`open_segy`); or the path does not exist.
    InputError
        A directory that is not a Zarr store of ``seismo3d convert``; invalid ``chunk_mb``, ``sample_unit``, ``iline``,
        ``xline`` or ``endian``.

    Examples
    --------
    >>> cube = open_lazy("f3_crop.sgy", chunk_mb=1)         # doctest: +SKIP
    >>> cube.data.chunks[0], float(cube.data[5].mean().compute())
    """
    path = Path(path)
    inline_block_size(1, 1, chunk_mb)  # validates chunk_mb
    if sample_unit is not None:
        check_choice(sample_unit, "sample_unit", {"ms", "m", "ft"})
    if tile is not None:
        check_int(tile, "tile", minimum=1)
    if path.is_dir():
        return _open_zarr_lazy(path, sample_unit=sample_unit, chunk_mb=chunk_mb, tile=tile)
    return _open_segy_lazy(path, iline=iline, xline=xline, sample_unit=sample_unit, endian=endian,
                           chunk_mb=chunk_mb, tile=tile)
