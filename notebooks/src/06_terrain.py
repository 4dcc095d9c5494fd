# %% [markdown]
# # 06 Terrain: registration, lineaments and a planned path
#
# Three jobs on real terrain data, all fetched by origin (hash-checked) or read from `SEISMO3D_DATA_DIR`:
#
# 1. **Registration** of two airborne LiDAR strips (Autzen Stadium, Oregon; coordinates in feet) with no initial
#    guess: the fused ICP starts from HOG-pyramid matches between the strips' slope-shaded height grids. The source
#    strip is turned by 15 degrees about an axis 3 degrees off the vertical and moved 50 ft, so the truth is known.
# 2. **Lineaments** of a real DEM (HydroSHEDS, near Dallas-Fort Worth, 3 arc-second pixels): straight terrain
#    edges found in the residual relief, linked, with their strikes in a rose diagram.
# 3. **A planned path** over the same DEM: the shortest 8-connected path (A*) through the cells whose slope is at
#    most 1.5 degrees.
#
# The same on the command line: `seismo3d register`, `seismo3d lineaments`, `seismo3d plan` and `seismo3d render
# DEM.tif --lineaments --path path.csv`. `python benchmarks/terrain.py` runs more pairs, generated DEMs with known
# scarps and replanning.

# %%
%matplotlib inline

import numpy as np
from IPython.display import Image

from seismo3d.data import fetch
from seismo3d.data.terrain import cut_scan_pair
from seismo3d.terrain import (
    LidarScan, astar, extract_lineaments, read_dem, read_las, register_terrain, rose_histogram, slope_deg,
    transform_errors,
)
from seismo3d.viz import plot_rose, show_point_clouds
from seismo3d.viz.terrain3d import show_terrain

# %% [markdown]
# ## 1. Two LiDAR strips registered without an initial guess

# %%
autzen = read_las(fetch("terrain/autzen_trim.laz"))
pair = cut_scan_pair(autzen.points, angle_deg=15.0, tilt_deg=3.0, translation=(40.0, -30.0, 2.0), noise=0.1, seed=0)
source = LidarScan(pair.source, np.ones(len(pair.source), np.uint8), autzen.crs)
target = LidarScan(pair.target, np.ones(len(pair.target), np.uint8), autzen.crs)
print(f"Autzen tile: {len(autzen.points)} points; source strip {len(pair.source)}, target strip {len(pair.target)}")

result = register_terrain(source, target)
errors = transform_errors(result.transform, pair.transform, pair.source)
print(f"registered from the {result.start} start "
      f"({result.n_feature_inliers} hillshade matches kept by RANSAC)")
print(f"rotation error: {errors.rotation_deg:.3f} deg")
print(f"displacement error at the source's centroid: {errors.centroid:.2f} ft, largest over its points: "
      f"{errors.max_displacement:.2f} ft")

# %% [markdown]
# The two strips seen from above, every 10th point, before and after the registration; the target in blue.

# %%
centre = pair.target.mean(axis=0)
every = slice(None, None, 10)
for label, transform in (("source as given", None), ("source registered", result.transform)):
    moved = pair.source if transform is None else pair.source @ transform[:3, :3].T + transform[:3, 3]
    show_point_clouds([moved[every] - centre, pair.target[every] - centre], labels=[label, "target"],
                      camera="xy", window_size=(560, 420));  # seen from above, north up

# %% [markdown]
# ## 2. Lineaments of a real DEM

# %%
dem = read_dem(fetch("terrain/dem_hydrosheds_dfw.tif"))
dy, dx = dem.pixel_size_m
print(f"DEM: {dem.shape[1]} x {dem.shape[0]} pixels of {dx:.0f} x {dy:.0f} m, elevation "
      f"{np.nanmin(dem.elevation_m):.0f}-{np.nanmax(dem.elevation_m):.0f} m")
lineaments = extract_lineaments(dem)
print(f"lineaments: {len(lineaments)}, total length {lineaments.length_m.sum() / 1000:.1f} km")
for n in range(len(lineaments)):
    print(f"  strike {lineaments.azimuth_deg[n]:5.1f} deg, {lineaments.length_m[n] / 1000:4.1f} km long, contrast "
          f"{lineaments.contrast[n]:.1f}")
edges, weights = rose_histogram(lineaments)
print("strike histogram (10-degree bins, length-weighted, km): "
      + ", ".join(f"{a:.0f}: {w / 1000:.1f}" for a, w in zip(edges[:-1], weights) if w > 0))

# %%
import tempfile
from pathlib import Path

rose = plot_rose(lineaments.azimuth_deg, lineaments.length_m, Path(tempfile.mkdtemp()) / "rose.png",
                 title="lineament strikes, DFW DEM", dpi=70)
Image(filename=rose)

# %% [markdown]
# ## 3. A path over the DEM
# Traversable: slope at most 1.5 degrees (the steepest third of the cells is blocked). From the north-west corner
# of the traversable region to the south-east one.

# %%
free = (slope_deg(dem.elevation_m, dem.pixel_size_m) <= 1.5) & dem.valid
path = astar(free, (8, 0), (358, 366), spacing=dem.pixel_size_m)
straight = np.hypot(350 * dy, 366 * dx)
print(f"traversable cells: {free.mean():.0%}")
print(f"path: {len(path.cells)} cells, {path.length_m / 1000:.1f} km ({path.length_m / straight:.2f} x the straight "
      f"line), {path.n_expanded} cells expanded")

# %% [markdown]
# The DEM in 3D (elevation exaggerated; the caption gives the factor), seen from the south, with the lineaments
# (red) and the path (black, from the green start to the red goal).

# %%
show_terrain(dem, lineaments=lineaments, path=path, window_size=(900, 650));
