"""Resampling through an index transform (seismo3d.seismic.volumes.resample), and the test pairs it is checked on."""

import numpy as np
import pytest

from seismo3d.data import random_grid_pair, resampled_pair, synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import resample_volume


@pytest.fixture(scope="module")
def big():
    return synthetic_cube((104, 104, 112), n_faults=3, seed=1).cube


def test_resample_volume_applies_the_index_transform(big):
    cube = big[:24, :24, :32]
    t = np.eye(4)
    t[:3, 3] = (2.0, -1.0, 3.0)
    out = resample_volume(cube, t, cube.shape, order=1)
    np.testing.assert_allclose(out[2:, :-1, 3:], cube[:-2, 1:, :-3], atol=1e-5)
    assert np.isnan(out[:2]).all()
    with pytest.raises(InputError, match="singular"):
        resample_volume(cube, np.diag([1.0, 0.0, 1.0, 1.0]), cube.shape)
    with pytest.raises(InputError, match="order must be an int in \\[0, 5\\]"):
        resample_volume(cube, t, cube.shape, order=7)


def test_resampled_pair_truth_maps_moving_samples_onto_the_fixed_volume(big):
    fixed, moving, truth = resampled_pair(big, (48, 48, 64), scales=(1.0, 1.0, 1.0), angle_deg=90.0)
    # a 90-degree map rotation with unit scales maps moving samples exactly onto fixed samples
    back = resample_volume(moving, truth, fixed.shape, order=1)
    ok = np.isfinite(back)
    assert ok.mean() > 0.4
    np.testing.assert_allclose(back[ok], fixed[ok], atol=1e-4)


@pytest.mark.slow
def test_random_grid_pairs_lie_inside_the_fixed_block_and_their_truth_maps_them_onto_it(big):
    rng = np.random.default_rng(5)
    for _ in range(6):
        pair = random_grid_pair(big, (64, 48, 80), rng)
        assert abs(pair.rotation_deg) <= 30.0
        assert np.all((pair.scales[:2] >= 0.7) & (pair.scales[:2] <= 1.4))
        assert 0.9 <= pair.scales[2] <= 1.1 and min(pair.moving.shape) >= 8
        # the moving corners map inside the fixed block, a sample in from its edges
        corners = np.array(np.meshgrid(*[[0.0, n - 1.0] for n in pair.moving.shape], indexing="ij")).reshape(3, -1)
        mapped = pair.transform_index[:3, :3] @ corners + pair.transform_index[:3, 3:]
        assert np.all(mapped >= 1.0 - 1e-9) and np.all(mapped <= np.array(pair.fixed.shape)[:, None] - 2.0 + 1e-9)
        np.testing.assert_array_equal(pair.fixed, big[tuple(slice(c, c + n) for c, n in zip(pair.corner,
                                                                                             pair.fixed.shape))])
        # the fixed block resampled through the truth at the moving samples is the moving block (two
        # interpolators, Lanczos-3 and the cubic B-spline, on a band-limited cube)
        back = resample_volume(pair.fixed, np.linalg.inv(pair.transform_index), pair.moving.shape)
        inner = back[2:-2, 2:-2, 2:-2]
        assert np.isfinite(inner).all()
        assert np.corrcoef(inner.ravel(), pair.moving[2:-2, 2:-2, 2:-2].ravel())[0, 1] > 0.98
    with pytest.raises(InputError, match="too small"):
        random_grid_pair(big, (12, 12, 12), rng, lateral_scales=(1.3, 1.4))  # 8 traces span 9.1 > 9
