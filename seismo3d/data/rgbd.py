"""Real RGB-D frames: Microsoft 7-Scenes, TUM RGB-D, NYU Depth v2 and SUN RGB-D.

Every loader returns :class:`RGBDFrame` with depth in metres as float32 and **NaN for invalid pixels** (no return,
out of range, sensor saturation), so that invalid depth can never be mistaken for a surface at 0 m; use
``np.isfinite(frame.depth)`` as the validity mask.

Camera conventions (OpenCV / ROS optical frame): x right, y down, z forward (depth is the z coordinate, not the ray
length); pixel (u, v) = (column, row) with integer coordinates at pixel centres, so a point (x, y, z) projects to
``u = fx * x / z + cx``, ``v = fy * y / z + cy``. Poses are camera-to-world: ``p_world = R @ p_camera + t``.

References
----------
.. [1] Shotton, J., Glocker, B., Zach, C., Izadi, S., Criminisi, A. and Fitzgibbon, A. (2013). Scene coordinate
       regression forests for camera relocalization in RGB-D images. CVPR, 2930-2937. doi:10.1109/CVPR.2013.377
       (7-Scenes)
.. [2] Sturm, J., Engelhard, N., Endres, F., Burgard, W. and Cremers, D. (2012). A benchmark for the evaluation of
       RGB-D SLAM systems. IROS, 573-580. doi:10.1109/IROS.2012.6385773 (TUM RGB-D)
.. [3] Silberman, N., Hoiem, D., Kohli, P. and Fergus, R. (2012). Indoor segmentation and support inference from
       RGBD images. ECCV, 746-760. doi:10.1007/978-3-642-33715-4_54 (NYU Depth v2)
.. [4] Song, S., Lichtenberg, S. P. and Xiao, J. (2015). SUN RGB-D: a RGB-D scene understanding benchmark suite.
       CVPR, 567-576. doi:10.1109/CVPR.2015.7298655
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np

from .._validation import check_choice, check_positive
from ..errors import DataIntegrityError, InputError
from .registry import fetch

__all__ = ["CameraIntrinsics", "RGBDFrame", "load_7scenes_frame", "load_tum_pair", "load_single_frame"]

_SEVEN_SCENES = "rgbd/7scenes_redkitchen_0000_0495"
_SEVEN_SCENES_FRAMES = range(0, 500, 5)
_SEVEN_SCENES_FPS = 30.0
_TUM_PAIR = "rgbd/tum_fr1xyz_pair"
_SINGLE = "rgbd/single_frames"


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics of a camera (no lens distortion).

    Attributes
    ----------
    fx, fy : float
        Focal lengths in pixels.
    cx, cy : float
        Principal point in pixels (column, row), pixel centres at integer coordinates.
    width, height : int
        Image size in pixels.
    """

    fx: float
    fy: float
    cx: float
    cy: float
    width: int
    height: int

    def __post_init__(self):
        for name in ("fx", "fy"):
            check_positive(getattr(self, name), name)
        for name in ("cx", "cy"):
            if not np.isfinite(getattr(self, name)):
                raise InputError(f"{name} must be finite; got {getattr(self, name)!r}")
        for name in ("width", "height"):
            value = getattr(self, name)
            if int(value) != value or value < 1:
                raise InputError(f"{name} must be a positive whole number of pixels; got {value!r}")

    @property
    def matrix(self) -> np.ndarray:
        """(3, 3) float64 ndarray: the camera matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @classmethod
    def from_matrix(cls, matrix, width: int, height: int) -> CameraIntrinsics:
        """Build intrinsics from a (3, 3) camera matrix and the image size in pixels.

        Raises
        ------
        InputError
            If ``matrix`` is not a (3, 3) upper-triangular camera matrix with zero skew and last row (0, 0, 1).
        """
        k = np.asarray(matrix, dtype=np.float64)
        if k.shape != (3, 3) or not np.allclose(k[2], [0, 0, 1]) or k[0, 1] != 0 or k[1, 0] != 0:
            raise InputError(f"matrix must be a (3, 3) camera matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]; "
                             f"got {np.array2string(k, precision=4)}")
        return cls(fx=float(k[0, 0]), fy=float(k[1, 1]), cx=float(k[0, 2]), cy=float(k[1, 2]),
                   width=int(width), height=int(height))


@dataclass(frozen=True, eq=False)
class RGBDFrame:
    """One colour + depth frame with its camera.

    Attributes
    ----------
    color : (H, W, 3) uint8 ndarray
        RGB colour image (red first).
    depth : (H, W) float32 ndarray
        Depth along the optical axis in metres; NaN where invalid.
    intrinsics : CameraIntrinsics
        Intrinsics of the depth image (pixels of ``depth``). Colour shares them only when the dataset registers
        colour to depth (TUM, SUN); see each loader.
    pose : (4, 4) float64 ndarray or None
        Camera-to-world transform of the depth camera, metres; None when unknown.
    timestamp : float or None
        Acquisition time in seconds; None when unknown.
    """

    color: np.ndarray
    depth: np.ndarray
    intrinsics: CameraIntrinsics
    pose: np.ndarray | None = None
    timestamp: float | None = None


def _read_image(path: pathlib.Path, *, color: bool) -> np.ndarray:
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_COLOR if color else cv2.IMREAD_UNCHANGED)
    if image is None:
        raise DataIntegrityError(f"{path}: OpenCV could not decode the image; the file is corrupt or not an image")
    if color:
        return np.ascontiguousarray(image[:, :, ::-1])  # OpenCV decodes to BGR
    if image.ndim != 2 or image.dtype != np.uint16:
        raise DataIntegrityError(f"{path}: expected a single-channel 16-bit depth image; got {image.dtype} "
                                 f"{image.shape}")
    return image


def _pose_from_tum(values) -> np.ndarray:
    """(4, 4) pose from TUM ``tx ty tz qx qy qz qw`` (world-from-camera, scalar-last quaternion)."""
    from scipy.spatial.transform import Rotation

    values = np.asarray(values, dtype=np.float64)
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_quat(values[3:7]).as_matrix()  # normalises the 4-decimal quaternion
    pose[:3, 3] = values[:3]
    return pose


def _frame(color, depth, intrinsics, pose=None, timestamp=None) -> RGBDFrame:
    for array in (color, depth, pose):
        if array is not None:
            array.setflags(write=False)
    return RGBDFrame(color=color, depth=depth, intrinsics=intrinsics, pose=pose, timestamp=timestamp)


def _depth_from_scaled(raw: np.ndarray, scale: float, invalid=(0,)) -> np.ndarray:
    depth = raw.astype(np.float32) / np.float32(scale)
    depth[np.isin(raw, invalid)] = np.nan
    return depth


def load_7scenes_frame(index: int) -> RGBDFrame:
    """Load one frame of the Microsoft 7-Scenes "redkitchen" sequence (Kinect v1, 640 x 480) with its pose.

    The data directory holds every 5th frame (0, 5, ..., 495) of the origin's first 1000. The colour camera is not
    registered to the depth camera in 7-Scenes: ``intrinsics`` and ``pose`` belong to the depth image, and colour
    pixels do not line up exactly with depth pixels.

    Parameters
    ----------
    index : int
        Original frame number, a multiple of 5 from 0 to 495.

    Returns
    -------
    frame : RGBDFrame
        ``color`` (480, 640, 3) uint8 RGB; ``depth`` (480, 640) float32 metres (raw uint16 millimetres / 1000; raw 0
        and 65535 are invalid and become NaN); ``intrinsics`` fx = fy = 585, cx = 320, cy = 240 pixels (from
        ``camera-intrinsics.txt``); ``pose`` (4, 4) camera-to-world from ``frame-NNNNNN.pose.txt`` (7-Scenes' reference
        poses, tracked by KinectFusion, metres), with the rotation block projected onto the nearest rotation matrix
        (the stored ones deviate from orthonormal by up to 2.4e-4); ``timestamp`` = index / 30 s, a synthetic time
        (7-Scenes has no timestamps) that matches the data directory's TUM-style ``groundtruth.txt``.

    Raises
    ------
    InputError
        If ``index`` is not one of 0, 5, ..., 495.
    DataNotFoundError
        If the files are neither in ``SEISMO3D_DATA_DIR`` nor downloadable.

    References
    ----------
    .. [1] Shotton, J. et al. (2013). Scene coordinate regression forests for camera relocalization in RGB-D images.
           CVPR. doi:10.1109/CVPR.2013.377
    """
    if isinstance(index, (bool, np.bool_)) or not isinstance(index, (int, np.integer)) or \
            index not in _SEVEN_SCENES_FRAMES:
        raise InputError(f"index={index!r} is not an available 7-Scenes frame; use a multiple of 5 from 0 to 495 "
                         "(the data directory keeps every 5th frame)")
    stem = f"frame-{int(index):06d}"
    color = _read_image(fetch(f"{_SEVEN_SCENES}/rgb/{stem}.color.jpg"), color=True)
    raw = _read_image(fetch(f"{_SEVEN_SCENES}/depth/{stem}.depth.png"), color=False)
    depth = _depth_from_scaled(raw, 1000.0, invalid=(0, 65535))
    pose = np.loadtxt(fetch(f"{_SEVEN_SCENES}/pose/{stem}.pose.txt"), dtype=np.float64)
    if pose.shape != (4, 4) or not np.allclose(pose[3], [0, 0, 0, 1]):
        raise DataIntegrityError(f"{stem}.pose.txt does not hold a 4x4 rigid transform; restore the file")
    # The stored rotations are orthonormal only to ~2e-4 (KinectFusion's float32 accumulation): use the nearest
    # rotation matrix (SVD projection onto SO(3)), which moves a point at 3 m by less than 1 mm.
    u, _, vt = np.linalg.svd(pose[:3, :3])
    pose[:3, :3] = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt
    matrix = np.loadtxt(fetch(f"{_SEVEN_SCENES}/camera-intrinsics.txt"), dtype=np.float64)
    intrinsics = CameraIntrinsics.from_matrix(matrix, width=raw.shape[1], height=raw.shape[0])
    return _frame(color, depth, intrinsics, pose, int(index) / _SEVEN_SCENES_FPS)


def load_tum_pair(*, calibration: str = "fr1") -> tuple[RGBDFrame, RGBDFrame]:
    """Load two nearby real TUM RGB-D fr1/xyz frames with motion-capture ground-truth poses.

    The frames are about 2 cm and 1.4 degrees apart; depth is registered to colour (one pixel grid).

    Parameters
    ----------
    calibration : {'fr1', 'ros_default'}, optional
        Intrinsics to attach. ``'fr1'`` (default): TUM's calibration of the freiburg1 Kinect, fx = 517.3, fy = 516.5,
        cx = 318.6, cy = 255.3 pixels (lens distortion ignored). ``'ros_default'``: the nominal Kinect values
        fx = fy = 525, cx = 319.5, cy = 239.5 stored with the pair in ``kinect_params.txt``, which TUM suggests for
        its pre-registered depth. Measured on this pair (warping previous depth into the current frame with the
        ground-truth poses): median depth residual 3.6 mm with ``'fr1'``, 4.0 mm with ``'ros_default'``.

    Returns
    -------
    prev, curr : RGBDFrame
        ``color`` (480, 640, 3) uint8 RGB; ``depth`` (480, 640) float32 metres (raw uint16 / 5000; raw 0 is invalid
        and becomes NaN); ``pose`` (4, 4) camera-to-world (world-from-camera) from TUM ``tx ty tz qx qy qz qw``;
        ``timestamp`` None (the pair's files carry none).

    Raises
    ------
    InputError
        If ``calibration`` is not one of the choices.
    DataNotFoundError
        If the files are neither in ``SEISMO3D_DATA_DIR`` nor downloadable.

    References
    ----------
    .. [1] Sturm, J. et al. (2012). A benchmark for the evaluation of RGB-D SLAM systems. IROS.
           doi:10.1109/IROS.2012.6385773
    """
    check_choice(calibration, "calibration", {"fr1", "ros_default"})
    frames = []
    for which in ("prev", "curr"):
        color = _read_image(fetch(f"{_TUM_PAIR}/img_{which}.png"), color=True)
        raw = _read_image(fetch(f"{_TUM_PAIR}/dep_{which}.png"), color=False)
        height, width = raw.shape
        if calibration == "fr1":
            intrinsics = CameraIntrinsics(517.3, 516.5, 318.6, 255.3, width, height)
        else:
            matrix = np.loadtxt(fetch(f"{_TUM_PAIR}/kinect_params.txt"), dtype=np.float64)
            intrinsics = CameraIntrinsics.from_matrix(matrix, width=width, height=height)
        values = np.loadtxt(fetch(f"{_TUM_PAIR}/pose_{which}.txt"), dtype=np.float64)
        if values.shape != (7,):
            raise DataIntegrityError(f"pose_{which}.txt must hold 7 numbers 'tx ty tz qx qy qz qw'; got {values.shape}")
        frames.append(_frame(color, _depth_from_scaled(raw, 5000.0), intrinsics, _pose_from_tum(values)))
    return frames[0], frames[1]


def load_single_frame(dataset: str) -> RGBDFrame:
    """Load one real RGB-D frame (640 x 480) of TUM RGB-D, NYU Depth v2 or SUN RGB-D, as shipped with Open3D.

    Each dataset stores depth differently; this loader converts all three to metres:

    - ``'tum'``: uint16 PNG, depth = raw / 5000, raw 0 invalid. Depth is registered to colour. Intrinsics: the
      nominal Kinect fx = fy = 525, cx = 319.5, cy = 239.5 (the frame's own sequence is not recorded).
    - ``'nyu'``: PGM of raw Kinect disparity, stored little-endian despite the PGM (big-endian) convention, so it is
      byte-swapped; depth = 351.3 / (1092.5 - raw) metres (NYU toolbox), raw 2047 (no return) and results outside
      (0, 10] m invalid. Depth is *not* registered to colour: the intrinsics are NYU's depth-camera calibration
      fx = 582.62, fy = 582.69, cx = 313.04, cy = 238.44.
    - ``'sun'``: uint16 PNG whose bits are rotated by 3: depth = (((d >> 3) | (d << 13)) & 0xFFFF) / 1000, raw 0
      invalid (values above 8 m, which the SUN RGB-D toolbox clips, are kept). Depth is registered to colour.
      Intrinsics: the nominal Kinect values as for ``'tum'`` (the frame's calibration is not shipped).

    Parameters
    ----------
    dataset : {'tum', 'nyu', 'sun'}
        Which frame to load.

    Returns
    -------
    frame : RGBDFrame
        ``color`` (480, 640, 3) uint8 RGB, ``depth`` (480, 640) float32 metres with NaN where invalid,
        ``intrinsics`` as above, ``pose`` None, ``timestamp`` None.

    Raises
    ------
    InputError
        If ``dataset`` is not one of the choices.
    DataNotFoundError
        If the files are neither in ``SEISMO3D_DATA_DIR`` nor downloadable.

    References
    ----------
    .. [1] Sturm, J. et al. (2012). A benchmark for the evaluation of RGB-D SLAM systems. IROS.
           doi:10.1109/IROS.2012.6385773
    .. [2] Silberman, N. et al. (2012). Indoor segmentation and support inference from RGBD images. ECCV.
           doi:10.1007/978-3-642-33715-4_54
    .. [3] Song, S., Lichtenberg, S. P. and Xiao, J. (2015). SUN RGB-D: a RGB-D scene understanding benchmark suite.
           CVPR. doi:10.1109/CVPR.2015.7298655
    """
    check_choice(dataset, "dataset", {"tum", "nyu", "sun"})
    if dataset == "tum":
        color = _read_image(fetch(f"{_SINGLE}/TUM_color.png"), color=True)
        raw = _read_image(fetch(f"{_SINGLE}/TUM_depth.png"), color=False)
        depth = _depth_from_scaled(raw, 5000.0)
        intrinsics = CameraIntrinsics(525.0, 525.0, 319.5, 239.5, raw.shape[1], raw.shape[0])
    elif dataset == "nyu":
        color = _read_image(fetch(f"{_SINGLE}/NYU_color.ppm"), color=True)
        raw = _read_image(fetch(f"{_SINGLE}/NYU_depth.pgm"), color=False).byteswap()
        with np.errstate(divide="ignore"):
            depth = (351.3 / (1092.5 - raw.astype(np.float64))).astype(np.float32)
        depth[(raw == 2047) | ~(depth > 0) | (depth > 10.0)] = np.nan
        # NYU Depth v2 toolbox, camera_params.m: depth camera intrinsics.
        intrinsics = CameraIntrinsics(5.8262448167737955e02, 5.8269103270988637e02, 3.1304475870804731e02,
                                      2.3844389626620386e02, raw.shape[1], raw.shape[0])
    else:
        color = _read_image(fetch(f"{_SINGLE}/SUN_color.jpg"), color=True)
        raw = _read_image(fetch(f"{_SINGLE}/SUN_depth.png"), color=False)
        rotated = ((raw >> 3) | (raw << 13)) & 0xFFFF  # uint16 arithmetic: << 13 drops the high bits
        depth = _depth_from_scaled(rotated, 1000.0)
        intrinsics = CameraIntrinsics(525.0, 525.0, 319.5, 239.5, raw.shape[1], raw.shape[0])
    return _frame(color, depth, intrinsics)
