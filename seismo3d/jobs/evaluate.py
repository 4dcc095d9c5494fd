"""The ``seismo3d evaluate`` command: the faults a ``seismo3d faults`` run traced on a seismic line, scored against
people's faults on the same line (OpendTect fault sticks or a raster mask).

:func:`run_evaluate_job` reads the run's ``fault_points.csv`` (inline / crossline / time or depth of every fault
sample) and ``fault_summary.csv`` (the faults' confidence), reads the line the run traced (the input its
``run.json`` records, with the run's SEG-Y flags) to place both drawings on its traces and samples through the
SEG-Y headers (inline and crossline numbers, sample times), and scores them with
:func:`seismo3d.seismic.fault_scoring.score_fault_line`: tolerant precision, recall and F1, the fault-by-fault
matches, and the precision-recall curve over the faults' confidence. The fault benchmark
(``benchmarks/faults.py``) calls this job, so the project's numbers and a user's are one computation.

**People's faults.** Fault sticks (``sticks``): OpendTect's fault-stick ASCII (as ``seismo3d faults`` writes it, or
an interpreter's 8-column export such as the data folder's ``gsb_crl_*_faults_opendtect.dat``), Charisma or IESX,
read by :func:`~seismo3d.seismic.io.read_fault_sticks`; the sticks on the line are placed by their line numbers and
times (:mod:`seismo3d.seismic.io.stick_sections`), sticks of other lines are left out with a warning. A raster mask
(``mask``), the line's own shape:

- ``.npy``: a (n_traces, n_samples) array, traces in the SEG-Y file's order: nonzero = fault. An integer array
  holding more than one nonzero value is read as fault ids (each value one fault, as
  :func:`~seismo3d.seismic.fault_labels` gives them); otherwise each 8-connected group of fault samples is one fault.
- ``.png`` (or any image Pillow reads): rows = samples (time down), columns = traces in the file's order, as the
  section is seen; with an alpha channel a fault where alpha > 0 (a drawing on a transparent layer), otherwise where
  the pixel is nonzero; each 8-connected group one fault.

**Confidence.** The column ``confidence`` of ``fault_summary.csv`` when it has one, else ``mean_likelihood`` (the
fault network's mean probability along the fault, in [0, 1], for the default learned likelihood: what the evidence
compares with ``min_probability``). On the two Great South Basin lines the average precision barely depends on the
column (0.22-0.26 and 0.55-0.60 over seven columns of the summary: 3 and 7 faults are too few to tell them apart).
"""

from __future__ import annotations

import csv
import json
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._atomic import StagedFolder
from ..errors import DataNotFoundError, InputError, Seismo3dWarning
from ..seismic.fault_scoring import FaultLineScores, FaultScoringOptions, SectionFaults, score_fault_line
from .outputs import check_outputs, output_folder
from .runinfo import RUN_JSON, RunRecord, input_changed, jsonable, read_run_json

__all__ = ["CONFIDENCE_COLUMNS", "EvaluateJob", "RESULTS", "SeismicLine", "evaluation_table", "read_line",
           "read_people_faults", "read_picked_lines", "run_evaluate_job"]

RESULTS = ("evaluation.csv", "evaluation.json", "evaluation.png", RUN_JSON)  # what a run writes into its folder
CONFIDENCE_COLUMNS = ("confidence", "mean_likelihood")  # of fault_summary.csv, the first present is read
_FAULT_FILES = ("fault_points.csv", "fault_summary.csv", RUN_JSON)  # what evaluate reads of a faults folder
_SEGY_OPTIONS = ("iline", "xline", "endian", "ignore_geometry", "sample_unit")  # how the faults run read its input


