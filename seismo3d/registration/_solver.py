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

import numpy as np
from scipy.spatial.transform import Rotation

from ..geometry.transforms import make_transform, nearest_rotation


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
