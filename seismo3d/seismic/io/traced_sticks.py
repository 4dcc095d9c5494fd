"""Fault sticks drawn from traced faults as interpreters draw them: the lines a fault's sticks lie on, and the few
nodes of one stick (:meth:`FaultSticks.from_faults <seismo3d.seismic.io.fault_sticks.FaultSticks.from_faults>`).

An interpreter draws a fault on a section as one polyline from its top to its bottom, with a node where the fault
bends; in a 3D survey on every n-th section across the fault's strike. A traced fault is a set of samples (a curve one
sample thick on a section; a surface in a cube), so a stick is made from the fault's samples on one section in three
steps:

1. **One trace per sample** (the fault resolved into a single-valued function of time): at each time the fault
   crosses the section in one or more runs of adjacent traces (several where a low-dip fault crosses a time, or where
   it folds back or branches); of their middle samples, the one on the smoothest path from the fault's top to its
   bottom (dynamic programming over the times, cost the squared lateral step over the time step, as a random walk's),
   so that a fault folding back or branching is followed along one strand, never zigzagging between two.
2. **Nodes where the fault bends**: that path simplified by the Ramer-Douglas-Peucker algorithm to within
   ``tolerance`` of it (the vertices :func:`skimage.measure.approximate_polygon` keeps).
3. **Every sample of the fault within ``tolerance`` of the stick**: where a fault sample near the path is farther than
   ``tolerance`` from the simplified stick (the simplification measures distance to the path, not to the samples
   beside it at the same time), the path's sample at its time becomes a node too, until none is.

Distances are measured in the section's index space (a trace and a sample are one unit each), as the fault scores
measure their tolerance. Every node is one of the fault's own samples, so it sits at its trace's coordinates and on a
whole sample; times increase strictly along a stick.

References
----------
Douglas, D. H. and Peucker, T. K. (1973). Algorithms for the reduction of the number of points required to represent
a digitized line or its caricature. *Cartographica* 10(2), 112-122, doi:10.3138/FM57-6770-U75U-7727.
Bellman, R. (1957). *Dynamic Programming*. Princeton University Press (the path of step 1).
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError

__all__ = ["STICK_LINE_STEP", "distance_to_stick", "stick_lines", "stick_nodes"]

STICK_LINE_STEP = 10  # every 10th inline or crossline of a cube, as interpreters pick fault sticks (module notes)


def stick_lines(points, *, line_step: int = STICK_LINE_STEP) -> tuple:
    """The sections of a cube a traced fault's sticks are drawn on: every ``line_step``-th inline or crossline across
    the fault's strike.

    The sections are the inlines when the fault's strike runs more along the inline axis than along the crossline
    axis (an inline then cuts the fault across its strike), else the crosslines; the strike is that of the plane
    fitted to the fault's samples (least squares: the normal is the direction of least spread of the samples, in
    index space). The sections are the survey's every ``line_step``-th line, counted from its first, so that the
    sticks of all faults lie on the same sections, as an interpreter picks them; a fault that crosses fewer than two
    of them gets its first and last line instead. Only lines on which the fault spans at least two samples of time
    carry a stick.

    Parameters
    ----------
    points : (n, 3) int ndarray
        The fault's samples as (inline, crossline, sample) indices of the traced cube.
    line_step : int
        Draw a stick on every ``line_step``-th line (>= 1).

    Returns
    -------
    axis : int
        0 when the sticks lie on inlines (fixed inline index), 1 on crosslines.
    lines : (m,) int64 ndarray
        The indices along ``axis`` of the lines with a stick, increasing; empty when the fault spans one sample of
        time on every line.

    Raises
    ------
    InputError
        ``points`` not (n, 3), or ``line_step`` < 1.
    """
    p = np.asarray(points)
    if p.ndim != 2 or p.shape[1] != 3:
        raise InputError(f"stick_lines takes a cube's fault samples (n, 3); got shape {p.shape}")
    if int(line_step) < 1:
        raise InputError(f"line_step must be a whole number >= 1 (a stick every line_step-th line); got {line_step}")
    axis = _across_strike_axis(p)
    lines = np.unique(p[:, axis])
    # lines on which the fault spans at least two samples of time: the others cannot carry a stick
    order = np.lexsort((p[:, 2], p[:, axis]))
    bounds = np.r_[np.flatnonzero(np.diff(p[order, axis])) + 1, p.shape[0]]
    starts = np.r_[0, bounds[:-1]]
    spans = p[order[bounds - 1], 2] - p[order[starts], 2]
    lines = lines[spans > 0]
    on_grid = lines[lines % int(line_step) == 0]
    if on_grid.size >= 2:
        return axis, on_grid.astype(np.int64)
    return axis, np.unique(lines[[0, -1]]).astype(np.int64) if lines.size else lines.astype(np.int64)


def _across_strike_axis(p: np.ndarray) -> int:
    """0 when an inline cuts the fault across its strike, else 1 (the normal of the fault's least-squares plane)."""
    q = p.astype(np.float64)
    q -= q.mean(axis=0)
    _, vectors = np.linalg.eigh(q.T @ q)
    normal = vectors[:, 0]  # the direction of least spread
    if abs(normal[0]) == abs(normal[1]) == 0.0:  # a horizontal plane: no strike; the longer extent is along strike
        return 0 if np.ptp(p[:, 0]) >= np.ptp(p[:, 1]) else 1
    # the normal's lateral part points across strike: along the crosslines' direction -> an inline section cuts it
    return 0 if abs(normal[1]) >= abs(normal[0]) else 1


def stick_nodes(trace, sample, *, tolerance: float = 1.0) -> tuple:
    """The nodes of one stick through a fault's samples on one section (module notes: a path of one trace per
    sample, simplified by Douglas-Peucker, every sample near the path within ``tolerance``).

    Parameters
    ----------
    trace : (n,) int ndarray
        Trace index of each fault sample along the section (for a cube's section: the crossline index on an inline,
        the inline index on a crossline).
    sample : (n,) int ndarray
        Sample index of each.
    tolerance : float
        Largest distance of a fault sample from the stick, in samples (index space; > 0).

    Returns
    -------
    nodes : (k,) int64 ndarray
        Indices into ``trace`` / ``sample`` of the stick's nodes, in order of strictly increasing sample; k >= 2
        when the fault spans two samples or more, 1 when it spans one.
    resolved : (n,) bool ndarray
        True for the samples the single-valued stick leaves farther than ``tolerance`` (a strand folding back or
        branching off, at the same times as the one the stick follows); False for every sample within it.

    Raises
    ------
    InputError
        No samples, arrays of different shapes, or ``tolerance`` <= 0.
    """
    t = np.asarray(trace, dtype=np.int64)
    k = np.asarray(sample, dtype=np.int64)
    if t.ndim != 1 or t.shape != k.shape or t.size == 0:
        raise InputError(f"stick_nodes takes (n,) trace and sample indices of one fault, n >= 1; got {t.shape} and "
                         f"{k.shape}")
    if not tolerance > 0:
        raise InputError(f"tolerance must be > 0 samples; got {tolerance}")
    path = _smoothest_path(t, k)
    xy = np.column_stack([t, k]).astype(np.float64)
    nodes = path[_bends(xy[path], tolerance)]
    near = _near_path(xy, xy[path], tolerance)  # samples the stick can hold: near the path it follows
    while True:
        away = distance_to_stick(xy, xy[nodes]) > tolerance
        far = near & away & ~np.isin(k, k[nodes])
        if not far.any():
            break
        worst = np.flatnonzero(far)[np.argmax(distance_to_stick(xy[far], xy[nodes]))]
        nodes = np.r_[nodes, path[k[path] == k[worst]]]
        nodes = nodes[np.argsort(k[nodes])]
    return nodes.astype(np.int64), away


def _bends(line: np.ndarray, tolerance: float) -> np.ndarray:
    """The vertices of the polyline ``line`` ((n, 2) float64, n >= 1) that the Ramer-Douglas-Peucker algorithm keeps
    at ``tolerance`` (> 0), as a boolean mask: the ends, and recursively the vertex farthest from the chord of each
    part while it lies beyond ``tolerance`` (distance to the chord's line where the vertex projects inside the chord,
    to its nearer end otherwise; the first of equal distances).

    The arithmetic of :func:`skimage.measure.approximate_polygon`, so the same vertices, bit for bit (tested),
    without importing it: its module imports ``scipy.signal``, and through it ``scipy.stats``, which nothing else of a
    ``seismo3d faults`` run imports (the sticks of a generated 256^3 cube took 1.14 CPU s with that import, 0.32
    without).
    """
    keep = np.zeros(line.shape[0], bool)
    keep[[0, -1]] = True
    parts = [(0, line.shape[0] - 1)]
    while parts:
        start, end = parts.pop()
        if end - start < 2:
            continue
        (r0, c0), (r1, c1) = line[start], line[end]
        dr, dc = r1 - r0, c1 - c0
        angle = -np.arctan2(dr, dc)  # the chord's line: r cos(angle) + c sin(angle) = offset
        cos, sin = np.cos(angle), np.sin(angle)
        offset = c0 * sin + r0 * cos
        inner = line[start + 1:end]
        dr0, dc0 = inner[:, 0] - r0, inner[:, 1] - c0
        dr1, dc1 = inner[:, 0] - r1, inner[:, 1] - c1
        beside = (dr0 * dr + dc0 * dc > 0) & (-dr1 * dr - dc1 * dc > 0)  # projects inside the chord
        distance = np.where(beside, np.abs(inner[:, 0] * cos + inner[:, 1] * sin - offset),
                            np.minimum(np.sqrt(dc0 ** 2 + dr0 ** 2), np.sqrt(dc1 ** 2 + dr1 ** 2)))
        if np.any(distance > tolerance):
            far = start + 1 + int(np.argmax(distance))
            keep[far] = True
            parts += [(far, end), (start, far)]
    return keep


def _smoothest_path(t: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Indices of one fault sample per time, from the first time to the last, minimising the sum over consecutive
    times of (lateral step)^2 / (time step) (dynamic programming; ties to the smaller trace). The candidates at a
    time are the middle samples of its runs of adjacent traces (a low-dip fault crosses a time in a run of several
    traces: the stick passes through its middle)."""
    order = np.lexsort((t, k))
    ko, to = k[order], t[order]
    new_run = np.r_[True, (np.diff(ko) != 0) | (np.diff(to) > 1)]
    run_start = np.flatnonzero(new_run)
    run_length = np.diff(np.r_[run_start, order.size])
    middle = order[run_start + (run_length - 1) // 2]  # a run's middle sample (the left one of two)
    times, starts = np.unique(k[middle], return_index=True)
    groups = np.split(middle, starts[1:])
    cost = np.zeros(groups[0].size)
    back = []
    only = np.zeros(1, np.intp)  # the choice where a time has one candidate after a time with one
    for previous, group, dk in zip(groups[:-1], groups[1:], np.diff(times).tolist()):
        if previous.size == group.size == 1:  # one way on (most times of a thin fault): the same sums, no matrices
            step = float(t[group[0]] - t[previous[0]])
            cost = cost + step * step / dk
            back.append(only)
            continue
        step = (t[group][None, :] - t[previous][:, None]).astype(np.float64) ** 2 / dk
        total = cost[:, None] + step
        best = np.argmin(total, axis=0)
        back.append(best)
        cost = total[best, np.arange(group.size)]
    choice = [int(np.argmin(cost))]
    for best in reversed(back):
        choice.append(int(best[choice[-1]]))
    return np.array([g[c] for g, c in zip(groups, reversed(choice))], dtype=np.int64)


def _near_path(points: np.ndarray, path: np.ndarray, tolerance: float) -> np.ndarray:
    """``distance_to_stick(points, path) <= tolerance`` for a path whose samples (``path[:, 1]``) strictly increase,
    from the only segments that can be that near a point: those reaching within ``tolerance`` of its sample (a
    segment farther in time is farther in space). Each distance is computed as :func:`distance_to_stick` computes it,
    so the answer is the same, from a few segments per point instead of all of them (a stick's path has one node per
    sample: 0.6 of the 0.9 CPU s of the 78 sticks of a 256^3 cube went into measuring every sample against every
    segment)."""
    if path.shape[0] < 2:
        return distance_to_stick(points, path) <= tolerance
    n_segments = path.shape[0] - 1
    times = path[:, 1]
    # segment s joins nodes s and s + 1: it can be within tolerance when times[s + 1] >= k - tol and times[s] <= k + tol
    first = np.clip(np.searchsorted(times, points[:, 1] - tolerance, side="left") - 1, 0, n_segments - 1)
    last = np.clip(np.searchsorted(times, points[:, 1] + tolerance, side="right") - 1, 0, n_segments - 1)
    width = max(int((last - first).max()) + 1, 1)
    segment = first[:, None] + np.arange(width)[None]
    beyond = segment > last[:, None]
    segment = np.minimum(segment, n_segments - 1)
    a = path[segment]
    ab = path[segment + 1] - a
    ap = points[:, None, :] - a
    u = np.clip((ap * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12), 0.0, 1.0)
    d = ap - u[..., None] * ab
    distance = np.sqrt((d * d).sum(-1))
    distance[beyond] = np.inf
    return distance.min(axis=1) <= tolerance


def distance_to_stick(points, nodes) -> np.ndarray:
    """Distance of points from a polyline (the nearest of its segments; its one node when it has one).

    Parameters
    ----------
    points : (n, 2) float ndarray
        (trace, sample) of each point, index space.
    nodes : (k,) or (k, 2) float ndarray
        The stick's nodes in order, (trace, sample); k >= 1.

    Returns
    -------
    (n,) float64 ndarray
        Euclidean distance in index space (samples).
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    v = np.asarray(nodes, dtype=np.float64).reshape(-1, 2)
    if v.shape[0] == 1:
        return np.hypot(*(p - v[0]).T)
    a, b = v[:-1], v[1:]
    ab = b - a
    ap = p[:, None, :] - a[None]
    u = np.clip((ap * ab[None]).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-12)[None], 0.0, 1.0)
    d = ap - u[..., None] * ab[None]
    return np.sqrt((d * d).sum(-1)).min(axis=1)
