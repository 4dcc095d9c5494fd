"""The ``seismo3d`` command: thin typer wrappers over the jobs (:mod:`seismo3d.jobs`, one per command).

Conventions, the same for every command:

- ``seismo3d --version`` prints the version.
- Registrations read ``SOURCE TARGET``: the first file is moved onto the second (for SEG-Y cubes: ``MOVING FIXED``).
- Errors of seismo3d's own types are printed as one line (problem + fix, naming the command's flags) with exit code 2;
  a registration that did not converge writes its result, says so in one line and exits with 1; Ctrl-C exits with
  130. Anything else is a bug and keeps its traceback.
- Progress goes to standard error: a bar on a terminal, one line per step otherwise (logs, CI).
"""

from __future__ import annotations

import contextlib
import functools
import logging
import pathlib
import re
import sys
import warnings
from enum import Enum
from typing import Optional

import numpy as np
import typer

from . import __version__
from .errors import SegyGeometryError, Seismo3dError

app = typer.Typer(help="seismo3d: fault and horizon interpretation of seismic cubes, and point-cloud / RGB-D "
                       "registration, on one fused-ICP engine.", no_args_is_help=True, add_completion=False)

NOT_CONVERGED = 1  # exit code of a registration that did not converge (its result is written)


class _StderrHandler(logging.Handler):
    """Log records as plain lines on the current standard error (progress lines of long steps)."""

    def emit(self, record):
        try:
            sys.stderr.write(self.format(record) + "\n")
            sys.stderr.flush()
        except (ValueError, OSError):  # pragma: no cover - stderr closed
            pass


def _log_progress_to_stderr() -> None:
    logger = logging.getLogger("seismo3d")
    if not any(isinstance(h, _StderrHandler) for h in logger.handlers):
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter("%(message)s"))
        logger.addHandler(handler)
    logger.setLevel(logging.INFO)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"seismo3d {__version__}")
        raise typer.Exit()


@app.callback()
def _main(version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="Print the version and exit.")) -> None:
    """seismo3d: fault and horizon interpretation of seismic cubes, and point-cloud / RGB-D registration."""
    _log_progress_to_stderr()


_WORDS = {"init"}  # argument names that are no common English word: translated wherever they stand alone


def _in_flags(message: str, flags: dict) -> str:
    """A library message in the command's terms: ``max_distance=0.1`` -> ``--max-distance 0.1``, ``max_distance``
    -> ``--max-distance`` (names without an underscore, such as ``model``, only when followed by ``=``)."""
    for name, flag in flags.items():
        message = re.sub(rf"(?<![\w-]){name}=", f"{flag} ", message)
        if "_" in name or name in _WORDS:
            message = re.sub(rf"(?<![\w-]){name}\b", flag, message)
    return message


@contextlib.contextmanager
def _one_line_warnings():
    """Warnings as one line each on standard error (``warning: ...``), not Python's two-line format."""

    def one_line(message, category, filename, lineno, file=None, line=None):
        typer.echo(f"warning: {message}", err=True)

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = one_line
        yield


def _friendly(flags: dict | None = None):
    """Seismo3d's errors as one line with exit code 2 (library argument names replaced by ``flags``); Ctrl-C as one
    line with exit code 130."""
    flags = flags or {}

    def decorate(fn):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            try:
                return fn(*args, **kwargs)
            except Seismo3dError as exc:
                typer.echo(f"error: {_in_flags(str(exc), flags)}", err=True)
                raise typer.Exit(2) from None
            except KeyboardInterrupt:
                typer.echo("interrupted: finished outputs were kept, unfinished ones were not written", err=True)
                raise typer.Exit(130) from None

        return wrapper

    return decorate


class Method(str, Enum):
    point_to_point = "point_to_point"
    point_to_plane = "point_to_plane"
    fused = "fused"


class Model(str, Enum):
    rigid = "rigid"
    similarity = "similarity"
    axis_scaled = "axis_scaled"
    affine = "affine"


_REGISTER_FLAGS = {"max_distance": "--max-distance", "init": "--init", "alpha": "--alpha", "model": "--model",
                   "method": "--method", "source_features": "--features", "target_features": "--features"}


