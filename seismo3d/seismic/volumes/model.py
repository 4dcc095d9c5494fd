"""The map between two sub-volumes: its parameters, and its decomposition into map rotation and bin scales.

Each survey has its own bins, so the map from MOVING index coordinates to FIXED index coordinates is, in map view,
``diag(fixed_bins)^-1 R(theta) diag(moving_bins)`` (both bin sizes in one physical unit), and along the traces a
vertical scale and shift: ``z_f = s z_m + t``. Any such map is a general 2 x 2 linear map in map view, so the
registration estimates the general one (8 parameters, linear in the coordinates: :func:`model_matrix`) and
:func:`decompose_map` splits it into the map rotation and the scales of both volumes. A per-axis scale on one side
only cannot express the map when the *other* volume's bins are the ones that differ; the general map does not depend
on which volume is passed as fixed (its inverse is of the same family).

``'rigid'`` trusts the spacings: a map rotation and a translation of the physical coordinates, the vertical scale the
ratio of the sample intervals (4 parameters, :func:`rigid_to_affine`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["VOLUME_MODELS", "N_AFFINE", "homogeneous_diag", "rotation_2d", "model_matrix", "model_params",
           "point_derivatives", "Reparam", "MapDecomposition", "decompose_map", "map_matrix", "transform_corners",
           "corner_distance"]

VOLUME_MODELS = ("affine", "rigid")
N_AFFINE = 8  # a00, a01, a10, a11 (map view), s (vertical scale), b0, b1, b2 (image of the centre)


def homogeneous_diag(v) -> np.ndarray:
    """The (4, 4) homogeneous matrix scaling axis k by ``v[k]`` ((3,) array_like of float)."""
    return np.diag(np.r_[np.asarray(v, dtype=np.float64), 1.0])


def rotation_2d(theta_deg: float) -> np.ndarray:
    """(2, 2) rotation by ``theta_deg`` degrees, counter-clockwise from the first axis towards the second."""
    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    return np.array([[c, -s], [s, c]])


def map_matrix(theta_deg: float, lateral, vertical: float) -> np.ndarray:
    """(3, 3) linear part ``R(theta) diag(lateral)`` in map view and ``vertical`` along the traces."""
    a = np.zeros((3, 3))
    a[:2, :2] = rotation_2d(theta_deg) @ np.diag(np.asarray(lateral, dtype=np.float64))
    a[2, 2] = vertical
    return a


def model_matrix(p, centre) -> np.ndarray:
    """The (4, 4) moving-index to fixed-index transform of the 8 parameters ``p``: ``f = A (m - centre) + b``.

    ``p = (a00, a01, a10, a11, s, b0, b1, b2)``: the map-view linear part, the vertical scale, and ``b``, the fixed
    position of the moving point ``centre`` ((3,), index units). Acting about the moving centre keeps the parameters
    of similar sensitivity.
    """
    a = np.array([[p[0], p[1], 0.0], [p[2], p[3], 0.0], [0.0, 0.0, p[4]]])
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = a, np.asarray(p[5:8]) - a @ centre
    return t


def model_params(t_index, centre) -> np.ndarray:
    """The 8 parameters (:func:`model_matrix`) nearest to a (4, 4) transform: its map-view block, vertical scale and
    the image of ``centre``; lateral-vertical coupling terms are dropped."""
    a = t_index[:3, :3]
    b = a @ centre + t_index[:3, 3]
    return np.array([a[0, 0], a[0, 1], a[1, 0], a[1, 1], a[2, 2], b[0], b[1], b[2]])


def point_derivatives(points, centre) -> np.ndarray:
    """(8, 3, N) derivatives of ``A (m - centre) + b`` with respect to the 8 parameters at the (3, N) points."""
    d = points - np.asarray(centre, dtype=np.float64)[:, None]
    out = np.zeros((N_AFFINE, 3, points.shape[1]))
    out[0, 0], out[1, 0], out[2, 1], out[3, 1], out[4, 2] = d[0], d[1], d[0], d[1], d[2]
    out[5, 0] = out[6, 1] = out[7, 2] = 1.0
    return out


class Reparam:
    """The parameters the fit varies, as a map to the 8 affine parameters with its Jacobian.

    ``'affine'`` varies the 8 parameters themselves. ``'rigid'`` varies (theta, b0, b1, b2): a map rotation by theta
    (radians) of the physical coordinates, ``A = diag(1 / fixed_spacing) R(theta) diag(moving_spacing)`` in map view
    and the ratio of the sample intervals along the traces.

    Parameters
    ----------
    model : {'affine', 'rigid'}
    sp_fixed, sp_moving : (3,) float64 ndarray
        Spacings (inline bin, crossline bin, sample interval) of the two volumes at the level fitted.
    """

    def __init__(self, model: str, sp_fixed, sp_moving):
        self.model = model
        self.wf = np.asarray(sp_fixed, dtype=np.float64)
        self.wm = np.asarray(sp_moving, dtype=np.float64)

    def start(self, p8) -> np.ndarray:
        """The fitted parameters nearest to 8 affine ones."""
        if self.model == "affine":
            return np.array(p8, dtype=np.float64)
        lat = np.diag(self.wf[:2]) @ np.array([[p8[0], p8[1]], [p8[2], p8[3]]]) @ np.diag(1.0 / self.wm[:2])
        u, _, vt = np.linalg.svd(lat)
        r = u @ vt
        return np.array([np.arctan2(r[1, 0], r[0, 0]), *p8[5:8]])

    def affine(self, q) -> tuple[np.ndarray, np.ndarray]:
        """(8,) affine parameters and their (8, n) Jacobian with respect to ``q``."""
        if self.model == "affine":
            return np.asarray(q, dtype=np.float64), np.eye(N_AFFINE)
        c, s = np.cos(q[0]), np.sin(q[0])
        k = np.outer(1.0 / self.wf[:2], self.wm[:2])  # A_ij = k_ij R_ij
        p = np.array([k[0, 0] * c, -k[0, 1] * s, k[1, 0] * s, k[1, 1] * c, self.wm[2] / self.wf[2], *q[1:4]])
        jac = np.zeros((N_AFFINE, 4))
        jac[:4, 0] = [-k[0, 0] * s, -k[0, 1] * c, k[1, 0] * c, -k[1, 1] * s]
        jac[5:8, 1:4] = np.eye(3)
        return p, jac


@dataclass(frozen=True)
class MapDecomposition:
    """A map between two volumes as a map rotation and the bin scales of both (:func:`decompose_map`).

    Attributes
    ----------
    rotation_deg : float
        Map rotation of the moving grid, degrees, counter-clockwise from the fixed +inline axis towards the fixed
        +crossline axis.
    moving_scales : (3,) float64 ndarray
        Moving inline bin, crossline bin and sample interval in units of the spacings given for the fixed volume
        (1 when the spacings are right).
    fixed_scales : (3,) float64 ndarray
        Corrections of the fixed inline and crossline bins whose product is 1 (the fixed bin area is the unit), and 1
        for the sample interval.
    separable : bool
        Whether the anisotropy of the two grids could be told apart: only under a map rotation away from 0 and 90
        degrees (more than ``min_angle``) and for a map of the two-sided form; otherwise all of it is reported on
        the moving volume (``fixed_scales`` 1), which gives the same map.
    """

    rotation_deg: float
    moving_scales: np.ndarray
    fixed_scales: np.ndarray
    separable: bool


def decompose_map(t_physical, *, min_angle: float = 5.0) -> MapDecomposition:
    """Split a physical map into ``diag(1 / fixed_scales) R(theta) diag(moving_scales)`` (map view) and a vertical
    scale.

    The map-view block ``L`` of the (4, 4) ``t_physical`` (physical moving coordinates to physical fixed coordinates)
    has 4 degrees of freedom; the two-sided form has 5 (theta, two scales per side) less one common factor, fixed
    here by ``fixed_scales[0] * fixed_scales[1] = 1``. With ``L = diag(1/f) R diag(m)``:
    ``(f1 / f0)^2 = -L00 L01 / (L10 L11)`` (the columns of ``diag(f) L`` are orthogonal), then
    ``diag(f) L = R diag(m)`` gives theta and m.

    Parameters
    ----------
    t_physical : (4, 4) array_like of float
    min_angle : float
        Degrees from 0 and 90 within which the two grids' anisotropies are not told apart (see
        :class:`MapDecomposition`).

    Returns
    -------
    MapDecomposition
    """
    lat = np.asarray(t_physical, dtype=np.float64)[:2, :2]
    vertical = float(t_physical[2][2])
    f = np.ones(2)
    num, den = -lat[0, 0] * lat[0, 1], lat[1, 0] * lat[1, 1]
    ratio2 = num / den if abs(den) > 1e-12 else -1.0
    if ratio2 > 0:
        rho = np.sqrt(ratio2)
        f = np.array([1.0 / np.sqrt(rho), np.sqrt(rho)])
    scaled = np.diag(f) @ lat
    m = np.linalg.norm(scaled, axis=0)
    theta = float(np.degrees(np.arctan2(scaled[1, 0] - scaled[0, 1] * m[0] / m[1],
                                        scaled[0, 0] + scaled[1, 1] * m[0] / m[1])))
    separable = ratio2 > 0 and min_angle < abs(theta) % 90.0 < 90.0 - min_angle
    if not separable:  # one side only: the moving volume's axes carry the scales
        f = np.ones(2)
        m = np.linalg.norm(lat, axis=0)
        r = lat / m
        u, _, vt = np.linalg.svd(r)
        r = u @ vt
        theta = float(np.degrees(np.arctan2(r[1, 0], r[0, 0])))
    return MapDecomposition(rotation_deg=theta, moving_scales=np.array([m[0], m[1], vertical]),
                            fixed_scales=np.array([f[0], f[1], 1.0]), separable=bool(separable))


def transform_corners(shape) -> np.ndarray:
    """(4, 8) homogeneous index coordinates of the 8 corner samples of a volume of ``shape``."""
    c = np.array(np.meshgrid(*[[0.0, n - 1.0] for n in shape], indexing="ij")).reshape(3, -1)
    return np.vstack([c, np.ones(8)])


def corner_distance(t_a, t_b, shape) -> float:
    """Largest distance (index units of the target volume) between the images of the corners of a volume of
    ``shape`` under two (4, 4) transforms."""
    c = transform_corners(shape)
    return float(np.linalg.norm((np.asarray(t_a) - np.asarray(t_b))[:3] @ c, axis=0).max())
