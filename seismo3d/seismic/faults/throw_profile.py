"""The throw profile of a fault in a 2D section: the throw measured in windows down the fault, the reflectors of each
side read outside the whole fault zone and carried along their own dip to its centre
(:mod:`~seismo3d.seismic.faults.throw`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .windows import CubeWindow
from ..traces import ncc_curve, runner_up_peak, side_coherence, small_shift_weight, subsample_peak

# used by the throw module; not part of the package's public face
__all__ = ["SectionProfile", "FaultZone", "fault_zone", "section_profile", "section_read_box", "section_step",
           "side_images"]


@dataclass(frozen=True)
class FaultZone:
    """The traces a 2D fault occupies at each sample: every strand of it, branches included.

    Attributes
    ----------
    t : (n_t,) float64 ndarray
        Samples from the fault's shallowest to its deepest point.
    lo, hi : (n_t,) float64 ndarray
        Smallest and largest trace of the fault's points within 1 sample of ``t`` (interpolated over rows without
        points), trace index.
    hw : float
        +1 when the hanging wall lies toward increasing trace index, -1 otherwise.
    """

    t: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    hw: float

    @property
    def centre(self) -> np.ndarray:
        """(n_t,) trace index of the zone's middle at each sample."""
        return 0.5 * (self.lo + self.hi)


@dataclass(frozen=True)
class SectionProfile:
    """Throw down a 2D fault, per window (see :func:`section_profile`)."""

    t: np.ndarray  # (n_windows,) window centres, samples
    throw: np.ndarray  # (n_windows,) samples, positive = hanging wall down; NaN where unmeasured
    correlation: np.ndarray  # (n_windows,) normalised correlation of the sides at the throw's shift
    correlation_unshifted: np.ndarray  # (n_windows,) ... with no shift
    coherence: float  # the smaller of the two sides' continuity (nearer against farther traces)
    step: np.ndarray = None  # (n_windows,) samples, the offset that is a step at the fault (section_step)
    rival: np.ndarray = None  # (n_windows,) samples, the throw of the best rival profile (the profile moved alike)
    rival_ratio: np.ndarray = None  # (n_windows,) its summed score over the chosen profile's

    @property
    def median_step(self) -> float:
        """Median of the finite ``step`` over the windows, samples; NaN if none."""
        return _finite_median(self.step if self.step is not None else [])


def fault_zone(pts: np.ndarray, hw: float) -> FaultZone:
    """The fault zone of a 2D fault: the extent of all its strands at each sample.

    Parameters
    ----------
    pts : (n, 2) float ndarray
        The fault's points (trace index, sample index).
    hw : float
        +1 when the hanging wall lies toward increasing trace index, -1 otherwise.

    Returns
    -------
    FaultZone
    """
    t_lo, t_hi = int(np.floor(pts[:, 1].min())), int(np.ceil(pts[:, 1].max()))
    t = np.arange(t_lo, t_hi + 1, dtype=np.float64)
    lo = np.full(t.size, np.nan)
    hi = np.full(t.size, np.nan)
    rows = np.rint(pts[:, 1]).astype(np.int64) - t_lo
    for dr in (-1, 0, 1):  # points within 1 sample of each row
        r = rows + dr
        ok = (r >= 0) & (r < t.size)
        np.fmin.at(lo, r[ok], pts[ok, 0])
        np.fmax.at(hi, r[ok], pts[ok, 0])
    have = np.isfinite(lo)
    lo = np.interp(t, t[have], lo[have])
    hi = np.interp(t, t[have], hi[have])
    return FaultZone(t, lo, hi, float(hw))


def section_read_box(zone: FaultZone, reach: float, n_traces: int) -> tuple[int, int, int, int]:
    """Trace range ``(i0, i1, 0, 1)`` (half-open) read for ``zone`` with reads up to ``reach`` traces beyond it."""
    i0 = max(int(np.floor(zone.lo.min() - reach)) - 1, 0)
    i1 = min(int(np.floor(zone.hi.max() + reach)) + 3, n_traces)
    return i0, max(i1, i0 + 1), 0, 1