@app.command()
@_friendly(_REGISTER_FLAGS)
def register(
    source: pathlib.Path = typer.Argument(
        ..., metavar="SOURCE", help="SOURCE, moved onto TARGET: a point cloud (.ply, .xyz/.txt/.csv, .npy) or the "
                                    "MOVING SEG-Y cube (.sgy/.segy)."),
    target: pathlib.Path = typer.Argument(
        ..., metavar="TARGET", help="TARGET, kept fixed: a point cloud or the FIXED SEG-Y cube."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Where to write the transform JSON."),
    method: Method = typer.Option(Method.point_to_plane, help="Point clouds: point-to-point, point-to-plane or fused "
                                                               "(features + point-to-plane, eq. 16)."),
    model: Optional[Model] = typer.Option(None, help="Transform family; default rigid for point clouds, axis_scaled "
                                                     "for SEG-Y cubes."),
    init: Optional[pathlib.Path] = typer.Option(None, help="Point clouds: JSON with an initial source-to-target "
                                                           "transform."),
    max_distance: Optional[list[float]] = typer.Option(
        None, help="Point clouds: maximum correspondence distance (repeat for a coarse-to-fine schedule); default: "
                   "10/3/1 % of the target's bounding-box diagonal."),
    features: Optional[pathlib.Path] = typer.Option(
        None, help="For --method fused: matched feature points, one row per match: source coordinates then target "
                   "coordinates (.csv/.txt/.npy with 2d columns)."),
    alpha: float = typer.Option(0.1, help="For --method fused: weight of the feature term in [0, 1]."),
) -> None:
    """Register SOURCE onto TARGET and write the transform mapping SOURCE's coordinates into TARGET's.

    Point clouds: the JSON holds the (d+1)x(d+1) matrix under "transform" plus fitness, inlier_rmse, n_iterations,
    converged. Two SEG-Y cubes (`seismo3d register MOVING.sgy FIXED.sgy`): sub-volumes of different bin size, sample
    rate or map orientation are registered with register_volumes (--model rigid, axis_scaled or affine); the JSON
    holds the 4x4 transforms from MOVING's inline / crossline / sample indices to FIXED's (transform_index) and
    between physical units (transform_physical: m, m, ms or m), the scales, the map rotation, fitness, inlier RMSE,
    correlation and converged. A registration that did not converge is written, reported and exits with 1."""
    from .jobs.register import run_register_job

    with _one_line_warnings():
        job = run_register_job(source, target, output, method=method.value,
                               model=None if model is None else model.value, init=init,
                               max_distance=max_distance or None, features=features, alpha=alpha, progress=True)
    if job.kind == "volumes":
        reg = job.result
        typer.echo(f"map rotation {reg.rotation_deg:.2f} deg  scales {np.array2string(reg.scales, precision=4)}  "
                   f"fitness {reg.fitness:.3f}  inlier RMSE {reg.inlier_rmse:.3g}  correlation {reg.correlation:.3f}")
        typer.echo(np.array2string(reg.transform_index, precision=4, suppress_small=True))
    else:
        result = job.result
        typer.echo(f"fitness {result.fitness:.3f}  inlier RMSE {result.inlier_rmse:.4g}  iterations "
                   f"{result.n_iterations}  converged {result.converged}"
                   + ("  (DEGENERATE geometry)" if result.degenerate else ""))
        typer.echo(np.array2string(result.transform, precision=6, suppress_small=True))
    if not job.converged:
        if job.kind == "volumes":
            why = ("the correlation polish stopped on its evaluation limit; check that the cubes overlap and their "
                   "spacings")
        elif job.result.degenerate:
            why = ("the geometry does not constrain every degree of freedom (a plane slides in itself); add "
                   "--features with --method fused")
        else:
            why = "it stopped on its iteration limit; check the overlap, or pass a closer --init"
        typer.echo(f"error: the registration did not converge ({why}); its last estimate was written to {output}",
                   err=True)
        raise typer.Exit(NOT_CONVERGED)


class SampleUnit(str, Enum):
    ms = "ms"
    m = "m"
    ft = "ft"


@app.command()
@_friendly({"sample_unit": "--sample-unit", "n_samples": "--n-samples", "ignore_geometry": "--ignore-geometry",
            "demo_seed": "--demo-seed", "sensitivity": "--sensitivity"})
def faults(
    input: Optional[pathlib.Path] = typer.Argument(
        None, metavar="INPUT", help="SEG-Y cube or 2D line, raw .f32be section or .npy array; omit with --demo.",
        show_default=False),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Output folder (created if missing); not the "
                                                                      "input's own folder."),
    demo: bool = typer.Option(False, "--demo", help="Run on a generated 128^3 cube with 3 faults (no input file)."),
    demo_seed: int = typer.Option(0, "--demo-seed", help="Random seed of the --demo cube."),
    iline: int = typer.Option(189, help="Trace header byte of the inline number (SEG-Y)."),
    xline: int = typer.Option(193, help="Trace header byte of the crossline number (SEG-Y)."),
    ignore_geometry: bool = typer.Option(False, "--ignore-geometry", help="Read the SEG-Y as a trace list (unsorted "
                                                                          "file, arbitrary line): trace a 2D section."),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms unless they speak of depth)."),
    n_samples: Optional[int] = typer.Option(None, help="Samples per trace of a raw .f32be section of unknown shape."),
    sensitivity: float = typer.Option(0.5, min=0.0, max=1.0, help="How readily faults are traced, 0-1: higher for "
                                                                  "more (and weaker) faults, lower for fewer; the "
                                                                  "thresholds scale by up to 2x either way."),
) -> None:
    """Trace the faults of INPUT and write fault likelihood, strike, dip and votes (SEG-Y for SEG-Y input), fault
    surfaces (faults.vtp), fault points and a per-fault summary (CSV) and a picture (faults.png) into OUTPUT."""
    import csv

    from .jobs.faults import run_faults_job

    with _one_line_warnings():
        try:
            written = run_faults_job(input, output, demo=demo, demo_seed=demo_seed, iline=iline, xline=xline,
                                     ignore_geometry=ignore_geometry,
                                     sample_unit=None if sample_unit is None else sample_unit.value,
                                     n_samples=n_samples, sensitivity=sensitivity, progress=True)
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
            where = (f"strike {r['mean_strike_deg']:>5}, dip {r['mean_dip_deg']:>4}" if "mean_strike_deg" in r else
                     f"dip {r['mean_dip_deg']:>4} toward {r['dips_toward']}")
            typer.echo(f"  fault {r['id']:>3}: {r['n_points']:>6} samples, {where}, median throw {throw}")
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
@_friendly({"ratio": "--ratio", "threshold": "--threshold", "method": "--method"})
def match(
    image1: pathlib.Path = typer.Argument(
        ..., metavar="IMAGE1", help="First image (PNG, JPEG, TIFF, ...; colour is converted to grey)."),
    image2: pathlib.Path = typer.Argument(..., metavar="IMAGE2", help="Second image."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="CSV of verified matches: x1,y1,x2,y2,score."),
    method: MatchMethod = typer.Option(MatchMethod.hog, help="Features: HOG-pyramid or an OpenCV detector."),
    ratio: float = typer.Option(0.8, help="Lowe's ratio-test threshold."),
    threshold: float = typer.Option(3.0, help="RANSAC inlier reprojection error, pixels."),
) -> None:
    """Match IMAGE1 to IMAGE2, verify with a RANSAC homography, write the matches and print the homography.

    Pixel coordinates have their origin at the centre of the top-left pixel, x to the right, y down.
    """
    from .jobs.match import run_match_job

    job = run_match_job(image1, image2, output, method=method.value, ratio=ratio, threshold=threshold)
    result = job.result
    typer.echo(f"{result.n_putative} putative matches, {job.n_written} verified ({method.value}) -> {output}")
    if result.homography is None:
        typer.echo("no homography could be fitted (too few matches)")
    else:
        typer.echo("homography (image1 -> image2):")
        typer.echo(np.array2string(result.homography, precision=6, suppress_small=True))


