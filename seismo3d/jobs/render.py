"""The ``seismo3d render`` command: a picture of a SEG-Y cube, a ``faults`` or ``map`` output folder, a horizon file
or a DEM.

:func:`run_render_job` finds out what the input is, reads it, builds one pyvista scene
(:func:`seismo3d.viz.show_seismic`) and renders it off screen into a PNG.
"""

from __future__ import annotations

import csv
import json
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .._validation import check_choice
from ..errors import DataNotFoundError, InputError, Seismo3dWarning
from ..mapping import read_tum_trajectory
from ..terrain import extract_lineaments, read_dem
from .inputs import SEGY_SUFFIXES, read_seismic
from .outputs import check_outputs, output_file
from .runinfo import RUN_JSON, RunRecord, input_changed, read_run_json, run_json_output, run_json_path

__all__ = ["RenderJob", "run_render_job"]

_SEGY = set(SEGY_SUFFIXES)
_TEXT = {".txt", ".dat", ".csv", ".xyz"}
_DEM = {".tif", ".tiff"}
# The files render reads of a 'seismo3d faults' or 'seismo3d map' output folder (inputs: never replaced by the PNG).
_FOLDER_FILES = ("faults.vtp", "fault_likelihood.sgy", "fault_likelihood.npy", "demo_seismic.sgy", "mesh.ply",
                 "trajectory.txt", "keyframes.json", RUN_JSON)
# The SEG-Y options of a faults or horizon run (its run.json's options): how the run read its input.
_SEGY_OPTIONS = ("iline", "xline", "endian", "ignore_geometry", "sample_unit")


@dataclass(frozen=True)
class RenderJob:
    """What :func:`run_render_job` drew.

    Attributes
    ----------
    kind : {'segy', 'faults', 'horizon', 'dem', 'map'}
        What the input was.
    picture : pathlib.Path
        The PNG written.
    caption : str
        The scene's caption (lines, samples, vertical exaggeration).
    n_faults : int
        Traced faults drawn (0 without).
    n_lineaments : int
        Lineaments drawn on a DEM (0 without).
    seismic : pathlib.Path or None
        The SEG-Y cube drawn under faults or a horizon: ``seismic`` as given, the demo's cube, or the input recorded
        in the run's ``run.json``; None when none was drawn.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``render``: reading and drawing).
    section : bool
        A single line drawn as a section (:func:`seismo3d.viz.plot_section`) rather than a 3D scene.
    n_stick_faults : int
        Faults of people's fault sticks drawn (``sticks``; 0 without).
    """

    kind: str
    picture: Path
    caption: str
    n_faults: int = 0
    n_lineaments: int = 0
    seismic: Path | None = None
    run_json: Path | None = None
    stage_seconds: dict | None = None
    section: bool = False
    n_stick_faults: int = 0


def _kind(path: Path) -> str:
    if not path.exists():
        raise DataNotFoundError(f"{path} does not exist; pass a SEG-Y cube, a 'seismo3d faults' output folder or a "
                                "horizon text file")
    if path.is_dir():
        if (path / "faults.vtp").is_file():
            return "faults"
        if (path / "mesh.ply").is_file():
            return "map"
        raise InputError(f"{path} is a folder without faults.vtp or mesh.ply; pass the output folder of 'seismo3d "
                         "faults' or 'seismo3d map' (or a file)")
    suffix = path.suffix.lower()
    if suffix in _SEGY:
        return "segy"
    if suffix in _TEXT:
        return "horizon"
    if suffix in _DEM:
        return "dem"
    raise InputError(f"{path.name}: cannot tell what to draw from the extension {suffix!r}; pass a SEG-Y cube "
                     "(.sgy/.segy), a 'seismo3d faults' output folder, a horizon file (.txt: inline xline time rows) "
                     "or a DEM (.tif)")


def _check_throws(kind: str, path: Path) -> None:
    """Refuse ``color_by='throw'`` before any work where there is no throw to colour by: an input that is not a
    faults folder, or one whose faults carry no measured throw."""
    if kind != "faults":
        what = {"segy": "a SEG-Y file", "horizon": "a horizon file", "dem": "a DEM", "map": "a map folder"}[kind]
        raise InputError(f"color_by='throw' colours traced faults by their throw, and {path.name} is {what}; pass "
                         "the output folder of 'seismo3d faults', or leave color_by out")
    import pyvista as pv

    surfaces = pv.read(path / "faults.vtp")
    throw = np.asarray(surfaces.point_data["throw"], float) if "throw" in surfaces.point_data else np.zeros(0)
    if surfaces.n_points and not np.isfinite(throw).any():
        raise InputError(f"color_by='throw': the faults of {path.name} carry no measured throw (faults.vtp's "
                         "'throw' is empty); leave color_by out to colour them by fault id")


