"""The RGB-D mapping loop of method.md section 3: track, fuse, predict, with keyframes, landmarks and loop closure.

For every frame (:meth:`RGBDMapper.process`), in order:

1. measure: depth -> filtered points and normals, image pyramid (:func:`~.odometry.measure_frame`); ORB features
   lifted through depth (:func:`~.landmarks.frame_features`) and matched to the last keyframe;
2. predict the pose with the Kalman filter (constant velocity, :class:`~.kalman.PoseFilter`) and the surface by a
   raycast of the map at that pose (:meth:`~.tsdf.TSDFVolume.raycast`);
3. track: fused ICP of the frame onto the predicted surface with projective association, coarse to fine
   (:func:`~.odometry.track_frame`), with the feature matches the motion model supports (guided matching); when
   tracking fails, the engine's RANSAC over every match relocalises the camera, the map is raycast again there and the
   frame tracked from it (the fused ICP's global reach);
4. update the filter with the ICP pose (its information matrix as the measurement noise) and with the landmarks the
   frame sees;
5. fuse the frame into the TSDF at the filtered pose, leaving out dynamic pixels;
6. keyframes: when the camera moved or turned enough, add a keyframe, an odometry edge and new landmarks; look for a
   loop by bag of words, verify it by fused ICP, optimise the pose graph (gtsam) and re-fuse the map from the corrected
   keyframes.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError, RegistrationError, Seismo3dWarning
from ..registration import ransac
from .kalman import FilterOptions, PoseFilter
from .keyframes import Keyframe, KeyframeGraph, KeyframeOptions, is_new_keyframe
from .landmarks import FeatureOptions, FrameFeatures, LandmarkTable, frame_features, match_to_keyframe
from .loop_closure import LoopDetector, LoopOptions
from .odometry import TrackingOptions, dynamic_mask, kinect_depth_sigma, measure_frame, track_frame
from .tsdf import TSDFOptions, TSDFVolume

__all__ = ["MapperOptions", "FrameResult", "FrameRecord", "Trajectory", "RGBDMapper"]


@dataclass(frozen=True)
class MapperOptions:
    """Options of the mapping loop (each part has its own options dataclass).

    Attributes
    ----------
    tsdf : TSDFOptions
    tracking : TrackingOptions
    features : FeatureOptions
    filter : FilterOptions
    keyframes : KeyframeOptions
    loops : LoopOptions
    use_features : bool
        Feature term in tracking, landmarks and loop closure (False: depth only).
    loop_closure : bool
        Look for loops and optimise the pose graph.
    max_gap : float
        A timestamp gap longer than this (seconds) is reported; the filter predicts across it.
    min_valid_fraction : float
        Frames with fewer valid depth pixels than this fraction are skipped.
    landmark_gate : float
        A landmark match farther than this from its landmark at the tracked pose is not used (metres).
    default_frame_interval : float
        Seconds between frames that carry no timestamp.
    guided_radius : float
        Feature matches farther than this (metres) from their keyframe point at the predicted pose are left out of
        tracking (guided matching with the motion model, as ORB-SLAM); all matches are used again to relocalise
        when tracking fails.
    relocalise_translation, relocalise_rotation_deg : float
        A feature (RANSAC) start farther than this from the prediction (metres, degrees) is a relocalisation: the map
        is raycast again at the new pose, the frame tracked again, and the filter restarted there.
    """

    tsdf: TSDFOptions = field(default_factory=TSDFOptions)
    tracking: TrackingOptions = field(default_factory=TrackingOptions)
    features: FeatureOptions = field(default_factory=FeatureOptions)
    filter: FilterOptions = field(default_factory=FilterOptions)
    keyframes: KeyframeOptions = field(default_factory=KeyframeOptions)
    loops: LoopOptions = field(default_factory=LoopOptions)
    use_features: bool = True
    loop_closure: bool = True
    max_gap: float = 1.0
    min_valid_fraction: float = 0.05
    landmark_gate: float = 0.05
    default_frame_interval: float = 1.0 / 30.0
    guided_radius: float = 0.25
    relocalise_translation: float = 0.10
    relocalise_rotation_deg: float = 10.0


@dataclass(frozen=True)
class FrameResult:
    """What the loop did with one frame.

    Attributes
    ----------
    index : int
        The frame's index given to :meth:`RGBDMapper.process`.
    timestamp : float
        Seconds.
    pose : (4, 4) float64 ndarray
        Estimated camera-to-world pose (before later loop corrections), metres.
    status : {'first', 'tracked', 'relocalised', 'lost'}
        ``'lost'``: tracking failed; the pose is the filter's prediction and the frame was not fused.
    keyframe : int or None
        The keyframe this frame became.
    fitness, inlier_rmse : float
        Of the tracking (NaN for the first frame).
    n_landmarks : int
        Landmark measurements the filter used.
    loops : int
        Loop closures accepted at this frame.
    """

    index: int
    timestamp: float
    pose: np.ndarray
    status: str
    keyframe: int | None
    fitness: float
    inlier_rmse: float
    n_landmarks: int
    loops: int


@dataclass(frozen=True)
class FrameRecord:
    """The mapper's record of one frame: its pose is kept relative to a keyframe, so that a pose-graph correction of
    the keyframe moves it too.

    Attributes
    ----------
    index : int
    timestamp : float
        Seconds.
    keyframe : int
        Id of the keyframe the pose is relative to (the newest keyframe when the frame was mapped).
    relative : (4, 4) float64 ndarray
        ``inv(keyframe pose) @ frame pose``.
    status : {'first', 'tracked', 'relocalised', 'lost'}
    """

    index: int
    timestamp: float
    keyframe: int
    relative: np.ndarray
    status: str


@dataclass(frozen=True)
class Trajectory:
    """The poses of the frames mapped so far (see :meth:`RGBDMapper.trajectory`).

    Attributes
    ----------
    timestamps : (N,) float64 ndarray
        Seconds.
    poses : (N, 4, 4) float64 ndarray
        Camera-to-world, metres, corrected by the pose graph.
    status : list of str
        Per frame, as :attr:`FrameRecord.status`.
    indices : (N,) int64 ndarray
        The frames' indices.
    """

    timestamps: np.ndarray
    poses: np.ndarray
    status: list
    indices: np.ndarray

    def __len__(self) -> int:
        return int(len(self.timestamps))


class RGBDMapper:
    """Stateful RGB-D mapper (see the module docstring).

    Parameters
    ----------
    options : MapperOptions, optional

    Attributes
    ----------
    volume : TSDFVolume
        The map.
    graph : KeyframeGraph
        Keyframes and edges.
    filter : PoseFilter or None
        The Kalman filter (None before the first frame).
    """

    def __init__(self, options: MapperOptions | None = None):
        self.options = MapperOptions() if options is None else options
        self.volume = TSDFVolume(self.options.tsdf)
        self.graph = KeyframeGraph()
        self.landmark_table = LandmarkTable()
        self.loop_detector = LoopDetector(self.options.loops)
        self.filter = None
        self.frames = []  # FrameRecord per mapped (or predicted) frame
        self._last_time = None
        self._frames_since_keyframe = 0
        self._intrinsics = None

    # ---------------------------------------------------------------------------------------------------------------
    def trajectory(self) -> Trajectory:
        """The poses of every processed frame, corrected by the pose graph (each frame's pose relative to its
        keyframe, composed with the keyframe's current pose).

        Returns
        -------
        Trajectory
        """
        kf = {k.id: k.pose for k in self.graph.keyframes}
        return Trajectory(timestamps=np.array([f.timestamp for f in self.frames], dtype=np.float64),
                          poses=np.array([kf[f.keyframe] @ f.relative for f in self.frames]).reshape(-1, 4, 4),
                          status=[f.status for f in self.frames],
                          indices=np.array([f.index for f in self.frames], dtype=np.int64))

    def predict(self, index: int, timestamp: float | None) -> FrameResult:
        """Account for a frame that could not be used: the filter predicts its pose (recorded as ``'lost'``).

        Raises
        ------
        InputError
            Before the first frame (there is nothing to predict from).
        """
        if self.filter is None:
            raise InputError("no frame has been mapped yet; the first frame must be usable")
        dt = self._interval(timestamp)
        pose = self.filter.predict(dt)
        self._record(index, self._last_time, pose, "lost")
        return FrameResult(index, self._last_time, pose, "lost", None, float("nan"), float("nan"), 0, 0)

    def process(self, frame, *, index: int | None = None) -> FrameResult:
        """Map one RGB-D frame (steps 1-6 of the module docstring).

        Parameters
        ----------
        frame : RGBDFrame
            ``depth`` (H, W) metres with NaN where invalid, ``color`` (H, W, 3) uint8 or None, ``intrinsics``,
            ``timestamp`` (seconds; None: frames are ``default_frame_interval`` apart).
        index : int, optional
            The frame's index, recorded in the results (default: a running count).

        Returns
        -------
        FrameResult

        Raises
        ------
        InputError
            No valid depth (fewer than ``min_valid_fraction`` of the pixels), a depth image whose size differs from
            the first frame's, or a timestamp not after the previous frame's. The mapper's state is unchanged.
        """
        opt = self.options
        index = len(self.frames) if index is None else int(index)
        depth = np.asarray(frame.depth, dtype=np.float32)
        self._check_frame(depth, frame)
        dt = self._check_time(frame.timestamp)
        measurement = measure_frame(depth, frame.intrinsics, opt.tracking)
        features = frame_features(frame.color, depth, frame.intrinsics, opt.features) if opt.use_features else None
        if self.filter is None:
            return self._first_frame(index, frame, depth, measurement, features)
        self._last_time = self._last_time + dt
        predicted = self.filter.predict(dt)
        keyframe = self.graph.keyframes[-1]
        matches, fs, fd = self._match(features, keyframe)
        tracking = self._track(measurement, predicted, fs, fd)
        if not tracking.ok:
            self._record(index, self._last_time, predicted, "lost")
            warnings.warn(f"frame {index}: tracking lost (fitness {tracking.fitness:.2f}, RMSE "
                          f"{tracking.inlier_rmse:.3f} m); its pose is the motion prediction and it is not fused",
                          Seismo3dWarning, stacklevel=2)
            return FrameResult(index, self._last_time, predicted, "lost", None, tracking.fitness,
                               tracking.inlier_rmse, 0, 0)
        status = "relocalised" if tracking.start == "ransac" and self._jumped(tracking.pose, predicted) else "tracked"
        if status == "relocalised":
            self.filter.reset_pose(tracking.pose)
        self.filter.update_pose(tracking.pose, tracking.information)
        n_land = self._update_landmarks(features, keyframe, matches)
        pose = self.filter.pose.copy()
        mask = dynamic_mask(tracking, depth.shape, measurement.scale, opt.tracking.dynamic_dilation)
        self.volume.integrate(depth, frame.intrinsics, pose, mask=mask)
        self._frames_since_keyframe += 1
        kf_id, loops = None, 0
        if is_new_keyframe(pose, keyframe.pose, self._frames_since_keyframe, opt.keyframes):
            kf_id, loops = self._new_keyframe(index, frame, depth, features, matches, tracking, pose)
            pose = self.filter.pose.copy()
        self._record(index, self._last_time, pose, status)
        return FrameResult(index, self._last_time, pose, status, kf_id, tracking.fitness, tracking.inlier_rmse,
                           n_land, loops)

    # ---------------------------------------------------------------------------------------------------------------
    def _check_frame(self, depth, frame):
        if depth.ndim != 2:
            raise InputError(f"depth must be a (H, W) image; got shape {depth.shape}")
        if self._intrinsics is not None and depth.shape != self._shape:
            raise InputError(f"depth image is {depth.shape[1]} x {depth.shape[0]} but the sequence's is "
                             f"{self._shape[1]} x {self._shape[0]}; the frame does not belong to it")
        valid = np.isfinite(depth) & (depth > 0)
        if valid.mean() < self.options.min_valid_fraction:
            raise InputError(f"only {valid.mean():.1%} of the depth pixels are valid (at least "
                             f"{self.options.min_valid_fraction:.0%} are needed); the frame cannot be tracked")

    def _check_time(self, timestamp):
        if self._last_time is None:
            return 0.0
        if timestamp is None:
            return self.options.default_frame_interval
        dt = float(timestamp) - self._last_time
        if not dt > 0:
            raise InputError(f"timestamp {timestamp} is not after the previous frame's ({self._last_time}); frames "
                             "must come in time order")
        if dt > self.options.max_gap:
            warnings.warn(f"a gap of {dt:.2f} s in the timestamps before t = {timestamp:.3f} s; the motion prediction "
                          "is uncertain across it (relocalisation by features takes over if tracking fails)",
                          Seismo3dWarning, stacklevel=3)
        return dt

    def _interval(self, timestamp):
        dt = self._check_time(timestamp)
        self._last_time = self._last_time + dt
        return dt

    def _first_frame(self, index, frame, depth, measurement, features):
        self._intrinsics, self._shape = frame.intrinsics, depth.shape
        self._last_time = 0.0 if frame.timestamp is None else float(frame.timestamp)
        pose = np.eye(4)
        self.filter = PoseFilter(pose, self.options.filter)
        self.volume.integrate(depth, frame.intrinsics, pose)
        self._add_keyframe(index, frame, depth, features, pose)
        self._record(index, self._last_time, pose, "first")
        return FrameResult(index, self._last_time, pose, "first", 0, float("nan"), float("nan"), 0, 0)

    def _match(self, features, keyframe):
        """Matches of the frame to the keyframe and the paired points (frame camera, world)."""
        if features is None or len(features) < 2:
            return None, None, None
        matches = match_to_keyframe(features, keyframe.features, ratio=self.options.features.ratio)
        if len(matches) == 0:
            return matches, None, None
        fs = features.points[matches.frame_index]
        kp = keyframe.features.points[matches.keyframe_index]
        fd = kp @ keyframe.pose[:3, :3].T + keyframe.pose[:3, 3]
        return matches, fs, fd

    def _jumped(self, pose, predicted):
        """True when ``pose`` is farther from the prediction than the map's raycast can be trusted to cover."""
        rel = np.linalg.inv(predicted) @ pose
        angle = np.degrees(np.arccos(np.clip((np.trace(rel[:3, :3]) - 1) / 2, -1, 1)))
        return bool(np.linalg.norm(rel[:3, 3]) > self.options.relocalise_translation
                    or angle > self.options.relocalise_rotation_deg)

    def _track(self, measurement, predicted, fs, fd):
        """Track with the matches the prediction supports (guided matching); when that fails, relocalise with all
        matches: the fused ICP's RANSAC start, then a second raycast at the pose it found."""
        opt = self.options.tracking
        shape = measurement.points[0].shape[:2]
        prediction = self.volume.raycast(measurement.intrinsics[0], predicted, shape=shape)
        guided = None
        if fs is not None:
            near = np.linalg.norm(fs @ predicted[:3, :3].T + predicted[:3, 3] - fd, axis=1) < self.options.guided_radius
            guided = (fs[near], fd[near])
        tracking = track_frame(measurement, prediction, features=guided, options=opt)
        if tracking.ok or fs is None or len(fs) < opt.min_features:
            return tracking
        # relocalisation: the engine's RANSAC over every match gives the camera-to-world pose directly (the fused
        # ICP's start); the map is raycast there and the frame tracked from it
        try:
            start = ransac(fs, fd, model="rigid", threshold=opt.ransac_threshold, max_trials=2000).transform
        except (RegistrationError, InputError):
            return tracking
        again = self.volume.raycast(measurement.intrinsics[0], start, shape=shape)
        second = track_frame(measurement, again, features=(fs, fd), options=opt)
        if second.ok:
            return replace(second, start="ransac")
        return tracking

    def _update_landmarks(self, features, keyframe, matches):
        if matches is None or len(matches) == 0 or self.filter.options.max_landmarks == 0:
            return 0
        ids = self.landmark_table.ids.get(keyframe.id)
        if ids is None:
            return 0
        lid = ids[matches.keyframe_index]
        has = lid >= 0
        if not has.any():
            return 0
        z = features.points[matches.frame_index[has]]
        return self.filter.update_landmarks(lid[has], z, kinect_depth_sigma(z[:, 2]))

    def _add_keyframe(self, index, frame, depth, features, pose):
        feats = features if features is not None else FrameFeatures(np.zeros((0, 2)), np.zeros((0, 32), np.uint8),
                                                                    np.zeros((0, 3)), None)
        depth_mm = np.where(np.isfinite(depth), np.clip(np.rint(depth * 1000.0), 0, 65535), 0).astype(np.uint16)
        kf = Keyframe(id=len(self.graph.keyframes), frame_index=index, timestamp=self._last_time, pose=pose.copy(),
                      features=feats, depth=depth_mm, intrinsics=frame.intrinsics)
        self.graph.add_keyframe(kf)
        self.landmark_table.add_keyframe(kf.id, len(feats))
        self._frames_since_keyframe = 0
        if self.options.use_features and self.options.loop_closure and len(feats):
            self.loop_detector.add(self.graph)
        return kf

    def _new_keyframe(self, index, frame, depth, features, matches, tracking, pose):
        previous = self.graph.keyframes[-1]
        kf = self._add_keyframe(index, frame, depth, features, pose)
        scale = self.filter.options.icp_covariance_scale
        self.graph.add_edge(previous.id, kf.id, np.linalg.inv(previous.pose) @ pose, tracking.information / scale,
                            "odometry")
        if matches is not None and len(matches):
            self._new_landmarks(kf, previous, matches, pose)
        loops = self._close_loops() if self.options.use_features and self.options.loop_closure else 0
        return kf.id, loops

    def _new_landmarks(self, kf, previous, matches, pose):
        cur = kf.features.points[matches.frame_index] @ pose[:3, :3].T + pose[:3, 3]
        old = previous.features.points[matches.keyframe_index] @ previous.pose[:3, :3].T + previous.pose[:3, 3]
        inliers = np.linalg.norm(cur - old, axis=1) < self.options.landmark_gate
        # at most a third of the filter's capacity per keyframe: older landmarks stay long enough to be seen again
        budget = max(1, self.filter.options.max_landmarks // 3)
        for lid, row, is_new in self.landmark_table.link(kf.id, previous.id, matches, inliers):
            if is_new and budget > 0:
                z = kf.features.points[row]
                if self.filter.add_landmark(lid, z, float(kinect_depth_sigma(z[2]))):
                    budget -= 1

    def _close_loops(self):
        accepted = 0
        for candidate, score in self.loop_detector.candidates(self.graph):
            loop = self.loop_detector.verify(self.graph, candidate, score, ratio=self.options.features.ratio)
            if loop is None:
                continue
            scale = self.filter.options.icp_covariance_scale
            self.graph.add_edge(loop.source, loop.target, loop.relative, loop.information / scale, "loop")
            accepted += 1
        if accepted:
            self._optimise()
        return accepted

    def _optimise(self):
        """Optimise the pose graph, move the filter and landmarks with the newest keyframe, re-fuse the map."""
        last = self.graph.keyframes[-1]
        before = last.pose.copy()
        self.graph.optimise()
        correction = last.pose @ np.linalg.inv(before)
        self.filter.pose = correction @ self.filter.pose
        self.filter.transform_landmarks(correction)
        self.volume.reset()
        for k in self.graph.keyframes:
            self.volume.integrate(k.depth_metres(), k.intrinsics, k.pose)

    def _record(self, index, timestamp, pose, status):
        kf = self.graph.keyframes[-1]
        self.frames.append(FrameRecord(int(index), float(timestamp), kf.id, np.linalg.inv(kf.pose) @ pose, status))
