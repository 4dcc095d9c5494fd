"""Coordinate reference systems of LAS/LAZ and GeoTIFF files (GeoKeys), and the local metric frame fits run in.

LAS 1.0-1.3 and GeoTIFF describe their CRS with the same GeoTIFF GeoKey directory (a table of ``(key, location,
count, value)`` shorts with double and ASCII parameter blocks, decoded here); LAS 1.4 may use OGC WKT instead, read by
pyproj (PROJ), which also gives the units of a CRS the keys name only by its EPSG code. What seismo3d keeps: whether
the CRS is projected or geographic, its EPSG code, the linear and vertical units and their size in metres. Two files
are compatible when their horizontal CRS agree; seismo3d does not reproject.

Fits never see the files' large coordinates (e.g. 849,000 ft of northing): :class:`LocalFrame` recentres them (and for
geographic CRSs turns degrees into metres east and north on a local tangent plane), and maps transforms back.

References
----------
Ritter, N., Ruth, M. (2000). GeoTIFF Format Specification, revision 1.8.2 (key IDs and unit codes);
OGC 19-008r4 (2019), OGC GeoTIFF Standard 1.1. ASPRS (2019). LAS Specification 1.4 R15, section 2.5.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["CoordinateReference", "LocalFrame", "parse_geokeys", "reference_from_geokeys", "encode_geokeys",
           "geokeys_for", "parse_wkt", "metres_per_degree",
           "check_compatible", "UNKNOWN_CRS"]

# GeoKey IDs (GeoTIFF 1.8.2, section 6.2)
_MODEL_TYPE, _RASTER_TYPE, _CITATION = 1024, 1025, 1026
_GEOGRAPHIC_TYPE, _GEOG_CITATION, _GEOG_LINEAR_UNITS, _GEOG_ANGULAR_UNITS = 2048, 2049, 2052, 2054
_PROJECTED_TYPE, _PCS_CITATION, _PROJ_LINEAR_UNITS = 3072, 3073, 3076
_VERTICAL_TYPE, _VERTICAL_UNITS = 4096, 4099

# EPSG unit-of-measure codes -> (name, metres)
_LINEAR_UNITS = {
    9001: ("metre", 1.0),
    9002: ("foot", 0.3048),
    9003: ("US survey foot", 1200.0 / 3937.0),
    9036: ("kilometre", 1000.0),
}
_USER_DEFINED = 32767

# WGS 84 ellipsoid (EPSG:7030): semi-major axis (m) and first eccentricity squared
_WGS84_A = 6378137.0
_WGS84_E2 = 6.69437999014e-3


@dataclass(frozen=True)
class CoordinateReference:
    """What seismo3d knows of a file's coordinate reference system.

    Attributes
    ----------
    kind : {'projected', 'geographic', 'unknown'}
        Projected (x, y in a linear unit), geographic (longitude, latitude in degrees) or not stated by the file.
    epsg : int or None
        EPSG code of the projected or geographic CRS when the file gives one (None for user-defined CRSs).
    name : str
        The file's citation of the CRS (may be empty).
    linear_unit : str
        Unit of x and y: ``'metre'``, ``'foot'``, ``'US survey foot'``..., ``'degree'`` for geographic CRSs,
        ``'unknown'``.
    unit_to_metre : float
        Size of one x/y unit in metres (1.0 for geographic and unknown CRSs, whose x/y are converted separately).
    vertical_unit : str
        Unit of z (the vertical units key when present, else the linear unit; metres for geographic CRSs).
    vertical_to_metre : float
        Size of one z unit in metres.
    geokeys : dict
        The raw GeoKey directory ``{key_id: value}`` (for writing the CRS back unchanged); empty when unknown.
    """

    kind: str = "unknown"
    epsg: int | None = None
    name: str = ""
    linear_unit: str = "unknown"
    unit_to_metre: float = 1.0
    vertical_unit: str = "unknown"
    vertical_to_metre: float = 1.0
    geokeys: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def is_geographic(self) -> bool:
        """True for longitude / latitude coordinates in degrees."""
        return self.kind == "geographic"

    def describe(self) -> str:
        """One line for messages and reports, e.g. ``'projected CRS (EPSG:2992), x/y in foot'``."""
        code = f"EPSG:{self.epsg}" if self.epsg else (self.name or "user-defined")
        if self.kind == "unknown":
            return "no CRS stated (units unknown, taken as metres)"
        return f"{self.kind} CRS ({code}), x/y in {self.linear_unit}, z in {self.vertical_unit}"

    def to_dict(self) -> dict:
        """JSON-ready summary (without the raw keys)."""
        return {"kind": self.kind, "epsg": self.epsg, "name": self.name, "linear_unit": self.linear_unit,
                "unit_to_metre": self.unit_to_metre, "vertical_unit": self.vertical_unit,
                "vertical_to_metre": self.vertical_to_metre}


UNKNOWN_CRS = CoordinateReference()


def parse_geokeys(directory, doubles=(), ascii_params: str = "") -> dict:
    """Decode a GeoKey directory into ``{key_id: value}``.

    Parameters
    ----------
    directory : sequence of int
        The GeoKeyDirectory shorts: header ``(version, revision, minor, n_keys)`` then ``n_keys`` rows of
        ``(key_id, tag_location, count, value_offset)``.
    doubles : sequence of float
        The GeoDoubleParams block (tag 34736).
    ascii_params : str
        The GeoAsciiParams block (tag 34737); values end with ``'|'``.

    Returns
    -------
    dict
        Key IDs to an int (location 0), a float or tuple of floats (34736) or a str (34737).

    Raises
    ------
    InputError
        If the directory is shorter than its header says.
    """
    d = [int(v) for v in directory]
    if len(d) < 4:
        raise InputError(f"the GeoKey directory has {len(d)} values; it needs a 4-value header")
    n = d[3]
    if len(d) < 4 + 4 * n:
        raise InputError(f"the GeoKey directory declares {n} keys but holds {(len(d) - 4) // 4}; the file is corrupt")
    doubles = [float(v) for v in doubles]
    keys = {}
    for k in range(n):
        key, loc, count, value = d[4 + 4 * k: 8 + 4 * k]
        if key == 0:
            continue
        if loc == 0:
            keys[key] = value
        elif loc == 34736:
            vals = tuple(doubles[value: value + count])
            keys[key] = vals[0] if count == 1 and vals else vals
        elif loc == 34737:
            keys[key] = ascii_params[value: value + count].rstrip("|\x00")
    return keys


def reference_from_geokeys(keys: dict) -> CoordinateReference:
    """Build a :class:`CoordinateReference` from decoded GeoKeys (see :func:`parse_geokeys`).

    Parameters
    ----------
    keys : dict
        ``{key_id: value}``.

    Returns
    -------
    CoordinateReference
        ``kind='unknown'`` when the keys state neither a projected nor a geographic model.
    """
    model = keys.get(_MODEL_TYPE)
    if model == 2 or (model is None and _GEOGRAPHIC_TYPE in keys and _PROJECTED_TYPE not in keys):
        epsg = keys.get(_GEOGRAPHIC_TYPE)
        name = str(keys.get(_GEOG_CITATION, "") or keys.get(_CITATION, ""))
        vunit, vm = _unit(keys.get(_VERTICAL_UNITS), ("metre", 1.0))
        return CoordinateReference("geographic", _code(epsg), name, "degree", 1.0, vunit, vm, dict(keys))
    if model == 1 or _PROJECTED_TYPE in keys:
        epsg = keys.get(_PROJECTED_TYPE)
        name = str(keys.get(_PCS_CITATION, "") or keys.get(_CITATION, ""))
        unit, um = _unit(keys.get(_PROJ_LINEAR_UNITS), _epsg_unit(_code(epsg)))
        vunit, vm = _unit(keys.get(_VERTICAL_UNITS), (unit, um))
        return CoordinateReference("projected", _code(epsg), name, unit, um, vunit, vm, dict(keys))
    return CoordinateReference(geokeys=dict(keys))


def _code(value):
    return None if value in (None, 0, _USER_DEFINED) else int(value)


def _epsg_unit(epsg) -> tuple:
    """(name, metres) of the linear unit of the projected CRS ``epsg`` in PROJ's database; metres when unknown."""
    if epsg is None:
        return "metre", 1.0
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    try:
        axis = CRS.from_epsg(int(epsg)).axis_info
    except CRSError:
        return "metre", 1.0
    return (axis[0].unit_name, float(axis[0].unit_conversion_factor)) if axis else ("metre", 1.0)


