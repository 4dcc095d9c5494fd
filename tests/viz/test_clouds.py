"""Point clouds (pyvista, off screen) and image matches (matplotlib): seismo3d.viz.clouds."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.viz.clouds import plot_matches, show_point_clouds


def test_two_clouds_in_their_colours(tmp_path):
    from matplotlib.image import imread

    rng = np.random.default_rng(0)
    plane = np.column_stack([rng.uniform(-1, 1, (2000, 2)), np.zeros(2000)])
    moved = np.eye(4)
    moved[:3, 3] = [0.0, 0.0, 0.5]
    shot = tmp_path / "clouds.png"
    show_point_clouds([plane, plane], labels=["source", "target"], transforms=[moved, None], point_size=4,
                      screenshot=shot, window_size=(320, 240))
    img = (imread(shot)[..., :3] * 255).round()
    orange = (img[..., 0] > 200) & (img[..., 2] < 80)  # tab:orange (255, 127, 14)
    blue = (img[..., 2] > 150) & (img[..., 0] < 80)  # tab:blue (31, 119, 180)
    assert orange.mean() > 0.01 and blue.mean() > 0.01
    with pytest.raises(InputError, match="labels"):
        show_point_clouds([plane], labels=["a", "b"], screenshot=shot)
    with pytest.raises(InputError, match="N, 3"):
        show_point_clouds([plane[:, :2]], screenshot=shot)


def test_matches_drawn_green_and_red(tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    image = np.zeros((40, 60), np.uint8)
    xy1 = np.array([[10.0, 10.0], [20.0, 30.0]])
    xy2 = xy1 + [5.0, 0.0]
    fig = plot_matches(image, image, xy1, xy2, correct=np.array([True, False]), title="two matches")
    lines = fig.axes[0].get_lines()
    assert len(lines) == 2
    assert lines[0].get_xdata()[1] == pytest.approx(15.0 + 60)  # second image drawn to the right of the first
    assert [ln.get_color() for ln in lines] == ["tab:green", "tab:red"]
    FigureCanvasAgg(fig).print_png(tmp_path / "m.png")
    with pytest.raises(InputError):
        plot_matches(image, image, xy1, xy2[:1])


def test_many_matches_thinned_to_a_readable_spread_and_counted():
    """4000 matches (a real TUM pair gives 4011 verified): at most 80 lines, at most one per grid cell, spread over
    the image, and the picture says how many of how many it draws."""
    rng = np.random.default_rng(1)
    image = np.zeros((480, 640), np.uint8)
    xy1 = np.column_stack([rng.uniform(0, 640, 4000), rng.uniform(0, 480, 4000)])
    fig = plot_matches(image, image, xy1, xy1 + [3.0, 1.0])
    lines = fig.axes[0].get_lines()
    assert 40 <= len(lines) <= 80
    starts = np.array([ln.get_xydata()[0] for ln in lines])
    cell = np.sqrt(480 * 640 / 80)
    assert len({(int(x // cell), int(y // cell)) for x, y in starts}) == len(lines)  # one per cell
    assert np.ptp(starts[:, 0]) > 500 and np.ptp(starts[:, 1]) > 380  # over the whole image, not a clump
    assert f"{len(lines)} of 4000 matches drawn" in fig.axes[0].get_title()
    few = plot_matches(image, image, xy1[:2], xy1[:2])
    assert len(few.axes[0].get_lines()) == 2 and "all 2 matches drawn" in few.axes[0].get_title()
