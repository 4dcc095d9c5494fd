"""Robust kernels as iteratively-reweighted-least-squares weights.

References
----------
Zhang, Z. (1997). Parameter estimation techniques: a tutorial with application to conic fitting.
Image and Vision Computing 15(1), 59-76. doi:10.1016/S0262-8856(96)01112-2
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice

__all__ = ["KERNELS", "robust_weights"]

KERNELS = ("none", "huber", "tukey", "cauchy")


def robust_weights(residuals, kernel: str, scale: float) -> np.ndarray:
    """IRLS weights ``w(r) = rho'(r) / r`` of a robust kernel.

    Parameters
    ----------
    residuals : (N,) array_like
        Residual magnitudes (any sign), in the unit of ``scale``.
    kernel : {'none', 'huber', 'tukey', 'cauchy'}
        ``huber``: 1 for |r| <= k, k/|r| beyond; ``tukey`` (biweight): (1 - (r/c)^2)^2 inside c, 0 outside;
        ``cauchy``: 1 / (1 + (r/c)^2).
    scale : float
        The kernel's k or c, in the residuals' unit.

    Returns
    -------
    (N,) float64 ndarray in [0, 1]
    """
    check_choice(kernel, "kernel", KERNELS)
    r = np.abs(np.asarray(residuals, dtype=np.float64))
    if kernel == "none":
        return np.ones_like(r)
    if kernel == "huber":
        return np.minimum(1.0, scale / np.maximum(r, 1e-300))
    if kernel == "tukey":
        u = r / scale
        return np.where(u < 1.0, (1.0 - u * u) ** 2, 0.0)
    return 1.0 / (1.0 + (r / scale) ** 2)
