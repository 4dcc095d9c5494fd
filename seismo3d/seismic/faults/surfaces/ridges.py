"""Ridges of a fault image: thinning fault likelihood (or votes) to 1-sample-wide traces, after Hale 2013.

- :func:`ridge_image`: non-maximum suppression across the fault plane (the ridges, the voting's seeds);
- :func:`thin_faults`: the ridges thresholded by hysteresis from the data (Otsu on the ridge values);
- the pipeline's steps on them (:func:`live_likelihood`, :func:`ridges`, :func:`without_dead_edges`,
  :func:`thin_votes`) and their blocks in a run by blocks (:func:`ridge_block`, :func:`thin_block`,
  :func:`cell_block`).

Conventions (strike, dip, normals, index space) are those of :mod:`seismo3d.seismic.faults.likelihood.scan`.
"""

from __future__ import annotations

import functools
import math

import numba as nb
import numpy as np

from ...._threads import run_threads
from ...._validation import check_core, check_positive
from ....errors import InputError
from ... import _kernels
from ...attributes import structure_tensor_halo, structure_tensor_slopes
from ...blocks.apply import BlockOutput
from ...blocks.statistics import otsu
from ..result import check_fault_arrays
from ...amplitudes import dead_samples, near_dead_samples

__all__ = ["RIDGE_HALO", "THIN_HALO", "amplitude_halo", "cell_block", "thin_faults", "live_likelihood", "ridge_block",
           "ridges", "thin_block", "thin_votes", "without_dead_edges"]

# Lateral halo of the ridges (thin_faults with its defaults): the Gaussian of sigma 1.5 (5 traces), the average along
# the dip over +-4 samples on planes steeper than 45 degrees (4 traces, +1 for the bilinear reads), and the
# comparison one sample across the fault (+1, +1 for the trilinear reads).
RIDGE_HALO = 12
# Lateral halo of the thinning of the votes (no smoothing): one sample across the fault, trilinear reads.
THIN_HALO = 2


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _trilinear(f, x, y, z):
    # compiled once and called from _ridges' two reads (inlined there by numba it compiled twice: 0.4-0.9 CPU s more
    # on a first run); math.floor of the clamped position, not int(): int() compiled a function of numba's
    n0, n1, n2 = f.shape
    x = min(max(x, 0.0), n0 - 1.0)
    y = min(max(y, 0.0), n1 - 1.0)
    z = min(max(z, 0.0), n2 - 1.0)
    i = min(math.floor(x), n0 - 2) if n0 > 1 else 0
    j = min(math.floor(y), n1 - 2) if n1 > 1 else 0
    k = min(math.floor(z), n2 - 2) if n2 > 1 else 0
    u = x - i
    v = y - j
    w = z - k
    i1 = i + 1 if n0 > 1 else i
    j1 = j + 1 if n1 > 1 else j
    k1 = k + 1 if n2 > 1 else k
    f0 = (1 - v) * ((1 - w) * f[i, j, k] + w * f[i, j, k1]) + v * ((1 - w) * f[i, j1, k] + w * f[i, j1, k1])
    f1 = (1 - v) * ((1 - w) * f[i1, j, k] + w * f[i1, j, k1]) + v * ((1 - w) * f[i1, j1, k] + w * f[i1, j1, k1])
    return (1 - u) * f0 + u * f1


_LUT_STEP = 4  # angular resolution 1/4 degree of the normal / dip-vector lookup table used by the thinning


