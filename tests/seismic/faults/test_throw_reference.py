"""The true throw of a traced fault from people's horizons (seismo3d.seismic.horizon_offsets, what
benchmarks/fault_throw.py scores the throws with), on generated sections with a known throw."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import horizon_offsets


def _section(throw, *, dips_toward=+1, n_traces=200, horizon_dip=0.05, fault_dip_run=0.2):
    """A fault line from (100, 20) down to sample 380, dipping toward ``dips_toward`` (``fault_dip_run`` traces per
    sample), and three dipping horizons offset by ``throw`` samples on its hanging-wall side (positive: down)."""
    t = np.arange(20.0, 381.0)
    x = 100.0 + dips_toward * fault_dip_run * (t - 20.0)
    points = np.column_stack([x, t])
    traces = np.arange(n_traces, dtype=np.float64)
    tops = (100.0, 200.0, 300.0)
    horizons = np.empty((len(tops), n_traces))
    for k, top in enumerate(tops):
        depth = top + horizon_dip * traces
        # the fault's trace at this horizon's depth, and the hanging-wall side beyond it
        x_fault = 100.0
        for _ in range(5):  # where the fault meets the footwall's horizon
            x_fault = np.interp(top + horizon_dip * x_fault, t, x)
        hanging = (traces - x_fault) * dips_toward > 0
        horizons[k] = depth + np.where(hanging, throw, 0.0)
    return points, horizons, x


@pytest.mark.parametrize("throw", [-7.0, -3.0, 4.0, 12.0])
@pytest.mark.parametrize("dips_toward", [-1, 1])
def test_offsets_are_the_known_throw_at_each_crossing(throw, dips_toward):
    points, horizons, x = _section(throw, dips_toward=dips_toward)
    ids = np.full(len(points), 5)
    res = horizon_offsets(points, ids, {5: dips_toward}, horizons)
    assert res.horizon.tolist() == [0, 1, 2]
    assert res.fault_id.tolist() == [5, 5, 5]
    # the line fits of both sides carry the horizons' dip to the fault: the offset is the throw to rounding
    np.testing.assert_allclose(res.offset, throw, atol=0.35)
    # the crossing lies on the fault, midway between the two sides' depths
    x_cross = points[res.point, 0]
    expected_t = np.array([100.0, 200.0, 300.0]) + 0.05 * x_cross + throw / 2
    np.testing.assert_allclose(res.sample, expected_t, atol=0.5)
    np.testing.assert_allclose(res.trace, points[res.point, 0])
    np.testing.assert_allclose(points[res.point, 1], res.sample, atol=1.0)


def test_a_fault_that_ends_above_a_horizon_does_not_cross_it():
    points, horizons, _ = _section(6.0)
    short = points[:150]  # samples 20-169: crosses the horizon near 105 only
    res = horizon_offsets(short, np.zeros(150, int), {0: 1}, horizons)
    assert res.horizon.tolist() == [0]
    np.testing.assert_allclose(res.offset, 6.0, atol=0.35)


def test_the_hanging_wall_side_gives_the_sign():
    points, horizons, _ = _section(5.0, dips_toward=1)
    ids = np.zeros(len(points), int)
    right = horizon_offsets(points, ids, {0: 1}, horizons)
    wrong = horizon_offsets(points, ids, {0: -1}, horizons)
    np.testing.assert_allclose(wrong.offset, -right.offset)
    assert len(horizon_offsets(points, ids, {}, horizons)) == 0  # a fault without a side is skipped


def test_absent_picks_give_no_crossing():
    points, horizons, _ = _section(5.0)
    horizons[1, 60:] = np.nan  # the second horizon stops short of the fault's hanging wall
    res = horizon_offsets(points, np.zeros(len(points), int), {0: 1}, horizons)
    assert res.horizon.tolist() == [0, 2]


def test_bad_input_names_the_argument():
    points, horizons, _ = _section(5.0)
    with pytest.raises(InputError, match="points must be"):
        horizon_offsets(points[:, :1], np.zeros(len(points)), {0: 1}, horizons)
    with pytest.raises(InputError, match="fault_ids"):
        horizon_offsets(points, np.zeros(3), {0: 1}, horizons)
    with pytest.raises(InputError, match="near and far"):
        horizon_offsets(points, np.zeros(len(points)), {0: 1}, horizons, near=5, far=2)


# --------------------------------------------------------------------------------------------------------------------
# an ambiguous throw says so (FaultThrow.rival_ratio, alternative_throw; fault_summary.csv's throw_ambiguity)


def _faulted_section(trace, throw, *, n_traces=120):
    """A section of one repeated ``trace`` cut by a fault line dipping toward increasing trace (0.2 traces per
    sample), its hanging wall (beyond the line) moved down by ``throw`` samples; and the fault's points."""
    t = np.arange(trace.size, dtype=np.float64)
    fault_t = np.arange(20, trace.size - 20)
    fault_x = 45.0 + 0.2 * (fault_t - 20)
    section = np.empty((n_traces, trace.size))
    for x in range(n_traces):
        hanging = x > np.interp(t, fault_t, fault_x, left=fault_x[0], right=fault_x[-1])
        section[x] = np.where(hanging, np.interp(t - throw, t, trace), trace)
    return section, np.column_stack([np.rint(fault_x), fault_t]).astype(np.int64)


