"""Horizon tracking (seismo3d.seismic.horizons.tracking) against ground truth: the generator's horizons (2D sections,
faulted cubes with traced faults), people's picks on the 18 real Penobscot inlines, beside the plain autotracker; gap
closing and the lateral continuity check; bad input."""

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import (
    FaultCrossings, TrackingOptions, autotrack, fill_horizon, horizon_errors, reflector_picks, track_horizon,
)
from seismo3d.seismic.horizons.lateral_check import close_gaps, despike, despike_lines
from seismo3d.seismic.reflectors import ReflectorSlice, nearest_pick


def _seed_on(ref, i0=None):
    if ref.ndim == 1:
        ok = np.nonzero(np.isfinite(ref))[0]
        j0 = int(ok[np.argmin(np.abs(ok - ref.size // 2))])
        return (j0, float(ref[j0]))
    ok = np.nonzero(np.isfinite(ref[i0]))[0]
    j0 = int(ok[np.argmin(np.abs(ok - ref.shape[1] // 2))])
    return (i0, j0, float(ref[i0, j0]))


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_track_2d_section_without_faults_follows_true_horizons(seed):
    syn = synthetic_cube((160, 128), n_faults=0, seed=seed, noise=0.2)
    for k in range(syn.horizons.shape[0]):
        ref = syn.horizons[k]
        pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
        hz = track_horizon(syn.cube, _seed_on(ref), polarity=pol)
        e = horizon_errors(hz.times, ref)
        assert e.median_abs <= 0.13, (k, e)  # measured 0.053-0.083 over seeds 0-1, limit 1.5x the worst
        assert e.within_2 >= 0.99, (k, e)  # measured 1.0 on every horizon; limit: one trace of the 160 off


# the synthetic section of benchmarks/horizons.py prints these horizons (cube seeds 0-2): the target is a median
# within one sample on every horizon (the global tracker: 0.05-0.17 samples). The suite keeps cube 0 (its faults are
# traced once for three tests); cubes 1 and 2 (about 40 s each in the suite) are asserted with the same limits by
# ``python benchmarks/horizons.py --only synthetic --check`` (benchmarks/checks.py, issue 58). Before the crossing test
# used each fault's local plane, cube 0 horizon 1 (seeded where two faults cross) was 5.4 samples off with the
# registration tracker; before pairs across traced faults were checked with short windows, cube 0 horizon 2 was 5.0 off.
def _faulted_errors(syn, faults):
    out = []
    for k in range(syn.horizons.shape[0]):
        ref = syn.horizons[k]
        pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
        hz = track_horizon(syn.cube, _seed_on(ref, syn.shape[0] // 2), polarity=pol, faults=faults)
        out.append(horizon_errors(hz.times, ref))
    return out


@pytest.fixture(scope="module")
def faulted_errors(faulted_cube):
    """``faulted_errors(seed)``: the errors of every horizon of ``faulted_cube(seed)``, tracked once per module (two
    tests read them)."""
    import functools

    @functools.lru_cache(maxsize=None)
    def errors(cube_seed):
        return _faulted_errors(*faulted_cube(cube_seed))

    return errors


@pytest.mark.parametrize("cube_seed", [0])
@pytest.mark.slow
def test_track_3d_across_faults_median_error_within_one_sample(faulted_errors, cube_seed):
    medians = [e.median_abs for e in faulted_errors(cube_seed)]
    assert np.all(np.isfinite(medians)) and np.max(medians) <= 1.0, medians  # the target
    assert np.max(medians) <= 0.16, medians  # measured 0.083 / 0.068 / 0.106 (cubes 0-2), limit 1.5x the worst


# The registration tracker kept 80 % of these horizons' traces within 2 samples on average; the global tracker keeps 95
# / 93 / 96 % (cubes 0-2; 93 / 87 / 90 % at an earlier stop). It kept 79 / 85 / 74 % before the lags near the trace ends
# were searched symmetrically (82 / 83 / 82 % with that alone) and the picks chosen by sweeps over both lateral axes
# (regions beyond a fault a cycle off on some inlines only, which the line-by-line choice could not see).
@pytest.mark.parametrize("cube_seed", [0])
@pytest.mark.slow
def test_track_3d_across_faults_keeps_most_traces_within_two_samples(faulted_errors, cube_seed):
    # measured 0.951 / 0.928 / 0.958 (cubes 0-2, 2026-11-27; 0.930 / 0.871 / 0.890 before); limit the worst less 3
    # points (a cube's horizons moved a cycle off over 3 % of their traces fail)
    assert np.mean([e.within_2 for e in faulted_errors(cube_seed)]) >= 0.89


@pytest.mark.slow
def test_fault_throw_makes_the_jump(faulted_cube, faulted_errors):
    # the horizon that crosses faults: without fault input the tracker follows the wrong reflector. With the faults,
    # the tracking of the tests above (faulted_errors: the same seed, polarity and faults), once in the module (6 CPU
    # s, 2026-11-29): the global method, the default, reads no image features (TrackingOptions.features is the
    # registration method's), so features=None, which this test passed, tracks the same horizon (the same bits)
    assert TrackingOptions().method == "global"
    syn, faults = faulted_cube(0)
    k = 2
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    seed = _seed_on(ref, syn.shape[0] // 2)
    with_faults = faulted_errors(0)[k]
    without = horizon_errors(track_horizon(syn.cube, seed, polarity=pol, features=None).times, ref)
    assert with_faults.median_abs <= 0.13  # measured 0.083, limit 1.5x
    assert without.median_abs > 3.0  # measured 5.0: the contrast the test shows (the jump of a reflector cycle)


def test_low_confidence_picks_are_empty_and_fill_is_explicit():
    syn = synthetic_cube((120, 96), n_faults=0, seed=2, noise=0.1)
    cube = syn.cube.copy()
    cube[60:64] = np.random.default_rng(0).standard_normal((4, cube.shape[1])).astype(np.float32)  # noise traces
    k = 2
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    hz = track_horizon(cube, (30, float(ref[30])), polarity=pol, min_confidence=0.6)
    assert np.isnan(hz.times[60:64]).sum() >= 2  # the noise traces are not guessed
    assert np.isfinite(hz.times[70:]).mean() > 0.9  # ... and tracking goes on beyond them
    filled = fill_horizon(hz)
    assert np.isfinite(filled.times[1:-1]).all()
    assert np.isnan(hz.times[60:64]).sum() >= 2  # the input is not modified
    gap = np.isnan(hz.times)
    assert np.nanmax(np.abs(filled.times[gap] - ref[gap])) < 0.16  # measured 0.105, limit 1.5x


@pytest.mark.slow
def test_gap_closing_refills_a_hole_and_leaves_noise_empty():
    syn = synthetic_cube((24, 40, 64), n_faults=0, seed=4, noise=0.05)
    k = 2
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    hz = track_horizon(syn.cube, _seed_on(syn.horizons[k], 12), polarity=pol, features=None)
    assert np.isfinite(hz.times).all()
    opt = TrackingOptions()
    times, conf = hz.times.astype(np.float64), hz.confidence.astype(np.float64)
    holed = times.copy()
    holed[8:14, 10:18] = np.nan
    given = holed.copy()
    assert close_gaps(syn.cube, holed, conf.copy(), polarity=pol, options=opt) == 48
    np.testing.assert_allclose(holed[8:14, 10:18], times[8:14, 10:18], atol=0.5)
    # the cube's picks passed in (as track_horizon does) fill the same traces at the same times
    cube_picks = reflector_picks(syn.cube.reshape(-1, syn.cube.shape[-1]), polarity=pol)
    assert close_gaps(syn.cube, given, conf.copy(), polarity=pol, options=opt, picks=cube_picks) == 48
    np.testing.assert_array_equal(given, holed)
    # where the traces hold only noise, nothing correlates at min_confidence 0.6: the hole stays empty (at the
    # default 0.3, chance correlations fill a few noise traces)
    noisy = syn.cube.copy()
    noisy[8:14, 10:18] = np.random.default_rng(1).standard_normal((6, 8, noisy.shape[2])).astype(np.float32)
    holed = times.copy()
    holed[8:14, 10:18] = np.nan
    close_gaps(noisy, holed, conf.copy(), polarity=pol, faults=FaultCrossings.empty(3),
               options=TrackingOptions(min_confidence=0.6))
    assert np.isnan(holed[9:13, 12:16]).all()


def test_despike_puts_a_cycle_skipped_pick_back_and_leaves_a_step_alone():
    syn = synthetic_cube((60, 96), n_faults=0, seed=3, noise=0.05)
    k = 2
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    sl = ReflectorSlice(syn.cube, pol, (2.0, 2.0))
    truth = np.array([sl.snap(j, syn.horizons[k][j], 1.0) for j in range(60)])
    assert np.isfinite(truth).all()
    picks, offsets = reflector_picks(syn.cube, polarity=pol)
    other = picks[offsets[30]:offsets[31]]
    wrong = other[np.argmin(np.where(np.abs(other - truth[30]) > 3, np.abs(other - truth[30]), np.inf))]
    out = truth.copy()
    out[30] = wrong  # one pick on the neighbouring cycle
    out[45:] += 6.0  # and a step (a fault's jump) further on
    carried, conf = out.copy(), np.ones(60)
    changed = despike(sl, out, carried, conf, min_confidence=0.3)
    assert changed == 1
    assert out[30] == pytest.approx(truth[30]) and carried[30] == pytest.approx(truth[30])
    np.testing.assert_array_equal(out[45:], truth[45:] + 6.0)


def test_despike_lines_changes_only_the_spikes_of_a_cube():
    # five identical inlines of a generated section; a pick one cycle off on inline 2 (a spike along its crossline
    # line and along its inline line): despike_lines puts it back and leaves every other pick as it was (the lines
    # without a spike candidate are not visited)
    syn = synthetic_cube((60, 96), n_faults=0, seed=3, noise=0.05)
    k = 2
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    cube = np.stack([syn.cube] * 5)
    picks, offsets = reflector_picks(cube.reshape(-1, cube.shape[-1]), polarity=pol)
    truth = np.array([nearest_pick(picks, offsets, j, syn.horizons[k][j], 1.0) for j in range(60)])
    assert np.isfinite(truth).all()
    times = np.tile(truth, (5, 1))
    spike = 2 * 60 + 30
    other = picks[offsets[spike]:offsets[spike + 1]]
    times[2, 30] = other[np.argmin(np.where(np.abs(other - truth[30]) > 3, np.abs(other - truth[30]), np.inf))]
    conf = np.ones((5, 60))
    changed = despike_lines(cube, times, conf, pol, TrackingOptions(), FaultCrossings.empty(3), picks=(picks, offsets))
    assert changed == 1
    np.testing.assert_allclose(times, np.tile(truth, (5, 1)), atol=1e-9)


def test_bad_input_gives_clear_errors():
    syn = synthetic_cube((20, 20, 64), n_faults=0, seed=0)
    with pytest.raises(InputError, match="outside the data"):
        track_horizon(syn.cube, (25, 3, 30.0))
    with pytest.raises(InputError, match="outside the data"):
        track_horizon(syn.cube, (5, 3, 64.0))
    dead = syn.cube.copy()
    dead[5, 3] = 0.0
    with pytest.raises(InputError, match="dead trace"):
        track_horizon(dead, (5, 3, 30.0))
    with pytest.raises(InputError, match="polarity"):
        track_horizon(syn.cube, (5, 3, 30.0), polarity="max")
    with pytest.raises(InputError, match="seeds must be"):
        track_horizon(syn.cube, (5, 30.0))
    with pytest.raises(InputError, match="half_traces must be an int >= 1"):
        track_horizon(syn.cube, (5, 3, 30.0), half_traces=2.5)
    with pytest.raises(InputError, match="unknown keyword argument"):
        track_horizon(syn.cube, (5, 3, 30.0), half_trace=5)


@pytest.mark.parametrize("method", ["global", "registration"])
@pytest.mark.parametrize("shape, seed", [((20, 20, 64), (5, 3, 4.0)), ((40, 64), (5, 4.0))])
def test_seed_without_a_pick_names_the_nearest_pick(method, shape, seed):
    """A seed in a muted top: SeedError with the seed and the nearest pick on its trace (index space), for every
    method and dimension."""
    from seismo3d.errors import SeedError
    from seismo3d.seismic import reflector_picks

    cube = synthetic_cube(shape, n_faults=0, seed=0).cube.copy()
    cube[..., :20] = 0.0
    with pytest.raises(SeedError, match="no reflector pick") as caught:
        track_horizon(cube, seed, method=method, progress=False)
    trace = cube[tuple(int(v) for v in seed[:-1])]
    first = reflector_picks(trace[None], polarity="peak")[0].min()
    assert caught.value.seed == seed and caught.value.window == 5.0
    assert caught.value.nearest == pytest.approx((*seed[:-1], first))


def test_options_object_and_keywords_agree():
    syn = synthetic_cube((160, 128), n_faults=0, seed=1, noise=0.2)
    ref = syn.horizons[1]
    pol = "peak" if syn.horizon_polarity[1] > 0 else "trough"
    a = track_horizon(syn.cube, _seed_on(ref), polarity=pol, options=TrackingOptions(step=6, min_confidence=0.5))
    b = track_horizon(syn.cube, _seed_on(ref), polarity=pol, step=6, min_confidence=0.5)
    np.testing.assert_array_equal(a.times, b.times)


# The cross-validation (benchmarks/horizons.py prints it): the same defaults on each half of the 18 Penobscot
# inlines, one seed per horizon on the fold's first inline (trace 256, at the people's pick). Targets on every fold and
# horizon: >= 99 % of the live traces within 5 samples, median <= 1 sample (horizon 5: 1.5, the people's picks wander
# within clipped plateaus), and at least the plain autotracker's % within 5 less half a point, measured here.
# The median limits are per horizon, for a reason: the people's picks sit on a grid of half a sample, so a horizon's
# median |error| moves in steps of 0.5 and no margin fits between the measured median and the next step. Each limit is
# the median measured on that horizon, the same on both folds and with traced faults (MEDIAN_MEASURED); a horizon that
# gets one step worse fails. The targets (1 sample, 1.5 on horizon 5) are asserted beside them.
MEDIAN_MEASURED = {0: 1.0, 1: 1.0, 2: 0.5, 3: 0.5, 4: 0.5, 5: 1.5, 6: 1.0}
MEDIAN_TARGET = {k: 1.5 if k == 5 else 1.0 for k in range(7)}  # the issue's: horizon 5's picks wander (above)
FOLDS = {"1075-1083": slice(0, 9), "1084-1092": slice(9, 18)}
# measured (at the plain autotracker; below the 99 %): horizon 1 on 1084-1092 cuts the bottom of the pockmark's sag on
# some inlines (the autotracker: 98.9 %). Horizon 6 on 1075-1083 (a fault whose throw at the horizon is about half a
# reflector period, so the correlations across it are ambiguous; 91.6 % before) reaches 99.5 % since the cycle cut moves
# the region the solve kept a cycle off (seismo3d.seismic.horizons.cycle_cut) and the gap closing refills the inline
# whose picks the lateral check had emptied.
# What the section shows where horizon 1 misses on 1084-1092 (48 of 4599 traces, 23 allowed at 99.5 %): the pockmark's
# bottom (traces 312-316) and east flank (323-327) on inlines 1087-1091 hold two peaks each, 6-8 samples apart; ours
# follows the upper one in the bottom (145.5-147) and the lower one on the flank (147.5-149), the people's V the other
# two (152.5-154 and 142-143.5), their picks within a sample of a peak as everywhere (median 0.98). Moved onto the
# people's peaks, our 34 missed picks correlate worse with every pair that touches them, at every pair distance and
# window (+-16 samples: distance 1 0.63 -> 0.37 mean, along the inline axis 0.69 -> 0.47; +-4: 0.82 -> 0.67), and the
# structure-tensor slopes (1-4 traces) carried across the sag stay within 4 samples of flat: the V is not in these
# clipped 8-bit amplitudes, whose pairs the solve would have to outvote (their picks are the same V on every inline,
# to a sample, where ours is on the lower peak on 1084-1086 and the upper on 1087-1091).
MISSED = {("1084-1092", 1): "pockmark sag bottom: 98.93-98.98 % within 5 as the solver rounds (autotracker 98.93 %)"}


def _peak_seed(cube, ref, trace=256):
    """The seed both trackers get: inline 0, ``trace``, at the peak nearest the people's pick (within 5 samples: on
    1084-1092 horizon 5's pick sits 4 samples from it, beyond the autotracker's own 3-sample snap)."""
    picks, offsets = reflector_picks(cube[0, trace][None])
    return (0, trace, nearest_pick(picks, offsets, 0, float(ref[0, trace]), 5.0))


@pytest.fixture(scope="module")
def penobscot_folds(penobscot):
    return {name: (np.ascontiguousarray(penobscot.cube[rows]), penobscot.horizons[rows]) for name, rows in
            FOLDS.items()}


@pytest.mark.slow
@pytest.mark.parametrize("fold, k", [pytest.param(f, k, marks=pytest.mark.xfail(reason=MISSED[(f, k)], strict=True))
                                     if (f, k) in MISSED else (f, k) for f in FOLDS for k in range(7)])
def test_penobscot_folds_against_peoples_picks(penobscot_folds, fold, k):
    cube, human = penobscot_folds[fold]
    ref = human[:, k]
    seed = _peak_seed(cube, ref)
    ours = horizon_errors(track_horizon(cube, seed).times, ref)
    plain = horizon_errors(autotrack(cube, seed).times, ref)
    assert ours.within_5 >= 0.99 and ours.median_abs <= MEDIAN_TARGET[k], ours  # the targets
    assert ours.median_abs <= MEDIAN_MEASURED[k], ours  # measured (see MEDIAN_MEASURED)
    assert ours.within_5 >= plain.within_5 - 0.005, (ours, plain)


@pytest.mark.slow
@pytest.mark.xfail(reason="measured 99.4 % within 5 (the sag's bottom traces on the inlines where it is deepest)",
                   strict=True)
def test_penobscot_pockmark_passed_with_margin(penobscot):
    # horizon 1 crosses the pockmark's V-shaped sag near traces 307-330 on all 18 inlines; the issue asks >= 99.5 %
    ref = penobscot.horizons[:, 1]
    ours = horizon_errors(track_horizon(penobscot.cube, (0, 256, ref[0, 256])).times, ref)
    assert ours.within_5 >= 0.995 and ours.median_abs <= 1.0, ours


# The Penobscot horizons with the faults trace_faults finds in the 18 inlines (many of them spurious: the clipped 8-bit
# slab): no horizon loses more than half a point against tracking without fault input, each keeps its measured median
# (MEDIAN_MEASURED) and, but horizon 6, 99 % within 5 samples. Tracing those faults and tracking every horizon twice
# took about 4 minutes of the suite's 10 (2 cores, 2026-11-26): the claim is asserted by
# `python benchmarks/horizons.py --only traced_faults --check` (the same limits). Windows of these inlines small enough
# for the suite hold one or two traced faults that change no pick, so the suite proves tracking across traced faults on
# the generated cubes above (and below), where the faults' throw is known.


@pytest.mark.slow
def test_seed_on_a_fault_steps_off_it_by_registration(faulted_cube):
    # A seed on a traced fault is in neither wall as far as the fault surface can tell; the first step to each side
    # stays in the seed's wall or jumps out of the other one, whichever the seed's waveform correlates with better.
    # Synthetic cube 1, horizon 4 is seeded on a fault traced 1-2 traces beside the true one; deciding the side
    # from the surface alone put one side of the seed inline 4.4 samples off (median).
    syn, faults = faulted_cube(1)
    k = 4
    ref = syn.horizons[k]
    pol = "peak" if syn.horizon_polarity[k] > 0 else "trough"
    seed = _seed_on(ref, syn.shape[0] // 2)
    assert TrackingOptions().fault_crossings(faults, 3).on_fault(np.array(seed)), "the seed is no longer on a fault"
    hz = track_horizon(syn.cube, seed, polarity=pol, faults=faults, features=None)
    line = horizon_errors(hz.times[seed[0]], ref[seed[0]])
    # measured median 0.044, 98.4 % within 2; limits 1.5x the median, the share less 3 points
    assert line.median_abs <= 0.07 and line.within_2 >= 0.95, line


@pytest.mark.slow
@pytest.mark.parametrize("ms", [132.0, 236.0])
def test_f3_crop_picks_do_not_jitter(data_dir, ms):
    # f3_crop has no people's picks: the measure is the share of neighbouring picks (along inlines and crosslines)
    # that step by 10 ms or more, ours against the plain autotracker's from the same seed (before the sweeps over
    # both axes and the symmetric lags near the trace ends: 236 ms 12.4 %, autotracker 3.6 %)
    from seismo3d.data import fetch
    from seismo3d.seismic import read_segy

    cube, geom = read_segy(fetch("seismic/f3_crop.sgy"))
    dt = float(geom.sample_interval)
    picks, offsets = reflector_picks(cube[11, 9][None])
    seed = (11, 9, nearest_pick(picks, offsets, 0, (ms - float(geom.samples[0])) / dt, 5.0))

    def share_of_jumps(times):
        times = np.asarray(times, np.float64)
        steps = np.concatenate([np.abs(np.diff(times, axis=0)).ravel(), np.abs(np.diff(times, axis=1)).ravel()])
        steps = steps[np.isfinite(steps)] * dt
        return float(np.mean(steps >= 10.0)), steps.size

    ours, n_ours = share_of_jumps(track_horizon(cube, seed).times)
    plain, _ = share_of_jumps(autotrack(cube, seed).times)
    # emptying picks would hide jumps: at least two thirds of the neighbouring pairs are picked (measured: 684 and
    # 618 of 787; low-confidence picks stay empty)
    assert n_ours >= 2 / 3 * (22 * 18 + 23 * 17), n_ours
    assert ours <= plain, (ours, plain)
