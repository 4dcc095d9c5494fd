"""Fault surfaces: thinning fault likelihood to 1-sample-wide traces and linking them into faults.

Surfaces in 3D cubes, curves in 2D sections, after Hale 2013:

1. :func:`thin_faults`: non-maximum suppression across the fault plane, then a hysteresis threshold chosen from the
   data (Otsu on the ridge values) leaves 1-sample-wide fault traces.
2. :func:`link_faults`: thinned samples with compatible orientations are grown into separate faults; tiny ones are
   dropped. Each :class:`Fault` carries its points and their normals, the input for measuring throw across it
   (:mod:`seismo3d.seismic.faults.throw`).
3. :func:`fault_labels`: faults painted into a label array.

Conventions (strike, dip, normals, index space) are those of :mod:`seismo3d.seismic.faults.likelihood`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numba as nb
import numpy as np
from scipy import sparse

from ..._validation import as_seismic, check_positive
from ...errors import InputError
from .. import _kernels
from ._kernels import grow_by_mean_normal
from .likelihood import fault_normals, fault_strike_dip

__all__ = ["Fault", "check_fault_arrays", "thin_faults", "link_faults", "fault_labels"]


@dataclass(frozen=True, eq=False)
class Fault:
    """One linked fault: a surface of thinned samples in 3D, a curve in 2D.

    Attributes
    ----------
    id : int
        Fault id, 1, 2, ... in decreasing size.
    points : (n, ndim) int64 ndarray
        Index coordinates (inline, xline, sample) or (trace, sample) of the fault's samples.
    likelihood : (n,) float32 ndarray
        The value at each point of the thinned fault image the fault was linked from
        (:func:`~seismo3d.seismic.faults.skins.fault_skins`): in
        :func:`~seismo3d.seismic.trace_faults`, the thinned votes of the optimal-surface voting, not the fault
        likelihood itself (Hale's skins, whose cells carry a thinned likelihood, give the name).
    strike_deg, dip_deg : (n,) float32 ndarray
        Strike and dip at each point, degrees (module conventions).
    normals : (n, ndim) float32 ndarray
        Unit fault normal at each point, pointing into the footwall. The two sides of the fault at point ``p`` are
        near ``p + d * normal`` (footwall) and ``p - d * normal`` (hanging wall): the hook for measuring throw by
        registering the reflectors of the two sides.
    """

    id: int
    points: np.ndarray
    likelihood: np.ndarray
    strike_deg: np.ndarray
    dip_deg: np.ndarray
    normals: np.ndarray

    @property
    def size(self) -> int:
        """Number of samples on the fault."""
        return int(self.points.shape[0])

    @property
    def mean_normal(self) -> np.ndarray:
        """(ndim,) float64 unit mean normal (likelihood-weighted, sign-aligned, sample component >= 0)."""
        n = self.normals.astype(np.float64)
        ref = n[np.argmax(self.likelihood)]
        sgn = np.where(n @ ref < 0, -1.0, 1.0)
        m = (n * (sgn * self.likelihood)[:, None]).sum(axis=0)
        m /= max(np.linalg.norm(m), 1e-12)
        return -m if m[-1] < 0 else m

    @property
    def mean_strike_deg(self) -> float:
        """Strike of :attr:`mean_normal`, degrees in [0, 360)."""
        return float(fault_strike_dip(self.mean_normal)[0])

    @property
    def mean_dip_deg(self) -> float:
        """Dip of :attr:`mean_normal`, degrees in [0, 90]."""
        return float(fault_strike_dip(self.mean_normal)[1])



@nb.njit(cache=True, inline="always")
def _trilinear(f, x, y, z):
    n0, n1, n2 = f.shape
    x = min(max(x, 0.0), n0 - 1.0)
    y = min(max(y, 0.0), n1 - 1.0)
    z = min(max(z, 0.0), n2 - 1.0)
    i = min(int(x), n0 - 2) if n0 > 1 else 0
    j = min(int(y), n1 - 2) if n1 > 1 else 0
    k = min(int(z), n2 - 2) if n2 > 1 else 0
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


@nb.njit(cache=True, inline="always")
def _lut_index(strike_deg, dip_deg, n_phi, n_theta):
    i = int(np.floor(strike_deg * _LUT_STEP + 0.5)) % n_phi
    j = min(max(int(np.floor(dip_deg * _LUT_STEP + 0.5)), 0), n_theta - 1)
    return i, j


@nb.njit(cache=True, inline="always")
def _bilinear01(f, x, y, k):
    # bilinear interpolation of f[:, :, k] at (x, y), clamped to the array
    n0, n1, _ = f.shape
    x = min(max(x, 0.0), n0 - 1.0)
    y = min(max(y, 0.0), n1 - 1.0)
    i = min(int(x), n0 - 2) if n0 > 1 else 0
    j = min(int(y), n1 - 2) if n1 > 1 else 0
    u = x - i
    v = y - j
    i1 = i + 1 if n0 > 1 else i
    j1 = j + 1 if n1 > 1 else j
    return (1 - u) * ((1 - v) * f[i, j, k] + v * f[i, j1, k]) + u * ((1 - v) * f[i1, j, k] + v * f[i1, j1, k])


@nb.njit(cache=True, parallel=True)
def _near_above(f, floor, need):
    # need[i, j, k]: some sample of the 3 x 3 x 3 neighbourhood of (i, j, k) has f > floor (the samples whose ranking
    # value a ridge test of a sample above floor reads: trilinear reads one sample away along the normal)
    n0, n1, n2 = f.shape
    for i in nb.prange(n0):
        for j in range(n1):
            for k in range(n2):
                hit = False
                for a in range(max(i - 1, 0), min(i + 2, n0)):
                    for b in range(max(j - 1, 0), min(j + 2, n1)):
                        for c in range(max(k - 1, 0), min(k + 2, n2)):
                            if f[a, b, c] > floor:
                                hit = True
                                break
                        if hit:
                            break
                    if hit:
                        break
                need[i, j, k] = hit


@nb.njit(cache=True, parallel=True)
def _smooth_along_dip(f, strike, dip, lut, h, need, out):
    # Average f along the dip of each sample's fault plane, one sample per step down (the fault is steeper than
    # 45 degrees in the scan, so the dip vector has its largest component along the sample axis): triangle weights
    # over +-h samples, bilinear interpolation across. Joins fault ridges broken by noise before thinning. Computed
    # where need is True, 0 elsewhere.
    n0, n1, n2 = f.shape
    n_phi, n_theta, _ = lut.shape
    for i in nb.prange(n0):
        for j in range(n1):
            for k in range(n2):
                if not need[i, j, k]:
                    out[i, j, k] = 0.0
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


@nb.njit(cache=True, parallel=True)
def _ridges(f, g, strike, dip, lut, floor, out):
    # Non-maximum suppression of g across the fault: keep f where g(p) > g(p - n) and g(p) >= g(p + n), n the unit
    # fault normal of the sample (trilinear interpolation); samples with f <= floor are 0 (not tested).
    n0, n1, n2 = f.shape
    n_phi, n_theta, _ = lut.shape
    for i in nb.prange(n0):
        for j in range(n1):
            for k in range(n2):
                if not f[i, j, k] > floor:
                    out[i, j, k] = 0.0
                    continue
                ip, it = _lut_index(strike[i, j, k], dip[i, j, k], n_phi, n_theta)
                a = lut[ip, it, 0]
                b = lut[ip, it, 1]
                c = lut[ip, it, 2]
                gc = g[i, j, k]
                gp = _trilinear(g, i + a, j + b, k + c)
                gm = _trilinear(g, i - a, j - b, k - c)
                out[i, j, k] = f[i, j, k] if (gc > gm and gc >= gp) else 0.0


def ridge_image(likelihood, strike, dip, *, floor=-1.0, sigma=1.5, dip_smoothing=4) -> np.ndarray:
    """Steps 1-2 of :func:`thin_faults` (ranking image, non-maximum suppression across the fault), on the samples
    whose likelihood is above ``floor`` only.

    The ranking image is computed only where a ridge test above ``floor`` reads it (the 3 x 3 x 3 neighbourhood of
    those samples: the test reads it one sample away along the unit normal), so the ridges above ``floor`` are those
    of the whole image, bit for bit, at a fraction of the cost when few samples are above it.

    Parameters
    ----------
    likelihood, strike, dip : float32 ndarray, one shape
        Checked by :func:`check_fault_arrays` (2D sections or 3D cubes).
    floor : float
        Samples with a likelihood at or below it (compared in float64) are 0 in the result (default: none, a
        likelihood is >= 0). Whether a caller then keeps the values above a threshold ``t`` in float32 or in float64,
        ``floor=t`` tests every sample it keeps.
    sigma, dip_smoothing : float, int
        As in :func:`thin_faults`.

    Returns
    -------
    ndarray of the likelihood's shape, float32
        The likelihood on its ridge samples above ``floor``, 0 elsewhere.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (thinning of fault images).
    """
    two_d = likelihood.ndim == 2
    f3 = _kernels.as_3d(likelihood)
    st3 = np.ascontiguousarray(_kernels.as_3d(strike))
    dp3 = np.ascontiguousarray(_kernels.as_3d(dip))
    floor = float(floor)
    lut = _direction_lut()
    g = _kernels.gaussian3(f3, (sigma, 0.0 if two_d else sigma, sigma)) if sigma > 0 else f3
    if dip_smoothing > 0:
        need = np.empty(f3.shape, np.bool_)
        _near_above(f3, floor, need)
        g2 = np.empty_like(f3)
        _smooth_along_dip(g, st3, dp3, lut, int(dip_smoothing), need, g2)
        del need
        g = g2
    ridge = np.empty_like(f3)
    _ridges(f3, g, st3, dp3, lut, floor, ridge)
    del g
    return ridge[:, 0, :] if two_d else ridge


# --------------------------------------------------------------------------------------------------------------------
# thinning


def check_fault_arrays(likelihood, strike, dip):
    """A fault image and its strike and dip as float32 arrays of one shape, or :class:`InputError`.

    Parameters
    ----------
    likelihood : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Fault likelihood, votes or thinned faults; finite.
    strike, dip : array_like of float, same shape
        Strike and dip, degrees.

    Returns
    -------
    likelihood, strike, dip : float32 ndarray

    Raises
    ------
    InputError
        Shapes differ or values are not finite.
    """
    fl = as_seismic(likelihood, "likelihood", min_size=1)
    st = np.asarray(strike, dtype=np.float32)
    dp = np.asarray(dip, dtype=np.float32)
    if st.shape != fl.shape or dp.shape != fl.shape:
        raise InputError(
            f"likelihood {fl.shape}, strike {st.shape} and dip {dp.shape} must have the same shape; pass the fields "
            "of one FaultLikelihood"
        )
    if not (np.all(np.isfinite(st)) and np.all(np.isfinite(dp))):
        raise InputError("strike and dip have NaN or inf values; pass the strike_deg and dip_deg of a FaultLikelihood")
    return fl, st, dp


def _otsu(values: np.ndarray) -> float:
    from skimage.filters import threshold_otsu

    if values.size == 0 or float(values.max()) <= float(values.min()):
        return float(values.max()) if values.size else 1.0
    return float(threshold_otsu(values))


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
        lo = _otsu(ridge[ridge > 0])
        hi = 0.5 * (lo + 1.0)
    else:
        lo, hi = float(thr[0]), float(thr[-1])
    keep = apply_hysteresis_threshold(ridge, lo, hi) & (ridge > 0)
    return np.where(keep, fl, 0.0).astype(np.float32)


# --------------------------------------------------------------------------------------------------------------------
# linking


def link_faults(thin, strike, dip, *, min_size=None, max_angle=20.0) -> list[Fault]:
    """Link thinned fault samples into separate faults.

    Thinned samples are linked to their neighbours (26-connectivity in 3D, 8 in 2D) when the angle between their
    fault normals is below ``max_angle``, and to samples two steps away that also lie within one sample of each
    other's fault plane (this bridges one-sample gaps left by the thinning). Faults grow over these links from the
    sample of highest likelihood, breadth first, accepting a sample only if its normal is also within
    1.5 ``max_angle`` of the growing fault's mean normal: this keeps two faults that cross or meet (linked through
    samples of intermediate orientation) apart, as fault skins are kept apart in Hale (2013). Faults with fewer than
    ``min_size`` samples are dropped.

    Parameters
    ----------
    thin : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Thinned fault likelihood from :func:`thin_faults` (> 0 on fault samples).
    strike, dip : array_like of float, same shape
        Fault strike and dip in degrees.
    min_size : int, optional
        Smallest fault kept, in samples. Default: in 2D, 10 % of the samples per trace (at least 10); in 3D, 1 % of
        n_samples x min(n_inlines, n_xlines), the smaller vertical face (at least 100).
    max_angle : float, optional
        Largest angle between the normals of linked neighbours, degrees. The default 20 lets neighbours differ by
        one step of the default strike / dip scan.

    Returns
    -------
    list of Fault
        Sorted by decreasing size, ids 1, 2, ... in that order.

    Raises
    ------
    InputError
        If the shapes differ or an argument is out of range.

    References
    ----------
    .. [1] D. Hale, Geophysics 78(2), O33-O43, 2013, doi:10.1190/geo2012-0331.1 (fault skins grown from seeds of
       high likelihood).
    """
    fl, st, dp = check_fault_arrays(thin, strike, dip)
    max_angle = check_positive(max_angle, "max_angle")
    ndim = fl.ndim
    if min_size is None:
        # a fault must span about a tenth of the data: 10 % of the samples of a trace in 2D; in 3D, 1 % of the
        # smaller vertical face (samples x the shorter of inlines and crosslines), which a fault striking across
        # the narrow side of a slab (a few inlines cut from a survey) cannot outgrow
        if ndim == 2:
            min_size = max(10, int(round(0.1 * fl.shape[-1])))
        else:
            min_size = max(100, int(round(0.01 * fl.shape[-1] * min(fl.shape[:2]))))
    min_size = int(check_positive(min_size, "min_size"))
    mask = fl > 0
    pts = np.argwhere(mask)
    if pts.shape[0] == 0:
        return []
    n = fault_normals(st[mask], dp[mask], ndim=ndim)
    index = np.full(fl.shape, -1, dtype=np.int32 if pts.shape[0] < 2**31 - 1 else np.int64)
    index[mask] = np.arange(pts.shape[0])
    cos_max = np.cos(np.radians(max_angle))
    rows, cols = [], []
    # half of the offsets within 2 samples (the other half gives the same edges reversed): immediate neighbours link
    # when their normals agree; samples two steps apart (bridging one-sample gaps in a thinned fault) must also lie
    # in each other's fault plane (within one sample of it)
    offsets = [np.array(o) - 2 for o in np.ndindex(*(5,) * ndim) if o > (2,) * ndim]
    for d in offsets:
        q = pts + d
        ok = np.all((q >= 0) & (q < np.array(fl.shape)), axis=1)
        src = np.nonzero(ok)[0]
        dst = index[tuple(q[ok].T)]
        has = dst >= 0
        src, dst = src[has], dst[has]
        compatible = np.abs(np.einsum("ij,ij->i", n[src], n[dst])) >= cos_max
        if np.abs(d).max() > 1:
            compatible &= (np.abs(n[src] @ d) <= 1.0) & (np.abs(n[dst] @ d) <= 1.0)
        rows.append(src[compatible])
        cols.append(dst[compatible])
    rows = np.concatenate(rows)
    cols = np.concatenate(cols)
    n_pts = pts.shape[0]
    graph = sparse.coo_matrix((np.ones(rows.size, dtype=np.int8), (rows, cols)), shape=(n_pts, n_pts)).tocsr()
    graph = (graph + graph.T).tocsr()
    vals, svals, dvals = fl[mask], st[mask], dp[mask]
    order = np.argsort(-vals, kind="stable")
    comp = grow_by_mean_normal(graph.indptr.astype(np.int64), graph.indices.astype(np.int64),
                               n.astype(np.float64), order,
                               float(np.cos(np.radians(1.5 * max_angle))))
    sizes = np.bincount(comp)
    keep = np.nonzero(sizes >= min_size)[0]
    keep = keep[np.argsort(-sizes[keep], kind="stable")]
    srt = np.argsort(comp, kind="stable")
    bounds = np.searchsorted(comp[srt], np.arange(sizes.size + 1))
    groups = [srt[bounds[c]:bounds[c + 1]] for c in keep]
    return [
        Fault(id=i + 1, points=pts[g].astype(np.int64), likelihood=vals[g].astype(np.float32),
              strike_deg=svals[g].astype(np.float32), dip_deg=dvals[g].astype(np.float32), normals=n[g])
        for i, g in enumerate(groups)
    ]


def fault_labels(faults, shape) -> np.ndarray:
    """Paint faults into a label array.

    Parameters
    ----------
    faults : sequence of Fault
        Faults from :func:`link_faults`.
    shape : tuple of int
        Shape of the cube or section the faults came from.

    Returns
    -------
    shape int32 ndarray
        0 off faults, ``fault.id`` on each fault's points.

    Raises
    ------
    InputError
        If a fault's points do not fit ``shape``.
    """
    shape = tuple(int(s) for s in shape)
    labels = np.zeros(shape, dtype=np.int32)
    for f in faults:
        p = np.asarray(f.points)
        if p.ndim != 2 or p.shape[1] != len(shape) or (p.size and (p.min() < 0 or np.any(p.max(0) >= shape))):
            raise InputError(f"fault {f.id} has points outside an array of shape {shape}")
        labels[tuple(p.T)] = f.id
    return labels
