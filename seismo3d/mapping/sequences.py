"""RGB-D sequences on disk: the TUM RGB-D layout and the Microsoft 7-Scenes layout, streamed frame by frame.

Two layouts are recognised by :func:`open_sequence`:

* **TUM RGB-D** (Sturm et al. 2012): ``rgb.txt`` and ``depth.txt`` (``timestamp filename`` rows, ``#`` comments),
  optionally ``associations.txt`` (``t_rgb rgb t_depth depth`` rows) and ``groundtruth.txt``
  (``timestamp tx ty tz qx qy qz qw``, camera-to-world). Depth is uint16 PNG at 5000 units per metre, 0 invalid.
  Intrinsics: TUM's calibration of the camera named by the folder (``freiburg1`` / ``fr1``, ``freiburg2``,
  ``freiburg3``), else the ROS default Kinect values (fx = fy = 525, cx = 319.5, cy = 239.5).
* **7-Scenes** (Shotton et al. 2013): ``frame-NNNNNN.color.png|jpg``, ``frame-NNNNNN.depth.png`` (uint16 millimetres,
  0 and 65535 invalid) and ``frame-NNNNNN.pose.txt`` (4 x 4 camera-to-world), either side by side (the origin's
  ``seq-XX`` folders) or listed by TUM-style text files with ``rgb/``, ``depth/`` and ``pose/`` folders. Intrinsics:
  ``camera-intrinsics.txt`` when present, else 7-Scenes' published fx = fy = 585, cx = 320, cy = 240. Frames without
  timestamps get ``frame number / 30`` s (the Kinect's frame rate).

A ``camera-intrinsics.txt`` (3 x 3 matrix) in the folder overrides the defaults of either layout. Frames are read one
at a time (:meth:`RGBDSequence.read`), never all at once.

References
----------
Sturm, J., Engelhard, N., Endres, F., Burgard, W., Cremers, D. (2012). A benchmark for the evaluation of RGB-D SLAM
systems. IROS, 573-580. doi:10.1109/IROS.2012.6385773
Shotton, J., Glocker, B., Zach, C., Izadi, S., Criminisi, A., Fitzgibbon, A. (2013). Scene coordinate regression
forests for camera relocalization in RGB-D images. CVPR, 2930-2937. doi:10.1109/CVPR.2013.377
"""

from __future__ import annotations

import pathlib
import re
from collections import Counter
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from .._validation import as_intrinsics, check_positive
from ..data.rgbd import CameraIntrinsics, RGBDFrame
from ..errors import DataIntegrityError, DataNotFoundError, InputError

__all__ = ["FrameEntry", "RGBDSequence", "open_sequence", "read_tum_trajectory", "associate_timestamps",
           "TUM_INTRINSICS"]

#: TUM RGB-D calibrations (fx, fy, cx, cy) of the freiburg cameras and the ROS default (TUM "file formats" page).
TUM_INTRINSICS = {
    "fr1": (517.3, 516.5, 318.6, 255.3),
    "fr2": (520.9, 521.0, 325.1, 249.7),
    "fr3": (535.4, 539.2, 320.1, 247.6),
    "ros_default": (525.0, 525.0, 319.5, 239.5),
}
_SEVEN_SCENES_INTRINSICS = (585.0, 585.0, 320.0, 240.0)
_KINECT_FPS = 30.0
_FRAME_NUMBER = re.compile(r"frame-(\d+)\.")


