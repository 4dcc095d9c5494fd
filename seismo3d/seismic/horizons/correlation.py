"""Normalised cross-correlation of trace windows at given times, pair by pair: the lag search of the least-squares
horizon's pairs (:func:`~seismo3d.seismic.horizons.lsq.pair_shifts`), the correlation of two windows, and a pick's
confidence against its neighbours (used by :mod:`~seismo3d.seismic.horizons.lsq` and
:mod:`~seismo3d.seismic.horizons.cycle_cut`).

Conventions: traces ``(n_traces, n_samples)``; times in fractional samples.
"""

from __future__ import annotations

import numpy as np

__all__ = ["window_correlation", "neighbour_confidence"]


_PAIR_CHUNK = 8192  # pairs at a time (memory: about 0.3 KB a pair per lag searched each side)


def pair_lags(traces, a, ta, b, centre, half, max_lag, min_fraction):
    """For each pair p: the lag around ``centre[p]`` (times on trace ``b[p]``) at which trace ``b[p]`` correlates best
    with the window of trace ``a[p]`` around ``ta[p]``, refined by a parabola, and its correlation; returns (lag
    relative to the centre, score), NaN where not measured.

    Near the ends of the traces the window is shortened to the samples trace a has (at least 4 each side); a lag is
    scored over the samples where trace b is finite (with the means of those) where they are at least
    ``min_fraction`` of the window, and the lags are cut on both sides where one side is cut (or a pair's wrong-cycle
    matches, more of them on the longer side, would bias the shifts towards it). Array work in numpy, pairs in chunks
    of :data:`_PAIR_CHUNK` (the compiled kernels it replaces cost the horizon's first run 4-5 CPU s of compiling):
    each lag's correlation from the sums over the samples (products of the windows, cumulative sums down trace b),
    where the kernels summed the products in another order (reassociated) and the deviations from the means near the
    trace ends: the scores agree to about 1e-14.
    """
    n = len(a)
    lag_out = np.full(n, np.nan)
    score_out = np.full(n, np.nan)
    half, max_lag = int(half), int(max_lag)
    n_s = traces.shape[1]
    ta = np.asarray(ta, np.float64)
    centre = np.asarray(centre, np.float64)
    ok = np.isfinite(ta) & np.isfinite(centre)
    t = np.where(ok, ta, 0.0)
    h = np.minimum(np.minimum(np.floor(t), np.floor((n_s - 1) - t)), half)
    keep = np.nonzero(ok & (h >= 4))[0]  # h < 4 or a NaN time: not measured
    with np.errstate(invalid="ignore", divide="ignore"):  # NaN windows, empty overlaps: masked
        for s in range(0, keep.size, _PAIR_CHUNK):
            p = keep[s:s + _PAIR_CHUNK]
            lag_out[p], score_out[p] = _lags(traces, a[p], ta[p], b[p], centre[p], h[p].astype(np.int64), half,
                                             max_lag, float(min_fraction))
    return lag_out, score_out


def _read_windows(traces, rows, start, count):
    """``out[k, p] = sample_at(traces[rows[p]], start[p] + k)`` for k < ``count`` ((count, n) float64, a window a
    column; :func:`~seismo3d.seismic.horizons.dp.sample_at`: linear interpolation, NaN outside the trace), each
    column's samples with one interpolation weight (as the kernel it replaces: the same bits)."""
    n_s = traces.shape[1]
    k0 = np.floor(start)
    f = start - k0
    k0 = k0.astype(np.int64)
    i = k0 + np.arange(count + 1)[:, None]  # the samples k0 .. k0 + count of each window
    w = traces.reshape(-1).take(rows * n_s + np.clip(i, 0, n_s - 1)).astype(np.float64)
    if k0.min(initial=0) < 0 or k0.max(initial=0) + count >= n_s:
        w[(i < 0) | (i >= n_s)] = np.nan
    out = (1.0 - f) * w[:-1] + f * w[1:]
    # sample_at's rule at the last sample: its value at its time (the formula read past the trace)
    k = n_s - 1 - k0
    end = np.nonzero((k >= 0) & (k < count))[0]
    if end.size:
        end = end[start[end] + k[end] == n_s - 1]
        out[k[end], end] = w[k[end], end]
    return out


def _cumsum(v):
    """``np.cumsum(v, axis=0)``, row after row (numpy's walks down the columns, 5 x slower)."""
    c = v.copy()
    for r in range(1, c.shape[0]):
        c[r] += c[r - 1]
    return c


