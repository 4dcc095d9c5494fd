"""Registration of terrain: LiDAR scan to LiDAR scan, DEM to DEM, LiDAR scan to DEM, with the fused ICP of eq. 16.

The pipeline (each step a named function):

1. :func:`terrain_frame`: one local frame for both inputs (recentred on the target; degrees to metres for
   geographic CRSs), so no fit sees large projected coordinates;
2. :func:`terrain_surface`: each input as points in that frame, with normals for the target (PCA over neighbours for
   a scan, the grid gradient for a DEM: a DEM is a 2.5D surface) and a north-up height grid of square cells;
3. :func:`match_hillshades`: the HOG-pyramid matcher (method.md section 2) on the slope shading of both grids (the
   zenith-lit hillshade ``cos(slope)`` in angle units: unchanged by rotations about the vertical, so the matches do
   not depend on any initial guess), verified by a 2D similarity, lifted to 3D through the grids' heights;
4. :func:`~seismo3d.registration.fused_icp`: RANSAC on the lifted matches for the start, then feature and dense
   point-to-plane terms in one objective (eq. 16), coarse to fine;
5. the transform back in the files' coordinates (:meth:`~seismo3d.terrain.georef.LocalFrame.transform_to_file`).
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .._options import resolve_options
from .._validation import check_positive
from ..errors import DegenerateGeometryWarning, InputError, RegistrationError, Seismo3dWarning
from ..features import match_images
from ..geometry import estimate_normals, voxel_downsample
from ..registration import ICPOptions, RegistrationResult, fused_icp, icp
from .dem import Dem
from .georef import LocalFrame, check_compatible
from .hillshade import slope_deg
from .lidar import LidarScan
from .surface import HeightGrid, fill_holes, grid_normals, point_spacing, rasterize_points, sample_grid

__all__ = ["TerrainRegistrationOptions", "TerrainSurface", "FeaturePairs", "TerrainRegistration", "terrain_frame",
           "terrain_surface", "match_hillshades", "register_terrain"]


@dataclass(frozen=True)
class TerrainRegistrationOptions:
    """Options of :func:`register_terrain` (defaults are used for every input; nothing is tuned per file).

    Attributes
    ----------
    cell : float or None
        Cell of the hillshade images, in the local frame's unit (the files' unit, metres for geographic CRSs).
        Default: the coarser input's spacing (a scan's mean point spacing times 1.5, so that cells hold points; a
        DEM's larger pixel side).
    features : bool
        Start from hillshade feature matches (True) or from ``init`` / the identity only.
    alpha : float
        Weight of the feature term in eq. 16, in [0, 1].
    max_points : int
        Scans with more points are voxel-downsampled to about this many (DEM cells alike).
    max_distance : tuple of float or None
        Coarse-to-fine maximum correspondence distances in the local unit. Default: ``icp.max_distance`` when set;
        otherwise ``distance_cells`` times the cell after a feature start (its error is about the RANSAC threshold:
        a schedule as wide as the engine's default, 10 % of the bounding-box diagonal, lets the points outside the
        overlap drag the fit away), the engine's default schedule from ``init`` or the identity.
    distance_cells : tuple of float
        The default schedule after a feature start, in cells.
    ransac_cells : float
        RANSAC inlier distance of the lifted matches, in cells.
    normal_neighbours : int
        Neighbours of the PCA normals of a target scan.
    model : {'rigid', 'similarity'}
        Transform family (rigid for co-registered surveys; similarity also fits a unit mismatch).
    icp : ICPOptions
        The engine's dense loop (iterations, tolerance, robust kernel, degeneracy threshold; its distance schedule
        is replaced as ``max_distance`` says).
    """

    cell: float | None = None
    features: bool = True
    alpha: float = 0.001
    max_points: int = 200_000
    max_distance: tuple | None = None
    distance_cells: tuple = (8.0, 3.0, 1.5)
    ransac_cells: float = 3.0
    normal_neighbours: int = 16
    model: str = "rigid"
    icp: ICPOptions = ICPOptions()

    def __post_init__(self):
        if self.cell is not None:
            check_positive(self.cell, "cell")
        if not 0.0 <= float(self.alpha) <= 1.0:
            raise InputError(f"alpha must be in [0, 1]; got {self.alpha!r}")
        if int(self.max_points) < 100:
            raise InputError(f"max_points must be >= 100; got {self.max_points!r}")
        check_positive(self.ransac_cells, "ransac_cells")
        if self.model not in ("rigid", "similarity"):
            raise InputError(f"model={self.model!r} is not supported for terrain; use 'rigid' or 'similarity'")
        if not isinstance(self.icp, ICPOptions):
            raise InputError(f"icp must be an ICPOptions; got {type(self.icp).__name__}")


@dataclass(frozen=True)
class TerrainSurface:
    """One input prepared for registration, in the local frame.

    Attributes
    ----------
    points : (N, 3) float64 ndarray
        Points (scan points, or DEM cell centres) in the local frame.
    normals : (N, 3) float64 ndarray or None
        Unit normals (computed for the target only).
    grid : HeightGrid
        North-up height grid of square cells (the source of the hillshade image).
    kind : {'lidar', 'dem'}
    """

    points: np.ndarray
    normals: np.ndarray | None
    grid: HeightGrid
    kind: str


@dataclass(frozen=True)
class FeaturePairs:
    """Hillshade matches lifted to 3D.

    Attributes
    ----------
    source, target : (K, 3) float64 ndarray
        Matched points in the local frame.
    n_putative : int
        Image matches before the 2D verification.
    """

    source: np.ndarray
    target: np.ndarray
    n_putative: int


@dataclass(frozen=True)
class TerrainRegistration:
    """Result of :func:`register_terrain`.

    Attributes
    ----------
    transform : (4, 4) float64 ndarray
        Source to target in the files' coordinates and units (for geographic CRSs an affine map of longitude,
        latitude and height, the image of ``transform_local``).
    transform_local : (4, 4) float64 ndarray
        The fitted transform in the local frame (rigid for ``model='rigid'``).
    frame : LocalFrame
        The local frame (origin in file coordinates, scale, unit).
    registration : RegistrationResult
        The engine's result (fitness, inlier RMSE in the local unit, iterations, convergence of the dense term:
        ``registration.degenerate`` when the surfaces alone leave a direction free).
    n_matches : int
        Verified hillshade matches lifted to 3D (0 when features were not used or failed).
    n_feature_inliers : int
        Matches RANSAC kept.
    n_agreeing_matches : int
        Matches the final transform maps within the RANSAC distance of their partners.
    held_by_features : bool
        The surfaces alone are degenerate (gentle or planar terrain leaves the horizontal position weakly fixed),
        but the fit met the engine's tolerance and at least 3 hillshade matches, spread across the overlap (not on
        one line), agree with it: the matches, which fix a rigid motion on their own, hold the fit.
    start : {'ransac', 'init', 'identity'}
        Where the fit started.
    seconds : float
        Wall time of the registration (inputs already read).
    cell : float
        Cell of the hillshade images and unit of the default distance schedule, local unit.
    """

    transform: np.ndarray
    transform_local: np.ndarray
    frame: LocalFrame
    registration: RegistrationResult
    n_matches: int
    n_feature_inliers: int
    start: str
    seconds: float
    cell: float = float("nan")
    n_agreeing_matches: int = 0
    held_by_features: bool = False

    @property
    def converged(self) -> bool:
        """The engine converged, or its dense term alone is degenerate and the hillshade matches hold the fit
        (``held_by_features``)."""
        return bool(self.registration.converged or self.held_by_features)

    @property
    def rotation_deg(self) -> float:
        """Angle of the local rotation, degrees."""
        r = self.transform_local[:3, :3] / np.cbrt(np.linalg.det(self.transform_local[:3, :3]))
        return float(np.degrees(np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0))))

    @property
    def heading_deg(self) -> float:
        """Rotation about the vertical (counter-clockwise seen from above, x east towards y north), degrees."""
        return float(np.degrees(np.arctan2(self.transform_local[1, 0], self.transform_local[0, 0])))

    def to_dict(self) -> dict:
        """JSON-ready dict: the engine's fields (``transform`` in file coordinates; ``converged`` as
        :attr:`converged`, ``degenerate`` the dense term's) plus the frame, start and matches."""
        out = self.registration.to_dict()
        out.update(transform=self.transform.tolist(), transform_local=self.transform_local.tolist(),
                   local_origin=self.frame.origin.tolist(), local_scale=self.frame.scale.tolist(),
                   local_unit=self.frame.unit, rotation_deg=self.rotation_deg, heading_deg=self.heading_deg,
                   translation_local=self.transform_local[:3, 3].tolist(), n_matches=self.n_matches,
                   n_feature_inliers=self.n_feature_inliers, start=self.start, seconds=self.seconds,
                   cell=self.cell, converged=self.converged, n_agreeing_matches=self.n_agreeing_matches,
                   held_by_features=self.held_by_features)
        return out


