"""Sequence readers: the real 7-Scenes subset, generated TUM-layout folders, and bad input."""

import cv2
import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import DataIntegrityError, DataNotFoundError, InputError
from seismo3d.mapping import associate_timestamps, open_sequence, read_tum_trajectory
from seismo3d.mapping.sequences import TUM_INTRINSICS


def test_seven_scenes_subset(seven_scenes):
    from seismo3d.data import load_7scenes_frame

    seq = seven_scenes
    assert seq.layout == "7scenes" and len(seq) == 100 and seq.depth_scale == 1000.0
    assert (seq.intrinsics.fx, seq.intrinsics.cx, seq.intrinsics.width) == (585.0, 320.0, 640)
    assert_allclose(np.diff(seq.timestamps), 5 / 30.0, atol=1e-5)
    frame, ref = seq.read(50), load_7scenes_frame(250)
    assert frame.timestamp == pytest.approx(250 / 30.0, abs=1e-5)
    assert np.array_equal(np.isnan(frame.depth), np.isnan(ref.depth))
    assert_allclose(frame.depth, ref.depth, equal_nan=True)
    assert_allclose(frame.pose, ref.pose, atol=2e-4)  # groundtruth.txt keeps 7 decimals of the 4x4 files
    assert seq.groundtruth[1].shape == (100, 4, 4)


def _write_tum(folder, n=6, *, name_times=None, depth_dtype=np.uint16, size=(48, 64)):
    """A TUM-layout folder with n frames: colour and depth 30 ms apart, a ground truth every 10 ms."""
    (folder / "rgb").mkdir(parents=True)
    (folder / "depth").mkdir()
    rgb, dep, gt = ["# rgb"], ["# depth"], ["# timestamp tx ty tz qx qy qz qw"]
    times = name_times or [1000.0 + 0.033 * i for i in range(n)]
    for i, t in enumerate(times):
        depth = np.full(size, 5000 + 100 * i, depth_dtype)  # 1.0 m, 1.02 m, ...
        cv2.imwrite(str(folder / f"depth/{t:.6f}.png"), depth)
        cv2.imwrite(str(folder / f"rgb/{t + 0.004:.6f}.png"), np.full(size + (3,), 100, np.uint8))
        rgb.append(f"{t + 0.004:.6f} rgb/{t + 0.004:.6f}.png")
        dep.append(f"{t:.6f} depth/{t:.6f}.png")
    for j in range(int(len(times) * 4)):
        t = times[0] - 0.01 + 0.01 * j
        gt.append(f"{t:.4f} {0.01 * j:.4f} 0 0 0 0 0 1")
    (folder / "rgb.txt").write_text("\n".join(rgb) + "\n")
    (folder / "depth.txt").write_text("\n".join(dep) + "\n")
    (folder / "groundtruth.txt").write_text("\n".join(gt) + "\n")
    return times


def test_tum_layout_is_associated_and_scaled(tmp_path):
    folder = tmp_path / "rgbd_dataset_freiburg1_test"
    times = _write_tum(folder)
    seq = open_sequence(folder)
    assert seq.layout == "tum" and len(seq) == 6 and seq.depth_scale == 5000.0
    fx, fy, cx, cy = TUM_INTRINSICS["fr1"]
    assert (seq.intrinsics.fx, seq.intrinsics.cy, seq.intrinsics.width, seq.intrinsics.height) == (fx, cy, 64, 48)
    assert_allclose(seq.timestamps, times)
    frame = seq.read(2)
    assert frame.depth.dtype == np.float32 and frame.depth[0, 0] == pytest.approx(1.04)
    assert frame.color.shape == (48, 64, 3)
    assert frame.pose is not None and frame.pose[0, 3] == pytest.approx(0.01 * round((times[2] - times[0] + 0.01) /
                                                                                      0.01), abs=0.011)


def test_unknown_camera_gets_the_ros_default(tmp_path):
    folder = tmp_path / "my_sequence"
    _write_tum(folder, n=3)
    seq = open_sequence(folder)
    assert (seq.intrinsics.fx, seq.intrinsics.cx) == (525.0, 319.5)


def test_bad_frames_raise_clear_errors(tmp_path):
    folder = tmp_path / "seq"
    times = _write_tum(folder, n=4)
    (folder / f"depth/{times[1]:.6f}.png").unlink()
    cv2.imwrite(str(folder / f"depth/{times[2]:.6f}.png"), np.zeros((48, 64), np.uint8))
    cv2.imwrite(str(folder / f"depth/{times[3]:.6f}.png"), np.zeros((24, 32), np.uint16))
    seq = open_sequence(folder)
    seq.read(0)
    with pytest.raises(DataNotFoundError, match="missing"):
        seq.read(1)
    with pytest.raises(DataIntegrityError, match="16-bit"):
        seq.read(2)
    with pytest.raises(DataIntegrityError, match="32 x 24"):
        seq.read(3)


def test_not_a_sequence(tmp_path):
    with pytest.raises(InputError, match="neither a TUM"):
        open_sequence(tmp_path)
    with pytest.raises(DataNotFoundError):
        open_sequence(tmp_path / "absent")


def test_associate_timestamps_pairs_closest_first():
    i, j = associate_timestamps([0.0, 0.033, 0.066, 0.5], [0.001, 0.030, 0.070, 0.071], max_difference=0.02)
    assert i.tolist() == [0, 1, 2] and j.tolist() == [0, 1, 2]


def test_read_tum_trajectory(data_dir):
    from seismo3d.data import fetch

    t, p = read_tum_trajectory(fetch("rgbd/tum_trajectories/freiburg1_xyz-groundtruth.txt"))
    assert len(t) > 1000 and np.all(np.diff(t) > 0)
    r = p[:, :3, :3]
    assert_allclose(np.einsum("nji,njk->nik", r, r), np.broadcast_to(np.eye(3), r.shape), atol=1e-6)


def test_raw_seven_scenes_folder(tmp_path, data_dir):
    """The origin's seq-XX layout: frame-NNNNNN.color.png / .depth.png / .pose.txt side by side, no lists."""
    import shutil

    from seismo3d.data import fetch

    src = fetch("rgbd/7scenes_redkitchen_0000_0495/associations.txt").parent
    for n in (0, 5, 10):
        stem = f"frame-{n:06d}"
        shutil.copy(src / f"depth/{stem}.depth.png", tmp_path)
        shutil.copy(src / f"pose/{stem}.pose.txt", tmp_path)
        cv2.imwrite(str(tmp_path / f"{stem}.color.png"), cv2.imread(str(src / f"rgb/{stem}.color.jpg")))
    seq = open_sequence(tmp_path)
    assert seq.layout == "7scenes" and len(seq) == 3 and seq.intrinsics.fx == 585.0
    assert_allclose(seq.timestamps, [0.0, 5 / 30.0, 10 / 30.0])
    frame = seq.read(1)
    assert frame.pose is not None and frame.color.shape == (480, 640, 3)
    assert_allclose(frame.pose, np.loadtxt(src / "pose/frame-000005.pose.txt"), atol=1e-9)
    assert seq.groundtruth[1].shape == (3, 4, 4)
