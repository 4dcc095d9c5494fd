"""Numba kernels and array helpers shared by the seismic attributes, the faults and the horizons (a private module:
import it whole, ``from . import _kernels``; the kernels only the faults use are in ``faults/_kernels.py``).

Arrays are 3D ``(n0, n1, n_samples)`` float32; a 2D section is viewed as ``(n_traces, 1, n_samples)`` (:func:`as_3d`).
Distances are in samples and traces. The kernels are compiled on first call and cached on disk.
"""

from __future__ import annotations

import numba as nb
import numpy as np

MAX_SLOPE = 5.0  # samples per trace; steeper "reflectors" are clipped (as in Hale's FaultScanner.slopes)


def as_3d(arr: np.ndarray) -> np.ndarray:
    """View a 2D section (n_traces, n_samples) as a cube (n_traces, 1, n_samples)."""
    return arr[:, None, :] if arr.ndim == 2 else arr


@nb.njit(cache=True, inline="always")
def interp_trace(f, i, j, t, nt):
    # linear interpolation along the sample axis, constant extrapolation at both ends
    if t <= 0.0:
        return f[i, j, 0]
    if t >= nt - 1:
        return f[i, j, nt - 1]
    k = int(t)
    w = t - k
    return (1.0 - w) * f[i, j, k] + w * f[i, j, k + 1]

_SLAB = 1 << 17  # samples of x per pass of correlate_axis: a slab and its products stay in the processor's cache


def correlate_axis(x: np.ndarray, w: np.ndarray, axis: int) -> np.ndarray:
    """Correlate a cube with an odd-length kernel along one axis, edges clamped (``scipy.ndimage.correlate1d`` with
    ``mode='nearest'``), accumulating in float32.

    The sum runs in kernel order, ``out = ((0 + w[0] x[i - r]) + w[1] x[i - r + 1]) + ...``, each product and sum
    rounded to float32: the bits of the compiled loop this replaced (``scipy.ndimage.correlate1d`` sums in float64,
    so its results differ in the last bits). Worked in slabs of about 2^17 samples so that the terms stay in cache.

    Parameters
    ----------
    x : (n0, n1, n2) float32 ndarray
        The cube.
    w : (2 r + 1,) float32 ndarray
        Correlation weights (:func:`gaussian_kernel`), centred on index ``r``.
    axis : {0, 1, 2}
        The axis correlated along.

    Returns
    -------
    (n0, n1, n2) float32 ndarray
        The correlated cube.
    """
    n = x.shape[axis]
    r = (w.shape[0] - 1) // 2
    out = np.zeros(x.shape, np.float32)
    clamped = np.clip(np.arange(-r, n + r), 0, n - 1)  # the axis padded by r samples on each side, edges repeated
    other = 1 if axis == 0 else 0  # slabs across another axis
    step = max(1, _SLAB // max(1, x.size // max(1, x.shape[other])))
    for a in range(0, x.shape[other], step):
        slab = tuple(slice(a, a + step) if d == other else slice(None) for d in range(3))
        padded = np.take(x[slab], clamped, axis=axis)
        acc = out[slab]
        term = np.empty(acc.shape, np.float32)
        for m in range(2 * r + 1):
            np.multiply(padded[tuple(slice(m, m + n) if d == axis else slice(None) for d in range(3))], w[m],
                        out=term)
            acc += term
    return out


@nb.njit(cache=True, inline="always")
def eig3(a, b, c, d, e, f):
    # Largest eigenvector (unit, third component >= 0) and (l1 - l2) / l1 of the symmetric tensor
    # [[a, b, c], [b, d, e], [c, e, f]]: closed-form eigenvalues (trigonometric solution of the characteristic
    # cubic), eigenvector from the largest cross product of two rows of T - l1 I.
    p1 = b * b + c * c + e * e
    q = (a + d + f) / 3.0
    p2 = (a - q) ** 2 + (d - q) ** 2 + (f - q) ** 2 + 2.0 * p1
    if p2 <= 1e-30 * (q * q + 1e-300):
        return 0.0, 0.0, 1.0, 0.0
    p = np.sqrt(p2 / 6.0)
    b00 = (a - q) / p
    b11 = (d - q) / p
    b22 = (f - q) / p
    b01 = b / p
    b02 = c / p
    b12 = e / p
    r = 0.5 * (b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02))
    r = min(1.0, max(-1.0, r))
    phi = np.arccos(r) / 3.0
    l1 = q + 2.0 * p * np.cos(phi)
    l3 = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
    l2 = 3.0 * q - l1 - l3
    r0x, r0y, r0z = a - l1, b, c
    r1x, r1y, r1z = b, d - l1, e
    r2x, r2y, r2z = c, e, f - l1
    c0x = r0y * r1z - r0z * r1y
    c0y = r0z * r1x - r0x * r1z
    c0z = r0x * r1y - r0y * r1x
    c1x = r0y * r2z - r0z * r2y
    c1y = r0z * r2x - r0x * r2z
    c1z = r0x * r2y - r0y * r2x
    c2x = r1y * r2z - r1z * r2y
    c2y = r1z * r2x - r1x * r2z
    c2z = r1x * r2y - r1y * r2x
    m0 = c0x * c0x + c0y * c0y + c0z * c0z
    m1 = c1x * c1x + c1y * c1y + c1z * c1z
    m2 = c2x * c2x + c2y * c2y + c2z * c2z
    if m0 >= m1 and m0 >= m2:
        vx, vy, vz, m = c0x, c0y, c0z, m0
    elif m1 >= m2:
        vx, vy, vz, m = c1x, c1y, c1z, m1
    else:
        vx, vy, vz, m = c2x, c2y, c2z, m2
    if m <= 0.0:
        return 0.0, 0.0, 1.0, 0.0
    s = 1.0 / np.sqrt(m)
    if vz < 0.0:
        s = -s
    return vx * s, vy * s, vz * s, ((l1 - l2) / l1 if l1 > 0.0 else 0.0)


