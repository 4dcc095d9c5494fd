"""The ``seismo3d horizon`` job: track a horizon in a SEG-Y cube or 2D line from seed picks and write it as text (and a
surface).

Seeds are given in the survey's terms (inline and crossline numbers, or the trace number of a file without them, and
the time or depth in the file's sample unit) and converted to index positions; the faults are traced first, on cubes and
lines alike unless turned off (:func:`seismo3d.seismic.trace_faults`; their jumps are taken only where the correlation
across them supports it), and
the horizon is tracked by :func:`seismo3d.seismic.track_horizon` (global least squares over correlations between near
and distant traces, then dynamic programming over candidate picks), on a cube or a line.
"""

from __future__ import annotations

import pathlib
import tempfile
import warnings
from dataclasses import dataclass

import numpy as np

from .._progress import LOGGER
from ..errors import (InputError, MissingDependencyError, SeedError, SegyGeometryError, Seismo3dWarning,
                      UnsupportedDataError)
from ..seismic.horizons.result import Horizon
from .inputs import read_seismic
from .outputs import check_outputs, output_file
from .runinfo import RunRecord, run_json_output, run_json_path

__all__ = ["HorizonJob", "check_faults_run", "run_horizon_job", "seed_index", "trace_seed_index"]


@dataclass(frozen=True, eq=False)
class HorizonJob:
    """What :func:`run_horizon_job` did.

    Attributes
    ----------
    horizon : Horizon
        The tracked (and, with ``fill``, filled) horizon, index space.
    n_rows : int
        Rows written to the text file (tracked traces).
    output : pathlib.Path
        The text file.
    surface : pathlib.Path or None
        The surface file, when asked for.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``read``, ``faults`` when traced, ``track``, ``write``).
    n_faults : int
        Faults traced first (0 without).
    """

    horizon: Horizon
    n_rows: int
    output: pathlib.Path
    surface: pathlib.Path | None
    run_json: pathlib.Path | None = None
    stage_seconds: dict | None = None
    n_faults: int = 0
    maps: dict | None = None  # with maps=True: the map files written, by format (seismo3d.jobs.interchange)


@dataclass(frozen=True, eq=False)
class _Survey:
    """What the job read: the data, and how seeds and output rows name its traces.

    ``data`` is (n_inlines, n_xlines, n_samples) for a 3D cube and (n_traces, n_samples) for a 2D line: a line of
    a 3D survey (one inline or one crossline; ``inlines`` and ``xlines`` set) or a trace list (a file without an
    inline / crossline grid; ``inlines`` and ``xlines`` None, traces numbered from 1 in file order). ``cube`` is the
    file as :func:`seismo3d.open` labels it (its coordinates for ``--maps`` and ``--seed-file``)."""

    name: str
    description: str
    data: np.ndarray
    inlines: np.ndarray | None
    xlines: np.ndarray | None
    samples: np.ndarray
    unit: str
    cube: object = None

    @property
    def coordinates(self):
        """The survey's X / Y and grid map, from the cube's headers as read (:func:`~seismo3d.seismic.io.coordinates.
        cube_coordinates`): (n_inlines, n_crosslines) for a cube, (n_traces,) for a line or a trace list."""
        from ..seismic.io.coordinates import cube_coordinates

        return cube_coordinates(self.cube)

    @property
    def kind(self) -> str:
        if self.data.ndim == 3:
            return "cube"
        return "line" if self.inlines is not None else "trace list"


def _read_survey(path: pathlib.Path, *, iline, xline, ignore_geometry, endian, sample_unit=None) -> _Survey:
    """The SEG-Y file as a cube or a 2D line (:func:`~seismo3d.jobs.inputs.read_seismic`); a single trace is
    refused."""
    seismic = read_seismic(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian,
                           sample_unit=sample_unit, arrays=False)
    data, n_samples = seismic.data, seismic.samples.size
    n_traces = int(np.prod(data.shape[:-1]))
    if n_traces < 2 or n_samples < 2:
        raise SegyGeometryError(f"{path.name} is {seismic.description} of {n_samples} samples; horizon tracking "
                                "needs a 2D line or a 3D cube")
    if seismic.kind == "line":
        data = data.reshape(n_traces, n_samples)  # a line of a survey, (n, 1, ns) or (1, n, ns)
    return _Survey(path.name, seismic.description, data, seismic.inlines, seismic.xlines, seismic.samples,
                   seismic.sample_unit, seismic.cube)


