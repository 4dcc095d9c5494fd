"""A SEG-Y cube read by blocks of inlines (and crosslines), only those traces: the dask array of ``seismo3d.open``'s
SEG-Y cubes, lines and trace lists (:func:`segy_dask_array`, a :func:`read_segy_block` task per tile of traces) and
the task functions of the Zarr conversion (:class:`~seismo3d.seismic.io.zarr_store.SeismicZarrWriter`).

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
from .layout import SAMPLE_BYTES, TRACE_HEADER_BYTES

__all__ = ["SegyGrid", "read_segy_block", "read_segy_block_headers", "segy_dask_array", "segyio_handle"]

_RUN_TRACES = 1024  # traces read per segyio call into a block (a few MB of temporaries, not a block's worth)
# Bytes of each trace header field: up to the next field's first byte (SEG-Y rev 1 Table 3; 2 or 4)
FIELD_STARTS = sorted(int(k) for k in segyio.TraceField.enums())
_FIELD_BYTES = dict(zip(FIELD_STARTS, np.diff(FIELD_STARTS + [TRACE_HEADER_BYTES + 1]).tolist()))
_IEEE_FLOAT32 = 5
_ENDIAN = {"big": ">", "little": "<"}


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

    def trace_block(self, table: np.ndarray, inline_start: int, inline_stop: int, xline_start: int,
                    xline_stop: int) -> np.ndarray:
        """The block's traces in a table of the file's traces, without copying them.

        Parameters
        ----------
        table : (n_traces, trace_bytes) uint8 ndarray
            Every trace of the file in file order (header then samples), e.g. a memory map.
        inline_start, inline_stop, xline_start, xline_stop : int
            The block, array indices.

        Returns
        -------
        (inline_stop - inline_start, xline_stop - xline_start, trace_bytes) uint8 ndarray
            A strided view of ``table`` (the traces as :meth:`trace_runs` lays them out: the grid is regular, so the
            block is one view, copied by the caller in one numpy call rather than a run at a time).
        """
        if self.sorting == "inline":
            return table.reshape(self.n_inlines, self.n_xlines, -1)[inline_start:inline_stop, xline_start:xline_stop]
        by_xline = table.reshape(self.n_xlines, self.n_inlines, -1)
        return by_xline[xline_start:xline_stop, inline_start:inline_stop].transpose(1, 0, 2)


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

    The task function of :func:`segy_dask_array`'s graph: module-level and picklable; it opens the file itself unless an
    open ``segyfile`` is given, and reads one run of consecutive traces at a time (one run for whole inlines of an
    inline-sorted file, one per crossline of a crossline-sorted file): IEEE float samples (format 5) straight out of
    a numpy memory map of the file (byte order swapped by numpy, the same values as segyio; about twice its speed),
    the other formats through segyio's memory map, which converts them.

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
    f = segyfile if segyfile is not None else segyio_handle(grid)
    try:
        table = _trace_table(f, grid) if int(f.format) == _IEEE_FLOAT32 else None
        return _read_amplitudes(f, table, grid, inline_start, inline_stop, xline_start, xline_stop)
    finally:
        if segyfile is None:
            f.close()


def segy_dask_array(grid: SegyGrid, *, tile: int):
    """The amplitudes of a SEG-Y grid as a float32 dask array: one :func:`read_segy_block` task per tile of ``tile``
    x ``tile`` traces (every sample; partial tiles at the far edges).

    Parameters
    ----------
    grid : SegyGrid
        The file and its grid (a 2D line is a grid of one inline or crossline; a trace list one of ``n_traces``
        inlines and one crossline, inline-sorted).
    tile : int
        Traces a side of a tile.

    Returns
    -------
    (n_inlines, n_xlines, n_samples) float32 dask.array.Array
        Its graph holds no open file (each task opens the file read-only, so it runs on a ``dask.distributed``
        cluster whose workers see the file at the same path), and its name the file's size and time.

    References
    ----------
    Dask array, https://docs.dask.org/en/stable/array.html (an array from a task graph).
    """
    import dask.array as da
    from dask.base import tokenize

    stat = Path(grid.path).stat()
    name = f"segy-{tokenize(grid, stat.st_mtime_ns, stat.st_size, tile)}"
    edges = [[(a, min(a + tile, n)) for a in range(0, n, tile)] for n in (grid.n_inlines, grid.n_xlines)]
    graph = {(name, k, q, 0): (read_segy_block, grid, a, b, c, d) for k, (a, b) in enumerate(edges[0])
             for q, (c, d) in enumerate(edges[1])}
    chunks = (tuple(b - a for a, b in edges[0]), tuple(d - c for c, d in edges[1]), (grid.n_samples,))
    return da.Array(graph, name, chunks, dtype=np.float32)


def _read_amplitudes(f, table, grid: SegyGrid, inline_start, inline_stop, xline_start, xline_stop) -> np.ndarray:
    """:func:`read_segy_block` from an open handle and, for IEEE float samples, the file's trace table (or None)."""
    out = np.empty((inline_stop - inline_start, xline_stop - xline_start, grid.n_samples), np.float32)
    runs = grid.trace_runs(inline_start, inline_stop, xline_start, xline_stop)
    if table is not None and int(f.format) == _IEEE_FLOAT32:
        # IEEE floats: the samples as they are, byte order swapped by numpy as segyio does, in one copy
        block = grid.trace_block(table, inline_start, inline_stop, xline_start, xline_stop)
        out[...] = block[..., TRACE_HEADER_BYTES:].view(_ENDIAN[grid.endian] + "f4")
        return out
    for first, last, where in runs:
        flat = out[where].reshape(last - first, grid.n_samples)
        if np.shares_memory(flat, out):  # a view: filled in pieces, so the temporaries stay small
            for a in range(first, last, _RUN_TRACES):
                b = min(a + _RUN_TRACES, last)
                flat[a - first:b - first] = f.trace.raw[a:b]
        else:
            out[where] = np.asarray(f.trace.raw[first:last], dtype=np.float32).reshape(out[where].shape)
    return out


