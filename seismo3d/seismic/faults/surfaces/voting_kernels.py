"""The irregular loops of optimal surface voting (:mod:`~seismo3d.seismic.faults.surfaces.voting`, Wu & Fomel 2018):
the seeds spread greedily over the image (:func:`greedy_seeds`), Hale's dynamic warping with a strain bound in each
seed's box (:func:`surface_kernel`), the votes of the best surface summed per thread (:func:`cast_votes`), and the
strongest surface's orientation at each sample (:func:`strongest`)."""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ...._threads import run_threads
from ....errors import InputError

# used by the voting module; not part of the package's public face
__all__ = ["cast_votes", "greedy_seeds", "place_order", "strongest", "surface_kernel"]


# --------------------------------------------------------------------------------------------------------------------
# dynamic programming in the box: Hale's dynamic warping with a strain bound, as Wu & Fomel (2018) use it


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _prefix(e, c):
    # c[i + 1, l] = sum of e[:i + 1, l]: sums over runs of rows in O(1)
    ni, nl = e.shape
    for l in range(nl):
        c[0, l] = 0.0
    for i in range(ni):
        for l in range(nl):
            c[i + 1, l] = c[i, l] + e[i, l]


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _accumulate_forward(e, b, d, c):
    # d[i, l]: least cost of a path over rows up to i ending at lag l, the lag changing by at most one every b rows
    # (the costs of the b - 1 rows in between are added along the new lag, from the prefix sums c of e made by
    # _prefix before). Forward and backward are two kernels, not one with a flag: a constant flag compiles the kernel
    # once per value; neither calls _prefix: each kernel a called kernel is linked into is compiled again with it
    # (the caller makes c once for both).
    # Each lag's path from row jb over rows jb + 1 .. ji is summed once per row and kept while the lags on either
    # side read it (prev, cur, nxt: the lags il - 1, il, il + 1, clamped at the ends): the same sums, in the same
    # order, as summing it for each neighbour (the same bits), at half the additions: with _accumulate_backward's
    # alike, the surfaces of the generated 256^3 cube's 2406 seeds took 3.18-3.98 CPU s against 3.56-4.29 (4 pairs
    # at load 11).
    ni, nl = e.shape
    for il in range(nl):
        d[0, il] = e[0, il]
    for ii in range(1, ni):
        ji = ii - 1
        jb = max(ii - b, 0)
        cur = d[jb, 0] + c[ji + 1, 0] - c[jb + 1, 0]
        prev = cur
        for il in range(nl):
            nxt = d[jb, il + 1] + c[ji + 1, il + 1] - c[jb + 1, il + 1] if il + 1 < nl else cur
            m = d[ji, il]
            if prev < m:
                m = prev
            if nxt < m:
                m = nxt
            d[ii, il] = m + e[ii, il]
            prev = cur
            cur = nxt


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _accumulate_backward(e, b, d, c):
    # d[i, l]: least cost of a path over rows from i on starting at lag l (as _accumulate_forward, rows reversed)
    ni, nl = e.shape
    for il in range(nl):
        d[ni - 1, il] = e[ni - 1, il]
    for ii in range(ni - 2, -1, -1):
        ji = ii + 1
        jb = min(ii + b, ni - 1)
        # rows ji .. jb - 1 on each lag, summed once per row (as in _accumulate_forward)
        cur = d[jb, 0] + c[jb, 0] - c[ji, 0]
        prev = cur
        for il in range(nl):
            nxt = d[jb, il + 1] + c[jb, il + 1] - c[ji, il + 1] if il + 1 < nl else cur
            m = d[ji, il]
            if prev < m:
                m = prev
            if nxt < m:
                m = nxt
            d[ii, il] = m + e[ii, il]
            prev = cur
            cur = nxt


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _backtrack(d, e, b, u, c):
    # the least-cost path of a forward accumulation, traced back from the cheapest lag of the last row; a change of
    # lag is spread linearly over the b rows it spans (c: prefix sums of e, as left by _accumulate_forward)
    ni, nl = d.shape
    ii = ni - 1
    il = 0
    for jl in range(1, nl):
        if d[ii, jl] < d[ii, il]:
            il = jl
    u[ii] = il
    while ii > 0:
        ji = ii - 1
        jb = max(ii - b, 0)
        ilm = max(il - 1, 0)
        ilp = min(il + 1, nl - 1)
        dm = d[jb, ilm] + c[ji + 1, ilm] - c[jb + 1, ilm]
        dp = d[jb, ilp] + c[ji + 1, ilp] - c[jb + 1, ilp]
        if d[ji, il] <= dm and d[ji, il] <= dp:
            ii -= 1
            u[ii] = il
            continue
        new = ilm if dm <= dp else ilp
        start = u[ii]
        steps = ii - jb
        for s in range(1, steps + 1):
            u[ii - s] = start + (new - il) * s / steps
        ii = jb
        il = new


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _smooth_costs(e, b, t1, t2, c, out):
    # nonlinear smoothing of the costs along axis 0: forward + backward accumulation - cost, the cost of the best
    # path through each (row, lag) (Hale 2013, dynamic warping). Inlined into its caller by numba: a kernel of its
    # own compiled the accumulations linked into it once more (0.5 CPU s on a first run)
    _prefix(e, c)
    _accumulate_forward(e, b, t1, c)
    _accumulate_backward(e, b, t2, c)
    ni, nl = e.shape
    for i in range(ni):
        for l in range(nl):
            out[i, l] = t1[i, l] + t2[i, l] - e[i, l]


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _smooth_exponential(x, a, tmp):
    # two-sided recursive exponential smoothing with zero-slope ends, coefficient a
    n = x.shape[0]
    if a <= 0.0 or n < 2:
        return
    tmp[0] = x[0]
    for i in range(1, n):
        tmp[i] = a * tmp[i - 1] + (1.0 - a) * x[i]
    x[n - 1] = tmp[n - 1]
    for i in range(n - 2, -1, -1):
        x[i] = a * x[i + 1] + (1.0 - a) * tmp[i]