@functools.lru_cache(maxsize=1)
def _direction_lut() -> np.ndarray:
    """(1440, 361, 6) float32 table of (normal, dip vector) for strike, dip on a 1/4-degree grid (computed once: 40 ms,
    called by every block's ridges and thinning; read only)."""
    phi = np.radians(np.arange(360 * _LUT_STEP) / _LUT_STEP)[:, None]
    theta = np.radians(np.arange(90 * _LUT_STEP + 1) / _LUT_STEP)[None, :]
    sp, cp, st, ct = np.sin(phi), np.cos(phi), np.sin(theta), np.cos(theta)
    out = np.stack(np.broadcast_arrays(st * sp, -st * cp, ct + 0 * sp, -ct * sp, ct * cp, st + 0 * sp), axis=-1)
    return out.astype(np.float32)


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _lut_index(strike_deg, dip_deg, n_phi, n_theta):
    i = math.floor(strike_deg * _LUT_STEP + 0.5) % n_phi
    j = min(max(math.floor(dip_deg * _LUT_STEP + 0.5), 0), n_theta - 1)
    return i, j


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _bilinear01(f, x, y, k):
    # bilinear interpolation of f[:, :, k] at (x, y), clamped to the array
    n0, n1, _ = f.shape
    x = min(max(x, 0.0), n0 - 1.0)
    y = min(max(y, 0.0), n1 - 1.0)
    i = min(math.floor(x), n0 - 2) if n0 > 1 else 0
    j = min(math.floor(y), n1 - 2) if n1 > 1 else 0
    u = x - i
    v = y - j
    i1 = i + 1 if n0 > 1 else i
    j1 = j + 1 if n1 > 1 else j
    return (1 - u) * ((1 - v) * f[i, j, k] + v * f[i, j1, k]) + u * ((1 - v) * f[i1, j, k] + v * f[i1, j1, k])


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _smooth_along_dip(t, n_threads, f, strike, dip, lut, h, need, box, out):
    # Average f along the dip of each sample's fault plane, one sample per step down (the fault is steeper than
    # 45 degrees in the scan, so the dip vector has its largest component along the sample axis): triangle weights
    # over +-h samples, bilinear interpolation across. Joins fault ridges broken by noise before thinning. Computed
    # on the traces box = (i0, i1, j0, j1) where need (the box's shape) is True, 0 elsewhere in the box (out is f's
    # shape; the reads are f's, whatever the box). A sample without strike and dip (NaN: the learned likelihood
    # below its orientation floor) keeps f. Inlines i0 + t, i0 + t + n_threads, ...
    n0, n1, n2 = f.shape
    n_phi, n_theta, _ = lut.shape
    i0, i1, j0, j1 = box
    for i in range(i0 + t, i1, n_threads):
        for j in range(j0, j1):
            for k in range(n2):
                if not need[i - i0, j - j0, k]:
                    out[i, j, k] = 0.0
                    continue
                if math.isnan(strike[i, j, k]) or math.isnan(dip[i, j, k]):
                    out[i, j, k] = f[i, j, k]
                    continue
                ip, it = _lut_index(strike[i, j, k], dip[i, j, k], n_phi, n_theta)
                c = max(lut[ip, it, 5], 1e-3)
                a = lut[ip, it, 3] / c
                b = lut[ip, it, 4] / c
                acc = 0.0
                wsum = 0.0
                for p in range(-h, h + 1):
                    z = k + p
                    if z < 0 or z > n2 - 1:
                        continue
                    x = i + p * a
                    y = j + p * b
                    if x < 0 or y < 0 or x > n0 - 1 or y > n1 - 1:
                        continue
                    w = h + 1.0 - abs(p)
                    acc += w * _bilinear01(f, x, y, z)
                    wsum += w
                out[i, j, k] = acc / wsum if wsum > 0 else f[i, j, k]


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _ridges(t, n_threads, f, g, strike, dip, lut, floor, box, out):
    # Non-maximum suppression of g across the fault: keep f where g(p) > g(p - n) and g(p) >= g(p + n), n the unit
    # fault normal of the sample (trilinear interpolation); samples with f <= floor, or without strike and dip (NaN:
    # the learned likelihood below its orientation floor), are 0 (not tested). On the traces box = (i0, i1, j0, j1)
    # only, into out (the box's shape; the reads are g's, whatever the box). Inlines i0 + t, i0 + t + n_threads, ...
    n0, n1, n2 = f.shape
    n_phi, n_theta, _ = lut.shape
    i0, i1, j0, j1 = box
    for i in range(i0 + t, i1, n_threads):
        for j in range(j0, j1):
            for k in range(n2):
                if not f[i, j, k] > floor or math.isnan(strike[i, j, k]) or math.isnan(dip[i, j, k]):
                    out[i - i0, j - j0, k] = 0.0
                    continue
                ip, it = _lut_index(strike[i, j, k], dip[i, j, k], n_phi, n_theta)
                a = lut[ip, it, 0]
                b = lut[ip, it, 1]
                c = lut[ip, it, 2]
                gc = g[i, j, k]
                gp = _trilinear(g, i + a, j + b, k + c)
                gm = _trilinear(g, i - a, j - b, k - c)
                out[i - i0, j - j0, k] = f[i, j, k] if (gc > gm and gc >= gp) else 0.0


