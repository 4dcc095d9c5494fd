"""Matching: NN + ratio + cross-check, the match_images chain on real images, bad inputs, CSV output."""

import csv
import os
from pathlib import Path

import numpy as np
import pytest
import skimage.data

from seismo3d.errors import InputError
from seismo3d.features import (
    METHODS,
    Features,
    MatchResult,
    detect_and_describe,
    evaluate_matches,
    match_descriptors,
    match_features,
    match_images,
    rotation_homography,
    scale_homography,
    tilt_homography,
    warp_image,
    write_matches_csv,
)


def _brute_force(d1, d2, ratio, cross_check, hamming=False):
    if hamming:
        a, b = np.unpackbits(d1, axis=1).astype(int), np.unpackbits(d2, axis=1).astype(int)
        dist = (a[:, None, :] != b[None, :, :]).sum(-1).astype(float)
    else:
        dist = np.linalg.norm(d1[:, None, :].astype(float) - d2[None, :, :], axis=-1)
    nn = dist.argmin(1)
    two = np.sort(dist, axis=1)[:, :2]
    ok = two[:, 0] < ratio * two[:, 1]
    if cross_check:
        ok &= dist.argmin(0)[nn] == np.arange(len(d1))
    return np.nonzero(ok)[0], nn[ok], (two[:, 0] / two[:, 1])[ok]


@pytest.mark.slow
@pytest.mark.parametrize("cross_check", [True, False])
@pytest.mark.parametrize("ratio", [0.6, 0.8, 0.95])
def test_match_descriptors_equals_brute_force_euclidean(ratio, cross_check):
    rng = np.random.default_rng(0)
    d2 = rng.random((300, 32)).astype(np.float32)
    d1 = np.vstack([d2[:150] + 0.02 * rng.standard_normal((150, 32)), rng.random((100, 32))]).astype(np.float32)
    i1, i2, r = match_descriptors(d1, d2, ratio=ratio, cross_check=cross_check)
    j1, j2, rr = _brute_force(d1, d2, ratio, cross_check)
    assert np.array_equal(i1, j1) and np.array_equal(i2, j2)
    np.testing.assert_allclose(r, rr, atol=1e-4)


def test_match_descriptors_equals_brute_force_hamming_and_blocks(monkeypatch):
    import seismo3d.features.matching as matching

    monkeypatch.setattr(matching, "_BLOCK", 7)  # several row blocks: the column minima must merge across them
    rng = np.random.default_rng(1)
    d2 = rng.integers(0, 256, (120, 32), dtype=np.uint8)
    d1 = d2[:60].copy()
    d1[:, :4] ^= rng.integers(0, 256, (60, 4), dtype=np.uint8)
    i1, i2, r = match_descriptors(d1, d2, binary=True)
    j1, j2, rr = _brute_force(d1, d2, 0.8, True, hamming=True)
    assert np.array_equal(i1, j1) and np.array_equal(i2, j2)
    np.testing.assert_allclose(r, rr, atol=1e-6)
    assert len(i1) > 40 and np.all(i1 == i2)


def test_match_descriptors_edge_cases():
    d = np.random.default_rng(2).random((5, 8)).astype(np.float32)
    for a, b in ((d[:0], d), (d, d[:1]), (d[:0], d[:0])):
        i1, i2, r = match_descriptors(a, b)
        assert i1.size == i2.size == r.size == 0
    with pytest.raises(InputError, match="width"):
        match_descriptors(d, d[:, :4])
    with pytest.raises(InputError, match="ratio"):
        match_descriptors(d, d, ratio=1.5)
    bad = d.copy()
    bad[0, 0] = np.nan
    with pytest.raises(InputError, match="NaN"):
        match_descriptors(bad, d)


@pytest.mark.slow
@pytest.mark.parametrize("make_h, value", [(rotation_homography, 45), (tilt_homography, 25),
                                           (scale_homography, 0.8)])
def test_hog_matches_a_real_photo_under_the_papers_views(make_h, value):
    image = skimage.data.camera()
    h = make_h(image.shape, value)
    warped, valid = warp_image(image, h)
    result = match_images(image, warped, method="hog", mask2=valid, verify="homography")
    before = evaluate_matches(result.xy1, result.xy2, h)
    assert before.n_matches > 300
    assert before.fraction_correct > 0.95  # the paper's Tables 2-4 (>= 95 / 72 / 84 %)
    corners = np.array([[0, 0, 1], [511, 0, 1], [0, 511, 1], [511, 511, 1.0]])
    fit = corners @ result.homography.T
    truth = corners @ h.T
    err = np.linalg.norm(fit[:, :2] / fit[:, 2:] - truth[:, :2] / truth[:, 2:], axis=1)
    assert err.max() < 0.15  # pixels, at the image corners: measured 0.064-0.094 over the views, limit 1.5x the worst
    assert result.n_inliers >= 0.95 * before.n_correct


