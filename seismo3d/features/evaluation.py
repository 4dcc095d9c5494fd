"""Evaluation of image matches against a ground-truth homography, and the synthetic views of the paper's Tables 2-4.

A match is correct when image 1's point, mapped by the ground-truth homography, falls within 3 pixels of its match
in image 2 (the criterion of the paper's Tables 2-4; Mikolajczyk et al. [1] use the same overlap-free test for
point matches). The views: in-plane rotation about the image centre (Table 2), out-of-plane rotation of the scene
plane about an in-plane axis through the image centre seen by a pinhole camera (Table 3), and scaling about the image
centre (Table 4).

References
----------
.. [1] K. Mikolajczyk, C. Schmid, "A performance evaluation of local descriptors", IEEE TPAMI 27 (2005),
   doi:10.1109/TPAMI.2005.188.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._validation import as_image, as_pair, check_choice, check_positive
from ..errors import InputError
from .matching import match_images

__all__ = [
    "MatchEvaluation",
    "reprojection_errors",
    "evaluate_matches",
    "timed_match",
    "rotation_homography",
    "tilt_homography",
    "scale_homography",
    "warp_image",
]


@dataclass(frozen=True)
class MatchEvaluation:
    """Correctness of a set of matches under a ground-truth homography.

    Attributes
    ----------
    n_matches : int
        Matches evaluated.
    n_correct : int
        Matches with reprojection error below the threshold.
    fraction_correct : float
        ``n_correct / n_matches`` in [0, 1] (NaN when there is no match).
    median_error : float
        Median reprojection error in pixels of image 2 (NaN when there is no match).
    seconds : float
        Wall-clock time of the matching, when measured (:func:`timed_match`), else NaN.
    """

    n_matches: int
    n_correct: int
    fraction_correct: float
    median_error: float
    seconds: float = float("nan")

    @property
    def percent_correct(self) -> float:
        """``100 * fraction_correct``."""
        return 100.0 * self.fraction_correct


def _as_homography(h, name="homography"):
    m = np.asarray(h, dtype=np.float64)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        raise InputError(f"{name} must be a finite (3, 3) matrix; got shape {m.shape}")
    return m


def reprojection_errors(xy1, xy2, homography) -> np.ndarray:
    """Distance between ``H(xy1)`` and ``xy2`` for every match.

    Parameters
    ----------
    xy1, xy2 : (M, 2) array_like of float
        Matched pixel positions in image 1 and image 2.
    homography : (3, 3) array_like
        Ground truth mapping image 1 onto image 2 (``[x2, y2, 1] ~ H @ [x1, y1, 1]``).

    Returns
    -------
    errors : (M,) float64 ndarray
        Euclidean errors in pixels of image 2 (inf for points mapped to infinity).
    """
    h = _as_homography(homography)
    if np.asarray(xy1).size == 0 and np.asarray(xy2).size == 0:
        return np.zeros(0)
    a, b = as_pair(xy1, xy2, dims=(2,), names=("xy1", "xy2"))
    p = np.column_stack([a, np.ones(a.shape[0])]) @ h.T
    with np.errstate(divide="ignore", invalid="ignore"):
        q = p[:, :2] / p[:, 2:]
    err = np.linalg.norm(q - b, axis=1)
    return np.where(np.isfinite(err), err, np.inf)


def evaluate_matches(xy1, xy2, homography, *, threshold: float = 3.0, seconds: float = float("nan")) -> MatchEvaluation:
    """Count the matches consistent with a ground-truth homography.

    Parameters
    ----------
    xy1, xy2 : (M, 2) array_like of float
        Matched pixel positions (e.g. ``result.xy1``, or ``result.xy1[result.inliers]`` after verification).
    homography : (3, 3) array_like
        Ground truth from image 1 to image 2.
    threshold : float
        A match is correct when its reprojection error is below this many pixels (3 in the paper).
    seconds : float
        Time to record with the evaluation.

    Returns
    -------
    evaluation : MatchEvaluation
    """
    check_positive(threshold, "threshold")
    err = reprojection_errors(xy1, xy2, homography)
    n = int(err.size)
    correct = int(np.count_nonzero(err < threshold))
    return MatchEvaluation(
        n_matches=n,
        n_correct=correct,
        fraction_correct=correct / n if n else float("nan"),
        median_error=float(np.median(err)) if n else float("nan"),
        seconds=float(seconds),
    )


def timed_match(image1, image2, homography, *, threshold: float = 3.0, use_inliers: bool = False, **match_options):
    """Run :func:`~seismo3d.features.match_images`, time it, and evaluate it against a ground truth.

    Parameters
    ----------
    image1, image2 : (H, W) or (H, W, 3) array_like
        The image pair.
    homography : (3, 3) array_like
        Ground truth mapping image 1 onto image 2.
    threshold : float
        Correctness threshold in pixels.
    use_inliers : bool
        Evaluate only the verified matches (``result.inliers``) instead of all matches returned by the ratio test and
        cross-check.
    **match_options
        Passed to :func:`~seismo3d.features.match_images` (``method``, ``ratio``, ``verify``, masks, ...).

    Returns
    -------
    result : MatchResult
    evaluation : MatchEvaluation
        With ``seconds`` = wall-clock time of detection, description, matching and verification of the pair.
    """
    start = time.perf_counter()
    result = match_images(image1, image2, **match_options)
    seconds = time.perf_counter() - start
    sel = result.inliers if use_inliers else np.ones(len(result), bool)
    return result, evaluate_matches(result.xy1[sel], result.xy2[sel], homography, threshold=threshold,
                                    seconds=seconds)


def _centre(shape):
    if len(shape) < 2 or min(shape[:2]) < 1:
        raise InputError(f"shape must be (rows, cols); got {shape!r}")
    h, w = shape[:2]
    return (w - 1) / 2.0, (h - 1) / 2.0


def rotation_homography(shape, angle_deg: float) -> np.ndarray:
    """Rotation of an image about its centre (the view of the paper's Table 2).

    Parameters
    ----------
    shape : tuple
        ``(rows, cols)`` of the image.
    angle_deg : float
        Rotation in degrees, counter-clockwise as displayed (y axis down), as ``cv2.getRotationMatrix2D``.

    Returns
    -------
    homography : (3, 3) float64 ndarray
        Maps pixels of the original onto the rotated image.
    """
    cx, cy = _centre(shape)
    t = np.deg2rad(angle_deg)
    c, s = np.cos(t), np.sin(t)
    # counter-clockwise on screen with y down: x' = c x + s y, y' = -s x + c y about the centre
    return np.array([[c, s, cx - c * cx - s * cy], [-s, c, cy + s * cx - c * cy], [0.0, 0.0, 1.0]])


def scale_homography(shape, factor: float) -> np.ndarray:
    """Uniform scaling of an image about its centre (the view of the paper's Table 4).

    Parameters
    ----------
    shape : tuple
        ``(rows, cols)`` of the image.
    factor : float
        Scale factor (> 0); 1.2 enlarges the content by 20 %.

    Returns
    -------
    homography : (3, 3) float64 ndarray
    """
    cx, cy = _centre(shape)
    s = check_positive(factor, "factor")
    return np.array([[s, 0.0, cx * (1 - s)], [0.0, s, cy * (1 - s)], [0.0, 0.0, 1.0]])


def tilt_homography(shape, angle_deg: float, *, focal: float | None = None, axis: str = "vertical") -> np.ndarray:
    """Out-of-plane rotation: the homography of a fronto-parallel scene plane rotated about an in-plane axis.

    The image is taken as a plane facing a pinhole camera of focal length ``f`` (pixels) at distance ``f``, so that
    plane coordinates equal pixel offsets from the centre. The plane is rotated by ``angle_deg`` about the axis
    through the image centre (the point where the optical axis pierces it) and viewed by the same camera:
    ``H = K [r1 r2 t] C`` with ``K = [[f, 0, cx], [0, f, cy], [0, 0, 1]]``, ``r1, r2`` the first two columns of the
    rotation, ``t = (0, 0, f)`` and ``C`` the shift of the image centre to the origin (the view of the paper's
    Table 3). Equivalently, the camera orbits about the image centre at distance ``f``. The centre stays fixed; one
    half of the image is foreshortened and shrunk, the other enlarged.

    Parameters
    ----------
    shape : tuple
        ``(rows, cols)`` of the image.
    angle_deg : float
        Rotation of the plane in degrees (|angle| < 90).
    focal : float, optional
        Focal length in pixels (default: the image width).
    axis : {'vertical', 'horizontal'}
        The in-plane axis of rotation: the image's vertical (column) or horizontal (row) centre line.

    Returns
    -------
    homography : (3, 3) float64 ndarray
        Normalised with ``H[2, 2] = 1``.
    """
    check_choice(axis, "axis", ("vertical", "horizontal"))
    if not abs(angle_deg) < 90:
        raise InputError(f"angle_deg must be in (-90, 90) for the plane to stay in view; got {angle_deg!r}")
    cx, cy = _centre(shape)
    f = float(shape[1]) if focal is None else check_positive(focal, "focal")
    t = np.deg2rad(angle_deg)
    c, s = np.cos(t), np.sin(t)
    if axis == "vertical":
        rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    else:
        rot = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    k = np.array([[f, 0.0, cx], [0.0, f, cy], [0.0, 0.0, 1.0]])
    to_centre = np.array([[1.0, 0.0, -cx], [0.0, 1.0, -cy], [0.0, 0.0, 1.0]])
    h = k @ np.column_stack([rot[:, 0], rot[:, 1], [0.0, 0.0, f]]) @ to_centre
    return h / h[2, 2]


def warp_image(image, homography, *, output_shape=None):
    """Warp an image by a homography (bilinear), returning the warped image and its valid-pixel mask.

    Parameters
    ----------
    image : (H, W) array_like
        Grey image (uint8 is kept as uint8; other dtypes are warped as float64).
    homography : (3, 3) array_like
        Maps input pixels onto output pixels.
    output_shape : tuple, optional
        ``(rows, cols)`` of the output (default: the input's).

    Returns
    -------
    warped : (rows, cols) ndarray
        Zero outside the warped input.
    valid : (rows, cols) bool ndarray
        True where the output pixel comes from inside the input.
    """
    import cv2

    arr = np.asarray(image)
    img = arr if arr.dtype == np.uint8 and arr.ndim == 2 else as_image(arr)
    h = _as_homography(homography)
    rows, cols = img.shape if output_shape is None else tuple(int(v) for v in output_shape)
    warped = cv2.warpPerspective(img, h, (cols, rows), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                                 borderValue=0)
    ones = np.full(img.shape, 255, np.uint8)
    valid = cv2.warpPerspective(ones, h, (cols, rows), flags=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT,
                                borderValue=0) > 0
    return warped, valid
