"""Terrain: LiDAR (LAS/LAZ) and DEM (GeoTIFF) inputs, terrain registration, hillshade, lineaments, path planning.

- :mod:`~seismo3d.terrain.georef`: CRSs from GeoKeys / WKT, the local metric frame fits run in;
- :mod:`~seismo3d.terrain.lidar`, :mod:`~seismo3d.terrain.dem`, :mod:`~seismo3d.terrain.inputs`: readers and writers;
- :mod:`~seismo3d.terrain.hillshade`: gradient, slope, aspect, hillshades;
- :mod:`~seismo3d.terrain.surface`: height grids from points, normals from grids;
- :mod:`~seismo3d.terrain.registration`: scan / DEM registration with the fused ICP;
- :mod:`~seismo3d.terrain.lineaments`: lineaments (oriented gradients, Hough, linking, at several scales), rose
  histograms; their straight segments in :mod:`~seismo3d.terrain.lineament_segments`;
- :mod:`~seismo3d.terrain.water`: flat water (lakes and reservoirs flattened to one height);
- :mod:`~seismo3d.terrain.occupancy`, :mod:`~seismo3d.terrain.planning`: occupancy grids, A* and D* Lite;
- :mod:`~seismo3d.terrain.evaluation`: scores against ground truth.
"""

from .dem import DEM_SUFFIXES, Dem, read_dem, write_dem
from .georef import CoordinateReference, LocalFrame, metres_per_degree
from .hillshade import (
    TerrainGradient,
    aspect_deg,
    hillshade,
    hillshades,
    multidirectional_hillshade,
    slope_deg,
    terrain_gradient,
)
from .evaluation import LineamentEvaluation, TransformErrors, evaluate_lineaments, transform_errors
from .inputs import TERRAIN_SUFFIXES, is_terrain_file, read_terrain
from .lidar import LAS_SUFFIXES, LidarScan, read_las, write_las
from .lineaments import (
    LineamentOptions,
    Lineaments,
    detect_lineaments,
    extract_lineaments,
    flat_water,
    rose_histogram,
    write_lineaments_csv,
)
from .occupancy import OccupancyGrid, OccupancyOptions, occupancy_from_dem, occupancy_from_points, read_map_folder
from .planning import CostBounds, DStarLite, GridPath, astar, path_length
from .registration import (
    FeaturePairs,
    TerrainRegistration,
    TerrainRegistrationOptions,
    TerrainSurface,
    match_hillshades,
    register_terrain,
    terrain_frame,
    terrain_surface,
)
from .surface import HeightGrid, fill_holes, grid_normals, point_spacing, rasterize_points, sample_grid

__all__ = [
    "CoordinateReference", "CostBounds", "DEM_SUFFIXES", "DStarLite", "Dem", "FeaturePairs", "GridPath", "HeightGrid",
    "LAS_SUFFIXES", "LidarScan", "LineamentEvaluation", "LineamentOptions", "Lineaments", "LocalFrame",
    "OccupancyGrid", "OccupancyOptions", "TERRAIN_SUFFIXES", "TerrainGradient", "TerrainRegistration",
    "TerrainRegistrationOptions", "TerrainSurface", "TransformErrors", "aspect_deg", "astar", "detect_lineaments",
    "evaluate_lineaments", "extract_lineaments", "fill_holes", "flat_water", "grid_normals", "hillshade", "hillshades",
    "is_terrain_file", "match_hillshades", "metres_per_degree", "multidirectional_hillshade", "occupancy_from_dem",
    "occupancy_from_points", "path_length", "point_spacing", "rasterize_points", "read_dem", "read_las",
    "read_map_folder", "read_terrain", "register_terrain", "rose_histogram", "sample_grid", "slope_deg",
    "terrain_frame", "terrain_gradient", "terrain_surface", "transform_errors", "write_dem", "write_las",
    "write_lineaments_csv",
]
