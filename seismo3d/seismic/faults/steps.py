"""The one sequence of the steps of :func:`~seismo3d.seismic.faults.trace_faults` after the fault likelihood.

:func:`surface_cells` calls the steps of a :class:`~seismo3d.seismic.faults.surfaces.blocks.SurfaceRun` (the
declared block steps of the fault surfaces, run by blocks into Zarr stores or on the whole array in memory as one
block) in their order with the saturation refusal between them, and :func:`faults_from_cells` links the cells into
fault skins, measures their throws, keeps the faults the evidence supports and trims their tips (2D).

The refusals of fault tracing are here too, one function each: data too small for the scan and the voting boxes
(:func:`check_size`), the saturation refusal between the steps (:func:`check_saturation`), and the same refusals
made early on a sample of blocks of a large cube (:func:`judge_sample`, on the blocks the executor's preflight reads:
:func:`~seismo3d.seismic.blocks.preflight.sample_blocks`), which also gives the density of the voting's seed
candidates from which :func:`~seismo3d.seismic.faults.pipeline.minimum_memory_limit` estimates the memory of the
seeds step of a block-by-block run. The sample is measured with the likelihood the run makes
(:func:`run_likelihood`, the one choice between the network and the scan in memory) through the run's own surface
steps (:func:`~seismo3d.seismic.faults.surfaces.blocks.memory_surface_run`).
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..._progress import no_progress
from ..amplitudes import check_amplitudes, clean_traces
from ..blocks import preflight
from ..blocks.preflight import SampleOptions
from ...errors import InputError, Seismo3dWarning, UnsupportedDataError
from .evidence import supported_faults
from .likelihood.learned import learned_fault_likelihood
from .likelihood.scan import fault_likelihood
from .tips import trimmed_tips
from .surfaces.skins import skins_from_cells
from .result import FaultLikelihood
from .throw import fault_throws
from .reflector_period import half_period

if TYPE_CHECKING:  # annotations only: the options are passed in (the run, a surfaces.blocks.SurfaceRun, imports
    from .options import FaultTracingOptions  # this module, so it is named in the docstring only)

__all__ = ["CubeSample", "SurfaceCells", "check_saturation", "check_size", "faults_from_cells", "judge_sample",
           "lateral_coherence", "no_coherence_message", "run_likelihood", "surface_cells"]


@dataclass(frozen=True)
class SurfaceCells:
    """What :func:`surface_cells` found.

    Attributes
    ----------
    thresholds : (float, float)
        Lower and upper thresholds on the thinned votes.
    n_seeds, n_cells : int
        Voting seeds, and thinned-vote samples linked into skins.
    saturated_fraction : float
        Fraction of the live samples with a likelihood above ``saturation_level``.
    """

    thresholds: tuple
    n_seeds: int
    n_cells: int
    saturated_fraction: float


def surface_cells(run, opt: FaultTracingOptions, bar=None) -> SurfaceCells:
    """Ridges, saturation refusal, seeds, votes, thresholds and cells, in this order (Hale 2013; Wu & Fomel 2018).

    Parameters
    ----------
    run : seismo3d.seismic.faults.surfaces.blocks.SurfaceRun
        The fault surfaces' steps on their executor: by blocks, or the whole array in memory as one block.
    opt : FaultTracingOptions
    bar : progress bar, optional
        Of :func:`seismo3d._progress.progress_steps`, advanced once per named step (ridges, voting, thinning);
        default none (a run by blocks reports per block).

    Returns
    -------
    SurfaceCells

    Raises
    ------
    UnsupportedDataError
        The likelihood is saturated (:func:`check_saturation`).
    InputError
        A run by blocks whose seed candidates or cells need more than its memory limit.
    """
    bar = bar or no_progress()
    bar.start("ridges")
    high, live = run.ridges()
    saturated = check_saturation(high, live, opt)
    bar.advance()
    bar.start("voting")
    seeds, frames = run.seeds()
    run.votes(seeds, frames)
    bar.advance()
    bar.start("thinning")
    lower, upper = run.thresholds()
    n_cells = run.cells(lower)
    bar.advance()
    return SurfaceCells((float(lower), float(upper)), int(len(seeds)), int(n_cells), float(saturated))


def check_size(shape: tuple, opt: FaultTracingOptions) -> None:
    """Refuse data too small for the scan and the voting boxes (the executor's preflight check,
    :func:`~seismo3d.seismic.blocks.preflight.check_size`, with ``opt.min_traces`` and ``opt.min_samples``).

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
    preflight.check_size(shape, min_traces=opt.min_traces, min_samples=opt.min_samples, task="fault tracing",
                         spans="the fault-plane windows and voting boxes")


