"""Resampling through an index transform (seismo3d.seismic.volumes.resample), and the test pairs it is checked on."""

import numpy as np
import pytest

from seismo3d.data import resampled_pair, synthetic_cube
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
