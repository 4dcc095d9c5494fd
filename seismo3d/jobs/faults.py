"""The ``seismo3d faults`` job: read a seismic file (or make the demo cube), trace its faults, write the results.

:func:`run_faults_job` reads an input file (SEG-Y cube, 2D SEG-Y line, raw ``.f32be`` section, ``.npy`` array) or
makes a synthetic cube, runs :func:`seismo3d.seismic.trace_faults` and writes the outputs of ``seismo3d faults`` (see
its docstring for the list of files and their columns). Every file is written atomically; the input is only read.

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.faults.likelihood.scan`.
"""

from __future__ import annotations

import csv
import shutil
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import segyio

from .._atomic import SetAside, StagedFolder, atomic_path
from .._progress import LOGGER, progress_steps
from .._validation import check_choice
from ..errors import EarlierStoresError, InputError, Seismo3dWarning
from ..seismic.blocks.memory import fits_in_memory, in_memory_bytes, parse_memory_limit, resident_memory, size_text
from ..seismic.faults.blocks.cube_run import LIKELIHOOD_STORE, SURFACES_STORE
from ..seismic.blocks.options import BlockRunOptions
from ..seismic.faults.result import FaultInterpretation
from ..seismic.faults.options import FaultTracingOptions
from ..seismic.faults.pipeline import trace_faults
from ..seismic.io.lazy import open_lazy
from ..seismic.io.segy import open_segy
from ..seismic.io.writer import write_like, write_like_blocks
from .fault_tables import write_points, write_summary
from .inputs import read_seismic
from .interchange import FAULT_INTERCHANGE_FILES, fault_coordinates, fault_interchange_steps
from .outputs import check_outputs, output_folder
from .runinfo import RUN_JSON, RunRecord

__all__ = ["FaultsJobResult", "RESULTS", "run_faults_job"]

# What a run writes into its folder (SEG-Y volumes for a SEG-Y input, .npy otherwise; the demo's cube and truth).
# The Zarr stores of a block-by-block run are not among them: they are reused or resumed by the next run.
RESULTS = tuple(f"fault_{name}.{ext}" for ext in ("sgy", "npy") for name in ("likelihood", "strike", "dip", "votes")) + (
    "faults.vtp", "fault_points.csv", "fault_summary.csv", "faults.png", "demo_seismic.sgy", "demo_truth.csv",
    RUN_JSON) + FAULT_INTERCHANGE_FILES

_DEMO_SHAPE = (128, 128, 128)
_DEMO_DT_MS = 4.0


@dataclass(frozen=True)
class FaultsJobResult:
    """What :func:`run_faults_job` wrote and found.

    Attributes
    ----------
    written : dict of str to pathlib.Path
        The files written, by key (see :func:`run_faults_job`'s Returns), and ``run_json``.
    faults : tuple of dict
        One row per fault as written to ``fault_summary.csv``: column name to the text written.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage, seconds: ``read input``, each step of the fault interpretation
        (:attr:`~seismo3d.seismic.faults.FaultInterpretation.step_seconds`) and ``write outputs``.
    """

    written: dict
    faults: tuple
    run_json: Path
    stage_seconds: dict

    @property
    def n_faults(self) -> int:
        """How many faults were kept."""
        return len(self.faults)


# --------------------------------------------------------------------------------------------------------------------
# inputs


@dataclass(frozen=True)
class _Input:
    """What the job read: the array it traces and how to label and write results."""

    data: np.ndarray  # (n_il, n_xl, ns) 3D or (n_traces, ns) 2D
    name: str
    segy_path: Path | None  # template for SEG-Y outputs
    segy_shape: tuple | None  # the template's grid shape (cube.shape) to write 2D results back into
    inline: np.ndarray  # inline number per inline (3D) or per trace (2D; the trace index for raw sections)
    xline: np.ndarray | None  # crossline number per crossline (3D) or per trace (2D); None for raw sections
    samples: np.ndarray  # (ns,) sample positions in `unit` (sample index for 'samples')
    unit: str
    trace_axis: str = "trace"  # 2D: what labels the traces in pictures: 'inline', 'crossline' or 'trace' (index)
    sorting: str | None = None  # SEG-Y trace order of a grid: 'inline' or 'crossline'

    def file_order(self, values: np.ndarray) -> np.ndarray:
        """(n_traces, n_samples) of an array shaped like ``data``, in the SEG-Y file's trace order."""
        ns = values.shape[-1]
        if self.segy_shape is None:  # trace list: already in file order (contiguous float32 for segyio)
            return np.ascontiguousarray(values.reshape(-1, ns), dtype=np.float32)
        grid = values.reshape(self.segy_shape)
        if self.sorting == "crossline":
            grid = np.swapaxes(grid, 0, 1)
        return np.ascontiguousarray(grid, dtype=np.float32).reshape(-1, ns)

    @property
    def axes(self) -> tuple:
        """Annotation of each array axis: (inlines, crosslines, samples) in 3D, (trace labels, samples) in 2D."""
        if self.data.ndim == 3:
            return (self.inline, self.xline, self.samples)
        lateral = {"inline": self.inline, "crossline": self.xline}.get(self.trace_axis)
        return (np.arange(self.data.shape[0]) if lateral is None else lateral, self.samples)

    @property
    def labels(self) -> tuple:
        """Axis names for pictures."""
        vertical = {"samples": "sample", "ms": "time (ms)", "m": "depth (m)", "ft": "depth (ft)"}[self.unit]
        if self.data.ndim == 3:
            return ("inline", "crossline", vertical)
        return (self.trace_axis, vertical)


