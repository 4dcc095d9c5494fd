"""The ``seismo3d plan`` job: an occupancy grid from a DEM or a map folder, the A* path between two cells, path.csv."""

from __future__ import annotations

import csv
import pathlib
from dataclasses import dataclass

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError
from ..terrain import DEM_SUFFIXES, read_dem
from ..terrain.occupancy import (
    OccupancyGrid,
    OccupancyOptions,
    occupancy_from_dem,
    occupancy_from_points,
    read_map_folder,
)
from ..terrain.planning import GridPath, astar
from .outputs import check_outputs, output_file
from .runinfo import RunRecord, run_json_output, run_json_path

__all__ = ["PlanResult", "load_occupancy", "parse_cell", "run_plan_job", "write_path_csv"]


@dataclass(frozen=True)
class PlanResult:
    """What :func:`run_plan_job` did.

    Attributes
    ----------
    path : GridPath
    grid : OccupancyGrid
    seconds : float
        Wall time of the search alone.
    output : pathlib.Path
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``read``, ``search``, ``write``).
    """

    path: GridPath
    grid: OccupancyGrid
    seconds: float
    output: pathlib.Path
    run_json: pathlib.Path | None = None
    stage_seconds: dict | None = None


def load_occupancy(grid, *, max_slope_deg: float = 15.0, options: OccupancyOptions | None = None) -> OccupancyGrid:
    """The occupancy grid of a DEM file (slope limit) or of a ``seismo3d map`` output folder (robot height).

    Parameters
    ----------
    grid : str or os.PathLike
        A GeoTIFF DEM or a folder holding ``mesh.ply`` (and ``trajectory.txt`` for the up direction).
    max_slope_deg : float
        Steepest traversable slope of a DEM, degrees.
    options : OccupancyOptions, optional
        For a map folder.

    Returns
    -------
    OccupancyGrid

    Raises
    ------
    InputError, DataNotFoundError
        An unsupported file, an all-nodata DEM, a folder without ``mesh.ply``.
    """
    grid = pathlib.Path(grid)
    if grid.is_dir():
        scene = read_map_folder(grid)
        return occupancy_from_points(scene.points, options=options, hint=scene.up_hint)
    if grid.suffix.lower() in DEM_SUFFIXES:
        return occupancy_from_dem(read_dem(grid), max_slope_deg=max_slope_deg)
    raise InputError(f"{grid.name}: plan on a GeoTIFF DEM ({', '.join(DEM_SUFFIXES)}) or on the output folder of "
                     "seismo3d map")


def _check_end(grid: OccupancyGrid, cell, name: str, why_blocked: str, loosen: str) -> tuple[int, int]:
    """``cell`` as (row, col) when it is inside the grid and traversable; InputError naming ``--{name}``, why the
    cell is blocked and the nearest traversable cell (or, with none, ``loosen``: what would free cells)."""
    r, c = (int(v) for v in cell)
    h, w = grid.shape
    if not (0 <= r < h and 0 <= c < w):
        raise InputError(f"--{name} {r},{c} is outside the grid of {h} rows x {w} columns (rows 0-{h - 1}, "
                         f"columns 0-{w - 1})")
    if not grid.free[r, c]:
        reason = "has no data" if not grid.known[r, c] else why_blocked
        free = np.argwhere(grid.free)
        if free.size == 0:
            raise InputError(f"--{name} {r},{c} is on an obstacle (the cell {reason}) and no cell of the grid is "
                             f"traversable; {loosen}")
        distance = np.hypot(*(free - (r, c)).T)
        rr, cc = (int(v) for v in free[np.argmin(distance)])
        raise InputError(f"--{name} {r},{c} is on an obstacle (the cell {reason}); the nearest traversable cell is "
                         f"{rr},{cc} ({distance.min():.1f} cells away): pass --{name} {rr},{cc}")
    return r, c


