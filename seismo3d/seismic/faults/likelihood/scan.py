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
from dataclasses import dataclass

import numba as nb
import numpy as np

from ...._options import resolve_options
from ...._progress import progress_steps
from ...._validation import as_seismic, as_sigma_pair, check_int, check_positive
from ....errors import InputError, Seismo3dWarning
from ... import _kernels
from .scan_kernels import (CODE_BITS, FL_LEVELS, box_half, default_angles, exponential_coefficient, orientation_table,
                           scan_dip, smooth_strike, sum_samples)
from ..result import FaultLikelihood

__all__ = ["FaultScanOptions", "fault_likelihood"]


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

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes; the last axis is the sample (time or depth, downward). Must be finite.
    options : FaultScanOptions, optional
        The scanned strikes and dips, smoothing, balancing and power (see :class:`FaultScanOptions` for the
        defaults).
    progress : bool, optional
        Report the scan's progress over strikes (:mod:`seismo3d._progress`: a bar on a terminal, log lines
        otherwise).
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
    stats = AmplitudeStatistics.of(f3)
    # structure-oriented semblance numerator and denominator of each sample (3 x 3 traces along the reflector),
    # summed over pairs of samples (the scan's vertical step)
    sn, sd = semblance_terms(balance_amplitudes(f3, opt, stats, two_d=two_d), opt, two_d=two_d)
    tiny = semblance_floor(float(sd.sum(dtype=np.float64)), sd.size)
    live = sd > tiny
    # the scan: each plane's semblance smoothed within it; the best plane per sample, packed into one int32 key
    key = scan_planes(sn, sd, opt, tiny, n_samples=f3.shape[2], two_d=two_d, progress=progress)
    del sn, sd
    _warn_if_saturated(*saturation_counts(key, live, opt.saturation_level), opt)
    fl, strike, dip = decode_scan(key, opt, n_samples=f3.shape[2], two_d=two_d)
    del key
    if two_d:
        fl, strike, dip = fl[:, 0, :], strike[:, 0, :], dip[:, 0, :]
    return FaultLikelihood(fl, strike, dip)


# The scan in steps, each of which also runs on a block of a cube (seismo3d.seismic.faults.likelihood.scan_blocks): a
# block's result equals the whole cube's over the block when the block carries the halo each step needs.

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

    @classmethod
    def of(cls, f3: np.ndarray) -> "AmplitudeStatistics":
        """The statistics of a whole (n0, n1, n_samples) array of amplitudes."""
        peak = float(np.max(np.abs(f3))) if f3.size else 0.0
        return cls.from_sums(peak, float(np.einsum("ijk,ijk->", f3, f3, dtype=np.float64)), f3.size)


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
                two_d: bool = False, axes: tuple = (0, 1), core: tuple | None = None, origin: int = 0,
                sheared_layout: bool = False, progress: bool = False) -> np.ndarray:
    """The scan (step 4 of :func:`fault_likelihood`) over the planes sheared along ``axes``.

    Parameters
    ----------
    sn, sd : (n0, n1, m) float32 ndarray
        From :func:`semblance_terms`.
    options : FaultScanOptions
    tiny : float
        From :func:`semblance_floor` over the whole cube.
    n_samples : int
        Samples per trace before grouping.
    two_d : bool
    axes : tuple of {0, 1}
        Shear axes of the planes to scan. A block of a cube scanned for the planes sheared along one axis must hold
        that whole axis, and :func:`strike_halo` traces of halo along the other one.
    core, origin : optional
        For a block: the ``(start, stop)`` along the other axis whose result is returned, and the cube index of the
        block's first trace along that axis.
    sheared_layout : bool
        With one axis: ``sn`` and ``sd`` are given in the scan's own layout, (sheared axis, sample, other axis),
        C-contiguous, and are used (and overwritten) in place: no copies, for blocks read to fit a memory limit.
    progress : bool

    Returns
    -------
    (n0, n1, m) int32 ndarray (``core`` taken along the other axis)
        Packed ``likelihood << 11 | plane`` of the best plane at each grouped sample: decode with
        :func:`decode_scan`; the maximum of two keys is the key of the union of their planes.
    """
    table = orientation_table(*options.angles(), two_d)
    if len(table) > (1 << CODE_BITS):
        raise InputError(f"{len(table)} fault planes to scan but at most {1 << CODE_BITS} are supported; pass fewer "
                         "strikes or dips")
    step = scan_step(options, n_samples)
    if sheared_layout and len(axes) != 1:
        raise InputError("sheared_layout=True scans the planes of one shear axis; pass axes=(0,) or axes=(1,)")
    return _scan(sn, sd, table, two_d, options, tiny, step, progress, axes, core, origin, sheared_layout)


