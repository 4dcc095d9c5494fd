"""seismo3d.jobs.plan: occupancy from a DEM file or a map folder, path.csv written atomically; `seismo3d plan` on the
real DEM and a map folder, one clear line for each bad cell."""

import csv
import re

import numpy as np
import pytest
from typer.testing import CliRunner

from seismo3d.cli import app
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
    assert result.path.length_m > 300.0 and result.seconds > 0.0  # speed: benchmarks/terrain.py, not a timed test


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


@pytest.mark.slow  # 1.8 s in the fast lane, whose budget is 60 s
def test_map_folder_and_other_inputs(map_folder, tmp_path):
    grid = load_occupancy(map_folder, options=OccupancyOptions(cell_size=0.1))
    assert grid.spacing == (0.1, 0.1) and grid.free.any()
    with pytest.raises(InputError, match="plan on a GeoTIFF DEM"):
        load_occupancy(tmp_path / "x.ply")


runner = CliRunner()


def _one_error_line(result):
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.exit_code == 2, result.output
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


def test_plan_command_on_the_dem(dfw, tmp_path):
    out = tmp_path / "path.csv"
    result = runner.invoke(app, ["plan", str(dfw.path), "--start", "8,0", "--goal", "358,366", "--max-slope", "1.5",
                                 "-o", str(out)])
    assert result.exit_code == 0, result.output
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["row", "col", "x", "y", "z"]
    assert (rows[0]["row"], rows[0]["col"], rows[-1]["row"], rows[-1]["col"]) == ("8", "0", "358", "366")
    x, y = dfw.xy(8, 0)
    assert float(rows[0]["x"]) == pytest.approx(x) and float(rows[0]["y"]) == pytest.approx(y)
    assert float(rows[0]["z"]) == dfw.elevation[8, 0]
    assert "66220.6 m" in result.stdout  # = MCP_Geometric's optimum (tests/terrain/test_planning.py)


@pytest.mark.parametrize("start, goal, message", [
    ("400,0", "358,366", "--start 400,0 is outside the grid of 359 rows x 367 columns"),
    ("0,366", "358,366", "--start 0,366 is on an obstacle (the cell is steeper than --max-slope 1.5 deg); the "
                         "nearest traversable cell is"),
    ("8,0", "0,366", "--goal 0,366 is on an obstacle"),
    ("0,0", "358,366", "no path from start (0, 0) to goal (358, 366)"),
    ("8", "358,366", "--start '8' must be ROW,COL"),
])
def test_plan_bad_cells(dfw, tmp_path, start, goal, message):
    result = runner.invoke(app, ["plan", str(dfw.path), "--start", start, "--goal", goal, "--max-slope", "1.5",
                                 "-o", str(tmp_path / "p.csv")])
    assert message in _one_error_line(result)
    assert not (tmp_path / "p.csv").exists()


def test_plan_names_the_nearest_free_cell(dfw, tmp_path):
    """A start on an obstacle: the message names the nearest traversable cell, which is free, no free cell is nearer,
    and planning from it works."""
    args = ["plan", str(dfw.path), "--goal", "358,366", "--max-slope", "1.5", "-o", str(tmp_path / "p.csv")]
    line = _one_error_line(runner.invoke(app, [*args, "--start", "0,366"]))
    rr, cc = (int(v) for v in re.search(r"pass --start (\d+),(\d+)", line).groups())
    free = load_occupancy(dfw.path, max_slope_deg=1.5).free
    assert free[rr, cc] and not free[0, 366]
    rows, cols = np.nonzero(free)
    assert np.hypot(rr - 0, cc - 366) == pytest.approx(np.hypot(rows - 0, cols - 366).min())
    again = runner.invoke(app, [*args, "--start", f"{rr},{cc}"])
    assert "on an obstacle" not in again.output


@pytest.mark.slow  # 1.5 s in the fast lane, whose budget is 60 s
def test_plan_command_on_a_map_folder(map_folder, tmp_path):
    out = tmp_path / "path.csv"
    result = runner.invoke(app, ["plan", str(map_folder), "--start", "20,8", "--goal", "20,56", "-o", str(out)])
    assert result.exit_code == 0, result.output
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    y = np.array([float(r["y"]) for r in rows])
    np.testing.assert_allclose(y, 0.3, atol=0.02)  # on the floor (y points down in the map's frame)
    missing = _one_error_line(runner.invoke(app, ["plan", str(tmp_path), "--start", "1,1", "--goal", "2,2", "-o",
                                                  str(tmp_path / "p.csv")]))
    assert "has no mesh.ply" in missing


def test_plan_slope_limit_in_flag_terms(dfw, tmp_path):
    result = runner.invoke(app, ["plan", str(dfw.path), "--start", "8,0", "--goal", "358,366", "--max-slope", "95",
                                 "-o", str(tmp_path / "p.csv")])
    assert "--max-slope must be in (0, 90) degrees" in _one_error_line(result)
