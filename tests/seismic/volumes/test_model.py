"""The map between two sub-volumes (seismo3d.seismic.volumes.model): parameters, the rigid reparametrisation, and the
decomposition into a map rotation and the bin scales of both volumes."""

import numpy as np
import pytest

from seismo3d.seismic.volumes import decompose_map
from seismo3d.seismic.volumes.model import (Reparam, corner_distance, map_matrix, model_matrix, model_params,
                                            point_derivatives, rotation_2d)


def _two_sided(theta, fixed_lateral, moving, vertical=1.0):
    """``diag(1 / fixed) R(theta) diag(moving)`` in map view and ``vertical`` along the traces, (4, 4)."""
    t = np.eye(4)
    t[:2, :2] = np.diag(1.0 / np.asarray(fixed_lateral)) @ rotation_2d(theta) @ np.diag(moving)
    t[2, 2] = vertical
    return t


@pytest.mark.parametrize("theta, fixed, moving", [
    (25.0, (1.25, 0.8), (0.7, 1.3)),
    (-40.0, (0.6 ** 0.5, 0.6 ** -0.5), (1.6, 1.6)),
    (12.0, (1.0, 1.0), (1.25, 0.8)),
])
def test_two_sided_maps_are_decomposed_into_their_rotation_and_both_volumes_scales(theta, fixed, moving):
    # the common factor of the two sides is fixed by fixed_scales[0] * fixed_scales[1] = 1
    g = np.sqrt(fixed[0] * fixed[1])
    dec = decompose_map(_two_sided(theta, fixed, moving, vertical=1.1))
    assert dec.separable
    assert dec.rotation_deg == pytest.approx(theta, abs=1e-9)
    np.testing.assert_allclose(dec.fixed_scales, [fixed[0] / g, fixed[1] / g, 1.0], rtol=1e-9)
    np.testing.assert_allclose(dec.moving_scales, [moving[0] / g, moving[1] / g, 1.1], rtol=1e-9)


def test_without_a_rotation_the_anisotropy_is_reported_on_the_moving_volume():
    # diag(1/f) diag(m) is the same map for any split of the anisotropy: it goes to the moving scales
    dec = decompose_map(_two_sided(0.0, (1.25, 0.8), (1.0, 1.0)))
    assert not dec.separable
    assert dec.rotation_deg == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(dec.moving_scales, [0.8, 1.25, 1.0])
    np.testing.assert_allclose(dec.fixed_scales, 1.0)


def test_a_map_and_its_inverse_have_opposite_rotations_and_swapped_scales():
    t = _two_sided(30.0, (1.25, 0.8), (0.7, 1.3))
    forward, backward = decompose_map(t), decompose_map(np.linalg.inv(t))
    assert backward.rotation_deg == pytest.approx(-forward.rotation_deg, abs=1e-9)
    # the gauge (fixed scales multiply to 1) rescales both sides of the inverse by one factor
    ratio = backward.fixed_scales[:2] / forward.moving_scales[:2]
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)
    np.testing.assert_allclose(backward.moving_scales[:2] / forward.fixed_scales[:2], ratio[0], rtol=1e-9)


def test_parameters_round_trip_and_their_point_derivatives_are_exact():
    centre = np.array([5.0, 4.0, 20.0])
    p = np.array([0.9, -0.3, 0.25, 1.1, 1.2, 7.0, -2.0, 3.5])
    t = model_matrix(p, centre)
    np.testing.assert_allclose(model_params(t, centre), p)
    np.testing.assert_allclose(t[:3, :3] @ centre + t[:3, 3], p[5:])  # b is the image of the centre
    pts = np.random.default_rng(0).uniform(0, 30, (3, 7))
    d = point_derivatives(pts, centre)
    for k in range(8):
        q = p.copy()
        q[k] += 1e-6
        tq = model_matrix(q, centre)
        moved = (tq[:3, :3] @ pts + tq[:3, 3:]) - (t[:3, :3] @ pts + t[:3, 3:])
        np.testing.assert_allclose(moved / 1e-6, d[k], atol=1e-6)


def test_rigid_parameters_are_a_map_rotation_of_the_physical_coordinates():
    sp_f, sp_m = np.array([25.0, 12.5, 4.0]), np.array([50.0, 25.0, 2.0])
    rep = Reparam("rigid", sp_f, sp_m)
    q = np.array([np.radians(20.0), 3.0, -1.0, 2.0])
    p, jac = rep.affine(q)
    lateral = np.diag(sp_f[:2]) @ np.array([[p[0], p[1]], [p[2], p[3]]]) @ np.diag(1.0 / sp_m[:2])
    np.testing.assert_allclose(lateral, rotation_2d(20.0), atol=1e-12)
    assert p[4] == pytest.approx(0.5)  # 2 ms samples in 4 ms samples
    np.testing.assert_allclose(rep.start(p), q, atol=1e-12)
    step = np.array([1e-7, 0, 0, 0])
    np.testing.assert_allclose((rep.affine(q + step)[0] - p) / 1e-7, jac[:, 0], atol=1e-5)


def test_map_matrix_and_corner_distance():
    a = map_matrix(90.0, (2.0, 1.0), 0.5)
    np.testing.assert_allclose(a, [[0, -1, 0], [2, 0, 0], [0, 0, 0.5]], atol=1e-12)
    shift = np.eye(4)
    shift[:3, 3] = (0.0, 0.3, 0.4)
    assert corner_distance(shift, np.eye(4), (5, 5, 5)) == pytest.approx(0.5)
