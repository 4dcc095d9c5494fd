"""Stage 5 of the volume registration: the polish, a local maximisation of the two volumes' correlation.

Powell over the model's parameters (rotation and translation in the fixed working frame, scales along the moving axes),
maximising the normalised cross-correlation of the amplitudes over the overlap, evaluated at the moving samples with
the fixed volume interpolated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi
from scipy.optimize import minimize
from scipy.spatial.transform import Rotation

from .frames import WorkingFrames
from .options import VolumeOptions

__all__ = ["OverlapCorrelation", "Polished", "polish"]


@dataclass(frozen=True, eq=False)
class Polished:
    """Result of :func:`polish`."""

    transform: np.ndarray  # (4, 4) moving index -> fixed index
    n_evaluations: int  # correlation evaluations
    converged: bool  # Powell stopped on its tolerances, not on the evaluation limit


def polish(overlap: "OverlapCorrelation", t_index, frames: WorkingFrames, model: str,
           opt: VolumeOptions) -> Polished:
    """Local maximisation of the NCC of the two volumes (``overlap``) over the model's parameters (Powell, at most
    ``opt.polish_evaluations`` evaluations), with the moving axes' scales (working frame) kept within
    ``opt.scale_range`` widened by a quarter, from the (4, 4) ``t_index``.

    The parameters act about the moving volume's centre: a rotation vector and a translation in the fixed working
    frame (so that a rotation is a rotation of the physical coordinates, whatever the moving axes' scales), and
    log-scales (and for 'affine' a symmetric stretch) along the moving axes, applied before the current transform.
    Rotation and scale parameters are radians and log units times the volume's radius (one unit moves its edge by
    about one cell). A correction applied on the moving side only rotates the moving *index* axes: with unequal
    moving scales that is a shear of the physical coordinates, and the polish stalled half a degree from the truth
    on a pair with moving scales 0.6 and 1.8. On volumes that are each other's resampling the NCC peaks at the true
    transform, while slice tracks (stage 3) keep a bias along the reflectors where the aperture problem leaves them
    free.
    """
    t0_work = frames.to_work(t_index)
    c_m = (np.array(overlap.moving_shape) - 1.0) / 2.0 * frames.w_moving
    c_f = t0_work[:3, :3] @ c_m + t0_work[:3, 3]
    radius = max(float(np.linalg.norm(t0_work[:3, :3] @ c_m)), 1.0)

    def about(centre, linear, shift=0.0):
        out = np.eye(4)
        out[:3, :3], out[:3, 3] = linear, centre + shift - linear @ centre
        return out

    def transform(p):
        rot = Rotation.from_rotvec(p[:3] / radius).as_matrix()
        stretch = np.eye(3)
        if model == "axis_scaled":
            stretch = np.diag(np.exp(p[6:9] / radius))
        elif model == "affine":
            stretch = np.eye(3) + np.array([[p[6], p[9], p[10]], [p[9], p[7], p[11]], [p[10], p[11], p[8]]]) / radius
        return frames.to_index(about(c_f, rot, p[3:6]) @ t0_work @ about(c_m, stretch))

    # the overlap may not shrink below half its start (nor the shared fraction below min_fraction, or half the
    # start's when that is smaller): a small overlap can correlate by chance
    min_overlap = max(1000, 0.5 * overlap.inside(t_index)[1].sum())
    min_shared = min(opt.min_fraction, 0.5 * overlap.shared(t_index))
    lo, hi = opt.scale_range[0] / 1.25, opt.scale_range[1] * 1.25

    def cost(p):
        t = transform(p)
        scales = np.linalg.norm(frames.to_work(t)[:3, :3], axis=0)
        if np.any(scales < lo) or np.any(scales > hi) or overlap.shared(t) < min_shared:
            # out of the model's range, or overlapping too little: a volume squeezed into a corner of the other
            # can correlate by chance (two unrelated 24 x 18-trace synthetic volumes reach 0.88 over 1 % of the
            # fixed one)
            return 1.0
        c = overlap.ncc(t, min_overlap)[0]
        return -c if np.isfinite(c) else 1.0

    n = {"rigid": 6, "axis_scaled": 9, "affine": 12}[model]
    res = minimize(cost, np.zeros(n), method="Powell",
                   options=dict(xtol=1e-3, ftol=1e-7, maxfev=int(opt.polish_evaluations), direc=np.eye(n) * 0.5))
    return Polished(transform(res.x) if res.fun < cost(np.zeros(n)) else t_index, int(res.nfev), bool(res.success))


class OverlapCorrelation:
    """The normalised cross-correlation of the two volumes through a transform, over their overlap.

    It is evaluated at the moving volume's samples (a subsampled grid of about ``n_points``), with the fixed volume
    interpolated there (cubic B-spline): the fixed cube is the reference whose sampling is trusted. Interpolating the
    moving volume instead, which may be coarser (aliased) than the fixed one, moves the NCC maximum off the truth: by
    1-3 % in scale on pairs cut from f3_crop (and to none within +-3 % for moving bins twice the fixed ones).

    Parameters
    ----------
    fn, mn : (n0, n1, n2) float32 ndarray
        Fixed and moving volumes.
    coef_f : float32 ndarray
        Cubic B-spline coefficients of ``fn`` (``scipy.ndimage.spline_filter``, mode 'mirror').
    n_points : int
        About this many moving samples (a regular subset) are correlated.
    taper : float
        Samples: weights fall linearly to 0 over this distance from the fixed volume's edge.
    """

    def __init__(self, fn, mn, coef_f, n_points, taper: float = 2.0):
        self.taper = float(taper)
        step = max(1, int(round((mn.size / n_points) ** (1 / 3))))
        sub = mn[::step, ::step, ::step]
        self.grid = np.indices(sub.shape).reshape(3, -1).astype(np.float64) * step
        self.m = sub.ravel().astype(np.float64)
        self.coef = coef_f  # cubic B-spline coefficients of fixed
        self.hi = np.array(fn.shape, dtype=np.float64)[:, None] - 1
        self.moving_shape = mn.shape
        # fixed samples (subsampled) for the fraction of the fixed volume the moving one covers
        step_f = max(1, int(round((fn.size / n_points) ** (1 / 3))))
        sub_f = fn[::step_f, ::step_f, ::step_f]
        self.fixed_grid = np.indices(sub_f.shape).reshape(3, -1).astype(np.float64) * step_f
        self.m_hi = np.array(mn.shape, dtype=np.float64)[:, None] - 1

    def inside(self, t_index):
        """Fixed index coordinates of the moving grid points, and which fall inside the fixed volume."""
        f = t_index[:3, :3] @ self.grid + t_index[:3, 3:]
        return f, np.all((f >= 0) & (f <= self.hi), axis=0)

    def ncc(self, t_index, min_points):
        """(NCC, overlap points); the NCC is NaN under ``min_points`` or without variance.

        Points within ``taper`` samples of the fixed volume's edge are weighted down linearly to 0 at the edge, so
        the NCC changes continuously as points enter or leave the overlap (a hard edge makes it jump, which the
        polish's line searches can stop on)."""
        f, ok = self.inside(t_index)
        n = int(ok.sum())
        if n < min_points:
            return np.nan, n
        f = f[:, ok]
        w = np.clip(np.minimum(f, self.hi - f) / self.taper, 0.0, 1.0).prod(axis=0)
        m = self.m[ok]
        v = ndi.map_coordinates(self.coef, f, order=3, prefilter=False, mode="mirror")
        sw = w.sum()
        m, v = m - np.dot(w, m) / sw, v - np.dot(w, v) / sw
        den = np.sqrt(np.dot(w, m * m) * np.dot(w, v * v))
        return (float(np.dot(w, m * v) / den) if den > 0 else np.nan), n

    def covered(self, t_index):
        """Fraction of the fixed volume's samples that the moving volume covers through ``t_index``."""
        t_inv = np.linalg.inv(t_index)
        m = t_inv[:3, :3] @ self.fixed_grid + t_inv[:3, 3:]
        return float(np.all((m >= 0) & (m <= self.m_hi), axis=0).mean())

    def shared(self, t_index):
        """The overlap as a fraction of the smaller volume (measured in fixed samples)."""
        n_f = float(np.prod(self.hi + 1))
        n_m = float(np.prod(self.m_hi + 1)) * abs(np.linalg.det(t_index[:3, :3]))
        return self.covered(t_index) * n_f / max(min(n_f, n_m), 1.0)

    def correlation(self, t_index):
        """NCC and the fraction of the fixed volume covered; NCC -1 when fewer than 100 grid points overlap, 0
        without variance."""
        c, n = self.ncc(t_index, 100)
        if n < 100:
            return -1.0, self.covered(t_index)
        return (c if np.isfinite(c) else 0.0), self.covered(t_index)
