"""HOG-pyramid descriptor: recursive sliding histograms against direct sums, rotation invariance, parameters."""

import numpy as np
import pytest
from scipy import ndimage

from seismo3d.errors import InputError
from seismo3d.features import (
    HogPyramidParams,
    dense_ring_histograms,
    disc_half_widths,
    hog_pyramid_features,
    orientation_votes,
    ring_descriptors,
    ring_histograms,
)

RADII = (2.5, 4.0, 6.0, 9.0)


def direct_ring_histograms(bins, weights, radii, rows, cols, *, n_bins):
    """The reference: each point's ring histograms summed offset by offset (ring k: r_{k-1}^2 < d^2 <= r_k^2; no
    votes outside the image), with numpy alone."""
    bins, weights = np.asarray(bins), np.asarray(weights)
    if bins.ndim == 2:
        bins, weights = bins[..., None], weights[..., None]
    pad = int(np.floor(max(radii)))
    widths = ((pad, pad), (pad, pad), (0, 0))
    bp, wp = np.pad(bins, widths), np.pad(weights.astype(np.float64), widths)
    dy, dx = np.mgrid[-pad:pad + 1, -pad:pad + 1]
    d2 = (dy * dy + dx * dx)[..., None].repeat(bins.shape[2], axis=2)
    out = np.zeros((np.size(rows), len(radii), n_bins))
    for i, (r, c) in enumerate(zip(np.ravel(rows), np.ravel(cols))):
        b, w = bp[r:r + 2 * pad + 1, c:c + 2 * pad + 1], wp[r:r + 2 * pad + 1, c:c + 2 * pad + 1]
        inner = -1.0
        for k, rad in enumerate(radii):
            ring = (d2 <= rad * rad) & (d2 > inner)
            out[i, k] = np.bincount(b[ring], weights=w[ring], minlength=n_bins)
            inner = rad * rad
    return out.astype(np.int64) if weights.dtype.kind in "iu" else out  # exact: sums below 2**53


def _random_votes(rng, shape, n_bins, n_votes=2, integer=True):
    # the dtypes of orientation_votes (uint8 bins, int32 fixed-point weights): the kernels' signature of the matcher
    bins = rng.integers(0, n_bins, shape + (n_votes,), dtype=np.uint8)
    if integer:
        weights = rng.integers(0, 2 ** 20, shape + (n_votes,), dtype=np.int32)
    else:
        weights = rng.random(shape + (n_votes,))
    return bins, weights


@pytest.mark.parametrize("radii", [RADII, (1.0,), (3.0, 7.5), (4.0, 8.0, 12.0, 16.0)])
@pytest.mark.parametrize("seed", [0, 1])
def test_dense_recursive_histograms_equal_direct_sums_exactly(radii, seed):
    rng = np.random.default_rng(seed)
    bins, weights = _random_votes(rng, (23, 31), 12)
    dense = dense_ring_histograms(bins, weights, radii, n_bins=12)
    rows, cols = np.meshgrid(np.arange(23), np.arange(31), indexing="ij")
    direct = direct_ring_histograms(bins, weights, radii, rows.ravel(), cols.ravel(), n_bins=12)
    assert dense.dtype == np.int64
    assert np.array_equal(dense.reshape(-1, len(radii), 12), direct)


def test_dense_recursive_histograms_float_weights_match_to_1e9():
    rng = np.random.default_rng(3)
    bins, weights = _random_votes(rng, (20, 40), 16, integer=False)
    dense = dense_ring_histograms(bins, weights, RADII, n_bins=16, rows=[0, 7, 19])
    rows, cols = np.meshgrid([0, 7, 19], np.arange(40), indexing="ij")
    direct = direct_ring_histograms(bins, weights, RADII, rows.ravel(), cols.ravel(), n_bins=16)
    np.testing.assert_allclose(dense.reshape(-1, len(RADII), 16), direct, rtol=0, atol=1e-9)


@pytest.mark.parametrize("max_gap", [0, 1, 4, 1000])
def test_histograms_at_points_equal_direct_sums_for_any_slide_length(max_gap):
    rng = np.random.default_rng(5)
    bins, weights = _random_votes(rng, (30, 45), 16)
    rows = rng.integers(0, 30, 300)
    cols = rng.integers(0, 45, 300)
    rows[:40] = 11  # many points on one row: long recursive slides
    got = ring_histograms(bins, weights, RADII, rows, cols, n_bins=16, max_gap=max_gap)
    want = direct_ring_histograms(bins, weights, RADII, rows, cols, n_bins=16)
    assert np.array_equal(got, want)


