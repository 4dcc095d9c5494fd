"""Fault likelihood: a scan over fault strikes and dips (after Hale 2013), in 3D cubes and 2D sections.

The structure-oriented semblance is summed within each candidate fault plane; each sample keeps the largest likelihood
``1 - s^8`` of the scanned planes through it, and that plane's strike and dip.
:mod:`seismo3d.seismic.faults.surfaces.ridges` thins and links the likelihood into faults.

Conventions (index space: one trace spacing and one sample both count as 1, the sample axis points down; the same
as :mod:`seismo3d.data.synthetic`):

- ``strike_deg`` in [0, 360): azimuth of the horizontal strike vector ``(cos phi, sin phi)`` in the (inline, xline)
  plane, measured from the inline axis (axis 0) toward the crossline axis (axis 1).
- ``dip_deg`` in (0, 90]: angle of the fault plane from the horizontal. The plane deepens toward the horizontal
  dip direction ``(-sin phi, cos phi)`` (to the right of the strike).
- The unit fault normal is ``(sin(dip) sin(phi), -sin(dip) cos(phi), cos(dip))`` (inline, xline, sample): it points
  down into the footwall; the hanging wall lies on the side of ``-normal``.
- A 2D section ``(n_traces, n_samples)`` is treated as a cube with one crossline: strike is 270 when the fault
  deepens toward increasing trace index and 90 when it deepens toward decreasing trace index; its normal is
  ``(sin(dip) sin(phi), cos(dip))`` (trace, sample).

Dips are in index space; to convert them to true dips use ``atan(tan(dip) * dz / dx)`` with the sample interval
``dz`` and trace spacing ``dx`` in the same unit (depth, or time times velocity).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

import numba as nb
import numpy as np

from ...._options import resolve_options
from ...._validation import as_seismic, as_sigma_pair, check_int, check_positive
from ....errors import InputError, Seismo3dWarning
from ... import _kernels
from ...amplitudes import check_finite
from ...blocks.apply import BlockOutput
from ...blocks.plan import CUBE, BlockStep, lateral_blocks
from ...blocks.stores import read_sheared
from .scan_kernels import (CODE_BITS, FL_LEVELS, box_half, default_angles, exponential_coefficient, orientation_table,
                           scan_dip, smooth_strike, sum_samples)
from ..result import FaultLikelihood
from .runs import likelihood_in_memory

__all__ = ["FaultScanOptions", "block_steps", "fault_likelihood", "run_scan", "whole_plan"]


@dataclass(frozen=True)
class FaultScanOptions:
    """Options of :func:`fault_likelihood` (the scan over fault orientations); the defaults are the ones every
    seismo3d command uses, on synthetic and real data alike.

    Attributes
    ----------
    strikes : tuple of float, optional
        Strikes to scan, degrees in [0, 360). None: ``ceil(6 * strike_smoothing)`` strikes evenly spaced over
        [0, 360) (every 15 degrees for the default ``strike_smoothing``; a plane misoriented by d radians leaves the
        fault by about ``strike_smoothing * d`` traces at one smoothing width, so a step of ``1 / strike_smoothing``
        radians keeps that under half a trace). Ignored for 2D sections.
    dips : tuple of float, optional
        Dips to scan, degrees in (0, 90] in index space. None: from 90 down to ``min_dip``, evenly spaced in
        cot(dip) (the lateral shift per sample down the fault) by ``1 / dip_smoothing``, so that neighbouring planes
        part by about one trace at one smoothing width from the centre (Hale's angle sampling).
    min_dip : float
        Shallowest dip scanned when ``dips`` is None, degrees in index space. In time sections sampled at 2-4 ms
        with traces 12.5-25 m apart, normal faults dipping 45-75 degrees appear at 65-88 degrees, so 60 keeps them
        with a margin; Hale (2013) scans 65-85.
    strike_smoothing : float
        Width (standard deviation) of the triangle filter along strike, in traces along the fault (unused in 2D).
    dip_smoothing : float
        Width of the two-sided exponential smoothing down the fault's dip, in samples along the fault (Hale's
        ``sigmaTheta``, 20 in his examples).
    power : {1, 2, 4, 8, 16, 32}
        Exponent ``p`` in ``1 - s^p`` (Hale uses 8). It only changes the spread of values, not where the ridges are.
    sigma_gradient : float
        Width of the Gaussian derivative filters of the reflector slopes, samples (see
        :func:`~seismo3d.seismic.structure_tensor_orientation`).
    sigma_tensor : (float, float)
        Smoothing (lateral in traces, vertical in samples) of the structure tensor of the reflector slopes.
    planarity_sigma : (float, float) or None
        Smoothing (lateral, vertical) of the structure tensor whose planarity (linearity in 2D) multiplies the
        semblance numerator: reflectors that end or bend at a fault lower it even where the waveforms across the
        fault still look alike (small throws). Narrow windows keep faults sharp and do not stretch them vertically.
        None: semblance alone.
    balance : (float, float) or None
        Widths (lateral in traces, vertical in samples) of the Gaussian window of the amplitude balancing (the data
        divided by its local RMS amplitude), so that weak reflectors weigh as much as strong ones in the sums along
        the fault planes. None: no balancing.
    decimation : int
        The semblance terms are summed in pairs of samples (1: none) before the scan: faults are long down the dip,
        so the scan loses nothing at half the vertical resolution and runs twice as fast; the result is brought
        back to every sample.
    saturated : float
        A :class:`~seismo3d.errors.Seismo3dWarning` is issued when the likelihood exceeds ``saturation_level`` at
        more than this fraction of the live samples (data without lateral coherence: noise, or traces out of order).
    saturation_level : float
        In (0, 1): a likelihood above it counts as saturated (0.9).

    Raises
    ------
    InputError
        A value out of range (checked when the options are made).
    """

    strikes: tuple | None = None
    dips: tuple | None = None
    min_dip: float = 60.0
    strike_smoothing: float = 4.0
    dip_smoothing: float = 20.0
    power: int = 8
    sigma_gradient: float = 1.0
    sigma_tensor: tuple = (2.0, 6.0)
    planarity_sigma: tuple | None = (1.0, 2.0)
    balance: tuple | None = (4.0, 20.0)
    decimation: int = 2
    saturated: float = 0.95
    saturation_level: float = 0.9

    def __post_init__(self):
        check_positive(self.strike_smoothing, "strike_smoothing")
        check_positive(self.dip_smoothing, "dip_smoothing")
        check_positive(self.sigma_gradient, "sigma_gradient")
        if not 0.0 < float(self.min_dip) < 90.0:
            raise InputError(f"min_dip must be in (0, 90) degrees; got {self.min_dip!r}")
        object.__setattr__(self, "sigma_tensor", as_sigma_pair(self.sigma_tensor, "sigma_tensor"))
        for name in ("planarity_sigma", "balance"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, as_sigma_pair(getattr(self, name), name))
        check_int(self.decimation, "decimation", minimum=1)
        try:
            p = int(self.power) if float(self.power) == int(self.power) else -1
        except (TypeError, ValueError, OverflowError):
            p = -1
        if p < 1 or p > 32 or (p & (p - 1)) != 0:
            raise InputError(f"power must be one of 1, 2, 4, 8, 16, 32; got {self.power!r}")
        if not 0.0 < float(self.saturated) <= 1.0:
            raise InputError(f"saturated must be a fraction in (0, 1]; got {self.saturated!r}")
        if not 0.0 < float(self.saturation_level) < 1.0:
            raise InputError(f"saturation_level must be a likelihood in (0, 1); got {self.saturation_level!r}")
        strikes, dips = self.angles()
        if self.strikes is not None:
            object.__setattr__(self, "strikes", tuple(float(v) for v in strikes))
        if self.dips is not None:
            object.__setattr__(self, "dips", tuple(float(v) for v in dips))

    def angles(self) -> tuple[np.ndarray, np.ndarray]:
        """The (strikes, dips) scanned, degrees: the given ones or the defaults."""
        return default_angles(self.strikes, self.dips, float(self.strike_smoothing), float(self.min_dip),
                               float(self.dip_smoothing))


def fault_likelihood(data, *, options: FaultScanOptions | None = None, progress: bool = False,
                     **overrides) -> FaultLikelihood:
    """Fault likelihood, strike and dip by scanning fault orientations (Hale 2013).

    1. Amplitude balancing: the data divided by its local RMS amplitude (Gaussian window ``balance``), so that weak
       reflectors count as much as strong ones. Data whose peak amplitude is beyond 2^32 or below 2^-32 (e.g.
       unsigned 64-bit samples) is first scaled by a power of two, exactly, so that float32 sums of squares hold.
    2. Reflector slopes ``p`` from the structure tensor (as in
       :func:`~seismo3d.seismic.attributes.structure_tensor_orientation`).
    3. Structure-oriented semblance numerator ``n = (sum_k f_k)^2`` and denominator ``d = J sum_k f_k^2`` over the
       J = 3 x 3 neighbouring traces (3 in 2D), each read along the reflector through the centre sample (Hale 2013;
       Marfurt et al. 1998); the numerator is multiplied by the planarity of a narrow structure tensor
       (``planarity_sigma``), which falls where reflectors end or bend.
    4. For every candidate fault plane (strike ``phi``, dip ``theta``), ``n`` and ``d`` are smoothed *within* the
       plane: a triangle filter of width ``strike_smoothing`` along strike, then a two-sided exponential filter of
       width ``dip_smoothing`` down the dip, both along staircase lines of the sheared cube (exact integer shifts, no
       interpolation, so the likelihood is not blurred across the fault). The plane's semblance is ``s = <n> / <d>``
       and its likelihood ``1 - s^p``.
    5. Each sample keeps the maximum over the scan, and the strike and dip where it occurred.

    The scan runs on pairs of samples (``decimation``) and its result is brought back to every sample. Time is
    linear in the number of samples and in the number of scanned planes (300 by default in 3D: 24 strikes x 13
    dips, vertical planes counted once; 25 in 2D).

    The steps are those of the run by blocks (:func:`block_steps`, run in their order by :func:`run_scan`), here on
    one block, the whole array (:class:`~seismo3d.seismic.blocks.executor.MemoryRun`); a section runs as a cube of
    one crossline, its steps told that it is 2D (3 traces in the semblance, the planes of a section).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample (time or depth, downward). Must be finite.
    options : FaultScanOptions, optional
        The scanned strikes and dips, smoothing, balancing and power (see :class:`FaultScanOptions` for the
        defaults).
    progress : bool, optional
        Report the progress over the steps (:mod:`seismo3d._progress`: a bar on a terminal, log lines otherwise).
    **overrides
        Fields of :class:`FaultScanOptions` by name, replacing those of ``options``.

    Returns
    -------
    FaultLikelihood
        ``likelihood`` in [0, 1], ``strike_deg`` and ``dip_deg``: float32 arrays of the data's shape.

    Raises
    ------
    InputError
        If ``data`` is not a finite 2D or 3D array with at least 3 samples per axis, an angle is out of range, more
        than 2048 planes are asked for, or ``power`` is not one of 1, 2, 4, 8, 16, 32.

    Warns
    -----
    Seismo3dWarning
        If the likelihood exceeds ``saturation_level`` at more than ``saturated`` of the live samples (data without lateral
        coherence).

    References
    ----------
    .. [1] D. Hale, "Methods to compute fault images, extract fault surfaces, and estimate fault throws from 3D
       seismic images", Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1.
    .. [2] D. Hale, ``ipf.FaultScanner`` in https://github.com/dhale/ipf (2014): the reference implementation of the
       scan over fault strikes and dips with rotated and sheared recursive smoothing.
    .. [3] K. J. Marfurt, R. L. Kirlin, S. L. Farmer and M. S. Bahorich, "3-D seismic attributes using a
       semblance-based coherency algorithm", Geophysics 63(4), 1998, doi:10.1190/1.1444415.
    .. [4] X. Wu and S. Fomel, "Automatic fault interpretation with optimal surface voting", Geophysics 83(5),
       O67-O82, 2018, doi:10.1190/geo2018-0115.1 (planarity as a fault attribute).

    Examples
    --------
    >>> from seismo3d.data.synthetic import synthetic_cube
    >>> from seismo3d.seismic import fault_likelihood
    >>> syn = synthetic_cube((64, 64, 64), seed=0)
    >>> fl = fault_likelihood(syn.cube)
    >>> fl.likelihood.shape
    (64, 64, 64)
    """
    arr = as_seismic(data)
    opt = resolve_options(FaultScanOptions, options, overrides, "fault_likelihood")
    two_d = arr.ndim == 2
    f3 = _kernels.as_3d(arr)
    *found, saturated = likelihood_in_memory(f3, opt=opt, plan=whole_plan(f3.shape), steps=run_scan, section=two_d,
                                             progress=progress, two_d=two_d)
    _warn_if_saturated(saturated, opt)
    return FaultLikelihood(*found)


# The scan in steps, each of which runs on a block of a cube (the whole cube in memory): a block's result equals the
# whole cube's over the block when the block carries the halo each step needs.

@dataclass(frozen=True)
class AmplitudeStatistics:
    """Whole-cube amplitude statistics that the likelihood of every sample depends on.

    Attributes
    ----------
    scale : float
        Power of two multiplying the amplitudes: 1 unless the peak amplitude is beyond 2^32 or below 2^-32 (e.g.
        unsigned 64-bit samples), so that float32 sums of squares neither overflow nor underflow. Exact; the
        likelihood does not depend on it (semblance is a ratio of sums of squares).
    energy_floor : float
        ``1e-6`` times the mean squared (scaled) amplitude: added to the local energy before amplitude balancing,
        so that dead traces are not divided by zero.
    """

    scale: float
    energy_floor: float

    @classmethod
    def from_sums(cls, peak: float, sum_squares: float, count: int) -> "AmplitudeStatistics":
        """From the peak absolute amplitude and the sum of squared amplitudes over ``count`` samples (float64 sums
        of the unscaled data; a chunked run adds them up block by block)."""
        scale = 1.0 if peak == 0.0 or 2.0 ** -32 <= peak <= 2.0 ** 32 else float(2.0 ** -np.ceil(np.log2(peak)))
        mean_square = sum_squares / max(int(count), 1) * scale * scale
        return cls(scale, float(1e-6 * mean_square + 1e-30))



def scan_step(options: FaultScanOptions, n_samples: int) -> int:
    """Samples summed into one by the scan (``decimation``, less for short traces)."""
    return int(min(options.decimation, max(1, n_samples // 16)))


def balance_halo(options: FaultScanOptions) -> int:
    """Traces on each side of a block that :func:`balance_amplitudes` needs so that the block's result equals the
    whole cube's (the Gaussian window of the local RMS, truncated at 3 sigma)."""
    return _kernels.gaussian_radius(options.balance[0]) if options.balance is not None else 0


