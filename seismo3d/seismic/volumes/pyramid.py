"""Decimated copies of the two volumes, coarse to fine, and the volume sampled through a transform.

The registration starts on the coarsest copies and ends at full resolution. A level keeps every ``factor``-th
inline, crossline and sample after a Gaussian smoothing of width ``factor / 2``. Along the traces, a level holds the
amplitudes while the smoothing keeps enough of their variance (``keep_amplitude``: a smooth property such as a
velocity keeps almost all of it at any level), else the envelope of the traces (instantaneous amplitude: smooth, so
a vertical misfit of a few samples does not flip the sign of the correlation) while it still varies
(``min_contrast``), else the smoothed amplitudes while a little of them is left (``min_amplitude``: the envelope of
heavily clipped amplitudes is flat); the samples are decimated no further than that, the traces may be. Both volumes
hold the same kind on each level.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import fft, ndimage as ndi

from ._spline import linear_values, spline_gradients, spline_values
from .model import homogeneous_diag

HIGH_FREQUENCY = 0.3  # cycles per sample: above it, a cubic spline interpolates poorly (Sampled.high_frequency)
GRADIENTS = ("central", "spline")

__all__ = ["Sampled", "Samples", "level_factors", "smoothing_measures", "level_kind", "build_level", "envelope",
           "live_traces", "to_level", "from_level", "without_mean_trace"]


def live_traces(volume) -> np.ndarray:
    """(n_inlines, n_xlines) bool: the traces that are not constant (dead or padded traces are)."""
    return np.ptp(volume, axis=2) > 0


def envelope(volume, live) -> np.ndarray:
    """Instantaneous amplitude along the traces (the modulus of the analytic signal, by the Hilbert transform in the
    Fourier domain), float32; dead traces hold the mean of the live ones (so that smoothing near them barely changes
    the live values)."""
    n = volume.shape[2]
    h = np.zeros(n)  # the analytic signal's spectrum: DC (and Nyquist) once, positive frequencies twice
    h[0] = 1.0
    if n % 2 == 0:
        h[n // 2] = 1.0
        h[1:n // 2] = 2.0
    else:
        h[1:(n + 1) // 2] = 2.0
    e = np.abs(fft.ifft(fft.fft(volume, axis=2) * h, axis=2)).astype(np.float32)
    e[~live] = e[live].mean()
    return e


def level_factors(shape, *, min_lateral: int, min_vertical: int, max_factor: int) -> tuple[int, int, int]:
    """Coarsest decimation factor of each axis, a power of 2 up to ``max_factor``, that keeps at least
    ``min_lateral`` traces along each map axis and ``min_vertical`` samples along the traces."""
    out = []
    for n, least in zip(shape, (min_lateral, min_lateral, min_vertical)):
        factor = 1
        while factor < max_factor and n / (2 * factor) >= least:
            factor *= 2
        out.append(factor)
    return tuple(out)


def smoothing_measures(volume, env, live, factor: int) -> tuple[float, float]:
    """What a Gaussian of width ``factor / 2`` samples along the traces leaves: the fraction of the amplitudes'
    variance it keeps, and the spread of the smoothed envelope over its mean (NaN without ``env``)."""
    if factor == 1:
        return 1.0, float("inf")
    amp = volume[live].astype(np.float64)
    kept = ndi.gaussian_filter1d(amp, factor / 2.0, axis=-1, mode="nearest").var() / max(amp.var(), 1e-12)
    if env is None:
        return float(kept), float("nan")
    smooth = ndi.gaussian_filter1d(env[live].astype(np.float64), factor / 2.0, axis=-1, mode="nearest")
    return float(kept), float(smooth.std() / max(abs(smooth.mean()), 1e-12))


def level_kind(measures, finer: str | None, *, keep_amplitude: float, min_contrast: float,
               min_amplitude: float) -> str | None:
    """What a level holds, the same for both volumes so that they are compared like with like.

    Parameters
    ----------
    measures : list of (float, float)
        Each volume's :func:`smoothing_measures` at its vertical factor on this level.
    finer : {'amplitude', 'envelope'} or None
        What the next finer level holds (None for the finest).
    keep_amplitude, min_contrast, min_amplitude : float
        ``'amplitude'`` while every volume keeps ``keep_amplitude`` of its variance (and the finer levels hold
        amplitudes); then ``'envelope'`` while every volume's envelope spreads ``min_contrast`` of its mean; else
        the smoothed amplitudes while every volume keeps ``min_amplitude`` of its variance (amplitudes clipped
        until their envelope is flat still have their low frequencies).

    Returns
    -------
    {'amplitude', 'envelope'} or None
        None when nothing holds: the samples are decimated no further.
    """
    kept = [k for k, _ in measures]
    if min(kept) >= keep_amplitude and finer in (None, "amplitude"):
        return "amplitude"
    if all(c >= min_contrast for _, c in measures):  # NaN (no envelope) fails
        return "envelope"
    if min(kept) >= min_amplitude and finer in (None, "amplitude"):
        return "amplitude"
    return None


@dataclass(frozen=True)
class Samples:
    """A volume sampled at points: weights, values and gradients."""

    weights: np.ndarray  # (N,) in [0, 1]: 0 outside the volume or on dead traces, tapered at its edges
    values: np.ndarray  # (N,) cubic B-spline interpolation
    gradients: np.ndarray | None  # (3, N) per index unit (None: not computed)


class Sampled:
    """One volume at one level: decimated data, live traces, and what sampling it at any point needs.

    Parameters
    ----------
    data : (n0, n1, n2) float32 ndarray
        The level's amplitudes (or envelope).
    live : (n0, n1) bool ndarray
    factors : (3,) int
        Full-resolution index = level index * factors.
    taper : float
        Samples: weights fall linearly from 1 at ``taper - 0.5`` samples inside the edge to 0 half a sample beyond it
        (and across dead traces), so that a correlation changes continuously as points enter or leave the volume.
    """

    def __init__(self, data, live, factors, taper: float):
        self.data = data
        self.live = live
        self.factors = np.asarray(factors, dtype=np.float64)
        self.taper = float(taper)
        self.shape = data.shape
        self.hi = np.array(data.shape, dtype=np.float64) - 1.0

    @cached_property
    def coefficients(self) -> np.ndarray:
        """Cubic B-spline coefficients of the data (mode 'mirror')."""
        return ndi.spline_filter(self.data, order=3, output=np.float32, mode="mirror")

    @cached_property
    def gradient_volumes(self) -> np.ndarray:
        """Central differences of the data along the three axes, (3, n0, n1, n2) float32. Smoother than the cubic
        B-spline's own derivative near the Nyquist frequency, they give the refinement steps that keep to the main
        correlation peak from a start on it: with the spline's derivative on every level, the f3_crop pair of
        ``benchmarks/volumes.py`` rotated 40 degrees with fixed bins 1.25 / 0.8 (FIXED onto MOVING) converged 49 % off
        in scale (the coarsest level, whose starts are further off, uses the spline's derivative:
        :func:`~seismo3d.seismic.volumes.registration._refine_starts`)."""
        return np.stack(np.gradient(self.data)).astype(np.float32)  # (3, n0, n1, n2)

    @cached_property
    def high_frequency(self) -> float:
        """How poorly the volume interpolates: the fraction of its power above ``HIGH_FREQUENCY`` cycles per sample,
        summed over the three axes (each axis's spectrum along it, live traces only along the traces). A volume
        with coarse bins (or resampled without a low-pass) is aliased and holds more (the Volve velocity copies of
        ``benchmarks/volumes.py``: 0.09-0.12 at the survey's own bins, 0.16-0.27 at 1.6 times them)."""
        return sum(_high_fraction(self.data, axis, self.live) for axis in range(3))

    @cached_property
    def live_weights(self) -> np.ndarray:
        """The live-trace mask as float32, for linear interpolation."""
        return self.live.astype(np.float32)

    def points(self, n_points: int) -> tuple[np.ndarray, np.ndarray]:
        """At most ``n_points`` samples on live traces, evenly spread through them in storage order: (3, N) index
        coordinates, (N,) values."""
        i0, i1 = np.nonzero(self.live)
        flat = (np.ravel_multi_index((i0, i1), self.live.shape)[:, None] * self.shape[2]
                + np.arange(self.shape[2])).ravel()
        if len(flat) > n_points:
            flat = flat[np.linspace(0, len(flat) - 1, n_points).round().astype(np.int64)]
        grid = np.array(np.unravel_index(flat, self.shape))
        return grid.astype(np.float64), self.data.ravel()[flat].astype(np.float64)

    def sample(self, pts, gradient: str = "central", *, gradients: bool = True) -> Samples:
        """Weights, values (cubic B-spline) and gradients at (3, N) index coordinates.

        ``gradient``: ``'central'``, the :attr:`gradient_volumes` interpolated linearly (smoother near the Nyquist
        frequency than the values' own derivative); ``'spline'``, the derivative of the cubic B-spline that gives
        the values (:func:`~seismo3d.seismic.volumes._spline.spline_gradients`): the exact gradient of the
        correlation the refinement climbs. On aliased volumes the two differ by much of their size (the Volve
        velocity pairs of ``benchmarks/volumes.py`` at 0 and 30 degrees, on a grid of points between the samples:
        24-126 % along the map axes depending on the level, the sign differing at 4-24 % of the points).
        Without ``gradients`` the samples' gradients are None (:meth:`with_gradients` adds them).
        """
        n = pts.shape[1]
        edge = np.minimum(pts, self.hi[:, None] - pts)
        w = np.clip((edge + 0.5) / self.taper, 0.0, 1.0).prod(axis=0)
        inside = w > 0
        p = pts[:, inside]
        weights, values = np.zeros(n), np.zeros(n)
        weights[inside] = w[inside] * ndi.map_coordinates(self.live_weights, p[:2], order=1, mode="nearest")
        values[inside] = spline_values(self.coefficients, p)
        out = Samples(weights, values, None)
        return self.with_gradients(pts, out, gradient) if gradients else out

    def with_gradients(self, pts, samples: Samples, gradient: str = "central") -> Samples:
        """``samples`` of :meth:`sample` at the (3, N) ``pts`` with their gradients (see :meth:`sample`)."""
        inside = samples.weights > 0
        p = pts[:, inside]
        grads = np.zeros((3, pts.shape[1]))
        if gradient == "spline":
            grads[:, inside] = spline_gradients(self.coefficients, p)
        else:
            grads[:, inside] = linear_values(self.gradient_volumes, p)
        return Samples(samples.weights, samples.values, grads)


def _high_fraction(data, axis: int, live) -> float:
    """The fraction of the power of ``data`` (its mean along ``axis`` removed) above ``HIGH_FREQUENCY`` cycles per
    sample along ``axis``, counted on live traces."""
    d = data - data.mean(axis=axis, keepdims=True)
    power = np.abs(fft.rfft(d, axis=axis)) ** 2
    high = fft.rfftfreq(data.shape[axis]) > HIGH_FREQUENCY
    power = np.moveaxis(power, axis, -1)
    if axis == 2:
        power = power[live]
    return float(power[..., high].sum() / max(power.sum(), 1e-30))


def build_level(source, live, factors, taper: float) -> Sampled:
    """The level of a full-resolution ``source`` (normalised amplitudes or the envelope) decimated by ``factors``
    (3 ints: inline, crossline, sample)."""
    sigma = [0.5 * f if f > 1 else 0.0 for f in factors]
    out = ndi.gaussian_filter(source, sigma, mode="nearest") if any(sigma) else source
    f0, f1, f2 = (int(f) for f in factors)
    out = np.ascontiguousarray(out[::f0, ::f1, ::f2], dtype=np.float32)
    return Sampled(out, np.ascontiguousarray(live[::f0, ::f1]), factors, taper)


def without_mean_trace(level: Sampled) -> Sampled:
    """The level with its mean trace (the mean of each sample over the live traces) removed, 0 on dead traces.

    The mean trace tells nothing of the map-view part of a map; where it holds most of the variance, every map the
    search scores correlates alike (time slices rendered each by its own range: the Parihaka cube of
    ``benchmarks/volumes.py --only any_grid``, 80 % of the variance at full resolution and 86-98 % on the coarser
    levels, where every map of the search correlated 0.94 and no start was near the right one)."""
    if not level.live.any():
        return level
    out = level.data - level.data[level.live].mean(axis=0)
    out[~level.live] = 0.0
    return Sampled(out.astype(np.float32), level.live, level.factors, level.taper)


def to_level(t_index, fixed: Sampled, moving: Sampled) -> np.ndarray:
    """A full-resolution moving-to-fixed (4, 4) transform between the two volumes' level indices."""
    return homogeneous_diag(1.0 / fixed.factors) @ t_index @ homogeneous_diag(moving.factors)


def from_level(t_level, fixed: Sampled, moving: Sampled) -> np.ndarray:
    """A level's moving-to-fixed (4, 4) transform between full-resolution indices."""
    return homogeneous_diag(fixed.factors) @ t_level @ homogeneous_diag(1.0 / moving.factors)
