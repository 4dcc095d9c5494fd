"""Map-view candidates from the amplitudes alone: Fourier-Mellin on the map-view power spectra of the two volumes.

The power spectrum of a map-view image does not change when the image is shifted, and a linear map of the map view
maps it by the inverse transpose: when ``moving(m) = fixed(A m + t)`` (``A`` the (2, 2) map-view part of the moving
index to fixed index map), ``P_moving(k) = P_fixed(A^-T k) / det(A)^2`` (k in cycles per sample). Summed over the
time (depth) slices of each volume, the spectra need neither the translation nor the vertical scale.

Written as ``A = s diag(1 / f) R(theta) diag(m)`` with the anisotropy of each volume's bins ``m = (a^1/2, a^-1/2)``
(moving) and ``f = (rho^-1/2, rho^1/2)`` (fixed), the moving spectrum read at ``diag(m) u`` equals the fixed one read
at ``diag(f) R(theta) u / s``: after the two anisotropies are undone, a map rotation and an isotropic scale, which
become shifts of log-polar images (angle, log radius) found for all rotations and scales at once by a masked
normalised cross-correlation in the Fourier domain (Reddy & Chatterji 1996; :class:`~.search.MaskedNCC`). The
anisotropies ``a`` and ``rho`` are searched on a grid. A power spectrum is symmetric about 0, so a map rotation and
the same rotation plus 180 degrees are both candidates (the translation search tells them apart).

The spectra tell the map only as far as the map view holds enough traces: on maps of 18-24 traces (f3_crop, the
Penobscot and Volve blocks of ``benchmarks/volumes.py --only spectral``) a candidate within half a step of the
search's grid of the right map is among the 6 best in 24 of 36 pairs, and the best one in 16; the registration
scores them beside that grid, and only on volumes of ``spectral_min_traces`` traces or more per map axis
(:class:`~seismo3d.seismic.volumes.VolumeOptions`).

References
----------
.. [1] B. S. Reddy and B. N. Chatterji, "An FFT-based technique for translation, rotation, and scale-invariant image
   registration", IEEE Trans. Image Process. 5(8), 1266-1271, 1996, doi:10.1109/83.506761.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft, ndimage as ndi

from .model import rotation_2d
from .search import MaskedNCC

__all__ = ["MapSpectrum", "SpectralMap", "map_spectrum", "spectral_maps"]

NYQUIST_MARGIN = 0.45  # cycles per sample: spectra are read inside |k| < this along each axis (resampling roll-off)
LIVE_TAPER = 0.125  # of the smaller map size: the window's rise from dead traces (_live_taper)
MAIN_LOBE = 2.5  # resolution cells (1 / n_traces along each axis): the window's main lobe about 0 is left out


@dataclass(frozen=True, eq=False)
class MapSpectrum:
    """The map-view log power spectrum of one volume, summed over its time (depth) slices.

    Attributes
    ----------
    log_power : (N0, N1) float64 ndarray
        ``log`` of the power, zero frequency at ``(N0 // 2, N1 // 2)`` (fftshifted).
    n_traces : (2,) int
        Inlines and crosslines of the volume (its resolution: ``1 / n_traces`` cycles per sample).
    """

    log_power: np.ndarray
    n_traces: tuple

    def read(self, k) -> tuple[np.ndarray, np.ndarray]:
        """Values at (2, ...) frequencies ``k`` (cycles per sample, bilinear) and where they are trusted (inside the
        Nyquist margin, outside the window's main lobe)."""
        n = np.array(self.log_power.shape, dtype=np.float64)
        index = np.stack([k[i] * n[i] + n[i] // 2 for i in range(2)])
        values = ndi.map_coordinates(self.log_power, index.reshape(2, -1), order=1, mode="nearest")
        lobe = np.hypot(k[0] * self.n_traces[0], k[1] * self.n_traces[1])
        ok = (np.abs(k[0]) < NYQUIST_MARGIN) & (np.abs(k[1]) < NYQUIST_MARGIN) & (lobe > MAIN_LOBE)
        return values.reshape(k.shape[1:]), ok


@dataclass(frozen=True)
class SpectralMap:
    """A map-view candidate of :func:`spectral_maps`."""

    linear: np.ndarray  # (2, 2) map-view part of the moving index -> fixed index map (full resolution)
    correlation: float  # NCC of the two log-polar spectra at it


def map_spectrum(volume, live, *, max_slices: int = 64, max_fft: int = 256) -> MapSpectrum:
    """The map-view log power spectrum of a volume: windowed time (depth) slices, their means removed, summed.

    The window is a Hann window over each map axis times a cosine rise away from dead traces.

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) float ndarray
        Normalised amplitudes (0 on dead traces).
    live : (n_inlines, n_xlines) bool ndarray
        Live traces (the window is 0 on dead ones).
    max_slices : int
        At most this many slices, evenly spread, are summed.
    max_fft : int
        The slices are zero-padded to twice their size, a power of 2 of at least 64 and at most this.

    Returns
    -------
    MapSpectrum
    """
    n0, n1, n2 = volume.shape
    window = np.outer(_hann(n0 + 2)[1:-1], _hann(n1 + 2)[1:-1]) * _live_taper(live)
    picked = np.unique(np.linspace(0, n2 - 1, min(n2, max_slices)).round().astype(int))
    size = [int(min(max(64, 2 ** np.ceil(np.log2(2 * n))), max_fft)) for n in (n0, n1)]
    half = np.zeros((size[0], size[1] // 2 + 1))  # the non-negative crossline frequencies (real slices)
    for chunk in np.array_split(picked, max(1, len(picked) // 16)):  # 16 slices at a time: little memory
        s = volume[:, :, chunk].astype(np.float64)
        s = s - (window[:, :, None] * s).sum(axis=(0, 1)) / max(window.sum(), 1e-12)
        spectrum = fft.rfft2((s * window[:, :, None]).astype(np.float32), s=size, axes=(0, 1))
        half += (spectrum.real ** 2 + spectrum.imag ** 2).sum(axis=2)
    # the other half by the symmetry of a real slice's spectrum: P(k0, k1) = P(-k0, -k1)
    mirrored = half[(-np.arange(size[0])) % size[0]][:, size[1] - np.arange(size[1] // 2 + 1, size[1])]
    power = np.concatenate([half, mirrored], axis=1)
    power = np.fft.fftshift(power)
    return MapSpectrum(np.log(power + 1e-9 * max(power.max(), 1e-30)), (n0, n1))


def _hann(m: int) -> np.ndarray:
    """The symmetric Hann window of ``m`` samples, (m,) float64: 0.5 + 0.5 cos(x) at ``m`` points x evenly spaced over
    [-pi, pi], the bits of ``scipy.signal.windows.hann`` (importing scipy.signal costs a command about 1 CPU s, scipy
    1.17; ``np.hanning`` differs in the last bits at most lengths)."""
    if m <= 1:
        return np.ones(m)
    return 0.5 + 0.5 * np.cos(np.linspace(-np.pi, np.pi, m))


def _live_taper(live) -> np.ndarray:
    """(n0, n1) weights rising from 0 at dead traces to 1 over ``LIVE_TAPER`` of the smaller map size (a cosine of
    the distance): the edge of a dead area (a copy's corners outside its source) would print its own orientation,
    the other grid's, into the spectrum."""
    if live.all():
        return np.ones(live.shape)
    width = max(LIVE_TAPER * min(live.shape), 1.0)
    d = np.minimum(ndi.distance_transform_edt(live) / width, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * d)


def _log_polar(spectrum: MapSpectrum, anisotropy: float, angles, radii, inverse: bool):
    """The spectrum read at ``diag(g) u`` for ``u`` on a log-polar grid (angles x radii, cycles per sample), with
    ``g = (a^1/2, a^-1/2)`` (moving) or ``(a^-1/2, a^1/2)`` (``inverse``, fixed): (image, mask of trusted values)."""
    g = np.array([anisotropy ** 0.5, anisotropy ** -0.5])
    if inverse:
        g = 1.0 / g
    u = np.stack([np.cos(angles)[:, None] * radii[None, :], np.sin(angles)[:, None] * radii[None, :]])
    values, ok = spectrum.read(u * g[:, None, None])
    return np.where(ok, values, 0.0), ok.astype(np.float64)


def spectral_maps(fixed: MapSpectrum, moving: MapSpectrum, *, scale_range, max_rotation: float,
                  max_anisotropy: float, n_best: int, angle_step: float = 1.5, n_radii: int = 64,
                  anisotropy_step: float = 2.0 ** (1.0 / 3.0)) -> list[SpectralMap]:
    """Map-view candidates (moving index -> fixed index) whose spectra agree best, best first.

    Parameters
    ----------
    fixed, moving : MapSpectrum
        The two volumes' map-view spectra (:func:`map_spectrum`).
    scale_range : (float, float)
        Isotropic scales (the square root of the map's determinant) searched.
    max_rotation : float
        Degrees: map rotations within +-max_rotation (and their twins 180 degrees away when within it).
    max_anisotropy : float
        Largest ratio of the two bin scales of either volume.
    n_best : int
        Candidates returned, at most (one per pair of anisotropies, the best ones).
    angle_step : float
        Degrees per angle bin of the log-polar images.
    n_radii : int
        Log-spaced radii from ``1 / (2 max(n_traces))`` to 0.5 cycles per sample.
    anisotropy_step : float
        Ratio between neighbouring anisotropies searched (each volume's, from 1 / max_anisotropy to max_anisotropy).

    Returns
    -------
    list of SpectralMap
    """
    lo, hi = scale_range
    n_angles = int(round(180.0 / angle_step))
    step = np.radians(180.0 / n_angles)
    r_min = MAIN_LOBE / max(max(fixed.n_traces), max(moving.n_traces))  # below: the window's main lobe only
    radii = np.exp(np.linspace(np.log(r_min), np.log(0.5), n_radii))
    dr = np.log(radii[1] / radii[0])
    # moving: one half plane; fixed: wider by the rotations and scales searched (shifts of the moving image in it)
    pad_a, pad_r = int(np.ceil(np.radians(max_rotation) / step)) + 1, int(np.ceil(np.log(max(hi, 1 / lo)) / dr)) + 1
    a_moving = np.arange(n_angles) * step
    a_fixed = np.arange(-pad_a, n_angles + pad_a) * step
    r_fixed = radii[0] * np.exp(np.arange(-pad_r, n_radii + pad_r) * dr)
    k = int(np.floor(np.log(max_anisotropy) / np.log(anisotropy_step) + 1e-9))
    anisotropies = anisotropy_step ** np.arange(-k, k + 1)
    fixed_images = {rho: _log_polar(fixed, rho, a_fixed, r_fixed, inverse=True) for rho in anisotropies}
    # untrusted fixed values: their mean, their mask is folded into the moving side's overlap count below; each
    # fixed image's transforms once, each moving image's once for every fixed one (all of one shape)
    fixed_ncc = {rho: MaskedNCC(np.where(f_mask > 0, f_img, f_img[f_mask > 0].mean())[:, :, None])
                 for rho, (f_img, f_mask) in fixed_images.items() if f_mask.any()}
    found = []
    for a in anisotropies:
        img, mask = _log_polar(moving, a, a_moving, radii, inverse=False)
        if not mask.any() or not fixed_ncc:  # no trusted frequency (a map too small for its window)
            continue
        need = max(0.25 * mask.sum(), 8.0)
        # the moving image lies inside the fixed one at every rotation and scale searched (the fixed one is padded
        # by them): only those shifts are computed
        spectra = next(iter(fixed_ncc.values())).moving_spectra(img[:, :, None], mask[:, :, None], inside=True)
        for rho, ncc_of in fixed_ncc.items():
            ncc, n, origin = ncc_of.with_overlap(img[:, :, None], mask[:, :, None], need, spectra, inside=True)
            ncc = ncc[:, :, 0]
            # index shifts -> rotation (fixed angle = moving angle + theta) and log scale (fixed radius = r / s)
            shifts_a = (np.arange(ncc.shape[0]) - origin[0] - pad_a) * step
            shifts_r = (np.arange(ncc.shape[1]) - origin[1] - pad_r) * dr
            rot_ok = np.abs(np.degrees(shifts_a)) <= max_rotation
            scale_ok = (-shifts_r >= np.log(lo)) & (-shifts_r <= np.log(hi))
            ncc = np.where(rot_ok[:, None] & scale_ok[None, :], ncc, -np.inf)
            i, j = np.unravel_index(int(np.argmax(ncc)), ncc.shape)
            if not np.isfinite(ncc[i, j]):
                continue
            di, dj = _subsample_peak(ncc, i, j)
            theta, s = (shifts_a[i] + di * step), np.exp(-(shifts_r[j] + dj * dr))
            f = np.array([rho ** -0.5, rho ** 0.5])
            m = np.array([a ** 0.5, a ** -0.5])
            linear = s * np.diag(1.0 / f) @ rotation_2d(np.degrees(theta)) @ np.diag(m)
            found.append(SpectralMap(linear, float(ncc[i, j])))
    found.sort(key=lambda c: -c.correlation)
    out = []
    for c in found:
        twins = [c] + ([SpectralMap(-c.linear, c.correlation)] if max_rotation > 90.0 else [])
        for t in twins:
            if all(np.abs(t.linear - o.linear).max() > 0.1 for o in out):
                out.append(t)
        if len(out) >= n_best:
            break
    return out[:n_best]


def _subsample_peak(ncc, i, j) -> tuple[float, float]:
    """Parabolic offsets (within +-0.5) of a peak at ``(i, j)`` along both axes."""
    out = []
    for axis, idx in ((0, i), (1, j)):
        line = ncc[:, j] if axis == 0 else ncc[i, :]
        if 0 < idx < len(line) - 1 and np.all(np.isfinite(line[idx - 1:idx + 2])):
            a, b, c = line[idx - 1:idx + 2]
            den = a - 2 * b + c
            out.append(float(np.clip(0.5 * (a - c) / den, -0.5, 0.5)) if den < 0 else 0.0)
        else:
            out.append(0.0)
    return out[0], out[1]