@dataclass(frozen=True, eq=False)
class SeismicLine:
    """The line a faults run traced, as its traces and samples are named.

    Attributes
    ----------
    path : pathlib.Path
    section : (n_traces, n_samples) float32 ndarray
        Amplitudes, traces in the file's order.
    trace_labels : (n_traces,) float64 ndarray
        Inline numbers of a crossline, crossline numbers of an inline, trace indices of a 2D array.
    axis : {'inline', 'crossline'} or None
        Which number labels the traces (None: the trace index).
    fixed : (str, float) or None
        The line's own number: ``('crossline', 2600.0)`` for crossline 2600; None for a 2D array.
    samples : (n_samples,) float64 ndarray
        Two-way times (ms), depths, or sample indices, in ``sample_unit``.
    sample_unit : {'ms', 'm', 'ft', 'samples'}
    cube : xarray.DataArray or None
        The line as :func:`seismo3d.open` labels it (its ``cdp_x`` / ``cdp_y`` place sticks given by X / Y); None for
        a 2D array.
    """

    path: Path
    section: np.ndarray
    trace_labels: np.ndarray
    axis: str | None
    fixed: tuple | None
    samples: np.ndarray
    sample_unit: str
    cube: object = None

    @property
    def name(self) -> str:
        """In words: 'crossline 2600 of gsb_crl_2600.sgy'."""
        own = f"{self.fixed[0]} {self.fixed[1]:g}" if self.fixed else "the section"
        return f"{own} of {self.path.name}"


@dataclass(frozen=True, eq=False)
class EvaluateJob:
    """What :func:`run_evaluate_job` measured and wrote.

    Attributes
    ----------
    scores : FaultLineScores
    line : SeismicLine
    traced, people : SectionFaults
        Both drawings as placed on the line.
    people_source : str
        ``'sticks'`` or ``'mask'``.
    confidence_column : str or None
        The column of ``fault_summary.csv`` the precision-recall curve ranks the faults by (None: none found; the
        faults are added by id).
    written : dict
        ``{'csv': path, 'json': path, 'picture': path}``.
    run_json : pathlib.Path
    stage_seconds : dict
    """

    scores: FaultLineScores
    line: SeismicLine
    traced: SectionFaults
    people: SectionFaults
    people_source: str
    confidence_column: str | None
    written: dict
    run_json: Path | None = None
    stage_seconds: dict | None = None


def read_line(path, *, segy_options: dict | None = None) -> SeismicLine:
    """A seismic line (a SEG-Y inline or crossline, or a 2D ``.npy`` / ``.f32be`` section) as evaluate places faults on
    it, through the jobs' one reader (:func:`~seismo3d.jobs.inputs.read_seismic`).

    Parameters
    ----------
    path : str or os.PathLike
    segy_options : dict, optional
        ``iline``, ``xline``, ``endian``, ``ignore_geometry``, ``sample_unit`` as the faults run used them.

    Returns
    -------
    SeismicLine

    Raises
    ------
    InputError
        A 3D cube or a trace list: evaluate scores one line of a survey.
    DataNotFoundError, SegyFormatError, SegyGeometryError
        As :func:`~seismo3d.jobs.inputs.read_seismic`.
    """
    from .inputs import read_seismic

    seismic = read_seismic(path, **(segy_options or {}))
    line = _as_line(seismic)
    if line is None:
        raise InputError(f"{Path(path).name} is {seismic.description}, not one line: evaluate scores the faults of one "
                         "seismic line (an inline or crossline as SEG-Y, or a 2D array); trace a line and evaluate "
                         "that run")
    return line


def _as_line(seismic) -> SeismicLine | None:
    """A :class:`~seismo3d.jobs.inputs.SeismicInput` of one line as a :class:`SeismicLine`; None for anything else."""
    data, samples = seismic.data, np.asarray(seismic.samples, dtype=np.float64)
    if seismic.kind == "line":
        along_inlines = data.shape[1] == 1  # one crossline, many inlines
        index = ("crossline", 0) if along_inlines else ("inline", 0)
        return _grid_line(seismic, *index)
    if seismic.kind in ("array", "section") and data.ndim == 2:
        return SeismicLine(seismic.path, np.asarray(data, dtype=np.float32), np.arange(data.shape[0],
                           dtype=np.float64), None, None, samples, seismic.sample_unit)
    return None


def _grid_line(seismic, fixed: str, index: int) -> SeismicLine:
    """The inline (``fixed='inline'``) or crossline at ``index`` of a SEG-Y grid (a cube or a line), its traces in
    the file's order, read from a lazy cube only there."""
    if fixed == "inline":
        section, labels, number = seismic.data[index], seismic.xlines, seismic.inlines[index]
    else:
        section, labels, number = seismic.data[:, index], seismic.inlines, seismic.xlines[index]
    return SeismicLine(seismic.path, np.asarray(section, dtype=np.float32), np.asarray(labels, dtype=np.float64),
                       "crossline" if fixed == "inline" else "inline", (fixed, float(number)),
                       np.asarray(seismic.samples, dtype=np.float64), seismic.sample_unit, seismic.cube)


