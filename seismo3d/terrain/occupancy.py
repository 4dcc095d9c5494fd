"""Occupancy grids for path planning: from a DEM (traversable where the slope is gentle) and from a 3D map (a mesh or
point cloud, e.g. the ``mesh.ply`` of ``seismo3d map``: free where the floor was seen and nothing stands at the
robot's height).

A grid cell ``(row, col)`` keeps the coordinates of its centre (x, y, z), so a path can be written in the input's own
frame: a DEM's CRS and heights, or the map's world frame at floor level.
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.spatial.transform import Rotation

from .._validation import as_points, check_positive
from ..data import read_points
from ..errors import DataNotFoundError, InputError
from ..geometry import estimate_normals
from .dem import Dem
from .hillshade import slope_deg

__all__ = ["OccupancyGrid", "OccupancyOptions", "occupancy_from_dem", "occupancy_from_points", "estimate_up",
           "read_map_folder", "MapScene"]


@dataclass(frozen=True)
class OccupancyGrid:
    """Traversable cells and their coordinates.

    Attributes
    ----------
    free : (H, W) bool ndarray
        True where the robot may be.
    spacing : (float, float)
        (dy, dx): cell height (one row step) and width (one column step), metres.
    coordinates : (H, W, 3) float64 ndarray
        x, y, z of each cell centre in the input's frame (a DEM's CRS and vertical unit; a map's world frame, on
        the floor).
    known : (H, W) bool ndarray
        Cells the input says something about (valid DEM cells; map cells where the floor or an obstacle was seen).
    description : str
        What the grid was built from and with which limits (for reports).
    """

    free: np.ndarray
    spacing: tuple
    coordinates: np.ndarray
    known: np.ndarray
    description: str = ""

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols)."""
        return tuple(self.free.shape)


def occupancy_from_dem(dem: Dem, *, max_slope_deg: float) -> OccupancyGrid:
    """Traversable DEM cells: a valid cell whose slope ``arctan |grad z|`` (central differences, pixel sizes in
    metres) is at most ``max_slope_deg``.

    Parameters
    ----------
    dem : Dem
    max_slope_deg : float
        Steepest traversable slope, degrees in (0, 90).

    Returns
    -------
    OccupancyGrid
        ``spacing`` is :attr:`Dem.pixel_size_m`; ``coordinates`` the cells' CRS x, y and elevation.

    Raises
    ------
    InputError
        A slope limit outside (0, 90).
    """
    limit = float(max_slope_deg)
    if not 0.0 < limit < 90.0:
        raise InputError(f"max_slope_deg must be in (0, 90) degrees; got {max_slope_deg!r}")
    slope = slope_deg(dem.elevation_m, dem.metric_axes)
    free = np.isfinite(slope) & (slope <= limit)
    rows, cols = np.mgrid[0:dem.shape[0], 0:dem.shape[1]]
    x, y = dem.xy(rows, cols)
    coords = np.stack([x, y, dem.elevation], axis=-1)
    return OccupancyGrid(free, dem.pixel_size_m, coords, dem.valid,
                         f"DEM cells with slope <= {limit:g} deg ({np.count_nonzero(free)} of {free.size})")


@dataclass(frozen=True)
class OccupancyOptions:
    """How a 3D map becomes an occupancy grid (metres; the map's unit is taken as metres).

    Attributes
    ----------
    cell_size : float
        Side of a grid cell.
    robot_height : float
        Height of the robot: anything between ``step_height`` and this above the floor is an obstacle; what is
        higher (a table top, a ceiling) the robot passes under.
    step_height : float
        The highest bump the robot drives over: map points up to this above the floor are floor.
    robot_radius : float
        Obstacles are grown by this radius (the robot's centre keeps this far from them); 0 for a point robot.
    unknown_is_free : bool
        Treat cells where the map saw neither floor nor obstacle as traversable (default: not, the safe choice).
    floor_angle_deg : float
        Map points whose normal is within this angle of the up direction may be floor (for estimating the floor).
    """

    cell_size: float = 0.05
    robot_height: float = 0.5
    step_height: float = 0.05
    robot_radius: float = 0.0
    unknown_is_free: bool = False
    floor_angle_deg: float = 20.0

    def __post_init__(self):
        check_positive(self.cell_size, "cell_size")
        check_positive(self.robot_height, "robot_height")
        check_positive(self.step_height, "step_height")
        check_positive(self.robot_radius, "robot_radius", allow_zero=True)
        if self.step_height >= self.robot_height:
            raise InputError(f"step_height ({self.step_height}) must be below robot_height ({self.robot_height})")
        if not 0.0 < self.floor_angle_deg < 90.0:
            raise InputError(f"floor_angle_deg must be in (0, 90); got {self.floor_angle_deg!r}")


