"""Lineaments of a DEM: long straight terrain edges (fault scarps, fracture-controlled valleys, the paper's neotectonic
structures), found by oriented gradients, the Hough transform and linking.

The pipeline (:func:`extract_lineaments`), each step a named function:

0. :func:`flat_water`: lakes and reservoirs (a connected region of exactly one elevation over a least area) are kept
   out with the nodata: their shores are edges of the DEM's flattening, not of the terrain. Steps 1-5 then run on the
   DEM itself and on the DEM averaged to pixels of about 200 and 400 m (``level_pixels_m``), where a valley wall
   dissected by gullies is a straight edge; a lineament of a coarser level must follow edges of the DEM itself over
   half its length;
1. :func:`residual_relief`: the DEM minus its regional relief (a Gaussian of ``regional_px``): a lineament is a local
   break in the surface, and the long slopes of hills would otherwise take the strongest gradients;
2. :func:`terrain_edges`: Canny edges of that residual relief (non-maximum suppression of the gradient across the
   edge, hysteresis between two quantiles of the gradient magnitude): the line of steepest slope of each break;
3. :func:`orientation_classes`: each edge pixel's gradient orientation from the HOG machinery
   (:func:`seismo3d.features.orientation_votes`, the votes of method.md section 2), folded to ``n_orientations``
   classes over 180 degrees. The relief term of a hillshade lit from azimuth ``a`` is the slope along ``a``, so the
   edges of class ``a`` are those the hillshade from ``a`` shows best: the classes are the multi-directional
   hillshade set of manual lineament mapping;
4. :func:`hough_segments`: scikit-image's probabilistic Hough transform on each class's edges, with the line normals
   restricted to that class (and its neighbours), so crossing structures do not merge;
5. :func:`link_segments`: collinear segments (direction, offset and gap within tolerances) are merged, repeatedly,
   into lineaments fitted by total least squares;
6. :func:`lineament_contrast`: each lineament's contrast, the median across-line slope along it over the median
   slope of the residual relief; lineaments shorter than ``min_length_px`` or with too little evidence
   ``(contrast - 1) * length`` are dropped (lengths in the DEM's pixels at every level);
7. the lineaments of all levels ranked by evidence, and one that lies along a higher-ranked one of similar strike
   (the same structure at another level) dropped.

Azimuths and lengths are measured in metres in the map (pixel sizes of geographic rasters converted), so they do not
depend on the pixel aspect ratio.

References
----------
Canny, J. (1986). A computational approach to edge detection. IEEE TPAMI 8(6), 679-698. doi:10.1109/TPAMI.1986.4767851
Matas, J., Galambos, C., Kittler, J. (2000). Robust detection of lines using the progressive probabilistic Hough
transform. CVIU 78(1), 119-137. doi:10.1006/cviu.1999.0831
Smith, M. J., Clark, C. D. (2005). Methods for the visualization of digital elevation models for landform mapping.
Earth Surf. Process. Landforms 30, 885-900. doi:10.1002/esp.1210
Masoud, A., Koike, K. (2011). Auto-detection and integration of tectonically influenced lineaments from DEMs.
ISPRS J. Photogramm. Remote Sens. 66(6), 818-832. doi:10.1016/j.isprsjprs.2011.08.003
"""

from __future__ import annotations

import csv
import pathlib
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .._atomic import atomic_path
from .._validation import check_positive
from ..errors import InputError
from ..features import orientation_votes
from .dem import Dem
from .hillshade import as_metric_axes
from .lineament_segments import break_support, hough_segments, link_segments, same_structure
from .surface import fill_holes
from .water import flat_water

__all__ = ["LineamentOptions", "Lineaments", "extract_lineaments", "detect_lineaments", "flat_water", "residual_relief",
           "terrain_edges", "orientation_classes", "hough_segments", "link_segments", "lineament_contrast",
           "write_lineaments_csv", "rose_histogram"]


