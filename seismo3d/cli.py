"""The ``seismo3d`` command: thin wrappers over the library's functions.

Errors of seismo3d's own types are printed as one line (problem + fix) with exit code 2; anything else is a bug and
keeps its traceback.
"""

from __future__ import annotations

import functools
import json
import pathlib
from enum import Enum
from typing import Optional

import numpy as np
import typer

from .errors import InputError, SegyGeometryError, Seismo3dError

app = typer.Typer(help="seismo3d: fault and horizon interpretation of seismic cubes, and point-cloud / RGB-D "
                       "registration, on one fused-ICP engine.", no_args_is_help=True, add_completion=False)


@app.callback()
def _main() -> None:
    """seismo3d: fault and horizon interpretation of seismic cubes, and point-cloud / RGB-D registration."""


class Method(str, Enum):
    point_to_point = "point_to_point"
    point_to_plane = "point_to_plane"
    fused = "fused"


class Model(str, Enum):
    rigid = "rigid"
    similarity = "similarity"
    axis_scaled = "axis_scaled"
    affine = "affine"


def _friendly(fn):
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except Seismo3dError as exc:
            typer.echo(f"error: {exc}", err=True)
            raise typer.Exit(2) from None
        except KeyboardInterrupt:
            typer.echo("interrupted: finished outputs were kept, unfinished ones were not written", err=True)
            raise typer.Exit(130) from None

    return wrapper


def _write_json(path: pathlib.Path, payload: dict) -> None:
    from ._atomic import atomic_path

    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(payload, indent=2) + "\n")


def _read_transform(path: pathlib.Path, dim: int) -> np.ndarray:
    from .geometry.transforms import as_transform

    try:
        payload = json.loads(pathlib.Path(path).read_text())
    except FileNotFoundError as exc:
        raise InputError(f"--init file {path} does not exist") from exc
    except json.JSONDecodeError as exc:
        raise InputError(f"--init file {path} is not JSON ({exc}); write {{\"transform\": [[...], ...]}}") from exc
    matrix = payload.get("transform") if isinstance(payload, dict) else payload
    return as_transform(matrix, f"the transform in {path}", dims=(dim,))


