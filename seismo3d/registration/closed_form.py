"""Closed-form weighted fits of a transform to paired points (method.md section 1, eqs. 1-9).

All fits minimise ``sum_i w_i |A x_i + t - y_i|^2`` over the model's family of A. The translation always has the closed
form ``t = mean_w(y) - A mean_w(x)`` (eq. 3), so every fit first centres both point sets (eq. 4-5).
"""

from __future__ import annotations

import numpy as np

from .._validation import as_pair, as_weights
from ..errors import InputError
from ..geometry.transforms import check_model, make_transform, nearest_rotation

__all__ = ["fit_rigid", "fit_similarity", "fit_axis_scaled", "fit_affine", "fit_transform", "min_points"]


def min_points(model: str, dim: int) -> int:
    """Fewest point pairs that determine ``model`` in ``dim`` dimensions (the RANSAC minimal sample size).

    Rigid and similarity transforms need ``dim`` pairs (2 in 2D, 3 in 3D); axis-scaled and affine ones need ``dim + 1``.

    Parameters
    ----------
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
    dim : int
        2 or 3.

    Returns
    -------
    int
    """
    check_model(model)
    return dim if model in ("rigid", "similarity") else dim + 1


def _centred(src, dst, w):
    wn = w / w.sum()
    mx = wn @ src
    my = wn @ dst
    return src - mx, dst - my, mx, my, wn


def _check_rank(a, wn, model, need):
    # Spread of the centred source: singular values of the weighted scatter.
    sv = np.linalg.svd(a * np.sqrt(wn)[:, None], compute_uv=False)
    scale = sv[0] if sv.size and sv[0] > 0 else 1.0
    rank = int(np.count_nonzero(sv > 1e-9 * scale)) if sv[0] > 0 else 0
    if rank < need:
        shape = {0: "coincident", 1: "collinear", 2: "coplanar"}.get(rank, "degenerate")
        raise InputError(
            f"the source points are {shape} (rank {rank}), which does not determine a {model} transform in "
            f"{a.shape[1]}D; pass points that span {need} dimensions or use a model with fewer degrees of freedom"
        )


def _kabsch(a, b, wn):
    """Rotation R minimising sum w |R a - b|^2 and the singular values / sign matrix (Umeyama 1991, eqs. 38-40)."""
    cov = (b * wn[:, None]).T @ a  # sum_i w_i b_i a_i^T
    u, sv, vt = np.linalg.svd(cov)
    sign = np.ones(a.shape[1])
    sign[-1] = 1.0 if np.linalg.det(u) * np.linalg.det(vt) >= 0 else -1.0  # det-sign fix: no reflections
    return (u * sign) @ vt, sv, sign


def fit_rigid(source, target, *, weights=None) -> np.ndarray:
    """Weighted least-squares rigid transform (Kabsch) mapping ``source`` onto ``target``.

    Parameters
    ----------
    source, target : (N, d) array_like, d in {2, 3}
        Paired points (row i of source corresponds to row i of target), any length unit.
    weights : (N,) array_like, optional
        Non-negative per-pair weights (default all ones).

    Returns
    -------
    (d+1, d+1) float64 ndarray
        ``[[R, t], [0, 1]]`` with R in SO(d).

    Raises
    ------
    InputError
        Mismatched shapes, NaNs, fewer than d pairs, or collinear (3D) / coincident source points.

    References
    ----------
    Kabsch, W. (1976). A solution for the best rotation to relate two sets of vectors. Acta Cryst. A32, 922-923.
    Umeyama, S. (1991). Least-squares estimation of transformation parameters between two point patterns.
    IEEE TPAMI 13(4), 376-380. doi:10.1109/34.88573
    """
    return fit_transform(source, target, model="rigid", weights=weights)


def fit_similarity(source, target, *, weights=None) -> np.ndarray:
    """Weighted least-squares similarity transform ``y = s R x + t`` (Umeyama 1991).

    Parameters and errors as :func:`fit_rigid`; returns ``[[s R, t], [0, 1]]`` with s > 0.

    References
    ----------
    Umeyama, S. (1991). doi:10.1109/34.88573, eqs. (40)-(42).
    """
    return fit_transform(source, target, model="similarity", weights=weights)


