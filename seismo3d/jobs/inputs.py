"""The jobs' seismic inputs: a SEG-Y cube, line or trace list, a ``.npy`` array, a raw ``.f32be`` section or a Zarr
store of ``seismo3d convert``, opened by :func:`seismo3d.open` (the one place that maps a file to its reader: its
headers read once) and held as a :class:`SeismicInput`: the labelled cube and its file, every other attribute (what
kind, the amplitudes, their geometry and sample interval) read from the cube. A 3D cube is read whole or, when the
caller's ``lazy_if`` says so from its shape (the memory decision of a fault run), kept as a lazy dask array.

:func:`input_kind` names every job input by its file (seismic files by :func:`seismo3d.seismic.io.cube.seismic_kind`,
point clouds and terrain files here), so that ``faults``, ``horizon`` and ``render`` do not each work it out their own
way.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from ..seismic.io.cube import SEGY_SUFFIXES, open_cube, seismic_axes, seismic_kind

__all__ = ["SEGY_SUFFIXES", "SeismicInput", "input_kind", "read_seismic", "seismic_input"]

_TERRAIN_SUFFIXES = (".las", ".laz", ".tif", ".tiff")
_CLOUD_SUFFIXES = (".ply", ".xyz", ".txt", ".csv", ".pts", ".npy")


def input_kind(path) -> str:
    """What a job's input file is, by its name: one rule for every command.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    {'segy', 'zarr', 'f32be', 'npy', 'terrain', 'points', 'folder', 'unknown'}
        ``'segy'``: .sgy / .segy; ``'zarr'``: a .zarr store; ``'f32be'``: a raw big-endian float32 section;
        ``'terrain'``: LAS/LAZ scans and GeoTIFF DEMs; ``'points'``: point-cloud files (.ply, .xyz, .txt, .csv,
        .pts); ``'npy'``: a numpy array (a seismic array or a point cloud, as the command reads it); ``'folder'``:
        another folder (the output folder of a command).
    """
    path = Path(path)
    kind = seismic_kind(path)  # the seismic files: the rule of seismo3d.open
    if kind in ("segy", "zarr"):
        return kind
    if path.is_dir():
        return "folder"
    if kind is not None:
        return kind
    suffix = path.suffix.lower()
    if suffix in _TERRAIN_SUFFIXES:
        return "terrain"
    if suffix in _CLOUD_SUFFIXES:
        return "points"
    return "unknown"


@dataclass(frozen=True, eq=False)
class SeismicInput:
    """A seismic input as a job reads it: the cube of :func:`seismo3d.open` and its file. The cube is the one record of
    the input: every other attribute is read from it (its ``kind``, ``description``, ``segy_*`` and ``xy_unit``
    attributes, its dimensions and coordinates), none is kept beside it.

    Attributes
    ----------
    cube : xarray.DataArray
        The input as :func:`seismo3d.open` labels it (a line with its one lateral dimension), read whole (numpy) or
        lazy (dask, chunks of ``tile`` x ``tile`` whole traces).
    path : pathlib.Path
        The source file.
    kind : {'cube', 'line', 'trace list', 'array', 'section', 'store'}
        A SEG-Y 3D cube, a SEG-Y line of a survey (one inline or one crossline), a SEG-Y file read as a trace
        list (no inline / crossline grid, or ``ignore_geometry``), a ``.npy`` array, a raw ``.f32be`` section, a
        Zarr store of ``seismo3d convert`` (the cube's ``kind`` attribute).
    data : ndarray or dask.array.Array
        The cube's data, a line's as (n_inlines, n_xlines, n_samples) with one of the first two 1: float32 for
        SEG-Y and raw sections, (n_traces, n_samples) for a trace list and a raw section; a ``.npy`` array as stored
        (2D or 3D); with :attr:`lazy` a (n_inlines, n_xlines, n_samples) float32 dask array.
    samples : (n_samples,) float64 ndarray
        Sample positions in ``sample_unit`` (the cube's sample coordinate; the sample index for ``.npy`` and
        ``.f32be``).
    sample_unit : {'ms', 'm', 'ft', 'samples'}
    inlines, xlines : ndarray or None
        The grid's inline and crossline numbers (SEG-Y cubes and lines, stores); None otherwise.
    description : str
        In words, what was read (SEG-Y: :attr:`~seismo3d.seismic.io.SeismicCube.description`).
    grid_shape : tuple or None
        The grid's shape ``(n_inlines, n_xlines, n_samples)``; None for a trace list and other files.
    sorting : {'inline', 'crossline'} or None
        Trace order of a SEG-Y grid.
    trace_inlines, trace_xlines : ndarray or None
        A trace list's inline and crossline header values per trace (at the ``iline`` / ``xline`` bytes; zeros
        when the file has none there).
    cdp_x, cdp_y : ndarray or None
        SEG-Y trace coordinates (the cube's ``cdp_x`` / ``cdp_y``; a line's on its grid, (n_inlines, n_xlines)).
    map_unit : {'m', 'ft'}
        Unit of ``cdp_x`` / ``cdp_y`` (binary header bytes 3255-3256).
    format_name, endian : str or None
        SEG-Y sample format and byte order.
    lazy : bool
        ``data`` is a lazy dask array (read block by block), not the samples in memory.
    """

    cube: object
    path: Path

    @property
    def kind(self) -> str:
        return self.cube.attrs["kind"]

    @property
    def lazy(self) -> bool:
        return not isinstance(self.cube.data, np.ndarray)

    @property
    def description(self) -> str:
        return self.cube.attrs.get("description", "")

    @property
    def format_name(self) -> str | None:
        return self.cube.attrs.get("segy_format")

    @property
    def endian(self) -> str | None:
        return self.cube.attrs.get("segy_endian")

    @property
    def map_unit(self) -> str:
        return self.cube.attrs.get("xy_unit", "m")

    @cached_property
    def _axes(self):
        return seismic_axes(self.cube)

    @property
    def sample_unit(self) -> str:
        return self._axes.sample_unit

    @cached_property
    def samples(self) -> np.ndarray:
        return np.asarray(self.cube.coords[self._axes.sample].values, dtype=np.float64)

    @property
    def _gridded(self) -> bool:
        """A grid of inlines and crosslines: a SEG-Y cube or line, a store."""
        return self.kind not in ("array", "section", "trace list")

    @cached_property
    def inlines(self) -> np.ndarray | None:
        return np.atleast_1d(np.asarray(self.cube.coords["iline"].values)) if self._gridded else None

    @cached_property
    def xlines(self) -> np.ndarray | None:
        return np.atleast_1d(np.asarray(self.cube.coords["xline"].values)) if self._gridded else None

    @property
    def grid_shape(self) -> tuple | None:
        return (self.inlines.size, self.xlines.size, self.samples.size) if self._gridded else None

    @property
    def sorting(self) -> str | None:
        return (self.cube.attrs.get("segy_sorting") or None) if self._gridded else None

    @property
    def data(self):
        data = self.cube.data
        return data.reshape(self.grid_shape) if self._gridded and self.cube.ndim == 2 else data

    def _trace_numbers(self, name: str) -> np.ndarray | None:
        """A trace list's header values at the ``iline`` / ``xline`` bytes, per trace (zeros where it has none)."""
        if self.kind != "trace list":
            return None
        coord = self.cube.coords.get(name)
        if coord is not None and coord.dims == ("trace",):
            return np.asarray(coord.values)
        return np.zeros(self.cube.shape[0], np.int64)

    @property
    def trace_inlines(self) -> np.ndarray | None:
        return self._trace_numbers("iline")

    @property
    def trace_xlines(self) -> np.ndarray | None:
        return self._trace_numbers("xline")

    def _map(self, name: str) -> np.ndarray | None:
        if name not in self.cube.coords:
            return None
        values = np.asarray(self.cube.coords[name].values)
        return values.reshape(self.grid_shape[:2]) if self._gridded and self.cube.ndim == 2 else values

    @property
    def cdp_x(self) -> np.ndarray | None:
        return self._map("cdp_x")

    @property
    def cdp_y(self) -> np.ndarray | None:
        return self._map("cdp_y")

    @property
    def sample_interval(self) -> float:
        """Sample step in :attr:`sample_unit` (1 for one sample)."""
        return float(self.samples[1] - self.samples[0]) if self.samples.size > 1 else 1.0

    @property
    def is_segy(self) -> bool:
        return self.kind in ("cube", "line", "trace list")

    # how the traces are named in the outputs of the faults job (its tables, sticks, surfaces and picture)

    @property
    def name(self) -> str:
        """The input's name in messages, outputs and stores: the file's stem (a store's name before its first dot)."""
        return self.path.name.split(".")[0] if self.kind == "store" else self.path.stem

    @property
    def amplitudes(self):
        """The amplitudes as :func:`seismo3d.open` labels them (:attr:`cube`'s data): (n_inlines, n_xlines,
        n_samples) for a cube, a store or a 3D array (a dask array with :attr:`lazy`), (n_traces, n_samples) for a
        line, a trace list, a raw section or a 2D array."""
        return self.cube.data

    @property
    def segy_path(self) -> Path | None:
        """The SEG-Y file (the template of SEG-Y outputs); None for other inputs."""
        return self.path if self.is_segy else None

    @property
    def segy_shape(self) -> tuple | None:
        """The SEG-Y grid's shape of a cube or a line (to write 2D results back into); None otherwise."""
        return self.grid_shape if self.kind in ("cube", "line") else None

    @property
    def trace_axis(self) -> str:
        """What labels the traces of a 2D input in pictures: 'inline' or 'crossline' for a line of a survey,
        'trace' otherwise."""
        if self.kind != "line":
            return "trace"
        return "inline" if self.grid_shape[1] == 1 else "crossline"

    @property
    def inline_labels(self) -> np.ndarray:
        """(n,) int64: the inline number of each inline (3D) or of each trace (2D); a trace list's without numbers:
        its trace number, from 1 in file order (:func:`seismo3d.open`'s ``trace`` coordinate); a raw section's or an
        array's: the trace index, from 0."""
        return self._trace_labels[0]

    @property
    def xline_labels(self) -> np.ndarray | None:
        """(n,) int64: the crossline number of each crossline (3D) or of each trace (2D); None for a raw section, a
        2D array or a trace list without numbers."""
        return self._trace_labels[1]

    @cached_property
    def _trace_labels(self) -> tuple:
        if self.kind == "trace list":  # its header inline / crossline numbers, if any
            il, xl = self.trace_inlines.astype(np.int64), self.trace_xlines.astype(np.int64)
            if np.all(il == il[0]) and np.all(xl == xl[0]):  # no numbers there: seismo3d.open's trace number
                return self.cube["trace"].values.astype(np.int64), None
            return il, xl
        if not self.is_segy and self.kind != "store":  # .npy, .f32be: the indices
            idx = [np.arange(n, dtype=np.int64) for n in self.amplitudes.shape]
            return idx[0], idx[1] if len(idx) == 3 else None
        il, xl = self.inlines.astype(np.int64), self.xlines.astype(np.int64)
        if self.trace_axis == "inline":  # a line along the inlines (one crossline), e.g. penobscot_xl1155
            return il, np.full(il.size, xl[0])
        if self.trace_axis == "crossline":
            return np.full(xl.size, il[0]), xl
        return il, xl

    @property
    def coords(self) -> dict:
        """Coordinates of a run by blocks' Zarr stores (``BlockRunOptions.coords``)."""
        return {"inline": self.inline_labels, "crossline": self.xline_labels, "sample": self.samples,
                "sample_unit": self.sample_unit}

    def file_order(self, values: np.ndarray) -> np.ndarray:
        """(n_traces, n_samples) of an array shaped like :attr:`amplitudes`, in the SEG-Y file's trace order."""
        ns = values.shape[-1]
        if self.segy_shape is None:  # trace list: already in file order (contiguous float32 for segyio)
            return np.ascontiguousarray(values.reshape(-1, ns), dtype=np.float32)
        grid = values.reshape(self.segy_shape)
        if self.sorting == "crossline":
            grid = np.swapaxes(grid, 0, 1)
        return np.ascontiguousarray(grid, dtype=np.float32).reshape(-1, ns)

    @property
    def axes(self) -> tuple:
        """Annotation of each axis of :attr:`amplitudes`: (inlines, crosslines, samples) in 3D, (trace labels,
        samples) in 2D."""
        if self.amplitudes.ndim == 3:
            return (self.inline_labels, self.xline_labels, self.samples)
        lateral = {"inline": self.inline_labels, "crossline": self.xline_labels,
                   "trace": self.inline_labels if self.kind == "trace list" else None}.get(self.trace_axis)
        return (np.arange(self.amplitudes.shape[0]) if lateral is None else lateral, self.samples)

    @property
    def axis_titles(self) -> tuple:
        """Axis names for pictures."""
        vertical = {"samples": "sample", "ms": "time (ms)", "m": "depth (m)", "ft": "depth (ft)"}[self.sample_unit]
        if self.amplitudes.ndim == 3:
            return ("inline", "crossline", vertical)
        return (self.trace_axis, vertical)


