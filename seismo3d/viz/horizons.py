"""Horizon surfaces for pyvista (see :func:`seismo3d.seismic.track_horizon`)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["horizon_surface"]


def horizon_surface(horizon, *, inlines=None, xlines=None, samples=None):
    """A tracked 3D horizon as a pyvista surface: one quad per 2 x 2 block of picked traces.

    Empty traces (NaN) leave holes: quads with an empty corner are dropped, nothing is interpolated (use
    :func:`seismo3d.seismic.fill_horizon` first to close gaps).

    Parameters
    ----------
    horizon : Horizon or (n_inlines, n_xlines) array_like of float
        Horizon times in fractional samples, NaN where empty.
    inlines, xlines : (n_inlines,), (n_xlines,) array_like, optional
        Inline / crossline numbers, added as point arrays ``inline`` and ``crossline``.
    samples : (n_samples,) array_like of float, optional
        The sample axis (ms or m); adds the point array ``time_or_depth`` (linear interpolation of the fractional
        sample index).

    Returns
    -------
    pyvista.PolyData
        Points at ``(i, j, -t)`` (index space with z up, as :func:`seismo3d.viz.fault_surfaces`), one per picked
        trace; point arrays ``sample`` (float32, fractional sample index), ``confidence`` (float32, NaN without),
        and the annotations given.

    Raises
    ------
    InputError
        ``horizon`` is not a 2D grid, or an annotation's length does not match it.
    """
    import pyvista as pv

    times = np.asarray(getattr(horizon, "times", horizon), dtype=np.float64)
    if times.ndim != 2:
        raise InputError(f"a horizon surface needs a (n_inlines, n_xlines) grid; got shape {times.shape}")
    conf = getattr(horizon, "confidence", None)
    conf = np.full(times.shape, np.nan) if conf is None else np.asarray(conf, dtype=np.float64)
    have = np.isfinite(times)
    index = np.full(times.shape, -1, dtype=np.int64)
    index[have] = np.arange(int(have.sum()))
    ii, jj = np.nonzero(have)
    points = np.column_stack([ii, jj, -times[have]]).astype(np.float64)
    a, b = index[:-1, :-1], index[1:, :-1]
    c, d = index[1:, 1:], index[:-1, 1:]
    full = (a >= 0) & (b >= 0) & (c >= 0) & (d >= 0)
    quads = np.column_stack([np.full(int(full.sum()), 4), a[full], b[full], c[full], d[full]]).ravel()
    mesh = pv.PolyData(points)
    mesh.verts = np.empty(0, dtype=np.int64)
    if quads.size:
        mesh.faces = quads
    mesh.point_data["sample"] = times[have].astype(np.float32)
    mesh.point_data["confidence"] = conf[have].astype(np.float32)
    for name, labels, axis in (("inline", inlines, 0), ("crossline", xlines, 1)):
        if labels is None:
            continue
        labels = np.asarray(labels)
        if labels.shape != (times.shape[axis],):
            raise InputError(f"{name}s has shape {labels.shape}; the horizon has {times.shape[axis]} along axis {axis}")
        mesh.point_data[name] = labels[(ii, jj)[axis]]
    if samples is not None:
        s = np.asarray(samples, dtype=np.float64)
        if s.ndim != 1 or s.size < 2:
            raise InputError(f"samples must be the 1D sample axis; got shape {s.shape}")
        mesh.point_data["time_or_depth"] = np.interp(times[have], np.arange(s.size), s).astype(np.float32)
    return mesh
