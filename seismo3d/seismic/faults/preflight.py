"""Judging a 3D cube from a few blocks before tracing its faults (:func:`judge_sample`): the refusals of
:func:`~seismo3d.seismic.faults.trace_faults` made in seconds, before the whole likelihood, on the blocks the
executor's preflight reads (:func:`~seismo3d.seismic.blocks.preflight.sample_blocks`): data that is not seismic
amplitudes, traces no more alike than noise (:func:`lateral_coherence`), a saturated likelihood; and the density of
the voting's seed candidates, from which :func:`~seismo3d.seismic.faults.pipeline.minimum_memory_limit` estimates the
memory of the seeds step of a block-by-block run. The sample is measured as the run measures the cube: the
likelihood the run makes (:func:`~seismo3d.seismic.faults.steps.run_likelihood`) and the run's ridges step on one
block (:func:`~seismo3d.seismic.faults.surfaces.blocks.memory_surface_run`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...errors import InputError, Seismo3dWarning, UnsupportedDataError
from ..amplitudes import check_amplitudes, clean_traces
from ..blocks import preflight
from ..blocks.preflight import SampleOptions
from .steps import NO_COHERENCE, check_size, no_coherence_message, run_likelihood
from .surfaces.blocks import memory_surface_run

if TYPE_CHECKING:
    from .options import FaultTracingOptions

__all__ = ["CubeSample", "judge_sample", "lateral_coherence"]


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
                                   f"): " + NO_COHERENCE)
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