def _grown(mask: np.ndarray) -> np.ndarray:
    """``mask`` (bool ndarray) grown by one sample along every axis, its edges clamped: what
    ``scipy.ndimage.maximum_filter(mask, size=3, mode='nearest')`` gives (a sample is True when one of its 3 x 3 x 3
    neighbourhood is), as two shifted ORs per axis: on the mask of the generated 256^3 cube 0.03 CPU s against
    scipy's 0.30 (its running maximum of a window, over bytes)."""
    out = mask
    for axis in range(mask.ndim):
        src, out = out, out.copy()
        ahead = tuple(slice(1, None) if a == axis else slice(None) for a in range(mask.ndim))
        behind = tuple(slice(None, -1) if a == axis else slice(None) for a in range(mask.ndim))
        out[ahead] |= src[behind]
        out[behind] |= src[ahead]
    return out


def ridge_image(likelihood, strike, dip, *, floor=-1.0, sigma=1.5, dip_smoothing=4, core=None) -> np.ndarray:
    """Steps 1-2 of :func:`thin_faults` (ranking image, non-maximum suppression across the fault), on the samples
    whose likelihood is above ``floor`` only.

    The ranking image is computed only where a ridge test above ``floor`` reads it (the 3 x 3 x 3 neighbourhood of
    those samples: the test reads it one sample away along the unit normal), so the ridges above ``floor`` are those
    of the whole image, bit for bit, at a fraction of the cost when few samples are above it.

    Parameters
    ----------
    likelihood, strike, dip : float32 ndarray, one shape
        Checked by :func:`check_fault_arrays` (2D sections or 3D cubes). Where strike or dip is NaN (the learned
        likelihood below its orientation floor) the sample is not a ridge (0) and the ranking image there is not
        averaged along the dip.
    floor : float
        Samples with a likelihood at or below it (compared in float64) are 0 in the result (default: none, a
        likelihood is >= 0). Whether a caller then keeps the values above a threshold ``t`` in float32 or in float64,
        ``floor=t`` tests every sample it keeps.
    sigma, dip_smoothing : float, int
        As in :func:`thin_faults`.
    core : (slice, slice), optional
        A cube's inlines and crosslines whose ridges are returned, e.g. a block's core inside the region read with
        ``RIDGE_HALO`` around it: the Gaussian over the whole array (the average along the dip reads it anywhere),
        the average along the dip and the ridge test at ``core`` and the 2 traces around it that the test reads,
        the same bits as ``ridge_image(...)[rows, cols]``.

    Returns
    -------
    ndarray of the likelihood's shape (of ``likelihood[core]``'s when given), float32
        The likelihood on its ridge samples above ``floor``, 0 elsewhere.

    Raises
    ------
    InputError
        If ``core`` is given for a 2D section, is not two slices of step 1 or selects no trace of the cube.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (thinning of fault images).
    """
    two_d = likelihood.ndim == 2
    f3 = np.ascontiguousarray(_kernels.as_3d(likelihood))  # C order: one compiled signature of the kernels below
    n0, n1 = f3.shape[:2]
    i0, i1, j0, j1 = (0, n0, 0, n1) if core is None else check_core(core, likelihood.shape)
    st3 = np.ascontiguousarray(_kernels.as_3d(strike))
    dp3 = np.ascontiguousarray(_kernels.as_3d(dip))
    floor = float(floor)
    lut = _direction_lut()
    g = f3
    # the ranking image's Gaussian summed in float32 by OpenCV (gaussian_pass32: each output's arithmetic its own,
    # whatever the block; within 2e-7 of scipy's float64 passes): 0.16-0.19 against 0.58-0.85 CPU s on the generated
    # 256^3 cube, the same ridges there
    for axis, width in enumerate((sigma, 0.0 if two_d else sigma, sigma) if sigma > 0 else ()):
        g = _kernels.gaussian_pass32(g, axis, float(width))
    n_threads = nb.get_num_threads()
    if dip_smoothing > 0:
        # the ranking image where the ridge test of the core reads it: the trilinear reads one sample away along the
        # normal read 2 traces away at most; only where a test above floor reads it: some sample of its 3 x 3 x 3
        # neighbourhood has a likelihood above floor (the maximum filter's edges clamped as on the whole array; of the
        # samples above floor, a bool array: the same mask as the likelihood's maximum above floor, at half the time)
        box = (max(i0 - 2, 0), min(i1 + 2, n0), max(j0 - 2, 0), min(j1 + 2, n1))
        a0, a1, b0, b1 = max(box[0] - 1, 0), min(box[1] + 1, n0), max(box[2] - 1, 0), min(box[3] + 1, n1)
        need = _grown(f3[a0:a1, b0:b1] > np.float64(floor))
        need = np.ascontiguousarray(need[box[0] - a0:box[1] - a0, box[2] - b0:box[3] - b0])
        g2 = np.zeros(f3.shape, f3.dtype)  # read in the box only (np.zeros, not zeros_like: no pass writing 0 first)
        run_threads(_smooth_along_dip, n_threads, g, st3, dp3, lut, int(dip_smoothing), need, box, g2)
        del need
        g = g2
    ridge = np.empty((i1 - i0, j1 - j0, f3.shape[2]), f3.dtype)
    run_threads(_ridges, n_threads, f3, g, st3, dp3, lut, floor, (i0, i1, j0, j1), ridge)
    del g
    return ridge[:, 0, :] if two_d else ridge


