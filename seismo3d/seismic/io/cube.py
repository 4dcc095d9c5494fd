"""The one cube type of seismo3d and the one place that opens a seismic input as one: :func:`open_cube`
(``seismo3d.open``).

A seismic cube or line is an ``xarray.DataArray`` with segysak's conventions:

- dimensions ``('iline', 'xline', 'twt')`` for a 3D cube in time (``'depth'`` for a cube in depth, ``'samples'``
  for an input without a sample interval: ``.npy`` arrays and raw sections); a 2D line has one lateral dimension:
  ``'iline'`` or ``'xline'`` for a line of a survey (the other line number a scalar coordinate), ``'trace'`` for a
  trace list, a raw section or a 2D array;
- coordinates of the same names (inline and crossline numbers, times or depths with a ``units`` attribute) and
  ``cdp_x``, ``cdp_y`` on the lateral dimensions when the trace headers hold them (the coordinate scalar applied);
  a trace list's ``trace`` coordinate is each trace's number in file order, from 1, as every command numbers it
  (``seismo3d horizon --seed TRACE,T`` and its rows, the pictures of ``seismo3d render``), with its header inline
  and crossline numbers as ``iline`` / ``xline`` on it when they vary; a ``.npy`` array's or raw section's lateral
  coordinates are its indices, from 0 (it has no numbers of its own);
- attributes: ``sample_interval`` and ``sample_unit`` ('ms', 'm', 'ft' or 'samples'; segysak's ``sample_rate`` and
  ``d3_domain`` too), ``source_file``, ``kind`` ('cube', 'line', 'trace list', 'array', 'section', 'store'),
  ``description`` and, for SEG-Y, the layout found (``segy_format``, ``segy_endian``, ``segy_sorting``,
  ``iline_byte``, ``xline_byte``) and the unit of X / Y (``xy_unit``, ``xy_source``, ``xy_resolution``).

Files are opened lazily: the amplitudes are a dask array of tiles of whole traces, each task opening the file
read-only itself (a SEG-Y through :func:`~seismo3d.seismic.io.blocks.read_segy_block`, a Zarr store of ``seismo3d
convert`` through ``xarray.open_zarr``, a ``.npy`` array through its memory map), so the same graph runs on a
``dask.distributed`` cluster. Only the headers are read here, once. A segysak Dataset's variable (a DataArray with
these dimensions) is taken as it is by every seismic function (:func:`seismic_axes`).

References
----------
segysak (T. Hallam), https://segysak.readthedocs.io: ``xr.open_dataset(path, engine='sgy')``, dimensions ``iline``,
``xline``, ``twt`` / ``depth``, ``cdp``, coordinates ``cdp_x`` / ``cdp_y``. xarray, https://docs.xarray.dev.
"""

from __future__ import annotations

import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import DataNotFoundError, InputError, Seismo3dWarning

__all__ = ["SEGY_SUFFIXES", "CubeAxes", "as_cube", "grid_spacing", "index_positions", "is_data_array", "line_values",
           "on_lateral", "open_cube", "reader_kind", "sample_dim", "sample_interval", "sample_positions", "samples_at",
           "seismic_axes", "seismic_kind"]

SEGY_SUFFIXES = (".sgy", ".segy")
_ALIASES = {"inline": ("inline", "iline", "il", "inline_3d"), "crossline": ("crossline", "xline", "xl", "crossline_3d"),
            "sample": ("sample", "samples", "twt", "time", "depth", "z"), "trace": ("trace", "cdp", "traces")}
_UNIT_OF_DIM = {"twt": "ms", "time": "ms", "depth": "m"}
_SAMPLE_DIMS = {"ms": "twt", "m": "depth", "ft": "depth", "samples": "samples"}
_DOMAINS = {"ms": "TWT", "m": "DEPTH", "ft": "DEPTH", "samples": "SAMPLES"}
DEFAULT_TILE = 64  # traces a side of a chunk (as the Zarr store of seismo3d convert)