def _read_input(path, *, iline, xline, ignore_geometry, sample_unit, n_samples, endian=None) -> _Input:
    """The input through the jobs' one reader (:func:`~seismo3d.jobs.inputs.read_seismic`), labelled for the
    outputs."""
    seismic = read_seismic(path, iline=iline, xline=xline, ignore_geometry=ignore_geometry, sample_unit=sample_unit,
                           n_samples=n_samples, endian=endian)
    path, data, samples, unit = seismic.path, seismic.data, seismic.samples, seismic.sample_unit
    if not seismic.is_segy:  # .npy, .f32be: traces labelled by their index
        idx = [np.arange(n, dtype=np.int64) for n in data.shape]
        return _Input(np.asarray(data), path.stem, None, None, idx[0], idx[1] if data.ndim == 3 else None, samples,
                      unit)
    if seismic.kind == "trace list":  # label traces with their header inline / crossline numbers, if any
        il, xl = seismic.trace_inlines.astype(np.int64), seismic.trace_xlines.astype(np.int64)
        if np.all(il == il[0]) and np.all(xl == xl[0]):  # no numbers there: the trace index
            il, xl = np.arange(il.size, dtype=np.int64), None
        return _Input(data, path.stem, path, None, il, xl, samples, unit, "trace")
    LOGGER.info("%s: %s, %d samples of %g %s, %s, %s-endian", path.name, seismic.description, samples.size,
                seismic.sample_interval, unit, seismic.format_name, seismic.endian)
    il, xl = seismic.inlines.astype(np.int64), seismic.xlines.astype(np.int64)
    shape, sorting = seismic.grid_shape, seismic.sorting
    if seismic.kind == "cube":
        return _Input(data, path.stem, path, shape, il, xl, samples, unit, "trace", sorting)
    if shape[1] == 1:  # a line along inlines (one crossline), e.g. penobscot_xl1155
        return _Input(data[:, 0, :], path.stem, path, shape, il, np.full(il.size, xl[0]), samples, unit, "inline",
                      sorting)
    return _Input(data[0], path.stem, path, shape, np.full(xl.size, il[0]), xl, samples, unit, "crossline", sorting)


def _demo_input(out_dir: Path, seed) -> tuple[Path, Path]:
    """Write a synthetic cube as SEG-Y (4 ms, inlines / crosslines 1..128) and its true faults (CSV) into ``out_dir``;
    the two files' paths (the cube is then read like any SEG-Y input)."""
    from ..data.synthetic import synthetic_cube  # 0.5 s of imports (the data package): only for --demo

    syn = synthetic_cube(_DEMO_SHAPE, seed=seed)
    path = out_dir / "demo_seismic.sgy"
    with atomic_path(path) as tmp:
        segyio.tools.from_array3D(str(tmp), syn.cube, format=5, dt=int(_DEMO_DT_MS * 1000))
    truth = out_dir / "demo_truth.csv"
    with atomic_path(truth) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["id", "kind", "strike_deg", "dip_deg", "throw_samples", "throw_ms", "throw_gradient"])
        for f in syn.faults:
            signed = f.throw_samples if f.kind == "normal" else -f.throw_samples  # + = hanging wall down
            w.writerow([f.id, f.kind, f"{f.strike_deg:.1f}", f"{f.dip_deg:.1f}", f"{signed:.5g}",
                        f"{signed * _DEMO_DT_MS:.5g}", f"{f.throw_gradient:.4g}"])
    del syn
    return path, truth


# --------------------------------------------------------------------------------------------------------------------
# the job: outputs


