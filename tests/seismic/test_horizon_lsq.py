"""Least-squares horizons (seismo3d.seismic.horizons.lsq): pairs, correlation shifts, the robust solve, the cycle-skip
self-check; generated data with known truth."""

import numpy as np
import pytest

from seismo3d.seismic.horizons.dp import reflector_period
from seismo3d.seismic.horizons.lsq import PairShifts, cycle_skips, pair_shifts, solve_horizon, trace_pairs
from seismo3d.seismic.reflectors import nearest_pick

from .conftest import next_cycle, random_layers


def test_trace_pairs_cover_every_line_at_every_distance():
    a, b, d, axis = trace_pairs((3, 10), (1, 4, 16))
    # along axis 1: 3 lines x (9 + 6) pairs; along axis 0: 10 lines x 2 pairs at distance 1 (4 and 16 do not fit)
    assert a.size == 3 * (9 + 6) + 10 * 2
    assert set(d.tolist()) == {1, 4}
    sel = (axis == 1) & (d == 4)
    np.testing.assert_array_equal(b[sel] - a[sel], 4)
    sel = axis == 0
    np.testing.assert_array_equal(b[sel] - a[sel], 10)


def test_pair_shifts_measure_a_known_delay():
    rng = np.random.default_rng(0)
    base = np.convolve(rng.standard_normal(200), np.hanning(7), mode="same")
    x = np.arange(200, dtype=np.float64)
    traces = np.stack([np.interp(x - s, x, base) for s in (0.0, 3.4, -6.0)]).astype(np.float32)
    a = np.array([0, 0, 1])
    b = np.array([1, 2, 2])
    ps = pair_shifts(traces, np.full(3, 100.0), a, b, np.ones(3, np.intp), half=16, max_lag=10)
    np.testing.assert_allclose(ps.shift, [3.4, -6.0, -9.4], atol=0.2)
    assert np.all(ps.score > 0.95)


@pytest.mark.parametrize("seed", [5, 6, 7])
@pytest.mark.parametrize("t", [13.0, 84.0])
def test_pair_shifts_near_the_trace_ends_are_not_biased(seed, t):
    # flat noisy layers (true shift 0) measured 13 samples from either end of 100-sample traces with windows of
    # +-16 and lags of +-12: the lags that overlap the trace enough reach further on one side; searched there
    # alone, the noisy pairs' wrong-cycle matches all fell on that side and moved the mean shift by 0.36-0.6 samples
    traces, _, _, _ = random_layers((400,), n_samples=100, dip=0.0, seed=seed)
    rng = np.random.default_rng(0)
    traces = traces + traces.std() * rng.standard_normal(traces.shape).astype(np.float32)
    a, b, d, _ = trace_pairs((400,), (1, 2, 4, 8))
    ps = pair_shifts(traces, np.full(400, t), a, b, d, half=16, max_lag=12)
    measured = ps.shift[np.isfinite(ps.shift)]
    assert measured.size > 0.9 * a.size
    assert abs(np.mean(measured)) < 0.25


def test_pair_shifts_do_not_depend_on_the_order_of_the_pairs():
    # each pair is measured on its own (work arrays reused from pair to pair must not carry scores over: near the
    # trace ends, where the lag range is cut, the parabola beside the best lag read the previous pair's scores)
    traces, _, _, _ = random_layers((300,), n_samples=100, dip=0.02, seed=6)
    rng = np.random.default_rng(2)
    traces = traces + traces.std() * rng.standard_normal(traces.shape).astype(np.float32)
    a, b, d, _ = trace_pairs((300,), (1, 4, 16))
    times = rng.uniform(8.0, 92.0, 300)  # many windows near the ends
    forward = pair_shifts(traces, times, a, b, d, half=16, max_lag=12)
    order = rng.permutation(a.size)
    shuffled = pair_shifts(traces, times, a[order], b[order], d[order], half=16, max_lag=12)
    np.testing.assert_array_equal(forward.shift[order], shuffled.shift)
    np.testing.assert_array_equal(forward.score[order], shuffled.score)
    assert np.isfinite(forward.shift).mean() > 0.5


