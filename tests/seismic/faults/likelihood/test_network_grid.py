"""The network grids (seismo3d.seismic.faults.likelihood.network_grid): a block's grid is the whole cube's."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.faults.likelihood.network_grid import to_network_grid


def test_network_grid_alignment_per_axis():
    block = np.random.default_rng(0).standard_normal((40, 40, 16)).astype(np.float32)
    _, first = to_network_grid(block, 0.7, origin=(13, 13), align=(1, 8))
    assert first == (10, 16, 0)  # ceil(13 * 0.7) = 10; the first multiple of 8 at or after 9.1
    with pytest.raises(InputError, match="align"):
        to_network_grid(block, 0.7, origin=(13, 13), align=(1, 8, 8))


@pytest.mark.parametrize("factor", [0.5, 0.25, 0.7])
@pytest.mark.parametrize("origin", [(0, 0), (13, 21)])
def test_the_network_grid_is_the_filtered_cube_interpolated(factor, origin):
    # the reference: the whole block filtered along every axis, then interpolated linearly onto the network samples;
    # to_network_grid filters and interpolates axis by axis, the samples first (the same operator, its float32 passes
    # rounded in another order: measured at most 4.8e-7 on these amplitudes of up to 2.9, about 2 units in the last
    # place; limit 1e-6)
    from scipy.ndimage import gaussian_filter

    from seismo3d.seismic.faults.likelihood.network_grid import anti_alias_sigma, interpolate_axis

    block = np.random.default_rng(3).standard_normal((37, 30, 41)).astype(np.float32)
    small, first = to_network_grid(block, factor, origin=origin, align=(1, 8))
    expected = gaussian_filter(block, anti_alias_sigma(factor), truncate=4.0)
    for axis, (n, o, u0) in enumerate(zip(block.shape, origin + (0,), first)):
        expected = interpolate_axis(expected, axis, np.arange(u0, u0 + small.shape[axis]) / factor - o)
        assert u0 + small.shape[axis] - 1 <= (o + n - 1) * factor + 1e-9 < u0 + small.shape[axis]
    assert small.dtype == np.float32 and small.shape == expected.shape
    np.testing.assert_allclose(small, expected, rtol=0, atol=1e-6)