def test_disc_half_widths_describe_the_digital_disc():
    for r in (1.0, 2.5, 7.0, 9.9):
        hw = disc_half_widths([r])[0]
        pad = (hw.size - 1) // 2
        dy, dx = np.mgrid[-pad:pad + 1, -pad:pad + 1]
        inside = dx ** 2 + dy ** 2 <= r * r
        from_hw = np.abs(dx) <= hw[:, None]
        assert np.array_equal(inside, from_hw)


def test_orientation_votes_split_magnitude_between_neighbouring_bins():
    rng = np.random.default_rng(2)
    gx, gy = rng.standard_normal((2, 9, 11))
    bins, weights = orientation_votes(gx, gy, n_bins=8, pad=2)
    mag = np.hypot(gx, gy)
    unit = 2.0 ** 20 / mag.max()
    inner = (slice(2, -2), slice(2, -2))
    np.testing.assert_allclose(weights[inner].sum(-1), np.rint(mag * unit), atol=1)
    angle = np.mod(np.degrees(np.arctan2(gy, gx)), 360.0)
    b0 = bins[inner][..., 0]
    # the lower bin is floor(angle / 45); tolerate the fast arctangent's 0.02 degree error at bin edges
    edge = np.abs(angle / 45.0 - np.rint(angle / 45.0)) < 1e-3
    assert np.array_equal(b0[~edge], (np.floor(angle / 45.0).astype(int) % 8)[~edge])
    assert np.array_equal(bins[inner][..., 1], (b0 + 1) % 8)
    assert not weights[:2].any() and not weights[:, -2:].any()  # the zero margin votes nothing


def _smooth_random_image(seed, size=65):
    rng = np.random.default_rng(seed)
    return ndimage.gaussian_filter(rng.random((size, size)), 2.0)


def _centre_descriptor(image, radii=(4.0, 8.0, 12.0, 16.0), n_bins=16):
    gy, gx = np.gradient(image)  # central differences: exactly equivariant under quarter turns
    bins, weights = orientation_votes(gx, gy, n_bins=n_bins)
    c = image.shape[0] // 2
    hist = ring_histograms(bins, weights, radii, [c], [c], n_bins=n_bins)
    desc, ori, index = ring_descriptors(hist, radii, peak_ratio=1.0)
    assert np.array_equal(index, [0])
    return desc[0], ori[0]


