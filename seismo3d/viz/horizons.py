"""Horizon surfaces for pyvista (see :func:`seismo3d.seismic.track_horizon`)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["horizon_surface", "plot_horizon_section"]


def horizon_surface(horizon, *, inlines=None, xlines=None, samples=None):
    """A tracked horizon as a pyvista surface: one quad per 2 x 2 block of picked traces; on a single line (one
    inline or one crossline: a (n, 1) or (1, n) grid) a curve, one segment between neighbouring picked traces.

    Empty traces (NaN) leave holes: quads (segments) with an empty corner (end) are dropped, nothing is interpolated
    (use :func:`seismo3d.seismic.fill_horizon` first to close gaps).

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
    elif 1 in times.shape:  # a line: its picks joined along it
        along = index.ravel()
        pair = (along[:-1] >= 0) & (along[1:] >= 0)
        mesh.lines = np.column_stack([np.full(int(pair.sum()), 2), along[:-1][pair], along[1:][pair]]).ravel()
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


def plot_horizon_section(section, picks, *, samples=None, traces=None, styles=None, axis_labels=("trace", "sample"),
                         clip_percentile=99.0, title=None, ax=None):
    """A seismic section with horizon picks drawn over it, one colour per entry of ``picks``.

    Parameters
    ----------
    section : (n_traces, n_samples) array_like
        Amplitudes (one inline or crossline of a cube), shown in grey with symmetric limits at the
        ``clip_percentile`` of ``|amplitude|``.
    picks : dict of str to (n_traces,) array_like of float
        Label -> the horizon's fractional sample index on each trace (NaN where absent), e.g.
        ``{"people": ..., "tracked": ...}``.
    samples : (n_samples,) array_like, optional
        Vertical axis values (ms or m); default sample indices.
    traces : (n_traces,) array_like, optional
        Horizontal axis values (trace or line numbers); default indices.
    styles : dict of str to dict, optional
        Matplotlib line keywords per label (e.g. ``{"people": {"lw": 3, "alpha": 0.6}}``); default: colour
        ``C0``, ``C1``, ... in order, 1.2 points wide.
    axis_labels : (str, str), optional
        Horizontal and vertical axis labels, e.g. ``("crossline", "time (ms)")``.
    clip_percentile : float, optional
    title : str, optional
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        A section that is not 2D, or picks of another length than its traces.
    """
    from matplotlib.figure import Figure

    from .plotting import symmetric_clip

    data = np.asarray(section, dtype=np.float32)
    if data.ndim != 2:
        raise InputError(f"section must be (n_traces, n_samples); got shape {data.shape}")
    x = np.arange(data.shape[0], dtype=np.float64) if traces is None else np.asarray(traces, dtype=np.float64)
    s = np.arange(data.shape[1], dtype=np.float64) if samples is None else np.asarray(samples, dtype=np.float64)
    if x.shape != (data.shape[0],) or s.shape != (data.shape[1],):
        raise InputError("traces and samples must label the section's two axes")
    if ax is None:
        fig = Figure(figsize=(10, 5), layout="constrained")
        ax = fig.subplots()
    else:
        fig = ax.figure
    clip = symmetric_clip(data, clip_percentile)
    ax.imshow(data.T, cmap="gray", vmin=-clip, vmax=clip, aspect="auto", interpolation="bilinear",
              extent=(x[0], x[-1], s[-1], s[0]))
    for n, (label, times) in enumerate(picks.items()):
        t = np.asarray(times, dtype=np.float64)
        if t.shape != (data.shape[0],):
            raise InputError(f"picks[{label!r}] has shape {t.shape}; it needs one value per trace ({data.shape[0]})")
        style = {"lw": 1.2, "color": f"C{n}"} | dict((styles or {}).get(label, {}))
        ax.plot(x, np.interp(t, np.arange(s.size), s, left=np.nan, right=np.nan), label=label, **style)
    ax.set_xlabel(str(axis_labels[0]))
    ax.set_ylabel(str(axis_labels[1]))
    ax.legend(loc="lower right")
    if title:
        ax.set_title(title)
    return fig