def thin_faults(likelihood, strike, dip, *, threshold=None, sigma=1.5, dip_smoothing=4) -> np.ndarray:
    """Thin fault likelihood to 1-sample-wide fault traces.

    1. Ranking image: the likelihood smoothed with a Gaussian of width ``sigma``, then averaged along the dip of
       each sample's fault plane (triangle weights over +-``dip_smoothing`` samples), which joins fault ridges broken
       by noise. It is used only to rank neighbours; the returned values are the input likelihood.
    2. Non-maximum suppression across the fault: a sample is kept when its ranking value exceeds the values one
       sample away on both sides along its fault normal (trilinear interpolation) (Hale 2013).
    3. Hysteresis threshold (Canny 1986) on the ridge samples' likelihood: samples above the upper threshold seed
       faults that grow through 26-connected (8 in 2D) ridge samples above the lower threshold.

    With ``threshold=None`` both thresholds come from the data: the lower one is Otsu's threshold of the ridge
    samples' likelihood (it separates fault ridges from the lower ridges of noise and of the scan's side lobes) and
    the upper one is half-way between it and 1. The same defaults are used on synthetic and real data.

    Parameters
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Fault likelihood in [0, 1] (``FaultLikelihood.likelihood``).
    strike, dip : array_like of float, same shape
        Fault strike and dip in degrees (``FaultLikelihood.strike_deg``, ``.dip_deg``).
    threshold : float or (float, float), optional
        Fixed likelihood thresholds instead of the data-driven ones: one value for both, or (lower, upper).
    sigma : float, optional
        Width of the isotropic Gaussian of the ranking image, in samples (0 for none).
    dip_smoothing : int, optional
        Half-length of the average along dip of the ranking image, in samples (0 for none).

    Returns
    -------
    (*likelihood.shape) float32 ndarray
        The likelihood on the thinned fault samples, 0 elsewhere.

    Raises
    ------
    InputError
        If the shapes differ, the likelihood has NaN or a threshold is out of range.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (thinning of fault images).
    .. [2] N. Otsu, "A threshold selection method from gray-level histograms", IEEE Trans. SMC 9(1), 1979,
       doi:10.1109/TSMC.1979.4310076.
    .. [3] J. Canny, "A computational approach to edge detection", IEEE TPAMI 8(6), 1986,
       doi:10.1109/TPAMI.1986.4767851.
    """
    from skimage.filters import apply_hysteresis_threshold

    fl, st, dp = check_fault_arrays(likelihood, strike, dip)
    sigma = check_positive(sigma, "sigma", allow_zero=True)
    along = int(check_positive(dip_smoothing, "dip_smoothing", allow_zero=True))
    if threshold is not None:
        thr = np.atleast_1d(np.asarray(threshold, dtype=np.float64)).ravel()
        if thr.size not in (1, 2) or not np.all((thr >= 0) & (thr <= 1)) or thr[0] > thr[-1]:
            raise InputError(f"threshold must be a likelihood in [0, 1] or a pair (lower <= upper); got {threshold!r}")
    # no sample at or below a fixed lower threshold is kept (the hysteresis compares in float64, as the ridge test's
    # floor): its ridge test is skipped
    floor = -1.0 if threshold is None else float(thr[0])
    ridge = ridge_image(fl, st, dp, floor=floor, sigma=sigma, dip_smoothing=along)
    if threshold is None:
        lo = otsu(ridge[ridge > 0])
        hi = 0.5 * (lo + 1.0)
    else:
        lo, hi = float(thr[0]), float(thr[-1])
    keep = apply_hysteresis_threshold(ridge, lo, hi) & (ridge > 0)
    return np.where(keep, fl, 0.0).astype(np.float32)


