"""Test pairs of sub-volume registration: a fixed block of a cube and a moving block resampled from it on another grid,
with the exact map between them (:func:`resampled_pair`, :func:`random_grid_pair`).

Index space as in :mod:`seismo3d.data.synthetic` (axis 0 inline, axis 1 crossline, axis 2 sample); maps are moving
index to fixed index (4, 4) homogeneous transforms, as :func:`seismo3d.seismic.register_volumes` returns them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["GridPair", "random_grid_pair", "resampled_pair"]


def resampled_pair(volume, fixed_shape, *, scales=(1.0, 1.0, 1.0), angle_deg: float = 0.0, offset=(0.0, 0.0, 0.0),
                   moving_fraction: float = 0.75, fixed_scales=(1.0, 1.0, 1.0), moving_shape=None):
    """Cut a fixed sub-volume and an overlapping, resampled and rotated moving sub-volume with the exact transform.

    The test pair of sub-volume registration (:func:`seismo3d.seismic.register_volumes`): ``fixed`` samples the centre
    of ``volume`` on a grid of ``fixed_shape`` whose axes are ``volume``'s scaled by ``fixed_scales`` (with unit
    ``fixed_scales``, the default, it is the centre ``fixed_shape`` of ``volume`` itself, no interpolation); ``moving``
    samples ``volume`` on a grid whose axes are ``volume``'s scaled by ``scales`` and rotated in map view by
    ``angle_deg`` (inline towards crossline), centred on the fixed centre plus ``offset``. A scale above 1 makes the
    bins / sample interval coarser. With scales on both volumes the index map is
    ``diag(fixed_scales)^-1 R diag(scales)``, which no per-axis scale on one side alone expresses. The samples are
    interpolated with a Lanczos-3 windowed sinc (along the sample axis, then in map view), not with the cubic
    B-spline that registration resamples with: a pair made with the registration's own interpolator would be matched
    by running it backwards.

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) array_like
        Source amplitudes (a synthetic or a real cube); finite.
    fixed_shape : tuple of 3 int
        Shape of the fixed sub-volume, at most ``volume.shape``.
    scales : (3,) float
        Moving inline, crossline and sample spacing in traces / samples of ``volume`` (each > 0).
    angle_deg : float
        Map-view rotation of the moving axes, degrees.
    offset : (3,) float
        Position of the moving centre relative to the fixed centre, fixed index units.
    moving_fraction : float in (0, 1]
        Extent of the moving volume along each of its axes, as a fraction of the fixed extent (before rotation).
    fixed_scales : (3,) float
        Fixed inline, crossline and sample spacing in traces / samples of ``volume`` (each > 0);
        ``fixed_shape * fixed_scales`` must fit in ``volume``.
    moving_shape : tuple of 3 int, optional
        Shape of the moving volume (each at least 8), instead of the one ``moving_fraction`` gives.

    Returns
    -------
    fixed : (fixed_shape) float32 ndarray
    moving : (n_inlines', n_xlines', n_samples') float32 ndarray
        Each axis at least 8. Samples whose position falls outside ``volume`` are 0 (dead traces).
    transform_index : (4, 4) float64 ndarray
        The exact map from moving index coordinates to fixed index coordinates.

    Raises
    ------
    InputError
        A volume that is not a finite 3D array of at least 8 per axis, a fixed grid larger than it, non-positive
        scales or a moving shape under 8.

    References
    ----------
    .. [1] C. E. Duchon, "Lanczos filtering in one and two dimensions", J. Appl. Meteorology 18(8), 1016-1022, 1979,
       doi:10.1175/1520-0450(1979)018<1016:LFIOAT>2.0.CO;2.
    """
    arr = np.asarray(volume, dtype=np.float32)
    if arr.ndim != 3:
        raise InputError(f"volume must be 3D (n_inlines, n_xlines, n_samples); got shape {arr.shape}")
    nb, nf = np.array(arr.shape), np.array(fixed_shape, dtype=int)
    scales = np.asarray(scales, dtype=np.float64)
    fixed_scales = np.asarray(fixed_scales, dtype=np.float64)
    for name, value in (("scales", scales), ("fixed_scales", fixed_scales)):
        if value.shape != (3,) or not np.all(value > 0):
            raise InputError(f"{name} must be 3 numbers > 0; got {value.tolist()}")
    if nf.shape != (3,) or np.any(nf < 8) or np.any((nf - 1) * fixed_scales > nb - 1):
        raise InputError(f"fixed_shape must be 3 ints >= 8 whose grid (fixed_shape - 1) * fixed_scales fits in "
                         f"volume.shape {arr.shape}; got {fixed_shape}")
    if not 0 < moving_fraction <= 1:
        raise InputError(f"moving_fraction must be in (0, 1]; got {moving_fraction}")
    if np.all(fixed_scales == 1.0):  # the centre of the volume itself, on its own samples
        o = ((nb - nf) // 2).astype(np.float64)
        fixed = np.ascontiguousarray(arr[int(o[0]):int(o[0]) + nf[0], int(o[1]):int(o[1]) + nf[1],
                                         int(o[2]):int(o[2]) + nf[2]])
    else:
        o = (nb - 1) / 2 - fixed_scales * (nf - 1) / 2
        to_fixed = np.diag(np.r_[fixed_scales, 1.0])
        to_fixed[:3, 3] = o
        fixed = _lanczos_resample(arr, to_fixed, tuple(nf))
    th = np.radians(angle_deg)
    linear = np.diag(scales)
    linear[:2, :2] = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]]) @ np.diag(scales[:2])
    if moving_shape is None:
        nm = np.maximum((nf * fixed_scales * moving_fraction / scales).astype(int), 8)
    else:
        nm = np.array(moving_shape, dtype=int)
        if nm.shape != (3,) or np.any(nm < 8):
            raise InputError(f"moving_shape must be 3 ints >= 8; got {moving_shape}")
    # moving index -> volume index: centred on the fixed centre plus offset (fixed index units)
    to_volume = np.eye(4)
    to_volume[:3, :3] = linear
    centre = o + fixed_scales * ((nf - 1) / 2 + np.asarray(offset, dtype=np.float64))
    to_volume[:3, 3] = centre - linear @ ((nm - 1) / 2)
    moving = _lanczos_resample(arr, to_volume, tuple(nm))
    from_fixed = np.diag(np.r_[1.0 / fixed_scales, 1.0])
    from_fixed[:3, 3] = -o / fixed_scales
    return fixed, moving, from_fixed @ to_volume


_LANCZOS = 3  # lobes of the windowed sinc of resampled_pair


def _lanczos_weights(frac):
    """Lanczos weights (2a, n) of the taps -a+1..a around points at fractional offsets ``frac`` (n,) past a sample,
    normalised to sum 1 (a constant stays constant)."""
    taps = np.arange(-_LANCZOS + 1, _LANCZOS + 1)[:, None]
    x = frac[None, :] - taps
    w = np.sinc(x) * np.sinc(x / _LANCZOS)
    return taps, w / w.sum(axis=0, keepdims=True)


def _lanczos_axis(values, positions, axis):
    """``values`` interpolated along ``axis`` at ``positions`` (1D, index units); 0 more than half a sample outside."""
    n = values.shape[axis]
    along = [1] * values.ndim
    along[axis] = -1  # broadcasts a (len(positions),) array along `axis`
    base = np.floor(positions).astype(np.int64)
    taps, w = _lanczos_weights(positions - base)
    out = 0.0
    for tap, wt in zip(taps[:, 0], w):
        idx = np.clip(base + tap, 0, n - 1)  # edge samples repeated past the ends
        out = out + np.take(values, idx, axis=axis) * wt.reshape(along)
    inside = (positions >= -0.5) & (positions <= n - 0.5)
    return np.where(inside.reshape(along), out, 0.0)


def _lanczos_resample(volume, to_volume, shape):
    """``out[p] = volume(to_volume @ p)`` by a Lanczos-3 windowed sinc, for a map that scales the sample axis on its
    own (a map-view rotation and per-axis scales, as :func:`resampled_pair` makes): first along the samples, then in
    map view. Positions more than half a sample or trace outside ``volume`` give 0, as in ``resample_volume``."""
    lin, off = to_volume[:3, :3], to_volume[:3, 3]
    vertical = lin[2, 2] * np.arange(shape[2]) + off[2]
    traces = _lanczos_axis(volume.astype(np.float64), vertical, axis=2)  # (n0, n1, shape[2])
    g = np.indices(shape[:2]).reshape(2, -1).astype(np.float64)
    pos = lin[:2, :2] @ g + off[:2, None]
    n0, n1 = volume.shape[:2]
    b0, b1 = np.floor(pos[0]).astype(np.int64), np.floor(pos[1]).astype(np.int64)
    taps, w0 = _lanczos_weights(pos[0] - b0)
    _, w1 = _lanczos_weights(pos[1] - b1)
    out = np.zeros((pos.shape[1], shape[2]))
    for t0, wa in zip(taps[:, 0], w0):
        i0 = np.clip(b0 + t0, 0, n0 - 1)
        for t1, wb in zip(taps[:, 0], w1):
            out += traces[i0, np.clip(b1 + t1, 0, n1 - 1)] * (wa * wb)[:, None]
    inside = (pos[0] >= -0.5) & (pos[0] <= n0 - 0.5) & (pos[1] >= -0.5) & (pos[1] <= n1 - 0.5)
    out[~inside] = 0.0
    return out.reshape(shape).astype(np.float32)


@dataclass(frozen=True)
class GridPair:
    """A pair of :func:`random_grid_pair`: a fixed block of a real cube and a moving block resampled from it.

    Attributes
    ----------
    fixed : (n_inlines, n_xlines, n_samples) float32 ndarray
        A block of the source cube on its own grid.
    moving : (n_inlines', n_xlines', n_samples') float32 ndarray
        The source resampled (Lanczos-3) on a grid rotated ``rotation_deg`` in map view with bins ``scales``,
        its whole footprint inside the fixed block's.
    transform_index : (4, 4) float64 ndarray
        The exact map from moving index coordinates to fixed index coordinates.
    rotation_deg : float
        Map rotation of the moving grid, degrees (inline towards crossline).
    scales : (3,) float64 ndarray
        Moving inline bin, crossline bin and sample interval in source traces / samples.
    corner : (3,) int ndarray
        Index of the fixed block's first sample in the source cube.
    """

    fixed: np.ndarray
    moving: np.ndarray
    transform_index: np.ndarray
    rotation_deg: float
    scales: np.ndarray
    corner: np.ndarray


def random_grid_pair(volume, fixed_shape, rng, *, max_rotation: float = 30.0, lateral_scales=(0.7, 1.4),
                     vertical_scales=(0.9, 1.1), fill=(0.6, 1.0), margin: float = 1.0) -> GridPair:
    """A fixed block of a real cube and a moving block on another grid inside it, drawn at random.

    The fixed block (``fixed_shape``) is cut at a random place of ``volume``, on its own grid. The moving grid has a
    map rotation uniform in +-``max_rotation`` degrees, inline and crossline bins drawn independently (log-uniform)
    from ``lateral_scales``, a sample interval uniform in ``vertical_scales`` (in source traces / samples), and an
    extent along each of its axes between ``fill`` of the largest whose footprint (rotated, in map view) and time
    range fit inside the fixed block, ``margin`` samples in from its edges, at least 8 samples; it is placed at a
    random position inside. Both registration orders are then well posed: the whole moving block lies in the fixed
    one. The moving samples are interpolated by :func:`resampled_pair` (Lanczos-3, from up to 3 samples of the source
    around the fixed block where the source has them).

    Parameters
    ----------
    volume : (n_inlines, n_xlines, n_samples) array_like
        The source cube (real amplitudes); finite.
    fixed_shape : tuple of 3 int
        Shape of the fixed block, at most ``volume.shape``.
    rng : numpy.random.Generator
        The random draws (a seeded generator makes the pairs again).
    max_rotation : float
        Degrees.
    lateral_scales, vertical_scales : (float, float)
        Ranges of the moving bins and sample interval, source traces / samples.
    fill : (float, float)
        Range of the moving extent as a fraction of the largest that fits (per axis, drawn uniformly).
    margin : float
        Samples kept between the moving footprint and the fixed block's edges.

    Returns
    -------
    GridPair

    Raises
    ------
    InputError
        A fixed block larger than the volume, or one too small to hold a rotated moving block of 8 traces per axis
        at the largest scale.
    """
    arr = np.asarray(volume, dtype=np.float32)
    nb, nf = np.array(arr.shape), np.array(fixed_shape, dtype=int)
    if arr.ndim != 3 or nf.shape != (3,) or np.any(nf > nb) or np.any(nf < 8):
        raise InputError(f"fixed_shape must be 3 ints >= 8 within volume.shape {arr.shape}; got {fixed_shape}")
    room = nf - 1 - 2.0 * margin  # the fixed block's extent the moving footprint may use, source samples
    for _ in range(1000):  # draws whose smallest moving block (8 samples per axis) does not fit are drawn again
        theta = rng.uniform(-max_rotation, max_rotation)
        scales = np.r_[np.exp(rng.uniform(*np.log(lateral_scales), size=2)), rng.uniform(*vertical_scales)]
        c, s = abs(np.cos(np.radians(theta))), abs(np.sin(np.radians(theta)))
        least = 7.0 * scales  # extents of 8 samples per axis
        if c * least[0] + s * least[1] > room[0] or s * least[0] + c * least[1] > room[1] or least[2] > room[2]:
            continue
        # the footprint's extents along the fixed map axes are ``foot @ e`` for moving extents e: e in the fixed
        # block's proportions times a random aspect (0.5-2), ``fill`` of the largest that fits, at least ``least``
        foot = np.array([[c, s], [s, c]])
        aspect = np.exp(rng.uniform(np.log(0.5), np.log(2.0)))
        e = room[:2] * np.array([aspect ** 0.5, aspect ** -0.5])
        e = np.maximum(least[:2], rng.uniform(*fill) * e * (room[:2] / (foot @ e)).min())
        for axis in (0, 1):  # an axis raised to its least: the other shrunk to fit beside it
            left = room[:2] - foot[:, 1 - axis] * e[1 - axis]
            e[axis] = min(e[axis], (left / foot[:, axis]).min())
        if np.any(e < least[:2] - 1e-9):
            continue
        ex, ey = e
        ez = max(least[2], rng.uniform(*fill) * room[2])
        n_moving = (np.floor(np.array([ex, ey, ez]) / scales + 1e-9) + 1).astype(int)
        extent = (n_moving - 1) * scales
        half = np.array([c * extent[0] + s * extent[1], s * extent[0] + c * extent[1], extent[2]]) / 2.0
        centre = margin + half + rng.uniform(0.0, 1.0, size=3) * (room - 2.0 * half)  # fixed index
        break
    else:
        raise InputError(f"fixed_shape {tuple(nf)} is too small for a moving block of 8 samples per axis at scales "
                         f"up to {max(lateral_scales)} rotated {max_rotation} degrees; pass a larger fixed_shape")
    # the fixed block at a random place, with up to 3 source samples around it for the interpolation
    corner = np.array([rng.integers(0, nb[k] - nf[k] + 1) for k in range(3)])
    pad = np.minimum(np.minimum(corner, nb - nf - corner), _LANCZOS)
    block = arr[tuple(slice(corner[k] - pad[k], corner[k] + nf[k] + pad[k]) for k in range(3))]
    fixed, moving, truth = resampled_pair(block, tuple(nf), scales=scales, angle_deg=theta,
                                          offset=centre - (nf - 1) / 2.0, moving_shape=tuple(n_moving))
    return GridPair(fixed, moving, truth, float(theta), scales, corner)
