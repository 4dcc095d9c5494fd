"""The keyframe graph: time-stamped keyframe vertices, odometry and loop-closure edges, pose-graph optimisation.

A frame becomes a keyframe when the camera has moved or turned enough since the last keyframe
(:func:`is_new_keyframe`). Consecutive keyframes are joined by odometry edges; loop closure adds edges between a
keyframe and an earlier one it recognises (:mod:`.loop_closure`). :meth:`KeyframeGraph.optimise` solves the pose graph
with gtsam's Levenberg-Marquardt (Dellaert and Kaess 2017), loop edges under a Huber kernel, and returns the
corrected keyframe poses.

References
----------
Dellaert, F., Kaess, M. (2017). Factor graphs for robot perception. Foundations and Trends in Robotics 6(1-2), 1-139.
doi:10.1561/2300000043
Kummerle, R., Grisetti, G., Strasdat, H., Konolige, K., Burgard, W. (2011). g2o: A general framework for graph
optimization. ICRA, 3607-3613. doi:10.1109/ICRA.2011.5979949
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validation import check_positive
from ..errors import InputError
from .lie import log_se3

__all__ = ["KeyframeOptions", "Keyframe", "GraphEdge", "KeyframeGraph", "is_new_keyframe"]


@dataclass(frozen=True)
class KeyframeOptions:
    """When a frame becomes a keyframe.

    Attributes
    ----------
    translation : float
        Camera travel since the last keyframe, metres.
    rotation_deg : float
        Camera turn since the last keyframe, degrees.
    max_frames : int
        A keyframe at least every this many tracked frames (keeps the feature matches overlapping).
    """

    translation: float = 0.10
    rotation_deg: float = 10.0
    max_frames: int = 15

    def __post_init__(self):
        check_positive(self.translation, "translation")
        check_positive(self.rotation_deg, "rotation_deg")
        if int(self.max_frames) < 1:
            raise InputError(f"max_frames must be >= 1; got {self.max_frames!r}")


@dataclass(eq=False)
class Keyframe:
    """A vertex of the keyframe graph.

    Attributes
    ----------
    id : int
        0, 1, 2, ... in creation order.
    frame_index : int
        Index of the frame in the sequence.
    timestamp : float
        Seconds.
    pose : (4, 4) float64 ndarray
        Camera-to-world pose (corrected by pose-graph optimisation).
    features : FrameFeatures
        Keypoints with depth, descriptors, camera-frame points.
    depth : (H, W) uint16 ndarray
        Depth in millimetres (0 invalid), kept to re-fuse the map after a loop closure and to verify loops.
    intrinsics : CameraIntrinsics
        Of the depth image.
    bow : dict
        Bag-of-words vector (word -> tf-idf weight), set by :class:`~seismo3d.mapping.loop_closure.LoopDetector`.
    cache : dict
        Derived data computed once (e.g. the downsampled cloud loop verification registers).
    """

    id: int
    frame_index: int
    timestamp: float
    pose: np.ndarray
    features: object
    depth: np.ndarray
    intrinsics: object
    bow: dict = field(default_factory=dict)
    cache: dict = field(default_factory=dict)

    def depth_metres(self) -> np.ndarray:
        """(H, W) float32 depth in metres, NaN where invalid."""
        d = self.depth.astype(np.float32) / 1000.0
        d[self.depth == 0] = np.nan
        return d


@dataclass(frozen=True)
class GraphEdge:
    """A relative-pose constraint between two keyframes.

    Attributes
    ----------
    source, target : int
        Keyframe ids; the measurement is ``inv(pose[source]) @ pose[target]``.
    relative : (4, 4) float64 ndarray
        Measured relative pose, metres.
    information : (6, 6) float64 ndarray
        Information matrix (rotation rad, translation m).
    kind : {'odometry', 'loop'}
    """

    source: int
    target: int
    relative: np.ndarray
    information: np.ndarray
    kind: str


def is_new_keyframe(pose, keyframe_pose, frames_since: int, options: KeyframeOptions) -> bool:
    """True when the camera moved or turned past the thresholds, or ``max_frames`` passed, since the keyframe.

    Parameters
    ----------
    pose, keyframe_pose : (4, 4) array_like
        Camera-to-world poses.
    frames_since : int
        Tracked frames since the keyframe.
    options : KeyframeOptions
    """
    rel = np.linalg.inv(np.asarray(keyframe_pose)) @ np.asarray(pose)
    angle = np.degrees(np.arccos(np.clip((np.trace(rel[:3, :3]) - 1) / 2, -1, 1)))
    return bool(np.linalg.norm(rel[:3, 3]) > options.translation or angle > options.rotation_deg
                or frames_since >= options.max_frames)


@dataclass
class KeyframeGraph:
    """Keyframes and edges (see the module docstring)."""

    keyframes: list = field(default_factory=list)
    edges: list = field(default_factory=list)

    def add_keyframe(self, keyframe: Keyframe) -> None:
        """Append a vertex (its id must be the next one)."""
        if keyframe.id != len(self.keyframes):
            raise InputError(f"keyframe id {keyframe.id} must be {len(self.keyframes)} (ids are consecutive)")
        self.keyframes.append(keyframe)

    def add_edge(self, source: int, target: int, relative, information, kind: str) -> GraphEdge:
        """Add an edge; returns it.

        Raises
        ------
        InputError
            Unknown keyframes, malformed matrices or kind.
        """
        if kind not in ("odometry", "loop"):
            raise InputError(f"kind must be 'odometry' or 'loop'; got {kind!r}")
        for k in (source, target):
            if not 0 <= k < len(self.keyframes):
                raise InputError(f"keyframe {k} is not in the graph ({len(self.keyframes)} keyframes)")
        rel = np.asarray(relative, dtype=np.float64)
        info = np.asarray(information, dtype=np.float64)
        if rel.shape != (4, 4) or info.shape != (6, 6):
            raise InputError(f"relative must be (4, 4) and information (6, 6); got {rel.shape}, {info.shape}")
        edge = GraphEdge(int(source), int(target), rel, 0.5 * (info + info.T), kind)
        self.edges.append(edge)
        return edge

    @property
    def n_loops(self) -> int:
        """Number of loop-closure edges."""
        return sum(e.kind == "loop" for e in self.edges)

    def poses(self) -> np.ndarray:
        """(K, 4, 4) keyframe poses."""
        return np.array([k.pose for k in self.keyframes]).reshape(-1, 4, 4)

    def optimise(self, *, max_iterations: int = 100) -> np.ndarray:
        """Optimise the keyframe poses with gtsam (first keyframe fixed) and store them in the keyframes.

        Returns
        -------
        (K, 4, 4) float64 ndarray
            The corrected poses.

        Raises
        ------
        ImportError
            If gtsam is not installed (``pip install gtsam``).
        """
        try:
            import gtsam
        except ImportError as exc:  # pragma: no cover - a dependency of seismo3d
            raise ImportError("pose-graph optimisation needs gtsam: pip install gtsam") from exc
        if len(self.keyframes) < 2:
            return self.poses()
        graph = gtsam.NonlinearFactorGraph()
        values = gtsam.Values()
        for k in self.keyframes:
            values.insert(k.id, gtsam.Pose3(k.pose))
        graph.add(gtsam.PriorFactorPose3(0, gtsam.Pose3(self.keyframes[0].pose),
                                         gtsam.noiseModel.Isotropic.Sigma(6, 1e-6)))
        for e in self.edges:
            info = e.information + 1e-9 * np.eye(6)
            noise = gtsam.noiseModel.Gaussian.Information(info)
            if e.kind == "loop":
                noise = gtsam.noiseModel.Robust.Create(gtsam.noiseModel.mEstimator.Huber.Create(1.345), noise)
            graph.add(gtsam.BetweenFactorPose3(e.source, e.target, gtsam.Pose3(e.relative), noise))
        params = gtsam.LevenbergMarquardtParams()
        params.setMaxIterations(int(max_iterations))
        result = gtsam.LevenbergMarquardtOptimizer(graph, values, params).optimize()
        for k in self.keyframes:
            k.pose = np.asarray(result.atPose3(k.id).matrix(), dtype=np.float64)
        return self.poses()

    def to_dict(self) -> dict:
        """JSON-ready description: vertices (id, frame index, timestamp, pose) and edges (ids, kind, relative pose,
        and the error of the relative pose at the current keyframe poses)."""
        poses = {k.id: k.pose for k in self.keyframes}
        edges = []
        for e in self.edges:
            err = log_se3(np.linalg.inv(e.relative) @ np.linalg.inv(poses[e.source]) @ poses[e.target])
            edges.append(dict(source=e.source, target=e.target, kind=e.kind, relative=e.relative.tolist(),
                              rotation_error_deg=float(np.degrees(np.linalg.norm(err[:3]))),
                              translation_error_m=float(np.linalg.norm(err[3:]))))
        return dict(
            keyframes=[dict(id=k.id, frame_index=k.frame_index, timestamp=k.timestamp, pose=k.pose.tolist(),
                            n_features=0 if k.features is None else len(k.features)) for k in self.keyframes],
            edges=edges,
        )
