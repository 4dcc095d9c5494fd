"""The merging of fault skins that continue each other (seismo3d.seismic.faults.surfaces.skin_merging): the closest
cells of two skins within the gap."""

import numpy as np
import pytest

from seismo3d.seismic.faults.surfaces import skin_merging
from seismo3d.seismic.faults.surfaces.skin_merging import closest_pairs


@pytest.mark.slow
@pytest.mark.parametrize("two_d, side, n_labels, pairs", [(False, 30, 12, None), (True, 30, 12, None),
                                                          (False, 90, 60, 20), (False, 30, 12, 300),
                                                          (True, 300, 60, None)])
def test_closest_pairs_of_skins_equal_a_brute_force_search(two_d, side, n_labels, pairs, monkeypatch):
    # the merge step's search (a k-d tree, a query of edge cells at a time) against every pair: for each two skins,
    # the closest (edge cell, cell of the other skin) within the gap, ties to the lower edge cell, then the lower
    # other cell. Sparse cells (side 90 and 300) leave each query of edge cells a few pairs only; a budget of 20 or
    # 300 pairs a query: queries of a few edge cells each, sized by the query before, the closest pair of two skins
    # found across them
    if pairs is not None:
        monkeypatch.setattr(skin_merging, "_PAIRS_PER_QUERY", pairs)
        monkeypatch.setattr(skin_merging, "_FEWEST_EDGES", 1)
        monkeypatch.setattr(skin_merging, "_FIRST_EDGES", 4)

    rng = np.random.default_rng(7)
    pts = rng.integers(0, side, (600, 3)).astype(np.float64)
    if two_d:
        pts[:, 1] = 0.0
    pts = np.unique(pts, axis=0)
    lab = rng.integers(0, n_labels, len(pts))
    edge = np.sort(rng.choice(len(pts), len(pts) // 3, replace=False))
    gap = 5.0
    best = {}
    for i in edge:
        for j in range(len(pts)):
            d = float(np.linalg.norm(pts[i] - pts[j]))
            if lab[i] != lab[j] and d <= gap:
                key = (min(lab[i], lab[j]), max(lab[i], lab[j]))
                best[key] = min(best.get(key, (np.inf, 0, 0)), (d, int(i), j))
    got = closest_pairs(pts, lab, edge, gap, n_labels)
    assert len(best) > 20
    assert sorted(map(tuple, got.tolist())) == sorted((i, j) for _, i, j in best.values())


@pytest.mark.slow
@pytest.mark.parametrize("gap", [3.0, 12.0, 12.5])
def test_closest_pairs_of_skins_apart_equal_a_brute_force_search(gap):
    # skins as patches of planes, most cells farther than the gap from every other skin (those the search leaves
    # out, _near_other_labels): the same closest pairs as every pair of cells gives
    rng = np.random.default_rng(3)
    patches = []
    for n, (x0, y0, z0) in enumerate([(0, 0, 0), (6, 0, 31), (13, 4, 10), (40, 0, 0), (45, 30, 60)]):
        j, k = np.meshgrid(np.arange(25), np.arange(30), indexing="ij")
        x = x0 + np.round(0.2 * (k - 15)).astype(int)  # a dipping plane
        patches.append(np.stack([x.ravel(), (y0 + j).ravel(), (z0 + k).ravel()], axis=1))
    pts = np.concatenate(patches).astype(np.float64)
    lab = np.concatenate([np.full(len(p), n) for n, p in enumerate(patches)])
    edge = np.sort(rng.choice(len(pts), len(pts) // 4, replace=False))
    d = np.sqrt(((pts[edge, None, :] - pts[None, :, :]) ** 2).sum(axis=-1))
    best = {}
    for a, b in zip(*np.nonzero((d <= gap) & (lab[edge, None] != lab[None, :]))):
        i, j = int(edge[a]), int(b)
        key = (min(lab[i], lab[j]), max(lab[i], lab[j]))
        best[key] = min(best.get(key, (np.inf, 0, 0)), (float(d[a, b]), i, j))
    near = skin_merging._near_other_labels(pts, lab, gap)
    assert 0 < np.count_nonzero(near) < len(pts)  # the search skips some cells
    got = closest_pairs(pts, lab, edge, gap, len(patches))
    assert len(best) >= (1 if gap < 12 else 2)
    assert sorted(map(tuple, got.tolist())) == sorted((i, j) for _, i, j in best.values())


def test_closest_pairs_with_a_gap_small_for_the_cloud_keep_every_cell(monkeypatch):
    # two skins 2 samples apart at the ends of a wide cloud, gap 2.5: the grid of _near_other_labels would hold more
    # grid cells than _GRID_CELLS_PER_POINT a cell, so every cell is searched, with the same pairs as a brute force
    line = np.arange(0, 3000, 1.0)
    pts = np.concatenate([np.stack([line, 0 * line, 0 * line], 1), np.stack([line, 0 * line + 2, 0 * line + 3000], 1),
                          np.array([[0.0, 2.0, 0.0]])])
    lab = np.concatenate([np.zeros(line.size, int), np.ones(line.size + 1, int)])
    assert skin_merging._near_other_labels(pts, lab, 2.5).all()
    edge = np.arange(len(pts))
    got = closest_pairs(pts, lab, edge, 2.5, 2)
    assert got.tolist() == [[0, 2 * line.size]]  # (0, 0, 0) and (0, 2, 0), 2 apart: the closest, the lower first
