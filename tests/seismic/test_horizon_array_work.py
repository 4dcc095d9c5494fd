"""The horizon's array work in numpy (issue 58: no compiling on a first run) against the loops it replaced: the
picker (seismo3d.seismic.reflectors._section_picks), the dynamic programme's candidates, nearest picks, pick gaps
and grid energy (horizons.dp), the neighbouring cycles (horizons.cycle_cut.neighbour_cycle) and the solver's numpy /
Python twins of its kernels on a small coarse level (horizons.laplacian). Each reference below
is the replaced kernel's loop in plain Python; the results must be the same bits (the grid energy: within 1e-13,
numpy's dot products; the pairs' lag search: within 1e-12, its products and near the trace ends its sums taken in
another order). Last, a first run of the horizon compiles only the irregular loops: the dynamic programme (and the
solver's kernels on a coarse level of over 16 aggregates)."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from seismo3d.seismic import reflectors
from seismo3d.seismic.horizons import correlation, cycle_cut, dp, laplacian
from seismo3d.seismic.horizons.lsq import trace_pairs

from .conftest import random_layers


def _ref_trace_picks(a, code, plateau_start):
    # the replaced kernel's loop (reflectors._trace_picks)
    n, out, refine = a.size, [], []
    if code >= 2:
        for i in range(n - 1):
            y0, y1 = a[i], a[i + 1]
            if (code == 2 and y0 < 0.0 <= y1) or (code == 3 and y0 > 0.0 >= y1):
                out.append(i + y0 / (y0 - y1) if y0 != y1 else i)
                refine.append(False)
        return out, refine
    sgn = 1.0 if code == 0 else -1.0
    i = 1
    while i < n - 1:
        y = sgn * a[i]
        if plateau_start:
            if y > 0.0 and y > sgn * a[i - 1] and y >= sgn * a[i + 1]:
                out.append(float(i))
                refine.append(True)
            i += 1
            continue
        if y > 0.0 and y > sgn * a[i - 1]:
            j = i
            while j + 1 < n and sgn * a[j + 1] == y:
                j += 1
            if j + 1 < n and sgn * a[j + 1] < y:
                out.append(0.5 * (i + j) if j > i else float(i))
                refine.append(j == i)
            i = j + 1
        else:
            i += 1
    return out, refine


def test_section_picks_are_the_loops_picks_on_clipped_and_gappy_sections(monkeypatch):
    monkeypatch.setattr(reflectors, "_CHUNK", 50)  # several chunks of traces
    rng = np.random.default_rng(0)
    for trial in range(60):
        a = np.round(rng.normal(size=(int(rng.integers(1, 12)), int(rng.integers(2, 30)))) * 3, trial % 3)
        a = np.clip(a, -2, 2) if trial % 2 else a  # clipped plateaus
        if trial % 5 == 0:
            a[rng.random(a.shape) < 0.1] = np.nan
        for code, plateau_start in ((0, False), (1, False), (2, False), (3, False), (0, True)):
            pos, refine, offsets = reflectors._section_picks(a, code, plateau_start)
            ref = [_ref_trace_picks(row, code, plateau_start) for row in a]
            assert np.array_equal(np.diff(offsets), [len(p) for p, _ in ref])
            assert np.array_equal(pos, np.array([x for p, _ in ref for x in p], np.float64))
            assert np.array_equal(refine, np.array([x for _, r in ref for x in r], np.bool_))


def _layers_with_seeds():
    lat = (6, 30)
    traces, picks, offsets, _ = random_layers(lat, n_samples=50, dip=0.1, seed=2)
    rng = np.random.default_rng(1)
    guide = rng.uniform(-3.0, 53.0, traces.shape[0])  # some guides near or past the trace ends
    guide[::17] = np.nan
    fixed = np.full(guide.size, np.nan)
    fixed[[4, 40, 77]] = guide[[4, 40, 77]] + 0.3
    slopes = rng.normal(size=traces.shape).astype(np.float32)
    across = rng.normal(size=traces.shape).astype(np.float32)
    return lat, traces, picks, offsets, guide, fixed, slopes, across


def test_candidates_are_the_loops_candidates_and_windows():
    lat, traces, picks, offsets, guide, fixed, slopes, across = _layers_with_seeds()
    reach, half = 6.0, 5
    first, pick, unit, whole, slope, cross_slope = dp._candidates(traces, guide, fixed, picks, offsets, reach, half,
                                                                  slopes, across)
    m = 2 * half + 1
    for k in range(guide.size):
        # the replaced kernels' choice (dp._trace_candidates)
        near = [p for p in picks[offsets[k]:offsets[k + 1]] if abs(p - guide[k]) <= reach][:dp._MAX_CANDIDATES]
        if np.isfinite(fixed[k]) and near:
            near = [near[int(np.argmin([abs(p - fixed[k]) for p in near]))]]
        assert np.array_equal(pick[first[k]:first[k + 1]], near)
        for q in range(first[k], first[k + 1]):
            assert slope[q] == slopes[k, min(max(int(round(pick[q])), 0), traces.shape[1] - 1)]
            assert cross_slope[q] == across[k, min(max(int(round(pick[q])), 0), traces.shape[1] - 1)]
            win = np.array([dp.sample_at.py_func(traces[k], pick[q] - half + s) for s in range(m)])
            assert whole[q] == np.isfinite(win).all()
            if whole[q]:
                mean = 0.0
                for v in win:
                    mean += v
                win -= mean / m
                ss = 0.0
                for v in win:
                    ss += v * v
                assert np.array_equal(unit[q], (win * (1.0 / np.sqrt(ss))).astype(np.float32))
            else:
                assert not unit[q].any()
    assert (np.diff(first) > 1).any() and (~whole).any()


def test_trace_search_nearest_picks_gaps_and_cycles_are_the_loops():
    _, traces, picks, offsets, guide, _, _, _ = _layers_with_seeds()
    n = guide.size
    k = np.arange(n)
    for side in ("left", "right"):
        got = dp.trace_search(picks, offsets, k, np.nan_to_num(guide), side)
        want = [offsets[j] + np.searchsorted(picks[offsets[j]:offsets[j + 1]], np.nan_to_num(guide[j]), side)
                for j in k]
        assert np.array_equal(got, want)
    nearest = dp._nearest_picks(picks, offsets, guide, 3.0)
    for j in k:
        d = np.abs(picks[offsets[j]:offsets[j + 1]] - guide[j])
        ok = np.nonzero(d <= 3.0)[0]
        want = picks[offsets[j] + ok[d[ok] == d[ok].min()][-1]] if ok.size else np.nan  # the later on a tie
        assert np.array_equal(nearest[j], want, equal_nan=True)
    gaps = dp._pick_gaps(picks, offsets, k, guide)
    want = []
    for j in k:
        p = picks[offsets[j]:offsets[j + 1]]
        if p.size >= 2 and np.isfinite(guide[j]):
            i = min(max(int(np.searchsorted(p, guide[j])), 1), p.size - 1)
            want.append(p[i] - p[i - 1])
    assert np.array_equal(gaps, want)
    for direction in (1, -1):
        got = cycle_cut.neighbour_cycle(picks, offsets, guide, direction, 2.5)
        for j in k:
            p = picks[offsets[j]:offsets[j + 1]]
            if direction > 0:
                after = p[p >= guide[j] + 2.5]
                want = after[0] if after.size else np.nan
            else:
                before = p[p <= guide[j] - 2.5]
                want = before[-1] if before.size else np.nan
            assert np.array_equal(got[j], want, equal_nan=True)


def test_grid_energy_is_the_loops_energy():
    lat, traces, picks, offsets, guide, fixed, slopes, across = _layers_with_seeds()
    half = 5
    cands = dp._candidates(traces, guide, fixed, picks, offsets, 6.0, half, slopes, across)
    first, pick, unit, whole = cands[:4]
    rng = np.random.default_rng(3)
    count = np.diff(first)
    for trial in range(4):
        choice = first[:-1] + rng.integers(0, 1 << 20, count.size) % np.maximum(count, 1)
        t = np.where(count > 0, pick[np.minimum(choice, pick.size - 1)], np.nan)
        if trial == 3:
            t[rng.random(t.size) < 0.2] += 0.4  # picks that are no candidate
        out, g, wg = t.reshape(lat), guide.reshape(lat), rng.random(lat)
        # faults' jumps between neighbours (trial 0: none), some of unknown throw (NaN: the step costs nothing)
        jumps = [np.where(rng.random((lat[0] - 1, lat[1])) < 0.1, rng.normal(0.0, 4.0, (lat[0] - 1, lat[1])), 0.0),
                 np.where(rng.random((lat[0], lat[1] - 1)) < 0.1, rng.normal(0.0, 4.0, (lat[0], lat[1] - 1)), 0.0)]
        if trial == 0:
            jumps = [np.zeros_like(v) for v in jumps]
        jumps[1][rng.random(jumps[1].shape) < 0.03] = np.nan
        steps = dp._grid_jumps(jumps, lat)
        energy = dp._grid_energy(out, g, wg, first, pick, unit, whole, traces, slopes, across, steps, 0.7, 1.9, half)
        # the replaced kernel's loop (dp._grid_energy)
        wa, wb, e = np.empty(2 * half + 1), np.empty(2 * half + 1), 0.0
        ni, nx = lat
        for i in range(ni):
            for j in range(nx):
                if not np.isfinite(out[i, j]):
                    continue
                e += wg[i, j] * abs(out[i, j] - g[i, j])
                kk = i * nx + j
                q = dp._candidate_at.py_func(first, pick, kk, out[i, j])
                for i2, j2, along, jump in ((i + 1, j, across, jumps[0]), (i, j + 1, slopes, jumps[1])):
                    if i2 >= ni or j2 >= nx or not np.isfinite(out[i2, j2]):
                        continue
                    k2 = i2 * nx + j2
                    step = (out[i2, j2] - out[i, j]) - 0.5 * (dp._slope_at.py_func(along, kk, out[i, j])
                                                              + dp._slope_at.py_func(along, k2, out[i2, j2]))
                    q2 = dp._candidate_at.py_func(first, pick, k2, out[i2, j2])
                    if q >= 0 and q2 >= 0 and whole[q] and whole[q2]:
                        r = float(np.dot(unit[q].astype(np.float64), unit[q2].astype(np.float64)))
                    else:
                        r = dp._pick_ncc(traces, unit, whole, kk, out[i, j], q, k2, out[i2, j2], q2, half, wa, wb)
                    fault = jump[i, j]  # the faults' jump from (i, j) to (i2, j2)
                    e += (0.0 if np.isnan(fault) else 0.7 * (step - fault) ** 2) + 1.9 * (1.0 - r)
        assert energy == pytest.approx(e, rel=1e-13)


def _ref_pair_lag(trace_a, ta, trace_b, centre, half, max_lag, min_fraction):
    # the replaced kernel's loop for one pair (correlation._pair_lags_share with its helpers), each lag on its own
    n_s = trace_a.size
    sample = dp.sample_at.py_func
    if not (np.isfinite(ta) and np.isfinite(centre)):
        return np.nan, np.nan
    h = min(half, int(np.floor(ta)), int(np.floor(n_s - 1 - ta)))
    if h < 4:
        return np.nan, np.nan
    m = 2 * h + 1
    min_samples = max(int(min_fraction * m), 5)
    ref = np.array([sample(trace_a, ta - h + k) for k in range(m)])
    sig = np.array([sample(trace_b, centre - h - max_lag + k) for k in range(m + 2 * max_lag)])
    reach = max_lag
    for k in range(max_lag + 1):
        lo, hi = centre - h - k, centre + h + k
        if (min(lo + m - 1, n_s - 1.0) - max(lo, 0.0) + 1 < min_samples
                or min(hi, n_s - 1.0) - max(hi - m + 1, 0.0) + 1 < min_samples):
            reach = k - 1
            break
    ref = ref - ref.mean()
    scores = np.full(2 * max_lag + 1, np.nan)
    for s in range(max_lag - reach, max_lag + reach + 1):
        y = sig[s:s + m]
        ok = np.isfinite(ref) & np.isfinite(y)
        if ok.sum() < min_samples:
            continue
        x, y = ref[ok] - ref[ok].mean(), y[ok] - y[ok].mean()
        saa, sbb = x @ x, y @ y
        scores[s] = x @ y / np.sqrt(saa * sbb) if saa > 0 and sbb > 0 else 0.0
    if np.isnan(scores).all():
        return np.nan, np.nan
    k = int(np.nanargmax(scores))
    off = 0.0
    if 0 < k < 2 * max_lag and np.isfinite(scores[k - 1]) and np.isfinite(scores[k + 1]):
        y0, y1, y2 = scores[k - 1:k + 2]
        if y0 - 2 * y1 + y2 < 0:
            off = float(np.clip(0.5 * (y0 - y2) / (y0 - 2 * y1 + y2), -0.5, 0.5))
    return k - max_lag + off, scores[k]


@pytest.mark.slow
def test_pair_lags_are_the_loops_lags_near_the_trace_ends_and_at_nan_times():
    # the lag search in numpy against the replaced kernel's loop: shortened windows near both ends, lags cut where
    # they leave trace b, NaN times, a flat trace; the scores within 1e-12 (products summed in another order)
    rng = np.random.default_rng(5)
    traces, _, _, _ = random_layers((40,), n_samples=60, dip=0.2, seed=4)
    traces = traces + 0.3 * traces.std() * rng.standard_normal(traces.shape).astype(np.float32)
    traces[3] = 0.5  # flat
    n = 600
    a, b = rng.integers(0, 40, n), rng.integers(0, 40, n)
    ta = rng.uniform(-2.0, 62.0, n)
    tb = ta + rng.uniform(-6.0, 6.0, n)
    ta[::37] = np.nan
    tb[::41] = np.round(tb[::41])  # whole samples, the last one among them
    for half, max_lag, fraction in ((16, 12, 0.8), (8, 3, 0.5), (6, 0, 0.8)):
        lag, score = correlation.pair_lags(traces, a, ta, b, tb, half, max_lag, fraction)
        want = np.array([_ref_pair_lag(traces[i], ta[p], traces[j], tb[p], half, max_lag, fraction)
                         for p, (i, j) in enumerate(zip(a, b))])
        assert np.array_equal(np.isnan(lag), np.isnan(want[:, 0]))
        assert np.isfinite(lag).sum() > n // 2
        np.testing.assert_allclose(lag, want[:, 0], rtol=0, atol=1e-10)
        np.testing.assert_allclose(score, want[:, 1], rtol=0, atol=1e-12)


def test_the_solvers_twins_are_its_kernels_bits():
    # the matvec by np.bincount and the preconditioner in Python floats against the kernels (the matvec: the same
    # values, a zero's sign aside), on random graphs and coarse levels
    rng = np.random.default_rng(3)
    for trial in range(30):
        n = int(rng.integers(2, 800))
        e = int(rng.integers(1, 5 * n))
        a, b, w = rng.integers(0, n, e), rng.integers(0, n, e), rng.random(e)
        diag, x = rng.random(n) * (trial % 2), rng.normal(size=n)
        x[::7] = 0.0
        want, got = np.empty(n), np.empty(n)
        laplacian._laplacian_matvec(a, b, w, diag, x, want)
        ends = np.concatenate([np.arange(n), np.stack([a, b], axis=1).ravel()])
        laplacian._matvec_numpy(ends, w, diag, x, got, np.empty(ends.size))
        nonzero = want != 0
        assert np.array_equal(got, want) and np.array_equal(got[nonzero].view(np.int64), want[nonzero].view(np.int64))
        nc = int(rng.integers(1, 20))
        labels = np.concatenate([np.arange(min(nc, n)), rng.integers(0, nc, n - min(nc, n))])
        m = rng.normal(size=(nc, nc))
        chol = np.linalg.cholesky(m @ m.T + nc * np.eye(nc))
        r, inv = rng.normal(size=n), rng.random(n)
        laplacian._precondition(r, inv, labels, chol, np.empty(nc), want)
        laplacian._precondition_python(r, inv, labels, chol.tolist(), got)
        assert np.array_equal(got.view(np.int64), want.view(np.int64)), trial


@pytest.mark.parametrize("shape", [(20, 30), (300,), (9, 12)])
def test_the_solve_on_a_small_coarse_level_is_the_kernels_solve(monkeypatch, shape):
    # a whole weighted solve through the twins (the default up to 16 aggregates) and through the kernels: the same bits
    rng = np.random.default_rng(sum(shape))
    a, b, _, _ = trace_pairs(shape, (1, 2, 4))
    n = int(np.prod(shape))
    labels, n_coarse = laplacian.coarse_labels(shape)
    assert 1 < n_coarse <= laplacian._SMALL
    s, w = rng.normal(size=a.size), rng.random(a.size)
    seeds = np.array([0, n // 2])
    args = (n, a, b, s, w, seeds, np.array([30.0, 31.5]), np.full(n, 30.0), 1e3, 1e-3, np.full(n, 30.0), labels,
            n_coarse)
    got = laplacian.solve_weighted(*args)
    monkeypatch.setattr(laplacian, "_SMALL", 0)
    want = laplacian.solve_weighted(*args)
    assert np.array_equal(got.view(np.int64), want.view(np.int64))


_COMPILES = r"""
import json, sys
import numpy as np
from numba.core import event
compiled = set()
library = set()
class Compiles(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        f = ev.data["dispatcher"].py_func
        (compiled if f.__module__.startswith("seismo3d") else library).add(f.__module__ + "." + f.__qualname__)
event.register("numba:compile", Compiles())
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.horizons import track_horizon
syn = synthetic_cube(shape=(16, 16, 64), seed=1)
track_horizon(syn.cube, [(8, 8, 32.0)])
json.dump({"seismo3d": sorted(compiled), "library": sorted(library)}, sys.stdout)
"""


@pytest.mark.slow
def test_a_first_horizon_run_compiles_only_the_dynamic_programme(tmp_path):
    # issue 58: a first run (numba's cache empty) compiles the irregular loops only; the array work (the pairs' lag
    # search too: 4-5 CPU s of compiling before) is numpy's, and on this 16 x 16 cube (4 aggregates) the solver runs
    # its numpy / Python twins (0.8-1.2 CPU s of compiling before)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", _COMPILES], env=env, check=True, capture_output=True, text=True)
    record = json.loads(out.stdout)
    compiled = set(record["seismo3d"])
    # nor any function of numba's of its own: min(), max(), int(), ** and np.empty inside the kernels each compiled one
    # (0.03-0.2 CPU s each, 9 of them before)
    assert record["library"] == [], record["library"]
    allowed = {f"seismo3d.seismic.horizons.dp.{name}" for name in
               ("_choose_lines", "_pick_ncc", "window_ncc", "sample_at", "_slope_at", "_unit_dot", "_candidate_at")}
    assert "seismo3d.seismic.horizons.dp._choose_lines" in compiled
    assert compiled <= allowed, sorted(compiled - allowed)