def _xarray():
    import xarray as xr  # on first use: a dependency, kept out of the command line's import time

    return xr


def seismic_kind(path) -> str | None:
    """What kind of seismic file ``path`` is, by its name: the one rule of every command.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    {'segy', 'zarr', 'f32be', 'npy'} or None
        ``'segy'``: .sgy / .segy; ``'zarr'``: a .zarr store; ``'f32be'``: a raw big-endian float32 section;
        ``'npy'``: a numpy array; None otherwise.
    """
    suffix = Path(path).suffix.lower()
    if suffix in SEGY_SUFFIXES:
        return "segy"
    return {".zarr": "zarr", ".f32be": "f32be", ".npy": "npy"}.get(suffix)


def reader_kind(path, format: str | None = None) -> str:
    """The reader :func:`open_cube` (``seismo3d.open``) opens ``path`` with: the one decision of an input's kind.

    Parameters
    ----------
    path : str or os.PathLike
    format : {'segy', 'zarr', 'npy', 'f32be'}, optional
        The kind given by the caller, which wins over the name.

    Returns
    -------
    {'segy', 'zarr', 'npy', 'f32be'}
        ``format``, else the kind by name (:func:`seismic_kind`), else ``'zarr'`` for another folder (refused by the
        store's reader when it is not one, saying how to make one) and ``'segy'`` for another file (whose reader's
        error then says what the file is not).

    Raises
    ------
    InputError
        ``format`` is not one of the four.
    """
    from ..._validation import check_choice

    path = Path(path)
    kind = format or seismic_kind(path) or ("zarr" if path.is_dir() else "segy")
    check_choice(kind, "format", {"segy", "zarr", "npy", "f32be"})
    return kind


def sample_dim(unit: str) -> str:
    """The sample dimension's name for a sample unit: 'twt' (ms), 'depth' (m, ft) or 'samples'."""
    return _SAMPLE_DIMS[unit]


def open_cube(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False, endian=None,
              sample_unit=None, n_samples: int | None = None, tile: int = DEFAULT_TILE, format: str | None = None):
    """Open a seismic input as a lazy, labelled cube: a SEG-Y cube, line or trace list, a Zarr store of ``seismo3d
    convert``, a ``.npy`` array or a raw ``.f32be`` section (``seismo3d.open``).

    Only the headers are read (once: the SEG-Y geometry, CDP X/Y and layout in one opening); the amplitudes are a
    dask array read tile by tile when computed (``cube.values``, ``cube.load()``).

    Parameters
    ----------
    path : str or os.PathLike
    iline, xline : int
        SEG-Y: trace header bytes of the inline and crossline numbers (:func:`~seismo3d.seismic.io.open_segy`).
    ignore_geometry : bool
        SEG-Y: read the file as a trace list (dimension ``trace``) without the warning a file without a grid gets.
    endian : {'big', 'little'}, optional
        SEG-Y: byte order; by default detected from the binary header.
    sample_unit : {'ms', 'm', 'ft'}, optional
        SEG-Y and Zarr: the unit of the sample axis, instead of the one the headers suggest. Refused for ``.npy`` and
        ``.f32be`` (they have no sample interval).
    n_samples : int, optional
        Samples per trace of a raw ``.f32be`` section whose shape is not known by name.
    tile : int
        Traces a side of the dask chunks (every sample of a trace in one chunk): a block of a run by blocks reads
        only the tiles around it.
    format : {'segy', 'zarr', 'npy', 'f32be'}, optional
        The kind of file; by default from its name (:func:`seismic_kind`; any other name is opened as SEG-Y, whose
        error then says what the file is not).

    Returns
    -------
    xarray.DataArray
        float32 (a ``.npy`` array keeps its dtype), dask-backed, named ``'seismic'``, dims, coordinates and
        attributes as the module docstring says: ``('iline', 'xline', 'twt' | 'depth' | 'samples')`` for a cube,
        ``('iline' | 'xline' | 'trace', ...)`` for a line.

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        A ``.npy`` file numpy cannot read, or not 2D / 3D; ``sample_unit`` for a file without a sample interval; a
        raw section of unknown shape; a folder that is not a store of ``seismo3d convert``.
    SegyFormatError, SegyGeometryError
        As :func:`~seismo3d.seismic.io.open_segy`.

    Warns
    -----
    TraceListWarning
        A SEG-Y file without an inline / crossline grid, read as a trace list (one line).

    Examples
    --------
    >>> import seismo3d
    >>> cube = seismo3d.open("f3_crop.sgy")            # doctest: +SKIP
    >>> cube.dims, cube.attrs["sample_interval"]        # doctest: +SKIP
    (('iline', 'xline', 'twt'), 4.0)
    """
    from ..._validation import check_choice, check_int

    path = Path(path)
    check_int(tile, "tile", minimum=1)
    if sample_unit is not None:
        check_choice(sample_unit, "sample_unit", {"ms", "m", "ft"})
    kind = reader_kind(path, format)
    if kind == "zarr":
        return _open_store(path, sample_unit=sample_unit, tile=tile)
    if kind in ("npy", "f32be"):
        return _open_array(path, kind, sample_unit=sample_unit, n_samples=n_samples, tile=tile)
    return _open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian,
                      sample_unit=sample_unit, tile=tile)


