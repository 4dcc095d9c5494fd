"""The fault interpretation of an array: fault likelihood -> optimal surface voting -> fault skins -> throw.

After Hale (2013, 2014) and Wu & Fomel (2018). :func:`trace_faults` runs the steps with the defaults every seismo3d
command uses and returns a :class:`FaultInterpretation`; :func:`clean_traces` finds the dead samples (mutes, dead
traces, gaps) whose edges are not faults, and reports clipped amplitudes. Reading files and writing results is the
``faults`` command's job (:mod:`seismo3d.jobs.faults`).

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.faults.likelihood`.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..._progress import progress_steps
from ..._validation import check_choice, check_positive
from ...errors import InputError, Seismo3dWarning, UnsupportedDataError
from .dead_samples import CleanTraces, clean_traces, near_dead_samples
from .evidence import EvidenceOptions, sensitivity_factor, supported_faults
from .likelihood import FaultLikelihood, FaultScanOptions, fault_likelihood
from .learned import LearnedOptions, learned_fault_likelihood
from .skins import SkinOptions, fault_skins
from .surfaces import thin_faults
from .throw import fault_throws
from .voting import VotingOptions, vote_faults

__all__ = ["FaultInterpretation", "FaultTracingOptions", "CleanTraces", "clean_traces", "trace_faults"]

_UNITS = {"samples", "ms", "m", "ft"}
LIKELIHOODS = ("scan", "learned")


@dataclass(frozen=True)
class FaultTracingOptions:
    """Options of :func:`trace_faults`; the defaults are the ones every seismo3d command uses, on every input.

    Attributes
    ----------
    sensitivity : float
        In [0, 1]: how readily a fault is traced. The upper threshold on the thinned votes is the data's Otsu
        threshold times ``2 ** (1 - 2 * sensitivity)`` (twice it at 0, half of it at 1, the threshold itself at the
        default 0.5), at least ``min_vote`` times the same factor; the lower threshold is a third of the upper one.
    min_vote : float
        Floor of the upper threshold at the default sensitivity, on the absolute scale of
        :class:`~seismo3d.seismic.faults.voting.FaultVotes` (about the mean likelihood of the surfaces through a
        sample): data whose votes are all weak yield no faults rather than the strongest of its noise.
    max_fault_fraction : float
        The lower threshold leaves at most this fraction of the samples on thinned faults (scaled like the
        thresholds by the sensitivity): a fault every 8 traces is already dense faulting (12 % on the Costa Rica
        sections), and denser ridges are the uniform votes of incoherent data, not faults.
    likelihood : {'scan', 'learned'}
        The fault likelihood of step 1: the scan of fault-plane semblance (Hale 2013, ``scan``) or the fault network
        trained on generated sections (:mod:`~seismo3d.seismic.faults.learned`, ``learned``).
    scan : FaultScanOptions
        The fault likelihood scan.
    learned : LearnedOptions
        The learned fault likelihood.
    voting : VotingOptions
        The optimal surface voting.
    skins : SkinOptions
        The linking into fault skins.
    evidence : EvidenceOptions
        The displacement a fault must show to be kept (:func:`~seismo3d.seismic.faults.evidence.supported_faults`).
    min_traces : (int, int)
        Fewest traces along the longer and the shorter lateral axis (2D: along the section) for the scan and the
        voting boxes to see a fault's continuity; smaller data is refused.
    min_samples : int
        Fewest samples per trace.
    min_crossings : float
        Fewest zero crossings per 100 samples of a trace with its mean removed (median over traces): seismic
        amplitudes oscillate (a reflection every few samples), velocity or impedance models do not.
    max_saturated : float
        Largest fraction of the live samples with a likelihood above 0.9; beyond it the data has no lateral
        coherence to trace faults in (noise, or traces out of order) and is refused.

    Raises
    ------
    InputError
        A value out of range.
    """

    sensitivity: float = 0.5
    min_vote: float = 0.1
    max_fault_fraction: float = 0.15
    likelihood: str = "scan"
    scan: FaultScanOptions = field(default_factory=FaultScanOptions)
    learned: LearnedOptions = field(default_factory=LearnedOptions)
    voting: VotingOptions = field(default_factory=VotingOptions)
    skins: SkinOptions = field(default_factory=SkinOptions)
    evidence: EvidenceOptions = field(default_factory=EvidenceOptions)
    min_traces: tuple = (32, 8)
    min_samples: int = 32
    min_crossings: float = 3.0
    max_saturated: float = 0.95

    def __post_init__(self):
        if not 0.0 <= float(self.sensitivity) <= 1.0:
            raise InputError(f"sensitivity must be in [0, 1]; got {self.sensitivity!r}")
        if not 0.0 <= float(self.min_vote) < 1.0:
            raise InputError(f"min_vote must be in [0, 1); got {self.min_vote!r}")
        if not 0.0 < float(self.max_fault_fraction) <= 1.0:
            raise InputError(f"max_fault_fraction must be in (0, 1]; got {self.max_fault_fraction!r}")
        check_choice(self.likelihood, "likelihood", LIKELIHOODS)
        for name, cls in (("scan", FaultScanOptions), ("learned", LearnedOptions), ("voting", VotingOptions),
                          ("skins", SkinOptions), ("evidence", EvidenceOptions)):
            if not isinstance(getattr(self, name), cls):
                raise InputError(f"{name} must be a {cls.__name__}; got {type(getattr(self, name)).__name__}")
        if (len(tuple(self.min_traces)) != 2 or any(int(v) != v or v < 3 for v in self.min_traces)):
            raise InputError(f"min_traces must be two integers >= 3; got {self.min_traces!r}")
        object.__setattr__(self, "min_traces", tuple(int(v) for v in self.min_traces))
        check_positive(self.min_samples, "min_samples")
        check_positive(self.min_crossings, "min_crossings", allow_zero=True)
        if not 0.0 < float(self.max_saturated) <= 1.0:
            raise InputError(f"max_saturated must be a fraction in (0, 1]; got {self.max_saturated!r}")

    def thresholds(self, thinned_votes: np.ndarray) -> tuple[float, float]:
        """(lower, upper) thresholds on the thinned votes (see ``sensitivity`` and ``max_fault_fraction``)."""
        values = thinned_votes[thinned_votes > 0]
        otsu = _otsu(values) if values.size else 1.0
        return self.thresholds_from(otsu, values.size, thinned_votes.size,
                                    lambda q: float(np.quantile(values, q)))

    def thresholds_from(self, otsu: float, n_values: int, n_samples: int, quantile) -> tuple[float, float]:
        """(lower, upper) thresholds from statistics of the thinned votes, as :meth:`thresholds` (for a cube whose
        thinned votes are gathered block by block).

        Parameters
        ----------
        otsu : float
            Otsu's threshold of the positive thinned votes (1 when there are none).
        n_values, n_samples : int
            Number of positive thinned votes, and of samples.
        quantile : callable
            ``quantile(q)``: the q-quantile of the positive thinned votes (``numpy.quantile``'s linear method);
            called only when they are denser than ``max_fault_fraction`` allows.

        Returns
        -------
        (float, float)
        """
        factor = sensitivity_factor(self.sensitivity)
        upper = min(0.99, factor * max(float(otsu), float(self.min_vote)))
        lower = upper / 3.0
        fraction = min(1.0, float(self.max_fault_fraction) / factor)
        if n_values > fraction * n_samples:
            dense = float(quantile(1.0 - fraction * n_samples / n_values))
            if dense > lower:
                lower = min(dense, 0.99)
                upper = max(upper, min(0.99, 3.0 * lower))
        return lower, upper


def _otsu(values: np.ndarray) -> float:
    from skimage.filters import threshold_otsu

    if values.size == 0 or float(values.max()) <= float(values.min()):
        return float(values.max()) if values.size else 1.0
    return float(threshold_otsu(values))


@dataclass(frozen=True)
class FaultInterpretation:
    """Result of :func:`trace_faults`.

    Attributes
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Fault likelihood in [0, 1] (0 on and next to dead samples).
    strike_deg, dip_deg : same shape, float32 ndarray
        Strike and dip of the most likely fault plane at each sample, degrees, index space.
    votes : same shape, float32 ndarray
        Optimal-surface votes in [0, 1] (:func:`~seismo3d.seismic.vote_faults`): about the mean likelihood of the
        fault surfaces through each sample.
    thin : same shape, float32 ndarray
        The votes on the 1-sample-wide thinned faults above the lower threshold, 0 elsewhere.
    thresholds : (float, float)
        The lower and upper thresholds on the thinned votes (see :class:`FaultTracingOptions`).
    faults : list of Fault
        Fault skins (surfaces in 3D, curves in 2D), ids 1, 2, ... by decreasing size; their ``likelihood`` holds the
        thinned votes.
    throws : list of FaultThrow
        One per fault, in the order of ``faults``; ``throws[i].throw`` is the vertical throw at each point of
        ``faults[i]``, in samples.
    evidence : list of FaultEvidence
        One per fault: median throw, its spread, the sides' correlation and its gain from the throw's shift.
    sample_interval : float
        Sample interval in ``sample_unit`` (1 for 'samples').
    sample_unit : {'samples', 'ms', 'm', 'ft'}
        Unit of the sample axis.
    """

    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    votes: np.ndarray
    thin: np.ndarray
    thresholds: tuple
    faults: list
    throws: list
    evidence: list
    sample_interval: float
    sample_unit: str


def trace_faults(data, *, sample_interval=None, sample_unit="samples", sensitivity=None,
                 options: FaultTracingOptions | None = None, likelihood: FaultLikelihood | None = None,
                 progress=True) -> FaultInterpretation:
    """Trace the faults of a seismic cube or section: likelihood, voting, skins, throw.

    The steps, with their defaults chosen from the data (no per-file tuning):

    1. :func:`~seismo3d.seismic.faults.fault_likelihood`: scan of fault strikes and dips of the semblance of balanced
       amplitudes (Hale 2013);
    2. :func:`~seismo3d.seismic.thin_faults`: its ridges (non-maximum suppression across the fault), the seeds;
    3. :func:`~seismo3d.seismic.vote_faults`: optimal surface voting (Wu & Fomel 2018), which makes faults
       continuous across gaps of the likelihood and leaves isolated noise weak;
    4. the votes thinned, and thresholded from the data (Otsu, see :class:`FaultTracingOptions`);
    5. :func:`~seismo3d.seismic.faults.fault_skins`: the thinned votes linked into fault surfaces (curves in 2D);
    6. :func:`~seismo3d.seismic.fault_throws`: vertical throw by registering the reflectors on both sides;
    7. :func:`~seismo3d.seismic.faults.evidence.supported_faults`: only the faults across which the reflectors are
       displaced are kept (a throw of at least a sample that aligns the sides better than no shift).

    NaN / inf samples are read as 0 (with a :class:`~seismo3d.errors.Seismo3dWarning`). Dead samples (runs of 5 or
    more equal values along a trace: dead traces, mutes, gaps, NaN runs) are skipped, with a warning: the likelihood
    within 3 traces and 8 samples of them is set to 0, since the edge of a dead zone is not a fault.

    Data that cannot support fault tracing is refused with an :class:`~seismo3d.errors.UnsupportedDataError`:
    too few traces or samples, data that does not oscillate like seismic amplitudes (a velocity model), or a
    likelihood saturated everywhere (no lateral coherence).

    Memory and time: the whole array is processed in memory, time and memory linear in the number of samples (see
    ``benchmarks/faults.py`` for the figures at 64^3 to 256^3).

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
        :func:`~seismo3d.seismic.faults.likelihood_blocks.chunked_fault_likelihood`), arrays of the data's shape; the
        scan is then skipped.
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
        ``data`` is not a numeric 2D / 3D array with at least 3 samples per axis, all samples are equal, or the
        sample interval / unit or an option is invalid.
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

    # bad arrays raise InputError; data that cannot support fault tracing is refused before any work, and before
    # warnings about its dead or clipped samples that would not matter then
    arr = np.asarray(data)
    if arr.ndim in (2, 3) and min(arr.shape) < 3 and np.issubdtype(arr.dtype, np.number):
        check_size(arr.shape, opt)  # numbers, but below clean_traces' 3 samples per axis: the size message
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", Seismo3dWarning)
        cleaned = clean_traces(arr)
    check_size(cleaned.data.shape, opt)
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    arr, dead = cleaned.data, cleaned.dead
    del cleaned
    check_amplitudes(arr, dead, opt)
    with progress_steps(7, "faults", enabled=progress) as bar:
        bar.start("fault likelihood")
        if likelihood is None:
            with warnings.catch_warnings():  # saturation is decided below, on the live samples
                warnings.simplefilter("ignore", Seismo3dWarning)
                fl = (fault_likelihood(arr, options=opt.scan, progress=progress) if opt.likelihood == "scan" else
                      learned_fault_likelihood(arr, options=opt.learned, progress=progress))
        else:
            fl = _given_likelihood(likelihood, arr.shape)
        likelihood, strike, dip = fl.likelihood, fl.strike_deg, fl.dip_deg
        del fl
        near_dead = near_dead_samples(dead) if dead.any() else None
        if near_dead is not None:  # the edge of a dead zone is not a fault
            likelihood[near_dead] = 0.0
        _check_saturation(likelihood, near_dead, opt)
        del dead
        bar.advance()
        bar.start("ridges")
        ridges = thin_faults(likelihood, strike, dip, threshold=0.0)
        bar.advance()
        bar.start("voting")
        votes = vote_faults(likelihood, strike, dip, ridges, options=opt.voting, progress=progress)
        del ridges
        if near_dead is not None:  # voting surfaces bridge gaps, but a fault is not drawn across dead traces
            votes.votes[near_dead] = 0.0
        bar.advance()
        bar.start("thinning")
        thin = thin_faults(votes.votes, votes.strike_deg, votes.dip_deg, threshold=0.0, sigma=0.0, dip_smoothing=0)
        lower, upper = opt.thresholds(thin)
        thin[thin < lower] = 0.0
        bar.advance()
        bar.start("fault skins")
        faults = fault_skins(thin, votes.strike_deg, votes.dip_deg, lower=lower, upper=upper, options=opt.skins)
        bar.advance()
        bar.start("throw")
        throws = fault_throws(arr, faults, progress=progress) if faults else []
        bar.advance()
        bar.start("evidence")
        faults, throws, evidence = supported_faults(faults, list(throws), options=opt.evidence,
                                                    sensitivity=opt.sensitivity)
        bar.advance()
    return FaultInterpretation(likelihood=likelihood, strike_deg=strike, dip_deg=dip, votes=votes.votes, thin=thin,
                               thresholds=(float(lower), float(upper)), faults=faults, throws=throws,
                               evidence=evidence, sample_interval=float(sample_interval), sample_unit=sample_unit)


