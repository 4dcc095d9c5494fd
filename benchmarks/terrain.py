"""Terrain benchmark: registration of LiDAR scans and DEMs beside Open3D, lineaments on generated DEMs with known
scarps and on the real DEM, planning and replanning on the real DEM beside scikit-image's MCP_Geometric and A* from
scratch, replanning on generated grids.

Run:  SEISMO3D_DATA_DIR=../shared/data python benchmarks/terrain.py [--pairs 5] [--dems 50] [--grids 8]
      [--only registration|lineaments|planning]

Table 1, registration (all from the identity: no initial guess):
- Autzen LiDAR tile (terrain/autzen_trim.laz, feet) cut into two strips overlapping by 30 % of its width; the source
  strip turned by up to 20 degrees about an axis 3 degrees off the vertical, moved 50 ft, with 0.1 ft Gaussian noise
  (seismo3d.data.terrain.cut_scan_pair, seeds 0..pairs-1). Errors: rotation (deg), displacement at the source's
  centroid and the largest displacement over its points (ft).
- The real DEM (terrain/dem_hydrosheds_dfw.tif) against 200 x 200 crops of itself turned by up to 20 degrees and
  shifted by up to 1.5 km (seismo3d.data.terrain.moved_grid). Error: the largest displacement over the crop's cells,
  in pixels.
- The moved Autzen strip against a 3 ft DEM (mean heights) gridded from the other strip.
Methods: seismo3d's fused ICP started from hillshade matches (`seismo3d register`'s default); seismo3d's
point-to-plane ICP without features; Open3D's point-to-plane ICP (``pip install open3d``, needs the system library
libusb-1.0-0) on the same recentred points and normals, with the engine's default distance schedule (10/3/1 % of the
target's diagonal), and with seismo3d's schedule from seismo3d's RANSAC start (the dense stage alone).

Table 2, lineaments: generated DEMs (seismo3d.data.terrain.synthetic_scarp_dem, seeds 200..200+dems-1, 8 scarps of
8-20 m on 20 m rolling relief, 256 x 256 pixels of 30 m; the defaults were chosen on seeds 0-9 and 100-119): scarps
found (a lineament within 5 deg of its strike, both ends within 3 px of its trace, covering half of the trace; and
half of the middle two thirds, where the tapered offset is at least half its maximum), lineaments, false ones, seconds
per DEM; then the real DEM.

Table 3, planning on the real DEM with --max-slope 1.5 between the corners of its traversable region (8, 0) and
(358, 366): A* (seismo3d) and MCP_Geometric (scikit-image) lengths and seconds (median of 5 warm runs); DStarLite's
first plan (with its default lookahead band and without it); replanning after a wall appears across the path (9
cells long and 3 thick, so that no diagonal step slips through; the first position at or after the stated fraction
of the first path that leaves a way round), with the robot at the start or part way along it: DStarLite as shipped
(the backward D* Lite search repaired, or A* from the robot guided by it), plain D* Lite (forward_search=False) and
A* from scratch from the robot's cell on the changed grid; every replanned path is checked equal in length to A*'s.

Table 4, the same replanning on generated grids (seismo3d.data.terrain.synthetic_occupancy: rolling fractal terrain,
the steepest 30 % blocked), walls at 10-90 % of the path (ahead of the robot): the median and worst ratios of the
replanning time to A*'s from scratch, how many cases are under 0.5, the ratio of expanded cells, and plain D* Lite's
ratios.

Timings were measured on a 2-core machine shared with other jobs: they are pessimistic.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time
import warnings

import numpy as np

from seismo3d.data import fetch
from seismo3d.data.terrain import cut_scan_pair, moved_grid, synthetic_scarp_dem
from seismo3d.errors import Seismo3dWarning
from seismo3d.geometry import estimate_normals
from seismo3d.registration import default_distance_schedule
from seismo3d.terrain import (
    Dem,
    DStarLite,
    LidarScan,
    TerrainRegistrationOptions,
    astar,
    detect_lineaments,
    evaluate_lineaments,
    extract_lineaments,
    occupancy_from_dem,
    rasterize_points,
    read_dem,
    read_las,
    register_terrain,
    transform_errors,
)
from seismo3d.terrain.georef import LocalFrame

try:
    import open3d as o3d
except (ImportError, OSError):  # OSError: libusb missing
    o3d = None


# ---- Table 1: registration ---------------------------------------------------------------------------------------

def _open3d_point_to_plane(source, target, normals, init, schedule):
    reg = o3d.pipelines.registration
    src = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.ascontiguousarray(source)))
    dst = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.ascontiguousarray(target)))
    dst.normals = o3d.utility.Vector3dVector(np.ascontiguousarray(normals))
    m = np.asarray(init, dtype=np.float64)
    for dmax in schedule:
        res = reg.registration_icp(src, dst, dmax, m, reg.TransformationEstimationPointToPlane(),
                                   reg.ICPConvergenceCriteria(max_iteration=50))
        m = np.asarray(res.transformation)
    return m


def _lidar_cases(autzen, n_pairs):
    rng = np.random.default_rng(2024)
    for seed in range(n_pairs):
        angle = rng.choice([-1, 1]) * rng.uniform(10.0, 20.0)
        direction = rng.normal(size=2)
        translation = np.r_[50.0 * direction / np.linalg.norm(direction), rng.uniform(-3, 3)]
        pair = cut_scan_pair(autzen.points, angle_deg=angle, tilt_deg=3.0, translation=translation, noise=0.1,
                             seed=seed)
        yield f"LiDAR {angle:+.0f} deg", pair


def _lidar_rows(autzen, n_pairs):
    rows = []
    for name, pair in _lidar_cases(autzen, n_pairs):
        source = LidarScan(pair.source, np.ones(len(pair.source), np.uint8), autzen.crs)
        target = LidarScan(pair.target, np.ones(len(pair.target), np.uint8), autzen.crs)

        def score(transform, seconds):
            e = transform_errors(transform, pair.transform, pair.source)
            return e.rotation_deg, e.centroid, e.max_displacement, seconds

        t0 = time.perf_counter()
        fused = register_terrain(source, target)
        rows.append((name, "seismo3d fused (hillshade HOG)", *score(fused.transform, time.perf_counter() - t0)))
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Seismo3dWarning)
            plain = register_terrain(source, target, options=TerrainRegistrationOptions(features=False))
        rows.append((name, "seismo3d point-to-plane", *score(plain.transform, time.perf_counter() - t0)))
        if o3d is not None:
            frame = fused.frame  # the same recentred points Open3D sees
            src_l, dst_l = frame.to_local(pair.source), frame.to_local(pair.target)
            t0 = time.perf_counter()
            normals = estimate_normals(dst_l, orient="none")
            m = _open3d_point_to_plane(src_l, dst_l, normals, np.eye(4), default_distance_schedule(dst_l))
            seconds = time.perf_counter() - t0
            rows.append((name, "Open3D point-to-plane", *score(frame.transform_to_file(m), seconds)))
            start = _ransac_start(source, target, fused)
            cell = fused.cell
            t0 = time.perf_counter()
            m = _open3d_point_to_plane(src_l, dst_l, normals, start, [c * cell for c in (8.0, 3.0, 1.5)])
            rows.append((name, "Open3D p2plane from our start", *score(frame.transform_to_file(m),
                                                                     time.perf_counter() - t0)))
    return rows


def _ransac_start(source, target, fused):
    """seismo3d's start alone (RANSAC on the lifted hillshade matches), in the fused result's local frame."""
    from seismo3d.registration import ransac
    from seismo3d.terrain import match_hillshades, terrain_surface

    a = terrain_surface(source, fused.frame, cell=fused.cell, with_normals=False)
    b = terrain_surface(target, fused.frame, cell=fused.cell, with_normals=False)
    pairs = match_hillshades(a.grid, b.grid)
    return ransac(pairs.source, pairs.target, model="rigid", threshold=3.0 * fused.cell).transform


def _dem_rows(dfw, n_pairs):
    rows = []
    rng = np.random.default_rng(7)
    dy, dx = dfw.pixel_size_m
    sy, sx = dfw.pixel_size
    for k in range(n_pairs):
        angle = rng.uniform(-20, 20)
        shift = rng.uniform(-1500, 1500, 2)
        r0, c0 = (int(v) for v in rng.integers(40, 120, 2))
        rows_, cols_ = slice(r0, r0 + 200), slice(c0, c0 + 200)
        mg = moved_grid(dfw.elevation, (dy, dx), crop=(rows_, cols_), angle_deg=angle, shift=shift)
        source = dataclasses.replace(dfw.crop(rows_, cols_), elevation=mg.elevation)
        cx, cy = source.centre_xy
        truth = LocalFrame(np.array([cx, cy, 0.0]), np.array([dx / sx, dy / sy, 1.0]), "m").transform_to_file(
            mg.transform)
        cells = np.c_[source.points(), np.ones(int(source.valid.sum()))]

        def pixels(transform):
            d = (cells @ transform.T - cells @ truth.T)[:, :2]
            return float(np.max(np.hypot(d[:, 0] / sx, d[:, 1] / sy)))

        name = f"DEM {angle:+.0f} deg"
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Seismo3dWarning)
            fused = register_terrain(source, dfw)
        rows.append((name, "seismo3d fused (hillshade HOG)", fused.rotation_deg - abs(angle), pixels(fused.transform),
                     np.nan, time.perf_counter() - t0))
        if o3d is not None:
            frame = fused.frame
            src_l, dst_l = frame.to_local(source.points()), frame.to_local(dfw.points())
            t0 = time.perf_counter()
            normals = estimate_normals(dst_l, orient="none")
            m = _open3d_point_to_plane(src_l, dst_l, normals, np.eye(4), default_distance_schedule(dst_l))
            rows.append((name, "Open3D point-to-plane", np.nan, pixels(frame.transform_to_file(m)), np.nan,
                         time.perf_counter() - t0))
    return rows


def _lidar_to_dem_row(autzen):
    pair = cut_scan_pair(autzen.points, angle_deg=-18.0, tilt_deg=3.0, translation=(-35.0, 30.0, 4.0), noise=0.1,
                         seed=5)
    g = rasterize_points(pair.target, 3.0, statistic="mean", fill=False)
    dem = Dem(g.elevation, np.array([[g.cell, 0, g.x0], [0, -g.cell, g.y0], [0, 0, 1.0]]), autzen.crs)
    t0 = time.perf_counter()
    result = register_terrain(LidarScan(pair.source, np.ones(len(pair.source), np.uint8), autzen.crs), dem)
    e = transform_errors(result.transform, pair.transform, pair.source)
    return "LiDAR -> 3 ft DEM", "seismo3d fused (hillshade HOG)", e.rotation_deg, e.centroid, e.max_displacement, \
        time.perf_counter() - t0


def registration_table(n_pairs):
    autzen = read_las(fetch("terrain/autzen_trim.laz"))
    dfw = read_dem(fetch("terrain/dem_hydrosheds_dfw.tif"))
    print("Table 1: registration from the identity (no initial guess); targets 0.2 deg / 0.5 ft (LiDAR), 0.5 pixel "
          "(DEM)")
    header = f"{'case':18s} {'method':32s} {'rot err deg':>11s} {'centroid':>9s} {'max disp':>9s} {'seconds':>8s}"
    print(header)
    print("-" * len(header))
    for name, method, rot, centroid, worst, seconds in _lidar_rows(autzen, n_pairs):
        print(f"{name:18s} {method:32s} {rot:11.4f} {centroid:9.3f} {worst:9.3f} {seconds:8.2f}   (ft)")
    print(f"{'':18s} (DEM rows: 'rot err' is the fitted minus the true angle, 'centroid' the largest error in pixels)")
    for name, method, rot, px, _, seconds in _dem_rows(dfw, n_pairs):
        rot_text = f"{rot:11.4f}" if np.isfinite(rot) else f"{'':11s}"
        print(f"{name:18s} {method:32s} {rot_text} {px:9.3f} {'':9s} {seconds:8.2f}   (pixels)")
    name, method, rot, centroid, worst, seconds = _lidar_to_dem_row(autzen)
    print(f"{name:18s} {method:32s} {rot:11.4f} {centroid:9.3f} {worst:9.3f} {seconds:8.2f}   (ft)")
    if o3d is None:
        print("(Open3D not installed: pip install 'seismo3d[bench]' and apt-get install libusb-1.0-0)")


# ---- Table 2: lineaments -----------------------------------------------------------------------------------------

def lineament_table(n_dems):
    print("\nTable 2: lineaments; target >= 90 % of the scarps found within 5 deg, few false lineaments")
    totals = np.zeros(5, int)
    seconds = []
    for seed in range(200, 200 + n_dems):
        truth = synthetic_scarp_dem(seed=seed)
        t0 = time.perf_counter()
        found = detect_lineaments(truth.elevation, (truth.pixel_size, truth.pixel_size))
        seconds.append(time.perf_counter() - t0)
        e = evaluate_lineaments(found, truth.scarps)
        totals += [e.n_scarps, e.n_found, e.n_found_visible, e.n_lineaments, e.n_false]
    n, full, visible, detected, false = totals
    print(f"{'input':34s} {'scarps':>7s} {'found':>12s} {'found (mid)':>12s} {'lineaments':>11s} {'false':>6s} "
          f"{'s/DEM':>6s}")
    print(f"{f'{n_dems} generated DEMs (seeds 200-{199 + n_dems})':34s} {n:7d} {full:5d} ({full / n:5.1%}) "
          f"{visible:4d} ({visible / n:5.1%}) {detected:11d} {false:6d} {np.median(seconds):6.3f}")
    dfw = read_dem(fetch("terrain/dem_hydrosheds_dfw.tif"))
    t0 = time.perf_counter()
    found = extract_lineaments(dfw)
    seconds = time.perf_counter() - t0
    print(f"{'dem_hydrosheds_dfw.tif (real)':34s} {'':>7s} {'':>12s} {'':>12s} {len(found):11d} {'':>6s} "
          f"{seconds:6.3f}   ({found.length_m.sum() / 1000:.1f} km)")


# ---- Tables 3 and 4: planning and replanning ----------------------------------------------------------------------

def _timed(fn, repeats=5):
    out, times = None, []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, float(np.median(times))


def _wall(path, index, half=4):
    """Cells of a wall across the path at ``path.cells[index]``: a line 2 * half + 1 cells long, thickened to 3 cells
    so that no diagonal step slips through it."""
    from scipy import ndimage

    (r, c), (r2, c2) = path.cells[index], path.cells[index + 1]
    normal = np.array([-(c2 - c), r2 - r], float) / np.hypot(r2 - r, c2 - c)
    t = np.linspace(-half, half, 8 * half + 1)
    line = np.unique(np.round(np.column_stack([r + t * normal[0], c + t * normal[1]])).astype(int), axis=0)
    lo = line.min(axis=0) - 1
    mask = np.zeros(tuple(line.max(axis=0) - lo + 2), bool)
    mask[tuple((line - lo).T)] = True
    return np.argwhere(ndimage.binary_dilation(mask, np.ones((3, 3), bool))) + lo


def _blocking_wall(free, spacing, path, index, here, goal):
    """The first wall at or after ``path.cells[index]`` that blocks the path but leaves a way round (narrow passages
    of the slope mask would otherwise cut the grid in two); None when there is none within 60 cells."""
    from seismo3d.errors import PlanningError

    for at in range(index, min(index + 60, len(path.cells) - 1)):
        wall = _wall(path, at)
        inside = (wall[:, 0] >= 0) & (wall[:, 0] < free.shape[0]) & (wall[:, 1] >= 0) & (wall[:, 1] < free.shape[1])
        wall = wall[inside]
        wall = wall[[tuple(w) not in (here, goal) for w in wall]]
        changed = free.copy()
        changed[wall[:, 0], wall[:, 1]] = False
        try:
            astar(changed, here, goal, spacing=spacing)
        except PlanningError:
            continue
        return wall, changed, at
    return None


@dataclasses.dataclass(frozen=True)
class Replan:
    """One replanning case: the robot at ``robot`` of the first path, a wall across it at ``wall`` (fractions)."""

    robot: float
    wall: float
    detour_m: float
    length_m: float
    seconds: float  # DStarLite (default: repair near the robot, guided search far from it): set_cells + plan
    search: str
    expanded: int
    dstar_seconds: float  # DStarLite(forward_search=False): plain D* Lite
    dstar_expanded: int
    astar_seconds: float  # A* from scratch from the robot's cell on the changed grid
    astar_expanded: int


def _replan(free, spacing, start, goal, first, robot_at, wall_at, repeats=5):
    """Time replanning (set_cells + plan on planners that planned once and moved) beside A* from scratch; each
    timing is the median of ``repeats`` runs, each replan on a fresh planner. None when no wall leaves a way round."""
    here = tuple(int(v) for v in first.cells[int(robot_at * (len(first.cells) - 1))])
    found = _blocking_wall(free, spacing, first, int(wall_at * (len(first.cells) - 1)), here, goal)
    if found is None:
        return None
    wall, changed, at = found
    scratch, t_astar = _timed(lambda: astar(changed, here, goal, spacing=spacing))
    before = astar(free, here, goal, spacing=spacing)
    runs = {}
    for forward in (True, False):
        times = []
        for _ in range(repeats):
            planner = DStarLite(free, start, goal, spacing=spacing, forward_search=forward)
            planner.plan()
            planner.move_to(here)
            planner.plan()
            t0 = time.perf_counter()
            planner.set_cells(wall, free=False)
            out = planner.plan()
            times.append(time.perf_counter() - t0)
        assert abs(out.length_m - scratch.length_m) <= 1e-9 * scratch.length_m, (out.length_m, scratch.length_m)
        runs[forward] = (out, float(np.median(times)))
    (hybrid, t_hybrid), (plain, t_plain) = runs[True], runs[False]
    return Replan(robot_at, at / (len(first.cells) - 1), scratch.length_m - before.length_m, scratch.length_m,
                  t_hybrid, hybrid.planner, hybrid.n_expanded, t_plain, plain.n_expanded, t_astar,
                  scratch.n_expanded)


def _load():
    one, five, _ = os.getloadavg()
    return f"load average {one:.1f} (1 min), {five:.1f} (5 min) on {os.cpu_count()} cores"


def planning_table():
    from skimage.graph import MCP_Geometric

    dfw = read_dem(fetch("terrain/dem_hydrosheds_dfw.tif"))
    grid = occupancy_from_dem(dfw, max_slope_deg=1.5)
    start, goal = (8, 0), (358, 366)
    print("\nTable 3: planning on the real DEM, --max-slope 1.5, (8, 0) -> (358, 366); targets <= 1.03 x MCP's "
          f"length in <= 1 s, replanning < half of planning from scratch ({_load()})")
    astar(grid.free, start, goal, spacing=grid.spacing)  # compile / load the numba kernels once
    path, t_astar = _timed(lambda: astar(grid.free, start, goal, spacing=grid.spacing))
    costs = np.where(grid.free, 1.0, np.inf)
    (cum, _), t_mcp = _timed(lambda: MCP_Geometric(costs, sampling=grid.spacing).find_costs([start], [goal]))
    optimum = float(cum[goal])
    warm = DStarLite(grid.free, start, goal, spacing=grid.spacing)  # load the numba kernels once
    warm_path = warm.plan()
    warm.set_cells(_wall(warm_path, 100), free=False)
    warm.plan()
    warm.set_cells(_wall(warm_path, 500), free=False)
    warm.plan()
    first, t_dstar = _timed(lambda: DStarLite(grid.free, start, goal, spacing=grid.spacing).plan())
    plain, t_plain = _timed(lambda: DStarLite(grid.free, start, goal, spacing=grid.spacing, lookahead=0.0).plan())
    print(f"{'planner':40s} {'length m':>10s} {'x MCP':>7s} {'expanded':>9s} {'seconds':>8s}")
    print(f"{'seismo3d A*':40s} {path.length_m:10.1f} {path.length_m / optimum:7.4f} {path.n_expanded:9d} "
          f"{t_astar:8.4f}")
    print(f"{'scikit-image MCP_Geometric':40s} {optimum:10.1f} {1.0:7.4f} {'':>9s} {t_mcp:8.4f}")
    print(f"{'seismo3d D* Lite, first plan':40s} {first.length_m:10.1f} {first.length_m / optimum:7.4f} "
          f"{first.n_expanded:9d} {t_dstar:8.4f}")
    print(f"{'seismo3d D* Lite, first plan, lookahead 0':40s} {plain.length_m:10.1f} {plain.length_m / optimum:7.4f} "
          f"{plain.n_expanded:9d} {t_plain:8.4f}")
    print("\nReplanning after a wall (9 x 3 cells) appears across the path, with the robot at the start or part way "
          "along it.\n'replan': DStarLite as shipped (repairs its backward D* Lite search when the repair is cheap, "
          "else A* from the robot\nguided by it); 'D* Lite': DStarLite(forward_search=False); 'A*': from scratch from "
          "the robot's cell on the changed grid.\nSeconds: set_cells + plan, median of 5 fresh planners (A*: of 5 "
          "runs); 'detour': the new path's length minus the old one's.")
    header = (f"{'robot / wall':>14s} {'detour m':>9s} {'replan s':>9s} {'search':>12s} {'expanded':>8s} "
              f"{'D* Lite s':>9s} {'expanded':>8s} {'A* s':>7s} {'expanded':>8s} {'replan/A*':>9s} "
              f"{'D*L/A*':>7s} {'length m':>9s}")
    print(header)
    print("-" * len(header))
    cases = ((0.0, 0.05), (0.3, 0.35), (0.6, 0.65), (0.0, 0.5), (0.0, 0.9),  # the rows of the first version
             (0.0, 0.2), (0.0, 0.35), (0.0, 0.6), (0.0, 0.7), (0.0, 0.8), (0.0, 0.95),
             (0.3, 0.5), (0.3, 0.6), (0.3, 0.7), (0.3, 0.9), (0.6, 0.8), (0.6, 0.95))
    for robot_at, wall_at in cases:
        r = _replan(grid.free, grid.spacing, start, goal, first, robot_at, wall_at)
        print(f"{f'{r.robot:.0%} / {r.wall:.0%}':>14s} {r.detour_m:9.1f} {r.seconds:9.4f} {r.search:>12s} "
              f"{r.expanded:8d} {r.dstar_seconds:9.4f} {r.dstar_expanded:8d} {r.astar_seconds:7.4f} "
              f"{r.astar_expanded:8d} {r.seconds / r.astar_seconds:9.2f} {r.dstar_seconds / r.astar_seconds:7.2f} "
              f"{r.length_m:9.1f}")
    print(f"({_load()})")


def generated_replanning_table(n_grids):
    from seismo3d.data.terrain import synthetic_occupancy

    print(f"\nTable 4: replanning on {n_grids} generated grids (seismo3d.data.terrain.synthetic_occupancy, seeds "
          f"0-{n_grids - 1}: 400 x 400 cells of 30 x 25 m, 70 % free, between the corners of the largest free "
          f"region), as in Table 3; ratios to A* from scratch ({_load()})")
    header = (f"{'robot / wall':>14s} {'cases':>5s} {'replan/A* median':>16s} {'worst':>6s} {'< 0.5':>6s} "
              f"{'expanded/A* median':>18s} {'worst':>6s} {'guided':>6s} {'D*L/A* median':>13s} {'worst':>6s} "
              f"{'detour m max':>12s}")
    print(header)
    print("-" * len(header))
    grids = [synthetic_occupancy(seed=seed) for seed in range(n_grids)]
    firsts = [DStarLite(t.free, t.start, t.goal, spacing=t.spacing).plan() for t in grids]
    for robot_at, walls_at in ((0.0, (0.1, 0.3, 0.5, 0.7, 0.9)), (0.3, (0.35, 0.5, 0.7, 0.9))):
        for wall_at in walls_at:
            rows = [r for t, first in zip(grids, firsts)
                    if (r := _replan(t.free, t.spacing, t.start, t.goal, first, robot_at, wall_at)) is not None]
            ratio = np.array([r.seconds / r.astar_seconds for r in rows])
            expanded = np.array([r.expanded / r.astar_expanded for r in rows])
            plain = np.array([r.dstar_seconds / r.astar_seconds for r in rows])
            guided = sum(r.search == "guided_astar" for r in rows)
            print(f"{f'{robot_at:.0%} / {wall_at:.0%}':>14s} {len(rows):5d} {np.median(ratio):16.2f} "
                  f"{ratio.max():6.2f} {int(np.sum(ratio < 0.5)):6d} {np.median(expanded):18.3f} "
                  f"{expanded.max():6.3f} {guided:6d} {np.median(plain):13.2f} {plain.max():6.2f} "
                  f"{max(r.detour_m for r in rows):12.1f}")
    print(f"({_load()})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=5, help="LiDAR and DEM pairs in Table 1")
    parser.add_argument("--dems", type=int, default=50, help="generated DEMs in Table 2")
    parser.add_argument("--grids", type=int, default=8, help="generated occupancy grids in Table 4")
    parser.add_argument("--only", choices=["registration", "lineaments", "planning"], help="print one part only")
    args = parser.parse_args()
    if args.only in (None, "registration"):
        registration_table(args.pairs)
    if args.only in (None, "lineaments"):
        lineament_table(args.dems)
    if args.only in (None, "planning"):
        planning_table()
        generated_replanning_table(args.grids)


if __name__ == "__main__":
    main()