@app.command()
@_friendly
def register(
    source: pathlib.Path = typer.Argument(..., help="Source point cloud (.ply, .xyz/.txt/.csv, .npy): moved. For "
                                                    "SEG-Y (.sgy/.segy): the FIXED cube."),
    target: pathlib.Path = typer.Argument(..., help="Target point cloud: fixed. For SEG-Y: the MOVING cube."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Where to write the transform JSON."),
    method: Method = typer.Option(Method.point_to_plane, help="Residual: point-to-point, point-to-plane or fused "
                                                               "(features + point-to-plane, eq. 16)."),
    model: Optional[Model] = typer.Option(None, help="Transform family; default rigid for point clouds, axis_scaled "
                                                     "for SEG-Y cubes."),
    init: Optional[pathlib.Path] = typer.Option(None, help="JSON with an initial source-to-target transform."),
    max_distance: Optional[list[float]] = typer.Option(
        None, help="Maximum correspondence distance (repeat for a coarse-to-fine schedule); default: 10/3/1 % of "
                   "the target's bounding-box diagonal."),
    features: Optional[pathlib.Path] = typer.Option(
        None, help="For --method fused: matched feature points, one row per match: source coordinates then target "
                   "coordinates (.csv/.txt/.npy with 2d columns)."),
    alpha: float = typer.Option(0.1, help="For --method fused: weight of the feature term in [0, 1]."),
) -> None:
    """Register SOURCE onto TARGET and write the (d+1)x(d+1) transform mapping source into target coordinates.

    For two SEG-Y cubes the order is FIXED MOVING (the reference first, as in `seismo3d register BASE.sgy
    MONITOR.sgy`): sub-volumes of different bin size, sample rate or map orientation are registered with
    register_volumes (--model rigid, axis_scaled or affine); the JSON holds the 4x4 transforms from MOVING's
    inline / crossline / sample indices to FIXED's, and between physical units (m, m, ms or m), the scales, the map
    rotation, fitness and inlier RMSE."""
    if _is_segy(source) or _is_segy(target):
        _register_volumes(source, target, output, model or Model.axis_scaled)
        return
    model = model or Model.rigid
    from .data.pointclouds import read_points
    from .geometry import estimate_normals
    from .registration import fused_icp, icp

    src = read_points(source)
    dst = read_points(target)
    if src.shape[1] != dst.shape[1]:
        raise InputError(f"{source} is {src.shape[1]}D but {target} is {dst.shape[1]}D")
    start = None if init is None else _read_transform(init, src.shape[1])
    common = dict(model=model.value, init=start, max_distance=max_distance or None)
    normals = None
    if method is not Method.point_to_point:
        normals = estimate_normals(dst, orient="none")
    if method is Method.fused:
        if features is None:
            raise InputError("--method fused needs --features MATCHES (rows of source then target coordinates of "
                             "matched features, e.g. from `seismo3d match` lifted to 3D)")
        pairs = _read_matches(features, src.shape[1])
        result = fused_icp(src, dst, target_normals=normals, source_features=pairs[:, : src.shape[1]],
                           target_features=pairs[:, src.shape[1]:], alpha=alpha, **common)
    else:
        result = icp(src, dst, method=method.value, target_normals=normals, **common)
    payload = result.to_dict()
    payload.update(method=method.value, model=model.value, source=str(source), target=str(target))
    _write_json(output, payload)
    typer.echo(f"fitness {result.fitness:.3f}  inlier RMSE {result.inlier_rmse:.4g}  iterations {result.n_iterations}"
               f"  converged {result.converged}" + ("  (DEGENERATE geometry)" if result.degenerate else ""))
    typer.echo(np.array2string(result.transform, precision=6, suppress_small=True))


def _is_segy(path: pathlib.Path) -> bool:
    return path.suffix.lower() in (".sgy", ".segy")


def _register_volumes(fixed_path: pathlib.Path, moving_path: pathlib.Path, output: pathlib.Path, model) -> None:
    """`seismo3d register FIXED.sgy MOVING.sgy`: sub-volume registration, JSON with both transforms."""
    from .seismic import open_segy, register_volumes
    from .seismic.volumes import VOLUME_MODELS

    if not (_is_segy(moving_path) and _is_segy(fixed_path)):
        raise InputError(f"{fixed_path} and {moving_path}: register either two SEG-Y cubes or two point clouds, not "
                         "one of each")
    if model.value not in VOLUME_MODELS:
        raise InputError(f"--model {model.value} is not available for SEG-Y volumes; use rigid (spacings from the "
                         "headers are right), axis_scaled (default for unknown bins / sample rates) or affine")
    with open_segy(fixed_path) as fixed, open_segy(moving_path) as moving:
        first_f = (int(fixed.inlines[0]), int(fixed.xlines[0]), float(fixed.samples[0]))
        first_m = (int(moving.inlines[0]), int(moving.xlines[0]), float(moving.samples[0]))
        reg = register_volumes(fixed, moving, model=model.value, progress=True)
    payload = reg.to_dict()
    payload.update(model=model.value, moving=str(moving_path), fixed=str(fixed_path),
                   index_axes=["inline", "crossline", "sample"],
                   fixed_first=dict(zip(("inline", "xline", "sample_value"), first_f)),
                   moving_first=dict(zip(("inline", "xline", "sample_value"), first_m)))
    _write_json(output, payload)
    typer.echo(f"map rotation {reg.rotation_deg:.2f} deg  scales {np.array2string(reg.scales, precision=4)}  "
               f"fitness {reg.fitness:.3f}  inlier RMSE {reg.inlier_rmse:.3g}  correlation {reg.correlation:.3f}")
    typer.echo(np.array2string(reg.transform_index, precision=4, suppress_small=True))


class SampleUnit(str, Enum):
    ms = "ms"
    m = "m"
    ft = "ft"


@app.command()
@_friendly
def faults(
    input: Optional[pathlib.Path] = typer.Argument(
        None, help="SEG-Y cube or 2D line, raw .f32be section or .npy array; omit with --demo.", show_default=False),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Output folder (created if missing); not the "
                                                                      "input's own folder."),
    demo: bool = typer.Option(False, "--demo", help="Run on a generated 128^3 cube with 3 faults (no input file)."),
    seed: int = typer.Option(0, help="Seed of the --demo cube."),
    iline: int = typer.Option(189, help="Trace header byte of the inline number (SEG-Y)."),
    xline: int = typer.Option(193, help="Trace header byte of the crossline number (SEG-Y)."),
    ignore_geometry: bool = typer.Option(False, "--ignore-geometry", help="Read the SEG-Y as a trace list (unsorted "
                                                                          "file, arbitrary line): trace a 2D section."),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms unless they speak of depth)."),
    n_samples: Optional[int] = typer.Option(None, help="Samples per trace of a raw .f32be section of unknown shape."),
) -> None:
    """Trace the faults of INPUT and write fault likelihood, strike and dip (SEG-Y for SEG-Y input), fault surfaces
    (faults.vtp), fault points and a per-fault summary (CSV) and a picture (faults.png) into OUTPUT."""
    import csv
    import warnings

    from .seismic.job import run_faults_job

    def one_line(message, category, filename, lineno, file=None, line=None):
        typer.echo(f"warning: {message}", err=True)

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = one_line
        try:
            written = run_faults_job(input, output, demo=demo, seed=seed, iline=iline, xline=xline,
                                     ignore_geometry=ignore_geometry,
                                     sample_unit=None if sample_unit is None else sample_unit.value,
                                     n_samples=n_samples, progress=True)
        except SegyGeometryError as exc:
            raise SegyGeometryError(f"{exc} On the command line: --ignore-geometry, or --iline BYTE --xline "
                                    "BYTE.") from None
    with open(written["summary"], newline="") as fh:
        rows = list(csv.DictReader(fh))
    source = "the demo cube" if demo else input.name
    typer.echo(f"{len(rows)} faults in {source} -> {output}")
    if rows:
        unit = next((k[len("median_throw_"):] for k in rows[0] if k.startswith("median_throw_")
                     and k != "median_throw_samples"), None)
        for r in rows[:5]:
            throw = "not measured"
            if r["median_throw_samples"]:
                throw = f"{float(r['median_throw_samples']):.1f} samples"
                if unit:
                    throw += f" ({float(r['median_throw_' + unit]):.1f} {unit})"
            typer.echo(f"  fault {r['id']:>3}: {r['n_points']:>6} samples, strike {r['mean_strike_deg']:>5}, "
                       f"dip {r['mean_dip_deg']:>4}, median throw {throw}")
        if len(rows) > 5:
            typer.echo(f"  ... {len(rows) - 5} more in {pathlib.Path(written['summary']).name}")
    typer.echo("wrote " + ", ".join(pathlib.Path(p).name for p in written.values()))