def live_likelihood(likelihood: np.ndarray, near_dead, core=None, *, level: float) -> tuple[int, int]:
    """Set the likelihood next to dead samples to 0 (the edge of a dead zone is not a fault), in place; count the
    saturated and the live samples of ``core`` for :func:`~seismo3d.seismic.faults.steps.check_saturation`.

    Parameters
    ----------
    likelihood : float32 ndarray
        Fault likelihood of an array or of a block with its halo; modified.
    near_dead : bool ndarray of the same shape, or None
        Samples near dead ones (:func:`~seismo3d.seismic.amplitudes.near_dead_samples`); None: none.
    core : tuple of slice, optional
        The block's core within ``likelihood`` (default: all of it).
    level : float
        A likelihood above it counts as saturated (``FaultTracingOptions.saturation_level``).

    Returns
    -------
    (int, int)
        Live samples of the core with a likelihood above ``level``, and live samples of the core.
    """
    core = core or (slice(None),)
    if near_dead is not None:
        likelihood[near_dead] = 0.0
    values = likelihood[core] if near_dead is None else likelihood[core][~near_dead[core]]
    return int(np.count_nonzero(values > level)), int(values.size)


def ridges(likelihood: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray, floor: float = 0.0,
           core=None) -> np.ndarray:
    """The ridges of the fault likelihood (non-maximum suppression across the fault, smoothed): the voting's seed
    candidates.

    Parameters
    ----------
    likelihood, strike_deg, dip_deg : ndarray, one shape, float32
        The (live) fault likelihood, its strike and dip in degrees.
    floor : float
        Ridge samples with a likelihood at or below it are left out (0): pass the voting's seed threshold, the
        only ridges used (:attr:`~seismo3d.seismic.faults.VotingOptions.seed_threshold`); the ridges above it are
        those of :func:`~seismo3d.seismic.thin_faults` with ``threshold=0``, computed on their neighbourhood only.
    core : (slice, slice), optional
        A cube's inlines and crosslines whose ridges are returned (:func:`ridge_image`): a block's core with
        ``RIDGE_HALO`` traces of the likelihood around it.

    Returns
    -------
    ndarray of the likelihood's shape (of ``likelihood[core]``'s when given), float32
        The likelihood on its ridge samples above ``floor``, 0 elsewhere. Halo: ``RIDGE_HALO`` traces.

    Raises
    ------
    InputError
        If the arrays' shapes differ, the likelihood has NaN, or ``core`` is bad (:func:`ridge_image`).
    """
    fl, st, dp = check_fault_arrays(likelihood, strike_deg, dip_deg)
    return ridge_image(fl, st, dp, floor=float(floor), core=core)


def without_dead_edges(votes: np.ndarray, near_dead) -> np.ndarray:
    """The votes set to 0 near dead samples, in place: voting surfaces bridge gaps, but a fault is not drawn across
    dead traces. ``near_dead``: bool array of the votes' shape, or None (nothing to do)."""
    if near_dead is not None:
        votes[near_dead] = 0.0
    return votes


