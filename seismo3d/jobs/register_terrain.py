"""The terrain branch of ``seismo3d register``: LAS/LAZ scans and GeoTIFF DEMs in, the transform JSON out.

:func:`seismo3d.jobs.register.run_register_job` hands terrain files here; the result is the same
:class:`~seismo3d.jobs.register_files.RegisterJob` (``kind='terrain'``).
"""

from __future__ import annotations

import pathlib

import numpy as np

from ..errors import InputError
from ..terrain import TerrainRegistrationOptions, is_terrain_file, read_terrain, register_terrain
from .outputs import check_outputs, output_file
from .register_files import RegisterJob, finish_register_job, read_transform
from .runinfo import RunRecord, run_json_output

__all__ = ["run_register_terrain_job"]


def run_register_terrain_job(source, target, output, *, method: str = "fused", model: str = "rigid", init=None,
                             max_distance=None, alpha: float | None = None, overwrite: bool = False,
                             record: RunRecord | None = None) -> RegisterJob:
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
        converged, degenerate, held_by_features (see :attr:`~seismo3d.terrain.TerrainRegistration.converged`), the
        matches used, both CRSs and the paths.
    method : {'fused', 'point_to_plane'}
        ``'fused'``: hillshade features start and join the fit (eq. 16); ``'point_to_plane'``: ICP from ``init`` or
        the identity.
    model : {'rigid', 'similarity'}
    init : str or os.PathLike, optional
        A JSON file with an initial source-to-target transform in the files' coordinates
        (``{"transform": [[...], ...]}``, 4 x 4).
    max_distance : sequence of float, optional
        Correspondence distances, coarse to fine, in the local unit (the files' unit; metres for geographic CRSs).
    alpha : float, optional
        Weight of the feature term (default :class:`~seismo3d.terrain.TerrainRegistrationOptions`'s).
    overwrite : bool, optional
        Replace an existing ``output`` (:mod:`seismo3d.jobs.outputs`).
    record : RunRecord, optional
        The run's record when :func:`~seismo3d.jobs.register.run_register_job` hands the files here (its
        arguments are the run's options); by default a new one with this function's arguments. Written beside
        ``output`` as ``<output>.run.json`` (:mod:`seismo3d.jobs.runinfo`).

    Returns
    -------
    RegisterJob
        ``kind='terrain'``, ``result`` the :class:`~seismo3d.terrain.TerrainRegistration`, ``converged`` its
        :attr:`~seismo3d.terrain.TerrainRegistration.converged` (the hillshade matches count when the surfaces are
        too gentle to fix the horizontal position).

    Raises
    ------
    InputError
        An output that is an input, exists (without ``overwrite``) or cannot be written; a file that is not
        LAS/LAZ/GeoTIFF beside one that is, unsupported method or model, a bad ``init`` file, incompatible CRSs, an
        empty LAS or an all-nodata DEM.
    RegistrationError
        When the inputs do not overlap enough to register.
    """
    if record is None:
        record = RunRecord("register", {k: v for k, v in locals().items() if k != "record"})
    source, target, output = (pathlib.Path(p) for p in (source, target, output))
    main = output_file(output, "transform.json")
    check_outputs([main, run_json_output(main)], [source, target, init], overwrite=overwrite)
    if not (is_terrain_file(source) and is_terrain_file(target)):
        raise InputError(f"{source} and {target}: register two terrain files (LAS/LAZ, GeoTIFF) or two point clouds, "
                         "not one of each (convert the point cloud to LAS/LAZ)")
    if model not in ("rigid", "similarity"):
        raise InputError(f"--model {model} is not available for terrain files; use rigid or similarity")
    if method not in ("fused", "point_to_plane"):
        raise InputError(f"--method {method} is not available for terrain files; use fused (hillshade features + "
                         "point-to-plane, the default) or point_to_plane (from --init or the identity)")
    with record.stage("read"):
        src = read_terrain(source)
        dst = read_terrain(target)
    fields = dict(features=method == "fused", model=model)
    if max_distance:
        fields["max_distance"] = tuple(float(v) for v in max_distance)
    if alpha is not None:
        fields["alpha"] = float(alpha)
    options = TerrainRegistrationOptions(**fields)
    start = None if init is None else read_transform(init, 3)
    with record.stage("register"):
        result = register_terrain(src, dst, init=start, options=options)
    payload = _jsonable(result.to_dict())
    payload.update(method=method, model=model, source=str(source), target=str(target),
                   source_crs=_jsonable(src.crs.to_dict()), target_crs=_jsonable(dst.crs.to_dict()),
                   units=_units(dst.crs))
    job = RegisterJob("terrain", result, payload, bool(result.converged))
    return finish_register_job(job, record, output, {"source": source, "target": target, "init": init})


def _units(crs) -> str:
    if crs.is_geographic:
        return "transform: degrees of longitude / latitude and metres of height; transform_local: metres"
    return f"{crs.linear_unit} (x, y), {crs.vertical_unit} (z)"


def _jsonable(value):
    """``value`` with numpy scalars and arrays (at any depth of dicts and lists) as plain Python values."""
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value
