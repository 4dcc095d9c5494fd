"""The lateral check and the gap closing of :func:`~seismo3d.seismic.horizons.tracking.track_horizon`'s carried
horizons: :func:`despike` puts back picks that snapped to a neighbouring cycle while the traces beside them agree
(along a carried slice, then along every line of a cube), and :func:`close_gaps` fills the traces the inline order
left empty from their tracked neighbours along both axes. Steps at faults (from the fault input, or where the two
sides disagree) are left alone.
"""

from __future__ import annotations

import numpy as np

from ..reflectors import ReflectorSlice, nearest_pick, reflector_picks
from ..traces import ncc, waveform
from .fault_crossings import FaultCrossings
from .options import TrackingOptions

__all__ = ["despike", "despike_lines", "close_gaps"]


def despike(section: ReflectorSlice, picks: np.ndarray, carried: np.ndarray, confidence: np.ndarray, *,
            min_confidence: float = 0.3, faults: FaultCrossings | None = None, line_point=None, reach: int = 2,
            agree: float = 2.0) -> int:
    """Lateral continuity check of one carried slice: put back picks that snapped to a neighbouring cycle.

    The carry moves every trace on its own, so a pick that snapped to the neighbouring cycle is carried on, trace
    for trace, through all later slices: a streak across the cube while the traces beside it are right. A pick is
    such a spike when the nearest picks on both sides (within ``reach`` traces) agree with each other within
    ``agree`` samples and it lies more than ``agree`` samples from their interpolation. It is re-snapped at that
    interpolation (within ``agree``) when the waveform there correlates with the two sides at least
    ``min_confidence``, else left empty and carried on from the interpolation. A fault between the sides (fault
    input), or a step between them (sides that disagree: a discontinuity), leaves the pick alone.

    Parameters
    ----------
    section : ReflectorSlice
        The slice the picks were carried onto.
    picks : (n_traces,) float64 ndarray
        Snapped picks, fractional samples (NaN where empty); modified in place.
    carried : (n_traces,) float64 ndarray
        Positions tracking carries on from; modified in place.
    confidence : (n_traces,) float64 ndarray
        Confidence of each pick; modified in place.
    min_confidence : float
        Correlation a re-snapped pick needs with both sides.
    faults : FaultCrossings, optional
        Faults of the data (default none).
    line_point : callable, optional
        ``line_point(trace, t)`` -> the position in ``faults``' coordinates (default ``(trace, t)``: a 2D section).
    reach : int
        Traces searched on each side for the nearest picks.
    agree : float
        Samples within which the two sides must agree, and beyond which a pick is a spike.

    Returns
    -------
    int
        The number of picks changed (re-snapped or emptied).
    """
    sl, out, conf = section, picks, confidence
    if faults is None:
        faults = FaultCrossings.empty(2)
    if line_point is None:
        def line_point(x, t):
            return np.array([x, t], np.float64)
    before = out.copy()  # every decision on the slice as carried, so one correction cannot set off the next
    spike, left, right, predicted = (v[0] for v in _spike_candidates(before[None], reach, agree))
    changed = 0
    for x in np.nonzero(spike)[0]:
        a, b, pred = int(left[x]), int(right[x]), float(predicted[x])
        ta, tb = before[a], before[b]
        if faults.jump(line_point(a, ta), line_point(b, tb)) != 0.0:
            continue
        t = sl.snap(x, pred, agree)
        score = np.nan
        if np.isfinite(t):
            wave = sl.window(x, t)
            score = min(ncc(wave, sl.window(a, ta)), ncc(wave, sl.window(b, tb)))
        if np.isfinite(score) and score >= min_confidence:
            out[x], carried[x], conf[x] = t, t, score
        else:
            out[x], carried[x], conf[x] = np.nan, pred, score
        changed += 1
    return changed