def _write_volume(inp: _Input, out_dir: Path, stem: str, values: np.ndarray, *, like=None, iline, xline,
                  ignore_geometry, endian=None) -> Path:
    """SEG-Y with the input's headers for a SEG-Y input, .npy otherwise.

    With ``like`` (a SEG-Y file this job already wrote with :func:`~seismo3d.seismic.io.write_like`), the file is a
    copy of it with the trace data replaced: the same headers, without copying them field by field again.
    """
    if inp.segy_path is not None:
        out = out_dir / f"{stem}.sgy"
        if like is None:
            grid = values.reshape(inp.segy_shape) if inp.segy_shape is not None else values
            return write_like(inp.segy_path, out, grid, iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                              endian=endian)
        traces = inp.file_order(values)
        with atomic_path(out) as tmp:
            shutil.copyfile(like, tmp)
            with segyio.open(str(tmp), "r+", ignore_geometry=True) as f:
                if f.tracecount != traces.shape[0] or len(f.samples) != traces.shape[1]:  # pragma: no cover
                    raise RuntimeError(f"{like} does not match the input's {traces.shape} traces")
                f.trace.raw[:] = traces
        return out
    out = out_dir / f"{stem}.npy"
    with atomic_path(out) as tmp:
        with open(tmp, "wb") as fh:
            np.save(fh, np.asarray(values, dtype=np.float32), allow_pickle=False)
    return out


@dataclass(frozen=True)
class LazyInput:
    """A 3D input read block by block: its lazy amplitudes and what labels them."""

    data: object  # (n_il, n_xl, ns) float32 dask array, chunks of whole traces
    name: str
    inline: np.ndarray
    xline: np.ndarray
    samples: np.ndarray  # in `unit` (sample index for 'samples')
    unit: str  # 'ms', 'm', 'ft' or 'samples'
    segy: dict | None = None  # a SEG-Y input: template path and how to open it, for SEG-Y outputs

    @property
    def coords(self) -> dict:
        """Coordinates for the output Zarr group."""
        return {"inline": self.inline, "crossline": self.xline, "sample": self.samples, "sample_unit": self.unit}


def _lazy_if_too_large(path, limit: int, held: int, *, iline, xline, sample_unit, endian) -> LazyInput | None:
    """The input read lazily when it is a Zarr store, or a 3D SEG-Y cube or ``.npy`` array whose in-memory run does
    not fit ``limit`` beside the ``held`` bytes of the process (:func:`~seismo3d.seismic.blocks.memory.fits_in_memory`);
    else None (the in-memory run)."""

    if path is None:
        return None
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".f32be" or not path.exists():
        return None  # 2D sections; a missing file is reported by _read_input
    if suffix == ".npy":
        try:
            arr = np.load(path, allow_pickle=False, mmap_mode="r")
        except (ValueError, OSError):
            return None  # _read_input says why
        if arr.ndim != 3 or fits_in_memory(arr.shape, limit, held=held):
            return None
        if sample_unit is not None:
            raise InputError(f"{path.name} has no sample interval, so --sample-unit cannot be used; its results are "
                             "in samples")
        import dask.array as da

        idx = [np.arange(n, dtype=np.int64) for n in arr.shape]
        data = da.from_array(arr, chunks=(_TILE, _TILE, -1))
        return LazyInput(data.astype(np.float32), path.stem, idx[0], idx[1], idx[2].astype(np.float64), "samples")
    if not path.is_dir():
        with warnings.catch_warnings():  # only the size is wanted here: the reading that follows warns, once
            warnings.simplefilter("ignore", Seismo3dWarning)
            cube = open_segy(path, iline=iline, xline=xline, sample_unit=sample_unit, endian=endian)
        with cube:
            if not cube.is_3d or cube.inlines is None or fits_in_memory(cube.shape, limit, held=held):
                return None
    lazy = open_lazy(path, iline=iline, xline=xline, sample_unit=sample_unit, endian=endian, tile=_TILE)
    segy = None if path.is_dir() else {"template_path": path, "iline": iline, "xline": xline, "endian": endian}
    return LazyInput(lazy.data, path.stem if path.is_file() else path.name.split(".")[0], np.asarray(lazy.inlines),
                     np.asarray(lazy.xlines), np.asarray(lazy.samples, dtype=np.float64), lazy.sample_unit, segy)