def terrain_frame(source, target) -> LocalFrame:
    """The local frame of a registration: centred on the target, in its CRS's units (metres if geographic).

    Parameters
    ----------
    source, target : LidarScan or Dem

    Returns
    -------
    LocalFrame

    Raises
    ------
    InputError
        If the two CRSs differ (seismo3d does not reproject) or an input is of another type.
    """
    for name, item in (("source", source), ("target", target)):
        if not isinstance(item, (LidarScan, Dem)):
            raise InputError(f"{name} must be a LidarScan or a Dem (read_las / read_dem); got {type(item).__name__}")
    check_compatible(source.crs, target.crs)
    pts = target.points if isinstance(target, LidarScan) else target.points()
    return LocalFrame.about(pts, target.crs)


def _natural_cell(item, frame: LocalFrame) -> float:
    if isinstance(item, Dem):
        axes = np.diag(frame.scale[:2]) @ item.affine[:2, :2]
        return float(np.linalg.norm(axes, axis=0).max())
    return 1.5 * point_spacing(frame.to_local(item.points))


def terrain_surface(item, frame: LocalFrame, *, cell: float, with_normals: bool,
                    options: TerrainRegistrationOptions | None = None) -> TerrainSurface:
    """Prepare a scan or DEM for registration in ``frame``.

    Parameters
    ----------
    item : LidarScan or Dem
    frame : LocalFrame
    cell : float
        Side of the height grid's cells, local unit.
    with_normals : bool
        Compute normals (needed for the target of point-to-plane ICP).
    options : TerrainRegistrationOptions, optional

    Returns
    -------
    TerrainSurface
        For a DEM, cells next to nodata (no gradient) are left out.
    """
    opts = options or TerrainRegistrationOptions()
    if isinstance(item, Dem):
        return _dem_surface(item, frame, cell, with_normals, opts)
    points = frame.to_local(item.points)
    grid = rasterize_points(points, cell, statistic="max")
    if len(points) > opts.max_points:
        voxel = point_spacing(points) * np.sqrt(len(points) / opts.max_points)
        points = voxel_downsample(points, voxel)[0]
    normals = None
    if with_normals:
        normals = estimate_normals(points, k=opts.normal_neighbours, orient="none")
    return TerrainSurface(points, normals, grid, "lidar")


