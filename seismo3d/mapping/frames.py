"""RGB-D frame-to-frame registration: depth -> points and normals -> features lifted through depth -> fused ICP.

Steps 1 and 2 of the method's robot-mapping pipeline (method.md section 3): measure a depth map, back-project it,
compute normals, then estimate the camera motion by the fused ICP between the two surfaces.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_positive
from ..errors import InputError
from ..geometry import backproject_depth, normals_from_points_image, voxel_downsample
from ..registration import fused_icp, icp

__all__ = ["frame_points", "frame_feature_matches", "register_frames"]


def _frame_parts(frame, name):
    for attr in ("depth", "intrinsics"):
        if not hasattr(frame, attr):
            raise InputError(f"{name} must be an RGB-D frame with .color, .depth (metres) and .intrinsics, e.g. from "
                             "seismo3d.data.load_7scenes_frame")
    return frame


def frame_points(depth, intrinsics, *, voxel_size: float | None = 0.01, max_depth: float | None = None):
    """Camera-frame points and normals of a depth image, optionally voxel-downsampled.

    Parameters
    ----------
    depth : (H, W) array_like
        Depth in metres; 0 or NaN where invalid.
    intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
        Pinhole intrinsics in pixels.
    voxel_size : float or None
        Edge of the downsampling voxel in metres (None keeps every valid pixel).
    max_depth : float, optional
        Ignore pixels farther than this (metres).

    Returns
    -------
    points : (N, 3) float64 ndarray
        Metres, camera frame (x right, y down, z forward).
    normals : (N, 3) float64 ndarray
        Unit normals facing the camera (central differences on the organised image, KinectFusion-style).
    """
    pts = backproject_depth(depth, intrinsics)
    if max_depth is not None:
        pts[pts[..., 2] > check_positive(max_depth, "max_depth")] = np.nan
    nrm = normals_from_points_image(pts)
    ok = np.isfinite(pts).all(axis=-1) & np.isfinite(nrm).all(axis=-1)
    pts, nrm = pts[ok], nrm[ok]
    if voxel_size is not None and len(pts):
        pts, nrm = voxel_downsample(pts, voxel_size, values=nrm)
        nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    return pts, nrm


def frame_feature_matches(source_frame, target_frame, *, method: str = "sift", ratio: float = 0.8,
                          max_keypoints: int | None = None):
    """Match two RGB-D frames' colour images and lift the matches to 3D through their depth images.

    Matches are not verified in the image (a homography does not hold for a 3D scene); the fused ICP's RANSAC
    verifies them in 3D.

    Parameters
    ----------
    source_frame, target_frame : RGBDFrame
        Frames with ``color`` (H, W, 3) uint8, ``depth`` (H, W) metres and ``intrinsics``.
    method : {'sift', 'orb', 'akaze', 'brisk', 'hog'}
        Feature method of :func:`seismo3d.features.match_images`.
    ratio : float
        Lowe's ratio-test threshold.
    max_keypoints : int, optional
        Keypoints per image.

    Returns
    -------
    source_points, target_points : (K, 3) float64 ndarray
        Paired camera-frame points in metres.
    """
    from ..features import match_images
    from ..features.verification import lift_match_pairs

    check_choice(method, "method", {"sift", "orb", "akaze", "brisk", "hog"})
    src = _frame_parts(source_frame, "source_frame")
    dst = _frame_parts(target_frame, "target_frame")
    result = match_images(src.color, dst.color, method=method, ratio=ratio, verify=None, max_keypoints=max_keypoints)
    p1, p2, _ = lift_match_pairs(result, src.depth, dst.depth, src.intrinsics, dst.intrinsics, inliers_only=False)
    return p1, p2


def register_frames(source_frame, target_frame, *, method: str = "fused", init=None, voxel_size: float = 0.01,
                    alpha: float = 0.1, feature_method: str = "sift", max_distance=None, seed: int = 0):
    """Camera motion between two RGB-D frames: the transform mapping source-camera into target-camera coordinates.

    Parameters
    ----------
    source_frame, target_frame : RGBDFrame
        Frames with ``color``, ``depth`` (metres) and ``intrinsics``.
    method : {'fused', 'point_to_plane'}
        Fused ICP (SIFT/HOG matches through depth + dense point-to-plane, eq. 16, RANSAC start) or point-to-plane
        ICP alone from ``init``.
    init : (4, 4) array_like, optional
        Prior motion (e.g. a Kalman prediction); identity when None.
    voxel_size : float
        Downsampling voxel in metres.
    alpha : float
        Feature weight of the fused objective.
    feature_method : str
        See :func:`frame_feature_matches`.
    max_distance : float or sequence, optional
        Correspondence distance schedule in metres (default: derived from the target cloud).
    seed : int
        RANSAC seed.

    Returns
    -------
    RegistrationResult
        ``transform`` is T_target<-source; with camera-to-world poses, ``inv(P_target) @ P_source``.
    """
    check_choice(method, "method", {"fused", "point_to_plane"})
    src = _frame_parts(source_frame, "source_frame")
    dst = _frame_parts(target_frame, "target_frame")
    sp, _ = frame_points(src.depth, src.intrinsics, voxel_size=voxel_size)
    tp, tn = frame_points(dst.depth, dst.intrinsics, voxel_size=voxel_size)
    if method == "point_to_plane":
        return icp(sp, tp, target_normals=tn, init=init, max_distance=max_distance)
    fs, fd = frame_feature_matches(src, dst, method=feature_method)
    return fused_icp(sp, tp, target_normals=tn, source_features=fs, target_features=fd, alpha=alpha, init=init,
                     max_distance=max_distance, seed=seed)