@nb.njit(cache=True, parallel=True)
def eig_normals(t00, t01, t02, t11, t12, t22, normals, planarity):
    # reflector normals (..., 3) and planarity of every tensor
    n0, n1, n2 = t00.shape
    for i in nb.prange(n0):
        for j in range(n1):
            for k in range(n2):
                vx, vy, vz, pl = eig3(float(t00[i, j, k]), float(t01[i, j, k]), float(t02[i, j, k]),
                                       float(t11[i, j, k]), float(t12[i, j, k]), float(t22[i, j, k]))
                normals[i, j, k, 0] = vx
                normals[i, j, k, 1] = vy
                normals[i, j, k, 2] = vz
                planarity[i, j, k] = pl


@nb.njit(cache=True, parallel=True)
def eig_slopes(t00, t01, t02, t11, t12, t22, max_slope, p0, p1, as_float32_normals):
    # reflector slopes -n0 / n2 and -n1 / n2 (samples per trace, clipped to +-max_slope) of every tensor; with
    # as_float32_normals, from the normals rounded to float32 and divided in float32, as slopes_from_normals takes
    # eig_normals' normals (the same bits), else in float64
    floor32 = np.float32(1.0 / max_slope / 2.0)
    top32 = np.float32(max_slope)
    n0, n1, n2 = t00.shape
    for i in nb.prange(n0):
        for j in range(n1):
            for k in range(n2):
                vx, vy, vz, _ = eig3(float(t00[i, j, k]), float(t01[i, j, k]), float(t02[i, j, k]),
                                      float(t11[i, j, k]), float(t12[i, j, k]), float(t22[i, j, k]))
                if as_float32_normals:
                    nz = max(np.float32(vz), floor32)
                    p0[i, j, k] = min(max(-np.float32(vx) / nz, -top32), top32)
                    p1[i, j, k] = min(max(-np.float32(vy) / nz, -top32), top32)
                else:
                    vz = max(vz, 0.5 / max_slope)
                    p0[i, j, k] = min(max(-vx / vz, -max_slope), max_slope)
                    p1[i, j, k] = min(max(-vy / vz, -max_slope), max_slope)