def _sample_coord(samples, unit: str) -> tuple:
    xr = _xarray()
    return sample_dim(unit), xr.Variable((sample_dim(unit),), np.asarray(samples, dtype=np.float64),
                                         attrs={"units": unit})


def _sample_attrs(samples, unit: str) -> dict:
    interval = float(samples[1] - samples[0]) if len(samples) > 1 else 1.0
    return {"sample_interval": interval, "sample_unit": unit, "sample_rate": interval, "d3_domain": _DOMAINS[unit]}


def _open_segy(path: Path, *, iline, xline, ignore_geometry, endian, sample_unit, tile: int):
    """A SEG-Y file: geometry, layout and coordinates from one opening; amplitudes read tile by tile."""
    import segyio

    from .blocks import SegyGrid, segy_dask_array
    from .coordinates import header_resolution
    from .segy import open_segy

    xr = _xarray()
    # read, not mapped: a pass over every trace header of a mapped file would count in the resident memory
    with open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit,
                   endian=endian, mmap=False) as cube:
        f = cube.segyfile
        unit = cube.sample_unit
        samples = np.asarray(cube.samples, dtype=np.float64)
        lateral = (cube.inlines.size, cube.xlines.size) if cube.inlines is not None else (cube.n_traces, 1)
        grid = SegyGrid(path=str(path.resolve()), endian=cube.endian, sorting=cube.sorting or "inline",
                        n_inlines=int(lateral[0]), n_xlines=int(lateral[1]), n_samples=int(samples.size))
        x, y = cube.cdp_x, cube.cdp_y
        cdp = bool(np.any(f.attributes(segyio.TraceField.CDP_X)[:]) or np.any(f.attributes(segyio.TraceField.CDP_Y)[:]))
        resolution = header_resolution(np.asarray(f.attributes(segyio.TraceField.SourceGroupScalar)[:]))
        xy_unit = "ft" if int(f.bin[segyio.BinField.MeasurementSystem]) == 2 else "m"
        trace_il = trace_xl = None
        if cube.inlines is None:
            trace_il = np.asarray(f.attributes(cube.iline_byte)[:])
            trace_xl = np.asarray(f.attributes(cube.xline_byte)[:])
        attrs = {"source_file": path.name, "kind": "trace list" if cube.inlines is None else
                 ("cube" if cube.is_3d else "line"), "description": cube.description,
                 "segy_format": cube.format_name, "segy_endian": cube.endian, "segy_sorting": cube.sorting or "",
                 "iline_byte": int(cube.iline_byte), "xline_byte": int(cube.xline_byte),
                 **_sample_attrs(samples, unit)}
        inlines = None if cube.inlines is None else np.asarray(cube.inlines)
        xlines = None if cube.xlines is None else np.asarray(cube.xlines)
    data = segy_dask_array(grid, tile=tile)  # (n_inlines, n_xlines, n_samples); (n_traces, 1, ns) for a trace list
    name, sample = _sample_coord(samples, unit)
    coords = {name: sample}
    if x is not None:
        attrs.update(xy_unit=xy_unit, xy_resolution=resolution,
                     xy_source=("CDP X/Y (trace bytes 181-188)" if cdp else "source X/Y (trace bytes 73-80)")
                     + f" with the coordinate scalar of bytes 71-72, {xy_unit}")
    else:
        attrs.update(xy_unit="inline/crossline")
    if inlines is None:  # a trace list: one lateral dimension, its header line numbers as coordinates
        dims = ("trace", name)
        data = data[:, 0, :]
        coords["trace"] = np.arange(1, data.shape[0] + 1)  # numbered from 1 in file order, as the commands do
        if not (np.all(trace_il == trace_il[0]) and np.all(trace_xl == trace_xl[0])):
            coords.update(iline=("trace", trace_il), xline=("trace", trace_xl))
        xy = None if x is None else (np.ravel(x), np.ravel(y))
    elif 1 in lateral and not (lateral[0] == lateral[1] == 1):  # a 2D line of a survey
        along = "iline" if lateral[1] == 1 else "xline"
        other = "xline" if along == "iline" else "iline"
        dims = (along, name)
        data = data[:, 0, :] if along == "iline" else data[0]
        coords.update({along: inlines if along == "iline" else xlines,
                       other: int((xlines if along == "iline" else inlines)[0])})
        xy = None if x is None else (np.ravel(x), np.ravel(y))
    else:
        dims = ("iline", "xline", name)
        coords.update(iline=inlines, xline=xlines)
        xy = None if x is None else (x, y)
    if xy is not None:
        coords.update(cdp_x=(dims[:-1], np.asarray(xy[0], dtype=np.float64), {"units": xy_unit}),
                      cdp_y=(dims[:-1], np.asarray(xy[1], dtype=np.float64), {"units": xy_unit}))
    return xr.DataArray(data, dims=dims, coords=coords, attrs=attrs, name="seismic")


