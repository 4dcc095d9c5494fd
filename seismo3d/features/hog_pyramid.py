"""HOG-pyramid descriptor: oriented-gradient histograms over concentric circular rings, computed recursively.

The image matcher of method.md section 2 (the paper's refs [20, 24]):

1. gradients of each pyramid level; each pixel votes its gradient magnitude into Q orientation bins (linear soft
   binning between the two nearest bins; votes in fixed point so that window sums are exact integers);
2. around a point, K concentric discs of radii ``r_1 < ... < r_K`` (pixels with ``dx^2 + dy^2 <= r^2``) and their
   differences, the rings; one Q-bin histogram per ring;
3. as a window slides one pixel along a row only its boundary arcs change, so each disc histogram is updated in
   O(r) (the column offsets entering and leaving the disc on each row are tabulated once,
   :func:`disc_half_widths`): :func:`dense_ring_histograms` gives the ring histograms centred on every pixel of an
   image in O(r) per pixel; at sparse keypoints (:func:`ring_histograms`) the window slides from one keypoint to the
   next along a row when that is cheaper than a direct sum;
4. a ring is rotation invariant as a set of pixels, so rotating the image circularly shifts every histogram: all
   rings are shifted by the dominant orientation (a peak of the smoothed disc histogram, to a fraction of a bin, by
   an exact sub-bin shift of their Fourier series); a window with several strong peaks gets one descriptor per peak;
5. normalisation: rings divided by their area, unit L2 length, Hellinger (square root) map;
6. an image pyramid (:func:`~seismo3d.features.keypoints.image_pyramid`, 4 levels per octave from 1.4x enlarged
   down): Harris keypoints and descriptors on every level with the same ring radii in level pixels, so coarser
   levels describe larger regions; nearest-neighbour matching over all levels gives tolerance to scale changes.

References
----------
.. [1] A. Vokhmintcev, M. Timchenko, "The new combined method of the generation of a 3d dense map of environment
   based on history of camera positions and the robot's movements" (the paper of this project), section 4, Tables 2-4.
.. [2] J. Diaz-Escobar, V. Kober, V. Karnaukhov, M. Mozerov, "A robust HOG-based descriptor for pattern recognition",
   Proc. SPIE 9971, 99712A (2016), doi:10.1117/12.2237260.
.. [3] S. Miramontes-Jaramillo, V. Kober, V. H. Diaz-Ramirez, "Multiple objects tracking with HOGs matching in
   circular windows", Proc. SPIE 9217, 92171N (2014), doi:10.1117/12.2061660.
.. [4] D. G. Lowe, "Distinctive image features from scale-invariant keypoints", IJCV 60 (2004),
   doi:10.1023/B:VISI.0000029664.99615.94.
.. [5] R. Arandjelovic, A. Zisserman, "Three things everyone should know to improve object retrieval" (RootSIFT),
   CVPR 2012, doi:10.1109/CVPR.2012.6248018.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_positive
from ..errors import InputError
from . import _kernels
from .keypoints import Features, harris_peaks, harris_response, resize_levels, to_gray
from .orientations import dominant_orientations, shifted_descriptors

__all__ = [
    "HogPyramidParams",
    "disc_half_widths",
    "orientation_votes",
    "dense_ring_histograms",
    "ring_histograms",
    "ring_descriptors",
    "hog_pyramid_features",
]

# Fixed-point unit of the votes: the largest gradient magnitude of a level votes 2**20.
_VOTE_UNIT = 2.0 ** 20


@dataclass(frozen=True)
class HogPyramidParams:
    """Parameters of the HOG-pyramid detector and descriptor (defaults tuned on benchmarks/matching.py).

    Attributes
    ----------
    n_bins : int
        Q, number of orientation bins over 360 degrees (the gradient's sign is kept), 4..255.
    radii : tuple of float
        Outer radii in pixels (of each pyramid level) of the K concentric rings, increasing. The descriptor has
        ``K * n_bins`` values (64 by default).
    scale_factor : float
        Downsampling factor between pyramid levels (> 1); 2**(1/4) puts four levels in an octave.
    n_levels : int
        Largest number of pyramid levels (fewer when a level would be smaller than the outer disc).
    first_level : int
        Index of the finest level: -2 starts at ``scale_factor**2`` = 1.41x the input size, which adds small-scale
        keypoints (SIFT starts at 2x).
    gradient_sigma : float
        Gaussian pre-smoothing of each level before the derivatives, in level pixels (0 for none).
    harris_sigma : float
        Integration scale of the Harris structure tensor, in level pixels.
    harris_k : float
        Harris sensitivity k.
    nms_size : int
        Side of the non-maximum-suppression window, in level pixels.
    scale_nms : bool
        Also suppress a peak when a neighbouring level has a stronger one at the same place. Fewer, faster
        keypoints, but Harris is a poor scale selector: fewer correct matches under scale change (off by default).
    threshold : float
        Keypoints must have a Harris response above ``threshold`` times the strongest response of the image.
    max_keypoints : int
        Keep at most this many keypoints, the strongest responses over all levels (before the extra descriptors of
        windows with several dominant orientations).
    clip : float
        SIFT-style clipping of the unit-length descriptor (0 disables; with the Hellinger map it did not help).
    peak_ratio : float
        A keypoint gets one descriptor per orientation peak reaching this fraction of its highest peak (at most 4).
    max_gap : int or None
        Along a row, slide the window recursively to the next keypoint when it is at most this many columns away,
        otherwise start afresh with a direct sum (cheaper for distant keypoints). None: the break-even gap (the
        outer disc's area over the pixels entering and leaving all discs per step, 4 columns for the default).
    """

    n_bins: int = 16
    radii: tuple = (4.0, 8.0, 12.0, 16.0)
    scale_factor: float = 2 ** 0.25
    n_levels: int = 11
    first_level: int = -2
    gradient_sigma: float = 1.0
    harris_sigma: float = 1.0
    harris_k: float = 0.04
    nms_size: int = 3
    scale_nms: bool = False
    threshold: float = 1e-6
    max_keypoints: int = 6000
    clip: float = 0.0
    peak_ratio: float = 0.9
    max_gap: int | None = None

    def __post_init__(self):
        if int(self.n_bins) < 4:
            raise InputError(f"n_bins must be >= 4; got {self.n_bins!r}")
        r = np.asarray(self.radii, dtype=np.float64)
        if r.ndim != 1 or r.size < 1 or not np.all(np.isfinite(r)) or np.any(r <= 0) or np.any(np.diff(r) <= 0):
            raise InputError(f"radii must be positive and strictly increasing, e.g. (4, 8, 12, 16); got {self.radii!r}")
        if not self.scale_factor > 1:
            raise InputError(f"scale_factor must be > 1; got {self.scale_factor!r}")
        for name in ("n_levels", "nms_size", "max_keypoints"):
            if int(getattr(self, name)) < 1:
                raise InputError(f"{name} must be >= 1; got {getattr(self, name)!r}")
        if int(self.n_bins) > 255:
            raise InputError(f"n_bins must be <= 255; got {self.n_bins!r}")
        check_positive(self.harris_sigma, "harris_sigma")
        for name in ("gradient_sigma", "threshold", "clip"):
            check_positive(getattr(self, name), name, allow_zero=True)
        if not 0 < self.peak_ratio <= 1:
            raise InputError(f"peak_ratio must be in (0, 1]; got {self.peak_ratio!r}")

    @property
    def n_dims(self) -> int:
        """Length of a descriptor, K * Q."""
        return len(self.radii) * int(self.n_bins)

    @property
    def pad(self) -> int:
        """Outer radius rounded up: the margin in pixels a window needs around its centre."""
        return int(np.floor(max(self.radii)))


def disc_half_widths(radii, pad: int | None = None) -> np.ndarray:
    """Row half-widths of digital discs: the column offsets entering and leaving a disc as it slides.

    Parameters
    ----------
    radii : (K,) array_like of float
        Disc radii in pixels; a disc holds the offsets with ``dx^2 + dy^2 <= r^2``.
    pad : int, optional
        Largest row offset tabulated (default: ``floor(max(radii))``).

    Returns
    -------
    half_widths : (K, 2 * pad + 1) int64 ndarray
        ``half_widths[k, dy + pad]`` is the largest ``|dx|`` inside disc k on row offset dy, or -1 when that row
        misses the disc. Sliding one pixel to the right removes column ``x - h`` and adds column ``x + 1 + h``.
    """
    r = np.asarray(radii, dtype=np.float64).ravel()
    if pad is None:
        pad = int(np.floor(r.max()))
    hw = np.full((r.size, 2 * pad + 1), -1, dtype=np.int64)
    for k, rad in enumerate(r):
        r2 = rad * rad
        for j, dy in enumerate(range(-pad, pad + 1)):
            if dy * dy > r2:
                continue
            h = int(np.floor(np.sqrt(r2 - dy * dy)))
            while h * h + dy * dy > r2:  # guard against rounding of sqrt
                h -= 1
            while (h + 1) ** 2 + dy * dy <= r2:
                h += 1
            hw[k, j] = h
    return hw


def orientation_votes(gx, gy, *, n_bins: int = 16, pad: int = 0):
    """Soft-binned, fixed-point orientation votes of every pixel, zero-padded for window sums.

    Parameters
    ----------
    gx, gy : (H, W) array_like of float
        Derivatives along x (columns) and y (rows).
    n_bins : int
        Q, orientation bins over [0, 360) degrees (4 <= Q <= 255); bin b is centred on ``b * 360 / Q`` degrees.
    pad : int
        Zero margin added on every side (pixels outside the image vote nothing); leave it 0 for
        :func:`dense_ring_histograms` and :func:`ring_histograms`, which add their own.

    Returns
    -------
    bins : (H + 2 pad, W + 2 pad, 2) uint8 ndarray
        The two bins each pixel votes into.
    weights : (H + 2 pad, W + 2 pad, 2) int32 ndarray
        The votes, ``round(u |g| (1 - f))`` and ``round(u |g| f)`` where f is the orientation's fractional position
        between the two bins and ``u = 2**20 / max |g|`` (fixed point: window sums are exact integers).
    """
    gx = np.asarray(gx)
    gy = np.asarray(gy)
    if gx.shape != gy.shape or gx.ndim != 2:
        raise InputError(f"gx and gy must be 2D arrays of one shape; got {gx.shape} and {gy.shape}")
    if not 4 <= int(n_bins) <= 255:
        raise InputError(f"n_bins must be in [4, 255]; got {n_bins!r}")
    dtype = np.float32 if gx.dtype == np.float32 and gy.dtype == np.float32 else np.float64
    gx = np.ascontiguousarray(gx, dtype=dtype)
    gy = np.ascontiguousarray(gy, dtype=dtype)
    h, w = gx.shape
    bins = np.zeros((h + 2 * pad, w + 2 * pad, 2), np.uint8)
    weights = np.zeros((h + 2 * pad, w + 2 * pad, 2), np.int32)
    gmax = float(np.sqrt(np.max(gx.astype(np.float64) ** 2 + gy.astype(np.float64) ** 2))) if gx.size else 0.0
    if gmax > 0 and np.isfinite(gmax):
        _kernels.orientation_votes(gx, gy, int(n_bins), int(pad), _VOTE_UNIT / gmax, bins, weights)
    return bins, weights


def _check_votes(bins, weights, n_bins):
    bins = np.ascontiguousarray(bins)
    weights = np.ascontiguousarray(weights)
    if bins.ndim == 2:
        bins, weights = bins[..., None], weights[..., None]
    if bins.ndim != 3 or bins.shape != weights.shape:
        raise InputError(f"bins and weights must both be (H, W) or (H, W, P) arrays; got {bins.shape}, {weights.shape}")
    if bins.dtype.kind not in "iu":
        raise InputError(f"bins must be integer orientation bins; got dtype {bins.dtype}")
    if bins.size and (bins.min() < 0 or bins.max() >= n_bins):
        raise InputError(f"bins must lie in [0, {n_bins}); got [{bins.min()}, {bins.max()}]")
    if weights.dtype.kind not in "iuf":
        raise InputError(f"weights must be integer or float; got dtype {weights.dtype}")
    if weights.dtype.kind == "f":
        weights = weights.astype(np.float64, copy=False)
    elif weights.dtype not in (np.int32, np.int64):
        weights = weights.astype(np.int64)
    if bins.dtype not in (np.uint8, np.int32, np.int64):
        bins = bins.astype(np.int64)
    return bins, weights


def _break_even_gap(half_widths):
    """Columns over which sliding costs about as much as a fresh direct sum of the outer disc."""
    direct = np.sum(2 * half_widths[-1][half_widths[-1] >= 0] + 1)
    per_step = 2 * np.count_nonzero(half_widths >= 0)
    return max(1, int(direct // per_step))


def _check_radii(radii):
    r = np.asarray(radii, dtype=np.float64)
    if r.ndim != 1 or r.size < 1 or not np.all(np.isfinite(r)) or np.any(r <= 0) or np.any(np.diff(r) <= 0):
        raise InputError(f"radii must be positive and strictly increasing, e.g. (4, 8, 12, 16); got {radii!r}")
    return r


def _hist_dtype(weights):
    return np.float64 if weights.dtype.kind == "f" else np.int64


def _pad_votes(bins, weights, pad):
    widths = ((pad, pad), (pad, pad), (0, 0))
    return np.pad(bins, widths), np.pad(weights, widths)


def dense_ring_histograms(bins, weights, radii, *, n_bins: int, rows=None) -> np.ndarray:
    """Ring histograms centred on every pixel of an image (or of some rows), by recursive sliding windows.

    Along each row the first window is summed directly; every next one is obtained from its left neighbour by
    removing the pixels leaving each disc (one per disc row) and adding those entering it: O(r) per pixel.

    Parameters
    ----------
    bins : (H, W) or (H, W, P) integer array_like
        Orientation bin(s) in [0, n_bins) each pixel votes into (P votes per pixel, e.g. 2 with soft binning).
    weights : (H, W) or (H, W, P) array_like, integer or float
        The votes. Integer votes give exact integer histograms.
    radii : (K,) array_like of float
        Increasing disc radii in pixels; ring k is disc k minus disc k - 1.
    n_bins : int
        Q, number of orientation bins.
    rows : (R,) array_like of int, optional
        Rows to compute (default: all H rows).

    Returns
    -------
    hist : (R, W, K, Q) int64 or float64 ndarray
        ``hist[i, x, k]`` is the histogram of ring k centred on pixel ``(rows[i], x)``. Pixels outside the image
        vote nothing.

    Raises
    ------
    InputError
        If shapes, dtypes, bins or rows are invalid.
    """
    b, w = _check_votes(bins, weights, int(n_bins))
    radii = _check_radii(radii)
    h, wd = b.shape[:2]
    rows = np.arange(h, dtype=np.int64) if rows is None else np.asarray(rows, dtype=np.int64).ravel()
    if rows.size and (rows.min() < 0 or rows.max() >= h):
        raise InputError(f"rows must lie in [0, {h}); got [{rows.min()}, {rows.max()}]")
    pad = int(np.floor(radii.max()))
    hw = disc_half_widths(radii, pad)
    bp, wp = _pad_votes(b, w, pad)
    out = np.zeros((rows.size, wd, radii.size, int(n_bins)), dtype=_hist_dtype(w))
    if rows.size and wd:
        _kernels.dense_disc_histograms(bp, wp, hw, pad, rows, wd, out)
    out[:, :, 1:] -= out[:, :, :-1].copy()  # rings = differences of nested discs
    return out


def ring_histograms(bins, weights, radii, rows, cols, *, n_bins: int, max_gap: int | None = None) -> np.ndarray:
    """Ring histograms at given pixels, sliding recursively between the pixels of each row.

    Parameters
    ----------
    bins, weights : (H, W[, P]) array_like
        As in :func:`dense_ring_histograms`.
    radii : (K,) array_like of float
        Increasing disc radii in pixels.
    rows, cols : (N,) array_like of int
        Pixel centres; any order (they are sorted internally and the result is returned in the input order).
    n_bins : int
        Q.
    max_gap : int, optional
        Slide to the next point of a row when it is at most this many columns away, else sum afresh (default: the
        break-even gap where both cost the same, 4 columns for the default rings).

    Returns
    -------
    hist : (N, K, Q) int64 or float64 ndarray
        Ring histograms; identical to the sums over each ring's pixels (exactly, for integer weights).
    """
    b, w = _check_votes(bins, weights, int(n_bins))
    radii = _check_radii(radii)
    pad = int(np.floor(radii.max()))
    b, w = _pad_votes(b, w, pad)
    h, wd = b.shape[0] - 2 * pad, b.shape[1] - 2 * pad
    rows = np.asarray(rows, dtype=np.int64).ravel()
    cols = np.asarray(cols, dtype=np.int64).ravel()
    if rows.shape != cols.shape:
        raise InputError(f"rows and cols must have the same length; got {rows.size} and {cols.size}")
    if rows.size and (rows.min() < 0 or rows.max() >= h or cols.min() < 0 or cols.max() >= wd):
        raise InputError(f"points must lie inside the {h}x{wd} image")
    order = np.lexsort((cols, rows))
    out = np.zeros((rows.size, radii.size, int(n_bins)), dtype=_hist_dtype(w))
    hw = disc_half_widths(radii, pad)
    gap = _break_even_gap(hw) if max_gap is None else int(max_gap)
    if rows.size:
        _kernels.point_disc_histograms(b, w, hw, pad, rows[order], cols[order], gap, out)
    out[:, 1:] -= out[:, :-1].copy()
    result = np.empty_like(out)
    result[order] = out
    return result


def ring_descriptors(hist, radii, *, clip: float = 0.0, peak_ratio: float = 0.9, max_orientations: int = 4):
    """Rotation-invariant descriptors from ring histograms: shift by each dominant orientation, then normalise.

    Parameters
    ----------
    hist : (N, K, Q) array_like
        Ring histograms of N windows (e.g. from :func:`ring_histograms`).
    radii : (K,) array_like of float
        The rings' outer radii in pixels (for the area normalisation).
    clip : float
        Clip the unit-length descriptor at this value and renormalise, as in SIFT [4] (0 disables).
    peak_ratio : float
        A window gets one descriptor per orientation-histogram peak reaching this fraction of its highest peak
        (SIFT [4] uses 0.8); 1 keeps only the highest.
    max_orientations : int
        At most this many descriptors per window (the highest peaks).

    Returns
    -------
    descriptors : (M, K * Q) float32 ndarray
        Ring after ring (innermost first), each ring's Q bins starting at the dominant orientation; unit L2 norm
        after the Hellinger map (square root of the L1-normalised vector) [5]. Windows without gradient give none.
    orientations : (M,) float64 ndarray
        Dominant orientation of each descriptor in degrees in [0, 360).
    index : (M,) int64 ndarray
        The window (row of ``hist``) each descriptor comes from, ascending.

    Notes
    -----
    Each ring is divided by its area, so that all rings weigh alike per pixel. The orientation histogram is the
    whole disc's histogram smoothed by a Gaussian of one bin; its peaks are found on a 4x finer grid (its Fourier
    series) and refined by a parabola. Rotating an image by ``phi`` moves every gradient orientation by ``phi``: the
    histograms shift by ``phi * Q / 360`` bins and so do the peaks, so resampling the rings from the peak on makes
    the descriptor invariant (exactly for multiples of ``360 / Q`` degrees, up to gradient discretisation
    otherwise). The fractional shift multiplies the m-th Fourier coefficient of every ring histogram by
    ``exp(2 pi i m s / Q)``; negative ripples of the resampled histograms are set to zero.
    Seismic sections have nearly as much gradient pointing up as down; a second descriptor at the second peak keeps
    such windows matchable when the two peaks swap.
    """
    h = np.asarray(hist, dtype=np.float64)
    if h.ndim != 3:
        raise InputError(f"hist must have shape (N, K, Q); got {h.shape}")
    n, k, q = h.shape
    radii = np.asarray(radii, dtype=np.float64)
    if radii.shape != (k,):
        raise InputError(f"radii must have {k} entries, one per ring; got {radii.shape}")
    if n == 0:
        return np.zeros((0, k * q), np.float32), np.zeros(0), np.zeros(0, np.int64)
    disc_area = np.pi * radii ** 2
    ring_area = np.diff(disc_area, prepend=0.0)
    rings = np.ascontiguousarray(h / ring_area[None, :, None])
    disc = np.ascontiguousarray(h.sum(axis=1))
    # smoothing of the orientation histogram by a Gaussian of one bin, as Fourier weights
    smooth = np.exp(-0.5 * (2 * np.pi * np.arange(q // 2 + 1) / q) ** 2)
    max_peaks = int(max_orientations)
    if max_peaks < 1:
        raise InputError(f"max_orientations must be >= 1; got {max_orientations!r}")
    index, shift = dominant_orientations(disc, smooth, float(peak_ratio), 4 * q, max_peaks)
    desc, kept = shifted_descriptors(rings, index, shift, float(clip))
    return desc, np.mod(shift[kept] * (360.0 / q), 360.0), index[kept]


def _level_gradients(level, sigma):
    """Derivatives of a level after Gaussian smoothing (float32; Sobel / 8 is the central difference smoothed
    across by [1, 2, 1] / 4)."""
    import cv2

    if sigma > 0:
        level = cv2.GaussianBlur(level, (0, 0), sigma)
    gx = cv2.Sobel(level, cv2.CV_32F, 1, 0, ksize=3, scale=0.125)
    gy = cv2.Sobel(level, cv2.CV_32F, 0, 1, ksize=3, scale=0.125)
    return gx, gy


def _detect_level(level, mask, p: HogPyramidParams):
    """Gradients, Harris response and its peaks on one pyramid level."""
    import cv2

    h, w = level.shape
    pad = p.pad
    gx, gy = _level_gradients(level, p.gradient_sigma)
    resp = harris_response(gx, gy, sigma=p.harris_sigma, k=p.harris_k)
    level_mask = None
    if mask is not None:  # the whole outer disc must lie inside the mask
        m = cv2.resize(mask, (w, h), interpolation=cv2.INTER_NEAREST)
        level_mask = cv2.erode(m, np.ones((2 * pad + 3, 2 * pad + 3), np.uint8), borderValue=0) > 0
    rows, cols, xy, values = harris_peaks(resp, nms_size=p.nms_size, threshold=0.0, border=pad + 1, mask=level_mask)
    local_max = cv2.dilate(resp, np.ones((3, 3), np.uint8)) if p.scale_nms else None
    return {"gx": gx, "gy": gy, "rows": rows, "cols": cols, "xy": xy, "values": values, "local_max": local_max}


def _scale_nms(found):
    """Keep a peak only if no neighbouring level has a larger response within one pixel of the same place."""
    keeps = []
    for i, f in enumerate(found):
        keep = np.ones(f["rows"].size, bool)
        h, w = f["gx"].shape
        for j in (i - 1, i + 1):
            if 0 <= j < len(found):
                hj, wj = found[j]["gx"].shape
                r = np.clip(np.rint((f["rows"] + 0.5) * hj / h - 0.5).astype(np.int64), 0, hj - 1)
                c = np.clip(np.rint((f["cols"] + 0.5) * wj / w - 0.5).astype(np.int64), 0, wj - 1)
                keep &= f["values"] >= found[j]["local_max"][r, c]
        keeps.append(keep)
    for f, keep in zip(found, keeps):
        for key in ("rows", "cols", "xy", "values"):
            f[key] = f[key][keep]


def _describe_level(f, cut, radii, half_widths, p: HogPyramidParams):
    """Ring histograms (recursive sliding along rows) and rotation-invariant descriptors of one level's peaks."""
    keep = f["values"] >= cut
    rows, cols, xy, values = f["rows"][keep], f["cols"][keep], f["xy"][keep], f["values"][keep]
    if rows.size == 0:
        return None
    pad = p.pad
    bins, weights = orientation_votes(f["gx"], f["gy"], n_bins=p.n_bins, pad=pad)
    hist = np.zeros((rows.size, radii.size, p.n_bins), np.int64)
    gap = _break_even_gap(half_widths) if p.max_gap is None else int(p.max_gap)
    _kernels.point_disc_histograms(bins, weights, half_widths, pad, rows, cols, gap, hist)  # peaks sorted by row
    hist[:, 1:] -= hist[:, :-1].copy()  # nested discs -> rings
    desc, ori, src = ring_descriptors(hist, radii, clip=p.clip, peak_ratio=p.peak_ratio)
    return xy[src], values[src], desc, ori


def hog_pyramid_features(image, *, params: HogPyramidParams | None = None, mask=None) -> Features:
    """Detect keypoints and compute HOG-pyramid descriptors on every level of an image pyramid.

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        Grey image of any real dtype, or RGB colour (converted with :func:`~seismo3d.features.to_gray`).
    params : HogPyramidParams, optional
        Detector and descriptor parameters (defaults: ``HogPyramidParams()``).
    mask : (H, W) array_like of bool, optional
        Where keypoints may be; a keypoint is kept only if its whole outer disc lies inside the mask (e.g. the valid
        area of a warped image).

    Returns
    -------
    features : Features
        ``method='hog'``; float32 descriptors of ``len(params.radii) * params.n_bins`` values, one per keypoint and
        dominant orientation. Empty (N = 0) for an image without corners (constant, or smaller than a descriptor
        window).

    Raises
    ------
    InputError
        If the image is empty, smaller than 2 x 2, has NaN or inf values, or has 4 channels, or the mask's shape
        differs from the image's.

    Notes
    -----
    Per pyramid level (float32): Gaussian smoothing, Sobel derivatives, Harris response, peaks in ``nms_size``
    windows with sub-pixel refinement; the ``max_keypoints`` strongest peaks over all levels are described, each at
    its own level (a corner that persists over several levels is described at each of them, which is what makes
    matches tolerant to scale changes between levels).

    References
    ----------
    See the module docstring: [1] (Tables 2-4), [2], [3] (ring histograms in sliding circular windows), [4], [5].
    """
    p = HogPyramidParams() if params is None else params
    img = to_gray(image)
    h0, w0 = img.shape
    mask_u8 = None
    if mask is not None:
        mask = np.asarray(mask)
        if mask.shape != img.shape:
            raise InputError(f"mask must have the image's shape {img.shape}; got {mask.shape}")
        mask_u8 = mask.astype(bool).astype(np.uint8)
    radii = np.asarray(p.radii, dtype=np.float64)
    half_widths = disc_half_widths(radii, p.pad)
    lo, hi = float(img.min()), float(img.max())
    if not hi > lo:
        return Features.empty("hog", p.n_dims)
    img = ((img - lo) / (hi - lo)).astype(np.float32)
    levels = resize_levels(img, p.scale_factor, p.n_levels, 2 * p.pad + 3, p.first_level)
    found = [_detect_level(level, mask_u8, p) for level in levels]
    if p.scale_nms:
        _scale_nms(found)
    all_values = np.concatenate([f["values"] for f in found] + [np.zeros(0)])
    if all_values.size == 0:
        return Features.empty("hog", p.n_dims)
    cut = p.threshold * all_values.max()
    if all_values.size > p.max_keypoints:
        kth = all_values.size - p.max_keypoints
        cut = max(cut, np.partition(all_values, kth)[kth])
    described = [_describe_level(f, cut, radii, half_widths, p) for f in found]
    out_xy, out_desc, out_scale, out_ori, out_resp = [], [], [], [], []
    for f, d in zip(found, described):
        if d is None:
            continue
        xy, values, desc, ori = d
        h, w = f["gx"].shape
        sx, sy = w0 / w, h0 / h
        out_xy.append(np.column_stack([(xy[:, 0] + 0.5) * sx - 0.5, (xy[:, 1] + 0.5) * sy - 0.5]))
        out_desc.append(desc)
        out_scale.append(np.full(values.size, 2.0 * radii[-1] * 0.5 * (sx + sy)))
        out_ori.append(ori)
        out_resp.append(values)
    if not out_xy:
        return Features.empty("hog", p.n_dims)
    desc = np.concatenate(out_desc)
    good = np.any(desc > 0, axis=1)
    return Features(
        keypoints=np.concatenate(out_xy)[good],
        descriptors=desc[good],
        scales=np.concatenate(out_scale)[good],
        orientations=np.concatenate(out_ori)[good],
        responses=np.concatenate(out_resp)[good],
        method="hog",
    )