def check_saturation(high: int, live: int, opt: FaultTracingOptions) -> float:
    """Refuse data whose likelihood is high almost everywhere (no lateral coherence).

    Parameters
    ----------
    high, live : int
        Live samples (not near dead ones) with a likelihood above ``opt.saturation_level``, and all live samples: counted over the whole
        array in memory, summed over the blocks of a run by blocks
        (:func:`~seismo3d.seismic.faults.surfaces.ridges.live_likelihood`).
    opt : FaultTracingOptions

    Returns
    -------
    float
        The fraction ``high / live`` (0 when nothing is live).

    Raises
    ------
    UnsupportedDataError
        The fraction exceeds ``opt.max_saturated``.
    """
    fraction = float(high) / float(live) if live else 0.0
    if fraction > opt.max_saturated:
        raise UnsupportedDataError(no_coherence_message(fraction, opt.saturation_level))
    return fraction


_NO_COHERENCE = ("the data has no lateral coherence to trace faults in (noise, chaotic reflections, or traces out "
                 "of order); check the inline/crossline geometry or the file")


def no_coherence_message(fraction: float, level: float) -> str:
    """The refusal of data without lateral coherence, its likelihood above ``level`` (the options'
    ``saturation_level``) at ``fraction`` of the samples."""
    return f"the fault likelihood is above {level:g} at {fraction:.0%} of the samples: " + _NO_COHERENCE


def run_likelihood(data: np.ndarray, opt: FaultTracingOptions, *, progress: bool = False) -> FaultLikelihood:
    """The fault likelihood the run makes of amplitudes in memory, the one choice between the two: the fault network's
    probability (``opt.likelihood == 'learned'``, the default, with ``opt.learned``) or the scan of strikes and dips
    (``'scan'``, with ``opt.scan``); the run by blocks runs the same steps block by block.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Amplitudes, finite (:func:`~seismo3d.seismic.amplitudes.clean_traces`).
    opt : FaultTracingOptions
    progress : bool
        Report the likelihood's own progress.

    Returns
    -------
    FaultLikelihood
        Likelihood in [0, 1], strike and dip (degrees), float32 arrays of ``data``'s shape
        (:func:`~seismo3d.seismic.faults.learned_fault_likelihood`, Wu et al. 2019; or
        :func:`~seismo3d.seismic.faults.fault_likelihood`, Hale 2013).
    """
    with warnings.catch_warnings():  # saturation is decided by the steps, on the live samples
        warnings.simplefilter("ignore", Seismo3dWarning)
        if opt.likelihood == "scan":
            return fault_likelihood(data, options=opt.scan, progress=progress)
        return learned_fault_likelihood(data, options=opt.learned, progress=progress)