@dataclass(frozen=True)
class LineamentOptions:
    """Options of :func:`extract_lineaments` (pixels of the DEM, or metres where named; the same defaults on every DEM).

    The defaults were chosen on generated DEMs (seeds 0-9 and 100-119 of
    :func:`seismo3d.data.terrain.synthetic_scarp_dem`) and checked on others (seeds 200-249; benchmarks/terrain.py).

    Attributes
    ----------
    regional_px : float
        Sigma of the Gaussian regional relief removed before edge detection (0: none).
    smoothing_px : float
        Sigma of Canny's smoothing.
    high_quantile, low_quantile : float
        Canny's hysteresis thresholds as quantiles of the gradient magnitude.
    n_orientations : int
        Orientation classes over 180 degrees.
    hough_threshold : int
        Votes a Hough line needs.
    hough_length_px : int
        Shortest Hough segment.
    hough_gap_px : int
        Largest gap bridged inside a Hough segment.
    link_angle_deg, link_offset_px, link_gap_px : float
        Two lineaments merge when their directions differ by at most ``link_angle_deg``, the other's ends lie within
        ``link_offset_px`` of one's line and the gap between them along it is at most ``link_gap_px``.
    min_length_px : float
        Shortest lineament kept, in the DEM's pixels (at every level).
    min_evidence : float
        Smallest ``(contrast - 1) * length_px`` kept (the length in the DEM's pixels, at every level).
    border_px : int
        Edges this close to the raster's border or to nodata are ignored (smoothing artefacts).
    seed : int
        Seed of the probabilistic Hough transform (the result is deterministic given it).
    level_pixels_m : tuple of float
        The coarser scales searched besides the DEM itself, as pixel sizes in metres: steps 1-5 also run on the DEM
        averaged over blocks of ``f x f`` cells, ``f`` the whole number nearest to the ratio of each size to the
        DEM's pixel (levels of fewer than 16 x 16 blocks, or ``f`` of 1, are left out), the pixel values above in
        pixels of that level but the shortest lineament and its evidence in the DEM's pixels. A geologist reads an
        escarpment on the hillshade at the zoom where it is straight: a valley wall dissected by gullies is ragged
        at a 90 m pixel and a straight edge at 200-400 m, where the shortest Hough segment (10 pixels) is 2-4 km,
        the valley walls and escarpments of a regional map. A lineament of a coarser level must follow edges of the
        DEM itself over half its length (a break in the terrain, not the smooth flank of a hill).
    water_min_area_m2 : float
        Flat water: a 4-connected region of exactly one elevation of at least this area (m^2) is a water surface
        (lakes and reservoirs are flattened to one height in SRTM-derived DEMs such as HydroSHEDS and in LiDAR
        DEMs with hydro-flattening) and is treated like nodata: filled smoothly, and no edge within ``border_px`` of
        it. 1 km^2: land stays at one integer metre over 1 km^2 only where it is flatter than 1 m per km every way,
        which a DEM of metre steps shows only on the flattest floodplains, where no escarpment is; smaller ponds
        cannot line a lineament of the shortest length. 0 turns it off.
    overlap_px : float
        A lineament of one level that lies, over half its length, within this many pixels of its level (and within
        ``2 * link_angle_deg`` of strike) of a higher-ranked lineament of any level is the same structure seen
        at another scale, and is dropped.
"""

    regional_px: float = 8.0
    smoothing_px: float = 1.0
    high_quantile: float = 0.95
    low_quantile: float = 0.7
    n_orientations: int = 16
    hough_threshold: int = 8
    hough_length_px: int = 10
    hough_gap_px: int = 3
    link_angle_deg: float = 4.0
    link_offset_px: float = 2.5
    link_gap_px: float = 12.0
    min_length_px: float = 20.0
    min_evidence: float = 45.0
    border_px: int = 4
    seed: int = 0
    level_pixels_m: tuple = (200.0, 400.0)
    water_min_area_m2: float = 1.0e6
    overlap_px: float = 3.0

    def __post_init__(self):
        check_positive(self.regional_px, "regional_px", allow_zero=True)
        check_positive(self.smoothing_px, "smoothing_px")
        if not 0.0 < self.low_quantile <= self.high_quantile < 1.0:
            raise InputError(f"quantiles must satisfy 0 < low_quantile <= high_quantile < 1; got "
                             f"{self.low_quantile}, {self.high_quantile}")
        if not 4 <= int(self.n_orientations) <= 90:
            raise InputError(f"n_orientations must be in [4, 90]; got {self.n_orientations!r}")
        for name in ("hough_threshold", "hough_length_px"):
            if int(getattr(self, name)) < 1:
                raise InputError(f"{name} must be >= 1; got {getattr(self, name)!r}")
        for name in ("link_angle_deg", "link_offset_px", "min_length_px"):
            check_positive(getattr(self, name), name)
        for name in ("hough_gap_px", "link_gap_px", "min_evidence", "border_px", "water_min_area_m2"):
            check_positive(getattr(self, name), name, allow_zero=True)
        check_positive(self.overlap_px, "overlap_px")
        for size in self.level_pixels_m:
            check_positive(size, "level_pixels_m")


