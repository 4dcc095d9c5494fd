"""Numba kernels and array helpers shared by the seismic attributes, the faults and the horizons (a private module:
import it whole, ``from . import _kernels``; the kernels only the faults use are in ``faults/_kernels.py``).

Arrays are 3D ``(n0, n1, n_samples)`` float32; a 2D section is viewed as ``(n_traces, 1, n_samples)`` (:func:`as_3d`).
Distances are in samples and traces. The Gaussian and derivative filters are scipy's
(:func:`scipy.ndimage.gaussian_filter1d`, truncated at 3 sigma, edges clamped); the fault side's structure tensor
(``float32=True``) and the fault orientation use OpenCV's with the same weights (:func:`gaussian_pass32`: float32 sums,
a third of the CPU seconds); the compiled kernels are the
loops of our own algorithms (semblance, eigen-coherence along the reflector slopes), compiled on first call and cached
on disk.
"""

from __future__ import annotations


import numba as nb
import numpy as np

from .._progress import progress_within
from .._threads import run_threads

MAX_SLOPE = 5.0  # samples per trace; steeper "reflectors" are clipped (as in Hale's FaultScanner.slopes)


def as_3d(arr: np.ndarray) -> np.ndarray:
    """View a 2D section (n_traces, n_samples) as a cube (n_traces, 1, n_samples)."""
    return arr[:, None, :] if arr.ndim == 2 else arr


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def interp_trace(f, i, j, t, nt):
    # linear interpolation along the sample axis, constant extrapolation at both ends
    if t <= 0.0:
        return f[i, j, 0]
    if t >= nt - 1:
        return f[i, j, nt - 1]
    k = int(t)
    w = t - k
    return (1.0 - w) * f[i, j, k] + w * f[i, j, k + 1]

# voxels per pass of the eigen-decomposition: its float64 temporaries (~40 of 64 KiB, 2.5 MB a thread) stay in the
# processor's cache (2^15: ~10 MB a thread, about twice the CPU seconds on a 200 x 200 x 500 cube)
_EIG_CHUNK = 1 << 13