def estimate_up(points, *, hint=None, floor_angle_deg: float = 20.0) -> tuple[np.ndarray, float]:
    """The up direction and the floor's height along it, from the lowest large horizontal surface of a map.

    Points whose PCA normal lies within ``floor_angle_deg`` of ``hint`` are candidate floor; their heights along
    ``hint`` are histogrammed (2 cm bins), and the floor is the lowest bin holding at least 30 % of the fullest
    bin's count (tables and shelves are higher, stray points below the floor are few); the plane fitted (total least
    squares) to the points within 5 cm of it gives the refined up direction and the floor height.

    Parameters
    ----------
    points : (N, 3) array_like
        Map points, metres.
    hint : (3,) array_like, optional
        Rough up direction (e.g. minus the mean camera y axis of an RGB-D trajectory); default +z.
    floor_angle_deg : float

    Returns
    -------
    up : (3,) float64 ndarray
        Unit normal of the floor, on the side of ``hint``.
    floor : float
        ``up . p`` for points p on the floor, metres.

    Raises
    ------
    InputError
        Too few points, or none facing up (no floor seen).
    """
    pts = as_points(points, "points", dims=(3,), min_points=10)
    hint = np.array([0.0, 0.0, 1.0]) if hint is None else np.asarray(hint, dtype=np.float64).reshape(3)
    hint = hint / np.linalg.norm(hint)
    sample = pts if len(pts) <= 200_000 else pts[np.random.default_rng(0).choice(len(pts), 200_000, replace=False)]
    normals = estimate_normals(sample, k=12, orient="none")
    facing = np.abs(normals @ hint) >= np.cos(np.radians(floor_angle_deg))
    if np.count_nonzero(facing) < 10:
        raise InputError(f"no horizontal surface facing {np.round(hint, 3).tolist()} was found in the map: the floor "
                         "was not seen; give the up direction or a map with floor")
    heights = sample[facing] @ hint
    bins = np.arange(heights.min(), heights.max() + 0.04, 0.02)
    counts, edges = np.histogram(heights, bins=bins if len(bins) > 1 else 1)
    first = int(np.nonzero(counts >= 0.3 * counts.max())[0][0])
    level = 0.5 * (edges[first] + edges[first + 1])
    near = sample[facing][np.abs(heights - level) <= 0.05]
    centre = near.mean(axis=0)
    _, _, vt = np.linalg.svd(near - centre, full_matrices=False)
    up = vt[-1] * np.sign(vt[-1] @ hint)
    return up, float(up @ centre)


