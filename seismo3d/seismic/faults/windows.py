"""Lateral windows of a cube (whole traces) with their reflector slopes, for measurements that read a cube only near a
fault (:func:`seismo3d.seismic.fault_throws`).

A *window source* hands out :class:`CubeWindow` s: ``source.window(i0, i1, j0, j1)`` holds at least the traces
``[i0, i1) x [j0, j1)`` (every sample) with the reflector slopes of :func:`structure_tensor_orientation` over them,
equal to those of the whole cube. Two sources, one interface:

- :class:`ArrayWindows`: an in-memory cube (or 2D section) and its orientation, computed once; every window is the
  whole array (nothing is copied or recomputed).
- :class:`LazyWindows`: a 3D ``dask.array.Array`` (e.g. ``seismo3d.open(path).data``), never held
  whole: each window reads the requested traces plus the halo of the structure tensor's filters
  (:func:`structure_tensor_halo`), clipped at the cube's edges, and computes the slopes there. Away from the window's
  inner sides (the halo) they equal the whole cube's; at the cube's edges the filters clamp as on the whole cube.

Positions are index coordinates of the whole cube (axis 0 inline, axis 1 crossline, axis 2 sample); a window reads
them shifted by its origin, so the same code runs on either source.
"""

from __future__ import annotations

import sys
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..._validation import as_seismic, check_int, check_positive, check_seismic_layout
from ...errors import InputError
from ..attributes import ReflectorOrientation, structure_tensor_halo, structure_tensor_slopes

__all__ = ["ArrayWindows", "CubeWindow", "LazyWindows", "StoredWindows", "cube_windows", "is_dask_array"]


@dataclass(frozen=True, eq=False)
class CubeWindow:
    """A block of whole traces of a cube with the reflector slopes over it.

    Attributes
    ----------
    amplitude : (m0, m1, n_samples) float32 ndarray
        The traces ``[origin[0], origin[0] + m0) x [origin[1], origin[1] + m1)`` of the cube (a 2D section as
        ``(n_traces, 1, n_samples)``).
    slope_inline, slope_xline : (m0, m1, n_samples) float32 ndarray
        Reflector slopes along the inline and crossline axes over the window, samples per trace (zeros along the
        crossline of a 2D section), equal to the whole cube's inside the window's halo.
    origin : (int, int)
        Inline and crossline index (in the cube) of the window's first trace.
    cube_shape : (int, int, int)
        Shape of the whole cube ``(n_inlines, n_xlines, n_samples)`` (``(n_traces, 1, n_samples)`` for a section):
        the bounds that reads are tested against.
    """

    amplitude: np.ndarray
    slope_inline: np.ndarray
    slope_xline: np.ndarray
    origin: tuple
    cube_shape: tuple

    def _read(self, field, il, xl, t) -> np.ndarray:
        # the cube coordinates shifted into the window (exact: the window starts at or below every read, or at 0)
        coords = np.stack([np.asarray(il, np.float64) - self.origin[0], np.asarray(xl, np.float64) - self.origin[1],
                           np.asarray(t, np.float64)])
        return ndi.map_coordinates(field, coords, order=1, mode="nearest")

    def amplitude_at(self, il, xl, t) -> np.ndarray:
        """Amplitude at cube positions, trilinear, clamped at the cube's edges (``scipy.ndimage`` mode 'nearest').

        Parameters
        ----------
        il, xl, t : (n,) array_like of float
            Inline, crossline and sample index coordinates in the whole cube, within the window's traces.

        Returns
        -------
        (n,) float32 ndarray
        """
        return self._read(self.amplitude, il, xl, t)

    def slope_along(self, il, xl, t, direction) -> np.ndarray:
        """Reflector slope along a horizontal unit ``direction`` (inline, crossline) at cube positions, samples per
        trace: ``p_inline d_0 + p_xline d_1``, each slope trilinear as :meth:`amplitude_at`.

        Returns
        -------
        (n,) float64 ndarray
        """
        return (self._read(self.slope_inline, il, xl, t) * direction[0]
                + self._read(self.slope_xline, il, xl, t) * direction[1])


