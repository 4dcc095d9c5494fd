"""Sub-volume registration (seismo3d.seismic.volumes): generated and real cube pairs with known per-axis scales and
map rotation, in either order; unrelated and bad volumes."""

import os

import numpy as np
import pytest

from seismo3d.data import resampled_pair, synthetic_cube
from seismo3d.errors import InputError, RegistrationError
from seismo3d.seismic import VolumeOptions, register_volumes, registration_errors

ROTATION_DEG, SCALE_PCT, CENTRE = 0.5, 1.0, 0.5  # the tolerances


@pytest.fixture(scope="module")
def big():
    return synthetic_cube((104, 104, 112), n_faults=3, seed=1).cube


@pytest.fixture(scope="module")
def penobscot_slab(penobscot):
    # 18 consecutive inlines of 8-bit amplitudes; every second sample keeps the file's band below Nyquist
    return penobscot.cube[:, :, ::2]


@pytest.fixture(scope="module")
def f3_crop(data_dir):
    from seismo3d.seismic import read_segy

    return read_segy(os.path.join(data_dir, "seismic", "f3_crop.sgy"))[0]


def _assert_recovered(reg, truth, moving_shape):
    err = registration_errors(reg.transform_index, truth, moving_shape)
    print(f"rotation {err.rotation_deg:.3f} deg, scales {np.round(err.scale_pct, 2)} %, centre "
          f"{err.centre_error:.3f}, correlation {reg.correlation:.3f}, fitness {reg.fitness:.2f}")
    assert err.rotation_deg <= ROTATION_DEG
    assert err.max_scale_pct <= SCALE_PCT
    assert err.centre_error <= CENTRE
    return err


@pytest.mark.slow
# one case here; benchmarks/volumes.py runs eight (scales 0.5-2, rotations up to 30 degrees)
@pytest.mark.parametrize("scales, angle", [((0.5, 1.0, 2.0), 15.0)])
def test_synthetic_scales_and_map_rotation(big, scales, angle):
    fixed, moving, truth = resampled_pair(big, (64, 64, 80), scales=scales, angle_deg=angle, offset=(3, -2, 1.5))
    reg = register_volumes(fixed, moving, model="axis_scaled")
    _assert_recovered(reg, truth, moving.shape)
    assert reg.fitness > 0.5 and reg.correlation > 0.9
    assert abs(reg.rotation_deg - angle) <= ROTATION_DEG
    np.testing.assert_allclose(reg.scales, scales, rtol=SCALE_PCT / 100)  # spacings default to 1: index scales