def write_path_csv(path, route: GridPath, grid: OccupancyGrid) -> pathlib.Path:
    """Write ``row,col,x,y,z`` per cell from start to goal, atomically.

    Parameters
    ----------
    path : str or os.PathLike
    route : GridPath
    grid : OccupancyGrid
        Gives each cell's x, y, z (:attr:`OccupancyGrid.coordinates`).

    Returns
    -------
    pathlib.Path
    """
    path = pathlib.Path(path)
    xyz = grid.coordinates[route.cells[:, 0], route.cells[:, 1]]
    with atomic_path(path) as tmp:
        with open(tmp, "w", newline="") as fh:
            out = csv.writer(fh)
            out.writerow(["row", "col", "x", "y", "z"])
            for (r, c), (x, y, z) in zip(route.cells, xyz):
                out.writerow([int(r), int(c), f"{x:.12g}", f"{y:.12g}", f"{z:.12g}"])
    return path


def run_plan_job(grid, start, goal, output, *, max_slope_deg: float = 15.0, options: OccupancyOptions | None = None,
                 corner_cutting: bool = True, overwrite: bool = False) -> PlanResult:
    """Plan the shortest 8-connected path between two cells of a DEM or map and write ``path.csv``.

    Parameters
    ----------
    grid : str or os.PathLike
        A GeoTIFF DEM (a cell is traversable when its slope is at most ``max_slope_deg``) or the output folder of
        ``seismo3d map`` (an occupancy grid at the robot's height from its ``mesh.ply``).
    start, goal : (int, int)
        (row, col) cells of the grid.
    output : str or os.PathLike
        The CSV: ``row, col, x, y, z`` per cell from start to goal (x, y in the DEM's CRS, z its elevation; for a
        map, the cell centre on the floor in the map's frame). Not the input, and not an existing file unless
        ``overwrite`` (see :mod:`seismo3d.jobs.outputs`; checked before the grid is read).
    max_slope_deg : float
        Slope limit of a DEM, degrees.
    options : OccupancyOptions, optional
        For a map folder.
    corner_cutting : bool
        Allow diagonal steps between two blocked cells.
    overwrite : bool
        Replace an existing ``output``.

    Returns
    -------
    PlanResult

    Raises
    ------
    InputError
        An output that is the input, exists (without ``overwrite``) or cannot be written; start or goal outside the
        grid or on an obstacle; bad inputs.
    PlanningError
        No path exists.
    """
    record = RunRecord("plan", locals())  # first: the arguments as called
    output = pathlib.Path(output)
    folder = pathlib.Path(grid)
    read = [folder / "mesh.ply", folder / "trajectory.txt"] if folder.is_dir() else []  # a map folder's inputs
    main = output_file(output, "path.csv")
    check_outputs([main, run_json_output(main)], [grid, *read], overwrite=overwrite)
    with record.stage("read"):
        occupancy = load_occupancy(grid, max_slope_deg=max_slope_deg, options=options)
    if pathlib.Path(grid).is_dir():
        blocked = "holds an obstacle at the robot's height, or no floor was seen there"
        loosen = "lower --robot-radius or raise --step-height"
    else:
        blocked = f"is steeper than --max-slope {max_slope_deg:g} deg"
        loosen = f"raise --max-slope (now {max_slope_deg:g} deg)"
    s = _check_end(occupancy, start, "start", blocked, loosen)
    g = _check_end(occupancy, goal, "goal", blocked, loosen)
    with record.stage("search"):
        route = astar(occupancy.free, s, g, spacing=occupancy.spacing, corner_cutting=corner_cutting)
    with record.stage("write"):
        write_path_csv(output, route, occupancy)
    inputs = {"grid": grid} if not read else {"mesh": read[0], "trajectory": read[1] if read[1].is_file() else None}
    run_json = record.write(run_json_path(main), inputs=inputs, outputs={"path": output},
                            results=dict(cells=len(route.cells), length_m=route.length_m,
                                         n_expanded=route.n_expanded, grid_shape=occupancy.shape))
    return PlanResult(route, occupancy, record.stage_seconds["search"], output, run_json, dict(record.stage_seconds))


def parse_cell(text: str, flag: str) -> tuple[int, int]:
    """``'ROW,COL'`` -> (row, col); the error names ``flag``."""
    try:
        r, c = (int(v) for v in text.split(","))
    except ValueError:
        raise InputError(f"{flag} {text!r} must be ROW,COL (two integers separated by a comma)") from None
    return r, c

