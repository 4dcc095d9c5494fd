"""The ICP family: point-to-point and point-to-plane ICP for every model, its engine pieces, and the Fast ICP baseline.

Point-to-point and point-to-plane for rigid, similarity, axis-scaled and affine models, the fused
objective's dense loop, and the "Fast ICP" baseline of the paper's Table 1 (method.md section 1).

All iterations run in a normalised frame (target centroid at the origin, unit RMS radius) so that rotation, scale and
translation updates are commensurate; distances given by the caller are converted into it and results back out.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .._options import resolve_options
from .._validation import as_normals, as_points, check_choice
from ..errors import DegenerateGeometryWarning, InputError, RegistrationError
from ..geometry.neighbours import bounding_diagonal, median_spacing, voxel_downsample
from ..geometry.transforms import as_transform, check_model, make_transform
from . import _solver
from .closed_form import fit_weighted, min_points
from .correspondences import as_correspondences
from .kernels import robust_weights
from .options import ICPOptions
from .result import RegistrationResult

__all__ = ["icp", "fast_icp", "default_distance_schedule", "ICPProblem", "NormalisedFrame", "DenseStage",
           "prepare_problem", "dense_stages", "run_icp"]

METHODS = ("point_to_point", "point_to_plane")


def default_distance_schedule(target, *, fractions=(0.1, 0.03, 0.01), spacing_factor: float = 3.0) -> tuple:
    """The coarse-to-fine maximum correspondence distances used when none are given.

    Each stage is a fraction of the target's bounding-box diagonal, but never below ``spacing_factor`` times the
    target's median point spacing (closer than that, correspondences are sampling noise).

    Parameters
    ----------
    target : (N, d) array_like
        Target points.
    fractions : sequence of float
        Fractions of the bounding-box diagonal, coarse to fine.
    spacing_factor : float
        Floor in units of the median nearest-neighbour spacing.

    Returns
    -------
    tuple of float
        Decreasing distances in the points' unit (duplicates removed).
    """
    diag = bounding_diagonal(target)
    floor = spacing_factor * median_spacing(target)
    out = []
    for f in fractions:
        v = max(f * diag, floor)
        if not out or v < out[-1] * 0.999:
            out.append(v)
    return tuple(out)


@dataclass(frozen=True)
class NormalisedFrame:
    """The normalising similarity ``N: p -> (p - centre) / scale`` in which ICP iterates (target centroid at the
    origin, unit RMS radius), so that rotation, scale and translation updates are commensurate.

    Attributes
    ----------
    centre : (d,) float64 ndarray
        The target's centroid.
    scale : float
        The target's RMS distance from it (1 when it is 0).
    """

    centre: np.ndarray
    scale: float

    @classmethod
    def of(cls, points):
        """The frame of ``points`` ((M, d) float64 ndarray)."""
        c = points.mean(axis=0)
        s = float(np.sqrt(np.mean(np.einsum("ij,ij->i", points - c, points - c))))
        return cls(c, s if s > 0 else 1.0)

    def points(self, p):
        """``p`` ((n, d) ndarray) in the frame."""
        return (p - self.centre) / self.scale

    def matrix(self):
        """N as a (d+1, d+1) homogeneous matrix."""
        d = len(self.centre)
        return make_transform(np.eye(d) / self.scale, -self.centre / self.scale)

    def inverse(self):
        """N^-1 as a (d+1, d+1) homogeneous matrix."""
        d = len(self.centre)
        return make_transform(np.eye(d) * self.scale, self.centre)

    def into(self, transform):
        """A transform between points' coordinates, as it acts in the frame."""
        return self.matrix() @ transform @ self.inverse()

    def out_of(self, transform):
        """A transform acting in the frame, back between the points' coordinates."""
        return self.inverse() @ transform @ self.matrix()


@dataclass(frozen=True, eq=False)
class ICPProblem:
    """A checked registration problem: what :func:`prepare_problem` returns.

    Attributes
    ----------
    source : (N, d) float64 ndarray
    target : (M, d) float64 ndarray
    target_normals : (M, d) float64 ndarray or None
        Unit normals (point-to-plane only).
    init : (d+1, d+1) float64 ndarray
        The initial transform.
    schedule : tuple of float
        Maximum correspondence distance of each stage, coarse to fine, in the points' unit.
    voxels : tuple of (float or None, float or None)
        Per stage, the source and target voxel sizes (None: not downsampled).
    """

    source: np.ndarray
    target: np.ndarray
    target_normals: np.ndarray | None
    init: np.ndarray
    schedule: tuple
    voxels: tuple