def test_runner_up_peak_finds_the_rival_a_period_away():
    from seismo3d.seismic.traces import runner_up_peak

    k = np.arange(-20, 21)
    curve = np.cos(2 * np.pi * (k - 4) / 10.0) * (1 - 0.25 * np.abs(k) / 21)
    index, ratio = runner_up_peak(curve, int(np.argmax(curve)))
    assert k[0] + index == pytest.approx(-6, abs=0.5)  # one period (10 samples) from the chosen +4
    assert 0.9 < ratio < 1.0
    assert runner_up_peak([0.0, 1.0, 0.0], 1) == (pytest.approx(np.nan, nan_ok=True), 0.0)  # no rival
    index, ratio = runner_up_peak([0.2, 0.5, 0.1, 0.9, 0.2], 1)  # a chosen peak that a rival beats
    assert index == pytest.approx(3, abs=0.5) and ratio == pytest.approx(1.8)


def test_a_periodic_section_gives_an_ambiguous_throw_with_its_alternative():
    from seismo3d.seismic.faults.throw import fault_throw

    t = np.arange(300)
    section, points = _faulted_section(np.sin(2 * np.pi * t / 10.0), 4.0)  # a reflector every 10 samples
    res = fault_throw(section, points)
    # +4 and -6 fit the sides equally (a period apart): the throw says it may be either
    assert res.median_throw == pytest.approx(4.0, abs=0.5)
    assert res.ambiguity > 0.8
    assert res.alternative_throw == pytest.approx(-6.0, abs=1.0)


def test_a_throw_of_unlike_reflectors_is_not_ambiguous():
    from scipy.signal import fftconvolve

    from seismo3d.seismic.faults.throw import fault_throw

    rng = np.random.default_rng(0)
    tw = np.arange(-12, 13)
    ricker = (1 - 2 * (np.pi * 0.08 * tw) ** 2) * np.exp(-(np.pi * 0.08 * tw) ** 2)
    trace = fftconvolve(rng.standard_normal(300) * (rng.random(300) < 0.3), ricker, mode="same")
    section, points = _faulted_section(trace, 6.0)
    res = fault_throw(section, points)
    assert res.median_throw == pytest.approx(6.0, abs=0.5)
    assert res.ambiguity < 0.5
    assert np.isnan(res.alternative_throw)


def test_a_periodic_cube_gives_an_ambiguous_throw_with_its_alternative():
    from seismo3d.seismic.faults.throw import fault_throw

    t = np.arange(200)
    section, points = _faulted_section(np.sin(2 * np.pi * t / 10.0), 4.0, n_traces=100)
    cube = np.repeat(section[None], 24, axis=0)  # the same section on 24 inlines: a fault plane along them
    points3 = np.concatenate([np.column_stack([np.full(len(points), i), points]) for i in range(24)])
    res = fault_throw(cube, points3)
    assert res.median_throw == pytest.approx(4.0, abs=0.5)
    assert res.ambiguity > 0.8
    assert res.alternative_throw == pytest.approx(-6.0, abs=1.0)
