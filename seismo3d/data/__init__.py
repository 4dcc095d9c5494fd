"""Real data (registry, point-cloud and RGB-D loaders) and synthetic generators.

Real files are resolved by :func:`fetch` from the data directory ``$SEISMO3D_DATA_DIR`` or downloaded from their
public origin with pooch; see ``seismo3d/data/README.md`` for every file's purpose, origin and licence.
"""

from .pointclouds import BunnyPair, load_bunny, read_points, write_points
from .registry import REGISTRY, DataFile, data_dir, fetch, fetch_folder, file_info, list_files
from .rgbd import CameraIntrinsics, RGBDFrame, load_7scenes_frame, load_single_frame, load_tum_pair
from .sections import (F3FaultSections, ParihakaTimeSlices, PenobscotSections, load_f3_fault_sections,
                       load_parihaka_timeslices, load_penobscot_sections)
from .synthetic import SyntheticCube, synthetic_cube
from .volume_pairs import GridPair, random_grid_pair, resampled_pair

__all__ = [
    "REGISTRY",
    "DataFile",
    "data_dir",
    "fetch",
    "fetch_folder",
    "file_info",
    "list_files",
    "BunnyPair",
    "read_points",
    "write_points",
    "load_bunny",
    "CameraIntrinsics",
    "RGBDFrame",
    "load_7scenes_frame",
    "load_tum_pair",
    "load_single_frame",
    "F3FaultSections",
    "PenobscotSections",
    "load_f3_fault_sections",
    "load_penobscot_sections",
    "ParihakaTimeSlices",
    "load_parihaka_timeslices",
    "SyntheticCube",
    "synthetic_cube",
    "resampled_pair",
    "GridPair",
    "random_grid_pair",
]
