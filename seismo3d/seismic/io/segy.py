"""Reading and writing seismic data: SEG-Y cubes and lines (through segyio), raw sections, ASCII line exports.

The one way to read SEG-Y is a lazy handle::

    with open_segy(path) as cube:              # reads headers only
        section = cube.inline(cube.inlines[0])  # (n_xlines, n_samples) float32
        data = cube.read()                      # the whole file, only when asked

Layouts
-------
* A file with inline / crossline geometry (sorted 3D cube, or a 2D line of a 3D survey, i.e. one inline or one
  crossline) has ``cube.shape == (n_inlines, n_xlines, n_samples)``; the arrays use inline as axis 0, crossline as
  axis 1 and the sample (time or depth, downward) as axis 2, whatever the trace order of the file.
* A file without an inline / crossline grid (an unsorted file, an arbitrary line, a 2D line without inline /
  crossline numbers, an irregular survey) is read as a trace list, with one :class:`~seismo3d.errors.TraceListWarning`
  saying what its trace headers show (``ignore_geometry=True`` asks for a trace list and silences it):
  ``cube.shape == (n_traces, n_samples)`` in file order, and ``inlines`` / ``xlines`` are None.

``cube.traces`` gives (n_traces, n_samples) in file order for every file. A 2D line read with geometry (e.g.
``penobscot_xl1155.sgy``, crossline 1155 of Penobscot 3D) keeps its inline and crossline numbers: ``cube.shape`` is
(601, 1, 1501), ``cube.is_3d`` is False and the section is ``cube.xline(1155)`` or ``cube.traces[:]``.
``cube.description`` says in words what was read.

Every file goes through the same steps (:func:`open_segy`): the binary header gives the byte order, the sample
format and the trace layout (:func:`~seismo3d.seismic.io.layout.read_segy_layout`; files segyio cannot read are
refused there, one line each), segyio infers the grid, and the trace headers of a file without one say what it is
(:func:`~seismo3d.seismic.io.geometry.trace_geometry`); prestack gathers are refused.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import segyio

from ..._validation import check_choice
from ...errors import DataNotFoundError, InputError, SegyFormatError, SegyGeometryError, TraceListWarning
from .geometry import TraceGeometry, scale_coordinates, span, trace_geometry
from .layout import SegyLayout, read_segy_layout, segyio_failure

__all__ = ["SeismicCube", "open_segy", "read_segy"]


# Header byte pairs tried (only after a failure) to suggest where the inline / crossline numbers are.
_COMMON_HEADER_BYTES = ((189, 193), (9, 21), (5, 21), (9, 17), (17, 21), (221, 225))

_DEPTH_WORDS = re.compile(r"\b(depth|tvdss|tvd)\b", re.IGNORECASE)
_TIME_WORDS = re.compile(r"\b(time|twt|two[- ]way)\b", re.IGNORECASE)
_EITHER = re.compile(r"time\s*/\s*depth|depth\s*/\s*time", re.IGNORECASE)


def _check_header_byte(value, name: str) -> int:
    valid = set(segyio.TraceField.enums())
    try:
        byte = int(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a trace header byte position (int); got {value!r}") from exc
    if byte != value or byte not in valid:
        raise InputError(
            f"{name}={value!r} is not the first byte of a trace header field; use e.g. {name}="
            f"{189 if name == 'iline' else 193} (SEG-Y rev1 default) or 9 / 21 (common alternatives)"
        )
    return byte


def _guess_sample_unit(text: str, measurement_system: int) -> str:
    """'ms' unless the textual header speaks only of depth (then 'm', or 'ft' for a file in feet)."""
    cleaned = _EITHER.sub(" ", text)
    if _DEPTH_WORDS.search(cleaned) and not _TIME_WORDS.search(cleaned):
        return "ft" if measurement_system == 2 else "m"
    return "ms"


class _TraceView:
    """Lazy (n_traces, n_samples) view of a file's traces in file order; indexing reads only the requested traces."""

    def __init__(self, cube: "SeismicCube"):
        self._cube = cube

    @property
    def shape(self) -> tuple:
        return (self._cube.n_traces, self._cube.samples.size)

    dtype = np.dtype(np.float32)
    ndim = 2

    def __len__(self) -> int:
        return self._cube.n_traces

    def __getitem__(self, key) -> np.ndarray:
        f = self._cube._handle()
        n = self._cube.n_traces
        if isinstance(key, (int, np.integer)):
            i = int(key) + n if key < 0 else int(key)
            if not 0 <= i < n:
                raise IndexError(f"trace {key} is out of range for a file with {n} traces")
            return np.asarray(f.trace[i], dtype=np.float32)
        if isinstance(key, slice):
            start, stop, step = key.indices(n)
            if step == 1:
                if stop <= start:
                    return np.empty((0, self.shape[1]), np.float32)
                return np.asarray(f.trace.raw[start:stop], dtype=np.float32).reshape(stop - start, -1)
            key = np.arange(start, stop, step)
        idx = np.asarray(key)
        if idx.dtype == bool:
            idx = np.flatnonzero(idx)
        if idx.ndim != 1 or idx.dtype.kind not in "iu":
            raise IndexError("index traces with an int, a slice, or a 1D array of ints / bools")
        idx = np.where(idx < 0, idx + n, idx)
        if idx.size and (idx.min() < 0 or idx.max() >= n):
            raise IndexError(f"trace index out of range for a file with {n} traces")
        out = np.empty((idx.size, self.shape[1]), np.float32)
        for k, i in enumerate(idx):
            out[k] = f.trace[int(i)]
        return out

    def __array__(self, dtype=None, copy=None):
        arr = self[:]
        return arr if dtype is None else arr.astype(dtype)

    def __repr__(self) -> str:
        return f"<traces of {self._cube.path.name}: {self.shape[0]} x {self.shape[1]} float32, lazy>"