@dataclass(frozen=True)
class FrameEntry:
    """One listed frame of a sequence (its files are read only by :meth:`RGBDSequence.read`).

    Attributes
    ----------
    index : int
        Position in the sequence, 0-based.
    timestamp : float
        Acquisition time of the depth image, seconds.
    color_path, depth_path : pathlib.Path
        Image files (may be missing on disk: reading then raises).
    pose : (4, 4) float64 ndarray or None
        Reference camera-to-world pose when the sequence has one at this timestamp (metres).
    """

    index: int
    timestamp: float
    color_path: pathlib.Path
    depth_path: pathlib.Path
    pose: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class RGBDSequence:
    """An RGB-D sequence on disk, read frame by frame.

    Attributes
    ----------
    root : pathlib.Path
        The sequence folder.
    layout : {'tum', '7scenes'}
        Which layout was recognised.
    intrinsics : CameraIntrinsics
        Pinhole intrinsics of the depth images (pixels).
    depth_scale : float
        Stored depth units per metre (5000 for TUM, 1000 for 7-Scenes).
    invalid_depth : tuple of int
        Raw depth values that mean "no measurement".
    entries : tuple of FrameEntry
        The frames in time order.
    groundtruth : tuple (timestamps (K,) float64, poses (K, 4, 4) float64) or None
        The reference trajectory, when the folder has one.
    """

    root: pathlib.Path
    layout: str
    intrinsics: CameraIntrinsics
    depth_scale: float
    invalid_depth: tuple
    entries: tuple
    groundtruth: tuple | None = None

    def __len__(self) -> int:
        return len(self.entries)

    @property
    def timestamps(self) -> np.ndarray:
        """(N,) float64 ndarray: the frames' timestamps in seconds."""
        return np.array([e.timestamp for e in self.entries], dtype=np.float64)

    def read(self, index: int) -> RGBDFrame:
        """Read one frame.

        Parameters
        ----------
        index : int
            Position in the sequence.

        Returns
        -------
        RGBDFrame
            ``color`` (H, W, 3) uint8 RGB (None when the colour image is missing or unreadable: the frame is still
            usable by depth), ``depth`` (H, W) float32 metres with NaN where invalid, ``intrinsics``, ``pose`` (the
            reference pose or None), ``timestamp`` in seconds.

        Raises
        ------
        DataNotFoundError
            If the depth image is missing.
        DataIntegrityError
            If the depth image cannot be decoded, is not a single-channel 16-bit image, or its size differs from the
            intrinsics' image size.
        """
        entry = self.entries[index]
        raw = _read_depth(entry.depth_path)
        k = self.intrinsics
        if raw.shape != (k.height, k.width):
            raise DataIntegrityError(f"{entry.depth_path}: depth image is {raw.shape[1]} x {raw.shape[0]} but the "
                                     f"camera's is {k.width} x {k.height}; the file does not belong to this sequence")
        depth = raw.astype(np.float32) / np.float32(self.depth_scale)
        depth[np.isin(raw, self.invalid_depth)] = np.nan
        color = _read_color(entry.color_path, raw.shape)
        return RGBDFrame(color=color, depth=depth, intrinsics=k, pose=entry.pose, timestamp=entry.timestamp)


def _read_depth(path: pathlib.Path) -> np.ndarray:
    import cv2

    if not path.is_file():
        raise DataNotFoundError(f"{path}: depth image listed by the sequence is missing")
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise DataIntegrityError(f"{path}: OpenCV could not decode the depth image; the file is corrupt")
    if image.ndim != 2 or image.dtype != np.uint16:
        raise DataIntegrityError(f"{path}: expected a single-channel 16-bit depth image; got {image.dtype} with "
                                 f"shape {image.shape}")
    return image


def _read_color(path: pathlib.Path, shape) -> np.ndarray | None:
    import cv2

    if not path.is_file():
        return None
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if image is None:
        return None
    return np.ascontiguousarray(image[:, :, ::-1])


def _read_list(path: pathlib.Path, n_columns: int) -> list:
    rows = []
    for number, line in enumerate(path.read_text().splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.replace(",", " ").split()
        if len(parts) < n_columns:
            raise InputError(f"{path}, line {number}: expected {n_columns} columns, got {len(parts)}: {line!r}")
        rows.append(parts)
    return rows


def read_tum_trajectory(path) -> tuple[np.ndarray, np.ndarray]:
    """Read a trajectory in the TUM format (``timestamp tx ty tz qx qy qz qw`` per line, ``#`` comments).

    Parameters
    ----------
    path : str or os.PathLike
        Text file.

    Returns
    -------
    timestamps : (K,) float64 ndarray
        Seconds, in file order.
    poses : (K, 4, 4) float64 ndarray
        Camera-to-world transforms, metres (quaternions normalised).

    Raises
    ------
    DataNotFoundError
        If the file does not exist.
    InputError
        If a line does not hold 8 numbers.
    """
    path = pathlib.Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"trajectory file {path} does not exist")
    rows = _read_list(path, 8)
    try:
        values = np.array([[float(v) for v in r[:8]] for r in rows], dtype=np.float64).reshape(-1, 8)
    except ValueError as exc:
        raise InputError(f"{path}: every line must be 'timestamp tx ty tz qx qy qz qw' numbers ({exc})") from exc
    poses = np.tile(np.eye(4), (len(values), 1, 1))
    if len(values):
        poses[:, :3, :3] = Rotation.from_quat(values[:, 4:8]).as_matrix()
        poses[:, :3, 3] = values[:, 1:4]
    return values[:, 0], poses


