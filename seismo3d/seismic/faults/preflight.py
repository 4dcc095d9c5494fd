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
(:func:`~seismo3d.seismic.faults.likelihood.scan_blocks.chunked_fault_likelihood` and
:func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`) can plan their smallest blocks, and, with
a sample, hold the seed candidates. The thinned fault cells linked into skins come from the voting and cannot be judged
from a sample; a limit too small for them is still reported when they are counted.

:func:`check_block_run` makes these checks before any block of a run by blocks, then the checks of the data the run
in memory makes (:func:`finite_cube`: NaN / inf samples read as 0, constant data refused, clipped amplitudes and dead
samples warned about), from passes over the blocks.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..._progress import LOGGER
from ..._validation import check_int, check_positive
from ...errors import InputError, Seismo3dWarning, UnsupportedDataError
from ..blocks.executor import release_memory
from ..blocks.memory import resident_memory, size_text, worker_baseline
from ..blocks.options import ChunkOptions
from ..blocks.plan import limit_for_blocks
from .checks import check_amplitudes, check_size, no_coherence_message
from .likelihood.learned_blocks import learned_block_bytes
from .likelihood.scan import fault_likelihood
from .likelihood.scan_blocks import smallest_block_bytes as likelihood_block_bytes
from .options import FaultTracingOptions
from .surfaces.block_steps import CANDIDATE_BYTES, smallest_block_bytes as surfaces_block_bytes
from .surfaces.dead_samples import (
    DeadSampleOptions, check_varies, clean_traces, clipped_count, dead_samples, fill_values, near_dead_samples,
    warn_clipped, warn_dead, warn_non_finite,
)
from .surfaces.ridges import live_likelihood, ridges

__all__ = ["CubeSample", "SampleOptions", "STAGE_GROWTH", "check_block_run", "finite_cube", "judge_sample",
           "minimum_memory_limit"]

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


def minimum_memory_limit(shape, *, baseline: int, options: FaultTracingOptions | None = None,
                         tile: int | None = None, workers: int = 1, sample: CubeSample | None = None, growth: int = STAGE_GROWTH) -> int:
    """The smallest ``memory_limit`` (bytes) with which a block-by-block fault run of a cube can go through: both
    stages plan their smallest blocks (the second from a process grown by ``growth``), and (with ``sample``) the
    seed candidates fit.

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    baseline : int
        Bytes the process holds before its blocks
        (:func:`~seismo3d.seismic.faults.likelihood.scan_blocks.worker_baseline`).
    options : FaultTracingOptions, optional
    tile : int, optional
        Traces a side of the smallest blocks (default :attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile`).
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
    tile = int(tile or ChunkOptions().tile)
    shape = tuple(int(n) for n in shape)
    baseline, growth = int(baseline), int(growth)
    first = limit_for_blocks(likelihood_block_bytes(shape, opt.scan, tile) if opt.likelihood == "scan"
                             else learned_block_bytes(shape, opt.learned, tile), baseline, workers)
    need = max(first, limit_for_blocks(surfaces_block_bytes(shape, opt, tile), baseline + growth, workers))
    if sample is not None:
        need = max(need, baseline + growth + sample.candidates(shape) * CANDIDATE_BYTES)
    return need


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


def check_block_run(x, name: str, limit: int, scheduler, options: FaultTracingOptions):
    """Before any block of a run by blocks: the memory its smallest blocks need (at once); the data judged from a
    sample of blocks (not seismic amplitudes, no lateral coherence: the refusals of the run in memory, in seconds);
    the memory the seed candidates the sample predicts need; then the data's NaN, constant, clipped and dead samples
    (:func:`finite_cube`, passes over the whole cube).

    Parameters
    ----------
    x : (n_inlines, n_xlines, n_samples) dask.array.Array
    name : str
        The input, for messages.
    limit : int
        Memory limit, bytes.
    scheduler : str or None
    options : FaultTracingOptions

    Returns
    -------
    dask.array.Array
        ``x`` with NaN / inf read as 0 (:func:`finite_cube`).

    Raises
    ------
    UnsupportedDataError
        The sample refuses the data.
    InputError
        ``limit`` below what the run needs (the message names the smallest limit that works), or constant data.
    """
    shape = tuple(int(n) for n in x.shape)
    chunks = x.chunks

    def baseline() -> int:  # the process as it is now, and the input chunks a block reads
        return worker_baseline(ChunkOptions(memory_limit=limit, scheduler=scheduler),
                               4 * max(chunks[0]) * max(chunks[1]) * shape[2])

    _check_limit(name, shape, limit, minimum_memory_limit(shape, baseline=baseline(), options=options),
                 " for its smallest blocks alone")
    LOGGER.info("%s: judging the data from a sample of blocks", name)
    sample = judge_sample(x, options=options)  # before the passes over the whole cube: a refusal in seconds
    release_memory()  # the sample's arrays, before the process is measured again
    need = minimum_memory_limit(shape, baseline=baseline(), options=options, sample=sample)
    _check_limit(name, shape, limit, need, f" (with the ~{sample.candidates(shape)} seed candidates a sample "
                                           "of its blocks predicts)")
    return finite_cube(x, options.dead)


def _check_limit(name: str, shape: tuple, limit: int, need: int, why: str) -> None:
    """InputError naming the smallest memory limit that works when ``limit`` is below ``need``."""
    if need <= limit:
        return
    held = resident_memory()
    raise InputError(f"{name}: a block-by-block run of its {shape[0]} x {shape[1]} x {shape[2]} samples needs a "
                     f"memory limit of at least {size_text(need)}{why}, more than the {size_text(limit)} given "
                     f"(this process alone holds {size_text(held)}); pass memory_limit='{size_text(need)}' or more")
