"""Numba kernels of the grid planners (A*, D* Lite, the forward search guided by D* Lite); see planning.py for the
public API and the methods' references.

Cells are flat indices ``n = row * W + col``. Step costs are integers: ``cost = (dy, dx, diag)`` in a unit fine
enough that no two paths of different length in metres compare the other way round (planning.py picks it), so sums
are exact whatever their order and ties between equally long paths are exact ties. A diagonal step may be forbidden
when either orthogonal neighbour it passes is blocked (``corner_cutting=False``). ``INF`` marks unreachable cells.
"""

from __future__ import annotations

import numpy as np
from numba import njit

INF = np.int64(1) << np.int64(62)

_DR = np.array([-1, -1, -1, 0, 0, 1, 1, 1], dtype=np.int64)
_DC = np.array([-1, 0, 1, -1, 1, -1, 0, 1], dtype=np.int64)


@njit(cache=True, no_cfunc_wrapper=True)
def octile(r0, c0, r1, c1, cost):
    """Cost of the shortest 8-connected path between two cells of an empty grid (the heuristic)."""
    a = abs(r0 - r1)
    b = abs(c0 - c1)
    m = b if b < a else a  # min(a, b) by a comparison: min() compiles a function of numba's of its own
    return m * cost[2] + (a - m) * cost[0] + (b - m) * cost[1]


@njit(cache=True, no_cfunc_wrapper=True)
def _step(free, h, w, r, c, k, cost, corner_cutting):
    """Cost of the step from (r, c) in direction k, or -1 when it leaves the grid or is blocked. Steps are
    symmetric: the step back costs the same and is allowed under the same conditions."""
    dr = _DR[k]
    dc = _DC[k]
    rr = r + dr
    cc = c + dc
    if rr < 0 or rr >= h or cc < 0 or cc >= w or not free[rr, cc] or not free[r, c]:
        return -1
    if dr != 0 and dc != 0:
        if not corner_cutting and (not free[r + dr, c] or not free[r, c + dc]):
            return -1
        return cost[2]
    return cost[0] if dr != 0 else cost[1]


@njit(cache=True, no_cfunc_wrapper=True)
def _less(a1, a2, b1, b2):
    """Lexicographic order of two-component keys."""
    return a1 < b1 or (a1 == b1 and a2 < b2)


# ---- binary min-heap with lazy deletion (forward searches) -------------------------------------------------------

# inlined in its one caller: a called kernel is compiled on its own too (0.3 CPU s)
@njit(cache=True, no_cfunc_wrapper=True, inline="always")
def _push(k1, k2, nodes, size, key1, key2, node):
    """Insert (key1, key2, node) at the end and sift it up; the arrays must have room for size + 1 entries."""
    i = size
    while i > 0:
        p = (i - 1) >> 1
        if not _less(key1, key2, k1[p], k2[p]):
            break
        k1[i] = k1[p]
        k2[i] = k2[p]
        nodes[i] = nodes[p]
        i = p
    k1[i] = key1
    k2[i] = key2
    nodes[i] = node
    return size + 1


@njit(cache=True, no_cfunc_wrapper=True, inline="always")  # as _push
def _pop(k1, k2, nodes, size):
    """Remove the top entry (read it before the call); return the new size."""
    size -= 1
    key1 = k1[size]
    key2 = k2[size]
    node = nodes[size]
    i = 0
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        if child + 1 < size and _less(k1[child + 1], k2[child + 1], k1[child], k2[child]):
            child += 1
        if not _less(k1[child], k2[child], key1, key2):
            break
        k1[i] = k1[child]
        k2[i] = k2[child]
        nodes[i] = nodes[child]
        i = child
    if size > 0:
        k1[i] = key1
        k2[i] = key2
        nodes[i] = node
    return size


# ---- A*, optionally guided by a backward D* Lite search -----------------------------------------------------------