@dataclass(frozen=True)
class Lineaments:
    """Lineaments of a raster, K of them, ranked: the strongest evidence first (``(contrast - 1) * length``, the
    length in the raster's pixels), the longest first among equals.

    Attributes
    ----------
    rows0, cols0, rows1, cols1 : (K,) float64 ndarray
        End points in (fractional) pixel indices.
    azimuth_deg : (K,) float64 ndarray
        Strike: compass azimuth in the map, degrees clockwise from north, in [0, 180).
    length_m : (K,) float64 ndarray
        Length in metres.
    contrast : (K,) float64 ndarray
        Median across-line slope along the lineament over the median slope of the residual relief (>= 1 means
        steeper than the typical terrain).
    x0, y0, x1, y1 : (K,) float64 ndarray
        End points in the raster's CRS (pixel indices when it has no georeferencing).
    """

    rows0: np.ndarray
    cols0: np.ndarray
    rows1: np.ndarray
    cols1: np.ndarray
    azimuth_deg: np.ndarray
    length_m: np.ndarray
    contrast: np.ndarray
    x0: np.ndarray
    y0: np.ndarray
    x1: np.ndarray
    y1: np.ndarray

    def __len__(self) -> int:
        return int(self.azimuth_deg.shape[0])

    @property
    def segments_px(self) -> np.ndarray:
        """(K, 4) float64: ``row0, col0, row1, col1``."""
        return np.column_stack([self.rows0, self.cols0, self.rows1, self.cols1])


def residual_relief(elevation, regional_px: float) -> np.ndarray:
    """The elevation minus its regional trend (a Gaussian of ``regional_px`` pixels); the input when 0.

    Parameters
    ----------
    elevation : (H, W) array_like
        Finite heights.
    regional_px : float

    Returns
    -------
    (H, W) float64 ndarray
    """
    z = np.asarray(elevation, dtype=np.float64)
    if regional_px <= 0:
        return z.copy()
    return z - ndimage.gaussian_filter(z, float(regional_px), mode="nearest")


def terrain_edges(relief, *, smoothing_px: float, high_quantile: float, low_quantile: float, mask=None):
    """Canny edges of a relief grid with quantile thresholds.

    Parameters
    ----------
    relief : (H, W) array_like
    smoothing_px : float
    high_quantile, low_quantile : float
    mask : (H, W) bool array_like, optional
        Where edges may be.

    Returns
    -------
    (H, W) bool ndarray
    """
    from skimage.feature import canny

    return canny(np.asarray(relief, dtype=np.float64), sigma=float(smoothing_px), low_threshold=float(low_quantile),
                 high_threshold=float(high_quantile), use_quantiles=True, mask=mask)


def orientation_classes(relief, *, smoothing_px: float, n_orientations: int) -> np.ndarray:
    """Each pixel's gradient orientation class: the HOG vote bin (over 360 degrees, 2 n bins) with the larger vote,
    folded over 180 degrees.

    Class k holds normals at ``k * 180 / n`` degrees from the +column axis towards +row (the angle of scikit-image's
    Hough ``theta``), so the lines of class k run at ``k * 180 / n + 90`` degrees in pixel space.

    Parameters
    ----------
    relief : (H, W) array_like
    smoothing_px : float
        Gaussian smoothing before the derivatives.
    n_orientations : int

    Returns
    -------
    (H, W) int64 ndarray
        Classes in [0, n_orientations).
    """
    z = ndimage.gaussian_filter(np.asarray(relief, dtype=np.float64), float(smoothing_px), mode="nearest")
    g_row = ndimage.sobel(z, axis=0, mode="nearest")
    g_col = ndimage.sobel(z, axis=1, mode="nearest")
    bins, weights = orientation_votes(g_col, g_row, n_bins=2 * int(n_orientations))
    dominant = np.where(weights[..., 1] > weights[..., 0], bins[..., 1], bins[..., 0]).astype(np.int64)
    return dominant % int(n_orientations)