def run_faults_job(input_path, out_dir, *, demo=False, demo_seed=0, iline=189, xline=193, ignore_geometry=False,
                   endian=None, sample_unit=None, n_samples=None, sensitivity=0.5, likelihood="learned",
                   memory_limit=None, scheduler=None, overwrite=False, progress=True) -> FaultsJobResult:
    """Trace the faults of a seismic file and write the results: the ``seismo3d faults`` command.

    Inputs
    ------
    * a SEG-Y 3D cube (any sorting, either byte order, inline / crossline numbers at trace bytes ``iline`` /
      ``xline``), read by :func:`~seismo3d.seismic.io.open_segy` like every SEG-Y input of seismo3d;
    * a 2D SEG-Y line: one inline or one crossline of a survey (e.g. ``penobscot_xl1155.sgy``, shape (601, 1, 1501)),
      or a file without an inline / crossline grid, read as a trace list (an arbitrary or 2D line such as
      ``volve_fullstack_twt_arbline.sgy``; one warning says so); traced as a 2D section;
    * a raw section ``.f32be`` (big-endian float32, trace after trace; see :func:`~seismo3d.seismic.io.read_section`);
    * a ``.npy`` array, 2D (n_traces, n_samples) or 3D (n_inlines, n_xlines, n_samples);
    * nothing, with ``demo=True``: a synthetic 128^3 cube with 3 faults (:func:`~seismo3d.data.synthetic_cube`)
      is written as ``demo_seismic.sgy`` (inlines and crosslines 1..128, 4 ms) into ``out_dir`` and traced; its
      true faults go to ``demo_truth.csv`` (columns ``id, kind, strike_deg, dip_deg, throw_samples, throw_ms,
      throw_gradient``: the throw at the fault's reference point, + for hanging wall down, and its change per trace
      along strike), to compare with ``fault_summary.csv``.

    The input is read whole into memory unless it is too large (below); it is never written to.

    Outputs (in ``out_dir``, created if needed; written into a staging folder and moved in together once every one
    is written, so a failed or interrupted run leaves the previous files or none, never a mix or a half-written one)
    -------------------------------------------------------------------------------------------------------------
    * ``fault_likelihood.sgy``, ``fault_strike.sgy``, ``fault_dip.sgy``, ``fault_votes.sgy``: fault likelihood in
      [0, 1], strike and dip in degrees, and the optimal-surface votes in [0, 1], as SEG-Y with the textual, binary
      and trace headers of the input (for a SEG-Y input; IEEE float). For other inputs the same volumes as float32
      ``.npy`` arrays of the input's shape.
    * ``faults.vtp``: all fault surfaces (triangulated; polylines for 2D inputs) in one VTK PolyData, points at
      (inline, crossline, time_or_depth) (2D: (trace label, 0, time_or_depth)), point arrays ``fault_id``,
      ``throw`` (samples) and ``likelihood``.
    * ``fault_points.csv``: one row per fault sample, columns ``inline, crossline, time_or_depth, fault_id,
      throw_samples, throw_<unit>, throw_correlation, correlation_gain, side_coherence``; ``time_or_depth`` is in the
      sample unit (ms, m or ft from the SEG-Y headers or ``sample_unit``; the sample index for raw sections and
      ``.npy``, which have no ``throw_<unit>`` column). For raw sections, 2D ``.npy`` arrays and trace lists whose
      inline / crossline header bytes hold no numbers, one ``trace`` column (the trace index, from 0) replaces
      ``inline, crossline``. Throw is positive where the hanging wall moved down (normal fault); ``throw_correlation``
      (in [-1, 1]) is the normalised cross-correlation of the reflectors on the two sides once aligned, a quality
      measure (see
      :class:`~seismo3d.seismic.faults.throw.FaultThrow`); ``correlation_gain`` is that correlation less the sides'
      correlation with no shift (the evidence of a displacement); ``side_coherence`` how continuous the reflectors are
      along each side in itself (the smaller of the two sides; reported, not asked for: sides that do not match say less
      of a fault when they are not continuous themselves). An unmeasured throw is empty.
    * ``fault_summary.csv``: one row per fault, columns ``id, n_points, mean_strike_deg, mean_dip_deg,
      median_throw_samples, median_throw_<unit>, throw_spread_samples, throw_correlation, correlation_gain,
      side_coherence, vote_ratio, mean_likelihood`` (``throw_spread_samples`` is empty on a 2D line: its faults'
      throws are one shift each, with no spread measured): the
      evidence each fault shows (:class:`~seismo3d.seismic.faults.evidence.FaultEvidence`; only faults whose votes
      hold along them and whose reflectors are displaced, or which the network calls likely, are kept:
      :func:`~seismo3d.seismic.faults.evidence.supported_faults`), to sort and filter on; ``vote_ratio`` is the
      fault's mean thinned votes over the run's upper vote threshold, ``mean_likelihood`` its mean fault likelihood;
      for 2D inputs ``dips_toward`` (e.g. ``increasing inline``)
      replaces the strike. Strike and dip are in index space (one trace step = one sample; strike from the inline
      axis toward the crossline axis, see :mod:`seismo3d.seismic.faults.likelihood.scan`).
    * ``fault_sticks_opendtect.txt``, ``fault_sticks_charisma.txt``, ``fault_sticks_iesx.txt``: every fault's points
      along each line that cuts it, as fault sticks in map coordinates (OpendTect ASCII, and Charisma and IESX, which
      Petrel imports); ``fault_surfaces_gocad.ts``: the triangulated faults of ``faults.vtp`` as GOCAD TSurf, 3D
      inputs (:mod:`seismo3d.jobs.interchange`). ``fault_points.csv`` holds ``x``, ``y`` and ``xy_unit`` after the
      crossline: each point's trace's CDP X/Y with the coordinate scalar applied, or its inline and crossline numbers
      with ``xy_unit`` ``inline/crossline`` for an input without coordinates.
    * ``faults.png``: an inline, a crossline and a time slice (the most faulted of each) with the faults drawn over
      the seismic, coloured by their |median throw| (in the sample unit), above the same slices of the fault
      likelihood; for 2D inputs the section, cropped to its live traces and samples.

    Cubes larger than memory
    ------------------------
    A 3D SEG-Y cube, Zarr store (``seismo3d convert``) or ``.npy`` array that would need more than ``memory_limit``
    in memory is read lazily and traced block by block, with the same results as in memory: the fault likelihood,
    strike and dip (:func:`~seismo3d.seismic.faults.blocks.scan_blocks.chunked_fault_likelihood`) into
    ``fault_likelihood.zarr``, then the votes, thinned faults, skins and throws
    (:func:`~seismo3d.seismic.faults.blocks.surface_blocks.chunked_fault_surfaces`) into ``fault_surfaces.zarr`` (arrays
    ``likelihood``, ``votes``, ``thin``; both opened by ``xarray.open_zarr``), then the same ``faults.vtp``, CSV
    files and picture as in memory (the picture reads only its three slices). Both stores are resumable (an
    interrupted run started again with the same arguments skips the finished blocks) and reused when finished. For
    a SEG-Y input, ``fault_likelihood.sgy``, ``fault_strike.sgy``, ``fault_dip.sgy`` and ``fault_votes.sgy`` are
    written block by block with its headers, as in memory. Only the fault cells (the thinned faults, about 160
    bytes each) and the seed candidates are held whole; a limit too small for them is reported with the memory
    they need.

    Data that cannot support fault tracing (too few traces, not seismic amplitudes, no lateral coherence: see
    :func:`~seismo3d.seismic.trace_faults`) raises :class:`~seismo3d.errors.UnsupportedDataError` before any output
    is written.

    Parameters
    ----------
    input_path : str or os.PathLike or None
        The input file; None with ``demo=True``.
    out_dir : str or os.PathLike
        Output folder; not one holding the input, and not one holding an earlier run's files (:data:`RESULTS`)
        unless ``overwrite`` (:mod:`seismo3d.jobs.outputs`; checked before the input is read).
    demo : bool, optional
        Run on a synthetic cube instead of ``input_path``.
    demo_seed : int, optional
        Seed of the synthetic cube (``demo=True``; ``--demo-seed`` on the command line).
    iline, xline : int, optional
        Trace header bytes of the inline and crossline numbers of a SEG-Y input.
    ignore_geometry : bool, optional
        Read a SEG-Y input as a trace list (unsorted file, arbitrary line) and trace it as a 2D section, without the
        warning that a file without a grid at the default bytes gets.
    endian : {'big', 'little'}, optional
        Byte order of a SEG-Y input; by default detected from its binary header.
    sample_unit : {'ms', 'm', 'ft'}, optional
        Unit of a SEG-Y input's sample axis; by default guessed from its headers (see
        :func:`~seismo3d.seismic.io.open_segy`).
    n_samples : int, optional
        Samples per trace of a raw ``.f32be`` section whose shape is not known by name.
    sensitivity : float, optional
        In [0, 1]: more faults when higher (see :class:`~seismo3d.seismic.FaultTracingOptions`).
    likelihood : {'scan', 'learned'}, optional
        The fault likelihood: the scan of fault-plane semblance or the fault network
        (:attr:`~seismo3d.seismic.FaultTracingOptions.likelihood`).
    memory_limit : int or str, optional
        Memory the job may use, bytes or a size such as ``'4GB'`` (default: half of the machine's RAM). A 3D cube
        whose in-memory run would need more (about 24 times its float32 size) is processed block by block (see
        *Cubes larger than memory* below).
    scheduler : str, optional
        A ``dask.distributed`` scheduler address (``tcp://host:port``) for the block-by-block run; default: dask's
        local threaded scheduler.
    overwrite : bool, optional
        Replace the files of an earlier run in ``out_dir``, and the block-by-block stores of another input or other
        options (moved aside while this run writes its own, deleted when it has finished, moved back if it fails;
        without ``overwrite`` they are refused, and those of the same input and options reused or resumed).
    progress : bool, optional
        Report progress (:mod:`seismo3d._progress`: a bar on a terminal, one log line per step otherwise).

    Returns
    -------
    FaultsJobResult
        ``faults``: the rows of ``fault_summary.csv``; ``written``: the files written, keyed ``likelihood``,
        ``strike``, ``dip``, ``votes``, ``surfaces``, ``points``, ``summary``, ``figure``, ``run_json`` (and
        ``input``, ``truth`` for the demo). For a cube beyond ``memory_limit``:
        ``likelihood`` is ``fault_likelihood.zarr`` (holding strike and dip too), ``surfaces_zarr`` is
        ``fault_surfaces.zarr``, with ``surfaces``, ``points``, ``summary``, ``figure``, and for a SEG-Y input
        ``likelihood_segy``, ``strike_segy``, ``dip_segy``, ``votes_segy``.

    Raises
    ------
    InputError
        No input (and not ``demo``), ``out_dir`` holds the input, is a file, holds an earlier run's files (without
        ``overwrite``) or cannot be written, an invalid option, a constant input,
        a ``memory_limit`` too small for the smallest blocks or for the fault cells, or ``out_dir`` holding the
        ``fault_likelihood.zarr`` or ``fault_surfaces.zarr`` of another input (without ``overwrite``).
    DataNotFoundError
        The input does not exist.
    SegyFormatError
        The input is not SEG-Y, is cut short, or holds something segyio cannot read (one line saying which; see
        :func:`~seismo3d.seismic.io.open_segy`). Prestack gathers raise :class:`SegyGeometryError` ("stack it first").
    SegyGeometryError
        The inline / crossline geometry cannot be read with ``iline`` / ``xline`` (the message suggests header bytes
        that work, or ``ignore_geometry``).
    UnsupportedDataError
        The data cannot support fault tracing; nothing is written.

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples or constant traces in the input.
    TraceListWarning
        A SEG-Y input without an inline / crossline grid at bytes 189 / 193, read as a trace list (one line).
    """
    record = RunRecord("faults", locals())  # first: the arguments as called
    if sample_unit is not None:
        check_choice(sample_unit, "sample_unit", {"ms", "m", "ft"})
    options = FaultTracingOptions(sensitivity=sensitivity, likelihood=likelihood)
    if demo and input_path is not None:
        raise InputError("pass either an input file or demo=True (--demo), not both")
    if not demo and input_path is None:
        raise InputError("no input file; pass a SEG-Y cube or line, a .f32be section or a .npy array, or use "
                         "demo=True (--demo) to run on a synthetic cube")
    out_dir = Path(out_dir)
    stem = "demo" if demo else Path(input_path).stem
    check_outputs([output_folder(out_dir, RESULTS, f"{stem}_faults")], [input_path], overwrite=overwrite)
    limit = parse_memory_limit(memory_limit)
    segy = dict(iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian, sample_unit=sample_unit)
    summary = []  # the rows of fault_summary.csv, as written
    # the files moved in together when every one is written; with overwrite, another run's block-by-block stores
    # moved aside, deleted once the new files are in, moved back if the run fails
    with SetAside(out_dir) as aside, StagedFolder(out_dir) as stage:
        written = _trace_and_write(input_path, stage.path, out_dir, demo=demo, demo_seed=demo_seed, segy=segy,
                                   n_samples=n_samples, options=options, limit=limit, scheduler=scheduler,
                                   progress=progress, summary=summary, aside=aside if overwrite else None,
                                   record=record)
        final = {key: stage.final(path) for key, path in written.items()}
        record.options["tracing_options"] = options
        final["run_json"] = stage.final(record.write(stage.path / RUN_JSON, inputs={"input": input_path},
                                                     outputs=final, results={"n_faults": len(summary)}))
    return FaultsJobResult(final, tuple(summary), final["run_json"], dict(record.stage_seconds))


