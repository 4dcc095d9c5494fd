"""Neighbourhoods, voxel grids and point pyramids (scipy.spatial.cKDTree underneath)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .._threads import query_workers
from .._validation import as_points, check_positive

__all__ = ["voxel_downsample", "median_spacing", "bounding_diagonal", "axis_bounds"]


def axis_bounds(points):
    """Smallest and largest coordinate of a point set along each axis.

    One reduction per column: numpy 2.4's ``points.min(axis=0)`` over an (N, 3) array reduces across the short rows
    without vectorising, 1.4 ms for 40,000 points on this project's machine, against 0.06 ms for the three columns
    reduced one by one (the ICP engine asks for the bounds of every index it builds).

    Parameters
    ----------
    points : (N, d) ndarray
        Coordinates (any numeric dtype), N >= 1.

    Returns
    -------
    lo, hi : (d,) ndarray
        The minimum and maximum of each column, in the points' dtype and unit.
    """
    pts = np.asarray(points)
    lo = np.array([pts[:, j].min() for j in range(pts.shape[1])], dtype=pts.dtype)
    hi = np.array([pts[:, j].max() for j in range(pts.shape[1])], dtype=pts.dtype)
    return lo, hi


def voxel_downsample(points, voxel_size: float, *, values=None):
    """Average the points (and optional per-point values) falling in each cubic voxel.

    Parameters
    ----------
    points : (N, d) array_like, d in {2, 3}
        Coordinates, any length unit.
    voxel_size : float
        Edge of the voxel, in the points' unit.
    values : (N, k) array_like, optional
        Per-point attributes averaged the same way (e.g. normals; renormalise them afterwards).

    Returns
    -------
    points : (M, d) float64 ndarray
        Voxel centroids, M <= N, in order of first occurrence of the voxel.
    values : (M, k) float64 ndarray or None
        Averaged attributes, or None when ``values`` is None.

    Raises
    ------
    InputError
        Bad points or a non-positive voxel size.
    """
    pts = as_points(points)
    size = check_positive(voxel_size, "voxel_size")
    keys = np.floor((pts - axis_bounds(pts)[0]) / size).astype(np.int64)
    dims = axis_bounds(keys)[1] + 1
    if np.prod(dims.astype(np.float64)) < 2.0**62:  # one int64 per voxel: a 1D unique is far faster than rows
        keys = np.ravel_multi_index(keys.T, dims)
        _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    else:
        _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    order = np.argsort(first)  # keep the voxels in order of first occurrence (stable, reproducible)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    inverse = rank[inverse]
    counts = np.bincount(inverse).astype(np.float64)
    out = np.stack([np.bincount(inverse, weights=pts[:, j]) for j in range(pts.shape[1])], axis=1) / counts[:, None]
    vals = None
    if values is not None:
        v = np.asarray(values, dtype=np.float64).reshape(len(pts), -1)
        vals = np.stack([np.bincount(inverse, weights=v[:, j]) for j in range(v.shape[1])], axis=1) / counts[:, None]
    return out, vals


def median_spacing(points, *, sample: int = 2000, seed: int = 0) -> float:
    """Median nearest-neighbour distance of a point set (estimated on a random subset of ``sample`` points).

    Parameters
    ----------
    points : (N, d) array_like
    sample : int
        How many query points to use.
    seed : int
        Seed of the subset.

    Returns
    -------
    float
        In the points' unit.
    """
    pts = as_points(points, min_points=2)
    tree = cKDTree(pts, balanced_tree=False, compact_nodes=False)  # half the build time, same exact neighbours
    rng = np.random.default_rng(seed)
    q = pts if len(pts) <= sample else pts[rng.choice(len(pts), sample, replace=False)]
    dist, _ = tree.query(q, k=2, workers=query_workers(len(q)))
    return float(np.median(dist[:, 1]))


def bounding_diagonal(points) -> float:
    """Length of the diagonal of the axis-aligned bounding box.

    Parameters
    ----------
    points : (N, d) array_like

    Returns
    -------
    float
        In the points' unit.
    """
    lo, hi = axis_bounds(as_points(points))
    return float(np.linalg.norm(hi - lo))