def read_picked_lines(path, *, sticks=None, mask=None, segy_options: dict | None = None) -> list:
    """The lines of a seismic file that people's faults were drawn on, each with its faults: the file's one line
    (a SEG-Y inline or crossline, a 2D ``.npy`` / ``.f32be`` section) with its sticks or mask
    (:func:`read_people_faults`), or the inlines and crosslines of a 3D SEG-Y cube that the fault sticks were picked
    on (:func:`~seismo3d.seismic.io.stick_sections.picked_sections`), taken out of it as sections (the cube is read
    lazily: only the picked lines' traces).

    Parameters
    ----------
    path : str or os.PathLike
        The seismic file.
    sticks, mask : str or os.PathLike, optional
        One of them: a fault-stick file (OpendTect, Charisma, IESX: the only kind for a cube), or a mask of the line
        (module notes).
    segy_options : dict, optional
        ``iline``, ``xline``, ``endian``, ``ignore_geometry``, ``sample_unit``.

    Returns
    -------
    list of (SeismicLine, SectionFaults)
        For a cube, its picked inlines by increasing number, then its crosslines.

    Raises
    ------
    InputError
        Both or neither of ``sticks`` and ``mask``; a trace list or a 3D array without line numbers; a mask for a
        cube; for a cube, a stick on no single inline or crossline, between two of them, outside the cube, or above
        or below its samples (the message names the stick); for a line, as :func:`read_people_faults`.
    DataNotFoundError, SegyFormatError, SegyGeometryError
        As :func:`~seismo3d.jobs.inputs.read_seismic`.
    """
    from .inputs import read_seismic

    if (sticks is None) == (mask is None):
        raise InputError("pass people's faults as either sticks=FILE (--sticks) or mask=FILE (--mask)")
    seismic = read_seismic(path, **(segy_options or {}), lazy_if=lambda shape: True)
    line = _as_line(seismic)
    if line is not None:
        return [(line, read_people_faults(line, sticks=sticks, mask=mask))]
    name = Path(path).name
    if seismic.kind != "cube":
        raise InputError(f"{name} is {seismic.description}, neither one line nor a 3D SEG-Y cube with inline / "
                         "crossline numbers to place fault sticks on; pass a SEG-Y line or cube, or a 2D section")
    if mask is not None:
        raise InputError(f"{name} is a 3D cube and a mask is of one line: pass the fault sticks picked on the cube's "
                         f"lines (--sticks FILE), or the picked line as its own SEG-Y or .npy with its mask")
    return _cube_picked_lines(seismic, Path(sticks))


def _cube_picked_lines(seismic, path: Path) -> list:
    """The inlines and crosslines of a SEG-Y cube that the sticks of ``path`` were picked on, with their sticks."""
    from ..seismic.io.coordinates import cube_coordinates
    from ..seismic.io.fault_sticks import read_fault_sticks
    from ..seismic.io.stick_sections import picked_sections

    if not path.is_file():
        raise DataNotFoundError(f"no fault-stick file at {path}; check the path")
    sticks = read_fault_sticks(path)
    if np.isnan(sticks.inline).any() or np.isnan(sticks.crossline).any():  # IESX: placed by X / Y, the cube's own
        sticks = read_fault_sticks(path, coordinates=cube_coordinates(seismic.cube))
    try:
        sections = picked_sections(sticks, seismic.inlines, seismic.xlines, seismic.samples)
    except InputError as exc:
        raise InputError(f"{path.name} on {seismic.path.name}: {exc}") from None
    out = []
    for picked in sections:
        line = _grid_line(seismic, picked.fixed, picked.index)
        out.append((line, SectionFaults.from_sticks(sticks.take(picked.nodes), line.trace_labels, line.samples,
                                                    axis=line.axis)))
    return out