def _unit(code, default):
    if code is None or code == _USER_DEFINED:
        return default
    return _LINEAR_UNITS.get(int(code), default)


def parse_wkt(wkt: str) -> CoordinateReference:
    """Build a :class:`CoordinateReference` from an OGC WKT string (WKT1 or WKT2), read by ``pyproj.CRS.from_wkt``.

    A projected CRS gives its axes' unit as the linear unit, a geographic one degrees; a compound CRS its horizontal
    part, with its vertical part's unit as the vertical unit. The EPSG code is the CRS's own (PROJ's identification
    at full confidence: a user-defined CRS has none).

    Parameters
    ----------
    wkt : str

    Returns
    -------
    CoordinateReference
        ``kind='unknown'`` for a WKT that is neither projected nor geographic (an engineering ``LOCAL_CS``) or that
        PROJ cannot read.

    References
    ----------
    OGC 18-010r7 (2019), Well-known text representation of coordinate reference systems; pyproj, ``pyproj.CRS``.
    """
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    try:
        crs = CRS.from_wkt(wkt.strip().rstrip("\x00"))
    except CRSError:
        return UNKNOWN_CRS
    vertical = None
    if crs.is_compound:
        vertical = next((c for c in crs.sub_crs_list if c.is_vertical), None)
        crs = next((c for c in crs.sub_crs_list if c.is_projected or c.is_geographic), crs)
    if not (crs.is_projected or crs.is_geographic):
        return UNKNOWN_CRS
    epsg = crs.to_epsg(min_confidence=100)
    if crs.is_geographic:
        vunit, vm = _axis_unit(vertical, ("metre", 1.0))
        return CoordinateReference("geographic", epsg, crs.name, "degree", 1.0, vunit, vm)
    unit, um = _axis_unit(crs, ("metre", 1.0))
    vunit, vm = _axis_unit(vertical, (unit, um))
    return CoordinateReference("projected", epsg, crs.name, unit, um, vunit, vm)


