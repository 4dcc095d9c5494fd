"""The fault interpretation of an array: fault likelihood -> optimal surface voting -> fault skins -> throw.

After Hale (2013, 2014) and Wu & Fomel (2018). :func:`trace_faults` runs the steps with the defaults every seismo3d
command uses and returns a :class:`FaultInterpretation`: the checks and the likelihood, then the one sequence of
steps of :mod:`~seismo3d.seismic.faults.steps`, on the whole array as one block
(:func:`~seismo3d.seismic.faults.surfaces.blocks.memory_surface_run`) or block by block into Zarr stores
(:func:`trace_faults_by_blocks`, before any block :func:`check_block_run`: the data judged from a sample of blocks,
:func:`~seismo3d.seismic.faults.preflight.judge_sample`, then the memory the run needs, :func:`minimum_memory_limit`);
:func:`clean_traces` finds the dead samples (mutes, dead traces, gaps) whose edges are not faults, and reports clipped
amplitudes (:mod:`~seismo3d.seismic.amplitudes`). Reading files and writing results is the ``faults`` command's job
(:mod:`seismo3d.jobs.faults`).

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.faults.likelihood.scan`.
"""

from __future__ import annotations

import dataclasses
import pathlib
import sys
import tempfile
import time
import uuid
import warnings
from dataclasses import dataclass

import numpy as np

from ..._progress import LOGGER, progress_steps
from ..._validation import check_choice, check_positive, check_seismic_layout
from ...errors import EarlierStoresError, InputError, Seismo3dWarning
from ..amplitudes import CleanTraces, check_amplitudes, clean_traces, finite_cube
from ..blocks.executor import release_memory, trace_cube
from ..blocks.memory import (in_memory_bytes, parse_memory_limit, process_bytes, resident_memory, size_text,
                             worker_baseline)
from ..blocks.options import BlockRunOptions, ChunkOptions
from ..blocks.plan import limit_for_blocks
from ..blocks.preflight import SampleOptions
from ..blocks.stores import earlier_run
from ..io.cube import as_cube, sample_interval as cube_sample_interval, seismic_axes
from ..time_slices import balanced_slices, blank_slices, filled_slices, slice_extremes
from .likelihood.learned_blocks import chunked_learned_likelihood, learned_block_bytes
from .likelihood.scan_blocks import chunked_fault_likelihood, smallest_block_bytes as likelihood_block_bytes
from .options import LIKELIHOODS, FaultTracingOptions
from .result import FaultInterpretation, FaultLikelihood
from .preflight import CubeSample, judge_sample
from .steps import check_size, faults_from_cells, no_coherence_message, run_likelihood, surface_cells
from ..blocks.plan import held_need
from .surfaces.blocks import (
    CANDIDATE_BYTES, CELLS_PER_CANDIDATE, chunked_fault_surfaces, held_stages, memory_surface_run,
    smallest_block_bytes as surfaces_block_bytes,
)

# check_size, check_amplitudes, no_coherence_message and LIKELIHOODS are imported here by older callers
__all__ = ["FaultInterpretation", "FaultTracingOptions", "CleanTraces", "LIKELIHOOD_STORE", "LIKELIHOODS",
           "STAGE_GROWTH", "SURFACES_STORE", "check_amplitudes", "check_block_run", "check_size", "clean_traces",
           "minimum_memory_limit", "no_coherence_message", "trace_faults", "trace_faults_by_blocks"]

_UNITS = {"samples", "ms", "m", "ft"}
LIKELIHOOD_STORE = "fault_likelihood.zarr"
SURFACES_STORE = "fault_surfaces.zarr"
_STORE_NAMES = {LIKELIHOOD_STORE: "fault likelihood", SURFACES_STORE: "fault surfaces"}
# What the process keeps of the fault likelihood stage when the surfaces stage plans its blocks from the resident
# memory: measured 33 MiB on a 96 x 96 x 200 cube and 46 MiB on a 160 x 160 x 256 one (glibc, 2 threads), rounded up.
STAGE_GROWTH = 64 << 20


