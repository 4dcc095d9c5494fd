"""The splits of 2D fault skins (:mod:`~seismo3d.seismic.faults.surfaces.skins`) that linked two faults into one.

- :func:`split_opposite_dips` (``SkinOptions.split_angle``): a fault plane dips one way, but the linking keeps to one
  mean normal within ``max_angle``, so two steep faults dipping opposite ways (a Y and its antithetic branch, an
  inverted V) whose normals lie closer than that link into one skin, whose zone then spans the block between them and
  whose throw compares the reflectors outside both.
- :func:`split_forks` (``SkinOptions.split_forks``): two faults that meet (a Y, an X) link into one skin; their
  branches' lines, not their normals, tell them apart."""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

__all__ = ["split_forks", "split_opposite_dips"]


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
