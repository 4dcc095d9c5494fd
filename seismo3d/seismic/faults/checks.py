"""The refusals of fault tracing: data too small, not seismic amplitudes, or without lateral coherence.

One function a check, called by every way a fault run goes: in memory (:func:`~seismo3d.seismic.faults.trace_faults`),
block by block (:mod:`~seismo3d.seismic.faults.surfaces.blocks`) and on a sample of blocks
(:mod:`~seismo3d.seismic.faults.preflight`). The warnings about NaN, dead and clipped samples are those of
:mod:`~seismo3d.seismic.faults.surfaces.dead_samples`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...errors import UnsupportedDataError
if TYPE_CHECKING:
    from .options import FaultTracingOptions

__all__ = ["check_amplitudes", "check_saturation", "check_size", "no_coherence_message"]


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


def no_coherence_message(fraction: float, level: float) -> str:
    """The refusal of data without lateral coherence, its likelihood above ``level`` (the options'
    ``saturation_level``) at ``fraction`` of the samples."""
    return (f"the fault likelihood is above {level:g} at {fraction:.0%} of the samples: the data has no lateral "
            "coherence to trace faults in (noise, chaotic reflections, or traces out of order); check the "
            "inline/crossline geometry or the file")
