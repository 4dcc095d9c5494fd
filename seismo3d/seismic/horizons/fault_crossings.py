"""Fault crossings: which faults a step of a horizon crosses, and by how much the horizon jumps there.

:class:`FaultCrossings` holds the traced fault points of an interpretation with their normals (oriented into the
footwall as :func:`~seismo3d.seismic.faults.throw.fault_throw` measured the throw) and their throws. A step from point
``a`` to point ``b`` crosses a fault when it pierces the fault's local plane (the least-squares plane of its points near
the step, oriented like their normals) within ``pierce`` voxels of one of those points; the horizon then jumps by the
throw, down into the hanging wall and up into the footwall. Two faults between the same traces add their jumps, and a
fault is crossed once going one way (:meth:`FaultCrossings.jump`). Only faults with a reliable throw are used
(:func:`reliable_throw`).

Conventions: index space as in :mod:`seismo3d.seismic.faults.likelihood.scan` (points ``(inline, xline, sample)`` or
``(trace, sample)``); jumps in samples.
"""

from __future__ import annotations

import itertools

import numba as nb
import numpy as np
from scipy.spatial import cKDTree

from ...errors import InputError
from ..faults.throw import hanging_wall_normals

__all__ = ["FaultCrossings", "footwall_normals", "reliable_throw"]


def footwall_normals(normals) -> np.ndarray:
    """A fault's unit normals (n, ndim), of either sign, pointing into its footwall as its throw was measured.

    A fault's normals come from the strike and dip of each point, so on a (near-)vertical fault they point to either
    side (strike and strike + 180 degrees). The throw is measured with the normals sign-aligned to their principal
    direction (:func:`~seismo3d.seismic.faults.throw.hanging_wall_normals`), so the jump of a horizon must use the
    same sides.

    Parameters
    ----------
    normals : (n, 3) or (n, 2) array_like of float
        Fault normals (inline, xline, sample) or (trace, sample), any length but non-zero.

    Returns
    -------
    (n, ndim) float64 ndarray
        Unit normals into the footwall.
    """
    n = np.asarray(normals, np.float64)
    n = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)  # unit, as fault_throw makes them
    if n.shape[1] == 2:
        n3 = np.column_stack([n[:, 0], np.zeros(len(n)), n[:, 1]])
        return -hanging_wall_normals(n3)[:, [0, 2]]
    return -hanging_wall_normals(n)