def _trace_and_write(input_path, files: Path, out_dir: Path, *, demo, demo_seed, segy: dict, n_samples,
                     options: FaultTracingOptions, limit: int, scheduler, progress, summary: list,
                     aside: SetAside | None, record: RunRecord) -> dict:
    """Read (or make) the input, trace its faults in memory or block by block, write the results into ``files``
    (the block-by-block run's Zarr stores into ``out_dir``, another run's stores there moved into ``aside``, or
    refused when it is None); the files written, by key (the summary's rows appended to ``summary``; the seconds of
    reading, of each step and of writing in ``record``)."""
    iline, xline, ignore_geometry, endian, sample_unit = (segy[k] for k in ("iline", "xline", "ignore_geometry",
                                                                            "endian", "sample_unit"))
    held = resident_memory()  # the process as it is now: the run may add up to the limit less this
    written = {}
    if demo:
        with record.stage("make the demo cube"):
            inp, written["truth"] = _demo_input(files, demo_seed)
        iline, xline, ignore_geometry, endian, sample_unit, n_samples = 189, 193, False, None, "ms", None
        input_path = written["input"] = inp
    with record.stage("read input"):
        lazy = None if ignore_geometry else _lazy_if_too_large(input_path, limit, held, iline=iline, xline=xline,
                                                               sample_unit=sample_unit, endian=endian)
    if lazy is not None:
        _say_how_it_runs(lazy.name, tuple(lazy.data.shape), limit, held, by_blocks=True)
        written.update(_run_chunked(lazy, out_dir, files, memory_limit=limit, scheduler=scheduler,
                                    options=options, progress=progress, summary=summary, aside=aside, record=record))
        return written
    with record.stage("read input"):
        inp = _read_input(input_path, iline=iline, xline=xline, ignore_geometry=ignore_geometry,
                          sample_unit=sample_unit, n_samples=n_samples, endian=endian)
    _say_how_it_runs(inp.name, inp.data.shape, limit, held, by_blocks=False)
    dt = float(inp.samples[1] - inp.samples[0]) if inp.samples.size > 1 else 1.0
    if inp.unit != "samples" and not dt > 0:
        raise InputError(f"the sample interval of {inp.name} is {dt:g} {inp.unit}; it must be > 0 (check the "
                         "binary header's sample interval, bytes 3217-3218)")
    result = trace_faults(inp.data, sample_interval=None if inp.unit == "samples" else dt, sample_unit=inp.unit,
                          options=options, blocks=BlockRunOptions(in_memory=True), progress=progress)
    record.stage_seconds.update(result.step_seconds)

    geo = dict(iline=iline, xline=xline, ignore_geometry=ignore_geometry, endian=endian)
    steps = [
        ("likelihood", lambda: _write_volume(inp, files, "fault_likelihood", result.likelihood, **geo)),
        ("strike", lambda: _write_volume(inp, files, "fault_strike", result.strike_deg,
                                         like=written["likelihood"], **geo)),
        ("dip", lambda: _write_volume(inp, files, "fault_dip", result.dip_deg, like=written["likelihood"], **geo)),
        ("votes", lambda: _write_volume(inp, files, "fault_votes", result.votes, like=written["likelihood"], **geo)),
    ]
    coords = fault_coordinates(inp, **geo)
    with record.stage("write outputs"):
        _write_steps(steps + _surface_steps(inp, result, files, summary, coords), written, progress)
    return written


