"""Homogeneous transforms in 2D and 3D: build, compose, invert, apply, and measure errors.

A transform of dimension d is a (d+1, d+1) float64 matrix ``[[A, t], [0, 1]]`` acting on column vectors:
``y = A @ x + t``. The four models seismo3d fits differ only in what ``A`` may be:

========== ============================ ======================== =====================
model      A                            degrees of freedom (3D)  method.md / paper
========== ============================ ======================== =====================
rigid      R (rotation)                 6                        Kabsch
similarity s R                          7                        Umeyama 1991
axis_scaled R S, S = diag(s_1..s_d) > 0 9                        eqs. 1-9
affine     any invertible A             12                       eqs. 10-15
========== ============================ ======================== =====================
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from .._validation import check_choice
from ..errors import InputError

__all__ = [
    "MODELS",
    "make_transform",
    "split_transform",
    "apply_transform",
    "compose",
    "invert",
    "rotation_matrix",
    "rotation_about_axis",
    "nearest_rotation",
    "decompose_axis_scaled",
    "rotation_error_deg",
    "translation_error",
    "as_transform",
    "check_model",
    "perturb",
]

MODELS = ("rigid", "similarity", "axis_scaled", "affine")


def as_transform(transform, name: str = "transform", *, dims=(2, 3)) -> np.ndarray:
    """Validate a homogeneous transform and return it as a (d+1, d+1) float64 array.

    Raises
    ------
    InputError
        If the matrix is not square (3, 3) or (4, 4), has non-finite entries, or its last row is not ``[0, ..., 0, 1]``.
    """
    m = np.asarray(transform, dtype=np.float64)
    if m.ndim != 2 or m.shape[0] != m.shape[1] or m.shape[0] - 1 not in dims:
        allowed = " or ".join(f"({d + 1}, {d + 1})" for d in dims)
        raise InputError(f"{name} must be a homogeneous {allowed} matrix; got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise InputError(f"{name} has NaN or inf entries")
    d = m.shape[0] - 1
    if not np.allclose(m[d], np.r_[np.zeros(d), 1.0], atol=1e-9):
        raise InputError(f"{name}'s last row must be [0, ..., 0, 1] (a homogeneous transform); got {m[d].tolist()}")
    return m


def make_transform(linear, translation) -> np.ndarray:
    """Build the homogeneous matrix ``[[A, t], [0, 1]]``.

    Parameters
    ----------
    linear : (d, d) array_like
        The linear part A (rotation, R S, s R or any affine matrix).
    translation : (d,) array_like
        The translation t, in the units of the points.

    Returns
    -------
    (d+1, d+1) float64 ndarray
    """
    a = np.asarray(linear, dtype=np.float64)
    t = np.asarray(translation, dtype=np.float64).reshape(-1)
    d = a.shape[0]
    if a.shape != (d, d) or t.shape != (d,):
        raise InputError(f"linear must be (d, d) and translation (d,); got {a.shape} and {t.shape}")
    m = np.eye(d + 1)
    m[:d, :d] = a
    m[:d, d] = t
    return m


def split_transform(transform):
    """Split a homogeneous transform into its linear part and translation.

    Parameters
    ----------
    transform : (d+1, d+1) array_like

    Returns
    -------
    A : (d, d) float64 ndarray
        Linear part (a copy).
    t : (d,) float64 ndarray
        Translation, in the points' unit (a copy).
    """
    m = np.asarray(transform, dtype=np.float64)
    d = m.shape[0] - 1
    return m[:d, :d].copy(), m[:d, d].copy()


def apply_transform(transform, points) -> np.ndarray:
    """Apply a homogeneous transform to points.

    Parameters
    ----------
    transform : (d+1, d+1) array_like
        Homogeneous transform.
    points : (N, d) array_like
        Points, one per row.

    Returns
    -------
    (N, d) float64 ndarray
        ``points @ A.T + t``.

    Raises
    ------
    InputError
        If the dimensions of the transform and the points disagree.
    """
    m = as_transform(transform)
    p = np.asarray(points, dtype=np.float64)
    d = m.shape[0] - 1
    if p.ndim != 2 or p.shape[1] != d:
        raise InputError(f"points must be (N, {d}) for a ({d + 1}, {d + 1}) transform; got {p.shape}")
    return p @ m[:d, :d].T + m[:d, d]


def compose(*transforms) -> np.ndarray:
    """Compose transforms right to left: ``compose(A, B)`` applies B first, then A (the matrix product A @ B)."""
    if not transforms:
        raise InputError("compose needs at least one transform")
    out = as_transform(transforms[0])
    for t in transforms[1:]:
        t = as_transform(t)
        if t.shape != out.shape:
            raise InputError(f"cannot compose a {out.shape} with a {t.shape} transform")
        out = out @ t
    return out


def invert(transform) -> np.ndarray:
    """Invert a homogeneous transform exactly: ``[[A^-1, -A^-1 t], [0, 1]]``.

    Parameters
    ----------
    transform : (d+1, d+1) array_like

    Returns
    -------
    (d+1, d+1) float64 ndarray

    Raises
    ------
    InputError
        If the matrix is not a homogeneous transform or its linear part is singular.
    """
    m = as_transform(transform)
    a, t = split_transform(m)
    if abs(np.linalg.det(a)) < 1e-12 * max(1.0, np.abs(a).max() ** a.shape[0]):
        raise InputError("the transform's linear part is singular and cannot be inverted")
    ai = np.linalg.inv(a)
    return make_transform(ai, -ai @ t)


def rotation_matrix(angle_deg: float) -> np.ndarray:
    """2D rotation matrix for a counter-clockwise angle.

    Parameters
    ----------
    angle_deg : float
        Angle in degrees, counter-clockwise (x towards y).

    Returns
    -------
    (2, 2) float64 ndarray
    """
    a = np.deg2rad(angle_deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def rotation_about_axis(axis, angle_deg: float) -> np.ndarray:
    """3D rotation matrix about an axis (right-hand rule).

    Parameters
    ----------
    axis : (3,) array_like
        Any non-zero vector; it is normalised.
    angle_deg : float
        Angle in degrees.

    Returns
    -------
    (3, 3) float64 ndarray

    Raises
    ------
    InputError
        If ``axis`` is not a non-zero 3-vector.
    """
    ax = np.asarray(axis, dtype=np.float64)
    n = np.linalg.norm(ax)
    if ax.shape != (3,) or n == 0:
        raise InputError(f"axis must be a non-zero (3,) vector; got {axis!r}")
    return Rotation.from_rotvec(ax / n * np.deg2rad(angle_deg)).as_matrix()


def nearest_rotation(matrix) -> np.ndarray:
    """Project a matrix onto SO(d): the rotation closest to it in the Frobenius norm.

    Polar decomposition via the SVD ``M = U S V^T``, returning ``U diag(1, .., det(U V^T)) V^T`` (no reflections).

    Parameters
    ----------
    matrix : (d, d) array_like

    Returns
    -------
    (d, d) float64 ndarray

    References
    ----------
    Higham, N. J. (1986). Computing the polar decomposition. SIAM J. Sci. Stat. Comput. 7(4), 1160-1174.
    """
    u, _, vt = np.linalg.svd(np.asarray(matrix, dtype=np.float64))
    d = np.ones(u.shape[0])
    d[-1] = np.sign(np.linalg.det(u @ vt)) or 1.0
    return (u * d) @ vt


def decompose_axis_scaled(transform):
    """Split a transform whose linear part is ``R @ diag(s)`` into ``(R, s, t)``.

    Parameters
    ----------
    transform : (d+1, d+1) array_like

    Returns
    -------
    R : (d, d) float64 ndarray
        Rotation (the nearest one if the linear part is not exactly R S).
    s : (d,) float64 ndarray
        Per-axis scales (column norms of the linear part), applied in the source frame before R (eq. 1).
    t : (d,) float64 ndarray
        Translation.
    """
    a, t = split_transform(as_transform(transform))
    s = np.linalg.norm(a, axis=0)
    return nearest_rotation(a / s), s, t


def rotation_error_deg(estimate, truth) -> float:
    """Angle of the rotation between the rotational parts of two transforms.

    Both linear parts are first projected onto SO(d) (column scales removed), so the measure also applies to
    similarity, axis-scaled and affine estimates. For 3D this is the geodesic angle
    ``arccos((tr(R_e^T R_t) - 1) / 2)``; for 2D the absolute difference of the angles.

    Parameters
    ----------
    estimate, truth : (d+1, d+1) array_like
        Homogeneous transforms of the same dimension.

    Returns
    -------
    float
        Degrees, in [0, 180].

    Raises
    ------
    InputError
        If the transforms are malformed or of different dimensions.
    """
    e, _ = split_transform(as_transform(estimate))
    g, _ = split_transform(as_transform(truth))
    if e.shape != g.shape:
        raise InputError(f"cannot compare a {e.shape} with a {g.shape} linear part")
    r = nearest_rotation(e / np.linalg.norm(e, axis=0)).T @ nearest_rotation(g / np.linalg.norm(g, axis=0))
    if r.shape[0] == 2:
        return float(abs(np.degrees(np.arctan2(r[1, 0], r[0, 0]))))
    c = np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)
    return float(np.degrees(np.arccos(c)))


def translation_error(estimate, truth) -> float:
    """Euclidean distance between the translation parts of two transforms.

    Parameters
    ----------
    estimate, truth : (d+1, d+1) array_like

    Returns
    -------
    float
        In the points' unit (e.g. metres).
    """
    _, te = split_transform(as_transform(estimate))
    _, tt = split_transform(as_transform(truth))
    return float(np.linalg.norm(te - tt))


def check_model(model: str) -> str:
    """Raise :class:`~seismo3d.errors.InputError` unless ``model`` is one of :data:`MODELS`."""
    return check_choice(model, "model", MODELS)



def perturb(transform, angle_deg: float, *, centre, rng) -> np.ndarray:
    """Rotate a 3D transform's output by ``angle_deg`` about a random axis through ``centre``.

    The perturbed initial guesses of the registration tests and benchmarks: ``R_p (T x - c) + c``.

    Parameters
    ----------
    transform : (4, 4) array_like
        The transform to perturb (e.g. a ground truth).
    angle_deg : float
        Rotation angle in degrees; the rotation error of the result against ``transform`` is exactly this.
    centre : (3,) array_like
        A point of the transform's output space on the rotation axis (e.g. the centroid of the moved source).
    rng : numpy.random.Generator
        Draws the axis (uniform on the sphere).

    Returns
    -------
    (4, 4) float64 ndarray
    """
    m = as_transform(transform, dims=(3,))
    c = np.asarray(centre, dtype=np.float64).reshape(3)
    r = rotation_about_axis(rng.normal(size=3), angle_deg)
    return make_transform(r, c - r @ c) @ m
