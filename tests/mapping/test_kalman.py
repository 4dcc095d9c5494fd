"""The EKF: constant-velocity prediction, pose and landmark updates, gating, augmentation and marginalisation."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.mapping import FilterOptions, PoseFilter
from seismo3d.mapping.lie import exp_se3, log_se3


def _truth(k, dt=0.1):
    """Constant body velocity: 0.2 rad/s about y, 0.3 m/s forward."""
    return exp_se3(np.array([0, 0.2, 0, 0, 0, 0.3]) * dt) if k == 1 else np.linalg.matrix_power(_truth(1, dt), k)


def test_constant_velocity_prediction_after_pose_updates(rng):
    filt = PoseFilter(np.eye(4))
    info = np.diag([1e6] * 3 + [1e6] * 3)  # a confident ICP: 1 mrad, 1 mm
    for k in range(1, 8):
        filt.predict(0.1)
        noisy = _truth(k) @ exp_se3(rng.normal(0, 1e-3, 6))
        filt.update_pose(noisy, info)
    predicted = filt.predict(0.1)
    err = log_se3(np.linalg.inv(_truth(8)) @ predicted)
    assert np.linalg.norm(err[3:]) < 0.005 and np.degrees(np.linalg.norm(err[:3])) < 0.3
    assert np.allclose(filt.velocity, [0, 0.2, 0, 0, 0, 0.3], atol=0.03)


def test_pose_update_weighs_by_information():
    filt = PoseFilter(np.eye(4), FilterOptions(icp_covariance_scale=1.0))
    filt.predict(0.1)
    before = filt.pose_covariance
    measured = exp_se3([0, 0, 0, 0.01, 0, 0])
    filt.update_pose(measured, np.eye(6) * 1e8)  # far more certain than the prediction
    assert filt.pose[0, 3] == pytest.approx(0.01, abs=1e-4)
    assert np.all(np.diag(filt.pose_covariance) < np.diag(before))


def test_landmarks_are_added_measured_gated_and_marginalised():
    opt = FilterOptions(max_landmarks=3, landmark_sigma=0.01)
    filt = PoseFilter(np.eye(4), opt)
    points = np.array([[0.5, 0.0, 2.0], [-0.5, 0.2, 2.5], [0.0, -0.3, 1.5]])
    for i, p in enumerate(points):
        assert filt.add_landmark(i, p, 0.01)
    assert filt.landmarks.shape == (3, 3) and filt.covariance.shape == (21, 21)
    cov = filt.covariance
    assert np.allclose(cov, cov.T) and np.all(np.linalg.eigvalsh(cov) > -1e-12)
    # the camera moves 5 cm to the right; landmarks measured from there correct the pose
    filt.predict(0.1)
    moved = points - np.array([0.05, 0.0, 0.0])
    wrong = np.array([[3.0, 3.0, 3.0]])  # an outlier far outside the gate
    used = filt.update_landmarks([0, 1, 2, 2], np.vstack([moved, wrong]), [0.005] * 4)
    assert used == 3
    assert filt.pose[0, 3] == pytest.approx(0.05, abs=0.01)
    # a fourth landmark marginalises the least recently seen one
    filt.add_landmark(7, [0.0, 0.0, 3.0], 0.01)
    assert len(filt.landmark_ids) == 3 and 7 in filt.landmark_ids
    assert filt.covariance.shape == (21, 21)
    filt.remove_landmarks([7])
    assert filt.covariance.shape == (18, 18) and 7 not in filt.landmark_ids


def test_bad_input():
    with pytest.raises(InputError, match="pose"):
        PoseFilter(np.eye(3))
    with pytest.raises(InputError, match="dt"):
        PoseFilter(np.eye(4)).predict(-1.0)
    with pytest.raises(InputError):
        FilterOptions(landmark_sigma=0.0)
