"""SEG-Y written like a template file: an attribute with the template's headers, whole (:func:`write_like`) or one
block of inlines at a time for a cube larger than memory (:func:`write_like_blocks`: a Zarr or dask array; memory is
one block, never the cube).
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import segyio

from ..._atomic import atomic_path
from ..._progress import progress_steps
from ...errors import InputError, TraceListWarning
from .blocks import FIELD_STARTS, TRACE_HEADER_BYTES, SegyGrid, header_dtype, trace_layout
from .segy import open_segy

__all__ = ["INLINES_PER_BLOCK", "write_like", "write_like_blocks"]

# Inlines a block of write_like_blocks reads, checks and writes at a time (its default; the faults job's memory
# plan of the SEG-Y writers counts one such block)
INLINES_PER_BLOCK = 32


def write_like(template_path, out_path, data, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False,
               endian=None) -> Path:
    """Write an attribute as SEG-Y with the headers and geometry of a template file.

    The textual, binary and every trace header are copied from the template (segyio's copy-a-file recipe); only the
    binary header's data format becomes 5 (4-byte IEEE float) so that any attribute fits. The file is big-endian, the
    SEG-Y standard's byte order, whatever the template's. It is written to a temporary file in the output folder and
    moved into place when complete, so an interrupted call never leaves a half-written ``out_path``. The template is
    only read.

    Parameters
    ----------
    template_path : str or os.PathLike
        The SEG-Y file whose headers are copied.
    out_path : str or os.PathLike
        Output file; its folder must exist. Replaced if it exists.
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        The attribute on the template's grid (``open_segy(template).shape``) or per trace in file order; written
        as float32.
    iline, xline, ignore_geometry, endian
        How to open the template, as in :func:`open_segy` (a template without a grid is read as a trace list
        without a second :class:`TraceListWarning`).

    Returns
    -------
    out_path : pathlib.Path

    Raises
    ------
    InputError
        ``out_path`` is the template, its folder does not exist, ``data`` has the wrong shape or NaN / inf values.
    SegyFormatError, SegyGeometryError, DataNotFoundError
        The template cannot be read (see :func:`open_segy`).
    """
    template_path, out_path = _check_destination(template_path, out_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TraceListWarning)  # the caller was told when it read the template
        cube = open_segy(template_path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian)
    with cube:
        arr = np.asarray(data, dtype=np.float32)
        ntr, ns = cube.n_traces, cube.samples.size
        if arr.shape == cube.shape:
            traces = cube._to_traces(arr)
        elif arr.shape == (ntr, ns):
            traces = arr
        else:
            raise InputError(f"data has shape {arr.shape} but the template {template_path.name} needs {cube.shape} "
                             f"(its grid) or {(ntr, ns)} (traces in file order)")
        if not np.all(np.isfinite(traces)):
            raise InputError("data contains NaN or inf, which most SEG-Y readers reject; replace them first, e.g. "
                             "np.nan_to_num(data)")
        traces = np.ascontiguousarray(traces, dtype=np.float32)
        src = cube.segyfile
        spec = segyio.tools.metadata(src)
        spec.format = int(segyio.SegySampleFormat.IEEE_FLOAT_4_BYTE)
        spec.endian = "big"  # segyio converts the copied header values to it
        if src.unstructured:
            spec.tracecount = src.tracecount
        with atomic_path(out_path) as tmp:
            with segyio.create(str(tmp), spec) as dst:
                fixed_length = _start_like(src, dst, template_path)
                if not fixed_length:
                    _write_segyio_traces(dst, 0, traces)
            if fixed_length:
                with _TraceWriter(template_path, src, cube.endian, tmp) as writer:
                    writer.write(0, traces)
    return out_path


def write_like_blocks(template_path, out_path, values, *, iline: int = 189, xline: int = 193, endian=None,
                      inlines_per_block: int = INLINES_PER_BLOCK, progress: bool = False) -> Path:
    """Write an attribute of a 3D cube as SEG-Y with the template's headers, one block of inlines at a time.

    As :func:`~seismo3d.seismic.io.write_like`: the textual, binary and every trace header are copied from the
    template, the data format becomes 5 (4-byte IEEE float) and the file is big-endian; it is written to a temporary
    file in the output folder and moved into place when complete (an interrupted call leaves no ``out_path``). The
    template is only read.

    Parameters
    ----------
    template_path : str or os.PathLike
        A 3D SEG-Y cube (inline- or crossline-sorted).
    out_path : str or os.PathLike
        Output file; its folder must exist. Replaced if it exists.
    values : (n_inlines, n_xlines, n_samples) array-like with slicing
        The attribute on the template's grid (e.g. a ``zarr.Array`` or a dask array); read by blocks of
        ``inlines_per_block`` inlines (``values[i0:i1]``), written as float32.
    iline, xline, endian
        How to open the template, as in :func:`~seismo3d.seismic.io.open_segy`.
    inlines_per_block : int
    progress : bool
        Report progress per block.

    Returns
    -------
    out_path : pathlib.Path

    Raises
    ------
    InputError
        ``out_path`` is the template, its folder does not exist, the template is not a 3D cube, ``values`` has
        another shape, or a block holds NaN / inf values.
    SegyFormatError, SegyGeometryError, DataNotFoundError
        The template cannot be read (see :func:`~seismo3d.seismic.io.open_segy`).

    References
    ----------
    .. [1] SEG Technical Standards Committee, "SEG-Y_r2.0: SEG-Y revision 2.0 Data Exchange format", 2017.
    """
    template_path, out_path = _check_destination(template_path, out_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TraceListWarning)
        cube = open_segy(template_path, iline=iline, xline=xline, endian=endian)
    with cube:
        if not cube.is_3d or cube.inlines is None:
            raise InputError(f"{template_path.name} is {cube.description}; block-by-block SEG-Y output needs a 3D "
                             "cube template (use write_like for lines)")
        if tuple(values.shape) != tuple(cube.shape):
            raise InputError(f"values have shape {tuple(values.shape)} but the template {template_path.name} needs "
                             f"{cube.shape}")
        grid = SegyGrid.from_cube(cube)
        src = cube.segyfile
        spec = segyio.tools.metadata(src)
        spec.format = int(segyio.SegySampleFormat.IEEE_FLOAT_4_BYTE)
        spec.endian = "big"
        with atomic_path(out_path) as tmp:
            with segyio.create(str(tmp), spec) as dst:
                fixed_length = _start_like(src, dst, template_path)
                if not fixed_length:
                    _write_inline_blocks(values, grid, int(inlines_per_block), f"writing {out_path.name}", progress,
                                         lambda first, traces: _write_segyio_traces(dst, first, traces))
            if fixed_length:
                with _TraceWriter(template_path, src, cube.endian, tmp) as writer:
                    _write_inline_blocks(values, grid, int(inlines_per_block), f"writing {out_path.name}", progress,
                                         writer.write)
    return out_path


def _write_inline_blocks(values, grid: SegyGrid, inlines_per_block: int, label: str, progress: bool, write) -> None:
    """The traces of ``values``, ``inlines_per_block`` inlines read at a time, handed to ``write(first_trace,
    traces)`` one run of consecutive traces of the file at a time."""
    starts = range(0, grid.n_inlines, inlines_per_block)
    with progress_steps(len(starts), label, unit="block", enabled=progress) as bar:
        for i0 in starts:
            i1 = min(i0 + inlines_per_block, grid.n_inlines)
            block = np.asarray(values[i0:i1], dtype=np.float32)
            if not np.all(np.isfinite(block)):
                raise InputError(f"values hold NaN or inf in inlines {i0}-{i1 - 1} (indices), which most SEG-Y "
                                 "readers reject; replace them first")
            for first, last, where in grid.trace_runs(i0, i1, 0, grid.n_xlines):
                write(first, np.ascontiguousarray(block[where]).reshape(-1, grid.n_samples))
            bar.advance()


def _write_segyio_traces(dst, first: int, traces: np.ndarray) -> None:
    """Traces ``first, first + 1, ...`` through segyio, one at a time (templates whose traces differ in length)."""
    for k in range(traces.shape[0]):
        dst.trace[first + k] = traces[k]


def _start_like(src, dst, template_path: Path) -> bool:
    """Copy the textual and binary headers of ``src`` into the new file ``dst`` (data format 5); the trace headers
    too when the template's traces are not of one fixed length (through segyio, field by field). Whether the traces
    are of one fixed length (then :class:`_TraceWriter` writes them, headers and samples, once ``dst`` is closed)."""
    for i in range(1 + src.ext_headers):
        dst.text[i] = src.text[i]
    dst.bin = src.bin
    dst.bin.update({segyio.BinField.Format: int(segyio.SegySampleFormat.IEEE_FLOAT_4_BYTE)})
    if trace_layout(src, template_path, len(src.samples), src.tracecount) is None:
        dst.header = src.header
        return False
    return True


_COPY_TRACES = 8192  # traces written at a time (the template's read and the output's: 2 x 18 MB at most)


class _TraceWriter:
    """The traces of a big-endian IEEE-float SEG-Y ``out_path`` whose textual and binary headers segyio wrote (no
    trace yet), written with plain file writes: each trace's 240-byte header copied from the template as segyio's
    header copy does field by field (byte for byte from a big-endian template, each field of SEG-Y rev 1 Table 3, 2
    or 4 bytes, byte-swapped from a little-endian one), then its samples as big-endian 4-byte floats. One write per
    run of traces instead of segyio's write per trace and a second pass for the headers; plain reads of the template
    (no memory map: the files' pages are not the process's). Use as a context manager; the file is sized for every
    trace at the start, so runs may come in any order."""

    def __init__(self, template_path: Path, src, endian: str, out_path):
        self.n = src.tracecount
        self.first, self.stride = trace_layout(src, template_path, len(src.samples), self.n)
        self.n_samples = len(src.samples)
        self.out_stride = TRACE_HEADER_BYTES + 4 * self.n_samples  # IEEE float samples
        self.swap = None if endian == "big" else (header_dtype(FIELD_STARTS, "little"),
                                                  header_dtype(FIELD_STARTS, "big"))
        self.template_path, self.out_path = template_path, out_path

    def __enter__(self) -> "_TraceWriter":
        self._fin = open(self.template_path, "rb")
        try:
            self._fout = open(self.out_path, "r+b")
            self._fout.truncate(self.first + self.n * self.out_stride)  # the same textual and binary headers
        except BaseException:
            self._fin.close()
            raise
        return self

    def __exit__(self, *exc) -> None:
        try:
            self._fout.close()
        finally:
            self._fin.close()

    def write(self, first: int, traces: np.ndarray) -> None:
        """Traces ``first, first + 1, ...`` of the file: ``traces`` (m, n_samples) float32."""
        for a in range(0, traces.shape[0], _COPY_TRACES):
            m = min(_COPY_TRACES, traces.shape[0] - a)
            self._fin.seek(self.first + (first + a) * self.stride)
            raw = np.fromfile(self._fin, np.uint8, m * self.stride).reshape(m, self.stride)[:, :TRACE_HEADER_BYTES]
            out = np.empty((m, self.out_stride), np.uint8)
            if self.swap is not None:
                raw = np.ascontiguousarray(raw).view(self.swap[0]).reshape(-1).astype(self.swap[1]).view(np.uint8)
                raw = raw.reshape(m, TRACE_HEADER_BYTES)
            out[:, :TRACE_HEADER_BYTES] = raw
            out[:, TRACE_HEADER_BYTES:].view(">f4")[:] = traces[a:a + m]
            self._fout.seek(self.first + (first + a) * self.out_stride)
            out.tofile(self._fout)


def _check_destination(template_path, out_path) -> tuple[Path, Path]:
    """The two paths, after refusing an ``out_path`` that is the template (also through a link) or whose folder does
    not exist."""
    template_path, out_path = Path(template_path), Path(out_path)
    if template_path.resolve() == out_path.resolve() or (
        out_path.exists() and template_path.exists() and os.path.samefile(template_path, out_path)
    ):
        raise InputError(f"out_path {out_path} is the template file itself; write to another file, the template "
                         "must not be overwritten")
    out_dir = out_path.resolve().parent
    if not out_dir.is_dir():
        raise InputError(f"output folder {out_dir} does not exist; create it first")
    return template_path, out_path