def eig3(a, b, c, d, e, f, planarity: bool = True):
    """Largest eigenvector and planarity of the symmetric tensors ``[[a, b, c], [b, d, e], [c, e, f]]``.

    Closed-form eigenvalues (Smith 1961: trigonometric solution of the characteristic cubic), the eigenvector from
    the largest cross product of two rows of ``T - l1 I``, in float64 (``np.linalg.eigh`` gives the same to
    float rounding, at several times the time and memory on a cube's tensors).

    Parameters
    ----------
    a, b, c, d, e, f : (n,) float32 ndarray
        The tensor components ``t00, t01, t02, t11, t12, t22``.
    planarity : bool, optional
        False: the planarity and the two smaller eigenvalues it needs are not computed (None in its place); the
        eigenvector is the same bits.

    Returns
    -------
    vx, vy, vz : (n,) float64 ndarray
        The unit eigenvector of the largest eigenvalue, ``vz >= 0``; ``(0, 0, 1)`` for an isotropic or zero tensor.
    planarity : (n,) float64 ndarray or None
        ``(l1 - l2) / l1`` (0 when ``l1 <= 0`` or the tensor is isotropic); None when not asked for.

    References
    ----------
    .. [1] O. K. Smith, "Eigenvalues of a symmetric 3 x 3 matrix", Communications of the ACM 4(4), 168, 1961,
       doi:10.1145/355578.366316.
    """
    f64 = np.float64
    with np.errstate(all="ignore"):  # isotropic tensors divide by zero; their results are replaced below
        # the float32 products of the off-diagonal components, each once (b c and c b are the same bits)
        bb, cc, ee, be, bc, ce = b * b, c * c, e * e, b * e, b * c, c * e
        p1 = (bb + cc + ee).astype(f64)
        bb, cc, ee, be, bc, ce = (x.astype(f64) for x in (bb, cc, ee, be, bc, ce))
        q = (a + d + f).astype(f64) / 3.0
        a64, b64, c64, d64, e64, f64_ = (t.astype(f64) for t in (a, b, c, d, e, f))
        aq, dq, fq = a64 - q, d64 - q, f64_ - q
        p2 = aq * aq + dq * dq + fq * fq + 2.0 * p1
        isotropic = p2 <= 1e-30 * (q * q + 1e-300)
        p = np.sqrt(p2 / 6.0)
        b00, b11, b22, b01, b02, b12 = aq / p, dq / p, fq / p, b64 / p, c64 / p, e64 / p
        r = 0.5 * (b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02))
        r = np.where(r > -1.0, r, -1.0)  # min(1, max(-1, r)) as Python's max and min (NaN -> -1)
        r = np.where(r < 1.0, r, 1.0)
        phi = np.arccos(r) / 3.0
        l1 = q + 2.0 * p * np.cos(phi)
        # rows of T - l1 I: (a - l1, b, c), (b, d - l1, e), (c, e, f - l1); their cross products
        r0x, r1y, r2z = a64 - l1, d64 - l1, f64_ - l1
        c0 = (be - c64 * r1y, bc - r0x * e64, r0x * r1y - bb)
        c1 = (b64 * r2z - ce, cc - r0x * r2z, r0x * e64 - bc)
        c2 = (r1y * r2z - ee, ce - b64 * r2z, be - r1y * c64)
        m0, m1, m2 = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] for v in (c0, c1, c2))
        pick0 = (m0 >= m1) & (m0 >= m2)
        pick1 = ~pick0 & (m1 >= m2)
        v = [np.where(pick0, c0[k], np.where(pick1, c1[k], c2[k])) for k in range(3)]
        m = np.where(pick0, m0, np.where(pick1, m1, m2))
        s = 1.0 / np.sqrt(m)
        s = np.where(v[2] < 0.0, -s, s)
        zero = isotropic | (m <= 0.0)
        vx = np.where(zero, 0.0, v[0] * s)
        vy = np.where(zero, 0.0, v[1] * s)
        vz = np.where(zero, 1.0, v[2] * s)
        if not planarity:
            return vx, vy, vz, None
        l3 = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
        l2 = 3.0 * q - l1 - l3
        return vx, vy, vz, np.where(zero | ~(l1 > 0.0), 0.0, (l1 - l2) / l1)


def _eig_chunks(components, work):
    """Call ``work(slice, six (n,) float32 arrays)`` on the tensor components (six float32 arrays of one shape) as flat
    arrays, in chunks of ``_EIG_CHUNK``, the chunks shared out over numba's thread count of threads (numpy
    releases the GIL)."""
    flat = [np.asarray(t, np.float32).reshape(-1) for t in components]
    starts = range(0, flat[0].size, _EIG_CHUNK)

    def chunks(t, n_threads):
        for start in starts[t::n_threads]:
            part = slice(start, start + _EIG_CHUNK)
            work(part, [c[part] for c in flat])

    run_threads(chunks, max(1, min(nb.get_num_threads(), len(starts))))


def eig_normals(t00, t01, t02, t11, t12, t22, normals, planarity):
    """Reflector normals and planarity of every structure tensor (:func:`eig3`), written into ``normals``
    (``shape + (3,)`` float32, C order) and ``planarity`` (``shape`` float32, C order); the components are float32
    arrays of ``shape``."""
    n_flat = normals.reshape(-1, 3)
    p_flat = planarity.reshape(-1)

    def work(part, comps):
        vx, vy, vz, pl = eig3(*comps)
        n_flat[part, 0] = vx
        n_flat[part, 1] = vy
        n_flat[part, 2] = vz
        p_flat[part] = pl

    _eig_chunks((t00, t01, t02, t11, t12, t22), work)