def prepare_problem(source, target, target_normals, method: str, model: str, init,
                    options: ICPOptions) -> ICPProblem:
    """Check the inputs of an ICP and resolve its distance schedule and point pyramid.

    Parameters
    ----------
    source : (N, d) array_like, d in {2, 3}
    target : (M, d) array_like
    target_normals : (M, d) array_like or None
        Required for point-to-plane.
    method : {'point_to_plane', 'point_to_point'}
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
    init : (d+1, d+1) array_like or None
    options : ICPOptions

    Returns
    -------
    ICPProblem

    Raises
    ------
    InputError
        Bad shapes, NaNs, mismatched dimensions, too few points for the model, missing normals, unknown options.
    """
    check_choice(method, "method", METHODS)
    check_model(model)
    src = as_points(source, "source")
    dst = as_points(target, "target")
    d = src.shape[1]
    if dst.shape[1] != d:
        raise InputError(f"source is {d}D but target is {dst.shape[1]}D; both must have the same dimension")
    need = _needed(method, model, d)
    for name, pts in (("source", src), ("target", dst)):
        if len(pts) < need:
            raise InputError(f"{method} ICP with a {model} model in {d}D needs at least {need} {name} points; "
                             f"got {len(pts)}")
    nrm = None
    if method == "point_to_plane":
        if target_normals is None:
            raise InputError("point-to-plane needs target_normals; compute them with "
                             "seismo3d.geometry.estimate_normals(target)")
        nrm = as_normals(target_normals, "target_normals", dst.shape, of="target point")
    m0 = np.eye(d + 1) if init is None else as_transform(init, "init", dims=(d,))
    sched = default_distance_schedule(dst) if options.max_distance is None else options.max_distance
    if options.voxel_size is None:
        # Default point pyramid: coarse stages see the source at voxel = stage distance / 8, the last stage all of it;
        # the target (and its KD-tree) stays at full resolution.
        voxels = tuple((v / 8.0, None) for v in sched[:-1]) + ((None, None),)
    else:
        sizes = options.voxel_size
        if len(sizes) == 1:
            sizes = sizes * len(sched)
        if len(sizes) != len(sched):
            raise InputError(f"voxel_size has {len(sizes)} entries but the distance schedule has {len(sched)}; "
                             "give one voxel size per stage or a single one")
        voxels = tuple((v, v) for v in sizes)
    return ICPProblem(src, dst, nrm, m0, sched, voxels)


class DenseStage:
    """One stage of the schedule: source and target (each optionally voxel-downsampled) in the normalised frame,
    with the target's correspondence index (a KD-tree, or a projective pixel map: see
    :mod:`~seismo3d.registration.correspondences`).

    Parameters
    ----------
    frame : NormalisedFrame
    src : (n, d) float64 ndarray
        Source points (points' coordinates).
    target : tuple
        ``(points, normals or None, index)`` of the target, already in the frame; ``index`` is what a correspondence
        strategy's ``index()`` returns (``index.query(moved, dmax) -> (dist, idx)``).
    """

    def __init__(self, frame, src, target):
        self.src = frame.points(src)
        self.dst, self.nrm, self.index = target

    def query(self, transform, dmax):
        """The moved source and, for every source point, its correspondence within ``dmax`` (frame units) by the
        stage's index: (moved source (n, d), distances (n,) ``inf`` where none, target rows (n,) ``len(dst)`` where
        none)."""
        moved = _solver.moved_points(self.src, transform)
        dist, idx = self.index.query(moved, dmax)
        return moved, dist, idx

    def correspond(self, transform, dmax):
        """Correspondences of the moved source within ``dmax`` (frame units) by the stage's index: (moved source,
        mask of the source points with one, target indices, distances)."""
        moved, dist, idx = self.query(transform, dmax)
        ok = np.isfinite(dist)
        return moved, ok, idx[ok], dist[ok]


