"""Horizons: the result type of horizon tracking, seed checks, gap filling and text export.

A :class:`Horizon` holds one fractional sample index per trace (NaN where empty) and a confidence, from
:func:`~seismo3d.seismic.track_horizon` (registration of neighbouring slices) or :func:`~seismo3d.seismic.autotrack`
(the plain amplitude autotracker). :func:`fill_horizon` interpolates the gaps as an explicit step;
:func:`write_horizon_text` writes "inline xline time" rows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import distance_transform_edt

from ..._atomic import atomic_path
from ..._validation import check_positive
from ...errors import InputError, SeedError
from ..io.cube import is_data_array

__all__ = ["Horizon", "as_seeds", "check_live_seed", "fill_horizon", "snap_seeds", "write_horizon_text"]


@dataclass(frozen=True, eq=False)
class Horizon:
    """A tracked horizon (see :func:`~seismo3d.seismic.track_horizon` and :func:`~seismo3d.seismic.autotrack`).

    Attributes
    ----------
    times : (n_inlines, n_xlines) or (n_traces,) float32 ndarray, or float64 xarray.DataArray
        Fractional sample index of the horizon on each trace; NaN where it is empty (not reached, no extremum of
        the polarity within the snap window, or confidence below the threshold). Tracked in a DataArray cube
        (:func:`seismo3d.open`): a DataArray on the cube's lateral dimensions and coordinates (line numbers,
        ``cdp_x`` / ``cdp_y``), in the cube's sample unit (two-way time in ms, or depth; its ``units`` attribute).
    confidence : same shape, float32 ndarray or DataArray
        Normalised cross-correlation, in [-1, 1], of the waveform (+-8 samples by default) around each pick with the
        waveform around the pick it was carried from (1 at seeds); NaN where the tracker never reached the trace.
    polarity : str
        One of :data:`~seismo3d.seismic.reflectors.POLARITIES`.
    seeds : (n_seeds, ndim) float64 ndarray
        Seed positions in index space, ``(inline, xline, sample)`` or ``(trace, sample)``; in the cube's own
        numbers (inline, crossline, time) for a horizon tracked in a DataArray.
    """

    times: np.ndarray
    confidence: np.ndarray
    polarity: str
    seeds: np.ndarray

    @property
    def mask(self) -> np.ndarray:
        """Boolean array (a DataArray for a labelled horizon), True where the horizon has a pick."""
        return np.isfinite(self.times)

    @property
    def coverage(self) -> float:
        """Fraction of traces with a pick."""
        return float(np.count_nonzero(self.mask) / self.times.size)


def as_seeds(seeds, shape) -> np.ndarray:
    """Seed picks as an (n_seeds, ndim) float64 array inside data of ``shape``, or raise :class:`InputError`.

    Parameters
    ----------
    seeds : (ndim,) or (n_seeds, ndim) array_like of float
        Index positions ``(inline, xline, sample)`` (3D) or ``(trace, sample)`` (2D).
    shape : tuple of int
        The data's shape.

    Returns
    -------
    (n_seeds, ndim) float64 ndarray

    Raises
    ------
    InputError
        Wrong shape, not finite, or outside the data.
    """
    ndim = len(shape)
    arr = np.asarray(seeds, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != ndim or arr.shape[0] == 0:
        names = "(inline, xline, sample)" if ndim == 3 else "(trace, sample)"
        raise InputError(f"seeds must be one or more {names} index triples for data of shape {shape}; got "
                         f"{np.asarray(seeds).shape}")
    if not np.isfinite(arr).all():
        raise InputError("seeds must be finite index positions")
    for s in arr:
        for axis, (v, size) in enumerate(zip(s, shape)):
            limit = size - 1
            if not (0 <= v <= limit):
                raise InputError(f"seed {tuple(float(x) for x in s)} lies outside the data: axis {axis} index {v} is "
                                 f"not in [0, {limit}]; give seeds in index space inside the cube (the CLI converts "
                                 "inline, xline and time for you)")
    return arr


def check_live_seed(data: np.ndarray, seed: np.ndarray) -> None:
    """Raise :class:`~seismo3d.errors.SeedError` when ``seed`` (an index position, last coordinate the sample) lies
    on a dead trace of ``data`` (all samples equal); its ``nearest`` is the nearest live trace at the seed's
    sample."""
    trace = data[tuple(int(round(v)) for v in seed[:-1])]
    if np.ptp(trace) == 0:
        live = np.argwhere(np.ptp(data, axis=-1) > 0)
        nearest = None
        if live.size:
            at = live[np.argmin(((live - np.asarray(seed[:-1], np.float64)) ** 2).sum(axis=1))]
            nearest = (*at, seed[-1])
        raise dead_trace_error(seed, nearest, f" (all samples equal {trace[0]})")


def snap_seeds(data: np.ndarray, seeds: np.ndarray, *, polarity: str, window: float, picks=None) -> np.ndarray:
    """The seeds' times snapped to the nearest reflector pick of ``polarity`` on their traces, or the error a user
    needs: the check every tracker makes of its seeds, which a caller can also make before costly work (the
    ``seismo3d horizon`` job, before tracing the faults).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) ndarray
        Seismic amplitudes, zero-mean, the last axis the sample.
    seeds : (n_seeds, data.ndim) ndarray of float
        Index positions, the sample last (:func:`as_seeds`).
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The event (:func:`~seismo3d.seismic.reflector_picks`).
    window : float
        The largest distance from a seed to its pick, samples (``TrackingOptions.seed_snap``).
    picks : (ndarray, ndarray), optional
        ``(times, offsets)``: the picks of every trace of ``data`` (lateral axes flattened), when the caller has
        them; default: those of the seeds' traces, and of every trace only to name the nearest pick in an error.

    Returns
    -------
    (n_seeds,) float64 ndarray
        The snapped fractional sample index of each seed.

    Raises
    ------
    SeedError
        A seed on a dead trace (:func:`check_live_seed`), or with no pick within ``window`` samples; its ``nearest``
        is the nearest position that has one (:func:`~seismo3d.seismic.reflectors.nearest_reflector`).
    """
    from ..reflectors import nearest_pick, nearest_reflector, reflector_picks

    lat = data.shape[:-1]
    traces = data.reshape(-1, data.shape[-1])
    out = np.empty(len(seeds))
    for k, s in enumerate(seeds):
        check_live_seed(data, s)
        flat = int(np.ravel_multi_index(tuple(int(round(v)) for v in s[:-1]), lat))
        if picks is None:
            out[k] = nearest_pick(*reflector_picks(traces[flat][None], polarity=polarity), 0, s[-1], window)
        else:
            out[k] = nearest_pick(*picks, flat, s[-1], window)
        if not np.isfinite(out[k]):
            every = reflector_picks(traces, polarity=polarity) if picks is None else picks
            raise no_pick_error(s, window, nearest_reflector(*every, lat, s))
    return out


def dead_trace_error(seed, nearest, note: str = "") -> SeedError:
    """The error of a seed on a dead trace.

    Parameters
    ----------
    seed : sequence of float
        The seed's position, the sample last.
    nearest : sequence of float or None
        The nearest live position.
    note : str
        What the trace holds, in words (``' (all samples equal 0.0)'``).

    Returns
    -------
    SeedError
    """
    return SeedError(f"seed {_position(seed)} is on a dead trace{note}; move the seed to a live trace"
                     + ("" if nearest is None else f", e.g. {_position(nearest)}"), seed, nearest)


def no_pick_error(seed, window: float, nearest) -> SeedError:
    """The error of a seed with no reflector pick of the requested polarity within ``window`` samples.

    Parameters
    ----------
    seed : sequence of float
        Index position, the sample last.
    window : float
        The snapping distance searched, samples.
    nearest : sequence of float or None
        The nearest position with a pick (:func:`~seismo3d.seismic.reflectors.nearest_reflector`).

    Returns
    -------
    SeedError
    """
    where = "" if nearest is None else f" (the nearest is at {_position(nearest)})"
    return SeedError(f"seed {_position(seed)} has no reflector pick of the requested polarity within {window:g} "
                     f"samples{where}; move it onto the event or choose another polarity", seed, nearest, window)


def _position(values) -> str:
    return "(" + ", ".join(f"{float(v):g}" for v in values) + ")"


def fill_horizon(horizon: Horizon, *, max_gap: float | None = None) -> Horizon:
    """Fill the empty traces of a horizon by interpolation (an explicit step: :func:`~seismo3d.seismic.track_horizon`
    never guesses).

    1D horizons are interpolated linearly between picks; 2D grids by linear interpolation over a Delaunay
    triangulation of the picked traces (scipy.interpolate.griddata), without extrapolation beyond their convex
    hull. Filled traces get confidence NaN.

    Parameters
    ----------
    horizon : Horizon
    max_gap : float, optional
        Fill only traces within this distance (traces) of a pick; default: all inside the hull.

    Returns
    -------
    Horizon
        A new horizon; the input is not modified. A labelled horizon (tracked in a DataArray) stays labelled: the
        same coordinates and unit.

    Raises
    ------
    InputError
        Fewer than 2 (1D) or 3 (2D) picks to interpolate from, or ``max_gap`` <= 0.
    """
    t = np.asarray(horizon.times, dtype=np.float64)
    have = np.isfinite(t)
    need = 2 if t.ndim == 1 else 3
    if have.sum() < need:
        raise InputError(f"the horizon has {int(have.sum())} picks; at least {need} are needed to interpolate")
    if max_gap is not None:
        check_positive(max_gap, "max_gap")
    if t.ndim == 1:
        x = np.arange(t.size)
        filled = np.interp(x, x[have], t[have], left=np.nan, right=np.nan)
    else:
        from scipy.interpolate import griddata  # on first use: 0.2-0.5 CPU s of `seismo3d horizon`'s start

        grid = np.indices(t.shape).reshape(t.ndim, -1).T.astype(np.float64)
        filled = griddata(grid[have.ravel()], t[have], grid, method="linear").reshape(t.shape)
    if max_gap is not None:
        far = distance_transform_edt(~have) > max_gap
        filled[far & ~have] = np.nan
    filled[have] = t[have]
    conf = np.where(have, horizon.confidence, np.nan).astype(np.float32)
    if is_data_array(horizon.times):  # on the same coordinates, in the same unit
        return Horizon(horizon.times.copy(data=filled), horizon.confidence.copy(data=conf), horizon.polarity,
                       horizon.seeds)
    return Horizon(filled.astype(np.float32), conf, horizon.polarity, horizon.seeds)


def write_horizon_text(path, horizon: Horizon, *, inlines=None, xlines=None, samples=None) -> int:
    """Write a horizon as "inline xline time" rows, one per picked trace (empty traces are skipped).

    The file is written atomically (a temporary file renamed over ``path``).

    Parameters
    ----------
    path : str or path-like
        Output text file.
    horizon : Horizon
        A 3D horizon (``times`` of shape (n_inlines, n_xlines)) or a 2D one ((n_traces,): rows are "trace time", or
        "inline xline time" when both labels are given). A labelled horizon (tracked in a DataArray) carries its
        labels: its inline and crossline numbers (a line's trace labels, or inline and crossline when the line has
        both), its times in its sample unit; ``inlines``, ``xlines`` and ``samples`` are then not given.
    inlines, xlines : (n_inlines,), (n_xlines,) array_like of int, optional
        Inline and crossline numbers of the grid (e.g. ``SeismicCube.inlines``); default: indices. For a 2D horizon,
        one number per trace each (the trace headers' inline and crossline).
    samples : (n_samples,) array_like of float, optional
        The sample axis in ms or m (``SeismicCube.samples``); fractional sample indices are converted by linear
        interpolation. Default: sample indices.

    Returns
    -------
    int
        Number of rows written.

    Raises
    ------
    InputError
        Axis lengths do not match the horizon's grid; labels given for a labelled horizon.
    """
    if is_data_array(horizon.times):
        if inlines is not None or xlines is not None or samples is not None:
            raise InputError("a horizon tracked in a DataArray carries its line numbers and times; leave out "
                             "inlines=, xlines= and samples=")
        inlines, xlines = _line_numbers(horizon.times)
    t = np.asarray(horizon.times, np.float64)
    grid = np.indices(t.shape).reshape(t.ndim, -1).T
    have = np.isfinite(t).ravel()
    cols = []
    if t.ndim == 1 and inlines is not None and xlines is not None:  # a 2D line labelled trace by trace
        for name, labels in (("inlines", inlines), ("xlines", xlines)):
            if np.shape(labels) != t.shape:
                raise InputError(f"{name} of a 2D line must hold one number per trace ({t.size}); got "
                                 f"{np.shape(labels)}")
        cols = [np.asarray(inlines)[have], np.asarray(xlines)[have]]
    for axis, labels in enumerate((inlines, xlines)[:t.ndim] if not cols else ()):
        if labels is None:
            cols.append(grid[have, axis])
            continue
        labels = np.asarray(labels)
        if labels.shape != (t.shape[axis],):
            raise InputError(f"axis {axis} has {t.shape[axis]} traces but {labels.shape} labels were given")
        cols.append(labels[grid[have, axis]])
    tv = t.ravel()[have]
    if samples is not None:
        s = np.asarray(samples, np.float64)
        if s.ndim != 1 or s.size < 2:
            raise InputError(f"samples must be the 1D sample axis of the cube; got shape {s.shape}")
        tv = np.interp(tv, np.arange(s.size), s, left=np.nan, right=np.nan)
    with atomic_path(path) as tmp:
        with open(tmp, "w") as fh:
            header = "inline xline time" if len(cols) == 2 else "trace time"
            fh.write(f"# {header}\n")
            for row in zip(*cols, tv):
                fh.write(" ".join(str(int(v)) for v in row[:-1]) + f" {row[-1]:.3f}\n")
    return int(have.sum())


def _line_numbers(times) -> tuple:
    """The (inlines, xlines) labels of a labelled horizon's rows for :func:`write_horizon_text`: a grid's inline and
    crossline numbers; a line's inline and crossline per trace when it has both (a line of a survey, a trace list
    with line numbers), else its trace labels and None."""
    dims = times.dims

    def numbers(name):
        return np.asarray(times.coords[name].values) if name in times.coords else None

    if len(dims) == 2:
        return (numbers(dims[0]) if dims[0] in times.coords else np.arange(times.shape[0]),
                numbers(dims[1]) if dims[1] in times.coords else np.arange(times.shape[1]))
    il, xl = numbers("iline"), numbers("xline")
    if il is not None and xl is not None:
        return np.broadcast_to(il, times.shape), np.broadcast_to(xl, times.shape)
    return (numbers(dims[0]) if dims[0] in times.coords else np.arange(times.shape[0])), None