@pytest.mark.slow
def test_match_images_on_real_seismic_neighbour_lines(data_dir):
    path = Path(data_dir) / "seismic" / "sections"
    a = np.fromfile(path / "costarica_gx808.f32be", ">f4").reshape(825, -1).T
    b = np.fromfile(path / "costarica_gx809.f32be", ">f4").reshape(825, -1).T
    result = match_images(a, b, method="hog", verify="similarity")
    assert result.n_inliers > 300
    # two neighbouring parallel lines: the fitted similarity is close to the identity
    np.testing.assert_allclose(result.homography[:2, :2], np.eye(2), atol=0.01)
    assert np.all(np.abs(result.homography[:2, 2]) < 3.0)


@pytest.mark.slow
@pytest.mark.parametrize("method", METHODS)
def test_every_method_shares_the_interface(method):
    image = skimage.data.camera()[::2, ::2]
    features = detect_and_describe(image, method=method)
    assert isinstance(features, Features) and features.method == method
    assert features.keypoints.shape == (len(features), 2) and features.keypoints.dtype == np.float64
    assert features.descriptors.shape[0] == len(features)
    assert features.descriptors.dtype == (np.uint8 if features.binary else np.float32)
    assert features.binary == (method not in ("hog", "sift"))
    for attr in ("scales", "orientations", "responses"):
        assert getattr(features, attr).shape == (len(features),)
    result = match_images(image, np.rot90(image).copy(), method=method, verify="similarity")
    assert isinstance(result, MatchResult) and result.method == method
    truth = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, image.shape[1] - 1.0], [0.0, 0.0, 1.0]])
    assert evaluate_matches(result.xy1[result.inliers], result.xy2[result.inliers], truth).fraction_correct > 0.97


@pytest.mark.parametrize("method", ["hog", "sift", "orb"])
@pytest.mark.parametrize("image", [
    np.full((64, 64), 3.0),  # constant
    np.zeros((12, 12)),  # tiny and constant
    np.random.default_rng(0).random((6, 6)),  # smaller than any descriptor window
    np.full((40, 40, 3), 200, np.uint8),  # constant colour
], ids=["constant", "tiny", "smaller-than-window", "constant-rgb"])
def test_images_without_structure_give_an_empty_match_set(method, image):
    result = match_images(image, image, method=method)
    assert len(result) == 0 and result.n_inliers == 0 and result.homography is None
    assert result.xy1.shape == (0, 2)


@pytest.mark.parametrize("method", ["hog", "sift"])
@pytest.mark.parametrize("image, message", [
    (np.zeros((0, 0)), "at least 2x2"),
    (np.zeros((1, 1)), "at least 2x2"),
    (np.zeros(10), "2D"),
    (np.where(np.eye(32) > 0, np.nan, 1.0), "NaN"),
    (np.zeros((32, 32, 4)), "4 channels"),
    (np.zeros((32, 32, 2)), "2D"),
])
def test_bad_images_raise_a_clear_input_error(method, image, message):
    with pytest.raises(InputError, match=message):
        match_images(image, np.ones((32, 32)), method=method)


def test_bad_options_raise_input_error():
    image = skimage.data.camera()[:64, :64]
    with pytest.raises(InputError, match="method"):
        detect_and_describe(image, method="surf")
    with pytest.raises(InputError, match="verify"):
        match_images(image, image, verify="affine")
    with pytest.raises(InputError, match="mask"):
        detect_and_describe(image, mask=np.ones((10, 10), bool))
    f_hog = detect_and_describe(image, method="hog")
    f_orb = detect_and_describe(image, method="orb")
    with pytest.raises(InputError, match="same method"):
        match_features(f_hog, f_orb)


@pytest.mark.slow
def test_write_matches_csv_writes_verified_rows_atomically(tmp_path):
    image = skimage.data.camera()
    h = rotation_homography(image.shape, 30)
    warped, valid = warp_image(image, h)
    result = match_images(image, warped, mask2=valid)
    path = tmp_path / "matches.csv"
    path.write_text("old content\n")
    n = write_matches_csv(path, result)
    assert n == result.n_inliers > 100
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["x1", "y1", "x2", "y2", "score"]
    table = np.array(rows[1:], float)
    assert table.shape == (n, 5)
    np.testing.assert_allclose(table[:, :2], result.xy1[result.inliers], atol=1e-3)
    np.testing.assert_allclose(table[:, 2:4], result.xy2[result.inliers], atol=1e-3)
    assert np.all((table[:, 4] > 0) & (table[:, 4] <= 1))
    assert sorted(os.listdir(tmp_path)) == ["matches.csv"]  # no temporary file left behind
    assert write_matches_csv(path, result, inliers_only=False) == len(result)
    with pytest.raises(InputError):
        write_matches_csv(path, "not a result")
