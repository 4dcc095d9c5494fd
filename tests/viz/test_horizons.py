"""Horizon rendering (seismo3d.viz.horizons): a surface with holes where the horizon is empty."""

import numpy as np

from seismo3d.seismic import Horizon
from seismo3d.viz import horizon_surface


def test_horizon_surface_has_a_hole_where_the_horizon_is_empty():
    times = np.array([[10.0, 10.5, np.nan], [11.0, 11.5, 12.0]], np.float32)
    hz = Horizon(times, np.ones_like(times), "peak", np.zeros((1, 3)))
    mesh = horizon_surface(hz, inlines=[100, 101], xlines=[7, 8, 9])
    assert mesh.n_points == 5 and mesh.n_cells == 1  # one quad: the other has an empty corner
    np.testing.assert_allclose(mesh.points[:, 2], -times[np.isfinite(times)])
    np.testing.assert_array_equal(mesh.point_data["inline"], [100, 100, 101, 101, 101])
    timed = horizon_surface(hz, samples=4.0 * np.arange(20))
    np.testing.assert_allclose(timed.point_data["time_or_depth"], 4.0 * times[np.isfinite(times)])
