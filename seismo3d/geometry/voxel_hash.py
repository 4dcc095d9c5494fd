"""Exact nearest neighbours within a maximum distance by a hashed voxel grid (the ICP engine's correspondence search).

The points are sorted by voxel and an open-addressing hash table maps a voxel's integer coordinates to its run of
points. A query looks at its own voxel first, then at the voxels within ``ceil(max_distance / cell)`` rings, skipping
every voxel whose box is farther than the best distance found so far, so the answer is the exact nearest point within
the distance (the same as ``scipy.spatial.cKDTree.query(..., distance_upper_bound=...)`` up to ties). With a cell of
about half the search distance a query visits a handful of voxels of a few points each: O(1) per point instead of a
tree descent. This is the voxel-hash association of KISS-ICP and small_gicp, made exact.

References
----------
Vizzo, I., Guadagnino, T., Mersch, B., Wiesmann, L., Behley, J., Stachniss, C. (2023). KISS-ICP: In defense of
point-to-point ICP. IEEE RA-L 8(2), 1029-1036. doi:10.1109/LRA.2023.3236571
Koide, K. (2024). small_gicp: Efficient and parallel algorithms for point cloud registration. JOSS 9(100), 6948.
doi:10.21105/joss.06948
Teschner, M., Heidelberger, B., Mueller, M., Pomeranets, D., Gross, M. (2003). Optimized spatial hashing for collision
detection of deformable objects. VMV, 47-54 (the hash of the voxel coordinates).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._threads import MIN_QUERIES_PER_THREAD, run_threads
from .._validation import as_points, check_positive
from ..errors import InputError
from .neighbours import axis_bounds

__all__ = ["VoxelHashIndex"]

_BITS = 21  # bits per voxel coordinate in the packed key
_LIMIT = (1 << _BITS) - 8  # voxel coordinates allowed per axis (the cell grows beyond that)


class VoxelHashIndex:
    """Nearest-neighbour index of a 2D or 3D point set for searches within a maximum distance.

    Parameters
    ----------
    points : (M, d) array_like, d in {2, 3}
        The indexed points (any length unit; 2D points are searched as 3D points with z = 0).
    cell : float
        Voxel edge, in the points' unit. Queries are exact for any cell; about half the search distance is fastest.
        A cell so small that the grid would have more than about 2e6 voxels per axis is enlarged.

    Raises
    ------
    InputError
        Bad points (NaN, wrong shape, fewer than one point) or a non-positive cell.

    Examples
    --------
    >>> import numpy as np
    >>> index = VoxelHashIndex(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), cell=0.5)
    >>> dist, idx = index.query(np.array([[0.9, 0.1, 0.0], [5.0, 5.0, 5.0]]), 1.0)
    >>> idx.tolist(), bool(np.isinf(dist[1]))
    ([1, 2], True)
    """

    def __init__(self, points, cell: float):
        pts = as_points(points, "points")
        if pts.shape[1] not in (2, 3):
            raise InputError(f"VoxelHashIndex indexes 2D or 3D points; got {pts.shape[1]}D")
        self.n = len(pts)
        self.dim = pts.shape[1]
        pts = _as_3d(pts)
        self.origin, top = axis_bounds(pts)
        extent = float((top - self.origin).max())
        self.cell = max(check_positive(cell, "cell"), extent / _LIMIT, 1e-300)
        keys = _voxel_keys(pts, self.origin, self.cell)
        order = np.argsort(keys, kind="stable")
        self.order = order.astype(np.int64)
        self.points = np.ascontiguousarray(pts[order])
        sorted_keys = keys[order]
        starts = np.flatnonzero(np.r_[True, sorted_keys[1:] != sorted_keys[:-1]])
        size = 1 << int(np.ceil(np.log2(2 * len(starts) + 1)))
        self.table_keys = np.full(size, -1, np.int64)
        self.table_start = np.zeros(size, np.int64)
        self.table_stop = np.zeros(size, np.int64)
        _fill_table(sorted_keys, starts, np.r_[starts[1:], len(keys)], 64 - _log2(size), self.table_keys,
                    self.table_start, self.table_stop)

    def query(self, queries, max_distance: float):
        """The nearest indexed point of each query within ``max_distance``.

        Parameters
        ----------
        queries : (N, d) array_like
            Points, same dimension and unit as the indexed points.
        max_distance : float
            Search radius (a neighbour must be strictly closer).

        Returns
        -------
        dist : (N,) float64 ndarray
            Distance to the nearest point, ``inf`` where none is within ``max_distance``.
        idx : (N,) int64 ndarray
            Row of that point in the indexed points, ``M`` (the number of points) where there is none, as
            ``cKDTree.query`` returns.

        Raises
        ------
        InputError
            Queries of another dimension, or a non-positive distance.
        """
        q = np.asarray(queries, dtype=np.float64)
        if q.ndim != 2 or q.shape[1] != self.dim:
            raise InputError(f"queries must be (N, {self.dim}) like the indexed points; got shape {q.shape}")
        dmax = check_positive(max_distance, "max_distance")
        rings = int(np.ceil(dmax / self.cell))
        dist = np.empty(len(q))
        idx = np.empty(len(q), np.int64)
        # each query point independent of the others: shares of the queries on numba's threads
        n_threads = max(1, min(numba.get_num_threads(), len(q) // MIN_QUERIES_PER_THREAD))
        run_threads(_query, n_threads, np.ascontiguousarray(_as_3d(q)), self.points, self.order, self.origin,
                    self.cell, rings, dmax, self.table_keys, 64 - _log2(len(self.table_keys)), self.table_start,
                    self.table_stop, dist, idx)
        return dist, idx


def _as_3d(pts):
    return pts if pts.shape[1] == 3 else np.column_stack([pts, np.zeros(len(pts))])


def _voxel_keys(pts, origin, cell):
    ijk = np.floor((pts - origin) / cell).astype(np.int64)
    return (ijk[:, 0] << (2 * _BITS)) | (ijk[:, 1] << _BITS) | ijk[:, 2]


@numba.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _slot(key, shift):
    """Fibonacci hashing: the top bits of the key times 2^64 / golden ratio (low bits would ignore x and y)."""
    h = np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)
    return np.int64(h >> np.uint64(shift))


def _log2(size: int) -> int:
    """log2 of a power of two (in Python: a kernel of its own compiled 0.1 CPU s on a first run)."""
    return int(size).bit_length() - 1


@numba.njit(cache=True, no_cfunc_wrapper=True)
def _fill_table(sorted_keys, starts, stops, shift, table_keys, table_start, table_stop):
    # shift: 64 - log2 of the table's size (a power of two)
    mask = len(table_keys) - 1
    for c in range(len(starts)):
        key = sorted_keys[starts[c]]
        s = _slot(key, shift)
        while table_keys[s] != -1:
            s = (s + 1) & mask
        table_keys[s] = key
        table_start[s] = starts[c]
        table_stop[s] = stops[c]


@numba.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _lookup(key, table_keys, mask, shift):
    s = _slot(key, shift)
    while True:
        k = table_keys[s]
        if k == key:
            return s
        if k == -1:
            return -1
        s = (s + 1) & mask


@numba.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _gap(offset, frac):
    """Distance (in cells) from a point at fraction ``frac`` of its voxel to the voxel ``offset`` away."""
    if offset > 0:
        return offset - frac
    if offset < 0:
        return frac - offset - 1.0
    return 0.0


@numba.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _query(t, n_threads, q, pts, order, origin, cell, rings, dmax, table_keys, shift, table_start, table_stop, dist,
           idx):
    # share t of n_threads of the queries (shift: 64 - log2 of the table's size)
    n_pts = len(order)
    mask = len(table_keys) - 1
    limit = np.int64(1) << np.int64(_BITS)
    n = len(q)
    for i in range(t * n // n_threads, (t + 1) * n // n_threads):
        best = dmax * dmax
        found = -1
        fx = (q[i, 0] - origin[0]) / cell
        fy = (q[i, 1] - origin[1]) / cell
        fz = (q[i, 2] - origin[2]) / cell
        cx, cy, cz = math.floor(fx), math.floor(fy), math.floor(fz)  # int64 (np.floor's float: 0.15 CPU s more)
        fx, fy, fz = fx - cx, fy - cy, fz - cz
        # rings outward; a voxel is opened only when its box can hold a closer point than the best so far
        for ring in range(rings + 1):
            if ring > 0 and (ring - 1.0) * (ring - 1.0) * cell * cell >= best:
                break
            for ox in range(-ring, ring + 1):
                gx = _gap(ox, fx)
                vx = cx + ox
                if vx < 0 or vx >= limit:
                    continue
                for oy in range(-ring, ring + 1):
                    gy = _gap(oy, fy)
                    vy = cy + oy
                    if vy < 0 or vy >= limit:
                        continue
                    edge = ox == -ring or ox == ring or oy == -ring or oy == ring
                    for oz in range(-ring, ring + 1):
                        if not edge and oz != -ring and oz != ring:
                            continue  # inner voxels belong to earlier rings
                        vz = cz + oz
                        if vz < 0 or vz >= limit:
                            continue
                        gz = _gap(oz, fz)
                        if (gx * gx + gy * gy + gz * gz) * cell * cell >= best:
                            continue
                        key = (np.int64(vx) << np.int64(2 * _BITS)) | (np.int64(vy) << np.int64(_BITS)) | \
                            np.int64(vz)
                        s = _lookup(key, table_keys, mask, shift)
                        if s < 0:
                            continue
                        for j in range(table_start[s], table_stop[s]):
                            dx = q[i, 0] - pts[j, 0]
                            dy = q[i, 1] - pts[j, 1]
                            dz = q[i, 2] - pts[j, 2]
                            d2 = dx * dx + dy * dy + dz * dz
                            if d2 < best:
                                best = d2
                                found = j
        if found < 0:
            dist[i] = np.inf
            idx[i] = n_pts
        else:
            dist[i] = np.sqrt(best)
            idx[i] = order[found]
