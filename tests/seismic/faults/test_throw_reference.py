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
