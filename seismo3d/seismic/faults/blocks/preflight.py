"""What a fault run on a large cube can be told before its full computation: the data judged from a sample of blocks,
and the memory a block-by-block run needs.

:func:`judge_sample` reads a few blocks spread over the cube and applies to them the refusals of
:func:`~seismo3d.seismic.faults.trace_faults` that otherwise come only after the whole fault likelihood: data that
does not oscillate like seismic amplitudes (a velocity model) and data without lateral coherence (noise, traces out of
order). A refusal from the sample is stricter than the full run's own (``SampleOptions.saturated``), so data the full
run would trace is not refused here; the full run's checks still apply to the rest. The sample also gives the
density of the voting's seed candidates, from which :func:`minimum_memory_limit` estimates the memory of the seeds
step of a block-by-block run.

:func:`minimum_memory_limit` is the smallest ``memory_limit`` with which both block-by-block stages
(:func:`~seismo3d.seismic.faults.blocks.scan_blocks.chunked_fault_likelihood` and
:func:`~seismo3d.seismic.faults.blocks.surface_blocks.chunked_fault_surfaces`) can plan their smallest blocks, and, with
a sample, hold the seed candidates. The thinned fault cells linked into skins come from the voting and cannot be judged
from a sample; a limit too small for them is still reported when they are counted.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ...._validation import check_int, check_positive
from ....errors import InputError, Seismo3dWarning, UnsupportedDataError
from ...blocks.executor import limit_for_blocks
from ..surfaces.dead_samples import clean_traces, near_dead_samples
from ..likelihood.scan import fault_likelihood
from .scan_blocks import smallest_block_bytes as likelihood_block_bytes
from ..checks import check_amplitudes, check_size, no_coherence_message
from ..options import FaultTracingOptions
from .learned_blocks import learned_block_bytes
from ..surfaces.ridges import live_likelihood, ridges
from .surface_plan import CANDIDATE_BYTES, smallest_block_bytes as surfaces_block_bytes

__all__ = ["CubeSample", "SampleOptions", "STAGE_GROWTH", "judge_sample", "minimum_memory_limit"]

# What the process keeps of the fault likelihood stage when the surfaces stage plans its blocks from the resident
# memory: measured 33 MiB on a 96 x 96 x 200 cube and 46 MiB on a 160 x 160 x 256 one (glibc, 2 threads), rounded up.
STAGE_GROWTH = 64 << 20


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
        The sample refuses the data when the fault likelihood exceeds 0.9 at more than this fraction of its live
        samples. Stricter than :attr:`~seismo3d.seismic.FaultTracingOptions.max_saturated` (0.95), because a small
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
        Fraction of the live samples whose fault likelihood exceeds 0.9.
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
                                   f"{amplitudes[0].shape[1]} traces, " + no_coherence_message(fraction))
    return CubeSample(len(amplitudes), read, float(fraction), candidates / read if read else 0.0)


def _block_measures(data: np.ndarray, dead: np.ndarray, opt: FaultTracingOptions) -> tuple[int, int, int]:
    """(saturated live samples, live samples, seed candidates) of one block, as the full run counts them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        fl = fault_likelihood(data, options=opt.scan, progress=False)
    near = near_dead_samples(dead, options=opt.dead) if dead.any() else None
    high, live = live_likelihood(fl.likelihood, near)
    seeds = ridges(fl.likelihood, fl.strike_deg, fl.dip_deg, opt.voting.seed_threshold)
    return high, live, int(np.count_nonzero(seeds > float(opt.voting.seed_threshold)))


def minimum_memory_limit(shape, *, baseline: int, options: FaultTracingOptions | None = None, tile: int = 32,
                         workers: int = 1, sample: CubeSample | None = None, growth: int = STAGE_GROWTH) -> int:
    """The smallest ``memory_limit`` (bytes) with which a block-by-block fault run of a cube can go through: both
    stages plan their smallest blocks (the second from a process grown by ``growth``), and (with ``sample``) the
    seed candidates fit.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    baseline : int
        Bytes the process holds before its blocks
        (:func:`~seismo3d.seismic.faults.blocks.scan_blocks.worker_baseline`).
    options : FaultTracingOptions, optional
    tile : int
        Traces a side of the smallest blocks.
    workers : int
        Blocks computed at once.
    sample : CubeSample, optional
        From :func:`judge_sample`: adds the seed candidates it predicts.
    growth : int
        Bytes the process grows by during the likelihood stage (:data:`STAGE_GROWTH`).

    Returns
    -------
    int
        Bytes.
    """
    opt = options or FaultTracingOptions()
    shape = tuple(int(n) for n in shape)
    baseline, growth = int(baseline), int(growth)
    first = limit_for_blocks(likelihood_block_bytes(shape, opt.scan, tile) if opt.likelihood == "scan"
                             else learned_block_bytes(shape, opt.learned, tile), baseline, workers)
    need = max(first, limit_for_blocks(surfaces_block_bytes(shape, opt, tile), baseline + growth, workers))
    if sample is not None:
        need = max(need, baseline + growth + sample.candidates(shape) * CANDIDATE_BYTES)
    return need