def saturation_counts(key: np.ndarray, live: np.ndarray, level: float) -> tuple[int, int]:
    """Live (grouped) samples whose likelihood exceeds ``level``, and live samples: for the saturation warning."""
    return int(np.count_nonzero((key >> CODE_BITS)[live] > int(level * FL_LEVELS))), int(np.count_nonzero(live))


def _warn_if_saturated(high: int, live: int, opt: FaultScanOptions) -> None:
    if live and high / live > opt.saturated:
        warnings.warn(
            f"fault likelihood exceeds {opt.saturation_level:g} at {high / live:.0%} of the samples: the data has no lateral coherence "
            "(noise, chaotic reflections, or traces out of order), so faults traced from it are unreliable; "
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


def _scan(sn, sd, table, two_d, opt, tiny, step, progress, axes=(0, 1), core=None, origin=0, sheared_layout=False):
    """The packed (likelihood << CODE_BITS | orientation code) int32 maximum over the scanned planes, on samples
    grouped by ``step``."""
    squarings = int(opt.power).bit_length() - 1
    strike_smoothing = float(opt.strike_smoothing)
    n_threads = nb.get_num_threads()
    shape = list(sn.shape)
    if sheared_layout:  # (na, nt, nb) -> the cube's axes
        shape = [shape[0], shape[2], shape[1]] if axes[0] == 0 else [shape[2], shape[0], shape[1]]
    if core is not None:  # a block scanned along one axis, kept on `core` of the other
        shape[1 - axes[0]] = core[1] - core[0]
    key = np.zeros(shape, dtype=np.int32)
    # planes sheared along axis 0 or 1, grouped by strike (mod 180): one smoothing along strike serves a group
    groups = {axis: {} for axis in (0, 1)}
    for k, r in enumerate(table):
        groups[r[2]].setdefault(round(r[0] % 180.0, 6), []).append((k, r))
    with progress_steps(sum(len(groups[a]) for a in axes), "fault likelihood", unit="strike",
                        enabled=progress) as bar:
        for axis in axes:
            if not groups[axis]:
                continue
            # kernels work in the layout (na, nt, nb): na = the sheared horizontal axis, nb = the other one
            perm = (0, 2, 1) if axis == 0 else (1, 2, 0)
            if sheared_layout:
                xn, xd = sn, sd
            else:
                xn = np.ascontiguousarray(sn.transpose(perm))
                xd = np.ascontiguousarray(sd.transpose(perm))
            smooth_lateral = not two_d and xn.shape[2] > 1
            yn = np.empty_like(xn) if smooth_lateral else xn
            yd = np.empty_like(xd) if smooth_lateral else xd
            b0, b1 = (0, yn.shape[2]) if core is None else core
            keya = np.zeros(yn.shape[:2] + (b1 - b0,), dtype=np.int32)
            for members in groups[axis].values():
                alpha, lateral = members[0][1][3], members[0][1][5]
                if smooth_lateral:
                    hs = box_half(strike_smoothing * lateral)
                    smooth_strike(xn, float(alpha), hs, origin, n_threads, yn)
                    smooth_strike(xd, float(alpha), hs, origin, n_threads, yd)
                for k, r in members:
                    # lateral shift per (grouped) sample, and the smoothing width down the dip in grouped samples
                    beta = float(r[4]) * step
                    sigma = float(opt.dip_smoothing) * float(np.sin(np.radians(r[1]))) / step
                    scan_dip(yn, yd, beta, exponential_coefficient(max(sigma, 0.5)), np.int32(k), squarings,
                              tiny, n_threads, keya, b0)
                bar.advance()
            del xn, xd, yn, yd
            np.maximum(key, keya.transpose(tuple(np.argsort(perm))), out=key)
            del keya
    return key