@nb.njit(cache=True, parallel=True)
def semblance_num_den(f, p0, p1, r0, r1, num, den):
    # Semblance numerator (sum of the traces)^2 and denominator J * sum of squares, over the (2 r0 + 1) x
    # (2 r1 + 1) neighbouring traces, each read at t + p0 * di + p1 * dj (reflector slopes of the centre sample;
    # zero slopes give plain semblance). Traces outside the cube are left out (J counts the others).
    n0, n1, nt = f.shape
    for i in nb.prange(n0):
        for j in range(n1):
            for t in range(nt):
                s = 0.0
                s2 = 0.0
                cnt = 0
                q0 = p0[i, j, t]
                q1 = p1[i, j, t]
                for di in range(-r0, r0 + 1):
                    ii = i + di
                    if ii < 0 or ii >= n0:
                        continue
                    for dj in range(-r1, r1 + 1):
                        jj = j + dj
                        if jj < 0 or jj >= n1:
                            continue
                        v = interp_trace(f, ii, jj, t + q0 * di + q1 * dj, nt)
                        s += v
                        s2 += v * v
                        cnt += 1
                num[i, j, t] = s * s
                den[i, j, t] = cnt * s2

@nb.njit(cache=True, parallel=True)
def eigen_coherence_kernel(f, p0, p1, r0, r1, h, out):
    # Gersztenkorn & Marfurt (1999): C_kl = sum_tau f_k(t + tau) f_l(t + tau) over J traces and 2h+1 samples
    # (traces read along the reflector slopes); coherence = lambda_max(C) / trace(C), by power iteration.
    n0, n1, nt = f.shape
    jmax = (2 * r0 + 1) * (2 * r1 + 1)
    nw = 2 * h + 1
    for i in nb.prange(n0):
        w = np.empty((jmax, nw))
        c = np.empty((jmax, jmax))
        v = np.empty(jmax)
        u = np.empty(jmax)
        for j in range(n1):
            for t in range(nt):
                q0 = p0[i, j, t]
                q1 = p1[i, j, t]
                m = 0
                for di in range(-r0, r0 + 1):
                    ii = i + di
                    if ii < 0 or ii >= n0:
                        continue
                    for dj in range(-r1, r1 + 1):
                        jj = j + dj
                        if jj < 0 or jj >= n1:
                            continue
                        for k in range(nw):
                            w[m, k] = interp_trace(f, ii, jj, t + k - h + q0 * di + q1 * dj, nt)
                        m += 1
                tr = 0.0
                for a in range(m):
                    for b in range(a, m):
                        acc = 0.0
                        for k in range(nw):
                            acc += w[a, k] * w[b, k]
                        c[a, b] = acc
                        c[b, a] = acc
                    tr += c[a, a]
                if tr <= 0.0:
                    out[i, j, t] = 1.0
                    continue
                v0 = 1.0 / np.sqrt(m)
                for a in range(m):
                    v[a] = v0
                lam = 0.0
                for _ in range(50):
                    # u = C v; Rayleigh quotient u . v (|v| = 1); v <- u / |u|
                    nrm = 0.0
                    ray = 0.0
                    for a in range(m):
                        acc = 0.0
                        for b in range(m):
                            acc += c[a, b] * v[b]
                        u[a] = acc
                        nrm += acc * acc
                        ray += acc * v[a]
                    if nrm <= 0.0:
                        break
                    nrm = np.sqrt(nrm)
                    for a in range(m):
                        v[a] = u[a] / nrm
                    done = abs(ray - lam) <= 1e-7 * ray
                    lam = ray
                    if done:
                        break
                acc = lam
                out[i, j, t] = min(1.0, max(0.0, acc / tr))


