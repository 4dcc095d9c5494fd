"""Image features: the HOG-pyramid matcher of method.md section 2, OpenCV adapters, verification and evaluation.

One interface for every method::

    features = detect_and_describe(image, method="hog")          # or 'sift', 'orb', 'akaze', 'brisk'
    result = match_images(image1, image2, method="hog", verify="homography")

SURF is patented and excluded from the OpenCV wheels, so it is not available (its benchmark row stays empty).
"""

from .evaluation import (
    MatchEvaluation,
    evaluate_matches,
    reprojection_errors,
    rotation_homography,
    scale_homography,
    tilt_homography,
    timed_match,
    warp_image,
)
from .hog_pyramid import (
    HogPyramidParams,
    dense_ring_histograms,
    disc_half_widths,
    hog_pyramid_features,
    orientation_votes,
    ring_descriptors,
    ring_histograms,
)
from .keypoints import Features, harris_peaks, harris_response, image_pyramid, to_gray
from .matching import (
    METHODS,
    MatchResult,
    detect_and_describe,
    match_descriptors,
    match_features,
    match_images,
    write_matches_csv,
)
from .opencv import OPENCV_METHODS, opencv_features, to_uint8
from .verification import (
    fit_homography,
    fit_similarity_2d,
    lift_match_pairs,
    lift_matches_depth,
    lift_matches_section,
    verify_matches,
)

__all__ = [
    "METHODS", "OPENCV_METHODS", "Features", "HogPyramidParams", "MatchEvaluation", "MatchResult",
    "dense_ring_histograms", "detect_and_describe", "disc_half_widths", "evaluate_matches",
    "fit_homography", "fit_similarity_2d", "harris_peaks", "harris_response", "hog_pyramid_features",
    "image_pyramid", "lift_match_pairs", "lift_matches_depth", "lift_matches_section", "match_descriptors",
    "match_features", "match_images", "opencv_features", "orientation_votes", "reprojection_errors",
    "ring_descriptors", "ring_histograms", "rotation_homography", "scale_homography", "tilt_homography",
    "timed_match", "to_gray", "to_uint8", "verify_matches", "warp_image", "write_matches_csv",
]
