"""Gauss-Newton machinery shared by ICP and fused ICP (method.md section 1, eqs. 10-16).

Every residual is a signed distance along a unit direction: ``r = n . (M p - q)``. Point-to-plane residuals use the
target normal; a point-to-point residual ``M p - q`` is the d residuals along the axis directions e_1..e_d. So one
linearisation serves both terms of the fused objective (eq. 16) and all four models.

Parametrisation of an update around the current ``M0 = [A0, t0]`` (u = A0 p):

=========== =================================================== ========================================
model       updated transform                                   d(n . y) / d(delta)
=========== =================================================== ========================================
rigid       exp([w]x) A0 p + t0 + dt                            [u x n, n]  (2D: [u_x n_y - u_y n_x, n])
similarity  e^sigma exp([w]x) A0 p + t0 + dt                    [u x n, n . u, n]
axis_scaled exp([w]x) A0 diag(e^sigma) p + t0 + dt   (R S)      [u x n, (n^T A0)_j p_j, n]
affine      (A0 + dA) p + t0 + dt                               [n_i p_j, n]
=========== =================================================== ========================================

For the affine model the residual is linear in (dA, dt), so a single step is the exact minimiser: this is the
normal-equation solution of eqs. 12-15. For the rigid model this is point-to-plane ICP on SE(d)
(Chen & Medioni 1991; Low 2004), with the exponential map for the rotation update.
"""

from __future__ import annotations

import numba
import numpy as np
from scipy.spatial.transform import Rotation

from .._threads import run_threads
from ..geometry.transforms import make_transform, nearest_rotation
from .kernels import KERNELS

_CHUNKS = 64  # fixed work split of the compiled accumulation, so sums do not depend on the thread count


def n_params(model: str, d: int) -> int:
    rot = 3 if d == 3 else 1
    return {"rigid": rot + d, "similarity": rot + 1 + d, "axis_scaled": rot + 2 * d, "affine": d * d + d}[model]