def reliable_throw(throw, min_correlation: float = 0.0) -> bool:
    """Whether a fault's throw is reliable enough for a horizon to jump by it: the registration across the fault
    explains its two sides better than no throw (the median of ``FaultThrow.correlation`` above the median of
    ``FaultThrow.correlation_unshifted``) and they correlate at least ``min_correlation`` at the throw (median of
    ``FaultThrow.correlation``); False without a throw.

    Whether a horizon takes the jump where it crosses the fault is decided there, pair by pair of traces, by the
    correlation at the jump against the correlation without it (:func:`~seismo3d.seismic.horizons.lsq.pair_shifts`):
    this check only leaves out the faults whose throw explains nothing. A fault-wide median correlation is no measure
    of the throw at one horizon: the large fault of ``penobscot_xl1155.sgy`` (a 2D throw profile of 57 ms at 2000 ms,
    as read by hand) correlates 0.412 at its throw down its 380 samples (0.094 without it), and a threshold of 0.5
    left it out, so the horizon crossed it as if it were not there. On the data folder's 18 Penobscot inlines no
    traced fault reaches a horizon picked by people (the faults lie at samples 757-1432, the horizons above 670).

    Parameters
    ----------
    throw : FaultThrow
        Any object with ``correlation`` and ``correlation_unshifted`` (n,) arrays.
    min_correlation : float
        The least median correlation at the throw, in [-1, 1].

    Returns
    -------
    bool
    """
    corr = np.asarray(throw.correlation, np.float64)
    if not np.isfinite(corr).any() or np.nanmedian(corr) < min_correlation:
        return False
    flat = getattr(throw, "correlation_unshifted", None)
    flat = np.full(corr.shape, np.nan) if flat is None else np.asarray(flat, np.float64)
    if not np.isfinite(flat).any():
        return True  # nothing to compare with: the correlation alone
    return bool(np.nanmedian(corr) > np.nanmedian(flat))


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _group_plane(pts, nrm, cells, ndim):
    # the local plane of one fault's points ``cells`` (FaultCrossings._planes, and the compiled steps): centre and
    # unit normal (zeros when the normals cancel). The least-squares plane (line in 2D) from the scatter matrix's
    # eigenvectors (its square-rooted eigenvalues are the singular values of the centred points) where the points
    # spread over it and lie on it; else their mean normal.
    m = cells.size
    c = np.zeros(ndim)
    n = np.zeros(ndim)
    for k in range(m):
        for d in range(ndim):
            c[d] += pts[cells[k], d]
            n[d] += nrm[cells[k], d]
    c /= m
    n /= m
    if m >= 4:
        scatter = np.zeros((ndim, ndim))
        for k in range(m):
            for d in range(ndim):
                for e in range(ndim):
                    scatter[d, e] += (pts[cells[k], d] - c[d]) * (pts[cells[k], e] - c[e])
        w, v = np.linalg.eigh(scatter)  # ascending
        sv = np.sqrt(np.maximum(w, 0.0))
        if ndim == 3:
            planar = sv[1] > 0.5 * sv[2] and sv[0] < 0.5 * sv[1]  # spread over two axes, thin on the third
        else:
            planar = sv[0] < 0.5 * sv[1]  # 2D: along a line
        if planar:
            sign = 0.0
            for d in range(ndim):
                sign += v[d, 0] * n[d]
            for d in range(ndim):
                n[d] = v[d, 0] if sign >= 0 else -v[d, 0]
    norm = np.sqrt(np.sum(n * n))
    if norm > 0.0:
        n /= norm
    return c, n


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _one_step_jump(a, b, pts, nrm, throws, ids, candidates, pierce):
    # FaultCrossings.jump of the step a -> b (no faults crossed before): the fault points within
    # |b - a| / 2 + pierce + 1 of the step's midpoint (among ``candidates``, the k-d tree's points around it, sorted by
    # fault, then point: sorted by the caller, as np.argsort here compiled for 2.4 CPU s), by fault, each fault's local
    # plane and its pierce point. Scalar loops, not array expressions: the same sums in the same order, and the
    # kernel's first run compiles in 1.2-1.3 CPU s instead of 2.3
    ndim = a.shape[0]
    mid = np.empty(ndim)
    length2 = 0.0
    for d in range(ndim):
        mid[d] = 0.5 * (a[d] + b[d])
        length2 += (b[d] - a[d]) ** 2
    r = 0.5 * np.sqrt(length2) + pierce + 1.0
    found = np.empty(candidates.size, np.int64)
    m = 0
    for k in candidates:
        d2 = 0.0
        for d in range(ndim):
            d2 += (pts[k, d] - mid[d]) ** 2
        if d2 <= r * r:
            found[m] = k
            m += 1
    if m == 0:
        return 0.0
    near = found[:m]
    hit = np.empty(ndim)
    total = 0.0
    g = 0
    while g < m:
        h = g
        while h < m and ids[near[h]] == ids[near[g]]:
            h += 1
        cells = near[g:h]
        g = h
        c, n = _group_plane(pts, nrm, cells, ndim)
        sa = 0.0
        sb = 0.0
        flat = True  # the normals cancelled: no plane
        for d in range(ndim):
            sa += (a[d] - c[d]) * n[d]
            sb += (b[d] - c[d]) * n[d]
            flat = flat and n[d] == 0.0
        if flat or (sa > 0) == (sb > 0):
            continue
        for d in range(ndim):
            hit[d] = a[d] + sa / (sa - sb) * (b[d] - a[d])
        best, nearest = np.inf, -1
        for k in cells:
            d2 = 0.0
            for d in range(ndim):
                d2 += (pts[k, d] - hit[d]) ** 2
            if d2 < best:
                best, nearest = d2, k
        if np.sqrt(best) > pierce:
            continue
        thr = throws[nearest]
        total += -thr if sb > 0 else thr
    return total


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _step_jumps(a, b, pts, nrm, throws, ids, indptr, indices, pierce):
    # _one_step_jump of every step a[s] -> b[s], its candidate points indices[indptr[s]:indptr[s + 1]]. Serial: with
    # parallel=True its first run compiled for 5.2 CPU s instead of 1.3, and 20,000 steps near a 40,000-point fault
    # took 0.06-0.12 CPU s either way, less than the k-d tree query that gives their candidates (0.12-0.14 s)
    out = np.zeros(a.shape[0])
    for s in range(a.shape[0]):
        out[s] = _one_step_jump(a[s], b[s], pts, nrm, throws, ids, indices[indptr[s]:indptr[s + 1]], pierce)
    return out


