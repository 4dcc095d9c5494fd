"""Fault skins (seismo3d.seismic.faults.surfaces.skins): gaps bridged, crossing faults kept apart, pieces of one fault
cut by
another merged, hysteresis and sizes, options."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import Fault, SkinOptions, fault_normals, fault_skins
from seismo3d.seismic.faults.surfaces.skins import skins_from_cells


def _plane(shape, strike, dip, centre):
    i, j, k = np.meshgrid(*(np.arange(n) for n in shape), indexing="ij")
    n = fault_normals(np.array([strike]), np.array([dip]))[0]
    d = (i - centre[0]) * n[0] + (j - centre[1]) * n[1] + (k - centre[2]) * n[2]
    return np.abs(d) < 0.5  # a one-sample-thick digital plane


def _image(masks_and_orientations, shape):
    thin = np.zeros(shape, np.float32)
    strike = np.zeros(shape, np.float32)
    dip = np.zeros(shape, np.float32)
    for mask, s, d, value in masks_and_orientations:
        thin[mask] = value
        strike[mask] = s
        dip[mask] = d
    return thin, strike, dip


def test_crossing_planes_stay_apart_and_gaps_are_bridged():
    shape = (64, 64, 64)
    a = _plane(shape, 0.0, 80.0, (32, 32, 32))
    b = _plane(shape, 90.0, 70.0, (32, 32, 32))
    b &= ~a
    a[:, :, 30:34] = False  # a 4-sample gap across plane a
    thin, strike, dip = _image([(b, 90.0, 70.0, 0.8), (a, 0.0, 80.0, 0.6)], shape)
    faults = fault_skins(thin, strike, dip, lower=0.3, upper=0.5)
    assert len(faults) == 2 and all(isinstance(f, Fault) for f in faults)
    for f in faults:
        orient = {(float(s), float(d)) for s, d in zip(f.strike_deg, f.dip_deg)}
        assert len(orient) == 1  # each skin holds one plane's cells only
    a_skin = next(f for f in faults if f.strike_deg[0] == 0.0)
    assert a_skin.size == int(a.sum())  # one skin across the gap
    assert a_skin.points[:, 2].min() < 30 and a_skin.points[:, 2].max() >= 34
    # the same skins from the cells as lists in any order (a cube larger than memory gathers them block by block)
    cells = np.argwhere(thin >= 0.3)
    order = np.random.default_rng(0).permutation(len(cells))
    at = tuple(cells[order].T)
    again = skins_from_cells(cells[order], thin[at], strike[at], dip[at], shape=shape, lower=0.3, upper=0.5)
    assert [f.id for f in again] == [f.id for f in faults]
    assert all(np.array_equal(f.points, g.points) for f, g in zip(again, faults))
    with pytest.raises(InputError, match="outside"):
        skins_from_cells(cells + 64, thin[at], strike[at], dip[at], shape=shape, lower=0.3, upper=0.5)


def test_pieces_of_a_fault_cut_by_another_are_merged():
    shape = (64, 64, 80)
    a = _plane(shape, 0.0, 65.0, (32, 32, 40))
    cut = _plane(shape, 90.0, 80.0, (32, 32, 40))
    i = np.arange(shape[0])[:, None, None]
    hanging = np.broadcast_to(i > 32, shape)
    # displace plane a by 3 samples down on one side of the cutting fault, leaving a 5-trace gap between the pieces
    moved = np.zeros(shape, bool)
    moved[:, :, 3:] = (a & hanging)[:, :, :-3]
    a = (a & ~hanging & (np.abs(i - 32) > 2)) | (moved & (np.abs(i - 32) > 2))
    thin, strike, dip = _image([(cut, 90.0, 80.0, 0.9), (a, 0.0, 65.0, 0.7)], shape)
    faults = fault_skins(thin, strike, dip, lower=0.3, upper=0.5)
    pieces = [f for f in faults if f.strike_deg[0] == 0.0]
    assert len(pieces) == 1 and pieces[0].size == int(a.sum())
    apart = fault_skins(thin, strike, dip, lower=0.3, upper=0.5, options=SkinOptions(merge_gap=0))
    assert len([f for f in apart if f.strike_deg[0] == 0.0]) == 2


def test_hysteresis_and_smallest_skin_in_2d():
    thin = np.zeros((100, 80), np.float32)
    thin[20, 5:75] = 0.4  # a long weak fault with one strong sample: kept
    thin[20, 40] = 0.9
    thin[60, 5:75] = 0.4  # a long weak fault without: dropped
    thin[80, 10:20] = 0.9  # a strong 10-sample fault: too small (15 samples in 2D)
    strike = np.full(thin.shape, 90.0, np.float32)
    dip = np.full(thin.shape, 90.0, np.float32)
    faults = fault_skins(thin, strike, dip, lower=0.3, upper=0.8)
    assert [f.points[:, 0].min() for f in faults] == [20] and faults[0].size == 70
    assert faults[0].points.shape[1] == 2 and faults[0].normals.shape[1] == 2


def test_options_and_errors():
    assert SkinOptions().smallest((100, 120)) == 15
    assert SkinOptions().smallest((601, 1501)) == 150
    assert SkinOptions().smallest((128, 128, 128)) == 164
    assert SkinOptions().smallest((18, 512, 1536)) == 276
    assert SkinOptions().smallest((40, 40, 64)) == 100
    for bad in (dict(lateral_reach=0), dict(max_angle=95.0), dict(min_size=0), dict(merge_offset=0.0)):
        with pytest.raises(InputError):
            SkinOptions(**bad)
    thin = np.zeros((40, 40), np.float32)
    with pytest.raises(InputError, match="lower <= upper"):
        fault_skins(thin, thin, thin, lower=0.5, upper=0.3)
    assert fault_skins(thin, thin, thin, lower=0.3, upper=0.5) == []


# --- branches of opposite dip (a Y, an inverted V) -------------------------------------------------------------------

def _strand(image, x0, t0, t1, dip, strike, value=0.8):
    """Cells of a straight 2D fault from (x0, t0) down to t1 at ``dip`` (degrees), dipping toward increasing trace
    for strike 270 and decreasing trace for strike 90 (index space)."""
    thin, st, dp = image
    run = (1.0 if strike == 270.0 else -1.0) / np.tan(np.radians(dip))
    for t in range(t0, t1):
        x = int(round(x0 + run * (t - t0)))
        thin[x, t], st[x, t], dp[x, t] = value, strike, dip


def _section_image(shape=(96, 140)):
    return tuple(np.zeros(shape, np.float32) for _ in range(3))


@pytest.mark.parametrize("dip", [80.0, 82.0])
def test_inverted_v_of_opposite_dips_is_two_faults(dip):
    """Two faults dipping opposite ways from a common apex (an inverted V, 16-20 degrees apart) link into one skin
    (their normals are within max_angle); split_angle parts them, each fault with one dip direction."""
    image = _section_image()
    _strand(image, 48, 10, 110, dip, 90.0)
    _strand(image, 48, 10, 110, dip, 270.0)
    whole = fault_skins(*image, lower=0.3, upper=0.5, options=SkinOptions(split_angle=None))
    assert len(whole) == 1  # one skin over both branches without the split
    faults = fault_skins(*image, lower=0.3, upper=0.5)
    assert len(faults) == 2
    for f in faults:
        assert len(set(f.strike_deg.tolist())) == 1  # one dip direction each
        assert f.points[:, 1].max() - f.points[:, 1].min() >= 95  # each branch whole, apex to base
    assert {float(f.strike_deg[0]) for f in faults} == {90.0, 270.0}


def test_y_branch_of_opposite_dip_is_split_off_and_the_fault_stays_whole():
    """A Y: a fault (80 degrees toward decreasing trace) from whose middle a branch dips the other way. The branch
    becomes a fault of its own; the fault keeps its cells above and below the junction."""
    image = _section_image()
    _strand(image, 60, 5, 125, 80.0, 90.0)
    x_mid = int(round(60 - (60 - 5) / np.tan(np.radians(80.0))))
    _strand(image, x_mid + 1, 61, 121, 82.0, 270.0)
    faults = fault_skins(*image, lower=0.3, upper=0.5)
    assert len(faults) == 2
    main, branch = faults  # by size
    assert set(main.strike_deg.tolist()) == {90.0} and main.points[:, 1].min() == 5 and main.points[:, 1].max() == 124
    assert set(branch.strike_deg.tolist()) == {270.0} and branch.points[:, 1].min() >= 61


def test_vertical_fault_whose_cells_wiggle_stays_one():
    """A near-vertical fault whose cells' dip direction flips every few samples (dip 88 either way) is one fault:
    the wiggles are shorter than two link reaches, and no branch dips away from the other."""
    image = _section_image()
    thin, st, dp = image
    for t in range(10, 130):
        thin[48, t], st[48, t], dp[48, t] = 0.8, (90.0 if (t // 5) % 2 else 270.0), 88.0
    faults = fault_skins(*image, lower=0.3, upper=0.5)
    assert len(faults) == 1 and faults[0].size == 120
    # two long halves of opposite direction along one vertical line: their lines agree, one fault
    st[48, 10:70], st[48, 70:130] = 90.0, 270.0
    assert len(fault_skins(*image, lower=0.3, upper=0.5)) == 1


def test_split_angle_option():
    assert SkinOptions().split_angle == 10.0
    with pytest.raises(InputError, match="split_angle"):
        SkinOptions(split_angle=90.0)
    with pytest.raises(InputError, match="split_angle"):
        SkinOptions(split_angle=0.0)
