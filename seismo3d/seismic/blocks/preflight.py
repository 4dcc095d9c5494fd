"""The preflight of a run over a cube: the checks made before the work, in seconds, so that a cube the run would
refuse is refused before its first pass over the whole cube. Data too small for the run's windows
(:func:`check_size`), and a few blocks spread over a large cube read for the run to judge it from
(:class:`SampleOptions`, :func:`sample_blocks`).

What a run judges in the sample is its own: fault tracing refuses from it data that is not seismic amplitudes or has no
lateral coherence and predicts the seeds of its voting (:func:`~seismo3d.seismic.faults.preflight.judge_sample`). The
checks of the amplitudes themselves (NaN / inf, constant, clipped and dead samples, of an array in memory or of a lazy
cube by blocks) are :mod:`~seismo3d.seismic.amplitudes`'.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_int, check_positive
from ...errors import InputError, UnsupportedDataError

__all__ = ["SampleOptions", "check_size", "sample_blocks"]


def check_size(shape: tuple, *, min_traces: tuple, min_samples: int, task: str, spans: str) -> None:
    """Refuse data too small for a run's windows.

    Parameters
    ----------
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)`` or ``(n_traces, n_samples)``.
    min_traces : (int, int)
        Traces needed along the longer and the shorter lateral axis (the first only, for a section).
    min_samples : int
        Samples needed per trace.
    task : str
        What needs them, for the message (``"fault tracing"``).
    spans : str
        What spans them, for the message (``"the fault-plane windows and voting boxes"``).

    Raises
    ------
    UnsupportedDataError
        Fewer traces or samples than ``min_traces`` / ``min_samples``.
    """
    lateral = sorted(shape[:-1], reverse=True)
    need = list(min_traces[: len(lateral)])
    if any(n < m for n, m in zip(lateral, need)) or shape[-1] < min_samples:
        size = " x ".join(str(n) for n in shape[:-1])
        want = (f"{need[0]} traces along one lateral axis and {need[1]} along the other" if len(need) == 2 else
                f"{need[0]} traces")
        raise UnsupportedDataError(
            f"the data has {size} trace{'s' if np.prod(shape[:-1]) != 1 else ''} of {shape[-1]} samples: {task} "
            f"needs at least {want}, and "
            f"{min_samples} samples per trace ({spans} span that much); "
            "trace a larger cube or section")


# Where the sampled blocks sit, as fractions of the lateral extent left around a block: the centre, then halfway to
# each corner.
_SPOTS = ((0.5, 0.5), (0.25, 0.25), (0.75, 0.75), (0.25, 0.75), (0.75, 0.25))


@dataclass(frozen=True)
class SampleOptions:
    """How a cube is sampled before a run (:func:`sample_blocks`), and how strictly the sample refuses it.

    Attributes
    ----------
    n_blocks : int
        Blocks read, 1 to 5, spread over the cube: its centre, then points halfway to its corners.
    traces : int
        Traces a side of a block (fewer on a smaller cube).
    samples : int
        Samples of a block, centred on the middle of the traces (all of them on shorter traces).
    saturated : float
        Fault tracing refuses the data from the sample when the fault likelihood exceeds the run's
        ``saturation_level`` (0.9) at more than this fraction of its live samples. Stricter than
        :attr:`~seismo3d.seismic.FaultTracingOptions.max_saturated` (0.95), because a small block's edges raise its
        likelihood: real seismic blocks of 18-64 traces measured 0.50-0.90, white noise 1.00.
    min_coherence : float
        Fault tracing refuses the data from the sample when neighbouring traces correlate below this (the median of
        their best correlation within ``max_lag`` samples,
        :func:`~seismo3d.seismic.faults.preflight.lateral_coherence`):
        white noise measures about ``1.3 / sqrt(samples)``, 0.08 on 256 samples, 0.23 on the fewest (32).
    max_lag : int
        Largest shift between neighbouring traces tried by that correlation, samples.
    worth : float
        A cube is worth judging from a sample (:meth:`worth_sampling`) when it holds at least this many times the
        samples of the sample: a smaller cube is run in about the time its sample would save.

    Raises
    ------
    InputError
        A value out of range.
    """

    n_blocks: int = 3
    traces: int = 48
    samples: int = 256
    saturated: float = 0.99
    min_coherence: float = 0.3
    max_lag: int = 4
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
        if not -1.0 <= float(self.min_coherence) < 1.0:
            raise InputError(f"min_coherence must be a correlation in [-1, 1); got {self.min_coherence!r}")
        check_int(self.max_lag, "max_lag", minimum=0)
        check_positive(self.worth, "worth")


def sample_blocks(cube, options: SampleOptions | None = None) -> list[np.ndarray]:
    """Copies of a few blocks spread over a 3D cube: its centre, then points halfway to its corners.

    Parameters
    ----------
    cube : (n_inlines, n_xlines, n_samples) array_like or dask.array.Array
        Amplitudes; only the sampled blocks are read (the cube itself is never modified).
    options : SampleOptions, optional

    Returns
    -------
    list of (b0, b1, bt) float32 ndarray
        ``options.n_blocks`` blocks of ``options.traces`` traces a side (at most the cube's) and ``options.samples``
        samples (at most the cube's), centred on the middle of the traces.
    """
    options = options or SampleOptions()
    return [_read(cube, region) for region in _block_origins(tuple(cube.shape), options)]


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
