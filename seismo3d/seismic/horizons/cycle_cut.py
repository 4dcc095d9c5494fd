"""Cycle-skip repair by a minimum cut: move whole regions of a horizon by one reflector cycle where that makes the
traces' waveforms correlate better with the traces they are paired with.

A horizon tracked from one seed can follow the wrong cycle over a region it reached through one ambiguous step, for
example across a fault whose throw is near half a reflector period: the region is internally continuous, and the
least-squares solve (:mod:`~seismo3d.seismic.horizons.lsq`), whose shifts are measured around its own estimate, keeps
it. What betrays it is its border with the part of the horizon that reached the same traces the right way: there the
horizon steps by a period between traces whose waveforms say there is no step.

The repair asks, for every trace, whether it should stay or move to its neighbouring pick of the same polarity one
cycle down (then, in a second pass, up). The cost of an answer is the sum over the trace pairs of the least-squares
solve (``1, 2, 4, ..., 32`` traces apart) of ``w_ab (1 - ncc_ab)``, ``ncc_ab`` the normalised cross-correlation of
the two traces' windows at their picks and ``w_ab`` one over the pair's distance to ``distance_power`` (the direct
objective that the least-squares shifts approximate, Wu & Fomel 2018, eq. 3). Each pair's cost depends on the two
traces' answers only, so the best set of traces to move is a minimum s-t cut of a graph with one node per trace
(Kolmogorov & Zabih 2004; pairwise terms that are not submodular are truncated), solved with scipy's maximum flow.

Four rules keep the repair from changing which reflector the horizon follows: the seeds never move; only traces the
cycle-skip self-check flags may move (:func:`~seismo3d.seismic.horizons.lsq.cycle_skips`: about a period from the
correlation-predicted horizon); each region the cut moves (its connected moved traces, grouped across single traces
that stay) must reach further than ``min_extent`` traces along a lateral axis, the longest pair distance of the
least-squares solve: pairs span a narrower region, so the solve has weighed it already (a small sag or a patch of
chaotic data), while a wider region is held only by the pairs across its border; and it must remove at least
``min_gain`` of its traces' decorrelation with their neighbours (``1 - confidence``, the pick confidence of
:func:`~seismo3d.seismic.horizons.lsq.neighbour_confidence`): a region that is continuous either way, or that lies in
chaotic data, stays. A pass is kept only when the total cost falls.

Conventions: flat trace indices over the lateral grid, times in fractional samples, NaN where a trace is empty.

References
----------
.. [1] X. Wu and S. Fomel, "Least-squares horizons with local slopes and multigrid correlations", Geophysics 83(4),
   IM29-IM40, 2018, doi:10.1190/geo2017-0830.1.
.. [2] V. Kolmogorov and R. Zabih, "What energy functions can be minimized via graph cuts?", IEEE Trans. Pattern
   Analysis and Machine Intelligence 26(2), 147-159, 2004.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse.csgraph import breadth_first_order, maximum_flow

from .correlation import neighbour_confidence, window_correlation
from .dp import trace_search

__all__ = ["CycleCut", "neighbour_cycle", "binary_min_cut", "cycle_cut"]


@dataclass(frozen=True, eq=False)
class CycleCut:
    """What :func:`cycle_cut` did: the repaired ``times`` ((n,) float64, samples), the number of traces ``moved``, and
    the pair cost before and after (``cost_before``, ``cost_after``)."""

    times: np.ndarray
    moved: int
    cost_before: float
    cost_after: float


def neighbour_cycle(picks: np.ndarray, offsets: np.ndarray, times: np.ndarray, direction: int,
                    min_gap: float) -> np.ndarray:
    """Each trace's pick of the next cycle down (``direction`` +1) or up (-1) from its time.

    Parameters
    ----------
    picks, offsets : ndarray
        Every trace's sorted picks of one polarity (:func:`~seismo3d.seismic.reflector_picks`: trace ``j``'s picks
        are ``picks[offsets[j]:offsets[j + 1]]``), samples.
    times : (n,) float64 ndarray
        The horizon, samples (NaN: empty).
    direction : {1, -1}
        Down (later times) or up.
    min_gap : float
        Samples: the next cycle's pick lies at least this far from the time (about half a reflector period, so a
        small side lobe is not taken for a cycle).

    Returns
    -------
    (n,) float64 ndarray
        Samples; NaN where the trace is empty or has no such pick.
    """
    times = np.asarray(times, np.float64)
    out = np.full(times.size, np.nan)
    j = np.nonzero(np.isfinite(times))[0]
    if direction > 0:  # the first pick at or below the time + min_gap
        k = trace_search(picks, offsets, j, times[j] + min_gap, "left")
        ok = k < offsets[j + 1]
        out[j[ok]] = picks[k[ok]]
    else:  # the last pick at or above the time - min_gap
        k = trace_search(picks, offsets, j, times[j] - min_gap, "right")
        ok = k > offsets[j]
        out[j[ok]] = picks[k[ok] - 1]
    return out


def binary_min_cut(n: int, a: np.ndarray, b: np.ndarray, e00: np.ndarray, e01: np.ndarray, e10: np.ndarray,
                   e11: np.ndarray, fixed: np.ndarray, *, resolution: float = 1e-3) -> np.ndarray:
    """Labels ``x`` in {0, 1} of ``n`` nodes minimising ``sum_p E_p(x[a_p], x[b_p])`` with ``x[fixed] = 0``.

    ``E_p(0, 0) = e00[p]``, ``E_p(0, 1) = e01[p]`` (``x[a] = 0``, ``x[b] = 1``) and so on. Each term is written as
    unary terms plus ``lambda (1 - x_a) x_b`` with ``lambda = e01 + e10 - e00 - e11``, which a graph represents when
    it is not negative (the term is submodular); a negative ``lambda`` is truncated to 0 (Kolmogorov & Zabih 2004).
    The minimum s-t cut (:func:`scipy.sparse.csgraph.maximum_flow`, Dinic's algorithm, on capacities rounded to
    ``resolution``) gives the labels: nodes left on the source side keep label 0.

    Parameters
    ----------
    n : int
        Number of nodes.
    a, b : (n_pairs,) intp ndarray
        The nodes of each pairwise term.
    e00, e01, e10, e11 : (n_pairs,) float64 ndarray
        The term's value for each pair of labels (cost units; finite).
    fixed : (k,) intp ndarray
        Nodes that keep label 0.
    resolution : float
        Cost units per integer capacity step (coarser when the costs would overflow 32-bit capacities).

    Returns
    -------
    (n,) bool ndarray
        True where the label is 1.
    """
    lam = np.maximum(e01 + e10 - e00 - e11, 0.0)
    coef_a = e10 - e00  # E = e00 + coef_a x_a + coef_b x_b + lam (1 - x_a) x_b
    coef_b = e11 - e10
    cost1 = np.zeros(n)  # paid when the label is 1 (source -> node)
    cost0 = np.zeros(n)  # paid when the label is 0 (node -> sink)
    np.add.at(cost1, a, np.maximum(coef_a, 0.0))
    np.add.at(cost0, a, np.maximum(-coef_a, 0.0))
    np.add.at(cost1, b, np.maximum(coef_b, 0.0))
    np.add.at(cost0, b, np.maximum(-coef_b, 0.0))
    unary = np.minimum(cost1, cost0)  # a node's two unary costs: only their difference matters
    cost1 -= unary
    cost0 -= unary
    forced = np.zeros(n, bool)
    forced[np.asarray(fixed, np.intp)] = True
    src, snk = n, n + 1
    rows = np.concatenate([np.full(n, src), np.arange(n), a])
    cols = np.concatenate([np.arange(n), np.full(n, snk), b])
    cap = np.concatenate([cost1, cost0, lam])
    # integer capacities: steps of ``resolution``, coarser where the costs would not fit in int32 with the
    # forced nodes' capacity (more than every other capacity together) on top
    step = max(resolution, 2.0 * float(cap.sum()) / 2.0 ** 30)
    cap = np.rint(cap / step)
    cap[:n][forced] = float(cap.sum()) + 1.0
    keep = cap > 0
    graph = sparse.csr_matrix((cap[keep].astype(np.int32), (rows[keep], cols[keep])), shape=(n + 2, n + 2))
    graph.sum_duplicates()
    flow = maximum_flow(graph, src, snk, method="dinic").flow
    residual = (graph - flow).tocsr()  # the flow matrix is antisymmetric: reverse edges get the flow back
    residual.data = (residual.data > 0).astype(np.int8)
    residual.eliminate_zeros()
    reached = breadth_first_order(residual, src, directed=True, return_predecessors=False)
    label = np.ones(n + 2, bool)
    label[reached] = False
    return label[:n]


def _pair_ncc(traces, a, ta, b, tb, half):
    return np.nan_to_num(window_correlation(traces, a, ta, b, tb, half=half), nan=0.0)


def _clear_regions(flip, lateral_shape, before, after, *, min_extent, min_gain):
    """The moved traces whose region (connected, grouped across single traces that stay: a noisy pick does not split
    a region) reaches further than ``min_extent`` traces along a lateral axis and whose mean confidence rises from
    ``before`` to ``after`` by at least ``min_gain`` of its decorrelation (flat (n,) bool)."""
    grid = flip.reshape(lateral_shape)
    joined, _ = ndimage.label(ndimage.binary_dilation(grid, np.ones((3,) * grid.ndim, bool)))
    region = np.where(grid, joined, 0)
    keep = np.zeros(flip.size, bool)
    flat = region.ravel()
    for r, box in enumerate(ndimage.find_objects(region), start=1):
        if box is None or max(sl.stop - sl.start for sl in box) <= min_extent:
            continue
        sel = flat == r
        g0, g1 = np.nanmean(before[sel]), np.nanmean(after[sel])
        if g1 - g0 >= min_gain * (1.0 - g0):
            keep |= sel
    return keep


def cycle_cut(traces: np.ndarray, picks: np.ndarray, offsets: np.ndarray, times: np.ndarray, lateral_shape: tuple,
              a: np.ndarray, b: np.ndarray, distance: np.ndarray, *, seeds: np.ndarray, movable: np.ndarray,
              period: float, half: int, ncc_half: int, distance_power: float, min_gain: float,
              min_extent: int = 0, rounds: int = 3) -> CycleCut:
    """Move regions of a horizon by one reflector cycle where the pairs' waveforms correlate better (module
    docstring).

    Parameters
    ----------
    traces : (n, n_samples) float32 ndarray
        The data's traces (flat lateral index).
    picks, offsets : ndarray
        Every trace's picks of the horizon's polarity (:func:`~seismo3d.seismic.reflector_picks`).
    times : (n,) float64 ndarray
        The horizon, samples (NaN: empty); picks of ``picks``.
    lateral_shape : (n_traces,) or (n_inlines, n_xlines)
    a, b, distance : (n_pairs,) intp ndarray
        The trace pairs (:func:`~seismo3d.seismic.horizons.lsq.trace_pairs`).
    seeds : (n_seeds,) intp ndarray
        Traces that never move.
    movable : (n,) bool ndarray
        Traces that may move (the self-check's flags).
    period : float
        Reflector period near the horizon, samples: a cycle's pick lies at least half of it away.
    half : int
        Half-length, samples, of the pairs' correlation windows.
    ncc_half : int
        Half-length, samples, of the confidence windows (neighbouring traces).
    distance_power : float
        A pair weighs one over its distance (traces) to this power.
    min_gain : float
        Fraction of a moved region's mean decorrelation with its neighbours (1 - confidence) the move must remove.
    min_extent : int
        Traces: a moved region reaches further than this along one lateral axis (the longest pair distance: pairs
        span a narrower region, and the least-squares solve has weighed it already).
    rounds : int
        Largest number of passes (each: down, then up).

    Returns
    -------
    CycleCut
    """
    t = np.asarray(times, np.float64).copy()
    n = t.size
    # only pairs of two picked traces count (a move keeps a trace picked); each pair's current cost is kept, and a
    # pass re-measures only the pairs that touch a trace free to move
    live = np.isfinite(t[a]) & np.isfinite(t[b])
    a, b = a[live], b[live]
    weight = 1.0 / distance[live].astype(np.float64) ** distance_power
    near = distance[live] == 1
    pair_cost = weight * (1.0 - _pair_ncc(traces, a, t[a], b, t[b], half))
    before = cost = float(pair_cost.sum())
    can_move = np.asarray(movable, bool) & np.isfinite(t)
    can_move[np.asarray(seeds, np.intp)] = False
    moved = np.zeros(n, bool)
    if not (np.isfinite(period) and can_move.any()):
        return CycleCut(t, 0, before, before)
    for _ in range(rounds):
        changed = False
        for direction in (1, -1):
            alt = neighbour_cycle(picks, offsets, t, direction, 0.5 * period)
            free = can_move & np.isfinite(alt)
            touch = free[a] | free[b]
            if not touch.any():
                continue
            pa, pb, w = a[touch], b[touch], weight[touch]
            ta, tb = t[pa], t[pb]
            xa = np.where(free[pa], alt[pa], ta)
            xb = np.where(free[pb], alt[pb], tb)
            terms = [pair_cost[touch]] + [w * (1.0 - _pair_ncc(traces, pa, u, pb, v, half))
                                          for u, v in ((ta, xb), (xa, tb), (xa, xb))]
            flip = binary_min_cut(n, pa, pb, *terms, np.nonzero(~free)[0])
            if not flip.any():
                continue
            # each moved region must reach beyond the longest pair and correlate clearly better with its neighbours
            cand = np.where(flip, alt, t)
            mine = near & (flip[a] | flip[b])  # every neighbour pair of a moved trace
            flip &= _clear_regions(flip, lateral_shape,
                                   neighbour_confidence(traces, t, a[mine], b[mine], ncc_half),
                                   neighbour_confidence(traces, cand, a[mine], b[mine], ncc_half),
                                   min_extent=min_extent, min_gain=min_gain)
            if not flip.any():
                continue
            cand = np.where(flip, alt, t)
            hit = flip[a] | flip[b]
            new_cost = weight[hit] * (1.0 - _pair_ncc(traces, a[hit], cand[a[hit]], b[hit], cand[b[hit]], half))
            delta = float(new_cost.sum() - pair_cost[hit].sum())
            if delta < 0.0:
                t, changed = cand, True
                pair_cost[hit] = new_cost
                cost += delta
                moved |= flip
        if not changed:
            break
    return CycleCut(t, int(moved.sum()), before, cost)
