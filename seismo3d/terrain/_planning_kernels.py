"""Numba kernels of the grid planners (A*, D* Lite) on 8-connected grids; see planning.py for the public API.

Cells are flat indices ``n = row * W + col``. Step lengths: ``dy`` along a column, ``dx`` along a row, the
diagonal ``sqrt(dx^2 + dy^2)``. A diagonal step may be forbidden when either orthogonal neighbour it passes is
blocked (``corner_cutting=False``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

_DR = np.array([-1, -1, -1, 0, 0, 1, 1, 1], dtype=np.int64)
_DC = np.array([-1, 0, 1, -1, 1, -1, 0, 1], dtype=np.int64)


@njit(cache=True, inline="always")
def octile(r0, c0, r1, c1, dy, dx, diag):
    """Length of the shortest 8-connected path between two cells of an empty grid (the heuristic), metres."""
    a = abs(r0 - r1)
    b = abs(c0 - c1)
    m = min(a, b)
    return m * diag + (a - m) * dy + (b - m) * dx


@njit(cache=True, inline="always")
def _step(free, w, h, r, c, k, dy, dx, diag, corner_cutting):
    """Cost of the step from (r, c) in direction k, or inf when it leaves the grid or is blocked."""
    dr = _DR[k]
    dc = _DC[k]
    rr = r + dr
    cc = c + dc
    if rr < 0 or rr >= h or cc < 0 or cc >= w or not free[rr, cc] or not free[r, c]:
        return np.inf
    if dr != 0 and dc != 0:
        if not corner_cutting and (not free[r + dr, c] or not free[r, c + dc]):
            return np.inf
        return diag
    return dy if dr != 0 else dx


# ---- binary min-heap over (key1, key2, node) with lazy deletion -------------------------------------------------

@njit(cache=True)
def _less_keys(a1, a2, b1, b2):
    """Key order (lexicographic) with the first components compared up to rounding: keys are sums of step lengths
    taken in different orders, and a tie in exact arithmetic, which D* Lite breaks by the second component, must stay
    a tie (a 1-ulp difference put a node before one it depends on and ended the search early)."""
    if a1 == np.inf or b1 == np.inf:
        return a1 < b1 or (a1 == b1 and a2 < b2)
    tol = 1e-9 * max(abs(a1), abs(b1), 1.0)
    if a1 < b1 - tol:
        return True
    if a1 > b1 + tol:
        return False
    if a2 == np.inf or b2 == np.inf:
        return a2 < b2
    return a2 < b2 - 1e-9 * max(abs(a2), abs(b2), 1.0)


@njit(cache=True)
def heap_push(k1, k2, nodes, size, key1, key2, node):
    """Insert (key1, key2, node) into the heap of ``size`` entries held in the arrays; return the new size."""
    i = size
    k1[i] = key1
    k2[i] = key2
    nodes[i] = node
    while i > 0:
        p = (i - 1) >> 1
        if _less_keys(k1[i], k2[i], k1[p], k2[p]):
            k1[i], k1[p] = k1[p], k1[i]
            k2[i], k2[p] = k2[p], k2[i]
            nodes[i], nodes[p] = nodes[p], nodes[i]
            i = p
        else:
            break
    return size + 1


@njit(cache=True)
def _sift_down(k1, k2, nodes, size, i):
    while True:
        left = 2 * i + 1
        if left >= size:
            break
        best = left
        right = left + 1
        if right < size and _less_keys(k1[right], k2[right], k1[left], k2[left]):
            best = right
        if _less_keys(k1[best], k2[best], k1[i], k2[i]):
            k1[i], k1[best] = k1[best], k1[i]
            k2[i], k2[best] = k2[best], k2[i]
            nodes[i], nodes[best] = nodes[best], nodes[i]
            i = best
        else:
            break


@njit(cache=True)
def _pop(k1, k2, nodes, size):
    """Remove the top; return the new size (the removed entry is left at index size - 1)."""
    last = size - 1
    k1[0], k1[last] = k1[last], k1[0]
    k2[0], k2[last] = k2[last], k2[0]
    nodes[0], nodes[last] = nodes[last], nodes[0]
    _sift_down(k1, k2, nodes, last, 0)
    return last


# ---- A* -----------------------------------------------------------------------------------------------------------

@njit(cache=True)
def astar(free, start, goal, dy, dx, corner_cutting):
    """A* from start to goal (flat indices). Returns (parent, g, n_expanded); g[goal] = inf when unreachable."""
    h, w = free.shape
    n = h * w
    diag = np.sqrt(dx * dx + dy * dy)
    g = np.full(n, np.inf)
    parent = np.full(n, -1, dtype=np.int64)
    closed = np.zeros(n, dtype=np.bool_)
    cap = 8 * n + 16
    k1 = np.empty(cap)
    k2 = np.empty(cap)
    nodes = np.empty(cap, dtype=np.int64)
    gr, gc = goal // w, goal % w
    g[start] = 0.0
    size = heap_push(k1, k2, nodes, 0, octile(start // w, start % w, gr, gc, dy, dx, diag), 0.0, start)
    expanded = 0
    while size > 0:
        size = _pop(k1, k2, nodes, size)
        u = nodes[size]
        if closed[u]:
            continue
        closed[u] = True
        expanded += 1
        if u == goal:
            break
        r, c = u // w, u % w
        for k in range(8):
            cost = _step(free, w, h, r, c, k, dy, dx, diag, corner_cutting)
            if cost == np.inf:
                continue
            v = (r + _DR[k]) * w + (c + _DC[k])
            if closed[v]:
                continue
            tentative = g[u] + cost
            if tentative < g[v]:
                g[v] = tentative
                parent[v] = u
                hv = octile(r + _DR[k], c + _DC[k], gr, gc, dy, dx, diag)
                # ties on f broken towards larger g (deeper nodes): fewer expansions on open ground
                size = heap_push(k1, k2, nodes, size, tentative + hv, -tentative, v)
    return parent, g, expanded


# ---- D* Lite (Koenig & Likhachev 2002, optimised version, Fig. 4) -------------------------------------------------

@njit(cache=True)
def _key(g, rhs, s, start_r, start_c, w, km, dy, dx, diag):
    m = min(g[s], rhs[s])
    return m + octile(start_r, start_c, s // w, s % w, dy, dx, diag) + km, m


@njit(cache=True)
def _rhs_from_successors(free, g, s, w, h, dy, dx, diag, corner_cutting):
    r, c = s // w, s % w
    best = np.inf
    for k in range(8):
        cost = _step(free, w, h, r, c, k, dy, dx, diag, corner_cutting)
        if cost == np.inf:
            continue
        v = (r + _DR[k]) * w + (c + _DC[k])
        val = cost + g[v]
        if val < best:
            best = val
    return best


@njit(cache=True)
def _update_vertex(g, rhs, open_k1, open_k2, in_open, k1, k2, nodes, size, s, start_r, start_c, w, km, dy, dx,
                   diag):
    if g[s] != rhs[s]:
        a, b = _key(g, rhs, s, start_r, start_c, w, km, dy, dx, diag)
        if not in_open[s] or open_k1[s] != a or open_k2[s] != b:
            in_open[s] = True
            open_k1[s] = a
            open_k2[s] = b
            size = heap_push(k1, k2, nodes, size, a, b, s)
    else:
        in_open[s] = False  # stale heap entries are skipped when popped
    return size


@njit(cache=True)
def _compact(k1, k2, nodes, size, in_open, open_k1, open_k2):
    """Drop stale heap entries and re-heapify (when the heap array is nearly full)."""
    j = 0
    for i in range(size):
        s = nodes[i]
        if in_open[s] and open_k1[s] == k1[i] and open_k2[s] == k2[i]:
            k1[j] = k1[i]
            k2[j] = k2[i]
            nodes[j] = s
            j += 1
    for i in range(j // 2 - 1, -1, -1):
        _sift_down(k1, k2, nodes, j, i)
    return j


@njit(cache=True)
def dstar_compute(free, g, rhs, open_k1, open_k2, in_open, k1, k2, nodes, size, start, goal, km, dy, dx,
                  corner_cutting):
    """ComputeShortestPath of D* Lite. Returns (heap size, expansions); the heap arrays are updated in place."""
    h, w = free.shape
    diag = np.sqrt(dx * dx + dy * dy)
    start_r, start_c = start // w, start % w
    cap = k1.shape[0]
    expanded = 0
    while size > 0:
        if size > cap - 16:
            size = _compact(k1, k2, nodes, size, in_open, open_k1, open_k2)
        # top entry, skipping stale ones
        u = nodes[0]
        if not in_open[u] or open_k1[u] != k1[0] or open_k2[u] != k2[0]:
            size = _pop(k1, k2, nodes, size)
            continue
        top1, top2 = k1[0], k2[0]
        s1, s2 = _key(g, rhs, start, start_r, start_c, w, km, dy, dx, diag)
        if not (_less_keys(top1, top2, s1, s2) or rhs[start] > g[start]):
            break
        new1, new2 = _key(g, rhs, u, start_r, start_c, w, km, dy, dx, diag)
        size = _pop(k1, k2, nodes, size)
        if _less_keys(top1, top2, new1, new2):
            open_k1[u] = new1
            open_k2[u] = new2
            size = heap_push(k1, k2, nodes, size, new1, new2, u)
            continue
        expanded += 1
        r, c = u // w, u % w
        if g[u] > rhs[u]:
            g[u] = rhs[u]
            in_open[u] = False
            for k in range(8):
                # predecessors = successors on an undirected grid (step costs are symmetric)
                cost = _step(free, w, h, r, c, k, dy, dx, diag, corner_cutting)
                if cost == np.inf:
                    continue
                s = (r + _DR[k]) * w + (c + _DC[k])
                if s != goal and cost + g[u] < rhs[s]:
                    rhs[s] = cost + g[u]
                size = _update_vertex(g, rhs, open_k1, open_k2, in_open, k1, k2, nodes, size, s, start_r, start_c,
                                      w, km, dy, dx, diag)
        else:
            g_old = g[u]
            g[u] = np.inf
            for k in range(9):
                if k < 8:
                    cost = _step(free, w, h, r, c, k, dy, dx, diag, corner_cutting)
                    if cost == np.inf:
                        continue
                    s = (r + _DR[k]) * w + (c + _DC[k])
                else:
                    cost = 0.0
                    s = u
                if s != goal and (k == 8 or rhs[s] == cost + g_old):
                    rhs[s] = _rhs_from_successors(free, g, s, w, h, dy, dx, diag, corner_cutting)
                size = _update_vertex(g, rhs, open_k1, open_k2, in_open, k1, k2, nodes, size, s, start_r, start_c,
                                      w, km, dy, dx, diag)
    return size, expanded


@njit(cache=True)
def dstar_cells_changed(free, g, rhs, open_k1, open_k2, in_open, k1, k2, nodes, size, cells, start, goal, km, dy,
                        dx, corner_cutting):
    """After ``free`` changed at ``cells``: recompute rhs of every cell whose outgoing steps changed and queue it."""
    h, w = free.shape
    diag = np.sqrt(dx * dx + dy * dy)
    start_r, start_c = start // w, start % w
    cap = k1.shape[0]
    for i in range(cells.shape[0]):
        r0, c0 = cells[i] // w, cells[i] % w
        # the cell itself and its 8 neighbours: every step into or out of the cell, and every diagonal step that
        # passes beside it (both ends of such a step are neighbours of the cell)
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                r, c = r0 + dr, c0 + dc
                if r < 0 or r >= h or c < 0 or c >= w:
                    continue
                s = r * w + c
                if size > cap - 16:
                    size = _compact(k1, k2, nodes, size, in_open, open_k1, open_k2)
                if s != goal:
                    rhs[s] = _rhs_from_successors(free, g, s, w, h, dy, dx, diag, corner_cutting)
                size = _update_vertex(g, rhs, open_k1, open_k2, in_open, k1, k2, nodes, size, s, start_r, start_c,
                                      w, km, dy, dx, diag)
    return size


@njit(cache=True)
def descend(free, g, rhs, start, goal, dy, dx, corner_cutting):
    """Greedy path start -> goal along the cost-to-goal field (each step to the successor minimising step + g);
    returns flat cells (empty when unreachable). The start may be left overconsistent (g > rhs) by the optimised
    D* Lite loop, so its reachability is read from rhs."""
    h, w = free.shape
    diag = np.sqrt(dx * dx + dy * dy)
    out = np.empty(h * w, dtype=np.int64)
    if min(g[start], rhs[start]) == np.inf:
        return out[:0]
    n = 0
    u = start
    out[n] = u
    n += 1
    while u != goal and n < h * w:
        r, c = u // w, u % w
        best = np.inf
        nxt = -1
        for k in range(8):
            cost = _step(free, w, h, r, c, k, dy, dx, diag, corner_cutting)
            if cost == np.inf:
                continue
            v = (r + _DR[k]) * w + (c + _DC[k])
            val = cost + g[v]
            if val < best:
                best = val
                nxt = v
        if nxt < 0:
            return out[:0]
        u = nxt
        out[n] = u
        n += 1
    return out[:n]