def dense_stages(frame: NormalisedFrame, problem: ICPProblem, correspondences=None) -> list:
    """One :class:`DenseStage` per stage of ``problem``'s schedule; downsampled sources and target indices (KD-trees
    or projective pixel maps) are shared between stages.

    Parameters
    ----------
    frame : NormalisedFrame
        Usually ``NormalisedFrame.of(problem.target)``.
    problem : ICPProblem
    correspondences : NearestNeighbourCorrespondences or ProjectiveCorrespondences, optional
        How each stage finds correspondences (usually ``ICPOptions.correspondences``; None: nearest neighbours by a
        KD-tree).

    Returns
    -------
    list of DenseStage

    Raises
    ------
    InputError
        ``correspondences`` is not a strategy, or a projective strategy is given a voxel-downsampled target.
    """
    strategy = as_correspondences(correspondences)
    src, dst, nrm, voxels = problem.source, problem.target, problem.target_normals, problem.voxels
    sources, targets, out = {}, {}, []
    for src_voxel, dst_voxel in voxels:
        if src_voxel not in sources:
            sources[src_voxel] = src if src_voxel is None else voxel_downsample(src, src_voxel)[0]
        if dst_voxel not in targets:
            pts, nv = dst, nrm
            if dst_voxel is not None:
                pts, nv = voxel_downsample(dst, dst_voxel, values=nrm)
                if nv is not None:
                    nv = nv / np.maximum(np.linalg.norm(nv, axis=1, keepdims=True), 1e-300)
            pts = frame.points(pts)
            targets[dst_voxel] = (pts, nv, strategy.index(pts, centre=frame.centre, scale=frame.scale))
        out.append(DenseStage(frame, sources[src_voxel], targets[dst_voxel]))
    return out


def _needed(method, model, d):
    return min_points(model, d) if method == "point_to_point" else _solver.n_params(model, d)


