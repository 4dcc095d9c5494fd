"""Surface normals of 2D / 3D point sets and of organised depth images."""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components, minimum_spanning_tree
from scipy.spatial import cKDTree

from .._threads import query_workers
from .._validation import as_intrinsics, as_points, check_choice
from ..errors import InputError

__all__ = ["estimate_normals", "orient_normals", "normals_from_points_image", "backproject_depth"]


def estimate_normals(points, *, k: int = 16, radius: float | None = None, orient: str = "mst", viewpoint=None):
    """Unit normals by PCA over each point's neighbourhood, consistently oriented.

    The normal is the eigenvector of the neighbourhood covariance with the smallest eigenvalue (the direction of
    least spread); in 2D it is the normal of the local line, in 3D of the local plane.

    Parameters
    ----------
    points : (N, d) array_like, d in {2, 3}
        Coordinates.
    k : int
        Number of nearest neighbours (including the point itself) when ``radius`` is None.
    radius : float, optional
        Use all neighbours within this distance instead (at least ``d`` of them are needed; points with fewer keep
        their k-nearest-neighbour normal).
    orient : {'mst', 'viewpoint', 'none'}
        ``'viewpoint'`` flips normals to face ``viewpoint`` (for scans and depth images: the sensor position);
        ``'mst'`` propagates a consistent sign along a minimum spanning tree of the kNN graph (Hoppe et al. 1992),
        starting from the point with the largest last coordinate, whose normal is made to point along +last axis;
        ``'none'`` leaves the sign arbitrary (fine for point-to-plane ICP, whose residual ignores the sign).
    viewpoint : (d,) array_like, optional
        Sensor position, required for ``orient='viewpoint'``.

    Returns
    -------
    normals : (N, d) float64 ndarray
        Unit vectors.

    Raises
    ------
    InputError
        Fewer than ``d + 1`` points, bad ``k``, unknown ``orient``, missing viewpoint.

    References
    ----------
    Hoppe, H., DeRose, T., Duchamp, T., McDonald, J., Stuetzle, W. (1992). Surface reconstruction from unorganized
    points. SIGGRAPH '92, 71-78. doi:10.1145/133994.134011
    """
    pts = as_points(points, min_points=3)
    d = pts.shape[1]
    check_choice(orient, "orient", {"mst", "viewpoint", "none"})
    k = int(min(k, len(pts)))
    if k < d:
        raise InputError(f"k={k} neighbours cannot define a normal in {d}D; use k >= {d + 1}")
    tree = cKDTree(pts)
    _, idx = tree.query(pts, k=k, workers=query_workers(len(pts)))
    nb = pts[idx]  # (N, k, d)
    if radius is None:
        centred = nb - nb.mean(axis=1, keepdims=True)
        cov = np.einsum("nki,nkj->nij", centred, centred)
    else:
        cov = _radius_covariances(tree, pts, radius, nb)
    _, vecs = np.linalg.eigh(cov)
    normals = vecs[:, :, 0]
    return orient_normals(pts, normals, method=orient, viewpoint=viewpoint, neighbours=idx)


def _radius_covariances(tree, pts, radius, knn_neighbours):
    lists = tree.query_ball_point(pts, r=radius, workers=query_workers(len(pts)))
    counts = np.fromiter((len(x) for x in lists), dtype=np.int64, count=len(lists))
    flat = np.fromiter((j for x in lists for j in x), dtype=np.int64, count=int(counts.sum()))
    owner = np.repeat(np.arange(len(pts)), counts)
    d = pts.shape[1]
    mean = np.stack([np.bincount(owner, pts[flat, j], len(pts)) for j in range(d)], 1) / np.maximum(counts, 1)[:, None]
    c = pts[flat] - mean[owner]
    cov = np.zeros((len(pts), d, d))
    for i in range(d):
        for j in range(i, d):
            cov[:, i, j] = cov[:, j, i] = np.bincount(owner, c[:, i] * c[:, j], len(pts))
    few = counts <= d
    if np.any(few):
        centred = knn_neighbours[few] - knn_neighbours[few].mean(axis=1, keepdims=True)
        cov[few] = np.einsum("nki,nkj->nij", centred, centred)
    return cov


