"""Horizon tracking by registering neighbouring slices ("seismic tracks", method.md section 6).

A horizon is followed from seed picks in two moves, both made with the registration engine:

1. **Along a slice** (a 2D section, or the seed's inline of a cube): a window of traces around the current pick
   (the *source panel*) is registered onto the window a few traces further on (the *target panel*) by point-to-plane
   ICP (:func:`seismo3d.registration.icp`) on the *reflector points*: the same-polarity extrema of every trace in a
   band around the horizon, with normals from the structure tensor. The pick is carried by the transform, followed
   along the reflector slope to the next trace and snapped to the nearest extremum of the same polarity. Because the
   panel holds several reflectors over a dozen traces, one weak or split reflector cannot pull the pick onto its
   neighbour, which is exactly the jump a plain amplitude autotracker (:func:`autotrack`) makes.
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
two sides correlate less than 0.5 across it (median of its throw correlation), or which has no throw, is left out, as
if not traced. Without fault input, a step whose panels do not fit (a discontinuity) is re-made from one side with
the shift found by normalised cross-correlation of the two sides' stacked traces, the start the throw estimation
uses (:mod:`seismo3d.seismic.throw`).

Each pick gets a confidence: the normalised cross-correlation of the waveform around it with the waveform around the
pick it came from. Picks below ``min_confidence``, and picks with no extremum of the right polarity within the snap
window, are left empty (NaN); tracking goes on from their predicted position. :func:`fill_horizon` interpolates the
gaps as a separate, explicit step.

Conventions: index space as in :mod:`seismo3d.seismic.faults` (axis 0 inline, axis 1 crossline, last axis sample,
downward; a 2D section is ``(n_traces, n_samples)``). Horizon times are fractional sample indices; convert with the
cube's ``samples`` axis (ms or m).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numba as nb
import numpy as np
from scipy.spatial import cKDTree

from .._validation import check_choice, check_positive
from ..errors import DegenerateGeometryWarning, InputError, RegistrationError
from .attributes import _as_seismic, structure_tensor_orientation
from .throw import _hanging_wall_normals

__all__ = ["POLARITIES", "Horizon", "reflector_picks", "autotrack", "track_horizon", "fill_horizon",
           "horizon_errors", "write_horizon_text"]

POLARITIES = ("peak", "trough", "zero_rising", "zero_falling")
_POLARITY_CODE = {"peak": 0, "trough": 1, "zero_rising": 2, "zero_falling": 3}
_NCC_HALF = 8  # samples each side of a pick in the confidence correlation
_PANEL_ITERATIONS = 15  # per distance stage: panels of ~100 points converge in a few; sliding never stops by itself
_REFERENCE_WEIGHT = 0.3  # weight of the newest accepted pick in the running reference waveform along a slice
_SEED_SNAP = 5.0  # samples: a seed snaps to an extremum this far at most (about half a period)
_PIERCE = 1.5  # voxels: a step crosses a fault when it pierces the fault surface this close to a fault point
_ON_FAULT = 0.5  # voxels: a point this close to a fault's local plane (and to its points) lies on the fault
_FAULT_ZONE = 2.0  # traces: along a slice, no step ends this close to a fault (its drag zone); it steps over it
# A fault whose two sides correlate less than this (median over its points of FaultThrow.correlation) is not used
# (_reliable_throw): on the clipped Penobscot data trace_faults' low-correlation faults carry throws of several
# samples where people see none, and jumping by them (or searching a shift at each of them) moved horizon 2 off its
# reflector.
# The "traced faults" rows of benchmarks/horizons.py show the horizons with the faults that pass.
_MIN_THROW_CORRELATION = 0.5


@dataclass(frozen=True, eq=False)
class Horizon:
    """A tracked horizon (see :func:`track_horizon`).

    Attributes
    ----------
    times : (n_inlines, n_xlines) or (n_traces,) float32 ndarray
        Fractional sample index of the horizon on each trace; NaN where it is empty (not reached, no extremum of
        the polarity within the snap window, or confidence below the threshold).
    confidence : same shape, float32 ndarray
        Normalised cross-correlation, in [-1, 1], of the waveform (+-8 samples) around each pick with the waveform
        around the pick it was carried from (1 at seeds); NaN where the tracker never reached the trace.
    polarity : str
        One of :data:`POLARITIES`.
    seeds : (n_seeds, ndim) float64 ndarray
        Seed positions in index space, ``(inline, xline, sample)`` or ``(trace, sample)``.
    """

    times: np.ndarray
    confidence: np.ndarray
    polarity: str
    seeds: np.ndarray

    @property
    def mask(self) -> np.ndarray:
        """Boolean array, True where the horizon has a pick."""
        return np.isfinite(self.times)

    @property
    def coverage(self) -> float:
        """Fraction of traces with a pick."""
        return float(np.count_nonzero(self.mask) / self.times.size)


# --------------------------------------------------------------------------------------------------------------------
# Reflector picks: same-polarity extrema (or zero crossings) along every trace, with sub-sample positions.

@nb.njit(cache=True)
def _trace_picks(a, code, out):
    """Sub-sample picks of one trace into ``out``; returns their number. Peaks on clipped plateaus sit at the
    plateau's centre; isolated extrema are refined by a parabola through three samples."""
    n = a.size
    k = 0
    if code >= 2:
        for i in range(n - 1):
            y0, y1 = a[i], a[i + 1]
            if (code == 2 and y0 < 0.0 <= y1) or (code == 3 and y0 > 0.0 >= y1):
                out[k] = i + y0 / (y0 - y1) if y0 != y1 else i
                k += 1
        return k
    sgn = 1.0 if code == 0 else -1.0
    i = 1
    while i < n - 1:
        y = sgn * a[i]
        if y > 0.0 and y > sgn * a[i - 1]:
            j = i
            while j + 1 < n and sgn * a[j + 1] == y:
                j += 1
            if j + 1 < n and sgn * a[j + 1] < y:
                if j > i:
                    out[k] = 0.5 * (i + j)
                else:
                    y0, y2 = sgn * a[i - 1], sgn * a[i + 1]
                    den = y0 - 2.0 * y + y2
                    out[k] = i + (0.5 * (y0 - y2) / den if den != 0.0 else 0.0)
                k += 1
            i = j + 1
        else:
            i += 1
    return k


