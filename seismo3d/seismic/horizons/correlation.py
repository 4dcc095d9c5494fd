"""Normalised cross-correlation of trace windows at given times, pair by pair: the lag search of the least-squares
horizon's pairs (:func:`~seismo3d.seismic.horizons.lsq.pair_shifts`), the correlation of two windows, and a pick's
confidence against its neighbours (used by :mod:`~seismo3d.seismic.horizons.lsq` and
:mod:`~seismo3d.seismic.horizons.cycle_cut`).

Conventions: traces ``(n_traces, n_samples)``; times in fractional samples.
"""

from __future__ import annotations

import numpy as np

__all__ = ["window_correlation", "neighbour_confidence"]


_PAIR_CHUNK = 4096  # pairs handled at once by pair_lags


def pair_lags(traces, a, ta, b, centre, half, max_lag, min_fraction):
    """For each pair: the lag around ``centre`` (times on trace b) at which trace b correlates best with the window
    of trace a around ``ta``; returns (lag relative to centre, score), NaN where not measured.

    The window is ``+-half`` samples, shortened near the ends of the traces to the samples trace a has (at least 4
    each side); a lag is scored where at least ``min_fraction`` of the window lies on trace b (:func:`_reach`), the
    best one refined by a parabola. Array work in numpy, the pairs of one window length together in chunks of
    :data:`_PAIR_CHUNK` (the compiled kernels it replaces cost the horizon's first run 2.7 CPU s of compiling). The
    sums run sample by sample in the kernels' order, but the kernels' products over a window were fused
    multiply-adds: scores can differ from theirs in the last bits."""
    a, b = np.asarray(a, np.intp), np.asarray(b, np.intp)
    ta, centre = np.asarray(ta, np.float64), np.asarray(centre, np.float64)
    n = a.size
    lag_out = np.full(n, np.nan)
    score_out = np.full(n, np.nan)
    n_s = traces.shape[1]
    ok = np.isfinite(ta) & np.isfinite(centre)
    h = np.full(n, -1, np.int64)
    h[ok] = np.minimum(np.minimum(np.floor(ta[ok]), np.floor(n_s - 1 - ta[ok])), half)
    for width in np.unique(h[h >= 4]):
        group = np.nonzero(h == width)[0]
        for lo in range(0, group.size, _PAIR_CHUNK):
            p = group[lo:lo + _PAIR_CHUNK]
            lag_out[p], score_out[p] = _pair_lags(traces, a[p], ta[p], b[p], centre[p], int(width), int(max_lag),
                                                  float(min_fraction))
    return lag_out, score_out


def _read_windows(traces, rows, start, count):
    """``out[p, k] = sample_at(traces[rows[p]], start[p] + k)`` for k < ``count`` (:func:`~seismo3d.seismic.horizons.
    dp.sample_at`: linear interpolation, NaN outside the trace); a window's samples share one interpolation weight."""
    n = traces.shape[1]
    k0 = np.floor(start)
    f = (start - k0)[:, None]
    i = k0.astype(np.int64)[:, None] + np.arange(count)
    inside = (i >= 0) & (i < n - 1)
    j = np.clip(i, 0, n - 2)
    r = rows[:, None]
    out = (1.0 - f) * traces[r, j] + f * traces[r, j + 1]
    if not inside.all():  # the ends: sample_at at start + k
        t = start[:, None] + np.arange(count)
        k = np.clip(np.floor(t), 0, n - 1).astype(np.int64)
        g = t - k
        at = (1.0 - g) * traces[r, k] + g * traces[r, np.minimum(k + 1, n - 1)]
        at = np.where(k >= n - 1, traces[r, k], at)
        at = np.where((t < 0.0) | (t > n - 1), np.nan, at)
        out = np.where(inside, out, at)
    return out


def _reach(centre, h, m, n_s, max_lag, min_samples):
    """The lags scored (``+-reach``): those where at least ``min_samples`` of the window lie on trace b, on both
    sides (near the trace ends that cuts the range on one side; it is cut on the other side as well, or a pair's
    wrong-cycle matches, more of them on the longer side, would bias the shifts towards it); -1: none."""
    reach = np.full(centre.size, max_lag)
    cut = (centre - h - max_lag >= 0.0) & (centre + h + max_lag <= n_s - 1.0)  # every lag overlaps wholly
    for k in range(max_lag + 1):
        if cut.all():
            break
        lo = centre - h - k
        hi = centre + h + k
        short = ((np.minimum(lo + m - 1, n_s - 1.0) - np.maximum(lo, 0.0) + 1 < min_samples)
                 | (np.minimum(hi, n_s - 1.0) - np.maximum(hi - m + 1, 0.0) + 1 < min_samples)) & ~cut
        reach[short] = k - 1
        cut |= short
    return reach


