"""Flat water of a DEM: lakes and reservoirs, flattened to one height in SRTM-derived DEMs (HydroSHEDS) and in
hydro-flattened LiDAR DEMs, found as connected regions of exactly one elevation over a least area.
"""

from __future__ import annotations

import numpy as np

__all__ = ["flat_water"]


def flat_water(elevation, cell_area_m2: float, min_area_m2: float, valid=None) -> np.ndarray:
    """Flat water: the 4-connected regions of exactly one elevation that cover at least ``min_area_m2``.

    Lakes and reservoirs are one height in SRTM-derived DEMs (HydroSHEDS) and in hydro-flattened LiDAR DEMs; their
    shores are edges of the flattening, not of the terrain (the choice of the least area:
    :class:`~seismo3d.terrain.LineamentOptions`' ``water_min_area_m2``).

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights, metres (NaN = nodata, never water).
    cell_area_m2 : float
        Area of one cell, m^2.
    min_area_m2 : float
        Least area of a water surface, m^2 (0: no water).
    valid : (H, W) bool array_like, optional
        Cells with data (default: finite elevations).

    Returns
    -------
    (H, W) bool ndarray
    """
    z = np.asarray(elevation, dtype=np.float64)
    ok = np.isfinite(z) if valid is None else np.asarray(valid, dtype=bool) & np.isfinite(z)
    water = np.zeros(z.shape, dtype=bool)
    if min_area_m2 <= 0:
        return water
    min_cells = max(int(np.ceil(min_area_m2 / float(cell_area_m2))), 2)
    # equal neighbours, 4-connected: regions of one height are the components of the graph of equal pairs
    same_row = ok[:, 1:] & ok[:, :-1] & (z[:, 1:] == z[:, :-1])
    same_col = ok[1:, :] & ok[:-1, :] & (z[1:, :] == z[:-1, :])
    flat = np.zeros(z.shape, dtype=bool)
    flat[:, 1:] |= same_row
    flat[:, :-1] |= same_row
    flat[1:, :] |= same_col
    flat[:-1, :] |= same_col
    if np.count_nonzero(flat) < min_cells:
        return water
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    index = np.arange(z.size).reshape(z.shape)
    a = np.concatenate([index[:, :-1][same_row], index[:-1, :][same_col]])
    b = np.concatenate([index[:, 1:][same_row], index[1:, :][same_col]])
    graph = coo_matrix((np.ones(a.size, dtype=np.int8), (a, b)), shape=(z.size, z.size))
    _, labels = connected_components(graph, directed=False)
    sizes = np.bincount(labels)
    water = (sizes[labels] >= min_cells).reshape(z.shape) & flat
    return water
