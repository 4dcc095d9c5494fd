"""Fused ICP: visual feature correspondences and dense point-to-plane geometry in one objective (method.md eq. 16)."""

from __future__ import annotations

import numpy as np

from .._options import resolve_options
from .._validation import as_pair, as_weights, check_positive
from ..errors import InputError, RegistrationError
from ..geometry.neighbours import bounding_diagonal
from .icp import NormalisedFrame, dense_stages, prepare_problem, run_icp
from .options import ICPOptions
from .ransac import ransac
from .result import RegistrationResult

__all__ = ["fused_icp"]


def fused_icp(source, target, *, target_normals, source_features, target_features, alpha: float = 0.1,
              model: str = "rigid", init=None, feature_weights=None, ransac_threshold: float | None = None,
              ransac_trials: int = 5000, seed: int = 0, options: ICPOptions | None = None,
              **overrides) -> RegistrationResult:
    """Register ``source`` onto ``target`` by minimising the fused objective of the method's eq. 16.

    .. math::

        E(M) = \\frac{\\alpha}{W} \\frac{1}{|A_f|} \\sum_i w_i |M F_s^i - F_d^i|^2
             + \\frac{1-\\alpha}{W} \\frac{1}{|A_d|} \\sum_j w_j ((M p_j - q_j) \\cdot n_j)^2

    ``A_f`` are the feature matches (``source_features[i]`` <-> ``target_features[i]``, e.g. SIFT or HOG-pyramid
    matches lifted to 3D through depth, or to (trace, sample) points on seismic slices) that RANSAC kept as inliers;
    ``A_d`` are the dense nearest-neighbour correspondences, re-found every iteration within the current maximum
    distance. ``w_i`` are the given feature weights times a robust kernel, ``w_j`` the robust kernel on the plane
    residuals. ``W = alpha mean(w_i) + (1 - alpha) mean(w_j)`` normalises the energy (it scales both terms alike, so
    it changes the reported energy, not the minimiser). Each iteration makes one joint Gauss-Newton step on both
    residual blocks (exact for the affine model).

    Initialisation: ``M_0`` is the RANSAC fit on the feature matches (closed-form minimal solvers). When ``init`` is
    also given (e.g. a motion prediction), the start is whichever of the two has more dense correspondences within
    the first stage's distance.

    Parameters
    ----------
    source : (N, d) array_like, d in {2, 3}
        Dense source points.
    target : (M, d) array_like
        Dense target points.
    target_normals : (M, d) array_like
        Unit target normals.
    source_features, target_features : (K, d) array_like
        Putative feature matches in the same coordinates as the dense points.
    alpha : float in [0, 1]
        Weight of the feature term (0: pure point-to-plane after the RANSAC start; 1: features only).
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
    init : (d+1, d+1) array_like, optional
        A prior transform competing with the RANSAC start.
    feature_weights : (K,) array_like, optional
        Per-match confidence (default ones).
    ransac_threshold : float, optional
        Feature inlier distance in the points' unit (default 2 % of the target's bounding-box diagonal).
    ransac_trials : int
        RANSAC's maximum number of minimal samples.
    seed : int
        RANSAC seed (the result is deterministic given it).
    options : ICPOptions, optional
        The dense loop's distance schedule, point pyramid, iterations, tolerance, kernel, degeneracy threshold and
        correspondence strategy, as in :func:`~seismo3d.registration.icp` (default ``ICPOptions()``).
    **overrides
        Fields of :class:`ICPOptions` by name, replacing those of ``options``.

    Returns
    -------
    RegistrationResult
        As :func:`~seismo3d.registration.icp`; ``info`` adds ``n_feature_inliers``, ``start`` ('ransac' or 'init')
        and ``energy`` (eq. 16 at the result).

    Raises
    ------
    InputError
        Bad shapes or options (alpha outside [0, 1], mismatched feature arrays).
    RegistrationError
        RANSAC found no consensus and no ``init`` was given, or too few dense correspondences.

    References
    ----------
    Vokhmintcev, A., Timchenko, M., method.md eq. 16 (the paper's joint error function).
    Henry, P., Krainin, M., Herbst, E., Ren, X., Fox, D. (2012). RGB-D mapping: Using Kinect-style depth cameras for
    dense 3D modeling of indoor environments. IJRR 31(5), 647-663. doi:10.1177/0278364911434148
    """
    alpha = float(alpha)
    if not 0.0 <= alpha <= 1.0:
        raise InputError(f"alpha must be in [0, 1]; got {alpha}")
    opt = resolve_options(ICPOptions, options, overrides, "fused_icp")
    problem = prepare_problem(source, target, target_normals, "point_to_plane", model, init, opt)
    src, dst, m0, sched = problem.source, problem.target, problem.init, problem.schedule
    fs, fd = as_pair(source_features, target_features, dims=(src.shape[1],),
                     names=("source_features", "target_features"))
    wf = as_weights(feature_weights, len(fs), "feature_weights")
    thr = 0.02 * bounding_diagonal(dst) if ransac_threshold is None else check_positive(ransac_threshold,
                                                                                           "ransac_threshold")
    try:
        rs = ransac(fs, fd, model=model, threshold=thr, max_trials=ransac_trials, seed=seed)
        inliers = rs.info["inliers"]
    except (RegistrationError, InputError) as exc:
        if init is None:
            raise RegistrationError(f"fused ICP could not start: {exc}; pass init= (a prior transform)") from exc
        rs, inliers = None, np.zeros(len(fs), bool)

    frame = NormalisedFrame.of(dst)
    stages = dense_stages(frame, problem, opt.correspondences)
    start, m_start = "init", m0
    if rs is not None:
        start, m_start = "ransac", rs.transform
        if init is not None:
            dmax = sched[0] / frame.scale
            n_ransac = stages[0].correspond(frame.into(rs.transform), dmax)[1].sum()
            n_init = stages[0].correspond(frame.into(m0), dmax)[1].sum()
            if n_init > n_ransac:
                start, m_start = "init", m0
    features = None
    if inliers.any():
        fscale = thr / frame.scale
        features = (frame.points(fs[inliers]), frame.points(fd[inliers]), wf[inliers], fscale)
    result = run_icp(stages, sched, frame, m_start, method="point_to_plane", model=model, options=opt,
                     features=features, alpha=alpha if features else 0.0)
    info = dict(result.info, n_feature_inliers=int(inliers.sum()), start=start,
                energy=_energy(result.transform, src, stages[-1], frame, sched[-1], fs[inliers], fd[inliers],
                               wf[inliers], alpha))
    return RegistrationResult(transform=result.transform, fitness=result.fitness, inlier_rmse=result.inlier_rmse,
                              n_iterations=result.n_iterations, converged=result.converged,
                              min_eigenvalue=result.min_eigenvalue, degenerate=result.degenerate, info=info)


def _energy(transform, src, stage, frame, dist_max, fs, fd, wf, alpha):
    """Eq. 16 at ``transform`` (unit robust weights), in the points' squared unit."""
    m = frame.into(transform)
    d = m.shape[0] - 1
    _, ok, idx, _ = stage.correspond(m, dist_max / frame.scale)
    p = stage.src[ok]
    r_d = np.einsum("ij,ij->i", stage.nrm[idx], p @ m[:d, :d].T + m[:d, d] - stage.dst[idx]) * frame.scale
    e_d = float(np.mean(r_d**2)) if len(r_d) else 0.0
    e_f = 0.0
    if len(fs):
        r_f = fs @ transform[:d, :d].T + transform[:d, d] - fd
        e_f = float(np.sum(wf * np.einsum("ij,ij->i", r_f, r_f)) / len(fs))
    big_w = alpha * (float(wf.mean()) if len(wf) else 0.0) + (1 - alpha) * 1.0
    return (alpha * e_f + (1 - alpha) * e_d) / big_w