def despike_lines(arr, times, conf, polarity, opt: TrackingOptions, crossings: FaultCrossings,
                  picks: tuple | None = None) -> int:
    """:func:`despike` along every line of a horizon (a 2D section's line; a cube's inlines, then its crosslines):
    picks that left both line neighbours for a neighbouring cycle while the neighbours agree are re-snapped between
    them or emptied. ``times`` and ``conf`` (lateral shape) are modified in place; returns the picks changed.
    ``picks``: the cube's reflector picks ``(times, offsets)``, lateral axes flattened, if the caller has them."""
    if arr.ndim == 2:
        return despike(ReflectorSlice(arr, polarity, opt.sigma_tensor, opt.ncc_half), times, times.copy(), conf,
                       min_confidence=opt.min_confidence, faults=crossings, reach=opt.despike_reach,
                       agree=opt.despike_agree)
    # the lines' picks are the cube's (picks are per trace), gathered once instead of re-picked line by line
    picks, offsets = reflector_picks(arr.reshape(-1, arr.shape[-1]), polarity=polarity) if picks is None else picks
    ids = np.arange(times.size).reshape(times.shape)
    changed = 0
    for axis in (0, 1):  # lines along crosslines (one per inline), then along inlines (one per crossline)
        # only the lines with a spike candidate (the test of :func:`despike` before the faults, the snap and the
        # waveforms) are visited: on the others it changes nothing
        spiky = _spike_candidates(times if axis == 0 else times.T, opt.despike_reach,
                                  opt.despike_agree)[0].any(axis=1)
        for k in np.nonzero(spiky)[0]:
            index = (k, slice(None)) if axis == 0 else (slice(None), k)
            line, line_conf = times[index].copy(), conf[index].copy()

            def line_point(x, t, k=k, axis=axis):
                return np.array([k, x, t] if axis == 0 else [x, k, t], np.float64)

            changed += despike(_LinePicks(arr[index], picks, offsets, ids[index], opt.ncc_half), line,
                               line.copy(), line_conf, min_confidence=opt.min_confidence, faults=crossings,
                               line_point=line_point, reach=opt.despike_reach, agree=opt.despike_agree)
            times[index], conf[index] = line, line_conf
    return changed


def _spike_candidates(lines: np.ndarray, reach: int, agree: float) -> tuple:
    """The picks :func:`despike` tests further, for many lines at once ((n_lines, n_traces) float64, NaN where
    empty): a pick whose nearest picks within ``reach`` traces on both sides agree within ``agree`` samples and lies
    more than ``agree`` samples from their interpolation. ``(spike, left, right, predicted)``, each (n_lines,
    n_traces): the test (bool), the two sides' traces (-1 where none) and their interpolation at the pick."""
    have = np.isfinite(lines)
    n = lines.shape[1]
    x = np.arange(n)
    sides = []
    for direction in (-1, 1):
        pos = np.full(lines.shape, -1)
        for d in range(reach, 0, -1):  # the nearest side wins: written last
            u = x + direction * d
            inside = (u >= 0) & (u < n)
            take = have[:, np.clip(u, 0, n - 1)] & inside
            pos = np.where(take, u, pos)
        sides.append(pos)
    a, b = sides
    found = have & (a >= 0) & (b >= 0)
    ta = np.take_along_axis(lines, np.maximum(a, 0), axis=1)
    tb = np.take_along_axis(lines, np.maximum(b, 0), axis=1)
    with np.errstate(invalid="ignore"):
        pred = ta + (tb - ta) * (x - a) / np.where(found, b - a, 1)
        spike = found & (np.abs(ta - tb) <= agree) & (np.abs(lines - pred) > agree)
    return spike, a, b, pred


class _LinePicks:
    """One line of a cube as :func:`despike` reads it (``n_traces``, ``snap``, ``window`` of
    :class:`~seismo3d.seismic.reflectors.ReflectorSlice`), its picks gathered from the cube's (``picks``,
    ``offsets`` of the flattened cube; ``ids`` the line's flat trace indices)."""

    snap = ReflectorSlice.snap
    window = ReflectorSlice.window

    def __init__(self, amp, picks, offsets, ids, window_half: int):
        self.amp, self.n_traces, self.window_half = amp, len(ids), int(window_half)
        counts = np.diff(offsets)[ids]
        self.offsets = np.concatenate([[0], np.cumsum(counts)])
        self.t = picks[np.repeat(offsets[ids] - self.offsets[:-1], counts) + np.arange(self.offsets[-1])]


