"""The ``seismo3d register`` job: register SOURCE onto TARGET and write the transform as JSON.

Two point clouds (PLY, XYZ text, NPY) are registered by ICP or fused ICP (:mod:`seismo3d.registration`); two SEG-Y
sub-volumes by :func:`seismo3d.seismic.register_volumes`; two terrain files (LAS/LAZ scans, GeoTIFF DEMs) by
:func:`seismo3d.terrain.register_terrain` (:mod:`seismo3d.jobs.register_terrain`). The order means the same for all:
the first file is moved (source, the moving volume) onto the second (target, the fixed volume), and the JSON's
transforms map the first's coordinates into the second's.
"""

from __future__ import annotations

import dataclasses
import pathlib
import warnings

import numpy as np

from ..errors import InputError, TraceListWarning
from ..seismic import register_volumes
from ..seismic.io.cube import grid_spacing
from ..seismic.volumes import VOLUME_MODELS
from .inputs import input_kind, read_seismic
from .outputs import check_outputs, output_file
from .register_files import RegisterJob, finish_register_job, read_transform
from .runinfo import RunRecord, run_json_output

__all__ = ["RegisterJob", "run_register_job", "is_segy"]


def is_segy(path) -> bool:
    """Whether ``path`` names a SEG-Y file (.sgy or .segy, any case; :func:`~seismo3d.jobs.inputs.input_kind`)."""
    return input_kind(path) == "segy"


def run_register_job(source, target, output, *, method: str | None = None, model: str | None = None,
                     init=None, max_distance=None, features=None, alpha: float | None = None, iline: int = 189,
                     xline: int = 193, endian=None, overwrite: bool = False, progress: bool = True) -> RegisterJob:
    """Register ``source`` onto ``target`` and write the JSON of the transform (atomically).

    Parameters
    ----------
    source, target : str or path-like
        Two point clouds, two SEG-Y cubes (the moving one first, then the fixed one), or two terrain files (LAS/LAZ,
        GeoTIFF DEM; :func:`~seismo3d.jobs.register_terrain.run_register_terrain_job`).
    output : str or path-like
        The JSON file; not an input, and not an existing file unless ``overwrite`` (see
        :mod:`seismo3d.jobs.outputs`; checked before the inputs are read).
    method : {'point_to_plane', 'point_to_point', 'fused'}, optional
        Point clouds: the residual (fused = feature matches + point-to-plane, eq. 16); default point_to_plane.
        Terrain files: fused (hillshade matches, the default) or point_to_plane.
    model : {'rigid', 'similarity', 'axis_scaled', 'affine'}, optional
        Transform family; default rigid for point clouds, affine for SEG-Y cubes (which allow affine: the bins of
        both cubes, a map rotation, a vertical scale and shift; and rigid).
    init : str or path-like, optional
        Point clouds and terrain files: a JSON file with an initial source-to-target transform
        (``{"transform": [[...], ...]}``).
    max_distance : sequence of float, optional
        Point clouds: maximum correspondence distances, coarse to fine (default 10 / 3 / 1 % of the target's
        bounding-box diagonal).
    features : str or path-like, optional
        ``method='fused'``: matched feature points, one row per match, source coordinates then target coordinates
        (.csv / .txt / .npy with 2d columns).
    alpha : float, optional
        ``method='fused'``: weight of the feature term in [0, 1] (default 0.1 for point clouds,
        :class:`~seismo3d.terrain.TerrainRegistrationOptions`'s for terrain files).
    iline, xline, endian
        SEG-Y cubes: how to open both (:func:`seismo3d.open`, as :func:`~seismo3d.seismic.open_segy`: by default
        inline / crossline numbers at trace header bytes 189 / 193 and the byte order detected per file); their bins
        from their CDP X / Y and sample intervals (:func:`~seismo3d.seismic.io.cube.grid_spacing`).
    overwrite : bool
        Replace an existing ``output``.
    progress : bool
        Report progress of a volume registration (:mod:`seismo3d._progress`).

    Returns
    -------
    RegisterJob

    Raises
    ------
    InputError
        An output that is an input, exists (without ``overwrite``) or cannot be written; mixed inputs (a cloud and
        a cube, a cloud and a terrain file), mismatched dimensions, points or matches with NaN or infinite
        coordinates (the message names the file and rows), a model unavailable for volumes or terrain files, a
        missing or bad ``init`` or ``features`` file, a SEG-Y file that is not a 3D cube; and the registrations' own errors (:class:`~seismo3d.errors.InputError`,
        :class:`~seismo3d.errors.RegistrationError`).
    SegyFormatError, SegyGeometryError
        A SEG-Y file that cannot be read (see :func:`~seismo3d.seismic.open_segy`).
    """
    record = RunRecord("register", locals())  # first: the arguments as called
    source, target, output = pathlib.Path(source), pathlib.Path(target), pathlib.Path(output)
    main = output_file(output, "transform.json")
    check_outputs([main, run_json_output(main)], [source, target, init, features], overwrite=overwrite)
    if is_segy(source) or is_segy(target):
        if not (is_segy(source) and is_segy(target)):
            raise InputError(f"{source} and {target}: register either two SEG-Y cubes or two point clouds, not one "
                             "of each")
        segy = dict(iline=iline, xline=xline, endian=endian)
        with record.stage("register"):
            job = _register_volumes(source, target, model or "affine", progress, segy)
    elif _is_terrain(source, target):
        # the point-cloud and terrain machinery (data registry, ICP, rasters: 1.2 s of the 2.6 s of imports) only
        # for those inputs, so that registering two SEG-Y cubes does not wait for it
        from .register_terrain import run_register_terrain_job

        if features is not None:
            raise InputError("--features is for point clouds; terrain files are matched through their hillshades")
        return run_register_terrain_job(source, target, output, method=method or "fused", model=model or "rigid",
                                        init=init, max_distance=max_distance, alpha=alpha, overwrite=overwrite,
                                        record=record)
    else:
        job = _register_point_clouds(source, target, method or "point_to_plane", model or "rigid", init,
                                     max_distance, features, 0.1 if alpha is None else alpha, record)
    return finish_register_job(job, record, output, {"source": source, "target": target, "init": init,
                                                     "features": features})


