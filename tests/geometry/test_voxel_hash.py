"""The voxel-hash nearest-neighbour index equals a KD-tree's answer within the search distance."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from seismo3d.errors import InputError
from seismo3d.geometry.voxel_hash import VoxelHashIndex


def _surface(rng, n):
    """Points on a wavy sheet (clustered like a depth image) plus scattered outliers."""
    xy = rng.uniform(-1, 1, size=(n, 2))
    z = 0.2 * np.sin(3 * xy[:, 0]) * np.cos(2 * xy[:, 1])
    return np.column_stack([xy, z])


@pytest.mark.parametrize("cell_fraction", [0.3, 1.0, 2.5])
@pytest.mark.parametrize("dmax", [0.02, 0.3])
def test_same_neighbours_as_kdtree_3d(rng, cell_fraction, dmax):
    target = _surface(rng, 5000)
    queries = np.vstack([_surface(rng, 3000) + rng.normal(scale=0.05, size=(3000, 3)),
                         rng.uniform(-3, 3, size=(200, 3))])  # some far from every target point
    want_d, want_i = cKDTree(target).query(queries, distance_upper_bound=dmax)
    got_d, got_i = VoxelHashIndex(target, cell_fraction * dmax).query(queries, dmax)
    none = np.isinf(want_d)
    assert 0 < none.sum() < len(queries)  # both cases occur
    np.testing.assert_array_equal(np.isinf(got_d), none)
    np.testing.assert_array_equal(got_i[none], len(target))
    # the same point (random data: no ties) at the same distance
    np.testing.assert_array_equal(got_i[~none], want_i[~none])
    np.testing.assert_allclose(got_d[~none], want_d[~none], rtol=1e-12)


def test_2d_points(rng):
    target = rng.uniform(0, 10, size=(2000, 2))
    queries = rng.uniform(-1, 11, size=(1000, 2))
    want_d, want_i = cKDTree(target).query(queries, distance_upper_bound=0.4)
    got_d, got_i = VoxelHashIndex(target, 0.4).query(queries, 0.4)
    np.testing.assert_array_equal(got_i, want_i)
    np.testing.assert_allclose(got_d, want_d)


def test_refuses_bad_input():
    index = VoxelHashIndex(np.zeros((3, 3)), 1.0)
    with pytest.raises(InputError, match="queries must be"):
        index.query(np.zeros((2, 2)), 1.0)
    with pytest.raises(InputError):
        index.query(np.zeros((2, 3)), 0.0)
    with pytest.raises(InputError):
        VoxelHashIndex(np.zeros((3, 4)), 1.0)
    with pytest.raises(InputError):
        VoxelHashIndex(np.zeros((3, 3)), -1.0)


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int64, np.int32])
@pytest.mark.parametrize("d", [2, 3])
def test_axis_bounds_equal_numpys_reductions(rng, dtype, d):
    from seismo3d.geometry.neighbours import axis_bounds

    points = (rng.normal(size=(1001, d)) * 1000).astype(dtype)
    lo, hi = axis_bounds(points)
    assert lo.dtype == hi.dtype == np.dtype(dtype) and lo.shape == hi.shape == (d,)
    np.testing.assert_array_equal(lo, points.min(axis=0))
    np.testing.assert_array_equal(hi, points.max(axis=0))
