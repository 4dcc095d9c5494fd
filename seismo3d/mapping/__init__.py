"""Robot mapping from RGB-D frames (method.md section 3): frame-to-model fused ICP tracking, Kalman prediction, a TSDF
map, keyframes, landmarks, loop closure and pose-graph optimisation, and the TUM trajectory metrics.

One module per concept: :mod:`.sequences` (TUM / 7-Scenes readers), :mod:`.odometry` (frame-to-model tracking),
:mod:`.kalman` (the EKF), :mod:`.landmarks` (features and landmarks), :mod:`.keyframes` (keyframe graph, gtsam),
:mod:`.tsdf` (the map), :mod:`.loop_closure` (bag of words + fused-ICP verification), :mod:`.metrics` (ATE / RPE by
evo), :mod:`.mapper` (the loop), :mod:`.frames` (frame-pair registration).
"""

from .frames import frame_feature_matches, frame_points, register_frames
from .kalman import FilterOptions, PoseFilter
from .keyframes import GraphEdge, Keyframe, KeyframeGraph, KeyframeOptions, is_new_keyframe
from .landmarks import FeatureOptions, FrameFeatures, LandmarkTable, frame_features, match_to_keyframe
from .loop_closure import LoopClosure, LoopDetector, LoopOptions, Vocabulary
from .mapper import FrameRecord, FrameResult, MapperOptions, RGBDMapper, Trajectory
from .metrics import (TrajectoryError, absolute_trajectory_error, reference_in_map_frame, relative_pose_error,
                      write_tum_trajectory)
from .odometry import FrameMeasurement, TrackingOptions, TrackingResult, measure_frame, track_frame
from .sequences import FrameEntry, RGBDSequence, associate_timestamps, open_sequence, read_tum_trajectory
from .tsdf import SurfacePrediction, TriangleMesh, TSDFOptions, TSDFVolume

__all__ = [
    "FeatureOptions", "FilterOptions", "FrameEntry", "FrameRecord", "Trajectory", "FrameFeatures", "FrameMeasurement", "FrameResult", "GraphEdge",
    "Keyframe", "KeyframeGraph", "KeyframeOptions", "LandmarkTable", "LoopClosure", "LoopDetector", "LoopOptions",
    "MapperOptions", "PoseFilter", "RGBDMapper", "RGBDSequence", "SurfacePrediction", "TSDFOptions", "TSDFVolume",
    "TrackingOptions", "TrackingResult", "TrajectoryError", "TriangleMesh", "Vocabulary", "absolute_trajectory_error",
    "associate_timestamps", "frame_feature_matches", "frame_features", "frame_points", "is_new_keyframe",
    "match_to_keyframe", "measure_frame", "open_sequence", "read_tum_trajectory", "register_frames",
    "reference_in_map_frame", "relative_pose_error", "track_frame", "write_tum_trajectory",
]
