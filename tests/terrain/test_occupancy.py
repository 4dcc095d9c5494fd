"""seismo3d.terrain.occupancy: DEM slope grids, and occupancy at robot height from a generated map mesh."""

import numpy as np
import pytest

from seismo3d.data.terrain import SyntheticRoom
from seismo3d.errors import DataNotFoundError, InputError
from seismo3d.terrain import OccupancyOptions, astar, occupancy_from_dem, occupancy_from_points, read_map_folder, \
    slope_deg
from seismo3d.terrain.occupancy import estimate_up

BOX, TABLE, FLOOR_Y = SyntheticRoom.box, SyntheticRoom.table, 0.3  # the map_folder fixture's room (tests/conftest.py)
room_obstacle = SyntheticRoom.obstacle


def test_dem_grid(dfw):
    grid = occupancy_from_dem(dfw, max_slope_deg=1.5)
    slope = slope_deg(dfw.elevation_m, dfw.metric_axes)
    np.testing.assert_array_equal(grid.free, slope <= 1.5)
    assert grid.spacing == dfw.pixel_size_m
    np.testing.assert_allclose(grid.coordinates[3, 4], [*dfw.xy(3, 4), dfw.elevation[3, 4]])
    with pytest.raises(InputError, match="max_slope_deg must be in"):
        occupancy_from_dem(dfw, max_slope_deg=95)


@pytest.fixture(scope="module")
def room(map_folder):
    scene = read_map_folder(map_folder)
    return scene, occupancy_from_points(scene.points, hint=scene.up_hint)


@pytest.mark.slow
def test_up_and_floor_from_the_map(room):
    scene, _ = room
    assert scene.up_hint @ [0, -1, 0] > 0.9  # minus the cameras' mean y axis
    up, floor = estimate_up(scene.points, hint=scene.up_hint)
    assert np.degrees(np.arccos(up @ [0, -1, 0])) < 0.5
    assert floor == pytest.approx(-FLOOR_Y, abs=0.02)  # up . p on the floor, p_y = FLOOR_Y (y points down)


def test_grid_matches_the_room(room):
    _, grid = room
    x, z = grid.coordinates[..., 0], grid.coordinates[..., 2]
    np.testing.assert_allclose(grid.coordinates[..., 1], FLOOR_Y, atol=0.02)
    truth = room_obstacle(x, z)
    inside = (x > 0.1) & (x < 2.9) & (z > 0.1) & (z < 1.9)
    assert not np.any(grid.free & truth)  # no free cell where something stands at robot height
    assert np.mean((~grid.free == truth)[inside]) > 0.95  # the rest: cells straddling an obstacle's edge
    under_table = (np.abs(x - np.mean(TABLE["x"])) < 0.15) & (np.abs(z - np.mean(TABLE["z"])) < 0.15)
    assert grid.free[under_table].all()  # the top is above the robot
    on_box = (np.abs(x - np.mean(BOX["x"])) < 0.1) & (np.abs(z - np.mean(BOX["z"])) < 0.5)
    assert not grid.free[on_box].any()


def test_path_around_the_box_and_under_the_table(room):
    _, grid = room
    x, z = grid.coordinates[..., 0], grid.coordinates[..., 2]
    start = np.unravel_index(np.argmin(np.hypot(x - 0.4, z - 1.0)), x.shape)
    goal = np.unravel_index(np.argmin(np.hypot(x - 2.6, z - 1.0)), x.shape)
    path = astar(grid.free, start, goal, spacing=grid.spacing)
    px, pz = x[tuple(path.cells.T)], z[tuple(path.cells.T)]
    crossing = (px >= BOX["x"][0]) & (px <= BOX["x"][1])
    assert np.all(pz[crossing] > BOX["z"][1])  # around the box's end, the only way
    truth_free = ~room_obstacle(x, z) & (x > 0.05) & (x < 2.95) & (z > 0.05) & (z < 1.95)
    best = astar(truth_free, start, goal, spacing=grid.spacing).length_m
    assert best <= path.length_m <= 1.05 * best


@pytest.mark.slow
def test_robot_radius_and_errors(room, tmp_path):
    scene, _ = room
    grid = occupancy_from_points(scene.points, hint=scene.up_hint, options=OccupancyOptions(robot_radius=0.2))
    x, z = grid.coordinates[..., 0], grid.coordinates[..., 2]
    near_box = (x > BOX["x"][0] - 0.15) & (x < BOX["x"][1] + 0.15) & (z > BOX["z"][0]) & (z < BOX["z"][1])
    assert not grid.free[near_box].any()
    with pytest.raises(DataNotFoundError, match="no mesh.ply"):
        read_map_folder(tmp_path)
    with pytest.raises(InputError, match="step_height"):
        OccupancyOptions(step_height=0.6, robot_height=0.5)
    flat_wall = np.column_stack([np.zeros(100), np.repeat(np.arange(10.0), 10), np.tile(np.arange(10.0), 10)])
    with pytest.raises(InputError, match="floor was not seen"):
        estimate_up(flat_wall)