def _grid_axes(up):
    """Two unit vectors completing ``up`` to a right-handed frame (east-like, north-like)."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - (ref @ up) * up
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    return e1, e2


def occupancy_from_points(points, *, options: OccupancyOptions | None = None, up=None, floor=None,
                          hint=None) -> OccupancyGrid:
    """An occupancy grid at the robot's height from a 3D map (mesh vertices or a point cloud).

    Steps: (1) the up direction and floor height (given, or :func:`estimate_up`); (2) map points are projected on
    the floor plane into square cells; (3) a cell is an obstacle when a point stands between ``step_height`` and
    ``robot_height`` above the floor, floor when a point lies within ``step_height`` of it; (4) obstacles are grown by
    ``robot_radius``; free = floor seen and no obstacle (or unknown, with ``unknown_is_free``).

    Parameters
    ----------
    points : (N, 3) array_like
        Map points, metres (a mesh's vertices are dense enough when its edges are shorter than ``cell_size``).
    options : OccupancyOptions, optional
    up : (3,) array_like, optional
        Up direction (estimated from the floor when not given).
    floor : float, optional
        ``up . p`` on the floor (estimated when not given).
    hint : (3,) array_like, optional
        Rough up direction for the estimate (default +z).

    Returns
    -------
    OccupancyGrid
        Rows run along ``-e2``, columns along ``e1`` (two axes of the floor plane); ``coordinates`` are the cells'
        centres on the floor, in the map's frame.

    Raises
    ------
    InputError
        Too few points, no floor, or a grid over 50 million cells (raise ``cell_size``).

    References
    ----------
    Elfes, A. (1989). Using occupancy grids for mobile robot perception and navigation. Computer 22(6), 46-57.
    doi:10.1109/2.30720
    """
    opts = options or OccupancyOptions()
    pts = as_points(points, "points", dims=(3,), min_points=10)
    if up is None or floor is None:
        est_up, est_floor = estimate_up(pts, hint=hint if up is None else up, floor_angle_deg=opts.floor_angle_deg)
        up = est_up if up is None else up
        floor = est_floor if floor is None else floor
    up = np.asarray(up, dtype=np.float64).reshape(3)
    up = up / np.linalg.norm(up)
    e1, e2 = _grid_axes(up)
    height = pts @ up - float(floor)
    u, v = pts @ e1, pts @ e2
    cell = float(opts.cell_size)
    u0, v1 = u.min(), v.max()
    cols = np.floor((u - u0) / cell).astype(np.int64)
    rows = np.floor((v1 - v) / cell).astype(np.int64)
    shape = (int(rows.max()) + 1, int(cols.max()) + 1)
    if shape[0] * shape[1] > 50_000_000:
        raise InputError(f"a {cell:g} m grid over this map has {shape[0]} x {shape[1]} cells; raise the cell size")
    obstacle = np.zeros(shape, bool)
    floor_seen = np.zeros(shape, bool)
    band = (height > opts.step_height) & (height <= opts.robot_height)
    obstacle[rows[band], cols[band]] = True
    on_floor = np.abs(height) <= opts.step_height
    floor_seen[rows[on_floor], cols[on_floor]] = True
    if opts.robot_radius > 0 and obstacle.any():
        obstacle = ndimage.distance_transform_edt(~obstacle) * cell <= opts.robot_radius
    known = floor_seen | obstacle
    free = (floor_seen | (opts.unknown_is_free & ~known)) & ~obstacle
    rr, cc = np.mgrid[0:shape[0], 0:shape[1]]
    centre_u = u0 + (cc + 0.5) * cell
    centre_v = v1 - (rr + 0.5) * cell
    coords = centre_u[..., None] * e1 + centre_v[..., None] * e2 + float(floor) * up
    return OccupancyGrid(free, (cell, cell), coords, known,
                         f"map cells of {cell:g} m, obstacles between {opts.step_height:g} and {opts.robot_height:g} "
                         f"m above the floor, grown by {opts.robot_radius:g} m")


@dataclass(frozen=True)
class MapScene:
    """What :func:`read_map_folder` reads from the output folder of ``seismo3d map``.

    Attributes
    ----------
    points : (N, 3) float64 ndarray
        The mesh's vertices (``mesh.ply``), metres.
    up_hint : (3,) float64 ndarray or None
        Minus the mean camera y axis over ``trajectory.txt`` (cameras look along +z with +y down, so -y is roughly
        up), or None without a trajectory.
    """

    points: np.ndarray
    up_hint: np.ndarray | None


def read_map_folder(folder) -> MapScene:
    """Read the map of a ``seismo3d map`` output folder: ``mesh.ply`` (required) and ``trajectory.txt`` (optional,
    TUM format ``timestamp tx ty tz qx qy qz qw``, camera-to-world).

    Parameters
    ----------
    folder : str or os.PathLike

    Returns
    -------
    MapScene

    Raises
    ------
    DataNotFoundError
        If the folder or its ``mesh.ply`` is missing.
    InputError, DataIntegrityError
        A malformed mesh or trajectory.
    """

    folder = pathlib.Path(folder)
    mesh = folder / "mesh.ply"
    if not folder.is_dir():
        raise DataNotFoundError(f"{folder}: no such folder; give a DEM (.tif) or the output folder of seismo3d map")
    if not mesh.is_file():
        raise DataNotFoundError(f"{folder} has no mesh.ply; give the output folder of `seismo3d map` (it writes "
                                "mesh.ply) or a DEM")
    points = read_points(mesh, ndim=3)
    points = points[np.isfinite(points).all(axis=1)]
    hint = None
    trajectory = folder / "trajectory.txt"
    if trajectory.is_file():
        try:
            rows = np.loadtxt(trajectory, comments="#", ndmin=2)
        except ValueError as exc:
            raise InputError(f"{trajectory} is not a TUM trajectory (timestamp tx ty tz qx qy qz qw): {exc}") from exc
        if rows.shape[1] != 8:
            raise InputError(f"{trajectory} has {rows.shape[1]} columns; a TUM trajectory has 8")
        if len(rows):
            y_axes = Rotation.from_quat(rows[:, 4:8]).as_matrix()[:, :, 1]
            mean = -y_axes.mean(axis=0)
            if np.linalg.norm(mean) > 1e-6:
                hint = mean / np.linalg.norm(mean)
    return MapScene(points, hint)