@pytest.mark.slow
def test_rigid_with_known_spacings_is_a_map_rotation_in_metres(big):
    # moving bins 50 m x 25 m and 2 ms against fixed 25 m bins and 4 ms: in index space a scale of (2, 1, 0.5)
    fixed, moving, truth = resampled_pair(big, (64, 64, 80), scales=(2.0, 1.0, 0.5), angle_deg=20.0, offset=(1, 2, 0))
    reg = register_volumes(fixed, moving, model="rigid", fixed_spacing=(25.0, 25.0, 4.0),
                           moving_spacing=(50.0, 25.0, 2.0))
    _assert_recovered(reg, truth, moving.shape)
    # rigid in the working frame (metres laterally, fixed samples vertically): unit scales in physical units up to
    # the tiny tilt a 3D rotation may mix between metres and milliseconds
    np.testing.assert_allclose(reg.scales, 1.0, atol=1e-3)
    assert abs(reg.rotation_deg - 20.0) <= ROTATION_DEG
    phys = np.diag([25.0, 25.0, 4.0, 1.0]) @ reg.transform_index @ np.diag([1 / 50, 1 / 25, 1 / 2, 1.0])
    np.testing.assert_allclose(reg.transform_physical, phys)
    map_view = reg.transform_physical[:2, :2]  # metres to metres: a rotation
    np.testing.assert_allclose(map_view.T @ map_view, np.eye(2), atol=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize("scales, angle", [((0.7, 1.3, 0.8), 5.0)])  # more cases: benchmarks/volumes.py
def test_real_penobscot_slab(penobscot_slab, scales, angle):
    # a real 18-inline slab: the moving volume must stay inside it, so map rotations are small here (see the
    # benchmark for what larger ones do)
    fixed, moving, truth = resampled_pair(penobscot_slab, (18, 192, 288), scales=scales, angle_deg=angle,
                                          offset=(0.3, 1.2, 1.5))
    reg = register_volumes(fixed, moving, model="axis_scaled")
    _assert_recovered(reg, truth, moving.shape)


@pytest.mark.slow
def test_affine_model_recovers_a_scaled_rotation(big):
    fixed, moving, truth = resampled_pair(big, (64, 64, 80), scales=(1.25, 0.8, 1.1), angle_deg=10.0)
    reg = register_volumes(fixed, moving, model="affine")
    _assert_recovered(reg, truth, moving.shape)


@pytest.mark.slow
def test_unrelated_volumes_raise_registration_error(big):
    other = synthetic_cube((40, 40, 48), n_faults=2, seed=7).cube
    with pytest.raises(RegistrationError, match="correlat|consistent|overlap"):
        # a coarser correlation search than the default (rotations every 15 degrees, 3 scales per axis) and a shorter
        # polish keep the test short; what fails and how it is reported are the same
        register_volumes(big[30:70, 30:70, 30:78], other, rotation_step=15.0, scale_steps=3, polish_evaluations=150)


@pytest.mark.slow
def test_volumes_too_small_for_slice_features_say_so_when_nothing_correlates():
    # small volumes that are not each other's resampling: no feature matches and no start correlating as much as
    # asked; the message names the sizes and what to do. (They reach 0.88 by chance, the moving one squeezed to 0.45
    # scale over 1 % of the fixed one, so min_correlation is raised as register_volumes' docstring advises.)
    fixed = synthetic_cube((24, 18, 80), n_faults=1, seed=2).cube
    moving = synthetic_cube((20, 16, 64), n_faults=1, seed=9).cube
    with pytest.raises(RegistrationError, match=r"small for slice features \(fixed 24 x 18 traces, moving 20 x 16"):
        register_volumes(fixed, moving, min_correlation=0.9, rotation_step=15.0, scale_steps=3)  # a coarser search


@pytest.mark.parametrize("fixed, moving, kwargs, match", [
    (np.zeros((32, 32)), None, {}, "3D volume"),
    (np.zeros((32, 32, 32)), None, {}, "constant"),
    (None, np.full((32, 32, 32), np.nan), {}, "NaN"),
    (None, np.zeros((4, 32, 32)), {}, "at least 8"),
    (None, None, {"fixed_spacing": (25.0, 4.0)}, "3 values"),
    (None, None, {"moving_spacing": (25.0, -25.0, 4.0)}, "> 0"),
    (None, None, {"model": "similarity"}, "model"),
    (None, None, {"scale_range": (2.0, 0.5)}, "scale_range"),
    (None, None, {"options": {"seed": 1}}, "VolumeOptions"),
    (None, None, {"sed": 1}, "unknown keyword argument"),
])
def test_bad_input_gives_clear_error(big, fixed, moving, kwargs, match):
    cube = big[:32, :32, :48]
    with pytest.raises(InputError, match=match):
        register_volumes(cube if fixed is None else fixed, cube if moving is None else moving, **kwargs)


def test_noise_has_too_few_reflector_points():
    noise = np.random.default_rng(0).normal(size=(24, 24, 24)).astype(np.float32)
    with pytest.raises(InputError, match="reflector points"):
        register_volumes(noise, noise)


# The held-out check on real data: f3_crop (23 x 18 traces x 75 samples, too small for slice features: the
# correlation start) against a resampled copy rotated 12 degrees with scales 1.25 / 0.8 / 1.1, registered in both
# orders. The small copy onto the cube landed within 0.012 deg, the cube onto the copy 2.1 deg off (its scales are
# along the copy's axes, which the moving-axis model cannot represent); with the polish along the fixed axes too
# (VolumeOptions.symmetric) both orders give inverse transforms. Every f3_crop case of benchmarks/volumes.py (scales
# 0.5-2, rotations up to 30 degrees) passes the tolerances.
@pytest.mark.slow
def test_real_registration_does_not_depend_on_which_volume_is_fixed(f3_crop):
    fixed, moving, truth = resampled_pair(f3_crop, f3_crop.shape, scales=(1.25, 0.8, 1.1), angle_deg=12.0,
                                          offset=(0.3, 1.2, 1.5))
    forward = register_volumes(fixed, moving)
    backward = register_volumes(moving, fixed)
    err_f = _assert_recovered(forward, truth, moving.shape)
    err_b = _assert_recovered(backward, np.linalg.inv(truth), fixed.shape)
    # the two answers are each other's inverse
    both = registration_errors(np.linalg.inv(backward.transform_index), forward.transform_index, moving.shape)
    print(f"forward {err_f}, backward {err_b}, forward vs inverse of backward {both}")
    assert both.rotation_deg <= ROTATION_DEG and both.max_scale_pct <= SCALE_PCT and both.centre_error <= CENTRE
    assert forward.converged and backward.converged
    assert (forward.scaled_axes, backward.scaled_axes) == ("moving", "fixed")
    for reg in (forward, backward):
        assert reg.n_feature_matches == 0 and reg.result.info["start"] == "correlation"


def test_volume_options_are_checked():
    assert VolumeOptions().scale_range == (0.5, 2.0)
    with pytest.raises(InputError, match="alpha"):
        VolumeOptions(alpha=2.0)
    with pytest.raises(InputError, match="feature_method"):
        VolumeOptions(feature_method="orb")
