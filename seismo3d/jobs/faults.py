"""The ``seismo3d faults`` job: read a seismic file (or make the demo cube), trace its faults, write the results.

:func:`run_faults_job` reads an input file (SEG-Y cube, 2D SEG-Y line, raw ``.f32be`` section, ``.npy`` array) or
makes a synthetic cube, runs :func:`seismo3d.seismic.trace_faults` and writes the outputs of ``seismo3d faults`` (see
its docstring for the list of files and their columns). Every file is written atomically; the input is only read.

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.faults.likelihood.scan`.
"""

from __future__ import annotations

import importlib
import os
import shutil
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import segyio

from .._atomic import SetAside, StagedFolder, atomic_path, deferred_interrupt
from .._progress import LOGGER, progress_steps
from .._threads import task_pool
from .._validation import check_choice
from ..errors import EarlierStoresError, InputError
from ..seismic.blocks.executor import release_memory
from ..seismic.blocks.memory import in_memory_bytes, parse_memory_limit, resident_memory, size_text
from ..seismic.faults.pipeline import LIKELIHOOD_STORE, SURFACES_STORE, stores_of_another_run
from ..seismic.blocks.options import BlockRunOptions
from ..seismic.blocks.plan import HeldStage
from ..seismic.faults.result import FaultInterpretation
from ..seismic.faults.options import FaultTracingOptions
from ..seismic.faults.pipeline import trace_faults
from ..seismic.adapted_network import MODEL_NETWORK
from ..seismic.io.writer import INLINES_PER_BLOCK, write_like, write_like_blocks
from .fault_inputs import read_input, write_demo_input
from .inputs import SeismicInput
from .fault_tables import write_points, write_summary
from .interchange import FAULT_INTERCHANGE_FILES, fault_coordinates, fault_interchange_steps
from .outputs import check_outputs, output_folder
from .runinfo import RUN_JSON, RunRecord

__all__ = ["FaultsJobResult", "RESULTS", "run_faults_job"]

# What a run writes into its folder (SEG-Y volumes for a SEG-Y input, .npy otherwise; the demo's cube and truth).
# The Zarr stores of a block-by-block run are not among them: they are reused or resumed by the next run.
RESULTS = tuple(f"fault_{name}.{ext}" for ext in ("sgy", "npy") for name in ("likelihood", "strike", "dip", "votes")) + (
    "faults.vtp", "fault_points.csv", "fault_summary.csv", "faults.png", "demo_seismic.sgy", "demo_truth.csv",
    RUN_JSON) + FAULT_INTERCHANGE_FILES
# What a run by blocks keeps in the output folder: its Zarr stores, and while unfinished their work folders and
# partial stores (resumed by the next run of the same input and options)
STORE_ENTRIES = tuple(name + end for name in (LIKELIHOOD_STORE, SURFACES_STORE) for end in ("", ".partial", ".work"))


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
# the job: outputs (its inputs: seismo3d.jobs.fault_inputs)


def _write_volume(inp: SeismicInput, out_dir: Path, stem: str, values, *, like: Path | None, progress: bool, iline,
                  xline, ignore_geometry, endian) -> Path:
    """One volume (numpy or Zarr array of the input's shape): SEG-Y with the input's headers for a SEG-Y input,
    ``.npy`` otherwise.

    A 3D SEG-Y cube is written by blocks of inlines (:func:`~seismo3d.seismic.io.write_like_blocks`, whatever the
    array), with the headers of ``like`` when given (a SEG-Y file this job already wrote so, whose headers are the
    input's). A SEG-Y line or trace list is written with :func:`~seismo3d.seismic.io.write_like`, or, given ``like``,
    as a copy of it with the trace data replaced: the same headers, without copying them field by field again.
    """
    if inp.segy_path is not None and len(inp.segy_shape or ()) == 3 and np.ndim(values) == 3:
        if like is not None:  # the headers of the first volume written, the input's: the input is not opened again
            return write_like_blocks(like, out_dir / f"{stem}.sgy", values, progress=progress)
        return write_like_blocks(inp.segy_path, out_dir / f"{stem}.sgy", values, iline=iline, xline=xline,
                                 endian=endian, progress=progress)
    if inp.segy_path is not None:
        out = out_dir / f"{stem}.sgy"
        values = np.asarray(values)
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