@njit(cache=True, no_cfunc_wrapper=True)
def guide_bound(v, r, c, goal_r, goal_c, cost, back_g, certificate):
    """Lower bound of the cost from cell v = (r, c) to the goal.

    Without a certificate (``certificate[0] == 0``) the octile distance. With one, from a backward D* Lite search
    whose grid has no more obstacles than the one searched now (costs only grew since): its exact cost to the goal
    where it has settled v, otherwise the larger of the octile distance and the bound its queue gives.
    ``certificate = (1, top, km, start row, start col)``, recorded when its loop stopped, ``top`` the queue's
    smallest first key (INF when empty). Then every cell with ``g* + h(start, v) + km < top`` is locally consistent
    with ``g = g*``: follow a shortest path from the goal to v; the first cell on it that is inconsistent or has a
    wrong g would be queued (or, consistent with g too low, lead down a chain of such cells to a queued one) with a
    key at most v's, below ``top``, since stored keys never exceed true ones (km) and h is consistent. So a cell with
    ``g + h(start, v) + km < top`` has ``g = g*`` (it is consistent, as a queued cell's key is at least ``top``, and
    g cannot be too high or too low by the same argument), and any other has ``g* >= top - km - h(start, v)``.
    """
    h = octile(r, c, goal_r, goal_c, cost)
    if certificate[0] == 0:
        return h
    top = certificate[1]
    gb = back_g[v]
    if top >= INF:  # the backward queue is empty: every cell is consistent and exact
        return gb
    hs = octile(certificate[3], certificate[4], r, c, cost)
    if gb < INF and gb + hs + certificate[2] < top:
        return gb
    below = top - certificate[2] - hs
    return below if below > h else h  # max(h, below) by a comparison (max() compiles a function of numba's)


@njit(cache=True, no_cfunc_wrapper=True)
def bound_field(shape_h, w, goal, cost, back_g, certificate, lower, exact):
    """:func:`guide_bound` of every cell into ``lower`` (N,), and into ``exact`` (N,) whether it is the cell's exact
    cost (settled by the backward search)."""
    goal_r, goal_c = goal // w, goal % w
    top = certificate[1]
    for r in range(shape_h):
        for c in range(w):
            v = r * w + c
            lower[v] = guide_bound(v, r, c, goal_r, goal_c, cost, back_g, certificate)
            if certificate[0] == 0:
                exact[v] = False
            elif top >= INF:
                exact[v] = True
            else:
                hs = octile(certificate[3], certificate[4], r, c, cost)
                exact[v] = back_g[v] < INF and back_g[v] + hs + certificate[2] < top