def semblance_halo(options: FaultScanOptions) -> int:
    """Traces on each side of a block that :func:`semblance_terms` needs: the wider of the structure tensor for the
    slopes (plus the neighbouring trace read along them) and the tensor for the planarity."""
    sg = _kernels.gaussian_radius(options.sigma_gradient)
    slopes = sg + _kernels.gaussian_radius(options.sigma_tensor[0]) + 1
    planarity = (sg + _kernels.gaussian_radius(options.planarity_sigma[0])
                 if options.planarity_sigma is not None else 0)
    return max(slopes, planarity)


def strike_halo(options: FaultScanOptions) -> int:
    """Traces on each side of a block that the smoothing along strike needs (two passes of a box, widest strike)."""
    return 2 * box_half(float(options.strike_smoothing))


def balance_amplitudes(f3: np.ndarray, options: FaultScanOptions, stats: AmplitudeStatistics, *,
                       two_d: bool = False) -> np.ndarray:
    """Amplitudes divided by their local RMS (step 1 of :func:`fault_likelihood`), after the exact scaling of
    ``stats``.

    Parameters
    ----------
    f3 : (n0, n1, n_samples) float32 ndarray
        Amplitudes (a 2D section as ``(n_traces, 1, n_samples)``), a whole cube or a block of one with
        :func:`balance_halo` traces of halo on each side that is not the cube's edge.
    options : FaultScanOptions
        ``balance``: the Gaussian window (traces, samples) of the local RMS; None leaves the amplitudes as they are.
    stats : AmplitudeStatistics
        Of the whole cube.
    two_d : bool

    Returns
    -------
    (n0, n1, n_samples) float32 ndarray
    """
    if stats.scale != 1.0:
        f3 = f3 * np.float32(stats.scale)
    if options.balance is None:
        return np.asarray(f3, dtype=np.float32)
    lat, vert = options.balance
    energy = _kernels.gaussian3(f3 * f3, (lat, 0.0 if two_d else lat, vert))
    energy += np.float32(stats.energy_floor)
    np.sqrt(energy, out=energy)
    return np.divide(f3, energy, out=energy, dtype=np.float32)