def eig_vectors(t00, t01, t02, t11, t12, t22, write):
    """Call ``write(part, vx, vy, vz)`` with the unit eigenvectors of the largest eigenvalue (:func:`eig3`, float64,
    planarity not computed) of the flat elements ``part`` (a slice) of the structure tensors, chunk by chunk of
    ``_EIG_CHUNK`` on numba's thread count of threads: what is made of the vectors stays in the processor's cache
    too. The components are float32 arrays of one shape."""

    def work(part, comps):
        vx, vy, vz, _ = eig3(*comps, planarity=False)
        write(part, vx, vy, vz)

    _eig_chunks((t00, t01, t02, t11, t12, t22), work)


def eig_slopes(t00, t01, t02, t11, t12, t22, max_slope, p0, p1, as_float32_normals):
    """Reflector slopes ``-n0 / n2`` and ``-n1 / n2`` (samples per trace, clipped to +-``max_slope``) of every
    structure tensor, written into ``p0`` and ``p1`` (float32, C order, the components' shape). With
    ``as_float32_normals``, from the normals rounded to float32 and divided in float32, as
    :func:`slopes_from_normals` takes :func:`eig_normals`' normals (the same bits); else in float64."""
    p0_flat = p0.reshape(-1)
    p1_flat = p1.reshape(-1)
    floor32 = np.float32(1.0 / max_slope / 2.0)
    top32 = np.float32(max_slope)

    def work(part, comps):
        vx, vy, vz, _ = eig3(*comps, planarity=False)
        if as_float32_normals:
            vz32 = vz.astype(np.float32)
            nz = np.where(floor32 > vz32, floor32, vz32)  # max(vz, floor) as Python's max
            for v, out in ((vx, p0_flat), (vy, p1_flat)):
                ratio = -v.astype(np.float32) / nz
                ratio = np.where(-top32 > ratio, -top32, ratio)
                out[part] = np.where(top32 < ratio, top32, ratio)
        else:
            floor = 0.5 / max_slope
            nz = np.where(floor > vz, floor, vz)
            for v, out in ((vx, p0_flat), (vy, p1_flat)):
                ratio = -v / nz
                ratio = np.where(-max_slope > ratio, -max_slope, ratio)
                out[part] = np.where(max_slope < ratio, max_slope, ratio)

    _eig_chunks((t00, t01, t02, t11, t12, t22), work)


def semblance_num_den(f, p0, p1, r0, r1, num, den):
    """Semblance numerator and denominator of every sample of ``f`` (float32, C order; ``p0``, ``p1``: its reflector
    slopes, float32) over ``(2 r0 + 1) x (2 r1 + 1)`` traces, written into ``num`` and ``den`` (float32, ``f.shape``);
    the rows of axis 0 shared out over numba's thread count of threads (:func:`~seismo3d._threads.run_threads`), also
    inside a block's thread, as the ``prange`` loop it replaces did (its memory does not grow with the threads)."""
    run_threads(_semblance_rows, max(1, min(nb.get_num_threads(), f.shape[0])), f, p0, p1, r0, r1, num, den,
                from_any_thread=True)


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _semblance_rows(share, n_shares, f, p0, p1, r0, r1, num, den):
    # Semblance numerator (sum of the traces)^2 and denominator J * sum of squares, over the (2 r0 + 1) x
    # (2 r1 + 1) neighbouring traces, each read at t + p0 * di + p1 * dj (reflector slopes of the centre sample;
    # zero slopes give plain semblance). Traces outside the cube are left out (J counts the others). Rows
    # share, share + n_shares, ... of axis 0 (run_threads).
    n0, n1, nt = f.shape
    for i in range(share, n0, n_shares):
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

