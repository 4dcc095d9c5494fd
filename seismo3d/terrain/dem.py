"""Digital elevation models from GeoTIFF files (tifffile): elevations, nodata, georeferencing and pixel sizes in
metres."""

from __future__ import annotations

import pathlib
from dataclasses import dataclass, field, replace

import numpy as np
import tifffile

from .._atomic import atomic_path
from ..errors import DataIntegrityError, DataNotFoundError, InputError
from .georef import (
    UNKNOWN_CRS,
    CoordinateReference,
    encode_geokeys,
    geokeys_for,
    metres_per_degree,
    parse_geokeys,
    reference_from_geokeys,
)

__all__ = ["Dem", "read_dem", "write_dem", "DEM_SUFFIXES"]

DEM_SUFFIXES = (".tif", ".tiff")

# TIFF tags of GeoTIFF and GDAL
_PIXEL_SCALE, _TIEPOINT, _TRANSFORMATION = 33550, 33922, 34264
_GEOKEYS, _GEODOUBLES, _GEOASCII, _GDAL_NODATA = 34735, 34736, 34737, 42113
_RASTER_TYPE_KEY, _PIXEL_IS_POINT = 1025, 2


@dataclass(frozen=True)
class Dem:
    """A raster of elevations with its georeferencing.

    Pixel ``(row, col)`` has its centre at ``(x, y) = affine @ (col, row, 1)`` in the CRS (rows usually run south,
    columns east).

    Attributes
    ----------
    elevation : (H, W) float64 ndarray
        Heights in ``crs.vertical_unit``; NaN where the file has nodata.
    affine : (3, 3) float64 ndarray
        Pixel-centre indices ``(col, row, 1)`` to CRS coordinates ``(x, y, 1)``.
    crs : CoordinateReference
    nodata : float or None
        The file's nodata value (already turned into NaN in ``elevation``).
    path : pathlib.Path or None
    """

    elevation: np.ndarray
    affine: np.ndarray
    crs: CoordinateReference = UNKNOWN_CRS
    nodata: float | None = None
    path: pathlib.Path | None = field(default=None, compare=False)

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols)."""
        return tuple(self.elevation.shape)

    @property
    def valid(self) -> np.ndarray:
        """(H, W) bool: cells with an elevation."""
        return np.isfinite(self.elevation)

    @property
    def pixel_size(self) -> tuple[float, float]:
        """(row step, column step): length of one pixel along the rows and the columns, in CRS units."""
        return float(np.hypot(*self.affine[:2, 1])), float(np.hypot(*self.affine[:2, 0]))

    @property
    def centre_xy(self) -> tuple[float, float]:
        """CRS coordinates of the raster's centre."""
        h, w = self.shape
        x, y = self.xy((h - 1) / 2.0, (w - 1) / 2.0)
        return float(x), float(y)

    @property
    def metric_axes(self) -> np.ndarray:
        """(2, 2) float64: metres east (row 0) and north (row 1) of one column step (column 0) and one row step
        (column 1), at the raster's centre.

        Projected CRSs: the affine's linear part times the unit's length. Geographic CRSs: degrees times the WGS 84
        lengths of a degree of longitude and latitude at the centre latitude
        (:func:`~seismo3d.terrain.georef.metres_per_degree`; across a 0.3-degree raster at 33 degrees north the width
        of a pixel varies by 0.3 %).
        """
        if self.crs.is_geographic:
            m_lat, m_lon = metres_per_degree(self.centre_xy[1])
            return np.diag([m_lon, m_lat]) @ self.affine[:2, :2]
        return self.affine[:2, :2] * self.crs.unit_to_metre

    @property
    def pixel_size_m(self) -> tuple[float, float]:
        """(dy, dx): pixel height (one row step) and width (one column step) in metres at the raster's centre."""
        axes = self.metric_axes
        return float(np.hypot(*axes[:, 1])), float(np.hypot(*axes[:, 0]))

    @property
    def elevation_m(self) -> np.ndarray:
        """(H, W) float64: elevations in metres (NaN at nodata)."""
        return self.elevation * self.crs.vertical_to_metre

    def xy(self, rows, cols):
        """CRS coordinates of (fractional) pixel centres.

        Parameters
        ----------
        rows, cols : array_like
            Pixel indices (broadcast together).

        Returns
        -------
        x, y : float64 ndarrays
        """
        r = np.asarray(rows, dtype=np.float64)
        c = np.asarray(cols, dtype=np.float64)
        a = self.affine
        return a[0, 0] * c + a[0, 1] * r + a[0, 2], a[1, 0] * c + a[1, 1] * r + a[1, 2]

    def rowcol(self, x, y):
        """Fractional pixel indices of CRS coordinates (the inverse of :meth:`xy`).

        Returns
        -------
        rows, cols : float64 ndarrays
        """
        inv = np.linalg.inv(self.affine)
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        return inv[1, 0] * x + inv[1, 1] * y + inv[1, 2], inv[0, 0] * x + inv[0, 1] * y + inv[0, 2]

    def points(self) -> np.ndarray:
        """(N, 3) float64: x, y, z of every valid cell centre, in file coordinates (row-major order)."""
        rows, cols = np.nonzero(self.valid)
        x, y = self.xy(rows, cols)
        return np.column_stack([x, y, self.elevation[rows, cols]])

    def crop(self, rows: slice, cols: slice) -> "Dem":
        """The DEM restricted to ``elevation[rows, cols]`` (unit-step slices), georeferenced accordingly."""
        r0 = rows.start or 0
        c0 = cols.start or 0
        shift = np.array([[1.0, 0.0, c0], [0.0, 1.0, r0], [0.0, 0.0, 1.0]])
        return replace(self, elevation=np.ascontiguousarray(self.elevation[rows, cols]), affine=self.affine @ shift)