def close_gaps(data, times: np.ndarray, confidence: np.ndarray, *, polarity: str = "peak",
               faults: FaultCrossings | None = None, options: TrackingOptions | None = None,
               picks: tuple | None = None) -> int:
    """Fill empty traces of a 3D horizon from their tracked neighbours: the gap-closing pass of :func:`track_horizon`.

    A line-by-line carry leaves a trace empty where its own pick was unsure, and the inline order means a gap is
    never revisited from the crosslines. Here every empty trace next to tracked ones (4-neighbourhood, both
    directions) is predicted at its neighbours' times (plus the jump of a fault between them), snapped to the nearest
    same-polarity extremum within ``snap`` samples, and kept only when the neighbours agree (their snaps within one
    sample) and its waveform correlates with theirs at least ``min_confidence``; repeated until nothing changes (at
    most ``gap_passes`` times).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) float32 ndarray
        The cube the horizon was tracked in (finite).
    times : (n_inlines, n_xlines) float64 ndarray
        Horizon times, fractional samples, NaN where empty; filled in place.
    confidence : (n_inlines, n_xlines) float64 ndarray
        Their confidence; filled in place.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The horizon's polarity.
    faults : FaultCrossings, optional
        Faults of ``data`` (default none).
    options : TrackingOptions, optional
        ``snap``, ``min_confidence``, ``ncc_half`` and ``gap_passes`` are used.
    picks : (ndarray, ndarray), optional
        ``(times, offsets)``: the reflector picks of ``polarity`` of every trace of ``data``, lateral axes flattened
        (:func:`~seismo3d.seismic.reflector_picks` of ``data.reshape(-1, n_samples)``), when the caller has them;
        default: each inline's, computed when first needed.

    Returns
    -------
    int
        The number of traces filled.
    """
    opt = options or TrackingOptions()
    arr = data
    fidx = FaultCrossings.empty(3) if faults is None else faults
    n_il, n_xl = arr.shape[:2]
    per_inline: dict[int, tuple] = {}

    def snap(i, j, t):
        if picks is not None:
            return nearest_pick(*picks, i * n_xl + j, t, opt.snap)
        if i not in per_inline:
            per_inline[i] = reflector_picks(arr[i], polarity=polarity)
        return nearest_pick(*per_inline[i], j, t, opt.snap)

    steps = ((1, 0), (-1, 0), (0, 1), (0, -1))
    filled = 0
    for _ in range(opt.gap_passes):
        empty = ~np.isfinite(times)
        if not empty.any():
            break
        have = ~empty
        near = np.zeros_like(empty)
        near[1:] |= have[:-1]
        near[:-1] |= have[1:]
        near[:, 1:] |= have[:, :-1]
        near[:, :-1] |= have[:, 1:]
        added = 0
        for i, j in zip(*np.nonzero(empty & near)):
            cand, score = [], []
            for di, dj in steps:
                a, b = i + di, j + dj
                if not (0 <= a < n_il and 0 <= b < n_xl) or not np.isfinite(times[a, b]):
                    continue
                jump = fidx.jump(np.array([a, b, times[a, b]], np.float64), np.array([i, j, times[a, b]], np.float64))
                if not np.isfinite(jump):
                    continue
                t = snap(i, j, times[a, b] + jump)
                if np.isfinite(t):
                    cand.append(t)
                    score.append(ncc(waveform(arr[i, j], t, opt.ncc_half),
                                     waveform(arr[a, b], times[a, b], opt.ncc_half)))
            if not cand or np.ptp(cand) > 1.0:
                continue
            c = float(np.nanmin(score)) if np.isfinite(score).any() else np.nan
            if c >= opt.min_confidence:
                times[i, j], confidence[i, j] = float(np.median(cand)), c
                added += 1
        filled += added
        if not added:
            break
    return filled
