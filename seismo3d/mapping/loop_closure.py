"""Loop closure: place recognition over keyframes by a bag of visual words, verified by the fused ICP.

Place recognition (Sivic and Zisserman 2003; Galvez-Lopez and Tardos 2012): keyframe descriptors are quantised into
visual words of a vocabulary learned by k-means once enough keyframes exist (binary descriptors are unpacked to
0/1 vectors, on which the squared Euclidean distance is the Hamming distance); each keyframe becomes a tf-idf vector,
and a new keyframe's candidates are earlier keyframes outside a recent window whose cosine similarity beats both an
absolute floor and a fraction of its similarity to the previous keyframe (ORB-SLAM's covisibility-relative score).
A candidate is verified geometrically: the two keyframes' features are matched and the engine's fused ICP
(RANSAC start on the lifted matches, then dense point-to-plane on the depth clouds) registers them; the loop is
accepted when enough features agree and the dense fit is tight.

References
----------
Sivic, J., Zisserman, A. (2003). Video Google: a text retrieval approach to object matching in videos. ICCV,
1470-1477. doi:10.1109/ICCV.2003.1238663
Galvez-Lopez, D., Tardos, J. D. (2012). Bags of binary words for fast place recognition in image sequences. IEEE T-RO
28(5), 1188-1197. doi:10.1109/TRO.2012.2197158
Mur-Artal, R., Tardos, J. D. (2014). Fast relocalisation and loop closing in keyframe-based SLAM. ICRA, 846-853.
doi:10.1109/ICRA.2014.6906953
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

from .._validation import check_positive
from ..errors import DegenerateGeometryWarning, InputError, RegistrationError
from ..registration import ICPOptions, fused_icp, ransac
from .frames import frame_points
from .landmarks import match_to_keyframe
from .odometry import point_to_plane_information

__all__ = ["LoopOptions", "LoopClosure", "Vocabulary", "LoopDetector"]


@dataclass(frozen=True)
class LoopOptions:
    """Options of place recognition and loop verification.

    Attributes
    ----------
    n_words : int
        Visual words of the vocabulary.
    vocabulary_keyframes : int
        Keyframes whose descriptors train the vocabulary (it is learned once, when that many exist).
    recent_window : int
        The last this many keyframes are never loop candidates (they are odometry neighbours).
    min_score : float
        Absolute floor of the cosine similarity of a candidate.
    relative_score : float
        A candidate's similarity must reach this fraction of the similarity to the previous keyframe.
    max_candidates : int
        Best-scoring candidates verified per keyframe.
    min_feature_inliers : int
        Feature matches the verification's RANSAC must keep.
    min_fitness : float
        Fraction of the dense points with a correspondence within ``max_rmse`` at the verified pose.
    max_rmse : float
        Inlier RMSE of the verified registration, metres.
    voxel_size : float
        Voxel of the depth clouds registered in verification, metres.
    """

    n_words: int = 256
    vocabulary_keyframes: int = 5
    recent_window: int = 4
    min_score: float = 0.05
    relative_score: float = 0.6
    max_candidates: int = 2
    min_feature_inliers: int = 20
    min_fitness: float = 0.4
    max_rmse: float = 0.02
    voxel_size: float = 0.02

    def __post_init__(self):
        if int(self.n_words) < 2:
            raise InputError(f"n_words must be >= 2; got {self.n_words!r}")
        check_positive(self.max_rmse, "max_rmse")
        check_positive(self.voxel_size, "voxel_size")


@dataclass(frozen=True)
class LoopClosure:
    """A verified loop: ``relative = inv(pose[source]) @ pose[target]`` measured by the fused ICP.

    Attributes
    ----------
    source, target : int
        Keyframe ids (``source`` the earlier one).
    relative : (4, 4) float64 ndarray
    information : (6, 6) float64 ndarray
    score : float
        Bag-of-words similarity.
    fitness, inlier_rmse : float
        Of the verifying registration.
    n_feature_inliers : int
    """

    source: int
    target: int
    relative: np.ndarray
    information: np.ndarray
    score: float
    fitness: float
    inlier_rmse: float
    n_feature_inliers: int


def _as_vectors(descriptors):
    d = np.asarray(descriptors)
    if d.dtype == np.uint8:
        return np.unpackbits(d, axis=1).astype(np.float32)
    return d.astype(np.float32)


@dataclass
class Vocabulary:
    """Visual words (k-means centres) and their inverse document frequencies."""

    centres: np.ndarray
    idf: np.ndarray = field(default=None)

    @classmethod
    def learn(cls, descriptor_sets, n_words: int, *, seed: int = 0) -> Vocabulary:
        """k-means (OpenCV, k-means++ seeding) over the stacked descriptors; idf from the sets as documents.

        Raises
        ------
        InputError
            Fewer descriptors than words.
        """
        import cv2

        data = np.vstack([_as_vectors(d) for d in descriptor_sets if len(d)])
        k = int(min(n_words, len(data) // 4))
        if k < 2:
            raise InputError(f"{len(data)} descriptors are too few to learn a vocabulary of {n_words} words")
        cv2.setRNGSeed(seed)
        criteria = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 20, 1e-3)
        _, _, centres = cv2.kmeans(data, k, None, criteria, 1, cv2.KMEANS_PP_CENTERS)
        vocab = cls(centres.astype(np.float32))
        df = np.zeros(k)
        for d in descriptor_sets:
            if len(d):
                df[np.unique(vocab.words(d))] += 1
        vocab.idf = np.log((len(descriptor_sets) + 1.0) / (df + 1.0)) + 1.0
        return vocab

    def words(self, descriptors) -> np.ndarray:
        """(N,) int64 word of each descriptor (nearest centre)."""
        x = _as_vectors(descriptors)
        d2 = (x * x).sum(1)[:, None] - 2.0 * x @ self.centres.T + (self.centres * self.centres).sum(1)[None, :]
        return np.argmin(d2, axis=1).astype(np.int64)

    def vector(self, descriptors) -> dict:
        """L2-normalised tf-idf vector as ``{word: weight}``."""
        if len(descriptors) == 0:
            return {}
        w = self.words(descriptors)
        counts = np.bincount(w, minlength=len(self.centres)).astype(np.float64)
        v = counts / counts.sum() * self.idf
        nz = np.nonzero(v)[0]
        norm = np.linalg.norm(v[nz])
        return {int(i): float(v[i] / norm) for i in nz}


def _cloud(keyframe, voxel_size):
    """The keyframe's depth as a voxel-downsampled cloud with normals, computed once and kept on the keyframe."""
    cached = keyframe.cache.get(("cloud", voxel_size))
    if cached is None:
        cached = keyframe.cache[("cloud", voxel_size)] = frame_points(keyframe.depth_metres(), keyframe.intrinsics,
                                                                      voxel_size=voxel_size)
    return cached