def _say_how_it_runs(name: str, shape: tuple, limit: int, held: int, *, by_blocks: bool) -> None:
    """One log line: whether the input is traced in memory or block by block, and why (the memory it needs)."""
    samples = " x ".join(str(int(n)) for n in shape)
    if len(shape) == 2:
        LOGGER.info("%s: a section of %s samples, traced in memory", name, samples)
        return
    need = f"about {size_text(in_memory_bytes(shape))} beside the {size_text(held)} this process holds"
    if by_blocks:
        LOGGER.info("%s: %s samples traced block by block into %s and %s in the output folder (its run in memory "
                    "needs %s, more than the memory limit of %s); run the same command again to resume an "
                    "interrupted run", name, samples, LIKELIHOOD_STORE, SURFACES_STORE, need, size_text(limit))
    else:
        LOGGER.info("%s: %s samples traced in memory (%s, within the memory limit of %s)", name, samples, need,
                    size_text(limit))


def _surface_steps(inp: _Input, result: FaultInterpretation, out_dir: Path, summary: list, coords) -> list:
    """The writers of the fault surfaces, points, summary (its rows appended to ``summary``) and picture."""
    from ..viz.faults import fault_surfaces, plot_fault_slices, save_polydata

    axes = inp.axes
    return [
        ("surfaces", lambda: save_polydata(fault_surfaces(result.faults, result.throws, axes=axes),
                                           out_dir / "faults.vtp")),
        ("points", lambda: write_points(inp, result, out_dir / "fault_points.csv", coordinates=coords)),
        ("summary", lambda: write_summary(inp, result, out_dir / "fault_summary.csv", summary)),
        ("figure", lambda: plot_fault_slices(inp.data, result.faults, path=out_dir / "faults.png",
                                             likelihood=result.likelihood, axes=axes, axis_labels=inp.labels,
                                             title=inp.name, **_throw_colours(inp, result))),
    ] + fault_interchange_steps(inp, result, out_dir, coords)


