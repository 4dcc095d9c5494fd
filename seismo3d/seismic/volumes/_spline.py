"""A cubic B-spline volume and linear volumes sampled at scattered points: the refinement's hot loop.

``scipy.ndimage.map_coordinates`` gives a spline's values, not its derivative: a central difference of it along each
axis costs six more interpolations per point. The derivative of the cubic B-spline basis is closed-form (Unser 1999,
eq. 5: ``d/dx beta3(x) = beta2(x + 1/2) - beta2(x - 1/2)``), so the gradient comes from the same coefficients and the
same 4 x 4 x 4 neighbourhood as the value (:func:`spline_gradients`). The refinement samples two volumes at some
20,000 points a few hundred times per registration; ``map_coordinates`` spends most of that time on its general
N-dimensional machinery (about 10 ms for the cubic values and 3.5 ms per trilinear volume at 20,000 points, against
2-3 ms here for the values and three trilinear volumes together), so :func:`spline_values` and
:func:`linear_values` give the same numbers as ``map_coordinates(..., order=3, prefilter=False, mode='mirror')`` and
``map_coordinates(..., order=1, mode='nearest')`` (in double precision) in one pass each.

References
----------
.. [1] M. Unser, "Splines: a perfect fit for signal and image processing", IEEE Signal Process. Mag. 16(6), 22-38,
   1999, doi:10.1109/79.799930.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["linear_values", "spline_gradients", "spline_values"]


@numba.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _mirror(i: int, n: int) -> int:
    """Index ``i`` of an axis of ``n`` coefficients, reflected as scipy.ndimage's mode 'mirror' (no edge repeat)."""
    if n == 1:
        return 0
    period = 2 * (n - 1)
    i = abs(i) % period
    return period - i if i >= n else i


@numba.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _weights(t: float, w, d) -> None:
    """Cubic B-spline weights ``w`` of the 4 coefficients around a point ``t`` (in [0, 1)) past the first inner
    one, and their derivatives ``d``."""
    s = 1.0 - t
    w[0] = s * s * s / 6.0
    w[1] = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0
    w[2] = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0
    w[3] = t * t * t / 6.0
    d[0] = -0.5 * s * s
    d[1] = 1.5 * t * t - 2.0 * t
    d[2] = -1.5 * t * t + t + 0.5
    d[3] = 0.5 * t * t


@numba.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _spline(coefficients, pts, values, gradients, with_gradients):
    """Values (and with ``with_gradients`` the gradients) of the spline at the (3, N) points into ``values`` (N,)
    and ``gradients`` (3, N): one kernel for both (each numba kernel compiles once per install, about 1 CPU s)."""
    n0, n1, n2 = coefficients.shape
    w = np.empty((3, 4))
    d = np.empty((3, 4))
    idx = np.empty((3, 4), dtype=np.int64)
    dims = (n0, n1, n2)
    for p in range(pts.shape[1]):
        for a in range(3):
            x = pts[a, p]
            f = np.floor(x)
            _weights(x - f, w[a], d[a])
            for k in range(4):
                idx[a, k] = _mirror(int(f) - 1 + k, dims[a])
        v = 0.0
        g0 = 0.0
        g1 = 0.0
        g2 = 0.0
        for i in range(4):
            for j in range(4):
                c0 = 0.0  # sum over the third axis: with its weights, and their derivatives
                c2 = 0.0
                for k in range(4):
                    c = coefficients[idx[0, i], idx[1, j], idx[2, k]]
                    c0 += w[2, k] * c
                    if with_gradients:
                        c2 += d[2, k] * c
                v += w[0, i] * w[1, j] * c0
                if with_gradients:
                    g0 += d[0, i] * w[1, j] * c0
                    g1 += w[0, i] * d[1, j] * c0
                    g2 += w[0, i] * w[1, j] * c2
        values[p] = v
        if with_gradients:
            gradients[0, p] = g0
            gradients[1, p] = g1
            gradients[2, p] = g2


def spline_gradients(coefficients, pts) -> np.ndarray:
    """The gradient of a cubic B-spline volume at points: the exact derivative of what
    ``scipy.ndimage.map_coordinates(coefficients, pts, order=3, prefilter=False, mode='mirror')`` interpolates.

    Parameters
    ----------
    coefficients : (n0, n1, n2) float32 or float64 ndarray
        Cubic B-spline coefficients (``scipy.ndimage.spline_filter(data, order=3, mode='mirror')``).
    pts : (3, N) float64 ndarray
        Index coordinates.

    Returns
    -------
    (3, N) float64 ndarray
        Derivatives along the three axes, per index unit.
    """
    out = np.empty((3, pts.shape[1]))
    _spline(np.ascontiguousarray(coefficients), np.ascontiguousarray(pts, dtype=np.float64), np.empty(pts.shape[1]),
            out, True)
    return out


def spline_values(coefficients, pts) -> np.ndarray:
    """The values of a cubic B-spline volume at points: what
    ``scipy.ndimage.map_coordinates(coefficients, pts, order=3, prefilter=False, mode='mirror')`` interpolates, in
    double precision.

    Parameters
    ----------
    coefficients : (n0, n1, n2) float32 or float64 ndarray
        Cubic B-spline coefficients (``scipy.ndimage.spline_filter(data, order=3, mode='mirror')``).
    pts : (3, N) float64 ndarray
        Index coordinates, within half a sample of the volume (the mirror extends it beyond).

    Returns
    -------
    (N,) float64 ndarray
    """
    out = np.empty(pts.shape[1])
    _spline(np.ascontiguousarray(coefficients), np.ascontiguousarray(pts, dtype=np.float64), out, np.empty((3, 0)),
            False)
    return out


@numba.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _linear(volumes, pts, out):
    n_vol = volumes.shape[0]
    dims = volumes.shape[1:]
    lo = np.empty(3, dtype=np.int64)
    hi = np.empty(3, dtype=np.int64)
    t = np.empty(3)
    for p in range(pts.shape[1]):
        for a in range(3):
            x = min(max(pts[a, p], 0.0), dims[a] - 1.0)  # mode 'nearest': the coordinate clamped to the volume
            f = np.floor(x)
            lo[a] = int(f)
            hi[a] = min(lo[a] + 1, dims[a] - 1)
            t[a] = x - f
        for v in range(n_vol):
            acc = 0.0
            for i in range(2):
                wi = t[0] if i else 1.0 - t[0]
                ii = hi[0] if i else lo[0]
                for j in range(2):
                    wj = t[1] if j else 1.0 - t[1]
                    jj = hi[1] if j else lo[1]
                    acc += wi * wj * ((1.0 - t[2]) * volumes[v, ii, jj, lo[2]] + t[2] * volumes[v, ii, jj, hi[2]])
            out[v, p] = acc


def linear_values(volumes, pts) -> np.ndarray:
    """Several volumes of one shape interpolated linearly at points: what
    ``scipy.ndimage.map_coordinates(volume, pts, order=1, mode='nearest')`` gives for each, in double precision.

    Parameters
    ----------
    volumes : (n_volumes, n0, n1, n2) float32 or float64 ndarray
    pts : (3, N) float64 ndarray
        Index coordinates (clamped to the volume, as mode 'nearest').

    Returns
    -------
    (n_volumes, N) float64 ndarray
    """
    out = np.empty((volumes.shape[0], pts.shape[1]))
    _linear(np.ascontiguousarray(volumes), np.ascontiguousarray(pts, dtype=np.float64), out)
    return out
