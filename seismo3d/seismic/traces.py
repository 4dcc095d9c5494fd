"""Trace primitives: the sub-sample peak of a parabola, waveform windows, NCC, the lag search built on them, and the
shift-by-shift correlation of two reflector images (the two sides of a fault) with the continuity of one side.

Positions are fractional sample indices (sample ``k`` at ``k``); every function works on plain arrays and is used by
horizon tracking, fault throw, reflector picking and volume registration alike.
"""

from __future__ import annotations

import numpy as np

__all__ = ["parabolic_offset", "subsample_peak", "runner_up_peak", "waveform", "ncc", "ncc_lag_search", "ncc_curve",
           "small_shift_weight", "side_coherence"]


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


def runner_up_peak(scores, k: int) -> tuple[float, float]:
    """The best rival of the peak of a score series that holds index ``k``: the lag and relative score of the
    highest other local maximum.

    The peak holding ``k`` is the local maximum reached by climbing from ``k`` (``k`` itself when it is one); its
    rivals are the other local maxima inside the series (a maximum at either end is the edge of the search, not a
    peak), e.g. the shifts a reflector period away on a correlation curve of periodic reflectors.

    Parameters
    ----------
    scores : (n,) array_like of float
        Scores over evenly spaced lags (e.g. a weighted correlation over shifts); NaN where a lag could not be scored.
    k : int
        Index of the chosen lag.

    Returns
    -------
    index : float
        The rival's index, refined by a parabola (:func:`subsample_peak`); NaN when there is none.
    ratio : float
        Its score over the chosen peak's score: near 1, two lags score about equally (the choice between them is
        ambiguous); above 1, the rival scores higher; 0 when there is no rival (``index`` NaN); NaN when the chosen
        peak scores <= 0.
    """
    s = np.asarray(scores, dtype=np.float64)
    v = np.where(np.isfinite(s), s, -np.inf)
    m = int(k)
    while True:  # climb to the chosen peak
        step = max((j for j in (m - 1, m + 1) if 0 <= j < v.size), key=lambda j: v[j], default=m)
        if v[step] <= v[m]:
            break
        m = step
    inner = np.arange(1, v.size - 1)
    is_peak = (v[inner] > v[inner - 1]) & (v[inner] >= v[inner + 1]) & np.isfinite(v[inner])
    rivals = inner[is_peak & (np.abs(inner - m) >= 2)]
    if not v[m] > 0:
        return float("nan"), float("nan")
    if rivals.size == 0:
        return float("nan"), 0.0
    j = int(rivals[np.argmax(v[rivals])])
    return j + subsample_peak(s, j), float(v[j] / v[m])


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


def ncc_curve(f, h, vf, vh, max_shift: int, min_overlap: int, min_rows: int):
    """Normalised cross-correlation of ``f(u, t - k)`` with ``h(u, t)`` for every integer shift ``k`` in
    ``[-max_shift, max_shift]``: two images of reflectors (e.g. the two sides of a fault) compared shift by shift
    along the sample axis.

    Parameters
    ----------
    f, h : (n_rows, n_samples) float ndarray
        The two images (rows: positions along the fault or traces; columns: samples).
    vf, vh : (n_rows, n_samples) bool ndarray
        Where each image holds data.
    max_shift : int
        Largest shift, samples.
    min_overlap : int
        Fewest samples of both images that must overlap at a shift.
    min_rows : int
        Fewest rows that must overlap at a shift.

    Returns
    -------
    (ks, cc, local) or None
        ``ks`` (2 max_shift + 1,) int64 shifts; ``cc`` float64, the correlation normalised by the energies of the
        *whole* images (zero outside the overlap), which penalises shifts where the images barely overlap (on a
        short fault a large shift would otherwise correlate a few samples by chance); ``local`` float64, the
        correlation normalised over the overlap only. NaN where the overlap is below ``min_overlap`` samples or
        ``min_rows`` rows; None when either image has no energy.
    """
    nt = f.shape[1]
    ks = np.arange(-max_shift, max_shift + 1)
    cc = np.full(ks.size, np.nan)
    local = np.full(ks.size, np.nan)
    ef = np.dot(f[vf], f[vf])
    eh = np.dot(h[vh], h[vh])
    if ef <= 0 or eh <= 0:
        return None
    for i, k in enumerate(ks):
        if abs(k) >= nt:
            continue
        if k >= 0:
            a, va, b, vb = f[:, :nt - k], vf[:, :nt - k], h[:, k:], vh[:, k:]
        else:
            a, va, b, vb = f[:, -k:], vf[:, -k:], h[:, :nt + k], vh[:, :nt + k]
        m = va & vb
        if m.sum() < min_overlap or np.count_nonzero(m.any(axis=0)) < min_rows:
            continue
        am, bm = a[m], b[m]
        num = np.dot(am, bm)
        cc[i] = num / np.sqrt(ef * eh)
        den = np.sqrt(np.dot(am, am) * np.dot(bm, bm))
        local[i] = num / den if den > 0 else 0.0
    return ks, cc, local


def small_shift_weight(ks, max_shift: int, prior: float) -> np.ndarray:
    """The preference for small shifts of :func:`ncc_curve`: weight 1 at zero, ``1 - prior`` at ``max_shift + 1``.

    Parameters
    ----------
    ks : (n,) int ndarray
        Shifts, samples.
    max_shift : int
        Largest shift searched, samples.
    prior : float
        Weight lost at one sample beyond ``max_shift``, in [0, 1].

    Returns
    -------
    (n,) float64 ndarray
    """
    return 1.0 - prior * np.abs(ks) / (max_shift + 1.0)


def side_coherence(vals: np.ndarray, inside: np.ndarray) -> float:
    """How continuous the reflectors are along one side of a fault: the normalised correlation, over the nodes read
    at every offset, of the mean of the nearer half of the offsets with the mean of the farther half.

    Parameters
    ----------
    vals : (n_offsets, n_nodes) float ndarray
        Amplitudes read at increasing lateral offsets from the fault (rows), along the reflectors through each node.
    inside : (n_offsets, n_nodes) bool ndarray
        Where ``vals`` lies inside the data.

    Returns
    -------
    float
        In [-1, 1]; NaN when fewer than 16 nodes are read at every offset or a half has no energy.
    """
    half = vals.shape[0] // 2
    both = inside.all(axis=0)
    if half < 1 or np.count_nonzero(both) < 16:
        return float("nan")
    near, far = vals[:half, both].mean(axis=0), vals[half:, both].mean(axis=0)
    den = np.sqrt(np.dot(near, near) * np.dot(far, far))
    return float(np.dot(near, far) / den) if den > 0 else float("nan")