class Polarity(str, Enum):
    peak = "peak"
    trough = "trough"
    zero_rising = "zero_rising"
    zero_falling = "zero_falling"


@app.command()
@_friendly({"polarity": "--polarity", "sample_unit": "--sample-unit", "ignore_geometry": "--ignore-geometry"})
def horizon(
    input: pathlib.Path = typer.Argument(..., metavar="INPUT", help="SEG-Y cube (inline-sorted or crossline-sorted)."),
    seed: list[str] = typer.Option(..., "--seed", help="Seed pick IL,XL,T: inline and crossline numbers and the time "
                                                       "(or depth) in the cube's sample unit; repeat for more seeds."),
    output: pathlib.Path = typer.Option(..., "-o", "--output", help="Text file: one 'inline xline time' row per "
                                                                      "tracked trace."),
    polarity: Polarity = typer.Option(Polarity.peak, help="Event the horizon follows."),
    faults: Optional[bool] = typer.Option(None, "--faults/--no-faults", help="Trace the faults first and take their "
                                          "jumps where the correlation across them supports it (the whole fault job "
                                          "runs in memory). Default: on for 3D cubes, off for 2D lines."),
    fill: bool = typer.Option(False, "--fill", help="Fill empty traces by interpolation after tracking."),
    surface: Optional[pathlib.Path] = typer.Option(None, help="Also write the horizon as a surface (.vtp or .vtk)."),
    iline: int = typer.Option(189, help="Trace header byte of the inline number."),
    xline: int = typer.Option(193, help="Trace header byte of the crossline number."),
    ignore_geometry: bool = typer.Option(False, "--ignore-geometry", help="Read the SEG-Y as a trace list (a 2D "
                                         "line, or headers that do not describe a grid); seeds still name the "
                                         "trace by its header inline and crossline."),
    sample_unit: Optional[SampleUnit] = typer.Option(None, help="Unit of the SEG-Y sample axis; default: from the "
                                                                "headers (ms)."),
) -> None:
    """Track a horizon in INPUT (a 3D cube or a 2D line) from one or more seed picks, globally (least squares over
    correlations between near and distant traces, then the picks of each line by dynamic programming), and write it
    as 'inline xline time' rows."""
    from .errors import InputError
    from .jobs.horizon import run_horizon_job

    seeds = []
    for text in seed:
        try:
            seeds.append(tuple(float(v) for v in text.split(",")))
        except ValueError:
            seeds.append(())
        if len(seeds[-1]) != 3:
            raise InputError(f"--seed {text!r} must be IL,XL,T (three numbers separated by commas)")
    job = run_horizon_job(input, seeds, output, polarity=polarity.value, faults=faults, fill=fill, surface=surface,
                          iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                          sample_unit=None if sample_unit is None else sample_unit.value, progress=True)
    typer.echo(f"{job.n_rows} of {job.horizon.times.size} traces tracked ({job.horizon.coverage:.1%}) -> {output}")
    if job.surface is not None:
        typer.echo(f"surface -> {job.surface}")


if __name__ == "__main__":  # pragma: no cover
    app()
