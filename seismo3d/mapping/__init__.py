"""Robot mapping from RGB-D frames (method.md section 3): frame-to-frame registration by the fused ICP."""

from .frames import frame_feature_matches, frame_points, register_frames

__all__ = ["frame_feature_matches", "frame_points", "register_frames"]