def _is_terrain(*paths) -> bool:
    """Whether any of ``paths`` is a LAS/LAZ scan or a GeoTIFF DEM (:func:`~seismo3d.jobs.inputs.input_kind`)."""
    return any(input_kind(p) == "terrain" for p in paths)


def _register_point_clouds(source, target, method, model, init, max_distance, features, alpha,
                           record: RunRecord) -> RegisterJob:
    from ..data.pointclouds import read_points
    from ..geometry import estimate_normals
    from ..registration import ICPOptions, fused_icp, icp

    with record.stage("read"):
        src = _finite_rows(read_points(source), source, "SOURCE")
        dst = _finite_rows(read_points(target), target, "TARGET")
    if src.shape[1] != dst.shape[1]:
        raise InputError(f"{source} is {src.shape[1]}D but {target} is {dst.shape[1]}D")
    start = None if init is None else read_transform(init, src.shape[1])
    options = ICPOptions(max_distance=tuple(max_distance) if max_distance else None)
    if method == "fused" and features is None:
        raise InputError("--method fused needs --features MATCHES (rows of source then target coordinates of "
                         "matched features, e.g. from `seismo3d match` lifted to 3D)")
    with record.stage("register"):
        normals = None if method == "point_to_point" else estimate_normals(dst, orient="none")
        if method == "fused":
            pairs = _finite_rows(read_matches(features, src.shape[1]), features, "--features")
            result = fused_icp(src, dst, target_normals=normals, source_features=pairs[:, : src.shape[1]],
                               target_features=pairs[:, src.shape[1]:], alpha=alpha, model=model, init=start,
                               options=options)
        else:
            result = icp(src, dst, method=method, model=model, target_normals=normals, init=start, options=options)
    payload = result.to_dict()
    payload.update(method=method, model=model, source=str(source), target=str(target))
    return RegisterJob("point_clouds", result, payload, bool(result.converged))


def _register_volumes(moving_path, fixed_path, model, progress, segy: dict) -> RegisterJob:
    """MOVING.sgy onto FIXED.sgy: the sub-volume registration, JSON with both transforms, the check and the stage
    times."""
    if model not in VOLUME_MODELS:
        raise InputError(f"--model {model} is not available for SEG-Y volumes; use affine (the default: the bins of "
                         "both cubes, the map rotation and the vertical scale are estimated) or rigid (the spacings "
                         "from the headers are right)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TraceListWarning)  # a file without a grid is refused below, saying why
        # through seismo3d.open: the headers now, a cube's samples when registered
        fixed, moving = (read_seismic(path, **segy, arrays=False, lazy_if=lambda shape: True)
                         for path in (fixed_path, moving_path))
    for cube in (moving, fixed):
        if cube.kind != "cube":
            raise InputError(f"{cube.path.name} is {cube.description}, not a 3D cube; register two 3D cubes")
    (sp_f, note_f), (sp_m, note_m) = grid_spacing(fixed.cube), grid_spacing(moving.cube)
    first_f = (int(fixed.inlines[0]), int(fixed.xlines[0]), float(fixed.samples[0]))
    first_m = (int(moving.inlines[0]), int(moving.xlines[0]), float(moving.samples[0]))
    reg = register_volumes(fixed.cube.values, moving.cube.values, model=model, fixed_spacing=sp_f,
                           moving_spacing=sp_m, progress=progress)
    reg = dataclasses.replace(reg, spacing_note=f"fixed: {note_f}; moving: {note_m}")  # the headers, not "given"
    payload = reg.to_dict()
    payload.update(model=model, moving=str(moving_path), fixed=str(fixed_path),
                   index_axes=["inline", "crossline", "sample"],
                   fixed_first=dict(zip(("inline", "xline", "sample_value"), first_f)),
                   moving_first=dict(zip(("inline", "xline", "sample_value"), first_m)))
    return RegisterJob("volumes", reg, payload, bool(reg.converged))


def _finite_rows(table: np.ndarray, path, role: str) -> np.ndarray:
    """``table`` when every row is finite; else InputError naming the file and its first bad rows (from 1)."""
    bad = np.flatnonzero(~np.isfinite(table).all(axis=1))
    if bad.size:
        rows = ", ".join(str(int(r) + 1) for r in bad[:5]) + (" ..." if bad.size > 5 else "")
        raise InputError(f"{role} {pathlib.Path(path).name} has {bad.size} of {len(table)} rows with NaN or infinite "
                         f"coordinates (rows {rows}, counting from 1); remove or fix those rows in the file and run "
                         "again")
    return table


def read_matches(path, dim: int) -> np.ndarray:
    """(K, 2 dim) feature matches of a .npy, .csv or whitespace text file (source then target coordinates).

    Raises
    ------
    InputError
        Not 2 dim columns (the message names the file).
    """
    path = pathlib.Path(path)
    if path.suffix == ".npy":
        table = np.load(path, allow_pickle=False)
    else:
        table = np.loadtxt(path, delimiter="," if path.suffix == ".csv" else None, ndmin=2, comments="#")
    if table.ndim != 2 or table.shape[1] != 2 * dim:
        raise InputError(f"{path} must have {2 * dim} columns (source then target coordinates); got {table.shape}")
    return table
