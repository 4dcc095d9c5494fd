"""The ``seismo3d lineaments`` job: a DEM in; lineaments.csv, rose.png and lineaments.png out."""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np

from .._atomic import StagedFolder
from ..terrain import (
    LineamentOptions,
    Lineaments,
    extract_lineaments,
    multidirectional_hillshade,
    read_dem,
    write_lineaments_csv,
)
from .outputs import check_outputs, output_folder
from .runinfo import RUN_JSON, RunRecord, run_json_path

__all__ = ["LineamentsJobResult", "RESULTS", "run_lineaments_job"]

RESULTS = ("lineaments.csv", "rose.png", "lineaments.png", RUN_JSON)  # what a run writes into its folder


@dataclass(frozen=True)
class LineamentsJobResult:
    """What :func:`run_lineaments_job` found and wrote.

    Attributes
    ----------
    lineaments : Lineaments
    written : dict
        ``{'csv': path, 'rose': path, 'map': path}``.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``read``, ``extract``, ``write``).
    """

    lineaments: Lineaments
    written: dict
    run_json: pathlib.Path | None = None
    stage_seconds: dict | None = None


def run_lineaments_job(dem_path, outdir, *, options: LineamentOptions | None = None,
                       overwrite: bool = False) -> LineamentsJobResult:
    """Extract the lineaments of a GeoTIFF DEM and write them with two pictures.

    Writes into ``outdir`` (created if missing; the files moved in together once all are written):

    - ``lineaments.csv``: ``x0, y0, x1, y1`` (end points in the raster's CRS), ``azimuth_deg`` (strike in [0, 180),
      clockwise from north), ``length_m``, ``contrast`` (see :class:`~seismo3d.terrain.Lineaments`), ranked (the strongest evidence first);
    - ``rose.png``: the length-weighted rose diagram of the strikes (10-degree bins);
    - ``lineaments.png``: the lineaments over the multidirectional hillshade, coloured by strike;
    - ``run.json``: the record of the run (options, inputs' sha256, stage times; :mod:`seismo3d.jobs.runinfo`).

    Parameters
    ----------
    dem_path : str or os.PathLike
        A GeoTIFF DEM.
    outdir : str or os.PathLike
        Not the DEM's folder nor one holding an earlier run's files unless ``overwrite`` (see
        :mod:`seismo3d.jobs.outputs`; checked before the DEM is read).
    options : LineamentOptions, optional
    overwrite : bool, optional
        Replace the files of an earlier run in ``outdir``.

    Returns
    -------
    LineamentsJobResult

    Raises
    ------
    InputError
        An output folder that holds the DEM, is a file, holds an earlier run's files (without ``overwrite``) or
        cannot be written; an all-nodata DEM, a DEM smaller than 16 x 16.
    DataNotFoundError, DataIntegrityError
        A missing or unreadable file.
    """
    record = RunRecord("lineaments", locals())  # first: the arguments as called
    outdir = pathlib.Path(outdir)
    name = pathlib.Path(dem_path).name
    main = output_folder(outdir, RESULTS, f"{pathlib.Path(dem_path).stem}_lineaments")
    check_outputs([main], [dem_path], overwrite=overwrite)
    with record.stage("read"):
        dem = read_dem(dem_path)
    with record.stage("extract"):
        found = extract_lineaments(dem, options=options)
    with StagedFolder(outdir) as stage:
        with record.stage("write"):
            written = _write_files(stage.path, dem, found, name)
        final = {key: stage.final(path) for key, path in written.items()}
        record.write(stage.path / RUN_JSON, inputs={"dem": dem_path}, outputs=final,
                     results=dict(n_lineaments=len(found), length_km=float(found.length_m.sum()) / 1000))
    return LineamentsJobResult(found, final, run_json_path(main), dict(record.stage_seconds))


def _write_files(folder: pathlib.Path, dem, found: Lineaments, name: str) -> dict:
    """lineaments.csv, rose.png and lineaments.png into ``folder``, by key."""
    from ..viz.terrain import plot_lineament_map, plot_rose

    written = {"csv": write_lineaments_csv(folder / "lineaments.csv", found)}
    written["rose"] = plot_rose(found.azimuth_deg, found.length_m, folder / "rose.png",
                                title=f"{name}: {len(found)} lineaments, {found.length_m.sum() / 1000:.1f} km, "
                                      "length-weighted strikes")
    shade = multidirectional_hillshade(dem.elevation_m, dem.metric_axes)
    extent, segments, aspect, labels = _map_frame(dem, found)
    written["map"] = plot_lineament_map(shade, extent, segments, found.azimuth_deg, folder / "lineaments.png",
                                        aspect=aspect, axis_labels=labels,
                                        title=f"{name}: {len(found)} lineaments over the multidirectional "
                                              "hillshade")
    return written


def _map_frame(dem, found: Lineaments):
    """Extent, segments, aspect and axis labels of the map: CRS coordinates for north-up rasters, pixels otherwise."""
    a = dem.affine
    north_up = abs(a[0, 1]) < 1e-15 and abs(a[1, 0]) < 1e-15 and a[0, 0] > 0 and a[1, 1] < 0
    h, w = dem.shape
    if north_up:
        left, top = dem.xy(-0.5, -0.5)
        right, bottom = dem.xy(h - 0.5, w - 0.5)
        segments = np.column_stack([found.x0, found.y0, found.x1, found.y1])
        if dem.crs.is_geographic:
            aspect = 1.0 / np.cos(np.radians(dem.centre_xy[1]))
            labels = ("longitude, degrees", "latitude, degrees")
        else:
            aspect = 1.0
            unit = dem.crs.linear_unit if dem.crs.kind != "unknown" else "map units"
            labels = (f"x, {unit}", f"y, {unit}")
        return (float(left), float(right), float(bottom), float(top)), segments, aspect, labels
    segments = np.column_stack([found.cols0, found.rows0, found.cols1, found.rows1])
    dy, dx = dem.pixel_size_m
    return (-0.5, w - 0.5, h - 0.5, -0.5), segments, dy / dx, ("column", "row")
