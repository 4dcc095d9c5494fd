"""Dominant orientations of circular windows and their ring histograms shifted to start at each (the HOG-pyramid
descriptor's rotation invariance, method.md: the HOG matcher).

Internal module: inputs are trusted (validated by :func:`seismo3d.features.hog_pyramid.ring_descriptors`). Regular
array work over all windows at once: discrete Fourier series as matrix products, the peaks of every window's smoothed
orientation histogram on a fine grid, the rings resampled at each peak through their Fourier series.
"""

from __future__ import annotations

import numpy as np


def _bin_tables(q: int) -> tuple[np.ndarray, np.ndarray]:
    """cos / sin of 2 pi m b / q, (q // 2 + 1, q) float64: the one-sided Fourier series over the ``q`` bins."""
    phase = 2.0 * np.pi * np.arange(q // 2 + 1, dtype=np.float64)[:, None] * np.arange(q)[None, :] / q
    return np.cos(phase), np.sin(phase)


def _grid_tables(q: int, up: int) -> tuple[np.ndarray, np.ndarray]:
    """cos / sin of 2 pi m t / up, (up, q // 2 + 1) float64: the series evaluated on a grid of ``up`` samples."""
    phase = 2.0 * np.pi * np.arange(up)[:, None] * np.arange(q // 2 + 1, dtype=np.float64)[None, :] / up
    return np.cos(phase), np.sin(phase)


def _one_sided(q: int) -> np.ndarray:
    """Weights of the one-sided Fourier series of a real signal of ``q`` samples, (q // 2 + 1,): 1 for the mean
    (and the Nyquist term of an even ``q``), 2 for the others."""
    w = np.full(q // 2 + 1, 2.0)
    w[0] = 1.0
    if q % 2 == 0:
        w[-1] = 1.0
    return w


def dominant_orientations(disc: np.ndarray, smooth: np.ndarray, peak_ratio: float, up: int,
                          max_peaks: int) -> tuple[np.ndarray, np.ndarray]:
    """The peaks of each window's smoothed orientation histogram, strongest first.

    Parameters
    ----------
    disc : (N, Q) float64 ndarray
        Orientation histogram of each window.
    smooth : (Q // 2 + 1,) float64 ndarray
        Fourier weights of the smoothing (a Gaussian).
    peak_ratio : float
        A peak counts when it reaches this fraction of the window's highest value on the fine grid.
    up : int
        Fine-grid samples over 360 degrees.
    max_peaks : int
        At most this many peaks per window (the highest; equal heights in the order of the grid).

    Returns
    -------
    window : (M,) int64 ndarray
        The window of each peak, ascending; within a window the peaks by decreasing height.
    position : (M,) float64 ndarray
        The peak's position in bins, refined by a parabola through its grid value and neighbours.
    """
    q = disc.shape[1]
    cos_q, sin_q = _bin_tables(q)
    cos_f, sin_f = _grid_tables(q, up)
    w = smooth * _one_sided(q)
    re = (disc @ cos_q.T) * w
    im = -(disc @ sin_q.T) * w
    fine = re @ cos_f.T - im @ sin_f.T  # (N, up): the smoothed histogram on the fine grid
    top = fine.max(axis=1)
    left, right = np.roll(fine, 1, axis=1), np.roll(fine, -1, axis=1)
    peak = (fine > left) & (fine >= right) & (fine >= peak_ratio * top[:, None]) & (top[:, None] > 0.0)
    window, t = np.nonzero(peak)
    c, lv, rv = fine[window, t], left[window, t], right[window, t]
    order = np.lexsort((t, -c, window))  # per window: highest first, equal heights in grid order
    window, t, c, lv, rv = window[order], t[order], c[order], lv[order], rv[order]
    first = np.searchsorted(window, window)  # index of each window's first peak
    keep = np.arange(window.size) - first < max_peaks
    window, t, c, lv, rv = window[keep], t[keep], c[keep], lv[keep], rv[keep]
    den = lv - 2.0 * c + rv
    offset = np.divide(0.5 * (lv - rv), den, out=np.zeros_like(den), where=den < 0.0)
    return window.astype(np.int64), (t + offset) * q / up


def shifted_descriptors(rings: np.ndarray, window: np.ndarray, position: np.ndarray,
                        clip: float) -> tuple[np.ndarray, np.ndarray]:
    """The ring histograms of each window resampled from each of its peaks on, normalised as descriptors.

    Parameters
    ----------
    rings : (N, K, Q) float64 ndarray
        Ring histograms (area-normalised).
    window, position : (M,) ndarray
        The window and position (bins) of each peak (:func:`dominant_orientations`).
    clip : float
        Values of the unit-length vector above it are clipped (0: none).

    Returns
    -------
    descriptors : (M', K * Q) float32 ndarray
        Ring after ring, each resampled at ``b + position`` through its Fourier series (an exact sub-bin circular
        shift), negative ripples set to 0, scaled to unit L2 norm, clipped, L1-normalised and square-rooted (the
        Hellinger map: unit L2 norm).
    kept : (M,) bool ndarray
        The peaks that give a descriptor (not those whose resampled rings are all 0).
    """
    n, k, q = rings.shape
    cos_q, sin_q = _bin_tables(q)
    ring_re = rings @ cos_q.T  # (N, K, Q // 2 + 1)
    ring_im = -(rings @ sin_q.T)
    m = np.arange(q // 2 + 1)
    phase = 2.0 * np.pi * m[None, :] * position[:, None] / q  # (M, Q // 2 + 1)
    w = _one_sided(q) / q
    c, s = np.cos(phase) * w, np.sin(phase) * w
    a, b = ring_re[window], ring_im[window]  # (M, K, Q // 2 + 1)
    shifted_re = a * c[:, None, :] - b * s[:, None, :]
    shifted_im = a * s[:, None, :] + b * c[:, None, :]
    values = np.maximum(shifted_re @ cos_q - shifted_im @ sin_q, 0.0).reshape(len(window), k * q)
    norm = np.sqrt(np.einsum("ij,ij->i", values, values))
    kept = norm > 0.0
    values = values[kept] / norm[kept, None]
    if clip > 0.0:
        values = np.minimum(values, clip)
    return np.sqrt(values / values.sum(axis=1, keepdims=True)).astype(np.float32), kept
