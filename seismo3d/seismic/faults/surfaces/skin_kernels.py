"""The closest cells of different fault skins within a gap (:mod:`~seismo3d.seismic.faults.surfaces.skins`): edge cells
matched to the nearest cell of every other skin through a grid of buckets; the pairs the merging of coplanar skins
considers."""

from __future__ import annotations

import numba as nb
import numpy as np

from ... import _kernels

__all__ = []


@nb.njit(cache=True)
def _grown(a, size):
    # a copy of a in a longer array (the first a.size entries)
    out = np.empty(size, a.dtype)
    for i in range(a.size):
        out[i] = a[i]
    return out


@nb.njit(cache=True)
def _nearest_of_other_skins(e, pts, lab, origin, dims, side, keys, order, gap2, slot, labels, dist2, cells):
    # For cell e: the nearest cell (squared distance, index) of every other label within sqrt(gap2), ties to the
    # lower index, from the buckets (cubes of ``side`` from ``origin``, :func:`~seismo3d.seismic._kernels.bucket_grid`)
    # around e's bucket that come within the gap; ``keys`` are the cells' bucket keys in ``order``. ``labels``,
    # ``dist2``, ``cells`` take the results (grown when full); ``slot`` (one per label, all -1) is the position of a
    # label in them, and is left all -1 again. Returns the number of labels found and the three (grown) arrays.
    m = 0
    gap = np.sqrt(gap2)
    own = lab[e]
    ex = np.empty(3)
    for a in range(3):
        ex[a] = pts[e, a] - origin[a]
    # the buckets within the gap of e along each axis
    first_b = np.empty(3, np.int64)
    last_b = np.empty(3, np.int64)
    for a in range(3):
        first_b[a] = max(int(np.floor((ex[a] - gap) / side)), 0)
        last_b[a] = min(int(np.floor((ex[a] + gap) / side)), dims[a] - 1)
    for bx in range(first_b[0], last_b[0] + 1):
        for by in range(first_b[1], last_b[1] + 1):
            # the column's buckets along the samples are consecutive keys: one range of cells; the column is
            # skipped when its nearest point to e (buckets counted from the cells' lowest corner) is beyond the gap
            box2 = 0.0
            for a, b in ((0, bx), (1, by)):
                lo = b * side - ex[a]
                hi = lo + side
                if lo > 0.0:
                    box2 += lo * lo
                elif hi < 0.0:
                    box2 += hi * hi
            if box2 > gap2:
                continue
            column = bx * dims[1] + by
            low = column * dims[2] + first_b[2]
            high = column * dims[2] + last_b[2]
            for r in range(_kernels.search_left(keys, low), _kernels.search_right(keys, high)):
                j = order[r]
                if lab[j] == own:
                    continue
                d2 = 0.0
                for a in range(3):
                    t = pts[j, a] - pts[e, a]
                    d2 += t * t
                if d2 > gap2:
                    continue
                k = slot[lab[j]]
                if k < 0:
                    if m == labels.size:  # grow the lists
                        labels = _grown(labels, 2 * m)
                        dist2 = _grown(dist2, 2 * m)
                        cells = _grown(cells, 2 * m)
                    slot[lab[j]] = m
                    labels[m] = lab[j]
                    dist2[m] = d2
                    cells[m] = j
                    m += 1
                elif d2 < dist2[k] or (d2 == dist2[k] and j < cells[k]):
                    dist2[k] = d2
                    cells[k] = j
    for k in range(m):
        slot[labels[k]] = -1
    return m, labels, dist2, cells