@dataclass(frozen=True)
class _EarlierRun:
    """What the ``run.json`` of the faults or horizon run that wrote render's input says of the run's input.

    ``input``: the input's path (None for a ``--demo`` run or without a record); ``entry``: its identity as recorded
    (:func:`~seismo3d.jobs.runinfo.input_identity`); ``segy_options``: the SEG-Y options the run read it with (None
    without a record)."""

    input: Path | None = None
    entry: dict | None = None
    segy_options: dict | None = None


def _earlier_run(kind: str, path: Path) -> _EarlierRun:
    """The record of the run that wrote a faults folder (its ``run.json``) or a horizon file
    (``<file>.run.json``)."""
    if kind not in ("faults", "horizon"):
        return _EarlierRun()
    record = read_run_json(path / RUN_JSON if kind == "faults" else run_json_path(output_file(path)))
    if record is None or record.get("command") != kind:
        return _EarlierRun()
    options = record.get("options") or {}
    segy = {k: options[k] for k in _SEGY_OPTIONS if k in options}
    entry = (record.get("inputs") or {}).get("input")
    if not isinstance(entry, dict) or "path" not in entry:  # a --demo run: its options were not the cube's
        return _EarlierRun()
    return _EarlierRun(Path(entry["path"]), entry, segy)


def _run_input_to_draw(run: _EarlierRun) -> Path | None:
    """The earlier run's input when it is still the file the run read and is SEG-Y; else None, said in one
    warning naming ``seismic``."""
    if run.input is None:
        return None
    problem = input_changed(run.entry)
    if problem is None and run.input.suffix.lower() not in _SEGY:
        problem = "is not SEG-Y (render draws SEG-Y cubes only)"
    if problem is None:
        return run.input
    warnings.warn(f"the run's input {run.input} {problem}: drawn without seismic; pass seismic=CUBE.sgy to draw "
                  "one under it", Seismo3dWarning, stacklevel=2)
    return None


def _read_segy(path: Path, vertical_exaggeration, segy_options=None):
    """The amplitudes as (n_inlines, n_xlines, n_samples) and their geometry; a trace list as one section of
    (n_traces, 1, n_samples), its traces numbered from 1 in file order (:func:`~seismo3d.jobs.inputs.read_seismic`)."""
    from ..viz.geometry import cube_geometry

    seismic = read_seismic(path, **(segy_options or {}), arrays=False)
    if seismic.kind != "trace list":
        return seismic.data, cube_geometry(seismic.data.shape, inlines=seismic.inlines, xlines=seismic.xlines,
                                           samples=seismic.samples, sample_unit=seismic.sample_unit,
                                           cdp_x=seismic.cdp_x, cdp_y=seismic.cdp_y, map_unit=seismic.map_unit,
                                           vertical_exaggeration=vertical_exaggeration)
    data = seismic.data[:, None, :]
    geometry = cube_geometry(data.shape, inlines=seismic.cube["trace"].values, xlines=[0],
                             samples=seismic.samples, sample_unit=seismic.sample_unit,
                             vertical_exaggeration=vertical_exaggeration, lateral_names=("trace", ""))
    return data, geometry


def _slices_for(shape):
    """The middle planes; a single line (one inline or one crossline) is shown as that one plane, seen square on."""
    if shape[0] == 1:
        return (0, None, None), "section"
    if shape[1] == 1:
        return (None, 0, None), "section"
    return None, "iso"