def trace_faults(cube, *, memory_limit=None, sample_interval=None, sample_unit=None, sensitivity=None,
                 options: FaultTracingOptions | None = None, likelihood: FaultLikelihood | None = None,
                 blocks: BlockRunOptions | None = None, progress=True, model=None) -> FaultInterpretation:
    """Trace the faults of a seismic cube or section: likelihood, voting, skins, throw.

    The steps, with their defaults chosen from the data (no per-file tuning):

    1. the fault likelihood: by default the fault network's probability (:func:`~seismo3d.seismic.faults.
       learned_fault_likelihood`, the mean over its network grids), or with ``options.likelihood='scan'``
       :func:`~seismo3d.seismic.faults.fault_likelihood`, a scan of fault strikes and dips of the semblance of
       balanced amplitudes (Hale 2013);
    2. :func:`~seismo3d.seismic.thin_faults`: its ridges (non-maximum suppression across the fault), the seeds;
    3. :func:`~seismo3d.seismic.vote_faults`: optimal surface voting (Wu & Fomel 2018), which makes faults
       continuous across gaps of the likelihood and leaves isolated noise weak;
    4. the votes thinned, and thresholded from the data (Otsu, see :class:`FaultTracingOptions`);
    5. :func:`~seismo3d.seismic.faults.fault_skins`: the thinned votes linked into fault surfaces (curves in 2D);
    6. :func:`~seismo3d.seismic.fault_throws`: vertical throw by registering the reflectors on both sides;
    7. :func:`~seismo3d.seismic.faults.evidence.supported_faults`: only the faults that show the evidence of
       :class:`~seismo3d.seismic.faults.EvidenceOptions` are kept: votes that hold along them, and displaced
       reflectors (a throw of at least a sample that aligns the sides at least as well as no shift) or a likely
       fault (mean probability at least 0.5); or a throw of 3 samples or more on a likely fault.

    NaN / inf samples are read as 0 (with a :class:`~seismo3d.errors.Seismo3dWarning`). Blank time slices (one value
    on every trace: the missing images of a time-slice export, flat events of extreme amplitude continuous across every
    fault) are filled from the slices above and below, and the export's slices balanced (each its own mean and
    spread removed), with a warning (:mod:`~seismo3d.seismic.time_slices`). Dead
    samples (runs of 5 or more equal values along a trace: dead traces, mutes, gaps, NaN runs) are skipped, with a
    warning: the likelihood within 3 traces and 8 samples of them is set to 0, since the edge of a dead zone is not a
    fault.

    Data that cannot support fault tracing is refused with an :class:`~seismo3d.errors.UnsupportedDataError`:
    too few traces or samples, data that does not oscillate like seismic amplitudes (a velocity model), or a
    likelihood saturated everywhere (no lateral coherence).

    Memory and time: time and memory linear in the number of samples (see ``benchmarks/faults.py`` for the figures
    at 64^3 to 256^3). A 3D cube whose run in memory would need more than ``memory_limit`` beside the process
    (:func:`~seismo3d.seismic.blocks.memory.fits_in_memory`: 160 MiB and 24 times its float32 size) is traced
    block by block (:func:`trace_faults_by_blocks`) into Zarr stores in ``blocks.work_dir`` (default: a new
    temporary folder, kept: its path is in :attr:`FaultInterpretation.stores`), with the same checks, warnings and
    results: its volumes are then read lazily from the stores. A cube large enough to be judged from a sample of
    blocks first (:meth:`~seismo3d.seismic.blocks.preflight.SampleOptions.worth_sampling`) is refused from that
    sample before the whole likelihood (:func:`~seismo3d.seismic.faults.preflight.judge_sample`), on either path.

    Parameters
    ----------
    cube : xarray.DataArray or (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, the sample (time or depth, downward) last: a cube of :func:`seismo3d.open` or a segysak
        Dataset's variable (dims ``(iline, xline, twt | depth)`` or ``(line or trace, twt | depth)``, numpy- or
        dask-backed; its sample interval and unit from its sample coordinate, :func:`~seismo3d.seismic.io.cube.
        seismic_axes`; a cube of a single inline or crossline is traced as its 2D section), or a plain array.
    memory_limit : int or str, optional
        Memory the run may use, bytes or a size such as ``'4GB'`` (default ``blocks.memory_limit``: half of the
        RAM): a 3D cube whose run in memory needs more is traced block by block.
    sample_interval : float, optional
        Plain arrays: the sample interval in ``sample_unit``; required unless ``sample_unit`` is 'samples'.
    sample_unit : {'samples', 'ms', 'm', 'ft'}, optional
        Plain arrays: the unit of the sample axis (for converting throws, see
        :attr:`FaultInterpretation.sample_interval`); default 'samples'.
    sensitivity : float, optional
        In [0, 1], more faults when higher; replaces ``options.sensitivity`` (default 0.5). None with ``model``: the
        sensitivity the MODEL records (:meth:`FaultTracingOptions.with_model`), if any.
    options : FaultTracingOptions, optional
        Options of every step.
    likelihood : FaultLikelihood, optional
        The result of step 1 computed elsewhere with ``options.scan`` (e.g. block by block by
        :func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood`), arrays of the data's shape; the
        scan is then skipped.
    blocks : BlockRunOptions, optional
        How a cube is run: the memory limit (default half of the RAM), a forced choice between the run in memory and
        the run by blocks, the folder of the Zarr stores of a run by blocks (default a new temporary folder), its
        dask scheduler,
        and the input's name and coordinates recorded in the stores (:class:`BlockRunOptions`).
    progress : bool, optional
        Report progress over the steps (:mod:`seismo3d._progress`: a bar on a terminal, one log line per step
        otherwise; the likelihood and the throw report their own progress too).
    model : str or os.PathLike, optional
        A MODEL folder written by ``seismo3d adapt`` (the fault network adapted to a survey from an interpreter's
        faults): the learned likelihood runs it instead of the shipped network (``LearnedOptions.adapted``), with the
        evidence's unbroken veto MODEL records (:meth:`FaultTracingOptions.with_model`); default:
        ``options.learned.adapted`` (the shipped network unless set).

    Returns
    -------
    FaultInterpretation
        Likelihood, strike, dip, votes, thinned faults, fault skins and their throws; one type however the run
        went. For a DataArray ``cube`` the volumes (``likelihood``, ``strike_deg``, ``dip_deg``, ``votes``,
        ``thin``) are DataArrays on the cube's own dimensions and coordinates (``cdp_x`` / ``cdp_y`` included),
        numpy-backed in memory, dask-backed over the Zarr stores by blocks; for a plain array they are arrays
        (numpy in memory, Zarr arrays of the stores by blocks), as the input.

    Raises
    ------
    InputError
        ``cube`` is not a numeric 2D / 3D array with at least 3 samples per axis or a seismic DataArray
        (:func:`~seismo3d.seismic.io.cube.seismic_axes`), all samples are equal, the sample interval / unit or an
        option is invalid (or given beside a DataArray, which carries its own), a ``memory_limit`` too small for
        the blocks (the message names one that works), or ``model`` is not a MODEL folder of ``seismo3d adapt``
        (or one changed since).
    DataNotFoundError
        No folder at ``model``.
    UnsupportedDataError
        The data cannot support fault tracing (see above); the message says why and what to do.

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples, dead samples (constant runs), or clipped amplitudes (more than 5 % of the samples at the
        data's smallest or largest value); blank time slices (one value on every trace:
        :mod:`~seismo3d.seismic.time_slices`), filled before the likelihood.

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    .. [2] D. Hale, "Fault surfaces and fault throws from 3D seismic images", Geophysics 79(5), O53-O66, 2014,
       doi:10.1190/geo2013-0270.1.
    .. [3] X. Wu and S. Fomel, "Automatic fault interpretation with optimal surface voting", Geophysics 83(5),
       O67-O82, 2018, doi:10.1190/geo2018-0115.1.

    Examples
    --------
    >>> from seismo3d.data.synthetic import synthetic_cube
    >>> syn = synthetic_cube((64, 64, 64), seed=0)
    >>> result = trace_faults(syn.cube, sample_interval=4.0, sample_unit="ms", progress=False)
    >>> len(result.faults) >= 1
    True
    """
    labels = _Labels.of(cube, sample_interval, sample_unit)
    data = cube if labels is None else labels.values
    if labels is not None:
        sample_interval, sample_unit = labels.interval, labels.unit
    sample_unit = "samples" if sample_unit is None else sample_unit
    check_choice(sample_unit, "sample_unit", _UNITS)
    if sample_unit == "samples":
        if sample_interval not in (None, 1, 1.0):
            raise InputError(f"sample_interval={sample_interval!r} needs a unit; pass sample_unit='ms', 'm' or 'ft'")
        sample_interval = 1.0
    elif sample_interval is None:
        raise InputError(f"sample_unit={sample_unit!r} needs sample_interval= (the sample interval in {sample_unit})")
    sample_interval = check_positive(sample_interval, "sample_interval")
    opt = options or FaultTracingOptions()
    if not isinstance(opt, FaultTracingOptions):
        raise InputError(f"trace_faults(options=...) must be a FaultTracingOptions; got {type(opt).__name__}")
    if model is not None:  # before any work: a missing or changed MODEL is refused here
        opt = opt.with_model(model, sensitivity=sensitivity)
    elif sensitivity is not None:
        opt = dataclasses.replace(opt, sensitivity=sensitivity)

    run = _block_run(blocks, memory_limit)
    if not run.in_memory_for(np.shape(data), has_likelihood=likelihood is not None):
        coords, source = run.coords, run.source
        if labels is not None:  # the cube's own coordinates and file name in the stores, unless given
            coords = labels.store_coords() if coords is None else coords
            source = labels.cube.attrs.get("source_file") if source is None else source
        found = trace_faults_by_blocks(data, opt, sample_interval=sample_interval, sample_unit=sample_unit,
                                       memory_limit=run.limit, work_dir=run.work_dir, scheduler=run.scheduler,
                                       source=source or "cube", coords=coords, progress=progress, after=run.after)
        return found if labels is None else labels.label(found)
    arr, dead = _cleaned(data, opt)
    with progress_steps(7, "faults", enabled=progress) as bar:
        bar.start("fault likelihood")
        if likelihood is None:
            fl = run_likelihood(arr, opt, progress=progress)
        else:
            fl = _given_likelihood(likelihood, arr.shape)
        del dead  # the steps find the dead samples again, as by blocks (the same fill values: the whole array's)
        bar.advance()
        run = memory_surface_run(arr, fl.likelihood, fl.strike_deg, fl.dip_deg, opt,  # one block: the whole array
                                 progress=progress)
        del fl
        found = surface_cells(run, opt, bar)
        likelihood = run.volume("likelihood")
        faults, throws, evidence = faults_from_cells(run.cells_found(), arr.shape, arr, found.thresholds, opt,
                                                     likelihood=likelihood, bar=bar, progress=progress)
    result = FaultInterpretation(likelihood=likelihood, strike_deg=run.volume("fault_strike_deg"),
                                 dip_deg=run.volume("fault_dip_deg"), votes=run.volume("votes"),
                                 thin=run.volume("thin"), thresholds=found.thresholds, faults=faults,
                                 throws=throws, evidence=evidence, sample_interval=float(sample_interval),
                                 sample_unit=sample_unit, step_seconds=dict(bar.seconds))
    return result if labels is None else labels.label(result)


