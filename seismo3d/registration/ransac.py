"""RANSAC over putative point matches with the closed-form fits as minimal solvers (method.md section 1)."""

from __future__ import annotations

import numpy as np

from .._validation import as_pair, check_positive
from ..errors import InputError, RegistrationError
from ..geometry.transforms import check_model, make_transform, nearest_rotation
from .closed_form import fit_weighted, min_points
from .result import RegistrationResult

__all__ = ["ransac"]


def ransac(source, target, *, model: str = "rigid", threshold: float, max_trials: int = 5000,
           confidence: float = 0.999, min_inliers: int | None = None, seed: int = 0) -> RegistrationResult:
    """Robustly fit a transform to putative matches that contain outliers.

    Minimal samples of :func:`~seismo3d.registration.min_points` matches (d for rigid / similarity, d + 1 for
    axis-scaled / affine) are fitted in closed form, all in one batch (batched SVD / solve); a hypothesis scores the
    number of matches whose residual ``|M x_i - y_i|`` is below ``threshold``. The best hypothesis is refitted on its
    inliers with the weighted closed form (local optimisation), twice. Trials stop early once the standard bound
    ``log(1 - confidence) / log(1 - inlier_ratio^m)`` is reached. Deterministic for a given ``seed``.

    Parameters
    ----------
    source, target : (N, d) array_like, d in {2, 3}
        Putative matches, row i of ``source`` matched to row i of ``target``.
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
        Transform family.
    threshold : float
        Inlier distance, in the points' unit.
    max_trials : int
        Upper bound on the number of minimal samples.
    confidence : float
        Probability of drawing at least one all-inlier sample, for early stopping.
    min_inliers : int, optional
        Fewest inliers accepted (default: the minimal sample size plus 3).
    seed : int
        Seed of the sampler.

    Returns
    -------
    RegistrationResult
        ``fitness`` = inlier fraction, ``inlier_rmse`` over inliers, ``n_iterations`` = trials drawn,
        ``info['inliers']`` the (N,) bool inlier mask.

    Raises
    ------
    InputError
        Bad input or fewer matches than the minimal sample.
    RegistrationError
        No hypothesis reached ``min_inliers``.

    References
    ----------
    Fischler, M. A., Bolles, R. C. (1981). Random sample consensus. Comm. ACM 24(6), 381-395. doi:10.1145/358669.358692
    Chum, O., Matas, J., Kittler, J. (2003). Locally optimized RANSAC. DAGM, LNCS 2781, 236-243.
    """
    check_model(model)
    src, dst = as_pair(source, target)
    thr = check_positive(threshold, "threshold")
    n, d = src.shape
    m = min_points(model, d)
    if n < m:
        raise InputError(f"RANSAC for a {model} model in {d}D needs at least {m} matches; got {n}")
    min_inliers = m + 3 if min_inliers is None else int(min_inliers)
    rng = np.random.default_rng(seed)

    best_count, best = -1, None
    drawn, needed, batch = 0, max_trials, 256
    while drawn < min(needed, max_trials):
        size = int(min(batch, max_trials - drawn))
        idx = np.argsort(rng.random((size, n)), axis=1)[:, :m]  # m distinct matches per trial
        drawn += size
        hyps = _minimal_fits(src[idx], dst[idx], model)
        if hyps is None:
            continue
        pred = np.einsum("tij,nj->tni", hyps[:, :d, :d], src) + hyps[:, None, :d, d]
        inl = np.einsum("tni,tni->tn", pred - dst, pred - dst) < thr * thr
        counts = inl.sum(axis=1)
        k = int(np.argmax(counts))
        if counts[k] > best_count:
            best_count, best = int(counts[k]), hyps[k]
            ratio = best_count / n
            if ratio >= 1.0:
                needed = drawn
            elif ratio > 0:
                needed = int(np.ceil(np.log(1 - confidence) / np.log(max(1 - ratio**m, 1e-300))))
    if best is None or best_count < min_inliers:
        raise RegistrationError(
            f"RANSAC found no {model} transform with at least {min_inliers} of {n} matches within {thr:g}; "
            "check the matches, raise threshold, or use a model with fewer degrees of freedom"
        )
    transform, inliers = best, _inliers(best, src, dst, thr)
    for _ in range(2):  # local optimisation: refit on all inliers
        if inliers.sum() < m:
            break
        try:
            refit = fit_weighted(src[inliers], dst[inliers], np.ones(int(inliers.sum())), model)
        except InputError:
            break
        new_inliers = _inliers(refit, src, dst, thr)
        if new_inliers.sum() < inliers.sum():
            break
        transform, inliers = refit, new_inliers
    res = src @ transform[:d, :d].T + transform[:d, d] - dst
    rmse = float(np.sqrt(np.mean(np.einsum("ij,ij->i", res[inliers], res[inliers]))))
    return RegistrationResult(transform=transform, fitness=float(inliers.mean()), inlier_rmse=rmse,
                              n_iterations=drawn, converged=True, info={"inliers": inliers})


def _inliers(transform, src, dst, thr):
    d = src.shape[1]
    r = src @ transform[:d, :d].T + transform[:d, d] - dst
    return np.einsum("ij,ij->i", r, r) < thr * thr


def _minimal_fits(xs, ys, model):
    """Batched closed-form fits on minimal samples xs, ys of shape (T, m, d); degenerate samples are dropped."""
    t, m, d = xs.shape
    mx, my = xs.mean(axis=1, keepdims=True), ys.mean(axis=1, keepdims=True)
    a, b = xs - mx, ys - my
    sv_a = np.linalg.svd(a, compute_uv=False)
    need = d - 1 if model in ("rigid", "similarity") else d
    ok = sv_a[:, need - 1] > 1e-9 * np.maximum(sv_a[:, 0], 1e-300)
    if not np.any(ok):
        return None
    a, b, mx, my = a[ok], b[ok], mx[ok, 0], my[ok, 0]
    if model in ("rigid", "similarity"):
        u, sv, vt = np.linalg.svd(np.einsum("tmi,tmj->tij", b, a))  # Kabsch / Umeyama per sample
        sign = np.ones((len(u), d))
        sign[:, -1] = np.where(np.linalg.det(u) * np.linalg.det(vt) < 0, -1.0, 1.0)
        lin = np.einsum("tij,tj,tjk->tik", u, sign, vt)
        if model == "similarity":
            var = np.einsum("tmi,tmi->t", a, a)
            lin = lin * (np.einsum("tj,tj->t", sv, sign) / var)[:, None, None]
    else:
        # d + 1 points: A solves A a_i = b_i exactly; least squares in case of more points.
        lin = np.transpose(np.linalg.pinv(a) @ b, (0, 2, 1))
        if model == "axis_scaled":
            s = np.maximum(np.linalg.norm(lin, axis=1), 1e-12)
            lin = np.stack([nearest_rotation(l / sc) * sc for l, sc in zip(lin, s)])
    tr = my - np.einsum("tij,tj->ti", lin, mx)
    return np.stack([make_transform(l, v) for l, v in zip(lin, tr)])
