"""Correspondence strategies of the ICP engine: how each moved source point finds its target point.

:func:`~seismo3d.registration.icp` and :func:`~seismo3d.registration.fused_icp` take ``correspondences=`` one of:

* :class:`NearestNeighbourCorrespondences` (the default): the nearest target point within the stage's maximum
  distance, by a hashed voxel grid (:class:`~seismo3d.geometry.voxel_hash.VoxelHashIndex`, cells of a fraction of
  that distance, compiled, one thread). Works on any point set; a query costs O(1) per point.
* :class:`ProjectiveCorrespondences`: projective data association for *organised* targets (a depth or raycast image
  whose pixels are the target points): each moved source point is projected into the target camera and takes the
  target point of the pixel it lands on, kept when it is within the maximum distance. O(1) per point, no tree; the
  KinectFusion association (Newcombe et al. 2011, section 3.5; Blais and Levine 1995).

A strategy is a small frozen object; the engine calls ``strategy.index(target, centre=..., scale=...)`` once per
target (points in the engine's normalised frame, ``(p - centre) / scale``) and then ``index.query(moved, dmax)`` every
iteration, which returns ``(dist, idx)`` like ``cKDTree.query``: ``dist`` (N,) in normalised units, ``inf`` where
there is no correspondence, and ``idx`` (N,) target rows (``len(target)`` where there is none).

References
----------
Newcombe, R. A., Izadi, S., Hilliges, O., Molyneaux, D., Kim, D., Davison, A. J., Kohli, P., Shotton, J., Hodges, S.,
Fitzgibbon, A. (2011). KinectFusion: Real-time dense surface mapping and tracking. ISMAR, 127-136.
doi:10.1109/ISMAR.2011.6092378
Blais, G., Levine, M. D. (1995). Registering multiview range data to create 3D computer objects. IEEE TPAMI 17(8),
820-824. doi:10.1109/34.400574
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from .._validation import as_intrinsics, check_positive
from ..errors import InputError
from ..geometry.voxel_hash import VoxelHashIndex

__all__ = ["NearestNeighbourCorrespondences", "ProjectiveCorrespondences", "as_correspondences"]

@dataclass(frozen=True)
class NearestNeighbourCorrespondences:
    """Exact nearest-neighbour correspondences within the stage's distance (the engine's default), by a hashed voxel
    grid over the target built once per distance (:class:`~seismo3d.geometry.voxel_hash.VoxelHashIndex`).

    Attributes
    ----------
    cell_fraction : float
        Voxel edge as a fraction of the stage's maximum distance (speed only: the correspondences are the exact
        nearest neighbours, as a KD-tree finds them, for any value).

    Raises
    ------
    InputError
        A non-positive ``cell_fraction``.
    """

    cell_fraction: float = 1.0

    def __post_init__(self):
        check_positive(self.cell_fraction, "cell_fraction")

    def index(self, target, *, centre=None, scale=1.0):
        """The nearest-neighbour index of ``target`` ((M, d) float64, the engine's normalised frame); ``centre`` and
        ``scale`` are unused (nearest neighbours do not depend on the frame)."""
        return _GridIndex(target, self.cell_fraction)


class _GridIndex:
    """One voxel hash of the target per maximum distance asked (a schedule asks for a few)."""

    def __init__(self, target, cell_fraction):
        self.target = target
        self.cell_fraction = cell_fraction
        self.grids = {}

    def query(self, moved, dmax):
        grid = self.grids.get(dmax)
        if grid is None:
            grid = self.grids[dmax] = VoxelHashIndex(self.target, self.cell_fraction * dmax)
        return grid.query(moved, dmax)


@dataclass(frozen=True, eq=False)
class ProjectiveCorrespondences:
    """Projective data association into an organised target (KinectFusion).

    The target points must be the valid pixels of one camera image, in that camera's frame (x right, y down,
    z forward, metres), in the order given by ``pixel_index``. A moved source point ``x`` is projected to the pixel
    ``(round(fx x/z + cx), round(fy y/z + cy))``; its correspondence is that pixel's target point when the pixel holds
    one and the two are within the stage's maximum distance.

    Attributes
    ----------
    intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
        Pinhole intrinsics of the target image, pixels.
    pixel_index : (H, W) int ndarray
        Row of the target point seen at each pixel, -1 where the image has none.
    window : int
        Half-width in pixels of a search window around the projected pixel: the closest target point within it is
        taken (0: the projected pixel only, KinectFusion's association). A small window (1-2 pixels) lets the
        correspondence slide along the surface as a nearest neighbour would, which projective association alone
        does poorly where the geometry constrains a direction weakly; it still costs O(window^2) per point, no tree.

    Raises
    ------
    InputError
        If ``pixel_index`` is not a 2D integer image or the intrinsics are malformed.

    Notes
    -----
    Use it with the whole organised target: a voxel-downsampled target (``voxel_size=``) no longer matches the pixel
    map and is refused by :meth:`index`.
    """

    intrinsics: object
    pixel_index: np.ndarray
    window: int = 0

    def __post_init__(self):
        if int(self.window) != self.window or self.window < 0:
            raise InputError(f"window must be a whole number of pixels >= 0; got {self.window!r}")
        pix = np.asarray(self.pixel_index)
        if pix.ndim != 2 or not np.issubdtype(pix.dtype, np.integer):
            raise InputError(f"pixel_index must be a 2D integer image (row of the target point per pixel, -1 for "
                             f"none); got {pix.dtype} {pix.shape}")
        object.__setattr__(self, "pixel_index", np.ascontiguousarray(pix, dtype=np.int64))
        object.__setattr__(self, "intrinsics", as_intrinsics(self.intrinsics))

    @classmethod
    def from_mask(cls, intrinsics, valid, *, window: int = 0) -> ProjectiveCorrespondences:
        """The strategy for target points ``points_image[valid]`` (row-major order of the valid pixels).

        Parameters
        ----------
        intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
        valid : (H, W) bool array_like
            Pixels that hold a target point.
        window : int
            See the class.
        """
        valid = np.asarray(valid, dtype=bool)
        if valid.ndim != 2:
            raise InputError(f"valid must be a (H, W) mask; got shape {valid.shape}")
        pix = np.full(valid.shape, -1, np.int64)
        pix[valid] = np.arange(int(valid.sum()))
        return cls(intrinsics, pix, int(window))

    def index(self, target, *, centre=None, scale=1.0):
        """Prepare the association for ``target`` ((M, 3) float64 in the engine's normalised frame
        ``(p - centre) / scale``).

        Raises
        ------
        InputError
            If the target is not 3D or does not hold one point per valid pixel of ``pixel_index``.
        """
        n_valid = int((self.pixel_index >= 0).sum())
        if target.ndim != 2 or target.shape[1] != 3 or len(target) != n_valid:
            raise InputError(f"projective correspondences need the whole organised 3D target ({n_valid} points, one "
                             f"per valid pixel); got {target.shape}. Do not voxel-downsample the target "
                             "(voxel_size=None) and pass the points in pixel_index order")
        c = np.zeros(3) if centre is None else np.asarray(centre, dtype=np.float64)
        return _ProjectiveIndex(target, self.pixel_index, self.intrinsics, c, float(scale), int(self.window))


class _ProjectiveIndex:
    def __init__(self, target, pixel_index, intrinsics, centre, scale, window):
        self.window = window
        self.target = target
        self.pixel_index = pixel_index
        self.fx, self.fy, self.cx, self.cy = intrinsics
        self.centre = centre
        self.scale = scale

    def query(self, moved, dmax):
        moved = np.ascontiguousarray(moved, dtype=np.float64)
        dist = np.empty(len(moved))
        idx = np.empty(len(moved), np.int64)
        _project_and_match(moved, self.target, self.pixel_index, self.fx, self.fy, self.cx, self.cy, self.centre,
                           self.scale, float(dmax), self.window, dist, idx)
        return dist, idx


@numba.njit(cache=True, no_cfunc_wrapper=True)
def _project_and_match(moved, target, pixel_index, fx, fy, cx, cy, centre, scale, dmax, window, dist, idx):
    """Project each moved point (normalised frame) into the target image and take the closest target point within
    ``window`` pixels of that pixel (KinectFusion's projective association for window 0); ``inf`` /
    ``len(target)`` where none is within ``dmax``."""
    n = len(target)
    h, w = pixel_index.shape
    for i in range(len(moved)):
        dist[i] = np.inf
        idx[i] = n
        x = moved[i, 0] * scale + centre[0]
        y = moved[i, 1] * scale + centre[1]
        z = moved[i, 2] * scale + centre[2]
        if z <= 1e-9:
            continue
        u0 = int(np.floor(fx * x / z + cx + 0.5))
        v0 = int(np.floor(fy * y / z + cy + 0.5))
        best = dmax * dmax
        for v in range(v0 - window, v0 + window + 1):
            if v < 0 or v >= h:
                continue
            for u in range(u0 - window, u0 + window + 1):
                if u < 0 or u >= w:
                    continue
                j = pixel_index[v, u]
                if j < 0:
                    continue
                dx = moved[i, 0] - target[j, 0]
                dy = moved[i, 1] - target[j, 1]
                dz = moved[i, 2] - target[j, 2]
                d2 = dx * dx + dy * dy + dz * dz
                if d2 <= best:
                    best = d2
                    dist[i] = np.sqrt(d2)
                    idx[i] = j


def as_correspondences(value):
    """Return the strategy object for ``correspondences=`` (None: :class:`NearestNeighbourCorrespondences`).

    Raises
    ------
    InputError
        If ``value`` is not None and has no ``index`` method.
    """
    if value is None:
        return NearestNeighbourCorrespondences()
    if type(value).__module__ == "builtins" or not callable(getattr(value, "index", None)):
        raise InputError("correspondences must be NearestNeighbourCorrespondences(), ProjectiveCorrespondences(...) "
                         f"or None; got {type(value).__name__}")
    return value