def eigen_coherence_kernel(f, p0, p1, r0, r1, h, out):
    """Eigenstructure coherence of every sample of ``f`` (float32, C order; ``p0``, ``p1``: its reflector slopes,
    float32) over ``(2 r0 + 1) x (2 r1 + 1)`` traces and ``2 h + 1`` samples, written into ``out`` (float32,
    ``f.shape``); the rows of axis 0 shared out over numba's thread count of threads
    (:func:`~seismo3d._threads.run_threads`), also inside a block's thread, as the ``prange`` loop it replaces did."""
    run_threads(_eigen_coherence_rows, max(1, min(nb.get_num_threads(), f.shape[0])), f, p0, p1, r0, r1, h, out,
                from_any_thread=True)


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _eigen_coherence_rows(share, n_shares, f, p0, p1, r0, r1, h, out):
    # Gersztenkorn & Marfurt (1999): C_kl = sum_tau f_k(t + tau) f_l(t + tau) over J traces and 2h+1 samples
    # (traces read along the reflector slopes); coherence = lambda_max(C) / trace(C), by power iteration. Rows
    # share, share + n_shares, ... of axis 0 (run_threads).
    n0, n1, nt = f.shape
    jmax = (2 * r0 + 1) * (2 * r1 + 1)
    nw = 2 * h + 1
    w = np.empty((jmax, nw))
    c = np.empty((jmax, jmax))
    v = np.empty(jmax)
    u = np.empty(jmax)
    for i in range(share, n0, n_shares):
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


def gaussian_radius(sigma: float, truncate: float = 3.0) -> int:
    """Half-width, in samples, of the Gaussian filters of width ``sigma`` (:func:`gaussian_pass`: scipy's radius,
    ``int(truncate sigma + 0.5)``, at least 1; 0 when the width is 0: no filter)."""
    return max(1, int(float(truncate) * float(sigma) + 0.5)) if sigma > 0 else 0


def gaussian_pass(x: np.ndarray, axis: int, sigma: float, order: int = 0, keep=None) -> np.ndarray:
    """A Gaussian (order 0) or Gaussian derivative (order 1) filter of a float32 cube along one axis, truncated at
    3 sigma, edges clamped (:func:`scipy.ndimage.gaussian_filter1d`, ``mode='nearest'``), float32.

    Parameters
    ----------
    x : (n0, n1, n2) ndarray
    axis : {0, 1, 2}
    sigma : float
        Width, samples (or traces); 0 leaves ``x`` alone (as does an axis of length 1).
    order : {0, 1}
        1: the derivative of the smoothed signal along ``axis``.
    keep : (int, int), optional
        ``(lo, hi)``: only the outputs ``lo <= i < hi`` along ``axis``, each equal to the whole axis' (filtered from
        the lines within the radius of them, edges clamped at the whole axis' ends); default all.

    Returns
    -------
    ndarray, float32
        ``x``'s shape (``hi - lo`` along ``axis`` with ``keep``).
    """
    from scipy.ndimage import gaussian_filter1d

    n = x.shape[axis]
    lo, hi = (0, n) if keep is None else (int(keep[0]), int(keep[1]))
    if sigma <= 0 or n == 1:
        return np.asarray(x[(slice(None),) * axis + (slice(lo, hi),)], dtype=np.float32)
    r = gaussian_radius(sigma)
    a, b = max(lo - r, 0), min(hi + r, n)  # the lines the kept outputs read: clamped at the axis' ends as the whole
    window = np.asarray(x[(slice(None),) * axis + (slice(a, b),)], dtype=np.float32)
    out = gaussian_filter1d(window, float(sigma), axis=axis, order=int(order), mode="nearest", truncate=3.0)
    return out[(slice(None),) * axis + (slice(lo - a, hi - a),)] if (a, b) != (lo, hi) else out


def _gaussian_weights(sigma: float, order: int, truncate: float = 3.0) -> np.ndarray:
    """Correlation weights of the Gaussian (order 0) or Gaussian derivative (order 1) filter of width ``sigma``
    truncated at :func:`gaussian_radius`: scipy's (``scipy.ndimage.gaussian_filter1d``: the normalised Gaussian,
    and its derivative ``-x / sigma^2`` times it, reversed for a correlation), float64."""
    r = gaussian_radius(sigma, truncate)
    x = np.arange(-r, r + 1, dtype=np.float64)
    phi = np.exp(-0.5 / (float(sigma) * float(sigma)) * x * x)
    phi = phi / phi.sum()
    return phi if order == 0 else x / (float(sigma) * float(sigma)) * phi


