"""Terrain: LiDAR (LAS/LAZ) and DEM (GeoTIFF) inputs, terrain registration, hillshade, lineaments, path planning.

- :mod:`~seismo3d.terrain.georef`: CRSs from GeoKeys / WKT, the local metric frame fits run in;
- :mod:`~seismo3d.terrain.lidar`, :mod:`~seismo3d.terrain.dem`, :mod:`~seismo3d.terrain.inputs`: readers and writers;
- :mod:`~seismo3d.terrain.hillshade`: gradient, slope, aspect, hillshades;
- :mod:`~seismo3d.terrain.surface`: height grids from points, normals from grids;
- :mod:`~seismo3d.terrain.registration`: scan / DEM registration with the fused ICP.
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
from .inputs import TERRAIN_SUFFIXES, is_terrain_file, read_terrain
from .lidar import LAS_SUFFIXES, LidarScan, read_las, write_las
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
    "CoordinateReference", "DEM_SUFFIXES", "Dem", "FeaturePairs", "HeightGrid", "LAS_SUFFIXES", "LidarScan",
    "LocalFrame", "TERRAIN_SUFFIXES", "TerrainGradient", "TerrainRegistration", "TerrainRegistrationOptions",
    "TerrainSurface", "aspect_deg", "fill_holes", "grid_normals", "hillshade", "hillshades", "is_terrain_file",
    "match_hillshades", "metres_per_degree", "multidirectional_hillshade", "point_spacing", "rasterize_points",
    "read_dem", "read_las", "read_terrain", "register_terrain", "sample_grid", "slope_deg", "terrain_frame",
    "terrain_gradient", "terrain_surface", "write_dem", "write_las",
]