class MatchMethod(str, Enum):
    hog = "hog"
    sift = "sift"
    orb = "orb"
    akaze = "akaze"
    brisk = "brisk"


@app.command()
@_friendly
def match(
    image1: pathlib.Path = typer.Argument(..., help="First image (PNG, JPEG, TIFF, ...; colour is converted to grey)."),
    image2: pathlib.Path = typer.Argument(..., help="Second image."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="CSV of verified matches: x1,y1,x2,y2,score."),
    method: MatchMethod = typer.Option(MatchMethod.hog, help="Features: HOG-pyramid or an OpenCV detector."),
    ratio: float = typer.Option(0.8, help="Lowe's ratio-test threshold."),
    threshold: float = typer.Option(3.0, help="RANSAC inlier reprojection error, pixels."),
) -> None:
    """Match IMAGE1 to IMAGE2, verify with a RANSAC homography, write the matches and print the homography.

    Pixel coordinates have their origin at the centre of the top-left pixel, x to the right, y down.
    """
    from .features import match_images, write_matches_csv

    images = [_read_image(p) for p in (image1, image2)]
    result = match_images(*images, method=method.value, ratio=ratio, threshold=threshold, verify="homography")
    n = write_matches_csv(output, result)
    typer.echo(f"{result.n_putative} putative matches, {n} verified ({method.value}) -> {output}")
    if result.homography is None:
        typer.echo("no homography could be fitted (too few matches)")
    else:
        typer.echo("homography (image1 -> image2):")
        typer.echo(np.array2string(result.homography, precision=6, suppress_small=True))


