"""The ``seismo3d`` command: thin typer wrappers over the jobs (:mod:`seismo3d.jobs`, one per command).

Conventions, the same for every command:

- ``seismo3d --version`` prints the version.
- Registrations read ``SOURCE TARGET``: the first file is moved onto the second (for SEG-Y cubes: ``MOVING FIXED``).
- Errors of seismo3d's own types are printed as one line (problem + fix, naming the command's flags) with exit code 2;
  a registration that did not converge writes its result, says so in one line and exits with 1; Ctrl-C exits with
  130. Anything else is a bug and keeps its traceback.
- Progress goes to standard error: a bar on a terminal, one line per step otherwise (logs, CI).
- Each command checks its output (:func:`~seismo3d._cli_outputs.check_before_import`) before it imports its job:
  the jobs are imported inside the commands, deliberately, so that a refusal and ``--help`` need no numba / scipy
  (nor numpy: the module imports typer and the light modules that check outputs; tests/jobs/test_job_imports.py).
"""

from __future__ import annotations

import gc
import pathlib
from typing import Optional

import typer

from . import __version__
from ._cli_coercion import FastCoercionGroup
from ._cli_choices import (Compression, Endian, FaultColour, Likelihood, MatchMethod, Method, Model, Polarity,
                           SampleUnit)
from ._cli_outputs import check_before_import
from ._cli_text import array_text, echo_terrain, frames_tracked, why_not_converged
from .jobs.outputs import output_file
from ._cli_messages import compile_note, friendly as _friendly, log_progress_to_stderr
from ._cli_messages import one_line_warnings as _one_line_warnings


class _App(typer.Typer):
    """The ``seismo3d`` typer app; when a command ends the process (click's ``sys.exit``, the standalone mode of the
    installed script and of ``python -m seismo3d.cli``), the objects left are moved out of the garbage collector's
    generations (:func:`gc.freeze`) before the interpreter shuts down.

    The interpreter's own collections at shut-down otherwise walk every object of the modules a command imported
    (numpy, zarr, typer, ...) once more, to free memory the ending process returns anyway: 0.14 of 1.38 CPU s of
    ``seismo3d convert`` of the 198 MB cube and 0.04 of 0.19 CPU s of ``seismo3d --help`` (medians of 12 paired runs,
    load 8-9). Objects are still freed by their reference counts, and ``atexit`` handlers run as before; only a
    reference cycle left at the end is not collected nor finalized (its memory goes with the process). A caller that
    catches the ``SystemExit`` and goes on (a notebook calling ``app()``) keeps those cycles;
    ``typer.testing.CliRunner`` does not go through here.
    """

    def __call__(self, *args, **kwargs):
        try:
            return super().__call__(*args, **kwargs)
        except SystemExit:
            gc.freeze()
            raise


# rich_markup_mode=None: help and usage errors in click's plain text, as every click command prints them; typer's rich
# panels import rich, markdown-it and pygments, 0.2 CPU s of a 0.3 s --help (benchmarks/commands.py)
app = _App(help="seismo3d: fault and horizon interpretation of seismic cubes, point-cloud / RGB-D / terrain "
                "registration, lineaments and path planning, on one fused-ICP engine.", no_args_is_help=True,
           add_completion=False, cls=FastCoercionGroup, rich_markup_mode=None)

NOT_CONVERGED = 1  # exit code of a registration that did not converge (its result is written)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"seismo3d {__version__}")
        raise typer.Exit()


@app.callback()
def _main(version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="Print the version and exit.")) -> None:
    """seismo3d: fault and horizon interpretation of seismic cubes, point-cloud / RGB-D / terrain registration."""
    log_progress_to_stderr()


_ENDIAN_HELP = "Byte order of the SEG-Y input; default: detected from its binary header."
_ILINE_HELP = ("Trace header byte of the inline number (SEG-Y); a file without a grid at 189 / 193 is read as a "
               "trace list, at other bytes it is an error.")
_XLINE_HELP = "Trace header byte of the crossline number (SEG-Y)."


def _overwrite_option():
    """The --overwrite flag, the same on every command."""
    return typer.Option(False, "--overwrite", help="Replace the results of an earlier run at the output (an existing "
                                                   "output file, or an output folder's files); without it they are "
                                                   "refused, and an output is never an input.")


def _value(option):
    """The value of an optional Enum option (None stays None)."""
    return None if option is None else option.value


_REGISTER_FLAGS = {"max_distance": "--max-distance", "init": "--init", "alpha": "--alpha", "model": "--model",
                   "method": "--method", "source_features": "--features", "target_features": "--features"}