def run_icp(stages, sched, frame, m0, *, method: str, model: str, options: ICPOptions, features=None,
            alpha: float = 0.0) -> RegistrationResult:
    """The ICP loop over the distance schedule (method.md eqs. 1-15; with ``features``, eq. 16).

    Parameters
    ----------
    stages : list of DenseStage
        From :func:`dense_stages`.
    sched : tuple of float
        The stages' maximum correspondence distances, points' unit.
    frame : NormalisedFrame
    m0 : (d+1, d+1) ndarray
        Start, points' coordinates.
    method : {'point_to_plane', 'point_to_point'}
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
    options : ICPOptions
        Iterations, tolerance, kernel and degeneracy threshold (the schedule is ``sched``).
    features : tuple, optional
        ``(fs, fd, wf, feature_scale)``: feature matches in the frame, their weights and the kernel scale of the
        feature term (eq. 16's first term).
    alpha : float
        Weight of the feature term.

    Returns
    -------
    RegistrationResult

    Raises
    ------
    RegistrationError
        Too few correspondences within a stage's distance.

    Warns
    -----
    DegenerateGeometryWarning
        The final normal matrix is (near) singular.
    """
    max_iterations, tolerance = options.max_iterations, options.tolerance
    kernel, kernel_scale, degeneracy_threshold = options.kernel, options.kernel_scale, options.degeneracy_threshold
    m = frame.into(m0)
    d = m.shape[0] - 1
    need = _needed(method, model, d)
    total_iters, converged, h = 0, False, None
    per_stage = []
    for stage, dist_max in zip(stages, sched):
        dmax = dist_max / frame.scale
        stage_tol = tolerance * dist_max / sched[-1]  # coarse stages need only converge to their own scale
        scale = (dmax / 3.0) if kernel_scale is None else kernel_scale / frame.scale
        converged = False
        it = 0
        for it in range(1, max_iterations + 1):
            moved, dist, idx = stage.query(m, dmax)
            queried = m
            ok = np.isfinite(dist)
            n_ok = int(ok.sum())
            if n_ok < need:
                raise RegistrationError(
                    f"only {n_ok} source points have a target point within max_distance={dist_max:g}; "
                    f"at least {need} are needed: raise max_distance or pass a better init"
                )
            if method == "point_to_point":
                w = robust_weights(dist[ok], kernel, scale)
                new = fit_weighted(stage.src[ok], stage.dst[idx[ok]], np.maximum(w, 1e-12), model)
                step = np.abs(new - m).max()
                m = new
            else:
                wd = (1.0 - alpha) / n_ok  # (1 - alpha) / |A_d|  (eq. 16; W scales both terms alike)
                h, g = _plane_system(stage, moved, idx, m, model, kernel, scale, wd)
                if features is not None and alpha > 0:
                    fs, fd, wf, fscale = features
                    res = fs @ m[:d, :d].T + m[:d, d] - fd
                    rw = wf * robust_weights(np.linalg.norm(res, axis=1), kernel, fscale)
                    hf, gf = _solver.normal_matrix([(np.repeat(fs, d, 0), _solver.axis_directions(len(fs), d),
                                                     np.repeat(fd, d, 0), np.repeat(rw, d), alpha / len(fs))],
                                                   model, m)
                    h, g = h + hf, g + gf
                delta = _solver.solve_step(h, g)
                m = _solver.apply_update(model, m, delta)
                step = float(np.abs(delta).max())
            if step < stage_tol:
                converged = True
                break
        total_iters += it
        per_stage.append(it)
    # Final statistics at the last stage's distance: of the last iteration's correspondences when that stage
    # converged (the transform has since moved by less than the tolerance), else re-found with the final transform.
    stage, dmax = stages[-1], sched[-1] / frame.scale
    if not converged:
        queried = m
        moved, dist, idx = stage.query(m, dmax)
    ok = np.isfinite(dist)
    fitness = float(ok.mean())
    rmse = float(np.sqrt(np.mean(dist[ok] ** 2)) * frame.scale) if ok.any() else float("inf")
    if method == "point_to_plane":
        h, _ = _plane_system(stage, moved, idx, queried, model, "none", 1.0, 1.0)
    else:
        p, q = stage.src[ok], stage.dst[idx[ok]]
        h, _ = _solver.normal_matrix([(np.repeat(p, d, 0), _solver.axis_directions(len(p), d), np.repeat(q, d, 0),
                                       np.ones(len(p) * d), 1.0)], model, queried)
    lo, hi = _solver.eigen_range(h, float(ok.sum()))
    degenerate = hi <= 0 or lo / hi < degeneracy_threshold
    if degenerate:
        warnings.warn(
            f"the geometry does not constrain every degree of freedom of the {model} transform (smallest/largest "
            f"eigenvalue of the normal matrix {lo:.2e}/{hi:.2e}); the result is not unique along that direction, "
            "e.g. a plane can slide in itself: add features (fused_icp) or constrain the model",
            DegenerateGeometryWarning, stacklevel=3,
        )
    return RegistrationResult(
        transform=frame.out_of(m), fitness=fitness, inlier_rmse=rmse, n_iterations=total_iters,
        converged=bool(converged and not degenerate), min_eigenvalue=lo, degenerate=bool(degenerate),
        info={"iterations_per_stage": per_stage, "max_distance": tuple(sched), "eigenvalue_ratio": lo / hi if hi else 0.0,
              "tolerance_met": bool(converged)},
    )


def _plane_system(stage, moved, idx, m, model, kernel, scale, factor):
    """Point-to-plane normal equations (H, g) of a stage's correspondences (``idx``: target row per source point,
    ``len(stage.dst)`` where none), each residual weighted by ``factor`` times the robust kernel: one compiled pass
    for the rigid 3D model, numpy over the gathered pairs for the others."""
    d = m.shape[0] - 1
    if model == "rigid" and d == 3:
        h, g, _ = _solver.plane_system_rigid3(moved, m[:d, d], stage.dst, stage.nrm, idx, kernel, scale, factor)
        return h, g
    ok = idx < len(stage.dst)
    p, j = stage.src[ok], idx[ok]
    n, q = stage.nrm[j], stage.dst[j]
    w = robust_weights(np.einsum("ij,ij->i", n, moved[ok] - q), kernel, scale)
    return _solver.normal_matrix([(p, n, q, w, factor)], model, m)