def side_images(zone: FaultZone, win: CubeWindow, sides, slope_margin):
    """The footwall and hanging-wall images of a 2D fault on its zone's centre line.

    Side ``sigma`` (-1 footwall, +1 hanging wall) is read at ``sides[0]..sides[1]`` traces beyond the zone's edge on
    that side, each sample on the reflector through the centre node: ``t + p (x - c)``, ``c`` the zone's centre and
    ``p`` the reflector slope read on that side ``sides[1] + slope_margin`` traces beyond the edge, where the reflector
    lands (two fixed-point iterations). The reflectors of each side are so carried along their own dip to the centre,
    across the strands of the zone, and the two images differ by the throw only.

    Returns
    -------
    images : ((n_t,) float64, (n_t,) float64)
        Footwall and hanging-wall images (0 where not valid).
    valid : ((n_t,) bool, (n_t,) bool)
        Samples read at half the offsets or more on that side.
    coherence : (float, float)
        Each side's continuity (nearer against farther half of the offsets; NaN when unmeasurable).
    """
    c = zone.centre
    n0, _, nt = win.cube_shape
    east = np.array([1.0, 0.0])
    images, valids, coherence = [], [], []
    for sigma in (-1.0, 1.0):
        step = sigma * zone.hw  # trace direction of this side
        edge = zone.hi if step > 0 else zone.lo
        x_far = edge + step * (sides[1] + slope_margin)
        p = np.zeros(zone.t.size)
        for _ in range(2):
            p = win.slope_along(x_far, np.zeros_like(x_far), zone.t + p * (x_far - c), east)
        d = np.arange(sides[0], sides[1] + 1, dtype=np.float64)[:, None]
        x = edge[None, :] + step * d
        tt = zone.t[None, :] + p[None, :] * (x - c[None, :])
        inside = (x >= -0.01) & (x <= n0 - 0.99) & (tt >= 0) & (tt <= nt - 1)
        vals = win.amplitude_at(x.ravel(), np.zeros(x.size), tt.ravel()).reshape(x.shape)
        vals = np.where(inside, vals, 0.0)
        cnt = inside.sum(axis=0)
        good = cnt >= 0.5 * d.size
        images.append(np.where(good, vals.sum(axis=0) / np.maximum(cnt, 1), 0.0))
        valids.append(good)
        coherence.append(side_coherence(vals, inside))
    return tuple(images), tuple(valids), tuple(coherence)


