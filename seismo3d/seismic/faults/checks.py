"""The refusals of fault tracing, and the checks of the data before the work: data too small, not seismic amplitudes,
or without lateral coherence, judged on the whole array in memory or on a sample of blocks of a large cube; NaN,
constant, clipped and dead samples of a cube read by blocks.

One function a check, called by every way a fault run goes: in memory and block by block
(:mod:`~seismo3d.seismic.faults.pipeline`). :func:`judge_sample` reads a few blocks spread over the cube and applies to
them the refusals that otherwise come only after the whole fault likelihood: data that does not oscillate like seismic
amplitudes (a velocity model) and data without lateral coherence (noise, traces out of order). A refusal from the
sample is stricter than the full run's own (``SampleOptions.saturated``), so data the full run would trace is not
refused here; the full run's checks still apply to the rest (the saturation refusal between the steps:
:func:`~seismo3d.seismic.faults.steps.check_saturation`). The sample also gives the density of the voting's seed
candidates, from which :func:`~seismo3d.seismic.faults.pipeline.minimum_memory_limit` estimates the memory of the seeds
step of a block-by-block run. :func:`finite_cube` makes, from passes over the blocks of a lazy cube, the checks of the
data the run in memory makes (NaN / inf samples read as 0, constant data refused, clipped amplitudes and dead samples
warned about: the warnings of :mod:`~seismo3d.seismic.faults.surfaces.dead_samples`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..._validation import check_int, check_positive
from ...errors import InputError, Seismo3dWarning, UnsupportedDataError
from .likelihood.scan import fault_likelihood
from .options import FaultTracingOptions
from .steps import no_coherence_message
from .surfaces.dead_samples import (
    DeadSampleOptions, check_varies, clean_traces, clipped_count, dead_samples, fill_values, near_dead_samples,
    warn_clipped, warn_dead, warn_non_finite,
)
from .surfaces.ridges import live_likelihood, ridges

__all__ = ["CubeSample", "SampleOptions", "check_amplitudes", "check_size", "finite_cube", "judge_sample"]


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
        Amplitudes (NaN-free, as :func:`~seismo3d.seismic.faults.surfaces.dead_samples.clean_traces` returns them).
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


# Where the sampled blocks sit, as fractions of the lateral extent left around a block: the centre, then halfway to
# each corner.
_SPOTS = ((0.5, 0.5), (0.25, 0.25), (0.75, 0.75), (0.25, 0.75), (0.75, 0.25))


@dataclass(frozen=True)
class SampleOptions:
    """How :func:`judge_sample` samples a cube.

    Attributes
    ----------
    n_blocks : int
        Blocks read, 1 to 5, spread over the cube: its centre, then points halfway to its corners.
    traces : int
        Traces a side of a block (fewer on a smaller cube).
    samples : int
        Samples of a block, centred on the middle of the traces (all of them on shorter traces).
    saturated : float
        The sample refuses the data when the fault likelihood exceeds the run's ``saturation_level`` (0.9) at more
        than this fraction of its live samples. Stricter than :attr:`~seismo3d.seismic.FaultTracingOptions.max_saturated` (0.95), because a small
        block's edges raise its likelihood: real seismic blocks of 18-64 traces measured 0.50-0.90, white noise 1.00.
    worth : float
        A cube is worth judging from a sample (:meth:`worth_sampling`) when it holds at least this many times the
        samples of the sample: a smaller cube is traced in about the time its sample would save.

    Raises
    ------
    InputError
        A value out of range.
    """

    n_blocks: int = 3
    traces: int = 48
    samples: int = 256
    saturated: float = 0.99
    worth: float = 16.0

    def worth_sampling(self, shape) -> bool:
        """Whether a cube of ``shape`` is large enough to be judged from a sample first (see ``worth``).

        Parameters
        ----------
        shape : tuple of int

        Returns
        -------
        bool
        """
        sampled = self.n_blocks * self.traces ** 2 * self.samples
        return len(shape) == 3 and float(np.prod(shape, dtype=np.float64)) >= self.worth * sampled

    def __post_init__(self):
        check_int(self.n_blocks, "n_blocks", minimum=1, maximum=len(_SPOTS))
        check_int(self.traces, "traces", minimum=8)
        check_int(self.samples, "samples", minimum=32)
        if not 0.0 < float(self.saturated) <= 1.0:
            raise InputError(f"saturated must be a fraction in (0, 1]; got {self.saturated!r}")
        check_positive(self.worth, "worth")


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
        Fraction of the live samples whose fault likelihood exceeds ``saturation_level``.
    candidate_density : float
        Seed candidates of the voting (fault-likelihood ridges above ``VotingOptions.seed_threshold``) per sample.
    """

    n_blocks: int
    n_samples: int
    saturated_fraction: float
    candidate_density: float

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


def _block_origins(shape, options: SampleOptions) -> list:
    """Slices of the sampled blocks: the cube's centre, then points halfway to its corners."""
    n0, n1, nt = shape
    b0, b1, bt = min(options.traces, n0), min(options.traces, n1), min(options.samples, nt)
    t0 = (nt - bt) // 2
    blocks = []
    for fi, fj in _SPOTS[:options.n_blocks]:
        i0 = int(round(fi * (n0 - b0)))
        j0 = int(round(fj * (n1 - b1)))
        blocks.append((slice(i0, i0 + b0), slice(j0, j0 + b1), slice(t0, t0 + bt)))
    return blocks


def _read(cube, region) -> np.ndarray:
    """A copy of one block (the cube itself is never modified)."""
    block = cube[region]
    if hasattr(block, "compute"):  # a dask array: only this block's chunks are read
        block = block.compute()
    return np.array(block, dtype=np.float32, copy=True)