# scipy's edge modes by OpenCV's border names: 'reflect' (d c b a | a b c d) is OpenCV's BORDER_REFLECT
_CV_BORDERS = {"nearest": "BORDER_REPLICATE", "reflect": "BORDER_REFLECT"}


def gaussian_pass32(x: np.ndarray, axis: int, sigma: float, order: int = 0, keep=None, *, out=None,
                    truncate: float = 3.0, mode: str = "nearest") -> np.ndarray:
    """:func:`gaussian_pass` summed in float32: OpenCV's separable filter (``cv2.sepFilter2D``, edges replicated as
    scipy's ``'nearest'``) with scipy's weights, a third of the CPU seconds of scipy's lines in double precision on a
    cube (the structure tensor's passes, :func:`structure_tensor_at`), within 1e-6 of the largest value of scipy's.

    Each call filters 2D images whose rows are whole traces (the sample axis, never cut): one per crossline (axis 0),
    one per inline (axis 1 and 2), written in place. An output's arithmetic depends on its sample index only, not on
    where the array was cut, so a part of a cube read with the filter's radius beyond it gets the whole cube's bits
    there (a run by blocks equals the run in memory).

    Parameters
    ----------
    x : (n0, n1, n_samples) ndarray
        Any real dtype (filtered as float32).
    axis : {0, 1, 2}
    sigma : float
        Width, traces or samples; 0 leaves ``x`` alone (as does an axis of length 1).
    order : {0, 1}
        1: the derivative of the smoothed signal along ``axis``.
    keep : (int, int), optional
        ``(lo, hi)``: only the outputs ``lo <= i < hi`` along ``axis``, each equal to the whole axis' (filtered from the
        lines within the radius of them); default all.
    out : (n0, n1, n_samples) float32 ndarray, optional
        Where to write the result (whole traces: each inline's (n1, n_samples) rows contiguous); not with ``keep``.
    truncate : float, optional
        The filter's half-width in ``sigma`` (scipy's ``truncate``; :func:`gaussian_radius`).
    mode : {'nearest', 'reflect'}, optional
        The edges, as scipy's modes: the end value repeated, or the line mirrored about its end (``d c b a | a b c d``).

    Returns
    -------
    ndarray, float32
        ``x``'s shape (``hi - lo`` along ``axis`` with ``keep``); a view of the lines filtered with ``keep``.

    Raises
    ------
    ValueError
        ``out`` given with ``keep`` or of another shape than the result, or another ``mode`` (a caller's bug: not for
        users).

    References
    ----------
    .. [1] OpenCV, ``cv::sepFilter2D``, https://docs.opencv.org/4.x/d4/d86/group__imgproc__filter.html.
    """
    import cv2  # a dependency of seismo3d, imported where it is used (as the features do)

    n = x.shape[axis]
    lo, hi = (0, n) if keep is None else (int(keep[0]), int(keep[1]))
    if sigma <= 0 or n == 1:
        kept = np.asarray(x[(slice(None),) * axis + (slice(lo, hi),)], dtype=np.float32)
        if out is None:
            return kept
        out[...] = kept
        return out
    if mode not in _CV_BORDERS:
        raise ValueError(f"gaussian_pass32: mode {mode!r} is not one of {sorted(_CV_BORDERS)}")
    r = gaussian_radius(sigma, truncate)
    a, b = max(lo - r, 0), min(hi + r, n)  # the lines the kept outputs read (as gaussian_pass)
    window = np.asarray(x[(slice(None),) * axis + (slice(a, b),)], dtype=np.float32)
    if window.strides[-1] != window.itemsize:
        window = np.ascontiguousarray(window)
    if out is None:
        out = np.empty(window.shape, np.float32)
    elif keep is not None or out.shape != window.shape:
        raise ValueError(f"gaussian_pass32: out of shape {out.shape} for a result of shape {window.shape}")
    weights, one, edge = _gaussian_weights(sigma, order, truncate), np.ones(1), getattr(cv2, _CV_BORDERS[mode])
    if axis == 0:  # across the inlines: an image (inline, sample) per crossline
        for j in range(window.shape[1]):
            cv2.sepFilter2D(window[:, j], cv2.CV_32F, one, weights, dst=out[:, j], borderType=edge)
    else:  # an image (crossline, sample) per inline: filtered across its rows (axis 1) or along them (axis 2)
        kx, ky = (one, weights) if axis == 1 else (weights, one)
        for i in range(window.shape[0]):
            cv2.sepFilter2D(window[i], cv2.CV_32F, kx, ky, dst=out[i], borderType=edge)
    return out[(slice(None),) * axis + (slice(lo - a, hi - a),)] if (a, b) != (lo, hi) else out


