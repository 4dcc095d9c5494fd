"""The extended Kalman filter of the mapping loop: camera pose, velocity and landmark positions (step 4).

The state is the camera pose ``T`` (camera-to-world), its body-frame velocity ``v = (omega, nu)`` (rad/s, m/s) and
the world positions of the landmarks (3D visual features seen from several keyframes), as in the paper's EKF
(method.md section 3) and EKF-SLAM (Davison et al. 2007). Errors are right perturbations, ``T = T_hat exp(delta)``
(:mod:`.lie`), so the covariance is ``(6 + 6 + 3 K) x (6 + 6 + 3 K)``.

* :meth:`PoseFilter.predict`: constant velocity, ``T <- T exp(v dt)``, velocity random walk (process noise in
  acceleration units).
* :meth:`PoseFilter.update_pose`: the ICP's pose with the inverse of its information matrix (times
  ``icp_covariance_scale``: the Gauss-Newton information is known to be optimistic, Censi 2007) as the measurement.
* :meth:`PoseFilter.update_landmarks`: landmark positions measured in the camera frame (features lifted through
  depth), ``z = R^T (l - t)``, with Mahalanobis gating.
* :meth:`PoseFilter.add_landmark` / :meth:`PoseFilter.remove_landmarks`: state augmentation and marginalisation.

References
----------
Davison, A. J., Reid, I. D., Molton, N. D., Stasse, O. (2007). MonoSLAM: Real-time single camera SLAM. IEEE TPAMI
29(6), 1052-1067. doi:10.1109/TPAMI.2007.1049
Censi, A. (2007). An accurate closed-form estimate of ICP's covariance. ICRA, 3167-3172. doi:10.1109/ROBOT.2007.363961
Sola, J., Deray, J., Atchuthan, D. (2018). A micro Lie theory for state estimation in robotics. arXiv:1812.01537.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import block_diag

from .._validation import check_positive
from ..errors import InputError
from .lie import exp_se3, log_se3, skew

__all__ = ["FilterOptions", "PoseFilter"]

_CHI2_3DOF_99 = 11.345  # 99 % quantile of chi-square with 3 degrees of freedom
_CHI2_6DOF_999 = 22.458  # 99.9 % quantile with 6 degrees of freedom


@dataclass(frozen=True)
class FilterOptions:
    """Noise model of :class:`PoseFilter`.

    Attributes
    ----------
    angular_acceleration : float
        Standard deviation of the angular acceleration, rad/s^2 (velocity random walk).
    linear_acceleration : float
        Standard deviation of the linear acceleration, m/s^2.
    icp_covariance_scale : float
        Factor on the inverse ICP information (>= 1: ICP covariances are optimistic).
    landmark_sigma : float
        Floor of a landmark measurement's standard deviation, metres (colour keypoints lifted through depth).
    max_landmarks : int
        Most landmarks in the state (the least recently seen are marginalised out first).
    initial_sigma : tuple of float
        Standard deviations of the first pose (rad, m) and velocity (rad/s, m/s).
    """

    angular_acceleration: float = 2.0
    linear_acceleration: float = 2.0
    icp_covariance_scale: float = 10.0
    landmark_sigma: float = 0.01
    max_landmarks: int = 60
    initial_sigma: tuple = (1e-4, 1e-4, 0.5, 0.5)

    def __post_init__(self):
        for name in ("angular_acceleration", "linear_acceleration", "icp_covariance_scale", "landmark_sigma"):
            check_positive(getattr(self, name), name)
        if int(self.max_landmarks) < 0:
            raise InputError(f"max_landmarks must be >= 0; got {self.max_landmarks!r}")


class PoseFilter:
    """EKF over camera pose, velocity and landmarks (see the module docstring).

    Parameters
    ----------
    pose : (4, 4) array_like
        Initial camera-to-world pose.
    options : FilterOptions, optional
    """

    def __init__(self, pose, options: FilterOptions | None = None):
        self.options = FilterOptions() if options is None else options
        self.pose = np.array(pose, dtype=np.float64)
        if self.pose.shape != (4, 4):
            raise InputError(f"pose must be (4, 4); got {self.pose.shape}")
        self.velocity = np.zeros(6)
        sr, st, sw, sv = self.options.initial_sigma
        self.covariance = np.diag([sr**2] * 3 + [st**2] * 3 + [sw**2] * 3 + [sv**2] * 3)
        self.landmarks = np.zeros((0, 3))
        self.landmark_ids = np.zeros(0, np.int64)
        self.last_seen = np.zeros(0, np.int64)
        self.step = 0

    # ---------------------------------------------------------------------------------------------------------------
    @property
    def pose_covariance(self) -> np.ndarray:
        """(6, 6) covariance of the pose error (rad, m)."""
        return self.covariance[:6, :6].copy()

    def predict(self, dt: float) -> np.ndarray:
        """Propagate by ``dt`` seconds at constant velocity; return the predicted pose (4, 4).

        Raises
        ------
        InputError
            If ``dt`` is negative or not finite.
        """
        dt = check_positive(dt, "dt", allow_zero=True)
        self.step += 1
        step = exp_se3(self.velocity * dt)
        self.pose = self.pose @ step
        n = len(self.covariance)
        f = np.eye(n)
        f[:6, :6] = _adjoint(np.linalg.inv(step))
        f[:6, 6:12] = np.eye(6) * dt
        q = np.zeros((n, n))
        acc = np.array([self.options.angular_acceleration] * 3 + [self.options.linear_acceleration] * 3)
        q[6:12, 6:12] = np.diag((acc**2) * max(dt, 1e-3))
        # the pose also takes the integrated acceleration noise (dt^3 / 3)
        q[:6, :6] = np.diag((acc**2) * max(dt, 1e-3) ** 3 / 3.0)
        self.covariance = f @ self.covariance @ f.T + q
        return self.pose.copy()

    def update_pose(self, measured_pose, information) -> bool:
        """Fuse a measured pose (the ICP result) with its information matrix (rad, m; camera frame).

        Returns
        -------
        bool
            False when the measurement failed the chi-square gate (99.9 %) and was not used.
        """
        info = np.asarray(information, dtype=np.float64)
        cov = np.linalg.pinv(info + 1e-12 * np.eye(6)) * self.options.icp_covariance_scale
        r = log_se3(np.linalg.inv(self.pose) @ np.asarray(measured_pose, dtype=np.float64))
        h = np.zeros((6, len(self.covariance)))
        h[:, :6] = np.eye(6)
        return self._update(r, h, cov, gate=None)

    def update_landmarks(self, ids, points_camera, depth_sigma) -> int:
        """Fuse measured landmark positions (camera frame, metres) for landmarks already in the state.

        Parameters
        ----------
        ids : (M,) int array_like
            Landmark identifiers (unknown ones are ignored).
        points_camera : (M, 3) array_like
            Measured positions in the camera frame, metres.
        depth_sigma : (M,) array_like
            Axial standard deviation of each measurement, metres.

        Returns
        -------
        int
            Measurements used (after the 99 % chi-square gate of each one).
        """
        ids = np.asarray(ids, dtype=np.int64).reshape(-1)
        z = np.asarray(points_camera, dtype=np.float64).reshape(-1, 3)
        sig = np.asarray(depth_sigma, dtype=np.float64).reshape(-1)
        rows = {int(i): k for k, i in enumerate(self.landmark_ids)}
        used = 0
        rot, t = self.pose[:3, :3], self.pose[:3, 3]
        n = len(self.covariance)
        hs, rs, covs = [], [], []
        for lid, meas, s in zip(ids, z, sig):
            k = rows.get(int(lid))
            if k is None:
                continue
            z0 = rot.T @ (self.landmarks[k] - t)
            h = np.zeros((3, n))
            h[:, :3] = skew(z0)
            h[:, 3:6] = -np.eye(3)
            h[:, 12 + 3 * k: 15 + 3 * k] = rot.T
            s_lat = max(self.options.landmark_sigma, s)
            cov = np.diag([s_lat**2, s_lat**2, max(self.options.landmark_sigma, s) ** 2])
            r = meas - z0
            # individual gate against the current covariance
            sk = h @ self.covariance @ h.T + cov
            if r @ np.linalg.solve(sk, r) > _CHI2_3DOF_99:
                continue
            hs.append(h)
            rs.append(r)
            covs.append(cov)
            self.last_seen[k] = self.step
            used += 1
        if used:
            self._update(np.concatenate(rs), np.vstack(hs), block_diag(*covs), gate=None)
        return used

    def add_landmark(self, landmark_id: int, point_camera, depth_sigma: float) -> bool:
        """Augment the state with a landmark measured in the camera frame; returns False when the state is full and
        no landmark could be marginalised to make room (``max_landmarks`` = 0)."""
        opt = self.options
        if opt.max_landmarks == 0:
            return False
        if len(self.landmark_ids) >= opt.max_landmarks:
            oldest = int(np.argmin(self.last_seen))
            self.remove_landmarks([self.landmark_ids[oldest]])
        z = np.asarray(point_camera, dtype=np.float64).reshape(3)
        rot, t = self.pose[:3, :3], self.pose[:3, 3]
        world = rot @ z + t
        n = len(self.covariance)
        # l = t + R z ; dl/d(theta) = -R [z]x ; dl/d(p) = R ; dl/dz = R
        j = np.zeros((3, n))
        j[:, :3] = -rot @ skew(z)
        j[:, 3:6] = rot
        s = max(opt.landmark_sigma, float(depth_sigma))
        r_cov = rot @ np.diag([s**2, s**2, s**2]) @ rot.T
        p_ll = j @ self.covariance @ j.T + r_cov
        p_lx = j @ self.covariance
        cov = np.zeros((n + 3, n + 3))
        cov[:n, :n] = self.covariance
        cov[n:, :n] = p_lx
        cov[:n, n:] = p_lx.T
        cov[n:, n:] = p_ll
        self.covariance = cov
        self.landmarks = np.vstack([self.landmarks, world])
        self.landmark_ids = np.append(self.landmark_ids, int(landmark_id))
        self.last_seen = np.append(self.last_seen, self.step)
        return True

    def remove_landmarks(self, ids) -> None:
        """Marginalise landmarks out of the state (delete their rows and columns of the covariance)."""
        drop = np.isin(self.landmark_ids, np.asarray(list(ids), dtype=np.int64))
        if not drop.any():
            return
        keep_rows = np.concatenate([np.ones(12, bool), np.repeat(~drop, 3)])
        self.covariance = self.covariance[np.ix_(keep_rows, keep_rows)]
        self.landmarks = self.landmarks[~drop]
        self.landmark_ids = self.landmark_ids[~drop]
        self.last_seen = self.last_seen[~drop]

    def reset_pose(self, pose) -> None:
        """Set the pose (relocalisation or a corrected pose graph), keep the covariance, zero the velocity."""
        self.pose = np.array(pose, dtype=np.float64)
        self.velocity = np.zeros(6)

    def transform_landmarks(self, correction) -> None:
        """Apply a world correction (4, 4) to every landmark (after pose-graph optimisation)."""
        c = np.asarray(correction, dtype=np.float64)
        if len(self.landmarks):
            self.landmarks = self.landmarks @ c[:3, :3].T + c[:3, 3]

    # ---------------------------------------------------------------------------------------------------------------
    def _update(self, r, h, cov, gate):
        s = h @ self.covariance @ h.T + cov
        if gate is not None and r @ np.linalg.solve(s, r) > gate:
            return False
        k = np.linalg.solve(s, h @ self.covariance).T
        delta = k @ r
        n = len(self.covariance)
        ikh = np.eye(n) - k @ h
        self.covariance = ikh @ self.covariance @ ikh.T + k @ cov @ k.T  # Joseph form
        self.covariance = 0.5 * (self.covariance + self.covariance.T)
        self.pose = self.pose @ exp_se3(delta[:6])
        self.velocity = self.velocity + delta[6:12]
        if len(self.landmarks):
            self.landmarks = self.landmarks + delta[12:].reshape(-1, 3)
        return True


def _adjoint(transform) -> np.ndarray:
    """(6, 6) adjoint of a rigid transform for (rotation, translation) tangent vectors."""
    rot, t = transform[:3, :3], transform[:3, 3]
    out = np.zeros((6, 6))
    out[:3, :3] = rot
    out[3:, 3:] = rot
    out[3:, :3] = skew(t) @ rot
    return out