def _horizon_grid(path: Path, geometry):
    """(n_inlines, n_xlines) fractional sample indices of an "inline xline time" text file (or "trace time" rows of
    a trace list, on a (n_traces, 1) grid) on ``geometry``'s grid (or on the grid of its own lines when ``geometry``
    is None), and the geometry."""
    from ..viz.geometry import cube_geometry

    try:
        rows = np.loadtxt(path, ndmin=2, comments="#", delimiter="," if path.suffix.lower() == ".csv" else None)
    except ValueError as exc:
        raise InputError(f"{path.name} is not a table of numbers ({exc}); a horizon file has 'inline xline time' "
                         "rows") from None
    if rows.shape[1] < 2 or rows.shape[0] < 4:
        raise InputError(f"{path.name} has {rows.shape[0]} rows of {rows.shape[1]} columns; a horizon file has "
                         "'inline xline time' rows, or 'trace time' rows for a trace list (at least 4)")
    trace_list = rows.shape[1] == 2
    il, xl, t = (rows[:, 0], np.zeros(len(rows)), rows[:, 1]) if trace_list else (rows[:, 0], rows[:, 1], rows[:, 2])
    if geometry is None:
        samples = np.arange(np.floor(t.min()), np.ceil(t.max()) + 1.0)
        geometry = cube_geometry((np.unique(il).size, np.unique(xl).size, samples.size), inlines=np.unique(il),
                                 xlines=np.unique(xl), samples=samples, sample_unit="ms",
                                 lateral_names=("trace", "") if trace_list else ("inline", "crossline"))
    i = np.searchsorted(geometry.inlines, il)
    j = np.searchsorted(geometry.xlines, xl)
    ok = (i < geometry.inlines.size) & (j < geometry.xlines.size)
    ok[ok] &= (geometry.inlines[i[ok]] == il[ok]) & (geometry.xlines[j[ok]] == xl[ok])
    if not ok.any():
        raise InputError(f"no row of {path.name} falls on the lines of the cube given with --seismic; pass the cube "
                         "the horizon was tracked in")
    times = np.full(geometry.shape[:2], np.nan)
    times[i[ok], j[ok]] = np.interp(t[ok], geometry.samples, np.arange(geometry.samples.size))
    return times, geometry


def _read_path_csv(path: Path, shape) -> np.ndarray:
    """(K, 2) row, col cells of a ``seismo3d plan`` CSV."""
    if not path.is_file():
        raise DataNotFoundError(f"path={path} does not exist; pass the CSV written by 'seismo3d plan'")
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    if not rows or not {"row", "col"} <= set(rows[0]):
        raise InputError(f"{path.name} has no row and col columns; pass the CSV written by 'seismo3d plan'")
    cells = np.array([[float(r["row"]), float(r["col"])] for r in rows])
    if cells.min() < 0 or np.any(cells.max(axis=0) > np.array(shape) - 1):
        raise InputError(f"the cells of {path.name} lie outside the DEM's {shape} grid; pass the path planned on it")
    return cells


def _render_dem(path: Path, output: Path, *, lineaments, plan, vertical_exaggeration, window_size) -> RenderJob:
    from ..viz.terrain3d import show_terrain

    dem = read_dem(path)
    found = extract_lineaments(dem) if lineaments else None
    cells = None if plan is None else _read_path_csv(Path(plan), dem.shape)
    show_terrain(dem, lineaments=found, path=cells, vertical_exaggeration=vertical_exaggeration, screenshot=output,
                 window_size=window_size)
    dy, dx = dem.pixel_size_m
    caption = f"{dem.shape[1]} x {dem.shape[0]} pixels of {dx:.0f} x {dy:.0f} m"
    if vertical_exaggeration is None:
        from ..viz.terrain3d import terrain_exaggeration

        vertical_exaggeration = terrain_exaggeration(dem)
    caption += f", vertical exaggeration {vertical_exaggeration:.2g}x"
    return RenderJob(kind="dem", picture=output, caption=caption, n_lineaments=0 if found is None else len(found))


def _render_map(path: Path, output: Path, *, window_size) -> RenderJob:
    """The mesh, trajectory and keyframes of a ``seismo3d map`` folder."""

    import pyvista as pv

    from ..viz.maps import show_map

    try:
        mesh = pv.read(path / "mesh.ply")
    except Exception as exc:  # noqa: BLE001 - VTK's reader raises assorted errors on a damaged file
        raise InputError(f"{path / 'mesh.ply'} cannot be read as a PLY mesh ({exc}); write it again with "
                         "'seismo3d map'") from None
    poses = np.zeros((0, 4, 4))
    if (path / "trajectory.txt").is_file():
        _, poses = read_tum_trajectory(path / "trajectory.txt")
    keyframes = np.zeros((0, 4, 4))
    if (path / "keyframes.json").is_file():
        graph = json.loads((path / "keyframes.json").read_text())
        keyframes = np.array([k["pose"] for k in graph.get("keyframes", [])], dtype=np.float64).reshape(-1, 4, 4)
    show_map(mesh, poses, keyframes, screenshot=output, window_size=window_size)
    caption = f"{mesh.n_points} mesh vertices, {len(poses)} camera poses, {len(keyframes)} keyframes"
    return RenderJob(kind="map", picture=output, caption=caption)