def _dem_surface(dem: Dem, frame: LocalFrame, cell: float, with_normals: bool,
                 opts: TerrainRegistrationOptions) -> TerrainSurface:
    axes = np.diag(frame.scale[:2]) @ dem.affine[:2, :2]  # local units per column step and per row step
    z_local = (dem.elevation - frame.origin[2]) * frame.scale[2]
    normals = grid_normals(z_local, axes)
    keep = np.isfinite(z_local) & np.isfinite(normals).all(axis=-1)
    stride = max(1, int(np.ceil(np.sqrt(keep.sum() / opts.max_points))))
    sub = np.zeros_like(keep)
    sub[::stride, ::stride] = True
    rows, cols = np.nonzero(keep & sub)
    x, y = dem.xy(rows, cols)
    points = frame.to_local(np.column_stack([x, y, dem.elevation[rows, cols]]))
    grid = _resample_dem(dem, frame, z_local, cell)
    return TerrainSurface(points, normals[rows, cols] if with_normals else None, grid, "dem")


def _resample_dem(dem: Dem, frame: LocalFrame, z_local, cell: float) -> HeightGrid:
    """The DEM on a north-up grid of square ``cell`` cells in the local frame (bilinear)."""
    corners = np.array([[0, 0], [0, dem.shape[1] - 1], [dem.shape[0] - 1, 0], [dem.shape[0] - 1, dem.shape[1] - 1]])
    cx, cy = dem.xy(corners[:, 0], corners[:, 1])
    local = frame.to_local(np.column_stack([cx, cy, np.zeros(4)]))
    lo, hi = local[:, :2].min(axis=0), local[:, :2].max(axis=0)
    n_cols = int(np.floor((hi[0] - lo[0]) / cell)) + 1
    n_rows = int(np.floor((hi[1] - lo[1]) / cell)) + 1
    x0, y0 = lo[0], lo[1] + (n_rows - 1) * cell
    gy, gx = np.mgrid[0:n_rows, 0:n_cols]
    file_xy = frame.to_file(np.column_stack([x0 + gx.ravel() * cell, y0 - gy.ravel() * cell, np.zeros(gx.size)]))
    r, c = dem.rowcol(file_xy[:, 0], file_xy[:, 1])
    valid = np.isfinite(z_local)
    z = ndimage.map_coordinates(fill_holes(z_local, valid), [r, c], order=1, mode="nearest").reshape(n_rows, n_cols)
    support = ndimage.map_coordinates(valid.astype(np.float64), [r, c], order=1, mode="constant", cval=0.0)
    observed = (support > 0.999).reshape(n_rows, n_cols)
    if observed.any():
        z = fill_holes(z, observed)
    return HeightGrid(z, observed, float(x0), float(y0), float(cell))