@nb.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _nearest(f, x, y, z, g0, g1):
    # f's sample nearest to the image position (x, y, z), f holding the image from inline g0 and crossline g1: the
    # index is rounded in image coordinates (as when f is the whole image), then clamped to f
    # (math.floor, not int(np.floor()): int() compiled a function of numba's of its own)
    n0, n1, n2 = f.shape
    i = min(max(math.floor(x + 0.5) - g0, 0), n0 - 1)
    j = min(max(math.floor(y + 0.5) - g1, 0), n1 - 1)
    k = min(max(math.floor(z + 0.5), 0), n2 - 1)
    return f[i, j, k]


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _surfaces_of_thread(t, n_threads, att, g0, g1, shape, seeds, order, frames, ru, rv, rw, b, a_smooth, offsets,
                        fa, seed_normal, work3, work2, surfs, work1):
    # steps 1-4 for seeds t, t + n_threads, ... (see surface_kernel), with this thread's work arrays (made by the
    # caller: np.empty here compiled a function of numba's for each shape). One kernel, not a loop calling a kernel
    # per seed: numba compiles a called kernel on its own and again inside its caller (0.8 CPU s more on a first run)
    n0, n1, n2 = shape[0], shape[1], shape[2]
    nu = 2 * ru + 1
    nv = 2 * rv + 1
    nw = 2 * rw + 1
    e = work3[t, 0]  # (nw, nv, nu)
    es = work3[t, 1]
    t1 = work2[t, 0]  # (max(nv, nw) + 1, nu)
    t2 = work2[t, 1]
    cs = work2[t, 2]
    row = work2[t, 3]
    row_s = work2[t, 4]
    surf = surfs[t]  # (nw, nv)
    tmp = work1[t, 0]  # (max(nv, nw),)
    line = work1[t, 1]
    for q in range(t, seeds.shape[0], n_threads):
        s = order[q]  # the seeds in the order of their places (neighbouring boxes share the likelihood they read)
        # seed s: its optimal surface in surf (nw, nv) (offsets across the fault, samples), the surface's mean
        # likelihood inside the image in fa[s] (-1 when no sample of it is inside), its normal at the seed in
        # seed_normal[s] and the samples it passes in offsets[s]. att (n_a, n_b, n2) the likelihood of the image of
        # shape (n0, n1, n2) from inline g0 and crossline g1 on; positions in image coordinates (the same float
        # arithmetic whatever the block)
        c0, c1, c2 = seeds[s, 0], seeds[s, 1], seeds[s, 2]
        ux, uy, uz = frames[s, 0, 0], frames[s, 0, 1], frames[s, 0, 2]
        vx, vy, vz = frames[s, 1, 0], frames[s, 1, 1], frames[s, 1, 2]
        wx, wy, wz = frames[s, 2, 0], frames[s, 2, 1], frames[s, 2, 2]
        # 1. costs 1 - likelihood in the box; outside the cone |u| <= distance from the seed, cost 1, so that the
        #    surface passes near the seed
        for iw in range(nw):
            dw = iw - rw
            for iv in range(nv):
                dv = iv - rv
                r = math.sqrt(dv * dv + dw * dw)
                lim = math.floor(r + 0.5) if r > 2.0 else 0
                x0 = c0 + dv * vx + dw * wx
                y0 = c1 + dv * vy + dw * wy
                z0 = c2 + dv * vz + dw * wz
                for iu in range(nu):
                    du = iu - ru
                    if du < -lim or du > lim:
                        e[iw, iv, iu] = 1.0
                    else:
                        e[iw, iv, iu] = 1.0 - _nearest(att, x0 + du * ux, y0 + du * uy, z0 + du * uz, g0, g1)
        # 2. nonlinear smoothing of the costs down the dip, then along the strike
        for iw in range(nw):
            _smooth_costs(e[iw], b, t1[:nv], t2[:nv], cs[:nv + 1], es[iw])
        if nw > 1:
            for iv in range(nv):
                for iw in range(nw):
                    for iu in range(nu):
                        row[iw, iu] = es[iw, iv, iu]
                _smooth_costs(row[:nw], b, t1[:nw], t2[:nw], cs[:nw + 1], row_s[:nw])
                for iw in range(nw):
                    for iu in range(nu):
                        es[iw, iv, iu] = row_s[iw, iu]
        # 3. the least-cost path down the dip in every strike slice: the surface, smoothed both ways
        for iw in range(nw):
            _prefix(es[iw], cs[:nv + 1])
            _accumulate_forward(es[iw], b, t1[:nv], cs[:nv + 1])
            _backtrack(t1[:nv], es[iw], b, line[:nv], cs[:nv + 1])
            for iv in range(nv):
                surf[iw, iv] = line[iv] - ru
            _smooth_exponential(surf[iw], a_smooth, tmp[:nv])
        if nw > 1:
            for iv in range(nv):
                for iw in range(nw):
                    line[iw] = surf[iw, iv]
                _smooth_exponential(line[:nw], a_smooth, tmp[:nw])
                for iw in range(nw):
                    surf[iw, iv] = line[iw]
        # 4. the surface's mean likelihood inside the image, and its normal at the seed
        total = 0.0
        count = 0
        for iw in range(nw):
            dw = iw - rw
            for iv in range(nv):
                dv = iv - rv
                du = surf[iw, iv]
                x = c0 + du * ux + dv * vx + dw * wx
                y = c1 + du * uy + dv * vy + dw * wy
                z = c2 + du * uz + dv * vz + dw * wz
                if x < -0.5 or y < -0.5 or z < -0.5 or x > n0 - 0.5 or y > n1 - 0.5 or z > n2 - 0.5:
                    continue
                total += _nearest(att, x, y, z, g0, g1)
                count += 1
        if count == 0:
            fa[s] = -1.0
            continue
        fa[s] = total / count
        gv = 0.5 * (surf[rw, rv + 1] - surf[rw, rv - 1])
        gw = 0.5 * (surf[min(rw + 1, nw - 1), rv] - surf[max(rw - 1, 0), rv]) if nw > 1 else 0.0
        nx = ux - gv * vx - gw * wx
        ny = uy - gv * vy - gw * wy
        nz = uz - gv * vz - gw * wz
        nn = math.sqrt(nx * nx + ny * ny + nz * nz)
        nx /= nn
        ny /= nn
        nz /= nn
        seed_normal[s, 0] = nx
        seed_normal[s, 1] = ny
        seed_normal[s, 2] = nz
        # 5. the samples the surface passes, rounded in image coordinates as its votes are cast
        for iw in range(nw):
            dw = iw - rw
            for iv in range(nv):
                dv = iv - rv
                du = surf[iw, iv]
                offsets[s, iw, iv, 0] = math.floor(c0 + du * ux + dv * vx + dw * wx + 0.5) - c0
                offsets[s, iw, iv, 1] = math.floor(c1 + du * uy + dv * vy + dw * wy + 0.5) - c1
                offsets[s, iw, iv, 2] = math.floor(c2 + du * uz + dv * vz + dw * wz + 0.5) - c2


