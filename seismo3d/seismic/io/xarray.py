"""The horizon tracker on a labelled seismic cube: :func:`track_horizon_xr`, seeds in the cube's own coordinates and
the horizon on its lateral coordinates.

The cube is the project's one cube type (:func:`seismo3d.open`, :mod:`~seismo3d.seismic.io.cube`: segysak's
dimensions ``iline``, ``xline``, ``twt`` / ``depth``; a segysak Dataset's variable or a ``seismo3d convert`` store
opened by xarray work as they are). The fault tracer takes such a cube itself (:func:`~seismo3d.seismic.trace_faults`).

References
----------
xarray, https://docs.xarray.dev; segysak (``xr.open_dataset(..., engine='sgy')``), https://segysak.readthedocs.io.
"""

from __future__ import annotations

import warnings

import numpy as np

from ...errors import InputError, Seismo3dWarning
from .cube import CubeAxes, sample_positions, seismic_axes

__all__ = ["seismic_axes", "track_horizon_xr"]


def _xarray():
    import xarray as xr

    return xr


def _values(data_array, axes: CubeAxes) -> tuple:
    """(values as tracked, squeezed lateral dim or None): a grid with a single inline or crossline is tracked as
    its 2D section."""
    values = np.asarray(data_array.values, dtype=np.float32)
    if len(axes.lateral) == 2 and 1 in values.shape[:2]:
        squeezed = 0 if values.shape[0] == 1 else 1
        return np.take(values, 0, axis=squeezed), squeezed
    return values, None


def _seed_indices(data_array, axes: CubeAxes, seeds) -> np.ndarray:
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
    samples = sample_positions(data_array, axes)
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
        A seismic cube or line (:func:`seismo3d.open`, :func:`~seismo3d.seismic.io.cube.seismic_axes`); a grid of a
        single line is tracked as its 2D section.
    seeds : (n_seeds, 3) or (n_seeds, 2) array_like of float
        Seed picks in the DataArray's coordinate values: (inline, crossline, time or depth), or (trace label, time)
        for a (trace, sample) array.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
    faults : FaultInterpretation, optional
        Faults of the same cube (:func:`~seismo3d.seismic.trace_faults`).
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
    horizon = track_horizon(values, index_seeds, polarity=polarity, faults=faults, **kwargs)
    samples = sample_positions(data_array, axes)
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