def judge_sample(cube, *, options: FaultTracingOptions | None = None,
                 sample: SampleOptions | None = None) -> CubeSample:
    """Judge a 3D cube from a few blocks before tracing its faults: refuse data that is not seismic amplitudes or has
    no lateral coherence, and measure the density of the voting's seed candidates.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) array_like or dask.array.Array
        Amplitudes; only the sampled blocks are read.
    options : FaultTracingOptions, optional
        The run's options (the amplitude check, the scan, the voting's seed threshold).
    sample : SampleOptions, optional

    Returns
    -------
    CubeSample

    Raises
    ------
    UnsupportedDataError
        Too few traces or samples, traces that do not oscillate like seismic amplitudes, or a sample whose fault
        likelihood is saturated (no lateral coherence); the message says what the sample showed.
    InputError
        ``cube`` is not 3D.
    """
    opt = options or FaultTracingOptions()
    sample = sample or SampleOptions()
    shape = tuple(int(n) for n in getattr(cube, "shape", ()))
    if len(shape) != 3:
        raise InputError(f"judge_sample needs a 3D cube (n_inlines, n_xlines, n_samples); got shape {shape}")
    check_size(shape, opt)
    high = live = candidates = read = 0
    amplitudes, dead_masks = [], []
    for region in _block_origins(shape, sample):
        with warnings.catch_warnings():  # dead or clipped samples are reported by the run itself
            warnings.simplefilter("ignore", Seismo3dWarning)
            cleaned = clean_traces(_read(cube, region), options=opt.dead)
        amplitudes.append(cleaned.data)
        dead_masks.append(cleaned.dead)
        read += cleaned.data.size
    check_amplitudes(np.concatenate(amplitudes), np.concatenate(dead_masks), opt)
    for data, dead in zip(amplitudes, dead_masks):
        block_high, block_live, block_candidates = _block_measures(data, dead, opt)
        high, live, candidates = high + block_high, live + block_live, candidates + block_candidates
    fraction = high / live if live else 0.0
    if fraction > sample.saturated:
        raise UnsupportedDataError(f"in a sample of {len(amplitudes)} blocks of {amplitudes[0].shape[0]} x "
                                   f"{amplitudes[0].shape[1]} traces, " + no_coherence_message(fraction, opt.saturation_level))
    return CubeSample(len(amplitudes), read, float(fraction), candidates / read if read else 0.0)


def _block_measures(data: np.ndarray, dead: np.ndarray, opt: FaultTracingOptions) -> tuple[int, int, int]:
    """(saturated live samples, live samples, seed candidates) of one block, as the full run counts them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        fl = fault_likelihood(data, options=opt.scan, progress=False)
    near = near_dead_samples(dead, options=opt.dead) if dead.any() else None
    high, live = live_likelihood(fl.likelihood, near, level=opt.saturation_level)
    seeds = ridges(fl.likelihood, fl.strike_deg, fl.dip_deg, opt.voting.seed_threshold)
    return high, live, int(np.count_nonzero(seeds > float(opt.voting.seed_threshold)))


def finite_cube(x, dead: DeadSampleOptions | None = None):
    """The cube with NaN / inf read as 0 (warned, as in memory); constant data refused, clipped amplitudes and dead
    samples warned about (:mod:`~seismo3d.seismic.faults.surfaces.dead_samples`), from three passes over the blocks (the
    dead samples need the fill values of the whole cube).

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) float32 dask.array.Array
        Chunks of whole traces.
    dead : DeadSampleOptions, optional
        What counts as a dead sample (default
        :class:`~seismo3d.seismic.faults.surfaces.dead_samples.DeadSampleOptions`).

    Returns
    -------
    dask.array.Array
        ``x``, or ``x`` with its NaN / inf samples read as 0.

    Raises
    ------
    InputError
        Every sample equal (NaN read as 0).

    Warns
    -----
    Seismo3dWarning
        NaN / inf, clipped or dead samples (:func:`~seismo3d.seismic.faults.surfaces.dead_samples.clean_traces`'
        warnings).
    """
    import dask
    import dask.array as da

    finite = da.isfinite(x)
    cleaned = da.where(finite, x, np.float32(0.0))
    n_bad, lo, hi = dask.compute(da.sum(~finite), da.min(cleaned), da.max(cleaned))
    n = int(np.prod(x.shape, dtype=np.int64))
    warn_non_finite(int(n_bad), n)
    check_varies(float(lo), float(hi))
    x = cleaned if n_bad else x
    lo, hi = np.float32(lo), np.float32(hi)
    parts = [dask.delayed(_clipped_and_fills)(b, lo, hi, dead) for b in x.to_delayed().ravel()]
    parts = dask.compute(*parts)
    warn_clipped(sum(p[0] for p in parts), n - int(np.prod(x.shape[:-1], dtype=np.int64)), options=dead)
    fill = np.unique(np.concatenate([p[1] for p in parts]))
    counts = dask.compute(*[dask.delayed(_dead_counts)(b, fill, lo, hi, dead) for b in x.to_delayed().ravel()])
    warn_dead(sum(d[0] for d in counts), n, sum(d[1] for d in counts), options=dead)
    return x


def _clipped_and_fills(block, lo, hi, dead) -> tuple:
    """(clipped samples, fill values) of a block of whole traces."""
    block = np.asarray(block, np.float32)
    return clipped_count(block, lo, hi), fill_values(block, lo, hi, options=dead)


def _dead_counts(block, fill, lo, hi, options) -> tuple[int, int]:
    """(dead samples, dead traces) of a block of whole traces."""
    dead = dead_samples(np.asarray(block, np.float32), fill, lo, hi, options=options)
    return int(np.count_nonzero(dead)), int(np.count_nonzero(dead.all(axis=-1)))