@pytest.mark.parametrize("k", [1, 2, 3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_descriptor_is_invariant_to_quarter_turns(k, seed):
    image = _smooth_random_image(seed)
    d0, o0 = _centre_descriptor(image)
    dk, ok = _centre_descriptor(np.rot90(image, k))
    np.testing.assert_allclose(dk, d0, atol=1e-5)
    # np.rot90 turns the picture counter-clockwise on screen (y down): gradient angles decrease by 90 degrees
    assert abs((o0 - ok - 90.0 * k + 180.0) % 360.0 - 180.0) < 1e-3


@pytest.mark.parametrize("angle", [37.0, 121.0])
def test_descriptor_is_nearly_invariant_to_arbitrary_rotation(angle):
    image = _smooth_random_image(7, size=129)
    rotated = ndimage.rotate(image, angle, reshape=False, order=3, mode="reflect")
    d0, o0 = _centre_descriptor(image)
    d1, o1 = _centre_descriptor(rotated)
    # other windows of the same image, as the scale of "different"
    gy, gx = np.gradient(image)
    bins, weights = orientation_votes(gx, gy, n_bins=16)
    rng = np.random.default_rng(0)
    rows, cols = rng.integers(20, 109, (2, 200))
    others, _, _ = ring_descriptors(ring_histograms(bins, weights, (4.0, 8.0, 12.0, 16.0), rows, cols, n_bins=16),
                                    (4.0, 8.0, 12.0, 16.0), peak_ratio=1.0)
    far = np.hypot(rows - 64, cols - 64) > 8
    d_true = np.linalg.norm(d1 - d0)
    d_other = np.linalg.norm(others[far] - d0, axis=1)
    assert d_true < 0.15
    assert d_true < 0.5 * np.percentile(d_other, 5)
    assert abs((o0 - o1 - angle + 180.0) % 360.0 - 180.0) < 5.0  # ndimage.rotate turns counter-clockwise on screen


def test_ring_descriptors_follow_a_circular_shift_of_all_rings():
    rng = np.random.default_rng(4)
    hist = rng.integers(0, 1000, (50, 3, 16)).astype(np.int64)
    hist[:, :, 5] += 20000  # one clear dominant orientation per window
    shifted = np.roll(hist, 3, axis=2)
    d0, o0, i0 = ring_descriptors(hist, (2.0, 4.0, 6.0), peak_ratio=1.0)
    d1, o1, i1 = ring_descriptors(shifted, (2.0, 4.0, 6.0), peak_ratio=1.0)
    assert np.array_equal(i0, np.arange(50)) and np.array_equal(i1, i0)
    np.testing.assert_allclose(d1, d0, atol=1e-6)
    np.testing.assert_allclose(np.mod(o1 - o0, 360.0), 3 * 22.5, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(d0, axis=1), 1.0, atol=1e-6)


def test_two_peaks_give_two_descriptors():
    hist = np.zeros((1, 2, 16), np.int64)
    hist[0, :, 4] = 1000
    hist[0, :, 12] = 990  # opposite direction, almost as strong: an up/down seismic reflector
    d, o, idx = ring_descriptors(hist, (3.0, 6.0), peak_ratio=0.9)
    assert np.array_equal(idx, [0, 0])
    np.testing.assert_allclose(np.sort(o), [90.0, 270.0], atol=0.5)
    d1, o1, idx1 = ring_descriptors(hist, (3.0, 6.0), peak_ratio=1.0)
    assert idx1.size == 1 and abs(o1[0] - 90.0) < 0.5


@pytest.mark.slow
def test_features_of_an_image_rotated_by_90_degrees_match_exactly():
    import skimage.data

    image = skimage.data.camera()[128:384, 128:384]
    f0 = hog_pyramid_features(image)
    f1 = hog_pyramid_features(np.rot90(image))
    assert len(f0) > 500
    # rot90: (x, y) -> (y, W - 1 - x)
    mapped = np.column_stack([f0.keypoints[:, 1], image.shape[1] - 1 - f0.keypoints[:, 0]])
    from scipy.spatial import cKDTree

    dist, j = cKDTree(f1.keypoints).query(mapped)
    close = dist < 0.6
    assert close.mean() > 0.9
    desc_err = np.linalg.norm(f1.descriptors[j[close]] - f0.descriptors[close], axis=1)
    assert np.median(desc_err) < 1e-3


def test_constant_and_tiny_images_give_no_features():
    assert len(hog_pyramid_features(np.full((64, 64), 7.0))) == 0
    assert len(hog_pyramid_features(np.random.default_rng(0).random((8, 8)))) == 0
    f = hog_pyramid_features(np.zeros((5, 5)))
    assert f.descriptors.shape == (0, 64) and f.keypoints.shape == (0, 2)


def test_mask_keeps_whole_windows_inside():
    import skimage.data

    image = skimage.data.camera()
    mask = np.zeros(image.shape, bool)
    mask[100:400, 150:450] = True
    f = hog_pyramid_features(image, mask=mask)
    assert len(f) > 100
    x, y = f.keypoints.T
    margin = f.scales / 2 - 2  # outer radius in input pixels, minus rounding
    assert np.all(x - margin >= 150) and np.all(x + margin <= 449)
    assert np.all(y - margin >= 100) and np.all(y + margin <= 399)


@pytest.mark.parametrize("bad", [
    {"radii": (8.0, 4.0)}, {"radii": ()}, {"n_bins": 2}, {"n_bins": 300}, {"scale_factor": 1.0},
    {"max_keypoints": 0}, {"peak_ratio": 0.0}, {"harris_sigma": -1.0}, {"threshold": float("nan")},
])
def test_invalid_parameters_are_rejected(bad):
    with pytest.raises(InputError):
        HogPyramidParams(**bad)


def test_invalid_votes_are_rejected():
    bins = np.zeros((5, 5), int)
    with pytest.raises(InputError, match="bins must lie"):
        dense_ring_histograms(bins + 9, np.ones((5, 5)), (2.0,), n_bins=8)
    with pytest.raises(InputError, match="same shape|both be"):
        dense_ring_histograms(bins, np.ones((4, 5)), (2.0,), n_bins=8)
    with pytest.raises(InputError, match="inside"):
        ring_histograms(bins, np.ones((5, 5)), (2.0,), [5], [0], n_bins=8)