def run_render_job(input_path, output, *, seismic=None, color_by="fault_id", vertical_exaggeration=None,
                   lineaments=False, plan=None, window_size=(1200, 900), iline: int = 189, xline: int = 193,
                   endian=None, ignore_geometry: bool = False, sample_unit=None,
                   overwrite: bool = False, sticks=None) -> RenderJob:
    """Render INPUT off screen into a PNG: the ``seismo3d render`` command.

    Inputs
    ------
    * a SEG-Y cube: its middle inline, crossline and time slice (a single line: that section), placed by its CDP X/Y
      when the headers have them (see :func:`seismo3d.viz.cube_geometry`); a file without an inline / crossline grid
      (or with ``ignore_geometry``) is drawn as one section, its traces numbered from 1 in file order;
    * the output folder of ``seismo3d faults``: the fault surfaces (``faults.vtp``) with the fault likelihood as a
      semi-transparent volume, over the slices of ``seismic`` (default: ``demo_seismic.sgy`` in the folder, written
      by ``--demo``, else the run's input as its ``run.json`` records it), placed by the geometry of
      ``fault_likelihood.sgy``;
    * a horizon text file ("inline xline time" rows, as ``seismo3d horizon`` writes): the horizon coloured by time,
      over the slices of ``seismic`` (default: the run's input as ``<file>.run.json`` records it);

    The run's input is drawn only while it is the file the run read (the size and sha256 in ``run.json``, or size
    and modification time for a file above :data:`~seismo3d.jobs.runinfo.HASH_LIMIT`), read with the SEG-Y options
    the run used (so are the folder's own SEG-Y files); otherwise the picture has no seismic and a warning says why.
    * a GeoTIFF DEM: its surface coloured by elevation (metres about its centre), with its lineaments
      (``lineaments=True``: :func:`~seismo3d.terrain.extract_lineaments`) and a path planned by ``seismo3d plan``
      (``plan``: its CSV) draped over it (:func:`seismo3d.viz.terrain3d.show_terrain`);
    * the output folder of ``seismo3d map``: ``mesh.ply`` coloured by height, the trajectory of ``trajectory.txt``
      and the keyframes of ``keyframes.json`` as camera pyramids (:func:`seismo3d.viz.maps.show_map`).

    Parameters
    ----------
    input_path : str or os.PathLike
    output : str or os.PathLike
        The PNG to write (atomically; its folder must exist); not an input, and not an existing file unless
        ``overwrite`` (see :mod:`seismo3d.jobs.outputs`; checked before the inputs are read).
    seismic : str or os.PathLike, optional
        A SEG-Y cube to draw under faults or a horizon (read with ``iline``, ``xline``, ... below); default: the
        input of the run that wrote them (above).
    color_by : {'fault_id', 'throw'}, optional
        Colour of the fault surfaces (3D) or lines (a line drawn as a section): by fault, or by the throw measured
        along them; 'throw' is refused before any work for an input without traced faults or faults without a
        measured throw.
    vertical_exaggeration : float, optional
        Default: the cube's height becomes half its longer side; a single line gets the round factor that makes
        its section about half as tall as wide (at least 1, :func:`seismo3d.viz.sections.section_exaggeration`);
        a DEM's relief at most a 40th of its longer side (a factor from 1 to 5).
    lineaments : bool, optional
        DEM: extract its lineaments and draw them.
    plan : str or os.PathLike, optional
        DEM: the CSV of ``seismo3d plan`` (columns row, col, ...) to draw as a path.
    window_size : (int, int), optional
        Pixels.
    iline, xline : int, optional
        Trace header bytes of the inline and crossline numbers of the SEG-Y files read (for a faults folder or
        horizon file with a ``run.json``, of ``seismic`` only: the run's own files are read with the run's).
    endian : {'big', 'little'}, optional
        Byte order of the SEG-Y files read; by default detected from each binary header.
    ignore_geometry : bool, optional
        Read the SEG-Y files as trace lists, without the warning a file without a grid gets.
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of the SEG-Y sample axis; by default from the headers.
    overwrite : bool, optional
        Replace an existing ``output``.
    sticks : str or os.PathLike, optional
        Fault sticks to draw over a SEG-Y input, a faults folder or a horizon (OpendTect fault-stick ASCII or
        Charisma; :func:`seismo3d.jobs.interchange.sticks_mesh`), coloured by fault; nodes given only by X / Y are
        placed by the drawn SEG-Y's grid map.

    Returns
    -------
    RenderJob

    Warns
    -----
    Seismo3dWarning
        The recorded input of a faults or horizon run no longer exists, has changed or is not SEG-Y: drawn without
        seismic.

    Raises
    ------
    DataNotFoundError
        The input (or ``seismic``) does not exist.
    InputError
        An output that is an input, exists (without ``overwrite``) or cannot be written; an input of unknown kind, a
        folder without ``faults.vtp``, a horizon file that is not a table; ``color_by='throw'`` without throws
        (above).
    SegyFormatError, SegyGeometryError
        As :func:`seismo3d.seismic.open_segy`.
    """
    record = RunRecord("render", locals())  # first: the arguments as called
    segy_options = {"iline": iline, "xline": xline, "endian": endian, "ignore_geometry": ignore_geometry,
                    "sample_unit": sample_unit}

    check_choice(color_by, "color_by", {"fault_id", "throw"})
    path, output = Path(input_path), Path(output)
    read = [path / name for name in _FOLDER_FILES] if path.is_dir() else []  # what render reads of a folder
    main = output_file(output, "picture.png")
    check_outputs([main, run_json_output(main)], [path, seismic, plan, sticks, *read], overwrite=overwrite)
    if output.suffix.lower() != ".png":
        raise InputError(f"{output.name}: render writes a PNG; name the output picture.png")
    kind = _kind(path)
    if color_by == "throw":
        _check_throws(kind, path)
    run = _earlier_run(kind, path)
    with record.stage("render"):
        job = _render(kind, path, output, seismic=seismic, color_by=color_by,
                      vertical_exaggeration=vertical_exaggeration, lineaments=lineaments, plan=plan,
                      window_size=window_size, segy_options=segy_options, run=run, sticks=sticks)
    inputs = {"input": path, "seismic": job.seismic, "path": plan, "sticks": sticks}
    inputs.update({name: p for name, p in zip(_FOLDER_FILES, read) if p.is_file()})
    run_json = record.write(run_json_path(main), inputs=inputs, outputs={"picture": output},
                            results=dict(kind=job.kind, caption=job.caption, n_faults=job.n_faults,
                                         n_stick_faults=job.n_stick_faults, n_lineaments=job.n_lineaments))
    return replace(job, run_json=run_json, stage_seconds=dict(record.stage_seconds))