def gaussian3(x: np.ndarray, sigmas, orders=(0, 0, 0)) -> np.ndarray:
    """Separable Gaussian (derivative) filter of a 3D array (:func:`gaussian_pass` along each axis), float32; axes
    with sigma 0 are left alone."""
    out = np.asarray(x, dtype=np.float32)
    for axis, (sig, order) in enumerate(zip(sigmas, orders)):
        out = gaussian_pass(out, axis, float(sig), int(order))
    return out if out is not x else x.astype(np.float32, copy=True)


# Inlines of a cube's structure tensor computed at once (:func:`structure_tensor`): a generated 256^3 cube took 1.0-1.25
# CPU s in slabs of 64, 1.2 in one, 1.3-1.6 in slabs of 32 (OpenCV's passes, 2 threads beside other jobs, 2026-11-28)
TENSOR_SLAB = 64


def structure_tensor(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], two_d: bool, *,
                     slab: int = TENSOR_SLAB, float32: bool = False):
    """The six smoothed components (t00, t01, t02, t11, t12, t22) of the structure tensor of a 3D-shaped array.

    A cube (``two_d`` False) is computed ``slab`` inlines at a time (:func:`structure_tensor_at` on the slab and the
    lines its tensor reads, the gradients' and the tensor's lateral radii beyond it): the same bits as the whole
    cube's in one call, the gradients held for one slab only, and a progress line per slab under the name of the
    step that asks for it (:func:`seismo3d._progress.progress_within`; the throw's reflector slopes).

    ``float32``: the passes summed in float32 by OpenCV (:func:`gaussian_pass32`, a third of the CPU seconds, within
    1e-6 of the largest value), for the throw, whose correlation windows only need the slopes' direction; otherwise
    scipy's passes in double precision (:func:`gaussian_pass`), whose bits the reflector slopes of the horizons, the
    attributes and the fault scan keep (a horizon tracker on a generated cube skipped a cycle on the float32 slopes).
    """
    lat, vert = sigma_tensor
    sg = sigma_gradient
    sig = (lat, 0.0 if two_d else lat, vert)
    # gradients with shared smoothing passes: g0 = D0 G1 G2 f, g1 = G0 D1 G2 f, g2 = G0 G1 D2 f
    if two_d and float32:
        gauss = gaussian_pass32
        g0 = gauss(gauss(f3, 2, sg), 0, sg, 1)
        g2 = gauss(gauss(f3, 0, sg), 2, sg, 1)

        def smooth(t):
            return gauss(gauss(t, 0, lat), 2, vert)

        t00, t02, t22 = smooth(g0 * g0), smooth(g0 * g2), smooth(g2 * g2)
        zero = np.zeros_like(t00)
        return t00, zero, t02, zero, zero, t22
    if two_d:
        g0 = gaussian3(gaussian3(f3, (0.0, 0.0, sg)), (sg, 0.0, 0.0), (1, 0, 0))
        g2 = gaussian3(gaussian3(f3, (sg, 0.0, 0.0)), (0.0, 0.0, sg), (0, 0, 1))
        t00, t02, t22 = (gaussian3(g, sig) for g in (g0 * g0, g0 * g2, g2 * g2))
        zero = np.zeros_like(t00)
        return t00, zero, t02, zero, zero, t22
    n0, reach = f3.shape[0], gaussian_radius(lat) + gaussian_radius(sg)  # the inlines a slab's tensor reads beyond it
    out = tuple(np.empty(f3.shape, dtype=np.float32) for _ in range(6))
    with progress_within(n0, unit="inline") as bar:
        for a in range(0, n0, max(1, int(slab))):
            b = min(a + max(1, int(slab)), n0)
            lo, hi = max(a - reach, 0), min(b + reach, n0)  # clamped at the cube's ends as the whole cube's passes
            structure_tensor_at(f3[lo:hi], sg, sigma_tensor, (slice(a - lo, b - lo), slice(None)),
                                out=tuple(whole[a:b] for whole in out), float32=float32)
            bar.advance(b - a, status="structure tensor")
    return out


