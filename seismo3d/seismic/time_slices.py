"""Time-slice exports: blank time slices (samples at which every trace holds the same value) found and filled from the
slices above and below, and then each slice's own offset and gain removed, before faults are traced.

A cube exported as time-slice images (map views, each rendered to 8 bits between its own smallest and largest value)
holds a blank image wherever a slice was missing or flat: the whole slice at one grey, often black or white, the
data's extremes. No recorded time slice is the same on every trace (even a flat reflector's amplitude varies with the
noise from trace to trace), so such a slice is missing data. Left in, it is a perfectly flat, laterally constant event
of extreme amplitude crossing every fault: the fault network reads the faults as broken by nothing, and the throw
measurement finds sides that match with no shift (on the real Parihaka time slices of the data folder, 7 blank slices
in 128 halved the network's probability along its large fault, 0.86 -> 0.46, and the fault was dropped).

:func:`blank_slices` finds them: samples, between the first and the last live ones, at which every trace that is not
constant along itself (a dead trace) holds one value. :func:`filled_slices` replaces each by linear interpolation
along the traces between the nearest slices that are not blank (the nearest one beyond the last or before the first).
Dead samples of runs along the traces (mutes, padding, gaps: :mod:`~seismo3d.seismic.amplitudes`) are not blank
slices unless they fill a whole slice, and such slices at the top or bottom are left to the dead-sample rules (a
muted top is not filled).

A blank slice also tells how the data was made: each slice rendered as an image of its own, scaled by its own smallest
and largest value, so that every slice carries its own gain and offset (horizontal stripes on sections, continuous
across every fault). :func:`balanced_slices` then removes each slice's mean and brings its interquartile range to
the slices' typical one. It is not done on data without a blank slice: no statistic of the slices alone told the
Parihaka slices from recorded data (their medians' roughness along the samples, 0.38-0.49, is that of their traces,
0.38-0.43, as on the F3 cube, 11 real lines and generated cubes; their medians' jumps between slices, 0.62-0.66
interquartile ranges, against 0.06-0.48 there), and on a cube of flat reflectors removing the slices' means removes
the reflectors. Measured on the Parihaka slices 45-172: the network's mean probability along the large fault 0.46 as
exported, 0.81 with the blank slices filled, 0.87 balanced too; generated sections and 96^3 cubes exported so (six
blank slices) keep precision and recall of 0.98-1.0 (``tests/seismic/test_time_slices.py``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["balanced_slices", "blank_slices", "filled_slices", "slice_extremes"]

# Traces read for the slices' means and spreads: every trace up to this many samples, a regular lateral
# subsample beyond (as the network's amplitude scale, seismo3d.seismic.faults.likelihood.learned)
_STAT_SAMPLES = 4_000_000


def blank_slices(smallest: np.ndarray, largest: np.ndarray) -> np.ndarray:
    """The blank time slices from each slice's smallest and largest value over the live traces.

    Parameters
    ----------
    smallest, largest : (n_samples,) array_like of float
        Smallest and largest value of each time slice over the traces that are not constant along themselves
        (:func:`slice_extremes`).

    Returns
    -------
    (n_samples,) bool ndarray
        True at the samples whose slice holds one value, between two samples whose slices do not (the top and the
        bottom of the traces are never blank: a mute or padding there is the dead-sample rules' to judge). All False
        when every slice, or none, is blank.
    """
    lo, hi = np.asarray(smallest, np.float64), np.asarray(largest, np.float64)
    flat = lo == hi
    varies = np.nonzero(~flat)[0]
    blank = np.zeros(flat.shape, dtype=bool)
    if varies.size >= 2:
        blank[varies[0]:varies[-1] + 1] = flat[varies[0]:varies[-1] + 1]
    return blank


def slice_extremes(data) -> tuple[np.ndarray, np.ndarray]:
    """Smallest and largest value of each time slice over the traces that vary along themselves (a dead trace, one
    value along all of it, is left out).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) ndarray or dask.array.Array
        Finite amplitudes, samples along the last axis (a dask array: one pass over its blocks).

    Returns
    -------
    smallest, largest : (n_samples,) float64 ndarray
        Both 0 where no trace varies.
    """
    lateral = tuple(range(np.ndim(data) - 1))
    varies = (data.max(axis=-1) > data.min(axis=-1))[..., None]
    lo = np.where(varies, data, np.inf).min(axis=lateral)
    hi = np.where(varies, data, -np.inf).max(axis=lateral)
    if hasattr(lo, "compute"):
        import dask

        lo, hi = dask.compute(lo, hi)
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    none = ~np.isfinite(lo)
    lo[none], hi[none] = 0.0, 0.0
    return lo, hi


def filled_slices(data, blank: np.ndarray):
    """The amplitudes with each blank time slice interpolated linearly along the traces between the nearest slices
    that are not blank.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray or dask.array.Array
        Amplitudes, samples along the last axis (a dask array in chunks of whole traces).
    blank : (n_samples,) bool ndarray
        From :func:`blank_slices`.

    Returns
    -------
    float32 array of the type and shape of ``data``
        ``data`` itself when no slice is blank.
    """
    blank = np.asarray(blank, dtype=bool)
    if not blank.any():
        return data
    k = np.arange(blank.size)
    live = k[~blank]
    after = np.clip(np.searchsorted(live, k), 0, live.size - 1)
    before = np.clip(after - 1, 0, live.size - 1)
    lo, hi = live[before], live[after]
    weight = np.where(hi > lo, (k - lo) / np.maximum(hi - lo, 1), 0.0)
    rows = np.nonzero(blank)[0]
    if hasattr(data, "map_blocks"):
        return data.map_blocks(_fill_block, rows, lo[rows], hi[rows], weight[rows].astype(np.float32),
                               dtype=np.float32)
    return _fill_block(data, rows, lo[rows], hi[rows], weight[rows].astype(np.float32))


def _fill_block(block, rows, lo, hi, weight):
    """A block of whole traces with the samples ``rows`` interpolated between the samples ``lo`` and ``hi``."""
    out = np.array(block, dtype=np.float32)
    out[..., rows] = (1.0 - weight) * out[..., lo] + weight * out[..., hi]
    return out


def balanced_slices(data, blank: np.ndarray):
    """The amplitudes of a time-slice export with each slice's own offset and gain undone as far as the data allow:
    ``(x - mean) * typical / spread`` per time slice, the mean and the interquartile range over the traces that vary
    along themselves, ``typical`` the median of the slices' spreads (the data's amplitude scale kept). The mean, not
    the median: an 8-bit slice's median is one of its values, and runs of samples at it along a trace would become
    runs of zeros, read as dead samples.

    An export that holds blank slices (:func:`blank_slices`) rendered each slice as an image of its own, scaled by its
    own smallest and largest value: its slices carry their own gain and offset, horizontal stripes on sections that
    are continuous across every fault. What the slices held in common (a flat reflector's mean amplitude) is lost
    with the offsets; the traces' shapes within each slice are kept.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray or dask.array.Array
        Amplitudes with the blank slices filled (:func:`filled_slices`), samples along the last axis (a dask array
        in chunks of whole traces; a lateral subsample of about 4 million samples is read for the statistics).
    blank : (n_samples,) bool ndarray
        From :func:`blank_slices`: the slices are balanced when one is blank; else ``data`` is returned as it is.

    Returns
    -------
    float32 array of the type and shape of ``data``
        Traces with one value along all of them (dead traces) unchanged; a slice of one value over the live traces
        unchanged.
    """
    if not np.asarray(blank, dtype=bool).any():
        return data
    shape = tuple(int(n) for n in np.shape(data))
    total = float(np.prod(shape, dtype=np.float64))
    stride = max(1, int(np.ceil((total / _STAT_SAMPLES) ** (1.0 / (len(shape) - 1)))))
    sub = data[tuple(slice(None, None, stride) for _ in shape[:-1]) + (slice(None),)]
    traces = np.asarray(sub.compute() if hasattr(sub, "compute") else sub, np.float64).reshape(-1, shape[-1])
    traces = traces[traces.max(axis=-1) > traces.min(axis=-1)]
    if traces.shape[0] == 0:
        return data
    q25, q75 = np.quantile(traces, [0.25, 0.75], axis=0)
    spread = q75 - q25
    ok = spread > 0
    if not ok.any():
        return data
    typical = float(np.median(spread[ok]))
    factor = np.where(ok, typical / np.where(ok, spread, 1.0), 1.0).astype(np.float32)
    offset = np.where(ok, traces.mean(axis=0), 0.0).astype(np.float32)
    if hasattr(data, "map_blocks"):
        return data.map_blocks(_balance_block, offset, factor, dtype=np.float32)
    return _balance_block(data, offset, factor)


def _balance_block(block, offset, factor):
    """A block of whole traces balanced slice by slice, its dead traces (one value along them) unchanged."""
    block = np.asarray(block, dtype=np.float32)
    out = (block - offset) * factor
    dead = block.max(axis=-1) == block.min(axis=-1)
    if dead.any():
        out[dead] = block[dead]
    return out
