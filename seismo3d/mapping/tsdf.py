"""The map: a truncated signed distance function (TSDF) in voxel blocks allocated where the surface is.

Each depth frame is fused into a TSDF (Curless and Levoy 1996) as in KinectFusion (Newcombe et al. 2011): every voxel
near the measured surface keeps a weighted running average of its signed distance to the surface along the optical
axis, truncated to ``[-truncation, truncation]`` and stored divided by ``truncation`` (so in [-1, 1]). Memory is
bounded by allocating voxels only in blocks of ``block_size``^3 that the truncation band of some depth pixel touches
(voxel hashing, Niessner et al. 2013); a coarse table of block slots, grown as the camera explores, replaces the hash
table so that every voxel lookup is O(1) and branch-free in numba. The surface predicted at a camera pose is a
raycast of the zero crossing (with normals from the TSDF gradient), the model that frame-to-model tracking registers
each new frame against; :meth:`TSDFVolume.extract_mesh` runs marching cubes (scikit-image) over the blocks.

References
----------
Curless, B., Levoy, M. (1996). A volumetric method for building complex models from range images. SIGGRAPH, 303-312.
doi:10.1145/237170.237269
Newcombe, R. A. et al. (2011). KinectFusion: Real-time dense surface mapping and tracking. ISMAR, 127-136.
doi:10.1109/ISMAR.2011.6092378
Niessner, M., Zollhoefer, M., Izadi, S., Stamminger, M. (2013). Real-time 3D reconstruction at scale using voxel
hashing. ACM TOG 32(6), 169. doi:10.1145/2508363.2508374
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numba
import numpy as np

from .._threads import run_threads
from .._validation import as_intrinsics, check_positive
from ..errors import InputError, Seismo3dWarning
from . import _tsdf_kernels as kernels

__all__ = ["TSDFOptions", "TSDFVolume", "SurfacePrediction", "TriangleMesh"]


@dataclass(frozen=True)
class TSDFOptions:
    """Options of the TSDF map.

    Attributes
    ----------
    voxel_size : float
        Voxel edge, metres.
    truncation : float or None
        Truncation distance, metres (default 4 voxels).
    block_size : {2, 4, 8, 16, 32}
        Voxels per block edge (blocks are allocated whole).
    max_weight : float
        Cap of the per-voxel fusion weight: older measurements fade once it is reached, so that a moved object is
        carved away after about this many frames.
    min_depth, max_depth : float
        Depth range fused and raycast, metres (the Kinect's reliable range by default).
    max_blocks : int
        Most blocks the map may hold (memory bound: 8 bytes per voxel, so 4 KiB per 8^3 block); past it new surface
        is not fused and a warning is issued.
    """

    voxel_size: float = 0.01
    truncation: float | None = None
    block_size: int = 8
    max_weight: float = 64.0
    min_depth: float = 0.2
    max_depth: float = 4.0
    max_blocks: int = 200_000

    def __post_init__(self):
        check_positive(self.voxel_size, "voxel_size")
        if self.truncation is not None:
            check_positive(self.truncation, "truncation")
            if self.truncation < self.voxel_size:
                raise InputError(f"truncation ({self.truncation} m) must be at least one voxel ({self.voxel_size} m)")
        if self.block_size not in (2, 4, 8, 16, 32):
            raise InputError(f"block_size must be a power of two from 2 to 32; got {self.block_size!r}")
        check_positive(self.max_weight, "max_weight")
        check_positive(self.min_depth, "min_depth", allow_zero=True)
        if not self.max_depth > self.min_depth:
            raise InputError(f"max_depth ({self.max_depth}) must exceed min_depth ({self.min_depth})")
        if int(self.max_blocks) < 1:
            raise InputError(f"max_blocks must be >= 1; got {self.max_blocks!r}")

    @property
    def truncation_distance(self) -> float:
        """The truncation distance in metres (``truncation`` or 4 voxels)."""
        return 4.0 * self.voxel_size if self.truncation is None else float(self.truncation)


@dataclass(frozen=True)
class SurfacePrediction:
    """The map's surface seen from a camera pose (a raycast).

    Attributes
    ----------
    points : (H, W, 3) float64 ndarray
        Surface points in the camera frame, metres; NaN where the ray meets no surface.
    normals : (H, W, 3) float64 ndarray
        Unit surface normals in the camera frame (facing the camera), NaN where there is no point.
    pose : (4, 4) float64 ndarray
        The camera-to-world pose the prediction was made from.
    intrinsics : tuple (fx, fy, cx, cy)
        Pixels of this prediction.
    """

    points: np.ndarray
    normals: np.ndarray
    pose: np.ndarray
    intrinsics: tuple

    @property
    def valid(self) -> np.ndarray:
        """(H, W) bool ndarray: pixels that hold a surface point."""
        return np.isfinite(self.points[..., 2])


@dataclass(frozen=True)
class TriangleMesh:
    """A triangle mesh in world coordinates.

    Attributes
    ----------
    vertices : (V, 3) float64 ndarray
        Metres.
    faces : (F, 3) int64 ndarray
        Vertex indices, counter-clockwise seen from outside (the side the camera saw).
    normals : (V, 3) float64 ndarray
        Unit vertex normals.
    """

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray


class TSDFVolume:
    """A TSDF map in voxel blocks (see the module docstring).

    Parameters
    ----------
    options : TSDFOptions, optional

    Examples
    --------
    >>> volume = TSDFVolume(TSDFOptions(voxel_size=0.02))                          # doctest: +SKIP
    >>> volume.integrate(frame.depth, frame.intrinsics, pose)                      # doctest: +SKIP
    >>> prediction = volume.raycast(frame.intrinsics, pose, shape=(240, 320))      # doctest: +SKIP
    """

    def __init__(self, options: TSDFOptions | None = None):
        self.options = TSDFOptions() if options is None else options
        self.reset()

    def reset(self) -> None:
        """Forget every measurement (keep the options)."""
        b = int(self.options.block_size)
        capacity = min(1024, int(self.options.max_blocks))
        self._tsdf = np.ones((capacity, b, b, b), np.float32)
        self._weight = np.zeros((capacity, b, b, b), np.float32)
        self._coords = np.zeros((capacity, 3), np.int64)
        self._n_blocks = 0
        self._grid = np.full((1, 1, 1), -1, np.int32)
        self._origin = np.zeros(3, np.int64)
        self._stamp = np.zeros(capacity, np.int64)
        self._frame = 0
        self._full_warned = False

    # ---------------------------------------------------------------------------------------------------------------
    @property
    def n_blocks(self) -> int:
        """Number of allocated blocks."""
        return int(self._n_blocks)

    @property
    def nbytes(self) -> int:
        """Bytes held by the voxel blocks and the block table."""
        return int(self._tsdf.nbytes + self._weight.nbytes + self._coords.nbytes + self._grid.nbytes
                   + self._stamp.nbytes)

    def integrate(self, depth, intrinsics, pose, *, mask=None) -> int:
        """Fuse one depth image taken from ``pose``.

        Parameters
        ----------
        depth : (H, W) array_like
            Depth along the optical axis, metres; NaN or <= 0 where invalid.
        intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
            Of the depth image, pixels.
        pose : (4, 4) array_like
            Camera-to-world transform, metres.
        mask : (H, W) bool array_like, optional
            Pixels to fuse (default every valid pixel); e.g. False on moving objects.

        Returns
        -------
        int
            Number of blocks updated.

        Raises
        ------
        InputError
            Malformed depth, intrinsics, pose or mask.
        """
        z = _as_depth(depth)
        k = np.array(as_intrinsics(intrinsics), np.float64)
        m = _as_pose(pose)
        if mask is not None:
            mask = np.asarray(mask, dtype=bool)
            if mask.shape != z.shape:
                raise InputError(f"mask {mask.shape} must have the depth image's shape {z.shape}")
            z = np.where(mask, z, np.nan).astype(np.float32)
        opt = self.options
        z = np.where((z >= opt.min_depth) & (z <= opt.max_depth), z, np.nan).astype(np.float32)
        if not np.isfinite(z).any():
            return 0
        trunc = opt.truncation_distance
        self._ensure_grid(z, k, m, trunc)
        touched = self._allocate(z, k, m, trunc)
        run_threads(kernels.integrate_blocks, max(1, min(numba.get_num_threads(), len(touched))), self._tsdf,
                    self._weight, self._coords, touched, z, k, m[:3, :3].T.copy(), m[:3, 3].copy(),
                    float(opt.voxel_size), float(trunc), float(opt.max_weight))
        return int(len(touched))

    def raycast(self, intrinsics, pose, *, shape) -> SurfacePrediction:
        """Predict the surface seen from ``pose`` by marching rays through the TSDF to its zero crossing.

        Parameters
        ----------
        intrinsics : CameraIntrinsics, (3, 3) array_like or (fx, fy, cx, cy)
            Pixels of the output image.
        pose : (4, 4) array_like
            Camera-to-world transform, metres.
        shape : (int, int)
            Output (H, W) in pixels.

        Returns
        -------
        SurfacePrediction
            Points and normals in the camera frame.
        """
        k = np.array(as_intrinsics(intrinsics), np.float64)
        m = _as_pose(pose)
        h, w = (int(v) for v in shape)
        points = np.full((h, w, 3), np.nan)
        normals = np.full((h, w, 3), np.nan)
        opt = self.options
        if self._n_blocks:
            rot, trans = m[:3, :3].copy(), m[:3, 3].copy()
            # per 8 x 8 tile of the image, the depth range the allocated blocks cover: rays march only there
            tile = 8
            near = np.full(((h + tile - 1) // tile, (w + tile - 1) // tile), np.inf)
            far = np.zeros_like(near)
            kernels.block_ranges(self._coords[: self._n_blocks], float(opt.block_size * opt.voxel_size), k,
                                 rot.T.copy(), trans, float(opt.min_depth), float(opt.max_depth), tile, h, w, near, far)
            run_threads(kernels.raycast, max(1, min(numba.get_num_threads(), h)), self._tsdf, self._weight,
                        self._grid, self._origin, k, rot, trans, float(opt.voxel_size),
                        float(opt.truncation_distance), near, far, tile, points, normals)
        return SurfacePrediction(points=points, normals=normals, pose=m, intrinsics=tuple(k))

    def extract_mesh(self, *, slab: int = 96) -> TriangleMesh:
        """Marching cubes (scikit-image, Lewiner et al. 2003) on the zero level of the TSDF.

        The blocks are copied into dense slabs of at most ``slab`` voxels along x, one at a time, so the memory
        used stays a few times the map's own.

        Parameters
        ----------
        slab : int
            Slab thickness in voxels.

        Returns
        -------
        TriangleMesh
            Empty (no vertex) when the map has no surface yet.
        """
        from skimage.measure import marching_cubes

        vs = float(self.options.voxel_size)
        b = int(self.options.block_size)
        empty = TriangleMesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros((0, 3)))
        if not self._n_blocks:
            return empty
        coords = self._coords[: self._n_blocks]
        lo = coords.min(axis=0) * b
        hi = (coords.max(axis=0) + 1) * b
        verts, faces, norms, offset = [], [], [], 0
        for x0 in range(int(lo[0]), int(hi[0]) - 1, slab):
            x1 = min(x0 + slab + 1, int(hi[0]))  # one voxel of overlap with the next slab
            box_lo = np.array([x0, lo[1], lo[2]], np.int64)
            dense = np.full((x1 - x0, int(hi[1] - lo[1]), int(hi[2] - lo[2])), np.nan, np.float32)
            kernels.fill_dense(self._tsdf, self._weight, coords, box_lo, dense)
            valid = np.isfinite(dense)
            if valid.sum() < 8 or min(dense.shape) < 2:
                continue
            values = np.where(valid, dense, 1.0)
            if values.min() > 0 or values.max() < 0:
                continue
            try:
                v, f, n, _ = marching_cubes(values, level=0.0, mask=valid, allow_degenerate=False)
            except (ValueError, RuntimeError):
                continue
            verts.append((v + box_lo) * vs)
            faces.append(f[:, ::-1] + offset)  # outward = towards positive TSDF (free space)
            norms.append(-n)
            offset += len(v)
        if not verts:
            return empty
        normals = np.concatenate(norms).astype(np.float64)
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
        return TriangleMesh(np.concatenate(verts).astype(np.float64), np.concatenate(faces).astype(np.int64),
                            normals)

    # ---------------------------------------------------------------------------------------------------------------
    def _ensure_grid(self, z, k, m, trunc):
        """Grow the block table to cover this frame's points (plus the truncation band)."""
        b = self.options.block_size * self.options.voxel_size
        v, u = np.nonzero(np.isfinite(z[::4, ::4]))  # every 4th pixel: the bounds need not be exact, the margin
        v, u = 4 * v, 4 * u                           # below covers the rest (allocation ignores blocks outside)
        zz = z[v, u].astype(np.float64)
        cam = np.stack([(u - k[2]) * zz / k[0], (v - k[3]) * zz / k[1], zz], axis=1)
        world = cam @ m[:3, :3].T + m[:3, 3]
        lo = np.floor((np.minimum(world.min(axis=0), m[:3, 3]) - trunc) / b).astype(np.int64) - 1
        hi = np.floor((np.maximum(world.max(axis=0), m[:3, 3]) + trunc) / b).astype(np.int64) + 2
        cur_lo, cur_hi = self._origin, self._origin + np.array(self._grid.shape)
        if np.all(lo >= cur_lo) and np.all(hi <= cur_hi):
            return
        if self._n_blocks == 0:
            new_lo, new_hi = lo - 4, hi + 4
        else:
            new_lo, new_hi = np.minimum(lo - 4, cur_lo), np.maximum(hi + 4, cur_hi)
        grid = np.full(tuple(int(s) for s in new_hi - new_lo), -1, np.int32)
        if self._n_blocks:
            c = self._coords[: self._n_blocks] - new_lo
            grid[c[:, 0], c[:, 1], c[:, 2]] = np.arange(self._n_blocks, dtype=np.int32)
        self._grid, self._origin = grid, new_lo.astype(np.int64)

    def _allocate(self, z, k, m, trunc):
        """Allocate the blocks the truncation band of the frame's pixels touches; return the touched slots."""
        opt = self.options
        while True:
            capacity = len(self._tsdf)
            self._frame += 1  # a fresh stamp per attempt: a retry after growing the pool lists every block again
            touched, n_blocks, full = kernels.allocate_blocks(z, k, m[:3, :3].copy(), m[:3, 3].copy(),
                                                              float(opt.voxel_size), int(opt.block_size), float(trunc),
                                                              self._grid, self._origin, self._coords, self._stamp,
                                                              self._n_blocks, self._frame)
            self._n_blocks = int(n_blocks)
            if not full:
                return touched
            if capacity >= opt.max_blocks:
                if not self._full_warned:
                    warnings.warn(f"the map holds max_blocks={opt.max_blocks} blocks ({self.nbytes / 2**20:.0f} MiB); "
                                  "new surface is no longer fused: raise TSDFOptions.max_blocks or voxel_size",
                                  Seismo3dWarning, stacklevel=3)
                    self._full_warned = True
                return touched
            self._grow(min(2 * capacity, int(opt.max_blocks)))

    def _grow(self, capacity):
        b = int(self.options.block_size)
        n = len(self._tsdf)
        tsdf = np.ones((capacity, b, b, b), np.float32)
        weight = np.zeros((capacity, b, b, b), np.float32)
        coords = np.zeros((capacity, 3), np.int64)
        stamp = np.zeros(capacity, np.int64)
        tsdf[:n], weight[:n], coords[:n], stamp[:n] = self._tsdf, self._weight, self._coords, self._stamp
        self._tsdf, self._weight, self._coords, self._stamp = tsdf, weight, coords, stamp


def _as_depth(depth):
    z = np.asarray(depth)
    if z.ndim != 2 or z.size == 0 or not np.issubdtype(z.dtype, np.number):
        raise InputError(f"depth must be a numeric (H, W) image in metres; got {z.dtype} {z.shape}")
    z = z.astype(np.float32)
    z[~(z > 0)] = np.nan
    return z


def _as_pose(pose):
    m = np.asarray(pose, dtype=np.float64)
    if m.shape != (4, 4) or not np.all(np.isfinite(m)) or not np.allclose(m[3], [0, 0, 0, 1]):
        raise InputError(f"pose must be a finite (4, 4) camera-to-world transform; got shape {m.shape}")
    return m
