"""Horizons (seismo3d.seismic.horizons): text export, gap filling, seed checks."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import Horizon, fill_horizon, write_horizon_text
from seismo3d.seismic.horizons import as_seeds, check_live_seed


def test_write_horizon_text(tmp_path):
    times = np.array([[10.0, 10.5, np.nan], [11.0, 11.5, 12.0]], np.float32)
    hz = Horizon(times, np.ones_like(times), "peak", np.zeros((1, 3)))
    out = tmp_path / "h.txt"
    n = write_horizon_text(out, hz, inlines=[100, 101], xlines=[7, 8, 9], samples=4.0 * np.arange(20) + 4.0)
    rows = np.loadtxt(out, comments="#")
    assert n == 5 and rows.shape == (5, 3)
    np.testing.assert_allclose(rows[0], [100, 7, 44.0])
    np.testing.assert_allclose(rows[1], [100, 8, 46.0])
    with pytest.raises(InputError, match="labels"):
        write_horizon_text(out, hz, inlines=[100])


def test_fill_horizon_interpolates_inside_the_picks_only():
    t = np.array([np.nan, 10.0, np.nan, np.nan, 13.0, np.nan], np.float32)
    hz = Horizon(t, np.ones_like(t), "peak", np.zeros((1, 2)))
    filled = fill_horizon(hz)
    np.testing.assert_allclose(filled.times[1:5], [10.0, 11.0, 12.0, 13.0])
    assert np.isnan(filled.times[[0, 5]]).all() and np.isnan(filled.confidence[2])  # no extrapolation
    assert np.isnan(hz.times[2])  # the input is not modified
    grid = np.full((5, 5), np.nan, np.float32)
    grid[0, 0], grid[0, 4], grid[4, 0], grid[4, 4] = 0.0, 4.0, 8.0, 12.0  # a plane: t = 2 i + j
    plane = fill_horizon(Horizon(grid, np.ones_like(grid), "peak", np.zeros((1, 3))))
    i, j = np.indices((5, 5))
    np.testing.assert_allclose(plane.times, 2 * i + j, atol=1e-5)
    near = fill_horizon(Horizon(grid, np.ones_like(grid), "peak", np.zeros((1, 3))), max_gap=1.0)
    assert np.isnan(near.times[2, 2]) and np.isfinite(near.times[0, 1])
    with pytest.raises(InputError, match="at least 2"):
        fill_horizon(Horizon(np.full(4, np.nan, np.float32), np.ones(4, np.float32), "peak", np.zeros((1, 2))))


def test_seed_checks():
    np.testing.assert_array_equal(as_seeds((1, 2, 3.5), (4, 4, 8)), [[1.0, 2.0, 3.5]])
    with pytest.raises(InputError, match="outside the data"):
        as_seeds((1, 2, 8.0), (4, 4, 8))
    with pytest.raises(InputError, match="seeds must be"):
        as_seeds((1, 2), (4, 4, 8))
    data = np.ones((4, 4, 8), np.float32)
    with pytest.raises(InputError, match="dead trace"):
        check_live_seed(data, np.array([1.0, 2.0, 3.0]))
