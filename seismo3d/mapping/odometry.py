"""Frame-to-model tracking: the camera pose by the fused ICP between the measured surface and the map's prediction.

Steps 1 and 2 of the method's mapping loop (method.md section 3), done as KinectFusion does them (Newcombe et al.
2011, section 3.5): the depth image is filtered, back-projected and turned into an image pyramid (steps 1); the map
predicts the surface at the predicted pose (a TSDF raycast); the engine's fused ICP (eq. 16: feature matches to the last
keyframe plus dense point-to-plane; the feature weight is set per level, by default on the coarsest only) aligns the
measured points to the prediction level by level, coarse to fine, with *projective* data association
(:class:`~seismo3d.registration.ProjectiveCorrespondences` as ``ICPOptions.correspondences``, O(1) per point) instead
of a KD-tree. The result carries the pose's information matrix (the Gauss-Newton normal matrix at the
solution, in the camera frame), the Kalman filter's measurement noise, and a mask of pixels whose residual stays large
at the solution (moving objects: not fused into the map).

References
----------
Newcombe, R. A. et al. (2011). KinectFusion: Real-time dense surface mapping and tracking. ISMAR, 127-136.
doi:10.1109/ISMAR.2011.6092378
Nguyen, C. V., Izadi, S., Lovell, D. (2012). Modeling Kinect sensor noise for improved 3D reconstruction and tracking.
3DIMPVT, 524-530. doi:10.1109/3DIMPVT.2012.84 (axial noise sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 m)
Palazzolo, E., Behley, J., Lottes, P., Giguere, P., Stachniss, C. (2019). ReFusion: 3D reconstruction in dynamic
environments for RGB-D cameras exploiting residuals. IROS, 7855-7862. doi:10.1109/IROS40897.2019.8967590
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .._validation import as_intrinsics
from ..errors import DegenerateGeometryWarning, InputError, RegistrationError
from ..geometry import backproject_depth, normals_from_points_image
from ..registration import ICPOptions, ProjectiveCorrespondences, fused_icp, icp

__all__ = ["TrackingOptions", "FrameMeasurement", "TrackingResult", "measure_frame", "track_frame",
           "kinect_depth_sigma", "point_to_plane_information", "normal_space_sample", "dynamic_mask"]


@dataclass(frozen=True)
class TrackingOptions:
    """Options of frame-to-model tracking.

    Attributes
    ----------
    scale : int
        The tracking image is the depth image subsampled by this factor (2: 320 x 240 from 640 x 480); the map is
        raycast at the same resolution.
    levels : int
        Pyramid levels (each halves the previous one), registered coarse to fine.
    max_distance : tuple of float
        Correspondence distance per level, coarse to fine, metres.
    max_iterations : tuple of int
        Gauss-Newton iterations per level, coarse to fine.
    window : int
        Half-width of the projective association's search window, pixels (0: KinectFusion's single pixel; 1: the
        closest of 3 x 3, which converges like a nearest-neighbour search where the geometry constrains a direction
        weakly, e.g. a camera turning in front of a wall; see
        :class:`~seismo3d.registration.correspondences.ProjectiveCorrespondences`).
    tolerance : float
        The engine's convergence tolerance (largest parameter update, see :func:`~seismo3d.registration.icp`).
    kernel : {'huber', 'tukey', 'cauchy', 'none'}
        Robust kernel of the dense and feature residuals.
    kernel_scale : float
        The kernel's threshold, metres.
    alpha : tuple of float
        Weight of the feature term of the fused objective (eq. 16) per level, coarse to fine. The features give the
        coarse levels their reach (RANSAC start, large motions); the finest level leans on the dense term, whose
        points are far more numerous and, when colour is not registered to depth (7-Scenes), far more accurate than
        colour keypoints lifted through depth. A level with alpha 0 runs point-to-plane ICP.
    min_features : int
        Fewest feature matches for the fused objective (fewer: point-to-plane alone).
    ransac_threshold : float
        Feature inlier distance of the engine's RANSAC, metres.
    bilateral_sigma_depth, bilateral_sigma_pixels : float
        Bilateral filter of the tracking depth (range sigma in metres, spatial sigma in pixels; 0 disables it).
    min_fitness : float
        Tracking is lost when fewer than this fraction of the measured points have a correspondence at the finest
        level.
    max_rmse : float
        Tracking is lost when the inlier RMSE exceeds this, metres.
    dynamic_sigmas, dynamic_min : float
        A pixel is *dynamic* (not fused) when its point-to-plane residual at the solution exceeds
        ``max(dynamic_min, dynamic_sigmas * sigma(z))`` with the Kinect noise sigma(z) of Nguyen et al. (2012).
    dynamic_dilation : int
        Dynamic regions are grown by this many pixels (of the full-resolution image) before masking.
    max_points : int or None
        A level with more measured points registers this many, drawn by normal-space sampling (Rusinkiewicz and
        Levoy 2001: as many points per normal direction as each direction allows, so that the directions few
        surfaces constrain keep their points); None uses every point.
    """

    scale: int = 2
    levels: int = 3
    max_distance: tuple = (0.12, 0.06, 0.03)
    max_iterations: tuple = (10, 6, 4)
    window: int = 1
    tolerance: float = 1e-4
    kernel: str = "huber"
    kernel_scale: float = 0.01
    alpha: tuple = (0.1, 0.0, 0.0)
    min_features: int = 12
    ransac_threshold: float = 0.04
    bilateral_sigma_depth: float = 0.03
    bilateral_sigma_pixels: float = 2.0
    min_fitness: float = 0.25
    max_rmse: float = 0.04
    dynamic_sigmas: float = 4.0
    dynamic_min: float = 0.05
    dynamic_dilation: int = 4
    max_points: int | None = 20000

    def __post_init__(self):
        if int(self.scale) != self.scale or self.scale < 1:
            raise InputError(f"scale must be a whole number >= 1; got {self.scale!r}")
        if int(self.levels) != self.levels or self.levels < 1:
            raise InputError(f"levels must be a whole number >= 1; got {self.levels!r}")
        for name in ("max_distance", "max_iterations", "alpha"):
            if len(getattr(self, name)) != self.levels:
                raise InputError(f"{name} needs one value per pyramid level ({self.levels}); got "
                                 f"{getattr(self, name)!r}")
        if not all(0.0 <= a <= 1.0 for a in self.alpha):
            raise InputError(f"alpha must be in [0, 1] at every level; got {self.alpha}")


@dataclass(frozen=True, eq=False)
class FrameMeasurement:
    """A depth frame prepared for tracking (step 1 of the loop).

    Attributes
    ----------
    points : list of (H_l, W_l, 3) float64 ndarray
        Camera-frame points per pyramid level (level 0 finest), metres; NaN where invalid.
    normals : (H_0, W_0, 3) float64 ndarray
        Unit normals of level 0 (central differences), NaN where undefined.
    intrinsics : list of tuple (fx, fy, cx, cy)
        Per level, pixels.
    scale : int
        Subsampling of level 0 with respect to the input depth.
    all_points : (H_0, W_0, 3) float64 ndarray
        Level-0 points before the pixels without a normal (edges) were dropped; the dynamic-pixel test uses them.
    """

    points: list
    normals: np.ndarray
    intrinsics: list
    scale: int
    all_points: np.ndarray

    def level_normals(self, level: int) -> np.ndarray:
        """(H_l, W_l, 3) normals of a pyramid level (level 0's, subsampled)."""
        step = 2**level
        return self.normals[::step, ::step]

    @property
    def n_valid(self) -> int:
        """Valid points of level 0."""
        return int(np.isfinite(self.points[0][..., 2]).sum())


@dataclass(frozen=True)
class TrackingResult:
    """Outcome of :func:`track_frame`.

    Attributes
    ----------
    pose : (4, 4) float64 ndarray
        Camera-to-world pose of the frame, metres.
    relative : (4, 4) float64 ndarray
        The frame's pose in the prediction's camera frame (``inv(prediction.pose) @ pose``).
    information : (6, 6) float64 ndarray
        Information matrix of the pose, rotation (radians) first then translation (metres), for a perturbation
        ``pose @ exp(delta)`` in the camera frame.
    fitness : float
        Fraction of measured points with a correspondence at the finest level.
    inlier_rmse : float
        Point-to-point RMSE of those correspondences, metres.
    n_feature_inliers : int
        Feature matches kept by the engine's RANSAC (0 without features).
    start : str
        Where the ICP started: ``'prediction'`` or ``'ransac'`` (the feature start won: a relocalisation).
    ok : bool
        Tracking succeeded (fitness and RMSE within the options' limits).
    dynamic : (H_0, W_0) bool ndarray
        Level-0 pixels whose residual at the solution is too large to be noise (moving objects).
    info : dict
        Per-level iterations and residual statistics.
    """

    pose: np.ndarray
    relative: np.ndarray
    information: np.ndarray
    fitness: float
    inlier_rmse: float
    n_feature_inliers: int
    start: str
    ok: bool
    dynamic: np.ndarray
    info: dict = field(default_factory=dict)


def kinect_depth_sigma(z):
    """Axial noise of a Kinect depth measurement (Nguyen et al. 2012, eq. 6, for surfaces facing the camera).

    Parameters
    ----------
    z : array_like
        Depth in metres.

    Returns
    -------
    ndarray
        Standard deviation in metres: ``0.0012 + 0.0019 (z - 0.4)^2``.
    """
    z = np.asarray(z, dtype=np.float64)
    return 0.0012 + 0.0019 * (z - 0.4) ** 2


def normal_space_sample(normals, n: int, *, seed: int = 0) -> np.ndarray:
    """Indices of ``n`` points spread evenly over normal directions (normal-space sampling).

    The normals are binned by their dominant axis and sign (6 bins); each bin gets an equal share of ``n`` (a bin
    with fewer points gives all of them and its unused share goes to the others), drawn at random within the bin.

    Parameters
    ----------
    normals : (N, 3) float64 ndarray
        Unit normals.
    n : int
        Points to keep (all when N <= n).
    seed : int
        Seed of the draw (the result is deterministic).

    Returns
    -------
    (min(N, n),) int64 ndarray
        Sorted indices.

    References
    ----------
    Rusinkiewicz, S., Levoy, M. (2001). Efficient variants of the ICP algorithm. 3DIM, 145-152.
    doi:10.1109/IM.2001.924423
    """
    m = len(normals)
    if m <= n:
        return np.arange(m)
    axis = np.argmax(np.abs(normals), axis=1)
    sign = np.take_along_axis(normals, axis[:, None], axis=1)[:, 0] > 0
    bins = axis * 2 + sign
    counts = np.bincount(bins, minlength=6)
    share = np.zeros(6, np.int64)
    left, open_bins = n, np.flatnonzero(counts > 0)
    while left > 0 and len(open_bins):
        each = max(left // len(open_bins), 1)
        give = np.minimum(counts[open_bins] - share[open_bins], each)
        share[open_bins] += give
        left -= int(give.sum())
        open_bins = open_bins[share[open_bins] < counts[open_bins]]
        if give.sum() == 0:
            break
    rng = np.random.default_rng(seed)
    order = np.argsort(bins, kind="stable")
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    picks = [order[starts[b] + rng.choice(counts[b], share[b], replace=False)] for b in range(6) if share[b]]
    return np.sort(np.concatenate(picks))


def _level_intrinsics(k, factor):
    fx, fy, cx, cy = k
    return (fx / factor, fy / factor, cx / factor, cy / factor)


def _bilateral(depth, sigma_depth, sigma_pixels):
    import cv2

    valid = np.isfinite(depth)
    filled = np.where(valid, depth, 0.0).astype(np.float32)
    d = int(2 * np.ceil(2 * sigma_pixels) + 1)
    # holes (0) differ from any valid depth by far more than sigma_depth: the range kernel gives them no weight
    out = cv2.bilateralFilter(filled, d, float(sigma_depth), float(sigma_pixels))
    return np.where(valid, out, np.nan).astype(np.float32)


def measure_frame(depth, intrinsics, options: TrackingOptions | None = None) -> FrameMeasurement:
    """Step 1 of the loop: depth -> filtered, subsampled depth -> points and normals -> image pyramid.

    Parameters
    ----------
    depth : (H, W) array_like
        Depth in metres; NaN or <= 0 where invalid.
    intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
        Of the depth image, pixels.
    options : TrackingOptions, optional

    Returns
    -------
    FrameMeasurement

    Raises
    ------
    InputError
        Malformed depth or intrinsics.
    """
    opt = TrackingOptions() if options is None else options
    z = np.asarray(depth, dtype=np.float32)
    if z.ndim != 2:
        raise InputError(f"depth must be a (H, W) image; got shape {z.shape}")
    z = np.where(z > 0, z, np.nan).astype(np.float32)
    k = as_intrinsics(intrinsics)
    z0 = z[:: opt.scale, :: opt.scale]
    if opt.bilateral_sigma_depth > 0 and opt.bilateral_sigma_pixels > 0:
        z0 = _bilateral(z0, opt.bilateral_sigma_depth, opt.bilateral_sigma_pixels)
    k0 = _level_intrinsics(k, opt.scale)
    all0 = backproject_depth(z0, k0)
    normals = normals_from_points_image(all0)
    pts0 = all0.copy()
    pts0[~np.isfinite(normals).all(axis=-1)] = np.nan  # no normal (edge, border): not a reliable point
    points, ks = [pts0], [k0]
    for level in range(1, opt.levels):
        points.append(points[-1][::2, ::2])
        ks.append(_level_intrinsics(k0, 2**level))
    return FrameMeasurement(points=points, normals=normals, intrinsics=ks, scale=opt.scale, all_points=all0)


def _prediction_level(prediction, level, window=0):
    step = 2**level
    pts = prediction.points[::step, ::step]
    nrm = prediction.normals[::step, ::step]
    valid = np.isfinite(pts[..., 2]) & np.isfinite(nrm).all(axis=-1)
    k = _level_intrinsics(prediction.intrinsics, step)
    return pts[valid], nrm[valid], ProjectiveCorrespondences.from_mask(k, valid, window=window)


def point_to_plane_information(points, relative, target_points, target_normals, weights=None, *, sigma: float):
    """Information matrix of a pose from point-to-plane correspondences (the Gauss-Newton normal matrix / sigma^2).

    Parameters
    ----------
    points : (N, 3) float64 ndarray
        Source points in the source camera frame, metres.
    relative : (4, 4) float64 ndarray
        Source-to-target transform at the solution.
    target_points, target_normals : (N, 3) float64 ndarray
        Corresponding target points and unit normals (target frame).
    weights : (N,) float64 ndarray, optional
        Robust weights.
    sigma : float
        Standard deviation of one residual, metres.

    Returns
    -------
    (6, 6) float64 ndarray
        For a perturbation ``relative @ exp(delta)``, delta = (rotation (rad), translation (m)) in the source frame:
        rows ``[p x m, m]`` with ``m = R^T n`` (Censi 2007 notes this is optimistic; the filter scales it).
    """
    m = target_normals @ relative[:3, :3]  # R^T n, row-wise
    rows = np.concatenate([np.cross(points, m), m], axis=1)
    w = np.ones(len(points)) if weights is None else weights
    return (rows * w[:, None]).T @ rows / (sigma * sigma)


def _residuals(measurement, level0, relative, dmax):
    """Level-0 correspondences at ``relative``: (valid mask of level-0 pixels, index, residuals, targets)."""
    pts = measurement.points[0]
    valid = np.isfinite(pts[..., 2])
    src = pts[valid]
    tgt, nrm, strategy = level0
    moved = src @ relative[:3, :3].T + relative[:3, 3]
    if len(tgt) == 0:
        return valid, src, np.zeros(len(src), bool), np.full(len(src), len(tgt)), tgt, nrm, moved, strategy
    dist, idx = strategy.index(tgt).query(moved, dmax)
    return valid, src, np.isfinite(dist), idx, tgt, nrm, moved, strategy


def _dynamic_pixels(measurement, relative, tgt, nrm, strategy, opt):
    """Level-0 pixels whose residual at the solution stays too large for sensor noise (ReFusion): each valid depth
    pixel (edges included) is projected into the prediction and compared with the predicted surface there."""
    pts = measurement.all_points
    valid = np.isfinite(pts[..., 2])
    dynamic = np.zeros(valid.shape, bool)
    if len(tgt) == 0 or not valid.any():
        return dynamic
    src = pts[valid]
    moved = src @ relative[:3, :3].T + relative[:3, 3]
    single = ProjectiveCorrespondences(strategy.intrinsics, strategy.pixel_index, 0)
    dist, idx = single.index(tgt).query(moved, np.inf)
    seen = np.isfinite(dist)
    r = np.zeros(len(src))
    r[seen] = np.einsum("ij,ij->i", moved[seen] - tgt[idx[seen]], nrm[idx[seen]])
    limit = np.maximum(opt.dynamic_min, opt.dynamic_sigmas * kinect_depth_sigma(src[:, 2]))
    dynamic[valid] = seen & (np.abs(r) > limit)
    return dynamic


def track_frame(measurement: FrameMeasurement, prediction, *, features=None,
                options: TrackingOptions | None = None) -> TrackingResult:
    """Step 2 of the loop: register the measured frame to the map's predicted surface, coarse to fine.

    Each pyramid level runs the engine's fused ICP (or point-to-plane ICP without enough feature matches) with
    projective correspondences into the prediction, from the previous level's result; the first level's fused ICP also
    tries the RANSAC start of the feature matches, so a bad prediction (tracking loss) is recovered when the features
    allow it (the fused ICP's global reach).

    Parameters
    ----------
    measurement : FrameMeasurement
        From :func:`measure_frame`.
    prediction : SurfacePrediction
        The map raycast at the predicted pose, at the resolution of the measurement's level 0.
    features : tuple (source (K, 3), target (K, 3)) of float64 ndarray, optional
        Feature matches: points in this camera's frame and the matched points in the *world* frame, metres.
    options : TrackingOptions, optional

    Returns
    -------
    TrackingResult

    Raises
    ------
    InputError
        If the prediction and the measurement differ in size.
    """
    opt = TrackingOptions() if options is None else options
    if prediction.points.shape[:2] != measurement.points[0].shape[:2]:
        raise InputError(f"the prediction is {prediction.points.shape[:2]} pixels but the measurement's level 0 is "
                         f"{measurement.points[0].shape[:2]}; raycast at the measurement's resolution")
    world_to_ref = np.linalg.inv(prediction.pose)
    fs = fd = None
    if features is not None and len(features[0]) >= opt.min_features:
        fs = np.asarray(features[0], dtype=np.float64)
        fd = np.asarray(features[1], dtype=np.float64) @ world_to_ref[:3, :3].T + world_to_ref[:3, 3]
    relative = np.eye(4)
    start, n_feat, per_level, failed = "prediction", 0, [], None
    targets = {}
    for level in reversed(range(opt.levels)):
        i = opt.levels - 1 - level  # option index, coarse to fine
        src = measurement.points[level]
        valid = np.isfinite(src[..., 2])
        src = src[valid]
        if opt.max_points and len(src) > opt.max_points:
            src = src[normal_space_sample(measurement.level_normals(level)[valid], opt.max_points)]
        tgt, nrm, strategy = targets[level] = _prediction_level(prediction, level, opt.window)
        if len(src) < 50 or len(tgt) < 50:
            failed = f"too few points at pyramid level {level} ({len(src)} measured, {len(tgt)} predicted)"
            break
        icp_options = ICPOptions(max_distance=opt.max_distance[i], max_iterations=opt.max_iterations[i],
                                 tolerance=opt.tolerance, kernel=opt.kernel, kernel_scale=opt.kernel_scale,
                                 correspondences=strategy)
        common = dict(target_normals=nrm, init=relative, options=icp_options)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DegenerateGeometryWarning)
                if fs is not None and opt.alpha[i] > 0:
                    res = fused_icp(src, tgt, source_features=fs, target_features=fd, alpha=opt.alpha[i],
                                    ransac_threshold=opt.ransac_threshold,
                                    ransac_trials=500 if i == 0 else 256, **common)
                    if i == 0 and res.info.get("start") == "ransac":
                        start = "ransac"
                    n_feat = int(res.info.get("n_feature_inliers", 0))
                    # finer levels see only the matches consistent with this level's result: their RANSAC then
                    # stops after one batch of samples
                    resid = np.linalg.norm(fs @ res.transform[:3, :3].T + res.transform[:3, 3] - fd, axis=1)
                    keep = resid < opt.ransac_threshold
                    if keep.sum() >= opt.min_features:
                        fs, fd = fs[keep], fd[keep]
                else:
                    res = icp(src, tgt, **common)
        except RegistrationError as exc:
            failed = str(exc)
            break
        relative = res.transform
        per_level.append(dict(level=level, iterations=res.n_iterations, fitness=res.fitness,
                              rmse=res.inlier_rmse))
    level0 = targets.get(0) or _prediction_level(prediction, 0, opt.window)
    return _finish(measurement, prediction, level0, relative, start, n_feat, per_level, failed, opt)


def _finish(measurement, prediction, level0, relative, start, n_feat, per_level, failed, opt):
    """Statistics, information matrix and dynamic mask at the solution."""
    valid, src, has, idx, tgt, nrm, moved, strategy = _residuals(measurement, level0, relative, opt.max_distance[-1])
    n = max(len(src), 1)
    fitness = float(has.sum()) / n
    h0, w0 = valid.shape
    dynamic = np.zeros((h0, w0), bool)
    information = np.zeros((6, 6))
    rmse = float("inf")
    if has.sum() >= 6:
        q, nv = tgt[idx[has]], nrm[idx[has]]
        diff = moved[has] - q
        rmse = float(np.sqrt(np.mean(np.einsum("ij,ij->i", diff, diff))))
        r = np.einsum("ij,ij->i", diff, nv)
        sigma = max(float(np.median(np.abs(r))) * 1.4826, 1e-3)
        w = np.minimum(1.0, opt.kernel_scale / np.maximum(np.abs(r), 1e-12))
        information = point_to_plane_information(src[has], relative, q, nv, w, sigma=sigma)
        dynamic = _dynamic_pixels(measurement, relative, tgt, nrm, strategy, opt)
    ok = failed is None and fitness >= opt.min_fitness and rmse <= opt.max_rmse
    pose = prediction.pose @ relative
    info = dict(levels=per_level, failure=failed)
    return TrackingResult(pose=pose, relative=relative, information=information, fitness=fitness,
                          inlier_rmse=rmse, n_feature_inliers=n_feat, start=start, ok=bool(ok), dynamic=dynamic,
                          info=info)


def dynamic_mask(tracking: TrackingResult, shape, scale: int, dilation: int) -> np.ndarray:
    """The full-resolution mask of pixels to fuse: not dynamic (grown by ``dilation`` pixels).

    Parameters
    ----------
    tracking : TrackingResult
    shape : (int, int)
        Full-resolution (H, W).
    scale : int
        Subsampling of level 0.
    dilation : int
        Growth of the dynamic regions, pixels.

    Returns
    -------
    (H, W) bool ndarray
        True where the pixel may be fused.
    """
    import cv2

    dyn = tracking.dynamic
    if not dyn.any():
        return np.ones(shape, bool)
    full = np.repeat(np.repeat(dyn, scale, axis=0), scale, axis=1)[: shape[0], : shape[1]]
    pad = np.zeros(shape, bool)
    pad[: full.shape[0], : full.shape[1]] = full
    if dilation > 0:
        kernel = np.ones((2 * dilation + 1, 2 * dilation + 1), np.uint8)
        pad = cv2.dilate(pad.astype(np.uint8), kernel) > 0
    return ~pad
