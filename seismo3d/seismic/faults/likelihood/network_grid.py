"""The network grids: a section, cube or block resampled by a factor for the fault network
(:mod:`~seismo3d.seismic.faults.likelihood.network`), and its probability interpolated back onto the input's samples.

Below a factor of 1 the data is filtered by a Gaussian against aliasing (:func:`anti_alias_sigma`) and interpolated
linearly onto a grid whose last sample is at ``(n - 1) * factor`` (:func:`grid_size`); a block's grid is the whole
cube's (:func:`to_network_grid`'s ``origin`` and ``align``), so that the blocks of a cube give its probability
(:func:`grid_halo`: the halo a block needs for that).
:class:`~seismo3d.seismic.faults.likelihood.learned.LearnedOptions` chooses the grids (:func:`grid_factors` checks
them); the network's likelihood is the mean of their probabilities.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import gaussian_filter1d

from ....errors import InputError

__all__ = ["anti_alias_sigma", "grid_size", "grid_halo", "grid_factors", "to_network_grid", "from_network_grid",
           "interpolate_axis"]


def _check_factor(factor) -> float:
    f = float(factor)
    if not 0.25 <= f <= 1.0:
        raise InputError(f"the network's resampling factor must be in [0.25, 1]; got {factor!r}")
    return f


def anti_alias_sigma(factor: float) -> float:
    """Standard deviation (input samples) of the Gaussian filter applied before resampling by ``factor``.

    Parameters
    ----------
    factor : float
        Resampling factor in [0.25, 1] (1: no filter).

    Returns
    -------
    float
        ``0.5 / factor - 0.5``: 0 at 1, 0.5 samples at 0.5.

    Raises
    ------
    InputError
        ``factor`` is outside [0.25, 1].
    """
    return 0.5 / _check_factor(factor) - 0.5


def grid_size(n: int, factor: float) -> int:
    """Samples of the network grid along an axis of ``n`` input samples (the last at ``(n - 1) * factor``).

    Parameters
    ----------
    n : int
        Input samples along the axis.
    factor : float
        Resampling factor in [0.25, 1].

    Returns
    -------
    int

    Raises
    ------
    InputError
        ``factor`` is outside [0.25, 1].
    """
    return int(math.floor((int(n) - 1) * _check_factor(factor) + 1e-9)) + 1


def grid_halo(network_halo: int, factor: float, align: int) -> int:
    """Input samples of halo a block needs so that its core's probability equals the whole cube's.

    Parameters
    ----------
    network_halo : int
        Halo the network needs on its own grid (its receptive half).
    factor : float
        Resampling factor in [0.25, 1].
    align : int
        The network grid of a block starts at a multiple of this (up to ``align - 1`` network samples lost).

    Returns
    -------
    int
        Input samples: ``network_halo`` itself at factor 1 (the data's own grid, whose blocks start at multiples of
        ``align``), else a multiple of ``align``.

    Raises
    ------
    InputError
        ``factor`` is outside [0.25, 1].
    """
    f = _check_factor(factor)
    if f == 1.0:
        return int(network_halo)
    need = (int(network_halo) + int(align)) / f + 2 + 4 * anti_alias_sigma(f)
    return int(math.ceil(need / align)) * int(align)


def _first(origin: int, factor: float, align: int) -> int:
    """First network sample of a block whose first input sample is ``origin`` (a multiple of ``align``)."""
    return int(math.ceil(origin * factor / align - 1e-9)) * align


def _full_origin(origin, ndim: int) -> tuple:
    """The block's global index along every axis: ``origin`` along the lateral axes (0 when None), 0 along the
    sample axis."""
    return tuple(int(o) for o in (origin or (0,) * (ndim - 1))) + (0,)


def _lateral_aligns(align, n_lateral: int) -> tuple:
    """``align`` (an int, or one per lateral axis) as a tuple of ``n_lateral`` positive ints."""
    aligns = tuple(int(a) for a in align) if np.ndim(align) else (int(align),) * n_lateral
    if len(aligns) != n_lateral or min(aligns) < 1:
        raise InputError(f"align must be a positive int or one per lateral axis ({n_lateral}); got {align!r}")
    return aligns


def interpolate_axis(a: np.ndarray, axis: int, positions: np.ndarray) -> np.ndarray:
    """Values of ``a`` at fractional ``positions`` along ``axis``, interpolated linearly.

    Parameters
    ----------
    a : ndarray
        The values (float32 probabilities here).
    axis : int
        The axis interpolated along.
    positions : (m,) ndarray of float
        Local indices along ``axis``, within [0, n - 1].

    Returns
    -------
    ndarray
        ``a`` with ``m`` values along ``axis``, float32.
    """
    lo = np.floor(positions).astype(np.int64)
    lo = np.clip(lo, 0, max(a.shape[axis] - 2, 0))
    w = (positions - lo).astype(np.float32)
    hi = np.minimum(lo + 1, a.shape[axis] - 1)
    shape = [1] * a.ndim
    shape[axis] = -1
    w = w.reshape(shape)
    out = np.take(a, lo, axis=axis)  # in place: two arrays of the result's size at a time, not four
    out *= 1 - w
    upper = np.take(a, hi, axis=axis)
    upper *= w
    out += upper
    return out


def to_network_grid(data: np.ndarray, factor: float, *, origin=None, align: int = 8) -> tuple[np.ndarray, tuple]:
    """Resample a section, cube or block onto the network grid.

    Parameters
    ----------
    data : (n_traces, n_samples) or (n_inlines, n_xlines, n_samples) float32 ndarray
        Amplitudes (a block of a larger cube when ``origin`` is given).
    factor : float
        Resampling factor in [0.25, 1] along every axis.
    origin : sequence of int, optional
        Global index of ``data``'s first sample along each lateral axis (default 0: the whole input).
    align : int or sequence of int, optional
        Along the lateral axes the block's network grid starts at a multiple of this (one value per lateral axis,
        or one for all): the network's pooling multiple along an axis the network convolves over, 1 along an axis
        its sections are stacked on (no pooling grid to keep).

    Returns
    -------
    small : float32 ndarray
        The data on the network grid.
    first : tuple of int
        Global network index of ``small``'s first sample along each axis (0 along the sample axis).

    Raises
    ------
    InputError
        ``factor`` is outside [0.25, 1].
    """
    f = _check_factor(factor)
    arr = np.asarray(data, dtype=np.float32)
    origin = _full_origin(origin, arr.ndim)
    aligns = _lateral_aligns(align, arr.ndim - 1)
    if f == 1.0:
        return arr, origin
    # The Gaussian filter is separable and each axis's interpolation reads that axis only, so each axis is filtered
    # and interpolated in turn, the sample axis first: every later pass runs on the samples the earlier ones kept, and
    # the filter along the inlines, scipy's slowest (lines strided across the whole array; 0.27 CPU s of a 256^3 cube
    # against 0.08 along the samples), runs last on the smallest array. Onto the 0.7 grid of a 256^3 cube 0.60 -> 0.25
    # CPU s, onto the 0.5 grid 0.45 -> 0.35; the same linear operator as filtering the whole cube first, the rounding
    # of its float32 passes in another order (1e-6 of amplitudes of order 1).
    sigma = anti_alias_sigma(f)
    out = arr
    first = list(origin)
    for axis in reversed(range(arr.ndim)):
        n, o = arr.shape[axis], origin[axis]
        lateral = axis < arr.ndim - 1
        u0 = _first(o, f, aligns[axis]) if lateral else 0
        u1 = grid_size(o + n, f)  # one past the last network sample inside the data
        u = np.arange(u0, u1, dtype=np.float64)
        out = gaussian_filter1d(out, sigma, axis=axis, truncate=4.0)
        out = interpolate_axis(out, axis, u / f - o)
        first[axis] = u0
    return np.ascontiguousarray(out, dtype=np.float32), tuple(first)


def from_network_grid(small: np.ndarray, shape, factor: float, *, origin=None, first=None) -> np.ndarray:
    """Interpolate a probability on the network grid back onto the input's samples.

    Parameters
    ----------
    small : float32 ndarray
        Values on the network grid (:func:`to_network_grid`'s ``small``).
    shape : tuple of int
        Shape of the input block.
    factor : float
        The resampling factor.
    origin : sequence of int, optional
        Global lateral index of the input block's first sample (default 0).
    first : sequence of int, optional
        Global network index of ``small``'s first sample along each axis (:func:`to_network_grid`'s ``first``).

    Returns
    -------
    float32 ndarray of ``shape``

    Raises
    ------
    InputError
        ``factor`` is outside [0.25, 1].
    """
    f = _check_factor(factor)
    out = np.asarray(small, dtype=np.float32)
    if f == 1.0:
        return out
    origin = _full_origin(origin, len(shape))
    first = tuple(first or (0,) * len(shape))
    for axis, (n, o, u0) in enumerate(zip(shape, origin, first)):
        i = np.arange(o, o + n, dtype=np.float64)
        out = interpolate_axis(out, axis, np.clip(i * f - u0, 0, out.shape[axis] - 1))
    return np.ascontiguousarray(out, dtype=np.float32)


def grid_factors(name: str, value) -> tuple:
    """``value``, factors of the network grids (each in [0.25, 1], distinct), as floats; else an InputError."""
    try:
        factors = tuple(float(f) for f in ((value,) if np.ndim(value) == 0 else value))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a factor or a tuple of factors in [0.25, 1]; got {value!r}") from exc
    if not factors or len(set(factors)) != len(factors) or not all(0.25 <= f <= 1.0 for f in factors):
        raise InputError(f"{name} must be one or more distinct factors in [0.25, 1]; got {value!r}")
    return factors