def _run_input(folder: Path, seismic) -> tuple:
    """The line to place the faults on and the SEG-Y options to read it with: ``seismic`` if given, else the input
    the faults run's ``run.json`` records, while it is unchanged."""
    record = read_run_json(folder / RUN_JSON)
    options = (record or {}).get("options") or {}
    segy = {k: options[k] for k in _SEGY_OPTIONS if k in options}
    if seismic is not None:
        return Path(seismic), segy
    if record is None or record.get("command") != "faults":
        raise InputError(f"{folder} has no run.json of a 'seismo3d faults' run, so the line its faults were traced on "
                         "is unknown; pass seismic=LINE.sgy (--seismic), the line the run traced")
    entry = (record.get("inputs") or {}).get("input")
    if not isinstance(entry, dict) or "path" not in entry:
        raise InputError(f"the faults run of {folder} read no input file (a --demo run of a 3D cube); evaluate scores "
                         "the faults of a line: trace one and evaluate that run")
    problem = input_changed(entry)
    if problem is not None:
        raise InputError(f"the line the faults run of {folder} traced, {entry['path']}, {problem}; pass "
                         "seismic=LINE.sgy (--seismic), the line as the run read it")
    return Path(entry["path"]), segy


def _read_traced(folder: Path, line: SeismicLine) -> SectionFaults:
    """fault_points.csv placed on the line (:meth:`SectionFaults.from_positions`)."""
    path = folder / "fault_points.csv"
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
        columns = set(rows[0]) if rows else set()
    if not rows:
        return SectionFaults(np.zeros((0, 2), np.int64), np.zeros(0, np.int64), line.section.shape)
    label_column = line.axis or "trace"
    needed = {label_column, "time_or_depth", "fault_id"} | ({line.fixed[0]} if line.fixed else set())
    if not needed <= columns:
        raise InputError(f"{path} has the columns {sorted(columns)}, not {sorted(needed)} that fault points of "
                         f"{line.name} need; pass the output folder of 'seismo3d faults' on that line")
    if line.fixed:
        other = {float(r[line.fixed[0]]) for r in rows} - {line.fixed[1]}
        if other:
            raise InputError(f"the fault points of {path} are on {line.fixed[0]} {min(other):g}, not on {line.name}; "
                             "pass seismic=LINE.sgy (--seismic) of the line the faults were traced on")
    return SectionFaults.from_positions([float(r[label_column]) for r in rows],
                                        [float(r["time_or_depth"]) for r in rows],
                                        [int(r["fault_id"]) for r in rows], trace_labels=line.trace_labels,
                                        samples=line.samples)


def _read_confidence(folder: Path) -> tuple:
    """(column, {fault id: confidence}) of fault_summary.csv (:data:`CONFIDENCE_COLUMNS`); (None, {}) without."""
    path = folder / "fault_summary.csv"
    if not path.is_file():
        return None, {}
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
        columns = rows[0].keys() if rows else ()
    column = next((c for c in CONFIDENCE_COLUMNS if c in columns), None)
    if column is None:
        return None, {}
    return column, {int(r["id"]): float(r[column]) if r[column] else float("nan") for r in rows}


def read_people_faults(line: SeismicLine, *, sticks=None, mask=None) -> SectionFaults:
    """People's faults on a line, from fault sticks or a raster mask (the module notes), as evaluate places them.

    Parameters
    ----------
    line : SeismicLine
        From :func:`read_line`.
    sticks, mask : str or os.PathLike, optional
        One of them: an OpendTect, Charisma or IESX fault-stick file (sticks of other lines left out with a
        warning), or a mask of the line's shape (.npy or an image).

    Returns
    -------
    SectionFaults

    Raises
    ------
    InputError
        Both or neither given; no stick on the line; a mask of another shape; a line without inline / crossline
        numbers for sticks.
    DataNotFoundError
        No file at the path.
    """
    if (sticks is None) == (mask is None):
        raise InputError("pass people's faults as either sticks=FILE (--sticks) or mask=FILE (--mask)")
    if sticks is not None:
        if not Path(sticks).is_file():
            raise DataNotFoundError(f"no fault-stick file at {sticks}; check the path")
        return _read_sticks(Path(sticks), line)
    return _read_mask(Path(mask), line)