def read_seismic(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False, endian=None,
                 sample_unit=None, n_samples: int | None = None, arrays: bool = True, lazy_if=None,
                 tile: int = 32) -> SeismicInput:
    """Read a seismic input through :func:`seismo3d.open` (one opening of its headers): a SEG-Y file, a ``.npy``
    array, a raw ``.f32be`` section, or (with ``lazy_if``) a Zarr store of ``seismo3d convert``; a 3D cube whole or
    lazily, as ``lazy_if`` decides.

    Parameters
    ----------
    path : str or os.PathLike
    iline, xline, ignore_geometry, endian, sample_unit
        SEG-Y: as :func:`~seismo3d.seismic.io.open_segy`. ``sample_unit`` is refused for ``.npy`` and ``.f32be``
        (they have no sample interval).
    n_samples : int, optional
        Samples per trace of a raw ``.f32be`` section whose shape is not known by name.
    arrays : bool
        Read ``.npy`` and ``.f32be`` files as arrays; False for a command that reads SEG-Y only (every file is then
        opened as SEG-Y, whose error says what the file is not).
    lazy_if : callable, optional
        ``lazy_if(shape) -> bool``, asked once with the shape ``(n_inlines, n_xlines, n_samples)`` of a 3D cube
        (a SEG-Y cube, a 3D ``.npy`` array, a Zarr store) before its samples are read: True gives a lazy
        :attr:`SeismicInput.data`. Without it every input is read whole and Zarr stores are refused.
    tile : int
        Traces a side of the chunks of a lazy cube (a block of a run by blocks reads only the tiles around it).

    Returns
    -------
    SeismicInput

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        A ``.npy`` file numpy cannot read, or not 2D / 3D; ``sample_unit`` for a file without a sample interval; a
        raw section of unknown shape.
    SegyFormatError, SegyGeometryError
        As :func:`~seismo3d.seismic.io.open_segy`.

    Warns
    -----
    TraceListWarning
        A SEG-Y file without an inline / crossline grid, read as a trace list (one line).
    """
    path = Path(path)
    kind = input_kind(path)
    fmt = kind if (kind in ("npy", "f32be") and arrays) or (kind == "zarr" and lazy_if is not None) else "segy"
    cube = open_cube(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian,
                     sample_unit=sample_unit, n_samples=n_samples, tile=tile, format=fmt)
    return seismic_input(cube, path, lazy_if=lazy_if)


def seismic_input(cube, path, *, lazy_if=None) -> SeismicInput:
    """A cube of :func:`seismo3d.open` as a :class:`SeismicInput`: read whole, or kept lazy when ``lazy_if(shape)``
    says so for a 3D cube (see :func:`read_seismic`)."""
    lazy = (lazy_if is not None and cube.ndim == 3 and cube.attrs["kind"] in ("cube", "store", "array")
            and bool(lazy_if(tuple(int(n) for n in cube.shape))))
    if not lazy:  # read whole, once, by dask's threaded scheduler (its default for arrays) given as a function:
        # without one, or with its name, dask imports dask.distributed to look for a client (0.2 s of every command)
        data = cube.data
        if hasattr(data, "dask"):
            import dask.threaded

            data = data.compute(scheduler=dask.threaded.get)
        cube = cube.copy(data=np.asarray(data))
    return SeismicInput(cube, Path(path))
