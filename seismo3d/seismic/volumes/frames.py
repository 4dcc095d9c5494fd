"""Frames of the volume registration: each volume's index space and the working frame of square map cells.

Index coordinates are each volume's (inline, crossline, sample) indices; the working frame divides physical coordinates
by ``(b, b, dt_fixed)``, ``b`` the smaller fixed bin, so that a map rotation is a rotation there
(:mod:`seismo3d.seismic.volumes`, Conventions).
"""

from __future__ import annotations

import numpy as np

from ...geometry.transforms import decompose_axis_scaled

__all__ = ["homogeneous_diag", "project_to_model", "WorkingFrames"]


def homogeneous_diag(v) -> np.ndarray:
    """The (4, 4) homogeneous matrix scaling axis k by ``v[k]`` ((3,) array_like of float)."""
    return np.diag(np.r_[np.asarray(v, dtype=np.float64), 1.0])


def project_to_model(transform, model: str) -> np.ndarray:
    """The (4, 4) transform of ``model`` ({'rigid', 'axis_scaled', 'affine'}) nearest to an affine one: column scales,
    then the nearest rotation (:func:`~seismo3d.geometry.transforms.decompose_axis_scaled`)."""
    if model == "affine":
        return transform
    r, s, _ = decompose_axis_scaled(transform)
    out = transform.copy()
    out[:3, :3] = r * s if model == "axis_scaled" else r
    return out


class WorkingFrames:
    """Index <-> working-frame scalings of the two volumes (working = physical / (b, b, dt_fixed), ``b`` the smaller
    fixed bin).

    Parameters
    ----------
    sp_fixed, sp_moving : (3,) float64 ndarray
        Inline bin, crossline bin, sample interval of each volume.

    Attributes
    ----------
    w_fixed, w_moving : (3,) float64 ndarray
        Working units per index unit along each axis.
    """

    def __init__(self, sp_fixed, sp_moving):
        b = min(sp_fixed[0], sp_fixed[1])
        ref = np.array([b, b, sp_fixed[2]])
        self.w_fixed = sp_fixed / ref
        self.w_moving = sp_moving / ref

    def to_work(self, t_index):
        """A moving-index to fixed-index (4, 4) transform, as it acts between working frames."""
        return homogeneous_diag(self.w_fixed) @ t_index @ homogeneous_diag(1.0 / self.w_moving)

    def to_index(self, t_work):
        """A working-frame (4, 4) transform, back between index spaces."""
        return homogeneous_diag(1.0 / self.w_fixed) @ t_work @ homogeneous_diag(self.w_moving)

    def project_index(self, t_index, model):
        """The index transform of ``model`` (imposed in the working frame) nearest to ``t_index``."""
        return self.to_index(project_to_model(self.to_work(t_index), model))

    def swapped(self) -> "WorkingFrames":
        """The frames of the reverse problem (moving as fixed), with the same working unit: this one's ``b`` and
        sample interval, so that a rotation here is a rotation there."""
        out = WorkingFrames.__new__(WorkingFrames)
        out.w_fixed, out.w_moving = self.w_moving, self.w_fixed
        return out