def _throw_colours(inp, result) -> dict:
    """faults.png's colours: each fault's |median throw| (the evidence of fault_summary.csv), in the data's unit."""
    scale = 1.0 if inp.unit == "samples" else float(result.sample_interval)
    values = {e.fault_id: abs(e.median_throw) * scale for e in result.evidence}
    return {"fault_values": values, "value_label": f"|median throw| ({inp.unit})"}


def _write_steps(steps: list, written: dict, progress: bool) -> None:
    with progress_steps(len(steps), "writing", unit="file", enabled=progress) as bar:
        for key, write in steps:
            bar.start(key)
            written[key] = write()
            bar.advance()


# --------------------------------------------------------------------------------------------------------------------
# cubes larger than memory

_TILE = 32  # traces per side of the lazy input's chunks: a block of the chunked run reads only the tiles around it


def _run_chunked(lazy: LazyInput, out_dir: Path, files: Path, *, memory_limit: int, scheduler,
                 options: FaultTracingOptions, progress, summary: list, aside: SetAside | None,
                 record: RunRecord) -> dict:
    """The faults of a cube traced block by block (:func:`~seismo3d.seismic.faults.trace_faults`) into
    ``fault_likelihood.zarr`` and ``fault_surfaces.zarr`` in ``out_dir`` (reused when finished, resumed when
    interrupted; those of another run moved into ``aside``, or refused without it); the same files as in memory,
    into ``files``."""
    dt = float(lazy.samples[1] - lazy.samples[0]) if lazy.unit != "samples" else None

    def trace():
        blocks = BlockRunOptions(memory_limit=memory_limit, in_memory=False, work_dir=out_dir, scheduler=scheduler,
                                 source=lazy.name, coords=lazy.coords)
        return trace_faults(lazy.data, sample_interval=dt, sample_unit=lazy.unit, options=options, blocks=blocks,
                            progress=progress)

    try:
        result = _replacing_earlier_stores(trace, out_dir, aside)
    except KeyboardInterrupt as exc:
        exc.resume_hint = _resume_hint(out_dir)  # the CLI's one line (seismo3d._cli_messages.friendly)
        raise
    record.stage_seconds.update(result.step_seconds)
    written = {"likelihood": result.stores["likelihood"], "surfaces_zarr": result.stores["surfaces"]}
    inp = _Input(lazy.data, lazy.name, None, None, lazy.inline, lazy.xline, lazy.samples, lazy.unit, "trace")
    coords = fault_coordinates(inp, **{k: v for k, v in (lazy.segy or {}).items() if k != "template_path"},
                               segy_path=(lazy.segy or {}).get("template_path"))
    with record.stage("write outputs"):
        _write_steps(_surface_steps(inp, result, files, summary, coords), written, progress)
        written.update(_segy_volumes(lazy, result.stores["surfaces"], files, {"likelihood": "likelihood",
                                                                              "votes": "votes"}, progress))
        written.update(_segy_volumes(lazy, result.stores["likelihood"], files,
                                     {"strike": "strike_deg", "dip": "dip_deg"}, progress))
    return written


