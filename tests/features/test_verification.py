"""Geometric verification (RANSAC homography / similarity) and lifting matches to 3D or (trace, sample)."""

from pathlib import Path

import numpy as np
import pytest

from seismo3d.errors import InputError, RegistrationError
from seismo3d.features import (
    MatchResult,
    fit_homography,
    fit_similarity_2d,
    lift_match_pairs,
    lift_matches_depth,
    lift_matches_section,
    match_images,
    verify_matches,
)


def _project(h, xy):
    p = np.column_stack([xy, np.ones(len(xy))]) @ h.T
    return p[:, :2] / p[:, 2:]


@pytest.mark.parametrize("estimator", ["usac", "ransac"])
def test_fit_homography_recovers_the_truth_among_outliers(estimator, rng):
    h = np.array([[0.9, 0.1, 20.0], [-0.05, 1.1, -10.0], [1e-4, -2e-4, 1.0]])
    xy1 = rng.uniform(0, 500, (300, 2))
    xy2 = _project(h, xy1) + rng.normal(0, 0.3, (300, 2))
    outliers = rng.random(300) < 0.4
    xy2[outliers] = rng.uniform(0, 500, (outliers.sum(), 2))
    fit, inliers = fit_homography(xy1, xy2, threshold=2.0, estimator=estimator)
    assert np.mean(inliers[~outliers]) > 0.95 and np.mean(inliers[outliers]) < 0.05
    grid = np.array([[0, 0], [500, 0], [0, 500], [500, 500.0]])
    assert np.abs(_project(fit, grid) - _project(h, grid)).max() < 1.0


def test_fit_similarity_recovers_rotation_scale_shift(rng):
    a = np.deg2rad(20)
    s = 1.1
    t = np.array([[s * np.cos(a), -s * np.sin(a), 5.0], [s * np.sin(a), s * np.cos(a), -7.0], [0, 0, 1.0]])
    xy1 = rng.uniform(0, 300, (100, 2))
    xy2 = _project(t, xy1)
    xy2[:20] += 50.0
    fit, inliers = fit_similarity_2d(xy1, xy2)
    np.testing.assert_allclose(fit, t, atol=1e-6)
    assert not inliers[:20].any() and inliers[20:].all()


def test_too_few_matches_raise_registration_error_and_verify_returns_none():
    with pytest.raises(RegistrationError, match="at least 4"):
        fit_homography(np.zeros((3, 2)), np.zeros((3, 2)))
    with pytest.raises(RegistrationError, match="at least 2"):
        fit_similarity_2d(np.zeros((1, 2)), np.zeros((1, 2)))
    with pytest.raises(InputError):
        fit_homography(np.zeros((5, 2)), np.zeros((4, 2)))
    empty = MatchResult(np.zeros((2, 2)), np.zeros((2, 2)), np.ones(2), np.arange(2), np.arange(2), None,
                        np.ones(2, bool), 2, "hog")
    checked = verify_matches(empty, model="homography")
    assert checked.homography is None and not checked.inliers.any()


def test_lift_matches_depth_back_projects_through_the_pinhole_model():
    depth = np.full((4, 6), 2000, np.uint16)  # millimetres
    depth[1, 2] = 0  # missing
    k = np.array([[500.0, 0, 3.0], [0, 400.0, 2.0], [0, 0, 1]])
    xy = np.array([[3.0, 2.0], [2.2, 0.9], [5.0, 3.0], [7.0, 1.0], [0.4, 0.0]])
    points, index = lift_matches_depth(xy, depth, k, depth_scale=1000.0)
    assert np.array_equal(index, [0, 2, 4])  # (2.2, 0.9) reads the missing pixel, (7, 1) is outside
    expected = np.array([[0, 0, 2.0], [2 * 2.0 / 500, 1 * 2.0 / 400, 2.0], [-2.6 * 2.0 / 500, -2 * 2.0 / 400, 2.0]])
    np.testing.assert_allclose(points, expected)
    p4, i4 = lift_matches_depth(xy, depth.astype(float) / 1000, (500.0, 400.0, 3.0, 2.0), max_depth=1.5)
    assert p4.shape == (0, 3) and i4.size == 0
    with pytest.raises(InputError, match="intrinsics"):
        lift_matches_depth(xy, depth, np.eye(2))


@pytest.mark.slow
def test_lift_match_pairs_on_real_tum_frames_agrees_with_motion_capture(data_dir):
    import cv2
    from scipy.spatial.transform import Rotation

    folder = Path(data_dir) / "rgbd" / "tum_fr1xyz_pair"
    img1 = cv2.imread(str(folder / "img_prev.png"))[..., ::-1]
    img2 = cv2.imread(str(folder / "img_curr.png"))[..., ::-1]
    dep1 = cv2.imread(str(folder / "dep_prev.png"), cv2.IMREAD_UNCHANGED)
    dep2 = cv2.imread(str(folder / "dep_curr.png"), cv2.IMREAD_UNCHANGED)

    def pose(name):
        v = np.loadtxt(folder / name)
        t = np.eye(4)
        t[:3, :3] = Rotation.from_quat(v[3:]).as_matrix()
        t[:3, 3] = v[:3]
        return t

    rel = np.linalg.inv(pose("pose_curr.txt")) @ pose("pose_prev.txt")  # camera 1 -> camera 2
    result = match_images(img1, img2, method="hog")
    p1, p2, index = lift_match_pairs(result, dep1, dep2, (517.3, 516.5, 318.6, 255.3), depth_scale=5000.0)
    assert len(index) > 500 and np.all(result.inliers[index])
    err = np.linalg.norm(p1 @ rel[:3, :3].T + rel[:3, 3] - p2, axis=1)
    still = np.linalg.norm(p1 - p2, axis=1)
    assert np.median(err) < 0.012  # metres; the camera moved 2.2 cm
    assert np.median(err) < 0.6 * np.median(still)


def test_lift_matches_section_maps_columns_to_traces_and_rows_to_samples():
    xy = np.array([[0.0, 0.0], [10.5, 3.0]])
    pts = lift_matches_section(xy, first_trace=1000, trace_step=2, first_sample=4.0, sample_step=4.0)
    np.testing.assert_allclose(pts, [[1000, 4.0], [1021, 16.0]])
    assert lift_matches_section(np.zeros((0, 2))).shape == (0, 2)
    with pytest.raises(InputError):
        lift_matches_section(xy, trace_step=0)
