"""Geometry core: transforms, normals, neighbourhoods. Imports only numpy and scipy."""

from .neighbours import axis_bounds, bounding_diagonal, median_spacing, voxel_downsample
from .normals import backproject_depth, estimate_normals, normals_from_points_image, orient_normals
from .transforms import (
    MODELS,
    apply_transform,
    as_transform,
    compose,
    decompose_axis_scaled,
    invert,
    make_transform,
    nearest_rotation,
    perturb,
    rotation_about_axis,
    rotation_error_deg,
    rotation_matrix,
    split_transform,
    translation_error,
)

__all__ = [
    "MODELS", "apply_transform", "as_transform", "axis_bounds", "backproject_depth", "bounding_diagonal", "compose",
    "decompose_axis_scaled", "estimate_normals", "invert", "make_transform", "median_spacing", "nearest_rotation",
    "normals_from_points_image", "orient_normals", "perturb", "rotation_about_axis", "rotation_error_deg", "rotation_matrix",
    "split_transform", "translation_error", "voxel_downsample",
]