def _open_store(path: Path, *, sample_unit, tile: int):
    """A Zarr store of ``seismo3d convert``, lazily, renamed to segysak's dimensions."""
    from .zarr_store import open_seismic_group

    xr = _xarray()
    if not path.exists():
        raise DataNotFoundError(f"no Zarr store at {path}; check the path")
    meta = open_seismic_group(path)  # checks the layout
    unit = sample_unit or str(meta.attrs.get("sample_unit", "ms"))
    ds = xr.open_zarr(str(path), consolidated=None)
    keep = ["seismic"] + [c for c in ("cdp_x", "cdp_y") if c in ds]
    da = ds[keep].set_coords(keep[1:])["seismic"]
    name = sample_dim(unit)
    da = da.rename({"inline": "iline", "crossline": "xline", "sample": name})
    da = da.chunk({"iline": tile, "xline": tile, name: -1})
    da.coords[name].attrs["units"] = unit
    xy_unit = str(ds["cdp_x"].attrs.get("units", "m")) if "cdp_x" in ds else "inline/crossline"
    layout = meta.attrs.get("seismo3d", {})
    shape = " x ".join(str(n) for n in da.shape)
    da.attrs = {"source_file": path.name, "kind": "store", "description": f"a Zarr store of {shape} samples",
                "segy_endian": layout.get("endian", ""), "segy_sorting": layout.get("sorting", ""),
                "xy_unit": xy_unit, **_sample_attrs(np.asarray(meta["sample"][:], dtype=np.float64), unit)}
    return da


