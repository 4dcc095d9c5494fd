"""Trace primitives: the sub-sample peak of a parabola, waveform windows, NCC and the lag search built on them.

Positions are fractional sample indices (sample ``k`` at ``k``); every function works on plain arrays and is used by
horizon tracking, fault throw, reflector picking and volume registration alike.
"""

from __future__ import annotations

import numpy as np

__all__ = ["parabolic_offset", "subsample_peak", "waveform", "ncc", "ncc_lag_search"]


def parabolic_offset(y_minus, y_0, y_plus):
    """Sub-sample offset of a peak from the vertex of the parabola through three equally spaced samples.

    Parameters
    ----------
    y_minus, y_0, y_plus : float or array_like of float, broadcastable
        Values one sample before, at and one sample after the peak sample (any real dtype; the arithmetic is done in
        it, so float32 inputs give float32 offsets).

    Returns
    -------
    float or ndarray
        ``0.5 (y_minus - y_plus) / (y_minus - 2 y_0 + y_plus)`` where the curvature is negative (a maximum), clipped
        to [-0.5, 0.5]; 0 elsewhere (a minimum or a straight line). Add it to the peak sample's index. For a
        minimum, pass the negated values.

    References
    ----------
    .. [1] J. O. Smith, "Spectral Audio Signal Processing", W3K Publishing, 2011, section "Quadratic Interpolation of
       Spectral Peaks".

    Examples
    --------
    >>> round(float(parabolic_offset(1.0, 2.0, 1.5)), 4)   # the vertex lies a sixth of a sample after the peak
    0.1667
    """
    den = y_minus - 2.0 * y_0 + y_plus
    return np.clip(np.where(den < 0, 0.5 * (y_minus - y_plus) / np.where(den < 0, den, -1.0), 0.0), -0.5, 0.5)


def subsample_peak(scores, k: int) -> float:
    """Sub-sample offset of the peak at index ``k`` of a score series (a correlation over lags), from the parabola
    through ``scores[k - 1: k + 2]``; 0 at either end of the series or next to a NaN.

    Parameters
    ----------
    scores : (n,) array_like of float
        Scores over evenly spaced lags; NaN where a lag could not be scored.
    k : int
        Index of the peak (e.g. ``np.nanargmax(scores)``).

    Returns
    -------
    float
        Offset in [-0.5, 0.5] lag steps, to add to ``k`` (see :func:`parabolic_offset`).
    """
    s = np.asarray(scores, dtype=np.float64)
    if not 0 < k < s.size - 1 or not np.isfinite(s[k - 1:k + 2]).all():
        return 0.0
    return float(parabolic_offset(s[k - 1], s[k], s[k + 1]))


def waveform(trace, t: float, half: int) -> np.ndarray:
    """Amplitudes of a trace at ``t - half .. t + half`` samples, by linear interpolation.

    Parameters
    ----------
    trace : (n_samples,) array_like of float
        One trace.
    t : float
        Centre, fractional sample index.
    half : int
        Half-length of the window, samples.

    Returns
    -------
    (2 half + 1,) float64 ndarray
        NaN where the window leaves the trace.
    """
    s = t + np.arange(-half, half + 1, dtype=np.float64)
    return np.interp(s, np.arange(np.shape(trace)[0]), trace, left=np.nan, right=np.nan)


def ncc(a, b, *, min_samples: int = 5) -> float:
    """Normalised cross-correlation (Pearson correlation) of two equally long windows, over their finite samples.

    Parameters
    ----------
    a, b : (n,) array_like of float
        The two windows; NaN where a window has no value (it is left out of both).
    min_samples : int
        Fewest samples finite in both for a correlation.

    Returns
    -------
    float
        In [-1, 1]; NaN with fewer than ``min_samples`` shared finite samples, 0 when a window is constant.

    References
    ----------
    .. [1] J. P. Lewis, "Fast normalized cross-correlation", Vision Interface, 1995.
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < min_samples:
        return np.nan
    a = a[ok] - a[ok].mean()
    b = b[ok] - b[ok].mean()
    den = np.sqrt((a * a).sum() * (b * b).sum())
    return float((a * b).sum() / den) if den > 0 else 0.0


def ncc_lag_search(reference, signal, max_lag: int) -> float:
    """The lag (samples, sub-sample) at which a window of ``signal`` correlates best with ``reference``.

    ``reference`` holds ``2 h + 1`` samples; ``signal`` holds the same window extended by ``max_lag`` samples at both
    ends (``2 h + 1 + 2 max_lag``). Each lag ``s`` in ``-max_lag..max_lag`` is scored by :func:`ncc` of
    ``reference`` with ``signal[max_lag + s: max_lag + s + 2 h + 1]``; the best one is refined by
    :func:`subsample_peak`.

    Parameters
    ----------
    reference : (2 h + 1,) array_like of float
        The reference window (NaN where absent).
    signal : (2 h + 1 + 2 max_lag,) array_like of float
        The searched signal, centred like ``reference`` (NaN where absent).
    max_lag : int
        Largest lag searched, samples.

    Returns
    -------
    float
        The lag, positive when ``signal`` is delayed (its event lies at later samples); 0 when no lag correlates
        (too few finite samples everywhere).
    """
    ref = np.asarray(reference, dtype=np.float64)
    sig = np.asarray(signal, dtype=np.float64)
    n = ref.size
    scores = np.array([ncc(ref, sig[max_lag + s:max_lag + s + n]) for s in range(-max_lag, max_lag + 1)])
    if not np.isfinite(scores).any():
        return 0.0
    k = int(np.nanargmax(scores))
    return float(k - max_lag) + subsample_peak(scores, k)
