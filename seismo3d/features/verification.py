"""Geometric verification of image matches and their lifting to 3D (RGB-D) or (trace, sample) points (seismic).

Robust fits use OpenCV's RANSAC family: ``cv2.findHomography`` (USAC [1] or classic RANSAC [2]) for a homography and
``cv2.estimateAffinePartial2D`` for a similarity (rotation, uniform scale, shift). The lifted matches are what the
fused ICP's feature term consumes (method.md section 1, eq. 16 of the paper).

References
----------
.. [1] R. Raguram, O. Chum, M. Pollefeys, J. Matas, J.-M. Frahm, "USAC: a universal framework for random sample
   consensus", IEEE TPAMI 35 (2013), doi:10.1109/TPAMI.2012.257.
.. [2] M. A. Fischler, R. C. Bolles, "Random sample consensus", Comm. ACM 24 (1981), doi:10.1145/358669.358692.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .._validation import as_intrinsics, as_pair, as_points, check_choice, check_positive
from ..errors import InputError, RegistrationError
from ..registration import ransac

__all__ = [
    "fit_homography",
    "fit_similarity_2d",
    "verify_matches",
    "lift_matches_depth",
    "lift_match_pairs",
    "lift_matches_section",
]

_ESTIMATORS = ("usac", "ransac")


def fit_homography(xy1, xy2, *, threshold: float = 3.0, estimator: str = "usac", confidence: float = 0.999,
                   max_iterations: int = 10000):
    """Robustly fit the homography mapping points of image 1 onto image 2.

    Parameters
    ----------
    xy1, xy2 : (M, 2) array_like of float
        Matched ``(x, y)`` pixel positions, row i of one matching row i of the other; M >= 4.
    threshold : float
        Largest reprojection error of an inlier, in pixels of image 2.
    estimator : {'usac', 'ransac'}
        ``'usac'``: OpenCV's USAC_ACCURATE (graph-cut RANSAC with local optimisation) [1]; ``'ransac'``: classic
        RANSAC [2] with a least-squares refit on the inliers.
    confidence : float
        Probability in (0, 1) that the returned model is the best one.
    max_iterations : int
        Largest number of random samples.

    Returns
    -------
    homography : (3, 3) float64 ndarray
        ``H`` with ``[x2, y2, 1] ~ H @ [x1, y1, 1]``, normalised so that ``H[2, 2] = 1``.
    inliers : (M,) bool ndarray
        Matches within ``threshold`` of the fitted model.

    Raises
    ------
    InputError
        If the inputs are not paired (M, 2) arrays or contain NaN.
    RegistrationError
        If there are fewer than 4 matches or no consistent homography is found.
    """
    import cv2

    src, dst = as_pair(xy1, xy2, dims=(2,), min_points=0, names=("xy1", "xy2"))
    check_positive(threshold, "threshold")
    check_choice(estimator, "estimator", _ESTIMATORS)
    if src.shape[0] < 4:
        raise RegistrationError(f"a homography needs at least 4 matches; got {src.shape[0]}. "
                                "Loosen the ratio test or use verify='similarity' (2 matches)")
    flag = cv2.USAC_ACCURATE if estimator == "usac" else cv2.RANSAC
    h, mask = cv2.findHomography(src.astype(np.float32), dst.astype(np.float32), flag, float(threshold),
                                 maxIters=int(max_iterations), confidence=float(confidence))
    if h is None or mask is None or not np.all(np.isfinite(h)) or abs(h[2, 2]) < 1e-12:
        raise RegistrationError("no consistent homography among the matches; the images may not overlap")
    h = np.asarray(h, dtype=np.float64) / h[2, 2]
    return h, mask.ravel().astype(bool)


def fit_similarity_2d(xy1, xy2, *, threshold: float = 3.0, confidence: float = 0.999, max_iterations: int = 10000):
    """Robustly fit a 2D similarity (rotation, uniform scale, translation) mapping image 1 onto image 2.

    Uses the registration engine's :func:`~seismo3d.registration.ransac` (minimal samples of 2 matches fitted in
    closed form by Umeyama's method, local optimisation on the inliers).

    Parameters
    ----------
    xy1, xy2 : (M, 2) array_like of float
        Matched ``(x, y)`` pixel positions; M >= 2.
    threshold : float
        Largest reprojection error of an inlier, in pixels.
    confidence : float
        RANSAC confidence in (0, 1).
    max_iterations : int
        Largest number of random samples.

    Returns
    -------
    transform : (3, 3) float64 ndarray
        ``[[s R, t], [0, 0, 1]]`` acting on ``[x, y, 1]``.
    inliers : (M,) bool ndarray

    Raises
    ------
    InputError
        If the inputs are not paired (M, 2) arrays or contain NaN.
    RegistrationError
        If there are fewer than 2 matches or RANSAC finds no model.
    """
    src, dst = as_pair(xy1, xy2, dims=(2,), min_points=0, names=("xy1", "xy2"))
    check_positive(threshold, "threshold")
    if src.shape[0] < 2:
        raise RegistrationError(f"a similarity needs at least 2 matches; got {src.shape[0]}")
    try:  # the engine's RANSAC with its closed-form Umeyama minimal solver (method.md section 1)
        result = ransac(src, dst, model="similarity", threshold=threshold, max_trials=max_iterations,
                        confidence=confidence, min_inliers=min(src.shape[0], 3))
    except (RegistrationError, InputError) as exc:
        raise RegistrationError(f"no consistent similarity among the matches ({exc}); the images may not overlap") \
            from exc
    return result.transform, result.info["inliers"]


def verify_matches(result, *, model: str = "homography", threshold: float = 3.0):
    """Fit a geometric model to a :class:`~seismo3d.features.MatchResult` and mark its inliers.

    Parameters
    ----------
    result : MatchResult
        Putative matches.
    model : {'homography', 'similarity'}
        Model fitted with :func:`fit_homography` or :func:`fit_similarity_2d`.
    threshold : float
        Inlier reprojection error in pixels.

    Returns
    -------
    verified : MatchResult
        A copy with ``homography`` set (None when the fit failed: too few or inconsistent matches, and then no match
        is an inlier) and ``inliers`` marking the consistent matches.
    """
    check_choice(model, "model", ("homography", "similarity"))
    fit = fit_homography if model == "homography" else fit_similarity_2d
    try:
        matrix, inliers = fit(result.xy1, result.xy2, threshold=threshold)
    except RegistrationError:
        return replace(result, homography=None, inliers=np.zeros(len(result), bool))
    return replace(result, homography=matrix, inliers=inliers)


def lift_matches_depth(xy, depth, intrinsics, *, depth_scale: float = 1.0, max_depth: float | None = None):
    """Back-project image points into 3D camera coordinates through a depth image (pinhole model).

    Parameters
    ----------
    xy : (M, 2) array_like of float
        ``(x, y)`` pixel positions (origin at the centre of the top-left pixel), e.g. ``MatchResult.xy1``.
    depth : (H, W) array_like
        Depth image registered to the colour image the points come from; 0, NaN or inf mark missing depth. Depth is
        read at the nearest pixel (no interpolation across depth edges).
    intrinsics : (3, 3) array_like or (fx, fy, cx, cy)
        Pinhole intrinsics in pixels.
    depth_scale : float
        Stored depth units per metre (1000 for millimetre PNGs such as 7-Scenes, 5000 for TUM); points are returned
        in metres (``depth / depth_scale``).
    max_depth : float, optional
        Drop points farther than this many metres.

    Returns
    -------
    points : (K, 3) float64 ndarray
        Camera-frame ``(X, Y, Z)`` in metres (x right, y down, z forward) of the K points with valid depth.
    index : (K,) int64 ndarray
        Rows of ``xy`` the points come from (points without depth or outside the image are dropped).

    Raises
    ------
    InputError
        If ``xy``, ``depth`` or ``intrinsics`` are malformed.
    """
    pts = as_points(xy, "xy", dims=(2,), min_points=0) if np.asarray(xy).size else np.zeros((0, 2))
    d = np.asarray(depth)
    if d.ndim != 2 or min(d.shape) < 1:
        raise InputError(f"depth must be a 2D (H, W) image; got shape {d.shape}")
    fx, fy, cx, cy = as_intrinsics(intrinsics)
    scale = check_positive(depth_scale, "depth_scale")
    cols = np.rint(pts[:, 0]).astype(np.int64)
    rows = np.rint(pts[:, 1]).astype(np.int64)
    inside = (rows >= 0) & (rows < d.shape[0]) & (cols >= 0) & (cols < d.shape[1])
    z = np.full(pts.shape[0], np.nan)
    z[inside] = d[rows[inside], cols[inside]].astype(np.float64) / scale
    valid = np.isfinite(z) & (z > 0)
    if max_depth is not None:
        valid &= z <= check_positive(max_depth, "max_depth")
    index = np.nonzero(valid)[0].astype(np.int64)
    zv = z[index]
    points = np.column_stack([(pts[index, 0] - cx) * zv / fx, (pts[index, 1] - cy) * zv / fy, zv])
    return points, index


def lift_match_pairs(result, depth1, depth2, intrinsics1, intrinsics2=None, *, depth_scale: float = 1.0,
                     max_depth: float | None = None, inliers_only: bool = True):
    """Lift both sides of the matches to 3D and keep the pairs with depth on both sides.

    Parameters
    ----------
    result : MatchResult
        Matches between two RGB-D frames.
    depth1, depth2 : (H, W) array_like
        Depth images of frame 1 and frame 2 (see :func:`lift_matches_depth`).
    intrinsics1 : (3, 3) array_like or (fx, fy, cx, cy)
        Intrinsics of frame 1; ``intrinsics2`` defaults to the same camera.
    depth_scale, max_depth
        See :func:`lift_matches_depth`.
    inliers_only : bool
        Use only the verified matches (default).

    Returns
    -------
    points1, points2 : (K, 3) float64 ndarray
        Paired camera-frame points in metres, ready as the fused ICP's feature correspondences.
    index : (K,) int64 ndarray
        Rows of ``result`` the pairs come from.
    """
    sel = np.nonzero(result.inliers if inliers_only else np.ones(len(result), bool))[0]
    p1, i1 = lift_matches_depth(result.xy1[sel], depth1, intrinsics1, depth_scale=depth_scale, max_depth=max_depth)
    k2 = intrinsics1 if intrinsics2 is None else intrinsics2
    p2, i2 = lift_matches_depth(result.xy2[sel], depth2, k2, depth_scale=depth_scale, max_depth=max_depth)
    common, a, b = np.intersect1d(i1, i2, assume_unique=True, return_indices=True)
    return p1[a], p2[b], sel[common].astype(np.int64)


def lift_matches_section(xy, *, first_trace: float = 0.0, trace_step: float = 1.0, first_sample: float = 0.0,
                         sample_step: float = 1.0) -> np.ndarray:
    """Convert pixel positions on a seismic-section image into ``(trace, sample)`` points.

    The section image has traces along x (columns) and samples along y (rows, time or depth increasing
    downwards), i.e. ``image = traces.T`` for a trace-major ``(n_traces, n_samples)`` array.

    Parameters
    ----------
    xy : (M, 2) array_like of float
        ``(x, y)`` pixel positions, e.g. ``MatchResult.xy1``.
    first_trace, trace_step : float
        Trace number (or inline / crossline number, or distance) of column 0 and its increment per column.
    first_sample, sample_step : float
        Sample value of row 0 (index, two-way time in ms or depth in m) and its increment per row (e.g. dt = 4 ms).

    Returns
    -------
    points : (M, 2) float64 ndarray
        ``(trace, sample)`` of each point, in the units of the arguments (fractional: sub-pixel positions are kept).
    """
    pts = as_points(xy, "xy", dims=(2,), min_points=0) if np.asarray(xy).size else np.zeros((0, 2))
    for name, v in (("first_trace", first_trace), ("first_sample", first_sample)):
        if not np.isfinite(v):
            raise InputError(f"{name} must be finite; got {v!r}")
    for name, v in (("trace_step", trace_step), ("sample_step", sample_step)):
        if not np.isfinite(v) or v == 0:
            raise InputError(f"{name} must be finite and non-zero; got {v!r}")
    return np.column_stack([first_trace + trace_step * pts[:, 0], first_sample + sample_step * pts[:, 1]])
