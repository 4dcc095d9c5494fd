"""OpenCV adapters: conversion to 8 bits, keypoint limits and masks."""

import numpy as np
import pytest
import skimage.data

from seismo3d.errors import InputError
from seismo3d.features import OPENCV_METHODS, opencv_features, to_uint8


def test_to_uint8_scales_floats_and_keeps_uint8():
    img = skimage.data.camera()
    assert np.array_equal(to_uint8(img), img)
    assert img.min() == 0 and img.max() == 255
    f = img.astype(np.float32) * 0.01 - 3.0  # any linear grey scale maps back onto 0..255
    np.testing.assert_allclose(to_uint8(f), img, atol=1)
    rgb = skimage.data.astronaut()
    gray = to_uint8(rgb)
    expected = rgb.astype(float) @ [0.299, 0.587, 0.114]
    assert gray.shape == rgb.shape[:2] and np.abs(gray - expected).max() <= 0.5 + 1e-9
    assert not to_uint8(np.full((8, 8), 5.0)).any()
    with pytest.raises(InputError, match="channels"):
        to_uint8(np.zeros((8, 8, 4)))


@pytest.mark.parametrize("method", OPENCV_METHODS)
def test_opencv_features_respect_mask_and_max_keypoints(method):
    img = skimage.data.camera()
    mask = np.zeros(img.shape, bool)
    mask[:, 256:] = True
    f = opencv_features(img, method=method, mask=mask, max_keypoints=150)
    assert 0 < len(f) <= 150
    assert np.all(f.keypoints[:, 0] >= 255.5)
    assert np.all(np.isfinite(f.scales)) and np.all(f.scales > 0)
    ori = f.orientations[np.isfinite(f.orientations)]
    assert np.all((ori >= 0) & (ori < 360))


def test_surf_is_not_offered():
    assert "surf" not in OPENCV_METHODS
    with pytest.raises(InputError, match="method"):
        opencv_features(skimage.data.camera(), method="surf")