def fit_axis_scaled(source, target, *, weights=None, max_iterations: int = 200, tolerance: float = 1e-13) -> np.ndarray:
    """Weighted least-squares ``y = R S x + t`` with a per-axis scale ``S = diag(s_1..s_d)`` (method eqs. 1-9).

    The energy ``E(R, S) = sum_i w_i |R S a_i - b_i|^2`` of the centred points (eq. 5) is minimised by alternating
    the two closed forms: for fixed S, R is the Kabsch rotation of the pairs (S a_i, b_i); for fixed R,
    ``s_j = sum_i w_i (R^T b_i)_j a_ij / sum_i w_i a_ij^2`` (eq. 9, in the corrected form of method.md). The
    alternation starts from the affine least-squares fit split as ``A = R S`` (column norms of A, then the nearest
    rotation), which is already exact for noise-free data; per-axis scale is what registers data of different
    spatial resolution (bin sizes, sample rates, time vs depth).

    Parameters
    ----------
    source, target : (N, d) array_like, d in {2, 3}, N >= d + 1
        Paired points.
    weights : (N,) array_like, optional
        Non-negative per-pair weights.
    max_iterations : int
        Cap on the R / S alternation.
    tolerance : float
        Stop when the relative decrease of the energy is below this.

    Returns
    -------
    (d+1, d+1) float64 ndarray
        ``[[R diag(s), t], [0, 1]]``; recover the parts with :func:`seismo3d.geometry.decompose_axis_scaled`.

    Raises
    ------
    InputError
        Mismatched shapes, NaNs, too few pairs, or source points that do not span d dimensions.
    """
    return fit_transform(source, target, model="axis_scaled", weights=weights,
                         max_iterations=max_iterations, tolerance=tolerance)


def fit_affine(source, target, *, weights=None) -> np.ndarray:
    """Weighted linear least-squares affine transform ``y = A x + t``.

    Parameters and errors as :func:`fit_axis_scaled` (needs d + 1 pairs spanning d dimensions).
    """
    return fit_transform(source, target, model="affine", weights=weights)


def fit_transform(source, target, *, model: str = "rigid", weights=None, max_iterations: int = 200,
                  tolerance: float = 1e-13) -> np.ndarray:
    """Closed-form weighted fit of any of the models ``{'rigid', 'similarity', 'axis_scaled', 'affine'}``.

    See :func:`fit_rigid`, :func:`fit_similarity`, :func:`fit_axis_scaled` and :func:`fit_affine` for the methods.

    Parameters
    ----------
    source, target : (N, d) array_like, d in {2, 3}
        Paired points.
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
        Family of the linear part.
    weights : (N,) array_like, optional
        Non-negative per-pair weights.
    max_iterations, tolerance
        Only for ``'axis_scaled'``: the R / S alternation's limits.

    Returns
    -------
    (d+1, d+1) float64 ndarray

    Raises
    ------
    InputError
        Unknown model, mismatched or non-finite input, too few pairs, degenerate source geometry.
    """
    check_model(model)
    src, dst = as_pair(source, target)
    d = src.shape[1]
    need = min_points(model, d)
    if src.shape[0] < need:
        raise InputError(f"a {model} fit in {d}D needs at least {need} point pairs; got {src.shape[0]}")
    w = as_weights(weights, src.shape[0])
    return fit_weighted(src, dst, w, model, max_iterations, tolerance)


def fit_weighted(src, dst, w, model, max_iterations=200, tolerance=1e-13) -> np.ndarray:
    """:func:`fit_transform` without the input checks: the hot path of ICP and RANSAC.

    Parameters
    ----------
    src, dst : (N, d) float64 ndarray
        Paired points, finite, at least ``min_points(model, d)`` of them.
    w : (N,) float64 ndarray
        Non-negative weights, not all zero.
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}
    max_iterations, tolerance
        Only for ``'axis_scaled'``: the R / S alternation's limits.

    Returns
    -------
    (d+1, d+1) float64 ndarray

    Raises
    ------
    InputError
        Degenerate source geometry (the points do not span enough dimensions for the model).
    """
    a, b, mx, my, wn = _centred(src, dst, w)
    d = src.shape[1]
    if model in ("rigid", "similarity"):
        _check_rank(a, wn, model, d - 1)
        r, sv, sign = _kabsch(a, b, wn)
        lin = r
        if model == "similarity":
            var = float(wn @ np.einsum("ij,ij->i", a, a))
            lin = r * (float(sv @ sign) / var)  # Umeyama eq. (42): s = tr(D S) / sigma_x^2
    else:
        _check_rank(a, wn, model, d)
        sw = np.sqrt(wn)[:, None]
        lin = np.linalg.lstsq(a * sw, b * sw, rcond=None)[0].T  # affine: A minimising sum w |A a - b|^2
        if model == "axis_scaled":
            lin = _alternate_axis_scaled(a, b, wn, lin, max_iterations, tolerance)
    return make_transform(lin, my - lin @ mx)  # eq. 3


def _alternate_axis_scaled(a, b, wn, affine, max_iterations, tolerance):
    s = np.maximum(np.linalg.norm(affine, axis=0), 1e-12)
    r = nearest_rotation(affine / s)
    aw = a * wn[:, None]
    denom = np.einsum("ij,ij->j", aw, a)  # sum_i w_i a_ij^2
    prev = np.inf
    for _ in range(max_iterations):
        s = np.maximum(np.einsum("ij,ij->j", aw, b @ r) / denom, 1e-12)  # eq. 9: (R^T b_i)_j = (b_i @ R)_j
        r, _, _ = _kabsch(a * s, b, wn)  # R for fixed S
        resid = a * s @ r.T - b
        energy = float(wn @ np.einsum("ij,ij->i", resid, resid))  # eq. 5
        if prev - energy <= tolerance * max(prev, 1e-300):
            break
        prev = energy
    return r * s