_TILE = 16  # samples a side of the tiles of place_order: a voting box (21 x 41 x 61 samples in 3D) spans a few


def place_order(seeds: np.ndarray) -> np.ndarray:
    """The order of ``seeds`` ((k, 3) int) by the tiles of ``_TILE`` samples a side they lie in (inline, crossline,
    sample tile, then the seed's own indices): the boxes of seeds taken one after the other in it read much the same
    likelihood, from the processor's cache (the cost boxes of the generated 256^3 cube's 2405 seeds filled in 0.99
    CPU s against 1.22-1.29 in the order of strength, 1.37 in a random order). Returns (k,) int64 indices."""
    seeds = np.asarray(seeds).reshape(-1, 3)
    tile = seeds // _TILE
    return np.lexsort((seeds[:, 2], seeds[:, 1], seeds[:, 0], tile[:, 2], tile[:, 1], tile[:, 0])).astype(np.int64)


def surface_kernel(att, g0, g1, shape, seeds, frames, ru, rv, rw, b, a_smooth, n_threads, offsets, fa, seed_normal):
    """Steps 1-4 for every seed, seed ``s`` on thread ``s % n_threads`` (no shared writes): ``fa[s]`` the surface's
    mean likelihood (-1: no vote), ``seed_normal[s]`` its normal at the seed, ``offsets[s, iw, iv]`` the sample
    (inline, crossline, sample) the surface passes at (dip step iv, strike step iw), relative to the seed, rounded
    in image coordinates as the votes are cast (so that :func:`cast_votes` gives the votes of the surface wherever it
    was computed). Arrays as :func:`~seismo3d.seismic.faults.surfaces.voting.seed_surfaces` makes them."""
    n_threads = int(n_threads)
    nu, nv, nw = 2 * ru + 1, 2 * rv + 1, 2 * rw + 1
    nm = max(nv, nw)
    order = place_order(seeds)  # each seed's surface is its own (written at its index), whatever the order
    run_threads(_surfaces_of_thread, n_threads, att, g0, g1, shape, seeds, order, frames, ru, rv, rw, b, a_smooth,
                offsets, fa, seed_normal, np.empty((n_threads, 2, nw, nv, nu)), np.empty((n_threads, 5, nm + 1, nu)),
                np.empty((n_threads, nw, nv)), np.empty((n_threads, 2, nm)))


