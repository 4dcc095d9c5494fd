"""The Zarr v3 layout of a seismic cube (written by ``seismo3d convert``, opened by ``seismo3d.open``,
:func:`~seismo3d.seismic.io.cube.open_cube`, and by ``xarray.open_zarr`` as is).

Layout (one Zarr v3 group; the idea is MDIO's: amplitudes, their coordinates and the SEG-Y headers in one store)::

    OUTPUT.zarr/
      seismic      (n_inlines, n_xlines, n_samples) float32, dimension_names (inline, crossline, sample),
                   chunks (64, 64, n_samples), attrs {long_name, coordinates: "cdp_x cdp_y" when present};
                   uncompressed unless written with a compressor (``AMPLITUDE_COMPRESSORS``; the codecs are in the
                   array's metadata, so that every Zarr reader decodes either)
      inline       (n_inlines,) int32, dims (inline,)          inline numbers
      crossline    (n_xlines,) int32, dims (crossline,)        crossline numbers
      sample       (n_samples,) float64, dims (sample,)        time or depth, attrs {units: 'ms' | 'm' | 'ft'}
      cdp_x, cdp_y (n_inlines, n_xlines) float64, dims (inline, crossline), chunks (64, n_xlines), coordinate
                   scalar applied (as SeismicCube.cdp_x: CDP X/Y, else source X/Y), attrs {units: 'm' | 'ft'}; absent
                   when both are 0
      <TraceField> (n_inlines, n_xlines) int32, dims (inline, crossline), chunks (64, n_xlines): every trace
                   header field that is not zero on every trace, named as segyio.TraceField (``CDP_X``,
                   ``INLINE_3D``, ...)
      group attrs: seismo3d {layout: 'seismic-zarr', version: 1, source, sorting, endian, segy_format, iline_byte,
                   xline_byte}, sample_unit, sample_interval, text_header (str, 40 lines of 80 characters),
                   extended_text_headers (list of str), binary_header {segyio.BinField name: int}

Chunks: (64, 64, n_samples) tiles of whole traces. The fault scan and the attributes need every sample of a trace,
so a chunk never splits a trace; 64 x 64 traces keep a chunk at 8-40 MB for 500-2500 samples, small enough for a
worker, large enough for few files (a 10 GB cube makes about 500 chunks), and square so that inline, crossline and
map views read alike. ``seismo3d.open`` rechunks to its tiles (``tile``).

References
----------
Zarr v3 core specification (``dimension_names``), https://zarr-specs.readthedocs.io/en/latest/v3/core/index.html.
MDIO (TGS), https://mdio-python.readthedocs.io: the layout idea (named dimensions, coordinates, headers kept).
SEG-Y rev 1 (SEG Technical Standards Committee, 2002), textual, binary and trace headers.
"""

from __future__ import annotations

import os
import warnings
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import segyio

from ...errors import InputError
from .blocks import SegyGrid, read_block_and_headers, segyio_handle
from .geometry import scale_coordinates

__all__ = ["LAYOUT", "TILE_TRACES", "AMPLITUDE_COMPRESSORS", "SeismicZarrWriter", "consolidate", "is_seismic_zarr",
           "open_seismic_group"]

LAYOUT = {"layout": "seismic-zarr", "version": 1}
TILE_TRACES = 64  # traces per chunk along inline and crossline
_TRACE_FIELDS = {int(f): str(f) for f in segyio.TraceField.enums()}
_BIN_FIELDS = {int(f): str(f) for f in segyio.BinField.enums()}
_COORDINATE_FIELDS = ((segyio.TraceField.CDP_X, segyio.TraceField.CDP_Y),
                      (segyio.TraceField.SourceX, segyio.TraceField.SourceY))