_VOLUMES = ("likelihood", "strike_deg", "dip_deg", "votes", "thin")


@dataclass(frozen=True)
class _Labels:
    """A DataArray input of :func:`trace_faults`: what is traced (its values, a single line squeezed to its 2D
    section), its sample interval and unit, and how the results get its dimensions and coordinates back."""

    cube: object
    values: object  # numpy or dask array
    interval: float | None
    unit: str
    squeezed: int | None  # the lateral axis of length 1 taken out of a grid of one line

    @classmethod
    def of(cls, cube, sample_interval, sample_unit):
        """None for a plain array; the labels of a seismic DataArray (refused with a sample interval or unit beside
        it: it carries its own)."""
        xr = sys.modules.get("xarray")  # a DataArray's class is imported whenever there is one
        if xr is None or not isinstance(cube, xr.DataArray):
            return None
        axes = seismic_axes(cube)
        if sample_interval is not None or sample_unit is not None:
            raise InputError(f"a DataArray carries its sample interval and unit (its {axes.sample!r} coordinate and "
                             "its units attribute); drop sample_interval= and sample_unit=, or set them on the cube")
        interval, unit = cube_sample_interval(cube, axes)
        values, squeezed = cube.data, None
        if len(axes.lateral) == 2 and 1 in values.shape[:2]:  # a grid of one line: its 2D section
            squeezed = 0 if values.shape[0] == 1 else 1
            values = values[0] if squeezed == 0 else values[:, 0]
        return cls(cube, values, interval, unit, squeezed)

    def store_coords(self) -> dict | None:
        """The coordinates recorded in the Zarr stores of a run by blocks."""
        lateral = [np.asarray(self.cube.coords[d].values) if d in self.cube.coords else None
                   for d in self.cube.dims[:-1]]
        if len(lateral) != 2:
            return None
        sample = self.cube.dims[-1]
        return {"inline": lateral[0], "crossline": lateral[1],
                "sample": np.asarray(self.cube.coords[sample].values) if sample in self.cube.coords else None,
                "sample_unit": self.unit}

    def label(self, result: FaultInterpretation) -> FaultInterpretation:
        """``result`` with its volumes as DataArrays on the cube's dimensions and coordinates (dask-backed over
        the stores of a run by blocks)."""
        volumes = {}
        for name in _VOLUMES:
            v = getattr(result, name)
            if self.squeezed is not None:
                v = np.expand_dims(np.asarray(v), self.squeezed)
            volumes[name] = as_cube(v, self.cube, name=name)
        return dataclasses.replace(result, **volumes)