def gaussian_radius(sigma: float) -> int:
    """Half-width, in samples, of :func:`gaussian_kernel` of width ``sigma`` (truncated at 3 sigma; 0 when the
    width is 0: no filter)."""
    return max(1, int(3.0 * float(sigma) + 0.5)) if sigma > 0 else 0


def gaussian_kernel(sigma: float, order: int) -> np.ndarray:
    """Correlation weights of a Gaussian (order 0) or of its first derivative (order 1), truncated at 3 sigma."""
    r = gaussian_radius(sigma)
    t = np.arange(-r, r + 1, dtype=np.float64)
    g = np.exp(-0.5 * (t / sigma) ** 2)
    g /= g.sum()
    if order == 1:
        g = g * t / sigma**2  # correlation with these weights = d/dx of the Gaussian-smoothed signal
    return g.astype(np.float32)


def gaussian3(x: np.ndarray, sigmas, orders=(0, 0, 0)) -> np.ndarray:
    """Separable Gaussian (derivative) filter of a float32 3D array; axes with sigma 0 are left alone."""
    out = x
    for axis, (sig, order) in enumerate(zip(sigmas, orders)):
        if sig <= 0 or x.shape[axis] == 1:
            continue
        out = correlate_axis(np.asarray(out, dtype=np.float32), gaussian_kernel(float(sig), int(order)), axis)
    return out if out is not x else x.astype(np.float32, copy=True)


def structure_tensor(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], two_d: bool):
    """The six smoothed components (t00, t01, t02, t11, t12, t22) of the structure tensor of a 3D-shaped array."""
    lat, vert = sigma_tensor
    sg = sigma_gradient
    sig = (lat, 0.0 if two_d else lat, vert)
    # gradients with shared smoothing passes: g0 = D0 G1 G2 f, g1 = G0 D1 G2 f, g2 = G0 G1 D2 f
    if two_d:
        g0 = gaussian3(gaussian3(f3, (0.0, 0.0, sg)), (sg, 0.0, 0.0), (1, 0, 0))
        g2 = gaussian3(gaussian3(f3, (sg, 0.0, 0.0)), (0.0, 0.0, sg), (0, 0, 1))
        t00 = gaussian3(g0 * g0, sig)
        t02 = gaussian3(g0 * g2, sig)
        t22 = gaussian3(g2 * g2, sig)
        zero = np.zeros_like(t00)
        return t00, zero, t02, zero, zero, t22
    f2 = gaussian3(f3, (0.0, 0.0, sg))
    g0 = gaussian3(gaussian3(f2, (0.0, sg, 0.0)), (sg, 0.0, 0.0), (1, 0, 0))
    g1 = gaussian3(gaussian3(f2, (sg, 0.0, 0.0)), (0.0, sg, 0.0), (0, 1, 0))
    del f2
    g2 = gaussian3(gaussian3(f3, (sg, sg, 0.0)), (0.0, 0.0, sg), (0, 0, 1))
    # products in an order that frees each gradient as soon as possible (peak memory)
    t00 = gaussian3(g0 * g0, sig)
    t01 = gaussian3(g0 * g1, sig)
    t02 = gaussian3(g0 * g2, sig)
    del g0
    t11 = gaussian3(g1 * g1, sig)
    t12 = gaussian3(g1 * g2, sig)
    del g1
    t22 = gaussian3(g2 * g2, sig)
    return t00, t01, t02, t11, t12, t22