def run_faults_job(input_path, out_dir, *, demo=False, demo_seed=0, iline=189, xline=193, ignore_geometry=False,
                   endian=None, sample_unit=None, n_samples=None, sensitivity=None, likelihood="learned",
                   memory_limit=None, scheduler=None, overwrite=False, progress=True, model=None) -> FaultsJobResult:
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
      ``.npy`` arrays of the input's shape. In a cube traced with the fault network, strike and dip are not computed
      where its probability is below ``LearnedOptions.orientation_floor`` (0.01: no fault is traced there): NaN in
      the ``.npy`` arrays, 0 in the SEG-Y files (which most readers take no NaN in; a computed dip is in (0, 90]),
      the likelihood there the probability.
    * ``faults.vtp``: all fault surfaces (triangulated; polylines for 2D inputs) in one VTK PolyData, points at
      (inline, crossline, time_or_depth) (2D: (trace label, 0, time_or_depth)), point arrays ``fault_id``,
      ``throw`` (samples) and ``likelihood``.
    * ``fault_points.csv``: one row per fault sample, columns ``inline, crossline, time_or_depth, fault_id,
      throw_samples, throw_<unit>, throw_correlation, correlation_gain, side_coherence``; ``time_or_depth`` is in the
      sample unit (ms, m or ft from the SEG-Y headers or ``sample_unit``; the sample index for raw sections and
      ``.npy``, which have no ``throw_<unit>`` column). For raw sections, 2D ``.npy`` arrays and trace lists whose
      inline / crossline header bytes hold no numbers, one ``trace`` column replaces ``inline, crossline``:
      the trace index from 0 for arrays and raw sections, the trace number from 1 in file order for a trace list.
      Throw is positive where the hanging wall moved down (normal fault); ``throw_correlation`` (in [-1, 1]) is the
      normalised cross-correlation of the reflectors on the two sides once aligned, a quality
      measure (see
      :class:`~seismo3d.seismic.faults.throw.FaultThrow`); ``correlation_gain`` is that correlation less the sides'
      correlation with no shift (the evidence of a displacement); ``side_coherence`` how continuous the reflectors are
      along each side in itself (the smaller of the two sides; reported, not asked for: sides that do not match say less
      of a fault when they are not continuous themselves). An unmeasured throw is empty.
    * ``fault_summary.csv``: one row per fault, columns ``id, n_points, mean_strike_deg, mean_dip_deg,
      median_throw_samples, median_throw_<unit>, throw_spread_samples, throw_step_samples,
      throw_alternative_samples, throw_ambiguity, throw_correlation, correlation_gain, side_coherence, vote_ratio,
      mean_likelihood, confidence`` (``throw_spread_samples`` is empty where a fault's throw is one shift: a 2D
      fault spanning fewer than two windows of its throw profile; ``throw_step_samples``, 2D only, the part of the
      offset that is a step at the fault, about the throw at a fault and a small part of it at a flexure:
      :attr:`~seismo3d.seismic.faults.evidence.FaultEvidence.step`; ``throw_ambiguity``, how well the best rival
      shift, often a reflector period away, matches the sides against the throw's (0: no rival, near 1: about as
      well; on a 2D fault, its whole throw profile moved alike), and ``throw_alternative_samples``, that rival throw
      where the ambiguity reaches 0.4 (empty otherwise): the throw, its sign included, may then be either,
      :attr:`~seismo3d.seismic.faults.FaultThrow.rival_ratio`): the
      evidence each fault shows (:class:`~seismo3d.seismic.faults.evidence.FaultEvidence`; only faults whose votes
      hold along them and whose reflectors are displaced, or which the network calls likely, are kept:
      :func:`~seismo3d.seismic.faults.evidence.supported_faults`), to sort and filter on; ``vote_ratio`` is the
      fault's mean thinned votes over the run's upper vote threshold, ``mean_likelihood`` its mean fault likelihood;
      for 2D inputs ``dips_toward`` (e.g. ``increasing inline``)
      replaces the strike. Strike and dip are in index space (one trace step = one sample; strike from the inline
      axis toward the crossline axis, see :mod:`seismo3d.seismic.faults.likelihood.scan`).
    * ``fault_sticks_opendtect.txt``, ``fault_sticks_charisma.txt``, ``fault_sticks_iesx.txt``,
      ``fault_sticks_rms.pol``: every fault's points along each line that cuts it, as fault sticks in map coordinates
      (OpendTect ASCII; Charisma and IESX, which Petrel imports; RMS's XYZ polygons, which xtgeo reads);
      ``fault_surfaces_gocad/``: the triangulated faults of ``faults.vtp``, a GOCAD TSurf file per
      fault (``fault_<id>.ts``, as xtgeo reads and Petrel imports them), 3D inputs (:mod:`seismo3d.jobs.interchange`).
      ``fault_points.csv`` holds ``x``, ``y`` and ``xy_unit`` after the crossline: each point's trace's CDP X/Y with
      the coordinate scalar applied, or its inline and crossline numbers with ``xy_unit`` ``inline/crossline`` for an
      input without coordinates (the TSurf files alike; ``run.json``'s ``results`` name the unit, ``xy_unit``).
    * ``faults.png``: an inline, a crossline and a time slice (the most faulted of each) with the faults drawn over
      the seismic, coloured by their ``confidence`` (the column of ``fault_summary.csv``), above the same slices of
      the fault likelihood; for 2D inputs the section, cropped to its live traces and samples.

    Cubes larger than memory
    ------------------------
    A 3D SEG-Y cube, Zarr store (``seismo3d convert``) or ``.npy`` array that would need more than ``memory_limit``
    in memory is read lazily and traced block by block, with the same results as in memory: the fault likelihood,
    strike and dip (:func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood`) into
    ``fault_likelihood.zarr``, then the votes, thinned faults, skins and throws
    (:func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`) into ``fault_surfaces.zarr`` (arrays
    ``likelihood``, ``votes``, ``thin``; both opened by ``xarray.open_zarr``), then the same ``faults.vtp``, CSV
    files and picture as in memory (the picture reads only its three slices). Both stores are resumable (an
    interrupted run started again with the same arguments skips the finished blocks) and reused when finished. For
    a SEG-Y input, ``fault_likelihood.sgy``, ``fault_strike.sgy``, ``fault_dip.sgy`` and ``fault_votes.sgy`` are
    written block by block with its headers, as in memory. Only the seed candidates and the fault cells (the thinned
    faults, their skins, throws and the outputs made of them) are held whole; a limit too small for as many as a sample
    of blocks predicts is refused before the work, and for the cells counted after the blocks, then, with the limit
    they need (the finished blocks are kept for the run with it).

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
        In [0, 1]: more faults when higher (see :class:`~seismo3d.seismic.FaultTracingOptions`); default 0.5, or
        with ``model`` the sensitivity its record holds (:meth:`~seismo3d.seismic.FaultTracingOptions.with_model`).
    likelihood : {'scan', 'learned'}, optional
        The fault likelihood: the scan of fault-plane semblance or the fault network
        (:attr:`~seismo3d.seismic.FaultTracingOptions.likelihood`).
    memory_limit : int or str, optional
        Memory the job may use, bytes or a size such as ``'4GB'`` (default: half of the machine's RAM). A 3D cube
        whose in-memory run would need more beside what the process holds (160 MiB and 24 times its float32 size:
        :func:`~seismo3d.seismic.blocks.memory.in_memory_bytes`) is processed block by block (see *Cubes larger
        than memory* below); the decision is :meth:`~seismo3d.seismic.BlockRunOptions.in_memory_for`'s, asked once
        when the input is opened.
    scheduler : str, optional
        A ``dask.distributed`` scheduler address (``tcp://host:port``) for the block-by-block run; default: dask's
        local threaded scheduler.
    model : str or os.PathLike, optional
        A MODEL folder written by ``seismo3d adapt``: the fault network adapted to the survey replaces the shipped one
        (:attr:`~seismo3d.seismic.faults.LearnedOptions.adapted`; with ``likelihood='learned'`` only); its network
        file is recorded with its sha256 among the run's inputs. Default: the shipped network.
    overwrite : bool, optional
        Replace the files of an earlier run in ``out_dir``, and the block-by-block stores of another input or other
        options (found from what they record before the work, moved aside while this run writes its own, deleted
        when it has finished, moved back if it fails or is interrupted; without ``overwrite`` they are refused, and
        those of the same input and options reused or resumed).
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
    options = FaultTracingOptions(likelihood=likelihood, **({} if sensitivity is None else
                                                           {"sensitivity": sensitivity}))
    inputs = {"input": input_path}
    if model is not None:  # the adapted network, checked before any work
        if likelihood != "learned":
            raise InputError(f"--model is the adapted fault network, which the learned likelihood runs; drop "
                             f"--likelihood {likelihood} or --model")
        options = options.with_model(model, sensitivity=sensitivity)
        inputs["model"] = Path(model) / MODEL_NETWORK if Path(model).is_dir() else Path(model)
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
    how = {"by_blocks": False}  # the memory decision, once made (the hint of an interrupted run by blocks); xy_unit
    # the files moved in together when every one is written; with overwrite, an earlier run's block-by-block stores
    # set aside before the work, deleted once the new files are in, put back if the run fails or is interrupted
    aside = SetAside(out_dir)
    _load_writers()  # before the staging folder: an interrupt here leaves nothing to clean up
    try:
        with aside, StagedFolder(out_dir, owner="seismo3d faults") as stage:
            written = _trace_and_write(input_path, stage.path, out_dir, demo=demo, demo_seed=demo_seed, segy=segy,
                                       n_samples=n_samples, options=options, limit=limit, scheduler=scheduler,
                                       progress=progress, summary=summary, aside=aside if overwrite else None,
                                       record=record, how=how)
            final = {key: stage.final(path) for key, path in written.items()}
            record.options["tracing_options"] = options
            final["run_json"] = stage.final(record.write(stage.path / RUN_JSON, inputs=inputs,
                                                         outputs=final, results={"n_faults": len(summary),
                                                                                 "xy_unit": how["xy_unit"]}))
    except KeyboardInterrupt as exc:
        if how["by_blocks"]:  # the CLI's one line (seismo3d._cli_messages.friendly), once the folder is cleaned up
            exc.resume_hint = _resume_hint(out_dir, aside if overwrite else None)
        raise
    return FaultsJobResult(final, tuple(summary), final["run_json"], dict(record.stage_seconds))


def _trace_and_write(input_path, files: Path, out_dir: Path, *, demo, demo_seed, segy: dict, n_samples,
                     options: FaultTracingOptions, limit: int, scheduler, progress, summary: list,
                     aside: SetAside | None, record: RunRecord, how: dict) -> dict:
    """Read (or make) the input once, decide once whether it is traced in memory or block by block, trace it, and
    write the results into ``files`` (a run by blocks keeps its Zarr stores in ``out_dir``; with ``aside``, the
    stores of an earlier run there are set aside before the work); the files written, by key (the summary's rows
    appended to ``summary``, the seconds of each stage and step in ``record``, the decision and the unit of X / Y in
    ``how``)."""
    written = {}
    if demo:
        with record.stage("make the demo cube"):
            written["input"], written["truth"] = write_demo_input(files, demo_seed)
        input_path = written["input"]
        segy = dict(iline=189, xline=193, ignore_geometry=False, endian=None, sample_unit="ms")
        n_samples = None
    blocks = BlockRunOptions(memory_limit=limit, work_dir=out_dir, scheduler=scheduler)
    held = [resident_memory()]  # the process before the input is read: what the decision and its message use

    def lazy_if(shape) -> bool:  # asked with a 3D cube's shape: by blocks when its run in memory would not fit
        # the writers (imported before the staging folder, _load_writers) count twice in the in-memory estimate
        # (here and in in_memory_bytes' 160 MiB, calibrated without them): ~90 MB conservative; the block plan needs
        # them counted (issue 53's note, stop 65)
        held[0] = resident_memory()
        return not blocks.in_memory_for(shape, held=held[0])

    with record.stage("read input"):  # seismo3d.open: its headers read once; a cube beyond the limit is kept lazy
        inp = read_input(input_path, n_samples=n_samples, **segy, lazy_if=lazy_if)
    if inp.sample_unit != "samples" and not inp.sample_interval > 0:
        raise InputError(f"the sample interval of {inp.name} is {inp.sample_interval:g} {inp.sample_unit}; it must be "
                         "> 0 (check the binary header's sample interval, bytes 3217-3218)")
    how["by_blocks"] = inp.lazy
    _say_how_it_runs(inp.name, tuple(inp.amplitudes.shape), limit, held[0], by_blocks=inp.lazy)
    if inp.lazy and aside is not None:
        _set_aside_earlier_stores(out_dir, aside, inp, options)
    # decided: not again; the writers planned with the run's stages after its blocks
    blocks = replace(blocks, in_memory=not inp.lazy, source=inp.name, coords=inp.coords,
                     after=_writer_stages(tuple(inp.amplitudes.shape)))
    try:
        result = trace_faults(inp.cube, options=options, blocks=blocks, progress=progress)
    except EarlierStoresError as exc:  # without overwrite: stores of another input or other options are kept
        raise _stores_in_the_way(out_dir, exc) from None
    record.stage_seconds.update(result.step_seconds)
    if result.stores:  # a run by blocks: its Zarr stores, in out_dir
        written.update(likelihood=result.stores["likelihood"], surfaces_zarr=result.stores["surfaces"])
    coords = fault_coordinates(inp, iline=segy["iline"], xline=segy["xline"],
                               ignore_geometry=segy["ignore_geometry"], endian=segy["endian"])
    how["xy_unit"] = coords.unit  # the unit of X / Y in every interchange file, for run.json
    # in memory, faults.vtp's triangulation on a thread beside the other writers; by blocks, where the writing is the
    # run's memory peak, each writer alone
    beside = None if inp.lazy else _MESH_STEP
    with record.stage("write outputs"):
        _write_steps(_volume_steps(inp, result, files, segy, progress)
                     + _surface_steps(inp, result, files, summary, coords, mesh_last=beside is not None), written,
                     progress, beside=beside)
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


# the writers' libraries (_load_writers), by module name
WRITER_MODULES = ("matplotlib.figure", "pyvista")
# The writers' memory after a run by blocks, beyond the process as the run's plan counts it (as the stages before
# them: seismo3d.seismic.faults.surfaces.blocks.held_stages, measured alike by benchmarks/post_block_memory.py on
# the same three cubes, 159,474 / 357,331 / 92,879 cells, MiB beyond the process + 64 MiB): the SEG-Y volumes 51 / 47
# / 47 (a block of 32 inlines of 1.31 / 1.38 / 2.62 M samples read, checked and written: 46 / 50 / 63 MiB above the
# results held), faults.vtp then the TSurf files 83 / 150 / 30, faults.png 86 / 94 / 55. The first volume written
# takes the heap the throws' stage left, which held_stages covers.
_RESULTS_PER_CELL = 64  # the faults, throws and evidence held while they are written
_SEGY_FIXED, _SEGY_PER_SAMPLE = 32 << 20, 16  # per sample of write_like_blocks' block of INLINES_PER_BLOCK
_MESH_FIXED, _MESH_PER_CELL = 32 << 20, 480  # 105 / 196 / 75 MiB on the three cubes
_FIGURE_FIXED = 96 << 20  # its three slices of amplitudes and likelihood, matplotlib's layout


def _writer_stages(shape) -> tuple:
    """The writers of a run by blocks as stages of its plan (:class:`~seismo3d.seismic.blocks.plan.HeldStage`),
    with their memory models (the notes above): the SEG-Y volumes, the meshes, the picture.

    Parameters
    ----------
    shape : tuple of int
        The input's shape; a section (2D) is traced in memory and has none.

    Returns
    -------
    tuple of HeldStage
        Their ``held_bytes(cells)``, bytes beyond the process as the run's plan counts it.
    """
    if len(shape) != 3:
        return ()
    block = min(INLINES_PER_BLOCK, shape[0]) * shape[1] * shape[2]
    return (HeldStage("writing the SEG-Y volumes", lambda cells: (_RESULTS_PER_CELL * cells + _SEGY_FIXED
                                                                   + _SEGY_PER_SAMPLE * block)),
            HeldStage("writing faults.vtp and the TSurf files", lambda cells: _MESH_FIXED + _MESH_PER_CELL * cells),
            HeldStage("drawing faults.png", lambda cells: _RESULTS_PER_CELL * cells + _FIGURE_FIXED))


def _load_writers() -> None:
    """Import the writers' libraries (pyvista with VTK for the meshes, matplotlib for the picture: about 90 MB)
    before a cube's memory decision and its blocks' plan measure the memory this process holds, so that the memory
    limit covers the writing too. Imported when the writing started, they took the 128^3 demo cube at
    ``--memory-limit 500MB`` from about 500 MB during its blocks to 596 MB while writing.

    Called before the output folder's staging folder is made, with a Ctrl-C held until the imports end
    (:func:`~seismo3d._atomic.deferred_interrupt`): a SIGINT inside VTK's import crashed the process (a segmentation
    fault, no clean-up), which left the staging folder (``.staged-*.tmp``, holding the demo's input) in the output
    folder of ``seismo3d faults --demo`` interrupted in its first seconds."""
    with deferred_interrupt():
        for name in WRITER_MODULES:
            importlib.import_module(name)


def _volume_steps(inp: SeismicInput, result: FaultInterpretation, out_dir: Path, segy: dict, progress: bool) -> list:
    """The writers of the four volumes (likelihood, strike, dip, votes), numpy or Zarr arrays alike: SEG-Y with the
    input's headers for a SEG-Y input; ``.npy`` otherwise, unless the run by blocks's Zarr stores hold them (keys
    ``likelihood`` and ``surfaces_zarr``)."""
    volumes = {"likelihood": result.likelihood, "strike": result.strike_deg, "dip": result.dip_deg,
               "votes": result.votes}
    if inp.segy_path is not None:  # most SEG-Y readers take no NaN: strike and dip not computed are written as 0
        volumes.update(strike=_NanAsZero(result.strike_deg), dip=_NanAsZero(result.dip_deg))
    geo = {k: segy[k] for k in ("iline", "xline", "ignore_geometry", "endian")}
    steps = []
    if result.stores and inp.segy_path is None:  # a run by blocks: its stores are the volumes (SEG-Y ones too)
        return steps
    first = []  # the first volume written: the template of the others (a SEG-Y line or trace list)

    def write(key, values):
        path = _write_volume(inp, out_dir, f"fault_{key}", values, like=first[0] if first else None,
                             progress=progress, **geo)
        first.append(path)
        return path

    for key, values in volumes.items():
        steps.append((f"{key}_segy" if result.stores else key, lambda key=key, values=values: write(key, values)))
    return steps


class _NanAsZero:
    """A volume (numpy, Zarr or dask array, or a DataArray of one) read by slicing, NaN read as 0: strike and dip
    where they were not computed (the likelihood below ``LearnedOptions.orientation_floor``) in the SEG-Y files,
    which most readers refuse NaN in; a dip of 0 is none (a computed one is in (0, 90])."""

    def __init__(self, values):
        self._values = getattr(values, "data", values)
        self.shape = tuple(self._values.shape)
        self.ndim = len(self.shape)

    def __getitem__(self, key) -> np.ndarray:
        return np.nan_to_num(np.asarray(self._values[key], dtype=np.float32), nan=0.0, posinf=np.inf, neginf=-np.inf)

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        return self[...] if dtype is None else self[...].astype(dtype)


_MESH_STEP = "surfaces"  # faults.vtp: the meshes triangulated by VTK, which releases the GIL while it works


def _surface_steps(inp: SeismicInput, result: FaultInterpretation, out_dir: Path, summary: list, coords, *,
                   mesh_last: bool = False) -> list:
    """The writers of the fault surfaces, points, summary (its rows appended to ``summary``) and picture; with
    ``mesh_last``, faults.vtp and the TSurf files (which reuse its mesh) last, where :func:`_write_steps` waits for
    the mesh made beside the others; else first."""
    from ..viz.fault_meshes import fault_surfaces, save_polydata
    from ..viz.faults import plot_fault_slices

    axes = inp.axes
    meshes = []  # faults.vtp's mesh for fault_surfaces_gocad/ (the same points and triangles), written next

    def surfaces():
        mesh = fault_surfaces(result.faults, result.throws, axes=axes)
        if tsurf:
            meshes.append(mesh)
        return save_polydata(mesh, out_dir / "faults.vtp")

    interchange = fault_interchange_steps(inp, result, out_dir, coords, mesh=lambda: meshes.pop() if meshes else None)
    # the TSurf files right after faults.vtp, whose mesh they reuse: by blocks first, so that the mesh is not held
    # while the other files are written (the run's peak is in the writing); in memory last, the mesh made meanwhile
    tsurf = [step for step in interchange if step[0] == "surfaces_tsurf"]
    meshed = [(_MESH_STEP, surfaces), *tsurf]
    others = [("points", lambda: write_points(inp, result, out_dir / "fault_points.csv", coordinates=coords)),
              ("summary", lambda: write_summary(inp, result, out_dir / "fault_summary.csv", summary)),
              ("figure", lambda: plot_fault_slices(inp.amplitudes, result.faults, path=out_dir / "faults.png",
                                                   likelihood=result.likelihood, axes=axes,
                                                   axis_labels=inp.axis_titles, title=inp.name,
                                                   **_throw_colours(inp, result))),
              ] + [step for step in interchange if step[0] != "surfaces_tsurf"]
    return others + meshed if mesh_last else meshed + others


def _throw_colours(inp, result) -> dict:
    """faults.png's colours: each fault's confidence (the column of fault_summary.csv that ranks them)."""
    values = {e.fault_id: e.confidence for e in result.evidence}
    return {"fault_values": values, "value_label": "confidence (fault_summary.csv)"}


def _write_steps(steps: list, written: dict, progress: bool, *, beside: str | None = None) -> None:
    """Run the writers ``steps`` (``(key, write)``) in their order, a progress line each, their paths put in
    ``written``. The writer ``beside`` (a run in memory: faults.vtp, whose triangulation in VTK releases the GIL)
    starts first, on a second thread (:func:`~seismo3d._threads.task_pool`), and is waited for in its place. An
    interrupt or a writer's error waits for it before it propagates, so that nothing is written into the staging
    folder once it is removed."""
    with task_pool(1 if beside is None else 2, name="seismo3d-writer") as submit:
        started = {key: submit(write) for key, write in steps if key == beside}  # one call: one thread
        with progress_steps(len(steps), "writing", unit="file", enabled=progress) as bar:
            for key, write in steps:
                bar.start(key)
                written[key] = started[key].result() if key in started else write()
                release_memory()  # a writer's freed temporaries, before the next writer's
                bar.advance()


# --------------------------------------------------------------------------------------------------------------------
# the stores of a run by blocks


def _set_aside_earlier_stores(out_dir: Path, aside: SetAside, inp: SeismicInput, options: FaultTracingOptions) -> None:
    """With ``overwrite``, before the work: the stores (and work folders) of another input, shape or options that an
    earlier run by blocks left in ``out_dir`` (:func:`~seismo3d.seismic.faults.pipeline.stores_of_another_run`)
    moved aside, deleted once this run's files are in, put back if it fails or is interrupted (with this run's
    entries of the same names removed); this input's own are left to be reused or resumed."""
    found = stores_of_another_run(out_dir, inp.name, tuple(int(n) for n in inp.amplitudes.shape), options)
    if found:
        LOGGER.info("%s: moving the earlier run's %s aside (deleted when this run has finished)", out_dir,
                    " and ".join(p.name for p in found))
        stores = tuple({p.name.removesuffix(".work").removesuffix(".partial") for p in found})
        aside.move([name for name in STORE_ENTRIES if name.startswith(stores)])  # this run's, if it fails, removed


def _stores_in_the_way(out_dir: Path, exc: EarlierStoresError) -> InputError:
    """The refusal of a run whose folder holds the stores of another input or other options (found by the block run
    before it touches them): without ``overwrite``, or with it when their records did not tell
    (:func:`~seismo3d.seismic.faults.pipeline.stores_of_another_run`)."""
    stores = sorted({Path(p).name.removesuffix(".work").removesuffix(".partial") for p in exc.paths})
    return InputError(f"output folder {out_dir} holds {' and '.join(stores)} of another input or other options "
                      "(rerun with those to resume or reuse them); pass overwrite=True (--overwrite) to replace them "
                      "(they are kept until this run has written its own), or choose another folder")


def _resume_hint(out_dir: Path, aside: SetAside | None) -> str:
    """What an interrupted run by blocks left in ``out_dir`` and what to do, in one line (after the staging folder
    and the stores set aside have been cleaned up: what it says is what is there)."""
    if aside is not None and aside.moved:
        return (f"interrupted: the earlier run's {', '.join(aside.moved)} are back in {out_dir} and nothing of this "
                "run was kept (an interrupted --overwrite leaves the folder as it was); run the same command again "
                "to start over")
    kept = sorted(p for name in STORE_ENTRIES for p in [out_dir / name] if os.path.lexists(p))
    if not kept:
        return "interrupted before any block was finished: nothing was written"
    size = sum(f.stat().st_size for p in kept for f in ([p] if p.is_file() else p.rglob("*")) if f.is_file())
    return (f"interrupted: the blocks finished so far are kept in {out_dir} ({', '.join(p.name for p in kept)}; "
            f"{size_text(size)}) and no other output was written; run the same command again to resume (finished "
            "blocks are skipped), or delete them to start over")
