"""OpenCV feature detectors behind the one interface of :func:`~seismo3d.features.detect_and_describe`.

SIFT [1], ORB [2], AKAZE [3] and BRISK [4] from ``opencv-contrib-python-headless`` (OpenCV 4.4+ has SIFT in the main
module; OpenCV 5 moved AKAZE and BRISK to ``cv2.xfeatures2d``; both layouts are supported). SURF [5] is patented
and excluded from the OpenCV wheels (``OPENCV_ENABLE_NONFREE`` is off), so it is not offered here and its row in
``benchmarks/matching.py`` stays empty.

References
----------
.. [1] D. G. Lowe, "Distinctive image features from scale-invariant keypoints", IJCV 60 (2004),
   doi:10.1023/B:VISI.0000029664.99615.94.
.. [2] E. Rublee, V. Rabaud, K. Konolige, G. Bradski, "ORB: an efficient alternative to SIFT or SURF", ICCV 2011,
   doi:10.1109/ICCV.2011.6126544.
.. [3] P. F. Alcantarilla, J. Nuevo, A. Bartoli, "Fast explicit diffusion for accelerated features in nonlinear
   scale spaces", BMVC 2013, doi:10.5244/C.27.13.
.. [4] S. Leutenegger, M. Chli, R. Y. Siegwart, "BRISK: binary robust invariant scalable keypoints", ICCV 2011,
   doi:10.1109/ICCV.2011.6126542.
.. [5] H. Bay, A. Ess, T. Tuytelaars, L. Van Gool, "Speeded-up robust features (SURF)", CVIU 110 (2008),
   doi:10.1016/j.cviu.2007.09.014.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice
from ..errors import InputError
from .keypoints import Features, to_gray

__all__ = ["OPENCV_METHODS", "to_uint8", "opencv_features"]

OPENCV_METHODS = ("sift", "orb", "akaze", "brisk")

# descriptor length of each method (float values for SIFT, bytes of packed bits for the binary ones)
_N_DIMS = {"sift": 128, "orb": 32, "akaze": 61, "brisk": 64}

# ORB keeps 500 keypoints unless told otherwise, too few for a 640 x 480 frame; SIFT, AKAZE and BRISK keep all.
_ORB_DEFAULT_KEYPOINTS = 2000


def to_uint8(image) -> np.ndarray:
    """Convert a grey or RGB image to the 8-bit grey levels OpenCV's detectors need.

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        uint8 images are used as they are (RGB converted to luma); any other dtype is scaled linearly from its
        minimum to its maximum onto 0..255.

    Returns
    -------
    gray : (H, W) uint8 ndarray

    Raises
    ------
    InputError
        As :func:`~seismo3d.features.to_gray`.
    """
    arr = np.asarray(image)
    gray = to_gray(arr)
    if arr.dtype == np.uint8:
        return np.clip(np.rint(gray), 0, 255).astype(np.uint8)
    lo, hi = float(gray.min()), float(gray.max())
    if not hi > lo:
        return np.zeros(gray.shape, np.uint8)
    return np.clip(np.rint((gray - lo) * (255.0 / (hi - lo))), 0, 255).astype(np.uint8)


def _factory(method: str, max_keypoints):
    import cv2

    if method == "sift":
        return cv2.SIFT_create(nfeatures=int(max_keypoints or 0))
    if method == "orb":
        return cv2.ORB_create(nfeatures=int(max_keypoints or _ORB_DEFAULT_KEYPOINTS))
    name = {"akaze": "AKAZE_create", "brisk": "BRISK_create"}[method]
    create = getattr(cv2, name, None)
    if create is None:
        create = getattr(getattr(cv2, "xfeatures2d", None), name, None)
    if create is None:  # pragma: no cover - depends on the OpenCV build
        raise InputError(f"this OpenCV build has no {method.upper()}; install opencv-contrib-python-headless")
    return create()


def opencv_features(image, *, method: str = "sift", mask=None, max_keypoints: int | None = None) -> Features:
    """Detect keypoints and compute descriptors with an OpenCV method.

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        Grey or RGB image (see :func:`to_uint8` for the conversion to 8 bits).
    method : {'sift', 'orb', 'akaze', 'brisk'}
        OpenCV detector + descriptor, with OpenCV's default parameters (ORB: 2000 keypoints instead of 500).
    mask : (H, W) array_like of bool, optional
        Keypoints are detected only where the mask is True.
    max_keypoints : int, optional
        Keep at most this many keypoints, the strongest by detector response.

    Returns
    -------
    features : Features
        float32 (N, 128) descriptors for SIFT; packed-bit uint8 descriptors (``binary=True``) of 32 (ORB), 61 (AKAZE)
        or 64 (BRISK) bytes. Orientations are OpenCV's ``KeyPoint.angle`` (NaN where OpenCV gives none).

    Raises
    ------
    InputError
        If the image or mask is invalid or the method unknown.
    """
    check_choice(method, "method", OPENCV_METHODS)
    gray = to_uint8(image)
    cv_mask = None
    if mask is not None:
        m = np.asarray(mask)
        if m.shape != gray.shape:
            raise InputError(f"mask must have the image's shape {gray.shape}; got {m.shape}")
        cv_mask = np.where(m.astype(bool), 255, 0).astype(np.uint8)
    binary = method != "sift"
    if max_keypoints is not None and int(max_keypoints) < 1:
        raise InputError(f"max_keypoints must be >= 1 or None; got {max_keypoints!r}")
    detector = _factory(method, max_keypoints)
    kps, desc = detector.detectAndCompute(gray, cv_mask)
    if desc is None or len(kps) == 0:
        return Features.empty(method, _N_DIMS[method], binary=binary)
    resp = np.array([k.response for k in kps], dtype=np.float64)
    keep = np.arange(len(kps))
    if max_keypoints is not None and len(kps) > int(max_keypoints):
        keep = np.sort(np.argsort(-resp, kind="stable")[: int(max_keypoints)])
    kps = [kps[i] for i in keep]
    angles = np.array([k.angle for k in kps], dtype=np.float64)
    return Features(
        keypoints=np.array([k.pt for k in kps], dtype=np.float64).reshape(-1, 2),
        descriptors=np.ascontiguousarray(desc[keep], dtype=np.uint8 if binary else np.float32),
        scales=np.array([k.size for k in kps], dtype=np.float64),
        orientations=np.where(angles < 0, np.nan, np.mod(angles, 360.0)),
        responses=resp[keep],
        method=method,
        binary=binary,
    )