def _direct_lag_search(traces, ka, ta, kb, tb, half, max_lag):
    """The lag search of pair_shifts written out for windows inside both traces: every lag's normalised
    cross-correlation computed on its own with numpy, the best refined by a parabola."""
    x = np.arange(traces.shape[1], dtype=np.float64)
    ref = np.interp(ta - half + np.arange(2 * half + 1), x, traces[ka])
    ref = ref - ref.mean()
    scores = []
    for lag in range(-max_lag, max_lag + 1):
        sig = np.interp(tb + lag - half + np.arange(2 * half + 1), x, traces[kb])
        sig = sig - sig.mean()
        scores.append(ref @ sig / np.sqrt((ref @ ref) * (sig @ sig)))
    k = int(np.argmax(scores))
    off = 0.0
    if 0 < k < 2 * max_lag:
        y0, y1, y2 = scores[k - 1:k + 2]
        if y0 - 2 * y1 + y2 < 0:
            off = float(np.clip(0.5 * (y0 - y2) / (y0 - 2 * y1 + y2), -0.5, 0.5))
    return tb + k - max_lag + off - ta, scores[k]


def test_pair_shifts_inside_the_traces_equal_a_direct_lag_search():
    # the compiled search (products of eight lags at a time, sums slid from lag to lag) against each lag computed
    # on its own, at fractional times of noisy dipping layers
    traces, _, _, _ = random_layers((200,), n_samples=120, dip=0.3, seed=3)
    rng = np.random.default_rng(4)
    traces = traces + 0.3 * traces.std() * rng.standard_normal(traces.shape).astype(np.float32)
    a, b, d, _ = trace_pairs((200,), (1, 4, 32))
    times = rng.uniform(40.0, 80.0, 200)  # windows of +-16 and lags of +-12 stay inside the 120 samples
    ps = pair_shifts(traces, times, a, b, d, half=16, max_lag=12)
    for p in rng.choice(a.size, 60, replace=False):
        shift, score = _direct_lag_search(traces, a[p], times[a[p]], b[p], times[b[p]], 16, 12)
        assert ps.shift[p] == pytest.approx(shift, abs=1e-9)
        assert ps.score[p] == pytest.approx(score, abs=1e-9)


def test_two_level_solve_equals_the_direct_solution():
    # the conjugate gradients with the aggregates' coarse level reach the normal equations' own solution (a sparse
    # direct solve) on a grid of 12 x 90 traces, with and without a grid shape for the aggregates
    from scipy.sparse import coo_matrix, diags
    from scipy.sparse.linalg import spsolve

    rng = np.random.default_rng(7)
    lat = (12, 90)
    n = lat[0] * lat[1]
    truth = 60.0 + np.cumsum(rng.normal(0.0, 0.4, n))
    a, b, d, _ = trace_pairs(lat, (1, 2, 4, 8, 16, 32))
    shift = truth[b] - truth[a] + rng.normal(0.0, 0.3, a.size)
    score = rng.uniform(0.6, 1.0, a.size)
    ps = PairShifts(a, b, d, shift, score)
    seeds = np.array([5 * 90 + 40, 9 * 90 + 10])
    previous = np.full(n, 60.0)
    w = score ** 2
    lap = coo_matrix((np.r_[w, w, -w, -w], (np.r_[a, b, a, b], np.r_[a, b, b, a])), shape=(n, n))
    diag = np.full(n, 1e-6)
    diag[seeds] += 1e4
    rhs = np.bincount(b, w * shift, minlength=n) - np.bincount(a, w * shift, minlength=n) + 1e-6 * previous
    rhs[seeds] += 1e4 * truth[seeds]
    direct = spsolve((lap + diags(diag)).tocsc(), rhs)
    for shape in (lat, None):
        t = solve_horizon(n, ps, seeds, truth[seeds], min_correlation=0.5, previous=previous, robust=None,
                          lateral_shape=shape)
        np.testing.assert_allclose(t, direct, atol=1e-3)


