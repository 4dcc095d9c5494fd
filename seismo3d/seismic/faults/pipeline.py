"""The fault interpretation of an array: fault likelihood -> optimal surface voting -> fault skins -> throw.

After Hale (2013, 2014) and Wu & Fomel (2018). :func:`trace_faults` runs the steps with the defaults every seismo3d
command uses and returns a :class:`FaultInterpretation`: the checks and the likelihood, then the one sequence of
steps of :mod:`~seismo3d.seismic.faults.steps`, on the whole array as one block
(:class:`~seismo3d.seismic.faults.blocks.array_run.ArrayRun`) or block by block
(:mod:`~seismo3d.seismic.faults.blocks.cube_run`); :func:`clean_traces` finds the dead samples (mutes, dead traces,
gaps) whose edges are not faults, and reports clipped amplitudes. Reading files and writing results is the ``faults``
command's job (:mod:`seismo3d.jobs.faults`).

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.faults.likelihood.scan`.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from ..._progress import progress_steps
from ..._validation import check_choice, check_positive
from ...errors import InputError, Seismo3dWarning
from .blocks.array_run import ArrayRun
from ..blocks.options import BlockRunOptions
from .checks import check_amplitudes, check_size, no_coherence_message
from .surfaces.dead_samples import CleanTraces, clean_traces, near_dead_samples
from .options import LIKELIHOODS, FaultTracingOptions
from .result import FaultInterpretation, FaultLikelihood
from .likelihood.learned import learned_fault_likelihood
from .likelihood.scan import fault_likelihood
from .blocks.preflight import SampleOptions, judge_sample
from .steps import faults_from_cells, surface_cells

# check_size, check_amplitudes, no_coherence_message and LIKELIHOODS are imported here by older callers
__all__ = ["FaultInterpretation", "FaultTracingOptions", "CleanTraces", "LIKELIHOODS", "check_amplitudes",
           "check_size", "clean_traces", "no_coherence_message", "trace_faults"]

_UNITS = {"samples", "ms", "m", "ft"}


def trace_faults(data, *, sample_interval=None, sample_unit="samples", sensitivity=None,
                 options: FaultTracingOptions | None = None, likelihood: FaultLikelihood | None = None,
                 blocks: BlockRunOptions | None = None, progress=True) -> FaultInterpretation:
    """Trace the faults of a seismic cube or section: likelihood, voting, skins, throw.

    The steps, with their defaults chosen from the data (no per-file tuning):

    1. the fault likelihood: by default the fault network's probability (:func:`~seismo3d.seismic.faults.
       learned_fault_likelihood`, the mean over three network grids), or with ``options.likelihood='scan'``
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

    NaN / inf samples are read as 0 (with a :class:`~seismo3d.errors.Seismo3dWarning`). Dead samples (runs of 5 or
    more equal values along a trace: dead traces, mutes, gaps, NaN runs) are skipped, with a warning: the likelihood
    within 3 traces and 8 samples of them is set to 0, since the edge of a dead zone is not a fault.

    Data that cannot support fault tracing is refused with an :class:`~seismo3d.errors.UnsupportedDataError`:
    too few traces or samples, data that does not oscillate like seismic amplitudes (a velocity model), or a
    likelihood saturated everywhere (no lateral coherence).

    Memory and time: time and memory linear in the number of samples (see ``benchmarks/faults.py`` for the figures
    at 64^3 to 256^3). A 3D cube whose run in memory would need more than ``blocks.memory_limit`` beside the process
    (:func:`~seismo3d.seismic.blocks.memory.fits_in_memory`: 160 MiB and 24 times its float32 size) is traced
    block by block (:mod:`~seismo3d.seismic.faults.blocks.cube_run`) into Zarr stores in ``blocks.work_dir``, with
    the same checks, warnings and results: its arrays are then Zarr arrays. A cube large enough to be judged from a sample of
    blocks first (:meth:`~seismo3d.seismic.faults.blocks.preflight.SampleOptions.worth_sampling`) is refused from that
    sample before the whole likelihood (:func:`~seismo3d.seismic.faults.blocks.preflight.judge_sample`), on either path.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample (time or depth, downward).
    sample_interval : float, optional
        Sample interval in ``sample_unit``; required unless ``sample_unit`` is 'samples'.
    sample_unit : {'samples', 'ms', 'm', 'ft'}, optional
        Unit of the sample axis (for converting throws, see :attr:`FaultInterpretation.sample_interval`).
    sensitivity : float, optional
        In [0, 1], more faults when higher; replaces ``options.sensitivity`` (default 0.5).
    options : FaultTracingOptions, optional
        Options of every step.
    likelihood : FaultLikelihood, optional
        The result of step 1 computed elsewhere with ``options.scan`` (e.g. block by block by
        :func:`~seismo3d.seismic.faults.blocks.scan_blocks.chunked_fault_likelihood`), arrays of the data's shape; the
        scan is then skipped.
    blocks : BlockRunOptions, optional
        How a cube is run: the memory limit (default half of the RAM), a forced choice between the run in memory and
        the run by blocks, the folder of the Zarr stores of a run by blocks (required for one), its dask scheduler,
        and the input's name and coordinates recorded in the stores (:class:`BlockRunOptions`).
    progress : bool, optional
        Report progress over the steps (:mod:`seismo3d._progress`: a bar on a terminal, one log line per step
        otherwise; the likelihood, the voting and the throw report their own progress too).

    Returns
    -------
    FaultInterpretation
        Likelihood, strike, dip, votes, thinned faults, fault skins and their throws.

    Raises
    ------
    InputError
        ``data`` is not a numeric 2D / 3D array with at least 3 samples per axis, all samples are equal, the
        sample interval / unit or an option is invalid, a run by blocks without ``blocks.work_dir`` or with a
        ``blocks.memory_limit`` too small for its blocks (the message names one that works).
    UnsupportedDataError
        The data cannot support fault tracing (see above); the message says why and what to do.

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples, dead samples (constant runs), or clipped amplitudes (more than 5 % of the samples at the
        data's smallest or largest value).

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
    if sensitivity is not None:
        opt = dataclasses.replace(opt, sensitivity=sensitivity)

    run = _block_run(blocks)
    if not run.in_memory_for(np.shape(data), has_likelihood=likelihood is not None):
        if run.work_dir is None:
            raise InputError(f"a {' x '.join(str(n) for n in np.shape(data))} cube beyond the memory limit is traced "
                             "block by block into Zarr stores: pass blocks=BlockRunOptions(work_dir=...) (an "
                             "existing folder), or a larger memory_limit")
        from .blocks.cube_run import trace_faults_by_blocks

        return trace_faults_by_blocks(data, opt, sample_interval=sample_interval, sample_unit=sample_unit,
                                      memory_limit=run.limit, work_dir=run.work_dir, scheduler=run.scheduler,
                                      source=run.source, coords=run.coords, progress=progress)
    arr, dead = _cleaned(data, opt)
    with progress_steps(7, "faults", enabled=progress) as bar:
        bar.start("fault likelihood")
        if likelihood is None:
            with warnings.catch_warnings():  # saturation is decided by the steps, on the live samples
                warnings.simplefilter("ignore", Seismo3dWarning)
                fl = (fault_likelihood(arr, options=opt.scan, progress=progress) if opt.likelihood == "scan" else
                      learned_fault_likelihood(arr, options=opt.learned, progress=progress))
        else:
            fl = _given_likelihood(likelihood, arr.shape)
        near_dead = near_dead_samples(dead, options=opt.dead) if dead.any() else None
        del dead
        bar.advance()
        run = ArrayRun(fl.likelihood, fl.strike_deg, fl.dip_deg, near_dead, opt, progress=progress)
        del fl
        found = surface_cells(run, opt, bar)
        faults, throws, evidence = faults_from_cells(run.cell_arrays, arr.shape, arr, found.thresholds, opt,
                                                     likelihood=run.likelihood, bar=bar, progress=progress)
    votes = run.fault_votes
    return FaultInterpretation(likelihood=run.likelihood, strike_deg=run.strike_deg, dip_deg=run.dip_deg,
                               votes=votes.votes, thin=run.thin, thresholds=found.thresholds, faults=faults,
                               throws=throws, evidence=evidence, sample_interval=float(sample_interval),
                               sample_unit=sample_unit, step_seconds=dict(bar.seconds))


def _block_run(blocks) -> BlockRunOptions:
    """The block-run options given to :func:`trace_faults` (its defaults when None), checked for their type."""
    if blocks is None:
        return BlockRunOptions()
    if not isinstance(blocks, BlockRunOptions):
        raise InputError(f"trace_faults(blocks=...) must be a BlockRunOptions (memory_limit, in_memory, work_dir, "
                         f"scheduler, source, coords); got {type(blocks).__name__}")
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
        cleaned = clean_traces(arr, options=opt.dead)
    check_size(cleaned.data.shape, opt)
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if SampleOptions().worth_sampling(cleaned.data.shape):  # refused from a sample, not after the whole likelihood
        judge_sample(cleaned.data, options=opt)
    check_amplitudes(cleaned.data, cleaned.dead, opt)
    return cleaned.data, cleaned.dead


def _given_likelihood(fl, shape: tuple) -> FaultLikelihood:
    """A precomputed likelihood, checked against the data's shape; its arrays are copied (they are modified)."""
    if not isinstance(fl, FaultLikelihood):
        raise InputError(f"trace_faults(likelihood=...) must be a FaultLikelihood; got {type(fl).__name__}")
    arrays = [np.array(a, dtype=np.float32) for a in (fl.likelihood, fl.strike_deg, fl.dip_deg)]
    if any(a.shape != tuple(shape) for a in arrays):
        raise InputError(f"the given fault likelihood has shape {arrays[0].shape} but the data {tuple(shape)}; "
                         "compute it from the same data")
    return FaultLikelihood(*arrays)
