"""What the amplitudes of a seismic cube are worth before it is interpreted: NaN / inf, constant data, clipped
amplitudes, dead samples (mutes, dead traces, zero padding and gaps, whose edges are not faults), and whether the
traces oscillate like seismic amplitudes at all (not a velocity or impedance model).

A sample is dead when it lies in a run of at least ``DeadSampleOptions.run`` equal values along its trace at a *fill
value*: 0, or a value that fills a whole trace or a run of at least ``DeadSampleOptions.fill_run`` samples somewhere
in the data (a mute's or a
padding's value, such as the grey of an image export). Shorter runs at other values are the quantisation of slowly
varying amplitudes in integer exports, and runs at the data's smallest or largest value are clipped amplitudes (8-bit
exports of sections): neither is dead, unless it fills the whole trace.

:func:`clean_traces` applies this to an array in memory; :func:`fill_values`, :func:`dead_samples` and
:func:`near_dead_samples` are its steps, which also run block by block on a cube larger than memory (the fill values
gathered over every block first, from the data's global smallest and largest values): dead samples are found along
each trace, so a block needs no halo for them, and ``DeadSampleOptions.reach[0]`` traces of halo to grow them.
:func:`finite_cube` makes the checks :func:`clean_traces` makes in memory from passes over the blocks of a lazy cube;
:func:`check_amplitudes` refuses traces that do not cross their mean like seismic reflections.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import binary_opening, maximum_filter1d

from .._validation import check_int, check_positive, check_seismic_layout
from ..errors import InputError, Seismo3dWarning, UnsupportedDataError

__all__ = ["CleanTraces", "CubeAmplitudes", "DeadSampleOptions", "check_amplitudes", "check_finite", "check_varies",
           "clean_traces", "clipped_count", "dead_samples", "fill_values", "finite_cube", "near_dead_samples",
           "warn_clipped", "warn_dead", "warn_non_finite"]


@dataclass(frozen=True)
class DeadSampleOptions:
    """What counts as a dead sample (mutes, dead traces, zero padding, gaps), and how far a dead zone's edge reaches.

    Attributes
    ----------
    run : int
        Equal values in a row along a trace that make a run of dead samples, at a fill value (default 5).
    fill_run : int
        A value that fills a run this long somewhere in the data (or a whole trace) is a fill value (a mute's or a
        padding's value) besides 0 (default 16). Shorter runs at other values are the quantisation of slowly varying
        amplitudes in integer exports: in the 8-bit Penobscot sections a run of five 107s sits on a fault at inlines
        1-2, and reading it as dead blanked the fault's likelihood over inlines 0-5.
    reach : (int, int)
        Reach (traces, samples) of a dead zone's edge in the fault likelihood (default (3, 8)): the 3 x 3-trace
        semblance and the reflector slopes of the structure tensor (smoothed over about 2 traces and 6 samples) see
        the edge this far; likelihood this close to a dead sample is an artefact of the edge, not a fault.
    clipped_warning : float
        Fraction of the samples at the data's extremes above which the data are reported as clipped (default 0.05:
        unclipped data such as F3 and the synthetic cubes have a handful of such samples; 8-bit exports like the
        Penobscot sections, most of them).

    Raises
    ------
    InputError
        On construction: a run below 2 samples, a negative reach, a fraction outside [0, 1].
    """

    run: int = 5
    fill_run: int = 16
    reach: tuple = (3, 8)
    clipped_warning: float = 0.05

    def __post_init__(self):
        check_int(self.run, "DeadSampleOptions.run", minimum=2)
        check_int(self.fill_run, "DeadSampleOptions.fill_run", minimum=2)
        if (not isinstance(self.reach, tuple) or len(self.reach) != 2
                or any(isinstance(r, bool) or not isinstance(r, (int, np.integer)) or r < 0 for r in self.reach)):
            raise InputError(f"DeadSampleOptions.reach must be (traces, samples), two integers >= 0; got "
                             f"{self.reach!r}")
        check_positive(self.clipped_warning, "DeadSampleOptions.clipped_warning", allow_zero=True)
        if self.clipped_warning > 1:
            raise InputError(f"DeadSampleOptions.clipped_warning is a fraction in [0, 1]; got {self.clipped_warning!r}")


def _options(options) -> DeadSampleOptions:
    if options is None:
        return DeadSampleOptions()
    if not isinstance(options, DeadSampleOptions):
        raise InputError(f"options must be a DeadSampleOptions; got {type(options).__name__}")
    return options


@dataclass(frozen=True, eq=False)
class CleanTraces:
    """Result of :func:`clean_traces`.

    Attributes
    ----------
    data : float32 ndarray
        The data with NaN / inf read as 0.
    dead : bool ndarray, same shape
        True on dead samples.
    """

    data: np.ndarray
    dead: np.ndarray


def _flat_samples(arr: np.ndarray, lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """(flat, clipped), both (..., n_samples - 1) bool: sample k + 1 equals sample k; sample k + 1 sits at the data's
    smallest ``lo`` or largest ``hi`` value (on a trace that is not constant)."""
    flat = np.diff(arr, axis=-1) == 0
    clipped = (arr[..., 1:] == lo) | (arr[..., 1:] == hi)
    clipped &= ~flat.all(axis=-1, keepdims=True)
    return flat, clipped


def _runs(equal: np.ndarray, length: int) -> np.ndarray:
    """The differences inside runs of at least ``length`` equal values along the last axis: a morphological opening
    by a line of ``length - 1`` differences (scipy's ``binary_opening``; a trace shorter than the line is one run when
    all its differences are), of the traces holding an equal pair only: the line opens each trace alone, and most
    traces of most cubes hold none (a float cube of 512 x 512 x 256 with a few equal neighbours: 8 CPU s spared)."""
    out = np.zeros(equal.shape, dtype=bool)
    held = np.asarray(equal, dtype=bool).any(axis=-1)
    if equal.shape[-1] == 0 or not held.any():
        return out
    line = np.ones((1, min(length - 1, equal.shape[-1])), dtype=bool)
    out[held] = binary_opening(np.asarray(equal, dtype=bool)[held], structure=line)
    return out


def _fills(arr: np.ndarray, flat: np.ndarray, opt: DeadSampleOptions) -> np.ndarray:
    whole = np.broadcast_to(flat.all(axis=-1, keepdims=True), flat.shape)
    return np.union1d([0.0], arr[..., 1:][_runs(flat, opt.fill_run) | whole]).astype(np.float32)


def _dead(arr: np.ndarray, flat: np.ndarray, fill: np.ndarray, opt: DeadSampleOptions) -> np.ndarray:
    flat = _runs(flat, opt.run) & np.isin(arr[..., 1:], fill)
    dead = np.zeros(arr.shape, dtype=bool)
    dead[..., 1:] |= flat
    dead[..., :-1] |= flat
    return dead


def fill_values(data, lo: float, hi: float, *, options: DeadSampleOptions | None = None) -> np.ndarray:
    """The fill values of a block of traces: 0 and the values of its constant traces and of its runs of at least
    ``options.fill_run`` equal samples that are not clipped amplitudes.

    Parameters
    ----------
    data : (..., n_samples) float32 ndarray
        Finite amplitudes; whole traces.
    lo, hi : float
        The smallest and largest value of the whole data (not only of this block): runs at them are clipped
        amplitudes.
    options : DeadSampleOptions, optional
        What counts as a dead sample (default :class:`DeadSampleOptions`).

    Returns
    -------
    (m,) float32 ndarray
        Sorted unique fill values; the fill values of a cube are the union over its blocks.
    """
    opt = _options(options)
    arr = np.asarray(data, dtype=np.float32)
    flat, clipped = _flat_samples(arr, lo, hi)
    flat &= ~clipped
    return _fills(arr, flat, opt)


def dead_samples(data, fill, lo: float, hi: float, *, options: DeadSampleOptions | None = None) -> np.ndarray:
    """The dead samples of a block of traces: runs of at least ``options.run`` equal values at a fill value.

    Parameters
    ----------
    data : (..., n_samples) float32 ndarray
        Finite amplitudes; whole traces.
    fill : (m,) array_like of float
        The data's fill values (the union of :func:`fill_values` over every block).
    lo, hi : float
        The smallest and largest value of the whole data.
    options : DeadSampleOptions, optional
        What counts as a dead sample (default :class:`DeadSampleOptions`).

    Returns
    -------
    bool ndarray, the shape of ``data``
        True on dead samples.
    """
    opt = _options(options)
    arr = np.asarray(data, dtype=np.float32)
    flat, clipped = _flat_samples(arr, lo, hi)
    flat &= ~clipped
    return _dead(arr, flat, np.asarray(fill, dtype=np.float32), opt)


def near_dead_samples(dead: np.ndarray, *, options: DeadSampleOptions | None = None) -> np.ndarray:
    """Dead samples grown by ``options.reach`` (traces, samples): a box, by separable maximum filters.

    Parameters
    ----------
    dead : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) bool ndarray
        Dead samples (:func:`dead_samples`); a block of a cube needs ``options.reach[0]`` traces of halo.
    options : DeadSampleOptions, optional
        What counts as a dead sample (default :class:`DeadSampleOptions`).

    Returns
    -------
    bool ndarray, same shape
        True within ``options.reach`` of a dead sample: fault likelihood there is an artefact of the dead zone's
        edge.
    """
    opt = _options(options)
    near = np.ascontiguousarray(dead, dtype=bool).view(np.uint8)
    for axis in range(near.ndim):
        reach = opt.reach[1] if axis == near.ndim - 1 else opt.reach[0]
        if near.shape[axis] > 1:
            near = maximum_filter1d(near, 2 * reach + 1, axis=axis, mode="constant")
    return near.view(bool)


def clean_traces(data, *, options: DeadSampleOptions | None = None) -> CleanTraces:
    """Replace NaN / inf by 0 and find the dead samples, with a warning for each, and for clipped amplitudes.

    Dead samples are those in runs of at least ``options.run`` equal values along a trace at a *fill value*: dead
    traces, mutes (the zeroed top of a survey), zero padding and NaN gaps. The fill values are 0 and every value that
    fills a whole trace or a run of at least ``options.fill_run`` samples somewhere in the data (a mute or padding value
    such as the grey of an image export). Short runs at other values are quantisation (integer exports), and runs at
    the data's largest or smallest value are clipped amplitudes (8-bit exports of sections): neither is dead, unless
    it fills the whole trace.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, any real dtype.
    options : DeadSampleOptions, optional
        What counts as a dead sample (default :class:`DeadSampleOptions`).

    Returns
    -------
    CleanTraces
        ``data`` (float32) and the ``dead`` mask.

    Raises
    ------
    InputError
        Not a numeric 2D / 3D array with at least 3 samples per axis, or every sample equal.

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples, dead samples, or clipped amplitudes (more than ``options.clipped_warning`` of the samples
        at the data's smallest or largest value).
    """
    opt = _options(options)
    arr = np.asarray(data)
    check_seismic_layout(arr.shape, arr.dtype)
    arr = np.asarray(arr, dtype=np.float32)
    finite = np.isfinite(arr)
    if not finite.all():
        warn_non_finite(int(arr.size - np.count_nonzero(finite)), arr.size)
        arr = np.where(finite, arr, np.float32(0.0))
    del finite
    lo, hi = arr.min(), arr.max()
    check_varies(lo, hi)
    flat, clipped = _flat_samples(arr, lo, hi)
    warn_clipped(int(np.count_nonzero(clipped)), clipped.size, options=opt)
    flat &= ~clipped
    del clipped
    dead = _dead(arr, flat, _fills(arr, flat, opt), opt)
    del flat
    warn_dead(int(np.count_nonzero(dead)), dead.size, int(np.count_nonzero(dead.all(axis=-1))), options=opt)
    return CleanTraces(arr, dead)


def clipped_count(data, lo: float, hi: float) -> int:
    """Samples of a block of whole traces at the data's smallest ``lo`` or largest ``hi`` value (after the first of
    each trace, on traces that are not constant): summed over the blocks, the count :func:`warn_clipped` takes.

    Returns
    -------
    int
    """
    _, clipped = _flat_samples(np.asarray(data, dtype=np.float32), lo, hi)
    return int(np.count_nonzero(clipped))


def warn_non_finite(n_bad: int, n: int) -> None:
    """Warn that ``n_bad`` of ``n`` samples are NaN or inf (read as 0).

    Warns
    -----
    Seismo3dWarning
        When ``n_bad > 0``.
    """
    if n_bad:
        warnings.warn(f"data has {n_bad} NaN or inf samples ({n_bad / n:.1%}); they are read as 0, and "
                      "runs of them are skipped like dead traces", Seismo3dWarning, stacklevel=3)


def check_finite(values, inlines: tuple | None = None) -> None:
    """Refuse amplitudes that hold NaN or inf, in a likelihood by blocks called directly (``trace_faults`` reads them
    as 0 with a warning before its blocks: :func:`finite_cube`).

    Parameters
    ----------
    values : array_like or float
        Amplitudes of a block, or statistics of the cube (its peak, its sum of squares).
    inlines : (int, int), optional
        The first and last inline (indices) of the block, named in the message.

    Raises
    ------
    InputError
        Naming the inlines when given.
    """
    if not np.all(np.isfinite(values)):
        where = "" if inlines is None else f" in inlines {inlines[0]}-{inlines[1]} (indices)"
        raise InputError(f"the cube holds NaN or infinite amplitudes{where}; replace them (e.g. by 0) before "
                         "tracing faults")


def check_varies(lo: float, hi: float) -> None:
    """Refuse data whose smallest and largest values (NaN read as 0) are equal.

    Raises
    ------
    InputError
        ``lo == hi``.
    """
    if lo == hi:
        raise InputError("every sample has the same value (or is NaN): there are no reflectors to trace faults in; "
                         "check that the file is the right one and that its data format is read correctly")


def warn_clipped(n_clipped: int, n: int, *, options: DeadSampleOptions | None = None) -> None:
    """Warn when more than ``options.clipped_warning`` of the ``n`` sample steps are clipped amplitudes
    (:func:`clipped_count`).

    Warns
    -----
    Seismo3dWarning
        ``n_clipped / n`` above ``options.clipped_warning`` (default 5 %).
    """
    fraction = float(n_clipped) / n if n else 0.0
    if fraction > _options(options).clipped_warning:
        warnings.warn(f"{fraction:.0%} of the samples sit at the data's smallest or largest value: clipped "
                      "amplitudes (an 8-bit export?). Fault likelihood and throws are measured on the clipped "
                      "waveforms and are less reliable; trace the unclipped data if you have it",
                      Seismo3dWarning, stacklevel=3)


def warn_dead(n_dead: int, n: int, n_dead_traces: int, *, options: DeadSampleOptions | None = None) -> None:
    """Warn that ``n_dead`` of ``n`` samples are dead (``n_dead_traces`` whole traces).

    Warns
    -----
    Seismo3dWarning
        When ``n_dead > 0``.
    """
    opt = _options(options)
    if n_dead:
        warnings.warn(f"{n_dead / n:.1%} of the samples are constant over {opt.run} or more samples "
                      f"(mutes, gaps, {n_dead_traces} dead traces); fault likelihood within {opt.reach[0]} traces "
                      f"and {opt.reach[1]} samples of them is set to 0", Seismo3dWarning, stacklevel=3)


def check_amplitudes(arr: np.ndarray, dead: np.ndarray, min_crossings: float) -> None:
    """Refuse data whose traces do not oscillate like seismic amplitudes (median zero crossings per 100 samples below
    ``min_crossings``, over up to about 4000 live traces).

    Parameters
    ----------
    arr : (..., n_samples) float ndarray
        Amplitudes (NaN-free, as :func:`clean_traces` returns them).
    dead : bool ndarray of ``arr``'s shape
        Dead samples.
    min_crossings : float
        Median crossings of a trace's mean per 100 samples below which the data is refused
        (:attr:`~seismo3d.seismic.FaultTracingOptions.min_crossings` for fault tracing).

    Raises
    ------
    UnsupportedDataError
        Every trace dead, or too few zero crossings.
    """
    live = ~dead.all(axis=-1)
    traces = arr[live] if arr.ndim == 2 else arr.reshape(-1, arr.shape[-1])[live.ravel()]
    traces = traces[:: max(1, traces.shape[0] // 4000)].astype(np.float64)
    if traces.shape[0] == 0:
        raise UnsupportedDataError("every trace is dead (constant): there is nothing to trace faults in")
    centred = traces - traces.mean(axis=1, keepdims=True)
    crossings = float(np.median(np.count_nonzero(np.diff(np.signbit(centred), axis=1), axis=1)))
    per_100 = 100.0 * crossings / traces.shape[1]
    if per_100 < min_crossings:
        raise UnsupportedDataError(
            f"the traces cross their mean {per_100:.1f} times per 100 samples (seismic reflections: 10-30 times): "
            "this is not seismic amplitude data (a velocity or impedance model?); fault tracing needs a stacked, "
            "migrated seismic image")


@dataclass(frozen=True)
class CubeAmplitudes:
    """What the dead-sample rules need of a whole cube, measured once over its blocks (:func:`finite_cube`) and
    given to every block after (:func:`dead_samples`).

    Attributes
    ----------
    lo, hi : float
        The cube's smallest and largest amplitude (NaN / inf read as 0).
    fill : tuple of float
        Its fill values, sorted: the union of :func:`fill_values` over its blocks (0 among them).
    """

    lo: float
    hi: float
    fill: tuple


def finite_cube(x, dead: DeadSampleOptions | None = None) -> tuple:
    """The cube with NaN / inf read as 0 (warned, as in memory); constant data refused, clipped amplitudes and dead
    samples warned about, from three passes over the blocks (the
    dead samples need the fill values of the whole cube).

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) float32 dask.array.Array
        Chunks of whole traces.
    dead : DeadSampleOptions, optional
        What counts as a dead sample (default :class:`DeadSampleOptions`).

    Returns
    -------
    x : dask.array.Array
        ``x``, or ``x`` with its NaN / inf samples read as 0.
    amplitudes : CubeAmplitudes
        Its smallest and largest amplitude and its fill values, for the dead samples of its blocks.

    Raises
    ------
    InputError
        Every sample equal (NaN read as 0).

    Warns
    -----
    Seismo3dWarning
        NaN / inf, clipped or dead samples (:func:`clean_traces`' warnings).
    """
    import dask
    import dask.array as da

    finite = da.isfinite(x)
    cleaned = da.where(finite, x, np.float32(0.0))
    n_bad, lo, hi = dask.compute(da.sum(~finite), da.min(cleaned), da.max(cleaned))
    n = int(np.prod(x.shape, dtype=np.int64))
    warn_non_finite(int(n_bad), n)
    check_varies(float(lo), float(hi))
    x = cleaned if n_bad else x
    lo, hi = np.float32(lo), np.float32(hi)
    parts = [dask.delayed(_clipped_and_fills)(b, lo, hi, dead) for b in x.to_delayed().ravel()]
    parts = dask.compute(*parts)
    warn_clipped(sum(p[0] for p in parts), n - int(np.prod(x.shape[:-1], dtype=np.int64)), options=dead)
    fill = np.unique(np.concatenate([p[1] for p in parts]))
    counts = dask.compute(*[dask.delayed(_dead_counts)(b, fill, lo, hi, dead) for b in x.to_delayed().ravel()])
    warn_dead(sum(d[0] for d in counts), n, sum(d[1] for d in counts), options=dead)
    return x, CubeAmplitudes(float(lo), float(hi), tuple(float(v) for v in fill))


def _clipped_and_fills(block, lo, hi, dead) -> tuple:
    """(clipped samples, fill values) of a block of whole traces."""
    block = np.asarray(block, np.float32)
    return clipped_count(block, lo, hi), fill_values(block, lo, hi, options=dead)


def _dead_counts(block, fill, lo, hi, options) -> tuple[int, int]:
    """(dead samples, dead traces) of a block of whole traces."""
    dead = dead_samples(np.asarray(block, np.float32), fill, lo, hi, options=options)
    return int(np.count_nonzero(dead)), int(np.count_nonzero(dead.all(axis=-1)))