@njit(cache=True, no_cfunc_wrapper=True)
def forward_search(free, start, goal, cost, corner_cutting, g, parent, stamp, generation, back_g, certificate, k1, k2,
                   nodes):
    """A* from ``start`` to ``goal`` (flat indices) with the bound of :func:`guide_bound` as heuristic.

    ``g``, ``parent`` and ``stamp`` are work arrays of N entries kept between calls: a cell's g and parent are valid
    only where ``stamp == generation`` (no O(N) reset per search). Ties on f go to the larger g (deeper cells). An
    entry popped with a g above the cell's current one is outdated and skipped; a cell whose g drops after its
    expansion is queued again, so the result is optimal for any admissible bound (with a consistent one, as here,
    no cell is expanded twice). ``k1``, ``k2``, ``nodes``: the queue's arrays, allocated by the caller (numba's
    allocator in a kernel costs a first run compiling); when the queue fills them the search stops and returns
    expanded = -1 (call again with longer ones and a new generation: 8 N + 1 entries always suffice, each entry being
    a cell's g lowered). Returns (cost to the goal or INF, expansions); the path is read from ``parent``.
    """
    h, w = free.shape
    goal_r, goal_c = goal // w, goal % w
    stamp[start] = generation
    g[start] = 0
    parent[start] = -1
    bound = guide_bound(start, start // w, start % w, goal_r, goal_c, cost, back_g, certificate)
    if bound >= INF:
        return INF, 0
    # the start alone in the queue, written here: a second call of _push would be compiled a second time
    k1[0], k2[0], nodes[0] = bound, 0, start
    size = np.int64(1)
    expanded = 0
    while size > 0:
        u = nodes[0]
        gu = -k2[0]
        size = _pop(k1, k2, nodes, size)
        if gu != g[u]:
            continue  # outdated entry
        expanded += 1
        if u == goal:
            return gu, expanded
        r, c = u // w, u % w
        for k in range(8):
            step = _step(free, h, w, r, c, k, cost, corner_cutting)
            if step < 0:
                continue
            rv, cv = r + _DR[k], c + _DC[k]
            v = rv * w + cv
            tentative = gu + step
            if stamp[v] == generation and tentative >= g[v]:
                continue
            bound = guide_bound(v, rv, cv, goal_r, goal_c, cost, back_g, certificate)
            if bound >= INF:
                continue  # the backward search proved the goal unreachable from v
            if size == k1.shape[0]:
                return INF, -1  # the queue is full
            stamp[v] = generation
            g[v] = tentative
            parent[v] = u
            size = _push(k1, k2, nodes, size, tentative + bound, -tentative, v)
    return INF, expanded


def run_forward_search(free, start, goal, cost, corner_cutting, g, parent, stamp, generation, back_g, certificate,
                       queue):
    """:func:`forward_search` at generation ``generation + 1``, its queue's arrays in ``queue`` (a list: empty or the
    last search's, reused), doubled and run again when it fills them: (cost or INF, expansions, generation used)."""
    start_size = max(1024, min(free.size + 1, 1 << 20))  # N + 1 entries, at most 2^20 (24 MiB) on a large grid
    if not queue or queue[0].size < start_size:
        queue[:] = [np.empty(start_size, dtype=np.int64) for _ in range(3)]
    while True:
        generation += 1
        total, expanded = forward_search(free, start, goal, cost, corner_cutting, g, parent, stamp, generation, back_g,
                                         certificate, *queue)
        if expanded >= 0:
            return total, expanded, generation
        queue[:] = [np.empty(2 * queue[0].size, dtype=np.int64) for _ in range(3)]


def trace_back(parent, start, goal):
    """Flat cells from start to goal along ``parent`` (written by :func:`forward_search`), (n,) int64: a loop over
    the path in Python (compiled, it cost a first run 0.2 CPU s)."""
    out = [goal]
    while out[-1] != start:
        out.append(int(parent[out[-1]]))
    return np.array(out[::-1], dtype=np.int64)


# ---- indexed binary min-heap (D* Lite: one entry per cell, keys updated in place) --------------------------------

@njit(cache=True, no_cfunc_wrapper=True)
def _place(k1, k2, nodes, pos, i, key1, key2, node):
    k1[i] = key1
    k2[i] = key2
    nodes[i] = node
    pos[node] = i


@njit(cache=True, no_cfunc_wrapper=True)
def _sift_up(k1, k2, nodes, pos, i):
    key1, key2, node = k1[i], k2[i], nodes[i]
    while i > 0:
        p = (i - 1) >> 1
        if not _less(key1, key2, k1[p], k2[p]):
            break
        _place(k1, k2, nodes, pos, i, k1[p], k2[p], nodes[p])
        i = p
    _place(k1, k2, nodes, pos, i, key1, key2, node)


@njit(cache=True, no_cfunc_wrapper=True)
def _sift_down(k1, k2, nodes, pos, size, i):
    key1, key2, node = k1[i], k2[i], nodes[i]
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        if child + 1 < size and _less(k1[child + 1], k2[child + 1], k1[child], k2[child]):
            child += 1
        if not _less(k1[child], k2[child], key1, key2):
            break
        _place(k1, k2, nodes, pos, i, k1[child], k2[child], nodes[child])
        i = child
    _place(k1, k2, nodes, pos, i, key1, key2, node)


@njit(cache=True, no_cfunc_wrapper=True)
def heap_set(k1, k2, nodes, pos, size, node, key1, key2):
    """Insert ``node`` or change its key; return the new size."""
    i = pos[node]
    if i < 0:
        i = size
        size += 1
        _place(k1, k2, nodes, pos, i, key1, key2, node)
        _sift_up(k1, k2, nodes, pos, i)
    elif _less(key1, key2, k1[i], k2[i]):
        k1[i] = key1
        k2[i] = key2
        _sift_up(k1, k2, nodes, pos, i)
    else:
        k1[i] = key1
        k2[i] = key2
        _sift_down(k1, k2, nodes, pos, size, i)
    return size


@njit(cache=True, no_cfunc_wrapper=True)
def _heap_remove(k1, k2, nodes, pos, size, node):
    """Remove ``node`` (which must be queued); return the new size."""
    i = pos[node]
    pos[node] = -1
    size -= 1
    if i == size:
        return size
    _place(k1, k2, nodes, pos, i, k1[size], k2[size], nodes[size])
    if i > 0 and _less(k1[i], k2[i], k1[(i - 1) >> 1], k2[(i - 1) >> 1]):
        _sift_up(k1, k2, nodes, pos, i)
    else:
        _sift_down(k1, k2, nodes, pos, size, i)
    return size


# ---- D* Lite (Koenig & Likhachev 2002, optimised version, Fig. 4), searching from the goal ------------------------

@njit(cache=True, no_cfunc_wrapper=True)
def _key(g, rhs, s, r, c, start_r, start_c, km, cost):
    """D* Lite's key of cell s = (r, c)."""
    m = min(g[s], rhs[s])
    if m >= INF:
        return INF, INF
    return m + octile(start_r, start_c, r, c, cost) + km, m


@njit(cache=True, no_cfunc_wrapper=True)
def _rhs_from_successors(free, g, r, c, w, h, cost, corner_cutting):
    """min over the steps out of (r, c) of step + g."""
    best = INF
    for k in range(8):
        step = _step(free, h, w, r, c, k, cost, corner_cutting)
        if step < 0:
            continue
        gv = g[(r + _DR[k]) * w + (c + _DC[k])]
        if gv < INF and step + gv < best:
            best = step + gv
    return best


@njit(cache=True, no_cfunc_wrapper=True)
def _update_vertex(g, rhs, k1, k2, nodes, pos, size, s, r, c, start_r, start_c, km, cost):
    """Queue cell s = (r, c) with its key when inconsistent, else take it out of the queue."""
    if g[s] != rhs[s]:
        a, b = _key(g, rhs, s, r, c, start_r, start_c, km, cost)
        return heap_set(k1, k2, nodes, pos, size, s, a, b)
    if pos[s] >= 0:
        return _heap_remove(k1, k2, nodes, pos, size, s)
    return size


@njit(cache=True, no_cfunc_wrapper=True)
def dstar_compute(free, g, rhs, k1, k2, nodes, pos, size, start, goal, km, cost, corner_cutting, lookahead):
    """ComputeShortestPath of D* Lite, carried on until the queue's smallest key exceeds the start's by
    ``lookahead`` times the start's cost (0: the paper's loop). Returns (heap size, expansions, the queue's smallest
    first key or INF)."""
    h, w = free.shape
    start_r, start_c = start // w, start % w
    expanded = 0
    while size > 0:
        s1, s2 = _key(g, rhs, start, start_r, start_c, start_r, start_c, km, cost)
        if s2 < INF:
            s1 += np.int64(lookahead * s2)
        top1, top2 = k1[0], k2[0]
        if not (_less(top1, top2, s1, s2) or rhs[start] > g[start]):
            break
        u = nodes[0]
        r, c = u // w, u % w
        new1, new2 = _key(g, rhs, u, r, c, start_r, start_c, km, cost)
        if _less(top1, top2, new1, new2):  # queued before the robot moved: the key only grows
            size = heap_set(k1, k2, nodes, pos, size, u, new1, new2)
            continue
        expanded += 1
        if g[u] > rhs[u]:  # overconsistent: its cost is final
            g[u] = rhs[u]
            size = _heap_remove(k1, k2, nodes, pos, size, u)
            for k in range(8):
                # predecessors = successors on an undirected grid
                step = _step(free, h, w, r, c, k, cost, corner_cutting)
                if step < 0:
                    continue
                rs, cs = r + _DR[k], c + _DC[k]
                s = rs * w + cs
                if s != goal and step + g[u] < rhs[s]:
                    rhs[s] = step + g[u]
                    size = _update_vertex(g, rhs, k1, k2, nodes, pos, size, s, rs, cs, start_r, start_c, km, cost)
        else:  # underconsistent: raise it and let the cells that relied on it find another way
            g_old = g[u]
            g[u] = INF
            size = _update_vertex(g, rhs, k1, k2, nodes, pos, size, u, r, c, start_r, start_c, km, cost)
            for k in range(8):
                step = _step(free, h, w, r, c, k, cost, corner_cutting)
                if step < 0:
                    continue
                rs, cs = r + _DR[k], c + _DC[k]
                s = rs * w + cs
                if s != goal and rhs[s] == step + g_old:
                    rhs[s] = _rhs_from_successors(free, g, rs, cs, w, h, cost, corner_cutting)
                    size = _update_vertex(g, rhs, k1, k2, nodes, pos, size, s, rs, cs, start_r, start_c, km, cost)
    top = k1[0] if size > 0 else INF
    return size, expanded, top


@njit(cache=True, no_cfunc_wrapper=True)
def dstar_cells_changed(free, g, rhs, k1, k2, nodes, pos, size, cells, start, goal, km, cost, corner_cutting):
    """After ``free`` changed at ``cells``: recompute the rhs of every cell whose steps changed and queue it."""
    h, w = free.shape
    start_r, start_c = start // w, start % w
    for i in range(cells.shape[0]):
        r0, c0 = cells[i] // w, cells[i] % w
        # the cell and its 8 neighbours: every step into or out of the cell, and every diagonal step that passes
        # beside it (both ends of such a step are neighbours of the cell)
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                r, c = r0 + dr, c0 + dc
                if r < 0 or r >= h or c < 0 or c >= w:
                    continue
                s = r * w + c
                if s != goal:
                    rhs[s] = _rhs_from_successors(free, g, r, c, w, h, cost, corner_cutting)
                size = _update_vertex(g, rhs, k1, k2, nodes, pos, size, s, r, c, start_r, start_c, km, cost)
    return size


@njit(cache=True, no_cfunc_wrapper=True)
def count_raised(known, g, rhs, cells, start, cost, corner_cutting, lookahead, budget, stamp, generation):
    """How many cells the backward search would have to raise (and lower again) if ``cells`` were blocked, counted
    up to ``budget``: the cells below them in its tree (a cell hangs below a neighbour whose step plus cost to the
    goal equals its own cost; with ties, below each such neighbour, so a cell with another way out is counted too)
    whose key is below the start's plus the lookahead, i.e. that D* Lite would expand before it stops. When the
    start itself hangs below them, the count is ``budget``: D* Lite must then also raise every cell of the tree
    whose key is below the start's new one, which exceeds the old by the length of the detour, not known before the
    search (a wall that closes a passage in front of the robot raises the whole region behind it).
    ``stamp == generation`` marks counted cells."""
    h, w = known.shape
    start_r, start_c = start // w, start % w
    limit = min(g[start], rhs[start])
    if limit < INF:
        limit += np.int64(lookahead * limit)
    queue = np.empty(budget + 9, dtype=np.int64)
    n = 0
    for i in range(cells.shape[0]):
        if n < budget and g[cells[i]] < INF and stamp[cells[i]] != generation:
            stamp[cells[i]] = generation
            queue[n] = cells[i]
            n += 1
    head = 0
    while head < n and n < budget:
        x = queue[head]
        head += 1
        r, c = x // w, x % w
        for k in range(8):
            step = _step(known, h, w, r, c, k, cost, corner_cutting)
            if step < 0:
                continue
            rv, cv = r + _DR[k], c + _DC[k]
            v = rv * w + cv
            if stamp[v] == generation or g[v] != step + g[x]:
                continue
            if v == start:
                return budget  # the robot's own cost rises by a detour unknown here: so does the repair's reach
            if g[v] + octile(start_r, start_c, rv, cv, cost) >= limit:
                continue
            stamp[v] = generation
            queue[n] = v
            n += 1
    return min(n, budget)


@njit(cache=True, no_cfunc_wrapper=True)
def dstar_rekey(g, rhs, k1, k2, nodes, pos, size, start, w, cost):
    """Recompute every queued key with km = 0 (when km grows large) and restore the heap order."""
    start_r, start_c = start // w, start % w
    for i in range(size):
        # km as np.int64(0), not 0: a literal 0 compiled _key once more, for Literal[int](0) (0.26 CPU s)
        k1[i], k2[i] = _key(g, rhs, nodes[i], nodes[i] // w, nodes[i] % w, start_r, start_c, np.int64(0), cost)
    for i in range(size // 2 - 1, -1, -1):
        _sift_down(k1, k2, nodes, pos, size, i)


@njit(cache=True, no_cfunc_wrapper=True)
def descend(free, g, rhs, start, goal, cost, corner_cutting):
    """Path start -> goal along the cost-to-goal field (each step to the successor minimising step + g); returns
    flat cells (empty when unreachable). The optimised D* Lite loop may leave the start overconsistent (g > rhs),
    so its reachability is read from rhs."""
    h, w = free.shape
    out = np.empty(h * w, dtype=np.int64)
    if min(g[start], rhs[start]) >= INF:
        return out[:0]
    n = 0
    u = start
    out[n] = u
    n += 1
    while u != goal and n < h * w:
        r, c = u // w, u % w
        best = INF
        nxt = -1
        for k in range(8):
            step = _step(free, h, w, r, c, k, cost, corner_cutting)
            if step < 0:
                continue
            v = (r + _DR[k]) * w + (c + _DC[k])
            if g[v] < INF and step + g[v] < best:
                best = step + g[v]
                nxt = v
        if nxt < 0:
            return out[:0]
        u = nxt
        out[n] = u
        n += 1
    return out[:n].copy()
