"""The split of 2D fault skins at a fork (seismo3d.seismic.faults.surfaces.skin_splits.split_forks,
SkinOptions.split_forks): a Y is split into its branches, each trunk going with the branch it continues; straight
and gently curved faults, a short side spur and two branches along one line stay whole."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.seismic import SkinOptions, fault_skins
from seismo3d.seismic.faults.surfaces.skin_splits import split_forks

LATERAL, VERTICAL, ANGLE, MINIMUM = 2, 6, 10.0, 15


def _line(x0, t0, t1, slope, bend=0.0):
    """(t1 - t0, 2) cells (trace, sample) of x = x0 + slope (t - t0) + bend (t - t0)^2, one a sample."""
    t = np.arange(t0, t1)
    return np.stack([np.round(x0 + slope * (t - t0) + bend * (t - t0) ** 2), t], axis=1).astype(np.int64)


def _split(*pieces):
    xz = np.concatenate(pieces)
    return xz, split_forks(xz, np.zeros(len(xz), np.int64), MINIMUM, LATERAL, VERTICAL, ANGLE)


@pytest.mark.parametrize("arm_slope", [0.35, -0.35, 0.6])
def test_y_is_split_and_the_trunk_goes_with_the_branch_it_continues(arm_slope):
    trunk = _line(50, 10, 60, 0.02)
    straight = _line(51, 60, 130, 0.02)  # the trunk's continuation
    arm = _line(51, 60, 130, arm_slope)  # leaves the junction at 19-31 degrees
    xz, label = _split(trunk, straight, arm)
    assert len(np.unique(label)) == 2
    n1, n2 = len(trunk), len(trunk) + len(straight)
    assert len(np.unique(label[:n2])) == 1  # trunk and its continuation one fault
    # the arm is the other fault below the junction (its first samples, within a few traces of the trunk, may go
    # either way)
    far = np.abs(arm[:, 0] - straight[:, 0]) > LATERAL
    assert np.all(label[n2:][far] != label[0])
    assert far.sum() >= 50


def test_x_is_split_into_its_two_lines():
    """Two faults crossing as an X whose cells link into one skin: no part holds cells of both lines away from the
    crossing (the lower limbs form a second fork, split again: the line not continued may come in two parts)."""
    a = _line(30, 10, 130, 0.3)
    b = _line(66, 10, 130, -0.3)
    xz, label = _split(a, b)
    la, lb = label[:len(a)], label[len(a):]
    apart = np.abs(a[:, 0] - b[:, 0]) > 2 * LATERAL  # within a link reach of the crossing cells may go either way
    assert 2 <= len(np.unique(label)) <= 3
    assert not set(la[apart]) & set(lb[apart])
    assert len(np.unique(la[apart])) == 1 or len(np.unique(lb[apart])) == 1  # one line whole


@pytest.mark.parametrize("bend", [0.0, 0.001, 0.003])
def test_straight_or_gently_curved_fault_is_not_split(bend):
    xz, label = _split(_line(40, 5, 150, 0.1, bend))
    assert np.all(label == 0)


@pytest.mark.parametrize("spur_cells", [1, 2])
def test_short_side_spur_is_not_split(spur_cells):
    fault = _line(40, 5, 150, 0.05)
    spur = np.array([[46 + k, 70 + k] for k in range(spur_cells)])
    xz, label = _split(fault, spur)
    assert np.all(label == 0)


def test_two_parallel_branches_along_one_direction_stay_one():
    """Two branches 8 traces apart, parallel: their lines agree within the angle, nothing to split."""
    xz, label = _split(_line(40, 5, 60, 0.0), _line(40, 60, 130, 0.0), _line(48, 60, 130, 0.0))
    assert np.all(label == 0)


def test_small_skins_and_other_labels_are_left_alone():
    y = np.concatenate([_line(50, 10, 60, 0.0), _line(50, 60, 130, 0.0), _line(50, 60, 130, 0.4)])
    xz = np.concatenate([y, _line(5, 5, 12, 0.0)])
    label = np.concatenate([np.full(len(y), 3), np.full(7, 1)])
    out = split_forks(xz, label, MINIMUM, LATERAL, VERTICAL, ANGLE)
    assert np.all(out[len(y):] == 1) and np.all(out[:60] == 3)
    assert set(np.unique(out[:len(y)])) == {3, 4}  # the branch takes a label above every old one
    assert np.all(split_forks(xz, label, len(xz) + 1, LATERAL, VERTICAL, ANGLE) == label)  # all below minimum


def _strand(image, x0, t0, t1, dip):
    thin, st, dp = image
    run = 1.0 / np.tan(np.radians(dip))
    for t in range(t0, t1):
        x = int(round(x0 + run * (t - t0)))
        thin[x, t], st[x, t], dp[x, t] = 0.8, 270.0, dip


def test_fault_skins_split_a_y_whose_branches_dip_the_same_way():
    """A Y whose branch dips the same way as the fault, 14 degrees off it (the normals link it into the fault's
    skin, and the opposite-dip split sees one direction): one fault without the fork split, two with it."""
    image = tuple(np.zeros((110, 140), np.float32) for _ in range(3))
    _strand(image, 40, 5, 130, 88.0)
    _strand(image, 42, 60, 130, 74.0)
    one = fault_skins(*image, lower=0.3, upper=0.5, options=SkinOptions(split_forks=False))
    assert len(one) == 1
    two = fault_skins(*image, lower=0.3, upper=0.5, options=SkinOptions(split_forks=True))
    assert len(two) == 2
    main = two[0]
    assert main.points[:, 1].min() == 5 and main.points[:, 1].max() == 129  # the fault whole
    assert np.all(two[1].points[:, 1] >= 60)  # the branch, below the junction


def test_split_forks_option():
    with pytest.raises(InputError, match="split_forks"):
        SkinOptions(split_forks="yes")
    with pytest.raises(InputError, match="split_forks"):
        SkinOptions(split_forks=1)
    assert SkinOptions(split_forks=False, split_angle=None).split_forks is False


def test_lens_whose_branches_join_again_stays_one():
    """A fault that parts into two strands and joins again (a lens, as in a braided fault zone) stays whole: no
    branch ends free. Cut before they join again, the same strands end free and are split."""
    s = np.arange(0, 50)
    out = np.where(s < 40, 0.35 * s, 14 - 1.4 * (s - 40))  # out along a line 19 degrees off, back in 10 samples
    left = np.stack([np.round(55 - out), 50 + s], axis=1).astype(np.int64)
    right = np.stack([np.round(55 + out), 50 + s], axis=1).astype(np.int64)
    top, bottom = _line(55, 5, 50, 0.0), _line(55, 100, 150, 0.0)
    xz, label = _split(top, left, right, bottom)
    assert np.all(label == 0)
    xz, label = _split(top, left[:40], right[:40])
    assert len(np.unique(label)) == 2


def test_branch_too_small_to_be_kept_is_not_cut_off():
    """A Y whose arm (30 cells, its first few with the trunk) is split off when a skin of its size may be kept, and
    left on its fault when it may not."""
    xz = np.concatenate([_line(50, 10, 60, 0.0), _line(50, 60, 130, 0.0), _line(50, 60, 90, 0.5)])
    label = np.zeros(len(xz), np.int64)
    arm = np.bincount(split_forks(xz, label, MINIMUM, LATERAL, VERTICAL, ANGLE)).min()
    assert 20 <= arm <= 30
    assert len(np.unique(split_forks(xz, label, arm, LATERAL, VERTICAL, ANGLE))) == 2
    assert np.all(split_forks(xz, label, arm + 1, LATERAL, VERTICAL, ANGLE) == 0)