@nb.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def _votes_of_thread(t, n_threads, seeds, ids, positions, offsets, fa, o0, o1, votes, best, best_seed):
    # the votes of the seeds with ids[s] % n_threads == t, into votes[t], best[t] and best_seed[t] (see cast_votes)
    _, m0, m1, n2 = votes.shape
    nw, nv = offsets.shape[1], offsets.shape[2]
    for s in range(seeds.shape[0]):
        if ids[s] % n_threads != t or fa[s] < 0:
            continue
        f = fa[s]
        p = positions[s]
        c0, c1, c2 = seeds[s, 0], seeds[s, 1], seeds[s, 2]
        for iw in range(nw):
            for iv in range(nv):
                i = c0 + offsets[s, iw, iv, 0] - o0
                j = c1 + offsets[s, iw, iv, 1] - o1
                k = c2 + offsets[s, iw, iv, 2]
                if i < 0 or j < 0 or k < 0 or i >= m0 or j >= m1 or k >= n2:
                    continue
                votes[t, i, j, k] += f
                q = best_seed[t, i, j, k]
                if f > best[t, i, j, k] or (f == best[t, i, j, k] and q >= 0 and p < q):
                    best[t, i, j, k] = f
                    best_seed[t, i, j, k] = p


def cast_votes(seeds, ids, positions, offsets, fa, o0, o1, votes, best, best_seed):
    """Step 5: one vote ``fa[s]`` per sample of each seed's surface (``offsets`` from :func:`surface_kernel`) inside
    the core ``[o0:o0 + m0, o1:o1 + m1]`` of the image.

    Thread ``ids[s] % n_threads`` (``n_threads = votes.shape[0]``; ids: the seeds' indices among all seeds of the
    image, increasing) sums seed s's votes, in the order of the list: the same sums, in the same order, whether the
    cube is voted whole or block by block. ``best`` and ``best_seed`` (n_threads, m0, m1, n2), also per thread,
    record the strongest surface of the thread's seeds through each sample (its mean likelihood and the seed's
    position, ``positions[s]``, in the list of seeds the votes are summed over, increasing with the ids; equal means
    go to the smaller position); :func:`strongest` then takes the strongest over the threads, so the result depends
    neither on the threads' timing nor on their number."""
    run_threads(_votes_of_thread, votes.shape[0], seeds, ids, positions, offsets, fa, o0, o1, votes, best,
                best_seed)