def _axis_unit(crs, default) -> tuple:
    """(name, metres) of the first axis of a pyproj CRS, ``default`` without one."""
    axis = crs.axis_info if crs is not None else []
    return (axis[0].unit_name, float(axis[0].unit_conversion_factor)) if axis else default


def metres_per_degree(latitude_deg: float) -> tuple[float, float]:
    """Length of one degree of latitude and of longitude on the WGS 84 ellipsoid at a latitude.

    Parameters
    ----------
    latitude_deg : float
        Geodetic latitude in degrees.

    Returns
    -------
    (metres_per_degree_latitude, metres_per_degree_longitude) : tuple of float
        ``M pi / 180`` and ``N cos(lat) pi / 180`` with M, N the meridional and prime-vertical radii of curvature.

    References
    ----------
    Torge, W., Mueller, J. (2012). Geodesy, 4th ed., De Gruyter, eqs. 4.15 and 4.16.
    """
    phi = np.radians(float(latitude_deg))
    w = np.sqrt(1.0 - _WGS84_E2 * np.sin(phi) ** 2)
    m = _WGS84_A * (1.0 - _WGS84_E2) / w**3
    n = _WGS84_A / w
    return float(m * np.pi / 180.0), float(n * np.cos(phi) * np.pi / 180.0)


@dataclass(frozen=True)
class LocalFrame:
    """The working frame of a fit: file coordinates recentred on ``origin`` and scaled to ``scale`` per axis.

    ``local = (file - origin) * scale``. For projected CRSs ``scale`` is ones (the fit runs in the files' own units,
    only recentred; z is converted into the x/y unit when the file states another vertical unit); for geographic CRSs it is (metres per degree of longitude, of latitude, 1) at the origin's
    latitude, so x is metres east, y metres north (a local equirectangular projection; its length error grows as
    ``tan(lat) * dlat`` away from the origin, 0.2 % at 15 km from it at 33 degrees north).

    Attributes
    ----------
    origin : (3,) float64 ndarray
        File coordinates of the local origin (x, y, z).
    scale : (3,) float64 ndarray
        Local units per file unit, per axis.
    unit : str
        The local frame's unit (the files' linear unit, or ``'metre'`` for geographic files).
    """

    origin: np.ndarray
    scale: np.ndarray
    unit: str

    @classmethod
    def about(cls, points, crs: CoordinateReference) -> "LocalFrame":
        """The frame centred on the bounding-box centre of ``points`` ((N, 3) file coordinates) for ``crs``."""
        pts = np.asarray(points, dtype=np.float64)
        origin = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        if crs.is_geographic:
            m_lat, m_lon = metres_per_degree(origin[1])
            return cls(origin, np.array([m_lon, m_lat, crs.vertical_to_metre]), "metre")
        return cls(origin, np.array([1.0, 1.0, crs.vertical_to_metre / crs.unit_to_metre]), crs.linear_unit)

    def to_local(self, points) -> np.ndarray:
        """(N, 3) file coordinates -> (N, 3) local coordinates."""
        return (np.asarray(points, dtype=np.float64) - self.origin) * self.scale

    def to_file(self, points) -> np.ndarray:
        """(N, 3) local coordinates -> (N, 3) file coordinates."""
        return np.asarray(points, dtype=np.float64) / self.scale + self.origin

    def matrix(self) -> np.ndarray:
        """(4, 4) homogeneous map from file to local coordinates."""
        m = np.diag(np.r_[self.scale, 1.0])
        m[:3, 3] = -self.origin * self.scale
        return m

    def transform_to_file(self, local_transform) -> np.ndarray:
        """A (4, 4) transform between local coordinates as the same map between file coordinates.

        Exact for projected CRSs (a rigid transform stays rigid); for geographic CRSs the result is the affine map of
        (longitude, latitude, height) that the local rigid transform amounts to.
        """
        to_local = self.matrix()
        return np.linalg.inv(to_local) @ np.asarray(local_transform, dtype=np.float64) @ to_local