def thin_votes(votes: np.ndarray, strike_deg: np.ndarray, dip_deg: np.ndarray) -> np.ndarray:
    """The votes thinned to 1-sample-wide faults (no smoothing: the votes are smooth already).

    Halo: ``THIN_HALO`` traces. Arrays of one shape, float32; returns the thinned votes, float32 (0 off the faults).
    """
    fv, st, dp = check_fault_arrays(votes, strike_deg, dip_deg)
    return ridge_image(fv, st, dp, floor=0.0, sigma=0.0, dip_smoothing=0)


# -- one block of a run by blocks (declared in seismo3d.seismic.faults.surfaces.blocks) ---------------------------

def amplitude_halo(opt) -> int:
    """Traces of amplitudes read around a block of :func:`ridge_block`: the dead samples' reach around
    ``RIDGE_HALO``, and the structure tensor's halo for the reflector slopes.

    Parameters
    ----------
    opt : FaultTracingOptions
        Its ``dead`` options (their reach).

    Returns
    -------
    int
        Traces on each lateral side.
    """
    return max(RIDGE_HALO + opt.dead.reach[0], structure_tensor_halo()[0])


def ridge_block(place, f, likelihood, strike, dip, fill, lo: float, hi: float, shape, opt, slopes: bool = True
                ) -> BlockOutput:
    """Reflector slopes, dead samples, live likelihood and ridges of one block (Hale 2013).

    Parameters
    ----------
    place : BlockPlace
        The block's core and the region of ``f``.
    f : (m0, m1, n_samples) ndarray
        Amplitudes of ``place.region``: the block grown by the dead samples' reach around ``RIDGE_HALO`` and by the
        structure tensor's halo (:func:`amplitude_halo`); a section as a cube of one crossline.
    likelihood, strike, dip : (n_inlines, n_xlines, n_samples) arrays read by slicing
        The fault likelihood, strike and dip of the cube, read around the block with ``RIDGE_HALO``; the likelihood
        is set to 0 near dead samples in place when it is an array in memory.
    fill : (k,) float32 ndarray
        Fill values of the dead-sample rules; ``lo``, ``hi`` the cube's smallest and largest amplitudes.
    shape : (int, int, int) or (int, int)
        Of the image: a 2D shape for a section (one block, the whole section, in memory; its ridges those of the
        section, :func:`ridges` in 2D).
    opt : FaultTracingOptions
    slopes : bool
        Compute the reflector slopes of a cube (the throws of a run by blocks read them from its stores; in memory
        they are computed from the amplitudes when a throw needs them); never for a section.

    Returns
    -------
    BlockOutput
        The core's ``slope_inline``, ``slope_xline`` (:func:`structure_tensor_slopes`, as the throws read them in
        memory; None without ``slopes`` or for a section), ``likelihood`` (0 near dead samples) and ``near``
        (uint8; None without dead samples); lists ``points`` (k, 3) int64 (a section's as (trace, 0, sample)),
        ``values`` (k,) float32 and ``angles`` (k, 2) float32 of the ridge samples above the seed threshold (the
        seed candidates); summary ``high``, ``live`` (:func:`live_likelihood`).
    """
    i0, i1, j0, j1 = place.block
    origin = place.origin
    section = len(shape) == 2
    f = np.asarray(f, np.float32)
    arrays = {"slope_inline": None, "slope_xline": None}
    if slopes and not section:
        # the slopes from the amplitudes within the structure tensor's halo of the core (not the dead samples' wider
        # one: 82^2 against 94^2 traces for a 64-trace block), each pass at the lines it feeds, eigen-decomposed at the
        # core only: the same bits, 1.1 against 1.5 CPU s (whole tensor) for a 64 x 64 x 500 block of a 400^2 x 500
        # cube
        halo = structure_tensor_halo()[0]
        crop = tuple(slice(max(s.start - halo, 0), min(s.stop + halo, n)) for s, n in zip(place.core, f.shape[:2]))
        found = structure_tensor_slopes(f[crop], core=tuple(slice(s.start - c.start, s.stop - c.start)
                                                            for s, c in zip(place.core, crop)), float32=True)
        arrays["slope_inline"], arrays["slope_xline"] = found[0], found[1]
        del found
    dead = dead_samples(f, fill, lo, hi, options=opt.dead)
    del f
    near = near_dead_samples(dead, options=opt.dead) if dead.any() else None
    del dead
    n0, n1 = likelihood.shape[:2]
    a0, a1, b0, b1 = max(i0 - RIDGE_HALO, 0), min(i1 + RIDGE_HALO, n0), max(j0 - RIDGE_HALO, 0), min(j1 + RIDGE_HALO, n1)
    fl, st, dp = (a[a0:a1, b0:b1] for a in (likelihood, strike, dip))
    if near is not None:
        near = near[a0 - origin[0]:a1 - origin[0], b0 - origin[1]:b1 - origin[1]]
    core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
    high, live = live_likelihood(fl, near, core, level=opt.saturation_level)
    if section:  # the section's ridges (2D: no smoothing across the one crossline)
        ridge = ridges(fl[:, 0], st[:, 0], dp[:, 0], opt.voting.seed_threshold)[:, None]
    else:  # tested and smoothed along dip at the core
        ridge = ridges(fl, st, dp, opt.voting.seed_threshold, core=core)
    cand = np.argwhere(ridge > float(opt.voting.seed_threshold))
    at = tuple(cand.T)
    local = (cand[:, 0] + i0 - a0, cand[:, 1] + j0 - b0, cand[:, 2])
    candidates = {"points": (cand + np.array([i0, j0, 0])).astype(np.int64), "values": ridge[at].astype(np.float32),
                  "angles": np.stack([st[local], dp[local]], axis=-1).astype(np.float32)}
    arrays.update({"likelihood": fl[core], "near": None if near is None else near[core].view(np.uint8)})
    return BlockOutput(arrays, {"high": high, "live": live}, candidates)