def _resume_hint(out_dir: Path) -> str:
    """What an interrupted block-by-block run leaves in ``out_dir`` and how to resume it, in one line."""
    kept = sorted(p for name in (LIKELIHOOD_STORE, SURFACES_STORE) for p in out_dir.glob(name + "*"))
    if not kept:
        return "interrupted before any block was finished: nothing was written"
    size = sum(f.stat().st_size for p in kept for f in ([p] if p.is_file() else p.rglob("*")) if f.is_file())
    return (f"interrupted: the blocks finished so far are kept in {out_dir} ({', '.join(p.name for p in kept)}; "
            f"{size_text(size)}) and no other output was written; run the same command again to resume (finished "
            "blocks are skipped), or delete them to start over")


def _replacing_earlier_stores(trace, out_dir: Path, aside: SetAside | None):
    """``trace()``, a block-by-block run; where it finds the stores (or work folders) of another run in
    ``out_dir``, it is refused without ``aside`` (no overwrite), else they are moved aside with their work folders
    and the run starts again (the stores it may reuse are kept)."""
    while True:
        try:
            return trace()
        except EarlierStoresError as exc:
            stores = sorted({Path(p).name.removesuffix(".work").removesuffix(".partial") for p in exc.paths})
            names = [name + end for name in stores for end in ("", ".work", ".partial")]
            if aside is None:
                raise InputError(f"output folder {out_dir} holds {' and '.join(stores)} of another input or other "
                                 "options (rerun with those to resume or reuse them); pass overwrite=True "
                                 "(--overwrite) to replace them (they are kept until this run has written its "
                                 "own), or choose another folder") from None
            if set(names) <= set(aside.names):  # already moved aside, and still in the way: not ours to replace
                raise
            LOGGER.info("%s: moving the earlier run's %s aside (deleted when this run has finished)", out_dir,
                        " and ".join(stores))
            aside.move(names)


def _segy_volumes(lazy: LazyInput, path: Path, out_dir: Path, names: dict, progress: bool) -> dict:
    """For a SEG-Y input, the Zarr volumes also as SEG-Y with its headers (as the in-memory run writes them),
    block by block; keyed ``<name>_segy``."""
    if lazy.segy is None:
        return {}
    import zarr

    group = zarr.open_group(str(path), mode="r")
    stems = {"likelihood": "fault_likelihood", "strike": "fault_strike", "dip": "fault_dip", "votes": "fault_votes"}
    options = {k: v for k, v in lazy.segy.items() if k != "template_path"}
    written = {}
    for key, array in names.items():
        written[f"{key}_segy"] = write_like_blocks(lazy.segy["template_path"], out_dir / f"{stems[key]}.sgy",
                                                   group[array], progress=progress, **options)
    return written