def read_dem(path) -> Dem:
    """Read a single-band GeoTIFF DEM.

    The georeferencing comes from ModelTransformationTag, or ModelTiepointTag with ModelPixelScaleTag; the raster
    type key says whether the tie point refers to a pixel's corner (PixelIsArea, the default) or its centre
    (PixelIsPoint). Nodata cells (GDAL_NODATA tag, and NaN in float rasters) become NaN. A multi-band file gives
    its first band.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.tif`` / ``.tiff`` file.

    Returns
    -------
    Dem

    Raises
    ------
    DataNotFoundError
        If the file does not exist.
    DataIntegrityError
        If tifffile cannot read it.
    InputError
        If it has no georeferencing tags, a non-numeric or 1-pixel raster, or only nodata.

    References
    ----------
    OGC 19-008r4 (2019), OGC GeoTIFF Standard 1.1, sections 7.2-7.4 (raster to model transformation).
    """
    path = pathlib.Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"{path}: no such file; check the path")
    try:
        with tifffile.TiffFile(path) as tif:
            page = tif.pages[0]
            tags = {tag.code: tag.value for tag in page.tags.values()}
            data = page.asarray()
    except (tifffile.TiffFileError, OSError, ValueError) as exc:
        raise DataIntegrityError(f"{path.name} is not a readable TIFF ({exc}); check that it is complete") from exc
    band = _first_band(data, page_samples=tags.get(277, 1), name=path.name)
    keys = {}
    if _GEOKEYS in tags:
        keys = parse_geokeys(tags[_GEOKEYS], tags.get(_GEODOUBLES, ()), _ascii(tags.get(_GEOASCII, "")))
    crs = reference_from_geokeys(keys) if keys else UNKNOWN_CRS
    affine = _affine(tags, keys.get(_RASTER_TYPE_KEY) == _PIXEL_IS_POINT, path.name)
    nodata = _nodata(tags.get(_GDAL_NODATA))
    elevation = band.astype(np.float64)
    if nodata is not None:
        elevation[band == nodata] = np.nan
    if not np.isfinite(elevation).any():
        raise InputError(f"{path.name} holds only nodata ({'NaN' if nodata is None else repr(nodata)} everywhere); "
                         "give a DEM with elevations")
    return Dem(elevation, affine, crs, nodata, path)


def _ascii(value) -> str:
    return value.decode("ascii", "replace") if isinstance(value, bytes) else str(value)


def _first_band(data, *, page_samples: int, name: str) -> np.ndarray:
    if data.dtype.kind not in "iuf":
        raise InputError(f"{name} holds {data.dtype} pixels; a DEM needs numbers")
    if data.ndim == 3:
        data = data[..., 0] if data.shape[-1] == page_samples else data[0]
    if data.ndim != 2 or min(data.shape) < 2:
        raise InputError(f"{name} is a {data.shape} raster; a DEM needs at least 2 x 2 pixels in one band")
    return data