def _similarity(a: dict, b: dict) -> float:
    if len(a) > len(b):
        a, b = b, a
    return float(sum(w * b.get(k, 0.0) for k, w in a.items()))


class LoopDetector:
    """Bag-of-words place recognition over the keyframes of a :class:`~seismo3d.mapping.keyframes.KeyframeGraph`,
    with fused-ICP verification."""

    def __init__(self, options: LoopOptions | None = None):
        self.options = LoopOptions() if options is None else options
        self.vocabulary = None

    def add(self, graph) -> None:
        """Give the graph's newest keyframe its bag-of-words vector (learning the vocabulary when due)."""
        opt = self.options
        if self.vocabulary is None and len(graph.keyframes) >= opt.vocabulary_keyframes:
            sets = [k.features.descriptors for k in graph.keyframes]
            try:
                self.vocabulary = Vocabulary.learn(sets, opt.n_words)
            except InputError:
                return
            for k in graph.keyframes:
                k.bow = self.vocabulary.vector(k.features.descriptors)
            return
        if self.vocabulary is not None:
            kf = graph.keyframes[-1]
            kf.bow = self.vocabulary.vector(kf.features.descriptors)

    def candidates(self, graph) -> list:
        """(keyframe id, score) of the newest keyframe's loop candidates, best first."""
        opt = self.options
        if self.vocabulary is None or len(graph.keyframes) <= opt.recent_window + 1:
            return []
        query = graph.keyframes[-1]
        reference = _similarity(query.bow, graph.keyframes[-2].bow)
        floor = max(opt.min_score, opt.relative_score * reference)
        scored = [(k.id, _similarity(query.bow, k.bow)) for k in graph.keyframes[: -opt.recent_window - 1]]
        scored = [(i, s) for i, s in scored if s >= floor]
        scored.sort(key=lambda x: -x[1])
        return scored[: opt.max_candidates]

    def verify(self, graph, candidate: int, score: float, *, ratio: float = 0.8):
        """Register the newest keyframe onto a candidate with the fused ICP; a :class:`LoopClosure` or None.

        The fused ICP starts from the RANSAC fit of the matched features (no pose prior: the drift may be large).
        """

        opt = self.options
        new, old = graph.keyframes[-1], graph.keyframes[candidate]
        matches = match_to_keyframe(new.features, old.features, ratio=ratio)
        if len(matches) < opt.min_feature_inliers:
            return None
        fs = new.features.points[matches.frame_index]
        fd = old.features.points[matches.keyframe_index]
        # a cheap consensus test on the features alone rejects most false candidates before the dense registration
        try:
            ransac(fs, fd, model="rigid", threshold=0.05, max_trials=1000, min_inliers=opt.min_feature_inliers)
        except (RegistrationError, InputError):
            return None
        src, _ = _cloud(new, opt.voxel_size)
        dst, nrm = _cloud(old, opt.voxel_size)
        if len(src) < 100 or len(dst) < 100:
            return None
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DegenerateGeometryWarning)
                res = fused_icp(src, dst, target_normals=nrm, source_features=fs, target_features=fd,
                                ransac_threshold=0.05, options=ICPOptions(max_distance=(0.1, 0.04, 0.02)))
        except RegistrationError:
            return None
        if res.info.get("n_feature_inliers", 0) < opt.min_feature_inliers or res.fitness < opt.min_fitness \
                or res.inlier_rmse > opt.max_rmse or res.degenerate:
            return None
        # information of the loop edge from the dense correspondences at the solution (KD-tree)
        moved = src @ res.transform[:3, :3].T + res.transform[:3, 3]
        dist, idx = cKDTree(dst).query(moved, distance_upper_bound=opt.max_rmse * 2)
        ok = np.isfinite(dist)
        info = point_to_plane_information(src[ok], res.transform, dst[idx[ok]], nrm[idx[ok]],
                                          sigma=max(res.inlier_rmse, 1e-3))
        # res.transform maps the new keyframe's camera into the old one's: inv(pose_old) @ pose_new
        return LoopClosure(source=old.id, target=new.id, relative=res.transform, information=info, score=score,
                           fitness=res.fitness, inlier_rmse=res.inlier_rmse,
                           n_feature_inliers=int(res.info.get("n_feature_inliers", 0)))