def match_hillshades(source: HeightGrid, target: HeightGrid, *, threshold_cells: float = 3.0) -> FeaturePairs:
    """Match the slope shading of two height grids (HOG-pyramid) and lift the verified matches to 3D.

    The image is the slope in degrees, ``arccos`` of the hillshade lit from the zenith: it does not change when the
    terrain turns about the vertical (a hillshade lit from one azimuth does), and both grids have square cells of
    the same size, so the image-to-image map is a 2D rotation and translation. On the Autzen scans the slope gave
    1.5-2 times more correct matches than ``cos(slope)`` itself, which flattens gentle slopes, and than the heights.
    Matches are verified with a similarity (RANSAC, ``threshold_cells``), then lifted through each grid's heights;
    matches on cells without data are dropped.

    Parameters
    ----------
    source, target : HeightGrid
        Grids with the same cell.
    threshold_cells : float
        Image verification threshold, in cells.

    Returns
    -------
    FeaturePairs
        Possibly empty.

    References
    ----------
    Vokhmintcev & Timchenko (method.md section 2), the HOG-pyramid matcher; Horn (1981) for the hillshade.
    """
    if abs(source.cell - target.cell) > 1e-9 * max(source.cell, target.cell):
        raise InputError(f"both grids need the same cell; got {source.cell} and {target.cell}")
    images = [slope_deg(g.elevation, (g.cell, g.cell)) for g in (source, target)]
    result = match_images(images[0], images[1], method="hog", verify="similarity", threshold=threshold_cells)
    empty = FeaturePairs(np.zeros((0, 3)), np.zeros((0, 3)), int(result.n_putative))
    if result.homography is None or result.n_inliers < 3:
        return empty
    xy1, xy2 = result.xy1[result.inliers], result.xy2[result.inliers]
    lifted = []
    for grid, xy in ((source, xy1), (target, xy2)):
        x, y = grid.xy(xy[:, 1], xy[:, 0])
        lifted.append(np.column_stack([x, y, sample_grid(grid, x, y)]))
    ok = np.isfinite(lifted[0][:, 2]) & np.isfinite(lifted[1][:, 2])
    return FeaturePairs(lifted[0][ok], lifted[1][ok], int(result.n_putative))


def register_terrain(source, target, *, init=None, options: TerrainRegistrationOptions | None = None,
                     **overrides) -> TerrainRegistration:
    """Register a terrain scan or DEM (source) onto another (target) with the fused ICP.

    Parameters
    ----------
    source, target : LidarScan or Dem
        Any pair: scan to scan, DEM to DEM, scan to DEM, DEM to scan. Both in one CRS (not reprojected).
    init : (4, 4) array_like, optional
        Initial source-to-target transform in the files' coordinates. It competes with the feature start (the one
        with more dense correspondences is used); without features it is the start.
    options : TerrainRegistrationOptions, optional
    **overrides
        Fields of :class:`TerrainRegistrationOptions` by name, replacing those of ``options``.

    Returns
    -------
    TerrainRegistration
        ``transform`` in the files' coordinates and units; ``converged`` counts a fit held by the hillshade matches
        where the surfaces alone are degenerate.

    Raises
    ------
    InputError
        Incompatible CRSs, bad inputs or options.
    RegistrationError
        Too few correspondences (e.g. the inputs do not overlap).

    Warns
    -----
    Seismo3dWarning
        When the hillshades gave too few matches and the fit starts from ``init`` or the identity.
    DegenerateGeometryWarning
        When the surfaces alone leave a direction weakly constrained (saying whether the hillshade matches hold it).

    References
    ----------
    Vokhmintcev & Timchenko (method.md), eq. 16 (fused ICP); Chen & Medioni (1991) point-to-plane ICP.
    """
    opts = resolve_options(TerrainRegistrationOptions, options, overrides, "register_terrain")
    t0 = time.perf_counter()
    frame = terrain_frame(source, target)
    cell = opts.cell or max(_natural_cell(source, frame), _natural_cell(target, frame))
    src = terrain_surface(source, frame, cell=cell, with_normals=False, options=opts)
    dst = terrain_surface(target, frame, cell=cell, with_normals=True, options=opts)
    local_init = None
    if init is not None:
        to_local = frame.matrix()
        local_init = to_local @ np.asarray(init, dtype=np.float64) @ np.linalg.inv(to_local)
    pairs = match_hillshades(src.grid, dst.grid, threshold_cells=opts.ransac_cells) if opts.features else None
    fit = _fit(src, dst, pairs, local_init, cell, opts)
    result = fit.result
    return TerrainRegistration(frame.transform_to_file(result.transform), result.transform, frame, result,
                               0 if pairs is None else len(pairs.source), fit.n_feature_inliers, fit.start,
                               time.perf_counter() - t0, float(cell), fit.n_agreeing, fit.held)


