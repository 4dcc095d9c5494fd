"""Image matching with one interface for every method: detect, describe, match (NN + ratio + cross-check), verify.

``match_images(image1, image2, method='hog')`` is the whole chain; the steps are public as
:func:`detect_and_describe`, :func:`match_descriptors`, :func:`match_features` and
:func:`~seismo3d.features.verification.verify_matches`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._atomic import atomic_path
from .._validation import check_choice
from ..errors import InputError
from . import _kernels
from .hog_pyramid import HogPyramidParams, hog_pyramid_features
from .keypoints import Features
from .opencv import OPENCV_METHODS, opencv_features
from .verification import verify_matches

__all__ = [
    "METHODS",
    "MatchResult",
    "detect_and_describe",
    "match_descriptors",
    "match_features",
    "match_images",
    "write_matches_csv",
]

METHODS = ("hog",) + OPENCV_METHODS
VERIFY_MODELS = ("homography", "similarity")

# rows of the distance matrix computed at once (bounds memory at _BLOCK * n2 * 4 bytes)
_BLOCK = 2048


@dataclass(frozen=True)
class MatchResult:
    """Putative matches between two images and their geometric verification.

    Attributes
    ----------
    xy1, xy2 : (M, 2) float64 ndarray
        Matched ``(x, y)`` pixel positions in image 1 and image 2 (origin at the centre of the top-left pixel),
        every match that passed the ratio test and the cross-check.
    scores : (M,) float64 ndarray
        ``1 - d1 / d2`` with d1, d2 the distances to the nearest and second-nearest descriptor of image 2:
        in (0, 1], larger is more distinctive.
    indices1, indices2 : (M,) int64 ndarray
        Rows of the matched keypoints in the two :class:`~seismo3d.features.Features`.
    homography : (3, 3) float64 ndarray or None
        Fitted transform mapping image 1 pixels to image 2 pixels (homogeneous ``[x, y, 1]`` column vectors): a
        homography, or a similarity when verified with ``verify='similarity'``. None without verification or when
        the fit failed (too few or inconsistent matches).
    inliers : (M,) bool ndarray
        Matches consistent with ``homography`` (all True without verification, all False when the fit failed).
    n_putative : int
        M, the number of matches before verification.
    method : str
        The feature method used.
    """

    xy1: np.ndarray
    xy2: np.ndarray
    scores: np.ndarray
    indices1: np.ndarray
    indices2: np.ndarray
    homography: np.ndarray | None
    inliers: np.ndarray
    n_putative: int
    method: str = ""

    def __len__(self) -> int:
        return int(self.xy1.shape[0])

    @property
    def n_inliers(self) -> int:
        """Number of verified matches."""
        return int(np.count_nonzero(self.inliers))


def detect_and_describe(image, *, method: str = "hog", mask=None, max_keypoints: int | None = None,
                        params: HogPyramidParams | None = None) -> Features:
    """Detect keypoints and compute their descriptors with the HOG-pyramid or an OpenCV method.

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        Grey image of any real dtype, or RGB colour (converted to luma, see :func:`~seismo3d.features.to_gray`).
    method : {'hog', 'sift', 'orb', 'akaze', 'brisk'}
        ``'hog'``: the HOG-pyramid of method.md section 2 (:func:`~seismo3d.features.hog_pyramid_features`); the
        others: OpenCV (:func:`~seismo3d.features.opencv_features`). SURF is patented and absent from the OpenCV
        wheels.
    mask : (H, W) array_like of bool, optional
        Where keypoints may be detected.
    max_keypoints : int, optional
        Keep at most this many keypoints (default: the method's own; 6000 for ``'hog'``, before the extra
        descriptors of keypoints with two dominant orientations).
    params : HogPyramidParams, optional
        Parameters of ``'hog'`` (ignored by the other methods).

    Returns
    -------
    features : Features
        Empty (N = 0) when the image has no usable structure (e.g. constant).

    Raises
    ------
    InputError
        If the image is empty, smaller than 2 x 2, contains NaN or inf, has 4 channels, or the method is unknown.
    """
    check_choice(method, "method", METHODS)
    if method == "hog":
        p = HogPyramidParams() if params is None else params
        if max_keypoints is not None:
            if int(max_keypoints) < 1:
                raise InputError(f"max_keypoints must be >= 1 or None; got {max_keypoints!r}")
            p = replace(p, max_keypoints=int(max_keypoints))
        return hog_pyramid_features(image, params=p, mask=mask)
    return opencv_features(image, method=method, mask=mask, max_keypoints=max_keypoints)


def match_descriptors(descriptors1, descriptors2, *, binary: bool = False, ratio: float = 0.8,
                      cross_check: bool = True):
    """Nearest-neighbour matching with Lowe's ratio test and a mutual (cross) check, by exhaustive search.

    Parameters
    ----------
    descriptors1 : (N1, D) array_like
        Descriptors of image 1 (float, Euclidean distance; or packed-bit uint8 with ``binary=True``).
    descriptors2 : (N2, D) array_like
        Descriptors of image 2, same D and kind.
    binary : bool
        Compare packed bits with the Hamming distance (ORB, AKAZE, BRISK) instead of the Euclidean distance.
    ratio : float
        Keep a match when ``d1 < ratio * d2`` (nearest over second-nearest distance in image 2), in (0, 1]; 1 turns
        the test off. Lowe's 0.8 by default.
    cross_check : bool
        Keep a match only if the image-1 descriptor is also the nearest neighbour of its match in image 1.

    Returns
    -------
    index1, index2 : (M,) int64 ndarray
        Matched rows of ``descriptors1`` and ``descriptors2``, ascending in ``index1``.
    ratios : (M,) float64 ndarray
        ``d1 / d2`` of each match (0 for an exact duplicate).

    Raises
    ------
    InputError
        If the descriptor widths differ or ``ratio`` is outside (0, 1].

    References
    ----------
    D. G. Lowe, "Distinctive image features from scale-invariant keypoints", IJCV 60 (2004), section 7.1,
    doi:10.1023/B:VISI.0000029664.99615.94.
    """
    d1 = np.asarray(descriptors1)
    d2 = np.asarray(descriptors2)
    if d1.ndim != 2 or d2.ndim != 2 or d1.shape[1] != d2.shape[1]:
        raise InputError(f"descriptors must be (N, D) arrays of one width D; got {d1.shape} and {d2.shape}")
    if not 0 < ratio <= 1:
        raise InputError(f"ratio must be in (0, 1]; got {ratio!r} (0.8 is Lowe's choice, 1 disables the test)")
    empty = np.zeros(0, np.int64)
    if d1.shape[0] == 0 or d2.shape[0] < 2:
        return empty, empty.copy(), np.zeros(0)
    if binary:
        if d1.dtype != np.uint8 or d2.dtype != np.uint8:
            raise InputError("binary descriptors must be packed bits (uint8)")
        a = np.unpackbits(d1, axis=1).astype(np.float32)
        b = np.unpackbits(d2, axis=1).astype(np.float32)
    else:
        a = np.ascontiguousarray(d1, dtype=np.float32)
        b = np.ascontiguousarray(d2, dtype=np.float32)
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            raise InputError("descriptors contain NaN or inf")
    n1, n2 = a.shape[0], b.shape[0]
    nn = np.empty(n1, np.int64)
    best = np.empty(n1, np.float32)
    second = np.empty(n1, np.float32)
    col_idx = np.full(n2, -1, np.int64)
    col_best = np.full(n2, np.inf, np.float32)
    blk_idx = np.empty(n2, np.int64)
    blk_best = np.empty(n2, np.float32)
    a_sq = np.einsum("ij,ij->i", a, a)
    b_sq = np.einsum("ij,ij->i", b, b)
    for start in range(0, n1, _BLOCK):
        stop = min(start + _BLOCK, n1)
        gram = a[start:stop] @ b.T
        _kernels.two_nearest(gram, a_sq[start:stop], b_sq, not binary, nn[start:stop], best[start:stop],
                             second[start:stop], blk_idx, blk_best)
        better = blk_best < col_best
        col_best[better] = blk_best[better]
        col_idx[better] = blk_idx[better] + start
    ratios = np.divide(best, second, out=np.ones(n1, np.float64), where=second > 0).astype(np.float64)
    keep = ratios < ratio if ratio < 1 else np.ones(n1, bool)
    if cross_check:
        keep &= col_idx[nn] == np.arange(n1)
    idx1 = np.nonzero(keep)[0].astype(np.int64)
    return idx1, nn[idx1], ratios[idx1]


def match_features(features1: Features, features2: Features, *, ratio: float = 0.8, cross_check: bool = True,
                   verify: str | None = "homography", threshold: float = 3.0) -> MatchResult:
    """Match two feature sets and optionally verify the matches geometrically.

    Parameters
    ----------
    features1, features2 : Features
        From :func:`detect_and_describe` with the same method.
    ratio, cross_check
        See :func:`match_descriptors`.
    verify : {'homography', 'similarity', None}
        Geometric model fitted robustly to the matches (:func:`~seismo3d.features.verification.verify_matches`):
        a plane or a rotating camera (homography), or a rotation + scale + shift such as a seismic section against
        its neighbour (similarity); None skips verification.
    threshold : float
        Largest reprojection error of an inlier, in pixels of image 2.

    Returns
    -------
    result : MatchResult

    Raises
    ------
    InputError
        If the two feature sets come from different methods or the options are invalid.
    """
    if not isinstance(features1, Features) or not isinstance(features2, Features):
        raise InputError("features1 and features2 must be Features from detect_and_describe")
    if features1.method != features2.method or features1.descriptors.shape[1] != features2.descriptors.shape[1]:
        raise InputError(f"cannot match {features1.method!r} features against {features2.method!r} features; "
                         "describe both images with the same method")
    if verify is not None:
        check_choice(verify, "verify", VERIFY_MODELS)
    i1, i2, ratios = match_descriptors(features1.descriptors, features2.descriptors, binary=features1.binary,
                                       ratio=ratio, cross_check=cross_check)
    m = i1.size
    result = MatchResult(
        xy1=features1.keypoints[i1].copy(),
        xy2=features2.keypoints[i2].copy(),
        scores=1.0 - ratios,
        indices1=i1,
        indices2=i2,
        homography=None,
        inliers=np.ones(m, bool),
        n_putative=int(m),
        method=features1.method,
    )
    if verify is None:
        return result
    return verify_matches(result, model=verify, threshold=threshold)


def match_images(image1, image2, *, method: str = "hog", ratio: float = 0.8, cross_check: bool = True,
                 verify: str | None = "homography", threshold: float = 3.0, mask1=None, mask2=None,
                 max_keypoints: int | None = None, params: HogPyramidParams | None = None) -> MatchResult:
    """Match two images: detect and describe both, match descriptors, verify geometrically.

    Parameters
    ----------
    image1, image2 : (H, W) or (H, W, 3) array_like
        Grey images of any real dtype, or RGB colour (converted to luma). Seismic sections are images with traces
        along x and samples along y.
    method : {'hog', 'sift', 'orb', 'akaze', 'brisk'}
        Feature method, see :func:`detect_and_describe`.
    ratio : float
        Lowe's ratio-test threshold in (0, 1] (default 0.8).
    cross_check : bool
        Keep only mutual nearest neighbours (default True).
    verify : {'homography', 'similarity', None}
        Geometric verification model (default ``'homography'``).
    threshold : float
        Inlier reprojection error in pixels (default 3).
    mask1, mask2 : (H, W) array_like of bool, optional
        Where keypoints may be detected in each image.
    max_keypoints : int, optional
        Keypoints kept per image (default: the method's default).
    params : HogPyramidParams, optional
        Parameters of the ``'hog'`` method.

    Returns
    -------
    result : MatchResult
        Empty (M = 0) when either image has no usable structure (e.g. constant).

    Raises
    ------
    InputError
        If an image is empty, smaller than 2 x 2, contains NaN or inf, has 4 channels, or an option is invalid.

    Examples
    --------
    >>> import numpy as np, skimage.data
    >>> from seismo3d.features import match_images
    >>> img = skimage.data.camera()
    >>> result = match_images(img, np.rot90(img).copy(), method="hog")
    >>> result.n_inliers > 100
    True
    """
    check_choice(method, "method", METHODS)
    if verify is not None:
        check_choice(verify, "verify", VERIFY_MODELS)
    f1 = detect_and_describe(image1, method=method, mask=mask1, max_keypoints=max_keypoints, params=params)
    f2 = detect_and_describe(image2, method=method, mask=mask2, max_keypoints=max_keypoints, params=params)
    return match_features(f1, f2, ratio=ratio, cross_check=cross_check, verify=verify, threshold=threshold)


def write_matches_csv(path, result: MatchResult, *, inliers_only: bool = True) -> int:
    """Write matches as CSV with the header ``x1,y1,x2,y2,score``, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Output file; written to a temporary file in the same directory, then renamed over ``path``.
    result : MatchResult
        Matches to write.
    inliers_only : bool
        Write only the verified matches (``result.inliers``), the default; False writes every putative match.

    Returns
    -------
    n_rows : int
        Number of matches written.

    Raises
    ------
    InputError
        If ``result`` is not a MatchResult.
    OSError
        If the directory is not writable.
    """
    if not isinstance(result, MatchResult):
        raise InputError("result must be a MatchResult from match_images or match_features")
    sel = result.inliers if inliers_only else np.ones(len(result), bool)
    table = np.column_stack([result.xy1[sel], result.xy2[sel], result.scores[sel]])
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        fh.write("x1,y1,x2,y2,score\n")
        for row in table:
            fh.write(",".join(f"{v:.6g}" if j == 4 else f"{v:.3f}" for j, v in enumerate(row)) + "\n")
    return int(table.shape[0])
