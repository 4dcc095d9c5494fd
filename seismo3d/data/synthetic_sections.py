"""Generated faulted seismic sections with fault labels: the training and validation data of the learned likelihood.

Each section is built like FaultSeg3D's training cubes (Wu et al. 2019), in 2D and with more variety:

1. **Reflectivity** in relative geologic time (RGT): a blocky impedance log (layers 1-12 samples thick, a random
   walk of log-impedance with occasional strong contrasts) differentiated, with smooth lateral amplitude changes.
2. **Layering**: folding (sums of Gaussian bumps and a plane, up to ``max_fold_dip``), and with probability 0.4
   an angular unconformity (a second package of another dip above a wavy surface: reflector terminations that are
   not faults).
3. **Faults**, oldest first, 0-``max_faults`` of them (none with probability ``p_unfaulted``): normal or reverse
   dip-slip on a planar or slightly curved (listric) trace of dip 50-88 degrees (index space), the throw tapering
   to 0 at the fault's tips (faults that die out within the section) or constant along it (faults crossing it),
   0-``max_throw`` samples at the fault's centre. Younger faults offset older ones (faults cut faults).
   Optional draws (off by default): small throws, short faults, fault systems, steep folds, faults at the base of the
   section running into its last sample (``p_basal_fault``) and faults older than an unconformity that ends them
   (``p_buried_faults``).
4. Every output sample is mapped back through the faults, youngest first, then through the layering to its RGT
   (exact labels); the reflectivity is sampled there and convolved along the trace with a Ricker wavelet of peak
   frequency 0.06-0.2 cycles per sample (15-50 Hz at 4 ms) and random phase rotation.
5. The degradations of real data (:func:`seismo3d.data.degradations.degrade`).

Labels: the samples within 1 sample (across the fault) of a fault trace where its local throw is at least
``min_label_throw`` samples (a fault that displaces nothing is invisible, and labelling it would teach the network to
guess).

Conventions: axis 0 trace, axis 1 sample (downward), as in :mod:`seismo3d.data.synthetic`.

References
----------
Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45.
doi:10.1190/geo2018-0646.1
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d, map_coordinates

from .._validation import check_int
from ..errors import InputError
from .degradations import degrade
from .synthetic import ricker

__all__ = ["FaultSectionOptions", "FaultSection", "synthetic_fault_section", "fault_section_batch"]


@dataclass(frozen=True)
class FaultSectionOptions:
    """Ranges of the random draws of :func:`synthetic_fault_section`.

    Attributes
    ----------
    max_faults : int
        Most faults per section (the number is uniform in 1..max_faults when faulted).
    p_unfaulted : float
        Probability of a section without any fault.
    dip_range : (float, float)
        Fault dips, degrees from the horizontal in index space (one trace = one sample).
    max_throw : float
        Largest throw at a fault's centre, samples.
    reverse_fraction : float
        Fraction of reverse faults.
    frequency_range : (float, float)
        Peak frequency of the Ricker wavelet, cycles per sample (15-50 Hz at 4 ms is 0.06-0.2).
    max_fold_dip : float
        Steepest reflector dip of the folding, degrees.
    min_label_throw : float
        Fault samples are labelled where the local throw is at least this, samples.
    degradation : float
        Strength of :func:`~seismo3d.data.degradations.degrade` (0: clean up to a little white noise).
    p_fault_system : float
        Probability that a faulted section's faults form one system, as extension and compression make them
        (Anderson's faulting: a set of nearly parallel faults and its conjugate): one dip direction and a dip
        drawn for the section, each fault within ``system_dip_spread`` degrees of it and antithetic (the other
        direction) with probability ``p_antithetic``. Otherwise (and at the default 0) every fault draws its own dip
        and direction.
    system_dip_spread : float
        Standard deviation of a system's fault dips about the section's dip, degrees.
    p_antithetic : float
        Probability that a fault of a system dips the other way.
    p_steep_fold : float
        Probability that a section's folding reaches ``steep_fold_dip`` instead of ``max_fold_dip``: reflectors as
        steep as faults (diapir flanks, drag folds) that offset nothing and are not faults.
    steep_fold_dip : float
        Steepest reflector dip of a steeply folded section, degrees.
    p_small_throw : float
        Probability that a fault's throw at its centre is drawn from ``small_throw_range`` instead of
        0-``max_throw``: the small faults people draw on real sections (F3's steep faults offset reflectors by a few
        samples). The default 0 leaves the draws unchanged.
    small_throw_range : (float, float)
        Throws of the small faults, samples.
    fault_length_range : (float, float)
        Lengths of the faults that die out within the section (tapered throw), fractions of the section's
        samples; shorter faults are those of a few tens of samples people draw below F3's strong reflectors.
    p_buried_faults : float
        Probability that a faulted section's faults are older than an angular unconformity: the erosion surface
        (depth drawn in ``buried_surface_range``) cuts the faulted layering, the package above it, laid down after
        the faulting, is unbroken, and the surface is a strong reflector (a reflection coefficient of 2.5-8 times
        the layering's typical one, either sign). The faults and their labels end at the surface, so the faulted
        package is the lower part of the section, down to its last sample: the short faults at the base of F3's
        inlines, under a strong unconformity, that run into the data's bottom edge. The default 0 leaves the draws
        unchanged.
    buried_surface_range : (float, float)
        Depth of the erosion surface of a section of buried faults (its mean over the traces; the surface is wavy
        as the other unconformities), fractions of the section's samples.
    p_basal_fault : float
        Probability that a fault is a short one at the base of the section: it slips from an upper tip drawn in
        ``basal_top_range`` down past the section's last sample (the throw tapering to 0 at the upper tip only, so
        the fault runs into the data's bottom edge still slipping), as F3's short faults at the base of inlines
        100-400 run into its last samples. The default 0 leaves the draws unchanged.
    basal_top_range : (float, float)
        Depth of a basal fault's upper tip, fractions of the section's samples.
    """

    max_faults: int = 8
    p_unfaulted: float = 0.15
    dip_range: tuple = (50.0, 88.0)
    max_throw: float = 20.0
    reverse_fraction: float = 0.3
    frequency_range: tuple = (0.06, 0.2)
    max_fold_dip: float = 30.0
    min_label_throw: float = 1.0
    degradation: float = 1.0
    p_fault_system: float = 0.0
    system_dip_spread: float = 5.0
    p_antithetic: float = 0.25
    p_steep_fold: float = 0.0
    steep_fold_dip: float = 55.0
    p_small_throw: float = 0.0
    small_throw_range: tuple = (1.5, 5.0)
    fault_length_range: tuple = (0.3, 1.2)
    p_buried_faults: float = 0.0
    buried_surface_range: tuple = (0.4, 0.85)
    p_basal_fault: float = 0.0
    basal_top_range: tuple = (0.55, 0.9)

    def __post_init__(self):
        for name in ("p_unfaulted", "reverse_fraction", "p_fault_system", "p_antithetic", "p_steep_fold",
                     "p_small_throw", "p_buried_faults", "p_basal_fault"):
            if not 0.0 <= float(getattr(self, name)) <= 1.0:
                raise InputError(f"{name} must be a probability in [0, 1]; got {getattr(self, name)!r}")
        if not 0.0 <= float(self.system_dip_spread) <= 45.0:
            raise InputError(f"system_dip_spread must be in [0, 45] degrees; got {self.system_dip_spread!r}")
        if not 0.0 <= float(self.steep_fold_dip) < 90.0:
            raise InputError(f"steep_fold_dip must be in [0, 90) degrees; got {self.steep_fold_dip!r}")
        low, high = (float(v) for v in self.fault_length_range)
        if not 0.0 < low <= high:
            raise InputError(f"fault_length_range must be (low, high) with 0 < low <= high; got "
                             f"{self.fault_length_range!r}")
        for name in ("buried_surface_range", "basal_top_range"):
            low, high = (float(v) for v in getattr(self, name))
            if not 0.0 <= low <= high <= 1.0:
                raise InputError(f"{name} must be (low, high) with 0 <= low <= high <= 1; got "
                                 f"{getattr(self, name)!r}")
        low, high = (float(v) for v in self.small_throw_range)
        if not 0.0 <= low <= high:
            raise InputError(f"small_throw_range must be (low, high) with 0 <= low <= high samples; "
                             f"got {self.small_throw_range!r}")


@dataclass(frozen=True, eq=False)
class FaultSection:
    """Result of :func:`synthetic_fault_section`.

    Attributes
    ----------
    section : (n_traces, n_samples) float32 ndarray
        Degraded amplitudes.
    clean : (n_traces, n_samples) float32 ndarray
        The same before the degradations.
    faults : (n_traces, n_samples) bool ndarray
        Fault labels.
    throw : (n_traces, n_samples) float32 ndarray
        Local throw (samples) at the labelled samples, 0 elsewhere.
    n_faults : int
        Number of faults drawn (some may have no labelled sample where their throw stays below the minimum).
    """

    section: np.ndarray
    clean: np.ndarray
    faults: np.ndarray
    throw: np.ndarray
    n_faults: int


def _impedance_reflectivity(rng, n: int) -> np.ndarray:
    """Reflectivity of a blocky log-impedance random walk, length n (samples of RGT)."""
    out = np.zeros(n)
    z = 0
    log_imp = 0.0
    while z < n:
        thick = int(rng.integers(1, 9))
        step = rng.normal(0, 0.08) + (rng.normal(0, 0.2) if rng.random() < 0.03 else 0.0)
        log_imp += step
        out[z] = step
        z += thick
    return out


def _folded(rng, nx: int, nz: int, dip_deg: float) -> np.ndarray:
    """RGT of a (nx, nz) folded package (sums of Gaussian bumps and a plane, steepest dip ``dip_deg``)."""
    x = np.arange(nx, dtype=np.float64)[:, None]
    z = np.arange(nz, dtype=np.float64)[None, :]
    g = np.zeros((nx, 1))
    for _ in range(int(rng.integers(1, 5))):
        c, s = rng.uniform(-0.2, 1.2) * nx, rng.uniform(0.1, 0.5) * nx
        g += rng.uniform(-1, 1) * np.exp(-0.5 * ((x - c) / s) ** 2)
    g += rng.uniform(-0.5, 0.5) * (x - nx / 2) / nx
    slope = np.abs(np.gradient(g[:, 0])).max() or 1.0
    g *= np.tan(np.radians(dip_deg)) / slope
    growth = rng.uniform(0.2, 1.0)
    return z + ((1 - growth) + growth * z / nz) * g


def _wavy_surface(rng, nx: int, nz: int, depth: float) -> np.ndarray:
    """Depth (samples) of an erosion surface along the nx traces: ``depth`` plus smooth waves."""
    return depth + gaussian_filter1d(rng.normal(0, 1, nx), nx / 8) * nz * 0.5


def _layering(rng, nx: int, nz: int, max_dip: float):
    """RGT of every sample of a (nx, nz) section before faulting: folding and an optional unconformity."""
    rgt = _folded(rng, nx, nz, rng.uniform(0.0, 1.0) * max_dip)
    if rng.random() < 0.4:  # angular unconformity: another package above a wavy erosion surface
        upper = _folded(rng, nx, nz, rng.uniform(0.0, 1.0) * max_dip) - 3 * nz
        surface = _wavy_surface(rng, nx, nz, rng.uniform(0.2, 0.7) * nz)
        rgt = np.where(np.arange(nz)[None, :] < surface[:, None], upper, rgt)
    return rgt


def _buried_layering(rng, nx: int, nz: int, margin: int, max_dip: float, surface_range, xs, zs):
    """RGT of a section whose faults are older than an unconformity, the erosion surface, the samples above it and
    the strong reflector's trace-wise sample index (``nz``: below the section).

    ``xs, zs``: the unfaulted positions of the section's samples; the package above the surface, laid down after the
    faulting, is sampled at the samples' own positions, the surface is a present-day depth."""
    nx_s, nz_s = xs.shape
    lower = _folded(rng, nx, nz, rng.uniform(0.0, 1.0) * max_dip)
    upper = _folded(rng, nx, nz, rng.uniform(0.0, 1.0) * max_dip) - 3 * nz
    surface = _wavy_surface(rng, nx, nz, rng.uniform(*surface_range) * nz_s + margin)[margin:margin + nx_s] - margin
    x0, z0 = np.meshgrid(np.arange(nx_s, dtype=np.float64), np.arange(nz_s, dtype=np.float64), indexing="ij")
    above = z0 < surface[:, None]
    rgt = np.where(above, map_coordinates(upper, [x0 + margin, z0 + margin], order=1, mode="nearest"),
                   map_coordinates(lower, [xs + margin, zs + margin], order=1, mode="nearest"))
    return rgt, above, np.clip(np.ceil(surface), 0, nz_s).astype(np.int64)


@dataclass(frozen=True)
class _Fault:
    x0: float  # lateral position of the trace at depth z0
    z0: float
    cot: float  # lateral change of the trace per sample of depth (signed: the dip direction)
    curvature: float  # listric bend: extra lateral offset per sample^2
    direction: float  # +1: the fault dips towards +x (increasing trace index), -1 towards -x
    throw: float  # throw at the centre, samples (negative: reverse)
    top: float  # depth range where the fault slips
    bottom: float
    tapered: bool

    def trace_x(self, z):
        dz = z - self.z0
        return self.x0 + self.cot * dz + self.curvature * dz * dz

    def local_throw(self, z):
        if not self.tapered:
            inside = (z >= self.top) & (z <= self.bottom)
            return np.where(inside, self.throw, 0.0)
        mid, half = 0.5 * (self.top + self.bottom), 0.5 * (self.bottom - self.top)
        u = np.clip(1 - ((z - mid) / half) ** 2, 0, None)
        return self.throw * np.sqrt(u)


def _draw_fault(rng, nx: int, nz: int, opt: FaultSectionOptions, system=None) -> _Fault:
    """One fault; ``system``: (dip, direction) of the section's fault system, or None for an independent fault."""
    if system is None:
        dip = rng.uniform(*opt.dip_range)
        direction = rng.choice([-1.0, 1.0])
    else:
        dip = float(np.clip(rng.normal(system[0], opt.system_dip_spread), *opt.dip_range))
        direction = -system[1] if rng.random() < opt.p_antithetic else system[1]
    throw = rng.uniform(0.0, opt.max_throw) * (-1.0 if rng.random() < opt.reverse_fraction else 1.0)
    if opt.p_small_throw > 0 and rng.random() < opt.p_small_throw:  # drawn only when asked: defaults unchanged
        throw = float(np.copysign(rng.uniform(*opt.small_throw_range), throw))
    z0 = rng.uniform(0.2, 0.8) * nz
    tapered = rng.random() < 0.6
    if tapered:
        length = rng.uniform(*opt.fault_length_range) * nz
        top = z0 - rng.uniform(0.3, 0.7) * length
        bottom, top = top + length, top
    else:
        top, bottom = -np.inf, np.inf
    curvature = rng.uniform(0, 0.4) / nz * direction if rng.random() < 0.3 else 0.0
    if opt.p_basal_fault > 0 and rng.random() < opt.p_basal_fault:  # drawn only when asked: defaults unchanged
        top = rng.uniform(*opt.basal_top_range) * nz
        bottom, tapered = nz + rng.uniform(0.0, 1.0) * (nz - top), True  # the lower tip below the section
    return _Fault(x0=rng.uniform(0.1, 0.9) * nx, z0=z0, cot=direction / np.tan(np.radians(dip)),
                  curvature=float(curvature), direction=float(direction), throw=float(throw), top=float(top), bottom=float(bottom),
                  tapered=bool(tapered))


def _unfault(fault: _Fault, xs, zs):
    """Map sample coordinates back across one fault: (x, z) before the slip, distance to the trace, local throw."""
    xf = fault.trace_x(zs)
    slope = fault.cot + 2 * fault.curvature * (zs - fault.z0)  # dx/dz along the trace
    sin_dip = 1.0 / np.sqrt(1.0 + slope * slope)
    distance = (xs - xf) * sin_dip  # perpendicular distance, positive on the +x side
    # the hanging wall is the block above the fault: on the side the fault dips towards
    hanging = (xs - xf) * fault.direction > 0
    t = fault.local_throw(zs)
    # dip-slip: the hanging wall moved down (normal) by t vertically and t * slope laterally
    xs = np.where(hanging, xs - t * slope, xs)
    zs = np.where(hanging, zs - t, zs)
    return xs, zs, distance, t


def synthetic_fault_section(shape=(128, 128), *, seed=0, options: FaultSectionOptions | None = None) -> FaultSection:
    """Generate a faulted (or unfaulted) seismic section with the degradations of real data and its fault labels.

    See the module docstring for the construction.

    Parameters
    ----------
    shape : (int, int)
        ``(n_traces, n_samples)``, each >= 16.
    seed : int or numpy.random.Generator
        Seed of the random draws (the same seed gives the same section).
    options : FaultSectionOptions, optional
        Ranges of the draws.

    Returns
    -------
    FaultSection

    Raises
    ------
    InputError
        ``shape`` is not two integers >= 16, or ``options`` is not a :class:`FaultSectionOptions`.

    References
    ----------
    Wu et al. 2019, FaultSeg3D, Geophysics 84(3), IM35-IM45, doi:10.1190/geo2018-0646.1.
    """
    opt = options or FaultSectionOptions()
    if not isinstance(opt, FaultSectionOptions):
        raise InputError(f"options must be a FaultSectionOptions; got {type(opt).__name__}")
    if len(tuple(shape)) != 2:
        raise InputError(f"shape must be (n_traces, n_samples); got {shape!r}")
    nx, nz = (check_int(v, "shape", minimum=16) for v in shape)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)

    n_faults = 0 if rng.random() < opt.p_unfaulted else int(rng.integers(1, opt.max_faults + 1))
    system = None
    if n_faults and opt.p_fault_system > 0 and rng.random() < opt.p_fault_system:
        system = (rng.uniform(*opt.dip_range), rng.choice([-1.0, 1.0]))
    faults = [_draw_fault(rng, nx, nz, opt, system) for _ in range(n_faults)]
    xs, zs = np.meshgrid(np.arange(nx, dtype=np.float64), np.arange(nz, dtype=np.float64), indexing="ij")
    labels = np.zeros((nx, nz), bool)
    throw = np.zeros((nx, nz), np.float32)
    for fault in reversed(faults):  # youngest first
        xs, zs, distance, t = _unfault(fault, xs, zs)
        on = (np.abs(distance) <= 1.0) & (np.abs(t) >= opt.min_label_throw)
        labels |= on
        throw[on] = np.abs(t[on])

    # the layering, sampled at the unfaulted positions (RGT of a margin around the section: faults move samples)
    margin = int(np.ceil(opt.max_throw * 2 + 8))
    fold_dip = opt.max_fold_dip
    if opt.p_steep_fold > 0 and rng.random() < opt.p_steep_fold:
        fold_dip = opt.steep_fold_dip
    buried = bool(n_faults) and opt.p_buried_faults > 0 and rng.random() < opt.p_buried_faults  # drawn only if asked
    if buried:  # the faults end at a younger erosion surface: no labels above it
        rgt, above, surface_index = _buried_layering(rng, nx + 2 * margin, nz + 2 * margin, margin, fold_dip,
                                                     opt.buried_surface_range, xs, zs)
        labels &= ~above
        throw[above] = 0.0
    else:
        rgt_grid = _layering(rng, nx + 2 * margin, nz + 2 * margin, fold_dip)
        rgt = map_coordinates(rgt_grid, [xs + margin, zs + margin], order=1, mode="nearest")
    lo = float(rgt.min()) - 1
    n_rgt = int(np.ceil(float(rgt.max()) - lo)) + 2
    series = _impedance_reflectivity(rng, n_rgt)
    amplitude = 1 + 0.3 * gaussian_filter1d(rng.normal(0, 1, nx), nx / 6)[:, None] * np.sqrt(nx / 6)
    reflectivity = np.interp(rgt - lo, np.arange(n_rgt), series) * amplitude
    if buried:  # the erosion surface a strong reflector: 2.5-8 times the layering's typical coefficient (0.08)
        rows = np.nonzero(surface_index < nz)[0]
        contrast = rng.uniform(0.2, 0.64) * rng.choice([-1.0, 1.0])
        reflectivity[rows, surface_index[rows]] += contrast * amplitude[rows, 0]

    f = rng.uniform(*opt.frequency_range)
    wavelet = ricker(f)
    phase = np.radians(rng.uniform(-90.0, 90.0))
    from scipy.signal import hilbert  # here: importing scipy.signal takes about 0.5 CPU s, every pytest worker's too

    wavelet = np.cos(phase) * wavelet + np.sin(phase) * np.imag(hilbert(wavelet))
    start = (wavelet.size - 1) // 2  # the centred part of the full convolution ('same' even for short traces)
    clean = np.apply_along_axis(lambda tr: np.convolve(tr, wavelet)[start:start + nz], 1, reflectivity)
    clean = (clean / (float(clean.std()) or 1.0)).astype(np.float32)
    section = degrade(clean, rng, strength=opt.degradation)
    return FaultSection(section=section, clean=clean, faults=labels, throw=throw, n_faults=n_faults)


def fault_section_batch(n: int, shape=(128, 128), *, seed=0, options: FaultSectionOptions | None = None):
    """``n`` sections of :func:`synthetic_fault_section` with seeds ``seed * 1_000_003 + i``.

    Parameters
    ----------
    n : int
        Number of sections.
    shape : (int, int)
        ``(n_traces, n_samples)`` of each.
    seed : int
        Seed of the batch (different batches, different sections).
    options : FaultSectionOptions, optional

    Returns
    -------
    sections : (n, n_traces, n_samples) float32 ndarray
    labels : (n, n_traces, n_samples) bool ndarray
    """
    n = check_int(n, "n", minimum=1)
    out = [synthetic_fault_section(shape, seed=int(seed) * 1_000_003 + i, options=options) for i in range(n)]
    return np.stack([s.section for s in out]), np.stack([s.faults for s in out])