def _seed_indices(survey: _Survey, seeds) -> list:
    """Seeds in the survey's terms to index positions of ``survey.data``."""
    out = []
    for seed in seeds:
        values = tuple(float(v) for v in seed)
        text = ",".join(f"{v:g}" for v in values)
        if survey.kind == "trace list":
            if len(values) != 2:
                raise InputError(f"--seed {text}: {survey.name} is read as a trace list ({survey.description}); give "
                                 "seeds as TRACE,T: the trace number in file order (from 1) and the time")
            out.append(trace_seed_index(values, survey.data.shape[0], survey.samples, survey.unit))
            continue
        if len(values) != 3:
            raise InputError(f"--seed {text} must be IL,XL,T: the inline and crossline numbers of {survey.name} and "
                             "the time")
        i, j, t = seed_index(values, survey.inlines, survey.xlines, survey.samples, survey.unit)
        if survey.kind == "cube":
            out.append((i, j, t))
        else:  # along the inlines of one crossline, or along the crosslines of one inline
            out.append((i if survey.inlines.size > 1 else j, t))
    return out


@dataclass(frozen=True)
class _Position:
    """An index position in the survey's terms: the trace's labels (('inline', 1010), ('crossline', 1155)) or
    (('trace', 7),), and the time or depth in the file's unit."""

    labels: tuple
    time: float
    unit: str

    @property
    def trace(self) -> str:
        return ", ".join(f"{name} {value}" for name, value in self.labels)

    @property
    def words(self) -> str:
        return f"{self.trace}, {self.time:.6g} {self.unit}"

    @property
    def seed(self) -> str:
        """As a --seed value: IL,XL,T or TRACE,T."""
        return ",".join(str(value) for _, value in self.labels) + f",{self.time:.6g}"


def _survey_position(survey: _Survey, position) -> _Position:
    """An index position (lateral indices, fractional sample) of ``survey.data`` in the survey's terms."""
    *lateral, k = (float(v) for v in position)
    lateral = [int(round(v)) for v in lateral]
    time = float(np.interp(k, np.arange(survey.samples.size), survey.samples))
    if survey.kind == "trace list":  # its number in file order (seismo3d.open's trace coordinate)
        labels = (("trace", int(survey.cube["trace"][lateral[0]])),)
    elif survey.kind == "cube":
        labels = (("inline", int(survey.inlines[lateral[0]])), ("crossline", int(survey.xlines[lateral[1]])))
    elif survey.inlines.size > 1:  # a line along the inlines of one crossline
        labels = (("inline", int(survey.inlines[lateral[0]])), ("crossline", int(survey.xlines[0])))
    else:
        labels = (("inline", int(survey.inlines[0])), ("crossline", int(survey.xlines[lateral[0]])))
    return _Position(labels, time, survey.unit)


def _mute_note(survey: _Survey, position) -> str:
    """' (muted there: constant from 0 to 1456 ms)' when the trace is constant around ``position``, else ''."""
    trace = survey.data[tuple(int(round(v)) for v in position[:-1])]
    k = int(np.clip(round(position[-1]), 0, trace.size - 1))
    same = trace == trace[k]
    if k + 1 < trace.size and not same[k + 1] and (k == 0 or not same[k - 1]):
        return ""
    first = k - int(np.argmin(same[k::-1])) + 1 if not same[:k + 1].all() else 0
    last = k + int(np.argmin(same[k:])) - 1 if not same[k:].all() else trace.size - 1
    return f" (muted there: constant from {survey.samples[first]:g} to {survey.samples[last]:g} {survey.unit})"