def is_dask_array(data) -> bool:
    """True if ``data`` is a ``dask.array.Array`` (without importing dask when it was never imported)."""
    da = sys.modules.get("dask.array")
    return da is not None and isinstance(data, da.Array)


def _slope_fields(orientation, shape) -> tuple[np.ndarray, np.ndarray]:
    """Reflector slopes along inline and crossline as two (n0, n1, nt) float32 arrays (zeros along xline in 2D)."""
    slopes = np.asarray(getattr(orientation, "slopes", orientation), dtype=np.float32)
    ndim = len(shape)
    if slopes.shape != (ndim - 1, *shape):
        raise InputError(f"orientation.slopes has shape {slopes.shape} but the data needs ({ndim - 1}, *{shape}); pass "
                         "the ReflectorOrientation of this data (structure_tensor_orientation(data))")
    if not np.all(np.isfinite(slopes)):
        raise InputError("orientation.slopes has NaN or inf; recompute it with structure_tensor_orientation(data)")
    if ndim == 2:
        p0 = slopes[0][:, None, :]
        return p0, np.zeros_like(p0)
    return slopes[0], slopes[1]


class ArrayWindows:
    """Windows of an in-memory cube or section: every window is the whole array, with its orientation's slopes.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like
        Seismic amplitudes, finite (converted to float32).
    orientation : ReflectorOrientation, optional
        Of ``data`` (:func:`structure_tensor_orientation`); computed at the first window when not given.

    Attributes
    ----------
    shape : tuple of int
        Shape of ``data`` (2 or 3 axes).

    Raises
    ------
    InputError
        ``data`` is not a finite 2D / 3D numeric array, or ``orientation`` does not match it.
    """

    def __init__(self, data, orientation: ReflectorOrientation | None = None):
        self._arr = as_seismic(data)
        self.shape = self._arr.shape
        self._slopes = None if orientation is None else _slope_fields(orientation, self.shape)
        self._whole = None

    def window(self, i0: int, i1: int, j0: int, j1: int) -> CubeWindow:
        """The whole array (it holds every window ``[i0, i1) x [j0, j1)``), with origin (0, 0); the orientation is
        computed at the first call when it was not given."""
        if self._whole is None:
            if self._slopes is None:
                self._slopes = _slope_fields(structure_tensor_slopes(self._arr, float32=True), self.shape)
            cube = self._arr[:, None, :] if self._arr.ndim == 2 else self._arr
            self._whole = CubeWindow(cube, *self._slopes, (0, 0), cube.shape)
        return self._whole


