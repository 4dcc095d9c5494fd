"""Numba kernels of the HOG-pyramid descriptor: recursive (sliding) and direct circular-window histograms.

Internal module: inputs are trusted (validated by the public functions in :mod:`seismo3d.features.hog_pyramid`).
The arrays ``bins`` and ``weights`` have shape (rows + 2 * pad, cols + 2 * pad, P): each pixel of the zero-padded
image votes ``weights[y, x, p]`` into orientation bin ``bins[y, x, p]`` for p < P (P = 2 with linear soft binning).
A disc of radius r centred on pixel (y, x) is the set of offsets (dy, dx) with ``|dx| <= half_widths[dy + pad]``
(a half width of -1 marks a row outside the disc), so sliding it one pixel to the right only removes the column
``x - half_width`` and adds the column ``x + 1 + half_width`` on each of its rows: O(r) work per step instead of
O(r^2).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, no_cfunc_wrapper=True, nogil=True, inline="always")
def _put(hist, dest):
    """``dest[:, :] = hist`` ((K, Q) each) as a loop: an array assignment compiles numba's generic setitem, which
    cost ``seismo3d match``'s first run about 5 CPU s of compiling."""
    for k in range(hist.shape[0]):
        for b in range(hist.shape[1]):
            dest[k, b] = hist[k, b]


@njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _init_discs(bins, weights, half_widths, pad, y, x, hist):
    """Direct O(r^2) sums of every disc at (y, x) (unpadded coordinates) into hist (K, Q).

    One pass over the outer disc: each row is split into the ring segments between consecutive half widths, the
    ring histograms are summed, then accumulated from the inside out into the nested disc histograms.
    """
    n_discs = half_widths.shape[0]
    n_votes = bins.shape[2]
    for k in range(hist.shape[0]):  # hist[:, :] = 0, as a loop (see _put)
        for b in range(hist.shape[1]):
            hist[k, b] = 0
    for j in range(half_widths.shape[1]):
        yy = y + j  # padded row of offset dy = j - pad
        inner = -1  # half width of the previous (inner) disc on this row, -1 if it misses the row
        for k in range(n_discs):
            h = half_widths[k, j]
            if h < 0:
                continue
            # ring k on this row: columns inner + 1 .. h on both sides (the whole span -h .. h when inner < 0)
            lo = x + pad - h
            hi = x + pad - inner - 1
            for xx in range(lo, hi + 1):
                for p in range(n_votes):
                    hist[k, bins[yy, xx, p]] += weights[yy, xx, p]
            lo = x + pad + inner + 1
            if inner < 0:
                lo = hi + 1
            for xx in range(lo, x + pad + h + 1):
                for p in range(n_votes):
                    hist[k, bins[yy, xx, p]] += weights[yy, xx, p]
            inner = h
    for k in range(1, n_discs):
        for b in range(hist.shape[1]):
            hist[k, b] += hist[k - 1, b]


@njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _slide_discs(bins, weights, half_widths, pad, y, x, hist):
    """Move every disc of hist from (y, x) to (y, x + 1): subtract the leaving arc, add the entering arc."""
    n_discs = half_widths.shape[0]
    n_votes = bins.shape[2]
    for k in range(n_discs):
        for j in range(half_widths.shape[1]):
            h = half_widths[k, j]
            if h < 0:
                continue
            yy = y + j
            x_out = x + pad - h
            x_in = x + pad + h + 1
            for p in range(n_votes):
                hist[k, bins[yy, x_out, p]] -= weights[yy, x_out, p]
                hist[k, bins[yy, x_in, p]] += weights[yy, x_in, p]


@njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def dense_disc_histograms(bins, weights, half_widths, pad, rows, n_cols, out):
    """Disc histograms at every column of the given rows, by recursion along each row.

    out : (len(rows), n_cols, K, Q) array, filled in place. The first column of a row is summed directly, every
    further column is obtained from its left neighbour by :func:`_slide_discs`.
    """
    n_discs = half_widths.shape[0]
    n_bins = out.shape[3]
    hist = np.zeros((n_discs, n_bins), dtype=out.dtype)
    for i in range(rows.shape[0]):
        y = rows[i]
        # np.int64(0), not 0: a literal 0 compiled _init_discs once more, for Literal[int](0) (1.1-1.5 CPU s)
        _init_discs(bins, weights, half_widths, pad, y, np.int64(0), hist)
        _put(hist, out[i, 0])
        for x in range(n_cols - 1):
            _slide_discs(bins, weights, half_widths, pad, y, x, hist)
            _put(hist, out[i, x + 1])


@njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def point_disc_histograms(bins, weights, half_widths, pad, ys, xs, max_gap, out):
    """Disc histograms at points sorted by (row, column), sliding along each row between consecutive points.

    A row is started with a direct sum at its first point; the window then slides recursively to the next point of
    the same row, unless the gap exceeds ``max_gap`` columns, where a fresh direct sum is cheaper.
    out : (N, K, Q) array, filled in place.
    """
    n_discs = half_widths.shape[0]
    n_bins = out.shape[2]
    hist = np.zeros((n_discs, n_bins), dtype=out.dtype)
    n = ys.shape[0]
    i = 0
    while i < n:
        y = ys[i]
        x = xs[i]
        _init_discs(bins, weights, half_widths, pad, y, x, hist)
        _put(hist, out[i])
        i += 1
        while i < n and ys[i] == y:
            target = xs[i]
            if target - x > max_gap:
                x = target
                _init_discs(bins, weights, half_widths, pad, y, x, hist)
            else:
                while x < target:
                    _slide_discs(bins, weights, half_widths, pad, y, x, hist)
                    x += 1
            _put(hist, out[i])
            i += 1




@njit(cache=True, no_cfunc_wrapper=True, nogil=True, inline="always")
def _angle(u, v):
    """atan2(v, u) mapped to [0, 2 pi), by octant reduction and a polynomial for atan on [0, 1].

    |error| < 3e-4 rad (0.02 degrees), far below a 22.5 degree orientation bin.

    The reduction makes the result exactly equivariant to quarter turns and mirror flips of (u, v) (up to the final
    rounding), which keeps descriptors of images rotated by multiples of 90 degrees identical.
    """
    au = abs(u)
    av = abs(v)
    mx = max(au, av)
    if mx == 0.0:
        return 0.0
    a = min(au, av) / mx
    s = a * a
    r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a
    if av > au:
        r = 0.5 * np.pi - r
    if u < 0.0:
        r = np.pi - r
    if v < 0.0:
        r = 2.0 * np.pi - r
    return r


@njit(cache=True, no_cfunc_wrapper=True, nogil=True, fastmath=True)
def orientation_votes(gx, gy, n_bins, pad, unit, bins, weights):
    """Soft-binned orientation votes of every pixel into the padded (H + 2 pad, W + 2 pad, 2) bins / weights.

    The orientation atan2(gy, gx) in [0, 2 pi) falls between bins b and b + 1 (mod Q) at fraction f; the pixel votes
    round(unit * |g| * (1 - f)) into b and round(unit * |g| * f) into b + 1 (fixed point, so that sums are exact).
    """
    scale = n_bins / (2.0 * np.pi)
    for y in range(gx.shape[0]):
        for x in range(gx.shape[1]):
            u = np.float64(gx[y, x])
            v = np.float64(gy[y, x])
            mag = np.sqrt(u * u + v * v)
            t = _angle(u, v) * scale
            b0 = int(t)
            f = t - b0
            if b0 >= n_bins:
                b0 -= n_bins
            b1 = b0 + 1
            if b1 >= n_bins:
                b1 -= n_bins
            w = np.rint(mag * unit)
            w1 = np.rint(mag * f * unit)
            bins[y + pad, x + pad, 0] = b0
            bins[y + pad, x + pad, 1] = b1
            weights[y + pad, x + pad, 0] = np.int64(w - w1)
            weights[y + pad, x + pad, 1] = np.int64(w1)


@njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def two_nearest(gram, sq1, sq2, euclidean, best_idx, best, second, col_best_idx, col_best):
    """One pass over a (n1, n2) Gram matrix of descriptors: distances d = sq1[i] + sq2[j] - 2 gram[i, j] (their
    square roots when ``euclidean``); per row the two smallest (and the index of the smallest), per column the
    smallest and its row."""
    n1, n2 = gram.shape
    for j in range(n2):
        col_best[j] = np.inf
        col_best_idx[j] = -1
    for i in range(n1):
        b = np.inf
        s = np.inf
        bi = -1
        si = sq1[i]
        for j in range(n2):
            d = si + sq2[j] - 2.0 * gram[i, j]  # squared distance (sqrt is monotonic: taken at the end)
            if d < b:
                s = b
                b = d
                bi = j
            elif d < s:
                s = d
            if d < col_best[j]:
                col_best[j] = d
                col_best_idx[j] = i
        best_idx[i] = bi
        best[i] = _finish(b, euclidean)
        second[i] = _finish(s, euclidean)
    for j in range(n2):
        col_best[j] = _finish(col_best[j], euclidean)


@njit(cache=True, no_cfunc_wrapper=True, nogil=True, inline="always")
def _finish(d, euclidean):
    if d < 0.0:
        d = 0.0
    if euclidean:
        d = np.sqrt(d)
    return d
