"""Dynamic programming over candidate picks: the picks of each line of a horizon chosen together.

Given a guide (the least-squares horizon of :mod:`~seismo3d.seismic.horizons.lsq`), every trace of a line offers its
extrema of the horizon's polarity within ``reach`` samples of the guide as candidates; the Viterbi algorithm chooses
one per trace minimising, along the line, ``w_guide |pick - guide|`` (per trace) + ``w_step (step - slope)^2`` (the
step between neighbouring picks against the structure-tensor reflector slope there) + ``w_wave (1 - ncc)`` (their
waveforms' correlation). A seed's trace keeps the candidate nearest the seed. Lines are the last lateral axis
(crosslines of each inline). In a cube the lines are then chosen together: sweeps over inlines and crosslines lower
the energy of the whole surface, the same terms along both lateral axes (:func:`dp_picks`). Without sweeps,
:func:`settle_lone_departures` moves back picks that leave the guide by half a reflector period on their inline
alone.

References
----------
.. [1] A. J. Viterbi, "Error bounds for convolutional codes and an asymptotically optimum decoding algorithm", IEEE
   Trans. Information Theory 13(2), 260-269, 1967.
.. [2] D. Hale, "Dynamic warping of seismic images", Geophysics 78(2), S105-S115, 2013 (dynamic programming with a
   smoothness constraint on seismic shifts).
.. [3] J. Besag, "On the statistical analysis of dirty pictures", J. Royal Statistical Society B 48(3), 259-302,
   1986 (iterated conditional modes: coordinate descent on a Markov random field's energy).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..attributes import section_slopes, structure_tensor_orientation
from ..reflectors import nearest_pick

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
def _line_dp(trace_ids, guide, fixed, picks, offsets, traces, slopes, reach, w_guide, w_step, w_wave, half,
             cross_ids, cross_t, cross_slopes):
    """Viterbi along one line of traces: one candidate pick per trace (within ``reach`` of ``guide``), minimising the
    sum of ``w_guide |p - guide|`` per trace and :func:`_pair_cost` per step; a trace with ``fixed`` finite keeps only
    the candidate nearest to it. ``cross_ids`` / ``cross_t`` ((n, k), -1 / NaN where none) are picks of neighbouring
    lines held fixed, the previous line's in column 0 and the next line's in column 1: their pair costs (slopes
    ``cross_slopes`` across the lines) join each candidate's guide term. Returns the chosen pick per trace (NaN where
    the trace has no candidate; the line restarts after it)."""
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
    win_prev = np.empty((max_c, m))  # the candidates' windows on the previous trace and on this one
    win = np.empty((max_c, m))
    ns = slopes.shape[1]
    n_cross = cross_ids.shape[1]
    w_cross = np.empty((n_cross, m))
    for j in range(n):
        kb = trace_ids[j]
        # the neighbouring lines' windows: the same for every candidate of the trace
        for e in range(n_cross):
            if cross_ids[j, e] >= 0 and np.isfinite(cross_t[j, e]):
                for s in range(m):
                    w_cross[e, s] = sample_at(traces[cross_ids[j, e]], cross_t[j, e] - half + s)
        win_prev, win = win, win_prev
        for c in range(count[j]):
            wb = win[c]
            for s in range(m):
                wb[s] = sample_at(traces[kb], cand[j, c] - half + s)
            u = w_guide[j] * abs(cand[j, c] - guide[j])
            for e in range(n_cross):
                ko = cross_ids[j, e]
                to = cross_t[j, e]
                if ko < 0 or not np.isfinite(to):
                    continue
                so = cross_slopes[ko, min(max(int(round(to)), 0), ns - 1)]
                sc = cross_slopes[kb, min(max(int(round(cand[j, c])), 0), ns - 1)]
                # the previous line's pick before this one (e = 0), the next line's after it
                step = (cand[j, c] - to) - 0.5 * (so + sc) if e == 0 else (to - cand[j, c]) - 0.5 * (sc + so)
                u += _windows_cost(step, w_cross[e], wb, w_step, w_wave)
            if j == 0 or count[j - 1] == 0:
                cost[j, c] = u
                continue
            ka = trace_ids[j - 1]
            best, arg = np.inf, -1
            for p in range(count[j - 1]):
                wa = win_prev[p]
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
             fixed: np.ndarray, slopes: np.ndarray, *, reach: float, w_guide, w_step: float, w_wave: float, half: int,
             cross_slopes: np.ndarray | None = None, sweeps: int = 0) -> np.ndarray:
    """Picks of a horizon chosen by dynamic programming along lines, then (cubes) by sweeps over both lateral axes.

    Every line of the last lateral axis (crosslines of each inline) is chosen by the Viterbi algorithm (module
    docstring). For a cube with ``cross_slopes`` and ``sweeps`` > 0 the lines are then chosen together, by coordinate
    descent on the energy of the whole surface: the guide terms plus the pair costs (step against the reflector slope,
    waveform correlation) of neighbouring traces along *both* lateral axes. Each sweep re-chooses every line of the
    first axis, then of the last, by the same dynamic programme with the pair costs to the picks of its two
    neighbouring lines, held, added to each candidate's guide term; no re-choice raises the energy, which the
    line-by-line choice, blind across lines, can leave high (neighbouring inlines a cycle apart over a patch).
    Coordinate descent stops in a local minimum, and a patch one cycle off that is continuous inside is one, so it runs
    from two starts, the line-by-line picks and the picks nearest the guide, and keeps the lower energy. This is
    iterated conditional modes (reference 3 of the module) with lines as blocks.

    Parameters
    ----------
    traces : (n, n_samples) float32 ndarray
        The traces, flat over the lateral grid.
    picks, offsets : ndarray
        Every trace's picks of the horizon's polarity (:func:`~seismo3d.seismic.reflector_picks`), samples.
    guide : (n,) float64 ndarray
        The guide (least-squares horizon), samples; NaN: the trace gets no pick.
    lateral_shape : (int,) or (int, int)
        The lateral grid.
    fixed : (n,) float64 ndarray
        Seed times (NaN elsewhere): a seed trace keeps its candidate nearest the seed.
    slopes : (n, n_samples) float32 ndarray
        Reflector slope along the last lateral axis (:func:`line_slopes`), samples per trace.
    reach : float
        Candidates lie within ``reach`` samples of the guide.
    w_guide : float or (n,) float64 ndarray
        Weight of ``|pick - guide|`` (per sample).
    w_step, w_wave : float
        Weights of ``(step - slope)^2`` (per sample squared) and of ``1 - ncc``.
    half : int
        Half-length of the waveform windows, samples.
    cross_slopes : (n, n_samples) float32 ndarray, optional
        Reflector slope along the first lateral axis (cubes); without it, no sweeps.
    sweeps : int
        Coordinate-descent sweeps over both axes (cubes; 0: the line-by-line picks).

    Returns
    -------
    (n,) float64 ndarray
        Picks, samples (NaN where a trace has no candidate).

    Notes
    -----
    Raises nothing of its own: its callers (:func:`~seismo3d.seismic.horizons.lsq.lsq_horizon`) check the inputs.
    """
    g = guide.reshape(lateral_shape)
    f = fixed.reshape(lateral_shape)
    wg = np.ascontiguousarray(np.broadcast_to(np.asarray(w_guide, np.float64), guide.shape).reshape(lateral_shape))
    ids = np.arange(g.size).reshape(lateral_shape)
    no_ids = np.full((g.shape[-1], 0), -1, np.int64)
    no_t = np.full((g.shape[-1], 0), np.nan)
    if len(lateral_shape) == 1:
        return _line_dp(ids, g, f, picks, offsets, traces, slopes, reach, wg, w_step, w_wave, half, no_ids, no_t,
                        slopes)
    lines = np.full(lateral_shape, np.nan)
    for i in range(lateral_shape[0]):
        lines[i] = _line_dp(ids[i], g[i], f[i], picks, offsets, traces, slopes, reach, wg[i], w_step, w_wave, half,
                            no_ids, no_t, slopes)
    if cross_slopes is None or sweeps <= 0:
        return lines.ravel()
    nearest = _nearest_picks(picks, offsets, np.where(np.isfinite(fixed), fixed, guide), reach)
    nearest[~np.isfinite(guide)] = np.nan
    best, best_energy = lines, np.inf
    for start in (lines, nearest.reshape(lateral_shape)):
        cur = start.copy()
        for _ in range(sweeps):
            _sweep(cur, g, f, wg, ids, picks, offsets, traces, slopes, cross_slopes, reach, w_step, w_wave, half)
        energy = _grid_energy(cur, g, wg, traces, slopes, cross_slopes, w_step, w_wave, half)
        if energy < best_energy:
            best, best_energy = cur, energy
    return best.ravel()


def _sweep(out, g, f, wg, ids, picks, offsets, traces, slopes, cross_slopes, reach, w_step, w_wave, half):
    """One coordinate-descent sweep: every line along the first lateral axis, then along the last, re-chosen by
    :func:`_line_dp` with the picks of its two neighbouring lines held (``out``, (n_inlines, n_xlines), updated in
    place)."""
    for axis in (0, 1):
        along, across = (cross_slopes, slopes) if axis == 0 else (slopes, cross_slopes)
        g_t, f_t, w_t, ids_t, out_t = (np.ascontiguousarray(np.moveaxis(x, axis, -1)) for x in (g, f, wg, ids, out))
        _sweep_lines(out_t, g_t, f_t, w_t, ids_t, picks, offsets, traces, along, across, reach, w_step, w_wave, half)
        np.moveaxis(out, axis, -1)[...] = out_t


@nb.njit(cache=True)
def _sweep_lines(out, guide, fixed, w_guide, ids, picks, offsets, traces, along, across, reach, w_step, w_wave,
                 half):
    """The lines (rows of the (n_lines, length) arrays) re-chosen in order by :func:`_line_dp`, each with the picks
    of the line before it (already re-chosen) and after it held; ``out`` updated in place."""
    n_lines, length = guide.shape
    for i in range(n_lines):
        c_ids = np.full((length, 2), -1, np.int64)
        c_t = np.full((length, 2), np.nan)
        if i > 0:
            c_ids[:, 0] = ids[i - 1]
            c_t[:, 0] = out[i - 1]
        if i + 1 < n_lines:
            c_ids[:, 1] = ids[i + 1]
            c_t[:, 1] = out[i + 1]
        out[i] = _line_dp(ids[i], guide[i], fixed[i], picks, offsets, traces, along, reach, w_guide[i], w_step,
                          w_wave, half, c_ids, c_t, across)


@nb.njit(cache=True)
def _nearest_picks(picks, offsets, times, reach):
    """Each trace's pick nearest to ``times`` ((n,) samples) within ``reach`` samples, NaN where none."""
    out = np.full(times.size, np.nan)
    for k in range(times.size):
        t = times[k]
        if not np.isfinite(t):
            continue
        best = reach
        for q in range(offsets[k], offsets[k + 1]):
            d = abs(picks[q] - t)
            if d <= best:
                best = d
                out[k] = picks[q]
    return out