def _given_likelihood(fl, shape: tuple) -> FaultLikelihood:
    """A precomputed likelihood, checked against the data's shape; its arrays are copied (they are modified)."""
    if not isinstance(fl, FaultLikelihood):
        raise InputError(f"trace_faults(likelihood=...) must be a FaultLikelihood; got {type(fl).__name__}")
    arrays = [np.array(a, dtype=np.float32) for a in (fl.likelihood, fl.strike_deg, fl.dip_deg)]
    if any(a.shape != tuple(shape) for a in arrays):
        raise InputError(f"the given fault likelihood has shape {arrays[0].shape} but the data {tuple(shape)}; "
                         "compute it from the same data")
    return FaultLikelihood(*arrays)


def check_size(shape: tuple, opt: FaultTracingOptions) -> None:
    """Refuse data too small for the scan and the voting boxes.

    Parameters
    ----------
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)`` or ``(n_traces, n_samples)``.
    opt : FaultTracingOptions

    Raises
    ------
    UnsupportedDataError
        Fewer traces or samples than ``opt.min_traces`` / ``opt.min_samples``.
    """
    lateral = sorted(shape[:-1], reverse=True)
    need = list(opt.min_traces[: len(lateral)])
    if any(n < m for n, m in zip(lateral, need)) or shape[-1] < opt.min_samples:
        size = " x ".join(str(n) for n in shape[:-1])
        want = (f"{need[0]} traces along one lateral axis and {need[1]} along the other" if len(need) == 2 else
                f"{need[0]} traces")
        raise UnsupportedDataError(
            f"the data has {size} trace{'s' if np.prod(shape[:-1]) != 1 else ''} of {shape[-1]} samples: fault "
            f"tracing needs at least {want}, and "
            f"{opt.min_samples} samples per trace (the fault-plane windows and voting boxes span that much); "
            "trace a larger cube or section")


