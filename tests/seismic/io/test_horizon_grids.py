"""Horizons as IRAP / ZMAP+ grids and x y z points through xtgeo, read back by xtgeo (and ZMAP+ by zmapio), on the
real F3 grid (rotated, 25 m bins, coordinates with a scalar of -10) and on a grid without coordinates."""

import importlib.util
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import InputError
from seismo3d.seismic.io.coordinates import read_survey_coordinates, survey_coordinates
from seismo3d.seismic.io.horizon_grids import horizon_surface, read_horizon_picks, write_horizon_grids

# skipped without xtgeo, found without importing it: every pytest-xdist worker collects this module, and importing
# xtgeo takes about a CPU second (the tests import it when they run)
pytestmark = [pytest.mark.skipif(importlib.util.find_spec("xtgeo") is None, reason="xtgeo is not installed"),
              pytest.mark.filterwarnings("ignore::DeprecationWarning", "ignore::FutureWarning",
                                         "ignore:The inplace keyword")]


@pytest.fixture(scope="module")
def f3(data_dir):
    from seismo3d.data import fetch

    coords = read_survey_coordinates(fetch("seismic/f3_crop.sgy"))
    il, xl = coords.inline[:, 0], coords.crossline[0]
    times = 100.0 + 0.5 * (il[:, None] - il[0]) + 0.25 * (xl[None, :] - xl[0]) + 0.001 * (il[:, None] * xl[None, :])
    times[3, 4] = np.nan  # not tracked there
    return coords, il, xl, times


def _nodes(picks, coords, il0, xl0):
    picks = picks.with_lines(coords)
    i, j = np.round(picks.inline - il0).astype(int), np.round(picks.crossline - xl0).astype(int)
    return picks, i, j


@pytest.mark.parametrize("fmt, xy_atol", [("irap_ascii", 0.1), ("irap_binary", 0.5), ("xyz", 1e-6)])
def test_f3_horizon_round_trip(f3, tmp_path, fmt, xy_atol):
    coords, il, xl, times = f3
    written = write_horizon_grids(tmp_path / "h", times, il, xl, coords, formats=(fmt,))
    picks, i, j = _nodes(read_horizon_picks(written[fmt]), coords, il[0], xl[0])
    assert picks.n_picks == np.isfinite(times).sum()  # the untracked node stays undefined
    assert np.abs(picks.inline - (il[0] + i)).max() < 0.02  # every node falls on its trace
    assert_allclose(picks.z, times[i, j], atol=1e-4)  # IRAP binary holds float32: 100 ms to 1e-5
    # X / Y of every node: the trace's header CDP X/Y, within the grid map's 0.1 m (IRAP binary's float32 origin:
    # 0.5 m at 6 million)
    assert_allclose(picks.x, coords.x[i, j], atol=xy_atol)
    assert_allclose(picks.y, coords.y[i, j], atol=xy_atol)


def test_f3_zmap_is_resampled_and_read_by_zmapio(f3, tmp_path):
    """ZMAP+ has no rotation: xtgeo writes the rotated F3 grid resampled onto an unrotated one. Its nodes read by
    xtgeo and by zmapio agree, and it samples the horizon back at the traces (a plane: bilinear is exact inside)."""
    import xtgeo
    from zmapio import ZMAPGrid

    coords, il, xl, times = f3
    path = write_horizon_grids(tmp_path / "h", times, il, xl, coords, formats=("zmap",))["zmap"]
    surf = xtgeo.surface_from_file(path, fformat="zmap_ascii")
    assert surf.rotation == 0.0
    z = ZMAPGrid(str(path))
    zv = np.where(z.z_values == z.null_value, np.nan, z.z_values)
    ours = np.ma.filled(surf.values, np.nan)
    # zmapio: z_values (n_columns, n_rows) with rows from the top (max Y); xtgeo: (ncol, nrow) from the bottom
    assert zv.shape == ours.shape
    assert_allclose(zv[:, ::-1], ours, atol=1e-4, equal_nan=True)
    surface = horizon_surface(times, il, xl, coords)
    inner = np.zeros_like(times, dtype=bool)
    inner[2:-2, 2:-2] = True
    inner &= np.isfinite(times)
    near_gap = np.zeros_like(inner)
    near_gap[1:6, 2:7] = True
    inner &= ~near_gap
    xs, ys = coords.x[inner], coords.y[inner]
    back = np.array([surf.get_value_from_xy((x, y)) for x, y in zip(xs, ys)], dtype=float)
    assert_allclose(back, times[inner], atol=0.02)
    assert surface.rotation != 0.0


def test_grid_without_coordinates_round_trips_exactly(tmp_path):
    il, xl = np.arange(1, 11), np.arange(1, 8)
    coords = survey_coordinates(*np.meshgrid(il.astype(float), xl.astype(float), indexing="ij"))
    times = np.add.outer(np.linspace(400, 420, 10), np.linspace(0, 6, 7))
    written = write_horizon_grids(tmp_path / "h", times, il, xl, coords)
    assert written["zmap"].read_text().startswith("! seismo3d: X, Y are inline and crossline numbers")
    for fmt, path in written.items():
        picks = read_horizon_picks(path).with_lines(coords)
        i, j = np.round(picks.inline - 1).astype(int), np.round(picks.crossline - 1).astype(int)
        assert picks.n_picks == times.size, fmt
        assert_allclose(picks.x, picks.inline, atol=1e-4)  # X = inline number, Y = crossline number
        assert_allclose(picks.z, times[i, j], atol=1e-4, err_msg=fmt)


def test_line_horizon_is_points_only_and_lines_rows_read(tmp_path):
    coords = survey_coordinates(np.arange(1000.0, 1010.0), np.full(10, 1155.0), 7e5 + 5.0 * np.arange(10),
                                4.8e6 + 10.0 * np.arange(10), resolution=0.1)
    with pytest.raises(InputError, match="write it as points"):
        write_horizon_grids(tmp_path / "h", np.ones(10), coords.inline, coords.crossline, coords)
    path = tmp_path / "h.txt"
    path.write_text("# inline xline time\n1000 1155 800\n1001 1155 804\n")
    picks = read_horizon_picks(path)
    assert picks.source_format == "lines" and picks.n_picks == 2 and np.isnan(picks.x).all()
    assert_allclose(picks.inline, [1000, 1001])


def test_skewed_grid_is_refused(f3):
    coords, il, xl, times = f3
    from dataclasses import replace

    gm = coords.grid_map
    skewed = replace(coords, grid_map=replace(gm, crossline_vector=gm.crossline_vector + 0.2 * gm.inline_vector))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InputError, match="not 90"):
            horizon_surface(times, il, xl, skewed)