def trace_faults_by_blocks(cube, opt: FaultTracingOptions, *, sample_interval: float, sample_unit: str,
                           memory_limit: int, work_dir, scheduler=None, source: str = "cube", coords=None,
                           progress: bool = True, after: tuple = ()) -> FaultInterpretation:
    """Trace the faults of a 3D cube block by block (called by :func:`trace_faults`): the checks before any block
    (:func:`check_block_run`), the fault likelihood
    (:func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood` or the learned one) into
    ``fault_likelihood.zarr`` (a finished likelihood of the same source is reused; an unfinished one resumes), the
    fault surfaces (:func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`) into
    ``fault_surfaces.zarr``.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) dask.array.Array or array_like
        Amplitudes, samples along the last axis (e.g. ``seismo3d.open(path).data``).
    opt : FaultTracingOptions
    sample_interval : float
    sample_unit : str
    memory_limit : int
        Bytes.
    work_dir : str or os.PathLike or None
        Existing folder of the Zarr stores ``fault_likelihood.zarr`` and ``fault_surfaces.zarr``; None: a new
        temporary folder, made after the checks and kept (the result reads its volumes from it).
    scheduler : str, optional
        ``dask.distributed`` scheduler address; default the local threads.
    source : str
        Name of the input, recorded in the stores (a likelihood of another source is not reused).
    coords : dict, optional
        Coordinates of the likelihood store (``inline``, ``crossline``, ``sample``, ``sample_unit``).
    progress : bool
    after : tuple of HeldStage, optional
        Stages after the run that hold its results whole (the faults job's writers,
        :attr:`~seismo3d.seismic.blocks.options.BlockRunOptions.after`), planned with the run's own.

    Returns
    -------
    FaultInterpretation
        Its arrays are Zarr arrays of the stores (``stores``).

    Raises
    ------
    InputError
        Constant data, a memory limit too small (the message names one that works), or stores of another input in
        ``work_dir``.
    UnsupportedDataError
        As :func:`~seismo3d.seismic.faults.trace_faults`.
    """
    import zarr

    chunking = ChunkOptions(memory_limit=memory_limit, scheduler=scheduler)
    check_size(tuple(int(n) for n in np.shape(cube)), opt)
    # float32 chunks of whole traces (an array given in memory: chunks of the runs' tile)
    x = trace_cube(cube, "fault tracing by blocks", chunks=(chunking.tile, chunking.tile, -1), dtype=np.float32)
    shape = tuple(int(n) for n in x.shape)
    if work_dir is not None:  # the stores of another run refused before any work
        work_dir = pathlib.Path(work_dir)
        if not work_dir.is_dir():
            raise InputError(f"cannot write the fault stores into {work_dir}: it is not a folder; create it first")
        if in_the_way := stores_of_another_run(work_dir, source, shape, opt):
            store = in_the_way[0].name.removesuffix(".work").removesuffix(".partial")  # the first one in the way
            raise EarlierStoresError(f"{work_dir / store} holds the {_STORE_NAMES[store]} of another input or other "
                                     "options; pick another output folder (-o) or delete it",
                                     [p for p in in_the_way if p.name.startswith(store)])
    x, process, amplitudes = check_block_run(x, source, memory_limit, scheduler, opt, after=after)
    # the likelihood's blocks planned from the process the refusal measured, the surfaces' from it grown by the
    # likelihood stage (STAGE_GROWTH, as minimum_memory_limit counts it; more when the process has grown more): the
    # same blocks for the same input and limit, run after run
    chunking = dataclasses.replace(chunking, process=process)
    if work_dir is None:  # after the checks; kept: the result's volumes are read from its stores
        work_dir = pathlib.Path(tempfile.mkdtemp(prefix="seismo3d-faults-"))
        LOGGER.info("%s: the fault stores of this run by blocks go to %s (pass blocks=BlockRunOptions(work_dir=...) "
                    "to choose the folder)", source, work_dir)
    path = work_dir / LIKELIHOOD_STORE
    started = time.perf_counter()
    likelihood_seconds = {}
    if earlier_run(path, _store_records(source, shape, opt)[LIKELIHOOD_STORE]).state == "finished":  # reused
        LOGGER.info("%s: reusing the finished fault likelihood in %s", source, path)
    else:
        held = resident_memory()
        LOGGER.info("%s: %d x %d x %d samples need about %.2f GiB in memory besides this process (%.2f GiB), more "
                    "than the memory limit of %.2f GiB allows: fault likelihood block by block into %s", source,
                    *shape, in_memory_bytes(shape) / 2**30, held / 2**30, memory_limit / 2**30, path.name)
        # "id": this store, told apart from a later one at the same path (fault_surfaces.zarr records whose it is);
        # written with the store's other attributes before it is renamed into place
        attrs = {"source": source, "likelihood": opt.likelihood, "id": uuid.uuid4().hex}
        if opt.likelihood == "learned":
            found = chunked_learned_likelihood(x, path, options=opt.learned, coords=coords, progress=progress,
                                               chunking=chunking, attrs=attrs)
        else:
            found = chunked_fault_likelihood(x, path, options=opt.scan, coords=coords, progress=progress,
                                             chunking=chunking, attrs=attrs)
        likelihood_seconds = dict(found.seconds)  # its block steps computed in this call
    seconds = {f"fault likelihood: {name}": t for name, t in likelihood_seconds.items()}
    seconds["fault likelihood"] = time.perf_counter() - started - sum(likelihood_seconds.values())  # the rest
    started = time.perf_counter()
    grown = dataclasses.replace(chunking, process=max(process + STAGE_GROWTH, process_bytes(scheduler)))
    surfaces = chunked_fault_surfaces(x, path, work_dir / SURFACES_STORE, options=opt, chunking=grown,
                                      progress=progress, amplitudes=amplitudes, attrs={"source": source},
                                      after=after)
    seconds.update(surfaces.seconds)  # the block steps computed in this call, the skins, the throw, the evidence
    seconds["fault surfaces"] = time.perf_counter() - started - sum(surfaces.seconds.values())  # the rest
    LOGGER.info("%s: %d faults from %d seeds and %d thinned fault samples (thresholds %.3f, %.3f)", source,
                len(surfaces.faults), surfaces.n_seeds, surfaces.n_cells, *surfaces.thresholds)
    scan = zarr.open_group(str(path), mode="r")
    traced = zarr.open_group(str(surfaces.path), mode="r")
    return FaultInterpretation(likelihood=traced["likelihood"], strike_deg=scan["strike_deg"],
                               dip_deg=scan["dip_deg"], votes=traced["votes"], thin=traced["thin"],
                               thresholds=surfaces.thresholds, faults=surfaces.faults, throws=surfaces.throws,
                               evidence=surfaces.evidence, sample_interval=float(sample_interval),
                               sample_unit=sample_unit, stores={"likelihood": path, "surfaces": surfaces.path},
                               step_seconds=seconds)