def structure_tensor_at(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], core, *,
                        out=None, float32: bool = False):
    """:func:`structure_tensor` of a cube at ``core`` only (``(rows, cols)`` slices of its first two axes; all of
    them: the whole cube's tensor), the same bits as the whole cube's there: the gradients with shared smoothing
    passes (g0 = D0 G1 G2 f, g1 = G0 D1 G2 f, g2 = G0 G1 D2 f), each pass computing only the lines its later passes
    read (its outputs within the later lateral radius of ``core``: :func:`gaussian_pass` ``keep``), so the tensor's
    wide vertical pass runs at ``core``'s traces only; the products in an order that frees each gradient as soon as
    possible (peak memory). Returns the six components, each of ``f3[core]``'s shape, float32 (written into ``out``,
    six arrays of that shape with contiguous inlines, when given). The passes are :func:`gaussian_pass32`'s with
    ``float32``, else :func:`gaussian_pass`'s (as :func:`structure_tensor`)."""
    gauss = gaussian_pass32 if float32 else gaussian_pass
    sg, (lat, vert) = sigma_gradient, sigma_tensor
    r = gaussian_radius(lat)
    spans = [s.indices(n)[:2] for s, n in zip(core, f3.shape[:2])]
    wide = [(max(a - r, 0), min(b + r, n)) for (a, b), n in zip(spans, f3.shape[:2])]  # the lines the tensor reads
    inner = [(a - w, b - w) for (a, b), (w, _) in zip(spans, wide)]  # core within them

    f2 = gauss(f3, 2, sg)
    g0 = gauss(gauss(f2, 1, sg, 0, wide[1]), 0, sg, 1, wide[0])
    g1 = gauss(gauss(f2, 0, sg, 0, wide[0]), 1, sg, 1, wide[1])
    del f2
    g2 = gauss(gauss(gauss(f3, 0, sg, 0, wide[0]), 1, sg, 0, wide[1]), 2, sg, 1)

    def smooth(t, k):
        lateral = gauss(gauss(t, 0, lat, 0, inner[0]), 1, lat, 0, inner[1])
        if float32:
            return gaussian_pass32(lateral, 2, vert, out=None if out is None else out[k])
        if out is None:
            return gaussian_pass(lateral, 2, vert)
        out[k][...] = gaussian_pass(lateral, 2, vert)
        return out[k]

    t00, t01, t02 = smooth(g0 * g0, 0), smooth(g0 * g1, 1), smooth(g0 * g2, 2)
    del g0
    t11, t12 = smooth(g1 * g1, 3), smooth(g1 * g2, 4)
    del g1
    return t00, t01, t02, t11, t12, smooth(g2 * g2, 5)


def tensor_eig(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], two_d: bool):
    """Normals (n0, n1, nt, 3) and planarity of a 3D-shaped array (2D sections as (n, 1, nt))."""
    t = structure_tensor(f3, sigma_gradient, sigma_tensor, two_d)
    normals = np.empty(f3.shape + (3,), dtype=np.float32)
    planarity = np.empty(f3.shape, dtype=np.float32)
    eig_normals(*t, normals, planarity)
    return normals, planarity


