"""The one sequence of the steps of :func:`~seismo3d.seismic.faults.trace_faults` after the fault likelihood.

:func:`surface_cells` calls the steps of a :class:`~seismo3d.seismic.faults.surfaces.blocks.SurfaceRun` (the
declared block steps of the fault surfaces, run by blocks into Zarr stores or on the whole array in memory as one
block) in their order with the saturation refusal between them, and :func:`faults_from_cells` links the cells into
fault skins, measures their throws, keeps the faults the evidence supports and trims their tips (2D).

The refusals of fault tracing are here too, one function each: data too small for the scan and the voting boxes
(:func:`check_size`) and the saturation refusal between the steps (:func:`check_saturation`); the same refusals are
made early on a sample of blocks of a large cube by :mod:`~seismo3d.seismic.faults.preflight`, with the likelihood
the run makes (:func:`run_likelihood`, the one choice between the network and the scan in memory).
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..._progress import no_progress
from ..blocks import preflight
from ...errors import Seismo3dWarning, UnsupportedDataError
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

__all__ = ["NO_COHERENCE", "SurfaceCells", "check_saturation", "check_size", "faults_from_cells",
           "no_coherence_message", "run_likelihood", "surface_cells"]


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


NO_COHERENCE = ("the data has no lateral coherence to trace faults in (noise, chaotic reflections, or traces out "
                 "of order); check the inline/crossline geometry or the file")


def no_coherence_message(fraction: float, level: float) -> str:
    """The refusal of data without lateral coherence, its likelihood above ``level`` (the options'
    ``saturation_level``) at ``fraction`` of the samples."""
    return f"the fault likelihood is above {level:g} at {fraction:.0%} of the samples: " + NO_COHERENCE


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