def stores_of_another_run(work_dir, source: str, shape, opt: FaultTracingOptions) -> tuple:
    """The entries of ``work_dir`` that a run by blocks of ``source`` would find of another run
    (:func:`~seismo3d.seismic.blocks.stores.earlier_run`): the fault likelihood's store and work folders when they
    record another input, shape or likelihood options; the fault surfaces' when they record another input, shape or
    options, or when they go with a likelihood that is not this run's finished one. Those of this run are left to be
    reused or resumed.

    Parameters
    ----------
    work_dir : str or os.PathLike
        The folder of the stores (:data:`LIKELIHOOD_STORE`, :data:`SURFACES_STORE`).
    source : str
        The input's name, as recorded in the stores.
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    opt : FaultTracingOptions

    Returns
    -------
    tuple of pathlib.Path
        The likelihood's entries first (the store, ``.partial``, ``.work``: those that exist), then the surfaces'.
    """
    work_dir = pathlib.Path(work_dir)
    records = _store_records(source, shape, opt)
    likelihood = earlier_run(work_dir / LIKELIHOOD_STORE, records[LIKELIHOOD_STORE])
    surfaces = earlier_run(work_dir / SURFACES_STORE, records[SURFACES_STORE])
    # the surfaces go with the likelihood they were computed from: this run's finished one (its id), or they are not
    # this run's
    ours = likelihood.state == "finished" and surfaces.record.get("likelihood_id") == likelihood.attrs.get("id")
    another = likelihood.paths if likelihood.state == "another" else ()
    if surfaces.state == "another" or (surfaces.state != "none" and not ours):
        another += surfaces.paths
    return another