@app.command()
@_friendly(_REGISTER_FLAGS)
def register(
    source: pathlib.Path = typer.Argument(
        ..., metavar="SOURCE", help="SOURCE, moved onto TARGET: a point cloud (.ply, .xyz/.txt/.csv, .npy), a LiDAR "
                                    "scan (.las/.laz), a GeoTIFF DEM or the MOVING SEG-Y cube (.sgy/.segy)."),
    target: pathlib.Path = typer.Argument(
        ..., metavar="TARGET", help="TARGET, kept fixed: a point cloud, a LiDAR scan or DEM, or the FIXED SEG-Y "
                                    "cube."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Where to write the transform JSON."),
    method: Optional[Method] = typer.Option(None, help="Residual: point-to-point, point-to-plane or fused (features "
                                                       "+ point-to-plane, eq. 16). Default point_to_plane for point "
                                                       "clouds; fused (hillshade features) for LAS/LAZ/GeoTIFF."),
    model: Optional[Model] = typer.Option(None, help="Transform family; default rigid for point clouds, affine for "
                                                     "SEG-Y cubes (the bins of both, map rotation, vertical scale)."),
    init: Optional[pathlib.Path] = typer.Option(None, help="Point clouds and terrain files: JSON with an initial "
                                                           "source-to-target transform (files' coordinates)."),
    max_distance: Optional[list[float]] = typer.Option(
        None, help="Point clouds and terrain files: maximum correspondence distance (repeat for a coarse-to-fine "
                   "schedule); default: 10/3/1 % of the target's bounding-box diagonal (terrain after a feature "
                   "start: 8/3/1.5 hillshade cells)."),
    features: Optional[pathlib.Path] = typer.Option(
        None, help="For --method fused: matched feature points, one row per match: source coordinates then target "
                   "coordinates (.csv/.txt/.npy with 2d columns)."),
    alpha: Optional[float] = typer.Option(None, help="For --method fused: weight of the feature term in [0, 1] "
                                                     "(default 0.1; 0.001 for terrain files)."),
    iline: int = typer.Option(189, help="SEG-Y cubes: trace header byte of the inline number."),
    xline: int = typer.Option(193, help="SEG-Y cubes: trace header byte of the crossline number."),
    endian: Optional[Endian] = typer.Option(None, help="SEG-Y cubes: byte order; default: detected from each file's "
                                                       "binary header."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Register SOURCE onto TARGET and write the transform mapping SOURCE's coordinates into TARGET's.

    Point clouds: the JSON holds the (d+1)x(d+1) matrix under "transform" plus fitness, inlier_rmse, n_iterations,
    converged. Two SEG-Y cubes (`seismo3d register MOVING.sgy FIXED.sgy`): sub-volumes of different bin size, sample
    rate or map orientation are registered with register_volumes (--model affine or rigid), with the same answer in
    either order; the JSON holds the 4x4 transforms from MOVING's inline / crossline / sample indices to FIXED's
    (transform_index) and between physical units (transform_physical: m, m, ms or m), the map rotation, the scales
    of both cubes, correlation, overlap, converged and the reason when not, the consistency check and the seconds of
    each stage. LAS/LAZ scans and GeoTIFF DEMs (any pair in one CRS) are registered in a frame
    recentred on the target, started from matches between their hillshades (no initial guess needed); the JSON's
    transform is in the files' own coordinates and units. A registration that did not converge is written, reported
    and exits with 1 (a terrain fit whose surfaces are too gentle to fix the horizontal position counts as converged
    when the hillshade matches hold it)."""
    check_before_import("file", output, [source, target, init, features], overwrite=overwrite)
    from .jobs.register import run_register_job

    with _one_line_warnings(), compile_note():
        job = run_register_job(source, target, output, method=None if method is None else method.value,
                               model=None if model is None else model.value, init=init,
                               max_distance=max_distance or None, features=features, alpha=alpha, iline=iline,
                               xline=xline, endian=_value(endian), overwrite=overwrite, progress=True)
    if job.kind == "volumes":
        reg = job.result
        stages = "  ".join(f"{k} {v:.1f}" for k, v in reg.stage_seconds.items())
        typer.echo(f"map rotation {reg.rotation_deg:.2f} deg  moving scales "
                   f"{array_text(reg.moving_scales, precision=4)}  fixed scales "
                   f"{array_text(reg.fixed_scales[:2], precision=4)}  correlation {reg.correlation:.3f}  "
                   f"overlap {reg.overlap:.0%}  converged {reg.converged}")
        typer.echo(f"seconds: {stages}")
        typer.echo(array_text(reg.transform_index, precision=4, suppress_small=True))
    elif job.kind == "terrain":
        echo_terrain(job.result)
    else:
        result = job.result
        typer.echo(f"fitness {result.fitness:.3f}  inlier RMSE {result.inlier_rmse:.4g}  iterations "
                   f"{result.n_iterations}  converged {result.converged}"
                   + ("  (DEGENERATE geometry)" if result.degenerate else ""))
        typer.echo(array_text(result.transform, precision=6, suppress_small=True))
    if not job.converged:
        typer.echo(f"error: the registration did not converge ({why_not_converged(job)}); its last estimate was "
                   f"written to {output}", err=True)
        raise typer.Exit(NOT_CONVERGED)


@app.command()
@_friendly({"sample_unit": "--sample-unit", "n_samples": "--n-samples", "ignore_geometry": "--ignore-geometry",
            "demo_seed": "--demo-seed", "sensitivity": "--sensitivity", "likelihood": "--likelihood",
            "memory_limit": "--memory-limit",
            "scheduler": "--scheduler"})
def faults(
    input: Optional[pathlib.Path] = typer.Argument(
        None, metavar="INPUT", help="SEG-Y cube or 2D line, raw .f32be section or .npy array; omit with --demo.",
        show_default=False),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Output folder (created if missing); not one "
                                                                      "holding the input."),
    demo: bool = typer.Option(False, "--demo", help="Run on a generated 128^3 cube with 3 faults (no input file)."),
    demo_seed: int = typer.Option(0, "--demo-seed", help="Random seed of the --demo cube."),
    iline: int = typer.Option(189, help=_ILINE_HELP),
    xline: int = typer.Option(193, help=_XLINE_HELP),
    endian: Optional[Endian] = typer.Option(None, help=_ENDIAN_HELP),
    ignore_geometry: bool = typer.Option(False, "--ignore-geometry", help="Read the SEG-Y as a trace list (unsorted "
                                                                          "file, arbitrary line): trace a 2D section."),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms unless they speak of depth)."),
    n_samples: Optional[int] = typer.Option(None, help="Samples per trace of a raw .f32be section of unknown shape."),
    sensitivity: Optional[float] = typer.Option(None, min=0.0, max=1.0, show_default=False, help="How readily faults "
                                                "are traced, 0-1 (default 0.5, or the one --model MODEL records): "
                                                "higher for more (and weaker) faults, lower for fewer; the "
                                                "thresholds scale by up to 2x either way."),
    likelihood: Likelihood = typer.Option(Likelihood.learned, "--likelihood", help="Fault likelihood: 'learned' "
                                          "(seismo3d's fault network, trained on generated sections; the default, "
                                          "chosen on faults drawn by people) or 'scan' (fault-plane semblance, "
                                          "Hale 2013)."),
    memory_limit: Optional[str] = typer.Option(None, "--memory-limit", help="Memory the run may use, e.g. 8GB "
                                               "(default: half the RAM). A larger 3D cube is traced block by "
                                               "block (fault_likelihood.zarr, fault_surfaces.zarr), resumably, "
                                               "with the same faults."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="dask.distributed scheduler address "
                                            "(tcp://host:port) for block-by-block runs; default: local threads."),
    model: Optional[pathlib.Path] = typer.Option(None, "--model", show_default=False, help="A MODEL folder of "
                                                 "'seismo3d adapt': its network replaces the shipped one, traced "
                                                 "as MODEL records (sensitivity; whether faults across unbroken "
                                                 "reflectors are dropped)."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Trace the faults of INPUT and write fault likelihood, strike, dip and votes (SEG-Y for SEG-Y input), fault
    surfaces (faults.vtp), fault points and a per-fault summary (CSV) and a picture (faults.png) into OUTPUT. In a cube
    strike and dip are not computed where the fault network's probability is below 0.01 (no fault is traced there):
    0 in SEG-Y files (a computed dip is in (0, 90]), NaN in .npy files."""
    check_before_import("folder", output, [input, model], overwrite=overwrite)
    from .jobs.faults import run_faults_job

    with _one_line_warnings(), compile_note():
        job = run_faults_job(input, output, demo=demo, demo_seed=demo_seed, iline=iline, xline=xline,
                             ignore_geometry=ignore_geometry, endian=_value(endian),
                             sample_unit=None if sample_unit is None else sample_unit.value,
                             n_samples=n_samples, sensitivity=sensitivity, likelihood=likelihood.value,
                             memory_limit=memory_limit, scheduler=scheduler, overwrite=overwrite, progress=True,
                             **({"model": model} if model is not None else {}))
    rows = job.faults
    source = "the demo cube" if demo else input.name
    typer.echo(f"{len(rows)} fault{'' if len(rows) == 1 else 's'} in {source} -> {output}")
    if rows:
        unit = next((k[len("median_throw_"):] for k in rows[0] if k.startswith("median_throw_")
                     and k != "median_throw_samples"), None)
        for r in rows[:5]:
            throw = "not measured"
            if r["median_throw_samples"]:
                throw = f"{float(r['median_throw_samples']):.1f} samples"
                if unit:
                    throw += f" ({float(r['median_throw_' + unit]):.1f} {unit})"
            where = (f"strike {r['mean_strike_deg']:>5}, dip {r['mean_dip_deg']:>4}" if "mean_strike_deg" in r else
                     f"dip {r['mean_dip_deg']:>4} toward {r['dips_toward']}")
            typer.echo(f"  fault {r['id']:>3}: {r['n_points']:>6} samples, {where}, median throw {throw}")
        if len(rows) > 5:
            typer.echo(f"  ... {len(rows) - 5} more in {pathlib.Path(job.written['summary']).name}")
    typer.echo("wrote " + ", ".join(pathlib.Path(p).name for p in job.written.values()))


@app.command()
@_friendly({"overwrite": "--overwrite", "chunk_mb": "--chunk-mb", "compression": "--compression"})
def convert(
    input: pathlib.Path = typer.Argument(..., metavar="INPUT", help="3D SEG-Y cube (inline- or crossline-sorted).",
                                         show_default=False),
    output: pathlib.Path = typer.Argument(..., metavar="OUTPUT", help="Zarr store to write, e.g. cube.zarr (its "
                                                                      "folder must exist).", show_default=False),
    iline: int = typer.Option(189, help=_ILINE_HELP),
    xline: int = typer.Option(193, help=_XLINE_HELP),
    endian: Optional[Endian] = typer.Option(None, help=_ENDIAN_HELP),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms unless they speak of depth)."),
    chunk_mb: float = typer.Option(64.0, "--chunk-mb", min=0.001, help="MiB of amplitudes read or being written at "
                                                                       "a time (the memory bound)."),
    compression: Compression = typer.Option(Compression.none, help="Compressor of the amplitudes: none (float32 "
                                            "seismic barely compresses losslessly, 1.1x on field data, and none "
                                            "converts fastest), Blosc LZ4 or Zstd."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace OUTPUT if it is a store written by "
                                                              "'seismo3d convert' (anything else is refused; an "
                                                              "output is never the input)."),
) -> None:
    """Convert the 3D SEG-Y cube INPUT into the Zarr v3 store OUTPUT that xarray.open_zarr opens as is: amplitudes
    'seismic' on dimensions inline, crossline, sample with their coordinates, cdp_x / cdp_y, every non-zero trace
    header field, and the textual and binary headers as attributes. Written chunk by chunk; an interrupted convert
    leaves no OUTPUT."""
    check_before_import("store", output, [input], overwrite=overwrite)
    from .jobs.convert import run_convert_job

    result = run_convert_job(input, output, iline=iline, xline=xline, endian=_value(endian),
                             sample_unit=None if sample_unit is None else sample_unit.value, chunk_mb=chunk_mb,
                             compression=compression.value, overwrite=overwrite, progress=True)
    typer.echo(f"converted {input.name}: {result.summary}")


@app.command()
@_friendly({"ratio": "--ratio", "threshold": "--threshold", "method": "--method"})
def match(
    image1: pathlib.Path = typer.Argument(
        ..., metavar="IMAGE1", help="First image (PNG, JPEG, TIFF, ...; colour is converted to grey)."),
    image2: pathlib.Path = typer.Argument(..., metavar="IMAGE2", help="Second image."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="CSV of verified matches: x1,y1,x2,y2,score."),
    method: MatchMethod = typer.Option(MatchMethod.hog, help="Features: HOG-pyramid or an OpenCV detector."),
    ratio: float = typer.Option(0.8, help="Lowe's ratio-test threshold."),
    threshold: float = typer.Option(3.0, help="RANSAC inlier reprojection error, pixels."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Match IMAGE1 to IMAGE2, verify with a RANSAC homography, write the matches and print the homography.

    Pixel coordinates have their origin at the centre of the top-left pixel, x to the right, y down.
    """
    check_before_import("file", output, [image1, image2], overwrite=overwrite)
    from .jobs.match import run_match_job

    job = run_match_job(image1, image2, output, method=method.value, ratio=ratio, threshold=threshold,
                        overwrite=overwrite)
    result = job.result
    typer.echo(f"{result.n_putative} putative matches, {job.n_written} verified ({method.value}) -> {output}, "
               f"{job.picture.name} (drawn), {job.homography_file.name}")
    if result.homography is None:
        typer.echo("no homography could be fitted (too few matches)")
    else:
        typer.echo("homography (image1 -> image2):")
        typer.echo(array_text(result.homography, precision=6, suppress_small=True))


@app.command()
@_friendly()
def lineaments(
    dem: pathlib.Path = typer.Argument(..., metavar="DEM", help="A GeoTIFF DEM (geographic or projected CRS)."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Output folder (created if missing)."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Extract the lineaments of DEM (linear terrain structures: escarpments, valley walls, fracture-controlled
    valleys; at the DEM's pixel and at about 200 and 400 m; nodata and flat water kept out) and write lineaments.csv
    (x0, y0, x1, y1 in the raster's CRS, azimuth_deg in [0, 180), length_m, contrast; the strongest first), rose.png
    (a length-weighted rose diagram) and lineaments.png (the lineaments over the multidirectional hillshade)."""
    check_before_import("folder", output, [dem], overwrite=overwrite)
    from .jobs.lineaments import run_lineaments_job

    with compile_note():
        result = run_lineaments_job(dem, output, overwrite=overwrite)
    found = result.lineaments
    typer.echo(f"{len(found)} lineaments in {dem.name}, {found.length_m.sum() / 1000:.1f} km in all -> {output}")
    if len(found):
        import numpy as np

        from .terrain import rose_histogram

        edges, km = rose_histogram(found, bin_deg=10.0)
        top = np.argsort(-km)[:3]
        typer.echo("strongest strikes (length-weighted): " + ", ".join(
            f"{edges[i]:.0f}-{edges[i + 1]:.0f} deg ({km[i] / 1000:.1f} km)" for i in top))
    typer.echo("wrote " + ", ".join(pathlib.Path(p).name for p in result.written.values()))


_PLAN_FLAGS = {"max_slope_deg": "--max-slope", "cell_size": "--cell-size", "robot_height": "--robot-height",
               "step_height": "--step-height", "robot_radius": "--robot-radius"}


@app.command()
@_friendly(_PLAN_FLAGS)
def plan(
    grid: pathlib.Path = typer.Argument(..., metavar="GRID", help="A GeoTIFF DEM, or the output folder of `seismo3d "
                                                                  "map` (its mesh.ply becomes an occupancy grid at "
                                                                  "the robot's height)."),
    start: str = typer.Option(..., "--start", help="Start cell ROW,COL of the grid."),
    goal: str = typer.Option(..., "--goal", help="Goal cell ROW,COL of the grid."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="CSV of the path: row,col,x,y,z per cell."),
    max_slope: float = typer.Option(15.0, "--max-slope", help="DEM: steepest traversable slope, degrees."),
    cell_size: float = typer.Option(0.05, "--cell-size", help="Map folder: grid cell, metres."),
    robot_height: float = typer.Option(0.5, "--robot-height", help="Map folder: obstacles are what stands between "
                                                                   "--step-height and this above the floor, metres."),
    step_height: float = typer.Option(0.05, "--step-height", help="Map folder: highest bump driven over, metres."),
    robot_radius: float = typer.Option(0.0, "--robot-radius", help="Map folder: obstacles grown by this, metres."),
    corner_cutting: bool = typer.Option(True, "--corner-cutting/--no-corner-cutting",
                                        help="Allow diagonal steps between two blocked cells."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Plan the shortest 8-connected path (in metres, A*) from --start to --goal through traversable cells of GRID
    and write it as CSV (row, col, x, y, z per cell: x, y in the DEM's CRS and z its elevation; for a map, the cell
    centre on the floor in the map's frame)."""
    check_before_import("file", output, [grid], overwrite=overwrite)
    from .jobs.plan import parse_cell, run_plan_job

    s = parse_cell(start, "--start")
    g = parse_cell(goal, "--goal")
    options = None
    if grid.is_dir():
        from .terrain import OccupancyOptions

        options = OccupancyOptions(cell_size=cell_size, robot_height=robot_height, step_height=step_height,
                                   robot_radius=robot_radius)
    with compile_note():
        result = run_plan_job(grid, s, g, output, max_slope_deg=max_slope, options=options,
                              corner_cutting=corner_cutting, overwrite=overwrite)
    p = result.path
    typer.echo(f"path of {len(p.cells)} cells, {p.length_m:.1f} m, from {s} to {g} on a {result.grid.shape[0]} x "
               f"{result.grid.shape[1]} grid ({result.grid.description}); A* expanded {p.n_expanded} cells in "
               f"{result.seconds:.3f} s -> {output}")


@app.command("map")
@_friendly({"max_frames": "--max-frames", "voxel_size": "--voxel-size"})
def map_(
    sequence: pathlib.Path = typer.Argument(..., help="Sequence folder: TUM RGB-D (rgb.txt, depth.txt [, associations.txt, "
                                                      "groundtruth.txt]) or 7-Scenes (frame-NNNNNN.depth.png, ...)."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Output folder (created if missing): "
                                                                      "trajectory.txt, keyframes.json, mesh.ply, "
                                                                      "map.png."),
    max_frames: Optional[int] = typer.Option(None, "--max-frames", help="Map only the first N frames."),
    loop_closure: bool = typer.Option(True, "--loop-closure/--no-loop-closure",
                                      help="Look for loops (bag of words + fused ICP) and optimise the pose graph."),
    features: bool = typer.Option(True, "--features/--no-features",
                                  help="Use ORB features (fused ICP term, landmarks, loops); off: depth only."),
    voxel_size: float = typer.Option(0.01, "--voxel-size", help="TSDF voxel edge, metres."),
    render: bool = typer.Option(True, "--render/--no-render", help="Write map.png (off-screen pyvista)."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Map an RGB-D SEQUENCE: frame-to-model fused ICP tracking, Kalman prediction, a TSDF map, keyframes and loop
    closure. Writes the trajectory (TUM format), the keyframe graph, the mesh and a picture of the map into OUTPUT.

    Ctrl-C stops the run and still writes the trajectory of the frames done and the map so far.
    """
    from dataclasses import replace

    from .errors import InputError

    check_before_import("folder", output, [sequence], overwrite=overwrite)
    from .jobs.map import run_map_job
    from .mapping import MapperOptions, TSDFOptions

    if voxel_size <= 0:
        raise InputError(f"--voxel-size must be > 0; got {voxel_size}")
    if max_frames is not None and max_frames < 1:
        raise InputError(f"--max-frames must be >= 1; got {max_frames}")
    options = MapperOptions(loop_closure=loop_closure, use_features=features)
    options = replace(options, tsdf=TSDFOptions(voxel_size=voxel_size))

    with _one_line_warnings(), compile_note():
        try:
            job = run_map_job(sequence, output, options=options, max_frames=max_frames, render=render,
                              overwrite=overwrite)
        except KeyboardInterrupt:
            typer.echo(f"interrupted: the trajectory of the frames done and the map so far are in {output}", err=True)
            raise typer.Exit(130) from None
    summary = job.summary
    typer.echo(f"{frames_tracked(summary, max_frames)}, {summary['keyframes']} keyframes, "
               f"{summary['loop_closures']} loop closures, {summary['frames_per_second']:.1f} frames/s -> {output}")
    if job.evaluation:
        ev = job.evaluation
        typer.echo(f"against the sequence's reference: ATE RMSE {100 * ev['ate_rmse_m']:.2f} cm, RPE "
                   f"{100 * ev['rpe_translation_rmse_m']:.2f} cm / {ev['rpe_rotation_rmse_deg']:.2f} deg per frame")
    typer.echo("wrote " + ", ".join(pathlib.Path(p).name for p in job.written.values()))


@app.command()
@_friendly({"polarity": "--polarity", "surface": "--surface", "sample_unit": "--sample-unit",
            "ignore_geometry": "--ignore-geometry", "faults_from": "--faults-from"})
def horizon(
    input: pathlib.Path = typer.Argument(..., metavar="INPUT", help="SEG-Y cube or 2D line (inline- or "
                                                                    "crossline-sorted, big- or little-endian; a file "
                                                                    "without inline / crossline numbers is read as a "
                                                                    "trace list)."),
    seed: list[str] = typer.Option([], "--seed", help="Seed pick IL,XL,T: inline and crossline numbers and the time "
                                                       "(or depth) in the file's sample unit; TRACE,T for a file read "
                                                       "as a trace list (trace number in file order, from 1). Repeat "
                                                       "for more seeds."),
    seed_file: Optional[pathlib.Path] = typer.Option(None, "--seed-file", help="More seeds from a file of picks: "
                                                     "'inline xline time' rows, an IRAP (.fgr, .gri) or ZMAP+ "
                                                     "(.zmap) grid or X Y Z points (.xyz), placed by the file's "
                                                     "coordinates (at most 64 picks, spread through the file)."),
    maps: bool = typer.Option(False, "--maps", help="Also write the horizon beside OUTPUT as IRAP ASCII (.fgr), "
                                                    "IRAP binary (.gri), ZMAP+ (.zmap) grids and X Y Z points (.xyz) "
                                                    "in map coordinates, through xtgeo (a 2D line: .xyz only)."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Text file: one 'inline xline time' row per "
                                                                      "tracked trace ('trace time' for a trace list)."),
    polarity: Polarity = typer.Option(Polarity.peak, help="Event the horizon follows."),
    faults: Optional[bool] = typer.Option(None, "--faults/--no-faults", help="Trace the faults first and take their "
                                          "jumps where the correlation across them supports it, so that the horizon "
                                          "steps across a fault or stops at it (the fault job on the whole input; "
                                          "seconds on a line, minutes on a large cube). Default: on, and data the "
                                          "fault tracer refuses is tracked without them (said in one line); "
                                          "--faults: a refusal is an error; --no-faults: skip them."),
    faults_from: Optional[pathlib.Path] = typer.Option(None, "--faults-from", help="The output folder of "
                                                       "'seismo3d faults' run on this INPUT: its faults are used "
                                                       "instead of being traced again (checked by its run.json)."),
    fill: bool = typer.Option(False, "--fill", help="Fill empty traces by interpolation after tracking."),
    surface: Optional[pathlib.Path] = typer.Option(None, help="Also write the horizon as a surface (.vtp or .vtk); "
                                                              "3D cubes only."),
    iline: int = typer.Option(189, help=_ILINE_HELP),
    xline: int = typer.Option(193, help=_XLINE_HELP),
    endian: Optional[Endian] = typer.Option(None, help=_ENDIAN_HELP),
    ignore_geometry: bool = typer.Option(False, "--ignore-geometry", help="Read the SEG-Y as a trace list (unsorted "
                                                                          "file, arbitrary line); seeds are TRACE,T."),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms)."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Track a horizon in INPUT (a 3D cube or a 2D line) from one or more seed picks, globally (least squares over
    correlations between near and distant traces, then the picks by dynamic programming along inlines and crosslines),
    and write it as 'inline xline time' rows ('trace time' for a trace list)."""
    from .errors import InputError

    check_before_import("file", output, [input, seed_file], overwrite=overwrite,
                        also=surface and output_file(surface))
    from .jobs.horizon import run_horizon_job

    seeds = []
    for text in seed:
        try:
            seeds.append(tuple(float(v) for v in text.split(",")))
        except ValueError:
            seeds.append(())
        if len(seeds[-1]) not in (2, 3):
            raise InputError(f"--seed {text!r} must be IL,XL,T (three numbers separated by commas), or TRACE,T for a "
                             "file read as a trace list")
    with compile_note():
        job = run_horizon_job(input, seeds, output, polarity=polarity.value, faults=faults, fill=fill,
                              surface=surface, iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                              endian=_value(endian), sample_unit=None if sample_unit is None else sample_unit.value,
                              overwrite=overwrite, progress=True, seed_file=seed_file, maps=maps,
                              faults_from=faults_from)
    typer.echo(f"{job.n_rows} of {job.horizon.times.size} traces tracked ({job.horizon.coverage:.1%}) -> {output}")
    if job.surface is not None:
        typer.echo(f"surface -> {job.surface}")
    for path in (job.maps or {}).values():
        typer.echo(f"map -> {path}")


@app.command()
@_friendly({"vertical_exaggeration": "--vertical-exaggeration", "seismic": "--seismic", "color_by": "--color-by",
            "window_size": "--size", "plan": "--path", "endian": "--endian", "iline": "--iline",
            "xline": "--xline"})
def render(
    input: pathlib.Path = typer.Argument(
        ..., metavar="INPUT", help="A SEG-Y cube, the output folder of 'seismo3d faults' or 'seismo3d map', a "
                                   "horizon file ('inline xline time' rows) or a GeoTIFF DEM."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="The PNG to write."),
    seismic: Optional[pathlib.Path] = typer.Option(None, help="SEG-Y cube drawn under faults or a horizon; default: "
                                                              "the run's input recorded in its run.json, read with "
                                                              "the run's SEG-Y flags, while unchanged (a faults "
                                                              "folder from --demo: its demo_seismic.sgy)."),
    color_by: FaultColour = typer.Option(FaultColour.fault_id, help="Colour of the faults (surfaces in 3D, lines on "
                                                                    "a section): by id, or by the throw measured "
                                                                    "along them."),
    sticks: Optional[pathlib.Path] = typer.Option(None, "--sticks", help="Fault sticks to draw over the seismic "
                                                  "(OpendTect fault-stick ASCII or Charisma fault sticks), e.g. an "
                                                  "interpreter's, placed by the drawn SEG-Y's line numbers and "
                                                  "coordinates."),
    vertical_exaggeration: Optional[float] = typer.Option(
        None, help="Vertical exaggeration; default: the cube's height is half its longer side."),
    size: str = typer.Option("1200x900", help="Picture size WIDTHxHEIGHT in pixels."),
    lineaments: bool = typer.Option(False, "--lineaments", help="DEM: extract its lineaments and draw them."),
    plan: Optional[pathlib.Path] = typer.Option(None, "--path", help="DEM: the CSV of 'seismo3d plan' to draw."),
    iline: int = typer.Option(189, help=_ILINE_HELP),
    xline: int = typer.Option(193, help=_XLINE_HELP),
    endian: Optional[Endian] = typer.Option(None, help=_ENDIAN_HELP),
    ignore_geometry: bool = typer.Option(False, "--ignore-geometry", help="Read the SEG-Y as a trace list (unsorted "
                                                                          "file, arbitrary line): draw one section."),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms unless they speak of depth)."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Render INPUT off screen (no display needed) into a PNG: a cube's inline, crossline and time slices, faults
    coloured by id or throw with the fault likelihood as a semi-transparent volume, a horizon coloured by time, an
    RGB-D map (mesh, trajectory, keyframes), or a DEM coloured by elevation with its lineaments and a planned path."""
    from .errors import InputError

    check_before_import("file", output, [input, seismic, plan, sticks], overwrite=overwrite)
    from .jobs.render import run_render_job

    try:
        width, height = (int(v) for v in size.lower().split("x"))
    except ValueError:
        raise InputError(f"--size {size!r} must be WIDTHxHEIGHT, e.g. 1200x900") from None
    with _one_line_warnings(), compile_note():
        job = run_render_job(input, output, seismic=seismic, color_by=color_by.value,
                             vertical_exaggeration=vertical_exaggeration, lineaments=lineaments, plan=plan,
                             window_size=(width, height), iline=iline, xline=xline, endian=_value(endian),
                             ignore_geometry=ignore_geometry, sample_unit=_value(sample_unit), overwrite=overwrite,
                             sticks=sticks)
    what = {"segy": "SEG-Y line" if job.section else "SEG-Y cube",
            "faults": f"{job.n_faults} fault{'' if job.n_faults == 1 else 's'}", "horizon": "horizon",
            "dem": f"DEM with {job.n_lineaments} lineaments" if lineaments else "DEM", "map": "map"}[job.kind]
    sticks_drawn = f" and the --sticks file's {job.n_stick_faults} faults" if job.n_stick_faults else ""
    typer.echo(f"{what}{sticks_drawn} of {input.name}: {job.caption} -> {job.picture}")


@app.command()
@_friendly({"sticks": "--sticks", "mask": "--mask", "seismic": "--seismic", "tolerance": "--tolerance"})
def evaluate(
    faults_output: pathlib.Path = typer.Argument(..., metavar="OUTPUT", help="The output folder of 'seismo3d faults' "
                                                 "on one seismic line (an inline or crossline)."),
    sticks: Optional[pathlib.Path] = typer.Option(None, "--sticks", help="People's fault sticks: OpendTect ASCII, "
                                                  "Charisma or IESX (sticks of other lines are left out)."),
    mask: Optional[pathlib.Path] = typer.Option(None, "--mask", help="People's faults as a mask of the line, nonzero "
                                                "(or alpha > 0) on faults: .npy (n_traces, n_samples), or a PNG of "
                                                "a row per sample and a column per trace."),
    output: Optional[pathlib.Path] = typer.Option(None, "-o", "--output", help="Folder of the evaluation (created if "
                                                  "missing); default OUTPUT/evaluation."),
    tolerance: float = typer.Option(3.0, min=0.0, help="Samples (a trace = a sample) within which faults match."),
    seismic: Optional[pathlib.Path] = typer.Option(None, help="The line the faults were traced on; default: the "
                                                   "input run.json records, while unchanged."),
    overwrite: bool = _overwrite_option(),
) -> None:
    """Score the faults a 'seismo3d faults' run traced on a line against people's (--sticks or --mask), placed by the
    SEG-Y headers: tolerant precision, recall and F1, fault-by-fault matches, the precision-recall curve over the
    faults' confidence; evaluation.csv, evaluation.json, evaluation.png."""
    out = output if output is not None else faults_output / "evaluation"
    check_before_import("folder", out, [faults_output, sticks, mask, seismic], overwrite=overwrite)
    from .jobs.evaluate import evaluation_table, run_evaluate_job
    from .seismic.fault_scoring import FaultScoringOptions

    job = run_evaluate_job(faults_output, sticks=sticks, mask=mask, out=out, seismic=seismic,
                           options=FaultScoringOptions(tolerance=tolerance), overwrite=overwrite)
    typer.echo("\n".join(evaluation_table(job) + [f"wrote evaluation.csv, evaluation.json, evaluation.png -> {out}"]))


@app.command()
@_friendly({"picks": "--sticks / --mask", "model": "-o"})
def adapt(
    inputs: list[pathlib.Path] = typer.Argument(..., metavar="INPUT...", show_default=False, help="The picked lines: "
                                                "SEG-Y inlines or crosslines, .npy (traces, samples) or .f32be; or a "
                                                "3D SEG-Y cube with one --sticks file picked on some of its lines."),
    sticks: Optional[list[pathlib.Path]] = typer.Option(None, "--sticks", show_default=False, help="Fault sticks of "
                                                        "the i-th INPUT (OpendTect, Charisma, IESX); once: of all. "
                                                        "On a cube, each stick on one of its inlines or crosslines."),
    mask: Optional[list[pathlib.Path]] = typer.Option(None, "--mask", show_default=False, help="Faults of the i-th "
                                                      "INPUT, a line: .npy (traces, samples) or PNG (a row per "
                                                      "sample)."),
    model: pathlib.Path = typer.Option(..., "-o", "--output", show_default=False, help="The MODEL folder to write "
                                       "(must not exist); trace with 'seismo3d faults --model MODEL'."),
    iline: int = typer.Option(189, help=_ILINE_HELP),
    xline: int = typer.Option(193, help=_XLINE_HELP),
    endian: Optional[Endian] = typer.Option(None, help=_ENDIAN_HELP),
    steps: int = typer.Option(100, min=1, help="Training steps (4 patches each, seed 0)."),
) -> None:
    """Adapt the fault network to your survey from an interpreter's faults on a few lines; write MODEL.

    Each picked line is taken as fully interpreted: a sample away from the drawn faults is taught as no fault, so
    pick every fault of a line you pass. A 3D cube with one --sticks file: the inlines and crosslines its sticks lie
    on (placed by their inline / crossline numbers, or by X / Y through the cube's coordinates) are taken out of it
    and learned from as picked lines; a stick on no single line of the cube, between its lines or outside it is
    refused, and so is a line of fewer than 32 traces or 32 samples (what fault tracing needs). Picks are held back
    (the line with the fewest when several are picked, else a quarter of the line's traces): the F1 there with the
    shipped and the adapted network is printed, and MODEL keeps the shipped one unless the adapted one scores
    higher there and on most quarters of the held-back traces that hold picks. The adapted network is scored there with and without the tracing's drop of faults across which the
    reflectors continue unbroken (faults you draw where reflectors dim without a throw), and MODEL records the
    better. Needs PyTorch and onnx (pip install torch onnx, or the train extra); tracing does not."""
    check_before_import("folder", model, [*inputs, *(sticks or []), *(mask or [])], overwrite=False)
    from .jobs.adapt import adapt_report, paired_picks, run_adapt_job

    with compile_note():
        job = run_adapt_job(inputs, paired_picks(sticks, mask), model, iline=iline, xline=xline,
                            endian=_value(endian), steps=steps, progress=True)
    typer.echo("\n".join(adapt_report(job)))


if __name__ == "__main__":  # pragma: no cover
    app()