def _seed_error(exc: SeedError, survey: _Survey, seeds, index_seeds, polarity: str) -> InputError:
    """The library's seed error in the user's terms: the seed as typed, where it is, and the nearest position that
    can start a horizon as a --seed to pass."""
    which = int(np.argmin([np.abs(np.subtract(s, exc.seed)).sum() for s in index_seeds]))
    text = ",".join(f"{float(v):g}" for v in seeds[which])
    trace = _survey_position(survey, exc.seed).trace
    if exc.window is None:
        problem, kind = f"the trace at {trace} is dead (all samples equal)", "live trace"
    else:
        dt = float(survey.samples[1] - survey.samples[0])
        problem = (f"no {polarity} pick within {exc.window:g} samples ({exc.window * dt:g} {survey.unit}) of "
                   f"{float(seeds[which][-1]):g} {survey.unit} on the trace at {trace}{_mute_note(survey, exc.seed)}")
        kind = f"{polarity} pick"
    if exc.nearest is None:
        return InputError(f"--seed {text}: {problem}, and no trace of {survey.name} has one; check --polarity and "
                          "the file")
    near = _survey_position(survey, exc.nearest)
    return InputError(f"--seed {text}: {problem}; the nearest {kind} is at {near.words}: pass --seed {near.seed}"
                      + ("" if exc.window is None else " (or another --polarity)"))


@dataclass(frozen=True)
class _RecordedFaults:
    """The faults of a ``seismo3d faults`` run read back in index space, as :func:`track_horizon` reads an
    interpretation: ``faults`` (objects with ``points`` and ``normals``) and ``throws`` (``throw``, ``correlation``,
    ``correlation_unshifted``), in the same order."""

    faults: list
    throws: list


@dataclass(frozen=True)
class _Piece:
    points: np.ndarray | None = None
    normals: np.ndarray | None = None
    throw: np.ndarray | None = None
    correlation: np.ndarray | None = None
    correlation_unshifted: np.ndarray | None = None


def check_faults_run(folder, input_path) -> dict:
    """The record (``run.json``) of the ``seismo3d faults`` run whose output folder is ``folder``, checked to have
    read the file ``input_path`` as it is now (size and sha256, or size and modification time above
    :data:`~seismo3d.jobs.runinfo.HASH_LIMIT`).

    Parameters
    ----------
    folder : path-like
        The output folder of ``seismo3d faults``.
    input_path : path-like
        The SEG-Y file the horizon is tracked in.

    Returns
    -------
    dict
        The run's record (:func:`~seismo3d.jobs.runinfo.read_run_json`).

    Raises
    ------
    InputError
        No faults run's record or points in ``folder``, or a run of another input (or of this file before it
        changed).
    """
    from .runinfo import RUN_JSON, input_identity, read_run_json

    folder = pathlib.Path(folder)
    record = read_run_json(folder / RUN_JSON)
    if record is None or record.get("command") != "faults" or not (folder / "fault_points.csv").is_file():
        raise InputError(f"faults_from folder {folder} holds no `seismo3d faults` run (run.json and "
                         "fault_points.csv); pass the output folder of `seismo3d faults` run on this input")
    then = (record.get("inputs") or {}).get("input") or {}
    now = input_identity(input_path)
    hashed = bool(then.get("sha256") and now["sha256"])
    same = then.get("bytes") == now["bytes"] and (then.get("sha256") == now["sha256"] if hashed
                                                  else then.get("mtime") == now["mtime"])
    if not same:
        raise InputError(f"the faults run in faults_from folder {folder} traced {then.get('path', 'another file')}, "
                         f"not {pathlib.Path(input_path).name} as it is now; leave out faults_from to trace its "
                         "faults again, or run `seismo3d faults` on it")
    return record