class SeismicCube:
    """An open SEG-Y file: geometry read from the headers, data read on request.

    Create it with :func:`open_segy`, preferably as a context manager; the file stays open (memory-mapped where the
    platform allows) until :meth:`close`. Geometry attributes stay valid after closing; data access does not.

    Attributes
    ----------
    path : pathlib.Path
        The file.
    inlines : (n_inlines,) int32 ndarray or None
        Inline numbers in array order (None for a trace list).
    xlines : (n_xlines,) int32 ndarray or None
        Crossline numbers in array order (None for a trace list).
    samples : (n_samples,) float64 ndarray
        Sample positions, ``start + i * sample_interval``, in ``sample_unit``. The start is the delay recording
        time (trace bytes 109-110) and the interval the binary header's (bytes 3217-3218) divided by 1000
        (microseconds to ms for time; the same scaling that Petrel, OpendTect and segyio use for depth files).
    sample_interval : float
        In ``sample_unit``.
    sample_unit : {'ms', 'm', 'ft'}
        'ms' for time data. SEG-Y rev 0/1 has no field for the vertical domain, so unless ``sample_unit=`` is given
        to :func:`open_segy` the unit is 'ms' except when the textual header speaks only of depth (then 'm', or 'ft'
        when the binary header's measurement system is feet).
    n_traces : int
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)`` with geometry, ``(n_traces, n_samples)`` for a trace list.
    is_3d : bool
        True for a cube with more than one inline and more than one crossline.
    sorting : {'inline', 'crossline'} or None
        The file's trace order: 'inline' when traces of one inline are consecutive. None for a trace list.
    format : int
        SEG-Y data sample format code (1 IBM float, 2 int32, 3 int16, 5 IEEE float, 8 int8, ...).
    format_name : str
    endian : {'big', 'little'}
        The file's byte order (detected from the binary header unless given to :func:`open_segy`).
    iline_byte, xline_byte : int
        The trace header bytes holding the inline and crossline numbers.
    layout : SegyLayout
        What the binary header says (byte order and how it was decided, sample format, extended textual headers;
        see :func:`~seismo3d.seismic.io.layout.read_segy_layout`).
    description : str
        What the file is, in words: e.g. ``'a 3D cube of 23 inlines (111-133) x 18 crosslines (875-892)'``,
        ``'a 2D line along inlines 1000-1600 (crossline 1155)'``, or for a trace list what its trace headers show
        (``'a 2D or arbitrary line without inline / crossline numbers ...'``).
    """

    def __init__(self, segyfile, path: Path, *, iline: int, xline: int, sample_unit: str, layout: SegyLayout,
                 traces: TraceGeometry | None = None):
        f = segyfile
        self._f = f
        self.path = path
        self.iline_byte = iline
        self.xline_byte = xline
        self.layout = layout
        self.endian = layout.endian
        self.n_traces = int(f.tracecount)
        self.samples = np.asarray(f.samples, dtype=np.float64)
        self.samples.setflags(write=False)
        self.sample_interval = float(self.samples[1] - self.samples[0]) if self.samples.size > 1 else float(
            segyio.tools.dt(f) / 1000.0
        )
        self.sample_unit = sample_unit
        self.format = layout.format
        self.format_name = layout.format_name
        if f.unstructured:
            self.inlines = self.xlines = None
            self.sorting = None
            self.shape = (self.n_traces, self.samples.size)
        else:
            self.inlines = np.asarray(f.ilines, dtype=np.int32)
            self.xlines = np.asarray(f.xlines, dtype=np.int32)
            self.inlines.setflags(write=False)
            self.xlines.setflags(write=False)
            self.sorting = "inline" if f.sorting == segyio.TraceSortingFormat.INLINE_SORTING else "crossline"
            self.shape = (self.inlines.size, self.xlines.size, self.samples.size)
        self.is_3d = self.inlines is not None and self.inlines.size > 1 and self.xlines.size > 1
        self.description = traces.description if traces is not None else self._grid_description()
        self._coords = None

    def _grid_description(self) -> str:
        if self.inlines is None:
            return f"a trace list of {self.n_traces} traces"
        il, xl = self.inlines, self.xlines
        if self.is_3d:
            return f"a 3D cube of {il.size} inlines ({span(il)}) x {xl.size} crosslines ({span(xl)})"
        if il.size == xl.size == 1:
            return f"a single trace (inline {il[0]}, crossline {xl[0]})"
        if xl.size == 1:
            return f"a 2D line along inlines {span(il)} (crossline {xl[0]})"
        return f"a 2D line along crosslines {span(xl)} (inline {il[0]})"

    @property
    def kind(self) -> str:
        """``'3D cube'``, ``'2D line'`` (one inline or one crossline of a grid) or ``'trace list'``."""
        return "trace list" if self.inlines is None else ("3D cube" if self.is_3d else "2D line")

    # -- handle ------------------------------------------------------------------------------------------------
    def _handle(self):
        if self._f is None:
            raise InputError(f"{self.path.name} is closed; reopen it with open_segy() to read data")
        return self._f

    def close(self) -> None:
        """Close the file; geometry attributes remain usable."""
        if self._f is not None:
            self._f.close()
            self._f = None

    def __enter__(self) -> "SeismicCube":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._f is None else "open"
        return (f"<SeismicCube {self.path.name}: {self.kind} {self.shape}, {self.sample_interval:g} "
                f"{self.sample_unit}, {self.format_name}, {self.endian}-endian, {state}>")

    @property
    def is_open(self) -> bool:
        """Whether the file is open (data can be read)."""
        return self._f is not None

    @property
    def segyfile(self):
        """The underlying read-only ``segyio.SegyFile`` (for header fields not exposed here)."""
        return self._handle()

    # -- layout helpers --------------------------------------------------------------------------------------
    def _to_grid(self, per_trace: np.ndarray) -> np.ndarray:
        """Reorder a per-trace array (n_traces, ...) in file order into (n_inlines, n_xlines, ...)."""
        if self.inlines is None:
            return per_trace
        n_il, n_xl = self.inlines.size, self.xlines.size
        rest = per_trace.shape[1:]
        if self.sorting == "inline":
            return per_trace.reshape(n_il, n_xl, *rest)
        return np.ascontiguousarray(np.swapaxes(per_trace.reshape(n_xl, n_il, *rest), 0, 1))

    def _to_traces(self, grid: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`_to_grid`: (n_inlines, n_xlines, ...) to (n_traces, ...) in file order."""
        if self.inlines is None:
            return grid
        rest = grid.shape[2:]
        if self.sorting == "inline":
            return grid.reshape(self.n_traces, *rest)
        return np.ascontiguousarray(np.swapaxes(grid, 0, 1)).reshape(self.n_traces, *rest)

    def require_geometry(self, what: str) -> None:
        """Raise :class:`SegyGeometryError` naming ``what`` (e.g. ``'inline()'``) when the cube was opened as a trace
        list."""
        if self.inlines is None:
            raise SegyGeometryError(
                f"{what} needs inline / crossline geometry, but {self.path.name} was read as a trace list "
                f"({self.description}); use cube.traces"
            )

    # -- data --------------------------------------------------------------------------------------------------
    @property
    def traces(self) -> _TraceView:
        """(n_traces, n_samples) float32 lazy view in file order: ``cube.traces[i]``, ``cube.traces[a:b]``,
        ``cube.traces[:]`` (all). Only the indexed traces are read."""
        self._handle()
        return _TraceView(self)

    def read(self) -> np.ndarray:
        """Read the whole file.

        Returns
        -------
        data : (n_inlines, n_xlines, n_samples) float32 ndarray, or (n_traces, n_samples) for a trace list
            Shape ``cube.shape``. Integer formats are converted to float32 without scaling.
        """
        f = self._handle()
        raw = np.asarray(f.trace.raw[:], dtype=np.float32).reshape(self.n_traces, self.samples.size)
        return self._to_grid(raw)

    def inline(self, number: int) -> np.ndarray:
        """Read one inline.

        Parameters
        ----------
        number : int
            Inline number (as in ``cube.inlines``), not an index.

        Returns
        -------
        section : (n_xlines, n_samples) float32 ndarray
        """
        self.require_geometry("inline()")
        f = self._handle()
        if int(number) not in set(self.inlines.tolist()):
            raise InputError(f"inline {number} is not in {self.path.name}; its inlines are "
                             f"{self.inlines[0]}..{self.inlines[-1]} ({self.inlines.size} lines)")
        return np.asarray(f.iline[int(number)], dtype=np.float32).reshape(self.xlines.size, self.samples.size)

    def xline(self, number: int) -> np.ndarray:
        """Read one crossline.

        Parameters
        ----------
        number : int
            Crossline number (as in ``cube.xlines``), not an index.

        Returns
        -------
        section : (n_inlines, n_samples) float32 ndarray
        """
        self.require_geometry("xline()")
        f = self._handle()
        if int(number) not in set(self.xlines.tolist()):
            raise InputError(f"crossline {number} is not in {self.path.name}; its crosslines are "
                             f"{self.xlines[0]}..{self.xlines[-1]} ({self.xlines.size} lines)")
        return np.asarray(f.xline[int(number)], dtype=np.float32).reshape(self.inlines.size, self.samples.size)

    def time_slice(self, index: int) -> np.ndarray:
        """Read one horizontal slice (time or depth).

        Parameters
        ----------
        index : int
            Sample index, 0 <= index < n_samples (``cube.samples[index]`` is its time / depth).

        Returns
        -------
        slice : (n_inlines, n_xlines) float32 ndarray
        """
        self.require_geometry("time_slice()")
        f = self._handle()
        ns = self.samples.size
        if not isinstance(index, (int, np.integer)) or not 0 <= index < ns:
            raise InputError(f"index={index!r} must be a sample index in 0..{ns - 1}; "
                             "convert a time with np.searchsorted(cube.samples, t)")
        sl = np.asarray(f.depth_slice[int(index)], dtype=np.float32)
        if self.sorting == "inline":
            return sl.reshape(self.inlines.size, self.xlines.size)
        return np.ascontiguousarray(sl.reshape(self.xlines.size, self.inlines.size).T)

    # -- coordinates -------------------------------------------------------------------------------------------
    def _load_coords(self):
        if self._coords is None:
            f = self._handle()
            tf = segyio.TraceField
            scal = np.asarray(f.attributes(tf.SourceGroupScalar)[:])
            result = (None, None)
            for fx, fy in ((tf.CDP_X, tf.CDP_Y), (tf.SourceX, tf.SourceY)):
                x = np.asarray(f.attributes(fx)[:])
                y = np.asarray(f.attributes(fy)[:])
                if np.any(x != 0) or np.any(y != 0):
                    result = (self._to_grid(scale_coordinates(x, scal)), self._to_grid(scale_coordinates(y, scal)))
                    break
            self._coords = result
        return self._coords

    @property
    def cdp_x(self):
        """(n_inlines, n_xlines) float64 ndarray (or (n_traces,) for a trace list) of trace X coordinates with the
        coordinate scalar applied (CDP X, trace bytes 181-184; source X, bytes 73-76, when CDP X is all zero), in the
        survey's unit (``segyfile.bin[segyio.BinField.MeasurementSystem]``: 1 metres, 2 feet); None when absent.
        Read from the headers on first access."""
        return self._load_coords()[0]

    @property
    def cdp_y(self):
        """Like :attr:`cdp_x`, for Y (CDP Y, trace bytes 185-188; source Y, bytes 77-80)."""
        return self._load_coords()[1]


def _grid_elsewhere(path: Path, endian: str, tried: tuple, *, need_3d: bool) -> str | None:
    """The first common header byte pair other than ``tried`` under which segyio finds a post-stack grid (3D when
    ``need_3d``), as ``'iline=9, xline=21 (23 inlines x 18 crosslines)'``; None if there is none."""
    for il, xl in _COMMON_HEADER_BYTES:
        if (il, xl) == tried:
            continue
        try:
            with warnings.catch_warnings(), segyio.open(str(path), "r", iline=il, xline=xl, endian=endian) as f:
                warnings.simplefilter("ignore")
                n_il, n_xl, n_off = len(f.ilines), len(f.xlines), len(f.offsets)
        except (RuntimeError, ValueError, IndexError, OSError, KeyError):
            continue
        if n_off == 1 and ((n_il > 1 and n_xl > 1) if need_3d else (n_il > 1 or n_xl > 1)):
            return f"iline={il}, xline={xl} ({n_il} inlines x {n_xl} crosslines)"
    return None


def _segyio_open(path: Path, layout: SegyLayout, **kwargs):
    """segyio's read-only handle, or SegyFormatError saying why segyio cannot read a file whose layout is valid."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # segyio's own warnings (e.g. unusual headers) are not ours to pass on
            return segyio.open(str(path), "r", endian=layout.endian, **kwargs)
    except PermissionError:
        raise
    except (RuntimeError, ValueError, IndexError, OSError, KeyError) as exc:
        raise SegyFormatError(segyio_failure(layout, path.name)) from exc


def _open_with_geometry(path: Path, layout: SegyLayout, *, iline: int, xline: int, ignore_geometry: bool,
                        given_bytes: bool):
    """(segyio handle, TraceGeometry or None): the file with its inline / crossline grid, else as a trace list
    described by its trace headers; prestack gathers, and a grid that is elsewhere than the given bytes, raise."""
    no_grid = None  # segyio's reason, kept as the cause of our errors
    if not ignore_geometry:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return segyio.open(str(path), "r", iline=iline, xline=xline, endian=layout.endian), None
        except (RuntimeError, ValueError, IndexError, KeyError) as exc:
            no_grid = exc  # no grid at these bytes: read the trace headers below
    f = _segyio_open(path, layout, ignore_geometry=True)
    try:
        traces = trace_geometry(f, iline, xline)
        if ignore_geometry:
            return f, traces
        if traces.prestack:
            raise SegyGeometryError(f"{path.name} holds prestack gathers ({traces.prestack}); seismo3d reads "
                                    "post-stack data: stack it first") from no_grid
        elsewhere = _grid_elsewhere(path, layout.endian, (iline, xline), need_3d=not given_bytes)
        if given_bytes or elsewhere:
            fix = (f"{elsewhere} give one: pass those" if elsewhere else
                   f"read there, it is {traces.description}: pass the bytes of its inline / crossline numbers")
            raise SegyGeometryError(f"{path.name} has no inline / crossline grid at trace header bytes iline={iline}, "
                                    f"xline={xline}; {fix}, or ignore_geometry=True to read a trace list") from no_grid
        warnings.warn(f"{path.name}: no inline / crossline grid at trace header bytes {iline} / {xline}, read as a "
                      f"trace list of {f.tracecount} traces: {traces.description} (ignore_geometry=True: the same "
                      "without this warning)", TraceListWarning, stacklevel=3)
        return f, traces
    except BaseException:
        f.close()
        raise


def _check_post_stack(f, layout: SegyLayout, name: str) -> None:
    """SegyFormatError if segyio disagrees with the binary header; SegyGeometryError for prestack gathers."""
    if f.tracecount != layout.n_traces or len(f.samples) != layout.n_samples:
        raise SegyFormatError(f"segyio reads {f.tracecount} traces of {len(f.samples)} samples from {name} but its "
                              f"binary header and size say {layout.n_traces} of {layout.n_samples}; the file is "
                              "damaged")
    if not f.unstructured and len(f.offsets) > 1:
        raise SegyGeometryError(f"{name} holds prestack gathers ({len(f.offsets)} offsets per inline / crossline "
                                "position); seismo3d reads post-stack data: stack it first")


def open_segy(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False, sample_unit=None,
              endian=None, mmap: bool = True) -> SeismicCube:
    """Open a SEG-Y file for lazy reading: the one way every command reads SEG-Y.

    Only the headers are read here; the file is memory-mapped when possible and read only through
    :meth:`SeismicCube.read`, :meth:`~SeismicCube.inline`, :meth:`~SeismicCube.xline`,
    :meth:`~SeismicCube.time_slice` and :attr:`~SeismicCube.traces`. The file is opened read-only.

    Steps: the binary header gives the byte order, sample format and trace layout
    (:func:`~seismo3d.seismic.io.layout.read_segy_layout`); segyio infers the inline / crossline grid from the
    trace header bytes ``iline`` / ``xline``; a file without one is read as a trace list described by its trace
    headers (:func:`~seismo3d.seismic.io.geometry.trace_geometry`), with one :class:`TraceListWarning`.

    Parameters
    ----------
    path : str or os.PathLike
        SEG-Y file, big- or little-endian (samples in IBM float, IEEE float, int8/16/32/64, uint8/16/32/64).
    iline, xline : int
        Trace header bytes of the inline and crossline numbers: 189 and 193 (SEG-Y rev 1) by default, where a file
        without a grid is read as a trace list. Other bytes are a claim about the file (older files often use 9 / 21
        or 5 / 21): a file without a grid there raises :class:`SegyGeometryError`.
    ignore_geometry : bool
        Read the file as a trace list in file order, without a grid and without the warning (unsorted files,
        arbitrary lines, 2D lines without inline / crossline numbers, irregular surveys; also prestack gathers).
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of the sample axis; overrides the guess from the headers (see :class:`SeismicCube`).
    endian : {'big', 'little'}, optional
        Byte order of the file; by default detected from the binary header (see
        :mod:`~seismo3d.seismic.io.layout`).
    mmap : bool
        Memory-map the file (segyio's ``mmap``, default). False reads it with file reads: for one pass over every
        trace header of a large file, whose mapped pages would otherwise count in the process's resident memory
        until it is closed (reading the coordinates of a 358 MB cube mapped 350 MB).

    Returns
    -------
    cube : SeismicCube
        Use it as a context manager (``with open_segy(p) as cube:``) or call ``cube.close()``.

    Raises
    ------
    DataNotFoundError
        ``path`` does not exist or is not a file.
    SegyFormatError
        The file is not SEG-Y, is cut short, has no traces, or uses something segyio cannot read (sample formats
        4, 7, 15; SEG-Y rev 2 additional trace headers; a variable number of extended textual headers); or
        ``endian`` contradicts the binary header. One line naming the reason.
    SegyGeometryError
        Prestack gathers (stack them first); no grid at ``iline`` / ``xline`` other than 189 / 193; no grid at
        189 / 193 while other common bytes give a 3D grid (the message names them).
    InputError
        Invalid ``iline``, ``xline``, ``sample_unit`` or ``endian``.

    Warns
    -----
    TraceListWarning
        The file has no grid at the default header bytes and is read as a trace list (one line saying what it is).

    Examples
    --------
    >>> with open_segy("f3_crop.sgy") as cube:      # doctest: +SKIP
    ...     print(cube.shape, cube.sample_interval, cube.sample_unit, cube.endian)
    (23, 18, 75) 4.0 ms big
    """
    path = Path(path)
    iline = _check_header_byte(iline, "iline")
    xline = _check_header_byte(xline, "xline")
    given_bytes = (iline, xline) != (189, 193)
    if endian is not None:
        check_choice(endian, "endian", {"big", "little"})
    if sample_unit is not None:
        check_choice(sample_unit, "sample_unit", {"ms", "m", "ft"})
    if not path.is_file():
        raise DataNotFoundError(f"no SEG-Y file at {path}; check the path"
                                + (" (it is a directory)" if path.is_dir() else ""))
    layout = read_segy_layout(path, endian=endian)  # byte order, format, trace layout; unreadable files refused
    f, traces = _open_with_geometry(path, layout, iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                                    given_bytes=given_bytes)
    try:
        _check_post_stack(f, layout, path.name)
        if mmap:
            f.mmap()
        if sample_unit is None:
            text = segyio.tools.wrap(f.text[0]) if f.text[0] else ""
            sample_unit = _guess_sample_unit(text, int(f.bin[segyio.BinField.MeasurementSystem]))
        return SeismicCube(f, path, iline=iline, xline=xline, sample_unit=sample_unit, layout=layout, traces=traces)
    except BaseException:
        f.close()
        raise


def read_segy(path, **kwargs):
    """Read a whole (small) SEG-Y file: a shortcut for ``with open_segy(path, **kwargs) as c: c.read()``.

    Parameters
    ----------
    path : str or os.PathLike
    **kwargs
        Keyword arguments of :func:`open_segy`.

    Returns
    -------
    data : (n_inlines, n_xlines, n_samples) float32 ndarray, or (n_traces, n_samples) for a trace list
    cube : SeismicCube
        Closed; its geometry (including ``cdp_x`` / ``cdp_y``) is loaded.

    Raises
    ------
    See :func:`open_segy`.
    """
    with open_segy(path, **kwargs) as cube:
        data = cube.read()
        cube._load_coords()
    return data, cube