def orient_normals(points, normals, *, method: str = "mst", viewpoint=None, neighbours=None):
    """Flip normals to a consistent sign (see :func:`estimate_normals` for the methods).

    Parameters
    ----------
    points : (N, d) float64 ndarray
    normals : (N, d) float64 ndarray
        Unit normals of arbitrary sign; a new array is returned.
    method : {'mst', 'viewpoint', 'none'}
    viewpoint : (d,) array_like, optional
    neighbours : (N, k) int ndarray, optional
        kNN indices (recomputed with k = 10 when not given).

    Returns
    -------
    (N, d) float64 ndarray
    """
    n = np.array(normals, dtype=np.float64)
    if method == "none":
        return n
    if method == "viewpoint":
        if viewpoint is None:
            raise InputError("orient='viewpoint' needs viewpoint=(x, y[, z]), the sensor position")
        vp = np.asarray(viewpoint, dtype=np.float64).reshape(-1)
        if vp.shape != (points.shape[1],):
            raise InputError(f"viewpoint must have {points.shape[1]} coordinates; got {vp.shape}")
        flip = np.einsum("ij,ij->i", n, vp - points) < 0
        n[flip] *= -1
        return n
    if neighbours is None:
        k = min(10, len(points))
        _, neighbours = cKDTree(points).query(points, k=k, workers=query_workers(len(points)))
    rows = np.repeat(np.arange(len(points)), neighbours.shape[1])
    cols = neighbours.reshape(-1)
    keep = rows != cols
    rows, cols = rows[keep], cols[keep]
    # Edge cost 1 - |n_i . n_j| (plus a tiny term so that zero-cost edges are kept by the sparse MST).
    cost = 1.0 - np.abs(np.einsum("ij,ij->i", n[rows], n[cols])) + 1e-9
    graph = coo_matrix((cost, (rows, cols)), shape=(len(points),) * 2).tocsr()
    graph = graph.maximum(graph.T)
    tree = minimum_spanning_tree(graph)
    tree = tree + tree.T
    n_comp, labels = connected_components(tree, directed=False)
    up = points.shape[1] - 1
    for comp in range(n_comp):
        members = np.flatnonzero(labels == comp)
        root = members[np.argmax(points[members, up])]
        if n[root, up] < 0:
            n[root] *= -1
        order, parent = breadth_first_order(tree, root, directed=False, return_predecessors=True)
        for node in order[1:]:  # parents are visited before children
            if n[node] @ n[parent[node]] < 0:
                n[node] *= -1
    return n


def backproject_depth(depth, intrinsics) -> np.ndarray:
    """Back-project a depth image to camera-frame 3D points (pinhole model, x right, y down, z forward).

    Parameters
    ----------
    depth : (H, W) array_like
        Depth along the optical axis in metres; 0, negative or NaN mark invalid pixels.
    intrinsics : (3, 3) array_like or sequence (fx, fy, cx, cy)
        Pinhole intrinsics in pixels.

    Returns
    -------
    (H, W, 3) float64 ndarray
        Points in metres; NaN at invalid pixels.

    Raises
    ------
    InputError
        Depth not 2D or intrinsics not (3, 3) / four numbers.
    """
    z = np.asarray(depth, dtype=np.float64)
    if z.ndim != 2:
        raise InputError(f"depth must be a (H, W) image; got shape {z.shape}")
    fx, fy, cx, cy = as_intrinsics(intrinsics)
    z = np.where(np.isfinite(z) & (z > 0), z, np.nan)
    v, u = np.indices(z.shape, dtype=np.float64)
    return np.stack([(u - cx) * z / fx, (v - cy) * z / fy, z], axis=-1)


def normals_from_points_image(points_image, *, max_depth_jump: float = 0.05) -> np.ndarray:
    """Normals of an organised point image (e.g. from :func:`backproject_depth`) by central differences.

    The normal at pixel (v, u) is ``(P[v, u+1] - P[v, u-1]) x (P[v+1, u] - P[v-1, u])``, normalised and turned to
    face the camera (``n . p < 0``), as in KinectFusion.

    Parameters
    ----------
    points_image : (H, W, 3) array_like
        Camera-frame points in metres, NaN where invalid.
    max_depth_jump : float
        Neighbours whose depth differs by more than this (metres) are treated as across an occlusion edge: the pixel
        gets a NaN normal.

    Returns
    -------
    (H, W, 3) float64 ndarray
        Unit normals, NaN where undefined (invalid pixel, image border, depth discontinuity).

    References
    ----------
    Newcombe, R. A. et al. (2011). KinectFusion: Real-time dense surface mapping and tracking. ISMAR, 127-136.
    doi:10.1109/ISMAR.2011.6092378
    """
    p = np.asarray(points_image, dtype=np.float64)
    if p.ndim != 3 or p.shape[2] != 3:
        raise InputError(f"points_image must be (H, W, 3); got {p.shape}")
    du = np.full_like(p, np.nan)
    dv = np.full_like(p, np.nan)
    du[:, 1:-1] = p[:, 2:] - p[:, :-2]
    dv[1:-1, :] = p[2:, :] - p[:-2, :]
    n = np.cross(du, dv)
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        n = n / norm
        jump = (np.abs(du[..., 2]) > 2 * max_depth_jump) | (np.abs(dv[..., 2]) > 2 * max_depth_jump)
    n[jump] = np.nan
    flip = np.einsum("hwi,hwi->hw", n, p) > 0
    n[flip] *= -1
    return n