def _open_array(path: Path, kind: str, *, sample_unit, n_samples, tile: int):
    """A ``.npy`` array (through its memory map) or a raw ``.f32be`` section, in samples; traces labelled by their
    index."""
    import dask.array as da

    from .sections import known_section_shape, read_section

    xr = _xarray()
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
    lateral = ("iline", "xline") if data.ndim == 3 else ("trace",)
    chunks = (tile,) * len(lateral) + (-1,)
    name, sample = _sample_coord(np.arange(data.shape[-1]), "samples")
    coords = {d: np.arange(n) for d, n in zip(lateral, data.shape)}
    coords[name] = sample
    what = "a raw section" if kind == "f32be" else "an array"
    return xr.DataArray(da.from_array(data, chunks=chunks), dims=(*lateral, name), coords=coords, name="seismic",
                        attrs={"source_file": path.name, "kind": "section" if kind == "f32be" else "array",
                               "description": f"{what} of {shape} samples", "xy_unit": "inline/crossline",
                               **_sample_attrs(np.arange(data.shape[-1]), "samples")})


@dataclass(frozen=True)
class CubeAxes:
    """Which dimension of a seismic DataArray is what.

    Attributes
    ----------
    lateral : tuple of str
        The lateral dimension names in the array's order: ``('iline', 'xline')``, or one for a line.
    sample : str
        The sample dimension (the last).
    sample_unit : {'ms', 'm', 'ft', 'samples'}
    """

    lateral: tuple
    sample: str
    sample_unit: str


def seismic_axes(cube) -> CubeAxes:
    """Find the inline / crossline (or trace) and sample dimensions of a seismic DataArray.

    Parameters
    ----------
    cube : xarray.DataArray
        3D (inline, crossline, sample) or 2D (line or trace, sample), under segysak's names (``iline``, ``xline``,
        ``twt`` / ``depth`` / ``samples``, ``cdp`` / ``trace``) or those of a ``seismo3d convert`` store
        (``inline``, ``crossline``, ``sample``).

    Returns
    -------
    CubeAxes
        The sample unit from the sample coordinate's ``units`` attribute, the array's ``sample_unit`` attribute, or
        the dimension's name ('ms' for twt, 'm' for depth); 'ms' for another sample coordinate without a unit, as
        for SEG-Y (segysak's ``samples``); 'samples' without a sample coordinate.

    Raises
    ------
    InputError
        Not a DataArray, a sample dimension that is not last, or dimensions without these names.
    """
    xr = _xarray()
    if not isinstance(cube, xr.DataArray):
        raise InputError(f"expected an xarray.DataArray; got {type(cube).__name__} (for a Dataset, pass its "
                         "amplitude variable, e.g. ds['data'] or ds['seismic'])")
    dims = list(cube.dims)
    role = {}
    for d in dims:
        for name, aliases in _ALIASES.items():
            if str(d).lower() in aliases:
                role[d] = name
    if len(dims) not in (2, 3) or role.get(dims[-1]) != "sample":
        raise InputError(f"a seismic DataArray has dimensions (iline, xline, twt) or (trace, twt), the sample "
                         f"last; got {tuple(dims)} (transpose it, e.g. cube.transpose(..., 'twt'))")
    lateral = tuple(dims[:-1])
    if len(lateral) == 2 and [role.get(d) for d in lateral] != ["inline", "crossline"]:
        raise InputError(f"the lateral dimensions {lateral} must be inline then crossline (iline, xline)")
    s = dims[-1]
    unit = (cube.coords[s].attrs.get("units") if s in cube.coords else None) or cube.attrs.get("sample_unit") or \
        _UNIT_OF_DIM.get(str(s).lower())
    if unit is None:  # segysak's 'samples' carry no unit: time in ms, as open_segy assumes for SEG-Y
        unit = "ms" if s in cube.coords else "samples"
    if unit not in ("ms", "m", "ft", "samples"):
        raise InputError(f"the sample unit {unit!r} of {s!r} is not one of ms, m, ft; set "
                         f"cube[{s!r}].attrs['units'] to one of them")
    return CubeAxes(lateral, s, str(unit))


