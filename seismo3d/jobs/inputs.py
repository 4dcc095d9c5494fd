"""The one reader of the jobs' seismic inputs: a SEG-Y cube, line or trace list, a ``.npy`` array, a raw ``.f32be``
section or a Zarr store of ``seismo3d convert``, as a :class:`SeismicInput` (what kind, the amplitudes, their
geometry and sample interval, the source path). A 3D cube is read whole or, when the caller's ``lazy_if`` says so from
its shape (the memory decision of a fault run), as a lazy dask array: either way from one opening of the file.

SEG-Y is opened by :func:`~seismo3d.seismic.io.open_segy` (the flags, errors and warnings of every command) and raw
sections by :func:`~seismo3d.seismic.io.read_section`; this module only chooses the reader by the file's kind
(:func:`input_kind`, also used for point clouds and terrain files) and gathers what the jobs need into one object,
so that ``faults``, ``horizon`` and ``render`` do not each work it out their own way.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DataNotFoundError, InputError
from ..seismic.io.sections import known_section_shape, read_section
from ..seismic.io.segy import open_segy

__all__ = ["SEGY_SUFFIXES", "SeismicInput", "input_kind", "read_seismic"]

SEGY_SUFFIXES = (".sgy", ".segy")
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
    suffix = path.suffix.lower()
    if suffix in SEGY_SUFFIXES:
        return "segy"
    if suffix == ".zarr":
        return "zarr"
    if path.is_dir():
        return "folder"
    if suffix == ".f32be":
        return "f32be"
    if suffix == ".npy":
        return "npy"
    if suffix in _TERRAIN_SUFFIXES:
        return "terrain"
    if suffix in _CLOUD_SUFFIXES:
        return "points"
    return "unknown"


@dataclass(frozen=True, eq=False)
class SeismicInput:
    """A seismic input as read: the amplitudes and how their traces and samples are named.

    Attributes
    ----------
    kind : {'cube', 'line', 'trace list', 'array', 'section', 'store'}
        A SEG-Y 3D cube, a SEG-Y line of a survey (one inline or one crossline), a SEG-Y file read as a trace
        list (no inline / crossline grid, or ``ignore_geometry``), a ``.npy`` array, a raw ``.f32be`` section, a
        Zarr store of ``seismo3d convert``.
    path : pathlib.Path
        The source file.
    data : ndarray or dask.array.Array
        float32 for SEG-Y and raw sections: (n_inlines, n_xlines, n_samples) for a cube or a line (one of the first
        two 1), (n_traces, n_samples) for a trace list and a raw section; a ``.npy`` array as stored (2D or 3D,
        memory-mapped). With ``lazy`` a (n_inlines, n_xlines, n_samples) float32 dask array, chunks of
        ``tile`` x ``tile`` whole traces.
    samples : (n_samples,) float64 ndarray
        Sample positions in ``sample_unit`` (the sample index for ``.npy`` and ``.f32be``).
    sample_unit : {'ms', 'm', 'ft', 'samples'}
    inlines, xlines : ndarray or None
        The grid's inline and crossline numbers (SEG-Y cubes and lines); None otherwise.
    description : str
        In words, what was read (SEG-Y: :attr:`~seismo3d.seismic.io.SeismicCube.description`).
    grid_shape : tuple or None
        The SEG-Y grid's shape ``(n_inlines, n_xlines, n_samples)``; None for a trace list and other files.
    sorting : {'inline', 'crossline'} or None
        Trace order of a SEG-Y grid.
    trace_inlines, trace_xlines : ndarray or None
        A trace list's inline and crossline header values per trace (at the ``iline`` / ``xline`` bytes).
    cdp_x, cdp_y : ndarray or None
        SEG-Y trace coordinates (with ``coordinates=True``), as
        :attr:`~seismo3d.seismic.io.SeismicCube.cdp_x`.
    map_unit : {'m', 'ft'}
        Unit of ``cdp_x`` / ``cdp_y`` (binary header bytes 3255-3256).
    format_name, endian : str or None
        SEG-Y sample format and byte order.
    lazy : bool
        ``data`` is a lazy dask array (read block by block), not the samples in memory.
    """

    kind: str
    path: Path
    data: np.ndarray
    samples: np.ndarray
    sample_unit: str
    inlines: np.ndarray | None = None
    xlines: np.ndarray | None = None
    description: str = ""
    grid_shape: tuple | None = None
    sorting: str | None = None
    trace_inlines: np.ndarray | None = None
    trace_xlines: np.ndarray | None = None
    cdp_x: np.ndarray | None = None
    cdp_y: np.ndarray | None = None
    map_unit: str = "m"
    format_name: str | None = None
    endian: str | None = None
    lazy: bool = False

    @property
    def sample_interval(self) -> float:
        """Sample step in :attr:`sample_unit` (1 for one sample)."""
        return float(self.samples[1] - self.samples[0]) if self.samples.size > 1 else 1.0

    @property
    def is_segy(self) -> bool:
        return self.kind in ("cube", "line", "trace list")


def read_seismic(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False, endian=None,
                 sample_unit=None, n_samples: int | None = None, coordinates: bool = False,
                 arrays: bool = True, lazy_if=None, tile: int = 32) -> SeismicInput:
    """Read a seismic input, opening it once: a SEG-Y file, a ``.npy`` array, a raw ``.f32be`` section, or (with
    ``lazy_if``) a Zarr store of ``seismo3d convert``; a 3D cube whole or lazily, as ``lazy_if`` decides.

    Parameters
    ----------
    path : str or os.PathLike
    iline, xline, ignore_geometry, endian, sample_unit
        SEG-Y: as :func:`~seismo3d.seismic.io.open_segy`. ``sample_unit`` is refused for ``.npy`` and ``.f32be``
        (they have no sample interval).
    n_samples : int, optional
        Samples per trace of a raw ``.f32be`` section whose shape is not known by name.
    coordinates : bool
        SEG-Y: also read the trace coordinates (``cdp_x``, ``cdp_y``; one pass over the trace headers).
    arrays : bool
        Read ``.npy`` and ``.f32be`` files as arrays; False for a command that reads SEG-Y only (every file is then
        opened as SEG-Y, whose error says what the file is not).
    lazy_if : callable, optional
        ``lazy_if(shape) -> bool``, asked once with the shape ``(n_inlines, n_xlines, n_samples)`` of a 3D cube
        (a SEG-Y cube, a 3D ``.npy`` array, a Zarr store) before its samples are read: True gives a lazy
        :attr:`SeismicInput.data` (e.g. ``lambda shape: not BlockRunOptions(...).in_memory_for(shape)``). Without
        it every input is read whole and Zarr stores are refused.
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
    if lazy_if is not None and kind == "zarr" and path.is_dir():
        return _read_store(path, sample_unit=sample_unit, lazy_if=lazy_if, tile=tile)
    if arrays and kind in ("npy", "f32be"):
        return _read_array(path, kind, sample_unit=sample_unit, n_samples=n_samples, lazy_if=lazy_if, tile=tile)
    with open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit,
                   endian=endian) as cube:
        lazy = (lazy_if is not None and cube.is_3d and cube.inlines is not None
                and bool(lazy_if(tuple(int(n) for n in cube.shape))))
        fields = dict(path=path, data=_lazy_segy(cube, tile) if lazy else cube.read(),
                      samples=np.asarray(cube.samples, dtype=np.float64), sample_unit=cube.sample_unit,
                      description=cube.description, format_name=cube.format_name, endian=cube.endian, lazy=lazy)
        if coordinates:
            fields.update(cdp_x=cube.cdp_x, cdp_y=cube.cdp_y,
                          map_unit="ft" if int(cube.segyfile.bin[3255]) == 2 else "m")
        if cube.inlines is None:  # a trace list (announced by open_segy's warning unless ignore_geometry)
            f = cube.segyfile
            return SeismicInput(kind="trace list", trace_inlines=np.asarray(f.attributes(cube.iline_byte)[:]),
                                trace_xlines=np.asarray(f.attributes(cube.xline_byte)[:]), **fields)
        return SeismicInput(kind="cube" if cube.is_3d else "line", inlines=np.asarray(cube.inlines),
                            xlines=np.asarray(cube.xlines), grid_shape=tuple(cube.shape), sorting=cube.sorting,
                            **fields)


