"""Traced faults between the pairs of traces of the least-squares horizon (:mod:`~seismo3d.seismic.horizons.lsq`): the
jump of a horizon from each trace to the next along a lateral axis, a pair's jump along its path, and fault zones.

A fault crossed more than once in the same sense along a line (its strands, or a strand its traced points cross back
and forth) is one fault zone: its throw, measured across the whole zone (a 2D throw profile reads the sides beyond every
strand, :mod:`~seismo3d.seismic.faults.throw_profile`), is the jump across it once; the traces between its outermost
strands are left untracked, and the pairs from the zone's nearest traces on each side span it.

Conventions: the lateral grid ``(n_traces,)`` or ``(n_inlines, n_xlines)``, traces by flat index; times in fractional
samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .fault_crossings import FaultCrossings

__all__ = ["FaultSteps", "faults_between", "pair_jumps", "fault_steps"]


def faults_between(faults: FaultCrossings, lateral_shape: tuple, times: np.ndarray) -> tuple:
    """Jumps (samples) of traced faults between neighbouring traces along each lateral axis, at the horizon ``times``
    (lateral shape): a list of arrays, one per axis, shaped like ``times`` less one along the axis (0 where no fault;
    NaN where a crossed fault's throw is unknown)."""
    out = []
    ndim = len(lateral_shape)
    for axis in range(ndim):
        n_steps = list(lateral_shape)
        n_steps[axis] -= 1
        jump = np.zeros(n_steps)
        if faults.tree is not None and jump.size:
            here = np.indices(n_steps).reshape(ndim, -1).T  # C order, as jump.flat
            there = here.copy()
            there[:, axis] += 1
            ta, tb = times[tuple(here.T)], times[tuple(there.T)]
            ok = np.nonzero(np.isfinite(ta) & np.isfinite(tb))[0]
            pa = np.column_stack([here[ok], ta[ok]]).astype(np.float64)
            pb = np.column_stack([there[ok], tb[ok]]).astype(np.float64)
            near = np.nonzero(faults.near_segments(pa, pb))[0]  # only steps near a fault can cross one
            jump.flat[ok[near]] = faults.step_jumps(pa[near], pb[near])
        out.append(jump)
    return out


def pair_jumps(steps: list, lateral_shape: tuple, a: np.ndarray, b: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """The sum of the neighbour-step jumps (:func:`faults_between`) along each pair's path."""
    out = np.zeros(a.size)
    for ax, jump in enumerate(steps):
        sel = axis == ax
        if not sel.any() or not np.any(jump != 0.0):
            continue
        cum = np.concatenate([np.zeros_like(np.take(jump, [0], axis=ax)), np.cumsum(np.nan_to_num(jump), axis=ax)],
                             axis=ax)
        flat = cum.ravel()
        out[sel] = flat[b[sel]] - flat[a[sel]]
    return out


@dataclass(frozen=True, eq=False)
class FaultSteps:
    """The traced faults between neighbouring traces at a horizon estimate (:func:`fault_steps`).

    Attributes
    ----------
    jumps : list of ndarray
        One per lateral axis, shaped like the lateral grid less one along the axis: the jump (samples) of the horizon
        from a trace to the next along the axis (:func:`faults_between`), a fault zone's throw once, at its first
        strand; 0 where no fault, NaN where a crossed fault's throw is unknown.
    zone : (n,) bool ndarray
        Traces inside a fault zone, left untracked (flat over the lateral grid).
    spans : (3, n_spans) intp ndarray
        Rows ``a``, ``b``, ``axis``: pairs of traces just outside each zone of a line, across it.
    """

    jumps: list
    zone: np.ndarray
    spans: np.ndarray

    def pairs(self, a: np.ndarray, b: np.ndarray, distance: np.ndarray, axis: np.ndarray, lateral_shape: tuple):
        """The pairs ``a, b, distance, axis`` without those that end inside a zone, with the spans across the zones,
        and their jumps (:func:`pair_jumps`): ``(a, b, distance, axis, jumps)``."""
        keep = ~(self.zone[a] | self.zone[b])
        sa, sb, sx = self.spans
        coords_a = np.unravel_index(sa, lateral_shape)
        coords_b = np.unravel_index(sb, lateral_shape)
        sd = np.asarray([coords_b[x][k] - coords_a[x][k] for k, x in enumerate(sx)], np.intp)
        a, b = np.concatenate([a[keep], sa]), np.concatenate([b[keep], sb])
        distance, axis = np.concatenate([distance[keep], sd]), np.concatenate([axis[keep], sx])
        return a, b, distance, axis, pair_jumps(self.jumps, lateral_shape, a, b, axis)


def fault_steps(faults: FaultCrossings, lateral_shape: tuple, times: np.ndarray, *, keep: np.ndarray,
                reach: int = 3) -> FaultSteps:
    """The jumps of traced faults between neighbouring traces at the horizon ``times``, and their zones.

    A fault crossed more than once along a line, each time in the same sense (its strands, or a strand its traced
    points cross back and forth), is one fault zone: its throw (measured across the whole zone, the sides read
    beyond every strand, :mod:`~seismo3d.seismic.faults.throw_profile`) is the jump across it, once; the traces
    between its outermost strands (a sliver, or the drag between them) are not tracked, and the horizon on either
    side is tied by the pairs that span the zone from its ``reach`` nearest traces on each side.

    Parameters
    ----------
    faults : FaultCrossings
    lateral_shape : (n_traces,) or (n_inlines, n_xlines)
    times : (n,) float64 ndarray
        The horizon estimate, samples (NaN: filled from the nearest estimate for the faults' geometry).
    keep : (k,) intp ndarray
        Traces never in a zone (the seeds): a zone holding one is left as strands.
    reach : int
        Traces on each side of a zone whose pairs span it.

    Returns
    -------
    FaultSteps
    """
    n = int(np.prod(lateral_shape))
    t = np.asarray(times, np.float64).reshape(lateral_shape)
    have = np.isfinite(t)
    if not have.any():
        return FaultSteps(faults_between(FaultCrossings.empty(len(lateral_shape) + 1), lateral_shape, t),
                          np.zeros(n, bool), np.zeros((3, 0), np.intp))
    if not have.all():  # the nearest estimate, for where the faults cross the lines
        _, near = ndimage.distance_transform_edt(~have, return_indices=True)
        t = t[tuple(near)]
    jumps = faults_between(faults, lateral_shape, t)
    zone = np.zeros(lateral_shape, bool)
    protected = np.zeros(n, bool)
    protected[np.asarray(keep, np.intp)] = True
    protected = protected.reshape(lateral_shape)
    spans = []
    for axis, jump in enumerate(jumps):
        steps = np.argwhere(jump != 0.0)  # NaN too: a crossing of unknown throw
        if len(steps) < 2:
            continue
        groups = {}  # (line, fault id) -> [(position along the line, jump)]
        for s in steps:
            here = tuple(int(v) for v in s)
            there = list(here)
            there[axis] += 1
            there = tuple(there)
            crossed = faults.crossings(np.array([*here, t[here]], np.float64), np.array([*there, t[there]], np.float64))
            for fid, value in crossed.items():
                groups.setdefault((here[:axis] + here[axis + 1:], fid), []).append((here[axis], value))
        for (line, _), cross in groups.items():
            pos = np.array([c[0] for c in cross])
            val = np.array([c[1] for c in cross], np.float64)
            if pos.size < 2 or not np.isfinite(val).all() or not (np.all(val > 0) or np.all(val < 0)):
                continue
            first, last = int(pos.min()), int(pos.max())
            at = lambda p: line[:axis] + (p,) + line[axis:]  # noqa: E731 - the grid index of a position on the line
            if protected[at(slice(first + 1, last + 1))].any():
                continue
            for p, v in cross:  # the zone's throw once, at its first strand
                jump[at(p)] -= v
            jump[at(first)] += float(np.mean(val))
            zone[at(slice(first + 1, last + 1))] = True
            flat = np.ravel_multi_index
            size = lateral_shape[axis]
            for i in range(reach):
                for j in range(reach):
                    lo, hi = first - i, last + 1 + j
                    if lo >= 0 and hi < size:
                        spans.append((flat(at(lo), lateral_shape), flat(at(hi), lateral_shape), axis))
    zone = zone.ravel()
    span = np.array(spans, np.intp).T.reshape(3, -1) if spans else np.zeros((3, 0), np.intp)
    if span.size:  # a span's end inside another zone (zones of two axes, or two zones on a line) does not tie it
        span = span[:, ~(zone[span[0]] | zone[span[1]])]
    return FaultSteps(jumps, zone, span)