def sample_positions(cube, axes: CubeAxes) -> np.ndarray:
    """The positions of a cube's samples.

    Parameters
    ----------
    cube : xarray.DataArray
    axes : CubeAxes
        Its axes (:func:`seismic_axes`).

    Returns
    -------
    (n_samples,) float64 ndarray
        In ``axes.sample_unit``; the sample index without a sample coordinate.
    """
    if axes.sample in cube.coords:
        return np.asarray(cube.coords[axes.sample].values, dtype=np.float64)
    return np.arange(cube.sizes[axes.sample], dtype=np.float64)


def sample_interval(cube, axes: CubeAxes) -> tuple:
    """The sample interval of a cube and its unit.

    Parameters
    ----------
    cube : xarray.DataArray
    axes : CubeAxes
        Its axes (:func:`seismic_axes`).

    Returns
    -------
    (float or None, str)
        ``(interval, unit)``; ``(None, 'samples')`` without a sample interval (no unit, or a single sample).

    Raises
    ------
    InputError
        The sample coordinate is not regularly sampled.
    """
    samples = sample_positions(cube, axes)
    if axes.sample_unit == "samples" or samples.size < 2:
        return None, "samples"
    steps = np.diff(samples)
    if not np.allclose(steps, steps[0], rtol=1e-6, atol=0):
        raise InputError(f"the {axes.sample} coordinate is not regularly sampled (steps {steps.min():g} to "
                         f"{steps.max():g} {axes.sample_unit}); resample the cube to one sample interval")
    return float(steps[0]), axes.sample_unit


def grid_spacing(cube) -> tuple:
    """Inline bin, crossline bin and sample interval of a 3D cube, from its ``cdp_x`` / ``cdp_y`` and its sample
    coordinate.

    The inline bin is the median distance between the CDP positions of neighbouring inlines (same crossline), the
    crossline bin that between neighbouring crosslines (the coordinate scalar is applied when the cube is opened:
    :func:`open_cube`).

    Parameters
    ----------
    cube : xarray.DataArray
        A 3D seismic cube ``(iline, xline, twt | depth | samples)`` (:func:`seismic_axes`).

    Returns
    -------
    spacing : (3,) float64 ndarray
        Inline bin and crossline bin in the survey's unit (m or ft: ``cube.attrs['xy_unit']``), sample interval in
        the cube's sample unit. A bin is 1.0 when the coordinates are missing or do not change along that axis, the
        sample interval 1.0 without one (then see ``note``).
    note : str
        Where each value came from, e.g. ``'bins 25.01 x 25.01 from CDP X/Y, sample interval 4 ms from the binary
        header'``.

    Raises
    ------
    InputError
        Not a 3D seismic DataArray, or a sample coordinate that is not regularly sampled.
    """
    from ...errors import InputError

    axes = seismic_axes(cube)
    if len(axes.lateral) != 2:
        raise InputError(f"a grid spacing needs a 3D cube (iline, xline, sample); got dimensions {cube.dims}")
    from .coordinates import grid_spacing_from_cdp

    x = cube.coords["cdp_x"].values if "cdp_x" in cube.coords else None
    y = cube.coords["cdp_y"].values if "cdp_y" in cube.coords else None
    interval, unit = sample_interval(cube, axes)
    source = "from the binary header" if "segy_format" in cube.attrs else f"from its {axes.sample} coordinate"
    return grid_spacing_from_cdp(x, y, interval, unit, source)