@nb.njit(cache=True)
def _pair_cost(traces, ka, ta, kb, tb, sa, sb, w_step, w_wave, half, wa, wb):
    """Cost of picks ``ta`` on trace ``ka`` and ``tb`` on its next trace ``kb`` (slopes ``sa``, ``sb`` at the two
    picks; ``wa``, ``wb``: work arrays for their windows): :func:`_windows_cost`."""
    for s in range(2 * half + 1):
        wa[s] = sample_at(traces[ka], ta - half + s)
        wb[s] = sample_at(traces[kb], tb - half + s)
    return _windows_cost((tb - ta) - 0.5 * (sa + sb), wa, wb, w_step, w_wave)


@nb.njit(cache=True)
def _windows_cost(step, wa, wb, w_step, w_wave):
    """``w_step step^2 + w_wave (1 - ncc)``: a step (samples, less the reflector slope) and the correlation of the two
    picks' windows."""
    return w_step * step * step + w_wave * (1.0 - window_ncc(wa, wb))


@nb.njit(cache=True)
def _grid_energy(out, guide, wg, traces, slopes, cross_slopes, w_step, w_wave, half):
    """The energy the line sweeps lower, over a (n_inlines, n_xlines) grid of picks: guide terms plus the pair costs
    of neighbouring traces along both axes (pairs with an empty pick left out)."""
    ni, nx = out.shape
    ns = slopes.shape[1]
    wa = np.empty(2 * half + 1)
    wb = np.empty(2 * half + 1)
    e = 0.0
    for i in range(ni):
        for j in range(nx):
            t = out[i, j]
            if not np.isfinite(t):
                continue
            e += wg[i, j] * abs(t - guide[i, j])
            k = i * nx + j
            r = min(max(int(round(t)), 0), ns - 1)
            if j + 1 < nx and np.isfinite(out[i, j + 1]):
                t2 = out[i, j + 1]
                r2 = min(max(int(round(t2)), 0), ns - 1)
                e += _pair_cost(traces, k, t, k + 1, t2, slopes[k, r], slopes[k + 1, r2], w_step, w_wave, half, wa, wb)
            if i + 1 < ni and np.isfinite(out[i + 1, j]):
                t2 = out[i + 1, j]
                r2 = min(max(int(round(t2)), 0), ns - 1)
                e += _pair_cost(traces, k, t, k + nx, t2, cross_slopes[k, r], cross_slopes[k + nx, r2], w_step, w_wave,
                                half, wa, wb)
    return e


def line_slopes(data: np.ndarray, sigma_tensor, rows: tuple[int, int] | None = None, *, axis: int = -1) -> np.ndarray:
    """Reflector slope (samples per trace) along one lateral axis, (n_traces, n_samples) float32 flat over the lateral
    grid: the structure tensor of each line along ``axis`` (-1: the last lateral axis, the crosslines of each inline;
    0: the inline axis of a cube; :func:`~seismo3d.seismic.attributes.section_slopes`), computed in the band of
    samples ``rows`` (default all; 0 outside it)."""
    lo, hi = (0, data.shape[-1]) if rows is None else rows
    out = np.zeros(data.shape, np.float32)
    if data.ndim == 2:
        out[:, lo:hi] = structure_tensor_orientation(data[:, lo:hi], sigma_tensor=sigma_tensor).slopes[0]
    else:
        out[..., lo:hi] = section_slopes(data[..., lo:hi], 0 if axis == 0 else 1, sigma_tensor=sigma_tensor)
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