def _lags(traces, a, ta, b, centre, h, half, max_lag, min_fraction):
    """:func:`pair_lags` of one chunk of pairs whose windows ``+-h`` (per pair, 4 <= h <= ``half``) lie on trace a.
    Windows are columns: (samples, pairs) arrays."""
    n_s = traces.shape[1]
    n = a.size
    m = 2 * h + 1  # the window of each pair
    width = 2 * half + 1
    n_lags = 2 * max_lag + 1
    cols = np.arange(n)
    live = np.arange(width)[:, None] < m  # the samples of each pair's window
    min_samples = np.maximum((min_fraction * m).astype(np.int64), 5)
    ref = np.where(live, _read_windows(traces, a, ta - h, width), 0.0)
    # trace a's window is all finite (a trace's NaN samples make it all NaN): centred, summed sample by sample
    ma = np.add.reduce(ref, axis=0, initial=0.0) / m
    ref = np.where(live, ref - ma, 0.0)
    sig = _read_windows(traces, b, centre - h - max_lag, width + 2 * max_lag)
    row = np.arange(sig.shape[0])[:, None]
    finite = np.isfinite(sig) & (row < m + 2 * max_lag)  # a pair's samples past m + 2 max_lag are not its own
    y = np.where(finite, sig, 0.0)
    # the lags whose windows overlap trace b enough: cut on both sides at the first lag that does not
    reach = np.full(n, max_lag)
    inside = (centre - h - max_lag >= 0.0) & (centre + h + max_lag <= n_s - 1.0)  # every lag overlaps wholly
    if not inside.all():
        kk = np.arange(max_lag + 1)[:, None]
        lo = centre - h - kk
        hi = centre + h + kk
        lo_end, hi_start = lo + m - 1, hi - m + 1  # in the kernel's order: (lo + m) - 1
        short = ((np.minimum(lo_end, n_s - 1.0) - np.maximum(lo, 0.0) + 1 < min_samples)
                 | (np.minimum(hi, n_s - 1.0) - np.maximum(hi_start, 0.0) + 1 < min_samples))
        cut = short.any(axis=0) & ~inside
        reach[cut] = np.argmax(short[:, cut], axis=0) - 1
    # every lag's sums over the samples where trace b is finite: the products of the windows and trace a's sums by
    # products with them, trace b's by cumulative sums down it
    lag = np.arange(n_lags)[:, None]
    sab = np.einsum("kp,ksp->sp", ref, _shifted(y, width, n_lags))
    window = _shifted(finite.astype(np.float64), width, n_lags)
    sa = np.einsum("kp,ksp->sp", ref, window)
    saa = np.einsum("kp,ksp->sp", ref * ref, window)
    # trace b's sums, sum_k<m v[s + k] at every lag s: differences of the cumulative sums down its columns
    if (m == m[0]).all():
        def window_sums(v):
            c = _cumsum(v)
            out = c[m[0] - 1:m[0] - 1 + n_lags].copy()
            out[1:] -= c[:n_lags - 1]
            return out
    else:
        at = (lag + m - 1) * n + cols
        before = np.maximum(lag - 1, 0) * n + cols

        def window_sums(v):
            c = _cumsum(v).reshape(-1)
            return c.take(at) - np.where(lag > 0, c.take(before), 0)

    cnt = window_sums(finite.astype(np.int64))
    sb = window_sums(y)
    sbb = window_sums(y * y)
    sab -= sa * sb / cnt
    saa -= sa * sa / cnt
    var = sbb - sb * sb / cnt
    spread = (saa > 1e-9 * (saa + sa * sa / cnt)) & (var > 1e-9 * sbb) & (saa > 0) & (var > 0)
    scores = np.where(spread, sab / np.sqrt(np.where(spread, saa * var, 1.0)), 0.0)  # 0: a flat window
    bad = np.nonzero(~np.isfinite(ma))[0]
    if bad.size:
        # a window of trace a with a NaN sample (all NaN once centred): the lags in trace b's first run of finite
        # samples score 0 (a flat window), the others are not scored
        run = finite[:, bad]
        first = np.where(run.any(axis=0), np.argmax(run, axis=0), run.shape[0])
        gap = ~run & (np.arange(run.shape[0])[:, None] >= first)
        last = np.where(gap.any(axis=0), np.argmax(gap, axis=0), run.shape[0])
        scores[:, bad] = np.where((lag >= first) & (lag <= last - m[bad]), 0.0, np.nan)
    scores[(np.abs(lag - max_lag) > reach) | (cnt < min_samples)] = np.nan
    # the best lag (the first of equal ones), refined by a parabola through it and its neighbours
    best = np.where(np.isnan(scores), -np.inf, scores)
    kbest = np.argmax(best, axis=0)
    top = best[kbest, cols]
    found = top > -np.inf
    off = np.zeros(n)
    y0 = scores[np.maximum(kbest - 1, 0), cols]
    y2 = scores[np.minimum(kbest + 1, n_lags - 1), cols]
    mid = found & (kbest > 0) & (kbest < n_lags - 1) & np.isfinite(y0) & np.isfinite(y2)
    den = y0 - 2 * top + y2
    mid &= den < 0
    off[mid] = np.clip(0.5 * (y0[mid] - y2[mid]) / den[mid], -0.5, 0.5)
    return np.where(found, (kbest - max_lag) + off, np.nan), np.where(found, top, np.nan)


def _shifted(x, width, n_lags):
    """The (width, n_lags, n) view ``x[k + s, p]`` of (width + n_lags - 1, n) ``x``: trace b's window at every lag."""
    return np.lib.stride_tricks.as_strided(x, shape=(width, n_lags, x.shape[1]), strides=(x.strides[0],) + x.strides)


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
