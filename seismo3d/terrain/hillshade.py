"""Terrain derivatives of an elevation grid: gradient, slope, aspect, hillshade from one or several light azimuths.

Grids are arrays of heights in metres with a metric spacing: either ``(dy, dx)`` for a north-up raster (rows run
south, columns east) or the (2, 2) matrix :attr:`~seismo3d.terrain.Dem.metric_axes` (metres east and north of one
column step and one row step) for any raster orientation. Derivatives are central differences (one-sided at the
edges); a cell next to nodata (NaN) gets NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_positive
from ..errors import InputError

__all__ = ["TerrainGradient", "terrain_gradient", "slope_deg", "aspect_deg", "hillshade", "hillshades",
           "multidirectional_hillshade", "as_metric_axes"]


@dataclass(frozen=True)
class TerrainGradient:
    """The elevation gradient of a grid in map directions.

    Attributes
    ----------
    east, north : (H, W) float64 ndarray
        dz/dx and dz/dy, metres per metre (x east, y north); NaN at and next to nodata.
    """

    east: np.ndarray
    north: np.ndarray

    @property
    def magnitude(self) -> np.ndarray:
        """(H, W) |grad z|, metres per metre."""
        return np.hypot(self.east, self.north)


def as_metric_axes(spacing) -> np.ndarray:
    """``(dy, dx)`` of a north-up grid, or a (2, 2) axes matrix, as the (2, 2) axes matrix (see the module docstring).

    Raises
    ------
    InputError
        If the spacing is not two positive numbers or a non-singular (2, 2) matrix.
    """
    a = np.asarray(spacing, dtype=np.float64)
    if a.shape == (2,):
        dy = check_positive(a[0], "spacing dy")
        dx = check_positive(a[1], "spacing dx")
        return np.array([[dx, 0.0], [0.0, -dy]])
    if a.shape != (2, 2) or not np.all(np.isfinite(a)) or abs(np.linalg.det(a)) < 1e-300:
        raise InputError(f"spacing must be (dy, dx) in metres or a non-singular (2, 2) axes matrix; got {spacing!r}")
    return a


def _as_grid(elevation) -> np.ndarray:
    z = np.asarray(elevation, dtype=np.float64)
    if z.ndim != 2 or min(z.shape) < 2:
        raise InputError(f"elevation must be a 2D grid of at least 2 x 2 cells; got shape {z.shape}")
    return z


def terrain_gradient(elevation, spacing) -> TerrainGradient:
    """Gradient of an elevation grid by central differences, in map directions.

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights in metres (NaN = nodata).
    spacing : (dy, dx) or (2, 2) array_like
        Grid spacing in metres (see the module docstring).

    Returns
    -------
    TerrainGradient

    Raises
    ------
    InputError
        Bad grid or spacing.

    References
    ----------
    Horn, B. K. P. (1981). Hill shading and the reflectance map. Proc. IEEE 69(1), 14-47 (central differences as the
    simplest of the slope estimators compared there).
    """
    z = _as_grid(elevation)
    axes = as_metric_axes(spacing)
    dz_drow, dz_dcol = np.gradient(z)
    # [dz/dcol, dz/drow] = axes^T [dz/dx, dz/dy]  ->  solve for the map gradient
    inv_t = np.linalg.inv(axes.T)
    east = inv_t[0, 0] * dz_dcol + inv_t[0, 1] * dz_drow
    north = inv_t[1, 0] * dz_dcol + inv_t[1, 1] * dz_drow
    return TerrainGradient(east, north)


def slope_deg(elevation, spacing) -> np.ndarray:
    """Slope angle ``arctan |grad z|`` in degrees.

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights in metres.
    spacing : (dy, dx) or (2, 2) array_like
        Grid spacing in metres.

    Returns
    -------
    (H, W) float64 ndarray
        Degrees in [0, 90); NaN at and next to nodata.
    """
    return np.degrees(np.arctan(terrain_gradient(elevation, spacing).magnitude))


def aspect_deg(elevation, spacing) -> np.ndarray:
    """Aspect: the compass azimuth the slope faces (downhill direction), degrees clockwise from north in [0, 360).

    Flat cells (zero gradient) get 0. Parameters as :func:`slope_deg`.
    """
    g = terrain_gradient(elevation, spacing)
    return _aspect(g)


def _aspect(g: TerrainGradient) -> np.ndarray:
    return np.mod(np.degrees(np.arctan2(-g.east, -g.north)), 360.0)


def hillshade(elevation, spacing, *, azimuth_deg: float = 315.0, altitude_deg: float = 45.0,
              z_factor: float = 1.0) -> np.ndarray:
    """Lambertian hillshade: the cosine of the angle between the surface normal and the direction of the light.

    ``cos(zenith) cos(slope) + sin(zenith) sin(slope) cos(azimuth - aspect)``, clipped at 0 (cells facing away from
    the light are black). ``altitude_deg=90`` lights from the zenith: ``cos(slope)``, which does not change when the
    terrain is rotated about the vertical (the shading :mod:`~seismo3d.terrain.registration` matches).

    Parameters
    ----------
    elevation : (H, W) array_like
        Heights in metres.
    spacing : (dy, dx) or (2, 2) array_like
        Grid spacing in metres.
    azimuth_deg : float
        Compass direction the light comes from, degrees clockwise from north (315 = north-west, the cartographic
        default).
    altitude_deg : float
        Elevation of the light above the horizon, degrees in (0, 90].
    z_factor : float
        Vertical exaggeration applied to the heights.

    Returns
    -------
    (H, W) float64 ndarray
        In [0, 1]; NaN at and next to nodata.

    Raises
    ------
    InputError
        Bad grid, spacing, altitude or z_factor.

    References
    ----------
    Burrough, P. A., McDonnell, R. A. (1998). Principles of Geographical Information Systems, Oxford, pp. 190-192.
    Horn, B. K. P. (1981). Hill shading and the reflectance map. Proc. IEEE 69(1), 14-47. doi:10.1109/PROC.1981.11918
    """
    if not 0.0 < float(altitude_deg) <= 90.0:
        raise InputError(f"altitude_deg must be in (0, 90]; got {altitude_deg!r}")
    check_positive(z_factor, "z_factor")
    g = terrain_gradient(np.asarray(elevation, dtype=np.float64) * float(z_factor), spacing)
    return _shade(g, [float(azimuth_deg)], float(altitude_deg))[0]


def _shade(g: TerrainGradient, azimuths, altitude_deg):
    slope = np.arctan(g.magnitude)
    aspect = np.radians(_aspect(g))
    zen = np.radians(90.0 - altitude_deg)
    flat = np.cos(zen) * np.cos(slope)
    tilt = np.sin(zen) * np.sin(slope)
    out = [np.clip(flat + tilt * np.cos(np.radians(az) - aspect), 0.0, 1.0) for az in azimuths]
    return np.stack(out) if out else np.zeros((0,) + slope.shape)


def hillshades(elevation, spacing, *, azimuths=(0.0, 45.0, 90.0, 135.0), altitude_deg: float = 45.0) -> np.ndarray:
    """Hillshades of one grid from several light azimuths (the multi-directional set of lineament mapping).

    A linear feature shows best in the hillshade lit perpendicular to it, so a set of azimuths over 180 degrees
    shows features of every strike.

    Parameters
    ----------
    elevation : (H, W) array_like
    spacing : (dy, dx) or (2, 2) array_like
    azimuths : sequence of float
        Light azimuths, degrees clockwise from north.
    altitude_deg : float

    Returns
    -------
    (len(azimuths), H, W) float64 ndarray

    References
    ----------
    Smith, M. J., Clark, C. D. (2005). Methods for the visualization of digital elevation models for landform
    mapping. Earth Surf. Process. Landforms 30, 885-900. doi:10.1002/esp.1210
    """
    if not 0.0 < float(altitude_deg) <= 90.0:
        raise InputError(f"altitude_deg must be in (0, 90]; got {altitude_deg!r}")
    g = terrain_gradient(elevation, spacing)
    return _shade(g, [float(a) for a in azimuths], float(altitude_deg))


def multidirectional_hillshade(elevation, spacing, *, azimuths=(225.0, 270.0, 315.0, 360.0),
                               altitude_deg: float = 45.0) -> np.ndarray:
    """Multidirectional oblique-weighted hillshade: the hillshades of several azimuths, each cell weighting them by
    ``cos^2(aspect - azimuth)`` (the light most across the local slope counts most).

    With the default azimuths this is Mark's (1992) MDOW combination as GDAL computes it (``gdaldem hillshade
    -multidirectional``); flat cells weight all azimuths equally.

    Parameters
    ----------
    elevation : (H, W) array_like
    spacing : (dy, dx) or (2, 2) array_like
    azimuths : sequence of float
    altitude_deg : float

    Returns
    -------
    (H, W) float64 ndarray
        In [0, 1]; NaN at and next to nodata.

    References
    ----------
    Mark, R. K. (1992). Multidirectional, oblique-weighted, shaded-relief image of the Island of Hawaii. USGS
    Open-File Report 92-422.
    """
    if not 0.0 < float(altitude_deg) <= 90.0:
        raise InputError(f"altitude_deg must be in (0, 90]; got {altitude_deg!r}")
    azimuths = [float(a) for a in azimuths]
    if not azimuths:
        raise InputError("azimuths must hold at least one light direction")
    g = terrain_gradient(elevation, spacing)
    shades = _shade(g, azimuths, float(altitude_deg))
    aspect = np.radians(_aspect(g))
    weights = np.stack([np.cos(aspect - np.radians(a)) ** 2 for a in azimuths])
    total = weights.sum(axis=0)
    flat = ~(total > 1e-12)
    weights[:, flat] = 1.0
    total[flat] = len(azimuths)
    return (weights * shades).sum(axis=0) / total
