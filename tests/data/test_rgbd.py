"""Tests of seismo3d.data.rgbd: real frames load with the right shapes, units, invalid masks and pose conventions."""

from __future__ import annotations

import os

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from seismo3d.data import CameraIntrinsics, RGBDFrame, load_7scenes_frame, load_single_frame, load_tum_pair
from seismo3d.errors import InputError


needs_data = pytest.mark.skipif(not os.environ.get("SEISMO3D_DATA_DIR"), reason="SEISMO3D_DATA_DIR is not set")


def _check_frame(frame: RGBDFrame, *, depth_range=(0.3, 5.0)):
    assert frame.color.shape == (480, 640, 3) and frame.color.dtype == np.uint8
    assert frame.depth.shape == (480, 640) and frame.depth.dtype == np.float32
    assert (frame.intrinsics.width, frame.intrinsics.height) == (640, 480)
    valid = np.isfinite(frame.depth)
    assert 0.5 < valid.mean() < 1.0  # Kinect frames have some holes, but mostly valid depth
    assert depth_range[0] <= np.nanmin(frame.depth) and np.nanmax(frame.depth) <= depth_range[1]
    assert not frame.depth.flags.writeable and not frame.color.flags.writeable
    if frame.pose is not None:
        assert frame.pose.shape == (4, 4) and frame.pose.dtype == np.float64
        rotation = frame.pose[:3, :3]
        assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-6)
        assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-6)
        assert_array_equal(frame.pose[3], [0, 0, 0, 1])


def _warp_residual(a: RGBDFrame, b: RGBDFrame, b_from_a: np.ndarray) -> float:
    """Median |depth| disagreement after moving frame a's depth points into camera b and projecting them."""
    ka, kb = a.intrinsics, b.intrinsics
    v, u = np.nonzero(np.isfinite(a.depth))
    z = a.depth[v, u].astype(np.float64)
    points = np.stack([(u - ka.cx) * z / ka.fx, (v - ka.cy) * z / ka.fy, z])
    moved = b_from_a[:3, :3] @ points + b_from_a[:3, 3:]
    col = np.round(moved[0] / moved[2] * kb.fx + kb.cx).astype(int)
    row = np.round(moved[1] / moved[2] * kb.fy + kb.cy).astype(int)
    inside = (moved[2] > 0) & (col >= 0) & (col < kb.width) & (row >= 0) & (row < kb.height)
    seen = b.depth[row[inside], col[inside]]
    ok = np.isfinite(seen)
    return float(np.median(np.abs(seen[ok] - moved[2][inside][ok])))


@needs_data
@pytest.mark.parametrize("index", [0, 250, 495])
def test_7scenes_frame(index):
    frame = load_7scenes_frame(index)
    _check_frame(frame)
    assert frame.intrinsics == CameraIntrinsics(585.0, 585.0, 320.0, 240.0, 640, 480)
    assert_array_equal(frame.intrinsics.matrix, [[585, 0, 320], [0, 585, 240], [0, 0, 1]])
    assert frame.timestamp == pytest.approx(index / 30.0)


@needs_data
def test_7scenes_depth_units_and_invalid_pixels():
    import cv2

    from seismo3d.data import fetch

    raw = cv2.imread(str(fetch("rgbd/7scenes_redkitchen_0000_0495/depth/frame-000250.depth.png")),
                     cv2.IMREAD_UNCHANGED)
    frame = load_7scenes_frame(250)
    invalid = (raw == 0) | (raw == 65535)
    assert invalid.any()
    assert_array_equal(np.isnan(frame.depth), invalid)
    assert_allclose(frame.depth[~invalid], raw[~invalid] / 1000.0, rtol=1e-6)


@needs_data
@pytest.mark.parametrize("first, second", [(0, 25), (250, 255), (490, 495)])
def test_7scenes_poses_are_camera_to_world(first, second):
    a, b = load_7scenes_frame(first), load_7scenes_frame(second)
    ground_truth = _warp_residual(a, b, np.linalg.inv(b.pose) @ a.pose)
    assert ground_truth < 0.010  # measured 5.8-6.3 mm (KinectFusion poses, raw Kinect depth)
    # the test can fail: no motion, or the world-to-camera reading of the poses, fits worse
    assert ground_truth < 0.6 * _warp_residual(a, b, np.eye(4))
    assert ground_truth < 0.4 * _warp_residual(a, b, b.pose @ np.linalg.inv(a.pose))


@pytest.mark.parametrize("index", [-5, 3, 500, 1000, 5.0, True, "5"])
def test_7scenes_bad_index(index):
    with pytest.raises(InputError, match="multiple of 5"):
        load_7scenes_frame(index)


