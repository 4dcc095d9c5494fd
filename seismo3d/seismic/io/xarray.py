"""Seismic as xarray: open SEG-Y or a ``seismo3d convert`` Zarr store as a labelled ``xarray.DataArray``, and run the
fault tracer and the horizon tracker on one, with the results carrying its coordinates.

Conventions (those of ``seismo3d convert``'s Zarr store and of segysak): dimensions ``inline``, ``crossline``,
``sample`` (segysak's ``iline``, ``xline`` and ``twt`` / ``depth`` / ``samples`` are accepted as well), coordinates of
the same names holding the line numbers and the times or depths, and ``cdp_x`` / ``cdp_y`` on (inline, crossline)
with the coordinate scalar applied. A trace list is (``trace``, ``sample``).

xarray is imported inside the functions; install it with ``pip install xarray``.

References
----------
xarray, https://docs.xarray.dev; segysak (``segysak.segy.segy_loader``, ``xr.open_dataset(..., engine='sgy')``),
https://segysak.readthedocs.io.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, Seismo3dWarning

__all__ = ["LabelledFaults", "open_seismic_dataarray", "seismic_axes", "trace_faults_xr", "track_horizon_xr"]

_ALIASES = {"inline": ("inline", "iline", "il", "INLINE_3D"), "crossline": ("crossline", "xline", "xl",
                                                                            "CROSSLINE_3D"),
            "sample": ("sample", "samples", "twt", "time", "depth", "z"), "trace": ("trace", "cdp", "traces")}
_UNIT_OF_DIM = {"twt": "ms", "time": "ms", "depth": "m"}


def _xarray():
    try:
        import xarray as xr
    except ImportError as exc:  # pragma: no cover - xarray is a dependency of the interchange extra
        raise ImportError("seismic DataArrays need xarray: pip install xarray (or pip install "
                          "'seismo3d[interchange]')") from exc
    return xr


@dataclass(frozen=True)
class _Axes:
    """Which dimension of a DataArray is what."""

    lateral: tuple  # dimension names: ('inline', 'crossline') or ('trace',)
    sample: str
    sample_unit: str


def seismic_axes(data_array) -> _Axes:
    """Find the inline / crossline (or trace) and sample dimensions of a seismic DataArray.

    Parameters
    ----------
    data_array : xarray.DataArray
        3D (inline, crossline, sample) or 2D (trace or inline or crossline, sample), under the names of
        ``seismo3d convert`` or segysak.

    Returns
    -------
    _Axes
        ``lateral`` dimension names in the array's order, the ``sample`` dimension, its unit (the coordinate's
        ``units`` attribute, the array's ``sample_unit`` attribute, or from the dimension's name: 'ms' for twt,
        'm' for depth; 'ms' for another sample coordinate without a unit, as for SEG-Y (segysak's ``samples``);
        'samples' without a sample coordinate).

    Raises
    ------
    InputError
        Not a DataArray, a sample dimension that is not last, or dimensions without these names.
    """
    xr = _xarray()
    if not isinstance(data_array, xr.DataArray):
        raise InputError(f"expected an xarray.DataArray; got {type(data_array).__name__} (for a Dataset, pass its "
                         "amplitude variable, e.g. ds['seismic'] or ds['data'])")
    dims = list(data_array.dims)
    role = {}
    for d in dims:
        for name, aliases in _ALIASES.items():
            if d in aliases or d.lower() in aliases:
                role[d] = name
    if len(dims) not in (2, 3) or role.get(dims[-1]) != "sample":
        raise InputError(f"a seismic DataArray has dimensions (inline, crossline, sample) or (trace, sample), the "
                         f"sample last; got {tuple(dims)} (transpose it, e.g. da.transpose(..., 'sample'))")
    lateral = tuple(dims[:-1])
    if len(lateral) == 2 and [role.get(d) for d in lateral] != ["inline", "crossline"]:
        raise InputError(f"the lateral dimensions {lateral} must be inline then crossline")
    s = dims[-1]
    unit = (data_array.coords[s].attrs.get("units") if s in data_array.coords else None) or \
        data_array.attrs.get("sample_unit") or _UNIT_OF_DIM.get(s.lower())
    if unit is None:  # segysak's 'samples' carry no unit: time in ms, as open_segy assumes for SEG-Y
        unit = "ms" if s in data_array.coords else "samples"
    if unit not in ("ms", "m", "ft", "samples"):
        raise InputError(f"the sample unit {unit!r} of {s!r} is not one of ms, m, ft; set "
                         f"da[{s!r}].attrs['units'] to one of them")
    return _Axes(lateral, s, str(unit))


def _sample_axis(data_array, axes: _Axes) -> np.ndarray:
    n = data_array.sizes[axes.sample]
    if axes.sample in data_array.coords:
        return np.asarray(data_array.coords[axes.sample].values, dtype=np.float64)
    return np.arange(n, dtype=np.float64)


def open_seismic_dataarray(path, *, iline: int = 189, xline: int = 193, ignore_geometry: bool = False, endian=None,
                           sample_unit=None):
    """Open a SEG-Y file or a ``seismo3d convert`` Zarr store as a labelled DataArray.

    Parameters
    ----------
    path : str or os.PathLike
        A SEG-Y cube, 2D line of a survey or trace list (read whole into memory), or a ``.zarr`` store of
        ``seismo3d convert`` (opened lazily with ``xarray.open_zarr``: dask-backed).
    iline, xline, ignore_geometry, endian, sample_unit
        SEG-Y only, as :func:`~seismo3d.seismic.io.open_segy`.

    Returns
    -------
    xarray.DataArray
        float32, dims ``(inline, crossline, sample)`` for a grid (a 2D line of a survey keeps its single inline or
        crossline), ``(trace, sample)`` for a trace list; coordinates ``inline``, ``crossline`` (int), ``sample``
        (float64, ``units`` attribute 'ms' / 'm' / 'ft'), and ``cdp_x`` / ``cdp_y`` (float64, scalar applied, on the
        lateral dims) when the headers hold coordinates; attrs ``sample_unit``, ``xy_unit``, ``source``.

    Raises
    ------
    DataNotFoundError, SegyFormatError, SegyGeometryError
        As :func:`~seismo3d.seismic.io.open_segy`.
    InputError
        A folder that is not a ``seismo3d convert`` store.
    """
    from pathlib import Path

    xr = _xarray()
    path = Path(path)
    if path.is_dir():
        from .zarr_store import open_seismic_zarr

        meta = open_seismic_zarr(path)  # checks the layout
        ds = xr.open_zarr(str(path), consolidated=None)
        da = ds["seismic"]
        da.coords["sample"].attrs.setdefault("units", meta.sample_unit)
        da.attrs.update(sample_unit=meta.sample_unit, source=path.name,
                        xy_unit=str(ds["cdp_x"].attrs.get("units", "m")) if "cdp_x" in ds else "inline/crossline")
        return da
    from .coordinates import read_survey_coordinates
    from .segy import open_segy

    with open_segy(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit,
                   endian=endian) as cube:
        data = cube.read()
        samples = np.asarray(cube.samples, dtype=np.float64)
        unit, inlines, xlines = cube.sample_unit, cube.inlines, cube.xlines
    coords = read_survey_coordinates(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian)
    sample = xr.Variable(("sample",), samples, attrs={"units": unit})
    attrs = {"sample_unit": unit, "xy_unit": coords.unit, "source": path.name}
    if inlines is None:
        c = {"trace": np.arange(1, data.shape[0] + 1), "sample": sample}
        lateral = ("trace",)
    else:
        c = {"inline": np.asarray(inlines), "crossline": np.asarray(xlines), "sample": sample}
        lateral = ("inline", "crossline")
    if coords.has_coordinates:
        c["cdp_x"] = (lateral, coords.x.reshape(data.shape[:-1]), {"units": coords.unit})
        c["cdp_y"] = (lateral, coords.y.reshape(data.shape[:-1]), {"units": coords.unit})
    return xr.DataArray(np.asarray(data, dtype=np.float32), dims=(*lateral, "sample"), coords=c, attrs=attrs,
                        name="seismic")


def _values(data_array, axes: _Axes) -> tuple:
    """(values as traced, squeezed lateral dim or None): a grid with a single inline or crossline is traced as
    its 2D section."""
    values = np.asarray(data_array.values, dtype=np.float32)
    if len(axes.lateral) == 2 and 1 in values.shape[:2]:
        squeezed = 0 if values.shape[0] == 1 else 1
        return np.take(values, 0, axis=squeezed), squeezed
    return values, None


def _sample_interval(samples: np.ndarray, unit: str):
    if unit == "samples" or samples.size < 2:
        return None, "samples"
    return float(samples[1] - samples[0]), unit


@dataclass(frozen=True, eq=False)
class LabelledFaults:
    """:func:`trace_faults_xr`'s result: the interpretation and its volumes with the input's coordinates.

    Attributes
    ----------
    interpretation : FaultInterpretation
        As :func:`~seismo3d.seismic.trace_faults` returns it on the DataArray's values (a grid of one line: on its
        2D section).
    volumes : xarray.Dataset
        ``likelihood``, ``strike_deg``, ``dip_deg``, ``votes``, ``thin`` (float32) on the input's dims and
        coordinates (``cdp_x`` / ``cdp_y`` included), attrs ``sample_unit``, ``n_faults``.
    """

    interpretation: object
    volumes: object


def trace_faults_xr(data_array, *, options=None, progress: bool = False) -> LabelledFaults:
    """:func:`~seismo3d.seismic.trace_faults` on a labelled seismic DataArray.

    Parameters
    ----------
    data_array : xarray.DataArray
        (inline, crossline, sample) or (trace, sample) amplitudes (:func:`open_seismic_dataarray`, a segysak
        Dataset's ``data`` variable, or ``xarray.open_zarr`` of a ``seismo3d convert`` store); the sample interval
        and unit from the sample coordinate. A grid of a single inline or crossline is traced as a 2D section.
    options : FaultTracingOptions, optional
    progress : bool, optional

    Returns
    -------
    LabelledFaults

    Raises
    ------
    InputError, UnsupportedDataError
        As :func:`~seismo3d.seismic.trace_faults`, and dimensions not named as above (:func:`seismic_axes`).
    """
    from ..blocks.options import BlockRunOptions
    from ..faults.pipeline import trace_faults

    xr = _xarray()
    axes = seismic_axes(data_array)
    values, squeezed = _values(data_array, axes)
    dt, unit = _sample_interval(_sample_axis(data_array, axes), axes.sample_unit)
    result = trace_faults(values, sample_interval=dt, sample_unit=unit, options=options,
                          blocks=BlockRunOptions(in_memory=True), progress=progress)
    volumes = {}
    for name in ("likelihood", "strike_deg", "dip_deg", "votes", "thin"):
        v = np.asarray(getattr(result, name), dtype=np.float32)
        if squeezed is not None:
            v = np.expand_dims(v, squeezed)
        volumes[name] = (data_array.dims, v)
    ds = xr.Dataset(volumes, coords=data_array.coords,
                    attrs={"sample_unit": unit, "n_faults": len(result.faults)})
    return LabelledFaults(result, ds)


def _seed_indices(data_array, axes: _Axes, seeds) -> np.ndarray:
    """Seeds in the DataArray's labels (inline, crossline, time; or trace label, time) to index space."""
    s = np.atleast_2d(np.asarray(seeds, dtype=np.float64))
    if s.shape[1] != len(axes.lateral) + 1:
        names = ", ".join((*axes.lateral, axes.sample))
        raise InputError(f"seeds must be ({names}) rows in the DataArray's coordinates; got shape {s.shape}")
    out = []
    for column, dim in enumerate(axes.lateral):
        labels = np.asarray(data_array.coords[dim].values if dim in data_array.coords
                            else np.arange(data_array.sizes[dim]), dtype=np.float64)
        idx = [int(np.argmin(np.abs(labels - v))) for v in s[:, column]]
        bad = [v for v, i in zip(s[:, column], idx) if labels[i] != v]
        if bad:
            raise InputError(f"seed {dim} {bad[0]:g} is not a {dim} of the DataArray ({labels[0]:g}..{labels[-1]:g})")
        out.append(idx)
    samples = _sample_axis(data_array, axes)
    t = s[:, -1]
    if np.any((t < samples.min()) | (t > samples.max())):
        raise InputError(f"a seed's {axes.sample} is outside the DataArray's samples ({samples[0]:g}..{samples[-1]:g} "
                         f"{axes.sample_unit})")
    out.append(np.interp(t, samples, np.arange(samples.size)))
    return np.column_stack(out)


def track_horizon_xr(data_array, seeds, *, polarity: str = "peak", faults=None, **kwargs):
    """:func:`~seismo3d.seismic.track_horizon` on a labelled seismic DataArray, seeds in its coordinates.

    Parameters
    ----------
    data_array : xarray.DataArray
        As :func:`trace_faults_xr`; a grid of a single line is tracked as its 2D section.
    seeds : (n_seeds, 3) or (n_seeds, 2) array_like of float
        Seed picks in the DataArray's coordinate values: (inline, crossline, time or depth), or (trace label, time)
        for a (trace, sample) array.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
    faults : LabelledFaults or FaultInterpretation, optional
        Faults of the same array (:func:`trace_faults_xr`).
    **kwargs
        Passed to :func:`~seismo3d.seismic.track_horizon` (``options``, ``progress``, overrides).

    Returns
    -------
    xarray.Dataset
        On the lateral dims and coordinates of ``data_array`` (``cdp_x`` / ``cdp_y`` included): ``time_or_depth``
        (float64, the sample unit; NaN where empty), ``sample_index`` (fractional), ``confidence``; attrs
        ``polarity``, ``sample_unit``.

    Raises
    ------
    InputError, SeedError
        As :func:`~seismo3d.seismic.track_horizon`; a seed off the DataArray's lines or samples.
    """
    from ..horizons.tracking import track_horizon

    xr = _xarray()
    axes = seismic_axes(data_array)
    values, squeezed = _values(data_array, axes)
    index_seeds = _seed_indices(data_array, axes, seeds)
    if squeezed is not None:
        index_seeds = np.delete(index_seeds, squeezed, axis=1)
    interp = getattr(faults, "interpretation", faults)
    horizon = track_horizon(values, index_seeds, polarity=polarity, faults=interp, **kwargs)
    samples = _sample_axis(data_array, axes)
    k = np.asarray(horizon.times, dtype=np.float64)
    t = np.where(np.isfinite(k), np.interp(np.nan_to_num(k), np.arange(samples.size), samples), np.nan)
    conf = np.asarray(horizon.confidence, dtype=np.float32)
    if squeezed is not None:
        k, t, conf = (np.expand_dims(a, squeezed) for a in (k, t, conf))
    coords = {name: c for name, c in data_array.coords.items() if axes.sample not in c.dims}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        return xr.Dataset({"time_or_depth": (axes.lateral, t), "sample_index": (axes.lateral, k),
                           "confidence": (axes.lateral, conf)}, coords=coords,
                          attrs={"polarity": polarity, "sample_unit": axes.sample_unit})
