"""The reflector slopes a fault's throw reads, computed only where it reads them (an in-memory cube).

:func:`~seismo3d.seismic.faults.fault_throws` reads the reflector slopes at a few samples beside each fault (two
fixed-point reads per fault-plane node and side, :mod:`~seismo3d.seismic.faults.throw_patches`): about 7 % of the
samples of a generated 256^3 cube with three faults, 2 % of the real Parihaka cube of ``parihaka_dev_scores.py``.
The structure tensor is smoothed only at the traces the faults' patches read (their read boxes: 93 % of the traces
of that 256^3 cube, 13 % of Parihaka's), by slabs of inlines and runs of crosslines read with the filters' reach
beyond them (:func:`~seismo3d.seismic._kernels.structure_tensor_at`), and eigen-decomposed (half the CPU seconds of
:func:`~seismo3d.seismic.attributes.structure_tensor_slopes`) only at the samples a window's reads interpolate from,
once each: the slopes read are those of the whole cube's :func:`~seismo3d.seismic.attributes.structure_tensor_slopes`,
bit for bit.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from ..._progress import progress_within
from ..._threads import deferred
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
    widths), the structure tensor smoothed at the traces read (all those of :meth:`prepare`'s boxes at once) and
    eigen-decomposed at the samples read only.

    Every window is the whole cube (origin (0, 0), as
    :class:`~seismo3d.seismic.faults.windows.ArrayWindows`). Before a window's ``slope_along`` reads, the tensor is
    smoothed at the traces it reads where it was not yet, and the samples its trilinear interpolation reads (the
    corners ``floor`` and ``floor + 1`` of each position along each axis, clamped to the cube's edges) that were not
    decomposed yet are (:func:`~seismo3d.seismic._kernels.eig_slopes`,
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
    Memory: the six tensor components and the two slope volumes, float32 (32 bytes per sample; the components are
    written only where the tensor is smoothed), from the first window to the source's release; the whole cube's
    slopes peak at the same (the components while the slopes are written); :meth:`prepare` on a pool of threads holds
    the workspace of a part per thread.

    Threads: windows may be read from several threads at once (the tensor smoothed and the slopes decomposed by one
    thread at a time, under a lock: the same bits); :meth:`prepare` is called once, before the reads.
    """

    def __init__(self, data):
        arr = as_seismic(data)
        if arr.ndim != 3:
            raise InputError(f"TensorWindows needs a 3D cube (n_inlines, n_xlines, n_samples); got shape {arr.shape}; "
                             "pass a 2D section to ArrayWindows")
        self._arr = arr
        self.shape = arr.shape
        self._tensor = self._flat = self._done = self._slopes = self._whole = None
        self._lock = threading.Lock()  # one decomposition at a time: windows read on several threads at once

    def window(self, i0: int, i1: int, j0: int, j1: int) -> CubeWindow:
        """The whole cube (it holds every window ``[i0, i1) x [j0, j1)``), with origin (0, 0); the arrays of the
        tensor and the slopes are made at the first call, the tensor smoothed where a read needs it (or
        :meth:`prepare` asked for it).

        Returns
        -------
        CubeWindow
            Its ``slope_along`` smooths the tensor at the traces it reads and decomposes the samples it reads first.
        """
        if self._whole is None:
            self._tensor = tuple(np.empty(self.shape, np.float32) for _ in range(6))
            self._flat = tuple(t.reshape(-1) for t in self._tensor)
            self._done = np.zeros(self.shape[:2], bool)
            self._slopes = np.full((2, *self.shape), np.nan, dtype=np.float32)
            self._whole = _TensorWindow(self._arr, self._slopes[0], self._slopes[1], (0, 0), self.shape,
                                        self._decompose)
        return self._whole

    def prepare(self, boxes, *, run=deferred) -> None:
        """Smooth the structure tensor at the traces of ``boxes`` at once (the read boxes of every patch of the faults
        measured: :func:`~seismo3d.seismic.faults.throw_patches.read_box`), a line per part (a slab of inlines, or a
        run of its crosslines; :func:`~seismo3d.seismic._kernels.structure_tensor`'s progress); reads elsewhere
        smooth their traces when they come.

        Parameters
        ----------
        boxes : sequence of (int, int, int, int)
            ``(i0, i1, j0, j1)``: half-open inline and crossline ranges of the traces read.
        run : callable, optional
            ``run(func, *args)`` returning an object whose ``result()`` is ``func(*args)`` (e.g. a thread pool's
            ``submit``): the parts are computed by it, several at once on a pool (each writes its own traces; the
            same bits), and reported in order. Default (:func:`~seismo3d._threads.deferred`): one after the other in
            the calling thread.
        """
        self.window(0, 0, 0, 0)
        need = np.zeros(self.shape[:2], bool)
        for i0, i1, j0, j1 in boxes:
            need[i0:i1, j0:j1] = True
        self._smooth(need & ~self._done, submit=run)

    def _smooth(self, need: np.ndarray, submit=deferred) -> None:
        """The tensor at the traces ``need`` ((n0, n1) bool) marks: per slab of :data:`_kernels.TENSOR_SLAB`
        inlines, at each run of its crosslines that need it (runs closer than two filter reaches joined), the rows of
        the slab that need it (:func:`~seismo3d.seismic._kernels.structure_tensor_at` on the traces within the
        filters' reach: the whole cube's bits there); each part by ``submit`` (:meth:`prepare`'s ``run``)."""
        n0, n1 = self.shape[:2]
        reach = _kernels.gaussian_radius(_SIGMA_TENSOR[0]) + _kernels.gaussian_radius(_SIGMA_GRADIENT)
        slab = _kernels.TENSOR_SLAB
        work = []
        for a in range(0, n0, slab):
            rows = np.flatnonzero(need[a:a + slab].any(axis=1)) + a
            if not rows.size:
                continue
            cols = np.flatnonzero(need[rows[0]:rows[-1] + 1].any(axis=0))
            starts = np.flatnonzero(np.diff(cols) > 2 * reach) + 1
            for run in np.split(cols, starts):
                work.append((int(rows[0]), int(rows[-1]) + 1, int(run[0]), int(run[-1]) + 1))
        if not work:
            return

        def part(i0, i1, j0, j1):
            lo, hi = max(i0 - reach, 0), min(i1 + reach, n0)  # clamped at the cube's edges as the whole cube's
            c0, c1 = max(j0 - reach, 0), min(j1 + reach, n1)
            _kernels.structure_tensor_at(self._arr[lo:hi, c0:c1], _SIGMA_GRADIENT, _SIGMA_TENSOR,
                                         (slice(i0 - lo, i1 - lo), slice(j0 - c0, j1 - c0)),
                                         out=tuple(t[i0:i1, j0:j1] for t in self._tensor), float32=True)

        with progress_within(len(work), unit="part") as bar:
            parts = [submit(part, *box) for box in work]  # started at once on a pool; deferred: each at its result()
            for (i0, i1, j0, j1), done in zip(work, parts):
                done.result()
                self._done[i0:i1, j0:j1] = True
                bar.advance(1, status="structure tensor")

    def _decompose(self, il, xl, t) -> None:
        """Decompose the tensors at the samples trilinear reads at ``(il, xl, t)`` interpolate from, once each (their
        traces' tensor smoothed first when it was not); the tensor and the slopes are changed by one call at a time
        (the reads of several threads)."""
        corners = []  # along each axis: floor and floor + 1 of the position clamped to the cube (a superset of
        for x, n in zip((il, xl, t), self.shape):  # the two an edge-clamped linear read takes, in or beyond the cube)
            lo = np.floor(np.clip(np.asarray(x, np.float64).ravel(), 0.0, n - 1.0)).astype(np.int64)
            corners.append(np.stack([lo, np.minimum(lo + 1, n - 1)]))
        traces = (corners[0][:, None], corners[1][None, :])
        flat = np.ravel_multi_index((corners[0][:, None, None], corners[1][None, :, None], corners[2][None, None, :]),
                                    self.shape).ravel()
        with self._lock:
            self._decompose_at(traces, flat)

    def _decompose_at(self, traces, flat) -> None:
        """:meth:`_decompose` at the traces ``traces`` ((2, 2, n) index arrays) and flat sample indices ``flat``."""
        if not self._done[traces].all():
            need = np.zeros(self.shape[:2], bool)
            need[traces] = True
            self._smooth(need & ~self._done)
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
        _kernels.eig_slopes(*(c[todo] for c in self._flat), _kernels.MAX_SLOPE, out0, out1, True)
        p0[todo] = out0
        p1[todo] = out1