def _recorded_faults(folder: pathlib.Path, survey: _Survey, segy: dict) -> _RecordedFaults:
    """The faults of a checked ``seismo3d faults`` run (:func:`check_faults_run`) on this survey, in index space:
    points from ``fault_points.csv``, normals from the strike and dip volumes at them (at a point without them, a
    dip of 0 or NaN where the likelihood was below its orientation floor and the votes bridged a gap, the nearest
    point's of the same fault), throws and their correlations from the table."""
    from ..seismic.faults.result import fault_normals
    from .fault_tables import read_points

    table = read_points(folder / "fault_points.csv")
    k = np.interp(table["time_or_depth"], survey.samples, np.arange(survey.samples.size))
    if survey.kind == "trace list" and "trace" in table:  # numbered as seismo3d.open numbers them: from 1
        lateral = [np.searchsorted(survey.cube["trace"].values, table["trace"])]
    elif survey.kind == "trace list":  # traces the headers number: each point's trace by its inline and crossline
        cube = survey.cube
        trace_of = {(int(i), int(x)): k for k, (i, x) in enumerate(zip(cube["iline"].values, cube["xline"].values))}
        lateral = [np.array([trace_of[(int(i), int(x))] for i, x in zip(table["inline"], table["crossline"])])]
    else:
        where = [np.searchsorted(labels, table[name]) for name, labels in
                 (("inline", survey.inlines), ("crossline", survey.xlines))]
        lateral = where if survey.kind == "cube" else [where[0] if survey.inlines.size > 1 else where[1]]
    points = np.column_stack([*lateral, k])
    grid = tuple(np.rint(points).astype(np.int64).T)
    angles = [read_seismic(folder / f"fault_{name}.sgy", **segy, arrays=False).data.reshape(survey.data.shape)[grid]
              for name in ("strike", "dip")]
    angles[1] = np.where(angles[1] > 0, angles[1], np.nan)  # a dip of 0: none computed (a computed one is > 0)
    normals = fault_normals(*angles, ndim=survey.data.ndim)
    faults, throws = [], []
    for fid in dict.fromkeys(table["fault_id"].tolist()):
        sel = table["fault_id"] == fid
        if not np.isfinite(normals[sel]).all(axis=1).any():
            raise InputError(f"fault {fid} of faults_from folder {folder} has no strike and dip at any of its points "
                             "(fault_strike.sgy, fault_dip.sgy); run `seismo3d faults` on the input again")
        faults.append(_Piece(points=points[sel], normals=_nearest_known(points[sel], normals[sel])))
        throws.append(_Piece(throw=table["throw_samples"][sel], correlation=table["throw_correlation"][sel],
                             correlation_unshifted=table["throw_correlation"][sel] - table["correlation_gain"][sel]))
    return _RecordedFaults(faults, throws)


