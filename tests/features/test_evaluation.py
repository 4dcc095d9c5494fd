"""Ground-truth views of the paper's Tables 2-4 and the match evaluation."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.features import (
    evaluate_matches,
    reprojection_errors,
    rotation_homography,
    scale_homography,
    tilt_homography,
    timed_match,
    warp_image,
)


def _apply(h, xy):
    p = np.column_stack([xy, np.ones(len(xy))]) @ h.T
    return p[:, :2] / p[:, 2:]


def test_rotation_homography_matches_opencv_and_keeps_the_centre():
    import cv2

    h = rotation_homography((480, 640), 37.0)
    m = cv2.getRotationMatrix2D((319.5, 239.5), 37.0, 1.0)
    np.testing.assert_allclose(h[:2], m, atol=1e-12)
    np.testing.assert_allclose(_apply(rotation_homography((480, 640), 90), [[319.5, 239.5]]), [[319.5, 239.5]])


def test_scale_homography_scales_distances_about_the_centre():
    h = scale_homography((100, 200), 1.2)
    p = _apply(h, [[99.5, 49.5], [109.5, 49.5]])
    np.testing.assert_allclose(p[0], [99.5, 49.5])
    np.testing.assert_allclose(np.linalg.norm(p[1] - p[0]), 12.0)


def test_tilt_homography_is_a_plane_rotated_about_its_centre_line():
    shape = (400, 600)
    np.testing.assert_allclose(tilt_homography(shape, 0.0), np.eye(3), atol=1e-12)
    h = tilt_homography(shape, 30.0)
    cx, cy = 299.5, 199.5
    np.testing.assert_allclose(_apply(h, [[cx, cy]]), [[cx, cy]], atol=1e-9)  # the centre stays
    # points of the vertical centre line (the rotation axis) stay; the two halves are foreshortened unequally
    np.testing.assert_allclose(_apply(h, [[cx, 0.0], [cx, 399.0]]), [[cx, 0.0], [cx, 399.0]], atol=1e-9)
    left, right = _apply(h, [[cx - 100, cy], [cx + 100, cy]])
    assert 0 < cx - left[0] < 100 and 0 < right[0] - cx < 100 and abs((cx - left[0]) - (right[0] - cx)) > 5
    # by direct projection: plane point (X, 0, 0) rotated about y by 30 deg, seen at distance f = width
    f, t = 600.0, np.deg2rad(30)
    x3, z3 = 100 * np.cos(t), f - 100 * np.sin(t)
    np.testing.assert_allclose(right[0], cx + f * x3 / z3, atol=1e-9)
    hh = tilt_homography(shape, 20.0, axis="horizontal")
    np.testing.assert_allclose(_apply(hh, [[0.0, cy], [599.0, cy]]), [[0.0, cy], [599.0, cy]], atol=1e-9)
    with pytest.raises(InputError):
        tilt_homography(shape, 95.0)


def test_evaluate_matches_counts_errors_below_three_pixels():
    h = scale_homography((100, 100), 2.0)
    xy1 = np.array([[10.0, 10], [20, 20], [30, 30], [40, 40]])
    xy2 = _apply(h, xy1) + np.array([[0, 0], [2.9, 0], [3.1, 0], [0, -10]])
    ev = evaluate_matches(xy1, xy2, h)
    assert (ev.n_matches, ev.n_correct) == (4, 2)
    assert ev.fraction_correct == 0.5 and ev.percent_correct == 50.0
    np.testing.assert_allclose(reprojection_errors(xy1, xy2, h), [0, 2.9, 3.1, 10])
    empty = evaluate_matches(np.zeros((0, 2)), np.zeros((0, 2)), h)
    assert empty.n_matches == 0 and np.isnan(empty.fraction_correct)


def test_warp_image_and_timed_match():
    import skimage.data

    image = skimage.data.camera()
    h = rotation_homography(image.shape, 45)
    warped, valid = warp_image(image, h)
    assert warped.dtype == np.uint8 and warped.shape == image.shape
    assert not valid[0, 0] and valid[256, 256]
    assert abs(valid.mean() - 2 * (np.sqrt(2) - 1)) < 0.01  # the octagon common to a square and its 45 deg turn
    result, ev = timed_match(image, warped, h, method="orb", mask2=valid)
    assert ev.seconds > 0 and ev.n_matches == len(result) > 100 and ev.fraction_correct > 0.8
