"""Slice images of the volume registration, their features and the 3D matches between them.

Slices resampled to a common pixel size, the HOG-pyramid (or SIFT) features of each, cached, and the 3D matches between
time slices or inline sections lifted with their slice coordinate.
"""

from __future__ import annotations

import numpy as np

from .frames import WorkingFrames
from .options import VolumeOptions

__all__ = ["resample_slice", "FeatureCache", "slice_pairs", "time_slice_matches", "section_matches"]


def resample_slice(img, f0: float, f1: float) -> tuple[np.ndarray, float, float]:
    """Resample a slice image by factors (``f0`` rows, ``f1`` columns), area-averaged when shrinking (OpenCV).

    Returns the float32 image and the factors from its pixels back to slice indices (rows, columns)."""
    import cv2

    n0, n1 = max(int(round(img.shape[0] * f0)), 2), max(int(round(img.shape[1] * f1)), 2)
    interp = cv2.INTER_AREA if f0 * f1 < 1 else cv2.INTER_LINEAR
    out = cv2.resize(np.ascontiguousarray(img, dtype=np.float32), (n1, n0), interpolation=interp)
    return out, img.shape[0] / n0, img.shape[1] / n1  # image pixel -> slice index factors


class FeatureCache:
    """Features (:func:`seismo3d.features.detect_and_describe`, at most 800 per image) of slice images, computed once
    per key."""

    def __init__(self, method):
        self.method = method
        self.store = {}

    def get(self, key, make_image):
        """(features, row factor, column factor) of the image ``make_image()`` returns (as :func:`resample_slice`)."""
        from ...features import detect_and_describe

        if key not in self.store:
            img = make_image()
            self.store[key] = (detect_and_describe(img[0], method=self.method, max_keypoints=800), img[1], img[2])
        return self.store[key]


def slice_pairs(features_m, features_f, ratio: float = 0.85):
    """Ratio-test matches (:func:`seismo3d.features.match_features`, unverified) of two feature sets, or None."""
    from ...features import match_features

    if len(features_m) < 2 or len(features_f) < 2:
        return None
    r = match_features(features_m, features_f, verify=None, ratio=ratio)
    return r if len(r) else None


def time_slice_matches(fn, mn, frames: WorkingFrames, s2: float, t2: float, aspect: float, cache_f: FeatureCache,
                       cache_m: FeatureCache, opt: VolumeOptions):
    """3D matches ((K, 3) moving index, (K, 3) fixed index) from time slices for one vertical map (moving sample k
    at fixed sample ``s2 k + t2``) and one anisotropy ``aspect`` (moving axis-0 / axis-1 scale); None when no slice
    matches. ``opt.n_slices`` moving slices, each against the fixed slices ``opt.shift_window`` around its
    predicted one."""
    n_slices = opt.n_slices
    wf, wm = frames.w_fixed, frames.w_moving
    g = min(2.0, opt.max_feature_side / max(fn.shape[0] * wf[0], fn.shape[1] * wf[1]))
    c0, c1 = np.sqrt(aspect), 1.0 / np.sqrt(aspect)
    # moving slices from one grid of 2 n_slices samples (so that their features serve every shift t2), n_slices of
    # those inside the fixed volume at this shift
    grid = np.unique(np.linspace(0, mn.shape[2] - 1, 2 * n_slices + 2)[1:-1].round())
    inside = grid[(s2 * grid + t2 >= 0) & (s2 * grid + t2 <= fn.shape[2] - 1)]
    if len(inside) < 2:
        return None
    src, dst = [], []
    for zm in inside[np.unique(np.linspace(0, len(inside) - 1, n_slices).round().astype(int))]:
        zm = float(zm)
        fm, pm0, pm1 = cache_m.get((zm, aspect), lambda: resample_slice(mn[:, :, int(zm)], g * wm[0] * c0,
                                                                      g * wm[1] * c1))
        for dz in opt.shift_window:
            zf = float(np.round(s2 * zm + t2 + dz))
            if not 0 <= zf <= fn.shape[2] - 1:
                continue
            ff, pf0, pf1 = cache_f.get(zf, lambda: resample_slice(fn[:, :, int(zf)], g * wf[0], g * wf[1]))
            r = slice_pairs(fm, ff)
            if r is None:
                continue
            src.append(np.column_stack([r.xy1[:, 1] * pm0, r.xy1[:, 0] * pm1, np.full(len(r), zm)]))
            dst.append(np.column_stack([r.xy2[:, 1] * pf0, r.xy2[:, 0] * pf1, np.full(len(r), zf)]))
    if not src:
        return None
    return np.vstack(src), np.vstack(dst)


def section_matches(fn, mn, frames: WorkingFrames, s2: float, aspect: float, cache_f: FeatureCache,
                    cache_m: FeatureCache, n_sections: int, opt: VolumeOptions):
    """3D matches ((K, 3) moving index, (K, 3) fixed index) from inline sections (thin volumes), or None;
    ``aspect`` is the crossline scale in fixed samples."""
    wf, wm = frames.w_fixed, frames.w_moving
    g = min(1.0, 2 * opt.max_feature_side / max(fn.shape[1] * wf[1], fn.shape[2]))
    n_f = fn.shape[0]
    f_idx = np.unique(np.linspace(0, n_f - 1, min(n_f, 24)).round().astype(int))
    src, dst = [], []
    for im in np.unique(np.linspace(0, mn.shape[0] - 1, n_sections + 2)[1:-1].round().astype(int)):
        fm, pm0, pm1 = cache_m.get((int(im), aspect), lambda: resample_slice(mn[im], g * wm[1] * aspect, g * s2))
        for i_f in f_idx:
            ff, pf0, pf1 = cache_f.get(int(i_f), lambda: resample_slice(fn[i_f], g * wf[1], g))
            r = slice_pairs(fm, ff)
            if r is None:
                continue
            src.append(np.column_stack([np.full(len(r), float(im)), r.xy1[:, 1] * pm0, r.xy1[:, 0] * pm1]))
            dst.append(np.column_stack([np.full(len(r), float(i_f)), r.xy2[:, 1] * pf0, r.xy2[:, 0] * pf1]))
    if not src:
        return None
    return np.vstack(src), np.vstack(dst)
