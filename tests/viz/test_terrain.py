"""seismo3d.viz.terrain: the rose diagram and the lineament map are written as PNGs; bad shapes are refused."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.viz import plot_lineament_map, plot_rose


@pytest.mark.slow
def test_rose_and_map(tmp_path):
    az = np.array([10.0, 15.0, 100.0])
    length = np.array([1000.0, 500.0, 2000.0])
    rose = plot_rose(az, length, tmp_path / "rose.png")
    assert rose.read_bytes()[:4] == b"\x89PNG"
    shade = np.random.default_rng(0).random((30, 40))
    shade[0, 0] = np.nan
    segs = np.array([[0.0, 0.0, 10.0, 10.0], [5.0, 20.0, 30.0, 2.0], [1.0, 1.0, 2.0, 2.0]])
    path = plot_lineament_map(shade, (0, 40, 0, 30), segs, az, tmp_path / "map.png", aspect=1.2)
    assert path.read_bytes()[:4] == b"\x89PNG"


def test_errors(tmp_path):
    with pytest.raises(InputError, match="one value per lineament"):
        plot_rose([1.0, 2.0], [1.0], tmp_path / "r.png")
    with pytest.raises(InputError, match="divide 180"):
        plot_rose([1.0], [1.0], tmp_path / "r.png", bin_deg=7)
    with pytest.raises(InputError, match="2 segments but 1 azimuths"):
        plot_lineament_map(np.zeros((5, 5)), (0, 5, 0, 5), np.zeros((2, 4)), [1.0], tmp_path / "m.png")
    with pytest.raises(InputError, match="does not exist"):
        plot_rose([1.0], [1.0], tmp_path / "missing" / "r.png")
