"""Per-frame features lifted through depth, matches to a keyframe, and the landmark table."""

import numpy as np
import pytest

from seismo3d.mapping import FeatureOptions, LandmarkTable, frame_features, match_to_keyframe
from seismo3d.mapping.landmarks import FeatureMatches


@pytest.fixture(scope="module")
def pair(data_dir):
    from seismo3d.data import load_tum_pair

    return load_tum_pair()


def test_features_lift_and_match_consistently_with_the_ground_truth(pair):
    prev, curr = pair
    a = frame_features(prev.color, prev.depth, prev.intrinsics)
    b = frame_features(curr.color, curr.depth, curr.intrinsics)
    assert 200 < len(a) <= FeatureOptions().max_keypoints and np.all(a.points[:, 2] > 0)
    matches = match_to_keyframe(b, a)
    assert len(matches) > 100
    # the matched 3D points agree under the motion-capture motion (TUM colour is registered to depth)
    truth = np.linalg.inv(prev.pose) @ curr.pose
    moved = b.points[matches.frame_index] @ truth[:3, :3].T + truth[:3, 3]
    err = np.linalg.norm(moved - a.points[matches.keyframe_index], axis=1)
    assert np.median(err) < 0.02 and np.mean(err < 0.05) > 0.8


def test_no_colour_gives_no_features(pair):
    prev, _ = pair
    f = frame_features(None, prev.depth, prev.intrinsics)
    assert len(f) == 0 and len(match_to_keyframe(f, f)) == 0


def test_landmark_table_links_keyframes():
    table = LandmarkTable()
    table.add_keyframe(0, 5)
    table.add_keyframe(1, 4)
    m = FeatureMatches(np.array([0, 1, 2]), np.array([3, 4, 0]))
    out = table.link(1, 0, m, [True, True, False])
    assert [(lid, row, new) for lid, row, new in out] == [(0, 0, True), (1, 1, True)]
    assert table.ids[0].tolist() == [-1, -1, -1, 0, 1] and table.ids[1].tolist() == [0, 1, -1, -1]
    table.add_keyframe(2, 3)
    out = table.link(2, 1, FeatureMatches(np.array([2]), np.array([0])), [True])
    assert out == [(0, 2, False)] and table.observations[0] == 3 and table.n_landmarks == 2