@nb.njit(cache=True)
def _edge_pairs(edge_idx, pts, lab, n_labels, origin, dims, side, keys, order, gap2):
    # every (edge cell, nearest cell of another label within the gap, squared distance), in the order of the edge
    # cells
    slot = np.full(n_labels, -1, np.int64)  # left all -1 by _nearest_of_other_skins
    labels = np.empty(16, np.int64)
    dist2 = np.empty(16)
    cells = np.empty(16, np.int64)
    first = np.empty(64, np.int64)
    second = np.empty(64, np.int64)
    dist = np.empty(64)
    used = 0
    for r in range(edge_idx.size):
        m, labels, dist2, cells = _nearest_of_other_skins(edge_idx[r], pts, lab, origin, dims, side, keys, order,
                                                         gap2, slot, labels, dist2, cells)
        if used + m > first.size:
            size = max(2 * first.size, used + m)
            first = _grown(first, size)
            second = _grown(second, size)
            dist = _grown(dist, size)
        for k in range(m):
            first[used] = edge_idx[r]
            second[used] = cells[k]
            dist[used] = dist2[k]
            used += 1
    return first[:used], second[:used], dist[:used]


def closest_pairs(pts: np.ndarray, lab: np.ndarray, edge_idx: np.ndarray, gap: float, n_labels: int) -> np.ndarray:
    """(m, 2) int64 indices into ``pts`` (n, 3): for every pair of labels, the closest (edge cell, cell of the other
    label) pair within ``gap`` (ties: the lower edge cell, then the lower other cell). Cells are binned in buckets
    of side ``gap / 2`` (memory: three int64 arrays of n besides the cells), so each edge cell compares itself with
    the cells of the buckets that come within the gap only and keeps the nearest cell of each other label (no list
    of all the pairs)."""
    if edge_idx.size == 0 or pts.shape[0] == 0:
        return np.empty((0, 2), dtype=np.int64)
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    _, compact = np.unique(lab, return_inverse=True)  # labels 0..k-1: one slot each
    compact = compact.astype(np.int64).ravel()
    side = max(0.5 * float(gap), 0.5)
    keys, order, origin, dims = _kernels.bucket_grid(pts, side)
    first, second, dist2 = _edge_pairs(np.ascontiguousarray(edge_idx, dtype=np.int64), pts, compact,
                                       int(compact.max()) + 1, origin, dims, side, keys, order, float(gap) ** 2)
    if first.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    key = np.minimum(lab[first], lab[second]).astype(np.int64) * n_labels + np.maximum(lab[first], lab[second])
    order = np.lexsort((second, first, dist2, key))
    keep = np.ones(order.size, dtype=bool)
    keep[1:] = key[order][1:] != key[order][:-1]
    sel = order[keep]
    return np.stack([first[sel], second[sel]], axis=1)


@nb.njit(cache=True)
def grow_by_mean_normal(indptr, indices, normals, order, cos_mean):
    # Region growing over the neighbour graph (whose edges already join only compatible normals): from the
    # unassigned sample of highest likelihood, add neighbours whose normal is within acos(cos_mean) of the growing
    # fault's mean normal, breadth first. The mean keeps a fault from drifting into another one through samples of
    # intermediate orientation where two faults meet.
    n_pts, dim = normals.shape
    label = -np.ones(n_pts, np.int64)
    queue = np.empty(n_pts, np.int64)
    mean = np.zeros(dim)
    n_lab = 0
    for seed in order:
        if label[seed] >= 0:
            continue
        label[seed] = n_lab
        for d in range(dim):
            mean[d] = normals[seed, d]
        head = 0
        tail = 1
        queue[0] = seed
        while head < tail:
            i = queue[head]
            head += 1
            for e in range(indptr[i], indptr[i + 1]):
                j = indices[e]
                if label[j] >= 0:
                    continue
                dot = 0.0
                nm = 0.0
                for d in range(dim):
                    dot += normals[j, d] * mean[d]
                    nm += mean[d] * mean[d]
                if abs(dot) < cos_mean * np.sqrt(nm):
                    continue
                label[j] = n_lab
                sgn = 1.0 if dot >= 0 else -1.0
                for d in range(dim):
                    mean[d] += sgn * normals[j, d]
                queue[tail] = j
                tail += 1
        n_lab += 1
    return label
