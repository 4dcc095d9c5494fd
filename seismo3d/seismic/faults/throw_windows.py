"""The reflector slopes a fault's throw reads, eigen-decomposed only where it reads them (an in-memory cube).

:func:`~seismo3d.seismic.faults.fault_throws` reads the reflector slopes at a few samples beside each fault (two
fixed-point reads per fault-plane node and side, :mod:`~seismo3d.seismic.faults.throw_patches`): about 7 % of the
samples of a generated 256^3 cube with three faults. The structure tensor is smoothed over the whole cube once (its
separable Gaussian passes, :func:`~seismo3d.seismic._kernels.structure_tensor`), but its eigen-decomposition (half
the CPU seconds of :func:`~seismo3d.seismic.attributes.structure_tensor_slopes`) runs only at the samples a window's
reads interpolate from, once each: the slopes read are those of the whole cube's
:func:`~seismo3d.seismic.attributes.structure_tensor_slopes`, bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import as_seismic
from ...errors import InputError
from .. import _kernels
from .windows import CubeWindow

# used by the throw module; not part of the package's public face
__all__ = ["TensorWindows"]

# the widths of structure_tensor_slopes' defaults (the slopes every window source holds)
_SIGMA_GRADIENT = 1.0
_SIGMA_TENSOR = (2.0, 6.0)


@dataclass(frozen=True, eq=False)
class _TensorWindow(CubeWindow):
    """A :class:`~seismo3d.seismic.faults.windows.CubeWindow` of the whole cube whose slopes are eigen-decomposed
    (by ``fill``) at the samples a read interpolates from, just before it reads them."""

    fill: object = None

    def slope_along(self, il, xl, t, direction) -> np.ndarray:
        """As :meth:`CubeWindow.slope_along <seismo3d.seismic.faults.windows.CubeWindow.slope_along>`."""
        self.fill(il, xl, t)
        return super().slope_along(il, xl, t, direction)


class TensorWindows:
    """Windows of an in-memory 3D cube with its reflector slopes (:func:`structure_tensor_slopes` with its default
    widths), the structure tensor smoothed at the first window and eigen-decomposed at the samples read only.

    Every window is the whole cube (origin (0, 0), as
    :class:`~seismo3d.seismic.faults.windows.ArrayWindows`). Before a window's ``slope_along`` reads, the samples
    its trilinear interpolation reads (the corners ``floor`` and ``floor + 1`` of each position along each axis,
    clamped to the cube's edges) that were not decomposed yet are (:func:`~seismo3d.seismic._kernels.eig_slopes`,
    the same arithmetic as the whole cube's); the others hold NaN, so that a read outside them could not pass
    unnoticed.

    Parameters
    ----------
    data : (n_inlines, n_xlines, n_samples) array_like
        Seismic amplitudes, finite (converted to float32).

    Attributes
    ----------
    shape : (int, int, int)
        Shape of ``data``.

    Raises
    ------
    InputError
        ``data`` is not a finite 3D numeric array with at least 3 samples per axis.

    Notes
    -----
    Memory: the six tensor components and the two slope volumes, float32 (32 bytes per sample), from the first
    window to the source's release; the whole cube's slopes peak at the same (the components while the slopes are
    written).
    """

    def __init__(self, data):
        arr = as_seismic(data)
        if arr.ndim != 3:
            raise InputError(f"TensorWindows needs a 3D cube (n_inlines, n_xlines, n_samples); got shape {arr.shape}; "
                             "pass a 2D section to ArrayWindows")
        self._arr = arr
        self.shape = arr.shape
        self._tensor = self._slopes = self._whole = None

    def window(self, i0: int, i1: int, j0: int, j1: int) -> CubeWindow:
        """The whole cube (it holds every window ``[i0, i1) x [j0, j1)``), with origin (0, 0); the structure tensor
        is smoothed at the first call.

        Returns
        -------
        CubeWindow
            Its ``slope_along`` decomposes the samples it reads first.
        """
        if self._whole is None:
            self._tensor = tuple(t.reshape(-1) for t in _kernels.structure_tensor(
                self._arr, _SIGMA_GRADIENT, _SIGMA_TENSOR, two_d=False, float32=True))
            self._slopes = np.full((2, *self.shape), np.nan, dtype=np.float32)
            self._whole = _TensorWindow(self._arr, self._slopes[0], self._slopes[1], (0, 0), self.shape,
                                        self._decompose)
        return self._whole

    def _decompose(self, il, xl, t) -> None:
        """Decompose the tensors at the samples trilinear reads at ``(il, xl, t)`` interpolate from, once each."""
        corners = []  # along each axis: floor and floor + 1 of the position clamped to the cube (a superset of
        for x, n in zip((il, xl, t), self.shape):  # the two an edge-clamped linear read takes, in or beyond the cube)
            lo = np.floor(np.clip(np.asarray(x, np.float64).ravel(), 0.0, n - 1.0)).astype(np.int64)
            corners.append(np.stack([lo, np.minimum(lo + 1, n - 1)]))
        flat = np.ravel_multi_index((corners[0][:, None, None], corners[1][None, :, None], corners[2][None, None, :]),
                                    self.shape).ravel()
        p0, p1 = (s.reshape(-1) for s in self._slopes)
        todo = flat[np.isnan(p0[flat])]
        if todo.size == 0:
            return
        # each sample once, without sorting: number the samples in p0's bits (NaN until decomposed) and keep the
        # entry whose number its sample holds (the last written); the slopes overwrite the numbers below
        stamp, order = p0.view(np.uint32), np.arange(todo.size, dtype=np.uint32)
        stamp[todo] = order
        todo = todo[stamp[todo] == order]
        out0 = np.empty(todo.size, np.float32)
        out1 = np.empty(todo.size, np.float32)
        _kernels.eig_slopes(*(c[todo] for c in self._tensor), _kernels.MAX_SLOPE, out0, out1, True)
        p0[todo] = out0
        p1[todo] = out1