def lineament_contrast(relief, segments, *, smoothing_px: float) -> np.ndarray:
    """Median across-line slope along each segment over the median slope of the relief.

    The across-line slope at a sample is the largest ``|grad z . n|`` within 1.5 pixels across the line (n its
    normal), so a line half a pixel off its edge is not penalised.

    Parameters
    ----------
    relief : (H, W) array_like
    segments : (K, 4) array_like
        ``row0, col0, row1, col1``.
    smoothing_px : float

    Returns
    -------
    (K,) float64 ndarray
    """
    z = ndimage.gaussian_filter(np.asarray(relief, dtype=np.float64), float(smoothing_px), mode="nearest")
    g_row = ndimage.sobel(z, axis=0, mode="nearest") / 8.0
    g_col = ndimage.sobel(z, axis=1, mode="nearest") / 8.0
    typical = float(np.median(np.hypot(g_row, g_col))) or 1e-300
    out = np.zeros(len(segments))
    for k, (r0, c0, r1, c1) in enumerate(np.asarray(segments, dtype=np.float64).reshape(-1, 4)):
        length = np.hypot(r1 - r0, c1 - c0)
        m = max(int(np.ceil(length)), 2)
        rr, cc = np.linspace(r0, r1, m), np.linspace(c0, c1, m)
        nr, nc = -(c1 - c0) / max(length, 1e-12), (r1 - r0) / max(length, 1e-12)
        across = np.zeros(m)
        for off in (-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5):
            at = [rr + off * nr, cc + off * nc]
            gr = ndimage.map_coordinates(g_row, at, order=1, mode="nearest")
            gc = ndimage.map_coordinates(g_col, at, order=1, mode="nearest")
            across = np.maximum(across, np.abs(gr * nr + gc * nc))
        out[k] = float(np.median(across)) / typical
    return out


def _block_mean(z: np.ndarray, ok: np.ndarray, f: int):
    """The grid averaged over blocks of ``f x f`` cells (a partial block at the far edges averaged over what it
    holds) and the blocks that are mostly data."""
    if f == 1:
        return z, ok
    from skimage.measure import block_reduce

    weight = block_reduce(ok.astype(np.float64), (f, f), np.mean)
    total = block_reduce(np.where(ok, z, 0.0), (f, f), np.mean)
    keep = weight > 0.5
    return np.where(keep, total / np.maximum(weight, 1e-12), np.nan), keep


def _level_edges(z: np.ndarray, ok: np.ndarray, opts: LineamentOptions):
    """Steps 1-2 on one grid (``ok`` where data): its residual relief and the edges of it away from borders, nodata
    and water."""
    relief = residual_relief(fill_holes(z, ok), opts.regional_px)
    inside = ndimage.binary_erosion(np.pad(ok, 1), iterations=int(opts.border_px) + 1)[1:-1, 1:-1]
    edges = terrain_edges(relief, smoothing_px=opts.smoothing_px, high_quantile=opts.high_quantile,
                          low_quantile=opts.low_quantile, mask=inside)
    return relief, edges


