"""The weighted graph-Laplacian least-squares solve of :mod:`~seismo3d.seismic.horizons.lsq`: conjugate gradients on
the traces' pair equations, preconditioned by a coarse level of trace aggregates solved densely."""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["coarse_labels", "solve_weighted"]


_AGGREGATE = 64  # traces per aggregate of the solver's coarse level


_MAX_COARSE = 512  # aggregates at most (their system is solved densely)


def coarse_labels(lateral_shape: tuple) -> tuple[np.ndarray, int]:
    """Aggregates of the solver's coarse level: compact blocks of about :data:`_AGGREGATE` neighbouring traces (as
    square as the grid allows; larger where there would be more than :data:`_MAX_COARSE`), as (n,) int64 labels (C
    order over ``lateral_shape``) and their count."""
    n = int(np.prod(lateral_shape))
    if n == 0:
        return np.zeros(0, np.int64), 1
    size = max(_AGGREGATE, n / _MAX_COARSE)  # traces per aggregate
    labels = np.zeros(lateral_shape, np.int64)
    for axis, length in enumerate(lateral_shape):
        # the side the aggregate's remaining traces would have on the remaining axes: a short axis is taken whole
        # and the aggregates grow along the others
        side = size ** (1.0 / (len(lateral_shape) - axis))
        count = max(1, min(length, int(round(length / side))))
        size /= length / count
        shape = [1] * len(lateral_shape)
        shape[axis] = length
        labels = labels * count + (np.arange(length) * count // length).reshape(shape)  # blocks of equal length
    labels = labels.ravel()  # every block holds a trace (count <= length): the labels are 0 .. n_coarse - 1
    return labels, int(labels.max()) + 1


def solve_weighted(n, a, b, s, w, seeds, seed_times, prev, seed_weight, damping, start, labels, n_coarse):
    """One weighted solve of the normal equations by two-level preconditioned conjugate gradients (started at
    ``start``: the last re-weighted solution, which the next one differs little from)."""
    # normal equations of the pair rows (a graph Laplacian, applied from the pair list) plus the seeds and the damping
    ws = w * s
    rhs = np.bincount(b, ws, minlength=n) - np.bincount(a, ws, minlength=n) + damping ** 2 * prev
    diag = np.full(n, damping ** 2) + np.bincount(seeds, minlength=n) * seed_weight ** 2
    rhs += np.bincount(seeds, seed_weight ** 2 * seed_times, minlength=n)
    # the right-hand side is dominated by the seed rows (seed_weight^2 x time, ~1e6), so a residual relative to it
    # must be small for the pair rows (weights ~1) to be solved to a fraction of a sample
    return _laplacian_cg(a, b, w, diag, rhs, np.array(start, np.float64), 1e-10, 2000, labels, n_coarse)


_SMALL = 16  # aggregates at most for the solver's numpy path (no kernel compiled on a first run)


def _matvec_numpy(ends, w, diag, x, out, values):
    """:func:`_laplacian_matvec`'s ``out`` by ``np.bincount`` (a loop in C over its input's order: ``diag * x`` at
    each trace, then each pair's ``w (x[a] - x[b])`` at ``a`` and its negation at ``b``, as the loop adds them, so the
    same bits but for the sign of a zero); ``ends`` is ``range(n)`` then the pairs' ``a, b`` interleaved, ``values``
    a work array of its size."""
    n = x.size
    np.multiply(diag, x, out=values[:n])
    d = values[n:].reshape(-1, 2)
    np.subtract(x[ends[n::2]], x[ends[n + 1::2]], out=d[:, 0])
    d[:, 0] *= w
    np.negative(d[:, 0], out=d[:, 1])
    out[:] = np.bincount(ends, values, minlength=n)


def _precondition_python(r, inv, labels, rows, z):
    """:func:`_precondition` in Python floats (IEEE doubles as the kernel's, in the kernel's order: the same bits) for
    a coarse level of a few aggregates (``rows``: the factor as nested lists), where it costs less than compiling."""
    nc = len(rows)
    rc = np.bincount(labels, r, minlength=nc).tolist()  # in the traces' order, from 0.0, as the kernel's loop
    for i in range(nc):  # forward: chol y = rc
        v, row = rc[i], rows[i]
        for j in range(i):
            v -= row[j] * rc[j]
        rc[i] = v / row[i]
    for i in range(nc - 1, -1, -1):  # backward: chol^T x = y
        v = rc[i]
        for j in range(i + 1, nc):
            v -= rows[j][i] * rc[j]
        rc[i] = v / rows[i][i]
    np.multiply(inv, r, out=z)
    z += np.array(rc)[labels]


# no_cfunc_wrapper: the kernels here are called from Python and from each other, never as C callbacks, so
# numba's C-callable wrapper of each is not compiled (0.02-0.03 CPU s a kernel on a first run)
@nb.njit(cache=True, no_cfunc_wrapper=True)
def _laplacian_matvec(a, b, w, diag, x, out):
    """``out = (L + diag(diag)) x`` with ``L`` the weighted graph Laplacian of the pairs ``a, b`` (weights ``w``)."""
    for k in range(x.size):
        out[k] = diag[k] * x[k]
    for e in range(a.size):
        d = w[e] * (x[a[e]] - x[b[e]])
        out[a[e]] += d
        out[b[e]] -= d


def _coarse_factor(a, b, w, diag, labels, n_coarse):
    """Cholesky factor (lower) of the aggregates' system ``P^T (L + diag(diag)) P`` (``P`` the 0/1 matrix of
    ``labels``): the pairs inside an aggregate drop out, those between two add to the Laplacian of the aggregates.
    Factored by LAPACK's ``dpotrf`` through scipy as numba's ``np.linalg.cholesky`` calls it (the upper factor of the
    symmetric matrix, transposed: the same bits; the lower one differs in the last bits)."""
    from scipy.linalg.lapack import dpotrf

    i, j = labels[a], labels[b]
    between = i != j
    i, j, we = i[between], j[between], w[between]
    # the traces' diag, then each pair between two aggregates, added in that order (as a loop over them would)
    cells = np.concatenate([labels * (n_coarse + 1),
                            np.stack([i * (n_coarse + 1), j * (n_coarse + 1), i * n_coarse + j, j * n_coarse + i],
                                     axis=1).ravel()])
    values = np.concatenate([diag, np.stack([we, we, -we, -we], axis=1).ravel()])
    coarse = np.bincount(cells, values, minlength=n_coarse * n_coarse)
    upper, info = dpotrf(coarse.reshape(n_coarse, n_coarse), lower=0, clean=1)
    if info != 0:
        raise np.linalg.LinAlgError("the aggregates' system is not positive definite")
    return np.ascontiguousarray(upper.T)


@nb.njit(cache=True, no_cfunc_wrapper=True)
def _precondition(r, inv, labels, chol, rc, z):
    """``z = D^-1 r + P (P^T A P)^-1 P^T r``: Jacobi plus the aggregates' correction (``chol`` the factor of
    :func:`_coarse_factor`; ``rc`` work array)."""
    nc = rc.size
    for i in range(nc):  # loops here, not array expressions: those compile numba's generic setitem and ufuncs
        rc[i] = 0.0
    for k in range(r.size):
        rc[labels[k]] += r[k]
    for i in range(nc):  # forward: chol y = rc
        v = rc[i]
        for j in range(i):
            v -= chol[i, j] * rc[j]
        rc[i] = v / chol[i, i]
    for i in range(nc - 1, -1, -1):  # backward: chol^T x = y
        v = rc[i]
        for j in range(i + 1, nc):
            v -= chol[j, i] * rc[j]
        rc[i] = v / chol[i, i]
    for k in range(r.size):
        z[k] = inv[k] * r[k] + rc[labels[k]]


def _laplacian_cg(a, b, w, diag, rhs, x, rtol, maxiter, labels, n_coarse):
    """Preconditioned conjugate gradients on ``(L + diag(diag)) x = rhs`` from ``x`` (overwritten), stopped when the
    residual's norm falls below ``rtol`` times the right-hand side's (the iteration of :func:`scipy.sparse.linalg.cg`,
    with the Laplacian applied from the pair list by :func:`_laplacian_matvec`); preconditioned by
    :func:`_precondition`. The loop is numpy's, its dot products BLAS's ``ddot`` through scipy (the routine numba's
    ``np.dot`` calls: a compiled loop gave the same bits and cost 1.5-2 CPU s of compiling on a first run). With at
    most :data:`_SMALL` aggregates (up to about 1,000 traces) the two kernels' numpy and Python twins run instead, the
    same bits: compiling the kernels (0.8-1.2 CPU s on a first run) would cost more than they save there."""
    from scipy.linalg.blas import ddot

    n = rhs.size
    # the diagonal of the system: diag, then each pair's weight at both of its traces, added in that order
    inv = 1.0 / np.bincount(np.concatenate([np.arange(n), np.stack([a, b], axis=1).ravel()]),
                            np.concatenate([diag, np.repeat(w, 2)]), minlength=n)
    bnrm = np.sqrt(ddot(rhs, rhs))
    if bnrm == 0.0:
        return rhs.copy()
    chol = _coarse_factor(a, b, w, diag, labels, n_coarse)
    if n_coarse <= _SMALL:
        ends = np.concatenate([np.arange(n), np.stack([a, b], axis=1).ravel()])
        values, rows = np.empty(ends.size), chol.tolist()

        def matvec(v, out):
            _matvec_numpy(ends, w, diag, v, out, values)

        def precondition(r, z):
            _precondition_python(r, inv, labels, rows, z)
    else:
        rc = np.empty(n_coarse)

        def matvec(v, out):
            _laplacian_matvec(a, b, w, diag, v, out)

        def precondition(r, z):
            _precondition(r, inv, labels, chol, rc, z)
    atol = rtol * bnrm
    q = np.empty(n)
    matvec(x, q)
    r = rhs - q
    p = np.empty(n)
    z = np.empty(n)
    rho_prev = 1.0
    for it in range(maxiter):
        if np.sqrt(ddot(r, r)) < atol:
            break
        precondition(r, z)
        rho = ddot(r, z)
        if it > 0:
            p *= rho / rho_prev
            p += z
        else:
            p[:] = z
        matvec(p, q)
        alpha = rho / ddot(p, q)
        x += alpha * p
        r -= alpha * q
        rho_prev = rho
    return x
