"""Visual features of the mapping loop and the landmarks they become.

Each frame's colour image is described by the features module (ORB by default: fast enough for every frame) and
each keypoint is lifted to 3D through the depth image (:func:`frame_features`). The frame is matched to the last
keyframe (:func:`match_to_keyframe`): the matches are the feature term of the fused ICP (eq. 16) and, through the
keyframe's landmark identifiers, the landmark measurements of the Kalman filter. A landmark is a feature matched in
two or more keyframes (:class:`LandmarkTable` keeps which keyframe feature is which landmark and how often it was seen),
as in ORB-SLAM's map points (Mur-Artal et al. 2015).

References
----------
Rublee, E., Rabaud, V., Konolige, K., Bradski, G. (2011). ORB: An efficient alternative to SIFT or SURF. ICCV,
2564-2571. doi:10.1109/ICCV.2011.6126544
Mur-Artal, R., Montiel, J. M. M., Tardos, J. D. (2015). ORB-SLAM: a versatile and accurate monocular SLAM system.
IEEE T-RO 31(5), 1147-1163. doi:10.1109/TRO.2015.2463671
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace as dc_replace

import numpy as np

from .._validation import check_choice
from ..errors import InputError

__all__ = ["FeatureOptions", "FrameFeatures", "FeatureMatches", "frame_features", "match_to_keyframe",
           "LandmarkTable"]


@dataclass(frozen=True)
class FeatureOptions:
    """Options of the per-frame features.

    Attributes
    ----------
    method : {'orb', 'sift', 'akaze', 'brisk', 'hog'}
        Detector and descriptor (:func:`seismo3d.features.detect_and_describe`).
    max_keypoints : int
        Keypoints per frame.
    ratio : float
        Lowe's ratio test of the matching.
    max_depth : float
        Keypoints deeper than this (metres) are not lifted.
    """

    method: str = "orb"
    max_keypoints: int = 800
    ratio: float = 0.8
    max_depth: float = 4.0

    def __post_init__(self):
        check_choice(self.method, "method", {"orb", "sift", "akaze", "brisk", "hog"})
        if int(self.max_keypoints) < 8:
            raise InputError(f"max_keypoints must be >= 8; got {self.max_keypoints!r}")


@dataclass(frozen=True, eq=False)
class FrameFeatures:
    """Keypoints of one frame that have depth, with their descriptors and camera-frame 3D points.

    Attributes
    ----------
    keypoints : (K, 2) float64 ndarray
        ``(x, y)`` pixels.
    descriptors : (K, D) ndarray
        As :class:`seismo3d.features.Features`.
    points : (K, 3) float64 ndarray
        Camera-frame points, metres.
    features : Features
        The described keypoints (only those with depth), for :func:`seismo3d.features.match_features`.
    """

    keypoints: np.ndarray
    descriptors: np.ndarray
    points: np.ndarray
    features: object

    def __len__(self) -> int:
        return int(len(self.points))


@dataclass(frozen=True)
class FeatureMatches:
    """Matches of a frame's features to a keyframe's.

    Attributes
    ----------
    frame_index, keyframe_index : (M,) int64 ndarray
        Rows of the frame's and the keyframe's :class:`FrameFeatures`.
    """

    frame_index: np.ndarray
    keyframe_index: np.ndarray

    def __len__(self) -> int:
        return int(len(self.frame_index))


def frame_features(color, depth, intrinsics, options: FeatureOptions | None = None) -> FrameFeatures:
    """Detect and describe keypoints of the colour image and lift those with depth to 3D.

    Parameters
    ----------
    color : (H, W, 3) uint8 ndarray or None
        RGB image (None: no features).
    depth : (H, W) float array
        Depth in metres, NaN where invalid (registered to the colour image, or close to it).
    intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
        Pixels.
    options : FeatureOptions, optional

    Returns
    -------
    FrameFeatures
        Possibly empty (K = 0).
    """

    from ..features import Features, detect_and_describe, lift_matches_depth

    opt = FeatureOptions() if options is None else options
    if color is None:
        empty = Features.empty(opt.method, 32, binary=opt.method != "sift" and opt.method != "hog")
        return FrameFeatures(np.zeros((0, 2)), empty.descriptors, np.zeros((0, 3)), empty)
    feats = detect_and_describe(color, method=opt.method, max_keypoints=opt.max_keypoints)
    depth = np.where(np.isfinite(depth), depth, 0.0)
    points, index = lift_matches_depth(feats.keypoints, depth, intrinsics, max_depth=opt.max_depth)
    kept = dc_replace(feats, keypoints=feats.keypoints[index], descriptors=feats.descriptors[index],
                      scales=feats.scales[index], orientations=feats.orientations[index],
                      responses=feats.responses[index])
    return FrameFeatures(kept.keypoints, kept.descriptors, points, kept)


def match_to_keyframe(frame: FrameFeatures, keyframe: FrameFeatures, *, ratio: float = 0.8) -> FeatureMatches:
    """Match a frame's features to a keyframe's (ratio test and mutual check, no image-space model: the fused ICP's
    RANSAC verifies them in 3D).

    Returns
    -------
    FeatureMatches
    """
    from ..features import match_features

    if len(frame) < 2 or len(keyframe) < 2:
        return FeatureMatches(np.zeros(0, np.int64), np.zeros(0, np.int64))
    result = match_features(frame.features, keyframe.features, ratio=ratio, verify=None)
    return FeatureMatches(np.asarray(result.indices1, np.int64), np.asarray(result.indices2, np.int64))


@dataclass
class LandmarkTable:
    """Which keyframe feature is which landmark.

    Attributes
    ----------
    ids : dict
        ``keyframe id -> (K,) int64 ndarray`` of landmark identifiers per feature (-1: none yet).
    observations : dict
        ``landmark id -> number of keyframes that saw it``.
    """

    ids: dict = field(default_factory=dict)
    observations: dict = field(default_factory=dict)
    next_id: int = 0

    def add_keyframe(self, keyframe_id: int, n_features: int) -> None:
        """Register a keyframe's features (no landmark yet)."""
        self.ids[int(keyframe_id)] = np.full(int(n_features), -1, np.int64)

    def link(self, keyframe_id: int, previous_id: int, matches: FeatureMatches, inliers) -> list:
        """Give the new keyframe's matched features the previous keyframe's landmarks, creating new landmarks for
        matched features that had none.

        Parameters
        ----------
        keyframe_id, previous_id : int
            The new keyframe and the keyframe it was matched to.
        matches : FeatureMatches
            The new keyframe's features (``frame_index``) against the previous keyframe's.
        inliers : (M,) bool array_like
            Matches consistent with the estimated motion.

        Returns
        -------
        list of (landmark id, feature row, is_new)
            The landmarks the new keyframe observes.
        """
        new_ids, old_ids = self.ids[int(keyframe_id)], self.ids[int(previous_id)]
        out = []
        for fi, ki, ok in zip(matches.frame_index, matches.keyframe_index, np.asarray(inliers, bool)):
            if not ok or new_ids[fi] >= 0:
                continue
            lid = int(old_ids[ki])
            is_new = lid < 0
            if is_new:
                lid = self.next_id
                self.next_id += 1
                old_ids[ki] = lid
                self.observations[lid] = 1
            new_ids[fi] = lid
            self.observations[lid] = self.observations.get(lid, 0) + 1
            out.append((lid, int(fi), is_new))
        return out

    @property
    def n_landmarks(self) -> int:
        """Landmarks seen from two or more keyframes."""
        return int(sum(1 for n in self.observations.values() if n >= 2))
