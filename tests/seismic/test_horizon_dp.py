"""Dynamic programming over candidate picks (seismo3d.seismic.horizons.dp): the picks of a line chosen together from a
noisy guide, and lone departures moved back; generated data with known truth."""

import numpy as np

from seismo3d.seismic.horizons.dp import dp_picks, line_slopes, settle_lone_departures
from seismo3d.seismic.reflectors import nearest_pick, reflector_picks

from .conftest import next_cycle, random_layers, section_and_truth


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


def test_sweeps_bring_inlines_a_cycle_off_back_in_line_with_their_neighbours():
    # 9 inlines of a gently dipping random layering; the guide of inlines 3-5 is one cycle down over crosslines 0-69
    # (a patch the least-squares solution got wrong): each inline alone follows it (stepping back costs more than
    # the guide), but a cycle between neighbouring inlines costs more still, so the sweeps over both axes restore them
    lat = (9, 80)
    traces, picks, offsets, pos = random_layers(lat, n_samples=160, dip=0.05, seed=5)
    first = nearest_pick(picks, offsets, 0, 80.0, 6.0)
    truth = np.array([nearest_pick(picks, offsets, k, first + 0.05 * pos[k], 1.0) for k in range(pos.size)])
    assert np.isfinite(truth).all()
    guide = truth.copy()
    for k in np.ravel_multi_index(np.mgrid[3:6, 0:70].reshape(2, -1), lat):
        guide[k] = next_cycle(picks, offsets, k, truth[k])
    fixed = np.full(truth.size, np.nan)
    fixed[0] = truth[0]
    data = traces.reshape(lat + (-1,))
    slopes = line_slopes(data, (2.0, 2.0))
    across = line_slopes(data, (2.0, 2.0), axis=0)
    kw = dict(reach=16.0, w_guide=0.2, w_step=1.0, w_wave=4.0, half=8)
    lines = dp_picks(traces, picks, offsets, guide, lat, fixed, slopes, **kw)
    wrong = (np.abs(lines - truth) > 1.0).reshape(lat)
    assert wrong[3:6].all() and not wrong[:3].any() and not wrong[6:].any()
    swept = dp_picks(traces, picks, offsets, guide, lat, fixed, slopes, cross_slopes=across, sweeps=2, **kw)
    np.testing.assert_allclose(swept, truth, atol=1e-9)
