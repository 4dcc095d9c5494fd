"""seismo3d.terrain.surface: rasterising, hole filling, grid normals, sampling."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.terrain import fill_holes, grid_normals, point_spacing, rasterize_points, sample_grid


def test_rasterize_statistics_and_geometry():
    pts = np.array([[0.2, 0.2, 1.0], [0.7, 0.4, 3.0], [2.1, 0.3, 5.0], [0.1, 1.9, 7.0]])
    g = rasterize_points(pts, 1.0, statistic="max", fill=False)
    assert g.elevation.shape == (2, 3)
    assert g.elevation[1, 0] == 3.0 and g.elevation[1, 2] == 5.0 and g.elevation[0, 0] == 7.0
    assert np.isnan(g.elevation[0, 1]) and not g.observed[0, 1]
    assert g.xy(1, 0) == pytest.approx((0.6, 0.7))  # cell centres half a cell from the minimum corner (0.1, 0.2)
    assert rasterize_points(pts, 1.0, statistic="mean", fill=False).elevation[1, 0] == 2.0
    assert rasterize_points(pts, 1.0, statistic="min", fill=False).elevation[1, 0] == 1.0
    filled = rasterize_points(pts, 1.0)
    assert np.isfinite(filled.elevation).all() and filled.elevation[1, 0] == 3.0


def test_fill_holes_is_smooth_and_keeps_data():
    rows, cols = np.mgrid[0:64, 0:64].astype(float)
    z = 0.5 * rows + 0.25 * cols
    observed = np.ones_like(z, bool)
    observed[20:40, 10:50] = False
    out = fill_holes(np.where(observed, z, np.nan), observed)
    np.testing.assert_array_equal(out[observed], z[observed])
    # a plane is filled to within a few cells' slope (push-pull is an average, not a plane fit)
    assert np.abs(out - z).max() < 6.0 and np.all(np.isfinite(out))
    with pytest.raises(InputError, match="no cell"):
        fill_holes(z, np.zeros_like(observed))


def test_grid_normals_of_a_plane_and_spacing():
    rows, cols = np.mgrid[0:10, 0:12].astype(float)
    z = 0.5 * cols * 2.0  # dz/dx = 0.5 with 2 m columns
    n = grid_normals(z, (1.0, 2.0))
    np.testing.assert_allclose(n[..., 0], -0.5 / np.sqrt(1.25))
    np.testing.assert_allclose(n[..., 2], 1 / np.sqrt(1.25))
    rng = np.random.default_rng(0)
    pts = np.column_stack([rng.uniform(0, 100, 10000), rng.uniform(0, 100, 10000), np.zeros(10000)])
    assert point_spacing(pts) == pytest.approx(1.0, rel=0.05)


def test_sample_grid_bilinear_and_unobserved():
    pts = np.array([[x, y, x + 2 * y] for x in range(5) for y in range(4)], float)
    g = rasterize_points(pts, 1.0, fill=False)
    # cell centres sit half a cell from the points binned into them: the grid is the function shifted by (0.5, 0.5)
    assert sample_grid(g, np.array([1.5]), np.array([2.25])) == pytest.approx([(1.5 - 0.5) + 2 * (2.25 - 0.5)])
    assert np.isnan(sample_grid(g, np.array([10.0]), np.array([0.0]))[0])
