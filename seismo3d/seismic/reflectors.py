"""Reflectors along traces: same-polarity picks with sub-sample positions, and reflector points with normals.

One peak picker serves horizon tracking (:func:`reflector_picks`: every extremum of a polarity, trace by trace) and
volume registration (:func:`reflector_points`: the strong, planar peaks of a cube as a point cloud with
structure-tensor normals). A peak is a sample above zero and above its predecessor, followed by a lower sample;
on a clipped plateau (equal samples, as in 8-bit exports) the pick is the plateau's centre, and an isolated extremum
is refined by the vertex of the parabola through it and its two neighbours (:func:`~seismo3d.seismic.traces.
parabolic_offset`).

Conventions: the last axis is the sample (downward); positions are fractional sample indices.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy import ndimage as ndi

from .._validation import as_seismic, check_choice
from ..errors import InputError
from .attributes import structure_tensor_orientation
from .traces import parabolic_offset, waveform

__all__ = ["POLARITIES", "ReflectorSlice", "reflector_picks", "nearest_pick", "nearest_reflector", "reflector_points",
           "normalise_amplitudes"]

POLARITIES = ("peak", "trough", "zero_rising", "zero_falling")
_POLARITY_CODE = {"peak": 0, "trough": 1, "zero_rising": 2, "zero_falling": 3}


_CHUNK = 1 << 20  # samples of a section handled at once by _section_picks


def _section_picks(sec, code, plateau_start):
    """Picks of every trace of ``sec`` (n_traces, n_samples float64): ``(positions, refine, offsets)``, the picks of
    trace ``j`` at ``offsets[j]:offsets[j + 1]`` in sample order.

    A peak (trough: of the negated trace) starts at a sample above zero and above its predecessor (not the trace's
    first or last sample) and runs over the equal samples after it; it is a pick where a lower sample follows: at its
    centre on a clipped plateau (or, with ``plateau_start``, at each such start that the next sample does not exceed,
    refined like an isolated extremum), at its sample with ``refine`` set when isolated (the parabola is applied
    afterwards, by :func:`parabolic_offset`). Zero crossings are interpolated linearly. Array work in numpy, the
    traces in chunks of about :data:`_CHUNK` samples (the compiled loops it replaces cost the horizon's first run 1
    CPU s of compiling)."""
    n_tr, n_s = sec.shape
    positions, flags, counts = [], [], []
    step = max(1, _CHUNK // max(n_s, 1))
    for lo in range(0, n_tr, step):
        a = sec[lo:lo + step]
        if code >= 2:
            y0, y1 = a[:, :-1], a[:, 1:]
            hit = (y0 < 0.0) & (0.0 <= y1) if code == 2 else (y0 > 0.0) & (0.0 >= y1)
            row, i = np.nonzero(hit)
            y0, y1 = y0[row, i], y1[row, i]
            pos = i + y0 / np.where(y0 != y1, y0 - y1, 1.0)
            pos = np.where(y0 != y1, pos, i)
            refine = np.zeros(i.size, np.bool_)
        else:
            y = a if code == 0 else -a
            start = np.zeros(y.shape, np.bool_)
            start[:, 1:-1] = (y[:, 1:-1] > 0.0) & (y[:, 1:-1] > y[:, :-2])
            if plateau_start:
                start[:, 1:-1] &= y[:, 1:-1] >= y[:, 2:]
                row, i = np.nonzero(start)
                pos, refine = i.astype(np.float64), np.ones(i.size, np.bool_)
            else:
                # the end of each run of equal samples: the sample before the next run's first (or the trace's last)
                new_run = np.ones(y.shape, np.bool_)
                new_run[:, 1:] = y[:, 1:] != y[:, :-1]
                flat_start = np.flatnonzero(new_run.ravel())
                run_end = np.append(flat_start[1:], y.size) - 1  # flat index of each run's last sample
                row, i = np.nonzero(start)
                j = run_end[np.searchsorted(flat_start, row * n_s + i, side="right") - 1] - row * n_s
                after = np.minimum(j + 1, n_s - 1)
                ok = (j + 1 < n_s) & (y[row, after] < y[row, i])
                row, i, j = row[ok], i[ok], j[ok]
                pos = np.where(j > i, 0.5 * (i + j), i)
                refine = j == i
        positions.append(pos.astype(np.float64))
        flags.append(refine)
        counts.append(np.bincount(row, minlength=a.shape[0]))
    offsets = np.zeros(n_tr + 1, np.int64)
    if counts:
        offsets[1:] = np.cumsum(np.concatenate(counts))
    if not positions:
        return np.zeros(0), np.zeros(0, np.bool_), offsets
    return np.concatenate(positions), np.concatenate(flags), offsets


def _picks(values: np.ndarray, code: int) -> tuple[np.ndarray, np.ndarray]:
    """Picks of every trace of ``values`` (n_traces, n_samples), any float dtype: (positions, offsets). The parabola
    of isolated extrema is computed in ``values``' dtype."""
    pos, refine, offsets = _section_picks(np.ascontiguousarray(values, dtype=np.float64), code, False)
    if refine.any():
        trace = np.repeat(np.arange(values.shape[0]), np.diff(offsets))[refine]
        k = pos[refine].astype(np.intp)
        sgn = 1 if code == 0 else -1
        pos[refine] = k + parabolic_offset(sgn * values[trace, k - 1], sgn * values[trace, k],
                                           sgn * values[trace, k + 1])
    return pos, offsets


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

    References
    ----------
    .. [1] J. O. Smith, "Spectral Audio Signal Processing", W3K Publishing, 2011 (quadratic interpolation of peaks).
    """
    code = _POLARITY_CODE[check_choice(polarity, "polarity", POLARITIES)]
    sec = np.asarray(section)
    if sec.ndim != 2 or sec.shape[1] < 3:
        raise InputError(f"section must be 2D (n_traces, n_samples) with at least 3 samples; got shape {sec.shape}")
    sec = as_seismic(sec, "section", min_size=1)
    return _picks(sec.astype(np.float64), code)


def nearest_pick(times: np.ndarray, offsets: np.ndarray, trace: int, t: float, window: float) -> float:
    """The pick of one trace nearest to ``t`` within ``window`` samples, else NaN.

    Parameters
    ----------
    times, offsets : ndarray
        Picks of a section, as :func:`reflector_picks` returns them.
    trace : int
        Trace index.
    t : float
        Position searched from, fractional samples (NaN gives NaN).
    window : float
        Largest distance, samples.

    Returns
    -------
    float
        The pick's position, or NaN.
    """
    p = times[offsets[trace]:offsets[trace + 1]]
    if p.size == 0 or not np.isfinite(t):
        return np.nan
    i = int(np.argmin(np.abs(p - t)))
    return float(p[i]) if abs(p[i] - t) <= window else np.nan


def nearest_reflector(times: np.ndarray, offsets: np.ndarray, lateral_shape: tuple, position) -> tuple | None:
    """The pick nearest to ``position`` with no distance limit: on its own trace the pick nearest in time; when that
    trace has none, the nearest trace that has picks (lateral distance, in traces), and its pick nearest in time.

    Parameters
    ----------
    times, offsets : ndarray
        Picks of the traces (lateral axes flattened in C order), as :func:`reflector_picks` returns them.
    lateral_shape : tuple of int
        ``(n_traces,)`` or ``(n_inlines, n_xlines)``.
    position : sequence of float
        Index position, the lateral indices then the fractional sample.

    Returns
    -------
    tuple of float or None
        The pick's index position (same axes as ``position``), or None when no trace has a pick.
    """
    lateral = np.asarray(position[:-1], dtype=np.float64)
    counts = np.diff(offsets)
    k = int(np.ravel_multi_index(tuple(int(round(v)) for v in lateral), lateral_shape))
    if counts[k] == 0:
        have = np.flatnonzero(counts > 0)
        if have.size == 0:
            return None
        where = np.column_stack(np.unravel_index(have, lateral_shape))
        k = int(have[np.argmin(((where - lateral) ** 2).sum(axis=1))])
    p = times[offsets[k]:offsets[k + 1]]
    t = float(p[np.argmin(np.abs(p - float(position[-1])))])
    return tuple(float(v) for v in np.unravel_index(k, lateral_shape)) + (t,)


class ReflectorSlice:
    """A 2D slice (n_traces, n_samples) with its reflector picks, slopes and reflector-point normals: what horizon
    tracking registers.

    Parameters
    ----------
    amp : (n_traces, n_samples) array_like
        Amplitudes of the slice (an inline of a cube, or a 2D section), zero-mean; finite.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The picks' polarity (:func:`reflector_picks`).
    sigma_tensor : (float, float)
        Smoothing (traces, samples) of the structure tensor that gives the slopes and normals.
    window_half : int
        Half-length, samples, of the waveform windows of :meth:`window`.

    Attributes
    ----------
    amp : (n_traces, n_samples) float32 ndarray
    slope : (n_traces, n_samples) float32 ndarray
        Reflector slope, samples per trace (the structure tensor is computed when ``slope`` or ``normals`` is first
        read).
    t, offsets : ndarray
        The picks, as :func:`reflector_picks` returns them.
    x : (n_picks,) float64 ndarray
        Trace index of each pick.
    normals : (n_picks, 2) float64 ndarray
        Unit reflector normal (trace, sample) at each pick.
    """

    def __init__(self, amp, polarity: str, sigma_tensor, window_half: int = 8):
        self.amp = np.ascontiguousarray(amp, dtype=np.float32)
        self.n_traces, self.n_samples = self.amp.shape
        self.window_half = int(window_half)
        self.sigma_tensor = sigma_tensor
        self.t, self.offsets = reflector_picks(self.amp, polarity=polarity)
        self.x = np.repeat(np.arange(self.n_traces, dtype=np.float64), np.diff(self.offsets))

    @functools.cached_property
    def _orientation(self):
        # the structure tensor, computed when slopes or normals are first read (the lateral check reads neither)
        return structure_tensor_orientation(self.amp, sigma_tensor=self.sigma_tensor)

    @functools.cached_property
    def slope(self) -> np.ndarray:
        return self._orientation.slopes[0]

    @functools.cached_property
    def normals(self) -> np.ndarray:
        ti = np.clip(np.rint(self.t).astype(np.intp), 0, self.n_samples - 1)
        return self._orientation.normals[self.x.astype(np.intp), ti].astype(np.float64)

    def slope_at(self, j: int, t: float) -> float:
        """Reflector slope (samples per trace) at trace ``j``, sample ``t`` (rounded, clipped to the slice)."""
        return float(self.slope[j, int(np.clip(round(t), 0, self.n_samples - 1))])

    def snap(self, j: int, t: float, window: float) -> float:
        """Nearest pick of trace ``j`` within ``window`` samples of ``t``, else NaN (:func:`nearest_pick`)."""
        return nearest_pick(self.t, self.offsets, j, t, window)

    def band(self, lo: int, hi: int, ref, half: float) -> tuple[np.ndarray, np.ndarray]:
        """Reflector points ((n, 2) trace, sample) and their normals of traces lo..hi (inclusive) within ``half``
        samples of ``ref[x - lo]``."""
        a, b = self.offsets[lo], self.offsets[hi + 1]
        x, t = self.x[a:b], self.t[a:b]
        keep = np.abs(t - ref[(x - lo).astype(np.intp)]) <= half
        return np.column_stack([x[keep], t[keep]]), self.normals[a:b][keep]

    def window(self, j: int, t: float, half: int | None = None) -> np.ndarray:
        """Amplitudes of trace ``j`` at ``t - half .. t + half`` (default ``window_half``; linear interpolation, NaN
        outside; :func:`~seismo3d.seismic.traces.waveform`)."""
        return waveform(self.amp[j], t, self.window_half if half is None else half)


def normalise_amplitudes(volume, name: str = "volume") -> np.ndarray:
    """Zero-median, unit robust-spread amplitudes of a cube (the spread from its live traces).

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) ndarray
        Finite amplitudes.
    name : str
        The argument's name, for messages.

    Returns
    -------
    (n_inlines, n_xlines, n_samples) float32 ndarray
        ``(volume - median) / spread``, the spread the 75th percentile of the absolute deviation divided by 1.15 (the
        standard deviation of a Gaussian), over live traces (those not constant).

    Raises
    ------
    InputError
        Fewer than 5 % live traces, or no amplitude variation on them.
    """
    v = volume
    live = np.ptp(v, axis=2) > 0
    if live.mean() < 0.05:
        raise InputError(f"{name} is constant or has fewer than 5 % live traces ({int(live.sum())} of {live.size}); "
                         "check that it holds seismic amplitudes (dead or padded region?)")
    vals = v[live]
    med = float(np.median(vals))
    spread = float(np.percentile(np.abs(vals - med), 75)) / 1.15  # sigma of a Gaussian
    if not spread > 0:
        spread = float(np.std(vals))
    if not spread > 0:
        raise InputError(f"{name} has no amplitude variation on its live traces; check the data")
    return ((v - med) / spread).astype(np.float32)


def reflector_points(data, *, quantile: float = 0.5, min_planarity: float = 0.5, max_points: int | None = None,
                     seed: int = 0, normalise: bool = True):
    """Reflector points of a seismic cube: strong amplitude peaks along each trace, with structure-tensor normals.

    A point is a peak of the amplitude along the trace (one polarity: peaks; the picker of :func:`reflector_picks`,
    except that a plateau counts at its first sample, refined by the parabola like any peak: half a sample in),
    refined to sub-sample precision by the vertex of the parabola through the sample and its two neighbours, kept
    where its amplitude is above the ``quantile`` of all peak amplitudes and the reflector planarity (from the
    structure tensor, :func:`~seismo3d.seismic.structure_tensor_orientation`) is at least ``min_planarity``. The
    amplitudes are first normalised (:func:`normalise_amplitudes`) and smoothed along the trace by a Gaussian of 1
    sample, which rounds the plateaus of clipped data.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) array_like
        Seismic amplitudes, any real dtype; finite; at least 8 samples along every axis.
    quantile : float in [0, 1)
        Fraction of the weakest peaks dropped.
    min_planarity : float in [0, 1]
        Smallest structure-tensor planarity kept (near 1 on clean reflectors, low at faults and in noise).
    max_points : int, optional
        Keep at most this many points (a uniform random subset, fixed by ``seed``).
    seed : int
        Seed of the subset.
    normalise : bool
        False when ``data`` is already normalised (float32, as :func:`normalise_amplitudes` returns it; the volume
        registration passes it so).

    Returns
    -------
    points : (N, 3) float64 ndarray
        Index coordinates (inline, crossline, sample), the sample coordinate fractional.
    normals : (N, 3) float64 ndarray
        Unit reflector normals in index space, pointing down (positive sample component).

    Raises
    ------
    InputError
        If ``data`` is not a finite 3D array of at least 8 samples per axis, or an option is out of range.

    References
    ----------
    Fehmers, G. C., Hoecker, C. F. W. (2003). Fast structural interpretation with structure-oriented filtering.
    Geophysics 68(4), 1286-1293. doi:10.1190/1.1598121
    """
    if normalise:
        if np.ndim(data) != 3:
            raise InputError(f"data must be a 3D cube (n_inlines, n_xlines, n_samples); got shape {np.shape(data)}")
        data = normalise_amplitudes(as_seismic(data, "data", min_size=8), "data")
    if not 0.0 <= float(quantile) < 1.0:
        raise InputError(f"quantile must be in [0, 1); got {quantile!r}")
    if not 0.0 <= float(min_planarity) <= 1.0:
        raise InputError(f"min_planarity must be in [0, 1]; got {min_planarity!r}")
    if max_points is not None and int(max_points) < 1:
        raise InputError(f"max_points must be >= 1 or None; got {max_points!r}")
    return _strong_planar_peaks(data, quantile, min_planarity, max_points, seed)


def _strong_planar_peaks(a, quantile, min_planarity, max_points, seed):
    s = ndi.gaussian_filter1d(a, 1.0, axis=2)
    n_tr = s.shape[0] * s.shape[1]
    flat = s.reshape(n_tr, s.shape[2])
    # peaks of the smoothed traces; a plateau (of clipped data that the smoothing left flat) counts at its first sample
    pos, refine, offsets = _section_picks(np.ascontiguousarray(flat, dtype=np.float64), 0, True)
    if pos.size == 0:
        return np.zeros((0, 3)), np.zeros((0, 3))
    trace = np.repeat(np.arange(n_tr), np.diff(offsets))
    k = np.floor(pos).astype(np.intp)  # the peak's (first plateau) sample
    amp = flat[trace, k]
    thr = np.quantile(amp, quantile)
    strong = amp > thr
    trace, k, pos, refine = trace[strong], k[strong], pos[strong], refine[strong]
    i, j = np.divmod(trace, s.shape[1])
    orient = structure_tensor_orientation(a)
    keep = orient.planarity[i, j, k] >= min_planarity
    i, j, k, pos, refine = i[keep], j[keep], k[keep], pos[keep], refine[keep]
    if max_points is not None and i.size > max_points:
        sel = np.sort(np.random.default_rng(seed).choice(i.size, int(max_points), replace=False))
        i, j, k, pos, refine = i[sel], j[sel], k[sel], pos[sel], refine[sel]
    frac = parabolic_offset(s[i, j, k - 1], s[i, j, k], s[i, j, k + 1])  # in the data's dtype (float32)
    points = np.column_stack([i, j, np.where(refine, k + frac, pos)]).astype(np.float64)
    normals = orient.normals[i, j, k].astype(np.float64)
    normals *= np.where(normals[:, 2:] < 0, -1.0, 1.0)
    return points, normals
