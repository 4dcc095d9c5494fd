"""Horizon rendering (seismo3d.viz.horizons): a surface with holes where the horizon is empty."""

import numpy as np

import pytest

from seismo3d.errors import InputError
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


def test_plot_horizon_section_draws_each_pick_at_its_time():
    from seismo3d.viz import plot_horizon_section

    section = np.random.default_rng(0).normal(size=(30, 50))
    picks = {"people": np.full(30, 10.0), "tracked": np.where(np.arange(30) < 5, np.nan, 12.0)}
    fig = plot_horizon_section(section, picks, samples=100 + 4.0 * np.arange(50), styles={"people": {"lw": 4}})
    people, tracked = fig.axes[0].get_lines()
    np.testing.assert_allclose(people.get_ydata(), 140.0)  # sample 10 at 4 ms from 100 ms
    assert people.get_linewidth() == 4
    assert np.isnan(tracked.get_ydata()[:5]).all() and tracked.get_ydata()[5] == 148.0
    with pytest.raises(InputError):
        plot_horizon_section(section, {"short": np.zeros(3)})
