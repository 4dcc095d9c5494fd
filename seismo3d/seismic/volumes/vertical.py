"""Stage 1 of the volume registration: the vertical scale and the vertical shift candidates.

The sample-rate ratio is where the mean trace spectra of the two volumes agree (a change of sample rate stretches the
spectrum; the wavelet is common to both); the vertical shift candidates are the modes of the vertical offsets of
section feature matches and the peak of the correlation of the mean envelope profiles.
"""

from __future__ import annotations

import numpy as np

from ...errors import RegistrationError
from ..traces import ncc
from .frames import WorkingFrames
from .options import VolumeOptions
from .slices import resample_slice, slice_pairs

__all__ = ["trace_spectrum", "vertical_scale", "profile_correlation", "correlation_peaks", "vertical_shifts",
           "sample_ratio"]


def trace_spectrum(v, n_fft: int) -> np.ndarray:
    """Mean amplitude spectrum ((n_fft // 2 + 1,) float64) of the live traces of a cube (at most 4000, evenly
    picked), Hann-windowed."""
    tr = v.reshape(-1, v.shape[2])
    tr = tr[np.ptp(tr, axis=1) > 0]
    if len(tr) > 4000:
        tr = tr[np.linspace(0, len(tr) - 1, 4000).astype(int)]
    tr = tr - tr.mean(axis=1, keepdims=True)
    return np.abs(np.fft.rfft(tr * np.hanning(tr.shape[1]), n=n_fft, axis=1)).mean(axis=0)


def vertical_scale(fixed, moving, lo: float, hi: float) -> float:
    """Sample-rate ratio (moving sample in fixed samples) in [lo, hi] where the mean trace spectra agree best (361
    log-spaced candidates): a change of sample rate stretches the spectrum, and the wavelet is common to both."""
    n_fft = int(2 ** np.ceil(np.log2(4 * max(fixed.shape[2], moving.shape[2]))))
    freqs = np.fft.rfftfreq(n_fft)
    sf, sm = trace_spectrum(fixed, n_fft), trace_spectrum(moving, n_fft)
    best, best_c = 1.0, -np.inf
    for s2 in np.exp(np.linspace(np.log(lo), np.log(hi), 361)):
        f = freqs[1:] / s2  # moving frequency (cycles per moving sample) in cycles per fixed sample
        ok = f < 0.5
        if ok.sum() < 8:
            continue
        c = np.corrcoef(np.interp(f[ok], freqs, sf), sm[1:][ok])[0, 1]
        if c > best_c:
            best, best_c = float(s2), c
    return best


def profile_correlation(pf, pm, s2: float, min_overlap: float) -> tuple[np.ndarray, np.ndarray]:
    """Correlation (:func:`~seismo3d.seismic.traces.ncc`) of two vertical profiles, the moving one stretched by
    ``s2``, for every shift t (fixed sample of moving sample 0), step 1/4 sample: (shifts, correlations), -inf where
    they overlap on less than ``min_overlap`` of the shorter one."""
    nf, zm = len(pf), np.arange(len(pm), dtype=np.float64)
    need = min_overlap * min(len(pm) * s2, nf)
    shifts = np.arange(-s2 * (len(pm) - 1), nf, 0.25)
    corr = np.full(len(shifts), -np.inf)
    for n, t in enumerate(shifts):
        zf = s2 * zm + t
        ok = (zf >= 0) & (zf <= nf - 1)
        if ok.sum() * s2 < need or ok.sum() < 8:
            continue
        a = np.interp(zf[ok], np.arange(nf), pf)
        b = pm[ok]
        if a.std() > 0 and b.std() > 0:
            corr[n] = ncc(a, b, min_samples=2)
    return shifts, corr


def correlation_peaks(shifts, corr, k: int, taken: list) -> list:
    """Up to ``k`` shifts of the highest finite correlations, each more than 3 samples from the others and from
    ``taken``, best first."""
    out = []
    for n in np.argsort(-corr):
        if not np.isfinite(corr[n]) or len(out) == k:
            break
        if all(abs(shifts[n] - t) > 3.0 for t in taken + out):
            out.append(float(shifts[n]))
    return out


def vertical_shifts(fn, mn, frames: WorkingFrames, s2: float, profiles, opt: VolumeOptions) -> list:
    """Candidate vertical shifts t (fixed sample of moving sample 0), best first.

    Two from feature matches between vertical sections (inline and crossline sections of the moving volume, resampled
    to the fixed sample rate and three lateral scales, against five of each in the fixed volume): the modes of the
    vertical offsets of the matches. Layered reflectors look alike in every section, so the offsets agree whatever
    the lateral misfit. One more from the correlation of the mean envelope profiles (``profiles``: fixed, moving),
    in case the sections have no features.
    """
    from ...features import detect_and_describe

    method = opt.feature_method
    wf, wm = frames.w_fixed, frames.w_moving
    g = min(1.0, 2 * opt.max_feature_side / max(fn.shape[0] * wf[0], fn.shape[1] * wf[1], fn.shape[2]))
    fixed_features = []
    for axis in (0, 1):
        lateral = wf[1 - axis]
        for i in np.unique(np.linspace(0, fn.shape[axis] - 1, 5).round().astype(int)):
            img, p0, p1 = resample_slice(np.take(fn, i, axis=axis), g * lateral, g)
            fixed_features.append((detect_and_describe(img, method=method, max_keypoints=800), p1))
    offsets = []
    for axis in (0, 1):
        for i in np.unique(np.linspace(0, mn.shape[axis] - 1, 4)[1:-1].round().astype(int)):
            for aspect in (0.5, 1.0, 2.0):
                img, p0, p1 = resample_slice(np.take(mn, i, axis=axis), g * wm[1 - axis] * aspect, g * s2)
                fm = detect_and_describe(img, method=method, max_keypoints=800)
                for ff, pf1 in fixed_features:
                    r = slice_pairs(fm, ff)
                    if r is not None:
                        offsets.append(r.xy2[:, 0] * pf1 - s2 * r.xy1[:, 0] * p1)
    out = []
    if offsets:
        offsets = np.concatenate(offsets)
        edges = np.arange(-s2 * mn.shape[2], fn.shape[2] + 1.0)
        hist = np.convolve(np.histogram(offsets, bins=edges)[0], [1, 2, 1], "same")
        for n in np.argsort(-hist):
            if hist[n] < 6 or len(out) == 2:
                break
            near = offsets[np.abs(offsets - edges[n] - 0.5) <= 1.5]
            t = float(np.median(near)) if len(near) else float(edges[n] + 0.5)
            if all(abs(t - u) > 3.0 for u in out):
                out.append(t)
    shifts, corr = profile_correlation(*profiles, s2, 0.4)
    out += correlation_peaks(shifts, corr, 1, out)
    if not out:
        raise RegistrationError("the two volumes cannot overlap vertically by 40 % at any shift; check that they "
                                "cover a common time / depth range and the sample intervals")
    return out


def sample_ratio(fn, mn, frames: WorkingFrames, model: str, scale_range) -> float:
    """The moving sample interval in fixed samples: from the spacings (rigid) or the trace spectra (stage 1)."""
    wf, wm = frames.w_fixed, frames.w_moving
    if model == "rigid":
        return wm[2] / wf[2]
    return vertical_scale(fn, mn, scale_range[0] * wm[2], scale_range[1] * wm[2])