@dataclass(frozen=True)
class CubeSample:
    """What :func:`judge_sample` measured.

    Attributes
    ----------
    n_blocks : int
        Blocks read.
    n_samples : int
        Samples read.
    saturated_fraction : float
        Fraction of the live samples whose fault likelihood (the run's: :func:`run_likelihood`) exceeds
        ``saturation_level``.
    candidate_density : float
        Seed candidates of the voting (fault-likelihood ridges above ``VotingOptions.seed_threshold``) per sample.
    coherence : float
        Lateral coherence of the amplitudes (:func:`lateral_coherence`).
    """

    n_blocks: int
    n_samples: int
    saturated_fraction: float
    candidate_density: float
    coherence: float = 1.0

    def candidates(self, shape) -> int:
        """The seed candidates expected in a cube of ``shape``.

        Parameters
        ----------
        shape : tuple of int

        Returns
        -------
        int
        """
        return int(np.ceil(self.candidate_density * float(np.prod(shape, dtype=np.float64))))


def judge_sample(cube, *, options: FaultTracingOptions, sample: SampleOptions | None = None) -> CubeSample:
    """Judge a 3D cube from a few blocks before tracing its faults: refuse data that is not seismic amplitudes or has
    no lateral coherence, and measure the saturation and the density of the voting's seed candidates of the
    likelihood the run makes.

    Each block is cleaned (:func:`~seismo3d.seismic.amplitudes.clean_traces`) and the amplitudes checked
    (:func:`~seismo3d.seismic.amplitudes.check_amplitudes`); their lateral coherence is measured
    (:func:`lateral_coherence`, refused below ``sample.min_coherence``); then each block runs the run's likelihood
    (:func:`run_likelihood`) and the run's ridges step on one block
    (:func:`~seismo3d.seismic.faults.surfaces.blocks.memory_surface_run`), which count the saturated live samples
    (refused above ``sample.saturated``) and the seed candidates.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) array_like or dask.array.Array
        Amplitudes; only the sampled blocks are read.
    options : FaultTracingOptions
        The run's options (the amplitude check, the likelihood and its options, the voting's seed threshold).
    sample : SampleOptions, optional
        The blocks read and the refusals' limits (:class:`~seismo3d.seismic.blocks.preflight.SampleOptions`).

    Returns
    -------
    CubeSample

    Raises
    ------
    UnsupportedDataError
        Too few traces or samples, traces that do not oscillate like seismic amplitudes, traces that do not resemble
        their neighbours more than noise does, or a sample whose fault likelihood is saturated (no lateral
        coherence); the message says what the sample showed.
    InputError
        ``cube`` is not 3D.
    """
    from .surfaces.blocks import memory_surface_run  # that module runs the steps of this one (surface_cells)

    opt = options
    sample = sample or SampleOptions()
    shape = tuple(int(n) for n in getattr(cube, "shape", ()))
    if len(shape) != 3:
        raise InputError(f"judge_sample needs a 3D cube (n_inlines, n_xlines, n_samples); got shape {shape}")
    check_size(shape, opt)
    amplitudes, dead_masks = [], []
    for block in preflight.sample_blocks(cube, sample):
        with warnings.catch_warnings():  # dead or clipped samples are reported by the run itself
            warnings.simplefilter("ignore", Seismo3dWarning)
            cleaned = clean_traces(block, options=opt.dead)
        amplitudes.append(cleaned.data)
        dead_masks.append(cleaned.dead)
    read = sum(a.size for a in amplitudes)
    where = f"in a sample of {len(amplitudes)} blocks of {amplitudes[0].shape[0]} x {amplitudes[0].shape[1]} traces"
    check_amplitudes(np.concatenate(amplitudes), np.concatenate(dead_masks), opt.min_crossings)
    coherence = lateral_coherence(amplitudes, dead_masks, max_lag=sample.max_lag)
    if coherence < sample.min_coherence:
        raise UnsupportedDataError(f"{where}, neighbouring traces correlate at {coherence:.2f} (the median of their "
                                   f"best correlation within {sample.max_lag} samples; below {sample.min_coherence:g}"
                                   f"): " + _NO_COHERENCE)
    high = live = candidates = 0
    for data in amplitudes:  # the run's likelihood, then the run's ridges step on one block
        fl = run_likelihood(data, opt)
        run = memory_surface_run(data, fl.likelihood, fl.strike_deg, fl.dip_deg, opt)
        del fl
        block_high, block_live = run.ridges()
        found = run.run.gathered_lists("ridges", run.blocks("ridges"), ("values",))["values"]
        high, live, candidates = high + block_high, live + block_live, candidates + int(found.size)
        del run, found
    fraction = high / live if live else 0.0
    if fraction > sample.saturated:
        raise UnsupportedDataError(f"{where}, " + no_coherence_message(fraction, opt.saturation_level))
    return CubeSample(len(amplitudes), read, float(fraction), candidates / read if read else 0.0, float(coherence))