def check_compatible(a: CoordinateReference, b: CoordinateReference, names=("source", "target")) -> None:
    """Raise :class:`InputError` unless two CRSs can be registered without reprojection.

    Compatible: same kind and, when both state one, the same EPSG code and linear unit. An unknown CRS is compatible
    with anything (the caller then assumes both files share coordinates).

    Raises
    ------
    InputError
        Naming both CRSs and the fix (reproject one file, e.g. with ``gdalwarp`` or ``pdal translate``).
    """
    if a.kind == "unknown" or b.kind == "unknown":
        return
    same_code = a.epsg is None or b.epsg is None or a.epsg == b.epsg
    if a.kind != b.kind or not same_code or abs(a.unit_to_metre - b.unit_to_metre) > 1e-9:
        raise InputError(f"{names[0]} is in a {a.describe()} but {names[1]} in a {b.describe()}; seismo3d does not "
                         "reproject: convert one file to the other's CRS first (e.g. gdalwarp -t_srs for a DEM, "
                         "pdal translate with filters.reprojection for a LAS/LAZ)")


def encode_geokeys(keys: dict):
    """Encode ``{key_id: value}`` as the three GeoTIFF tags (the inverse of :func:`parse_geokeys`).

    Parameters
    ----------
    keys : dict
        Values are ints (stored in the directory), floats or tuples of floats (GeoDoubleParams) or strs
        (GeoAsciiParams).

    Returns
    -------
    directory : list of int
        The GeoKeyDirectory shorts (tag 34735).
    doubles : list of float
        The GeoDoubleParams (tag 34736), possibly empty.
    ascii_params : str
        The GeoAsciiParams (tag 34737), possibly empty.
    """
    directory, doubles, ascii_params = [1, 1, 0, 0], [], ""
    for key in sorted(keys):
        value = keys[key]
        if isinstance(value, str):
            text = value + "|"
            directory += [key, 34737, len(text), len(ascii_params)]
            ascii_params += text
        elif isinstance(value, (float, tuple, list, np.floating)):
            vals = [float(v) for v in np.atleast_1d(value)]
            directory += [key, 34736, len(vals), len(doubles)]
            doubles += vals
        else:
            directory += [key, 0, 1, int(value)]
    directory[3] = (len(directory) - 4) // 4
    return directory, doubles, ascii_params


def geokeys_for(crs: CoordinateReference, *, pixel_is_point: bool = False) -> dict:
    """GeoKeys that describe ``crs`` (its own keys when it was read from keys, else a minimal set).

    Parameters
    ----------
    crs : CoordinateReference
    pixel_is_point : bool
        Raster type: pixel values at pixel centres (True) or over pixel areas (False, the default of GDAL).

    Returns
    -------
    dict
        ``{key_id: value}``; empty for an unknown CRS.
    """
    if crs.kind == "unknown":
        return {}
    keys = dict(crs.geokeys)
    if not keys:
        if crs.is_geographic:
            keys = {_MODEL_TYPE: 2, _GEOGRAPHIC_TYPE: crs.epsg or _USER_DEFINED, _GEOG_ANGULAR_UNITS: 9102}
            if crs.name:
                keys[_GEOG_CITATION] = crs.name
        else:
            unit = next((code for code, (_, m) in _LINEAR_UNITS.items() if abs(m - crs.unit_to_metre) < 1e-12),
                        _USER_DEFINED)
            keys = {_MODEL_TYPE: 1, _PROJECTED_TYPE: crs.epsg or _USER_DEFINED, _PROJ_LINEAR_UNITS: unit}
            if crs.name:
                keys[_PCS_CITATION] = crs.name
    keys[_RASTER_TYPE] = 2 if pixel_is_point else 1
    return keys
