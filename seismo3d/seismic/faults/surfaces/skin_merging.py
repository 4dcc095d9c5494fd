"""The merging of fault skins (:mod:`~seismo3d.seismic.faults.surfaces.skins`) that continue each other
(``SkinOptions.merge_gap``, ``merge_offset``, ``merge_angle``): the pieces of one fault cut by a younger fault or
broken by a gap longer than the neighbour search. The closest cells of different skins within the gap come from a
k-d tree (edge cells matched to the nearest cell of every other skin); planes (lines in 2D) fitted to each skin near
them decide."""

from __future__ import annotations

import math

import numpy as np
from scipy import sparse
from scipy.ndimage import maximum_filter, minimum_filter
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

__all__ = ["closest_pairs", "local_normal", "merge_coplanar"]


# pairs within the gap per query of :func:`closest_pairs` (about 90 bytes each while they are reduced): its edge cells
# as many as the pairs per edge cell of the query before allow (_FIRST_EDGES in the first; between _FEWEST_EDGES and
# _MOST_EDGES). Thick skins give about 500 pairs an edge cell (224 x 224 x 192, 8 faults: 523; 400 x 400 x 500: 463):
# 4,096 edge cells would hold 2 M pairs, about 190 MiB, more than the rest of the skins.
_PAIRS_PER_QUERY = 1 << 18
_FEWEST_EDGES, _FIRST_EDGES, _MOST_EDGES = 16, 256, 1 << 14


