"""Normalised cross-correlation of trace windows at given times, pair by pair: the lag search of the least-squares
horizon's pairs (:func:`~seismo3d.seismic.horizons.lsq.pair_shifts`), the correlation of two windows, and a pick's
confidence against its neighbours (used by :mod:`~seismo3d.seismic.horizons.lsq` and
:mod:`~seismo3d.seismic.horizons.cycle_cut`).

Conventions: traces ``(n_traces, n_samples)``; times in fractional samples.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..._threads import run_threads
from .dp import sample_at

__all__ = ["window_correlation", "neighbour_confidence"]


_PAIR_CHUNK = 256  # pairs per task of pair_lags


# no_cfunc_wrapper: the kernels here are called from Python and from each other, never as C callbacks, so
# numba's C-callable wrapper of each is not compiled (0.02-0.03 CPU s a kernel on a first run)
@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _pair_lags_share(t, n_threads, traces, a, ta_all, b, centre_all, half, max_lag, min_fraction, lag_out,
                     score_out, refs, sigs, scores_all, products_all):
    # the pairs of chunks t, t + n_threads, ... (see pair_lags): for pair p, the lag around centre_all[p] on trace
    # b[p] at which it correlates best with the window of trace a[p] around ta_all[p], refined by a parabola, and its
    # correlation; (NaN, NaN) where not measured. Near the ends of the traces the window is shortened to the samples
    # trace a[p] has (at least 4 each side); a lag is scored where at least min_fraction of the window lies on trace
    # b[p]. refs, sigs, scores_all, products_all: work arrays, a row per thread (allocated by the caller: np.empty in a
    # kernel compiles numba's allocator). One kernel, not a loop calling a kernel per pair: numba compiles a called
    # kernel on its own and again inside its caller. No min(), max() or int() (each compiles a function of numba's of
    # its own): comparisons and np.int64
    n = a.size
    n_chunks = (n + _PAIR_CHUNK - 1) // _PAIR_CHUNK
    ref, sig, scores, products = refs[t], sigs[t], scores_all[t], products_all[t]
    for chunk in range(t, n_chunks, n_threads):
        end = (chunk + 1) * _PAIR_CHUNK
        for p in range(chunk * _PAIR_CHUNK, n if n < end else end):
            ka, kb = a[p], b[p]
            ta, centre = ta_all[p], centre_all[p]
            n_s = traces.shape[1]
            if not (math.isfinite(ta) and math.isfinite(centre)):
                lag_out[p], score_out[p] = np.nan, np.nan
                continue
            h = half
            h0 = math.floor(ta)
            h1 = math.floor(n_s - 1 - ta)
            h = h0 if h0 < h else h
            h = h1 if h1 < h else h
            if h < 4:
                lag_out[p], score_out[p] = np.nan, np.nan
                continue
            m = 2 * h + 1
            min_samples = np.int64(min_fraction * m)
            min_samples = 5 if min_samples < 5 else min_samples
            ra = traces[ka]
            rb = traces[kb]
            _read_window(ra, ta - h, m, ref)
            _read_window(rb, centre - h - max_lag, m + 2 * max_lag, sig)
            # lags are scored only where the window overlaps trace b enough: near the trace ends that cuts the range on
            # one side; it is cut on the other side as well, or a pair's wrong-cycle matches (more of them on the
            # longer side) would bias the shifts towards it
            reach = max_lag
            inside = centre - h - max_lag >= 0.0 and centre + h + max_lag <= n_s - 1.0  # every lag overlaps wholly
            for k in range(0 if inside else max_lag + 1):
                lo = centre - h - k
                hi = centre + h + k
                lo_end = lo + m - 1
                hi_start = hi - m + 1
                if (lo_end if lo_end < n_s - 1.0 else n_s - 1.0) - (lo if lo > 0.0 else 0.0) + 1 < min_samples or \
                        (hi if hi < n_s - 1.0 else n_s - 1.0) - (hi_start if hi_start > 0.0 else 0.0) + 1 < min_samples:
                    reach = k - 1
                    break
            for k in range(scores.size):  # a loop: scores[:] = nan compiles numba's generic setitem
                scores[k] = np.nan
            best, kbest = -2.0, -1
            # trace a's window lies inside the trace (h above), so it is all finite: centred once, it serves every lag
            # where trace b's window is finite too (interior lags: the run of finite ``sig`` samples)
            ma = 0.0
            for k in range(m):
                ma += ref[k]
            ma /= m
            saa = 0.0
            for k in range(m):
                ref[k] -= ma
                saa += ref[k] * ref[k]
            first = 0  # sig[first:last] is finite
            while first < m + 2 * max_lag and not math.isfinite(sig[first]):
                first += 1
            last = first
            while last < m + 2 * max_lag and math.isfinite(sig[last]):
                last += 1
            # the interior lags (trace b's window finite): their products with the window of a at once, the sums of
            # trace b's window and of its squares slid from lag to lag
            lo = max_lag - reach
            lo = first if first > lo else lo
            hi = max_lag + reach
            hi = last - m if last - m < hi else hi  # inclusive
            if hi >= lo:
                _window_products(ref, sig, m, lo, hi + 1, products)
                _interior_scores(sig, m, lo, hi + 1, saa, products, scores)
            for s in range(max_lag - reach, max_lag + reach + 1):
                if lo <= s <= hi:
                    c = scores[s]
                else:
                    c = _partial_window_ncc(ref, sig, s, m, min_samples)
                    if math.isnan(c):
                        continue
                    scores[s] = c
                if c > best:
                    best, kbest = c, s
            if kbest < 0:
                lag_out[p], score_out[p] = np.nan, np.nan
                continue
            off = 0.0
            if 0 < kbest < 2 * max_lag and math.isfinite(scores[kbest - 1]) and math.isfinite(scores[kbest + 1]):
                y0, y1, y2 = scores[kbest - 1], scores[kbest], scores[kbest + 1]
                den = y0 - 2 * y1 + y2
                if den < 0:
                    off = 0.5 * (y0 - y2) / den
                    off = -0.5 if off < -0.5 else (0.5 if off > 0.5 else off)
            lag_out[p], score_out[p] = kbest - max_lag + off, best


def pair_lags(traces, a, ta, b, centre, half, max_lag, min_fraction):
    """For each pair: the lag around ``centre`` (times on trace b) at which trace b correlates best with the window
    of trace a around ``ta``; returns (lag relative to centre, score), NaN where not measured
    (``_pair_lags_share``); chunks of pairs shared out over numba's threads."""
    n = len(a)
    lag_out = np.full(n, np.nan)
    score_out = np.full(n, np.nan)
    n_threads = max(1, min(nb.get_num_threads(), (n + _PAIR_CHUNK - 1) // _PAIR_CHUNK))
    half, max_lag = int(half), int(max_lag)
    work = [np.empty((n_threads, size)) for size in (2 * half + 1, 2 * half + 1 + 2 * max_lag, 2 * max_lag + 1,
                                                     2 * max_lag + 1)]
    run_threads(_pair_lags_share, n_threads, traces, a, ta, b, centre, half, max_lag, float(min_fraction), lag_out,
                score_out, *work)
    return lag_out, score_out


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _read_window(trace, start, count, out):
    """``out[k] = sample_at(trace, start + k)`` for k < ``count`` (:func:`~seismo3d.seismic.horizons.dp.sample_at`:
    linear interpolation, NaN outside the trace); the samples share one interpolation weight."""
    k0 = math.floor(start)
    f = start - k0
    n = trace.size
    if k0 >= 0 and k0 + count < n:  # inside the trace: no sample needs the ends' rule (unsigned: no wraparound)
        base = nb.uint64(k0)
        for k in range(nb.uint64(count)):
            out[k] = (1.0 - f) * trace[base + k] + f * trace[base + k + nb.uint64(1)]
        return
    for k in range(count):
        i = k0 + k
        if 0 <= i < n - 1:
            out[k] = (1.0 - f) * trace[i] + f * trace[i + 1]
        else:
            out[k] = sample_at(trace, start + k)


@nb.njit(cache=True, no_cfunc_wrapper=True, fastmath={"reassoc", "contract", "nsz", "arcp"})
def _window_products(ref, sig, m, lo, hi, out):
    """``out[s] = sum_k ref[k] sig[s + k]`` (k < ``m``) for lags ``lo <= s < hi``: eight lags at a time, each one
    accumulator, so the compiler keeps them in vector registers (reassociated; unsigned indices, so that no
    negative-index wraparound stands in the way)."""
    one = nb.uint64(1)
    s = nb.uint64(lo)
    end = nb.uint64(hi)
    width = nb.uint64(m)
    while s + nb.uint64(8) <= end:
        a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = 0.0
        for k in range(width):
            r = ref[k]
            i = s + k
            a0 += r * sig[i]
            a1 += r * sig[i + one]
            a2 += r * sig[i + nb.uint64(2)]
            a3 += r * sig[i + nb.uint64(3)]
            a4 += r * sig[i + nb.uint64(4)]
            a5 += r * sig[i + nb.uint64(5)]
            a6 += r * sig[i + nb.uint64(6)]
            a7 += r * sig[i + nb.uint64(7)]
        out[s], out[s + one], out[s + nb.uint64(2)], out[s + nb.uint64(3)] = a0, a1, a2, a3
        out[s + nb.uint64(4)], out[s + nb.uint64(5)], out[s + nb.uint64(6)], out[s + nb.uint64(7)] = a4, a5, a6, a7
        s += nb.uint64(8)
    while s < end:
        acc = 0.0
        for k in range(width):
            acc += ref[k] * sig[s + k]
        out[s] = acc
        s += one


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _interior_scores(sig, m, lo, hi, saa, products, scores):
    """``scores[s]`` for the lags ``lo <= s < hi`` where trace b's window ``sig[s:s + m]`` is finite: the products
    (:func:`_window_products`) over the spreads of the two windows (``saa``: the centred window of a's), 0 where a
    window is flat. The sums of b's window and of its squares are slid from lag to lag into ``scores``, then turned
    into correlations in one loop the compiler vectorises."""
    one = nb.uint64(1)
    start = nb.uint64(lo)
    end = nb.uint64(hi)
    width = nb.uint64(m)
    sb = 0.0
    sbb = 0.0
    for k in range(width):
        y = sig[start + k]
        sb += y
        sbb += y * y
    for s in range(start, end):
        if s > start:
            y0 = sig[s - one]
            y1 = sig[s + width - one]
            sb += y1 - y0
            sbb += y1 * y1 - y0 * y0
        var = sbb - sb * sb / m
        scores[s] = var if saa > 0 and var > 1e-9 * sbb else -1.0  # -1: a flat window
    for s in range(start, end):
        v = scores[s]
        scores[s] = products[s] / math.sqrt(saa * v) if v > 0.0 else 0.0


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _partial_window_ncc(ref, sig, s, m, min_samples):
    """A pair's correlation at lag ``s`` (``_pair_lags_share``) over the samples where both windows are finite (the
    means of those); NaN with fewer than ``min_samples``."""
    sa = 0.0
    sb = 0.0
    cnt = 0
    for k in range(m):
        x, y = ref[k], sig[s + k]
        if math.isfinite(x) and math.isfinite(y):
            sa += x
            sb += y
            cnt += 1
    if cnt < min_samples:
        return np.nan
    ma, mb = sa / cnt, sb / cnt
    sab = 0.0
    saa = 0.0
    sbb = 0.0
    for k in range(m):
        x, y = ref[k], sig[s + k]
        if math.isfinite(x) and math.isfinite(y):
            dx = x - ma
            dy = y - mb
            sab += dx * dy
            saa += dx * dx  # not ** 2: it compiles a power function of numba's (the same bits)
            sbb += dy * dy
    return sab / math.sqrt(saa * sbb) if saa > 0 and sbb > 0 else 0.0


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
