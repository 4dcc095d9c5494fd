"""The keyframe graph: keyframe decisions, and gtsam's pose-graph optimisation closing a drifted loop."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.mapping import Keyframe, KeyframeGraph, KeyframeOptions, is_new_keyframe
from seismo3d.mapping.lie import exp_se3, log_se3


def test_keyframe_thresholds():
    opt = KeyframeOptions(translation=0.1, rotation_deg=10.0, max_frames=5)
    assert not is_new_keyframe(exp_se3([0, 0, 0, 0.05, 0, 0]), np.eye(4), 1, opt)
    assert is_new_keyframe(exp_se3([0, 0, 0, 0.11, 0, 0]), np.eye(4), 1, opt)
    assert is_new_keyframe(exp_se3([0, np.radians(11), 0, 0, 0, 0]), np.eye(4), 1, opt)
    assert is_new_keyframe(np.eye(4), np.eye(4), 5, opt)


def _square(n_side=5, step=0.5):
    """Poses around a square (turning 90 degrees at the corners), ending where it started."""
    poses, pose = [], np.eye(4)
    move = exp_se3([0, 0, 0, step, 0, 0])
    turn = exp_se3([0, 0, np.pi / 2, 0, 0, 0])
    for side in range(4):
        for _ in range(n_side):
            poses.append(pose.copy())
            pose = pose @ move
        pose = pose @ turn
    return np.array(poses)


def test_pose_graph_closes_a_drifted_loop(rng):
    truth = _square()
    n = len(truth)
    graph = KeyframeGraph()
    drift = exp_se3([0, 0, np.radians(1.5), 0.01, 0, 0])  # every odometry step turns 1.5 deg and slides 1 cm too far
    pose = truth[0].copy()
    for i in range(n):
        graph.add_keyframe(Keyframe(i, i, float(i), pose.copy(), features=None, depth=None, intrinsics=None))
        if i + 1 < n:
            pose = pose @ np.linalg.inv(truth[i]) @ truth[i + 1] @ drift
    for i in range(n - 1):
        odo = np.linalg.inv(truth[i]) @ truth[i + 1]
        graph.add_edge(i, i + 1, odo @ drift, np.diag([1e4] * 3 + [1e4] * 3), "odometry")
    before = np.linalg.norm(graph.poses()[-1][:3, 3] - truth[-1][:3, 3])
    # the loop: the last keyframe seen again from the first (true relative pose)
    graph.add_edge(0, n - 1, np.linalg.inv(truth[0]) @ truth[-1], np.eye(6) * 1e6, "loop")
    poses = graph.optimise()
    after = np.linalg.norm(poses[-1][:3, 3] - truth[-1][:3, 3])
    errors = [np.linalg.norm(p[:3, 3] - t[:3, 3]) for p, t in zip(poses, truth)]
    assert before > 0.3 and after < 0.02 and max(errors) < 0.5 * before
    assert graph.n_loops == 1
    d = graph.to_dict()
    assert len(d["keyframes"]) == n and d["edges"][-1]["kind"] == "loop"
    assert d["edges"][-1]["translation_error_m"] < 0.02


def test_graph_errors():
    graph = KeyframeGraph()
    with pytest.raises(InputError, match="keyframe id"):
        graph.add_keyframe(Keyframe(3, 0, 0.0, np.eye(4), None, None, None))
    graph.add_keyframe(Keyframe(0, 0, 0.0, np.eye(4), None, None, None))
    with pytest.raises(InputError, match="not in the graph"):
        graph.add_edge(0, 1, np.eye(4), np.eye(6), "odometry")
    with pytest.raises(InputError, match="kind"):
        graph.add_edge(0, 0, np.eye(4), np.eye(6), "gps")
    assert log_se3(graph.optimise()[0]).max() == 0.0  # one keyframe: nothing to optimise