def _read_sticks(path: Path, line: SeismicLine) -> SectionFaults:
    """People's fault sticks on the line; sticks of other lines left out with a warning."""
    from ..seismic.io.coordinates import cube_coordinates
    from ..seismic.io.fault_sticks import read_fault_sticks

    if line.axis is None:
        raise InputError(f"fault sticks are placed by inline / crossline numbers, and {line.path.name} has none; draw "
                         "people's faults as a mask of the section instead (mask=FILE, --mask)")
    sticks = read_fault_sticks(path)
    if np.isnan(sticks.inline).any() or np.isnan(sticks.crossline).any():  # IESX: placed by X / Y, the line's own
        sticks = read_fault_sticks(path, coordinates=cube_coordinates(line.cube))
    own = getattr(sticks, line.fixed[0])
    on_line = np.abs(own - line.fixed[1]) <= 0.5
    keep = [nodes for _, nodes in sticks.sticks() if on_line[nodes].all()]
    if not keep:
        raise InputError(f"none of the {sticks.n_sticks} fault sticks of {path.name} lies on {line.name} (they are "
                         f"on {line.fixed[0]}s {np.nanmin(own):g}-{np.nanmax(own):g}); pass the sticks of this line")
    if len(keep) < sticks.n_sticks:
        warnings.warn(f"{sticks.n_sticks - len(keep)} of the {sticks.n_sticks} fault sticks of {path.name} are not on "
                      f"{line.name} and were left out", Seismo3dWarning, stacklevel=3)
        sticks = sticks.take(np.concatenate(keep))
    return SectionFaults.from_sticks(sticks, line.trace_labels, line.samples, axis=line.axis)


def _read_mask(path: Path, line: SeismicLine) -> SectionFaults:
    """A raster mask of the line (module notes): .npy (n_traces, n_samples), or an image of n_samples rows."""
    if not path.is_file():
        raise DataNotFoundError(f"no mask file at {path}; check the path")
    n_traces, n_samples = line.section.shape
    if path.suffix.lower() == ".npy":
        try:
            mask = np.load(path, allow_pickle=False)
        except (ValueError, OSError) as exc:
            raise InputError(f"{path.name} is not a readable .npy array ({exc}); save it with numpy.save") from None
        expected, layout = (n_traces, n_samples), "(n_traces, n_samples)"
    else:
        from PIL import Image, UnidentifiedImageError

        try:
            with Image.open(path) as image:
                if image.mode == "P":
                    image = image.convert("RGBA")
                bands = np.asarray(image)
                alpha = "A" in image.getbands()
        except (UnidentifiedImageError, OSError) as exc:
            raise InputError(f"{path.name} is neither a .npy array nor an image Pillow reads ({exc}); save the mask as "
                             ".npy (n_traces, n_samples) or .png (n_samples rows, n_traces columns)") from None
        if bands.ndim == 3:
            bands = bands[..., -1] if alpha else bands.max(axis=-1)
        mask = bands.T  # columns are traces
        expected, layout = (n_traces, n_samples), "n_samples rows x n_traces columns"
    if mask.ndim != 2 or mask.shape != expected:
        shown = mask.shape if path.suffix.lower() == ".npy" else mask.shape[::-1]
        flipped = " (transposed: save mask.T)" if mask.shape == expected[::-1] else ""
        raise InputError(f"the mask {path.name} is {' x '.join(map(str, shown))}{flipped}, but {line.name} has "
                         f"{n_traces} traces and {n_samples} samples: a mask must be {layout}, here "
                         f"{' x '.join(map(str, expected if path.suffix.lower() == '.npy' else expected[::-1]))}")
    if np.issubdtype(mask.dtype, np.integer) and np.unique(mask[mask != 0]).size > 1:
        return SectionFaults.from_labels(mask)
    return SectionFaults.from_mask(mask)


