"""The numba kernels of the fault-likelihood scan (:mod:`~seismo3d.seismic.faults.likelihood.scan`): the packed scan
key, the
smoothing along strike and the exponential smoothing down the dip with the semblance's power, and their coefficients."""

from __future__ import annotations

import numba as nb
import numpy as np

from ...._threads import run_threads
from ....errors import InputError

# used by the scan module; not part of the package's public face
__all__ = ["CODE_BITS", "FL_LEVELS", "box_half", "default_angles", "exponential_coefficient", "orientation_table",
           "scan_dip", "smooth_strike", "sum_samples"]


# numba kernels of the scan

CODE_BITS = 11  # orientation code in the low bits of the packed scan key (at most 2048 orientations)
FL_LEVELS = (1 << 20) - 1  # likelihood quantised to 20 bits in the high bits


@nb.njit(cache=True)
def _shifts(slope, n, origin=0):
    # staircase line: integer offsets round(slope * (k + origin)) - round(slope * origin), k = 0..n-1 (exact integer
    # steps, no interpolation blur). `origin` is the index of element 0 in the whole cube, so that a block of a cube
    # draws the same staircase lines as the whole cube
    sh = np.empty(n, np.int64)
    s0 = int(np.floor(slope * origin + 0.5))
    for k in range(n):
        sh[k] = int(np.floor(slope * (k + origin) + 0.5)) - s0
    return sh


@nb.njit(cache=True)
def _segment(mono, positive, a0, na):
    # t range [lo, hi] of the staircase line a = a0 + sign * mono[t] (mono non-decreasing) inside 0 <= a < na
    if positive:
        lo = np.searchsorted(mono, -a0, side="left")
        hi = np.searchsorted(mono, na - 1 - a0, side="right") - 1
    else:
        lo = np.searchsorted(mono, a0 - na + 1, side="left")
        hi = np.searchsorted(mono, a0, side="right") - 1
    return lo, hi


@nb.njit(cache=True, inline="always")
def _box_rows(x, y, c, m, n, h):
    # y[k, :] = sum of x[j, :] over |j - k| <= h, 0 <= j < m (zero outside), vectorised along the rows
    for j in range(n):
        c[0, j] = 0.0
    for k in range(m):
        for j in range(n):
            c[k + 1, j] = c[k, j] + x[k, j]
    for k in range(m):
        e = min(k + h, m - 1) + 1
        s = max(k - h, 0)
        for j in range(n):
            y[k, j] = c[e, j] - c[s, j]


def smooth_strike(x, alpha, h, origin, n_threads, out):
    """Smoothing along strike of every time slice of ``x`` ((na, nt, nb) float32, C order) into ``out`` (float32,
    ``x.shape``): two passes of a box of half-width ``h`` traces (a triangle filter) along the staircase lines
    ``a = a0 + round(alpha * b)``, zero outside the cube; ``origin`` is the cube index of ``b = 0`` (a block of a
    cube). The lines are shared out in chunks over ``n_threads`` threads (:func:`~seismo3d._threads.run_threads`),
    also inside a block's thread, as the ``prange`` loop it replaces did."""
    run_threads(_smooth_strike_chunks, max(1, n_threads), x, alpha, h, origin, out, from_any_thread=True)


