"""seismo3d.jobs.plan: occupancy from a DEM file or a map folder, path.csv written atomically."""

import csv

import numpy as np
import pytest

from seismo3d.errors import InputError, PlanningError
from seismo3d.jobs.plan import load_occupancy, run_plan_job
from seismo3d.terrain import Dem, OccupancyOptions, write_dem
from seismo3d.terrain.georef import CoordinateReference

METRES = CoordinateReference("projected", None, "", "metre", 1.0, "metre", 1.0)


@pytest.fixture
def ridge_dem(tmp_path):
    """A 40 x 40 DEM of 10 m cells with a steep wall 5 cells wide across it, open at its northern end.

    (A wall one cell wide would have a flat top by central differences, z[c + 1] - z[c - 1] = 0: the issue's
    definition of slope.)"""
    z = np.zeros((40, 40))
    z[5:, 18:23] = 50.0
    affine = np.array([[10.0, 0.0, 1000.0], [0.0, -10.0, 5000.0], [0, 0, 1.0]])
    return write_dem(tmp_path / "wall.tif", Dem(z, affine, METRES))


def test_path_goes_round_the_wall(ridge_dem, tmp_path):
    result = run_plan_job(ridge_dem, (35, 5), (35, 35), tmp_path / "p.csv", max_slope_deg=10.0)
    with open(result.output, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert min(int(r["row"]) for r in rows) <= 4  # round the wall's northern end
    assert float(rows[0]["x"]) == pytest.approx(1000.0 + 5 * 10.0)  # the centre of column 5 (Dem.affine)
    assert result.path.length_m > 300.0 and result.seconds < 1.0


def test_unreachable_goal_writes_nothing(ridge_dem, tmp_path):
    grid = load_occupancy(ridge_dem, max_slope_deg=10.0)
    walled = grid.free.copy()
    assert not walled[5:, 17:19].any() and not walled[5:, 22:24].any()  # the wall's steep flanks
    with pytest.raises(PlanningError, match="no path"):  # closing the gap north of the wall cuts the grid in two
        import seismo3d.terrain.planning as planning

        closed = walled.copy()
        closed[:, 17:19] = False
        planning.astar(closed, (35, 5), (35, 35), spacing=grid.spacing)
    assert not (tmp_path / "p.csv").exists()


def test_map_folder_and_other_inputs(map_folder, tmp_path):
    grid = load_occupancy(map_folder, options=OccupancyOptions(cell_size=0.1))
    assert grid.spacing == (0.1, 0.1) and grid.free.any()
    with pytest.raises(InputError, match="plan on a GeoTIFF DEM"):
        load_occupancy(tmp_path / "x.ply")