def run_evaluate_job(faults_output, *, sticks=None, mask=None, out=None, seismic=None,
                     options: FaultScoringOptions | None = None, overwrite: bool = False,
                     picture: bool = True) -> EvaluateJob:
    """Score the faults of a ``seismo3d faults`` run on a line against people's faults: the ``seismo3d evaluate``
    command (module notes).

    Writes into ``out`` (created if missing; the files moved in together once all are written):

    - ``evaluation.csv``: a row per fault of both drawings: ``drawing`` ('people' or 'traced'), ``fault_id``,
      ``name``, ``n_samples`` (of the line it crosses), ``recall`` (people's: the share of its samples within the
      tolerance of a traced fault), ``precision`` (traced: the share of its samples within the tolerance of people's
      faults), ``confidence`` (traced), ``matches`` (the other drawing's faults it matches, ids separated by ``;``);
    - ``evaluation.json``: the line's precision, recall and F1, the tolerance, both tables, every pair of faults near
      each other (the shares both ways), and the precision-recall curve with its average precision;
    - ``evaluation.png``: both drawings over the line, and the curve (:func:`~seismo3d.viz.plot_fault_evaluation`);
    - ``run.json``: the record of the run (:mod:`seismo3d.jobs.runinfo`).

    Parameters
    ----------
    faults_output : str or os.PathLike
        The output folder of ``seismo3d faults`` on one line (its ``fault_points.csv``, ``fault_summary.csv`` and
        ``run.json``).
    sticks, mask : str or os.PathLike
        People's faults: fault sticks or a raster mask (module notes); exactly one.
    out : str or os.PathLike, optional
        Where to write; default ``<faults_output>/evaluation``. Not a folder holding an input, nor one holding an
        earlier evaluation unless ``overwrite`` (:mod:`seismo3d.jobs.outputs`; checked before anything is read).
    seismic : str or os.PathLike, optional
        The line the faults were traced on; default the input the run's ``run.json`` records (refused once changed).
    options : FaultScoringOptions, optional
        The tolerance (3 samples) and the share of a fault that makes a match (0.5).
    overwrite : bool, optional
        Replace an earlier evaluation in ``out``.
    picture : bool, optional
        Draw ``evaluation.png`` (about a second); False leaves it out (and removes an earlier one it replaces).

    Returns
    -------
    EvaluateJob

    Raises
    ------
    InputError
        Neither or both of ``sticks`` and ``mask``; an output that holds an input, holds an earlier evaluation
        (without ``overwrite``) or cannot be written; a folder without ``fault_points.csv``; a run without a recorded
        line (or one that changed) and no ``seismic``; a 3D cube; fault points or sticks of another line; a mask of
        another shape than the line (the message gives both).
    DataNotFoundError
        A missing file.
    """
    record = RunRecord("evaluate", locals())  # first: the arguments as called
    folder = Path(faults_output)
    if (sticks is None) == (mask is None):
        raise InputError("give people's faults as fault sticks or as a mask: sticks=FILE (--sticks) or mask=FILE "
                         "(--mask), one of them")
    out = folder / "evaluation" if out is None else Path(out)
    reads = [folder / name for name in _FAULT_FILES]
    check_outputs([output_folder(out, RESULTS, f"{folder.name}_evaluation")], [folder, *reads, sticks, mask, seismic],
                  overwrite=overwrite)
    if not folder.is_dir():
        raise DataNotFoundError(f"no folder at {folder}; pass the output folder of 'seismo3d faults'")
    if not (folder / "fault_points.csv").is_file():
        raise InputError(f"{folder} holds no fault_points.csv: pass the output folder of 'seismo3d faults' on a line")
    options = options or FaultScoringOptions()
    with record.stage("read"):
        segy_path, segy_options = _run_input(folder, seismic)
        line = read_line(segy_path, segy_options=segy_options)
        traced = _read_traced(folder, line)
        column, confidence = _read_confidence(folder)
        people = _read_sticks(Path(sticks), line) if sticks is not None else _read_mask(Path(mask), line)
    with record.stage("score"):
        scores = score_fault_line(traced, people, confidence=confidence, options=options)
    source = "sticks" if sticks is not None else "mask"
    job = EvaluateJob(scores, line, traced, people, source, column, {})
    with StagedFolder(out) as stage:
        with record.stage("write"):
            written = _write_files(stage.path, job, sticks if sticks is not None else mask, picture)
        final = {key: stage.final(path) for key, path in written.items()}
        record.write(stage.path / RUN_JSON, inputs={"fault_points": folder / "fault_points.csv",
                                                    "fault_summary": folder / "fault_summary.csv",
                                                    "seismic": segy_path, source: sticks or mask},
                     outputs=final, results=dict(precision=scores.precision, recall=scores.recall, f1=scores.f1,
                                                 average_precision=scores.curve.average_precision))
    if not picture:
        (out / "evaluation.png").unlink(missing_ok=True)  # an earlier run's, replaced (overwrite was checked)
    return EvaluateJob(scores, line, traced, people, source, column, final, out / RUN_JSON,
                       dict(record.stage_seconds))