def _nearest_known(points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """A fault's (n, ndim) normals with each row holding NaN (strike and dip not computed there: the likelihood
    below its orientation floor, where the votes bridged a gap) replaced by the nearest point's (``points``, (n, ndim)
    index space) that has one; at least one row must be finite."""
    from scipy.spatial import cKDTree

    known = np.isfinite(normals).all(axis=1)
    if known.all():
        return normals
    out = normals.copy()
    out[~known] = normals[known][cKDTree(points[known]).query(points[~known])[1]]
    return out


def _write_rows(output: pathlib.Path, survey: _Survey, horizon: Horizon) -> int:
    """'inline xline time' rows (a cube, or a line of a survey), or 'trace time' rows (a trace list)."""
    from ..seismic import write_horizon_text

    if survey.kind == "line":  # written on its (n_inlines, n_xlines) grid, one of them 1
        shape = (survey.inlines.size, survey.xlines.size)
        horizon = Horizon(horizon.times.reshape(shape), horizon.confidence.reshape(shape), horizon.polarity,
                          horizon.seeds)
    labels = survey.cube["trace"].values if survey.kind == "trace list" else survey.inlines
    return write_horizon_text(output, horizon, inlines=labels, xlines=survey.xlines, samples=survey.samples)


def run_horizon_job(input_path, seeds, output, *, polarity: str = "peak", faults: bool | None = None,
                    fill: bool = False, surface=None, iline: int = 189, xline: int = 193, ignore_geometry: bool = False,
                    endian=None, sample_unit=None, overwrite: bool = False, memory_limit=None,
                    progress: bool = True, seed_file=None, maps: bool = False, faults_from=None) -> HorizonJob:
    """Track a horizon in a SEG-Y cube or 2D line from seed picks and write it as text rows.

    Parameters
    ----------
    input_path : str or path-like
        SEG-Y file (either byte order), read once through :func:`seismo3d.open` (its headers, coordinates and
        samples; :func:`~seismo3d.jobs.inputs.read_seismic`); only read. A 3D cube
        (inline- or crossline-sorted), a 2D line of a survey (one inline or one crossline, e.g.
        ``penobscot_xl1155.sgy``), or a file without an inline / crossline grid, read as a trace list (an arbitrary or
        2D line, e.g. ``volve_fullstack_twt_arbline.sgy``; one warning says so).
    seeds : sequence of (float, float, float) or (float, float)
        Seed picks in the survey's terms: inline number, crossline number and time (or depth, in the file's sample
        unit) for a cube or a line of a survey; trace number (in file order, from 1) and time for a trace list.
    output : str or path-like
        The text file (written atomically; not the input): "inline xline time" rows, or "trace time" rows for a
        trace list.
    polarity : {'peak', 'trough', 'zero_rising', 'zero_falling'}
        The event the horizon follows.
    faults : bool or None
        Trace the faults first (:func:`seismo3d.seismic.trace_faults`) and let the tracker take their jumps where the
        correlation across them supports it, so that the horizon steps across a fault or stops at it instead of
        running through it. None (default): yes, on cubes, lines and trace lists alike, said in one log line; data
        the fault tracer refuses (e.g. a cube too small to trace) is tracked without them, said in one log line.
        True: always, and a refusal is raised. False: no faults (the tracker's own check of discontinuities only).
        In memory, or block by block when the cube's fault run does not fit ``memory_limit``
        (:func:`seismo3d.seismic.blocks.memory.fits_in_memory`). The cost: on Penobscot crossline 1155 (601 x 1501
        samples) about 8 s more than the 5 s of tracking alone on 2 cores; on a cube, minutes
        (``seismo3d faults``' times).
    fill : bool
        Fill empty traces by interpolation after tracking (:func:`seismo3d.seismic.fill_horizon`).
    surface : str or path-like, optional
        Also write the horizon as a surface (.vtp or .vtk; :func:`seismo3d.viz.horizon_surface`); 3D cubes only.
    iline, xline : int
        Trace header bytes of the inline and crossline numbers.
    ignore_geometry : bool
        Read the file as a trace list, without the warning a file without a grid gets.
    endian : {'big', 'little'}, optional
        Byte order of the file; by default detected from its binary header.
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of the sample axis; default from the SEG-Y headers.
    overwrite : bool
        Replace an existing ``output`` or ``surface`` (see :mod:`seismo3d.jobs.outputs`).
    memory_limit : int or str, optional
        Memory the fault tracing may use (default half of the RAM); a run by blocks keeps its stores in a temporary
        folder, removed at the end.
    progress : bool
        Report progress (:mod:`seismo3d._progress`).
    seed_file : str or path-like, optional
        More seeds from a file of picks: ``inline xline time`` rows, an IRAP / ZMAP+ grid or ``X Y Z`` points, placed
        on the survey by its coordinates (:func:`seismo3d.jobs.interchange.seeds_from_file`; at most 64 picks, spread
        through the file).
    faults_from : str or path-like, optional
        The output folder of a ``seismo3d faults`` run on this same file (checked by its ``run.json``): its faults are
        used instead of being traced again (their points, throws and the strike and dip volumes at them; in seconds
        where tracing a cube takes minutes). Not with ``faults=False``.
    maps : bool
        Also write the horizon beside ``output`` as IRAP ASCII (``.fgr``), IRAP binary (``.gri``), ZMAP+
        (``.zmap``) grids and ``X Y Z`` points (``.xyz``) in map coordinates, through xtgeo (a 2D line: ``.xyz``
        only; :func:`seismo3d.jobs.interchange.write_horizon_maps`).

    Returns
    -------
    HorizonJob
        ``horizon.times`` is (n_inlines, n_xlines) for a cube and (n_traces,) along a 2D line.

    Raises
    ------
    InputError
        An output that is the input, exists (without ``overwrite``) or cannot be written (checked before the input
        is read), a seed outside
        the data or with the wrong number of values (the message names ``--seed``), a surface asked for a 2D line.
    SegyGeometryError
        The file holds a single trace, or prestack gathers.
    SegyFormatError
        The file is not SEG-Y or cannot be read (see :func:`~seismo3d.seismic.open_segy`).
    UnsupportedDataError
        ``faults=True`` on data the fault tracer refuses.
    MissingDependencyError
        ``maps=True`` without xtgeo installed (before anything is read or written).

    Warns
    -----
    TraceListWarning
        The file has no inline / crossline grid and is read as a trace list (one line).
    """
    record = RunRecord("horizon", locals())  # first: the arguments as called
    from ..seismic import BlockRunOptions, TrackingOptions, fill_horizon, trace_faults, track_horizon
    from ..seismic.horizons import as_seeds, snap_seeds
    from .interchange import horizon_map_paths, seeds_from_file, write_horizon_maps

    input_path, output = pathlib.Path(input_path), pathlib.Path(output)
    surface = None if surface is None else pathlib.Path(surface)
    main = output_file(output, "horizon.txt")
    check_outputs([main, run_json_output(main), surface and output_file(surface, "horizon.vtp"),
                   *(output_file(p) for p in (horizon_map_paths(output) if maps else ()))],
                  [input_path, seed_file], overwrite=overwrite)
    if maps:  # the maps are written through xtgeo: refused before the work when it is not installed
        from ..seismic.io.horizon_grids import require_xtgeo

        try:
            require_xtgeo()
        except MissingDependencyError:
            raise MissingDependencyError("maps=True (--maps) writes the horizon's maps through xtgeo, which is not "
                                         "installed: pip install \"seismo3d[interchange]\", or leave out maps=True "
                                         "(--maps); nothing was written") from None
    if faults_from is not None:  # checked before the work
        if faults is False:
            raise InputError("faults=False (--no-faults) and faults_from contradict each other; leave out one")
        faults_from = pathlib.Path(faults_from)
        check_faults_run(faults_from, input_path)
    segy = dict(iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian)
    if not seeds and seed_file is None:
        raise InputError("no seeds; pass --seed IL,XL,T or --seed-file FILE")
    # read the cube or line (through seismo3d.open), and convert the seeds to index positions
    with record.stage("read"):
        survey = _read_survey(input_path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian,
                              sample_unit=sample_unit)
    if surface is not None and survey.kind != "cube":
        raise InputError(f"a horizon surface needs a 3D cube and {survey.name} is {survey.description}; leave out "
                         f"surface={surface} (--surface)")
    if seed_file is not None:  # placed on the survey by the coordinates of the headers read
        seeds = list(seeds) + seeds_from_file(seed_file, survey.coordinates, survey.name,
                                              trace_list=survey.kind == "trace list")
    index_seeds = _seed_indices(survey, seeds)
    # the seeds' picks checked before the faults are traced (the tracker checks them again)
    try:
        snap_seeds(survey.data, as_seeds(index_seeds, survey.data.shape), polarity=polarity,
                   window=TrackingOptions().seed_snap)
    except SeedError as exc:  # the library speaks of index positions: the user's inline, crossline and time
        raise _seed_error(exc, survey, seeds, index_seeds, polarity) from None
    # the faults first (by default; data the fault tracer refuses is tracked without them unless they were asked
    # for); then the horizon
    interp = None
    with tempfile.TemporaryDirectory(prefix="seismo3d-faults-") as work:  # the stores of a run by blocks
        if faults_from is not None:
            with record.stage("faults"):
                interp = _recorded_faults(faults_from, survey, segy)
            LOGGER.info("%s: the %d faults of %s reused (not traced again)", survey.name, len(interp.faults),
                        faults_from)
        elif faults is None or faults:
            if faults is None:
                LOGGER.info("%s: tracing its faults first so that the horizon steps across them (%s; --no-faults "
                            "skips them)", survey.name, "seconds on a line" if survey.kind != "cube" else
                            "minutes on a large cube")
            try:
                with record.stage("faults"), warnings.catch_warnings():
                    if faults is None:  # the fault tracer's notes on its likelihood (e.g. muted samples) are
                        warnings.simplefilter("ignore", Seismo3dWarning)  # for those who asked for the faults
                    interp = trace_faults(survey.data, sample_interval=float(survey.samples[1] - survey.samples[0]),
                                          sample_unit=survey.unit, progress=progress,
                                          blocks=BlockRunOptions(memory_limit=memory_limit, work_dir=work,
                                                                 source=survey.name))
            except (InputError, UnsupportedDataError) as exc:
                if faults:  # asked for: the refusal (e.g. a cube too small to trace) is the user's to see
                    raise
                LOGGER.info("%s: faults not traced (%s); the horizon is tracked without them", survey.name,
                            str(exc).splitlines()[0].rstrip("."))
        try:
            with record.stage("track"):
                result = track_horizon(survey.data, index_seeds, polarity=polarity, faults=interp, progress=progress)
        except SeedError as exc:  # the library speaks of index positions: the user's inline, crossline and time
            raise _seed_error(exc, survey, seeds, index_seeds, polarity) from None
    if fill:
        result = fill_horizon(result)
    # the outputs
    with record.stage("write"):
        n = _write_rows(output, survey, result)
        if surface is not None:
            from ..viz import horizon_surface, save_polydata

            save_polydata(horizon_surface(result, inlines=survey.inlines, xlines=survey.xlines,
                                          samples=survey.samples), surface)
        written_maps = write_horizon_maps(output, survey, result, survey.coordinates) if maps else None
    n_faults = 0 if interp is None else len(interp.faults)
    run_json = record.write(run_json_path(main), inputs={"input": input_path, "seed_file": seed_file,
                                                         **({"faults_from": faults_from / "fault_points.csv"}
                                                            if faults_from is not None else {})},
                            outputs={"horizon": output, "surface": surface, **(written_maps or {})},
                            results=dict(kind=survey.kind, n_rows=n, n_traces=int(result.times.size),
                                         coverage=float(result.coverage), n_faults=n_faults))
    return HorizonJob(result, n, output, surface, run_json, dict(record.stage_seconds), n_faults, written_maps)


def trace_seed_index(seed, n_traces: int, samples, unit: str) -> tuple[float, float]:
    """A seed on a trace list, (trace number from 1, time), to index space (trace index, fractional sample index).

    Parameters
    ----------
    seed : (float, float)
        Trace number in file order (1 to ``n_traces``) and time or depth in ``unit``.
    n_traces : int
    samples : (n_samples,) array_like of float
        The sample axis, ``unit``.
    unit : str
        The sample unit, for messages.

    Returns
    -------
    (float, float)

    Raises
    ------
    InputError
        A trace number that is not a whole number in 1..n_traces, or a time outside the samples (the message names
        ``--seed``).
    """
    trace, t = (float(v) for v in seed)
    text = f"{trace:g},{t:g}"
    if trace != round(trace) or not 1 <= trace <= n_traces:
        raise InputError(f"--seed {text}: trace {trace:g} is not a trace number of the file (1..{n_traces}, in file "
                         "order)")
    s = np.asarray(samples, dtype=np.float64)
    if not s[0] <= t <= s[-1]:
        raise InputError(f"--seed {text}: time {t:g} {unit} is outside the file's samples ({s[0]:g}..{s[-1]:g} {unit})")
    return trace - 1.0, float(np.interp(t, s, np.arange(s.size)))


def seed_index(seed, inlines, xlines, samples, unit: str) -> tuple[float, float, float]:
    """A seed in the survey's terms to index space.

    Parameters
    ----------
    seed : (float, float, float)
        Inline number, crossline number, time or depth in ``unit``.
    inlines, xlines : (n,) array_like of int
        The cube's inline and crossline numbers.
    samples : (n_samples,) array_like of float
        The cube's sample axis, ``unit``.
    unit : str
        The sample unit, for messages.

    Returns
    -------
    (float, float, float)
        Inline index, crossline index, fractional sample index.

    Raises
    ------
    InputError
        A line number not in the cube, or a time outside its samples (the message names ``--seed``).
    """
    il, xl, t = (float(v) for v in seed)
    text = f"{il:g},{xl:g},{t:g}"
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
