"""Shared terrain fixtures: the real LiDAR tile and DEM (skipped without the data directory) and a generated map
folder (a marching-cubes mesh of a room with a box and a table, and a camera trajectory)."""

import numpy as np
import pytest


@pytest.fixture(scope="session")
def autzen(data_dir):
    """The real Autzen LiDAR tile (110,000 points, feet)."""
    from seismo3d.data import fetch
    from seismo3d.terrain import read_las

    return read_las(fetch("terrain/autzen_trim.laz"))


@pytest.fixture(scope="session")
def dfw(data_dir):
    """The real HydroSHEDS DEM near Dallas-Fort Worth (359 x 367, 3 arc-seconds, EPSG:4326)."""
    from seismo3d.data import fetch
    from seismo3d.terrain import read_dem

    return read_dem(fetch("terrain/dem_hydrosheds_dfw.tif"))


# The generated room, in a camera-like world frame: x right, y DOWN, z forward, floor at y = FLOOR_Y.
FLOOR_Y = 0.3
ROOM = dict(x=(0.0, 3.0), z=(0.0, 2.0))
BOX = dict(x=(1.0, 1.3), z=(0.2, 1.6), height=0.6)           # an obstacle the robot must go around
TABLE = dict(x=(1.8, 2.4), z=(0.6, 1.4), top=(0.72, 0.76), leg=0.05)  # the robot (0.5 m) passes under its top


def _solid(x, h, z):
    """Indicator of the room's solid parts at points (x, height above the floor, z)."""
    floor = h < 0
    walls = (x < ROOM["x"][0] + 0.05) | (x > ROOM["x"][1] - 0.05) | (z < ROOM["z"][0] + 0.05) | \
            (z > ROOM["z"][1] - 0.05)
    walls &= h < 1.0
    box = (x >= BOX["x"][0]) & (x <= BOX["x"][1]) & (z >= BOX["z"][0]) & (z <= BOX["z"][1]) & (h <= BOX["height"])
    tx, tz, leg = TABLE["x"], TABLE["z"], TABLE["leg"]
    top = (x >= tx[0]) & (x <= tx[1]) & (z >= tz[0]) & (z <= tz[1]) & (h >= TABLE["top"][0]) & \
          (h <= TABLE["top"][1])
    legs = np.zeros_like(floor)
    for cx in (tx[0] + leg / 2, tx[1] - leg / 2):
        for cz in (tz[0] + leg / 2, tz[1] - leg / 2):
            legs |= (np.abs(x - cx) <= leg / 2) & (np.abs(z - cz) <= leg / 2) & (h <= TABLE["top"][1])
    return floor | walls | box | top | legs


def room_obstacle(x, z, *, robot_height=0.5):
    """Truth: is there something between 5 cm and robot_height above the floor at (x, z)?"""
    hs = np.linspace(0.06, robot_height, 12)
    return np.any([_solid(np.asarray(x), np.full(np.shape(x), h), np.asarray(z)) for h in hs], axis=0)


@pytest.fixture(scope="session")
def map_folder(tmp_path_factory):
    """A `seismo3d map`-like folder: mesh.ply (marching cubes of the room at 2 cm) and trajectory.txt."""
    from scipy.spatial.transform import Rotation
    from skimage.measure import marching_cubes

    folder = tmp_path_factory.mktemp("map")
    step = 0.02
    xs = np.arange(-0.1, 3.1 + step, step)
    hs = np.arange(-0.1, 1.1 + step, step)
    zs = np.arange(-0.1, 2.1 + step, step)
    X, H, Z = np.meshgrid(xs, hs, zs, indexing="ij")
    volume = _solid(X, H, Z).astype(np.float32)
    verts, faces, _, _ = marching_cubes(volume, 0.5, spacing=(step, step, step))
    verts += [xs[0], hs[0], zs[0]]
    world = np.column_stack([verts[:, 0], FLOOR_Y - verts[:, 1], verts[:, 2]])  # height up -> y down
    with open(folder / "mesh.ply", "w") as fh:
        fh.write(f"ply\nformat ascii 1.0\nelement vertex {len(world)}\nproperty float x\nproperty float y\n"
                 f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        np.savetxt(fh, world, fmt="%.5f")
        np.savetxt(fh, np.column_stack([np.full(len(faces), 3), faces]), fmt="%d")
    # cameras 1.2 m above the floor, looking along +z then +x, pitched 15 degrees down (y axis down)
    rows = []
    for k, (px, yaw) in enumerate([(0.4, 0.0), (1.0, 20.0), (2.0, 60.0), (2.6, 90.0)]):
        r = Rotation.from_euler("yx", [yaw, -15.0], degrees=True)
        q = r.as_quat()
        rows.append([k * 0.1, px, FLOOR_Y - 1.2, 1.0, *q])
    np.savetxt(folder / "trajectory.txt", rows, fmt="%.6f")
    return folder
