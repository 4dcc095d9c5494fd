"""Trajectory errors as the TUM RGB-D benchmark defines them, computed by evo (Grupp 2017).

* ATE (absolute trajectory error): estimated and reference poses are associated by timestamp, the estimate is
  aligned to the reference by the least-squares rigid transform of the positions (Horn 1987 / Umeyama 1991, no scale
  for RGB-D), and the error is the distance between the aligned positions (Sturm et al. 2012, eq. 2-3).
* RPE (relative pose error): over every pair of associated poses ``delta`` frames apart, the error of the relative
  motion ``(Q_i^-1 Q_{i+delta})^-1 (P_i^-1 P_{i+delta})``, split into its translation (metres) and rotation angle
  (degrees) (Sturm et al. 2012, eq. 1; every pair, as TUM's evaluate_rpe with a fixed frame step).

References
----------
Sturm, J., Engelhard, N., Endres, F., Burgard, W., Cremers, D. (2012). A benchmark for the evaluation of RGB-D SLAM
systems. IROS, 573-580. doi:10.1109/IROS.2012.6385773
Grupp, M. (2017). evo: Python package for the evaluation of odometry and SLAM. https://github.com/MichaelGrupp/evo
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from .._atomic import atomic_path
from .._validation import check_positive
from ..errors import InputError

__all__ = ["TrajectoryError", "absolute_trajectory_error", "reference_in_map_frame", "relative_pose_error",
           "write_tum_trajectory"]


@dataclass(frozen=True)
class TrajectoryError:
    """Statistics of a per-pose error.

    Attributes
    ----------
    rmse, mean, median, max : float
        Of ``errors``.
    errors : (K,) float64 ndarray
        Per associated pose (ATE) or pair (RPE); metres, or degrees for rotations.
    n : int
        Number of associated poses or pairs.
    """

    rmse: float
    mean: float
    median: float
    max: float
    errors: np.ndarray
    n: int

    @classmethod
    def of(cls, errors) -> TrajectoryError:
        """Summarise an array of errors."""
        e = np.asarray(errors, dtype=np.float64).reshape(-1)
        if len(e) == 0:
            nan = float("nan")
            return cls(nan, nan, nan, nan, e, 0)
        return cls(float(np.sqrt(np.mean(e**2))), float(e.mean()), float(np.median(e)), float(e.max()), e, len(e))


def _trajectory(timestamps, poses, name):
    from evo.core.trajectory import PoseTrajectory3D

    t = np.asarray(timestamps, dtype=np.float64).reshape(-1)
    p = np.asarray(poses, dtype=np.float64)
    if p.ndim != 3 or p.shape[1:] != (4, 4) or len(p) != len(t):
        raise InputError(f"{name}: poses must be (N, 4, 4) with one timestamp each; got {p.shape} and {t.shape}")
    if not np.all(np.isfinite(p)):
        raise InputError(f"{name}: poses contain NaN or inf; drop those frames first")
    return PoseTrajectory3D(poses_se3=list(p), timestamps=t)


def _associate(est_t, est_p, ref_t, ref_p, max_time_difference):
    from evo.core import sync

    check_positive(max_time_difference, "max_time_difference")
    ref = _trajectory(ref_t, ref_p, "reference")
    est = _trajectory(est_t, est_p, "estimate")
    try:
        ref, est = sync.associate_trajectories(ref, est, max_diff=max_time_difference)
    except sync.SyncException as exc:
        raise InputError(f"no estimated pose is within {max_time_difference} s of a reference pose ({exc}); check "
                         "that both trajectories use the same clock") from exc
    return ref, est


def absolute_trajectory_error(timestamps, poses, reference_timestamps, reference_poses, *,
                              max_time_difference: float = 0.02) -> TrajectoryError:
    """ATE of an estimated trajectory against a reference (translation, metres, after rigid alignment).

    Parameters
    ----------
    timestamps : (N,) array_like
        Seconds.
    poses : (N, 4, 4) array_like
        Estimated camera-to-world poses, metres.
    reference_timestamps : (M,) array_like
    reference_poses : (M, 4, 4) array_like
    max_time_difference : float
        Largest timestamp difference of an associated pair, seconds.

    Returns
    -------
    TrajectoryError
        Metres.

    Raises
    ------
    InputError
        Malformed trajectories or no associated pose.
    """
    from evo.core import metrics

    ref, est = _associate(timestamps, poses, reference_timestamps, reference_poses, max_time_difference)
    if est.num_poses < 3:
        raise InputError(f"only {est.num_poses} poses could be associated; ATE needs at least 3")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        est.align(ref, correct_scale=False)
    ape = metrics.APE(metrics.PoseRelation.translation_part)
    ape.process_data((ref, est))
    return TrajectoryError.of(ape.error)


def reference_in_map_frame(timestamps, poses, reference_timestamps, reference_poses, *,
                           max_time_difference: float = 0.02) -> np.ndarray:
    """The reference trajectory over the estimate's time span, moved into the estimate's (the map's) frame by the
    rigid transform the ATE aligns them with (Horn 1987 / Umeyama 1991 on the associated positions, no scale), to
    draw beside the estimate.

    Parameters
    ----------
    timestamps, poses, reference_timestamps, reference_poses, max_time_difference
        As :func:`absolute_trajectory_error`.

    Returns
    -------
    (K, 4, 4) float64 ndarray
        Camera-to-world reference poses from the first to the last estimated timestamp, in the map's frame, metres.

    Raises
    ------
    InputError
        Malformed trajectories, or fewer than 3 associated poses.
    """
    ref, est = _associate(timestamps, poses, reference_timestamps, reference_poses, max_time_difference)
    if est.num_poses < 3:
        raise InputError(f"only {est.num_poses} poses could be associated; aligning the reference needs at least 3")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rotation, translation, _ = ref.align(est, correct_scale=False)  # reference onto the estimate
    moved = np.eye(4)
    moved[:3, :3], moved[:3, 3] = rotation, translation
    t = np.asarray(timestamps, dtype=np.float64).reshape(-1)
    rt = np.asarray(reference_timestamps, dtype=np.float64).reshape(-1)
    span = (rt >= t.min() - max_time_difference) & (rt <= t.max() + max_time_difference)
    return moved @ np.asarray(reference_poses, dtype=np.float64)[span]


def relative_pose_error(timestamps, poses, reference_timestamps, reference_poses, *, delta: int = 1,
                        max_time_difference: float = 0.02) -> tuple[TrajectoryError, TrajectoryError]:
    """RPE over pairs ``delta`` associated frames apart.

    Parameters
    ----------
    timestamps, poses, reference_timestamps, reference_poses, max_time_difference
        As :func:`absolute_trajectory_error`.
    delta : int
        Frame step of the pairs.

    Returns
    -------
    translation : TrajectoryError
        Metres.
    rotation : TrajectoryError
        Degrees.
    """
    from evo.core import metrics

    ref, est = _associate(timestamps, poses, reference_timestamps, reference_poses, max_time_difference)
    if est.num_poses <= delta:
        raise InputError(f"only {est.num_poses} poses could be associated; RPE with delta={delta} needs more")
    out = []
    for relation in (metrics.PoseRelation.translation_part, metrics.PoseRelation.rotation_angle_deg):
        rpe = metrics.RPE(relation, delta=int(delta), delta_unit=metrics.Unit.frames, all_pairs=True)
        rpe.process_data((ref, est))
        out.append(TrajectoryError.of(rpe.error))
    return out[0], out[1]


def write_tum_trajectory(path, timestamps, poses) -> int:
    """Write ``timestamp tx ty tz qx qy qz qw`` lines (TUM format), atomically.

    Parameters
    ----------
    path : str or os.PathLike
    timestamps : (N,) array_like
        Seconds.
    poses : (N, 4, 4) array_like
        Camera-to-world, metres.

    Returns
    -------
    int
        Lines written.
    """

    t = np.asarray(timestamps, dtype=np.float64).reshape(-1)
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 4, 4)
    if len(t) != len(p):
        raise InputError(f"{len(t)} timestamps but {len(p)} poses")
    lines = ["# timestamp tx ty tz qx qy qz qw"]
    if len(p):
        q = Rotation.from_matrix(p[:, :3, :3]).as_quat()
        for ti, pi, qi in zip(t, p, q):
            lines.append(f"{ti:.6f} {pi[0, 3]:.7f} {pi[1, 3]:.7f} {pi[2, 3]:.7f} "
                         f"{qi[0]:.7f} {qi[1]:.7f} {qi[2]:.7f} {qi[3]:.7f}")
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return len(p)
