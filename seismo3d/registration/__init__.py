"""Registration engine: closed-form fits, ICP family, RANSAC and the fused ICP of method.md section 1."""

from .closed_form import fit_affine, fit_axis_scaled, fit_rigid, fit_similarity, fit_transform, min_points
from .correspondences import NearestNeighbourCorrespondences, ProjectiveCorrespondences
from .fused import fused_icp
from .icp import default_distance_schedule, fast_icp, icp
from .kernels import KERNELS, robust_weights
from .options import ICPOptions
from .ransac import ransac
from .result import RegistrationResult

__all__ = [
    "ICPOptions", "KERNELS", "NearestNeighbourCorrespondences", "ProjectiveCorrespondences", "RegistrationResult",
    "default_distance_schedule", "fast_icp", "fit_affine", "fit_axis_scaled", "fit_rigid", "fit_similarity",
    "fit_transform", "fused_icp", "icp", "min_points", "ransac", "robust_weights",
]