def _store_records(source: str, shape, opt: FaultTracingOptions) -> dict:
    """What each store of a run by blocks records of the run it belongs to (:func:`~seismo3d.seismic.blocks.stores.
    earlier_run`), by store name: the input, the shape, and the options the store is computed from."""
    from dataclasses import asdict
    used = opt.scan if opt.likelihood == "scan" else opt.learned
    return {LIKELIHOOD_STORE: {"source": source, "shape": list(shape), "options": asdict(used)},
            SURFACES_STORE: {"source": source, "shape": list(shape), "options": asdict(opt)}}


def _block_run(blocks, memory_limit=None) -> BlockRunOptions:
    """The block-run options given to :func:`trace_faults` (its defaults when None), checked for their type, with
    ``memory_limit`` when given."""
    if blocks is None:
        blocks = BlockRunOptions()
    if not isinstance(blocks, BlockRunOptions):
        raise InputError(f"trace_faults(blocks=...) must be a BlockRunOptions (memory_limit, in_memory, work_dir, "
                         f"scheduler, source, coords); got {type(blocks).__name__}")
    if memory_limit is not None:
        try:
            blocks = dataclasses.replace(blocks, memory_limit=parse_memory_limit(memory_limit))
        except InputError as exc:
            raise InputError(f"trace_faults(memory_limit=...): {exc}") from exc
    return blocks