def as_cube(values, like=None, *, name: str | None = None):
    """``values`` as a DataArray on the dimensions and coordinates of the cube ``like`` (a DataArray of the same
    shape), or on segysak's dimensions with index coordinates without one.

    Parameters
    ----------
    values : (..., n_samples) ndarray, dask.array.Array or zarr.Array
        A zarr array is wrapped lazily (``dask.array.from_zarr``).
    like : xarray.DataArray, optional
    name : str, optional

    Returns
    -------
    xarray.DataArray
        Numpy- or dask-backed as ``values``; ``like``'s attributes (sample interval and unit, source) kept.
    """
    xr = _xarray()
    zarr = sys.modules.get("zarr")  # a zarr.Array's class is imported whenever there is one
    if zarr is not None and isinstance(values, zarr.Array):
        import dask.array as da

        values = da.from_zarr(values)
    if like is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Seismo3dWarning)
            return xr.DataArray(values, dims=like.dims, coords=like.coords, attrs=dict(like.attrs), name=name)
    dims = ("iline", "xline", "samples") if np.ndim(values) == 3 else ("trace", "samples")
    return xr.DataArray(values, dims=dims, name=name)


def is_data_array(value) -> bool:
    """Whether ``value`` is an ``xarray.DataArray``, without importing xarray (its class is loaded whenever there is
    one)."""
    xr = sys.modules.get("xarray")
    return xr is not None and isinstance(value, xr.DataArray)


def line_values(cube, axes: CubeAxes) -> tuple:
    """The amplitudes of a seismic DataArray as a function of arrays takes them: a grid of a single inline or
    crossline as its 2D section.

    Parameters
    ----------
    cube : xarray.DataArray
    axes : CubeAxes
        Its axes (:func:`seismic_axes`).

    Returns
    -------
    values : ndarray or dask.array.Array
        The amplitudes, numpy- or dask-backed as the cube (``cube.data``, not read here): (n_inlines, n_xlines,
        n_samples), or (n_traces, n_samples) for a line and for a grid of one line.
    squeezed : int or None
        The lateral axis of length 1 taken out of a grid of one line (0 or 1); None otherwise.
    """
    values = cube.data
    if len(axes.lateral) == 2 and 1 in values.shape[:2]:
        squeezed = 0 if values.shape[0] == 1 else 1
        return (values[0] if squeezed == 0 else values[:, 0]), squeezed
    return values, None


def index_positions(cube, axes: CubeAxes, positions, *, what: str = "position") -> np.ndarray:
    """Positions in a cube's own numbers (inline, crossline, time or depth; or trace label, time) to index space.

    Parameters
    ----------
    cube : xarray.DataArray
    axes : CubeAxes
        Its axes (:func:`seismic_axes`).
    positions : (ndim,) or (n, ndim) array_like of float
        One value per dimension of ``cube``, in its coordinates: each lateral value one of the cube's line numbers
        (the index without a coordinate), the last in its sample unit within its samples. A line of a survey (one
        lateral dimension ``iline`` or ``xline``, the other line number a scalar coordinate) also takes (inline,
        crossline, time) rows, its own line number in them.
    what : str
        What the positions are, for messages (``'seed'``).

    Returns
    -------
    (n, ndim) float64 ndarray
        Lateral indices (whole numbers) and the fractional sample index.

    Raises
    ------
    InputError
        Not one value per dimension, a lateral value that is not one of the cube's, or a time or depth outside its
        samples; the message names the dimension and the cube's range.
    """
    from ...errors import InputError

    names = (*axes.lateral, axes.sample)
    try:
        rows = np.atleast_2d(np.asarray(positions, dtype=np.float64))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what}s must be rows of numbers ({', '.join(names)}); got {positions!r}") from exc
    other = _other_line(cube, axes)
    if other is not None and rows.ndim == 2 and rows.shape[1] == len(names) + 1:  # (inline, crossline, time)
        column, number = other
        for row in rows:
            if row[column] != number:
                name = "xline" if column else "iline"
                raise InputError(f"{what} {_row(row)}: {name} {row[column]:g} is not the line's {name} ({number:g})")
        rows = np.delete(rows, column, axis=1)
    if rows.ndim != 2 or rows.shape[1] != len(names) or rows.shape[0] == 0:
        raise InputError(f"{what}s must be ({', '.join(names)}) rows in the cube's own coordinates; got shape "
                         f"{np.shape(positions)}")
    out = np.empty_like(rows)
    for column, dim in enumerate(axes.lateral):
        labels = np.asarray(cube.coords[dim].values if dim in cube.coords else np.arange(cube.sizes[dim]),
                            dtype=np.float64)
        for n, value in enumerate(rows[:, column]):
            hit = np.flatnonzero(labels == value)
            if hit.size == 0:
                raise InputError(f"{what} {_row(rows[n])}: {dim} {value:g} is not a {dim} of the cube "
                                 f"({labels[0]:g}..{labels[-1]:g}); give one of its {dim} numbers")
            out[n, column] = hit[0]
    samples = sample_positions(cube, axes)
    for n, t in enumerate(rows[:, -1]):
        if not samples[0] <= t <= samples[-1]:
            raise InputError(f"{what} {_row(rows[n])}: {axes.sample} {t:g} {axes.sample_unit} is outside the cube's "
                             f"samples ({samples[0]:g}..{samples[-1]:g} {axes.sample_unit})")
    out[:, -1] = np.interp(rows[:, -1], samples, np.arange(samples.size))
    return out