def _detect_level(z: np.ndarray, ok: np.ndarray, opts: LineamentOptions, f: int = 1):
    """Steps 1-6 on one grid (``ok`` where data), the DEM averaged over blocks of ``f`` cells: segments ``row0,
    col0, row1, col1`` in its pixels, their contrast, and the grid's edges; the length and evidence kept are
    measured in the DEM's pixels (``f`` per pixel of the grid), so that a lineament is the same at every level."""
    relief, edges = _level_edges(z, ok, opts)
    classes = orientation_classes(relief, smoothing_px=opts.smoothing_px, n_orientations=opts.n_orientations)
    # 4-5: Hough segments per class, linked into lineaments
    segments = link_segments(hough_segments(edges, classes, opts), angle_deg=opts.link_angle_deg,
                             offset_px=opts.link_offset_px, gap_px=opts.link_gap_px)
    # 6: keep the long, contrasted ones
    length_px = f * np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    contrast = lineament_contrast(relief, segments, smoothing_px=opts.smoothing_px)
    keep = (length_px >= opts.min_length_px) & ((contrast - 1.0) * length_px >= opts.min_evidence)
    return segments[keep], contrast[keep], edges


def detect_lineaments(elevation, spacing, *, options: LineamentOptions | None = None, valid=None) -> Lineaments:
    """Lineaments of an elevation grid (steps 1-6 of the module docstring), with pixel coordinates only.

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights in metres (NaN = nodata, filled smoothly before filtering and masked from the edges).
    spacing : (dy, dx) or (2, 2) array_like
        Pixel size in metres, or the metric axes of the raster (see :mod:`seismo3d.terrain.hillshade`).
    options : LineamentOptions, optional
    valid : (H, W) bool array_like, optional
        Cells with data (default: finite elevations).

    Returns
    -------
    Lineaments
        ``x*, y*`` equal to the pixel columns and rows.

    Raises
    ------
    InputError
        A grid smaller than 16 x 16, without data, or bad options.
    """
    opts = options or LineamentOptions()
    z = np.asarray(elevation, dtype=np.float64)
    if z.ndim != 2 or min(z.shape) < 16:
        raise InputError(f"elevation must be a 2D grid of at least 16 x 16 cells; got shape {z.shape}")
    axes = as_metric_axes(spacing)
    ok = np.isfinite(z) if valid is None else np.asarray(valid, dtype=bool) & np.isfinite(z)
    if not ok.any():
        raise InputError("the DEM has no valid cells; nothing to extract lineaments from")
    # flat water is no terrain: kept out like nodata
    cell_area = abs(float(np.linalg.det(axes)))
    ok = ok & ~flat_water(z, cell_area, opts.water_min_area_m2, valid=ok)
    if not ok.any():
        raise InputError("the DEM holds only nodata and flat water; nothing to extract lineaments from")
    # steps 1-6 at each level, the segments back in the DEM's pixels
    found, contrasts, scales = [], [], []
    distance = None  # to the DEM's own edges, for the lineaments of coarser levels
    pixel_m = float(np.sqrt(cell_area))
    for f in sorted({1} | {int(round(size / pixel_m)) for size in opts.level_pixels_m} - {0}):
        zf, okf = _block_mean(z, ok, f)
        if min(zf.shape) < 16 or not okf.any():
            continue
        segments, contrast, edges = _detect_level(zf, okf, opts, f)
        segments = (segments + 0.5) * f - 0.5  # block centres, in the DEM's pixels
        if f == 1:
            distance = ndimage.distance_transform_edt(~edges)
        else:
            # a break in the terrain: a lineament seen at a coarser level follows edges of the DEM itself (a
            # ragged escarpment) over half its length at least, not the smooth flank of a hill
            supported = break_support(segments, distance, f) >= 0.5
            segments, contrast = segments[supported], contrast[supported]
        found.append(segments)
        contrasts.append(contrast)
        scales.append(np.full(len(contrast), float(f)))
    segments = np.concatenate(found).reshape(-1, 4) if found else np.zeros((0, 4))
    contrast = np.concatenate(contrasts) if found else np.zeros(0)
    scale = np.concatenate(scales) if found else np.zeros(0)
    east, north = _metric(segments, axes)
    length_m = np.hypot(east, north)
    azimuth = np.mod(np.degrees(np.arctan2(east, north)), 180.0)
    # ranked by evidence; the same structure found at several levels kept once, at its best rank
    length_px = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    order = np.lexsort((-length_m, -(contrast - 1.0) * length_px))
    keep = same_structure(segments, scale, azimuth, order, opts.overlap_px, 2.0 * opts.link_angle_deg)
    order = order[keep[order]]
    segments, contrast, length_m, azimuth = (a[order] for a in (segments, contrast, length_m, azimuth))
    r0, c0, r1, c1 = segments.T if len(segments) else (np.zeros(0),) * 4
    return Lineaments(r0, c0, r1, c1, azimuth, length_m, contrast, c0.copy(), r0.copy(), c1.copy(), r1.copy())