def tensor_planarity(f3: np.ndarray, sigma_gradient: float, sigma_tensor: tuple[float, float], two_d: bool):
    """Planarity (n0, n1, nt) float32 of a 3D-shaped array (2D sections as (n, 1, nt)), without keeping the
    normals: computed in slabs of inlines so that the normals' workspace stays small. Where the tensor is zero (no
    gradient in its window: constant amplitudes) the planarity is 1, so that the semblance it weights decides alone
    (constant data is as coherent as it gets; all-zero data is dead by its semblance denominator)."""
    t = structure_tensor(f3, sigma_gradient, sigma_tensor, two_d)
    planarity = np.empty(f3.shape, dtype=np.float32)
    slab = max(1, (1 << 24) // max(1, f3.shape[1] * f3.shape[2]))
    for a in range(0, f3.shape[0], slab):
        b = min(a + slab, f3.shape[0])
        normals = np.empty((b - a,) + f3.shape[1:] + (3,), dtype=np.float32)
        eig_normals(*(c[a:b] for c in t), normals, planarity[a:b])
        flat = (t[0][a:b] == 0) & (t[3][a:b] == 0) & (t[5][a:b] == 0)  # a zero trace: a zero tensor
        planarity[a:b][flat] = 1.0
    return planarity


def slopes_from_normals(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    nz = np.maximum(normals[..., 2], 1.0 / MAX_SLOPE / 2.0)
    p0 = np.clip(-normals[..., 0] / nz, -MAX_SLOPE, MAX_SLOPE).astype(np.float32)
    p1 = np.clip(-normals[..., 1] / nz, -MAX_SLOPE, MAX_SLOPE).astype(np.float32)
    return p0, p1


def reflector_slopes(f3: np.ndarray, two_d: bool, sigma_gradient: float, sigma_tensor,
                     as_float32_normals: bool = False, core=None, float32: bool = False) -> tuple:
    """Reflector slopes (p0, p1) in samples per trace of a 3D-shaped array, without storing the normals; with
    ``as_float32_normals`` equal bit for bit to those of :func:`tensor_eig`'s normals (:func:`slopes_from_normals`).
    ``core``: ``(rows, cols)`` slices of a cube's first two axes; the slopes of those traces only (the tensor
    smoothed over the lines of ``f3`` it reads and at ``core``, :func:`structure_tensor_at`, and eigen-decomposed
    there: the same bits as the whole array's slopes at ``core``). ``float32``: the tensor's passes in float32
    (:func:`structure_tensor`)."""
    if core is None:
        t = structure_tensor(f3, sigma_gradient, sigma_tensor, two_d, float32=float32)
    else:
        t = structure_tensor_at(f3, sigma_gradient, sigma_tensor, core, float32=float32)
    p0 = np.empty(t[0].shape, dtype=np.float32)
    p1 = np.empty(t[0].shape, dtype=np.float32)
    eig_slopes(*t, MAX_SLOPE, p0, p1, bool(as_float32_normals))
    return p0, p1


@nb.njit(cache=True, no_cfunc_wrapper=True)
def search_left(keys, value):
    # np.searchsorted(keys, value) of sorted keys (integers, or floats with NaN last): the first index whose key is
    # >= value (a plain binary search compiles in a fraction of numba's generic searchsorted)
    lo, hi = 0, keys.size
    while lo < hi:
        mid = (lo + hi) >> 1
        if keys[mid] < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@nb.njit(cache=True, no_cfunc_wrapper=True)
def search_right(keys, value):
    # np.searchsorted(keys, value, side="right") of sorted keys (as search_left): the first index whose key is > value
    lo, hi = 0, keys.size
    while lo < hi:
        mid = (lo + hi) >> 1
        if keys[mid] <= value:
            lo = mid + 1
        else:
            hi = mid
    return lo