def _other_line(cube, axes: CubeAxes):
    """For a line of a survey (one lateral dimension 'iline' or 'xline', the other line number a scalar
    coordinate): (its column in an (inline, crossline, time) row, its number); None otherwise."""
    if len(axes.lateral) != 1 or axes.lateral[0] not in ("iline", "xline"):
        return None
    name = "xline" if axes.lateral[0] == "iline" else "iline"
    if name not in cube.coords or cube.coords[name].ndim != 0:
        return None
    return (1 if name == "xline" else 0), float(cube.coords[name].values)


def _row(values) -> str:
    return "(" + ", ".join(f"{float(v):g}" for v in values) + ")"


def samples_at(cube, axes: CubeAxes, index) -> np.ndarray:
    """Fractional sample indices as positions in a cube's sample unit (linear between samples).

    Parameters
    ----------
    cube : xarray.DataArray
    axes : CubeAxes
        Its axes (:func:`seismic_axes`).
    index : array_like of float
        Fractional sample indices; NaN where there is none.

    Returns
    -------
    float64 ndarray
        Of ``index``'s shape, in ``axes.sample_unit`` (ms, m, ft; the index itself without a sample coordinate); NaN
        where ``index`` is NaN.
    """
    k = np.asarray(index, dtype=np.float64)
    samples = sample_positions(cube, axes)
    return np.where(np.isfinite(k), np.interp(np.nan_to_num(k), np.arange(samples.size), samples), np.nan)


def on_lateral(values, cube, axes: CubeAxes, *, squeezed: int | None = None, name: str | None = None,
               attrs: dict | None = None):
    """A map of one value per trace as a DataArray on a cube's lateral dimensions and coordinates.

    Parameters
    ----------
    values : (n_inlines, n_xlines) or (n_traces,) array_like
        One value per trace of ``cube`` (of its 2D section, with ``squeezed``).
    cube : xarray.DataArray
    axes : CubeAxes
        Its axes (:func:`seismic_axes`).
    squeezed : int, optional
        The lateral axis a grid of one line lost (:func:`line_values`): put back, of length 1.
    name : str, optional
    attrs : dict, optional

    Returns
    -------
    xarray.DataArray
        Dims ``axes.lateral``; every coordinate of ``cube`` that does not run along its samples (line numbers,
        ``cdp_x`` / ``cdp_y``, a line's scalar line number).
    """
    xr = _xarray()
    values = np.asarray(values)
    if squeezed is not None:
        values = np.expand_dims(values, squeezed)
    coords = {key: c for key, c in cube.coords.items() if axes.sample not in c.dims}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        return xr.DataArray(values, dims=axes.lateral, coords=coords, name=name, attrs=dict(attrs or {}))
