"""The mapping loop: ATE on the first 30 real 7-Scenes frames (the issue's test), relocalisation, bad frames."""

import warnings

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.geometry import rotation_error_deg, translation_error
from seismo3d.mapping import MapperOptions, RGBDMapper, absolute_trajectory_error, relative_pose_error

from .conftest import pose_at, room_frame


@pytest.fixture(scope="module")
def first_30(seven_scenes):
    """The loop over the first 30 frames of the 7-Scenes subset (every 5th original frame: 0..145)."""
    mapper = RGBDMapper()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no frame may be lost or skipped on this clean stretch
        results = [mapper.process(seven_scenes.read(i), index=i) for i in range(30)]
    return mapper, results


@pytest.mark.slow
def test_ate_on_the_first_30_frames(seven_scenes, first_30):
    mapper, results = first_30
    traj = mapper.trajectory()
    t, poses, status = traj.timestamps, traj.poses, traj.status
    assert len(t) == 30 and status[0] == "first" and all(s == "tracked" for s in status[1:])
    ref_t, ref_p = seven_scenes.groundtruth
    ate = absolute_trajectory_error(t, poses, ref_t, ref_p)
    rpe_t, rpe_r = relative_pose_error(t, poses, ref_t, ref_p)
    assert ate.n == 30
    assert ate.rmse < 0.03  # the target (3 cm) on the whole subset; measured here: see benchmarks/mapping.py
    assert rpe_t.rmse < 0.015 and rpe_r.rmse < 1.0
    # keyframes, landmarks and the map were built along the way
    assert len(mapper.graph.keyframes) >= 3 and len(mapper.filter.landmarks) > 0
    assert mapper.volume.n_blocks > 1000


@pytest.mark.slow
def test_relocalises_after_a_bad_prediction(seven_scenes, first_30):
    """Feed the same stretch to a fresh mapper, then throw its filter 60 degrees off: the feature (RANSAC) start
    of the fused ICP relocalises the camera."""
    mapper = RGBDMapper()
    for i in range(12):
        mapper.process(seven_scenes.read(i), index=i)
    turn = np.eye(4)
    turn[:3, :3] = pose_at(60.0, 0.0)[:3, :3]
    mapper.filter.pose = mapper.filter.pose @ turn
    frame = seven_scenes.read(12)
    result = mapper.process(frame, index=12)
    assert result.status == "relocalised"
    truth = np.linalg.inv(seven_scenes.entries[0].pose) @ frame.pose  # the map's frame is the first camera's
    # measured 0.58 deg and 0.017 m, limits 1.5x
    assert rotation_error_deg(result.pose, truth) < 0.88 and translation_error(result.pose, truth) < 0.026


@pytest.mark.slow
def test_bad_frames_are_refused_and_change_nothing():
    mapper = RGBDMapper(MapperOptions(use_features=False))
    first = room_frame(pose_at(), timestamp=0.0)
    mapper.process(first)
    state = (len(mapper.frames), mapper.filter.pose.copy(), mapper.volume.n_blocks)
    empty = room_frame(pose_at(1.0), timestamp=0.1)
    object.__setattr__(empty, "depth", np.full_like(empty.depth, np.nan))
    with pytest.raises(InputError, match="valid"):
        mapper.process(empty)
    with pytest.raises(InputError, match="not after"):
        mapper.process(room_frame(pose_at(1.0), timestamp=0.0))
    small = room_frame(pose_at(1.0), timestamp=0.2)
    object.__setattr__(small, "depth", small.depth[::2, ::2])
    with pytest.raises(InputError, match="does not belong"):
        mapper.process(small)
    assert len(mapper.frames) == state[0] and np.array_equal(mapper.filter.pose, state[1])
    assert mapper.volume.n_blocks == state[2]
    # a gap in the timestamps is reported and the frame is still mapped
    with pytest.warns(UserWarning, match="gap"):
        result = mapper.process(room_frame(pose_at(0.5), timestamp=3.0))
    assert result.status == "tracked"


@pytest.mark.slow
def test_generated_room_sequence_without_features():
    """Depth-only mapping of a generated room: a slow turn and slide, tracked frame to model."""
    mapper = RGBDMapper(MapperOptions(use_features=False))
    truths = [pose_at(0.8 * i, 0.2 * i, position=(0.01 * i, 0.0, -1.0 + 0.01 * i)) for i in range(10)]
    for i, pose in enumerate(truths):
        mapper.process(room_frame(pose, timestamp=i / 30.0))
    traj = mapper.trajectory()
    poses, status = traj.poses, traj.status
    assert len(traj) == 10 and all(s in ("first", "tracked") for s in status)
    # the map's frame is the first camera's: compare relative to it
    for est, truth in zip(poses, truths):
        rel = np.linalg.inv(truths[0]) @ truth
        # measured at worst 0.0050 deg and 3.1e-4 m over the frames, limits 1.5x
        assert rotation_error_deg(est, rel) < 0.0076 and translation_error(est, rel) < 4.7e-4
