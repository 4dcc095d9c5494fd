"""Least-squares horizons: one global solve from correlation shifts between near and distant traces.

A horizon ``t`` (one fractional sample per trace) is found as the least-squares solution of many difference
equations ``t[b] - t[a] = s_ab``, one per *pair* of traces ``a, b`` on the same inline or crossline at distances
``1, 2, 4, ..., 32`` traces apart, plus the seeds (Wu & Fomel 2018: least-squares horizons with local slopes and
multigrid correlations; here the neighbours' slopes are correlations too). Each shift ``s_ab`` is found by normalised
cross-correlation of a long window of trace ``a`` (``+-correlation_half`` samples around ``t[a]``: several reflector
cycles, so the sequence of reflectors and not one cycle decides) with trace ``b`` searched ``+-max_lag`` samples
around the current estimate (near the ends of the traces, where the window overlaps trace ``b`` at too few lags on
one side, the lags are cut as far on the other side: searched on one side only, the wrong-cycle matches of noisy
pairs would all fall there and bias the solve). A pair weighs its correlation squared over its distance to
``distance_power`` (pairs below ``min_pair_correlation`` are left out), and the solve is iteratively re-weighted with
Cauchy weights (scale ``robust`` samples) so that pairs the solution disagrees with lose their say. Because the
equations hold differences only and the long pairs tie distant traces directly, one bad local step (a cycle skip at a
pockmark's sag, a wrong shift across a fault) is outvoted by the pairs that span it and cannot propagate. The estimate
starts flat at the seeds' time and is re-solved a few times with the shifts re-measured around it (short pairs first),
as Wu & Fomel's Gauss-Newton iterations; each solve is a sparse conjugate-gradient solve of the normal equations.

Faults (:class:`~seismo3d.seismic.horizons.fault_crossings.FaultCrossings`): a pair whose path crosses traced faults is
checked with short windows around the estimate plus the faults' jump against around the estimate; it takes the jump only
where that correlates better, so a fault's jump is taken only where the registration across it supports it, and a
spurious fault surface leaves the pair's long-window shift alone. A fault crossed more than once in the same sense
along a line (its strands: a 2D throw profile is measured across all of them) is one fault zone
(:func:`~seismo3d.seismic.horizons.fault_pairs.fault_steps`): the traces between its outermost strands, a sliver
whose own offsets no throw tells, are left untracked, pairs ending there are left out, and pairs from the zone's
nearest traces on each side span it with the throw once (on ``penobscot_xl1155.sgy`` the horizon had climbed 35 ms
inside the large fault's sliver, where no strand was traced).

The picks of each line are then chosen together by dynamic programming over candidate extrema of the polarity near
the solution, and in a cube the lines of both lateral axes by sweeps of it over inlines and crosslines
(:mod:`~seismo3d.seismic.horizons.dp`), a step across a traced fault expected to jump by the fault's throw as the
pairs' (without it the programme paid the square of the throw at every crossing, and moved a narrow fault block by a
cycle to make its steps smaller: on the generated cube 2 of ``benchmarks/horizons.py`` whether it did hinged on a
1e-6 change of the fault likelihood). A pick's confidence is the median correlation of its waveform
with its neighbours' (``+-ncc_half`` samples); picks below ``min_confidence`` and traces not connected to a seed by
confident pairs stay empty (NaN). A last self-check (:func:`cycle_skips`) re-measures the pairs at the picked horizon
with lags of more than a reflector period and flags the traces where the correlation-predicted horizon (their plain
least-squares solution) lies about a period away; the tracker repairs them (moves them to the predicted cycle,
re-solves, picks again) and keeps the repair when it leaves fewer traces flagged. Regions of flagged traces that the
solve kept a cycle off are then moved by a minimum cut where their pairs correlate clearly better a cycle away
(:mod:`~seismo3d.seismic.horizons.cycle_cut`).

Conventions: index space (axis 0 inline, axis 1 crossline, last axis sample; a 2D section ``(n_traces, n_samples)``);
times in fractional samples.

References
----------
.. [1] X. Wu and S. Fomel, "Least-squares horizons with local slopes and multigrid correlations", Geophysics 83(4),
   IM29-IM40, 2018, doi:10.1190/geo2017-0830.1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components

from ..._progress import progress_steps
from ..reflectors import reflector_picks
from .correlation import pair_lags, neighbour_confidence, window_correlation
from .cycle_cut import cycle_cut
from .dp import dp_picks, line_slopes, reflector_period, settle_lone_departures
from .fault_crossings import FaultCrossings
from .fault_pairs import fault_steps
from .laplacian import coarse_labels, solve_weighted
from .result import snap_seeds

__all__ = ["PairShifts", "LsqHorizon", "trace_pairs", "pair_shifts", "window_correlation", "solve_horizon",
           "cycle_skips", "pair_agreement", "lsq_horizon"]


# --------------------------------------------------------------------------------------------------------------------
# Pairs of traces and their correlation shifts.

@dataclass(frozen=True, eq=False)
class PairShifts:
    """Pairs of traces (flat indices into the lateral grid) and their measured shifts.

    Attributes
    ----------
    a, b : (n_pairs,) intp ndarray
        The two traces of each pair (flat lateral indices).
    distance : (n_pairs,) intp ndarray
        Traces between them along their line.
    shift : (n_pairs,) float64 ndarray
        Measured ``t[b] - t[a]``, samples (NaN where not measured).
    score : (n_pairs,) float64 ndarray
        Normalised cross-correlation at that shift, NaN where not measured.
    """

    a: np.ndarray
    b: np.ndarray
    distance: np.ndarray
    shift: np.ndarray
    score: np.ndarray


def trace_pairs(lateral_shape: tuple, distances) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """All pairs of traces on the same line of a lateral grid at the given distances.

    Parameters
    ----------
    lateral_shape : (n_traces,) or (n_inlines, n_xlines)
        The grid of traces.
    distances : sequence of int
        Distances, traces, along each axis.

    Returns
    -------
    a, b : (n_pairs,) intp ndarray
        Flat indices of the two traces, ``b`` further along the axis than ``a``.
    distance : (n_pairs,) intp ndarray
    axis : (n_pairs,) intp ndarray
        The lateral axis the pair lies along.
    """
    idx = np.arange(int(np.prod(lateral_shape))).reshape(lateral_shape)
    out = [[], [], [], []]
    for axis in range(len(lateral_shape)):
        for d in distances:
            if d >= lateral_shape[axis]:
                continue
            lo = np.take(idx, np.arange(0, lateral_shape[axis] - d), axis=axis).ravel()
            hi = np.take(idx, np.arange(d, lateral_shape[axis]), axis=axis).ravel()
            out[0].append(lo)
            out[1].append(hi)
            out[2].append(np.full(lo.size, d))
            out[3].append(np.full(lo.size, axis))
    if not out[0]:
        z = np.zeros(0, np.intp)
        return z, z, z, z
    return tuple(np.concatenate(v).astype(np.intp) for v in out)


def pair_shifts(traces: np.ndarray, times: np.ndarray, a: np.ndarray, b: np.ndarray, distance: np.ndarray, *,
                half: int, max_lag: int, jumps: np.ndarray | None = None) -> PairShifts:
    """Measure ``t[b] - t[a]`` for pairs of traces by normalised cross-correlation around the current estimate.

    The window of trace ``a`` (``+-half`` samples around ``times[a]``) is correlated with trace ``b`` at lags
    ``-max_lag..max_lag`` around ``times[b]`` (and, where ``jumps`` is non-zero, also around ``times[b] + jumps``:
    the better-scoring centre is kept); the best lag is refined by a parabola.

    Parameters
    ----------
    traces : (n_traces, n_samples) float32 ndarray
        The data's traces (flat lateral index).
    times : (n_traces,) float64 ndarray
        Current horizon estimate, fractional samples (NaN: not measured).
    a, b, distance : (n_pairs,) intp ndarray
        The pairs (:func:`trace_pairs`).
    half : int
        Half-length of the correlation window, samples.
    max_lag : int
        Lags searched each side of the estimate, samples.
    jumps : (n_pairs,) float64 ndarray, optional
        A fault's jump expected between the two traces (0 where none).

    Returns
    -------
    PairShifts
    """
    ta, tb = times[a], times[b]
    lag, score = pair_lags(traces, a, ta, b, tb, int(half), int(max_lag), 0.8)
    shift = tb + lag - ta
    if jumps is not None:
        # pairs across traced faults: long windows straddle the fault where it dips, and its throw varies with
        # depth, so the fault's jump is checked with short windows: around the estimate plus the jump (lags of a
        # quarter) against around the estimate (full lags); only where the jump correlates better is the pair's
        # shift the jump's, else it keeps its long-window shift (a spurious fault's jump does not correlate)
        alt = np.nonzero(np.isfinite(jumps) & (jumps != 0.0))[0]
        if alt.size:
            short = max(4, int(half) // 4)
            _, score1 = pair_lags(traces, a[alt], ta[alt], b[alt], tb[alt], short, int(max_lag), 0.8)
            lag2, score2 = pair_lags(traces, a[alt], ta[alt], b[alt], tb[alt] + jumps[alt], short,
                                      int(max(3, max_lag // 4)), 0.8)
            better = np.nan_to_num(score2, nan=-2.0) > np.nan_to_num(score1, nan=-2.0)
            take = alt[better]
            shift[take] = (tb[alt] + jumps[alt] + lag2 - ta[alt])[better]
            score[take] = score2[better]
    return PairShifts(a, b, distance, shift, score)


# --------------------------------------------------------------------------------------------------------------------
# The least-squares solve.

def solve_horizon(n: int, pairs: PairShifts, seeds: np.ndarray, seed_times: np.ndarray, *, min_correlation: float,
                  previous: np.ndarray | None = None, seed_weight: float = 100.0, damping: float = 1e-3,
                  robust: float | None = 2.0, robust_iterations: int = 5, distance_power: float = 0.0,
                  lateral_shape: tuple | None = None):
    """Least-squares horizon from pair shifts and seed times (Wu & Fomel 2018, eq. 4 with correlations only).

    Minimises ``sum w_ab (t[b] - t[a] - s_ab)^2 + seed_weight^2 sum (t[s] - t_s)^2 + damping^2 sum (t - previous)^2``
    with ``w_ab`` the pair's correlation squared (pairs below ``min_correlation`` left out).

    Parameters
    ----------
    n : int
        Number of traces (unknowns).
    pairs : PairShifts
    seeds : (n_seeds,) intp ndarray
        Flat indices of the seed traces.
    seed_times : (n_seeds,) float64 ndarray
        Their times, samples.
    min_correlation : float
        Pairs correlating less are left out.
    previous : (n,) float64 ndarray, optional
        The previous estimate (the damping's target; default the mean seed time).
    seed_weight, damping : float
        Weights of the seed and damping equations.
    lateral_shape : tuple of int, optional
        The grid of the ``n`` traces (default ``(n,)``): the blocks of neighbouring traces whose common shift the
        solver's coarse level corrects (:func:`coarse_labels`).

    Returns
    -------
    times : (n,) float64 ndarray
        The solution, NaN on traces no confident pair connects to a seed.

    Notes
    -----
    Each weighted solve is conjugate gradients preconditioned on two levels (additive two-level Schwarz: Jacobi plus
    an exact solve on aggregates of neighbouring traces; Saad, *Iterative Methods for Sparse Linear Systems*, 2nd ed.,
    2003, ch. 13-14). Jacobi alone leaves the smooth components, a common shift of many traces that only the seeds
    fix, to hundreds of iterations; the aggregates' system corrects them at once (on 9 x 512 traces: 5-7 times fewer
    iterations).
    """
    ok = np.isfinite(pairs.shift) & (np.nan_to_num(pairs.score, nan=-1.0) >= min_correlation)
    a, b, s = pairs.a[ok], pairs.b[ok], pairs.shift[ok]
    w0 = pairs.score[ok] ** 2 / pairs.distance[ok].astype(np.float64) ** distance_power
    prev = np.full(n, float(np.mean(seed_times))) if previous is None else np.where(np.isfinite(previous), previous,
                                                                                        float(np.mean(seed_times)))
    labels, n_coarse = coarse_labels((n,) if lateral_shape is None else tuple(lateral_shape))
    t = prev
    for _ in range(robust_iterations + 1):
        w = w0 if robust is None else w0 / (1.0 + ((t[b] - t[a] - s) / robust) ** 2)
        t = solve_weighted(n, a, b, s, w, seeds, seed_times, prev, seed_weight, damping, start=t, labels=labels,
                            n_coarse=n_coarse)
    graph = sparse.coo_matrix((np.ones(a.size), (a, b)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    reached = np.isin(label, label[seeds])
    return np.where(reached, t, np.nan)


# --------------------------------------------------------------------------------------------------------------------
# The cycle-skip self-check.

def cycle_skips(pairs: PairShifts, times: np.ndarray, period: float, seeds: np.ndarray, seed_times: np.ndarray, *,
                min_correlation: float = 0.5, lateral_shape: tuple | None = None) -> np.ndarray:
    """Flag the traces of a horizon that sit about a reflector cycle from the correlation-predicted horizon.

    The prediction is the plain least-squares horizon (:func:`solve_horizon` without robust weights, which would
    down-weight exactly the pairs that disagree with the horizon checked) of the pair shifts measured at ``times``
    with lags of more than a period, through the seeds. Inside a run of traces one cycle off, the pairs agree with
    each other; the pairs that span its ends carry it back by the period, so the prediction departs from ``times``
    over the whole run. A trace is flagged where the two differ by more than half a ``period``.

    Parameters
    ----------
    pairs : PairShifts
        Shifts measured at ``times`` (:func:`pair_shifts` with ``max_lag`` above the period).
    times : (n,) float64 ndarray
        The horizon, samples (NaN: empty).
    period : float
        The reflector period near the horizon, samples (:func:`reflector_period`).
    seeds : (n_seeds,) intp ndarray
        Flat indices of the seed traces.
    seed_times : (n_seeds,) float64 ndarray
        Their times.
    min_correlation : float
        Weakest pair counted.
    lateral_shape : tuple of int, optional
        The grid of the traces (:func:`solve_horizon`).

    Returns
    -------
    (n,) float64 ndarray
        The correction (predicted minus current time, samples) of each flagged trace, NaN elsewhere.
    """
    ok = np.isfinite(times[pairs.a]) & np.isfinite(times[pairs.b])
    sub = PairShifts(pairs.a[ok], pairs.b[ok], pairs.distance[ok], pairs.shift[ok], pairs.score[ok])
    predicted = solve_horizon(times.size, sub, seeds, seed_times, min_correlation=min_correlation, previous=times,
                              robust=None, lateral_shape=lateral_shape)
    diff = predicted - times
    return np.where(np.abs(diff) > 0.5 * period, diff, np.nan)


def pair_agreement(pairs: PairShifts, times: np.ndarray, *, min_correlation: float, within: float) -> np.ndarray:
    """Fraction of each trace's confident pairs that agree with the horizon ``times`` within ``within`` samples
    (``|t[b] - t[a] - s_ab|``); 1 where a trace has no confident pair.

    Parameters
    ----------
    pairs : PairShifts
        Shifts measured at ``times``.
    times : (n,) float64 ndarray
    min_correlation : float
        Weakest pair counted.
    within : float
        Samples.

    Returns
    -------
    (n,) float64 ndarray in [0, 1]
    """
    ok = np.isfinite(pairs.shift) & (np.nan_to_num(pairs.score, nan=-1.0) >= min_correlation)
    a, b = pairs.a[ok], pairs.b[ok]
    agree = (np.abs(times[b] - times[a] - pairs.shift[ok]) <= within).astype(np.float64)
    n = times.size
    total = np.bincount(a, minlength=n) + np.bincount(b, minlength=n)
    good = np.bincount(a, agree, minlength=n) + np.bincount(b, agree, minlength=n)
    return np.where(total > 0, good / np.maximum(total, 1), 1.0)


def picks_of(data: np.ndarray, polarity: str) -> tuple[np.ndarray, np.ndarray]:
    """Reflector picks of every trace of ``data`` (lateral axes flattened)."""
    return reflector_picks(data.reshape(-1, data.shape[-1]), polarity=polarity)


@dataclass(frozen=True, eq=False)
class LsqHorizon:
    """What :func:`lsq_horizon` found: snapped ``times`` and ``confidence`` (lateral shape, NaN where empty), the
    unsnapped least-squares solution ``solution``, and ``repaired``, the traces the cycle-skip check moved."""

    times: np.ndarray
    confidence: np.ndarray
    solution: np.ndarray
    repaired: int


def lsq_horizon(data: np.ndarray, seeds: np.ndarray, *, polarity: str, faults: FaultCrossings, options,
                progress: bool = False, picks: tuple | None = None) -> LsqHorizon:
    """Least-squares horizon of ``data`` through ``seeds``, picks chosen by dynamic programming (module docstring).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Finite amplitudes, zero-mean.
    seeds : (n_seeds, ndim) float64 ndarray
        Seed picks in index space (checked by :func:`~seismo3d.seismic.horizons.as_seeds`).
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
    faults : FaultCrossings
        Traced faults (possibly empty).
    options : TrackingOptions
        The 'global' fields, ``seed_snap``, ``snap``, ``ncc_half``, ``min_confidence`` and ``sigma_tensor``.
    progress : bool
        Report progress over the solves (:mod:`seismo3d._progress`).
    picks : (ndarray, ndarray), optional
        ``(times, offsets)``: the reflector picks of ``polarity`` of every trace of ``data`` (lateral axes flattened,
        :func:`picks_of`), when the caller has them already; default: computed here.

    Returns
    -------
    LsqHorizon

    Raises
    ------
    SeedError
        A seed with no extremum of ``polarity`` within ``seed_snap`` samples.
    """
    opt = options
    lat = data.shape[:-1]
    n = int(np.prod(lat))
    traces = np.ascontiguousarray(data.reshape(n, data.shape[-1]), dtype=np.float32)
    picks, offsets = picks_of(data, polarity) if picks is None else picks
    # seeds: flat index and snapped time
    seed_idx = np.array([np.ravel_multi_index(tuple(int(round(v)) for v in s[:-1]), lat) for s in seeds], np.intp)
    seed_t = snap_seeds(data, seeds, polarity=polarity, window=opt.seed_snap, picks=(picks, offsets))
    a, b, dist, axis = trace_pairs(lat, opt.pair_distances)
    # start flat at the seeds' time; the first solves use the short pairs only (coarse to fine)
    t = np.full(n, float(np.mean(seed_t)))
    limits = [2, 8] + [max(opt.pair_distances)] * opt.iterations
    with progress_steps(opt.iterations, "horizon", unit="solve", enabled=progress) as bar:
        for it in range(opt.iterations):
            use = dist <= limits[it]
            sol = _solve_step(traces, t, a[use], b[use], dist[use], axis[use], lat, seed_idx, seed_t, faults, opt,
                              opt.max_lag)
            change = np.nanmax(np.abs(sol - t)) if np.isfinite(sol).any() else 0.0
            t = np.where(np.isfinite(sol), sol, t) if it < 2 else sol
            bar.advance()
            if it >= 2 and change < 0.05:
                break
    solution = t.copy()
    have = t[np.isfinite(t)]
    margin = int(opt.dp_reach + 4 * max(opt.sigma_tensor) + 8)
    rows = (int(max(np.min(have) - margin, 0)), int(min(np.max(have) + margin + 1, data.shape[-1])))
    if rows[1] - rows[0] < 8:
        rows = (0, data.shape[-1])
    slopes = line_slopes(data, opt.sigma_tensor, rows)
    cross = None  # slopes along the inline axis, for the sweeps of the picks over both axes
    if len(lat) == 2 and opt.dp_sweeps:
        cross = line_slopes(data, opt.sigma_tensor, rows, axis=0)
    fixed = np.full(n, np.nan)
    fixed[seed_idx] = seed_t

    def choose(guide):
        # the guide counts where the pairs agree with it (a trace whose pairs the robust solve outvoted, e.g. in a
        # narrow sag the long pairs span, is left to the slopes and waveforms of its line)
        # the picks' steps across the traced faults are expected to jump by their throws, as the pairs'
        steps = None if faults.tree is None else fault_steps(faults, lat, guide, keep=seed_idx)
        pa, pb, pd, _, jumps = (a, b, dist, axis, None) if steps is None else steps.pairs(a, b, dist, axis, lat)
        ps = pair_shifts(traces, guide, pa, pb, pd, half=opt.correlation_half, max_lag=opt.max_lag, jumps=jumps)
        weight = opt.dp_guide * pair_agreement(ps, guide, min_correlation=opt.min_pair_correlation,
                                               within=opt.robust)
        picked = dp_picks(traces, picks, offsets, guide, lat, fixed, slopes, reach=opt.dp_reach, w_guide=weight,
                          w_step=opt.dp_step, w_wave=opt.dp_wave, half=opt.ncc_half, cross_slopes=cross,
                          sweeps=opt.dp_sweeps, jumps=None if steps is None else steps.jumps)
        if len(lat) == 1 or cross is not None:  # the sweeps weigh a departure against the neighbouring inlines
            return picked
        return settle_lone_departures(picked, guide, lat, picks, offsets)

    snapped = choose(t)
    # the self-check: every pair re-measured at the picks with lags of 1.5 reflector periods and solved plainly; a
    # repair (the flagged traces moved by the correction, re-solved, picks chosen again) is kept when fewer traces
    # are flagged
    repaired = 0
    if opt.repair:
        check = _SkipCheck(traces, picks, offsets, lat, a, b, dist, axis, faults, opt, seed_idx, seed_t)
        corr = check(snapped)
        period = check.period
        bad = np.isfinite(corr)
        if bad.any():
            guide = np.where(bad, snapped + np.nan_to_num(corr), np.where(np.isfinite(snapped), snapped, t))
            for _ in range(2):
                guide = _solve_step(traces, guide, a, b, dist, axis, lat, seed_idx, seed_t, faults, opt, opt.max_lag)
            again = choose(guide)
            corr_again = check(again)
            left = int(np.isfinite(corr_again).sum())
            if left < int(bad.sum()):
                repaired = int(bad.sum()) - left
                snapped, solution = again, guide
                corr, period = corr_again, check.period
        # regions a cycle off that the least-squares solve kept (their shifts are measured around its own
        # estimate): moved by a minimum cut where their pairs correlate clearly better a cycle away
        flags = np.isfinite(corr)
        if flags.any():
            cut = cycle_cut(traces, picks, offsets, snapped, lat, a, b, dist, seeds=seed_idx, movable=flags,
                            period=period, half=opt.correlation_half, ncc_half=opt.ncc_half,
                            distance_power=opt.distance_power, min_gain=opt.cut_gain,
                            min_extent=int(dist.max()) if dist.size else 0)
            snapped = cut.times
            repaired += cut.moved
    near = dist == 1
    conf = neighbour_confidence(traces, snapped, a[near], b[near], opt.ncc_half)
    conf[seed_idx] = 1.0
    keep = np.isfinite(snapped) & (np.nan_to_num(conf, nan=-2.0) >= opt.min_confidence)
    keep[seed_idx] = np.isfinite(snapped[seed_idx])
    times = np.where(keep, snapped, np.nan)
    return LsqHorizon(times.reshape(lat), conf.reshape(lat), solution.reshape(lat), repaired)


class _SkipCheck:
    """:func:`cycle_skips` of a horizon (flat (n,) times): every pair re-measured at it with lags of 1.5 reflector
    periods; ``period`` is the reflector period (samples) of the last horizon checked."""

    def __init__(self, traces, picks, offsets, lat, a, b, dist, axis, faults, opt, seeds, seed_times):
        self.period = np.nan
        self.traces, self.picks, self.offsets, self.lat = traces, picks, offsets, lat
        self.seeds, self.seed_times = seeds, seed_times
        self.a, self.b, self.dist, self.axis, self.faults, self.opt = a, b, dist, axis, faults, opt

    def __call__(self, times):
        have = np.nonzero(np.isfinite(times))[0]
        period = self.period = reflector_period(self.picks, self.offsets, have[::7], times[have[::7]])
        if not np.isfinite(period):
            return np.full(times.size, np.nan)
        a, b, dist, _, jumps = _fault_pairs(self.faults, self.lat, times, self.a, self.b, self.dist, self.axis,
                                            self.seeds)
        ps = pair_shifts(self.traces, times, a, b, dist, half=self.opt.correlation_half,
                         max_lag=int(np.ceil(1.5 * period)), jumps=jumps)
        return cycle_skips(ps, times, period, self.seeds, self.seed_times,
                           min_correlation=self.opt.min_pair_correlation, lateral_shape=self.lat)


def _fault_pairs(faults: FaultCrossings, lat, t, a, b, dist, axis, seeds):
    """The pairs ``a, b, dist, axis`` across the traced faults at the estimate ``t`` (:meth:`~seismo3d.seismic.horizons.
    fault_pairs.FaultSteps.pairs`) and
    their jumps; the pairs unchanged and no jumps without faults."""
    if faults.tree is None:
        return a, b, dist, axis, None
    return fault_steps(faults, lat, t, keep=seeds).pairs(a, b, dist, axis, lat)


def _solve_step(traces, t, a, b, dist, axis, lat, seed_idx, seed_t, faults, opt, max_lag):
    a, b, dist, axis, jumps = _fault_pairs(faults, lat, t, a, b, dist, axis, seed_idx)
    ps = pair_shifts(traces, t, a, b, dist, half=opt.correlation_half, max_lag=max_lag, jumps=jumps)
    return solve_horizon(t.size, ps, seed_idx, seed_t, min_correlation=opt.min_pair_correlation, previous=t,
                         robust=opt.robust, robust_iterations=opt.robust_iterations,
                         distance_power=opt.distance_power, lateral_shape=lat)
