"""The fault interpretation of an array: fault likelihood -> thinning -> linking -> throw, after Hale (2013, 2014).

:func:`trace_faults` runs the steps with the defaults every seismo3d command uses and returns a
:class:`FaultInterpretation`; :func:`clean_traces` finds the dead samples (mutes, dead traces, gaps) whose edges are
not faults, and reports clipped amplitudes. Reading files and writing results is the ``faults`` command's job
(:mod:`seismo3d.jobs.faults`).

Index-space conventions (axes, strike, dip) are those of :mod:`seismo3d.seismic.fault_likelihood`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .._progress import progress_steps
from .._validation import check_choice, check_positive
from ..errors import InputError, Seismo3dWarning
from .fault_likelihood import fault_likelihood
from .fault_surfaces import link_faults, thin_faults
from .fault_throw import fault_throws

__all__ = ["FaultInterpretation", "CleanTraces", "clean_traces", "trace_faults"]

_UNITS = {"samples", "ms", "m", "ft"}
# Reach (traces, samples) of a dead zone's edge in fault_likelihood: the 3 x 3-trace semblance and the reflector slopes
# of the structure tensor (smoothed over about 2 traces and 6 samples) see the edge this far; likelihood this close to
# a dead sample is an artefact of the edge, not a fault.
_DEAD_REACH = (3, 8)
# Fraction of samples at the data's extremes above which the data are reported as clipped (unclipped data such as F3
# and the synthetic cubes have a handful of such samples; 8-bit exports like the Penobscot sections, most of them).
_CLIPPED_WARN = 0.05
# Equal values in a row along a trace that make a run of dead samples (mute, dead trace, gap), at a fill value.
_DEAD_RUN = 5
# A value that fills a run this long somewhere in the data (or a whole trace) is a fill value (a mute's or a padding's
# value) besides 0. Shorter runs at other values are the quantisation of slowly varying amplitudes in integer exports:
# in the 8-bit Penobscot sections a run of five 107s sits on a fault at inlines 1-2, and reading it as dead blanked
# the fault's likelihood over inlines 0-5.
_FILL_RUN = 16


@dataclass(frozen=True)
class FaultInterpretation:
    """Result of :func:`trace_faults`.

    Attributes
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        Fault likelihood in [0, 1] (0 on and next to dead samples).
    strike_deg, dip_deg : same shape, float32 ndarray
        Strike and dip of the most likely fault plane at each sample, degrees, index space.
    thin : same shape, float32 ndarray
        The likelihood on the 1-sample-wide thinned fault traces, 0 elsewhere (``thin > 0`` is the fault mask).
    faults : list of Fault
        Linked faults (surfaces in 3D, curves in 2D), ids 1, 2, ... by decreasing size.
    throws : list of FaultThrow
        One per fault, in the order of ``faults``; ``throws[i].throw`` is the vertical throw at each point of
        ``faults[i]``, in samples.
    sample_interval : float
        Sample interval in ``sample_unit`` (1 for 'samples').
    sample_unit : {'samples', 'ms', 'm', 'ft'}
        Unit of the sample axis.
    """

    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    thin: np.ndarray
    faults: list
    throws: list
    sample_interval: float
    sample_unit: str




@dataclass(frozen=True, eq=False)
class CleanTraces:
    """Result of :func:`clean_traces`.

    Attributes
    ----------
    data : float32 ndarray
        The data with NaN / inf read as 0.
    dead : bool ndarray, same shape
        True on dead samples.
    """

    data: np.ndarray
    dead: np.ndarray


def clean_traces(data) -> CleanTraces:
    """Replace NaN / inf by 0 and find the dead samples, with a warning for each, and for clipped amplitudes.

    Dead samples are those in runs of at least ``_DEAD_RUN`` equal values along a trace at a *fill value*: dead
    traces, mutes (the zeroed top of a survey), zero padding and NaN gaps. The fill values are 0 and every value that
    fills a whole trace or a run of at least ``_FILL_RUN`` samples somewhere in the data (a mute or padding value
    such as the grey of an image export). Short runs at other values are quantisation (integer exports), and runs at
    the data's largest or smallest value are clipped amplitudes (8-bit exports of sections): neither is dead, unless
    it fills the whole trace.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, any real dtype.

    Returns
    -------
    CleanTraces
        ``data`` (float32) and the ``dead`` mask.

    Raises
    ------
    InputError
        Not a numeric 2D / 3D array with at least 3 samples per axis, or every sample equal.

    Warns
    -----
    Seismo3dWarning
        NaN / inf samples, dead samples, or clipped amplitudes (more than 5 % of the samples at the data's smallest or
        largest value).
    """
    from scipy.ndimage import binary_opening

    arr = np.asarray(data)
    if arr.ndim not in (2, 3):
        raise InputError(f"data must be a 2D section (n_traces, n_samples) or a 3D cube (n_inlines, n_xlines, "
                         f"n_samples); got shape {arr.shape}")
    if not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise InputError(f"data must be numeric; got dtype {arr.dtype}")
    if min(arr.shape) < 3:
        raise InputError(f"data has shape {arr.shape}; every axis needs at least 3 samples")
    arr = np.asarray(arr, dtype=np.float32)
    finite = np.isfinite(arr)
    if not finite.all():
        n_bad = int(arr.size - np.count_nonzero(finite))
        warnings.warn(f"data has {n_bad} NaN or inf samples ({n_bad / arr.size:.1%}); they are read as 0, and "
                      "runs of them are skipped like dead traces", Seismo3dWarning, stacklevel=3)
        arr = np.where(finite, arr, np.float32(0.0))
    del finite
    n_s = arr.shape[-1]
    if arr.max() == arr.min():
        raise InputError("every sample has the same value (or is NaN): there are no reflectors to trace faults in; "
                         "check that the file is the right one and that its data format is read correctly")
    # equal neighbours along the trace, in runs of >= _DEAD_RUN - 1 differences
    flat = np.diff(arr, axis=-1) == 0
    lo, hi = arr.min(), arr.max()
    clipped = (arr[..., 1:] == lo) | (arr[..., 1:] == hi)
    clipped &= ~flat.all(axis=-1, keepdims=True)
    frac_clipped = float(np.count_nonzero(clipped)) / clipped.size
    if frac_clipped > _CLIPPED_WARN:
        warnings.warn(f"{frac_clipped:.0%} of the samples sit at the data's smallest or largest value: clipped "
                      "amplitudes (an 8-bit export?). Fault likelihood and throws are measured on the clipped "
                      "waveforms and are less reliable; trace the unclipped data if you have it",
                      Seismo3dWarning, stacklevel=3)
    flat &= ~clipped
    del clipped

    def runs(equal, length):  # the differences inside runs of at least `length` equal values
        structure = np.ones((1,) * (arr.ndim - 1) + (min(length - 1, n_s - 1),), dtype=bool)
        return binary_opening(equal, structure=structure)

    whole = np.broadcast_to(flat.all(axis=-1, keepdims=True), flat.shape)
    fill = np.union1d([0.0], arr[..., 1:][runs(flat, _FILL_RUN) | whole])
    flat = runs(flat, _DEAD_RUN) & np.isin(arr[..., 1:], fill)
    dead = np.zeros(arr.shape, dtype=bool)
    dead[..., 1:] |= flat
    dead[..., :-1] |= flat
    del flat
    if dead.any():
        n_dead = int(np.count_nonzero(dead))
        n_tr = int(np.count_nonzero(dead.all(axis=-1)))
        warnings.warn(f"{n_dead / dead.size:.1%} of the samples are constant over {_DEAD_RUN} or more samples "
                      f"(mutes, gaps, {n_tr} dead traces); fault likelihood within {_DEAD_REACH[0]} traces and "
                      f"{_DEAD_REACH[1]} samples of them is set to 0", Seismo3dWarning, stacklevel=3)
    return CleanTraces(arr, dead)


def _near(dead: np.ndarray) -> np.ndarray:
    """Dead samples grown by ``_DEAD_REACH`` (a box: separable maximum filters)."""
    from scipy.ndimage import maximum_filter1d

    near = dead.view(np.uint8)
    for axis in range(dead.ndim):
        reach = _DEAD_REACH[1] if axis == dead.ndim - 1 else _DEAD_REACH[0]
        if dead.shape[axis] > 1:
            near = maximum_filter1d(near, 2 * reach + 1, axis=axis, mode="constant")
    return near.view(bool)




def trace_faults(data, *, sample_interval=None, sample_unit="samples", progress=True) -> FaultInterpretation:
    """Trace the faults of a seismic cube or section: likelihood, thinning, linking, throw.

    The steps, with their defaults chosen from the data (no per-file tuning):

    1. :func:`~seismo3d.seismic.fault_likelihood` (scan of fault strikes and dips, Hale 2013);
    2. :func:`~seismo3d.seismic.thin_faults` (non-maximum suppression across the fault, Otsu + hysteresis);
    3. :func:`~seismo3d.seismic.link_faults` (fault surfaces in 3D, curves in 2D; tiny ones dropped);
    4. :func:`~seismo3d.seismic.fault_throws` (vertical throw by registering the reflectors on both sides).

    NaN / inf samples are read as 0 (with a :class:`~seismo3d.errors.Seismo3dWarning`). Dead samples (runs of 5 or
    more equal values along a trace: dead traces, mutes, gaps, NaN runs) are skipped, with a warning: the likelihood
    within 3 traces and 8 samples of them is set to 0, since the edge of a dead zone is not a fault.

    Memory and time: the whole array is processed in memory. The whole ``seismo3d faults`` command on a 256^3
    float32 cube (64 MiB) peaked at 1.3 GB resident and took about 55 s on 2 cores (128^3: 0.4 GB, about 20 s);
    both grow about linearly with the number of samples. Crop larger cubes, or trace them in overlapping pieces.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample (time or depth, downward).
    sample_interval : float, optional
        Sample interval in ``sample_unit``; required unless ``sample_unit`` is 'samples'.
    sample_unit : {'samples', 'ms', 'm', 'ft'}, optional
        Unit of the sample axis (for converting throws, see :attr:`FaultInterpretation.sample_interval`).
    progress : bool, optional
        Report progress over the steps (:mod:`seismo3d._progress`: a bar on a terminal, one log line per step
        otherwise; the fault likelihood and the throw, the long steps, report their progress too).

    Returns
    -------
    FaultInterpretation
        Likelihood, strike, dip, thinned faults, linked faults and their throws.

    Raises
    ------
    InputError
        ``data`` is not a numeric 2D / 3D array with at least 3 samples per axis, all samples are equal, or the
        sample interval / unit is invalid.

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

    cleaned = clean_traces(data)
    arr, dead = cleaned.data, cleaned.dead
    del cleaned
    with progress_steps(4, "faults", enabled=progress) as bar:
        bar.start("fault likelihood")
        fl = fault_likelihood(arr, progress=progress)
        likelihood, strike, dip = fl.likelihood, fl.strike_deg, fl.dip_deg
        del fl
        if dead.any():  # the edge of a dead zone is not a fault
            likelihood[_near(dead)] = 0.0
        del dead
        bar.advance()
        bar.start("thinning")
        thin = thin_faults(likelihood, strike, dip)
        bar.advance()
        bar.start("linking")
        faults = link_faults(thin, strike, dip)
        bar.advance()
        bar.start("throw")
        throws = fault_throws(arr, faults, progress=progress) if faults else []
        bar.advance()
    return FaultInterpretation(likelihood=likelihood, strike_deg=strike, dip_deg=dip, thin=thin, faults=faults,
                               throws=list(throws), sample_interval=float(sample_interval), sample_unit=sample_unit)

