"""Synthetic folded and faulted seismic cubes (and 2D sections) with ground truth, for tests and benchmarks.

Conventions (index space, used by every array and record here)
---------------------------------------------------------------
* 3D: axis 0 inline, axis 1 crossline, axis 2 sample (downward). 2D: axis 0 trace, axis 1 sample (downward).
  Coordinates are array indices (voxel centres at integers); one sample = one voxel along the last axis.
* Strike ``phi`` (degrees, 0-360) is the azimuth of the fault's strike direction in map view, measured from the
  +axis-0 (inline) direction towards the +axis-1 (crossline) direction: strike vector ``(cos phi, sin phi, 0)``.
  The fault dips to the right of its strike (right-hand rule): dip direction ``(-sin phi, cos phi, 0)``.
  In 2D, strike 270 means the fault dips towards +axis 0 (increasing trace index), strike 90 towards -axis 0.
* Dip ``theta`` (degrees) is measured from the horizontal, in index space (one voxel laterally = one sample
  vertically).
* ``FaultPlane.normal`` is the unit normal pointing into the hanging wall (the block above the plane):
  ``(sin theta * dip_direction, -cos theta)``. A point ``x`` is in the hanging wall when ``(x - point) . normal > 0``.
* Throw is the vertical component of the fault slip, in samples, always >= 3 and <= ``max_throw``. Normal faults move
  the hanging wall down its dip, reverse faults up. Slip is pure dip-slip, so the hanging wall also moves laterally by
  ``throw / tan(dip)`` towards (normal) or away from (reverse) the dip direction. Where a reflector dips at angle
  ``alpha`` along the fault's dip direction, the vertical *separation* of the reflector measured at one lateral
  position differs from the throw by the factor ``1 - tan(alpha) / tan(theta)``; measure throw along the slip to
  compare with ``fault_throw``.

Construction (after Wu et al., 2019, FaultSeg3D)
------------------------------------------------
1. A 1D random reflectivity series in relative geologic time (RGT, samples): uniform values in [-1, 1] kept with
   probability 0.6 (sparse-ish), plus one strong spike (|r| = 2.5, random sign, neighbours within 4 samples damped
   to a quarter) per chosen horizon.
2. Folding: vertical shift ``s(x, z) = (0.5 + z / n_samples) * G(x) + P(x)`` with ``G`` a sum of 3-6 Gaussian bumps
   and ``P`` a plane, scaled so the steepest reflector dips ``max_dip`` (default 20 degrees); RGT = z + s.
3. Faults, oldest first: planar dip-slip faults through a random point in the middle half of the cube, strike 0-360,
   dip 55-80 degrees, throw varying linearly along strike between two random values in [3, ``max_throw``].
   Younger faults offset older ones. New faults are placed at least ~12% of the lateral size away from earlier,
   near-parallel faults (faults at more than 30 degrees to each other may cross).
4. All warps are applied to coordinates (each output voxel is mapped back through the faults, youngest first, then
   through the folding to its RGT), so the ground truth is exact; the reflectivity is sampled at each voxel's RGT
   with linear interpolation, convolved along the sample axis with a Ricker wavelet of peak frequency
   ``peak_frequency`` (cycles per sample; 0.15 gives a ~6.7-sample period), scaled to unit standard deviation, and
   white Gaussian noise of standard deviation ``noise`` is added.

References
----------
Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Using synthetic data sets to train an end-to-end
convolutional neural network for 3D seismic fault segmentation: Geophysics, 84(3), IM35-IM45.
doi:10.1190/geo2018-0646.1

Hale, D., 2014, Fault surfaces and fault throws from 3D seismic images: Geophysics, 79(5), O53-O66 (ground-truth
conventions for throw). doi:10.1190/geo2013-0270.1
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import convolve1d

from .._validation import check_int, check_positive
from ..errors import InputError
from .synthetic_geology import MIN_THROW, FaultPlane, draw_faults, draw_folding

__all__ = ["FaultPlane", "SyntheticCube", "synthetic_cube", "ricker", "write_segy_cube"]

_MIN_SIZE = 16


@dataclass(frozen=True, eq=False)
class SyntheticCube:
    """A synthetic seismic cube or section with its ground truth (see :func:`synthetic_cube`).

    Attributes
    ----------
    cube : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) float32 ndarray
        ``clean`` plus white Gaussian noise.
    clean : same shape, float32 ndarray
        Noise-free image, unit standard deviation.
    fault_labels : same shape, int16 ndarray
        0 off faults, k on fault ``faults[k - 1]``: a surface one voxel thick along the axis most perpendicular to
        the fault (voxel centres within [-0.5, 0.5) voxel of the plane along that axis), without holes. Where faults
        cross, the younger (higher id) wins; an older fault offset by a younger one consists of pieces, each one
        voxel thick, that may overlap when seen along that axis.
    fault_throw : same shape, float32 ndarray
        Vertical throw (samples, >= 3) at fault voxels, NaN elsewhere.
    faults : tuple of FaultPlane
    horizons : (n_horizons, n_inlines, n_xlines) or (n_horizons, n_traces) float32 ndarray
        Fractional sample position of each horizon after folding and faulting; NaN where it is above or below the
        cube or cut out by a fault within the trace. Sorted from shallow to deep.
    horizon_polarity : (n_horizons,) int8 ndarray
        +1 where the horizon is a peak (maximum) of the image, -1 where it is a trough.
    rgt : same shape as ``cube``, float32 ndarray
        Relative geologic time: each voxel's depth (samples) before folding and faulting; horizon k is the
        iso-surface ``rgt == horizon_rgt[k]``.
    horizon_rgt : (n_horizons,) float64 ndarray
    peak_frequency : float
        Ricker peak frequency, cycles per sample.
    noise_std : float
        Standard deviation of the added noise (the image's ``clean`` has standard deviation 1).
    """

    cube: np.ndarray
    clean: np.ndarray
    fault_labels: np.ndarray
    fault_throw: np.ndarray
    faults: tuple
    horizons: np.ndarray
    horizon_polarity: np.ndarray
    rgt: np.ndarray
    horizon_rgt: np.ndarray
    peak_frequency: float
    noise_std: float

    @property
    def shape(self) -> tuple:
        return self.cube.shape


def ricker(peak_frequency: float, half_length: int | None = None) -> np.ndarray:
    """Zero-phase Ricker wavelet sampled at integer samples.

    Parameters
    ----------
    peak_frequency : float
        Peak frequency in cycles per sample (0 < f < 0.5); e.g. 25 Hz at 4 ms is 0.1.
    half_length : int, optional
        The wavelet has ``2 * half_length + 1`` samples; default ``ceil(1.5 / peak_frequency)``.

    Returns
    -------
    wavelet : (2 * half_length + 1,) float64 ndarray
        ``(1 - 2 (pi f t)^2) exp(-(pi f t)^2)``, peak 1 at the centre.
    """
    f = check_positive(peak_frequency, "peak_frequency")
    if f >= 0.5:
        raise InputError(f"peak_frequency={peak_frequency} cycles per sample is at or above Nyquist (0.5); use < 0.5")
    h = int(np.ceil(1.5 / f)) if half_length is None else int(half_length)
    a = (np.pi * f * np.arange(-h, h + 1)) ** 2
    return (1.0 - 2.0 * a) * np.exp(-a)


def _check_shape(shape) -> tuple:
    try:
        shp = tuple(int(s) for s in shape)
        ok = len(shp) in (2, 3) and all(int(s) == s for s in shape)
    except (TypeError, ValueError) as exc:
        raise InputError(f"shape must be a tuple of 2 or 3 ints; got {shape!r}") from exc
    if not ok:
        raise InputError(f"shape must have 2 (n_traces, n_samples) or 3 (n_inlines, n_xlines, n_samples) ints; "
                         f"got {shape!r}")
    if min(shp) < _MIN_SIZE:
        raise InputError(f"every axis of shape must be >= {_MIN_SIZE}; got {shp}")
    return shp


def synthetic_cube(shape=(128, 128, 128), *, n_faults: int = 3, seed=0, noise: float = 0.1,
                   max_throw: float = 8.0, n_horizons: int = 6, peak_frequency: float = 0.15,
                   max_dip: float = 20.0, reverse_fraction: float = 0.5) -> SyntheticCube:
    """Generate a folded, faulted synthetic seismic cube (or 2D section) with exact ground truth.

    See the module docstring (:mod:`seismo3d.data.synthetic`) for the index-space conventions (axes, strike, dip,
    normal, throw) and the construction.

    Parameters
    ----------
    shape : tuple of int
        ``(n_inlines, n_xlines, n_samples)`` for a cube, ``(n_traces, n_samples)`` for a 2D section; each >= 16.
    n_faults : int
        Number of planar faults (>= 0).
    seed : int or None
        Seed of the ``numpy.random.Generator``; the same seed gives the same output. None draws fresh entropy.
    noise : float
        Standard deviation of the white Gaussian noise relative to that of the noise-free image (>= 0).
    max_throw : float
        Largest vertical throw in samples (>= 3); throws are drawn in [3, max_throw].
    n_horizons : int
        Number of horizons to record (at most; fewer if the cube is too thin to keep them 10 samples apart).
    peak_frequency : float
        Ricker peak frequency in cycles per sample (0.1-0.2 is typical: 25-50 Hz at 4 ms).
    max_dip : float
        Steepest reflector dip produced by folding, degrees (the folding draws a value in [0.6, 1] * max_dip).
    reverse_fraction : float
        Probability that a fault is reverse rather than normal, in [0, 1].

    Returns
    -------
    SyntheticCube
        ``cube``, ``clean``, ``fault_labels`` (int16), ``fault_throw``, ``faults``, ``horizons``,
        ``horizon_polarity``, ``rgt``, ... (see :class:`SyntheticCube`).

    Raises
    ------
    InputError
        A shape that is not 2 or 3 ints >= 16, or an out-of-range parameter.

    References
    ----------
    Wu, X., Liang, L., Shi, Y., and Fomel, S., 2019, FaultSeg3D: Geophysics, 84(3), IM35-IM45.
    doi:10.1190/geo2018-0646.1

    Examples
    --------
    >>> syn = synthetic_cube((64, 64, 64), n_faults=2, seed=1)
    >>> syn.cube.shape, int(syn.fault_labels.max()), len(syn.faults)
    ((64, 64, 64), 2, 2)
    """
    shp = _check_shape(shape)
    check_int(n_faults, "n_faults", minimum=0)
    check_int(n_horizons, "n_horizons", minimum=0)
    noise = check_positive(noise, "noise", allow_zero=True)
    max_throw = check_positive(max_throw, "max_throw")
    if max_throw < MIN_THROW:
        raise InputError(f"max_throw must be >= {MIN_THROW} samples (throws are drawn in [3, max_throw]); "
                         f"got {max_throw}")
    if max_throw > shp[-1] / 4:
        raise InputError(f"max_throw={max_throw} is more than a quarter of n_samples={shp[-1]}; "
                         "use a smaller max_throw or more samples")
    wavelet = ricker(peak_frequency)
    max_dip = check_positive(max_dip, "max_dip")
    if max_dip >= 45.0:
        raise InputError(f"max_dip must be < 45 degrees so that folding does not overturn layers; got {max_dip}")
    reverse_fraction = check_positive(reverse_fraction, "reverse_fraction", allow_zero=True)
    if reverse_fraction > 1:
        raise InputError(f"reverse_fraction is a probability in [0, 1]; got {reverse_fraction}")
    check_int(seed, "seed", minimum=0, allow_none=True)

    rng = np.random.default_rng(seed)
    lat_shape, nz = shp[:-1], shp[-1]
    fold = draw_folding(rng, lat_shape, nz, max_dip)
    faults = draw_faults(rng, int(n_faults), lat_shape, nz, max_throw, reverse_fraction)

    # Map every voxel of the output grid (padded vertically for the wavelet) back to its RGT, in slabs of inlines
    # (every voxel is independent) to keep temporaries small.
    pad = (wavelet.size - 1) // 2
    nzp = nz + 2 * pad
    slabs = _slabs(lat_shape, nzp)
    rgt = np.empty((*lat_shape, nzp), np.float32)
    labels = np.empty(shp, np.int16)
    throw = np.empty(shp, np.float32)
    for i0, i1 in slabs:
        rgt[i0:i1], lab, thr = _map_slab(i0, i1, lat_shape, nzp, pad, faults, fold, max_throw)
        labels[i0:i1] = lab[..., pad:pad + nz]
        throw[i0:i1] = thr[..., pad:pad + nz]

    # Horizons: RGT levels evenly spread inside the cube, each a strong isolated spike in the reflectivity.
    inner = rgt[..., pad:pad + nz]
    top = float(np.max(inner[..., 0]))
    bottom = float(np.min(inner[..., -1]))
    margin = max(4.0, 0.05 * nz)
    lo, hi = top + margin, bottom - margin
    if hi <= lo:
        lo, hi = float(np.percentile(inner[..., 0], 90)) + margin, float(np.percentile(inner[..., -1], 10)) - margin
    n_h = int(min(n_horizons, max(0, np.floor((hi - lo) / 10.0) + 1))) if hi > lo else 0
    r0 = int(np.floor(rgt.min())) - 2
    r1 = int(np.ceil(rgt.max())) + 2
    refl = rng.uniform(-1.0, 1.0, r1 - r0 + 1) * (rng.random(r1 - r0 + 1) < 0.6)
    h_rgt = np.round(np.linspace(lo, hi, n_h)) if n_h else np.zeros(0)
    polarity = rng.choice(np.array([-1, 1], np.int8), size=n_h)
    for level, sign in zip(h_rgt, polarity):
        i = int(level) - r0
        refl[max(i - 4, 0):i + 5] *= 0.25
        refl[i] = 2.5 * sign

    # Reflectivity at each voxel's RGT, then the wavelet along the sample axis (in the output grid).
    clean = np.empty(shp, np.float32)
    grid = np.arange(r0, r1 + 1, dtype=np.float64)
    for i0, i1 in slabs:
        img = np.interp(rgt[i0:i1], grid, refl).astype(np.float32)
        img = convolve1d(img, wavelet.astype(np.float32), axis=-1, mode="nearest")
        clean[i0:i1] = img[..., pad:pad + nz]
    clean /= np.float32(clean.std())
    noise_std = float(noise)
    cube = clean + rng.standard_normal(clean.shape, dtype=np.float32) * np.float32(noise_std) if noise_std > 0 \
        else clean.copy()

    rgt = np.ascontiguousarray(inner)
    horizons = _horizon_positions(rgt, h_rgt)
    return SyntheticCube(cube=cube, clean=clean, fault_labels=labels, fault_throw=throw, faults=tuple(faults),
                         horizons=horizons, horizon_polarity=polarity, rgt=rgt, horizon_rgt=h_rgt.astype(np.float64),
                         peak_frequency=float(peak_frequency), noise_std=noise_std)


def _slabs(lat_shape, nzp, target=1 << 19):
    """Ranges of axis-0 indices holding about ``target`` voxels each."""
    per_row = int(np.prod(lat_shape[1:], dtype=np.int64)) * nzp
    step = max(1, target // per_row)
    return [(i, min(i + step, lat_shape[0])) for i in range(0, lat_shape[0], step)]


def _map_slab(i0, i1, lat_shape, nzp, pad, faults, fold, max_throw):
    """RGT, fault labels and throws of the voxels with axis-0 index in [i0, i1) (padded sample axis)."""
    d = len(lat_shape) + 1
    full = (i1 - i0, *lat_shape[1:], nzp)
    axes = [np.arange(i0, i1, dtype=np.float32)] + [np.arange(n, dtype=np.float32) for n in lat_shape[1:]]
    axes.append(np.arange(nzp, dtype=np.float32) - pad)
    coords = [np.broadcast_to(ax.reshape([-1 if i == a else 1 for i in range(d)]), full).copy()
              for a, ax in enumerate(axes)]
    labels = np.zeros(full, np.int16)
    throw = np.full(full, np.nan, np.float32)
    for f in reversed(faults):  # youngest first: undo its slip, then the older faults'
        sd = sum((c - p) * n for c, p, n in zip(coords, f.point.tolist(), f.normal.tolist()))
        a = int(np.argmax(np.abs(f.normal)))
        dist = sd * (1.0 / float(f.normal[a]))  # signed distance to the plane along axis a
        if d == 3:
            s0, s1 = f.strike_vector[:2].tolist()
            u = (coords[0] - float(f.point[0])) * s0 + (coords[1] - float(f.point[1])) * s1
            t = np.clip(u * f.throw_gradient + f.throw_samples, MIN_THROW, max_throw)
        else:
            t = np.full(full, f.throw_samples, np.float32)
        on = (dist >= -0.5) & (dist < 0.5) & (labels == 0)
        labels[on] = f.id
        throw[on] = t[on]
        hw = sd > 0
        for c, v in zip(coords, f.slip_vector.tolist()):
            if v != 0:
                c -= np.where(hw, t * v, np.float32(0))
    z = coords[-1]
    rgt = z + fold(coords[:-1], z)
    return rgt, labels, throw


def _horizon_positions(rgt: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """First downward crossing of each RGT level per trace, linearly interpolated; NaN outside or in a fault gap."""
    nz = rgt.shape[-1]
    out = np.full((levels.size, *rgt.shape[:-1]), np.nan, np.float32)
    step = np.diff(rgt, axis=-1)  # (..., nz - 1): rgt[k + 1] - rgt[k]
    for h, level in enumerate(levels):
        above = rgt >= level
        k1 = np.argmax(above, axis=-1)
        valid = above.any(axis=-1) & (k1 > 0)
        k1c = np.clip(k1, 1, nz - 1)[..., None]
        lo = np.take_along_axis(rgt, k1c - 1, axis=-1)[..., 0]
        hi = np.take_along_axis(rgt, k1c, axis=-1)[..., 0]
        jump = hi - lo
        # the normal RGT step next to the crossing (above and below); a much larger step is a fault gap
        prev = np.take_along_axis(step, np.clip(k1c - 2, 0, nz - 2), axis=-1)[..., 0]
        nxt = np.take_along_axis(step, np.clip(k1c, 0, nz - 2), axis=-1)[..., 0]
        ref = np.maximum(np.where(k1 >= 2, prev, 0), np.where(k1 <= nz - 2, nxt, 0))
        valid &= jump <= 1.5 * ref
        pos = (k1c[..., 0] - 1) + (level - lo) / np.where(jump > 0, jump, 1)
        out[h][valid] = pos[valid]
    return out


def write_segy_cube(path, cube, *, sorting: str = "inline", fmt: int = 5):
    """Write a generated cube as a 3D SEG-Y with a survey's headers, for tests and benchmarks of SEG-Y inputs.

    Inlines are numbered from 101, crosslines from 20 every 2nd, the sample interval is 4 ms, and CDP X / Y (trace
    bytes 181 / 185) are in centimetres with coordinate scalar -100. A cube with one inline or crossline is a 2D line.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (replaced if it exists).
    cube : (n_inlines, n_xlines, n_samples) float ndarray
        Amplitudes.
    sorting : {'inline', 'crossline'}
        Trace order of the file.
    fmt : int
        SEG-Y sample format code (5 IEEE float, 1 IBM float).

    Returns
    -------
    path
        As given.
    """
    import segyio

    n_il, n_xl, ns = np.shape(cube)
    spec = segyio.spec()
    spec.format = fmt
    spec.samples = np.arange(ns) * 4.0
    spec.sorting = 2 if sorting == "inline" else 1
    spec.ilines, spec.xlines = np.arange(101, 101 + n_il), np.arange(20, 20 + 2 * n_xl, 2)
    order = ([(i, j) for i in range(n_il) for j in range(n_xl)] if sorting == "inline"
             else [(i, j) for j in range(n_xl) for i in range(n_il)])
    with segyio.create(str(path), spec) as f:
        f.text[0] = segyio.tools.wrap("C 1 seismo3d generated cube")
        for t, (i, j) in enumerate(order):
            f.header[t] = {segyio.su.iline: 101 + i, segyio.su.xline: 20 + 2 * j, segyio.su.scalco: -100,
                           segyio.su.cdpx: 60_500_000 + 2500 * i + 7 * j, segyio.su.cdpy: 607_300_000 + 2500 * j}
            f.trace[t] = cube[i, j]
        f.bin.update(hdt=4000, hns=ns)
    return path