def _affine(tags: dict, pixel_is_point: bool, name: str) -> np.ndarray:
    half = 0.0 if pixel_is_point else 0.5  # raster-space coordinate of a pixel's centre is (col + 0.5, row + 0.5)
    if _TRANSFORMATION in tags:
        m = np.asarray(tags[_TRANSFORMATION], dtype=np.float64).reshape(4, 4)
        a = np.array([[m[0, 0], m[0, 1], m[0, 3]], [m[1, 0], m[1, 1], m[1, 3]], [0.0, 0.0, 1.0]])
    elif _TIEPOINT in tags and _PIXEL_SCALE in tags:
        i, j, _, x, y, _ = np.asarray(tags[_TIEPOINT], dtype=np.float64)[:6]
        sx, sy = np.asarray(tags[_PIXEL_SCALE], dtype=np.float64)[:2]
        a = np.array([[sx, 0.0, x - i * sx], [0.0, -sy, y + j * sy], [0.0, 0.0, 1.0]])
    else:
        raise InputError(f"{name} has no georeferencing (ModelPixelScale + ModelTiepoint or ModelTransformation "
                         "tags); it is a plain image, not a GeoTIFF DEM")
    shift = np.array([[1.0, 0.0, half], [0.0, 1.0, half], [0.0, 0.0, 1.0]])
    a = a @ shift
    if abs(np.linalg.det(a[:2, :2])) < 1e-300:
        raise InputError(f"{name} has a zero pixel size in its georeferencing tags")
    return a


def _nodata(value):
    if value is None:
        return None
    try:
        return float(_ascii(value).strip().rstrip("\x00"))
    except ValueError:
        return None


def write_dem(path, dem: Dem, *, nodata: float = -9999.0) -> pathlib.Path:
    """Write a DEM as a float32 GeoTIFF (tie point + pixel scale, or a transformation matrix when rotated), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Destination ending in ``.tif`` / ``.tiff``.
    dem : Dem
        NaN cells are written as ``nodata``.
    nodata : float
        Nodata value stored in the GDAL_NODATA tag.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        On a bad suffix.
    """
    path = pathlib.Path(path)
    if path.suffix.lower() not in DEM_SUFFIXES:
        raise InputError(f"{path.name}: a GeoTIFF DEM must end in .tif or .tiff")
    a = np.asarray(dem.affine, dtype=np.float64) @ np.array([[1, 0, -0.5], [0, 1, -0.5], [0, 0, 1.0]])  # corner
    tags = []
    if abs(a[0, 1]) < 1e-15 and abs(a[1, 0]) < 1e-15 and a[0, 0] > 0 and a[1, 1] < 0:
        tags.append((_PIXEL_SCALE, "d", 3, (a[0, 0], -a[1, 1], 0.0), True))
        tags.append((_TIEPOINT, "d", 6, (0.0, 0.0, 0.0, a[0, 2], a[1, 2], 0.0), True))
    else:
        m = np.eye(4)
        m[0, 0], m[0, 1], m[0, 3] = a[0, 0], a[0, 1], a[0, 2]
        m[1, 0], m[1, 1], m[1, 3] = a[1, 0], a[1, 1], a[1, 2]
        tags.append((_TRANSFORMATION, "d", 16, tuple(m.ravel()), True))
    directory, doubles, ascii_params = encode_geokeys(geokeys_for(dem.crs))
    if len(directory) > 4:
        tags.append((_GEOKEYS, "H", len(directory), tuple(directory), True))
        if doubles:
            tags.append((_GEODOUBLES, "d", len(doubles), tuple(doubles), True))
        if ascii_params:
            tags.append((_GEOASCII, "s", 0, ascii_params, True))
    tags.append((_GDAL_NODATA, "s", 0, repr(float(nodata)), True))
    data = np.where(np.isfinite(dem.elevation), dem.elevation, nodata).astype(np.float32)
    with atomic_path(path) as tmp:
        tifffile.imwrite(tmp, data, extratags=tags, photometric="minisblack")
    return path