@nb.njit(cache=True, nogil=True)
def _smooth_strike_chunks(share, n_shares, x, alpha, h, origin, out):
    # x in layout (na, nt, nb). Smooth along the staircase lines a = a0 + round(alpha * b) of every time slice with
    # two passes of a box of half-width h (a triangle filter), zero outside the cube; each output sample is written
    # once. `origin`: the cube index of b = 0 (blocks of a cube). The lines are split in 4 chunks per share (at most
    # one per line); this share smooths chunks share, share + n_shares, ... (run_threads) with one workspace.
    na, nt, nbb = x.shape
    sh = _shifts(alpha, nbb, origin)
    s_min = min(sh[0], sh[nbb - 1])
    s_max = max(sh[0], sh[nbb - 1])
    mono = np.abs(sh)
    n_a0 = na + s_max - s_min
    n_chunks = min(n_a0, 4 * n_shares)
    buf = np.empty((nbb, nt), np.float32)
    tmp = np.empty((nbb, nt), np.float32)
    c = np.empty((nbb + 1, nt))
    for ic in range(share, n_chunks, n_shares):
        for i in range(ic * n_a0 // n_chunks, (ic + 1) * n_a0 // n_chunks):
            a0 = i - s_max
            lo, hi = _segment(mono, alpha >= 0, a0, na)
            if hi < lo:
                continue
            m = hi - lo + 1
            for k in range(m):
                a = a0 + sh[lo + k]
                for t in range(nt):
                    buf[k, t] = x[a, t, lo + k]
            _box_rows(buf, tmp, c, m, nt, h)
            _box_rows(tmp, buf, c, m, nt, h)
            for k in range(m):
                a = a0 + sh[lo + k]
                for t in range(nt):
                    out[a, t, lo + k] = buf[k, t]


def scan_dip(sn, sd, beta, a, code_k, power_squarings, tiny, n_threads, key, b0):
    """One plane of the scan: the semblance numerator ``sn`` and denominator ``sd`` ((na, nt, nb) float32, C order)
    smoothed down the dip along the staircase lines ``a = a0 + round(beta * t)`` by a two-sided recursive
    exponential filter of coefficient ``a``, and ``1 - (num / den)^(2^power_squarings)`` quantised with the plane's
    code ``code_k`` into ``key`` ((na, nt, nb') int32, the packed maximum over the planes so far; columns ``b0 ..
    b0 + nb'`` of the inputs). The lines are shared out in chunks over ``n_threads`` threads
    (:func:`~seismo3d._threads.run_threads`), also inside a block's thread, as the ``prange`` loop it replaces did."""
    run_threads(_scan_dip_chunks, max(1, n_threads), sn, sd, beta, a, code_k, power_squarings, tiny, key, b0,
                from_any_thread=True)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _scan_dip_chunks(share, n_shares, sn, sd, beta, a, code_k, power_squarings, tiny, key, b0):
    # sn, sd, key in layout (na, nt, nb). Along the staircase lines a = a0 + round(beta * t) of every (a, t) slice
    # (vectorised over b), smooth the semblance numerator and denominator with a two-sided recursive exponential
    # filter of coefficient `a` (zero-slope ends; Hale's RecursiveExponentialFilter), and keep the maximum of
    # 1 - (num / den)^(2^p) and its orientation code, packed into one int32. Only b0 <= b < b0 + key.shape[2] is
    # scanned (key[..., b - b0]): the core of a block, read from contiguous arrays (vectorised loads). The lines are
    # split in 4 chunks per share (at most one per line); this share scans chunks share, share + n_shares, ...
    # (run_threads) with one workspace. NumPy's error model, as a prange loop's body has: the division below (by
    # d > tiny only) then carries no ZeroDivisionError check, and the loop over b vectorises (1.6x faster a call).
    na, nt = sn.shape[0], sn.shape[1]
    nbb = key.shape[2]
    sh = _shifts(beta, nt, np.int64(0))  # origin int64 as smooth_strike passes it: one compile of _shifts, not two
    s_min = min(sh[0], sh[nt - 1])
    s_max = max(sh[0], sh[nt - 1])
    mono = np.abs(sh)
    n_a0 = na + s_max - s_min
    n_chunks = min(n_a0, 4 * n_shares)
    af = np.float32(a)
    bf = np.float32(1.0 - a)
    yn = np.empty((nt, nbb), np.float32)
    yd = np.empty((nt, nbb), np.float32)
    for ic in range(share, n_chunks, n_shares):
        for i in range(ic * n_a0 // n_chunks, (ic + 1) * n_a0 // n_chunks):
            a0 = i - s_max
            lo, hi = _segment(mono, beta >= 0, a0, na)
            if hi < lo:
                continue
            m = hi - lo + 1
            # causal pass while gathering the line, then the anti-causal pass in place
            aa = a0 + sh[lo]
            for j in range(nbb):
                yn[0, j] = sn[aa, lo, j + b0]
                yd[0, j] = sd[aa, lo, j + b0]
            for k in range(1, m):
                aa = a0 + sh[lo + k]
                for j in range(nbb):
                    yn[k, j] = af * yn[k - 1, j] + bf * sn[aa, lo + k, j + b0]
                    yd[k, j] = af * yd[k - 1, j] + bf * sd[aa, lo + k, j + b0]
            for k in range(m - 2, -1, -1):
                for j in range(nbb):
                    yn[k, j] = af * yn[k + 1, j] + bf * yn[k, j]
                    yd[k, j] = af * yd[k + 1, j] + bf * yd[k, j]
            for k in range(m):
                aa = a0 + sh[lo + k]
                t = lo + k
                for j in range(nbb):
                    d = yd[k, j]
                    s = yn[k, j] / d if d > tiny else np.float32(1.0)
                    s = min(max(s, np.float32(0.0)), np.float32(1.0))
                    # s^(2^p) by repeated squaring (loop-invariant branches, so the loop still vectorises)
                    if power_squarings >= 1:
                        s = s * s
                    if power_squarings >= 2:
                        s = s * s
                    if power_squarings >= 3:
                        s = s * s
                    if power_squarings >= 4:
                        s = s * s
                    if power_squarings >= 5:
                        s = s * s
                    q = np.int32((np.float32(1.0) - s) * np.float32(FL_LEVELS) + np.float32(0.5))
                    key[aa, t, j] = max(key[aa, t, j], (q << CODE_BITS) | code_k)


def exponential_coefficient(sigma: float) -> float:
    """Coefficient of the two-sided recursive exponential filter whose impulse response has standard deviation
    ``sigma`` samples (Hale's RecursiveExponentialFilter)."""
    ss = sigma * sigma
    return float((1.0 + ss - np.sqrt(1.0 + 2.0 * ss)) / ss)


# --------------------------------------------------------------------------------------------------------------------
# fault likelihood


def box_half(sigma: float) -> int:
    # two passes of a box of half-width h have variance 2 h (h + 1) / 3; match it to sigma^2
    return max(1, int(round(np.sqrt(1.5 * sigma * sigma + 0.25) - 0.5)))


def orientation_table(strikes, dips, two_d):
    """Unique (strike, dip) pairs, with for each its shear axis, strike slope, dip slope and strike-group key."""
    if two_d:
        strikes = np.array([90.0, 270.0])
    pairs = []
    seen = set()
    for phi in np.asarray(strikes, dtype=np.float64) % 360.0:
        for theta in np.asarray(dips, dtype=np.float64):
            key_phi = phi % 180.0 if theta >= 90.0 - 1e-9 else phi
            key = (round(key_phi, 6), round(theta, 6))
            if key in seen:
                continue
            seen.add(key)
            pairs.append((key_phi, theta))
    rows = []
    for phi, theta in pairs:
        p = np.radians(phi)
        t = np.radians(theta)
        cot = np.cos(t) / np.sin(t)
        if two_d or abs(np.sin(p)) >= abs(np.cos(p)) - 1e-12:
            axis = 0
            alpha = np.cos(p) / np.sin(p)
            beta = -cot / np.sin(p)
            lateral = abs(np.sin(p))
        else:
            axis = 1
            alpha = np.sin(p) / np.cos(p)
            beta = cot / np.cos(p)
            lateral = abs(np.cos(p))
        rows.append((phi, theta, axis, alpha, beta, lateral))
    return rows


def default_angles(strikes, dips, strike_smoothing, min_dip=60.0, dip_smoothing=20.0):
    if strikes is None:
        # a plane misoriented by d radians leaves the fault by ~ sigma * d at one smoothing width from the centre:
        # a step of 1 / strike_smoothing radians (15 degrees for the default 4 traces) keeps that under half a trace
        n = max(8, int(np.ceil(6.0 * strike_smoothing)))
        strikes = np.arange(n) * (360.0 / n)
    if dips is None:
        # evenly spaced in cot(dip), the lateral shift per sample down the fault, by 1 / dip_smoothing: neighbouring
        # planes part by one trace at one smoothing width (13 dips from 90 to 60 degrees for the defaults)
        cot_max = 1.0 / np.tan(np.radians(min_dip))
        n = 1 + int(np.ceil(cot_max * dip_smoothing - 1e-9))
        dips = np.degrees(np.arctan2(1.0, np.linspace(0.0, cot_max, n)))
    strikes = np.atleast_1d(np.asarray(strikes, dtype=np.float64))
    dips = np.atleast_1d(np.asarray(dips, dtype=np.float64))
    if strikes.ndim != 1 or strikes.size == 0 or not np.all(np.isfinite(strikes)):
        raise InputError(f"strikes must be a non-empty 1D array of finite angles in degrees; got {strikes!r}")
    if dips.ndim != 1 or dips.size == 0 or not np.all((dips > 0) & (dips <= 90)):
        raise InputError(f"dips must be a non-empty 1D array of angles in (0, 90] degrees; got {dips!r}")
    return strikes, dips


def sum_samples(x: np.ndarray, step: int) -> np.ndarray:
    """Sums of ``step`` consecutive samples along the last axis (the last, partial group summed too)."""
    n = x.shape[-1]
    m = -(-n // step)
    pad = m * step - n
    if pad:
        x = np.concatenate([x, np.repeat(x[..., -1:], pad, axis=-1)], axis=-1)
    return np.ascontiguousarray(x.reshape(x.shape[:-1] + (m, step)).sum(axis=-1, dtype=np.float32))
