"""Stage 2 of the volume registration: the starting transforms, from slice features or a correlation search.

From slice features (time slices resampled with a grid of anisotropies, as in ASIFT, matched with the HOG-pyramid
matcher, then RANSAC), or, for volumes too small for slice features, from a correlation search over map rotations and
lateral scales with every translation scored at once by the masked normalised cross-correlation in the Fourier domain
(Padfield 2012).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft, ndimage as ndi

from ..._progress import progress_steps
from ...errors import InputError, RegistrationError
from ...registration import ransac
from .frames import WorkingFrames, project_to_model
from .options import VolumeOptions
from .slices import FeatureCache, section_matches, time_slice_matches
from .vertical import sample_ratio, vertical_shifts

__all__ = ["FeatureStart", "CorrelationStart", "MaskedNCC", "anisotropies", "is_thin", "feature_starts",
           "correlation_starts"]


@dataclass(frozen=True, eq=False)
class FeatureStart:
    """A start from slice features: the RANSAC consensus and its inlier matches (working-frame units)."""

    n_inliers: int
    transform: np.ndarray  # (4, 4) moving index -> fixed index
    source_matches: np.ndarray  # (K, 3) moving points of the inlier matches, working frame
    target_matches: np.ndarray  # (K, 3) fixed points, working frame


@dataclass(frozen=True, eq=False)
class CorrelationStart:
    """A start from the correlation search: its best normalised cross-correlation and the transform."""

    correlation: float
    transform: np.ndarray  # (4, 4) moving index -> fixed index


def anisotropies(model: str, lo: float, hi: float) -> tuple:
    """Candidate ratios (moving axis-0 scale / axis-1 scale) of the affine simulation over the scale range [lo, hi],
    steps of sqrt(2); (1,) for the rigid model."""
    if model == "rigid":
        return (1.0,)
    n = int(np.ceil(np.log(hi / lo) / np.log(np.sqrt(2.0)) - 1e-9))
    return tuple(float(a) for a in np.exp(np.linspace(-np.log(hi / lo), np.log(hi / lo), 2 * n + 1)))


def is_thin(shape_f, shape_m, frames: WorkingFrames, hi: float, opt: VolumeOptions) -> bool:
    """Too few traces across (fewer than ``opt.min_map`` working cells, the moving volume at its largest scale
    ``hi``) for time-slice features?"""
    wf, wm = frames.w_fixed, frames.w_moving
    return min(shape_f[0] * wf[0], shape_f[1] * wf[1], shape_m[0] * wm[0] * hi, shape_m[1] * wm[1] * hi) < opt.min_map


def feature_starts(fn, mn, frames: WorkingFrames, model: str, profiles, thin: bool,
                   opt: VolumeOptions) -> list[FeatureStart]:
    """Candidate starts from slice features, best (most RANSAC inliers) first.

    Parameters
    ----------
    fn, mn : (n0, n1, n2) float32 ndarray
        The normalised fixed and moving volumes.
    frames : WorkingFrames
    model : {'rigid', 'axis_scaled'}
        The model imposed on the starts.
    profiles : tuple of (n,) ndarray
        The mean envelope profiles (fixed, moving) along the sample axis (for a vertical shift candidate).
    thin : bool
        :func:`is_thin`: inline sections instead of time slices.
    opt : VolumeOptions

    Returns
    -------
    list of FeatureStart
        Starts with plausible scales (within ``scale_range`` widened by a quarter), best first; empty when no slice
        features match.
    """
    method, seed = opt.feature_method, opt.seed
    scale_range = opt.scale_range
    lo, hi = scale_range
    wf, wm = frames.w_fixed, frames.w_moving
    s2 = sample_ratio(fn, mn, frames, model, scale_range)
    cache_f, cache_m = FeatureCache(method), FeatureCache(method)
    hyps = []
    if thin:
        # inline sections: 3D RANSAC (the inline correspondence is unknown)
        sizes = (1.0,) if model == "rigid" else tuple(np.exp(np.linspace(np.log(lo), np.log(hi), 5)))
        for aspect in sizes:
            m = section_matches(fn, mn, frames, s2, aspect, cache_f, cache_m, 3, opt)
            if m is None or len(m[0]) < 8:
                continue
            src, dst = m[0] * wm, m[1] * wf
            try:
                r = ransac(src, dst, model="rigid" if model == "rigid" else "affine", threshold=2.0, seed=seed,
                           max_trials=3000)
            except (RegistrationError, InputError):
                continue
            inl = r.info["inliers"]
            hyps.append(FeatureStart(int(inl.sum()), r.transform, src[inl], dst[inl]))
    else:
        # time slices: the vertical map is (s2, t2) up to the +-2 samples of the slice window, so RANSAC fits the
        # map-view part only (2D, 3 matches per sample) and the vertical shift is the inliers' median
        aspects = anisotropies(model, lo, hi)
        for t2 in vertical_shifts(fn, mn, frames, s2, profiles, opt):
            for aspect in aspects:
                m = time_slice_matches(fn, mn, frames, s2, t2, aspect, cache_f, cache_m, opt)
                if m is None or len(m[0]) < 8:
                    continue
                src, dst = m[0] * wm, m[1] * wf
                try:
                    r = ransac(src[:, :2], dst[:, :2], model="rigid" if model == "rigid" else "affine",
                               threshold=2.0, seed=seed, max_trials=opt.ransac_trials)
                except (RegistrationError, InputError):
                    continue
                inl = r.info["inliers"]
                t = np.eye(4)
                t[:2, :2], t[:2, 3] = r.transform[:2, :2], r.transform[:2, 2]
                t[2, 2] = s2 * wf[2] / wm[2]  # working units
                t[2, 3] = float(np.median(dst[inl, 2] - t[2, 2] * src[inl, 2]))
                hyps.append(FeatureStart(int(inl.sum()), t, src[inl], dst[inl]))
    out = []
    for h in sorted(hyps, key=lambda h: -h.n_inliers):
        t_work = project_to_model(h.transform, model)
        s = np.linalg.norm(t_work[:3, :3], axis=0)
        if model != "rigid" and (np.any(s < lo / 1.25) or np.any(s > hi * 1.25)):
            continue  # implausible scales: a false consensus
        out.append(FeatureStart(h.n_inliers, frames.to_index(t_work), h.source_matches, h.target_matches))
    return out


class MaskedNCC:
    """Normalised cross-correlation of the fixed volume with a masked image for every integer shift at once, in the
    Fourier domain (masked NCC, Padfield 2012, eqs. 14-20); the fixed volume's transforms are kept per padded shape.

    The same quantity as scikit-image's ``phase_cross_correlation(..., reference_mask=, moving_mask=)``, which
    returns only the best shift: the correlation start needs every shift's correlation, an overlap threshold in
    samples rather than a fraction of the largest overlap, and the fixed volume's transforms reused for every map
    (real FFTs, three instead of six forward transforms per call); ``benchmarks/volumes.py --only masked_ncc``
    compares the two on the registration's own calls.

    Parameters
    ----------
    fixed : (n0, n1, n2) array_like of float
        The fixed volume (no mask: every sample valid).

    References
    ----------
    .. [1] D. Padfield, "Masked object registration in the Fourier domain", IEEE Trans. Image Process. 21(5),
       2706-2718, 2012, doi:10.1109/TIP.2011.2181402.
    """

    def __init__(self, fixed):
        self.f = np.asarray(fixed, np.float64)
        self.cache = {}

    def __call__(self, img, mask, min_overlap):
        """Correlation of ``img`` (n0', n1', n2') over ``mask`` (same shape, 0 / 1) with the fixed volume at every
        integer shift: (ncc, origin), ``ncc[k]`` correlating ``fixed[x + k - origin]`` with ``img[x]``; -inf where
        fewer than ``min_overlap`` samples overlap or a side is constant."""
        origin = np.array(img.shape) - 1
        shape = tuple(fft.next_fast_len(int(a + b - 1), real=True) for a, b in zip(self.f.shape, img.shape))
        if shape not in self.cache:
            self.cache[shape] = [fft.rfftn(a, shape, workers=-1) for a in (self.f, self.f * self.f,
                                                                             np.ones_like(self.f))]
        f1, f2, f0 = self.cache[shape]
        flip = (slice(None, None, -1),) * 3
        g1, g2, g0 = (fft.rfftn(a[flip], shape, workers=-1) for a in (img * mask, img * img * mask, mask))

        def corr(a, b):
            return fft.irfftn(a * b, shape, workers=-1)

        n = np.round(corr(f0, g0))
        nn = np.maximum(n, 1.0)
        sum_f, sum_f2, sum_m, sum_m2 = corr(f1, g0), corr(f2, g0), corr(f0, g1), corr(f0, g2)
        num = corr(f1, g1) - sum_f * sum_m / nn
        den = np.sqrt(np.maximum(sum_f2 - sum_f ** 2 / nn, 0.0) * np.maximum(sum_m2 - sum_m ** 2 / nn, 0.0))
        ok = (n >= min_overlap) & (den > 1e-6 * nn)
        return np.where(ok, num / np.where(ok, den, 1.0), -np.inf), origin


def correlation_starts(fn, mn, frames: WorkingFrames, model: str, opt: VolumeOptions, *, n_best: int = 3,
                       progress: bool = False) -> list[CorrelationStart]:
    """Starting transforms (index space) without features, best first.

    For each map rotation within +-``max_rotation`` degrees and (unless rigid) each pair of lateral scales over
    ``scale_range``, with the vertical scale of stage 1, the moving volume is resampled (linear) onto the fixed grid
    through that linear map, and its normalised cross-correlation with the fixed volume is computed for every integer
    translation at once (:class:`MaskedNCC`), over overlaps of at least ``min_fraction`` of the smaller volume; the
    best translation scores the map. The ``n_refined`` best distinct maps are searched again on a grid of half the
    steps. The sample axis of both volumes is halved for the search (after smoothing), which keeps the cost to about
    20 ms per map on a 23 x 18 x 75 cube; volumes of more than ``max_search`` samples (so halved) are not searched
    (an empty list). ``progress`` reports the maps scored.
    """
    scale_range = opt.scale_range
    lo, hi = scale_range
    wf, wm = frames.w_fixed, frames.w_moving
    dec = 2 if min(fn.shape[2], mn.shape[2]) >= 32 else 1
    if max(fn.size, mn.size) / dec > opt.max_search:
        return []  # about 0.1 s per map at this size: larger volumes carry slice features
    s2 = sample_ratio(fn, mn, frames, model, scale_range) * wf[2] / wm[2]  # working units
    fz, mz = ((ndi.gaussian_filter1d(v, 0.5 * dec, axis=2)[:, :, ::dec] if dec > 1 else v).astype(np.float64)
              for v in (fn, mn))
    shifts = MaskedNCC(fz)
    corners = np.array(np.meshgrid(*[[0.0, n - 1.0] for n in mz.shape], indexing="ij")).reshape(3, -1)
    m_hi = np.array(mz.shape, dtype=np.float64)[:, None] - 1

    def score(theta, sx, sy):
        c, s = np.cos(np.radians(theta)), np.sin(np.radians(theta))
        work = np.diag([sx, sy, s2])
        work[:2, :2] = np.array([[c, -s], [s, c]]) @ np.diag([sx, sy])
        lin = np.diag(1.0 / wf) @ work @ np.diag(wm)  # moving index -> fixed index
        foot = lin @ corners
        g_lo, g_hi = np.floor(foot.min(axis=1)).astype(int), np.ceil(foot.max(axis=1)).astype(int)
        grid = np.indices(g_hi - g_lo + 1).reshape(3, -1) + g_lo[:, None]
        m = np.linalg.solve(lin, grid)
        mask = np.all((m >= 0) & (m <= m_hi), axis=0)
        img = np.zeros(grid.shape[1])
        img[mask] = ndi.map_coordinates(mz, m[:, mask], order=1)
        shape = tuple(g_hi - g_lo + 1)
        need = opt.min_fraction * min(fz.size, mz.size * abs(np.linalg.det(lin)))
        ncc, origin = shifts(img.reshape(shape), mask.reshape(shape).astype(np.float64), need)
        k = np.unravel_index(int(np.argmax(ncc)), ncc.shape)
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = lin, np.array(k) - origin - g_lo
        t[2, 3] *= dec  # back to full-resolution samples (the vertical scale is the same at both)
        return float(ncc[k]), t

    angles = np.arange(-opt.max_rotation, opt.max_rotation + 1e-9, opt.rotation_step)
    n_s = 1 if model == "rigid" else opt.scale_steps
    scales = np.exp(np.linspace(np.log(lo), np.log(hi), n_s)) if n_s > 1 else np.ones(1)
    step = np.log(hi / lo) / (n_s - 1) if n_s > 1 else 0.0
    half = [-0.5, 0.0, 0.5]
    n_fine = len(half) * (len(half) ** 2 if n_s > 1 else 1)
    with progress_steps(len(angles) * n_s * n_s + opt.n_refined * n_fine, "correlation start", unit="map",
                        enabled=progress) as bar:

        def scored(a, sx, sy):
            out = score(a, sx, sy)
            bar.advance()
            return out

        # the coarse grid of maps, then the n_refined best distinct ones on a grid of half the steps
        coarse = sorted(((*scored(a, sx, sy), a, sx, sy) for a in angles for sx in scales for sy in scales),
                        key=lambda r: -r[0])
        top = []
        for r in coarse:
            if not np.isfinite(r[0]):
                break
            if all(abs(r[2] - q[2]) > opt.rotation_step / 2 or abs(np.log(r[3] / q[3])) > step / 2
                   or abs(np.log(r[4] / q[4])) > step / 2 for q in top):
                top.append(r)
            if len(top) == opt.n_refined:
                break
        fine = [scored(a + da * opt.rotation_step, sx * np.exp(dx * step), sy * np.exp(dy * step))
                for _, _, a, sx, sy in top for da in half for dx in (half if n_s > 1 else [0.0])
                for dy in (half if n_s > 1 else [0.0])]
    fine = [r for r in sorted(fine, key=lambda r: -r[0]) if np.isfinite(r[0])]
    return [CorrelationStart(c, t) for c, t in fine[:n_best]]
