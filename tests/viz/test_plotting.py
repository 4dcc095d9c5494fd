"""Scene helpers (seismo3d.viz.plotting): the camera fitted to the room the colour bars leave."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.viz.plotting import _viewport_fractions, fit_camera, new_plotter


@pytest.mark.parametrize("view", ["iso", "xz"])
def test_the_camera_fills_the_room_and_centres_the_scene_in_it(view):
    """A box of 2 x 1 x 0.5 fitted into the upper right quarter of a 400 x 300 window, 20 px margins: its projected
    corners touch the room less its margins on one side (1 %) and are centred in it (1 % of the window)."""
    import pyvista as pv

    plotter = new_plotter(off_screen=True, window_size=(400, 300))
    plotter.add_mesh(pv.Box(bounds=(0, 2, 0, 1, 0, 0.5)))
    plotter.camera_position = view
    room = (0.5, 0.5, 1.0, 1.0)
    fit_camera(plotter, room, margin_px=(20, 20, 20, 20))
    corners = np.array([[x, y, z] for x in (0, 2) for y in (0, 1) for z in (0, 0.5)], dtype=np.float64)
    uv = _viewport_fractions(plotter.renderer, corners)
    plotter.close()
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    inner = np.array([0.5 + 20 / 400, 0.5 + 20 / 300, 1 - 20 / 400, 1 - 20 / 300])
    assert np.all(lo >= inner[:2] - 0.01) and np.all(hi <= inner[2:] + 0.01)
    assert max((hi - lo) / (inner[2:] - inner[:2])) == pytest.approx(1.0, abs=0.01)
    np.testing.assert_allclose((lo + hi) / 2, (inner[:2] + inner[2:]) / 2, atol=0.01)


def test_a_room_outside_the_window_is_refused():
    plotter = new_plotter(off_screen=True, window_size=(64, 48))
    with pytest.raises(InputError, match="fractions of the window"):
        fit_camera(plotter, (0.5, 0.2, 0.4, 1.0))
    plotter.close()
