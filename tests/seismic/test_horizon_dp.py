"""Dynamic programming over candidate picks (seismo3d.seismic.horizon_dp): the picks of a line chosen together from a
noisy guide, and lone departures moved back; generated data with known truth."""

import numpy as np

from seismo3d.seismic.horizon_dp import dp_picks, line_slopes, settle_lone_departures
from seismo3d.seismic.reflectors import nearest_pick, reflector_picks

from .conftest import next_cycle, section_and_truth


def test_dp_picks_the_true_reflector_from_a_noisy_guide():
    syn, pol, picks, offsets, truth = section_and_truth()
    guide = truth + np.random.default_rng(0).normal(0.0, 1.5, truth.size)  # +-1.5 samples of noise per trace
    fixed = np.full(truth.size, np.nan)
    fixed[80] = truth[80]
    out = dp_picks(syn.cube, picks, offsets, guide, (160,), fixed, line_slopes(syn.cube, (2.0, 2.0)), reach=8.0,
                   w_guide=0.2, w_step=1.0, w_wave=4.0, half=8)
    np.testing.assert_allclose(out, truth, atol=1e-9)
    # nearest-pick snapping of the same guide jumps cycles where the noise is large
    snapped = np.array([nearest_pick(picks, offsets, j, g, 8.0) for j, g in enumerate(guide)])
    assert np.any(np.abs(snapped - truth) > 1.0)


def test_lone_departure_is_moved_back_and_shared_one_kept():
    syn, pol, _, _, truth = section_and_truth()
    cube = np.stack([syn.cube] * 5)  # five identical inlines
    picks, offsets = reflector_picks(cube.reshape(-1, cube.shape[-1]), polarity=pol)
    guide = np.tile(truth, 5)
    picked = guide.copy()
    # inline 2 alone one cycle off at traces 50-60; inlines 3 and 4 together one cycle off at traces 100-110
    for i, span in ((2, range(50, 61)), (3, range(100, 111)), (4, range(100, 111))):
        for j in span:
            k = i * 160 + j
            picked[k] = next_cycle(picks, offsets, k, guide[k])
    out = settle_lone_departures(picked, guide, (5, 160), picks, offsets)
    lone = slice(2 * 160 + 50, 2 * 160 + 61)
    np.testing.assert_allclose(out[lone], guide[lone], atol=1e-9)
    for i in (3, 4):
        shared = slice(i * 160 + 100, i * 160 + 111)
        np.testing.assert_array_equal(out[shared], picked[shared])
