"""Sub-volume registration (seismo3d.seismic.volumes): pairs generated from real seismic with map rotations, bin scales
on either volume and vertical scales, in both argument orders; pairs with no common volume or unrelated data; bad
input. The full grid (12 pairs per data set, f3_crop, Penobscot, Volve, both orders) is in benchmarks/volumes.py; the
pairs asserted here before the suite's 10 minutes ran out (4 f3_crop, 2 Penobscot and 3 Volve pairs, both orders:
150 s under load) are asserted by ``python benchmarks/volumes.py --only suite_grid --check``, and one pair per data set
stays here in one order."""

import os

import numpy as np
import pytest

from seismo3d.data import resampled_pair, synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import VolumeOptions, register_volumes, registration_errors
from seismo3d.seismic.volumes import decompose_map

ROTATION_DEG, SCALE_PCT, CORNERS = 0.5, 1.0, 0.5  # the tolerances


@pytest.fixture(scope="module")
def f3_crop(data_dir):
    from seismo3d.seismic import read_segy

    return read_segy(os.path.join(data_dir, "seismic", "f3_crop.sgy"))[0]


@pytest.fixture(scope="module")
def penobscot_block(penobscot):
    # 18 real inlines, 24 crosslines, 200 samples (every second sample keeps the file's band below Nyquist)
    return np.ascontiguousarray(penobscot.cube[:, 200:224, ::2][:, :, 250:450])


@pytest.fixture(scope="module")
def volve_block(data_dir):
    from seismo3d.seismic import read_segy

    # the real Volve velocity model (a smooth property, m/s): 18 inlines, 24 crosslines, 226 depth samples
    cube = read_segy(os.path.join(data_dir, "seismic", "volve_migvel_depth_sub3d.sgy"))[0]
    return np.ascontiguousarray(cube[:, 14:38, :])


def make_pair(base, angle, moving_scales, fixed_scales=(1.0, 1.0, 1.0)):
    """A fixed volume sampled from ``base`` with bins ``fixed_scales`` and a moving one with bins ``moving_scales``,
    rotated ``angle`` degrees in map view (80 % of the fixed extent, off-centre by (0.3, 1.2, 1.5) fixed samples):
    (fixed, moving, moving index -> fixed index)."""
    nb, sf = np.array(base.shape), np.asarray(fixed_scales, dtype=np.float64)
    shape = tuple(np.minimum(((nb - 1) / sf).astype(int) + 1, nb))
    return resampled_pair(base, shape, scales=moving_scales, fixed_scales=fixed_scales, angle_deg=angle,
                          offset=(0.3, 1.2, 1.5), moving_fraction=0.8)


def register_in_order(fixed, moving, truth, order, **kwargs):
    """``register_volumes`` with ``moving`` onto ``fixed`` ('moving first' in the command's order) or the reverse;
    the result, the true transform of that order and the shape of the volume it moves."""
    if order == "moving onto fixed":
        return register_volumes(fixed, moving, **kwargs), truth, moving.shape
    return register_volumes(moving, fixed, **kwargs), np.linalg.inv(truth), fixed.shape


def assert_recovered(reg, truth, moving_shape):
    err = registration_errors(reg.transform_index, truth, moving_shape)
    true_rotation = decompose_map(truth).rotation_deg
    print(f"rotation {err.rotation_deg:.3f} deg (reported {reg.rotation_deg:.2f}, true {true_rotation:.2f}), "
          f"scales {np.round(err.scale_pct, 2)} %, corners {err.corner_error:.3f}, correlation "
          f"{reg.correlation:.3f}, converged {reg.converged} {reg.reason}")
    assert reg.converged, reg.reason
    assert err.rotation_deg <= ROTATION_DEG and abs(reg.rotation_deg - true_rotation) <= ROTATION_DEG
    assert err.max_scale_pct <= SCALE_PCT
    assert err.corner_error <= CORNERS
    return err


ORDERS = ["moving onto fixed", "fixed onto moving"]


