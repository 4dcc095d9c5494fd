"""ATE / RPE (computed by evo) against the TUM definitions written out here, on generated and real trajectories."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from seismo3d.errors import InputError
from seismo3d.mapping import (absolute_trajectory_error, read_tum_trajectory, reference_in_map_frame,
                              relative_pose_error, write_tum_trajectory)


def _tum_ate(est, ref):
    """TUM's evaluate_ate: Horn/Umeyama rigid alignment of the positions, then RMSE of the position differences."""
    a, b = est[:, :3, 3], ref[:, :3, 3]
    ma, mb = a.mean(0), b.mean(0)
    u, _, vt = np.linalg.svd((b - mb).T @ (a - ma))
    s = np.diag([1, 1, np.sign(np.linalg.det(u @ vt))])
    rot = u @ s @ vt
    err = np.linalg.norm((a - ma) @ rot.T + mb - b, axis=1)
    return np.sqrt(np.mean(err**2))


def _tum_rpe(est, ref, delta=1):
    """TUM's evaluate_rpe (eq. 1): error of the relative motion over pairs delta frames apart."""
    t, r = [], []
    for i in range(len(est) - delta):
        e = np.linalg.inv(np.linalg.inv(ref[i]) @ ref[i + delta]) @ (np.linalg.inv(est[i]) @ est[i + delta])
        t.append(np.linalg.norm(e[:3, 3]))
        r.append(np.degrees(Rotation.from_matrix(e[:3, :3]).magnitude()))
    return np.sqrt(np.mean(np.square(t))), np.sqrt(np.mean(np.square(r)))


def _trajectory(n, rng):
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, :3] = Rotation.from_euler("xyz", np.cumsum(rng.normal(0, 2, (n, 3)), 0), degrees=True).as_matrix()
    poses[:, :3, 3] = np.cumsum(rng.normal(0, 0.03, (n, 3)), 0)
    return np.arange(n) * 0.1, poses


def test_ate_removes_the_rigid_offset_and_matches_the_tum_definition(rng):
    t, ref = _trajectory(60, rng)
    offset = np.eye(4)
    offset[:3, :3] = Rotation.from_euler("z", 30, degrees=True).as_matrix()
    offset[:3, 3] = [1.0, -2.0, 0.5]
    est = offset @ ref
    noise = rng.normal(0, 0.01, (60, 3))
    est[:, :3, 3] += noise
    ate = absolute_trajectory_error(t, est, t, ref)
    assert ate.n == 60
    assert ate.rmse == pytest.approx(_tum_ate(est, ref), rel=1e-9)
    assert ate.rmse < np.sqrt(np.mean(np.sum(noise**2, 1))) + 1e-9  # alignment can only lower it
    assert ate.rmse > 0.8 * np.sqrt(np.mean(np.sum(noise**2, 1)))


def test_the_reference_moved_into_the_map_frame(rng):
    """The ground truth over the estimate's span, moved by the ATE's alignment: on an estimate that is the
    reference in another frame, it lands on the estimate (its positions and orientations)."""
    t, ref = _trajectory(60, rng)
    offset = np.eye(4)
    offset[:3, :3] = Rotation.from_euler("zx", [40, -15], degrees=True).as_matrix()
    offset[:3, 3] = [1.0, -2.0, 0.5]
    est = offset @ ref[10:50]  # the map starts at frame 10 and stops at 49
    moved = reference_in_map_frame(t[10:50], est, t, ref)
    assert moved.shape == (40, 4, 4)
    np.testing.assert_allclose(moved, est, atol=1e-9)
    with pytest.raises(InputError, match="at least 3"):
        reference_in_map_frame(t[:2], est[:2], t, ref)


def test_rpe_matches_the_tum_definition(rng):
    t, ref = _trajectory(40, rng)
    est = ref.copy()
    for i in range(40):
        est[i] = est[i] @ np.block([[Rotation.from_rotvec(rng.normal(0, 0.01, 3)).as_matrix(),
                                     rng.normal(0, 0.005, (3, 1))], [np.zeros((1, 3)), np.ones((1, 1))]])
    for delta in (1, 5):
        trans, rot = relative_pose_error(t, est, t, ref, delta=delta)
        want_t, want_r = _tum_rpe(est, ref, delta)
        assert trans.rmse == pytest.approx(want_t, rel=1e-9) and rot.rmse == pytest.approx(want_r, rel=1e-6)


def test_real_rgbdslam_trajectory_against_motion_capture(data_dir):
    """fr1/xyz: RGBD-SLAM's estimate against the motion-capture ground truth, associated by timestamp."""
    from seismo3d.data import fetch
    from seismo3d.mapping import associate_timestamps

    gt_t, gt_p = read_tum_trajectory(fetch("rgbd/tum_trajectories/freiburg1_xyz-groundtruth.txt"))
    est_t, est_p = read_tum_trajectory(fetch("rgbd/tum_trajectories/freiburg1_xyz-rgbdslam.txt"))
    ate = absolute_trajectory_error(est_t, est_p, gt_t, gt_p)
    i, j = associate_timestamps(est_t, gt_t, max_difference=0.02)
    assert ate.n == len(i) > 700
    assert ate.rmse == pytest.approx(_tum_ate(est_p[i], gt_p[j]), rel=1e-6)
    assert 0.005 < ate.rmse < 0.05  # a working SLAM system on fr1/xyz: centimetres


def test_write_and_read_back(tmp_path, rng):
    t, poses = _trajectory(10, rng)
    n = write_tum_trajectory(tmp_path / "traj.txt", t + 1e9, poses)
    back_t, back_p = read_tum_trajectory(tmp_path / "traj.txt")
    assert n == 10
    np.testing.assert_allclose(back_t, t + 1e9, atol=1e-6)
    np.testing.assert_allclose(back_p, poses, atol=1e-6)


def test_errors_on_bad_input(rng):
    t, p = _trajectory(5, rng)
    with pytest.raises(InputError, match="no estimated pose"):
        absolute_trajectory_error(t + 100.0, p, t, p)
    with pytest.raises(InputError, match="one timestamp each"):
        absolute_trajectory_error(t[:3], p, t, p)