def section_profile(zone: FaultZone, win: CubeWindow, *, sides, slope_margin, window: int, step: int, reach: int,
                    min_overlap: int, smoothness: float, opt) -> SectionProfile:
    """Throw down a 2D fault: the shifts of its side images (:func:`side_images`) in windows of ``window`` samples
    every ``step`` samples (the whole fault when it spans fewer than two windows), chosen together.

    1. Each window's correlation curve over the integer shifts within ``reach``
       (:func:`~seismo3d.seismic.traces.ncc_curve`), weighted by the preference for small shifts.
    2. The shifts of all windows maximise the sum of their weighted correlations less ``smoothness`` times the sum
       of the squared changes between consecutive windows (dynamic programming, as the smooth shifts of dynamic
       warping, Hale 2013): a change of a reflector period between windows that share three quarters of their
       samples is a cycle skip, not a throw gradient.
    3. Each chosen shift is refined by a parabola through its curve's three values.

    Parameters
    ----------
    zone : FaultZone
        The fault's zone (:func:`fault_zone`).
    win : CubeWindow
        The traces of :func:`section_read_box` (a section as ``(n_traces, 1, n_samples)``).
    sides : (int, int)
        Nearest and farthest offsets read beyond the zone's edges, traces.
    slope_margin : int
        Traces beyond the farthest offset where the reflector slopes are read.
    window, step : int
        Window length and the distance between window starts, samples.
    reach : int
        Largest |shift| searched, samples.
    min_overlap : int
        Fewest samples seen on both sides for a shift to count.
    smoothness : float
        Cost of a change of shift between consecutive windows, correlation per squared sample.
    opt : ThrowOptions
        ``min_rows``, ``small_shift_prior`` and ``step_traces`` (the traces beside the zone whose lags give each
        side's dip for the step at the fault, :func:`section_step`; at most ``sides[1] + slope_margin - 2``).

    Returns
    -------
    SectionProfile
        Per window: its centre (samples), throw (samples, positive = hanging wall down; NaN where the sides overlap
        too little), the correlation at that shift and at none, the step at the fault, and the throw of the best
        rival profile (the chosen one moved alike in every window, e.g. by a reflector period) with its summed score
        over the chosen one's (:func:`_profile_rival`); and the sides' continuity.

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    """
    (f, h), (vf, vh), coh = side_images(zone, win, sides, slope_margin)
    n = zone.t.size
    if n <= 2 * window:  # windows that all overlap measure nothing apart: one shift for the whole fault
        starts, size = [0], n
    else:
        last = n - window
        starts = list(range(0, last + 1, step))
        if starts[-1] != last:
            starts.append(last)
        size = window
    ks = np.arange(-reach, reach + 1)
    weight = small_shift_weight(ks, reach, opt.small_shift_prior)
    n_w = len(starts)
    # the whole fault's curve, added to every window's: a prior against a cycle skip that one window alone prefers
    whole = ncc_curve(f[None], h[None], vf[None], vh[None], reach, min_overlap, opt.min_rows)
    prior = np.zeros(ks.size) if whole is None else np.nan_to_num(whole[1] * weight, nan=0.0)
    score = np.zeros((n_w, ks.size))  # weighted correlation; 0 (no evidence either way) where unmeasured
    curves = []
    for w, s in enumerate(starts):
        sl = slice(s, s + size)
        curve = ncc_curve(f[None, sl], h[None, sl], vf[None, sl], vh[None, sl], reach, min_overlap, opt.min_rows)
        curves.append(curve)
        if curve is not None:
            score[w] = np.nan_to_num(curve[1] * weight, nan=0.0) + prior
    k_best = _smooth_path(score, ks, smoothness)
    centres = np.asarray([zone.t[s] + 0.5 * (size - 1) for s in starts])
    throw = np.full(n_w, np.nan)
    corr = np.full(n_w, np.nan)
    corr0 = np.full(n_w, np.nan)
    for w, (curve, i) in enumerate(zip(curves, k_best)):
        if curve is None or not np.isfinite(curve[1][i]):
            continue
        throw[w] = float(ks[i]) + subsample_peak(curve[1], i)
        corr[w] = curve[2][i]
        corr0[w] = curve[2][reach]
    coherence = float(np.min(coh)) if np.all(np.isfinite(coh)) else float("nan")
    near = min(int(opt.step_traces), int(sides[1]) + int(slope_margin) - 2)  # within the traces read
    steps = section_step(zone, win, starts=starts, size=size, near=near, reach=reach, min_overlap=min_overlap,
                         min_rows=opt.min_rows)
    offset, ratio = _profile_rival(score, k_best)
    measured = np.isfinite(throw)
    rival = np.where(measured, throw + offset, np.nan)
    rival_ratio = np.where(measured, ratio, np.nan)
    return SectionProfile(centres, throw, corr, corr0, coherence, steps, rival, rival_ratio)


def _profile_rival(score: np.ndarray, k_best: np.ndarray) -> tuple[float, float]:
    """The best rival of a chosen throw profile: the whole profile moved by ``d`` samples (a cycle skip moves every
    window alike, and moving all keeps the smoothness cost). Its summed score over the windows, as a function of
    ``d`` (the moves that keep every window within the shifts searched), and the rival peak of that function
    (:func:`~seismo3d.seismic.traces.runner_up_peak`): the move and its summed score over the chosen profile's."""
    n_k = score.shape[1]
    d = np.arange(-int(k_best.min()), n_k - int(k_best.max()))  # every window stays within the shifts searched
    rows = np.arange(score.shape[0])[:, None]
    total = score[rows, k_best[:, None] + d[None, :]].sum(axis=0)
    j, ratio = runner_up_peak(total, int(np.flatnonzero(d == 0)[0]))
    return (float(d[0]) + j if np.isfinite(j) else float("nan")), ratio


def _finite_median(values) -> float:
    """Median of the finite values, NaN if none (no warning)."""
    values = np.asarray(values, np.float64)
    values = values[np.isfinite(values)]
    return float(np.median(values)) if values.size else float("nan")


def _lag(a, b, va, vb, reach: int, min_overlap: int, min_rows: int) -> float:
    """Shift of column ``b`` relative to column ``a`` (samples, positive: ``b``'s reflectors deeper) where their
    normalised correlation peaks within ``reach``, to a fraction of a sample; NaN when unmeasurable."""
    curve = ncc_curve(a[None], b[None], va[None], vb[None], reach, min_overlap, min_rows)
    if curve is None or not np.isfinite(curve[1]).any():
        return float("nan")
    i = int(np.nanargmax(curve[1]))
    return float(curve[0][i]) + subsample_peak(curve[1], i)