@dataclass(frozen=True)
class _Fit:
    """What :func:`_fit` returns: the engine's result, where it started, and how the hillshade matches agree."""

    result: RegistrationResult
    start: str
    n_feature_inliers: int
    n_agreeing: int
    held: bool


def _agreeing_matches(result: RegistrationResult, pairs: FeaturePairs, threshold: float) -> np.ndarray:
    """(K,) bool: the lifted matches that ``result.transform`` maps within ``threshold`` of their partners."""
    m = result.transform
    moved = pairs.source @ m[:3, :3].T + m[:3, 3]
    return np.linalg.norm(moved - pairs.target, axis=1) <= threshold


def _holds(result: RegistrationResult, pairs: FeaturePairs, agree: np.ndarray, spread: float, alpha: float) -> bool:
    """Whether the hillshade matches hold a fit whose dense term is degenerate: the engine met its tolerance, the
    feature term was in the objective, and >= 3 agreeing matches span the overlap in both horizontal directions
    (their minor standard deviation at least ``spread``), so they fix a rigid motion on their own."""
    if not (result.degenerate and result.info.get("tolerance_met", False) and alpha > 0 and agree.sum() >= 3):
        return False
    xy = pairs.target[agree, :2]
    minor = np.linalg.svd(xy - xy.mean(axis=0), compute_uv=False)[-1] / np.sqrt(len(xy))
    return bool(minor >= spread)


def _reissue(caught, held: bool, n_agreeing: int, alpha: float) -> None:
    """Pass on the engine's warnings; its degeneracy test looks at the dense term only, so when hillshade matches are
    in the objective say whether they hold the fit instead of advising to add features."""
    for w in caught:
        if issubclass(w.category, DegenerateGeometryWarning):
            detail = str(w.message).split("(")[1].split(")")[0]
            if held:
                msg = (f"the surfaces alone constrain the horizontal position weakly (gentle or planar terrain: "
                       f"{detail}); the {n_agreeing} hillshade matches in the fit (alpha={alpha:g}) hold it, and the "
                       "result reports degenerate=True for the surfaces")
            else:
                msg = (f"the surfaces alone constrain the horizontal position weakly (gentle or planar terrain: "
                       f"{detail}) and the hillshade matches do not hold the fit ({n_agreeing} agree with it): the "
                       "result is not unique along that direction")
            warnings.warn(msg, DegenerateGeometryWarning, stacklevel=4)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def _fit(src: TerrainSurface, dst: TerrainSurface, pairs, local_init, cell, opts) -> _Fit:
    """Fused ICP from the lifted matches, or ICP from init / identity when there are too few of them."""
    common = dict(target_normals=dst.normals, model=opts.model)
    schedule = opts.max_distance or opts.icp.max_distance
    if pairs is not None and len(pairs.source) >= 6:
        threshold = opts.ransac_cells * cell
        icp_options = dataclasses.replace(opts.icp, max_distance=schedule or tuple(c * cell for c in
                                                                                    opts.distance_cells))
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", DegenerateGeometryWarning)
                result = fused_icp(src.points, dst.points, source_features=pairs.source,
                                   target_features=pairs.target, alpha=opts.alpha, init=local_init,
                                   ransac_threshold=threshold, options=icp_options, **common)
            agree = _agreeing_matches(result, pairs, threshold)
            held = _holds(result, pairs, agree, threshold, opts.alpha)
            _reissue(caught, held, int(agree.sum()), opts.alpha)
            return _Fit(result, result.info.get("start", "ransac"), int(result.info.get("n_feature_inliers", 0)),
                        int(agree.sum()), held)
        except RegistrationError as exc:
            reason = str(exc)
    else:
        reason = f"{0 if pairs is None else len(pairs.source)} verified hillshade matches"
    if pairs is not None:
        warnings.warn(f"terrain registration: no feature start ({reason}); starting from "
                      f"{'the given init' if local_init is not None else 'the identity'}", Seismo3dWarning,
                      stacklevel=3)
    result = icp(src.points, dst.points, method="point_to_plane", init=local_init,
                 options=dataclasses.replace(opts.icp, max_distance=schedule), **common)
    return _Fit(result, "init" if local_init is not None else "identity", 0, 0, False)
