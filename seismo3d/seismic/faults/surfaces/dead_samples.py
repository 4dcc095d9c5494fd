"""Dead samples of seismic data: mutes, dead traces, zero padding and gaps, whose edges are not faults.

A sample is dead when it lies in a run of at least ``DEAD_RUN`` equal values along its trace at a *fill value*: 0, or
a value that fills a whole trace or a run of at least ``FILL_RUN`` samples somewhere in the data (a mute's or a
padding's value, such as the grey of an image export). Shorter runs at other values are the quantisation of slowly
varying amplitudes in integer exports, and runs at the data's smallest or largest value are clipped amplitudes (8-bit
exports of sections): neither is dead, unless it fills the whole trace.

:func:`clean_traces` applies this to an array in memory; :func:`fill_values`, :func:`dead_samples` and
:func:`near_dead_samples` are its steps, which also run block by block on a cube larger than memory (the fill values
gathered over every block first, from the data's global smallest and largest values): dead samples are found along
each trace, so a block needs no halo for them, and ``DEAD_REACH[0]`` traces of halo to grow them.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import numba as nb
from scipy.ndimage import maximum_filter1d

from ...._validation import check_seismic_layout
from ....errors import InputError, Seismo3dWarning

__all__ = ["CleanTraces", "clean_traces", "check_varies", "clipped_count", "fill_values", "dead_samples",
           "near_dead_samples", "warn_clipped", "warn_dead", "warn_non_finite", "DEAD_REACH"]

# Reach (traces, samples) of a dead zone's edge in fault_likelihood: the 3 x 3-trace semblance and the reflector slopes
# of the structure tensor (smoothed over about 2 traces and 6 samples) see the edge this far; likelihood this close to
# a dead sample is an artefact of the edge, not a fault.
DEAD_REACH = (3, 8)
# Fraction of samples at the data's extremes above which the data are reported as clipped (unclipped data such as F3
# and the synthetic cubes have a handful of such samples; 8-bit exports like the Penobscot sections, most of them).
_CLIPPED_WARN = 0.05
# Equal values in a row along a trace that make a run of dead samples (mute, dead trace, gap), at a fill value.
DEAD_RUN = 5
# A value that fills a run this long somewhere in the data (or a whole trace) is a fill value (a mute's or a padding's
# value) besides 0. Shorter runs at other values are the quantisation of slowly varying amplitudes in integer exports:
# in the 8-bit Penobscot sections a run of five 107s sits on a fault at inlines 1-2, and reading it as dead blanked
# the fault's likelihood over inlines 0-5.
FILL_RUN = 16


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
    """The differences inside runs of at least ``length`` equal values along the last axis (a morphological opening
    by a line of ``length - 1`` differences, as scipy's ``binary_opening`` gives it, in one pass per trace)."""
    m = equal.shape[-1]
    rows = np.ascontiguousarray(equal, dtype=bool).reshape(-1, m)
    out = np.zeros(rows.shape, dtype=bool)
    _true_runs(rows, min(length - 1, m), out)
    return out.reshape(equal.shape)


@nb.njit(cache=True, parallel=True)
def _true_runs(rows, length, out):
    # out[r, k]: rows[r, k] lies in a run of at least `length` Trues along the row
    m = rows.shape[1]
    for r in nb.prange(rows.shape[0]):
        k = 0
        while k < m:
            if not rows[r, k]:
                k += 1
                continue
            start = k
            while k < m and rows[r, k]:
                k += 1
            if k - start >= length:
                out[r, start:k] = True


def _fills(arr: np.ndarray, flat: np.ndarray) -> np.ndarray:
    whole = np.broadcast_to(flat.all(axis=-1, keepdims=True), flat.shape)
    return np.union1d([0.0], arr[..., 1:][_runs(flat, FILL_RUN) | whole]).astype(np.float32)


def _dead(arr: np.ndarray, flat: np.ndarray, fill: np.ndarray) -> np.ndarray:
    flat = _runs(flat, DEAD_RUN) & np.isin(arr[..., 1:], fill)
    dead = np.zeros(arr.shape, dtype=bool)
    dead[..., 1:] |= flat
    dead[..., :-1] |= flat
    return dead


def fill_values(data, lo: float, hi: float) -> np.ndarray:
    """The fill values of a block of traces: 0 and the values of its constant traces and of its runs of at least
    ``FILL_RUN`` equal samples that are not clipped amplitudes.

    Parameters
    ----------
    data : (..., n_samples) float32 ndarray
        Finite amplitudes; whole traces.
    lo, hi : float
        The smallest and largest value of the whole data (not only of this block): runs at them are clipped
        amplitudes.

    Returns
    -------
    (m,) float32 ndarray
        Sorted unique fill values; the fill values of a cube are the union over its blocks.
    """
    arr = np.asarray(data, dtype=np.float32)
    flat, clipped = _flat_samples(arr, lo, hi)
    flat &= ~clipped
    return _fills(arr, flat)


def dead_samples(data, fill, lo: float, hi: float) -> np.ndarray:
    """The dead samples of a block of traces: runs of at least ``DEAD_RUN`` equal values at a fill value.

    Parameters
    ----------
    data : (..., n_samples) float32 ndarray
        Finite amplitudes; whole traces.
    fill : (m,) array_like of float
        The data's fill values (the union of :func:`fill_values` over every block).
    lo, hi : float
        The smallest and largest value of the whole data.

    Returns
    -------
    bool ndarray, the shape of ``data``
        True on dead samples.
    """
    arr = np.asarray(data, dtype=np.float32)
    flat, clipped = _flat_samples(arr, lo, hi)
    flat &= ~clipped
    return _dead(arr, flat, np.asarray(fill, dtype=np.float32))


def near_dead_samples(dead: np.ndarray) -> np.ndarray:
    """Dead samples grown by ``DEAD_REACH`` (traces, samples): a box, by separable maximum filters.

    Parameters
    ----------
    dead : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) bool ndarray
        Dead samples (:func:`dead_samples`); a block of a cube needs ``DEAD_REACH[0]`` traces of halo.

    Returns
    -------
    bool ndarray, same shape
        True within ``DEAD_REACH`` of a dead sample: fault likelihood there is an artefact of the dead zone's edge.
    """
    near = np.ascontiguousarray(dead, dtype=bool).view(np.uint8)
    for axis in range(near.ndim):
        reach = DEAD_REACH[1] if axis == near.ndim - 1 else DEAD_REACH[0]
        if near.shape[axis] > 1:
            near = maximum_filter1d(near, 2 * reach + 1, axis=axis, mode="constant")
    return near.view(bool)


def clean_traces(data) -> CleanTraces:
    """Replace NaN / inf by 0 and find the dead samples, with a warning for each, and for clipped amplitudes.

    Dead samples are those in runs of at least ``DEAD_RUN`` equal values along a trace at a *fill value*: dead
    traces, mutes (the zeroed top of a survey), zero padding and NaN gaps. The fill values are 0 and every value that
    fills a whole trace or a run of at least ``FILL_RUN`` samples somewhere in the data (a mute or padding value
    such as the grey of an image export). Short runs at other values are quantisation (integer exports), and runs at
    the data's largest or smallest value are clipped amplitudes (8-bit exports of sections): neither is dead, unless
    it fills the whole trace.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, any real dtype.

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
        NaN / inf samples, dead samples, or clipped amplitudes (more than 5 % of the samples at the data's smallest or
        largest value).
    """
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
    warn_clipped(int(np.count_nonzero(clipped)), clipped.size)
    flat &= ~clipped
    del clipped
    dead = _dead(arr, flat, _fills(arr, flat))
    del flat
    warn_dead(int(np.count_nonzero(dead)), dead.size, int(np.count_nonzero(dead.all(axis=-1))))
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


def warn_clipped(n_clipped: int, n: int) -> None:
    """Warn when more than 5 % of the ``n`` sample steps are clipped amplitudes (:func:`clipped_count`).

    Warns
    -----
    Seismo3dWarning
        ``n_clipped / n`` above 5 %.
    """
    fraction = float(n_clipped) / n if n else 0.0
    if fraction > _CLIPPED_WARN:
        warnings.warn(f"{fraction:.0%} of the samples sit at the data's smallest or largest value: clipped "
                      "amplitudes (an 8-bit export?). Fault likelihood and throws are measured on the clipped "
                      "waveforms and are less reliable; trace the unclipped data if you have it",
                      Seismo3dWarning, stacklevel=3)


def warn_dead(n_dead: int, n: int, n_dead_traces: int) -> None:
    """Warn that ``n_dead`` of ``n`` samples are dead (``n_dead_traces`` whole traces).

    Warns
    -----
    Seismo3dWarning
        When ``n_dead > 0``.
    """
    if n_dead:
        warnings.warn(f"{n_dead / n:.1%} of the samples are constant over {DEAD_RUN} or more samples "
                      f"(mutes, gaps, {n_dead_traces} dead traces); fault likelihood within {DEAD_REACH[0]} traces "
                      f"and {DEAD_REACH[1]} samples of them is set to 0", Seismo3dWarning, stacklevel=3)
