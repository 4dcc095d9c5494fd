"""The closest cells of different fault skins within a gap (:mod:`~seismo3d.seismic.faults.surfaces.skins`): edge cells
matched to the nearest cell of every other skin through a k-d tree; the pairs the merging of coplanar skins
considers. And the split of 2D skins whose branches dip opposite ways (:func:`split_opposite_dips`,
``SkinOptions.split_angle``): a fault plane dips one way, but the linking keeps to one mean normal within
``max_angle``, so two steep faults dipping opposite ways (a Y and its antithetic branch, an inverted V) whose normals
lie closer than that link into one skin, whose zone then spans the block between them and whose throw compares the
reflectors outside both. And the split of 2D skins at a fork (:func:`split_forks`, ``SkinOptions.split_forks``):
two faults that meet (a Y, an X) link into one skin; their branches' lines, not their normals, tell them apart.

And the tips of kept 2D faults trimmed back to where the fault likelihood holds (:func:`trimmed_tips`,
``FaultTracingOptions.tip_level``): optimal surface voting (:mod:`~seismo3d.seismic.faults.surfaces.voting`) casts
each seed's votes along a path of ``2 * half_length_dip + 1`` samples, so a fault's votes, and the skin linked from
them, run on past the fault's last likely sample by up to ``half_length_dip`` samples (30 on a long section), fading:
beyond its tip the skin follows the votes of surfaces through samples where nothing is displaced."""

from __future__ import annotations

import dataclasses
import math

import numba as nb
import numpy as np
from scipy import sparse
from scipy.ndimage import maximum_filter
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ....errors import InputError

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


def _dip_directions(normals: np.ndarray) -> np.ndarray:
    """(n,) int8: +1 where a 2D cell's normal (trace, sample) points toward increasing trace when turned to point
    down (its fault dips toward increasing trace), -1 the other way, 0 for a vertical cell."""
    nx, nz = normals[:, 0], normals[:, 1]
    direction = np.sign(nx) * np.where(nz < 0, -1.0, 1.0)
    return np.where(np.abs(nz) < 1e-6, 0, direction).astype(np.int8)