class FaultCrossings:
    """Fault points with normals (into the footwall), throws and fault ids, for finding the faults a step crosses.

    Parameters
    ----------
    points : (n, ndim) array_like of float
        Fault points, index space.
    normals : (n, ndim) array_like of float
        Unit normals into the footwall (:func:`footwall_normals`).
    throws : (n,) array_like of float
        Throw at each point, samples (+ = hanging wall down); NaN where unknown.
    ids : (n,) array_like of int, optional
        Fault id of each point (default all 0: one fault).
    pierce : float
        Voxels: a step crosses a fault when it pierces the fault's local plane this close to one of its points.
    on_fault : float
        Voxels: a point this close to a fault's local plane (and within ``pierce`` of its points) lies on the fault.

    Examples
    --------
    >>> y, t = np.meshgrid(np.arange(9.0), np.arange(40.0), indexing="ij")
    >>> pts = np.column_stack([np.full(y.size, 10.5), y.ravel(), t.ravel()])   # a vertical fault at inline 10.5
    >>> faults = FaultCrossings(pts, np.tile([1.0, 0.0, 0.0], (len(pts), 1)), np.full(len(pts), 4.0))
    >>> faults.jump(np.array([10.0, 4.0, 20.0]), np.array([11.0, 4.0, 20.0]))   # into the footwall: up by 4
    -4.0
    """

    def __init__(self, points, normals, throws, ids=None, *, pierce: float = 1.5, on_fault: float = 0.5):
        points = np.ascontiguousarray(points, np.float64)  # contiguous: read by the compiled plane fit and steps
        normals = np.ascontiguousarray(normals, np.float64)
        throws = np.ascontiguousarray(throws, np.float64)
        self.pierce, self.on_fault_distance = float(pierce), float(on_fault)
        self.points = points
        self.normals = normals
        self.throws = throws
        self.ids = np.zeros(len(points), np.int64) if ids is None else np.asarray(ids, np.int64)
        self.tree = cKDTree(points) if len(points) else None

    @classmethod
    def empty(cls, ndim: int, **kwargs) -> "FaultCrossings":
        """No faults: every step crosses none (``ndim`` 2 or 3)."""
        return cls(np.zeros((0, ndim)), np.zeros((0, ndim)), np.zeros(0), **kwargs)

    @classmethod
    def from_interpretation(cls, faults, ndim: int, *, min_throw_correlation: float = 0.0,
                            **kwargs) -> "FaultCrossings":
        """The faults of a :class:`~seismo3d.seismic.FaultInterpretation` (or None: no faults) with a reliable
        throw (:func:`reliable_throw` at ``min_throw_correlation``); faults without a throw are left out, as if not
        traced.

        Parameters
        ----------
        faults : FaultInterpretation or None
            Anything with ``faults`` (objects with ``points`` and ``normals``) and ``throws`` (with ``throw`` and
            ``correlation``), in the same order.
        ndim : {2, 3}
            Dimension of the data the horizon is tracked in.
        min_throw_correlation : float
            See :func:`reliable_throw`.
        **kwargs
            ``pierce``, ``on_fault`` (see the class).

        Returns
        -------
        FaultCrossings

        Raises
        ------
        InputError
            The faults were traced in data of another dimension.
        """
        if faults is None:
            return cls.empty(ndim, **kwargs)
        pts, nrm, thr, ids = [], [], [], []
        for k, (f, th) in enumerate(zip(faults.faults, faults.throws)):
            p = np.asarray(f.points, np.float64)
            if p.ndim != 2 or p.shape[1] != ndim:
                raise InputError(f"faults were traced on {p.shape[-1]}D data but the horizon is tracked in {ndim}D "
                                 "data; trace the faults of the same array")
            if not reliable_throw(th, min_throw_correlation):
                continue
            pts.append(p)
            nrm.append(footwall_normals(f.normals))
            thr.append(np.asarray(th.throw, np.float64))
            ids.append(np.full(len(p), k, np.intp))
        if not pts:
            return cls.empty(ndim, **kwargs)
        return cls(np.concatenate(pts), np.concatenate(nrm), np.concatenate(thr), np.concatenate(ids), **kwargs)

    def _planes(self, a: np.ndarray, b: np.ndarray):
        """For each fault with points near the segment a-b: (fault id, indices of those points, centre, unit normal
        into the footwall) of its local plane.

        The least-squares plane of the points (a line in 2D), oriented like their normals: the per-point normals come
        from a coarse strike / dip scan, and a plane through each voxel misplaces the pierce point where the traced
        surface steps from voxel to voxel. Fewer than 4 points, or points that do not spread over a plane (a strip
        along the fault's edge, a thin slab) or do not lie on one: their mean normal."""
        if self.tree is None:
            return
        idx = self.tree.query_ball_point(0.5 * (a + b), 0.5 * float(np.linalg.norm(b - a)) + self.pierce + 1.0)
        if not idx:
            return
        idx = np.asarray(idx, dtype=np.int64)
        for fid in np.unique(self.ids[idx]):
            sel = idx[self.ids[idx] == fid]
            c, n = _group_plane(self.points, self.normals, sel, self.points.shape[1])
            if np.any(n != 0.0):
                yield int(fid), sel, c, n

    def crossings(self, a: np.ndarray, b: np.ndarray) -> dict:
        """The faults between point ``a`` and point ``b``: {fault id: vertical jump (samples) of a horizon going from
        ``a`` to ``b`` across it}, +throw into the hanging wall, -throw into the footwall, NaN for unknown throw.

        A step crosses a fault when it pierces the fault's local plane (:meth:`_planes`) within ``pierce`` of one of
        the fault's points, not beside the fault (past its end)."""
        out = {}
        for fid, sel, c, n in self._planes(a, b):
            sa, sb = float(np.dot(a - c, n)), float(np.dot(b - c, n))
            if (sa > 0) == (sb > 0):
                # the same side; a point on the plane counts as the hanging wall's (sb <= 0, as in wall_jump), so a
                # step that ends on a steep fault's plane (a carry from inline to inline lands on it) and the step
                # that leaves it cross it once
                continue
            pierce = a + sa / (sa - sb) * (b - a)
            d = np.linalg.norm(self.points[sel] - pierce, axis=1)
            if d.min() > self.pierce:
                continue
            thr = self.throws[sel[np.argmin(d)]]
            out[fid] = -thr if sb > 0 else thr  # NaN stays NaN: unknown throw
        return out

    def on_fault(self, a: np.ndarray) -> set:
        """Ids of the faults point ``a`` lies on: within ``on_fault`` of the fault's local plane and within
        ``pierce`` of one of its points."""
        return {fid for fid, sel, c, n in self._planes(a, a)
                if np.linalg.norm(self.points[sel] - a, axis=1).min() <= self.pierce
                and abs(float(np.dot(a - c, n))) < self.on_fault_distance}

    def wall_jump(self, a: np.ndarray, b: np.ndarray, ids: set) -> float:
        """Jump (samples) of a horizon from ``a``, which lies on the faults ``ids``, to ``b`` if ``a`` is in the wall
        ``b`` is not in: the sum of those faults' throws, signed as in :meth:`crossings`. NaN for an unknown throw."""
        total = 0.0
        for fid, sel, c, n in self._planes(a, b):
            if fid in ids:
                thr = self.throws[sel[np.argmin(np.linalg.norm(self.points[sel] - a, axis=1))]]
                total += -thr if float(np.dot(b - c, n)) > 0 else thr
        return total

    def block(self, line_point, n: int, c: int, tc: float, slope: float, lo: int, hi: int) -> tuple[int, int]:
        """The traces of ``lo..hi`` (inclusive, containing ``c``) that a horizon through (c, tc) with ``slope``
        (samples per trace) reaches without crossing a fault: the fault block of the pick along a slice of ``n``
        traces, which ``line_point(x, t)`` maps to this index's coordinates. An end short of ``lo`` / ``hi`` is the
        last trace before a fault."""
        if self.tree is None:
            return lo, hi
        a, b = line_point(lo, tc + slope * (lo - c)), line_point(hi, tc + slope * (hi - c))
        if not self.tree.query_ball_point(0.5 * (a + b), 0.5 * float(np.linalg.norm(b - a)) + self.pierce + 1.0):
            return lo, hi
        ends = []
        for direction, end in ((-1, lo), (1, hi)):
            x = c
            while x != end and 0 <= x + direction < n:
                y = x + direction
                if self.crossings(line_point(x, tc + slope * (x - c)), line_point(y, tc + slope * (y - c))):
                    break
                x = y
            ends.append(x)
        return ends[0], ends[1]

    def near_segments(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Which of many segments come near a traced fault: only these can cross one (:meth:`crossings` of the
        others is empty; the same search radius as :meth:`_planes`, in one KD-tree query).

        Parameters
        ----------
        a, b : (n, ndim) float64 ndarray
            The segments' ends, index space (samples last); finite.

        Returns
        -------
        (n,) bool ndarray
        """
        a = np.asarray(a, np.float64)
        b = np.asarray(b, np.float64)
        if self.tree is None or len(a) == 0:
            return np.zeros(len(a), bool)
        radius = 0.5 * np.linalg.norm(b - a, axis=1) + self.pierce + 1.0
        # the search stops at the largest radius (most segments are far from every fault: inf, not near)
        nearest, _ = self.tree.query(0.5 * (a + b), k=1, distance_upper_bound=float(radius.max()) * (1 + 1e-9) + 1e-9)
        return nearest <= radius

    def step_jumps(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """:meth:`jump` of many steps at once (each on its own: no fault crossed before), in compiled code.

        The same local planes and pierce test as :meth:`crossings` (the plane from the eigenvectors of the points'
        scatter matrix instead of an SVD of the centred points: the same plane to rounding).

        Parameters
        ----------
        a, b : (n, ndim) float64 ndarray
            The steps' ends, index space (samples last); finite.

        Returns
        -------
        (n,) float64 ndarray
            Jump of each step, samples: 0 where it crosses no fault, NaN where a crossed fault's throw is unknown.

        Raises
        ------
        InputError
            ``a`` and ``b`` differ in shape or are not (n, ndim) with the faults' ndim.
        """
        a = np.ascontiguousarray(a, np.float64)
        b = np.ascontiguousarray(b, np.float64)
        ndim = self.points.shape[1]
        if a.shape != b.shape or a.ndim != 2 or a.shape[1] != ndim:
            raise InputError(f"step_jumps needs two (n, {ndim}) arrays of step ends; got shapes {a.shape} and "
                             f"{b.shape}")
        if self.tree is None or len(a) == 0:
            return np.zeros(len(a))
        # each step's candidate points from the tree: within a hair more than the kernel's radius (which decides)
        radius = 0.5 * np.sqrt(np.sum((b - a) ** 2, axis=1)) + self.pierce + 1.0
        near = self.tree.query_ball_point(0.5 * (a + b), radius * (1 + 1e-9) + 1e-9)
        counts = np.fromiter((len(n) for n in near), np.int64, len(near))
        indptr = np.concatenate([[0], np.cumsum(counts)])
        indices = np.fromiter(itertools.chain.from_iterable(near), np.int64, int(indptr[-1]))
        step = np.repeat(np.arange(len(near)), counts)
        indices = indices[np.lexsort((indices, self.ids[indices], step))]  # each step's points by fault, then point
        return _step_jumps(a, b, self.points, self.normals, self.throws, self.ids, indptr, indices, self.pierce)

    def jump(self, a: np.ndarray, b: np.ndarray, crossed: set | None = None) -> float:
        """Vertical jump (samples) of a horizon going from ``a`` to ``b``: the sum over the faults crossed (two faults
        between the same traces add up); 0 when none, NaN when a crossed fault's throw is unknown.

        ``crossed``: the fault ids this horizon path has already crossed, left out and updated. A (planar) fault is
        crossed once going one way; after the jump, a dipping fault's plane can lie beyond the new pick (heave,
        reverse-fault overlap), which is no second crossing."""
        cross = self.crossings(a, b)
        if crossed is not None:
            cross = {f: v for f, v in cross.items() if f not in crossed}
            crossed.update(cross)
        return float(sum(cross.values()))