def thin_block(place, votes, strike, dip, shape) -> BlockOutput:
    """Thinned votes of one block (:func:`thin_votes`), and the count, smallest and largest of the positive ones of
    its core (the thresholds' range).

    Parameters
    ----------
    place : BlockPlace
    votes, strike, dip : (m0, m1, n_samples) float32 ndarrays
        Votes and their strike and dip (degrees) over ``place.region``: the block grown by ``THIN_HALO`` (a section
        as a cube of one crossline).
    shape : (int, int, int) or (int, int)
        Of the image: a 2D shape for a section (thinned in 2D).

    Returns
    -------
    BlockOutput
        ``thin_raw``: (core, n_samples) float32; summary ``count``, ``min``, ``max``.
    """
    if len(shape) == 2:  # a section: thinned in 2D
        thin = thin_votes(votes[:, 0], strike[:, 0], dip[:, 0])[:, None]
    else:
        thin = thin_votes(votes, strike, dip)[place.core]
    positive = thin[thin > 0]
    return BlockOutput({"thin_raw": thin}, {"count": int(positive.size),
                                            "min": float(positive.min()) if positive.size else 0.0,
                                            "max": float(positive.max()) if positive.size else 0.0})


def cell_block(place, thin, strike, dip, lower: float) -> BlockOutput:
    """The thinned votes at or above ``lower`` of one block (the others set to 0), and its cells.

    Parameters
    ----------
    place : BlockPlace
    thin, strike, dip : (m0, m1, n_samples) float32 ndarrays
        Thinned votes (modified in place) and the votes' strike and dip (degrees) of the block's core.
    lower : float
        Lower threshold.

    Returns
    -------
    BlockOutput
        ``thin``; lists ``points`` (k, 3) int64 cube indices, ``values``, ``strike``, ``dip`` (k,) float32; summary
        ``count``.
    """
    thin[thin < lower] = 0.0
    cells = np.argwhere(thin >= lower)
    at = tuple(cells.T)
    i0, j0 = place.block[0], place.block[2]
    lists = {"points": (cells + np.array([i0, j0, 0])).astype(np.int64), "values": thin[at], "strike": strike[at],
             "dip": dip[at]}
    return BlockOutput({"thin": thin}, {"count": int(len(cells))}, lists)