def _render(kind: str, path: Path, output: Path, *, seismic, color_by, vertical_exaggeration, lineaments, plan,
            window_size, segy_options, run: _EarlierRun, sticks=None) -> RenderJob:
    """Read the input of ``kind`` and draw it into ``output`` (the scenes of :func:`run_render_job`; ``run``: the
    record of the faults or horizon run that wrote the input)."""
    import pyvista as pv

    from ..viz.geometry import cube_geometry
    from ..viz.seismic import show_seismic

    if kind == "map":
        return _render_map(path, output, window_size=window_size)
    if kind == "dem":
        return _render_dem(path, output, lineaments=lineaments, plan=plan,
                           vertical_exaggeration=vertical_exaggeration, window_size=window_size)
    if seismic is not None and not Path(seismic).is_file():
        raise DataNotFoundError(f"seismic={seismic} does not exist; pass the SEG-Y cube to draw under the input")
    cube, geometry, extra = None, None, {}
    n_faults = n_stick_faults = 0
    run_options = run.segy_options or segy_options  # the run's files and input, read as the run read its input
    under, under_options = (Path(seismic), segy_options) if seismic is not None else (None, run_options)
    if kind == "segy":
        cube, geometry = _read_segy(path, vertical_exaggeration, segy_options)
    elif kind == "faults":
        if under is None and (path / "demo_seismic.sgy").is_file():
            under = path / "demo_seismic.sgy"
        under = under or _run_input_to_draw(run)
        if under is not None:
            cube, geometry = _read_segy(under, vertical_exaggeration, under_options)
        likelihood_file = path / "fault_likelihood.sgy"
        if likelihood_file.is_file():
            likelihood, like_geometry = _read_segy(likelihood_file, vertical_exaggeration, run_options)
            geometry = geometry or like_geometry
        elif (path / "fault_likelihood.npy").is_file():
            likelihood = np.load(path / "fault_likelihood.npy")
            likelihood = likelihood[:, None, :] if likelihood.ndim == 2 else likelihood
            geometry = geometry or cube_geometry(likelihood.shape, vertical_exaggeration=vertical_exaggeration)
        else:
            raise InputError(f"{path} has faults.vtp but no fault_likelihood.sgy or .npy; pass the complete output "
                             "folder of 'seismo3d faults'")
        if likelihood.shape != geometry.shape:
            raise InputError(f"the fault likelihood in {path} has shape {likelihood.shape} but the seismic "
                             f"{geometry.shape}; pass the cube the faults were traced in")
        surfaces = pv.read(path / "faults.vtp")
        n_faults = int(np.unique(surfaces.point_data["fault_id"]).size) if surfaces.n_points else 0
        extra = dict(faults=surfaces, likelihood=likelihood, color_faults_by=color_by)
    else:
        under = under or _run_input_to_draw(run)
        if under is not None:
            cube, geometry = _read_segy(under, vertical_exaggeration, under_options)
        times, geometry = _horizon_grid(path, geometry)
        if under is None and vertical_exaggeration is not None:
            geometry = cube_geometry(geometry.shape, inlines=geometry.inlines, xlines=geometry.xlines,
                                     samples=geometry.samples, sample_unit=geometry.sample_unit,
                                     vertical_exaggeration=vertical_exaggeration)
        extra = dict(horizons=[times])
    slices, camera = _slices_for(geometry.shape)
    if sticks is not None:  # the --sticks file's faults over the seismic
        from .interchange import sticks_mesh

        mesh = sticks_mesh(sticks, geometry, path if kind == "segy" else under, segy_options=under_options)
        n_stick_faults = int(np.unique(mesh.point_data["fault_id"]).size)
        if camera == "section":  # a line: drawn in a style of their own beside the traced faults
            extra["sticks"] = mesh
        else:  # a 3D scene: drawn as faults, numbered after the traced ones so that their colours differ
            if "faults" in extra:
                traced = extra["faults"]
                mesh.point_data["fault_id"] += int(traced.point_data["fault_id"].max()) if traced.n_points else 0
                mesh = traced.merge(mesh)
            extra["faults"] = mesh
    if camera == "section":  # one line: a section with its numbers and times on labelled axes (matplotlib)
        caption = _render_section(cube, geometry, output, extra=extra, vertical_exaggeration=vertical_exaggeration,
                                  window_size=window_size, color_by=color_by)
        return RenderJob(kind=kind, picture=output, caption=caption, n_faults=n_faults, seismic=under, section=True,
                         n_stick_faults=n_stick_faults)
    show_seismic(cube, geometry, slices=slices, camera=camera, screenshot=output, window_size=window_size, **extra)
    return RenderJob(kind=kind, picture=output, caption=geometry.describe(), n_faults=n_faults, seismic=under,
                     n_stick_faults=n_stick_faults)