def test_robust_solve_outvotes_cycle_skipped_pairs():
    # a smooth horizon over 200 traces; pairs 1..32 traces apart with exact shifts, 10 % of them off by a
    # reflector period (12 samples): the robust least squares puts every trace back within a third of a sample
    rng = np.random.default_rng(1)
    n = 200
    truth = 50.0 + np.cumsum(rng.normal(0.0, 0.5, n))
    a, b, d, _ = trace_pairs((n,), (1, 2, 4, 8, 16, 32))
    shift = truth[b] - truth[a]
    bad = rng.random(a.size) < 0.1
    shift[bad] += rng.choice([-12.0, 12.0], bad.sum())
    ps = PairShifts(a, b, d, shift, np.full(a.size, 0.9))
    seeds = np.array([100])
    t = solve_horizon(n, ps, seeds, truth[seeds], min_correlation=0.5, previous=np.full(n, truth[100]))
    assert np.max(np.abs(t - truth)) < 0.3
    # plain least squares (no robust weights) carries the bad pairs into the horizon
    plain = solve_horizon(n, ps, seeds, truth[seeds], min_correlation=0.5, robust=None)
    assert np.max(np.abs(plain - truth)) > 1.0


def test_solve_leaves_traces_no_pair_reaches_empty():
    a, b, d, _ = trace_pairs((10,), (1,))
    score = np.full(a.size, 0.9)
    score[4] = 0.1  # the pair between traces 4 and 5 does not correlate: 5..9 are cut off from the seed
    ps = PairShifts(a, b, d, np.ones(a.size), score)
    t = solve_horizon(10, ps, np.array([0]), np.array([20.0]), min_correlation=0.5)
    np.testing.assert_allclose(t[:5], 20.0 + np.arange(5), atol=1e-3)
    assert np.isnan(t[5:]).all()


def test_cycle_skip_check_flags_a_one_period_offset():
    section, picks, offsets, _ = random_layers()
    t0 = nearest_pick(picks, offsets, 0, 80.0, 8.0)
    truth = np.array([nearest_pick(picks, offsets, j, t0 + 0.05 * j, 1.0) for j in range(160)])
    assert np.isfinite(truth).all()
    period = reflector_period(picks, offsets, np.arange(160), truth)
    skipped = truth.copy()
    for j in range(100, 140):  # a run of traces one cycle down, as a tracker that jumped at trace 100 leaves it
        skipped[j] = next_cycle(picks, offsets, j, truth[j])
    a, b, d, _ = trace_pairs((160,), (1, 2, 4, 8, 16, 32))
    lag = int(np.ceil(1.5 * max(period, np.max(skipped - truth))))
    seeds = np.array([60])
    ps = pair_shifts(section, skipped, a, b, d, half=16, max_lag=lag)
    corr = cycle_skips(ps, skipped, period, seeds, truth[seeds])
    flagged = np.isfinite(corr)
    assert flagged[100:140].all()
    assert not flagged[np.r_[0:100, 140:160]].any()
    np.testing.assert_allclose(corr[100:140], (truth - skipped)[100:140], atol=1.0)
    # the true horizon raises no flag
    ps = pair_shifts(section, truth, a, b, d, half=16, max_lag=lag)
    assert not np.isfinite(cycle_skips(ps, truth, period, seeds, truth[seeds])).any()


@pytest.mark.parametrize("bad", [dict(method="lsq"), dict(pair_distances=(0, 2)), dict(max_lag=0),
                                 dict(robust=-1.0), dict(min_pair_correlation=2.0),
                                 dict(dp_sweeps=-1), dict(dp_sweeps=1.5)])
def test_global_options_are_checked(bad):
    from seismo3d.errors import InputError
    from seismo3d.seismic import TrackingOptions

    with pytest.raises(InputError):
        TrackingOptions(**bad)


def test_group_nanmedian_is_the_median_of_each_groups_finite_values():
    """The per-node median of neighbour_confidence (numpy, was a numba kernel): np.median of each group's finite
    values, odd and even counts, ties, NaN / inf left out, NaN for a group without one."""
    from seismo3d.seismic.horizons.correlation import _group_nanmedian

    rng = np.random.default_rng(5)
    node = rng.integers(0, 40, 600)
    val = np.round(rng.standard_normal(600), 1)  # ties
    val[rng.random(600) < 0.15] = np.nan
    val[rng.random(600) < 0.05] = np.inf
    node[node == 7] = 8  # group 7 empty
    node[(node == 9) & np.isfinite(val)] = 10  # group 9 without a finite value
    got = _group_nanmedian(node, val, 41)
    want = np.array([np.median(val[(node == k) & np.isfinite(val)]) if ((node == k) & np.isfinite(val)).any()
                     else np.nan for k in range(41)])
    np.testing.assert_array_equal(got, want)
    assert np.isnan(got[[7, 9, 40]]).all()
