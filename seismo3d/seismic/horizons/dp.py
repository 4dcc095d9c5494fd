"""Dynamic programming over candidate picks: the picks of each line of a horizon chosen together.

Given a guide (the least-squares horizon of :mod:`~seismo3d.seismic.horizons.lsq`), every trace of a line offers its
extrema of the horizon's polarity within ``reach`` samples of the guide as candidates; the Viterbi algorithm chooses
one per trace minimising, along the line, ``w_guide |pick - guide|`` (per trace) + ``w_step (step - slope)^2`` (the
step between neighbouring picks against the structure-tensor reflector slope there) + ``w_wave (1 - ncc)`` (their
waveforms' correlation); where a traced fault lies between the two traces the step is expected to be the slope plus
the fault's jump there (its throw, as the least-squares pairs take it), and a fault of unknown throw leaves the step
free. A seed's trace keeps the candidate nearest the seed. Lines are the last lateral axis
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

from concurrent.futures import ThreadPoolExecutor

import math

import numba as nb
import numpy as np

from ..attributes import section_slopes, structure_tensor_orientation
from ..reflectors import nearest_pick

__all__ = ["sample_at", "window_ncc", "dp_picks", "line_slopes", "reflector_period", "settle_lone_departures",
           "trace_search"]


# no_cfunc_wrapper: the kernels here are called from Python and from each other, never as C callbacks, so
# numba's C-callable wrapper of each is not compiled (0.02-0.03 CPU s a kernel on a first run)
@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def sample_at(trace, t):
    """Amplitude of ``trace`` at fractional sample ``t`` by linear interpolation; NaN outside the trace."""
    n = trace.size
    if t < 0.0 or t > n - 1:
        return np.nan
    k = math.floor(t)  # math.floor, not int(np.floor()): int() compiles a function of numba's of its own
    if k >= n - 1:
        return trace[n - 1]
    f = t - k
    return (1.0 - f) * trace[k] + f * trace[k + 1]



_MAX_CANDIDATES = 64  # candidates per trace at most (the reach holds a few reflector cycles)


def _candidates(traces, guide, fixed, picks, offsets, reach, half, slopes, cross_slopes):
    """Every trace's candidate picks and their waveforms, once for all the programmes of :func:`dp_picks`.

    A trace's candidates are its picks within ``reach`` of ``guide`` (the first :data:`_MAX_CANDIDATES` of them), or,
    where ``fixed`` is finite, the one of them nearest to it (the first on a tie); none where the guide is NaN.
    Returns ``(first, pick, unit, whole, slope, cross_slope)``, the candidates of trace ``k`` at
    ``first[k]:first[k + 1]`` of ``pick``; ``unit`` (n_candidates, 2 half + 1) float32 the window ``+-half`` samples
    around each pick centred and scaled to unit norm (zeros where flat), so that two windows' normalised
    cross-correlation is their dot product; ``whole`` False where a window leaves the trace (its correlations are
    :func:`window_ncc`'s of the raw windows); ``slope``, ``cross_slope`` the reflector slopes ``slopes`` and
    ``cross_slopes`` at each candidate. About ``4 (2 half + 1) + 18`` bytes a candidate (a few candidates a trace: ~0.2
    KB a trace at ``half`` 8). Array work in numpy (the compiled kernels it replaces cost the horizon's first run 1.2
    CPU s of compiling); the window sums are taken sample by sample, in the kernels' order (the same bits)."""
    n = guide.size
    trace = np.repeat(np.arange(n), np.diff(offsets))
    near = np.abs(picks - guide[trace]) <= reach  # False where the guide is NaN
    count = np.cumsum(near)
    rank = count - 1 - np.concatenate([[0], count])[offsets[:-1]][trace]  # among the trace's near picks
    keep = near & (rank < _MAX_CANDIDATES)
    seeded = np.isfinite(fixed)
    if seeded.any():
        on_seeded = seeded[trace]
        keep &= ~on_seeded
        d = np.where(near & on_seeded, np.abs(picks - fixed[trace]), np.inf)
        for k in np.nonzero(seeded)[0]:  # the seeds: a few traces
            dk = d[offsets[k]:offsets[k + 1]]
            if dk.size and dk.min() < 1e9:
                keep[offsets[k] + int(np.argmin(dk))] = True  # the first of the nearest
    chosen = np.nonzero(keep)[0]
    k = trace[chosen]
    first = np.zeros(n + 1, np.int64)
    first[1:] = np.cumsum(np.bincount(k, minlength=n))
    pick = picks[chosen].astype(np.float64)
    m = 2 * half + 1
    n_s = traces.shape[1]
    nearest = np.clip(np.rint(pick), 0, n_s - 1).astype(np.int64)  # the sample nearest each pick (round half even)
    slope = slopes[k, nearest].astype(np.float32)
    cross_slope = cross_slopes[k, nearest].astype(np.float32)
    win = sample_windows(traces, k, pick, half)
    whole = np.isfinite(win).all(axis=1)
    mean = np.zeros(pick.size)
    for s in range(m):  # summed sample by sample, in the kernel's order
        mean += win[:, s]
    mean /= m
    win -= mean[:, None]
    ss = np.zeros(pick.size)
    for s in range(m):
        ss += win[:, s] * win[:, s]
    unit = np.zeros((pick.size, m), np.float32)
    scaled = whole & (ss > 0)
    unit[scaled] = win[scaled] * (1.0 / np.sqrt(ss[scaled]))[:, None]
    return first, pick, unit, whole, slope, cross_slope


def sample_windows(traces: np.ndarray, rows: np.ndarray, centres: np.ndarray, half: int) -> np.ndarray:
    """The windows ``+-half`` samples around ``centres`` on the traces ``rows``, (n, 2 half + 1) float64:
    ``sample_at(traces[rows[p]], centres[p] - half + s)`` (:func:`sample_at`: linear interpolation, NaN outside the
    trace), in numpy, sample by sample."""
    n_s = traces.shape[1]
    win = np.empty((centres.size, 2 * half + 1))
    for s in range(2 * half + 1):
        t = centres - half + s
        i = np.clip(np.floor(t), 0, n_s - 1).astype(np.int64)
        f = t - i
        lo = traces[rows, i].astype(np.float64)
        v = (1.0 - f) * lo + f * traces[rows, np.minimum(i + 1, n_s - 1)].astype(np.float64)
        last = i >= n_s - 1
        v[last] = lo[last]
        v[(t < 0.0) | (t > n_s - 1) | ~np.isfinite(t)] = np.nan
        win[:, s] = v
    return win


def _windows_ncc(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`window_ncc` of each row of ``a`` with the same row of ``b``, in numpy (sums sample by sample, in its
    order)."""
    both = np.isfinite(a) & np.isfinite(b)
    cnt = both.sum(axis=1)
    sa = np.zeros(a.shape[0])
    sb = np.zeros(a.shape[0])
    for k in range(a.shape[1]):
        sa += np.where(both[:, k], a[:, k], 0.0)
        sb += np.where(both[:, k], b[:, k], 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ma, mb = sa / cnt, sb / cnt
        sab = np.zeros(a.shape[0])
        saa = np.zeros(a.shape[0])
        sbb = np.zeros(a.shape[0])
        for k in range(a.shape[1]):
            dx, dy = a[:, k] - ma, b[:, k] - mb
            sab += np.where(both[:, k], dx * dy, 0.0)
            saa += np.where(both[:, k], dx * dx, 0.0)
            sbb += np.where(both[:, k], dy * dy, 0.0)
        out = np.where((saa > 0) & (sbb > 0), sab / np.sqrt(saa * sbb), 0.0)
    return np.where(cnt < 5, 0.0, out)


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _candidate_at(first, pick, k, t):
    """The index of trace ``k``'s candidate at ``t`` (exactly), -1 where ``t`` is none of them."""
    for q in range(first[k], first[k + 1]):
        if pick[q] == t:
            return q
    return -1


@nb.njit(cache=True, no_cfunc_wrapper=True, fastmath={"reassoc", "contract", "nsz"})
def _unit_dot(ua, ub):
    """The dot product of two unit windows (float32, summed in float64; reassociated, so it is vectorised)."""
    r = 0.0
    for s in range(nb.uint64(ua.size)):
        r += np.float64(ua[s]) * np.float64(ub[s])
    return r


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _pick_ncc(traces, unit, whole, ka, ta, qa, kb, tb, qb, half, wa, wb):
    """Normalised cross-correlation of the windows ``+-half`` samples around ``ta`` on trace ``ka`` and ``tb`` on
    ``kb`` (:func:`window_ncc`): the dot product of the candidates' unit windows ``qa``, ``qb`` where both lie inside
    their traces, else computed from the traces (``wa``, ``wb``: work arrays)."""
    if qa >= 0 and qb >= 0 and whole[qa] and whole[qb]:
        return _unit_dot(unit[qa], unit[qb])
    for s in range(2 * half + 1):
        wa[s] = sample_at(traces[ka], ta - half + s)
        wb[s] = sample_at(traces[kb], tb - half + s)
    return window_ncc(wa, wb)


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _slope_at(slopes, k, t):
    """The reflector slope on trace ``k`` at the sample nearest ``t``."""
    i = round(t)  # the bounds by comparisons: min() and max() compile functions of numba's of their own
    i = 0 if i < 0 else i
    return slopes[k, slopes.shape[1] - 1 if i > slopes.shape[1] - 1 else i]


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def window_ncc(a, b):
    """Normalised cross-correlation of two equally long windows over their finite samples (0 with fewer than 5)."""
    sa = 0.0
    sb = 0.0
    cnt = 0
    for k in range(a.size):
        if math.isfinite(a[k]) and math.isfinite(b[k]):
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
        if math.isfinite(a[k]) and math.isfinite(b[k]):
            da = a[k] - ma
            db = b[k] - mb
            sab += da * db
            saa += da * da  # not ** 2: it compiles a power function of numba's (the same bits)
            sbb += db * db
    return sab / math.sqrt(saa * sbb) if saa > 0 and sbb > 0 else 0.0


def dp_picks(traces: np.ndarray, picks: np.ndarray, offsets: np.ndarray, guide: np.ndarray, lateral_shape: tuple,
             fixed: np.ndarray, slopes: np.ndarray, *, reach: float, w_guide, w_step: float, w_wave: float, half: int,
             cross_slopes: np.ndarray | None = None, sweeps: int = 0, jumps: list | None = None) -> np.ndarray:
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
    jumps : list of ndarray, optional
        Traced faults' jumps between neighbouring traces, one array per lateral axis shaped like the grid less one
        along the axis (:attr:`~seismo3d.seismic.horizons.fault_pairs.FaultSteps.jumps`, samples; 0 where no fault):
        a step across a fault is expected to be the reflector slope plus the jump (Hale 2013: the horizon jumps by
        the throw), and a step across a fault of unknown throw (NaN) costs nothing; default no faults.

    Returns
    -------
    (n,) float64 ndarray
        Picks, samples (NaN where a trace has no candidate).

    Notes
    -----
    Raises nothing of its own: its callers (:func:`~seismo3d.seismic.horizons.lsq.lsq_horizon`) check the inputs.
    """
    g = guide.reshape(lateral_shape)
    # a writable copy: a read-only view (an (n,) w_guide broadcast) would compile the kernels taking it a second time
    wg = np.array(np.broadcast_to(np.asarray(w_guide, np.float64), guide.shape).reshape(lateral_shape))
    ids = np.arange(g.size).reshape(lateral_shape)
    across = slopes if cross_slopes is None else cross_slopes
    steps = _grid_jumps(jumps, g.shape)  # the jump into each trace from the previous one along each axis
    *cands, slope, cross_slope = _candidates(traces, np.ascontiguousarray(guide, np.float64),
                                             np.ascontiguousarray(fixed, np.float64), picks, offsets, float(reach),
                                             int(half), slopes, across)
    # every line alone (no neighbouring line held), as a section's single line or a cube's first picks
    lines = np.full(lateral_shape, np.nan)
    _sweep_lines(lines.reshape(-1, g.shape[-1]), np.ascontiguousarray(g.reshape(-1, g.shape[-1])),
                 wg.reshape(-1, g.shape[-1]), ids.reshape(-1, g.shape[-1]), *cands, slope, cross_slope, traces,
                 slopes, across, steps[-1].reshape(-1, g.shape[-1]), steps[0].reshape(-1, g.shape[-1]), w_step,
                 w_wave, half, False)
    if len(lateral_shape) == 1 or cross_slopes is None or sweeps <= 0:
        return lines.ravel()
    nearest = _nearest_picks(picks, offsets, np.where(np.isfinite(fixed), fixed, guide), reach)
    nearest[~np.isfinite(guide)] = np.nan

    def descend(start):
        cur = start.copy()
        for _ in range(sweeps):
            _sweep(cur, g, wg, ids, cands, (slope, cross_slope), traces, slopes, cross_slopes, steps, w_step, w_wave,
                   half)
        return cur, _grid_energy(cur, g, wg, *cands, traces, slopes, cross_slopes, steps, w_step, w_wave, half)

    # the two starts are independent: one thread each (the compiled sweeps release the GIL)
    with ThreadPoolExecutor(2) as pool:
        ends = list(pool.map(descend, (lines, nearest.reshape(lateral_shape))))
    best, best_energy = lines, np.inf
    for cur, energy in ends:  # in order: on a tie the line-by-line start's, as one after the other
        if energy < best_energy:
            best, best_energy = cur, energy
    return best.ravel()


def _grid_jumps(jumps, lateral_shape) -> list:
    """The faults' jumps of :func:`dp_picks` as one array per lateral axis shaped like the grid: the jump into each
    trace from the previous one along the axis (0 on the first; zeros without faults)."""
    out = []
    for axis in range(len(lateral_shape)):
        grid = np.zeros(lateral_shape)
        if jumps is not None:
            np.moveaxis(grid, axis, 0)[1:] = np.moveaxis(np.asarray(jumps[axis], np.float64), axis, 0)
        out.append(grid)
    return out


def _sweep(out, g, wg, ids, cands, at_candidates, traces, slopes, cross_slopes, steps, w_step, w_wave, half):
    """One coordinate-descent sweep: every line along the first lateral axis, then along the last, re-chosen by
    :func:`_sweep_lines` with the picks of its two neighbouring lines held (``out``, (n_inlines, n_xlines), updated in
    place; ``cands``: :func:`_candidates`' candidates and waveforms, ``at_candidates`` its two slopes; ``steps``:
    :func:`_grid_jumps`)."""
    for axis in (0, 1):
        along, across = (cross_slopes, slopes) if axis == 0 else (slopes, cross_slopes)
        along_c, across_c = at_candidates[::-1] if axis == 0 else at_candidates
        j_along, j_across = (steps[0], steps[1]) if axis == 0 else (steps[1], steps[0])
        g_t, w_t, ids_t, out_t, ja_t, jc_t = (np.ascontiguousarray(np.moveaxis(x, axis, -1))
                                              for x in (g, wg, ids, out, j_along, j_across))
        _sweep_lines(out_t, g_t, w_t, ids_t, *cands, along_c, across_c, traces, along, across, ja_t, jc_t, w_step,
                     w_wave, half, True)
        np.moveaxis(out, axis, -1)[...] = out_t


def _sweep_lines(out, guide, w_guide, ids, first, pick, unit, whole, along_c, across_c, traces, along, across,
                 jump_along, jump_across, w_step, w_wave, half, hold):
    """:func:`_choose_lines` with its work arrays allocated here (a kernel's np.empty compiles numba's allocator:
    0.2 CPU s of a first run)."""
    length = guide.shape[1]
    width = max(1, int(np.diff(first).max(initial=0)))
    _choose_lines(out, guide, w_guide, ids, first, pick, unit, whole, along_c, across_c, traces, along, across,
                  jump_along, jump_across, w_step, w_wave, half, hold, np.empty((length, 2), np.int64),
                  np.empty((length, 2)), np.empty((length, width)), np.empty((length, width), np.int64),
                  np.empty(2 * half + 1), np.empty(2 * half + 1), np.empty(2, np.int64))


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _step_cost(step, jump, w_step):
    """``w_step (step - jump)^2``; 0 across a fault of unknown throw (``jump`` NaN)."""
    if not math.isfinite(jump):
        return 0.0
    d = step - jump
    return w_step * d * d


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _choose_lines(out, guide, w_guide, ids, first, pick, unit, whole, along_c, across_c, traces, along, across,
                  jump_along, jump_across, w_step, w_wave, half, hold, c_ids, c_t, cost, back, wa, wb, held):
    """The lines (rows of the (n_lines, length) arrays) chosen in order, into ``out``; with ``hold``, each with the
    picks in ``out`` of the line before it (already re-chosen) and of the line after it held, else each alone.

    Viterbi along each line of traces: one candidate pick per trace (:func:`_candidates`), minimising the sum of
    ``w_guide |p - guide|`` per trace and ``w_step (step - slope)^2 + w_wave (1 - ncc)`` per step. The picks of the
    neighbouring lines held (``c_ids`` / ``c_t`` (length, 2), -1 / NaN where none; the previous line's in column 0
    and the next line's in column 1) add their pair costs (slopes ``across`` across the lines) to each candidate's
    guide term. ``along_c``, ``across_c``: ``along`` and ``across`` at each candidate. ``jump_along[i, j]``: the
    faults' jump from trace ``j - 1`` to ``j`` of line ``i``; ``jump_across[i, j]``: from line ``i - 1`` to line ``i``
    at trace ``j`` (:func:`_grid_jumps`): a step is expected to be the slope plus it. A line's pick is NaN where the
    trace has no candidate; the line restarts after it. ``c_ids``, ``c_t``, ``cost``, ``back`` (length, at least the
    most candidates of a trace), ``wa``, ``wb`` (2 half + 1), ``held`` (2): work arrays. One kernel, not a loop calling
    a kernel per line: numba compiles a called kernel on its own and again inside its caller."""
    n_lines, length = guide.shape
    for i in range(n_lines):
        # the neighbouring lines' picks, by loops (slice assignments and np.full compile numba's generic setitem and
        # fill: seconds)
        for j in range(length):
            for side in range(2):
                c_ids[j, side] = -1
                c_t[j, side] = np.nan
        for side in range(2):  # not a loop over a tuple of tuples: numba compiles its iterator
            other = i - 1 if side == 0 else i + 1
            if hold and 0 <= other < n_lines:
                for j in range(length):
                    c_ids[j, side] = ids[other, j]
                    c_t[j, side] = out[other, j]
        trace_ids, g_line, wg_line = ids[i], guide[i], w_guide[i]
        n = trace_ids.size
        width = 1
        for j in range(n):
            out[i, j] = np.nan  # loops, not np.full: it compiles numba's generic fill (about 1 CPU s)
            count = first[trace_ids[j] + 1] - first[trace_ids[j]]
            width = count if count > width else width
        for j in range(n):
            for c in range(width):
                cost[j, c] = np.inf
                back[j, c] = -1
        n_cross = c_ids.shape[1]
        for j in range(n):
            kb = trace_ids[j]
            # the neighbouring lines' picks: the same for every candidate of the trace (-2: none held)
            for e in range(n_cross):
                held[e] = -2
                if c_ids[j, e] >= 0 and math.isfinite(c_t[j, e]):
                    held[e] = _candidate_at(first, pick, c_ids[j, e], c_t[j, e])
            ka = trace_ids[j - 1] if j > 0 else -1
            n_prev = first[ka + 1] - first[ka] if j > 0 else 0
            for c in range(first[kb + 1] - first[kb]):
                qb = first[kb] + c
                tb = pick[qb]
                sb = along_c[qb]
                u = wg_line[j] * abs(tb - g_line[j])
                best, arg = np.inf, -1
                # the partners of the candidate: the neighbouring lines' picks held (e < n_cross), then the previous
                # trace's candidates; one loop, so that _pick_ncc has one call site (inlined: a called kernel is
                # compiled on its own too, and an inlined one at each call site)
                for e in range(n_cross + n_prev):
                    if e < n_cross:
                        if held[e] == -2:
                            continue
                        ko = c_ids[j, e]
                        to = c_t[j, e]
                        qo = held[e]
                        so = across_c[qo] if qo >= 0 else _slope_at(across, ko, to)
                        sc = across_c[qb]
                        # the previous line's pick before this one (e = 0), the next line's after it
                        step = (tb - to) - 0.5 * (so + sc) if e == 0 else (to - tb) - 0.5 * (sc + so)
                        jump = jump_across[i, j] if e == 0 else jump_across[i + 1, j]
                    else:
                        ko = ka
                        qo = first[ka] + e - n_cross
                        to = pick[qo]
                        step = (tb - to) - 0.5 * (along_c[qo] + sb)
                        jump = jump_along[i, j]
                    r = _pick_ncc(traces, unit, whole, ko, to, qo, kb, tb, qb, half, wa, wb)
                    if e < n_cross:
                        u += _step_cost(step, jump, w_step) + w_wave * (1.0 - r)
                        continue
                    v = cost[j - 1, e - n_cross] + _step_cost(step, jump, w_step) + w_wave * (1.0 - r)
                    if v < best:
                        best, arg = v, e - n_cross
                if n_prev == 0:
                    cost[j, c] = u
                    continue
                cost[j, c] = best + u
                back[j, c] = arg
        # backtrack each run of traces with candidates from its end
        j = n - 1
        while j >= 0:
            count = first[trace_ids[j] + 1] - first[trace_ids[j]]
            if count == 0:
                j -= 1
                continue
            c = 0
            for q in range(count):
                if cost[j, q] < cost[j, c]:
                    c = q
            while j >= 0 and first[trace_ids[j] + 1] > first[trace_ids[j]] and c >= 0:
                out[i, j] = pick[first[trace_ids[j]] + c]
                c = back[j, c]
                j -= 1


def _nearest_picks(picks, offsets, times, reach):
    """Each trace's pick nearest to ``times`` ((n,) samples) within ``reach`` samples (the later one on a tie), NaN
    where none."""
    trace = np.repeat(np.arange(times.size), np.diff(offsets))
    d = np.abs(picks - times[trace])  # NaN where the time is
    best = np.full(times.size, np.inf)
    np.minimum.at(best, trace, np.where(np.isnan(d), np.inf, d))
    at = np.nonzero((d <= reach) & (d == best[trace]))[0]
    last = np.full(times.size, -1)
    np.maximum.at(last, trace[at], at)
    return np.where(last >= 0, picks[last], np.nan)


def _grid_energy(out, guide, wg, first, pick, unit, whole, traces, slopes, cross_slopes, steps, w_step, w_wave,
                 half):
    """The energy the line sweeps lower, over a (n_inlines, n_xlines) grid of picks: guide terms plus the pair costs
    ``w_step (step - slope)^2 + w_wave (1 - ncc)`` of neighbouring traces along both axes (pairs with an empty pick
    left out). In numpy: the terms added one after the other in the order of a loop over the grid (each trace's
    guide term, then its pairs down the first axis and along the last), by a cumulative sum; the correlations of
    two unit windows are dot products summed in numpy's order (the compiled loop's were reassociated)."""
    ni, nx = out.shape
    t = out.ravel()
    live = np.isfinite(t)
    k = np.nonzero(live)[0]
    # each picked trace's candidate at its pick (the first equal one; -1: none)
    owner = np.repeat(np.arange(t.size), np.diff(first))
    hit = np.nonzero(pick == t[owner])[0]
    q = np.full(t.size, np.iinfo(np.int64).max)
    np.minimum.at(q, owner[hit], hit)
    q[q == np.iinfo(np.int64).max] = -1
    terms = np.zeros((t.size, 3))
    terms[k, 0] = wg.ravel()[k] * np.abs(t[k] - guide.ravel()[k])
    n_s = slopes.shape[1]
    for col, (along, shift, jump) in enumerate(((cross_slopes, nx, steps[0].ravel()), (slopes, 1, steps[1].ravel())),
                                               start=1):
        ka = k[(k % nx + 1 < nx) if shift == 1 else (k + shift < t.size)]  # the pair's second trace on the grid
        ka = ka[live[ka + shift]]
        kb = ka + shift
        ta, tb = t[ka], t[kb]
        sa = along[ka, np.clip(np.rint(ta), 0, n_s - 1).astype(np.int64)]
        sb = along[kb, np.clip(np.rint(tb), 0, n_s - 1).astype(np.int64)]
        step = (tb - ta) - 0.5 * (sa + sb)  # the slopes added in their dtype, as the compiled loop
        jb = jump[kb]
        with np.errstate(invalid="ignore"):
            step_cost = np.where(np.isfinite(jb), w_step * (step - jb) * (step - jb), 0.0)
        qa, qb = q[ka], q[kb]
        units = (qa >= 0) & (qb >= 0)
        units[units] &= whole[qa[units]] & whole[qb[units]]
        r = np.empty(ka.size)
        r[units] = np.einsum("ij,ij->i", unit[qa[units]].astype(np.float64), unit[qb[units]].astype(np.float64))
        raw = ~units
        if raw.any():
            r[raw] = _windows_ncc(sample_windows(traces, ka[raw], ta[raw], half),
                                  sample_windows(traces, kb[raw], tb[raw], half))
        terms[ka, col] = step_cost + w_wave * (1.0 - r)
    return float(np.cumsum(terms.ravel())[-1]) if terms.size else 0.0


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
    gaps = _pick_gaps(picks, offsets, np.asarray(traces, np.int64), np.asarray(times, np.float64))
    return float(np.median(gaps)) if gaps.size else np.nan


def trace_search(picks: np.ndarray, offsets: np.ndarray, traces: np.ndarray, values: np.ndarray,
                 side: str = "left") -> np.ndarray:
    """``np.searchsorted`` of each value in its trace's sorted picks, for many traces at once.

    Parameters
    ----------
    picks, offsets : ndarray
        Every trace's sorted picks (:func:`~seismo3d.seismic.reflector_picks`: trace ``j``'s picks are
        ``picks[offsets[j]:offsets[j + 1]]``).
    traces : (m,) int ndarray
        The trace of each value.
    values : (m,) float64 ndarray
    side : {"left", "right"}
        The first pick ``>=`` the value (left) or ``>`` it (right).

    Returns
    -------
    (m,) int64 ndarray
        The index into ``picks`` (from ``offsets[trace]`` to ``offsets[trace + 1]``). A binary search of all the
        values together, in numpy (the compiled search per trace it replaces cost a first run compiling).
    """
    lo = offsets[traces].astype(np.int64)
    hi = offsets[traces + 1].astype(np.int64)
    top = max(picks.size - 1, 0)
    while True:
        active = lo < hi
        if not active.any():
            return lo
        mid = (lo + hi) >> 1
        key = picks[np.minimum(mid, top)] if picks.size else np.zeros(mid.size)
        up = active & ((key < values) if side == "left" else (key <= values))
        lo = np.where(up, mid + 1, lo)
        hi = np.where(active & ~up, mid, hi)


def _pick_gaps(picks, offsets, traces, times):
    """The spacing of the two picks around ``times`` on each of ``traces`` (the pair at the nearer end where the
    time lies outside them); traces with fewer than two picks or no time are left out."""
    ok = (offsets[traces + 1] - offsets[traces] >= 2) & np.isfinite(times)
    traces, times = traces[ok], times[ok]
    k = trace_search(picks, offsets, traces, times)
    k = np.minimum(np.maximum(k, offsets[traces] + 1), offsets[traces + 1] - 1)
    return picks[k] - picks[k - 1]
