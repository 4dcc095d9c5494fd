"""Dynamic programming over candidate picks: the picks of each line of a horizon chosen together.

Given a guide (the least-squares horizon of :mod:`~seismo3d.seismic.horizon_lsq`), every trace of a line offers its
extrema of the horizon's polarity within ``reach`` samples of the guide as candidates; the Viterbi algorithm chooses
one per trace minimising, along the line, ``w_guide |pick - guide|`` (per trace) + ``w_step (step - slope)^2`` (the
step between neighbouring picks against the structure-tensor reflector slope there) + ``w_wave (1 - ncc)`` (their
waveforms' correlation). A seed's trace keeps the candidate nearest the seed. Lines are the last lateral axis
(crosslines of each inline); :func:`settle_lone_departures` then moves back picks that leave the guide by half a
reflector period on their inline alone.

References
----------
.. [1] A. J. Viterbi, "Error bounds for convolutional codes and an asymptotically optimum decoding algorithm", IEEE
   Trans. Information Theory 13(2), 260-269, 1967.
.. [2] D. Hale, "Dynamic warping of seismic images", Geophysics 78(2), S105-S115, 2013 (dynamic programming with a
   smoothness constraint on seismic shifts).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .reflectors import nearest_pick

__all__ = ["sample_at", "window_ncc", "dp_picks", "line_slopes", "reflector_period", "settle_lone_departures"]


@nb.njit(cache=True)
def sample_at(trace, t):
    """Amplitude of ``trace`` at fractional sample ``t`` by linear interpolation; NaN outside the trace."""
    n = trace.size
    if t < 0.0 or t > n - 1:
        return np.nan
    k = int(np.floor(t))
    if k >= n - 1:
        return trace[n - 1]
    f = t - k
    return (1.0 - f) * trace[k] + f * trace[k + 1]



@nb.njit(cache=True)
def _line_dp(trace_ids, guide, fixed, picks, offsets, traces, slopes, reach, w_guide, w_step, w_wave, half):
    """Viterbi along one line of traces: one candidate pick per trace (within ``reach`` of ``guide``), minimising
    ``w_guide |p - guide| + w_step (dp - dguide)^2 + w_wave (1 - ncc)``; a trace with ``fixed`` finite keeps only
    the candidate nearest to it. Returns the chosen pick per trace (NaN where the trace has no candidate; the line
    restarts after it)."""
    n = trace_ids.size
    out = np.full(n, np.nan)
    max_c = 64
    cand = np.full((n, max_c), np.nan)
    count = np.zeros(n, np.int64)
    for j in range(n):
        g = guide[j]
        if not np.isfinite(g):
            continue
        k = trace_ids[j]
        best_d = 1e9
        for q in range(offsets[k], offsets[k + 1]):
            d = abs(picks[q] - g)
            if d <= reach and count[j] < max_c:
                if np.isfinite(fixed[j]):
                    if abs(picks[q] - fixed[j]) < best_d:
                        best_d = abs(picks[q] - fixed[j])
                        cand[j, 0] = picks[q]
                        count[j] = 1
                else:
                    cand[j, count[j]] = picks[q]
                    count[j] += 1
    cost = np.full((n, max_c), np.inf)
    back = np.full((n, max_c), -1, np.int64)
    m = 2 * half + 1
    wa = np.empty(m)
    wb = np.empty(m)
    for j in range(n):
        for c in range(count[j]):
            u = w_guide[j] * abs(cand[j, c] - guide[j])
            if j == 0 or count[j - 1] == 0:
                cost[j, c] = u
                continue
            kb = trace_ids[j]
            ka = trace_ids[j - 1]
            for s in range(m):
                wb[s] = sample_at(traces[kb], cand[j, c] - half + s)
            best, arg = np.inf, -1
            for p in range(count[j - 1]):
                for s in range(m):
                    wa[s] = sample_at(traces[ka], cand[j - 1, p] - half + s)
                ns = slopes.shape[1]
                sa = slopes[ka, min(max(int(round(cand[j - 1, p])), 0), ns - 1)]
                sb = slopes[kb, min(max(int(round(cand[j, c])), 0), ns - 1)]
                step = (cand[j, c] - cand[j - 1, p]) - 0.5 * (sa + sb)
                r = window_ncc(wa, wb)
                v = cost[j - 1, p] + w_step * step * step + w_wave * (1.0 - r)
                if v < best:
                    best, arg = v, p
            cost[j, c] = best + u
            back[j, c] = arg
    # backtrack each run of traces with candidates from its end
    j = n - 1
    while j >= 0:
        if count[j] == 0:
            j -= 1
            continue
        c = 0
        for q in range(count[j]):
            if cost[j, q] < cost[j, c]:
                c = q
        while j >= 0 and count[j] > 0 and c >= 0:
            out[j] = cand[j, c]
            c = back[j, c]
            j -= 1
    return out


@nb.njit(cache=True)
def window_ncc(a, b):
    """Normalised cross-correlation of two equally long windows over their finite samples (0 with fewer than 5)."""
    sa = 0.0
    sb = 0.0
    cnt = 0
    for k in range(a.size):
        if np.isfinite(a[k]) and np.isfinite(b[k]):
            sa += a[k]
            sb += b[k]
            cnt += 1
    if cnt < 5:
        return 0.0
    ma, mb = sa / cnt, sb / cnt
    sab = 0.0
    saa = 0.0
    sbb = 0.0
    for k in range(a.size):
        if np.isfinite(a[k]) and np.isfinite(b[k]):
            sab += (a[k] - ma) * (b[k] - mb)
            saa += (a[k] - ma) ** 2
            sbb += (b[k] - mb) ** 2
    return sab / np.sqrt(saa * sbb) if saa > 0 and sbb > 0 else 0.0


def dp_picks(traces: np.ndarray, picks: np.ndarray, offsets: np.ndarray, guide: np.ndarray, lateral_shape: tuple,
             fixed: np.ndarray, slopes: np.ndarray, *, reach: float, w_guide: float, w_step: float, w_wave: float, half: int) -> np.ndarray:
    """Picks along every line of the last lateral axis chosen by :func:`_line_dp` (flat (n,) arrays in and out)."""
    g = guide.reshape(lateral_shape)
    f = fixed.reshape(lateral_shape)
    wg = np.broadcast_to(np.asarray(w_guide, np.float64), guide.shape).reshape(lateral_shape)
    ids = np.arange(g.size).reshape(lateral_shape)
    out = np.full(lateral_shape, np.nan)
    if len(lateral_shape) == 1:
        return _line_dp(ids, g, f, picks, offsets, traces, slopes, reach, np.ascontiguousarray(wg), w_step, w_wave,
                        half)
    for i in range(lateral_shape[0]):
        out[i] = _line_dp(ids[i], g[i], f[i], picks, offsets, traces, slopes, reach, np.ascontiguousarray(wg[i]), w_step,
                          w_wave, half)
    return out.ravel()


def line_slopes(data: np.ndarray, sigma_tensor, rows: tuple[int, int] | None = None) -> np.ndarray:
    """Reflector slope (samples per trace) along the last lateral axis, (n_traces, n_samples) float32 (structure
    tensor of each line, :func:`~seismo3d.seismic.structure_tensor_orientation`), computed in the band of samples
    ``rows`` (default all; 0 outside it)."""
    from .attributes import structure_tensor_orientation

    lo, hi = (0, data.shape[-1]) if rows is None else rows
    out = np.zeros(data.shape, np.float32)
    lines = data[None] if data.ndim == 2 else data
    view = out[None] if data.ndim == 2 else out
    for i in range(lines.shape[0]):
        view[i, :, lo:hi] = structure_tensor_orientation(lines[i, :, lo:hi], sigma_tensor=sigma_tensor).slopes[0]
    return out.reshape(-1, data.shape[-1])


def settle_lone_departures(picked: np.ndarray, guide: np.ndarray, lat: tuple, picks: np.ndarray, offsets: np.ndarray,
                           *, agree: float = 2.0) -> np.ndarray:
    """Picks of a cube that leave the least-squares solution by more than half a reflector period on their inline
    alone: moved to the pick nearest the solution.

    Each inline's picks are chosen by its own dynamic programme, so a departure from the (smooth, 3D) least-squares
    solution is believed where the neighbouring inlines make it too (a sag or a fault crosses several inlines: their
    departures agree within ``agree`` samples) and not where one inline makes it alone.

    Parameters
    ----------
    picked, guide : (n,) float64 ndarray
        The chosen picks and the least-squares solution (flat over the (n_inlines, n_xlines) grid ``lat``).
    lat : (int, int)
    picks, offsets : ndarray
        Every trace's picks (:func:`~seismo3d.seismic.reflector_picks` of the flattened cube).
    agree : float
        Samples.

    Returns
    -------
    (n,) float64 ndarray
        A new array.
    """
    have = np.nonzero(np.isfinite(picked))[0]
    period = reflector_period(picks, offsets, have[::7], picked[have[::7]])
    if not np.isfinite(period):
        return picked
    dev = (picked - guide).reshape(lat)
    lone = np.abs(dev) > 0.5 * period
    supported = np.zeros_like(lone)
    for step in (1, -1):
        nb = np.roll(dev, step, axis=0)
        ok = np.abs(nb - dev) <= agree
        if step == 1:
            ok[0] = False
        else:
            ok[-1] = False
        supported |= ok
    out = picked.copy()
    for k in np.nonzero((lone & ~supported).ravel())[0]:
        out[k] = nearest_pick(picks, offsets, k, guide[k], 0.5 * period)
    return out


def reflector_period(picks: np.ndarray, offsets: np.ndarray, traces: np.ndarray, times: np.ndarray) -> float:
    """Median spacing, samples, of consecutive same-polarity picks next to the horizon on ``traces``."""
    gaps = []
    for j, t in zip(traces, times):
        p = picks[offsets[j]:offsets[j + 1]]
        if p.size < 2 or not np.isfinite(t):
            continue
        k = int(np.clip(np.searchsorted(p, t), 1, p.size - 1))
        gaps.append(p[k] - p[k - 1])
    return float(np.median(gaps)) if gaps else np.nan