def plane_rows(model: str, p: np.ndarray, u: np.ndarray, a0: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Jacobian rows d(n . y)/d(delta), shape (N, n_params). ``p`` source points, ``u = p @ A0.T``, ``n`` directions."""
    d = p.shape[1]
    cols = []
    if model != "affine":
        if d == 3:
            cols.append(np.cross(u, n))
        else:
            cols.append((u[:, 0] * n[:, 1] - u[:, 1] * n[:, 0])[:, None])
        if model == "similarity":
            cols.append(np.einsum("ij,ij->i", n, u)[:, None])
        elif model == "axis_scaled":
            cols.append((n @ a0) * p)
    else:
        cols.append((n[:, :, None] * p[:, None, :]).reshape(len(p), d * d))
    cols.append(n)
    return np.concatenate(cols, axis=1)


def apply_update(model: str, transform: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """Compose the increment ``delta`` (see the module table) with ``transform``."""
    d = transform.shape[0] - 1
    a0 = transform[:d, :d]
    t = transform[:d, d] + delta[-d:]
    if model == "affine":
        return make_transform(a0 + delta[: d * d].reshape(d, d), t)
    k = 3 if d == 3 else 1
    w = delta[:k]
    if d == 3:
        rot = Rotation.from_rotvec(w).as_matrix()
    else:
        c, s = np.cos(w[0]), np.sin(w[0])
        rot = np.array([[c, -s], [s, c]])
    if model == "rigid":
        a = nearest_rotation(rot @ a0)
    elif model == "similarity":
        scale = np.exp(delta[k]) * np.linalg.norm(a0, axis=0).mean()
        a = scale * nearest_rotation(rot @ a0)
    else:  # axis_scaled: keep A = R S exactly
        s0 = np.linalg.norm(a0, axis=0)
        r = nearest_rotation(rot @ (a0 / s0))
        a = r * (s0 * np.exp(delta[k:k + d]))
    return make_transform(a, t)


def normal_matrix(blocks, model: str, transform: np.ndarray):
    """Accumulate ``H = sum_b c_b sum_i w_i J_i^T J_i`` and ``g = sum_b c_b sum_i w_i J_i r_i`` over residual blocks.

    Each block is ``(p, n, q, w, c)``: source points, directions, target points, per-residual weights, block factor.
    Returns H, g and the total weighted count used to normalise H for the degeneracy measure.
    """
    d = transform.shape[0] - 1
    a0, t0 = transform[:d, :d], transform[:d, d]
    size = n_params(model, d)
    h = np.zeros((size, size))
    g = np.zeros(size)
    for p, n, q, w, c in blocks:
        if len(p) == 0:
            continue
        u = p @ a0.T
        rows = plane_rows(model, p, u, a0, n)
        r = np.einsum("ij,ij->i", n, u + t0 - q)
        wr = rows * (c * w)[:, None]
        h += wr.T @ rows
        g += wr.T @ r
    return h, g


def solve_step(h: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Solve ``H delta = -g`` with a tiny Levenberg damping so a degenerate H still gives a bounded step."""
    lam = 1e-9 * max(np.trace(h) / len(h), 1e-300)
    try:
        return np.linalg.solve(h + lam * np.eye(len(h)), -g)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(h, -g, rcond=None)[0]


def eigen_range(h: np.ndarray, total_weight: float):
    """Smallest and largest eigenvalue of the normalised normal matrix ``H / total_weight``."""
    if total_weight <= 0:
        return 0.0, 0.0
    ev = np.linalg.eigvalsh(h / total_weight)
    return float(max(ev[0], 0.0)), float(ev[-1])


def axis_directions(n: int, d: int) -> np.ndarray:
    """The d unit axis directions repeated for n points: shape (n * d, d), row-major (point 0 e_1..e_d, point 1, ...)."""
    return np.tile(np.eye(d), (n, 1))


def plane_system_rigid3(moved, t0, dst, nrm, idx, kernel: str, scale: float, factor: float):
    """The point-to-plane normal equations of the rigid 3D model in one compiled pass (no gathered copies).

    For every source point ``i`` with a correspondence (``idx[i] < len(dst)``): ``r = n . (y - q)`` with
    ``y = moved[i]``, ``q = dst[idx[i]]``, ``n = nrm[idx[i]]``, weight ``w = factor * robust_weight(r)`` and Jacobian
    row ``[u x n, n]`` (``u = y - t0``): the same ``H``, ``g`` as :func:`normal_matrix` with the block
    ``(p, n, q, w, factor)``, up to rounding.

    Parameters
    ----------
    moved : (N, 3) float64 ndarray
        Source points moved by the current transform (``A0 p + t0``).
    t0 : (3,) float64 ndarray
        The current translation.
    dst, nrm : (M, 3) float64 ndarrays
        Target points and unit normals.
    idx : (N,) int64 ndarray
        Target row of each source point, ``M`` where there is none (as ``cKDTree.query`` returns).
    kernel : {'none', 'huber', 'tukey', 'cauchy'}
        Robust kernel (:func:`~seismo3d.registration.kernels.robust_weights`).
    scale : float
        Kernel scale, unit of the residuals.
    factor : float
        Block factor multiplying every weight.

    Returns
    -------
    h : (6, 6) float64 ndarray
    g : (6,) float64 ndarray
    count : int
        Source points with a correspondence.
    """
    sums = np.zeros((_CHUNKS, 28))
    n_threads = max(1, min(numba.get_num_threads(), _CHUNKS))
    run_threads(_plane_sums_share, n_threads, moved, np.ascontiguousarray(t0, dtype=np.float64), dst, nrm, idx,
                KERNELS.index(kernel), float(scale), float(factor), sums, np.empty((n_threads, 6)))
    total = sums.sum(axis=0)
    h = np.zeros((6, 6))
    h[np.triu_indices(6)] = total[:21]
    h = h + np.triu(h, 1).T
    return h, total[21:27].copy(), int(round(total[27]))


@numba.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _plane_sums_share(t, n_threads, moved, t0, dst, nrm, idx, kernel, scale, factor, out, rows):
    """Per-chunk sums into ``out`` (_CHUNKS, 28) (zeros): the 21 upper-triangle entries of H, the 6 of g and the
    count, for chunks t, t + n_threads, ... (run_threads; the caller adds the chunks in order, so the sums do not
    depend on the threads). ``rows`` (n_threads, 6): work arrays. Threads of run_threads, not a prange loop, and no
    np.zeros / np.empty, max() or ** inside: each compiled more of numba's on a first run (the prange loop 1.4 CPU s
    against 0.3)."""
    n, m = len(moved), len(dst)
    row = rows[t]
    for chunk in range(t, _CHUNKS, n_threads):
        acc = out[chunk]
        for i in range(chunk * n // _CHUNKS, (chunk + 1) * n // _CHUNKS):
            j = idx[i]
            if j >= m:
                continue
            nx, ny, nz = nrm[j, 0], nrm[j, 1], nrm[j, 2]
            r = nx * (moved[i, 0] - dst[j, 0]) + ny * (moved[i, 1] - dst[j, 1]) + nz * (moved[i, 2] - dst[j, 2])
            a = abs(r)
            if kernel == 1:
                w = 1.0 if a <= scale else scale / (1e-300 if 1e-300 > a else a)
            elif kernel == 2:
                v = a / scale
                y = 1.0 - v * v
                w = y * y if v < 1.0 else 0.0
            elif kernel == 3:
                z = a / scale
                w = 1.0 / (1.0 + z * z)
            else:
                w = 1.0
            w *= factor
            ux, uy, uz = moved[i, 0] - t0[0], moved[i, 1] - t0[1], moved[i, 2] - t0[2]
            row[0] = uy * nz - uz * ny
            row[1] = uz * nx - ux * nz
            row[2] = ux * ny - uy * nx
            row[3], row[4], row[5] = nx, ny, nz
            k = 0
            for p in range(6):
                wp = w * row[p]
                for q in range(p, 6):
                    acc[k] += wp * row[q]
                    k += 1
                acc[21 + p] += wp * r
            acc[27] += 1.0


def moved_points(points, transform):
    """``points @ A.T + t`` for ``transform = [A, t]`` in one compiled pass ((n, d) float64 -> (n, d) float64);
    the BLAS product of an (n, 3) and a (3, 3) matrix is several times slower and starts threads."""
    d = points.shape[1]
    out = np.empty(points.shape)  # here, not in the kernel: np.empty there compiled a function of numba's of its own
    _moved(np.ascontiguousarray(points), np.ascontiguousarray(transform[:d, :d]),
           np.ascontiguousarray(transform[:d, d]), out)
    return out


@numba.njit(cache=True, no_cfunc_wrapper=True)
def _moved(points, a, t, out):
    n, d = points.shape
    for i in range(n):
        for r in range(d):
            v = t[r]
            for c in range(d):
                v += a[r, c] * points[i, c]
            out[i, r] = v