# the grid's hardest kinds: a 40-degree rotation with an anisotropy of 2.7 on the moving volume,
# and bins that differ on both volumes (no per-axis scale on one side expresses the map)
@pytest.mark.parametrize("order", [ORDERS[0], pytest.param(ORDERS[1], marks=pytest.mark.slow)])
@pytest.mark.parametrize("angle, moving_scales, fixed_scales", [
    # 2.4-4.4 s each: in the slow lane (the fast lane's budget is 60 s); the fast lane keeps the pair below, in
    # one order (the other order in the slow lane)
    pytest.param(40.0, (1.6, 0.6, 0.8), (1.0, 1.0, 1.0), marks=pytest.mark.slow),
    (25.0, (0.7, 1.3, 1.1), (1.25, 0.8, 1.0)),
])
def test_f3_pairs_in_either_order(f3_crop, angle, moving_scales, fixed_scales, order):
    fixed, moving, truth = make_pair(f3_crop, angle, moving_scales, fixed_scales)
    reg, t, shape = register_in_order(fixed, moving, truth, order)
    assert_recovered(reg, t, shape)
    assert set(reg.stage_seconds) == {"prepare", "search", "coarse", "fine", "check"}
    assert reg.overlap > 0.8
    # the last stage (check.py): the same physical way leads in either order, and refined alone from the two-way
    # optimum (its optimum is the answer) it moves 0.00-0.026 samples and 0.00-0.23 % (limits 1.5x); the other way,
    # reported, ends 0.03-0.13 samples and 0.05-1.5 % from the answer (limits 1.5x)
    check = reg.check
    assert check.leading_way == ("forward" if order == "moving onto fixed" else "backward")
    np.testing.assert_array_equal(reg.transform_index, check.transform)
    assert check.disagreement <= 0.04 and check.scale_disagreement <= 0.0035, check.to_dict()
    assert check.other_way_disagreement <= 0.2 and check.other_way_scale_disagreement <= 0.022, check.to_dict()


@pytest.mark.slow
def test_f3_onto_its_shifted_copy(f3_crop):
    copy = np.ascontiguousarray(f3_crop[4:, 4:, 5:])  # 4 inlines, 4 crosslines and 5 samples in
    reg = register_volumes(copy, f3_crop)
    truth = np.eye(4)
    truth[:3, 3] = (-4.0, -4.0, -5.0)
    assert_recovered(reg, truth, f3_crop.shape)
    np.testing.assert_allclose(reg.moving_scales, 1.0, atol=2e-3)
    assert reg.correlation > 0.99


@pytest.mark.slow
def test_order_does_not_change_the_answer(f3_crop):
    # the pair of issue 33: a copy rotated 12 degrees with scales 1.25 / 0.8 / 1.1; the cube onto the copy was 8.69
    # degrees and 7.8 samples off with converged: true before the map had the bins of both volumes
    fixed, moving, truth = resampled_pair(f3_crop, f3_crop.shape, scales=(1.25, 0.8, 1.1), angle_deg=12.0,
                                          offset=(0.3, 1.2, 1.5), moving_fraction=1.0)
    forward, backward = register_volumes(fixed, moving), register_volumes(moving, fixed)
    assert_recovered(forward, truth, moving.shape)
    assert_recovered(backward, np.linalg.inv(truth), fixed.shape)
    both = registration_errors(np.linalg.inv(backward.transform_index), forward.transform_index, moving.shape)
    assert both.corner_error <= 0.1  # measured 0.01-0.02
    assert backward.rotation_deg == pytest.approx(-forward.rotation_deg, abs=0.1)


@pytest.mark.slow
def test_a_generated_pair_with_the_spectra_candidates():
    # 64 traces per map axis: the search scores the map-view spectra's candidates beside its grid (n_maps counts
    # both; the grid alone scores the same maps with n_spectral=0). One order here (15 s); both orders, Penobscot's
    # pair without coordinates and a 160 x 160 one: python benchmarks/volumes.py --only coordinates --check
    order = ORDERS[0]
    cube = synthetic_cube((96, 96, 72), n_faults=2, seed=5).cube
    fixed, moving, truth = resampled_pair(cube, (64, 64, 56), scales=(1.25, 0.8, 1.1), angle_deg=12.0,
                                          offset=(1.3, -2.2, 1.5), moving_fraction=0.9)
    reg, t, shape = register_in_order(fixed, moving, truth, order)
    assert_recovered(reg, t, shape)
    grid_only = VolumeOptions(n_spectral=0)
    assert 0 < reg.n_maps - register_in_order(fixed, moving, truth, order, options=grid_only)[0].n_maps <= 6