def _write_files(folder: Path, job: EvaluateJob, people_path, picture: bool) -> dict:
    """evaluation.csv, evaluation.json and (``picture``) evaluation.png into ``folder``, by key."""
    from .._atomic import atomic_path
    from ..viz.fault_evaluation import plot_fault_evaluation

    s = job.scores
    rows = [["drawing", "fault_id", "name", "n_samples", "recall", "precision", "confidence", "matches"]]
    rows += [["people", f.fault_id, f.name, f.n_samples, f"{f.recall:.6g}", "", "", ";".join(map(str, f.matches))]
             for f in s.people]
    rows += [["traced", f.fault_id, f"fault {f.fault_id}", f.n_samples, "", f"{f.precision:.6g}",
              "" if not np.isfinite(f.confidence) else f"{f.confidence:.6g}", ";".join(map(str, f.matches))]
             for f in s.traced]
    with atomic_path(folder / "evaluation.csv") as tmp, open(tmp, "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)
    summary = {
        "line": job.line.name, "seismic": str(job.line.path), "people": {"kind": job.people_source,
                                                                         "path": str(people_path)},
        "tolerance_samples": s.tolerance, "precision": s.precision, "recall": s.recall, "f1": s.f1,
        "n_traced_samples": s.n_traced, "n_people_samples": s.n_people, "confidence_column": job.confidence_column,
        "average_precision": s.curve.average_precision,
        "precision_recall_curve": {"confidence": [None if not np.isfinite(c) else float(c) for c in s.curve.confidence],
                                   "fault_ids": s.curve.fault_ids, "n_faults": s.curve.n_faults,
                                   "precision": s.curve.precision, "recall": s.curve.recall},
        "people_faults": s.people, "traced_faults": s.traced, "pairs": s.pairs,
    }
    with atomic_path(folder / "evaluation.json") as tmp:
        tmp.write_text(json.dumps(_finite(jsonable(summary)), indent=1) + "\n")
    written = {"csv": folder / "evaluation.csv", "json": folder / "evaluation.json"}
    if not picture:
        return written
    line = job.line
    unit = {"ms": "time (ms)", "m": "depth (m)", "ft": "depth (ft)"}.get(line.sample_unit, "sample")
    drawn = "fault sticks" if job.people_source == "sticks" else "a mask"
    title = (f"{line.name}: {len(s.people)} people's faults ({drawn}) and {len(s.traced)} traced faults\n"
             f"precision {s.precision:.3f}, recall {s.recall:.3f}, F1 {s.f1:.3f} within {s.tolerance:g} "
             "samples")
    drawn_to = plot_fault_evaluation(line.section, job.people.labels(), job.traced.labels(),
                                     path=folder / "evaluation.png", traces=line.trace_labels, samples=line.samples,
                                     axis_labels=(line.axis or "trace", unit), title=title, curve=s.curve)
    return {**written, "picture": drawn_to}


def _finite(value):
    """NaN as null, for strict JSON."""
    if isinstance(value, float):
        return value if np.isfinite(value) else None
    if isinstance(value, list):
        return [_finite(v) for v in value]
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    return value


def evaluation_table(job: EvaluateJob) -> list:
    """The lines ``seismo3d evaluate`` prints: the line's scores, both fault tables and the curve.

    Parameters
    ----------
    job : EvaluateJob

    Returns
    -------
    list of str
    """
    s = job.scores
    out = [f"{job.line.name}: precision {s.precision:.3f}  recall {s.recall:.3f}  F1 {s.f1:.3f}  (within "
           f"{s.tolerance:g} samples; {len(s.traced)} traced faults, {len(s.people)} people's faults from "
           f"{job.people_source})", "", f"{'people fault':>16s} {'samples':>7s} {'recall':>6s}  matched by traced"]
    out += [f"{f.name[:16]:>16s} {f.n_samples:7d} {f.recall:6.2f}  {', '.join(map(str, f.matches)) or '-'}"
            for f in s.people]
    out += ["", f"{'traced fault':>16s} {'samples':>7s} {'precision':>9s} {'confidence':>10s}  matches people's"]
    out += [f"{f.fault_id:16d} {f.n_samples:7d} {f.precision:9.2f} {f.confidence:10.3f}  "
            f"{', '.join(job.people.name(j) for j in f.matches) or '-'}" for f in s.traced]
    c = s.curve
    by = job.confidence_column or "fault id (no confidence column)"
    out += ["", f"precision-recall adding faults by {by}: average precision {c.average_precision:.3f}"]
    out += ["  " + "  ".join(f"{int(n)}: P {p:.2f} R {r:.2f}" for n, p, r in zip(c.n_faults, c.precision, c.recall))]
    return out