def _lazy_segy(cube, tile: int):
    """The open SEG-Y cube's amplitudes as a float32 dask array of ``tile`` x ``tile`` whole traces."""
    from ..seismic.io.lazy import lazy_segy_cube

    return lazy_segy_cube(cube, tile=tile).data


def _read_store(path: Path, *, sample_unit, lazy_if, tile: int) -> SeismicInput:
    """A Zarr store of ``seismo3d convert``: lazily or read whole, as ``lazy_if`` decides from its shape."""
    from ..seismic.io.lazy import open_lazy

    store = open_lazy(path, sample_unit=sample_unit, tile=tile)
    lazy = bool(lazy_if(store.shape))
    shape = " x ".join(str(n) for n in store.shape)
    return SeismicInput(kind="store", path=path, data=store.data if lazy else store.data.compute(),
                        samples=np.asarray(store.samples, dtype=np.float64), sample_unit=store.sample_unit,
                        inlines=np.asarray(store.inlines), xlines=np.asarray(store.xlines),
                        description=f"a Zarr store of {shape} samples", grid_shape=store.shape, lazy=lazy)


def _read_array(path: Path, kind: str, *, sample_unit, n_samples, lazy_if=None, tile: int = 32) -> SeismicInput:
    """A ``.npy`` array (memory-mapped, or a lazy dask array as ``lazy_if`` decides for a 3D one) or a raw
    ``.f32be`` section, in samples."""
    if not path.is_file():
        raise DataNotFoundError(f"no input file at {path}; check the path")
    if kind == "f32be":
        if n_samples is None and known_section_shape(path) is None:  # a raw file says nothing of its shape
            n_values = path.stat().st_size // 4
            raise InputError(f"the shape of {path.name} is unknown (a raw section of {n_values} float32 values, "
                             "no header); give its number of samples per trace: n_samples=N")
        data = read_section(path, n_samples=n_samples)
    else:
        try:
            data = np.load(path, allow_pickle=False, mmap_mode="r")
        except (ValueError, OSError) as exc:
            raise InputError(f"{path.name} is not a readable .npy array ({exc}); save it with numpy.save") from exc
        if data.ndim not in (2, 3):
            raise InputError(f"{path.name} holds an array of shape {data.shape}; expected a 2D section "
                             "(n_traces, n_samples) or a 3D cube (n_inlines, n_xlines, n_samples)")
    if sample_unit is not None:
        raise InputError(f"{path.name} has no sample interval, so --sample-unit cannot be used; its results are "
                         "in samples")
    shape = " x ".join(str(n) for n in data.shape)
    lazy = lazy_if is not None and data.ndim == 3 and bool(lazy_if(tuple(int(n) for n in data.shape)))
    if lazy:
        import dask.array as da

        data = da.from_array(data, chunks=(tile, tile, -1)).astype(np.float32)
    return SeismicInput(kind="section" if kind == "f32be" else "array", path=path, data=data,
                        samples=np.arange(data.shape[-1], dtype=np.float64), sample_unit="samples",
                        description=f"{'a raw section' if kind == 'f32be' else 'an array'} of {shape} samples",
                        lazy=lazy)