# One pair per real data set in one order, beside the f3_crop pairs above: the grid's other pairs with bins that
# differ on the fixed volume (or on both), the Penobscot and Volve pairs in both orders, are asserted by
# `python benchmarks/volumes.py --only suite_grid --check` (SUITE_GRID there; 10-30 s a pair on 2 shared cores)
@pytest.mark.slow
def test_penobscot_pair(penobscot_block):
    # clipped 8-bit amplitudes: neither their smoothing nor their envelope survives decimating the samples by 4, so
    # the search runs on every second sample (9-12 s on 2 shared cores; the other order and the 30-degree pair with
    # bins 1.6 on the fixed volume: the benchmark's check)
    fixed, moving, truth = make_pair(penobscot_block, 40.0, (1.6, 0.6, 0.8), (1.0, 1.0, 1.0))
    assert_recovered(*register_in_order(fixed, moving, truth, ORDERS[0]))


@pytest.mark.slow
def test_volve_velocity_pair_is_right(volve_block):
    # a smooth property, registered by its derivative along the traces: the lateral position rests on small
    # anomalies, and copies with coarse bins are aliased, so the way that interpolates them is biased. The answer is
    # the way that interpolates the less aliased volume refined alone (check.py). Of the benchmark's pairs (24 of 24
    # right and converged), the pair at 30 deg with fixed bins 1.6 was 2.2 % (moving onto fixed) and 3.4 % (fixed
    # onto moving) off at the two-way optimum (not converged), and the 0-deg pair fixed onto moving climbed from its
    # start to a map rotation of 118 deg with the central-difference Jacobian on the coarsest level
    # (registration._refine_starts): those are in the check; here the pair with the fixed bins 1.6 / 0.6 (6-9 s)
    fixed, moving, truth = make_pair(volve_block, 10.0, (1.0, 1.0, 1.0), (1.6, 0.6, 1.0))
    assert_recovered(*register_in_order(fixed, moving, truth, ORDERS[1]))


@pytest.fixture(scope="module")
def parihaka_pair(data_dir):
    # the real Parihaka time slices (8-bit, each slice by its own range: its mean trace is 80 % of the variance);
    # the third pair of seed 1234 of random_grid_pair: map rotation 6.7 deg, moving bins 0.73 / 1.38, samples 0.99.
    # Before the search left the mean traces out, every map it scored correlated 0.94 and the answer's scales were
    # 0.32 / 1.67 (moving onto fixed) and 3.4 / 0.6 (fixed onto moving). The 50 pairs per cube of the issue:
    # `python benchmarks/volumes.py --only any_grid --check`
    from seismo3d.data import fetch, random_grid_pair

    with np.load(fetch("seismic/parihaka_timeslices/parihaka_timeslices_cols174_302.npz")) as z:
        cube = np.ascontiguousarray(z["seismic"].transpose(1, 2, 0), dtype=np.float32)
    rng = np.random.default_rng(1234)
    pair = [random_grid_pair(cube, (96, 96, 128), rng) for _ in range(3)][2]
    return pair.fixed, pair.moving, pair.transform_index


@pytest.mark.slow  # 6-8 CPU s each
@pytest.mark.parametrize("order", ORDERS)
def test_parihaka_pair_on_a_rotated_anisotropic_grid(parihaka_pair, order):
    assert_recovered(*register_in_order(*parihaka_pair, order))


@pytest.mark.slow  # 3.6 s in the fast lane, whose budget is 60 s
def test_unrelated_volumes_are_not_converged(f3_crop):
    other = synthetic_cube((24, 24, 80), n_faults=1, seed=4).cube
    reg = register_volumes(other, f3_crop)
    assert not reg.converged
    assert reg.reason and "\n" not in reg.reason
    print(reg.reason, reg.correlation, reg.check.control_correlation)
    # resampled pairs of f3_crop: 0.88-1.0; the spurious optimum here depends on the search's path: -0.09 with every
    # map scored on the coarsest level and 20,000 points per level, 0.57 (refused by the shifted controls, 0.56)
    # with the first scoring on decimated levels and 5000 points on them
    assert reg.correlation < 0.65