def section_step(zone: FaultZone, win: CubeWindow, *, starts, size: int, near: int, reach: int, min_overlap: int,
                 min_rows: int) -> np.ndarray:
    """The part of the offset across a 2D fault that is a step at the fault, per window down it.

    A fault offsets the reflectors abruptly: the lag between the traces just outside its zone on either side (its
    strands and the traces between them) is the throw plus the reflectors' dip over that width, while the lags
    between neighbouring traces beside it are the dip alone. A flexure (a drape or drag fold, a monocline) bends
    them over several traces instead: the lags ramp up toward its axis and the lag across the zone is the dip
    there. The step is the lag across (between the traces one trace outside the zone's edges, each row on the
    fault's own trace) less the zone's width times the mean dip of the two sides, each the median lag between
    neighbouring traces within ``near`` traces of the edge (where the fold is as steep as at its axis, so a fold's
    step stays near 0, while the throw read from reflectors carried from farther out along their flatter dip shows
    an offset).

    Parameters
    ----------
    zone : FaultZone
        The fault's zone.
    win : CubeWindow
        The traces of :func:`section_read_box` (reaching ``near + 2`` traces beyond the zone).
    starts : list of int
        First row (index into ``zone.t``) of each window.
    size : int
        Rows per window.
    near : int
        Traces beside each edge whose neighbour lags give the dip of that side (>= 1).
    reach : int
        Largest |lag| searched across the zone, samples (the throw's search); between neighbouring traces at most 3.
    min_overlap, min_rows : int
        Fewest samples and distinct rows of both columns for a lag to count.

    Returns
    -------
    (len(starts),) float64 ndarray
        The step per window, samples, positive where the hanging wall side lies deeper; NaN where unmeasured.
    """
    n0 = win.cube_shape[0]
    t = zone.t

    def column(x):
        inside = (x >= -0.01) & (x <= n0 - 0.99)
        vals = win.amplitude_at(np.clip(x, 0, n0 - 1), np.zeros(x.size), t)
        return np.where(inside, vals, 0.0), inside

    left = [column(zone.lo - d) for d in range(1, near + 2)]  # left[0]: one trace outside the zone
    right = [column(zone.hi + d) for d in range(1, near + 2)]
    width = zone.hi - zone.lo + 2.0
    near_reach = min(3, reach)
    out = np.full(len(starts), np.nan)
    for w, s in enumerate(starts):
        sl = slice(s, s + size)

        def lag(a, b, r):
            return _lag(a[0][sl], b[0][sl], a[1][sl], b[1][sl], r, min_overlap, min_rows)

        dip_left = _finite_median([lag(left[d + 1], left[d], near_reach) for d in range(near)])
        dip_right = _finite_median([lag(right[d], right[d + 1], near_reach) for d in range(near)])
        across = lag(left[0], right[0], reach + int(np.ceil(near_reach * float(width[sl].max()))))
        if np.isfinite(dip_left) and np.isfinite(dip_right) and np.isfinite(across):
            out[w] = zone.hw * (across - float(width[sl].mean()) * 0.5 * (dip_left + dip_right))
    return out


def _smooth_path(score: np.ndarray, ks: np.ndarray, smoothness: float) -> np.ndarray:
    """Indices into ``ks``, one per row of ``score (n_windows, n_shifts)``, maximising the sum of the chosen scores
    less ``smoothness`` times the squared changes of shift between consecutive rows (Viterbi)."""
    penalty = smoothness * np.square(ks[:, None] - ks[None, :]).astype(np.float64)  # (from, to)
    value = score[0].copy()
    back = np.zeros(score.shape, np.int64)
    for w in range(1, score.shape[0]):
        cand = value[:, None] - penalty
        back[w] = np.argmax(cand, axis=0)
        value = cand[back[w], np.arange(ks.size)] + score[w]
    path = np.zeros(score.shape[0], np.int64)
    path[-1] = int(np.argmax(value))
    for w in range(score.shape[0] - 1, 0, -1):
        path[w - 1] = back[w, path[w]]
    return path