def lateral_coherence(blocks: list, dead: list | None = None, *, max_lag: int = 4) -> float:
    """How alike neighbouring traces are: the median, over every pair of traces next to each other along an inline
    or a crossline, of their largest normalised cross-correlation at a shift of at most ``max_lag`` samples.

    Reflections continue from trace to trace (seismic lines measure 0.8-1.0); white noise, or traces out of order,
    measure about ``1.3 / sqrt(n_samples)`` (0.08 on 256 samples). A pair with a dead or constant trace is left out.

    Parameters
    ----------
    blocks : list of (n0, n1, n_samples) float32 ndarray
        Amplitudes (finite).
    dead : list of (n0, n1, n_samples) bool ndarray, optional
        Dead samples of each block (:func:`~seismo3d.seismic.amplitudes.clean_traces`): a trace holding one is
        left out.
    max_lag : int
        Largest shift tried, samples (reflections dipping by up to that many samples a trace).

    Returns
    -------
    float
        In [-1, 1]; 1.0 when no pair is live.
    """
    best = []
    for k, block in enumerate(blocks):
        x = np.asarray(block, np.float64)
        bad = np.asarray(dead[k]).any(axis=-1) if dead is not None else np.zeros(x.shape[:-1], bool)
        for axis in (0, 1):
            if x.shape[axis] < 2:
                continue
            a, b = np.moveaxis(x, axis, 0)[:-1], np.moveaxis(x, axis, 0)[1:]
            keep = ~(np.moveaxis(bad, axis, 0)[:-1] | np.moveaxis(bad, axis, 0)[1:])
            n = x.shape[-1]
            pair = np.full(a.shape[:-1], -np.inf)
            for lag in range(-int(max_lag), int(max_lag) + 1):
                u = a[..., max(lag, 0):n + min(lag, 0)]
                v = b[..., max(-lag, 0):n - max(lag, 0)]
                u = u - u.mean(axis=-1, keepdims=True)
                v = v - v.mean(axis=-1, keepdims=True)
                norm = np.sqrt((u * u).sum(axis=-1) * (v * v).sum(axis=-1))
                with np.errstate(invalid="ignore", divide="ignore"):
                    pair = np.maximum(pair, np.where(norm > 0, (u * v).sum(axis=-1) / norm, -np.inf))
            best.append(pair[keep & np.isfinite(pair)])
    values = np.concatenate(best) if best else np.empty(0)
    return float(np.median(values)) if values.size else 1.0


