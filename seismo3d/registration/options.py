"""ICPOptions: the distance schedule, stopping rule, robust kernel and correspondence strategy of icp and fused_icp.

Keyword arguments of :func:`~seismo3d.registration.icp` and :func:`~seismo3d.registration.fused_icp` with the same
names replace its fields (:mod:`seismo3d._options`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_choice, check_int, check_positive
from ..errors import InputError
from .correspondences import NearestNeighbourCorrespondences, as_correspondences
from .kernels import KERNELS

__all__ = ["ICPOptions", "as_schedule"]


def as_schedule(value, name: str) -> tuple:
    """A positive number or a non-empty sequence of them (coarse to fine) as a tuple of floats.

    Parameters
    ----------
    value : float or sequence of float
        Distances or voxel sizes, in the points' unit.
    name : str
        The argument's name, for messages.

    Returns
    -------
    tuple of float

    Raises
    ------
    InputError
        Empty, non-finite or non-positive values.
    """
    try:
        seq = np.atleast_1d(np.asarray(value, dtype=np.float64))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be a positive number or a non-empty sequence of them (coarse to fine)") from exc
    if seq.ndim != 1 or len(seq) == 0 or not np.all(np.isfinite(seq)) or np.any(seq <= 0):
        raise InputError(f"{name} must be a positive number or a non-empty sequence of them (coarse to fine)")
    return tuple(float(v) for v in seq)


@dataclass(frozen=True)
class ICPOptions:
    """How an ICP runs: the coarse-to-fine correspondence distances, the point pyramid, when a stage stops, the
    robust kernel and how correspondences are found. Shared by :func:`~seismo3d.registration.icp` and
    :func:`~seismo3d.registration.fused_icp`.

    Attributes
    ----------
    max_distance : float or tuple of float, optional
        Maximum correspondence distance per stage, coarse to fine, in the points' unit. None:
        :func:`~seismo3d.registration.default_distance_schedule` of the target (10 %, 3 %, 1 % of its bounding-box
        diagonal, floored at 3x the point spacing).
    voxel_size : float or tuple of float, optional
        Voxel-downsample source and target per stage (a point pyramid); one size for all stages or one per stage.
        None: the source is downsampled to voxels of 1/8 of each coarse stage's maximum distance and used whole in
        the last stage; the target is never downsampled.
    max_iterations : int
        Iterations per stage.
    tolerance : float
        Stop the last stage when the largest parameter update (radians, relative scale, and translation in units of
        the target's RMS radius) falls below this; a coarser stage stops at ``tolerance`` times the ratio of its
        maximum distance to the last stage's. The default, 3e-4 (0.017 degrees, and 0.3 mm on a scene of 1 m RMS
        radius), is 3-6 times stricter than small_gicp's stop (0.1 degrees, 1 mm): nearest-neighbour ICP converges
        linearly (each update about half the last on the 7-Scenes frames), and below this the updates change the
        answer by less than its error against the ground truth moves between peers (``python
        benchmarks/registration.py``: 1e-4 took 8 iterations from the identity on 7-Scenes 5 -> 0, 3e-4 takes 4,
        rotation error 0.167 / 0.170 deg, translation 5.16 / 5.12 mm; the bunny's answers are the same).
    kernel : {'huber', 'tukey', 'cauchy', 'none'}
        Robust kernel on the residuals.
    kernel_scale : float, optional
        The kernel's threshold in the points' unit (None: a third of the stage's maximum distance).
    degeneracy_threshold : float
        A final normal matrix whose smallest/largest eigenvalue ratio is below this is reported as degenerate (0:
        never).
    correspondences : NearestNeighbourCorrespondences or ProjectiveCorrespondences
        How each moved source point finds its target point (:mod:`seismo3d.registration.correspondences`): the
        nearest target point by a KD-tree (the default, any point set), or projective data association into an
        organised target (KinectFusion: the target point of the pixel the source point projects to; needs the whole
        organised target, so no target downsampling by ``voxel_size``). None is taken as the default.

    Raises
    ------
    InputError
        A value out of range or a ``correspondences`` that is not a strategy (checked when the options are made).

    Examples
    --------
    >>> opt = ICPOptions(max_distance=(3.0, 1.5), max_iterations=15)
    >>> opt.max_distance, opt.tolerance
    ((3.0, 1.5), 0.0003)
    """

    max_distance: float | tuple | None = None
    voxel_size: float | tuple | None = None
    max_iterations: int = 50
    tolerance: float = 3e-4
    kernel: str = "huber"
    kernel_scale: float | None = None
    degeneracy_threshold: float = 1e-3
    correspondences: object = NearestNeighbourCorrespondences()

    def __post_init__(self):
        if self.max_distance is not None:
            object.__setattr__(self, "max_distance", as_schedule(self.max_distance, "max_distance"))
        if self.voxel_size is not None:
            object.__setattr__(self, "voxel_size", as_schedule(self.voxel_size, "voxel_size"))
        object.__setattr__(self, "max_iterations", check_int(self.max_iterations, "max_iterations", minimum=1))
        check_positive(self.tolerance, "tolerance")
        check_choice(self.kernel, "kernel", KERNELS)
        if self.kernel_scale is not None:
            check_positive(self.kernel_scale, "kernel_scale")
        check_positive(self.degeneracy_threshold, "degeneracy_threshold", allow_zero=True)
        object.__setattr__(self, "correspondences", as_correspondences(self.correspondences))
