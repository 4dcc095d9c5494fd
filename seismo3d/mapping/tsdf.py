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

from .._validation import as_intrinsics, check_positive
from ..errors import InputError, Seismo3dWarning

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
        _integrate_blocks(self._tsdf, self._weight, self._coords, touched, z, k, m[:3, :3].T.copy(),
                          m[:3, 3].copy(), float(opt.voxel_size), float(trunc), float(opt.max_weight))
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
            _block_ranges(self._coords[: self._n_blocks], float(opt.block_size * opt.voxel_size), k, rot.T.copy(),
                          trans, float(opt.min_depth), float(opt.max_depth), tile, h, w, near, far)
            _raycast(self._tsdf, self._weight, self._grid, self._origin, k, rot, trans, float(opt.voxel_size),
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
            _fill_dense(self._tsdf, self._weight, coords, box_lo, dense)
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
            touched, n_blocks, full = _allocate_blocks(z, k, m[:3, :3].copy(), m[:3, 3].copy(), float(opt.voxel_size),
                                                       int(opt.block_size), float(trunc), self._grid, self._origin,
                                                       self._coords, self._stamp, self._n_blocks, self._frame)
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


# ----------------------------------------------------------------------------------------------------------------------
# numba kernels


@numba.njit(cache=True)
def _allocate_blocks(z, k, rot, trans, vs, b, trunc, grid, origin, coords, stamp, n_blocks, frame):
    """Serial: mark every block within the truncation band along each pixel's ray (every 2nd pixel: a block is
    8 voxels wide, far wider than two pixels' footprint). Returns the touched slots, the block count, and whether the
    pool ran out of slots."""
    h, w = z.shape
    bs = b * vs
    touched = np.empty(len(coords), np.int64)
    n_touched = 0
    full = False
    for v in range(0, h, 2):
        for u in range(0, w, 2):
            d = z[v, u]
            if not d > 0:
                continue
            xc = (u - k[2]) * d / k[0]
            yc = (v - k[3]) * d / k[1]
            norm = np.sqrt(xc * xc + yc * yc + d * d)
            dx, dy, dz = xc / norm, yc / norm, d / norm
            wx = rot[0, 0] * dx + rot[0, 1] * dy + rot[0, 2] * dz
            wy = rot[1, 0] * dx + rot[1, 1] * dy + rot[1, 2] * dz
            wz = rot[2, 0] * dx + rot[2, 1] * dy + rot[2, 2] * dz
            n_steps = int(np.ceil(2.0 * trunc / (0.5 * bs))) + 1
            for s in range(n_steps):
                t = norm - trunc + (2.0 * trunc) * s / max(n_steps - 1, 1)
                px = trans[0] + wx * t
                py = trans[1] + wy * t
                pz = trans[2] + wz * t
                bx = int(np.floor(px / bs)) - origin[0]
                by = int(np.floor(py / bs)) - origin[1]
                bz = int(np.floor(pz / bs)) - origin[2]
                if bx < 0 or by < 0 or bz < 0 or bx >= grid.shape[0] or by >= grid.shape[1] or bz >= grid.shape[2]:
                    continue
                slot = grid[bx, by, bz]
                if slot < 0:
                    if n_blocks >= len(coords):
                        full = True
                        continue
                    slot = n_blocks
                    n_blocks += 1
                    grid[bx, by, bz] = slot
                    coords[slot, 0] = bx + origin[0]
                    coords[slot, 1] = by + origin[1]
                    coords[slot, 2] = bz + origin[2]
                if stamp[slot] != frame:
                    stamp[slot] = frame
                    touched[n_touched] = slot
                    n_touched += 1
    return touched[:n_touched].copy(), n_blocks, full


@numba.njit(parallel=True, cache=True)
def _integrate_blocks(tsdf, weight, coords, touched, z, k, rot_t, trans, vs, trunc, max_weight):
    """Parallel over the touched blocks: project every voxel centre into the depth image and update its running
    average (Curless and Levoy 1996, eq. 5-6; KinectFusion eq. 11-12)."""
    h, w = z.shape
    b = tsdf.shape[1]
    for i in numba.prange(len(touched)):
        slot = touched[i]
        for a in range(b):
            gx = (coords[slot, 0] * b + a) * vs
            for c in range(b):
                gy = (coords[slot, 1] * b + c) * vs
                for e in range(b):
                    gz = (coords[slot, 2] * b + e) * vs
                    qx, qy, qz = gx - trans[0], gy - trans[1], gz - trans[2]
                    xc = rot_t[0, 0] * qx + rot_t[0, 1] * qy + rot_t[0, 2] * qz
                    yc = rot_t[1, 0] * qx + rot_t[1, 1] * qy + rot_t[1, 2] * qz
                    zc = rot_t[2, 0] * qx + rot_t[2, 1] * qy + rot_t[2, 2] * qz
                    if zc <= 0:
                        continue
                    u = int(np.floor(k[0] * xc / zc + k[2] + 0.5))
                    v = int(np.floor(k[1] * yc / zc + k[3] + 0.5))
                    if u < 0 or v < 0 or u >= w or v >= h:
                        continue
                    d = z[v, u]
                    if not d > 0:
                        continue
                    sdf = d - zc
                    if sdf < -trunc:
                        continue
                    f = min(1.0, sdf / trunc)
                    w0 = weight[slot, a, c, e]
                    tsdf[slot, a, c, e] = (tsdf[slot, a, c, e] * w0 + f) / (w0 + 1.0)
                    weight[slot, a, c, e] = min(w0 + 1.0, max_weight)


@numba.njit(cache=True, inline="always")
def _slot(grid, origin, bx, by, bz):
    gx, gy, gz = bx - origin[0], by - origin[1], bz - origin[2]
    if gx < 0 or gy < 0 or gz < 0 or gx >= grid.shape[0] or gy >= grid.shape[1] or gz >= grid.shape[2]:
        return -1
    return grid[gx, gy, gz]


@numba.njit(cache=True)
def _trilinear(tsdf, weight, grid, origin, px, py, pz, vs):
    """TSDF at a world point by trilinear interpolation; NaN when a corner voxel has never been observed."""
    b = tsdf.shape[1]
    shift = int(np.log2(b) + 0.5)
    gx, gy, gz = px / vs, py / vs, pz / vs
    ix, iy, iz = int(np.floor(gx)), int(np.floor(gy)), int(np.floor(gz))
    fx, fy, fz = gx - ix, gy - iy, gz - iz
    lx, ly, lz = ix & (b - 1), iy & (b - 1), iz & (b - 1)
    total = 0.0
    if lx < b - 1 and ly < b - 1 and lz < b - 1:  # the 8 corners share one block: one lookup
        slot = _slot(grid, origin, ix >> shift, iy >> shift, iz >> shift)
        if slot < 0:
            return np.nan
        for a in range(2):
            wa = fx if a else 1.0 - fx
            for c in range(2):
                wc = fy if c else 1.0 - fy
                for e in range(2):
                    if weight[slot, lx + a, ly + c, lz + e] <= 0:
                        return np.nan
                    total += wa * wc * (fz if e else 1.0 - fz) * tsdf[slot, lx + a, ly + c, lz + e]
        return total
    for a in range(2):
        wa = fx if a else 1.0 - fx
        for c in range(2):
            wc = fy if c else 1.0 - fy
            for e in range(2):
                jx, jy, jz = ix + a, iy + c, iz + e
                slot = _slot(grid, origin, jx >> shift, jy >> shift, jz >> shift)
                if slot < 0:
                    return np.nan
                lx2, ly2, lz2 = jx & (b - 1), jy & (b - 1), jz & (b - 1)
                if weight[slot, lx2, ly2, lz2] <= 0:
                    return np.nan
                total += wa * wc * (fz if e else 1.0 - fz) * tsdf[slot, lx2, ly2, lz2]
    return total


@numba.njit(parallel=True, cache=True)
def _raycast(tsdf, weight, grid, origin, k, rot, trans, vs, trunc, near, far, tile, points, normals):
    """Parallel over rows: march each pixel's ray to the first + to - zero crossing of the TSDF (KinectFusion 3.4),
    within the depth range of its tile's blocks, refine it by linear interpolation and take the normal from the
    TSDF's central-difference gradient."""
    h, w = points.shape[0], points.shape[1]
    b = tsdf.shape[1]
    shift = int(np.log2(b) + 0.5)
    bs = b * vs
    for v in numba.prange(h):
        for u in range(w):
            dxc = (u - k[2]) / k[0]
            dyc = (v - k[3]) / k[1]
            norm = np.sqrt(dxc * dxc + dyc * dyc + 1.0)
            dx, dy, dz = dxc / norm, dyc / norm, 1.0 / norm
            wx = rot[0, 0] * dx + rot[0, 1] * dy + rot[0, 2] * dz
            wy = rot[1, 0] * dx + rot[1, 1] * dy + rot[1, 2] * dz
            wz = rot[2, 0] * dx + rot[2, 1] * dy + rot[2, 2] * dz
            z0 = near[v // tile, u // tile]
            z1 = far[v // tile, u // tile]
            if not z1 > z0:
                continue
            t = z0 * norm
            t_end = z1 * norm
            f_prev = np.nan
            t_prev = t
            step = 0.0
            while t < t_end:
                px, py, pz = trans[0] + wx * t, trans[1] + wy * t, trans[2] + wz * t
                ix = int(np.floor(px / vs))
                iy = int(np.floor(py / vs))
                iz = int(np.floor(pz / vs))
                if _slot(grid, origin, ix >> shift, iy >> shift, iz >> shift) < 0:
                    f_prev = np.nan
                    t_prev = t
                    step = 0.5 * bs
                    t += step
                    continue
                f = _trilinear(tsdf, weight, grid, origin, px, py, pz, vs)
                if np.isnan(f):
                    f_prev = np.nan
                    t_prev = t
                    step = vs
                    t += step
                    continue
                if f < 0 and np.isnan(f_prev) and step > vs:
                    # a coarse step jumped over the front half of the band: go back and come in at voxel steps
                    t = t - step + vs
                    step = vs
                    continue
                if f_prev > 0 and f < 0:
                    ts = t_prev + (t - t_prev) * f_prev / (f_prev - f)
                    sx, sy, sz = trans[0] + wx * ts, trans[1] + wy * ts, trans[2] + wz * ts
                    nx = _trilinear(tsdf, weight, grid, origin, sx + vs, sy, sz, vs) - \
                        _trilinear(tsdf, weight, grid, origin, sx - vs, sy, sz, vs)
                    ny = _trilinear(tsdf, weight, grid, origin, sx, sy + vs, sz, vs) - \
                        _trilinear(tsdf, weight, grid, origin, sx, sy - vs, sz, vs)
                    nz = _trilinear(tsdf, weight, grid, origin, sx, sy, sz + vs, vs) - \
                        _trilinear(tsdf, weight, grid, origin, sx, sy, sz - vs, vs)
                    nn = np.sqrt(nx * nx + ny * ny + nz * nz)
                    if nn > 0 and not np.isnan(nn):
                        # world -> camera: R^T (x - t); the gradient points to free space, i.e. towards the camera
                        qx, qy, qz = sx - trans[0], sy - trans[1], sz - trans[2]
                        points[v, u, 0] = rot[0, 0] * qx + rot[1, 0] * qy + rot[2, 0] * qz
                        points[v, u, 1] = rot[0, 1] * qx + rot[1, 1] * qy + rot[2, 1] * qz
                        points[v, u, 2] = rot[0, 2] * qx + rot[1, 2] * qy + rot[2, 2] * qz
                        nx, ny, nz = nx / nn, ny / nn, nz / nn
                        normals[v, u, 0] = rot[0, 0] * nx + rot[1, 0] * ny + rot[2, 0] * nz
                        normals[v, u, 1] = rot[0, 1] * nx + rot[1, 1] * ny + rot[2, 1] * nz
                        normals[v, u, 2] = rot[0, 2] * nx + rot[1, 2] * ny + rot[2, 2] * nz
                    break
                if f_prev < 0 and f > 0:
                    break  # a back face: the ray left a surface from behind
                f_prev = f
                t_prev = t
                step = max(vs, 0.8 * f * trunc) if f > 0 else vs
                t += step


@numba.njit(cache=True)
def _block_ranges(coords, bs, k, rot_t, trans, min_depth, max_depth, tile, h, w, near, far):
    """Splat every allocated block's bounding box into the tiles of the image it covers: per tile, the nearest and
    farthest depth of its blocks (the raycast's bounds, as InfiniTAM's range image; Kaehler et al. 2015)."""
    th, tw = near.shape
    for i in range(len(coords)):
        zmin, zmax = np.inf, -np.inf
        umin, umax, vmin, vmax = np.inf, -np.inf, np.inf, -np.inf
        behind = False
        for c in range(8):
            px = (coords[i, 0] + (c & 1)) * bs - trans[0]
            py = (coords[i, 1] + ((c >> 1) & 1)) * bs - trans[1]
            pz = (coords[i, 2] + ((c >> 2) & 1)) * bs - trans[2]
            x = rot_t[0, 0] * px + rot_t[0, 1] * py + rot_t[0, 2] * pz
            y = rot_t[1, 0] * px + rot_t[1, 1] * py + rot_t[1, 2] * pz
            z = rot_t[2, 0] * px + rot_t[2, 1] * py + rot_t[2, 2] * pz
            zmin = min(zmin, z)
            zmax = max(zmax, z)
            if z < min_depth:
                behind = True
                continue
            u = k[0] * x / z + k[2]
            v = k[1] * y / z + k[3]
            umin, umax = min(umin, u), max(umax, u)
            vmin, vmax = min(vmin, v), max(vmax, v)
        if zmax < min_depth or zmin > max_depth:
            continue
        if behind:  # the block reaches behind the near plane: it may cover any pixel
            umin, umax, vmin, vmax = 0.0, w - 1.0, 0.0, h - 1.0
        if umax < 0 or vmax < 0 or umin > w - 1 or vmin > h - 1:
            continue
        t0 = max(int(np.floor(umin)) // tile, 0)
        t1 = min(int(np.ceil(umax)) // tile, tw - 1)
        s0 = max(int(np.floor(vmin)) // tile, 0)
        s1 = min(int(np.ceil(vmax)) // tile, th - 1)
        z0 = max(zmin, min_depth)
        z1 = min(zmax, max_depth)
        for a in range(s0, s1 + 1):
            for b in range(t0, t1 + 1):
                if z0 < near[a, b]:
                    near[a, b] = z0
                if z1 > far[a, b]:
                    far[a, b] = z1


@numba.njit(cache=True)
def _fill_dense(tsdf, weight, coords, box_lo, out):
    """Copy observed voxels of the blocks overlapping ``out`` (voxel box starting at ``box_lo``) into it."""
    b = tsdf.shape[1]
    nx, ny, nz = out.shape
    for slot in range(len(coords)):
        x0 = coords[slot, 0] * b - box_lo[0]
        y0 = coords[slot, 1] * b - box_lo[1]
        z0 = coords[slot, 2] * b - box_lo[2]
        if x0 + b <= 0 or x0 >= nx:
            continue
        for a in range(b):
            x = x0 + a
            if x < 0 or x >= nx:
                continue
            for c in range(b):
                y = y0 + c
                if y < 0 or y >= ny:
                    continue
                for e in range(b):
                    zz = z0 + e
                    if zz < 0 or zz >= nz:
                        continue
                    if weight[slot, a, c, e] > 0:
                        out[x, y, zz] = tsdf[slot, a, c, e]