def icp(source, target, *, method: str = "point_to_plane", model: str = "rigid", target_normals=None, init=None,
        options: ICPOptions | None = None, **overrides) -> RegistrationResult:
    """Iterative closest point registration of ``source`` onto ``target``, in 2D or 3D.

    Each iteration finds, for every (transformed) source point, its nearest target point within the current maximum
    correspondence distance (exact, by a hashed voxel grid: :mod:`~seismo3d.geometry.voxel_hash`; with ``correspondences=ProjectiveCorrespondences``
    the target point its projection lands on in an organised target), weights the pairs with a robust kernel and
    updates the transform: in closed form for point-to-point (Kabsch / Umeyama / eqs. 1-9 / affine least squares),
    by one Gauss-Newton step for point-to-plane (exact for the affine model, eqs. 11-15; on SE(d) with the exponential
    map for the rigid one). Stages of a coarse-to-fine distance schedule run one after another, each until the update is
    below the tolerance or the iteration limit is reached (:class:`ICPOptions`).

    Parameters
    ----------
    source : (N, d) array_like, d in {2, 3}
        Points to move.
    target : (M, d) array_like
        Points to align to.
    method : {'point_to_plane', 'point_to_point'}
        Residual: distance to the target's tangent plane (line in 2D) or to the target point.
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
        Transform family (see :mod:`seismo3d.geometry.transforms`).
    target_normals : (M, d) array_like, optional
        Unit normals of the target (required for point-to-plane; their sign does not matter).
    init : (d+1, d+1) array_like, optional
        Initial source-to-target transform (default identity).
    options : ICPOptions, optional
        Distance schedule, point pyramid, iterations, tolerance, robust kernel, degeneracy threshold, correspondence
        strategy (default ``ICPOptions()``).
    **overrides
        Fields of :class:`ICPOptions` by name (``max_distance``, ``voxel_size``, ``max_iterations``, ``tolerance``,
        ``kernel``, ``kernel_scale``, ``degeneracy_threshold``, ``correspondences``), replacing those of ``options``.

    Returns
    -------
    RegistrationResult
        Transform (source to target), fitness, inlier RMSE (Euclidean), iterations, converged, smallest
        eigenvalue and degeneracy flag.

    Raises
    ------
    InputError
        Bad shapes, NaNs, mismatched dimensions, missing normals, unknown options.
    RegistrationError
        Too few correspondences within the maximum distance for the model.

    Warns
    -----
    DegenerateGeometryWarning
        When the data does not constrain every degree of freedom (the result then has ``converged=False``).

    References
    ----------
    Besl, P. J., McKay, N. D. (1992). A method for registration of 3-D shapes. IEEE TPAMI 14(2), 239-256.
    Chen, Y., Medioni, G. (1991). Object modeling by registration of multiple range images. ICRA, 2724-2729.
    Low, K.-L. (2004). Linear least-squares optimization for point-to-plane ICP surface registration. TR04-004, UNC.
    Vokhmintcev, A., Timchenko, M. (method.md), eqs. 1-15.
    """
    opt = resolve_options(ICPOptions, options, overrides, "icp")
    problem = prepare_problem(source, target, target_normals, method, model, init, opt)
    frame = NormalisedFrame.of(problem.target)
    stages = dense_stages(frame, problem, opt.correspondences)
    return run_icp(stages, problem.schedule, frame, problem.init, method=method, model=model, options=opt)


def fast_icp(source, target, *, n_samples: int = 2000, init=None, max_distance=None, max_iterations: int = 30,
             tolerance: float = 1e-4, seed: int = 0) -> RegistrationResult:
    """The "Fast ICP" baseline of the paper's Table 1: rigid point-to-point ICP on a random subset of the source.

    Parameters
    ----------
    source : (N, d) array_like
    target : (M, d) array_like
    n_samples : int
        Source points kept (uniform random subset, fixed by ``seed``).
    init, max_distance, max_iterations, tolerance
        As in :func:`icp`; the default distance is a single stage of 5 % of the target's bounding-box diagonal.
    seed : int
        Seed of the subset.

    Returns
    -------
    RegistrationResult

    References
    ----------
    Rusinkiewicz, S., Levoy, M. (2001). Efficient variants of the ICP algorithm. 3DIM, 145-152.
    doi:10.1109/IM.2001.924423
    """
    src = as_points(source, "source")
    if len(src) > n_samples:
        src = src[np.random.default_rng(seed).choice(len(src), int(n_samples), replace=False)]
    if max_distance is None:
        max_distance = 0.05 * bounding_diagonal(target)
    return icp(src, target, method="point_to_point", model="rigid", init=init,
               options=ICPOptions(max_distance=max_distance, max_iterations=max_iterations, tolerance=tolerance,
                                  kernel="none"))