def header_dtype(fields, endian: str) -> np.dtype:
    """The listed trace header fields as one structured 240-byte record: 4- or 2-byte signed integers at their byte
    positions (SEG-Y rev 1 Table 3, as segyio decodes them), in the file's byte order."""
    order = _ENDIAN[endian]
    return np.dtype({"names": [str(k) for k in fields], "formats": [f"{order}i{_FIELD_BYTES[k]}" for k in fields],
                     "offsets": [k - 1 for k in fields], "itemsize": TRACE_HEADER_BYTES})


def trace_layout(f, path, n_samples: int, n_traces: int) -> tuple | None:
    """``(byte of the first trace, bytes per trace)`` of the open SEG-Y ``f`` at ``path``, or None when its size does
    not match traces of one fixed length (or its sample format is unknown)."""
    sample_bytes = SAMPLE_BYTES.get(int(f.format))
    if sample_bytes is None:
        return None
    first = 3600 + 3200 * int(f.ext_headers)
    stride = TRACE_HEADER_BYTES + int(n_samples) * sample_bytes
    if Path(path).stat().st_size != first + stride * int(n_traces):
        return None
    return first, stride


def _trace_table(f, grid: SegyGrid):
    """The file's traces as a read-only ``(n_traces, trace_bytes)`` uint8 memory map (header then samples), or None
    when the file's size does not match that layout (then the headers are read through segyio)."""
    layout = trace_layout(f, grid.path, grid.n_samples, grid.n_traces)
    if layout is None:
        return None
    first, stride = layout
    return np.memmap(grid.path, np.uint8, mode="r", offset=first, shape=(grid.n_traces, stride))


def read_segy_block_headers(grid: SegyGrid, fields, inline_start: int, inline_stop: int, xline_start: int = 0,
                            xline_stop: int | None = None, *, segyfile=None) -> dict:
    """Read trace header fields of a block of a 3D SEG-Y cube, laid out on the grid.

    The block's 240-byte trace headers are copied out of a memory map of the file once (one run of consecutive traces
    at a time) and every field decoded from them with numpy; a field whose bytes are zero on every trace of the block
    is not decoded (zeros). Files whose size does not match fixed-length traces are read through segyio instead.

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
    fields = [int(k) for k in fields]
    unknown = [k for k in fields if k not in _FIELD_BYTES]
    if unknown:
        raise InputError(f"{unknown} are not trace header fields; pass segyio.TraceField values")
    f = segyfile if segyfile is not None else segyio_handle(grid)
    try:
        return _read_headers(f, _trace_table(f, grid), grid, fields, inline_start, inline_stop, xline_start,
                             xline_stop)
    finally:
        if segyfile is None:
            f.close()


def read_block_and_headers(grid: SegyGrid, fields, inline_start: int, inline_stop: int, xline_start: int,
                            xline_stop: int, segyfile) -> tuple:
    """:func:`read_segy_block` and :func:`read_segy_block_headers` of one block in bounds, through one memory map
    of the file (its pages faulted in once, not twice): ``(amplitudes, headers)``. The Zarr conversion's reader:
    ``headers`` may leave out fields that are zero on every trace of the block (not made and filled with zeros: 91
    arrays a chunk, about a third of its header time)."""
    table = _trace_table(segyfile, grid)
    headers = _read_headers(segyfile, table, grid, [int(k) for k in fields], inline_start, inline_stop, xline_start,
                            xline_stop, zeros=False)
    return _read_amplitudes(segyfile, table, grid, inline_start, inline_stop, xline_start, xline_stop), headers


def _read_headers(f, table, grid: SegyGrid, fields, inline_start, inline_stop, xline_start, xline_stop, *,
                  zeros: bool = True) -> dict:
    """:func:`read_segy_block_headers` from an open handle and the file's trace table (None: through segyio); with
    ``zeros=False``, the fields whose bytes are zero on every trace of the block may be left out."""
    if table is None:
        return _read_headers_segyio(f, grid, fields, inline_start, inline_stop, xline_start, xline_stop)
    shape = (inline_stop - inline_start, xline_stop - xline_start)
    raw = np.ascontiguousarray(grid.trace_block(table, inline_start, inline_stop, xline_start,
                                                xline_stop)[..., :TRACE_HEADER_BYTES])
    # a field is zero on every trace when all of its bytes are: only the others are decoded
    used = raw.reshape(-1, TRACE_HEADER_BYTES).any(axis=0)
    used = used.tolist()  # a list: 91 slices of it take 20 us, of the array 0.2 ms
    decoded = [k for k in fields if any(used[k - 1:k - 1 + _FIELD_BYTES[k]])]
    records = raw.view(header_dtype(decoded, grid.endian))[..., 0]
    out = {k: np.zeros(shape, np.int32) for k in (fields if zeros else decoded)}
    for k in decoded:
        out[k][...] = records[str(k)]
    return out


def _read_headers_segyio(f, grid: SegyGrid, fields, inline_start, inline_stop, xline_start, xline_stop) -> dict:
    """:func:`read_segy_block_headers` through segyio's field reader, one field and run at a time."""
    out = {k: np.empty((inline_stop - inline_start, xline_stop - xline_start), np.int32) for k in fields}
    for first, last, where in grid.trace_runs(inline_start, inline_stop, xline_start, xline_stop):
        for k in fields:
            target = out[k][where]
            out[k][where] = np.asarray(f.attributes(k)[first:last], dtype=np.int64).reshape(target.shape)
    return out