@app.command("map")
@_friendly
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
) -> None:
    """Map an RGB-D SEQUENCE: frame-to-model fused ICP tracking, Kalman prediction, a TSDF map, keyframes and loop
    closure. Writes the trajectory (TUM format), the keyframe graph, the mesh and a picture of the map into OUTPUT.

    Ctrl-C stops the run and still writes the trajectory of the frames done and the map so far.
    """
    import warnings
    from dataclasses import replace

    from .jobs.map import run_map_job
    from .mapping import MapperOptions, TSDFOptions

    if voxel_size <= 0:
        raise InputError(f"--voxel-size must be > 0; got {voxel_size}")
    if max_frames is not None and max_frames < 1:
        raise InputError(f"--max-frames must be >= 1; got {max_frames}")
    options = MapperOptions(loop_closure=loop_closure, use_features=features)
    options = replace(options, tsdf=TSDFOptions(voxel_size=voxel_size))

    def one_line(message, category, filename, lineno, file=None, line=None):
        typer.echo(f"warning: {message}", err=True)

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = one_line
        try:
            written = run_map_job(sequence, output, options=options, max_frames=max_frames, render=render)
        except KeyboardInterrupt:
            typer.echo(f"interrupted: the trajectory of the frames done and the map so far are in {output}", err=True)
            raise typer.Exit(130) from None
    summary = written["summary"]
    typer.echo(f"{summary['frames_tracked']} of {summary['frames_in_sequence']} frames tracked, "
               f"{summary['keyframes']} keyframes, {summary['loop_closures']} loop closures, "
               f"{summary['frames_per_second']:.1f} frames/s -> {output}")
    if summary.get("evaluation"):
        ev = summary["evaluation"]
        typer.echo(f"against the sequence's reference: ATE RMSE {100 * ev['ate_rmse_m']:.2f} cm, RPE "
                   f"{100 * ev['rpe_translation_rmse_m']:.2f} cm / {ev['rpe_rotation_rmse_deg']:.2f} deg per frame")
    typer.echo("wrote " + ", ".join(pathlib.Path(p).name for k, p in written.items() if k != "summary"))


class Polarity(str, Enum):
    peak = "peak"
    trough = "trough"
    zero_rising = "zero_rising"
    zero_falling = "zero_falling"


