"""Terrain files by extension: LAS/LAZ point clouds and GeoTIFF DEMs behind one reader."""

from __future__ import annotations

import pathlib

from ..errors import InputError
from .dem import DEM_SUFFIXES, Dem, read_dem
from .lidar import LAS_SUFFIXES, LidarScan, read_las

__all__ = ["TERRAIN_SUFFIXES", "is_terrain_file", "read_terrain"]

TERRAIN_SUFFIXES = LAS_SUFFIXES + DEM_SUFFIXES


def is_terrain_file(path) -> bool:
    """True when ``path`` ends in .las, .laz, .tif or .tiff (case-insensitive)."""
    return pathlib.Path(path).suffix.lower() in TERRAIN_SUFFIXES


def read_terrain(path) -> LidarScan | Dem:
    """Read a LAS/LAZ file (:func:`~seismo3d.terrain.read_las`) or a GeoTIFF DEM (:func:`~seismo3d.terrain.read_dem`).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    LidarScan or Dem

    Raises
    ------
    InputError
        For another extension, an empty LAS or an all-nodata DEM.
    DataNotFoundError, DataIntegrityError
        As the readers.
    """
    suffix = pathlib.Path(path).suffix.lower()
    if suffix in LAS_SUFFIXES:
        return read_las(path)
    if suffix in DEM_SUFFIXES:
        return read_dem(path)
    raise InputError(f"{pathlib.Path(path).name}: terrain files are LAS/LAZ ({', '.join(LAS_SUFFIXES)}) or GeoTIFF "
                     f"DEMs ({', '.join(DEM_SUFFIXES)})")