def _pair_lags(traces, ka, ta, kb, centre, h, max_lag, min_fraction):
    """:func:`pair_lags` of pairs with one window half-length ``h``."""
    n_s = traces.shape[1]
    count = ka.size
    rows = np.arange(count)
    m = 2 * h + 1
    n_lags = 2 * max_lag + 1
    min_samples = max(5, int(min_fraction * m))
    ref = _read_windows(traces, ka, ta - h, m)  # inside trace a (h above): all finite
    sig = _read_windows(traces, kb, centre - h - max_lag, m + 2 * max_lag)
    reach = _reach(centre, h, m, n_s, max_lag, min_samples)
    # trace a's window centred once: it serves every lag where trace b's window is finite too (interior lags: the
    # run of finite sig samples from the first)
    ma = np.zeros(count)
    for k in range(m):
        ma += ref[:, k]
    ma /= m
    ref -= ma[:, None]
    saa = np.zeros(count)
    for k in range(m):
        saa += ref[:, k] * ref[:, k]
    finite = np.isfinite(sig)
    first = np.where(finite.any(axis=1), finite.argmax(axis=1), sig.shape[1])
    gap = ~finite & (np.arange(sig.shape[1]) >= first[:, None])
    last = np.where(gap.any(axis=1), gap.argmax(axis=1), sig.shape[1])
    lo = np.maximum(max_lag - reach, first)
    hi = np.minimum(max_lag + reach, last - m)  # inclusive
    scores = np.full((count, n_lags), np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        if (hi >= lo).any():
            # the interior lags: the products with trace a's window, over the spreads of both windows; the sums of
            # trace b's window and of its squares slid from lag to lag (from each pair's first interior lag)
            products = np.zeros((count, n_lags))
            for k in range(m):
                products += ref[:, k:k + 1] * sig[:, k:k + n_lags]
            top = sig.shape[1] - 1
            sb = np.zeros(count)
            sbb = np.zeros(count)
            for k in range(m):
                y = sig[rows, np.minimum(lo + k, top)]
                sb += y
                sbb += y * y
            for d in range(n_lags):
                s = lo + d
                live = s <= hi
                if not live.any():
                    break
                if d:
                    y0 = sig[rows, np.minimum(s - 1, top)]
                    y1 = sig[rows, np.minimum(s + m - 1, top)]
                    sb += y1 - y0
                    sbb += y1 * y1 - y0 * y0
                var = sbb - sb * sb / m
                v = np.where((saa > 0) & (var > 1e-9 * sbb), var, -1.0)  # -1: a flat window
                sc = np.where(v > 0.0, products[rows, np.minimum(s, n_lags - 1)] / np.sqrt(saa * v), 0.0)
                scores[rows[live], s[live]] = sc[live]
        # the other lags within reach: over the samples where both windows are finite (their means)
        lag = np.arange(n_lags)
        partial = ((lag >= max_lag - reach[:, None]) & (lag <= max_lag + reach[:, None])
                   & ~((lag >= lo[:, None]) & (lag <= hi[:, None])))
        p, s = np.nonzero(partial)
        if p.size:
            scores[p, s] = _partial_ncc(ref[p], sig, p, s, m, min_samples)
    best = np.where(np.isnan(scores), -np.inf, scores)
    kbest = best.argmax(axis=1)
    score = best[rows, kbest]
    found = score > -2.0
    # the best lag refined by the parabola through it and its neighbours
    y0 = scores[rows, np.maximum(kbest - 1, 0)]
    y1 = scores[rows, kbest]
    y2 = scores[rows, np.minimum(kbest + 1, n_lags - 1)]
    den = y0 - 2 * y1 + y2
    with np.errstate(invalid="ignore", divide="ignore"):
        off = np.minimum(np.maximum(0.5 * (y0 - y2) / den, -0.5), 0.5)
    bend = (kbest > 0) & (kbest < 2 * max_lag) & np.isfinite(y0) & np.isfinite(y2) & (den < 0)
    off = np.where(bend, off, 0.0)
    return np.where(found, kbest - max_lag + off, np.nan), np.where(found, score, np.nan)


def _partial_ncc(ref, sig, p, s, m, min_samples):
    """Correlations at lags ``s`` of pairs ``p`` (``ref``: their windows of trace a) over the samples where both
    windows are finite (the means of those); NaN with fewer than ``min_samples``."""
    sa = np.zeros(p.size)
    sb = np.zeros(p.size)
    cnt = np.zeros(p.size, np.int64)
    both = np.empty((m, p.size), np.bool_)
    for k in range(m):
        x, y = ref[:, k], sig[p, s + k]
        both[k] = np.isfinite(x) & np.isfinite(y)
        sa += np.where(both[k], x, 0.0)
        sb += np.where(both[k], y, 0.0)
        cnt += both[k]
    ma, mb = sa / cnt, sb / cnt
    sab = np.zeros(p.size)
    saa = np.zeros(p.size)
    sbb = np.zeros(p.size)
    for k in range(m):
        dx, dy = ref[:, k] - ma, sig[p, s + k] - mb
        sab += np.where(both[k], dx * dy, 0.0)
        saa += np.where(both[k], dx * dx, 0.0)
        sbb += np.where(both[k], dy * dy, 0.0)
    out = np.where((saa > 0) & (sbb > 0), sab / np.sqrt(saa * sbb), 0.0)
    return np.where(cnt < min_samples, np.nan, out)


def window_correlation(traces: np.ndarray, a: np.ndarray, ta: np.ndarray, b: np.ndarray, tb: np.ndarray, *,
                       half: int) -> np.ndarray:
    """Normalised cross-correlation of trace ``a``'s window around ``ta`` with trace ``b``'s around ``tb``, for each
    pair (no lag search; windows ``+-half`` samples, shortened near the ends of the traces as in
    :func:`pair_shifts`).

    Parameters
    ----------
    traces : (n_traces, n_samples) float32 ndarray
    a, b : (n_pairs,) intp ndarray
        The traces of each pair.
    ta, tb : (n_pairs,) float64 ndarray
        Window centres, fractional samples.
    half : int
        Samples.

    Returns
    -------
    (n_pairs,) float64 ndarray
        In [-1, 1]; NaN where a centre is NaN or the windows overlap the traces too little.
    """
    _, score = pair_lags(traces, np.asarray(a, np.intp), np.asarray(ta, np.float64), np.asarray(b, np.intp),
                          np.asarray(tb, np.float64), int(half), 0, 0.8)
    return score


def neighbour_confidence(traces: np.ndarray, times: np.ndarray, a: np.ndarray, b: np.ndarray, half: int) -> np.ndarray:
    """Median normalised cross-correlation (``+-half`` samples) of each trace's waveform at ``times`` with its
    neighbours' (the pairs ``a, b``) at theirs; NaN where no neighbour is picked."""
    ok = np.isfinite(times[a]) & np.isfinite(times[b])
    a, b = a[ok], b[ok]
    score = window_correlation(traces, a, times[a], b, times[b], half=half)
    return _group_nanmedian(np.concatenate([a, b]), np.concatenate([score, score]), times.size)


def _group_nanmedian(node: np.ndarray, val: np.ndarray, n: int) -> np.ndarray:
    """Median of the finite ``val`` of each ``node``.

    Parameters
    ----------
    node : (m,) int ndarray
        The group of each value, in ``[0, n)``.
    val : (m,) float64 ndarray
    n : int
        Number of groups.

    Returns
    -------
    (n,) float64 ndarray
        NaN where a group has no finite value. The median as ``np.median`` and numba's: the middle value, or the
        two middle values' sum halved (the same bits as the numba kernel this replaces, whose compile cost the
        horizon's first run 2 CPU s, numba's median with it).
    """
    finite = np.isfinite(val)
    node, val = node[finite], val[finite]
    order = np.lexsort((val, node))  # by group, then by value
    node, val = node[order], val[order]
    count = np.bincount(node, minlength=n)
    start = np.cumsum(count) - count
    out = np.full(n, np.nan)
    has = count > 0
    first, half = start[has], count[has] >> 1
    upper = val[first + half]
    lower = val[first + np.maximum(half - 1, 0)]
    out[has] = np.where(count[has] & 1, upper, (lower + upper) / 2)
    return out