def _metric(segments, axes):
    """East and north components (metres) of each segment's vector from end 0 to end 1."""
    d_row = segments[:, 2] - segments[:, 0]
    d_col = segments[:, 3] - segments[:, 1]
    return axes[0, 0] * d_col + axes[0, 1] * d_row, axes[1, 0] * d_col + axes[1, 1] * d_row


def extract_lineaments(dem: Dem, *, options: LineamentOptions | None = None) -> Lineaments:
    """Lineaments of a DEM, with end points in its CRS, azimuths and lengths in metres.

    Parameters
    ----------
    dem : Dem
    options : LineamentOptions, optional

    Returns
    -------
    Lineaments

    Raises
    ------
    InputError
        A DEM smaller than 16 x 16 cells or bad options.

    Examples
    --------
    >>> from seismo3d.data.terrain import synthetic_scarp_dem
    >>> from seismo3d.terrain import detect_lineaments
    >>> truth = synthetic_scarp_dem(seed=3)
    >>> found = detect_lineaments(truth.elevation, (truth.pixel_size, truth.pixel_size))
    >>> len(found) >= len(truth.scarps) - 1
    True
    """
    if not isinstance(dem, Dem):
        raise InputError(f"dem must be a seismo3d.terrain.Dem (read_dem); got {type(dem).__name__}")
    found = detect_lineaments(dem.elevation_m, dem.metric_axes, options=options, valid=dem.valid)
    x0, y0 = dem.xy(found.rows0, found.cols0)
    x1, y1 = dem.xy(found.rows1, found.cols1)
    return Lineaments(found.rows0, found.cols0, found.rows1, found.cols1, found.azimuth_deg, found.length_m,
                      found.contrast, np.asarray(x0), np.asarray(y0), np.asarray(x1), np.asarray(y1))


def write_lineaments_csv(path, lineaments: Lineaments) -> pathlib.Path:
    """Write ``x0, y0, x1, y1, azimuth_deg, length_m, contrast`` (one lineament a row, in rank order), atomically.

    Parameters
    ----------
    path : str or os.PathLike
    lineaments : Lineaments

    Returns
    -------
    pathlib.Path
    """
    path = pathlib.Path(path)
    with atomic_path(path) as tmp:
        with open(tmp, "w", newline="") as fh:
            out = csv.writer(fh)
            out.writerow(["x0", "y0", "x1", "y1", "azimuth_deg", "length_m", "contrast"])
            for k in range(len(lineaments)):
                out.writerow([f"{lineaments.x0[k]:.12g}", f"{lineaments.y0[k]:.12g}", f"{lineaments.x1[k]:.12g}",
                              f"{lineaments.y1[k]:.12g}", f"{lineaments.azimuth_deg[k]:.2f}",
                              f"{lineaments.length_m[k]:.1f}", f"{lineaments.contrast[k]:.3f}"])
    return path


def rose_histogram(lineaments: Lineaments, *, bin_deg: float = 10.0):
    """Length-weighted histogram of lineament azimuths over [0, 180) (the data of a rose diagram).

    Parameters
    ----------
    lineaments : Lineaments
    bin_deg : float
        Bin width, degrees (must divide 180).

    Returns
    -------
    edges_deg : (B + 1,) float64 ndarray
    length_m : (B,) float64 ndarray
        Total length per bin, metres.

    Raises
    ------
    InputError
        If ``bin_deg`` does not divide 180.
    """
    n = 180.0 / float(bin_deg)
    if not bin_deg > 0 or abs(n - round(n)) > 1e-9:
        raise InputError(f"bin_deg must divide 180; got {bin_deg!r}")
    edges = np.linspace(0.0, 180.0, int(round(n)) + 1)
    hist, _ = np.histogram(lineaments.azimuth_deg, bins=edges, weights=lineaments.length_m)
    return edges, hist.astype(np.float64)
