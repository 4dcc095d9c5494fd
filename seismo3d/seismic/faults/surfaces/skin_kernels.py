"""The closest cells of different fault skins within a gap (:mod:`~seismo3d.seismic.faults.surfaces.skins`): edge cells
matched to the nearest cell of every other skin through a k-d tree; the pairs the merging of coplanar skins
considers."""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from scipy.spatial import cKDTree

__all__ = []


# edge cells per query of :func:`closest_pairs`: their pairs within the gap (a few hundred each on a thick skin) stay
# a few MB
_EDGE_CHUNK = 1 << 12


def closest_pairs(pts: np.ndarray, lab: np.ndarray, edge_idx: np.ndarray, gap: float, n_labels: int) -> np.ndarray:
    """(m, 2) int64 indices into ``pts`` (n, 3): for every pair of labels, the closest (edge cell, cell of the other
    label) pair within ``gap`` (ties: the lower edge cell, then the lower other cell). The pairs within the gap come
    from a k-d tree of the cells (:meth:`scipy.spatial.cKDTree.sparse_distance_matrix`), a chunk of edge cells at a
    time, each chunk's reduced to the closest pair of each pair of labels (no list of all the pairs)."""
    if edge_idx.size == 0 or pts.shape[0] == 0:
        return np.empty((0, 2), dtype=np.int64)
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    lab = np.asarray(lab).astype(np.int64, copy=False)
    edge_idx = np.asarray(edge_idx, dtype=np.int64)
    tree = cKDTree(pts)
    gap2 = float(gap) ** 2
    kept = []
    for start in range(0, edge_idx.size, _EDGE_CHUNK):
        edge = edge_idx[start:start + _EDGE_CHUNK]
        # a hair beyond the gap: the squared distances below decide, summed as the loop this replaced summed them
        near = cKDTree(pts[edge]).sparse_distance_matrix(tree, float(gap) * (1 + 1e-9), output_type="ndarray")
        first, second = edge[near["i"]], near["j"].astype(np.int64)
        other = lab[first] != lab[second]
        first, second = first[other], second[other]
        d = pts[second] - pts[first]
        dist2 = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2]
        within = dist2 <= gap2
        kept.append(_closest_per_key(first[within], second[within], dist2[within], lab, n_labels))
    first, second, dist2 = (np.concatenate(a) for a in zip(*kept))
    first, second, _ = _closest_per_key(first, second, dist2, lab, n_labels)
    return np.stack([first, second], axis=1)


def _closest_per_key(first, second, dist2, lab, n_labels):
    """The pairs ``(first, second, dist2)`` reduced to the closest of each pair of labels (ties: the lower first,
    then the lower second cell)."""
    key = np.minimum(lab[first], lab[second]) * n_labels + np.maximum(lab[first], lab[second])
    order = np.lexsort((second, first, dist2, key))
    keep = np.ones(order.size, dtype=bool)
    keep[1:] = key[order][1:] != key[order][:-1]
    sel = order[keep]
    return first[sel], second[sel], dist2[sel]


def grow_by_mean_normal(indptr, indices, normals, order, cos_mean):
    """Region growing over the neighbour graph (CSR ``indptr``, ``indices``; its edges already join only compatible
    normals): from the unassigned sample of highest likelihood (``order``), add neighbours whose normal (``normals``
    (n, dim) float64) is within acos(cos_mean) of the growing fault's mean normal, breadth first; (n,) int64 labels.
    The mean keeps a fault from drifting into another one through samples of intermediate orientation where two
    faults meet."""
    n_pts, dim = normals.shape
    label = np.full(n_pts, -1, np.int64)
    _grow_by_mean_normal(indptr, indices, normals, order, cos_mean, label, np.empty(n_pts, np.int64), np.zeros(dim))
    return label


@nb.njit(cache=True)
def _grow_by_mean_normal(indptr, indices, normals, order, cos_mean, label, queue, mean):
    # grow_by_mean_normal's loop: label (all -1) takes the labels; queue and mean are work arrays (np.empty, np.full,
    # np.zeros in here each compiled a function of numba's of its own)
    dim = normals.shape[1]
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
                if abs(dot) < cos_mean * math.sqrt(nm):
                    continue
                label[j] = n_lab
                sgn = 1.0 if dot >= 0 else -1.0
                for d in range(dim):
                    mean[d] += sgn * normals[j, d]
                queue[tail] = j
                tail += 1
        n_lab += 1


def heights(samples: np.ndarray, label: np.ndarray, roots: np.ndarray) -> np.ndarray:
    """Extent along the sample axis (max - min + 1) of the skins ``roots``, samples."""
    top = np.full(label.size, np.iinfo(np.int64).max, dtype=np.int64)
    bottom = np.full(label.size, -1, dtype=np.int64)
    np.minimum.at(top, label, samples)
    np.maximum.at(bottom, label, samples)
    return bottom[roots] - top[roots] + 1