def check_amplitudes(arr: np.ndarray, dead: np.ndarray, opt: FaultTracingOptions) -> None:
    """Refuse data whose traces do not oscillate like seismic amplitudes (median zero crossings per 100 samples below
    ``opt.min_crossings``, over up to about 4000 live traces).

    Parameters
    ----------
    arr : (..., n_samples) float ndarray
        Amplitudes (NaN-free, as :func:`~seismo3d.seismic.faults.dead_samples.clean_traces` returns them).
    dead : bool ndarray of ``arr``'s shape
        Dead samples.
    opt : FaultTracingOptions

    Raises
    ------
    UnsupportedDataError
        Every trace dead, or too few zero crossings.
    """
    live = ~dead.all(axis=-1)
    traces = arr[live] if arr.ndim == 2 else arr.reshape(-1, arr.shape[-1])[live.ravel()]
    traces = traces[:: max(1, traces.shape[0] // 4000)].astype(np.float64)
    if traces.shape[0] == 0:
        raise UnsupportedDataError("every trace is dead (constant): there is nothing to trace faults in")
    centred = traces - traces.mean(axis=1, keepdims=True)
    crossings = float(np.median(np.count_nonzero(np.diff(np.signbit(centred), axis=1), axis=1)))
    per_100 = 100.0 * crossings / traces.shape[1]
    if per_100 < opt.min_crossings:
        raise UnsupportedDataError(
            f"the traces cross their mean {per_100:.1f} times per 100 samples (seismic reflections: 10-30 times): "
            "this is not seismic amplitude data (a velocity or impedance model?); fault tracing needs a stacked, "
            "migrated seismic image")


def _check_saturation(likelihood: np.ndarray, near_dead, opt: FaultTracingOptions) -> None:
    """Refuse data whose likelihood is high almost everywhere (no lateral coherence)."""
    values = likelihood if near_dead is None else likelihood[~near_dead]
    if values.size == 0:
        return
    high = float(np.count_nonzero(values > 0.9)) / float(values.size)
    if high > opt.max_saturated:
        raise UnsupportedDataError(no_coherence_message(high))


def no_coherence_message(fraction: float) -> str:
    """The refusal of data without lateral coherence, its likelihood above 0.9 at ``fraction`` of the samples."""
    return (f"the fault likelihood is above 0.9 at {fraction:.0%} of the samples: the data has no lateral coherence "
            "to trace faults in (noise, chaotic reflections, or traces out of order); check the inline/crossline "
            "geometry or the file")