@app.command()
@_friendly
def horizon(
    input: pathlib.Path = typer.Argument(..., help="SEG-Y cube (inline-sorted or crossline-sorted)."),
    seed: list[str] = typer.Option(..., "--seed", help="Seed pick IL,XL,T: inline and crossline numbers and the time "
                                                       "(or depth) in the cube's sample unit; repeat for more seeds."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Text file: one 'inline xline time' row per "
                                                                      "tracked trace."),
    polarity: Polarity = typer.Option(Polarity.peak, help="Event the horizon follows."),
    faults: bool = typer.Option(False, "--faults", help="Trace the faults first and jump across them by their throw "
                                                        "(slower: the whole fault job runs in memory)."),
    fill: bool = typer.Option(False, "--fill", help="Fill empty traces by interpolation after tracking."),
    surface: Optional[pathlib.Path] = typer.Option(None, help="Also write the horizon as a surface (.vtp or .vtk)."),
    iline: int = typer.Option(189, help="Trace header byte of the inline number."),
    xline: int = typer.Option(193, help="Trace header byte of the crossline number."),
) -> None:
    """Track a horizon in INPUT from one or more seed picks by registering neighbouring inlines, and write it as
    'inline xline time' rows."""
    from .seismic import fill_horizon, open_segy, trace_faults, track_horizon, write_horizon_text

    if output.resolve() == input.resolve() or (surface is not None and surface.resolve() == input.resolve()):
        raise InputError(f"{output} would overwrite the input; choose another output path")
    with open_segy(input, iline=iline, xline=xline) as cube:
        if not cube.is_3d:
            raise SegyGeometryError(f"{input} is not a 3D cube with inline/crossline geometry; horizon tracking "
                                    "needs one (check --iline/--xline header bytes)")
        data = cube.read()
        inlines, xlines, samples = cube.inlines, cube.xlines, cube.samples
        unit = cube.sample_unit
    seeds = [_parse_seed(s, inlines, xlines, samples, unit) for s in seed]
    interp = trace_faults(data, sample_interval=float(samples[1] - samples[0]), sample_unit=unit) if faults else None
    result = track_horizon(data, seeds, polarity=polarity.value, faults=interp, progress=True)
    if fill:
        result = fill_horizon(result)
    n = write_horizon_text(output, result, inlines=inlines, xlines=xlines, samples=samples)
    typer.echo(f"{n} of {result.times.size} traces tracked ({result.coverage:.1%}) -> {output}")
    if surface is not None:
        from .viz import horizon_surface, save_polydata

        save_polydata(horizon_surface(result, inlines=inlines, xlines=xlines, samples=samples), surface)
        typer.echo(f"surface -> {surface}")


def _parse_seed(text: str, inlines, xlines, samples, unit: str) -> tuple[float, float, float]:
    """'IL,XL,T' (line numbers and time/depth) -> (inline index, xline index, fractional sample index)."""
    try:
        il, xl, t = (float(v) for v in text.split(","))
    except ValueError:
        raise InputError(f"--seed {text!r} must be IL,XL,T (three numbers separated by commas)") from None
    where = []
    for name, value, labels in (("inline", il, inlines), ("crossline", xl, xlines)):
        hit = np.nonzero(np.asarray(labels) == value)[0]
        if hit.size == 0:
            raise InputError(f"--seed {text}: {name} {value:g} is not in the cube ({name}s {labels[0]}..{labels[-1]})")
        where.append(float(hit[0]))
    s = np.asarray(samples, dtype=np.float64)
    if not s[0] <= t <= s[-1]:
        raise InputError(f"--seed {text}: time {t:g} {unit} is outside the cube's samples ({s[0]:g}..{s[-1]:g} {unit})")
    return where[0], where[1], float(np.interp(t, s, np.arange(s.size)))


def _read_image(path: pathlib.Path) -> np.ndarray:
    import cv2

    from .errors import DataNotFoundError

    if not path.is_file():
        raise DataNotFoundError(f"{path}: no such file; check the path")
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise InputError(f"{path} is not an image OpenCV can read (PNG, JPEG, TIFF, BMP, PPM/PGM)")
    if image.ndim == 3:
        image = cv2.cvtColor(image, cv2.COLOR_BGRA2RGB if image.shape[2] == 4 else cv2.COLOR_BGR2RGB)
    return image


def _read_matches(path: pathlib.Path, dim: int) -> np.ndarray:
    if path.suffix == ".npy":
        table = np.load(path, allow_pickle=False)
    else:
        table = np.loadtxt(path, delimiter="," if path.suffix == ".csv" else None, ndmin=2, comments="#")
    if table.ndim != 2 or table.shape[1] != 2 * dim:
        raise InputError(f"{path} must have {2 * dim} columns (source then target coordinates); got {table.shape}")
    return table


if __name__ == "__main__":  # pragma: no cover
    app()
