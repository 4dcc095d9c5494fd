"""Horizon tracking: :func:`track_horizon`, by default global (least-squares horizons,
:mod:`~seismo3d.seismic.horizons.lsq`), or (``method='registration'``) by registering neighbouring slices ("seismic
tracks", method.md section 6), described here.

A horizon is followed from seed picks in two moves, both made with the registration engine:

1. **Along a slice** (a 2D section, or the seed's inline of a cube): a window of traces around the current pick
   (the *source panel*) is registered onto the window a few traces further on (the *target panel*) by point-to-plane
   ICP (:func:`seismo3d.registration.icp`) on the *reflector points*: the same-polarity extrema of every trace in a
   band around the horizon, with normals from the structure tensor. The pick is carried by the transform, followed
   along the reflector slope to the next trace and snapped to the nearest extremum of the same polarity. Because the
   panel holds several reflectors over a dozen traces, one weak or split reflector cannot pull the pick onto its
   neighbour, which is exactly the jump a plain amplitude autotracker (:func:`~seismo3d.seismic.autotrack`) makes.
2. **From slice to slice** (inline k to inline k + 1 of a cube): the two sections are registered panel by panel
   with the fused ICP (:func:`seismo3d.registration.fused_icp`, eq. 16): reflector points plus HOG-pyramid matches
   between the two section images (:func:`seismo3d.features.match_images`), per-axis scale allowed. Every pick of
   slice k is carried onto slice k + 1 and snapped. Each trace is carried on its own, so a pick that snapped to
   the neighbouring cycle would be carried, trace for trace, through every later slice; a lateral continuity check
   puts back a pick whose neighbours on both sides agree with each other but not with it (a *spike*), and leaves
   steps (faults) alone.
3. **Closing gaps** (cubes): the inline order never revisits a trace it left empty, so a last pass predicts each
   empty trace from its tracked neighbours along both the inline and the crossline (plus a fault's jump between
   them), snaps, and keeps the pick when the neighbours agree within a sample and its waveform correlates with
   theirs at least ``min_confidence``; repeated until nothing changes.

Across a fault (from :func:`seismo3d.seismic.trace_faults`), the step is made from one side only: the pick jumps by
the fault's throw (down when it enters the hanging wall, up when it enters the footwall), and the panels on the two
sides are registered starting from that jump (a refinement within the snap window; a registration that slides
further, onto another cycle, is not taken). A step crosses a fault when it pierces the fault's local plane (the
least-squares plane of its traced points near the step, oriented as the throw was measured) within a voxel and a
half of one of those points; two faults between the same traces add their jumps; and a fault is crossed once going
one way (after the jump, a dipping fault's plane can lie beyond the new pick). A seed picked on a traced fault is in
neither wall as far as the fault can tell: each first step away from it along its slice stays in the seed's wall or
jumps out of the other one, whichever the seed's waveform correlates with better. Along a slice, the panels around a
pick are kept within its fault block (the traces a horizon through it reaches without crossing a fault: reflector
points past a fault belong to another block), and no step ends within two traces of a fault, where drag bends the
reflectors towards it (on Penobscot horizon 6 the tracker had climbed 5 samples there before the jump): the step is
carried on over that zone to the next trace of its grid. Only faults with a reliable throw are used: a fault whose
two sides do not correlate better at its throw than without it (medians of its throw correlations), or which has no
throw, is left out, as if not traced. Without fault input, a step whose panels do not fit (a discontinuity) is
re-made from one side with the shift found by normalised cross-correlation of the two sides' stacked traces, the
start the throw estimation uses (:mod:`seismo3d.seismic.faults.throw`). The fault geometry (piercing, walls, blocks) is
:class:`~seismo3d.seismic.horizons.fault_crossings.FaultCrossings`.

Each pick gets a confidence: the normalised cross-correlation of the waveform around it with the waveform around the
pick it came from. Picks below ``min_confidence``, and picks with no extremum of the right polarity within the snap
window, are left empty (NaN); tracking goes on from their predicted position. :func:`~seismo3d.seismic.fill_horizon`
interpolates the gaps as a separate, explicit step. The tuning values are the fields of :class:`TrackingOptions`.

Conventions: index space as in :mod:`seismo3d.seismic.faults.likelihood.scan` (axis 0 inline, axis 1 crossline, last
axis sample, downward; a 2D section is ``(n_traces, n_samples)``). Horizon times are fractional sample indices; convert
with the cube's ``samples`` axis (ms or m).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..._options import resolve_options
from ..._progress import progress_steps
from ..._validation import as_seismic, check_choice
from ...errors import DegenerateGeometryWarning, InputError, RegistrationError
from ...registration import ICPOptions, fused_icp, icp
from ..reflectors import POLARITIES, ReflectorSlice, nearest_reflector
from ..traces import ncc, ncc_lag_search
from .fault_crossings import FaultCrossings
from .labelled import HorizonLabels
from .lateral_check import close_gaps, despike, despike_lines
from .lsq import lsq_horizon, picks_of
from .options import TrackingOptions
from .result import Horizon, as_seeds, check_live_seed, no_pick_error

__all__ = ["TrackingOptions", "track_horizon"]


# --------------------------------------------------------------------------------------------------------------------
# Registration of two panels (point-to-plane ICP or fused ICP) and the one-sided shift search.

def _register(src_pts, dst_pts, dst_nrm, init, opt: TrackingOptions, features=None):
    """Panel registration; returns (transform, fitness) or (None, 0) when it cannot run."""
    icp_options = ICPOptions(max_distance=(3.0, 1.5), degeneracy_threshold=0.0, max_iterations=opt.panel_iterations)

    if len(src_pts) < 6 or len(dst_pts) < 6:
        return None, 0.0
    with warnings.catch_warnings():
        # Reflectors are near-parallel lines: sliding along them is unconstrained by design (the pick is followed
        # along the reflector afterwards), so the degeneracy warning carries no news here.
        warnings.simplefilter("ignore", DegenerateGeometryWarning)
        try:
            if features is not None and len(features[0]) >= 8:
                res = fused_icp(src_pts, dst_pts, target_normals=dst_nrm, source_features=features[0],
                                target_features=features[1], model=opt.model, init=init, ransac_threshold=1.5,
                                options=icp_options)
            else:
                res = icp(src_pts, dst_pts, target_normals=dst_nrm, method="point_to_plane", model=opt.model,
                          init=init, options=icp_options)
        except (RegistrationError, InputError):
            return None, 0.0
    return res.transform, float(res.fitness)


def _stack(sl: ReflectorSlice, traces: np.ndarray, ref: np.ndarray, half: int) -> np.ndarray:
    """Mean of the traces' amplitudes read along ``ref`` (samples), over ``-half..half`` samples."""
    rows = np.array([sl.window(j, r, half) for j, r in zip(traces, ref)]).reshape(len(traces), 2 * half + 1)
    ok = np.isfinite(rows)
    count = ok.sum(axis=0)
    total = np.where(ok, rows, 0.0).sum(axis=0)
    return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def _sides(n: int, c: int, j: int, direction: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Up to ``width`` traces behind trace ``c`` (from c back) and ahead from trace ``j`` on, within 0..n-1."""
    behind = np.arange(c, c - direction * width, -direction)
    ahead = np.arange(j, j + direction * width, direction)
    return behind[(behind >= 0) & (behind < n)], ahead[(ahead >= 0) & (ahead < n)]


def _wall_score(sl: ReflectorSlice, j0: int, t0: float, j: int, pred: float, pc: float, direction: int, width: int,
                shift: float) -> float:
    """Normalised cross-correlation of the waveform at the seed (j0, t0) with the stack of the ``width`` traces from
    ``j`` on (away from the seed), read along the slope ``pc`` from ``pred + shift``."""
    _, ahead = _sides(sl.n_traces, j0, j, direction, width)
    return ncc(sl.window(j0, t0), _stack(sl, ahead, pred + pc * (ahead - j) + shift, sl.window_half))


def _side_shift(sl: ReflectorSlice, c: int, tc: float, pc: float, j: int, direction: int, width: int, half: int,
                max_shift: int) -> float:
    """Shift (samples) of the horizon from the traces behind ``c`` to the traces from ``j`` on, by normalised
    cross-correlation of the two sides' stacked traces (flattened along the slope ``pc``); 0 when a side has fewer
    than two traces or nothing correlates."""
    behind, ahead = _sides(sl.n_traces, c, j, direction, width)
    if behind.size < 2 or ahead.size < 2:
        return 0.0
    f = _stack(sl, behind, tc + pc * (behind - c), half + max_shift)
    g = _stack(sl, ahead, tc + pc * (ahead - c), half + max_shift)
    return ncc_lag_search(f[max_shift:max_shift + 2 * half + 1], g, max_shift)




# --------------------------------------------------------------------------------------------------------------------
# Tracking along one slice.

def _panel_step(sl: ReflectorSlice, src_span: tuple[int, int], dst_span: tuple[int, int], c: int, tc: float, j: int,
                t_j: float, pc: float, opt: TrackingOptions) -> tuple[float, float]:
    """Register the panel of traces ``src_span`` (inclusive) around the pick (c, tc) onto the panel ``dst_span``
    around the predicted position (j, t_j), bands of reflector points along the slope ``pc``; returns the pick
    carried to trace ``j`` (followed along the reflector slope) and the fitness, or (NaN, 0) when it cannot run."""
    hv = opt.half_samples
    xs = np.arange(src_span[0], src_span[1] + 1)
    xd = np.arange(dst_span[0], dst_span[1] + 1)
    src, _ = sl.band(src_span[0], src_span[1], tc + pc * (xs - c), hv)
    dst, dnrm = sl.band(dst_span[0], dst_span[1], t_j + pc * (xd - j), hv)
    init = np.eye(3)
    init[:2, 2] = (j - c, t_j - tc)
    m, fit = _register(src, dst, dnrm, init, opt)
    if m is None:
        return np.nan, 0.0
    q = m @ np.array([c, tc, 1.0])
    return q[1] + sl.slope_at(j, q[1]) * (j - q[0]), fit


@dataclass(frozen=True, eq=False)
class _LineTrack:
    """A horizon along one slice: times and confidence (n_traces,), NaN where empty / unreached."""

    times: np.ndarray
    confidence: np.ndarray


def _track_along(sl: ReflectorSlice, j0: int, t0: float, opt: TrackingOptions, faults: FaultCrossings,
                 line_point) -> _LineTrack:
    """Track from (j0, t0) to both ends of a slice. ``line_point(j, t)`` maps a slice position to the fault
    crossings' coordinates."""
    n = sl.n_traces
    times = np.full(n, np.nan)
    conf = np.full(n, np.nan)
    times[j0], conf[j0] = t0, 1.0
    hw, hv = opt.half_traces, opt.half_samples
    # A seed picked on a traced fault is in neither wall as far as the fault surface can tell: the first step away
    # from it decides by correlation, and those faults are not crossed again.
    on_seed = faults.on_fault(line_point(j0, t0))
    for direction in (1, -1):
        c, tc = j0, t0  # tc: carried position (kept even where the output is left empty)
        reference = sl.window(j0, t0)  # running waveform of the accepted picks, for the confidence
        crossed: set = set(on_seed)  # the faults this direction has crossed (see FaultCrossings.jump)
        while 0 <= c + direction < n:
            j = int(np.clip(c + direction * opt.step, 0, n - 1))
            pc = sl.slope_at(c, tc)
            span = (max(min(c, j) - hw, 0), min(max(c, j) + hw, n - 1))
            block = faults.block(line_point, n, c, tc, pc, *span)
            edge = block[0] if direction < 0 else block[1]
            if edge != (span[0] if direction < 0 else span[1]):
                # A fault between trace `edge` and the next. A step ending within fault_zone traces of it, where drag
                # bends the reflectors towards the fault, is carried on over the zone, to the next trace of the step
                # grid (seed + multiples of `step`), so that a fault does not move where later steps fall.
                at = edge + 0.5 * direction
                while abs(j - at) < opt.fault_zone and 0 <= j + direction * opt.step < n:
                    j += direction * opt.step
            pred = tc + pc * (j - c)
            jump = faults.jump(line_point(c, tc), line_point(j, pred), crossed)
            if on_seed and c == j0:
                # off a fault the seed lies on: into the seed's wall (no jump) or out of the other one (the throw),
                # whichever the seed's waveform correlates with better. (Stacks on both sides, as _side_shift uses,
                # would straddle the very fault the seed is on.)
                other = faults.wall_jump(line_point(c, tc), line_point(j, pred), on_seed)
                if not np.isfinite(other):
                    jump = np.nan  # a throw is unknown: the shift is searched (below), as without fault input
                elif other != 0.0 and np.isfinite(jump):
                    stay, leave = (_wall_score(sl, j0, t0, j, pred, pc, direction, max(hw // 2, 2), jump + s)
                                   for s in (0.0, other))
                    if leave > stay or (np.isnan(stay) and np.isfinite(leave)):
                        jump += other
            t_new = np.nan
            if jump == 0.0:
                # both panels within the pick's fault block: reflector points past a fault belong to another block
                lo, hi = block if block[0] <= j <= block[1] else (0, n - 1)
                t_new, fit = _panel_step(sl, (max(c - hw, lo), min(c + hw, hi)), (max(j - hw, lo), min(j + hw, hi)),
                                         c, tc, j, pred, pc, opt)
                if not (np.isfinite(t_new) and fit >= opt.min_fitness):
                    t_new = pred  # panels that do not fit (noise, chaotic zone): follow the slope, do not search
            if not np.isfinite(t_new):
                # A fault: register from each side only, starting from its throw (or, when the fault's throw is
                # unknown, from the side-to-side correlation shift).
                if np.isfinite(jump) and jump != 0.0:
                    shift = jump
                else:
                    shift = _side_shift(sl, c, tc, pc, j, direction, 2 * hw, int(hv), opt.max_throw)
                behind = tuple(sorted((c, int(np.clip(c - direction * 2 * hw, 0, n - 1)))))
                ahead = tuple(sorted((j, int(np.clip(j + direction * 2 * hw, 0, n - 1)))))
                t_new = pred + shift
                refined, _ = _panel_step(sl, behind, ahead, c, tc, j, t_new, pc, opt)
                if abs(refined - t_new) <= opt.snap:  # a refinement, not a slide onto the next cycle (NaN: none)
                    t_new = refined
            # Snap the new pick and the traces in between; score each against the trace it came from.
            t_j = sl.snap(j, t_new, opt.snap)
            carried = t_j if np.isfinite(t_j) else t_new
            span = abs(j - c)
            for u in range(1, span + 1):
                jj = c + direction * u
                guess = tc + (carried - tc) * u / span
                tt = sl.snap(jj, guess, opt.snap) if u < span else t_j
                anchor = tt if np.isfinite(tt) else guess
                wave = sl.window(jj, anchor)
                score = ncc(reference, wave)
                conf[jj] = score
                if np.isfinite(tt) and np.isfinite(score) and score >= opt.min_confidence:
                    times[jj] = tt
                    if np.isfinite(wave).all():
                        reference = (1 - opt.reference_weight) * reference + opt.reference_weight * wave
            c, tc = j, carried
            if not (0 <= tc < sl.n_samples):
                break
    return _LineTrack(times, conf)




# --------------------------------------------------------------------------------------------------------------------
# Carrying picks from one slice to the next.

def _slice_matches(a: ReflectorSlice, b: ReflectorSlice, rows: tuple[int, int], method):
    """Feature matches between two slices' images (traces along x, samples along y), restricted to a band of rows;
    returned as ((K, 2), (K, 2)) (trace, sample) arrays, or None."""
    if method is None:
        return None
    from ...features import lift_matches_section, match_images

    r0, r1 = rows
    ia = a.amp[:, r0:r1].T
    ib = b.amp[:, r0:r1].T
    lo, hi = np.percentile(np.concatenate([ia.ravel(), ib.ravel()]), [1, 99])
    scale = 255.0 / max(hi - lo, 1e-12)
    to8 = [np.clip((im - lo) * scale, 0, 255).astype(np.uint8) for im in (ia, ib)]
    try:
        res = match_images(to8[0], to8[1], method=method, verify="similarity", threshold=2.0)
    except (InputError, RegistrationError):
        return None
    if res.inliers is None or not np.any(res.inliers):
        return None
    keep = res.inliers
    return (lift_matches_section(res.xy1[keep], first_sample=r0), lift_matches_section(res.xy2[keep], first_sample=r0))


@dataclass(frozen=True, eq=False)
class _Carried:
    """One slice's picks after a carry (n_traces,) each: the snapped confident picks (NaN elsewhere), the positions
    to carry on from, and the confidence."""

    picks: np.ndarray
    carried: np.ndarray
    confidence: np.ndarray


def _carry(src: ReflectorSlice, dst: ReflectorSlice, times: np.ndarray, opt: TrackingOptions,
           faults: FaultCrossings, point_pair, matches, panel: int, crossed: list) -> _Carried:
    """Carry the carried positions ``times`` (n_traces,) of ``src`` onto ``dst``. ``crossed[x]`` is the set of faults
    trace ``x`` has already crossed in this pass (updated; see :meth:`FaultCrossings.jump`)."""
    n = src.n_traces
    out = np.full(n, np.nan)
    carried = np.full(n, np.nan)
    conf = np.full(n, np.nan)
    have = np.isfinite(times)
    if not have.any():
        return _Carried(out, carried, conf)
    x_all = np.arange(n)
    ref = np.interp(x_all, x_all[have], times[have])
    hv = opt.half_samples
    half = panel // 2
    for c0 in range(0, n, half):
        core = np.arange(c0, min(c0 + half, n))
        core = core[have[core]]
        if core.size == 0:
            continue
        lo, hi = max(c0 - half // 2, 0), min(c0 + half + half // 2, n) - 1
        src_pts, _ = src.band(lo, hi, ref[lo:hi + 1], hv)
        dst_pts, dst_nrm = dst.band(lo, hi, ref[lo:hi + 1], hv)
        feats = None
        if matches is not None:
            f0, f1 = matches
            sel = ((f0[:, 0] >= lo) & (f0[:, 0] <= hi) & (np.abs(f0[:, 1] - np.interp(f0[:, 0], x_all, ref)) <= hv))
            feats = (f0[sel], f1[sel])
        m, fit = _register(src_pts, dst_pts, dst_nrm, np.eye(3), opt, feats)
        if m is None or fit < opt.min_fitness:
            m = np.eye(3)
        for x in core:
            t = times[x]
            q = m @ np.array([x, t, 1.0])
            guess = q[1] + dst.slope_at(x, q[1]) * (x - q[0])
            a, b = point_pair(x, t, guess)
            jump = faults.jump(a, b, crossed[x])
            if np.isfinite(jump):
                guess += jump
            tt = dst.snap(x, guess, opt.snap)
            anchor = tt if np.isfinite(tt) else guess
            score = ncc(src.window(x, t), dst.window(x, anchor))
            conf[x] = score
            carried[x] = anchor
            if np.isfinite(tt) and np.isfinite(score) and score >= opt.min_confidence:
                out[x] = tt
    despike(dst, out, carried, conf, min_confidence=opt.min_confidence, faults=faults,
            line_point=lambda x, t: point_pair(x, t, t)[1], reach=opt.despike_reach, agree=opt.despike_agree)
    return _Carried(out, carried, conf)


# --------------------------------------------------------------------------------------------------------------------
# The public functions.

def track_horizon(data, seeds, *, polarity: str = "peak", faults=None, options: TrackingOptions | None = None,
                  progress: bool = False, **overrides) -> Horizon:
    """Track a horizon from seed picks: by default globally (least-squares horizons, then dynamic programming over
    candidate picks: :mod:`~seismo3d.seismic.horizons.lsq`), or by registering neighbouring slices
    (``method='registration'``, module docstring).

    With ``method='global'`` every trace's time comes from one robust least-squares solve of correlation shifts
    between near and distant traces (1 to 32 traces apart along inlines and crosslines) through all the seeds at
    once, so one bad local step is outvoted by the pairs that span it; each line's picks are then chosen together
    by dynamic programming (near the solution, steps along the reflector slope, waveforms that correlate), in a cube
    swept over inlines and crosslines so that neighbouring lines agree (``dp_sweeps``), checked
    for cycle skips against the long pairs (regions a cycle off moved back by a minimum cut where their pairs
    correlate clearly better: :mod:`~seismo3d.seismic.horizons.cycle_cut`), and scored by their correlation with their
    neighbours; in 3D, empty traces beside tracked ones are then filled where their neighbours agree and correlate
    (:func:`close_gaps`).

    With ``method='registration'``, in 2D the horizon is tracked along the section from each seed. In 3D it is tracked
    along each seed's inline, then carried inline by inline to both ends of the cube with the fused ICP; a trace the
    carry leaves empty is kept at its predicted position for the next inline, so a gap does not stop the horizon. A last
    pass fills empty traces from their tracked neighbours along inlines and crosslines where they agree and correlate
    (module docstring, step 3).

    Parameters
    ----------
    data : xarray.DataArray or (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, zero-mean, the last axis the sample. Must be finite. A cube of :func:`seismo3d.open` or
        a segysak Dataset's variable (dims ``(iline, xline, twt | depth)`` or ``(line or trace, twt | depth)``,
        :func:`~seismo3d.seismic.io.cube.seismic_axes`; a grid of a single inline or crossline is tracked as its 2D
        section), or a plain array.
    seeds : (ndim,) or (n_seeds, ndim) array_like of float
        Seed picks. For a DataArray, in the cube's own numbers: ``(inline, crossline, time or depth)`` (the time in
        its sample unit), ``(inline or crossline or trace label, time)`` for a line; for a plain array, in index
        space: ``(inline, xline, sample)`` (3D) or ``(trace, sample)`` (2D). Each is snapped to the nearest extremum
        of ``polarity`` within ``seed_snap`` (5) samples. Later seeds fill only traces the earlier ones left empty.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        Which event the horizon follows (see :func:`~seismo3d.seismic.reflector_picks`).
    faults : FaultInterpretation, optional
        Faults of the same ``data`` from :func:`seismo3d.seismic.trace_faults`: steps that cross one jump by its
        throw. Faults whose sides do not correlate better at their throw than without it (medians of
        ``FaultThrow.correlation`` and ``correlation_unshifted``), or that have no throw, are not used. A seed on a
        traced fault steps off it into the wall its waveform matches (module docstring). Without it, discontinuities
        are found by the registration (panels that do not fit).
    options : TrackingOptions, optional
        Panel sizes, steps, snapping, confidence, features and the other tuning values (:class:`TrackingOptions`).
    progress : bool
        Report progress over inlines (3D; :mod:`seismo3d._progress`: a bar on a terminal, log lines otherwise).
    **overrides
        Fields of :class:`TrackingOptions` by name (e.g. ``model='axis_scaled'``, ``features=None``,
        ``min_confidence=0.6``), replacing those of ``options``.

    Returns
    -------
    Horizon
        ``times`` (n_inlines, n_xlines) or (n_traces,) float32 fractional samples, NaN where empty, and
        ``confidence``. For a DataArray ``data``: ``times`` a float64 DataArray in the cube's sample unit (two-way
        time in ms, or depth; its ``units`` attribute) and ``confidence`` a float32 one, both on the cube's lateral
        dimensions and coordinates (line numbers, ``cdp_x`` / ``cdp_y``); ``seeds`` as given.

    Raises
    ------
    InputError
        ``data`` is not a finite 2D / 3D numeric array or a seismic DataArray; a seed is outside the data (for a
        DataArray: not on its lines or within its samples), on a dead trace, or has no extremum of ``polarity``
        within ``seed_snap`` samples; an option is out of range.

    References
    ----------
    .. [1] method.md section 6 (seismic tracks) and eq. 16 (fused ICP); the paper's "reconstruction of seismic
       tracks in a three-dimensional seismic cube".
    .. [3] X. Wu and S. Fomel, "Least-squares horizons with local slopes and multigrid correlations", Geophysics
       83(4), IM29-IM40, 2018 (the global method).
    .. [2] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013 (throw as the jump across a fault).
    """
    labels = HorizonLabels.of(data, seeds)
    if labels is not None:  # a labelled cube: tracked as its values, the horizon on its coordinates
        with labels.seed_errors():
            return labels.label(track_horizon(labels.values, labels.seeds, polarity=polarity, faults=faults,
                                              options=options, progress=progress, **overrides))
    check_choice(polarity, "polarity", POLARITIES)
    arr = as_seismic(data)
    seeds = as_seeds(seeds, arr.shape)
    opt = resolve_options(TrackingOptions, options, overrides, "track_horizon")
    crossings = opt.fault_crossings(faults, arr.ndim)
    for s in seeds:
        check_live_seed(arr, s)
    if opt.method == "global":
        return _track_global(arr, seeds, polarity, opt, crossings, progress)
    if arr.ndim == 2:
        return _track_2d(arr, seeds, polarity, opt, crossings)
    return _track_3d(arr, seeds, polarity, opt, crossings, progress)


def _track_global(arr, seeds, polarity, opt: TrackingOptions, crossings: FaultCrossings, progress: bool) -> Horizon:
    """``method='global'``: the least-squares horizon and its picks (:func:`~seismo3d.seismic.horizons.lsq.
    lsq_horizon`), the lateral continuity check along both lateral axes (the lines' programmes do not see each
    other: a lone pick a cycle off its agreeing neighbours is a spike; the seeds' own picks stay), then, in 3D, the
    gap closing (traces left empty beside tracked ones, e.g. a pick the lateral checks gave up while its neighbours
    were a cycle off before the repair, filled where the neighbours agree and correlate)."""
    picks = picks_of(arr, polarity)  # every trace's picks, once for the three steps
    found = lsq_horizon(arr, seeds, polarity=polarity, faults=crossings, options=opt, progress=progress, picks=picks)
    times, conf = found.times.copy(), found.confidence.copy()
    at_seeds = tuple(np.rint(seeds[:, :-1]).astype(np.intp).T)
    kept = times[at_seeds].copy(), conf[at_seeds].copy()
    despike_lines(arr, times, conf, polarity, opt, crossings, picks=picks)
    times[at_seeds], conf[at_seeds] = kept
    if arr.ndim == 3:
        close_gaps(arr, times, conf, polarity=polarity, faults=crossings, options=opt, picks=picks)
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)


def _snap_seed(sl: ReflectorSlice, j: int, t: float, window: float, seed) -> float:
    """The seed's pick on trace ``j`` of its slice (the seed's inline in 3D); SeedError naming the nearest pick."""
    t0 = sl.snap(j, t, window)
    if not np.isfinite(t0):
        nearest = nearest_reflector(sl.t, sl.offsets, (sl.n_traces,), (j, t))
        raise no_pick_error(seed, window, None if nearest is None else (*seed[:-2], *nearest))
    return t0


def _track_2d(arr, seeds, polarity, opt: TrackingOptions, crossings: FaultCrossings) -> Horizon:
    sl = ReflectorSlice(arr, polarity, opt.sigma_tensor, opt.ncc_half)
    times = np.full(sl.n_traces, np.nan)
    conf = np.full(sl.n_traces, np.nan)
    for s in seeds:
        j0 = int(round(s[0]))
        t0 = _snap_seed(sl, j0, s[1], opt.seed_snap, s)
        line = _track_along(sl, j0, t0, opt, crossings, lambda j, t: np.array([j, t], np.float64))
        fill = ~np.isfinite(times)
        times[fill], conf[fill] = line.times[fill], line.confidence[fill]
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)


def _track_3d(arr, seeds, polarity, opt: TrackingOptions, crossings: FaultCrossings, progress: bool) -> Horizon:
    n_il, n_xl, n_s = arr.shape
    times = np.full((n_il, n_xl), np.nan)
    conf = np.full((n_il, n_xl), np.nan)
    cache: dict[int, ReflectorSlice] = {}

    def slice_(i):
        if i not in cache:
            if len(cache) > 2:
                cache.pop(next(iter(cache)))
            cache[i] = ReflectorSlice(arr[i], polarity, opt.sigma_tensor, opt.ncc_half)
        return cache[i]

    with progress_steps(len(seeds) * n_il, "horizon", unit="inline", enabled=progress) as bar:
        for s in seeds:
            i0 = int(round(s[0]))
            sl = slice_(i0)
            j0 = int(round(s[1]))
            t0 = _snap_seed(sl, j0, s[2], opt.seed_snap, s)
            # along the seed's inline
            line = _track_along(sl, j0, t0, opt, crossings, lambda j, t, i=i0: np.array([i, j, t], np.float64))
            new_t = np.full((n_il, n_xl), np.nan)
            new_c = np.full((n_il, n_xl), np.nan)
            new_t[i0], new_c[i0] = line.times, line.confidence
            bar.advance()
            # carried inline by inline to both ends, from the tracked picks and from predicted positions where the
            # along-line pick was empty
            start = line.times.copy()
            for direction in (1, -1):
                prev, carried = i0, start
                crossed = [set() for _ in range(n_xl)]
                for i in range(i0 + direction, n_il if direction > 0 else -1, direction):
                    a, b = slice_(prev), slice_(i)
                    have = np.isfinite(carried)
                    if not have.any():
                        break
                    rows = (int(max(np.nanmin(carried) - opt.half_samples - 8, 0)),
                            int(min(np.nanmax(carried) + opt.half_samples + 8, n_s)))
                    matches = _slice_matches(a, b, rows, opt.features)
                    step = _carry(
                        a, b, carried, opt, crossings,
                        lambda x, t, g, i0_=prev, i1_=i: (np.array([i0_, x, t], np.float64),
                                                           np.array([i1_, x, g], np.float64)),
                        matches, opt.panel_traces, crossed)
                    new_t[i], new_c[i], carried = step.picks, step.confidence, step.carried
                    prev = i
                    bar.advance()
            fill = ~np.isfinite(times)
            times[fill], conf[fill] = new_t[fill], new_c[fill]
    # the gap-closing pass: traces the inline order left empty, from their neighbours along both axes
    close_gaps(arr, times, conf, polarity=polarity, faults=crossings, options=opt)
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)
