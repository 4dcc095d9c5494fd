"""Terrain as a 2.5D surface: height grids rasterised from point clouds, and points with normals from grids.

A :class:`HeightGrid` is a north-up grid of square cells in a local metric (or file-unit) frame: cell ``(row, col)``
has its centre at ``x = x0 + col * cell``, ``y = y0 - row * cell``. It is how LiDAR scans and DEMs are turned into
images for feature matching, and how DEM cells become points with exact surface normals for point-to-plane ICP.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .._validation import as_points, check_choice, check_positive
from ..errors import InputError
from .hillshade import terrain_gradient

__all__ = ["HeightGrid", "rasterize_points", "grid_normals", "point_spacing", "sample_grid", "fill_holes",
           "footprint"]


@dataclass(frozen=True)
class HeightGrid:
    """A north-up grid of heights with square cells.

    Attributes
    ----------
    elevation : (H, W) float64 ndarray
        Height of each cell; cells without data filled smoothly (:func:`fill_holes`).
    observed : (H, W) bool ndarray
        Cells that held at least one point.
    x0, y0 : float
        x and y of the centre of cell (0, 0) (top-left: the largest y).
    cell : float
        Cell side, in the points' unit.
    """

    elevation: np.ndarray
    observed: np.ndarray
    x0: float
    y0: float
    cell: float

    def xy(self, rows, cols):
        """x, y of (fractional) cell indices."""
        return self.x0 + np.asarray(cols, np.float64) * self.cell, self.y0 - np.asarray(rows, np.float64) * self.cell

    def rowcol(self, x, y):
        """Fractional (row, col) of x, y."""
        return (self.y0 - np.asarray(y, np.float64)) / self.cell, (np.asarray(x, np.float64) - self.x0) / self.cell


def point_spacing(points) -> float:
    """Mean horizontal spacing of a 2.5D point set: ``sqrt(occupied area / N)`` (area from 1 m-scale occupancy).

    Parameters
    ----------
    points : (N, 3) array_like

    Returns
    -------
    float
        In the points' unit.
    """
    pts = as_points(points, "points", dims=(3,), min_points=2)
    xy = pts[:, :2]
    extent = np.ptp(xy, axis=0)
    rough = float(np.sqrt(max(extent[0] * extent[1], 1e-300) / len(pts)))
    # occupied area at 4x the uniform spacing: holes (water, shadows) do not thin the estimate
    coarse = 4.0 * rough
    keys = np.unique(np.floor((xy - xy.min(axis=0)) / coarse).astype(np.int64), axis=0)
    return float(np.sqrt(len(keys) * coarse * coarse / len(pts)))


def rasterize_points(points, cell: float, *, statistic: str = "max", fill: bool = True) -> HeightGrid:
    """Grid 2.5D points into a height grid.

    Parameters
    ----------
    points : (N, 3) array_like
        x, y, z (any unit; the grid keeps it).
    cell : float
        Cell side in the points' unit.
    statistic : {'max', 'mean', 'min'}
        Height of a cell from its points: the top surface (``'max'``, a digital surface model), their mean, or the
        lowest (``'min'``, closest to bare earth).
    fill : bool
        Fill empty cells smoothly (:func:`fill_holes`; for images, :attr:`HeightGrid.observed` keeps the truth);
        otherwise they are NaN.

    Returns
    -------
    HeightGrid

    Raises
    ------
    InputError
        Bad points, cell or statistic.
    """
    pts = as_points(points, "points", dims=(3,))
    cell = check_positive(cell, "cell")
    check_choice(statistic, "statistic", ("max", "mean", "min"))
    lo = pts[:, :2].min(axis=0)
    hi = pts[:, :2].max(axis=0)
    n_cols = int(np.floor((hi[0] - lo[0]) / cell)) + 1
    n_rows = int(np.floor((hi[1] - lo[1]) / cell)) + 1
    if n_cols * n_rows > 50_000_000:
        raise InputError(f"a {cell:g} cell grid over this extent has {n_rows} x {n_cols} cells; use a larger cell")
    cols = np.floor((pts[:, 0] - lo[0]) / cell).astype(np.int64)
    rows = (n_rows - 1) - np.floor((pts[:, 1] - lo[1]) / cell).astype(np.int64)
    flat = rows * n_cols + cols
    size = n_rows * n_cols
    if statistic == "mean":
        count = np.bincount(flat, minlength=size)
        z = np.bincount(flat, weights=pts[:, 2], minlength=size) / np.maximum(count, 1)
        observed = count > 0
    else:
        z = np.full(size, -np.inf if statistic == "max" else np.inf)
        (np.maximum if statistic == "max" else np.minimum).at(z, flat, pts[:, 2])
        observed = np.isfinite(z)
    z = z.reshape(n_rows, n_cols)
    observed = observed.reshape(n_rows, n_cols)
    z[~observed] = np.nan
    if fill:
        z = fill_holes(z, observed)
    x0 = lo[0] + 0.5 * cell
    y0 = lo[1] + (n_rows - 0.5) * cell
    return HeightGrid(z, observed, float(x0), float(y0), float(cell))


def grid_normals(elevation, spacing) -> np.ndarray:
    """Unit upward normals of a height grid, from its central-difference gradient.

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights, in the unit of ``spacing``.
    spacing : (dy, dx) or (2, 2) array_like
        Grid spacing (see :mod:`seismo3d.terrain.hillshade`).

    Returns
    -------
    (H, W, 3) float64 ndarray
        ``(-dz/dx, -dz/dy, 1) / norm`` (x east, y north); NaN at and next to nodata.
    """
    g = terrain_gradient(elevation, spacing)
    n = np.stack([-g.east, -g.north, np.ones_like(g.east)], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def sample_grid(grid: HeightGrid, x, y) -> np.ndarray:
    """Bilinear height of a grid at x, y; NaN outside the grid or where a corner cell was not observed.

    Parameters
    ----------
    grid : HeightGrid
    x, y : (K,) array_like

    Returns
    -------
    (K,) float64 ndarray
    """
    r, c = grid.rowcol(x, y)
    h, w = grid.elevation.shape
    inside = (r >= 0) & (r <= h - 1) & (c >= 0) & (c <= w - 1)
    out = np.full(np.shape(r), np.nan)
    if not inside.any():
        return out
    rr, cc = r[inside], c[inside]
    z = ndimage.map_coordinates(grid.elevation, [rr, cc], order=1, mode="nearest")
    r0 = np.clip(np.floor(rr).astype(np.int64), 0, h - 1)
    c0 = np.clip(np.floor(cc).astype(np.int64), 0, w - 1)
    r1 = np.minimum(r0 + 1, h - 1)
    c1 = np.minimum(c0 + 1, w - 1)
    seen = grid.observed[r0, c0] & grid.observed[r0, c1] & grid.observed[r1, c0] & grid.observed[r1, c1]
    out[inside] = np.where(seen, z, np.nan)
    return out


def fill_holes(elevation, observed) -> np.ndarray:
    """Fill unobserved cells smoothly by push-pull interpolation (a mask-weighted image pyramid).

    Push: halve the grid repeatedly, each coarse cell the weighted mean of its observed children, until every cell
    has data; pull: back up the pyramid, each unobserved fine cell takes the bilinear interpolation of the coarser
    level. Observed cells keep their values. Unlike nearest-neighbour filling it draws no edges between regions
    (edges would be features for the matcher).

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights (values at unobserved cells are ignored).
    observed : (H, W) array_like of bool
        Cells with data (at least one).

    Returns
    -------
    (H, W) float64 ndarray

    Raises
    ------
    InputError
        If no cell is observed or the shapes differ.

    References
    ----------
    Gortler, S. J., Grzeszczuk, R., Szeliski, R., Cohen, M. F. (1996). The lumigraph. SIGGRAPH '96, 43-54
    (pull-push). doi:10.1145/237170.237200
    """
    z = np.asarray(elevation, dtype=np.float64)
    m = np.asarray(observed, dtype=bool)
    if z.shape != m.shape or z.ndim != 2:
        raise InputError(f"elevation {z.shape} and observed {m.shape} must be 2D grids of one shape")
    if not m.any():
        raise InputError("no cell is observed; nothing to fill from")
    if m.all():
        return z.copy()
    return _push_pull(np.where(m, z, 0.0), m.astype(np.float64))


def _push_pull(z, w):
    h, wd = z.shape
    if h <= 1 and wd <= 1:
        return z
    ph, pw = h + h % 2, wd + wd % 2
    zp = np.zeros((ph, pw))
    wp = np.zeros((ph, pw))
    zp[:h, :wd] = z * w
    wp[:h, :wd] = w
    zs = zp.reshape(ph // 2, 2, pw // 2, 2).sum(axis=(1, 3))
    ws = wp.reshape(ph // 2, 2, pw // 2, 2).sum(axis=(1, 3))
    coarse = np.where(ws > 0, zs / np.maximum(ws, 1e-300), 0.0)
    wc = (ws > 0).astype(np.float64)
    if not wc.all():
        coarse = _push_pull(coarse, wc)
    # bilinear upsampling: fine cell i sits at coarse coordinate (i - 0.5) / 2
    rr = np.clip((np.arange(h) - 0.5) / 2.0, 0, coarse.shape[0] - 1)
    cc = np.clip((np.arange(wd) - 0.5) / 2.0, 0, coarse.shape[1] - 1)
    up = ndimage.map_coordinates(coarse, np.meshgrid(rr, cc, indexing="ij"), order=1, mode="nearest")
    return np.where(w > 0, z, up)


def footprint(observed, *, close: int = 2, margin: int = 2) -> np.ndarray:
    """Cells inside the data: observed cells with gaps up to ``2 * close`` cells closed, shrunk by ``margin`` cells.

    Parameters
    ----------
    observed : (H, W) array_like of bool
    close, margin : int
        Closing and erosion iterations (cells).

    Returns
    -------
    (H, W) bool ndarray
    """
    m = np.asarray(observed, dtype=bool)
    if close > 0:
        m = ndimage.binary_closing(np.pad(m, close), iterations=int(close))[close:-close, close:-close]
    if margin > 0:
        m = ndimage.binary_erosion(m, iterations=int(margin), border_value=0)
    return m