_UNITS = {1: "m", 2: "ft"}  # binary header bytes 3255-3256, measurement system
_COPY_THREADS = 2  # threads reading, encoding and writing chunks (numpy copies, codecs, file writes: GIL free)
# Stores of the chunked fault runs: Blosc LZ4 with byte shuffle compresses float32 as well as Zarr's default (Zstd
# level 0) at about three times its speed. On the 400 x 400 x 500 target of benchmarks/fault_paths.py it encodes the
# learned likelihood 5x faster (416 against 83 MB/s), strike and slopes 3x, decodes 1.5-3x faster, at the same or a
# better ratio (1.30 against 1.28 for the likelihood, 1.43 against 1.15 for the slopes; 23 against 50 for the sparse
# votes).
SEISMIC_CODEC = ({"name": "blosc", "configuration": {"cname": "lz4", "clevel": 5, "shuffle": "shuffle",
                                                      "typesize": 4, "blocksize": 0}},)
# The amplitudes of ``seismo3d convert``, by ``compression``: uncompressed by default, because float32 seismic barely
# compresses losslessly (LZ4 + shuffle 1.10-1.13x, Zstd level 0 1.07-1.08x on the data folder's field sections: Volve's
# full stack, Campos, Costa Rica, Teapot, an F3 section) while encoding costs CPU (LZ4 0.22-0.41 CPU s for the
# 198 MB cube of benchmarks/commands.py, whose convert takes about 1.2 CPU s in all); amplitudes that were integers or
# are smooth compress more (1.5-1.8x: the F3 crop and section f3d178sub2, Penobscot xl1155, Volve's velocities),
# where ``'lz4'`` or ``'zstd'`` (Zarr's default codec) may pay.
AMPLITUDE_COMPRESSORS = {
    "none": (),
    "lz4": SEISMIC_CODEC,
    "zstd": ({"name": "zstd", "configuration": {"level": 0, "checksum": False}},),
}


def is_seismic_zarr(path) -> bool:
    """Whether ``path`` is a directory holding a Zarr group written in this layout (reads only its metadata)."""
    try:
        open_seismic_group(path)
    except InputError:
        return False
    return True


def open_seismic_group(path):
    """The Zarr group of a store written by ``seismo3d convert``, checked, for reading (``seismo3d.open`` opens the
    store as a cube: :func:`~seismo3d.seismic.io.cube.open_cube`).

    Parameters
    ----------
    path : str or os.PathLike
        The store's directory.

    Returns
    -------
    zarr.Group
        Opened read-only; its arrays and attributes as the module docstring says.

    Raises
    ------
    InputError
        Not a Zarr group, not this layout (the message says how to make one), another layout version, or arrays
        missing.
    """
    import zarr

    path = Path(path)
    not_ours = (f"{path} is not a seismic Zarr store written by 'seismo3d convert'; convert the SEG-Y with "
                f"'seismo3d convert INPUT.sgy {path.name}'")
    try:
        group = zarr.open_group(str(path), mode="r")
    except (FileNotFoundError, ValueError, KeyError, TypeError, OSError) as exc:
        raise InputError(f"{not_ours} (no Zarr group there)") from exc
    if dict(group.attrs).get("seismo3d", {}).get("layout") != LAYOUT["layout"]:
        raise InputError(f"{not_ours} (its attributes do not name the seismo3d layout)")
    version = group.attrs["seismo3d"].get("version")
    if version != LAYOUT["version"]:
        raise InputError(f"{path} is seismic-zarr version {version}; this seismo3d reads version "
                         f"{LAYOUT['version']}: convert the SEG-Y again")
    missing = [k for k in ("seismic", "inline", "crossline", "sample") if k not in group]
    if missing:
        raise InputError(f"{path} lacks the array(s) {', '.join(missing)}; the store is incomplete: convert the SEG-Y "
                         "again")
    return group


def consolidate(store) -> None:
    """Write a Zarr group's consolidated metadata (every array's metadata in the group's ``zarr.json``), so that
    xarray opens it with one read; call it again after adding arrays or attributes.

    Parameters
    ----------
    store : str, os.PathLike or zarr store
        The group.

    Notes
    -----
    Consolidated metadata is zarr-python's extension of the Zarr v3 specification (it warns about that; the
    warning is silenced here); readers without it ignore it. zarr lists the arrays in the order its asynchronous
    listing finds them, which changes from run to run: in a store on disk they are put in name order, so that
    converting the same file again writes the same ``zarr.json``.
    """
    import zarr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # ZarrUserWarning: consolidated metadata is not in the v3 specification
        zarr.consolidate_metadata(store if not isinstance(store, (str, os.PathLike)) else str(store))
    root = store if isinstance(store, (str, os.PathLike)) else getattr(store, "root", None)
    if root is not None:
        _sort_consolidated(Path(root) / "zarr.json")