_SLAB = 1 << 20  # samples per slab of strongest: its temporaries stay small


def strongest(best, best_seed, ids, seed_strike, seed_dip, strike, dip):
    """Strike and dip (m0, m1, n2, C order) of the strongest surface through each sample over the threads' records
    of :func:`cast_votes` (the larger mean likelihood, then the smaller seed id ``ids[q]``), written into ``strike``
    and ``dip``; left as they are where no surface passes. Worked in slabs of about 2^20 samples, on the samples of
    each that a surface passes only (a seed recorded by some thread)."""
    if ids.size == 0:  # no seed: no surface passes anywhere
        return
    n_threads = best.shape[0]
    flat_best, flat_seed = best.reshape(n_threads, -1), best_seed.reshape(n_threads, -1)
    flat_strike, flat_dip = strike.reshape(-1), dip.reshape(-1)  # views: C order
    for a in range(0, flat_seed.shape[1], _SLAB):
        at = a + np.flatnonzero(np.any(flat_seed[:, a:a + _SLAB] >= 0, axis=0))
        if not at.size:
            continue
        # the first thread's records as they are, then the others in thread order, as the compiled loop took them
        top = flat_best[0, at]
        s = flat_seed[0, at].astype(np.int64)
        for t in range(1, n_threads):
            q = flat_seed[t, at]
            f = flat_best[t, at]
            tie = (f == top) & (ids[np.maximum(q, 0)] < ids[np.maximum(s, 0)])
            take = (q >= 0) & ((s < 0) | (f > top) | tie)
            top = np.where(take, f, top)
            s = np.where(take, q, s)
        found = s >= 0
        flat_strike[at[found]] = seed_strike[s[found]]
        flat_dip[at[found]] = seed_dip[s[found]]


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _greedy_seeds(cand, d, cells, out):
    # keep candidates (sorted strongest first) with no kept seed within Chebyshev distance d, into out; returns how
    # many. Kept seeds are filed in cells of d + 1 samples per side (cells: all -1): a cell holds at most one (two
    # points of a cell are within d of each other), and a seed within d of a candidate lies in the candidate's cell or
    # a neighbouring one. The arrays come from the caller: np.empty and np.full in here each compiled a function of
    # numba's of its own
    size = d + 1
    g0, g1, g2 = cells.shape
    n = 0
    for c in range(cand.shape[0]):
        i, j, k = cand[c, 0], cand[c, 1], cand[c, 2]
        a, bb, cc = i // size, j // size, k // size
        ok = True
        for x in range(max(a - 1, 0), min(a + 2, g0)):
            for y in range(max(bb - 1, 0), min(bb + 2, g1)):
                for z in range(max(cc - 1, 0), min(cc + 2, g2)):
                    s = cells[x, y, z]
                    if s >= 0 and abs(out[s, 0] - i) <= d and abs(out[s, 1] - j) <= d and abs(out[s, 2] - k) <= d:
                        ok = False
                        break
                if not ok:
                    break
            if not ok:
                break
        if ok:
            cells[a, bb, cc] = n
            out[n, 0] = i
            out[n, 1] = j
            out[n, 2] = k
            n += 1
    return n


