"""LiDAR point clouds from LAS / LAZ files (laspy; LAZ through its lazrs backend), with their CRS."""

from __future__ import annotations

import pathlib
from dataclasses import dataclass, field

import numpy as np

from .._atomic import atomic_path
from .._validation import as_points
from ..errors import DataIntegrityError, DataNotFoundError, InputError
from .georef import UNKNOWN_CRS, CoordinateReference, parse_geokeys, parse_wkt, reference_from_geokeys

__all__ = ["LidarScan", "read_las", "write_las", "LAS_SUFFIXES"]

LAS_SUFFIXES = (".las", ".laz")


@dataclass(frozen=True)
class LidarScan:
    """A LiDAR point cloud in its file's coordinates.

    Attributes
    ----------
    points : (N, 3) float64 ndarray
        x, y, z in the file's CRS and units (scaled and offset as the header says).
    classification : (N,) uint8 ndarray
        ASPRS class of each point (2 = ground, 6 = building...).
    crs : CoordinateReference
        From the GeoKey directory or the WKT VLR (``kind='unknown'`` when the file states none).
    path : pathlib.Path or None
        The file read, if any.
    header : laspy.LasHeader or None
        The file's header (VLRs, scales, offsets) for :func:`write_las` to copy.
    """

    points: np.ndarray
    classification: np.ndarray
    crs: CoordinateReference = UNKNOWN_CRS
    path: pathlib.Path | None = None
    header: object = field(default=None, compare=False, repr=False)

    def __len__(self) -> int:
        return int(self.points.shape[0])


def read_las(path, *, classes=None) -> LidarScan:
    """Read a LAS or LAZ file.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.las`` or ``.laz`` file (LAS 1.0-1.4, any point format).
    classes : sequence of int, optional
        Keep only points of these ASPRS classes (e.g. ``(2,)`` for ground); default all.

    Returns
    -------
    LidarScan

    Raises
    ------
    DataNotFoundError
        If the file does not exist.
    DataIntegrityError
        If laspy cannot read it (not LAS/LAZ, truncated, LAZ without a backend).
    InputError
        If the file (or the chosen classes) holds no points.

    References
    ----------
    ASPRS (2019). LAS Specification 1.4 R15. laspy: https://laspy.readthedocs.io
    """
    import laspy

    path = pathlib.Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"{path}: no such file; check the path")
    try:
        las = laspy.read(path)
    except (laspy.errors.LaspyException, OSError, ValueError, EOFError) as exc:
        raise DataIntegrityError(f"{path.name} is not a readable LAS/LAZ file ({exc}); check that it is complete "
                                 "(LAZ needs laspy's lazrs backend: pip install 'laspy[lazrs]')") from exc
    points = np.column_stack([np.asarray(las.x, np.float64), np.asarray(las.y, np.float64),
                              np.asarray(las.z, np.float64)]) if len(las.points) else np.zeros((0, 3))
    cls = np.asarray(las.classification, dtype=np.uint8) if len(las.points) else np.zeros(0, np.uint8)
    if len(points) == 0:
        raise InputError(f"{path.name} contains no points (its header counts {las.header.point_count}); "
                         "give a LAS/LAZ file with points")
    if classes is not None:
        keep = np.isin(cls, np.asarray(list(classes), dtype=np.int64))
        if not keep.any():
            raise InputError(f"{path.name} has no points of classes {sorted(classes)} (it has "
                             f"{sorted(np.unique(cls).tolist())}); choose other classes")
        points, cls = points[keep], cls[keep]
    return LidarScan(np.ascontiguousarray(points), cls, _crs_of(las.header), path, las.header)


def _crs_of(header) -> CoordinateReference:
    """The CRS from a laspy header: GeoKey VLRs (LAS <= 1.3 and many 1.4 files) or the OGC WKT VLR."""
    keys, doubles, ascii_params, wkt = None, (), "", None
    for vlr in list(header.vlrs) + list(getattr(header, "evlrs", None) or []):
        kind = type(vlr).__name__
        if kind == "GeoKeyDirectoryVlr":
            h = vlr.geo_keys_header
            keys = [h.key_directory_version, h.key_revision, h.minor_revision, h.number_of_keys]
            for k in vlr.geo_keys:
                keys += [k.id, k.tiff_tag_location, k.count, k.value_offset]
        elif kind == "GeoDoubleParamsVlr":
            doubles = [float(v.value) if hasattr(v, "value") else float(v) for v in vlr.doubles]
        elif kind == "GeoAsciiParamsVlr":
            ascii_params = "|".join(vlr.strings) if isinstance(vlr.strings, list) else str(vlr.strings)
        elif kind == "WktCoordinateSystemVlr":
            wkt = vlr.string
    if wkt:
        crs = parse_wkt(wkt)
        if crs.kind != "unknown":
            return crs
    if keys is not None:
        try:
            return reference_from_geokeys(parse_geokeys(keys, doubles, ascii_params))
        except InputError:
            return UNKNOWN_CRS
    return UNKNOWN_CRS


def write_las(path, points, *, like: LidarScan | None = None, classification=None) -> pathlib.Path:
    """Write points to a LAS or LAZ file (compressed when the suffix is ``.laz``), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Destination ending in ``.las`` or ``.laz``.
    points : (N, 3) array_like
        x, y, z in the CRS of ``like`` (or none).
    like : LidarScan, optional
        A scan whose header (point format, VLRs including the CRS, scales) is copied; default a LAS 1.2 point
        format 3 header with 0.001 scales and offsets at the points' minimum.
    classification : (N,) array_like of int, optional
        ASPRS classes (default 1, unclassified).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        On a bad suffix, points or classification.
    """
    import laspy

    path = pathlib.Path(path)
    if path.suffix.lower() not in LAS_SUFFIXES:
        raise InputError(f"{path.name}: a LAS file must end in .las or .laz")
    pts = as_points(points, "points", dims=(3,))
    if like is not None and like.header is not None:
        header = laspy.LasHeader(point_format=like.header.point_format, version=like.header.version)
        header.vlrs = list(like.header.vlrs)
        header.scales = np.array(like.header.scales)
    else:
        header = laspy.LasHeader(point_format=3, version="1.2")
        header.scales = np.array([0.001, 0.001, 0.001])
    header.offsets = np.floor(pts.min(axis=0))
    las = laspy.LasData(header)
    las.x, las.y, las.z = pts[:, 0], pts[:, 1], pts[:, 2]
    if classification is not None:
        c = np.asarray(classification)
        if c.shape != (len(pts),):
            raise InputError(f"classification must have shape ({len(pts)},); got {c.shape}")
        las.classification = c.astype(np.uint8)
    else:
        las.classification = np.ones(len(pts), np.uint8)
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            las.write(fh, do_compress=path.suffix.lower() == ".laz")
    return path