def _render_section(data, geometry, output: Path, *, extra: dict, vertical_exaggeration, window_size,
                    color_by="fault_id") -> str:
    """A single line (a 2D line of a survey or a trace list) drawn as a section: trace numbers along, time or depth
    down, the vertical exaggeration stated, faults as lines and a horizon as a curve
    (:func:`seismo3d.viz.sections.plot_section`), coloured by ``color_by``; returns the caption."""
    from ..viz.sections import plot_section

    along = 0 if geometry.shape[0] > 1 else 1
    traces = geometry.inlines if along == 0 else geometry.xlines
    name = geometry.lateral_names[along]
    spacing = float(np.linalg.norm(geometry.axes[along])) if geometry.map_unit != "line" else None
    values = "amplitude"
    if data is None:  # no seismic: the fault likelihood of a faults folder, or nothing under a horizon
        data = extra.get("likelihood")
        values = "none" if data is None else "fault likelihood"
        data = np.zeros(geometry.shape, np.float32) if data is None else data
    section = np.asarray(data, dtype=np.float32).reshape(geometry.shape[along], geometry.shape[2])
    horizons = extra.get("horizons") or []
    horizon = np.asarray(horizons[0], dtype=np.float64).ravel() if len(horizons) else None
    dpi = 120
    return plot_section(section, path=output, traces=traces, samples=geometry.samples, trace_name=name,
                        sample_unit=geometry.sample_unit, trace_spacing=spacing,
                        vertical_exaggeration=vertical_exaggeration, faults=extra.get("faults"),
                        sticks=extra.get("sticks"), horizon=horizon, values=values, width=window_size[0] / dpi,
                        dpi=dpi, color_by=color_by)