def _components(pairs: np.ndarray, group: np.ndarray, n: int) -> np.ndarray:
    """Connected components of ``n`` cells over their adjacent ``pairs`` (m, 2) that share a ``group`` value;
    (n,) int64 labels."""
    same = pairs[group[pairs[:, 0]] == group[pairs[:, 1]]]
    graph = sparse.coo_matrix((np.ones(len(same)), (same[:, 0], same[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1].astype(np.int64)


def _line_angle(xz: np.ndarray) -> float:
    """Angle from the sample axis of the line x = a + b t fitted to the points ``xz`` (n, 2), degrees in (-90, 90)."""
    t = xz[:, 1] - xz[:, 1].mean()
    var = float(t @ t)
    slope = float(t @ (xz[:, 0] - xz[:, 0].mean())) / var if var > 0 else 0.0
    return float(np.degrees(np.arctan(slope)))


def split_opposite_dips(xz, normals, label, minimum: int, lateral: int, vertical: int, angle: float) -> np.ndarray:
    """Split the 2D skins whose cells dip two opposite ways into their branches (see ``SkinOptions.split_angle``).

    In each skin of at least ``minimum`` cells, a cell's dip direction is its normal's (vertical cells take the
    direction of their nearest cell that has one). The cells of one direction connected within the link reach
    (``lateral`` traces, ``vertical`` samples) make a branch; a branch spanning fewer than ``2 * vertical`` samples
    that meets another is a wiggle and takes the direction around it (the shortest first, until none is left). When
    both directions then hold a branch at least that tall, and the lines fitted to the cells of each direction differ
    by at least ``angle`` degrees, the cells dipping toward decreasing trace become a skin of their own: a Y's
    antithetic branch leaves the fault and its other branch whole, an inverted V becomes its two faults.

    Parameters
    ----------
    xz : (n, 2) ndarray of int
        The cells' (trace, sample) indices.
    normals : (n, 2) ndarray of float
        The cells' unit fault normals (trace, sample components).
    label : (n,) ndarray of int
        The cells' skin labels.
    minimum : int
        Skins with fewer cells are left as they are (too small to be kept whatever their branches).
    lateral, vertical : int
        The link reach across traces and along samples.
    angle : float
        Smallest angle between the lines fitted to the two directions' cells for a split, degrees.

    Returns
    -------
    (n,) ndarray of int64
        The labels, a branch split off taking a new label (above every old one).
    """
    xz = np.asarray(xz, np.float64)
    label = np.asarray(label, np.int64).copy()
    sizes = np.bincount(label)
    next_label = int(label.max()) + 1 if label.size else 0
    direction_all = _dip_directions(np.asarray(normals, np.float64))
    by_label = np.argsort(label, kind="stable")
    starts = np.searchsorted(label[by_label], np.arange(sizes.size + 1))
    for skin in np.nonzero(sizes >= max(int(minimum), 2))[0]:
        cells = by_label[starts[skin]:starts[skin + 1]]
        direction = direction_all[cells].astype(np.int64)
        signed = direction != 0
        if not signed.any() or np.all(direction[signed] == direction[signed][0]):
            continue  # one dip direction: nothing to split
        if not signed.all():  # vertical cells go with their nearest cell that has a direction
            _, near = cKDTree(xz[cells][signed]).query(xz[cells][~signed])
            direction[~signed] = direction[signed][near]
        pts = xz[cells]
        scaled = pts / np.array([float(lateral), float(vertical)])
        pairs = cKDTree(scaled).query_pairs(1.0, p=np.inf, output_type="ndarray")
        for _ in range(64):  # branches too short to be one take the direction around them, shortest first
            comp = _components(pairs, direction, len(cells))
            top = np.full(comp.max() + 1, np.inf)
            bottom = np.full(comp.max() + 1, -np.inf)
            np.minimum.at(top, comp, pts[:, 1])
            np.maximum.at(bottom, comp, pts[:, 1])
            height = bottom - top + 1
            touching = np.zeros(height.size, bool)  # a branch that meets another (an isolated piece stays)
            across = comp[pairs[:, 0]] != comp[pairs[:, 1]]
            touching[comp[pairs[across].ravel()]] = True
            short = (height < 2 * vertical) & touching
            if not short.any():
                break
            direction[comp == int(np.argmin(np.where(short, height, np.inf)))] *= -1
        long_ = height >= 2 * vertical
        if not (long_ & np.isin(np.arange(height.size), comp[direction > 0])).any() or \
                not (long_ & np.isin(np.arange(height.size), comp[direction < 0])).any():
            continue  # one of the two directions holds only wiggles
        if abs(_line_angle(pts[direction > 0]) - _line_angle(pts[direction < 0])) < angle:
            continue  # the two directions lie along one line: a (near-vertical) fault, not two
        label[cells[direction < 0]] = next_label
        next_label += 1
    return label


def _forks(pts: np.ndarray, lateral: int, vertical: int) -> list:
    """(top, bottom) samples of the forks of one skin's cells ``pts`` (n, 2) (trace, sample): spans of at least
    ``2 * vertical`` samples whose samples hold two or more runs of traces (cells more than ``lateral`` traces
    apart), samples less than ``vertical`` apart joined (a gap the links bridge)."""
    order = np.lexsort((pts[:, 0], pts[:, 1]))
    x, t = pts[order, 0], pts[order, 1]
    starts = np.concatenate([[True], (t[1:] != t[:-1]) | (x[1:] - x[:-1] > lateral)])
    rows, first = np.unique(t, return_index=True)
    forked = rows[np.add.reduceat(starts.astype(np.int64), first) >= 2]
    cut = np.nonzero(np.diff(forked) >= vertical)[0]
    tops, bottoms = np.append(forked[:1], forked[cut + 1]), np.append(forked[cut], forked[-1:])
    return [(a, b) for a, b in zip(tops, bottoms) if b - a + 1 >= 2 * vertical]


def _fork_groups(pts: np.ndarray, top: float, bottom: float, scale: np.ndarray, angle: float):
    """(n,) int64 part of each of one skin's cells ``pts`` (n, 2) split at the fork from sample ``top`` to
    ``bottom`` (0: the largest branch's), or None (see :func:`split_forks`); ``scale`` the reach (traces, samples)."""
    vertical = int(scale[1])
    core = np.nonzero((pts[:, 1] >= top + vertical) & (pts[:, 1] <= bottom - vertical))[0]
    if core.size < 2:
        return None
    comp = _components(cKDTree(pts[core] / scale).query_pairs(1.0, p=np.inf, output_type="ndarray"),
                       np.zeros(core.size, np.int64), core.size)
    spans = [np.ptp(pts[core[comp == c], 1]) + 1 for c in range(comp.max() + 1)]
    branches = [c for c in np.argsort(-np.bincount(comp), kind="stable") if spans[c] >= vertical]
    angles = [_line_angle(pts[core[comp == c]]) for c in branches]
    heads, part = [], []  # a branch joins the first (larger) one within ``angle`` of its line
    for a in angles:
        part.append(next((g for g, h in enumerate(heads) if abs(a - angles[h]) < angle), len(heads)))
        heads += [len(part) - 1] if part[-1] == len(heads) else []
    if len(heads) < 2:
        return None
    index, branch = np.full(comp.max() + 1, -1, np.int64), np.full(len(pts), -1, np.int64)  # the cells' branches
    index[branches], branch[core] = np.arange(len(branches)), index[comp]
    # the fork's other cells (its ends, short pieces) go with the branch whose line passes nearest
    inside = (pts[:, 1] >= top) & (pts[:, 1] <= bottom)
    rest = np.nonzero(inside & (branch < 0))[0]
    lines = [(pts[core[comp == c]].mean(axis=0), np.tan(np.radians(a))) for c, a in zip(branches, angles)]
    branch[rest] = np.argmin([np.abs(m[0] + b * (pts[rest, 1] - m[1]) - pts[rest, 0]) for m, b in lines], axis=0)
    # a branch is joined at both ends when a cell beyond the fork lies within two link reaches of its top and of its
    # bottom; a lens (every branch joined: strands parting and joining again) is one fault
    beyond = cKDTree(pts[~inside] / scale) if (~inside).any() else None
    ends = [pts[branch == i][np.argsort(pts[branch == i, 1])[[0, -1]]] for i in range(len(branches))]
    joined = [beyond is not None and beyond.query(e / scale, p=np.inf)[0].max() <= 2.0 for e in ends]
    if all(joined):
        return None
    group = np.where(branch >= 0, np.asarray(part)[branch], -1)
    # each trunk (a linked part above or below the fork) goes with a branch joined at both ends (the fault through
    # the fork) if any, the one whose cell nearest the trunk lies closest to the trunk's line (fitted within 4 reaches)
    through = {part[i] for i in range(len(branches)) if joined[i]}
    rest = np.nonzero(group < 0)[0]
    below = np.where(pts[rest, 1] > bottom, 1e6, 0.0)[:, None]
    parts = _components(cKDTree(pts[rest] / scale + below).query_pairs(1.0, p=np.inf, output_type="ndarray"),
                        np.zeros(rest.size, np.int64), rest.size) if rest.size else np.zeros(0, np.int64)
    for p in range(parts.max() + 1 if rest.size else 0):
        cells = rest[parts == p]
        edge = top if pts[cells[0], 1] < top else bottom
        close = cells[np.abs(pts[cells, 1] - edge) <= 4 * vertical]
        fit = pts[close if close.size >= 2 else cells]
        (x0, t0), slope, miss = fit.mean(axis=0), np.tan(np.radians(_line_angle(fit))), []
        for g in range(len(heads)):
            mine = np.nonzero(group == g)[0]
            dist, j = cKDTree(pts[mine] / scale).query(pts[cells] / scale)
            x, t = pts[mine[j[np.argmin(dist)]]]
            miss.append(abs(x0 + slope * (t - t0) - x) if not through or g in through else np.inf)
        group[cells] = int(np.argmin(miss))
    return group


def split_forks(xz, label, minimum: int, lateral: int, vertical: int, angle: float) -> np.ndarray:
    """Split the 2D skins that fork into branches along lines at least ``angle`` degrees apart (see
    ``SkinOptions.split_forks``); the labels (n,) int64, each part split off a new label above every old one.

    In a skin of at least ``minimum`` cells, a fork is a span of at least ``2 * vertical`` samples whose samples hold
    two or more runs of traces (cells more than ``lateral`` traces apart). In the fork less ``vertical`` samples at
    each end, the cells linked within the reach (``lateral`` traces, ``vertical`` samples) spanning ``vertical``
    samples or more are its branches, fitted with lines; the fork's other cells go with the nearest line. A branch
    within ``angle`` of a larger one's line stays with it, the others become new skins, when a branch ends free (a
    lens whose branches join again at both ends stays whole) and each part holds ``minimum`` cells (a piece too
    small to be kept would only be cut off its fault); each linked part above or below the fork (a trunk) goes with
    a branch joined at both ends if any, the one whose cell nearest it lies closest to its line. Parts are looked at
    again (up to 8 splits). A side spur, a straight or gently curved fault and branches along one line stay whole.

    Parameters
    ----------
    xz : (n, 2) ndarray of int
        The cells' (trace, sample) indices.
    label : (n,) ndarray of int
        The cells' skin labels (>= 0).
    minimum : int
        Skins with fewer cells are left as they are.
    lateral, vertical : int
        The link reach across traces and along samples (>= 1).
    angle : float
        Smallest angle between two branches' fitted lines for a split, degrees.
    """
    xz = np.asarray(xz, np.float64)
    label = np.asarray(label, np.int64).copy()
    scale = np.array([float(lateral), float(vertical)])
    next_label = int(label.max()) + 1 if label.size else 0
    for skin in np.nonzero(np.bincount(label) >= max(int(minimum), 2))[0]:
        todo, splits = [int(skin)], 0
        while todo and splits < 8:
            own = todo.pop()
            cells = np.nonzero(label == own)[0]
            for top, bottom in _forks(xz[cells], int(lateral), int(vertical)) if cells.size >= minimum else []:
                group = _fork_groups(xz[cells], top, bottom, scale, float(angle))
                if group is not None and np.bincount(group).min() >= minimum:  # each part a skin that may be kept
                    for g in range(1, int(group.max()) + 1):
                        label[cells[group == g]] = next_label
                        todo, next_label = todo + [next_label], next_label + 1
                    todo.append(own)
                    splits += 1
                    break
    return label


def heights(samples: np.ndarray, label: np.ndarray, roots: np.ndarray) -> np.ndarray:
    """Extent along the sample axis (max - min + 1) of the skins ``roots``, samples."""
    top = np.full(label.size, np.iinfo(np.int64).max, dtype=np.int64)
    bottom = np.full(label.size, -1, dtype=np.int64)
    np.minimum.at(top, label, samples)
    np.maximum.at(bottom, label, samples)
    return bottom[roots] - top[roots] + 1


_POINT_ARRAYS = ("points", "likelihood", "strike_deg", "dip_deg", "normals")


def trimmed_tips(faults: list, throws: list, likelihood, level: float | None) -> tuple[list, list]:
    """The 2D faults with their ends cut back to the first point, from each end along the sample axis, whose fault
    likelihood (the largest within a trace either side: the faults lie on the ridges of the votes, which may pass a
    trace off the likelihood's own ridge) reaches ``level``; and their throws' per-point arrays cut alike.

    A fault whose likelihood reaches ``level`` nowhere is left whole (the evidence kept it, on its displacement).
    Its throw's values measured over the whole fault (median throw, step, fitness) are left as measured.

    Parameters
    ----------
    faults : list of Fault
        2D faults, points (trace, sample) into ``likelihood``.
    throws : list of FaultThrow
        Their throws, in the same order (per-point arrays in the order of the fault's points).
    likelihood : (n_traces, n_samples) array_like of float, or None
        The fault likelihood they were traced from (the network's probability); None: nothing is trimmed.
    level : float or None
        In [0, 1]; None: nothing is trimmed.

    Returns
    -------
    faults, throws : list
        In the input's order, with the same ids; the points of a trimmed fault (and its throw's per-point values)
        in the order of their samples.

    Raises
    ------
    InputError
        ``likelihood`` is not 2D, ``level`` lies outside [0, 1], or faults and throws differ in number.

    Examples
    --------
    >>> import numpy as np
    >>> from seismo3d.seismic.faults.result import Fault
    >>> lik = np.zeros((8, 40), np.float32); lik[4, 10:30] = 0.9
    >>> pts = np.stack([np.full(40, 4), np.arange(40)], axis=1)
    >>> f = Fault(1, pts, np.ones(40, np.float32), np.full(40, 90, np.float32), np.full(40, 80, np.float32),
    ...           np.tile(np.float32([1, 0]), (40, 1)))
    >>> g = trimmed_tips([f], [None], lik, 0.3)[0][0]
    >>> int(g.points[0, 1]), int(g.points[-1, 1])
    (10, 29)
    """
    if level is None or likelihood is None or not faults:
        return list(faults), list(throws)
    lik = np.asarray(likelihood)
    if lik.ndim != 2:
        raise InputError(f"trimmed_tips needs a 2D likelihood (n_traces, n_samples); got shape {lik.shape}")
    if not 0.0 <= float(level) <= 1.0:
        raise InputError(f"the tip level must be in [0, 1]; got {level!r}")
    if len(faults) != len(throws):
        raise InputError(f"{len(faults)} faults but {len(throws)} throws; pass the throws of these faults")
    near = maximum_filter(lik, size=(3, 1), mode="nearest")
    out_faults, out_throws = [], []
    for f, t in zip(faults, throws):
        n = len(f.points)
        order = np.argsort(f.points[:, -1], kind="stable")
        held = np.nonzero(near[f.points[order, 0], f.points[order, -1]] >= float(level))[0]
        if held.size == 0 or (held[0] == 0 and held[-1] == n - 1):
            out_faults.append(f)
            out_throws.append(t)
            continue
        take = order[held[0]:held[-1] + 1]
        out_faults.append(dataclasses.replace(f, **{name: getattr(f, name)[take] for name in _POINT_ARRAYS}))
        out_throws.append(t if t is None else dataclasses.replace(t, **{
            field.name: getattr(t, field.name)[take] for field in dataclasses.fields(t)
            if isinstance(getattr(t, field.name), np.ndarray) and getattr(t, field.name).shape[:1] == (n,)}))
    return out_faults, out_throws