@needs_data
def test_tum_pair():
    prev, curr = load_tum_pair()
    for frame in (prev, curr):
        _check_frame(frame)
        assert frame.intrinsics == CameraIntrinsics(517.3, 516.5, 318.6, 255.3, 640, 480)
        assert frame.timestamp is None
    assert_allclose(prev.pose[:3, 3], [1.3303, 0.6256, 1.6464])
    motion = np.linalg.inv(prev.pose) @ curr.pose
    assert 0.005 < np.linalg.norm(motion[:3, 3]) < 0.05  # measured 2.2 cm


@needs_data
@pytest.mark.parametrize("calibration, limit", [("fr1", 0.0045), ("ros_default", 0.0050)])
def test_tum_poses_are_world_from_camera(calibration, limit):
    prev, curr = load_tum_pair(calibration=calibration)
    ground_truth = _warp_residual(prev, curr, np.linalg.inv(curr.pose) @ prev.pose)
    assert ground_truth < limit  # measured 3.6 mm (fr1), 4.0 mm (ros_default)
    assert ground_truth < 0.2 * _warp_residual(prev, curr, np.eye(4))
    assert ground_truth < 0.4 * _warp_residual(prev, curr, curr.pose @ np.linalg.inv(prev.pose))


@needs_data
def test_tum_pair_calibrations():
    prev, _ = load_tum_pair(calibration="ros_default")
    assert prev.intrinsics == CameraIntrinsics(525.0, 525.0, 319.5, 239.5, 640, 480)
    with pytest.raises(InputError, match="calibration"):
        load_tum_pair(calibration="fr2")


@needs_data
@pytest.mark.parametrize("dataset", ["tum", "nyu", "sun"])
def test_single_frames(dataset):
    frame = load_single_frame(dataset)
    _check_frame(frame, depth_range=(0.3, 10.0))
    assert frame.pose is None and frame.timestamp is None
    assert 1.0 < np.nanmedian(frame.depth) < 5.0  # indoor scenes; wrong decoding gives nonsense here


@needs_data
def test_single_frame_nyu_decoding():
    import cv2

    from seismo3d.data import fetch

    raw = cv2.imread(str(fetch("rgbd/single_frames/NYU_depth.pgm")), cv2.IMREAD_UNCHANGED)
    assert raw.max() > 2047  # OpenCV reads the PGM big-endian: the values are byte-swapped
    disparity = raw.byteswap()
    frame = load_single_frame("nyu")
    assert_array_equal(np.isnan(frame.depth), disparity == 2047)
    valid = disparity != 2047
    assert_allclose(frame.depth[valid], 351.3 / (1092.5 - disparity[valid]), rtol=1e-6)
    assert frame.intrinsics.fx == pytest.approx(582.62448, abs=1e-4)


@needs_data
@pytest.mark.parametrize("dataset", ["tum", "sun"])
def test_single_frames_agree_with_open3d(dataset):
    o3d = pytest.importorskip("open3d")
    from seismo3d.data import fetch

    name = {"tum": ("TUM_color.png", "TUM_depth.png"), "sun": ("SUN_color.jpg", "SUN_depth.png")}[dataset]
    factory = {"tum": o3d.geometry.RGBDImage.create_from_tum_format,
               "sun": o3d.geometry.RGBDImage.create_from_sun_format}[dataset]
    color, depth = (o3d.io.read_image(str(fetch(f"rgbd/single_frames/{n}"))) for n in name)
    theirs = factory(color, depth, convert_rgb_to_intensity=False)
    their_depth = np.asarray(theirs.depth)  # metres, 0 = invalid or beyond Open3D's truncation (4 m / 7 m)
    frame = load_single_frame(dataset)
    assert_array_equal(np.asarray(theirs.color), frame.color)
    both = their_depth > 0
    assert both.mean() > 0.7
    assert_array_equal(frame.depth[both], their_depth[both])
    assert np.all(np.isnan(frame.depth[~both]) | (frame.depth[~both] > 3.9))


def test_single_frame_bad_dataset():
    with pytest.raises(InputError, match="dataset"):
        load_single_frame("kitti")


def test_camera_intrinsics_validation():
    k = CameraIntrinsics(500.0, 501.0, 320.0, 240.0, 640, 480)
    assert_array_equal(k.matrix, [[500, 0, 320], [0, 501, 240], [0, 0, 1]])
    assert CameraIntrinsics.from_matrix(k.matrix, 640, 480) == k
    with pytest.raises(InputError, match="fx"):
        CameraIntrinsics(0.0, 501.0, 320.0, 240.0, 640, 480)
    with pytest.raises(InputError, match="width"):
        CameraIntrinsics(500.0, 501.0, 320.0, 240.0, 640.5, 480)
    with pytest.raises(InputError, match="camera matrix"):
        CameraIntrinsics.from_matrix(np.eye(4), 640, 480)
