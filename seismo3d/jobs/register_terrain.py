"""The terrain branch of ``seismo3d register``: LAS/LAZ scans and GeoTIFF DEMs in, the transform JSON out."""

from __future__ import annotations

import json
import pathlib

import numpy as np

from .._atomic import atomic_path
from ..errors import InputError
from ..terrain import TerrainRegistration, TerrainRegistrationOptions, read_terrain, register_terrain

__all__ = ["run_register_terrain_job"]


def run_register_terrain_job(source, target, output, *, method: str = "fused", model: str = "rigid", init=None,
                             max_distance=None, alpha: float | None = None) -> TerrainRegistration:
    """Register a terrain file onto another and write the transform JSON, atomically.

    Parameters
    ----------
    source, target : str or os.PathLike
        LAS/LAZ or GeoTIFF DEM files (any pair, in one CRS). The source is moved onto the target.
    output : str or os.PathLike
        The JSON: ``transform`` (4 x 4, source to target in the files' coordinates and units; for geographic DEMs
        the affine map of longitude, latitude and height), ``transform_local`` and ``local_origin`` /
        ``local_scale`` / ``local_unit`` (the recentred frame the fit ran in: metres east / north for geographic
        CRSs), ``rotation_deg``, ``heading_deg``, the engine's fitness, inlier_rmse (local unit), n_iterations,
        converged, degenerate, the matches used, both CRSs and the paths.
    method : {'fused', 'point_to_plane'}
        ``'fused'``: hillshade features start and join the fit (eq. 16); ``'point_to_plane'``: ICP from ``init`` or
        the identity.
    model : {'rigid', 'similarity'}
    init : (4, 4) array_like, optional
        Initial source-to-target transform in the files' coordinates.
    max_distance : sequence of float, optional
        Correspondence distances, coarse to fine, in the local unit (the files' unit; metres for geographic CRSs).
    alpha : float, optional
        Weight of the feature term (default :class:`~seismo3d.terrain.TerrainRegistrationOptions`'s).

    Returns
    -------
    TerrainRegistration

    Raises
    ------
    InputError
        Unsupported method or model, an output that would overwrite an input, incompatible CRSs, an empty LAS or an
        all-nodata DEM.
    RegistrationError
        When the inputs do not overlap enough to register.
    """
    source, target, output = (pathlib.Path(p) for p in (source, target, output))
    if method not in ("fused", "point_to_plane"):
        raise InputError(f"--method {method} is not available for terrain files; use fused (hillshade features + "
                         "point-to-plane, the default) or point_to_plane (from --init or the identity)")
    if output.resolve() in (source.resolve(), target.resolve()):
        raise InputError(f"{output} would overwrite an input; choose another output path")
    src = read_terrain(source)
    dst = read_terrain(target)
    fields = dict(features=method == "fused", model=model)
    if max_distance:
        fields["max_distance"] = tuple(float(v) for v in max_distance)
    if alpha is not None:
        fields["alpha"] = float(alpha)
    options = TerrainRegistrationOptions(**fields)
    result = register_terrain(src, dst, init=init, options=options)
    payload = result.to_dict()
    payload.update(method=method, model=model, source=str(source), target=str(target),
                   source_crs=src.crs.to_dict(), target_crs=dst.crs.to_dict(),
                   units=_units(dst.crs))
    with atomic_path(output) as tmp:
        tmp.write_text(json.dumps(payload, indent=2, default=_jsonable) + "\n")
    return result


def _units(crs) -> str:
    if crs.is_geographic:
        return "transform: degrees of longitude / latitude and metres of height; transform_local: metres"
    return f"{crs.linear_unit} (x, y), {crs.vertical_unit} (z)"


def _jsonable(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")
