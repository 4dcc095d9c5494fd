"""Resampling a volume onto another grid through an index-space transform.

E.g. the moving volume onto the fixed grid after :func:`~seismo3d.seismic.register_volumes`, with a cubic B-spline.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..._validation import check_int
from ...errors import InputError
from ...geometry.transforms import as_transform
from .inputs import as_volume

__all__ = ["resample_volume"]


def resample_volume(volume, transform_index, shape, *, order: int = 3, fill: float = np.nan) -> np.ndarray:
    """Resample a volume onto another grid through an index-space transform, e.g. MOVING onto FIXED after registration.

    ``out[p] = volume(T^-1 p)`` for every integer index ``p`` of the output grid, where ``T = transform_index`` maps
    the volume's index coordinates to the output's (the convention of
    :attr:`~seismo3d.seismic.volumes.VolumeRegistration.transform_index`), with a cubic B-spline (``order=3``)
    between samples.

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) array_like
        Amplitudes, any real dtype; finite.
    transform_index : (4, 4) array_like of float
        Invertible affine map from the volume's index coordinates (inline, crossline, sample) to the output's.
    shape : tuple of 3 int
        Output shape (n_inlines, n_xlines, n_samples).
    order : int in [0, 5]
        Spline order of :func:`scipy.ndimage.map_coordinates` (0 nearest, 1 linear, 3 cubic).
    fill : float
        Value of output samples that fall outside the volume (by more than half a sample).

    Returns
    -------
    (shape) float32 ndarray

    Raises
    ------
    InputError
        A volume that is not a finite 3D array, a transform that is not an invertible 4x4 affine map, a bad shape or
        order.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.random.default_rng(0).normal(size=(8, 8, 8))
    >>> shift = np.eye(4); shift[:3, 3] = (1, 0, 0)          # output inline i is volume inline i - 1
    >>> out = resample_volume(v, shift, (8, 8, 8))
    >>> bool(np.allclose(out[1:], v[:-1], atol=1e-5)), bool(np.isnan(out[0]).all())
    (True, True)
    """
    arr = as_volume(volume, "volume", None).data
    t = as_transform(transform_index, "transform_index", dims=(3,))
    try:
        t_inv = np.linalg.inv(t)
    except np.linalg.LinAlgError as exc:
        raise InputError("transform_index is singular; pass an invertible affine map (e.g. a registration's "
                         "transform_index)") from exc
    try:
        shape = tuple(int(n) for n in shape)
    except (TypeError, ValueError) as exc:
        raise InputError(f"shape must be three ints; got {shape!r}") from exc
    if len(shape) != 3 or min(shape) < 1:
        raise InputError(f"shape must be three ints >= 1 (n_inlines, n_xlines, n_samples); got {shape}")
    order = check_int(order, "order", minimum=0, maximum=5)
    out = np.empty(shape, np.float32)
    hi = np.array(arr.shape, dtype=np.float64)[:, None] - 0.5
    grid = np.indices(shape[1:]).reshape(2, -1).astype(np.float64)
    # the B-spline coefficients once for all output inlines, as map_coordinates' own prefilter makes them (the data
    # padded by its edge values, mode="nearest"), instead of once per inline
    pad = 12 if int(order) > 1 else 0
    coef = ndi.spline_filter(np.pad(arr, pad, mode="edge"), int(order), mode="nearest") if pad else arr
    for i in range(shape[0]):  # one output inline at a time keeps the coordinate arrays small
        p = np.vstack([np.full(grid.shape[1], float(i)), grid])
        m = t_inv[:3, :3] @ p + t_inv[:3, 3:]
        vals = ndi.map_coordinates(coef, m + pad, order=int(order), prefilter=False, mode="nearest")
        vals[~np.all((m >= -0.5) & (m <= hi), axis=0)] = fill
        out[i] = vals.reshape(shape[1:])
    return out
