"""The gradient of a cubic B-spline volume at scattered points, in one pass over its 64 coefficients per point.

``scipy.ndimage.map_coordinates`` gives a spline's values, not its derivative: a central difference of it along each
axis costs six more interpolations per point. The derivative of the cubic B-spline basis is closed-form (Unser 1999,
eq. 5: ``d/dx beta3(x) = beta2(x + 1/2) - beta2(x - 1/2)``), so the gradient comes from the same coefficients and the
same 4 x 4 x 4 neighbourhood as the value.

References
----------
.. [1] M. Unser, "Splines: a perfect fit for signal and image processing", IEEE Signal Process. Mag. 16(6), 22-38,
   1999, doi:10.1109/79.799930.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["spline_gradients"]


@numba.njit(cache=True, inline="always")
def _mirror(i: int, n: int) -> int:
    """Index ``i`` of an axis of ``n`` coefficients, reflected as scipy.ndimage's mode 'mirror' (no edge repeat)."""
    if n == 1:
        return 0
    period = 2 * (n - 1)
    i = abs(i) % period
    return period - i if i >= n else i


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, nogil=True)
def _gradients(coefficients, pts, out):
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
                    c2 += d[2, k] * c
                g0 += d[0, i] * w[1, j] * c0
                g1 += w[0, i] * d[1, j] * c0
                g2 += w[0, i] * w[1, j] * c2
        out[0, p] = g0
        out[1, p] = g1
        out[2, p] = g2


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
    _gradients(np.ascontiguousarray(coefficients), np.ascontiguousarray(pts, dtype=np.float64), out)
    return out