def _sort_consolidated(path: Path) -> None:
    """The consolidated metadata of a group's ``zarr.json`` in name order, the file replaced atomically."""
    import json

    from ..._atomic import atomic_path

    meta = json.loads(path.read_text())
    members = (meta.get("consolidated_metadata") or {}).get("metadata")
    if not isinstance(members, dict) or list(members) == sorted(members):
        return
    meta["consolidated_metadata"]["metadata"] = dict(sorted(members.items()))
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(meta, indent=2))


def _text(raw: bytes) -> str:
    return segyio.tools.wrap(raw.decode("ascii", errors="replace"), 80) if raw else ""


def _group_attrs(cube) -> dict:
    """The SEG-Y file's headers and the layout's identity, as JSON-able group attributes."""
    f = cube.segyfile
    binary = {_BIN_FIELDS.get(int(k), str(k)): int(v) for k, v in f.bin.items()}
    return {
        "seismo3d": {**LAYOUT, "source": cube.path.name, "sorting": cube.sorting, "endian": cube.endian,
                     "segy_format": int(cube.format), "iline_byte": int(cube.iline_byte),
                     "xline_byte": int(cube.xline_byte)},
        "sample_unit": cube.sample_unit,
        "sample_interval": float(cube.sample_interval),
        "text_header": _text(f.text[0]),
        "extended_text_headers": [_text(f.text[i]) for i in range(1, 1 + f.ext_headers)],
        "binary_header": binary,
    }


