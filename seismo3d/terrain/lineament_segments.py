"""The straight segments of lineament extraction (:mod:`seismo3d.terrain.lineaments`): probabilistic Hough segments of
each orientation class, collinear segments linked into lineaments, how much of a segment follows a grid's edges, and
the same structure found twice.

References
----------
Matas, J., Galambos, C., Kittler, J. (2000). Robust detection of lines using the progressive probabilistic Hough
transform. CVIU 78(1), 119-137. doi:10.1006/cviu.1999.0831
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__ = ["break_support", "hough_segments", "link_segments", "same_structure"]


def hough_segments(edges, classes, options) -> np.ndarray:
    """Probabilistic Hough segments of each orientation class (normals within 1.5 class widths of the class's).

    Parameters
    ----------
    edges : (H, W) bool ndarray
    classes : (H, W) int ndarray
        From :func:`~seismo3d.terrain.lineaments.orientation_classes`.
    options : ~seismo3d.terrain.LineamentOptions
        ``n_orientations``, ``hough_threshold``, ``hough_length_px``, ``hough_gap_px`` and ``seed`` are read.

    Returns
    -------
    (M, 4) float64 ndarray
        ``row0, col0, row1, col1`` per segment.
    """
    from skimage.transform import probabilistic_hough_line

    n = int(options.n_orientations)
    width = np.pi / n
    out = []
    for k in range(n):
        near = np.abs((classes - k + n // 2) % n - n // 2) <= 1  # this class and its two neighbours
        sel = edges & near
        if np.count_nonzero(sel) < options.hough_threshold:
            continue
        theta = k * width + np.linspace(-1.5 * width, 1.5 * width, 31)
        theta = np.sort((theta + np.pi / 2) % np.pi - np.pi / 2)
        lines = probabilistic_hough_line(sel, threshold=int(options.hough_threshold),
                                         line_length=int(options.hough_length_px), line_gap=int(options.hough_gap_px),
                                         theta=theta, rng=int(options.seed) + k)
        out.extend((y0, x0, y1, x1) for (x0, y0), (x1, y1) in lines)
    return np.asarray(out, dtype=np.float64).reshape(-1, 4)


def _fit(points, weights):
    """Total-least-squares line of weighted points: centre, unit direction, extent along it."""
    w = weights / weights.sum()
    centre = w @ points
    q = points - centre
    _, vecs = np.linalg.eigh((q * w[:, None]).T @ q)
    u = vecs[:, -1]
    t = q @ u
    return centre, u, float(t.min()), float(t.max())


def link_segments(segments, *, angle_deg: float, offset_px: float, gap_px: float) -> np.ndarray:
    """Merge collinear segments into lineaments, repeatedly, longest first.

    Two groups merge when their fitted directions differ by at most ``angle_deg``, both ends of the other lie within
    ``offset_px`` of one's line, and the gap between them along it is at most ``gap_px``; a merged group is refitted
    by total least squares over its segments' end points, weighted by segment length.

    Parameters
    ----------
    segments : (M, 4) array_like
        ``row0, col0, row1, col1``.
    angle_deg, offset_px, gap_px : float

    Returns
    -------
    (K, 4) float64 ndarray
        The lineaments' end points (extreme projections of their segments' ends), K <= M.
    """
    segs = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    order = np.argsort(-np.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1]))
    groups = [[s] for s in segs[order]]
    cos_tol = np.cos(np.radians(angle_deg))

    def line(group):
        """The group's fitted line from its segments' end points, weighted by segment length."""
        g = np.asarray(group)
        pts = np.concatenate([g[:, :2], g[:, 2:]])
        w = np.tile(np.hypot(g[:, 2] - g[:, 0], g[:, 3] - g[:, 1]) + 1e-9, 2)
        return _fit(pts, w)

    lines = [line(g) for g in groups]
    merged = True
    while merged:
        merged = False
        i = 0
        while i < len(groups):
            c, u, t0, t1 = lines[i]
            n = np.array([-u[1], u[0]])
            others = range(i + 1, len(groups))
            for j in others:
                c2, u2, s0, s1 = lines[j]
                if abs(u @ u2) < cos_tol:
                    continue
                ends = np.array([c2 + s0 * u2, c2 + s1 * u2]) - c
                if np.any(np.abs(ends @ n) > offset_px):
                    continue
                along = ends @ u
                if max(along.min() - t1, t0 - along.max(), 0.0) > gap_px:
                    continue
                groups[i] = groups[i] + groups.pop(j)
                lines.pop(j)
                lines[i] = line(groups[i])
                merged = True
                break
            else:
                i += 1
    out = [np.r_[c + t0 * u, c + t1 * u] for c, u, t0, t1 in lines]
    return np.asarray(out, dtype=np.float64).reshape(-1, 4)


def break_support(segments, distance, f: int) -> np.ndarray:
    """The fraction of each segment that lies within ``f`` pixels of an edge of the DEM itself: how much of a
    lineament found on the DEM averaged over blocks of ``f`` cells follows a break in the terrain.

    Parameters
    ----------
    segments : (K, 4) array_like of float
        ``row0, col0, row1, col1`` in the DEM's pixels.
    distance : (H, W) float ndarray
        The distance of every cell to the nearest edge of the DEM, pixels (``scipy.ndimage.distance_transform_edt``
        of the edges' complement).
    f : int
        The block size of the level the segments were found at, cells.

    Returns
    -------
    (K,) float64 ndarray
        Fractions in [0, 1], sampled once a pixel along each segment.
    """
    out = np.zeros(len(segments))
    for k, (r0, c0, r1, c1) in enumerate(segments):
        m = max(int(np.ceil(np.hypot(r1 - r0, c1 - c0))), 2)
        d = ndimage.map_coordinates(distance, [np.linspace(r0, r1, m), np.linspace(c0, c1, m)], order=1,
                                    mode="nearest")
        out[k] = float(np.mean(d <= f))
    return out


def same_structure(segments, scale, azimuth, order, overlap_px: float, angle_deg: float) -> np.ndarray:
    """Which lineaments to keep, visited in rank ``order``: one lying over half its length within ``overlap_px``
    pixels of its own level of a kept one whose strike differs by at most ``angle_deg`` is the same structure seen at
    another level, and is dropped.

    Parameters
    ----------
    segments : (K, 4) float ndarray
        ``row0, col0, row1, col1`` in the DEM's pixels.
    scale : (K,) float ndarray
        The block size of each one's level, cells.
    azimuth : (K,) float ndarray
        Strikes, degrees in [0, 180).
    order : (K,) int ndarray
        The rank order, the best first.
    overlap_px : float
        Distance, in pixels of a lineament's own level.
    angle_deg : float
        Largest strike difference, degrees.

    Returns
    -------
    (K,) bool ndarray
    """
    keep = np.zeros(len(segments), dtype=bool)
    kept = []
    for k in order:
        r0, c0, r1, c1 = segments[k]
        m = max(int(np.ceil(np.hypot(r1 - r0, c1 - c0) / 2.0)), 2)
        pts = np.column_stack([np.linspace(r0, r1, m), np.linspace(c0, c1, m)])
        duplicate = False
        for j in kept:
            if abs((azimuth[k] - azimuth[j] + 90.0) % 180.0 - 90.0) > angle_deg:
                continue
            a, b = segments[j, :2], segments[j, 2:]
            u = b - a
            t = np.clip((pts - a) @ u / max(u @ u, 1e-12), 0.0, 1.0)
            d = np.hypot(*(pts - (a + t[:, None] * u)).T)
            if np.mean(d <= overlap_px * scale[k]) > 0.5:
                duplicate = True
                break
        if not duplicate:
            keep[k] = True
            kept.append(k)
    return keep