def _cleaned(data, opt: FaultTracingOptions) -> tuple[np.ndarray, np.ndarray]:
    """(amplitudes, dead samples) of the data in memory, after the refusals that come before the likelihood: bad
    arrays raise InputError; data that cannot support fault tracing is refused before any work, and before warnings
    about its dead or clipped samples that would not matter then."""
    arr = np.asarray(data)
    if arr.ndim in (2, 3) and min(arr.shape) < 3 and np.issubdtype(arr.dtype, np.number):
        check_size(arr.shape, opt)  # numbers, but below clean_traces' 3 samples per axis: the size message
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", Seismo3dWarning)
        cleaned = clean_traces(without_blank_slices(arr), options=opt.dead)
    check_size(cleaned.data.shape, opt)
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if SampleOptions().worth_sampling(cleaned.data.shape):  # refused from a sample, not after the whole likelihood
        judge_sample(cleaned.data, options=opt)
    check_amplitudes(cleaned.data, cleaned.dead, opt.min_crossings)
    return cleaned.data, cleaned.dead


def without_blank_slices(x):
    """The amplitudes with their blank time slices filled and, a blank slice showing a time-slice export, each slice's
    own offset and gain removed, with a warning (:mod:`~seismo3d.seismic.time_slices`): done before the clipped and
    dead samples are counted and the likelihood computed; ``x`` itself when no slice is blank.

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like or dask.array.Array
        Amplitudes (a dask array in chunks of whole traces; one pass over it).

    Returns
    -------
    ndarray or dask.array.Array
        float32 when filled.

    Raises
    ------
    InputError
        Not a numeric 2D / 3D array.

    Warns
    -----
    Seismo3dWarning
        Blank time slices, named.
    """
    if not hasattr(x, "map_blocks"):
        x = np.asarray(x)
        check_seismic_layout(x.shape, x.dtype)
    blank = blank_slices(*slice_extremes(x))
    if not blank.any():
        return x
    rows = np.nonzero(blank)[0]
    listed = ", ".join(str(int(k)) for k in rows[:8]) + (", ..." if rows.size > 8 else "")
    warnings.warn(f"{rows.size} time slices hold one value on every trace (samples {listed}; 0 the first): blank "
                  "images of a time-slice export, each slice scaled by its own range; the blank slices filled by "
                  "interpolation along the traces, and every slice's own offset and gain removed (its mean and "
                  "interquartile range), before tracing faults", Seismo3dWarning, stacklevel=4)
    filled = filled_slices(x if hasattr(x, "map_blocks") else x.astype(np.float32, copy=False), blank)
    return balanced_slices(filled, blank)


def _given_likelihood(fl, shape: tuple) -> FaultLikelihood:
    """A precomputed likelihood, checked against the data's shape; its arrays are copied (they are modified)."""
    if not isinstance(fl, FaultLikelihood):
        raise InputError(f"trace_faults(likelihood=...) must be a FaultLikelihood; got {type(fl).__name__}")
    arrays = [np.array(a, dtype=np.float32) for a in (fl.likelihood, fl.strike_deg, fl.dip_deg)]
    if any(a.shape != tuple(shape) for a in arrays):
        raise InputError(f"the given fault likelihood has shape {arrays[0].shape} but the data {tuple(shape)}; "
                         "compute it from the same data")
    return FaultLikelihood(*arrays)


def minimum_memory_limit(shape, *, baseline: int, options: FaultTracingOptions | None = None,
                         tile: int | None = None, workers: int = 1, sample: CubeSample | None = None,
                         growth: int = STAGE_GROWTH, after: tuple = ()) -> int:
    """The smallest ``memory_limit`` (bytes) with which a block-by-block fault run of a cube can go through: both
    stages plan their smallest blocks (the second from a process grown by ``growth``), and (with ``sample``) the
    seed candidates fit, and the stages after the blocks
    (:func:`~seismo3d.seismic.faults.surfaces.blocks.held_stages` and ``after``) with the cells the sample predicts
    (:data:`~seismo3d.seismic.faults.surfaces.blocks.CELLS_PER_CANDIDATE` per seed candidate).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    baseline : int
        Bytes the process holds before its blocks
        (:func:`~seismo3d.seismic.blocks.memory.worker_baseline`).
    options : FaultTracingOptions, optional
    tile : int, optional
        Traces a side of the smallest blocks (default :attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile`).
    workers : int
        Blocks computed at once.
    sample : CubeSample, optional
        From :func:`judge_sample`: adds the seed candidates it predicts.
    growth : int
        Bytes the process grows by during the likelihood stage (:data:`STAGE_GROWTH`).
    after : tuple of HeldStage, optional
        Stages after the run that hold its results whole (the faults job's writers).

    Returns
    -------
    int
        Bytes.
    """
    opt = options or FaultTracingOptions()
    tile = int(tile or ChunkOptions().tile)
    shape = tuple(int(n) for n in shape)
    baseline, growth = int(baseline), int(growth)
    first = limit_for_blocks(likelihood_block_bytes(shape, opt.scan, tile) if opt.likelihood == "scan"
                             else learned_block_bytes(shape, opt.learned, tile), baseline, workers)
    need = max(first, limit_for_blocks(surfaces_block_bytes(shape, opt, tile), baseline + growth, workers))
    if sample is not None:
        candidates = sample.candidates(shape)
        cells = int(np.ceil(candidates * CELLS_PER_CANDIDATE))
        held, _ = held_need(held_stages(shape) + tuple(after), cells)
        need = max(need, baseline + growth + max(candidates * CANDIDATE_BYTES, held))
    return need