class SeismicZarrWriter:
    """Write a 3D SEG-Y cube into the Zarr layout tile by tile (memory: about ``chunk_mb``).

    Use: ``with SeismicZarrWriter(cube, store) as w:``, ``w.write_tile(t)`` for each ``t`` in ``w.tiles`` (in any
    order; in their order one row of header fields is held at a time), then ``w.finish()``, which waits for the last
    writes and adds ``cdp_x`` / ``cdp_y`` when the coordinates are not CDP X / Y but source X / Y. Leaving the
    ``with`` waits for the writes under way (after an error too), so that the store can then be removed.

    A tile is copied chunk by chunk (64 x 64 traces) on two threads: each reads its chunk's headers and amplitudes
    through one memory map, encodes the amplitudes with the array's codecs (little-endian bytes, then the compressor
    if any) and writes them to the chunk's key in the store, so that both cores read, encode and write (zarr's array
    API would add about a quarter to the CPU time with LZ4, 0.59 against 0.47 CPU s for the same chunks, and more
    uncompressed, 0.50-0.62 against 0.28-0.35 CPU s for the 198 MB bench cube: its asyncio tasks and buffer
    copies). At most ``chunk_mb`` of amplitudes, and no more than three chunks, are held at a time (with each its
    encoded bytes). Chunks of zeros are not written (left to the fill value, as zarr does). The trace header fields of
    a row of chunks (64 inlines, every crossline) are gathered from its tiles (only the fields not zero there) and
    written once the row is complete, with ``cdp_x`` / ``cdp_y`` of that row: one chunk file per field and row,
    encoded and written on the same threads as the amplitudes (through zarr's array API the main thread spent 1-2 ms
    on each, 0.07 s of the bench cube's 0.3 s; memory: 64 x n_xlines int32 per field that is not zero, e.g. 1 MiB per
    field for 4000 crosslines). zarr writes every array's metadata and the consolidated metadata.

    Parameters
    ----------
    cube : SeismicCube
        An open 3D cube (:func:`~seismo3d.seismic.io.open_segy`); read through its memory-mapped handle.
    store : str or os.PathLike
        Directory of the new store (created; an existing one is replaced).
    chunk_mb : float
        Upper bound in MiB of the amplitudes read or being written at a time, and of a tile (at least one 64 x
        64-trace chunk).
    compression : {'none', 'lz4', 'zstd'}
        The amplitudes' compressor (:data:`AMPLITUDE_COMPRESSORS`): none (the default), Blosc LZ4 with byte shuffle, or
        Zstd level 0 (Zarr's default).

    Attributes
    ----------
    tiles : list of (int, int, int, int)
        ``(inline_start, inline_stop, xline_start, xline_stop)`` array indices; whole chunks.

    Raises
    ------
    SegyGeometryError
        ``cube`` is not a 3D cube.
    InputError
        ``compression`` is not one of :data:`AMPLITUDE_COMPRESSORS`.
    """

    def __init__(self, cube, store, *, chunk_mb: float = 64, compression: str = "none"):
        import zarr

        if compression not in AMPLITUDE_COMPRESSORS:
            raise InputError(f"compression must be one of {', '.join(map(repr, AMPLITUDE_COMPRESSORS))}; got "
                             f"{compression!r}")

        self.cube = cube
        self.grid = SegyGrid.from_cube(cube)
        n_il, n_xl, ns = cube.shape
        chunk = (min(TILE_TRACES, n_il), min(TILE_TRACES, n_xl), ns)
        self.root = zarr.open_group(str(store), mode="w", zarr_format=3, attributes=_group_attrs(cube))
        self._coordinates(cube)
        self.seismic = self.root.create_array("seismic", shape=cube.shape, chunks=chunk, dtype="float32",
                                              dimension_names=("inline", "crossline", "sample"), fill_value=0.0,
                                              compressors=AMPLITUDE_COMPRESSORS[compression],
                                              attributes={"long_name": "amplitude"})
        self._store = store
        self._chunk_files = _ChunkFiles(self.seismic, store)
        self._files = {}  # array path -> _ChunkFiles of the header and coordinate arrays
        self._header_chunks = (chunk[0], n_xl)  # one chunk file per field and row (64 x 64 chunks: 7x the files)
        self.headers = {}  # TraceField -> zarr array, created at the field's first non-zero value (before it: fill 0)
        self.nonzero = {k: False for k in _TRACE_FIELDS}
        self._rows = {}  # first inline of a row of chunks -> _HeaderRow, until all its tiles are written
        self._cdp = None  # (cdp_x, cdp_y) zarr arrays from CDP X / Y, created at their first non-zero row
        chunk_bytes = chunk[0] * chunk[1] * ns * 4
        self._copies = _BackgroundWork(max(chunk_mb * 2**20, chunk_bytes), max_pending=_COPY_THREADS + 1)
        xl_step = chunk[1] * max(1, int(chunk_mb * 2**20 // chunk_bytes))
        self.tiles = [(a, min(a + chunk[0], n_il), b, min(b + xl_step, n_xl))
                      for a in range(0, n_il, chunk[0]) for b in range(0, n_xl, xl_step)]

    def __enter__(self) -> "SeismicZarrWriter":
        return self

    def __exit__(self, *exc) -> None:
        self._copies.close(raise_errors=exc[0] is None)

    def _coordinates(self, cube) -> None:
        self.root.create_array("inline", data=np.asarray(cube.inlines, np.int32), dimension_names=("inline",),
                               attributes={"long_name": "inline number"})
        self.root.create_array("crossline", data=np.asarray(cube.xlines, np.int32), dimension_names=("crossline",),
                               attributes={"long_name": "crossline number"})
        self.root.create_array("sample", data=np.asarray(cube.samples, np.float64), dimension_names=("sample",),
                               attributes={"units": cube.sample_unit, "long_name": "time or depth"})

    def write_tile(self, tile) -> None:
        """Copy one tile of amplitudes from the SEG-Y into the store (chunks on the background threads) and gather its
        trace headers; write the row's headers once it is complete.

        Parameters
        ----------
        tile : (int, int, int, int)
            An element of :attr:`tiles`.

        Raises
        ------
        Exception
            The error of a chunk's copy (reading the SEG-Y or writing the store), if one failed.
        """
        a, b, c, d = tile
        step = self.seismic.chunks[1]
        row = self._rows.setdefault(a, _HeaderRow(b - a, self.seismic.shape[1]))
        # A memory map of its own per tile (its pages count as this process's memory until it is closed, so the
        # cube's handle, mapped for the whole run, would hold the whole file by the last tile)
        with segyio_handle(self.grid) as f:
            copies = [(j, min(j + step, d)) for j in range(c, d, step)]
            copies = [(j, k, self._copies.run(self._copy_chunk, f, a, b, j, k,
                                              nbytes=(b - a) * (k - j) * self.grid.n_samples * 4))
                      for j, k in copies]
            for j, k, future in copies:  # the handle stays open until its chunks are read
                row.add(future.result(), j, k)
        if row.complete:
            self._write_header_row(self._rows.pop(a), a, b)

    def _write_rows(self, array, a: int, values: np.ndarray) -> None:
        """A row of chunks of a header or coordinate array (one chunk: 64 inlines, every crossline) written on the
        background threads as a chunk file (zarr's async writes cost the main thread 1-2 ms each)."""
        files = self._files.get(array.path)
        if files is None:
            files = self._files[array.path] = _ChunkFiles(array, self._store)
        self._copies.run(files.write, values, a, 0, nbytes=values.nbytes)

    def _copy_chunk(self, f, a: int, b: int, c: int, d: int) -> dict:
        """On a background thread: the chunk of inlines ``a:b`` and crosslines ``c:d`` read from the open SEG-Y
        ``f`` and its amplitudes written to the store unless all zero; its trace headers."""
        chunk, headers = read_block_and_headers(self.grid, _TRACE_FIELDS, a, b, c, d, f)
        self._chunk_files.write(chunk, a, c, 0)  # not a chunk of zeros (bit patterns, as zarr: -0.0 is written)
        return headers

    def _write_header_row(self, row: "_HeaderRow", a: int, b: int) -> None:
        """A complete row of chunks: its non-zero header fields, and cdp_x / cdp_y from CDP X / Y."""
        n_il, n_xl = self.seismic.shape[:2]
        for k, values in row.fields.items():
            if k not in self.headers:
                self.headers[k] = self.root.create_array(
                    _TRACE_FIELDS[k], shape=(n_il, n_xl), chunks=self._header_chunks, dtype="int32",
                    dimension_names=("inline", "crossline"), fill_value=0)
            self._write_rows(self.headers[k], a, values)
            self.nonzero[k] = True
        fx, fy = _COORDINATE_FIELDS[0]
        if fx in row.fields or fy in row.fields:  # rows where both are 0 keep the fill value, 0.0
            if self._cdp is None:
                self._cdp = self._create_cdp_arrays()
            scalar = row.values(segyio.TraceField.SourceGroupScalar)
            for out, field in zip(self._cdp, (fx, fy)):
                self._write_rows(out, a, scale_coordinates(row.values(field), scalar))

    def _create_cdp_arrays(self) -> tuple:
        n_il, n_xl = self.seismic.shape[:2]
        unit = _UNITS.get(int(self.cube.segyfile.bin[segyio.BinField.MeasurementSystem]), "unknown")
        return tuple(self.root.create_array(name, shape=(n_il, n_xl), chunks=self._header_chunks,
                                            dtype="float64", dimension_names=("inline", "crossline"), fill_value=0.0,
                                            attributes={"units": unit})
                     for name in ("cdp_x", "cdp_y"))

    def finish(self) -> list:
        """Write the rows of header fields still gathered (tiles missing), wait for every write, add ``cdp_x`` /
        ``cdp_y`` from source X / Y when CDP X / Y are zero everywhere; return the names of the header fields kept.

        Raises
        ------
        Exception
            The error of a write, if one failed.
        """
        for a, row in sorted(self._rows.items()):
            self._write_header_row(row, a, a + row.n_inlines)
        self._rows.clear()
        self._copies.wait()
        self._add_source_coordinates()
        if self._cdp is not None:
            self.seismic.attrs["coordinates"] = "cdp_x cdp_y"
        consolidate(self.root.store)  # every array's metadata in the group's zarr.json (consolidate's notes)
        return [name for k, name in _TRACE_FIELDS.items() if self.nonzero[k]]

    def _header_rows(self, field):
        """``rows(a, b)``: the field's values on inlines ``a:b`` (zeros for a field never written)."""
        if field in self.headers:
            return lambda a, b: self.headers[field][a:b]
        return lambda a, b: np.zeros((min(b, self.seismic.shape[0]) - a, self.seismic.shape[1]), np.int32)

    def _add_source_coordinates(self) -> None:
        """cdp_x / cdp_y from source X / Y with the coordinate scalar applied, one row of chunks at a time (as
        SeismicCube.cdp_x), when CDP X / Y are zero on every trace and source X / Y are not."""
        fields = _COORDINATE_FIELDS[1]
        if self._cdp is not None or not (self.nonzero[fields[0]] or self.nonzero[fields[1]]):
            return
        self._cdp = self._create_cdp_arrays()
        scalar = self._header_rows(segyio.TraceField.SourceGroupScalar)
        rows = self.seismic.chunks[0]
        for out, field in zip(self._cdp, fields):
            for a in range(0, self.seismic.shape[0], rows):
                self._write_rows(out, a, scale_coordinates(self._header_rows(field)(a, a + rows), scalar(a, a + rows)))
        self._copies.wait()


class _ChunkFiles:
    """The chunk files of a Zarr v3 array in a local store, written as zarr would write them: the values encoded by
    the array's codecs (little-endian bytes, then its compressor if it has one: a Blosc or Zstd configuration such as
    :data:`AMPLITUDE_COMPRESSORS` or zarr's default, Zstd level 0, encoded by numcodecs as zarr does), at the chunk's
    key (the array's chunk key encoding), an edge chunk padded with the fill value to the full chunk shape (as the Zarr
    v3 specification stores it), and no file for a chunk of fill values only (zarr's ``write_empty_chunks=False``,
    its default: bit patterns, so -0.0 is written). For the amplitudes, the header fields and cdp_x / cdp_y;
    thread-safe: each call writes its own file."""

    def __init__(self, array, store: Path):
        codecs = array.metadata.to_dict()["codecs"]
        if codecs[0] != {"name": "bytes", "configuration": {"endian": "little"}}:
            raise ValueError(f"{array.path}: chunk files are written for little-endian bytes, not {codecs[0]}")
        self._codec = _numcodecs_compressor(codecs[1:])
        self._dtype = np.dtype(array.dtype).newbyteorder("<")
        self._fill = np.asarray(array.fill_value, self._dtype)
        self._fill_bytes = self._fill.reshape(1).view(np.uint8)
        self._array, self._folder = array, Path(store) / array.path

    def _is_fill(self, values: np.ndarray) -> bool:
        """Whether every element of ``values`` (contiguous, of the array's dtype) has the fill value's bits."""
        bits = values.view(f"u{self._dtype.itemsize}") if self._dtype.itemsize in (1, 2, 4, 8) else None
        if bits is not None and not self._fill_bytes.any():  # a fill of zero bits (0, 0.0): no temporary array
            # every 509th value first: a chunk of data is told without a pass over all of it (0.02 CPU s of 198 MB)
            return not bits.reshape(-1)[::509].any() and not bits.any()
        return bool(np.all(values.view(np.uint8).reshape(values.size, -1) == self._fill_bytes))

    def write(self, values: np.ndarray, *start: int) -> None:
        """Write the chunk whose first element is at array index ``start`` (chunk-aligned) from ``values`` (the
        chunk's elements inside the array), unless it holds only the fill value."""
        shape = self._array.chunks
        if len(start) != len(shape):
            raise ValueError(f"a chunk of the {len(shape)}D array {self._array.path} needs {len(shape)} start "
                             f"indices; got {start}")
        if values.shape != shape:
            full = np.full(shape, self._fill, self._dtype)
            full[tuple(slice(0, n) for n in values.shape)] = values
            values = full
        values = np.ascontiguousarray(values, dtype=self._dtype)
        if self._is_fill(values):
            return
        key = self._array.metadata.encode_chunk_key(tuple(i // n for i, n in zip(start, shape)))
        path = self._folder / key
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(values.data if self._codec is None else self._codec.encode(values))


def _numcodecs_compressor(compressors):
    """The numcodecs codec that zarr uses for the compressor of an array's codecs after ``bytes`` (None: none)."""
    import numcodecs

    if not compressors:
        return None
    (codec,) = compressors
    config = codec["configuration"]
    if codec["name"] == "zstd":
        return numcodecs.Zstd(level=config["level"], checksum=config["checksum"])
    shuffle = {"noshuffle": numcodecs.Blosc.NOSHUFFLE, "shuffle": numcodecs.Blosc.SHUFFLE,
               "bitshuffle": numcodecs.Blosc.BITSHUFFLE}[config["shuffle"]]
    # typesize: the item size of the float32 values encoded (as the codec's "typesize": 4)
    return numcodecs.Blosc(cname=config["cname"], clevel=config["clevel"], shuffle=shuffle,
                           blocksize=config["blocksize"])


class _BackgroundWork:
    """Calls on background threads, with the bytes each holds until done: at most ``max_bytes`` of them and
    ``max_pending`` calls at a time; the first error is raised by the next call."""

    def __init__(self, max_bytes: float, *, max_pending: int):
        self.max_bytes, self.max_pending = max_bytes, max_pending
        self._pool = ThreadPoolExecutor(max_workers=_COPY_THREADS, thread_name_prefix="seismic-zarr-copy")
        self._pending = deque()  # (future, bytes), oldest first

    def wait_for_room(self, nbytes: int) -> None:
        """Wait until ``nbytes`` more can be held (oldest calls first)."""
        while self._pending and (len(self._pending) >= self.max_pending
                                 or sum(n for _, n in self._pending) + nbytes > self.max_bytes):
            future, _ = self._pending.popleft()
            future.result()

    def run(self, function, *args, nbytes: int):
        """Call ``function(*args)`` in the background once ``nbytes`` more can be held; its future."""
        self.wait_for_room(nbytes)
        future = self._pool.submit(function, *args)
        self._pending.append((future, nbytes))
        return future

    def wait(self) -> None:
        """Wait for every call; raise the first error."""
        self.wait_for_room(self.max_bytes + 1)

    def close(self, *, raise_errors: bool) -> None:
        """Wait for the calls under way (raising their first error only if ``raise_errors``) and stop the threads."""
        try:
            if raise_errors:
                self.wait()
            else:
                for future, _ in self._pending:
                    future.exception()  # waits; the error that ended the run is the one reported
        finally:
            self._pending.clear()
            self._pool.shutdown(wait=True)


class _HeaderRow:
    """The non-zero trace header fields of one row of chunks (inlines ``a:a + n_inlines``, every crossline), filled
    tile by tile."""

    def __init__(self, n_inlines: int, n_xlines: int):
        self.n_inlines, self.n_xlines = n_inlines, n_xlines
        self.fields = {}  # TraceField -> (n_inlines, n_xlines) int32, made at the field's first non-zero tile
        self.filled = 0  # crosslines written

    @property
    def complete(self) -> bool:
        """Whether every crossline was added."""
        return self.filled == self.n_xlines

    def add(self, headers: dict, c: int, d: int) -> None:
        """Add the fields of the row's crosslines ``c:d``."""
        for k, values in headers.items():
            if values.any():
                if k not in self.fields:
                    self.fields[k] = np.zeros((self.n_inlines, self.n_xlines), np.int32)
                self.fields[k][:, c:d] = values
        self.filled += d - c

    def values(self, field) -> np.ndarray:
        """A field's values (zeros when it is zero on every trace of the row)."""
        return self.fields.get(field, np.zeros((self.n_inlines, self.n_xlines), np.int32))