def tensor_eig(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], two_d: bool):
    """Normals (n0, n1, nt, 3) and planarity of a 3D-shaped array (2D sections as (n, 1, nt))."""
    t = structure_tensor(f3, sigma_gradient, sigma_tensor, two_d)
    normals = np.empty(f3.shape + (3,), dtype=np.float32)
    planarity = np.empty(f3.shape, dtype=np.float32)
    eig_normals(*t, normals, planarity)
    return normals, planarity


def tensor_planarity(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], two_d: bool):
    """Planarity (n0, n1, nt) float32 of a 3D-shaped array (2D sections as (n, 1, nt)), without keeping the
    normals: computed in slabs of inlines so that the normals' workspace stays small."""
    t = structure_tensor(f3, sigma_gradient, sigma_tensor, two_d)
    planarity = np.empty(f3.shape, dtype=np.float32)
    slab = max(1, (1 << 24) // max(1, f3.shape[1] * f3.shape[2]))
    for a in range(0, f3.shape[0], slab):
        b = min(a + slab, f3.shape[0])
        normals = np.empty((b - a,) + f3.shape[1:] + (3,), dtype=np.float32)
        eig_normals(*(c[a:b] for c in t), normals, planarity[a:b])
    return planarity


def slopes_from_normals(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    nz = np.maximum(normals[..., 2], 1.0 / MAX_SLOPE / 2.0)
    p0 = np.clip(-normals[..., 0] / nz, -MAX_SLOPE, MAX_SLOPE).astype(np.float32)
    p1 = np.clip(-normals[..., 1] / nz, -MAX_SLOPE, MAX_SLOPE).astype(np.float32)
    return p0, p1


def reflector_slopes(f3: np.ndarray, two_d: bool, sigma_gradient: float, sigma_tensor,
                     as_float32_normals: bool = False) -> tuple:
    """Reflector slopes (p0, p1) in samples per trace of a 3D-shaped array, without storing the normals; with
    ``as_float32_normals`` equal bit for bit to those of :func:`tensor_eig`'s normals (:func:`slopes_from_normals`)."""
    t = structure_tensor(f3, sigma_gradient, sigma_tensor, two_d)
    p0 = np.empty(f3.shape, dtype=np.float32)
    p1 = np.empty(f3.shape, dtype=np.float32)
    eig_slopes(*t, MAX_SLOPE, p0, p1, bool(as_float32_normals))
    return p0, p1


@nb.njit(cache=True)
def _bucket_keys(points, origin, side, dims):
    # each point's bucket (cubes of ``side`` from ``origin``) as one key, C order over ``dims`` buckets
    keys = np.empty(points.shape[0], np.int64)
    for c in range(points.shape[0]):
        k = 0
        for a in range(3):
            k = k * dims[a] + int(np.floor((points[c, a] - origin[a]) / side))
        keys[c] = k
    return keys


def bucket_grid(points: np.ndarray, side: float) -> tuple:
    """Points binned in cubes of ``side`` for neighbour searches in compiled code: the points of one column of
    buckets along the last axis are one range of sorted keys (``np.searchsorted`` on the keys of its first and last
    bucket).

    Parameters
    ----------
    points : (n, 3) float64 ndarray
        Point coordinates (a 2D section's with a constant middle coordinate), n >= 1.
    side : float
        Side of the buckets, in the points' units (> 0).

    Returns
    -------
    keys : (n,) int64 ndarray
        Bucket keys, sorted: ``(bx * dims[1] + by) * dims[2] + bz`` with ``b = floor((p - origin) / side)``.
    order : (n,) int64 ndarray
        The points in key order (``keys`` = the points' keys [order]; ties keep the points' order).
    origin : (3,) float64 ndarray
        The lowest corner (the points' minimum).
    dims : (3,) int64 ndarray
        Buckets along each axis.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    origin = points.min(axis=0)
    dims = np.floor((points.max(axis=0) - origin) / side).astype(np.int64) + 1
    keys = _bucket_keys(points, origin, float(side), dims)
    order = np.argsort(keys, kind="stable")
    return keys[order], order, origin, dims