def check_block_run(x, name: str, limit: int, scheduler, options: FaultTracingOptions, *, after: tuple = ()):
    """Before any block of a run by blocks: the data judged from a sample of blocks (not seismic amplitudes, no
    lateral coherence: the refusals of the run in memory, in seconds), then the one memory decision: the smallest
    limit the run goes through with (its smallest blocks in both stages and the seed candidates the sample predicts,
    :func:`minimum_memory_limit`), refused once with that limit named; then the data's NaN, constant, clipped and
    dead samples (:func:`~seismo3d.seismic.amplitudes.finite_cube`, passes over the whole cube), after its blank time
    slices are filled (:func:`without_blank_slices`, one more pass; the sample is judged before it, on the data as
    read, so that a refusal stays a matter of seconds).

    The sample comes first, whatever the limit, so that the one limit named covers the seed candidates too (a run
    given it goes through), and data the sample refuses gets no memory advice. The sample reads a few blocks of
    :attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile` traces (a few MB), whatever the limit.

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) dask.array.Array
    name : str
        The input, for messages.
    limit : int
        Memory limit, bytes.
    scheduler : str or None
    options : FaultTracingOptions
    after : tuple of HeldStage, optional
        Stages after the run that hold its results whole (the faults job's writers), in the limit named.

    Returns
    -------
    x : dask.array.Array
        ``x`` with NaN / inf read as 0 (:func:`~seismo3d.seismic.amplitudes.finite_cube`), its blank time
        slices filled (:mod:`~seismo3d.seismic.time_slices`).
    process : int
        Bytes of this process as the refusal counted them
        (:func:`~seismo3d.seismic.blocks.memory.process_bytes`): what the run's plans count too.
    amplitudes : CubeAmplitudes
        The cube's smallest and largest amplitude and its fill values (:func:`~seismo3d.seismic.amplitudes.
        finite_cube`), which the dead samples of every block of the run read.

    Raises
    ------
    UnsupportedDataError
        The sample refuses the data.
    InputError
        ``limit`` below what the run needs (the message names the smallest limit that works), or constant data.
    """
    shape = tuple(int(n) for n in x.shape)
    LOGGER.info("%s: judging the data from a sample of blocks", name)
    sample = judge_sample(x, options=options)  # before the passes over the whole cube: a refusal in seconds
    release_memory()  # the sample's arrays, before the process is measured
    # the process as it is now, measured once for the refusal and every plan of the run, and the chunks a block reads
    process = process_bytes(scheduler)
    baseline = worker_baseline(ChunkOptions(memory_limit=limit, scheduler=scheduler, process=process), x)
    need = minimum_memory_limit(shape, baseline=baseline, options=options, sample=sample, after=after)
    _check_limit(name, shape, limit, need, f" (its smallest blocks, and the ~{sample.candidates(shape)} seed "
                                           "candidates a sample of its blocks predicts and the fault cells, skins, "
                                           "throws and outputs made of them)")
    x, amplitudes = finite_cube(without_blank_slices(x), options.dead)  # filled as in memory (_cleaned)
    return x, process, amplitudes


def _check_limit(name: str, shape: tuple, limit: int, need: int, why: str) -> None:
    """InputError naming the smallest memory limit that works when ``limit`` is below ``need``."""
    if need <= limit:
        return
    held = resident_memory()
    # the suggestion 5 % above the need: the process's size, part of the need, differs by ~10 MB between runs (the
    # demo cube refused at 500MB "needs 550MB", refused at 550MB "needs 560MB")
    raise InputError(f"{name}: a block-by-block run of its {shape[0]} x {shape[1]} x {shape[2]} samples needs a "
                     f"memory limit of at least {size_text(need)}{why}, more than the {size_text(limit)} given "
                     f"(this process alone holds {size_text(held)}); pass memory_limit='{size_text(need * 21 // 20)}' "
                     "or more")
