"""A DEM in 3D (seismo3d.viz.terrain3d): surface, lineaments and path rendered off screen, and `seismo3d render`
on a GeoTIFF."""

import numpy as np
import pytest
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.errors import InputError
from seismo3d.terrain import Dem, write_dem
from seismo3d.viz.terrain3d import show_terrain, terrain_exaggeration, terrain_surface_mesh

runner = CliRunner()


def _dem():
    """A 60 x 80 DEM of 30 m pixels: a ramp rising 60 m to the east with a 20 m step along row 30, a nodata hole."""
    rows, cols = np.mgrid[0:60, 0:80].astype(float)
    z = 100.0 + 0.75 * cols + 20.0 * (rows > 30)
    z[5:9, 60:66] = np.nan
    affine = np.array([[30.0, 0.0, 500_000.0], [0.0, -30.0, 4_000_000.0], [0.0, 0.0, 1.0]])
    return Dem(elevation=z, affine=affine)


def _pixels(path):
    from matplotlib.image import imread

    return (imread(path)[..., :3] * 255).round()


def test_surface_in_metres_about_the_centre():
    dem = _dem()
    mesh = terrain_surface_mesh(dem, vertical_exaggeration=2.0)
    x, y, z = np.asarray(mesh.points).T
    assert x.min() == pytest.approx(-30.0 * 79 / 2) and x.max() == pytest.approx(30.0 * 79 / 2)
    assert y.min() == pytest.approx(-30.0 * 59 / 2) and y.max() == pytest.approx(30.0 * 59 / 2)
    assert z.max() == pytest.approx(2.0 * np.nanmax(dem.elevation))
    assert mesh.n_cells < 59 * 79  # the cells touching the hole are gone
    with pytest.raises(InputError, match="vertical_exaggeration"):
        terrain_surface_mesh(dem, vertical_exaggeration=0.0)


@pytest.mark.parametrize("relief, expected", [(5.0, 5.0), (15.0, 4.0), (40.0, 1.5), (400.0, 1.0)])
def test_exaggeration_shows_relief_without_inventing_mountains(relief, expected):
    """A gentle DEM gets at most 5x (151 m over 30 km used to get 27x), a rugged one 1x; in between the relief is
    drawn a 40th of the longer side (2370 m here: 15 m of relief gets 3.95x, 4x to two digits)."""
    rows, cols = np.mgrid[0:60, 0:80].astype(float)
    affine = np.array([[30.0, 0.0, 500_000.0], [0.0, -30.0, 4_000_000.0], [0.0, 0.0, 1.0]])
    dem = Dem(elevation=100.0 + relief * cols / 79, affine=affine)
    assert terrain_exaggeration(dem) == pytest.approx(expected, rel=0.05)


@pytest.mark.slow
def test_path_and_surface_colours(tmp_path):
    dem = _dem()
    cells = np.column_stack([np.full(70, 45), np.arange(5, 75)])
    shot = tmp_path / "terrain.png"
    show_terrain(dem, path=cells, screenshot=shot, window_size=(400, 300))
    img = _pixels(shot)
    assert (img.min(axis=-1) < 250).mean() > 0.2  # the surface fills a fifth of the picture at least
    black = img.max(axis=-1) < 40
    assert black.mean() > 0.002  # the path
    with pytest.raises(InputError, match="outside"):
        show_terrain(dem, path=[(100, 0)], screenshot=shot)


@pytest.mark.slow
@pytest.mark.parametrize("window_size", [(400, 300), (1024, 768)])
def test_the_colour_bar_has_its_own_slot(colour_bars, window_size, tmp_path):
    """The elevation bar upright at the right, inside the window, its title and tick labels drawn inside its
    rectangle (main's fixed 0.06 of the width was 24 pixels at 400 x 300, narrower than 'elevation')."""
    import seismo3d.viz.terrain3d as terrain3d

    dem = _dem()
    cells = np.column_stack([np.full(70, 45), np.arange(5, 75)])
    bars = colour_bars(terrain3d, lambda: show_terrain(dem, path=cells, screenshot=tmp_path / "dem.png",
                                                            window_size=window_size))
    ((title, ((x0, _, x1, _), *_)),) = bars.items()
    assert title == "elevation\n(m)" and x0 > 0.5 * window_size[0]


@pytest.mark.slow
def test_render_a_geotiff_with_its_lineaments_and_a_path(tmp_path):
    write_dem(tmp_path / "dem.tif", _dem())
    (tmp_path / "path.csv").write_text("row,col,x,y,z\n" + "".join(f"45,{c},0,0,0\n" for c in range(5, 75)))
    out = tmp_path / "dem.png"
    res = runner.invoke(app, ["render", str(tmp_path / "dem.tif"), "--lineaments", "--path", str(tmp_path / "path.csv"),
                              "-o", str(out), "--size", "400x300"])
    assert res.exit_code == 0, res.output
    assert "80 x 60 pixels of 30 x 30 m" in res.stdout
    img = _pixels(out)
    assert (img.max(axis=-1) < 40).mean() > 0.002
    (tmp_path / "bad.csv").write_text("a,b\n1,2\n")
    res = runner.invoke(app, ["render", str(tmp_path / "dem.tif"), "--path", str(tmp_path / "bad.csv"), "-o",
                              str(tmp_path / "bad.png")])
    assert res.exit_code == 2 and "seismo3d plan" in res.stderr