def associate_timestamps(first, second, *, max_difference: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    """Pair two lists of timestamps one-to-one, closest pairs first, as TUM's ``associate.py`` does.

    Parameters
    ----------
    first, second : (N,) and (M,) array_like of float
        Timestamps in seconds.
    max_difference : float
        Largest accepted difference, seconds.

    Returns
    -------
    i, j : (K,) int64 ndarray
        Indices into ``first`` and ``second``, sorted by ``first``'s time.
    """
    a = np.asarray(first, dtype=np.float64).reshape(-1)
    b = np.asarray(second, dtype=np.float64).reshape(-1)
    check_positive(max_difference, "max_difference", allow_zero=True)
    if len(a) == 0 or len(b) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    order = np.argsort(b)
    bs = b[order]
    # candidate pairs: each timestamp of `first` with its two neighbours in `second`
    pos = np.searchsorted(bs, a)
    cand_i = np.concatenate([np.arange(len(a)), np.arange(len(a))])
    cand_j = np.concatenate([np.clip(pos - 1, 0, len(b) - 1), np.clip(pos, 0, len(b) - 1)])
    diff = np.abs(a[cand_i] - bs[cand_j])
    keep = diff <= max_difference
    cand_i, cand_j, diff = cand_i[keep], cand_j[keep], diff[keep]
    used_a, used_b, pairs = set(), set(), []
    for k in np.argsort(diff, kind="stable"):
        i, j = int(cand_i[k]), int(cand_j[k])
        if i in used_a or j in used_b:
            continue
        used_a.add(i)
        used_b.add(j)
        pairs.append((i, int(order[j])))
    pairs.sort()
    out = np.array(pairs, dtype=np.int64).reshape(-1, 2)
    return out[:, 0], out[:, 1]


def _intrinsics_for(root: pathlib.Path, layout: str, width: int, height: int, override) -> CameraIntrinsics:
    if override is not None:
        if isinstance(override, CameraIntrinsics):
            return override
        fx, fy, cx, cy = as_intrinsics(override)
        return CameraIntrinsics(fx, fy, cx, cy, width, height)
    matrix_file = root / "camera-intrinsics.txt"
    if matrix_file.is_file():
        try:
            matrix = np.loadtxt(matrix_file, dtype=np.float64)
        except ValueError as exc:
            raise InputError(f"{matrix_file} must hold a 3 x 3 camera matrix ({exc})") from exc
        return CameraIntrinsics.from_matrix(matrix, width=width, height=height)
    if layout == "7scenes":
        return CameraIntrinsics(*_SEVEN_SCENES_INTRINSICS, width, height)
    name = root.name.lower()
    for key, aliases in (("fr1", ("freiburg1", "fr1")), ("fr2", ("freiburg2", "fr2")), ("fr3", ("freiburg3", "fr3"))):
        if any(a in name for a in aliases):
            return CameraIntrinsics(*TUM_INTRINSICS[key], width, height)
    return CameraIntrinsics(*TUM_INTRINSICS["ros_default"], width, height)


def _frame_number(path: str) -> int | None:
    match = _FRAME_NUMBER.search(pathlib.Path(path).name)
    return int(match.group(1)) if match else None


def _tum_entries(root: pathlib.Path, max_difference: float):
    assoc = root / "associations.txt"
    if assoc.is_file():
        rows = _read_list(assoc, 4)
        return [(float(r[2]), root / r[1], root / r[3]) for r in rows]
    rgb = _read_list(root / "rgb.txt", 2)
    depth = _read_list(root / "depth.txt", 2)
    i, j = associate_timestamps([float(r[0]) for r in depth], [float(r[0]) for r in rgb],
                                max_difference=max_difference)
    return [(float(depth[a][0]), root / rgb[b][1], root / depth[a][1]) for a, b in zip(i, j)]


def _seven_scenes_entries(root: pathlib.Path):
    depth_files = sorted(root.glob("frame-*.depth.png"))
    out = []
    for path in depth_files:
        number = _frame_number(path.name)
        stem = path.name[: -len(".depth.png")]
        color = next((root / f"{stem}.color.{ext}" for ext in ("png", "jpg") if (root / f"{stem}.color.{ext}").is_file()),
                     root / f"{stem}.color.png")
        out.append((number / _KINECT_FPS, color, path))
    return out


def _pose_files(root: pathlib.Path, entries) -> list:
    poses = []
    for _, _, depth_path in entries:
        stem = depth_path.name[: -len(".depth.png")] if depth_path.name.endswith(".depth.png") else None
        pose = None
        if stem is not None:
            for candidate in (depth_path.parent / f"{stem}.pose.txt", root / "pose" / f"{stem}.pose.txt"):
                if candidate.is_file():
                    try:
                        pose = np.loadtxt(candidate, dtype=np.float64)
                    except ValueError:
                        pose = None
                    if pose is None or pose.shape != (4, 4) or not np.all(np.isfinite(pose)):
                        pose = None
                    break
        poses.append(pose)
    return poses


def open_sequence(path, *, intrinsics=None, depth_scale: float | None = None,
                  max_time_difference: float = 0.02) -> RGBDSequence:
    """Open an RGB-D sequence folder in the TUM or 7-Scenes layout (see the module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        The sequence folder.
    intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy), optional
        Override the layout's intrinsics (pixels).
    depth_scale : float, optional
        Override the stored depth units per metre (5000 TUM, 1000 7-Scenes).
    max_time_difference : float
        Largest colour-depth timestamp difference when pairing ``rgb.txt`` with ``depth.txt`` (seconds).

    Returns
    -------
    RGBDSequence

    Raises
    ------
    DataNotFoundError
        If the folder does not exist.
    InputError
        If the folder is in neither layout, lists no frame, or its list files are malformed.
    """
    root = pathlib.Path(path)
    if not root.is_dir():
        raise DataNotFoundError(f"sequence folder {root} does not exist")
    if (root / "associations.txt").is_file() or ((root / "rgb.txt").is_file() and (root / "depth.txt").is_file()):
        raw = _tum_entries(root, max_time_difference)
        seven = bool(raw) and all(str(d).endswith(".depth.png") for _, _, d in raw)
        layout = "7scenes" if seven else "tum"
    elif any(root.glob("frame-*.depth.png")):
        raw, layout = _seven_scenes_entries(root), "7scenes"
    else:
        raise InputError(f"{root} is neither a TUM RGB-D sequence (rgb.txt + depth.txt [+ associations.txt]) nor a "
                         "7-Scenes sequence (frame-NNNNNN.depth.png files); point to the folder holding them")
    if not raw:
        raise InputError(f"{root} lists no frame (empty lists, or no colour and depth timestamps within "
                         f"{max_time_difference} s of each other: raise max_time_difference)")
    raw.sort(key=lambda r: r[0])
    times = np.array([r[0] for r in raw])
    keep = np.concatenate([[True], np.diff(times) > 0])  # duplicated timestamps: keep the first
    raw = [r for r, k in zip(raw, keep) if k]
    scale = (1000.0 if layout == "7scenes" else 5000.0) if depth_scale is None else check_positive(depth_scale,
                                                                                                     "depth_scale")
    invalid = (0, 65535) if layout == "7scenes" else (0,)
    width, height = _image_size(raw)
    k = _intrinsics_for(root, layout, width, height, intrinsics)
    groundtruth = None
    gt_file = root / "groundtruth.txt"
    poses = [None] * len(raw)
    if gt_file.is_file():
        gt_t, gt_p = read_tum_trajectory(gt_file)
        groundtruth = (gt_t, gt_p)
        i, j = associate_timestamps([r[0] for r in raw], gt_t, max_difference=max_time_difference)
        for a, b in zip(i, j):
            poses[a] = gt_p[b]
    elif layout == "7scenes":
        poses = _pose_files(root, raw)
        have = [n for n, p in enumerate(poses) if p is not None]
        if have:
            groundtruth = (np.array([raw[n][0] for n in have]), np.stack([poses[n] for n in have]))
    entries = tuple(FrameEntry(n, t, c, d, None if p is None else _read_only(p))
                    for n, ((t, c, d), p) in enumerate(zip(raw, poses)))
    return RGBDSequence(root=root, layout=layout, intrinsics=k, depth_scale=scale, invalid_depth=invalid,
                        entries=entries, groundtruth=groundtruth)


def _read_only(array):
    array = np.array(array, dtype=np.float64)
    array.setflags(write=False)
    return array


def _image_size(raw) -> tuple[int, int]:
    """Width and height most common among the first five readable depth images (640 x 480 when none can be read)."""
    sizes = Counter()
    for _, _, depth_path in raw[:20]:
        try:
            image = _read_depth(depth_path)
        except (DataNotFoundError, DataIntegrityError):
            continue
        sizes[(image.shape[1], image.shape[0])] += 1
        if sum(sizes.values()) == 5:
            break
    return sizes.most_common(1)[0][0] if sizes else (640, 480)