def greedy_seeds(points, values, shape, spacing: int) -> np.ndarray:
    """Voting seeds: candidate samples taken strongest first, each more than ``spacing`` samples (Chebyshev distance)
    from every seed taken before it (Wu & Fomel 2018).

    The order is by decreasing value, ties by position (inline, then crossline, then sample), so the seeds do not
    depend on the order the candidates come in: candidates gathered block by block from a cube larger than memory
    give the seeds of the whole cube. Memory: the candidates and one int64 per cell of ``spacing + 1`` samples a side.

    Parameters
    ----------
    points : (n, 3) array_like of int
        Candidate samples (inline, crossline, sample indices; a 2D section's crossline index 0).
    values : (n,) array_like of float
        Their thinned fault likelihood.
    shape : (int, int, int)
        Shape of the cube (a section as (n_traces, 1, n_samples)).
    spacing : int
        Seeds are more than this many samples apart (:meth:`VotingOptions.spacing`).

    Returns
    -------
    (m, 3) int64 ndarray
        The seeds, strongest first.

    Raises
    ------
    InputError
        Points and values differ in length, or a point lies outside ``shape``.

    References
    ----------
    .. [1] X. Wu and S. Fomel, Geophysics 83(5), O67-O82, 2018, doi:10.1190/geo2018-0115.1 (seed picking).
    """
    pts = np.asarray(points, dtype=np.int64).reshape(-1, 3)
    vals = np.asarray(values, dtype=np.float32).ravel()
    shape = tuple(int(n) for n in shape)
    if vals.size != pts.shape[0]:
        raise InputError(f"greedy_seeds got {pts.shape[0]} points but {vals.size} values; pass one value per point")
    if pts.shape[0] == 0:
        return np.zeros((0, 3), np.int64)
    if pts.min() < 0 or np.any(pts.max(axis=0) >= np.asarray(shape)):
        raise InputError(f"greedy_seeds got points outside a cube of shape {shape}; pass indices of that cube")
    key = np.ravel_multi_index(tuple(pts.T), shape)
    order = np.lexsort((key, -vals))
    size = int(spacing) + 1
    cells = np.full(tuple((n + size - 1) // size for n in shape), -1, np.int64)
    out = np.empty(pts.shape, np.int64)
    return out[:_greedy_seeds(np.ascontiguousarray(pts[order]), int(spacing), cells, out)]