def faults_from_cells(cells: tuple, shape: tuple, windows, thresholds: tuple, opt: FaultTracingOptions, *,
                      likelihood=None, bar=None, progress: bool = False) -> tuple[list, list, list]:
    """Fault skins of the cells, their throws, their strength along them, and the faults their evidence supports,
    their tips trimmed (2D: :func:`~seismo3d.seismic.faults.tips.trimmed_tips`).

    Parameters
    ----------
    cells : tuple
        (points (n, 3) int, values, strike_deg, dip_deg (n,) float32) of the run's cells, in C order.
    shape : tuple of int
        Shape of the image (2D or 3D).
    windows : ndarray or window source
        The amplitudes, for :func:`~seismo3d.seismic.fault_throws`.
    thresholds : (float, float)
        Lower and upper thresholds of the skins' hysteresis.
    opt : FaultTracingOptions
    likelihood : ndarray or zarr.Array, optional
        The fault likelihood of the run, the shape of the image: its mean along each fault
        (:attr:`~seismo3d.seismic.faults.evidence.FaultEvidence.mean_likelihood`) is read at the fault's points.
        Needed when ``opt.evidence.min_probability`` is set.
    bar : progress bar, optional
        Advanced once per step (fault skins, throw, evidence).
    progress : bool
        Progress of the throws per fault.

    Returns
    -------
    (faults, throws, evidence) : lists
        As :attr:`~seismo3d.seismic.faults.FaultInterpretation.faults`, ``throws`` and ``evidence``.

    Raises
    ------
    InputError
        ``opt.evidence`` asks for the mean likelihood and ``likelihood`` is not given.
    """
    bar = bar or no_progress()
    lower, upper = thresholds
    bar.start("fault skins")
    faults = skins_from_cells(*cells, shape=shape, lower=lower, upper=upper, options=opt.skins)
    seeded = [True] * len(faults)
    if opt.evidence.unseeded_correlation_gain is not None and faults and len(shape) == 2:  # never seeded (2D):
        shape3 = (shape[0], 1, shape[1])  # a second hysteresis from the lower threshold, on the cells the first left
        used = np.concatenate([np.insert(f.points, 1, 0, axis=1) for f in faults])
        free = ~np.isin(np.ravel_multi_index(tuple(np.asarray(cells[0]).T), shape3),
                        np.ravel_multi_index(tuple(used.T), shape3))
        more = skins_from_cells(*(np.asarray(c)[free] for c in cells), shape=shape, lower=lower, upper=lower,
                                options=opt.skins) if free.any() else []
        faults += [dataclasses.replace(f, id=len(faults) + i + 1) for i, f in enumerate(more)]
        seeded += [False] * len(more)
    bar.advance()
    bar.start("throw")
    throws = fault_throws(windows, faults, progress=progress) if faults else []
    if opt.evidence.clear_half_periods is not None or opt.evidence.drag_half_periods is not None:  # half periods
        throws = [dataclasses.replace(t, half_period=half_period(windows, f.points)) for f, t in zip(faults, throws)]
    bar.advance()
    bar.start("evidence")
    ratios = [float(np.mean(f.likelihood)) / float(upper) for f in faults]  # a skin's values are its thinned votes
    means = _values_along(likelihood, faults) if likelihood is not None else None
    faults, throws, evidence = supported_faults(faults, list(throws), options=opt.evidence,
                                                sensitivity=opt.sensitivity, vote_ratios=ratios,
                                                mean_likelihoods=means, seeded=seeded)
    faults, throws = trimmed_tips(faults, throws, likelihood, opt.tip_level_for(len(shape)))  # voted past the tips
    bar.advance()
    return faults, throws, evidence


def _values_along(image, faults: list) -> list[float]:
    """The mean of ``image`` over each fault's points.

    Parameters
    ----------
    image : ndarray or zarr.Array
        An image of the faults' data (2D or 3D), e.g. the fault likelihood; a Zarr array is read at the points only
        (coordinate selection), all faults at once.
    faults : list of Fault
        Faults with ``points`` (n, ndim) integer indices into ``image``.

    Returns
    -------
    list of float
        One mean per fault (NaN for a fault without points).
    """
    if not faults:
        return []
    points = np.concatenate([np.asarray(f.points, np.int64) for f in faults])
    index = tuple(points.T)
    values = (np.asarray(image[index]) if isinstance(image, np.ndarray)
              else np.asarray(image.get_coordinate_selection(index)))
    out, start = [], 0
    for f in faults:
        n = len(f.points)
        out.append(float(values[start:start + n].astype(np.float64).mean()) if n else float("nan"))
        start += n
    return out