def closest_pairs(pts: np.ndarray, lab: np.ndarray, edge_idx: np.ndarray, gap: float, n_labels: int) -> np.ndarray:
    """(m, 2) int64 indices into ``pts`` (n, 3): for every pair of labels, the closest (edge cell, cell of the other
    label) pair within ``gap`` (ties: the lower edge cell, then the lower other cell). The pairs within the gap come
    from a k-d tree of the cells (:meth:`scipy.spatial.cKDTree.sparse_distance_matrix`), a chunk of edge cells at a
    time, each chunk's reduced to the closest pair of each pair of labels (no list of all the pairs)."""
    if edge_idx.size == 0 or pts.shape[0] == 0:
        return np.empty((0, 2), dtype=np.int64)
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    lab = np.asarray(lab).astype(np.int64, copy=False)
    # only the cells that may have another skin's cell within the gap, edge cells and others alike: the same pairs
    near_other = _near_other_labels(pts, lab, gap)
    edge_idx = np.asarray(edge_idx, dtype=np.int64)
    edge_idx = edge_idx[near_other[edge_idx]]
    if edge_idx.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    cells = np.nonzero(near_other)[0]
    tree = cKDTree(pts[cells])
    gap2 = float(gap) ** 2
    kept = []
    start, size = 0, _FIRST_EDGES
    while start < edge_idx.size:
        edge = edge_idx[start:start + size]
        start += edge.size
        # a hair beyond the gap: the squared distances below decide, summed as the loop this replaced summed them
        near = cKDTree(pts[edge]).sparse_distance_matrix(tree, float(gap) * (1 + 1e-9), output_type="ndarray")
        size = min(max(_PAIRS_PER_QUERY * edge.size // max(near.size, 1), _FEWEST_EDGES), _MOST_EDGES)
        first, second = edge[near["i"]], cells[near["j"]]
        other = lab[first] != lab[second]
        first, second = first[other], second[other]
        d = pts[second] - pts[first]
        dist2 = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2]
        within = dist2 <= gap2
        kept.append(_closest_per_key(first[within], second[within], dist2[within], lab, n_labels))
    first, second, dist2 = (np.concatenate(a) for a in zip(*kept))
    first, second, _ = _closest_per_key(first, second, dist2, lab, n_labels)
    return np.stack([first, second], axis=1)


# Grid cells per fault cell above which _near_other_labels keeps every cell: its two int64 grids (16 bytes a grid
# cell) stay within about the k-d tree's own memory (a 256^3 cube's 232,442 cells at the default gap: 0.03 grid
# cells a cell; a gap of 1 sample over a 2000 x 2000 x 1500 cube would be 6e9).
_GRID_CELLS_PER_POINT = 8


def _near_other_labels(pts: np.ndarray, lab: np.ndarray, gap: float) -> np.ndarray:
    """(n,) bool: the cells ``pts`` (n, 3) that may have a cell of another label within ``gap``: those whose cell of
    a grid of a hair more than ``gap`` a side, or one of its 26 neighbours, holds a cell of another label (two cells
    within the gap lie in neighbouring grid cells). The others pair only with their own skin's cells, which
    :func:`closest_pairs` drops: left out, the pairs are the same, and the k-d tree holds and lists a fraction of them
    (most cells within the gap of an edge cell are its own skin's). Every cell when the grid would hold more than
    ``_GRID_CELLS_PER_POINT`` grid cells a cell (a gap small for the cloud's extent)."""
    size = float(gap) * (1.0 + 1e-6) if gap > 0 else 1.0
    grid = np.floor(pts / size).astype(np.int64)
    grid -= grid.min(axis=0)
    shape = tuple(int(n) for n in grid.max(axis=0) + 1)
    if math.prod(shape) > _GRID_CELLS_PER_POINT * len(pts) + 4096:  # a small gap over a wide cloud: every cell
        return np.ones(len(pts), bool)
    flat = np.ravel_multi_index(tuple(grid.T), shape)
    n_labels = int(lab.max()) + 1
    lowest = np.full(int(np.prod(shape)), n_labels, np.int64)
    highest = np.full(lowest.size, -1, np.int64)
    np.minimum.at(lowest, flat, lab)
    np.maximum.at(highest, flat, lab)
    # over the 3 x 3 x 3 grid cells around each (the edges repeated: no label of their own)
    lowest = minimum_filter(lowest.reshape(shape), size=3, mode="nearest").ravel()[flat]
    highest = maximum_filter(highest.reshape(shape), size=3, mode="nearest").ravel()[flat]
    return (lowest < lab) | (highest > lab)


def _closest_per_key(first, second, dist2, lab, n_labels):
    """The pairs ``(first, second, dist2)`` reduced to the closest of each pair of labels (ties: the lower first,
    then the lower second cell)."""
    key = np.minimum(lab[first], lab[second]) * n_labels + np.maximum(lab[first], lab[second])
    order = np.lexsort((second, first, dist2, key))
    keep = np.ones(order.size, dtype=bool)
    keep[1:] = key[order][1:] != key[order][:-1]
    sel = order[keep]
    return first[sel], second[sel], dist2[sel]


def local_normal(points: np.ndarray, two_d: bool) -> np.ndarray:
    """Unit normal of the plane (line in 2D sections, whose crossline coordinate is constant) fitted to
    ``points`` (n, 3), n >= 3."""
    centred = points - points.mean(axis=0)
    if two_d:
        _, _, vt = np.linalg.svd(centred[:, [0, 2]], full_matrices=False)
        return np.array([vt[-1, 0], 0.0, vt[-1, 1]])
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    return vt[-1]


def merge_coplanar(points: np.ndarray, label: np.ndarray, edge: np.ndarray, minimum: int, two_d: bool, *,
                   gap: float, offset: float, angle: float) -> np.ndarray:
    """Labels of skins merged where they continue each other (see
    :class:`~seismo3d.seismic.faults.surfaces.skins.SkinOptions`): the pieces of one fault cut by a younger fault or
    broken by a long gap. For two skins of at least ``minimum`` cells whose edge cells come within ``gap``, planes are
    fitted to each skin's cells near the two closest edge cells; they merge when the planes agree within ``angle`` and
    the gap between the cells lies within ``offset`` of both planes, i.e. runs along the fault, not across it (two
    parallel faults side by side stay apart). An edge cell of one skin is compared with every cell of the other, so a
    piece ending on the side of another (a fork) is found too.

    Parameters
    ----------
    points : (n, 3) ndarray of int
        The cells' (inline, crossline, sample) indices (a section's as (trace, 0, sample)).
    label : (n,) ndarray of int64
        The cells' skin labels, 0, 1, ...
    edge : (n,) ndarray of bool
        The cells on the edge of their skin.
    minimum : int
        Skins with fewer cells are neither merged nor merged into.
    two_d : bool
        The cells are a section's: lines, not planes, are fitted.
    gap, offset : float
        ``SkinOptions.merge_gap`` and ``merge_offset``, samples.
    angle : float
        ``SkinOptions.merge_angle``, degrees.

    Returns
    -------
    (n,) ndarray of int64
        The labels, merged skins sharing one.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (fault skins).
    """
    n_labels = int(label.max()) + 1
    sizes = np.bincount(label, minlength=n_labels)
    big = sizes[label] >= minimum
    if np.count_nonzero(big & edge) == 0:
        return label
    # the closest pair (an edge cell of one skin, any cell of another) within merge_gap for every pair of skins: a
    # piece's end near another's end or side
    pts, lab = points[big].astype(np.float64), label[big]
    closest = closest_pairs(pts, lab, np.nonzero(edge[big])[0], float(gap), n_labels)
    if closest.size == 0:
        return label
    radius = 2.0 * float(gap)
    cos_angle = np.cos(np.radians(angle))
    # each skin's cells near a cell are searched among that skin's cells only (one KD-tree a skin, built when first
    # needed): a search among all cells returns mostly other skins' cells
    by_label = np.argsort(lab, kind="stable")
    starts = np.searchsorted(lab[by_label], np.arange(n_labels + 1))
    trees: dict = {}

    def own_skin_near(i):
        skin = int(lab[i])
        if skin not in trees:
            cells = by_label[starts[skin]:starts[skin + 1]]
            trees[skin] = (cells, cKDTree(pts[cells]))
        cells, tree = trees[skin]
        return cells[np.sort(np.asarray(tree.query_ball_point(pts[i], radius), dtype=np.int64))]

    rows, cols = [], []
    for i, j in closest:
        near_p, near_q = own_skin_near(i), own_skin_near(j)
        if near_p.size < 3 or near_q.size < 3:
            continue
        na = local_normal(pts[near_p], two_d)
        nb_ = local_normal(pts[near_q], two_d)
        d = pts[j] - pts[i]
        if abs(na @ nb_) >= cos_angle and abs(na @ d) <= offset and abs(nb_ @ d) <= offset:
            rows.append(lab[i])
            cols.append(lab[j])
    if not rows:
        return label
    graph = sparse.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n_labels, n_labels))
    _, merged = connected_components(graph, directed=False)
    return merged[label]