@pytest.mark.slow
@pytest.mark.parametrize("name", ["no common time", "noise"])
def test_no_common_volume_is_not_converged(f3_crop, name):
    if name == "no common time":  # the top and the bottom half of one cube
        a, b = f3_crop[:, :, :37], f3_crop[:, :, 38:]
    else:
        rng = np.random.default_rng(3)
        a, b = (rng.normal(size=s).astype(np.float32) for s in ((24, 20, 64), (22, 18, 60)))
    for fixed, moving in ((a, b), (b, a)):
        reg = register_volumes(fixed, moving)
        print(name, reg.reason)
        assert not reg.converged and reg.reason


@pytest.mark.slow
def test_rigid_with_known_spacings_is_a_map_rotation_in_metres():
    big = synthetic_cube((104, 104, 112), n_faults=3, seed=1).cube
    # moving bins 50 m x 25 m and 2 ms against fixed 25 m bins and 4 ms: in index space a scale of (2, 1, 0.5)
    fixed, moving, truth = resampled_pair(big, (64, 64, 80), scales=(2.0, 1.0, 0.5), angle_deg=20.0, offset=(1, 2, 0))
    reg = register_volumes(fixed, moving, model="rigid", fixed_spacing=(25.0, 25.0, 4.0),
                           moving_spacing=(50.0, 25.0, 2.0))
    assert_recovered(reg, truth, moving.shape)
    np.testing.assert_allclose(reg.moving_scales, 1.0, atol=1e-9)  # rigid: the spacings are the scales
    phys = np.diag([25.0, 25.0, 4.0, 1.0]) @ reg.transform_index @ np.diag([1 / 50, 1 / 25, 1 / 2, 1.0])
    np.testing.assert_allclose(reg.transform_physical, phys)
    map_view = reg.transform_physical[:2, :2]  # metres to metres: a rotation
    np.testing.assert_allclose(map_view.T @ map_view, np.eye(2), atol=1e-9)


@pytest.mark.parametrize("fixed, moving, kwargs, match", [
    (np.zeros((32, 32)), None, {}, "3D volume"),
    (np.zeros((32, 32, 32)), None, {}, "constant"),
    (None, np.full((32, 32, 32), np.nan), {}, "NaN"),
    (None, np.zeros((4, 32, 32)), {}, "at least 8"),
    (None, None, {"fixed_spacing": (25.0, 4.0)}, "3 values"),
    (None, None, {"moving_spacing": (25.0, -25.0, 4.0)}, "> 0"),
    (None, None, {"model": "axis_scaled"}, "model"),
    (None, None, {"scale_range": (2.0, 0.5)}, "scale_range"),
    (None, None, {"options": {"seed": 1}}, "VolumeOptions"),
    (None, None, {"sed": 1}, "unknown keyword argument"),
])
def test_bad_input_gives_clear_error(fixed, moving, kwargs, match):
    cube = synthetic_cube((32, 32, 48), n_faults=1, seed=1).cube
    with pytest.raises(InputError, match=match):
        register_volumes(cube if fixed is None else fixed, cube if moving is None else moving, **kwargs)


def test_volume_options_are_checked():
    assert VolumeOptions().scale_range == (0.5, 2.0)
    with pytest.raises(InputError, match="max_factor"):
        VolumeOptions(max_factor=6)
    with pytest.raises(InputError, match="scale_step"):
        VolumeOptions(scale_step=1.0)
    with pytest.raises(InputError, match="min_correlation"):
        VolumeOptions(min_correlation=1.5)
    with pytest.raises(InputError, match="n_spectral"):
        VolumeOptions(n_spectral=-1)
    with pytest.raises(InputError, match="spectral_min_traces"):
        VolumeOptions(spectral_min_traces=4)
    with pytest.raises(InputError, match="screen_keep"):
        VolumeOptions(screen_keep=-1)
    with pytest.raises(InputError, match="n_points_coarse"):
        VolumeOptions(n_points_coarse=0)