def semblance_terms(f3: np.ndarray, options: FaultScanOptions, *,
                    two_d: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Structure-oriented semblance numerator and denominator (steps 2-3 of :func:`fault_likelihood`), summed over
    the scan's groups of samples (:func:`scan_step`).

    Parameters
    ----------
    f3 : (n0, n1, n_samples) float32 ndarray
        Balanced amplitudes (:func:`balance_amplitudes`), a whole cube or a block of one with
        :func:`semblance_halo` traces of halo on each side that is not the cube's edge.
    options : FaultScanOptions
    two_d : bool

    Returns
    -------
    numerator, denominator : (n0, n1, ceil(n_samples / step)) float32 ndarray
        ``(sum_k f_k)^2`` times the planarity, and ``J sum_k f_k^2``, over the 3 x 3 traces (3 in 2D) read along the
        reflector slopes, summed over groups of ``step`` samples (the last group padded with its last sample).
    """
    if options.planarity_sigma is not None:  # first, so that its tensor is freed before the slopes' one is made
        planarity = _kernels.tensor_planarity(f3, float(options.sigma_gradient), options.planarity_sigma, two_d)
    p0, p1 = _kernels.reflector_slopes(f3, two_d, float(options.sigma_gradient), options.sigma_tensor)
    sn = np.empty(f3.shape, dtype=np.float32)
    sd = np.empty(f3.shape, dtype=np.float32)
    _kernels.semblance_num_den(f3, p0, p1, 1, 0 if two_d else 1, sn, sd)
    del p0, p1
    if options.planarity_sigma is not None:
        sn *= planarity
        del planarity
    step = scan_step(options, f3.shape[2])
    if step > 1:
        sn, sd = sum_samples(sn, step), sum_samples(sd, step)
    return sn, sd


def semblance_floor(sum_denominator: float, count: int) -> float:
    """Denominators at or below this (1e-6 of their mean over the cube) are dead samples: semblance 1, likelihood 0."""
    return float(1e-6 * sum_denominator / max(int(count), 1)) + 1e-30


def scan_planes(sn: np.ndarray, sd: np.ndarray, options: FaultScanOptions, tiny: float, *, n_samples: int,
                axis: int, two_d: bool = False, core: tuple | None = None, origin: int = 0) -> np.ndarray:
    """The scan (step 4 of :func:`fault_likelihood`) over the planes sheared along ``axis``, on a block that holds
    that whole axis and :func:`strike_halo` traces of halo along the other one.

    Parameters
    ----------
    sn, sd : (n_axis, m, n_other) float32 ndarray
        From :func:`semblance_terms`, in the scan's own layout (the sheared axis, the grouped samples, the other
        lateral axis; :func:`~seismo3d.seismic.blocks.stores.read_sheared`), C-contiguous, used in place.
    options : FaultScanOptions
    tiny : float
        From :func:`semblance_floor` over the whole cube.
    n_samples : int
        Samples per trace before grouping.
    axis : {0, 1}
        The shear axis of the planes scanned (:func:`sheared_axes`).
    two_d : bool
    core, origin : optional
        The ``(start, stop)`` along the other axis whose result is returned (default all), and the cube index of
        the block's first trace along that axis.

    Returns
    -------
    (n0, n1, m) int32 ndarray, the cube's layout (``core`` taken along the other axis)
        Packed ``likelihood << 11 | plane`` of the best plane at each grouped sample: decode with
        :func:`decode_scan`; the maximum of two keys is the key of the union of their planes.

    Raises
    ------
    InputError
        More planes than the key's code holds.
    """
    table = orientation_table(*options.angles(), two_d)
    if len(table) > (1 << CODE_BITS):
        raise InputError(f"{len(table)} fault planes to scan but at most {1 << CODE_BITS} are supported; pass fewer "
                         "strikes or dips")
    step = scan_step(options, n_samples)
    squarings = int(options.power).bit_length() - 1
    n_threads = nb.get_num_threads()
    # planes sheared along `axis`, grouped by strike (mod 180): one smoothing along strike serves a group
    groups = {}
    for k, r in enumerate(table):
        if r[2] == axis:
            groups.setdefault(round(r[0] % 180.0, 6), []).append((k, r))
    # the kernels work in the layout (na, nt, nb): na = the sheared horizontal axis, nb = the other one
    smooth_lateral = not two_d and sn.shape[2] > 1
    yn = np.empty_like(sn) if smooth_lateral else sn
    yd = np.empty_like(sd) if smooth_lateral else sd
    b0, b1 = (0, yn.shape[2]) if core is None else core
    key = np.zeros(yn.shape[:2] + (b1 - b0,), dtype=np.int32)
    for members in groups.values():
        alpha, lateral = members[0][1][3], members[0][1][5]
        if smooth_lateral:
            hs = box_half(float(options.strike_smoothing) * lateral)
            smooth_strike(sn, float(alpha), hs, origin, n_threads, yn)
            smooth_strike(sd, float(alpha), hs, origin, n_threads, yd)
        for k, r in members:
            # lateral shift per (grouped) sample, and the smoothing width down the dip in grouped samples
            beta = float(r[4]) * step
            sigma = float(options.dip_smoothing) * float(np.sin(np.radians(r[1]))) / step
            scan_dip(yn, yd, beta, exponential_coefficient(max(sigma, 0.5)), np.int32(k), squarings, tiny,
                     n_threads, key, b0)
    return np.ascontiguousarray(key.transpose((0, 2, 1) if axis == 0 else (2, 0, 1)))


def saturation_counts(key: np.ndarray, live: np.ndarray, level: float) -> tuple[int, int]:
    """Live (grouped) samples whose likelihood exceeds ``level``, and live samples: for the saturation warning."""
    return int(np.count_nonzero((key >> CODE_BITS)[live] > int(level * FL_LEVELS))), int(np.count_nonzero(live))


def _warn_if_saturated(saturated: float, opt: FaultScanOptions) -> None:
    if saturated > opt.saturated:
        warnings.warn(
            f"fault likelihood exceeds {opt.saturation_level:g} at {saturated:.0%} of the samples: the data has no "
            "lateral coherence (noise, chaotic reflections, or traces out of order), so faults traced from it are "
            "unreliable; "
            "check the inline/crossline geometry or filter the data first", Seismo3dWarning, stacklevel=3)


def decode_scan(key: np.ndarray, options: FaultScanOptions, *, n_samples: int,
                two_d: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Likelihood, strike and dip at every sample from the packed key of :func:`scan_planes` (step 5).

    Returns
    -------
    likelihood, strike_deg, dip_deg : (n0, n1, n_samples) float32 ndarray
    """
    step = scan_step(options, n_samples)
    if step > 1:
        key = key[..., np.minimum(np.arange(n_samples) // step, key.shape[2] - 1)]
    table = orientation_table(*options.angles(), two_d)
    code = key & ((1 << CODE_BITS) - 1)
    fl = (key >> CODE_BITS).astype(np.float32) * np.float32(1.0 / FL_LEVELS)
    strike = np.array([r[0] for r in table], dtype=np.float32)[code]
    dip = np.array([r[1] for r in table], dtype=np.float32)[code]
    np.clip(fl, 0.0, 1.0, out=fl)
    return fl, strike, dip


def sheared_axes(options: FaultScanOptions, two_d: bool = False) -> tuple:
    """The shear axes (0: along inlines, 1: along crosslines) that hold planes of the scan: both in 3D by default,
    axis 0 alone in a section."""
    table = orientation_table(*options.angles(), two_d)
    return tuple(axis for axis in (0, 1) if any(r[2] == axis for r in table))


# The scan's steps declared once (:func:`block_steps`) and run in their order by :func:`run_scan`, by blocks
# (:mod:`~seismo3d.seismic.faults.likelihood.scan_blocks`) or on the whole array in memory (:func:`fault_likelihood`).
# Bytes of working memory per sample of a block (incl. halo), from the arrays each step holds at its peak: balancing
# holds the amplitudes, their squares and two smoothing passes; the semblance step the balanced amplitudes, 3
# gradients, 6 tensor components, the planarity and the outputs; the scan 2 inputs read in its layout, 2 smoothed
# copies and the keys of the block's core (a third of it or less); decoding the key brought back to every sample
# and likelihood, strike and dip.
# (tracemalloc peaks of the steps on a 96 x 96 x 512 block: balance 12 + the input 4 and the tiles it is cut from 4,
# semblance 40 + the input 4, scan 23 per grouped sample, decoding 20; the semblance and decoding rounded up)
_BALANCE_BYTES = 20
_SEMBLANCE_BYTES = 48
_SCAN_BYTES = 24
_DECODE_BYTES = 24


def block_steps(shape, options: FaultScanOptions, *, block: int | None = None, strip: int | None = None) -> tuple:
    """The steps of the scan, declared once, in their order: the amplitude statistics and the balancing (square
    blocks read from the cube), the semblance terms (their denominators reduced into the semblance floor), the scan
    along inlines and along crosslines (blocks of every trace along the scanned axis and ``b`` traces across it)
    and the decoding (on the semblance's blocks), each with its block function, halo and the bytes of a block of
    ``b`` traces a side, largest and forced sides (:func:`~seismo3d.seismic.blocks.plan.plan_steps` plans those
    with bytes: ``'balance'``, ``'semblance'``, ``'scan'``).

    Parameters
    ----------
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)`` (a section: ``(n_traces, 1, n_samples)``).
    options : FaultScanOptions
    block, strip : int, optional
        Sides forced by the caller (``ChunkOptions.block``, ``ChunkOptions.strip``), traces.

    Returns
    -------
    tuple of BlockStep
        Named ``'amplitudes'``, ``'balance'``, ``'semblance'``, ``'scan'`` (run as ``'scan_inline'`` and
        ``'scan_crossline'``), ``'decode'``.
    """
    n0, n1, nt = shape
    m = -(-nt // scan_step(options, nt))
    bhalo, halo, shalo = balance_halo(options), semblance_halo(options), strike_halo(options)
    n_axis = max(n0, n1)

    def semblance_bytes(b):
        return max((b + 2 * halo) ** 2 * nt * _SEMBLANCE_BYTES, b ** 2 * nt * _DECODE_BYTES)

    def balance_bytes(b):
        return (b + 2 * bhalo) ** 2 * nt * _BALANCE_BYTES

    def scan_bytes(w):
        return n_axis * (w + 2 * shalo) * m * _SCAN_BYTES

    return (BlockStep("amplitudes", "reduce", 0, function=amplitude_block, label="amplitude statistics",
                      inputs=(CUBE,), place=True),
            BlockStep("balance", "map", bhalo, balance_bytes, 512, function=balance_block,
                      label="amplitude balancing", inputs=(CUBE,), outputs=("balanced",), place=True),
            BlockStep("semblance", "reduce", halo, semblance_bytes, 256, block, function=semblance_block,
                      label="semblance", inputs=("balanced",), outputs=("numerator", "denominator"), place=True),
            BlockStep("scan", "map", shalo, scan_bytes, n_axis, strip, function=scan_block,
                      label="fault scan", inputs=("numerator", "denominator"), outputs=("key",), place=True,
                      lazy=True),
            BlockStep("decode", "reduce", 0, function=decode_block, label="decode", inputs=("key", "denominator"),
                      outputs=("likelihood", "strike_deg", "dip_deg")))


def whole_plan(shape) -> dict:
    """The plan of a run in memory: every step on one block, the whole cube (sides as :func:`run_scan` reads them).

    Parameters
    ----------
    shape : (int, int, int)

    Returns
    -------
    dict
    """
    side = max(int(shape[0]), int(shape[1]))
    return {"shape": [int(n) for n in shape], "tile": side, "balance": side, "semblance": side, "scan": side}


def run_scan(run, x, opt: FaultScanOptions, plan: dict, *, two_d: bool = False) -> float:
    """The scan's declared steps (:func:`block_steps`) in their order on a run: by blocks
    (:class:`~seismo3d.seismic.blocks.stores.StoreRun`) or in memory on one block
    (:class:`~seismo3d.seismic.blocks.executor.MemoryRun`), the likelihood, strike and dip left in its arrays.

    Parameters
    ----------
    run : StoreRun or MemoryRun
    x : (n_inlines, n_xlines, n_samples) float32 dask.array.Array or ndarray
        The amplitudes (a section as a cube of one crossline, with ``two_d``).
    opt : FaultScanOptions
    plan : dict
        ``shape``, ``tile`` and the sides of the blocks of ``'balance'`` (also the statistics'), ``'semblance'``
        (also the decoding's) and ``'scan'`` (traces across the scanned axis) (:func:`whole_plan` in memory).
    two_d : bool
        ``x`` is a section.

    Returns
    -------
    float
        The saturated fraction: live samples with a likelihood above ``opt.saturation_level``, of the live ones.
    """
    shape = tuple(int(n) for n in plan["shape"])
    n0, n1, nt = shape
    m = -(-nt // scan_step(opt, nt))
    steps = {step.name: step for step in block_steps(shape, opt)}
    side, block, strip = plan["balance"], plan["semblance"], plan["scan"]
    # whole-cube amplitude statistics, then the balanced amplitudes and the semblance terms
    sums = run.run_step(steps["amplitudes"], lateral_blocks(shape, side, side), source=x)
    stats = AmplitudeStatistics.from_sums(max(r["peak"] for r in sums), sum(r["sum_squares"] for r in sums),
                                          n0 * n1 * nt)
    run.run_step(steps["balance"], lateral_blocks(shape, side, side), opt, stats, two_d, source=x)
    results = run.run_step(steps["semblance"], lateral_blocks(shape, block, block), opt, two_d)
    run.release("balanced")
    tiny = semblance_floor(sum(r["sum_denominator"] for r in results), n0 * n1 * m)
    # the planes sheared along each axis; a later axis keeps the better plane of both
    for k, axis in enumerate(sheared_axes(opt, two_d)):
        name = ("inline", "crossline")[axis]
        scan = replace(steps["scan"], name=f"scan_{name}", label=f"fault scan along {name}s",
                       combine=np.maximum if k else None)
        run.run_step(scan, lateral_blocks(shape, n0, strip) if axis == 0 else lateral_blocks(shape, strip, n1),
                     axis, opt, tiny, nt, plan["tile"], two_d)
    run.release("numerator")
    results = run.run_step(steps["decode"], lateral_blocks(shape, block, block), opt, tiny, nt, two_d)
    run.release("key", "denominator")
    live = sum(r["live"] for r in results)
    return sum(r["high"] for r in results) / live if live else 0.0


def amplitude_block(place, f) -> BlockOutput:
    """The peak absolute amplitude and the float64 sum of squares of a block, reduced into the cube's
    :class:`AmplitudeStatistics` (:meth:`AmplitudeStatistics.from_sums`).

    Parameters
    ----------
    place : BlockPlace
    f : (m0, m1, n_samples) array_like
        Amplitudes of the block.

    Returns
    -------
    BlockOutput
        Summary ``peak``, ``sum_squares``.

    Raises
    ------
    InputError
        The block holds NaN or inf.
    """
    f = np.ascontiguousarray(f, dtype=np.float32)
    check_finite(f, (place.block[0], place.block[1] - 1))
    return BlockOutput(summary={"peak": float(np.max(np.abs(f))) if f.size else 0.0,
                                "sum_squares": float(np.einsum("ijk,ijk->", f, f, dtype=np.float64))})


def balance_block(place, f, opt: FaultScanOptions, stats: AmplitudeStatistics, two_d: bool = False) -> BlockOutput:
    """Balanced amplitudes of a block read with the balancing's halo (:func:`balance_amplitudes`).

    Parameters
    ----------
    place : BlockPlace
    f : (m0, m1, n_samples) array_like
        Amplitudes of ``place.region``.
    opt : FaultScanOptions
    stats : AmplitudeStatistics
        Of the whole cube.
    two_d : bool
        A section as a cube of one crossline.

    Returns
    -------
    BlockOutput
        ``balanced``: (m0, m1, n_samples) float32, cut to the core by the executor.
    """
    return BlockOutput({"balanced": balance_amplitudes(np.ascontiguousarray(f, dtype=np.float32), opt, stats,
                                                       two_d=two_d)})


def semblance_block(place, f, opt: FaultScanOptions, two_d: bool = False) -> BlockOutput:
    """Semblance terms of a block of balanced amplitudes read with the semblance's halo
    (:func:`semblance_terms`), and the sum of the core's denominators (the semblance floor's).

    Parameters
    ----------
    place : BlockPlace
    f : (m0, m1, n_samples) float32 ndarray
        Balanced amplitudes of ``place.region``.
    opt : FaultScanOptions
    two_d : bool

    Returns
    -------
    BlockOutput
        ``numerator``, ``denominator`` of the core, float32 at the scan's grouped samples; summary
        ``sum_denominator``.
    """
    sn, sd = semblance_terms(f, opt, two_d=two_d)
    sn, sd = sn[place.core], sd[place.core]
    return BlockOutput({"numerator": sn, "denominator": sd}, {"sum_denominator": float(sd.sum(dtype=np.float64))})


def scan_block(place, numerator, denominator, axis: int, opt: FaultScanOptions, tiny: float, n_samples: int,
               tile: int, two_d: bool = False) -> BlockOutput:
    """The planes sheared along ``axis`` (:func:`scan_planes`) on a block that holds that whole axis.

    Parameters
    ----------
    place : BlockPlace
        The block (every trace along ``axis``) and the region read (the strike smoothing's halo across it).
    numerator, denominator : (n_inlines, n_xlines, m) arrays read by slicing
        Semblance terms (Zarr arrays by blocks, ndarrays in memory), read here in the sheared layout
        (:func:`~seismo3d.seismic.blocks.stores.read_sheared`).
    axis : {0, 1}
    opt : FaultScanOptions
    tiny : float
        The semblance floor.
    n_samples : int
        Samples per trace of the cube.
    tile : int
        Rows read at once.
    two_d : bool

    Returns
    -------
    BlockOutput
        ``key``: the core's packed scan keys, int32.
    """
    a0, a1, b0, b1 = place.region
    i0, i1, j0, j1 = place.block
    core, origin = ((j0 - b0, j1 - b0), b0) if axis == 0 else ((i0 - a0, i1 - a0), a0)
    sn = read_sheared(numerator, place.read, axis, tile)
    sd = read_sheared(denominator, place.read, axis, tile)
    key = scan_planes(sn, sd, opt, tiny, n_samples=n_samples, axis=axis, two_d=two_d, core=core, origin=origin)
    return BlockOutput({"key": key})


def decode_block(key, denominator, opt: FaultScanOptions, tiny: float, n_samples: int,
                 two_d: bool = False) -> BlockOutput:
    """Likelihood, strike and dip of a block from the combined key (:func:`decode_scan`), with its saturated and
    live samples.

    Parameters
    ----------
    key : (m0, m1, m) int32 ndarray
        Packed scan keys.
    denominator : (m0, m1, m) float32 ndarray
        Semblance denominators (live where above ``tiny``).
    opt : FaultScanOptions
    tiny : float
    n_samples : int
    two_d : bool

    Returns
    -------
    BlockOutput
        ``likelihood``, ``strike_deg``, ``dip_deg``: (m0, m1, n_samples) float32; summary ``high``, ``live``.
    """
    live = denominator > tiny
    high, n_live = saturation_counts(key, live, opt.saturation_level)
    del live
    fl, strike, dip = decode_scan(key, opt, n_samples=n_samples, two_d=two_d)
    return BlockOutput({"likelihood": fl, "strike_deg": strike, "dip_deg": dip}, {"high": high, "live": n_live})