class LazyWindows:
    """Windows of a 3D dask array of amplitudes, read on demand in tiles whose reflector slopes are computed with
    the halo of the structure tensor and kept in a small cache.

    The cube is cut into tiles of ``tile`` x ``tile`` traces (every sample). A tile is read with
    :func:`structure_tensor_halo` traces more on each side (clipped at the cube's edges), its slopes computed there
    and its own traces kept: their slopes equal the whole cube's. A window is assembled from the tiles it covers;
    the most recently used tiles (up to ``cache_mb``) are kept, so the overlapping windows of neighbouring fault
    patches compute each tile once.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) dask.array.Array
        Seismic amplitudes of any numeric dtype and any chunks (chunks of whole traces read fastest, e.g.
        ``seismo3d.open`` with ``tile``); converted to float32 tile by tile.
    orientation : ReflectorOrientation, optional
        Of the whole cube, in memory: tiles then slice its slopes instead of computing them.
    tile : int
        Tile side, in traces (>= 1).
    cache_mb : float
        Memory of the kept tiles (amplitudes and two slopes, float32), MiB; at least one tile is kept.

    Attributes
    ----------
    shape : (int, int, int)
        Shape of ``data``.
    halo : int
        Traces read beyond each side of a tile (:func:`structure_tensor_halo` of the default widths of
        :func:`structure_tensor_orientation`); 0 when ``orientation`` is given.

    Raises
    ------
    InputError
        ``data`` is not 3D, not numeric, or has an axis shorter than 3; ``orientation`` does not match it; ``tile``
        or ``cache_mb`` out of range. A tile holding NaN or inf raises when it is read.
    """

    def __init__(self, data, orientation: ReflectorOrientation | None = None, *, tile: int = 64,
                 cache_mb: float = 256.0):
        if data.ndim != 3:
            raise InputError(f"data must be a 3D dask array (n_inlines, n_xlines, n_samples) for the windowed path; got "
                             f"shape {data.shape}; pass a 2D section as a numpy array")
        check_seismic_layout(data.shape, data.dtype)
        self.shape = tuple(int(n) for n in data.shape)
        self._data = data
        self._tile = check_int(tile, "tile", minimum=1)
        tile_bytes = 3 * 4 * self._tile ** 2 * self.shape[2]
        self._max_tiles = max(1, int(check_positive(cache_mb, "cache_mb") * 2**20 // tile_bytes))
        self._slopes = None if orientation is None else _slope_fields(orientation, self.shape)
        self.halo = 0 if orientation is not None else structure_tensor_halo()[0]
        self._cache = OrderedDict()

    def _tile_fields(self, ti: int, tj: int) -> tuple:
        """Amplitudes and slopes (p0, p1) of tile (ti, tj), each (m0, m1, n_samples) float32, from the cache."""
        key = (ti, tj)
        if key in self._cache:
            self._cache.move_to_end(key)
            return self._cache[key]
        n0, n1, _ = self.shape
        t = self._tile
        i0, i1, j0, j1 = ti * t, min((ti + 1) * t, n0), tj * t, min((tj + 1) * t, n1)
        a0, a1 = max(i0 - self.halo, 0), min(i1 + self.halo, n0)
        b0, b1 = max(j0 - self.halo, 0), min(j1 + self.halo, n1)
        block = as_seismic(np.asarray(self._data[a0:a1, b0:b1, :].compute()), "data", min_size=1)
        if self._slopes is not None:
            p0, p1 = (p[a0:a1, b0:b1] for p in self._slopes)
        else:
            p0, p1 = structure_tensor_slopes(block, float32=True)
        core = (slice(i0 - a0, i1 - a0), slice(j0 - b0, j1 - b0))
        fields = tuple(np.ascontiguousarray(f[core]) for f in (block, p0, p1))
        self._cache[key] = fields
        while len(self._cache) > self._max_tiles:
            self._cache.popitem(last=False)
        return fields

    def window(self, i0: int, i1: int, j0: int, j1: int) -> CubeWindow:
        """The tiles covering traces ``[i0, i1) x [j0, j1)`` (clipped to the cube), every sample, with their
        reflector slopes.

        Parameters
        ----------
        i0, i1, j0, j1 : int
            Inline and crossline index ranges (half-open) of the traces needed.

        Returns
        -------
        CubeWindow
            Its origin is a tile corner; its slopes equal the whole cube's everywhere in it.

        Raises
        ------
        InputError
            The traces read hold NaN or inf.
        """
        n0, n1, nt = self.shape
        t = self._tile
        ti0, tj0 = max(int(i0), 0) // t, max(int(j0), 0) // t
        ti1, tj1 = max(-(-min(int(i1), n0) // t), ti0 + 1), max(-(-min(int(j1), n1) // t), tj0 + 1)
        a0, b0 = ti0 * t, tj0 * t
        a1, b1 = min(ti1 * t, n0), min(tj1 * t, n1)
        out = [np.empty((a1 - a0, b1 - b0, nt), np.float32) for _ in range(3)]
        for ti in range(ti0, ti1):
            for tj in range(tj0, tj1):
                fields = self._tile_fields(ti, tj)
                rows = slice(ti * t - a0, ti * t - a0 + fields[0].shape[0])
                cols = slice(tj * t - b0, tj * t - b0 + fields[0].shape[1])
                for dst, src in zip(out, fields):
                    dst[rows, cols] = src
        return CubeWindow(out[0], out[1], out[2], (a0, b0), self.shape)


class StoredWindows:
    """Windows of a cube whose reflector slopes were computed beforehand (block by block, e.g. by
    :func:`~seismo3d.seismic.faults.surfaces.blocks.chunked_fault_surfaces`) and stored: each window reads exactly
    its traces of the amplitudes and of the two slope arrays, and nothing is computed or cached (memory: one window).

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) dask.array.Array or array-like read by slicing (Zarr)
        Seismic amplitudes.
    slope_inline, slope_xline : (n_inlines, n_xlines, n_samples) array-like read by slicing (Zarr)
        Reflector slopes along inline and crossline, samples per trace, equal to those of
        :func:`structure_tensor_orientation` on the whole cube.

    Attributes
    ----------
    shape : (int, int, int)

    Raises
    ------
    InputError
        The three arrays differ in shape or are not 3D; a window holding NaN or inf when it is read.
    """

    def __init__(self, data, slope_inline, slope_xline):
        shapes = {tuple(int(n) for n in a.shape) for a in (data, slope_inline, slope_xline)}
        if len(shapes) != 1 or len(next(iter(shapes))) != 3:
            raise InputError(f"amplitudes and slopes must be 3D arrays of one shape; got {sorted(shapes)}")
        self.shape = shapes.pop()
        self._arrays = (data, slope_inline, slope_xline)

    def window(self, i0: int, i1: int, j0: int, j1: int) -> CubeWindow:
        """Traces ``[i0, i1) x [j0, j1)`` (clipped to the cube), every sample, with their slopes.

        Returns
        -------
        CubeWindow
        """
        n0, n1, _ = self.shape
        a0, a1, b0, b1 = max(int(i0), 0), min(int(i1), n0), max(int(j0), 0), min(int(j1), n1)
        a1, b1 = max(a1, a0 + 1), max(b1, b0 + 1)
        fields = []
        for arr in self._arrays:
            block = arr[a0:a1, b0:b1, :]
            block = block.compute() if hasattr(block, "compute") else block
            fields.append(np.ascontiguousarray(block, dtype=np.float32))
        if not np.all(np.isfinite(fields[0])):
            raise InputError(f"the cube holds NaN or inf in inlines {a0}-{a1 - 1}, crosslines {b0}-{b1 - 1} "
                             "(indices); replace them (e.g. by 0)")
        return CubeWindow(fields[0], fields[1], fields[2], (a0, b0), self.shape)


def cube_windows(data, orientation: ReflectorOrientation | None = None
                 ) -> ArrayWindows | LazyWindows | StoredWindows:
    """The window source of ``data``: :class:`LazyWindows` for a 3D dask array, else :class:`ArrayWindows`.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) or (n_traces, n_samples) array_like, 3D dask.array.Array, or a source
        Seismic amplitudes (a 2D dask array is read whole: a section fits in memory), or an :class:`ArrayWindows` /
        :class:`LazyWindows` / :class:`StoredWindows` already made (returned as it is: e.g. a ``LazyWindows`` with
        another ``tile`` or ``cache_mb``).
    orientation : ReflectorOrientation, optional
        Of ``data``; computed by the source when not given (once for an in-memory array, per tile for a lazy one).

    Returns
    -------
    ArrayWindows or LazyWindows
        Both have ``shape`` and ``window(i0, i1, j0, j1) -> CubeWindow``.

    Raises
    ------
    InputError
        As :class:`ArrayWindows` / :class:`LazyWindows`; ``orientation`` given with a source.
    """
    if isinstance(data, (ArrayWindows, LazyWindows, StoredWindows)):
        if orientation is not None:
            raise InputError("orientation was given with a window source; pass it to the source instead "
                             "(LazyWindows(data, orientation))")
        return data
    if is_dask_array(data) and data.ndim == 3:
        return LazyWindows(data, orientation)
    return ArrayWindows(data, orientation)
