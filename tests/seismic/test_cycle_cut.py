"""Cycle-skip repair by a minimum cut (seismo3d.seismic.horizons.cycle_cut): the cut against brute force, and regions of
a horizon put one cycle off on generated layers with known truth."""

import itertools

import numpy as np
import pytest

from seismo3d.seismic.horizons.cycle_cut import binary_min_cut, cycle_cut, neighbour_cycle
from seismo3d.seismic.horizons.dp import reflector_period
from seismo3d.seismic.horizons.lsq import trace_pairs
from seismo3d.seismic.reflectors import nearest_pick

from .conftest import random_layers


@pytest.mark.parametrize("seed", range(5))
def test_min_cut_finds_the_brute_force_minimum_of_a_submodular_energy(seed):
    rng = np.random.default_rng(seed)
    n = 9
    a, b = np.array(list(itertools.combinations(range(n), 2))).T
    keep = rng.random(a.size) < 0.5
    a, b = a[keep], b[keep]
    e00, e11 = rng.random(a.size), rng.random(a.size)
    # submodular terms: e01 + e10 >= e00 + e11
    e01 = rng.random(a.size) + 0.5 * (e00 + e11)
    e10 = e00 + e11 - e01 + rng.random(a.size)
    fixed = np.array([0])

    def energy(x):
        xa, xb = x[a], x[b]
        return np.sum(np.where(xa, np.where(xb, e11, e10), np.where(xb, e01, e00)))

    best = min((energy(np.array(x, bool)), x) for x in itertools.product((0, 1), repeat=n) if x[0] == 0)
    got = binary_min_cut(n, a, b, e00, e01, e10, e11, fixed, resolution=1e-6)
    assert not got[0]
    assert energy(got) == pytest.approx(best[0], abs=1e-4)


def _truth(picks, offsets, pos, t0, dip=0.04):
    start = nearest_pick(picks, offsets, 0, t0, 8.0)
    return np.array([nearest_pick(picks, offsets, k, start + dip * j, 1.0) for k, j in enumerate(pos)])


def _cut(traces, picks, offsets, times, lateral, seeds, movable, min_extent=0):
    a, b, d, _ = trace_pairs(lateral, (1, 2, 4, 8, 16, 32))
    have = np.nonzero(np.isfinite(times))[0]
    period = reflector_period(picks, offsets, have, times[have])
    return cycle_cut(traces, picks, offsets, times, lateral, a, b, d, seeds=seeds, movable=movable, period=period,
                     half=16, ncc_half=8, distance_power=0.5, min_gain=0.4, min_extent=min_extent)


@pytest.mark.parametrize("direction", [1, -1])
def test_a_region_one_cycle_off_is_moved_back(direction):
    # as a tracker leaves it after one wrong step across a fault: inlines 0-6, crosslines 0-15 of a 12 x 40 grid one
    # cycle down (or up); the seed and the rest are right
    lateral = (12, 40)
    traces, picks, offsets, pos = random_layers(lateral, n_samples=120, dip=0.04, seed=7)
    truth = _truth(picks, offsets, pos, 60.0)
    assert np.isfinite(truth).all()
    skipped = truth.reshape(lateral).copy()
    region = np.zeros(lateral, bool)
    region[:7, :16] = True
    idx = np.nonzero(region.ravel())[0]
    skipped.ravel()[idx] = neighbour_cycle(picks, offsets, truth, direction, 3.0)[idx]
    assert np.all(np.abs(skipped.ravel()[idx] - truth[idx]) > 4.0)
    seeds = np.array([np.ravel_multi_index((0, 30), lateral)])
    out = _cut(traces, picks, offsets, skipped.ravel(), lateral, seeds, np.ones(truth.size, bool), min_extent=12)
    assert out.moved == region.sum()
    np.testing.assert_array_equal(out.times, truth)
    assert out.cost_after < out.cost_before
    # a region no wider than the longest pair is left to the least-squares solve
    out = _cut(traces, picks, offsets, skipped.ravel(), lateral, seeds, np.ones(truth.size, bool), min_extent=16)
    assert out.moved == 0
    np.testing.assert_array_equal(out.times, skipped.ravel())


def test_a_consistent_horizon_and_traces_not_flagged_stay():
    lateral = (160,)
    traces, picks, offsets, pos = random_layers(lateral, n_samples=120, dip=0.04, seed=7)
    truth = _truth(picks, offsets, pos, 60.0)
    seeds = np.array([60])
    # the true horizon: nothing to gain
    out = _cut(traces, picks, offsets, truth, lateral, seeds, np.ones(truth.size, bool))
    assert out.moved == 0
    np.testing.assert_array_equal(out.times, truth)
    # a run one cycle down that the self-check did not flag is left alone; flagged, it is moved back
    skipped = truth.copy()
    skipped[100:140] = neighbour_cycle(picks, offsets, truth, 1, 3.0)[100:140]
    out = _cut(traces, picks, offsets, skipped, lateral, seeds, np.zeros(truth.size, bool))
    assert out.moved == 0
    movable = np.zeros(truth.size, bool)
    movable[90:150] = True
    out = _cut(traces, picks, offsets, skipped, lateral, seeds, movable)
    np.testing.assert_array_equal(out.times, truth)
    # the input is not modified
    assert np.all(skipped[100:140] > truth[100:140])


def test_neighbour_cycle_skips_side_lobes():
    picks = np.array([10.0, 12.0, 20.0, 31.0])
    offsets = np.array([0, 4])
    np.testing.assert_array_equal(neighbour_cycle(picks, offsets, np.array([12.0]), 1, 4.0), [20.0])
    np.testing.assert_array_equal(neighbour_cycle(picks, offsets, np.array([20.0]), -1, 4.0), [12.0])
    np.testing.assert_array_equal(neighbour_cycle(picks, offsets, np.array([31.0]), 1, 4.0), [np.nan])
    np.testing.assert_array_equal(neighbour_cycle(picks, offsets, np.array([np.nan]), 1, 4.0), [np.nan])
