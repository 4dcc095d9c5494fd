"""Keypoints: the :class:`Features` result type, grey-level conversion, the image pyramid and Harris peaks.

The image convention of :mod:`seismo3d.features`: an image is a (rows, cols) array, a keypoint is an ``(x, y)`` pair
in pixels with the origin at the centre of the top-left pixel, x along columns (to the right) and y along rows
(downwards). A seismic section is shown with traces along x and samples (two-way time or depth) along y.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import as_image, check_positive
from ..errors import InputError

__all__ = ["Features", "to_gray", "image_pyramid", "harris_response", "harris_peaks"]


@dataclass(frozen=True)
class Features:
    """Keypoints and their descriptors, as returned by :func:`~seismo3d.features.detect_and_describe`.

    Attributes
    ----------
    keypoints : (N, 2) float64 ndarray
        ``(x, y)`` positions in pixels of the input image, origin at the centre of the top-left pixel.
    descriptors : (N, D) ndarray
        float32 for ``'hog'`` and ``'sift'`` (compared with the Euclidean distance), packed-bit uint8 for ``'orb'``,
        ``'akaze'`` and ``'brisk'`` (compared with the Hamming distance, see ``binary``).
    scales : (N,) float64 ndarray
        Diameter of the image region each descriptor summarises, in pixels of the input image (OpenCV's
        ``KeyPoint.size``; for ``'hog'`` the outer ring's diameter times the pyramid level's downsampling factor).
    orientations : (N,) float64 ndarray
        Dominant orientation in degrees in [0, 360), measured from the +x axis towards +y (clockwise on screen).
    responses : (N,) float64 ndarray
        Detector response (Harris measure for ``'hog'``); larger is stronger. Only comparable within one method.
    method : str
        The method that produced the features (``'hog'``, ``'sift'``, ``'orb'``, ``'akaze'``, ``'brisk'``).
    binary : bool
        True when ``descriptors`` are packed bits compared with the Hamming distance.
    """

    keypoints: np.ndarray
    descriptors: np.ndarray
    scales: np.ndarray
    orientations: np.ndarray
    responses: np.ndarray
    method: str
    binary: bool = False

    def __len__(self) -> int:
        return int(self.keypoints.shape[0])

    @classmethod
    def empty(cls, method: str, n_dims: int, *, binary: bool = False) -> "Features":
        """Features with no keypoint (N = 0) and ``n_dims``-wide descriptors."""
        dtype = np.uint8 if binary else np.float32
        z = np.zeros(0)
        return cls(np.zeros((0, 2)), np.zeros((0, n_dims), dtype), z, z.copy(), z.copy(), method, binary)


def to_gray(image, name: str = "image") -> np.ndarray:
    """Return an image as a 2D float64 grey-level array, converting RGB colour when given.

    Parameters
    ----------
    image : (H, W) or (H, W, 3) array_like
        Grey levels of any real dtype, or RGB colour (channels last, in R, G, B order as read by scikit-image or
        imageio; for OpenCV's BGR reverse the last axis first). RGBA is rejected: drop the alpha channel.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    gray : (H, W) float64 ndarray
        Grey levels in the input's units; colour is converted with the ITU-R BT.601 luma weights 0.299, 0.587, 0.114.

    Raises
    ------
    InputError
        If the image is empty, smaller than 2 x 2, has NaN or inf values, or has neither 1 nor 3 channels.
    """
    arr = np.asarray(image)
    if arr.ndim == 3 and arr.shape[2] == 3:
        arr = arr.astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    return as_image(arr, name)


def image_pyramid(image, *, scale_factor: float = 2 ** 0.25, n_levels: int = 9, min_size: int = 16,
                  first_level: int = 0) -> list:
    """Downsample a grey image into a pyramid of levels, finest first.

    Level ``l`` (from ``first_level`` on) has size ``round(H / scale_factor**l) x round(W / scale_factor**l)`` and is
    resampled from the input, not from the previous level, so that blur does not accumulate: by pixel-area averaging
    (``cv2.INTER_AREA``, an anti-aliasing box filter) when shrinking, bilinearly when enlarging (l < 0).

    Parameters
    ----------
    image : (H, W) array_like
        Grey image (any real dtype).
    scale_factor : float
        Downsampling factor between consecutive levels (> 1). The default 2**(1/4) puts four levels per octave, so
        any scale change is within 2**(1/8) (9 %) of a level.
    n_levels : int
        Largest number of levels (>= 1); fewer are returned when a level would be smaller than ``min_size``.
    min_size : int
        Smallest allowed side of a level, in pixels.
    first_level : int
        Index of the first level; negative values start with enlarged levels (``first_level = -4`` with the default
        factor doubles the image, as SIFT's first octave does).

    Returns
    -------
    levels : list of (H_l, W_l) float64 ndarray
        Finest first; level 0 is the input itself.

    Raises
    ------
    InputError
        If the image is not 2D, is empty, contains NaN, or the parameters are out of range.
    """
    img = as_image(image)
    if not scale_factor > 1.0:
        raise InputError(f"scale_factor must be > 1 (the downsampling between levels); got {scale_factor!r}")
    if int(n_levels) < 1:
        raise InputError(f"n_levels must be >= 1; got {n_levels!r}")
    check_positive(min_size, "min_size")
    return resize_levels(img, float(scale_factor), int(n_levels), int(min_size), int(first_level))


def resize_levels(img, scale_factor: float, n_levels: int, min_size: int, first_level: int) -> list:
    """The levels of an image pyramid without the input checks (the hot path of the HOG-pyramid descriptor).

    Parameters
    ----------
    img : (H, W) float ndarray
        The image (checked by the caller).
    scale_factor : float
        Downsampling between levels, > 1.
    n_levels : int
        Largest number of levels.
    min_size : int
        A level whose smaller side would be below this is not made (the pyramid stops).
    first_level : int
        Level of the first image (0: the image itself).

    Returns
    -------
    list
        As :func:`image_pyramid`.
    """
    import cv2

    h0, w0 = img.shape
    levels = []
    for lev in range(first_level, first_level + n_levels):
        s = scale_factor ** lev
        h, w = int(round(h0 / s)), int(round(w0 / s))
        if min(h, w) < min_size:
            break
        if lev == 0:
            levels.append(img)
        else:
            levels.append(cv2.resize(img, (w, h), interpolation=cv2.INTER_AREA if lev > 0 else cv2.INTER_LINEAR))
    return levels


def harris_response(gx, gy, *, sigma: float = 1.5, k: float = 0.04) -> np.ndarray:
    """Harris corner measure ``det(M) - k trace(M)^2`` of the Gaussian-weighted structure tensor M.

    Parameters
    ----------
    gx, gy : (H, W) float32 or float64 ndarray
        Image derivatives along x (columns) and y (rows), in grey levels per pixel.
    sigma : float
        Standard deviation in pixels of the Gaussian integration window.
    k : float
        Harris sensitivity (0.04 to 0.06 in the literature).

    Returns
    -------
    response : (H, W) ndarray, dtype of gx
        Large positive at corners, negative along edges, near zero in flat areas.

    References
    ----------
    C. Harris and M. Stephens, "A combined corner and edge detector", Alvey Vision Conference, 1988.
    """
    import cv2

    a = cv2.GaussianBlur(gx * gx, (0, 0), sigma)
    b = cv2.GaussianBlur(gy * gy, (0, 0), sigma)
    c = cv2.GaussianBlur(gx * gy, (0, 0), sigma)
    return a * b - c * c - k * (a + b) ** 2


def harris_peaks(response, *, nms_size: int = 5, threshold: float = 0.0, border: int = 0, mask=None):
    """Local maxima of a corner response with non-maximum suppression and sub-pixel refinement.

    Parameters
    ----------
    response : (H, W) float32 or float64 ndarray
        Corner response, e.g. from :func:`harris_response`.
    nms_size : int
        Side in pixels of the square window in which a peak must be the maximum (odd, >= 3).
    threshold : float
        Peaks must exceed this response (absolute, in the response's units).
    border : int
        Peaks closer than this many pixels to the image edge are dropped.
    mask : (H, W) bool ndarray, optional
        Peaks are kept only where the mask is True.

    Returns
    -------
    rows, cols : (N,) int64 ndarray
        Integer pixel of each peak, sorted by row then column.
    xy : (N, 2) float64 ndarray
        Sub-pixel ``(x, y)`` of each peak (vertex of a parabola fitted through the 3 x 3 neighbourhood, at most half a
        pixel from the integer pixel).
    values : (N,) float64 ndarray
        Response at each peak.
    """
    import cv2

    r = np.asarray(response)
    if r.dtype not in (np.float32, np.float64):
        r = r.astype(np.float64)
    h, w = r.shape
    size = int(nms_size) | 1
    local_max = cv2.dilate(r, np.ones((size, size), np.uint8))
    keep = (r >= local_max) & (r > threshold)
    b = max(int(border), 1)
    keep[:b] = False
    keep[h - b:] = False
    keep[:, :b] = False
    keep[:, w - b:] = False
    if mask is not None:
        keep &= mask
    rows, cols = np.nonzero(keep)
    values = r[rows, cols].astype(np.float64)
    c = values
    east, west = r[rows, cols + 1].astype(np.float64), r[rows, cols - 1].astype(np.float64)
    south, north = r[rows + 1, cols].astype(np.float64), r[rows - 1, cols].astype(np.float64)
    dx, dy = 0.5 * (east - west), 0.5 * (south - north)
    dxx, dyy = east - 2 * c + west, south - 2 * c + north
    ox = np.where(dxx < 0, -dx / np.where(dxx < 0, dxx, -1.0), 0.0)
    oy = np.where(dyy < 0, -dy / np.where(dyy < 0, dyy, -1.0), 0.0)
    xy = np.column_stack([cols + np.clip(ox, -0.5, 0.5), rows + np.clip(oy, -0.5, 0.5)])
    return rows.astype(np.int64), cols.astype(np.int64), xy, values