@nb.njit(cache=True)
def _section_picks(sec, code):
    n_tr, n_s = sec.shape
    buf = np.empty(n_s, np.float64)
    offsets = np.zeros(n_tr + 1, np.int64)
    total = np.empty(n_tr * (n_s // 2 + 1), np.float64)
    m = 0
    for j in range(n_tr):
        c = _trace_picks(sec[j], code, buf)
        total[m:m + c] = buf[:c]
        m += c
        offsets[j + 1] = m
    return total[:m].copy(), offsets


def _check_polarity(polarity) -> int:
    return _POLARITY_CODE[check_choice(polarity, "polarity", POLARITIES)]


def reflector_picks(section, *, polarity: str = "peak") -> tuple[np.ndarray, np.ndarray]:
    """Same-polarity reflector picks along every trace of a section.

    Peaks (troughs) are local maxima of positive (minima of negative) amplitude, refined to a sub-sample position
    by a parabola through three samples; on a clipped plateau (several equal samples, as in 8-bit exports) the pick
    is the plateau's centre. Zero crossings are linearly interpolated.

    Parameters
    ----------
    section : (n_traces, n_samples) array_like
        Seismic amplitudes, zero-mean (the polarity is read from the sign). Must be finite.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        'zero_rising': amplitude goes from negative above to positive below (a "-/+" zero crossing);
        'zero_falling': from positive to negative ("+/-").

    Returns
    -------
    times : (n_picks,) float64 ndarray
        Fractional sample index of each pick, trace by trace, increasing within a trace.
    offsets : (n_traces + 1,) int64 ndarray
        Picks of trace ``j`` are ``times[offsets[j]:offsets[j + 1]]``.

    Raises
    ------
    InputError
        ``section`` is not a finite 2D numeric array, or ``polarity`` is unknown.
    """
    code = _check_polarity(polarity)
    sec = np.asarray(section)
    if sec.ndim != 2 or sec.shape[1] < 3:
        raise InputError(f"section must be 2D (n_traces, n_samples) with at least 3 samples; got shape {sec.shape}")
    sec = _as_seismic(sec, "section", min_size=1)
    return _section_picks(np.ascontiguousarray(sec, dtype=np.float64), code)


# --------------------------------------------------------------------------------------------------------------------
# One slice with its reflector points.

class _Slice:
    """A 2D slice (n_traces, n_samples): amplitudes, slopes and reflector points with normals."""

    def __init__(self, amp: np.ndarray, code: int, sigma_tensor):
        self.amp = np.ascontiguousarray(amp, dtype=np.float32)
        self.n_traces, self.n_samples = self.amp.shape
        orient = structure_tensor_orientation(self.amp, sigma_tensor=sigma_tensor)
        self.slope = orient.slopes[0]
        self.t, self.offsets = _section_picks(self.amp.astype(np.float64), code)
        self.x = np.repeat(np.arange(self.n_traces, dtype=np.float64), np.diff(self.offsets))
        ti = np.clip(np.rint(self.t).astype(np.intp), 0, self.n_samples - 1)
        self.normals = orient.normals[self.x.astype(np.intp), ti].astype(np.float64)

    def slope_at(self, j: int, t: float) -> float:
        return float(self.slope[j, int(np.clip(round(t), 0, self.n_samples - 1))])

    def snap(self, j: int, t: float, window: float) -> float:
        """Nearest pick of trace ``j`` within ``window`` samples of ``t``, else NaN."""
        return _nearest_pick(self.t, self.offsets, j, t, window)

    def band(self, lo: int, hi: int, ref: np.ndarray, half: float) -> tuple[np.ndarray, np.ndarray]:
        """Reflector points of traces lo..hi (inclusive) within ``half`` samples of ``ref[x - lo]``."""
        a, b = self.offsets[lo], self.offsets[hi + 1]
        x, t = self.x[a:b], self.t[a:b]
        keep = np.abs(t - ref[(x - lo).astype(np.intp)]) <= half
        return np.column_stack([x[keep], t[keep]]), self.normals[a:b][keep]

    def window(self, j: int, t: float, half: int = _NCC_HALF) -> np.ndarray:
        """Amplitudes of trace ``j`` at ``t - half .. t + half`` (linear interpolation; NaN outside)."""
        return _waveform(self.amp[j], t, half)


def _nearest_pick(picks: np.ndarray, offsets: np.ndarray, k: int, t: float, window: float) -> float:
    """The pick of trace ``k`` (``picks[offsets[k]:offsets[k + 1]]``) nearest to ``t`` within ``window``, else NaN."""
    p = picks[offsets[k]:offsets[k + 1]]
    if p.size == 0 or not np.isfinite(t):
        return np.nan
    i = int(np.argmin(np.abs(p - t)))
    return float(p[i]) if abs(p[i] - t) <= window else np.nan


def _waveform(trace: np.ndarray, t: float, half: int = _NCC_HALF) -> np.ndarray:
    """Amplitudes of ``trace`` at ``t - half .. t + half`` (linear interpolation; NaN outside)."""
    s = t + np.arange(-half, half + 1, dtype=np.float64)
    return np.interp(s, np.arange(trace.shape[0]), trace, left=np.nan, right=np.nan)


def _ncc(a: np.ndarray, b: np.ndarray) -> float:
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 5:
        return np.nan
    a = a[ok] - a[ok].mean()
    b = b[ok] - b[ok].mean()
    den = np.sqrt((a * a).sum() * (b * b).sum())
    return float((a * b).sum() / den) if den > 0 else 0.0


# --------------------------------------------------------------------------------------------------------------------
# Faults: which steps cross one, and by how much the horizon jumps there.

def _footwall_normals(normals) -> np.ndarray:
    """A fault's unit normals (n, ndim), of either sign, pointing into its footwall as its throw was measured.

    A fault's normals come from the strike and dip of each point, so on a (near-)vertical fault they point to either
    side (strike and strike + 180 degrees). The throw is measured with the normals sign-aligned to their principal
    direction (:mod:`seismo3d.seismic.throw`), so the jump of a horizon must use the same sides.
    """
    n = np.asarray(normals, np.float64)
    n = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)  # unit, as fault_throw makes them
    if n.shape[1] == 2:
        n3 = np.column_stack([n[:, 0], np.zeros(len(n)), n[:, 1]])
        return -_hanging_wall_normals(n3)[:, [0, 2]]
    return -_hanging_wall_normals(n)


def _reliable_throw(throw) -> bool:
    """Whether :func:`track_horizon` jumps by a fault's throw: its two sides correlate at least
    ``_MIN_THROW_CORRELATION`` across it (median of ``FaultThrow.correlation``); False without a throw."""
    corr = np.asarray(throw.correlation, np.float64)
    return bool(np.isfinite(corr).any() and np.nanmedian(corr) >= _MIN_THROW_CORRELATION)


class _FaultIndex:
    """Fault points with normals (into the footwall), throws and fault ids, for finding the faults a step crosses."""

    def __init__(self, points, normals, throws, ids=None):
        self.points = points
        self.normals = normals
        self.throws = throws
        self.ids = np.zeros(len(points), np.intp) if ids is None else np.asarray(ids, np.intp)
        self.tree = cKDTree(points) if len(points) else None

    @classmethod
    def _empty(cls, ndim: int):
        return cls(np.zeros((0, ndim)), np.zeros((0, ndim)), np.zeros(0))

    @classmethod
    def from_interpretation(cls, faults, ndim: int):
        if faults is None:
            return cls._empty(ndim)
        pts, nrm, thr, ids = [], [], [], []
        for k, (f, th) in enumerate(zip(faults.faults, faults.throws)):
            p = np.asarray(f.points, np.float64)
            if p.ndim != 2 or p.shape[1] != ndim:
                raise InputError(f"faults were traced on {p.shape[-1]}D data but the horizon is tracked in {ndim}D "
                                 "data; trace the faults of the same array")
            if not _reliable_throw(th):
                continue
            pts.append(p)
            nrm.append(_footwall_normals(f.normals))
            thr.append(np.asarray(th.throw, np.float64))
            ids.append(np.full(len(p), k, np.intp))
        if not pts:
            return cls._empty(ndim)
        return cls(np.concatenate(pts), np.concatenate(nrm), np.concatenate(thr), np.concatenate(ids))

    def _planes(self, a: np.ndarray, b: np.ndarray):
        """For each fault with points near the segment a-b: (fault id, indices of those points, centre, unit normal
        into the footwall) of its local plane.

        The least-squares plane of the points (a line in 2D), oriented like their normals: the per-point normals come
        from a coarse strike / dip scan, and a plane through each voxel misplaces the pierce point where the traced
        surface steps from voxel to voxel. Fewer than 4 points, or points that do not spread over a plane (a strip
        along the fault's edge, a thin slab) or do not lie on one: their mean normal."""
        if self.tree is None:
            return
        idx = self.tree.query_ball_point(0.5 * (a + b), 0.5 * float(np.linalg.norm(b - a)) + _PIERCE + 1.0)
        if not idx:
            return
        idx = np.asarray(idx)
        for fid in np.unique(self.ids[idx]):
            sel = idx[self.ids[idx] == fid]
            p = self.points[sel]
            n = self.normals[sel].mean(axis=0)
            c = p.mean(axis=0)
            if len(p) >= 4:
                _, sv, vt = np.linalg.svd(p - c, full_matrices=False)
                if len(sv) == 3:
                    planar = sv[1] > 0.5 * sv[0] and sv[2] < 0.5 * sv[1]  # spread over two axes, thin on the third
                else:
                    planar = sv[1] < 0.5 * sv[0]  # 2D: along a line
                if planar:
                    n = vt[-1] if np.dot(vt[-1], n) >= 0 else -vt[-1]
            norm = float(np.linalg.norm(n))
            if norm > 0.0:
                yield int(fid), sel, c, n / norm

    def crossings(self, a: np.ndarray, b: np.ndarray) -> dict:
        """The faults between point ``a`` and point ``b``: {fault id: vertical jump (samples) of a horizon going from
        ``a`` to ``b`` across it}, +throw into the hanging wall, -throw into the footwall, NaN for unknown throw.

        A step crosses a fault when it pierces the fault's local plane (:meth:`_planes`) within ``_PIERCE`` of one of
        the fault's points, not beside the fault (past its end)."""
        out = {}
        for fid, sel, c, n in self._planes(a, b):
            sa, sb = float(np.dot(a - c, n)), float(np.dot(b - c, n))
            if (sa > 0) == (sb > 0):
                # the same side; a point on the plane counts as the hanging wall's (sb <= 0, as in wall_jump), so a
                # step that ends on a steep fault's plane (a carry from inline to inline lands on it) and the step
                # that leaves it cross it once
                continue
            pierce = a + sa / (sa - sb) * (b - a)
            d = np.linalg.norm(self.points[sel] - pierce, axis=1)
            if d.min() > _PIERCE:
                continue
            thr = self.throws[sel[np.argmin(d)]]
            out[fid] = -thr if sb > 0 else thr  # NaN stays NaN: unknown throw
        return out

    def on_fault(self, a: np.ndarray) -> set:
        """Ids of the faults point ``a`` lies on: within ``_ON_FAULT`` of the fault's local plane and within
        ``_PIERCE`` of one of its points."""
        return {fid for fid, sel, c, n in self._planes(a, a)
                if np.linalg.norm(self.points[sel] - a, axis=1).min() <= _PIERCE
                and abs(float(np.dot(a - c, n))) < _ON_FAULT}

    def wall_jump(self, a: np.ndarray, b: np.ndarray, ids: set) -> float:
        """Jump (samples) of a horizon from ``a``, which lies on the faults ``ids``, to ``b`` if ``a`` is in the wall
        ``b`` is not in: the sum of those faults' throws, signed as in :meth:`crossings`. NaN for an unknown throw."""
        total = 0.0
        for fid, sel, c, n in self._planes(a, b):
            if fid in ids:
                thr = self.throws[sel[np.argmin(np.linalg.norm(self.points[sel] - a, axis=1))]]
                total += -thr if float(np.dot(b - c, n)) > 0 else thr
        return total

    def block(self, line_point, n: int, c: int, tc: float, slope: float, lo: int, hi: int) -> tuple[int, int]:
        """The traces of ``lo..hi`` (inclusive, containing ``c``) that a horizon through (c, tc) with ``slope``
        (samples per trace) reaches without crossing a fault: the fault block of the pick along a slice of ``n``
        traces, which ``line_point(x, t)`` maps to this index's coordinates. An end short of ``lo`` / ``hi`` is the
        last trace before a fault."""
        if self.tree is None:
            return lo, hi
        a, b = line_point(lo, tc + slope * (lo - c)), line_point(hi, tc + slope * (hi - c))
        if not self.tree.query_ball_point(0.5 * (a + b), 0.5 * float(np.linalg.norm(b - a)) + _PIERCE + 1.0):
            return lo, hi
        ends = []
        for direction, end in ((-1, lo), (1, hi)):
            x = c
            while x != end and 0 <= x + direction < n:
                y = x + direction
                if self.crossings(line_point(x, tc + slope * (x - c)), line_point(y, tc + slope * (y - c))):
                    break
                x = y
            ends.append(x)
        return ends[0], ends[1]

    def jump(self, a: np.ndarray, b: np.ndarray, crossed: set | None = None) -> float:
        """Vertical jump (samples) of a horizon going from ``a`` to ``b``: the sum over the faults crossed (two faults
        between the same traces add up); 0 when none, NaN when a crossed fault's throw is unknown.

        ``crossed``: the fault ids this horizon path has already crossed, left out and updated. A (planar) fault is
        crossed once going one way; after the jump, a dipping fault's plane can lie beyond the new pick (heave,
        reverse-fault overlap), which is no second crossing."""
        cross = self.crossings(a, b)
        if crossed is not None:
            cross = {f: v for f, v in cross.items() if f not in crossed}
            crossed.update(cross)
        return float(sum(cross.values()))


# --------------------------------------------------------------------------------------------------------------------
# Registration of two panels (point-to-plane ICP or fused ICP) and the one-sided shift search.

def _register(src_pts, dst_pts, dst_nrm, init, model, features=None):
    """Panel registration; returns (transform, fitness) or (None, 0) when it cannot run."""
    from ..registration import fused_icp, icp

    if len(src_pts) < 6 or len(dst_pts) < 6:
        return None, 0.0
    with warnings.catch_warnings():
        # Reflectors are near-parallel lines: sliding along them is unconstrained by design (the pick is followed
        # along the reflector afterwards), so the degeneracy warning carries no news here.
        warnings.simplefilter("ignore", DegenerateGeometryWarning)
        try:
            if features is not None and len(features[0]) >= 8:
                res = fused_icp(src_pts, dst_pts, target_normals=dst_nrm, source_features=features[0],
                                target_features=features[1], model=model, init=init, max_distance=(3.0, 1.5),
                                ransac_threshold=1.5, degeneracy_threshold=0.0, max_iterations=_PANEL_ITERATIONS)
            else:
                res = icp(src_pts, dst_pts, target_normals=dst_nrm, method="point_to_plane", model=model, init=init,
                          max_distance=(3.0, 1.5), degeneracy_threshold=0.0, max_iterations=_PANEL_ITERATIONS)
        except (RegistrationError, InputError):
            return None, 0.0
    return res.transform, float(res.fitness)


def _stack(sl: _Slice, traces: np.ndarray, ref: np.ndarray, half: int) -> np.ndarray:
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


def _wall_score(sl: _Slice, j0: int, t0: float, j: int, pred: float, pc: float, direction: int, width: int,
                shift: float) -> float:
    """Normalised cross-correlation of the waveform at the seed (j0, t0) with the stack of the ``width`` traces from
    ``j`` on (away from the seed), read along the slope ``pc`` from ``pred + shift``."""
    _, ahead = _sides(sl.n_traces, j0, j, direction, width)
    return _ncc(sl.window(j0, t0), _stack(sl, ahead, pred + pc * (ahead - j) + shift, _NCC_HALF))


def _side_shift(sl: _Slice, c: int, tc: float, pc: float, j: int, direction: int, width: int, half: int,
                max_shift: int) -> float:
    """Shift (samples) of the horizon from the traces behind ``c`` to the traces from ``j`` on, by normalised
    cross-correlation of the two sides' stacked traces (flattened along the slope ``pc``); 0 when a side has fewer
    than two traces or nothing correlates."""
    behind, ahead = _sides(sl.n_traces, c, j, direction, width)
    if behind.size < 2 or ahead.size < 2:
        return 0.0
    f = _stack(sl, behind, tc + pc * (behind - c), half + max_shift)
    g = _stack(sl, ahead, tc + pc * (ahead - c), half + max_shift)
    core = f[max_shift:max_shift + 2 * half + 1]
    scores = np.array([_ncc(core, g[max_shift + s:max_shift + s + 2 * half + 1])
                       for s in range(-max_shift, max_shift + 1)])
    if not np.isfinite(scores).any():
        return 0.0
    k = int(np.nanargmax(scores))
    shift = float(k - max_shift)
    if 0 < k < len(scores) - 1 and np.isfinite(scores[k - 1:k + 2]).all():
        y0, y1, y2 = scores[k - 1:k + 2]
        den = y0 - 2 * y1 + y2
        if den < 0:
            shift += 0.5 * (y0 - y2) / den
    return shift


# --------------------------------------------------------------------------------------------------------------------
# Tracking along one slice.

@dataclass(frozen=True)
class _Options:
    model: str
    half_traces: int
    half_samples: float
    step: int
    snap: float
    min_confidence: float
    max_throw: int
    min_fitness: float


def _panel_step(sl: _Slice, src_span: tuple[int, int], dst_span: tuple[int, int], c: int, tc: float, j: int,
                t_j: float, pc: float, opt: _Options) -> tuple[float, float]:
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
    m, fit = _register(src, dst, dnrm, init, opt.model)
    if m is None:
        return np.nan, 0.0
    q = m @ np.array([c, tc, 1.0])
    return q[1] + sl.slope_at(j, q[1]) * (j - q[0]), fit


def _track_along(sl: _Slice, j0: int, t0: float, opt: _Options, faults: _FaultIndex, line_point):
    """Track from (j0, t0) to both ends of a slice. ``line_point(j, t)`` maps a slice position to the fault index's
    coordinates. Returns (times, confidence), NaN where empty / unreached."""
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
        crossed: set = set(on_seed)  # the faults this direction has crossed (see _FaultIndex.jump)
        while 0 <= c + direction < n:
            j = int(np.clip(c + direction * opt.step, 0, n - 1))
            pc = sl.slope_at(c, tc)
            span = (max(min(c, j) - hw, 0), min(max(c, j) + hw, n - 1))
            block = faults.block(line_point, n, c, tc, pc, *span)
            edge = block[0] if direction < 0 else block[1]
            if edge != (span[0] if direction < 0 else span[1]):
                # A fault between trace `edge` and the next. A step ending within _FAULT_ZONE traces of it, where drag
                # bends the reflectors towards the fault, is carried on over the zone, to the next trace of the step
                # grid (seed + multiples of `step`), so that a fault does not move where later steps fall.
                at = edge + 0.5 * direction
                while abs(j - at) < _FAULT_ZONE and 0 <= j + direction * opt.step < n:
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
                score = _ncc(reference, wave)
                conf[jj] = score
                if np.isfinite(tt) and np.isfinite(score) and score >= opt.min_confidence:
                    times[jj] = tt
                    if np.isfinite(wave).all():
                        reference = (1 - _REFERENCE_WEIGHT) * reference + _REFERENCE_WEIGHT * wave
            c, tc = j, carried
            if not (0 <= tc < sl.n_samples):
                break
    return times, conf


# --------------------------------------------------------------------------------------------------------------------
# Carrying picks from one slice to the next.

def _slice_matches(a: _Slice, b: _Slice, rows: tuple[int, int], method):
    """Feature matches between two slices' images (traces along x, samples along y), restricted to a band of rows;
    returned as ((K, 2), (K, 2)) (trace, sample) arrays, or None."""
    if method is None:
        return None
    from ..features import lift_matches_section, match_images

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


def _carry(src: _Slice, dst: _Slice, times: np.ndarray, opt: _Options, faults: _FaultIndex, point_pair,
           matches, panel: int, crossed: list):
    """Carry the carried positions ``times`` (n_traces,) of ``src`` onto ``dst``. Returns (out, carried, conf):
    snapped confident picks (NaN elsewhere), positions to carry on from, confidence. ``crossed[x]`` is the set of
    faults trace ``x`` has already crossed in this pass (updated; see :meth:`_FaultIndex.jump`)."""
    n = src.n_traces
    out = np.full(n, np.nan)
    carried = np.full(n, np.nan)
    conf = np.full(n, np.nan)
    have = np.isfinite(times)
    if not have.any():
        return out, carried, conf
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
        m, fit = _register(src_pts, dst_pts, dst_nrm, np.eye(3), opt.model, feats)
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
            score = _ncc(src.window(x, t), dst.window(x, anchor))
            conf[x] = score
            carried[x] = anchor
            if np.isfinite(tt) and np.isfinite(score) and score >= opt.min_confidence:
                out[x] = tt
    _despike(dst, out, carried, conf, opt, faults, lambda x, t: point_pair(x, t, t)[1])
    return out, carried, conf


def _despike(sl: _Slice, out: np.ndarray, carried: np.ndarray, conf: np.ndarray, opt: _Options,
             faults: _FaultIndex, line_point, reach: int = 2, agree: float = 2.0) -> int:
    """Lateral continuity check of one carried slice (in place); returns the number of picks changed.

    The carry moves every trace on its own, so a pick that snapped to the neighbouring cycle is carried on, trace
    for trace, through all later slices: a streak across the cube while the traces beside it are right. A pick is
    such a spike when the nearest picks on both sides (within ``reach`` traces) agree with each other within
    ``agree`` samples and it lies more than ``agree`` samples from their interpolation. It is re-snapped at that
    interpolation (within ``agree``) when the waveform there correlates with the two sides at least
    ``min_confidence``, else left empty and carried on from the interpolation. A fault between the sides (fault
    input), or a step between them (sides that disagree: a discontinuity), leaves the pick alone.
    """
    n = sl.n_traces
    before = out.copy()  # every decision on the slice as carried, so one correction cannot set off the next
    have = np.isfinite(before)
    changed = 0
    for x in np.nonzero(have)[0]:
        left = [u for u in range(x - 1, x - reach - 1, -1) if 0 <= u and have[u]][:1]
        right = [u for u in range(x + 1, x + reach + 1) if u < n and have[u]][:1]
        if not left or not right:
            continue
        a, b = left[0], right[0]
        ta, tb = before[a], before[b]
        if abs(ta - tb) > agree:
            continue
        pred = ta + (tb - ta) * (x - a) / (b - a)
        if abs(before[x] - pred) <= agree:
            continue
        if faults.jump(line_point(a, ta), line_point(b, tb)) != 0.0:
            continue
        t = sl.snap(x, pred, agree)
        score = np.nan
        if np.isfinite(t):
            wave = sl.window(x, t)
            score = min(_ncc(wave, sl.window(a, ta)), _ncc(wave, sl.window(b, tb)))
        if np.isfinite(score) and score >= opt.min_confidence:
            out[x], carried[x], conf[x] = t, t, score
        else:
            out[x], carried[x], conf[x] = np.nan, pred, score
        changed += 1
    return changed


# --------------------------------------------------------------------------------------------------------------------
# Public API.

def _check_seeds(seeds, shape) -> np.ndarray:
    ndim = len(shape)
    arr = np.asarray(seeds, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != ndim or arr.shape[0] == 0:
        names = "(inline, xline, sample)" if ndim == 3 else "(trace, sample)"
        raise InputError(f"seeds must be one or more {names} index triples for data of shape {shape}; got "
                         f"{np.asarray(seeds).shape}")
    if not np.isfinite(arr).all():
        raise InputError("seeds must be finite index positions")
    for s in arr:
        for axis, (v, size) in enumerate(zip(s, shape)):
            limit = size - 1
            if not (0 <= v <= limit):
                raise InputError(f"seed {tuple(float(x) for x in s)} lies outside the data: axis {axis} index {v} is "
                                 f"not in [0, {limit}]; give seeds in index space inside the cube (the CLI converts "
                                 "inline, xline and time for you)")
    return arr


def _check_live(data: np.ndarray, seed: np.ndarray) -> None:
    trace = data[tuple(int(round(v)) for v in seed[:-1])]
    if np.ptp(trace) == 0:
        raise InputError(f"seed {tuple(float(x) for x in seed)} is on a dead trace (all samples equal {trace[0]}); "
                         "move the seed to a live trace")


def track_horizon(data, seeds, *, polarity: str = "peak", faults=None, model: str = "rigid",
                  half_traces: int = 10, half_samples: float = 20.0, step: int = 4, snap: float = 3.0,
                  min_confidence: float = 0.3, max_throw: int = 10, features: str | None = "hog",
                  panel_traces: int = 64, sigma_tensor=(2.0, 2.0), progress: bool = False) -> Horizon:
    """Track a horizon from seed picks by registering neighbouring slices (module docstring).

    In 2D the horizon is tracked along the section from each seed. In 3D it is tracked along each seed's inline,
    then carried inline by inline to both ends of the cube with the fused ICP; a trace the carry leaves empty is
    kept at its predicted position for the next inline, so a gap does not stop the horizon. A last pass fills
    empty traces from their tracked neighbours along inlines and crosslines where they agree and correlate (module
    docstring, step 3).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, zero-mean, the last axis the sample. Must be finite.
    seeds : (ndim,) or (n_seeds, ndim) array_like of float
        Seed picks in index space: ``(inline, xline, sample)`` (3D) or ``(trace, sample)`` (2D). Each is snapped
        to the nearest extremum of ``polarity`` within 5 samples. Later seeds fill only traces the earlier
        ones left empty.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        Which event the horizon follows (see :func:`reflector_picks`).
    faults : FaultInterpretation, optional
        Faults of the same ``data`` from :func:`seismo3d.seismic.trace_faults`: steps that cross one jump by its
        throw. Faults whose throw correlates less than 0.5 across them (median of ``FaultThrow.correlation``), or
        that have no throw, are not used. A seed on a traced fault steps off it into the wall its waveform matches
        (module docstring). Without it, discontinuities are found by the registration (panels that do not fit).
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
        Transform family of the panel registrations (2D). 'axis_scaled' allows per-axis scale (layers that thicken)
        but its vertical scale can slide a band that reaches the top or bottom of the data by one cycle (seen on a
        synthetic section), so the default is 'rigid'.
    half_traces : int
        Half-width of a panel along the slice, traces (source and target panels hold 2 * half_traces + 1 traces).
    half_samples : float
        Half-height of the band of reflector points around the horizon, samples.
    step : int
        Traces between two registrations along a slice.
    snap : float
        Largest distance, samples, from the carried position to the extremum it snaps to.
    min_confidence : float
        Picks whose waveform correlation with the pick they came from is below this are left empty.
    max_throw : int
        Largest shift, samples, searched when a discontinuity is found without fault input.
    features : {'hog', 'sift'} or None
        Feature matches between neighbouring inlines for the fused ICP (3D only); None: point-to-plane only.
    panel_traces : int
        Width, traces, of the panels registered between neighbouring inlines (3D).
    sigma_tensor : (float, float)
        Smoothing (traces, samples) of the structure tensor that gives the reflector normals and slopes.
    progress : bool
        Show a tqdm progress bar over inlines (3D).

    Returns
    -------
    Horizon
        ``times`` (n_inlines, n_xlines) or (n_traces,) float32 fractional samples, NaN where empty, and
        ``confidence``.

    Raises
    ------
    InputError
        ``data`` is not a finite 2D / 3D numeric array; a seed is outside the data, on a dead trace, or has no
        extremum of ``polarity`` within 5 samples; an option is out of range.

    References
    ----------
    .. [1] method.md section 6 (seismic tracks) and eq. 16 (fused ICP); the paper's "reconstruction of seismic
       tracks in a three-dimensional seismic cube".
    .. [2] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013 (throw as the jump across a fault).
    """
    code = _check_polarity(polarity)
    arr = _as_seismic(data)
    seeds = _check_seeds(seeds, arr.shape)
    check_choice(model, "model", ("rigid", "similarity", "axis_scaled", "affine"))
    if features is not None:
        check_choice(features, "features", ("hog", "sift"))
    for name, v in (("half_traces", half_traces), ("step", step), ("max_throw", max_throw),
                    ("panel_traces", panel_traces)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise InputError(f"{name} must be an int >= 1; got {v!r}")
    check_positive(half_samples, "half_samples")
    check_positive(snap, "snap")
    if not -1.0 <= min_confidence <= 1.0:
        raise InputError(f"min_confidence is a correlation in [-1, 1]; got {min_confidence}")
    opt = _Options(model, int(half_traces), float(half_samples), int(step), float(snap), float(min_confidence),
                   int(max_throw), 0.3)
    fidx = _FaultIndex.from_interpretation(faults, arr.ndim)
    for s in seeds:
        _check_live(arr, s)
    if arr.ndim == 2:
        return _track_2d(arr, seeds, code, polarity, opt, fidx, sigma_tensor)
    return _track_3d(arr, seeds, code, polarity, opt, fidx, sigma_tensor, features, int(panel_traces), progress)


def _snap_seed(sl: _Slice, j: int, t: float, window: float, seed) -> float:
    t0 = sl.snap(j, t, window)
    if not np.isfinite(t0):
        raise InputError(f"seed {tuple(float(x) for x in seed)} has no reflector pick of the requested polarity within "
                         f"{window} samples; move it onto the event or choose another polarity")
    return t0


def _track_2d(arr, seeds, code, polarity, opt, fidx, sigma_tensor) -> Horizon:
    sl = _Slice(arr, code, sigma_tensor)
    times = np.full(sl.n_traces, np.nan)
    conf = np.full(sl.n_traces, np.nan)
    for s in seeds:
        j0 = int(round(s[0]))
        t0 = _snap_seed(sl, j0, s[1], _SEED_SNAP, s)
        t, c = _track_along(sl, j0, t0, opt, fidx, lambda j, t: np.array([j, t], np.float64))
        fill = ~np.isfinite(times)
        times[fill], conf[fill] = t[fill], c[fill]
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)


def _track_3d(arr, seeds, code, polarity, opt, fidx, sigma_tensor, features, panel, progress) -> Horizon:
    from tqdm.auto import tqdm

    n_il, n_xl, n_s = arr.shape
    times = np.full((n_il, n_xl), np.nan)
    conf = np.full((n_il, n_xl), np.nan)
    cache: dict[int, _Slice] = {}

    def slice_(i):
        if i not in cache:
            if len(cache) > 2:
                cache.pop(next(iter(cache)))
            cache[i] = _Slice(arr[i], code, sigma_tensor)
        return cache[i]

    total = len(seeds) * n_il
    with tqdm(total=total, desc="horizon", unit="inline", disable=not progress) as bar:
        for s in seeds:
            i0 = int(round(s[0]))
            sl = slice_(i0)
            j0 = int(round(s[1]))
            t0 = _snap_seed(sl, j0, s[2], _SEED_SNAP, s)
            t_line, c_line = _track_along(sl, j0, t0, opt, fidx,
                                          lambda j, t, i=i0: np.array([i, j, t], np.float64))
            new_t = np.full((n_il, n_xl), np.nan)
            new_c = np.full((n_il, n_xl), np.nan)
            new_t[i0], new_c[i0] = t_line, c_line
            bar.update(1)
            # carry on from the tracked picks, and from predicted positions where the along-line pick was empty
            start = t_line.copy()
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
                    matches = _slice_matches(a, b, rows, features)
                    out, carried, c = _carry(
                        a, b, carried, opt, fidx,
                        lambda x, t, g, i0_=prev, i1_=i: (np.array([i0_, x, t], np.float64),
                                                           np.array([i1_, x, g], np.float64)),
                        matches, panel, crossed)
                    new_t[i], new_c[i] = out, c
                    prev = i
                    bar.update(1)
            fill = ~np.isfinite(times)
            times[fill], conf[fill] = new_t[fill], new_c[fill]
    _close_gaps(arr, code, times, conf, opt, fidx)
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)


def _close_gaps(arr, code, times, conf, opt, fidx, max_passes: int = 50) -> None:
    """Fill empty traces from their tracked neighbours (in place): the gap-closing pass of 3D tracking.

    A line-by-line carry leaves a trace empty where its own pick was unsure, and the inline order means a gap is
    never revisited from the crosslines. Here every empty trace next to tracked ones (4-neighbourhood, both
    directions) is predicted at its neighbours' times (plus the jump of a fault between them), snapped to the nearest
    same-polarity extremum within ``snap`` samples, and kept only when the neighbours agree (their snaps within one
    sample) and its waveform correlates with theirs at least ``min_confidence``; repeated until nothing changes (at
    most ``max_passes`` times).
    """
    n_il, n_xl = arr.shape[:2]
    picks: dict[int, tuple] = {}

    def snap(i, j, t):
        if i not in picks:
            picks[i] = _section_picks(arr[i].astype(np.float64), code)
        return _nearest_pick(*picks[i], j, t, opt.snap)

    steps = ((1, 0), (-1, 0), (0, 1), (0, -1))
    for _ in range(max_passes):
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
                    score.append(_ncc(_waveform(arr[i, j], t), _waveform(arr[a, b], times[a, b])))
            if not cand or np.ptp(cand) > 1.0:
                continue
            c = float(np.nanmin(score)) if np.isfinite(score).any() else np.nan
            if c >= opt.min_confidence:
                times[i, j], conf[i, j] = float(np.median(cand)), c
                added += 1
        if not added:
            break


def autotrack(data, seed, *, polarity: str = "peak", window: int = 3) -> Horizon:
    """Plain amplitude autotracker: follow the same-polarity extremum trace by trace (the peer of
    :func:`track_horizon`).

    From the seed, each neighbouring trace (4-neighbours in 3D, in breadth-first order) takes the extremum of
    ``polarity`` nearest to its neighbour's pick within ``+-window`` samples; a trace with none is left empty and
    the search does not continue through it. This is the seeded autotracking of interpretation software, without
    any registration.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, zero-mean. Must be finite.
    seed : (ndim,) array_like of float
        Seed pick in index space, snapped to the nearest extremum within ``window`` samples.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
    window : int
        Search half-window, samples.

    Returns
    -------
    Horizon
        ``times`` float32 fractional samples (NaN where empty), ``confidence`` 1 where picked.

    Raises
    ------
    InputError
        Bad ``data``, a seed outside the data, on a dead trace or with no extremum within ``window``.
    """
    from collections import deque

    code = _check_polarity(polarity)
    arr = _as_seismic(data)
    seeds = _check_seeds(seed, arr.shape)
    if len(seeds) != 1:
        raise InputError(f"autotrack takes one seed; got {len(seeds)}")
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1:
        raise InputError(f"window must be an int >= 1; got {window!r}")
    _check_live(arr, seeds[0])
    lat = arr.shape[:-1]
    flat = np.ascontiguousarray(arr.reshape(-1, arr.shape[-1]), dtype=np.float64)
    picks, offsets = _section_picks(flat, code)
    times = np.full(lat, np.nan)

    def snap(k, t):
        return _nearest_pick(picks, offsets, k, t, window)

    start = tuple(int(round(v)) for v in seeds[0][:-1])
    t0 = snap(int(np.ravel_multi_index(start, lat)), seeds[0][-1])
    if not np.isfinite(t0):
        raise InputError(f"seed {tuple(seeds[0])} has no {polarity} within {window} samples; move it onto the event")
    times[start] = t0
    queue = deque([start])
    steps = [(1,), (-1,)] if len(lat) == 1 else [(1, 0), (-1, 0), (0, 1), (0, -1)]
    while queue:
        p = queue.popleft()
        for d in steps:
            q = tuple(a + b for a, b in zip(p, d))
            if any(v < 0 or v >= s for v, s in zip(q, lat)) or np.isfinite(times[q]):
                continue
            t = snap(int(np.ravel_multi_index(q, lat)), times[p])
            if np.isfinite(t):
                times[q] = t
                queue.append(q)
    conf = np.where(np.isfinite(times), 1.0, np.nan)
    return Horizon(times.astype(np.float32), conf.astype(np.float32), polarity, seeds)


def fill_horizon(horizon: Horizon, *, max_gap: float | None = None) -> Horizon:
    """Fill the empty traces of a horizon by interpolation (an explicit step: :func:`track_horizon` never guesses).

    1D horizons are interpolated linearly between picks; 2D grids by linear interpolation over a Delaunay
    triangulation of the picked traces (scipy.interpolate.griddata), without extrapolation beyond their convex
    hull. Filled traces get confidence NaN.

    Parameters
    ----------
    horizon : Horizon
    max_gap : float, optional
        Fill only traces within this distance (traces) of a pick; default: all inside the hull.

    Returns
    -------
    Horizon
        A new horizon; the input is not modified.

    Raises
    ------
    InputError
        Fewer than 2 (1D) or 3 (2D) picks to interpolate from, or ``max_gap`` <= 0.
    """
    from scipy.interpolate import griddata
    from scipy.ndimage import distance_transform_edt

    t = horizon.times.astype(np.float64)
    have = np.isfinite(t)
    need = 2 if t.ndim == 1 else 3
    if have.sum() < need:
        raise InputError(f"the horizon has {int(have.sum())} picks; at least {need} are needed to interpolate")
    if max_gap is not None:
        check_positive(max_gap, "max_gap")
    if t.ndim == 1:
        x = np.arange(t.size)
        filled = np.interp(x, x[have], t[have], left=np.nan, right=np.nan)
    else:
        grid = np.indices(t.shape).reshape(t.ndim, -1).T.astype(np.float64)
        filled = griddata(grid[have.ravel()], t[have], grid, method="linear").reshape(t.shape)
    if max_gap is not None:
        far = distance_transform_edt(~have) > max_gap
        filled[far & ~have] = np.nan
    filled[have] = t[have]
    conf = np.where(have, horizon.confidence, np.nan)
    return Horizon(filled.astype(np.float32), conf.astype(np.float32), horizon.polarity, horizon.seeds)


def horizon_errors(times, reference) -> dict:
    """Compare tracked horizon times with reference picks (e.g. an interpreter's), in samples.

    Parameters
    ----------
    times, reference : array_like of float, same shape
        Horizon times in samples; NaN (or negative, in ``reference``) where absent. Traces without a reference
        pick are not counted; traces with a reference pick but no tracked pick count as misses.

    Returns
    -------
    dict
        ``n`` (traces with a reference pick), ``coverage`` (fraction of them tracked), ``median_abs`` (median
        absolute error over tracked traces, samples), ``within_2`` and ``within_5`` (fraction of the ``n`` traces
        tracked within 2 and 5 samples; misses count as failures).

    Raises
    ------
    InputError
        Shapes differ.
    """
    t = np.asarray(times, np.float64)
    r = np.asarray(reference, np.float64)
    if t.shape != r.shape:
        raise InputError(f"times {t.shape} and reference {r.shape} must have the same shape")
    ref_ok = np.isfinite(r) & (r >= 0)
    n = int(ref_ok.sum())
    err = np.abs(t[ref_ok] - r[ref_ok])
    tracked = np.isfinite(err)
    return {
        "n": n,
        "coverage": float(tracked.mean()) if n else np.nan,
        "median_abs": float(np.median(err[tracked])) if tracked.any() else np.nan,
        "within_2": float(np.mean(np.where(tracked, err, np.inf) <= 2)) if n else np.nan,
        "within_5": float(np.mean(np.where(tracked, err, np.inf) <= 5)) if n else np.nan,
    }


def write_horizon_text(path, horizon: Horizon, *, inlines=None, xlines=None, samples=None) -> int:
    """Write a horizon as "inline xline time" rows, one per picked trace (empty traces are skipped).

    The file is written atomically (a temporary file renamed over ``path``).

    Parameters
    ----------
    path : str or path-like
        Output text file.
    horizon : Horizon
        A 3D horizon (``times`` of shape (n_inlines, n_xlines)) or a 2D one ((n_traces,): rows are "trace time").
    inlines, xlines : (n_inlines,), (n_xlines,) array_like of int, optional
        Inline and crossline numbers of the grid (e.g. ``SeismicCube.inlines``); default: indices.
    samples : (n_samples,) array_like of float, optional
        The sample axis in ms or m (``SeismicCube.samples``); fractional sample indices are converted by linear
        interpolation. Default: sample indices.

    Returns
    -------
    int
        Number of rows written.

    Raises
    ------
    InputError
        Axis lengths do not match the horizon's grid.
    """
    from .._atomic import atomic_path

    t = np.asarray(horizon.times, np.float64)
    grid = np.indices(t.shape).reshape(t.ndim, -1).T
    have = np.isfinite(t).ravel()
    cols = []
    for axis, labels in enumerate((inlines, xlines)[:t.ndim]):
        if labels is None:
            cols.append(grid[have, axis])
            continue
        labels = np.asarray(labels)
        if labels.shape != (t.shape[axis],):
            raise InputError(f"axis {axis} has {t.shape[axis]} traces but {labels.shape} labels were given")
        cols.append(labels[grid[have, axis]])
    tv = t.ravel()[have]
    if samples is not None:
        s = np.asarray(samples, np.float64)
        if s.ndim != 1 or s.size < 2:
            raise InputError(f"samples must be the 1D sample axis of the cube; got shape {s.shape}")
        tv = np.interp(tv, np.arange(s.size), s, left=np.nan, right=np.nan)
    with atomic_path(path) as tmp:
        with open(tmp, "w") as fh:
            header = "inline xline time" if t.ndim == 2 else "trace time"
            fh.write(f"# {header}\n")
            for row in zip(*cols, tv):
                fh.write(" ".join(str(int(v)) for v in row[:-1]) + f" {row[-1]:.3f}\n")
    return int(have.sum())
