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
